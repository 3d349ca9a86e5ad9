"""Tables a person reads without a second look: rows labelled in words, one number format per column,
right-aligned numbers, no negative zero, CSV columns without spaces, and results that would mislead
on their own (a free drivetrain's frequency response, an empty list of crossings) saying what they
mean."""

from __future__ import annotations

import io
import re
import tomllib
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from conftest import EXAMPLES
from mechdyn.cli.common import _fmt, print_table, write_csv
from mechdyn.errors import ModelWarning
from mechdyn.io import load_model
from mechdyn.numbers import column_format as _column_spec
from mechdyn.registry import get
from mechdyn.results import Table

# the shipped model files: examples/*.toml and the measurement files beside their data
MODEL_EXAMPLES = sorted([*EXAMPLES.glob("*.toml"), *EXAMPLES.glob("measured/*.toml")])


def _shipped_name(path: Path) -> str:
    return path.relative_to(EXAMPLES).as_posix()


SNAKE = re.compile(r"^[a-z0-9]+(?:_[a-z0-9]+)+$")
# runs the summary test below does not make (it checks every table of every analysis of every example
# with the options of _LIGHT): an option that adds tables
CASES = [
    ("modal", "turret_milling.toml", {"compare_rigid": True}),
]


def _run(name, example, store=None, **options):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        kw = {"store": store} if get(name).uses_store else {}
        return get(name).run(load_model(EXAMPLES / example), **kw, **options)


@pytest.mark.parametrize(("name", "example", "options"), CASES, ids=lambda c: str(c))
def test_rows_are_labelled_in_words_and_every_number_column_has_one_format(name, example, options, tmp_path):
    from mechdyn.store import ResultStore

    with ResultStore(str(tmp_path / "r.db")) as store:
        tables = _run(name, example, store, **options).tables()
    for t in tables:
        _check_columns(t)


def _check_columns(t: Table) -> None:
    """Row labels in words, no negative zero, and one precision in each number column of a table
    whose rows are alike (a table with a unit column has each row another quantity)."""
    for row in t.rows:
        assert not (isinstance(row[0], str) and SNAKE.match(row[0])), f"{t.title}: row label {row[0]!r}"
    out = io.StringIO()
    print_table(t, file=out)
    text = out.getvalue()
    assert not re.search(r"(?<![\w.])-0(?:\.0*)?(?:e[+-]00)?(?![\w.])", text), text
    if "unit" in t.columns or t.per_value:  # each value formatted on its own
        return
    for i in range(len(t.columns)):
        spec = _column_spec([r[i] for r in t.rows])
        if spec is None:
            continue
        shown = [_fmt(r[i], spec) for r in t.rows if r[i] is not None and not isinstance(r[i], int)]
        decimals = {len(s.split("e")[0].split(".")[1]) if "." in s else 0 for s in shown if s != "—"}
        assert len(decimals) <= 1, f"{t.title}, column {t.columns[i]!r}: {shown}"


# light options for the analyses that would otherwise integrate or sweep at length
_LIGHT = {
    "mechanism": {"angles": 72},
    "support": {"cycles": 1},
    "frf": {"points": 200},
    "modes-from-test": {"bootstrap": 0, "starts": 0},  # no bootstrap of the scatter, no global start
    # a few milliseconds of a free run at speed: every drivetrain example, with or without [simulation]
    "simulate": {"duration": 0.005, "initial_speed": 100.0},
    # a few speeds and harmonics, teeth in contact: every drivetrain example, with or without [speed_sweep]
    "speed-sweep": {
        "speed_range": (200.0, 300.0),
        "points": 4,
        "harmonics": 4,
        "no_stability": True,
        "no_backlash": True,
    },
}


def _significant(text: str) -> int:
    """The significant digits a number is written with ("1496.3" 5, "0.0012" 2, "2.1e-16" 2)."""
    mantissa = text.lstrip("-").split("e")[0]
    digits = mantissa.replace(".", "").lstrip("0")
    return len(digits)


def _unit_tables():
    """Every analysis of every shipped example; ``first`` marks the example's first analysis, the one
    the command runs by default, which also answers for the example's warnings."""
    from mechdyn.io.modelfile import read
    from mechdyn.registry import analyses

    for path in MODEL_EXAMPLES:
        kind = read(path).model_type
        names = [name for name, a in analyses().items() if kind in a.model_types]
        for name in names:
            yield pytest.param(name, _shipped_name(path), name == names[0], id=f"{name}-{path.stem}")


