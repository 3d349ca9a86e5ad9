"""The published tooth formulas as printed, the printed pair values, and the small-pinion foundation.

Issue 25, points 7 and 14. The published model (SPEC §4) is written out plainly here, term by term,
and evaluated by hand at the published pair-2 geometry; the Sainsot foundation's extrapolation is
recomputed independently (adaptive quadrature of the generated tooth, Sainsot's table by hand).
"""

from __future__ import annotations

import math
import re
import warnings

import numpy as np
import pytest
from scipy.integrate import IntegrationWarning, quad

from mechdyn.errors import ModelWarning
from mechdyn.gears import SpurGear, TruncatedTooth

E, NU, F_W, PHI = 206e9, 0.3, 0.05, math.radians(20.0)  # steel, 50 mm face, 20° (SPEC §4)
PUBLISHED = {  # SPEC §4, m: h_a, h_b, h_c, t_a, t_b; and the k_c printed for that pair, N/m
    1: ((0.004025, 0.000525, 0.002275, 0.002749, 0.003073), 2.7082e9),
    2: ((0.0046, 0.0006, 0.0026, 0.003146, 0.006144), 3.8805e9),
}


def _printed_terms(ha, hb, hc, ta, tb, E=E, nu=NU, f=F_W, phi=PHI):
    """Eqs. 1–6 of the published model, written plainly (per unit normal force, m/N)."""
    w = (ha * tb - hb * ta) / (tb - ta)  # (1) apex height
    r = (w - hc) / (w - hb)
    c, s = math.cos(phi), math.sin(phi)
    d_bp = (  # (2) bending by F cos φ: the rectangle 0…h_b, then the trapezoid h_b…h_c
        12 * c**2 / (E * f * tb**3) * hb * (hc**2 - hc * hb + hb**2 / 3)
        + 6 * c**2 / (E * f * tb**3) * (w - hb) ** 3 * (r * (4 - r) - 2 * math.log(r) - 3)
    )
    d_bn = (  # (3) bending by F sin φ: its moment F sin φ · t_c/2, t_c = r t_b, on the cantilever
        -6 * s * c / (E * f * tb**2) * (r * hb * (hc - hb / 2) + (hc - hb) ** 2 / 2)
    )
    d_s = 2.4 * (1 + nu) * c**2 / (E * f * tb) * (hb + (w - hb) * math.log(1 / r))  # (4) shear
    d_f = 24 * c**2 * hc**2 / (math.pi * E * f * tb**2)  # (5) foundation
    d_h = 4 * (1 - nu**2) / (math.pi * E * f)  # (6) Hertz, in each tooth
    return {
        "bending_transverse": d_bp,
        "bending_radial": d_bn,
        "shear": d_s,
        "foundation": d_f,
        "hertz": d_h,
    }


def _tooth(n, **kw):
    ha, hb, _, ta, tb = PUBLISHED[n][0]
    return TruncatedTooth(ha, hb, ta, tb, F_W, E, NU, **kw)


# -- point 7: the published formulas as printed -------------------------------------------------


@pytest.mark.parametrize("n", [1, 2])
def test_the_published_terms_are_eqs_1_to_6_as_printed(n):
    (ha, hb, hc, ta, tb), _ = PUBLISHED[n]
    terms = _tooth(n).published_compliances(hc, PHI)
    expected = _printed_terms(ha, hb, hc, ta, tb)
    assert set(terms) == set(expected)
    for k, v in expected.items():
        assert terms[k] == pytest.approx(v, rel=1e-10), k


