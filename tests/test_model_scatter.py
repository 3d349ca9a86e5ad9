"""A model file carries the scatter of its own values (issue 46, point 1): ``[[scatter]]`` rows (a
study's path and a study parameter's ``scatter`` table) and ``[[correlations]]``, in every model file
type. The loaded model exposes them as an :class:`~mechdyn.uncertainty.InputSpace` equal to the same
rows written in a tolerance study; a tolerance study takes them as its default (its own parameters
override them, and with none it samples them: the same samples and probabilities, exactly); every
analysis ignores them; :func:`mechdyn.save` keeps them; bad rows are refused naming the file, the row
and field, the value and the fix."""

from __future__ import annotations

import json
import math
import re
import shutil
import tomllib
import warnings
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import mechdyn
from conftest import EXAMPLES
from mechdyn.errors import ModelFileError, ModelWarning
from mechdyn.studies import StudyError, load_study, run_study
from mechdyn.studies.kinds import kind
from mechdyn.studies.kinds.tolerance import space

MODEL = EXAMPLES / "press_on_support.toml"
WRITTEN = EXAMPLES / "studies" / "press_support_tolerance.toml"  # the rows in its [[parameters]]
FROM_MODEL = EXAMPLES / "studies" / "press_support_tolerance_from_model.toml"  # no [[parameters]]
HEADER = "# How the support scatters"


def _without_scatter(text: str) -> str:
    """The example's text without its scatter (the comment above the rows and the rows)."""
    head, found, _ = text.partition(HEADER)
    assert found, "the example gives its scatter under its comment"
    return head.rstrip() + "\n"


@pytest.fixture
def files(tmp_path: Path) -> Path:
    """A copy of the press on its support (with its mechanism) to change."""
    for name in ("press_on_support.toml", "press_link_drive.toml"):
        shutil.copy(EXAMPLES / name, tmp_path / name)
    return tmp_path


def _study(folder: Path, rows: str = "", correlations: str = "", samples: int = 64) -> Path:
    text = (
        f'[study]\nname = "s"\nkind = "tolerance"\nmodel = "press_on_support.toml"\nanalysis = "support"\n'
        f'samples = {samples}\nmethod = "qmc"\nseed = 3\n{rows}\n'
        '[[outputs]]\noutput = "displacement_max_m"\nlimit = "1.3 mm"\n'
        f"{correlations}"
    )
    path = folder / "study.toml"
    path.write_text(text)
    return path


# -- the file's scatter as an input space -------------------------------------------------------------


def test_the_file_scatter_is_the_input_space_the_same_rows_make_in_a_study():
    """Support stiffness lognormal (median the model's 4.5e8 N/m, cov 0.15) and damping ratio uniform
    on [0.03, 0.07]: the file's space equals the study's, variable by variable, and its moments are
    the closed forms (lognormal mean = median·√(1 + cov²), std = mean·cov; uniform (a + b)/2 and
    (b − a)/√12)."""
    scatter = mechdyn.load(MODEL).scatter
    from_file, written = scatter.space, space(load_study(WRITTEN))
    assert from_file.names == written.names == ["support stiffness", "damping ratio"]
    assert from_file.units == written.units == ["N/m", ""]
    for a, b in zip(from_file.variables, written.variables, strict=True):
        assert (a.kind, a.parameters, a.mean, a.std) == (b.kind, b.parameters, b.mean, b.std)
    assert np.array_equal(from_file.R, written.R) and from_file.independent
    k, zeta = from_file.variables
    assert k.mean == pytest.approx(4.5e8 * math.sqrt(1 + 0.15**2), rel=1e-12)
    assert k.std == pytest.approx(k.mean * 0.15, rel=1e-12)
    assert zeta.mean == pytest.approx(0.05, rel=1e-12)
    assert zeta.std == pytest.approx(0.04 / math.sqrt(12), rel=1e-12)
    assert [row.path for row in scatter.rows] == ["support.stiffness", "support.damping_ratio"]