@pytest.mark.parametrize(("name", "example", "first"), list(_unit_tables()))
def test_every_summary_of_every_example_reads_in_words_with_three_significant_digits(
    name, example, first, tmp_path
):
    """Every table of every analysis of every example passes the column checks above; and each row
    of a summary is another quantity: its value is written on its own, in the unit a
    designer reads it in (a stroke in mm, not "1 m"), with at least three significant digits, and its
    label is words, not a result key. The example's first analysis (the command's default) runs
    without a warning unless the warning is the example's point (:data:`WARNS_ON_PURPOSE`): one run
    answers both."""
    from mechdyn.store import ResultStore

    if first:
        tables = _check_quiet(example, tmp_path).tables()
    else:
        with ResultStore(str(tmp_path / "r.db")) as store:
            tables = _run(name, example, store, **_LIGHT.get(name, {})).tables()
    for t in tables:  # every table of every analysis of every example
        _check_columns(t)
    for t in (t for t in tables if "unit" in t.columns):
        out = io.StringIO()
        print_table(t, file=out)
        lines = out.getvalue().splitlines()
        for row in t.rows:
            label = str(row[0])
            raw_key = SNAKE.match(label) or re.search(r"[a-z]{2,}_[a-z]{2,}", label)  # a symbol (k_c) is fine
            assert not raw_key, f"{example} {name}, {t.title}: {label!r}"
            for v in row[1:]:
                if isinstance(v, bool) or not isinstance(v, float) or v == 0 or not np.isfinite(v):
                    continue
                line = next(ln for ln in lines if ln.startswith(label + " "))
                numbers = re.findall(r"-?\d+(?:\.\d+)?(?:e[+-]\d+)?", line[len(label) :])
                assert numbers and all(_significant(x) >= 3 for x in numbers[:1]), (example, t.title, line)


def test_a_column_keeps_one_precision_and_negative_zero_prints_as_zero():
    assert _column_spec([20.0, 10.0, 30.0]) == ".2f"
    assert _column_spec([792.34, 5658.6, 52363.0]) == ".1f"  # four digits for the smallest
    assert [_fmt(v, ".3f") for v in (20.0, 10.0, -0.0001)] == ["20.000", "10.000", "0.000"]
    assert _fmt(-0.0) == "0" and _fmt(-1e-20, ".4f") == "0.0000"
    assert _column_spec([1e-9, 500.0]) == ".1f"  # below a thousandth of the largest: shown near zero
    assert _column_spec([2.5e8, 7.1e8]) == ".4e"  # beyond seven digits: exponents for the column
    assert _column_spec(["no", 3.0]) is None  # rows of different quantities format on their own
    # values that differ only in their fifth digit read apart: a stroke against its limit
    assert _column_spec([1495.3, 1496.3]) == ".1f"
    assert [_fmt(v, _column_spec([1495.3, 1496.3])) for v in (1495.3, 1496.3)] == ["1495.3", "1496.3"]
    assert _column_spec([100.0, 101.0, 102.0]) == ".1f"  # no more digits than four already give
    t = Table("t", ["a", "b [mm]"], [["x", 1.5], ["y", -0.0]])
    out = io.StringIO()
    print_table(t, file=out)
    assert "-0" not in out.getvalue()


def test_csv_columns_have_no_spaces(tmp_path):
    frame = _run("frf", "turret_milling.toml", points=50).to_frame()
    assert any(" " in c for c in frame.columns)  # element names have spaces ...
    write_csv(frame, tmp_path / "f.csv")
    header = (tmp_path / "f.csv").read_text().splitlines()[0].split(",")
    assert not any(" " in c for c in header)  # ... the CSV's columns do not
    assert "shaft_1_Nm" in header and "mesh_1_N" in header
    back = pd.read_csv(tmp_path / "f.csv")
    np.testing.assert_allclose(back["frequency_hz"], frame["frequency_hz"], rtol=1e-9)


