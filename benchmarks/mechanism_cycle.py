"""Full inverse dynamics of the link-drive press over one revolution: mechdyn against a per-angle loop.

    python benchmarks/mechanism_cycle.py            # 360 angles; batch of 10^4 variants
    python benchmarks/mechanism_cycle.py --quick    # batch of 10^3 variants, within a minute
    python benchmarks/mechanism_cycle.py --json     # one JSON object with the times and ratios

Baseline, measured in the same run: the way a hand-written script does it — at every crank angle,
``scipy.optimize.fsolve`` on the published four loop-closure equations (SPEC §1) from the previous
angle, velocities and accelerations by central differences of the positions, then the Newton–Euler
equations of the five bodies solved per angle for every joint load and the driving torque.

mechdyn: ``inverse_dynamics`` (closed-form dyads, Jacobian solves for the joint loads) and with
``method="newton"`` (the general engine), and ``dyads.cycle`` over a batch of design variants (the
frame pivot D and the rocker joint C moved by a few centimetres): driving torque, shaking force and
moment of every variant at every angle. The figures printed are wall times and their ratios; the
results are compared so that fast means right.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np
from _timing import best_time
from scipy.optimize import fsolve

import mechdyn
from mechdyn.mechanism.constraints import ConstraintSet
from mechdyn.mechanism.dyads import cycle
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
    t_dyads, d = best_time(lambda: inverse_dynamics(mech, n, method="dyads"), max_repeats=50)
    t_newton, dn = best_time(lambda: inverse_dynamics(mech, n, method="newton"), max_repeats=1)
    rng = np.random.default_rng(0)
    pts = {k: np.asarray(mech.points[k]) + rng.normal(scale=0.03, size=(variants, 2)) for k in ("C", "D")}
    t_batch, batch = best_time(
        lambda: cycle(mech, n, points=pts, store_points=False), max_repeats=3, budget=10.0
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
        "mechdyn_newton_engine_s": t_newton,
        "newton_ratio_vs_loop": t_loop / t_newton,
        "batch_variants": variants,
        "batch_s": t_batch,
        "variant_cycles_per_s": variants / t_batch,
        "batch_assembled": int(batch.assembled.sum()),
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
        (f"batch of {variants} variants", t_batch, f"{variants / t_batch:7.0f} variant-cycles/s"),
    ]
    for label, t, note in rows:
        print(f"{label:42s}{t * 1e3:9.1f} ms   {note}")
    print(f"torque agreement: loop {diff_loop:.1e} (finite differences), Newton {diff_newton:.1e}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
