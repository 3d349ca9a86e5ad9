"""Modes from measured FRFs: least-squares complex frequency (LSCF) poles, a stabilisation chart,
least-squares frequency-domain (LSFD) residues and shapes, each with its scatter over the stable poles.

The poles come from the common-denominator LSCF estimator of sdypy-EMA (``sdypy.EMA.Model``,
``method="lscf"``; Guillaume et al., "A poly-reference implementation of the least-squares complex
frequency-domain estimator", IMAC XXI, 2003; Verboven, PhD thesis, VUB 2002) fitted to every
output/reference pair at once, for model orders 2, 4, … 2·``max_order``. A pole is stable when one of
the previous order lies within ``frequency_tolerance`` in frequency and ``damping_tolerance`` in damping
ratio (Peeters et al., "The PolyMAX frequency-domain method", Shock Vib. 11, 2004, §4). Stable poles
are grouped by frequency; a group stable over at least ``min_stable`` orders is a mode, with the median
frequency and damping of its poles and their standard deviation as its scatter. Residues come from
sdypy-EMA's LSFD with lower and upper residual terms; the shape of a mode is the first left singular
vector of its (n_out, n_ref) residue matrix (Allemang & Brown, *Handbook of Experimental Structural
Dynamics*, 2022, ch. "Modal parameter estimation").
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from mechdyn.measurement.data import MeasuredFRF

__all__ = ["IdentifiedModes", "StabilisationChart", "identify_modes", "mac"]

NEW, STABLE_FREQUENCY, STABLE = 0, 1, 2  # status of a pole in the stabilisation chart


def mac(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Modal assurance criterion between every column of ``a`` and every column of ``b``.

    MAC_ij = abs(a_iᴴ b_j)² / ((a_iᴴ a_i)(b_jᴴ b_j)) (Allemang & Brown, "A correlation coefficient for
    modal vector analysis", IMAC I, 1982); 1 for parallel shapes, 0 for orthogonal ones.

    Parameters
    ----------
    a, b : ndarray
        (n_points, n_a) and (n_points, n_b) shapes, real or complex, in the model's units (the same
        for both: the MAC itself is dimensionless).

    Returns
    -------
    ndarray
        (n_a, n_b) values in [0, 1].
    """
    a = np.asarray(a).reshape(len(a), -1)
    b = np.asarray(b).reshape(len(b), -1)
    cross = np.abs(a.conj().T @ b) ** 2
    na = np.real(np.sum(a.conj() * a, axis=0))
    nb = np.real(np.sum(b.conj() * b, axis=0))
    return np.asarray(cross / np.outer(np.where(na == 0, 1, na), np.where(nb == 0, 1, nb)))


@dataclass(frozen=True, repr=False)
class StabilisationChart:
    """The poles of every model order and whether they are stable.

    Attributes
    ----------
    order : ndarray
        (n_poles,) model order (number of poles of the common denominator) each pole came from.
    frequency_hz : ndarray
        (n_poles,) undamped natural frequency of each pole, Hz.
    damping : ndarray
        (n_poles,) damping ratio of each pole, 1.
    status : ndarray
        (n_poles,) index, 0: new, 1: frequency stable, 2: frequency and damping stable.
    measured : MeasuredFRF
        The data the poles were fitted to (its sum of magnitudes is drawn behind the poles).
    """

    order: np.ndarray
    frequency_hz: np.ndarray
    damping: np.ndarray
    status: np.ndarray
    measured: MeasuredFRF

    def plot(self, ax: Any = None, *, modes: IdentifiedModes | None = None) -> Any:
        """Draw the chart: poles over model order, the summed FRF magnitude behind (log scale).

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Where to draw (a new figure when None).
        modes : IdentifiedModes, optional
            Modes to mark with vertical lines at their frequencies.

        Returns
        -------
        matplotlib Axes
        """
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(8, 4.5))
        for code, marker, label in (
            (NEW, "x", "new"),
            (STABLE_FREQUENCY, "o", "f stable"),
            (STABLE, "s", "f, ζ stable"),
        ):
            sel = self.status == code
            ax.plot(self.frequency_hz[sel], self.order[sel], marker, ms=3, ls="", label=label, mfc="none")
        if modes is not None:
            for f in modes.frequencies_hz:
                ax.axvline(f, color="k", lw=0.6, ls="--")
        ax.set_xlabel("frequency (Hz)")
        ax.set_ylabel("model order")
        f = self.measured.frequencies_hz
        twin = ax.twinx()
        twin.semilogy(f, np.abs(self.measured.H).reshape(f.size, -1).sum(axis=1), color="0.6", lw=0.8)
        twin.set_ylabel(f"Σ|H| ({self.measured.kind}, SI)")
        ax.set_xlim(f[0], f[-1])
        ax.legend(loc="upper left", fontsize="small")
        return ax


