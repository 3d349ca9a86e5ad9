"""``mechdyn simulate`` on drivetrain files: the time-simulation tables (each mesh's backlash,
transmission error and stiffness variation, ``[motor]``, ``[[loads]]``, ``[simulation]``) read into the
GearSystem and the torque inputs, the command on the shipped start-up example, every bad input named,
and the tables written back by ``mechdyn.save``."""

from __future__ import annotations

import json
import math
import re
import warnings

import numpy as np
import pytest

import mechdyn
from conftest import EXAMPLES
from mechdyn.cli.main import main
from mechdyn.drive.motor import InductionMotor, TorqueSpeedCurve
from mechdyn.errors import ModelFileError, ModelWarning
from mechdyn.gear_dynamics import GearSystem, loads, rectangular_profile
from mechdyn.registry import get

STARTUP = EXAMPLES / "turret_milling_startup.toml"

# a pinion (20 teeth) on the motor disk driving a 40-tooth gear on the load disk
PAIR = """
[model]
type = "drivetrain"
name = "one pair"

[[disks]]
name = "motor"
inertia = "0.01 kg*m^2"
[[disks]]
name = "load"
inertia = "0.04 kg*m^2"

[[meshes]]
name = "mesh"
disks = ["motor", "load"]
teeth = [20, 40]
base_radii = ["18.79 mm", "37.58 mm"]
stiffness = "3e8 N/m"
damping = "500 N*s/m"
"""


def _load(tmp_path, text, name="m.toml"):
    path = tmp_path / name
    path.write_text(text)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        return mechdyn.load(path)


def _startup():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        return mechdyn.load(STARTUP)


# -- the file's tables, read ----------------------------------------------------------------------


def test_the_example_reads_into_the_gear_system_and_inputs_it_describes():
    loaded = _startup()
    dyn = loaded.settings.dynamics
    assert dyn.meshes["mesh 2"].backlash == pytest.approx(50e-6, rel=1e-12)
    assert dyn.meshes["mesh 1"].transmission_error == pytest.approx(3e-6, rel=1e-12)
    system = GearSystem.from_drivetrain(loaded.model, **dyn.system_options())
    m1, m2 = system.meshes
    assert m1.backlash is None and m2.backlash == pytest.approx(50e-6, rel=1e-12)
    # the stiffness over the mesh cycle is the gear pair's, normalised to its mean
    cycle = dyn.meshes["mesh 1"].gear_pair.mesh_cycle()
    own = np.asarray(cycle.profile(), dtype=float)
    np.testing.assert_allclose(m1.profile, own / own.mean(), rtol=1e-12)
    assert np.ptp(m1.profile) > 0.1  # single and double contact differ
    # the transmission error is a sine of the amplitude given
    assert np.max(np.abs(m1.error)) == pytest.approx(3e-6, rel=1e-3) and not np.any(m2.error)
    motor, drag, cut = dyn.inputs()
    assert isinstance(motor, loads.MotorTorque) and motor.disk == "1"
    rated = InductionMotor.from_rating("3 kW", "3000 rpm", "2880 rpm", 2.8)
    w = 2 * math.pi * 2880 / 60
    assert motor.torque(0.0, w) == pytest.approx(rated.torque(w), rel=1e-12)
    assert motor.torque(0.0, w) == pytest.approx(3000 / w, rel=1e-9)  # the rated point
    assert isinstance(drag, loads.ConstantTorque) and drag.value == pytest.approx(-0.2)
    assert isinstance(cut, loads.RampTorque)
    assert (cut.disk, cut.final, cut.start, cut.end) == ("7", pytest.approx(-6.0), 0.25, 0.3)
    sim = dyn.simulation
    assert (sim.duration, sim.start, sim.output_step) == (0.5, "rest", pytest.approx(1e-4))


