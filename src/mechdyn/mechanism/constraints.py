"""Constraint equations Φ(q, θ) = 0 of a planar mechanism, their Jacobian and acceleration terms.

Assembled from the joints; nothing is typed by hand. Every joint returns its residual, its
Jacobian blocks with respect to *both* bodies' coordinates (x, y, φ) — the frame included, so that
the frame's reactions follow from the same multipliers — and γ, the right-hand side of
Φ_q q̈ = γ: its terms (:mod:`mechdyn.mechanism.joint_terms`, formulas as in Nikravesh,
*Computer-Aided Analysis of Mechanical Systems* (1988), ch. 3–4). All arrays carry leading axes
(crank angles, design variants): q has shape (..., n).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

# the joints' terms are importable from here, as before
from mechdyn.mechanism.joint_terms import GearTerms, JointTerms, PrismaticTerms, RevoluteTerms
from mechdyn.mechanism.model import GROUND, Mechanism

__all__ = ["ConstraintSet", "Evaluation", "GearTerms", "JointTerms", "PrismaticTerms", "RevoluteTerms"]


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
    force_jacobian, force_ground_jacobian : ndarray or None
        With gear pairs: the Jacobian with each gear row replaced by its mesh-force row.
    """

    residual: np.ndarray
    jacobian: np.ndarray
    ground_jacobian: np.ndarray
    gamma: np.ndarray | None
    force_jacobian: np.ndarray | None = None
    force_ground_jacobian: np.ndarray | None = None

    @property
    def load_jacobian(self) -> tuple[np.ndarray, np.ndarray | None]:
        """(Φ_q, frame part) whose transpose times λ gives the joint loads: the Jacobian itself,
        except that a gear pair's row is its mesh force at the pitch point along the line of
        action (the same constraint on the motions the other joints allow, so the same motion and
        the same power, but the forces where the teeth put them)."""
        if self.force_jacobian is None:
            return self.jacobian, self.ground_jacobian
        return self.force_jacobian, self.force_ground_jacobian


class ConstraintSet:
    """The assembled constraints of a mechanism: every joint's rows in order, the driver last.

    Each joint gives its terms (:class:`JointTerms`); the frame is an extra body with zero
    coordinates, so its Jacobian comes out of the same arrays.
    """

    def __init__(self, mechanism: Mechanism):
        self.mechanism = mechanism
        idx = mechanism.body_index
        nb = len(mechanism.bodies)
        self.nb = nb
        self.n = mechanism.n_coordinates
        self.m = mechanism.n_constraints

        def slot(name: str) -> int:
            return nb if name == GROUND else idx[name]

        self._terms: list[tuple[int, JointTerms]] = []
        self.rows: list[tuple[str, str]] = []  # (element name, equation) per row, for messages
        kinds: dict[type[JointTerms], list[tuple[int, JointTerms]]] = {}
        for j, rows in zip(mechanism.joints, mechanism.joint_rows, strict=True):
            t = j.terms(mechanism, slot)
            self._terms.append((rows.start, t))
            kinds.setdefault(type(t), []).append((rows.start, t))
            self.rows += [(j.name, eq) for eq in t.equations]
        self._evaluators = [e for kind, members in kinds.items() for e in kind.stack(members)]
        self.crank = idx[mechanism.driver.body]
        self.rows.append(("driver", "crank angle"))
        # rows whose force law depends on their own multiplier's sign (a gear's loaded flank)
        self.load_dependent_rows = np.array([r0 for r0, t in self._terms if t.load_dependent], dtype=int)

    def evaluate(
        self,
        q: np.ndarray,
        crank_angle: np.ndarray,
        qd: np.ndarray | None = None,
        *,
        forces: bool = False,
        flank: np.ndarray | None = None,
    ) -> Evaluation:
        """Φ, Φ_q, the frame's Jacobian and (with velocities ``qd``) γ; with ``forces``, also the
        joints' force rows (see :attr:`Evaluation.load_jacobian`), a load-dependent joint's on the
        side ``flank`` gives ((..., load-dependent joints) of ±1; +1 by default).

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
        m, n, nb = self.m, self.n, self.nb
        zeros3 = np.zeros((*lead, 3))
        body = np.concatenate([q, zeros3], axis=-1).reshape(*lead, nb + 1, 3)
        rate = None if qd is None else np.concatenate([qd, zeros3], axis=-1).reshape(*lead, nb + 1, 3)
        res = np.zeros((*lead, m))
        jac = np.zeros((*lead, m, 3 * (nb + 1)))
        gam = np.zeros((*lead, m)) if qd is not None else None
        for e in self._evaluators:
            e.evaluate(body, rate, res, jac, gam)
        # driver: φ_crank − φ_frame − (θ − θ_drawing) = 0
        jac[..., -1, 3 * self.crank + 2], jac[..., -1, 3 * nb + 2] = 1.0, -1.0
        res[..., -1] = q[..., 3 * self.crank + 2] - (crank_angle - self.mechanism.drawing_crank_angle)
        fjac = None
        if forces:
            fjac = jac.copy()
            k = 0
            changed = False
            for r0, t in self._terms:
                side: float | np.ndarray = 1.0
                if t.load_dependent:
                    side = 1.0 if flank is None else np.asarray(flank)[..., k, None]
                    k += 1
                changed |= t.force_rows(body, fjac, r0, side)
            if not changed:
                fjac = None
        if fjac is None:
            return Evaluation(res, jac[..., :n], jac[..., n:], gam)
        return Evaluation(res, jac[..., :n], jac[..., n:], gam, fjac[..., :n], fjac[..., n:])