@dataclass(frozen=True, repr=False)
class IdentifiedModes:
    """Modes identified from measured FRFs, with their scatter over the stable poles.

    Attributes
    ----------
    omega : ndarray
        (n_modes,) undamped natural circular frequencies, rad/s, ascending (median of the stable poles).
    damping : ndarray
        (n_modes,) viscous damping ratios, 1.
    shapes : ndarray
        (n_out, n_modes) complex mode shapes at the measured outputs, dimensionless (largest entry
        real and 1).
    residues : ndarray
        (n_out, n_ref, n_modes) complex residues in the receptance form of the data's unit per second
        (H = Σ R_k/(iω − s_k) + conj terms).
    omega_scatter, damping_scatter : ndarray
        (n_modes,) standard uncertainty of the circular frequency (rad/s) and damping ratio (1):
        refined estimates (the default), from the refinement's parameter covariance; LSCF estimates,
        the spread over the stable model orders, over bootstrap data sets and the bootstrap's bias
        estimate, combined (see :func:`identify_modes`).
    shape_scatter : ndarray
        (n_modes,) dimensionless, 1 − the smallest MAC between the shape of the median pole and
        the shapes from the other sampled stable orders.
    stable_orders : ndarray
        (n_modes,) number of model orders at which each mode's pole was stable.
    outputs, references : tuple of (str, str)
        The measured (point, direction) of each row of ``shapes`` and each reference.
    chart : StabilisationChart
    method : str
        Which estimator made the frequencies, damping ratios and residues, and what the scatter is.
    start_omega, start_damping : ndarray or None
        (n_modes,) the LSCF estimates the refinement started from, rad/s and 1 (None when not
        refined).
    """

    omega: np.ndarray
    damping: np.ndarray
    shapes: np.ndarray
    residues: np.ndarray
    omega_scatter: np.ndarray
    damping_scatter: np.ndarray
    shape_scatter: np.ndarray
    stable_orders: np.ndarray
    outputs: tuple[tuple[str, str], ...]
    references: tuple[tuple[str, str], ...]
    chart: StabilisationChart = field(compare=False)
    method: str = "LSCF poles (sdypy-EMA), LSFD residues"
    start_omega: np.ndarray | None = field(default=None, compare=False)
    start_damping: np.ndarray | None = field(default=None, compare=False)

    @property
    def frequencies_hz(self) -> np.ndarray:
        """(n_modes,) natural frequencies, Hz."""
        return self.omega / (2.0 * np.pi)

    @property
    def frequency_scatter_hz(self) -> np.ndarray:
        """(n_modes,) standard deviation of the frequencies over the stable poles, Hz."""
        return self.omega_scatter / (2.0 * np.pi)

    def summary(self) -> dict[str, Any]:
        """Frequencies (Hz), damping ratios and their scatter, one list entry per mode."""
        return {
            "method": self.method,
            "natural_frequencies_hz": [float(f) for f in self.frequencies_hz],
            "frequency_scatter_hz": [float(f) for f in self.frequency_scatter_hz],
            "damping_ratios": [float(z) for z in self.damping],
            "damping_scatter": [float(z) for z in self.damping_scatter],
            "shape_scatter": [float(s) for s in self.shape_scatter],
        }

    def to_frame(self) -> Any:
        """One row per mode: frequency and damping with their scatter, stable orders."""
        import pandas as pd

        return pd.DataFrame(
            {
                "frequency_hz": self.frequencies_hz,
                "frequency_scatter_hz": self.frequency_scatter_hz,
                "damping_ratio": self.damping,
                "damping_scatter": self.damping_scatter,
                "shape_scatter": self.shape_scatter,
                "stable_orders": self.stable_orders,
            }
        )

    def plot(self, ax: Any = None) -> Any:
        """The stabilisation chart with the identified modes marked.

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Where to draw (a new figure when None).

        Returns
        -------
        matplotlib Axes
        """
        if self.chart.measured is None:
            raise ValueError(f"no stabilisation chart to draw: the modes were {self.method}")
        return self.chart.plot(ax, modes=self)


