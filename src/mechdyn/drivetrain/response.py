"""Steady-state response to harmonic torques (frequency response) with modal or Rayleigh damping."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
import scipy.sparse as sp

from mechdyn.checks import check_array, check_number
from mechdyn.drivetrain.assembly import assemble
from mechdyn.drivetrain.modal import modal
from mechdyn.drivetrain.model import Drivetrain
from mechdyn.errors import ModelError
from mechdyn.results import Result, Table
from mechdyn.units import si_field
from mechdyn.vibration.harmonic import harmonic_solve

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
    angles : ndarray
        (n_f, n_disks) complex disk angle amplitudes, rad (θ(t) = Re[Θ e^{iωt}]).
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
            "natural_frequencies_hz": self.natural_frequencies_hz.tolist(),
            "peaks": self.peaks,
        }

    def tables(self, **display_units: str) -> list[Table]:
        """The resonance peak of every output and element (see :meth:`peak`)."""
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
            )
        ]

    def plots(self, **display_units: str) -> dict[str, Any]:
        """``frf.png``: the output disks' amplitudes over frequency."""
        return {"frf.png": lambda: self.plot(list(self.outputs) or None)}

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
        """Plot magnitudes against frequency (log scale); returns the matplotlib axes.

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

    Returns
    -------
    FRFResult

    Notes
    -----
    Solves (K + iω C − ω² M) Q = Tᵀ F on the reduced coordinates for each ω
    (:func:`mechdyn.vibration.harmonic_solve`: one frequency at a time, so memory does not grow with
    the number of frequencies) and recovers every disk as Θ = T Q. Modal damping adds
    C_m = M Φ diag(2 ζ_r ω_r) Φᵀ M over the M-normalised flexible modes Φ (e.g. Craig & Kurdila,
    *Fundamentals of Structural Dynamics*, 2nd ed., 2006).
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
    force = np.zeros(len(drivetrain.disks), dtype=complex)
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
    M = sp.diags_array(asm.mass)
    K, C = asm.K, asm.C
    modes = modal(asm)
    Phi_r = modes.reduced_shapes
    if isinstance(damping, RayleighDamping):
        C = C + damping.alpha * M + damping.beta * K
    else:
        zeta = np.atleast_1d(np.asarray(damping.ratio, dtype=float))
        if zeta.size == 1:
            zeta = np.full(modes.omega.size, zeta[0])
        if zeta.size != modes.omega.size:
            raise ModelError(
                f"{zeta.size} modal damping ratios given for {modes.omega.size} flexible modes",
                element="modal damping",
                field="ratio",
            )
        MPhi = asm.mass[:, None] * Phi_r
        C = C.toarray() + (MPhi * (2 * zeta * modes.omega)) @ MPhi.T  # full: modal damping couples all
    w = 2 * np.pi * f
    F = np.asarray(asm.T.T @ force)
    if asm.n_rigid_body and np.any(w == 0):
        raise ModelError(
            "a free drivetrain has no static response at 0 Hz; start the frequencies above 0",
            element="frf",
            field="frequencies_hz",
        )
    Q = harmonic_solve(K, C, M, F, w)  # frequency by frequency: memory independent of len(f)
    overflow = ~np.isfinite(Q).all(axis=1)
    if overflow.any():
        k = int(np.argmax(overflow))
        raise ModelError(
            f"the response at {f[k]:g} Hz is not finite (the dynamic stiffness is singular there, or the "
            "response overflows: a free drivetrain's grows as 1/f² towards 0 Hz); leave that frequency "
            "out or start the frequencies higher",
            element="frf",
            field="frequencies_hz",
        )
    theta = np.asarray((asm.T @ Q.T).T)
    names, units, loads = [], [], []
    for e, b in drivetrain.element_blocks:
        if b.load_row is None:
            continue
        th = theta[:, [idx[d] for d in b.disks]]
        load = th @ b.load_row
        if b.load_rate_row is not None:
            load = load + 1j * w * (th @ b.load_rate_row)
        names.append(e.name)
        units.append(b.load_unit)
        loads.append(load)
    return FRFResult(
        f,
        drivetrain.disk_names,
        theta,
        tuple(names),
        np.column_stack(loads) if loads else np.zeros((f.size, 0), dtype=complex),
        tuple(units),
        modes.frequencies_hz,
        drivetrain.name,
        {d: complex(force[idx[d]]) for d in excitation},
        damping,
        tuple(outputs),
    )
