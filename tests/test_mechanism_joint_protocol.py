"""Joints follow one protocol: a new joint type works with the general engine without a change to it.

A massless link of fixed length between two points (a distance constraint, one row) is written here
from scratch as a joint class: its row count, reference checks, motion law and constraint terms.
A crank-rocker whose coupler is such a link must move exactly as the same linkage with a massless
coupler body, and the loads on the crank and the rocker must agree. Nothing in the assembler, the
Newton engine or the load computation asks what kind of joint it is (checked on the source too).
"""

from __future__ import annotations

import ast
import math
from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar

import numpy as np

import mechdyn
from mechdyn.mechanism import Body, Driver, Mechanism, Revolute, inverse_dynamics
from mechdyn.mechanism.joint_terms import JointTerms, _perp, _rotate


class DistanceTerms(JointTerms):
    """½ (d·d − L²) = 0 with d the vector from the point on body b to the point on body a."""

    equations = ("distance",)

    def __init__(self, ia, ib, sa, sb, length):
        self.ia, self.ib, self.sa, self.sb, self.length = ia, ib, sa, sb, length

    def evaluate(self, body, rate, res, jac, gam, r0):
        ia, ib = self.ia, self.ib
        Asa, Asb = _rotate(body[..., ia, 2], self.sa), _rotate(body[..., ib, 2], self.sb)
        d = body[..., ia, :2] + Asa - body[..., ib, :2] - Asb
        res[..., r0] = 0.5 * (np.sum(d * d, axis=-1) - self.length**2)
        jac[..., r0, 3 * ia : 3 * ia + 2] = d
        jac[..., r0, 3 * ia + 2] = np.sum(d * _perp(Asa), axis=-1)
        jac[..., r0, 3 * ib : 3 * ib + 2] = -d
        jac[..., r0, 3 * ib + 2] = -np.sum(d * _perp(Asb), axis=-1)
        if gam is not None:
            wa, wb = rate[..., ia, 2], rate[..., ib, 2]
            dd = (
                rate[..., ia, :2]
                + _perp(Asa) * wa[..., None]
                - rate[..., ib, :2]
                - _perp(Asb) * wb[..., None]
            )
            centripetal = Asa * (wa**2)[..., None] - Asb * (wb**2)[..., None]
            gam[..., r0] = -np.sum(dd * dd, axis=-1) + np.sum(d * centripetal, axis=-1)


@dataclass(frozen=True)
class Distance:
    """A massless link of fixed length from ``points[0]`` on ``bodies[0]`` to ``points[1]`` on
    ``bodies[1]``."""

    name: str
    bodies: tuple[str, str]
    points: tuple[str, str]

    n_rows: ClassVar[int] = 1
    pins: ClassVar[bool] = False
    slides: ClassVar[bool] = False

    def check(self, points, bodies):
        for b, p in zip(self.bodies, self.points, strict=True):
            assert p in points and (b == "ground" or p in bodies[b].points)

    def law(self, points):
        return None

    def terms(self, mechanism, slot):
        a, b = self.bodies
        pa, pb = self.points
        length = math.dist(mechanism.points[pa], mechanism.points[pb])
        return DistanceTerms(slot(a), slot(b), mechanism.local(a, pa), mechanism.local(b, pb), length)


def _crank_rocker(coupler_as_link: bool):
    pts = {"O2": (0.0, 0.0), "A": (0.025, 0.04330127), "B": (0.19460848, 0.14928695), "O4": (0.18, 0.0)}
    bodies = [Body("crank", ("O2", "A"), 0.3, 6.25e-5), Body("rocker", ("B", "O4"), 0.9, 1.6875e-3)]
    joints = [Revolute("O2", ("ground", "crank"), "O2"), Revolute("O4", ("rocker", "ground"), "O4")]
    if coupler_as_link:
        joints.append(Distance("AB", ("crank", "rocker"), ("A", "B")))
    else:
        bodies.insert(1, Body("coupler", ("A", "B"), 0.0, 0.0))
        joints += [Revolute("A", ("crank", "coupler"), "A"), Revolute("B", ("coupler", "rocker"), "B")]
    return Mechanism(
        pts, tuple(bodies), tuple(joints), Driver("crank", "O2", "A", 12.0), gravity=(0.0, -9.81)
    )


def test_a_joint_type_written_outside_the_package_runs_on_the_general_engine():
    new = inverse_dynamics(_crank_rocker(True), 72, method="newton")
    ref = inverse_dynamics(_crank_rocker(False), 72, method="newton")
    for body, point in (("rocker", "B"), ("crank", "A")):
        np.testing.assert_allclose(
            new.kinematics.point(body, point)[0], ref.kinematics.point(body, point)[0], atol=1e-12
        )
        np.testing.assert_allclose(
            new.kinematics.point(body, point)[2], ref.kinematics.point(body, point)[2], atol=1e-9
        )
    scale = np.abs(ref.driving_torque).max()
    np.testing.assert_allclose(new.driving_torque, ref.driving_torque, atol=1e-9 * scale)
    frame = np.abs(ref.shaking_force).max()
    o4_new, o4_ref = new.joint_load("O4", "ground"), ref.joint_load("O4", "ground")
    np.testing.assert_allclose(o4_new, o4_ref, atol=1e-9 * frame)
    np.testing.assert_allclose(new.shaking_force, ref.shaking_force, atol=1e-9 * frame)
    assert np.abs(new.power_balance_residual).max() < 1e-9 * np.abs(new.driving_torque * 12).max()


def test_no_module_of_the_engine_asks_which_type_a_joint_is():
    src = Path(mechdyn.__file__).resolve().parent / "mechanism"
    asked = []
    for path in src.glob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Call) and getattr(node.func, "id", None) == "isinstance":
                kinds = ast.unparse(node.args[1])
                if any(k in kinds for k in ("Revolute", "Prismatic", "GearJoint")):
                    asked.append(f"{path.name}:{node.lineno}: {ast.unparse(node)}")
    assert not asked, asked
