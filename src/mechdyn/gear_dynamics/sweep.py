"""The periodic steady state of a geared drivetrain over its running speed: the speed sweep.

:func:`speed_sweep` solves each speed as :mod:`.steady` does (:class:`.steady._Solver`: harmonic
balance, one linear solve per speed with the speed-independent coupling assembled once, or shooting),
and then:

* **follows the branches** with backlash (:func:`_sweep`): each speed starts Newton's method from
  the orbit of the speed before (natural continuation), visited up, down or both ways
  (``direction``), as a slowly run-up or run-down machine follows one branch of the response;
* **follows a branch through its folds** where Newton fails between two speeds: pseudo-arclength
  continuation from the last good orbit (:func:`.continuation.follow`) to the fold of the softening
  backlash nonlinearity (or a loss of stability), located to :data:`.continuation.FOLD_RTOL` of the
  speed, and through it along the unstable branch to the next fold; there the sweep **jumps**: the
  last state is run at the new speed until it settles, and Newton starts from there. The up and down
  sweeps then differ inside the band of multiple solutions, whose edges are the folds (Kahraman &
  Singh, *J. Sound Vib.* 142 (1990) 49–75; :meth:`.sweep_result.SpeedSweepResult.hysteresis`).
  Where the continuation fails, the end is **bisected** to within :data:`EDGE_RTOL` of the speed
  instead (the fallback, stated in the result's notes);
* **refines the peaks**: speeds are added either side of every local maximum of a mesh's force
  amplitude (:func:`.sweep_result._peaks`);
* checks the harmonic-balance truncation where it matters most (the lowest speed and the largest
  K_v), doubling the harmonics chosen until K_v is converged (:mod:`._harmonics`);
* adds ISO 6336-1's K_v of the meshes whose gear data are given (:func:`_iso_factors`), and refuses
  a sweep its counts make absurd before it starts (:func:`_check_sweep_cost`, :mod:`._cost`).

The result is :class:`.sweep_result.SpeedSweepResult`.
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Any, Literal

import numpy as np

from mechdyn.checks import check_count
from mechdyn.errors import ModelError
from mechdyn.gear_dynamics._cost import check as check_cost
from mechdyn.gear_dynamics._cost import sweep_cost
from mechdyn.gear_dynamics._harmonics import HARMONICS_RTOL, MAX_AUTO, harmonics_for, needed_harmonics
from mechdyn.gear_dynamics._stability import UNSTABLE_MARGIN
from mechdyn.gear_dynamics.continuation import ContinuedBranch, follow
from mechdyn.gear_dynamics.periodic import (
    LinearPeriodic,
    PeriodPlan,
    _natural_frequencies,
    _speeds,
    period_plan,
)
from mechdyn.gear_dynamics.propagators import segments
from mechdyn.gear_dynamics.steady import (
    Drive,
    Method,
    _check_integrator,
    _check_method,
    _choose,
    _grid,
    _harmonics_given,
    _harmonics_words,
    _mesh_forces,
    _model,
    _Solver,
    _static_forces,
    _truncation_error,
)
from mechdyn.gear_dynamics.sweep_result import SpeedSweepResult, _peaks

__all__ = ["speed_sweep"]

Direction = Literal["up", "down", "both"]
_DIRECTIONS = ("up", "down", "both")
#: The relative width in speed to which the end of a branch (a jump) is located by bisection, the
#: fallback where the continuation (:mod:`.continuation`) fails.
EDGE_RTOL = 1e-3


def speed_sweep(
    system: Any,
    speeds: Any,
    *,
    reference: str,
    load: Mapping[str, Any] | None = None,
    method: Method = "auto",
    harmonics: int | Literal["auto"] = "auto",
    refine: int = 3,
    gear_pairs: Mapping[str, Any] | None = None,
    integrator: Literal["magnus", "ivp"] = "magnus",
    substeps: int = 4,
    stability: bool = True,
    direction: Direction = "up",
    drive: Drive | None = None,
    motor: Any = None,
) -> SpeedSweepResult:
    """Dynamic mesh forces, dynamic factors and DTE of a drivetrain over its running speed.

    Parameters
    ----------
    system : GearSystem
        The time-varying system of a drivetrain (:class:`mechdyn.gear_dynamics.GearSystem`).
    speeds : array_like
        Speeds Ω of the reference disk, rad/s, positive (sorted; duplicates dropped).
    reference : str
        The disk held at Ω (a motor disk; a kinematic input).
    load : mapping of str to float, optional
        Torque drawn at each named disk, N·m (or quantities), resisting its rotation; the static mesh
        forces of K_v follow from it. Without a load K_v is NaN.
    method : {"auto", "harmonic_balance", "shooting"}
        ``"auto"``: harmonic balance, or shooting with Newton continued over speed where a mesh has
        backlash.
    harmonics : int or "auto"
        Harmonics of each mesh frequency kept by harmonic balance, a count from 1 to 2000, or
        ``"auto"``: enough to reach twice the highest natural frequency at the lowest speed
        (:func:`mechdyn.gear_dynamics._harmonics.harmonics_for`), doubled until K_v changes by less
        than 1 % (estimated) at the lowest speed and at the speed of the largest K_v. Either way the
        result states the estimated error (:attr:`SpeedSweepResult.harmonics_error`) and warns above 1 %.
    refine : int
        Rounds of adding speeds either side of every local maximum of a mesh's force amplitude (so
        that the peaks are resolved), a count from 0 to 20.
    gear_pairs : mapping of str to GearPair, optional
        Mesh name → its :class:`mechdyn.gears.GearPair`: adds ISO 6336-1's K_v to the result.
    integrator : {"magnus", "ivp"}
        The propagator of linear shooting.
    substeps : int
        Magnus segments per profile sample interval, a count from 1 to 1000.
    stability : bool
        Also compute each periodic solution's largest Floquet multiplier (harmonic balance: the
        monodromy matrix by the Magnus product, :func:`mechdyn.gear_dynamics.propagators.monodromy`;
        shooting has it anyway) and flag the speeds where it is unstable.
    direction : {"up", "down", "both"}
        The order in which the speeds are visited, which matters with backlash only (each speed starts
        from the solution of the one before, so that a sweep follows one branch of the response
        until it ends and then jumps, as a slowly run-up or run-down machine does): ``"up"``
        (ascending), ``"down"`` (descending) or ``"both"`` (up, then down from the top; the result is
        the up sweep with the down sweep as its :attr:`SpeedSweepResult.down`).
    drive : {"motor", "torque", "speed"}, optional
        How the train is driven at each speed (see :func:`.steady.steady_state`); default ``"motor"`` where
        ``motor`` is given, else ``"torque"``. ``"speed"`` holds the reference disk (a kinematic input):
        where that disk is a motor rotor, the train's first mode and resonances move.
    motor : MotorTorque, optional
        The motor of ``drive="motor"`` (:class:`mechdyn.gear_dynamics.loads.MotorTorque`).

    Returns
    -------
    SpeedSweepResult

    Notes
    -----
    Each speed's periodic solution as :func:`.steady.steady_state` (harmonic balance: one sparse solve per
    speed, the speed-independent stiffness coupling assembled once). With backlash, Newton's method
    on the event-located flow starts from the previous speed's solution (natural continuation); where
    it fails or finds an unstable orbit, the branch is followed from the previous solution by
    pseudo-arclength continuation (:func:`mechdyn.gear_dynamics.continuation.follow`; Keller 1977,
    Seydel 2010, ch. 4) to this speed or to its fold, located, and through the fold along the unstable
    branch to the next (:attr:`SpeedSweepResult.branches`); past the fold the orbit at the fold is run
    for the periods in which the slowest mode decays by e⁻⁶ at the new speed and Newton starts from
    there: the sweep jumps to the other branch, so that the up and down sweeps differ inside the band
    of multiple solutions, whose edges are the folds (Kahraman & Singh, *J. Sound Vib.* 142 (1990)
    49–75). Where the continuation fails, the end is bisected (:data:`EDGE_RTOL`) and a note says so.
    Each speed states what ran and its CPU time (:attr:`SpeedSweepResult.solve_paths`,
    :attr:`SpeedSweepResult.solve_cpu`). A speed where Newton still fails is kept with ``converged``
    False. K_v = max f / f_static follows ISO 6336-1
    (2019), clause 6's definition of the dynamic factor as the ratio of the largest to the nominal tooth load.
    """
    _check_method(method)
    _check_integrator(integrator)
    given = _harmonics_given(harmonics)
    refine = check_count("gear dynamics", "refine", refine, low=0, high=20, what="refinement rounds")
    substeps = check_count("gear dynamics", "substeps", substeps, low=1, high=1000, what="substeps")
    if direction not in _DIRECTIONS:
        raise ModelError(
            f"direction {direction!r}: give 'up', 'down' or 'both'",
            element="gear dynamics",
            field="direction",
        )
    s = np.unique(_speeds(speeds))
    lin = _model(system, reference, load, drive, motor)
    if not lin.names:
        raise ModelError(
            "the drivetrain has no flexible gear mesh; give a mesh a stiffness",
            element="gear dynamics",
            field="system",
        )
    chosen = _choose(lin, method)
    plan = period_plan(lin)
    balance = chosen == "harmonic_balance"
    H = given if given is not None else (harmonics_for(lin, plan, float(s.min())) if balance else 16)
    _check_sweep_cost(lin, plan, s, H, given, balance, stability, solver_substeps=substeps, refine=refine)
    iso_cache: dict[bytes, tuple[np.ndarray, np.ndarray, list[str]]] = {}
    natural = _natural_frequencies(lin)

    def result(sweep: str, known_folds: tuple[float, ...] = ()) -> SpeedSweepResult:
        log = _Log()
        grid, stack, jumps = _sweep(solver, s, sweep, refine, known_folds, log)
        error = float("nan")
        if balance:  # the truncation checked where it matters most: lowest speed, largest K_v
            kv = _sweep_kv(stack) * _stack_kv(stack)
            worst = [float(grid[0])]
            if np.isfinite(kv).any():
                worst.append(float(grid[int(np.nanargmax(np.nanmax(kv, axis=1)))]))
            error = _truncation_error(lin, plan, H, sorted(set(worst)))
        key = grid.tobytes()
        if key not in iso_cache:
            iso_cache[key] = _iso_factors(system, lin, grid, stack[3], dict(gear_pairs or {}))
        iso, iso_resonance, iso_notes = iso_cache[key]
        notes = [plan.note] if plan.note else []
        notes.extend(log.fallbacks)
        if not np.isfinite(_sweep_kv(stack)).any():
            notes.append("no load given: the dynamic factor K_v needs a static mesh force (give load=...)")
        return SpeedSweepResult(
            speeds=grid,
            reference=reference,
            mesh_names=lin.names,
            mesh_cycles=lin.cycles,
            force_max=stack[0],
            force_min=stack[1],
            force_rms=stack[2],
            static_force=stack[3],
            dte_amplitude=stack[4],
            iso_dynamic_factor=iso,
            iso_resonance_speed=iso_resonance,
            natural_frequencies_hz=natural,
            converged=stack[5][:, 0].astype(bool),
            spectral_radius=stack[5][:, 1],
            closure=stack[5][:, 2],
            period_multiple=stack[5][:, 3].astype(int),
            jump_speeds=tuple(jumps),
            branches=tuple(log.branches),
            solve_paths=tuple(log.paths.get(float(g), "") for g in grid) if solver.nonlinear else (),
            solve_cpu=np.array([log.cpu.get(float(g), np.nan) for g in grid]) if solver.nonlinear else None,
            method=(
                _harmonics_words(H, given is None, error)
                if balance
                else (
                    f"shooting with Newton's method on the backlash flow, continued over speed ({sweep})"
                    if solver.nonlinear
                    else f"shooting ({integrator})"
                )
            ),
            harmonics=H if balance else 0,
            harmonics_error=error,
            notes=tuple(notes),
            assumptions=tuple(iso_notes),
            direction=sweep,
            drive=lin.drive,
        )

    while True:  # chosen harmonics: doubled until K_v is converged to HARMONICS_RTOL
        solver = _Solver(lin, plan, chosen, H, substeps, integrator, stability=stability)
        first = result("up" if direction == "both" else direction)
        if given is None and first.harmonics_error > HARMONICS_RTOL and 2 * H <= MAX_AUTO:
            H *= 2
            continue
        break
    if direction == "both":
        folds = tuple(f for b in first.branches for f in b.folds)
        down = result("down", folds) if solver.nonlinear else replace(first, direction="down")
        return replace(first, down=down)
    return first


@dataclass
class _Log:
    """What one sweep did at each speed (in words) and its CPU time (s), the branches it followed by
    continuation, and where it fell back to bisection (in words)."""

    paths: dict[float, str] = field(default_factory=dict)
    cpu: dict[float, float] = field(default_factory=dict)
    branches: list[ContinuedBranch] = field(default_factory=list)
    fallbacks: list[str] = field(default_factory=list)


def _sweep(
    solver: _Solver,
    s: np.ndarray,
    direction: str,
    refine: int,
    known_folds: tuple[float, ...] = (),
    log: _Log | None = None,
) -> tuple[np.ndarray, list[np.ndarray], list[float]]:
    """The speeds computed (ascending), the stacked rows (force max, min, RMS, static force, DTE
    amplitude, [converged, ρ, closure, periods]) of one sweep over the ascending speeds ``s``, visited
    upwards or downwards, and the speeds where the sweep jumped (rad/s). With backlash each speed
    starts Newton from the periodic state of the speed before; where that fails (or the orbit found is
    unstable) the branch is followed from the last good orbit by pseudo-arclength continuation
    (:func:`.continuation.follow`): to this speed where it gets there, stable; else to its end, a fold
    or a loss of stability, located to :data:`.continuation.FOLD_RTOL`, and beyond a fold along the
    unstable branch to the next fold (unless ``known_folds`` holds it), after which the last state
    is run for a while at this speed before Newton (the jump). Where the continuation fails, the end
    is bisected from the last good orbit to within :data:`EDGE_RTOL` of the speed (the fallback,
    stated in ``log``)."""
    lin, plan = solver.lin, solver.plan
    J = len(lin.names)
    rows: dict[float, tuple[np.ndarray, ...]] = {}
    states: dict[float, np.ndarray] = {}
    jumps: list[float] = []
    log = log if log is not None else _Log()
    counted = 0.0  # CPU time of the continuation points kept as speeds (counted there)

    def run(speed: float, *, start: np.ndarray | None = None, settle: bool = True, keep: bool = True) -> bool:
        t, x, v, ok = solver.solve(speed, start=start, settle=settle)
        good = ok and not solver.rho > 1.0 + UNSTABLE_MARGIN
        if not (good or keep):
            return False
        rows[speed] = _row(lin, plan, speed, t, x, v, ok, solver.rho, solver.closure, solver.multiple)
        if ok and solver.nonlinear:
            states[speed] = np.concatenate([x[0], v[0]])
        return good

    def bisect(previous: float, speed: float) -> str:
        # the fallback: the branch followed to its end by bisection from the last good orbit; where it
        # ends short of this speed (a fold or a grazing: the jump), the end is located and the last
        # state run at this speed for a while before Newton (the branch a slow sweep lands on)
        lo, hi = previous, speed
        while abs(hi - lo) > EDGE_RTOL * speed:
            mid = 0.5 * (lo + hi)
            if run(mid, start=states[lo], settle=False, keep=False):
                log.paths[mid] = "a point of a bisection (the fallback)"
                lo = mid
            else:
                hi = mid
        if run(speed, start=states[lo], settle=False, keep=False):
            return "bisection to this speed (the fallback), then Newton"
        jumps.append(0.5 * (lo + hi))
        solver.start = states[lo]
        run(speed, settle=True)
        return "bisection to the branch's end (the fallback), then the jump: a settling run, Newton"

    def follow_branch(previous: float, speed: float) -> str:
        """The branch from the orbit at ``previous`` towards ``speed`` by continuation; what ran."""
        nonlocal counted
        N = _grid(lin, plan, solver.bal.H if solver.bal is not None else 16)
        branch = follow(
            lin,
            plan,
            previous,
            states[previous],
            toward=speed,
            bounds=(float(s[0]), float(s[-1])),
            samples=N,
            known_folds=known_folds + tuple(f for b in log.branches for f in b.folds),
            mesh_forces=lambda v, t, x, xd: _mesh_forces(lin, plan, v, t, x, xd)[0],
            static_forces=lambda v: _static_forces(lin, v),
        )
        if branch.failed:
            log.fallbacks.append(
                f"between {previous:.6g} and {speed:.6g} rad/s the continuation failed ({branch.end}): the "
                f"branch's end was bisected to {EDGE_RTOL:g} of the speed instead"
            )
            return bisect(previous, speed)
        first = _first_edge(branch)
        for i in range(1, first if first is not None else branch.speeds.size):
            if branch.stable[i] and branch.kinds[i] == "point":  # the stable branch up to its end
                speed_i = float(branch.speeds[i])
                if speed_i not in rows:
                    rows[speed_i] = _branch_row(lin, plan, branch, i)
                    states[speed_i] = branch.states[i]
                    log.paths[speed_i] = "a point of a continuation (the stable branch to its end)"
                    log.cpu[speed_i] = float(branch.cpu_seconds[i])
                    counted += float(branch.cpu_seconds[i])
        log.branches.append(replace(branch, samples=None))  # the orbits' samples: in the rows above
        if first is None:  # the branch reaches this speed, stable
            if run(speed, start=branch.states[-1], settle=False, keep=False):
                return "continuation to this speed, then Newton"
            solver.start = branch.states[-1]
            run(speed, settle=True)
            return "continuation to this speed, then a settling run, Newton"
        jumps.append(float(branch.speeds[first]))
        solver.start = branch.states[first]
        run(speed, settle=True)
        return (
            "continuation to the branch's end (a fold or a loss of stability), then the jump: a settling "
            "run, Newton"
        )

    order = s if direction == "up" else s[::-1]
    previous = None
    for speed in order.tolist():
        spent = time.process_time()
        counted = 0.0
        if not solver.nonlinear:  # a unique solution at each speed
            run(speed)
            log.paths[speed] = solver.method.replace("_", " ")
        else:
            fresh = solver.start is None
            ok = run(speed, settle=previous is None)
            log.paths[speed] = (
                "Newton from the orbit of the speed before"
                if previous is not None
                else (
                    "a run from the static deflection, then Newton"
                    if fresh
                    else "Newton from the last orbit of the sweep before"
                )
            )
            if not ok and previous is not None and previous in states and rows[previous][5][3] != 1:
                # the orbit before is period-doubled (the continuation follows orbits of one period):
                # run from it at this speed until it settles, then Newton over one or two periods
                run(speed, settle=True)
                log.paths[speed] = "a settling run from the period-doubled orbit before, then Newton"
            elif not ok and previous is not None and previous in states:
                log.paths[speed] = follow_branch(previous, speed)
            elif not ok and previous is not None:  # no orbit at the speed before: start afresh by a run
                run(speed, settle=True)
                log.paths[speed] = "a settling run, then Newton (no orbit at the speed before)"
        log.cpu[speed] = time.process_time() - spent - counted
        previous = speed
    for _ in range(refine):
        grid = np.array(sorted(rows))
        amp = np.array([0.5 * (rows[g][0] - rows[g][1]) for g in grid]).reshape(grid.size, J)
        new: set[float] = set()
        for j in range(J):
            for i in _peaks(amp[:, j]):
                new.update({0.5 * (grid[i - 1] + grid[i]), 0.5 * (grid[i] + grid[i + 1])})
        new -= set(rows)
        if not new:
            break
        for speed in sorted(new, reverse=direction == "down"):
            spent = time.process_time()
            start = None
            if solver.nonlinear:  # from the speed visited before it, on the same branch
                before = [g for g in states if (g < speed if direction == "up" else g > speed)]
                if before:
                    start = states[max(before) if direction == "up" else min(before)]
            run(float(speed), start=start)
            log.paths[float(speed)] = (
                "Newton from the nearest orbit before it (a speed added at a peak)"
                if solver.nonlinear
                else solver.method.replace("_", " ")
            )
            log.cpu[float(speed)] = time.process_time() - spent
    grid = np.array(sorted(rows))
    return grid, [np.array([rows[g][k] for g in grid]).reshape(grid.size, -1) for k in range(6)], jumps


def _row(
    lin: LinearPeriodic,
    plan: PeriodPlan,
    speed: float,
    t: np.ndarray,
    x: np.ndarray,
    v: np.ndarray,
    ok: bool,
    rho: float,
    closure: float,
    multiple: int,
) -> tuple[np.ndarray, ...]:
    """One speed's stacked row: force max, min, RMS, static force, DTE amplitude, [converged, ρ,
    closure, periods]."""
    force, delta = _mesh_forces(lin, plan, speed, t, x, v)
    return (
        force.max(axis=0),
        force.min(axis=0),
        np.sqrt(np.mean(force**2, axis=0)),
        _static_forces(lin, speed),
        0.5 * np.ptp(delta, axis=0),
        np.array([ok, rho, closure, multiple]),
    )


def _branch_row(
    lin: LinearPeriodic, plan: PeriodPlan, branch: ContinuedBranch, i: int
) -> tuple[np.ndarray, ...]:
    """The stacked row of a continuation point (a stable orbit of the branch the sweep follows)."""
    m = lin.m
    assert branch.samples is not None
    y = branch.samples[i]
    N = y.shape[1]
    return _row(
        lin,
        plan,
        float(branch.speeds[i]),
        np.arange(N) / N,
        y[:m].T,
        y[m : 2 * m].T,
        True,
        float(branch.spectral_radius[i]),
        float(branch.closure[i]),
        1,
    )


def _first_edge(branch: ContinuedBranch) -> int | None:
    """The index of the branch's first located fold or loss of stability; None where it reached the
    speed asked for."""
    for i, kind in enumerate(branch.kinds):
        if kind in ("fold", "loss of stability"):
            return i
    return None


def _iso_factors(
    system: Any, lin: LinearPeriodic, speeds: np.ndarray, static: np.ndarray, gear_pairs: Mapping[str, Any]
) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """ISO 6336-1 K_v per speed for the meshes whose gear pair is given (NaN elsewhere), the reference
    speed of each pair's own resonance n_E1 (rad/s, NaN elsewhere), and notes."""
    out = np.full((speeds.size, len(lin.names)), np.nan)
    resonance = np.full(len(lin.names), np.nan)
    notes: list[str] = []
    for name in gear_pairs:
        if name not in lin.names:
            raise ModelError(
                f"gear data for {name!r}, which is not a flexible mesh; give one of {', '.join(lin.names)}",
                element="gear dynamics",
                field="gear_pairs",
            )
    if not gear_pairs:
        return out, resonance, notes
    from mechdyn.gears.iso6336 import iso_dynamic_factor as iso

    dt = system.drivetrain
    meshes = {m.name: m for m in system.meshes}
    for name, pair in gear_pairs.items():
        j = lin.names.index(name)
        pinion_ratio = float(np.abs(np.asarray(meshes[name].phase_row, float) @ lin.rigid))
        pinion_speed = pinion_ratio * speeds
        force = float(np.mean(np.abs(static[:, j])))
        if force == 0.0:
            notes.append(f"mesh {name!r}: no load, so no ISO 6336-1 K_v")
            continue
        element = dt.element(name)
        inertia_a, inertia_b = (float(dt.disks[dt.disk_index[d]].inertia) for d in element.disks)
        inertias = (inertia_a, inertia_b)
        factor = iso(
            pair,
            pinion_speed,
            force * pair.pinion.base_radius,
            inertias=inertias,  # T₁ = F_bn r_b1
        )
        out[:, j] = np.asarray(factor.K_v, float)
        resonance[j] = float(factor.resonance_speed) / pinion_ratio
        notes.extend(f"ISO 6336-1 K_v of {name!r}: {n}" for n in factor.notes)
    return out, resonance, notes


