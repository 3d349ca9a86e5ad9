"""The floor's vibration on a foundation block, against the vibration criteria curves.

The machine on its mounts on the block on soil (:class:`~mechdyn.support.coupled.FoundationSystem`)
is solved exactly harmonic by harmonic, (K − (hΩ)² M + i hΩ C) X_h = B c_h; the floor's velocity at
a point p of the block is i hΩ T_b(p) X_h, one line of RMS √2 abs(i hΩ T_b(p) X_h) at h f₀ for each
harmonic h ≥ 1 (the series convention of :func:`mechdyn.support.excitation.series`). Each point's
line spectrum along x, y and z is gathered in one-third-octave bands and set against the VC-A … VC-E
and ISO 2631-2 curves (:func:`mechdyn.support.verdicts.floor_criteria`); the floor is judged by its
worst point and direction.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from functools import cached_property
from typing import Any

import numpy as np

from mechdyn.errors import ModelError
from mechdyn.results import Table
from mechdyn.support import verdicts as v
from mechdyn.support.coupled import FoundationSystem
from mechdyn.support.excitation import PeriodicLoad
from mechdyn.support.foundation import Foundation
from mechdyn.units import convert, show

__all__ = ["FloorVibration", "floor_vibration", "with_floor"]

_AXES = ("x", "y", "z")
GOVERNING = "VC-B"
"""The criterion the floor's probability is usually asked against (a ratio is reported for it)."""


def _um_s(x: float) -> float:
    return float(convert(float(x), "m/s", "um/s"))


