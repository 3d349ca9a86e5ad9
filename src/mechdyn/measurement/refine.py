"""Refinement of an identified modal model by nonlinear least squares on the measured FRFs.

The LSCF poles are the roots of a linearised (equation-error) least-squares problem: with noise on
the FRFs they carry a bias that grows with the noise and the damping (Pintelon, Guillaume &
Schoukens, "Uncertainty calculation in (operational) modal analysis", MSSP 21, 2007; Guillaume et
al., "A poly-reference implementation of the least-squares complex frequency-domain estimator",
IMAC XXI, 2003, §5). Minimising the output error of the modal model itself,

    H(ω) = (iω)^p [ Σ_r ( R_r/(iω − λ_r) + R_r*/(iω − λ_r*) ) − L/ω² + U ],

p = 0, 1, 2 for receptance, mobility, accelerance, over the poles λ_r = −ζ_r ω_r + i ω_r √(1 − ζ_r²),
the residues R_r and the lower and upper residuals L, U of every output/reference pair, is the
output-error direction of the maximum-likelihood modal-model estimator (ML-MM: Guillaume, Verboven
& Vanlanduit, "Frequency-domain maximum likelihood identification of modal parameters with
confidence intervals", ISMA 23, 1998; Peeters et al., "The PolyMAX frequency-domain method", Shock
Vib. 11, 2004, §5; Ewins, *Modal Testing*, 2nd ed., 2000, §4.4). Unweighted, as here, it is the
maximum-likelihood estimator for white complex Gaussian noise on H and consistent for any zero-mean
noise: the noise bias of the linearised start is removed.

The residues enter linearly: given the poles they are a linear least-squares solution, so only the
2·n_modes pole parameters are iterated (variable projection: Golub & Pereyra, SIAM J. Numer. Anal.
10, 1973); the Jacobian J of the projected residual gives the pole block of the full Gauss–Newton
covariance (Golub & Pereyra, §3).

Measured noise is not white: it grows with abs(H). It is modelled per channel as a multiplicative
part plus a floor, σ²(ω) = a abs(Ĥ(ω))² + b (the hammer-test noise of Ewins §3.9), with a, b ≥ 0
fitted by non-negative least squares to the squared residuals, each divided by 1 − its leverage
(HC2: MacKinnon & White, J. Econometrics 29, 1985); the pole covariance is then the sandwich
(JᵀJ)⁻¹ Jᵀ Σ J (JᵀJ)⁻¹ (White, Econometrica 48, 1980; Pintelon & Schoukens, *System
Identification*, 2nd ed., 2012, §7.6) with Σ = diag(σ²/2) over the real and imaginary parts.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares, nnls

from mechdyn.measurement.data import MeasuredFRF

__all__ = ["RefinedModes", "refine_modes"]

_POWER = {"receptance": 0, "mobility": 1, "accelerance": 2}
_RELATIVE_FLOOR = 1e-6  # least noise variance, of a channel's mean squared residual (noise-free data)


@dataclass(frozen=True)
class RefinedModes:
    """The modal model after the nonlinear least-squares refinement.

    Attributes
    ----------
    omega : ndarray
        (n_modes,) undamped natural circular frequencies, rad/s.
    damping : ndarray
        (n_modes,) damping ratios, 1.
    omega_std, damping_std : ndarray
        (n_modes,) standard uncertainties from the sandwich covariance, rad/s and 1.
    residues : ndarray
        (n_out, n_ref, n_modes) complex residues, receptance form (the data's unit per second).
    fitted : ndarray
        (n_f, n_out, n_ref) the refined model's FRFs in the band (zero outside), SI.
    noise_std : ndarray
        (n_f, n_out, n_ref) the estimated noise standard deviation at each line in the band, SI.
    converged : bool
        Whether the optimiser met its tolerance.
    """

    omega: np.ndarray
    damping: np.ndarray
    omega_std: np.ndarray
    damping_std: np.ndarray
    residues: np.ndarray
    fitted: np.ndarray
    noise_std: np.ndarray
    converged: bool


def _poles(theta: np.ndarray) -> np.ndarray:
    """Poles from (ln ω_1, atanh(2ζ_1 − 1), …): ω > 0 and 0 < ζ < 1 without bounds."""
    w = np.exp(theta[0::2])
    z = 0.5 * (np.tanh(theta[1::2]) + 1.0)
    return np.asarray(-z * w + 1j * w * np.sqrt(1.0 - z**2))


def _basis(omega: np.ndarray, poles: np.ndarray, power: int) -> np.ndarray:
    """(n_f, 2·n_modes + 4) complex basis: the columns multiplying Re R_r, Im R_r, Re L, Im L, Re U,
    Im U (the FRF is real-linear, not complex-linear, in the residues, through their conjugates)."""
    s = 1j * omega[:, None]
    a = 1.0 / (s - poles[None]) + 1.0 / (s - poles.conj()[None])  # multiplies Re R
    b = 1j / (s - poles[None]) - 1j / (s - poles.conj()[None])  # multiplies Im R
    low = -1.0 / omega**2
    one = np.ones_like(omega)
    cols = np.column_stack([a, b, low, 1j * low, one, 1j * one])
    return np.asarray(cols * ((1j * omega) ** power)[:, None])


def _solve(omega: np.ndarray, Y: np.ndarray, poles: np.ndarray, power: int) -> tuple[np.ndarray, np.ndarray]:
    """Residues and residual terms for given poles (linear least squares, all pairs at once) and the
    residual.

    Y: (n_f, n_pairs) complex data. Returns the coefficients (n_cols, n_pairs) and the real residual
    (2·n_f, n_pairs), real parts above imaginary ones."""
    P = _basis(omega, poles, power)
    Pr = np.vstack([P.real, P.imag])
    Yr = np.vstack([Y.real, Y.imag])
    scale = np.linalg.norm(Pr, axis=0)  # columns of very different size (1/ω², ω²): equilibrate
    scale[scale == 0] = 1.0
    A = Pr / scale
    # normal equations of the equilibrated basis (a few dozen columns, well conditioned once
    # scaled): far cheaper than a QR of the tall matrix on every one of the optimiser's calls
    coef = np.linalg.solve(A.T @ A, A.T @ Yr) / scale[:, None]
    return coef, Pr @ coef - Yr


def _noise(H: np.ndarray, fit: np.ndarray, leverage: np.ndarray) -> np.ndarray:
    """(n_f, n_pairs) noise standard deviation per line: σ² = a abs(Ĥ)² + b per channel, fitted by
    NNLS to the squared residuals divided by 1 − leverage (each residual's expected share of the
    noise: the HC2 correction of MacKinnon & White, J. Econometrics 29, 1985)."""
    r2 = np.abs(H - fit) ** 2 / np.clip(1.0 - leverage, 0.05, 1.0)
    sigma = np.empty(H.shape)
    n_f = H.shape[0]
    for j in range(H.shape[1]):
        X = np.column_stack([np.abs(fit[:, j]) ** 2, np.ones(n_f)])
        scale = X.max(axis=0)
        scale[scale == 0] = 1.0
        ab = nnls(X / scale, r2[:, j])[0] / scale
        floor = max(float(np.mean(r2[:, j])) * _RELATIVE_FLOOR, np.finfo(float).tiny)
        sigma[:, j] = np.sqrt(np.maximum(X @ ab, floor))
    return sigma


def _jacobian(fun: Callable[[np.ndarray], np.ndarray], theta: np.ndarray) -> np.ndarray:
    """Central-difference Jacobian of ``fun`` at ``theta`` (steps 1e-6 of the log-parameters)."""
    cols = []
    for k in range(theta.size):
        step = np.zeros_like(theta)
        step[k] = 1e-6
        cols.append((fun(theta + step) - fun(theta - step)) / 2e-6)
    return np.column_stack(cols)


def refine_modes(
    measured: MeasuredFRF, omega: np.ndarray, damping: np.ndarray, lo: int, hi: int
) -> RefinedModes:
    """Refine poles and residues by nonlinear least squares on the measured FRFs, with covariance.

    Parameters
    ----------
    measured : MeasuredFRF
        The measured FRFs (any kind).
    omega, damping : ndarray
        (n_modes,) start values: natural circular frequencies (rad/s) and damping ratios (1), e.g.
        from LSCF.
    lo, hi : int
        The band: frequency lines ``lo`` to ``hi − 1``.

    Returns
    -------
    RefinedModes

    Raises
    ------
    ValueError
        For start values that are not positive or not paired, or a band with too few lines for the
        parameters (naming the value and the fix).

    Notes
    -----
    See the module's sources. The fit minimises the unweighted output error (the maximum-likelihood
    estimator for white noise on H, consistent for any zero-mean noise); as the measured noise is
    not white (it grows with abs(H)), the covariance is the sandwich form
    (JᵀJ)⁻¹ Jᵀ Σ J (JᵀJ)⁻¹ (White, Econometrica 48, 1980; Pintelon & Schoukens, *System
    Identification*, 2nd ed., 2012, §7.6) with Σ the estimated noise model, on the pole parameters
    (ln ω, atanh(2ζ − 1)), mapped to ω and ζ by their derivatives (first-order propagation).
    """
    omega = np.atleast_1d(np.asarray(omega, float))
    damping = np.atleast_1d(np.asarray(damping, float))
    n_modes = omega.size
    if damping.shape != omega.shape or n_modes == 0:
        raise ValueError(
            f"give one damping ratio per frequency: {omega.size} frequencies, {damping.size} damping ratios"
        )
    if not (np.all(np.isfinite(omega)) and np.all(omega > 0)):
        raise ValueError(f"start frequencies {omega} rad/s must be positive and finite")
    if not (np.all(np.isfinite(damping)) and np.all((damping > 0) & (damping < 1))):
        raise ValueError(f"start damping ratios {damping} must lie between 0 and 1")
    w = measured.omega[lo:hi]
    n_f = w.size
    if n_f < n_modes + 4:
        raise ValueError(
            f"the band (lines {lo} to {hi - 1}) holds {n_f} lines, too few for {n_modes} modes with "
            f"residuals (at least {n_modes + 4}); widen the band"
        )
    shape = measured.H.shape
    Y = measured.H[lo:hi].reshape(n_f, -1)
    power = _POWER[measured.kind]
    z0 = np.clip(damping, 1e-6, 0.999)
    theta0 = np.empty(2 * n_modes)
    theta0[0::2] = np.log(omega)
    theta0[1::2] = np.arctanh(2.0 * z0 - 1.0)

    def residual(theta: np.ndarray) -> np.ndarray:
        return _solve(w, Y, _poles(theta), power)[1].ravel()

    sol = least_squares(residual, theta0, method="lm", x_scale="jac", xtol=1e-12, ftol=1e-12)
    th = sol.x
    coef, _ = _solve(w, Y, _poles(th), power)
    P = _basis(w, _poles(th), power)
    model = P @ coef
    J = _jacobian(residual, th)
    JTJi = np.linalg.pinv(J.T @ J)
    # leverage of each real residual: the residues' (the same basis for every pair) plus the poles'
    A = np.vstack([P.real, P.imag])
    h_lin = np.sum((A @ np.linalg.pinv(A.T @ A)) * A, axis=1)
    h = h_lin[:, None] + np.sum((J @ JTJi) * J, axis=1).reshape(2 * n_f, -1)
    sigma = _noise(Y, model, 0.5 * (h[:n_f] + h[n_f:]))
    var_r = (np.vstack([sigma, sigma]) ** 2 / 2.0).ravel()  # each of Re, Im carries half the variance
    cov = JTJi @ (J.T * var_r) @ J @ JTJi
    wn = np.exp(th[0::2])
    z = 0.5 * (np.tanh(th[1::2]) + 1.0)
    var = np.diag(cov)
    R = (coef[:n_modes] + 1j * coef[n_modes : 2 * n_modes]).T  # (n_pairs, n_modes)
    fitted = np.zeros(shape, complex)
    fitted[lo:hi] = model.reshape((n_f, *shape[1:]))
    noise = np.zeros(shape)
    noise[lo:hi] = sigma.reshape((n_f, *shape[1:]))
    return RefinedModes(
        omega=wn,
        damping=z,
        omega_std=np.sqrt(var[0::2]) * wn,  # dω/d(ln ω) = ω
        damping_std=np.sqrt(var[1::2]) * 0.5 / np.cosh(th[1::2]) ** 2,  # dζ/dθ
        residues=R.reshape(shape[1], shape[2], n_modes),
        fitted=fitted,
        noise_std=noise,
        converged=bool(sol.success),
    )
