"""The operating point of a free-running train: the torque that holds a speed, and a motor's slope.

A train that is not held at its speed (``boundary="free"`` or ``"motor"`` of
:func:`mechdyn.gear_dynamics.periodic.linear_periodic`) turns steadily when the drive's mean torque
balances the load and the drag of the grounded dampers: rᵀ (Q_load − Ω C r + T₀ t_d) = 0, with r the
rigid rotation per unit reference speed and t_d the drive disk's row of θ = T q (the principle of
virtual power for the rigid motion). About that point a motor's torque follows its torque–speed curve;
linearised, it acts as a damper on its disk of −dT/dω (times the square of its ratio), the slope of
the curve where it gives T₀.

For a speed other than the curve's own operating speed the curve is taken moved along the speed axis
to that speed, as a frequency converter at constant V/f moves an induction motor's curve (the torque
depends on the slip speed, the rotor frequency; e.g. Boldea & Nasar, *The Induction Machine
Handbook*, CRC Press, 2002, ch. on variable-frequency operation): the slope is the curve's slope at
the torque T₀. At the speed where the curve itself gives T₀ (a motor on the mains) this is exactly the
linearisation of what :func:`mechdyn.gear_dynamics.simulate` integrates. The curve is read
quasi-statically (no flux dynamics: a real induction motor's torque lags its slip at the mesh
frequencies), and the motor's sense (``direction``) does not enter: the train turning the other way
is the mirror image.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from mechdyn.errors import ModelError

__all__ = ["MotorSlope", "balancing"]

#: Speed steps over the motor's speed range in which the stable branch is searched for the torque.
_SCAN = 4000


def balancing(
    system: Any, r: np.ndarray, disk: str, torques: np.ndarray, drag: np.ndarray
) -> tuple[np.ndarray, tuple[float, float], np.ndarray, np.ndarray]:
    """The drive disk's row, the mean torque it must give and the balanced generalised forces.

    Parameters
    ----------
    system : GearSystem
    r : ndarray
        (n,) rigid rotation per unit reference angle, rad/rad.
    disk : str
        The drive disk.
    torques : ndarray
        (n,) generalised force of the load torques, N·m.
    drag : ndarray
        (n,) generalised force of the grounded dampers per unit reference speed, N·m·s/rad.

    Returns
    -------
    row : ndarray
        (n,) generalised force of a unit torque on the drive disk, rad per unit coordinate.
    need : tuple of float
        (a, b): the drive torque on its disk at reference speed Ω is a + b Ω, N·m (a in N·m, b in
        N·m·s/rad), in the global positive sense.
    torques, drag : ndarray
        The load and drag with that torque added: their rigid-body components vanish.
    """
    row = np.asarray(system.T, float)[system.disk(disk)]  # names the disks where it is not one
    share = float(row @ r)
    if abs(share) <= 1e-12 * np.abs(r).max():
        raise ModelError(
            f"disk {disk!r} does not turn with the train, so it cannot drive it; give a disk of the "
            "driven branch",
            element="gear dynamics",
            field="drive_disk",
        )
    a, b = -float(r @ torques) / share, -float(r @ drag) / share
    return row, (a, b), torques + a * row, drag + b * row


class MotorSlope:
    """A motor's linearised torque–speed slope on its disk at the torque that holds each speed.

    Parameters
    ----------
    motor : MotorTorque
        The motor (:class:`mechdyn.gear_dynamics.loads.MotorTorque`).
    row : ndarray
        (m,) the motor disk's angle per state coordinate, rad per unit coordinate.
    need : tuple of float
        (a, b): the torque on the disk that holds reference speed Ω is a + b Ω, N·m.
    turning : float
        The motor disk's speed per unit reference speed, rad/rad (signed).
    """

    def __init__(self, motor: Any, row: np.ndarray, need: tuple[float, float], turning: float) -> None:
        self.motor, self.row, self.need, self.turning = motor, np.asarray(row, float), need, float(turning)

    def torque(self, speed: float) -> float:
        """The motor's shaft torque that holds reference speed ``speed`` (rad/s), N·m, positive when
        it drives the train.

        Parameters
        ----------
        speed : float
            Reference speed Ω, rad/s.
        """
        a, b = self.need
        return (a + b * speed) * float(np.sign(self.turning) or 1.0) / float(self.motor.ratio)

    def shaft_speed(self, torque: float) -> float:
        """The speed on the curve's stable branch (falling torque) at which the motor gives
        ``torque`` (N·m), rad/s.

        Parameters
        ----------
        torque : float
            Shaft torque, N·m (negative: braking, above the no-load speed).

        Raises
        ------
        mechdyn.errors.ModelError
            Where the torque lies beyond the curve's pull-out torque.
        """
        from scipy.optimize import brentq

        curve = self.motor.motor
        w0 = float(curve.no_load_speed)
        sense = 1.0 if torque >= 0 else -1.0  # motoring below the no-load speed, braking above it
        w = w0 - sense * w0 * np.arange(_SCAN + 1) / _SCAN
        t = sense * np.asarray(curve.torque(w), float)  # grows along the stable branch
        past = np.flatnonzero(np.diff(t) < 0)  # the first step after the pull-out point
        end = int(past[0]) if past.size else _SCAN
        reached = np.flatnonzero(t[: end + 1] >= abs(torque))
        if not reached.size:
            raise ModelError(
                f"the motor must give {torque:.4g} N·m to hold the load at this speed but its curve "
                f"reaches only {sense * t[: end + 1].max():.4g} N·m on its stable branch (pull-out); give a "
                "larger motor or a smaller load",
                element=str(self.motor.disk),
                field="motor",
            )
        i = int(reached[0])
        if i == 0 or t[i] == abs(torque):
            return float(w[i])
        root = brentq(lambda x: float(curve.torque(float(x))) - torque, w[i - 1], w[i], xtol=1e-13 * w0)
        return float(root)

    def damping(self, speed: float) -> float:
        """The damping of the motor on its disk at reference speed ``speed`` (rad/s), N·m·s/rad:
        ratio² · (−dT/dω) where the curve gives the holding torque.

        Parameters
        ----------
        speed : float
            Reference speed Ω, rad/s.
        """
        curve = self.motor.motor
        torque = self.torque(speed)
        w = self.shaft_speed(torque)
        h = 1e-7 * float(curve.no_load_speed)
        slope = (float(curve.torque(w + h)) - float(curve.torque(w - h))) / (2 * h)
        return float(self.motor.ratio) ** 2 * max(-slope, 0.0)

    def describe(self) -> str:
        """The drive in words, for a result's notes."""
        return (
            f"no disk held: the motor on disk {self.motor.disk!r} drives, its torque following its "
            "torque–speed curve about the torque that holds the load (the curve moved to each speed, as "
            "a frequency converter at constant V/f moves it, and read quasi-statically, as simulate reads "
            "it; its slope damps the train's rigid rotation)"
        )
