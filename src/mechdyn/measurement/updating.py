"""Model updating: the model's uncertain values moved until its modes match the identified ones.

The parameters are model values named by their path in the model file (as a design study names
them, :mod:`mechdyn.studies.paths`: ``mounts.*.stiffness.z``, ``shafts.s1.stiffness``); each variant
is built in memory from the files (:meth:`mechdyn.studies.paths.ModelTree.variant`) and its modes
computed. The method is the sensitivity-based, regularised least squares of Friswell & Mottershead
(*Finite Element Model Updating in Structural Dynamics*, 1995, ch. 7–8):

- unknowns θ = ln p (positive values, relative steps), started at the model's values p₀;
- residuals: the paired frequencies' errors over their standard uncertainty, (f_model − f_meas)/σ_f
  (σ_f the measured scatter and ``model_error``·f_meas in quadrature), and
  optionally the shapes' w·(1 − MAC)/σ_MAC, the pairing fixed at each start (so that the residual
  vector keeps its meaning while the model moves; :func:`mechdyn.measurement.compare_modes` with
  ``pairs=``), plus the Tikhonov rows (θ − θ₀)/σ_prior that hold the values near the model's;
- minimised by a trust-region Gauss–Newton (Levenberg–Marquardt type) solver
  (:func:`scipy.optimize.least_squares`) from the model's values and from the best few of a Sobol
  sample of the search box (a global start against a wrong local minimum);
- uncertainty: the Gaussian (Laplace) posterior covariance of θ, (Jᵀ W J + Σ_prior⁻¹)⁻¹, with W the
  inverse squared measured scatter, multiplied by the Birge ratio χ²/(m − n) when that exceeds 1
  (the scatter understated; Birge, Phys. Rev. 40, 1932); a 95 % interval p·exp(±1.96 σ_θ);
- or, where asked (``posterior="sampling"``), the posterior itself sampled: the density
  exp(−½ χ²(θ)) of the same residuals and Tikhonov rows the solver minimises, over the identifiable
  parameters' θ, the residuals' variances scaled by the Birge ratio (its Bayesian reading: a common
  factor on the stated scatter), by importance sampling from the Laplace Gaussian
  (:mod:`mechdyn.measurement.posterior`); the intervals are then credible intervals (quantiles of
  the weighted sample) and the result states whether the sample represents the posterior;
- identifiability: from the data-only Fisher matrix F = Jᵀ W J: a parameter no measured mode sees
  (a zero column), or whose column depends on the others (a singular F), or whose marginal standard
  uncertainty sqrt((F⁻¹)ᵢᵢ) exceeds ``max_uncertainty``, is reported not identifiable from these
  modes and held at its model value (Brun, Reichert & Künsch, *Water Resour. Res.* 37, 2001, for the
  collinearity test).
"""

from __future__ import annotations

import warnings
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from mechdyn.errors import MechdynError
from mechdyn.measurement.compare import ModeComparison, Target, compare_modes
from mechdyn.measurement.identify import IdentifiedModes
from mechdyn.measurement.update_result import ModelUpdate

__all__ = ["ModelUpdate", "update_model", "updated_source"]

_Z95 = 1.959963984540054  # two-sided 95 % quantile of the standard normal distribution
_COLLINEAR = 1e-6  # smallest over largest singular value of the scaled sensitivities: columns dependent


class UpdateError(MechdynError):
    """A model updating that cannot be set up (a parameter, the pairing, the model's modes)."""


def _source(model: Any) -> Any:
    """The :class:`mechdyn.io.ModelSource` of a model file given as a path, a source or a loaded model."""
    from mechdyn.io.modelfile import ModelSource, read

    if isinstance(model, ModelSource):
        return model
    if hasattr(model, "source") and isinstance(model.source, ModelSource):
        return model.source
    if isinstance(model, (str, Path)):
        return read(model)
    raise UpdateError(
        f"update_model: the model is a {type(model).__name__}; give its model file (a path, a "
        "ModelSource or a model loaded with mechdyn.load), so that the updated values can be named by "
        "path and written back (mechdyn.save writes a model built in Python to a file first)"
    )


