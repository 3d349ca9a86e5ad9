"""The arguments of the dyad path's compiled kernel (:mod:`mechdyn.mechanism.dyads._kernel`): the plan
encoded as integer operations and per-variant data (:func:`encode`), the loads' program
(:func:`encode_loads`), and :class:`KernelArgs`, the one named structure the kernel takes.

Points are complex numbers x + iy (m) in the drawing's axes; every array with a leading V holds one
row per design variant.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any, NamedTuple, cast

import numpy as np

from mechdyn.mechanism.dyads.decomposition import Step
from mechdyn.mechanism.model import GROUND, Mechanism, Prismatic

__all__ = ["KernelArgs", "encode", "encode_loads", "kernel_args", "motion_only"]


class KernelArgs(NamedTuple):
    """Everything the compiled kernel reads and writes, one field per array (a NamedTuple: numba
    compiles its fields' access by name and passes it as one argument).

    Shapes: V design variants, N crank angles, S slots (the P drawing points, then the nb bodies'
    centres of mass), O plan operations, K kept slots, D dyads, J joints, G frame joints, L the
    multipliers λ (two rows per pin or slider, one per gear pair, one for the driver). An output not
    wanted is an empty array of the same number of dimensions.

    Attributes
    ----------
    drawing : ndarray
        (V, S) complex: every slot in each variant's drawing, m.
    ops : ndarray
        (O, 6) int: the plan's operations, each kind, target slot, known slots k1 and k2, body and
        dyad number (−1 where unused); the kinds are :data:`CRANK`, :data:`RIGID`, :data:`GUIDE`,
        :data:`PLACE`, :data:`RRR` and :data:`RRP`.
    op_data : ndarray
        (V, O, 4) each operation's numbers per variant: link lengths (m) and the branch sign of a
        dyad, the guide's direction (dimensionless components), 1/|k2 − k1|² of a rigid body (1/m²).
    grounded : ndarray
        (G,) int: the slots of the frame pivots.
    turn : ndarray
        (N,) complex: the crank's rotation from the drawing at each angle, dimensionless (unit
        modulus).
    omega, alpha : ndarray
        (V, N) crank speed θ̇ (rad/s) and acceleration θ̈ (rad/s²) at each angle, or (1, N): the same
        for every variant.
    mass, inertia : ndarray
        (V, nb) body masses, kg, and moments of inertia about the centres of mass, kg·m².
    gravity : complex
        The acceleration of gravity, m/s².
    keep : ndarray
        (K,) int: the slots whose motion is written to ``pos``, ``vel``, ``acc``.
    output_slot : int
        The slot of the output point (−1: no output), an index.
    output_axis : complex
        The output's upward axis, a unit vector (dimensionless).
    pos, vel, acc : ndarray
        (V, N, K) complex, written: the kept slots' positions (m), velocities (m/s) and
        accelerations (m/s²).
    rates : ndarray
        (V, N, nb, 3), written: each body's rotation from the drawing (rad), angular velocity (rad/s)
        and acceleration (rad/s²); (0, 0, 0, 0) for none.
    force, inertia_force : ndarray
        (V, N) complex, written: the load on the frame and −Σ m a_G, N.
    moment, torque : ndarray
        (V, N), written: the moment on the frame about the origin and the driving torque, N·m.
    stroke : ndarray
        (V, N), written: the output point's position along its axis from the drawing, m; (0, 0)
        without an output.
    dyad_measure : ndarray
        (V, N, D), written: the sine of each dyad's transmission angle, signed (dimensionless).
    load_ops : ndarray
        (D + 1, 16) int: the loads' program from the output back to the crank (:func:`encode_loads`);
        (0, 16) for the motion alone.
    load_data : ndarray
        (D + 1, 2): the guide normal of each RRP dyad (dimensionless components).
    frame_ops : ndarray
        (G, 4) int: each frame joint's kind (0 pin, 1 guide), joint, sign of λ and slot.
    frame_data : ndarray
        (G, 2): a frame guide's normal (dimensionless components).
    joint_kind : ndarray
        (J,) int: 0 for a pin, 1 for a slider (for the force peaks).
    n_multipliers : int
        L, the number of multipliers.
    applied : ndarray
        (V, N, nb, 3) the process forces as loads on the bodies: force (N) and moment about the centre
        of mass (N·m); (0, 0, 0, 0) for none.
    multipliers : ndarray
        (V, N, L), written: the multipliers λ; (0, 0, 0) when not kept.
    peaks : ndarray
        (V, J), written: each joint's largest force over the cycle, N.
    """

    # the plan and the drawing
    drawing: np.ndarray
    ops: np.ndarray
    op_data: np.ndarray
    grounded: np.ndarray
    # the crank's motion
    turn: np.ndarray
    omega: np.ndarray
    alpha: np.ndarray
    # the bodies
    mass: np.ndarray
    inertia: np.ndarray
    gravity: complex
    # the motions kept and the output
    keep: np.ndarray
    output_slot: int
    output_axis: complex
    pos: np.ndarray
    vel: np.ndarray
    acc: np.ndarray
    rates: np.ndarray
    # the frame loads
    force: np.ndarray
    inertia_force: np.ndarray
    moment: np.ndarray
    torque: np.ndarray
    stroke: np.ndarray
    dyad_measure: np.ndarray
    # the loads' program and the joint loads
    load_ops: np.ndarray
    load_data: np.ndarray
    frame_ops: np.ndarray
    frame_data: np.ndarray
    joint_kind: np.ndarray
    n_multipliers: int
    applied: np.ndarray
    multipliers: np.ndarray
    peaks: np.ndarray


# the arrays the kernel only reads
_INPUTS = (
    "drawing",
    "ops",
    "op_data",
    "grounded",
    "turn",
    "omega",
    "alpha",
    "mass",
    "inertia",
    "keep",
    "load_ops",
    "load_data",
    "frame_ops",
    "frame_data",
    "joint_kind",
    "applied",
)


def _read_only(a: np.ndarray) -> np.ndarray:
    view = a.view()
    view.flags.writeable = False
    return view


def kernel_args(**fields: Any) -> KernelArgs:
    """:class:`KernelArgs` with every array the kernel only reads passed as a read-only view (no
    copy).

    numba compiles one version of a kernel per argument type, and a read-only array is another type
    than a writable one: the plan kept with a model is read-only, a fresh batch's is not. Passing
    every input alike makes one signature per kernel, so a first run compiles each kernel once.

    Parameters
    ----------
    **fields
        Every field of :class:`KernelArgs`, by name (units as documented there).

    Returns
    -------
    KernelArgs
    """
    for name in _INPUTS:
        fields[name] = _read_only(fields[name])
    return KernelArgs(**fields)


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a × b for plane vectors written as complex numbers: Im(conj(a) b)."""
    return a.real * b.imag - a.imag * b.real


