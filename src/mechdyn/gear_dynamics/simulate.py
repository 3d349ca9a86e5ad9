"""Time simulation of a geared drivetrain: time-varying mesh stiffness, transmission error, backlash,
motors and loads.

The equations of motion of :class:`~mechdyn.gear_dynamics.GearSystem`,

.. math:: M \\ddot q + C \\dot q + K q + \\sum_j g_j f_j(q, \\dot q) = Q(t, \\dot q),

are integrated step by step by a :mod:`scipy.integrate` solver (``LSODA`` by default: Adams or the
stiff BDF formulas as the train needs) with a compiled right-hand side and Jacobian
(:mod:`mechdyn.gear_dynamics._kernel`). Three things keep the accuracy of the piecewise model:

* **Contact changes are events.** Each mesh with backlash is in one of three modes (drive-side
  contact, gap, back-side contact), a discrete state the force reads. After every step a compiled
  call gives x = δ − e of every mesh, and each exit of its mode is checked on its own, with its
  direction: drive → gap where x falls through 0, back → gap where x rises through −b, gap → drive
  where x rises through 0, gap → back where x falls through −b (so that a step that carries the
  teeth across the whole backlash is seen, and the side hit decides the new mode). The instant is
  located by Brent's method on the step's dense output, and the integration restarts there in the
  new mode, so that no step straddles the kink of the force or the jump of the contact damping
  (:mod:`mechdyn.gear_dynamics._events`). (This is :func:`scipy.integrate.solve_ivp`'s event
  handling, done on the solver's steps directly: one compiled call per step for all meshes instead
  of one Python call per mesh.)
* **A restart sits on the boundary it has crossed.** The located root is a rounding error on either
  side of it; the new mode is left only after x has been inside it (the step is probed from the
  restart on), so that a state a rounding error on the old side is not a new crossing. Where x
  never gets inside (a grazing touch: the relative velocity zero at the boundary), the mesh goes
  back at once, and the touch is not recorded as a change. The contact law is
  :func:`mechdyn.gear_dynamics._contact.mesh_force` (Kelvin–Voigt: f = k h + c ẋ_r in contact, which
  may pull just before the teeth part), the one Newton's shooting integrates
  (:mod:`mechdyn.gear_dynamics._nonsmooth`), so that a run settles on the orbit it finds there.
* **The mesh cycle is resolved.** The stiffness profile may jump (single/double tooth contact); its
  samples are joined by straight lines, so the jump is a steep ramp. The step is limited to
  1/``cycle_steps`` (default 8) of the shortest mesh period at the speed the present acceleration
  gives at the end of each segment of 20 mesh cycles, so that the error control cannot step over a
  ramp unseen; the error control then resolves the ramp itself. (Tested far above the resonance,
  where the response is smooth and steps would otherwise grow to a large part of the mesh period:
  with one or two steps per cycle the error was half the response on one machine and 0.3 % on another,
  as the steps follow the rounding; with eight it is within 1 % of a reference run on both.)
  Events at every jump were the alternative: each would restart the multistep integrator at order
  one, for two or more jumps per mesh and cycle.
* **The error control sees deflections.** The state is the rigid angle of each free branch and the
  deflections relative to it, not the absolute angles: after a thousand revolutions a relative
  tolerance on the angles would swamp the micrometre deflections of the teeth.

The work of the inputs, the energy dissipated and the work of the parametric excitation are
integrated with the motion, so that every run carries its own energy balance.
"""

from __future__ import annotations

import math
import time as _time
from collections.abc import Sequence
from typing import Any

import numpy as np

from mechdyn.checks import check_count
from mechdyn.errors import ModelError
from mechdyn.gear_dynamics._contact import BACK, DRIVE, GAP, NO_BACKLASH, mesh_forces
from mechdyn.gear_dynamics._events import EXIT_TO, exit_time, exits
from mechdyn.gear_dynamics.result import ContactLoss, SimulationResult
from mechdyn.gear_dynamics.system import GearSystem
from mechdyn.units import si_field

__all__ = ["simulate", "static_deflection"]

SEGMENT_CYCLES = 20
"""Mesh cycles per integration segment; the step limit follows the speed from segment to segment."""


