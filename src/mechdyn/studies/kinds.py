"""The design and the findings of each study kind (see :mod:`mechdyn.studies.run`).

Each kind is a function ``kind(runner) -> (findings, variants, best)``: ``findings`` is JSON-ready
(SI), ``variants`` the stored variants of the study in design order, ``best`` the ids of the
variants whose curves are always kept.
"""

from __future__ import annotations

import math
import os
import threading
import time
import warnings
from collections.abc import Callable
from datetime import datetime
from typing import Any

import numpy as np

from mechdyn.store.studies import StoredVariant, variant_key
from mechdyn.studies.polish import optimality, polish, target_cost
from mechdyn.studies.spec import StudyError

__all__ = ["KIND_RUNNERS"]

_FIRST_ORDER = 1e-4  # a KKT residual below this (relative) is a first-order point
_TIE = 1e-6  # relative: a polished design (with its proof) within this of the best is the optimum
HEARTBEAT, HEARTBEAT_GRACE = 2, 20  # s: an optimization trial's heartbeat, and how long it may miss it
Findings = tuple[dict[str, Any], list[StoredVariant], set[int] | None]


def _value(v: StoredVariant, key: str) -> float:
    x = v.outputs.get(key)
    return float(x) if x is not None and v.status == "ok" else math.nan


def oat(runner: Any) -> Findings:
    """The base, then each parameter at each level with the others at base."""
    st = runner.study
    base = runner.base_row()
    rows = [base]  # the base first: the changes are measured from it
    labels: list[tuple[int, float]] = []
    for j, p in enumerate(st.parameters):
        for level in p.levels or (p.low, p.high):
            r = base.copy()
            r[j] = level
            rows.append(r)
            labels.append((j, level))
    variants = runner.evaluate(np.array(rows))
    b = variants[0]
    table = []
    for lab, v in zip(labels, variants[1:], strict=True):
        j, level = lab
        p = st.parameters[j]
        rel = p.relative(level)
        effects = {}
        for w in st.watched:
            y0, y = _value(b, w.key), _value(v, w.key)
            effects[w.key] = {
                "value": None if math.isnan(y) else y,
                # relative to the base value itself: a negative output that grows in size (−294 kN
                # to −320 kN) reads as growing (+8.8 %), as a positive one does
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
    base_out = {w.key: (None if math.isnan(_value(b, w.key)) else _value(b, w.key)) for w in st.watched}
    return {"base": base_out, "base_variant": b.id, "effects": table}, variants, None


def factorial(runner: Any) -> Findings:
    """Every combination of levels."""
    from mechdyn.studies.run import grid

    st = runner.study
    levels = [p.levels or (p.low, p.high) for p in st.parameters]
    variants = runner.evaluate(np.vstack([runner.base_row(), grid(levels)]))
    findings, variants, best = _sweep(st, variants)
    findings["factorial"] = factorial_effects(st, variants[1:], levels)
    return findings, variants, best


def factorial_effects(st: Any, variants: list[StoredVariant], levels: list[Any]) -> dict[str, Any]:
    """Main effects, two-way interactions and the best and worst design of each output over a full
    factorial (Montgomery, *Design and Analysis of Experiments*, ch. 5 and 6).

    The main effect of level ℓ of parameter A is ȳ(A = ℓ) − ȳ; the interaction of levels ℓ, m of A
    and B is ȳ(A = ℓ, B = m) − ȳ(A = ℓ) − ȳ(B = m) + ȳ, over the variants of the grid (the base design,
    when it is not a point of the grid, is left out). Each output gets, per parameter, its level means
    and the spread of its main effects (largest minus smallest), per pair of parameters the largest
    interaction in magnitude, and the ids of the variants where it is lowest and highest. An output
    missing from any variant of the grid gets ``{"error": ...}``.
    """
    P = len(st.parameters)
    idx = np.array(
        [
            [
                int(np.argmin(np.abs(np.asarray(lv, dtype=float) - v.parameters[p.name])))
                for p, lv in zip(st.parameters, levels, strict=True)
            ]
            for v in variants
        ],
        dtype=int,
    ).reshape(len(variants), P)
    out: dict[str, Any] = {}
    for w in st.watched:
        y = np.array([_value(v, w.key) for v in variants])
        if not len(y) or not np.isfinite(y).all():
            out[w.key] = {"error": f"{int((~np.isfinite(y)).sum())} of {len(y)} variants have no value"}
            continue
        mean = float(y.mean())
        main: dict[str, Any] = {}
        for j, p in enumerate(st.parameters):
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
                            y[cell].mean() - main[st.parameters[a].name]["means"][ka]
                            - main[st.parameters[b].name]["means"][kb] + mean
                        )  # fmt: skip
                        biggest = max(biggest, abs(float(inter)))
                pairs.append(
                    {"parameters": [st.parameters[a].name, st.parameters[b].name], "largest": biggest}
                )
        out[w.key] = {
            "mean": mean,
            "main": main,
            "interactions": sorted(pairs, key=lambda d: -d["largest"]),
            "lowest": variants[int(np.argmin(y))].id,
            "highest": variants[int(np.argmax(y))].id,
        }
    return out


