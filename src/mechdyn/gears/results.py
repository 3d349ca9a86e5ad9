"""Gear-pair and tooth-pair stiffness as results of the protocol (what ``mechdyn gear`` reports).

:func:`gear_pair_stiffness` gives the pitch-point pair compliance with its terms, the mesh stiffness
over a mesh cycle (in both tooth models) and ISO 6336-1 Method B's c′ and c_γα beside them;
:func:`tooth_pair_stiffness` gives two published teeth in series, Hertz counted once and twice.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from mechdyn.checks import check_count
from mechdyn.gears.geometry import VALIDATED_HELIX_DEG, SpurGear
from mechdyn.gears.iso6336 import ISO_SHORT_CONTACT, ISO_SHORT_FACTOR, IsoStiffness, iso_stiffness
from mechdyn.gears.mesh import GearPair, MeshCycle
from mechdyn.gears.tooth import TruncatedTooth, pair_compliance
from mechdyn.results import Result, Table
from mechdyn.units import convert, key_label, show

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["GearPairResult", "ToothPairResult", "gear_pair_stiffness", "tooth_pair_stiffness"]

_MODEL_WORDS = {"involute": "generated tooth: fillet and involute", "truncated": "truncated-triangle tooth"}
"""How a table names each tooth model."""

_PER_WIDTH = "N/(mm*um)"

HARMONIC_ORDERS = 6
"""How many harmonics of the mesh frequency a gear-pair result reports."""


def _per_width(k: float, face_width: float) -> float:
    """Stiffness (N/m) over a face width (m), in N/(mm·µm)."""
    return float(convert(k / face_width, "N/m^2", _PER_WIDTH))


def _terms_table(title: str, rows: dict[str, float]) -> Table:
    total = rows["total"]
    return Table(
        title,
        ["term", "compliance [m/N]", "share [%]"],
        [[key_label(k)[0], v, 100 * v / total] for k, v in rows.items()],
    )


def _foundation_words(gear: SpurGear, elastic: bool) -> str:
    """How the geometry table names a gear's foundation."""
    rim = gear.ring_rim()
    if rim is not None:
        return f"rim {show(rim.thickness, 'm', 'mm', '.4g')} on {rim.supports} supports (curved beam)"
    if gear.internal:
        return "rigid rim"
    return "elastic (Sainsot)" if elastic else "rigid"


