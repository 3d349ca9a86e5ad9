"""Evaluating design variants: parameter values in, the analysis' outputs (and its status) out.

The :class:`Evaluator` holds the base model's files, the analysis and what to read from its summary.
Given a block of variants it first offers them to the analysis' batch evaluation
(:attr:`mechdyn.registry.Analysis.batch`: a mechanism's variants in one compiled cycle), and
otherwise builds each variant from its files and runs the analysis on it. A variant that cannot be
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
from mechdyn.studies.paths import ModelTree
from mechdyn.studies.spec import Parameter, output_value

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
    curves : dict of str → (ndarray, unit)
        The result's arrays, when they were asked for.
    """

    status: str
    error: str | None
    outputs: dict[str, float | None]
    warnings: tuple[str, ...] = ()
    curves: dict[str, tuple[np.ndarray, str]] = field(default_factory=dict)


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

    def __getstate__(self) -> dict[str, Any]:
        return {**self.__dict__, "_tree": None, "_base": None}

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

    def one(self, row: Sequence[float], curves: bool = False) -> Evaluation:
        """Build one variant from its files and run the analysis on it.

        Parameters
        ----------
        row : sequence of float
            The parameters' values, SI, in the study's order.
        curves : bool
            Keep the result's arrays.
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
                return Evaluation("failed", f"{type(exc).__name__}: {exc}", dict.fromkeys(self.outputs))
        outputs = {k: output_value(summary, k) for k in self.outputs}
        kept = result.arrays() if curves else {}
        return Evaluation("ok", None, outputs, tuple(str(w.message) for w in caught), kept)

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
        analysis = self._analysis()
        if analysis.batch is None:
            raise NotBatchable(f"{analysis.name} has no batch evaluation")
        if self._base is None:
            self._base = load_source(self.source)
        columns: dict[Any, np.ndarray] = {}
        for j, p in enumerate(self.parameters):
            for loc, col in p.location_values(X[:, j]).items():
                columns[(loc.files, loc.keys)] = col
        with warnings.catch_warnings(record=True):
            warnings.simplefilter("always")
            values, errors = analysis.batch(self._base, columns, list(self.outputs), **self.options)
        out = []
        for v, err in enumerate(errors):
            if err is not None:
                out.append(Evaluation("failed", err, dict.fromkeys(self.outputs)))
                continue
            row = {k: float(values[k][v]) if np.isfinite(values[k][v]) else None for k in self.outputs}
            out.append(Evaluation("ok", None, row))
        return out
