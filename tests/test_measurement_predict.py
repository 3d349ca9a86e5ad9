"""Prediction with a band (issue 47, point 5): a measurement file's ``[predict]`` table runs an
analysis of the tested model on the updated one, the updated values' posterior carried through by
sampling; ``modes-from-test`` reports the tested and the updated model's values, the median and the
95 % band with its confidence intervals, on the command line, in the results and in the report.

The shipped example ``examples/measured/tap_test.toml`` predicts the force on the floor of the
spindle's unbalance; its test was made by ``make_data.py`` from a machine whose mounts are 0.6, 0.7 and
2.3 MN/m with 600, 700 and 2300 N·s/m (stiffness-proportional damping, 1e-3 s).
"""

from __future__ import annotations

import json
import shutil

import numpy as np
import pytest

import mechdyn
from conftest import EXAMPLES
from mechdyn.cli.main import main
from mechdyn.errors import ModelFileError
from mechdyn.io.modelfile import load_source
from mechdyn.registry import get

pytest.importorskip("pyuff")

FOLDER = EXAMPLES / "measured"
TAP_TEST = FOLDER / "tap_test.toml"
LIGHT = {"bootstrap": 0, "starts": 0}
# make_data.py's machine as built: the mounts' stiffness (N/m) and damping (N·s/m) along x, y, z, in
# the order of tap_test.toml's [[update]] rows
TRUE_VALUES = np.array([0.6e6, 0.7e6, 2.3e6, 600.0, 700.0, 2300.0])
KEYS = ["transmitted_force_max_N", "transmitted_to_inertia_force_range", "natural_frequencies_hz.1"]


def _support_outputs(loaded) -> list[float]:
    """The example's three outputs of the support analysis, written here without mechdyn's output
    reader: the largest floor force, the transmissibility of the force range, the first frequency."""
    s = get("support").run(loaded, cycles=1).summary()
    return [
        s["transmitted_force_max_N"],
        s["transmitted_to_inertia_force_range"],
        s["natural_frequencies_hz"][0],
    ]


@pytest.fixture(scope="module")
def result():
    return get("modes-from-test").run(mechdyn.load(TAP_TEST), **LIGHT)


def _variant(tmp_path, old: str, new: str):
    for name in ("machine.toml", "tap_test.uff"):
        shutil.copy(FOLDER / name, tmp_path / name)
    text = TAP_TEST.read_text()
    assert old in text, old
    path = tmp_path / "test.toml"
    path.write_text(text.replace(old, new, 1))
    return path


def test_the_example_asks_for_the_floor_force_of_the_support_analysis():
    p = mechdyn.load(TAP_TEST).model.predict
    assert p.analysis == "support" and p.keys == KEYS
    assert [(o.unit, o.display) for o in p.outputs] == [("N", "kN"), ("", ""), ("Hz", "")]
    assert p.samples >= 32 and p.method == "mc" and dict(p.options) == {"cycles": 1}


def test_the_band_is_model_update_predict_with_the_same_seed(result):
    """The analysis' band is exactly what ``ModelUpdate.predict`` gives for the same outputs, samples,
    method and seed; the tested and the updated model's values are the support analysis' own."""
    p = result.prediction
    spec = p.spec
    direct = result.update.predict(_support_outputs, KEYS, spec.samples, method=spec.method, seed=spec.seed)
    np.testing.assert_array_equal(p.band.Y, direct.Y)
    for mine, theirs in zip(p.band.distributions, direct.distributions, strict=True):
        for q in (0.025, 0.5, 0.975):
            assert mine.quantiles[q] == theirs.quantiles[q]
    np.testing.assert_array_equal(p.low, [d.quantiles[0.025].value for d in direct.distributions])
    np.testing.assert_array_equal(p.high, [d.quantiles[0.975].value for d in direct.distributions])
    np.testing.assert_array_equal(p.prior, _support_outputs(mechdyn.load(FOLDER / "machine.toml")))
    np.testing.assert_array_equal(p.updated, _support_outputs(result.update.load()))
    # the summary holds the same figures, SI, each key with its unit
    entry = result.summary()["predicted"]["transmitted_force_max_N"]
    assert entry["band"] and entry["median_N"] == direct.distributions[0].quantiles[0.5].value
    assert (entry["low_95_N"], entry["high_95_N"]) == (p.low[0], p.high[0])
    assert entry["tested_model_N"] == p.prior[0] and entry["updated_model_N"] == p.updated[0]
    # a band end's confidence interval: an order-statistic interval around it; its outer side
    # unbounded with so few samples (P(all 32 above the 2.5 % quantile) = 0.975^32 > 2.5 %)
    lo_ci = p.confidence(0.025)[0]
    assert lo_ci[0] == -np.inf and p.low[0] <= lo_ci[1] <= p.median[0]
    assert "low_95_confidence_low_N" not in entry and entry["low_95_confidence_high_N"] == lo_ci[1]


