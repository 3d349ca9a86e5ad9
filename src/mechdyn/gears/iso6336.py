"""ISO 6336-1 Method B: single stiffness c′ and mesh stiffness c_γα of a spur gear pair.

All from ISO 6336-1:2006, clause 9 "Tooth stiffness parameters c′ and c_γ", Method B (the same
formulas stand in ISO 6336-1:2019). Stiffnesses per unit face width, N/(mm·µm), as the standard
gives them; 1 N/(mm·µm) = 10⁹ N/m per metre of face width.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from mechdyn.checks import check_number
from mechdyn.errors import ModelError
from mechdyn.gears.mesh import GearPair
from mechdyn.units import convert

__all__ = ["MAX_BLANK_RATIO", "MAX_SPECIFIC_LOAD", "IsoStiffness", "iso_stiffness"]

MAX_SPECIFIC_LOAD = 1e6
"""The largest specific load F_t K_A / b accepted, N/mm (ISO 6336's range ends near 10⁴ N/mm)."""
MAX_BLANK_RATIO = 1e4
"""The largest rim-thickness and web-width ratios of a gear blank accepted (ISO 6336 clamps both far
below)."""

# ISO 6336-1, clause 9 (Method B), the coefficients of q′ (its table of C1 … C9)
_C = (0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188, 0.00529, 0.00182)
E_STEEL = 206e9  # Pa, the reference modulus of the standard


@dataclass(frozen=True)
class IsoStiffness:
    """ISO 6336-1 Method B stiffness of a spur pair (per unit face width, N/(mm·µm)).

    Attributes
    ----------
    q_prime : float
        Minimum flexibility of a tooth pair q′, mm·µm/N.
    c_th : float
        Theoretical single stiffness c′_th = 1/q′, N/(mm·µm).
    C_M, C_R, C_B : float
        Theoretical correction factor, gear blank factor, basic rack factor.
    load_factor : float
        (F_t K_A / b / 100)^0.25 below 100 N/mm, else 1.
    material_factor : float
        E / E_st for materials other than steel.
    c_prime : float
        Single stiffness c′, N/(mm·µm).
    c_gamma_alpha : float
        Mesh stiffness c_γα = c′ (0.75 ε_α + 0.25), × 0.9 when ε_α < 1.2, N/(mm·µm).
    notes : tuple of str
        Where the input lies outside the regression's range of validity, and what was taken.
    """

    q_prime: float
    c_th: float
    C_M: float
    C_R: float
    C_B: float
    load_factor: float
    material_factor: float
    c_prime: float
    c_gamma_alpha: float
    notes: tuple[str, ...] = ()

    def mesh_stiffness(self, face_width: float) -> float:
        """c_γα b in N/m for a face width in m.

        Parameters
        ----------
        face_width : float
            Face width b, m, from 1e-9 to 1e3 m.
        """
        b = check_number("ISO 6336", "face_width", face_width, "m", positive=True)
        return convert(self.c_gamma_alpha, "N/(mm*um)", "N/m^2") * b


def iso_stiffness(
    pair: GearPair,
    *,
    specific_load: float = 100.0,
    rim_thickness_ratio: float | None = None,
    web_width_ratio: float = 1.0,
) -> IsoStiffness:
    """Single and mesh stiffness of a spur pair by ISO 6336-1 Method B.

    Parameters
    ----------
    pair : GearPair
    specific_load : float
        F_t K_A / b, N/mm, positive, at most 1e6 N/mm; below 100 N/mm the stiffness falls as
        (load/100)^0.25.
    rim_thickness_ratio : float, optional
        s_R / m_n of a rim-and-web gear, positive, at most 1e4; None takes each gear's own
        ``rim_thickness`` and ``web_width`` (solid gears: C_R = 1).
    web_width_ratio : float
        b_s / b of a webbed gear (0.2 … 1.2; outside, C_R takes the limit), positive, at most 1e4.

    Returns
    -------
    IsoStiffness

    Notes
    -----
    ISO 6336-1:2006, clause 9, Method B:

    - q′ = C1 + C2/z_n1 + C3/z_n2 + C4 x1 + C5 x1/z_n1 + C6 x2 + C7 x2/z_n2 + C8 x1² + C9 x2²
      (minimum flexibility of a tooth pair, mm·µm/N, the regression valid for x1 ≥ x2 and
      −0.5 ≤ x1 + x2 ≤ 2); c′_th = 1/q′;
    - C_M = 0.8, theoretical correction factor (solid disc gears);
    - C_R = 1 + ln(b_s/b) / (5 e^(s_R/(5 m_n))), gear blank factor (1 for solid gears);
    - C_B = [1 + 0.5 (1.2 − h_fP/m_n)] [1 − 0.02 (20° − α_n)], basic rack factor (mean of the two
      gears);
    - c′ = c′_th C_M C_R C_B cos β (× (F_t K_A/b / 100)^0.25 below 100 N/mm, × E/E_st for other
      materials, E = 2 E1 E2/(E1 + E2), E_st = 206 GPa);
    - c_γα = c′ (0.75 ε_α + 0.25), multiplied by 0.9 for ε_α < 1.2 (mesh stiffness).

    Spur gears only here (β = 0, z_n = z).
    """
    specific_load = check_number(
        "ISO 6336", "specific_load", specific_load, "N/mm", positive=True, high=MAX_SPECIFIC_LOAD
    )
    if rim_thickness_ratio is not None:
        rim_thickness_ratio = check_number(
            "ISO 6336", "rim_thickness_ratio", rim_thickness_ratio, positive=True, high=MAX_BLANK_RATIO
        )
    web_width_ratio = check_number(
        "ISO 6336", "web_width_ratio", web_width_ratio, positive=True, high=MAX_BLANK_RATIO
    )
    p, g = pair.pinion, pair.gear
    x1, x2, z1, z2 = p.profile_shift, g.profile_shift, p.teeth, g.teeth
    if not -0.5 <= x1 + x2 <= 2.0:
        raise ModelError(
            f"x1 + x2 = {x1 + x2:g} is outside the range −0.5 … 2 of the ISO 6336-1 regression",
            element=g.name,
            field="profile_shift",
        )
    notes: list[str] = []
    if x1 < x2:
        notes.append(
            f"ISO 6336-1: the pinion's profile shift x1 = {x1:g} is below the gear's x2 = {x2:g}, outside "
            "the range of the regression for q′ (x1 ≥ x2); c′ and c_γα are extrapolated"
        )
    C1, C2, C3, C4, C5, C6, C7, C8, C9 = _C
    q = C1 + C2 / z1 + C3 / z2 + C4 * x1 + C5 * x1 / z1 + C6 * x2 + C7 * x2 / z2 + C8 * x1**2 + C9 * x2**2
    c_th = 1.0 / q
    C_M = 0.8
    blanks = []
    if rim_thickness_ratio is not None:
        blanks.append(("the blank", rim_thickness_ratio, web_width_ratio))
    else:
        for gear in (p, g):
            if gear.rim_thickness is not None and gear.web_width is not None:  # given together
                face = gear.face_width
                blanks.append((gear.name, gear.rim_thickness / gear.module, gear.web_width / face))
    C_R = 1.0
    for name, sr, bs in blanks:
        if not 0.2 <= bs <= 1.2:
            notes.append(f"ISO 6336-1: {name}'s b_s/b = {bs:.3g} is outside 0.2 … 1.2; C_R takes the limit")
        if sr < 1.0:
            notes.append(f"ISO 6336-1: {name}'s s_R/m_n = {sr:.3g} is below 1; C_R takes 1")
        bs_c, sr_c = min(max(bs, 0.2), 1.2), max(sr, 1.0)
        # one C_R per pair in ISO 6336-1; with two webbed blanks the more flexible governs here
        C_R = min(C_R, 1.0 + math.log(bs_c) / (5.0 * math.exp(sr_c / 5.0)))

    def rack(gear):
        return (1.0 + 0.5 * (1.2 - gear.dedendum)) * (1.0 - 0.02 * (20.0 - math.degrees(gear.pressure_angle)))

    C_B = 0.5 * (rack(p) + rack(g))
    load = (specific_load / 100.0) ** 0.25 if specific_load < 100.0 else 1.0
    e = 2 * p.youngs_modulus * g.youngs_modulus / (p.youngs_modulus + g.youngs_modulus)
    mat = e / E_STEEL
    c_prime = c_th * C_M * C_R * C_B * load * mat
    eps = pair.contact_ratio
    c_gamma = c_prime * (0.75 * eps + 0.25) * (0.9 if eps < 1.2 else 1.0)
    return IsoStiffness(q, c_th, C_M, C_R, C_B, load, mat, c_prime, c_gamma, tuple(notes))
