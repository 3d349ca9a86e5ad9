"""Per-call cost of the Python API on small models, against the bare solve they wrap.

    python benchmarks/small_model.py            # more repeats
    python benchmarks/small_model.py --quick    # within a few seconds
    python benchmarks/small_model.py --json     # one JSON object with the times and ratios

A design study evaluates a 10-disk drivetrain or a four-bar thousands of times, so what the API adds
around the numerical core matters. Two cases, each timed in the same run as its baseline:

* ``modal`` of a 10-disk chain, against ``scipy.linalg.eigh(K, M)`` on the same assembled matrices.
  Timed three times: on a built model (a study's repeated analyses of one variant: the assembly is
  kept with the immutable model); a new variant of the built model (:meth:`Drivetrain.with_values`
  with all 19 values, then ``modal``: the values checked, the structure reused); and from the element
  lists (a new variant each call: build, check, assemble, solve).
* ``inverse_dynamics`` of the crank-rocker of ``examples/fourbar.toml`` at 360 crank angles, against
  a bare NumPy solution written here from the textbook equations: closed-form four-bar positions, the
  velocity and acceleration loop equations, and the 9 × 9 Newton–Euler system of the three links
  solved for all angles in one batched ``numpy.linalg.solve`` (e.g. Norton, *Design of Machinery*,
  ch. 11). The driving torques must agree to round-off.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np
import scipy.linalg as sla
from _timing import best_time

import mechdyn
from mechdyn.drivetrain import Disk, Drivetrain, Shaft, modal
from mechdyn.mechanism import inverse_dynamics

FOURBAR = Path(__file__).resolve().parents[1] / "examples" / "fourbar.toml"


def _per_call(fn, quick: bool) -> float:
    """Best mean time of a batch of calls (small calls are timed in batches)."""
    calls = 20 if quick else 200

    def batch():
        for _ in range(calls):
            fn()

    t, _ = best_time(batch, budget=0.2 if quick else 1.0, max_repeats=3 if quick else 7)
    return t / calls


def modal_case(quick: bool) -> dict:
    rng = np.random.default_rng(0)
    n = 10
    J, k = rng.uniform(0.5, 2.0, n) * 1e-2, rng.uniform(0.5, 2.0, n - 1) * 1e5

    def build() -> Drivetrain:
        disks = [Disk(f"d{i}", J[i]) for i in range(n)]
        return Drivetrain(disks, [Shaft(f"s{i}", (f"d{i}", f"d{i + 1}"), k[i]) for i in range(n - 1)])

    model = build()
    asm = model.assembly
    K, M = asm.K.toarray(), np.diag(asm.mass)
    t_bare = _per_call(lambda: sla.eigh(K, M), quick)
    t_model = _per_call(lambda: modal(model), quick)
    t_variant = _per_call(lambda: modal(build()), quick)
    new_values = {"inertia": {f"d{i}": float(1.1 * J[i]) for i in range(n)}}
    new_values["stiffness"] = {f"s{i}": float(0.9 * k[i]) for i in range(n - 1)}
    t_values = _per_call(lambda: modal(model.with_values(**new_values)), quick)
    lam = sla.eigh(K, M, eigvals_only=True)
    diff = float(np.max(np.abs(modal(model).omega / np.sqrt(lam[1:]) - 1)))
    return {
        "case": "modal, 10-disk chain",
        "bare_eigh_s": t_bare,
        "mechdyn_modal_s": t_model,
        "ratio_modal_vs_bare": t_model / t_bare,
        "mechdyn_with_values_and_modal_s": t_values,
        "ratio_with_values_and_modal_vs_bare": t_values / t_bare,
        "mechdyn_build_and_modal_s": t_variant,
        "ratio_build_and_modal_vs_bare": t_variant / t_bare,
        "max_rel_diff_vs_bare": diff,
    }


def _rot(v: np.ndarray, phi: np.ndarray) -> np.ndarray:
    c, s = np.cos(phi), np.sin(phi)
    return np.stack([c * v[0] - s * v[1], s * v[0] + c * v[1]], axis=-1)


def _cross(r: np.ndarray) -> np.ndarray:
    """(N, 2) r → the (N, 2) row of r × F as a function of F = (Fx, Fy): (−r_y, r_x)."""
    return np.stack([-r[:, 1], r[:, 0]], axis=-1)


def bare_fourbar(mech, crank_angle: np.ndarray) -> np.ndarray:
    """Driving torque of a four-bar O2-A-B-O4 at constant crank speed, from the loop equations."""
    P = {k: np.asarray(v, dtype=float) for k, v in mech.points.items()}
    O2, A0, B0, O4 = P["O2"], P["A"], P["B"], P["O4"]
    r2, r3, r4 = (np.linalg.norm(A0 - O2), np.linalg.norm(B0 - A0), np.linalg.norm(B0 - O4))
    w2 = mech.driver.speed
    g = np.asarray(mech.gravity, dtype=float)
    m1, m2, m3 = mech.masses
    i1, i2, i3 = mech.inertias
    th2 = crank_angle
    e = lambda a: np.stack([np.cos(a), np.sin(a)], axis=-1)  # noqa: E731
    p = lambda a: np.stack([-np.sin(a), np.cos(a)], axis=-1)  # noqa: E731
    # positions: B where the circles about A (r3) and O4 (r4) meet, on the drawing's branch
    A = O2 + r2 * e(th2)
    d = O4 - A
    L = np.linalg.norm(d, axis=1)
    a = (r3**2 - r4**2 + L**2) / (2 * L)
    h = np.sqrt(r3**2 - a**2)
    u = d / L[:, None]
    to_b, to_o4 = B0 - A0, O4 - A0
    side = np.sign(to_o4[0] * to_b[1] - to_o4[1] * to_b[0])  # B left (+1) or right of A → O4
    B = A + a[:, None] * u + side * h[:, None] * np.stack([-u[:, 1], u[:, 0]], axis=-1)
    th3 = np.arctan2(*(B - A).T[::-1])
    th4 = np.arctan2(*(B - O4).T[::-1])
    # velocities and accelerations: r2 w2 p2 + r3 w3 p3 = r4 w4 p4 and its derivative (α2 = 0)
    Mv = np.stack([r3 * p(th3), -r4 * p(th4)], axis=-1)  # (N, 2, 2) for (w3, w4)
    w3, w4 = np.linalg.solve(Mv, (-r2 * w2 * p(th2))[..., None])[..., 0].T
    rhs = r2 * w2**2 * e(th2) + r3 * w3[:, None] ** 2 * e(th3) - r4 * w4[:, None] ** 2 * e(th4)
    a3, a4 = np.linalg.solve(Mv, rhs[..., None])[..., 0].T
    # centres of mass, fixed in each link, and their accelerations
    phi1, phi3, phi4 = (
        th2 - np.arctan2(*(A0 - O2)[::-1]),
        th3 - np.arctan2(*(B0 - A0)[::-1]),
        th4 - np.arctan2(*(B0 - O4)[::-1]),
    )
    coms = [mech.com(b) for b in mech.bodies]
    s1, s2, s3 = _rot(coms[0] - O2, phi1), _rot(coms[1] - A0, phi3), _rot(coms[2] - O4, phi4)
    G1, G2, G3 = O2 + s1, A + s2, O4 + s3
    aA = -(w2**2) * (A - O2)
    acc1 = -(w2**2) * s1
    acc2 = aA + a3[:, None] * _cross(s2) - w3[:, None] ** 2 * s2
    acc3 = a4[:, None] * _cross(s3) - w4[:, None] ** 2 * s3
    # unknowns: F_O2 (ground on crank), F_A (crank on coupler), F_B (coupler on rocker),
    # F_O4 (ground on rocker), T (driver on crank); three equations per link
    N = th2.size
    S = np.zeros((N, 9, 9))
    b = np.zeros((N, 9))
    eye = np.eye(2)
    S[:, 0:2, 0:2], S[:, 0:2, 2:4] = eye, -eye
    S[:, 2, 0:2], S[:, 2, 2:4], S[:, 2, 8] = _cross(O2 - G1), -_cross(A - G1), 1.0
    S[:, 3:5, 2:4], S[:, 3:5, 4:6] = eye, -eye
    S[:, 5, 2:4], S[:, 5, 4:6] = _cross(A - G2), -_cross(B - G2)
    S[:, 6:8, 4:6], S[:, 6:8, 6:8] = eye, eye
    S[:, 8, 4:6], S[:, 8, 6:8] = _cross(B - G3), _cross(O4 - G3)
    b[:, 0:2] = m1 * (acc1 - g)
    b[:, 2] = 0.0 * i1  # constant crank speed
    b[:, 3:5] = m2 * (acc2 - g)
    b[:, 5] = i2 * a3
    b[:, 6:8] = m3 * (acc3 - g)
    b[:, 8] = i3 * a4
    return np.linalg.solve(S, b[..., None])[:, 8, 0]


def fourbar_case(quick: bool) -> dict:
    mech = mechdyn.load(FOURBAR).model
    n = 360
    inverse_dynamics(mech, n)  # the numba kernel compiles (or loads from its cache) before timing
    d = inverse_dynamics(mech, n)
    theta = d.kinematics.crank_angle
    t_bare = _per_call(lambda: bare_fourbar(mech, theta), quick)
    t_md = _per_call(lambda: inverse_dynamics(mech, n), quick)
    torque = bare_fourbar(mech, theta)
    diff = float(np.abs(torque - d.driving_torque).max() / np.abs(d.driving_torque).max())
    return {
        "case": "inverse dynamics, four-bar, 360 angles",
        "bare_numpy_s": t_bare,
        "mechdyn_inverse_dynamics_s": t_md,
        "ratio_vs_bare": t_md / t_bare,
        "max_rel_diff_torque_vs_bare": diff,
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer repeats (a few seconds)")
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    args = ap.parse_args(argv)
    cases = [modal_case(args.quick), fourbar_case(args.quick)]
    if args.json:
        print(json.dumps({"benchmark": "small_model", "quick": args.quick, "cases": cases}, indent=2))
        return 0
    m, f = cases
    print(f"{m['case']}:")
    print(f"  bare scipy.linalg.eigh(K, M)   {m['bare_eigh_s'] * 1e6:8.1f} µs")
    print(
        f"  modal(model)                   {m['mechdyn_modal_s'] * 1e6:8.1f} µs"
        f"  ({m['ratio_modal_vs_bare']:.2f}×)"
    )
    print(
        f"  modal(model.with_values(...))  {m['mechdyn_with_values_and_modal_s'] * 1e6:8.1f} µs"
        f"  ({m['ratio_with_values_and_modal_vs_bare']:.2f}×: check the values, reuse the structure)"
    )
    print(
        f"  modal(new variant)             {m['mechdyn_build_and_modal_s'] * 1e6:8.1f} µs  "
        f"({m['ratio_build_and_modal_vs_bare']:.1f}×: build, check, assemble, solve)"
    )
    print(f"  frequencies agree to {m['max_rel_diff_vs_bare']:.1e}")
    print(f"{f['case']}:")
    print(f"  bare NumPy loop equations      {f['bare_numpy_s'] * 1e6:8.1f} µs")
    print(
        f"  inverse_dynamics(model, 360)   {f['mechdyn_inverse_dynamics_s'] * 1e6:8.1f} µs"
        f"  ({f['ratio_vs_bare']:.2f}×)"
    )
    print(f"  driving torques agree to {f['max_rel_diff_torque_vs_bare']:.1e}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
