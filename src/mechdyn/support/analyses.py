"""The support's analysis in the registry: ``support`` (the machine on its supports)."""

from __future__ import annotations

from typing import Any

from mechdyn.registry import Analysis, ModelType, Option, Output, register, register_model_type

__all__: list[str] = []


def _support(
    loaded: Any,
    cycles: int | None = None,
    store: Any = None,
    machine_group: str | None = None,
    foundation: str | None = None,
) -> Any:
    from mechdyn.errors import MechdynError
    from mechdyn.support.result import mounts_from_drawing, support_analysis

    spec = loaded.settings
    if spec is None:  # a MountedMachine built in Python: no file settings
        raise MechdynError("the support analysis runs on a support model file (it holds the load)")
    s = spec.settings
    machine, applied = loaded.model, {}
    if any(e.calibrate for e in spec.estimates.values()):
        if store is None:
            raise MechdynError(
                'a mount asks for its stored calibration (calibration = "stored"): run with a results '
                "database (--db URL, or the default mechdyn.db)"
            )
        machine, applied = spec.calibrated(store)
    result = support_analysis(
        machine,
        spec.load,
        cycles=cycles or s.start_up_cycles,
        method=s.start_up_method,
        mounts=mounts_from_drawing(machine, spec.estimates, applied),
        excitation=spec.excitation_summary(),
        speeds=spec.sweep_speeds(),
        machine_group=int(machine_group) if machine_group is not None else s.machine_group,
        foundation=foundation or s.foundation,
        points=s.vibration_points,
        separation_margin=s.separation_margin,
    )
    if spec.foundation is None:
        return result
    from mechdyn.support.floor import with_floor

    return with_floor(result, spec.foundation, spec.floor_points)


def _support_batch(loaded: Any, columns: Any, keys: Any, **options: Any) -> Any:
    from mechdyn.registry import NotBatchable
    from mechdyn.support.batch import support_batch

    if getattr(loaded.settings, "foundation", None) is not None:
        raise NotBatchable("the batch takes a support on rigid ground, not on a foundation block")

    return support_batch(loaded, columns, keys, **options)


# the files its analysis runs on: the builder returns a SupportSpec, the machine and its load
register_model_type(
    ModelType(
        "support",
        builder="mechdyn.support.schema:build",
        schema="mechdyn.support.schema:SupportFile",
        model_attribute="machine",
        model_class="mechdyn.support.model:MountedMachine",
        writer="mechdyn.support.save:to_toml",
    )
)