def test_a_tolerance_class_levels_and_truncation_read_as_a_study_reads_them(files):
    """A tolerance class keeps its source; a truncated normal and discrete levels are the variables
    :func:`mechdyn.uncertainty.variable_from_dict` makes of the same table (the model's value the
    nominal)."""
    from mechdyn.uncertainty import variable_from_dict

    text = _without_scatter((files / "press_on_support.toml").read_text()) + (
        '\n[[scatter]]\npath = "support.stiffness"\ntolerance = "soil_stiffness"\n'
        '\n[[scatter]]\npath = "machine.mass"\ndistribution = "normal"\nstd = "20 t"\nlower = "570 t"\n'
        '\n[[scatter]]\npath = "support.damping_ratio"\ndistribution = "levels"\nvalues = [0.03, 0.05]\n'
        "probabilities = [0.25, 0.75]\n"
    )
    (files / "press_on_support.toml").write_text(text)
    soil, mass, zeta = mechdyn.load(files / "press_on_support.toml").scatter.variables
    assert "Phoon & Kulhawy" in soil.source and soil.kind == "lognormal"
    assert soil.parameters["cov"] == pytest.approx(0.35) and soil.parameters["median"] == 4.5e8
    expected = variable_from_dict(
        "machine.mass", {"std": "20 t", "lower": "570 t", "distribution": "normal"}, "kg", nominal=6e5
    )
    assert (mass.kind, mass.parameters, mass.mean) == (expected.kind, expected.parameters, expected.mean)
    assert mass.mean > 6e5  # truncated below only: the mean moves up
    assert not zeta.continuous and zeta.mean == pytest.approx(0.25 * 0.03 + 0.75 * 0.05, rel=1e-12)


# -- the tolerance study takes it as its default --------------------------------------------------------


def test_a_study_without_parameters_equals_the_study_that_writes_the_rows_exactly(tmp_path):
    """The shipped pair: the same samples, bit for bit, and the same findings (distributions,
    probabilities and their intervals, rankings), exactly."""
    a, b = load_study(FROM_MODEL), load_study(WRITTEN)
    assert [p.name for p in a.parameters] == [p.name for p in b.parameters]
    assert [p.locations for p in a.parameters] == [p.locations for p in b.parameters]
    tolerance = kind("tolerance")
    assert np.array_equal(tolerance.design(a), tolerance.design(b))
    ra = run_study(replace(a.quick(64), method="qmc"), str(tmp_path / "a.db"))
    rb = run_study(replace(b.quick(64), method="qmc"), str(tmp_path / "b.db"))
    assert ra.findings == rb.findings
    probability = ra.findings["limits"][0]["probability"]
    assert 0.0 < probability["value"] < 1.0 and probability["low"] < probability["high"]


def test_the_study_parameters_override_the_file_rows_and_keep_the_others(files):
    """A study parameter that moves a row's value replaces the row (its own scatter, its own name),
    first; the file's other rows follow in file order."""
    rows = (
        '[[parameters]]\npath = "support.stiffness"\nname = "k"\n'
        'scatter = {distribution = "normal", cov = 0.1}\n'
    )
    study = load_study(_study(files, rows))
    assert [p.name for p in study.parameters] == ["k", "damping ratio"]
    k, zeta = (p.scatter for p in study.parameters)
    assert k.kind == "normal" and k.std == pytest.approx(4.5e7, rel=1e-12)
    assert (zeta.kind, zeta.parameters["low"], zeta.parameters["high"]) == ("uniform", 0.03, 0.07)
    # a study of the damping ratio alone at another range: the stiffness still scatters as the file says
    rows = (
        '[[parameters]]\npath = "support.damping_ratio"\n'
        'scatter = {distribution = "uniform", low = 0.02, high = 0.04}\n'
    )
    study = load_study(_study(files, rows))
    assert [p.name for p in study.parameters] == ["support.damping_ratio", "support stiffness"]
    assert study.parameters[0].scatter.parameters["high"] == 0.04
    assert study.parameters[1].scatter.kind == "lognormal"


