"""The sweeps: one at a time (``oat``), full factorial (``factorial``) and Latin hypercube (``lhs``)."""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Sequence
from functools import partial
from typing import TYPE_CHECKING, Any

import numpy as np

from mechdyn.results import Table
from mechdyn.studies.cells import number, parameter_text, percent, signed, table, unit_text
from mechdyn.studies.kinds.base import (
    Found,
    Kind,
    base_row,
    best,
    describe,
    parallel_plot,
    register,
    safe,
    value,
    variant_table,
)
from mechdyn.studies.storage import StoredVariant

if TYPE_CHECKING:
    from mechdyn.studies.plan import Study, StudyFindings

__all__ = ["Factorial", "LatinHypercube", "OneAtATime", "factorial_effects", "grid", "sweep"]


def _levels(study: Study) -> list[tuple[float, ...]]:
    """Each parameter's levels (a range: its two ends), SI."""
    return [p.levels or (float(p.low), float(p.high)) for p in study.parameters]  # type: ignore[arg-type]


RHO_DIGITS = 3
"""Significant digits of a rank correlation in a table (ρ from −1 to 1: +0.571)."""


def grid(levels: Sequence[Sequence[float]]) -> np.ndarray:
    """Every combination of the levels (rows)."""
    return np.array(list(itertools.product(*levels)), dtype=float)


@register
class OneAtATime(Kind):
    """The base, then each parameter at each of its levels with the others at base (as both
    publications did); each output's change in % of the base value."""

    name = "oat"
    title = "one at a time"
    uses = "levels"

    def _moves(self, study: Study) -> list[tuple[int, float]]:
        return [(j, level) for j, levels in enumerate(_levels(study)) for level in levels]

    def design(self, study: Study) -> np.ndarray:
        base = base_row(study)
        rows = [base]  # the base first: the changes are measured from it
        for j, level in self._moves(study):
            r = base.copy()
            r[j] = level
            rows.append(r)
        return np.array(rows)

    def findings(self, study: Study, variants: list[StoredVariant]) -> Found:
        """``base`` (the outputs of the base design), ``base_variant`` and ``effects``: per parameter
        and level, each output's value and its change relative to the base value itself (a negative
        output that grows in size, −294 kN to −320 kN, reads as growing, +8.8 %)."""
        b = variants[0]
        table = []
        for (j, level), v in zip(self._moves(study), variants[1:], strict=True):
            p = study.parameters[j]
            rel = p.relative(level)
            effects = {}
            for w in study.watched:
                y0, y = value(b, w.key), value(v, w.key)
                effects[w.key] = {
                    "value": None if math.isnan(y) else y,
                    "change_percent": None if math.isnan(y) or not y0 else 100.0 * (y - y0) / y0,
                }
            table.append(
                {
                    "parameter": p.name,
                    "level": p.shown(level),
                    "level_percent": None if rel is None else 100.0 * rel,
                    "variant": v.id,
                    "status": v.status,
                    "error": v.error,
                    "outputs": effects,
                }
            )
        base_out = {w.key: (None if math.isnan(y := value(b, w.key)) else y) for w in study.watched}
        return Found({"base": base_out, "base_variant": b.id, "effects": table})

    def tables(self, result: StudyFindings) -> list[Table]:
        """The base, then one row per parameter and level: the level as the study file gives it
        (and in % of the base), each output in words with its change in % of the base value."""
        st, f = result.study, result.findings
        params = {p.name: p for p in st.parameters}
        at = {v.id: v.parameters for v in result.variants}
        # each output in its study unit, else in the unit the column's largest value reads best in
        shown = [
            w.readable([f["base"].get(w.key), *(e["outputs"][w.key]["value"] for e in f["effects"])])
            for w in st.watched
        ]
        cols = ["parameter", "level"]
        for w in shown:
            cols += [w.label, "change [%]"]
        rows = [["(base)", ""] + [x for w in shown for x in (w.show(f["base"].get(w.key)), None)]]
        for e in f["effects"]:
            x = at.get(e["variant"], {}).get(e["parameter"])
            level = parameter_text(params[e["parameter"]], x) if x is not None else e["level"]
            if e["level_percent"] is not None:
                level += f" ({percent(e['level_percent'])})"
            row = [e["parameter"], level]
            for w in shown:
                o = e["outputs"][w.key]
                row += [w.show(o["value"]), o["change_percent"]]
            rows.append(row)
        return [table(f"{st.name}: one at a time", cols, rows)]

    def plots(self, result: StudyFindings) -> dict[str, Callable[[], Any]]:
        from mechdyn.studies import plots as sp

        return {f"tornado_{safe(w.key)}.png": partial(sp.tornado, result, w) for w in result.study.watched}


