"""The study file's schema: the ``[study]`` table and the ``[[parameters]]``, ``[[outputs]]``,
``[[correlations]]``, ``[[objectives]]``, ``[[constraints]]`` and ``[[targets]]`` rows, as pydantic
models (:class:`StudyFile`); :mod:`mechdyn.studies.study` reads a file through it into a
:class:`~mechdyn.studies.Study`. The field docstrings are the model-file reference's text.
"""

from __future__ import annotations

import difflib
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field, field_validator

from mechdyn.store.schema import NAME_LENGTH

__all__ = ["ConstraintRow", "OutputRow", "StudyFile"]


class _Row(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, use_attribute_docstrings=True)


class _StudyTable(_Row):
    name: str = Field(min_length=1, max_length=NAME_LENGTH - 16)  # room for a box: "NAME ±10 %"
    """The study's name in the results database; running a study of a stored name resumes it."""
    kind: str
    """``oat`` (one at a time), ``factorial``, ``lhs`` (Latin hypercube), ``sobol`` (Sobol indices),
    ``optimize`` (Optuna), ``synthesis`` (differential evolution to targets) or ``tolerance`` (the
    parameters' scatter to each output's distribution and each limit's probability): the kinds
    registered in :mod:`mechdyn.studies.kinds`."""

    @field_validator("kind")
    @classmethod
    def _registered(cls, v: str) -> str:
        from mechdyn.studies.kinds import KINDS

        if v not in KINDS:
            close = difflib.get_close_matches(v, KINDS, n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise ValueError(f"{v!r} is not a study kind{hint}; the kinds are {', '.join(map(repr, KINDS))}")
        return v

    model: str = Field(description="the base model file, relative to the study file")
    analysis: str = Field(description="a registered analysis (`mechdyn analyses` lists them)")
    description: str = ""
    """Free text about the study."""
    options: dict[str, Any] = Field(default_factory=dict, description="the analysis' options")
    samples: int | None = Field(
        default=None,
        ge=1,
        le=10_000_000,
        description="lhs: variants; sobol: base samples N (N·(P+2) variants); optimize: trials; "
        "synthesis: generations; tolerance: samples (a power of 2 for qmc)",
    )
    seed: int = Field(default=1, ge=0, le=2**32 - 1)
    """Seed of the samplers and optimizers (0 to 2³²−1), so that a study can be repeated."""
    curves: int = Field(
        default=20, ge=0, le=1_000_000, description="keep every variant's curves up to this study size"
    )
    chunk: int = Field(
        default=2048, ge=1, le=1_000_000, description="variants per evaluation block (and per Dask task)"
    )
    population: int | None = Field(
        default=None, ge=4, le=100_000, description="synthesis: population per generation"
    )
    batch: int = Field(default=16, ge=1, le=100_000, description="optimize: trials asked for at once")
    sampler: Literal["tpe", "random", "qmc"] = "tpe"
    """optimize (one objective): the global stage's sampler, Optuna's ``tpe`` (default), ``random`` or
    ``qmc`` (scrambled Sobol points); a constrained SLSQP polish of its best designs follows."""
    scatter_samples: int | None = Field(
        default=None,
        ge=4,
        le=1_000_000,
        description="optimize with scatter (robust design): samples of the scatter at each design, the "
        "same points at every design (default 128; a power of 2 for qmc)",
    )
    method: Literal["qmc", "mc"] = "qmc"
    """tolerance, and optimize with scatter: how the scatter is sampled, ``qmc`` (randomized
    quasi-Monte Carlo: scrambled Sobol points in up to 16 independent replicates, samples a power of
    2) or ``mc`` (Monte Carlo)."""
    small_probability: Literal["importance", "subset", "form", "sorm", "off"] | None = None
    """tolerance: the method for a limit the samples exceed rarely (below 1e-3, or never):
    ``importance`` (FORM, then importance sampling at its design point; the default for continuous
    scatter), ``subset`` (subset simulation; the default with discrete levels), ``form``, ``sorm``, or
    ``off``."""
    boxes: list[str] = Field(
        default_factory=list,
        description='one study per box: parameters with range = "box" take each ("±10 %", "±20 %")',
    )


class _ParameterRow(_Row):
    path: str
    """The model value, as the model file spells it: ``support.stiffness``, ``points.C.y``,
    ``bodies.slide.mass``, ``mounts.*.stiffness``; through a referenced file:
    ``excitation.mechanism.points.C``; a whole number or a choice: ``gear_pairs.*.pinion.teeth``,
    ``mounts.*.mount.pad.material``, ``mounts.*.mount`` (``mechdyn study --paths MODEL`` lists them)."""
    name: str | None = Field(default=None, min_length=1, max_length=200)
    """The parameter's name in tables (default: the path)."""
    range: str | list[Any] | None = None
    """Low and high with units (``["1.2 m", "1.6 m"]``), relative (``"±10 %"``), or ``"box"`` (each of the
    study's ``boxes``); a quantity only (a whole number or a choice takes levels)."""
    levels: list[Any] | None = None
    """Levels with units, or relative (``["-10 %", "-20 %"]``), for ``oat`` and ``factorial``; a whole
    number (a tooth count) takes whole numbers (``[17, 21]``), a choice its names (a material:
    ``["rubber shore 50", "rubber shore 70"]``; another mount file: ``["wedge_mount.toml"]``)."""
    tie: list[str] = Field(default_factory=list)
    """More paths that move with this parameter, each by the same factor from its own value."""
    scatter: dict[str, Any] | None = None
    """tolerance: how the value scatters, instead of a range or levels: ``{distribution =
    "lognormal", median = "2 MN/m", cov = 0.15}``, ``{distribution = "uniform", low = ..., high =
    ...}`` (also normal, triangular, levels; truncated by lower/upper), or a named tolerance class
    ``{tolerance = "shore_a_5"}``, ``{tolerance = "band", plus_minus = "20 %"}``; the model's value
    is the default median, mean or nominal (:func:`mechdyn.uncertainty.variable_from_dict`).
    optimize (robust design): a parameter with a scatter and no range scatters about the model's
    value; one with a range and a scatter is a design variable whose value scatters about each
    design's (give the scatter relative: ``cov``, ``plus_minus``, a tolerance class)."""


class _OutputRow(_Row):
    output: str
    """A summary key of the analysis, nested with dots (``joint_force_peak_N.F``)."""
    unit: str = ""
    """Display unit of the output (default: SI)."""
    limit: str | float | None = None
    """tolerance: the limit whose exceedance probability is wanted, with its unit (``"25 um/s"``)."""
    side: Literal["above", "below"] = "above"
    """tolerance: the failure is the output ``above`` the limit (default) or ``below`` it."""
    statistic: str | None = None
    """optimize with scatter: report this statistic of the output over the scatter at each design
    (``mean``, ``std``, ``q95`` or any ``qNN``, ``p_exceed`` with ``limit``); without it, the output at
    the design's nominal (every scattered value at the model's or the design's value)."""


class _CorrelationRow(_Row):
    between: list[str] = Field(min_length=2, max_length=2)
    """tolerance: the two parameters whose scatter is correlated, by their names (the path where a
    row gives no name)."""
    coefficient: float
    """The correlation coefficient, between -1 and 1 (exclusive), dimensionless."""
    measure: Literal["normal", "spearman"] = "normal"
    """``normal``: the Gaussian copula's own correlation (default); ``spearman``: a rank correlation,
    converted exactly (2 sin(π ρ_S / 6))."""


class _GoalRow(_Row):
    output: str
    """A summary key of the analysis to optimize."""
    unit: str = ""
    """Display unit of the output."""
    goal: Literal["minimize", "maximize"] = "minimize"
    """``minimize`` or ``maximize``."""
    statistic: str | None = None
    """optimize with scatter: the statistic of the output over the scatter to optimize (``mean``,
    ``std``, ``q95`` or any ``qNN``, ``p_exceed``: the probability of the limit the output's
    ``[[outputs]]`` row gives)."""


class _ConstraintRow(_Row):
    output: str
    """A summary key of the analysis."""
    unit: str = ""
    """Unit of the limits (default: the output's SI unit)."""
    max: str | float | None = None
    """Upper limit."""
    min: str | float | None = None
    """Lower limit."""
    equals: str | float | None = None
    """Value to hold (with ``tolerance``)."""
    tolerance: str | float | None = None
    """Allowed deviation from ``equals``."""


class _LimitRow(_ConstraintRow):
    statistic: str | None = None
    """optimize with scatter: the statistic of the output over the scatter the limits hold
    (``q95``, ``mean``, ``std``, ``p_exceed`` with the output's limit: ``max = 0.05``)."""


class StudyFile(_Row):
    """Schema of a study file."""

    study: _StudyTable
    parameters: list[_ParameterRow] = Field(default_factory=list)
    """The values the study varies, at least one; a tolerance study may leave them out, and then
    samples the scatter its model file's ``[[scatter]]`` gives (those rows are the default of a
    tolerance study's parameters)."""
    outputs: list[_OutputRow] = Field(default_factory=list)
    objectives: list[_GoalRow] = Field(default_factory=list)
    constraints: list[_LimitRow] = Field(default_factory=list)
    targets: list[_ConstraintRow] = Field(default_factory=list)
    correlations: list[_CorrelationRow] = Field(default_factory=list)


# the rows study.py reads by name
ConstraintRow = _ConstraintRow
OutputRow = _OutputRow
