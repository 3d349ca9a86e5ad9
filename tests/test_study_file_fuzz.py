"""Study and materials files, mutated the ways users get them wrong: each mutation is refused with a
message naming the file and the field, or accepted only when it means something (the property test
of tests/test_bad_input.py, extended to the files beside the models)."""

from __future__ import annotations

import copy
import json
import shutil
import tomllib
import warnings
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from conftest import EXAMPLES
from mechdyn.cli.main import main
from mechdyn.errors import MechdynError

STUDIES = sorted((EXAMPLES / "studies").glob("*.toml"))
MATERIALS = Path(__import__("mechdyn.mounts", fromlist=["x"]).__file__).parent / "data" / "materials.toml"
VALUES = (
    -1, 0, 2**40, -(2**40), 1.5, True, "", "abc", "nan", "inf", "±0 %", "1e999 %", "-1e300 N/m", [], ["a"],
    {"x": 1}, "1 furlong", "±10 %",
)  # fmt: skip


def _toml(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float, str)):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, list):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    return "{" + ", ".join(f"{k} = {_toml(v)}" for k, v in value.items()) + "}"


def _dump(data: dict) -> str:
    """TOML of a study or materials file's parsed form (tables, arrays of tables, values)."""
    head, body = [], []
    for k, v in data.items():
        if isinstance(v, dict):
            body += [f"[{k}]", *(f"{kk} = {_toml(vv)}" for kk, vv in v.items())]
        elif isinstance(v, list) and v and all(isinstance(r, dict) for r in v):
            for row in v:
                body += [f"[[{k}]]", *(f"{kk} = {_toml(vv)}" for kk, vv in row.items())]
        else:
            head.append(f"{k} = {_toml(v)}")
    return "\n".join([*head, *body]) + "\n"


def _fields(data: dict) -> list[tuple[str, int | None, str]]:
    out = []
    for table, v in data.items():
        if isinstance(v, dict):
            out += [(table, None, k) for k in v]
        elif isinstance(v, list):
            out += [(table, i, k) for i, row in enumerate(v) if isinstance(row, dict) for k in row]
    return out


def _mutated(data: dict, where: tuple[str, int | None, str], value) -> dict:
    d = copy.deepcopy(data)
    table, i, key = where
    row = d[table] if i is None else d[table][i]
    if value is _DELETE:
        del row[key]
    else:
        row[key] = value
    return d


_DELETE = object()


def _study_outcome(path: Path) -> str:
    from mechdyn.studies import load_studies

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            load_studies(path)
    except MechdynError as exc:
        assert str(path) in str(exc), str(exc)
        return "refused"
    return "loaded"


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_any_mutation_of_a_study_file_loads_or_is_refused_naming_the_file(data, tmp_path):
    work = tmp_path / "ex"
    if not work.exists():
        shutil.copytree(EXAMPLES, work, ignore=shutil.ignore_patterns("gallery"))
    study = data.draw(st.sampled_from(STUDIES), label="study")
    parsed = tomllib.loads(study.read_text())
    where = data.draw(st.sampled_from(_fields(parsed)), label="field")
    value = data.draw(st.sampled_from((*VALUES, _DELETE)), label="value")
    target = work / "studies" / "mutated.toml"
    target.write_text(_dump(_mutated(parsed, where, value)))
    _study_outcome(target)  # no traceback: loaded, or refused naming the file


def _study(tmp_path: Path, text: str) -> Path:
    for f in ("press_on_support.toml", "press_link_drive.toml"):
        (tmp_path / f).write_text((EXAMPLES / f).read_text())
    p = tmp_path / "s.toml"
    p.write_text(text)
    return p


BASE = """
[study]
name = "s"
kind = "{kind}"
model = "press_on_support.toml"
analysis = "support"
{study}

[[parameters]]
path = "support.stiffness"
{parameter}
{more}
[[outputs]]
output = "transmitted_force_range_N"
{tail}
"""