def _check_sweep_cost(
    lin: LinearPeriodic,
    plan: PeriodPlan,
    s: np.ndarray,
    H: int,
    given: int | None,
    balance: bool,
    stability: bool,
    *,
    solver_substeps: int,
    refine: int,
) -> None:
    """Refuse (or warn on) a sweep that its counts make too large (:mod:`._cost`), naming the field."""
    low = float(s.min())
    if balance and given is None:
        need = needed_harmonics(lin, plan, low)
        if need > MAX_AUTO:
            from mechdyn.units import convert

            ok = low * need / MAX_AUTO
            low_rpm, ok_rpm = (float(convert(v, "rad/s", "rpm")) for v in (low, ok))
            raise ModelError(
                f"at the lowest speed, {low_rpm:.4g} rpm, the mesh frequency is so far below the train's "
                f"highest natural frequency that {need} harmonics would be needed (at most {MAX_AUTO} are "
                f"chosen); start the range at {ok_rpm:.4g} "
                "rpm or above, or give harmonics (and read the estimated error it states)",
                element="gear dynamics",
                field="speed_range",
            )
    nonlinear = any(b is not None for b in lin.backlash)
    top = int(plan.orders.max()) if plan.orders.size else 1
    seg = segments(lin, plan, solver_substeps, low) if (stability or nonlinear) else 0
    n_speeds = int(s.size * (1.3 if refine else 1.0)) + 2
    cost = sweep_cost(
        n_speeds, int(np.count_nonzero(plan.orders)), H, top, 2 * lin.m, seg, stability, nonlinear
    )
    memory_bound = 16.0 * (np.count_nonzero(plan.orders) * (2 * H * max(top, 1) + 1)) ** 2 >= cost.bytes
    field = ("harmonics" if given is not None else "speed_range") if memory_bound else "points"
    check_cost(
        cost,
        "gear dynamics",
        field,
        "give fewer speeds (points), a higher lowest speed or fewer harmonics, or no stability check",
    )


def _stack_kv(stack: list[np.ndarray]) -> np.ndarray:
    """(n_s, J) K_v of the stacked rows (force max, min, …, static force)."""
    force_max, force_min, static = stack[0], stack[1], stack[3]
    extreme = np.where(np.sign(static) >= 0, force_max, -force_min)
    with np.errstate(invalid="ignore", divide="ignore"):
        return extreme / np.abs(static)


def _sweep_kv(stack: list[np.ndarray]) -> np.ndarray:
    force_max, force_min, static = stack[0], stack[1], stack[3]
    loaded = np.abs(static) > 1e-9 * np.maximum(np.abs(force_max), np.abs(force_min))
    return np.where(loaded, 1.0, np.nan)
