"""The drive analysis and its result: steady state, start-up, flywheel, motor duty and the loads at the
real, fluctuating speed."""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass, replace
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np

from mechdyn.drive.forward import StartUp, SteadyState, size_flywheel, start_up, steady_state
from mechdyn.drive.inertia import ReducedMechanism, reduce_to_crank
from mechdyn.results import Result, Table, summary_table
from mechdyn.units import convert

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["DriveResult", "drive_analysis", "mechanism_at_speed"]


def mechanism_at_speed(reduced: ReducedMechanism, steady: SteadyState) -> Any:
    """The mechanism with its driver following the steady state's speed profile θ̇(θ).

    The profile is a periodic cubic spline through the steady state's speeds; the driver derives the
    acceleration from it (:class:`mechdyn.mechanism.Driver`). A support analysis of this mechanism
    sees the shaking force at the real speed.

    Parameters
    ----------
    reduced : ReducedMechanism
        The mechanism reduced to its crank.
    steady : SteadyState
        Its steady state (crank speeds, rad/s).
    """
    from scipy.interpolate import CubicSpline

    m = reduced.mechanism
    s = reduced.direction
    a0 = float(reduced.angle[0])
    phi = np.append(steady.turned, 2 * math.pi)
    spline = CubicSpline(phi, np.append(steady.speed, steady.speed[0]), bc_type="periodic")

    def speed(angle: np.ndarray) -> np.ndarray:
        return s * spline(np.mod(s * (np.asarray(angle) - a0), 2 * math.pi))

    driver = replace(m.driver, speed=s * steady.mean_speed, profile=speed)
    return replace(m, driver=driver)


def _loads_at_speed(reduced: ReducedMechanism, steady: SteadyState, mechanism: Any) -> Any:
    """Inverse dynamics at the steady state's own speeds and accelerations, sample for sample.

    The kinematics follow by the chain rule, q̇ = q′ φ̇ and q̈ = q″ φ̇² + q′ φ̈, from the constant-speed
    kinematics (exact at every sample: no spline of the speed).
    """
    from mechdyn.mechanism.dynamics import inverse_dynamics

    k = reduced.kinematics
    d1, d2 = reduced.coefficients
    w, a = steady.speed[:, None], steady.acceleration[:, None]
    rows = slice(None, None, 2)
    order = np.argsort(k.angle[rows])  # tables run in the angle from the datum
    kin = replace(
        k,
        mechanism=mechanism,
        crank_angle=k.crank_angle[rows][order],
        angle=k.angle[rows][order],
        time=steady.time[order],
        q=k.q[rows][order],
        qd=(d1[rows] * w)[order],
        qdd=(d2[rows] * w * w + d1[rows] * a)[order],
        dyads=None,
    )
    return inverse_dynamics(kin), order