def lhs(runner: Any) -> Findings:
    """A Latin hypercube over the ranges."""
    from scipy.stats import qmc

    st = runner.study
    n = st.samples or 10 * len(st.parameters)
    u = qmc.LatinHypercube(d=len(st.parameters), seed=st.seed).random(n)
    lo = np.array([p.low for p in st.parameters])
    hi = np.array([p.high for p in st.parameters])
    variants = runner.evaluate(np.vstack([runner.base_row(), lo + u * (hi - lo)]))
    return _sweep(st, variants)


def _sweep(st: Any, variants: list[StoredVariant]) -> Findings:
    """Ranges of the outputs over the variants, each parameter's rank correlation with each output,
    and (with an objective) the best feasible variant."""
    from scipy.stats import spearmanr

    ok = [v for v in variants if v.status == "ok"]
    X = np.array([[v.parameters[p.name] for p in st.parameters] for v in ok]) if ok else np.zeros((0, 0))
    spread: dict[str, Any] = {}
    corr: dict[str, Any] = {}
    for w in st.watched:
        y = np.array([_value(v, w.key) for v in ok])
        good = np.isfinite(y)
        spread[w.key] = {
            "min": float(y[good].min()) if good.any() else None,
            "max": float(y[good].max()) if good.any() else None,
        }
        corr[w.key] = {}
        for j, p in enumerate(st.parameters):
            if good.sum() > 2 and np.ptp(X[good, j]) > 0 and np.ptp(y[good]) > 0:
                corr[w.key][p.name] = float(spearmanr(X[good, j], y[good]).statistic)
            else:
                corr[w.key][p.name] = None
    findings: dict[str, Any] = {"output_ranges": spread, "rank_correlation": corr}
    best = _best(st, variants)
    if best is not None:
        findings["best"] = _describe(st, best)
    return findings, variants, {best.id} if best is not None else None


def _feasible(st: Any, v: StoredVariant) -> bool:
    return v.status == "ok" and all(c.violation(v.outputs.get(c.output.key)) <= 0 for c in st.constraints)


def _best(st: Any, variants: list[StoredVariant]) -> StoredVariant | None:
    if not st.objectives:
        return None
    o = st.objectives[0]
    cands = [v for v in variants if _feasible(st, v) and math.isfinite(_value(v, o.output.key))]
    return min(cands, key=lambda v: o.sign * _value(v, o.output.key)) if cands else None


def _describe(st: Any, v: StoredVariant) -> dict[str, Any]:
    return {
        "variant": v.id,
        "parameters": v.parameters,
        "given": v.given,
        "outputs": v.outputs,
        "constraints": [
            {
                "constraint": c.describe(),
                "value": v.outputs.get(c.output.key),
                "holds": c.violation(v.outputs.get(c.output.key)) <= 0,
            }
            for c in st.constraints
        ],
    }


