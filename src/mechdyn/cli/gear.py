"""``mechdyn gear``: tooth and mesh stiffness of a gear pair, against ISO 6336-1."""

from __future__ import annotations

import argparse
from dataclasses import replace
from typing import Any

from mechdyn.cli.common import AnalysisOutput, Table, add_common_options, run_analysis
from mechdyn.errors import ModelFileError
from mechdyn.gears.iso6336 import iso_stiffness
from mechdyn.gears.schema import GearPairSpec, ToothPairSpec
from mechdyn.gears.tooth import pair_compliance
from mechdyn.io.modelfile import ModelSource

__all__ = ["register"]

TERMS = ("bending_transverse", "bending_radial", "compression", "shear", "foundation")


def _per_width(k: float, face_width: float) -> float:
    """N/m over a face width in m → N/(mm·µm)."""
    return k / face_width * 1e-9


def _terms_table(title: str, rows: dict[str, float]) -> Table:
    total = rows["total"]
    return Table(
        title,
        ["term", "compliance [m/N]", "share [%]"],
        [[k, v, 100 * v / total] for k, v in rows.items()],
    )


def _gear_pair(spec: GearPairSpec) -> AnalysisOutput:
    pair = spec.pair
    p, g = pair.pinion, pair.gear
    b = min(p.face_width, g.face_width)
    cycle = pair.mesh_cycle(spec.points)
    pitch = pair.pair_compliances(pair.pitch_point)
    iso = iso_stiffness(pair, specific_load=spec.specific_load)
    k_pitch = 1.0 / pitch["total"]
    other_model = "involute" if pair.tooth_model == "truncated" else "truncated"
    other = replace(pair, tooth_model=other_model).mesh_cycle(spec.points)
    geometry = Table(
        "gears (radii in mm; truncated-triangle tooth, heights from the root circle, mm)",
        ["", "teeth", "module", "r_base", "r_tip", "r_root", "h_a", "h_b", "t_a", "t_b", "foundation"],
        [
            [
                gear.name,
                gear.teeth,
                gear.module * 1e3,
                gear.base_radius * 1e3,
                gear.tip_radius * 1e3,
                gear.root_radius * 1e3,
                t.tip_height * 1e3,
                t.root_height * 1e3,
                t.tip_thickness * 1e3,
                t.root_thickness * 1e3,
                "elastic (Sainsot)" if t.root_radius is not None else "rigid",
            ]
            for gear, t in zip((p, g), pair.teeth, strict=True)
        ],
    )
    stiffness = Table(
        f"stiffness along the line of action ({pair.tooth_model} tooth model)",
        ["quantity", "value", "unit", "per face width [N/(mm·µm)]"],
        [
            ["contact ratio ε_α", pair.contact_ratio, "", None],
            ["one tooth pair at the pitch point", k_pitch, "N/m", _per_width(k_pitch, b)],
            ["mesh stiffness, mean over a cycle", cycle.mean, "N/m", _per_width(cycle.mean, b)],
            [
                "mesh stiffness, min",
                float(cycle.stiffness.min()),
                "N/m",
                _per_width(float(cycle.stiffness.min()), b),
            ],
            [
                "mesh stiffness, max",
                float(cycle.stiffness.max()),
                "N/m",
                _per_width(float(cycle.stiffness.max()), b),
            ],
            ["fluctuation (max − min)/mean", cycle.fluctuation, "", None],
            [
                f"mesh stiffness, mean ({other_model} tooth model)",
                other.mean,
                "N/m",
                _per_width(other.mean, b),
            ],
            ["ISO 6336-1 single stiffness c′", iso.c_prime * 1e9 * b, "N/m", iso.c_prime],
            ["ISO 6336-1 mesh stiffness c_γα", iso.mesh_stiffness(b), "N/m", iso.c_gamma_alpha],
        ],
    )
    summary = {
        "contact_ratio": pair.contact_ratio,
        "face_width_m": b,
        "mesh_stiffness_mean_N_per_m": cycle.mean,
        "mesh_stiffness_min_N_per_m": float(cycle.stiffness.min()),
        "mesh_stiffness_max_N_per_m": float(cycle.stiffness.max()),
        "mesh_stiffness_fluctuation": cycle.fluctuation,
        "tooth_model": pair.tooth_model,
        "mesh_stiffness_mean_other_model_N_per_m": other.mean,
        "pair_stiffness_pitch_N_per_m": k_pitch,
        "compliance_terms_pitch_m_per_N": pitch,
        "iso_c_prime_N_per_mm_um": iso.c_prime,
        "iso_c_gamma_N_per_mm_um": iso.c_gamma_alpha,
        "iso_factors": {"q_prime": iso.q_prime, "C_M": iso.C_M, "C_R": iso.C_R, "C_B": iso.C_B},
        "base_radii_m": [p.base_radius, g.base_radius],
        "teeth": [p.teeth, g.teeth],
    }
    arrays = {
        "mesh_cycle_position": (cycle.position, "m"),
        "mesh_stiffness": (cycle.stiffness, "N/m"),
        "pairs_in_contact": (cycle.pairs_in_contact, ""),
    }
    tables = [geometry, _terms_table("compliance of one tooth pair at the pitch point", pitch), stiffness]
    return AnalysisOutput(
        "gear",
        {"points": spec.points, "specific_load_N_per_mm": spec.specific_load},
        summary,
        arrays,
        tables,
        {"mesh_stiffness.png": lambda: cycle.plot()},
    )


