"""Planar mechanism model: points of an assembly drawing, bodies, joints, a driver and loads.

A mechanism is described by one assembled pose (the *drawing*): every named point has global
coordinates there, every body lists the points it carries, its mass, its centre of mass and its
moment of inertia about the centre of mass. Joints name the point where they act. The drawing fixes
the link dimensions and chooses the assembly branch, which the solver then tracks over the cycle.

Body coordinates are (x_G, y_G, φ): the centre of mass and the rotation from the drawing pose, so
every body's local frame is parallel to the global one in the drawing and the mass matrix is diagonal.

The drawing's parts are those of :mod:`mechdyn.mechanism.elements` (bodies, counterweights, joints),
its driver and process forces those of :mod:`mechdyn.mechanism.inputs`; they are importable from here
as well.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any, cast

import numpy as np

from mechdyn.errors import ModelError
from mechdyn.mechanism.elements import (
    GROUND,
    Body,
    Counterweight,
    GearJoint,
    Prismatic,
    Revolute,
    _folded,
    _point,
)
from mechdyn.mechanism.inputs import Driver, ProcessForce
from mechdyn.mechanism.inputs import TabulatedForce as TabulatedForce  # its former home
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
        import pandas as pd

        return pd.DataFrame(_body_rows(self))

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

    def output_rocker(self) -> tuple[str, str, str] | None:
        """The output as a rocker: (body, frame pivot, the point whose direction from the pivot is the
        rocker's angle); None when the output is a slide (its stroke is the output's travel) or there
        is no single link pinned to the frame besides the crank.

        The output named in the model (``output = [body, point]``) is used when it is pinned to the
        frame; otherwise the one body other than the crank that is pinned to the frame (a four-bar's
        rocker).
        """
        if self.output_joint() is not None:
            return None
        pivots = {_other(j, GROUND): j.point for j in self.joints if j.pins and GROUND in j.bodies}
        if self.output is not None:
            body, wanted = self.output
            if body not in pivots:
                return None
        else:
            rockers = [b for b in pivots if b != self.driver.body]
            if len(rockers) != 1:
                return None
            body, wanted = rockers[0], None
        pivot = pivots[body]
        pts = self.bodies[self._index[body]].points
        pinned = [j.point for j in self.joints if j.pins and body in j.bodies and GROUND not in j.bodies]
        tip = next((p for p in (wanted, *pinned, *pts) if p is not None and p != pivot and p in pts), None)
        return None if tip is None else (body, pivot, tip)


def _other(joint: Any, body: str) -> str:
    """The joint's body that is not ``body``."""
    return joint.bodies[0] if joint.bodies[1] == body else joint.bodies[1]


def _body_rows(mechanism: Mechanism) -> list[dict[str, Any]]:
    """One row per body as assembled, SI: name, points, mass (kg), inertia about the centre of mass
    (kg·m²), centre of mass (m), a two-point link's length (m) and whether it is the crank."""
    rows = []
    for b in mechanism.bodies:
        com = mechanism.com(b)
        pts = [mechanism.points[p] for p in b.points]
        length = math.dist(pts[0], pts[1]) if len(pts) == 2 else None
        rows.append(
            {
                "body": b.name,
                "points": ", ".join(b.points),
                "mass_kg": float(b.mass),
                "inertia_kg_m2": float(b.inertia),
                "center_of_mass_x_m": float(com[0]),
                "center_of_mass_y_m": float(com[1]),
                "length_m": length,
                "driven": b.name == mechanism.driver.body,
            }
        )
    return rows