def sweep(study: Study, variants: Sequence[StoredVariant]) -> Found:
    """Ranges of the outputs over the variants, each parameter's Spearman rank correlation with each
    output, and (with an objective) the best feasible variant (Spearman, *Am. J. Psychol.* 15, 1904;
    :func:`scipy.stats.spearmanr`)."""
    from scipy.stats import spearmanr

    ok = [v for v in variants if v.status == "ok"]
    X = np.array([[v.parameters[p.name] for p in study.parameters] for v in ok]) if ok else np.zeros((0, 0))
    spread: dict[str, Any] = {}
    corr: dict[str, Any] = {}
    for w in study.watched:
        y = np.array([value(v, w.key) for v in ok])
        good = np.isfinite(y)
        spread[w.key] = {
            "min": float(y[good].min()) if good.any() else None,
            "max": float(y[good].max()) if good.any() else None,
        }
        corr[w.key] = {}
        for j, p in enumerate(study.parameters):
            # a choice's values are indices of names in no order: no rank to correlate with
            if not p.choices and good.sum() > 2 and np.ptp(X[good, j]) > 0 and np.ptp(y[good]) > 0:
                corr[w.key][p.name] = float(spearmanr(X[good, j], y[good]).statistic)
            else:
                corr[w.key][p.name] = None
    findings: dict[str, Any] = {"output_ranges": spread, "rank_correlation": corr}
    b = best(study, variants)
    if b is not None:
        findings["best"] = describe(study, b)
    base = variants[0] if variants else None
    if base is not None:
        findings["base"] = describe(study, base)
    return Found(findings, frozenset({b.id}) if b is not None else frozenset())


def _sweep_tables(result: StudyFindings) -> list[Table]:
    """Each output's range over the variants and the parameters ranked by their rank correlation with
    it (ρ from −1 to 1; the sign says whether the output grows with the parameter), the strongest
    first; then the best design (with an objective) and the base."""
    st, f = result.study, result.findings
    rows = []
    for w in st.watched:
        r = f["output_ranges"].get(w.key, {})
        corr = f["rank_correlation"].get(w.key, {})
        ranked = sorted(((n, c) for n, c in corr.items() if c is not None), key=lambda nc: -abs(nc[1]))
        text = ", ".join(f"{n} {signed(c, RHO_DIGITS)}" for n, c in ranked) or "—"
        shown = w.readable([r.get("min"), r.get("max")])
        rows.append([shown.label, shown.show(r.get("min")), shown.show(r.get("max")), text])
    out = [
        table(
            f"{st.name}: outputs over the variants, parameters ranked by rank correlation ρ",
            ["output", "lowest", "highest", "parameters by |ρ|"],
            rows,
        )
    ]
    if f.get("best"):
        out.append(variant_table(result, f["best"], "optimum"))
    if f.get("base"):
        out.append(variant_table(result, f["base"], "base design"))
    return out


@register
class Factorial(Kind):
    """Every combination of the parameters' levels (a range: its two ends), and the base design."""

    name = "factorial"
    title = "full factorial"
    uses = "levels"

    def design(self, study: Study) -> np.ndarray:
        return np.vstack([base_row(study), grid(_levels(study))])

    def findings(self, study: Study, variants: list[StoredVariant]) -> Found:
        """As :func:`sweep`, and ``factorial``: :func:`factorial_effects` over the grid."""
        found = sweep(study, variants)
        found.findings["factorial"] = factorial_effects(study, variants[1:], _levels(study))
        return found

    def tables(self, result: StudyFindings) -> list[Table]:
        return _sweep_tables(result)[:1] + _factorial_tables(result) + _sweep_tables(result)[1:]

    def plots(self, result: StudyFindings) -> dict[str, Callable[[], Any]]:
        from mechdyn.studies import plots as sp

        out: dict[str, Callable[[], Any]] = {}
        for w in result.study.watched:
            if "error" not in result.findings["factorial"].get(w.key, {"error": 1}):
                out[f"main_effects_{safe(w.key)}.png"] = partial(sp.main_effects, result, w)
        return out | parallel_plot(result)


