"""Sobol sensitivity indices (``sobol``)."""

from __future__ import annotations

from collections.abc import Callable
from functools import partial
from typing import TYPE_CHECKING, Any

import numpy as np

from mechdyn.results import Table
from mechdyn.studies.cells import table
from mechdyn.studies.errors import StudyError
from mechdyn.studies.kinds.base import Found, Kind, parallel_plot, register, safe, value
from mechdyn.studies.storage import StoredVariant

if TYPE_CHECKING:
    from mechdyn.studies.plan import Study, StudyFindings

__all__ = ["Sobol"]


def _problem(study: Study) -> dict[str, Any]:
    return {
        "num_vars": len(study.parameters),
        "names": [p.name for p in study.parameters],
        "bounds": [[p.low, p.high] for p in study.parameters],
    }


@register
class Sobol(Kind):
    """First- and total-order Sobol indices with 95 % confidence intervals: Saltelli's sampling and
    Jansen's estimators, by SALib (Saltelli et al., *Global Sensitivity Analysis. The Primer*, 2008;
    Herman & Usher, *JOSS* 2, 2017); ``samples`` base samples N (a power of 2), N·(P + 2) variants."""

    name = "sobol"
    title = "Sobol indices"

    def check(self, study: Study) -> None:
        super().check(study)
        n = study.samples or 256
        if n & (n - 1):
            raise StudyError(
                f"{study.path or study.name}: [study] samples = {n}: Sobol sampling needs a power of 2 "
                "(e.g. 256)"
            )

    def design(self, study: Study) -> np.ndarray:
        from SALib.sample import sobol as sample

        return np.asarray(
            sample.sample(_problem(study), study.samples or 256, calc_second_order=False, seed=study.seed)
        )

    def findings(self, study: Study, variants: list[StoredVariant]) -> Found:
        """``base_samples`` and ``indices``: per output, per parameter ``S1``, ``S1_conf``, ``ST`` and
        ``ST_conf`` (or ``{"error": ...}`` for an output missing from a variant, or constant)."""
        from SALib.analyze import sobol as analyze

        failed = sum(1 for v in variants if v.status != "ok")
        indices: dict[str, Any] = {}
        for w in study.watched:
            Y = np.array([value(v, w.key) for v in variants])
            if not np.isfinite(Y).all():
                indices[w.key] = {
                    "error": f"{int((~np.isfinite(Y)).sum())} of {Y.size} variants have no value (failed: "
                    f"{failed}); narrow the ranges so that every variant can be evaluated"
                }
                continue
            if np.ptp(Y) == 0:
                indices[w.key] = {"error": "the output does not change over the ranges"}
                continue
            r = analyze.analyze(_problem(study), Y, calc_second_order=False, conf_level=0.95, seed=study.seed)
            indices[w.key] = {
                p.name: {
                    "S1": float(r["S1"][j]),
                    "S1_conf": float(r["S1_conf"][j]),
                    "ST": float(r["ST"][j]),
                    "ST_conf": float(r["ST_conf"][j]),
                }
                for j, p in enumerate(study.parameters)
            }
        return Found({"base_samples": study.samples or 256, "indices": indices})

    def tables(self, result: StudyFindings) -> list[Table]:
        """Per output (in words): each parameter's first- and total-order index with its 95 %
        interval, the largest total order first."""
        words = {w.key: w.words for w in result.study.watched}
        out = []
        for key, ind in result.findings["indices"].items():
            if "error" in ind:
                out.append(table(f"Sobol indices of {words.get(key, key)}", ["note"], [[ind["error"]]]))
                continue
            ranked = sorted(ind.items(), key=lambda kv: -kv[1]["ST"])
            out.append(
                table(
                    f"Sobol indices of {words.get(key, key)} (95 % intervals), ranked by total order",
                    ["parameter", "S1", "± S1", "ST", "± ST"],
                    [[n, d["S1"], d["S1_conf"], d["ST"], d["ST_conf"]] for n, d in ranked],
                )
            )
        return out

    def plots(self, result: StudyFindings) -> dict[str, Callable[[], Any]]:
        from mechdyn.studies import plots as sp

        out: dict[str, Callable[[], Any]] = {}
        for w in result.study.watched:
            if "error" not in result.findings["indices"].get(w.key, {"error": 1}):
                out[f"sobol_{safe(w.key)}.png"] = partial(sp.sobol_bars, result, w)
        return out | parallel_plot(result)
