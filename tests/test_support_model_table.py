"""The machine on its mounts as assembled: body and mounts, each value with where it came from."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import mechdyn
from conftest import EXAMPLES
from mechdyn.errors import ModelWarning
from mechdyn.registry import get


def _run(name):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        loaded = mechdyn.load(EXAMPLES / name)
        return loaded, get("support").run(loaded, cycles=1, store=None)


def test_the_support_shows_the_body_and_mounts_it_solved_and_where_the_stiffness_came_from():
    _, result = _run("press_on_pads.toml")
    machine = result.machine
    body, mounts = result.tables()[-2:]
    assert body.title.endswith("the machine as assembled")
    assert mounts.title.endswith("the mounts as assembled")
    rows = {r[0]: r for r in body.rows}
    assert rows["mass"][1:] == [machine.body.mass, "kg"]
    assert rows["centre of mass z"][1] == pytest.approx(1e3 * machine.body.center_of_mass[2])
    assert rows["inertia Iyy"][1] == pytest.approx(np.asarray(machine.body.inertia)[1, 1])
    by_name = {r[0]: r for r in mounts.rows}
    m = machine.mounts[0]
    assert mounts.columns[6] == "k3 [kN/mm]"
    assert by_name[m.name][6] == pytest.approx(m.stiffness[2] / 1e6)  # N/m → kN/mm
    assert by_name[m.name][-1].startswith("elastomer pad estimate from ")
    assert by_name[m.name][-1].endswith("press_pad.toml")
    frame = machine.to_frame().set_index("mount")
    assert frame.loc[m.name, "stiffness_3_N_per_m"] == m.stiffness[2]
    assert frame.loc[m.name, "from"] == "given"  # the machine alone does not know its drawings


def test_mounts_given_in_the_file_say_so():
    _, result = _run("press_on_mounts.toml")
    mounts = result.tables()[-1]
    assert {r[-1] for r in mounts.rows} == {"given"}
