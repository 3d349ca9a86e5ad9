"""Study parameters that are not quantities: whole numbers (a tooth count) and choices (a material by
name, an option, another mount file), with levels; `--paths` lists them with what they take; an output
that is empty for the base design is refused before any work."""

from __future__ import annotations

import json
import re
import textwrap
from pathlib import Path

import numpy as np
import pytest

import mechdyn
from conftest import EXAMPLES
from mechdyn.io.modelfile import read
from mechdyn.registry import get
from mechdyn.store import ResultStore
from mechdyn.studies import Evaluator, ModelTree, Parameter, StudyError, load_study, recompute, run_study
from mechdyn.studies.storage import StudyStore

PAD_A = """
[model]
type = "mount"
name = "pad A"

[pad]
shore_a = 60
length = "300 mm"
width = "300 mm"
thickness = "30 mm"
"""

PAD_B = """
[model]
type = "mount"
name = "pad B"

[pad]
material = "rubber shore 60"
diameter = "300 mm"
thickness = "25 mm"
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
mount = "pad_a.toml"

[[mounts]]
name = "right"
position = ["1 m", "0 m", "0 m"]
mount = "pad_b.toml"

[excitation]
period = "0.1 s"
harmonics = [[1, "1 kN", "0 deg"]]

[analysis]
dofs = "planar"
start_up_cycles = 1
"""

OUTPUTS = ("natural_frequencies_hz.1", "transmitted_force_range_N", "static_deflection_m.right")


def machine(tmp_path: Path, pad_a: str = PAD_A, pad_b: str = PAD_B, name: str = "machine.toml") -> Path:
    """A machine on two elastomer pads: one by its Shore hardness, one by its material's name."""
    (tmp_path / "pad_a.toml").write_text(pad_a)
    (tmp_path / "pad_b.toml").write_text(pad_b)
    (tmp_path / name).write_text(MACHINE)
    return tmp_path / name


def gears(tmp_path: Path, teeth: int = 19) -> Path:
    """The mill turret's driving path with its meshes from gear data (truncated-triangle teeth: fast)."""
    text = (EXAMPLES / "turret_milling_gear_data.toml").read_text()
    pinion = 'pinion = { teeth = 19, module = "2.119 mm"'
    assert pinion in text
    text = text.replace(pinion, f'pinion = {{ teeth = {teeth}, module = "2.119 mm"')
    text = text.replace("[[meshes]]", 'tooth_model = "truncated"\n\n[[meshes]]', 1)
    p = tmp_path / f"gears_{teeth}.toml"
    p.write_text(text)
    return p


def study(tmp_path: Path, body: str, name: str = "study.toml") -> Path:
    p = tmp_path / name
    p.write_text(textwrap.dedent(body))
    return p


def hand_written(path: Path, analysis: str, **options: object) -> dict:
    """The analysis of a model file as a user would run it."""
    run = get(analysis)
    if run.uses_store:
        options.setdefault("store", None)
    return run.run(mechdyn.load(path), **options).summary()


def output(summary: dict, key: str) -> float:
    node: object = summary
    for part in key.split("."):
        node = node[int(part) - 1] if isinstance(node, list) else node[part]  # type: ignore[index]
    return float(node)  # type: ignore[arg-type]


# -- choices and whole numbers with levels -----------------------------------------------------------


