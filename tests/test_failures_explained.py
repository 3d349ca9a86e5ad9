"""Failures explained where they happen (issue 44, item 5): a study whose variants all fail exits
non-zero with its reasons grouped and counted, one where some fail says how many and why; a study's
counts add up on a rerun; a pad's Shore A hardness and its material's class are checked before any
work (in the model file and in a study that varies them); every problem of a model file is listed at
once, value checks among them."""

from __future__ import annotations

import json
import re
import textwrap
from pathlib import Path

import pytest

import mechdyn
from conftest import EXAMPLES
from mechdyn.cli.main import main
from mechdyn.errors import ModelError, ModelFileError
from mechdyn.store import ResultStore
from mechdyn.studies import StudyError, load_study
from mechdyn.studies.storage import StudyStore

# the four-bar with its rocker pivot B moved 5 m out: the loop does not close at any crank angle
FAR_B = ('B = ["194.608480 mm"', 'B = ["5000 mm"')

PAD = """
[model]
type = "mount"
name = "pad"

[pad]
shore_a = 60
length = "300 mm"
width = "300 mm"
thickness = "30 mm"
"""

MACHINE = """
[model]
type = "support"
name = "machine on two pads"

[machine]
mass = "2 t"
inertia = ["500 kg*m^2", "500 kg*m^2", "500 kg*m^2"]

[[mounts]]
name = "left"
position = ["-1 m", "0 m", "0 m"]
mount = "pad.toml"

[[mounts]]
name = "right"
position = ["1 m", "0 m", "0 m"]
mount = "pad.toml"
"""


def _files(tmp_path: Path, study: str, fourbar: str | None = None) -> Path:
    """A study file beside a copy of the four-bar (edited when ``fourbar`` is given)."""
    (tmp_path / "fourbar.toml").write_text(fourbar or (EXAMPLES / "fourbar.toml").read_text())
    path = tmp_path / "study.toml"
    path.write_text(textwrap.dedent(study))
    return path


def _pads(tmp_path: Path, study: str) -> Path:
    (tmp_path / "pad.toml").write_text(PAD)
    (tmp_path / "machine.toml").write_text(MACHINE)
    path = tmp_path / "study.toml"
    path.write_text(textwrap.dedent(study))
    return path


def _stored(db: str, name: str) -> int:
    with ResultStore(db) as store:
        return len(StudyStore(store).variants(name))


# -- a study whose variants fail ---------------------------------------------------------------


def test_a_study_whose_every_variant_fails_exits_non_zero_with_the_reasons_grouped_and_counted(
    tmp_path, capsys
):
    """Five variants (the base design among them) fail for two reasons: the loop does not close (3)
    and the crank does not turn (2). The command exits 1, says so with both reasons counted, shows no
    output "range" (it would be nothing), and the five variants stay stored with their errors."""
    text = (EXAMPLES / "fourbar.toml").read_text()
    assert FAR_B[0] in text
    path = _files(
        tmp_path,
        """
        [study]
        name = "nothing-turns"
        kind = "factorial"
        model = "fourbar.toml"
        analysis = "mechanism"
        options = { angles = 36 }

        [[parameters]]
        path = "points.B.x"
        levels = ["3000 mm", "6000 mm"]

        [[parameters]]
        path = "driver.speed"
        levels = ["0 rad/s", "12 rad/s"]

        [[outputs]]
        output = "driving_torque_peak_Nm"
        """,
        text.replace(*FAR_B),
    )
    db = str(tmp_path / "r.db")
    assert main(["study", str(path), "--db", db]) == 1
    out, err = capsys.readouterr()
    assert str(path) in err
    assert "5 of 5 variants failed: 3 × 'cannot assemble at crank angle …° (…° turned" in err, err
    assert ", 2 × '" in err and "[driver] → speed: … rad/s must not be zero" in err  # grouped: any angle
    assert "why variants failed" in out and "lowest" not in out  # no "range" of nothing
    assert _stored(db, "nothing-turns") == 5  # what was computed stays stored, errors with it
    # --json: the same counts and reasons, and the same exit status
    assert main(["study", str(path), "--db", db, "--json"]) == 1
    doc = json.loads(capsys.readouterr().out)
    assert doc["every_variant_failed"] is True
    assert [f["count"] for f in doc["failures"]] == [3, 2]
    assert doc["failures"][0]["reason"].startswith("cannot assemble at crank angle …°")
    assert "fourbar.toml: [driver] → speed: … rad/s must not be zero" in doc["failures"][1]["reason"]


