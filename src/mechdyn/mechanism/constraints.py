"""Constraint equations Φ(q, θ) = 0 of a planar mechanism, their Jacobian and acceleration terms.

Assembled from the joints; nothing is typed by hand. Every joint returns its residual, its
Jacobian blocks with respect to *both* bodies' coordinates (x, y, φ) — the frame included, so that
the frame's reactions follow from the same multipliers — and γ, the right-hand side of
Φ_q q̈ = γ. Formulas as in Nikravesh, *Computer-Aided Analysis of Mechanical Systems* (1988),
ch. 3–4 (revolute and translational joints in body coordinates). All arrays carry leading axes
(crank angles, design variants): q has shape (..., n).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mechdyn.mechanism.model import GROUND, Mechanism, Prismatic, Revolute

__all__ = ["ConstraintSet", "Evaluation"]


def _rotate(phi: np.ndarray, v: np.ndarray) -> np.ndarray:
    """A(φ) v for arrays φ (...) and v (..., 2) or (2,)."""
    c, s = np.cos(phi), np.sin(phi)
    return np.stack([c * v[..., 0] - s * v[..., 1], s * v[..., 0] + c * v[..., 1]], axis=-1)


def _perp(v: np.ndarray) -> np.ndarray:
    """v turned by +90°."""
    return np.stack([-v[..., 1], v[..., 0]], axis=-1)


@dataclass(frozen=True)
class Evaluation:
    """Constraint quantities at a set of configurations.

    Attributes
    ----------
    residual : ndarray
        (..., m) Φ.
    jacobian : ndarray
        (..., m, n) Φ_q over the moving bodies.
    ground_jacobian : ndarray
        (..., m, 3) ∂Φ/∂(x, y, φ) of the frame at its rest pose; the frame's reactions are
        −ground_jacobianᵀ λ (forces and the moment about the origin).
    gamma : ndarray
        (..., m) right-hand side of Φ_q q̈ = γ (when velocities were given).
    """

    residual: np.ndarray
    jacobian: np.ndarray
    ground_jacobian: np.ndarray
    gamma: np.ndarray | None


class ConstraintSet:
    """The assembled constraints of a mechanism (joints in order, two rows each; the driver last)."""

    def __init__(self, mechanism: Mechanism):
        self.mechanism = mechanism
        idx = mechanism.body_index
        self.rows: list[tuple[str, str]] = []  # (element name, equation) per row, for messages
        self._joints = []
        for j in mechanism.joints:
            a, b = j.bodies
            ia = -1 if a == GROUND else idx[a]
            ib = -1 if b == GROUND else idx[b]
            sa, sb = mechanism.local(a, j.point), mechanism.local(b, j.point)
            if isinstance(j, Revolute):
                self._joints.append(("revolute", ia, ib, sa, sb, None))
                self.rows += [(j.name, "x"), (j.name, "y")]
            elif isinstance(j, Prismatic):
                u = np.array([np.cos(j.axis), np.sin(j.axis)])
                self._joints.append(("prismatic", ia, ib, sa, sb, _perp(u)))
                self.rows += [(j.name, "rotation"), (j.name, "distance to the axis")]
            else:  # pragma: no cover
                raise TypeError(type(j))
        d = mechanism.driver
        self.crank = idx[d.body]
        self.rows.append(("driver", "crank angle"))
        self.n = mechanism.n_coordinates
        self.m = mechanism.n_constraints

    @staticmethod
    def _pose(q: np.ndarray, i: int) -> tuple[np.ndarray, np.ndarray]:
        if i < 0:
            shape = q.shape[:-1]
            return np.zeros((*shape, 2)), np.zeros(shape)
        return q[..., 3 * i : 3 * i + 2], q[..., 3 * i + 2]

    def evaluate(self, q: np.ndarray, crank_angle: np.ndarray, qd: np.ndarray | None = None) -> Evaluation:
        """Φ, Φ_q, the frame's Jacobian and (with velocities ``qd``) γ.

        Parameters
        ----------
        q : ndarray
            (..., n) body coordinates.
        crank_angle : ndarray
            (...) the driver's angle θ, rad (same leading shape as q).
        qd : ndarray, optional
            (..., n) velocities, for γ.
        """
        lead = q.shape[:-1]
        m, n = self.m, self.n
        res = np.zeros((*lead, m))
        jac = np.zeros((*lead, m, n))
        jg = np.zeros((*lead, m, 3))
        gam = np.zeros((*lead, m)) if qd is not None else None

        def put(row: int, body: int, block: np.ndarray) -> None:
            """Add a (..., r, 3) block for ``body`` at rows row..row+r."""
            r = block.shape[-2]
            if body < 0:
                jg[..., row : row + r, :] += block
            else:
                jac[..., row : row + r, 3 * body : 3 * body + 3] += block

        for k, (kind, ia, ib, sa, sb, normal) in enumerate(self._joints):
            row = 2 * k
            ra, pa = self._pose(q, ia)
            rb, pb = self._pose(q, ib)
            Asa, Asb = _rotate(pa, sa), _rotate(pb, sb)
            Bsa, Bsb = _perp(Asa), _perp(Asb)
            if qd is not None:
                va, wa = self._pose(qd, ia)
                vb, wb = self._pose(qd, ib)
            if kind == "revolute":
                res[..., row : row + 2] = ra + Asa - rb - Asb
                eye = np.broadcast_to(np.eye(2), (*lead, 2, 2))
                put(row, ia, np.concatenate([eye, Bsa[..., :, None]], axis=-1))
                put(row, ib, np.concatenate([-eye, -Bsb[..., :, None]], axis=-1))
                if gam is not None:
                    gam[..., row : row + 2] = Asa * (wa**2)[..., None] - Asb * (wb**2)[..., None]
            else:  # prismatic: body a's point on a line fixed in body b
                d = ra + Asa - rb - Asb
                nb = _rotate(pb, normal)
                Bnb = _perp(nb)
                res[..., row] = pa - pb
                res[..., row + 1] = np.sum(nb * d, axis=-1)
                one = np.ones((*lead, 1, 1))
                zero2 = np.zeros((*lead, 1, 2))
                put(row, ia, np.concatenate([zero2, one], axis=-1))
                put(row, ib, np.concatenate([zero2, -one], axis=-1))
                dphi_a = np.sum(nb * Bsa, axis=-1)
                dphi_b = np.sum(Bnb * d, axis=-1) - np.sum(nb * Bsb, axis=-1)
                put(row + 1, ia, np.concatenate([nb, dphi_a[..., None]], axis=-1)[..., None, :])
                put(row + 1, ib, np.concatenate([-nb, dphi_b[..., None]], axis=-1)[..., None, :])
                if gam is not None:
                    dd = va + Bsa * wa[..., None] - vb - Bsb * wb[..., None]
                    gam[..., row + 1] = (
                        wb**2 * np.sum(nb * d, axis=-1)
                        - 2.0 * wb * np.sum(Bnb * dd, axis=-1)
                        + np.sum(nb * (Asa * (wa**2)[..., None] - Asb * (wb**2)[..., None]), axis=-1)
                    )
        # driver: φ_crank − φ_frame − (θ − θ_drawing) = 0
        row = m - 1
        res[..., row] = q[..., 3 * self.crank + 2] - (crank_angle - self.mechanism.drawing_crank_angle)
        jac[..., row, 3 * self.crank + 2] = 1.0
        jg[..., row, 2] = -1.0
        return Evaluation(res, jac, jg, gam)
