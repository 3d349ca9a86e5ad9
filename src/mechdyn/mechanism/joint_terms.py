"""What each kind of joint puts into the constraint equations: its rows of Φ, Φ_q and γ, and (where
the force does not act along the constraint's own gradient) its force rows — :class:`JointTerms`, and
:class:`RevoluteTerms`, :class:`PrismaticTerms` and :class:`GearTerms` for the joints of
:mod:`mechdyn.mechanism.elements`.

Formulas as in Nikravesh, *Computer-Aided Analysis of Mechanical Systems* (1988), ch. 3–4 (revolute
and translational joints in body coordinates). Every joint builds its own terms; the assembler
(:class:`~mechdyn.mechanism.constraints.ConstraintSet`) stacks them. All arrays carry leading axes
(crank angles, design variants).
"""

from __future__ import annotations

import math
from typing import Any, cast

import numpy as np

__all__ = ["GearTerms", "JointTerms", "PrismaticTerms", "RevoluteTerms"]


def _rotate(phi: np.ndarray, v: np.ndarray) -> np.ndarray:
    """A(φ) v for arrays φ (...) and v (..., 2) or (2,)."""
    c, s = np.cos(phi), np.sin(phi)
    return np.stack([c * v[..., 0] - s * v[..., 1], s * v[..., 0] + c * v[..., 1]], axis=-1)


def _perp(v: np.ndarray) -> np.ndarray:
    """v turned by +90°."""
    return np.stack([-v[..., 1], v[..., 0]], axis=-1)


class JointTerms:
    """What a joint contributes to the constraints: its rows of Φ, Φ_q and γ, and (where the force
    does not act along the constraint's own gradient) its force rows.

    Each joint class builds its terms (``joint.terms(mechanism, slot)``); the assembler calls
    :meth:`evaluate` on every joint in turn and never asks what kind of joint it is. ``body`` and
    ``rate`` are (..., bodies + 1, 3) arrays of (x, y, φ) and their rates, the frame last.
    """

    equations: tuple[str, ...] = ()
    load_dependent = False  # the force row depends on the sign of the joint's own multiplier

    def evaluate(self, body, rate, res, jac, gam, r0: Any) -> None:  # pragma: no cover - abstract
        raise NotImplementedError

    def force_rows(self, body, fjac, r0: int, side) -> bool:
        """Write the joint's force rows where they differ from its Jacobian rows; False if none."""
        return False

    @classmethod
    def stack(cls, members: list[tuple[int, JointTerms]]) -> list[Any]:
        """Evaluators for several joints of this kind, each ``evaluate(body, rate, res, jac, gam)``;
        by default one per joint (a kind may evaluate all its joints at once)."""
        return [_One(r0, t) for r0, t in members]


class _One:
    """One joint's terms at its rows."""

    def __init__(self, r0: int | np.ndarray, terms: JointTerms):
        self.r0, self.terms = r0, terms

    def evaluate(self, body, rate, res, jac, gam) -> None:
        self.terms.evaluate(body, rate, res, jac, gam, self.r0)


class RevoluteTerms(JointTerms):
    """A pin: the point of body a and the point of body b coincide (two rows: x, y). All pins of a
    mechanism evaluate at once (:meth:`stack`)."""

    equations = ("x", "y")

    def __init__(self, ia: Any, ib: Any, sa: np.ndarray, sb: np.ndarray):
        self.ia, self.ib, self.sa, self.sb = ia, ib, sa, sb

    @classmethod
    def stack(cls, members: list[tuple[int, JointTerms]]) -> list[Any]:
        rows = np.array([r0 for r0, _ in members], dtype=int)
        # the assembler stacks the members of one kind: type(t) is cls for each
        ts = cast("list[RevoluteTerms]", [t for _, t in members])
        group = cls(
            np.array([t.ia for t in ts], dtype=int),
            np.array([t.ib for t in ts], dtype=int),
            np.array([t.sa for t in ts]).reshape(-1, 2),
            np.array([t.sb for t in ts]).reshape(-1, 2),
        )
        return [_One(rows, group)]  # rows as an array: every pin's two rows at once

    def evaluate(self, body, rate, res, jac, gam, r0: Any) -> None:
        ia, ib = self.ia, self.ib
        Asa, Asb = _rotate(body[..., ia, 2], self.sa), _rotate(body[..., ib, 2], self.sb)
        d = body[..., ia, :2] + Asa - body[..., ib, :2] - Asb
        res[..., r0], res[..., r0 + 1] = d[..., 0], d[..., 1]
        jac[..., r0, 3 * ia], jac[..., r0 + 1, 3 * ia + 1] = 1.0, 1.0
        jac[..., r0, 3 * ib], jac[..., r0 + 1, 3 * ib + 1] = -1.0, -1.0
        Bsa, Bsb = _perp(Asa), _perp(Asb)
        jac[..., r0, 3 * ia + 2], jac[..., r0 + 1, 3 * ia + 2] = Bsa[..., 0], Bsa[..., 1]
        jac[..., r0, 3 * ib + 2], jac[..., r0 + 1, 3 * ib + 2] = -Bsb[..., 0], -Bsb[..., 1]
        if gam is not None:
            wa, wb = rate[..., ia, 2], rate[..., ib, 2]
            g = Asa * (wa**2)[..., None] - Asb * (wb**2)[..., None]
            gam[..., r0], gam[..., r0 + 1] = g[..., 0], g[..., 1]