def _poles(measured: MeasuredFRF, f_lo: float, f_hi: float, max_order: int) -> list[np.ndarray]:
    """LSCF poles (rad/s, Im > 0, Re < 0, inside the band) for model orders 2, 4, … 2·max_order."""
    from sdypy.EMA import Model  # type: ignore[import-untyped]

    f = measured.frequencies_hz
    grid = np.linspace(f[0], f[-1], f.size)
    if np.abs(f - grid).max() > 0.01 * (f[-1] - f[0]) / max(f.size - 1, 1):  # allows rounding in files
        raise ValueError("LSCF needs equally spaced frequency lines; resample the FRFs on a uniform grid")
    frf = measured.H.reshape(f.size, -1).T
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # log of zero roots at low orders, dropped below
        model = Model(
            frf=frf, freq=f, lower=f_lo, upper=f[-1], pol_order_high=max_order, frf_form=measured.kind
        )
        model.get_poles(method="lscf", show_progress=False)
    out = []
    for p in model.all_poles:
        p = np.asarray(p)
        wn = np.abs(p)
        keep = (p.imag > 0) & (p.real < 0) & (wn >= 2 * np.pi * f_lo) & (wn <= 2 * np.pi * f_hi)
        out.append(p[keep])
    return out


def _lsfd(measured: MeasuredFRF, poles: np.ndarray, lo: int, hi: int) -> tuple[np.ndarray, np.ndarray]:
    """Residues (n_out, n_ref, n_poles) of the given poles by sdypy-EMA's LSFD with residual terms,
    and the reconstructed FRFs (n_out·n_ref, n_f)."""
    from sdypy.EMA.EMA import LSFD  # type: ignore[import-untyped]

    f = measured.frequencies_hz
    frf = measured.H.reshape(f.size, -1).T
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        A, rec = LSFD(poles, frf, f, True, True, lo, hi, measured.kind)[:2]
    return np.asarray(A).reshape(len(measured.outputs), len(measured.references), len(poles)), np.asarray(rec)


def _shapes(residues: np.ndarray) -> np.ndarray:
    """(n_out, n_modes) shapes: first left singular vector of each residue matrix, largest entry 1."""
    n_out, _, n = residues.shape
    out = np.empty((n_out, n), dtype=complex)
    for k in range(n):
        u = np.linalg.svd(residues[:, :, k])[0][:, 0]
        out[:, k] = u / u[np.argmax(np.abs(u))]
    return out


