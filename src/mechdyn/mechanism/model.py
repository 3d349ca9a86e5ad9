"""Planar mechanism model: points of an assembly drawing, bodies, joints, a driver and loads.

A mechanism is described by one assembled pose (the *drawing*): every named point has global
coordinates there, every body lists the points it carries, its mass, its centre of mass and its
moment of inertia about the centre of mass. Joints name the point where they act. The drawing fixes
the link dimensions and chooses the assembly branch, which the solver then tracks over the cycle.

Body coordinates are (x_G, y_G, φ): the centre of mass and the rotation from the drawing pose, so
every body's local frame is parallel to the global one in the drawing and the mass matrix is diagonal.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any, ClassVar, cast

import numpy as np

from mechdyn.checks import magnitude_limit
from mechdyn.errors import ModelError
from mechdyn.units import show, si_field

__all__ = [
    "GROUND",
    "Body",
    "Counterweight",
    "Driver",
    "GearJoint",
    "Mechanism",
    "Prismatic",
    "ProcessForce",
    "Revolute",
]

GROUND = "ground"
"""Name of the frame in joint definitions."""


def _point(owner: str, field_name: str, value: Any) -> tuple[float, float]:
    if isinstance(value, str) or len(value) != 2:
        raise ModelError(f"{value!r} must be two coordinates (x, y)", element=owner, field=field_name)
    return (si_field(owner, field_name, value[0], "m"), si_field(owner, field_name, value[1], "m"))


@dataclass(frozen=True)
class Body:
    """A rigid link.

    Parameters
    ----------
    name : str
    points : sequence of str
        Names of the drawing points it carries (at least one).
    mass : float or quantity
        kg, from 0 to 1e8 kg (zero for a link whose inertia is neglected).
    inertia : float or quantity
        Moment of inertia about the centre of mass, kg·m², from 0 to 1e10 kg·m².
    center_of_mass : (x, y) or str
        Global coordinates in the drawing, m (each at most 1e3 m in magnitude), or the name of a
        point; by default the mean of its points.
    """

    name: str
    points: tuple[str, ...]
    mass: float = 0.0
    inertia: float = 0.0
    center_of_mass: Any = None

    def __post_init__(self) -> None:
        if self.name == GROUND:
            raise ModelError(
                f"{GROUND!r} is the frame; give the body another name", element=self.name, field="name"
            )
        object.__setattr__(self, "points", tuple(self.points))
        if not self.points:
            raise ModelError("a body needs at least one point", element=self.name, field="points")
        for f, unit in (("mass", "kg"), ("inertia", "kg*m^2")):
            object.__setattr__(self, f, si_field(self.name, f, getattr(self, f), unit, nonnegative=True))
        if self.center_of_mass is not None and not isinstance(self.center_of_mass, str):
            object.__setattr__(
                self, "center_of_mass", _point(self.name, "center_of_mass", self.center_of_mass)
            )


@dataclass(frozen=True)
class Counterweight:
    """A mass fixed on a link to balance it: a point mass with, optionally, its own inertia.

    The mechanism folds it into its link when it is assembled (:class:`Mechanism`): the link's mass
    grows by ``mass``, its centre of mass moves to the common one, and its inertia about that centre
    follows by the parallel-axis theorem (Steiner; e.g. Meriam & Kraige, *Engineering Mechanics:
    Dynamics*, §B/1). The counterweight stays listed on the model (:attr:`Mechanism.counterweights`).

    Parameters
    ----------
    body : str
        The link it sits on.
    mass : float or quantity
        kg, from 0 to 1e8 kg.
    position : (x, y) or str
        Where it sits in the drawing: global coordinates, m (each at most 1e3 m in magnitude), or the
        name of a drawing point; it moves with the link.
    inertia : float or quantity
        Its own moment of inertia about its centre, kg·m², from 0 to 1e10 kg·m² (0: a point mass).
    name : str
        Its name in tables and messages (default: ``"counterweight on <body>"``).
    """

    body: str
    mass: Any
    position: Any
    inertia: Any = 0.0
    name: str = ""

    def __post_init__(self) -> None:
        if not self.name:
            object.__setattr__(self, "name", f"counterweight on {self.body}")
        for f, unit in (("mass", "kg"), ("inertia", "kg*m^2")):
            object.__setattr__(self, f, si_field(self.name, f, getattr(self, f), unit, nonnegative=True))
        if not isinstance(self.position, str):
            object.__setattr__(self, "position", _point(self.name, "position", self.position))


def _folded(body: Body, com: np.ndarray, weights: list[tuple[Counterweight, np.ndarray]]) -> Body:
    """``body`` with its counterweights folded in: mass, common centre of mass and the inertia about
    it by the parallel-axis theorem; the bare body is kept on it (:attr:`Mechanism.bare_bodies`)."""
    m0 = float(body.mass)
    total = m0 + sum(float(w.mass) for w, _ in weights)
    if total > 0:
        c = (m0 * com + sum(float(w.mass) * p for w, p in weights)) / total
    else:
        c = com
    inertia = float(body.inertia) + m0 * float(np.sum((com - c) ** 2))
    for w, p in weights:
        inertia += float(w.inertia) + float(w.mass) * float(np.sum((p - c) ** 2))
    out = Body(body.name, body.points, total, inertia, (float(c[0]), float(c[1])))
    object.__setattr__(out, "_bare", body)
    return out


class _AtAPoint:
    """What the joints acting at one drawing point share: their reference checks, and no motion
    law of their own."""

    name: str
    bodies: tuple[str, str]
    point: str

    def check(self, points: Mapping[str, Any], bodies: Mapping[str, Body]) -> None:
        """Refuse a point or body the mechanism does not have: the point in the drawing and on
        both bodies."""
        if self.point not in points:
            raise ModelError(f"point {self.point!r} is not in the drawing", element=self.name, field="point")
        for b in self.bodies:
            if b != GROUND and b not in bodies:
                known = ", ".join(bodies)
                raise ModelError(
                    f"body {b!r} is not defined; bodies: {known}", element=self.name, field="bodies"
                )
            if b != GROUND and self.point not in bodies[b].points:
                raise ModelError(
                    f"point {self.point!r} is not on body {b!r}", element=self.name, field="point"
                )

    def law(self, points: Mapping[str, Any]) -> Any:
        """None: such a joint imposes no motion law of its own (a gear pair does)."""
        return None


@dataclass(frozen=True)
class Revolute(_AtAPoint):
    """A pin joint at a drawing point between two bodies (or a body and ``"ground"``).

    Parameters
    ----------
    name : str
        The joint's name, unique in the mechanism.
    bodies : tuple of str
        The two bodies it joins.
    point : str
        The drawing point where the pin sits.
    """

    name: str
    bodies: tuple[str, str]
    point: str

    n_rows: ClassVar[int] = 2
    pins: ClassVar[bool] = True  # its two bodies share the point and turn about it
    slides: ClassVar[bool] = False

    def terms(self, mechanism: Mechanism, slot: Callable[[str], int]) -> Any:
        """Its constraint terms (:class:`~mechdyn.mechanism.constraints.RevoluteTerms`).

        Parameters
        ----------
        mechanism : Mechanism
            The mechanism the joint belongs to.
        slot : callable
            Body name → index of its first coordinate in the mechanism's coordinate vector.
        """
        from mechdyn.mechanism.constraints import RevoluteTerms

        a, b = self.bodies
        return RevoluteTerms(slot(a), slot(b), mechanism.local(a, self.point), mechanism.local(b, self.point))


@dataclass(frozen=True)
class Prismatic(_AtAPoint):
    """A slider: a point of body ``bodies[0]`` moves along a line fixed in ``bodies[1]``.

    The line passes through the point's drawing position with direction ``axis`` (angle from +x in
    the drawing, rad or quantity); the two bodies keep their relative rotation.

    Parameters
    ----------
    name : str
        The joint's name, unique in the mechanism.
    bodies : tuple of str
        The slider's body and the body that carries the guide (``"ground"`` for the frame).
    point : str
        The drawing point that slides.
    axis : float or quantity
        Direction of the guide from +x, rad; it points *up* (bottom dead centre is lowest along it).
    """

    name: str
    bodies: tuple[str, str]
    point: str
    axis: Any = 0.0

    n_rows: ClassVar[int] = 2
    pins: ClassVar[bool] = False
    slides: ClassVar[bool] = True  # a point of one body on a line of the other; it can be the stroke

    def __post_init__(self) -> None:
        object.__setattr__(self, "axis", si_field(self.name, "axis", self.axis, "rad"))

    def terms(self, mechanism: Mechanism, slot: Callable[[str], int]) -> Any:
        """Its constraint terms (:class:`~mechdyn.mechanism.constraints.PrismaticTerms`).

        Parameters
        ----------
        mechanism : Mechanism
            The mechanism the joint belongs to.
        slot : callable
            Body name → index of its first coordinate in the mechanism's coordinate vector.
        """
        from mechdyn.mechanism.constraints import PrismaticTerms

        a, b = self.bodies
        normal = np.array([-math.sin(self.axis), math.cos(self.axis)])
        sa, sb = mechanism.local(a, self.point), mechanism.local(b, self.point)
        return PrismaticTerms(slot(a), slot(b), sa, sb, normal)


@dataclass(frozen=True)
class GearJoint:
    """Two gears in mesh, rolling without slip at a fixed centre distance (one constraint).

    Both gears pivot on the same carrier (a body, or the frame) at the drawing points ``points``;
    the revolute joints that hold them there are separate joints of the model. A gear may be the
    frame itself (a fixed sun gear). The mesh force acts at the pitch point along the line of
    action: tangential to the pitch curves and, by the working pressure angle φ, a normal part
    ``F_n = |F_t| tan φ`` that pushes the gears apart, on the flank the tangential force loads
    (``flank = "fixed"`` keeps the published linear law F_n = F_t tan φ).

    Parameters
    ----------
    name : str
    bodies : (gear 1, gear 2)
        Gear 1 carries the pitch curve; gear 2 is its pure-rolling mate. Either may be ``"ground"``.
    points : (centre 1, centre 2)
        Drawing points of the two pivots; their distance is the centre distance.
    curve : PitchCurve
        Gear 1's pitch curve in its own frame (:mod:`mechdyn.mechanism.pitch`).
    carrier : str
        The body both pivots are fixed in (``"ground"`` for a fixed gearbox).
    orientation : float or quantity
        The drawing direction of the curve's θ = 0 (rad or quantity), e.g. the line from an
        eccentric gear's pivot to its centre.
    pressure_angle : float or quantity
        φ, rad or quantity (20° by default).
    internal : bool
        Gear 2 is an annulus (circular gears only).
    flank : {"load", "fixed"}
        ``"load"``: the teeth always push apart, ``F_n = |F_t| tan φ``, on whichever flank the
        tangential force loads; ``"fixed"``: F_n = F_t tan φ, the linear law of the published
        analyses (it pulls the gears together where F_t reverses).
    """

    name: str
    bodies: tuple[str, str]
    points: tuple[str, str]
    curve: Any
    carrier: str = GROUND
    orientation: Any = 0.0
    pressure_angle: Any = "20 deg"
    internal: bool = False
    flank: str = "load"

    def __post_init__(self) -> None:
        object.__setattr__(self, "bodies", tuple(self.bodies))
        object.__setattr__(self, "points", tuple(self.points))
        if self.flank not in ("load", "fixed"):
            raise ModelError(f"{self.flank!r} must be 'load' or 'fixed'", element=self.name, field="flank")
        object.__setattr__(self, "orientation", si_field(self.name, "orientation", self.orientation, "rad"))
        phi = si_field(self.name, "pressure_angle", self.pressure_angle, "rad")
        if not 0 <= phi < math.radians(45):
            raise ModelError(
                f"{math.degrees(phi):g}° must lie in [0°, 45°)", element=self.name, field="pressure_angle"
            )
        object.__setattr__(self, "pressure_angle", phi)
        if len(self.points) != 2 or self.points[0] == self.points[1]:
            raise ModelError(
                f"{self.points!r} must be two different points", element=self.name, field="points"
            )

    n_rows: ClassVar[int] = 1
    pins: ClassVar[bool] = False
    slides: ClassVar[bool] = False

    def check(self, points: Mapping[str, Any], bodies: Mapping[str, Body]) -> None:
        """Refuse a gear, carrier or pivot the mechanism does not have.

        Parameters
        ----------
        points : mapping of str to (float, float)
            The drawing's points, m.
        bodies : mapping of str to Body
            The mechanism's bodies.
        """
        for b in (*self.bodies, self.carrier):
            if b != GROUND and b not in bodies:
                raise ModelError(
                    f"body {b!r} is not defined; bodies: {', '.join(bodies)}",
                    element=self.name,
                    field="bodies",
                )
        if self.carrier in self.bodies:
            raise ModelError("a gear cannot be its own carrier", element=self.name, field="carrier")
        for b, p in zip(self.bodies, self.points, strict=True):
            if p not in points:
                raise ModelError(f"point {p!r} is not in the drawing", element=self.name, field="points")
            for owner in (b, self.carrier):
                if owner != GROUND and p not in bodies[owner].points:
                    raise ModelError(
                        f"point {p!r} is not on body {owner!r}", element=self.name, field="points"
                    )

    def law(self, points: Mapping[str, Any]) -> Any:
        """The rolling law ψ₂ = g(ψ₁) (:class:`~mechdyn.mechanism.pitch.PitchLaw`) at the drawing's
        centre distance.

        Parameters
        ----------
        points : mapping of str to (float, float)
            The drawing's points, m (the two pivots set the centre distance)."""
        from mechdyn.mechanism.pitch import pitch_law

        c1, c2 = (np.asarray(points[p], dtype=float) for p in self.points)
        a = float(np.hypot(*(c2 - c1)))
        beta = math.atan2(c2[1] - c1[1], c2[0] - c1[0])
        try:
            return pitch_law(self.curve, a, beta - self.orientation, self.internal)
        except ModelError as exc:
            raise ModelError(exc.detail, element=self.name, field=exc.field) from None

    @property
    def point(self) -> str:
        """Gear 1's pivot (where the joint is drawn)."""
        return self.points[0]

    def terms(self, mechanism: Mechanism, slot: Callable[[str], int]) -> Any:
        """Its constraint terms (:class:`~mechdyn.mechanism.constraints.GearTerms`).

        Parameters
        ----------
        mechanism : Mechanism
            The mechanism the joint belongs to.
        slot : callable
            Body name → index of its first coordinate in the mechanism's coordinate vector.
        """
        from mechdyn.mechanism.constraints import GearTerms

        c1, c2 = (mechanism.local(self.carrier, p) for p in self.points)
        g1, g2 = (slot(b) for b in self.bodies)
        law = mechanism.gear_laws[self.name]
        return GearTerms(g1, g2, slot(self.carrier), c1, c2, law, self.pressure_angle, self.flank)


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


