"""The parts of a mechanism's drawing: its links (:class:`Body`), the masses fixed on them
(:class:`Counterweight`), and the joints between them — :class:`Revolute` (a pin), :class:`Prismatic`
(a slider) and :class:`GearJoint` (two gears in mesh) — each with its constraint terms.

Points are named; the drawing (:class:`~mechdyn.mechanism.model.Mechanism`) gives their coordinates.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any, ClassVar, Protocol

import numpy as np

from mechdyn.errors import ModelError
from mechdyn.mechanism.joint_terms import GearTerms, PrismaticTerms, RevoluteTerms
from mechdyn.units import si_field

__all__ = ["GROUND", "Body", "Counterweight", "GearJoint", "Prismatic", "Revolute"]

GROUND = "ground"
"""Name of the frame in joint definitions."""


class Drawn(Protocol):
    """What a joint reads of the mechanism it belongs to (:class:`~mechdyn.mechanism.model.Mechanism`)
    to build its constraint terms."""

    def local(self, body: str, point: str) -> np.ndarray:
        """A drawing point in a body's frame, m (see :meth:`Mechanism.local`)."""
        ...

    @property
    def gear_laws(self) -> Mapping[str, Any]:
        """Each gear pair's rolling law by joint name (see :attr:`Mechanism.gear_laws`)."""
        ...


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

    def terms(self, mechanism: Drawn, slot: Callable[[str], int]) -> Any:
        """Its constraint terms (:class:`~mechdyn.mechanism.joint_terms.RevoluteTerms`).

        Parameters
        ----------
        mechanism : Mechanism
            The mechanism the joint belongs to.
        slot : callable
            Body name → index of its first coordinate in the mechanism's coordinate vector.
        """
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

    def terms(self, mechanism: Drawn, slot: Callable[[str], int]) -> Any:
        """Its constraint terms (:class:`~mechdyn.mechanism.joint_terms.PrismaticTerms`).

        Parameters
        ----------
        mechanism : Mechanism
            The mechanism the joint belongs to.
        slot : callable
            Body name → index of its first coordinate in the mechanism's coordinate vector.
        """
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

    def terms(self, mechanism: Drawn, slot: Callable[[str], int]) -> Any:
        """Its constraint terms (:class:`~mechdyn.mechanism.joint_terms.GearTerms`).

        Parameters
        ----------
        mechanism : Mechanism
            The mechanism the joint belongs to.
        slot : callable
            Body name → index of its first coordinate in the mechanism's coordinate vector.
        """
        c1, c2 = (mechanism.local(self.carrier, p) for p in self.points)
        g1, g2 = (slot(b) for b in self.bodies)
        law = mechanism.gear_laws[self.name]
        return GearTerms(g1, g2, slot(self.carrier), c1, c2, law, self.pressure_angle, self.flank)
