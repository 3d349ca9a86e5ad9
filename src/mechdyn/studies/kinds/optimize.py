"""Constrained optimization (``optimize``): one objective, or several and their Pareto front."""

from __future__ import annotations

import math
import time
import warnings
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from mechdyn.results import Table
from mechdyn.studies.cells import MEASURE_DIGITS, given, number, parameter_text, table, unit_text
from mechdyn.studies.errors import StudyError
from mechdyn.studies.kinds import liveness
from mechdyn.studies.kinds.base import (
    Found,
    Kind,
    Ran,
    base_row,
    best,
    describe,
    feasible,
    least_violation,
    least_violation_table,
    parallel_plot,
    register,
    value,
    variant_table,
)
from mechdyn.studies.polish import (
    CONVERGED,
    FIRST_ORDER,
    ITERATION_LIMIT,
    NOT_CONVERGED,
    optimality,
    polish,
    verdict,
)
from mechdyn.studies.storage import StoredVariant, variant_key

if TYPE_CHECKING:
    from mechdyn.studies.plan import Study, StudyFindings

__all__ = ["FIRST_ORDER", "TIE", "Optimize", "objective_of", "pareto_front"]

# FIRST_ORDER (from mechdyn.studies.polish, where the verdicts are given): a KKT residual at or below
# it (relative) is a first-order point; kept importable here, where the findings judge the optimum
TIE = 1e-6
"""Relative: a polished design (with its proof) within this of the best is the optimum."""


