"""Every option a mechanism file accepts reaches the model (none is read and silently dropped).

Each field of every table of the schema is set from a file here and checked on the model it builds;
a field added to the schema without a check here fails the coverage test.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import mechdyn
from conftest import EXAMPLES
from mechdyn.mechanism import GearJoint, Prismatic, inverse_dynamics
from mechdyn.mechanism import schema as ms

SLIDER = (EXAMPLES / "slider_crank.toml").read_text()

# two circular gears on a fixed frame, gear 1 driven (a minimal gear file to vary)
GEARS = """
[model]
type = "mechanism"
name = "gear pair"

[points]
O = ["0 mm", "0 mm"]
T = ["20 mm", "0 mm"]
C = ["50 mm", "0 mm"]
D = ["50 mm", "10 mm"]

[[bodies]]
name = "g1"
points = ["O", "T"]
mass = "0.2 kg"
inertia = "4e-5 kg*m^2"
center_of_mass = "O"

[[bodies]]
name = "g2"
points = ["C", "D"]
mass = "0.4 kg"
inertia = "1.6e-4 kg*m^2"
center_of_mass = "C"

[[joints]]
name = "O"
type = "revolute"
bodies = ["ground", "g1"]
point = "O"

[[joints]]
name = "C"
type = "revolute"
bodies = ["ground", "g2"]
point = "C"

[[joints]]
name = "mesh"
type = "gear"
bodies = ["g1", "g2"]
points = ["O", "C"]
pitch = { kind = "circle", radius = "20 mm" }

