"""The mechanism's analysis in the registry: ``mechanism`` (kinematics and inverse dynamics over one
revolution of the crank)."""

from __future__ import annotations

from typing import Any

from mechdyn.registry import Analysis, ModelType, Option, Output, register, register_model_type

__all__: list[str] = []


def _mechanism(loaded: Any, angles: int | None = None) -> Any:
    from dataclasses import replace

    from mechdyn.mechanism.dynamics import inverse_dynamics

    spec = loaded.settings
    n = angles or (spec.n_angles if spec is not None else 360)
    result = inverse_dynamics(loaded.model, n)
    if spec is not None and (spec.trace or spec.field_velocity is not None):
        result = replace(result, trace=tuple(spec.trace), field_velocity=spec.field_velocity)
    if getattr(spec, "rated_torque", None) is not None:  # a press's rating: its tonnage
        result = replace(
            result, rated_torque=spec.rated_torque, rated_force=spec.rated_force, frame=spec.frame
        )
    return result


def _mechanism_batch(loaded: Any, columns: Any, keys: Any, angles: int | None = None) -> Any:
    """Many variants in one compiled batch (:mod:`mechdyn.mechanism.batch`)."""
    from mechdyn.mechanism.batch import cycle_columns, summary_columns

    spec = loaded.settings
    n = angles or (spec.n_angles if spec is not None else 360)
    own = {}
    for (files, keys_), values in columns.items():
        if files:  # a value in another file: not the mechanism's
            from mechdyn.registry import NotBatchable

            raise NotBatchable("a value outside the mechanism file")
        own[keys_] = values
    batch = cycle_columns(loaded.model, own, n, summary_only=True)  # a study keeps scalars
    V = batch.n_variants
    errors = [batch.failures.get(v) for v in range(V)]
    return summary_columns(batch.summary(), keys, V), errors


# the files its analysis runs on: each builder returns a MechanismSpec, the mechanism and its settings
register_model_type(
    ModelType(
        "mechanism",
        builder="mechdyn.mechanism.schema:build",
        schema="mechdyn.mechanism.schema:MechanismFile",
        model_attribute="mechanism",
        model_class="mechdyn.mechanism.model:Mechanism",
        writer="mechdyn.mechanism.save:to_toml",
    )
)
register_model_type(
    ModelType(
        "planting_mechanism",
        builder="mechdyn.mechanism.planter:build",
        schema="mechdyn.mechanism.planter:PlanterFile",
        model_attribute="mechanism",
        # the model is a Mechanism too: one writer for both types, which writes a planting mechanism
        # loaded from its design file as that design
        model_class="mechdyn.mechanism.model:Mechanism",
        writer="mechdyn.mechanism.save:to_toml",
    )
)