@register
class Optimize(Kind):
    """Optuna (Akiba et al., KDD 2019): for one objective a global stage (TPE, random or scrambled
    Sobol points) and a constrained SLSQP polish of its best designs (:mod:`mechdyn.studies.polish`);
    for several, NSGA-II (Deb et al., *IEEE Trans. Evol. Comput.* 6, 2002) and the Pareto front.
    Constraints through ``trial.set_constraint``; a failed variant is infeasible. Trials are asked in
    batches of ``batch``, each batch evaluated as one block; several processes may share the study
    (:mod:`mechdyn.studies.kinds.liveness`). With scatter (robust design), objectives and constraints
    are statistics over it, each design estimated on common random numbers
    (:mod:`mechdyn.studies.kinds.robust`)."""

    name = "optimize"
    title = "optimization"

    def check(self, study: Study) -> None:
        super().check(study)
        if study.robust:
            from mechdyn.studies.kinds.robust import sampling

            n, r = sampling(study)
            if n < 4 or (r > 1 and n & (n - 1)):
                raise StudyError(
                    f"{study.path or study.name}: scatter_samples = {n}: give at least 4, a power of 2 "
                    'for method = "qmc" (e.g. 128)'
                )
        if not study.objectives:
            raise StudyError(
                f"{study.path or study.name}: an optimize study needs [[objectives]] (output and goal)"
            )

    # -- running ------------------------------------------------------------------------------
    def run(self, runner: Any) -> Ran:
        import optuna

        from mechdyn.studies.storage import optuna_name

        st = runner.study
        optuna.logging.set_verbosity(optuna.logging.WARNING)
        multi = len(st.objectives) > 1
        sampler = optuna.samplers.NSGAIISampler(seed=st.seed) if multi else _sampler(st)
        with runner.store.store.schema_lock(), warnings.catch_warnings():  # Optuna's tables, once
            warnings.simplefilter("ignore", optuna.exceptions.ExperimentalWarning)
            # a trial whose process died (kill -9) has no heartbeat after HEARTBEAT_GRACE s: it is
            # failed then, marked abandoned and asked again (liveness.retry)
            storage = optuna.storages.RDBStorage(
                runner.store.store.url,
                heartbeat_interval=liveness.HEARTBEAT,
                grace_period=liveness.HEARTBEAT_GRACE,
                heartbeat_stale_trial_callback=liveness.retry,
            )
        try:
            study = optuna.create_study(
                study_name=optuna_name(st.name),
                storage=storage,
                sampler=sampler,
                directions=[o.sense for o in st.objectives],
                load_if_exists=True,
            )
            if not study.trials:  # the base design first, then given starts (the optimum of a smaller box)
                for row in (runner.base_row(), *st.start):
                    study.enqueue_trial({p.name: float(x) for p, x in zip(st.parameters, row, strict=True)})
            with warnings.catch_warnings():  # the heartbeats are recorded here, around ask and tell
                warnings.filterwarnings(
                    "ignore", "Heartbeat of storage is supposed to be used with Study.optimize"
                )
                warnings.simplefilter("ignore", optuna.exceptions.ExperimentalWarning)
                ids = _trials(runner, study, storage)
        finally:
            storage.remove_session()
            storage.engine.dispose()
        base = runner.evaluate(runner.base_row())[0]
        extra: dict[str, Any] = {"trials": len(ids)}
        if not multi:  # the local stage: SLSQP from the best designs the sampler found (and the starts)
            found = runner.store.by_ids(ids)
            extra["polish"] = polish(runner, _starts(runner, [base, *found]), objective=objective_of(st))
        return Ran(self.order(st, runner.all_variants()), extra)

    def confirm(self, runner: Any, found: Found) -> dict[str, Any]:
        """The optimum evaluated again through the analysis itself (not the batch): the objective's
        relative difference (round-off when both paths agree); with scatter, its nominal and a few
        of its samples (:meth:`mechdyn.studies.kinds.robust.RobustEvaluator.check`)."""
        from mechdyn.studies.evaluate import Evaluator

        st = runner.study
        b = found.findings.get("best")
        if len(st.objectives) > 1 or not b:
            return {}
        key = st.objectives[0].output.key
        x = np.array([[b["parameters"][p.name] for p in st.parameters]])
        if st.robust:  # its nominal and a few of its samples one by one through the analysis itself
            from mechdyn.studies.kinds.robust import RobustEvaluator

            checked = RobustEvaluator(st).check(x[0])
            return {"single_design_check": {**checked, "value": b["outputs"].get(key)}}
        again = Evaluator(st.source, st.analysis, st.parameters, [key], st.options, batch=False)(x)[0]
        y0, y1 = b["outputs"].get(key), again.outputs.get(key)
        diff = abs(y1 - y0) / abs(y0) if y1 is not None and y0 else None
        return {"single_design_check": {"status": again.status, "value": y1, "relative_difference": diff}}

    # -- findings -----------------------------------------------------------------------------
    def findings(self, study: Study, variants: list[StoredVariant]) -> Found:
        """One objective: ``best`` (among the designs as good, within :data:`TIE`, one whose
        first-order optimality can be shown, a converged one first), ``base``,
        ``improvement_percent`` (of the objective over the base, > 0 when better), ``optimality``
        (:func:`mechdyn.studies.polish.optimality`), ``verdict`` on it
        (:func:`mechdyn.studies.polish.verdict`: ``"converged"`` or ``"not converged"``; that a
        polish start ran out of iterations only a run knows, in ``polish``), ``converged`` (true only
        when that verdict is), ``least_violation`` (where no variant keeps every constraint: the one
        that came nearest, :func:`~mechdyn.studies.kinds.base.least_violation`; else None) and
        ``evaluations``. Several: ``pareto_front`` with its ``knee`` and ``ends``
        (:func:`pareto_front`) and ``base``."""
        base = variants[0] if variants and variants[0].key == variant_key(base_row(study)) else None
        if len(study.objectives) > 1:
            front = pareto_front(study, [v for v in variants if base is None or v.id != base.id])
            ends = {**front, "base": describe(study, base) if base is not None else None}
            return Found(ends, frozenset(d["variant"] for d in front["pareto_front"]))
        o = study.objectives[0]
        by_key = {v.key: v for v in variants}
        plain = best(study, [v for v in variants if base is None or v.id != base.id] or variants)
        chosen, proof = plain, None
        if plain is not None:
            best_value = o.sign * value(plain, o.output.key)
            limit = best_value + TIE * abs(best_value)  # a polished design this close is as good
            ranked = sorted(
                (v for v in variants if feasible(study, v) and math.isfinite(value(v, o.output.key))),
                key=lambda v: o.sign * value(v, o.output.key),
            )
            for v in ranked:
                if o.sign * value(v, o.output.key) > limit:
                    break
                shown = optimality(study, v, by_key)
                if shown is None:
                    continue
                if proof is None:  # the first as good whose measure can be shown...
                    chosen, proof = v, shown
                if verdict(shown["measure"]) == CONVERGED:  # ...unless one as good has converged
                    chosen, proof = v, shown
                    break
        judged = verdict(proof["measure"]) if chosen is not None and proof is not None else NOT_CONVERGED
        counted = _counted(study)
        if counted:  # a step function of the design: a zero gradient there proves nothing
            judged = NOT_CONVERGED
        twins: list[StoredVariant] = []
        if chosen is not None and judged == CONVERGED:
            twins = [
                v
                for v in ranked
                if v.id != chosen.id
                and o.sign * value(v, o.output.key) <= limit
                and (shown := optimality(study, v, by_key)) is not None
                and verdict(shown["measure"]) == CONVERGED
            ]
        out: dict[str, Any] = {
            "best": describe(study, chosen) if chosen is not None else None,
            "base": describe(study, base) if base is not None else None,
            "improvement_percent": None,
            "optimality": proof,
            "verdict": judged,
            "converged": judged == CONVERGED,
            "not_judged": (
                f"{', '.join(counted)} counts samples beyond a limit: a step function of the design, "
                "whose first-order measure says nothing of optimality; constrain or minimise a "
                "quantile instead (the same event, smooth)"
                if counted
                else None
            ),
            "least_violation": least_violation(study, variants) if chosen is None else None,
            "non_unique": _non_unique(study, chosen, twins) if chosen is not None else None,
            "evaluations": len(variants),
        }
        if chosen is not None and base is not None:
            y0, y1 = value(base, o.output.key), value(chosen, o.output.key)
            out["improvement_percent"] = 100.0 * (y0 - y1) / abs(y0) * o.sign if y0 else None
        if getattr(study, "robust", False):  # an estimate: samples, interval, gain
            from mechdyn.studies.kinds.robust import robust_findings

            out["robust"] = robust_findings(study, chosen, base)
        return Found(out, frozenset({chosen.id}) if chosen is not None else frozenset())

    # -- showing ------------------------------------------------------------------------------
    def tables(self, result: StudyFindings) -> list[Table]:
        f = result.findings
        out: list[Table] = []
        if "pareto_front" in f:
            out.append(_front_table(result))
            if f.get("base"):
                out.append(variant_table(result, f["base"], "base design"))
            return out
        if f.get("best") is None:
            out.append(least_violation_table(result))
        else:
            out.append(variant_table(result, f["best"], "optimum"))
        if f.get("base"):
            out.append(variant_table(result, f["base"], "base design"))
        out.append(_optimality_table(result))
        return out

    def plots(self, result: StudyFindings) -> dict[str, Callable[[], Any]]:
        from mechdyn.studies import plots as sp

        out: dict[str, Callable[[], Any]] = {"history.png": lambda: sp.history(result)}
        if "pareto_front" in result.findings:
            out["pareto.png"] = lambda: sp.pareto(result)
        return out | parallel_plot(result)


