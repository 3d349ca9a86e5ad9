"""Full inverse dynamics of the link-drive press over one revolution: mechdyn against a per-angle loop.

    python benchmarks/mechanism_cycle.py            # 360 angles; batch of 10^4 variants (summary 3·10^4)
    python benchmarks/mechanism_cycle.py --quick    # batch of 10^3 variants (summary 10^4), within a minute
    python benchmarks/mechanism_cycle.py --json     # one JSON object with the times and ratios

Baseline, measured in the same run: the way a hand-written script does it — at every crank angle,
``scipy.optimize.fsolve`` on the published four loop-closure equations (SPEC §1) from the previous
angle, velocities and accelerations by central differences of the positions, then the Newton–Euler
equations of the five bodies solved per angle for every joint load and the driving torque.

A second baseline for the single design: the bare dyad-by-dyad NumPy form of the same press on the
same data (:func:`bare_dyads`): closed-form RRR and RRP dyads over all angles at once, velocities
and accelerations from each dyad's differentiated constraints, and the fifteen Newton–Euler
equations of the five bodies solved for every angle in one batched ``numpy.linalg.solve`` (as
``small_model.py`` does for the four-bar). ``ratio_vs_bare_dyads`` is mechdyn's time over it.

mechdyn: ``inverse_dynamics`` (closed-form dyads, Jacobian solves for the joint loads; what
``mechdyn mechanism`` and ``analyse`` call) and with ``method="newton"`` (the general engine), and
``dyads.cycle`` over a batch of design variants (the frame pivot D and the rocker joint C moved by a
few centimetres): driving torque, shaking force and moment of every variant at every angle. Then the
summary-only batch (``dyads.cycle_summary``, what a study that stores scalars runs): the same
variants reduced to their figures in chunks, timed beside the full batch, and its peak memory
(``tracemalloc``) per variant at a large batch (10^4 quick, 3·10^4 full) and its growth per variant,
beside the full batch's. The figures printed are wall times and their ratios; the results are compared so
that fast means right.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
import tracemalloc
from pathlib import Path

import numpy as np
from _timing import best_time
from scipy.optimize import fsolve

import mechdyn
from mechdyn.mechanism.constraints import ConstraintSet
from mechdyn.mechanism.dyads import cycle, cycle_summary
from mechdyn.mechanism.dynamics import inverse_dynamics

PRESS = Path(__file__).resolve().parents[1] / "examples" / "press_link_drive.toml"


def per_angle_loop(mech, n: int) -> np.ndarray:
    """The hand-written way; returns the driving torque over the cycle (in mechdyn's angle order)."""
    P = {k: np.asarray(v) for k, v in mech.points.items()}
    A, B, C, D, E, F = (P[k] for k in "ABCDEF")
    r, r1, r2 = np.linalg.norm(B - A), np.linalg.norm(C - B), np.linalg.norm(E - B)
    l1, l2 = np.linalg.norm(D - C), np.linalg.norm(F - E)
    ang = lambda v: math.atan2(v[1], v[0])  # noqa: E731
    c = ang(E - B) - ang(C - B)
    yf = F[1]
    theta0 = ang(B - A)
    thetas = theta0 + 2 * math.pi / n * np.arange(n) * math.copysign(1, mech.driver.speed)

    def loops(x, th):
        t1, t2, t3, t4 = x  # angles of BC, BE, DC, EF
        b = A + r * np.array([math.cos(th), math.sin(th)])
        return [
            b[0] + r1 * math.cos(t1) - D[0] - l1 * math.cos(t3),
            b[1] + r1 * math.sin(t1) - D[1] - l1 * math.sin(t3),
            t2 - t1 - c,
            b[1] + r2 * math.sin(t2) + l2 * math.sin(t4) - yf,
        ]

    x = np.array([ang(C - B), ang(E - B), ang(C - D), ang(F - E)])
    sol = np.empty((n, 4))
    for k, th in enumerate(thetas):
        x = fsolve(loops, x, args=(th,), xtol=1e-13)
        sol[k] = x
    # body coordinates (centres of mass) at every angle, as a script would assemble them
    cs = ConstraintSet(mech)
    q = np.empty((n, cs.n))
    for k, th in enumerate(thetas):
        t1, t2, t3, t4 = sol[k]
        b = A + r * np.array([math.cos(th), math.sin(th)])
        pts = {"A": A, "B": b, "C": b + r1 * np.array([math.cos(t1), math.sin(t1)]), "D": D}
        pts["E"] = b + r2 * np.array([math.cos(t2), math.sin(t2)])
        pts["F"] = pts["E"] + l2 * np.array([math.cos(t4), math.sin(t4)])
        rot = {
            "crank": th - theta0,
            "ternary": t1 - ang(C - B),
            "rocker": t3 - ang(C - D),
            "connecting rod": t4 - ang(F - E),
            "slide": 0.0,
        }
        for i, body in enumerate(mech.bodies):
            ref = body.points[0]
            phi = rot[body.name]
            s = mech.com(body) - P[ref]
            q[k, 3 * i : 3 * i + 2] = pts[ref] + [
                math.cos(phi) * s[0] - math.sin(phi) * s[1],
                math.sin(phi) * s[0] + math.cos(phi) * s[1],
            ]
            q[k, 3 * i + 2] = phi
    q[:, 2::3] = np.unwrap(q[:, 2::3], axis=0)
    # central differences over the periodic cycle: pad with the neighbours across the wrap, a body
    # that turns right round (the crank) carrying its whole turn
    turn = np.zeros(q.shape[1])
    turn[2::3] = 2 * math.pi * np.round((2 * q[-1, 2::3] - q[-2, 2::3] - q[0, 2::3]) / (2 * math.pi))
    ext = np.vstack([q[-1] - turn, q, q[0] + turn])
    dt = 2 * math.pi / n / abs(mech.driver.speed)
    qdd = (ext[2:] - 2 * q + ext[:-2]) / dt**2
    mass = np.repeat(mech.masses, 3).reshape(-1, 3)
    mass[:, 2] = mech.inertias
    torque = np.empty(n)
    for k in range(n):
        ev = cs.evaluate(q[k], np.asarray(thetas[k]))
        lam = np.linalg.solve(ev.jacobian.T, -mass.ravel() * qdd[k])
        torque[k] = -lam[-1]
    return torque


def _solve2(a1, b1, a2, b2):
    """The plane vector v (complex) with v·a1 = b1 and v·a2 = b2 (Cramer's rule)."""
    det = a1.real * a2.imag - a1.imag * a2.real
    return ((b1 * a2.imag - b2 * a1.imag) + 1j * (a1.real * b2 - a2.real * b1)) / det


def _dot(a, b):
    return a.real * b.real + a.imag * b.imag


def _cross(a, b):
    return a.real * b.imag - a.imag * b.real


def bare_dyads(mech, theta: np.ndarray) -> np.ndarray:
    """Driving torque of press A at crank angles ``theta`` (rad, from +x) at constant speed, dyad by
    dyad: closed-form positions (the RRR dyad B–C–D, the ternary's point E, the RRP dyad E–F on the
    guide), velocities and accelerations from each dyad's differentiated constraints, then the
    fifteen Newton–Euler equations of the five bodies solved for all angles in one batched
    ``numpy.linalg.solve``."""
    P = {k: complex(*v) for k, v in mech.points.items()}
    A, B0, C0, D, E0, F0 = (P[k] for k in "ABCDEF")
    guide = next(j for j in mech.joints if not j.pins)
    u = complex(math.cos(guide.axis), math.sin(guide.axis))
    n = 1j * u  # the guide's normal
    r, r1, l1, L = abs(B0 - A), abs(C0 - B0), abs(C0 - D), abs(F0 - E0)
    sg_c = math.copysign(1.0, _cross(D - B0, C0 - B0))
    sg_f = 1.0 if _dot(F0 - E0, u) >= 0 else -1.0
    w = mech.driver.speed
    g = complex(*mech.gravity)
    rot0 = (B0 - A) / r
    # positions: the crank, the circle–circle dyad at C, the ternary's E, the circle–line dyad at F
    Bz = A + rot0 * r * np.exp(1j * (theta - math.atan2(rot0.imag, rot0.real)))
    d = D - Bz
    dist = np.abs(d)
    x = (dist**2 + r1**2 - l1**2) / (2 * dist)
    C = Bz + d / dist * (x + 1j * sg_c * np.sqrt(r1**2 - x**2))
    rot2 = (C - Bz) * np.conj(C0 - B0) / r1**2
    E = Bz + rot2 * (E0 - B0)
    wq = F0 - E
    bq = _dot(wq, u)
    F = F0 + (-bq + sg_f * np.sqrt(bq**2 - (np.abs(wq) ** 2 - L**2))) * u
    # velocities and accelerations (θ̇ = w, θ̈ = 0)
    vB, aB = 1j * w * (Bz - A), -(w**2) * (Bz - A)
    a1, a2 = C - Bz, C - D
    vC = _solve2(a1, _dot(a1, vB), a2, 0.0)
    aC = _solve2(a1, _dot(a1, aB) - np.abs(vC - vB) ** 2, a2, -(np.abs(vC) ** 2))
    w2, al2 = _cross(a1, vC - vB) / r1**2, _cross(a1, aC - aB) / r1**2
    w3, al3 = _cross(a2, vC) / l1**2, _cross(a2, aC) / l1**2
    rE = E - Bz
    vE, aE = vB + 1j * w2 * rE, aB + (1j * al2 - w2**2) * rE
    rel = F - E
    vF = _dot(rel, vE) / _dot(rel, u) * u
    aF = (_dot(rel, aE) - np.abs(vF - vE) ** 2) / _dot(rel, u) * u
    w4, al4 = _cross(rel, vF - vE) / L**2, _cross(rel, aF - aE) / L**2
    # centres of mass, each carried by its body from the point it hangs on
    motion = {  # reference point now and in the drawing, its acceleration, rotation, ω, α
        "crank": (A, A, 0.0, (Bz - A) / (B0 - A), w, 0.0),
        "ternary": (Bz, B0, aB, rot2, w2, al2),
        "rocker": (D, D, 0.0, a2 / (C0 - D), w3, al3),
        "connecting rod": (E, E0, aE, rel / (F0 - E0), w4, al4),
        "slide": (F, F0, aF, 1.0, 0.0, 0.0),
    }
    G, aG, alpha = [], [], []
    for body in mech.bodies:
        p, p0, ap, rot, wb, ab = motion[body.name]
        s = rot * (complex(*mech.com(body)) - p0)
        G.append(p + s)
        aG.append(ap + (1j * ab - wb**2) * s)
        alpha.append(ab)
    # Newton–Euler: unknowns F_A, F_B, F_C, F_D, F_E, F_F (x, y: the force on the second body the
    # joint names), the guide's normal force and couple on the slide, the driving torque
    N = theta.size
    S = np.zeros((N, 15, 15))
    b = np.zeros((N, 15))

    def force(row: int, col: int, sign: float, at, body: int) -> None:
        arm = at - G[body]
        S[:, row, col], S[:, row + 1, col + 1] = sign, sign
        S[:, row + 2, col], S[:, row + 2, col + 1] = -sign * arm.imag, sign * arm.real

    FA, FB, FC, FD, FE, FF = range(0, 12, 2)
    force(0, FA, 1.0, A, 0)
    force(0, FB, -1.0, Bz, 0)
    S[:, 2, 14] = 1.0
    force(3, FB, 1.0, Bz, 1)
    force(3, FC, -1.0, C, 1)
    force(3, FE, -1.0, E, 1)
    force(6, FC, 1.0, C, 2)
    force(6, FD, 1.0, D, 2)
    force(9, FE, 1.0, E, 3)
    force(9, FF, -1.0, F, 3)
    force(12, FF, 1.0, F, 4)
    S[:, 12, 12], S[:, 13, 12] = n.real, n.imag
    S[:, 14, 12] = _cross(F - G[4], n)
    S[:, 14, 13] = 1.0
    for i in range(len(mech.bodies)):
        f = mech.masses[i] * (aG[i] - g)
        b[:, 3 * i], b[:, 3 * i + 1] = f.real, f.imag
        b[:, 3 * i + 2] = mech.inertias[i] * alpha[i]
    return np.linalg.solve(S, b[..., None])[:, 14, 0]


def _peak_bytes(fn) -> int:
    """Peak memory (bytes) that ``fn()`` allocates, by ``tracemalloc``."""
    tracemalloc.start()
    try:
        fn()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="a batch of 10^3 variants (within a minute)")
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    args = ap.parse_args(argv)
    mech = mechdyn.load(PRESS).model
    n = 360
    variants = 1000 if args.quick else 10_000
    cycle(mech, 8)  # compile the kernel (cached on disk) before timing
    # the best of several runs of each (what timeit recommends), within half a second each
    t_loop, torque_loop = best_time(lambda: per_angle_loop(mech, n), max_repeats=3)
    d = inverse_dynamics(mech, n)
    theta = d.kinematics.crank_angle
    # the single design and the bare dyad form, alternating, the best of each
    t_dyads = t_bare = math.inf
    for _ in range(5 if args.quick else 20):
        t_dyads = min(t_dyads, best_time(lambda: inverse_dynamics(mech, n), max_repeats=20, budget=0.1)[0])
        t_bare = min(t_bare, best_time(lambda: bare_dyads(mech, theta), max_repeats=20, budget=0.1)[0])
    t_newton, dn = best_time(lambda: inverse_dynamics(mech, n, method="newton"), max_repeats=1)
    rng = np.random.default_rng(0)
    pts = {k: np.asarray(mech.points[k]) + rng.normal(scale=0.03, size=(variants, 2)) for k in ("C", "D")}
    t_batch, batch = best_time(
        lambda: cycle(mech, n, points=pts, store_points=False), max_repeats=3, budget=10.0
    )
    cycle_summary(mech, n, points={k: v[:8] for k, v in pts.items()})  # compiled before timing
    t_summary, summ = best_time(lambda: cycle_summary(mech, n, points=pts), max_repeats=3, budget=10.0)
    # memory: the summary's peak per variant at a large batch (10^4 quick, 3·10^4 full) and its growth
    # per variant from a quarter of that (what each more variant costs; the chunk buffers are fixed)
    large = 10_000 if args.quick else 30_000
    rng_large = np.random.default_rng(1)
    big = {k: np.asarray(mech.points[k]) + rng_large.normal(scale=0.03, size=(large, 2)) for k in ("C", "D")}
    quarter = {k: v[: large // 4] for k, v in big.items()}
    peak_large = _peak_bytes(lambda: cycle_summary(mech, n, points=big))
    peak_quarter = _peak_bytes(lambda: cycle_summary(mech, n, points=quarter))
    t_large, _ = best_time(lambda: cycle_summary(mech, n, points=big), max_repeats=2, budget=5.0)
    # CPU seconds (every thread's) per variant: what the figures above cost on a shared machine
    cpu = time.process_time()
    cycle_summary(mech, n, points=big)
    cpu_summary = (time.process_time() - cpu) / large
    cpu = time.process_time()
    cycle(mech, n, points=pts, store_points=False).summary()
    cpu_batch = (time.process_time() - cpu) / variants
    bytes_summary = peak_large / large
    bytes_growth = (peak_large - peak_quarter) / (large - large // 4)
    bytes_full = _peak_bytes(lambda: cycle(mech, n, points=pts, store_points=False).summary()) / variants
    full = batch.summary()
    diff_summary = max(
        float(np.nanmax(np.abs(summ.figures[k] - full[k]) / np.maximum(np.abs(full[k]), 1e-300)))
        for k in summ.figures
    )
    diff_bare = float(
        np.abs(bare_dyads(mech, theta) - d.driving_torque).max() / np.abs(d.driving_torque).max()
    )
    # agreement: the loop differences positions, so it agrees to its truncation error only
    order = np.argsort(d.kinematics.crank_angle % (2 * math.pi))
    thetas = (mech.drawing_crank_angle + 2 * math.pi / n * np.arange(n)) % (2 * math.pi)
    loop_sorted = torque_loop[np.argsort(thetas)]
    diff_loop = float(np.abs(loop_sorted - d.driving_torque[order]).max() / np.abs(d.driving_torque).max())
    diff_newton = float(np.abs(dn.driving_torque - d.driving_torque).max() / np.abs(d.driving_torque).max())
    result = {
        "benchmark": "mechanism_cycle",
        "quick": args.quick,
        "angles": n,
        "per_angle_fsolve_loop_s": t_loop,
        "mechdyn_inverse_dynamics_s": t_dyads,
        "ratio_vs_loop": t_loop / t_dyads,
        "bare_dyads_s": t_bare,
        "ratio_vs_bare_dyads": t_dyads / t_bare,
        "mechdyn_newton_engine_s": t_newton,
        "newton_ratio_vs_loop": t_loop / t_newton,
        "batch_variants": variants,
        "batch_s": t_batch,
        "variant_cycles_per_s": variants / t_batch,
        "batch_assembled": int(batch.assembled.sum()),
        "batch_bytes_per_variant": bytes_full,
        "summary_s": t_summary,
        "summary_variant_cycles_per_s": variants / t_summary,
        "summary_bytes_per_variant": bytes_summary,
        "summary_bytes_growth_per_variant": bytes_growth,
        "summary_large_variants": large,
        "summary_large_variant_cycles_per_s": large / t_large,
        "summary_cpu_s_per_variant": cpu_summary,
        "batch_with_summary_cpu_s_per_variant": cpu_batch,
        "summary_at_batch_size_bytes_per_variant": _peak_bytes(lambda: cycle_summary(mech, n, points=pts))
        / variants,
        "summary_assembled": int(summ.assembled.sum()),
        "max_rel_diff_summary_vs_batch": diff_summary,
        "max_rel_diff_bare_dyads": diff_bare,
        "max_rel_diff_loop": diff_loop,
        "max_rel_diff_newton": diff_newton,
    }
    if args.json:
        print(json.dumps(result, indent=2))
        return 0
    rows = [
        ("per-angle fsolve loop (360 angles)", t_loop, ""),
        ("mechdyn inverse dynamics (dyads)", t_dyads, f"{t_loop / t_dyads:7.0f}× the loop"),
        ("mechdyn inverse dynamics (Newton engine)", t_newton, f"{t_loop / t_newton:7.1f}× the loop"),
        ("bare dyad-by-dyad NumPy form", t_bare, f"{t_dyads / t_bare:7.2f}× mechdyn / bare"),
        (f"batch of {variants} variants", t_batch, f"{variants / t_batch:7.0f} variant-cycles/s"),
        (f"summary-only batch of {variants}", t_summary, f"{variants / t_summary:7.0f} variant-cycles/s"),
        (f"summary-only batch of {large}", t_large, f"{large / t_large:7.0f} variant-cycles/s"),
    ]
    for label, t, note in rows:
        print(f"{label:42s}{t * 1e3:9.1f} ms   {note}")
    print(
        f"CPU per variant (all threads): summary only {cpu_summary * 1e6:.0f} µs, full batch and its "
        f"summary {cpu_batch * 1e6:.0f} µs"
    )
    print(
        f"memory per variant: full batch {bytes_full:.0f} B ({variants}); summary only {bytes_summary:.0f} B "
        f"({large}), growing by {bytes_growth:.0f} B per variant"
    )
    print(
        f"agreement: loop {diff_loop:.1e} (finite differences), Newton {diff_newton:.1e}, bare dyads "
        f"{diff_bare:.1e}, summary vs batch {diff_summary:.1e}"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
