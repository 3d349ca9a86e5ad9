"""How a ``tolerance`` study shows its findings (:mod:`mechdyn.studies.kinds.tolerance`): the scatter
and its correlations, each output's distribution, each limit's probability (and a rare limit's by
its small-probability method), the rankings, and each output's histogram with its CDF; and what a
report and the dashboard lead with (:func:`views`): each limit's probability in words, the sample
size and how far to trust it, each output's histogram and CDF and each limit's ranking as a bar
chart."""

from __future__ import annotations

import math
from functools import partial
from typing import TYPE_CHECKING, Any

import numpy as np

from mechdyn.results import Table
from mechdyn.studies.cells import given, number, table, unit_text
from mechdyn.studies.kinds.base import safe, value
from mechdyn.units import readable

if TYPE_CHECKING:
    from collections.abc import Callable

    from mechdyn.studies.outputs import Watched
    from mechdyn.studies.plan import StudyFindings

__all__ = ["distribution_plot", "headline", "plots", "ranking_plot", "statement", "tables", "views"]


def _limit_text(w: Watched, limit: float) -> str:
    """A limit (SI) as the study file gives it, in the output's display unit."""
    shown = w.readable([limit])
    x = shown.show(limit)
    return f"{given(x if x is not None else limit)} {unit_text(shown.shown_unit)}".strip()


def _scatter_text(d: dict[str, Any]) -> str:
    """A scatter's distribution and its parameters as given (each number with three digits at least)."""

    def shown(x: Any) -> str:
        if isinstance(x, list):
            return "[" + ", ".join(shown(y) for y in x) + "]"
        return given(float(x)) if isinstance(x, (int, float)) else str(x)

    return f"{d['distribution']} (" + ", ".join(f"{k} {shown(x)}" for k, x in d["parameters"].items()) + ")"


# a scatter's parameters that carry its unit (cov, sigma_ln and probabilities are dimensionless)
_IN_UNIT = frozenset({"mean", "std", "median", "low", "high", "mode", "lower", "upper", "values"})


def _scatter_row(name: str, d: dict[str, Any]) -> list[Any]:
    """A parameter's scatter in the unit a designer reads its mean in (MPa, not 3.2e8 Pa)."""
    mean, shown = readable(d["mean"], unit_text(d["unit"]))
    factor = mean / d["mean"] if d["mean"] else 1.0
    params = {
        k: ([x * factor for x in v] if isinstance(v, list) else v * factor) if k in _IN_UNIT else v
        for k, v in d["parameters"].items()
    }
    scatter = _scatter_text({**d, "parameters": params})
    return [name, shown, scatter, d["mean"] * factor, d["std"] * factor]


def tables(result: StudyFindings) -> list[Table]:
    """The scatter and its correlations; each output's distribution (95 % intervals) in its unit;
    each limit's probability with its interval, and a rare limit's by its small-probability
    method; each ranking, largest share first, with its method."""
    st, f = result.study, result.findings
    watched = {w.key: w for w in st.watched}
    out = [
        table(
            f"{st.name}: scatter of the parameters ({f['samples']} samples, {f['method']})",
            ["parameter", "unit", "scatter", "mean", "standard deviation"],
            [_scatter_row(name, d) for name, d in f["scatter"].items()],
        )
    ]
    if f.get("correlations"):
        out.append(
            table(
                f"{st.name}: correlations of the scatter (Gaussian copula)",
                ["parameter", "parameter", "coefficient", "measure", "copula's (normal space)"],
                [[*c["between"], c["coefficient"], c["measure"], c["normal"]] for c in f["correlations"]],
            )
        )
    rows: list[list[Any]] = []
    for key, d in f["outputs"].items():
        w = watched[key]
        if "error" in d:
            rows.append([w.words, "no value", None, None, d["error"]])
            continue
        dist = d["distribution"]
        shown = w.readable([dist["mean"], dist.get("q95")])
        for stat in ("mean", "std", "q5", "q50", "q95"):
            if stat not in dist:
                continue
            scale = shown.difference if stat == "std" else shown.show
            rows.append(
                [
                    shown.label,
                    {
                        "mean": "mean",
                        "std": "standard deviation",
                        "q5": "5 % quantile",
                        "q50": "median",
                        "q95": "95 % quantile",
                    }[stat],
                    scale(dist[stat]),
                    scale(dist[f"{stat}_low"]),
                    scale(dist[f"{stat}_high"]),
                ]
            )
    out.append(
        table(
            f"{st.name}: distribution of each output (95 % intervals)",
            ["output", "", "value", "low", "high"],
            rows,
        )
    )
    if f["limits"]:
        lrows: list[list[Any]] = []
        for d in f["limits"]:
            w = watched[d["output"]]
            event = f"{w.words} {'>' if d['side'] == 'above' else '<'} {_limit_text(w, d['value'])}"
            if "error" in d:
                lrows.append([event.strip(), None, None, None, d["error"]])
                continue
            p = d["probability"]
            lrows.append([event.strip(), p["value"], p["low"], p["high"], p["failures"]])
        out.append(
            table(
                f"{st.name}: probability of exceeding each limit (95 % intervals)",
                ["event", "probability", "low", "high", "samples beyond"],
                lrows,
            )
        )
        rare = _small_rows(result)
        if rare:
            approximate = any(str(r[1]).startswith(("FORM", "SORM")) for r in rare)
            out.append(
                table(
                    f"{st.name}: rarely exceeded limits, by a small-probability method (95 % intervals)",
                    [
                        "event",
                        "method",
                        "probability",
                        "low",
                        "high",
                        "coefficient of variation",
                        "evaluations",
                    ],
                    rare,
                    note=(
                        "FORM and SORM give no interval (low = high = the estimate): exact for a limit "
                        "state linear in the standard normal space, otherwise an approximation; "
                        if approximate
                        else ""
                    )
                    + "simulated estimates: p·exp(±1.96·√ln(1 + CoV²)); subset simulation's CoV is "
                    "an upper bound",
                )
            )
    for what, ranking in _rankings(result):
        if not ranking.get("ranked"):
            out.append(
                table(
                    f"{st.name}: tolerances ranked by their share of {what}",
                    ["note"],
                    [[ranking["method"]]],
                )
            )
            continue
        m = ranking["measures"]
        out.append(
            table(
                f"{st.name}: tolerances ranked by their share of {what}",
                ["parameter", "measure"],
                [[name, m[name]] for name in ranking["ranked"]],
                note=f"measure: {ranking['method']}",
            )
        )
    return out


