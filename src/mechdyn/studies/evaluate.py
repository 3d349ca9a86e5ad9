"""Evaluating design variants: parameter values in, the analysis' outputs (and its status) out.

The :class:`Evaluator` holds the base model's files, the analysis and what to read from its summary.
Given a block of variants it first offers them to the analysis' batch evaluation
(:attr:`mechdyn.registry.Analysis.batch`: a mechanism's variants in one compiled cycle), and
otherwise builds each variant from its files and runs the analysis on it. A whole number or a choice
(a tooth count, a material) is never a batch column: the variants that share those values are one
batch on the model file written with them. A variant that cannot be
evaluated (a linkage that does not assemble at some angle) is returned as failed, with the message;
the others go on. An evaluator is plain data, so it can be sent to Dask workers.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from mechdyn.errors import MechdynError
from mechdyn.io.modelfile import ModelSource, load_source
from mechdyn.registry import NotBatchable
from mechdyn.studies.outputs import output_value
from mechdyn.studies.parameters import Parameter
from mechdyn.studies.paths import ModelTree

__all__ = ["Evaluation", "Evaluator"]


@dataclass(frozen=True)
class Evaluation:
    """One variant's outcome.

    Attributes
    ----------
    status : {"ok", "failed"}
    error : str or None
        Why it failed.
    outputs : dict of str → float or None
        The wanted summary values, SI (None where the summary has no number).
    warnings : tuple of str
        What the model and the analysis warned of for this variant (stored with it): as the model
        was built, as the analysis ran (a batch: as its block ran), and what the result itself warns
        of (:attr:`mechdyn.results.Result.warnings`; one by one).
    curves : dict of str → (ndarray, unit)
        The result's arrays, when they were asked for.
    """

    status: str
    error: str | None
    outputs: dict[str, float | None]
    warnings: tuple[str, ...] = ()
    curves: dict[str, tuple[np.ndarray, str]] = field(default_factory=dict)
    result: Any = field(default=None, compare=False, repr=False)
    """The analysis' result itself, when asked for (never stored)."""


