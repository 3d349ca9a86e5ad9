"""How a ``tolerance`` study shows its findings (:mod:`mechdyn.studies.kinds.tolerance`): the scatter
and its correlations, each output's distribution, each limit's probability (and a rare limit's by
its small-probability method), the rankings, and each output's histogram with its CDF."""

from __future__ import annotations

import math
from functools import partial
from typing import TYPE_CHECKING, Any

import numpy as np

from mechdyn.results import Table
from mechdyn.studies.cells import given, number, table, unit_text
from mechdyn.studies.kinds.base import safe, value

if TYPE_CHECKING:
    from collections.abc import Callable

    from mechdyn.studies.outputs import Watched
    from mechdyn.studies.result import StudyResult

__all__ = ["distribution_plot", "plots", "tables"]


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


def tables(result: StudyResult) -> list[Table]:
    """The scatter and its correlations; each output's distribution (95 % intervals) in its unit;
    each limit's probability with its interval, and a rare limit's by its small-probability
    method; each ranking, largest share first, with its method."""
    st, f = result.study, result.findings
    watched = {w.key: w for w in st.watched}
    out = [
        table(
            f"{st.name}: scatter of the parameters ({f['samples']} samples, {f['method']})",
            ["parameter", "unit", "scatter", "mean", "standard deviation"],
            [
                [name, unit_text(d["unit"]), _scatter_text(d), d["mean"], d["std"]]
                for name, d in f["scatter"].items()
            ],
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


def _small_rows(result: StudyResult) -> list[list[Any]]:
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


def _rankings(result: StudyResult) -> list[tuple[str, dict[str, Any]]]:
    f, watched = result.findings, {w.key: w for w in result.study.watched}
    out = [
        (f"the scatter of {watched[k].words}", d["ranking"])
        for k, d in f["outputs"].items()
        if "ranking" in d
    ]
    for d in f["limits"]:
        if "ranking" in d:
            w = watched[d["output"]]
            side = ">" if d["side"] == "above" else "<"
            out.append((f"P({w.words} {side} {_limit_text(w, d['value'])})", d["ranking"]))
        importance = d.get("small_probability", {}).get("importance")
        if importance:
            w = watched[d["output"]]
            side = ">" if d["side"] == "above" else "<"
            ranking = {
                "method": "FORM importance factor α² at the design point (the share of the reliability "
                "index; with correlated parameters, of their independent parts in order)",
                "measures": importance,
                "ranked": sorted(importance, key=lambda k: -importance[k]),
            }
            out.append((f"P({w.words} {side} {_limit_text(w, d['value'])}) at its design point", ranking))
    return out


def plots(result: StudyResult) -> dict[str, Callable[[], Any]]:
    """Per output: its histogram and its empirical CDF, each limit drawn."""
    out: dict[str, Callable[[], Any]] = {}
    for w in result.study.watched:
        if "error" not in result.findings["outputs"].get(w.key, {"error": 1}):
            out[f"tolerance_{safe(w.key)}.png"] = partial(distribution_plot, result, w)
    return out


def distribution_plot(result: StudyResult, w: Watched, ax: Any = None) -> Any:
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
        label = f"limit {number(x)}: P = {number(p['value'])}"
        rare = d.get("small_probability", {})
        if "value" in rare:
            label += f" ({rare['method']}: {number(rare['value'])})"
        ax.axvline(x, color="C3", ls="--", label=label)
    ax.set_title(f"{w.words}: {result.findings['samples']} samples", fontsize=10)
    legend(ax, fontsize=8)
    return ax
