"""The drive's analyses in the registry: ``drive`` (a mechanism driven by a motor through gears, with a
flywheel: steady state, speed fluctuation, motor duty, start-up, loads at the real speed)."""

from __future__ import annotations

from typing import Any

from mechdyn.registry import Analysis, ModelType, Option, Output, register, register_model_type

__all__: list[str] = []


def _drive(
    loaded: Any,
    angles: int | None = None,
    fluctuation: float | None = None,
    no_startup: bool = False,
    startup_method: str | None = None,
) -> Any:
    from mechdyn.drive.result import drive_analysis

    spec = loaded.settings
    if spec is None:  # a Drive built in Python: the defaults
        return drive_analysis(
            loaded.model,
            angles or 720,
            target_fluctuation=fluctuation,
            startup=not no_startup,
            startup_method=startup_method or "LSODA",
        )
    s = spec.settings
    return drive_analysis(
        spec.drive,
        angles or s.n_angles,
        target_fluctuation=fluctuation if fluctuation is not None else spec.target_fluctuation,
        startup=s.start_up and not no_startup,
        startup_method=startup_method or s.start_up_method,
    )


register_model_type(
    ModelType(
        "drive",
        builder="mechdyn.drive.schema:build",
        schema="mechdyn.drive.schema:DriveFile",
        model_attribute="drive",
        model_class="mechdyn.drive.model:Drive",
    )
)

register(
    Analysis(
        "drive",
        ("drive",),
        _drive,
        "a mechanism driven by a motor through gears, with a flywheel: speed fluctuation, motor duty, "
        "start-up",
        headline=("speed_fluctuation_ratio", "motor_torque_rms_Nm", "motor_power_peak_W"),
        options=(
            Option("angles", "int", "crank angles per revolution (default: the file's, else 720)", minimum=8),
            Option(
                "fluctuation",
                "float",
                "size the flywheel for this coefficient of speed fluctuation (default: the file's)",
                minimum=0.0,
            ),
            Option("no_startup", "flag", "skip the run-up from rest"),
            Option(
                "startup_method",
                "choice",
                "time integrator of the start-up (default: the file's, else LSODA)",
                choices=("LSODA", "Radau", "BDF", "DOP853", "RK45"),
            ),
        ),
        outputs=(
            Output("crank_speed_mean_rad_s", "time-average crank speed, 2π over the period"),
            Output("crank_speed_max_rad_s", "largest crank speed over the cycle"),
            Output("crank_speed_min_rad_s", "smallest crank speed over the cycle"),
            Output("speed_fluctuation_ratio", "coefficient of speed fluctuation δ = (ω_max − ω_min)/ω_mean"),
            Output("period_s", "time of one revolution (one stroke)"),
            Output("strokes_per_minute_rpm", "strokes per minute"),
            Output("motor_speed_mean_rad_s", "time-average motor speed"),
            Output("motor_speed_min_rad_s", "smallest motor speed over the cycle"),
            Output("motor_torque_mean_Nm", "mean motor torque (work per revolution of the motor shaft)"),
            Output("motor_torque_rms_Nm", "root mean square of the motor torque over time (thermal duty)"),
            Output("motor_torque_peak_Nm", "largest motor torque magnitude"),
            Output("motor_power_mean_W", "mean motor power"),
            Output("motor_power_rms_W", "root mean square of the motor power over time"),
            Output("motor_power_peak_W", "largest motor power magnitude"),
            Output("motor_rated_torque_Nm", "the induction motor's rated torque"),
            Output("motor_torque_rms_to_rated_ratio", "RMS motor torque over the rated torque"),
            Output("motor_pullout_torque_Nm", "the induction motor's pull-out (breakdown) torque"),
            Output("motor_torque_peak_to_pullout_ratio", "peak motor torque over the pull-out torque"),
            Output("process_energy_per_stroke_J", "work the process (forming) force absorbs per stroke", "J"),
            Output("motor_energy_per_stroke_J", "work of the motor shaft per stroke", "J"),
            Output("gear_losses_per_stroke_J", "work lost in the train's stages per stroke", "J"),
            Output(
                "energy_balance_residual_relative",
                "|W_motor − W_losses + W_applied − ΔK| over W_motor, the integrator's balance (round-off)",
            ),
            Output("periodicity_residual_relative", "|K(2π) − K(0)| over W_motor (the shooting's tolerance)"),
            Output("gear_ratio", "gear ratio, motor speed over crank speed"),
            Output("gear_efficiency_ratio", "overall efficiency of the train, power flowing to the crank"),
            Output("flywheel_inertia_kg_m2", "the flywheel's inertia, as given"),
            Output("flywheel_shaft", "the shaft the flywheel sits on: motor, a stage's or crank", ""),
            Output("added_inertia_at_crank_kg_m2", "flywheel, motor rotor and train reduced to the crank"),
            Output("mechanism_inertia_min_kg_m2", "smallest reduced inertia of the mechanism at the crank"),
            Output("mechanism_inertia_max_kg_m2", "largest reduced inertia of the mechanism at the crank"),
            Output(
                "flywheel_energy_swing_J", "kinetic energy the flywheel and rotor give and take back", "J"
            ),
            Output("target_fluctuation_ratio", "the coefficient of fluctuation the flywheel was sized for"),
            Output("flywheel_for_target_kg_m2", "the flywheel inertia that gives the target fluctuation"),
            Output("mechanism_torque_peak_Nm", "largest torque the drive puts into the crank, real speed"),
            Output("constant_speed_torque_peak_Nm", "largest driving torque at constant mean speed"),
            Output("shaking_force_max_N", "largest shaking force at the real, fluctuating speed"),
            Output("shaking_force_max_constant_speed_N", "largest shaking force at constant mean speed"),
            Output(
                "torque_consistency_residual_relative",
                "reduced model against the mechanism's inverse dynamics at the real speed (round-off)",
            ),
            Output("startup_engaged_s", "time from rest to the stroke where the work is engaged"),
            Output("startup_settled_s", "time from rest until every crank pass is within 0.1 % of steady"),
            Output("startup_revolutions", "revolutions integrated in the start-up", ""),
            Output("startup_deviation_relative", "last start-up revolution off the steady state"),
            Output("startup_method", "start-up integrator", ""),
            Output("n_angles", "crank angles per revolution", ""),
        ),
        examples=(
            "mechdyn drive examples/press_driven.toml --plots plots",
            "mechdyn drive examples/press_driven.toml --fluctuation 0.03 --no-startup --json",
        ),
    )
)