def test_a_free_drivetrains_frequency_response_reports_its_resonance_peaks():
    """A free chain's angles are largest at the lowest frequency (rigid-body motion, ∝ 1/ω²): the
    reported peak is the resonance, at a natural frequency, to the frequency grid's resolution."""
    result = _run("frf", "turret_milling.toml", points=2000)
    f = result.frequencies_hz
    natural = result.natural_frequencies_hz
    for disk in ("1", "4", "7"):
        y = np.abs(result.angles[:, result.disk_names.index(disk)])
        assert np.argmax(y) == 0  # the raw maximum is the rigid-body response at the bottom
        amp, at = result.peak(disk)
        k = np.searchsorted(f, at)
        step = f[min(k + 1, f.size - 1)] - f[max(k - 1, 0)]
        assert np.min(np.abs(natural - at)) <= step, (disk, at, natural)
        assert amp < y[0]
    table = result.tables()[0]
    assert table.title.startswith("resonance peaks")


def test_an_empty_crossings_table_says_why():
    result = _run("campbell", "turret_indexing.toml")
    crossings = result.tables()[1]
    assert crossings.rows == []
    assert "none (" in crossings.title and "below the lowest natural frequency" in crossings.title
    assert "no gear-mesh orders: mesh 1, mesh 2 give no teeth" in crossings.title


def test_the_command_line_shows_forces_and_lengths_in_the_units_asked_for(tmp_path, capsys):
    """`--force-unit tonf --length-unit m`: the press's summary in tonnes-force and metres (the
    published figures are in tonf); without them, kN and mm; a unit of the wrong kind is refused
    with the value and an example."""
    from mechdyn.cli.main import main

    args = [
        "mechanism",
        str(EXAMPLES / "press_link_drive.toml"),
        "--db",
        str(tmp_path / "r.db"),
        "--angles",
        "72",
    ]
    assert main([*args, "--force-unit", "tonf", "--length-unit", "m"]) == 0
    out = capsys.readouterr().out
    assert re.search(r"inertia force max\s+5[34]\.\d+\s+tonf", out), out
    assert re.search(r"stroke\s+1\.496\d*\s+m\s", out), out
    assert main(args) == 0
    out = capsys.readouterr().out
    assert re.search(r"inertia force max\s+529\.\d+\s+kN", out) and re.search(r"stroke\s+1496\.\d+\s+mm", out)
    with pytest.raises(SystemExit):
        main([*args, "--force-unit", "mm"])
    assert "'mm' is not a unit of force (e.g. kN, tonf" in capsys.readouterr().err


# the examples whose warnings are their point, each explained in one line of the README
WARNS_ON_PURPOSE = {"turret_indexing.toml": "published base radii disagree with their tooth ratios"}


def _check_quiet(example: str, tmp_path: Path):
    """Run an example's first analysis (the command's default) and check that it warns only where
    warning is the example's point, said in the README; the result, for further checks."""
    from mechdyn.io.modelfile import read
    from mechdyn.registry import analyses
    from mechdyn.store import ResultStore

    kind = read(EXAMPLES / example).model_type
    name = next(n for n, a in analyses().items() if kind in a.model_types)
    with warnings.catch_warnings(record=True) as caught, ResultStore(str(tmp_path / "r.db")) as store:
        warnings.simplefilter("always")
        kw = {"store": store} if get(name).uses_store else {}
        result = get(name).run(load_model(EXAMPLES / example), **kw, **_LIGHT.get(name, {}))
    said = [str(w.message) for w in caught if issubclass(w.category, UserWarning)]
    said += list(getattr(result, "warnings", ()))
    if example in WARNS_ON_PURPOSE:
        readme = (EXAMPLES.parent / "README.md").read_text()
        assert said and "The two warnings are findings" in readme, said
    else:
        assert not said, said
    return result


def test_every_shipped_model_file_has_its_warnings_checked():
    """Each shipped model file is among the examples whose first analysis is checked for warnings
    (by the summary test above, which runs it once for both)."""
    checked = {p.values[1] for p in _unit_tables() if p.values[2]}
    assert checked == {_shipped_name(p) for p in MODEL_EXAMPLES}


@pytest.mark.parametrize(
    ("value", "text"),
    [
        (1496.3, "1496.3"),
        (26.7621, "26.762"),
        (0.00403694, "0.0040369"),
        (1805450.2, "1805450"),
        (6.84031e-6, "6.8403e-06"),
        (2.5e9, "2.5000e+09"),
        (-0.0, "0"),
        (0.0, "0"),
        (float("nan"), "—"),
    ],
)
def test_one_rule_writes_a_number_in_the_terminal_the_report_and_the_dashboard(value, text):
    """Each value on its own, five significant digits: the terminal (a table with a unit column), the
    report's and the dashboard's cells (reports.html) write it alike."""
    from mechdyn.numbers import number_text
    from mechdyn.reports.html import table_cell

    assert number_text(value) == text
    assert _fmt(value) == text
    assert table_cell(value).text == text


