"""ISO 6336-1 Method B dynamic factor K_v: a case by hand, the ranges and their limits, bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mechdyn.errors import ModelError
from mechdyn.gears import GearPair, SpurGear, iso_dynamic_factor
from mechdyn.gears.iso6336 import dynamic_factor_coefficients

pytestmark = pytest.mark.filterwarnings("ignore:.*range of the Sainsot fit:mechdyn.errors.ModelWarning")


def _pair(beta=0.0, b="20 mm"):
    return GearPair(
        SpurGear(20, "2 mm", b, bore_diameter="20 mm", name="pinion", helix_angle=beta),
        SpurGear(40, "2 mm", b, bore_diameter="40 mm", name="gear", helix_angle=beta),
    )


HAND = {  # examples/spur_pair.toml at 1500 rpm and 50 N·m, f_pb 10 µm, f_fα 8 µm, C_a 2 µm
    "speed": "1500 rpm",
    "torque": "50 N*m",
    "pitch_deviation": "10 um",
    "profile_form_deviation": "8 um",
    "tip_relief": "2 um",
    "inertias": (1e-4, 1.6e-3),  # kg·m²
}


def test_a_case_by_hand():
    # q′ = 0.04723 + 0.15551/20 + 0.25791/40 = 0.06145325 mm·µm/N; c′ = 0.8 × 0.975 / q′ = 12.692575
    # N/(mm·µm); ε_α = 1.635186, c_γα = c′ (0.75 ε_α + 0.25) = 18.739184 N/(mm·µm)
    # F_t = 50 N·m / 20 mm = 2500 N, F_t/b = 125 N/mm (≥ 100: N_S = 0.85, no load correction of c′)
    # J* = J/b = 5e-3 and 0.08 kg·m; r_b1 = 18.793852 mm, r_b2 = 37.587705 mm;
    # m_red = J₁* J₂*/(J₁* r_b2² + J₂* r_b1²) = 11.324743 kg/m (0.011324743 kg/mm)
    # n_E1 = 30000/(π 20) √(18.739184/0.011324743) = 19422.4 min⁻¹, Ω_E1 = 2033.907 rad/s
    # N = (1500 min⁻¹)/n_E1 = 0.0772305 (subcritical)
    # y_p = 0.075 × 10 = 0.75 µm, y_f = 0.075 × 8 = 0.6 µm (hardened)
    # B_p = c′ (10 − 0.75)/125 = 0.939251, B_f = c′ (8 − 0.6)/125 = 0.751400,
    # B_k = abs(1 − c′ × 2/125) = 0.796919
    # K = 0.32 B_p + 0.34 B_f + 0.23 B_k = 0.739328; K_v = 1 + N K = 1.057099
    r = iso_dynamic_factor(_pair(), **HAND)
    assert r.c_prime == pytest.approx(0.78 / 0.06145325, rel=1e-12)
    assert r.c_gamma_alpha == pytest.approx(0.78 / 0.06145325 * (0.75 * 1.6351859635714618 + 0.25), rel=1e-12)
    assert r.line_load == pytest.approx(125e3, rel=1e-12) and r.lower_limit == 0.85
    assert r.reduced_mass == pytest.approx(11.324743, rel=1e-7)
    n_e1 = 30000 / (math.pi * 20) * math.sqrt(r.c_gamma_alpha / (r.reduced_mass / 1000))  # min⁻¹, ISO units
    assert n_e1 == pytest.approx(19422.4, rel=1e-5)
    assert r.resonance_speed == pytest.approx(n_e1 * 2 * math.pi / 60, rel=1e-12)
    assert r.resonance_ratio == pytest.approx(1500 / n_e1, rel=1e-12)
    assert r.resonance_ratio == pytest.approx(0.0772305, rel=1e-6)
    assert (r.B_p, r.B_f, r.B_k) == pytest.approx((0.939251, 0.751400, 0.796919), rel=1e-6)
    assert r.range == "subcritical"
    assert r.K_v == pytest.approx(1.057099, rel=1e-6)
    assert r.K_v == pytest.approx(
        1 + r.resonance_ratio * (0.32 * r.B_p + 0.34 * r.B_f + 0.23 * r.B_k), rel=1e-14
    )
    assert not r.notes


def test_the_ranges_and_their_limits():
    pair = _pair()
    base = iso_dynamic_factor(pair, **HAND)
    cv, bp, bf, bk = base.C_v, base.B_p, base.B_f, base.B_k
    omega = base.resonance_speed
    ratios = np.array([0.0, 1e-9, 0.5, 0.8, 1.0, 1.1, 1.3, 1.6, 3.0])
    hand = {key: value for key, value in HAND.items() if key != "speed"}
    r = iso_dynamic_factor(pair, ratios * omega, **hand)
    assert r.range == (
        "subcritical",
        "subcritical",
        "subcritical",
        "subcritical",
        "main resonance",
        "main resonance",
        "intermediate",
        "supercritical",
        "supercritical",
    )
    k = cv[0] * bp + cv[1] * bf + cv[2] * bk
    main = cv[0] * bp + cv[1] * bf + cv[3] * bk + 1
    sup = cv[4] * bp + cv[5] * bf + cv[6]
    np.testing.assert_allclose(r.resonance_ratio, ratios, rtol=1e-12)
    assert r.K_v[0] == 1.0  # at rest: no dynamic load
    assert r.K_v[1] == pytest.approx(1.0, abs=1e-8)  # N → 0: K_v → 1 + N K
    assert r.K_v[2] == pytest.approx(1 + 0.5 * k, rel=1e-12)
    assert r.K_v[4] == pytest.approx(main, rel=1e-12) and r.K_v[5] == pytest.approx(main, rel=1e-12)
    assert r.K_v[6] == pytest.approx(sup + (main - sup) * (1.5 - 1.3) / 0.35, rel=1e-12)
    assert r.K_v[7] == pytest.approx(sup, rel=1e-12) and r.K_v[8] == pytest.approx(sup, rel=1e-12)
    # the intermediate range joins K_v(1.15) and K_v(1.5)
    edges = iso_dynamic_factor(pair, np.array([1.15 + 1e-12, 1.5 - 1e-12]) * omega, **hand)
    np.testing.assert_allclose(edges.K_v, [main, sup], rtol=1e-9)
    assert any("main resonance range should be avoided" in n for n in r.notes)


def test_light_loads_lower_the_main_resonance():
    # F_t K_A/b < 100 N/mm: N_S = 0.5 + 0.35 √(F_t K_A/(100 b)); 10 N·m: 25 N/mm, N_S = 0.675
    r = iso_dynamic_factor(
        _pair(), "1000 rpm", "10 N*m", pitch_deviation="10 um", profile_form_deviation="8 um"
    )
    assert r.lower_limit == pytest.approx(0.5 + 0.35 * math.sqrt(0.25), rel=1e-12)


def test_the_coefficients_of_table_8():
    assert dynamic_factor_coefficients(1.6) == pytest.approx(
        (0.32, 0.34, 0.23, 0.90, 0.47, 0.47, 0.125 * math.sin(math.pi * (1.6 - 2)) + 0.875)
    )
    e = 2.4
    assert dynamic_factor_coefficients(e) == pytest.approx(
        (
            0.32,
            0.57 / 2.1,
            0.096 / 0.84,
            (0.57 - 0.12) / 0.96,
            0.47,
            0.12 / 0.66,
            0.125 * math.sin(0.4 * math.pi) + 0.875,
        )
    )
    assert dynamic_factor_coefficients(3.0)[6] == 1.0 and dynamic_factor_coefficients(1.2)[6] == 0.75
    with pytest.raises(ModelError, match="total_contact_ratio"):
        dynamic_factor_coefficients(1.0)


def test_a_helical_pair_takes_its_total_contact_ratio_and_grade_deviations():
    pair = _pair(math.radians(15), b="40 mm")
    assert pair.total_contact_ratio > 2
    r = iso_dynamic_factor(pair, "3000 rpm", "100 N*m", accuracy_grade=5)
    assert r.C_v == pytest.approx(dynamic_factor_coefficients(pair.total_contact_ratio))
    # ISO 1328-1:1995 grade 5 at the gear (d = 82.822 mm, m_n 2): f_pt = 0.3 (2 + 0.4 √d) + 4,
    # f_fα = 2.5 √2 + 0.17 √d + 0.5, f_pb = f_pt cos α_t; grade 7 doubles them
    d = 2 * pair.gear.pitch_radius * 1000
    f_pt = 0.3 * (2 + 0.4 * math.sqrt(d)) + 4
    assert r.pitch_deviation == pytest.approx(
        f_pt * math.cos(pair.gear.transverse_pressure_angle) * 1e-6, rel=1e-12
    )
    assert r.profile_form_deviation == pytest.approx((2.5 * math.sqrt(2) + 0.17 * math.sqrt(d) + 0.5) * 1e-6)
    seven = iso_dynamic_factor(pair, "3000 rpm", "100 N*m", accuracy_grade=7)
    assert seven.pitch_deviation == pytest.approx(2 * r.pitch_deviation, rel=1e-12)
    assert any("accuracy grade 5" in n for n in r.notes)


def test_an_internal_pair_takes_the_ring_as_fixed_without_inertias():
    pair = GearPair(
        SpurGear(20, "2 mm", "20 mm", bore_diameter="20 mm", name="pinion"),
        SpurGear(80, "2 mm", "20 mm", name="ring", internal=True),
    )
    r = iso_dynamic_factor(pair, "1500 rpm", "50 N*m", accuracy_grade=6)
    p = pair.pinion
    d_m = p.tip_radius + p.root_radius
    m1 = math.pi / 32 * 7830 * (d_m**4 - 0.02**4) / p.base_radius**2
    assert r.reduced_mass == pytest.approx(m1, rel=1e-12)
    assert any("ring taken as fixed" in n for n in r.notes)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"speed": -1.0}, "field 'speed'"),
        ({"speed": np.array([1.0, np.nan])}, "field 'speed'"),
        ({"torque": 0.0}, "field 'torque'"),
        ({"accuracy_grade": None}, r"field 'accuracy_grade'.*give an accuracy_grade"),
        ({"running_in": "soft"}, "field 'running_in'"),
        ({"application_factor": 0.5}, "field 'application_factor'"),
        ({"inertias": (1e-4,)}, "field 'inertias'"),
    ],
)
def test_bad_input_is_refused(kwargs, match):
    args = {"speed": 100.0, "torque": 50.0} | kwargs
    with pytest.raises(ModelError, match=match):
        iso_dynamic_factor(_pair(), **args)
