"""Steady-state response to harmonic torques (frequency response) with modal or Rayleigh damping.

:func:`frf` checks its inputs and picks the outputs; the ways of computing the response (all modes, the
modes below a cut-off with a static residual, a banded or dense direct solve) are
:mod:`mechdyn.drivetrain.frf_paths`.
"""

from __future__ import annotations

import itertools
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
import scipy.sparse as sp

from mechdyn.checks import check_array, check_number
from mechdyn.drivetrain.assembly import assemble
from mechdyn.drivetrain.damping import ModalDamping, RayleighDamping
from mechdyn.drivetrain.frf_paths import respond
from mechdyn.drivetrain.model import Drivetrain
from mechdyn.errors import ModelError, ModelWarning
from mechdyn.results import Result, Table
from mechdyn.units import si_field

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["TRUNCATION_TOLERANCE", "FRFResult", "ModalDamping", "RayleighDamping", "frf"]

#: Estimated relative error of a truncated modal sum above which :func:`frf` warns.
TRUNCATION_TOLERANCE = 1e-2


@dataclass(frozen=True, repr=False)  # the short repr of Result
class FRFResult(Result):
    """Steady-state complex amplitudes over frequency.

    Attributes
    ----------
    frequencies_hz : ndarray
        (n_f,) excitation frequencies, Hz.
    disk_names : tuple of str
        The disks, then the nodes inside divided shafts (:attr:`Drivetrain.dof_names`); only those
        selected where :func:`frf` was given ``select``.
    angles : ndarray
        (n_f, n_dofs) complex disk (and shaft node) angle amplitudes, rad (θ(t) = Re[Θ e^{iωt}]).
    element_names : tuple of str
        The elements that carry a load (only those selected where ``select`` was given).
    element_loads : ndarray
        (n_f, n_elements) complex internal loads: shaft torque (N·m), mesh force (N), grounded spring
        torque (N·m); see ``element_units``.
    element_units : tuple of str
    natural_frequencies_hz : ndarray
        Undamped natural frequencies of the model, Hz, for reference: all of them, or where a large
        model's response summed the modes below a cut-off those modes, or (a large model solved
        directly, its modes never computed) none.
    model_name : str
    excitation : mapping of disk name → complex torque amplitude, N·m
    damping : ModalDamping or RayleighDamping or None
        The damping added to the model's own dampers.
    outputs : tuple of str
        The disks to report and plot (all disks when empty).
    method : str
        How the response was computed: modal superposition over all modes, over the modes below a
        cut-off with the static residual of the others (and the estimated error), or a direct solve
        at each frequency and why.
    drivetrain : Drivetrain or None
        The model, for its table as assembled.
    truncation_error : float
        Estimated error of the modes left out, relative to the largest amplitude of each output,
        the worst output's (0 where every mode was summed or the response solved directly).
    """

    frequencies_hz: np.ndarray
    disk_names: tuple[str, ...]
    angles: np.ndarray
    element_names: tuple[str, ...]
    element_loads: np.ndarray
    element_units: tuple[str, ...]
    natural_frequencies_hz: np.ndarray
    model_name: str = ""
    excitation: Mapping[str, complex] = field(default_factory=dict)
    damping: Any = None
    outputs: tuple[str, ...] = ()
    method: str = ""
    drivetrain: Drivetrain | None = None
    truncation_error: float = 0.0

    @property
    def peaks(self) -> dict[str, dict[str, Any]]:
        """For each output disk and each element: largest amplitude, its unit and frequency (Hz)."""
        out = {}
        for n in (*(self.outputs or self.disk_names), *self.element_names):
            amp, at = self.peak(n)
            unit = "rad" if n in self.disk_names else self.element_units[self.element_names.index(n)]
            out[n] = {"peak": amp, "unit": unit, "frequency_hz": at}
        return out

    def summary(self) -> dict[str, Any]:
        """Excitation, frequency range (Hz), damping, method (with the estimated truncation error where
        modes were left out), natural frequencies (Hz) and the peaks."""
        f = self.frequencies_hz
        return {
            "excitation": {
                k: {"re": complex(v).real, "im": complex(v).imag} for k, v in self.excitation.items()
            },
            "frequency_range_hz": [float(f.min()), float(f.max())],
            "points": int(f.size),
            "damping": repr(self.damping),
            "method": self.method,
            "natural_frequencies_hz": self.natural_frequencies_hz.tolist(),
            "peaks": self.peaks,
        }

    def tables(self, **display_units: str) -> list[Table]:
        """The resonance peak of every output and element (see :meth:`peak`); the model as assembled."""
        from mechdyn.drivetrain.summary import model_table

        shown = {"N*m": "N·m"}
        rows = [
            [
                ("disk " if p["unit"] == "rad" else "") + n,
                p["peak"],
                shown.get(p["unit"], p["unit"]),
                p["frequency_hz"],
            ]
            for n, p in self.peaks.items()
        ]
        return [
            Table(
                "resonance peaks: largest local maximum of each amplitude over the frequency range",
                ["output", "peak", "unit", "at [Hz]"],
                rows,
                note=f"Computed by {self.method}." if self.method else "",
            ),
            *([model_table(self.drivetrain)] if self.drivetrain is not None else []),
        ]

    def plots(self, **display_units: str) -> dict[str, Any]:
        """``frf.png``: the output disks' angles; ``frf_torques.png`` and ``frf_mesh_forces.png``: the
        shaft torques and mesh forces (what a drivetrain is sized on); magnitude and phase each."""
        from mechdyn.drivetrain.plots import plot_frf, plot_frf_loads

        out: dict[str, Any] = {"frf.png": lambda: plot_frf(self, outputs=list(self.outputs) or None)}
        if "N*m" in self.element_units:
            out["frf_torques.png"] = lambda: plot_frf_loads(self, "N*m")
        if "N" in self.element_units:
            out["frf_mesh_forces.png"] = lambda: plot_frf_loads(self, "N")
        return out

    def arrays(self) -> dict[str, tuple[np.ndarray, str]]:
        """Frequencies (Hz), complex disk angles (rad) and element loads (N·m or N)."""
        return {
            "frequencies_hz": (self.frequencies_hz, "Hz"),
            "angles": (self.angles, "rad"),
            "element_loads": (self.element_loads, "N*m | N"),
        }

    def peak(self, name: str) -> tuple[float, float]:
        """The resonance peak of a disk angle or element load: the largest local maximum of its
        magnitude over the frequency range, and its frequency (Hz). Where the magnitude has no
        local maximum (it only falls or only rises), its largest value at either end of the range.

        The rigid-body motion of a free drivetrain is largest at the lowest frequency and falls
        from there; it is not a resonance and is not reported as the peak.

        Parameters
        ----------
        name : str
            A disk (its angle, rad) or an element (its load, N·m or N).
        """
        if name in self.disk_names:
            y = np.abs(self.angles[:, self.disk_names.index(name)])
        elif name in self.element_names:
            y = np.abs(self.element_loads[:, self.element_names.index(name)])
        else:
            raise KeyError(name)
        inner = np.flatnonzero((y[1:-1] > y[:-2]) & (y[1:-1] >= y[2:])) + 1  # local maxima
        i = int(inner[np.argmax(y[inner])]) if inner.size else int(np.argmax(y))
        return float(y[i]), float(self.frequencies_hz[i])

    def to_frame(self) -> pd.DataFrame:
        """Magnitudes over frequency: one column per disk (rad) and element (its unit)."""
        import pandas as pd

        suffix = {"rad": "rad", "N*m": "Nm", "N": "N"}
        cols: dict[str, Any] = {"frequency_hz": self.frequencies_hz}
        for j, n in enumerate(self.disk_names):
            cols[f"disk_{n}_rad"] = np.abs(self.angles[:, j])
        for j, (n, u) in enumerate(zip(self.element_names, self.element_units, strict=True)):
            cols[f"{n}_{suffix.get(u, u)}"] = np.abs(self.element_loads[:, j])
        return pd.DataFrame(cols)

    def plot(self, outputs: Sequence[str] | None = None, ax: Any = None, **display_units: Any) -> Any:
        """Plot magnitudes against frequency (log scale); returns the matplotlib Figure.

        Parameters
        ----------
        outputs : sequence of str, optional
            Disks and elements to draw (default: every disk).
        ax : matplotlib.axes.Axes, optional
            Axes to draw on (default: a new figure).
        **display_units : str
            Display units (unused: angles in rad, loads in N·m or N).
        """
        from mechdyn.drivetrain.plots import plot_frf

        return plot_frf(self, outputs=outputs, ax=ax)


