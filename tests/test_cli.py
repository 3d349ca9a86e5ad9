"""The command line, run as a user would: every example through every drivetrain analysis."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import warnings
from pathlib import Path

import pytest

from conftest import EXAMPLES, ROOT
from mechdyn.cli.main import main
from mechdyn.errors import ModelWarning

DRIVETRAIN_EXAMPLES = sorted(p for p in EXAMPLES.glob("*.toml") if 'type = "drivetrain"' in p.read_text())
MECHANISM_EXAMPLES = sorted(
    p
    for p in EXAMPLES.glob("*.toml")
    if 'type = "mechanism"' in p.read_text() or 'type = "planting_mechanism"' in p.read_text()
)
SUPPORT_EXAMPLES = sorted(p for p in EXAMPLES.glob("*.toml") if 'type = "support"' in p.read_text())
MOUNT_EXAMPLES = sorted(p for p in EXAMPLES.glob("*.toml") if 'type = "mount"' in p.read_text())
DRIVE_EXAMPLES = sorted(p for p in EXAMPLES.glob("*.toml") if 'type = "drive"' in p.read_text())
# a measurement file beside its data (tests/test_measurement_file.py runs it through the command line)
MEASUREMENT_EXAMPLES = sorted(EXAMPLES.glob("measured/*.toml"))
GEAR_EXAMPLES = sorted(
    p
    for p in EXAMPLES.glob("*.toml")
    if 'type = "gear_pair"' in p.read_text() or 'type = "tooth_pair"' in p.read_text()
)


def _one_by_default(examples: list[Path], kept: str) -> list:
    """The examples of a kind with every one but ``kept`` in CI's heavy step: each runs its analyses
    through the command line with plots (slow), which the golden, protocol, table and plot tests
    cover in the default run; the default run keeps one example of each kind on this path."""
    assert any(p.name == kept for p in examples), kept
    return [p if p.name == kept else pytest.param(p, marks=pytest.mark.slow) for p in examples]


def test_every_example_is_run_by_one_of_the_tests():
    lists = [
        DRIVETRAIN_EXAMPLES,
        MECHANISM_EXAMPLES,
        SUPPORT_EXAMPLES,
        MOUNT_EXAMPLES,
        GEAR_EXAMPLES,
        DRIVE_EXAMPLES,
        MEASUREMENT_EXAMPLES,
    ]
    for p in [*EXAMPLES.glob("*.toml"), *EXAMPLES.glob("measured/*.toml")]:
        assert sum(p in group for group in lists) == 1, p.name


@pytest.fixture
def db(tmp_path, monkeypatch):
    path = tmp_path / "cli.db"
    monkeypatch.setenv("MECHDYN_DB", str(path))
    monkeypatch.chdir(tmp_path)
    return path


def run_json(capsys, *argv):
    assert main([*argv, "--json"]) == 0
    out = capsys.readouterr().out
    return json.loads(out)


def test_there_are_drivetrain_examples():
    assert {p.name for p in DRIVETRAIN_EXAMPLES} >= {"turret_indexing.toml", "turret_milling.toml"}


@pytest.mark.parametrize(
    "example", _one_by_default(DRIVETRAIN_EXAMPLES, "turret_milling.toml"), ids=lambda p: p.stem
)
def test_every_example_runs_every_analysis(example, db, capsys, tmp_path):
    plots = tmp_path / "plots"
    doc = run_json(capsys, "modal", str(example), "--compare-rigid", "--plots", str(plots))
    assert doc["rigid_body_modes"] == 1
    f = doc["frequencies_hz"]
    assert f == sorted(f) and f[0] > 0
    assert len(doc["modes"]) == len(f) and set(doc["modes"][0]["shape"]) >= {"1", "2"}
    assert all(c["flexible_mode"] for c in doc["comparison"])
    camp = run_json(capsys, "campbell", str(example), "--plots", str(plots))
    assert camp["lines"] and camp["frequencies_hz"] == pytest.approx(f)
    resp = run_json(capsys, "frf", str(example), "--plots", str(plots), "--points", "200")
    assert resp["peaks"]
    for name in ("mode_shapes.png", "mode_shapes_rigid.png", "campbell.png", "frf.png"):
        png = plots / name
        assert png.stat().st_size > 10_000 and png.read_bytes()[:4] == b"\x89PNG"
    # all three runs are stored, with the model text and its hash
    assert main(["results", "list", "--json"]) == 0
    runs = json.loads(capsys.readouterr().out)
    assert [r["analysis"] for r in runs] == ["frf", "campbell", "modal"]
    assert main(["results", "show", str(doc["run_id"]), "--json"]) == 0
    shown = json.loads(capsys.readouterr().out)
    assert shown["model_text"] == example.read_text()
    assert shown["scalars"]["frequencies_hz"] == pytest.approx(f)
    assert shown["arrays"]["mode_shapes"]["shape"][1] == len(f)


@pytest.mark.parametrize("example", GEAR_EXAMPLES, ids=lambda p: p.stem)
def test_every_gear_example_runs(example, db, capsys, tmp_path):
    doc = run_json(capsys, "gear", str(example), "--plots", str(tmp_path / "plots"))
    assert {"mesh_stiffness_mean_N_per_m", "iso_c_prime_N_per_mm_um", "iso_c_gamma_N_per_mm_um"} <= set(doc)
    if 'type = "gear_pair"' in example.read_text():
        assert 12 <= doc["iso_c_prime_N_per_mm_um"] <= 14
        assert (
            doc["mesh_stiffness_min_N_per_m"]
            < doc["mesh_stiffness_mean_N_per_m"]
            < doc["mesh_stiffness_max_N_per_m"]
        )
        assert (tmp_path / "plots" / "mesh_stiffness.png").stat().st_size > 10_000
    else:
        assert doc["pair_stiffness_hertz_twice_N_per_m"] < doc["pair_stiffness_N_per_m"]
        assert doc["mesh_stiffness_mean_N_per_m"] is None  # no gear geometry, so no mesh cycle
    assert main(["gear", str(example)]) == 0
    assert "stiffness along the line of action" in capsys.readouterr().out


@pytest.mark.parametrize(
    "example", _one_by_default(MECHANISM_EXAMPLES, "press_link_drive.toml"), ids=lambda p: p.stem
)
def test_every_mechanism_example_runs(example, db, capsys, tmp_path):
    csv = tmp_path / "table.csv"
    doc = run_json(
        capsys,
        "mechanism",
        str(example),
        "--plots",
        str(tmp_path / "plots"),
        "--csv",
        str(csv),
        "--angles",
        "120",
    )
    assert doc["power_balance_residual_relative"] < 1e-10
    header = csv.read_text().splitlines()[0].split(",")
    assert {"angle_deg", "driving_torque_Nm", "shaking_force_x_N", "shaking_force_y_N"} <= set(header)
    assert all(
        h.rsplit("_", 1)[-1] in {"deg", "s", "m", "N", "Nm", "s2", "W"} or h.endswith("_m_per_s")
        for h in header
    )
    for name in ("inertia_forces.png", "driving_torque.png", "frames.png"):
        assert (tmp_path / "plots" / name).stat().st_size > 10_000
    if "stroke_m" in doc:
        assert {
            "bdc_deg",
            "tdc_deg",
            "inertia_force_max_N",
            "inertia_force_max_deg",
            "inertia_force_min_N",
            "inertia_force_min_deg",
        } <= set(doc)


@pytest.mark.parametrize("example", DRIVE_EXAMPLES, ids=lambda p: p.stem)
def test_every_drive_example_runs_with_its_plots_table_and_documented_keys(example, db, capsys, tmp_path):
    csv, plots = tmp_path / "drive.csv", tmp_path / "plots"
    doc = run_json(capsys, "drive", str(example), "--plots", str(plots), "--csv", str(csv))
    assert doc["energy_balance_residual_relative"] < 1e-9  # over one periodic cycle
    assert 0 < doc["speed_fluctuation_ratio"] < 0.2 and doc["startup_settled_s"] > 0
    assert doc["motor_torque_peak_Nm"] >= doc["motor_torque_rms_Nm"] >= doc["motor_torque_mean_Nm"] > 0
    documented = set(re.findall(r"`([A-Za-z_0-9]+)`", (ROOT / "docs" / "cli.md").read_text()))
    assert set(doc) <= documented, sorted(set(doc) - documented)
    assert csv.read_text().splitlines()[0].startswith("angle_deg") or "," in csv.read_text()
    assert len(list(plots.glob("*.png"))) == len(doc["plots"]) >= 3


@pytest.mark.parametrize(
    "example", _one_by_default(SUPPORT_EXAMPLES, "press_on_mounts.toml"), ids=lambda p: p.stem
)
def test_every_support_example_runs(example, db, capsys, tmp_path):
    csv = tmp_path / "steady.csv"
    plots = tmp_path / "plots"
    doc = run_json(capsys, "support", str(example), "--plots", str(plots), "--csv", str(csv), "--cycles", "6")
    assert {
        "inertia_force_range_N",
        "transmitted_force_range_N",
        "displacement_max_m",
        "displacement_min_m",
        "natural_frequencies_hz",
    } <= set(doc)
    # quasi-static: the transmitted force follows the inertia force (published: 86 against 83 tonf)
    assert 1.0 < doc["transmitted_force_range_N"] / doc["inertia_force_range_N"] < 1.05
    assert doc["startup_last_cycle_deviation_relative"] < 1e-5
    assert doc["force_balance_residual_N"] < 1e-3
    header = csv.read_text().splitlines()[0].split(",")
    assert {"time_s", "crank_angle_deg", "z_m", "exciting_force_z_N", "floor_force_z_N"} <= set(header)
    names = ["displacement.png", "forces.png", "transmitted_vs_exciting.png"]
    if len(doc["natural_frequencies_hz"]) == 6:  # one degree of freedom has no modes plot
        names += ["modes.png", "mount_forces.png", "mode_shapes.png"]
        assert doc["elastic_centre_m"] == pytest.approx([0.0, 0.0, 0.0], abs=1e-12)
    for name in names:
        assert (plots / name).stat().st_size > 10_000
    assert main(["support", str(example)]) == 0
    out = capsys.readouterr().out
    assert "transmitted force range" in out


def test_there_are_the_mount_examples():
    names = {p.name for p in MOUNT_EXAMPLES}
    assert {"pad_shore60.toml", "anchor_concrete.toml", "wedge_mount.toml", "mount_frf.toml"} <= names


@pytest.mark.parametrize("example", _one_by_default(MOUNT_EXAMPLES, "press_pad.toml"), ids=lambda p: p.stem)
def test_every_mount_example_runs(example, db, capsys, tmp_path):
    plots = tmp_path / "plots"
    doc = run_json(capsys, "mount", str(example), "--plots", str(plots))
    assert doc["stiffness_N_per_m"] > 0 and isinstance(doc["breakdown"], dict)
    expected = {
        "pad": {"pad_curve.png"},
        "bolted": {"fe_convergence.png", "contact_pressure.png", "calibration.png"},
    }
    names = {Path(p).name for p in doc["plots"]}
    assert expected.get(doc["mount_type"], set()) <= names
    assert all(Path(p).stat().st_size > 10_000 for p in doc["plots"])
    if "contact" in doc:  # the published anchor: three preloads against 1.7 MPa
        assert [c["preload_N"] for c in doc["contact"]] == [2000.0, 4000.0, 6000.0]
        assert doc["pressure_threshold_Pa"] == 1.7e6
        assert doc["calibration"]["parameter"] == "cone_angle" and 15 < doc["calibration"]["value_deg"] < 30
        assert doc["calibration"]["record_id"] >= 1
    if "frf_fit" in doc:
        assert doc["frf_fit"]["stiffness_N_per_m"] == pytest.approx(1.2e7, rel=0.03)
        assert doc["frf_fit"]["damping_ratio"] == pytest.approx(0.08, rel=0.05)
    assert main(["mount", str(example)]) == 0
    assert "stiffness along the main axis" in capsys.readouterr().out


def test_a_stored_calibration_is_used_in_the_next_prediction(db, capsys, tmp_path):
    anchor = (EXAMPLES / "anchor_concrete.toml").read_text()
    first = run_json(capsys, "mount", str(EXAMPLES / "anchor_concrete.toml"))
    later = tmp_path / "later.toml"
    later.write_text(anchor.split("[fe]")[0] + "[calibration]\nuse_stored = true\n")
    doc = run_json(capsys, "mount", str(later))
    assert doc["applied_calibration"]["provenance"].startswith("axisymmetric FE")
    assert doc["member_stiffness_N_per_m"] == pytest.approx(first["fe_stiffness_N_per_m"], rel=1e-9)
    assert doc["stiffness_N_per_m"] < doc["stiffness_as_drawn_N_per_m"]


def test_support_command_refuses_a_mechanism(db, capsys):
    assert main(["support", str(EXAMPLES / "slider_crank.toml")]) == 2
    assert 'this command needs type = "support"' in capsys.readouterr().err


def test_the_planting_mechanism_from_the_command_line(db, capsys, tmp_path):
    plots = tmp_path / "plots"
    doc = run_json(
        capsys, "mechanism", str(EXAMPLES / "transplanter_rp1.toml"), "--plots", str(plots), "--angles", "72"
    )
    assert {
        "shaking_force_x_range_N",
        "shaking_force_y_range_N",
        "driving_torque_max_Nm",
        "tooth_force_max_N",
    } <= set(doc)
    assert doc["power_balance_residual_relative"] < 1e-9
    assert 20 < doc["tooth_force_max_N"] < 200 and doc["shaking_force_x_range_N"] > 1
    for name in ("trajectory.png", "joint_forces.png", "driving_torque.png", "shaking_force_polar.png"):
        assert (plots / name).stat().st_size > 10_000


def test_slider_crank_cli_figures(db, capsys):
    doc = run_json(capsys, "mechanism", str(EXAMPLES / "slider_crank.toml"))
    assert doc["stroke_m"] == pytest.approx(0.2) and (doc["bdc_deg"], doc["tdc_deg"]) == (180.0, 0.0)
    assert doc["inertia_force_max_N"] == pytest.approx(10625.0)


def test_gear_command_refuses_a_drivetrain(db, capsys):
    assert main(["gear", str(EXAMPLES / "turret_milling.toml")]) == 2
    assert "is not a gear model" in capsys.readouterr().err


def test_rigid_gears_flag_merges_the_meshing_disks(db, capsys):
    flex = run_json(capsys, "modal", str(EXAMPLES / "turret_milling.toml"))
    rigid = run_json(capsys, "modal", str(EXAMPLES / "turret_milling.toml"), "--rigid-gears")
    assert len(flex["frequencies_hz"]) == 6 and len(rigid["frequencies_hz"]) == 4
    shape = rigid["modes"][0]["shape"]
    assert shape["2"] == pytest.approx(-shape["4"]) and shape["5"] == pytest.approx(-shape["6"])


def test_table_output_is_readable(db, capsys):
    assert main(["modal", str(EXAMPLES / "turret_indexing.toml"), "--compare-rigid"]) == 0
    out, err = capsys.readouterr()
    assert "natural frequencies" in out and "mode shapes" in out and "strain energy per element" in out
    assert "paired by shape" in out and "stored as run 1" in out
    assert "792.3" in out  # lowest flexible mode of the indexing path, Hz
    assert "frequency [Hz]" in out and "[%]" in out  # units in brackets survive the table renderer
    assert err.count("warning:") == 2  # the published ratio inconsistencies


def test_cli_options_override_the_file(db, capsys):
    doc = run_json(
        capsys, "campbell", str(EXAMPLES / "turret_milling.toml"), "--speed-range", "0 rpm", "1000 rpm"
    )
    assert doc["speed_range_rpm"] == pytest.approx([0, 1000])
    doc = run_json(
        capsys,
        "frf",
        str(EXAMPLES / "turret_milling.toml"),
        "--excite",
        "1",
        "--frequency-range",
        "100 Hz",
        "1 kHz",
        "--points",
        "50",
        "--damping",
        "0.05",
    )
    assert doc["frequency_range_hz"] == pytest.approx([100, 1000]) and doc["points"] == 50


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["modal", "missing.toml"], "missing.toml: no such file"),
        (["campbell", "bad.toml"], "bad.toml: [[disks]] #1 (name = 'a') → inertia: '3 kg' is in kg"),
        (["results", "show", "42"], "no results database at"),  # read-only: never creates one
        (["frf", "nores.toml"], "no excitation; add a [response] table, or pass --excite DISK"),
        (["campbell", "nores.toml"], "no speed range"),
    ],
)
def test_errors_exit_2_with_a_message(db, capsys, tmp_path, argv, message):
    (tmp_path / "bad.toml").write_text(
        '[model]\ntype = "drivetrain"\n[[disks]]\nname = "a"\ninertia = "3 kg"\n'
    )
    (tmp_path / "nores.toml").write_text(
        '[model]\ntype = "drivetrain"\n[[disks]]\nname = "a"\ninertia = "3 kg*m^2"\n'
    )
    assert main(argv) == 2
    out, err = capsys.readouterr()
    assert message in err and "Traceback" not in err and out == ""


def test_bad_option_value_is_refused(db, capsys):
    with pytest.raises(SystemExit) as info:
        main(["campbell", str(EXAMPLES / "turret_milling.toml"), "--speed-range", "0 kg", "1 rpm"])
    assert info.value.code == 2
    assert "speed '0 kg'" in capsys.readouterr().err


def test_the_documentation_documents_every_json_key(db, capsys):
    """Every output key an analysis registers (the summary can hold no other: the protocol test
    checks that) is named on the command line's page; one real run shows its keys are among them."""
    from mechdyn.registry import analyses

    page = (ROOT / "docs" / "cli.md").read_text()
    documented = set(re.findall(r"`([A-Za-z_0-9]+)`", page))
    for name, analysis in analyses().items():
        keys = {o.key for o in analysis.outputs}
        assert keys <= documented, f"{name}: undocumented JSON keys {sorted(keys - documented)}"
    keys = set(run_json(capsys, "support", str(EXAMPLES / "press_on_mounts.toml"), "--cycles", "2"))
    assert keys <= documented, sorted(keys - documented)


