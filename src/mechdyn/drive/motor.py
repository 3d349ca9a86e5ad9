"""Motor models: the torque a motor gives at a shaft speed.

Every motor has the same small interface: ``torque(speed)`` (N·m at the motor shaft for a shaft speed
in rad/s, a float or an array), ``rotor_inertia`` (kg·m²), ``no_load_speed`` (rad/s, where the torque
falls to zero: the speed a drive starts its search from) and ``name``. Two are built in: a tabulated
torque–speed curve (:class:`TorqueSpeedCurve`, e.g. from a maker's data sheet) and the induction motor
of Kloss's formula from its rating plate (:class:`InductionMotor`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from mechdyn.errors import ModelError
from mechdyn.units import si_field

__all__ = ["InductionMotor", "TorqueSpeedCurve"]


@dataclass(frozen=True)
class TorqueSpeedCurve:
    """A motor given by its torque–speed curve, interpolated linearly between the points.

    Beyond the last point the last segment is extended (the torque of a motor near its no-load speed
    falls on a straight line through zero); below the first point the first torque holds.

    Parameters
    ----------
    speeds : ndarray
        Shaft speeds, rad/s, increasing, at least two, the first ≥ 0.
    torques : ndarray
        Torque at each speed, N·m.
    rotor_inertia : float
        The rotor's moment of inertia, kg·m².
    name : str
        What the motor is, for tables.
    """

    speeds: np.ndarray
    torques: np.ndarray
    rotor_inertia: float = 0.0
    name: str = "motor"

    def __post_init__(self) -> None:
        w = np.asarray(self.speeds, dtype=float)
        t = np.asarray(self.torques, dtype=float)
        if w.ndim != 1 or w.shape != t.shape or w.size < 2:
            raise ModelError(
                f"speeds ({w.size}) and torques ({t.size}) must be two rows of the same length, at least 2",
                element=self.name,
                field="curve",
            )
        if not (np.isfinite(w).all() and np.isfinite(t).all()):
            raise ModelError(
                "the curve's speeds and torques must be finite", element=self.name, field="curve"
            )
        if w[0] < 0 or np.any(np.diff(w) <= 0):
            raise ModelError(
                f"speeds {w.tolist()} rad/s must start at 0 or above and increase point by point",
                element=self.name,
                field="curve",
            )
        if t[-1] >= t[-2] and t[-1] > 0:
            raise ModelError(
                "the torque must fall at the curve's last point (a motor's torque falls toward its no-load "
                "speed); end the curve with falling torques, e.g. at the no-load speed with 0 N*m",
                element=self.name,
                field="curve",
            )
        object.__setattr__(self, "speeds", w)
        object.__setattr__(self, "torques", t)
        object.__setattr__(
            self,
            "rotor_inertia",
            si_field(self.name, "rotor_inertia", self.rotor_inertia, "kg*m^2", nonnegative=True),
        )

    @classmethod
    def from_table(
        cls, rows: Sequence[tuple[Any, Any]], rotor_inertia: Any = 0.0, name: str = "motor"
    ) -> TorqueSpeedCurve:
        """A curve from rows of quantities, ``[("0 rpm", "2.2 kN*m"), ("1480 rpm", "480 N*m"), ...]``.

        Parameters
        ----------
        rows : sequence of (speed, torque)
            Speed (rpm, rad/s or any angular speed) and torque (N·m or any torque) per point.
        rotor_inertia : float or quantity
            kg·m² (a plain number is SI).
        name : str
            What the motor is.
        """
        w = [si_field(name, "curve", s, "rad/s") for s, _ in rows]
        t = [si_field(name, "curve", m, "N*m") for _, m in rows]
        return cls(np.array(w), np.array(t), rotor_inertia, name)

    def torque(self, speed: Any) -> Any:
        """Shaft torque, N·m, at shaft speeds ``speed`` (rad/s; float or array).

        Parameters
        ----------
        speed : float or ndarray
            Motor shaft speed, rad/s.
        """
        w, t = self.speeds, self.torques
        x = np.asarray(speed, dtype=float)
        slope = (t[-1] - t[-2]) / (w[-1] - w[-2])
        out = np.where(x > w[-1], t[-1] + slope * (x - w[-1]), np.interp(x, w, t))
        return float(out) if out.ndim == 0 else out

    @property
    def no_load_speed(self) -> float:
        """Speed where the torque falls to zero on the curve (or its extension), rad/s."""
        w, t = self.speeds, self.torques
        for i in range(len(w) - 1, 0, -1):
            if t[i - 1] > 0 >= t[i]:
                return float(w[i - 1] + t[i - 1] * (w[i] - w[i - 1]) / (t[i - 1] - t[i]))
        slope = (t[-1] - t[-2]) / (w[-1] - w[-2])
        return float(w[-1] - t[-1] / slope)


@dataclass(frozen=True)
class InductionMotor:
    """A three-phase induction (asynchronous) motor by Kloss's formula.

    The torque at slip s = (ω_s − ω)/ω_s is

    .. math:: T(s) = \\frac{2 T_k}{s/s_k + s_k/s} = \\frac{2 T_k s s_k}{s^2 + s_k^2},

    with T_k the pull-out (breakdown) torque and s_k its slip (Kloss's formula, from the equivalent
    circuit with the stator resistance neglected: e.g. R. Fischer, *Elektrische Maschinen*, Hanser,
    the chapter on the induction machine's torque–slip curve; I. Boldea and S. A. Nasar, *The
    Induction Machine Handbook*, CRC Press, 2002). Through the rated point (s_N, T_N) with T_k = λ T_N
    it gives s_k = s_N (λ + √(λ² − 1)). It holds for negative slip (above the synchronous speed the
    motor brakes as a generator); near standstill it is rougher than a maker's curve (a real motor's
    starting torque is higher: give a :class:`TorqueSpeedCurve` where start-up matters).

    Parameters
    ----------
    synchronous_speed : float
        ω_s, rad/s (2π f / pole pairs).
    pullout_torque : float
        T_k, N·m, positive.
    pullout_slip : float
        s_k, dimensionless, in (0, 1].
    rotor_inertia : float
        kg·m².
    name : str
        What the motor is, for tables.
    rated_speed : float, optional
        ω_N, rad/s (kept for tables).
    rated_torque : float, optional
        T_N, N·m (kept for tables).
    """

    synchronous_speed: float
    pullout_torque: float
    pullout_slip: float
    rotor_inertia: float = 0.0
    name: str = "induction motor"
    rated_speed: float | None = None
    rated_torque: float | None = None

    def __post_init__(self) -> None:
        si = {
            "synchronous_speed": ("rad/s", True),
            "pullout_torque": ("N*m", True),
            "rotor_inertia": ("kg*m^2", False),
        }
        for f, (unit, positive) in si.items():
            v = si_field(self.name, f, getattr(self, f), unit, positive=positive, nonnegative=not positive)
            object.__setattr__(self, f, v)
        s = si_field(self.name, "pullout_slip", self.pullout_slip, "", low=0.0, high=1.0, low_open=True)
        object.__setattr__(self, "pullout_slip", s)

    @classmethod
    def from_rating(
        cls,
        power: Any,
        synchronous_speed: Any,
        rated_speed: Any,
        pullout_ratio: float,
        rotor_inertia: Any = 0.0,
        name: str = "induction motor",
    ) -> InductionMotor:
        """An induction motor from its rating plate and catalogue (Kloss's formula through the rated
        point).

        T_N = P_N / ω_N, s_N = (ω_s − ω_N)/ω_s, T_k = λ T_N, s_k = s_N (λ + √(λ² − 1)).

        Parameters
        ----------
        power : float or quantity
            Rated shaft power P_N, W (e.g. ``"75 kW"``; a plain number is SI).
        synchronous_speed : float or quantity
            ω_s, rad/s (e.g. ``"1500 rpm"``).
        rated_speed : float or quantity
            ω_N, rad/s (e.g. ``"1480 rpm"``), below the synchronous speed.
        pullout_ratio : float
            λ = T_k / T_N, the breakdown (pull-out) torque over the rated torque, dimensionless, > 1
            (catalogues give 2 to 3.5).
        rotor_inertia : float or quantity
            kg·m².
        name : str
            What the motor is.

        Examples
        --------
        >>> from mechdyn.drive import InductionMotor
        >>> m = InductionMotor.from_rating("75 kW", "1500 rpm", "1480 rpm", 2.5)
        >>> round(m.torque(m.rated_speed) / m.rated_torque, 12)
        1.0
        """
        P = si_field(name, "power", power, "W", positive=True)
        ws = si_field(name, "synchronous_speed", synchronous_speed, "rad/s", positive=True)
        wn = si_field(name, "rated_speed", rated_speed, "rad/s", positive=True)
        lam = si_field(name, "pullout_ratio", pullout_ratio, "", low=1.0, low_open=True)
        if wn >= ws:
            raise ModelError(
                f"the rated speed ({wn:.6g} rad/s) must be below the synchronous speed ({ws:.6g} rad/s): "
                "an induction motor slips",
                element=name,
                field="rated_speed",
            )
        sn = (ws - wn) / ws
        sk = sn * (lam + math.sqrt(lam * lam - 1.0))
        if sk > 1.0:
            raise ModelError(
                f"rated slip {sn:.4g} and pull-out ratio {lam:g} put the pull-out slip at {sk:.4g}, beyond "
                "standstill; check the rated speed and the pull-out ratio",
                element=name,
                field="pullout_ratio",
            )
        Tn = P / wn
        return cls(ws, lam * Tn, sk, rotor_inertia, name, wn, Tn)

    def torque(self, speed: Any) -> Any:
        """Shaft torque, N·m, at shaft speeds ``speed`` (rad/s; float or array), by Kloss's formula.

        Parameters
        ----------
        speed : float or ndarray
            Motor shaft speed, rad/s.
        """
        if isinstance(speed, float):  # the integrators' inner loop: no arrays
            s = (self.synchronous_speed - speed) / self.synchronous_speed
            sk = self.pullout_slip
            return 2.0 * self.pullout_torque * s * sk / (s * s + sk * sk)
        slip = (self.synchronous_speed - np.asarray(speed, dtype=float)) / self.synchronous_speed
        sk = self.pullout_slip
        out = 2.0 * self.pullout_torque * slip * sk / (slip * slip + sk * sk)
        return float(out) if np.ndim(out) == 0 else out

    @property
    def no_load_speed(self) -> float:
        """The synchronous speed, rad/s (no torque without slip)."""
        return self.synchronous_speed

    @property
    def pullout_speed(self) -> float:
        """Shaft speed of the pull-out torque, rad/s: ω_s (1 − s_k)."""
        return self.synchronous_speed * (1.0 - self.pullout_slip)
