"""After a study has run, its values appear in the units its study file gives (the database stays SI):
in its HTML report, on the dashboard's study page and in `mechdyn results export --csv`; a study built
in Python (no file units) shows SI with the SI unit named. Parquet stays SI, each column's unit in its
metadata. A tiny factorial study of the four-bar (four variants, the base design also a point of the
grid): the crank-side point B in mm, the coupler's mass in kg, the driving torque in N·mm and the
shaking force without a unit (so in N)."""

from __future__ import annotations

import html as htmllib
import json
import re
import tomllib
import urllib.request
from contextlib import contextmanager

import pytest

from conftest import EXAMPLES, serving
from mechdyn.cli.main import main
from mechdyn.store import ResultStore
from mechdyn.studies.storage import StudyStore

STUDY = """\
# a tiny study of the four-bar, in the units a designer reads (§ 7 of the spec)
[study]
name = "units-shown"
kind = "factorial"
model = "fourbar.toml"
analysis = "mechanism"
description = "B moved by 1 %, the coupler 25 % heavier (§ 7)"
options = { angles = 36 }

[[parameters]]
path = "points.B.x"
levels = ["0 %", "1 %"]

[[parameters]]
path = "bodies.coupler.mass"
levels = ["1.2 kg", "1500 g"]

[[outputs]]
output = "driving_torque_peak_Nm"
unit = "N*mm"

[[outputs]]
output = "shaking_force_max_N"
"""

TORQUE = "driving_torque_peak_Nm"
FORCE = "shaking_force_max_N"


def _g(x: float) -> str:
    """A number as the report and the dashboard write it (:func:`mechdyn.numbers.number_text`: five
    significant digits; a whole number of up to seven digits in full)."""
    from mechdyn.numbers import number_text

    return number_text(x)


@pytest.fixture(scope="module")
def ran(tmp_path_factory):
    """The study run once from its file (with its report), then reported from the database alone."""
    d = tmp_path_factory.mktemp("units")
    (d / "fourbar.toml").write_text((EXAMPLES / "fourbar.toml").read_text())
    (d / "study.toml").write_text(STUDY, encoding="utf-8")
    db = str(d / "r.db")
    assert main(["study", str(d / "study.toml"), "--db", db, "--report", str(d / "run.html")]) == 0
    assert main(["report", "--study", "units-shown", "--db", db, "-o", str(d / "stored.html")]) == 0
    with ResultStore(db, read_only=True) as store:
        studies = StudyStore(store)
        variants = studies.variants("units-shown")
        definition = studies.study("units-shown").definition
    assert len(variants) == 4 and all(v.status == "ok" for v in variants)
    return {"dir": d, "db": db, "variants": variants, "definition": definition}


def _text(page: str) -> str:
    """The page's text, tags dropped and entities read, images left out."""
    page = re.sub(r'src="data:image/png;base64,[^"]+"', "", page)
    return htmllib.unescape(re.sub(r"<[^>]+>", " ", page))


def _section(page: str, title: str) -> str:
    m = re.search(rf"<h2>{title}</h2>(.*?)</section>", page, re.S)
    assert m, title
    return m.group(1)


def _headers(fragment: str) -> list[str]:
    return [htmllib.unescape(h) for h in re.findall(r"<th(?:\s[^>]*)?>(.*?)</th>", fragment)]


def _rows(fragment: str) -> list[list[str]]:
    body = fragment.split("<tbody>", 1)[1]
    return [
        [htmllib.unescape(c) for c in re.findall(r"<td[^>]*>(.*?)</td>", row)]
        for row in re.findall(r"<tr>(.*?)</tr>", body, re.S)
    ]


# -- the HTML report -------------------------------------------------------------------------------