def test_the_band_holds_the_machine_as_built_and_not_the_catalogue(result):
    """The machine the test was made from (make_data.py) lies in the band of each output, and so does
    the updated model; the catalogue model, its mounts 10–20 % off, lies far outside."""
    p = result.prediction
    truth = np.asarray(_support_outputs(load_source(result.update.variant(TRUE_VALUES))))
    assert np.all(p.low <= truth) and np.all(truth <= p.high), (p.low, truth, p.high)
    assert np.all(p.low <= p.updated) and np.all(p.updated <= p.high)
    assert np.all((p.prior < p.low) | (p.prior > p.high))
    # the floor force of the machine as built is half as large again as the catalogue model says
    assert truth[0] > 1.4 * p.prior[0]


@pytest.fixture(scope="module")
def command_run(tmp_path_factory):
    """One run of the command on the tap test, with its report: the arguments, what it printed and
    the report (the table's and the report's checks read the same run)."""
    import contextlib
    import io

    tmp = tmp_path_factory.mktemp("command")
    report = tmp / "test.html"
    argv = ["modes-from-test", str(TAP_TEST), "--bootstrap", "0", "--starts", "0", "--db", str(tmp / "r.db")]
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        assert main([*argv, "--report", str(report)]) == 0
    return argv, printed.getvalue(), report.read_text(encoding="utf-8")


def _band_row(out: str) -> str:
    """The table's row of the largest transmitted force: its words, the tested and updated models,
    the median and the band's ends, in kN."""
    table = out[out.index("prediction of the support analysis") :]
    return next(line for line in table.splitlines() if line.startswith("transmitted force max "))


