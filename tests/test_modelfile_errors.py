"""Bad model files: each gives a ModelFileError naming the file, the table/field, the value and the fix."""

from __future__ import annotations

import math

import numpy as np
import pytest

import mechdyn
from conftest import EXAMPLES
from mechdyn.errors import ModelFileError, ModelWarning

GOOD = """
[model]
type = "drivetrain"
name = "two disks and a mesh"

[material]
density = "7850 kg/m^3"
shear_modulus = "80 GPa"

[[disks]]
name = "motor"
inertia = "1e-3 kg*m^2"

[[disks]]
name = "pinion"
thickness = "20 mm"
outer_diameter = "40 mm"

[[disks]]
name = "gear"
inertia = "5e-3 kg*m^2"

[[shafts]]
name = "input"
disks = ["motor", "pinion"]
diameter = "20 mm"
length = "100 mm"

[[meshes]]
name = "G1"
disks = ["pinion", "gear"]
teeth = [20, 60]
base_radii = ["18.8 mm", "56.4 mm"]
stiffness = "1.5e9 N/m"

[[ground_springs]]
name = "motor stiffness"
disk = "motor"
stiffness = "2 kN*m/rad"

[[ground_dampers]]
name = "bearing drag"
disk = "gear"
damping = "0.01 N*m*s/rad"

[response]
excitation = [{ disk = "motor", amplitude = "1 N*m" }]
frequency_range = ["10 Hz", "2 kHz"]

[response.rayleigh]
alpha = "2 1/s"
beta = "1e-6 s"
"""


def _write(tmp_path, text):
    p = tmp_path / "model.toml"
    p.write_text(text)
    return p


def test_the_good_file_loads(tmp_path):
    from mechdyn.drivetrain.response import RayleighDamping
    from mechdyn.gear_dynamics.file import settings
    from mechdyn.io import read

    path = _write(tmp_path, GOOD)
    dt = mechdyn.load(path).model
    assert dt.disk_names == ("motor", "pinion", "gear")
    assert dt.element("pinion").inertia == pytest.approx(7850 * 0.02 * 3.141592653589793 * 0.04**4 / 32)
    assert dt.element("input").stiffness == pytest.approx(80e9 * 3.141592653589793 * 0.02**4 / (32 * 0.1))
    assert dt.element("motor stiffness").stiffness == 2000.0
    assert dt.element("bearing drag").damping == 0.01
    read_back = settings(read(path), dt)
    campbell_settings, response = read_back.campbell, read_back.response
    assert campbell_settings is None and read_back.dynamics is None
    assert response.damping == RayleighDamping(2.0, 1e-6)
    assert response.frequency_range == (10.0, 2000.0)


