"""Speed sweep of a geared drivetrain: harmonic balance against time integration, at equal accuracy.

    python benchmarks/gear_dynamics.py            # 12 speeds, 200 to 400 rad/s of the motor
    python benchmarks/gear_dynamics.py --quick    # 2 speeds (within a minute)
    python benchmarks/gear_dynamics.py --json     # one JSON object: times, errors, ratio
    python benchmarks/gear_dynamics.py --tune     # the settings tried for both sides (minutes)

The drivetrain: ten disks — a motor, a coupling, three spur stages whose mesh stiffness varies over the
mesh cycle as the gear data give it (:meth:`mechdyn.gears.GearPair.mesh_cycle`, z 18/36, 24/48, 30/60),
a brake disk and the load — shafts with light damping, the motor held at each speed, a load torque.
Both sides solve the same linear time-periodic equations (:func:`linear_periodic`, the motor held:
``boundary="prescribed"``, ``drive="speed"``) for the dynamic factors K_v = largest mesh force in the
sense of the static one / static mesh force, of each mesh at each speed, the forces sampled at the same
N instants of the common mesh period (``_grid``, as :func:`speed_sweep` samples them).

Equal accuracy: both are held to every K_v within ``TARGET`` = 1e-3 (relative) of a reference, and
their achieved errors are printed side by side.

- Reference: the periodic orbit by shooting with ``solve_ivp`` (DOP853, rtol 1e-9): the monodromy
  matrix and the forced response over one period, the periodic state solved for, one more period
  sampled; no settling. Cross-checked against mechdyn's own shooting by Magnus products
  (``speed_sweep(method="shooting")``) on the finer grid that samples (19 200 instants, which hold the
  N = 1920): they agree to 1e-7, and the finer grid alone raises some K_v by 2.2e-4, hence one grid.
- mechdyn: :func:`mechdyn.gear_dynamics.steady.speed_sweep` by harmonic balance with ``HARMONICS`` = 15
  per mesh, the fewest that reach the target at the 12 speeds (14: 1.06e-3, at 200 rad/s); no peak
  refinement and no stability check, so that both compute the same thing. Its time includes its own
  truncation check (K_v again with twice the harmonics at the lowest speed and at the largest K_v), a
  fixed cost that weighs most on the quick run's two speeds.

The two are timed in turns (five each, three in the quick run), the best of each kept.
- Baseline, measured in the same run, what a script does without the periodic methods:
  ``solve_ivp`` from the static deflection, period after period, until no K_v changes by more than
  ``SETTLE`` (relative) from one period to the next; its last period gives K_v. Tuned (``--tune``):
  the fastest of RK45, RK23, DOP853 and LSODA (with the Jacobian), over rtol and the settle criterion,
  that reaches the target at the 12 speeds — RK45, rtol 3e-5, settle 1e-3 (3–5 periods a speed). The
  error is not monotonic in rtol there: the step sizes, and so the error of each period, jump with it,
  and now and then a speed stops a period early (RK45 at 5e-5 and 2e-5: 1.01e-3 and 1.19e-3; looser
  than 1e-4 the period-to-period noise holds the settle criterion off for many periods).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from dataclasses import dataclass

import numpy as np
from _timing import best_time
from scipy.integrate import solve_ivp

from mechdyn.drivetrain import Disk, Drivetrain, GearMesh, Shaft
from mechdyn.gear_dynamics import GearSystem
from mechdyn.gear_dynamics.periodic import LinearPeriodic, PeriodPlan, linear_periodic, period_plan
from mechdyn.gear_dynamics.propagators import segments
from mechdyn.gear_dynamics.steady import _grid, speed_sweep
from mechdyn.gears import GearPair, SpurGear

LOAD = 150.0  # N·m drawn at the load disk
POINTS = 40  # mesh-cycle samples of each stage's stiffness
TARGET = 1e-3  # the accuracy both sides are held to: relative error of every K_v
HARMONICS = 15  # per mesh, tuned to TARGET
BASELINE = {"method": "RK45", "rtol": 3e-5, "atol": 1e-12}  # tuned to TARGET
SETTLE = 1e-3  # the baseline stops when no K_v changed by more than this (relative) over a period
REFERENCE_RTOL = 1e-9
SUBSTEPS = 4  # Magnus segments per profile interval of the cross-check (speed_sweep's default)


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


def model(system: GearSystem) -> tuple[LinearPeriodic, PeriodPlan, int]:
    """The linear periodic equations with the motor held, their period plan, and the samples per period."""
    lin = linear_periodic(system, reference="motor", boundary="prescribed", load={"load": LOAD})
    plan = period_plan(lin)
    return lin, plan, _grid(lin, plan, HARMONICS * int(plan.orders.max()))


@dataclass(frozen=True)
class Equations:
    """y' = A(t) y + b at one speed, y = (x, ẋ): M ẍ + C ẋ + (K + Gᵀ diag k(t) G) x = F, written out
    from :func:`linear_periodic`'s matrices as a script would (the profiles all of one length here)."""

    lin: LinearPeriodic
    period: float  # s
    rates: np.ndarray  # mesh cycles per second of each mesh (signed)
    A0: np.ndarray  # A(t) without the mesh stiffness
    MG: np.ndarray  # M⁻¹ Gᵀ
    b: np.ndarray
    table: np.ndarray  # (J, P + 1) stiffness profiles, closed
    static_state: np.ndarray  # the static deflection at the mean stiffness, at rest
    static_force: np.ndarray  # N, each mesh at its mean stiffness

    @classmethod
    def at(cls, lin: LinearPeriodic, plan: PeriodPlan, speed: float) -> Equations:
        m = lin.m
        Minv = np.linalg.inv(lin.M)
        F = lin.force(speed)
        A0 = np.zeros((2 * m, 2 * m))
        A0[:m, m:] = np.eye(m)
        A0[m:, :m] = -Minv @ lin.K
        A0[m:, m:] = -Minv @ lin.C  # lin.C holds the mesh damping too
        kbar = lin.mean_stiffness
        x = np.linalg.solve(lin.K + (lin.G.T * kbar) @ lin.G, F)
        return cls(
            lin=lin,
            period=plan.period(speed),
            rates=plan.orders * plan.signs * plan.fundamental * speed,
            A0=A0,
            MG=Minv @ lin.G.T,
            b=np.concatenate([np.zeros(m), Minv @ F]),
            table=np.array([np.append(p, p[0]) for p in lin.profiles]),
            static_state=np.concatenate([x, np.zeros(m)]),
            static_force=kbar * (lin.G @ x),
        )

    def stiffness(self, t: np.ndarray) -> np.ndarray:
        """(J, n) mesh stiffness at the times t (s), N/m: each profile interpolated linearly."""
        P = self.table.shape[1] - 1
        u = np.mod(np.multiply.outer(self.rates, np.atleast_1d(t)), 1.0) * P
        i = np.minimum(u.astype(int), P - 1)
        f = u - i
        rows = np.arange(self.table.shape[0])[:, None]
        profile = self.table[rows, i] * (1.0 - f) + self.table[rows, i + 1] * f
        return self.lin.mean_stiffness[:, None] * profile

    def matrix(self, t: float) -> np.ndarray:
        A = self.A0.copy()
        m = self.lin.m
        A[m:, :m] -= self.MG @ (self.stiffness(t)[:, 0, None] * self.lin.G)
        return A

    def rhs(self, t: float, y: np.ndarray) -> np.ndarray:
        return self.matrix(t) @ y + self.b

    def dynamic_factor(self, t: np.ndarray, y: np.ndarray) -> np.ndarray:
        """K_v of each mesh from the states y (2m, n) at the times t (s) of one period."""
        m, G = self.lin.m, self.lin.G
        f = self.stiffness(t) * (G @ y[:m]) + self.lin.mesh_damping[:, None] * (G @ y[m:])
        return (f * np.sign(self.static_force)[:, None]).max(axis=1) / np.abs(self.static_force)


