"""Geared drivetrains in time in the registry: ``simulate`` and ``speed-sweep``.

The analysis runs on a ``type = "drivetrain"`` file: each mesh's ``backlash``, ``transmission_error`` and
``stiffness_variation`` build the :class:`~mechdyn.gear_dynamics.GearSystem` (one builder,
:func:`_system`); the ``[motor]`` and the ``[[loads]]`` are its torque inputs; ``[simulation]`` and
``[speed_sweep]`` give the defaults of the options. The model type itself is registered by
:mod:`mechdyn.drivetrain.analyses`; this wing extends it with those tables
(:mod:`mechdyn.gear_dynamics.file`).
"""

from __future__ import annotations

from typing import Any

import mechdyn.drivetrain.analyses  # noqa: F401 - registers the drivetrain file type this wing extends
from mechdyn.errors import MechdynError, ModelFileError
from mechdyn.registry import Analysis, Option, Output, extend_model_type, register

__all__: list[str] = []

# a drivetrain file's meshes carry their dynamics and the file its time tables
extend_model_type(
    "drivetrain",
    schema="mechdyn.gear_dynamics.file:DrivetrainFile",
    settings="mechdyn.gear_dynamics.file:settings",
)

_METHODS = ("LSODA", "Radau", "BDF", "DOP853", "RK45", "RK23")


def _where(loaded: Any) -> str:
    return str(loaded.source.path) if loaded.source is not None else repr(loaded.name)


def _system(loaded: Any, backlash: bool = True) -> Any:
    """The :class:`~mechdyn.gear_dynamics.GearSystem` of a drivetrain file: its meshes' stiffness
    variation, transmission error and (unless ``backlash`` is False) backlash."""
    from mechdyn.gear_dynamics.system import GearSystem

    dynamics = loaded.settings.dynamics if loaded.settings is not None else None
    options = dynamics.system_options() if dynamics is not None else {}
    if not backlash:
        options["backlash"] = {}
    return GearSystem.from_drivetrain(loaded.model, **options)


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
    motor: str | None = None,
) -> Any:
    from dataclasses import replace

    from mechdyn.gear_dynamics.schema import DynamicsSettings, motor_file
    from mechdyn.gear_dynamics.simulate import simulate

    where = _where(loaded)
    settings = loaded.settings
    dynamics = settings.dynamics if settings is not None else None
    table = dynamics.simulation if dynamics is not None else None
    if motor is not None:  # another file's [motor] in place of the model's own
        own = dynamics.motor if dynamics is not None else None
        chosen = motor_file(motor, own.disk if own is not None else reference, loaded.model.disk_names)
        dynamics = replace(dynamics or DynamicsSettings(), motor=chosen)
    if duration is None and table is None:
        raise MechdynError(
            f'{where}: no duration; add a [simulation] table with duration (e.g. duration = "2 s"), '
            "or pass --duration '2 s'"
        )
    _check_times(loaded, duration, output_step, table)
    inputs = dynamics.inputs() if dynamics is not None else []
    speed = initial_speed if initial_speed is not None else (table.initial_speed if table else 0.0)
    if not inputs and speed == 0.0:
        raise MechdynError(
            f"{where}: nothing moves the train; add a [motor] table or [[loads]] rows (or pass --motor "
            "FILE, a drive file's [motor]), or give "
            "[simulation] initial_speed (or --initial-speed '1500 rpm')"
        )
    system = _system(loaded)

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