def _dot(a: np.ndarray, b: np.ndarray | complex) -> np.ndarray:
    return a.real * b.real + a.imag * b.imag


# operation codes of the compiled kernel
CRANK, RIGID, GUIDE, PLACE, RRR, RRP = range(6)


def encode(m: Mechanism, steps: list[Step], draw: dict[str, np.ndarray]) -> tuple[Any, ...]:
    """The plan as integer operations and per-variant data for the kernel.

    Slots 0..P−1 hold the drawing points, P..P+nb−1 the bodies' centres of mass.

    Parameters
    ----------
    m : Mechanism
        The mechanism the plan is of.
    steps : list of Step
        Its plan (:func:`~mechdyn.mechanism.dyads.plan`).
    draw : dict of str to ndarray
        Each drawing point's (V,) complex coordinates in every variant, m.

    Returns
    -------
    tuple
        ``(slot, drawing, ops, op_data, grounded)``: the slot of every point and centre of mass by
        name, then the arrays of :class:`KernelArgs` of those names.
    """
    names = list(m.points)
    slot = {n: i for i, n in enumerate(names)}
    nb = len(m.bodies)
    P = len(names)
    for i, b in enumerate(m.bodies):
        slot[f"__com__{b.name}"] = P + i
    V = next(iter(draw.values())).shape[0]
    dz = np.empty((V, P + nb), dtype=complex)
    for n, i in slot.items():
        dz[:, i] = draw[n] if i < P else _com(m.bodies[i - P], draw)
    n_ops = sum(1 if st.kind in ("rrr", "rrp") else 1 + len(st.target) + 1 for st in steps)
    ops = np.full((n_ops, 6), -1, dtype=np.int64)  # kind, target, k1, k2, body, dyad number
    fdata = np.zeros((V, n_ops, 4))  # per-operation per-variant float data
    grounded = sorted({slot[j.point] for j in m.joints if j.pins and GROUND in j.bodies})
    o = 0
    dyad = 0
    for st in steps:
        bi = m.body_index[st.body] if st.body is not None else -1
        if st.kind in ("rrr", "rrp"):
            assert isinstance(st.target, str)  # a dyad finds one point
            t, k1 = slot[st.target], slot[st.known[0]]
            d1 = dz[:, t] - dz[:, k1]
            fdata[:, o, 0] = np.abs(d1)
            if st.kind == "rrr":
                k2 = slot[st.known[1]]
                ops[o] = (RRR, t, k1, k2, -1, dyad)
                fdata[:, o, 1] = np.abs(dz[:, t] - dz[:, k2])
                fdata[:, o, 2] = np.sign(_cross(dz[:, k2] - dz[:, k1], d1))
            else:
                assert st.guide is not None  # an RRP dyad slides on its guide
                u = complex(math.cos(st.guide.axis), math.sin(st.guide.axis))
                ops[o] = (RRP, t, k1, -1, -1, dyad)
                fdata[:, o, 1] = np.where(_dot(d1, u) >= 0, 1.0, -1.0)
                fdata[:, o, 2:] = u.real, u.imag
            o += 1
            dyad += 1
            continue
        k1 = slot[st.known[0]]
        if st.kind == "crank":
            ops[o, [0, 2, 4]] = CRANK, k1, bi
        elif st.guide is not None:
            ops[o, [0, 2, 4]] = GUIDE, k1, bi
        else:
            k2 = slot[st.known[1]]
            ops[o, [0, 2, 3, 4]] = RIGID, k1, k2, bi
            fdata[:, o, 0] = 1.0 / np.abs(dz[:, k2] - dz[:, k1]) ** 2
        # place every remaining point of the body and its centre of mass from k1
        for tname in (*st.target, f"__com__{m.bodies[bi].name}"):
            o += 1
            ops[o, :5] = PLACE, slot[tname], k1, -1, bi
        o += 1
    return slot, dz, ops, fdata, np.array(grounded, dtype=np.int64)