register(
    Analysis(
        "support",
        ("support",),
        _support,
        "a machine on its supports: modes, steady state, start-up, floor forces (an unbalance's over speed)",
        headline=("transmitted_force_range_N", "displacement_max_m", "natural_frequencies_hz"),
        uses_store=True,
        batch=_support_batch,
        options=(
            Option("cycles", "int", "start-up periods to integrate (default: the file's, else 5)", minimum=1),
            Option(
                "machine_group",
                "choice",
                "ISO 20816-3 machine group of the vibration verdict: 1 (300 kW to 50 MW) or 2 (15 kW to "
                "300 kW) (default: the file's, else 2)",
                choices=("1", "2"),
            ),
            Option(
                "foundation",
                "choice",
                "ISO 20816-3 foundation class: auto (from the modes), rigid or flexible (default: the "
                "file's, else auto)",
                choices=("auto", "rigid", "flexible"),
            ),
        ),
        outputs=(
            Output("inertia_force_max_N", "largest vertical exciting force"),
            Output("inertia_force_min_N", "smallest vertical exciting force"),
            Output("inertia_force_range_N", "range of the exciting force"),
            Output("transmitted_force_max_N", "largest vertical force on the floor"),
            Output("transmitted_force_min_N", "smallest vertical force on the floor"),
            Output("transmitted_force_range_N", "range of the force on the floor"),
            Output("transmitted_to_inertia_force_range", "transmitted over exciting force range", "1"),
            Output("displacement_max_m", "largest bed displacement"),
            Output("displacement_min_m", "smallest bed displacement"),
            Output("floor_force_range_N", "range of the floor force along x, y, z"),
            Output("mount_force_peak_N", "largest dynamic force through each mount"),
            Output("dofs", "the machine's kept coordinates", ""),
            Output("machine_mass_kg", "mass of the machine"),
            Output("period_s", "period of the load"),
            Output("natural_frequencies_hz", "natural frequencies on the mounts"),
            Output("mode_dominant_coordinate", "the coordinate that carries most of each mode", ""),
            Output("mode_decoupling", "largest kinetic-energy share of each mode (1: decoupled)", "1"),
            Output("static_deflection_m", "each mount's deflection under the weight"),
            Output("startup_cycles", "start-up periods integrated", ""),
            Output("startup_method", "start-up integrator", ""),
            Output("startup_displacement_max_m", "largest bed displacement during start-up"),
            Output("startup_displacement_min_m", "smallest bed displacement during start-up"),
            Output("startup_last_cycle_deviation_relative", "last start-up period off the steady state"),
            Output("force_balance_residual_N", "largest residual of the machine's force balance"),
            Output("elastic_centre_m", "the mounts' elastic centre"),
            Output("elastic_centre_residual", "coupling left at the elastic centre", "1"),
            Output(
                "excitation",
                "the summary of the mechanism whose shaking is the load (its stroke_m, ...), when it is one; "
                "for a drive file, at its real speed, with its speed_fluctuation_ratio, period_s, ...",
                "",
            ),
            Output("running_speed_rpm", "the first unbalanced rotor's running speed (rotors only)"),
            Output(
                "unbalance_force_N", "largest magnitude of the rotors' unbalance force at the running speed"
            ),
            Output("unbalance_floor_force_N", "largest magnitude of the floor force at the running speed"),
            Output(
                "unbalance_transmissibility_ratio", "floor force over unbalance force at the running speed"
            ),
            Output("unbalance_isolation_efficiency_percent", "1 − transmissibility (negative: amplifies)"),
            Output("unbalance_verdict", "what the mounts do to the unbalance force, in words", ""),
            Output("speed_range_rpm", "the first rotor's speeds swept"),
            Output("unbalance_floor_force_peak_N", "largest floor force over the speed range"),
            Output("unbalance_floor_force_peak_speed_rpm", "the speed of the largest floor force"),
            Output(
                "resonance_speeds_rpm", "the first rotor's speeds at which a rotor meets a natural frequency"
            ),
            Output(
                "mount_isolation",
                "each mount on its own at the running speed, as mechdyn mount rates it: static load (N), "
                "natural frequency (Hz), frequency ratio, damping ratio, transmissibility, isolation (%), "
                "verdict",
                "",
            ),
            Output(
                "iso20816_applies", "whether ISO 20816-3 covers the running speed (120 to 30 000 r/min)", ""
            ),
            Output("iso20816_machine_group", "ISO 20816-3 machine group of the verdict (1 or 2)", ""),
            Output("iso20816_foundation", "ISO 20816-3 foundation class (rigid or flexible)", ""),
            Output("iso20816_band_hz", "ISO 20816-3's frequency band for the running speed"),
            Output("iso20816_zone_boundaries_m_per_s", "the A/B, B/C and C/D boundaries (RMS velocity)"),
            Output(
                "iso20816_zone",
                "the zone of the frame's vibration (an indication where it does not apply)",
                "",
            ),
            Output(
                "frame_velocity_rms_band_m_per_s", "largest RMS vibration velocity of the frame in the band"
            ),
            Output(
                "frame_velocity_rms_all_harmonics_m_per_s", "largest RMS vibration velocity, all harmonics"
            ),
            Output("frame_velocity_rms_at_points_m_per_s", "each point's largest RMS velocity, as judged"),
            Output("frame_velocity_point", "the point of the largest vibration velocity", ""),
            Output("frame_velocity_direction", "its direction (x, y or z)", ""),
            Output("vibration_verdict", "the frame's vibration by ISO 20816-3, in words", ""),
            Output("isolation_orders", "the exciting harmonic orders (≥ 1 % of the largest)", ""),
            Output("isolation_efficiency_by_harmonic_percent", "VDI 2062 η = 1 − V at each exciting order"),
            Output("isolation_transmissibility_ratio", "RMS floor force over RMS exciting force", "1"),
            Output("isolation_efficiency_percent", "VDI 2062 η = 1 − V, overall"),
            Output("isolation_verdict", "the mounts' isolation, in words", ""),
            Output(
                "floor_vibration_verdict", "the floor against the vibration criteria curves, in words", ""
            ),
            Output(
                "floor_velocity_point", "on a foundation: the block's point of the worst floor vibration", ""
            ),
            Output("floor_velocity_direction", "on a foundation: its direction (x, y or z)", ""),
            Output(
                "floor_velocity_band_centre_hz", "on a foundation: the one-third-octave bands, 1 to 80 Hz"
            ),
            Output(
                "floor_velocity_band_m_per_s",
                "on a foundation: the floor's RMS velocity in each band, at its worst point and direction",
            ),
            Output("floor_velocity_band_max_m_per_s", "on a foundation: the floor's largest band velocity"),
            Output("floor_velocity_rms_m_per_s", "on a foundation: the floor's RMS velocity, all harmonics"),
            Output(
                "floor_velocity_band_max_at_points_m_per_s",
                "on a foundation: each floor point's largest band velocity",
            ),
            Output(
                "floor_criteria_band_ratio",
                "on a foundation: each criterion's largest band over its curve (VC-A … VC-E, ISO)",
                "1",
            ),
            Output(
                "floor_vc_b_ratio", "on a foundation: the floor's largest band over VC-B (above 1: exceeded)"
            ),
            Output("floor_vc_b_met", "on a foundation: whether the floor meets VC-B", ""),
            Output("floor_strictest_criterion_met", "on a foundation: the strictest floor criterion met", ""),
            Output(
                "floor_strictest_vc_met", "on a foundation: the strictest VC curve met (None: not VC-A)", ""
            ),
            Output(
                "foundation_natural_frequencies_hz",
                "on a foundation: natural frequencies of machine, mounts, block and soil together",
            ),
            Output(
                "soil_force_amplitude_N",
                "on a foundation: largest harmonic amplitude of the force on the soil",
            ),
            Output("foundation_mass_kg", "on a foundation: the block's mass"),
            Output("foundation_center_of_mass_m", "on a foundation: the block's centre of mass"),
            Output("soil_stiffness_N_per_m", "on a foundation: the soil's springs along x, y, z"),
            Output(
                "soil_rotational_stiffness_Nm_per_rad", "on a foundation: the soil's springs about x, y, z"
            ),
            Output("soil_damping_N_s_per_m", "on a foundation: the soil's dashpots along x, y, z"),
            Output(
                "soil_rotational_damping_Nm_s_per_rad", "on a foundation: the soil's dashpots about x, y, z"
            ),
            Output("soil_springs_from", "on a foundation: given, or the half-space's closed forms", ""),
            Output("soil_shear_modulus_Pa", "on a foundation over a half-space: the soil's shear modulus"),
            Output(
                "soil_shear_wave_speed_m_per_s", "on a foundation over a half-space: its shear-wave speed"
            ),
            Output("mode_nearest_harmonic", "each mode's nearest exciting harmonic order", ""),
            Output("mode_separation_margin_percent", "each mode's distance from it, (f − h f0)/(h f0)"),
            Output("mode_driven_by_harmonic", "whether that harmonic drives the mode", ""),
            Output("mode_close_to_harmonic", "a driven mode within the separation margin", ""),
            Output("mode_separation_limit_percent", "the separation margin flagged"),
            Output("mode_separation_verdict", "the modes near an exciting harmonic, in words", ""),
            Output(
                "mounts_from_drawing",
                "each mount estimated from its drawing: type, source, stiffness along its axes (N/m), "
                "loss factor, the stored calibration applied",
                "",
            ),
        ),
        examples=(
            "mechdyn support examples/press_on_support.toml --plots plots",
            "mechdyn support examples/press_on_mounts.toml --cycles 2 --csv steady.csv",
            "mechdyn support examples/press_driven_on_mounts.toml --plots plots",
            "mechdyn support examples/press_on_pads.toml --plots plots",
            "mechdyn support examples/pump_set_unbalance.toml --plots plots",
            "mechdyn support examples/press_on_mounts_foundation.toml",
        ),
    )
)
