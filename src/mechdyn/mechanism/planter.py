"""The gear-type rotary planting mechanism (SPEC §6) built from its design variables.

A carrier arm turns about a fixed sun gear; on each side an idler at R/2 and a planet at R mesh in
a chain, and a planting fork is fixed to each planet. The sun and the planets are eccentric circles
of pitch radius ρ, sized so that the mates close at the centre distance R/2; each idler is their
exact pure-rolling mate. The planets are installed at the phase α (the line from pivot to centre at
α to the horizontal in the drawing), the sun at the angle that makes each idler the exact mate of
both its neighbours (an idler is one gear), and side 2 as side 1 stands half a turn later, so that
the two sides run point-symmetric about the sun.

:class:`PlanterDesign` holds the design variables (ε, α, β, R, L, γ, d, the masses and the inertias
about the pivots, the speed); :func:`planter` builds the :class:`~mechdyn.mechanism.Mechanism`; a
``type = "planting_mechanism"`` model file holds a ``[design]`` table, so that a design study
varies ε or d by their path (``design.eccentricity_ratio``). The published prototype RP-1 is the
default design (d and the arm's inertia were not published: chosen, see the fields).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from pydantic import Field
from scipy.optimize import minimize_scalar

from mechdyn.errors import ModelError
from mechdyn.io.fields import (
    Acceleration,
    Angle,
    AngularSpeed,
    Dimensionless,
    FileModel,
    Inertia,
    Length,
    Mass,
    ModelTableBase,
    Velocity,
)
from mechdyn.mechanism.kinematics import MAX_ANGLES, kinematics
from mechdyn.mechanism.model import Body, Driver, GearJoint, Mechanism, Revolute
from mechdyn.mechanism.pitch import closing_centre_distance, eccentric_circle, pitch_law
from mechdyn.units import si_field, to_si

__all__ = ["PlanterDesign", "planter"]


@dataclass(frozen=True)
class PlanterDesign:
    """Design variables of a rotary planting mechanism (SI; angles in rad).

    Every number must be finite and within the magnitude a machine can have in its unit
    (:data:`mechdyn.checks.MAGNITUDE_LIMITS`: 1e3 m, 1e8 kg, 1e10 kg·m², 1e6 rad, 1e8 rad/s,
    1e6 m/s²); the ranges below are checked as well, and anything else is a
    :class:`~mechdyn.errors.ModelError` naming the field and the value.

    Attributes
    ----------
    eccentricity_ratio : float
        ε = e/ρ of the eccentric sun and planets, in [0, 1) (RP-1: 0.13; studied 0–0.2).
    alpha : float
        α, the planets' installation angle: the line from pivot to centre against the horizontal,
        rad (RP-1: −35°).
    beta : float
        β, the arm's angle in the drawing, rad (RP-1: −76°).
    arm_radius : float
        R, sun to planet centre, m, positive (RP-1: 76.8 mm); the idler sits at R/2.
    fork_length : float
        L, planet centre to fork tip, m, positive (RP-1: 138 mm).
    fork_angle : float
        γ, the fork's direction in the drawing, rad (RP-1: 14°; the publication writes 90° − β but
        its numbers fit 90° + β).
    com_offset : float
        d, planet pivot to the centre of mass of planet + fork along the fork, m (not published;
        20 mm: the inertia about the pivot allows at most √(I/m) = 32 mm).
    arm_mass, idler_mass, planet_mass : float
        kg, positive (RP-1: 1.0716, 0.0069, 1.0654 with the fork).
    arm_inertia : float
        About the sun, kg·m², not negative (not published: 2.1e-3, a bar of 2R; at constant speed it changes
        nothing).
    idler_inertia, planet_inertia : float
        About their pivots, kg·m², not negative (the planet's positive) (RP-1: 1.26e-5, 1.092e-3).
    speed : float
        The carrier's speed, rad/s, not zero (RP-1: 200 rpm).
    gravity : float
        m/s², along −y.
    """

    eccentricity_ratio: float = 0.13
    alpha: float = math.radians(-35.0)
    beta: float = math.radians(-76.0)
    arm_radius: float = 0.0768
    fork_length: float = 0.138
    fork_angle: float = math.radians(14.0)
    com_offset: float = 0.020
    arm_mass: float = 1.0716
    idler_mass: float = 0.0069
    planet_mass: float = 1.0654
    arm_inertia: float = 2.1e-3
    idler_inertia: float = 1.26e-5
    planet_inertia: float = 1.092e-3
    speed: float = field(default_factory=lambda: to_si("200 rpm", "rad/s"))
    gravity: float = 9.81

    def __post_init__(self) -> None:
        for name, unit, rule in (
            ("eccentricity_ratio", "", {"low": 0.0, "high": 1.0, "high_open": True}),
            ("alpha", "rad", {}),
            ("beta", "rad", {}),
            ("arm_radius", "m", {"positive": True}),
            ("fork_length", "m", {"positive": True}),
            ("fork_angle", "rad", {}),
            ("com_offset", "m", {}),
            ("arm_mass", "kg", {"positive": True}),
            ("idler_mass", "kg", {"positive": True}),
            ("planet_mass", "kg", {"positive": True}),
            ("arm_inertia", "kg*m^2", {"nonnegative": True}),
            ("idler_inertia", "kg*m^2", {"nonnegative": True}),
            ("planet_inertia", "kg*m^2", {"positive": True}),
            ("speed", "rad/s", {"nonzero": True}),
            ("gravity", "m/s^2", {}),
        ):
            object.__setattr__(self, name, si_field("design", name, getattr(self, name), unit, **rule))
        if self.planet_inertia - self.planet_mass * self.com_offset**2 <= 0:
            limit = math.sqrt(self.planet_inertia / self.planet_mass)
            raise ModelError(
                f"{self.com_offset:g} m: the planet's inertia about its pivot allows a centre of mass "
                f"at most {limit:.4g} m from it (I = I_G + m d²)",
                element="design",
                field="com_offset",
            )


def _side(design, curve, com, mass, sun, planet, k):
    """Bodies and joints of one side (k = 1 or 2); ``sun`` and ``planet``: the installation angles
    of the eccentrics (rad)."""
    mp, ip = mass
    bodies = (
        Body(f"idler {k}", (f"I{k}",), design.idler_mass, design.idler_inertia, f"I{k}"),
        Body(f"planet {k}", (f"P{k}", f"F{k}"), mp, ip, com),
    )
    g_sun, g_pl = ("G1-G2", "G3-G2") if k == 1 else ("G1-G4", "G5-G4")
    joints = (
        Revolute(f"I{k}", ("arm", f"idler {k}"), f"I{k}"),
        Revolute(f"P{k}", ("arm", f"planet {k}"), f"P{k}"),
        GearJoint(g_sun, ("ground", f"idler {k}"), ("O", f"I{k}"), curve, "arm", sun),
        GearJoint(g_pl, (f"planet {k}", f"idler {k}"), (f"P{k}", f"I{k}"), curve, "arm", planet),
    )
    return bodies, joints


def idler_mismatch(curve, a: float, beta: float, sun: float, planet: float, n: int = 2048) -> float:
    """Largest difference between the idler pitch curve that the sun mesh implies and the one the
    planet mesh implies (m): an idler is one gear, so the two must agree."""
    psi = 2 * np.pi * np.arange(n) / n
    curves = []
    for law, side in (
        (pitch_law(curve, a, beta - sun), math.pi),
        (pitch_law(curve, a, beta + math.pi - planet), 0.0),
    ):
        turned, _, _ = law(psi)
        theta = np.mod(beta + side - turned, 2 * np.pi)
        radius = a - law.contact_radius(psi)[0]
        o = np.argsort(theta)
        curves.append(
            np.interp(np.linspace(0, 2 * np.pi, 1000, endpoint=False), theta[o], radius[o], period=2 * np.pi)
        )
    return float(np.abs(curves[0] - curves[1]).max())


def sun_orientation(curve, a: float, beta: float, planet: float) -> float:
    """The sun's installation angle (rad) at which each idler is the exact mate of both the sun and
    its planet."""
    scan = np.radians(np.arange(-180.0, 180.0, 10.0))
    start = scan[int(np.argmin([idler_mismatch(curve, a, beta, x, planet) for x in scan]))]
    res = minimize_scalar(
        lambda x: idler_mismatch(curve, a, beta, x, planet),
        bounds=(start - math.radians(10), start + math.radians(10)),
        method="bounded",
        options={"xatol": 1e-10},
    )
    return float(res.x)


def geometry(design: PlanterDesign) -> tuple[dict, float, tuple, float, float]:
    """Drawing points (m), the pitch radius ρ (m), the planets' centres of mass, and the
    installation angles of the sun's and planet 2's eccentrics (rad; planet 1's is α).

    Side 2 is installed as side 1 stands half a turn later (the carrier's half turn brings side 1
    where side 2 is), so that the two sides run alike half a turn apart, point-symmetric about the
    sun: its planet, fork and eccentric are turned by the angle planet 1 turns in half a turn.
    """
    D = design
    eps, R, L, d = D.eccentricity_ratio, D.arm_radius, D.fork_length, D.com_offset
    a = R / 2
    rho = a / closing_centre_distance(eccentric_circle(1.0, eps)) if eps > 0 else a / 2
    b = D.beta
    u = np.array([math.cos(b), math.sin(b)])
    f = np.array([math.cos(D.fork_angle), math.sin(D.fork_angle)])
    pts = {"O": (0.0, 0.0), "I1": tuple(u * a), "P1": tuple(u * R), "F1": tuple(u * R + L * f)}
    com1 = tuple(u * R + d * f)
    curve = eccentric_circle(rho, eps * rho)
    planet = D.alpha
    sun = sun_orientation(curve, a, b, planet) if eps > 0 else planet
    # side 1 alone, half a turn on: how far has planet 1 turned?
    bodies, joints = _side(D, curve, com1, _planet_mass(D), sun, planet, 1)
    arm = Body("arm", ("O", "I1", "P1"), D.arm_mass, D.arm_inertia, "O")
    half = Mechanism(
        pts, (arm, *bodies), (Revolute("O", ("ground", "arm"), "O"), *joints), Driver("arm", "O", "I1", 1.0)
    )
    k = kinematics(half, 4)
    i = int(np.argmin(np.abs(np.angle(np.exp(1j * (k.crank_angle - b - math.pi))))))
    turn = float(k.q[i, 3 * half.body_index["planet 1"] + 2])
    rot = np.array([[math.cos(turn), -math.sin(turn)], [math.sin(turn), math.cos(turn)]])
    f2 = rot @ f
    pts |= {"I2": tuple(-u * a), "P2": tuple(-u * R), "F2": tuple(-u * R + L * f2)}
    com2 = tuple(-u * R + d * f2)
    return pts, rho, (com1, com2), sun, planet + turn


def _planet_mass(D: PlanterDesign) -> tuple[float, float]:
    """Planet + fork: mass, and inertia about the centre of mass (I_G = I_pivot − m d²)."""
    return D.planet_mass, D.planet_inertia - D.planet_mass * D.com_offset**2


def planter(design: PlanterDesign | None = None, name: str = "planting mechanism RP-1") -> Mechanism:
    """The planting mechanism of a design (by default the published prototype RP-1).

    Parameters
    ----------
    design : PlanterDesign, optional
    name : str

    Returns
    -------
    Mechanism
        Bodies arm, idler 1, planet 1, idler 2, planet 2; revolutes O, I1, P1, I2, P2; gear pairs
        G1-G2, G3-G2, G1-G4, G5-G4 on the arm; the fork tips F1, F2; driven at the arm.
    """
    D = design or PlanterDesign()
    pts, rho, com, sun, planet2 = geometry(D)
    curve = eccentric_circle(rho, D.eccentricity_ratio * rho)
    mass = _planet_mass(D)
    b1, j1 = _side(D, curve, com[0], mass, sun, D.alpha, 1)
    b2, j2 = _side(D, curve, com[1], mass, sun, planet2, 2)
    arm = Body("arm", ("O", "I1", "P1", "I2", "P2"), D.arm_mass, D.arm_inertia, "O")
    joints = (Revolute("O", ("ground", "arm"), "O"), *j1[:2], *j2[:2], *j1[2:], *j2[2:])
    return Mechanism(
        pts,
        (arm, b1[0], b1[1], b2[0], b2[1]),
        joints,
        Driver("arm", "O", "I1", D.speed),
        gravity=(0.0, -D.gravity),
        name=name,
    )


# -- the model file: [model] type = "planting_mechanism" -----------------------------------------


_D = PlanterDesign()


class PlanterModelTable(ModelTableBase):
    type: Literal["planting_mechanism"]
    """The file type, ``"planting_mechanism"``: it selects the schema and the analyses that read the file."""
    name: str = "planting mechanism"
    """The model's name, shown in tables, plots, reports and the results database."""


class DesignTable(FileModel):
    """The design variables; each left out takes RP-1's value (:class:`PlanterDesign`)."""

    eccentricity_ratio: Dimensionless = _D.eccentricity_ratio
    """ε, the eccentric gears' offset of pivot over radius."""
    alpha: Angle = _D.alpha
    """α, angle to the horizontal of the line through an eccentric gear's pivot and centre."""
    beta: Angle = _D.beta
    """β, the planet's installation angle."""
    arm_radius: Length = _D.arm_radius
    """R, the carrier's radius from the sun to the planet (the idler sits at R/2)."""
    fork_length: Length = _D.fork_length
    """L, from the planet's centre to the fork tip."""
    fork_angle: Angle = _D.fork_angle
    """γ, the fork's angle on the planet."""
    com_offset: Length = _D.com_offset
    """d, from the planet's pivot to the centre of mass of planet and fork (not published: chosen)."""
    arm_mass: Mass = _D.arm_mass
    """Mass of the carrier arm."""
    idler_mass: Mass = _D.idler_mass
    """Mass of each idler."""
    planet_mass: Mass = _D.planet_mass
    """Mass of each planet with its fork."""
    arm_inertia: Inertia = _D.arm_inertia
    """Moment of inertia of the carrier about the sun's axis (not published: chosen)."""
    idler_inertia: Inertia = _D.idler_inertia
    """Moment of inertia of each idler about its pivot."""
    planet_inertia: Inertia = _D.planet_inertia
    """Moment of inertia of each planet with its fork about its pivot."""
    speed: AngularSpeed = _D.speed
    """Carrier speed."""
    gravity: Acceleration = _D.gravity
    """Gravity, acting down the drawing's y axis."""


class SettingsTable(FileModel):
    """As a mechanism file's ``[settings]``."""

    n_angles: int = Field(default=360, ge=8, le=MAX_ANGLES)
    """Carrier angles per revolution."""
    trace: list[str] = Field(default_factory=list)
    """Points whose paths are drawn (e.g. the fork tips) and whose motion the table gives."""
    field_velocity: tuple[Velocity, Velocity] | None = None
    """Velocity of the machine over the ground, [v_x, v_y], for the paths over the field."""


class PlanterFile(FileModel):
    """Schema of a planting-mechanism file."""

    model: PlanterModelTable
    design: DesignTable = DesignTable()
    settings: SettingsTable = SettingsTable()


def build(source: Any) -> Any:
    """Builder for ``[model] type = "planting_mechanism"``: ``[design]`` (the variables of
    :class:`PlanterDesign`, quantities with units; those left out are RP-1's) and ``[settings]``
    (``n_angles``, ``trace``, ``field_velocity``, as in a mechanism file)."""
    from mechdyn.io.modelfile import field_context, validate
    from mechdyn.mechanism.schema import MechanismSpec

    f = validate(PlanterFile, source)
    with field_context(source, "[design]"):
        mech = planter(PlanterDesign(**f.design.model_dump()), f.model.name)
    s = f.settings
    return MechanismSpec(mech, s.n_angles, tuple(s.trace), s.field_velocity)
