"""The Bayesian posterior of updated values, sampled: importance sampling from the Laplace Gaussian.

:func:`mechdyn.measurement.update_model` minimises ½ χ²(θ) over θ = ln p, the squared weighted
residuals plus the Tikhonov (prior) rows; exp(−½ χ²(θ)) is then, up to a constant, the posterior
density of θ under Gaussian measurement errors and a Gaussian prior in ln p. Its linearised
(Laplace) form is the Gaussian N(θ̂, (Jᵀ J + Σ_prior⁻¹)⁻¹) at the optimum θ̂. Where asked, the exact
posterior is sampled here instead.

Method: self-normalised importance sampling. The proposal is a multivariate Student t centred at
θ̂ with the Laplace covariance as its scale matrix and ``df`` = 5 degrees of freedom (heavier tails
than the posterior it approximates, so that the weights stay bounded where the Laplace Gaussian is
close: Geweke, *Econometrica* 57, 1989, §3), mixed with the prior (10 % of the draws): as the
posterior over the prior is the likelihood, which is bounded, the weights stay bounded however far
the posterior reaches beyond the Laplace Gaussian (defensive importance sampling: Hesterberg,
*Technometrics* 37, 1995; the draws weighed by the mixture's density, Owen & Zhou, *JASA* 95,
2000). When a stage's sample disagrees with its proposal (a heavy weight tail, the weighted mean or
spread far from the proposal's), the proposal is moved onto the sample's mean and 1.5 times its
covariance and drawn anew, at most twice (adaptive importance sampling: Cappé, Guillin, Marin &
Robert, *J. Comput. Graph. Stat.* 13, 2004); the last stage is the result. Its weights are
Pareto-smoothed and diagnosed by the shape k̂ of a generalised Pareto distribution fitted to their
largest values (PSIS: Vehtari, Simpson, Gelman, Yao & Gabry, "Pareto smoothed importance
sampling", *JMLR* 25(72), 2024; the fit by Zhang & Stephens, *Technometrics* 51, 2009, with the
weakly informative prior of Vehtari et al., appendix C).

Why importance sampling and not a Markov chain (emcee, Metropolis): each density evaluation is a
modal analysis of a model variant (a few ms for a machine on mounts); the Laplace Gaussian is
already at hand and is close to the posterior whenever the parameters are identifiable (the
updating drops those that are not); the draws are independent, so that their number is fixed in
advance (S evaluations a stage, three stages at most; not walkers × steps × a burn-in to be judged)
and the same seed gives the same sample; and k̂ says when the sample does *not* represent the
posterior (k̂ above min(1 − 1/log₁₀ S, 0.7): skewed, plateau-shaped or multi-modal posteriors far
from the Gaussian), which a chain's R-hat says only with several chains at many times the cost.
What it cannot see: a posterior mode far from θ̂ that neither the proposal nor the prior's share of
the draws reaches; the statement says so.

Diagnostics reported: k̂ and its threshold, the effective sample size (Kish, *Survey Sampling*,
1965: (Σ w)²/Σ w² of the smoothed weights), the draws the model refused, and the Monte Carlo
standard error of each posterior mean, σ/√ESS (Vehtari et al. 2024, §3). There is no R-hat: the
draws are independent, not chains.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["PosteriorWarning", "SampledPosterior", "pareto_smooth", "sample_posterior"]

_SHIFT, _RATIO = 0.5, 1.5  # a weighted sample this far from its proposal: the proposal does not fit
DEFENSIVE_FRACTION = 0.1  # of the draws from the defensive component (the prior)
_INFLATE = 1.5  # an adapted proposal's scale over the sample's covariance: wider, to find more tail
MIN_ESS = 100.0  # fewer effective draws do not place the 2.5 % and 97.5 % quantiles
DEFAULT_DF = 5.0  # the proposal's degrees of freedom: heavier tails than the Gaussian, finite variance


class PosteriorWarning(UserWarning):
    """The sampled posterior's diagnostics say the sample does not represent the posterior."""