@pytest.mark.parametrize("which", ["run", "stored"])
def test_the_report_shows_every_variant_in_the_study_files_units(ran, which):
    page = (ran["dir"] / f"{which}.html").read_text()
    variants = _section(page, "Variants")
    assert _headers(variants) == [
        "variant", "status", "points.B.x [mm]", "bodies.coupler.mass [kg]", f"{TORQUE} [N*mm]",
        f"{FORCE} [N]", "error",
    ]  # fmt: skip
    rows = {int(r[0]): r for r in _rows(variants)}
    assert len(rows) == 4
    for v in ran["variants"]:
        row = rows[v.id]
        assert row[2] == _g(v.parameters["points.B.x"] * 1e3)  # m → mm
        assert row[3] == _g(v.parameters["bodies.coupler.mass"])
        assert row[4] == _g(v.outputs[TORQUE] * 1e3)  # N·m → N·mm
        assert row[5] == _g(v.outputs[FORCE])  # no unit asked: SI, named
        assert _g(v.outputs[TORQUE]) not in page and _g(v.parameters["points.B.x"]) not in page  # no SI
    parameters = _section(page, "Parameters")
    assert _headers(parameters)[0] == "parameter [unit]"
    names = [r[0] for r in _rows(parameters)]
    assert names == ["points.B.x [mm]", "bodies.coupler.mass [kg]"]
    assert _rows(parameters)[0][1] == "194.61"


def test_the_reports_variant_counts_add_up(ran):
    """Four variants (the base design is also a point of the grid: counted once): all evaluated by the
    run, all found stored by the report made from the database."""
    for which, evaluated, reused in (("run", 4, 0), ("stored", 0, 4)):
        text = " ".join(_text((ran["dir"] / f"{which}.html").read_text()).split())
        assert f"variants 4 = {evaluated} evaluated now + {reused} reused (found stored); none failed" in text
        assert f"variants evaluated now reused failed 4 {evaluated} {reused} 0" in text, which


def test_the_report_shows_the_study_file_as_toml_without_escapes(ran):
    run = _section((ran["dir"] / "run.html").read_text(), "Study file")
    assert "(§ 7 of the spec)" in htmllib.unescape(run)  # the file as written, its comment too
    page = (ran["dir"] / "stored.html").read_text()
    assert "\\u00a7" not in page and "\\u" not in _text(page)
    stored = _section(page, "Study file")
    assert "comments are not kept" in stored
    text = htmllib.unescape(re.search(r"<pre>(.*?)</pre>", stored, re.S).group(1))
    assert "(§ 7)" in text and "[study]" in text and "[[parameters]]" in text
    assert tomllib.loads(text) == ran["definition"]  # what the database holds, written back as TOML


def test_toml_text_reads_back_every_kind_of_value():
    from mechdyn.reports.html import toml_text

    data = {
        "top": 1,
        "study": {"name": '§ "quoted" \\ tab\t', "options": {"angles": 36, "on": True}, "x": 1.5e-9},
        "parameters": [{"path": "a.b", "levels": ["-10 %", 2, 3.25]}, {"path": "c", "tie": [], "q": {}}],
        "with space": {"k-1": [[1, 2], ["a"]]},
        "nan": float("inf"),
    }
    text = toml_text(data)
    assert "\\u00a7" not in text and "§" in text
    assert tomllib.loads(text) == data


# -- mechdyn results export ------------------------------------------------------------------------


def test_the_csv_export_is_in_the_study_files_units_with_the_unit_in_each_header(ran):
    import pandas as pd

    out = ran["dir"] / "v.csv"
    assert main(["results", "export", "--study", "units-shown", "--db", ran["db"], "--csv", str(out)]) == 0
    frame = pd.read_csv(out)
    assert list(frame.columns) == [
        "variant", "status", "error", "parameter:points.B.x [mm]", "parameter:bodies.coupler.mass [kg]",
        f"output:{TORQUE} [N*mm]", f"output:{FORCE} [N]",
    ]  # fmt: skip
    by_id = {v.id: v for v in ran["variants"]}
    for _, row in frame.iterrows():
        v = by_id[int(row["variant"])]
        assert row["parameter:points.B.x [mm]"] == pytest.approx(v.parameters["points.B.x"] * 1e3, rel=1e-9)
        assert row[f"output:{TORQUE} [N*mm]"] == pytest.approx(v.outputs[TORQUE] * 1e3, rel=1e-9)
        assert row[f"output:{FORCE} [N]"] == pytest.approx(v.outputs[FORCE], rel=1e-9)