def _tooth_pair(spec: ToothPairSpec) -> AnalysisOutput:
    t1, t2 = spec.teeth
    loads = ((spec.load_heights[0], spec.load_angle), (spec.load_heights[1], spec.load_angle))
    once = pair_compliance(t1, loads[0], t2, loads[1])
    twice = pair_compliance(t1, loads[0], t2, loads[1], hertz_per_tooth=True)
    terms = {f"pinion_{k}": v for k, v in t1.compliances(*loads[0]).items()}
    terms |= {f"gear_{k}": v for k, v in t2.compliances(*loads[1]).items()}
    terms |= {"hertz": once["hertz"], "total": once["total"]}
    k_once, k_twice = 1.0 / once["total"], 1.0 / twice["total"]
    rows: list[list[Any]] = [
        ["one tooth pair, Hertz once", k_once, "N/m"],
        ["one tooth pair, Hertz per tooth (counted twice)", k_twice, "N/m"],
        ["apex height w, pinion / gear", f"{t1.apex_height * 1e3:.5g} / {t2.apex_height * 1e3:.5g}", "mm"],
    ]
    if spec.published_stiffness is not None:
        rows.append(["published k_c", spec.published_stiffness, "N/m"])
        rows.append(["published / Hertz once", spec.published_stiffness / k_once, ""])
        rows.append(["published / Hertz twice", spec.published_stiffness / k_twice, ""])
    summary = {
        "pair_stiffness_N_per_m": k_once,
        "pair_stiffness_hertz_twice_N_per_m": k_twice,
        "compliance_terms_m_per_N": terms,
        "apex_height_m": [t1.apex_height, t2.apex_height],
        "published_mesh_stiffness_N_per_m": spec.published_stiffness,
        "mesh_stiffness_mean_N_per_m": None,
        "iso_c_prime_N_per_mm_um": None,
        "iso_c_gamma_N_per_mm_um": None,
    }
    tables = [
        _terms_table("compliance of the tooth pair at the load point", terms),
        Table("stiffness along the line of action", ["quantity", "value", "unit"], rows),
    ]
    return AnalysisOutput("gear", {"load_angle_rad": spec.load_angle}, summary, {}, tables, {})


def _gear_command(args: argparse.Namespace) -> int:
    def analyse(model: Any, source: ModelSource) -> AnalysisOutput:
        if isinstance(model, GearPairSpec):
            return _gear_pair(model)
        if isinstance(model, ToothPairSpec):
            return _tooth_pair(model)
        raise ModelFileError(
            source.path,
            "[model] → type",
            f"{source.model_type!r} is not a gear model; "
            'this command needs type = "gear_pair" or "tooth_pair"',
        )

    return run_analysis(args, analyse)


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("gear", help="tooth and mesh stiffness of a gear pair, against ISO 6336-1")
    add_common_options(p)
    p.set_defaults(func=_gear_command)