def sobol(runner: Any) -> Findings:
    """First- and total-order indices with confidence intervals (SALib)."""
    from SALib.analyze import sobol as analyze
    from SALib.sample import sobol as sample

    st = runner.study
    problem = {
        "num_vars": len(st.parameters),
        "names": [p.name for p in st.parameters],
        "bounds": [[p.low, p.high] for p in st.parameters],
    }
    n = st.samples or 256
    if n & (n - 1):
        raise StudyError(
            f"{st.path or st.name}: [study] samples = {n}: Sobol sampling needs a power of 2 (e.g. 256)"
        )
    X = sample.sample(problem, n, calc_second_order=False, seed=st.seed)
    variants = runner.evaluate(X)
    failed = [v for v in variants if v.status != "ok"]
    indices: dict[str, Any] = {}
    for w in st.watched:
        Y = np.array([_value(v, w.key) for v in variants])
        if not np.isfinite(Y).all():
            indices[w.key] = {
                "error": f"{int((~np.isfinite(Y)).sum())} of {Y.size} variants have no value (failed: "
                f"{len(failed)}); narrow the ranges so that every variant can be evaluated"
            }
            continue
        if np.ptp(Y) == 0:
            indices[w.key] = {"error": "the output does not change over the ranges"}
            continue
        r = analyze.analyze(problem, Y, calc_second_order=False, conf_level=0.95, seed=st.seed)
        indices[w.key] = {
            p.name: {
                "S1": float(r["S1"][j]),
                "S1_conf": float(r["S1_conf"][j]),
                "ST": float(r["ST"][j]),
                "ST_conf": float(r["ST_conf"][j]),
            }
            for j, p in enumerate(st.parameters)
        }
    return {"base_samples": n, "indices": indices}, variants, None