def test_a_factorial_over_a_material_name_and_a_shore_hardness_equals_hand_written_files(tmp_path):
    machine(tmp_path)
    path = study(
        tmp_path,
        """
        [study]
        name = "pads"
        kind = "factorial"
        model = "machine.toml"
        analysis = "support"

        [[parameters]]
        path = "mounts.left.mount.pad.shore_a"
        levels = [50, "+10 %"]

        [[parameters]]
        path = "mounts.right.mount.pad.material"
        name = "rubber"
        levels = ["rubber shore 40", "rubber shore 70"]

        [[outputs]]
        output = "natural_frequencies_hz.1"
        [[outputs]]
        output = "transmitted_force_range_N"
        [[outputs]]
        output = "static_deflection_m.right"
        """,
    )
    s = load_study(path)
    shore, rubber = s.parameters
    assert not shore.discrete and shore.levels == pytest.approx([50.0, 66.0])  # a number the schema reads
    assert rubber.choices == ("rubber shore 60", "rubber shore 40", "rubber shore 70")
    assert rubber.base == 0.0 and rubber.levels == (1.0, 2.0)  # the row holds the index of the name
    assert [rubber.shown(x) for x in (0.0, 1.0, 2.0)] == list(rubber.choices)
    assert rubber.relative(2.0) is None
    db = str(tmp_path / "r.db")
    result = run_study(s, db)
    grid = [v for v in result.variants if v.given["rubber"] != "rubber shore 60"]
    assert len(grid) == 4 and all(v.status == "ok" for v in result.variants)
    assert {v.given["rubber"] for v in grid} == {"rubber shore 40", "rubber shore 70"}
    assert all(isinstance(x, float) for v in grid for x in v.parameters.values())
    # every variant equals the model written by hand with its values
    for v in grid:
        hardness, material = v.parameters[shore.name], rubber.shown(v.parameters["rubber"])
        d = tmp_path / f"by_hand_{v.id}"
        d.mkdir()
        machine(
            d,
            PAD_A.replace("shore_a = 60", f"shore_a = {hardness!r}"),
            PAD_B.replace('"rubber shore 60"', f'"{material}"'),
        )
        by_hand = hand_written(d / "machine.toml", "support")
        for key in OUTPUTS:
            assert v.outputs[key] == output(by_hand, key), (v.given, key)
    # the harder the rubber on the right, the less it deflects; the tables name the material
    f = {
        v.given["rubber"]: v.outputs["static_deflection_m.right"] for v in grid if v.given[shore.name] == "50"
    }
    assert f["rubber shore 70"] < f["rubber shore 40"]
    cells = {str(c) for t in result.tables() for r in t.rows for c in r}
    assert {"rubber shore 40", "rubber shore 70"} <= cells


def test_a_choice_is_exported_and_plotted_by_its_name(tmp_path):
    """A choice's column holds the index of its level in the database; the CSV and Parquet exports
    write the level's name, and the dashboard plots the index on an axis labelled with the names."""
    import urllib.request

    import pandas as pd

    from conftest import serving
    from mechdyn.cli.main import main
    from mechdyn.dashboard.app import create_app

    machine(tmp_path)
    path = study(
        tmp_path,
        """
        [study]
        name = "rubbers"
        kind = "oat"
        model = "machine.toml"
        analysis = "support"

        [[parameters]]
        path = "mounts.right.mount.pad.material"
        name = "rubber"
        levels = ["rubber shore 40", "rubber shore 70"]

        [[outputs]]
        output = "static_deflection_m.right"
        unit = "mm"
        """,
    )
    db = str(tmp_path / "r.db")
    result = run_study(load_study(path), db)
    names = {v.id: v.given["rubber"] for v in result.variants}
    assert set(names.values()) == {"rubber shore 60", "rubber shore 40", "rubber shore 70"}
    for fmt in ("csv", "parquet"):
        out = tmp_path / f"v.{fmt}"
        assert main(["results", "export", "--study", "rubbers", "--db", db, f"--{fmt}", str(out)]) == 0
        frame = pd.read_csv(out) if fmt == "csv" else pd.read_parquet(out)
        column = next(c for c in frame.columns if c.startswith("parameter:rubber"))
        assert {int(i): r for i, r in zip(frame["variant"], frame[column], strict=True)} == names, fmt
    with ResultStore(db, read_only=True) as store:
        sid = StudyStore(store).study("rubbers").id
    with serving(create_app(db)) as address:
        with urllib.request.urlopen(f"{address}/studies/{sid}") as r:
            page = r.read().decode()
        with urllib.request.urlopen(f"{address}/api/studies/{sid}/points") as r:
            data = json.loads(r.read())
    every = json.loads(re.search(r"levels = (\[.*?\]), roles = ", page).group(1))
    levels = every[0]
    assert levels == ["rubber shore 60", "rubber shore 40", "rubber shore 70"] and every[1] == []
    for i, x in zip(data["ids"], data["values"][0], strict=True):
        assert levels[int(x)] == names[i]  # a number on the axis, its tick the level's name
    assert "tickvals" in page and "ticktext: levels[i]" in page