CASES = [
    # (old text, new text, location fragment, message fragment)
    ('inertia = "1e-3 kg*m^2"', 'inertia = "1e-3"', "[[disks]] #1 (name = 'motor') → inertia", "has no unit"),
    (
        'inertia = "1e-3 kg*m^2"',
        'inertia = "1e-3 N*m"',
        "inertia",
        "expected a quantity of [mass] * [length] ** 2",
    ),
    (
        'inertia = "1e-3 kg*m^2"',
        'inertia = "-1e-3 kg*m^2"',
        "[[disks]] #1 (name = 'motor') → inertia",
        "must be positive",
    ),
    ('inertia = "1e-3 kg*m^2"', "inertia = 0.001", "inertia", "has no unit"),
    (
        'inertia = "1e-3 kg*m^2"',
        'intertia = "1e-3 kg*m^2"',
        "[[disks]] #1 (name = 'motor') → intertia",
        "did you mean 'inertia'",
    ),
    (
        'disks = ["motor", "pinion"]',
        'disks = ["motor", "pinon"]',
        "[[shafts]] #1 (name = 'input') → disks",
        "disk 'pinon', which is not defined",
    ),
    (
        'disks = ["motor", "pinion"]',
        'disks = ["motor"]',
        "[[shafts]] #1 (name = 'input') → disks → item 2",
        "required field is missing",
    ),
    (
        'length = "100 mm"',
        'length = "-100 mm"',
        "[[shafts]] #1 (name = 'input') → length",
        "must be positive",
    ),
    ('length = "100 mm"', "", "[[shafts]] #1 (name = 'input')", "give stiffness, or length and diameter"),
    (
        'stiffness = "1.5e9 N/m"',
        'stiffness = "1.5e9 N*m/rad"',
        "[[meshes]] #1 (name = 'G1') → stiffness",
        "expected a quantity of [mass] / [time] ** 2",
    ),
    (
        'base_radii = ["18.8 mm", "56.4 mm"]\n',
        "",
        "[[meshes]] #1 (name = 'G1') → base_radii",
        "needs base_radii",
    ),
    (
        "teeth = [20, 60]",
        "teeth = [20, 60]\nratio = 2",
        "[[meshes]] #1 (name = 'G1') → ratio",
        "disagrees with the teeth ratio",
    ),
    (
        "teeth = [20, 60]",
        "teeth = [20.5, 60]",
        "[[meshes]] #1 (name = 'G1') → teeth → item 1",
        "valid integer",
    ),
    ('name = "gear"', 'name = "motor"', "", "used twice"),
    (
        'type = "drivetrain"',
        'type = "gearbox"',
        "[model] → type",
        "'gearbox' is not a model type; expected one of 'drive', 'drivetrain'",
    ),
    (
        'density = "7850 kg/m^3"\n',
        "",
        "[[disks]] #2 (name = 'pinion') → density",
        "give it here or in [material]",
    ),
    (
        'thickness = "20 mm"',
        'thickness = "20 mm"\ninertia = "1 kg*m^2"',
        "[[disks]] #2 (name = 'pinion')",
        "not both",
    ),
    (
        'name = "G1"',
        'name = "G1"\nkind = "bevel"',
        "[[meshes]] #1 (name = 'G1') → kind",
        "'external' or 'internal'",
    ),
    ("[model]", "[modle]", "[model]", "missing"),
    ('shear_modulus = "80 GPa"', 'shear_modulus = "80 GPa', "", "not valid TOML"),
]


@pytest.mark.parametrize(
    ("old", "new", "where", "what"), CASES, ids=[f"{i}-{c[3][:30] or c[2][:30]}" for i, c in enumerate(CASES)]
)
def test_bad_file_gives_a_named_error(tmp_path, old, new, where, what):
    assert old in GOOD
    path = _write(tmp_path, GOOD.replace(old, new, 1))
    with pytest.raises(ModelFileError) as info:
        mechdyn.load(path)
    err = info.value
    text = str(err)
    assert text.startswith(str(path))
    assert where in err.location
    assert what in text


def test_missing_file_is_named(tmp_path):
    with pytest.raises(ModelFileError, match="no such file"):
        mechdyn.load(tmp_path / "nope.toml")


def test_ratio_disagreement_warns_and_names_the_mesh(tmp_path):
    path = _write(tmp_path, GOOD.replace('"56.4 mm"', '"60 mm"'))
    with pytest.warns(
        mechdyn.ModelWarning,
        match=r"\[\[meshes\]\] #1 \(name = 'G1'\).*ratio 3 \(from the teeth\) but the base radii give 3.191",
    ):
        mechdyn.load(path)


def test_published_turret_ratios_warn(tmp_path):
    from conftest import EXAMPLES

    with pytest.warns(mechdyn.ModelWarning) as record:
        mechdyn.load(EXAMPLES / "turret_indexing.toml")
    messages = [str(w.message) for w in record]
    assert any("ratio 4 " in m and "4.317" in m for m in messages)
    assert any("ratio 6 " in m and "6.588" in m for m in messages)


def test_response_settings_are_checked_against_the_disks(tmp_path):
    from mechdyn.gear_dynamics.file import settings
    from mechdyn.io import read

    path = _write(tmp_path, GOOD.replace('excitation = [{ disk = "motor"', 'excitation = [{ disk = "motr"'))
    with pytest.raises(ModelFileError, match=r"\[response\] → excitation #1 → disk: 'motr' is not a disk"):
        settings(read(path), mechdyn.load(path).model)
    path = _write(tmp_path, GOOD.replace("[response.rayleigh]", "modal_damping = 0.02\n[response.rayleigh]"))
    with pytest.raises(ModelFileError, match="give modal_damping or"):
        mechdyn.load(path)


@pytest.mark.parametrize("teeth", [("20", "60"), (20.5, 60), (0, 60), (20,)])
def test_bad_teeth_in_python_are_named(teeth):
    from mechdyn.drivetrain import GearMesh

    with pytest.raises(mechdyn.ModelError, match="element 'G', field 'teeth'"):
        GearMesh("G", ("a", "b"), teeth=teeth)


