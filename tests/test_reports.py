"""HTML reports: one self-contained file per run or study, everything from a file or a user escaped."""

from __future__ import annotations

import base64
import re

import pytest

import mechdyn
from conftest import EXAMPLES
from mechdyn.cli.main import main


def _assert_self_contained(html: str) -> None:
    """Nothing is fetched when the page is opened: no external src, href, stylesheet or script."""
    assert not re.search(r"""(src|href)\s*=\s*["'](?!data:|#)""", html)
    assert "<script" not in html.lower()
    assert "@import" not in html and "url(" not in html


def _images(html: str) -> list[bytes]:
    return [base64.b64decode(m) for m in re.findall(r'src="data:image/png;base64,([^"]+)"', html)]


def test_an_analysis_writes_its_report(tmp_path, capsys):
    out = tmp_path / "press.html"
    db = str(tmp_path / "r.db")
    assert (
        main(
            [
                "support",
                str(EXAMPLES / "press_on_support.toml"),
                "--db",
                db,
                "--report",
                str(out),
                "--cycles",
                "2",
            ]
        )
        == 0
    )
    assert f"report: {out}" in capsys.readouterr().out
    html = out.read_text()
    _assert_self_contained(html)
    for text in ("press A on its support (1 DOF)", "transmitted force range", "Checks and warnings",
                 "force balance residual", "startup last cycle deviation relative", "Model file",
                 "[excitation]", "mechdyn"):  # fmt: skip
        assert text in html, text
    # the summary in words, no table of raw SI keys beside it (the database and --json keep those)
    assert "transmitted_force_range_N" not in html and "unit (SI)" not in html
    images = _images(html)
    # displacement, forces, transmitted against exciting (a one-degree-of-freedom support has no modes plot)
    assert len(images) >= 3 and all(i.startswith(b"\x89PNG") and len(i) > 5000 for i in images)


def test_a_stored_run_is_reported_from_what_is_stored(tmp_path, capsys):
    db = str(tmp_path / "r.db")
    assert main(["modal", str(EXAMPLES / "turret_indexing.toml"), "--db", db, "--json"]) == 0
    capsys.readouterr()
    out = tmp_path / "run.html"
    assert main(["report", "1", "--db", db, "--output", str(out)]) == 0
    html = out.read_text()
    _assert_self_contained(html)
    m = re.search(r"agrees with the stored one to ([0-9.e+-]+) \(relative\)", html)
    assert m and float(m.group(1)) < 1e-12
    assert "frequencies" in html and "frequencies_hz" not in html and "run</dt><dd>1 in" in html


def test_a_study_report_has_its_views(tmp_path, capsys):
    db = str(tmp_path / "r.db")
    study = EXAMPLES / "studies" / "press_support_influence.toml"
    out = tmp_path / "study.html"
    assert main(["study", str(study), "--db", db, "--report", str(out)]) == 0
    capsys.readouterr()
    html = out.read_text()
    _assert_self_contained(html)
    for text in ("press-support-influence", "one at a time", "support.stiffness", "tornado", "Study file",
                 "levels = [&#34;-10 %&#34;"):  # fmt: skip
        assert text in html, text
    again = tmp_path / "again.html"
    assert main(["report", "--study", "press-support-influence", "--db", db, "-o", str(again)]) == 0
    assert "one at a time" in again.read_text()


def test_text_from_a_model_file_is_escaped(tmp_path, capsys):
    evil = "<script>alert(1)</script>"
    text = (
        (EXAMPLES / "fourbar.toml").read_text().replace('name = "crank-rocker four-bar"', f'name = "{evil}"')
    )
    model = tmp_path / "evil.toml"
    model.write_text(text)
    out = tmp_path / "evil.html"
    assert (
        main(
            ["mechanism", str(model), "--db", str(tmp_path / "r.db"), "--report", str(out), "--angles", "36"]
        )
        == 0
    )
    capsys.readouterr()
    html = out.read_text()
    assert evil not in html and "&lt;script&gt;alert(1)&lt;/script&gt;" in html
    _assert_self_contained(html)


def test_a_report_needs_a_run_or_a_study(tmp_path, capsys):
    assert main(["report", "--db", str(tmp_path / "r.db"), "-o", str(tmp_path / "x.html")]) == 2
    assert "give a run id" in capsys.readouterr().err
    assert main(["report", "7", "--db", str(tmp_path / "r.db"), "-o", str(tmp_path / "x.html")]) == 2
    assert "no run with id 7" in capsys.readouterr().err


@pytest.mark.parametrize("command", [["report", "--help"]])
def test_the_report_help_ends_with_examples(command, capsys):
    with pytest.raises(SystemExit):
        main(command)
    assert "examples:\n  mechdyn report" in capsys.readouterr().out


def test_a_run_report_opens_with_its_headline_figures_and_checks(tmp_path):
    """The figures that matter first, in words and readable units (the press: stroke in mm, torque in
    kN·m), then the checks it passed; a key the result lacks (a four-bar has no stroke) is passed over."""
    import re as _re

    from mechdyn.cli.main import main as cli
    from mechdyn.registry import get
    from mechdyn.reports.html import headline

    out = tmp_path / "press.html"
    args = ["mechanism", str(EXAMPLES / "press_link_drive.toml"), "--db", str(tmp_path / "r.db")]
    assert cli([*args, "--report", str(out)]) == 0
    lines = _re.findall(r'<p class="headline">([^<]*)</p>', out.read_text())
    expect = r"stroke 1496 mm; driving torque peak 356\.\d kN·m; shaking force max 529\.\d kN"
    assert lines and _re.match(expect, lines[0]), lines
    assert lines[1].startswith("checks: power balance residual relative ")
    # the four-bar's headline, as the report writes it (the same function), passes its stroke over
    four = get("mechanism").run(mechdyn.load(EXAMPLES / "fourbar.toml"), angles=36)
    lines = headline(four.summary(), get("mechanism").headline)
    assert _re.match(r"driving torque peak [0-9.]+ N·m", lines[0]) and "stroke" not in lines[0], lines
    assert lines[1].startswith("checks: power balance residual relative ")