def test_the_published_terms_by_hand_at_pair_2():
    # pair 2, steel, 20°, 50 mm, by hand: w = (4.6·6.144 − 0.6·3.146)/(6.144 − 3.146) mm = 8.797465 mm,
    # r = (w − 2.6)/(w − 0.6) = 0.756022; E f = 1.03e10 N/m; sin 20° cos 20° = 0.321394
    # (3): −6 · 0.321394/(1.03e10 · 6.144e-3²) · [0.756022 · 0.6 · 2.3 + 2.0²/2] e-6 m²
    #    = −4.95963e-6 · 3.043311e-6 = −1.50937e-11 m/N (the earlier term: −1.8548e-11)
    # (5): 24 · 0.883022 · (2.6/6.144)²/(π · 1.03e10) = 1.17284e-10; (6): 4 · 0.91/(π · 1.03e10) = 1.12490e-10
    terms = _tooth(2).published_compliances(0.0026, PHI)
    assert terms["bending_radial"] == pytest.approx(-1.50937e-11, rel=1e-5)
    assert terms["bending_transverse"] == pytest.approx(2.8683e-11, rel=1e-4)
    assert terms["shear"] == pytest.approx(1.25934e-10, rel=1e-4)
    assert terms["foundation"] == pytest.approx(1.17284e-10, rel=1e-4)
    assert terms["hertz"] == pytest.approx(1.12490e-10, rel=1e-4)


def test_the_printed_values_settle_which_entry_belongs_to_which_pair():
    # k = F/Σδ of one tooth (Hertz in it, as published). One pair-2 tooth is the value printed for
    # pair 1 to 0.013 % (the earlier radial term: 0.93 %); pair 1's own tooth is 0.48 × that value
    # and 0.34 × the value printed for pair 2, so neither printed value belongs to pair 1's data
    k = {n: 1 / sum(_tooth(n).published_compliances(PUBLISHED[n][0][2], PHI).values()) for n in (1, 2)}
    assert k[2] == pytest.approx(PUBLISHED[1][1], rel=5e-4)
    assert k[2] / PUBLISHED[1][1] - 1 == pytest.approx(-1.3e-4, abs=0.5e-4)
    assert k[1] / PUBLISHED[1][1] == pytest.approx(0.4826, abs=1e-3)
    assert k[1] / PUBLISHED[2][1] == pytest.approx(0.3368, abs=1e-3)


# -- point 14: the Sainsot foundation's extrapolation, bounded -----------------------------------

_SAINSOT_BY_HAND = {  # Sainsot, Velex & Duverger (2004), table 1: A … F of X* in h_f and θ_f
    "L": (-5.574e-5, -1.9986e-3, -2.3015e-4, 4.7702e-3, 0.0271, 6.8045),
    "M": (60.111e-5, 28.100e-3, -83.431e-4, -9.9256e-3, 0.1624, 0.9086),
    "P": (-50.952e-5, 185.50e-3, 0.0538e-4, 53.300e-3, 0.2895, 0.9236),
    "Q": (-6.2042e-5, 9.0889e-3, -4.0964e-4, 7.8297e-3, -0.1472, 0.6904),
}


def _sainsot(u, s_f, h_f, theta_f, phi, f):
    x = {
        k: a / theta_f**2 + b * h_f**2 + c * h_f / theta_f + d / theta_f + e * h_f + g
        for k, (a, b, c, d, e, g) in _SAINSOT_BY_HAND.items()
    }
    v = u / s_f
    return (
        math.cos(phi) ** 2
        / (E * f)
        * (x["L"] * v**2 + x["M"] * v + x["P"] * (1 + x["Q"] * math.tan(phi) ** 2))
    )


def _share_by_quadrature(thickness, h0, loads, r_root, r_bore, f, kinks=()):
    """max |δ_f(own) − δ_f(nearest point of 1.4 ≤ h_f ≤ 7, 0.01 ≤ θ_f ≤ 0.12)| / Σδ over the loads, with
    the beam terms by adaptive quadrature from the root section h0 and Sainsot's table by hand."""
    G = E / (2 * (1 + NU))
    s_f = thickness(h0)
    h_f, theta_f = r_root / r_bore, s_f / (2 * r_root)
    edge = (min(max(h_f, 1.4), 7.0), min(max(theta_f, 0.01), 0.12))
    share = 0.0
    for hc, phi in loads:
        c, s, e = math.cos(phi), math.sin(phi), thickness(hc) / 2

        def integral(g, hc=hc):
            with warnings.catch_warnings():  # the generated fillet is interpolated: quad sees kinks
                warnings.simplefilter("ignore", IntegrationWarning)
                pts = [k for k in kinks if h0 < k < hc] or None
                return quad(g, h0, hc, points=pts, limit=500, epsabs=0, epsrel=1e-9)[0]

        beam = integral(
            lambda y, hc=hc, c=c, s=s, e=e: (
                12
                * ((c * (hc - y)) ** 2 + s * s * e * e - 2 * s * c * e * (hc - y))
                / (E * f * thickness(y) ** 3)
                + (s * s / E + 1.2 * c * c / G) / (f * thickness(y))
            )
        )
        own = _sainsot(hc - h0, s_f, h_f, theta_f, phi, f)
        share = max(share, abs(own - _sainsot(hc - h0, s_f, *edge, phi, f)) / (beam + own))
    return share


