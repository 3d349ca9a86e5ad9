"""Speed sweep of a geared drivetrain: periodic steady state by harmonic balance against time integration.

    python benchmarks/gear_dynamics.py            # 12 speeds, 200 to 400 rad/s of the motor
    python benchmarks/gear_dynamics.py --quick    # 2 speeds (within a minute)
    python benchmarks/gear_dynamics.py --json     # one JSON object with the times and ratios

The drivetrain: ten disks — a motor, a coupling, three spur stages whose mesh stiffness varies over the
mesh cycle as the gear data give it (:meth:`mechdyn.gears.GearPair.mesh_cycle`, z 18/36, 24/48, 30/60),
a brake disk and the load — shafts with light damping, the motor held at each speed, a load torque.

Baseline, measured in the same run: what a script does without the periodic methods —
``scipy.integrate.solve_ivp`` (DOP853, rtol 1e-8) of the same equations from the static deflection,
period after period of the common mesh period, until the mesh forces of one period differ from the
period before by less than 1e-5 of their swing; its last period gives the dynamic factors
K_v = max mesh force / static mesh force, sampled at the same instants as mechdyn's.

mechdyn: :func:`mechdyn.gear_dynamics.steady.speed_sweep` by harmonic balance (no peak refinement and
no stability check, so that both compute the same thing). Both dynamic factors must agree to 1e-3;
the agreement is printed.
"""

from __future__ import annotations

import argparse
import json
import sys
import time

import numpy as np
from _timing import best_time
from scipy.integrate import solve_ivp

from mechdyn.drivetrain import Disk, Drivetrain, GearMesh, Shaft
from mechdyn.gear_dynamics import GearSystem
from mechdyn.gear_dynamics.floquet import linear_periodic, period_plan
from mechdyn.gear_dynamics.steady import _grid, speed_sweep
from mechdyn.gears import GearPair, SpurGear

LOAD = 150.0  # N·m drawn at the load disk
HARMONICS = 20
POINTS = 40  # mesh-cycle samples of each stage's stiffness


def drivetrain() -> tuple[GearSystem, dict[str, GearPair]]:
    """The ten-disk drivetrain with its meshes' stiffness over the cycle from the gear data."""
    stages = {"m1": (18, 36, 0.003), "m2": (24, 48, 0.003), "m3": (30, 60, 0.004)}
    pairs = {
        n: GearPair(SpurGear(z1, m, 0.03, name=f"{n} pinion"), SpurGear(z2, m, 0.03, name=f"{n} gear"))
        for n, (z1, z2, m) in stages.items()
    }
    cycles = {n: p.mesh_cycle(POINTS) for n, p in pairs.items()}
    disks = [
        Disk("motor", 0.08),
        Disk("coupling", 0.01),
        Disk("p1", 0.01),
        Disk("g1", 0.05),
        Disk("p2", 0.02),
        Disk("g2", 0.08),
        Disk("p3", 0.05),
        Disk("g3", 0.3),
        Disk("brake", 0.05),
        Disk("load", 0.4),
    ]
    c = 1e-3  # shaft damping per unit stiffness, s
    shafts = [
        ("s0", "motor", "coupling", 3e4),
        ("s1", "coupling", "p1", 2e4),
        ("s2", "g1", "p2", 6e4),
        ("s3", "g2", "p3", 1.5e5),
        ("s4", "g3", "brake", 3e5),
        ("s5", "brake", "load", 2e5),
    ]
    elements: list = [Shaft(n, (a, b), k, damping=c * k) for n, a, b, k in shafts]
    links = {"m1": ("p1", "g1"), "m2": ("p2", "g2"), "m3": ("p3", "g3")}
    elements += [GearMesh.from_gear_pair(n, links[n], pairs[n], damping=2000.0, points=POINTS) for n in pairs]
    dt = Drivetrain(disks, elements, name="three-stage gearbox")
    return GearSystem.from_drivetrain(dt, mesh_profiles=cycles), pairs