def optimize(runner: Any) -> Findings:
    """Optuna: one objective (TPE) or several (NSGA-II, the Pareto front), in batches of trials."""
    import optuna

    from mechdyn.store.studies import optuna_name

    st = runner.study
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    multi = len(st.objectives) > 1

    sampler = optuna.samplers.NSGAIISampler(seed=st.seed) if multi else _sampler(st)
    with runner.store.store.schema_lock(), warnings.catch_warnings():  # Optuna's tables, once
        warnings.simplefilter("ignore", optuna.exceptions.ExperimentalWarning)
        # a trial whose process died (kill -9) has no heartbeat after HEARTBEAT_GRACE s: it is
        # failed then, marked abandoned and asked again (_retry)
        storage = optuna.storages.RDBStorage(
            runner.store.store.url,
            heartbeat_interval=HEARTBEAT,
            grace_period=HEARTBEAT_GRACE,
            heartbeat_stale_trial_callback=_retry,
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
            ids = _optimize(runner, study, storage)
    finally:
        storage.remove_session()
        storage.engine.dispose()

    variants = list(runner.store.by_ids(ids))
    base = runner.evaluate(runner.base_row())[0]
    findings: dict[str, Any] = {"trials": len(ids), "best": None, "improvement_percent": None}
    if multi:
        variants = [base, *variants]
        front_findings, front_ids = _front_findings(st, variants)
        findings.update(front_findings)
        findings["base"] = _describe(st, base)
        return findings, variants, front_ids
    # the local stage: SLSQP from the best designs the sampler found (and the given starts)
    findings["polish"] = polish(runner, _starts(runner, [base, *variants]), objective=_objective(st))
    variants = [base, *(v for v in runner.all_variants() if v.id != base.id)]
    findings.update(_optimum_findings(st, base, variants))
    b = findings.pop("_best")
    if b is not None:
        findings["single_design_check"] = _single_design_check(st, b)
    return findings, variants, {b.id} if b is not None else set()


def _sampler(st: Any) -> Any:
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
        y = _value(v, o.output.key)
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


def _optimum_findings(st: Any, base: StoredVariant | None, variants: list[StoredVariant]) -> dict[str, Any]:
    """The optimum (preferring a polished design whose optimality can be shown), its improvement
    over the base, its first-order optimality and the evaluations; ``_best`` is the variant."""
    o = st.objectives[0]
    by_key = {v.key: v for v in variants}
    plain = _best(st, [v for v in variants if base is None or v.id != base.id] or variants)
    best, proof = plain, None
    if plain is not None:
        best_value = o.sign * _value(plain, o.output.key)
        limit = best_value + _TIE * abs(best_value)  # a polished design this close is as good
        ranked = sorted(
            (v for v in variants if _feasible(st, v) and math.isfinite(_value(v, o.output.key))),
            key=lambda v: o.sign * _value(v, o.output.key),
        )
        for v in ranked:
            if o.sign * _value(v, o.output.key) > limit:
                break
            proof = optimality(st, v, by_key)
            if proof is not None:
                best = v
                break
    out: dict[str, Any] = {
        "_best": best,
        "best": _describe(st, best) if best is not None else None,
        "base": _describe(st, base) if base is not None else None,
        "improvement_percent": None,
        "optimality": proof,
        "evaluations": len(variants),
    }
    if best is not None and base is not None:
        y0, y1 = _value(base, o.output.key), _value(best, o.output.key)
        out["improvement_percent"] = 100.0 * (y0 - y1) / abs(y0) * o.sign if y0 else None
    return out


def _single_design_check(st: Any, best: StoredVariant) -> dict[str, Any]:
    """The optimum evaluated again through the analysis itself (not the batch): the objective's
    relative difference (round-off when both paths agree)."""
    from mechdyn.studies.evaluate import Evaluator

    o = st.objectives[0]
    key = o.output.key
    x = np.array([[best.parameters[p.name] for p in st.parameters]])
    again = Evaluator(st.source, st.analysis, st.parameters, [key], st.options, batch=False)(x)[0]
    y0, y1 = _value(best, key), again.outputs.get(key)
    diff = abs(y1 - y0) / abs(y0) if y1 is not None and y0 else None
    return {"status": again.status, "value": y1, "relative_difference": diff}


_RETRY_OF = "mechdyn:retry_of"  # a trial asked again for one whose process died
_OWNER = "mechdyn:owner"  # host:pid of the process that asked a trial


def _retry(study: Any, trial: Any) -> None:
    """A trial whose process died is asked again with the same parameters (a variant that process
    stored is then reused, not recomputed); the failed one counts for nothing (:func:`_abandoned`)."""
    import optuna

    study.add_trial(
        optuna.create_trial(
            state=optuna.trial.TrialState.WAITING,
            params=trial.params,
            distributions=trial.distributions,
            system_attrs={_RETRY_OF: trial.number},
        )
    )


def _abandoned(trials: list[Any]) -> set[int]:
    """The numbers of the trials that were failed because their process died (asked again since)."""
    return {t.system_attrs[_RETRY_OF] for t in trials if _RETRY_OF in t.system_attrs}


def _owner() -> str:
    """This process as a trial's owner: ``host:pid@start`` (the start time tells a reused pid apart)."""
    import socket

    start = _started(os.getpid())
    return f"{socket.gethostname()}:{os.getpid()}" + (f"@{start}" if start else "")


def _started(pid: int) -> str | None:
    """When a process started, in clock ticks since boot (Linux's /proc), or None where unknown;
    ``"gone"`` for a process that has exited and waits to be reaped (a zombie)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            fields = f.read().rpartition(")")[2].split()
    except OSError:
        return None
    if len(fields) < 20:
        return None
    return "gone" if fields[0] in ("Z", "X") else fields[19]


def _running_here(owner: str | None) -> bool | None:
    """Whether the process that asked a trial still runs, when it is another process on this host
    (True or False); None when it is this process, on another host or not known."""
    import socket

    who, _, start = (owner or "").partition("@")
    host, _, pid = who.rpartition(":")
    if host != socket.gethostname() or not pid.isdigit() or int(pid) == os.getpid():
        return None
    try:
        os.kill(int(pid), 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    now = _started(int(pid))
    if now == "gone":
        return False
    return not start or now in (start, None)  # a reused pid is another process


def _dead(owner: str | None) -> bool:
    """Whether the process that asked a trial is known to be gone (on this host)."""
    return _running_here(owner) is False


def _fail_abandoned(study: Any, storage: Any) -> None:
    """Fail (and ask again) the running trials whose process is gone: those whose heartbeat is stale
    (Optuna), those asked on this host by a process that no longer runs, and those that never got a
    heartbeat within the grace period (killed between ``ask`` and the first heartbeat)."""
    import optuna
    from sqlalchemy import text

    running = study.get_trials(deepcopy=False, states=(optuna.trial.TrialState.RUNNING,))
    if not running:
        return
    # Optuna's own test of a stale heartbeat (against the database server's clock)
    stale = set(storage._get_stale_trial_ids(study._study_id))
    with storage.engine.connect() as conn:
        beating = {tid for (tid,) in conn.execute(text("SELECT trial_id FROM trial_heartbeats"))}
    now = datetime.now()
    for t in running:
        owner = t.system_attrs.get(_OWNER)
        if _running_here(owner):
            # another process on this host that still runs: never taken for dead, however late its
            # heartbeat (a loaded machine delayed one past the grace period, and two processes then
            # failed each other's trials without end)
            continue
        silent = (
            t._trial_id not in beating
            and t.datetime_start is not None
            and ((now - t.datetime_start).total_seconds() > HEARTBEAT_GRACE)
        )
        if t._trial_id in stale or silent or _dead(owner):
            try:
                if storage.set_trial_state_values(t._trial_id, state=optuna.trial.TrialState.FAIL):
                    _retry(study, storage.get_trial(t._trial_id))
            except optuna.exceptions.UpdateFinishedTrialError:  # another process was first
                pass


class _Heartbeat:
    """Record the heartbeats of a batch's trials every ``HEARTBEAT`` s while it is evaluated, so a
    block that takes longer than the grace period is not taken for a dead process's."""

    def __init__(self, storage: Any, trial_ids: list[int]):
        self.storage, self.trial_ids = storage, trial_ids
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self._beat, daemon=True)

    def _beat(self) -> None:
        while not self.stop.wait(HEARTBEAT):
            for tid in self.trial_ids:
                self.storage.record_heartbeat(tid)

    def __enter__(self) -> _Heartbeat:
        for tid in self.trial_ids:
            self.storage.record_heartbeat(tid)
        self.thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop.set()
        self.thread.join()