def pareto_front(study: Study, variants: list[StoredVariant]) -> dict[str, Any]:
    """The Pareto front of the feasible variants (Optuna's non-dominated sort,
    :attr:`optuna.study.Study.best_trials`), its knee and its ends: ``pareto_front`` (the designs,
    :func:`~mechdyn.studies.kinds.base.describe`), ``knee`` (the id of the design nearest the ideal
    point once each objective is scaled to its range on the front: the compromise solution, Zeleny,
    *Multiple Criteria Decision Making*, 1973) and ``ends`` (per objective, the id of the front's best
    design in it)."""
    import optuna

    feas = [
        v
        for v in variants
        if feasible(study, v) and all(math.isfinite(value(v, o.output.key)) for o in study.objectives)
    ]
    out: dict[str, Any] = {"pareto_front": []}
    if not feas:
        return out
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    senses: list[Any] = [o.sense for o in study.objectives]
    s = optuna.create_study(directions=senses)
    s.add_trials(
        [
            optuna.trial.create_trial(
                values=[value(v, o.output.key) for o in study.objectives],
                params={},
                distributions={},
                user_attrs={"i": i},
            )
            for i, v in enumerate(feas)
        ]
    )
    front = [feas[i] for i in sorted(t.user_attrs["i"] for t in s.best_trials)]
    F = np.array([[o.sign * value(v, o.output.key) for o in study.objectives] for v in front])
    lo, hi = F.min(axis=0), F.max(axis=0)
    scaled = (F - lo) / np.where(hi > lo, hi - lo, 1.0)
    out["pareto_front"] = [describe(study, v) for v in front]
    out["knee"] = front[int(np.argmin(np.linalg.norm(scaled, axis=1)))].id
    out["ends"] = {o.output.key: front[int(np.argmin(F[:, j]))].id for j, o in enumerate(study.objectives)}
    return out