def _gpd_fit(x: np.ndarray) -> tuple[float, float]:
    """Shape k and scale σ of a generalised Pareto distribution fitted to exceedances ``x`` (sorted,
    ascending, positive): the empirical-Bayes estimator of Zhang & Stephens (*Technometrics* 51,
    2009, §3), its k pulled towards 0.5 with the weight of 10 observations (Vehtari et al., *JMLR*
    25(72), 2024, appendix C). k > 0: a heavy tail (moments of order ≥ 1/k infinite)."""
    n = x.size
    m = 30 + int(math.sqrt(n))
    quartile = x[max(int(n / 4 + 0.5) - 1, 0)]
    b = 1.0 / x[-1] + (1.0 - np.sqrt(m / (np.arange(1, m + 1) - 0.5))) / (3.0 * quartile)
    k = np.log1p(-b[:, None] * x[None]).mean(axis=1)  # −k of Zhang & Stephens' sign convention
    profile = n * (np.log(-b / k) - k - 1.0)
    weight = np.exp(profile - profile.max())  # the profile likelihood's weights, 1/Σ exp(l_j − l_i)
    weight /= weight.sum()
    b_hat = float(weight @ b)
    k_hat = float(np.log1p(-b_hat * x).mean())
    sigma = -k_hat / b_hat
    return (n * k_hat + 10 * 0.5) / (n + 10), sigma


def pareto_smooth(log_weights: np.ndarray) -> tuple[np.ndarray, float]:
    """Pareto-smoothed importance weights and the tail shape k̂ (PSIS).

    Parameters
    ----------
    log_weights : ndarray
        (S,) log importance ratios, log target density − log proposal density (−inf: a draw of zero
        density).

    Returns
    -------
    weights : ndarray
        (S,) smoothed weights, normalised to sum to 1.
    k_hat : float
        Shape of the generalised Pareto distribution fitted to the largest M = min(S/5, 3√S)
        ratios, dimensionless (0 when those are equal: bounded weights; inf when there are too few
        finite ratios to fit).

    Notes
    -----
    Vehtari, Simpson, Gelman, Yao & Gabry, "Pareto smoothed importance sampling", *JMLR* 25(72),
    2024, algorithm 1: the M largest ratios are replaced by the expected order statistics of the
    fitted distribution, F⁻¹((z − ½)/M), z = 1 … M, none above the largest raw ratio.
    """
    lw = np.asarray(log_weights, dtype=float)
    finite = np.isfinite(lw)
    if not finite.any():
        raise ValueError("every draw has zero posterior density: nothing to weight")
    lw = np.where(finite, lw - lw[finite].max(), -np.inf)
    S = lw.size
    M = int(min(math.ceil(0.2 * S), math.ceil(3.0 * math.sqrt(S))))
    k_hat = math.inf  # too few finite ratios to fit a tail: nothing says the sample is sound
    if finite.sum() > M + 1 and M >= 5:
        order = np.argsort(lw)
        tail, cutoff = order[-M:], lw[order[-M - 1]]
        exceed = np.exp(lw[tail]) - math.exp(cutoff)  # ascending, ≥ 0
        positive = exceed[exceed > 0]
        if positive.size < 5:  # the largest ratios (nearly) equal: bounded weights, nothing to smooth
            k_hat = 0.0
        else:
            k_hat, sigma = _gpd_fit(positive)
            p = (np.arange(1, M + 1) - 0.5) / M
            if abs(k_hat) > 1e-12:
                q = sigma * np.expm1(-k_hat * np.log1p(-p)) / k_hat
            else:
                q = -sigma * np.log1p(-p)
            lw[tail] = np.log(np.minimum(q + math.exp(cutoff), 1.0))  # none above the largest raw ratio, 1
    w = np.exp(lw)
    return w / w.sum(), float(k_hat)


def _weighted_quantile(x: np.ndarray, w: np.ndarray, q: Sequence[float]) -> np.ndarray:
    """Quantiles of a weighted sample: the midpoint rule of the weighted empirical distribution
    (each draw holds its weight centred on its value; Hyndman & Fan, *Am. Stat.* 50, 1996, type 5)."""
    order = np.argsort(x)
    xs, ws = x[order], w[order]
    mid = np.cumsum(ws) - 0.5 * ws
    return np.interp(np.asarray(q, dtype=float), mid, xs)