def _default_modes(loaded: Any) -> Any:
    """The modes of a loaded support or drivetrain model."""
    if loaded.type == "support":
        from mechdyn.support.modes import modes

        return modes(loaded.model)
    if loaded.type == "drivetrain":
        from mechdyn.drivetrain.modal import modal

        return modal(loaded.model)
    raise UpdateError(
        f"update_model: no default modal analysis for a {loaded.type!r} model; give modes=callable "
        "(a loaded model → its Modes, with omega, shapes and coordinate_names)"
    )


def _parameters(tree: Any, paths: Sequence[str]) -> list[Any]:
    """One study parameter per path (a vector path moves its components together), positive quantities."""
    from mechdyn.studies.errors import StudyError
    from mechdyn.studies.parameters import Parameter

    if isinstance(paths, str) or not paths:
        raise UpdateError(
            f"update_model: parameters={paths!r}; give a non-empty list of model paths, e.g. "
            "['mounts.*.stiffness.z', 'shafts.s1.stiffness']"
        )
    found = []
    for path in paths:
        if tree.nature(tree.resolve(path)[0]).kind != "quantity":
            raise UpdateError(f"update_model: {path!r} is not a quantity; only quantities are updated")
        positive = (
            f"update_model: {path!r} is not positive everywhere in the model; updating works on the "
            "logarithm of positive values (a stiffness, a damping, a mass): give such a path"
        )
        try:  # its range is only the search box of the global start, ±50 % of the model's values
            p = Parameter.from_spec(tree, path, range="±50 %", name=path)[0]
        except StudyError:  # a value of 0 has no relative range
            raise UpdateError(positive) from None
        if not p.base > 0 or any(b <= 0 for b in p.bases):
            raise UpdateError(
                f"update_model: {path!r} is {p.base!r} in the model; updating works on the logarithm "
                "of positive values: give a path whose values are positive"
            )
        found.append(p)
    return found


def updated_source(source: Any, values: Mapping[str, float]) -> Any:
    """A model file with updated values set as the updating sets them: each path's locations moved
    by the same factor from the model's values (a vector path moves its components together).

    Parameters
    ----------
    source : ModelSource
        The tested model file.
    values : mapping of str to float
        Path → its updated value, SI (the paths :func:`update_model` took).

    Returns
    -------
    ModelSource
        The file with the values, in memory (:func:`mechdyn.io.modelfile.load_source` loads it).
    """
    from mechdyn.studies.paths import ModelTree

    tree = ModelTree(source)
    file_values: dict[Any, Any] = {}
    for p, value in zip(_parameters(tree, list(values)), values.values(), strict=True):
        file_values.update(p.file_values(float(value)))
    return tree.variant(file_values)