def frf(
    drivetrain: Drivetrain,
    frequencies_hz: Sequence[float] | np.ndarray,
    excitation: Mapping[str, Any],
    *,
    damping: ModalDamping | RayleighDamping | None = None,
    outputs: Sequence[str] = (),
    method: Method = "auto",
    select: Sequence[str] | None = None,
    mode_cutoff: float | None = None,
    tolerance: float = TRUNCATION_TOLERANCE,
) -> FRFResult:
    """Steady-state response of a drivetrain to harmonic torques.

    Parameters
    ----------
    drivetrain : Drivetrain
    frequencies_hz : array_like
        Excitation frequencies, Hz, finite, from 0 to 1e7 Hz.
    excitation : mapping of disk name → torque amplitude
        Complex amplitudes in N·m (or quantities, e.g. ``"10 N*m"``), all at the same frequency,
        finite and at most 1e11 N·m in magnitude.
    damping : ModalDamping or RayleighDamping, optional
        Added to the model's own dampers; default ``ModalDamping(0.02)``.
    outputs : sequence of str
        Disks to report and plot (default: all).
    method : {"auto", "modal", "direct"}
        ``"auto"`` sums the modes where that is exact and cheaper, and solves directly otherwise;
        ``"modal"`` insists on the modes (a :class:`~mechdyn.errors.ModelError` says why where they
        cannot carry the damping); ``"direct"`` solves at each frequency. :attr:`FRFResult.method`
        says which ran.
    select : sequence of str, optional
        The disks (or shaft nodes) whose angles and the elements whose loads are computed and kept,
        by name, with the disks of ``outputs``; default: every disk and every element. A large model
        needs only these rows: memory is then n_f × len(select), not n_f × n.
    mode_cutoff : float, optional
        Sum only the modes up to this multiple of the top excitation frequency, the others entering
        by their residual (at least 1.5). Default: all modes for a model of up to 1000 coordinates;
        a larger one's modal sum keeps those up to 4 × the top frequency
        (:data:`mechdyn.drivetrain.frf_paths.MODE_CUTOFF`).
    tolerance : float
        A :class:`~mechdyn.errors.ModelWarning` is given where the estimated error of that
        truncation, relative to the largest amplitude of an output, is above this (default 1e-2).

    Returns
    -------
    FRFResult

    Notes
    -----
    The response solves (K + iω C − ω² M) Q = Tᵀ F on the reduced coordinates and recovers every
    disk as Θ = T Q. Modal damping adds C_m = M Φ diag(2 ζ_r ω_r) Φᵀ M over the M-normalised flexible
    modes Φ (e.g. Craig & Kurdila, *Fundamentals of Structural Dynamics*, 2nd ed., 2006, §10.4).

    Where the damping does not couple the modes — modal damping or Rayleigh damping added to a model
    whose own dampers are absent or proportional (ΦᵀCΦ diagonal to 1e-10) — a model of up to 1000
    coordinates (200 with Rayleigh damping) sums over all n modes, rigid-body ones included: exact,
    and n_f · n · n_out operations instead of n_f dense solves of n³/3. Otherwise (a damper between
    two disks of a chain with modal damping on top, say) it is solved frequency by frequency.

    A larger model is never solved through all its modes where something cheaper is exact:

    * Rayleigh (or no added) damping, or own dampers that couple the modes: K, C and M stay banded
      (tridiagonal for a chain), and one banded solve per frequency costs O(n) (LAPACK ``zgtsv`` /
      ``zgbsv`` in reverse Cuthill–McKee order; SuperLU where the band is wide).
    * Modal damping (C_m is full): the flexible modes up to ``mode_cutoff`` × the top frequency
      (bisection and inverse iteration on a chain's tridiagonal M^-½ K M^-½, else shift-invert
      Lanczos), and the static response of all the others, x_res = (K⁺ − Σ_kept φφᵀ/λ) F from one
      factorisation of K with a coordinate of each free branch held (the mode-acceleration or
      residual-flexibility correction; Craig & Kurdila, §11.3). Each left-out mode's term
      1/(λ_r − ω² + iωc_r) is replaced by 1/(λ_r(1 + iωβ)); the relative error of that is at most
      e(ω) = (ρ² + 2ζρ + αω/λ_c)/(abs(1 + iωβ) − ρ² − 2ζρ − αω/λ_c), ρ = ω/ω_c, and the result's
      :attr:`FRFResult.truncation_error` is max e(ω)·abs(x_res(ω)) over the largest amplitude, over
      every output (an estimate: the left-out modes' static terms are taken to add up, not cancel).

    Only the coordinates behind ``select`` are formed, frequency block by frequency block: memory is
    the model's band matrices, the kept modes and the output, never n_f × n or n × n.
    """
    damping = ModalDamping() if damping is None else damping
    asm = assemble(drivetrain)
    f = np.atleast_1d(
        check_array("frf", "frequencies_hz", frequencies_hz, "Hz", nonnegative=True, what="frequencies")
    )
    if f.ndim != 1:
        raise ModelError(
            "frequencies must be a 1-D list of non-negative values in Hz",
            element="frf",
            field="frequencies_hz",
        )
    cutoff = (
        None
        if mode_cutoff is None
        else check_number("frf", "mode_cutoff", mode_cutoff, low=1.5, high=1e6, what="multiple")
    )
    tolerance = check_number("frf", "tolerance", tolerance, low=0.0, high=1.0, low_open=True)
    idx = drivetrain.disk_index
    force = np.zeros(len(drivetrain.dof_names), dtype=complex)
    for disk, amp in excitation.items():
        if disk not in idx:
            raise ModelError(
                f"excitation at disk {disk!r}, which is not defined; defined disks: {_some(idx)}"
            )
        field = f"excitation[{disk!r}]"
        if isinstance(amp, complex | np.complexfloating):
            force[idx[disk]] += complex(
                check_array("frf", field, amp, "N*m", complex_values=True, what="torques")
            )
        else:
            force[idx[disk]] += si_field("frf", field, amp, "N*m", what="torque amplitude")
    zeta = _modal_ratios(damping, asm.n - asm.n_rigid_body)
    w = 2 * np.pi * f
    if asm.n_rigid_body and np.any(w == 0):
        raise ModelError(
            "a free drivetrain has no static response at 0 Hz; start the frequencies above 0",
            element="frf",
            field="frequencies_hz",
        )
    if method not in ("auto", "modal", "direct"):
        raise ModelError(
            f"method {method!r}: give 'auto', 'modal' or 'direct'", element="frf", field="method"
        )
    dof_rows, element_rows = _selection(drivetrain, select, outputs)
    names, units, L, L_rate = drivetrain._load_table
    if element_rows is not None and element_rows.size < len(names):
        names = tuple(names[i] for i in element_rows)
        units = tuple(units[i] for i in element_rows)
        L, L_rate = (sp.csr_array(A[element_rows]) for A in (L, L_rate)) if names else (None, None)
    # the degrees of freedom behind the outputs and the loads (sorted), and their reduced coordinates
    needed = (
        np.unique(np.concatenate([dof_rows, L.indices, L_rate.indices]) if L is not None else dof_rows)
        if select is not None
        else dof_rows
    ).astype(np.intp)
    whole = needed.size == len(drivetrain.dof_names)  # every degree of freedom, in order
    T = asm.T
    if T.shape[0] == T.shape[1]:  # no rigid mesh: T = I
        coordinate, factor, F = needed, np.ones(needed.size), force
    else:
        coordinate, factor = T.indices[T.indptr[needed]], T.data[T.indptr[needed]]
        F = np.asarray(T.T @ force)
    # a response that is not finite (an undamped resonance, a free drivetrain near 0 Hz) is refused,
    # naming the frequency
    r = respond(asm, F, w, coordinate, factor, damping, zeta, method, cutoff)
    at = dof_rows if whole else np.searchsorted(needed, dof_rows)
    theta = r.theta if whole and np.array_equal(at, needed) else r.theta[:, at]
    if L is None or L_rate is None:
        loads = np.zeros((w.size, 0), dtype=complex)
    else:
        if not whole:
            L, L_rate = _on(L, needed), _on(L_rate, needed)
        loads = np.asarray((L @ r.theta.T).T)
        if L_rate.nnz:
            loads = loads + 1j * w[:, None] * np.asarray((L_rate @ r.theta.T).T)
    error = 0.0
    method_text = r.method
    if r.residual is not None:
        error = _truncation_estimate(r, theta, loads, at, L, L_rate, w)
        method_text += f"; estimated truncation error {error:.2g} (relative)"
        if error > tolerance:
            warnings.warn(
                f"frf of {drivetrain.name!r}: the modes left out above the cut-off may "
                f"change the response by up to {error:.2g} of its largest amplitude (tolerance "
                f"{tolerance:g}); raise mode_cutoff, or give method='direct' with RayleighDamping",
                ModelWarning,
                stacklevel=2,
            )
    dof_names = drivetrain.dof_names
    return FRFResult(
        f,
        dof_names if select is None else tuple(dof_names[i] for i in dof_rows),
        theta,
        names,
        loads,
        units,
        r.natural_frequencies_hz,
        drivetrain.name,
        {d: complex(force[idx[d]]) for d in excitation},
        damping,
        tuple(outputs),
        method_text,
        drivetrain,
        error,
    )


