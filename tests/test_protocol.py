"""The spine: every registered analysis follows the result protocol; the command line is built from
the registry and starts without the numerical libraries."""

from __future__ import annotations

import json
import subprocess
import sys
import warnings

import numpy as np
import pandas as pd
import pytest

import mechdyn
from conftest import EXAMPLES
from mechdyn.errors import MechdynError, ModelFileError, ModelWarning
from mechdyn.io import load_model
from mechdyn.registry import Analysis, Option, Output, analyses, get
from mechdyn.results import Result
from mechdyn.units import convert, key_unit

# one example per model type, the quickest that exercises the analysis' tables and plots
EXAMPLE_OF = {
    "drivetrain": "turret_milling.toml",
    "mechanism": "transplanter_rp1.toml",
    "planting_mechanism": "transplanter_rp1_design.toml",
    "support": "press_on_mounts.toml",
    "gear_pair": "spur_pair.toml",
    "tooth_pair": "tooth_pair1_published.toml",
    "mount": "pad_shore60.toml",
    "drive": "press_driven.toml",
    "measurement": "measured/tap_test.toml",
}
OPTIONS = {
    "modes-from-test": [{"bootstrap": 0, "starts": 0}],
    "modal": [{}, {"compare_rigid": True}, {"rigid_gears": True}],
    "frf": [{"points": 40}],
    "mechanism": [{"angles": 36}],
    "support": [{"cycles": 2}],
    "drive": [{"angles": 180, "no_startup": True}],
    "simulate": [{"duration": 0.005, "initial_speed": 100.0}],
    "speed-sweep": [
        {
            "speed_range": (200.0, 300.0),
            "points": 4,
            "harmonics": 4,
            "no_stability": True,
            "no_backlash": True,
        }
    ],
}
CASES = [
    pytest.param(name, mtype, opts, id=f"{name}-{mtype}-{i}")
    for name, a in analyses().items()
    for mtype in a.model_types
    for i, opts in enumerate(OPTIONS.get(name, [{}]))
]


def _loaded(model_type):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        return load_model(EXAMPLES / EXAMPLE_OF[model_type])


def test_every_model_type_has_an_example_here():
    assert {t for a in analyses().values() for t in a.model_types} == set(EXAMPLE_OF)


@pytest.mark.parametrize(("name", "model_type", "options"), CASES)
def test_every_analysis_follows_the_result_protocol(name, model_type, options, tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from mechdyn.store import ResultStore

    analysis = get(name)
    with ResultStore(str(tmp_path / "p.db")) as store:
        kw = {"store": store} if analysis.uses_store else {}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ModelWarning)
            result = analysis.run(_loaded(model_type), **kw, **options)
    assert isinstance(result, Result)
    with pytest.raises(Exception, match=r"frozen|cannot assign"):
        result.__setattr__(next(iter(result.__dataclass_fields__)), None)
    # summary: JSON-ready, every key documented in the registry with its unit
    summary = result.summary()
    assert summary and set(summary) <= set(analysis.output_units), set(summary) - set(analysis.output_units)
    json.dumps(summary, default=float)
    # the table: units in every numeric column's name
    frame = result.to_frame()
    assert isinstance(frame, pd.DataFrame) and len(frame.columns)
    for c in frame.columns:
        if pd.api.types.is_float_dtype(frame[c]):
            assert key_unit(str(c)) is not None, f"{name}: column {c!r} names no unit"
    # arrays for the store, with units
    for key, (arr, unit) in result.arrays().items():
        assert isinstance(arr, np.ndarray) and isinstance(unit, str), key
    # tables and plots
    tables = result.tables()
    assert tables and all(len(r) == len(t.columns) for t in tables for r in t.rows)
    plots = result.plots()
    for file, draw in plots.items():
        ax = draw()
        assert ax is not None and file.endswith(".png")
        fig = ax.figure if hasattr(ax, "figure") else ax
        assert fig.axes and any(a.has_data() for a in fig.axes), file
    plt.close("all")
    assert isinstance(result.warnings, tuple)


def test_registered_outputs_have_units_and_descriptions():
    for a in analyses().values():
        assert a.help and a.outputs and a.examples, a.name
        for o in a.outputs:
            assert o.description and o.unit is not None, (a.name, o.key)
        for o in a.options:
            assert o.help and (o.kind != "quantity" or o.unit), (a.name, o.name)


