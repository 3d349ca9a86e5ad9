"""A design study as it runs: the base model, the analysis, the parameters, what it looks at and how
it searches (:class:`Study`), and what its kinds and figures read of its result (:class:`StudyFindings`).

:mod:`mechdyn.studies.study` reads a study file into a :class:`Study` (and gives it under its name
there too); the kinds (:mod:`mechdyn.studies.kinds`) design, run and show it; a
:class:`~mechdyn.studies.result.StudyResult` is what it found.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Protocol

from mechdyn.io.modelfile import ModelSource
from mechdyn.studies.errors import StudyError
from mechdyn.studies.outputs import Constraint, Objective, Watched
from mechdyn.studies.parameters import Parameter
from mechdyn.studies.paths import ModelTree
from mechdyn.studies.storage import StoredVariant

__all__ = ["Study", "StudyFindings"]


@dataclass(frozen=True)
class Study:
    """A design study.

    Attributes
    ----------
    name : str
        Its name in the results database (running a study of a stored name resumes it).
    kind : {"oat", "factorial", "lhs", "sobol", "optimize", "synthesis", "tolerance"}
    source : ModelSource
        The base model file.
    analysis : str
        The registered analysis every variant runs.
    parameters : tuple of Parameter
    outputs : tuple of Watched
        What is reported (objectives, constraints and targets are added).
    objectives : tuple of Objective
        ``optimize`` (one: the optimum; several: the Pareto front).
    constraints : tuple of Constraint
        Limits the optimum keeps (``optimize``, ``synthesis``).
    targets : tuple of Constraint
        ``synthesis``: features to reach (``equals`` within ``tolerance``).
    options : dict
        The analysis' options, SI.
    samples : int or None
        See the study file's ``samples``.
    seed : int
    curves : int
        Keep every variant's curves while the study has at most this many variants; the best and
        the base are always kept.
    chunk : int
        Variants per evaluation block.
    population, batch : int or None
        Synthesis population; optimization trials asked at once.
    sampler : {"tpe", "random", "qmc"}
        Optimization with one objective: the global stage's Optuna sampler.
    definition : dict
        What the study file says (stored, and compared when a study is resumed).
    path : str
        The study file ("" when built in Python).
    start : tuple of tuple of float
        Parameter rows (SI) an optimization tries first (e.g. the optimum of a smaller box).
    family : str
        The file's study name when the file holds one study per box ("" otherwise).
    method : {"qmc", "mc"}
        ``tolerance``: how the scatter is sampled (see the study file's ``method``).
    limits : tuple of mechdyn.uncertainty.Limit
        ``tolerance``: the outputs' limits (SI), whose exceedance probabilities are wanted.
    correlations : tuple of (str, str, float, str)
        ``tolerance``: the correlated pairs of parameters, each (name, name, coefficient,
        measure), the coefficient dimensionless.
    small_probability : str or None
        ``tolerance``: the method for rarely exceeded limits (see the study file's field).
    scattered : tuple of Parameter
        ``optimize`` with scatter (robust design): the parameters that scatter about the model's
        value without being designed (those in ``parameters`` that carry a scatter scatter about each
        design's value).
    scatter_samples : int or None
        ``optimize`` with scatter: samples of the scatter per design (see the study file's field).
    """

    name: str
    kind: str
    source: ModelSource
    analysis: str
    parameters: tuple[Parameter, ...]
    outputs: tuple[Watched, ...] = ()
    objectives: tuple[Objective, ...] = ()
    constraints: tuple[Constraint, ...] = ()
    targets: tuple[Constraint, ...] = ()
    options: dict[str, Any] = field(default_factory=dict)
    samples: int | None = None
    seed: int = 1
    curves: int = 20
    chunk: int = 2048
    population: int | None = None
    batch: int = 16
    sampler: str = "tpe"
    definition: dict[str, Any] = field(default_factory=dict)
    path: str = ""
    start: tuple[tuple[float, ...], ...] = ()
    family: str = ""
    method: str = "qmc"
    limits: tuple[Any, ...] = ()
    correlations: tuple[tuple[str, str, float, str], ...] = ()
    small_probability: str | None = None
    scattered: tuple[Parameter, ...] = ()
    scatter_samples: int | None = None

    @property
    def robust(self) -> bool:
        """An ``optimize`` study with scatter (robust design, :mod:`mechdyn.studies.kinds.robust`)."""
        return self.kind == "optimize" and (
            bool(self.scattered) or any(p.scatter is not None for p in self.parameters)
        )

    def starting_from(self, rows: Any) -> Study:
        """The same study, asked to evaluate these parameter rows (SI) first (an optimizer's start).

        Parameters
        ----------
        rows : array_like
            (k, P) parameter values, SI, in the study's order.
        """
        from dataclasses import replace

        return replace(self, start=tuple(tuple(float(x) for x in r) for r in rows))

    def quick(self, samples: int) -> Study:
        """A quick form of the study with ``samples`` samples, stored under its own name
        (``NAME [samples N]``) so that it never mixes with the full study's variants.

        Parameters
        ----------
        samples : int
            Samples (optimization trials, Sobol base samples, ...), at least 1.
        """
        from dataclasses import replace

        if int(samples) < 1:
            raise StudyError(f"{self.name}: samples = {samples} must be at least 1")
        return replace(
            self,
            name=f"{self.name} [samples {int(samples)}]",
            samples=int(samples),
            definition={**self.definition, "study": {**self.definition["study"], "samples": int(samples)}},
        )

    @property
    def watched(self) -> tuple[Watched, ...]:
        """Every output the study reads: the outputs, then the objectives', constraints' and targets';
        a statistic (robust design) followed by the two ends of its interval."""
        from mechdyn.studies.outputs import Statistic

        seen: dict[str, Watched] = {}
        for w in (
            *self.outputs,
            *(o.output for o in self.objectives),
            *(c.output for c in (*self.constraints, *self.targets)),
        ):
            seen.setdefault(w.key, w)
            if isinstance(w, Statistic) and not w.bound:
                for end in ("low", "high"):
                    seen.setdefault(f"{w.key}_{end}", w.with_bound(end))
        return tuple(seen.values())

    @property
    def tree(self) -> ModelTree:
        return ModelTree(self.source)


class StudyFindings(Protocol):
    """What a kind's tables, plots and views and the study figures read of a study's result (a
    :class:`~mechdyn.studies.result.StudyResult`): the study, its variants in design order and what
    its kind found (SI)."""

    @property
    def study(self) -> Study: ...
    @property
    def variants(self) -> tuple[StoredVariant, ...]: ...
    @property
    def findings(self) -> dict[str, Any]: ...