def encode_loads(m: Mechanism, steps: list[Step], slot: dict[str, int]) -> tuple[np.ndarray, ...]:
    """The loads' program for the kernel: the dyads from the output back to the crank, the frame's
    joints, and each joint's kind (pin or slider) for its force peak.

    Parameters
    ----------
    m : Mechanism
        The mechanism the plan is of.
    steps : list of Step
        Its plan (:func:`~mechdyn.mechanism.dyads.plan`).
    slot : dict of str to int
        The slot of every point and centre of mass (:func:`encode`), an index.

    Returns
    -------
    tuple of ndarray
        ``(load_ops, load_data, frame_ops, frame_data, joint_kind)`` of :class:`KernelArgs`.
    """
    joints = list(m.joints)
    idx = m.body_index

    def body(name: str) -> int:
        return -1 if name == GROUND else idx[name]

    def joint_at(point: str, on: str, other: str | None = None) -> int:
        for k, jt in enumerate(joints):
            if jt.pins and jt.point == point and on in jt.bodies:
                o = jt.bodies[1] if jt.bodies[0] == on else jt.bodies[0]
                if other is None or o != other:
                    return k
        raise KeyError((point, on))

    def record(k: int, on: str) -> list[int]:
        """[joint, sign of λ for a force on ``on``, the other body that takes its reaction]."""
        jt = joints[k]
        other = jt.bodies[0] if on == jt.bodies[1] else jt.bodies[1]
        return [k, 1 if on == jt.bodies[1] else -1, body(other)]

    kops, kf = [], []
    for st in reversed(steps):
        row = [0] * 16
        if st.kind == "rrr":
            assert isinstance(st.target, str)  # an RRR dyad finds one point
            p = st.target
            k1, k2 = st.known
            kp = next(
                k for k, jt in enumerate(joints) if jt.pins and jt.point == p and GROUND not in jt.bodies
            )
            jb = joints[kp].bodies
            b1 = jb[0] if k1 in m.bodies[idx[jb[0]]].points else jb[1]
            b2 = jb[1] if b1 == jb[0] else jb[0]
            row[:6] = [0, slot[p], slot[k1], slot[k2], idx[b1], idx[b2]]
            row[6:9] = record(joint_at(k1, b1, b2), b1)
            row[9:12] = record(joint_at(k2, b2, b1), b2)
            row[12:14] = [kp, 1 if joints[kp].bodies[1] == b2 else -1]
            kf.append((0.0, 0.0))
        elif st.kind == "rrp":
            target, (k1,), sl = st.target, st.known, st.body
            assert isinstance(target, str) and sl is not None and st.guide is not None  # one point
            p = target
            kg = joints.index(st.guide)
            kp = joint_at(p, sl)
            b1 = joints[kp].bodies[0] if joints[kp].bodies[1] == sl else joints[kp].bodies[1]
            row[:6] = [1, slot[p], slot[k1], -1, idx[b1], idx[sl]]
            row[6:9] = record(joint_at(k1, b1, sl), b1)
            row[9:12] = [kp, 1 if joints[kp].bodies[1] == sl else -1, kg]
            kf.append((-math.sin(st.guide.axis), math.cos(st.guide.axis)))
        else:
            continue
        kops.append(row)
    crank = m.driver.body
    k0 = joint_at(m.driver.pivot, crank)
    row = [0] * 16
    row[:8] = [
        2,
        slot[m.driver.pivot],
        -1,
        -1,
        idx[crank],
        -1,
        k0,
        1 if joints[k0].bodies[1] == crank else -1,
    ]
    kops.append(row)
    kf.append((0.0, 0.0))
    gops, gf = [], []
    for k, jt in enumerate(joints):
        if GROUND not in jt.bodies:
            continue
        if jt.pins:
            gops.append((0, k, 1 if jt.bodies[1] == GROUND else -1, slot[jt.point]))
            gf.append((0.0, 0.0))
        else:  # a slider on a frame guide (the planner allows no other)
            axis = cast(Prismatic, jt).axis
            gops.append((1, k, 0, slot[jt.point]))
            gf.append((-math.sin(axis), math.cos(axis)))
    return (
        np.array(kops, dtype=np.int64).reshape(-1, 16),
        np.array(kf, dtype=float).reshape(-1, 2),
        np.array(gops, dtype=np.int64).reshape(-1, 4),
        np.array(gf, dtype=float).reshape(-1, 2),
        np.array([0 if jt.pins else 1 for jt in joints], dtype=np.int64),
    )