def test_a_rectangular_stiffness_variation_and_every_load_kind_read_as_written(tmp_path):
    text = (
        PAIR
        + 'stiffness_variation = { fluctuation = 0.3, contact_ratio = 1.6 }\nbacklash = "0.1 mm"\n'
        + """
[motor]
disk = "motor"
type = "curve"
curve = [["0 rpm", "60 N*m"], ["1440 rpm", "26 N*m"], ["1500 rpm", "0 N*m"]]
ratio = 2
direction = -1

[[loads]]
kind = "step"
disk = "load"
torque = "-20 N*m"
time = "0.2 s"
initial_torque = "-1 N*m"
[[loads]]
kind = "table"
disk = "load"
rows = [["0 s", "0 N*m"], ["100 ms", "-3 N*m"]]
[[loads]]
kind = "harmonic"
disk = "load"
amplitude = "2 N*m"
frequency = "50 Hz"
phase = "90 deg"
torque = "-1 N*m"
[[loads]]
kind = "stop"
time = "0.4 s"
brake = "30 N*m"

[simulation]
duration = "0.5 s"
initial_speed = "-750 rpm"
reference = "motor"
method = "Radau"
rtol = 1e-6
cycle_steps = 12
"""
    )
    dyn = _load(tmp_path, text).settings.dynamics
    system = GearSystem.from_drivetrain(_load(tmp_path, text).model, **dyn.system_options())
    np.testing.assert_array_equal(system.meshes[0].profile, rectangular_profile(0.3, 1.6))
    assert system.meshes[0].backlash == pytest.approx(1e-4)
    stop, step, table, harmonic = dyn.inputs()
    assert isinstance(stop, loads.BrakeStop) and (stop.time, stop.brake) == (0.4, 30.0)
    motor = stop.drive
    assert isinstance(motor.motor, TorqueSpeedCurve) and (motor.ratio, motor.direction) == (2.0, -1)
    assert (step.after, step.before, step.time) == (-20.0, -1.0, 0.2)
    assert table.torque(0.05, 0.0) == pytest.approx(-1.5)
    assert harmonic.phase == pytest.approx(math.pi / 2) and harmonic.mean == -1.0
    sim = dyn.simulation
    assert sim.initial_speed == pytest.approx(-750 * 2 * math.pi / 60) and sim.method == "Radau"


def test_a_file_without_the_tables_loads_as_before():
    loaded = mechdyn.load(EXAMPLES / "turret_milling.toml")
    assert loaded.settings.dynamics is None and loaded.settings.campbell is not None


# -- the command ------------------------------------------------------------------------------------


def test_mechdyn_simulate_runs_the_startup_example_and_stores_it(tmp_path, capsys):
    db = tmp_path / "runs.db"
    argv = ["simulate", str(STARTUP), "--duration", "40 ms", "--json", "--db", str(db)]
    assert main([*argv, "--plots", str(tmp_path / "plots")]) == 0
    doc = json.loads(capsys.readouterr().out)
    documented = {o.key for o in get("simulate").outputs}
    assert {"duration_s", "mesh_force_peak_N", "final_speed_rad_s", "energy_residual_J"} <= set(doc)
    assert (
        set(doc)
        - {"run_id", "analysis", "model", "model_file", "model_sha256", "parameters"}
        - {
            "warnings",
            "plots",
            "report",
        }
        <= documented
    )
    assert doc["duration_s"] == pytest.approx(0.04) and doc["parameters"]["duration"] == pytest.approx(0.04)
    # started from rest, the motor has the spindle turning forward, through two reversing meshes
    assert doc["final_speed_rad_s"]["7"] > 100 and doc["final_speed_rad_s"]["4"] < -100
    assert set(doc["mesh_force_peak_N"]) == {"mesh 1", "mesh 2"}
    assert {p.rsplit("/", 1)[-1] for p in doc["plots"]} == {"speeds.png", "mesh_forces.png", "dte.png"}
    assert main(["results", "list", "--json", "--db", str(db)]) == 0
    runs = json.loads(capsys.readouterr().out)
    assert [r["analysis"] for r in runs] == ["simulate"] and runs[0]["id"] == doc["run_id"]


def test_the_help_lists_the_options_with_their_units(capsys):
    with pytest.raises(SystemExit):
        main(["simulate", "--help"])
    out = capsys.readouterr().out
    for flag in ("--duration", "--initial-speed", "--reference", "--start", "--method", "--output-step"):
        assert flag in out
    assert "turret_milling_startup.toml" in out


@pytest.mark.parametrize(
    ("extra", "options", "message"),
    [
        ("", [], "no duration; add a [simulation] table with duration"),
        ("", ["--duration", "0.1 s"], "nothing moves the train; add a [motor] table or [[loads]] rows"),
    ],
    ids=["no duration", "no inputs"],
)
def test_a_model_without_simulation_tables_is_refused_with_the_fix(tmp_path, capsys, extra, options, message):
    path = tmp_path / "bare.toml"
    path.write_text(PAIR + extra)
    assert main(["simulate", str(path), "--db", str(tmp_path / "r.db"), *options]) == 2
    err = capsys.readouterr().err
    assert "bare.toml" in err and message in err


