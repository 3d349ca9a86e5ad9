"""The periodic steady state of a geared drivetrain at one constant speed.

The reference disk turns at Ω (held at exactly Ω, a kinematic input; or free, a constant torque or a
motor on its torque–speed curve balancing the load: ``drive``) and the loads draw constant torques.
About the nominal rigid rotation q = Ω t r the teeth-in-contact vibration x obeys the linear
time-periodic system of :mod:`.periodic`,

    M ẍ + C ẋ + K(t) x = F₀ + Σ_j g_j (k_j(τ_j) e_j(τ_j) + c_j ė_j),  τ_j = z_j θ_a,nominal / (2π),

excited by the static transmission errors e_j and, through the varying stiffness, by the mean load.
Its periodic response at one speed (:class:`_Solver`, which :mod:`.sweep` calls speed after speed)
comes from

* **harmonic balance** (:mod:`.harmonic_balance`), the fast path: one linear solve in the harmonics;
* **shooting** (:mod:`.shooting`): the fixed point of the period map of the linear system, or with
  backlash Newton's method on the event-located nonlinear flow (:mod:`._nonsmooth`), started from the
  last orbit or a run of the flow, and past a flip the period-doubled orbit.

Along the orbit the mesh forces follow the contact law (:func:`._contact.mesh_force`); the dynamic
factor K_v = max f_j / f_j,static compares with ISO 6336-1's K_v (:mod:`.sweep`). Several meshes
share the common period of their mesh frequencies (:func:`.periodic.period_plan`); where it is
longer than 64 mesh periods the dominant mesh's period is used and the others held at their mean
stiffness, with a note.

The sweep over speed was defined here too: :func:`.sweep.speed_sweep` and
:class:`.sweep_result.SpeedSweepResult` stay importable from here.
"""

from __future__ import annotations

import importlib
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from mechdyn.checks import check_count
from mechdyn.errors import ModelError
from mechdyn.gear_dynamics._contact import BY_SIGN, NO_BACKLASH, announce, mesh_forces
from mechdyn.gear_dynamics._harmonics import estimated_error, harmonics_for, truncation_warning
from mechdyn.gear_dynamics._nonsmooth import FlowError
from mechdyn.gear_dynamics._stability import UNSTABLE_MARGIN, _spectral
from mechdyn.gear_dynamics.harmonic_balance import _balance, _hb_solve, _series
from mechdyn.gear_dynamics.periodic import (
    Boundary,
    LinearPeriodic,
    PeriodPlan,
    _check_speed,
    interpolate,
    interpolated_slope,
    linear_periodic,
    period_plan,
)
from mechdyn.gear_dynamics.propagators import _monodromy
from mechdyn.gear_dynamics.shooting import (
    _period_doubled,
    _settle,
    _shoot_linear,
    _shoot_nonlinear,
    _warm_start,
)
from mechdyn.results import Result

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["SteadyState", "steady_state"]

Method = Literal["auto", "harmonic_balance", "shooting"]
_METHODS = ("auto", "harmonic_balance", "shooting")
Drive = Literal["motor", "torque", "speed"]
_DRIVES = ("motor", "torque", "speed")
#: Runs of :func:`.shooting._settle_periods` periods, each followed by Newton, before a speed is given up.
_SETTLE_ROUNDS = 4


