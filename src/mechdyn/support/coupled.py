"""The machine on its mounts on a foundation block on soil: two rigid bodies, assembled.

Coordinates q = (q_m, q_b): the machine's kept coordinates about its centre of mass, then the block's
same coordinates about its own. A mount joins the two: its deflection is the machine's displacement
at the mount less the block's there, u = T_m(p) q_m − T_b(p) q_b with T(p) = [I, −[p − G]×]
(:meth:`MountedMachine.mount_transform`), so it adds Dᵀ R k Rᵀ D to K with D = [T_m, −T_b] (likewise
C). The soil acts at the centre of the block's base: its six displacements (translation and
rotation) are S q_b with S = [[I, −[b − G_b]×], [0, I]], so it adds Sᵀ K_s S to the block's block of
K. M is block-diagonal. With the soil removed the assembly keeps the block's rigid-body freedoms
(machine and block move together), which the tests check; with it, K is positive definite. (The
assembly of rigid bodies on point springs: e.g. Harris & Piersol, *Shock and Vibration Handbook*,
ch. 30, two-stage isolation.)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np
import scipy.linalg

from mechdyn.errors import ModelError
from mechdyn.support.excitation import PeriodicLoad
from mechdyn.support.foundation import SOIL_AXES, Foundation
from mechdyn.support.model import DOFS, Mount, MountedMachine, _skew

__all__ = ["FoundationSystem"]


@dataclass(frozen=True)
class FoundationSystem:
    """A rigid machine on its mounts on a rigid foundation block on soil (2 × its kept coordinates).

    Parameters
    ----------
    machine : MountedMachine
        The machine and its mounts; the block keeps the same coordinates as the machine.
    foundation : Foundation
        The block and the soil's springs and dashpots.

    Raises
    ------
    ModelError
        When the block has no moment of inertia about a kept rotation, or the soil leaves a kept
        motion of the block unrestrained.
    """

    machine: MountedMachine
    foundation: Foundation

    def __post_init__(self) -> None:
        rot = {"rx": 0, "ry": 1, "rz": 2}
        J = self.foundation.block.inertia
        for d in self.dofs:
            if d in rot and J[rot[d], rot[d]] <= 0:
                raise ModelError(
                    f"the block's moment of inertia about {d[1]} is zero but the model keeps {d}; give "
                    "the block's inertia or its size",
                    element=self.foundation.name,
                    field="inertia",
                )
        w = np.linalg.eigvalsh(self.stiffness_matrix)
        scale = float(np.abs(np.diag(self.stiffness_matrix)).max())
        if w.min() <= 1e-12 * scale:
            raise ModelError(
                "the soil leaves a motion of the block unrestrained (a soil stiffness along or about a "
                f"kept coordinate {list(self.dofs)} is zero); give every kept soil spring",
                element=self.foundation.name,
                field="soil",
            )

    @property
    def dofs(self) -> tuple[str, ...]:
        """The coordinates each body keeps (the machine's)."""
        return self.machine.dofs

    @property
    def coordinates(self) -> tuple[str, ...]:
        """The 2n coordinates' names: ``machine z``, ..., ``block z``, ..."""
        return (*(f"machine {d}" for d in self.dofs), *(f"block {d}" for d in self.dofs))

    @cached_property
    def _select(self) -> np.ndarray:
        return np.eye(6)[:, [DOFS.index(d) for d in self.dofs]]

    def machine_transform(self, point: Any) -> np.ndarray:
        """3×2n: the machine's displacement at a point (machine coordinates, m) from q.

        Parameters
        ----------
        point : (x, y, z)
            A point of the machine, m.
        """
        T = self.machine.mount_transform(Mount("probe", point, (0.0, 0.0, 0.0)))
        return np.hstack([T, np.zeros_like(T)])

    def block_transform(self, point: Any) -> np.ndarray:
        """3×2n: the block's displacement at a point (machine coordinates, m) from q.

        Parameters
        ----------
        point : (x, y, z)
            A point of the block, m.
        """
        r = np.asarray(point, dtype=float) - self.foundation.block.center_of_mass
        T = np.hstack([np.eye(3), -_skew(r)]) @ self._select
        return np.hstack([np.zeros_like(T), T])

    def mount_deflection(self, mount: Mount) -> np.ndarray:
        """3×2n D: the mount's deflection (machine less block at its position) from q.

        Parameters
        ----------
        mount : Mount
            One of the machine's mounts.
        """
        return self.machine_transform(mount.position) - self.block_transform(mount.position)

    @cached_property
    def soil_transform(self) -> np.ndarray:
        """6×2n S: the base's translation and rotation (along and about x, y, z) from q."""
        r = self.foundation.base - self.foundation.block.center_of_mass
        S = np.eye(6)
        S[:3, 3:] = -_skew(r)
        S = S @ self._select
        return np.hstack([np.zeros_like(S), S])

    @cached_property
    def mass_matrix(self) -> np.ndarray:
        """2n×2n block-diagonal M (kg, kg·m²)."""
        n = len(self.dofs)
        M = np.zeros((2 * n, 2 * n))
        M[:n, :n] = self.machine.mass_matrix
        M[n:, n:] = self._select.T @ self.foundation.block.mass_matrix @ self._select
        return M

    def _assemble(self, mount_part: str, soil_part: str) -> np.ndarray:
        n = len(self.dofs)
        out = np.zeros((2 * n, 2 * n))
        for m in self.machine.mounts:
            D = self.mount_deflection(m)
            out += D.T @ getattr(m, mount_part) @ D
        S = self.soil_transform
        out += S.T @ getattr(self.foundation, soil_part) @ S
        return 0.5 * (out + out.T)

    @cached_property
    def stiffness_matrix(self) -> np.ndarray:
        """2n×2n K: mounts between machine and block, soil under the block."""
        return self._assemble("stiffness_matrix", "soil_stiffness_matrix")

    @cached_property
    def damping_matrix(self) -> np.ndarray:
        """2n×2n C: the mounts' and the soil's dashpots."""
        return self._assemble("damping_matrix", "soil_damping_matrix")

    def load_matrix(self) -> np.ndarray:
        """2n×6 B: the load (F, M about the machine origin) acts on the machine only."""
        B = self.machine.load_matrix()
        return np.vstack([B, np.zeros_like(B)])

    @cached_property
    def natural_frequencies_hz(self) -> np.ndarray:
        """(2n,) undamped natural frequencies, Hz, ascending (K φ = ω² M φ)."""
        w2 = scipy.linalg.eigh(self.stiffness_matrix, self.mass_matrix, eigvals_only=True)
        return np.sqrt(np.clip(w2, 0.0, None)) / (2 * math.pi)

    def harmonic_response(self, load: PeriodicLoad) -> np.ndarray:
        """(H + 1, 2n) complex coefficients of q per harmonic: (K − (hΩ)² M + i hΩ C) X_h = B c_h.

        Parameters
        ----------
        load : PeriodicLoad
            The periodic load on the machine.
        """
        from mechdyn.vibration.harmonic import harmonic_solve

        omega = 2 * math.pi / load.period * load.orders()
        Q = load.coefficients @ self.load_matrix().T
        return harmonic_solve(self.stiffness_matrix, self.damping_matrix, self.mass_matrix, Q, omega)

    def soil_forces(self, X: np.ndarray, omega: np.ndarray) -> np.ndarray:
        """(H + 1, 6) the force and moment the block puts on the soil at the base, per harmonic.

        (K_s + iω C_s) S X_h: positive along +x, +y, +z (z up: positive pulls the soil up).

        Parameters
        ----------
        X : ndarray
            (H + 1, 2n) complex coefficients of q from :meth:`harmonic_response`, m and rad.
        omega : ndarray
            (H + 1,) each harmonic's circular frequency, rad/s.
        """
        f = self.foundation
        u = X @ self.soil_transform.T
        return u @ f.soil_stiffness_matrix.T + 1j * omega[:, None] * (u @ f.soil_damping_matrix.T)

    def mount_forces(self, X: np.ndarray, omega: np.ndarray) -> np.ndarray:
        """(H + 1, mounts, 3) the force each mount passes down to the block, per harmonic.

        Parameters
        ----------
        X : ndarray
            (H + 1, 2n) complex coefficients of q from :meth:`harmonic_response`, m and rad.
        omega : ndarray
            (H + 1,) rad/s.
        """
        out = []
        for m in self.machine.mounts:
            u = X @ self.mount_deflection(m).T
            out.append(u @ m.stiffness_matrix.T + 1j * omega[:, None] * (u @ m.damping_matrix.T))
        return np.stack(out, axis=1)

    @property
    def soil_axes(self) -> tuple[str, ...]:
        """The soil's six springs' directions (:data:`~mechdyn.support.foundation.SOIL_AXES`)."""
        return SOIL_AXES