@dataclass(frozen=True)
class Mechanism:
    """A planar mechanism in one assembled pose.

    Parameters
    ----------
    points : mapping of name → (x, y)
        The drawing, global coordinates in m.
    bodies : sequence of Body
    joints : sequence of Revolute, Prismatic or GearJoint
    driver : Driver
    gravity : (gx, gy), optional
        m/s² (e.g. ``(0, -9.81)``); none by default.
    process_forces : sequence of ProcessForce
    output : (body, point), optional
        Whose motion along its prismatic axis is the stroke; by default the one prismatic joint
        whose guide is the frame (a slider on a moving guide, as in a quick-return linkage, is never
        taken for the stroke unless named here; with several sliders on the frame it must be named).
        The axis points *up*: bottom dead centre is the lowest position along it, and inertia
        forces along it are positive upward (the press convention).
    angle_datum : float or "bdc"
        Crank angle reported as 0 (rad, from +x); ``"bdc"`` puts 0 at bottom dead centre.
    name : str
    counterweights : sequence of Counterweight
        Masses fixed on links (:class:`Counterweight`), folded into their links' mass, centre of
        mass and inertia when the model is assembled: :attr:`bodies` are then the loaded links and
        :attr:`bare_bodies` the links as given.
    """

    points: Mapping[str, tuple[float, float]]
    bodies: tuple[Body, ...]
    joints: tuple[Revolute | Prismatic | GearJoint, ...]
    driver: Driver
    gravity: tuple[float, float] = (0.0, 0.0)
    process_forces: tuple[ProcessForce, ...] = ()
    output: tuple[str, str] | None = None
    angle_datum: Any = 0.0
    name: str = "mechanism"
    counterweights: tuple[Counterweight, ...] = ()
    _index: dict[str, int] = field(default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        pts = {str(k): _point(str(k), "position", v) for k, v in dict(self.points).items()}
        object.__setattr__(self, "points", pts)
        # a body that already carries counterweights (a variant made by dataclasses.replace) is
        # taken back to its bare self, and this model's counterweights are folded in afresh
        bare = tuple(getattr(b, "_bare", b) for b in self.bodies)
        object.__setattr__(self, "bodies", bare)
        object.__setattr__(self, "counterweights", tuple(self.counterweights))
        object.__setattr__(self, "joints", tuple(self.joints))
        object.__setattr__(self, "process_forces", tuple(self.process_forces))
        g = tuple(si_field("gravity", "gravity", v, "m/s^2") for v in self.gravity)
        object.__setattr__(self, "gravity", g)
        if self.angle_datum != "bdc":
            object.__setattr__(
                self, "angle_datum", si_field("mechanism", "angle_datum", self.angle_datum, "rad")
            )
        names: dict[str, int] = {}
        for i, b in enumerate(self.bodies):
            if b.name in names:
                raise ModelError("the body name is used twice", element=b.name, field="name")
            names[b.name] = i
            for p in b.points:
                if p not in pts:
                    raise ModelError(
                        f"point {p!r} is not in the drawing; points: {', '.join(pts)}",
                        element=b.name,
                        field="points",
                    )
            if isinstance(b.center_of_mass, str) and b.center_of_mass not in pts:
                raise ModelError(
                    f"point {b.center_of_mass!r} is not in the drawing",
                    element=b.name,
                    field="center_of_mass",
                )
        object.__setattr__(self, "_index", names)
        if self.counterweights:
            object.__setattr__(self, "bodies", self._with_counterweights(pts))
        seen = set()
        for j in self.joints:
            if j.name in seen:
                raise ModelError("the joint name is used twice", element=j.name, field="name")
            seen.add(j.name)
            if len(j.bodies) != 2 or j.bodies[0] == j.bodies[1]:
                raise ModelError(
                    f"{j.bodies!r} must name two different bodies", element=j.name, field="bodies"
                )
            j.check(pts, {b.name: b for b in self.bodies})
        d = self.driver
        if d.body not in names:
            raise ModelError(f"body {d.body!r} is not defined", element="driver", field="body")
        for p in (d.pivot, d.tip):
            if p not in self.bodies[names[d.body]].points:
                raise ModelError(
                    f"point {p!r} is not on the crank {d.body!r}", element="driver", field="pivot"
                )
        if self.output is not None:
            out_body, out_point = self.output
            if out_body not in names or out_point not in self.bodies[names[out_body]].points:
                raise ModelError(
                    f"output {self.output!r} must be a body and one of its points", element="output"
                )
        on_frame = self._sliders_on_frame()
        if self.output is None and len(on_frame) > 1:
            raise ModelError(
                f"{len(on_frame)} sliders run on the frame ({', '.join(repr(j.name) for j in on_frame)}); "
                "say which one is the stroke: output = [body, point], e.g. "
                f"[{on_frame[0].bodies[0]!r}, {on_frame[0].point!r}]",
                element="output",
            )
        self._check_count()
        self.gear_laws  # noqa: B018 - a gear pair that cannot close is refused here
        self._check_gear_bodies()

    def _with_counterweights(self, pts: Mapping[str, tuple[float, float]]) -> tuple[Body, ...]:
        """The bodies with the counterweights folded in, each counterweight checked first."""
        on: dict[str, list[tuple[Counterweight, np.ndarray]]] = {}
        for w in self.counterweights:
            if not isinstance(w, Counterweight):
                raise ModelError(
                    f"{w!r} is not a Counterweight", element="counterweights", field="counterweights"
                )
            if w.body not in self._index:
                raise ModelError(
                    f"body {w.body!r} is not defined; put the counterweight on one of: "
                    f"{', '.join(self._index)}",
                    element=w.name,
                    field="body",
                )
            if isinstance(w.position, str):
                if w.position not in pts:
                    raise ModelError(
                        f"point {w.position!r} is not in the drawing; points: {', '.join(pts)}",
                        element=w.name,
                        field="position",
                    )
                p = np.asarray(pts[w.position], dtype=float)
            else:
                p = np.asarray(w.position, dtype=float)
            on.setdefault(w.body, []).append((w, p))
        return tuple(_folded(b, self.com(b), on[b.name]) if b.name in on else b for b in self.bodies)

    @property
    def bare_bodies(self) -> tuple[Body, ...]:
        """The bodies as given, without their counterweights (what a model file lists under
        ``[[bodies]]``); :attr:`bodies` are the assembled ones, counterweights folded in."""
        return tuple(getattr(b, "_bare", b) for b in self.bodies)

    @cached_property
    def gear_laws(self) -> dict[str, Any]:
        """The motion law of every gear joint (:class:`~mechdyn.mechanism.pitch.PitchLaw`), from the
        drawing's centre distances."""
        laws = {j.name: j.law(self.points) for j in self.joints}
        return {name: law for name, law in laws.items() if law is not None}

    def _check_gear_bodies(self) -> None:
        """A gear that meshes twice (an idler) is one gear: the pitch curves its meshes give it,
        each in its own drawing axes, must agree; warn where they do not."""
        import warnings

        from mechdyn.errors import ModelWarning

        grid = 2 * np.pi * np.arange(720) / 720
        for body in self.bodies:
            # the gear pairs are the joints with a rolling law (typed so for the checker)
            meshes = [
                cast(GearJoint, j) for j in self.joints if j.name in self.gear_laws and body.name in j.bodies
            ]
            if len(meshes) < 2:
                continue
            curves = []
            for j in meshes:
                law = self.gear_laws[j.name]
                if j.bodies[0] == body.name:  # its own curve, turned by its orientation
                    theta, r = np.mod(grid + j.orientation, 2 * np.pi), j.curve.radius(grid)
                else:  # the curve this mesh implies: the mate of gear 1's
                    c1, c2 = (np.asarray(self.points[p], dtype=float) for p in j.points)
                    beta = math.atan2(c2[1] - c1[1], c2[0] - c1[0])
                    r1 = law.contact_radius(grid)[0]
                    theta = np.mod(beta + math.pi - law(grid)[0], 2 * np.pi)
                    r = law.centre_distance + r1 if law.internal else law.centre_distance - r1
                o = np.argsort(theta)
                curves.append((j.name, np.interp(grid, theta[o], r[o], period=2 * np.pi)))
            ref_name, ref = curves[0]
            for name, other in curves[1:]:
                gap = float(np.abs(other - ref).max())
                if gap > 1e-4 * float(ref.max()):  # a few µm on gears of centimetres
                    warnings.warn(
                        f"gear {body.name!r} meshes in {ref_name!r} and {name!r}, which give it pitch curves "
                        f"up to {show(gap, 'm', 'mm', '.3g')} apart: one gear cannot be both; adjust the "
                        "installation angles (orientation) or the curves",
                        ModelWarning,
                        stacklevel=3,
                    )

    @cached_property
    def joint_rows(self) -> list[slice]:
        """The constraint rows of each joint (two for revolute and prismatic, one for a gear pair)."""
        out, r = [], 0
        for j in self.joints:
            out.append(slice(r, r + j.n_rows))
            r += j.n_rows
        return out

    # -- structure ---------------------------------------------------------------------------
    @property
    def body_index(self) -> dict[str, int]:
        return self._index

    @property
    def n_coordinates(self) -> int:
        return 3 * len(self.bodies)

    @property
    def n_constraints(self) -> int:
        return sum(j.n_rows for j in self.joints) + 1

    def _check_count(self) -> None:
        n, m = self.n_coordinates, self.n_constraints
        if n == m:
            return
        bodies = ", ".join(b.name for b in self.bodies)
        if m > n:
            raise ModelError(
                f"over-constrained: {m} constraint equations (2 per joint, 1 per gear pair, 1 driver) for "
                f"{n} coordinates "
                f"(3 per body: {bodies}); remove {m - n} equation(s) or add bodies"
            )
        raise ModelError(
            f"under-constrained: {m} constraint equations for {n} coordinates (3 per body: {bodies}); "
            f"{n - m} degree(s) of freedom are not driven; add joints"
        )

    def to_frame(self) -> Any:
        """The bodies as assembled, one row per body: mass (kg), inertia about the centre of mass
        (kg·m²), centre of mass (m) and a two-point link's length (m), as drawn
        (:func:`mechdyn.mechanism.summary.model_frame`)."""
        from mechdyn.mechanism.summary import model_frame

        return model_frame(self)

    def com(self, body: Body) -> np.ndarray:
        """Drawing position of a body's centre of mass, m.

        Parameters
        ----------
        body : Body
            One of the mechanism's bodies.
        """
        c = body.center_of_mass
        if c is None:
            return np.mean([self.points[p] for p in body.points], axis=0)
        return np.asarray(self.points[c] if isinstance(c, str) else c, dtype=float)

    def local(self, body: str, point: str) -> np.ndarray:
        """A point in a body's frame (from its centre of mass, drawing axes), m; on ground, global.

        Parameters
        ----------
        body : str
            The body's name, or ``"ground"``.
        point : str
            A point of the drawing.
        """
        p = np.asarray(self.points[point], dtype=float)
        if body == GROUND:
            return p
        return p - self.com(self.bodies[self._index[body]])

    @cached_property
    def drawing_coordinates(self) -> np.ndarray:
        """q in the drawing pose: every body at its centre of mass, φ = 0."""
        q = np.zeros(self.n_coordinates)
        for i, b in enumerate(self.bodies):
            q[3 * i : 3 * i + 2] = self.com(b)
        return q

    @property
    def drawing_crank_angle(self) -> float:
        """Crank angle θ of the drawing, rad."""
        a, b = (np.asarray(self.points[p]) for p in (self.driver.pivot, self.driver.tip))
        return math.atan2(b[1] - a[1], b[0] - a[0])

    @property
    def masses(self) -> np.ndarray:
        return np.array([b.mass for b in self.bodies])

    @property
    def inertias(self) -> np.ndarray:
        return np.array([b.inertia for b in self.bodies])

    def output_link(self) -> tuple[str, str] | None:
        """The two drawing points of the link that drives the output slide (the press's connecting
        rod): its far point, then the point it shares with the slide. None without a slide or when
        no single link pins onto it."""
        j = self.output_joint()
        if j is None:
            return None
        slide = j.bodies[0] if j.bodies[0] != GROUND else j.bodies[1]
        pins = [r for r in self.joints if r.pins and slide in r.bodies and GROUND not in r.bodies]
        if len(pins) != 1:
            return None
        r = pins[0]
        link = r.bodies[0] if r.bodies[1] == slide else r.bodies[1]
        far = [p for p in self.bodies[self._index[link]].points if p != r.point]
        return (far[0], r.point) if far else None

    def _sliders_on_frame(self) -> list[Prismatic]:
        return [cast(Prismatic, j) for j in self.joints if j.slides and GROUND in j.bodies]

    def output_joint(self) -> Prismatic | None:
        """The prismatic joint whose motion is the stroke: the one named by ``output``, else the one
        slider whose guide is the frame (None without one)."""
        prismatic = [cast(Prismatic, j) for j in self.joints if j.slides]
        if self.output is None:
            on_frame = self._sliders_on_frame()
            return on_frame[0] if len(on_frame) == 1 else None
        for j in prismatic:
            if self.output[0] in j.bodies:
                return j
        return None