register(
    Analysis(
        "mechanism",
        ("mechanism", "planting_mechanism"),
        _mechanism,
        "kinematics and inverse dynamics of a planar mechanism",
        headline=("stroke_m", "driving_torque_peak_Nm", "shaking_force_max_N", "inertia_force_max_N"),
        batch=_mechanism_batch,
        animates=True,
        options=(
            Option("angles", "int", "crank angles per revolution (default: the file's, else 360)", minimum=3),
        ),
        outputs=(
            Output("stroke_m", "slide stroke (mechanisms with a slide)"),
            Output("bdc_deg", "crank angle of bottom dead centre"),
            Output("tdc_deg", "crank angle of top dead centre"),
            Output("return_stroke_deg", "crank angle from BDC to TDC"),
            Output("working_stroke_deg", "crank angle from TDC to BDC"),
            Output("inertia_force_max_N", "largest inertia force along the slide axis"),
            Output("inertia_force_max_deg", "crank angle of the largest inertia force"),
            Output("inertia_force_min_N", "smallest inertia force along the slide axis"),
            Output("inertia_force_min_deg", "crank angle of the smallest inertia force"),
            Output("inertia_force_fluctuation_N", "largest minus smallest inertia force"),
            Output(
                "output_link_obliquity_max_deg",
                "largest angle between the link that drives the slide and the slide's axis",
            ),
            Output("guide_offset_m", "distance from the crank's pivot to the slide's guide line"),
            Output(
                "transmission_angle_min_deg",
                "smallest transmission angle of the dyads over the cycle (acute angle between coupler and "
                "output link, or the normal to a slide's travel; 90 deg transmits best, 0 locks)",
            ),
            Output(
                "crank_angle_at_transmission_angle_min_deg", "crank angle of the smallest transmission angle"
            ),
            Output(
                "dyads",
                "per dyad (by the joint at its inner point): its kind and links, its smallest and largest "
                "transmission angle and the crank angle of the smallest",
                "",
            ),
            Output("output_swing_deg", "angular swing of a rocker output (largest minus smallest angle)"),
            Output("output_angle_min_deg", "angle of a rocker output from +x at one limit of its swing"),
            Output(
                "output_angle_max_deg", "angle of a rocker output from +x at the other limit of its swing"
            ),
            Output(
                "crank_angle_at_output_angle_min_deg",
                "crank angle where a rocker output is at its smallest angle",
            ),
            Output(
                "crank_angle_at_output_angle_max_deg",
                "crank angle where a rocker output is at its largest angle",
            ),
            Output("driving_torque_max_Nm", "largest driving torque"),
            Output("driving_torque_min_Nm", "smallest driving torque"),
            Output("driving_torque_range_Nm", "largest minus smallest driving torque"),
            Output("driving_torque_peak_Nm", "largest magnitude of the driving torque"),
            Output("driving_torque_rms_Nm", "root mean square of the driving torque"),
            Output("shaking_force_max_N", "largest magnitude of the shaking force"),
            Output("shaking_moment_range_Nm", "range of the shaking moment about the origin"),
            Output("shaking_force_x_range_N", "range of the shaking force along x"),
            Output("shaking_force_y_range_N", "range of the shaking force along y"),
            Output("joint_force_peak_N", "largest force in each joint"),
            Output("tooth_force_max_N", "largest mesh force of the gear pairs (geared mechanisms)"),
            Output("gear_pairs", "per gear pair: centre distance, ratio, convexity, pressure angles", ""),
            Output("rated_torque_Nm", "a press's rated crank torque (from the file's settings)"),
            Output(
                "tonnage_capacity_min_N",
                "smallest slide force the rated torque delivers on the working stroke, T_r/|ds/dθ|",
            ),
            Output("rated_force_N", "a press's rated force (from the file's settings)"),
            Output(
                "rated_point_before_bdc_m",
                "distance before BDC from which the rated torque delivers the rated force (the rated point)",
            ),
            Output("rated_point_before_bdc_deg", "crank angle before BDC of the rated point"),
            Output("tonnage_at_rated_point_N", "force the rated torque delivers at the rated point"),
            Output(
                "rated_energy_below_rated_point_J",
                "work of the rated torque from the rated point to BDC (T_r times the crank angle)",
            ),
            Output(
                "process_energy_per_stroke_J", "work the drive does against the process forces per stroke"
            ),
            Output(
                "rated_torque_energy_over_process_J",
                "work the rated torque can deliver over the crank angle where the process forces act",
            ),
            Output(
                "process_force_to_capacity_max_ratio",
                "largest ratio of the process force to the force the rated torque delivers",
            ),
            Output(
                "crank_angle_at_process_force_to_capacity_max_deg",
                "crank angle of the largest ratio of process force to available force",
            ),
            Output(
                "process_force_to_capacity_max_before_bdc_m",
                "distance before BDC of the largest ratio of process force to available force",
            ),
            Output("breakthrough_force_N", "process force that breaks off on the working stroke"),
            Output("breakthrough_crank_angle_deg", "crank angle where it starts to break off"),
            Output("breakthrough_before_bdc_m", "distance before BDC where it starts to break off"),
            Output("breakthrough_release_time_s", "time over which it falls"),
            Output("press_stiffness_N_per_m", "the press's stiffness between slide and bed (file settings)"),
            Output("frame_period_s", "period of the slide on the press's stiffness, 2π√(m/k)"),
            Output("frame_energy_released_J", "elastic energy the frame releases at break-through", "J"),
            Output("reverse_load_peak_N", "reverse load when the frame springs back (one mode)"),
            Output("reverse_load_to_capacity_ratio", "reverse load over the press's reverse capacity"),
            Output("reverse_capacity_N", "the reverse load the press is rated for"),
            Output("reverse_load_verdict", "the reverse load against the press's reverse capacity", ""),
            Output(
                "tonnage_verdict", "whether the process force stays within the tonnage curve, and where", ""
            ),
            Output("power_balance_residual_relative", "power balance residual over the peak power"),
            Output("n_angles", "crank angles per revolution", ""),
        ),
        examples=(
            "mechdyn mechanism examples/press_link_drive.toml --plots plots --csv press.csv",
            "mechdyn mechanism examples/transplanter_rp1.toml --angles 72 --json",
            "mechdyn mechanism examples/fourbar.toml --animate fourbar.gif",
        ),
    )
)