def factorial_effects(study: Study, variants: list[StoredVariant], levels: list[Any]) -> dict[str, Any]:
    """Main effects, two-way interactions and the best and worst design of each output over a full
    factorial (Montgomery, *Design and Analysis of Experiments*, ch. 5 and 6).

    The main effect of level ℓ of parameter A is ȳ(A = ℓ) − ȳ; the interaction of levels ℓ, m of A
    and B is ȳ(A = ℓ, B = m) − ȳ(A = ℓ) − ȳ(B = m) + ȳ, over the variants of the grid (the base design,
    when it is not a point of the grid, is left out). Each output gets, per parameter, its level means
    and the spread of its main effects (largest minus smallest), per pair of parameters the largest
    interaction in magnitude, and the ids of the variants where it is lowest and highest. An output
    missing from any variant of the grid gets ``{"error": ...}``.

    Parameters
    ----------
    study : Study
    variants : list of StoredVariant
        The grid's variants.
    levels : list of sequence of float
        Each parameter's levels, SI.
    """
    P = len(study.parameters)
    idx = np.array(
        [
            [
                int(np.argmin(np.abs(np.asarray(lv, dtype=float) - v.parameters[p.name])))
                for p, lv in zip(study.parameters, levels, strict=True)
            ]
            for v in variants
        ],
        dtype=int,
    ).reshape(len(variants), P)
    out: dict[str, Any] = {}
    for w in study.watched:
        y = np.array([value(v, w.key) for v in variants])
        if not len(y) or not np.isfinite(y).all():
            out[w.key] = {"error": f"{int((~np.isfinite(y)).sum())} of {len(y)} variants have no value"}
            continue
        mean = float(y.mean())
        main: dict[str, Any] = {}
        for j, p in enumerate(study.parameters):
            means = [float(y[idx[:, j] == k].mean()) for k in range(len(levels[j]))]
            main[p.name] = {
                "levels": [float(x) for x in levels[j]],
                "means": means,
                "effects": [m - mean for m in means],
                "spread": max(means) - min(means),
            }
        pairs = []
        for a in range(P):
            for b in range(a + 1, P):
                biggest = 0.0
                for ka in range(len(levels[a])):
                    for kb in range(len(levels[b])):
                        cell = (idx[:, a] == ka) & (idx[:, b] == kb)
                        inter = (
                            y[cell].mean() - main[study.parameters[a].name]["means"][ka]
                            - main[study.parameters[b].name]["means"][kb] + mean
                        )  # fmt: skip
                        biggest = max(biggest, abs(float(inter)))
                pairs.append(
                    {"parameters": [study.parameters[a].name, study.parameters[b].name], "largest": biggest}
                )
        out[w.key] = {
            "mean": mean,
            "main": main,
            "interactions": sorted(pairs, key=lambda d: -d["largest"]),
            "lowest": variants[int(np.argmin(y))].id,
            "highest": variants[int(np.argmax(y))].id,
        }
    return out


def _factorial_tables(result: StudyFindings) -> list[Table]:
    """Per output of a factorial study: main effects by level (parameters by the spread of their
    effects), the two-way interactions, and the designs where it is lowest and highest; the output
    in words, in its study unit (else the unit its level means read best in)."""
    st = result.study
    by_id = {v.id: v for v in result.variants}
    params = {p.name: p for p in st.parameters}
    out: list[Table] = []
    for key, e in result.findings["factorial"].items():
        w = next(w for w in st.watched if w.key == key)
        if "error" in e:
            out.append(table(f"{st.name}: effects on {w.words}", ["note"], [[e["error"]]]))
            continue
        w = w.readable([e["mean"], *(m for main in e["main"].values() for m in main["means"])])
        unit = unit_text(w.shown_unit)
        in_unit = f" [{unit}]" if unit else ""
        rows = []
        for name, m in sorted(e["main"].items(), key=lambda kv: -kv[1]["spread"]):
            for level, mean, effect in zip(m["levels"], m["means"], m["effects"], strict=True):
                rows.append([name, parameter_text(params[name], level), w.show(mean), w.difference(effect)])
        out.append(
            table(
                f"{st.name}: main effects on {w.words} (grid mean {number(w.show(e['mean']))}"
                + (f" {unit}" if unit else "")
                + "), largest first",
                ["parameter", "level", w.label, "effect" + in_unit],
                rows,
            )
        )
        if e["interactions"]:
            out.append(
                table(
                    f"{st.name}: two-way interactions on {w.words}, largest first",
                    ["parameters", "largest interaction" + in_unit],
                    [[" × ".join(d["parameters"]), w.difference(d["largest"])] for d in e["interactions"]],
                )
            )
        rows = []
        for what in ("lowest", "highest"):
            v = by_id.get(e[what])
            if v is not None:
                shown = [parameter_text(p, v.parameters[p.name]) for p in st.parameters]
                rows.append([what, v.id, *shown, w.show(v.outputs.get(key))])
        out.append(
            table(
                f"{st.name}: where {w.words} is lowest and highest",
                ["", "variant", *(p.name for p in st.parameters), w.label],
                rows,
            )
        )
    return out


@register
class LatinHypercube(Kind):
    """A Latin hypercube over the ranges (:class:`scipy.stats.qmc.LatinHypercube`; McKay, Beckman &
    Conover, *Technometrics* 21, 1979), ``samples`` variants (default 10 per parameter), and the base."""

    name = "lhs"
    title = "Latin hypercube"

    def design(self, study: Study) -> np.ndarray:
        from scipy.stats import qmc

        n = study.samples or 10 * len(study.parameters)
        u = qmc.LatinHypercube(d=len(study.parameters), seed=study.seed).random(n)
        lo = np.array([p.low for p in study.parameters], dtype=float)
        hi = np.array([p.high for p in study.parameters], dtype=float)
        return np.vstack([base_row(study), lo + u * (hi - lo)])

    def findings(self, study: Study, variants: list[StoredVariant]) -> Found:
        """As :func:`sweep`."""
        return sweep(study, variants)

    def tables(self, result: StudyFindings) -> list[Table]:
        return _sweep_tables(result)

    def plots(self, result: StudyFindings) -> dict[str, Callable[[], Any]]:
        return parallel_plot(result)