@dataclass(frozen=True, repr=False)
class DriveResult(Result):
    """The driven mechanism in its periodic steady state, with its start-up and flywheel sizing.

    Attributes
    ----------
    drive : Drive
        Motor, gearing, flywheel and mechanism.
    reduced : ReducedMechanism
        The mechanism reduced to its crank.
    steady : SteadyState
        One revolution of the steady state.
    startup : StartUp or None
        The run-up from rest, when asked for.
    loads : DynamicsResult
        Inverse dynamics at the real (fluctuating) speed, rows in the angle from the datum.
    constant : DynamicsResult
        Inverse dynamics at the constant mean speed, for comparison.
    order : ndarray
        (N,) the steady state's sample (in the turned order) of each row of ``loads``, an index.
    target_fluctuation : float or None
        δ the flywheel was sized for, dimensionless.
    sized_flywheel : float or None
        The flywheel inertia that gives it, kg·m².
    """

    drive: Any
    reduced: ReducedMechanism
    steady: SteadyState
    startup: StartUp | None
    loads: Any
    constant: Any
    order: np.ndarray
    target_fluctuation: float | None = None
    sized_flywheel: float | None = None

    # -- per-sample quantities, in the turned order of the steady state ----------------------------
    @property
    def motor_speed(self) -> np.ndarray:
        """(N,) motor shaft speed, rad/s."""
        return self.drive.gear_ratio * self.steady.speed

    @property
    def motor_torque(self) -> np.ndarray:
        """(N,) motor shaft torque, N·m."""
        return np.asarray(self.drive.motor.torque(self.motor_speed), dtype=float)

    @property
    def motor_power(self) -> np.ndarray:
        """(N,) motor shaft power, W."""
        return self.motor_torque * self.motor_speed

    @property
    def mechanism_torque(self) -> np.ndarray:
        """(N,) torque the drive puts into the mechanism's crank, N·m in the direction of rotation:
        the motor's at the crank less the train's losses and the flywheel's, rotor's and train's
        inertia torque, n T_m − T_loss − J_a φ̈."""
        st = self.steady
        return st.crank_torque - st.loss_torque - self.drive.added_inertia * st.acceleration

    @property
    def loads_torque(self) -> np.ndarray:
        """(N,) the same torque from the inverse dynamics at the real speed, in the turned order, N·m."""
        T = np.empty(len(self.order))
        T[self.order] = self.loads.driving_torque * self.reduced.direction
        return T

    def _time_rms(self, values: np.ndarray) -> float:
        """RMS over time (the thermal duty), trapezoidal in time over the revolution."""
        v2 = np.append(values, values[0]) ** 2
        t = np.append(self.steady.time, self.steady.period)
        return float(math.sqrt(np.sum(0.5 * (v2[1:] + v2[:-1]) * np.diff(t)) / self.steady.period))

    # -- protocol ---------------------------------------------------------------------------------
    def summary(self) -> dict[str, Any]:
        """Speeds, fluctuation, energy per stroke, motor duty, loads and checks (SI, angles in degrees)."""
        return copy.deepcopy(self._summary)

    @cached_property
    def _summary(self) -> dict[str, Any]:
        st, d = self.steady, self.drive
        w = st.speed
        Tm, Pm = self.motor_torque, self.motor_power
        out: dict[str, Any] = {
            "crank_speed_mean_rad_s": st.mean_speed,
            "crank_speed_max_rad_s": float(w.max()),
            "crank_speed_min_rad_s": float(w.min()),
            "speed_fluctuation_ratio": st.fluctuation,
            "period_s": st.period,
            "strokes_per_minute_rpm": float(convert(st.mean_speed, "rad/s", "rpm")),
            "motor_speed_mean_rad_s": d.gear_ratio * st.mean_speed,
            "motor_speed_min_rad_s": float(self.motor_speed.min()),
            "motor_torque_mean_Nm": st.motor_work / (2 * math.pi * d.gear_ratio),
            "motor_torque_rms_Nm": self._time_rms(Tm),
            "motor_torque_peak_Nm": float(np.abs(Tm).max()),
            "motor_power_mean_W": st.motor_work / st.period,
            "motor_power_rms_W": self._time_rms(Pm),
            "motor_power_peak_W": float(np.abs(Pm).max()),
        }
        rated = getattr(d.motor, "rated_torque", None)
        if rated:
            out["motor_rated_torque_Nm"] = float(rated)
            out["motor_torque_rms_to_rated_ratio"] = out["motor_torque_rms_Nm"] / rated
        pullout = getattr(d.motor, "pullout_torque", None)
        if pullout:
            out["motor_pullout_torque_Nm"] = float(pullout)
            out["motor_torque_peak_to_pullout_ratio"] = out["motor_torque_peak_Nm"] / pullout
        W = st.motor_work
        out |= {
            "process_energy_per_stroke_J": -st.process_work,
            "motor_energy_per_stroke_J": W,
            "gear_losses_per_stroke_J": st.loss_work,
            "energy_balance_residual_relative": abs(st.energy_residual) / max(abs(W), 1e-300),
            "periodicity_residual_relative": abs(st.energy_change) / max(abs(W), 1e-300),
            "gear_ratio": d.gear_ratio,
            "gear_efficiency_ratio": d.efficiency,
            "flywheel_inertia_kg_m2": float(d.flywheel_inertia),
            "flywheel_shaft": d.flywheel_shaft,
            "added_inertia_at_crank_kg_m2": d.added_inertia,
            "mechanism_inertia_min_kg_m2": float(self.reduced.inertia.min()),
            "mechanism_inertia_max_kg_m2": float(self.reduced.inertia.max()),
            "flywheel_energy_swing_J": 0.5 * d.added_inertia * float(w.max() ** 2 - w.min() ** 2),
        }
        if self.sized_flywheel is not None and self.target_fluctuation is not None:
            out["target_fluctuation_ratio"] = self.target_fluctuation
            out["flywheel_for_target_kg_m2"] = self.sized_flywheel
        T = self.mechanism_torque
        Tc = self.reduced.constant_speed_torque(st.mean_speed)[::2]
        F = self.loads.shaking_force
        Fc = self.constant.shaking_force
        peak = max(float(np.abs(T).max()), 1e-300)
        out |= {
            "mechanism_torque_peak_Nm": float(np.abs(T).max()),
            "constant_speed_torque_peak_Nm": float(np.abs(Tc).max()),
            "shaking_force_max_N": float(np.hypot(F[:, 0], F[:, 1]).max()),
            "shaking_force_max_constant_speed_N": float(np.hypot(Fc[:, 0], Fc[:, 1]).max()),
            "torque_consistency_residual_relative": float(np.abs(T - self.loads_torque).max()) / peak,
        }
        if self.startup is not None:
            s = self.startup
            out |= {
                "startup_engaged_s": s.engaged_at,
                "startup_settled_s": s.settled_at,
                "startup_revolutions": s.revolutions,
                "startup_deviation_relative": float(s.deviation),
                "startup_method": s.method,
            }
        out["n_angles"] = len(st.speed)
        return out

    @cached_property
    def _columns(self) -> dict[str, np.ndarray]:
        st, r = self.steady, self.reduced
        rows = slice(None, None, 2)
        cols: dict[str, Any] = {
            "angle_deg": np.degrees(r.angle[rows]),
            "turned_deg": np.degrees(st.turned),
            "time_s": st.time,
            "crank_speed_rad_s": st.speed,
            "crank_acceleration_rad_s2": st.acceleration,
            "motor_speed_rad_s": self.motor_speed,
            "motor_torque_Nm": self.motor_torque,
            "motor_power_W": self.motor_power,
            "motor_torque_at_crank_Nm": st.crank_torque,
            "mechanism_torque_Nm": self.mechanism_torque,
            "constant_speed_torque_Nm": r.constant_speed_torque(st.mean_speed)[rows],
            "reduced_inertia_kg_m2": r.inertia[rows],
            "applied_torque_Nm": r.force[rows],
            "process_torque_Nm": r.process_force[rows],
        }
        inv = np.argsort(self.order)  # back from the datum's order to the turned order
        F, Fc = self.loads.shaking_force[inv], self.constant.shaking_force
        cols["shaking_force_x_N"], cols["shaking_force_y_N"] = F[:, 0], F[:, 1]
        cols["shaking_force_constant_speed_x_N"] = Fc[inv, 0]
        cols["shaking_force_constant_speed_y_N"] = Fc[inv, 1]
        s = self.loads.output_position
        if s is not None:
            cols["output_position_m"] = s[inv]
        return cols

    def to_frame(self) -> pd.DataFrame:
        """One row per crank angle of the steady state, in the order turned; every column names its
        unit."""
        import pandas as pd

        return pd.DataFrame(self._columns)

    def tables(self, **display_units: str) -> list[Table]:
        """The summary, and the motor's duty against its rating.

        Parameters
        ----------
        **display_units : str
            ``force_unit``, ``length_unit``: see :func:`mechdyn.results.summary_table`.
        """
        summary = self.summary()
        tables = []
        taken: set[str] = set()
        for title, prefixes in _TABLES:
            part = {k: v for k, v in summary.items() if k.startswith(prefixes) and k not in taken}
            taken |= set(part)
            if part:
                table = summary_table(part, display_units=display_units)
                tables.append(replace(table, title=title))
        rest = {k: v for k, v in summary.items() if k not in taken}
        if rest:
            tables.append(replace(summary_table(rest, display_units=display_units), title="checks"))
        return tables

    def plots(self, **display_units: str) -> dict[str, Any]:
        """Crank speed over the cycle, motor torque and power, torque into the crank against the
        constant-speed torque, shaking force at real and constant speed, and the start-up.

        Parameters
        ----------
        **display_units : str
            ``force_unit`` (e.g. ``"tonf"``) for the shaking force.
        """
        from mechdyn.drive import plots as dp

        out = {
            "drive_speed.png": lambda: dp.plot_speed(self),
            "drive_motor.png": lambda: dp.plot_motor(self),
            "drive_torque.png": lambda: dp.plot_torque(self),
            "drive_shaking_force.png": lambda: dp.plot_shaking(self, display_units.get("force_unit")),
        }
        if self.startup is not None:
            out["drive_startup.png"] = lambda: dp.plot_startup(self)
        return out