GEARED = GOOD.replace(
    """[[meshes]]
name = "G1"
disks = ["pinion", "gear"]
teeth = [20, 60]
base_radii = ["18.8 mm", "56.4 mm"]
stiffness = "1.5e9 N/m"
""",
    """[[gear_pairs]]
name = "P1"
pinion = { teeth = 20, module = "2 mm", face_width = "20 mm", bore_diameter = "15 mm" }
gear = { teeth = 60, module = "2 mm", face_width = "20 mm", bore_diameter = "40 mm" }

[[meshes]]
name = "G1"
disks = ["pinion", "gear"]
gear_pair = "P1"
""",
)


@pytest.mark.filterwarnings("ignore:.*range of the Sainsot fit:mechdyn.errors.ModelWarning")
def test_mesh_from_a_gear_pair_table(tmp_path):
    # (its 20-tooth pinion's foundation is extrapolated, and says so: tests/test_gears.py checks that)
    dt = mechdyn.load(_write(tmp_path, GEARED)).model
    mesh = dt.element("G1")
    assert mesh.teeth == (20, 60) and mesh.stiffness > 1e8
    assert mesh.base_radii[0] == pytest.approx(0.02 * math.cos(math.radians(20)))
    # without a bore the foundation takes half the root diameter, and the file's location says so
    no_bore = GEARED.replace(', bore_diameter = "15 mm"', "")
    with pytest.warns(ModelWarning, match=r"\[\[gear_pairs\]\] #1 \(name = 'P1'\): pinion: no bore_diameter"):
        mechdyn.load(_write(tmp_path, no_bore))


@pytest.mark.parametrize(
    ("old", "new", "where", "what"),
    [
        (
            'gear_pair = "P1"',
            'gear_pair = "P2"',
            "[[meshes]] #1 (name = 'G1') → gear_pair",
            "'P2' is not a [[gear_pairs]] name",
        ),
        (
            'gear_pair = "P1"',
            'gear_pair = "P1"\nstiffness = "1e9 N/m"',
            "[[meshes]] #1 (name = 'G1')",
            "remove stiffness",
        ),
        (
            'gear = { teeth = 60, module = "2 mm"',
            'gear = { teeth = 60, module = "3 mm"',
            "[[gear_pairs]] #1 (name = 'P1')",
            "share module",
        ),
        (
            "pinion = { teeth = 20,",
            "pinion = { teeth = 20, profile_shift = 3,",
            "[[gear_pairs]] #1 (name = 'P1') → pinion",
            "pointed",
        ),
    ],
)
def test_bad_gear_pair_tables_are_named(tmp_path, old, new, where, what):
    path = _write(tmp_path, GEARED.replace(old, new, 1))
    with pytest.raises(ModelFileError) as info:
        mechdyn.load(path)
    assert where in info.value.location and what in str(info.value)


@pytest.mark.parametrize(
    ("old", "new", "where", "what"),
    [
        (
            'root_thickness = "3.073 mm"',
            'root_thickness = "2.5 mm"',
            "[pinion] → tip_thickness",
            "must be smaller than the root thickness",
        ),
        ('load_height = "2.275 mm"', 'load_height = "5 mm"', "[pinion] → load_height", "outside the tooth"),
        ('face_width = "50 mm"', 'face_width = "-50 mm"', "[pinion] → face_width", "must be positive"),
        ("poisson_ratio = 0.3", "poisson_ratio = 0.5", "[material] → poisson_ratio", "less than 0.5"),
    ],
)
def test_bad_tooth_pair_files_are_named(tmp_path, old, new, where, what):
    from conftest import EXAMPLES

    text = (EXAMPLES / "tooth_pair1_published.toml").read_text()
    assert old in text
    path = _write(tmp_path, text.replace(old, new, 1))
    with pytest.raises(ModelFileError) as info:
        mechdyn.load(path)
    assert where in info.value.location and what in str(info.value)


