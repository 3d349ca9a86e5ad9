"""Forward dynamics of the driven mechanism: the periodic steady state, the start-up from rest and the
flywheel that holds the speed.

The machine has one degree of freedom, the crank angle φ turned in the direction of rotation. With
J(φ) = I(φ) + J_a (the mechanism's reduced inertia and the train's, flywheel's and rotor's, reduced
to the crank), the machine's kinetic energy K = ½ J φ̇² changes by the motor's power less the
train's losses and the applied forces' power; over the crank angle,

    dK/dφ = n T_m(n φ̇) − T_loss(φ, φ̇) + Q(φ),

with T_loss the power the stages lose over φ̇, found with the crank acceleration at every sample
from the torque each stage carries in the direction it carries it (:mod:`mechdyn.drive.train`; zero
for a lossless train). This energy form (Uicker, Pennock and Shigley, *Theory of Machines and
Mechanisms*, 5th ed., §16 on flywheels; the equation of motion of a machine in its energy form,
Harrison and Nettleton, *Advanced Engineering Dynamics*, ch. 7) is integrated by the classical
fourth-order Runge–Kutta rule over the crank angles of the mechanism's kinematics (the midpoints of
each step are samples too, so nothing is interpolated). The periodic steady state is the fixed point
K(2π) = K(0) of one revolution, found by the secant method on K(0) (shooting). Runge–Kutta rules
keep linear invariants, so the work of the motor, the work of the applied forces and the change of
kinetic energy balance to round-off, step by step. The start-up from rest is integrated in time
(``scipy.integrate.solve_ivp``, LSODA by default, which switches to a stiff method where needed).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from mechdyn.errors import MechdynError, ModelError

__all__ = ["StallError", "StartUp", "SteadyState", "size_flywheel", "start_up", "steady_state"]

SHOOTING_RTOL = 1e-12  # |K(2π) − K(0)| over K(0) at the steady state
MAX_SHOTS = 60
STOP_FRACTION = 1e-9  # a crank slower than this fraction of the steady mean speed has stopped
LONGEST_REVOLUTION = 1e3  # steady periods a start-up revolution may take at most (a slow run-up)


class StallError(MechdynError):
    """The motor cannot keep the machine turning: the crank stops (or would turn backward)."""


@dataclass(frozen=True)
class SteadyState:
    """One revolution of the periodic steady state, at the crank angles of the reduced mechanism.

    Attributes
    ----------
    turned : ndarray
        (N,) φ, crank angle turned from the first sample, rad.
    speed : ndarray
        (N,) φ̇, crank speed, rad/s.
    acceleration : ndarray
        (N,) φ̈, crank acceleration, rad/s².
    time : ndarray
        (N,) time from the first sample, s.
    period : float
        Time of one revolution, s.
    crank_torque : ndarray
        (N,) the motor's torque reduced to the crank, n T_m, N·m (before the train's losses).
    loss_torque : ndarray
        (N,) the power the train's stages lose, over the crank speed, N·m (≥ 0).
    motor_work : float
        Work of the motor's shaft over the revolution, J.
    loss_work : float
        Work lost in the train's stages over the revolution, J.
    applied_work : float
        Work of the applied forces Q over the revolution (gravity and process), J (negative when they
        absorb energy).
    process_work : float
        Work of the process forces over the revolution, J.
    energy_change : float
        K(2π) − K(0), J (zero to the shooting tolerance).
    energy_residual : float
        W_motor − W_losses + W_applied − ΔK, J: zero to round-off (the integrator's balance).
    shots : int
        Revolutions integrated by the shooting, a count.
    """

    turned: np.ndarray
    speed: np.ndarray
    acceleration: np.ndarray
    time: np.ndarray
    period: float
    crank_torque: np.ndarray
    loss_torque: np.ndarray
    motor_work: float
    loss_work: float
    applied_work: float
    process_work: float
    energy_change: float
    energy_residual: float
    shots: int

    @property
    def mean_speed(self) -> float:
        """ω_mean = 2π / period, the time-average crank speed, rad/s."""
        return 2 * math.pi / self.period

    @property
    def fluctuation(self) -> float:
        """δ = (ω_max − ω_min) / ω_mean, the coefficient of speed fluctuation, dimensionless."""
        return float((self.speed.max() - self.speed.min()) / self.mean_speed)


@dataclass(frozen=True)
class StartUp:
    """The start-up from rest in time.

    Attributes
    ----------
    time : ndarray
        (M,) s.
    turned : ndarray
        (M,) φ, crank angle turned, rad.
    speed : ndarray
        (M,) φ̇, crank speed, rad/s.
    engaged_at : float
        Time from which the process forces act, s (the first crank pass at or above the steady mean
        speed: the press runs up idle, then forms every stroke).
    settled_at : float
        Time after which every crank pass is within ``tolerance`` of the steady state's speed, s.
    deviation : float
        Largest abs(φ̇ − φ̇_steady(φ)) over the last revolution, relative to the steady mean speed,
        dimensionless.
    revolutions : int
        Whole revolutions integrated, a count.
    method : str
        The ``solve_ivp`` method.
    """

    time: np.ndarray
    turned: np.ndarray
    speed: np.ndarray
    engaged_at: float
    settled_at: float
    deviation: float
    revolutions: int
    method: str


def _tables(drive: Any, reduced: Any) -> tuple[list[float], list[float], list[float], list[float]]:
    J = (reduced.inertia + drive.added_inertia).tolist()
    return J, reduced.inertia_slope.tolist(), reduced.force.tolist(), reduced.process_force.tolist()


def _rate(drive: Any, reduced: Any) -> Callable[[int, float], tuple[float, float]]:
    """The motor's torque reduced to the crank, N_0 T_m, and the train's loss torque at the crank, at
    sample i with the kinetic energy K (both N·m): dK/dφ = N_0 T_m − loss + Q."""
    J, Jp, Q, _ = _tables(drive, reduced)
    Im = reduced.inertia.tolist()
    motor, train = drive.motor, drive.train
    N0 = drive.gear_ratio
    if train.lossless:

        def lossless(i: int, K: float) -> tuple[float, float]:
            return N0 * float(motor.torque(N0 * math.sqrt(2 * K / J[i]))), 0.0

        return lossless

    def lossy(i: int, K: float) -> tuple[float, float]:
        u = 2 * K / J[i]
        Tm = float(motor.torque(N0 * math.sqrt(u)))
        return N0 * Tm, train.accelerate(Tm, Im[i], Q[i] - 0.5 * Jp[i] * u)[1]

    return lossy


def _revolution(
    rate: Callable[[int, float], tuple[float, float]],
    J: list[float],
    Q: list[float],
    Qp: list[float],
    K0: float,
    Wp: list[float] | None = None,
) -> tuple[list[float], list[float], list[float], tuple[float, float, float, float]]:
    """One revolution of dK/dφ = N_0 T_m − loss + Q by RK4, steps over two samples (the midpoint is a
    sample).

    ``Wp`` is the process forces' work over each step, J, integrated between the samples where the
    force has its kinks (:mod:`mechdyn.mechanism.process`): it replaces the rule's Simpson weights of
    the process share of Q, which depends on the angle alone. Returns K, N_0 T_m and the loss torque
    at the step nodes, and the crank work of the motor, of the train's losses, of Q and of the process
    forces.
    """
    n2 = len(J)
    H = 4 * math.pi / n2
    K = K0
    Ks, Ts, Ls = [], [], []
    wT = wL = wQ = wP = 0.0
    for i in range(0, n2, 2):
        j1, j2 = i + 1, (i + 2) % n2
        if K <= 0.0:
            raise StallError(f"the crank stops at {math.degrees(i * H / 2):.4g}° turned")
        T1, L1 = rate(i, K)
        k1 = T1 - L1 + Q[i]
        Ka = K + 0.5 * H * k1
        if Ka <= 0.0:
            raise StallError(f"the crank stops at {math.degrees(i * H / 2):.4g}° turned")
        T2, L2 = rate(j1, Ka)
        k2 = T2 - L2 + Q[j1]
        Kb = K + 0.5 * H * k2
        if Kb <= 0.0:
            raise StallError(f"the crank stops at {math.degrees(i * H / 2):.4g}° turned")
        T3, L3 = rate(j1, Kb)
        k3 = T3 - L3 + Q[j1]
        Kc = K + H * k3
        if Kc <= 0.0:
            raise StallError(f"the crank stops at {math.degrees(i * H / 2):.4g}° turned")
        T4, L4 = rate(j2, Kc)
        k4 = T4 - L4 + Q[j2]
        Ks.append(K)
        Ts.append(T1)
        Ls.append(L1)
        K = K + H / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        wT += H / 6 * (T1 + 2 * T2 + 2 * T3 + T4)
        wL += H / 6 * (L1 + 2 * L2 + 2 * L3 + L4)
        wQ += H / 6 * (Q[i] + 4 * Q[j1] + Q[j2])
        simpson = H / 6 * (Qp[i] + 4 * Qp[j1] + Qp[j2])
        if Wp is None:
            wP += simpson
        else:  # the process's work between the samples, exactly where its force kinks
            K += Wp[i // 2] - simpson
            wQ += Wp[i // 2] - simpson
            wP += Wp[i // 2]
    Ks.append(K)
    return Ks, Ts, Ls, (wT, wL, wQ, wP)


def _process_work(reduced: Any) -> list[float] | None:
    """The process forces' work on the crank over each Runge–Kutta step (two samples), J, integrated
    between the samples where the force kinks; None without process forces."""
    if not reduced.mechanism.process_forces:
        return None
    from mechdyn.mechanism.process import process_path

    path = process_path(reduced.kinematics)
    w = -path.interval_work()  # the work the forces do on the crank: −∫ T_p dφ
    assert path.angle[0] == reduced.angle[0]  # both in the order turned, from the same first sample
    return (w[0::2] + w[1::2]).tolist()


def operating_speed(drive: Any, reduced: Any) -> float:
    """The crank speed at which the motor's crank torque equals the mean torque the mechanism
    demands (−mean Q): the steady state's mean speed to first order, rad/s.

    Parameters
    ----------
    drive : Drive
        The drive.
    reduced : ReducedMechanism
        Its mechanism reduced to the crank.

    Raises
    ------
    StallError
        When the motor gives less than the mean demand at every speed up to its no-load speed.
    """
    from scipy.optimize import brentq

    demand = -float(np.mean(reduced.force))
    top = drive.motor.no_load_speed / drive.gear_ratio
    ws = np.linspace(top, 0.0, 401)
    excess = drive.crank_torque(ws) - demand
    above = np.nonzero(excess > 0)[0]
    if above.size == 0:
        raise StallError(
            f"the motor cannot carry the mechanism's mean torque of {demand:.6g} N*m at the crank: it gives "
            f"at most {float(drive.crank_torque(ws).max()):.6g} N*m there; choose a stronger motor or a "
            "higher gear ratio"
        )
    k = int(above[0])
    if k == 0:
        return float(top)
    return float(brentq(lambda w: float(drive.crank_torque(w)) - demand, ws[k], ws[k - 1], xtol=1e-14))


def steady_state(drive: Any, reduced: Any) -> SteadyState:
    """The periodic steady state of the driven mechanism (shooting on one revolution).

    Parameters
    ----------
    drive : Drive
        The motor, gearing and flywheel.
    reduced : ReducedMechanism
        The drive's mechanism reduced to its crank (:func:`~mechdyn.drive.inertia.reduce_to_crank`),
        at 2N crank angles: the steady state is given at the N even ones.

    Returns
    -------
    SteadyState

    Raises
    ------
    StallError
        When the motor cannot keep the crank turning.
    """
    J, Jp, Q, Qp = _tables(drive, reduced)
    if len(J) % 2:
        raise ModelError("the reduced mechanism needs an even number of crank angles", element="drive")

    torque = _rate(drive, reduced)
    Wp = _process_work(reduced)
    w0 = operating_speed(drive, reduced)
    Ka = 0.5 * J[0] * w0 * w0
    ga = _revolution(torque, J, Q, Qp, Ka, Wp)[0][-1] - Ka
    shots = 1
    Kb = Ka + ga  # one revolution on: the natural iteration
    while True:
        try:
            run = _revolution(torque, J, Q, Qp, Kb, Wp)
            break
        except StallError:
            if shots > MAX_SHOTS:
                raise
            Kb = 0.5 * (Kb + Ka) if Kb < Ka else 2.0 * Kb
            shots += 1
    shots += 1
    gb = run[0][-1] - Kb
    while abs(gb) > SHOOTING_RTOL * Kb:
        if shots > MAX_SHOTS or gb == ga:
            raise StallError(
                f"no periodic steady state found after {shots} revolutions (K(2π) − K(0) = {gb:.3g} J); "
                "the motor may not hold the machine's speed: a larger flywheel or a stronger motor"
            )
        Kc = Kb - gb * (Kb - Ka) / (gb - ga)
        if Kc <= 0.0:
            Kc = 0.5 * Kb
        try:
            trial = _revolution(torque, J, Q, Qp, Kc, Wp)
        except StallError:
            Kc = 0.5 * (Kc + max(Ka, Kb))
            trial = _revolution(torque, J, Q, Qp, Kc, Wp)
        shots += 1
        Ka, ga, Kb, run = Kb, gb, Kc, trial
        gb = run[0][-1] - Kb
    Ks, Ts, Ls, (wT, wL, wQ, wP) = run
    K = np.array(Ks[:-1])
    Jn = np.array(J[::2])
    w = np.sqrt(2 * K / Jn)
    T, L = np.array(Ts), np.array(Ls)
    acc = (T - L + np.array(Q[::2]) - 0.5 * np.array(Jp[::2]) * w * w) / Jn
    h = 4 * math.pi / len(J)
    inv = 1 / np.append(w, w[0])
    dt = 0.5 * h * (inv[1:] + inv[:-1])
    t = np.concatenate([[0.0], np.cumsum(dt)[:-1]])
    dK = Ks[-1] - Ks[0]
    return SteadyState(
        turned=reduced.turned[::2],
        speed=w,
        acceleration=acc,
        time=t,
        period=float(np.sum(dt)),
        crank_torque=T,
        loss_torque=L,
        motor_work=wT,
        loss_work=wL,
        applied_work=wQ,
        process_work=wP,
        energy_change=dK,
        energy_residual=wT - wL + wQ - dK,
        shots=shots,
    )


def _periodic(values: np.ndarray, turned_step: float) -> Callable[[float], float]:
    """Linear interpolation of samples over one revolution, read at any turned angle."""
    v = np.asarray(values, dtype=float).tolist()
    n = len(v)

    def at(phi: float) -> float:
        x = (phi % (2 * math.pi)) / turned_step
        i = int(x)
        f = x - i
        i %= n
        return v[i] + f * (v[(i + 1) % n] - v[i])

    return at


def _hermite(values: np.ndarray, slopes: np.ndarray, turned_step: float) -> Callable[[float], float]:
    """Cubic Hermite interpolation of I(φ) with its exact slopes I′(φ), periodic."""
    v = np.asarray(values, dtype=float).tolist()
    d = np.asarray(slopes, dtype=float).tolist()
    n, h = len(v), turned_step

    def at(phi: float) -> float:
        x = (phi % (2 * math.pi)) / h
        i = int(x)
        s = x - i
        i %= n
        j = (i + 1) % n
        s2, s3 = s * s, s * s * s
        return (
            (2 * s3 - 3 * s2 + 1) * v[i]
            + (s3 - 2 * s2 + s) * h * d[i]
            + (-2 * s3 + 3 * s2) * v[j]
            + (s3 - s2) * h * d[j]
        )

    return at


def start_up(
    drive: Any,
    reduced: Any,
    steady: SteadyState,
    *,
    method: str = "LSODA",
    tolerance: float = 1e-3,
    max_revolutions: int = 400,
    rtol: float = 1e-9,
) -> StartUp:
    """The run-up from rest in time, until the speed settles on the steady state.

    The press runs up idle (no process forces) until the crank passes its starting angle at the steady
    state's mean speed or faster; from there every stroke forms (the clutch, or the operator, engages
    the work at speed). The motor starts at the crank angle φ = 0 from rest.

    Parameters
    ----------
    drive : Drive
        The motor, gearing and flywheel.
    reduced : ReducedMechanism
        The mechanism reduced to its crank.
    steady : SteadyState
        The steady state it should reach (from :func:`steady_state`).
    method : str
        A ``scipy.integrate.solve_ivp`` method (``"LSODA"``, ``"Radau"``, ``"BDF"`` for stiff
        problems; ``"DOP853"``, ``"RK45"``).
    tolerance : float
        Relative speed difference at a crank pass below which the machine has settled,
        dimensionless.
    max_revolutions : int
        Revolutions to integrate at most, a count.
    rtol : float
        Relative tolerance of the integrator, dimensionless.

    Raises
    ------
    StallError
        When the crank stops, or does not settle within ``max_revolutions``.
    """
    from scipy.integrate import solve_ivp

    h = 2 * math.pi / len(reduced.turned)
    J_at = _hermite(reduced.inertia + drive.added_inertia, reduced.inertia_slope, h)
    Jp_at = _periodic(reduced.inertia_slope, h)
    Q_at = _periodic(reduced.force, h)
    Qp_at = _periodic(reduced.process_force, h)
    ws_at = _periodic(steady.speed, 2 * math.pi / len(steady.speed))
    target = steady.mean_speed
    train, N0, Ja = drive.train, drive.gear_ratio, drive.added_inertia
    lossless = train.lossless

    def rhs(engaged: bool) -> Callable[[float, np.ndarray], list[float]]:
        def f(t: float, y: np.ndarray) -> list[float]:
            phi, w = float(y[0]), float(y[1])
            Q = Q_at(phi) if engaged else Q_at(phi) - Qp_at(phi)
            rest = Q - 0.5 * Jp_at(phi) * w * w
            Tm = float(drive.motor.torque(N0 * w))
            if lossless:
                return [w, (N0 * Tm + rest) / J_at(phi)]
            return [w, train.accelerate(Tm, J_at(phi) - Ja, rest)[0]]

        return f

    times, phis, speeds = [np.zeros(1)], [np.zeros(1)], [np.zeros(1)]
    t0, y0 = 0.0, np.array([0.0, 0.0])
    engaged, engaged_at, settled_at = False, math.nan, math.nan
    typical = max(steady.period, 1e-6)
    for rev in range(1, max_revolutions + 1):

        def passed(t: float, y: np.ndarray, rev: int = rev) -> float:
            return float(y[0] - 2 * math.pi * rev)

        def stopped(t: float, y: np.ndarray) -> float:
            return float(y[1]) + STOP_FRACTION * target

        passed.terminal = True  # type: ignore[attr-defined]
        stopped.terminal = True  # type: ignore[attr-defined]
        stopped.direction = -1  # type: ignore[attr-defined]
        sol = solve_ivp(
            rhs(engaged),
            (t0, t0 + LONGEST_REVOLUTION * typical * rev),
            y0,
            method=method,
            events=(passed, stopped),
            rtol=rtol,
            atol=[1e-12, 1e-12 * target],
            max_step=typical / 50,
        )
        if not sol.success:
            raise StallError(f"the start-up integration failed: {sol.message}")
        if sol.t_events[1].size:
            raise StallError(
                f"the crank stops during start-up at t = {sol.t_events[1][0]:.4g} s: the motor cannot turn "
                "the mechanism from rest (a stronger motor, or a higher gear ratio)"
            )
        if not sol.t_events[0].size:
            raise StallError(f"the crank does not complete revolution {rev} during start-up")
        times.append(sol.t[1:])
        phis.append(sol.y[0, 1:])
        speeds.append(sol.y[1, 1:])
        t0 = float(sol.t_events[0][0])
        y0 = sol.y_events[0][0].copy()
        w_pass = float(y0[1])
        # the work starts once the crank passes at the steady speed (within the tolerance: a run-up
        # approaches it from below, and the steady speed at this pass may lie below its mean)
        if not engaged and w_pass >= min(target, ws_at(0.0)) * (1 - tolerance):
            engaged, engaged_at = True, t0
            continue
        if engaged:
            off = abs(w_pass - ws_at(0.0)) / target
            if off < tolerance:
                if math.isnan(settled_at):
                    settled_at = t0
                # the last revolution must follow the steady state all round
                last = sol.t >= sol.t[0]
                dev = max(abs(w - ws_at(p)) for p, w in zip(sol.y[0, last], sol.y[1, last], strict=True))
                if dev / target < tolerance:
                    t = np.concatenate(times)
                    return StartUp(
                        t,
                        np.concatenate(phis),
                        np.concatenate(speeds),
                        engaged_at,
                        settled_at,
                        dev / target,
                        rev,
                        method,
                    )
            else:
                settled_at = math.nan
    raise StallError(f"the start-up does not settle on the steady state within {max_revolutions} revolutions")


def size_flywheel(drive: Any, reduced: Any, fluctuation: float, *, rtol: float = 1e-8) -> float:
    """The flywheel inertia, on the drive's flywheel shaft, that gives the coefficient of speed
    fluctuation ``fluctuation`` in the steady state (a root of δ(J) − δ_target by Brent's method).

    Parameters
    ----------
    drive : Drive
        The drive; its own flywheel inertia is replaced.
    reduced : ReducedMechanism
        Its mechanism reduced to the crank.
    fluctuation : float
        δ_target = (ω_max − ω_min)/ω_mean, dimensionless, in (0, 1).
    rtol : float
        Relative tolerance on the inertia, dimensionless.

    Returns
    -------
    float
        kg·m²; 0 when the machine without a flywheel already fluctuates less.

    Raises
    ------
    StallError
        When no flywheel brings the fluctuation down to the target.
    """
    from scipy.optimize import brentq

    if not 0.0 < fluctuation < 1.0:
        raise ModelError(f"{fluctuation!r} must lie in (0, 1)", element="flywheel", field="fluctuation")

    def delta(J: float) -> float:
        try:
            return steady_state(drive.with_flywheel(J), reduced).fluctuation
        except StallError:
            return math.inf

    if delta(0.0) <= fluctuation:
        return 0.0
    # the energy estimate J ≈ ΔE / (δ ω²) on the flywheel's shaft, for the bracket
    n = drive.flywheel_speed_ratio
    w = operating_speed(drive, reduced) * n
    swing = np.cumsum(reduced.constant_speed_torque(0.0) - np.mean(reduced.constant_speed_torque(0.0)))
    energy = float(np.ptp(swing)) * reduced.step + float(reduced.inertia.max()) * (w / n) ** 2
    hi = max(energy / (fluctuation * w * w), 1e-6)
    for _ in range(60):
        if delta(hi) < fluctuation:
            break
        hi *= 4.0
    else:
        raise StallError(f"no flywheel up to {hi:.4g} kg*m^2 brings the fluctuation below {fluctuation:g}")
    lo = 0.0
    return float(brentq(lambda J: delta(J) - fluctuation, lo, hi, rtol=rtol, xtol=1e-12 * hi))