# the summary's tables, by the keys' first words: each short enough to be printed whole
_TABLES: tuple[tuple[str, tuple[str, ...]], ...] = (
    ("crank speed", ("crank_speed", "speed_fluctuation", "period_s", "strokes", "target_fluctuation")),
    ("motor", ("motor_speed", "motor_torque", "motor_power", "motor_rated", "motor_pullout")),
    ("energy per stroke", ("process_energy", "motor_energy", "gear_losses", "flywheel_energy")),
    ("drive", ("gear_", "flywheel_", "added_inertia", "mechanism_inertia")),
    ("loads at the real speed", ("mechanism_torque", "constant_speed", "shaking_force")),
    ("start-up from rest", ("startup_",)),
)


def drive_analysis(
    drive: Any,
    n_angles: int = 720,
    *,
    target_fluctuation: float | None = None,
    startup: bool = True,
    startup_method: str = "LSODA",
) -> DriveResult:
    """Forward dynamics of a mechanism driven by a motor through gears, with a flywheel.

    Parameters
    ----------
    drive : Drive
        Motor, gear ratio and efficiency, flywheel, and the mechanism with its process forces.
    n_angles : int
        Crank angles per revolution of the steady state, a whole number from 4 to 50 000 (the
        kinematics run at twice as many: the Runge–Kutta rule's midpoints).
    target_fluctuation : float, optional
        Also size the flywheel for this coefficient of speed fluctuation δ, dimensionless, in (0, 1)
        (reported beside the drive's own flywheel; the steady state, start-up and loads are those of
        the drive as given).
    startup : bool
        Also integrate the run-up from rest.
    startup_method : str
        ``scipy.integrate.solve_ivp`` method of the start-up.

    Returns
    -------
    DriveResult

    Examples
    --------
    >>> import mechdyn
    >>> from mechdyn.drive import Drive, InductionMotor, drive_analysis
    >>> press = mechdyn.load("examples/press_link_drive.toml").model  # doctest: +SKIP
    >>> motor = InductionMotor.from_rating("75 kW", "1500 rpm", "1480 rpm", 2.5)
    >>> r = drive_analysis(Drive(press, motor, 98, "120 kg*m^2"), startup=False)  # doctest: +SKIP
    >>> r.summary()["speed_fluctuation_ratio"] < 0.1  # doctest: +SKIP
    True
    """
    from mechdyn.mechanism.dynamics import inverse_dynamics
    from mechdyn.mechanism.kinematics import check_angles

    n = check_angles(n_angles)
    drive = replace(drive, gear_ratio=None, efficiency=None)
    reduced = reduce_to_crank(drive.mechanism, 2 * n)
    sized = None
    if target_fluctuation is not None:
        sized = size_flywheel(drive, reduced, target_fluctuation)
    steady = steady_state(drive, reduced)
    at_speed = mechanism_at_speed(reduced, steady)
    loads, order = _loads_at_speed(reduced, steady, at_speed)
    constant_mech = replace(
        reduced.mechanism,
        driver=replace(reduced.mechanism.driver, speed=reduced.direction * steady.mean_speed),
    )
    k = reduced.kinematics
    w_ratio = steady.mean_speed / reduced.speed
    rows = slice(None, None, 2)
    constant = inverse_dynamics(
        replace(
            k,
            mechanism=constant_mech,
            crank_angle=k.crank_angle[rows][order],
            angle=k.angle[rows][order],
            time=(steady.turned / steady.mean_speed)[order],
            q=k.q[rows][order],
            qd=k.qd[rows][order] * w_ratio,
            qdd=k.qdd[rows][order] * w_ratio**2,
            dyads=None,
        )
    )
    run_up = start_up(drive, reduced, steady, method=startup_method) if startup else None
    result = DriveResult(drive, reduced, steady, run_up, loads, constant, order, target_fluctuation, sized)
    _warn_duty(result.summary())
    return result


