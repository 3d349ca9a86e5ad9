"""The mounts' analysis in the registry: ``mount`` (stiffness from the drawing, FE reference,
calibration)."""

from __future__ import annotations

from typing import Any

from mechdyn.registry import Analysis, ModelType, Output, register, register_model_type

__all__: list[str] = []


def _mount(loaded: Any, store: Any = None) -> Any:
    from mechdyn.mounts.analysis import analyse

    return analyse(loaded.settings, store)


# the files its analysis runs on: the builder returns a MountSpec, the estimate and its settings
register_model_type(
    ModelType(
        "mount",
        builder="mechdyn.mounts.schema:build",
        schema="mechdyn.mounts.schema:MountFile",
        model_attribute="mount",
    )
)

register(
    Analysis(
        "mount",
        ("mount",),
        _mount,
        "a mount's stiffness from the drawing, FE reference and calibration",
        headline=("stiffness_N_per_m", "shear_stiffness_N_per_m"),
        uses_store=True,
        outputs=(
            Output("mount_type", "pad, anchor, bolted, wedge, foot, damping_pad or spring", ""),
            Output("stiffness_N_per_m", "stiffness along the main axis"),
            Output("stiffness_as_drawn_N_per_m", "before a stored calibration was applied"),
            Output("applied_calibration", "the stored calibration applied, with its provenance", ""),
            Output("breakdown", "the estimate's parts (frusta, bolt, pad terms)", ""),
            Output("adjusts_height", "whether the mount levels the machine", ""),
            Output("damps", "whether the mount damps", ""),
            Output("loss_factor", "material loss factor", "1"),
            Output("shape_factor", "pad shape factor S", "1"),
            Output("shear_stiffness_N_per_m", "pad shear stiffness"),
            Output("linear_limits_N", "loads up to which the linear pad estimate holds"),
            Output("bolt_stiffness_N_per_m", "bolt stiffness"),
            Output("member_stiffness_N_per_m", "clamped-member stiffness (pressure cones in series)"),
            Output("load_factor", "share of an external load taken by the bolt", "1"),
            Output("cone_half_angle_deg", "pressure-cone half-angle"),
            Output("fe_stiffness_N_per_m", "finite-element reference, extrapolated to the converged mesh"),
            Output(
                "fe_error_bound_relative",
                "error bound of the reference: the change between the last two Richardson extrapolations",
                "1",
            ),
            Output(
                "fe_error_verified", "whether two successive extrapolations rest on admissible orders", ""
            ),
            Output("fe_note", "why the reference's error is not bounded, when it is not", ""),
            Output("fe_finest_mesh_N_per_m", "finite-element stiffness on the finest mesh"),
            Output("fe_discretisation_error_relative", "Richardson estimate of the finest mesh's error", "1"),
            Output("fe_convergence_order", "observed order of mesh convergence (last three meshes)", "1"),
            Output("fe_theoretical_order", "the elements' order for a stiffness (2 × their degree)", "1"),
            Output("fe_tolerance_relative", "the error bound the reference was refined to", "1"),
            Output("fe_convergence", "stiffness at each mesh refinement", ""),
            Output("estimate_to_fe", "estimate over the FE reference", "1"),
            Output("ideal_solid_estimate_to_fe", "ideal-solid pad estimate over the FE reference", "1"),
            Output("contact", "contact pressure at each preload", ""),
            Output("contact_lift_off_radius_m", "radius where the plate lifts off the concrete"),
            Output("pressure_threshold_Pa", "contact-pressure threshold"),
            Output("calibration", "the fitted parameter with its provenance and effect", ""),
            Output("frf_fit", "single-DOF fit to a measured FRF", ""),
            Output("isolation", "transmissibility and isolation on the given load", ""),
        ),
        examples=(
            "mechdyn mount examples/anchor_concrete.toml --plots plots",
            "mechdyn mount examples/pad_shore60.toml --json",
        ),
    )
)
