"""Self-contained HTML reports of an analysis run or a design study.

One file: the plots embedded as PNG (base64), the styles inline, nothing fetched when it is opened.
Rendered by Jinja2 with autoescaping, so that everything that comes from a model file or a user (a
model's name, a warning, the model file itself) shows as text.
"""

from __future__ import annotations

import base64
import io
import json
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

__all__ = ["Report", "render", "run_report", "study_report", "write"]

# summary keys that record a check the analysis ran (a residual, a deviation, a convergence figure)
_CHECK_WORDS = ("residual", "deviation", "convergence", "rigid_body_modes", "richardson", "error_relative")


@dataclass
class Cell:
    text: str
    css: str = ""


@dataclass
class HtmlTable:
    title: str
    columns: list[str]
    rows: list[list[Cell]]


@dataclass
class Figure:
    caption: str
    png: str  # base64


@dataclass
class Section:
    title: str
    note: str = ""
    tables: list[HtmlTable] = field(default_factory=list)
    figures: list[Figure] = field(default_factory=list)
    items: list[str] = field(default_factory=list)
    text: str | None = None


@dataclass
class Report:
    """What a report shows: a title, the facts that identify it, and its sections."""

    title: str
    subtitle: str
    meta: list[tuple[str, str]]
    sections: list[Section]


def _number(v: float) -> str:
    if v == 0:
        return "0"
    if not math.isfinite(v):
        return str(v)
    a = abs(v)
    return f"{v:.6g}" if 1e-4 <= a < 1e7 else f"{v:.4e}"


def _cell(v: Any) -> Cell:
    if v is None:
        return Cell("—")
    if isinstance(v, bool):
        return Cell("yes" if v else "no")
    if isinstance(v, (int, float)) or type(v).__module__ == "numpy":
        try:
            return Cell(_number(float(v)), "num")
        except (TypeError, ValueError):
            pass
    if isinstance(v, str) and v in ("holds", "VIOLATED"):
        return Cell(v, "holds" if v == "holds" else "fails")
    if isinstance(v, (list, tuple)) and all(isinstance(x, (int, float)) for x in v):
        return Cell(", ".join(_number(float(x)) for x in v), "num")
    if isinstance(v, (dict, list, tuple)):
        return Cell(json.dumps(v, default=str))
    return Cell(str(v))


def _table(t: Any) -> HtmlTable:
    """A :class:`mechdyn.results.Table` as HTML cells."""
    return HtmlTable(t.title, list(t.columns), [[_cell(v) for v in row] for row in t.rows])


def _png(make: Callable[[], Any]) -> str:
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    from mechdyn.plotting import plain_text

    ax = make()
    fig = ax.figure if hasattr(ax, "figure") else ax
    plain_text(fig)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110)
    plt.close(fig)
    return base64.b64encode(buf.getvalue()).decode("ascii")


def _figures(plots: Mapping[str, Callable[[], Any]]) -> list[Figure]:
    return [Figure(Path(name).stem.replace("_", " "), _png(make)) for name, make in plots.items()]


def _summary_table(summary: Mapping[str, Any], units: Mapping[str, str]) -> HtmlTable:
    """Every value of a summary, one row each; nested tables flattened (``excitation · stroke_m``),
    the unit read from the innermost key that names one."""
    from mechdyn.units import key_unit

    rows: list[list[Cell]] = []

    def add(path: list[str], value: Any, unit: str) -> None:
        if isinstance(value, Mapping):
            for k, v in value.items():
                add([*path, str(k)], v, key_unit(str(k)) or unit)
            return
        if isinstance(value, (list, tuple)) and any(isinstance(v, Mapping) for v in value):
            rows.append([Cell(" · ".join(path)), Cell(f"{len(value)} rows: see the tables below"), Cell("")])
            return
        rows.append([Cell(" · ".join(path)), _cell(value), Cell(unit if unit != "1" else "")])

    for key, value in summary.items():
        if key != "warnings":
            add([key], value, units.get(key) or key_unit(key) or "")
    return HtmlTable("", ["quantity", "value", "unit (SI)"], rows)


def _checks(summary: Mapping[str, Any]) -> HtmlTable | None:
    from mechdyn.units import key_unit

    rows = [
        [Cell(k), _cell(v), Cell(key_unit(k) or "")]
        for k, v in summary.items()
        if any(w in k for w in _CHECK_WORDS) and not isinstance(v, (dict, list))
    ]
    return HtmlTable("", ["check", "value", "unit"], rows) if rows else None