def test_an_oat_over_a_tooth_count_equals_the_gear_data_written_by_hand(tmp_path):
    model = gears(tmp_path)
    path = study(
        tmp_path,
        f"""
        [study]
        name = "teeth"
        kind = "oat"
        model = "{model.name}"
        analysis = "modal"

        [[parameters]]
        path = "gear_pairs.*.pinion.teeth"
        levels = [17, 21.0]

        [[outputs]]
        output = "frequencies_hz.2"
        """,
    )
    s = load_study(path)
    (teeth,) = s.parameters
    assert teeth.integer and teeth.base == 19 and teeth.levels == (17.0, 21.0)
    assert teeth.shown(21.0) == "21" and teeth.relative(21.0) == pytest.approx(2 / 19)
    (loc,) = teeth.locations
    assert teeth.file_values(21.0) == {loc: 21} and isinstance(teeth.file_values(21.0)[loc], int)
    result = run_study(s, str(tmp_path / "r.db"))
    by_level = {v.given["gear_pairs.*.pinion.teeth"]: v for v in result.variants}
    assert set(by_level) == {"19", "17", "21"}
    for z in (17, 21):
        by_hand = hand_written(gears(tmp_path, z), "modal")
        assert by_level[str(z)].outputs["frequencies_hz.2"] == by_hand["frequencies_hz"][1]
    assert by_level["17"].outputs["frequencies_hz.2"] != by_level["21"].outputs["frequencies_hz.2"]


def test_a_mount_file_and_an_option_are_choices_and_a_stored_variant_is_recomputed_from_the_store(tmp_path):
    # the right pad swapped for another mount file (the mount type is the model file a row names), and
    # the analysis' degrees of freedom; recomputed from the stored files after the file on disk changed
    machine(tmp_path)
    (tmp_path / "pad_c.toml").write_text(PAD_B.replace('"rubber shore 60"', '"rubber shore 75"'))
    path = study(
        tmp_path,
        """
        [study]
        name = "mount-type"
        kind = "factorial"
        model = "machine.toml"
        analysis = "support"

        [[parameters]]
        path = "mounts.right.mount"
        levels = ["pad_a.toml", "pad_c.toml"]

        [[parameters]]
        path = "analysis.dofs"
        levels = ["planar", "spatial"]

        [[outputs]]
        output = "static_deflection_m.right"
        """,
    )
    s = load_study(path)
    swap, dofs = s.parameters
    assert swap.choices == ("pad_b.toml", "pad_a.toml", "pad_c.toml")
    assert dofs.choices == ("planar", "spatial")
    db = str(tmp_path / "r.db")
    result = run_study(s, db)
    by = {(v.given["mounts.right.mount"], v.given["analysis.dofs"]): v for v in result.variants}
    assert len(by) == 5 and all(v.status == "ok" for (_, dofs), v in by.items() if dofs == "planar")
    # the option reached the model: two mounts on one line cannot hold the machine in space
    for f in ("pad_a.toml", "pad_c.toml"):
        assert by[f, "spatial"].status == "failed" and "do not resist rolling" in by[f, "spatial"].error
    # the right mount as the left one's pad (hand-written: both rows name pad_a.toml)
    d = tmp_path / "by_hand"
    d.mkdir()
    machine(d)
    (d / "machine.toml").write_text(MACHINE.replace('mount = "pad_b.toml"', 'mount = "pad_a.toml"'))
    by_hand = hand_written(d / "machine.toml", "support")
    assert by["pad_a.toml", "planar"].outputs["static_deflection_m.right"] == output(
        by_hand, "static_deflection_m.right"
    )
    stored = by["pad_c.toml", "planar"]
    (tmp_path / "pad_c.toml").write_text(PAD_B)  # the file on disk changes; the study stored its own
    again = recompute(db, stored.id, batch=False)
    assert again.outputs["static_deflection_m.right"] == stored.outputs["static_deflection_m.right"]