def _kernels() -> Any:
    from mechdyn._compiled import announce
    from mechdyn.gear_dynamics import _contact, _kernel

    announce(
        _kernel.rhs,
        _kernel.jacobian,
        _kernel.event_values,
        _kernel.event_value,
        _contact.mesh_force,
        _contact.mesh_forces,
    )
    return _kernel


def _coordinates(system: GearSystem) -> tuple[np.ndarray, np.ndarray]:
    """A (q = A z) with each free branch's reference coordinate replaced by its rigid-body motion."""
    n = system.n
    A = np.eye(n)
    R = system.rigid_body
    for k in range(R.shape[1]):
        r = R[:, k]
        i = int(np.argmax(np.abs(r)))
        A[:, i] = r / r[i]
    return A, np.linalg.inv(A)


def _load_torques(system: GearSystem, inputs: Sequence[Any], t: float, qd: np.ndarray) -> np.ndarray:
    Q = np.zeros(system.n)
    for load in inputs:
        row = system.input_vector(load.disk)
        Q += row * load.torque(t, float(row @ qd))
    return Q


def static_deflection(system: GearSystem, Q: np.ndarray, taus: np.ndarray | None = None) -> np.ndarray:
    """Quasi-static deflection under the generalised forces ``Q``, the rigid acceleration taken out.

    Solves K u = Q − M R α with Rᵀ M u = 0, α = (Rᵀ M R)⁻¹ Rᵀ Q (d'Alembert: a free train under a net
    torque accelerates as a rigid body and deflects as if its inertia forces were loads).

    Parameters
    ----------
    system : GearSystem
        The system (its meshes in contact, at the phases ``taus``).
    Q : ndarray
        (n,) generalised forces, N·m per unit coordinate.
    taus : ndarray, optional
        Mesh phases, cycles (dimensionless); default: the mean stiffness.

    Returns
    -------
    ndarray
        (n,) deflection u, rad per unit coordinate.
    """
    K = system.K_mean if taus is None else system.K_at(taus)
    R, M = system.rigid_body, system.M
    r = R.shape[1]
    if r == 0:
        return np.linalg.solve(K, Q)
    MR = M @ R
    alpha = np.linalg.solve(R.T @ MR, R.T @ Q)
    n = system.n
    big = np.zeros((n + r, n + r))
    big[:n, :n] = K
    big[:n, n:] = MR
    big[n:, :n] = MR.T
    rhs = np.concatenate([Q - MR @ alpha, np.zeros(r)])
    return np.linalg.solve(big, rhs)[:n]


def _packed(system: GearSystem) -> dict[str, Any]:
    m = len(system.meshes)
    n = system.n
    p_max = max([mesh.samples for mesh in system.meshes] + [1])
    prof = np.ones((m, p_max))
    err = np.zeros((m, p_max))
    for j, mesh in enumerate(system.meshes):
        prof[j, : mesh.samples] = mesh.profile
        err[j, : mesh.samples] = mesh.error
    return {
        "G": np.array([mesh.g for mesh in system.meshes]).reshape(m, n),
        "PH": np.array([mesh.teeth * mesh.phase_row / (2.0 * math.pi) for mesh in system.meshes]).reshape(
            m, n
        ),
        "prof": prof,
        "err": err,
        "P": np.array([mesh.samples for mesh in system.meshes], dtype=np.int64),
        "kbar": np.array([mesh.mean_stiffness for mesh in system.meshes]),
        "cm": np.array([mesh.damping for mesh in system.meshes]),
        "gap": np.array([-1.0 if mesh.backlash is None else mesh.backlash for mesh in system.meshes]),
    }


def _check_simulation_cost(
    system: GearSystem,
    inputs: tuple[Any, ...],
    ref: str,
    w0: float,
    duration: float,
    cycle_steps: int,
    out_step: float | None,
) -> None:
    """Refuse or warn on a run that its duration, speed and output step make too long or too large
    (:mod:`._cost`): the fastest mesh frequency at the highest speed the inputs reach (a motor's
    no-load speed over its ratio, or the initial speed)."""
    from mechdyn.gear_dynamics._cost import check, simulation_cost

    try:
        ratios = system.speed_ratios(ref)
    except ModelError:  # a grounded branch: no rigid rotation to reach a speed by
        ratios = np.zeros(system.n)
    top = abs(w0)
    for item in inputs:
        motor = getattr(item, "drive", item)  # a stop's motor
        curve = getattr(motor, "motor", None)
        if curve is not None and hasattr(curve, "no_load_speed"):
            share = abs(float(system.T[system.disk(motor.disk)] @ ratios)) or 1.0
            top = max(top, float(curve.no_load_speed) / float(motor.ratio) / share)
    fastest = max(
        (m.teeth * abs(float(m.phase_row @ ratios)) * top / (2 * math.pi) for m in system.meshes), default=0.0
    )
    samples = duration / out_step if out_step is not None else None
    cost = simulation_cost(duration, fastest, cycle_steps, system.n, len(system.meshes), samples)
    field = "output_step" if cost.bytes > 2**30 and samples is not None else "duration"
    check(cost, system.drivetrain.name, field, "give a shorter duration or a longer output_step")