def run_report(
    result: Any,
    *,
    analysis: str,
    model_name: str,
    model_path: str,
    model_text: str,
    model_sha256: str,
    options: Mapping[str, Any] | None = None,
    warnings: Sequence[str] = (),
    run_id: int | None = None,
    created: datetime | None = None,
    database: str = "",
    note: str = "",
) -> Report:
    """The report of one analysis run.

    Parameters
    ----------
    result : Result
        The analysis' result (:mod:`mechdyn.results`): its summary, tables and plots are shown.
    analysis : str
        The registered analysis.
    model_name, model_path, model_text, model_sha256 : str
        The model file, shown as given.
    options : mapping, optional
        The analysis' options (SI).
    warnings : sequence of str
    run_id : int, optional
        Its id in the results database.
    created : datetime, optional
        When it ran (default: now).
    database : str
        Where it is stored (shown without a password).
    note : str
        A line under the summary (e.g. that the result was recomputed from the stored model).
    """
    from mechdyn import __version__
    from mechdyn.registry import get

    summary = result.summary()
    units = get(analysis).output_units
    when = created or datetime.now(UTC)
    meta = [
        ("analysis", analysis),
        ("model file", model_path),
        ("model SHA-256", model_sha256),
        ("mechdyn", __version__),
        ("run", f"{run_id} in {database}" if run_id is not None else "not stored"),
        ("date", when.strftime("%Y-%m-%d %H:%M:%S UTC")),
    ]
    if options:
        meta.append(("options", ", ".join(f"{k} = {v}" for k, v in options.items())))
    sections = [Section("Summary", note=note, tables=[_summary_table(summary, units)])]
    all_warnings = list(dict.fromkeys([*warnings, *getattr(result, "warnings", ())]))
    checks = _checks(summary)
    sections.append(
        Section(
            "Checks and warnings",
            note="" if checks else "This analysis reports no residual or convergence figure.",
            tables=[checks] if checks else [],
            items=all_warnings or ["no warnings"],
        )
    )
    sections.append(Section("Tables", tables=[_table(t) for t in result.tables()]))
    sections.append(Section("Plots", figures=_figures(result.plots())))
    sections.append(Section("Model file", note=model_path, text=model_text))
    return Report(model_name or Path(model_path).stem, f"{analysis} analysis", meta, sections)


def study_report(result: Any, *, database: str = "", study_text: str | None = None) -> Report:
    """The report of a design study: its tables and plots, the parameters, the study file and the
    model file.

    Parameters
    ----------
    result : StudyResult
        :func:`mechdyn.studies.run_study` (for a stored study, run again: every variant is reused).
    database : str
        Where it is stored.
    study_text : str, optional
        The study file as written (default: its stored content as JSON).
    """
    from mechdyn import __version__

    st = result.study
    stored = result.stored
    meta = [
        ("kind", st.kind),
        ("analysis", st.analysis),
        ("model file", st.source.path),
        ("model files SHA-256", stored.model_sha256),
        ("mechdyn", __version__),
        ("database", database),
        ("created", stored.created_at.strftime("%Y-%m-%d %H:%M:%S UTC")),
        ("variants", f"{len(result.variants)} ({result.failed} failed)"),
    ]
    params = HtmlTable(
        "",
        ["parameter", "base", "low", "high", "levels", "unit"],
        [
            [
                Cell(p.name),
                _cell(p.base / p.factor),
                _cell(None if p.low is None else p.low / p.factor),
                _cell(None if p.high is None else p.high / p.factor),
                Cell(", ".join(_number(v / p.factor) for v in p.levels) or "—"),
                Cell(p.unit),
            ]
            for p in st.parameters
        ],
    )
    sections = [
        Section("Parameters", tables=[params]),
        Section("Findings", tables=[_table(t) for t in result.tables()]),
        Section("Plots", figures=_figures(result.plots())),
        Section(
            "Study file",
            note=st.path,
            text=study_text if study_text is not None else json.dumps(st.definition, indent=2, default=str),
        ),
        Section("Model file", note=st.source.path, text=st.source.text),
    ]
    return Report(st.name, f"design study: {st.kind} of {st.analysis}", meta, sections)


def render(report: Report) -> str:
    """The report as one HTML page (Jinja2, autoescaped)."""
    from jinja2 import Environment, PackageLoader, select_autoescape

    from mechdyn import __version__

    env = Environment(
        loader=PackageLoader("mechdyn.reports", "templates"),
        autoescape=select_autoescape(default=True, default_for_string=True),
    )
    return env.get_template("report.html.j2").render(
        report=report,
        version=__version__,
        written=datetime.now(UTC).strftime("%Y-%m-%d %H:%M UTC"),
    )


def write(report: Report, path: str | Path) -> Path:
    """Render and write a report; returns the path."""
    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    p.write_text(render(report), encoding="utf-8")
    return p