def steady_state(
    system: Any,
    speed: float,
    *,
    reference: str,
    load: Mapping[str, Any] | None = None,
    method: Method = "auto",
    harmonics: int | Literal["auto"] = "auto",
    integrator: Literal["magnus", "ivp"] = "magnus",
    substeps: int = 4,
    points: int | None = None,
    drive: Drive | None = None,
    motor: Any = None,
) -> SteadyState:
    """The periodic steady state of a drivetrain at one constant speed.

    Parameters
    ----------
    system : GearSystem
        The time-varying system of a drivetrain.
    speed : float
        Speed Ω of the reference disk, rad/s, positive.
    reference : str
        The disk whose speed is Ω (a motor disk).
    load : mapping of str to float, optional
        Torque drawn at each named disk, N·m (or quantities), resisting its rotation.
    method : {"auto", "harmonic_balance", "shooting"}
        ``"auto"``: harmonic balance, or shooting with Newton where a mesh has backlash.
    harmonics : int or "auto"
        Harmonics of each mesh frequency kept by harmonic balance, a count from 1 to 2000, or
        ``"auto"``: enough to reach twice the highest natural frequency
        (:func:`mechdyn.gear_dynamics._harmonics.harmonics_for`), checked by doubling them
        (:attr:`SteadyState.harmonics_error`).
    integrator : {"magnus", "ivp"}
        The propagator of linear shooting (:func:`mechdyn.gear_dynamics.propagators.monodromy`).
    substeps : int
        Magnus segments per profile sample interval, a count from 1 to 1000.
    points : int, optional
        Time samples per period of the harmonic-balance response, a count from 8 (default: 4 per
        profile sample interval, at least 256 and 2H + 2). Shooting samples at its segment ends.
    drive : {"motor", "torque", "speed"}, optional
        How the train is driven. ``"motor"``: no disk held, ``motor`` drives, its torque following its
        torque–speed curve about the torque that holds the load (its slope damps the rigid rotation,
        :mod:`mechdyn.gear_dynamics._operating`): what :func:`simulate` integrates; ``"torque"``: no disk
        held, a constant torque at the reference disk balances the load; ``"speed"``: the reference
        disk held at exactly Ω (a kinematic input, which moves the train's modes: a held motor rotor
        becomes a node). Default: ``"motor"`` where ``motor`` is given, else ``"torque"``.
    motor : MotorTorque, optional
        The motor (:class:`mechdyn.gear_dynamics.loads.MotorTorque`) of ``drive="motor"``.

    Returns
    -------
    SteadyState

    Notes
    -----
    Harmonic balance of a linear periodic system (Nayfeh & Mook, *Nonlinear Oscillations*, 1979,
    §5.4); shooting (Nayfeh & Balachandran, *Applied Nonlinear Dynamics*, 1995, §7.1).
    """
    _check_method(method)
    _check_integrator(integrator)
    given = _harmonics_given(harmonics)
    substeps = check_count("gear dynamics", "substeps", substeps, low=1, high=1000, what="substeps")
    speed = _check_speed("speed", speed)
    lin = _model(system, reference, load, drive, motor)
    chosen = _choose(lin, method)
    plan = period_plan(lin)
    if points is not None:
        points = check_count("gear dynamics", "points", points, low=8, high=10**7, what="time samples")
    H = given if given is not None else harmonics_for(lin, plan, speed)
    solver = _Solver(lin, plan, chosen, H, substeps, integrator, points)
    t, x, v, ok = solver.solve(speed)
    error = _truncation_error(lin, plan, H, [speed]) if chosen == "harmonic_balance" else float("nan")
    force, delta = _mesh_forces(lin, plan, speed, t, x, v)
    T = plan.period(speed)
    return SteadyState(
        speed=speed,
        period=T,
        time=t * T,
        mesh_names=lin.names,
        mesh_force=force,
        deflection=delta,
        static_force=_static_forces(lin, speed),
        coordinates=x @ lin.basis.T,
        method=(
            _harmonics_words(H, given is None, error)
            if chosen == "harmonic_balance"
            else f"shooting ({integrator})"
        ),
        converged=ok,
        notes=(plan.note,) if plan.note else (),
        drive=lin.drive,
        harmonics=H if chosen == "harmonic_balance" else 0,
        harmonics_error=error,
        periods=solver.multiple,
    )