def _small_rows(result: StudyFindings) -> list[list[Any]]:
    """One row per rare limit: its small-probability estimate with its interval and cost."""
    watched = {w.key: w for w in result.study.watched}
    rows: list[list[Any]] = []
    for d in result.findings["limits"]:
        s = d.get("small_probability")
        if s is None:
            continue
        w = watched[d["output"]]
        event = f"{w.words} {'>' if d['side'] == 'above' else '<'} {_limit_text(w, d['value'])}".strip()
        if "error" in s:
            rows.append([event, s["method"], None, None, None, None, s["error"]])
            continue
        rows.append([event, s["method"], s["value"], s["low"], s["high"], s["cov"], s["evaluations"]])
    return rows


def _event(w: Watched, d: dict[str, Any]) -> str:
    """A limit's event in words: ``displacement max > 1.30 mm``."""
    return f"{w.words} {'>' if d['side'] == 'above' else '<'} {_limit_text(w, d['value'])}".strip()


def _importance_ranking(importance: dict[str, float]) -> dict[str, Any]:
    """FORM's importance factors at a rare limit's design point as a ranking."""
    return {
        "method": "FORM importance factor α² at the design point (the share of the reliability "
        "index; with correlated parameters, of their independent parts in order)",
        "measures": importance,
        "ranked": sorted(importance, key=lambda k: -importance[k]),
    }


def _rankings(result: StudyFindings) -> list[tuple[str, dict[str, Any]]]:
    f, watched = result.findings, {w.key: w for w in result.study.watched}
    out = [
        (f"the scatter of {watched[k].words}", d["ranking"])
        for k, d in f["outputs"].items()
        if "ranking" in d
    ]
    for d in f["limits"]:
        if "ranking" in d:
            out.append((f"P({_event(watched[d['output']], d)})", d["ranking"]))
        importance = d.get("small_probability", {}).get("importance")
        if importance:
            event = _event(watched[d["output"]], d)
            out.append((f"P({event}) at its design point", _importance_ranking(importance)))
    return out


def plots(result: StudyFindings) -> dict[str, Callable[[], Any]]:
    """Per output: its histogram and its empirical CDF, each limit drawn."""
    out: dict[str, Callable[[], Any]] = {}
    for w in result.study.watched:
        if "error" not in result.findings["outputs"].get(w.key, {"error": 1}):
            out[f"tolerance_{safe(w.key)}.png"] = partial(distribution_plot, result, w)
    return out


