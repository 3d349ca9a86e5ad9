"""``mechdyn new TYPE``: a commented template of every model-file type, generated from its schema, that
loads and whose analysis runs as written; and the Markdown model-file reference in the checkout, which
must equal what its generator gives now (regenerate it with
``python -m mechdyn.io.reference --markdown docs/model_files/markdown``)."""

from __future__ import annotations

import math
import re
import tomllib

import pytest

import mechdyn
from conftest import ROOT
from mechdyn.cli.main import main
from mechdyn.io.modelfile import file_types
from mechdyn.io.reference import MARKDOWN_FOLDER, markdown_pages, reference, schema_tables
from mechdyn.io.template import template
from mechdyn.registry import get

# the analysis each file type is for (the first that runs on it)
ANALYSIS = {
    "drivetrain": "modal",
    "mechanism": "mechanism",
    "planting_mechanism": "mechanism",
    "support": "support",
    "mount": "mount",
    "gear_pair": "gear",
    "tooth_pair": "gear",
    "drive": "drive",
    "measurement": "modes-from-test",
}
MODEL_TYPES = [t for t in file_types() if t != "study"]


def test_every_file_type_has_a_template_and_an_analysis():
    assert set(ANALYSIS) == set(MODEL_TYPES)
    for file_type, analysis in ANALYSIS.items():
        assert file_type in get(analysis).model_types


def _sections(text: str) -> dict[str, list[str]]:
    """The template's lines by table header, comments and commented-out lines included: a header
    ``[[x]]`` or ``# [[x]]`` opens a section; a field is named by ``name =`` or ``# name =``."""
    sections: dict[str, list[str]] = {}
    current = sections.setdefault("", [])
    for line in text.splitlines():
        bare = line.removeprefix("# ").strip()
        if re.fullmatch(r"\[\[?[\w.]+\]\]?", bare):
            current = sections.setdefault(bare, [])
        else:
            current.append(bare)
    return sections


@pytest.mark.parametrize("file_type", file_types())
def test_the_template_names_every_table_and_field_of_the_schema(file_type):
    text = template(file_type)
    sections = _sections(text)
    walked = 0

    def check(t):
        nonlocal walked
        assert t.header in sections, (file_type, t.header)
        lines = sections[t.header]
        for name, field in t.fields:
            walked += 1
            assert any(line.startswith(f"{name} = ") for line in lines), (file_type, t.header, name)
            meaning = " ".join((field.description or "").replace("``", "").split())
            assert meaning[:40] in " ".join(lines), (file_type, t.header, name, "meaning")
        for child in t.children:
            check(child)

    for t in schema_tables(file_type):
        check(t)
    assert walked == sum(len(t.fields) for t in reference(file_type)[0])
    # every field has its type, and a default or "required"; no placeholder is left to fill in
    assert "required)" in text and "default" in text and '…"' not in text
    assert all(len(line) <= 100 for line in text.splitlines()), "a line longer than 100 characters"


@pytest.mark.parametrize("file_type", MODEL_TYPES)
def test_a_new_template_loads_and_its_analysis_runs(file_type, tmp_path, capsys):
    path = tmp_path / f"{file_type}.toml"
    if file_type == "drive":  # it drives the mechanism template's four-bar, in a file beside it
        assert main(["new", "mechanism", str(tmp_path / "mechanism.toml")]) == 0
    if file_type == "measurement":  # it tests the machine of examples/measured, with its data beside it
        for name in ("machine.toml", "tap_test.uff"):
            (tmp_path / name).write_bytes((ROOT / "examples" / "measured" / name).read_bytes())
    assert main(["new", file_type, str(path)]) == 0
    assert f"wrote {path}" in capsys.readouterr().out
    tomllib.loads(path.read_text())  # valid TOML as written
    loaded = mechdyn.load(path)
    assert loaded.type == file_type
    result = get(ANALYSIS[file_type]).run(loaded)
    summary = result.summary()
    assert summary
    if file_type == "drivetrain":  # two disks on a shaft: ω² = k (1/J₁ + 1/J₂)
        f = math.sqrt(2e4 * (1 / 0.02 + 1 / 0.5)) / (2 * math.pi)
        assert summary["frequencies_hz"] == [pytest.approx(f, rel=1e-9)]