# -- bad input ------------------------------------------------------------------------------------

MOTOR = (
    '\n[motor]\ndisk = "motor"\npower = "4 kW"\nsynchronous_speed = "1500 rpm"\nrated_speed = "1440 rpm"\n'
)
MOTOR_OK = MOTOR + "pullout_ratio = 2.8\n"

BAD = [
    (
        'stiffness_variation = "gears"\n',
        "[[meshes]] #1 (name = 'mesh')",
        'stiffness_variation = "gears" takes the mesh cycle of a gear pair; give gear_pair',
    ),
    (
        'stiffness_variation = "sometimes"\n',
        "[[meshes]] #1 (name = 'mesh') → stiffness_variation",
        """'sometimes' is not a stiffness variation; give "constant", "gears", or a table""",
    ),
    (
        "stiffness_variation = { fluctuation = 0.3 }\n",
        "[[meshes]] #1 (name = 'mesh') → stiffness_variation",
        "contact_ratio: Field required",
    ),
    (
        "stiffness_variation = { fluctuation = 1.8, contact_ratio = 1.9 }\n",
        "stiffness_variation",
        "single-contact stiffness",
    ),
    ('backlash = "-50 um"\n', "[[meshes]] #1 (name = 'mesh') → backlash", "greater than 0"),
    ('backlash = "50 kg"\n', "[[meshes]] #1 (name = 'mesh') → backlash", "'50 kg'"),
    ('transmission_error = "5 um"\n', None, None),  # by teeth: fine
    (
        MOTOR.replace('"motor"\npower', '"spindle"\npower') + "pullout_ratio = 2.8\n",
        "[motor] → disk",
        "spindle",
    ),
    (MOTOR, "[motor]", "an induction motor needs pullout_ratio"),
    (
        MOTOR_OK + 'rotor_inertia = "1e-3 kg*m^2"\n',
        "[motor]",
        "rotor_inertia: the rotor is disk 'motor'; add its inertia to that disk's inertia",
    ),
    (
        '\n[[loads]]\nkind = "ramp"\ndisk = "load"\ntorque = "-5 N*m"\nstart = "0.1 s"\n',
        "[[loads]] #1",
        'a ramp load needs end; e.g. torque = "-12 N*m", start = "0.5 s", end = "0.8 s"',
    ),
    (
        '\n[[loads]]\nkind = "ramp"\ndisk = "load"\ntorque = "-5 N*m"\nstart = "0.3 s"\nend = "0.1 s"\n',
        "[[loads]] #1",
        "the ramp ends at 0.1 s, not after its start at 0.3 s",
    ),
    (
        '\n[[loads]]\nkind = "constant"\ndisk = "load"\ntorque = "-5 N*m"\nfrequency = "5 Hz"\n',
        "[[loads]] #1",
        "frequency is not read by a constant load; remove it",
    ),
    ('\n[[loads]]\nkind = "constant"\ntorque = "-5 N*m"\n', "[[loads]] #1", "needs the disk it acts on"),
    (
        '\n[[loads]]\nkind = "constant"\ndisk = "tool"\ntorque = "-5 N*m"\n',
        "[[loads]] #1 → disk",
        "'tool' is not a disk; defined disks: motor, load",
    ),
    ('\n[[loads]]\nkind = "pulse"\ndisk = "load"\n', "[[loads]] #1 → kind", "'pulse'"),
    ('\n[[loads]]\nkind = "stop"\ntime = "1 s"\n', "[[loads]] #1 → kind", "a stop switches off the [motor]"),
    ('\n[simulation]\nduration = "0 s"\n', "[simulation] → duration", "greater than 0"),
    ('\n[simulation]\nduration = "1 s"\nreference = "tool"\n', "[simulation] → reference", "'tool' is not"),
    ('\n[simulation]\nduration = "1 s"\nmethod = "Euler"\n', "[simulation] → method", "LSODA"),
    ('\n[simulation]\nduration = "1 s"\nstart = "spinning"\n', "[simulation] → start", "static"),
]


