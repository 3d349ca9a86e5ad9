"""Steady-state response to harmonic torques (frequency response) with modal or Rayleigh damping."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
import scipy.sparse as sp

from mechdyn.checks import check_array, check_number
from mechdyn.drivetrain.assembly import Assembly, assemble
from mechdyn.drivetrain.modal import ModalResult, modal
from mechdyn.drivetrain.model import Drivetrain
from mechdyn.errors import ModelError
from mechdyn.results import Result, Table
from mechdyn.units import si_field
from mechdyn.vibration.harmonic import harmonic_solve, modal_superposition

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["FRFResult", "ModalDamping", "RayleighDamping", "frf"]


@dataclass(frozen=True)
class ModalDamping:
    """Viscous damping ratio ζ for every flexible mode (or one per mode, lowest first).

    Parameters
    ----------
    ratio : float or sequence of float
        ζ, dimensionless, in [0, 1): one for all flexible modes, or one per mode from the lowest.
    """

    ratio: float | tuple[float, ...] = 0.02

    def __post_init__(self) -> None:
        try:
            r = np.asarray(self.ratio, dtype=float)
        except (TypeError, ValueError):
            raise ModelError(
                f"{self.ratio!r} is not a number; give modal damping ratios in [0, 1)",
                element="modal damping",
                field="ratio",
            ) from None
        bad = ~(np.isfinite(r) & (r >= 0) & (r < 1))
        if bad.any():
            raise ModelError(
                f"modal damping ratio {r.flat[int(np.argmax(bad))]:g} must lie in [0, 1) (finite; 1 is "
                "critical damping)",
                element="modal damping",
                field="ratio",
            )
        if r.ndim > 1 or r.size == 0:
            raise ModelError(
                f"{self.ratio!r}: give one damping ratio, or one per flexible mode from the lowest",
                element="modal damping",
                field="ratio",
            )


@dataclass(frozen=True)
class RayleighDamping:
    """C = α M + β K, with α in 1/s and β in s (Rayleigh proportional damping; Lord Rayleigh,
    *The Theory of Sound*, vol. 1, 1877).

    Parameters
    ----------
    alpha : float
        Mass-proportional coefficient α, 1/s, from 0 to 1e8 1/s.
    beta : float
        Stiffness-proportional coefficient β, s, from 0 to 1e7 s."""

    alpha: float = 0.0
    beta: float = 0.0

    def __post_init__(self) -> None:
        alpha = check_number("Rayleigh damping", "alpha", self.alpha, "1/s", nonnegative=True, high=1e8)
        beta = check_number("Rayleigh damping", "beta", self.beta, "s", nonnegative=True)
        object.__setattr__(self, "alpha", alpha)
        object.__setattr__(self, "beta", beta)

    @classmethod
    def from_ratios(cls, f1_hz: float, f2_hz: float, zeta: float) -> RayleighDamping:
        """α, β giving damping ratio ζ at the two frequencies f1 and f2 (Hz).

        Parameters
        ----------
        f1_hz, f2_hz : float
            The two frequencies, Hz, positive (from 1e-7 to 1e7 Hz).
        zeta : float
            The damping ratio at both, dimensionless, in [0, 1).

        Notes
        -----
        ζ(ω) = α/(2ω) + βω/2 solved at ω₁ and ω₂ (e.g. Chopra, *Dynamics of Structures*, §11.4).
        """
        owner = "Rayleigh damping"
        f1 = check_number(owner, "f1_hz", f1_hz, "Hz", positive=True, what="frequency")
        f2 = check_number(owner, "f2_hz", f2_hz, "Hz", positive=True, what="frequency")
        zeta = check_number(owner, "zeta", zeta, low=0.0, high=1.0, high_open=True, what="damping ratio")
        w1, w2 = 2 * np.pi * f1, 2 * np.pi * f2
        return cls(alpha=2 * zeta * w1 * w2 / (w1 + w2), beta=2 * zeta / (w1 + w2))


@dataclass(frozen=True, repr=False)  # the short repr of Result
class FRFResult(Result):
    """Steady-state complex amplitudes over frequency.

    Attributes
    ----------
    frequencies_hz : ndarray
        (n_f,) excitation frequencies, Hz.
    disk_names : tuple of str
        The disks, then the nodes inside divided shafts (:attr:`Drivetrain.dof_names`).
    angles : ndarray
        (n_f, n_dofs) complex disk (and shaft node) angle amplitudes, rad (θ(t) = Re[Θ e^{iωt}]).
    element_names : tuple of str
    element_loads : ndarray
        (n_f, n_elements) complex internal loads: shaft torque (N·m), mesh force (N), grounded spring
        torque (N·m); see ``element_units``.
    element_units : tuple of str
    natural_frequencies_hz : ndarray
        Undamped natural frequencies of the model, Hz, for reference.
    model_name : str
    excitation : mapping of disk name → complex torque amplitude, N·m
    damping : ModalDamping or RayleighDamping or None
        The damping added to the model's own dampers.
    outputs : tuple of str
        The disks to report and plot (all disks when empty).
    method : str
        How the response was computed: modal superposition over all modes, or a direct solve at
        each frequency and why.
    drivetrain : Drivetrain or None
        The model, for its table as assembled.
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
        """Excitation, frequency range (Hz), damping, natural frequencies (Hz) and the peaks."""
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
        ``"auto"`` sums the modes where that is exact and solves directly otherwise; ``"modal"``
        insists on the modes (a :class:`~mechdyn.errors.ModelError` says why where they cannot carry
        the damping); ``"direct"`` solves at each frequency. :attr:`FRFResult.method` says which ran.

    Returns
    -------
    FRFResult

    Notes
    -----
    The response solves (K + iω C − ω² M) Q = Tᵀ F on the reduced coordinates and recovers every
    disk as Θ = T Q. Modal damping adds C_m = M Φ diag(2 ζ_r ω_r) Φᵀ M over the M-normalised flexible
    modes Φ (e.g. Craig & Kurdila, *Fundamentals of Structural Dynamics*, 2nd ed., 2006, §10.4).

    Where the damping does not couple the modes — modal damping or Rayleigh damping added to a model
    whose own dampers are absent or proportional (ΦᵀCΦ diagonal to 1e-10) — the response is the sum
    over all n modes, rigid-body ones included (:func:`mechdyn.vibration.modal_superposition`):
    exact, and n_f · n² operations instead of n_f dense solves of n³/3. Otherwise (a damper between
    two disks of a chain with modal damping on top, say) it is solved frequency by frequency
    (:func:`mechdyn.vibration.harmonic_solve`). Memory does not grow with the number of frequencies
    either way beyond the result itself.
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
    idx = drivetrain.disk_index
    force = np.zeros(len(drivetrain.dof_names), dtype=complex)
    for disk, amp in excitation.items():
        if disk not in idx:
            raise ModelError(
                f"excitation at disk {disk!r}, which is not defined; defined disks: {', '.join(idx)}"
            )
        field = f"excitation[{disk!r}]"
        if isinstance(amp, complex | np.complexfloating):
            force[idx[disk]] += complex(
                check_array("frf", field, amp, "N*m", complex_values=True, what="torques")
            )
        else:
            force[idx[disk]] += si_field("frf", field, amp, "N*m", what="torque amplitude")
    modes = modal(asm)
    zeta = _modal_ratios(damping, modes)
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
    F = np.asarray(asm.T.T @ force)
    basis = _modal_basis(asm, modes, damping, zeta) if method != "direct" else "as asked"
    if isinstance(basis, str) and method == "modal":
        raise ModelError(
            f"modal superposition is not exact here: {basis}; use method='direct' (or 'auto')",
            element="frf",
            field="method",
        )
    # a response that is not finite (an undamped resonance, a free drivetrain near 0 Hz) is refused by
    # the core, naming the frequency
    if isinstance(basis, str):
        chosen = f"direct solve at each frequency ({basis})"
        if isinstance(damping, RayleighDamping):
            C = asm.C + damping.alpha * asm.mass_operator() + damping.beta * asm.K
        else:
            assert zeta is not None  # modal damping has its ratios
            C = _with_modal_damping(asm, modes, zeta)
        Q = harmonic_solve(asm.K, C, asm.mass_operator(), F, w)
        theta = np.asarray((asm.T @ Q.T).T)
    else:
        P, lam, c = basis
        chosen = f"modal superposition over all {lam.size} modes"
        theta = modal_superposition(np.asarray(asm.T @ P), lam, c, P.T @ F, w)
    names, units, L, L_rate = _load_rows(drivetrain)
    loads = np.asarray((L @ theta.T).T)
    if L_rate.nnz:
        loads = loads + 1j * w[:, None] * np.asarray((L_rate @ theta.T).T)
    return FRFResult(
        f,
        drivetrain.dof_names,
        theta,
        names,
        loads,
        units,
        modes.frequencies_hz,
        drivetrain.name,
        {d: complex(force[idx[d]]) for d in excitation},
        damping,
        tuple(outputs),
        chosen,
        drivetrain,
    )


