"""Plots of a study: tornado, main effects, Sobol bars, optimization history, Pareto front, parallel
coordinates, and the overlaid curves of stored variants."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from mechdyn.plotting import legend, new_axes
from mechdyn.studies.cells import number, parameter_text, percent, signed, unit_text

if TYPE_CHECKING:
    from mechdyn.studies.outputs import Watched
    from mechdyn.studies.plan import StudyFindings
    from mechdyn.studies.storage import StoredVariant

__all__ = [
    "choose_curves",
    "curve_choice",
    "curves",
    "history",
    "main_effects",
    "parallel",
    "pareto",
    "sobol_bars",
    "tornado",
]


def tornado(result: StudyFindings, w: Watched, ax: Any = None) -> Any:
    """One bar per parameter from its lowest to its highest level's change of one output (in % of the
    base value; a negative output growing in size reads as growing), each end labelled with its level,
    the parameter with the larger effect on top."""
    by_param: dict[str, list[dict]] = {}
    for e in result.findings["effects"]:
        if e["outputs"][w.key]["change_percent"] is not None:
            by_param.setdefault(e["parameter"], []).append(e)

    def level(e: dict) -> str:
        return percent(e["level_percent"]) if e["level_percent"] is not None else str(e["level"])

    def change(e: dict) -> float:
        return float(e["outputs"][w.key]["change_percent"])

    names = sorted(by_param, key=lambda n: max(abs(change(e)) for e in by_param[n]))
    ax = new_axes(ax, figsize=(7.0, 0.9 + 0.42 * max(len(names), 1)))
    for y, n in enumerate(names):
        lo, hi = min(by_param[n], key=change), max(by_param[n], key=change)
        a, b = change(lo), change(hi)
        if lo is hi:  # one level: a bar from the base
            a, b = min(a, 0.0), max(b, 0.0)
        # the bar spans the parameter's levels; red where the output grows, blue where it shrinks
        if b > 0:
            ax.barh(y, b - max(a, 0.0), left=max(a, 0.0), color="tab:red", height=0.6)
        if a < 0:
            ax.barh(y, min(b, 0.0) - a, left=a, color="tab:blue", height=0.6)
        ax.annotate(f"{level(lo)} ({signed(change(lo), 3)} %) ", (a, y), ha="right", va="center", fontsize=7)
        if hi is not lo:
            ax.annotate(
                f" {level(hi)} ({signed(change(hi), 3)} %)", (b, y), ha="left", va="center", fontsize=7
            )
    ax.set_yticks(np.arange(len(names)), names, fontsize=8)
    ax.axvline(0.0, color="k", lw=0.8)
    span = max((abs(change(e)) for es in by_param.values() for e in es), default=1.0) or 1.0
    ax.set_xlim(-1.8 * span, 1.8 * span)
    ax.set_xlabel(f"change of {w.words} from the base [%]")
    ax.set_title(f"{result.study.name}: one at a time", fontsize=10)
    return ax


def main_effects(result: StudyFindings, w: Watched, ax: Any = None) -> Any:
    """A factorial study's main effects on one output: the mean over the grid at each level of each
    parameter, the parameters side by side on one axis (their levels as written), the grid mean dashed."""
    e = result.findings["factorial"][w.key]
    w = w.readable([e["mean"], *(m for main in e["main"].values() for m in main["means"])])
    params = {p.name: p for p in result.study.parameters}
    names = sorted(e["main"], key=lambda n: -e["main"][n]["spread"])
    ax = new_axes(ax, figsize=(7.0, 4.0))
    ticks, labels, x0 = [], [], 0
    for n in names:
        m = e["main"][n]
        x = x0 + np.arange(len(m["means"]))
        ax.plot(x, [w.show(v) for v in m["means"]], "o-", label=n)
        ticks += list(x)
        labels += [parameter_text(params[n], v) for v in m["levels"]]
        x0 += len(m["means"]) + 1
    ax.axhline(w.show(e["mean"]), color="k", lw=0.8, ls="--", label="grid mean")
    ax.set_xticks(ticks, labels, rotation=30, ha="right", fontsize=8)
    ax.set_ylabel(w.label)
    ax.set_title(f"{result.study.name}: main effects on {w.words}", fontsize=10)
    legend(ax, fontsize=8)
    return ax


def sobol_bars(result: StudyFindings, w: Watched, ax: Any = None) -> Any:
    """First- and total-order indices of one output with their 95 % intervals."""
    ind = result.findings["indices"][w.key]
    names = sorted(ind, key=lambda n: -ind[n]["ST"])
    ax = new_axes(ax, figsize=(7.0, 4.0))
    x = np.arange(len(names))
    ax.bar(
        x - 0.2,
        [ind[n]["S1"] for n in names],
        0.4,
        yerr=[ind[n]["S1_conf"] for n in names],
        label="first order S1",
        capsize=3,
    )
    ax.bar(
        x + 0.2,
        [ind[n]["ST"] for n in names],
        0.4,
        yerr=[ind[n]["ST_conf"] for n in names],
        label="total order ST",
        capsize=3,
    )
    ax.set_xticks(x, names, rotation=30, ha="right", fontsize=8)
    ax.set_ylabel("Sobol index")
    ax.set_title(f"Sobol indices of {w.words}", fontsize=10)
    legend(ax, fontsize=8)
    return ax


def history(result: StudyFindings, ax: Any = None) -> Any:
    """The objective of each evaluated variant in the order stored (those that break a constraint
    in light grey) and the best feasible one so far."""
    st = result.study
    o = st.objectives[0].output if st.objectives else st.targets[0].output
    vs = sorted(result.variants, key=lambda v: v.id)
    o = o.readable(v.outputs.get(o.key) for v in vs if v.status == "ok")
    y = np.array([o.show(v.outputs.get(o.key)) if v.status == "ok" else None for v in vs], dtype=float)
    feasible = np.array(
        [v.status == "ok" and all(c.holds(v.outputs.get(c.output.key)) for c in st.constraints) for v in vs]
    )
    ax = new_axes(ax)
    n = np.arange(y.size)
    ax.plot(n[~feasible], y[~feasible], ".", ms=3, color="0.85", label="breaks a constraint")
    ax.plot(n[feasible], y[feasible], ".", ms=3, color="0.45", label="feasible")
    if st.objectives and feasible.any():
        sign = st.objectives[0].sign
        best = np.fmin.accumulate(np.where(feasible & np.isfinite(y), sign * y, np.inf)) * sign
        ax.plot(
            n, np.where(np.isfinite(best), best, np.nan), "-", color="tab:red", label="best feasible so far"
        )
    good = y[feasible & np.isfinite(y)]
    if good.size > 4:  # the bulk of the feasible variants, not the odd wild one
        lo, hi = np.percentile(good, [0, 95])
        pad = 0.1 * (hi - lo or abs(hi) or 1.0)
        ax.set_ylim(lo - pad, hi + pad)
    ax.set_xlabel("variant (order evaluated)")
    ax.set_ylabel(o.label)
    ax.set_title(f"{st.name}: history", fontsize=10)
    legend(ax, fontsize=8)
    return ax


def pareto(result: StudyFindings, ax: Any = None) -> Any:
    """The first two objectives of every feasible variant and the Pareto front."""
    st = result.study
    ok = [v for v in result.variants if v.status == "ok"]
    a, b = (st.objectives[k].output for k in (0, 1))
    a, b = (w.readable(v.outputs.get(w.key) for v in ok) for w in (a, b))
    ax = new_axes(ax)
    pts = np.array(
        [[a.show(v.outputs.get(a.key)), b.show(v.outputs.get(b.key))] for v in ok],
        dtype=float,
    )
    ax.plot(pts[:, 0], pts[:, 1], ".", color="0.6", ms=4, label="variants")
    front = np.array(
        [
            [a.show(d["outputs"].get(a.key)), b.show(d["outputs"].get(b.key))]
            for d in result.findings["pareto_front"]
        ],
        dtype=float,
    )
    order = np.argsort(front[:, 0])
    ax.plot(front[order, 0], front[order, 1], "o-", color="tab:red", label="Pareto front")
    ids = [d["variant"] for d in result.findings["pareto_front"]]
    knee = result.findings.get("knee")
    if knee in ids:
        k = ids.index(knee)
        ax.plot(
            front[k, 0], front[k, 1], "*", ms=16, color="tab:orange", mec="k", label=f"knee (variant {knee})"
        )
    words = {w.key: w.words for w in st.watched}
    for key, v in (result.findings.get("ends") or {}).items():
        if v in ids:
            k = ids.index(v)
            ax.annotate(f" best {words.get(key, key)}", (front[k, 0], front[k, 1]), fontsize=7)
    ax.set_xlabel(a.label)
    ax.set_ylabel(b.label)
    legend(ax, fontsize=8)
    return ax


def parallel(result: StudyFindings, ax: Any = None) -> Any:
    """Parallel coordinates: each variant a line through its parameters and outputs, each axis from
    the variants' smallest to their largest value, written at its ends in the study's units; the lines
    coloured by the objective (else the last output), with its colour bar."""
    import matplotlib.pyplot as plt
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize

    st = result.study
    ok = [v for v in result.variants if v.status == "ok"][:2000]
    shown: list[tuple[str, Any, Any]] = [
        (p.name, lambda v, p=p: v.parameters.get(p.name), lambda x, p=p: parameter_text(p, x))
        for p in st.parameters
    ]
    watched = [w.readable(v.outputs.get(w.key) for v in ok) for w in st.watched]
    by = next((w for o in st.objectives for w in watched if w.key == o.output.key), None)
    by = by or (watched[-1] if watched else None)
    if by is not None:  # the colouring output last, beside its colour bar
        watched = [w for w in watched if w.key != by.key] + [by]
    for w in watched:
        unit = unit_text(w.shown_unit)
        shown.append(
            (
                w.words,
                lambda v, w=w: v.outputs.get(w.key),
                lambda x, w=w, u=unit: f"{number(w.show(x))} {u}".strip(),
            )
        )
    M = np.array([[f(v) if f(v) is not None else np.nan for _, f, _ in shown] for v in ok], dtype=float)
    M = M.reshape(len(ok), len(shown))
    with np.errstate(all="ignore"):
        lo, hi = np.nanmin(M, axis=0, initial=np.inf), np.nanmax(M, axis=0, initial=-np.inf)
    S = (M - lo) / np.where(hi > lo, hi - lo, 1.0)
    ax = new_axes(ax, figsize=(max(7.5, 1.2 * len(shown)), 4.8))
    cmap = plt.get_cmap("viridis")
    colour = S[:, -1] if S.size else np.zeros(0)
    x = np.arange(len(shown))
    for row, c in zip(S, colour, strict=True):
        ax.plot(x, row, color=cmap(c if np.isfinite(c) else 0.0), alpha=0.8 if len(ok) <= 50 else 0.3, lw=0.9)
    for k, (_, _, text) in enumerate(shown):  # each axis' real range at its ends
        ax.axvline(k, color="0.6", lw=0.6)
        if np.isfinite(lo[k]):
            ax.annotate(
                text(lo[k]), (k, 0.0), (0, -4), textcoords="offset points", ha="center", va="top", fontsize=7
            )
            ax.annotate(
                text(hi[k]),
                (k, 1.0),
                (0, 4),
                textcoords="offset points",
                ha="center",
                va="bottom",
                fontsize=7,
            )
    ax.set_xticks(x, [n for n, _, _ in shown], rotation=30, ha="right", fontsize=8)
    ax.set_yticks([])
    ax.set_ylim(-0.12, 1.12)
    if by is not None and len(ok):
        k = len(shown) - 1
        norm = Normalize(
            by.show(lo[k]) if np.isfinite(lo[k]) else 0.0, by.show(hi[k]) if np.isfinite(hi[k]) else 1.0
        )
        bar = ax.figure.colorbar(ScalarMappable(norm=norm, cmap=cmap), ax=ax, pad=0.02)
        bar.set_label(by.label, fontsize=8)
    ax.set_title(f"{st.name}: {len(ok)} variants, coloured by {by.words if by else '—'}", fontsize=10)
    return ax


def curve_choice(variants: Sequence[StoredVariant], n: int = 3) -> tuple[str | None, list[str]]:
    """Which stored curves of these variants to overlay (see :func:`choose_curves`)."""
    return choose_curves([v.curves for v in variants if v.curves], n)


def choose_curves(
    curves: Sequence[dict[str, tuple[np.ndarray, str]]], n: int = 3
) -> tuple[str | None, list[str]]:
    """Which of several runs' or variants' curves to overlay: the abscissa (the first curve, a time
    or an angle) and the ``n`` curves of its length, kept by all, that differ most between them
    (for one alone: the first ``n``); none with no curve. A check's residual (a power balance's
    round-off) is never chosen: its relative spread is noise.

    Runs of different lengths or grids (two machines of different periods, one mechanism at 360
    and at 180 angles) are compared on the first one's abscissa: each curve is interpolated there
    from its own (by its position along the curve where an abscissa does not rise throughout). Each is
    still drawn on its own abscissa.
    """
    if not curves:
        return None, []
    first = curves[0]
    x = next(iter(first))
    grid = np.asarray(first[x][0], dtype=float)
    size = grid.shape
    spread = {}
    for name, (y, _) in first.items():
        if name == x or np.asarray(y).shape != size or not all(name in c for c in curves):
            continue
        if any(w in name for w in ("angle", "time", "residual")):  # an abscissa, or a check's round-off
            continue
        try:
            stack = np.array([_on_grid(c, x, name, grid) for c in curves])
        except ValueError:  # a curve without the abscissa, or not one-dimensional: not comparable
            continue
        values = np.abs(stack[np.isfinite(stack)])
        if not values.size:  # no value at all (a speed sweep's stability, not worked out)
            continue
        apart = np.abs(stack - stack[0])
        apart = apart[np.isfinite(apart)]
        spread[name] = (float(apart.max()) if apart.size else 0.0) / (float(values.max()) or 1.0)
    if len(curves) == 1:  # one alone: its curves that are not flat
        return x, [k for k in spread if np.ptp(np.asarray(first[k][0], dtype=float)) > 0][:n]
    return x, [k for k, d in sorted(spread.items(), key=lambda kv: -kv[1]) if d > 0][:n]


def _words(key: str) -> str:
    """A curve's name in words with its unit (``crank angle [deg]`` for ``crank_angle_deg``)."""
    from mechdyn.units import key_label

    words, unit = key_label(key)
    return f"{words} [{unit}]" if unit else words