@pytest.mark.parametrize(("extra", "where", "message"), BAD, ids=[f"{i}" for i in range(len(BAD))])
def test_every_bad_table_is_named_with_its_fix(tmp_path, extra, where, message):
    path = tmp_path / "bad.toml"
    path.write_text(PAIR + extra)
    if where is None:
        assert mechdyn.load(path).settings.dynamics is not None
        return
    with pytest.raises(ModelFileError) as caught:
        mechdyn.load(path)
    text = str(caught.value)
    assert "bad.toml" in text and where in text and message in text, text


@pytest.mark.parametrize(
    ("mesh", "extra", "message"),
    [
        (
            'ratio = 2\nbase_radii = ["18.79 mm", "37.58 mm"]\nstiffness = "3e8 N/m"\n',
            'transmission_error = "5 um"\n',
            "needs the teeth",
        ),
        ("teeth = [20, 40]\n", 'backlash = "50 um"\n', "a rigid mesh (no stiffness) has no backlash"),
    ],
    ids=["error without teeth", "backlash on a rigid mesh"],
)
def test_a_mesh_that_cannot_carry_the_dynamics_is_named(tmp_path, mesh, extra, message):
    head = PAIR.split("teeth = [20, 40]")[0]
    path = tmp_path / "bad.toml"
    path.write_text(head + mesh + extra)
    with pytest.raises(ModelFileError, match=re.escape(message)) as caught:
        mechdyn.load(path)
    assert "bad.toml" in str(caught.value) and "[[meshes]] #1 (name = 'mesh')" in str(caught.value)


# -- mechdyn.save -----------------------------------------------------------------------------------


def test_save_writes_the_simulation_tables_back(tmp_path):
    text = STARTUP.read_text().replace(
        'stiffness_variation = "gears"        #',
        "stiffness_variation = { fluctuation = 0.3, contact_ratio = 1.6 } #",
    )
    text = text.replace('stiffness_variation = "gears"\n', "")
    loaded = _load(tmp_path, text, "rect.toml")
    again = _load(tmp_path, mechdyn.save(loaded, tmp_path / "saved.toml").read_text(), "again.toml")
    assert again.model == loaded.model and again.settings == loaded.settings
    assert again.settings.dynamics.meshes["mesh 1"].stiffness_variation == (0.3, 1.6)


def test_save_refuses_a_stiffness_from_gears_it_cannot_write(tmp_path):
    with pytest.raises(
        mechdyn.errors.MechdynError, match="takes its stiffness over the mesh cycle from its gear"
    ):
        mechdyn.save(_startup(), tmp_path / "x.toml")


def test_a_design_study_varies_a_mesh_s_backlash_and_reads_a_dynamic_factor(tmp_path):
    """``simulate`` in a study: a mesh's backlash varied one at a time, an output of one mesh stored
    per variant, each variant the same as the analysis run on the changed file by itself."""
    model = PAIR.replace(
        'damping = "500 N*s/m"', 'damping = "500 N*s/m"\nbacklash = "20 um"\ntransmission_error = "4 um"'
    )
    model += """
[[loads]]
kind = "constant"
disk = "load"
torque = "-2 N*m"

[simulation]
duration = "20 ms"
initial_speed = "1500 rpm"
"""
    (tmp_path / "pair.toml").write_text(model)
    (tmp_path / "study.toml").write_text(
        """
[study]
name = "pair-backlash"
kind = "oat"
model = "pair.toml"
analysis = "simulate"

[[parameters]]
path = "meshes.mesh.backlash"
levels = ["+100 %"]

[[outputs]]
output = "dynamic_factor.mesh"

[[outputs]]
output = "mesh_force_peak_N.mesh"
"""
    )
    db = str(tmp_path / "s.db")
    assert main(["study", str(tmp_path / "study.toml"), "--db", db, "--json"]) == 0
    from mechdyn.store import ResultStore
    from mechdyn.studies.storage import StudyStore

    with ResultStore(db, read_only=True) as store:
        variants = StudyStore(store).variants("pair-backlash")
    assert len(variants) == 2 and all(v.status == "ok" for v in variants)
    (tmp_path / "wider.toml").write_text(model.replace('backlash = "20 um"', 'backlash = "40 um"'))
    alone = get("simulate").run(mechdyn.load(tmp_path / "wider.toml")).summary()
    wider = next(v for v in variants if v.given["meshes.mesh.backlash"] == "40 um")
    outputs = dict(wider.outputs)
    assert outputs["mesh_force_peak_N.mesh"] == pytest.approx(alone["mesh_force_peak_N"]["mesh"], rel=1e-9)
    assert outputs["dynamic_factor.mesh"] == pytest.approx(alone["dynamic_factor"]["mesh"], rel=1e-9)


