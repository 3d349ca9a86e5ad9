"""Rotating unbalance as the load on a machine on its mounts: rotors, their force and moment.

A rotor of unbalance U = m·e (kg·m) spinning at Ω about the unit axis a puts on its bearings the
rotating force F(t) = U Ω² (u cos θ + v sin θ), θ = Ω t + φ, in the plane normal to a (Rao,
*Mechanical Vibrations*, 6th ed., §3.7 "Response of a damped system under rotating unbalance"; the
force of the heavy spot, pointing from the axis to it). u is the part of the machine's +z normal to
the axis (so that with phase 0 a horizontal rotor's heavy spot points up at t = 0), or +x for a
vertical axis; v = a × u, so that a positive speed turns the heavy spot right-handed about a. The
moment about the machine origin is r × F, r the centre of the rotor's plane of unbalance (a point
on its axis).

Several rotors add. A steady state needs one period: their speeds must be whole multiples n_k of a
common Ω₀ (the same speed, a 2:1 gear, a 148:295 belt drive), and the load is then the Fourier
series with the k-th rotor's force at harmonic h = abs(n_k) of Ω₀,
c_h = ½ U Ω² (u − i s v) e^{i s φ}, s the sign of the speed.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from fractions import Fraction
from typing import Any

import numpy as np

from mechdyn.checks import check_array
from mechdyn.errors import ModelError
from mechdyn.units import convert, si_field

__all__ = [
    "MAX_ROTOR_ORDER",
    "MIN_ROTOR_SPEED",
    "Rotor",
    "frequency_given_as_speed",
    "rotor_tuple",
    "unbalance_coefficients",
]

MAX_ROTOR_ORDER = 1000
"""The largest whole-number ratio of rotor speeds to their common fundamental (e.g. 1000:999)."""
MIN_ROTOR_SPEED = 0.01
"""The slowest rotor speed accepted, rad/s (about 0.1 rpm): slower, an unbalance shakes nothing."""
MAX_FORCE = 1e11
"""The largest unbalance force U Ω² accepted, N (the bound of every force of the package)."""
_AXES = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0)}


def _rpm(w: float) -> str:
    return f"{convert(w, 'rad/s', 'rpm'):.6g} rpm"


def frequency_given_as_speed(value: Any) -> str | None:
    """Why a speed given as a bare rate (``"150 1/s"``) is refused, or None.

    ``1/s`` says neither radians nor turns: it converts to rad/s one to one, so a shaft's turning
    frequency written so would be a speed 2π times too low. A speed in rpm, rad/s, deg/s, rev/s or Hz
    (turns a second, :func:`mechdyn.units.to_si`) converts differently to rad/s and to Hz; a bare rate
    converts alike to both.

    Parameters
    ----------
    value : str, quantity or float
        The speed as given (a plain number, rad/s, is always accepted).
    """
    from mechdyn.units import UnitError, to_si

    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return None
    try:
        as_speed, as_frequency = to_si(value, "rad/s"), to_si(value, "Hz")
    except UnitError:
        return None  # the conversion itself gives the message
    if as_speed == 0 or not math.isclose(as_speed, as_frequency, rel_tol=1e-12):
        return None
    return (
        f"{value!r} says neither radians nor turns; give the speed in rpm, Hz or rad/s, e.g. "
        f"'{convert(as_frequency, 'turn/s', 'rpm'):g} rpm' if it is turns a second"
    )


@dataclass(frozen=True)
class Rotor:
    """A rotor with a residual unbalance, spinning at a constant speed on the machine.

    Parameters
    ----------
    unbalance : float or quantity
        U = m·e, kg·m (``"0.02 kg*m"``, ``"20 kg*mm"``), positive. ISO 21940-11 (formerly ISO 1940-1)
        gives the permissible residual unbalance of a balance grade G (mm/s) as U = G·m_rotor/Ω.
    speed : float or quantity
        Ω, rad/s (``"1480 rpm"``), at least 0.01 rad/s in magnitude; its sign is the sense of
        rotation about ``axis`` (positive: right-handed).
    axis : str or sequence of float
        The spin axis: ``"x"``, ``"y"``, ``"z"`` or a direction [ax, ay, az] (dimensionless,
        normalised here) in machine coordinates (z up).
    position : sequence of float or quantity
        The centre of the rotor's plane of unbalance (a point on its axis), m, machine coordinates;
        the force's moment about the machine origin is r × F.
    phase : float or quantity
        φ, rad (``"90 deg"``): the heavy spot's angle at t = 0 from the reference direction u (the part
        of +z normal to the axis, or +x for a vertical axis), turning with the rotor.
    name : str
        The rotor's name, for messages and tables.

    Raises
    ------
    mechdyn.errors.ModelError
        For a unit that is not kg·m, rad/s, m or rad, a value that is not finite, a zero unbalance,
        a speed under :data:`MIN_ROTOR_SPEED`, a zero axis, or a force U Ω² over 1e11 N.

    Examples
    --------
    >>> from mechdyn.support import Rotor
    >>> fan = Rotor("0.02 kg*m", "1480 rpm", "y", position=("0 m", "0 m", "0.5 m"))
    >>> round(fan.force_amplitude, 1)  # U Ω², N
    480.4
    """

    unbalance: Any
    speed: Any
    axis: Any
    position: Any = (0.0, 0.0, 0.0)
    phase: Any = 0.0
    name: str = "rotor"

    def __post_init__(self) -> None:
        n = self.name
        U = si_field(n, "unbalance", self.unbalance, "kg*m", positive=True, what="unbalance")
        wrong = frequency_given_as_speed(self.speed)
        if wrong:
            raise ModelError(wrong, element=n, field="speed")
        w = si_field(n, "speed", self.speed, "rad/s", what="speed")
        if abs(w) < MIN_ROTOR_SPEED:
            raise ModelError(
                f"{_rpm(w)}: a rotor turning slower than {_rpm(MIN_ROTOR_SPEED)} shakes nothing; give its "
                'running speed, e.g. "1480 rpm" (its sign is the sense of rotation about the axis)',
                element=n,
                field="speed",
            )
        force = U * w * w
        if force > MAX_FORCE:
            raise ModelError(
                f"{U:g} kg·m at {_rpm(w)} makes a force U Ω² of {force:.3g} N, beyond any machine this "
                f"package models (at most {MAX_FORCE:g} N); check the unbalance, the speed and their units",
                element=n,
                field="unbalance",
            )
        if isinstance(self.position, str) or np.ndim(self.position) != 1 or len(self.position) != 3:
            raise ModelError(
                f"{self.position!r} must be three lengths [x, y, z] in m", element=n, field="position"
            )
        r = np.array([si_field(n, "position", v, "m") for v in self.position])
        object.__setattr__(self, "unbalance", U)
        object.__setattr__(self, "speed", w)
        object.__setattr__(self, "axis", _axis(n, self.axis))
        object.__setattr__(self, "position", r)
        object.__setattr__(self, "phase", si_field(n, "phase", self.phase, "rad", what="phase"))

    @property
    def force_amplitude(self) -> float:
        """U Ω², N: the magnitude of the rotating force."""
        return float(self.unbalance * self.speed**2)

    @property
    def basis(self) -> tuple[np.ndarray, np.ndarray]:
        """(u, v): the unit vectors of the plane of rotation, phase 0 along u, v = axis × u."""
        a = self.axis
        up = np.array([0.0, 0.0, 1.0]) - a[2] * a
        if np.linalg.norm(up) < 1e-9:  # a vertical axis: the phase counts from +x
            up = np.array([1.0, 0.0, 0.0]) - a[0] * a
        u = up / np.linalg.norm(up)
        return u, np.cross(a, u)

    def force(self, t: Any) -> np.ndarray:
        """(…, 6) the rotor's force (N) and its moment about the machine origin (N·m) at times t.

        Parameters
        ----------
        t : float or array_like
            Times, s, finite.
        """
        t = check_array(self.name, "t", t, "s", what="times")
        theta = self.speed * t + self.phase
        u, v = self.basis
        F = self.force_amplitude * (np.multiply.outer(np.cos(theta), u) + np.multiply.outer(np.sin(theta), v))
        return np.concatenate([F, np.cross(self.position, F)], axis=-1)

    def with_speed(self, speed: Any) -> Rotor:
        """The same rotor at another speed (same sense of rotation when ``speed`` is a magnitude ≥ 0).

        Parameters
        ----------
        speed : float or quantity
            rad/s (or ``"3000 rpm"``); a non-negative value keeps the rotor's sense of rotation, a
            negative one reverses it.
        """
        w = si_field(self.name, "speed", speed, "rad/s", what="speed")
        return replace(self, speed=math.copysign(w, self.speed) if w >= 0 else w)

    def scaled(self, factor: float) -> Rotor:
        """The same rotor with its unbalance multiplied by ``factor``.

        Parameters
        ----------
        factor : float
            Dimensionless, positive.
        """
        return replace(self, unbalance=self.unbalance * factor)


def _axis(name: str, value: Any) -> np.ndarray:
    if isinstance(value, str):
        key = value.strip().lower()
        if key not in _AXES:
            raise ModelError(
                f'{value!r} is not an axis: give "x", "y" or "z", or a direction [ax, ay, az]',
                element=name,
                field="axis",
            )
        return np.array(_AXES[key])
    a = check_array(name, "axis", value, what="direction")
    norm = float(np.linalg.norm(a)) if a.shape == (3,) else 0.0
    if norm == 0.0:
        raise ModelError(
            f"{np.asarray(value).tolist()} is not a direction: give three components [ax, ay, az], not "
            'all zero, or "x", "y" or "z"',
            element=name,
            field="axis",
        )
    return a / norm


def rotor_tuple(rotors: Rotor | Sequence[Rotor]) -> tuple[Rotor, ...]:
    """One rotor or several, as a non-empty tuple of :class:`Rotor` with distinct names.

    Parameters
    ----------
    rotors : Rotor or sequence of Rotor
        The rotors.
    """
    out = (rotors,) if isinstance(rotors, Rotor) else tuple(rotors)
    if not out or not all(isinstance(r, Rotor) for r in out):
        raise ModelError("give one Rotor or a sequence of them", element="load", field="rotors")
    names = [r.name for r in out]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise ModelError(f"rotor names {dup} appear more than once", element="load", field="rotors")
    return out


def common_orders(rotors: Sequence[Rotor]) -> tuple[float, np.ndarray]:
    """The common fundamental Ω₀ (rad/s) of the rotors' speeds and each speed's whole order, signed.

    Raises
    ------
    mechdyn.errors.ModelError
        When two speeds are not in a whole-number ratio with orders up to :data:`MAX_ROTOR_ORDER`.
    """
    w = np.array([abs(r.speed) for r in rotors])
    ref = int(np.argmin(w))
    fractions = []
    for r, wk in zip(rotors, w, strict=True):
        rho = wk / w[ref]
        f = Fraction(rho).limit_denominator(MAX_ROTOR_ORDER)
        if abs(rho - f.numerator / f.denominator) > 1e-9 * rho or f.numerator > MAX_ROTOR_ORDER:
            slow = rotors[ref]
            raise ModelError(
                f"{r.name!r} at {_rpm(r.speed)} and {slow.name!r} at {_rpm(slow.speed)} are not in a "
                f"whole-number ratio (theirs is {rho:.9g}, not n:m with n, m ≤ {MAX_ROTOR_ORDER}): a steady "
                "state needs a common period. Round the speeds to a simple ratio (one shaft, a gear or a "
                "belt drive gives one), or analyse the rotors one at a time",
                element=r.name,
                field="speed",
            )
        fractions.append(f)
    lcm = math.lcm(*(f.denominator for f in fractions))
    orders = np.array([f.numerator * (lcm // f.denominator) for f in fractions], dtype=int)
    g = math.gcd(*orders.tolist())
    orders //= g
    if orders.max() > MAX_ROTOR_ORDER:
        raise ModelError(
            f"the rotors' speeds {', '.join(_rpm(r.speed) for r in rotors)} have a common period of "
            f"{orders.max()} turns of the fastest (more than {MAX_ROTOR_ORDER}); round the speeds to a "
            "simpler ratio, or analyse the rotors one at a time",
            element=rotors[0].name,
            field="speed",
        )
    base = float(w[ref] / orders[ref])
    return base, orders * np.sign([r.speed for r in rotors]).astype(int)


def unbalance_coefficients(rotors: Rotor | Sequence[Rotor]) -> tuple[float, np.ndarray]:
    """The period (s) of the rotors' load and its (H + 1, 6) complex Fourier coefficients (N, N·m).

    c_h += ½ U Ω² (u − i s v) e^{i s φ} for each rotor of order n = s h (h = abs(n)) of the common
    fundamental, its moment r × c; f(t) = c₀ + 2 Re Σ c_h e^{i h Ω₀ t}
    (:mod:`~mechdyn.support.excitation`).

    Parameters
    ----------
    rotors : Rotor or sequence of Rotor
        One or several rotors with speeds in whole-number ratios.
    """
    rotors = rotor_tuple(rotors)
    base, orders = common_orders(rotors)
    c = np.zeros((int(np.abs(orders).max()) + 1, 6), dtype=complex)
    for r, n in zip(rotors, orders, strict=True):
        s = 1.0 if n > 0 else -1.0
        u, v = r.basis
        F = 0.5 * r.force_amplitude * (u - 1j * s * v) * np.exp(1j * s * r.phase)
        c[abs(int(n)), :3] += F
        c[abs(int(n)), 3:] += np.cross(r.position, F)
    return 2 * math.pi / base, c