@pytest.mark.parametrize(
    ("old", "new", "where", "what"),
    [
        ('speed = "100 rad/s"', 'speed = "100 m/s"', "[driver] → speed", "expected a quantity of 1 / [time]"),
        ('axis = "0 deg"\n', "", "[[joints]] #4 (name = 'guide')", "needs its sliding axis"),
        (
            'point = "A"\n\n[[joints]]\nname = "B"',
            'point = "Z"\n\n[[joints]]\nname = "B"',
            "[[joints]] #2 (name = 'A')",
            "'Z' is not in the drawing",
        ),
        (
            'type = "prismatic"',
            'type = "spherical"',
            "[[joints]] #4 (name = 'guide') → type",
            "'revolute', 'prismatic' or 'gear'",
        ),
        ('mass = "5 kg"', 'mass = "-5 kg"', "[[bodies]] #3 (name = 'slider') → mass", "must not be negative"),
        ('B = ["0.5 m", "0 m"]', 'B = ["0.5 m"]', "[points] → B → item 2", "required field is missing"),
    ],
)
def test_bad_mechanism_files_are_named(tmp_path, old, new, where, what):
    from conftest import EXAMPLES

    text = (EXAMPLES / "slider_crank.toml").read_text()
    assert old in text
    path = _write(tmp_path, text.replace(old, new, 1))
    with pytest.raises(ModelFileError) as info:
        mechdyn.load(path)
    assert where in info.value.location and what in str(info.value)


def test_process_force_tables(tmp_path):
    from conftest import EXAMPLES
    from mechdyn.mechanism.dynamics import inverse_dynamics

    text = (
        (EXAMPLES / "slider_crank.toml").read_text()
        + """
[[process_forces]]
body = "slider"
point = "B"
direction = "180 deg"
versus = "angle"
table = [["0 deg", "0 kN"], ["90 deg", "2 kN"], ["180 deg", "0 kN"]]
"""
    )
    spec = mechdyn.load(_write(tmp_path, text))
    d = inverse_dynamics(spec.model, 8)
    assert d.applied[2, 6] == pytest.approx(-2000.0)  # at 90°, 2 kN along −x on the slider
    assert np.abs(d.power_balance_residual).max() < 1e-9 * np.abs(d.driving_torque).max() * 100
    bad = text.replace('["90 deg", "2 kN"], ["180 deg"', '["190 deg", "2 kN"], ["180 deg"')
    with pytest.raises(ModelFileError, match=r"\[\[process_forces\]\] #1: table angle values must increase"):
        mechdyn.load(_write(tmp_path, bad))


def test_speed_profile_table(tmp_path):
    from conftest import EXAMPLES
    from mechdyn.mechanism.dynamics import inverse_dynamics

    text = (
        (EXAMPLES / "slider_crank.toml")
        .read_text()
        .replace(
            'speed = "100 rad/s"',
            'speed = "100 rad/s"\nspeed_profile = [["0 deg", "100 rad/s"], ["90 deg", "120 rad/s"], '
            '["180 deg", "100 rad/s"], ["270 deg", "80 rad/s"]]',
        )
    )
    spec = mechdyn.load(_write(tmp_path, text))
    d = inverse_dynamics(spec.model, 72)
    assert d.crank_speed.min() < 95 and d.crank_speed.max() > 105
    assert np.abs(d.power_balance_residual).max() < 1e-9 * np.abs(d.driving_torque * d.crank_speed).max()
    bad = text.replace('["0 deg", "100 rad/s"], ', "")
    with pytest.raises(ModelFileError, match=r"\[driver\]: speed_profile angles must start at 0 deg"):
        mechdyn.load(_write(tmp_path, bad))


def test_a_model_file_error_lists_every_problem_of_the_file(tmp_path, capsys):
    """Three problems in three tables: all three named, each with its field and value (a misspelt
    field without the "missing" error of the field it stands for)."""
    from mechdyn.cli.main import main

    text = (EXAMPLES / "press_on_support.toml").read_text()
    text = text.replace('mass = "600 t"', 'mas = "600 t"').replace('"4.5e8 N/m"', '"4.5e8 N"')
    text = text.replace("damping_ratio = 0.05", 'damping_ratio = "x"')
    bad = tmp_path / "bad.toml"
    bad.write_text(text)
    (tmp_path / "press_link_drive.toml").write_text((EXAMPLES / "press_link_drive.toml").read_text())
    assert main(["support", str(bad)]) == 2
    err = capsys.readouterr().err
    assert f"{bad}: 3 problems:" in err
    assert "[machine] → mas: unknown field 'mas'; did you mean 'mass'?" in err
    assert "[support] → stiffness: '4.5e8 N' is in N" in err and "e.g. '4.5e+08 N/m'" in err
    assert "[support] → damping_ratio: cannot read 'x'" in err and "a plain number" in err
    assert "missing" not in err and "Traceback" not in err