def _com(body, draw: Mapping[str, np.ndarray]) -> np.ndarray | complex:
    """A body's centre of mass in each variant's drawing (the same in all when given as coordinates)."""
    c = body.center_of_mass
    if c is None:
        return sum(draw[p] for p in body.points) / len(body.points)
    if isinstance(c, str):
        return draw[c]
    return complex(c[0], c[1])


def motion_only(
    drawing: np.ndarray,
    ops: np.ndarray,
    op_data: np.ndarray,
    grounded: np.ndarray,
    turn: np.ndarray,
    omega: np.ndarray,
    alpha: np.ndarray,
    mass: np.ndarray,
    inertia: np.ndarray,
    gravity: complex,
    dyad_measure: np.ndarray,
) -> KernelArgs:
    """The kernel's arguments for one variant's dyad measures alone: no point kept, no output, no
    loads (what the screening between the samples asks for).

    Parameters
    ----------
    drawing, ops, op_data, grounded : ndarray
        The encoded plan of one variant (:func:`encode`).
    turn : ndarray
        (M,) complex: the crank's rotation from the drawing at each angle, dimensionless.
    omega, alpha : ndarray
        (1, M) crank speed (rad/s) and acceleration (rad/s²) at each angle.
    mass, inertia : ndarray
        (1, nb) body masses, kg, and moments of inertia, kg·m².
    gravity : complex
        m/s².
    dyad_measure : ndarray
        (1, M, D), written: the sine of each dyad's transmission angle (dimensionless).
    """
    M = turn.size
    return kernel_args(
        drawing=drawing,
        ops=ops,
        op_data=op_data,
        grounded=grounded,
        turn=turn,
        omega=omega,
        alpha=alpha,
        mass=mass,
        inertia=inertia,
        gravity=gravity,
        keep=np.empty(0, dtype=np.int64),
        output_slot=-1,
        output_axis=0j,
        pos=np.empty((1, M, 0), dtype=complex),
        vel=np.empty((1, M, 0), dtype=complex),
        acc=np.empty((1, M, 0), dtype=complex),
        rates=np.empty((0, 0, 0, 0)),
        force=np.empty((1, M), dtype=complex),
        inertia_force=np.empty((1, M), dtype=complex),
        moment=np.empty((1, M)),
        torque=np.empty((1, M)),
        stroke=np.empty((0, 0)),
        dyad_measure=dyad_measure,
        load_ops=np.zeros((0, 16), dtype=np.int64),
        load_data=np.zeros((0, 2)),
        frame_ops=np.zeros((0, 4), dtype=np.int64),
        frame_data=np.zeros((0, 2)),
        joint_kind=np.zeros(0, dtype=np.int64),
        n_multipliers=0,
        applied=np.zeros((0, 0, 0, 0)),
        multipliers=np.zeros((0, 0, 0)),
        peaks=np.zeros((1, 0)),
    )