# -- the shipped studies: every table by the one number rule, the counts adding up ---------------

STUDIES = EXAMPLES / "studies"

# each shipped study in its quickest form: the fewest samples its file takes (one trial a box, a
# Sobol sample's smallest power of 2, one generation of the smallest population) and the analyses'
# lightest options; a sweep's design as the file gives it. What is checked here is how the tables
# write what a study found and count its variants, not the optimum (tests/test_studies.py and
# tests/test_study_optimum.py check that).
QUICK_STUDIES: dict[str, dict] = {
    "press_link_relocation.toml": {"samples": 1},
    "press_sobol.toml": {"samples": 2},
    "press_support_influence.toml": {},
    "press_synthesis.toml": {"samples": 1, "population": 4, "options": {"angles": 36}},
    "press_support_tolerance.toml": {"samples": 4},
    "press_support_robust.toml": {"samples": 4},
    "press_mounts_floor_tolerance.toml": {"samples": 4},
    "press_support_tolerance_from_model.toml": {"samples": 4},
    "rp1_sensitivity.toml": {"options": {"angles": 36}},
    "turret_mesh_clocking.toml": {"options": {"points": 4}},
    "turret_kv_tolerance.toml": {"samples": 4, "small_probability": "off", "options": {"points": 4}},
}
NUMBER = re.compile(r"(?<![\w.])[-+]?\d+(?:\.\d+)?(?:e[+-]\d+)?")
COUNTS = re.compile(r"^\s*(\d+)\s+(\d+)\s+(\d+)\s+(\d+)\s*$")


def _quick_file(name: str, folder) -> str:
    """The shipped study ``name`` in its quick form (:data:`QUICK_STUDIES`), written into ``folder``."""
    import tomllib

    from mechdyn.reports.html import toml_text

    data = tomllib.loads((STUDIES / name).read_text(encoding="utf-8"))
    quick = dict(QUICK_STUDIES[name])
    study = data["study"]
    study["model"] = str((STUDIES / study["model"]).resolve())
    study["options"] = {**study.get("options", {}), **quick.pop("options", {})}
    study.update(quick)
    path = folder / name
    path.write_text(toml_text(data), encoding="utf-8")
    return str(path)


def _shipped(name: str, folder) -> dict:
    """Run a shipped study's quick form twice, as ``mechdyn study`` does: into a new database, printing
    its tables (and count the variants the database then holds), then again (reusing what is stored)
    with ``--json`` and ``--report``."""
    import contextlib
    import html as htmllib
    import json

    from mechdyn.cli.main import main
    from mechdyn.store import ResultStore
    from mechdyn.studies.kinds.base import safe
    from mechdyn.studies.storage import StudyStore
    from mechdyn.studies.study import load_studies

    path, db = _quick_file(name, folder), str(folder / "r.db")
    studies = load_studies(path)
    report = folder / "report.html"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)  # the published turret's base radii
        printed = io.StringIO()
        with contextlib.redirect_stdout(printed):
            assert main(["study", path, "--db", db]) == 0
        with ResultStore(db, read_only=True) as store:
            stored = {s.name: len(StudyStore(store).variants(s.name)) for s in studies}
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            assert main(["study", path, "--db", db, "--json", "--report", str(report)]) == 0
    reports = {}
    for s in studies:
        target = report if len(studies) == 1 else report.with_name(f"report_{safe(s.name).strip('_')}.html")
        reports[s.name] = " ".join(htmllib.unescape(re.sub(r"<[^>]+>", " ", target.read_text())).split())
    return {
        "studies": studies,
        "printed": printed.getvalue(),
        "stored": stored,
        "json": json.loads(out.getvalue()),
        "reports": reports,
    }


def test_every_shipped_study_has_a_quick_form_here():
    assert sorted(p.name for p in STUDIES.glob("*.toml")) == sorted(QUICK_STUDIES)