Method = Literal["auto", "modal", "direct"]


def _load_rows(drivetrain: Drivetrain) -> tuple[tuple[str, ...], tuple[str, ...], sp.csr_array, sp.csr_array]:
    """The elements that carry a load, their units, and the sparse rows giving each load from the
    disk angles (N·m/rad or N/rad) and from their rates (N·m·s/rad or N·s/rad)."""
    idx = drivetrain.dof_index
    names: list[str] = []
    units: list[str] = []
    rows: list[int] = []
    cols: list[int] = []
    vals: list[np.ndarray] = []
    rate_vals: list[np.ndarray] = []
    for e, b in drivetrain.element_blocks:
        if b.load_row is None:
            continue
        i = len(names)
        names.append(e.name)
        units.append(b.load_unit)
        rows += [i] * len(b.disks)
        cols += [idx[d] for d in b.disks]
        vals.append(b.load_row)
        rate_vals.append(b.load_rate_row if b.load_rate_row is not None else np.zeros(len(b.disks)))
    shape = (len(names), len(drivetrain.dof_names))
    if not names:
        return (), (), sp.csr_array(shape), sp.csr_array(shape)
    L = sp.csr_array((np.concatenate(vals), (rows, cols)), shape=shape)
    L_rate = sp.csr_array((np.concatenate(rate_vals), (rows, cols)), shape=shape)
    L_rate.eliminate_zeros()
    return tuple(names), tuple(units), L, L_rate