@pytest.mark.parametrize(
    ("kind", "study", "parameter", "more", "tail", "message"),
    [
        ("lhs", "seed = -1", 'range = "±10 %"', "", "", "seed: Input should be greater than or equal to 0"),
        (
            "lhs",
            "seed = 4294967296",
            'range = "±10 %"',
            "",
            "",
            "seed: Input should be less than or equal to",
        ),
        ("lhs", "", 'range = "±0 %"', "", "", "range '±0 %' for 'support.stiffness' is empty"),
        ("lhs", "samples = 1099511627776", 'range = "±10 %"', "", "", "samples: Input should be less than"),
        ("lhs", 'name = ""', 'range = "±10 %"', "", "", "name: String should have at least 1 character"),
        (
            "lhs",
            "",
            'range = "±10 %"',
            '\n[[parameters]]\npath = "support.stiffness"\nrange = "±20 %"\n',
            "",
            "'support.stiffness' is named twice",
        ),
        (
            "lhs",
            "",
            'range = "±10 %"',
            '[[parameters]]\npath = "support.stiffness"\nname = "k"\nrange = "±20 %"\n',
            "",
            "'support.stiffness' is set by more than one parameter",
        ),
        (
            "lhs",
            "options = { cycles = -2 }",
            'range = "±10 %"',
            "",
            "",
            "options → cycles: -2 is below the least",
        ),
        (
            "lhs",
            'options = { cycles = "many" }',
            'range = "±10 %"',
            "",
            "",
            "options → cycles: give a whole number",
        ),
        (
            "lhs",
            "options = { cycles = [1, 2] }",
            'range = "±10 %"',
            "",
            "",
            "options → cycles: give one value",
        ),
        (
            "optimize",
            "",
            'range = "±10 %"',
            "",
            '[[objectives]]\noutput = "displacement_max_m"\n[[constraints]]\noutput = "displacement_max_m"\n'
            'min = "2 mm"\nmax = "1 mm"\n',
            "min '2 mm' must be below max '1 mm'",
        ),
        (
            "optimize",
            "",
            'range = "±10 %"',
            "",
            '[[objectives]]\noutput = "displacement_max_m"\n[[constraints]]\noutput = "displacement_max_m"\n'
            'equals = "1 mm"\ntolerance = "-0.1 mm"\n',
            "tolerance '-0.1 mm' must be above zero",
        ),
        (
            "optimize",
            "",
            'range = "±10 %"',
            "",
            '[[objectives]]\noutput = "displacement_max_m"\n[[constraints]]\noutput = "displacement_max_m"\n'
            'equals = "1 mm"\n',
            "equals '1 mm' needs a tolerance",
        ),
    ],
)
def test_nonsense_once_accepted_in_a_study_file_is_refused(
    tmp_path, kind, study, parameter, more, tail, message
):
    text = BASE.format(kind=kind, study=study, parameter=parameter, more=more, tail=tail)
    if study.startswith("name ="):  # in place of the study's name
        text = text.replace('name = "s"\n', "", 1)
    path = _study(tmp_path, text)
    from mechdyn.studies import load_studies
    from mechdyn.studies.spec import StudyError

    with pytest.raises(StudyError) as info:
        load_studies(path)
    assert str(path) in str(info.value) and message in str(info.value), str(info.value)


def test_boxes_that_are_not_a_list_of_ranges_are_refused(tmp_path, capsys):
    text = (EXAMPLES / "studies" / "press_link_relocation.toml").read_text()
    path = tmp_path / "studies" / "boxes.toml"
    shutil.copytree(EXAMPLES, tmp_path, ignore=shutil.ignore_patterns("gallery"), dirs_exist_ok=True)
    path.write_text(text.replace('boxes = ["±10 %", "±20 %", "±30 %"]', "boxes = 3"))
    assert main(["study", str(path), "--db", str(tmp_path / "r.db")]) == 2
    err = capsys.readouterr().err
    assert "boxes: Input should be a valid list" in err and "Traceback" not in err


# -- materials files --------------------------------------------------------------------------


def _materials_outcome(path: Path) -> str:
    from mechdyn.mounts.materials import default_materials

    try:
        default_materials().with_file(path)
    except MechdynError as exc:
        assert str(path) in str(exc), str(exc)
        return "refused"
    return "loaded"


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_any_mutation_of_a_materials_file_loads_or_is_refused_naming_the_file(data, tmp_path):
    parsed = tomllib.loads(MATERIALS.read_text())
    where = data.draw(st.sampled_from(_fields(parsed)), label="field")
    value = data.draw(
        st.sampled_from((*VALUES, "1e-300 Pa", "-5 kg/m^3", 0.4999, -0.9, _DELETE)), label="value"
    )
    target = tmp_path / "materials.toml"
    target.write_text(_dump(_mutated(parsed, where, value)))
    _materials_outcome(target)


