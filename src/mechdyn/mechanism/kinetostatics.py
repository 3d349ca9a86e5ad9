"""Joint forces by dyad kinetostatics: Newton–Euler group by group, from the output back to the crank.

A mechanism made of a crank and RRR/RRP dyads is statically determinate group by group (Assur): the
last dyad's six joint-force components follow from the six Newton–Euler equations of its two links;
its reactions on the links before it are then known loads there, and so on back to the crank, whose
equations give the frame pivot's force and the driving torque (e.g. Norton, *Design of Machinery*,
ch. 11; Uicker, Pennock & Shigley, *Theory of Machines and Mechanisms*, ch. 14). Each dyad's six
equations reduce, by taking moments about its inner pin, to a 2×2 system whose determinant is the
dyad's transmission measure; it is solved by Cramer's rule for all crank angles at once, and no
full constraint Jacobian is formed. The result is written as the
Lagrange multipliers of :class:`~mechdyn.mechanism.constraints.ConstraintSet`, so that
:class:`~mechdyn.mechanism.dynamics.DynamicsResult` serves both paths; the tests check both against
each other.
"""

from __future__ import annotations

import math

import numpy as np

from mechdyn.mechanism.model import GROUND, Mechanism, Prismatic

__all__ = ["multipliers"]


def multipliers(c, applied: np.ndarray) -> np.ndarray:
    """Lagrange multipliers (V, N, m) of a dyad solution, by kinetostatics, for every variant at once.

    Parameters
    ----------
    c : CycleBatch
        With its motions kept (``store_points=True``).
    applied : ndarray
        (V, N, n) generalised applied forces (gravity and process forces) in body coordinates,
        ordered by crank step as in ``c``.
    """
    m: Mechanism = c.mechanism
    V, N = c.angle.shape
    idx = m.body_index

    def pos(name):
        return c._z[name][0]

    G = {b.name: pos(f"__com__{b.name}") for b in m.bodies}
    a = {b.name: c._z[f"__com__{b.name}"][2] for b in m.bodies}
    alpha = {b.name: c._rates[b.name][2] for b in m.bodies}
    # what the joints must supply to each body: Σ joint forces = m a − Q, Σ joint moments = I α − Q_φ
    need_f = {}
    need_m = {}
    for i, b in enumerate(m.bodies):
        qf = applied[..., 3 * i] + 1j * applied[..., 3 * i + 1]
        need_f[b.name] = c._body_mass[:, i, None] * a[b.name] - qf
        need_m[b.name] = c._body_inertia[:, i, None] * alpha[b.name] - applied[..., 3 * i + 2]
    lam = np.zeros((V, N, m.n_constraints))
    joints = list(m.joints)

    def joint_at(point: str, body: str, other: str | None = None) -> tuple[int, str]:
        for k, j in enumerate(joints):
            if j.pins and j.point == point and body in j.bodies:
                o = j.bodies[1] if j.bodies[0] == body else j.bodies[0]
                if other is None or o != other:
                    return k, o
        raise KeyError((point, body))

    def record(k: int, on: str, force: np.ndarray, point: str) -> None:
        """Force on body ``on`` from revolute joint k; the other body takes the reaction as a known load."""
        j = joints[k]
        lam[..., 2 * k] = (force if on == j.bodies[1] else -force).real
        lam[..., 2 * k + 1] = (force if on == j.bodies[1] else -force).imag
        other = j.bodies[0] if on == j.bodies[1] else j.bodies[1]
        if other != GROUND:
            need_f[other] = need_f[other] + force  # −(−force): a known load reduces what is needed
            need_m[other] = need_m[other] + _cross(pos(point) - G[other], force)

    for st in reversed(c._steps):
        if st.kind == "rrr":
            p = st.target
            k1, k2 = st.known
            kp = next(k for k, j in enumerate(joints) if j.pins and j.point == p and GROUND not in j.bodies)
            jb = joints[kp].bodies
            b1 = jb[0] if k1 in m.bodies[idx[jb[0]]].points else jb[1]
            b2 = jb[1] if b1 == jb[0] else jb[0]
            j1, _ = joint_at(k1, b1, b2)
            j2, _ = joint_at(k2, b2, b1)
            # unknowns F1 (on b1 at K1), F2 (on b2 at K2), Fp (on b2 at P; −Fp on b1). Moments of
            # each link about P leave F1 and F2; their sum is what both links need together:
            #   a1 × F1 = M1 − (P − G1) × f1,  a2 × F2 = M2 − (P − G2) × f2,  F1 + F2 = f1 + f2
            # with a_i = K_i − P; the 2×2 system in F1 has determinant a1 × a2 (zero at a toggle).
            P = pos(p)
            a1, a2 = pos(k1) - P, pos(k2) - P
            f1, f2 = need_f[b1], need_f[b2]
            m1 = need_m[b1] - _cross(P - G[b1], f1)
            m2 = _cross(a2, f1 + f2) - need_m[b2] + _cross(P - G[b2], f2)
            F1 = _solve_cross(a1, m1, a2, m2)
            F2 = f1 + f2 - F1
            Fp = F1 - f1
            record(j1, b1, F1, k1)
            record(j2, b2, F2, k2)
            kpb = joints[kp]
            lam[..., 2 * kp] = (Fp if kpb.bodies[1] == b2 else -Fp).real
            lam[..., 2 * kp + 1] = (Fp if kpb.bodies[1] == b2 else -Fp).imag
        elif st.kind == "rrp":
            p = st.target
            (k1,) = st.known
            s = st.body
            g: Prismatic = st.guide  # type: ignore[assignment]
            kg = joints.index(g)
            kp, b1 = joint_at(p, s)
            j1, _ = joint_at(k1, b1, s)
            n = complex(-math.sin(g.axis), math.cos(g.axis))
            # unknowns F1 (on b1 at K1), Fp (on the slider at P; −Fp on b1), the guide's normal force
            # N n and moment Mg on the slider. The slider's balances give Fp = f_s − N n and Mg; the
            # link's moments about P then give N (a1 × n = 0 when the link lies across the guide).
            P = pos(p)
            a1 = pos(k1) - P
            m1 = need_m[b1] - _cross(P - G[b1], need_f[b1])
            total = need_f[b1] + need_f[s]
            normal = (_cross(a1, total) - m1) / _cross(a1, n)
            Fp = need_f[s] - normal * n
            F1 = need_f[b1] + Fp
            moment = need_m[s] - _cross(P - G[s], need_f[s])
            record(j1, b1, F1, k1)
            jp = joints[kp]
            lam[..., 2 * kp] = (Fp if jp.bodies[1] == s else -Fp).real
            lam[..., 2 * kp + 1] = (Fp if jp.bodies[1] == s else -Fp).imag
            lam[..., 2 * kg + 1] = -normal  # the guide: force −λ₂ n and moment −λ₁ on the slider
            lam[..., 2 * kg] = -moment
    # the crank: its frame pivot and the motor
    crank = m.driver.body
    k0, _ = joint_at(m.driver.pivot, crank)
    F0 = need_f[crank]
    T = need_m[crank] - _cross(pos(m.driver.pivot) - G[crank], F0)
    j0 = joints[k0]
    lam[..., 2 * k0] = (F0 if j0.bodies[1] == crank else -F0).real
    lam[..., 2 * k0 + 1] = (F0 if j0.bodies[1] == crank else -F0).imag
    lam[..., -1] = -T
    return lam


def _solve_cross(a1: np.ndarray, m1: np.ndarray, a2: np.ndarray, m2: np.ndarray) -> np.ndarray:
    """F with a1 × F = m1 and a2 × F = m2 (complex plane vectors), by Cramer's rule."""
    det = _cross(a1, a2)
    return (a2 * m1 - a1 * m2) / det


def _cross(r: np.ndarray, f) -> np.ndarray:
    f = np.asarray(f)
    return r.real * f.imag - r.imag * f.real
