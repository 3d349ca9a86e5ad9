"""What drives and loads a mechanism: the :class:`Driver` (the crank, at constant speed or following
a speed profile, checked against θ̈ = θ̇ dθ̇/dθ) and the process forces on its bodies
(:class:`ProcessForce`, :class:`TabulatedForce` read from a model file's table).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from mechdyn.checks import magnitude_limit
from mechdyn.errors import ModelError
from mechdyn.units import si_field

__all__ = ["Driver", "ProcessForce", "TabulatedForce"]


@dataclass(frozen=True)
class Driver:
    """The crank: a body turned about a pivot at constant speed, or following a speed profile.

    Parameters
    ----------
    body : str
    pivot, tip : str
        Drawing points; the crank angle θ is the direction from pivot to tip.
    speed : float or quantity
        θ̇, rad/s (e.g. ``"15 rpm"``), not zero, of magnitude from 1e-6 to 1e8 rad/s; positive
        counter-clockwise. With a profile, its sign gives
        the direction of rotation.
    profile : callable, optional
        ``profile(angle)`` for arrays of crank angle θ from the mechanism's ``angle_datum`` (rad, in
        [0, 2π), counter-clockwise: the angle that results, tables and plots show, and that process
        force tables are read against): either ``(speed, acceleration)``, θ̇ (rad/s, the sign of
        ``speed``, never zero) and θ̈ (rad/s²), which must agree with ``θ̈ = θ̇ dθ̇/dθ`` (chain rule);
        or the speed alone, and the acceleration is derived from it (a periodic cubic spline through
        1024 samples). With ``angle_datum = "bdc"`` the angle counts from the located bottom dead
        centre, which the motion finds first. None means constant speed.

    Raises
    ------
    ModelError
        When the profile's acceleration does not follow from its speed (naming the largest mismatch
        and where), or the profile is not periodic.
    """

    body: str
    pivot: str
    tip: str
    speed: Any
    profile: Callable[[np.ndarray], Any] | None = None

    def __post_init__(self) -> None:
        v = si_field("driver", "speed", self.speed, "rad/s", nonzero=True, what="crank speed")
        object.__setattr__(self, "speed", v)
        if self.profile is not None:
            object.__setattr__(self, "profile", _checked_profile(self.profile, v))

    def rates(self, angle: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """θ̇ (rad/s) and θ̈ (rad/s²) at crank angles from the angle datum (rad).

        Parameters
        ----------
        angle : ndarray
            Crank angles from the mechanism's angle datum, rad (any shape; read modulo 2π).
        """
        angle = np.mod(np.asarray(angle, dtype=float), 2 * math.pi)
        if self.profile is None:
            return np.full(angle.shape, self.speed), np.zeros(angle.shape)
        w, a = (np.broadcast_to(np.asarray(x, dtype=float), angle.shape) for x in self.profile(angle))
        _check_profile_speed(w, angle, self.speed)
        if not np.isfinite(a).all():
            k = int(np.argmin(np.isfinite(a)))
            raise ModelError(
                f"θ̈ = {a.flat[k]:g} rad/s² at crank angle {math.degrees(angle.flat[k]):.4g}°: the speed "
                "profile's acceleration must be finite",
                element="driver",
                field="profile",
            )
        return w, a

    def time(self, turned: np.ndarray, start: float = 0.0) -> np.ndarray:
        """Time to turn the crank by each angle, s (t = ∫ dθ/θ̇ ≥ 0, trapezoidal on 4097 points).

        Parameters
        ----------
        turned : ndarray
            Angles turned in the direction of rotation, rad, non-negative.
        start : float
            The crank angle from the angle datum where the turning starts, rad (the profile is read
            at ``start + sign(speed) · turned``; a whole turn takes the same time from any start).
        """
        turned = np.asarray(turned, dtype=float)
        if self.profile is None:
            return turned / abs(self.speed)
        fine = np.linspace(0.0, float(np.max(np.abs(turned))) if turned.size else 0.0, 4097)
        w, _ = self.rates(start + np.sign(self.speed) * fine)
        t = np.concatenate([[0.0], np.cumsum(0.5 * (1 / np.abs(w[1:]) + 1 / np.abs(w[:-1])) * np.diff(fine))])
        return np.interp(np.abs(turned), fine, t)


# samples of a speed profile over one turn for its check, and the mismatch it may show: a profile
# whose acceleration is exact shows the O(h²) error of the differences, h = 2π/_PROFILE_SAMPLES
_PROFILE_SAMPLES = 1024
_PROFILE_RTOL = 1e-4


def _check_profile_speed(w: np.ndarray, angle: np.ndarray, speed: float) -> None:
    """Refuse a profile speed θ̇ that is not finite, beyond any machine, zero or against ``speed``."""
    limit = magnitude_limit("rad/s")
    with np.errstate(invalid="ignore"):
        bad = ~np.isfinite(w) | (np.abs(w) > limit) | (w == 0) | (np.sign(w) != np.sign(speed))
    if bad.any():
        k = int(np.argmax(bad))
        raise ModelError(
            f"θ̇ = {w.flat[k]:g} rad/s at crank angle {math.degrees(angle.flat[k]):.4g}°: the speed profile "
            f"must stay finite (at most {limit:g} rad/s in magnitude), keep the sign of the speed and "
            "never stop the crank",
            element="driver",
            field="profile",
        )


def _checked_profile(profile: Callable[[np.ndarray], Any], speed: float) -> Callable[[np.ndarray], Any]:
    """The profile as (θ̇, θ̈); θ̈ derived when only θ̇ is given, checked against ``θ̇ dθ̇/dθ`` when given.

    The derivative dθ̇/dθ is taken from a periodic cubic spline through the samples, whose error on
    a smooth profile is O(h⁴) (de Boor, *A Practical Guide to Splines*, ch. V).
    """
    from scipy.interpolate import CubicSpline

    psi = np.linspace(0.0, 2 * math.pi, _PROFILE_SAMPLES + 1)
    out = profile(psi)
    given = isinstance(out, tuple) and len(out) == 2
    w = np.broadcast_to(np.asarray(out[0] if given else out, dtype=float), psi.shape)
    _check_profile_speed(w, psi, speed)
    if abs(w[-1] - w[0]) > 1e-6 * np.abs(w).max():
        raise ModelError(
            f"the speed profile is not periodic: θ̇ = {w[0]:.6g} rad/s at 0° and {w[-1]:.6g} rad/s after "
            "one turn; the crank must come back to the same speed",
            element="driver",
            field="profile",
        )
    spline = CubicSpline(psi, np.append(w[:-1], w[0]), bc_type="periodic")
    slope = spline.derivative()
    if not given:

        def derived(angle: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            t = np.mod(angle, 2 * math.pi)
            omega = spline(t)
            return omega, omega * slope(t)

        return derived
    a = np.broadcast_to(np.asarray(out[1], dtype=float), psi.shape)
    if not np.isfinite(a).all():
        k = int(np.argmin(np.isfinite(a)))
        raise ModelError(
            f"θ̈ = {a[k]:g} rad/s² at crank angle {math.degrees(psi[k]):.4g}°: the speed profile's "
            "acceleration must be finite",
            element="driver",
            field="profile",
        )
    expected = w * slope(psi)
    scale = max(float(np.abs(expected).max()), float(np.abs(a).max()), 1e-12 * speed**2)
    mismatch = np.abs(a - expected)
    k = int(np.argmax(mismatch))
    if mismatch[k] > _PROFILE_RTOL * scale:
        raise ModelError(
            f"the speed profile's acceleration does not follow from its speed: θ̈ = {a[k]:.6g} rad/s² at "
            f"{math.degrees(psi[k]):.4g}° where θ̇ dθ̇/dθ = {expected[k]:.6g} rad/s² (mismatch "
            f"{mismatch[k] / scale:.3g} of the largest acceleration); return θ̈ = θ̇ dθ̇/dθ, or the "
            "speed alone and let it be derived",
            element="driver",
            field="profile",
        )
    return profile


@dataclass(frozen=True)
class ProcessForce:
    """An external force on a body at a drawing point, as a function of the crank angle.

    Parameters
    ----------
    body, point : str
    force : callable
        ``force(theta, position) -> (Fx, Fy)`` in N for arrays of crank angle (rad, from the
        datum) and of the point's position along the output axis (m); e.g. a forming force over part
        of the stroke. Its values must be finite and at most 1e11 N in magnitude wherever the
        mechanism assembles (:meth:`values` checks them).
    """

    body: str
    point: str
    force: Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]

    def values(
        self, theta: np.ndarray, position: np.ndarray, valid: np.ndarray | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """(Fx, Fy), N, at crank angles ``theta`` and output positions ``position``, checked.

        Parameters
        ----------
        theta : ndarray
            Crank angles, rad.
        position : ndarray
            The output's position along its axis, m (zeros without an output), of ``theta``'s shape.
        valid : ndarray of bool, optional
            Where the mechanism assembled (dimensionless flags); elsewhere (a variant left NaN) the
            values are not checked.

        Raises
        ------
        mechdyn.errors.ModelError
            Naming the force, the first crank angle where it is not finite or beyond 1e11 N, and the
            value.
        """
        fx, fy = self.force(theta, position)
        Fx, Fy = (np.broadcast_to(np.asarray(f, dtype=float), np.shape(theta)) for f in (fx, fy))
        limit = magnitude_limit("N")
        with np.errstate(invalid="ignore"):
            bad = ~(np.isfinite(Fx) & np.isfinite(Fy)) | (np.abs(Fx) > limit) | (np.abs(Fy) > limit)
        if valid is not None:
            bad &= valid
        if bad.any():
            k = int(np.argmax(bad))
            raise ModelError(
                f"(Fx, Fy) = ({Fx.flat[k]:g}, {Fy.flat[k]:g}) N at crank angle "
                f"{math.degrees(float(np.asarray(theta).flat[k])):.4g}°: the force must be finite and at "
                f"most {limit:g} N in magnitude",
                element=f"process force on {self.body!r} at {self.point!r}",
                field="force",
            )
        return Fx, Fy


@dataclass(frozen=True, eq=False)
class TabulatedForce:
    """A process force read from a table (a mechanism file's ``[[process_forces]]``): its magnitude
    linear between the rows and zero outside them, against the crank angle or the output's position,
    along a fixed direction. Called as a :class:`ProcessForce`'s ``force``.

    Parameters
    ----------
    versus : {"angle", "position"}
        What the rows are read against.
    x : ndarray
        The rows' crank angles (rad, from the datum) or positions along the output axis (m),
        increasing.
    magnitude : ndarray
        The force at each row, N.
    direction : float
        The force's direction from +x, rad.
    """

    versus: str
    x: np.ndarray
    magnitude: np.ndarray
    direction: float

    def __call__(self, angle: np.ndarray, position: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(Fx, Fy), N, at crank angles ``angle`` (rad) and output positions ``position`` (m)."""
        if self.versus == "angle":  # read on the circle: rows may start below 0 or end at 360°
            x = np.mod(angle, 2 * math.pi)
            f = sum(
                np.interp(x + turn, self.x, self.magnitude, left=0.0, right=0.0)
                for turn in (-2 * math.pi, 0.0)
            )
        else:
            f = np.interp(position, self.x, self.magnitude, left=0.0, right=0.0)
        return f * math.cos(self.direction), f * math.sin(self.direction)

    def kinks(self) -> list[tuple[str, np.ndarray]]:
        """Where the force is not smooth: its rows, against ``versus`` (rad or m)."""
        return [(self.versus, self.x)]