class _Problem:
    """The residuals of one updating problem as functions of the log-parameters."""

    def __init__(
        self,
        source: Any,
        measured: IdentifiedModes,
        paths: Sequence[str],
        mapping: Mapping[str, Target],
        modes: Callable[[Any], Any],
        shape_weight: float,
        min_mac: float,
        model_error: float,
        shape_floor: float,
        damping_error: float | None,
    ) -> None:
        from mechdyn.studies.paths import ModelTree

        self.tree = ModelTree(source)
        self.params = _parameters(self.tree, paths)
        self.measured = measured
        self.mapping = mapping
        self.modes_of = modes
        self.shape_weight = float(shape_weight)
        self.min_mac = min_mac
        self.theta0 = np.log([p.base for p in self.params])
        self.model_error = model_error
        self.shape_floor = shape_floor
        self.damping_error = damping_error
        self.warned: list[str] = []

    def source(self, theta: np.ndarray) -> Any:
        values: dict[Any, Any] = {}
        for p, t, t0 in zip(self.params, theta, self.theta0, strict=True):
            values.update(p.file_values(p.base if t == t0 else float(np.exp(t))))
        return self.tree.variant(values)

    def modes(self, theta: np.ndarray) -> Any:
        from mechdyn.io.modelfile import load_source

        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            out = self.modes_of(load_source(self.source(theta)))
        self.warned.extend(str(w.message) for w in caught if str(w.message) not in self.warned)
        return out

    def compare(self, theta: np.ndarray, pairs: np.ndarray | None = None) -> ModeComparison:
        return compare_modes(
            self.measured, self.modes(theta), self.mapping, pairs=pairs, min_mac=self.min_mac
        )

    def sigma(self, pairs: np.ndarray) -> np.ndarray:
        """Each residual's standard uncertainty: relative frequency scatter, then the shapes', then
        the damping ratios' (relative), for the residuals in use."""
        i = pairs[:, 0]
        m = self.measured
        parts = [np.hypot(m.frequency_scatter_hz[i] / m.frequencies_hz[i], self.model_error)]
        if self.shape_weight:
            parts.append(np.maximum(m.shape_scatter[i], self.shape_floor))
        if self.damping_error is not None:
            parts.append(np.hypot(m.damping_scatter[i] / m.damping[i], self.damping_error))
        return np.concatenate(parts)

    def residuals(self, theta: np.ndarray, pairs: np.ndarray) -> np.ndarray:
        cmp = self.compare(theta, pairs)
        r = cmp.residuals(shape_weight=self.shape_weight)
        parts = [r[: len(pairs)]] + ([r[len(pairs) :]] if self.shape_weight else [])
        if self.damping_error is not None:
            if np.isnan(cmp.model_damping).any():
                raise UpdateError(
                    "update_model: damping_error is given but the model has no damping matrix to "
                    "compare damping ratios with; give the model dampers, or leave damping_error out"
                )
            parts.append(cmp.damping_error)
        return np.concatenate(parts) / self.sigma(pairs)

    def full(self, theta_free: np.ndarray, free: np.ndarray) -> np.ndarray:
        theta = self.theta0.copy()
        theta[free] = theta_free
        return theta

    def jacobian(self, theta: np.ndarray, pairs: np.ndarray, step: float = 1e-4) -> np.ndarray:
        """Central differences of the weighted residuals in θ = ln p (m × n)."""
        cols = []
        for j in range(len(theta)):
            e = np.zeros_like(theta)
            e[j] = step
            cols.append((self.residuals(theta + e, pairs) - self.residuals(theta - e, pairs)) / (2 * step))
        return np.column_stack(cols)


def _identifiable(
    J: np.ndarray, keep: np.ndarray, max_uncertainty: float, names: Sequence[str]
) -> tuple[np.ndarray, list[str]]:
    """Parameters the data pin down: a column that is zero, dependent or too weak is dropped, one at a
    time (the weakest first), until the data-only marginal uncertainty of each kept one is within
    ``max_uncertainty`` (in ln p). Returns the kept mask and, per parameter, why it was dropped."""
    n = J.shape[1]
    why = [""] * n
    keep = keep.copy()
    norms = np.linalg.norm(J, axis=0)
    for j in range(n):
        if keep[j] and norms[j] <= 1e-9 * max(1.0, norms.max()):
            keep[j], why[j] = False, "no measured mode sees it (zero sensitivity)"
    while keep.any():
        idx = np.flatnonzero(keep)
        Js = J[:, idx] / norms[idx]
        s, V = np.linalg.svd(Js, full_matrices=False)[1:]
        if s[-1] < _COLLINEAR * s[0]:  # dependent columns: drop the one weighing most in the null direction
            weights = np.abs(V[-1])
            k = idx[int(np.flatnonzero(weights >= weights.max() - 1e-9)[-1])]
            partners = ", ".join(names[idx[i]] for i in np.flatnonzero(weights > 0.1) if idx[i] != k)
            why[k] = f"its effect on the modes is that of {partners} (collinear sensitivities)"
            keep[k] = False
            continue
        F = Js.T @ Js
        std = np.sqrt(np.diag(np.linalg.inv(F))) / norms[idx]
        worst = int(np.argmax(std))
        if std[worst] <= max_uncertainty:
            break
        k = int(idx[worst])
        why[k] = f"the modes pin it only to ±{100 * std[worst]:.0f} % (above max_uncertainty)"
        keep[k] = False
    return keep, why