@dataclass(frozen=True)
class FloorVibration:
    """The floor's (the block's) vibration at its points, and the verdict against the criteria.

    Attributes
    ----------
    system : FoundationSystem
        The machine, its mounts, the block and the soil.
    fundamental : float
        The load's fundamental frequency, Hz.
    points : tuple of str
        The points of the block judged.
    positions : ndarray
        (P, 3) where they are, m, machine coordinates.
    velocity : ndarray
        (H + 1, P, 3) complex velocity coefficients of each point along x, y, z, m/s.
    soil_force : ndarray
        (H + 1, 6) complex force (N) and moment (N·m) on the soil at the base, per harmonic.
    mount_force : ndarray
        (H + 1, mounts, 3) complex force each mount passes down to the block, N.
    block_acceleration : ndarray
        (H + 1, 3) complex acceleration of the block's centre of mass, m/s² (zero along a translation
        not kept).
    """

    system: FoundationSystem
    fundamental: float
    points: tuple[str, ...]
    positions: np.ndarray
    velocity: np.ndarray
    soil_force: np.ndarray
    mount_force: np.ndarray
    block_acceleration: np.ndarray

    @property
    def foundation(self) -> Foundation:
        return self.system.foundation

    @property
    def frequencies_hz(self) -> np.ndarray:
        """(H + 1,) each harmonic's frequency, Hz."""
        return self.fundamental * np.arange(self.velocity.shape[0])

    @property
    def line_rms(self) -> np.ndarray:
        """(H, P, 3) each harmonic's RMS velocity (h ≥ 1), m/s: √2 abs(c_h)."""
        return math.sqrt(2.0) * np.abs(self.velocity[1:])

    @cached_property
    def ratings(self) -> list[list[dict[str, Any]]]:
        """[P][3] :func:`~mechdyn.support.verdicts.floor_criteria` of each point along x, y, z."""
        f = self.frequencies_hz[1:]
        r = self.line_rms
        return [[v.floor_criteria(f, r[:, p, k]) for k in range(3)] for p in range(len(self.points))]

    @cached_property
    def worst(self) -> tuple[int, int]:
        """(point, axis) whose largest band stands highest against VC-B."""
        ratio = np.array([[c["band_ratio"][GOVERNING] for c in row] for row in self.ratings])
        p, k = np.unravel_index(int(np.argmax(ratio)), ratio.shape)
        return int(p), int(k)

    @property
    def governing(self) -> dict[str, Any]:
        """The rating of the worst point and direction."""
        p, k = self.worst
        return self.ratings[p][k]

    @property
    def band_ratio(self) -> dict[str, float]:
        """Each criterion's largest band over the curve, at the worst point and direction for it."""
        names = v.VIBRATION_CRITERIA
        return {n: max(c["band_ratio"][n] for row in self.ratings for c in row) for n in names}

    @property
    def met(self) -> list[str]:
        """The criteria every point and direction meets, least strict first."""
        return [n for n, r in self.band_ratio.items() if r <= 1.0]

    @property
    def strictest_met(self) -> str | None:
        """The strictest criterion met (None: not even the ISO workshop curve)."""
        return self.met[-1] if self.met else None

    @property
    def strictest_vc_met(self) -> str | None:
        """The strictest VC curve met (None: not even VC-A)."""
        vc = [n for n in self.met if n.startswith("VC-")]
        return vc[-1] if vc else None

    @property
    def verdict(self) -> str:
        """The floor's vibration against the criteria, in words."""
        g = self.governing
        p, k = self.worst
        bands = np.asarray(g["band_velocity_m_per_s"])
        b = int(np.argmax(bands))
        centre = g["band_centre_hz"][b]
        ratio = self.band_ratio[GOVERNING]
        vc_b = v.VIBRATION_CRITERIA[GOVERNING]
        strict = self.strictest_met
        said = (
            f"The floor (the foundation block, {self.points[p]}, along {_AXES[k]}) vibrates at up to "
            f"{_um_s(bands[b]):.3g} µm/s RMS in the one-third-octave band at {centre:.3g} Hz, "
            f"{ratio:.3g} times VC-B ({_um_s(vc_b):.3g} µm/s; Gordon 1999, IEST-RP-CC012): VC-B is "
            f"{'met' if ratio <= 1.0 else 'exceeded'}. "
        )
        said += (
            f"The strictest criterion met is {strict}"
            + (
                f" (of the VC curves, {self.strictest_vc_met})"
                if self.strictest_vc_met not in (None, strict)
                else ""
            )
            + "."
            if strict
            else "Not even the ISO 2631-2 workshop curve is met."
        )
        fn = self.system.natural_frequencies_hz
        return said + (
            f" Machine, mounts, block ({show(self.foundation.block.mass, 'kg', 't', '.4g')}) and soil "
            f"({self._soil_words()}) solved together, {len(fn)} coordinates, natural frequencies "
            f"{', '.join(f'{x:.3g}' for x in fn)} Hz. The frame's vibration and the mount forces above "
            "are those on rigid ground."
        )

    def _soil_words(self) -> str:
        s = self.foundation.soil
        if s is None:
            return "springs and dashpots as given"
        return (
            f"G = {show(s.shear_modulus, 'Pa', 'MPa', '.3g')}, V_s = {s.shear_wave_speed:.3g} m/s, ν = "
            f"{s.poisson_ratio:g}: springs by Gazetas 1991, dashpots by Gazetas 1991 and Richart, Hall "
            "& Woods 1970"
        )

    def summary(self) -> dict[str, Any]:
        """The floor's figures, SI, and the verdict in words."""
        g = self.governing
        p, k = self.worst
        bands = [float(x) for x in g["band_velocity_m_per_s"]]
        rms = self.line_rms[:, p, k]
        out = {
            "floor_velocity_point": self.points[p],
            "floor_velocity_direction": _AXES[k],
            "floor_velocity_band_centre_hz": [float(c) for c in g["band_centre_hz"]],
            "floor_velocity_band_m_per_s": bands,
            "floor_velocity_band_max_m_per_s": max(bands),
            "floor_velocity_rms_m_per_s": float(np.sqrt(np.sum(rms**2))),
            "floor_velocity_band_max_at_points_m_per_s": {
                n: max(max(c["band_velocity_m_per_s"]) for c in row)
                for n, row in zip(self.points, self.ratings, strict=True)
            },
            "floor_criteria_band_ratio": self.band_ratio,
            "floor_vc_b_ratio": self.band_ratio[GOVERNING],
            "floor_vc_b_met": self.band_ratio[GOVERNING] <= 1.0,
            "floor_strictest_criterion_met": self.strictest_met,
            "floor_strictest_vc_met": self.strictest_vc_met,
            "foundation_natural_frequencies_hz": [float(x) for x in self.system.natural_frequencies_hz],
            "soil_force_amplitude_N": [float(x) for x in 2 * np.abs(self.soil_force[1:, :3]).max(axis=0)],
        }
        return out | self.foundation.summary()

    def table(self) -> Table:
        """The floor's one-third-octave spectrum at its worst point against the VC curves (the bands
        above a thousandth of the largest), the verdict under it."""
        g = self.governing
        p, k = self.worst
        vc = [n for n in v.VIBRATION_CRITERIA if n.startswith("VC-")]
        shown = 1e-3 * max(g["band_velocity_m_per_s"])  # bands a thousand times below the largest: none
        rows = [
            [float(c), _um_s(x), *[float(x / v.VIBRATION_CRITERIA[n]) for n in vc]]
            for c, x in zip(g["band_centre_hz"], g["band_velocity_m_per_s"], strict=True)
            if x > shown
        ]
        return Table(
            f"floor vibration at {self.points[p]} along {_AXES[k]} (one-third-octave bands)",
            ["band centre [Hz]", "velocity [µm/s RMS]", *[f"/ {n}" for n in vc]],
            rows,
            self.verdict,
        )