def test_a_summary_key_without_a_unit_is_refused_at_registration():
    with pytest.raises(ValueError, match="no unit suffix"):
        Output("stiffness", "a stiffness")
    with pytest.raises(ValueError, match="needs its SI unit"):
        Option("speed", "quantity", "a speed")


def test_an_analysis_refuses_a_model_of_another_type_and_unknown_options():
    with pytest.raises(ModelFileError, match='this command needs type = "drivetrain"'):
        get("modal").run(_loaded("mechanism"))
    with pytest.raises(MechdynError, match="has no option 'nmodes'"):
        get("modal").run(_loaded("drivetrain"), nmodes=3)
    with pytest.raises(MechdynError, match="no analysis named 'modes'"):
        get("modes")


def test_a_model_built_in_python_runs_through_the_registry(turret_c):
    from mechdyn.drivetrain import modal

    by_registry = get("modal").run(turret_c, modes=2)
    assert by_registry.frequencies_hz == pytest.approx(modal(turret_c, n_modes=2).frequencies_hz, rel=1e-12)


def test_a_new_analysis_is_one_function_and_one_registration(monkeypatch, tmp_path, capsys):
    """Registered at run time, it gets its command, options, table, JSON, CSV and stored run."""
    from dataclasses import dataclass

    from mechdyn import registry
    from mechdyn.cli.main import main

    @dataclass(frozen=True)
    class Total(Result):
        inertia: float

        def summary(self):
            return {"total_inertia_kg_m2": self.inertia}

        def to_frame(self):
            return pd.DataFrame({"total_inertia_kg_m2": [self.inertia]})

    monkeypatch.setattr(registry, "_REGISTRY", dict(registry._REGISTRY))
    registry.register(
        Analysis(
            "total-inertia",
            ("drivetrain",),
            lambda loaded, scale=1.0: Total(scale * float(loaded.model.inertias.sum())),
            "sum of the disk inertias",
            options=(Option("scale", "float", "a factor"),),
            outputs=(Output("total_inertia_kg_m2", "sum of the inertias", "kg*m^2"),),
            examples=("mechdyn total-inertia FILE",),
        )
    )
    db, csv = tmp_path / "x.db", tmp_path / "t.csv"
    argv = ["total-inertia", str(EXAMPLES / "turret_milling.toml"), "--scale", "2", "--db", str(db)]
    assert main([*argv, "--json", "--csv", str(csv)]) == 0
    doc = json.loads(capsys.readouterr().out)
    J = _loaded("drivetrain").model.inertias.sum()
    assert doc["total_inertia_kg_m2"] == pytest.approx(2 * J) and doc["parameters"] == {"scale": 2.0}
    assert csv.read_text().startswith("total_inertia_kg_m2")
    assert main(argv) == 0 and "total inertia" in capsys.readouterr().out  # the summary in words


def test_analyses_command_lists_names_options_and_units(capsys):
    from mechdyn.cli.main import main

    assert main(["analyses", "--json"]) == 0
    doc = {a["name"]: a for a in json.loads(capsys.readouterr().out)}
    assert set(doc) == set(analyses())
    assert doc["modal"]["model_types"] == ["drivetrain"]
    assert {"name": "compare_rigid", "flag": "--compare-rigid", "kind": "flag"}.items() <= next(
        o for o in doc["modal"]["options"] if o["name"] == "compare_rigid"
    ).items()
    speed = next(o for o in doc["campbell"]["options"] if o["name"] == "speed_range")
    assert speed["unit"] == "rad/s" and speed["nargs"] == 2
    outputs = {o["key"]: o["unit"] for o in doc["mechanism"]["outputs"]}
    assert outputs["stroke_m"] == "m" and outputs["driving_torque_peak_Nm"] == "N*m"
    assert main(["analyses"]) == 0
    assert "modal" in capsys.readouterr().out


HEAVY = ("scipy", "sqlalchemy", "numba", "matplotlib", "pandas", "skfem")


