"""Natural frequencies and mode shapes of a machine on its mounts, how coupled they are, and the
elastic centre.

K φ = ω² M φ over the kept coordinates (undamped), φ mass-normalised. The kinetic energy of mode k
splits over the coordinates as e_kj = φ_kj (M φ_k)_j (the shares sum to one); a mode with one share
near 1 is decoupled, which is what a mount layout aims for (e.g. Harris & Piersol, *Shock and
Vibration Handbook*, ch. 30, "decoupled modes"; the "kinetic energy distribution" tables of mount
vendors' calculators). The elastic centre is the point where a force produces translation only:
where the translation–rotation coupling of the stiffness matrix vanishes (in the least-squares sense
when no such point exists, as for most spatial layouts).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg

from mechdyn.support.model import MountedMachine, _skew

__all__ = ["SupportModes", "elastic_centre", "modes"]


@dataclass(frozen=True)
class SupportModes:
    """Undamped modes of a machine on its mounts.

    Attributes
    ----------
    machine : MountedMachine
    natural_frequencies : ndarray
        (n,) Hz, ascending.
    shapes : ndarray
        (n, n) mass-normalised mode shapes as columns, in the kept coordinates.
    """

    machine: MountedMachine
    natural_frequencies: np.ndarray
    shapes: np.ndarray

    @property
    def energy_share(self) -> np.ndarray:
        """(modes, coordinates) share of each mode's kinetic energy in each coordinate (rows sum to 1)."""
        phi = self.shapes
        return (phi * (self.machine.mass_matrix @ phi)).T

    @property
    def dominant(self) -> list[str]:
        """The coordinate that carries most of each mode's kinetic energy."""
        return [self.machine.dofs[int(np.argmax(e))] for e in self.energy_share]

    @property
    def decoupling(self) -> np.ndarray:
        """(modes,) the largest energy share of each mode: 1 for a fully decoupled mode."""
        return self.energy_share.max(axis=1)

    def table(self) -> list[dict[str, object]]:
        """One row per mode: frequency, dominant coordinate and the energy shares in per cent."""
        rows = []
        for k, f in enumerate(self.natural_frequencies):
            row: dict[str, object] = {"mode": k + 1, "frequency_hz": float(f), "dominant": self.dominant[k]}
            # to 1e-4 %: the round-off of an exactly decoupled mode is not news
            shares = np.round(100 * self.energy_share[k], 4) + 0.0
            row |= {f"{d}_percent": float(e) for d, e in zip(self.machine.dofs, shares, strict=True)}
            rows.append(row)
        return rows


def modes(machine: MountedMachine) -> SupportModes:
    """Natural frequencies (Hz) and mass-normalised mode shapes of the machine on its mounts.

    The generalised symmetric eigenproblem K φ = ω² M φ (LAPACK ``sygvd`` through
    :func:`scipy.linalg.eigh`).
    """
    M, K = machine.mass_matrix, machine.stiffness_matrix
    w2, phi = scipy.linalg.eigh(K, M)
    # sign: the largest component of each shape positive, for stable plots and tables
    big = np.argmax(np.abs(phi), axis=0)
    phi = phi * np.sign(phi[big, np.arange(phi.shape[1])])
    return SupportModes(machine, np.sqrt(np.clip(w2, 0.0, None)) / (2 * math.pi), phi)


def elastic_centre(machine: MountedMachine) -> tuple[np.ndarray, float] | None:
    """The elastic centre of the mounts and how well it decouples.

    Moving the reference point to p changes the coupling block of the stiffness matrix to
    K_tr(p) = K_tr(0) + K_tt [p]× (K_tt = Σ k_i, K_tr(0) = −Σ k_i [r_i]×); p is chosen to make it
    vanish in the kept coordinates (least squares).

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
