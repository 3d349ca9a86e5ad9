"""Geared drivetrains in time in the registry: ``simulate``.

The analysis runs on a ``type = "drivetrain"`` file: each mesh's ``backlash``, ``transmission_error`` and
``stiffness_variation`` build the :class:`~mechdyn.gear_dynamics.GearSystem`; the ``[motor]`` and the
``[[loads]]`` are its torque inputs; ``[simulation]`` gives the defaults of the options. The model type
itself is registered by :mod:`mechdyn.drivetrain.analyses`.
"""

from __future__ import annotations

from typing import Any

from mechdyn.errors import MechdynError
from mechdyn.registry import Analysis, Option, Output, register

__all__: list[str] = []

_METHODS = ("LSODA", "Radau", "BDF", "DOP853", "RK45", "RK23")


def _simulate(
    loaded: Any,
    duration: float | None = None,
    initial_speed: float | None = None,
    reference: str | None = None,
    start: str | None = None,
    method: str | None = None,
    rtol: float | None = None,
    output_step: float | None = None,
    cycle_steps: int | None = None,
) -> Any:
    from mechdyn.gear_dynamics.simulate import simulate
    from mechdyn.gear_dynamics.system import GearSystem

    where = loaded.source.path if loaded.source is not None else repr(loaded.name)
    settings = loaded.settings
    dynamics = settings.dynamics if settings is not None else None
    table = dynamics.simulation if dynamics is not None else None
    if duration is None and table is None:
        raise MechdynError(
            f'{where}: no duration; add a [simulation] table with duration (e.g. duration = "2 s"), '
            "or pass --duration '2 s'"
        )
    inputs = dynamics.inputs() if dynamics is not None else []
    speed = initial_speed if initial_speed is not None else (table.initial_speed if table else 0.0)
    if not inputs and speed == 0.0:
        raise MechdynError(
            f"{where}: nothing moves the train; add a [motor] table or [[loads]] rows, or give "
            "[simulation] initial_speed (or --initial-speed '1500 rpm')"
        )
    options = dynamics.system_options() if dynamics is not None else {}
    system = GearSystem.from_drivetrain(loaded.model, **options)

    def pick(value: Any, name: str, default: Any) -> Any:
        return value if value is not None else (getattr(table, name) if table is not None else default)

    return simulate(
        system,
        duration if duration is not None else table.duration,  # type: ignore[union-attr]
        inputs=inputs,
        initial_speed=speed,
        reference=pick(reference, "reference", None),
        start=pick(start, "start", "static"),
        method=pick(method, "method", "LSODA"),
        rtol=pick(rtol, "rtol", 1e-7),
        output_step=pick(output_step, "output_step", None),
        cycle_steps=pick(cycle_steps, "cycle_steps", 8),
    )


register(
    Analysis(
        "simulate",
        ("drivetrain",),
        _simulate,
        "time simulation of a geared drivetrain: varying mesh stiffness, backlash, motor and loads",
        headline=("mesh_force_peak_N", "dynamic_factor", "final_speed_rad_s"),
        options=(
            Option(
                "duration",
                "quantity",
                "simulated time, e.g. '2 s' (default: the file's [simulation])",
                unit="s",
                metavar="TIME",
            ),
            Option(
                "initial_speed",
                "quantity",
                "speed of the reference disk at t = 0, e.g. '1500 rpm' (default: [simulation], else 0)",
                unit="rad/s",
                metavar="SPEED",
            ),
            Option("reference", "text", "the disk of the initial speed (default: the first)", metavar="DISK"),
            Option(
                "start",
                "choice",
                "static: start deflected by the torques at t = 0; rest: not deflected",
                choices=("static", "rest"),
            ),
            Option("method", "choice", "time integrator (default: LSODA)", choices=_METHODS),
            Option("rtol", "float", "relative tolerance of the integrator (default 1e-7)", minimum=1e-13),
            Option(
                "output_step",
                "quantity",
                "sample the result every STEP, e.g. '0.1 ms' (default: every integration step)",
                unit="s",
                metavar="STEP",
            ),
            Option("cycle_steps", "int", "fewest integration steps per mesh cycle (default 8)", minimum=1),
        ),
        outputs=(
            Output("duration_s", "simulated time"),
            Output("samples", "number of time samples", ""),
            Output("method", "the time integrator that ran", ""),
            Output("max_speed_rad_s", "per disk: its largest speed (magnitude)"),
            Output("final_speed_rad_s", "per disk: its speed at the end"),
            Output("mesh_force_peak_N", "per flexible mesh: the largest force along the line of action"),
            Output("mesh_force_rms_N", "per flexible mesh: the RMS force"),
            Output("dte_peak_to_peak_m", "per flexible mesh: the dynamic transmission error, peak to peak"),
            Output("static_mesh_force_N", "per flexible mesh: the quasi-static force under the final inputs"),
            Output("dynamic_factor", "per loaded mesh: peak force over static force (cf. ISO 6336 K_v)", ""),
            Output("contact_losses", "per mesh: how many times the teeth separated", ""),
            Output("first_contact_loss_s", "per mesh that separated: when it first did"),
            Output("energy_residual_J", "largest drift of the energy balance (accuracy check)"),
            Output("input_work_J", "work done by the motor and the loads"),
        ),
        examples=(
            "mechdyn simulate examples/turret_milling_startup.toml --plots plots",
            "mechdyn simulate examples/turret_milling_startup.toml --duration '0.2 s' --json",
        ),
    )
)