Method = Literal["auto", "modal", "direct"]


def _some(names: Mapping[str, int] | Sequence[str], most: int = 20) -> str:
    """The names for a message: all of them, or the first ``most`` and how many more."""
    shown = list(itertools.islice(iter(names), most))
    rest = len(names) - len(shown)
    return ", ".join(shown) + (f", … ({rest} more)" if rest > 0 else "")


def _on(A: sp.csr_array, columns: np.ndarray) -> sp.csr_array:
    """The rows A with their columns renumbered to positions in ``columns`` (which holds them all)."""
    return sp.csr_array(
        (A.data, np.searchsorted(columns, A.indices), A.indptr), shape=(A.shape[0], columns.size)
    )


def _selection(
    drivetrain: Drivetrain, select: Sequence[str] | None, outputs: Sequence[str]
) -> tuple[np.ndarray, np.ndarray | None]:
    """The degrees of freedom (positions in :attr:`Drivetrain.dof_names`) and the elements (rows of
    the load table) to compute; None for the elements means all of them."""
    if select is None:
        return np.arange(len(drivetrain.dof_names)), None
    if isinstance(select, str):
        select = (select,)
    dofs = drivetrain.dof_index
    elements = drivetrain._load_index
    dof_rows: list[int] = []
    element_rows: list[int] = []
    for name in (*select, *outputs):
        if name in dofs:
            if dofs[name] not in dof_rows:
                dof_rows.append(dofs[name])
        elif name in elements:
            if elements[name] not in element_rows:
                element_rows.append(elements[name])
        else:
            raise ModelError(
                f"select names {name!r}, which is neither a disk nor an element with a load; disks: "
                f"{_some(dofs)}; elements: {_some(elements)}",
                element="frf",
                field="select",
            )
    return np.array(dof_rows, dtype=np.intp), np.array(element_rows, dtype=np.intp)