def simulate(
    system: GearSystem,
    duration: Any,
    *,
    inputs: Sequence[Any] = (),
    initial_speed: Any = 0.0,
    reference: str | None = None,
    start: str = "static",
    method: str = "LSODA",
    rtol: float = 1e-7,
    atol: Any = 1e-10,
    cycle_steps: int = 8,
    max_step: Any = None,
    output_step: Any = None,
    energy_atol: Any = None,
    max_events: int = 100_000,
) -> SimulationResult:
    """Integrate a geared drivetrain in time.

    Parameters
    ----------
    system : GearSystem
        The drivetrain with its meshes' stiffness profiles, errors and backlash.
    duration : float or quantity
        Simulated time, s.
    inputs : sequence of torque inputs
        :mod:`mechdyn.gear_dynamics.loads` objects (``disk``, ``torque(t, speed)`` in N·m,
        ``breakpoints`` in s); their torques add.
    initial_speed : float or quantity
        Speed of the ``reference`` disk at t = 0, rad/s (e.g. ``"1480 rpm"``); every disk starts in the
        rigid rotation of that speed (:meth:`GearSystem.speed_ratios`).
    reference : str, optional
        The disk of ``initial_speed`` (default: the first disk).
    start : {"static", "rest"}
        ``static``: the train starts deflected by the inputs' torques at t = 0 (the quasi-static
        deflection of :func:`static_deflection`, the meshes in contact at their phase, on the back
        flanks where the load pushes them there); ``rest``: not deflected.
    method : str
        :func:`scipy.integrate.solve_ivp` method: ``LSODA`` (default: switches between Adams and
        the stiff BDF formulas as the train needs, with the compiled Jacobian; the fastest here),
        ``Radau`` or ``BDF`` (implicit, stiff), or the explicit ``DOP853`` / ``RK45``.
    rtol : float
        Relative tolerance, dimensionless.
    atol : float or quantity
        Absolute tolerance on the mesh deflections along the line of action, m; converted into angles
        (rad) through the largest base radius and into speeds through the highest natural frequency.
    cycle_steps : int
        Fewest integration steps per mesh cycle (count), see the module docstring.
    max_step : float or quantity, optional
        Longest integration step, s (default: by ``cycle_steps`` only).
    output_step : float or quantity, optional
        Sample the result every ``output_step`` s (default: at every integration step and event).
    energy_atol : float or quantity, optional
        Absolute tolerance on the integrated input work, dissipation and parametric work, J. Default:
        they are integrated on the steps the motion needs, outside the error control (cheaper; their
        integrands spike where the stiffness jumps, so the balance then holds to the step's accuracy,
        not to the tolerance).
    max_events : int
        Most contact changes before the run stops with an error (count): a chattering contact.

    Returns
    -------
    SimulationResult

    Raises
    ------
    mechdyn.errors.ModelError
        For bad arguments (naming the argument and the fix), or when the integrator fails.

    Notes
    -----
    Mesh force f = k(τ) h(δ − e) + c_m (δ̇ − ė) in contact (Kahraman & Singh, J. Sound Vib. 142 (1990)
    49–75); contact events as in hybrid-system integration (e.g. Hairer, Nørsett & Wanner, *Solving
    Ordinary Differential Equations I*, §II.6, dense output and discontinuities).
    """
    if not isinstance(system, GearSystem):
        raise ModelError(
            f"{type(system).__name__} is not a GearSystem; build one with GearSystem.from_drivetrain",
            element="simulate",
            field="system",
        )
    name = system.drivetrain.name
    t_total = si_field(name, "duration", duration, "s", positive=True)
    rtol = si_field(name, "rtol", rtol, "", low=1e-13, high=1e-2)
    atol_m = si_field(name, "atol", atol, "m", low=1e-18, high=1e-3)
    cycle_steps = check_count(name, "cycle_steps", cycle_steps, low=1, high=100_000)
    max_events = check_count(name, "max_events", max_events, low=1, high=10**9)
    user_max_step = math.inf if max_step is None else si_field(name, "max_step", max_step, "s", positive=True)
    out_step = None if output_step is None else si_field(name, "output_step", output_step, "s", positive=True)
    if start not in ("static", "rest"):
        raise ModelError(f"start {start!r} must be 'static' or 'rest'", element=name, field="start")
    if method not in ("Radau", "BDF", "LSODA", "RK45", "RK23", "DOP853"):
        raise ModelError(
            f"method {method!r} is not a solve_ivp method; give Radau, BDF, LSODA, RK45, RK23 or DOP853",
            element=name,
            field="method",
        )
    inputs = tuple(inputs)
    for load in inputs:
        if not (callable(getattr(load, "torque", None)) and hasattr(load, "disk")):
            raise ModelError(
                f"{load!r} is not a torque input (disk, torque(t, speed), breakpoints)",
                element=name,
                field="inputs",
            )
        system.disk(load.disk)
    ref = reference if reference is not None else system.drivetrain.disk_names[0]
    system.disk(ref)
    w0 = si_field(name, "initial_speed", initial_speed, "rad/s")
    if out_step is not None and out_step > t_total:
        raise ModelError(
            f"output_step {out_step:g} s is longer than the duration {t_total:g} s; give at most "
            f"{t_total / 100:g} s (100 samples)",
            element=name,
            field="output_step",
        )
    _check_simulation_cost(system, inputs, ref, w0, t_total, cycle_steps, out_step)

    kern = _kernels()
    n = system.n
    A, A_inv = _coordinates(system)
    M_inv = np.linalg.inv(system.M)  # factored once (diagonal unless a shaft has consistent inertia)
    W = A_inv @ M_inv
    pk = _packed(system)
    m = len(system.meshes)
    K, C = np.ascontiguousarray(system.K), np.ascontiguousarray(system.C)

    # initial state
    qd0 = np.zeros(n)
    if w0 != 0.0:
        qd0 = w0 * system.speed_ratios(ref)
    q0 = np.zeros(n)
    if start == "static" and inputs:
        Q_in = _load_torques(system, inputs, 0.0, qd0)
        taus = system.mesh_phases(q0)
        back = np.zeros(m)  # the backlash crossed by a mesh loaded on its back flanks
        for _ in range(2):
            Q0 = Q_in.copy()
            for j, (mesh, tau) in enumerate(zip(system.meshes, taus, strict=True)):
                # the error displaces the flanks: the teeth see δ − e (− b on the back flanks)
                Q0 += mesh.g * mesh.stiffness(tau) * (mesh.transmission_error(tau) - back[j])
            q0 = static_deflection(system, Q0, taus if m else None)
            x = np.array(
                [
                    mesh.g @ q0 - mesh.transmission_error(tau)
                    for mesh, tau in zip(system.meshes, taus, strict=True)
                ]
            )
            flip = np.array([mesh.backlash or 0.0 for mesh in system.meshes]) * (x < 0)
            if np.array_equal(flip, back):
                break
            back = flip
    y = np.concatenate([A_inv @ q0, A_inv @ qd0, np.zeros(3)])

    # tolerances: deflections in rad from the mesh geometry, speeds from the highest frequency
    g_scale = float(np.abs(pk["G"] @ A).sum(axis=1).max()) if m else 1.0
    angle_tol = atol_m / g_scale
    lam = np.linalg.eigvals(M_inv @ system.K_mean)
    w_max = float(np.sqrt(np.max(np.abs(lam)))) if lam.size else 1.0
    w_max = w_max if w_max > 0 else 1.0
    energy_tol = (
        np.inf
        if energy_atol is None
        else si_field(name, "energy_atol", energy_atol, "J", low=1e-30, high=1e30)
    )
    atol_vec = np.concatenate([np.full(n, angle_tol), np.full(n, angle_tol * w_max), np.full(3, energy_tol)])

    mode = np.zeros(m, dtype=np.int64)
    ev_buf = np.zeros(m)
    gap = pk["gap"]
    has_gap = gap >= 0
    if m:
        kern.event_values(y, n, A, pk["G"], pk["PH"], pk["err"], pk["P"], ev_buf)
        mode[has_gap & (ev_buf < 0)] = GAP
        mode[has_gap & (ev_buf <= -gap)] = BACK
    # each mode's exits: margin = sign · x + offset, positive inside the mode, per mesh and boundary
    exit_sign, exit_offset = exits(gap)

    breakpoints = sorted({b for load in inputs for b in load.breakpoints if 0.0 < b < t_total})
    out_buf = np.zeros(2 * n + 3)
    Srows = np.array([system.input_vector(load.disk) for load in inputs]).reshape(len(inputs), n)
    Srows_A = Srows @ A
    torque_fns = [load.torque for load in inputs]
    PH_A = pk["PH"] @ A
    n_calls = [0]
    Q_none = np.zeros(n)

    def fun(t: float, yy: np.ndarray) -> np.ndarray:
        n_calls[0] += 1
        if torque_fns:
            speeds = (Srows_A @ yy[n : 2 * n]).tolist()
            Q = np.array([fn(t, w) for fn, w in zip(torque_fns, speeds, strict=True)]) @ Srows
        else:
            Q = Q_none
        kern.rhs(yy, out_buf, n, A, W, K, C, Q, pk["G"], pk["PH"], pk["prof"], pk["err"], pk["P"],
                 pk["kbar"], pk["cm"], gap, mode)  # fmt: skip
        return out_buf.copy()

    def jac(t: float, yy: np.ndarray) -> np.ndarray:
        J = kern.jacobian(
            yy, n, A, W, K, C, pk["G"], pk["PH"], pk["prof"], pk["P"], pk["kbar"], pk["cm"], mode
        )
        if torque_fns:  # a torque that follows the speed (a motor, a brake) damps or drives: its slope
            speeds = Srows_A @ yy[n : 2 * n]
            D = np.zeros((n, n))
            for i, fn in enumerate(torque_fns):
                w = float(speeds[i])
                h = 1e-7 * max(1.0, abs(w))
                slope = (fn(t, w + h) - fn(t, w - h)) / (2.0 * h)
                if slope:
                    D += slope * np.outer(Srows[i], Srows_A[i])
            J[n : 2 * n, n : 2 * n] += W @ D
        return J

    import scipy.integrate

    solver_class = getattr(scipy.integrate, method)
    solver_kwargs: dict[str, Any] = {"jac": jac} if method in ("Radau", "BDF", "LSODA") else {}
    any_gap = bool(has_gap.any())
    event_args = (n, A, pk["G"], pk["PH"], pk["err"], pk["P"])
    rows = np.arange(m)

    def margins(yy: np.ndarray) -> np.ndarray:
        """(m, 2) distances of x from the two exits of each mesh's present mode (inf: no exit)."""
        kern.event_values(yy, *event_args, ev_buf)
        sg, off = exit_sign[mode], exit_offset[rows, mode]
        return sg * ev_buf[:, None] + off

    times: list[np.ndarray] = [np.array([0.0])]
    states: list[np.ndarray] = [y[:, None].copy()]
    modes: list[np.ndarray] = [mode[:, None].copy()]
    changes: list[tuple[float, int, int, int]] = []
    n_switches = 0  # the changes, grazing touches included
    t = 0.0
    segments = 0
    started = _time.perf_counter()
    while t < t_total * (1 - 1e-14):
        seg, step = t_total / 20.0, user_max_step
        if m:
            # mesh frequencies now and, from the present acceleration, at the end of the segment
            rate = np.abs(PH_A @ y[n : 2 * n])
            accel = np.abs(PH_A @ fun(t, y)[n : 2 * n])
            if rate.max() > 0:
                seg = min(seg, SEGMENT_CYCLES / rate.max())
            f_hat = float((rate + accel * seg).max())
            if f_hat > 0:
                seg = min(seg, SEGMENT_CYCLES / f_hat)
                step = min(step, 1.0 / (cycle_steps * f_hat))
        tiny = 1e-12 * t_total  # a segment end this close to a breakpoint or the end is moved onto it
        t_end = min(t_total, t + seg)
        for b in breakpoints:
            if t + tiny < b < t_end + tiny:
                t_end = b
                break
        if t_total - t_end < tiny:
            t_end = t_total
        grid: np.ndarray = np.zeros(0)
        if out_step is not None:
            k0 = max(math.floor(t / out_step) - 1, 1)
            grid = np.arange(k0, math.floor(t_end / out_step * (1 + 1e-12)) + 1) * out_step
            grid = grid[(grid > t) & (grid <= t_end)]
            if t_end == t_total and (grid.size == 0 or grid[-1] < t_total * (1 - 1e-12)):
                grid = np.append(grid, t_total)
        solver = solver_class(fun, t, y, t_end, max_step=step, rtol=rtol, atol=atol_vec, **solver_kwargs)
        segments += 1
        s_prev = margins(y) if any_gap else None
        hit: list[tuple[int, int]] = []
        while solver.status == "running":
            solver.step()
            if solver.status == "failed":
                raise ModelError(
                    f"the integrator ({method}) failed at t = {solver.t:.6g} s; try a smaller rtol, another "
                    "method or a smaller max_step",
                    element=name,
                    field="method",
                )
            t0, t1 = float(solver.t_old), float(solver.t)
            dense = None
            t_hit = t1
            if any_gap:
                s_new = margins(solver.y)
                assert s_prev is not None
                for jj, side in np.argwhere(s_new < 0).tolist():  # a mesh past an exit of its mode
                    dense = dense if dense is not None else solver.dense_output()
                    sg, off = float(exit_sign[mode[jj], side]), float(exit_offset[jj, mode[jj], side])
                    root = exit_time(kern, dense, t0, t1, sg, off, jj, event_args, bool(s_prev[jj, side] > 0))
                    if root < t_hit - 1e-15 * max(1.0, t_hit):
                        t_hit, hit = root, [(jj, side)]
                    elif abs(root - t_hit) <= 1e-15 * max(1.0, t_hit):
                        hit.append((jj, side))
                s_prev = s_new
            upto = t_hit if hit else t1
            if out_step is None:
                if hit:
                    assert dense is not None
                    times.append(np.array([t_hit]))
                    states.append(np.asarray(dense(t_hit))[:, None])
                else:
                    times.append(np.array([t1]))
                    states.append(solver.y[:, None].copy())
                modes.append(mode[:, None].copy())
            else:
                pts = grid[(grid > t0) & (grid <= upto)]
                if pts.size:
                    dense = dense if dense is not None else solver.dense_output()
                    times.append(pts)
                    states.append(np.asarray(dense(pts)).reshape(-1, pts.size))
                    modes.append(np.repeat(mode[:, None], pts.size, axis=1))
            if hit:
                assert dense is not None
                y = np.asarray(dense(t_hit), dtype=float).copy()
                for j, side in hit:
                    old = int(mode[j])
                    new = int(EXIT_TO[old, side])
                    mode[j] = new
                    if changes and changes[-1] == (t_hit, j, new, old):
                        changes.pop()  # a grazing touch: entered and left at one instant, no change
                    else:
                        changes.append((t_hit, j, old, new))
                    n_switches += 1
                if n_switches > max_events:
                    raise ModelError(
                        f"more than {max_events} contact changes by t = {t_hit:.6g} s: the contact chatters; "
                        "add mesh damping, or raise max_events",
                        element=name,
                        field="max_events",
                    )
                t = t_hit
                break
        else:
            y = solver.y.copy()
            t = t_end
    wall = _time.perf_counter() - started

    tt = np.concatenate(times)
    Z = np.concatenate(states, axis=1)
    modes_all = np.concatenate(modes, axis=1)
    q = A @ Z[:n]
    qd = A @ Z[n : 2 * n]
    return _result(
        system, inputs, tt, q, qd, Z[2 * n :], modes_all, changes, method, wall, segments, n_calls[0]
    )


