"""The gears' analysis in the registry: ``gear`` (tooth and mesh stiffness against ISO 6336-1)."""

from __future__ import annotations

from typing import Any

from mechdyn.registry import Analysis, ModelType, Output, register, register_model_type

__all__: list[str] = []


def _gear(loaded: Any) -> Any:
    from mechdyn.errors import MechdynError
    from mechdyn.gears.results import gear_pair_stiffness, tooth_pair_stiffness

    spec = loaded.settings
    if loaded.type == "gear_pair":
        if spec is None:  # a GearPair built in Python: the file's defaults
            return gear_pair_stiffness(loaded.model)
        return gear_pair_stiffness(loaded.model, spec.points, spec.specific_load)
    if spec is None:
        raise MechdynError("a tooth pair runs from its file (it gives the load heights and angle)")
    return tooth_pair_stiffness(
        loaded.model, spec.load_heights, spec.load_angle, spec.published_stiffness, spec.formulas
    )


# the files its analysis runs on: each builder returns a spec of the pair (or teeth) and its settings
register_model_type(
    ModelType(
        "gear_pair",
        builder="mechdyn.gears.schema:build_gear_pair",
        schema="mechdyn.gears.schema:GearPairModel",
        model_attribute="pair",
        model_class="mechdyn.gears.mesh:GearPair",
        writer="mechdyn.gears.save:to_toml",
    )
)
register_model_type(
    ModelType(
        "tooth_pair",
        builder="mechdyn.gears.schema:build_tooth_pair",
        schema="mechdyn.gears.schema:ToothPairModel",
        model_attribute="teeth",
    )
)

register(
    Analysis(
        "gear",
        ("gear_pair", "tooth_pair"),
        _gear,
        "tooth and mesh stiffness of a gear pair, against ISO 6336-1",
        headline=("mesh_stiffness_mean_N_per_m", "contact_ratio", "iso_c_gamma_N_per_mm_um"),
        model_noun="gear",
        outputs=(
            Output("contact_ratio", "transverse contact ratio ε_α", "1"),
            Output("overlap_ratio", "overlap ratio ε_β (0 for spur gears)", "1"),
            Output("total_contact_ratio", "total contact ratio ε_γ = ε_α + ε_β", "1"),
            Output("helix_angle_rad", "helix angle β"),
            Output("internal", "an external pinion in an internal gear", ""),
            Output("face_width_m", "common face width"),
            Output("mesh_stiffness_mean_N_per_m", "mean mesh stiffness over a mesh cycle (gear pairs)"),
            Output("mesh_stiffness_min_N_per_m", "smallest mesh stiffness over the cycle"),
            Output("mesh_stiffness_max_N_per_m", "largest mesh stiffness over the cycle"),
            Output("mesh_stiffness_fluctuation", "(max − min)/mean of the mesh stiffness", "1"),
            Output(
                "mesh_stiffness_harmonics_relative",
                "amplitudes of the mesh stiffness's first harmonics of the mesh frequency, over its mean",
            ),
            Output("mesh_stiffness_harmonics_phase_rad", "phases of those harmonics"),
            Output("tooth_model", "the tooth model used", ""),
            Output("mesh_stiffness_mean_other_model_N_per_m", "mean mesh stiffness, other tooth model"),
            Output("pair_stiffness_pitch_N_per_m", "one tooth pair at the pitch point"),
            Output("compliance_terms_pitch_m_per_N", "compliance terms at the pitch point"),
            Output("iso_c_prime_N_per_mm_um", "ISO 6336-1 single stiffness c′ (gear pairs)"),
            Output("iso_c_gamma_N_per_mm_um", "ISO 6336-1 mesh stiffness c_γα (gear pairs)"),
            Output("iso_c_gamma_beta_N_per_mm_um", "ISO 6336-1 mesh stiffness c_γβ = 0.85 c_γα (gear pairs)"),
            Output("iso_factors", "ISO factors q′, C_M, C_R, C_B", "1"),
            Output("mesh_stiffness_iso_ratio", "mean mesh stiffness over ISO's c_γα b (gear pairs)", "1"),
            Output(
                "ring_rim_compliance_mean_m_per_N",
                "a ring gear's rim (curved beam between supports): compliance along the line of action, "
                "mean over a span",
            ),
            Output("ring_rim_compliance_max_m_per_N", "the ring rim's largest compliance over a span"),
            Output("mesh_stiffness_mean_rigid_rim_N_per_m", "mean mesh stiffness with the ring's rim rigid"),
            Output("base_radii_m", "base radii of pinion and gear"),
            Output("teeth", "tooth numbers of pinion and gear", ""),
            Output("pair_stiffness_N_per_m", "tooth pair, Hertz counted once (tooth pairs)"),
            Output("pair_stiffness_hertz_twice_N_per_m", "tooth pair, Hertz per tooth"),
            Output("tooth_stiffness_N_per_m", "one tooth of each gear alone, with its Hertz term"),
            Output("formulas", "the tooth model: published or refined (tooth pairs)", ""),
            Output("compliance_terms_m_per_N", "compliance terms of the tooth pair"),
            Output("apex_height_m", "apex height w of each truncated triangle"),
            Output("published_mesh_stiffness_N_per_m", "the published pair stiffness, if given"),
        ),
        examples=(
            "mechdyn gear examples/spur_pair.toml --plots plots",
            "mechdyn gear examples/tooth_pair1_published.toml --json",
        ),
    )
)