def _truncation_estimate(
    r: Any,
    theta: np.ndarray,
    loads: np.ndarray,
    at: np.ndarray,
    L: Any,
    L_rate: Any,
    w: np.ndarray,
) -> float:
    """max over outputs of max_ω e(ω)·|residual part| / max_ω |output| (see :func:`frf`)."""
    e = r.error_factor * np.abs(r.residual_scale)
    worst = 0.0
    res = r.residual[at]
    with np.errstate(invalid="ignore"):
        if res.size:
            top = np.abs(theta).max(axis=0)
            part = np.max(e[:, None] * np.abs(res)[None, :], axis=0)
            worst = max(worst, float(np.max(np.where(top > 0, part / np.where(top > 0, top, 1.0), 0.0))))
        if loads.shape[1]:
            a, b = L @ r.residual, L_rate @ r.residual
            top = np.abs(loads).max(axis=0)
            step = max(1, (1 << 18) // max(1, a.size))
            part = np.zeros(a.size)
            for lo in range(0, w.size, step):
                wb = w[lo : lo + step, None]
                part = np.maximum(part, np.max(e[lo : lo + step, None] * np.abs(a + 1j * wb * b), axis=0))
            worst = max(worst, float(np.max(np.where(top > 0, part / np.where(top > 0, top, 1.0), 0.0))))
    return worst if np.isfinite(worst) else float("inf")


def _modal_ratios(damping: ModalDamping | RayleighDamping, n_flexible: int) -> np.ndarray | None:
    """ζ for every flexible mode (None for Rayleigh damping), refusing a count that does not match."""
    if isinstance(damping, RayleighDamping):
        return None
    zeta = np.atleast_1d(np.asarray(damping.ratio, dtype=float))
    if zeta.size == 1:
        return np.full(n_flexible, zeta[0])
    if zeta.size != n_flexible:
        raise ModelError(
            f"{zeta.size} modal damping ratios given for {n_flexible} flexible modes",
            element="modal damping",
            field="ratio",
        )
    return zeta