def test_the_drivetrain_template_runs_every_drivetrain_analysis(tmp_path, capsys):
    """Its [campbell] and [response] tables are given, so campbell and frf run on it as written."""
    path = tmp_path / "gearbox.toml"
    assert main(["new", "drivetrain", str(path)]) == 0
    capsys.readouterr()
    for command in ("modal", "campbell", "frf"):
        assert main([command, str(path), "--db", f"sqlite:///{tmp_path / 'r.db'}"]) == 0, command
    out = capsys.readouterr().out
    assert "162.3" in out  # the shaft's mode, Hz


def test_the_study_template_runs_on_the_drivetrain_template(tmp_path):
    from mechdyn.studies import load_study, run_study

    assert main(["new", "drivetrain", str(tmp_path / "drivetrain.toml")]) == 0
    assert main(["new", "study", str(tmp_path / "study.toml")]) == 0
    study = load_study(tmp_path / "study.toml")
    result = run_study(study, str(tmp_path / "r.db"))
    summary = result.summary()
    assert summary["variants"] == 5 and summary["failed"] == 0


def test_new_prints_the_template_without_a_path(capsys):
    assert main(["new", "support"]) == 0
    out = capsys.readouterr().out
    assert out == template("support")
    assert 'type = "support"' in out and "# mechanism = " in out


def test_new_refuses_to_overwrite_a_file_unless_forced(tmp_path, capsys):
    path = tmp_path / "mine.toml"
    path.write_text("# my own model\n")
    assert main(["new", "mount", str(path)]) == 2
    err = capsys.readouterr().err
    assert f"{path} exists" in err and "--force" in err
    assert path.read_text() == "# my own model\n"
    assert main(["new", "mount", str(path), "--force"]) == 0
    assert path.read_text().startswith('# A "mount" model file')


def test_new_names_the_known_types_and_refuses_a_missing_folder(tmp_path, capsys):
    assert main(["new", "gearbox"]) == 2
    err = capsys.readouterr().err
    assert "no file type 'gearbox'; give one of drive, drivetrain" in err and "study" in err
    assert main(["new", "drivetrain", str(tmp_path / "nowhere" / "x.toml")]) == 2
    assert "is not a folder" in capsys.readouterr().err
    assert main(["new", "drivetrain", str(tmp_path)]) == 2
    assert "is a folder" in capsys.readouterr().err


def test_commented_out_fields_show_their_default_in_units_a_reader_knows():
    text = template("drivetrain")
    assert '# pressure_angle = "20 deg"' in text  # the schema holds 0.349… rad
    assert '# youngs_modulus = "206 GPa"' in text
    assert "(quantity in kg·m², > 0; optional, no default)" in text  # a disk's inertia, with its bound
    assert "(array of 2 × quantity in rad/s; required)" in text


# -- the Markdown reference ---------------------------------------------------------------------------


def test_the_markdown_reference_in_the_checkout_is_current():
    """Regenerate with ``python -m mechdyn.io.reference --markdown docs/model_files/markdown``."""
    folder = ROOT / MARKDOWN_FOLDER
    pages = markdown_pages()
    assert {p.name for p in folder.glob("*.md")} == set(pages)
    for name, text in pages.items():
        assert (folder / name).read_text(encoding="utf-8") == text, (
            f"{MARKDOWN_FOLDER}/{name} is stale: run "
            f"python -m mechdyn.io.reference --markdown {MARKDOWN_FOLDER}"
        )


@pytest.mark.parametrize("file_type", file_types())
def test_the_markdown_page_lists_every_table_and_field(file_type):
    page = markdown_pages()[f"{file_type}.md"]
    tables, _ = reference(file_type)
    for t in tables:
        assert f"## `{t.header}`" in page
        for f in t.fields:
            assert f"| `{f.name}` |" in page
    # the table rows have four cells: a | inside a meaning is escaped
    for line in page.splitlines():
        if line.startswith("| `"):
            assert len(re.findall(r"(?<!\\)\|", line)) == 5, line


def test_the_markdown_generator_writes_the_folder(tmp_path, capsys):
    from mechdyn.io.reference import main as reference_main

    assert reference_main(["--markdown", str(tmp_path)]) == 0
    assert (tmp_path / "index.md").read_text() == markdown_pages()["index.md"]
    assert "drivetrain.md" in capsys.readouterr().out
