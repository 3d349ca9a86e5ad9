"""The counterweights, the flywheel and the motor are study parameters like any other value (issue 29,
point 5): a study varies them by their path in the model file, and each variant is the model the
analysis would give for those values directly."""

from __future__ import annotations

import dataclasses
import shutil

import numpy as np
import pytest

from conftest import EXAMPLES
from mechdyn.store import ResultStore

COUNTERWEIGHT = """
[[counterweights]]
body = "crank"
name = "crank counterweight"
mass = "20 t"
position = ["-600 mm", "0 mm"]
"""

COUNTERWEIGHT_STUDY = """
[study]
name = "counterweight"
kind = "oat"
model = "press_cw.toml"
analysis = "mechanism"
options = {angles = 72}

[[parameters]]
path = "counterweights.crank counterweight.mass"
levels = ["0 kg", "40 t"]

[[outputs]]
output = "shaking_force_max_N"
unit = "kN"
"""

DRIVE_STUDY = """
[study]
name = "flywheel-and-motor"
kind = "oat"
model = "press_driven.toml"
analysis = "drive"
options = {no_startup = true, angles = 180}

[[parameters]]
path = "flywheel.inertia"
levels = ["300 kg*m^2", "1200 kg*m^2"]

[[parameters]]
path = "motor.power"
levels = ["110 kW"]

[[outputs]]
output = "speed_fluctuation_ratio"

[[outputs]]
output = "motor_torque_peak_Nm"
unit = "kN*m"
"""


def _by_value(result, path):
    return {v.parameters[path]: v for v in result.variants if path in v.parameters}


def test_a_counterweights_mass_is_a_study_parameter(tmp_path):
    import mechdyn
    from mechdyn.mechanism.dynamics import inverse_dynamics
    from mechdyn.studies import load_study, run_study

    (tmp_path / "press_cw.toml").write_text((EXAMPLES / "press_link_drive.toml").read_text() + COUNTERWEIGHT)
    (tmp_path / "study.toml").write_text(COUNTERWEIGHT_STUDY)
    with ResultStore(str(tmp_path / "results.db")) as store:
        result = run_study(load_study(tmp_path / "study.toml"), store)
    assert all(v.status == "ok" for v in result.variants)
    heavy = _by_value(result, "counterweights.crank counterweight.mass")[40_000.0]
    # the same design built directly: the file's counterweight, twice as heavy
    model = mechdyn.load(tmp_path / "press_cw.toml").model
    (w,) = model.counterweights
    direct = inverse_dynamics(
        dataclasses.replace(model, counterweights=(dataclasses.replace(w, mass=4e4),)), 72
    )
    F = np.hypot(*direct.shaking_force.T).max()
    assert heavy.outputs["shaking_force_max_N"] == pytest.approx(F, rel=1e-12)


def test_the_flywheel_and_the_motor_are_study_parameters(tmp_path):
    from mechdyn.studies import load_study, run_study

    for name in ("press_driven.toml", "press_link_drive.toml"):
        shutil.copy(EXAMPLES / name, tmp_path / name)
    (tmp_path / "study.toml").write_text(DRIVE_STUDY)
    with ResultStore(str(tmp_path / "results.db")) as store:
        result = run_study(load_study(tmp_path / "study.toml"), store)
    assert all(v.status == "ok" for v in result.variants)
    base = next(v for v in result.variants if not v.parameters or v.id == result.base_id)
    flywheel = _by_value(result, "flywheel.inertia")
    light, heavy = flywheel[300.0], flywheel[1200.0]
    # a lighter flywheel lets the speed swing more, and the motor takes the peaks
    delta = [v.outputs["speed_fluctuation_ratio"] for v in (light, base, heavy)]
    assert delta[0] > delta[1] > delta[2] > 0
    torque = [v.outputs["motor_torque_peak_Nm"] for v in (light, base, heavy)]
    assert torque[0] > torque[1] > torque[2] > 0
    stronger = _by_value(result, "motor.power")[110e3]
    assert stronger.outputs["speed_fluctuation_ratio"] < base.outputs["speed_fluctuation_ratio"]