@dataclass(frozen=True, repr=False)
class SampledPosterior:
    """A weighted sample of the posterior of θ = ln p (:func:`sample_posterior`).

    Attributes
    ----------
    names : tuple of str
        The sampled parameters (the identifiable ones of an update).
    samples_log : ndarray
        (S, k) the proposal's draws of ln p, ln of SI values.
    weights : ndarray
        (S,) their Pareto-smoothed importance weights, dimensionless, summing to 1 (0: a draw the model
        refused).
    log_density : ndarray
        (S,) the unnormalised log posterior density at each draw (−inf: refused), dimensionless.
    mode_log : ndarray
        (k,) the updating's optimum θ̂ (the posterior mode when the Birge ratio is 1), ln of SI
        values.
    laplace_covariance_log : ndarray
        (k, k) the Laplace (linearised) covariance the proposal is scaled by, dimensionless.
    df : float
        The t proposal's degrees of freedom.
    stages : int
        Proposals drawn from (1: the Laplace one sufficed; more: adapted, see
        :func:`sample_posterior`); the draws are the last stage's.
    proposal_mean_log, proposal_scale_log : ndarray
        (k,) and (k, k) the last stage's proposal: its centre (ln of SI values) and scale matrix.
    pareto_k, pareto_k_threshold : float
        The weights' tail shape k̂ and the largest for which the sample is taken as representing the
        posterior, min(1 − 1/log₁₀ S, 0.7).
    ess : float
        Effective sample size (Σ w)²/Σ w² of the smoothed weights, dimensionless (draws).
    refused : int
        Draws at which the model could not be built or analysed (zero density).
    likelihood_scale : float
        The factor the residuals' variance was scaled by (the Birge ratio, ≥ 1).
    warning : str
        Why the sample does not represent the posterior (empty when the diagnostics pass).
    """

    names: tuple[str, ...]
    samples_log: np.ndarray
    weights: np.ndarray
    log_density: np.ndarray
    mode_log: np.ndarray
    laplace_covariance_log: np.ndarray
    df: float
    stages: int
    proposal_mean_log: np.ndarray
    proposal_scale_log: np.ndarray
    pareto_k: float
    pareto_k_threshold: float
    ess: float
    refused: int
    likelihood_scale: float = 1.0
    warning: str = ""

    method = (
        "importance sampling from the Laplace Gaussian (multivariate t proposal with a defensive "
        "prior component, adapted where needed; PSIS weights)"
    )

    @property
    def size(self) -> int:
        """Number of draws S (of the last stage; S × stages model evaluations in all)."""
        return int(self.weights.size)

    @property
    def valid(self) -> bool:
        """Whether the diagnostics pass (k̂ within its threshold, ESS ≥ 100)."""
        return not self.warning

    @property
    def mean_log(self) -> np.ndarray:
        """(k,) posterior mean of ln p."""
        return np.asarray(self.weights @ self.samples_log)

    @property
    def covariance_log(self) -> np.ndarray:
        """(k, k) posterior covariance of ln p, dimensionless."""
        d = self.samples_log - self.mean_log
        return np.asarray((d * self.weights[:, None]).T @ d)

    @property
    def std_log(self) -> np.ndarray:
        """(k,) posterior standard deviation of ln p, dimensionless (about the relative one of p)."""
        return np.sqrt(np.diag(self.covariance_log))

    @property
    def correlation(self) -> np.ndarray:
        """(k, k) posterior correlation of ln p, dimensionless."""
        s = self.std_log
        return self.covariance_log / np.outer(s, s)

    @property
    def mcse_log(self) -> np.ndarray:
        """(k,) Monte Carlo standard error of :attr:`mean_log`, σ/√ESS (Vehtari et al. 2024, §3)."""
        return self.std_log / math.sqrt(self.ess)

    def quantile_log(self, q: Sequence[float]) -> np.ndarray:
        """(len(q), k) posterior quantiles of ln p (ln of SI values).

        Parameters
        ----------
        q : sequence of float
            Probabilities, fraction (0 to 1).
        """
        return np.column_stack(
            [_weighted_quantile(self.samples_log[:, j], self.weights, q) for j in range(len(self.names))]
        )

    @property
    def mean(self) -> np.ndarray:
        """(k,) posterior mean of p, SI."""
        return np.asarray(self.weights @ np.exp(self.samples_log))

    @property
    def std(self) -> np.ndarray:
        """(k,) posterior standard deviation of p, SI."""
        p = np.exp(self.samples_log)
        return np.sqrt(self.weights @ (p - self.mean) ** 2)

    @property
    def median(self) -> np.ndarray:
        """(k,) posterior median of p, SI."""
        return np.exp(self.quantile_log([0.5])[0])

    @property
    def interval_95(self) -> np.ndarray:
        """(k, 2) central 95 % credible interval of p (2.5 % and 97.5 % quantiles), SI."""
        return np.exp(self.quantile_log([0.025, 0.975]).T)

    def draw(self, u: Any) -> np.ndarray:
        """Resample: the draws whose cumulative weight first exceeds each ``u`` (inverse-CDF
        multinomial resampling; stratified when ``u`` is).

        Parameters
        ----------
        u : array_like
            (N,) numbers in [0, 1).

        Returns
        -------
        ndarray
            (N, k) values of ln p.
        """
        u = np.asarray(u, dtype=float)
        idx = np.searchsorted(np.cumsum(self.weights), u, side="right")
        return self.samples_log[np.clip(idx, 0, self.size - 1)]

    @property
    def statement(self) -> str:
        """Whether the sample represents the posterior, in words (never more than the diagnostics say)."""
        head = (
            f"{self.size} draws (stage {self.stages}), effective sample size {self.ess:.0f}, "
            f"Pareto k̂ {self.pareto_k:.2f} "
            f"(threshold {self.pareto_k_threshold:.2f}), {self.refused} refused by the model"
        )
        if self.warning:
            return f"{head}: NOT a valid sample of the posterior: {self.warning}"
        return (
            f"{head}: the diagnostics pass, no sign that the sample misrepresents the posterior (a mode "
            "far from the updated values that the proposal never reaches would not show)"
        )

    def diagnostics(self) -> dict[str, Any]:
        """The sampling's diagnostics, unit-suffixed where they have a unit (dimensionless here)."""
        return {
            "method": self.method,
            "draws": self.size,
            "stages": int(self.stages),
            "effective_sample_size": float(self.ess),
            "pareto_k": float(self.pareto_k),
            "pareto_k_threshold": float(self.pareto_k_threshold),
            "refused_draws": int(self.refused),
            "proposal_df": float(self.df),
            "likelihood_variance_scale": float(self.likelihood_scale),
            "r_hat": "not applicable: independent draws, no chains",
            "valid": self.valid,
            "statement": self.statement,
        }