# the studies whose quick form still takes tens of seconds (rp1's pitch-curve check per variant, the
# synthesis's generations) run in CI's heavy step (pytest -m slow)
# over 10 s each even in their quick form: CI's heavy step runs them (tests/test_studies.py runs the
# relocation's own checks, tests/test_gear_dynamics_clocking.py the clocking's, in the test command)
_HEAVY_STUDIES = (
    "rp1_sensitivity.toml",
    "press_synthesis.toml",
    "press_link_relocation.toml",
    "turret_mesh_clocking.toml",
    "press_sobol.toml",  # 5 s; tests/test_studies.py runs a Sobol study in the test command
)
_SHIPPED = [
    pytest.param(n, marks=pytest.mark.slow) if n in _HEAVY_STUDIES else n for n in sorted(QUICK_STUDIES)
]


# the two heaviest quick forms (a robust optimization, a speed sweep per sample) in CI's heavy step
# in CI's heavy step: the heaviest, the floor's (the same tables as the support's tolerance study) and the
# one whose samples equal press_support_tolerance.toml's (tests/test_model_scatter.py)
_HEAVY_QUICK = (
    "press_support_robust.toml",
    "turret_kv_tolerance.toml",
    "press_mounts_floor_tolerance.toml",
    "press_support_tolerance_from_model.toml",
)


@pytest.mark.parametrize(
    "name", [pytest.param(n, marks=pytest.mark.slow) if n in _HEAVY_QUICK else n for n in _SHIPPED]
)
def test_every_shipped_study_reads_in_words_and_counts_alike(name, tmp_path):
    """One run of each shipped study's quick form (once: parametrized tests go to different workers),
    its tables, JSON and report checked for both rules below."""
    ran = _shipped(name, tmp_path)
    _reads_in_words_with_three_significant_digits(ran)
    _variant_counts_add_up_alike_in_tables_json_and_report(ran)


def _reads_in_words_with_three_significant_digits(ran: dict) -> None:
    """Every number a study's tables print (cells, titles and sentences) has at least three significant
    digits, each written on its own: an output's change of a few millionths beside one of 40 % is not
    0.00, an effect is not 1.0580e-02 beside 358.22, a stroke of 1495.3 mm is not 1495 beside its
    1496.3 mm limit. Whole numbers are counts, ids and levels as the study file gives them. No output
    is named by its summary key: words, as a summary names it (``displacement_max_m`` → displacement
    max)."""
    short = []
    for line in ran["printed"].splitlines():
        if line.startswith(("study '", "stored in ")):  # the study's name and where it is stored
            continue
        decimals = [x for x in NUMBER.findall(line) if "." in x or "e" in x]
        short += [(x, line.strip()) for x in decimals if _significant(x) < 3]
    assert not short, short
    parts = {part for s in ran["studies"] for w in s.watched for part in w.key.split(".") if "_" in part}
    assert parts and not [p for p in parts if p in ran["printed"]], ran["printed"]


def _variant_counts_add_up_alike_in_tables_json_and_report(ran: dict) -> None:
    """Each variant once, the base design among them where the kind has one: a first run's table
    counts what the database then holds, all evaluated now; a rerun's JSON and its report count every
    one of those as reused, and evaluated now + reused adds up to the variants in each (a file with
    boxes: per box, and the JSON's totals are the boxes' sums)."""
    lines = ran["printed"].splitlines()
    for study, stored in ran["stored"].items():
        at = lines.index(f"{study}: variants")
        row = next(m for x in lines[at:] if (m := COUNTS.match(x)))
        n, evaluated, reused, _ = map(int, row.groups())
        assert (n, evaluated, reused) == (stored, stored, 0), (study, row.group(0))
    doc = ran["json"]
    again = {s["study"]: s for s in doc.get("studies", [doc])}
    assert set(again) == set(ran["stored"])
    for key in ("variants", "evaluated", "reused", "failed"):
        assert doc[key] == sum(d[key] for d in again.values())
    for study, d in again.items():
        assert d["variants"] == d["evaluated"] + d["reused"] and d["reused"] == ran["stored"][study], d
        counts = [d[key] for key in ("variants", "evaluated", "reused", "failed")]
        text = ran["reports"][study]
        assert "variants {} = {} evaluated now + {} reused (found stored)".format(*counts[:3]) in text
        assert "variants evaluated now reused failed {} {} {} {}".format(*counts) in text