def _front_role(findings: dict[str, Any], variant: int) -> str:
    """ "knee" and "best OUTPUT" for the designs of a Pareto front that are so."""
    roles = ["knee"] if findings.get("knee") == variant else []
    roles += [f"best {key}" for key, v in (findings.get("ends") or {}).items() if v == variant]
    return ", ".join(roles)


def _front_table(result: StudyFindings) -> Table:
    st, f = result.study, result.findings
    ws = [o.output.readable(d["outputs"].get(o.output.key) for d in f["pareto_front"]) for o in st.objectives]
    return table(
        f"{st.name}: Pareto front ({len(f['pareto_front'])} designs; the knee is nearest the "
        "ideal point, each objective scaled to its range on the front)",
        ["", "variant", *(p.name for p in st.parameters), *(w.label for w in ws)],
        [
            [
                _front_role(f, d["variant"]),
                d["variant"],
                *(parameter_text(p, d["parameters"][p.name]) for p in st.parameters),
                *(w.show(d["outputs"].get(w.key)) for w in ws),
            ]
            for d in sorted(f["pareto_front"], key=lambda d: d["outputs"].get(ws[0].key) or 0.0)
        ],
    )


def _optimality_table(result: StudyFindings) -> Table:
    """How far the optimum can be trusted: the verdict on its first-order measure, what holds it
    (the active constraints and bounds, each with what relaxing it by one unit is worth; only at a
    converged optimum, where the multipliers mean that), where each polish start ended and with what
    verdict (a run), the evaluations, and the optimum evaluated again through the analysis itself."""
    f = result.findings
    proof = f.get("optimality")
    o = result.study.objectives[0]
    verb = "lowers" if o.sense == "minimize" else "raises"
    polished = f.get("polish") or {}
    rows: list[list[Any]] = []
    if f.get("best") is None:
        rows.append(["verdict", f"{NOT_CONVERGED}: no variant keeps every constraint"])
    else:
        estimate = (
            " (of the estimate on the common random numbers: see its interval)" if f.get("robust") else ""
        )
        rows.append(["verdict", _verdict_words(f, polished) + estimate])
        if proof is None:
            rows.append(["first-order optimality", "not shown (no gradient stored at the optimum)"])
        else:
            rows.append(["first-order optimality (KKT residual, relative)", proof["measure"]])
            names = ", ".join(a["name"] for a in proof["active"])
            if f.get("verdict") != CONVERGED:
                # the multipliers of a design short of a first-order point are no limit's worth
                held = "not judged: not a first-order point" + (f" (at {names})" if names else "")
                rows.append(["held by", held])
            elif not proof["active"]:
                rows.append(["held by", "nothing: an interior optimum"])
            for a in proof["active"] if f.get("verdict") == CONVERGED else ():
                rows.append(
                    [
                        f"{a['per']} more on {a['name']}",
                        f"{verb} the objective by {number(a['worth'])} {unit_text(proof['unit'])}".strip(),
                    ]
                )
    if polished:
        rows.append(
            [
                "polish",
                f"{polished['method']} from {polished['starts']} start(s), "
                f"{polished['iterations']} iterations",
            ]
        )
        ends = polished.get("per_start") or []
        for k, end in enumerate(ends, start=1):
            rows.append([f"polish start {k}", _start_words(o, end)])
        optima = _local_optima(ends)
        if len(optima) > 1:
            rows.append(
                [
                    "local optima",
                    f"the polish starts converged to {len(optima)} different values of the objective: "
                    "it has several local optima here, and only the global stage finds the basin of "
                    "the best",
                ]
            )
    twins = f.get("non_unique")
    if twins:
        params = {p.name: p for p in result.study.parameters}
        spread = "; ".join(
            f"{name} from {parameter_text(params[name], lo)} to {parameter_text(params[name], hi)}"
            for name, (lo, hi) in twins["spans"].items()
            if name in params and hi > lo
        )
        rows.append(
            [
                "unique",
                f"no: {len(twins['designs'])} first-order points as good as the optimum (within "
                f"{given(TIE)}), "
                f"at variants {', '.join(map(str, twins['designs']))}, spread over {spread}; the objective "
                "is flat along them: choose among them by another criterion (a second objective or a "
                "constraint)",
            ]
        )
    from mechdyn.studies.kinds.robust import table_rows

    rows += table_rows(result.study, f)
    rows.append(["variants evaluated in all", f.get("evaluations")])
    check = f.get("single_design_check")
    if check:
        diff = check.get("relative_difference")
        rows.append(
            [
                "optimum through the analysis itself",
                "failed: " + str(check.get("status"))
                if diff is None
                else f"agrees to {number(diff, MEASURE_DIGITS)} (relative)"
                + (
                    f", its nominal and {check['samples_checked']} samples of the scatter"
                    if "samples_checked" in check
                    else ""
                ),
            ]
        )
    title = "how good the optimum is" if f.get("best") is not None else "how near the search came"
    return table(f"{result.study.name}: {title}", ["", "value"], rows)