def _generated_share(g):
    rf = g.root_radius
    low = max(g.involute_start_radius, g.base_radius)
    radii = [low + (g.tip_radius - low) * max(k, 1e-6) / 32 for k in range(33)]
    loads = [(r - rf, g.load_angle(r)) for r in radii]

    def t(y):
        return float(g.generated_thickness_array(np.array([rf + y]))[0])

    return _share_by_quadrature(
        t, 0.0, loads, rf, g.bore_radius, g.face_width, [g.involute_start_radius - rf]
    )


@pytest.mark.parametrize(
    ("z", "x", "h_f"),
    [(14, 0.0, 2.0), (16, 0.0, 1.45), (20, 0.0, 1.75), (20, 0.5, 1.45)],
)
def test_ordinary_pinions_are_within_the_tolerance_and_say_nothing(z, x, h_f):
    # θ_f at the root circle 0.15–0.21 rad (outside the fit's 0.12): the extrapolation carries under
    # 5 % of the tooth's compliance anywhere on the flank (independent quadrature), so no warning
    m = 0.002
    r_root = m * (z / 2 - 1.25 + x)
    g = SpurGear(z, m, 0.02, profile_shift=x, bore_diameter=2 * r_root / h_f, name="pinion")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        tooth = g.profile_tooth()
    assert tooth._foundation_parameters[1] > 0.12  # outside the range: extrapolated
    independent = _generated_share(g)
    assert 0.005 < independent < 0.05
    assert tooth.foundation_extrapolation() == pytest.approx(independent, rel=2e-3)


def _quoted_share(record):
    (w,) = [w for w in record if issubclass(w.category, ModelWarning)]
    found = re.search(r"moves the tooth's compliance by up to ([\d.]+) %", str(w.message))
    assert found, str(w.message)
    return float(found.group(1)) / 100


def test_a_small_shifted_pinion_on_a_thin_rim_warns_with_its_share():
    g = SpurGear(12, 0.002, 0.02, profile_shift=0.5, bore_diameter=2 * 0.0105 / 1.45, name="pinion")
    with pytest.warns(ModelWarning, match=r"range of the Sainsot fit") as record:
        g.profile_tooth()
    independent = _generated_share(g)
    assert independent > 0.05
    assert _quoted_share(record) == pytest.approx(independent, abs=0.0006)  # printed to 0.1 %


def test_a_truncated_tooth_on_a_thin_rim_warns_with_its_share():
    # the published pair-2 tooth on a 1.05 rim (h_f below 1.4), loaded at the documented set:
    # 16 heights from the root section to the tip, each at 0°, 10°, 20°, 30° and 40°
    (ha, hb, _, ta, tb), _ = PUBLISHED[2]
    with pytest.warns(ModelWarning, match=r"range of the Sainsot fit") as record:
        tooth = _tooth(2, root_radius=0.02, bore_radius=0.02 / 1.05)

    def t(y):
        return tb + (ta - tb) * (y - hb) / (ha - hb)

    loads = [(hb + (ha - hb) * k / 16, math.radians(a)) for k in range(1, 17) for a in (0, 10, 20, 30, 40)]
    independent = _share_by_quadrature(t, hb, loads, 0.02, 0.02 / 1.05, F_W)
    assert independent > 0.05
    assert _quoted_share(record) == pytest.approx(independent, abs=0.0006)
    assert tooth.foundation_extrapolation() == pytest.approx(independent, rel=1e-6)
    # inside the range nothing rests on extrapolation
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert _tooth(2, root_radius=0.03, bore_radius=0.008).foundation_extrapolation() == 0.0