def distribution_plot(result: StudyFindings, w: Watched, ax: Any = None) -> Any:
    """One output's histogram over its samples with its empirical CDF (right axis), each of its limits
    drawn as a vertical line with its probability.

    Parameters
    ----------
    result : StudyResult
        A tolerance study's result.
    w : Watched
        The output.
    ax : matplotlib Axes, optional
    """
    from mechdyn.plotting import legend, new_axes

    y = np.array([value(v, w.key) for v in result.variants[: result.findings["samples"]]])
    y = y[np.isfinite(y)]
    shown = w.readable([float(np.max(np.abs(y)))] if y.size else [])
    ys = np.array([shown.show(float(v)) for v in y])
    ax = new_axes(ax, figsize=(7.0, 4.0))
    ax.hist(ys, bins=max(10, min(60, int(math.sqrt(len(ys))))), density=True, alpha=0.6, label="samples")
    ax.set_xlabel(shown.label)
    ax.set_ylabel("probability density")
    cdf = ax.twinx()
    s = np.sort(ys)
    cdf.step(s, np.arange(1, len(s) + 1) / len(s), where="post", color="k", lw=1.0, label="CDF")
    cdf.set_ylabel("cumulative probability")
    cdf.set_ylim(0.0, 1.0)
    for d in result.findings["limits"]:
        if d["output"] != w.key or "probability" not in d:
            continue
        x = shown.show(d["value"])
        p = d["probability"]
        label = f"limit {_limit_text(w, d['value'])}: P = {_p(p['value'])} [{_p(p['low'])}, {_p(p['high'])}]"
        rare = d.get("small_probability", {})
        if "value" in rare:
            label += f" ({rare['method']}: {_p(rare['value'])})"
        ax.axvline(x, color="C3", ls="--", label=label)
    ax.set_title(f"{w.words}: {result.findings['samples']} samples", fontsize=10)
    legend(ax, fontsize=8)
    return ax


# -- what a report and the dashboard lead with ------------------------------------------------------

PROBABILITY_DIGITS = 3
"""Significant digits of a probability in a sentence: its interval is wider than the fourth."""


def _p(x: float | None) -> str:
    return number(x, PROBABILITY_DIGITS)


def _sentence(event: str, p: dict[str, Any], samples: int) -> str:
    """A probability found by sampling, in words, with its 95 % interval and how it was found."""
    level = f"{p['level'] * 100:.0f} %"
    if p.get("failures") == 0:
        return (
            f"P({event}) < {_p(p['high'])} ({level} upper bound, {p['method']}: no sample of {samples} "
            "beyond the limit)"
        )
    beyond = (
        f", {p['failures']} of {samples} samples beyond the limit" if p.get("failures") is not None else ""
    )
    return f"P({event}) = {_p(p['value'])} [{_p(p['low'])}, {_p(p['high'])}] ({level}, {p['method']}{beyond})"


def _rare_sentence(event: str, s: dict[str, Any]) -> str:
    """A rare limit's probability by its small-probability method, in words."""
    if "error" in s:
        return f"P({event}): {s['method']} found no probability ({s['error']})"
    cost = f"{s['evaluations']} evaluations"
    if s.get("interval_method") == "none":
        return f"P({event}) = {_p(s['value'])} by {s['method']} (no interval: {cost})"
    level = f"{s['level'] * 100:.0f} %"
    cov = f", coefficient of variation {_p(s['cov'])}" if s.get("cov") is not None else ""
    interval = f"[{_p(s['low'])}, {_p(s['high'])}]"
    return f"P({event}) = {_p(s['value'])} {interval} ({level}, {s['method']}, {cost}{cov})"


def headline(result: StudyFindings) -> list[str]:
    """Each limit's exceedance probability in words, as a designer signs it:
    ``P(displacement max > 1.30 mm) = 0.328 [0.264, 0.392] (95 %, randomized quasi-Monte Carlo, 21 of
    64 samples beyond the limit)``; a rarely exceeded limit's by its small-probability method
    (importance sampling, subset simulation or FORM), the samples' upper bound after it.

    Parameters
    ----------
    result : StudyResult
        A tolerance study's result.

    Returns
    -------
    list of str
        One sentence per limit, in the study file's order (probabilities as fractions, three
        significant digits; the limit in the output's display unit).
    """
    f, watched = result.findings, {w.key: w for w in result.study.watched}
    lines = []
    for d in f["limits"]:
        event = _event(watched[d["output"]], d)
        if "error" in d:
            lines.append(f"P({event}): no probability ({d['error']})")
            continue
        sampled = _sentence(event, d["probability"], f["samples"])
        rare = d.get("small_probability")
        lines.append(f"{_rare_sentence(event, rare)}; by the samples: {sampled}" if rare else sampled)
    return lines