def test_a_study_whose_variants_fail_but_the_base_design_says_so_and_exits_non_zero(tmp_path, capsys):
    """Only the base design evaluates: its outputs are no range; the command says every variant but
    the base failed, and why."""
    path = _files(
        tmp_path,
        """
        [study]
        name = "only-the-base"
        kind = "lhs"
        model = "fourbar.toml"
        analysis = "mechanism"
        samples = 6
        options = { angles = 36 }

        [[parameters]]
        path = "points.B.x"
        range = ["3000 mm", "9000 mm"]

        [[outputs]]
        output = "driving_torque_peak_Nm"
        """,
    )
    assert main(["study", str(path), "--db", str(tmp_path / "r.db")]) == 1
    err = capsys.readouterr().err
    assert "6 of 7 variants failed, every one but the base design: 6 × 'cannot assemble" in err, err


def test_a_study_where_some_variants_fail_goes_on_and_says_how_many_and_why(tmp_path, capsys):
    path = _files(
        tmp_path,
        """
        [study]
        name = "some-fail"
        kind = "oat"
        model = "fourbar.toml"
        analysis = "mechanism"
        options = { angles = 36 }

        [[parameters]]
        path = "points.B.x"
        levels = ["5 %", "3900 %", "4000 %"]

        [[outputs]]
        output = "driving_torque_peak_Nm"
        """,
    )
    db = str(tmp_path / "r.db")
    assert main(["study", str(path), "--db", db, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert (doc["variants"], doc["failed"], doc["every_variant_failed"]) == (4, 2, False)
    (group,) = doc["failures"]
    assert group["count"] == 2 and group["reason"].startswith("cannot assemble at crank angle …°")
    assert len(group["variants"]) == 2 and "does not close" in group["example"]
    assert main(["study", str(path), "--db", db]) == 0
    out = capsys.readouterr().out
    assert "some-fail: why variants failed" in out and "2 of 4 variants failed" in out


# -- counts that add up ------------------------------------------------------------------------


def test_a_rerun_counts_every_variant_once_as_reused_and_the_json_counts_as_the_table(tmp_path, capsys):
    """A factorial whose base design is a point of its grid: 4 designs, listed 5 times. The JSON's
    ``variants`` is the table's (each design once, the base among them), and evaluated + reused is
    that number on the first run and on the rerun."""
    path = _files(
        tmp_path,
        """
        [study]
        name = "base-in-grid"
        kind = "factorial"
        model = "fourbar.toml"
        analysis = "mechanism"
        options = { angles = 36 }

        [[parameters]]
        path = "points.B.x"
        levels = ["0 %", "5 %"]

        [[parameters]]
        path = "bodies.coupler.mass"
        levels = ["0 %", "10 %"]

        [[outputs]]
        output = "driving_torque_peak_Nm"
        """,
    )
    db = str(tmp_path / "r.db")
    runs = []
    for _ in range(2):
        assert main(["study", str(path), "--db", db, "--json"]) == 0
        runs.append(json.loads(capsys.readouterr().out))
    first, again = runs
    assert (first["variants"], first["evaluated"], first["reused"], first["failed"]) == (4, 4, 0, 0)
    assert (again["variants"], again["evaluated"], again["reused"], again["failed"]) == (4, 0, 4, 0)
    assert main(["study", str(path), "--db", db]) == 0
    out = capsys.readouterr().out
    assert re.search(r"base-in-grid: variants\n.*\n.*\n4\s+0\s+4\s+0\n", out), out
    assert _stored(db, "base-in-grid") == 4


# -- a pad's hardness and material, checked before any work ------------------------------------


def test_a_pad_file_lists_a_shore_a_hardness_of_80_with_its_other_problems(tmp_path):
    path = tmp_path / "pad.toml"
    path.write_text(PAD.replace("shore_a = 60", "shore_a = 80").replace('"30 mm"', '"-30 mm"'))
    with pytest.raises(ModelFileError) as info:
        mechdyn.load(path)
    problems = dict(info.value.problems)
    assert set(problems) == {"[pad] → shore_a", "[pad] → thickness"}, problems
    assert (
        "80 is out of range; give a finite Shore A hardness between 30 and 75" in problems["[pad] → shore_a"]
    )
    assert "material" in problems["[pad] → shore_a"]  # the other way to name a rubber
    assert str(path) in str(info.value)
    # the bounds are those of the shipped table
    from mechdyn.mounts.materials import default_materials
    from mechdyn.mounts.schema import SHORE_A_TABLE

    rubbers = [m.shore_a for m in default_materials().materials.values() if m.kind == "rubber"]
    assert (min(rubbers), max(rubbers)) == SHORE_A_TABLE


@pytest.mark.parametrize(
    ("parameter", "shown"),
    [
        ('range = ["50", "80"]', "the high end of its range, 80"),
        ('range = "±40 %"', "the high end of its range, 84"),  # 36 to 84: its low end is in the table
        ("levels = [50, 80]", "a level, 80"),
    ],
)
def test_a_study_whose_hardness_leaves_the_table_is_refused_when_read(tmp_path, capsys, parameter, shown):
    body = f"""
        [study]
        name = "harder"
        kind = "lhs"
        model = "machine.toml"
        analysis = "support"

        [[parameters]]
        path = "mounts.left.mount.pad.shore_a"
        {parameter}

        [[outputs]]
        output = "natural_frequencies_hz.1"
        """
    path = _pads(tmp_path, body.replace('"lhs"', '"oat"') if "levels" in parameter else body)
    with pytest.raises(StudyError) as info:
        load_study(path)
    text = str(info.value)
    for part in (str(path), "'mounts.left.mount.pad.shore_a'", shown, "between 30 and 75", "pad.toml"):
        assert part in text, (part, text)
    db = tmp_path / "r.db"
    assert main(["study", str(path), "--db", str(db)]) == 2  # refused before any variant is run
    assert "between 30 and 75" in capsys.readouterr().err
    assert not db.exists()


@pytest.mark.parametrize(("material", "kind"), [("steel", "a steel"), ("concrete C25/30", "concrete")])
def test_an_elastomer_pad_refuses_a_material_that_is_no_elastomer(tmp_path, material, kind):
    path = tmp_path / "pad.toml"
    path.write_text(PAD.replace("shore_a = 60", f'material = "{material}"'))
    with pytest.raises(ModelFileError) as info:
        mechdyn.load(path)
    assert info.value.location == "[pad] → material"
    text = str(info.value)
    assert f"{material!r} is {kind}, not an elastomer" in text, text
    assert "'rubber shore 30'" in text and "'rubber shore 75'" in text  # the elastomers there are
    # a damping pad is a pad too, and so is the Python API's
    path.write_text(PAD.replace("[pad]", "[damping_pad]").replace("shore_a = 60", f'material = "{material}"'))
    with pytest.raises(ModelFileError, match="not an elastomer"):
        mechdyn.load(path)
    from mechdyn.mounts import ElastomerPad, default_materials

    with pytest.raises(ModelError, match=r"element 'p', field 'material'.*not an elastomer"):
        ElastomerPad("p", default_materials()[material], "30 mm", diameter="300 mm")


def test_a_study_cannot_make_a_pad_of_steel(tmp_path):
    path = _pads(
        tmp_path,
        """
        [study]
        name = "steel-pad"
        kind = "oat"
        model = "machine.toml"
        analysis = "support"

        [[parameters]]
        path = "mounts.left.mount.pad.material"
        levels = ["rubber shore 50", "steel"]

        [[outputs]]
        output = "natural_frequencies_hz.1"
        """,
    )
    (tmp_path / "pad.toml").write_text(PAD.replace("shore_a = 60", 'material = "rubber shore 60"'))
    with pytest.raises(
        StudyError, match=r'level .steel. of .* is not a rubber the model accepts.*"rubber shore 30"'
    ):
        load_study(path)


# -- every problem of a model file at once -----------------------------------------------------


def test_a_drivetrain_file_lists_a_negative_inertia_beside_its_other_problems(tmp_path):
    text = (EXAMPLES / "turret_indexing.toml").read_text()
    edits = [
        ('inertia = "0.02875616e-3 kg*m^2"', 'inertia = "-0.02875616e-3 kg*m^2"'),
        ('stiffness = "0.95131987e6 N*m/rad"', 'stiffness = "0.95131987e6 N/m"'),
    ]
    for old, new in edits:
        assert text.count(old) == 1
        text = text.replace(old, new)
    path = tmp_path / "turret.toml"
    path.write_text(text)
    with pytest.raises(ModelFileError) as info:
        mechdyn.load(path)
    problems = dict(info.value.problems)
    assert problems["[[disks]] #2 (name = '2') → inertia"].startswith(
        "-2.87562e-05 kg*m^2 must be positive; give a finite inertia between 1e-18 and 1e+10 kg*m^2"
    )
    assert (
        "expected a quantity of [mass] * [length] ** 2"
        in problems["[[shafts]] #2 (name = 'shaft 2') → stiffness"]
    )
    assert str(info.value).startswith(f"{path}: 2 problems:")


def test_a_mechanism_file_lists_every_negative_mass_and_inertia(tmp_path):
    text = (EXAMPLES / "fourbar.toml").read_text()
    text = text.replace('mass = "1.2 kg"', 'mass = "-1.2 kg"').replace(
        'inertia = "1.6875e-3 kg*m^2"', 'inertia = "-1.6875e-3 kg*m^2"'
    )
    path = tmp_path / "fourbar.toml"
    path.write_text(text)
    with pytest.raises(ModelFileError) as info:
        mechdyn.load(path)
    mass = "-1.2 kg must not be negative; give a finite mass between 0 and 1e+08 kg"
    inertia = "-0.0016875 kg*m^2 must not be negative; give a finite inertia between 0 and 1e+10 kg*m^2"
    assert dict(info.value.problems) == {
        "[[bodies]] #2 (name = 'coupler') → mass": mass,
        "[[bodies]] #3 (name = 'rocker') → inertia": inertia,
    }