def _counted(study: Study) -> list[str]:
    """The objective or constraints that are a probability (``p_exceed``): counts of samples, flat
    between the designs where a sample crosses the limit, so no first-order measure judges them."""
    outputs = [o.output for o in study.objectives[:1]] + [c.output for c in study.constraints]
    return [w.words for w in outputs if getattr(w, "statistic", "") == "p_exceed"]


def _verdict_words(f: dict[str, Any], polished: dict[str, Any]) -> str:
    """The optimum's verdict in words, with the measure against its tolerance; a run that knows the
    polish start which ended at the optimum ran out of iterations says so."""
    proof = f.get("optimality")
    if f.get("not_judged"):
        return f"{NOT_CONVERGED}: {f['not_judged']}"
    if proof is None:
        return f"{NOT_CONVERGED}: its first-order measure cannot be shown (no gradient stored there)"
    measure = f"first-order measure {number(proof['measure'], MEASURE_DIGITS)}"
    if f.get("verdict") == CONVERGED:
        return f"{CONVERGED}: {measure} ≤ {given(FIRST_ORDER)}"
    ended_here = [e for e in polished.get("per_start") or [] if e.get("variant") == f["best"]["variant"]]
    if any(e.get("verdict") == ITERATION_LIMIT for e in ended_here):
        return f"{ITERATION_LIMIT}: {measure} > {given(FIRST_ORDER)}"
    return f"{NOT_CONVERGED}: {measure} > {given(FIRST_ORDER)}"


def _start_words(o: Any, end: dict[str, Any]) -> str:
    """Where one polish start ended: its verdict, the objective there and its measure."""
    if end.get("variant") is None:
        return f"{end['verdict']}: {end.get('message')}"
    w = o.output.readable([end.get("value")])
    y = w.show(end.get("value"))
    at = f"{number(y)} {unit_text(w.shown_unit)}".strip() if y is not None else "no value"
    m = end.get("measure")
    shown = number(m, MEASURE_DIGITS) if m is not None else "not shown"
    broken = "" if end.get("feasible") else ", a constraint broken"
    return (
        f"{end['verdict']}: {at} at variant {end['variant']}{broken} "
        f"(first-order measure {shown}, {end.get('iterations')} iterations)"
    )


NON_UNIQUE = 0.01
"""First-order points as good as the optimum (within :data:`TIE`) that lie further apart than this
share of a parameter's range make the optimum not unique: the objective is flat along a valley."""


def _non_unique(study: Study, chosen: StoredVariant, twins: list[StoredVariant]) -> dict[str, Any] | None:
    """Where other first-order points as good as the optimum lie apart from it: the designs, and each
    parameter's span over them (SI); None when every one lies within :data:`NON_UNIQUE` of its range
    (a unique optimum, as far as the stored points show)."""
    designs = [chosen, *twins]
    spans: dict[str, list[float]] = {}
    apart = False
    for p in study.parameters:
        xs = [v.parameters[p.name] for v in designs]
        width = (p.high - p.low) if p.low is not None and p.high is not None else abs(p.base) or 1.0
        spans[p.name] = [min(xs), max(xs)]
        apart |= (max(xs) - min(xs)) > NON_UNIQUE * width
    if not apart:
        return None
    return {"designs": [v.id for v in designs], "spans": spans}


def _local_optima(ends: list[dict[str, Any]]) -> list[float]:
    """The distinct objective values (SI) at which polish starts converged, each within
    :data:`TIE` of one of them counted once: more than one is a multi-modal objective."""
    optima: list[float] = []
    for y in sorted(e["value"] for e in ends if e.get("verdict") == CONVERGED and e.get("value") is not None):
        if not optima or abs(y - optima[-1]) > TIE * max(abs(y), abs(optima[-1])):
            optima.append(y)
    return optima