def _check_times(loaded: Any, duration: float | None, output_step: float | None, table: Any) -> None:
    """The duration and the output step checked before the model is built, each named where it was
    given (the option or the ``[simulation]`` field)."""
    where = _where(loaded)
    given = {
        "duration": ("--duration", duration) if duration is not None else ("[simulation] → duration", None),
        "output_step": ("--output-step", output_step)
        if output_step is not None
        else ("[simulation] → output_step", None),
    }
    values = {
        k: v if v is not None else (getattr(table, k) if table is not None else None)
        for k, (_, v) in given.items()
    }
    for key, value in values.items():
        if value is not None and not value > 0:
            raise ModelFileError(
                where, given[key][0], f"{value:g} s: give a positive time, e.g. '0.5 s'", value
            )
    T, step = values["duration"], values["output_step"]
    if T is not None and step is not None and step > T:
        raise ModelFileError(
            where,
            given["output_step"][0],
            f"{step:g} s is longer than the duration ({T:g} s): no sample would fall inside the run; give "
            f"a step of at most {T / 100:g} s (100 samples) or leave it out (every integration step)",
            step,
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
            Option(
                "motor",
                "text",
                "drive with the [motor] of FILE (a drive or drivetrain file) instead of the model's own; "
                "on its disk, else on the model's motor disk, else on --reference",
                metavar="FILE",
            ),
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


def _running_load(loaded: Any, system: Any, reference: str) -> dict[str, float]:
    """Torque drawn at each disk once the train runs, N·m, resisting the disk's rotation: each
    ``[[loads]]`` row's final torque (a constant's torque, a step's or ramp's after it, a harmonic
    load's mean, a table's last row); a ``stop`` is passed over."""
    import numpy as np

    from mechdyn.gear_dynamics import loads as L

    dynamics = loaded.settings.dynamics if loaded.settings is not None else None
    if dynamics is None or not dynamics.loads:
        return {}
    dt = system.drivetrain
    T = np.asarray(system.T, float)
    r = np.asarray(system.rigid_body, float).reshape(T.shape[1], -1)[:, 0]
    ref = float(T[dt.disk_index[reference]] @ r) or 1.0
    out: dict[str, float] = {}
    for row in dynamics.loads:
        if row.kind == "stop":
            continue
        disk = str(row.disk)
        if row.kind == "table":
            torque = float(L.TabulatedTorque.from_table(disk, row.rows or []).torques[-1])
        else:
            torque = float(row.torque or 0.0)
        # the file's torque is in the positive sense; speed_sweep's resists the disk's turning
        sense = float(np.sign(T[dt.disk_index[disk]] @ r / ref)) or 1.0
        out[disk] = out.get(disk, 0.0) - torque * sense
    return out


def _motor(dynamics: Any) -> Any:
    """The file's motor as a :class:`~mechdyn.gear_dynamics.loads.MotorTorque` (a stop's drive)."""
    first = dynamics.inputs()[0]
    return getattr(first, "drive", first)


def _speed_sweep(
    loaded: Any,
    speed_range: tuple[float, float] | None = None,
    points: int | None = None,
    reference: str | None = None,
    harmonics: int | None = None,
    no_backlash: bool = False,
    no_stability: bool = False,
    direction: str | None = None,
    drive: str | None = None,
) -> Any:
    import dataclasses

    import numpy as np

    from mechdyn.gear_dynamics.sweep import speed_sweep

    settings = loaded.settings
    table = settings.speed_sweep if settings is not None else None
    dynamics = settings.dynamics if settings is not None else None
    speeds = speed_range or (table.speed_range if table is not None else None)
    if speeds is None:
        raise ModelFileError(
            _where(loaded),
            "[speed_sweep] → speed_range",
            'no speed range; add a [speed_sweep] table with speed_range (e.g. speed_range = ["1000 rpm", '
            "\"5000 rpm\"]), or pass --speed-range '1000 rpm' '5000 rpm'",
        )
    low, high = speeds
    if not 0 < low < high:
        raise ModelFileError(
            _where(loaded),
            "--speed-range",
            "give 0 < LOW < HIGH, e.g. '1000 rpm' '5000 rpm' (a steady state needs the train turning)",
        )
    n = points if points is not None else (table.points if table is not None else 60)
    motor = dynamics.motor.disk if dynamics is not None and dynamics.motor is not None else None
    ref = reference or (table.reference if table is not None else None) or motor or loaded.model.disk_names[0]
    backlash = not no_backlash and (table.backlash if table is not None else True)
    system = _system(loaded, backlash=backlash)
    drive = drive or (table.drive if table is not None else None) or ("motor" if motor else "torque")
    if drive == "motor" and motor is None:
        raise ModelFileError(
            _where(loaded),
            "[speed_sweep] → drive" if table is not None and table.drive == "motor" else "--drive",
            "drive 'motor' needs a [motor] table (the motor's disk and curve); add one, or give drive "
            "'torque' (a constant torque at the reference disk) or 'speed' (the reference disk held)",
        )
    result = speed_sweep(
        system,
        np.linspace(low, high, n),
        reference=ref,
        load=_running_load(loaded, system, ref),
        harmonics=harmonics or (table.harmonics if table is not None else None) or "auto",
        gear_pairs=settings.gear_pairs if settings is not None else None,
        stability=not no_stability,
        direction=direction or (table.direction if table is not None else "up"),  # type: ignore[arg-type]
        drive=drive,  # type: ignore[arg-type]
        motor=_motor(dynamics) if drive == "motor" else None,
    )
    gaps = dynamics.system_options()["backlash"] if dynamics is not None else {}
    if not backlash and gaps:
        reversed_ = [
            name
            for j, name in enumerate(result.mesh_names)
            if name in gaps and np.any(np.sign(result.force_min[:, j]) != np.sign(result.force_max[:, j]))
        ]
        note = (
            f"The backlash of {', '.join(repr(g) for g in gaps)} is ignored: the teeth are held in contact"
            + (
                f"; the force of {', '.join(repr(m) for m in reversed_)} reverses, so there the teeth "
                "would separate and the result is not valid there (sweep with the backlash for the steady "
                "state with contact loss: backlash = true in [speed_sweep], no --no-backlash)"
                if reversed_
                else ""
            )
        )
        result = dataclasses.replace(result, notes=(*result.notes, note))
    return result


register(
    Analysis(
        "speed-sweep",
        ("drivetrain",),
        _speed_sweep,
        "periodic steady state over speed: dynamic mesh forces, K_v (with ISO 6336-1's), DTE, resonances",
        headline=("points", "unstable_points"),
        options=(
            Option(
                "speed_range",
                "quantity",
                "speeds of the reference disk, e.g. '1000 rpm' '5000 rpm' (default: [speed_sweep])",
                unit="rad/s",
                nargs=2,
                metavar=("LOW", "HIGH"),
            ),
            Option("points", "int", "speeds evenly spaced over the range (default 60)", minimum=3),
            Option(
                "reference",
                "text",
                "the disk whose speed is swept (default: the [motor]'s disk, else the first)",
                metavar="DISK",
            ),
            Option(
                "harmonics",
                "int",
                "harmonics of each mesh frequency (default: to twice the highest natural frequency at the "
                "lowest speed, doubled until K_v changes by under one per cent)",
                minimum=1,
            ),
            Option("no_backlash", "flag", "hold the teeth in contact: ignore the backlash (faster)"),
            Option(
                "direction",
                "choice",
                "with backlash, sweep the speeds up, down or both (both: the two branches of the jump)",
                choices=("up", "down", "both"),
            ),
            Option("no_stability", "flag", "skip the Floquet stability of each periodic solution (faster)"),
            Option(
                "drive",
                "choice",
                "motor: the [motor] drives, free on its torque-speed curve (as simulate; the default with "
                "a [motor]); torque: a constant torque at the reference disk; speed: the reference disk "
                "held at each speed (a kinematic input)",
                choices=("motor", "torque", "speed"),
            ),
        ),
        outputs=(
            Output("reference", "the disk whose speed is swept", ""),
            Output("drive", "how the train is driven at each speed", ""),
            Output(
                "method",
                "harmonic balance, or shooting (Newton, continued over speed through contact loss) where "
                "a mesh has backlash",
                "",
            ),
            Output("speed_min_rad_s", "the lowest speed swept"),
            Output("speed_max_rad_s", "the highest speed swept"),
            Output("points", "speeds computed (those given and those added near the peaks)", ""),
            Output("harmonics", "harmonics of each mesh frequency in harmonic balance (0: shooting)", ""),
            Output(
                "harmonics_error_ratio",
                "estimated largest relative error of K_v from the harmonics' truncation (doubling them)",
                "",
            ),
            Output("unstable_points", "speeds where the periodic solution is unstable (Floquet ρ > 1)", ""),
            Output(
                "period_doubled_points",
                "with backlash: speeds where the period-doubled orbit born at a flip is shown",
                "",
            ),
            Output(
                "meshes",
                "per flexible mesh: dynamic_factor_max_ratio and dynamic_factor_max_at_rad_s, "
                "static_force_N, force_max_N, dte_amplitude_max_m, resonance_speeds_rad_s and, with gear "
                "data, iso_dynamic_factor_max_ratio",
                "",
            ),
        ),
        examples=(
            "mechdyn speed-sweep examples/turret_milling_startup.toml --plots plots",
            "mechdyn speed-sweep examples/turret_milling_startup.toml --speed-range '2500 rpm' '4000 rpm' "
            "--points 30 --json",
        ),
    )
)
