"""The measurement model file (``[model] type = "measurement"``) and its analysis ``modes-from-test``:
points mapped to model points in the file, bad input named, the test against the model (MAC, frequency
and damping errors, FRF overlays) on the command line, in the results database and in every table.

The shipped example is ``examples/measured/tap_test.toml`` (the tap test of ``machine.toml``, made
by ``make_data.py`` from mounts of 0.6, 0.7 and 2.3 MN/m).
"""

from __future__ import annotations

import json
import shutil
import warnings

import numpy as np
import pytest

import mechdyn
from conftest import EXAMPLES
from mechdyn.cli.main import main
from mechdyn.errors import ModelFileError, ModelWarning
from mechdyn.registry import get

pytest.importorskip("pyuff")

FOLDER = EXAMPLES / "measured"
TAP_TEST = FOLDER / "tap_test.toml"
LIGHT = {"bootstrap": 0, "starts": 0}
TRUE_STIFFNESS_N_PER_M = np.array([0.6e6, 0.7e6, 2.3e6])  # make_data.py's mounts, x, y, z


@pytest.fixture(scope="module")
def result():
    return get("modes-from-test").run(mechdyn.load(TAP_TEST), **LIGHT)


def test_the_points_map_to_the_mounts_of_the_tested_model():
    spec = mechdyn.load(TAP_TEST).model
    machine = mechdyn.load(FOLDER / "machine.toml").model
    assert spec.tested.type == "support" and spec.tested.name == machine.name
    assert spec.mapping == {m.name: tuple(m.position) for m in machine.mounts}
    assert (spec.f_min_hz, spec.f_max_hz) == (3.0, 28.0)
    assert spec.parameters[:3] == ("mounts.*.stiffness.x", "mounts.*.stiffness.y", "mounts.*.stiffness.z")
    assert spec.measured.H.shape == (281, 12, 2)


def test_the_test_against_the_model_before_and_after_updating(result):
    s = result.summary()
    assert s["identified_modes"] == s["paired_modes"] == 6 and s["mac_min"] > 0.99
    # the catalogue mounts were 5–9 % off in frequency; updated, a tenth of a per cent
    assert 5.0 < s["frequency_error_max_percent"] < 10.0
    assert s["updated_frequency_error_max_percent"] < 0.3
    assert s["identifiable_parameters"] == s["updated_parameters"] == 6
    for axis, truth in zip("xyz", TRUE_STIFFNESS_N_PER_M, strict=True):
        v = s["updated_values"][f"mounts.*.stiffness.{axis}"]
        assert v["identifiable"] and v["prior_N_per_m"] in (0.5e6, 0.8e6, 2.0e6)
        lo, value, hi = v["low_95_N_per_m"], v["updated_N_per_m"], v["high_95_N_per_m"]
        assert abs(value / truth - 1) < 0.01 and lo < value < hi
    # the errors are (model − measured)/measured, paired one to one
    f = result.to_frame()
    np.testing.assert_allclose(
        f["frequency_error_percent"],
        100 * (f["model_frequency_hz"] / f["measured_frequency_hz"] - 1),
        rtol=1e-12,
    )
    assert sorted(f["model_mode"]) == list(range(1, 7))


def test_the_updated_model_frf_overlays_the_measured_one_better(result):
    """In the band, the log-magnitude misfit of the updated model's FRFs at the measured points is a
    fraction of the designed model's."""
    f = result.measured.frequencies_hz
    band = (f >= result.f_min_hz) & (f <= result.f_max_hz)

    def misfit(frf):
        return float(np.sqrt(np.mean(np.log(np.abs(frf.H[band]) / np.abs(result.measured.H[band])) ** 2)))

    assert misfit(result.updated_frf) < 0.3 * misfit(result.model_frf)
    # the model's FRF is H = B (K − ω²M + iωC)⁻¹ Bᵀ in the measured kind: accelerance −ω² × receptance
    from mechdyn.measurement.synthetic import model_matrices

    M, K, C, _ = model_matrices(mechdyn.load(FOLDER / "machine.toml").model)
    w = result.measured.omega[40]
    receptance = np.linalg.inv(K - w**2 * M + 1j * w * C)
    z = 2  # the blow at point 1 along z, seen at point 1 along z: the mount's position (-1.2, -0.8, 0)
    b = np.zeros(6)
    b[z], b[3], b[4] = 1.0, -0.8, 1.2  # u_z = t_z + θ_x y − θ_y x
    assert result.model_frf.outputs[2] == ("1", "z") and result.model_frf.references[0] == ("1", "z")
    np.testing.assert_allclose(result.model_frf.H[40, 2, 0], -(w**2) * b @ receptance @ b, rtol=1e-10)