def test_a_study_parameter_named_as_a_row_of_other_values_is_refused(files):
    rows = (
        '[[parameters]]\npath = "machine.mass"\nname = "damping ratio"\n'
        'scatter = {distribution = "normal", cov = 0.01}\n'
    )
    with pytest.raises(StudyError, match=r"'damping ratio' names a study parameter and the \[\[scatter\]\]"):
        load_study(_study(files, rows))


def test_the_file_correlations_hold_between_its_rows_and_the_study_own_pair_wins(files):
    model = files / "press_on_support.toml"
    model.write_text(
        model.read_text()
        + '\n[[correlations]]\nbetween = ["support stiffness", "damping ratio"]\ncoefficient = 0.4\n'
    )
    scatter = mechdyn.load(model).scatter
    assert scatter.correlations == (("support stiffness", "damping ratio", 0.4, "normal"),)
    assert scatter.space.R[0, 1] == 0.4
    study = load_study(_study(files))
    assert study.correlations == scatter.correlations
    assert np.array_equal(space(study).R, scatter.space.R)
    mine = (
        '\n[[correlations]]\nbetween = ["damping ratio", "support stiffness"]\n'
        'coefficient = -0.2\nmeasure = "spearman"\n'
    )
    study = load_study(_study(files, correlations=mine))
    assert study.correlations == (("damping ratio", "support stiffness", -0.2, "spearman"),)
    assert space(study).R[0, 1] == pytest.approx(2 * math.sin(math.pi * -0.2 / 6), rel=1e-12)
    # overriding one of the pair leaves the file's correlation out (the study states its own)
    rows = '[[parameters]]\npath = "support.stiffness"\nscatter = {distribution = "lognormal", cov = 0.3}\n'
    assert load_study(_study(files, rows)).correlations == ()


def test_a_tolerance_study_with_no_scatter_anywhere_says_where_to_give_it(files):
    model = files / "press_on_support.toml"
    model.write_text(_without_scatter(model.read_text()))
    with pytest.raises(
        StudyError, match=r"give \[\[parameters\]\] rows with a scatter, or \[\[scatter\]\] rows"
    ):
        load_study(_study(files))


def test_other_study_kinds_ignore_the_file_scatter(files):
    text = (
        '[study]\nname = "lhs"\nkind = "lhs"\nmodel = "press_on_support.toml"\nanalysis = "support"\n'
        'samples = 8\n[[parameters]]\npath = "machine.mass"\nrange = "±10 %"\n'
        '[[outputs]]\noutput = "displacement_max_m"\n'
    )
    (files / "lhs.toml").write_text(text)
    assert [p.name for p in load_study(files / "lhs.toml").parameters] == ["machine.mass"]


# -- bad input ------------------------------------------------------------------------------------------


BAD = [
    (
        ('path = "support.stiffness"', 'path = "support.stifness"'),
        r"\[\[scatter\]\] #1 \(name = 'support stiffness'\) → path: no value at 'support.stifness'; "
        r"paths nearby: support.stiffness",
    ),
    (
        ('distribution = "lognormal"', 'distribution = "lognormall"'),
        r"#1 \(name = 'support stiffness'\) → distribution: distribution = 'lognormall' is not known; "
        r"did you mean 'lognormal'\?",
    ),
    (("cov = 0.15", "cov = -0.15"), r"#1 \(name = 'support stiffness'\) → cov: -0.15 must be positive"),
    (("cov = 0.15", "cov = 0.15\nwidth = 2"), r"→ width: 'width' is not a field of a lognormal distribution"),
    (
        ("low = 0.03", "low = 0.09"),
        r"#2 \(name = 'damping ratio'\) → high: high = 0.07 is not above low = 0.09",
    ),
    (
        ('name = "damping ratio"', 'name = "support stiffness"'),
        r"#2 \(name = 'support stiffness'\) → name: 'support stiffness' names \[\[scatter\]\] #1 already",
    ),
    (
        ('path = "support.damping_ratio"', 'path = "support.stiffness"'),
        r"#2 \(name = 'damping ratio'\) → path: 'support.stiffness' gives a value "
        r"\[\[scatter\]\] #1 scatters",
    ),
    (
        ('path = "support.damping_ratio"', 'path = "excitation.mechanism"'),
        r"→ path: 'excitation.mechanism' is a mechanism model file.*a scatter is given to a quantity",
    ),
    (
        ('path = "support.damping_ratio"', ""),
        r"#2 \(name = 'damping ratio'\) → path: required field is missing",
    ),
    (
        ('distribution = "lognormal"', 'tolerance = "soil"'),
        r"→ tolerance: tolerance = 'soil' is not a tolerance class; give one of .*'soil_stiffness'",
    ),
    (("cov = 0.15", 'cov = 0.15\nlower = "3e8 N"'), r"→ lower: '3e8 N' is in N .*e.g. '3e\+08 N/m'"),
    (
        (
            "high = 0.07",
            'high = 0.07\n\n[[correlations]]\nbetween = ["support stiffness", "damping"]\ncoefficient = 0.3',
        ),
        r"\[\[correlations\]\] #1 → between: 'damping' is not the name of a \[\[scatter\]\] row "
        r"\(did you mean 'damping ratio'\?\)",
    ),
    (
        (
            "high = 0.07",
            'high = 0.07\n\n[[correlations]]\nbetween = ["support stiffness", "damping ratio"]\n'
            "coefficient = 1.5",
        ),
        r"\[\[correlations\]\] #1 → coefficient: 1.5 is not a correlation coefficient",
    ),
]


