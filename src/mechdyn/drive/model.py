"""The drive: a motor turning the mechanism's crank through a train of stages, with a flywheel.

The motor shaft turns n times as fast as the crank (n the overall ratio, motor to crank). The train is
one stage of ratio n and efficiency η, or stages of their own (:class:`~mechdyn.drive.train.Stage`:
belts and meshes, each with the inertia of the shaft it drives). Every stage passes the power that
crosses it with its efficiency in the direction the power flows, the flywheel's included: a flywheel
on the motor shaft gives its energy to the press through the same gears as the motor
(:mod:`mechdyn.drive.train`). The flywheel sits on the motor shaft, on the shaft a stage drives, or on
the crank shaft; its inertia counts N² times at the crank, N the speed of its shaft over the crank's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import cached_property
from typing import Any

import numpy as np

from mechdyn.errors import ModelError
from mechdyn.units import si_field

__all__ = ["Drive", "FormingForce"]


@dataclass(frozen=True)
class FormingForce:
    """A press's forming force: it resists the slide over the last part of its stroke before bottom
    dead centre, on the working stroke only.

    The force rises linearly from zero over ``rise`` of slide travel, then holds ``force`` down to
    bottom dead centre (a drawing or blanking load; a force that rises gradually keeps the crank's
    acceleration continuous). It acts on the mechanism's output slide, along its guide's axis, against
    the slide's motion (the guide's axis points up; the slide moves down on the working stroke).

    Parameters
    ----------
    force : float or quantity
        The full forming force, N (e.g. ``"10 MN"``), positive.
    before_bdc : float or quantity
        Slide travel before bottom dead centre over which it acts, m (e.g. ``"25 mm"``).
    rise : float or quantity
        Slide travel over which it rises from zero, m, from 0 to ``before_bdc``.
    """

    force: Any
    before_bdc: Any
    rise: Any = 0.0

    def __post_init__(self) -> None:
        f = si_field("forming force", "force", self.force, "N", positive=True)
        d = si_field("forming force", "before_bdc", self.before_bdc, "m", positive=True)
        r = si_field("forming force", "rise", self.rise, "m", nonnegative=True)
        if r > d:
            raise ModelError(
                f"the rise ({r:.6g} m) must not exceed the travel it acts over, before_bdc ({d:.6g} m)",
                element="forming force",
                field="rise",
            )
        object.__setattr__(self, "force", f)
        object.__setattr__(self, "before_bdc", d)
        object.__setattr__(self, "rise", r)

    def on(self, mechanism: Any, n_angles: int = 720) -> Any:
        """The mechanism with this force added to its process forces (a
        :class:`mechdyn.mechanism.ProcessForce` on its output slide).

        Parameters
        ----------
        mechanism : Mechanism
            A mechanism with an output slide (a prismatic joint on the frame) and ``angle_datum``
            of its own.
        n_angles : int
            Crank angles per revolution used to find the dead centres, a whole number from 4 to 100 000.

        Raises
        ------
        ModelError
            When the mechanism has no output slide or its stroke is shorter than ``before_bdc``.
        """
        from mechdyn.mechanism.kinematics import kinematics, output_position
        from mechdyn.mechanism.model import GROUND, ProcessForce

        joint = mechanism.output_joint()
        if joint is None:
            raise ModelError(
                "a forming force acts on the output slide; the mechanism has none (give its output)",
                element="forming force",
            )
        steady = replace(mechanism, driver=replace(mechanism.driver, profile=None))
        k = kinematics(steady, n_angles)
        s = output_position(steady, k.q)
        assert s is not None  # an output joint gives a position
        i_bdc, i_tdc = int(np.argmin(s)), int(np.argmax(s))
        s_bdc, stroke = float(s[i_bdc]), float(np.ptp(s))
        if self.before_bdc >= stroke:
            raise ModelError(
                f"before_bdc ({self.before_bdc:.6g} m) must be shorter than the stroke ({stroke:.6g} m)",
                element="forming force",
                field="before_bdc",
            )
        # the dead centres between the samples: one Newton step on ds/dθ = 0 from the nearest sample
        # (ds/dθ = v/θ̇ and d²s/dθ² = a/θ̇² at constant speed: the kinematics' own derivatives)
        slide = joint.bodies[1] if joint.bodies[0] == GROUND else joint.bodies[0]
        _, v, acc = k.point(slide, joint.point)
        axis = np.array([math.cos(joint.axis), math.sin(joint.axis)])
        w = float(steady.driver.speed)
        d1, d2 = (v @ axis) / w, (acc @ axis) / (w * w)
        a_bdc = float(k.angle[i_bdc] - d1[i_bdc] / d2[i_bdc])
        s_bdc = s_bdc - 0.5 * d1[i_bdc] ** 2 / d2[i_bdc]
        a_tdc = float(k.angle[i_tdc] - d1[i_tdc] / d2[i_tdc])
        direction = 1.0 if mechanism.driver.speed > 0 else -1.0
        # the working stroke: from TDC to BDC in the direction of rotation
        span = (direction * (a_bdc - a_tdc)) % (2 * math.pi)
        force = _Forming(self, joint.axis, direction, a_tdc, span, s_bdc)
        pf = ProcessForce(slide, joint.point, force)
        return replace(mechanism, process_forces=(*mechanism.process_forces, pf))


@dataclass(frozen=True, eq=False)
class _Forming:
    """A forming force placed on a mechanism's slide: called as a process force, ``(angle,
    position) -> (Fx, Fy)``, it acts from TDC to BDC (the working stroke, BDC included) where the slide
    is within ``before_bdc`` of BDC."""

    load: FormingForce
    axis: float
    direction: float
    tdc: float
    span: float
    bdc_position: float

    def __call__(self, angle: np.ndarray, position: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        F, d, rise = self.load.force, self.load.before_bdc, self.load.rise
        past_tdc = (self.direction * (np.asarray(angle) - self.tdc)) % (2 * math.pi)
        working = (past_tdc > 0) & (past_tdc <= self.span)
        depth = d - (np.asarray(position) - self.bdc_position)  # travel into the forming zone, m
        share = np.clip(depth / rise, 0.0, 1.0) if rise > 0 else (depth >= 0).astype(float)
        f = np.where(working & (depth >= 0), F * share, 0.0)
        return f * math.cos(self.axis), f * math.sin(self.axis)

    def kinks(self) -> list[tuple[str, tuple[float, ...]]]:
        """Where the force is not smooth: its start and its full load along the slide's axis (m), and
        BDC, where it ends, in crank angle (rad)."""
        start = self.bdc_position + self.load.before_bdc
        return [
            ("position", (start, start - self.load.rise)),
            ("angle", (self.tdc + self.direction * self.span,)),
        ]


@dataclass(frozen=True)
class Drive:
    """A mechanism driven by a motor through a train of stages, with a flywheel.

    Parameters
    ----------
    mechanism : Mechanism
        The driven mechanism (its process forces included); its driver's speed sign gives the
        direction of rotation, its speed (or profile) is otherwise not used.
    motor : TorqueSpeedCurve or InductionMotor
        Any object with ``torque(speed)`` (N·m at rad/s), ``rotor_inertia`` (kg·m²) and
        ``no_load_speed`` (rad/s).
    gear_ratio : float, optional
        n, motor speed over crank speed, dimensionless, > 0: one stage of efficiency ``efficiency``
        (give it or ``stages``; with both, it must be the stages' product).
    flywheel_inertia : float or quantity
        kg·m², on the shaft ``flywheel_shaft`` names.
    flywheel_shaft : str
        Where the flywheel sits: ``"motor"``, ``"crank"``, or the name of the stage that drives its
        shaft.
    efficiency : float, optional
        η of a one-stage train, dimensionless, in (0, 1] (default 1; with ``stages``, their product).
    name : str
        The drive's name.
    stages : tuple of Stage, optional
        The train from the motor to the crank, in order, each with its ratio, efficiency and the
        inertia of the shaft it drives.
    """

    mechanism: Any
    motor: Any
    gear_ratio: Any = None
    flywheel_inertia: Any = 0.0
    flywheel_shaft: str = "motor"
    efficiency: Any = None
    name: str = "drive"
    stages: tuple[Any, ...] = ()

    def __post_init__(self) -> None:
        from mechdyn.drive.train import Stage

        stages = tuple(self.stages)
        if not stages:
            if self.gear_ratio is None:
                raise ModelError(
                    "give the gear ratio (motor speed over crank speed) or the stages of the train",
                    element=self.name,
                    field="gear_ratio",
                )
            eta = 1.0 if self.efficiency is None else self.efficiency
            stages = (Stage(self.gear_ratio, eta, 0.0, f"{self.name} gearing"),)
        for k, s in enumerate(stages):
            if not isinstance(s, Stage):
                raise ModelError(
                    f"stage {k + 1} is {s!r}; give mechdyn.drive.Stage(ratio, efficiency, inertia, name)",
                    element=self.name,
                    field="stages",
                )
        n = math.prod(s.ratio for s in stages)
        eta = math.prod(s.efficiency for s in stages)
        for field, given, product in (
            ("gear_ratio", self.gear_ratio, n),
            ("efficiency", self.efficiency, eta),
        ):
            if self.stages and given is not None:
                value = si_field(self.name, field, given, "")
                if not math.isclose(value, product, rel_tol=1e-12):
                    raise ModelError(
                        f"{value:.6g} differs from the stages' product {product:.6g}; leave it out",
                        element=self.name,
                        field=field,
                    )
        J = si_field(self.name, "flywheel_inertia", self.flywheel_inertia, "kg*m^2", nonnegative=True)
        names = [s.name for s in stages]
        if self.flywheel_shaft not in ("motor", "crank", *names[:-1]):
            choices = ", ".join(repr(x) for x in ("motor", *names[:-1], "crank"))
            raise ModelError(
                f"{self.flywheel_shaft!r} names no shaft of the train; give one of {choices}",
                element=self.name,
                field="flywheel_shaft",
            )
        for attr in ("torque", "rotor_inertia", "no_load_speed"):
            if not hasattr(self.motor, attr):
                raise ModelError(
                    f"the motor {self.motor!r} has no {attr}; give an InductionMotor or a TorqueSpeedCurve",
                    element=self.name,
                    field="motor",
                )
        object.__setattr__(self, "gear_ratio", n)
        object.__setattr__(self, "efficiency", eta)
        object.__setattr__(self, "flywheel_inertia", J)
        object.__setattr__(self, "stages", stages)

    @property
    def flywheel_shaft_index(self) -> int:
        """The flywheel's shaft: 0 the motor's, k the one stage k drives, len(stages) the crank's."""
        if self.flywheel_shaft == "motor":
            return 0
        if self.flywheel_shaft == "crank":
            return len(self.stages)
        return [s.name for s in self.stages].index(self.flywheel_shaft) + 1

    @property
    def flywheel_speed_ratio(self) -> float:
        """N, the flywheel shaft's speed over the crank's, dimensionless."""
        return math.prod(s.ratio for s in self.stages[self.flywheel_shaft_index :])

    @cached_property
    def train(self) -> Any:
        """The train's shafts with the rotor, the stages' inertias and the flywheel where they sit
        (:class:`~mechdyn.drive.train.Train`)."""
        from mechdyn.drive.train import build_train

        return build_train(
            self.motor.rotor_inertia, self.stages, self.flywheel_inertia, self.flywheel_shaft_index
        )

    @property
    def added_inertia(self) -> float:
        """Inertia of the flywheel, the motor's rotor and the train reduced to the crank, Σ N_k² J_k,
        kg·m² (their kinetic energy is ½ J φ̇²)."""
        return self.train.reduced_inertia

    def crank_torque(self, speed: Any) -> Any:
        """The motor's torque at the crank at a steady speed, η n T_m(n φ̇), N·m (in the direction of
        rotation; η the train's overall efficiency with the power flowing to the crank).

        Parameters
        ----------
        speed : float or ndarray
            φ̇, crank speed, rad/s.
        """
        n = self.gear_ratio
        if isinstance(speed, float):
            return self.efficiency * n * self.motor.torque(n * speed)
        return self.efficiency * n * np.asarray(self.motor.torque(n * np.asarray(speed, dtype=float)))

    def with_flywheel(self, inertia: Any) -> Drive:
        """The same drive with another flywheel inertia.

        Parameters
        ----------
        inertia : float or quantity
            kg·m², on the same shaft.
        """
        return replace(self, flywheel_inertia=inertia, gear_ratio=None, efficiency=None)