@pytest.fixture(scope="module")
def command_run(tmp_path_factory):
    """One run of the command on the tap test with its plots, its report and the updated model
    written, as JSON: the folder its files went to, the arguments and the printed document (the
    checks of the files, the store, the report and the dashboard read the same run)."""
    import contextlib
    import io

    tmp = tmp_path_factory.mktemp("command")
    argv = ["modes-from-test", str(TAP_TEST), "--bootstrap", "0", "--starts", "0", "--db", str(tmp / "r.db")]
    extra = ["--plots", str(tmp / "plots"), "--write-updated", str(tmp / "machine_updated.toml")]
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        assert main([*argv, *extra, "--report", str(tmp / "test.html"), "--json"]) == 0
    return tmp, argv, json.loads(printed.getvalue())


def test_the_command_line_plots_stores_and_writes_the_updated_model(command_run, tmp_path, capsys):
    folder, argv, doc = command_run
    written, db = folder / "machine_updated.toml", folder / "r.db"
    assert doc["analysis"] == "modes-from-test" and doc["updated_model_file"] == str(written)
    names = {p.rsplit("/", 1)[-1] for p in doc["plots"]}
    # the file's [predict] table adds the prediction's plot (tests/test_measurement_predict.py)
    assert names == {"stabilisation.png", "mac.png", "frf_overlay.png", "frequency_errors.png"} | {
        "prediction.png"
    }
    machine = mechdyn.load(written).model
    for mount in machine.mounts:
        stiffness = [doc["updated_values"][f"mounts.*.stiffness.{a}"]["updated_N_per_m"] for a in "xyz"]
        np.testing.assert_allclose(mount.stiffness, stiffness, rtol=1e-12)
    from mechdyn.store import ResultStore

    with ResultStore(str(db)) as store:
        run = store.get(doc["run_id"])
    assert run.analysis == "modes-from-test"
    # the file is written once: not kept with the run, so its report (a run again) writes nothing
    assert "write_updated" not in run.parameters and run.parameters["bootstrap"] == 0
    # compare only: no update, and nothing to write
    assert main([*argv, "--no-update"]) == 0
    out = capsys.readouterr().out
    assert "model against the test (paired by MAC)" in out and "updated values" not in out
    assert main([*argv, "--no-update", "--write-updated", str(tmp_path / "x.toml")]) != 0
    assert "nothing is updated (--no-update is given)" in capsys.readouterr().err


# -- bad input ---------------------------------------------------------------------------------------


def _variant(tmp_path, old: str, new: str):
    for name in ("machine.toml", "tap_test.uff"):
        shutil.copy(FOLDER / name, tmp_path / name)
    text = TAP_TEST.read_text()
    assert old in text
    path = tmp_path / "test.toml"
    path.write_text(text.replace(old, new, 1))
    return path


@pytest.mark.parametrize(
    ("old", "new", "location", "message"),
    [
        ('data = "tap_test.uff"', 'data = "tap.uff"', "[measurement] → data", "'tap.uff': no such file"),
        ('data = "tap_test.uff"', 'data = "machine.toml"', "[measurement] → data", "neither a Universal"),
        ('model = "machine.toml"', 'model = "m.toml"', "[measurement] → model", "'m.toml': no such file"),
        ('f_max = "28 Hz"', 'f_max = "2 Hz"', "[measurement]", "give f_min < f_max"),
        ('f_max = "28 Hz"', 'f_max = "50 Hz"', "[measurement] → f_max", "outside the data's 2 … 30 Hz"),
        ('f_min = "3 Hz"', 'f_min = "3 m"', "[measurement] → f_min", "Hz"),
        ('mount = "2"', 'mount = "7"', "[[points]] #2 (point = '2') → mount", "'7' is not a mount"),
        ('mount = "2"', 'disk = "d1"', "[[points]] #2 (point = '2') → disk", "a support has no disks"),
        ('mount = "2"', 'mount = "2"\ndisk = "d1"', "[[points]] #2", "exactly one of mount"),
        ('point = "2"', 'point = "9"', "[[points]] #2 (point = '9') → point", "not a point of the data"),
        (
            '[[points]]\npoint = "2"\nmount = "2"\n',
            "",
            "[[points]]",
            "the data's point(s) '2' map to no model point",
        ),
        ("mounts.*.stiffness.x", "mounts.*.stifness.x", "[[update]] #1 → path", "mounts.*.stifness.x"),
        # a value of 0, or of both signs, has no logarithm to update: refused as the file is read
        ("mounts.*.stiffness.x", "mounts.1.position.z", "[[update]] #1 → path", "logarithm of positive"),
        ("mounts.*.stiffness.x", "mounts.*.position.x", "[[update]] #1 → path", "logarithm of positive"),
    ],
)
def test_bad_input_names_the_file_field_value_and_fix(tmp_path, old, new, location, message):
    path = _variant(tmp_path, old, new)
    with pytest.raises(ModelFileError) as info:
        mechdyn.load(path)
    err = info.value
    assert err.path.endswith("test.toml") and err.location == location, (err.location, str(err))
    assert message in str(err)