def sample_posterior(
    log_density: Callable[[np.ndarray], float],
    mode: Sequence[float],
    covariance: Any,
    samples: int = 1000,
    *,
    seed: int | np.random.Generator | None = 0,
    df: float = DEFAULT_DF,
    names: Sequence[str] = (),
    likelihood_scale: float = 1.0,
    adapt: int = 2,
    defensive: tuple[Any, Any] | None = None,
) -> SampledPosterior:
    """Sample a posterior by importance sampling from a t distribution around its mode (PSIS).

    Parameters
    ----------
    log_density : callable
        θ (k,) → the unnormalised log posterior density, dimensionless; −inf where it is zero (a
        value the model refuses).
    mode : sequence of float
        (k,) the posterior mode θ̂.
    covariance : array_like
        (k, k) the Laplace covariance at the mode (the proposal's scale matrix).
    samples : int
        Draws S (density evaluations), at least 50.
    seed : int or numpy Generator, optional
        Random seed (the same seed, the same sample).
    df : float
        The t proposal's degrees of freedom (> 2).
    names : sequence of str
        The parameters' names (for the report).
    likelihood_scale : float
        Recorded only: the factor by which ``log_density``'s residual variances were scaled.
    adapt : int
        At most this many further stages when a stage's sample disagrees with its proposal (k̂ above
        0.5, or the weighted mean more than half a scale away, or a standard deviation outside 2/3 …
        3/2 of the scale): the proposal moved onto that sample's mean and 1.5 times its covariance
        (wider, to look further into the tails) and drawn anew
        (adaptive importance sampling: Cappé, Guillin, Marin & Robert, *J. Comput. Graph. Stat.* 13,
        2004); the last stage alone is the result (S draws each; S × stages evaluations).
    defensive : (mean, covariance), optional
        A Gaussian that the posterior is bounded by (its prior: posterior/prior is the likelihood,
        which is bounded): 10 % of each stage's draws come from it and every draw is weighed by the
        mixture's density (a deterministic mixture: Owen & Zhou, *JASA* 95, 2000), so that the
        weights stay bounded however far the posterior's tails reach beyond the t proposal
        (defensive importance sampling: Hesterberg, *Technometrics* 37, 1995).

    Returns
    -------
    SampledPosterior
        With ``warning`` set, and a :class:`PosteriorWarning` issued, when k̂ exceeds
        min(1 − 1/log₁₀ S, 0.7) (Vehtari et al., *JMLR* 25(72), 2024, §3.2), the last stage's
        sample still disagrees with its proposal (as for ``adapt``), or the effective sample size is
        below 100.

    Raises
    ------
    ValueError
        For too few samples, a df of 2 or less, a covariance that is not (k, k) symmetric positive
        definite, or every draw of zero density.

    Notes
    -----
    See the module's description for the method and its sources.
    """
    from scipy.stats import multivariate_normal, multivariate_t

    centre = np.atleast_1d(np.asarray(mode, dtype=float))
    k = centre.size
    cov = np.atleast_2d(np.asarray(covariance, dtype=float))
    if not (isinstance(samples, int | np.integer) and samples >= 50):
        raise ValueError(f"samples={samples!r}: give an integer of at least 50 draws, e.g. 1000")
    if not df > 2:
        raise ValueError(f"df={df!r}: give more than 2 degrees of freedom (finite variance), e.g. 5")
    if cov.shape != (k, k) or not np.allclose(cov, cov.T) or np.linalg.eigvalsh(cov).min() <= 0:
        raise ValueError(
            f"the covariance {cov.tolist()} is not a symmetric positive definite {k} × {k} matrix; "
            "give the Laplace covariance at the mode"
        )
    rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
    threshold = min(1.0 - 1.0 / math.log10(samples), 0.7)
    loc, scale = centre, cov
    n_wide = 0 if defensive is None else round(DEFENSIVE_FRACTION * samples)
    if defensive is not None:
        wide = multivariate_normal(mean=np.asarray(defensive[0], float), cov=np.asarray(defensive[1], float))
    for stage in range(1 + adapt):
        proposal = multivariate_t(loc=loc, shape=scale, df=df)
        theta = np.asarray(proposal.rvs(size=int(samples) - n_wide, random_state=rng), float).reshape(-1, k)
        log_q = np.asarray(proposal.logpdf(theta), dtype=float).reshape(-1)
        if n_wide:  # the deterministic mixture (Owen & Zhou 2000): each draw weighed by the mixture
            theta = np.vstack(
                [theta, np.asarray(wide.rvs(size=n_wide, random_state=rng), float).reshape(-1, k)]
            )
            a = n_wide / samples
            log_q = np.logaddexp(
                np.log1p(-a) + np.asarray(proposal.logpdf(theta), float).reshape(-1),
                np.log(a) + np.asarray(wide.logpdf(theta), float).reshape(-1),
            )
        log_p = np.array([float(log_density(t)) for t in theta])
        log_p = np.where(np.isfinite(log_p), log_p, -np.inf)
        w, k_hat = pareto_smooth(log_p - log_q)
        mean = w @ theta
        d = theta - mean
        moments = (d * w[:, None]).T @ d
        s0 = np.sqrt(np.diag(scale))
        shift = float(np.max(np.abs(mean - loc) / s0))
        ratio = np.sqrt(np.diag(moments)) / s0
        mismatch = shift > _SHIFT or bool(np.any((ratio > _RATIO) | (ratio < 1.0 / _RATIO)))
        if k_hat <= 0.5 and not mismatch:
            break
        if stage < adapt and np.linalg.eigvalsh(moments).min() > 0:  # move the proposal onto the sample
            loc, scale = mean, _INFLATE * 0.5 * (moments + moments.T)
        else:
            break
    refused = int(np.sum(~np.isfinite(log_p)))
    ess = float(1.0 / np.sum(w**2))
    why = []
    if not k_hat <= threshold:
        why.append(
            f"the importance weights' tail is too heavy (Pareto k̂ {k_hat:.2f} above {threshold:.2f}): "
            "the posterior is far from the Laplace Gaussian (skewed, with a plateau, heavier tails or "
            "several modes) and its moments and quantiles from this sample are unreliable; the linear "
            "(Laplace) interval is no better there: narrow the parameters (a tighter prior_uncertainty, "
            "fewer parameters) or add measured modes"
        )
    if mismatch:
        why.append(
            f"the weighted sample's moments do not match the proposal's (mean shifted by {shift:.2f} of "
            f"its scale, standard deviations {np.round(ratio, 2).tolist()} of its scale): the estimate "
            "has not settled"
        )
    if ess < MIN_ESS:
        why.append(f"the effective sample size {ess:.0f} is below {MIN_ESS:.0f}: give more samples")
    out = SampledPosterior(
        names=tuple(names) or tuple(f"theta{j}" for j in range(k)),
        samples_log=theta,
        weights=w,
        log_density=log_p,
        mode_log=centre,
        laplace_covariance_log=cov,
        df=float(df),
        stages=stage + 1,
        proposal_mean_log=np.asarray(loc, dtype=float),
        proposal_scale_log=np.asarray(scale, dtype=float),
        pareto_k=k_hat,
        pareto_k_threshold=threshold,
        ess=ess,
        refused=refused,
        likelihood_scale=float(likelihood_scale),
        warning="; ".join(why),
    )
    if why:
        warnings.warn(PosteriorWarning("the sampled posterior: " + out.statement), stacklevel=2)
    return out