def test_the_batch_groups_variants_by_their_whole_numbers_and_equals_one_by_one(tmp_path):
    # a mechanism's batch varies the slide's mass as a column; the crank angles per revolution (a whole
    # number) cannot be a column: each value is one batch on the model file written with it
    (tmp_path / "press.toml").write_text((EXAMPLES / "press_link_drive.toml").read_text())
    tree = ModelTree(read(tmp_path / "press.toml"))
    (angles,) = Parameter.from_spec(tree, "settings.n_angles", levels=[180, 720])
    (mass,) = Parameter.from_spec(tree, "bodies.slide.mass", levels=["-10 %", "+10 %"])
    X = np.array([[a, m] for a in (180.0, 360.0, 720.0) for m in mass.levels])
    keys = ["inertia_force_max_N", "driving_torque_peak_Nm"]
    batched = Evaluator(tree.source, "mechanism", [angles, mass], keys)
    got = batched(X)
    assert batched.batch  # the batch took the block
    single = Evaluator(tree.source, "mechanism", [angles, mass], keys, batch=False)(X)
    for a, b in zip(got, single, strict=True):
        assert a.status == b.status == "ok"
        for k in keys:
            assert a.outputs[k] == pytest.approx(b.outputs[k], rel=1e-9)
    coarse = [e.outputs["driving_torque_peak_Nm"] for e in got[:2]]
    fine = [e.outputs["driving_torque_peak_Nm"] for e in got[4:]]
    assert coarse != fine  # the angles did reach the batch