@pytest.mark.parametrize(
    ("argv", "allowed"),
    [(["--help"], ()), (["analyses", "--json"], ()), (["results", "list"], ("sqlalchemy",))],
    ids=["help", "analyses", "results-list"],
)
def test_light_commands_import_no_numerical_library(argv, allowed, tmp_path):
    code = (
        "import sys\nfrom mechdyn.cli.main import main\n"
        f"try:\n    main({argv!r})\nexcept SystemExit:\n    pass\n"
        f"print(sorted(m for m in {HEAVY!r} if m in sys.modules))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        check=True,
        cwd=tmp_path,
        env={"MECHDYN_DB": str(tmp_path / "x.db"), "PATH": ""},
    )
    imported = json.loads(out.stdout.strip().splitlines()[-1].replace("'", '"'))
    assert set(imported) <= set(allowed), imported


def test_every_command_help_ends_with_examples(capsys):
    from mechdyn.cli.main import main

    commands = [[name] for name in [*analyses(), "analyses", "study", "results", "report", "dashboard"]]
    commands += [["results", sub] for sub in ("list", "show", "compare", "export", "delete")]
    for command in commands:
        with pytest.raises(SystemExit):
            main([*command, "--help"])
        assert "examples:\n  mechdyn " in capsys.readouterr().out, command


def test_display_units_come_from_the_one_registry():
    assert convert(9806.65, "N", "tonf") == pytest.approx(1.0, rel=1e-12)
    assert convert(1e6, "N/m", "kN/mm") == pytest.approx(1.0, rel=1e-12)
    assert convert(np.array([1.0, 2.0]), "m", "mm") == pytest.approx([1e3, 2e3])
    with pytest.raises(ValueError, match="cannot show N in 'mm'"):
        convert(1.0, "N", "mm")
    assert key_unit("stroke_m") == "m" and key_unit("mesh_stiffness_mean_N_per_m") == "N/m"
    assert key_unit("iso_c_prime_N_per_mm_um") == "N/(mm*um)" and key_unit("rigid_body_modes") is None


@pytest.mark.slow  # CI's heavy step (issue 48: the test command's minutes)
def test_the_first_run_says_it_compiles_and_later_runs_load_the_cache(tmp_path):
    """With an empty numba cache the first run announces the compile; the second run is silent."""
    code = (
        "from mechdyn.mechanism import cycle\nimport mechdyn\n"
        f"m = mechdyn.load({str(EXAMPLES / 'fourbar.toml')!r}).model\ncycle(m, 36)\n"
    )
    env = {"NUMBA_CACHE_DIR": str(tmp_path / "cache"), "PATH": ""}
    first = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, env=env)
    assert "compiling kernels, first run only" in first.stderr
    again = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, env=env)
    assert "compiling" not in again.stderr


@pytest.mark.parametrize("value", ["nan", "inf", "-0.1", "x"])
def test_a_numeric_option_refuses_nonsense(value, capsys):
    from mechdyn.cli.main import main

    with pytest.raises(SystemExit) as info:
        main(["frf", str(EXAMPLES / "turret_milling.toml"), "--damping", value])
    assert info.value.code == 2
    assert f"damping {value!r}: give a number of at least 0.0" in capsys.readouterr().err


def test_modal_damping_refuses_a_ratio_that_is_not_finite():
    from mechdyn.drivetrain import ModalDamping

    for bad in (float("nan"), float("inf"), (0.02, float("nan"))):
        with pytest.raises(MechdynError, match="must lie in"):
            ModalDamping(bad)


@pytest.mark.parametrize("model_type", sorted(EXAMPLE_OF))
def test_load_returns_one_shape_for_every_model_type(model_type):
    from mechdyn.io import LoadedModel

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        loaded = mechdyn.load(EXAMPLES / EXAMPLE_OF[model_type])
    assert isinstance(loaded, LoadedModel) and loaded.type == model_type
    assert loaded.source is not None and len(loaded.source.sha256) == 64
    assert loaded.model is not None and loaded.settings is not None and loaded.name


def test_loading_a_support_file_runs_no_analysis(monkeypatch):
    # the load comes from the press mechanism: its inverse dynamics runs when the load is asked for
    from mechdyn.mechanism import dynamics

    calls = []
    real = dynamics.inverse_dynamics
    monkeypatch.setattr(dynamics, "inverse_dynamics", lambda *a, **k: calls.append(a) or real(*a, **k))
    loaded = mechdyn.load(EXAMPLES / "press_on_support.toml")
    assert calls == [] and loaded.settings.mechanism_path.endswith("press_link_drive.toml")
    assert loaded.settings.load.period == pytest.approx(4.0)
    assert len(calls) == 1
    loaded.settings.dynamics, loaded.settings.load  # computed once
    assert len(calls) == 1