PULLOUT_MARGIN = 0.9
"""The motor's peak torque over the cycle above this fraction of its pull-out torque is warned on:
the slip–torque curve is flat near pull-out, so within 10 % a small overload or a low supply voltage
(the torque goes as V², IEC 60034-1 allows −5 %) stalls the motor."""


def _warn_duty(summary: dict[str, Any]) -> None:
    """Warn where the motor runs above its continuous rating (S1 duty, IEC 60034-1: the RMS torque
    over the cycle is what heats it) or reaches its pull-out torque at the peak."""
    import warnings

    from mechdyn.errors import ModelWarning

    rms = summary.get("motor_torque_rms_to_rated_ratio")
    if rms is not None and rms > 1.0:
        warnings.warn(
            f"the motor's RMS torque is {rms:.4g} times its rated torque: above its continuous (S1) "
            "rating it overheats; choose a larger motor, a larger flywheel, or check the train's losses",
            ModelWarning,
            stacklevel=3,
        )
    peak = summary.get("motor_torque_peak_to_pullout_ratio")
    if peak is not None and peak > PULLOUT_MARGIN:
        warnings.warn(
            f"the motor's peak torque is {peak:.3g} of its pull-out torque: a little more load stalls it",
            ModelWarning,
            stacklevel=3,
        )