def _result(
    system: GearSystem,
    inputs: tuple[Any, ...],
    t: np.ndarray,
    q: np.ndarray,
    qd: np.ndarray,
    work: np.ndarray,
    modes: np.ndarray,
    changes: list[tuple[float, int, int, int]],
    method: str,
    wall: float,
    segments: int,
    calls: int,
) -> SimulationResult:
    theta = system.T @ q
    omega = system.T @ qd
    m = len(system.meshes)
    N = t.size
    force = np.zeros((m, N))
    dte = np.zeros((m, N))
    strain = 0.5 * np.einsum("in,ij,jn->n", q, system.K, q)
    for j, mesh in enumerate(system.meshes):
        tau = mesh.teeth * (mesh.phase_row @ q) / (2.0 * math.pi)
        tau_d = mesh.teeth * (mesh.phase_row @ qd) / (2.0 * math.pi)
        from mechdyn.gear_dynamics.system import _periodic_slope

        e = mesh.transmission_error(tau)
        x = mesh.g @ q - e
        xd = mesh.g @ qd - _periodic_slope(mesh.error, tau) * tau_d
        k = mesh.stiffness(tau)
        force[j], h, _ = mesh_forces(
            np.full(N, k, dtype=float),
            np.full(N, mesh.damping, dtype=float),
            np.ascontiguousarray(x, dtype=float),
            np.ascontiguousarray(xd, dtype=float),
            np.full(N, NO_BACKLASH if mesh.backlash is None else mesh.backlash, dtype=float),
            np.ascontiguousarray(modes[j], dtype=np.int64),
        )
        dte[j] = x
        strain = strain + 0.5 * k * h * h
    kinetic = 0.5 * np.einsum("in,ij,jn->n", qd, system.M, qd)
    loads = {}
    dt = system.drivetrain
    from mechdyn.gear_dynamics.system import _dof_index

    idx = _dof_index(dt)
    for e, blk in dt.element_blocks:
        if blk.load_row is None or blk.load_unit != "N*m":
            continue
        d = [idx[x] for x in blk.disks]
        torque = blk.load_row @ theta[d]
        if blk.load_rate_row is not None:
            torque = torque + blk.load_rate_row @ omega[d]
        loads[e.name] = torque
    static = None
    if inputs:
        Q_end = _load_torques(system, inputs, float(t[-1]), qd[:, -1])
        u = static_deflection(system, Q_end)
        static = np.array([mesh.mean_stiffness * (mesh.g @ u) for mesh in system.meshes])
    loaded_flanks = None
    if inputs:  # the flanks the inputs press together at the start, else at the end of the run
        u0 = static_deflection(system, _load_torques(system, inputs, float(t[0]), qd[:, 0]))
        first = np.array([mesh.g @ u0 for mesh in system.meshes])
        last = static if static is not None else np.zeros(len(system.meshes))
        loaded_flanks = np.where(np.abs(first) > 0.0, np.sign(first), np.sign(last))
    losses = _contact_losses(system, modes[:, 0], changes, loaded_flanks)
    return SimulationResult(
        system=system,
        time=t,
        angles=theta,
        speeds=omega,
        mesh_forces=force,
        dte=dte,
        element_torques=loads,
        contact_modes=modes,
        contact_losses=losses,
        energy={
            "kinetic": kinetic,
            "strain": strain,
            "input_work": work[0],
            "dissipated": work[1],
            "parametric_work": work[2],
        },
        static_mesh_forces=static,
        method=method,
        stats={"wall_s": wall, "segments": segments, "rhs_calls": calls, "contact_changes": len(changes)},
    )