def _sampler(st: Study) -> Any:
    """The global stage's Optuna sampler for one objective."""
    import optuna

    if st.sampler == "random":
        return optuna.samplers.RandomSampler(seed=st.seed)
    if st.sampler == "qmc":
        with warnings.catch_warnings():  # experimental in Optuna, stable in use
            warnings.simplefilter("ignore", optuna.exceptions.ExperimentalWarning)
            return optuna.samplers.QMCSampler(qmc_type="sobol", scramble=True, seed=st.seed)
    return optuna.samplers.TPESampler(seed=st.seed)


def _starts(runner: Any, variants: list[StoredVariant]) -> list[np.ndarray]:
    """Where the polish starts: the best designs evaluated (feasible ones by objective, then the
    others by how far they break a constraint), the given starts and the base, without repeats."""
    st = runner.study
    o = st.objectives[0]

    def rank(v: StoredVariant) -> tuple[float, float]:
        y = value(v, o.output.key)
        if v.status != "ok" or not math.isfinite(y):
            return (math.inf, math.inf)
        worst = max((c.violation(v.outputs.get(c.output.key)) for c in st.constraints), default=0.0)
        return (max(worst, 0.0), o.sign * y)

    ranked = sorted((v for v in variants if rank(v)[0] < math.inf), key=rank)
    rows = [np.array([v.parameters[p.name] for p in st.parameters], dtype=float) for v in ranked[:1]]
    rows += [np.asarray(r, dtype=float) for r in st.start]
    rows.append(np.asarray(runner.base_row(), dtype=float))
    seen: set[str] = set()
    out = []
    for r in rows:
        k = variant_key(r.tolist())
        if k not in seen:
            seen.add(k)
            out.append(r)
    return out


def _trials(runner: Any, study: Any, storage: Any) -> list[int]:
    """Ask batches of trials, evaluate each batch as one block, tell the results; stop when the
    study holds ``samples`` evaluated trials (counting those of other processes on the same study,
    never those abandoned by a process that died). Returns the variant ids of the evaluated trials."""
    import optuna

    st = runner.study
    n_trials = st.samples or 100
    dists = {
        p.name: optuna.distributions.FloatDistribution(float(p.low), float(p.high)) for p in st.parameters
    }
    State = optuna.trial.TrialState
    me = liveness.owner()

    def evaluated() -> list[Any]:
        trials = study.get_trials(deepcopy=False)
        gone = liveness.abandoned(trials)
        return [
            t for t in trials if t.state.is_finished() and "variant" in t.user_attrs and t.number not in gone
        ]

    while True:
        liveness.fail_abandoned(study, storage)
        finished = len(evaluated())
        running = len(study.get_trials(deepcopy=False, states=(State.RUNNING,)))
        if finished >= n_trials:
            break
        n = min(st.batch, n_trials - finished - running)
        if n <= 0:  # the rest is being evaluated by another process (or will be failed as abandoned)
            time.sleep(0.5)
            continue
        trials = []
        for _ in range(n):
            t = study.ask(dists)
            storage.set_trial_system_attr(t._trial_id, liveness.OWNER, me)
            trials.append(t)
        X = np.array([[t.params[p.name] for p in st.parameters] for t in trials])
        with liveness.Heartbeat(storage, [t._trial_id for t in trials]):
            variants = runner.evaluate(X, objective=objective_of(st))
        for t, v in zip(trials, variants, strict=True):
            try:
                t.set_user_attr("variant", v.id)
                if v.status != "ok" or not all(math.isfinite(value(v, o.output.key)) for o in st.objectives):
                    study.tell(t, state=State.FAIL)
                    continue
                for i, c in enumerate(st.constraints):  # feasible where ≤ 0 (Optuna's convention)
                    t.set_constraint(f"{i + 1}: {c.describe()}", c.violation(v.outputs.get(c.output.key)))
                study.tell(t, [value(v, o.output.key) for o in st.objectives])
            except (optuna.exceptions.UpdateFinishedTrialError, RuntimeError, ValueError):
                # failed meanwhile by another process that took this one for dead: the trial is
                # asked again, and its variant is stored, so nothing is lost or recomputed
                continue
    return [t.user_attrs["variant"] for t in evaluated()]


def objective_of(study: Study) -> Callable[[dict[str, Any]], float] | None:
    """The first objective's value in a variant's outputs (NaN where missing), stored with the variant;
    None without objective."""
    if not study.objectives:
        return None
    key = study.objectives[0].output.key

    def f(outputs: dict[str, Any]) -> float:
        v = outputs.get(key)
        return float(v) if v is not None else math.nan

    return f
