"""The plan of a mechanism for the dyad path: a crank, then Assur groups of class II — RRR dyads (a
joint between two links whose other ends are known) and RRP dyads (a link end sliding on a frame
guide) — and rigid bodies whose points follow from two known ones, in the order in which the points
become known (e.g. Norton, *Design of Machinery*, ch. 4; Hansen's Assur-group method). A mechanism
with no such order is :class:`NotDecomposable` and runs on the general engine.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import cast

from mechdyn.errors import ModelError
from mechdyn.mechanism.model import GROUND, Mechanism, Prismatic

__all__ = ["NotDecomposable", "Step", "plan"]


class NotDecomposable(ModelError):
    """The mechanism is not a crank with RRR/RRP dyads; use the general engine."""


@dataclass(frozen=True)
class Step:
    """One step of the solution order: which point(s) it finds and from what.

    Attributes
    ----------
    kind : {"crank", "rigid", "rrr", "rrp"}
        The crank, a rigid body from two known points (or a slider from its guide point), an RRR or
        an RRP dyad.
    target : str or tuple of str
        The point a dyad finds, or the points of a body it places.
    known : tuple of str
        The points it starts from.
    body : str or None
        The body it places (the slider of an RRP dyad).
    guide : Prismatic or None
        The frame guide of an RRP dyad or of a slider body.
    """

    kind: str  # "crank", "rigid", "rrr", "rrp"
    target: str | tuple[str, ...]
    known: tuple[str, ...]
    body: str | None = None
    guide: Prismatic | None = None


def plan(mechanism: Mechanism) -> list[Step]:
    """The order in which the points become known; :class:`NotDecomposable` if there is none."""
    m = mechanism
    for j in m.joints:
        if not (j.pins or j.slides):
            raise NotDecomposable(
                f"joint {j.name!r} is neither a pin nor a slider; it runs on the general engine",
                element=j.name,
            )
    pts_of = {b.name: set(b.points) for b in m.bodies}
    grounded = {j.point for j in m.joints if j.pins and GROUND in j.bodies}
    for j in m.joints:
        if j.slides and j.bodies[0] == GROUND:
            raise NotDecomposable(
                "the frame cannot slide on a body here; swap the joint's bodies", element=j.name
            )
        if j.slides and j.bodies[1] != GROUND:
            raise NotDecomposable(
                f"slider {j.name!r} runs on a moving guide; use the general engine", element=j.name
            )
    d = m.driver
    if d.pivot not in grounded:
        raise NotDecomposable(f"the crank's pivot {d.pivot!r} is not a frame pivot", element="driver")
    known = set(grounded)
    steps = [Step("crank", tuple(sorted(pts_of[d.body] - {d.pivot})), (d.pivot,), d.body)]
    known |= pts_of[d.body]
    done_bodies = {d.body}
    sliders = {j.bodies[0]: cast(Prismatic, j) for j in m.joints if j.slides}
    revolutes = [j for j in m.joints if j.pins]
    while len(done_bodies) < len(m.bodies):
        progress = False
        for b in m.bodies:  # rigid: two known points fix the rest
            if b.name in done_bodies:
                continue
            k = sorted(pts_of[b.name] & known)
            if len(k) >= 2:
                rest = tuple(sorted(pts_of[b.name] - known))
                steps.append(Step("rigid", rest, (k[0], k[1]), b.name))
                known |= pts_of[b.name]
                done_bodies.add(b.name)
                progress = True
        for j in revolutes:  # RRR: an unknown pin between two links each with a known point
            p = j.point
            if p in known or GROUND in j.bodies:
                continue
            b1, b2 = j.bodies
            k1 = sorted((pts_of[b1] & known) - {p})
            k2 = sorted((pts_of[b2] & known) - {p})
            if k1 and k2 and b1 not in sliders and b2 not in sliders:
                steps.append(Step("rrr", p, (k1[0], k2[0])))
                known.add(p)
                progress = True
        for s, g in sliders.items():  # RRP: a link end on a frame guide
            p = g.point
            if p in known:
                continue
            links = [
                j.bodies[0] if j.bodies[1] == s else j.bodies[1]
                for j in revolutes
                if j.point == p and s in j.bodies
            ]
            for b1 in links:
                k1 = sorted((pts_of[b1] & known) - {p})
                if k1:
                    steps.append(Step("rrp", p, (k1[0],), s, g))
                    known.add(p)
                    progress = True
                    break
        for s, g in sliders.items():  # a slider body translates with its guide point
            if s not in done_bodies and g.point in known:
                rest = tuple(sorted(pts_of[s] - known))
                steps.append(Step("rigid", rest, (g.point,), s, g))
                known |= pts_of[s]
                done_bodies.add(s)
                progress = True
        if not progress:
            missing = ", ".join(b.name for b in m.bodies if b.name not in done_bodies)
            raise NotDecomposable(
                f"no RRR or RRP dyad closes the remaining bodies ({missing}); use the general engine"
            )
    return steps