def _bad(files: Path, old: str, new: str) -> Path:
    model = files / "press_on_support.toml"
    text = model.read_text()
    assert old in text
    model.write_text(text.replace(old, new, 1))
    return model


@pytest.mark.parametrize(("change", "message"), BAD, ids=lambda x: x[1] if isinstance(x, tuple) else None)
def test_a_bad_row_is_refused_naming_file_row_field_value_and_fix(files, change, message):
    model = _bad(files, *change)
    with pytest.raises(ModelFileError) as info:
        mechdyn.load(model)
    assert str(info.value).startswith(f"{model}: ")
    assert re.search(message, str(info.value)), str(info.value)


@pytest.mark.parametrize("change", [BAD[0][0], BAD[2][0], BAD[-1][0]], ids=["path", "cov", "correlation"])
def test_the_command_line_refuses_a_bad_row_in_one_message_without_a_traceback(
    files, change, tmp_path, capsys
):
    from mechdyn.cli.main import main

    model = _bad(files, *change)
    code = main(["support", str(model), "--cycles", "1", "--json", "--db", str(tmp_path / "r.db")])
    err = capsys.readouterr().err
    assert code == 2 and "Traceback" not in err
    assert str(model) in err and "[[" in err and "→" in err


def test_a_bad_row_in_the_model_of_a_tolerance_study_is_the_study_error(files):
    _bad(files, "cov = 0.15", "cov = -0.15")
    with pytest.raises(
        StudyError, match=r"study.toml: \[study\] → model: .*press_on_support.toml: \[\[scatter\]\] #1"
    ):
        load_study(_study(files))


# -- every model type takes it, every analysis ignores it; save keeps it ---------------------------------


def _one_per_type() -> list[Path]:
    seen, out = set(), []
    for p in [*sorted(EXAMPLES.glob("*.toml")), *sorted(EXAMPLES.glob("measured/*.toml"))]:
        kind_of_model = tomllib.loads(p.read_text())["model"]["type"]
        if kind_of_model not in seen:
            seen.add(kind_of_model)
            out.append(p)
    return out


def _nonzero_quantity(path: Path) -> str:
    """The first value a study varies in the file that is a quantity other than zero."""
    from mechdyn.io import read
    from mechdyn.studies.paths import ModelTree

    for e in ModelTree(read(path)).entries():
        if e.nature.kind != "quantity" or e.rows != 1 or "*" in e.path or isinstance(e.value, list):
            continue
        number = e.value if isinstance(e.value, float) else float(str(e.value).split()[0])
        if number != 0.0:
            return e.path
    raise AssertionError(f"{path.name} has no quantity")