def _optimize(runner: Any, study: Any, storage: Any) -> list[int]:
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
    owner = _owner()

    def evaluated() -> list[Any]:
        trials = study.get_trials(deepcopy=False)
        gone = _abandoned(trials)
        return [
            t for t in trials if t.state.is_finished() and "variant" in t.user_attrs and t.number not in gone
        ]

    while True:
        _fail_abandoned(study, storage)
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
            storage.set_trial_system_attr(t._trial_id, _OWNER, owner)
            trials.append(t)
        X = np.array([[t.params[p.name] for p in st.parameters] for t in trials])
        with _Heartbeat(storage, [t._trial_id for t in trials]):
            variants = runner.evaluate(X, objective=_objective(st))
        for t, v in zip(trials, variants, strict=True):
            try:
                t.set_user_attr("variant", v.id)
                if v.status != "ok" or not all(math.isfinite(_value(v, o.output.key)) for o in st.objectives):
                    study.tell(t, state=State.FAIL)
                    continue
                for i, c in enumerate(st.constraints):  # feasible where ≤ 0 (Optuna's convention)
                    t.set_constraint(f"{i + 1}: {c.describe()}", c.violation(v.outputs.get(c.output.key)))
                study.tell(t, [_value(v, o.output.key) for o in st.objectives])
            except (optuna.exceptions.UpdateFinishedTrialError, RuntimeError, ValueError):
                # failed meanwhile by another process that took this one for dead: the trial is
                # asked again, and its variant is stored, so nothing is lost or recomputed
                continue
    return [t.user_attrs["variant"] for t in evaluated()]


def _objective(st: Any) -> Callable[[dict[str, Any]], float] | None:
    if not st.objectives:
        return None
    key = st.objectives[0].output.key

    def f(outputs: dict[str, Any]) -> float:
        v = outputs.get(key)
        return float(v) if v is not None else math.nan

    return f