@pytest.mark.parametrize(
    ("field", "value", "message"),
    [
        ("youngs_modulus", '"1e-300 Pa"', "give a Young's modulus of at least 1000 Pa"),
        ("poissons_ratio", "0.4999", "is no Poisson's ratio of a steel"),
        ("poissons_ratio", "-0.9", "is no Poisson's ratio of a steel"),
        ("density", '"-5 kg/m^3"', "give a density between 1 and 25000"),
    ],
)
def test_nonsense_once_accepted_in_a_materials_file_is_refused(tmp_path, field, value, message):
    rows = {
        "name": '"my steel"', "kind": '"steel"', "youngs_modulus": '"200 GPa"', "poissons_ratio": "0.3",
        "density": '"7850 kg/m^3"', "source": '"a test"',
    }  # fmt: skip
    rows[field] = value
    path = tmp_path / "materials.toml"
    path.write_text("[[materials]]\n" + "".join(f"{k} = {v}\n" for k, v in rows.items()))
    from mechdyn.mounts.materials import default_materials

    with pytest.raises(MechdynError) as info:
        default_materials().with_file(path)
    assert str(path) in str(info.value) and field in str(info.value) and message in str(info.value)


def test_a_material_named_twice_in_one_file_is_refused(tmp_path):
    row = (
        '[[materials]]\nname = "m"\nkind = "steel"\nyoungs_modulus = "200 GPa"\n'
        'poissons_ratio = 0.3\nsource = "x"\n'
    )
    path = tmp_path / "materials.toml"
    path.write_text(row + row.replace("200 GPa", "190 GPa"))
    from mechdyn.mounts.materials import default_materials

    with pytest.raises(
        MechdynError, match=r"#2 \(name = 'm'\): the name is given to \[\[materials\]\] #1 too"
    ):
        default_materials().with_file(path)


def test_an_fe_refinement_of_zero_is_refused_at_the_field(tmp_path, capsys):
    anchor = next(p for p in sorted(EXAMPLES.glob("*.toml")) if "[fe]" in p.read_text())
    text = anchor.read_text()
    lines = [
        "refinements = [0, 8]" if ln.strip().startswith("refinements") else ln for ln in text.splitlines()
    ]
    if not any(ln.startswith("refinements") for ln in lines):
        lines = [*(ln + "\nrefinements = [0, 8]" if ln.strip() == "[fe]" else ln for ln in lines)]
    path = tmp_path / anchor.name
    shutil.copytree(
        EXAMPLES, tmp_path, ignore=shutil.ignore_patterns("gallery", "studies"), dirs_exist_ok=True
    )
    path.write_text("\n".join(lines) + "\n")
    assert main(["mount", str(path), "--db", str(tmp_path / "r.db")]) == 2
    err = capsys.readouterr().err
    assert "refinements" in err and "greater than or equal to 1" in err and "Traceback" not in err


def test_user_text_with_dollar_signs_is_drawn_as_written(tmp_path, capsys):
    """A $ in a study's or a parameter's name is a dollar sign, not mathtext (which failed to draw)."""
    path = _study(
        tmp_path,
        BASE.format(kind="oat", study="", parameter='levels = ["-10 %", "10 %"]\nname = "cost $k of $x"',
                    more="", tail="").replace('name = "s"', 'name = "study $1 $of"'),
    )  # fmt: skip
    assert main(["study", str(path), "--db", str(tmp_path / "r.db"), "--plots", str(tmp_path / "p"),
                 "--report", str(tmp_path / "r.html")]) == 0  # fmt: skip
    assert list((tmp_path / "p").glob("*.png")) and "study $1 $of" in (tmp_path / "r.html").read_text()


def test_a_plot_drawn_in_a_notebook_shows_dollar_signs_as_written():
    """Result.plot() (what a notebook shows) draws names with $ signs as written, as saved plots do:
    mathtext read "cost $1 $of" as a formula."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.text import Text

    from mechdyn.drivetrain import Disk, Drivetrain, Shaft, modal

    disks = [Disk("a $x", "1 kg*m^2"), Disk("b", "2 kg*m^2"), Disk("c", "1 kg*m^2")]
    shafts = [Shaft("s", ("a $x", "b"), "1000 N*m/rad"), Shaft("t", ("b", "c"), "1000 N*m/rad")]
    ax = modal(Drivetrain(disks, shafts, name="cost $1 $of")).plot()
    fig = (ax.flat[0] if hasattr(ax, "flat") else ax).figure
    fig.canvas.draw()
    texts = [t for t in fig.findobj(Text) if "$" in t.get_text()]
    plt.close(fig)
    assert any("cost $1 $of" in t.get_text() for t in texts) and any(t.get_text() == "a $x" for t in texts)
    assert not any(t.get_parse_math() for t in texts)