class _Solver:
    """One speed's periodic solution by the chosen method, sharing the speed-independent parts."""

    def __init__(
        self,
        lin: LinearPeriodic,
        plan: PeriodPlan,
        method: str,
        harmonics: int,
        substeps: int,
        integrator: str,
        points: int | None = None,
        stability: bool = False,
    ) -> None:
        self.lin, self.plan, self.method, self.points = lin, plan, method, points
        self.stability = stability
        self.rho = float("nan")
        self.closure = float("nan")  # the last orbit's closure after one period (backlash)
        self.multiple = 1  # periods T of the last orbit (2: period-doubled)
        self.harmonics, self.substeps, self.integrator = harmonics, substeps, integrator
        self.nonlinear = any(b is not None for b in lin.backlash)
        self.bal = (
            _balance(lin, plan, harmonics) if (method == "harmonic_balance" or self.nonlinear) else None
        )
        self.start: np.ndarray | None = None  # continuation: the last periodic state

    def solve(
        self, speed: float, *, start: np.ndarray | None = None, settle: bool = True
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, bool]:
        """Times (fractions of T), x, ẋ and convergence; :attr:`rho` the spectral radius where known.

        With backlash, Newton starts from ``start`` (default: the last periodic state, or a run from the
        static deflection); with ``settle``, where it fails or lands on an unstable orbit, it starts
        again from a run of :func:`.shooting._settle_periods` periods from that start at this speed
        (the orbit a slow sweep reaches: after a jump, the other branch), up to four runs in a row."""
        lin, plan = self.lin.at_speed(speed), self.plan
        self.rho = float("nan")
        self.closure = float("nan")
        self.multiple = 1
        if self.method == "harmonic_balance":
            assert self.bal is not None
            X = _hb_solve(lin, plan, self.bal, speed)
            N = _grid(lin, plan, self.bal.H) if self.points is None else self.points
            x, v = _series(X, 2 * np.pi * plan.fundamental * speed, N)
            if self.stability:
                self.rho = _spectral(_monodromy(lin, plan, speed, "magnus", self.substeps), lin)[1]
            return np.arange(N) / N, x, v, True
        if not self.nonlinear:
            t, x, v, Phi = _shoot_linear(lin, plan, speed, self.integrator, self.substeps)
            self.rho = _spectral(Phi, lin)[1]
            return t, x, v, True
        assert self.bal is not None
        if start is None:
            if self.start is None:  # a run from the static deflection starts Newton
                self.start = _warm_start(lin, plan, speed)
            start = self.start
        N = _grid(lin, plan, self.bal.H)
        t, x, v, ok, Phi, closure = _shoot_nonlinear(lin, plan, speed, start, N)
        rho = _spectral(Phi, lin)[1] if ok else float("inf")
        settled = start
        for _round in range(_SETTLE_ROUNDS if settle else 0):
            if rho <= 1.0 + UNSTABLE_MARGIN:
                break
            try:
                settled = _settle(lin, plan, speed, settled)
            except FlowError:
                break
            again = _shoot_nonlinear(lin, plan, speed, settled, N)
            rho_again = _spectral(again[4], lin)[1] if again[3] else float("inf")
            if again[3] and rho_again < rho:
                t, x, v, ok, Phi, closure = again
                rho = rho_again
        if settle and (not ok or rho > 1.0 + UNSTABLE_MARGIN):
            orbit = np.concatenate([x[0], v[0]]) if ok else settled
            doubled = _period_doubled(lin, plan, speed, Phi if ok else None, orbit, N)
            if doubled is not None:
                t, x, v, ok, Phi, closure = doubled
                rho = _spectral(Phi, lin)[1]
                self.multiple = 2
        self.closure = closure
        if ok:
            self.start = np.concatenate([x[0], v[0]])
            self.rho = rho
        return t, x, v, ok


