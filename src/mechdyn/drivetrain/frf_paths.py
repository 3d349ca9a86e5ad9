"""The ways :func:`mechdyn.drivetrain.frf` computes a forced response, and the choice between them.

* **All modes** (models of up to :data:`FULL_LIMIT` coordinates whose damping does not couple the modes,
  :data:`RAYLEIGH_MODAL_LIMIT` with Rayleigh damping): the exact sum over every mode.
* **The modes below a cut-off with a residual** (larger models with modal damping, or a ``mode_cutoff``
  asked for): every mode up to ``mode_cutoff`` times the top excitation frequency, and the others'
  static response (K⁺ − Σ_kept φφᵀ/λ) F and its ω² term, from one factorisation of K, with a bound on
  what that leaves out.
* **A direct solve at each frequency**: banded (or sparse) where K, C and M are (Rayleigh or no added
  damping, a model's own dampers), dense where modal damping fills C.

Only the coordinates behind the asked outputs are formed, frequency block by frequency block, so memory
is the model's (band) matrices, the kept modes at those coordinates and the output itself.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp

from mechdyn.drivetrain.assembly import Assembly
from mechdyn.drivetrain.banded import band_form, direct_response, static_flexible
from mechdyn.drivetrain.damping import RayleighDamping
from mechdyn.drivetrain.truncation import chain_form, modes_below, rigid_modes, truncation_factor
from mechdyn.errors import ModelError
from mechdyn.units import convert
from mechdyn.vibration.harmonic import finite_response

__all__ = ["FULL_LIMIT", "MODE_CUTOFF", "Response", "respond"]

#: Largest model (coordinates) whose forced response sums all its modes when the damping allows.
FULL_LIMIT = 1000
#: Largest model whose modes may all be computed (n² mode-shape entries) when a larger one needs them.
ALL_MODES_MAX = 6000
#: Largest model (coordinates) with Rayleigh or no added damping whose response sums all its modes under
#: ``method="auto"``; beyond it one banded solve per frequency is cheaper.
RAYLEIGH_MODAL_LIMIT = 200
#: Below this many coordinates the direct solve is dense LAPACK on blocks of frequencies.
DENSE_LIMIT = 200
#: Default multiple of the top excitation frequency up to which modes are kept.
MODE_CUTOFF = 4.0
#: Most mode-shape entries (coordinates × kept modes) the truncated sum may hold (1 GB of float64).
KEPT_ENTRIES = 125_000_000
_BLOCK_ENTRIES = 1 << 18


@dataclass(frozen=True)
class Response:
    """What a path computed.

    Attributes
    ----------
    theta : ndarray
        (n_f, n_rows) complex angles of the wanted degrees of freedom, rad.
    method : str
        How, in words.
    natural_frequencies_hz : ndarray
        The undamped natural frequencies the path found, Hz (all, the kept ones, or none).
    residual : ndarray or None
        (n_rows,) the static stand-in of the left-out modes, rad (None when exact).
    residual_scale : ndarray or None
        (n_f,) the complex factor 1/(1 + iωβ) it enters with at each frequency.
    error_factor : ndarray or None
        (n_f,) e(ω), :func:`mechdyn.drivetrain.truncation.truncation_factor`.
    """

    theta: np.ndarray
    method: str
    natural_frequencies_hz: np.ndarray
    residual: np.ndarray | None = None
    residual_scale: np.ndarray | None = None
    error_factor: np.ndarray | None = None


def modal_sum(
    shapes: np.ndarray,
    lam: np.ndarray,
    c: np.ndarray,
    g: np.ndarray,
    w: np.ndarray,
    residual: np.ndarray | None = None,
    beta: float = 0.0,
    residual2: np.ndarray | None = None,
) -> np.ndarray:
    """X(ω) = Σ_r φ_r g_r/(λ_r − ω² + iωc_r) (+ residual/s + ω² residual2/s², s = 1 + iωβ) at the
    rows of ``shapes``.

    Parameters
    ----------
    shapes : ndarray
        (n_rows, k) M-normalised modes at the wanted rows, rad per unit modal amplitude.
    lam, c : ndarray
        (k,) eigenvalues, (rad/s)², and modal damping, 1/s.
    g : ndarray
        (k,) complex modal loads φ_rᵀF, N·m.
    w : ndarray
        (n_f,) circular frequencies, rad/s.
    residual : ndarray, optional
        (n_rows,) complex static response of the modes left out, Σ φφᵀF/λ, rad.
    beta : float
        The stiffness-proportional damping of the left-out modes, s.
    residual2 : ndarray, optional
        (n_rows,) their next term, Σ φφᵀF/λ², rad·s².

    Returns
    -------
    ndarray
        (n_f, n_rows) complex amplitudes, rad; memory: this output and a block of at most 2¹⁸ modal
        amplitudes. Refuses a response that is not finite, naming the frequency.
    """
    out = np.empty((w.size, shapes.shape[0]), dtype=complex)
    # two real products do half the work of a complex one, worth their extra calls on large sums
    split = lam.size * shapes.shape[0] > 4096
    S = np.ascontiguousarray(shapes.T) if split else shapes.T.astype(complex)
    step = max(1, _BLOCK_ENTRIES // max(1, lam.size, shapes.shape[0]))
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        for lo in range(0, w.size, step):
            wb = w[lo : lo + step, None]
            Y = g / (lam - wb**2 + 1j * wb * c)  # (block, k) modal amplitudes
            block = out[lo : lo + step]
            if split:
                block.real = Y.real @ S
                block.imag = Y.imag @ S
            else:
                np.matmul(Y, S, out=block)
            if residual is not None:
                s = 1.0 + 1j * beta * wb
                block += residual / s
                if residual2 is not None:
                    block += (wb**2 / s**2) * residual2
    return finite_response(out, w)


def rayleigh_part(asm: Assembly) -> tuple[float, float] | None:
    """(α, β) with the model's own C = α M + β K (1/s, s), (0, 0) without dampers; None otherwise.

    Parameters
    ----------
    asm : Assembly
    """
    C = asm.C
    if not C.nnz or not np.any(C.data):
        return 0.0, 0.0
    M = asm.mass_operator()
    A = np.column_stack([sp.csr_array(M).diagonal(), asm.K.diagonal()])
    scale = np.abs(A).max(axis=0)
    scale[scale == 0] = 1.0
    coef = np.linalg.lstsq(A / scale, C.diagonal(), rcond=None)[0] / scale
    alpha, beta = float(coef[0]), float(coef[1])
    misfit = abs(sp.csr_array(C - alpha * M - beta * asm.K)).max() if C.nnz else 0.0
    if alpha >= 0 and beta >= 0 and misfit <= 1e-10 * abs(C).max():
        return alpha, beta
    return None


def full_basis(
    asm: Assembly, modes: Any, damping: Any, zeta: np.ndarray | None
) -> tuple[np.ndarray, np.ndarray, np.ndarray] | str:
    """All n M-normalised modes on the reduced coordinates (rigid-body ones first), their eigenvalues
    (rad/s)² and modal damping (1/s); or, where summing them would not be exact, why not.

    The rigid-body modes are the assembly's exact rigid motions, M-orthonormalised; the flexible ones
    the eigen solver's. Two random probes check ΦᵀMΦ = I (a set that is not complete or not
    orthonormal would give a wrong sum) at O(n²) cost; the model's own dampers are carried to the modes
    and must come out diagonal.
    """

    n, n_rb = asm.n, asm.n_rigid_body
    if modes.omega.size + n_rb != n:
        return f"{modes.omega.size + n_rb} of {n} modes"
    P = np.hstack([rigid_modes(asm), modes.reduced_shapes]) if n_rb else modes.reduced_shapes
    lam = np.concatenate([np.zeros(n_rb), modes.omega**2])
    probe = _probe(n)
    misfit = P.T @ asm.mass_times(P @ probe) - probe
    if not np.all(np.abs(misfit) <= 1e-9 * np.abs(probe).max()):
        return "the modes are not orthonormal to 1e-9"
    c = np.zeros(n)
    if asm.C.nnz and np.any(asm.C.data):
        Cm = P.T @ (asm.C @ P)
        off = Cm - np.diag(np.diag(Cm))
        if np.abs(off).max() > 1e-10 * np.abs(Cm).max():
            return "the model's own dampers couple the modes"
        c += np.diag(Cm)
    if isinstance(damping, RayleighDamping):
        c += damping.alpha + damping.beta * lam
    else:
        assert zeta is not None  # modal damping has its ratios
        c[n_rb:] += 2 * zeta * modes.omega
    return P, lam, c


@functools.lru_cache(maxsize=8)
def _probe(n: int) -> np.ndarray:
    """Two fixed random vectors of length n (read-only), to probe ΦᵀMΦ = I."""
    out = np.random.default_rng(0).standard_normal((n, 2))
    out.flags.writeable = False
    return out


def _with_modal_damping(asm: Assembly, modes: Any, zeta: np.ndarray) -> np.ndarray:
    """C + M Φ diag(2 ζ_r ω_r) Φᵀ M over the flexible modes: full, modal damping couples every disk."""
    MPhi = asm.mass_times(modes.reduced_shapes)
    return np.asarray(asm.C.toarray() + (MPhi * (2 * zeta * modes.omega)) @ MPhi.T)


def _dense_direct(K: Any, C: Any, M: Any, F: np.ndarray, w: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """Rows of X(ω) by dense LAPACK on blocks of frequencies (small models, or a full C)."""
    from mechdyn.drivetrain.banded import singular_error

    K, C, M = (A.toarray() if sp.issparse(A) else np.asarray(A, dtype=float) for A in (K, C, M))
    n = F.size
    out = np.empty((w.size, rows.size), dtype=complex)
    step = max(1, _BLOCK_ENTRIES // (n * n))
    for lo in range(0, w.size, step):
        wb = w[lo : lo + step, None, None]
        Z = K[None] + (1j * wb) * C[None] - wb**2 * M[None]
        try:
            X = np.linalg.solve(Z, np.broadcast_to(F[:, None], (Z.shape[0], n, 1)))[..., 0]
        except np.linalg.LinAlgError:
            for i in range(Z.shape[0]):
                try:
                    np.linalg.solve(Z[i], F)
                except np.linalg.LinAlgError:
                    raise singular_error(float(w[lo + i])) from None
            raise  # pragma: no cover - a batch fails only where one of its matrices does
        out[lo : lo + step] = X[:, rows]
    return out


def _direct(asm: Assembly, C: Any, F: np.ndarray, w: np.ndarray, rows: np.ndarray, why: str) -> Response:
    M = asm.mass_operator()
    if sp.issparse(C) and asm.n > DENSE_LIMIT:
        form = band_form(asm.K, C, M)
        theta = direct_response(asm.K, C, M, F, w, rows, form)
        how = "banded" if form is not None else "sparse"
        label = f"direct solve at each frequency ({why}; {how}, {asm.n} coordinates)"
    else:
        theta = _dense_direct(asm.K, C, M, F, w, rows)
        label = f"direct solve at each frequency ({why})"
    return Response(finite_response(theta, w), label, np.zeros(0))


def respond(
    asm: Assembly,
    F: np.ndarray,
    w: np.ndarray,
    rows: np.ndarray,
    amps: np.ndarray,
    damping: Any,
    zeta: np.ndarray | None,
    method: str,
    cutoff: float | None,
) -> Response:
    """The response at the wanted rows by the path that suits the model, damping and method.

    Parameters
    ----------
    asm : Assembly
    F : ndarray
        (n,) complex loads on the reduced coordinates, N·m.
    w : ndarray
        (n_f,) circular frequencies, rad/s.
    rows, amps : ndarray
        The reduced coordinate of each wanted degree of freedom and its factor (θ = amp · q).
    damping : ModalDamping or RayleighDamping
        The added damping; ``zeta`` its ratios per flexible mode (modal damping) or None.
    method : {"auto", "modal", "direct"}
    cutoff : float or None
        Multiple of the top frequency up to which modes are kept in a truncated sum; None: all modes
        for a model of up to :data:`FULL_LIMIT` coordinates, else :data:`MODE_CUTOFF`.

    Returns
    -------
    Response
        ``theta`` already scaled by ``amps``.
    """
    from mechdyn.drivetrain.modal import modal

    n = asm.n
    rayleigh = isinstance(damping, RayleighDamping)
    small = n <= FULL_LIMIT
    # Rayleigh (or no) added damping keeps C banded: one banded solve per frequency is exact, and
    # beyond a few hundred coordinates cheaper than the modes
    if (
        rayleigh
        and cutoff is None
        and (method == "direct" or (method == "auto" and n > RAYLEIGH_MODAL_LIMIT))
    ):
        C = asm.C + damping.alpha * asm.mass_operator() + damping.beta * asm.K
        if method == "direct":
            r = _direct(asm, C, F, w, rows, "as asked")
            return _scaled(r, amps, _natural(asm) if small else np.zeros(0))
        why = (
            "the model's own dampers couple the modes"
            if rayleigh_part(asm) is None
            else f"Rayleigh damping keeps K, C and M banded: cheaper than the {n} modes"
        )
        return _scaled(
            _direct(asm, C, F, w, rows, why), amps, natural_frequencies(asm) if small else np.zeros(0)
        )
    if method == "direct":
        assert zeta is not None
        modes = _all_modes(asm, "a direct solve with modal damping")
        r = _direct(asm, _with_modal_damping(asm, modes, zeta), F, w, rows, "as asked")
        return _scaled(r, amps, modes.frequencies_hz)
    if small and cutoff is None:
        modes = modal(asm)
        basis = full_basis(asm, modes, damping, zeta)
        if isinstance(basis, str):
            if method == "modal":
                raise ModelError(
                    f"modal superposition is not exact here: {basis}; use method='direct' (or 'auto')",
                    element="frf",
                    field="method",
                )
            C = (
                asm.C + damping.alpha * asm.mass_operator() + damping.beta * asm.K
                if rayleigh
                else _with_modal_damping(asm, modes, zeta)  # type: ignore[arg-type]
            )
            return _scaled(_direct(asm, C, F, w, rows, basis), amps, modes.frequencies_hz)
        P, lam, c = basis
        theta = modal_sum(P[rows] * amps[:, None], lam, c, P.T @ F, w)
        return Response(theta, f"modal superposition over all {lam.size} modes", modes.frequencies_hz)
    # a large model (or a cut-off asked for): never all its modes at once
    own = rayleigh_part(asm)
    if own is None:  # its own dampers are not of Rayleigh form: they may couple the modes
        if method == "modal":
            raise ModelError(
                "modal superposition is not exact here: the model's own dampers are not proportional "
                "(C ≠ αM + βK) and may couple the modes; use method='direct' (or 'auto')",
                element="frf",
                field="method",
            )
        why = "the model's own dampers couple the modes"
        if rayleigh:
            C = asm.C + damping.alpha * asm.mass_operator() + damping.beta * asm.K
            return _scaled(
                _direct(asm, C, F, w, rows, why), amps, natural_frequencies(asm) if small else np.zeros(0)
            )
        assert zeta is not None
        modes = _all_modes(asm, "modal damping on a model whose own dampers couple the modes")
        r = _direct(asm, _with_modal_damping(asm, modes, zeta), F, w, rows, why)
        return _scaled(r, amps, modes.frequencies_hz)
    return _truncated(asm, F, w, rows, amps, damping, zeta, own, MODE_CUTOFF if cutoff is None else cutoff)


def natural_frequencies(asm: Assembly) -> np.ndarray:
    """The flexible natural frequencies alone (no shapes), Hz: the eigenvalues of the band of
    M^-½ K M^-½ (LAPACK ``dsbevd`` through :func:`scipy.linalg.eig_banded`, O(n² b)) where M is
    diagonal and the band narrow, else of the dense pencil.

    Parameters
    ----------
    asm : Assembly
    """
    import scipy.linalg as sla

    n_rb = asm.n_rigid_body
    form = band_form(asm.K, sp.csr_array(asm.K.shape), asm.mass_operator())
    if asm.mass_diagonal is not None and form is not None:
        b = form.band
        d = 1.0 / np.sqrt(asm.mass_diagonal[form.perm])
        lower = form.K[b:].copy()  # row i: A[j + i, j] at column j
        for i in range(b + 1):
            lower[i, : d.size - i] *= d[i:] * d[: d.size - i]
        lam = sla.eig_banded(lower, lower=True, eigvals_only=True, check_finite=False)
    else:
        lam = sla.eigh(asm.K.toarray(), asm.mass_operator().toarray(), eigvals_only=True)
    return np.sqrt(np.clip(np.sort(lam)[n_rb:], 0.0, None)) / (2 * np.pi)


def _scaled(r: Response, amps: np.ndarray, natural: np.ndarray) -> Response:
    return Response(r.theta * amps, r.method, natural)


def _natural(asm: Assembly) -> np.ndarray:
    from mechdyn.drivetrain.modal import modal

    return modal(asm).frequencies_hz


def _all_modes(asm: Assembly, what: str) -> Any:
    from mechdyn.drivetrain.modal import modal

    if asm.n > ALL_MODES_MAX:
        shapes = convert(asm.n**2 * 8, "byte", "gigabyte")
        raise ModelError(
            f"{what} needs all {asm.n} modes ({shapes:.3g} GB of shapes, more than the "
            f"{ALL_MODES_MAX}-coordinate limit); give RayleighDamping (solved banded, frequency by "
            "frequency) or lower the frequency range",
            element="frf",
            field="damping",
        )
    return modal(asm)


def _truncated(
    asm: Assembly,
    F: np.ndarray,
    w: np.ndarray,
    rows: np.ndarray,
    amps: np.ndarray,
    damping: Any,
    zeta: np.ndarray | None,
    own: tuple[float, float],
    cutoff: float,
) -> Response:
    """Every mode up to ``cutoff`` × the top frequency, and the others' static response."""

    n, n_rb = asm.n, asm.n_rigid_body
    M = asm.mass_operator()
    alpha, beta = own
    if isinstance(damping, RayleighDamping):
        alpha, beta = alpha + damping.alpha, beta + damping.beta
    w_cut = cutoff * float(w.max())
    lam_cut = w_cut**2
    form = band_form(asm.K, asm.C, M)
    limit = max(1, min((n - n_rb) // 2, KEPT_ENTRIES // n))
    found = modes_below(asm, lam_cut, chain_form(asm, form), form, limit)
    if found is None:
        if n <= ALL_MODES_MAX:  # most modes are wanted: all of them is cheaper and exact
            modes = _all_modes(asm, "")
            basis = full_basis(asm, modes, damping, zeta)
            if not isinstance(basis, str):
                P, lam, c = basis
                theta = modal_sum(P[rows] * amps[:, None], lam, c, P.T @ F, w)
                return Response(theta, f"modal superposition over all {lam.size} modes", modes.frequencies_hz)
        raise ModelError(
            f"the frequencies reach {w.max() / (2 * np.pi):.4g} Hz, and more than {limit} of the model's "
            f"{n} modes lie below {cutoff:g} × that; give RayleighDamping (solved banded, frequency by "
            "frequency), a lower frequency range or a smaller mode_cutoff",
            element="frf",
            field="frequencies_hz",
        )
    lam, Phi = found
    k = lam.size
    omega = np.sqrt(np.clip(lam, 0.0, None))
    c = alpha + beta * lam
    zeta_rest = 0.0
    if zeta is not None:
        c = c + 2 * zeta[:k] * omega
        zeta_rest = float(zeta[k:].max()) if zeta.size > k else 0.0
    R = rigid_modes(asm)
    # the left-out modes' static response Σ φφᵀF/λ and its next term Σ φφᵀF/λ² (the flexible
    # flexibility applied twice), each the flexible static solve less the kept modes' part
    x_static = static_flexible(asm.K, M, R, F, form)
    x_static2 = static_flexible(asm.K, M, R, asm.mass_times(x_static), form)
    g = Phi.T @ F
    inv = 1.0 / np.where(lam > 0, lam, np.inf)
    residual = x_static - Phi @ (g * inv)
    residual2 = x_static2 - Phi @ (g * inv**2)
    shapes = np.hstack([R[rows], Phi[rows]]) * amps[:, None]
    lam_all = np.concatenate([np.zeros(n_rb), lam])
    c_all = np.concatenate([np.full(n_rb, alpha), c])
    g_all = np.concatenate([R.T @ F, g])
    res_rows = residual[rows] * amps
    theta = modal_sum(shapes, lam_all, c_all, g_all, w, res_rows, beta, residual2[rows] * amps)
    left = n - n_rb - k
    method = (
        f"modal superposition over the {k} flexible modes up to {cutoff:g} × the top frequency "
        f"({w_cut / (2 * np.pi):.4g} Hz), with the residual of the other {left} (static and ω² terms)"
    )
    return Response(
        theta,
        method,
        omega / (2 * np.pi),
        res_rows,
        1.0 / (1.0 + 1j * beta * w),
        truncation_factor(w, lam_cut, beta, alpha, zeta_rest),
    )
