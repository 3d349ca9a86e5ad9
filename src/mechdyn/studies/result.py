"""A study's result, with the result protocol: its summary, its tables and its plots."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from mechdyn.results import Result, Table
from mechdyn.store.studies import StoredStudy, StoredVariant
from mechdyn.studies.study import Study

__all__ = ["StudyResult"]


@dataclass(frozen=True)
class StudyResult(Result):
    """What a study found, and every variant it holds.

    Attributes
    ----------
    study : Study
    stored : StoredStudy
        Its row in the results database.
    variants : tuple of StoredVariant
        The study's variants in design order (optimization and synthesis: every variant stored).
    evaluated : int
        Variants of the result evaluated by this run (or stored meanwhile by another process sharing
        the study); ``evaluated + reused`` is the number of variants.
    reused : int
        Variants of the result found already stored (a resumed study).
    failed : int
        Variants that could not be evaluated (stored with their error).
    findings : dict
        What the kind found (SI): ``effects`` (oat), ``indices`` (sobol), ``best`` and
        ``improvement_percent`` (optimize), ``pareto_front``, ``targets`` (synthesis), ...
    kept : tuple of StoredVariant
        Variants with their curves (the base and the best; every variant of a small study).
    """

    study: Study
    stored: StoredStudy
    variants: tuple[StoredVariant, ...]
    evaluated: int
    reused: int
    failed: int
    findings: dict[str, Any]
    kept: tuple[StoredVariant, ...] = ()

    def summary(self) -> dict[str, Any]:
        """``study``, ``kind``, ``evaluated``, ``reused``, ``failed``, ``variants`` and the findings."""
        return {
            "study": self.study.name,
            "kind": self.study.kind,
            "analysis": self.study.analysis,
            "variants": len(self.variants),
            "evaluated": self.evaluated,
            "reused": self.reused,
            "failed": self.failed,
            "parameters": {
                p.name: {
                    "base": p.base,
                    "unit": p.unit,
                    "low": p.low,
                    "high": p.high,
                    "levels": list(p.levels),
                }
                for p in self.study.parameters
            },
            **self.findings,
        }

    def to_frame(self) -> Any:
        """One row per variant: id, status, parameters (SI) and outputs (SI)."""
        import pandas as pd

        rows = []
        for v in self.variants:
            row: dict[str, Any] = {"variant": v.id, "status": v.status}
            row |= {_column(p.name, _si_unit(p)): v.parameters.get(p.name) for p in self.study.parameters}
            row |= {_column(w.key, _key_suffix(w.unit)): v.outputs.get(w.key) for w in self.study.watched}
            row["error"] = v.error
            rows.append(row)
        return pd.DataFrame(rows)

    def arrays(self) -> dict[str, tuple[np.ndarray, str]]:
        return {}

    # -- tables -------------------------------------------------------------------------------
    def tables(self, **display_units: str) -> list[Table]:
        """The table a designer expects of the kind, in the outputs' display units."""
        st, f = self.study, self.findings
        out: list[Table] = []
        kind = st.kind
        if kind == "oat":
            cols = ["parameter", "level"]
            for w in st.watched:
                cols += [w.label, "change [%]"]
            rows = [["(base)", ""] + [x for w in st.watched for x in (w.show(f["base"].get(w.key)), None)]]
            for e in f["effects"]:
                level = e["level"] + (
                    f" ({e['level_percent']:+.0f} %)" if e["level_percent"] is not None else ""
                )
                row = [e["parameter"], level]
                for w in st.watched:
                    o = e["outputs"][w.key]
                    row += [w.show(o["value"]), o["change_percent"]]
                rows.append(row)
            out.append(Table(f"{st.name}: one at a time", cols, rows))
        if kind == "sobol":
            for key, ind in f["indices"].items():
                w = next(w for w in st.watched if w.key == key)
                if "error" in ind:
                    out.append(Table(f"Sobol indices of {w.key}", ["note"], [[ind["error"]]]))
                    continue
                ranked = sorted(ind.items(), key=lambda kv: -kv[1]["ST"])
                out.append(
                    Table(
                        f"Sobol indices of {w.key} (95 % intervals), ranked by total order",
                        ["parameter", "S1", "± S1", "ST", "± ST"],
                        [[n, d["S1"], d["S1_conf"], d["ST"], d["ST_conf"]] for n, d in ranked],
                    )
                )
        if kind in ("lhs", "factorial") and "rank_correlation" in f:
            out.append(self._ranking_table())
        if kind == "factorial" and "factorial" in f:
            out += self._factorial_tables()
        if kind == "optimize" and "best" in f and f["best"] is None:
            out.append(Table(f"{st.name}: optimum", ["note"], [["no variant keeps every constraint"]]))
        for key in ("best", "base"):
            if f.get(key) and kind in ("optimize", "synthesis", "factorial", "lhs"):
                out.append(self._variant_table(f[key], "optimum" if key == "best" else "base design"))
        if kind == "optimize" and f.get("best") and "pareto_front" not in f:
            out.append(self._optimality_table())
        if "pareto_front" in f:
            ws = [o.output for o in st.objectives]
            out.append(
                Table(
                    f"{st.name}: Pareto front ({len(f['pareto_front'])} designs; the knee is nearest the "
                    "ideal point, each objective scaled to its range on the front)",
                    ["", "variant", *(p.name for p in st.parameters), *(w.label for w in ws)],
                    [
                        [
                            _front_role(f, d["variant"]),
                            d["variant"],
                            *(d["given"].get(p.name) for p in st.parameters),
                            *(w.show(d["outputs"].get(w.key)) for w in ws),
                        ]
                        for d in sorted(f["pareto_front"], key=lambda d: d["outputs"].get(ws[0].key) or 0.0)
                    ],
                )
            )
        if "targets" in f:
            rows = []
            for t in f["targets"]:
                w = next(w for w in st.watched if w.key == t["output"])
                margin = t.get("margin")
                shown = w.show(abs(margin)) if margin is not None else None
                if margin is None or shown is None:
                    verdict = "no value"
                elif t.get("holds", margin >= 0):
                    verdict = f"holds ({shown:.3g} to spare)"
                else:
                    verdict = f"MISSED by {shown:.3g}"
                rows.append(
                    [
                        w.label,
                        w.show(t["target"]),
                        w.show(t["tolerance"]),
                        w.show(t["value"]),
                        verdict,
                        w.show(t["base_value"]),
                    ]
                )
            out.append(
                Table(
                    f"{st.name}: targets", ["output", "target", "tolerance", "fit", "verdict", "base"], rows
                )
            )
            if f.get("missed_because"):
                out.append(Table(f"{st.name}: why a target is missed", ["note"], [[f["missed_because"]]]))
        out.append(
            Table(
                f"{st.name}: variants",
                ["variants", "evaluated now", "reused", "failed"],
                [[len(self.variants), self.evaluated, self.reused, self.failed]],
            )
        )
        return out

    def _optimality_table(self) -> Table:
        """How far the optimum can be trusted: the first-order measure, what holds it (the active
        constraints and bounds, each with what relaxing it by one unit is worth), the evaluations,
        and the optimum evaluated again through the analysis itself."""
        f = self.findings
        proof = f.get("optimality")
        o = self.study.objectives[0]
        verb = "lowers" if o.sense == "minimize" else "raises"
        rows: list[list[Any]] = []
        if proof is None:
            rows.append(["first-order optimality", "not shown (no gradient stored at the optimum)"])
        else:
            rows.append(["first-order optimality (KKT residual, relative)", proof["measure"]])
            if not proof["active"]:
                rows.append(["held by", "nothing: an interior optimum"])
            for a in proof["active"]:
                rows.append(
                    [
                        f"{a['per']} more on {a['name']}",
                        f"{verb} the objective by {a['worth']:.4g} {proof['unit']}",
                    ]
                )
        polished = f.get("polish")
        if polished:
            rows.append(
                [
                    "polish",
                    f"{polished['method']} from {polished['starts']} start(s), "
                    f"{polished['iterations']} iterations",
                ]
            )
        rows.append(["variants evaluated in all", f.get("evaluations")])
        check = f.get("single_design_check")
        if check:
            diff = check.get("relative_difference")
            rows.append(
                [
                    "optimum through the analysis itself",
                    "failed: " + str(check.get("status"))
                    if diff is None
                    else f"agrees to {diff:.1e} (relative)",
                ]
            )
        return Table(f"{self.study.name}: how good the optimum is", ["", "value"], rows)

    def _ranking_table(self) -> Table:
        """Each output's range over the variants and the parameters ranked by their Spearman rank
        correlation with it (ρ from −1 to 1; the sign says whether the output grows with the
        parameter), the strongest first."""
        st, f = self.study, self.findings
        rows = []
        for w in st.watched:
            r = f["output_ranges"].get(w.key, {})
            corr = f["rank_correlation"].get(w.key, {})
            ranked = sorted(((n, c) for n, c in corr.items() if c is not None), key=lambda nc: -abs(nc[1]))
            text = ", ".join(f"{n} {c:+.2f}" for n, c in ranked) or "—"
            rows.append([w.label, w.show(r.get("min")), w.show(r.get("max")), text])
        return Table(
            f"{st.name}: outputs over the variants, parameters ranked by rank correlation ρ",
            ["output", "lowest", "highest", "parameters by |ρ|"],
            rows,
        )

    def _factorial_tables(self) -> list[Table]:
        """Per output of a factorial study: main effects by level (parameters by the spread of their
        effects), the two-way interactions, and the designs where it is lowest and highest."""
        st = self.study
        by_id = {v.id: v for v in self.variants}
        params = {p.name: p for p in st.parameters}
        out: list[Table] = []
        for key, e in self.findings["factorial"].items():
            w = next(w for w in st.watched if w.key == key)
            if "error" in e:
                out.append(Table(f"{st.name}: effects on {w.key}", ["note"], [[e["error"]]]))
                continue
            unit = w.shown_unit
            rows = []
            for name, m in sorted(e["main"].items(), key=lambda kv: -kv[1]["spread"]):
                for level, mean, effect in zip(m["levels"], m["means"], m["effects"], strict=True):
                    rows.append([name, params[name].shown(level), w.show(mean), _shown_difference(w, effect)])
            out.append(
                Table(
                    f"{st.name}: main effects on {w.key} (grid mean {w.show(e['mean']):.4g}"
                    + (f" {unit}" if unit else "")
                    + "), largest first",
                    ["parameter", "level", w.label, "effect" + (f" [{unit}]" if unit else "")],
                    rows,
                )
            )
            if e["interactions"]:
                out.append(
                    Table(
                        f"{st.name}: two-way interactions on {w.key}, largest first",
                        ["parameters", "largest interaction" + (f" [{unit}]" if unit else "")],
                        [
                            [" × ".join(d["parameters"]), _shown_difference(w, d["largest"])]
                            for d in e["interactions"]
                        ],
                    )
                )
            rows = []
            for what in ("lowest", "highest"):
                v = by_id.get(e[what])
                if v is not None:
                    rows.append(
                        [
                            what,
                            v.id,
                            *(p.shown(v.parameters[p.name]) for p in st.parameters),
                            w.show(v.outputs.get(key)),
                        ]
                    )
            out.append(
                Table(
                    f"{st.name}: where {w.key} is lowest and highest",
                    ["", "variant", *(p.name for p in st.parameters), w.label],
                    rows,
                )
            )
        return out

    def _variant_table(self, d: dict[str, Any], title: str) -> Table:
        st = self.study
        rows: list[list[Any]] = [[p.name, d["given"].get(p.name)] for p in st.parameters]
        rows += [[w.label, w.show(d["outputs"].get(w.key))] for w in st.watched]
        rows += [[c["constraint"], "holds" if c["holds"] else "VIOLATED"] for c in d.get("constraints", [])]
        if title == "optimum" and self.findings.get("improvement_percent") is not None:
            rows.append(["improvement of the objective [%]", self.findings["improvement_percent"]])
        return Table(f"{st.name}: {title} (variant {d['variant']})", ["", "value"], rows)

    @property
    def base_id(self) -> int | None:
        """The stored id of the study's base design (the model as given), or None when the study has
        none among its variants (a Sobol or Latin-hypercube sample)."""
        f = self.findings
        if f.get("base_variant") is not None:
            return int(f["base_variant"])
        base = f.get("base")
        return int(base["variant"]) if isinstance(base, dict) and base.get("variant") is not None else None

    # -- plots --------------------------------------------------------------------------------
    def plots(self, **display_units: str) -> dict[str, Any]:
        """Tornado (oat), Sobol bars, objective history and Pareto front (optimize), parameter
        scatter (sweeps), overlaid curves of the kept variants."""
        from mechdyn.studies import plots as sp

        kind = self.study.kind
        out: dict[str, Any] = {}
        if kind == "oat":
            for w in self.study.watched:
                out[f"tornado_{_safe(w.key)}.png"] = lambda w=w: sp.tornado(self, w)
        if kind == "factorial" and "factorial" in self.findings:
            for w in self.study.watched:
                if "error" not in self.findings["factorial"].get(w.key, {"error": 1}):
                    out[f"main_effects_{_safe(w.key)}.png"] = lambda w=w: sp.main_effects(self, w)
        if kind == "sobol":
            for w in self.study.watched:
                if "error" not in self.findings["indices"].get(w.key, {"error": 1}):
                    out[f"sobol_{_safe(w.key)}.png"] = lambda w=w: sp.sobol_bars(self, w)
        if kind in ("optimize", "synthesis"):
            out["history.png"] = lambda: sp.history(self)
        if "pareto_front" in self.findings:
            out["pareto.png"] = lambda: sp.pareto(self)
        if kind in ("lhs", "factorial", "sobol", "optimize", "synthesis"):
            out["parallel_coordinates.png"] = lambda: sp.parallel(self)
        x, names = sp.curve_choice(self.kept)
        for name in names:
            out[f"curves_{_safe(name)}.png"] = lambda name=name: sp.curves(
                self.kept, name, x, base=self.base_id
            )
        return out


def _si_unit(p: Any) -> str:
    return _key_suffix(p.unit)


def _key_suffix(unit: str) -> str:
    from mechdyn.units import key_suffix

    return key_suffix(unit)


def _column(name: str, suffix: str) -> str:
    """A column name without spaces that ends with its SI unit (``support.stiffness_N_per_m``)."""
    from mechdyn.units import key_unit

    name = name.replace(" ", "_")
    if key_unit(name) is not None or not suffix:
        return name
    return f"{name}_{suffix}"


def _safe(key: str) -> str:
    return "".join(c if c.isalnum() or c in "_-" else "_" for c in key)


def _shown_difference(w: Any, value: float | None) -> float | None:
    """A difference of an output (an effect) in its display unit (a scale: the units are ratios)."""
    if value is None:
        return None
    unit_one = w.show(1.0)
    zero = w.show(0.0)
    return None if unit_one is None or zero is None else value * (unit_one - zero)


def _front_role(findings: dict[str, Any], variant: int) -> str:
    """ "knee" and "best OUTPUT" for the designs of a Pareto front that are so."""
    roles = ["knee"] if findings.get("knee") == variant else []
    roles += [f"best {key}" for key, v in (findings.get("ends") or {}).items() if v == variant]
    return ", ".join(roles)
