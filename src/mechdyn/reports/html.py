"""Self-contained HTML reports of an analysis run or a design study.

One file: the plots embedded as PNG (base64), a linkage's animation as a GIF, the styles inline,
nothing fetched when it is opened.
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

from mechdyn.cells import Cell, HtmlTable, html_table, table_cell

__all__ = [
    "Report",
    "StudyViews",
    "figures_of",
    "render",
    "run_report",
    "study_report",
    "study_tables",
    "study_views",
    "table_cell",
    "toml_text",
    "variant_counts",
    "variants_table",
    "write",
]

ANIMATION_FRAMES = 72  # frames of a report's animation: one per 5° of crank angle

# summary keys that record a check the analysis ran (a residual, a deviation, a convergence figure)
_CHECK_WORDS = ("residual", "deviation", "convergence", "rigid_body_modes", "richardson", "error_relative")


@dataclass
class Figure:
    caption: str
    data: str  # base64
    mime: str = "image/png"


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
    headline: list[str] = field(default_factory=list)


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


def figures_of(
    plots: Mapping[str, Callable[[], Any]], captions: Mapping[str, str] | None = None
) -> list[Figure]:
    """A result's plots drawn as a report's figures (PNG, titled by their captions, else by their
    file names).

    Parameters
    ----------
    plots : mapping of str → callable
        File name → a function that draws the plot (``result.plots()``).
    captions : mapping of str → str, optional
        File name → the figure's caption in words.
    """
    captions = captions or {}
    return [
        Figure(captions.get(name) or Path(name).stem.replace("_", " "), _png(make))
        for name, make in plots.items()
    ]


@dataclass
class StudyViews:
    """What a study's kind leads with in its report and on its dashboard page (a tolerance study: each
    limit's probability in words, the sample size and how far to trust it, its histograms, CDFs and
    rankings); empty for a kind that shows its tables and plots alone.

    Attributes
    ----------
    title : str
        The title of the section that shows them ("" for none).
    headline : list of str
        Sentences a reader reads first (a report's header, the top of the dashboard's findings).
    note : str
        How far to trust them (a tolerance study: the sample size, the intervals' method).
    warnings : list of str
        What limits their validity.
    figures : list of Figure
        Their pictures, drawn, each with its caption.
    shown : frozenset of str
        The file names of the result's plots among ``figures`` (not drawn again under Plots).
    """

    title: str = ""
    headline: list[str] = field(default_factory=list)
    note: str = ""
    warnings: list[str] = field(default_factory=list)
    figures: list[Figure] = field(default_factory=list)
    shown: frozenset[str] = frozenset()


def study_views(result: Any) -> StudyViews:
    """The views a study's kind defines (``Kind.views(result)``, as
    :meth:`mechdyn.studies.kinds.tolerance.Tolerance.views`), its figures drawn; an empty
    :class:`StudyViews` for a kind that defines none.

    Parameters
    ----------
    result : StudyResult
        A run's result, or a stored study's.
    """
    from mechdyn.studies.kinds import kind

    got = kind(result.study.kind).views(result)
    if got is None:
        return StudyViews()
    named = [(name, caption) for name, caption, _draw in got["figures"]]
    return StudyViews(
        title=got["title"],
        headline=list(got["headline"]),
        note=got["note"],
        warnings=list(got["warnings"]),
        figures=figures_of({name: draw for name, _c, draw in got["figures"]}, dict(named)),
        shown=frozenset(name for name, _c in named),
    )


def _animations(result: Any) -> list[Figure]:
    """A result that animates (a linkage over its crank cycle, ``result.animate(path, frames)``): its
    animation as a GIF; any other result: none, at no cost."""
    animate = getattr(result, "animate", None)
    if not callable(animate):
        return []
    import tempfile

    with tempfile.TemporaryDirectory() as folder:
        gif = Path(folder) / "animation.gif"
        animate(gif, frames=ANIMATION_FRAMES)
        data = base64.b64encode(gif.read_bytes()).decode("ascii")
    return [Figure("the linkage over one crank cycle (animated)", data, "image/gif")]


def headline(summary: Mapping[str, Any], keys: Sequence[str]) -> list[str]:
    """What a reviewer reads first: the figures that matter (``keys``, an analysis' ``headline``), each
    in words and readable units, then the checks the result passed with their figure.

    Parameters
    ----------
    summary : mapping
        A result's summary (SI).
    keys : sequence of str
        Its headline keys (:attr:`mechdyn.registry.Analysis.headline`); missing ones are passed over.
    """
    from mechdyn.results import figure_text
    from mechdyn.units import key_label

    figures = []
    for k in keys:
        label, unit = key_label(k)
        shown = figure_text(summary.get(k), unit)
        if shown is not None:
            figures.append(f"{label} {shown}")
    lines = ["; ".join(figures)] if figures else []
    checks = [
        f"{key_label(k)[0]} {v:.2g}"
        for k, v in summary.items()
        if "residual" in k and isinstance(v, float) and not isinstance(v, bool)
    ]
    if checks:
        lines.append("checks: " + "; ".join(checks))
    return lines


def _checks(summary: Mapping[str, Any]) -> HtmlTable | None:
    from mechdyn.units import key_label

    rows = [
        [Cell(key_label(k)[0]), table_cell(v), Cell(key_label(k)[1])]
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
        The analysis' result (:mod:`mechdyn.results`): its summary, tables and plots are shown, and
        the animation of one that animates (a mechanism's linkage over its crank cycle).
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

    summary = result.summary()
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
    from mechdyn.results import nested_tables, summary_table

    tables = result.tables()
    # the summary in words and in the units a designer reads, its nested values as tables of their
    # own (the database and --json keep every value in SI)
    first = [t for t in tables if t.title == "summary"] or [summary_table(summary)]
    labels = [[str(r[0]) for r in t.rows] for t in tables]  # a nested value a table already shows
    nested = [t for t in nested_tables(summary) if [str(r[0]) for r in t.rows] not in labels]
    shown = [html_table(t) for t in [*first, *nested]]
    sections = [Section("Summary", note=note, tables=shown)]
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
    sections.append(Section("Tables", tables=[html_table(t) for t in tables if t.title != "summary"]))
    sections.append(Section("Plots", figures=[*_animations(result), *figures_of(result.plots())]))
    sections.append(Section("Model file", note=model_path, text=model_text))
    from mechdyn.registry import get

    lines = headline(summary, get(analysis).headline)
    return Report(model_name or Path(model_path).stem, f"{analysis} analysis", meta, sections, lines)


# the table of a study's counts (:meth:`mechdyn.studies.result.StudyResult.tables`)
_COUNT_COLUMNS = ["variants", "evaluated now", "reused", "failed"]
MAX_VARIANT_ROWS = 1000  # variants listed in a study's report (all are in `mechdyn results export`)


def variant_counts(result: Any) -> dict[str, int]:
    """A study's variants counted once each: ``variants`` = ``evaluated`` (now, by the run that made
    ``result``) + ``reused`` (found stored; all of a result read from the database alone); ``failed``
    counts the variants among them that could not be evaluated.

    Parameters
    ----------
    result : StudyResult
        A run's result, or a stored study's.

    Returns
    -------
    dict
        ``variants``, ``evaluated``, ``reused`` and ``failed`` (counts).
    """
    return {
        "variants": result.evaluated + result.reused,
        "evaluated": result.evaluated,
        "reused": result.reused,
        "failed": result.failed,
    }


def _counts_text(counts: Mapping[str, int]) -> str:
    """``4 = 1 evaluated now + 3 reused (found stored); none failed``: the counts add up."""
    f = counts["failed"]
    return (
        f"{counts['variants']} = {counts['evaluated']} evaluated now + {counts['reused']} reused (found "
        f"stored); {f'{f} of them failed' if f else 'none failed'}"
    )


def study_tables(result: Any) -> list[HtmlTable]:
    """A study's findings tables (:meth:`~mechdyn.studies.result.StudyResult.tables`, outputs in the
    study's units) as HTML cells, its counts counted once per variant (:func:`variant_counts`).

    Parameters
    ----------
    result : StudyResult
        A run's result, or a stored study's.
    """
    counts = variant_counts(result)
    tables = []
    for t in result.tables():
        table = html_table(t)
        if list(t.columns) == _COUNT_COLUMNS:
            table.rows = [[table_cell(counts[k]) for k in ("variants", "evaluated", "reused", "failed")]]
        tables.append(table)
    return tables


def variants_table(columns: Sequence[Any], variants: Sequence[Any], limit: int | None = None) -> HtmlTable:
    """One row per variant: its id, status, parameters and outputs in the study's units (the unit in
    each column's header), and its error.

    Parameters
    ----------
    columns : sequence of Column
        :func:`mechdyn.reports.columns.study_columns` or :func:`~mechdyn.reports.columns.stored_columns`.
    variants : sequence of StoredVariant
        The variants (each listed once), their values in SI.
    limit : int, optional
        At most this many rows (count).
    """
    rows = [
        [Cell(str(v.id)), Cell(v.status), *(table_cell(c.of(v)) for c in columns), Cell(v.error or "")]
        for v in list(variants)[:limit]
    ]
    return HtmlTable("", ["variant", "status", *(c.label for c in columns), "error"], rows)


def toml_text(data: Mapping[str, Any]) -> str:
    """A study file's content (as the database stores it: parsed, its comments gone) written back as
    TOML: what ``tomllib.loads`` reads back to ``data``, every character as itself (``§``, not
    ``\\u00a7``).

    Parameters
    ----------
    data : mapping
        Tables, arrays of tables and values (text, numbers, booleans, dates, lists).
    """

    def key(k: Any) -> str:
        k = str(k)
        bare = bool(k) and all(c.isascii() and (c.isalnum() or c in "_-") for c in k)
        return k if bare else json.dumps(k, ensure_ascii=False)

    def value(v: Any) -> str:
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, str):
            return json.dumps(v, ensure_ascii=False)
        if isinstance(v, float):
            return repr(v) if math.isfinite(v) else ("nan" if math.isnan(v) else "inf" if v > 0 else "-inf")
        if isinstance(v, int):
            return str(v)
        if isinstance(v, Mapping):
            return "{ " + ", ".join(f"{key(k)} = {value(x)}" for k, x in v.items()) + " }" if v else "{}"
        if isinstance(v, (list, tuple)):
            return "[" + ", ".join(value(x) for x in v) + "]"
        if hasattr(v, "isoformat"):
            return v.isoformat()
        return json.dumps(str(v), ensure_ascii=False)

    def is_rows(v: Any) -> bool:
        return isinstance(v, (list, tuple)) and bool(v) and all(isinstance(x, Mapping) for x in v)

    lines: list[str] = []

    def table(path: list[str], d: Mapping[str, Any], header: str | None) -> None:
        if header is not None:
            lines.extend(["", header] if lines else [header])
        nested = []
        for k, v in d.items():
            if isinstance(v, Mapping) and v and header is None:
                nested.append((k, v))
            elif is_rows(v):
                nested.append((k, v))
            else:
                lines.append(f"{key(k)} = {value(v)}")
        for k, v in nested:
            sub = [*path, key(k)]
            if isinstance(v, Mapping):
                table(sub, v, "[" + ".".join(sub) + "]")
            else:
                for row in v:
                    table(sub, row, "[[" + ".".join(sub) + "]]")

    table([], data, None)
    return "\n".join(lines) + "\n"


def study_report(result: Any, *, database: str = "", study_text: str | None = None) -> Report:
    """The report of a design study: its tables and plots, the parameters, every variant, the study
    file and the model file; parameters and outputs in the study file's units, the unit in each column
    header (a study built in Python: SI, the SI unit named).

    Parameters
    ----------
    result : StudyResult
        :func:`mechdyn.studies.run_study`, or :func:`mechdyn.studies.run.stored_result` for a stored
        study (read from the database, nothing evaluated).
    database : str
        Where it is stored.
    study_text : str, optional
        The study file as written (default: its stored content, written back as TOML).
    """
    from mechdyn import __version__
    from mechdyn.reports.columns import study_columns

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
        ("variants", _counts_text(variant_counts(result))),
    ]
    columns = study_columns(st)
    shown = {c.key: c for c in columns if c.role == "parameter"}
    params = HtmlTable(
        "",
        ["parameter [unit]", "base", "low", "high", "levels"],
        [
            [
                Cell(shown[p.name].label),
                table_cell(shown[p.name].shown(p.base)),
                table_cell(shown[p.name].shown(p.low)),
                table_cell(shown[p.name].shown(p.high)),
                Cell(", ".join(table_cell(shown[p.name].shown(v)).text for v in p.levels) or "—"),
            ]
            for p in st.parameters
        ],
    )
    distinct = list({v.id: v for v in result.variants}.values())  # a variant listed twice, once
    units_note = (
        "A study built in Python has no study file to give units: values in SI (an output in the display "
        "unit it was given, if any), the unit in each header."
        if not st.definition
        else "Values in the units the study file gives (outputs) and the model file writes (parameters), "
        "the unit in each header; the results database holds them in SI."
    )
    rows_note = ""
    if len(distinct) > MAX_VARIANT_ROWS:
        rows_note = (
            f" The first {MAX_VARIANT_ROWS} of {len(distinct)} variants: `mechdyn results export` gives all."
        )
    if study_text is not None:  # the file as written
        study_note = st.path
    elif st.definition:
        study_note = (
            "The study file as stored in the results database, written back as TOML (its comments are "
            "not kept)."
        )
        study_text = toml_text(st.definition)
    else:
        study_note, study_text = "Built in Python: no study file.", None
    variants = variants_table(columns, distinct, MAX_VARIANT_ROWS)
    views = study_views(result)
    led = (
        [Section(views.title, note=views.note, figures=views.figures, items=views.warnings)]
        if views.title
        else []
    )
    plots = {k: draw for k, draw in result.plots().items() if k not in views.shown}
    sections = [
        Section("Parameters", note=units_note, tables=[params]),
        *led,
        Section("Findings", tables=study_tables(result)),
        Section("Plots", figures=figures_of(plots)),
        Section("Variants", note=units_note + rows_note, tables=[variants]),
        Section("Study file", note=study_note, text=study_text),
        Section("Model file", note=st.source.path, text=st.source.text),
    ]
    return Report(st.name, f"design study: {st.kind} of {st.analysis}", meta, sections, views.headline)


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