@pytest.mark.parametrize(("peak", "unit"), [(12.0, "N"), (5e3, "N"), (5e4, "kN"), (2.4e7, "MN")])
def test_a_force_axis_takes_the_unit_the_tables_take_for_its_largest_value(peak, unit):
    """One ladder of units for tables and plots (:func:`mechdyn.units.readable_unit`): a plot keeps no
    ladder of its own (a support's force axis once went to kN from 1 kN, where the tables stay in N up
    to 10 kN); a unit asked for is kept."""
    from mechdyn.plotting import display_unit
    from mechdyn.support.plots import _force_scale
    from mechdyn.units import readable

    assert readable(peak, "N")[1] == unit
    assert display_unit([0.5 * peak, -peak], "N")[0] == unit
    scale, shown = _force_scale(np.array([0.5 * peak, -peak]), None)
    assert shown == unit and peak / scale == pytest.approx(readable(peak, "N")[0], rel=1e-12)
    assert _force_scale(np.array([peak]), "tonf")[1] == "tonf"


@pytest.mark.parametrize(("example", "unit"), [("fourbar.toml", "N"), ("press_link_drive.toml", "kN")])
def test_a_mechanisms_inertia_forces_are_drawn_in_the_unit_the_tables_take(example, unit):
    """The inertia-force plot's axis in the unit its largest drawn force reads best in, as a summary
    shows a force of that size (N for the four-bar's 12 N, kN for the press's 530 kN)."""
    import matplotlib

    matplotlib.use("Agg")
    from mechdyn.units import convert, readable_unit

    ax = _run("mechanism", example, angles=36).plots()["inertia_forces.png"]()
    assert ax.get_ylabel().endswith(f"({unit})")
    curves = [np.abs(line.get_ydata()) for line in ax.get_lines() if len(line.get_ydata()) > 2]
    largest = max(float(c.max()) for c in curves) / float(convert(1.0, "N", unit))  # back in N
    assert readable_unit(largest, "N")[1] == unit


def test_a_stored_study_s_variants_list_in_words_with_three_significant_digits(tmp_path, capsys):
    """``mechdyn results list --study``: each number on its own (a study's outputs spread over decades),
    an output the file does not show named in words with its SI unit, not by its key."""
    from mechdyn.cli.main import main

    path, db = _quick_file("press_support_influence.toml", tmp_path), str(tmp_path / "r.db")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        assert main(["study", path, "--db", db]) == 0
    capsys.readouterr()
    name = tomllib.loads(Path(path).read_text(encoding="utf-8"))["study"]["name"]
    assert main(["results", "list", "--study", name, "--db", db]) == 0
    printed = capsys.readouterr().out
    short = [x for x in NUMBER.findall(printed) if ("." in x or "e" in x) and _significant(x) < 3]
    assert not short, printed
    assert "_m " not in printed and "_N" not in printed, printed


def _short_numbers(printed: str) -> list[str]:
    """Numbers printed with a decimal point or exponent but fewer than three significant digits."""
    return [x for x in NUMBER.findall(printed) if ("." in x or "e" in x) and _significant(x) < 3]


def test_the_results_commands_print_in_words_with_three_significant_digits(tmp_path, capsys):
    """``mechdyn results compare`` (variants side by side), ``results show`` (one stored run) and
    ``results studies``: outputs named in words with their unit, each number on its own."""
    from mechdyn.cli.main import main

    path, db = _quick_file("press_support_influence.toml", tmp_path), str(tmp_path / "r.db")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        assert main(["study", path, "--db", db]) == 0
        assert main(["modal", str(EXAMPLES / "turret_milling.toml"), "--db", db]) == 0
    capsys.readouterr()
    assert main(["results", "compare", "1", "2", "3", "--db", db]) == 0
    compared = capsys.readouterr().out
    assert "transmitted force range [tonf]" in compared and "displacement max [mm]" in compared, compared
    assert "4.05e+08 N/m" in compared and "4.5e+08" not in compared, compared  # the given values, 3 digits
    assert main(["results", "show", "1", "--db", db]) == 0
    shown = capsys.readouterr().out.split("\n", 1)[1]  # after the header (the package's version)
    assert "frequencies [Hz]" in shown and "modes 1 · frequency [Hz]" in shown, shown
    assert re.search(r"frequencies \[Hz\]\s+1101\.3, 2710\.0, 6033\.2", shown), shown
    assert main(["results", "studies", "--db", db]) == 0
    studies = capsys.readouterr().out
    for printed in (compared, shown, studies):
        assert not _short_numbers(printed), printed
        assert not re.search(r"\b[a-z]+_(?:m|N|hz|Hz|s)\b", printed), printed  # no raw output key