# -- refusals -------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("row", "kind", "message"),
    [
        (
            'path = "mounts.right.mount.pad.material"\nlevels = ["rubber shore 90"]',
            "oat",
            r"study\.toml: \[\[parameters\]\] #1 \(path = 'mounts\.right\.mount\.pad\.material'\): level "
            r"'rubber shore 90' of .* is not a rubber the model accepts \(did you mean .*\); the choices: "
            r'.*"rubber shore 75"',
        ),
        (
            'path = "mounts.right.mount.pad.material"\nrange = "±10 %"',
            "oat",
            r"#1 .*is a rubber \(\"rubber shore 60\" in the model\), not a quantity: it takes levels, "
            r'not a range; give levels = \["rubber shore 30", "rubber shore 35"\] '
            r"\(studies of kind .*oat.*factorial",
        ),
        (
            'path = "mounts.right.mount.pad.material"\nlevels = ["rubber shore 40"]',
            "lhs",
            r"#1 .*is a choice \(rubber shore 60 in the model\), which takes levels, not a range: a lhs "
            r"study varies continuous ranges only\. Vary it in a study of kind .*oat.*factorial",
        ),
        (
            'path = "mounts.right.mount.pad.material"\nlevels = [40]',
            "oat",
            r"level 40 of .*; its levels are names, not numbers or changes; the choices: ",
        ),
        (
            'path = "analysis.dofs"\nlevels = ["3d"]',
            "oat",
            r"level '3d' of 'analysis\.dofs' is not an option the model accepts; the choices: "
            r'"planar", "spatial"',
        ),
        (
            'path = "analysis.start_up_cycles"\nlevels = ["+50 %"]',
            "factorial",
            r"level '\+50 %' of 'analysis\.start_up_cycles' is 1\.5, not a whole number .*give whole "
            r"numbers, e.g\. levels = \[2, 3\]",
        ),
        (
            'path = "analysis.start_up_cycles"\nlevels = ["3 cycles"]',
            "oat",
            r"'analysis\.start_up_cycles' is a whole number \(1 in the model\); give whole numbers without "
            r"a unit or quotes",
        ),
        (
            'path = "analysis.start_up_cycles"\nrange = [1, 3]',
            "oat",
            r"'analysis\.start_up_cycles' is a whole number \(1 in the model\), not a quantity: it takes "
            r"levels, not a range; give levels = \[2, 3\]",
        ),
        (
            'path = "mounts.right.mount"\nlevels = ["pad_x.toml"]',
            "oat",
            r"level 'pad_x\.toml' of 'mounts\.right\.mount': no such model file \(.*pad_x\.toml\); give a "
            r"mount model file relative to .*machine\.toml, e\.g\. .*\"pad_a\.toml\"",
        ),
        (
            'path = "mounts.right.mount"\nlevels = ["machine.toml"]',
            "oat",
            r"level 'machine\.toml' of 'mounts\.right\.mount': a 'support' model",
        ),
        (
            'path = "mounts.*.mount"\nlevels = ["pad_a.toml"]',
            "oat",
            r"'mounts\.\*\.mount' names 2 values that differ in the model \(\"pad_a\.toml\", "
            r"\"pad_b\.toml\"\); a choice sets them all to one value",
        ),
    ],
)
def test_a_level_the_model_does_not_accept_is_refused_naming_file_row_value_and_choices(
    tmp_path, row, kind, message
):
    machine(tmp_path)
    samples = "samples = 4\n" if kind == "lhs" else ""
    path = study(
        tmp_path,
        f'[study]\nname = "refused"\nkind = "{kind}"\nmodel = "machine.toml"\nanalysis = "support"\n'
        f'{samples}\n[[parameters]]\n{row}\n\n[[outputs]]\noutput = "transmitted_force_range_N"\n',
    )
    with pytest.raises(StudyError, match=message) as err:
        load_study(path)
    assert str(err.value).startswith(str(path))


def test_a_tooth_count_refuses_a_relative_level_that_is_no_whole_number(tmp_path):
    model = gears(tmp_path)
    tree = ModelTree(read(model))
    with pytest.raises(StudyError, match=r"level '\+10 %' of .* is 20\.9, not a whole number .*\[18, 20\]"):
        Parameter.from_spec(tree, "gear_pairs.*.pinion.teeth", levels=["+10 %"], where="s.toml")
    with pytest.raises(StudyError, match=r"a whole number \(19 in the model\), not a quantity"):
        Parameter.from_spec(tree, "gear_pairs.*.pinion.teeth", range="±10 %", where="s.toml")


def test_an_output_that_is_empty_for_the_base_design_is_refused_before_any_work(tmp_path):
    # no Campbell crossing below 10 rpm: crossings is an empty list, so crossings.1 has nothing to read
    model = gears(tmp_path)
    path = study(
        tmp_path,
        f"""
        [study]
        name = "crossings"
        kind = "oat"
        model = "{model.name}"
        analysis = "campbell"
        options = {{ speed_range = ["0 rpm", "10 rpm"] }}

        [[parameters]]
        path = "gear_pairs.*.pinion.teeth"
        levels = [17]

        [[outputs]]
        output = "crossings.1.speed_rpm"
        """,
    )
    db = str(tmp_path / "r.db")
    with pytest.raises(StudyError, match=r"'crossings\.1': crossings is empty for the base design"):
        run_study(load_study(path), db)
    with ResultStore(db) as store:
        assert StudyStore(store).studies() == []


# -- --paths --------------------------------------------------------------------------------------