def integrate_to_steady_state(system: GearSystem, speed: float, tol: float = 1e-5, max_periods: int = 400):
    """Periods of solve_ivp until the mesh forces repeat; returns (K_v per mesh, periods)."""
    lin = linear_periodic(system, reference="motor", load={"load": LOAD})
    plan = period_plan(lin)
    T = plan.period(speed)
    N = _grid(lin, plan, HARMONICS * int(plan.orders.max()))
    m = lin.m
    Minv = np.linalg.inv(lin.M)
    F0 = lin.force(speed)
    f0 = plan.fundamental * speed
    rates = plan.orders * plan.signs * f0  # dτ/dt of each mesh, cycles/s
    P = np.array([p.size for p in lin.profiles])
    profiles = [np.append(p, p[0]) for p in lin.profiles]
    G, kbar, cm = lin.G, lin.mean_stiffness, lin.mesh_damping
    C_struct = lin.C - (G.T * cm) @ G

    def forces(t: np.ndarray, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        tau = np.multiply.outer(rates, t) % 1.0
        k = np.array([kbar[j] * np.interp(tau[j] * P[j], np.arange(P[j] + 1), profiles[j]) for j in range(3)])
        return k * (G @ x) + cm[:, None] * (G @ v)

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        x, v = y[:m], y[m:]
        f = forces(np.array([t]), x[:, None], v[:, None])[:, 0]
        return np.concatenate([v, Minv @ (F0 - lin.K @ x - C_struct @ v - G.T @ f)])

    K_mean = lin.K + (G.T * kbar) @ G
    y = np.concatenate([np.linalg.solve(K_mean, F0), np.zeros(m)])
    static = kbar * (G @ y[:m])
    grid = T * np.arange(N) / N
    previous = None
    for n in range(max_periods):
        sol = solve_ivp(
            rhs, (n * T, (n + 1) * T), y, method="DOP853", rtol=1e-8, atol=1e-13, t_eval=n * T + grid
        )
        f = forces(sol.t, sol.y[:m], sol.y[m:])
        end = solve_ivp(rhs, (sol.t[-1], (n + 1) * T), sol.y[:, -1], method="DOP853", rtol=1e-8, atol=1e-13)
        y = end.y[:, -1]
        if previous is not None and np.abs(f - previous).max() <= tol * np.ptp(f, axis=1).max():
            sense = np.sign(static)[:, None]  # K_v: the largest force in the sense of the static one
            return (f * sense).max(axis=1) / np.abs(static), n + 1
        previous = f
    raise RuntimeError("no steady state within the periods allowed")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="2 speeds (within a minute)")
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    args = ap.parse_args(argv)
    system, _ = drivetrain()
    n_speeds = 2 if args.quick else 12
    speeds = np.linspace(200.0, 400.0, n_speeds)  # motor, rad/s

    def sweep():
        return speed_sweep(
            system,
            speeds,
            reference="motor",
            load={"load": LOAD},
            harmonics=HARMONICS,
            refine=0,
            stability=False,
        )

    t_sweep, result = best_time(sweep, max_repeats=1 if args.quick else 3)
    t0 = time.perf_counter()
    baseline = [integrate_to_steady_state(system, float(s)) for s in speeds]
    t_ivp = time.perf_counter() - t0
    kv_ivp = np.array([b[0] for b in baseline])
    kv = result.dynamic_factor
    agreement = float(np.abs(kv - kv_ivp).max() / np.abs(kv_ivp).max())
    doc = {
        "benchmark": "gear_dynamics",
        "quick": args.quick,
        "disks": len(system.drivetrain.disks),
        "meshes": len(system.meshes),
        "speeds": int(speeds.size),
        "harmonics": HARMONICS,
        "speed_sweep_s": t_sweep,
        "solve_ivp_to_steady_state_s": t_ivp,
        "solve_ivp_periods_mean": float(np.mean([b[1] for b in baseline])),
        "ratio": t_ivp / t_sweep,
        "dynamic_factor_max": float(np.nanmax(kv)),
        "max_rel_diff": agreement,
        "agree": agreement <= 1e-3,
    }
    if args.json:
        print(json.dumps(doc, indent=2))
        return 0 if doc["agree"] else 1
    print(f"{doc['disks']} disks, {doc['meshes']} meshes, {doc['speeds']} speeds, {HARMONICS} harmonics/mesh")
    print(f"speed_sweep (harmonic balance)  {t_sweep:8.3f} s")
    periods = doc["solve_ivp_periods_mean"]
    print(f"solve_ivp to steady state       {t_ivp:8.3f} s ({periods:.0f} periods on average)")
    print(f"ratio {doc['ratio']:.0f}×, K_v max {doc['dynamic_factor_max']:.3f}, agreement {agreement:.1e}")
    return 0 if doc["agree"] else 1


if __name__ == "__main__":
    sys.exit(main())