def _front_findings(st: Any, variants: list[StoredVariant]) -> tuple[dict[str, Any], set[int]]:
    """The Pareto front, its knee and its ends: ``pareto_front`` (the designs), ``knee`` (the id of the
    design nearest the ideal point once each objective is scaled to its range on the front: the
    compromise solution, Zeleny 1973) and ``ends`` (per objective, the id of the front's best design
    in it)."""
    front = _pareto(st, variants)
    out: dict[str, Any] = {"pareto_front": [_describe(st, v) for v in front]}
    if front:
        F = np.array([[o.sign * _value(v, o.output.key) for o in st.objectives] for v in front])
        lo, hi = F.min(axis=0), F.max(axis=0)
        scaled = (F - lo) / np.where(hi > lo, hi - lo, 1.0)
        out["knee"] = front[int(np.argmin(np.linalg.norm(scaled, axis=1)))].id
        out["ends"] = {o.output.key: front[int(np.argmin(F[:, j]))].id for j, o in enumerate(st.objectives)}
    return out, {v.id for v in front}


def _pareto(st: Any, variants: list[StoredVariant]) -> list[StoredVariant]:
    """The feasible variants no other feasible variant dominates."""
    feas = [v for v in variants[1:] if _feasible(st, v)]
    F = np.array([[o.sign * _value(v, o.output.key) for o in st.objectives] for v in feas])
    keep = []
    for i in range(len(feas)):
        dominated = np.any(np.all(F <= F[i], axis=1) & np.any(F < F[i], axis=1))
        if not dominated:
            keep.append(feas[i])
    return keep


def synthesis(runner: Any) -> Findings:
    """Fit the targets by differential evolution; every generation is one block of variants."""
    from scipy.optimize import differential_evolution

    st = runner.study
    penalty = 1e3

    def cost_of(v: StoredVariant) -> float:
        total = target_cost(st, v.outputs) if v.status == "ok" else math.inf
        if not math.isfinite(total):
            return 1e12
        for c in st.constraints:
            total += (
                penalty
                * max(0.0, c.violation(v.outputs.get(c.output.key))) ** 2
                / (
                    abs(c.max if c.max is not None else c.min if c.min is not None else c.equals or 1.0) ** 2
                    or 1.0
                )
            )
        return total

    def objective_outputs(outputs: dict[str, Any]) -> float:
        return target_cost(st, outputs)

    def f(X: np.ndarray) -> np.ndarray:
        vs = runner.evaluate(np.asarray(X).T, objective=objective_outputs)
        return np.array([cost_of(v) for v in vs])

    bounds = [(p.low, p.high) for p in st.parameters]
    pop = st.population or 15
    res = differential_evolution(
        f,
        bounds,
        maxiter=st.samples or 100,
        popsize=pop,
        seed=st.seed,
        vectorized=True,
        updating="deferred",
        polish=False,
        tol=1e-8,
        x0=np.clip(runner.base_row(), *np.array(bounds).T),  # the base design, moved into the ranges
    )
    base = runner.evaluate(runner.base_row())[0]
    # the local stage: SLSQP on the target cost from the evolution's best, constraints as constraints
    found = [v for v in runner.all_variants() if v.objective is not None and math.isfinite(v.objective)]
    found.sort(key=lambda v: (not _feasible(st, v), v.objective))
    starts = [np.array([v.parameters[p.name] for p in st.parameters]) for v in found[:1]]
    polished = polish(runner, starts or [np.clip(res.x, *np.array(bounds).T)], objective=objective_outputs)
    variants = runner.all_variants()
    findings = {
        "generations": int(res.nit),
        "polish": polished,
        **_fit_findings(st, base, variants),
    }
    best_v = findings.pop("_best")
    return findings, variants, {best_v.id, base.id} if best_v is not None else {base.id}


