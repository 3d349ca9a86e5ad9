"""Verdicts on a machine on its supports under its periodic load: the frame's vibration velocity by ISO
20816-3, the mounts' isolation efficiency by VDI 2062, the floor's vibration against the criteria
curves, and the modes' separation from the running speed's harmonics (:mod:`mechdyn.support.verdicts`
holds the standards' tables and functions).

Everything comes from the exact steady state, harmonic by harmonic: (K − (hΩ)² M + i hΩ C) X_h = B c_h
(:func:`mechdyn.support.harmonic_response`); the velocity of a point p of the frame is i hΩ T(p) X_h
with T(p) = [I, −[p − G]×] (:meth:`MountedMachine.mount_transform`), the force on the floor
Σ_m (K_m + i hΩ C_m) T_m X_h.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from mechdyn.errors import ModelError
from mechdyn.results import Table
from mechdyn.support import verdicts as v
from mechdyn.support.excitation import PeriodicLoad
from mechdyn.support.model import MountedMachine
from mechdyn.units import convert

__all__ = ["FOUNDATION_CHOICES", "VibrationVerdicts", "vibration_verdicts"]

FOUNDATION_CHOICES = ("auto", *v.FOUNDATIONS)
"""``auto``: the foundation class from the modes (ISO 20816-3, § 5.4); or ``rigid``, ``flexible``."""
DEFAULT_GROUP = 2
"""The machine group when none is given: group 2, the stricter boundaries."""
_AXES = ("x", "y", "z")


def _mm_s(x: float) -> float:
    return float(convert(float(x), "m/s", "mm/s"))


@dataclass(frozen=True)
class VibrationVerdicts:
    """The verdicts of a machine on its supports under its periodic load.

    Attributes
    ----------
    running_speed : float
        The running speed the standards are applied at, rad/s (the first rotor's, else the load's
        fundamental).
    fundamental : float
        The load's fundamental frequency, Hz (its harmonics are its multiples).
    group : int
        ISO 20816-3 machine group.
    foundation : str
        ``rigid`` or ``flexible``, as given or from the modes.
    foundation_from_modes : bool
        Whether the foundation class was found from the modes.
    group_by_default : bool
        Whether the group is the default one (none was given).
    band : (float, float)
        ISO 20816-3's frequency band for this speed, Hz.
    points : tuple of str
        The points of the frame assessed.
    positions : ndarray
        (P, 3) where they are, m.
    velocity_band, velocity_all : ndarray
        (P, 3) RMS vibration velocity along x, y, z in the band and over all harmonics, m/s.
    orders : ndarray
        (A,) the exciting harmonic orders (amplitude ≥ 1 % of the largest).
    exciting, transmitted : ndarray
        (H + 1,) amplitude of each harmonic of the exciting force (its kept translations) and of the
        force on the floor: the largest magnitude over a period (the ellipse's semi-major axis), N.
    peak_exciting, peak_transmitted : float
        The largest magnitude over a period of the whole dynamic exciting force and floor force (all
        harmonics ≥ 1), N.
    natural_frequencies : ndarray
        (n,) Hz.
    mode_coordinates : tuple of str
        The coordinate dominating each mode.
    modal_force : ndarray
        (H + 1, n) |φⱼᵀ B c_h|, the load's force on each mass-normalised mode at each harmonic
        (N/√kg for a translation).
    margin : float
        The separation margin flagged, a ratio.
    floor : FloorVibration or None
        The floor's vibration on a foundation block (:func:`mechdyn.support.floor.floor_vibration`);
        None when the mounts stand on rigid ground.
    """

    running_speed: float
    fundamental: float
    group: int
    foundation: str
    foundation_from_modes: bool
    group_by_default: bool
    band: tuple[float, float]
    points: tuple[str, ...]
    positions: np.ndarray
    velocity_band: np.ndarray
    velocity_all: np.ndarray
    orders: np.ndarray
    exciting: np.ndarray
    transmitted: np.ndarray
    peak_exciting: float
    peak_transmitted: float
    natural_frequencies: np.ndarray
    mode_coordinates: tuple[str, ...]
    modal_force: np.ndarray
    margin: float = v.SEPARATION_MARGIN
    floor: Any = None

    # -- ISO 20816-3 ---------------------------------------------------------------------------------
    @property
    def running_speed_rpm(self) -> float:
        """The running speed, rpm."""
        return float(convert(self.running_speed, "rad/s", "rpm"))

    @property
    def applies(self) -> bool:
        """Whether the running speed lies in the range ISO 20816-3 covers (120 to 30 000 r/min)."""
        lo, hi = v.ISO_20816_3_SPEEDS_RPM
        return lo <= self.running_speed_rpm <= hi

    @property
    def assessed(self) -> np.ndarray:
        """(P, 3) the velocity judged: in the standard's band where it applies, else all harmonics, m/s."""
        return self.velocity_band if self.applies else self.velocity_all

    @property
    def largest(self) -> tuple[int, int]:
        """(point, axis) indices of the largest assessed velocity."""
        p, k = np.unravel_index(int(np.argmax(self.assessed)), self.assessed.shape)
        return int(p), int(k)

    @property
    def zone(self) -> str:
        """ISO 20816-3 zone of the largest assessed velocity (an indication only where it does not apply)."""
        return v.iso_zone(float(self.assessed.max()), self.group, self.foundation)

    @property
    def boundaries(self) -> tuple[float, float, float]:
        """A/B, B/C, C/D, m/s."""
        return v.zone_boundaries(self.group, self.foundation)

    def _where(self) -> str:
        p, k = self.largest
        return f"at {self.points[p]}, along {_AXES[k]}"

    def _class(self) -> str:
        names = ("A/B", "B/C", "C/D")
        bounds = ", ".join(f"{a} {_mm_s(b):.3g}" for a, b in zip(names, self.boundaries, strict=True))
        by = " (by default, the stricter)" if self.group_by_default else ""
        how = " (from the modes, § 5.4)" if self.foundation_from_modes else ""
        return f"group {self.group}{by} on a {self.foundation} foundation{how}: {bounds} mm/s"

    @property
    def vibration_verdict(self) -> str:
        """The frame's vibration by ISO 20816-3, in words."""
        lo, hi = self.band
        band_v = _mm_s(self.velocity_band.max())
        zone = self.zone
        if self.applies:
            return (
                f"The frame's vibration velocity, {band_v:.3g} mm/s RMS in {lo:g}–{hi:g} Hz "
                f"({self._where()}), is in zone {zone} of ISO 20816-3 for {self._class()}: "
                f"{v.ZONE_MEANINGS[zone]}."
            )
        below = self.running_speed_rpm < v.ISO_20816_3_SPEEDS_RPM[0]
        return (
            f"ISO 20816-3 does not apply: it covers machines running at 120 to 30 000 r/min, and this one "
            f"runs at {self.running_speed_rpm:.4g} rpm, {'below' if below else 'above'} that range (its "
            f"{lo:g}–{hi:g} Hz band holds {band_v:.3g} mm/s RMS). Assessed instead: the RMS vibration "
            f"velocity of all the harmonics of the running speed, {_mm_s(self.velocity_all.max()):.3g} mm/s "
            f"({self._where()}), set against the standard's boundaries for {self._class()}, as an "
            f"indication only: zone {zone}"
            + (
                "; at so low a speed the bed displacement and the force on the floor are the figures to "
                "judge."
                if below
                else "."
            )
        )

    # -- VDI 2062 ------------------------------------------------------------------------------------
    @property
    def harmonic_transmissibility(self) -> np.ndarray:
        """(A,) the floor force over the exciting force at each exciting harmonic, a ratio."""
        return self.transmitted[self.orders] / self.exciting[self.orders]

    @property
    def transmissibility(self) -> float:
        """The largest floor force over the largest exciting force in a period, their dynamic parts (all
        harmonics ≥ 1): for one rotor the unbalance sweep's figure at the running speed."""
        e = self.peak_exciting
        return self.peak_transmitted / e if e > 0 else math.nan

    @property
    def isolation_verdict(self) -> str:
        """The mounts' isolation efficiency (VDI 2062 Blatt 1), in words."""
        eta = 100 * v.isolation_efficiency(self.transmissibility)
        by = 100 * v.isolation_efficiency(self.harmonic_transmissibility)
        f1 = float(self.natural_frequencies[self.natural_frequencies > 0].min(initial=math.inf))
        said = (
            f"Isolation efficiency of the mounts (VDI 2062 Blatt 1, η = 1 − V, V the force on the floor "
            f"over the exciting force): overall, as the largest dynamic forces in a period, {eta:.3g} %"
        )
        if by.size > 1:
            lo, hi = int(np.argmin(by)), int(np.argmax(by))
            said += (
                f"; by harmonic from {by[lo]:.3g} % (order {int(self.orders[lo])}) to {by[hi]:.3g} % "
                f"(order {int(self.orders[hi])})"
            )
        if eta < 0:
            fr = self.running_speed / (2 * math.pi)
            why = (
                f"the running speed ({fr:.3g} Hz) lies below √2 times the lowest natural frequency "
                f"({f1:.3g} Hz), and isolation begins only above it"
                + (
                    "; so far below, the forcing is quasi-static and the floor takes all of it"
                    if 2 * fr < f1
                    else ""
                )
            )
            return said + f". The mounts do not isolate, they amplify: {why}."
        return said + f". The floor takes {100 - eta:.3g} % of the exciting force."

    # -- modes -----------------------------------------------------------------------------------------
    @property
    def separation(self) -> list[dict[str, Any]]:
        """Each mode against the nearest exciting harmonic (:func:`mechdyn.support.verdicts.mode_separation`),
        with ``driven`` (the harmonic's force on the mode is at least 1 % of the largest modal force of
        the load); ``close`` only for a driven mode."""
        rows = v.mode_separation(self.natural_frequencies, self.fundamental, self.orders, self.margin)
        big = float(self.modal_force[1:].max(initial=0.0))
        for k, r in enumerate(rows):
            h = r["order"]
            r["driven"] = bool(h is not None and big > 0 and self.modal_force[h, k] >= v.EXCITING_SHARE * big)
            r["close"] = bool(r["close"] and r["driven"])
        return rows

    def _share(self, order: int) -> float:
        return float(self.exciting[order] / self.exciting[1:].max())

    @property
    def separation_verdict(self) -> str:
        """The modes near an exciting harmonic, in words."""
        pct = f"±{100 * self.margin:.3g} %"
        rows = self.separation
        close = [(k, r) for k, r in enumerate(rows) if r["close"]]
        idle = [
            k + 1
            for k, r in enumerate(rows)
            if r["margin_percent"] is not None
            and abs(r["margin_percent"]) < 100 * self.margin
            and not r["driven"]
        ]
        many = len(idle) > 1
        aside = (
            f" Mode{'s' if many else ''} {', '.join(map(str, idle))} also lie{'' if many else 's'} within "
            f"{pct} of a harmonic, which does not drive {'them' if many else 'it'} (its force on the mode "
            f"is below {100 * v.EXCITING_SHARE:.3g} % of the load's largest modal force)."
            if idle
            else ""
        )
        top = int(self.orders.max(initial=0))
        scope = (
            f"exciting harmonics of the running speed (orders with at least "
            f"{100 * v.EXCITING_SHARE:.3g} % of the largest harmonic's force: up to order "
            f"{top}, {top * self.fundamental:.3g} Hz)"
        )
        if not close:
            return f"No mode driven by the load lies within {pct} of the {scope}.{aside}"
        items = "; ".join(
            f"mode {k + 1} ({r['frequency_hz']:.3g} Hz, {self.mode_coordinates[k]}) "
            f"{abs(r['margin_percent']):.2g} % {'above' if r['margin_percent'] >= 0 else 'below'} "
            f"harmonic {r['order']} ({r['harmonic_hz']:.3g} Hz, {100 * self._share(r['order']):.2g} % of "
            "the largest harmonic's force)"
            for k, r in close
        )
        return (
            f"Within {pct} of the {scope}: {items}. That harmonic drives the mode near resonance: its "
            "response is amplified by the mode's dynamic factor; move the mode (mount stiffness) or check "
            f"the harmonic's share of the response.{aside}"
        )

    # -- the floor --------------------------------------------------------------------------------------
    @property
    def floor_verdict(self) -> str:
        """The floor's vibration against the criteria curves (on a foundation block), or why it is not
        set against them (the mounts stand on rigid ground: the model has no floor)."""
        if self.floor is not None:
            return self.floor.verdict
        return (
            "The floor is not modelled (the mounts stand on rigid ground), so its vibration cannot be set "
            "against the VC-A … VC-E curves (Gordon; IEST-RP-CC012) or the ISO 2631-2/ASHRAE workshop, "
            "office and residential curves: that needs a floor or foundation model (its mass, stiffness "
            "and damping under the mounts). The force on the floor above is that model's load "
            "(mechdyn.support.verdicts.floor_criteria rates a floor velocity spectrum)."
        )

    # -- the result protocol -------------------------------------------------------------------------------
    def summary(self) -> dict[str, Any]:
        """The verdicts' figures, SI, and the verdicts in words."""
        p, k = self.largest
        eta = v.isolation_efficiency(self.harmonic_transmissibility)
        sep = self.separation
        return {
            "iso20816_applies": self.applies,
            "iso20816_machine_group": self.group,
            "iso20816_foundation": self.foundation,
            "iso20816_band_hz": [float(x) for x in self.band],
            "iso20816_zone_boundaries_m_per_s": [float(x) for x in self.boundaries],
            "iso20816_zone": self.zone,
            "frame_velocity_rms_band_m_per_s": float(self.velocity_band.max()),
            "frame_velocity_rms_all_harmonics_m_per_s": float(self.velocity_all.max()),
            "frame_velocity_rms_at_points_m_per_s": {
                n: float(x) for n, x in zip(self.points, self.assessed.max(axis=1), strict=True)
            },
            "frame_velocity_point": self.points[p],
            "frame_velocity_direction": _AXES[k],
            "vibration_verdict": self.vibration_verdict,
            "isolation_orders": [int(h) for h in self.orders],
            "isolation_efficiency_by_harmonic_percent": [float(100 * e) for e in np.atleast_1d(eta)],
            "isolation_transmissibility_ratio": self.transmissibility,
            "isolation_efficiency_percent": float(100 * v.isolation_efficiency(self.transmissibility)),
            "isolation_verdict": self.isolation_verdict,
            "floor_vibration_verdict": self.floor_verdict,
            "mode_nearest_harmonic": [r["order"] for r in sep],
            "mode_separation_margin_percent": [r["margin_percent"] for r in sep],
            "mode_driven_by_harmonic": [r["driven"] for r in sep],
            "mode_close_to_harmonic": [r["close"] for r in sep],
            "mode_separation_limit_percent": float(100 * self.margin),
            "mode_separation_verdict": self.separation_verdict,
        } | ({} if self.floor is None else self.floor.summary())

    def tables(self, **display_units: str) -> list[Table]:
        """The frame's vibration at each point (the ISO 20816-3 verdict under it), the isolation by
        harmonic (the VDI 2062 verdict and the floor's under it) and the modes against the harmonics.
        Forces in ``force_unit`` where given, else in the unit their size reads best in."""
        from mechdyn.units import readable_unit

        lo, hi = self.band
        frame = Table(
            "frame vibration (ISO 20816-3)",
            [
                "point",
                "x [mm]",
                "y [mm]",
                "z [mm]",
                *[f"v{a} {lo:g}–{hi:g} Hz [mm/s]" for a in _AXES],
                "largest, all harmonics [mm/s]",
            ],
            [
                [
                    n,
                    *[float(convert(float(x), "m", "mm")) for x in pos],
                    *[_mm_s(x) for x in band],
                    _mm_s(float(every.max())),
                ]
                for n, pos, band, every in zip(
                    self.points, self.positions, self.velocity_band, self.velocity_all, strict=True
                )
            ],
            self.vibration_verdict,
        )
        fu = display_units.get("force_unit")
        big = float(max(self.exciting.max(initial=0.0), self.transmitted.max(initial=0.0)))
        unit, shown = (fu, fu) if fu else readable_unit(big, "N")
        T = self.harmonic_transmissibility
        iso = Table(
            "isolation by harmonic (VDI 2062)",
            [
                "order",
                "f [Hz]",
                f"exciting force amplitude [{shown}]",
                f"floor force amplitude [{shown}]",
                "transmissibility",
                "isolation [%]",
            ],
            [
                [
                    int(h),
                    float(h * self.fundamental),
                    float(convert(float(self.exciting[h]), "N", unit)),
                    float(convert(float(self.transmitted[h]), "N", unit)),
                    float(t),
                    float(100 * v.isolation_efficiency(float(t))),
                ]
                for h, t in zip(self.orders, T, strict=True)
            ],
            # on a foundation the floor's verdict stands under its own table
            self.isolation_verdict
            if self.floor is not None
            else f"{self.isolation_verdict} {self.floor_verdict}",
        )
        modes = Table(
            "modes against the running speed's harmonics",
            ["mode", "f [Hz]", "dominant", "nearest harmonic", "harmonic f [Hz]", "margin [%]", "driven", ""],
            [
                [
                    k + 1,
                    r["frequency_hz"],
                    self.mode_coordinates[k],
                    r["order"],
                    r["harmonic_hz"],
                    r["margin_percent"],
                    "yes" if r["driven"] else "no",
                    f"within ±{100 * self.margin:.3g} %" if r["close"] else "",
                ]
                for k, r in enumerate(self.separation)
            ],
            self.separation_verdict,
        )
        return [frame, iso, modes] + ([] if self.floor is None else [self.floor.table()])


def vibration_verdicts(
    machine: MountedMachine,
    load: PeriodicLoad,
    *,
    machine_group: int | None = None,
    foundation: str = "auto",
    points: Sequence[Sequence[float]] | None = None,
    margin: float = v.SEPARATION_MARGIN,
) -> VibrationVerdicts:
    """The frame's vibration (ISO 20816-3), the mounts' isolation (VDI 2062) and the modes' separation
    from the running speed's harmonics, from the exact steady state.

    Parameters
    ----------
    machine : MountedMachine
        The machine on its mounts.
    load : PeriodicLoad
        The periodic load.
    machine_group : {1, 2}, optional
        ISO 20816-3 machine group (Table A.1: 1, 300 kW to 50 MW; Table A.2: 2, 15 kW to 300 kW);
        by default 2, the stricter boundaries (and the verdict says so).
    foundation : {"auto", "rigid", "flexible"}
        The foundation class; ``auto`` (default): rigid when the lowest natural frequency lies at least
        25 % above the running frequency (ISO 20816-3:2022, § 5.4), else flexible.
    points : sequence of (x, y, z), optional
        Points of the frame to assess, m, machine coordinates; default the mounts' tops (where each
        mount holds the machine).
    margin : float
        Flag a mode closer than this to an exciting harmonic, a ratio (default 0.2: ±20 %), above 0
        and below 1.

    Returns
    -------
    VibrationVerdicts
    """
    from mechdyn.support.model import Mount
    from mechdyn.support.modes import modes
    from mechdyn.support.response import harmonic_response
    from mechdyn.support.sweep import _peak_magnitude

    if foundation not in FOUNDATION_CHOICES:
        raise ModelError(
            f"{foundation!r} must be one of {', '.join(FOUNDATION_CHOICES)}",
            element="vibration verdict",
            field="foundation",
        )
    group = DEFAULT_GROUP if machine_group is None else machine_group
    v.zone_boundaries(group, "rigid")  # refuses an unknown group
    if not 0.0 < float(margin) < 1.0:
        raise ModelError(
            f"{margin!r} must be a ratio above 0 and below 1 (0.2: ±20 %)",
            element="vibration verdict",
            field="separation_margin",
        )
    if points is None:
        names = tuple(m.name for m in machine.mounts)
        where = np.array([m.position for m in machine.mounts], dtype=float).reshape(-1, 3)
    else:
        where = np.asarray(points, dtype=float).reshape(-1, 3)
        names = tuple(f"point {i + 1}" for i in range(where.shape[0]))
        if not np.isfinite(where).all() or where.shape[0] == 0:
            raise ModelError(
                "give at least one point [x, y, z], finite, in m",
                element="vibration verdict",
                field="vibration_points",
            )
    f0 = 1.0 / load.period
    orders = load.orders()
    w = 2 * math.pi * f0 * orders
    X = harmonic_response(machine, load)  # (H + 1, n)
    V = 1j * w[:, None] * X
    T = np.stack([machine.mount_transform(Mount("probe", p, (0.0, 0.0, 0.0))) for p in where])
    Vp = np.einsum("hn,pkn->hpk", V, T)  # (H + 1, P, 3)
    running = abs(float(load.rotors[0].speed)) if load.rotors else 2 * math.pi * f0
    band = v.iso_band(running)
    kept = [k for k, d in enumerate(_AXES) if d in machine.dofs]
    F = np.zeros((orders.size, 3), dtype=complex)
    F[:, kept] = load.coefficients[:, kept]
    Kf = sum(m.stiffness_matrix @ machine.mount_transform(m) for m in machine.mounts)
    Cf = sum(m.damping_matrix @ machine.mount_transform(m) for m in machine.mounts)
    floor = X @ np.asarray(Kf).T + 1j * w[:, None] * (X @ np.asarray(Cf).T)
    # each harmonic's force draws an ellipse: its amplitude is the semi-major axis, and the whole
    # dynamic force's is its largest magnitude over a period (as the unbalance sweep measures them)
    exciting = _peak_magnitude(F[:, None, :], orders[:1] + 1)
    transmitted = _peak_magnitude(floor[:, None, :], orders[:1] + 1)
    exciting[0] = transmitted[0] = 0.0  # the mean is static, not vibration
    dyn = orders[1:]
    peak_exciting = float(_peak_magnitude(F[None, 1:, :], dyn)[0]) if dyn.size else 0.0
    peak_floor = float(_peak_magnitude(floor[None, 1:, :], dyn)[0]) if dyn.size else 0.0
    big = exciting.max()
    exciting_orders = orders[(exciting >= v.EXCITING_SHARE * big) & (orders >= 1)] if big > 0 else orders[:0]
    md = modes(machine)
    fn = np.asarray(md.frequencies_hz, dtype=float)
    found = foundation
    if foundation == "auto":
        moving = fn[fn > 0]
        found = v.foundation_class(float(moving.min()) if moving.size else math.inf, running / (2 * math.pi))
    return VibrationVerdicts(
        running_speed=running,
        fundamental=f0,
        group=int(group),
        foundation=found,
        foundation_from_modes=foundation == "auto",
        group_by_default=machine_group is None,
        band=band,
        points=names,
        positions=where,
        velocity_band=v.harmonic_band_rms(Vp, f0, band),
        velocity_all=v.harmonic_band_rms(Vp, f0, (0.0, math.inf)),
        orders=exciting_orders,
        exciting=exciting,
        transmitted=transmitted,
        peak_exciting=peak_exciting,
        peak_transmitted=peak_floor,
        natural_frequencies=fn,
        mode_coordinates=tuple(md.dominant),
        modal_force=np.abs((load.coefficients @ machine.load_matrix().T) @ md.shapes),
        margin=float(margin),
    )