class Evaluator:
    """Evaluates variants of one model file by one registered analysis.

    Parameters
    ----------
    source : ModelSource
        The base model file (with the files it refers to, read on demand).
    analysis : str
        A registered analysis (:func:`mechdyn.registry.get`).
    parameters : sequence of Parameter
    outputs : sequence of str
        Summary keys to read (nested with dots).
    options : mapping
        The analysis' options (SI).
    batch : bool
        Offer blocks to the analysis' batch evaluation (off: always one by one).
    """

    def __init__(
        self,
        source: ModelSource,
        analysis: str,
        parameters: Sequence[Parameter],
        outputs: Sequence[str],
        options: Mapping[str, Any] | None = None,
        batch: bool = True,
    ):
        self.source = source
        self.analysis = analysis
        self.parameters = tuple(parameters)
        self.outputs = tuple(outputs)
        self.options = dict(options or {})
        self.batch = batch and all(p.apply is None for p in self.parameters)
        self._tree: ModelTree | None = None
        self._base: Any = None
        self._base_warnings: tuple[str, ...] = ()

    def __getstate__(self) -> dict[str, Any]:
        return {**self.__dict__, "_tree": None, "_base": None, "_base_warnings": ()}

    @property
    def tree(self) -> ModelTree:
        if self._tree is None:
            self._tree = ModelTree(self.source)
        return self._tree

    def _analysis(self) -> Any:
        from mechdyn.registry import get

        return get(self.analysis)

    # -- evaluation ---------------------------------------------------------------------------
    def __call__(self, X: Any, curves: bool = False) -> list[Evaluation]:
        """Evaluate the variants whose parameter values (SI) are the rows of ``X`` (V × P)."""
        X = np.atleast_2d(np.asarray(X, dtype=float))
        if X.shape[1] != len(self.parameters):
            raise MechdynError(f"{X.shape[1]} values per variant for {len(self.parameters)} parameters")
        if self.batch and not curves and len(X):
            try:
                return self._batch(X)
            except NotBatchable:
                self.batch = False
        return [self.one(row, curves=curves) for row in X]

    def variant_source(self, row: Sequence[float]) -> ModelSource:
        """The model file of one variant, built in memory.

        Parameters
        ----------
        row : sequence of float
            The parameters' values, SI, in the study's order.
        """
        values: dict[Any, Any] = {}
        for p, x in zip(self.parameters, row, strict=True):
            if p.apply is None:
                values.update(p.file_values(float(x)))
        return self.tree.variant(values)

    def one(self, row: Sequence[float], curves: bool = False, keep_result: bool = False) -> Evaluation:
        """Build one variant from its files and run the analysis on it.

        Parameters
        ----------
        row : sequence of float
            The parameters' values, SI, in the study's order.
        curves : bool
            Keep the result's arrays.
        keep_result : bool
            Keep the result itself (:attr:`Evaluation.result`), e.g. to draw it.
        """
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                loaded = load_source(self.variant_source(row))
                for p, x in zip(self.parameters, row, strict=True):
                    if p.apply is not None:
                        loaded = replace(loaded, model=p.apply(loaded.model, float(x)))
                result = self._run(loaded)
                summary = result.summary()
            except MechdynError as exc:  # a bad design; anything else is a bug and stops the study
                error = f"{type(exc).__name__}: {exc}"
                return Evaluation("failed", error, dict.fromkeys(self.outputs), _said(caught))
        outputs = {k: output_value(summary, k) for k in self.outputs}
        kept = result.arrays() if curves else {}
        said = _said(caught, getattr(result, "warnings", ()))
        return Evaluation("ok", None, outputs, said, kept, result if keep_result else None)

    def _run(self, loaded: Any) -> Any:
        """The analysis on one loaded model, with the study's options."""
        analysis = self._analysis()
        options = dict(self.options)
        if analysis.uses_store:
            options.setdefault("store", None)
        return analysis.run(loaded, **options)

    def base_summary(self) -> dict[str, Any] | None:
        """The base model's whole summary by the single-design path, to check what the outputs name
        (None when the base model cannot be evaluated: its variants then say why)."""
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                return self._run(load_source(self.source)).summary()
            except MechdynError:
                return None

    def _batch(self, X: np.ndarray) -> list[Evaluation]:
        """The block through the analysis' batch evaluation: the quantities as columns, once per
        combination of the whole numbers and choices, on the model written with those."""
        analysis = self._analysis()
        if analysis.batch is None:
            raise NotBatchable(f"{analysis.name} has no batch evaluation")
        fixed = [j for j, p in enumerate(self.parameters) if p.discrete]
        varied = [j for j, p in enumerate(self.parameters) if not p.discrete]
        if fixed and not varied:
            raise NotBatchable("only whole numbers and choices vary: each variant is a model of its own")
        groups: dict[tuple[float, ...], list[int]] = {}
        for v, row in enumerate(X):
            groups.setdefault(tuple(float(x) for x in row[fixed]), []).append(v)
        out: list[Evaluation | None] = [None] * len(X)
        for values, rows in groups.items():
            built = self._group_base(dict(zip(fixed, values, strict=True)))
            if isinstance(built, Evaluation):  # the model with these values cannot be built
                for v in rows:
                    out[v] = built
                continue
            base, load_warnings = built
            sub = X[rows]
            columns: dict[Any, np.ndarray] = {}
            for j in varied:
                for loc, col in self.parameters[j].location_values(sub[:, j]).items():
                    columns[(loc.files, loc.keys)] = col
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                got, errors = analysis.batch(base, columns, list(self.outputs), **self.options)
            # what the model warned of as it was built, and what the block warned of as it ran (the
            # batch says no more than that: a warning of the block is stored with each of its variants)
            said = _said(load_warnings, caught)
            for i, (v, err) in enumerate(zip(rows, errors, strict=True)):
                if err is not None:
                    out[v] = Evaluation("failed", err, dict.fromkeys(self.outputs), said)
                    continue
                row = {k: float(got[k][i]) if np.isfinite(got[k][i]) else None for k in self.outputs}
                out[v] = Evaluation("ok", None, row, said)
        return [e for e in out if e is not None]

    def _group_base(self, values: Mapping[int, float]) -> Any:
        """The loaded model with the whole numbers and choices at ``values`` (parameter index → value;
        the base model when there are none, or all are at base) and what it warned of as it was built,
        or the failed :class:`Evaluation` when it cannot be built."""
        if all(self.parameters[j].base == x for j, x in values.items()):
            if self._base is None:
                with warnings.catch_warnings(record=True) as caught:
                    warnings.simplefilter("always")
                    self._base = load_source(self.source)
                self._base_warnings = _said(caught)
            return self._base, self._base_warnings
        edits: dict[Any, Any] = {}
        for j, x in values.items():
            edits.update(self.parameters[j].file_values(x))
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                loaded = load_source(self.tree.variant(edits))
            except MechdynError as exc:
                return Evaluation(
                    "failed", f"{type(exc).__name__}: {exc}", dict.fromkeys(self.outputs), _said(caught)
                )
        return loaded, _said(caught)


def _said(*sources: Any) -> tuple[str, ...]:
    """Warning messages, each once, in order: caught warnings (``warnings.WarningMessage``) or text."""
    return tuple(dict.fromkeys(str(getattr(w, "message", w)) for ws in sources for w in ws))
