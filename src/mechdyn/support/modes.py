"""Natural frequencies and mode shapes of a machine on its mounts, how coupled they are, and the
elastic centre.

K φ = ω² M φ over the kept coordinates (undamped), φ mass-normalised, through the shared linear-vibration
core (:mod:`mechdyn.vibration`); its kinetic-energy shares say how decoupled each mode is, which is what a
mount layout aims for. The elastic centre is the point where a force produces translation only: where the
translation–rotation coupling of the stiffness matrix vanishes (in the least-squares sense when no such
point exists, as for most spatial layouts)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from mechdyn.results import Result
from mechdyn.support.model import MountedMachine, _skew
from mechdyn.vibration.eigen import solve_eigen
from mechdyn.vibration.modes import Modes

__all__ = ["SupportModes", "elastic_centre", "modes"]


@dataclass(frozen=True, repr=False)  # the short repr of Result
class SupportModes(Result, Modes):
    """Undamped modes of a machine on its mounts (the shared :class:`~mechdyn.vibration.Modes`).

    Attributes
    ----------
    machine : MountedMachine
    omega : ndarray
        (n,) natural circular frequencies, rad/s, ascending (``frequencies_hz`` in Hz).
    shapes : ndarray
        (n, n) mass-normalised mode shapes as columns, in the kept coordinates (m and rad per unit
        modal amplitude).
    """

    machine: MountedMachine
    omega: np.ndarray
    shapes: np.ndarray

    @property
    def coordinate_names(self) -> tuple[str, ...]:
        """The machine's kept coordinates (``"x"``, ``"ry"``, …)."""
        return tuple(self.machine.dofs)

    def coordinate_mass(self) -> np.ndarray:
        """The rigid body's mass matrix on the kept coordinates (kg, kg·m, kg·m²)."""
        return self.machine.mass_matrix

    def summary(self) -> dict[str, Any]:
        """Natural frequencies (Hz), the dominant coordinate and the decoupling of each mode."""
        return {
            "natural_frequencies_hz": [float(f) for f in self.frequencies_hz],
            "mode_dominant_coordinate": self.dominant,
            "mode_decoupling": [float(v) for v in self.decoupling],
        }

    def to_frame(self) -> Any:
        """One row per mode: frequency, dominant coordinate, kinetic-energy shares in per cent."""
        import pandas as pd

        return pd.DataFrame(self.table())

    def arrays(self) -> dict[str, tuple[np.ndarray, str]]:
        """Frequencies (Hz) and the mass-normalised shapes (m, rad per unit modal amplitude)."""
        return {"frequencies_hz": (self.frequencies_hz, "Hz"), "mode_shapes": (self.shapes, "m | rad")}

    def plots(self, **display_units: str) -> dict[str, Any]:
        """Kinetic-energy shares per mode; with several mounts the mode shapes on the machine."""
        from mechdyn.support import plots as sp

        out = {"modes.png": lambda: sp.plot_modes(self)}
        if len(self.machine.mounts) > 1:
            out["mode_shapes.png"] = lambda: sp.plot_mode_shapes(self)
        return out

    def table(self) -> list[dict[str, object]]:
        """One row per mode: frequency, dominant coordinate and the energy shares in per cent."""
        rows = []
        for k, f in enumerate(self.frequencies_hz):
            row: dict[str, object] = {"mode": k + 1, "frequency_hz": float(f), "dominant": self.dominant[k]}
            # to 1e-4 %: the round-off of an exactly decoupled mode is not news
            shares = np.round(100 * self.kinetic_energy[:, k], 4) + 0.0
            row |= {f"{d}_percent": float(e) for d, e in zip(self.machine.dofs, shares, strict=True)}
            rows.append(row)
        return rows


def modes(machine: MountedMachine) -> SupportModes:
    """Natural frequencies and mass-normalised mode shapes of the machine on its mounts.

    Parameters
    ----------
    machine : MountedMachine
        The machine on its mounts.

    The generalised symmetric eigenproblem K φ = ω² M φ, solved by the shared core
    (:func:`mechdyn.vibration.solve_eigen`; LAPACK ``sygvd`` for the full rigid-body mass matrix).

    Returns
    -------
    SupportModes
        ``omega`` in rad/s, ``frequencies_hz`` in Hz.
    """
    w2, phi, _ = solve_eigen(machine.stiffness_matrix, machine.mass_matrix)
    # sign: the largest component of each shape positive, for stable plots and tables
    big = np.argmax(np.abs(phi), axis=0)
    phi = phi * np.sign(phi[big, np.arange(phi.shape[1])])
    return SupportModes(machine, np.sqrt(np.clip(w2, 0.0, None)), phi)


def elastic_centre(machine: MountedMachine) -> tuple[np.ndarray, float] | None:
    """The elastic centre of the mounts and how well it decouples.

    Moving the reference point to p changes the coupling block of the stiffness matrix to
    K_tr(p) = K_tr(0) + K_tt [p]× (K_tt = Σ k_i, K_tr(0) = −Σ k_i [r_i]×); p is chosen to make it
    vanish in the kept coordinates (least squares).

    Parameters
    ----------
    machine : MountedMachine
        The machine on its mounts.

    Returns
    -------
    (point, residual) or None
        The point (m, machine coordinates; components the kept coordinates do not fix are 0) and
        ‖K_tr(p)‖/‖K_tr(0)‖ over the kept entries (0: a true elastic centre; 0 also when there is no
        coupling at all). None when the machine keeps no translation or no rotation.
    """
    trans = [i for i, d in enumerate(("x", "y", "z")) if d in machine.dofs]
    rot = [i for i, d in enumerate(("rx", "ry", "rz")) if d in machine.dofs]
    if not trans or not rot:
        return None
    Ktt = sum(m.stiffness_matrix for m in machine.mounts)
    Ktr0 = -sum(m.stiffness_matrix @ _skew(m.position) for m in machine.mounts)
    sub = np.ix_(trans, rot)
    basis = [_skew(e) for e in np.eye(3)]
    A = np.column_stack([(Ktt @ E)[sub].ravel() for E in basis])
    b = -Ktr0[sub].ravel()
    p, *_ = np.linalg.lstsq(A, b, rcond=None)
    used = np.abs(A).max(axis=0) > 0
    p = np.where(used, p, 0.0)
    base = np.linalg.norm(b)
    residual = float(np.linalg.norm(A @ p - b) / base) if base > 0 else 0.0
    return p, residual
