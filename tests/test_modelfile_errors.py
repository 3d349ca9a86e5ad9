"""Bad model files: each gives a ModelFileError naming the file, the table/field, the value and the fix."""

from __future__ import annotations

import pytest

import mechdyn
from mechdyn.errors import ModelFileError

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
"""


def _write(tmp_path, text):
    p = tmp_path / "model.toml"
    p.write_text(text)
    return p


def test_the_good_file_loads(tmp_path):
    dt = mechdyn.load(_write(tmp_path, GOOD))
    assert dt.disk_names == ("motor", "pinion", "gear")
    assert dt.element("pinion").inertia == pytest.approx(7850 * 0.02 * 3.141592653589793 * 0.04**4 / 32)


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
        "'gearbox' is not a model type; expected one of 'drivetrain'",
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
