"""Robust design: an ``optimize`` study whose objectives and constraints are statistics of outputs
over the scatter of its parameters (a quantile, a mean, a standard deviation, a limit's probability).

The file holds design variables (parameters with a ``range``), scattered values (``scatter``) and
both at once: a design variable with a ``scatter`` (a mount's stiffness designed in [1, 5] MN/m and
bought at ±20 %) scatters about each design's value (:func:`mechdyn.uncertainty.variable_from_dict`
with ``nominal=`` the design's value); a scatter without a range scatters about the model's value.
An objective, constraint or output row names a ``statistic`` of its output (``mean``, ``std``,
``qNN``, ``p_exceed`` with the output's ``limit``); a row without one is the output at the design's
nominal (every scattered value at the design's or the model's value).

Common random numbers (Law, *Simulation Modeling and Analysis*, 5th ed., 2015, §11.2): one set of
``n`` standard-normal points ξ for the whole study (Monte Carlo, or scrambled Sobol points in
``min(16, n / 2)`` replicates, drawn with the study's seed as :func:`mechdyn.uncertainty.propagate`
draws them), mapped at each design through that design's :class:`~mechdyn.uncertainty.InputSpace`.
Differences between designs are then not sampling noise, and a statistic that is smooth in the
samples (a mean, a standard deviation, an interpolated quantile while the samples keep their order)
is a smooth function of the design, which the SLSQP polish needs. A limit's probability is a count
of samples, a step function of the design: the global stage handles it, the polish cannot move on
it (keep a probability under ``p`` as the ``1 − p`` quantile under the limit instead).

Each design's samples go through the batch engine as one block, its statistics are computed by
:func:`mechdyn.uncertainty.propagate` on them (the estimators and intervals of the tolerance kind),
and only the design-level values are stored: the statistic and its interval's ends, and the
nominal outputs. The samples of a design are a function of its parameters and the study's seed, so
a stored design is what a new evaluation would give, and the store holds one variant per design.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from mechdyn.studies.errors import StudyError
from mechdyn.studies.evaluate import Evaluation, Evaluator
from mechdyn.studies.outputs import Statistic, Watched, output_problem, statistic_level

if TYPE_CHECKING:
    from mechdyn.studies.parameters import Parameter
    from mechdyn.studies.plan import Study
    from mechdyn.uncertainty import InputSpace

__all__ = [
    "DEFAULT_SAMPLES",
    "RobustEvaluator",
    "check_rows",
    "common_points",
    "robust_findings",
    "sampling",
    "statistic_of",
    "statistics",
]

DEFAULT_SAMPLES = 128
"""Samples of the scatter per design where the file gives no ``scatter_samples`` (a power of 2; at
least 120 for the 95 % quantile's interval to have an upper end: order statistics, Hahn & Meeker,
*Statistical Intervals*, 1991, §5.2)."""

CHECKED_SAMPLES = 4
"""Samples of the optimum evaluated again through the analysis itself, one by one (count)."""


def sampling(study: Study) -> tuple[int, int]:
    """The samples of the scatter per design and the replicates (1 for Monte Carlo), as the
    tolerance kind samples (randomized QMC: ``min(16, n / 2)`` scrambled Sobol replicates).

    Parameters
    ----------
    study : Study
        An optimize study with scatter.
    """
    n = int(study.scatter_samples or DEFAULT_SAMPLES)
    return n, (1 if study.method == "mc" else min(16, n // 2))


def uncertain(study: Study) -> list[Parameter]:
    """The study's scattered parameters, in the order of the scatter's columns: the design variables
    that scatter, then the scattered values that are not designed."""
    return [*(p for p in study.parameters if p.scatter is not None), *study.scattered]


def common_points(d: int, n: int, replicates: int, seed: int) -> np.ndarray:
    """The study's common standard-normal points ξ (n × d, dimensionless): drawn as
    :func:`mechdyn.uncertainty.propagate` draws its inputs with the same seed (Monte Carlo, or
    ``replicates`` scrambled Sobol sets of ``n / replicates`` points), so that
    ``space.from_standard_normal(ξ)`` is exactly the sample ``propagate`` evaluates on ``space``.

    Parameters
    ----------
    d : int
        Scattered values (count).
    n : int
        Samples (count).
    replicates : int
        1 for Monte Carlo, else the Sobol replicates (count).
    seed : int
        The study's seed.
    """
    from mechdyn.uncertainty import InputSpace, normal

    unit = InputSpace(tuple(normal(f"xi{i}", 0.0, 1.0) for i in range(d)))
    rng = np.random.default_rng(seed)
    if replicates == 1:
        return unit.sample(n, method="mc", seed=rng)
    return np.concatenate([unit.sample(n // replicates, method="qmc", seed=rng) for _ in range(replicates)])


def space_at(study: Study, x: Sequence[float] | np.ndarray) -> InputSpace:
    """The scatter at the design ``x`` (SI, the design variables' values): each design variable's
    scatter centred on its value there, each other scattered value as the file gives it.

    Parameters
    ----------
    study : Study
    x : sequence of float
        The design variables' values, SI, in the study's order.
    """
    from mechdyn.uncertainty import InputSpace, variable_from_dict

    variables = [
        variable_from_dict(p.name, p.scatter_table[0], p.scatter_table[1], nominal=float(v))
        for p, v in zip(study.parameters, x, strict=True)
        if p.scatter is not None
    ]
    return InputSpace((*variables, *(p.scatter for p in study.scattered)))


def statistics(study: Study) -> list[Statistic]:
    """The statistics the study estimates at each design (not the ends of their intervals)."""
    return [w for w in study.watched if isinstance(w, Statistic) and not w.bound]


def statistic_of(w: Watched, statistic: str | None, limits: Sequence[Any], where: str) -> Watched:
    """The output ``w``, or its statistic over the scatter where a row names one.

    Parameters
    ----------
    w : Watched
        The output as the row names it.
    statistic : str or None
        The row's ``statistic``.
    limits : sequence of mechdyn.uncertainty.Limit
        The study's limits (``[[outputs]]`` rows with a ``limit``), for ``p_exceed``.
    where : str
        The file and row, for errors.

    Raises
    ------
    StudyError
        An unknown statistic, or ``p_exceed`` of an output without a limit.
    """
    if statistic is None:
        return w
    try:
        statistic_level(statistic)
    except ValueError as exc:
        raise StudyError(f"{where} → statistic: {exc}") from None
    if statistic == "p_exceed":
        if not any(lim.output == w.key for lim in limits):
            raise StudyError(
                f'{where} → statistic: "p_exceed" of {w.key!r} needs the output\'s limit: give an '
                f'[[outputs]] row output = {w.key!r}, limit = "..." (and side = "above" or "below")'
            )
        return Statistic(f"{w.key}.p_exceed", "", "", of=w.key, statistic="p_exceed")
    return Statistic(f"{w.key}.{statistic}", w.unit, w.display, of=w.key, statistic=statistic)


def check_rows(path: str, kind: str, f: Any, params: Sequence[Parameter]) -> None:
    """A study file's rows as robust design needs them: statistics only in an optimize study with
    scatter, a statistic wherever there is scatter, ``scatter_samples`` only with scatter and suited
    to the method, and each design variable's scatter centred on the design.

    Parameters
    ----------
    path : str
        The study file, for errors.
    kind : str
        The study's kind.
    f : StudyFile
        The validated file.
    params : sequence of Parameter
        Every parameter the file makes.

    Raises
    ------
    StudyError
        Naming the file, the row and the field, with the fix.
    """
    rows = [
        (f"[[{table}]] #{i + 1}", row)
        for table in ("outputs", "objectives", "constraints")
        for i, row in enumerate(getattr(f, table))
    ]
    stated = [(where, row) for where, row in rows if getattr(row, "statistic", None) is not None]
    scattered = [p for p in params if p.scatter is not None]
    if kind != "optimize":
        if stated:
            where, row = stated[0]
            raise StudyError(
                f"{path}: {where} → statistic: {row.statistic!r} is for an optimize study with scatter "
                "(robust design); remove it"
            )
        if f.study.scatter_samples is not None:
            raise StudyError(
                f"{path}: [study] → scatter_samples is for an optimize study with scatter; remove it"
            )
        return
    if not scattered:
        if stated:
            where, row = stated[0]
            raise StudyError(
                f"{path}: {where} → statistic: {row.statistic!r} is a statistic over the scatter, and no "
                'parameter scatters; give a parameter scatter = {distribution = "lognormal", cov = 0.2} '
                "(with its range for a design variable), or remove the statistic"
            )
        if f.study.scatter_samples is not None:
            raise StudyError(
                f"{path}: [study] → scatter_samples: no parameter scatters; give one a scatter, or "
                "remove scatter_samples"
            )
        return
    if not any(where.startswith(("[[objectives]]", "[[constraints]]")) for where, _ in stated):
        raise StudyError(
            f"{path}: parameters scatter ({', '.join(p.name for p in scattered)}), but no objective or "
            'constraint names a statistic; give one statistic = "q95" (or mean, std, p_exceed), or '
            "remove the scatter"
        )
    n = int(f.study.scatter_samples or DEFAULT_SAMPLES)
    if f.study.method == "qmc" and n & (n - 1):
        raise StudyError(
            f'{path}: [study] → scatter_samples = {n}: method = "qmc" needs a power of 2 (e.g. '
            f'{1 << (n.bit_length() - 1)} or {1 << n.bit_length()}), or method = "mc"'
        )
    for p in scattered:
        if p.bounded:
            _follows_design(path, p)


def _follows_design(path: str, p: Parameter) -> None:
    """Refuse a design variable whose scatter does not move with the design (an absolute median or
    mean) or cannot be built at an end of its range."""
    from mechdyn.errors import ModelError
    from mechdyn.uncertainty import variable_from_dict

    spec, si = p.scatter_table
    assert p.low is not None and p.high is not None
    where = f"{path}: [[parameters]] ({p.name!r}) → scatter"
    try:
        ends = [variable_from_dict(p.name, spec, si, nominal=x) for x in (p.low, p.high)]
    except ModelError as exc:
        raise StudyError(f"{where}: at an end of the range: {exc}") from None
    if math.isclose(ends[0].mean, ends[1].mean, rel_tol=1e-12, abs_tol=0.0):
        raise StudyError(
            f"{where}: {dict(spec)!r} does not move with the design (its location is given); a design "
            "variable's scatter is centred on each design's value: give it relative, e.g. "
            '{distribution = "lognormal", cov = 0.2} or {tolerance = "band", plus_minus = "20 %"}'
        )


class RobustEvaluator:
    """Evaluates designs of a robust study: for each design (a row of the design variables' values,
    SI) its nominal and its ``n`` samples of the scatter at the common points, all designs of a
    block as one block of the batch engine, and returns per design one :class:`Evaluation` whose
    outputs are the nominal outputs and each statistic with the ends of its interval.

    Parameters
    ----------
    study : Study
        An optimize study with scatter.
    batch : bool
        Offer the samples to the analysis' batch evaluation (off: one by one, the analysis itself).
    """

    def __init__(self, study: Study, batch: bool = True):
        self.study = study
        self.n, self.replicates = sampling(study)
        self.stats = statistics(study)
        self.plain = [w for w in study.watched if not isinstance(w, Statistic)]
        raw = list(dict.fromkeys([*(w.key for w in self.plain), *(s.of for s in self.stats)]))
        self.raw = raw
        self.inner = Evaluator(
            study.source, study.analysis, (*study.parameters, *study.scattered), raw, study.options, batch
        )
        self.outputs = tuple(w.key for w in study.watched)
        self.columns = [j for j, p in enumerate(study.parameters) if p.scatter is not None]
        self.columns += [len(study.parameters) + k for k in range(len(study.scattered))]
        self.xi = common_points(len(self.columns), self.n, self.replicates, study.seed)

    def nominal_row(self, x: Sequence[float] | np.ndarray) -> np.ndarray:
        """The design's nominal (every scattered value at the design's or the model's value), as a
        row of the inner evaluator (SI)."""
        return np.array([*map(float, x), *(p.base for p in self.study.scattered)])

    def samples(self, x: Sequence[float] | np.ndarray) -> np.ndarray:
        """The design's samples as rows of the inner evaluator (n × (P + S), SI): the common points
        mapped through the scatter at ``x`` (:func:`space_at`)."""
        rows = np.tile(self.nominal_row(x), (self.n, 1))
        rows[:, self.columns] = space_at(self.study, x).from_standard_normal(self.xi)
        return rows

    def __call__(self, X: Any, curves: bool = False) -> list[Evaluation]:
        """Evaluate the designs whose values (SI) are the rows of ``X`` (V × P)."""
        from mechdyn.errors import MechdynError

        X = np.atleast_2d(np.asarray(X, dtype=float))
        blocks: list[np.ndarray | Evaluation] = []
        for x in X:
            try:
                blocks.append(np.vstack([self.nominal_row(x), self.samples(x)]))
            except MechdynError as exc:  # the scatter cannot be centred here (a truncation's bound)
                blocks.append(
                    Evaluation("failed", f"{type(exc).__name__}: {exc}", dict.fromkeys(self.outputs))
                )
        rows = [b for b in blocks if isinstance(b, np.ndarray)]
        done = iter(self.inner(np.vstack(rows)) if rows else [])
        out = []
        for x, b in zip(X, blocks, strict=True):
            if isinstance(b, Evaluation):
                out.append(b)
                continue
            evs = [next(done) for _ in range(len(b))]
            out.append(self._design(x, evs[0], evs[1:]))
        return out

    def _design(self, x: np.ndarray, nominal: Evaluation, evs: list[Evaluation]) -> Evaluation:
        """One design's outputs from its nominal and its samples' evaluations."""
        from mechdyn.uncertainty import propagate

        said = tuple(dict.fromkeys(w for e in (nominal, *evs) for w in e.warnings))
        failed = [e for e in evs if e.status != "ok"]
        if nominal.status != "ok":
            return Evaluation(
                "failed", f"the nominal design: {nominal.error}", dict.fromkeys(self.outputs), said
            )
        Y = np.array([[e.outputs.get(k) if e.status == "ok" else None for k in self.raw] for e in evs], float)
        if failed or not np.isfinite(Y).all():
            bad = len(failed) or int((~np.isfinite(Y).all(axis=1)).sum())
            first = failed[0].error if failed else "an output with no value"
            return Evaluation(
                "failed",
                f"{bad} of {self.n} samples of the scatter failed at this design (first: {first}); the "
                "statistics need every sample: narrow or truncate the scatter to where the model holds",
                dict.fromkeys(self.outputs),
                said,
            )
        qs = sorted({q for s in self.stats if (q := statistic_level(s.statistic)) is not None})
        limits = [lim for lim in self.study.limits if any(s.of == lim.output for s in self.stats)]
        got = propagate(
            lambda _X: Y,
            space_at(self.study, x),
            self.n,
            outputs=self.raw,
            limits=limits,
            method=self.study.method,
            replicates=max(self.replicates, 2),
            quantiles=qs,
            seed=self.study.seed,
        )
        outputs: dict[str, float | None] = {w.key: nominal.outputs.get(w.key) for w in self.plain}
        for s in self.stats:
            d = got.distribution(s.of)
            if s.statistic == "p_exceed":
                p = got.probabilities[next(i for i, lim in enumerate(limits) if lim.output == s.of)]
                value, low, high = p.value, p.low, p.high
            else:
                q = statistic_level(s.statistic)
                iv = d.mean if q is None and s.statistic == "mean" else d.std if q is None else d.quantiles[q]
                value, low, high = iv.value, iv.low, iv.high
            outputs |= {s.key: value, f"{s.key}_low": low, f"{s.key}_high": high}
        return Evaluation("ok", None, outputs, said)

    def check(self, x: Sequence[float] | np.ndarray, samples: int = CHECKED_SAMPLES) -> dict[str, Any]:
        """The design's nominal and its first ``samples`` samples evaluated again one by one through
        the analysis itself: ``status`` and ``relative_difference`` (the largest over them and the
        outputs, against the batch path; round-off where both agree), ``samples_checked``.

        Parameters
        ----------
        x : sequence of float
            The design variables' values, SI.
        samples : int
            How many of its samples (count).
        """
        rows = np.vstack([self.nominal_row(x), self.samples(x)[:samples]])
        batch = self.inner(rows)
        single = [self.inner.one(r.tolist()) for r in rows]
        worst = 0.0
        for a, b in zip(batch, single, strict=True):
            if a.status != "ok" or b.status != "ok":
                return {"status": b.status if b.status != "ok" else a.status, "relative_difference": None}
            for k in self.raw:
                y0, y1 = a.outputs.get(k), b.outputs.get(k)
                if y0 is None or y1 is None:
                    return {"status": "failed", "relative_difference": None}
                worst = max(worst, abs(y1 - y0) / abs(y0) if y0 else abs(y1))
        return {"status": "ok", "relative_difference": worst, "samples_checked": len(rows) - 1}

    def one(self, row: Sequence[float], curves: bool = False, keep_result: bool = False) -> Evaluation:
        """The design's nominal through the analysis itself (its curves, for a report).

        Parameters
        ----------
        row : sequence of float
            The design variables' values, SI.
        curves, keep_result : bool
            As :meth:`mechdyn.studies.evaluate.Evaluator.one`.
        """
        return self.inner.one(self.nominal_row(row).tolist(), curves=curves, keep_result=keep_result)

    def base_summary(self) -> None:
        """Check what the statistics are of against the base model's summary (raising
        :class:`StudyError` for an output that names no number); None: the statistics' own keys are
        the study's, not the analysis'."""
        summary = self.inner.base_summary()
        if summary is None:
            return None
        problems = [p for k in self.raw if (p := output_problem(summary, k)) is not None]
        if problems:
            raise StudyError(
                f"{self.study.path or self.study.name}: [[outputs]] (or an objective or constraint) "
                + "; ".join(problems)
            )
        return None


def robust_findings(study: Study, chosen: Any, base: Any) -> dict[str, Any]:
    """What a robust study's result says of its estimates: ``samples`` (per design), ``method``,
    ``replicates``, ``common_random_numbers`` (in words), ``scatter`` (per scattered parameter: its
    distribution and whether it is centred on the design), ``objective`` (the statistic at the
    optimum with its interval, ``level`` 0.95) and ``improvement`` over the base (``difference`` in
    the objective's SI unit, better > 0; ``half_width``: the larger half-width of the two
    intervals; ``significant``: the difference exceeds it; ``base_feasible``: whether the base
    keeps every constraint).

    Parameters
    ----------
    study : Study
        An optimize study with scatter.
    chosen, base : StoredVariant or None
        The optimum and the base design.
    """
    n, r = sampling(study)
    method = "Monte Carlo" if r == 1 else f"randomized quasi-Monte Carlo (scrambled Sobol, {r} replicates)"
    out: dict[str, Any] = {
        "samples": n,
        "method": method,
        "replicates": r,
        "common_random_numbers": (
            f"the same {n} standard-normal points at every design (seed {study.seed}), mapped through "
            "that design's scatter"
        ),
        "scatter": {
            p.name: {"distribution": p.scatter.describe(), "centred_on_design": p.bounded}
            for p in uncertain(study)
        },
        "objective": None,
        "improvement": None,
    }
    o = study.objectives[0] if len(study.objectives) == 1 else None
    if o is None or not isinstance(o.output, Statistic) or chosen is None:
        return out
    key = o.output.key

    def at(v: Any) -> tuple[float | None, float | None, float | None]:
        return (v.outputs.get(key), v.outputs.get(f"{key}_low"), v.outputs.get(f"{key}_high"))

    y, lo, hi = at(chosen)
    out["objective"] = {"key": key, "statistic": o.output.statistic, "value": y, "low": lo, "high": hi}
    out["objective"]["level"] = 0.95
    if base is not None and None not in at(base) and None not in (y, lo, hi):
        y0, lo0, hi0 = at(base)
        assert y is not None and lo is not None and hi is not None
        assert y0 is not None and lo0 is not None and hi0 is not None
        from mechdyn.studies.kinds.base import feasible

        diff = o.sign * (y0 - y)
        half = max((hi - lo) / 2.0, (hi0 - lo0) / 2.0)
        out["improvement"] = {
            "difference": diff,
            "half_width": half,
            "significant": bool(diff > half),
            "base_feasible": feasible(study, base),
        }
    return out


def table_rows(study: Study, f: Mapping[str, Any]) -> list[list[Any]]:
    """The rows a robust study adds to its optimality table: the estimate, its interval, and whether
    the improvement over the base exceeds it.

    Parameters
    ----------
    study : Study
    f : mapping
        The findings (``robust`` from :func:`robust_findings`).
    """
    from mechdyn.studies.cells import number, unit_text

    rb = f.get("robust")
    if not rb:
        return []
    rows: list[list[Any]] = [
        [
            "statistics",
            f"estimates from {rb['samples']} samples of the scatter per design, by {rb['method']}; "
            f"common random numbers: {rb['common_random_numbers']}",
        ]
    ]
    o = study.objectives[0] if study.objectives else None
    est = rb.get("objective")
    if est and o is not None:
        w = o.output.readable([est["value"]])
        unit = unit_text(w.shown_unit)

        def shown(v: float | None) -> str:
            s = w.show(v)
            return f"{number(s)} {unit}".strip() if s is not None else "—"

        rows.append(
            [
                f"{w.words} at the optimum",
                f"{shown(est['value'])}, 95 % interval {shown(est['low'])} to {shown(est['high'])}: the "
                "optimum and its verdict are those of the estimate; the true statistic's optimum lies "
                "within about that interval",
            ]
        )
        imp = rb.get("improvement")
        if imp:
            d, h = w.difference(imp["difference"]), w.difference(imp["half_width"])
            said = (
                f"{number(d)} {unit}".strip() + " against a half-interval of " + f"{number(h)} {unit}".strip()
            )
            if imp["difference"] <= 0:
                word = "none in the objective" + (
                    ""
                    if imp.get("base_feasible", True)
                    else " (the base breaks a constraint the optimum keeps)"
                )
            elif imp["significant"]:
                word = (
                    "beyond both estimates' 95 % half-widths (conservative: on common points the "
                    "estimates move together)"
                )
            else:
                word = (
                    "within the estimates' 95 % half-width: not shown (more samples of the scatter "
                    "would tell)"
                )
            rows.append(["improvement over the base", f"{said}: {word}"])
    return rows