def _modal_ratios(damping: ModalDamping | RayleighDamping, modes: ModalResult) -> np.ndarray | None:
    """ζ for every flexible mode (None for Rayleigh damping), refusing a count that does not match."""
    if isinstance(damping, RayleighDamping):
        return None
    zeta = np.atleast_1d(np.asarray(damping.ratio, dtype=float))
    if zeta.size == 1:
        return np.full(modes.omega.size, zeta[0])
    if zeta.size != modes.omega.size:
        raise ModelError(
            f"{zeta.size} modal damping ratios given for {modes.omega.size} flexible modes",
            element="modal damping",
            field="ratio",
        )
    return zeta


def _with_modal_damping(asm: Assembly, modes: ModalResult, zeta: np.ndarray) -> np.ndarray:
    """C + M Φ diag(2 ζ_r ω_r) Φᵀ M over the flexible modes: full, modal damping couples every disk."""
    MPhi = asm.mass_times(modes.reduced_shapes)
    return np.asarray(asm.C.toarray() + (MPhi * (2 * zeta * modes.omega)) @ MPhi.T)


def _modal_basis(
    asm: Assembly, modes: ModalResult, damping: ModalDamping | RayleighDamping, zeta: np.ndarray | None
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
    col = asm.T.tocsc()
    first = np.asarray(col.argmax(axis=0)).ravel()  # the disk each coordinate is (T = 1 there)
    R = asm.rigid_body_vectors[first]
    if n_rb:
        L = np.linalg.cholesky(R.T @ asm.mass_times(R))
        R = np.linalg.solve(L, R.T).T  # RᵀMR = I
    P = np.hstack([R, modes.reduced_shapes])
    lam = np.concatenate([np.zeros(n_rb), modes.omega**2])
    probe = np.random.default_rng(0).standard_normal((n, 2))
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
