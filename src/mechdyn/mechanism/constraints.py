"""Constraint equations Φ(q, θ) = 0 of a planar mechanism, their Jacobian and acceleration terms.

Assembled from the joints; nothing is typed by hand. Every joint returns its residual, its
Jacobian blocks with respect to *both* bodies' coordinates (x, y, φ) — the frame included, so that
the frame's reactions follow from the same multipliers — and γ, the right-hand side of
Φ_q q̈ = γ. Formulas as in Nikravesh, *Computer-Aided Analysis of Mechanical Systems* (1988),
ch. 3–4 (revolute and translational joints in body coordinates). All arrays carry leading axes
(crank angles, design variants): q has shape (..., n).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mechdyn.mechanism.model import GROUND, GearJoint, Mechanism, Prismatic, Revolute

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
    def load_jacobian(self) -> tuple[np.ndarray, np.ndarray]:
        """(Φ_q, frame part) whose transpose times λ gives the joint loads: the Jacobian itself,
        except that a gear pair's row is its mesh force at the pitch point along the line of
        action (the same constraint on the motions the other joints allow, so the same motion and
        the same power, but the forces where the teeth put them)."""
        if self.force_jacobian is None:
            return self.jacobian, self.ground_jacobian
        return self.force_jacobian, self.force_ground_jacobian


class ConstraintSet:
    """The assembled constraints of a mechanism (joints in order, two rows each; the driver last).

    The entries of Φ_q that do not depend on the configuration (the ±1 of positions and
    rotations) form a template built once; per call only the rotation-dependent columns and γ are
    filled, for all revolute joints at once. The frame is an extra body with zero coordinates, so
    its Jacobian comes out of the same arrays.
    """

    def __init__(self, mechanism: Mechanism):
        self.mechanism = mechanism
        idx = mechanism.body_index
        nb = len(mechanism.bodies)
        self.nb = nb
        self.rows: list[tuple[str, str]] = []  # (element name, equation) per row, for messages
        self.n = mechanism.n_coordinates
        self.m = mechanism.n_constraints
        frame = nb  # the frame's slot in the augmented coordinates
        rev, pri = [], []
        template = np.zeros((self.m, 3 * (nb + 1)))
        gears = []
        for j, rows in zip(mechanism.joints, mechanism.joint_rows, strict=True):
            r0 = rows.start
            if isinstance(j, GearJoint):
                g1, g2 = (frame if b == GROUND else idx[b] for b in j.bodies)
                ic = frame if j.carrier == GROUND else idx[j.carrier]
                c1 = mechanism.local(j.carrier, j.points[0])
                c2 = mechanism.local(j.carrier, j.points[1])
                gears.append((r0, g1, g2, ic, c1, c2, mechanism.gear_laws[j.name], j))
                self.rows.append((j.name, "rolling"))
                continue
            a, b = j.bodies
            ia = frame if a == GROUND else idx[a]
            ib = frame if b == GROUND else idx[b]
            sa, sb = mechanism.local(a, j.point), mechanism.local(b, j.point)
            if isinstance(j, Revolute):
                rev.append((r0, ia, ib, sa, sb))
                template[r0, 3 * ia], template[r0 + 1, 3 * ia + 1] = 1.0, 1.0
                template[r0, 3 * ib], template[r0 + 1, 3 * ib + 1] = -1.0, -1.0
                self.rows += [(j.name, "x"), (j.name, "y")]
            elif isinstance(j, Prismatic):
                u = np.array([np.cos(j.axis), np.sin(j.axis)])
                pri.append((r0, ia, ib, sa, sb, _perp(u)))
                template[r0, 3 * ia + 2], template[r0, 3 * ib + 2] = 1.0, -1.0
                self.rows += [(j.name, "rotation"), (j.name, "distance to the axis")]
            else:  # pragma: no cover
                raise TypeError(type(j))
        self._gears = gears
        self.gear_rows = np.array([g[0] for g in gears], dtype=int)
        self.gear_flank_follows_load = np.array([g[7].flank == "load" for g in gears], dtype=bool)
        self.crank = idx[mechanism.driver.body]
        template[-1, 3 * self.crank + 2], template[-1, 3 * frame + 2] = 1.0, -1.0
        self.rows.append(("driver", "crank angle"))
        self._template = template
        self._rev = (
            np.array([r[0] for r in rev], dtype=int),
            np.array([r[1] for r in rev], dtype=int),
            np.array([r[2] for r in rev], dtype=int),
            np.array([r[3] for r in rev]).reshape(-1, 2),
            np.array([r[4] for r in rev]).reshape(-1, 2),
        )
        self._pri = pri

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
        gear pairs' mesh-force rows (see :attr:`Evaluation.load_jacobian`), their normal part on
        the side ``flank`` gives (..., gear pairs) of ±1 (+1 by default: towards gear 2).

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
        res = np.zeros((*lead, m))
        jac = np.array(np.broadcast_to(self._template, (*lead, m, 3 * (nb + 1))))
        gam = np.zeros((*lead, m)) if qd is not None else None
        if qd is not None:
            rate = np.concatenate([qd, zeros3], axis=-1).reshape(*lead, nb + 1, 3)
        row, ia, ib, sa, sb = self._rev
        if row.size:
            pa, pb = body[..., ia, 2], body[..., ib, 2]
            Asa, Asb = _rotate(pa, sa), _rotate(pb, sb)
            d = body[..., ia, :2] + Asa - body[..., ib, :2] - Asb  # (..., R, 2)
            res[..., row], res[..., row + 1] = d[..., 0], d[..., 1]
            Bsa, Bsb = _perp(Asa), _perp(Asb)
            jac[..., row, 3 * ia + 2], jac[..., row + 1, 3 * ia + 2] = Bsa[..., 0], Bsa[..., 1]
            jac[..., row, 3 * ib + 2], jac[..., row + 1, 3 * ib + 2] = -Bsb[..., 0], -Bsb[..., 1]
            if gam is not None:
                wa, wb = rate[..., ia, 2], rate[..., ib, 2]
                g = Asa * (wa**2)[..., None] - Asb * (wb**2)[..., None]
                gam[..., row], gam[..., row + 1] = g[..., 0], g[..., 1]
        for r0, ja, jb, psa, psb, normal in self._pri:  # a point of body a on a line fixed in body b
            ra, pa = body[..., ja, :2], body[..., ja, 2]
            rb, pb = body[..., jb, :2], body[..., jb, 2]
            Asa, Asb = _rotate(pa, psa), _rotate(pb, psb)
            Bsa, Bsb = _perp(Asa), _perp(Asb)
            d = ra + Asa - rb - Asb
            nrm = _rotate(pb, normal)
            Bn = _perp(nrm)
            res[..., r0] = pa - pb
            res[..., r0 + 1] = np.sum(nrm * d, axis=-1)
            r1 = r0 + 1
            jac[..., r1, 3 * ja], jac[..., r1, 3 * ja + 1] = nrm[..., 0], nrm[..., 1]
            jac[..., r1, 3 * jb], jac[..., r1, 3 * jb + 1] = -nrm[..., 0], -nrm[..., 1]
            jac[..., r1, 3 * ja + 2] = np.sum(nrm * Bsa, axis=-1)
            jac[..., r1, 3 * jb + 2] = np.sum(Bn * d, axis=-1) - np.sum(nrm * Bsb, axis=-1)
            if gam is not None:
                va, wa = rate[..., ja, :2], rate[..., ja, 2]
                vb, wb = rate[..., jb, :2], rate[..., jb, 2]
                dd = va + Bsa * wa[..., None] - vb - Bsb * wb[..., None]
                gam[..., r1] = (
                    wb**2 * np.sum(nrm * d, axis=-1)
                    - 2.0 * wb * np.sum(Bn * dd, axis=-1)
                    + np.sum(nrm * (Asa * (wa**2)[..., None] - Asb * (wb**2)[..., None]), axis=-1)
                )
        fjac = jac.copy() if self._gears and forces else None
        for n_gear, (r0, g1, g2, ic, c1, c2, law, joint) in enumerate(self._gears):
            pc = body[..., ic, 2]
            psi1, psi2 = body[..., g1, 2] - pc, body[..., g2, 2] - pc
            g, dg, ddg = law(psi1)
            res[..., r0] = psi2 - g
            jac[..., r0, 3 * g1 + 2] += -dg
            jac[..., r0, 3 * g2 + 2] += 1.0
            jac[..., r0, 3 * ic + 2] += dg - 1.0
            if gam is not None:
                w1 = rate[..., g1, 2] - rate[..., ic, 2]
                gam[..., r0] = ddg * w1**2
            if fjac is None:
                continue
            # the force row: the mesh force λ u on gear 2 (−λ u on gear 1) at the pitch point P
            rc = body[..., ic, :2]
            p1 = rc + _rotate(pc, c1)
            e = _rotate(pc, c2) - _rotate(pc, c1)
            e = e / np.linalg.norm(e, axis=-1, keepdims=True)
            if law.internal:
                e = -e
            r, dr_dpsi, _ = law.contact_radius(psi1)
            P = p1 + e * r[..., None]
            t = _perp(e) * r[..., None] - e * dr_dpsi[..., None]  # dr/dθ = −dr/dψ
            t = t / np.linalg.norm(t, axis=-1, keepdims=True)
            side = 1.0 if flank is None else np.asarray(flank)[..., n_gear, None]
            u = t - _perp(t) * (side * math.tan(joint.pressure_angle))  # −perp(t): gear 1's outward normal
            fjac[..., r0, :] = 0.0
            for slot, sign in ((g1, 1.0), (g2, -1.0)):
                arm = P - body[..., slot, :2]
                fjac[..., r0, 3 * slot] += sign * u[..., 0]
                fjac[..., r0, 3 * slot + 1] += sign * u[..., 1]
                fjac[..., r0, 3 * slot + 2] += sign * (arm[..., 0] * u[..., 1] - arm[..., 1] * u[..., 0])
        # driver: φ_crank − φ_frame − (θ − θ_drawing) = 0
        res[..., -1] = q[..., 3 * self.crank + 2] - (crank_angle - self.mechanism.drawing_crank_angle)
        if fjac is None:
            return Evaluation(res, jac[..., :n], jac[..., n:], gam)
        return Evaluation(res, jac[..., :n], jac[..., n:], gam, fjac[..., :n], fjac[..., n:])