def _sample(
    prob: _Problem,
    theta: np.ndarray,
    keep: np.ndarray,
    pairs: np.ndarray,
    Jk: np.ndarray,
    sp: np.ndarray,
    birge: float,
    samples: int,
    seed: int,
) -> Any:
    """The posterior of the kept parameters' θ sampled: exp(−½ (rᵀr/b + Σ((θ − θ₀)/σ_prior)²)) with r
    the weighted residuals at the fixed pairing (those the solver minimised), b the Birge ratio."""
    from mechdyn.measurement.posterior import sample_posterior

    t0, s0 = prob.theta0[keep], sp[keep]

    def log_density(x: np.ndarray) -> float:
        try:
            r = prob.residuals(prob.full(x, keep), pairs)
        except MechdynError:  # a value the model file refuses: zero density
            return -np.inf
        return -0.5 * (float(r @ r) / birge + float(np.sum(((x - t0) / s0) ** 2)))

    laplace = np.linalg.inv(Jk.T @ Jk / birge + np.diag(1.0 / s0**2))
    return sample_posterior(
        log_density,
        theta[keep],
        0.5 * (laplace + laplace.T),
        samples,
        seed=np.random.default_rng([seed, 47]),
        names=[p.name for p, q in zip(prob.params, keep, strict=True) if q],
        likelihood_scale=birge,
        defensive=(t0, np.diag(s0**2)),
    )


