"""The train from the motor to the crank: stages (belts, gear meshes) with their efficiencies, and the
inertias on each shaft where they sit.

Shaft 0 is the motor's, shaft k the one stage k drives, the last one the crank's. Shaft k turns N_k
times as fast as the crank (N_k the product of the ratios of the stages after it). A stage passes the
power that crosses it with its efficiency η *in the direction the power flows*: driven from its input
(T_in ≥ 0, the crank turning forward) it delivers T_out = n η T_in; driven back from its output (a
flywheel ahead of it taking energy back, a braking load) it takes T_out = n T_in / η. Either way it
loses (1 − η) of the power entering it (the constant-efficiency model of a mesh or belt; Niemann and
Winter, *Maschinenelemente* II, §21 on gear losses; Uicker, Pennock and Shigley, *Theory of Machines
and Mechanisms*, 5th ed., §16, for the train's reduced inertia).

With the crank acceleration φ̈ the torque entering stage k follows from the motor down the train,

    T_in,1 = T_m − J_0 N_0 φ̈,   T_in,k+1 = T_out,k − J_k N_k φ̈,

and the crank's equation (I + J_c) φ̈ + ½ I′ φ̇² = T_out,last + Q closes it. Each T_in,k falls with φ̈
and each stage's law is concave and increasing in its input, so the crank's residual is a concave,
falling, piecewise-linear function of φ̈: Newton's method from any start reaches its root exactly, in
at most one step more than the number of stages whose power turns (the flow's direction in every
stage found with the acceleration, never assumed).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from mechdyn.errors import ModelError
from mechdyn.units import si_field

__all__ = ["Stage", "Train"]

BALANCE_RTOL = 1e-9
"""The crank's torque balance must close to this, relative to its terms, after the Newton steps."""


@dataclass(frozen=True)
class Stage:
    """One stage of the drive train: a belt or a gear mesh, and the shaft it drives.

    Parameters
    ----------
    ratio : float
        n, its input speed over its output speed, dimensionless, > 0.
    efficiency : float
        η of the power crossing it (in either direction), dimensionless, in (0, 1].
    inertia : float or quantity
        Moment of inertia on the shaft it drives (its wheel or pulley, the shaft), kg·m².
    name : str
        The stage's name (a flywheel may sit on the shaft it drives: ``flywheel_shaft = name``).
    """

    ratio: Any
    efficiency: Any = 1.0
    inertia: Any = 0.0
    name: str = ""

    def __post_init__(self) -> None:
        where = self.name or "stage"
        n = si_field(where, "ratio", self.ratio, "", positive=True)
        eta = si_field(where, "efficiency", self.efficiency, "", low=0.0, high=1.0, low_open=True)
        J = si_field(where, "inertia", self.inertia, "kg*m^2", nonnegative=True)
        object.__setattr__(self, "ratio", n)
        object.__setattr__(self, "efficiency", eta)
        object.__setattr__(self, "inertia", J)


@dataclass(frozen=True)
class Train:
    """The train's shafts as the dynamics read them (built by :class:`~mechdyn.drive.Drive`).

    Attributes
    ----------
    speed_ratios : tuple of float
        N_k, speed of shaft k over the crank's, for the motor's shaft and each stage's input side
        (one per stage), dimensionless.
    inertias : tuple of float
        J_k on the same shafts (rotor and flywheel where they sit), kg·m².
    ratios, efficiencies : tuple of float
        n and η of each stage, dimensionless.
    crank_inertia : float
        Inertia on the crank's shaft beside the mechanism's (the last stage's wheel, a crank-shaft
        flywheel), kg·m².
    """

    speed_ratios: tuple[float, ...]
    inertias: tuple[float, ...]
    ratios: tuple[float, ...]
    efficiencies: tuple[float, ...]
    crank_inertia: float

    @property
    def lossless(self) -> bool:
        """Whether every stage passes its power without loss."""
        return all(e == 1.0 for e in self.efficiencies)

    @property
    def reduced_inertia(self) -> float:
        """Σ N_k² J_k + J_c: the train's inertia at the crank, kg·m² (its kinetic energy ½ J φ̇²)."""
        return (
            sum(N * N * J for N, J in zip(self.speed_ratios, self.inertias, strict=True)) + self.crank_inertia
        )

    def _down(self, motor_torque: float, acc: float) -> tuple[float, float, float]:
        """Torque out of the last stage, its slope in φ̈, and the loss torque at the crank (power lost
        over φ̇), at the crank acceleration ``acc``."""
        T, dT, loss = motor_torque, 0.0, 0.0
        for N, J, n, eta, N_out in zip(
            self.speed_ratios,
            self.inertias,
            self.ratios,
            self.efficiencies,
            (*self.speed_ratios[1:], 1.0),
            strict=True,
        ):
            T -= J * N * acc
            dT -= J * N
            if T >= 0.0:  # power flows to the crank
                loss += (1.0 - eta) * T * N
                T, dT = n * eta * T, n * eta * dT
            else:  # power flows back from the crank side
                T, dT = n * T / eta, n * dT / eta
                loss -= (1.0 - eta) * T * N_out
        return T, dT, loss

    def accelerate(self, motor_torque: float, inertia: float, rest: float) -> tuple[float, float]:
        """The crank acceleration and the train's loss torque at the crank.

        Parameters
        ----------
        motor_torque : float
            T_m, the motor's shaft torque, N·m.
        inertia : float
            I(φ), the mechanism's inertia reduced to the crank, kg·m².
        rest : float
            Q(φ) − ½ I′(φ) φ̇², the rest of the crank's generalised force, N·m.

        Returns
        -------
        acceleration : float
            φ̈, rad/s².
        loss : float
            The power lost in the stages over φ̇, N·m (≥ 0).
        """
        Ic = inertia + self.crank_inertia
        acc = 0.0
        for _ in range(len(self.ratios) + 3):
            T, dT, loss = self._down(motor_torque, acc)
            residual = T + rest - Ic * acc
            slope = dT - Ic
            step = -residual / slope
            if step == 0.0 or abs(step) <= 1e-15 * (abs(acc) + abs((T + rest) / Ic)):
                return acc, loss
            acc += step
        T, dT, loss = self._down(motor_torque, acc)
        if abs(T + rest - Ic * acc) > BALANCE_RTOL * (abs(T) + abs(rest) + abs(Ic * acc)):
            raise ModelError("the drive train's torque balance did not close", element="drive")
        return acc, loss


def build_train(
    motor_inertia: float, stages: tuple[Stage, ...], flywheel_inertia: float, flywheel_shaft: int
) -> Train:
    """The shafts of a train: the rotor on shaft 0, each stage's inertia on the shaft it drives, the
    flywheel on shaft ``flywheel_shaft`` (0 the motor's, len(stages) the crank's)."""
    m = len(stages)
    J = [float(motor_inertia)] + [s.inertia for s in stages]
    J[flywheel_shaft] += float(flywheel_inertia)
    N = [math.prod(s.ratio for s in stages[k:]) for k in range(m)]
    return Train(
        speed_ratios=tuple(N),
        inertias=tuple(J[:m]),
        ratios=tuple(s.ratio for s in stages),
        efficiencies=tuple(s.efficiency for s in stages),
        crank_inertia=J[m],
    )
