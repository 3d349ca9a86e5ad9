"""ISO 6336-1 Method B: single stiffness c′ and mesh stiffness c_γ of a gear pair, and the dynamic
factor K_v.

Stiffness from ISO 6336-1:2006, clause 9 "Tooth stiffness parameters c′ and c_γ", Method B (the same
formulas stand in ISO 6336-1:2019). Stiffnesses per unit face width, N/(mm·µm), as the standard
gives them; 1 N/(mm·µm) = 10⁹ N/m per metre of face width. The dynamic factor from ISO 6336-1:2006,
clause 6 "Internal dynamic factor K_v", Method B (6.5; the 2019 edition keeps it):
:func:`iso_dynamic_factor`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from mechdyn.checks import check_number
from mechdyn.errors import ModelError
from mechdyn.gears.mesh import GearPair
from mechdyn.units import convert
from mechdyn.units import si_field as _q

__all__ = [
    "ISO_SHORT_CONTACT",
    "ISO_SHORT_FACTOR",
    "MAX_BLANK_RATIO",
    "MAX_SPECIFIC_LOAD",
    "STEEL_DENSITY",
    "DynamicFactor",
    "IsoStiffness",
    "dynamic_factor_coefficients",
    "iso_dynamic_factor",
    "iso_stiffness",
]

MAX_SPECIFIC_LOAD = 1e6
"""The largest specific load F_t K_A / b accepted, N/mm (ISO 6336's range ends near 10⁴ N/mm)."""
MAX_BLANK_RATIO = 1e4
"""The largest rim-thickness and web-width ratios of a gear blank accepted (ISO 6336 clamps both far
below)."""

ISO_SHORT_CONTACT = 1.2
"""Below this transverse contact ratio ε_α, c_γα is reduced by :data:`ISO_SHORT_FACTOR` (ISO 6336-1,
clause 9, Method B)."""
ISO_SHORT_FACTOR = 0.9
"""The reduction of c_γα for ε_α below :data:`ISO_SHORT_CONTACT`."""

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
    c_gamma_beta : float
        Mesh stiffness c_γβ = 0.85 c_γα for the face load factor, N/(mm·µm) (ISO 6336-1:2006,
        clause 9, Method B; the same for spur gears).
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
    c_gamma_beta: float = 0.0

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
    """Single and mesh stiffness of a spur, helical or internal pair by ISO 6336-1 Method B.

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
    - c_γα = c′ (0.75 ε_α + 0.25), multiplied by 0.9 for ε_α < 1.2 (mesh stiffness);
    - c_γβ = 0.85 c_γα (mesh stiffness for the face load factor K_Hβ).

    Helical gears: q′ takes the virtual numbers of teeth z_n = z / (cos²β_b cos β) (ISO 6336-1 refers
    to ISO 6336-3 for z_n; z/cos³β is its usual approximation), x the normal profile-shift
    coefficients, and c′ the factor cos β above. Internal gears: 1/z_n2 = 0 in q′ (the ring's tooth
    taken as a rack's, as DIN 3990-1 prescribes for internal gears; taken so here where ISO 6336-1
    is not explicit), and a note says so.
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
    x1, x2, z1, z2 = p.profile_shift, g.profile_shift, p.virtual_teeth, g.virtual_teeth
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
    if pair.internal:
        notes.append(
            "ISO 6336-1: internal gear: 1/z_n2 = 0 in q′ (the ring's tooth as a rack's, as DIN 3990-1 "
            "prescribes)"
        )
    C1, C2, C3, C4, C5, C6, C7, C8, C9 = _C
    inv_z2 = 0.0 if pair.internal else 1.0 / z2
    q = (
        C1
        + C2 / z1
        + C3 * inv_z2
        + C4 * x1
        + C5 * x1 / z1
        + C6 * x2
        + C7 * x2 * inv_z2
        + C8 * x1**2
        + C9 * x2**2
    )
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
    if pair.helix_angle:
        c_prime *= math.cos(pair.helix_angle)
    eps = pair.contact_ratio
    c_gamma = c_prime * (0.75 * eps + 0.25) * (ISO_SHORT_FACTOR if eps < ISO_SHORT_CONTACT else 1.0)
    return IsoStiffness(q, c_th, C_M, C_R, C_B, load, mat, c_prime, c_gamma, tuple(notes), 0.85 * c_gamma)


# -- the dynamic factor K_v, ISO 6336-1:2006 clause 6.5 (Method B) ----------------------------------

STEEL_DENSITY = 7830.0
"""ρ of steel, kg/m³, as ISO 6336-1 takes it for the reduced mass (7.83·10⁻⁶ kg/mm³)."""

_RANGES = ("subcritical", "main resonance", "intermediate", "supercritical")


@dataclass(frozen=True)
class DynamicFactor:
    """ISO 6336-1 Method B dynamic factor at one pinion speed or an array of them.

    Attributes
    ----------
    speed : float or ndarray
        Pinion speed Ω₁, rad/s.
    resonance_speed : float
        Ω_E1 = √(c_γα / m_red) / z₁, rad/s: the pinion speed whose mesh frequency z₁ Ω₁ meets the
        natural frequency of the two gears on their mesh (ISO 6336-1:2006, eq. (6), n_E1 =
        30000/(π z₁) √(c_γα/m_red) in min⁻¹ with c_γα in N/(mm·µm) and m_red in kg/mm).
    resonance_ratio : float or ndarray
        N = Ω₁ / Ω_E1 (eq. (9)), dimensionless.
    range : str or tuple of str
        ``subcritical`` (N ≤ N_S), ``main resonance`` (N_S < N ≤ 1.15), ``intermediate``
        (1.15 < N < 1.5) or ``supercritical`` (N ≥ 1.5), per speed.
    K_v : float or ndarray
        The dynamic factor, dimensionless.
    lower_limit : float
        N_S, the lower limit of the main resonance range, dimensionless.
    reduced_mass : float
        m_red, kg/m (mass per unit face width on the line of action).
    line_load : float
        F_t K_A / b, N/m.
    B_p, B_f, B_k : float
        The pitch, profile and tip-relief parameters (eqs. (15)–(17)), dimensionless.
    C_v : tuple of float
        C_v1 … C_v7 (table 8) for the pair's ε_γ.
    c_prime, c_gamma_alpha : float
        ISO single and mesh stiffness taken, N/(mm·µm).
    pitch_deviation, profile_form_deviation, tip_relief : float
        f_pb and f_fα before running-in, and C_a, m.
    notes : tuple of str
        What was taken by default, and the ranges met (ISO: avoid running in the main resonance).
    """

    speed: Any
    resonance_speed: float
    resonance_ratio: Any
    range: Any
    K_v: Any
    lower_limit: float
    reduced_mass: float
    line_load: float
    B_p: float
    B_f: float
    B_k: float
    C_v: tuple[float, ...]
    c_prime: float
    c_gamma_alpha: float
    pitch_deviation: float
    profile_form_deviation: float
    tip_relief: float
    notes: tuple[str, ...] = ()


def dynamic_factor_coefficients(total_contact_ratio: float) -> tuple[float, ...]:
    """C_v1 … C_v7 of ISO 6336-1:2006, table 8, for a total contact ratio ε_γ > 1.

    Parameters
    ----------
    total_contact_ratio : float
        ε_γ = ε_α + ε_β, above 1.

    Returns
    -------
    tuple of float
        (C_v1, …, C_v7), dimensionless.
    """
    e = check_number("ISO 6336", "total_contact_ratio", total_contact_ratio, low=1.0, low_open=True)
    if e <= 2.0:
        c2, c3, c4, c6 = 0.34, 0.23, 0.90, 0.47
    else:
        c2, c3 = 0.57 / (e - 0.3), 0.096 / (e - 1.56)
        c4, c6 = (0.57 - 0.05 * e) / (e - 1.44), 0.12 / (e - 1.74)
    if e <= 1.5:
        c7 = 0.75
    elif e <= 2.5:
        c7 = 0.125 * math.sin(math.pi * (e - 2.0)) + 0.875
    else:
        c7 = 1.0
    return (0.32, c2, c3, c4, 0.47, c6, c7)


def _grade_deviations(pair: GearPair, grade: int) -> tuple[float, float]:
    """f_pb and f_fα of ISO 1328-1:1995 (annex: f_pt = 0.3 (m_n + 0.4 √d) + 4 µm,
    f_fα = 2.5 √m_n + 0.17 √d + 0.5 µm at grade 5, × 2^((Q − 5)/2); m_n, d in mm), f_pb = f_pt cos α_t,
    the larger of the two gears, m. The formulas at the gear's own m_n and d (the standard's tables
    take the geometric means of its size ranges)."""
    worst = (0.0, 0.0)
    for gear in (pair.pinion, pair.gear):
        m = float(convert(gear.module, "m", "mm"))
        d = float(convert(2.0 * gear.pitch_radius, "m", "mm"))
        step = 2.0 ** (0.5 * (grade - 5))
        f_pt = (0.3 * (m + 0.4 * math.sqrt(d)) + 4.0) * step
        f_fa = (2.5 * math.sqrt(m) + 0.17 * math.sqrt(d) + 0.5) * step
        f_pb = f_pt * math.cos(gear.transverse_pressure_angle)
        worst = (max(worst[0], f_pb), max(worst[1], f_fa))
    return float(convert(worst[0], "um", "m")), float(convert(worst[1], "um", "m"))


def _reduced_mass(
    pair: GearPair, inertias: tuple[Any, Any] | None, density: float, notes: list[str]
) -> float:
    """m_red, kg/m: J₁* J₂* / (J₁* r_b2² + J₂* r_b1²) with J* = J/b (ISO 6336-1:2006, eq. (7)); from the
    gear blanks, J* = (π/32) ρ (d_m⁴ − d_i⁴) with d_m = (d_a + d_f)/2 and d_i the bore (eq. (30) and
    its solid-disc form)."""
    p, g, b = pair.pinion, pair.gear, pair.face_width
    if inertias is not None:
        if len(inertias) != 2:
            raise ModelError(
                f"inertias {inertias!r}: give two, the pinion's and the gear's (kg·m²)",
                element="ISO 6336 K_v",
                field="inertias",
            )
        j1, j2 = (
            _q(gear.name, "inertia", j, "kg*m^2", positive=True) / b
            for gear, j in zip((p, g), inertias, strict=True)
        )
        return j1 * j2 / (j1 * g.base_radius**2 + j2 * p.base_radius**2)

    def blank(gear: Any) -> float:
        d_m = gear.tip_radius + gear.root_radius
        d_i = gear.bore_diameter or 0.0
        return math.pi / 32.0 * density * (d_m**4 - d_i**4)

    m1 = blank(p) / p.base_radius**2
    if pair.internal:
        notes.append(
            "ISO 6336-1: internal pair without inertias: the ring taken as fixed (infinitely heavy), "
            "m_red = the pinion's mass on its line of action; give inertias for a turning ring"
        )
        return m1
    notes.append(
        f"ISO 6336-1: m_red from the gear blanks (solid discs of the mean diameter (d_a + d_f)/2 less "
        f"the bore, ρ = {density:g} kg/m³, eq. (30)); give inertias for other blanks"
    )
    m2 = blank(g) / g.base_radius**2
    return m1 * m2 / (m1 + m2)


def iso_dynamic_factor(
    pair: GearPair,
    speed: Any,
    torque: Any,
    *,
    accuracy_grade: int | None = 6,
    pitch_deviation: Any = None,
    profile_form_deviation: Any = None,
    application_factor: float = 1.0,
    inertias: tuple[Any, Any] | None = None,
    density: Any = STEEL_DENSITY,
    tip_relief: Any = None,
    contact_stress_limit: Any = "1500 MPa",
    running_in: str = "hardened",
) -> DynamicFactor:
    """Dynamic factor K_v of a spur or helical pair by ISO 6336-1 Method B.

    Parameters
    ----------
    pair : GearPair
        The pair (spur or helical; an internal pair takes its ring as fixed unless ``inertias`` are
        given).
    speed : float, ndarray or quantity
        Pinion speed Ω₁, rad/s (e.g. ``"1500 rpm"``), not negative; an array gives arrays.
    torque : float or quantity
        Nominal pinion torque T₁, N·m, positive: F_t = T₁ / r₁ at the reference radius.
    accuracy_grade : int, optional
        ISO 1328-1 accuracy grade Q (1 … 12) giving f_pb and f_fα (:func:`_grade_deviations`) where
        they are not given.
    pitch_deviation, profile_form_deviation : float or quantity, optional
        Transverse base pitch deviation f_pb and profile form deviation f_fα, m (e.g. ``"8 um"``).
    application_factor : float
        K_A, at least 1.
    inertias : (float, float) or quantities, optional
        Polar moments of inertia of pinion and gear, kg·m², each with whatever turns with it; by
        default from the gear blanks (:func:`_reduced_mass`).
    density : float or quantity
        ρ of the gear blanks, kg/m³, for the default inertias.
    tip_relief : float or quantity, optional
        C_a, m; by default C_ay, the relief that running-in gives, (1/18)(σ_Hlim/97 − 18.45)² + 1.5 µm
        with σ_Hlim in N/mm² (eq. (18)).
    contact_stress_limit : float or quantity
        σ_Hlim, Pa, for C_ay (1500 MPa: case-hardened steel).
    running_in : {"hardened", "none"}
        Running-in allowances y_p = y_α and y_f: ``hardened`` (case-hardened or nitrided steel,
        0.075 f_pb and 0.075 f_fα, each at most 3 µm: ISO 6336-1:2006's running-in allowance y_α for
        Eh, IF, NT and NV materials, taken for y_f with f_fα as well, as the standard does) or ``none``.

    Returns
    -------
    DynamicFactor

    Notes
    -----
    ISO 6336-1:2006, 6.5 (Method B), equation numbers of that edition:

    - resonance speed n_E1 = 30000/(π z₁) √(c_γα/m_red) (6), here Ω_E1 = √(c_γα/m_red)/z₁ in SI;
      m_red = J₁* J₂*/(J₁* r_b2² + J₂* r_b1²) (7); N = n₁/n_E1 (9);
    - lower limit of the main resonance N_S = 0.5 + 0.35 √(F_t K_A/(100 b)) for F_t K_A/b < 100 N/mm,
      else 0.85 (11), (12);
    - B_p = c′ f_pb,eff/(F_t K_A/b), B_f = c′ f_fα,eff/(F_t K_A/b), B_k = abs(1 − c′ C_a/(F_t K_A/b))
      (15)–(17), f_pb,eff = f_pb − y_p, f_fα,eff = f_fα − y_f;
    - subcritical, N ≤ N_S: K_v = N K + 1, K = C_v1 B_p + C_v2 B_f + C_v3 B_k (13), (14) (K_v → 1 as
      N → 0); main resonance, N_S < N ≤ 1.15: K_v = C_v1 B_p + C_v2 B_f + C_v4 B_k + 1 (20);
      supercritical, N ≥ 1.5: K_v = C_v5 B_p + C_v6 B_f + C_v7 (21); intermediate: linear in N
      between K_v(1.15) and K_v(1.5) (22);
    - C_v1 … C_v7 from table 8 for ε_γ (:func:`dynamic_factor_coefficients`);
    - c′ and c_γα by Method B (:func:`iso_stiffness`) at the line load F_t K_A/b.

    Raises
    ------
    mechdyn.errors.ModelError
        For a negative or non-finite speed, a torque that is not positive, neither an accuracy grade
        nor both deviations, or an unknown ``running_in``.
    """
    name = "ISO 6336 K_v"
    if isinstance(speed, np.ndarray | list | tuple):
        speeds = np.asarray(speed, dtype=float)
    else:
        speeds = np.asarray(_q(name, "speed", speed, "rad/s"), dtype=float)
    if not np.all(np.isfinite(speeds)) or np.any(speeds < 0):
        raise ModelError(
            "the pinion speed must be finite and not negative (rad/s)", element=name, field="speed"
        )
    torque = _q(name, "torque", torque, "N*m", positive=True)
    k_a = check_number(name, "application_factor", application_factor, low=1.0, high=10.0)
    density = _q(name, "density", density, "kg/m^3", positive=True)
    if running_in not in ("hardened", "none"):
        raise ModelError(
            f"running_in {running_in!r} must be 'hardened' or 'none'", element=name, field="running_in"
        )
    notes: list[str] = []
    b = pair.face_width
    line_load = torque / pair.pinion.pitch_radius * k_a / b  # F_t K_A / b, N/m
    iso = iso_stiffness(pair, specific_load=min(float(convert(line_load, "N/m", "N/mm")), MAX_SPECIFIC_LOAD))
    c_prime = float(convert(iso.c_prime, "N/(mm*um)", "N/m^2"))
    c_gamma = float(convert(iso.c_gamma_alpha, "N/(mm*um)", "N/m^2"))
    f_pb = (
        None
        if pitch_deviation is None
        else _q(name, "pitch_deviation", pitch_deviation, "m", nonnegative=True)
    )
    f_fa = (
        None
        if profile_form_deviation is None
        else _q(name, "profile_form_deviation", profile_form_deviation, "m", nonnegative=True)
    )
    if f_pb is None or f_fa is None:
        if accuracy_grade is None:
            raise ModelError(
                "give an accuracy_grade, or both pitch_deviation and profile_form_deviation",
                element=name,
                field="accuracy_grade",
            )
        grade = int(check_number(name, "accuracy_grade", accuracy_grade, low=1, high=12))
        grade_pb, grade_fa = _grade_deviations(pair, grade)
        notes.append(f"f_pb and f_fα from ISO 1328-1:1995 accuracy grade {grade} where not given")
        f_pb = grade_pb if f_pb is None else f_pb
        f_fa = grade_fa if f_fa is None else f_fa
    cap = float(convert(3.0, "um", "m"))
    y_p, y_f = (min(0.075 * f_pb, cap), min(0.075 * f_fa, cap)) if running_in == "hardened" else (0.0, 0.0)
    if tip_relief is None:
        sigma = float(
            convert(
                _q(name, "contact_stress_limit", contact_stress_limit, "Pa", positive=True), "Pa", "N/mm^2"
            )
        )
        c_a = float(convert((sigma / 97.0 - 18.45) ** 2 / 18.0 + 1.5, "um", "m"))
        notes.append(
            f"C_a = C_ay = {convert(c_a, 'm', 'um'):.3g} µm (no tip relief; σ_Hlim {sigma:g} N/mm², eq. (18))"
        )
    else:
        c_a = _q(name, "tip_relief", tip_relief, "m", nonnegative=True)
    B_p = c_prime * (f_pb - y_p) / line_load
    B_f = c_prime * (f_fa - y_f) / line_load
    B_k = abs(1.0 - c_prime * c_a / line_load)
    cv = dynamic_factor_coefficients(pair.total_contact_ratio)
    m_red = _reduced_mass(pair, inertias, density, notes)
    omega_e = math.sqrt(c_gamma / m_red) / pair.pinion.teeth
    limit = float(convert(100.0, "N/mm", "N/m"))
    n_s = 0.5 + 0.35 * math.sqrt(line_load / limit) if line_load < limit else 0.85
    ratio = speeds / omega_e
    sub = ratio * (cv[0] * B_p + cv[1] * B_f + cv[2] * B_k) + 1.0
    main = cv[0] * B_p + cv[1] * B_f + cv[3] * B_k + 1.0
    sup = cv[4] * B_p + cv[5] * B_f + cv[6]
    between = sup + (main - sup) * (1.5 - ratio) / 0.35
    k_v = np.where(ratio <= n_s, sub, np.where(ratio <= 1.15, main, np.where(ratio < 1.5, between, sup)))
    which = np.where(ratio <= n_s, 0, np.where(ratio <= 1.15, 1, np.where(ratio < 1.5, 2, 3)))
    ranges = tuple(_RANGES[i] for i in np.atleast_1d(which))
    if "main resonance" in ranges:
        notes.append("ISO 6336-1, 6.5.5: running in the main resonance range should be avoided")
    scalar = speeds.ndim == 0
    return DynamicFactor(
        speed=float(speeds) if scalar else speeds,
        resonance_speed=omega_e,
        resonance_ratio=float(ratio) if scalar else ratio,
        range=ranges[0] if scalar else ranges,
        K_v=float(k_v) if scalar else k_v,
        lower_limit=n_s,
        reduced_mass=m_red,
        line_load=line_load,
        B_p=B_p,
        B_f=B_f,
        B_k=B_k,
        C_v=cv,
        c_prime=iso.c_prime,
        c_gamma_alpha=iso.c_gamma_alpha,
        pitch_deviation=f_pb,
        profile_form_deviation=f_fa,
        tip_relief=c_a,
        notes=tuple(notes),
    )
