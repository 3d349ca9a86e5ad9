"""The result of a model updating: values with their uncertainty, identifiability, residuals, the file."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from mechdyn.measurement.compare import ModeComparison
from mechdyn.measurement.posterior import SampledPosterior

__all__ = ["ModelUpdate"]


@dataclass(frozen=True, repr=False)
class ModelUpdate:
    """A model updated against identified modes (:func:`mechdyn.measurement.update_model`).

    Attributes
    ----------
    names : tuple of str
        The parameters' paths.
    units, factors : tuple of str, ndarray
        The unit each is written in in the model file and SI per that unit (for display).
    prior, value : ndarray
        (n,) the model's values and the updated ones, SI (a parameter not identifiable: its model
        value).
    log_std : ndarray
        (n,) standard uncertainty of ln p after the update, dimensionless (NaN: not identifiable):
        the Laplace one, or the sampled posterior's standard deviation when sampled.
    interval_95 : ndarray
        (n, 2) 95 % interval, SI (NaN: not identifiable): p·exp(±1.96 σ) (linear), or the sampled
        posterior's 2.5 % and 97.5 % quantiles (a credible interval).
    identifiable : ndarray
        (n,) bool, dimensionless: whether the measured modes pin the parameter down.
    reasons : tuple of str
        Why a parameter is not identifiable (empty for one that is).
    covariance_log : ndarray
        (n, n) posterior covariance of ln p, dimensionless (NaN rows for parameters held at their
        model values): the Laplace one, or the sampled posterior's.
    singular_values : ndarray
        Singular values of the weighted sensitivity matrix at the model's values, columns scaled to
        unit length, divided by the largest: a value near 0 means a combination of parameters the
        modes do not see.
    before, after : ModeComparison
        The measured modes against the model's, before and after (same measured modes).
    chi2_before, chi2_after : float
        Sum of squared weighted residuals (frequency errors over their scatter, and shapes' when
        weighted), before and after, dimensionless.
    birge_ratio : float
        max(1, χ²/(m − n)): the factor the covariance was scaled by for residuals larger than the
        stated scatter.
    starts : int
        Start points of the global search (the model's values and the Sobol points).
    source : ModelSource
        The updated model file, in memory.
    warnings : tuple of str
        What the model warned of as the variants were built.
    variant : callable
        (n,) parameter values, SI → the model file with them, in memory.
    posterior_method : {"linear", "sampling"}
        Where the uncertainty comes from: the Laplace covariance or the sampled posterior.
    posterior : SampledPosterior or None
        The sampled posterior of the identifiable parameters' ln p with its diagnostics
        (:mod:`mechdyn.measurement.posterior`; None: linear).
    """

    names: tuple[str, ...]
    units: tuple[str, ...]
    factors: np.ndarray
    prior: np.ndarray
    value: np.ndarray
    log_std: np.ndarray
    interval_95: np.ndarray
    identifiable: np.ndarray
    reasons: tuple[str, ...]
    covariance_log: np.ndarray
    singular_values: np.ndarray
    before: ModeComparison
    after: ModeComparison
    chi2_before: float
    chi2_after: float
    birge_ratio: float
    starts: int
    source: Any = field(compare=False)
    warnings: tuple[str, ...] = ()
    variant: Callable[[np.ndarray], Any] | None = field(default=None, compare=False)
    posterior_method: str = "linear"
    posterior: SampledPosterior | None = field(default=None, compare=False)

    @property
    def standard_uncertainty(self) -> np.ndarray:
        """(n,) standard uncertainty of each value, SI (first order, p·σ of ln p; NaN: not identifiable)."""
        return self.value * self.log_std

    @property
    def posterior_samples(self) -> np.ndarray | None:
        """(S, n) the sampled posterior's draws of every parameter, SI (those not identifiable at
        their model value), weighted by ``posterior.weights``; None when not sampled."""
        if self.posterior is None:
            return None
        out = np.tile(self.value, (self.posterior.size, 1))
        out[:, self.identifiable] = np.exp(self.posterior.samples_log)
        return out

    def posterior_draw(self, u: Any) -> np.ndarray:
        """Parameter values resampled from the sampled posterior by inverse-CDF resampling of its
        weights (:meth:`SampledPosterior.draw`).

        Parameters
        ----------
        u : array_like
            (N,) numbers in [0, 1) (uniform: multinomial resampling; stratified: stratified).

        Returns
        -------
        ndarray
            (N, n) values of every parameter, SI (those not identifiable at their model value).

        Raises
        ------
        ValueError
            When the posterior was not sampled (``posterior="sampling"`` in :func:`update_model`).
        """
        if self.posterior is None:
            raise ValueError(
                "this update's posterior was not sampled; give update_model(..., posterior='sampling')"
            )
        u = np.atleast_1d(np.asarray(u, dtype=float))
        out = np.tile(self.value, (u.size, 1))
        out[:, self.identifiable] = np.exp(self.posterior.draw(u))
        return out

    @property
    def correlation(self) -> np.ndarray:
        """(n, n) correlation of the updated values (ln p; NaN for those held at their model value)."""
        s = np.sqrt(np.diag(self.covariance_log))
        with np.errstate(invalid="ignore", divide="ignore"):
            return self.covariance_log / np.outer(s, s)

    def load(self) -> Any:
        """The updated model, loaded (:class:`mechdyn.io.LoadedModel`)."""
        from mechdyn.io.modelfile import load_source

        return load_source(self.source)

    def save(self, path: str | Path) -> Path:
        """Write the updated model file (with its analysis settings), via :func:`mechdyn.save`.

        Parameters
        ----------
        path : str or Path
            The model file to write (TOML); an existing file is overwritten.

        Returns
        -------
        Path
        """
        from mechdyn.io.save import save

        return save(self.load(), path)

    def input_space(self) -> Any:
        """The identifiable parameters' posterior as uncertain inputs for
        :func:`mechdyn.uncertainty.propagate`; the others are held at their values.

        Linear: lognormal variables (median the updated value, σ of ln p its standard uncertainty)
        with the posterior's correlation (Gaussian copula), one per identifiable parameter.
        Sampled: one variable ``posterior_draw``, uniform on [0, 1), that
        :meth:`posterior_draw` turns into a draw of all the parameters (resampling the weighted
        sample keeps its joint shape, which no copula of marginals would).

        Returns
        -------
        mechdyn.uncertainty.InputSpace
        """
        from mechdyn.uncertainty import InputSpace, lognormal, uniform

        idx = np.flatnonzero(self.identifiable)
        if not idx.size:
            raise ValueError("no parameter is identifiable from these modes: nothing to carry through")
        if self.posterior is not None:
            draw = uniform(
                "posterior_draw",
                0.0,
                1.0,
                source="resampling of the sampled posterior of " + ", ".join(self.names[i] for i in idx),
            )
            return InputSpace((draw,))
        variables = [
            lognormal(self.names[i], median=float(self.value[i]), sigma_ln=float(self.log_std[i]))
            for i in idx
        ]
        R = self.correlation[np.ix_(idx, idx)]
        return InputSpace(tuple(variables), correlation=R if idx.size > 1 else None)

    def predict(
        self,
        analysis: Callable[[Any], Sequence[float]],
        outputs: Sequence[str],
        n: int = 64,
        *,
        method: str = "mc",
        quantiles: Sequence[float] = (0.025, 0.5, 0.975),
        seed: int = 0,
    ) -> Any:
        """An analysis of the updated model with the band the measurement leaves: the identifiable
        parameters sampled from their posterior (:meth:`input_space`) and carried through by
        :func:`mechdyn.uncertainty.propagate`.

        Parameters
        ----------
        analysis : callable
            A loaded model (:class:`mechdyn.io.LoadedModel`) → its outputs, one float each, SI.
        outputs : sequence of str
            The outputs' names, with their unit as a suffix (``"floor_force_amplitude_N"``).
        n : int
            Model evaluations (samples).
        method : {"mc", "qmc"}
            Monte Carlo or randomised quasi-Monte Carlo (see :func:`mechdyn.uncertainty.propagate`).
        quantiles : sequence of float
            The outputs' quantiles to estimate, probabilities (fraction); by default the median and
            the 95 % band.
        seed : int
            Random seed (reproducible).

        Returns
        -------
        mechdyn.uncertainty.PropagationResult
        """
        from mechdyn.io.modelfile import load_source
        from mechdyn.uncertainty import propagate

        variant = self.variant
        if variant is None:
            raise ValueError("this update holds no way to build variants (made without update_model)")
        idx = np.flatnonzero(self.identifiable)
        space = self.input_space()

        def f(X: np.ndarray) -> np.ndarray:
            rows = []
            for x in X:
                if self.posterior is not None:
                    values = self.posterior_draw(x[:1])[0]
                else:
                    values = self.value.copy()
                    values[idx] = x
                rows.append(np.asarray(analysis(load_source(variant(values))), dtype=np.float64))
            return np.array(rows)

        return propagate(
            f, space, n, outputs=list(outputs), method=method, quantiles=tuple(quantiles), seed=seed
        )

    def summary(self) -> dict[str, Any]:
        """Updated values with their 95 % intervals (in the file's units), identifiability, χ², and
        where the uncertainty comes from (``posterior_method``; with the sampling's diagnostics, its
        validity and the posterior mean, median, standard deviation and correlation when sampled)."""
        post = self.posterior
        out: dict[str, Any] = {
            "chi2_before": self.chi2_before,
            "chi2_after": self.chi2_after,
            "birge_ratio": self.birge_ratio,
            "paired_modes": len(self.after.pairs),
            "posterior_method": (
                "linear: Laplace (Gauss–Newton) covariance of ln p, Birge-scaled; 95 % intervals "
                "p·exp(±1.96 σ)"
                if post is None
                else f"sampling: {post.method}; 95 % credible intervals from the weighted sample"
            ),
        }
        if post is not None:
            out["posterior"] = post.diagnostics()
            out["posterior_correlation"] = {
                "parameters": list(post.names),
                "matrix": post.correlation.round(6).tolist(),
            }
        j = 0
        for i, name in enumerate(self.names):
            f, u = self.factors[i], self.units[i]
            entry: dict[str, Any] = {
                "unit": u,
                "prior": float(self.prior[i] / f),
                "updated": float(self.value[i] / f),
                "identifiable": bool(self.identifiable[i]),
            }
            if self.identifiable[i]:
                entry["standard_uncertainty"] = float(self.standard_uncertainty[i] / f)
                entry["interval_95"] = [float(v / f) for v in self.interval_95[i]]
                if post is not None:
                    entry["posterior_mean"] = float(post.mean[j] / f)
                    entry["posterior_median"] = float(post.median[j] / f)
                    entry["posterior_std"] = float(post.std[j] / f)
                    entry["posterior_log_std"] = float(post.std_log[j])
                    entry["mcse_log_mean"] = float(post.mcse_log[j])
                    j += 1
            else:
                entry["note"] = f"not identifiable from these modes: {self.reasons[i]}; held at its prior"
                if post is not None:
                    entry["note"] += " (not sampled: its posterior is its prior)"
            out[name] = entry
        return out

    def to_frame(self) -> Any:
        """One row per parameter, in the model file's units (with the posterior mean and median when
        sampled)."""
        import pandas as pd

        f = self.factors
        table = pd.DataFrame(
            {
                "parameter": list(self.names),
                "unit": list(self.units),
                "prior": self.prior / f,
                "updated": self.value / f,
                "standard_uncertainty": self.standard_uncertainty / f,
                "low_95": self.interval_95[:, 0] / f,
                "high_95": self.interval_95[:, 1] / f,
                "identifiable": self.identifiable,
                "note": [r if r else "" for r in self.reasons],
            }
        )
        if self.posterior is not None:  # the sampled posterior's mean and median beside the optimum
            for at, column, v in (
                (4, "posterior_mean", self.posterior.mean),
                (5, "posterior_median", self.posterior.median),
            ):
                full = np.full(len(self.names), np.nan)
                full[self.identifiable] = v
                table.insert(at, column, full / f)
        return table

    def plot(self, ax: Any = None) -> Any:
        """The paired modes' frequency errors before and after the update, %.

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Where to draw (a new figure when None).

        Returns
        -------
        matplotlib Axes
        """
        import matplotlib.pyplot as plt

        from mechdyn.plotting import legend

        if ax is None:
            _, ax = plt.subplots(figsize=(6, 3.5))
        k = np.arange(len(self.after.pairs))
        ax.bar(k - 0.2, 100 * self.before.frequency_error, 0.4, label="before")
        ax.bar(k + 0.2, 100 * self.after.frequency_error, 0.4, label="after")
        ax.errorbar(
            k + 0.2,
            np.zeros_like(k, float),
            yerr=100 * self.after.measured_scatter_hz / self.after.measured_hz,
            fmt="none",
            color="k",
            capsize=3,
            label="measured scatter",
        )
        ax.set_xticks(k, [f"{f:.3g} Hz" for f in self.after.measured_hz])
        ax.set_ylabel("frequency error (%)")
        ax.axhline(0.0, color="0.5", lw=0.8)
        legend(ax, fontsize="small")
        return ax