def test_the_parquet_export_stays_si_and_names_each_columns_unit(ran):
    import pandas as pd
    import pyarrow.parquet as pq

    out = ran["dir"] / "v.parquet"
    args = ["results", "export", "--study", "units-shown", "--db", ran["db"], "--parquet", str(out)]
    assert main(args) == 0
    schema = pq.read_schema(out)
    units = {f.name: (f.metadata or {}).get(b"unit", b"?").decode() for f in schema}
    shown = {f.name: (f.metadata or {}).get(b"shown_unit", b"?").decode() for f in schema}
    assert units["parameter:points.B.x"] == "m" and shown["parameter:points.B.x"] == "mm"
    assert units["parameter:bodies.coupler.mass"] == "kg"
    assert units[f"output:{TORQUE}"] == "N*m" and shown[f"output:{TORQUE}"] == "N*mm"
    assert units[f"output:{FORCE}"] == "N"
    frame = pd.read_parquet(out)
    v = ran["variants"][0]
    row = frame[frame["variant"] == v.id].iloc[0]
    assert row[f"output:{TORQUE}"] == v.outputs[TORQUE]  # SI, exactly as stored
    assert row["parameter:points.B.x"] == v.parameters["points.B.x"]


def test_export_help_says_which_units_each_format_has(capsys):
    with pytest.raises(SystemExit):
        main(["results", "export", "--help"])
    out = " ".join(capsys.readouterr().out.split())
    assert "--csv is for people" in out and "the unit in the column's header" in out
    assert "--parquet is for programs: SI" in out and 'field metadata "unit"' in out


# -- the dashboard ----------------------------------------------------------------------------------


@contextmanager
def _dashboard(db: str):
    """The dashboard over ``db`` served by uvicorn on a free local port."""
    from mechdyn.dashboard.app import create_app

    with serving(create_app(db)) as url:
        yield url


def _get(url: str) -> str:
    with urllib.request.urlopen(url) as r:
        assert r.status == 200
        return r.read().decode()


def _study_id(db: str, name: str) -> int:
    with ResultStore(db, read_only=True) as store:
        return StudyStore(store).study(name).id


def _plotted(address: str, study_id: int, page: str) -> tuple[list[str], dict]:
    """The axis titles a study page gives Plotly and the points it fetches for its plots (one row
    of values per variant; seven significant digits, as the plots carry them)."""
    axes = json.loads(re.search(r"const axes = (\[.*?\]), levels = ", page).group(1))
    data = json.loads(_get(f"{address}/api/studies/{study_id}/points"))
    return axes, {"ids": data["ids"], "values": [list(r) for r in zip(*data["values"], strict=True)]}


def _findings(address: str, study_id: int) -> str:
    """The study's findings, once worked out (in the background: asked again until ready)."""
    import time

    for _ in range(1200):
        with urllib.request.urlopen(f"{address}/studies/{study_id}/findings") as r:
            if r.status == 200:
                return r.read().decode()
        time.sleep(0.1)
    raise AssertionError("the findings never came")