class PrismaticTerms(JointTerms):
    """A point of body a on a line fixed in body b: equal rotations, and no distance to the line."""

    equations = ("rotation", "distance to the axis")

    def __init__(self, ia: int, ib: int, sa: np.ndarray, sb: np.ndarray, normal: np.ndarray):
        self.ia, self.ib, self.sa, self.sb, self.normal = ia, ib, sa, sb, normal

    def evaluate(self, body, rate, res, jac, gam, r0: int) -> None:
        ja, jb = self.ia, self.ib
        ra, pa = body[..., ja, :2], body[..., ja, 2]
        rb, pb = body[..., jb, :2], body[..., jb, 2]
        Asa, Asb = _rotate(pa, self.sa), _rotate(pb, self.sb)
        Bsa, Bsb = _perp(Asa), _perp(Asb)
        d = ra + Asa - rb - Asb
        nrm = _rotate(pb, self.normal)
        Bn = _perp(nrm)
        res[..., r0] = pa - pb
        res[..., r0 + 1] = np.sum(nrm * d, axis=-1)
        jac[..., r0, 3 * ja + 2], jac[..., r0, 3 * jb + 2] = 1.0, -1.0
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


class GearTerms(JointTerms):
    """Two gears rolling on a carrier: ψ₂ = g(ψ₁) (one row); the mesh force acts at the pitch point
    along the line of action, so its force row is not the rolling row's gradient."""

    equations = ("rolling",)

    def __init__(self, g1: int, g2: int, ic: int, c1: np.ndarray, c2: np.ndarray, law, pressure_angle, flank):
        self.g1, self.g2, self.ic, self.c1, self.c2, self.law = g1, g2, ic, c1, c2, law
        self.tan_phi = math.tan(pressure_angle)
        self.load_dependent = flank == "load"

    def evaluate(self, body, rate, res, jac, gam, r0: int) -> None:
        g1, g2, ic = self.g1, self.g2, self.ic
        pc = body[..., ic, 2]
        g, dg, ddg = self.law(body[..., g1, 2] - pc)
        res[..., r0] = body[..., g2, 2] - pc - g
        jac[..., r0, 3 * g1 + 2] += -dg
        jac[..., r0, 3 * g2 + 2] += 1.0
        jac[..., r0, 3 * ic + 2] += dg - 1.0
        if gam is not None:
            w1 = rate[..., g1, 2] - rate[..., ic, 2]
            gam[..., r0] = ddg * w1**2

    def force_rows(self, body, fjac, r0: int, side) -> bool:
        """The mesh force λ u on gear 2 (−λ u on gear 1) at the pitch point P, u along the line of
        action on the flank ``side`` (±1) gives."""
        g1, g2, ic, law = self.g1, self.g2, self.ic, self.law
        pc = body[..., ic, 2]
        rc = body[..., ic, :2]
        p1 = rc + _rotate(pc, self.c1)
        e = _rotate(pc, self.c2) - _rotate(pc, self.c1)
        e = e / np.linalg.norm(e, axis=-1, keepdims=True)
        if law.internal:
            e = -e
        r, dr_dpsi, _ = law.contact_radius(body[..., g1, 2] - pc)
        P = p1 + e * r[..., None]
        t = _perp(e) * r[..., None] - e * dr_dpsi[..., None]  # dr/dθ = −dr/dψ
        t = t / np.linalg.norm(t, axis=-1, keepdims=True)
        u = t - _perp(t) * (side * self.tan_phi)  # −perp(t): gear 1's outward normal
        fjac[..., r0, :] = 0.0
        for slot, sign in ((g1, 1.0), (g2, -1.0)):
            arm = P - body[..., slot, :2]
            fjac[..., r0, 3 * slot] += sign * u[..., 0]
            fjac[..., r0, 3 * slot + 1] += sign * u[..., 1]
            fjac[..., r0, 3 * slot + 2] += sign * (arm[..., 0] * u[..., 1] - arm[..., 1] * u[..., 0])
        return True