def test_the_command_line_prints_the_band_in_words_with_units(command_run, capsys):
    argv, out, _ = command_run
    table = out[out.index("prediction of the support analysis") :]
    row = _band_row(out)
    assert row.rstrip().endswith("kN") and "−∞ … " in row
    tested, updated, median, low, high = (float(x) for x in row.split()[3:8])
    assert tested < low <= median <= high and low <= updated <= high and 3 < tested < 4  # kN
    assert "natural frequencies 1 " in table and "95 % band (2.5 % and 97.5 % quantiles)" in " ".join(
        table.split()
    )
    assert main([*argv, "--json", "--samples", "16"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["prediction_analysis"] == "support" and doc["prediction_samples"] == 16
    assert set(doc["predicted"]) == set(KEYS)
    # the file's samples give way to --samples; fewer than 32 make wide intervals, said so
    assert any("with 16 samples (fewer than 32)" in w and "wide" in w for w in doc["warnings"])
    entry = doc["predicted"]["natural_frequencies_hz.1"]  # keys end with the output's own unit suffix
    assert {"tested_model_hz", "median_hz", "low_95_hz", "high_95_hz"} <= set(entry)


def test_the_report_shows_the_band(command_run):
    import re

    _, out, html = command_run
    assert "prediction of the support analysis" in html and "95 % band" in html
    # the band's ends as the table writes them, in kN
    median, low, high = _band_row(out).split()[5:8]
    for text in (low, median, high):
        assert f">{text}<" in html, text  # a cell of its own
    assert len(re.findall(r'<img[^>]+src="data:image/png;base64,', html)) >= 5  # the prediction's plot too


def test_the_prediction_plot_draws_before_after_and_band(result):
    import matplotlib.pyplot as plt

    ax = result.prediction.plot()
    try:
        ticks = [t.get_text().replace("\n", " ") for t in ax.get_xticklabels()]
        assert ticks == [o.words for o in result.prediction.spec.outputs]
        labels = ax.get_legend_handles_labels()[1]
        assert labels == ["tested model", "updated model", "median, 95 % band"]
        # drawn relative to the tested model: it at 1, the updated model at its ratio
        p = result.prediction
        tested, updated = (np.asarray(c.get_offsets())[:, 1] for c in ax.collections[:2])
        np.testing.assert_allclose(tested, 1.0)
        np.testing.assert_allclose(updated, p.updated / p.prior, rtol=1e-12)
    finally:
        plt.close(ax.figure)


def test_no_identifiable_value_means_the_models_value_and_no_band(tmp_path):
    """A scatter limit no value meets: nothing is identifiable, every value held at the model's; the
    prediction is the model's value, and the result says that no band is claimed."""
    path = _variant(tmp_path, "damping_error = 0.05", "damping_error = 0.05\nmax_uncertainty = 1e-12")
    r = get("modes-from-test").run(mechdyn.load(path), **LIGHT)
    assert not np.any(r.update.identifiable)
    p = r.prediction
    assert p.band is None and np.all(np.isnan(p.median)) and np.all(np.isnan(p.low))
    np.testing.assert_array_equal(p.updated, p.prior)
    s = r.summary()
    assert s["prediction_samples"] == 0
    entry = s["predicted"]["transmitted_force_max_N"]
    assert entry == {"tested_model_N": p.prior[0], "updated_model_N": p.prior[0], "band": False}
    said = "no updated value is identifiable from the measured modes, so the prediction is the model's value"
    assert any(said in w for w in r.warnings)
    table = next(t for t in r.tables() if t.title.startswith("prediction"))
    assert said in table.note and all(row[3] is None and row[4] is None for row in table.rows)


def test_without_an_update_the_prediction_is_the_tested_models_value(tmp_path):
    r = get("modes-from-test").run(mechdyn.load(TAP_TEST), no_update=True, **LIGHT)
    p = r.prediction
    assert r.update is None and p.band is None
    np.testing.assert_array_equal(p.updated, p.prior)
    assert any("nothing was updated" in w and "no band is claimed" in w for w in r.warnings)


def test_few_samples_are_said_to_give_wide_intervals(tmp_path):
    path = _variant(tmp_path, "samples = 32", "samples = 8")
    r = get("modes-from-test").run(mechdyn.load(path), **LIGHT)
    assert r.prediction.band is not None and r.prediction.band.Y.shape == (8, 3)
    assert any("8 samples (fewer than 32)" in w and "wide" in w for w in r.warnings)


@pytest.mark.parametrize(
    ("old", "new", "location", "message"),
    [
        ('analysis = "support"', 'analysis = "suport"', "[predict] → analysis", "give one of 'support'"),
        (
            'analysis = "support"',
            'analysis = "modal"',
            "[predict] → analysis",
            "'modal' does not run on a support",
        ),
        (
            'output = "transmitted_force_max_N"',
            'output = "floor_force_N"',
            "[predict] → outputs #1",
            "'floor_force_N' is not an output of the support analysis",
        ),
        (
            '{ output = "natural_frequencies_hz.1" }',
            '{ output = "natural_frequencies_hz.1", unit = "kN" }',
            "[predict] → outputs #3 → unit",
            "unit 'kN' cannot show 'natural_frequencies_hz.1', which is in Hz",
        ),
        (
            '{ output = "natural_frequencies_hz.1" }',
            '{ output = "transmitted_force_max_N" }',
            "[predict] → outputs",
            "'transmitted_force_max_N' given twice",
        ),
        ("samples = 32", "samples = 4", "[predict] → samples", "4: give at least 8 samples"),
        (
            "samples = 32",
            'samples = 40\nmethod = "qmc"',
            "[predict] → samples",
            "give samples = 16 × 2^k (e.g. 32)",
        ),
        ("cycles = 1", "speed = 1", "[predict] → options → speed", "has no option 'speed' to run with"),
        ("cycles = 1", "cycles = 0", "[predict] → options → cycles", "0 is below the least value, 1"),
        ("seed = 1", 'seed = "one"', "[predict] → seed", "integer"),
    ],
)
def test_bad_input_names_the_file_field_value_and_fix(tmp_path, old, new, location, message):
    path = _variant(tmp_path, old, new)
    with pytest.raises(ModelFileError) as info:
        mechdyn.load(path)
    err = info.value
    assert err.path.endswith("test.toml") and err.location == location, (err.location, str(err))
    assert message in str(err), str(err)


def test_an_output_that_is_not_a_number_is_named_when_run(tmp_path):
    """A list named without its entry is refused as the analysis first runs, before any sampling."""
    path = _variant(tmp_path, '"natural_frequencies_hz.1"', '"natural_frequencies_hz"')
    with pytest.raises(ModelFileError) as info:
        get("modes-from-test").run(mechdyn.load(path), no_update=True, **LIGHT)
    err = info.value
    assert err.location == "[predict] → outputs #3" and "natural_frequencies_hz.1" in str(err)


def test_the_commands_samples_are_checked_as_the_files(tmp_path):
    with pytest.raises(ModelFileError, match="give at least 8 samples"):
        get("modes-from-test").run(mechdyn.load(TAP_TEST), samples=5, no_update=True, **LIGHT)
    text = _variant(tmp_path, "samples = 32", "samples = 32").read_text()
    bare = tmp_path / "bare.toml"
    bare.write_text(text[: text.index("\n[predict]\n")])
    from mechdyn.measurement.updating import UpdateError

    with pytest.raises(UpdateError, match="the file has no \\[predict\\] table"):
        get("modes-from-test").run(mechdyn.load(bare), samples=16, no_update=True, **LIGHT)
