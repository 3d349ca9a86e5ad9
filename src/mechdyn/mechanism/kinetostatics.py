"""Joint forces by dyad kinetostatics: Newton–Euler group by group, from the output back to the crank.

A mechanism made of a crank and RRR/RRP dyads is statically determinate group by group (Assur): the
last dyad's six joint-force components follow from the six Newton–Euler equations of its two links;
its reactions on the links before it are then known loads there, and so on back to the crank, whose
equations give the frame pivot's force and the driving torque (e.g. Norton, *Design of Machinery*,
ch. 11; Uicker, Pennock & Shigley, *Theory of Machines and Mechanisms*, ch. 14). Each dyad is one 6×6
linear system per crank angle; no full constraint Jacobian is formed. The result is written as the
Lagrange multipliers of :class:`~mechdyn.mechanism.constraints.ConstraintSet`, so that
:class:`~mechdyn.mechanism.dynamics.DynamicsResult` serves both paths; the tests check both against
each other.
"""

from __future__ import annotations

import math

import numpy as np

from mechdyn.mechanism.linalg import solve_with_det
from mechdyn.mechanism.model import GROUND, Mechanism, Prismatic, Revolute

__all__ = ["multipliers"]


def _arm(r: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Coefficients of (Fx, Fy) in r × F."""
    return -r.imag, r.real


def multipliers(c, applied: np.ndarray) -> np.ndarray:
    """Lagrange multipliers (N, m) of a one-variant dyad solution, by kinetostatics.

    Parameters
    ----------
    c : CycleBatch
        With its motions kept (``store_points=True``), one variant.
    applied : ndarray
        (N, n) generalised applied forces (gravity and process forces) in body coordinates,
        ordered by crank step as in ``c``.
    """
    m: Mechanism = c.mechanism
    N = c.angle.shape[1]
    idx = m.body_index

    def pos(name):
        return c._z[name][0][0]

    G = {b.name: pos(f"__com__{b.name}") for b in m.bodies}
    a = {b.name: c._z[f"__com__{b.name}"][2][0] for b in m.bodies}
    alpha = {b.name: c._rates[b.name][2][0] for b in m.bodies}
    # what the joints must supply to each body: Σ joint forces = m a − Q, Σ joint moments = I α − Q_φ
    need_f = {}
    need_m = {}
    for i, b in enumerate(m.bodies):
        qf = applied[:, 3 * i] + 1j * applied[:, 3 * i + 1]
        need_f[b.name] = b.mass * a[b.name] - qf
        need_m[b.name] = b.inertia * alpha[b.name] - applied[:, 3 * i + 2]
    lam = np.zeros((N, m.n_constraints))
    joints = list(m.joints)

    def joint_at(point: str, body: str, other: str | None = None) -> tuple[int, str]:
        for k, j in enumerate(joints):
            if isinstance(j, Revolute) and j.point == point and body in j.bodies:
                o = j.bodies[1] if j.bodies[0] == body else j.bodies[0]
                if other is None or o != other:
                    return k, o
        raise KeyError((point, body))

    def record(k: int, on: str, force: np.ndarray, point: str) -> None:
        """Force on body ``on`` from revolute joint k; the other body takes the reaction as a known load."""
        j = joints[k]
        lam[:, 2 * k] = (force if on == j.bodies[1] else -force).real
        lam[:, 2 * k + 1] = (force if on == j.bodies[1] else -force).imag
        other = j.bodies[0] if on == j.bodies[1] else j.bodies[1]
        if other != GROUND:
            need_f[other] = need_f[other] + force  # −(−force): a known load reduces what is needed
            need_m[other] = need_m[other] + _cross(pos(point) - G[other], force)

    for st in reversed(c._steps):
        if st.kind == "rrr":
            p = st.target
            k1, k2 = st.known
            kp = next(
                k
                for k, j in enumerate(joints)
                if isinstance(j, Revolute) and j.point == p and GROUND not in j.bodies
            )
            jb = joints[kp].bodies
            b1 = jb[0] if k1 in m.bodies[idx[jb[0]]].points else jb[1]
            b2 = jb[1] if b1 == jb[0] else jb[0]
            j1, _ = joint_at(k1, b1, b2)
            j2, _ = joint_at(k2, b2, b1)
            A = np.zeros((N, 6, 6))
            r1, rp1 = pos(k1) - G[b1], pos(p) - G[b1]
            r2, rp2 = pos(k2) - G[b2], pos(p) - G[b2]
            # unknowns: F1 (on b1 at K1), F2 (on b2 at K2), Fp (on b2 at P; −Fp on b1)
            A[:, 0, 0] = A[:, 1, 1] = 1.0
            A[:, 0, 4] = A[:, 1, 5] = -1.0
            A[:, 2, 0], A[:, 2, 1] = _arm(r1)
            ax, ay = _arm(rp1)
            A[:, 2, 4], A[:, 2, 5] = -ax, -ay
            A[:, 3, 2] = A[:, 4, 3] = 1.0
            A[:, 3, 4] = A[:, 4, 5] = 1.0
            A[:, 5, 2], A[:, 5, 3] = _arm(r2)
            A[:, 5, 4], A[:, 5, 5] = _arm(rp2)
            rhs = np.stack(
                [need_f[b1].real, need_f[b1].imag, need_m[b1], need_f[b2].real, need_f[b2].imag, need_m[b2]],
                -1,
            )
            x, _ = solve_with_det(A, rhs)
            F1, F2, Fp = x[:, 0] + 1j * x[:, 1], x[:, 2] + 1j * x[:, 3], x[:, 4] + 1j * x[:, 5]
            record(j1, b1, F1, k1)
            record(j2, b2, F2, k2)
            kpb = joints[kp]
            lam[:, 2 * kp] = (Fp if kpb.bodies[1] == b2 else -Fp).real
            lam[:, 2 * kp + 1] = (Fp if kpb.bodies[1] == b2 else -Fp).imag
        elif st.kind == "rrp":
            p = st.target
            (k1,) = st.known
            s = st.body
            g: Prismatic = st.guide  # type: ignore[assignment]
            kg = joints.index(g)
            kp, b1 = joint_at(p, s)
            j1, _ = joint_at(k1, b1, s)
            n = complex(-math.sin(g.axis), math.cos(g.axis))
            r1, rp1, rps = pos(k1) - G[b1], pos(p) - G[b1], pos(p) - G[s]
            A = np.zeros((N, 6, 6))
            # unknowns: F1 (on b1 at K1), Fp (on the slider at P; −Fp on b1), N (guide force along n), Mg
            A[:, 0, 0] = A[:, 1, 1] = 1.0
            A[:, 0, 2] = A[:, 1, 3] = -1.0
            A[:, 2, 0], A[:, 2, 1] = _arm(r1)
            ax, ay = _arm(rp1)
            A[:, 2, 2], A[:, 2, 3] = -ax, -ay
            A[:, 3, 2] = A[:, 4, 3] = 1.0
            A[:, 3, 4], A[:, 4, 4] = n.real, n.imag
            A[:, 5, 2], A[:, 5, 3] = _arm(rps)
            A[:, 5, 4] = _cross(rps, n)
            A[:, 5, 5] = 1.0
            rhs = np.stack(
                [need_f[b1].real, need_f[b1].imag, need_m[b1], need_f[s].real, need_f[s].imag, need_m[s]], -1
            )
            x, _ = solve_with_det(A, rhs)
            F1, Fp = x[:, 0] + 1j * x[:, 1], x[:, 2] + 1j * x[:, 3]
            record(j1, b1, F1, k1)
            jp = joints[kp]
            lam[:, 2 * kp] = (Fp if jp.bodies[1] == s else -Fp).real
            lam[:, 2 * kp + 1] = (Fp if jp.bodies[1] == s else -Fp).imag
            lam[:, 2 * kg + 1] = -x[:, 4]  # the guide: force −λ₂ n and moment −λ₁ on the slider
            lam[:, 2 * kg] = -x[:, 5]
    # the crank: its frame pivot and the motor
    crank = m.driver.body
    k0, _ = joint_at(m.driver.pivot, crank)
    F0 = need_f[crank]
    T = need_m[crank] - _cross(pos(m.driver.pivot) - G[crank], F0)
    j0 = joints[k0]
    lam[:, 2 * k0] = (F0 if j0.bodies[1] == crank else -F0).real
    lam[:, 2 * k0 + 1] = (F0 if j0.bodies[1] == crank else -F0).imag
    lam[:, -1] = -T
    return lam


def _cross(r: np.ndarray, f) -> np.ndarray:
    f = np.asarray(f)
    return r.real * f.imag - r.imag * f.real