def test_the_parts_of_the_support_analysis_and_the_batch_follow_the_protocol():
    # what the Python API returns outside the registry: support modes and responses, the batch
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from mechdyn.mechanism import cycle
    from mechdyn.support import modes, periodic_response, startup_response

    loaded = _loaded("support")
    machine, load = loaded.model, loaded.settings.load
    mech = mechdyn.load(EXAMPLES / "fourbar.toml").model
    pts = {"B": np.asarray(mech.points["B"]) + np.array([[0.0, 0.0], [0.002, 0.0], [0.0, 0.003]])}
    batch = cycle(mech, 36, points=pts)
    from mechdyn.mechanism import variants

    rp1 = mechdyn.load(EXAMPLES / "transplanter_rp1.toml").model
    designs = variants([rp1, rp1], 24)  # gears: design by design
    parts = (
        modes(machine),
        periodic_response(machine, load),
        startup_response(machine, load, 1),
        batch,
        designs,
    )
    for r in parts:
        assert isinstance(r, Result)
        frame = r.to_frame()
        assert isinstance(frame, pd.DataFrame) and len(frame)
        assert r.summary()
        for name, make in r.plots().items():
            ax = make()
            assert ax.figure.axes and name.endswith(".png")
            plt.close("all")
    # the batch's table: one row per variant, each equal to that variant's own summary
    frame = batch.to_frame()
    assert list(frame["variant"]) == [0, 1, 2] and frame["assembled"].all()
    np.testing.assert_allclose(frame["driving_torque_peak_Nm"], batch.summary()["driving_torque_peak_Nm"])


def test_tables_take_display_units_as_keywords():
    # the press on its support in tonnes-force and metres; the pad in kN/mm: the same SI figures
    support = get("support").run(_loaded("support"), cycles=1)
    s = support.summary()
    rows = {r[0]: r for r in support.tables(force_unit="tonf", length_unit="m")[0].rows}
    assert rows["transmitted force range"][1:] == [
        pytest.approx(s["transmitted_force_range_N"] / 9806.65),
        "tonf",
    ]
    assert rows["bed displacement max"][1:] == [pytest.approx(s["displacement_max_m"]), "m"]
    # without them, each in the unit its size reads best in: the press's forces in kN, its bed in mm
    rows = {r[0]: r for r in support.tables()[0].rows}
    assert rows["transmitted force range"][1:] == [pytest.approx(s["transmitted_force_range_N"] / 1e3), "kN"]
    assert rows["bed displacement max"][1:] == [pytest.approx(s["displacement_max_m"] * 1e3), "mm"]
    mount = get("mount").run(_loaded("mount"))
    first = mount.tables(stiffness_unit="kN/mm")[0]
    label, value, unit = first.rows[0]
    assert label == "stiffness along the main axis"
    assert unit == "kN/mm" and value == pytest.approx(mount.summary()["stiffness_N_per_m"] / 1e6)


@pytest.mark.parametrize(
    ("analysis", "example", "options", "first"),
    [
        ("mechanism", "press_link_drive.toml", {"angles": 36}, "driving torque max "),
        ("modal", "turret_milling.toml", {}, "frequencies "),
        ("support", "press_on_mounts.toml", {"cycles": 1}, "inertia force max "),
        ("gear", "spur_pair.toml", {}, "contact ratio "),
    ],
)
def test_a_result_reads_in_one_line_and_as_html_tables_in_a_notebook(analysis, example, options, first):
    """The repr is one short line of the first figures in readable units (it was the whole dataclass:
    36 794 characters for a four-bar); ``_repr_html_`` shows the tables as the report does."""
    from conftest import EXAMPLES
    from mechdyn.io import load_model

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = get(analysis).run(load_model(EXAMPLES / example), **options)
    text = repr(r)
    assert text.startswith(f"<{type(r).__name__}: {first}") and len(text) < 200 and "\n" not in text, text
    html = r._repr_html_()
    for t in r.tables():
        assert f"<h4>{t.title}</h4>" in html.replace("&#x27;", "'") and "<table>" in html