def _fit_findings(st: Any, base: StoredVariant | None, variants: list[StoredVariant]) -> dict[str, Any]:
    """A synthesis' fit (the variant nearest the targets among those that keep every constraint), a
    verdict and margin per target, and, for a missed target, what stops the fit: the constraints and
    bounds that hold it at a first-order point, or a search that stopped short."""
    feasible = sorted(
        (v for v in variants if _feasible(st, v) and v.objective is not None),
        key=lambda v: v.objective or 0.0,
    )
    best_v, proof = (feasible[0] if feasible else None), None
    by_key = {v.key: v for v in variants}
    for v in feasible:  # a fit as good whose first-order optimality can be shown, if there is one
        if (v.objective or 0.0) > (best_v.objective or 0.0) * (1.0 + _TIE) + _TIE:  # type: ignore[union-attr]
            break
        proof = optimality(st, v, by_key)
        if proof is not None:
            best_v = v
            break
    targets = []
    for t in st.targets:
        value = best_v.outputs.get(t.output.key) if best_v is not None else None
        off = abs(value - t.equals) if value is not None else None
        targets.append(
            {
                "output": t.output.key,
                "target": t.equals,
                "tolerance": t.tolerance,
                "value": value,
                "base_value": base.outputs.get(t.output.key) if base is not None else None,
                "holds": off is not None and off <= t.tolerance,
                "margin": t.tolerance - off if off is not None else None,  # < 0: missed by that much
            }
        )
    missed = [t for t in targets if not t["holds"]]
    if not missed:
        why = None
    elif proof is None:
        why = "the search stopped short: no gradient was stored at the fit"
    elif proof["measure"] > _FIRST_ORDER:
        why = f"the search stopped short (first-order residual {proof['measure']:.2g})"
    elif proof["active"]:
        why = "the limits make it unreachable: the fit is held by " + ", ".join(
            a["name"] for a in proof["active"]
        )
    else:
        why = "the targets cannot all be met together by these parameters (a least-squares compromise)"
    return {
        "_best": best_v,
        "feasible": bool(feasible),
        "evaluations": len(variants),
        "cost": best_v.objective if best_v is not None else None,
        "best": _describe(st, best_v) if best_v is not None else None,
        "base": _describe(st, base) if base is not None else None,
        "targets": targets,
        "optimality": proof,
        "missed_because": why,
    }


KIND_RUNNERS: dict[str, Callable[[Any], Findings]] = {
    "oat": oat,
    "factorial": factorial,
    "lhs": lhs,
    "sobol": sobol,
    "optimize": optimize,
    "synthesis": synthesis,
}


def from_stored(study: Any, variants: list[StoredVariant]) -> Findings:
    """What a stored study found, from its stored variants alone (nothing evaluated or written): the
    sweeps' and Sobol's findings as a run gives them; for an optimization or a synthesis, the best
    variant that keeps every constraint (or the Pareto front) among those stored.

    Raises
    ------
    StudyError
        When a sweep's variants are not all stored yet (the study is still running).
    """
    by_key = {v.key: v for v in variants}

    class _Stored:
        """The part of a runner that the kinds use, answered from the stored variants."""

        def __init__(self) -> None:
            self.study = study

        def base_row(self) -> np.ndarray:
            return np.array([p.base for p in study.parameters])

        def evaluate(self, X: Any, objective: Any = None) -> list[StoredVariant]:
            rows = np.atleast_2d(np.asarray(X, dtype=float))
            missing = [k for k in map(variant_key, rows) if k not in by_key]
            if missing:
                raise StudyError(
                    f"{len(missing)} of the study's {len(rows)} variants are not stored yet "
                    "(is it still running?)"
                )
            return [by_key[variant_key(r)] for r in rows]

    if study.kind in ("oat", "factorial", "lhs", "sobol"):
        return KIND_RUNNERS[study.kind](_Stored())
    base = next((v for v in variants if v.position == 0), variants[0] if variants else None)
    findings: dict[str, Any] = {"base": _describe(study, base) if base is not None else None}
    if study.kind == "optimize" and len(study.objectives) > 1:
        front_findings, front_ids = _front_findings(
            study, [base, *variants] if base is not None else variants
        )
        findings.update(front_findings)
        return findings, variants, front_ids
    if study.kind == "optimize":
        found = _optimum_findings(study, base, variants)
        best = found.pop("_best")
        findings.update(found)
        return findings, variants, {best.id} if best is not None else None
    found = _fit_findings(study, base, variants)
    best = found.pop("_best")
    findings.update(found)
    return findings, variants, {best.id} if best is not None else None