def test_installed_entry_point(db):
    out = subprocess.run(
        [
            sys.executable,
            "-m",
            "mechdyn",
            "modal",
            str(EXAMPLES / "turret_milling.toml"),
            "--json",
            "--db",
            str(db),
        ],
        capture_output=True,
        text=True,
        check=True,
    )
    assert json.loads(out.stdout)["frequencies_hz"][0] == pytest.approx(1101.275, rel=1e-5)


PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]


@pytest.mark.parametrize("page", PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_the_python_examples_of_the_readme_and_the_documentation_run(page, monkeypatch):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    monkeypatch.chdir(ROOT)
    blocks = re.findall(r"```python\n(.*?)```", page.read_text(), flags=re.S)
    try:
        for code in blocks:
            with warnings.catch_warnings():  # the published turret data warn of their gear ratios
                warnings.simplefilter("ignore", ModelWarning)
                exec(compile(code, str(page.relative_to(ROOT)), "exec"), {})
    finally:
        plt.close("all")


def test_a_model_without_flexible_modes(db, capsys, tmp_path):
    path = tmp_path / "one.toml"
    path.write_text('[model]\ntype = "drivetrain"\n[[disks]]\nname = "a"\ninertia = "1 kg*m^2"\n')
    doc = run_json(capsys, "modal", str(path), "--plots", str(tmp_path / "p"))
    assert doc["frequencies_hz"] == [] and doc["rigid_body_modes"] == 1
    assert main(["modal", str(path)]) == 0
    out = capsys.readouterr().out
    assert "rigid-body modes (0 Hz)" in out and "mode shapes" not in out


def test_a_large_model_gets_its_lowest_modes_and_a_short_table(db, capsys, tmp_path):
    # all modes of a 10⁴-disk chain are GBs and a 10⁴-row table nobody reads: the CLI computes the
    # lowest 20 (and says so) and prints the head and tail of long tables; --json keeps every value
    n = 300
    rows = ['[model]\ntype = "drivetrain"\nname = "long chain"\n']
    rows += [f'[[disks]]\nname = "d{i}"\ninertia = "0.01 kg*m^2"\n' for i in range(n)]
    rows += [
        f'[[shafts]]\nname = "s{i}"\ndisks = ["d{i}", "d{i + 1}"]\nstiffness = "1e5 N*m/rad"\n'
        for i in range(n - 1)
    ]
    path = tmp_path / "chain.toml"
    path.write_text("\n".join(rows))
    assert main(["modal", str(path)]) == 0
    out, err = capsys.readouterr()
    assert "300 disks: computing the lowest 20 flexible modes" in err
    assert f"({n - 35} of {n} rows not shown; --json has every value)" in out
    assert main(["modal", str(path), "--modes", "3", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert len(doc["frequencies_hz"]) == 3 and len(doc["modes"][0]["shape"]) == n


def test_the_isolation_table_says_whether_the_mount_isolates_or_amplifies(db, capsys):
    """A negative isolation efficiency is an amplification, and the table says so in words."""
    for name, word in (
        ("pad_shore60.toml", "amplifies: the floor gets 1.51 times"),
        ("mount_frf.toml", "isolates: 59 %"),
    ):
        assert main(["mount", str(EXAMPLES / name)]) == 0
        out = capsys.readouterr().out
        assert f"The mount {word}" in out, name
        assert not re.search(r"^verdict ", out, flags=re.M)  # a sentence under the table, not in a cell
        assert max(len(line) for line in out.splitlines()) <= 110, name


def test_a_transmissibility_of_one_is_not_called_an_amplification():
    from mechdyn.mounts.tables import isolation_verdict

    assert isolation_verdict(1.0003).startswith("passes the disturbing force to the floor almost unchanged")
    assert isolation_verdict(0.9990).startswith("passes") and isolation_verdict(1.2).startswith("amplifies")
    assert isolation_verdict(0.41).startswith("isolates: 59 %")
    # far below the natural frequency a T of 1 is the quasi-static mount, not the √2 crossover
    assert "near √2 times the natural frequency" in isolation_verdict(1.0003, 1.4)
    assert "far below the natural frequency (quasi-static)" in isolation_verdict(1.0003, 0.1)


def test_the_readme_first_session_is_what_the_command_prints(tmp_path):
    """The README's first session, output and warnings included, is what a newcomer sees."""
    import shutil

    readme = (ROOT / "README.md").read_text()
    block = re.search(r"## A first session\n\n```console\n\$ (.*?)\n(.*?)```", readme, flags=re.S)
    assert block, "the README has no first session"
    command, shown = block.group(1), block.group(2)
    shutil.copytree(EXAMPLES, tmp_path / "examples")
    run = subprocess.run(
        [sys.executable, "-m", "mechdyn", *command.split()[1:]],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        env={**os.environ, "MECHDYN_DB": "", "MPLBACKEND": "Agg"},
        check=True,
    )
    printed = run.stderr + run.stdout
    assert [ln.rstrip() for ln in printed.splitlines()] == [ln.rstrip() for ln in shown.splitlines()]


@pytest.mark.parametrize("file_type", ["drivetrain", "mechanism", "support", "mount", "study"])
def test_fields_prints_every_table_and_field_of_a_file_type_from_its_schema(file_type, capsys):
    """`mechdyn fields TYPE`: the reference the documentation renders, in the terminal, without the
    built site: every table, every field with its unit, default and meaning."""
    from mechdyn.io.modelfile import schema_of
    from mechdyn.io.reference import reference

    assert main(["fields", file_type]) == 0
    out = capsys.readouterr().out
    tables, undocumented = reference(file_type)
    assert not undocumented
    for t in tables:
        assert f"\n{t.header}  (" in out, t.header
        for f in t.fields:
            assert f"  {f.name}: " in out, (t.header, f.name)
    assert set(schema_of(file_type).model_fields) <= {t.path.split(".")[0] for t in tables}
    assert main(["fields", file_type, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert [d["header"] for d in doc] == [t.header for t in tables]


def test_fields_of_an_unknown_type_names_the_known_ones(capsys):
    assert main(["fields", "gearbox"]) == 2
    err = capsys.readouterr().err
    assert "no file type 'gearbox'; give one of drive, drivetrain" in err and "support" in err


def test_the_command_exits_without_the_collector_walking_every_object_again(monkeypatch):
    import gc
    from importlib.metadata import entry_points

    import mechdyn.cli.main as cli

    frozen: list[bool] = []
    monkeypatch.setattr(cli, "main", lambda: 3)
    monkeypatch.setattr(gc, "freeze", lambda: frozen.append(True))
    assert cli.console() == 3  # main's exit status, once main has returned
    assert frozen == [True]
    (script,) = [e for e in entry_points(group="console_scripts") if e.name == "mechdyn"]
    assert script.value == "mechdyn.cli.main:console"  # the installed command, as `python -m mechdyn`