def floor_vibration(
    machine: Any, foundation: Foundation, load: PeriodicLoad, points: Sequence[Sequence[float]] | None = None
) -> FloorVibration:
    """The floor's vibration under a machine on its mounts on a foundation block on soil.

    Parameters
    ----------
    machine : MountedMachine
        The machine on its mounts (the mounts' feet stand on the block).
    foundation : Foundation
        The block and its soil.
    load : PeriodicLoad
        The periodic load on the machine.
    points : sequence of (x, y, z), optional
        Points of the block whose vibration is judged, m, machine coordinates (default: the mounts'
        feet, where each mount stands on the block).

    Returns
    -------
    FloorVibration
    """
    system = FoundationSystem(machine, foundation)
    if points is None:
        names = tuple(f"foot of {m.name}" for m in machine.mounts)
        where = np.array([m.position for m in machine.mounts], dtype=float).reshape(-1, 3)
    else:
        where = np.asarray(points, dtype=float).reshape(-1, 3)
        names = tuple(f"floor point {i + 1}" for i in range(where.shape[0]))
        if where.shape[0] == 0 or not np.isfinite(where).all():
            raise ModelError(
                "give at least one point [x, y, z] of the block, finite, in m",
                element=foundation.name,
                field="floor_points",
            )
    omega = 2 * math.pi / load.period * load.orders()
    X = system.harmonic_response(load)
    T = np.stack([system.block_transform(p) for p in where])  # (P, 3, 2n)
    velocity = np.einsum("hn,pkn->hpk", 1j * omega[:, None] * X, T)
    n = len(system.dofs)
    acc = np.zeros((X.shape[0], 3), dtype=complex)
    for k, d in enumerate(_AXES):
        if d in system.dofs:
            acc[:, k] = -(omega**2) * X[:, n + system.dofs.index(d)]
    return FloorVibration(
        system,
        1.0 / load.period,
        names,
        where,
        velocity,
        system.soil_forces(X, omega),
        system.mount_forces(X, omega),
        acc,
    )


def with_floor(result: Any, foundation: Foundation, points: Any = None) -> Any:
    """A support analysis with the floor's vibration on the foundation in its verdicts.

    A new result (``dataclasses.replace``): the same steady state, start-up and modes, its verdicts
    holding :class:`FloorVibration`, so that ``summary()`` reports the ``floor_*`` figures and the
    floor's verdict no longer says the floor is not modelled.

    Parameters
    ----------
    result : SupportAnalysis
        The analysis of the machine on its mounts.
    foundation : Foundation
        The block and its soil under the mounts.
    points : sequence of (x, y, z), optional
        The block's points to judge (default: the mounts' feet).
    """
    floor = floor_vibration(result.machine, foundation, result.load, points)
    verdicts = replace(result.verdicts, floor=floor)
    out = replace(result)
    out.__dict__["verdicts"] = verdicts  # the cached property, computed once
    return out