def _on_grid(curve: dict[str, tuple[np.ndarray, str]], x: str, name: str, grid: np.ndarray) -> np.ndarray:
    """``curve[name]`` at the abscissa values ``grid`` (the first run's), from its own abscissa."""
    y = np.asarray(curve[name][0], dtype=float)
    if y.ndim != 1:
        raise ValueError(name)
    if y.shape == grid.shape and x in curve and np.array_equal(np.asarray(curve[x][0], dtype=float), grid):
        return y
    xs = np.asarray(curve[x][0], dtype=float) if x in curve else None
    if xs is None or xs.shape != y.shape:
        raise ValueError(name)
    if np.all(np.diff(xs) > 0) and np.all(np.diff(grid) > 0):
        return np.interp(grid, xs, y)
    # an abscissa that does not rise throughout: by the position along each curve
    return np.interp(np.linspace(0.0, 1.0, grid.size), np.linspace(0.0, 1.0, y.size), y)


def curves(
    variants: Sequence[StoredVariant],
    name: str,
    x: str | None = None,
    ax: Any = None,
    base: int | None = None,
) -> Any:
    """One stored curve of several variants, overlaid (against another stored curve, or the sample).

    ``base`` is the id of the study's base design, drawn bold and labelled "(base)" when it is among
    the variants (a study without a base design, such as a Sobol sample, labels none).
    """
    from mechdyn.plotting import display_unit
    from mechdyn.units import key_label, key_unit

    ax = new_axes(ax)
    drawn = [v for v in variants if name in v.curves]
    # the unit the curves' largest value reads best in, as the tables and the summaries choose it
    values = np.concatenate(
        [np.ravel(np.asarray(v.curves[name][0], dtype=float)) for v in drawn] or [np.zeros(0)]
    )
    unit, factor = display_unit(values[np.isfinite(values)], key_unit(name) or "")
    for v in drawn:
        y = np.asarray(v.curves[name][0]) * factor
        xs = v.curves[x][0] if x is not None and x in v.curves else np.arange(y.size)
        label = f"variant {v.id}" + (" (base)" if v.id == base else "")
        ax.plot(xs, y, label=label, lw=2.0 if v.id == base else 1.0)
    ax.set_xlabel(_words(x) if x else "sample")
    ax.set_title(f"{key_label(name)[0]}: {len(variants)} variants overlaid", fontsize=10)
    ax.set_ylabel(f"{key_label(name)[0]} [{unit_text(unit)}]" if unit_text(unit) else key_label(name)[0])
    legend(ax, fontsize=8)
    return ax