def _contact_losses(
    system: GearSystem,
    initial: np.ndarray,
    changes: list[tuple[float, int, int, int]],
    loaded_flanks: np.ndarray | None,
) -> tuple[ContactLoss, ...]:
    """Intervals in which each mesh's loaded flanks are apart, left for the gap and regained. The loaded
    flanks are those the inputs press together (``loaded_flanks``: the sign of the quasi-static mesh
    force at the start, else at the end of the run; in a train whose disks turn both ways the back
    flanks of some meshes carry the load), else those in contact at the start (the drive side when the
    run starts in the gap)."""
    out = []
    for j, mesh in enumerate(system.meshes):
        if loaded_flanks is not None and loaded_flanks[j] != 0.0 and mesh.backlash is not None:
            working = DRIVE if loaded_flanks[j] > 0.0 else BACK
        else:
            working = DRIVE if initial[j] == GAP else int(initial[j])
        opposite = BACK if working == DRIVE else DRIVE
        start: float | None = 0.0 if initial[j] != working else None
        impacts = 0
        for t, jj, old, new in changes:
            if jj != j:
                continue
            if old == working and new == GAP:
                start, impacts = t, 0
            elif new == opposite:
                impacts += 1
            elif new == working and start is not None:
                out.append(ContactLoss(mesh.name, start, t, impacts))
                start = None
        if start is not None:
            out.append(ContactLoss(mesh.name, start, None, impacts))
    return tuple(out)