def test_a_test_of_a_drivetrain_maps_its_points_to_disks(tmp_path):
    """A five-disk drivetrain's torsional test (CSV, rad/s² per N·m) against its own model: the
    pairs' frequency errors within a few times their scatter, MAC near 1."""
    from mechdyn.drivetrain import Disk, Drivetrain, GroundSpring, Shaft
    from mechdyn.measurement import simulate_frf

    k = (2.0e5, 1.2e5, 3.0e5, 0.8e5)  # N·m/rad
    disks = [Disk(f"d{i}", J) for i, J in enumerate((0.8, 0.5, 1.2, 0.4, 0.9))]
    shafts = [Shaft(f"s{i}", (f"d{i}", f"d{i + 1}"), k[i], damping=5e-5 * k[i]) for i in range(4)]
    model = Drivetrain(disks, [*shafts, GroundSpring("g", "d0", 1.0e5)])
    mechdyn.save(model, tmp_path / "drivetrain.toml")
    outputs = tuple((f"p{i}", "rz") for i in range(5))
    mapping = {f"p{i}": f"d{i}" for i in range(5)}
    meas = simulate_frf(model, outputs, outputs[:1], np.arange(1.0, 200.0, 0.1), mapping, seed=4)
    header = ["frequency [Hz]"] + [
        f"{p}:rz/p0:rz {part} [rad/s^2/(N*m)]" for p, _ in outputs for part in ("re", "im")
    ]
    cols = [meas.frequencies_hz] + [part(meas.H[:, o, 0]) for o in range(5) for part in (np.real, np.imag)]
    rows = np.column_stack(cols)
    (tmp_path / "torsion.csv").write_text(
        ",".join(header) + "\n" + "\n".join(",".join(f"{v:.12g}" for v in r) for r in rows) + "\n"
    )
    points = "".join(f'[[points]]\npoint = "p{i}"\ndisk = "d{i}"\n\n' for i in range(5))
    (tmp_path / "torsion.toml").write_text(
        '[model]\ntype = "measurement"\nname = "torsion test"\n\n[measurement]\ndata = "torsion.csv"\n'
        'model = "drivetrain.toml"\nf_min = "2 Hz"\nf_max = "150 Hz"\nbootstrap = 0\n\n' + points
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        r = get("modes-from-test").run(mechdyn.load(tmp_path / "torsion.toml"))
    s = r.summary()
    assert s["paired_modes"] == s["identified_modes"] >= 3 and s["mac_min"] > 0.99
    c = r.before
    assert np.all(np.abs(c.model_hz - c.measured_hz) < 5 * c.measured_scatter_hz + 1e-3 * c.measured_hz)
    assert r.update is None and "updated_values" not in s


def test_the_report_and_the_dashboard_show_the_model_against_the_measurement(command_run):
    """The run's report and its dashboard page: the paired modes (MAC, frequency errors) before and
    after updating, the updated values, and the four pictures (stabilisation chart, MAC, FRF overlay,
    frequency errors), with nothing special written for them (the result protocol)."""
    import re
    import urllib.request

    from conftest import serving
    from mechdyn.dashboard.app import create_app

    folder, _, doc = command_run
    db, html = str(folder / "r.db"), (folder / "test.html").read_text(encoding="utf-8")
    words = ("model against the test (paired by MAC)", "updated values", "frequency error")
    for text in words:
        assert text in html, text
    assert len(re.findall(r'<img[^>]+src="data:image/png;base64,', html)) >= 4
    with serving(create_app(db)) as address:
        with urllib.request.urlopen(f"{address}/runs/{doc['run_id']}", timeout=60) as response:
            page = response.read().decode()
    assert "modes-from-test" in page and "tap test" in page.lower()
    assert "frequency error" in page and "updated values" in page
    # per paired mode, drawn from the stored arrays: the frequency errors and MAC before and after
    titles = re.findall(r'"title": \{"text": "([^"]+)"\}, "xaxis"', page)
    assert any("frequency error" in t for t in titles) and any("mac" in t.lower() for t in titles), titles
