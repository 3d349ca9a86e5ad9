"""The mechanism as assembled: bodies and joints as the analysis sees them."""

from __future__ import annotations

import math

import pytest

import mechdyn
from conftest import EXAMPLES
from mechdyn.registry import get


def test_the_press_shows_its_bodies_and_joints_as_assembled():
    loaded = mechdyn.load(EXAMPLES / "press_link_drive.toml")
    m = loaded.model
    bodies, joints = get("mechanism").run(loaded).tables()[-2:]
    assert bodies.title.endswith("the bodies as assembled") and joints.title.endswith(
        "the joints as assembled"
    )
    rows = {r[0]: r for r in bodies.rows}
    crank = m.bodies[m.body_index[m.driver.body]]
    row = rows[f"{crank.name} (driven)"]
    assert row[1:3] == [crank.mass, crank.inertia]
    a, b = (m.points[p] for p in crank.points)
    assert row[5] == pytest.approx(1e3 * math.dist(a, b))
    assert rows["ternary"][5] is None  # three points: no single length
    kinds = {r[0]: r[1] for r in joints.rows}
    assert kinds["A"] == "revolute" and kinds["guide"] == "slider"
    assert len(joints.rows) == len(m.joints)
    frame = m.to_frame().set_index("body")
    assert frame.loc["slide", "mass_kg"] == m.bodies[m.body_index["slide"]].mass
    assert frame.loc[crank.name, "center_of_mass_x_m"] == pytest.approx(m.com(crank)[0])