def update_model(
    model: Any,
    measured: IdentifiedModes,
    parameters: Sequence[str],
    mapping: Mapping[str, Target] | None = None,
    *,
    modes: Callable[[Any], Any] | None = None,
    shape_weight: float = 0.0,
    prior_uncertainty: float | Sequence[float] = 1.0,
    search: float = 2.0,
    starts: int = 8,
    refine: int = 3,
    max_uncertainty: float = 0.5,
    min_mac: float = 0.5,
    model_error: float = 1e-3,
    shape_floor: float = 1e-3,
    damping_error: float | None = None,
    seed: int = 0,
    posterior: str = "linear",
    samples: int = 1000,
) -> ModelUpdate:
    """Update a model's values so that its modes match the identified ones, with their uncertainty.

    Parameters
    ----------
    model : str, Path, ModelSource or LoadedModel
        The model file (a support or a drivetrain by default; any type with ``modes=``).
    measured : IdentifiedModes
        From :func:`mechdyn.measurement.identify_modes` (or built from known frequencies, scatter and
        shapes).
    parameters : sequence of str
        Model paths, as a design study names them (``"mounts.*.stiffness.z"``: the z stiffness of
        every mount, moved together by one factor; ``"shafts.s1.stiffness"``). Positive quantities.
    mapping : mapping, optional
        Measurement point → model coordinate or location (:func:`mechdyn.measurement.observation_matrix`).
    modes : callable, optional
        A loaded model (:class:`mechdyn.io.LoadedModel`) → its modes (``omega`` rad/s,
        mass-normalised ``shapes``, ``coordinate_names``); by default :func:`mechdyn.support.modes`
        or :func:`mechdyn.drivetrain.modal`.
    shape_weight : float
        Weight of the shape residuals (1 − MAC over the shape scatter) against the frequency
        residuals, dimensionless; 0 (default): frequencies only. 1 − MAC is quadratic in a shape
        error and biased upward by noise, so the shape rows are best used to separate parameters
        that the frequencies alone cannot.
    prior_uncertainty : float or sequence of float
        Standard uncertainty of ln p before the test (0.3: about ±30 %), per parameter or for all:
        the Tikhonov rows (ln p − ln p₀)/σ_prior.
    search : float
        A factor, dimensionless: the global start samples p₀/search … p₀·search; the solver is
        bounded to p₀/search² … p₀·search².
    starts : int
        Sobol points of the global start (0: the model's values only).
    refine : int
        How many of the best starts (besides the model's values) are refined by the local solver.
    max_uncertainty : float
        A parameter whose data-only standard uncertainty in ln p exceeds this (0.5: ±50 %) is not
        identifiable from these modes and is held at its model value.
    min_mac : float
        Pairs below this MAC are left unpaired (they are not residuals).
    model_error : float
        Relative standard uncertainty added in quadrature to each measured frequency's scatter,
        dimensionless (0.001: 0.1 %): what the identification's scatter does not see (the LSCF
        noise bias of well-damped modes) and the model's own form error.
    shape_floor : float
        Least shape scatter taken for a shape residual's weight, dimensionless.
    damping_error : float, optional
        Also fit the damping ratios: the relative standard uncertainty added in quadrature to each
        measured damping ratio's scatter, dimensionless (0.05: 5 %, the model's proportional-damping
        estimate φᵀCφ/2ω against a measured complex mode); None (default): frequencies (and shapes)
        only, and a damping value is not identifiable.
    seed : int
        Seed of the Sobol sample and of the posterior's draws (reproducible).
    posterior : {"linear", "sampling"}
        ``"linear"`` (default): the Laplace (Gauss–Newton) covariance of ln p, Birge-scaled;
        ``"sampling"``: the posterior of the identifiable parameters' ln p sampled
        (:func:`mechdyn.measurement.posterior.sample_posterior`): the updated values stay the
        optimum (the file written), their standard uncertainty, correlation and 95 % intervals come
        from the sample, with its diagnostics (:attr:`ModelUpdate.posterior`); a parameter that is
        not identifiable is not sampled (held at its model value; its posterior is its prior).
    samples : int
        Draws of the sampled posterior (each a modal analysis of a variant), at least 50.

    Returns
    -------
    ModelUpdate

    Raises
    ------
    UpdateError
        For a path that is not a positive quantity, a model whose modes cannot be paired with the
        measured ones, or bad settings.
    mechdyn.studies.paths.PathError
        For a path the model does not have (naming the nearest ones).
    """
    from scipy.optimize import least_squares
    from scipy.stats import qmc

    if not search > 1:
        raise UpdateError(f"update_model: search={search!r}; give a factor > 1, e.g. 2")
    if not max_uncertainty > 0:
        raise UpdateError(f"update_model: max_uncertainty={max_uncertainty!r}; give a value > 0, e.g. 0.5")
    if posterior not in ("linear", "sampling"):
        raise UpdateError(
            f"update_model: posterior={posterior!r}; give 'linear' (the Laplace covariance) or 'sampling'"
        )
    if posterior == "sampling" and not (isinstance(samples, int | np.integer) and samples >= 50):
        raise UpdateError(f"update_model: samples={samples!r}; give an integer of at least 50, e.g. 1000")
    source = _source(model)
    prob = _Problem(
        source,
        measured,
        parameters,
        mapping or {},
        modes or _default_modes,
        shape_weight,
        min_mac,
        model_error,
        shape_floor,
        damping_error,
    )
    n = len(prob.params)
    sp = np.broadcast_to(np.asarray(prior_uncertainty, dtype=float), (n,)).copy()
    if np.any(sp <= 0):
        raise UpdateError(f"update_model: prior_uncertainty={prior_uncertainty!r}; give values > 0, e.g. 0.3")
    theta0 = prob.theta0
    before = prob.compare(theta0)
    pairs0 = before.pairs
    if len(pairs0) == 0:
        raise UpdateError(
            f"update_model: no measured mode pairs with a model mode at MAC ≥ {min_mac}; check the mapping "
            "of measurement points to the model, or lower min_mac"
        )
    measured_set = set(pairs0[:, 0].tolist())
    J0 = prob.jacobian(theta0, pairs0)
    names = [p.name for p in prob.params]
    keep, why = _identifiable(J0, np.ones(n, bool), max_uncertainty, names)
    lo, hi = theta0 - 2 * np.log(search), theta0 + 2 * np.log(search)

    def fit(free: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
        def fun(x: np.ndarray, pairs: np.ndarray) -> np.ndarray:
            try:
                r = prob.residuals(prob.full(x, free), pairs)
            except MechdynError:  # a value the model file refuses: a step the solver must not take
                r = np.full(prob.sigma(pairs).size, 1e6)
            return np.concatenate([r, (x - theta0[free]) / sp[free]])

        # the global start: the model's values and the best of a Sobol sample of the search box
        candidates = [theta0[free]]
        if starts > 0 and free.any():
            u = qmc.Sobol(int(free.sum()), scramble=True, seed=seed).random(int(starts))
            box = np.log(search)
            candidates.extend(theta0[free] - box + 2 * box * u)
        scored: list[tuple[float, int, np.ndarray, np.ndarray]] = []
        for x in candidates:
            try:
                pairs = prob.compare(prob.full(x, free)).pairs
            except MechdynError:
                continue
            if set(pairs[:, 0].tolist()) != measured_set:
                continue  # a start whose modes pair otherwise: its cost is not comparable
            scored.append((float(np.sum(fun(x, pairs) ** 2)), len(scored), x, pairs))
        scored.sort(key=lambda s: (s[0], s[1]))
        chosen = [s for s in scored if s[1] == 0][:1] + [s for s in scored if s[1] != 0][:refine]
        best: tuple[float, np.ndarray, np.ndarray] | None = None
        for _, _, x, pairs in chosen:
            for _ in range(3):  # refit while the pairing at the optimum differs from the start's
                sol = least_squares(
                    fun,
                    x,
                    args=(pairs,),
                    bounds=(lo[free], hi[free]),
                    method="trf",
                    diff_step=1e-6,  # central-enough steps above the eigen-solver's round-off
                    xtol=1e-10,
                    max_nfev=40 * (int(free.sum()) + 1),
                )
                now = prob.compare(prob.full(sol.x, free)).pairs
                if set(now[:, 0].tolist()) != measured_set or np.array_equal(now, pairs):
                    break
                x, pairs = sol.x, now
            cost = float(np.sum(sol.fun**2))
            if best is None or cost < best[0]:
                best = (cost, sol.x, pairs)
        if best is None:
            raise UpdateError("update_model: no start paired the measured modes as the model does")
        return best[1], best[2], len(candidates)

    for _ in range(n + 1):  # at most n parameters dropped, then one fit that keeps the rest
        x, pairs, tried = fit(keep) if keep.any() else (np.zeros(0), pairs0, 0)
        theta = prob.full(x, keep)
        J = prob.jacobian(theta, pairs)
        again, why_now = _identifiable(J, keep, max_uncertainty, names)
        if np.array_equal(again, keep):
            break
        for j in np.flatnonzero(keep & ~again):
            why[j] = why_now[j] + " at the updated values"
        keep = again
    r = prob.residuals(theta, pairs)
    m, k = r.size, int(keep.sum())
    birge = max(1.0, float(r @ r) / (m - k)) if m > k else 1.0
    cov = np.full((n, n), np.nan)
    sampled = None
    if k:
        Jk = J[:, keep]
        cov_k = np.linalg.inv(Jk.T @ Jk + np.diag(1.0 / sp[keep] ** 2)) * birge
        cov[np.ix_(keep, keep)] = cov_k
        if posterior == "sampling":
            sampled = _sample(prob, theta, keep, pairs, Jk, sp, birge, samples, seed)
            cov[np.ix_(keep, keep)] = sampled.covariance_log
    std = np.sqrt(np.diag(cov))
    prior = np.array([p.base for p in prob.params])
    value = np.where(keep, np.exp(theta), prior)
    interval = np.column_stack([value * np.exp(-_Z95 * std), value * np.exp(_Z95 * std)])
    if sampled is not None:
        interval[keep] = sampled.interval_95
    Jn = J0 / np.where(np.linalg.norm(J0, axis=0) > 0, np.linalg.norm(J0, axis=0), 1.0)
    sv = np.linalg.svd(Jn, compute_uv=False)
    return ModelUpdate(
        names=tuple(p.name for p in prob.params),
        units=tuple(p.unit for p in prob.params),
        factors=np.array([p.factor for p in prob.params]),
        prior=prior,
        value=value,
        log_std=std,
        interval_95=interval,
        identifiable=keep,
        reasons=tuple(why),
        covariance_log=cov,
        singular_values=sv / sv[0] if sv.size and sv[0] > 0 else sv,
        before=before,
        after=prob.compare(theta, pairs),
        chi2_before=float(np.sum(prob.residuals(theta0, pairs0) ** 2)),
        chi2_after=float(r @ r),
        birge_ratio=birge,
        starts=tried,
        source=prob.source(theta),
        warnings=tuple(prob.warned)
        + (
            ("posterior='sampling': no parameter is identifiable from these modes, nothing was sampled",)
            if posterior == "sampling" and sampled is None
            else ()
        ),
        variant=lambda values: prob.source(np.log(np.asarray(values, dtype=float))),
        posterior_method=posterior if sampled is not None else "linear",
        posterior=sampled,
    )