def _stabilise(
    poles: list[np.ndarray], f_tol: float, z_tol: float, max_damping: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Model order, pole and status (new, frequency stable, stable) of every pole of every order."""
    order, s_all, status = [], [], []
    for j, p in enumerate(poles):
        wn = np.abs(p)
        zeta = -p.real / np.where(wn == 0, 1, wn)
        prev = poles[j - 1] if j else np.zeros(0, complex)
        pw = np.abs(prev)
        pz = -prev.real / np.where(pw == 0, 1, pw)
        for k in range(p.size):
            code = NEW
            if zeta[k] <= max_damping and pw.size:
                i = int(np.argmin(np.abs(pw - wn[k])))
                if abs(pw[i] - wn[k]) <= f_tol * wn[k]:
                    code = STABLE_FREQUENCY
                    if abs(pz[i] - zeta[k]) <= z_tol * zeta[k]:
                        code = STABLE
            order.append(2 * (j + 1))
            s_all.append(p[k])
            status.append(code)
    return np.array(order, int), np.array(s_all, complex), np.array(status, int)


def _groups(
    order: np.ndarray, wn: np.ndarray, status: np.ndarray, f_tol: float, min_stable: int
) -> list[list[int]]:
    """Stable poles grouped by frequency (a gap wider than the tolerance starts a group), kept when
    stable over at least ``min_stable`` orders."""
    idx = np.flatnonzero(status == STABLE)
    idx = idx[np.argsort(wn[idx])]
    groups: list[list[int]] = []
    for i in idx:
        if groups and wn[i] - wn[groups[-1][-1]] <= f_tol * wn[i]:
            groups[-1].append(int(i))
        else:
            groups.append([int(i)])
    return [g for g in groups if len(set(order[g])) >= min_stable]


def _bootstrap(
    measured: MeasuredFRF,
    fitted: np.ndarray,
    lo: int,
    hi: int,
    omega: np.ndarray,
    zeta: np.ndarray,
    draws: int,
    seed: int,
    pole_args: tuple[float, float, int],
    stab_args: tuple[float, float, float, int],
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Mean and standard deviation of each mode's frequency (rad/s) and damping over wild-bootstrap
    data sets.

    Each set is the LSFD reconstruction plus the fit's residual at each line turned by a random
    phase (the wild bootstrap: Wu, Ann. Stat. 14, 1986), so the noise keeps its level line by line;
    the modes are re-identified and matched by frequency.
    """
    rng = np.random.default_rng(seed)
    H = measured.H.reshape(measured.omega.size, -1)
    rec = fitted.T
    resid = np.zeros_like(H)
    resid[lo:hi] = H[lo:hi] - rec[lo:hi]
    f_tol = stab_args[0]
    w_draws = np.full((draws, omega.size), np.nan)
    z_draws = np.full((draws, omega.size), np.nan)
    for d in range(draws):
        Hb = H.copy()
        Hb[lo:hi] = rec[lo:hi] + resid[lo:hi] * np.exp(2j * np.pi * rng.random(resid[lo:hi].shape))
        mb = MeasuredFRF(
            measured.omega, Hb.reshape(measured.H.shape), measured.outputs, measured.references, measured.kind
        )
        order, s, status = _stabilise(_poles(mb, *pole_args), *stab_args[:3])
        wn = np.abs(s)
        for g in _groups(order, wn, status, f_tol, stab_args[3]):
            wg = float(np.median(wn[g]))
            k = int(np.argmin(np.abs(omega - wg)))
            if abs(omega[k] - wg) <= 3 * f_tol * omega[k]:
                w_draws[d, k] = wg
                z_draws[d, k] = float(np.median(-s[g].real / wn[g]))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # a mode found in fewer than two draws
        return (
            np.nanmean(w_draws, axis=0),
            np.nanmean(z_draws, axis=0),
            np.nanstd(w_draws, axis=0, ddof=1),
            np.nanstd(z_draws, axis=0, ddof=1),
        )


def _shape_scatter(
    measured: MeasuredFRF,
    shapes: np.ndarray,
    s_all: np.ndarray,
    samples: list[list[int]],
    lo: int,
    hi: int,
    n_samples: int,
) -> np.ndarray:
    """1 − the smallest MAC between ``shapes`` and the LSFD shapes at pole sets taken at quantiles of
    each group of stable poles."""
    worst = np.ones(len(samples))
    for q in np.linspace(0.0, 1.0, n_samples):
        trial = np.array([s_all[g[round(q * (len(g) - 1))]] for g in samples])
        other = _shapes(_lsfd(measured, trial, lo, hi)[0])
        worst = np.minimum(worst, np.diag(mac(shapes, other)))
    return np.asarray(1.0 - worst)


def _rss(*parts: Any) -> np.ndarray:
    """Root sum of squares, a part that is NaN (a mode missed by every bootstrap draw) counted 0."""
    return np.asarray(np.sqrt(sum(np.nan_to_num(np.asarray(p, float)) ** 2 for p in parts)))


def identify_modes(
    measured: MeasuredFRF,
    *,
    f_min_hz: float | None = None,
    f_max_hz: float | None = None,
    max_order: int = 40,
    frequency_tolerance: float = 0.01,
    damping_tolerance: float = 0.05,
    min_stable: int | None = None,
    max_damping: float = 0.3,
    scatter_samples: int = 5,
    bootstrap: int = 20,
    seed: int = 0,
    refine: bool = True,
) -> IdentifiedModes:
    """Identify natural frequencies, damping ratios and mode shapes from measured FRFs: LSCF poles and
    LSFD residues, refined by nonlinear least squares on the FRFs (the default).

    Parameters
    ----------
    measured : MeasuredFRF
        Equally spaced frequency lines; receptance, mobility or accelerance.
    f_min_hz, f_max_hz : float, optional
        The band the modes are sought in, Hz (default: the data's range).
    max_order : int
        Highest number of complex-conjugate pole pairs of the common denominator (model order
        2·max_order); about 3–5× the number of modes in the band (over-modelling absorbs noise).
    frequency_tolerance, damping_tolerance : float
        Relative change of frequency and damping between successive orders under which a pole is
        stable (the usual 1 % and 5 %).
    min_stable : int, optional
        Orders a group of stable poles must span to be a mode (default: a quarter of the orders,
        at least 5).
    max_damping : float
        Poles with a larger damping ratio are taken as numerical, 1.
    scatter_samples : int
        Stable orders at which the residues are recomputed for the shape scatter.
    bootstrap : int
        Wild-bootstrap data sets for the noise part of the LSCF scatter (0 or 1: none); used with
        ``refine=False`` only (the refinement states its own covariance).
    seed : int
        Seed of the bootstrap's random phases (the result is reproducible).
    refine : bool
        Refine poles and residues together by nonlinear least squares on the FRFs in the band
        (:func:`mechdyn.measurement.refine.refine_modes`), which removes the noise bias of LSCF;
        False: the LSCF/LSFD estimates with their order and bootstrap scatter.

    Returns
    -------
    IdentifiedModes

    Notes
    -----
    Poles: sdypy-EMA's LSCF (see the module's sources); stabilisation and grouping: this module. The
    modes found (how many, and the start values) come from the stabilisation chart; with ``refine``
    their frequencies, damping ratios and residues are then those of the output-error least-squares
    fit of the modal model (with lower and upper residuals) to every FRF in the band, and their
    scatter is the standard uncertainty from its parameter covariance (sandwich form under a
    multiplicative-plus-floor noise model estimated from the fit's residual; see
    :mod:`mechdyn.measurement.refine` for the method and its sources). This is the
    maximum-likelihood direction of Guillaume et al. (ISMA 1998) and Peeters et al. (2004, §5): the
    linearised LSCF is biased by noise on H (Pintelon et al., MSSP 21, 2007), the refined fit is
    not; in the tests its errors are within twice the stated scatter in about 95 % of noisy draws.
    The stated scatter covers noise only: a modal model that cannot fit the data (a mode missed in
    the band, nonlinearity, leakage) is not in it; look at ``start_omega`` against ``omega`` and at
    the residual.

    With ``refine=False`` the frequency and damping scatter of the LSCF estimates is the root sum of
    squares of three parts: the standard deviation of the stable poles over the model orders; that
    of the re-identified modes over wild-bootstrap data sets (the fit's residual given random
    phases); and the shift of the bootstrap mean from the estimate, an estimate of the LSCF noise
    bias. The bootstrap sees the bias only once more on top of the biased fit, so it underestimates
    it: in the tests the error of well-damped modes (ζ ≈ 6 %) reaches about 3 times this scatter.
    """
    f = measured.frequencies_hz
    f_lo = float(f[0] if f_min_hz is None else f_min_hz)
    f_hi = float(f[-1] if f_max_hz is None else f_max_hz)
    poles = _poles(measured, max(f_lo, f[1]), f_hi, max_order)
    n_orders = len(poles)
    min_stable = max(5, n_orders // 4) if min_stable is None else int(min_stable)

    order, s_all, status = _stabilise(poles, frequency_tolerance, damping_tolerance, max_damping)
    wn_all = np.abs(s_all)
    z_all = -s_all.real / np.where(wn_all == 0, 1, wn_all)
    chart = StabilisationChart(order, wn_all / (2 * np.pi), z_all, status, measured)
    groups = _groups(order, wn_all, status, frequency_tolerance, min_stable)

    lo = int(np.argmin(np.abs(f - f_lo)))
    hi = int(np.argmin(np.abs(f - f_hi))) + 1
    omega, zeta, d_omega, d_zeta, n_stable, central, samples = [], [], [], [], [], [], []
    for g in groups:
        w, z = wn_all[g], z_all[g]
        omega.append(float(np.median(w)))
        zeta.append(float(np.median(z)))
        d_omega.append(float(np.std(w, ddof=1)) if len(g) > 1 else 0.0)
        d_zeta.append(float(np.std(z, ddof=1)) if len(g) > 1 else 0.0)
        n_stable.append(len(set(order[g])))
        central.append(s_all[g[int(np.argmin(np.abs(w - np.median(w)) / w + np.abs(z - np.median(z)) / z))]])
        samples.append(g)
    n = len(groups)
    if n == 0:
        empty = np.zeros(0)
        return IdentifiedModes(
            empty,
            empty,
            np.zeros((len(measured.outputs), 0), complex),
            np.zeros((len(measured.outputs), len(measured.references), 0), complex),
            empty,
            empty,
            empty,
            np.zeros(0, int),
            measured.outputs,
            measured.references,
            chart,
        )
    residues, fitted = _lsfd(measured, np.array(central), lo, hi)
    shapes = _shapes(residues)
    omega_a, zeta_a = np.array(omega), np.array(zeta)
    if refine:
        from mechdyn.measurement.refine import refine_modes

        try:
            ref = refine_modes(measured, omega_a, zeta_a, lo, hi)
        except (ValueError, np.linalg.LinAlgError):  # too few lines in the band, a singular fit
            ref = None
        if (
            ref is not None
            and ref.converged
            and np.all(np.isfinite(ref.omega_std))
            and np.abs(ref.omega / omega_a - 1.0).max() <= 0.1
        ):
            shapes = _shapes(ref.residues)
            return IdentifiedModes(
                omega=ref.omega,
                damping=ref.damping,
                shapes=shapes,
                residues=ref.residues,
                omega_scatter=ref.omega_std,
                damping_scatter=ref.damping_std,
                shape_scatter=_shape_scatter(measured, shapes, s_all, samples, lo, hi, scatter_samples),
                stable_orders=np.array(n_stable),
                outputs=measured.outputs,
                references=measured.references,
                chart=chart,
                method=(
                    "LSCF poles (sdypy-EMA) refined with the residues by nonlinear least squares on the "
                    "FRFs; scatter from its covariance"
                ),
                start_omega=omega_a,
                start_damping=zeta_a,
            )
    worst_mac = 1.0 - _shape_scatter(measured, shapes, s_all, samples, lo, hi, scatter_samples)
    w_boot, z_boot = np.zeros(n), np.zeros(n)
    w_mean, z_mean = omega_a, zeta_a
    if bootstrap > 1:
        w_mean, z_mean, w_boot, z_boot = _bootstrap(
            measured,
            fitted,
            lo,
            hi,
            omega_a,
            zeta_a,
            bootstrap,
            seed,
            (max(f_lo, f[1]), f_hi, max_order),
            (frequency_tolerance, damping_tolerance, max_damping, min_stable),
        )
    return IdentifiedModes(
        omega=omega_a,
        damping=zeta_a,
        shapes=shapes,
        residues=residues,
        omega_scatter=_rss(d_omega, w_boot, w_mean - omega_a),
        damping_scatter=_rss(d_zeta, z_boot, z_mean - zeta_a),
        shape_scatter=1.0 - worst_mac,
        stable_orders=np.array(n_stable),
        outputs=measured.outputs,
        references=measured.references,
        chart=chart,
        method=(
            "LSCF poles (sdypy-EMA), LSFD residues (not refined); scatter over model orders and bootstrap"
        )
        if not refine
        else "LSCF poles (sdypy-EMA), LSFD residues (the refinement did not converge)",
    )