def integrate_to_steady_state(
    eq: Equations, samples: int, method: str, rtol: float, atol: float, settle: float, max_periods: int = 100
) -> tuple[np.ndarray, int]:
    """Periods of solve_ivp from the static deflection until K_v repeats; returns (K_v, periods)."""
    T = eq.period
    extra = {"jac": lambda t, y: eq.matrix(t)} if method in ("LSODA", "BDF", "Radau") else {}
    y = eq.static_state
    previous = None
    for n in range(max_periods):
        t = np.linspace(n * T, (n + 1) * T, samples + 1)
        sol = solve_ivp(eq.rhs, (t[0], t[-1]), y, method=method, rtol=rtol, atol=atol, t_eval=t, **extra)
        y = sol.y[:, -1]
        kv = eq.dynamic_factor(sol.t[:-1], sol.y[:, :-1])
        if previous is not None and np.abs(kv / previous - 1.0).max() <= settle:
            return kv, n + 1
        previous = kv
    raise RuntimeError(f"no steady state within {max_periods} periods ({method}, rtol {rtol:g})")


def periodic_orbit(eq: Equations, *samples: int, rtol: float = REFERENCE_RTOL) -> list[np.ndarray]:
    """K_v of the periodic orbit by shooting, y(0) = Φ(T) y(0) + y_forced(T) with Φ and y_forced by
    solve_ivp, sampled at each count of instants per period."""
    d = eq.A0.shape[0]
    T = eq.period

    def flow(t: float, z: np.ndarray) -> np.ndarray:  # the forced response and the fundamental matrix
        Z = z.reshape(d, d + 1)
        out = eq.matrix(t) @ Z
        out[:, 0] += eq.b
        return out.ravel()

    z0 = np.hstack([np.zeros((d, 1)), np.eye(d)]).ravel()
    end = solve_ivp(flow, (0.0, T), z0, method="DOP853", rtol=rtol, atol=1e-14).y[:, -1].reshape(d, d + 1)
    y0 = np.linalg.solve(np.eye(d) - end[:, 1:], end[:, 0])
    orbit = solve_ivp(eq.rhs, (0.0, T), y0, method="DOP853", rtol=rtol, atol=1e-14, dense_output=True).sol
    return [eq.dynamic_factor(T * np.arange(n) / n, orbit(T * np.arange(n) / n)) for n in samples]