def test_paths_list_whole_numbers_and_choices_with_their_values_and_choices(tmp_path, capsys):
    from mechdyn.cli.main import main

    machine(tmp_path)
    assert main(["study", "--paths", str(tmp_path / "machine.toml")]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert "mounts.left.mount.pad.shore_a = 60" in lines
    assert "analysis.start_up_cycles = 1  # a whole number" in lines
    assert 'analysis.dofs = "planar"  # one of "planar", "spatial"' in lines
    (material,) = [x for x in lines if x.startswith("mounts.right.mount.pad.material = ")]
    # a pad's material is an elastomer: its choices are the rubbers, not the steels and concretes
    assert re.match(r'.* = "rubber shore 60"  # a rubber: "rubber shore 30", .*"rubber shore 75"$', material)
    assert "steel" not in material
    (star,) = [x for x in lines if x.startswith("mounts.*.mount = ")]
    assert star.startswith("mounts.*.mount = (differs by row)  # a mount model file; beside it: ")
    assert '"pad_a.toml"' in star and '"pad_b.toml"' in star and "machine.toml" not in star
    assert main(["study", "--paths", str(EXAMPLES / "turret_milling_gear_data.toml"), "--json"]) == 0
    listed = {e["path"]: e for e in json.loads(capsys.readouterr().out)}
    assert listed["gear_pairs.*.pinion.teeth"] == {
        "path": "gear_pairs.*.pinion.teeth",
        "value": 19,
        "kind": "integer",
        "choices": [],
        "of": "",
        "rows": 1,
    }
    assert listed["shafts.*.stiffness"]["kind"] == "quantity"
    # names (the disks a shaft joins, a mesh's gear pair) are not values a study varies
    assert not any(
        p.startswith(("shafts.*.disks", "meshes.*.gear_pair", "campbell.reference_disk")) for p in listed
    )


@pytest.mark.parametrize("name", ["press_on_mounts.toml", "press_on_pads.toml", "anchor_concrete.toml"])
def test_every_listed_value_resolves_to_its_kind_and_mounts_star_forms_are_parameters(name, tmp_path):
    tree = ModelTree(read(EXAMPLES / name))
    entries = tree.entries()
    assert len({e.path for e in entries}) == len(entries)
    for e in entries:
        locs = tree.resolve(e.path)
        assert {tree.nature(loc).kind for loc in locs} == {e.nature.kind}, e.path
    paths = [e.path for e in entries]
    if name == "press_on_mounts.toml":
        # the forms the docs recommend: every mount's stiffness (and one axis of it) at once
        for star in ("mounts.*.stiffness", "mounts.*.stiffness.z", "mounts.*.damping", "mounts.*.position.z"):
            assert paths.index(star) < paths.index(star.replace("*", "front left")), star
        assert len(tree.resolve("mounts.*.stiffness")) == 12
    if name == "press_on_pads.toml":
        # through the pad file the four rows share; a study of it loads (each value counted once)
        for star in ("mounts.*.mount", "mounts.*.mount.pad.thickness", "mounts.*.mount.pad.shore_a"):
            assert star in paths
        for f in ("press_on_pads.toml", "press_pad.toml", "press_link_drive.toml"):
            (tmp_path / f).write_text((EXAMPLES / f).read_text())
        for f in ("wedge_mount.toml",):
            (tmp_path / f).write_text((EXAMPLES / f).read_text())
        path = study(
            tmp_path,
            """
            [study]
            name = "pads"
            kind = "factorial"
            model = "press_on_pads.toml"
            analysis = "support"

            [[parameters]]
            path = "mounts.*.mount.pad.thickness"
            levels = ["-10 %"]

            [[parameters]]
            path = "mounts.*.mount"
            levels = ["wedge_mount.toml"]

            [[outputs]]
            output = "natural_frequencies_hz.1"
            """,
        )
        thickness, mount = load_study(path).parameters
        assert len(set(thickness.locations)) == 1 and len(mount.locations) == 4
        assert mount.choices == ("press_pad.toml", "wedge_mount.toml")
    if name == "anchor_concrete.toml":
        assert tree.nature(tree.resolve("bolted.nut")[0]).choices == ("nut", "tapped", "anchor")
        assert "bolted.layers.*.material" in paths and "bolted.bolt_material" in paths