def _quiet(path: Path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        return mechdyn.load(path)


@pytest.mark.parametrize("example", _one_per_type(), ids=lambda p: p.stem)
def test_every_model_type_takes_a_scatter_row_and_builds_the_same_model(example, tmp_path):
    """One example of each type with a row scattering its first quantity: the same model and settings
    as without it, and the same study paths (the row's fields are no values a study varies)."""
    from mechdyn.io import read
    from mechdyn.studies.paths import ModelTree

    shutil.copytree(EXAMPLES, tmp_path / "x", ignore=shutil.ignore_patterns("studies", "gallery"))
    target = tmp_path / "x" / example.relative_to(EXAMPLES)
    path = _nonzero_quantity(example)
    target.write_text(
        example.read_text() + f'\n[[scatter]]\npath = "{path}"\ndistribution = "normal"\ncov = 0.05\n'
    )
    plain, scattered = _quiet(example), _quiet(target)
    assert plain.scatter is None or example == MODEL
    assert scattered.scatter.names[-1] == path
    here = str(tmp_path / "x")

    def shown(x) -> str:  # the fields, with the folder the file is in and no function's address
        return re.sub(r" at 0x[0-9a-f]+", "", repr(x).replace(here, str(EXAMPLES)))

    for mine, theirs in ((scattered.model, plain.model), (scattered.settings, plain.settings)):
        assert shown(mine) == shown(theirs)
    assert ModelTree(read(target)).paths() == ModelTree(read(example)).paths()


def test_an_analysis_gives_the_same_results_with_and_without_the_table(tmp_path, capsys):
    """``mechdyn support`` of the example and of its copy without [[scatter]]: every figure of the
    JSON the same (the run, the file and its hash aside)."""
    from mechdyn.cli.main import main

    shutil.copy(EXAMPLES / "press_link_drive.toml", tmp_path)
    plain = tmp_path / "plain.toml"
    plain.write_text(_without_scatter(MODEL.read_text()))
    with_table = tmp_path / "with_table.toml"
    with_table.write_text(MODEL.read_text())
    docs = []
    for path in (with_table, plain):
        assert main(["support", str(path), "--cycles", "1", "--json", "--db", str(tmp_path / "r.db")]) == 0
        docs.append(json.loads(capsys.readouterr().out))
    differ = {k for k in docs[0] if docs[0][k] != docs[1][k]}
    assert differ == {"run_id", "model_file", "model_sha256"}, differ
    assert docs[0]["displacement_max_m"] > 0


def test_save_keeps_the_scatter_and_the_file_reads_back_the_same_space(files, tmp_path):
    model = files / "press_on_support.toml"
    model.write_text(
        model.read_text()
        + '\n[[correlations]]\nbetween = ["support stiffness", "damping ratio"]\ncoefficient = 0.25\n'
        'measure = "spearman"\n'
    )
    loaded = mechdyn.load(model)
    (tmp_path / "out").mkdir()
    again = mechdyn.load(mechdyn.save(loaded, tmp_path / "out" / "saved.toml"))
    a, b = loaded.scatter, again.scatter
    assert a.rows == b.rows and a.correlations == b.correlations
    assert a.space.describe() == b.space.describe() and np.array_equal(a.space.R, b.space.R)
    assert [v.parameters for v in a.variables] == [v.parameters for v in b.variables]
    # a model built in Python has none, and its file none either
    assert mechdyn.io.LoadedModel("support", loaded.model).scatter is None


def test_the_reference_page_of_every_model_type_lists_the_scatter_tables():
    """The generated model-file reference: ``[[scatter]]`` with every distribution the reader takes and
    ``[[correlations]]`` on each model type's page; none on the study file's."""
    from mechdyn.io.modelfile import file_types
    from mechdyn.io.reference import markdown
    from mechdyn.uncertainty.tables import DISTRIBUTION_KEYS

    for file_type in file_types():
        page = markdown(file_type)
        if file_type == "study":
            assert "## `[[scatter]]`" not in page
            continue
        assert "## `[[scatter]]`" in page and "## `[[correlations]]`" in page, file_type
        assert all(f"`{k}`" in page for k in DISTRIBUTION_KEYS)