def rel_error(kv: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """(speeds,) largest relative error of a speed's K_v over its meshes."""
    return np.abs(kv / reference - 1.0).max(axis=1)


def sweep(system: GearSystem, speeds: np.ndarray, harmonics: int):
    return speed_sweep(
        system,
        speeds,
        reference="motor",
        load={"load": LOAD},
        drive="speed",
        harmonics=harmonics,
        refine=0,
        stability=False,
    )


def baseline(system: GearSystem, speeds: np.ndarray, settle: float = SETTLE, **settings) -> list:
    """(K_v, periods) at each speed by the baseline, from the drivetrain on (as speed_sweep is timed)."""
    lin, plan, N = model(system)
    settings = {**BASELINE, **settings}
    return [
        integrate_to_steady_state(Equations.at(lin, plan, float(s)), N, settle=settle, **settings)
        for s in speeds
    ]


def tune(system: GearSystem, speeds: np.ndarray) -> int:
    """Time and error of the settings tried for both sides, at the full run's speeds."""
    lin, plan, N = model(system)
    eqs = [Equations.at(lin, plan, float(s)) for s in speeds]
    ref = np.array([periodic_orbit(eq, N)[0] for eq in eqs])
    print(f"target: every K_v within {TARGET:.0e}; time for {speeds.size} speeds, largest error")
    for H in (6, 8, 10, 12, 13, 14, 15, 16):
        t, result = best_time(lambda H=H: sweep(system, speeds, H), budget=np.inf, max_repeats=2)
        err = rel_error(result.dynamic_factor, ref).max()
        print(f"speed_sweep harmonics {H:<3d}            {t:7.2f} s  {err:.2e}")
    for method, rtol, settle in [
        ("RK45", 3e-4, 1e-3),
        ("RK45", 1e-4, 1e-3),
        ("RK45", 5e-5, 1e-3),
        ("RK45", 3e-5, 1e-3),
        ("RK45", 2e-5, 1e-3),
        ("RK45", 1e-5, 1e-3),
        ("RK45", 3e-5, 2e-3),
        ("RK23", 2e-4, 1e-3),
        ("RK23", 1e-4, 1e-3),
        ("DOP853", 1e-3, 1e-3),
        ("DOP853", 2e-4, 1e-3),
        ("LSODA", 5e-4, 1e-3),
        ("LSODA", 3e-4, 1e-3),
        ("RK45", 1e-3, 1e-2),  # a looser target, 1e-2
        ("RK45", 3e-4, 1e-2),
        ("DOP853", 1e-3, 1e-2),
        ("LSODA", 1e-3, 1e-2),
    ]:
        t0 = time.perf_counter()
        try:
            out = baseline(system, speeds, settle, method=method, rtol=rtol)
        except RuntimeError as e:
            print(f"{method:6s} rtol {rtol:.0e} settle {settle:.0e}  {e}")
            continue
        t = time.perf_counter() - t0
        err = rel_error(np.array([o[0] for o in out]), ref).max()
        periods = np.mean([o[1] for o in out])
        print(
            f"{method:6s} rtol {rtol:.0e} settle {settle:.0e}  {t:7.2f} s  {err:.2e}  ({periods:.1f} periods)"
        )
    return 0


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="2 speeds (within a minute)")
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    ap.add_argument("--tune", action="store_true", help="time the settings tried for both sides")
    args = ap.parse_args(argv)
    system, _ = drivetrain()
    n_speeds = 2 if args.quick else 12
    speeds = np.linspace(200.0, 400.0, n_speeds)  # motor, rad/s
    if args.tune:
        return tune(system, np.linspace(200.0, 400.0, 12))
    lin, plan, N = model(system)
    eqs = [Equations.at(lin, plan, float(s)) for s in speeds]

    # mechdyn's Magnus shooting samples the start of each segment: a finer grid holding the N instants
    fine = [segments(lin, plan, SUBSTEPS, float(s)) for s in speeds]
    t0 = time.perf_counter()
    orbits = [periodic_orbit(eq, N, n) for eq, n in zip(eqs, fine, strict=True)]
    t_ref = time.perf_counter() - t0
    ref, ref_fine = (np.array([o[i] for o in orbits]) for i in (0, 1))
    magnus = speed_sweep(
        system,
        speeds,
        reference="motor",
        load={"load": LOAD},
        drive="speed",
        method="shooting",
        substeps=SUBSTEPS,
        refine=0,
        stability=False,
    )
    cross_check = float(rel_error(magnus.dynamic_factor, ref_fine).max())
    sampling = float(rel_error(ref_fine, ref).max())  # what the finer grid adds to K_v

    times: dict[str, list[float]] = {"sweep": [], "ivp": []}
    for _ in range(3 if args.quick else 5):  # in turns, so that both meet the same load; the best of each
        t, result = best_time(lambda: sweep(system, speeds, HARMONICS), max_repeats=1)
        times["sweep"].append(t)
        t, out = best_time(lambda: baseline(system, speeds), max_repeats=1)
        times["ivp"].append(t)
    t_sweep, t_ivp = min(times["sweep"]), min(times["ivp"])
    err_sweep = rel_error(result.dynamic_factor, ref)
    err_ivp = rel_error(np.array([o[0] for o in out]), ref)
    periods = [o[1] for o in out]
    within = bool(err_sweep.max() <= TARGET and err_ivp.max() <= TARGET and cross_check <= TARGET / 100)
    doc = {
        "benchmark": "gear_dynamics",
        "quick": args.quick,
        "disks": len(system.drivetrain.disks),
        "meshes": len(system.meshes),
        "speeds": int(speeds.size),
        "samples_per_period": N,
        "target_rel_error": TARGET,
        "reference": {
            "method": f"solve_ivp shooting, DOP853 rtol {REFERENCE_RTOL:g}",
            "seconds": t_ref,
            "max_rel_diff_vs_magnus_shooting": cross_check,
            "magnus_samples_per_period": int(max(fine)),
            "max_rel_diff_finer_sampling": sampling,
            "dynamic_factor_max": float(ref.max()),
        },
        "speed_sweep": {
            "harmonics": int(result.harmonics),
            "seconds": t_sweep,
            "seconds_per_speed": t_sweep / speeds.size,
            "max_rel_error": float(err_sweep.max()),
            "estimated_error": float(result.harmonics_error),
        },
        "solve_ivp_to_steady_state": {
            **BASELINE,
            "settle": SETTLE,
            "seconds": t_ivp,
            "seconds_per_speed": t_ivp / speeds.size,
            "max_rel_error": float(err_ivp.max()),
            "periods_mean": float(np.mean(periods)),
        },
        "ratio": t_ivp / t_sweep,
        "within_target": within,
    }
    if args.json:
        print(json.dumps(doc, indent=2))
        return 0 if within else 1
    print(f"{doc['disks']} disks, {doc['meshes']} meshes, K_v sampled at {N} instants of the period")
    print(
        f"reference: {doc['reference']['method']} ({t_ref:.1f} s); mechdyn's Magnus shooting agrees to "
        f"{cross_check:.1e} at its {max(fine)} instants (which raise K_v by up to {sampling:.1e})"
    )
    ivp = f"solve_ivp {BASELINE['method']} rtol {BASELINE['rtol']:g}, settle {SETTLE:g}"
    print(f"target: every K_v within {TARGET:g} of the reference\n")
    print(f"{'speed rad/s':>11}  {'K_v max':>7}  {'speed_sweep':>11}  {'solve_ivp':>9}  periods")
    for s, k, e1, e2, n in zip(speeds, ref.max(axis=1), err_sweep, err_ivp, periods, strict=True):
        print(f"{s:11.1f}  {k:7.3f}  {e1:11.1e}  {e2:9.1e}  {n:7d}")
    print()
    print(f"{'':40s}  {'time':>8}  {'per speed':>9}  max error")
    print(
        f"{f'speed_sweep, {HARMONICS} harmonics/mesh':40s}  {t_sweep:6.2f} s  {t_sweep / speeds.size:7.3f} s"
        f"  {err_sweep.max():.1e} (estimated {result.harmonics_error:.1e})"
    )
    print(f"{ivp:40s}  {t_ivp:6.2f} s  {t_ivp / speeds.size:7.3f} s  {err_ivp.max():.1e}")
    print(f"ratio {doc['ratio']:.1f}× at equal accuracy" + ("" if within else " — NOT within the target"))
    return 0 if within else 1


if __name__ == "__main__":
    sys.exit(main())
