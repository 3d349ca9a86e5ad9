"""The result of the dyad path: :class:`CycleBatch`, many design variants of one mechanism over a
revolution from the compiled kernel, each variant with its status (the same summary keys as one
design's :meth:`~mechdyn.mechanism.DynamicsResult.summary`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, cast

import numpy as np

from mechdyn.errors import ModelError
from mechdyn.mechanism.dyads.arguments import _dot
from mechdyn.mechanism.dyads.decomposition import Step
from mechdyn.mechanism.model import Mechanism, Prismatic, _point
from mechdyn.results import Result

__all__ = ["CycleBatch"]


@dataclass(frozen=True, repr=False)  # the short repr of Result
class CycleBatch(Result):
    """Kinematics and frame loads of many design variants over one revolution.

    Arrays have shape (V, N, ...) for V variants (1 when none were given) and N crank angles.

    Attributes
    ----------
    angle : ndarray
        (V, N) crank angle from each variant's datum, rad (every variant starts its cycle at its
        own datum; with ``angle_datum = "bdc"`` at its own bottom dead centre).
    driving_torque : ndarray
        (V, N) N·m.
    frame_moment : ndarray
        (V, N) moment on the frame about the origin, N·m (motor reaction included).
    output_position : ndarray or None
        (V, N) along the upward output axis, m.
    mechanism : Mechanism
        The base design the variants were made from.
    failures : dict of int to str
        Variant index → why it could not be computed (its rows are NaN).
    """

    mechanism: Mechanism
    angle: np.ndarray
    driving_torque: np.ndarray
    frame_moment: np.ndarray
    output_position: np.ndarray | None
    _force: np.ndarray  # complex (V, N): the load on the frame
    _inertia: np.ndarray  # complex (V, N): −Σ m a_G
    _z: dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]
    _rates: dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]
    _dyad_measure: np.ndarray  # (V, N, dyads) sine of each dyad's transmission angle, signed
    _steps: list[Step]
    _raw: tuple[np.ndarray, ...]  # (pos, vel, acc, rates) as the kernel wrote them
    _body_mass: np.ndarray  # (V, bodies) kg
    _body_inertia: np.ndarray  # (V, bodies) kg·m²
    _lam: np.ndarray | None  # (V, N, m) the multipliers, with the motions kept
    _peaks: np.ndarray  # (V, joints) each joint's largest force, N
    failures: dict[int, str] = field(default_factory=dict)
    """Variant → why it was not computed (``errors="nan"``): the angle, the loop and the joint."""

    @property
    def shaking_force(self) -> np.ndarray:
        """(V, N, 2) force on the frame, N."""
        return np.stack([self._force.real, self._force.imag], axis=-1)

    @property
    def inertia_force(self) -> np.ndarray:
        """(V, N, 2) −Σ m a_G, N."""
        return np.stack([self._inertia.real, self._inertia.imag], axis=-1)

    def _stored(self, key: str) -> None:
        if key not in self._z:
            raise ModelError(
                f"the motion of {key.removeprefix('__com__')!r} was not kept; "
                "run cycle(..., store_points=True)",
                element="cycle",
            )

    def point(self, name: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Position, velocity and acceleration of a drawing point, each (V, N, 2).

        Parameters
        ----------
        name : str
            A point of the drawing; m, m/s and m/s² in the drawing's axes.
        """
        self._stored(name)
        p, v, a = (np.stack([z.real, z.imag], axis=-1) for z in self._z[name])
        return p, v, a

    def coordinates(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Body coordinates q, q̇, q̈, each (V, N, n), as in
        :class:`~mechdyn.mechanism.kinematics.KinematicsResult` (x_G, y_G, φ per body)."""
        m = self.mechanism
        self._stored(f"__com__{m.bodies[0].name}")
        pos, vel, acc, rates = self._raw
        nb = len(m.bodies)
        z = np.stack([pos[..., -nb:], vel[..., -nb:], acc[..., -nb:]])  # the centres of mass come last
        out = np.empty((*z.shape, 3))
        out[..., 0], out[..., 1], out[..., 2] = z.real, z.imag, np.moveaxis(rates, -1, 0)
        q, qd, qdd = out.reshape(3, *self.angle.shape, 3 * nb)
        return q, qd, qdd

    @property
    def q(self) -> np.ndarray:
        """(V, N, n) body coordinates (see :meth:`coordinates`)."""
        return self.coordinates()[0]

    @property
    def multipliers(self) -> np.ndarray:
        """(V, N, m) the constraint multipliers λ of every variant: every load comes from them (the
        driving torque −λ_last, the joint forces, the frame's share); kept with the motions."""
        if self._lam is None:
            raise ModelError(
                "the multipliers are kept with the motions; run cycle(..., store_points=True)",
                element="cycle",
            )
        return self._lam

    def joint_force(self, joint: str) -> np.ndarray:
        """(V, N, 2) force that ``joint`` puts on its second body, N (as
        :meth:`DynamicsResult.joint_load` gives it, without the moment).

        Parameters
        ----------
        joint : str
            The joint's name."""
        m = self.mechanism
        names = [j.name for j in m.joints]
        if joint not in names:
            raise KeyError(joint)
        k = names.index(joint)
        j = m.joints[k]
        rows = self.multipliers[..., m.joint_rows[k]]
        if j.pins:
            return rows
        # a slider on a frame guide: the normal force λ₂ n on the guide (−λ₂ n on the slider)
        axis = cast(Prismatic, j).axis
        n = np.array([-math.sin(axis), math.cos(axis)])
        return rows[..., 1:2] * n

    @property
    def joint_force_peaks(self) -> dict[str, np.ndarray]:
        """Joint → (V,) largest force magnitude over the cycle on its second body, N."""
        return {j.name: self._peaks[:, k] for k, j in enumerate(self.mechanism.joints)}

    @property
    def status(self) -> tuple[str, ...]:
        """Per variant: ``"ok"``, or why it was not computed (the angle, the loop and the joint)."""
        return tuple(self.failures.get(v, "ok") for v in range(self.angle.shape[0]))

    @property
    def assembled(self) -> np.ndarray:
        """(V,) True for the variants that assemble over the whole cycle."""
        return np.isfinite(self.driving_torque).all(axis=1)

    def shaking_moment(self, about: Any = (0.0, 0.0)) -> np.ndarray:
        """(V, N) moment on the frame about a point, N·m.

        Parameters
        ----------
        about : (float, float)
            The point, m, in the drawing's axes (each coordinate at most 1e3 m in magnitude).
        """
        px, py = _point("shaking moment", "about", about)
        F = self._force
        return self.frame_moment - (px * F.imag - py * F.real)

    def to_frame(self) -> Any:
        """One row per variant: whether it assembles and its :meth:`summary` figures (units in the names)."""
        import pandas as pd

        cols: dict[str, Any] = {"variant": np.arange(self.angle.shape[0]), "assembled": self.assembled}
        for key, value in self.summary().items():
            if isinstance(value, dict):  # joint → peak: one column per joint
                cols |= {f"joint_{name}_force_peak_N": v for name, v in value.items()}
            else:
                cols[key] = value
        return pd.DataFrame(cols)

    def summary(self) -> dict[str, Any]:
        """Per variant (arrays over V): the torque and frame-load figures, the output's stroke, dead
        centres and inertia-force extremes, and (motions kept) each joint's force peak; the same
        functions as one design's :meth:`DynamicsResult.summary`."""
        from mechdyn.mechanism.extrema import load_figures, output_figures

        deg = np.degrees(self.angle)
        out: dict[str, Any] = load_figures(self.driving_torque, self.shaking_force, self.shaking_moment())
        s = self.output_position
        j = self.mechanism.output_joint()
        if s is not None and j is not None:
            f = _dot(self._inertia, complex(math.cos(j.axis), math.sin(j.axis)))
            out.update(output_figures(deg, s, f, self.mechanism.angle_datum == "bdc"))
        ends = self.mechanism.output_link()
        pivot = self.mechanism.driver.pivot
        if s is not None and j is not None and ends is not None and all(p in self._z for p in (*ends, pivot)):
            from mechdyn.mechanism.extrema import layout_figures

            za, zb = (self._z[p][0] for p in ends)
            out.update(layout_figures(zb - za, j.axis, self._z[pivot][0][:, 0], zb[:, 0]))
        out.update(self._motion_figures(deg))
        out["joint_force_peak_N"] = self.joint_force_peaks
        return out

    def _motion_figures(self, deg: np.ndarray) -> dict[str, np.ndarray]:
        """Each variant's smallest transmission angle (from the kernel's sin μ of every dyad) and a
        rocker output's swing: the functions of one design's :meth:`DynamicsResult.summary`."""
        from mechdyn.mechanism.extrema import bdc_origin, swing_figures, transmission_figures

        s = self.output_position
        origin = bdc_origin(deg, s) if s is not None and self.mechanism.angle_datum == "bdc" else None
        out: dict[str, np.ndarray] = {}
        if self._dyad_measure.shape[-1]:
            mu = np.degrees(np.arcsin(np.minimum(np.abs(self._dyad_measure), 1.0)))
            mu[list(self.failures)] = np.nan
            out.update(transmission_figures(deg, mu, origin)[0])
        rocker = self.mechanism.output_rocker()
        if rocker is not None and all(p in self._z for p in rocker[1:]):
            _, pivot, tip = rocker
            out.update(swing_figures(deg, self._z[tip][0] - self._z[pivot][0], origin))
        return out
