"""Tables a person reads without a second look: rows labelled in words, one number format per column,
right-aligned numbers, no negative zero, CSV columns without spaces, and results that would mislead
on their own (a free drivetrain's frequency response, an empty list of crossings) saying what they
mean."""

from __future__ import annotations

import io
import re
import warnings

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

SNAKE = re.compile(r"^[a-z0-9]+(?:_[a-z0-9]+)+$")
CASES = [
    ("modal", "turret_milling.toml", {"compare_rigid": True}),
    ("campbell", "turret_indexing.toml", {}),
    ("frf", "turret_milling.toml", {"points": 200}),
    ("mechanism", "press_link_drive.toml", {"angles": 72}),
    ("support", "press_on_mounts.toml", {"cycles": 1}),
    ("mount", "anchor_concrete.toml", {}),
    ("mount", "pad_shore60.toml", {}),
    ("gear", "spur_pair.toml", {}),
    ("gear", "tooth_pair1_published.toml", {}),
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
        for row in t.rows:
            assert not (isinstance(row[0], str) and SNAKE.match(row[0])), f"{t.title}: row label {row[0]!r}"
        out = io.StringIO()
        print_table(t, file=out)
        text = out.getvalue()
        assert not re.search(r"(?<![\w.])-0(?:\.0*)?(?:e[+-]00)?(?![\w.])", text), text
        for i in range(len(t.columns)):
            if "unit" in t.columns:  # each row another quantity: each value formatted on its own
                continue
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
    from mechdyn.io.modelfile import read
    from mechdyn.registry import analyses

    for path in sorted(EXAMPLES.glob("*.toml")):
        kind = read(path).model_type
        for name, a in analyses().items():
            if kind in a.model_types:
                yield pytest.param(name, path.name, id=f"{name}-{path.stem}")


@pytest.mark.parametrize(("name", "example"), list(_unit_tables()))
def test_every_summary_of_every_example_reads_in_words_with_three_significant_digits(name, example, tmp_path):
    """Each row of a summary is another quantity: its value is written on its own, in the unit a
    designer reads it in (a stroke in mm, not "1 m"), with at least three significant digits, and its
    label is words, not a result key."""
    from mechdyn.store import ResultStore

    with ResultStore(str(tmp_path / "r.db")) as store:
        tables = _run(name, example, store, **_LIGHT.get(name, {})).tables()
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


@pytest.mark.parametrize("example", sorted(p.name for p in EXAMPLES.glob("*.toml")))
def test_a_shipped_example_runs_without_warnings_unless_they_are_its_point(example, tmp_path):
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