# -- --motor: another file's [motor] --------------------------------------------------------------

CURVE = (
    '\n[motor]\ntype = "curve"\n'
    'curve = [["0 rpm", "30 N*m"], ["1400 rpm", "25 N*m"], ["1500 rpm", "0 N*m"]]\n'
)


def _simulated(tmp_path, capsys, model_text, *options):
    path = tmp_path / "pair.toml"
    path.write_text(model_text)
    argv = ["simulate", str(path), "--duration", "20 ms", "--json", "--db", str(tmp_path / "r.db")]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        assert main([*argv, *options]) == 0
    doc = json.loads(capsys.readouterr().out)
    return {k: doc[k] for k in ("final_speed_rad_s", "mesh_force_peak_N", "input_work_J")}


def test_motor_option_drives_with_another_file_s_motor_as_if_written_in_the_model(tmp_path, capsys):
    other = tmp_path / "motor.toml"
    other.write_text(CURVE + 'disk = "motor"\n')
    inline = _simulated(tmp_path, capsys, PAIR + CURVE + 'disk = "motor"\n')
    # the model's own induction motor is replaced by the curve: the same run as the curve written in
    by_option = _simulated(tmp_path, capsys, PAIR + MOTOR_OK, "--motor", str(other))
    assert by_option == inline
    own = _simulated(tmp_path, capsys, PAIR + MOTOR_OK)
    assert own["final_speed_rad_s"]["motor"] != pytest.approx(inline["final_speed_rad_s"]["motor"], rel=1e-3)


def test_motor_option_takes_a_drive_file_s_motor_onto_the_reference_disk(tmp_path, capsys):
    drive = EXAMPLES / "press_driven.toml"  # a 90 kW induction motor, with its rotor's inertia
    table = drive.read_text().split("[motor]")[1].split("[transmission]")[0]
    table = "\n".join(line for line in table.splitlines() if not line.startswith("rotor_inertia"))
    inline = _simulated(tmp_path, capsys, PAIR + '\n[motor]\ndisk = "load"\n' + table)
    path = tmp_path / "pair.toml"
    path.write_text(PAIR)
    argv = ["simulate", str(path), "--duration", "20 ms", "--json", "--db", str(tmp_path / "r.db")]
    assert main([*argv, "--motor", str(drive), "--reference", "load"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert any(
        "[motor] → rotor_inertia = '1.4 kg*m^2' is not added: the rotor is disk 'load'" in w
        for w in doc["warnings"]
    )
    assert {k: doc[k] for k in inline} == inline


@pytest.mark.parametrize(
    ("motor", "options", "where", "message"),
    [
        ('[model]\nname = "x"\n', [], "[motor]", "no [motor] table; give a drive or drivetrain file"),
        (CURVE, [], "[motor] → disk", "names no disk and the model has no [motor]; add disk = "),
        (
            CURVE + 'disk = "motor"\nratoi = 2\n',
            [],
            "[motor] → ratoi",
            "ratio",
        ),
        (
            CURVE + 'disk = "nowhere"\n',
            [],
            "[motor] → disk",
            "'nowhere' is not a disk of the drivetrain; give one of motor, load",
        ),
    ],
    ids=["no motor table", "no disk", "misspelt field", "unknown disk"],
)
def test_a_bad_motor_file_is_named_with_its_fix(tmp_path, capsys, motor, options, where, message):
    other = tmp_path / "other_motor.toml"
    other.write_text(motor)
    path = tmp_path / "pair.toml"
    path.write_text(PAIR)
    argv = [
        "simulate",
        str(path),
        "--duration",
        "20 ms",
        "--db",
        str(tmp_path / "r.db"),
        "--motor",
        str(other),
    ]
    assert main([*argv, *options]) == 2
    err = capsys.readouterr().err
    assert message in err and where in err and "other_motor.toml" in err and "Traceback" not in err