@dataclass(frozen=True, repr=False)  # the short repr of Result
class GearPairResult(Result):
    """Stiffness of a gear pair along the line of action.

    Attributes
    ----------
    pair : GearPair
    cycle : MeshCycle
        Mesh stiffness over one mesh cycle (the pair's tooth model).
    other : MeshCycle
        The same in the other tooth model (truncated ↔ involute).
    pitch : dict of str → float
        Compliance terms of one tooth pair at the pitch point, m/N.
    iso : IsoStiffness
        ISO 6336-1 Method B single and mesh stiffness.
    specific_load : float
        Load per face width used for ISO's load factor, N/mm.
    orders : int
        Harmonics of the mesh frequency reported (:meth:`MeshCycle.harmonics`), at most half the
        cycle's positions less one.
    """

    pair: GearPair
    cycle: MeshCycle
    other: MeshCycle
    pitch: dict[str, float]
    iso: IsoStiffness
    specific_load: float
    orders: int = HARMONIC_ORDERS

    @property
    def face_width(self) -> float:
        """Common face width, m."""
        return min(self.pair.pinion.face_width, self.pair.gear.face_width)

    @property
    def harmonic_orders(self) -> int:
        """Harmonics reported: ``orders``, fewer for a short cycle."""
        return min(self.orders, len(self.cycle.stiffness) // 2 - 1)

    @property
    def warnings(self) -> tuple[str, ...]:
        """Inputs taken by default (a bore), a ring gear's rim taken as rigid, a helix angle beyond
        what has been compared with ISO (with the ratio to ISO), and ISO 6336-1 inputs outside its
        range of validity."""
        pair = self.pair
        notes = [*pair.pinion.guesses, *pair.gear.guesses]
        if pair.internal and pair.ring_rim is None:
            notes.append(
                f"{pair.gear.name}: no rim_thickness: the ring's rim is taken as rigid (its teeth stand on "
                "a rigid foundation, stiffer than a thin rim between supports); give rim_thickness and "
                "rim_supports"
            )
        beta = math.degrees(pair.helix_angle)
        if beta > VALIDATED_HELIX_DEG * (1 + 1e-12):
            ratio = self.iso_ratio
            words = (
                f"helix angle {beta:.4g}° is above {VALIDATED_HELIX_DEG:g}°, the largest at which the "
                "sliced helical mesh has been compared with ISO 6336-1 (1.11–1.15 × c_γα, generated "
                f"tooth): here the mean mesh stiffness is {ratio:.3f} × ISO's c_γα b"
            )
            if pair.contact_ratio < ISO_SHORT_CONTACT:
                words += (
                    f" ({ISO_SHORT_FACTOR * ratio:.3f} × without ISO's reduction of c_γα by "
                    f"{ISO_SHORT_FACTOR:g} for ε_α = {pair.contact_ratio:.3f} < {ISO_SHORT_CONTACT:g})"
                )
            notes.append(words)
        return (*notes, *self.iso.notes)

    @property
    def iso_ratio(self) -> float:
        """Mean mesh stiffness over ISO 6336-1's c_γα b, dimensionless."""
        return self.cycle.mean / self.iso.mesh_stiffness(self.face_width)

    @property
    def rigid_rim(self) -> MeshCycle | None:
        """The mesh cycle of the same pair with the ring's rim rigid (None without a flexible rim)."""
        if self.pair.ring_rim is None:
            return None
        return self.pair.rigid_rim().mesh_cycle(len(self.cycle.stiffness))

    @property
    def rim_compliance(self) -> tuple[float, float] | None:
        """The ring rim's compliance along the line of action, m/N: its mean over a span between two
        supports and its largest (None without a flexible rim)."""
        rim = self.pair.ring_rim
        if rim is None:
            return None
        load = self.pair.rim_load()
        theta, weight = rim.positions()
        mean = float(np.sum(weight * rim.compliance(theta, *load)))
        largest = float(rim.compliance(np.linspace(0.0, rim.span, 201), *load).max())
        return mean, largest

    @property
    def other_model(self) -> str:
        return "involute" if self.pair.tooth_model == "truncated" else "truncated"

    def summary(self) -> dict[str, Any]:
        """Contact ratios, mesh stiffness (mean, min, max, fluctuation, harmonics), pitch-point pair
        stiffness and its compliance terms, ISO c′, c_γα and c_γβ with their factors, the mean over
        ISO's c_γα b, and a ring gear's rim (its compliance, the mesh with the rim rigid)."""
        p, g, iso, cycle = self.pair.pinion, self.pair.gear, self.iso, self.cycle
        amplitude, phase = cycle.harmonics(self.harmonic_orders)
        rim, rigid = self.rim_compliance, self.rigid_rim
        return {
            "contact_ratio": self.pair.contact_ratio,
            "overlap_ratio": self.pair.overlap_ratio,
            "total_contact_ratio": self.pair.total_contact_ratio,
            "helix_angle_rad": self.pair.helix_angle,
            "internal": self.pair.internal,
            "face_width_m": self.face_width,
            "mesh_stiffness_mean_N_per_m": cycle.mean,
            "mesh_stiffness_min_N_per_m": float(cycle.stiffness.min()),
            "mesh_stiffness_max_N_per_m": float(cycle.stiffness.max()),
            "mesh_stiffness_fluctuation": cycle.fluctuation,
            "mesh_stiffness_harmonics_relative": [float(a) for a in amplitude],
            "mesh_stiffness_harmonics_phase_rad": [float(f) for f in phase],
            "tooth_model": self.pair.tooth_model,
            "mesh_stiffness_mean_other_model_N_per_m": self.other.mean,
            "pair_stiffness_pitch_N_per_m": 1.0 / self.pitch["total"],
            "compliance_terms_pitch_m_per_N": self.pitch,
            "iso_c_prime_N_per_mm_um": iso.c_prime,
            "iso_c_gamma_N_per_mm_um": iso.c_gamma_alpha,
            "iso_c_gamma_beta_N_per_mm_um": iso.c_gamma_beta,
            "iso_factors": {"q_prime": iso.q_prime, "C_M": iso.C_M, "C_R": iso.C_R, "C_B": iso.C_B},
            "mesh_stiffness_iso_ratio": self.iso_ratio,
            "ring_rim_compliance_mean_m_per_N": None if rim is None else rim[0],
            "ring_rim_compliance_max_m_per_N": None if rim is None else rim[1],
            "mesh_stiffness_mean_rigid_rim_N_per_m": None if rigid is None else rigid.mean,
            "base_radii_m": [p.base_radius, g.base_radius],
            "teeth": [p.teeth, g.teeth],
        }

    def to_frame(self) -> pd.DataFrame:
        """The mesh cycle: position along the line of action (m), stiffness (N/m), pairs in contact."""
        return self.cycle.to_frame()

    def arrays(self) -> dict[str, tuple[np.ndarray, str]]:
        c = self.cycle
        return {
            "mesh_cycle_position": (c.position, "m"),
            "mesh_stiffness": (c.stiffness, "N/m"),
            "pairs_in_contact": (c.pairs_in_contact, ""),
        }

    def tables(self, **display_units: str) -> list[Table]:
        """The gears' geometry, the pitch-point compliance terms, the stiffness against ISO.

        ``length_unit`` (default ``"mm"``) shows radii and tooth dimensions.
        """
        lu = display_units.get("length_unit", "mm")
        pair, b, cycle, iso = self.pair, self.face_width, self.cycle, self.iso

        def L(v: float) -> float:
            return float(convert(v, "m", lu))

        geometry = Table(
            f"gears (radii in {lu}; r_form: where the fillet meets the involute; truncated-triangle "
            f"tooth h_a … t_b, heights from the root circle, {lu})",
            [
                "",
                "teeth",
                "module",
                "r_base",
                "r_tip",
                "r_root",
                "r_form",
                "h_a",
                "h_b",
                "t_a",
                "t_b",
                "foundation",
            ],
            [
                [
                    gear.name,
                    gear.teeth,
                    L(gear.module),
                    L(gear.base_radius),
                    L(gear.tip_radius),
                    L(gear.root_radius),
                    L(gear.involute_start_radius),
                    L(t.tip_height),
                    L(t.root_height),
                    L(t.tip_thickness),
                    L(t.root_thickness),
                    _foundation_words(gear, t.root_radius is not None),
                ]
                # the truncated-triangle dimensions, whichever tooth model computes the stiffness
                for gear, t in ((g, g.tooth()) for g in (pair.pinion, pair.gear))
            ],
        )
        k_pitch = 1.0 / self.pitch["total"]
        kmin, kmax = float(cycle.stiffness.min()), float(cycle.stiffness.max())
        ratios: list[list[Any]] = [["contact ratio ε_α", pair.contact_ratio, "", None]]
        if pair.helix_angle:
            ratios += [
                ["overlap ratio ε_β", pair.overlap_ratio, "", None],
                ["total contact ratio ε_γ", pair.total_contact_ratio, "", None],
            ]
        kind = "internal pair, " if pair.internal else ""
        rim, rigid = self.rim_compliance, self.rigid_rim
        rim_rows: list[list[Any]] = []
        if rim is not None and rigid is not None:
            rim_rows = [
                ["ring rim: compliance, mean over a span between supports", rim[0], "m/N", None],
                ["ring rim: compliance, largest", rim[1], "m/N", None],
                ["mesh stiffness, mean, ring rim rigid", rigid.mean, "N/m", _per_width(rigid.mean, b)],
            ]
        stiffness = Table(
            f"stiffness along the {'transverse ' if pair.helix_angle else ''}line of action "
            f"({kind}{_MODEL_WORDS[pair.tooth_model]})",
            ["quantity", "value", "unit", "per face width [N/(mm·µm)]"],
            [
                *ratios,
                ["one tooth pair at the pitch point", k_pitch, "N/m", _per_width(k_pitch, b)],
                ["mesh stiffness, mean over a cycle", cycle.mean, "N/m", _per_width(cycle.mean, b)],
                *rim_rows,
                ["mesh stiffness, min", kmin, "N/m", _per_width(kmin, b)],
                ["mesh stiffness, max", kmax, "N/m", _per_width(kmax, b)],
                ["fluctuation (max − min)/mean", cycle.fluctuation, "", None],
                [
                    f"mesh stiffness, mean ({_MODEL_WORDS[self.other_model]})",
                    self.other.mean,
                    "N/m",
                    _per_width(self.other.mean, b),
                ],
                [
                    "ISO 6336-1 single stiffness c′",
                    float(convert(iso.c_prime, _PER_WIDTH, "N/m^2")) * b,
                    "N/m",
                    iso.c_prime,
                ],
                ["ISO 6336-1 mesh stiffness c_γα", iso.mesh_stiffness(b), "N/m", iso.c_gamma_alpha],
                ["mean mesh stiffness / ISO c_γα b", self.iso_ratio, "", None],
                [
                    "ISO 6336-1 mesh stiffness c_γβ (face load)",
                    float(convert(iso.c_gamma_beta, _PER_WIDTH, "N/m^2")) * b,
                    "N/m",
                    iso.c_gamma_beta,
                ],
            ],
        )
        amplitude, phase = cycle.harmonics(self.harmonic_orders)
        harmonics = Table(
            "harmonics of the mesh stiffness, k(τ) = k̄ [1 + Σ a_n cos(2π n τ + φ_n)], τ in mesh cycles",
            ["order n", "amplitude a_n [%]", "phase φ_n [deg]"],
            [
                [n, 100.0 * float(a), float(np.degrees(f))]
                for n, a, f in zip(range(1, len(amplitude) + 1), amplitude, phase, strict=True)
            ],
        )
        return [
            geometry,
            _terms_table("compliance of one tooth pair at the pitch point", self.pitch),
            stiffness,
            harmonics,
        ]

    def plots(self, **display_units: str) -> dict[str, Any]:
        """``mesh_stiffness.png``: the mesh stiffness over one mesh cycle;
        ``mesh_stiffness_harmonics.png``: its harmonics, bar chart."""
        return {
            "mesh_stiffness.png": lambda: self.cycle.plot(),
            "mesh_stiffness_harmonics.png": lambda: self.cycle.plot_harmonics(orders=self.harmonic_orders),
        }


def gear_pair_stiffness(
    pair: GearPair, points: int = 400, specific_load: float = 100.0, orders: int = HARMONIC_ORDERS
) -> GearPairResult:
    """Mesh stiffness of a gear pair over a mesh cycle, with ISO 6336-1 Method B beside it.

    Parameters
    ----------
    pair : GearPair
    points : int
        Positions along one mesh cycle.
    specific_load : float
        Load per face width for ISO's load factor, N/mm (ISO 6336-1:2019, 9.3.1).
    orders : int
        Harmonics of the mesh frequency in the summary, the tables and the bar chart, a whole number
        from 1 to 1000 (fewer where the cycle has too few positions).

    Returns
    -------
    GearPairResult
    """
    other: Literal["truncated", "involute"] = "involute" if pair.tooth_model == "truncated" else "truncated"
    return GearPairResult(
        pair,
        pair.mesh_cycle(points),
        replace(pair, tooth_model=other).mesh_cycle(points),
        pair.pair_compliances(pair.pitch_point),
        iso_stiffness(pair, specific_load=specific_load),
        specific_load,
        check_count(pair.pinion.name, "orders", orders, low=1, high=1000, what="harmonics"),
    )


@dataclass(frozen=True, repr=False)  # the short repr of Result
class ToothPairResult(Result):
    """Two truncated-triangle teeth in series at their load points.

    Attributes
    ----------
    teeth : (TruncatedTooth, TruncatedTooth)
    load_heights : (float, float)
        Load heights above each root, m.
    load_angle : float
        Pressure angle of the load, rad.
    published_stiffness : float, optional
        The published pair stiffness to compare with, N/m.
    formulas : {"published", "refined"}
        ``"published"``: the published tooth model term by term
        (:meth:`~mechdyn.gears.TruncatedTooth.published_compliances`: the whole tooth from the root,
        the published foundation term); ``"refined"``: bending and shear from the root section h_b
        up, axial compression, the foundation of Sainsot et al. (2004) where root and bore radii are
        given (:meth:`~mechdyn.gears.TruncatedTooth.compliances`).
    """

    teeth: tuple[TruncatedTooth, TruncatedTooth]
    load_heights: tuple[float, float]
    load_angle: float
    published_stiffness: float | None = None
    formulas: str = "published"

    @property
    def _loads(self) -> tuple[tuple[float, float], tuple[float, float]]:
        return ((self.load_heights[0], self.load_angle), (self.load_heights[1], self.load_angle))

    def _tooth_terms(self, i: int) -> dict[str, float]:
        """The terms of tooth ``i`` without any Hertz term, m/N, by the chosen formulas."""
        tooth, load = self.teeth[i], self._loads[i]
        if self.formulas == "published":
            terms = tooth.published_compliances(*load)
            del terms["hertz"]
            return terms
        return tooth.compliances(*load)

    @property
    def compliance_terms(self) -> dict[str, float]:
        """Every term of both teeth and the one Hertz term, m/N, and their total."""
        t1, t2 = self.teeth
        hertz = pair_compliance(t1, self._loads[0], t2, self._loads[1])["hertz"]
        terms = {f"pinion_{k}": v for k, v in self._tooth_terms(0).items()}
        terms |= {f"gear_{k}": v for k, v in self._tooth_terms(1).items()}
        return terms | {"hertz": hertz, "total": sum(terms.values()) + hertz}

    @property
    def stiffness(self) -> float:
        """Pair stiffness with Hertz counted once, N/m."""
        return 1.0 / self.compliance_terms["total"]

    @property
    def stiffness_hertz_twice(self) -> float:
        """Pair stiffness with a Hertz term per tooth (as the published formulas count it), N/m."""
        return 1.0 / (self.compliance_terms["total"] + self.compliance_terms["hertz"])

    @property
    def tooth_stiffness(self) -> tuple[float, float]:
        """One tooth of each gear alone, with its own Hertz term as the published model counts it,
        N/m (the published formulas' stiffness of one tooth)."""
        h = self.compliance_terms["hertz"]
        return (
            1.0 / (sum(self._tooth_terms(0).values()) + h),
            1.0 / (sum(self._tooth_terms(1).values()) + h),
        )

    def summary(self) -> dict[str, Any]:
        """Pair stiffness (Hertz once and twice), compliance terms, apex heights, published value."""
        t1, t2 = self.teeth
        return {
            "pair_stiffness_N_per_m": self.stiffness,
            "pair_stiffness_hertz_twice_N_per_m": self.stiffness_hertz_twice,
            "tooth_stiffness_N_per_m": list(self.tooth_stiffness),
            "formulas": self.formulas,
            "compliance_terms_m_per_N": self.compliance_terms,
            "apex_height_m": [t1.apex_height, t2.apex_height],
            "published_mesh_stiffness_N_per_m": self.published_stiffness,
            "mesh_stiffness_mean_N_per_m": None,
            "iso_c_prime_N_per_mm_um": None,
            "iso_c_gamma_N_per_mm_um": None,
        }

    def to_frame(self) -> pd.DataFrame:
        """One row per compliance term, m/N."""
        import pandas as pd

        terms = self.compliance_terms
        return pd.DataFrame({"term": list(terms), "compliance_m_per_N": list(terms.values())})

    def tables(self, **display_units: str) -> list[Table]:
        """The compliance terms and the pair stiffness against the published value."""
        lu = display_units.get("length_unit", "mm")
        k1, k2 = self.stiffness, self.stiffness_hertz_twice
        w1, w2 = (float(convert(t.apex_height, "m", lu)) for t in self.teeth)
        s1, s2 = self.tooth_stiffness
        rows: list[list[Any]] = [
            ["one tooth pair, Hertz once", k1, "N/m"],
            ["one tooth pair, Hertz per tooth (counted twice)", k2, "N/m"],
            ["one pinion tooth alone, with its Hertz term", s1, "N/m"],
            ["one gear tooth alone, with its Hertz term", s2, "N/m"],
            ["apex height w, pinion / gear", f"{w1:.5g} / {w2:.5g}", lu],
        ]
        if self.published_stiffness is not None:
            k = self.published_stiffness
            rows += [
                ["published k_c", k, "N/m"],
                ["published / Hertz once", k / k1, ""],
                ["published / Hertz twice", k / k2, ""],
            ]
        return [
            _terms_table(
                f"compliance of the tooth pair at the load point ({self.formulas} formulas)",
                self.compliance_terms,
            ),
            Table("stiffness along the line of action", ["quantity", "value", "unit"], rows),
        ]

    def arrays(self) -> dict[str, tuple[np.ndarray, str]]:
        return {}


def tooth_pair_stiffness(
    teeth: tuple[TruncatedTooth, TruncatedTooth],
    load_heights: tuple[float, float],
    load_angle: float,
    published_stiffness: float | None = None,
    formulas: str = "published",
) -> ToothPairResult:
    """Stiffness of two truncated-triangle teeth in series (see :class:`ToothPairResult`).

    Parameters
    ----------
    teeth : (TruncatedTooth, TruncatedTooth)
    load_heights : (float, float)
        Load height above each tooth's root, m.
    load_angle : float
        Pressure angle of the load, rad.
    published_stiffness : float, optional
        A published pair stiffness to compare with, N/m.
    formulas : {"published", "refined"}
        The tooth model (see :class:`ToothPairResult`).
    """
    if formulas not in ("published", "refined"):
        raise ValueError(f"formulas {formulas!r}: expected 'published' or 'refined'")
    (t1, t2), (h1, h2) = teeth, load_heights  # a pair each, as lists or tuples
    return ToothPairResult((t1, t2), (h1, h2), load_angle, published_stiffness, formulas)
