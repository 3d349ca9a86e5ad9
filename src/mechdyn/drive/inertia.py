"""The mechanism reduced to its crank: equivalent inertia I(φ), its slope I′(φ) and the generalised
force Q(φ) of gravity and process forces, from the assembled model.

With body coordinates q (x_G, y_G, ψ per body) and the diagonal mass matrix M (m, m, J_G per body),
the kinetic energy is ½ φ̇² q′ᵀ M q′, q′ = dq/dφ, so the mechanism's inertia reduced to the crank is

    I(φ) = q′ᵀ M q′,   I′(φ) = 2 q′ᵀ M q″,

and the applied forces Q_q (gravity, process forces) do the work Q(φ) = Q_qᵀ q′ per radian
(Lagrange's equation of a one-degree-of-freedom machine: I φ̈ + ½ I′ φ̇² = T + Q; Uicker, Pennock and
Shigley, *Theory of Machines and Mechanisms*, 5th ed., §16, "equivalent inertia" and the
energy equation; Harrison and Nettleton, *Advanced Engineering Dynamics*, ch. 7). q′ and q″ come from
the kinematics at constant speed Ω (q̇ = q′ Ω, q̈ = q″ Ω²), never from hand-typed formulas.

φ is the crank angle *turned* in the driver's direction of rotation, from the mechanism's angle datum,
so φ̇ > 0; a crank driven clockwise has φ = −θ.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import cached_property
from typing import Any

import numpy as np

from mechdyn.errors import ModelError

__all__ = ["ReducedMechanism", "reduce_to_crank"]


@dataclass(frozen=True)
class ReducedMechanism:
    """A mechanism's inertia and applied forces reduced to its crank, at equally spaced angles.

    Attributes
    ----------
    mechanism : Mechanism
        The mechanism (its driver at constant speed).
    kinematics : KinematicsResult
        Its kinematics at constant speed Ω, in the order of ``turned``.
    turned : ndarray
        (N,) φ, crank angle turned from the first sample in the direction of rotation, rad, 0 … 2π − h.
    angle : ndarray
        (N,) the crank angle from the mechanism's datum of each sample, rad (what tables show).
    inertia : ndarray
        (N,) I(φ), kg·m².
    inertia_slope : ndarray
        (N,) dI/dφ, kg·m²/rad.
    force : ndarray
        (N,) Q(φ), generalised applied force on the crank (gravity and process forces), N·m.
    process_force : ndarray
        (N,) the process forces' share of Q, N·m.
    direction : float
        +1 when the crank turns counter-clockwise, −1 clockwise (dimensionless).
    """

    mechanism: Any
    kinematics: Any
    turned: np.ndarray
    angle: np.ndarray
    inertia: np.ndarray
    inertia_slope: np.ndarray
    force: np.ndarray
    process_force: np.ndarray
    direction: float

    @property
    def step(self) -> float:
        """h, the angle between samples, rad."""
        return 2 * math.pi / len(self.turned)

    @property
    def speed(self) -> float:
        """Ω, the constant crank speed of the kinematics, rad/s (positive)."""
        return abs(float(self.mechanism.driver.speed))

    @cached_property
    def coefficients(self) -> tuple[np.ndarray, np.ndarray]:
        """(q′, q″): dq/dφ and d²q/dφ², each (N, n) (m/rad or rad/rad, and per rad²)."""
        k, w = self.kinematics, self.speed
        return k.qd / w, k.qdd / (w * w)

    def constant_speed_torque(self, speed: float) -> np.ndarray:
        """The driving torque at constant crank speed, N·m in the direction of rotation: ½ I′ Ω² − Q.

        Parameters
        ----------
        speed : float
            Ω, crank speed, rad/s (positive).
        """
        return 0.5 * self.inertia_slope * speed * speed - self.force


def reduce_to_crank(mechanism: Any, n_angles: int = 720) -> ReducedMechanism:
    """The mechanism's equivalent inertia, its slope and the generalised applied force on the crank.

    Parameters
    ----------
    mechanism : Mechanism
        Any one-degree-of-freedom mechanism (:class:`mechdyn.mechanism.Mechanism`); a speed profile
        of its driver is dropped (the reduction does not depend on the speed), its sign kept.
    n_angles : int
        Crank angles per revolution, a whole number from 4 to 100 000.

    Returns
    -------
    ReducedMechanism

    Notes
    -----
    I(φ) = q′ᵀ M q′, I′(φ) = 2 q′ᵀ M q″, Q(φ) = Q_qᵀ q′ (see the module docstring for the sources).
    """
    from mechdyn.mechanism.dynamics import applied_forces
    from mechdyn.mechanism.kinematics import kinematics

    steady = replace(mechanism, driver=replace(mechanism.driver, profile=None))
    k = kinematics(steady, n_angles)
    direction = 1.0 if steady.driver.speed > 0 else -1.0
    angle = np.asarray(k.angle, dtype=float)
    h = 2 * math.pi / n_angles
    spacing = np.diff(np.append(angle, angle[0] + 2 * math.pi))
    if np.abs(spacing - h).max() > 1e-9:
        raise ModelError(
            "the kinematics' crank angles are not equally spaced; the drive needs a regular grid",
            element="mechanism",
        )
    order = np.arange(n_angles) if direction > 0 else (-np.arange(n_angles)) % n_angles
    turned = h * np.arange(n_angles)
    w = abs(steady.driver.speed)
    qd, qdd = k.qd[order] / w, k.qdd[order] / (w * w)
    nb = len(steady.bodies)
    mass = np.repeat(steady.masses, 3).reshape(nb, 3)
    mass[:, 2] = steady.inertias
    m = mass.ravel()
    inertia = np.sum(m * qd * qd, axis=1)
    slope = 2.0 * np.sum(m * qd * qdd, axis=1)
    Q = applied_forces(steady, k)[order]
    force = np.sum(Q * qd, axis=1)
    gravity_only = replace(steady, process_forces=())
    Qg = applied_forces(gravity_only, k)[order]
    process = force - np.sum(Qg * qd, axis=1)
    ordered = _reordered(k, order)
    return ReducedMechanism(steady, ordered, turned, angle[order], inertia, slope, force, process, direction)


def _reordered(k: Any, order: np.ndarray) -> Any:
    """The kinematics in the order of the turned angle (a clockwise crank runs its angles backward)."""
    if np.array_equal(order, np.arange(len(order))):
        return k
    return replace(
        k,
        crank_angle=k.crank_angle[order],
        angle=k.angle[order],
        time=k.time[order],
        q=k.q[order],
        qd=k.qd[order],
        qdd=k.qdd[order],
        dyads=None,
    )