# -- the orbit's mesh forces and the result ------------------------------------------------------------
def _mesh_forces(
    lin: LinearPeriodic, plan: PeriodPlan, speed: float, t_over_T: np.ndarray, x: np.ndarray, v: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """(N, J) mesh forces (N) and deflections δ (m) along the lines of action: the contact law
    (:func:`._contact.mesh_force`) in the region each relative displacement lies in."""
    f0 = plan.fundamental * speed
    J = len(lin.names)
    N = t_over_T.size
    force = np.empty((N, J))
    delta = x @ lin.G.T
    rate = v @ lin.G.T
    by_sign = np.full(N, BY_SIGN, dtype=np.int64)
    announce()
    for j in range(J):
        o = int(plan.orders[j])
        tau = plan.signs[j] * o * t_over_T
        k: Any
        e: Any
        e_dot: Any
        if o:
            k = lin.mean_stiffness[j] * interpolate(lin.profiles[j], tau)
            e = interpolate(lin.errors[j], tau)
            e_dot = interpolated_slope(lin.errors[j], tau) * plan.signs[j] * o * f0
        else:
            k, e, e_dot = lin.mean_stiffness[j], 0.0, 0.0
        b = lin.backlash[j]
        force[:, j] = mesh_forces(
            np.full(N, k, dtype=float),
            np.full(N, lin.mesh_damping[j], dtype=float),
            np.ascontiguousarray(delta[:, j] - e, dtype=float),
            np.ascontiguousarray(rate[:, j] - e_dot, dtype=float),
            np.full(N, NO_BACKLASH if b is None else b, dtype=float),
            by_sign,
        )[0]
    return force, delta


def _grid(lin: LinearPeriodic, plan: PeriodPlan, H: int) -> int:
    """Time samples per period: resolve the profiles (4 per sample interval) and the harmonics."""
    need = [4 * p.size * int(o) for p, o in zip(lin.profiles, plan.orders, strict=True) if o]
    return int(max([2 * H + 2, 256, *need]))


def _static_forces(lin: LinearPeriodic, speed: float) -> np.ndarray:
    return lin.mean_stiffness * (lin.G @ lin.static(lin.force(speed)))


def _dynamic_factor(force: np.ndarray, static: np.ndarray) -> np.ndarray:
    """max of the force in the sense of the static one over the static force (NaN without load)."""
    sense = np.sign(static)
    loaded = np.abs(static) > 1e-9 * np.abs(force).max(axis=0)
    with np.errstate(invalid="ignore", divide="ignore"):
        kv = np.max(force * sense, axis=0) / np.abs(static)
    return np.where(loaded, kv, np.nan)


@dataclass(frozen=True, repr=False)
class SteadyState(Result):
    """The periodic steady state of a drivetrain at one speed.

    Attributes
    ----------
    speed : float
        Reference speed Ω, rad/s.
    period : float
        The common mesh period T, s.
    time : ndarray
        (N,) times over one period, s.
    mesh_names : tuple of str
    mesh_force : ndarray
        (N, J) dynamic mesh forces along the lines of action, N.
    deflection : ndarray
        (N, J) mesh deflections δ = g · x (the dynamic transmission error), m.
    static_force : ndarray
        (J,) mesh forces of the mean load at mean stiffness, N.
    coordinates : ndarray
        (N, n) vibration of the system's coordinates about the nominal rotation, rad.
    method : str
    converged : bool
        False where Newton's method (backlash) did not reach the periodic solution.
    notes : tuple of str
    drive : str
        How the train was driven, in words.
    harmonics : int
        Harmonics of each mesh frequency kept by harmonic balance (0 for shooting), count.
    harmonics_error : float
        The estimated largest relative error of K_v from the truncation (the change when the
        harmonics are doubled, :func:`mechdyn.gear_dynamics._harmonics.estimated_error`),
        dimensionless; NaN for shooting.
    periods : int
        Mesh periods T the orbit spans: 1, or 2 for a period-doubled orbit (backlash, past a flip);
        :attr:`time` then covers both.
    """

    speed: float
    period: float
    time: np.ndarray
    mesh_names: tuple[str, ...]
    mesh_force: np.ndarray
    deflection: np.ndarray
    static_force: np.ndarray
    coordinates: np.ndarray
    method: str
    converged: bool = True
    notes: tuple[str, ...] = field(default=())
    drive: str = ""
    harmonics: int = 0
    harmonics_error: float = float("nan")
    periods: int = 1

    @property
    def dynamic_factor(self) -> np.ndarray:
        """(J,) K_v = max dynamic mesh force / static mesh force, dimensionless (NaN without load)."""
        return _dynamic_factor(self.mesh_force, self.static_force)

    @property
    def dte_amplitude(self) -> np.ndarray:
        """(J,) half the peak-to-peak dynamic transmission error, m."""
        return 0.5 * np.ptp(self.deflection, axis=0)

    def summary(self) -> dict[str, Any]:
        """Speed (rad/s), period (s) and, per mesh, force extremes and RMS (N), K_v, DTE amplitude (m)."""
        f = self.mesh_force
        return {
            "speed_rad_s": self.speed,
            "period_s": self.period,
            "method": self.method,
            "meshes": {
                n: {
                    "force_max_N": float(f[:, j].max()),
                    "force_min_N": float(f[:, j].min()),
                    "force_rms_N": float(np.sqrt(np.mean(f[:, j] ** 2))),
                    "static_force_N": float(self.static_force[j]),
                    "dynamic_factor_ratio": float(self.dynamic_factor[j]),
                    "dte_amplitude_m": float(self.dte_amplitude[j]),
                }
                for j, n in enumerate(self.mesh_names)
            },
        }

    def to_frame(self) -> pd.DataFrame:
        """One row per time step: time (s), each mesh's force (N) and deflection (m)."""
        import pandas as pd

        cols: dict[str, Any] = {"time_s": self.time}
        for j, n in enumerate(self.mesh_names):
            cols[f"{n}_force_N"] = self.mesh_force[:, j]
            cols[f"{n}_dte_m"] = self.deflection[:, j]
        return pd.DataFrame(cols)

    @property
    def warnings(self) -> tuple[str, ...]:
        """Notes on the period and on convergence (Newton's, and the harmonics')."""
        return (
            self.notes
            + (() if self.converged else ("Newton's method did not converge",))
            + truncation_warning(self.harmonics, self.harmonics_error)
        )


# -- the arguments --------------------------------------------------------------------------------------
def _check_method(method: str) -> None:
    if method not in _METHODS:
        raise ModelError(
            f"method {method!r}: give 'auto', 'harmonic_balance' or 'shooting'",
            element="gear dynamics",
            field="method",
        )


def _check_integrator(integrator: str) -> None:
    if integrator not in ("magnus", "ivp"):
        raise ModelError(
            f"integrator {integrator!r}: give 'magnus' or 'ivp'", element="gear dynamics", field="integrator"
        )


def _choose(lin: LinearPeriodic, method: str) -> str:
    nonlinear = any(b is not None for b in lin.backlash)
    if method == "auto":
        return "shooting" if nonlinear else "harmonic_balance"
    if method == "harmonic_balance" and nonlinear:
        raise ModelError(
            "harmonic balance here is linear (teeth in contact) and a mesh has backlash; use "
            "method='shooting' (Newton on the nonlinear flow) or remove the backlash",
            element="gear dynamics",
            field="method",
        )
    return method


def _model(
    system: Any, reference: str, load: Mapping[str, Any] | None, drive: str | None, motor: Any
) -> LinearPeriodic:
    """The linear periodic model for a drive: ``"motor"`` (the motor free, on its curve),
    ``"torque"`` (free, a constant torque at the reference disk) or ``"speed"`` (the reference disk
    held); None: the motor where one is given, else the constant torque."""
    if drive is None:
        drive = "motor" if motor is not None else "torque"
    if drive not in _DRIVES:
        raise ModelError(
            f"drive {drive!r}: give 'motor' (the motor free on its torque-speed curve), 'torque' (free, a "
            "constant torque at the reference disk) or 'speed' (the reference disk held at each speed)",
            element="gear dynamics",
            field="drive",
        )
    if drive == "motor" and motor is None:
        raise ModelError(
            "drive 'motor' needs the motor: give motor=MotorTorque(...) (or a [motor] table in the file), "
            "or drive='torque'",
            element="gear dynamics",
            field="motor",
        )
    boundary: Boundary = {"motor": "motor", "torque": "free", "speed": "prescribed"}[drive]  # type: ignore[assignment]
    return linear_periodic(
        system, reference=reference, boundary=boundary, load=load, motor=motor if drive == "motor" else None
    )


def _harmonics_given(harmonics: Any) -> int | None:
    """The count given, checked; None for ``"auto"`` (or None): chosen by
    :func:`._harmonics.harmonics_for`."""
    if harmonics is None or (isinstance(harmonics, str) and harmonics == "auto"):
        return None
    return check_count("gear dynamics", "harmonics", harmonics, low=1, high=2000, what="harmonics")


# -- the truncation of harmonic balance ------------------------------------------------------------------
def _truncation_error(lin: LinearPeriodic, plan: PeriodPlan, H: int, speeds: list[float]) -> float:
    """The estimated largest relative error of K_v with H harmonics at ``speeds`` (rad/s), from the
    same with 2H (:func:`._harmonics.estimated_error`), dimensionless."""
    kv = []
    for h in (H, 2 * H):
        solver = _Solver(lin, plan, "harmonic_balance", h, 4, "magnus")
        row = []
        for speed in speeds:
            t, x, v, _ = solver.solve(speed)
            force, _ = _mesh_forces(lin, plan, speed, t, x, v)
            row.append(_dynamic_factor(force, _static_forces(lin, speed)))
        kv.append(np.array(row))
    return estimated_error(kv[0], kv[1])


def _harmonics_words(H: int, auto: bool, error: float) -> str:
    how = "chosen to reach twice the highest natural frequency at the lowest speed" if auto else "as given"
    size = f"{100 * error:.2g} %" if error >= 1e-4 else "0.01 %"
    est = (
        f"; K_v within an estimated {size} of the converged answer (against {2 * H})"
        if np.isfinite(error)
        else ""
    )
    return f"harmonic balance ({H} harmonics per mesh, {how}{est})"


# -- names that moved ---------------------------------------------------------------------------------
#: The sweep over speed was defined in this module; its names stay importable from here (PEP 562,
#: lazily: :mod:`.sweep` itself imports this module).
_MOVED = {
    "speed_sweep": "sweep",
    "Direction": "sweep",
    "EDGE_RTOL": "sweep",
    "SpeedSweepResult": "sweep_result",
    "PEAK_PROMINENCE": "sweep_result",
    "HYSTERESIS_RTOL": "sweep_result",
}


def __getattr__(name: str) -> Any:
    if name in _MOVED:
        return getattr(importlib.import_module(f"mechdyn.gear_dynamics.{_MOVED[name]}"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