def statement(result: StudyFindings) -> tuple[str, list[str]]:
    """How far to trust the probabilities: the sample size, the sampling method and how each interval
    is made, each estimate's coefficient of variation; then what limits their validity (the
    warnings of :func:`mechdyn.uncertainty.estimates.validity`, each naming its limit), or that no
    interval is wider than its probability.

    Parameters
    ----------
    result : StudyResult
        A tolerance study's result.

    Returns
    -------
    (str, list of str)
        The statement, and the warnings (none: an empty list).
    """
    f, watched = result.findings, {w.key: w for w in result.study.watched}
    intervals = list(
        dict.fromkeys(d["probability"]["interval_method"] for d in f["limits"] if "probability" in d)
    )
    text = f"{f['samples']} samples by {f['method']}"
    if intervals:
        text += "; 95 % intervals by " + " and ".join(intervals)
    covs = [
        f"{_event(watched[d['output']], d)}: {_p(d['probability']['cov'])}"
        for d in f["limits"]
        if d.get("probability", {}).get("cov") is not None
    ]
    if covs:
        text += "; coefficient of variation of each estimate: " + ", ".join(covs)
    warnings = []
    for d in f["limits"]:
        event = _event(watched[d["output"]], d)
        for part in ("probability", "small_probability"):
            for w in d.get(part, {}).get("warnings", []):
                warnings.append(f"{event}: {w}")
        if "error" in d:
            warnings.append(f"{event}: {d['error']}")
    if not f["limits"]:
        text += ". The study gives no limit: no probability to estimate."
    elif not warnings:
        text += (
            ". Every estimate is valid at this sample size: each limit is exceeded by some sample and "
            "no interval is wider than its probability."
        )
    else:
        text += "."
    return text, warnings


def _limit_ranking(result: StudyFindings, index: int) -> dict[str, Any] | None:
    """The ranking a limit's bar chart shows: the samples' (an indicator's share), else FORM's
    importance factors at a rare limit's design point; None where neither ranks anything."""
    d = result.findings["limits"][index]
    if d.get("ranking", {}).get("ranked"):
        return dict(d["ranking"])
    importance = d.get("small_probability", {}).get("importance")
    return _importance_ranking(importance) if importance else None


def ranking_plot(result: StudyFindings, index: int, ax: Any = None) -> Any:
    """The tolerances ranked by their share of one limit's probability, as horizontal bars, the
    largest share on top (the measure as the ranking table gives it: a Sobol index, a signed
    Spearman rank correlation or FORM's importance factor; :mod:`mechdyn.studies.kinds.tolerance`).

    Parameters
    ----------
    result : StudyResult
        A tolerance study's result.
    index : int
        The limit, its place in ``result.findings["limits"]``.
    ax : matplotlib Axes, optional
    """
    from mechdyn.plotting import new_axes

    d = result.findings["limits"][index]
    w = next(w for w in result.study.watched if w.key == d["output"])
    ranking = _limit_ranking(result, index)
    if ranking is None:
        raise ValueError(f"limit {index + 1} ({_event(w, d)}) has no ranking to draw")
    names = list(ranking["ranked"])[::-1]  # the largest share on top
    measures = [float(ranking["measures"][n]) for n in names]
    ax = new_axes(ax, figsize=(7.0, 0.8 + 0.45 * max(2, len(names))))
    ax.barh(names, measures, color=["C0" if m >= 0 else "C3" for m in measures])
    ax.axvline(0.0, color="k", lw=0.8)
    ax.set_xlabel(str(ranking["method"]).split(" (")[0])
    ax.set_title(f"tolerances ranked by their share of P({_event(w, d)})", fontsize=10)
    ax.tick_params(axis="y", labelsize=8)
    return ax


def views(result: StudyFindings) -> dict[str, Any]:
    """What a report and the dashboard lead with for a tolerance study.

    Parameters
    ----------
    result : StudyResult
        A tolerance study's result.

    Returns
    -------
    dict
        ``title`` (the section's), ``headline`` (:func:`headline`), ``note`` and ``warnings``
        (:func:`statement`), and ``figures``: (file name, caption, drawing function) per output, its
        histogram and CDF with its limits drawn (the plot of :func:`plots`, the same file name),
        followed by a bar chart of the tolerances' ranking (:func:`ranking_plot`) per limit of that
        output.
    """
    f = result.findings
    drawn = plots(result)
    figures: list[tuple[str, str, Callable[[], Any]]] = []
    for w in result.study.watched:
        name = f"tolerance_{safe(w.key)}.png"
        if name in drawn:
            limits = (
                "each limit dashed with its probability"
                if any(d["output"] == w.key for d in f["limits"])
                else "no limit given"
            )
            caption = f"{w.words}: histogram and CDF of the {f['samples']} samples, {limits}"
            figures.append((name, caption, drawn[name]))
        for i, d in enumerate(f["limits"]):
            if d["output"] != w.key or (ranking := _limit_ranking(result, i)) is None:
                continue
            caption = f"P({_event(w, d)}): the tolerances ranked (measure: {ranking['method']})"
            figures.append(
                (f"tolerance_ranking_{i + 1}_{safe(w.key)}.png", caption, partial(ranking_plot, result, i))
            )
    note, warnings = statement(result)
    return {
        "title": "Probabilities of exceeding the limits",
        "headline": headline(result),
        "note": note,
        "warnings": warnings,
        "figures": figures,
    }