def test_the_dashboards_study_page_shows_the_study_files_units(ran):
    sid = _study_id(ran["db"], "units-shown")
    with _dashboard(ran["db"]) as address:
        page = _get(f"{address}/studies/{sid}")
        compare = _get(f"{address}/compare?variant={ran['variants'][1].id}")
        axes, data = _plotted(address, sid, page)
        findings = _findings(address, sid)
    assert axes == ["points.B.x [mm]", "bodies.coupler.mass [kg]", f"{TORQUE} [N*mm]", f"{FORCE} [N]"]
    assert "[SI]" not in page
    by_id = {v.id: v for v in ran["variants"]}
    for i, values in zip(data["ids"], data["values"], strict=True):
        v = by_id[i]
        assert values == pytest.approx(
            [v.parameters["points.B.x"] * 1e3, v.parameters["bodies.coupler.mass"],
             v.outputs[TORQUE] * 1e3, v.outputs[FORCE]], rel=1e-6
        )  # fmt: skip
    table = page.split('<table id="variants">', 1)[1].split("</table>", 1)[0]
    assert _headers(table)[2:6] == axes
    v = ran["variants"][0]
    row = next(r for r in _rows(table) if f">{v.id}<" in r[0])
    assert row[2:6] == [_g(v.parameters["points.B.x"] * 1e3), _g(v.parameters["bodies.coupler.mass"]),
                        _g(v.outputs[TORQUE] * 1e3), _g(v.outputs[FORCE])]  # fmt: skip
    # the study file as TOML, what the database holds, "§" as itself
    text = htmllib.unescape(re.search(r"<h2>Study file</h2>.*?<pre>(.*?)</pre>", page, re.S).group(1))
    assert tomllib.loads(text) == ran["definition"] and "(§ 7)" in text
    # the counts of its findings add up
    assert "variants evaluated now reused failed 4 0 4 0" in " ".join(_text(findings).split())
    # picked variants compared: the outputs in the study's units too
    side = " ".join(_text(compare).split())
    w = ran["variants"][1]
    assert f"{TORQUE.removesuffix('_Nm').replace('_', ' ')} N*mm {_g(w.outputs[TORQUE] * 1e3)}" in side


# -- a study built in Python: SI, the SI unit named ---------------------------------------------------


@pytest.fixture(scope="module")
def python_study(tmp_path_factory):
    from dataclasses import replace

    import mechdyn
    from mechdyn.io.modelfile import read
    from mechdyn.studies import Parameter, Study, Watched, run_study

    db = str(tmp_path_factory.mktemp("python") / "r.db")
    m0 = mechdyn.load(EXAMPLES / "slider_crank.toml").model.bodies[-1].mass

    def slider_mass(model, value):
        return replace(model, bodies=(*model.bodies[:-1], replace(model.bodies[-1], mass=value)))

    study = Study(
        "built-in-python",
        "oat",
        read(EXAMPLES / "slider_crank.toml"),
        "mechanism",
        (Parameter.function("slider mass", slider_mass, m0, levels=(2.0 * m0,), unit="kg"),),
        (Watched("inertia_force_max_N", "N", ""), Watched("stroke_m", "m", "")),
        options={"angles": 36},
    )
    result = run_study(study, db)
    assert result.failed == 0
    return db, result


def test_a_study_built_in_python_is_shown_in_si_with_the_si_unit_named(python_study, tmp_path):
    import pandas as pd

    from mechdyn.reports.html import render, study_report

    db, result = python_study
    labels = ["slider mass [kg]", "inertia_force_max_N [N]", "stroke_m [m]"]
    v = result.variants[0]
    si = [v.parameters["slider mass"], v.outputs["inertia_force_max_N"], v.outputs["stroke_m"]]
    # the dashboard
    sid = _study_id(db, "built-in-python")
    with _dashboard(db) as address:
        page = _get(f"{address}/studies/{sid}")
        axes, data = _plotted(address, sid, page)
    assert axes == labels
    assert data["values"][data["ids"].index(v.id)] == pytest.approx(si, rel=1e-6)
    assert "Values in SI" in page and "Built in Python" in page
    # the CSV export
    out = tmp_path / "p.csv"
    assert main(["results", "export", "--study", "built-in-python", "--db", db, "--csv", str(out)]) == 0
    frame = pd.read_csv(out)
    assert list(frame.columns)[3:] == [f"parameter:{labels[0]}", *(f"output:{x}" for x in labels[1:])]
    row = frame[frame["variant"] == v.id].iloc[0]
    assert list(row.iloc[3:]) == pytest.approx(si, rel=1e-9)
    # the report of the run
    report = render(study_report(result))
    assert _headers(_section(report, "Variants"))[2:5] == labels
    assert "Built in Python: no study file." in report