[driver]
body = "g1"
pivot = "O"
tip = "T"
speed = "10 rad/s"
"""

# the schema's tables and the fields this file checks; the coverage test compares them
COVERED = {
    "MechanismFile": {
        "model",
        "points",
        "bodies",
        "joints",
        "driver",
        "settings",
        "process_forces",
        "counterweights",
    },
    "ModelTable": {"type", "name", "description", "source"},
    "BodyTable": {"name", "points", "mass", "inertia", "center_of_mass"},
    "JointTable": {
        "name",
        "type",
        "bodies",
        "point",
        "axis",
        "points",
        "carrier",
        "pitch",
        "orientation",
        "pressure_angle",
        "internal",
        "flank",
    },
    "PitchTable": {"kind", "radius", "eccentricity_ratio", "semi_major", "radii"},
    "DriverTable": {"body", "pivot", "tip", "speed", "speed_profile"},
    # rated_torque and rated_force: tests/test_mechanism_tonnage.py reads them from a file;
    # press_stiffness, reverse_capacity, press_damping: tests/test_press_load_cycle.py (press_blanking)
    "SettingsTable": {
        "gravity",
        "angle_datum",
        "n_angles",
        "output",
        "trace",
        "field_velocity",
        "rated_torque",
        "rated_force",
        "press_stiffness",
        "reverse_capacity",
        "press_damping",
    },
    "ProcessForceTable": {"body", "point", "direction", "versus", "table"},
    "CounterweightTable": {"body", "mass", "position", "inertia", "name"},
}


def _load(tmp_path, text):
    path = tmp_path / "m.toml"
    path.write_text(text)
    return mechdyn.load(path)


def _sub(text, old, new):
    assert old in text, old
    return text.replace(old, new, 1)


def test_every_field_of_the_mechanism_file_is_checked_here():
    for name, fields in COVERED.items():
        assert set(getattr(ms, name).model_fields) == fields, name


def test_model_points_bodies_and_settings_reach_the_model(tmp_path):
    text = _sub(SLIDER, 'name = "slider-crank"', 'name = "my crank"\ndescription = "d"\nsource = "s"')
    text = _sub(
        text,
        'name = "crank"\npoints = ["O", "A"]\nmass = "2 kg"\ninertia = "0.002 kg*m^2"\n'
        'center_of_mass = ["0.05 m", "0 m"]',
        'name = "crank"\npoints = ["O", "A"]\nmass = "2.5 kg"\ninertia = "0.003 kg*m^2"\n'
        'center_of_mass = ["0.04 m", "0.01 m"]',
    )
    text = _sub(
        text,
        "[settings]\nn_angles = 360",
        '[settings]\nn_angles = 72\ngravity = ["0 m/s^2", "-9.81 m/s^2"]\nangle_datum = "bdc"\n'
        'output = ["slider", "B"]\ntrace = ["A"]\nfield_velocity = ["0.5 m/s", "0 m/s"]',
    )
    loaded = _load(tmp_path, text)
    m, spec = loaded.model, loaded.settings
    assert m.name == "my crank" and loaded.source.data["model"]["description"] == "d"
    assert loaded.source.data["model"]["source"] == "s"  # kept with the file in the results store
    assert m.points["B"] == (0.5, 0.0)
    crank = m.bodies[0]
    assert (crank.name, crank.points, crank.mass, crank.inertia) == ("crank", ("O", "A"), 2.5, 0.003)
    np.testing.assert_allclose(m.com(crank), [0.04, 0.01])
    assert m.gravity == (0.0, -9.81) and m.angle_datum == "bdc" and m.output == ("slider", "B")
    assert spec.n_angles == 72 and spec.trace == ("A",) and spec.field_velocity == (0.5, 0.0)
    d = inverse_dynamics(m, spec.n_angles)
    assert d.summary()["bdc_deg"] == pytest.approx(0.0, abs=1e-9)  # the datum took effect


@pytest.mark.parametrize(("datum", "drawing"), [('"90 deg"', 270.0), ('"bdc"', 180.0)])
def test_a_speed_profile_in_a_file_is_read_against_the_crank_angle_it_shows(tmp_path, datum, drawing):
    # the rows are crank angles from angle_datum, as every table and plot shows them (not the angle
    # turned from the drawing, 90° or 180° away here): the speed in the results at 0°, 90°, … is the row's
    rows = [("0 deg", 100.0), ("90 deg", 150.0), ("180 deg", 100.0), ("270 deg", 60.0)]
    table = ", ".join(f'["{a}", "{w} rad/s"]' for a, w in rows)
    text = _sub(SLIDER, 'speed = "100 rad/s"', f'speed = "100 rad/s"\nspeed_profile = [{table}]')
    text = _sub(text, "n_angles = 360", f"n_angles = 360\nangle_datum = {datum}")
    m = _load(tmp_path, text).model
    d = inverse_dynamics(m, 360)
    np.testing.assert_allclose(d.crank_speed[[0, 90, 180, 270]], [w for _, w in rows], rtol=1e-9)
    # the drawing (crank along +x) is where the profile's clock starts
    assert d.kinematics.time[round(drawing)] == 0.0


def test_joint_driver_and_process_force_fields_reach_the_model(tmp_path):
    text = _sub(SLIDER, 'axis = "0 deg"', 'axis = "0.0 deg"')
    text = _sub(
        text,
        'speed = "100 rad/s"',
        'speed = "-100 rad/s"\nspeed_profile = [["0 deg", "100 rad/s"], ["180 deg", "120 rad/s"]]',
    )
    text += (
        '\n[[process_forces]]\nbody = "slider"\npoint = "B"\ndirection = "180 deg"\nversus = "position"\n'
        'table = [["-0.2 m", "0 N"], ["0 m", "1 kN"]]\n'
    )
    m = _load(tmp_path, text).model
    guide = next(j for j in m.joints if j.name == "guide")
    assert isinstance(guide, Prismatic) and guide.bodies == ("slider", "ground") and guide.point == "B"
    d = m.driver
    assert (d.body, d.pivot, d.tip, d.speed) == ("crank", "O", "A", -100.0)
    w, _ = d.rates(np.array([0.0, math.pi]))
    np.testing.assert_allclose(w, [-100.0, -120.0])  # the profile, in the direction of rotation
    (pf,) = m.process_forces
    assert (pf.body, pf.point) == ("slider", "B")
    fx, fy = pf.force(np.zeros(3), np.array([-0.3, -0.1, 0.0]))
    np.testing.assert_allclose(fx, [0.0, -500.0, -1000.0], atol=1e-9)  # along 180°, by position
    np.testing.assert_allclose(fy, 0.0, atol=1e-9)


def test_counterweight_fields_reach_the_model(tmp_path):
    text = SLIDER + (
        '\n[[counterweights]]\nbody = "crank"\nmass = "2 kg"\nposition = ["-20 mm", "0 mm"]\n'
        'inertia = "1e-4 kg*m^2"\nname = "crank weight"\n'
        '\n[[counterweights]]\nbody = "rod"\nmass = "0.5 kg"\nposition = "A"\n'
    )
    m = _load(tmp_path, text).model
    a, b = m.counterweights
    assert (a.body, a.mass, a.position, a.inertia, a.name) == (
        "crank",
        2.0,
        (-0.02, 0.0),
        1e-4,
        "crank weight",
    )
    assert (b.body, b.mass, b.position, b.inertia, b.name) == ("rod", 0.5, "A", 0.0, "counterweight on rod")
    bare = {x.name: x for x in m.bare_bodies}
    assert m.bodies[m.body_index["crank"]].mass == pytest.approx(bare["crank"].mass + 2.0)
    assert m.bodies[m.body_index["rod"]].mass == pytest.approx(bare["rod"].mass + 0.5)


def _closing_samples() -> str:
    """Radii of an eccentric pitch circle sized to close at the 50 mm of GEARS, as file text."""
    from mechdyn.mechanism import pitch

    unit = pitch.eccentric_circle(1.0, 0.1)
    rho = 0.050 / pitch.closing_centre_distance(unit)
    radii = pitch.eccentric_circle(rho, 0.1 * rho).radius(np.linspace(0, 2 * np.pi, 64, endpoint=False))
    return "[" + ", ".join(f'"{r * 1e3:.12f} mm"' for r in radii) + "]"


@pytest.mark.parametrize(
    "pitch, radius_at_0",
    [
        ('{ kind = "circle", radius = "20 mm" }', 0.020),
        ('{ kind = "eccentric", radius = "closing", eccentricity_ratio = 0.1 }', None),
        ('{ kind = "ellipse", semi_major = "closing", eccentricity_ratio = 0.2 }', None),
        ("samples", None),
    ],
)
def test_pitch_tables_reach_the_gear(tmp_path, pitch, radius_at_0):
    if pitch == "samples":
        pitch = f'{{ kind = "samples", radii = {_closing_samples()} }}'
    text = _sub(GEARS, 'pitch = { kind = "circle", radius = "20 mm" }', f"pitch = {pitch}")
    m = _load(tmp_path, text).model
    mesh = next(j for j in m.joints if isinstance(j, GearJoint))
    r = mesh.curve.radius(np.linspace(0, 2 * np.pi, 9))
    if radius_at_0 is not None:
        assert r[0] == pytest.approx(radius_at_0)
    if "circle" in pitch and "eccentric" not in pitch:
        np.testing.assert_allclose(r, 0.020)
    else:
        assert np.ptp(r) > 1e-3  # noncircular: the eccentricity or the samples took effect
    assert m.gear_laws["mesh"].centre_distance == pytest.approx(0.050)


def test_gear_joint_options_reach_the_model_and_change_the_result(tmp_path):
    text = _sub(
        GEARS,
        'pitch = { kind = "circle", radius = "20 mm" }',
        'pitch = { kind = "circle", radius = "20 mm" }\ncarrier = "ground"\norientation = "10 deg"\n'
        'pressure_angle = "25 deg"\nflank = "fixed"',
    )
    m = _load(tmp_path, text).model
    mesh = next(j for j in m.joints if isinstance(j, GearJoint))
    assert (mesh.name, mesh.bodies, mesh.points, mesh.carrier) == ("mesh", ("g1", "g2"), ("O", "C"), "ground")
    assert mesh.orientation == pytest.approx(math.radians(10))
    assert mesh.pressure_angle == pytest.approx(math.radians(25))
    assert mesh.flank == "fixed" and mesh.internal is False
    # an internal mesh: a ring around gear 1, centre distance r2 − r1
    ring = _sub(GEARS, 'C = ["50 mm", "0 mm"]', 'C = ["10 mm", "0 mm"]')
    ring = _sub(ring, 'D = ["50 mm", "10 mm"]', 'D = ["10 mm", "25 mm"]')
    ring = _sub(ring, 'radius = "20 mm" }', 'radius = "20 mm" }\ninternal = true')
    ring_mesh = next(j for j in _load(tmp_path, ring).model.joints if isinstance(j, GearJoint))
    assert ring_mesh.internal is True


def test_the_flank_option_from_a_file_changes_the_bearing_loads_as_in_python(tmp_path):
    # RP-1's carrier bearing: 103.7 N with the load-following flank, 110.3 N with the published
    # fixed law, from the file exactly as from Python
    from dataclasses import replace

    base = mechdyn.load(EXAMPLES / "transplanter_rp1.toml").model
    text = (
        (EXAMPLES / "transplanter_rp1.toml")
        .read_text()
        .replace('pressure_angle = "20 deg"', 'pressure_angle = "20 deg"\nflank = "fixed"')
    )
    from_file = _load(tmp_path, text).model
    in_python = replace(
        base, joints=tuple(replace(j, flank="fixed") if isinstance(j, GearJoint) else j for j in base.joints)
    )

    def carrier_peak(m):
        d = inverse_dynamics(m, 72)
        return max(d.joint_force_peaks[j.name] for j in m.joints if j.name in ("P1", "P2"))

    assert carrier_peak(from_file) == pytest.approx(carrier_peak(in_python), rel=1e-12)
    assert carrier_peak(from_file) != pytest.approx(carrier_peak(base), rel=1e-3)
