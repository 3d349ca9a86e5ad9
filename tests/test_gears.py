"""Gear tooth and mesh stiffness: every term, the geometry, ISO 6336-1, the published data, limits."""

from __future__ import annotations

import dataclasses
import itertools
import json
import math
import re
import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import IntegrationWarning, quad

from conftest import EXAMPLES
from mechdyn.errors import ModelError, ModelWarning
from mechdyn.gears import GearPair, SpurGear, TruncatedTooth, hertz_compliance, iso_stiffness, pair_compliance

E, NU = 206e9, 0.3
PUBLISHED = {  # SPEC §4, m: h_a, h_b, h_c, t_a, t_b, printed k_c (N/m)
    1: (0.004025, 0.000525, 0.002275, 0.002749, 0.003073, 2.7082e9),
    2: (0.0046, 0.0006, 0.0026, 0.003146, 0.006144, 3.8805e9),
}

# a pinion of fewer than about 25 teeth has its root-circle half-angle θ_f above the range of the
# Sainsot fit; it says so only where the extrapolation carries more than 5 % of the tooth's
# compliance (tests/test_gears_published.py); the other tests here check numbers, not that warning
pytestmark = pytest.mark.filterwarnings("ignore:.*range of the Sainsot fit:mechdyn.errors.ModelWarning")


def _tooth(n=2, f=0.05, **kw):
    ha, hb, _, ta, tb, _ = PUBLISHED[n]
    return TruncatedTooth(ha, hb, ta, tb, f, E, NU, **kw)


@pytest.mark.parametrize("n", [1, 2])
@pytest.mark.parametrize("phi_deg", [-8.0, 0.0, 14.0, 20.0, 30.0])
@pytest.mark.parametrize("hc_frac", [0.2, 0.5, 1.0])
@pytest.mark.parametrize("segment", [False, True])
def test_every_term_equals_the_castigliano_integral(n, phi_deg, hc_frac, segment):
    # the closed forms against numerical quadrature of the strain-energy integrals; with the root
    # segment (a gear's whole tooth), from height 0 with the root thickness t_b up to h_b
    t = _tooth(n, root_segment=segment)
    hc = t.root_height + hc_frac * (t.tip_height - t.root_height)
    phi = math.radians(phi_deg)
    c = t.compliances(hc, phi)
    f, G = t.face_width, t.shear_modulus

    def thickness(y):
        return t.root_thickness if y < t.root_height else t.thickness(y)

    inertia = lambda y: f * thickness(y) ** 3 / 12  # noqa: E731
    area = lambda y: f * thickness(y)  # noqa: E731
    e = t.thickness(hc) / 2
    cos, sin = math.cos(phi), math.sin(phi)
    start = 0.0 if segment else t.root_height

    def integral(fn):
        return quad(
            fn, start, hc, points=[t.root_height] if segment else None, epsabs=0, epsrel=1e-12, limit=200
        )[0]

    assert c["bending_transverse"] == pytest.approx(
        integral(lambda y: cos**2 * (hc - y) ** 2 / (E * inertia(y))), rel=1e-10
    )
    bending = integral(lambda y: (cos * (hc - y) - sin * e) ** 2 / (E * inertia(y)))
    assert c["bending_transverse"] + c["bending_radial"] == pytest.approx(bending, rel=1e-10)
    assert c["compression"] == pytest.approx(integral(lambda y: sin**2 / (E * area(y))), rel=1e-10, abs=1e-30)
    assert c["shear"] == pytest.approx(integral(lambda y: 1.2 * cos**2 / (G * area(y))), rel=1e-10)
    assert c["foundation"] == 0.0  # rigid foundation without root and bore radii


@pytest.mark.parametrize("taper", [1e-3, 1e-7, 1e-12])
def test_uniform_cantilever_limit(taper):
    # t_a → t_b: a rectangular cantilever, δ = 4 F L³/(E f t³) + 1.2 F L/(G f t) for φ = 0; the
    # closed forms must not cancel as the taper vanishes
    t_b, L, f = 0.005, 0.004, 0.02
    t = TruncatedTooth(L, 0.0, t_b * (1 - taper), t_b, f, E, NU)
    c = t.compliances(L, 0.0)
    tol = 2 * taper + 1e-12
    assert c["bending_transverse"] == pytest.approx(4 * L**3 / (E * f * t_b**3), rel=tol)
    assert c["shear"] == pytest.approx(1.2 * L / (E / (2 * (1 + NU)) * f * t_b), rel=tol)
    assert c["bending_radial"] == 0.0 and c["compression"] == 0.0


def test_apex_height():
    ha, hb, _, ta, tb, _ = PUBLISHED[2]
    t = _tooth(2)
    assert t.apex_height == pytest.approx((ha * tb - hb * ta) / (tb - ta))
    # the flanks meet at the apex (thickness() refuses heights at or above it)
    assert t.thickness(t.apex_height * (1 - 1e-12)) == pytest.approx(0.0, abs=1e-14)
    with pytest.raises(ModelError, match="height"):
        t.thickness(t.apex_height)
    assert t.thickness(ha) == pytest.approx(ta) and t.thickness(hb) == pytest.approx(tb)


def test_hertz_term():
    f = 0.02
    assert hertz_compliance(f, E, NU) == pytest.approx(4 * (1 - NU**2) / (math.pi * E * f))
    # two materials: symmetric, and between the two single-material values
    mixed = hertz_compliance(f, E, NU, 110e9, 0.34)
    assert mixed == pytest.approx(hertz_compliance(f, 110e9, 0.34, E, NU))
    assert hertz_compliance(f, E, NU) < mixed < hertz_compliance(f, 110e9, 0.34)


def test_pair_counts_hertz_once():
    t = _tooth(2)
    load = (PUBLISHED[2][2], math.radians(20))
    once = pair_compliance(t, load, t, load)
    twice = pair_compliance(t, load, t, load, hertz_per_tooth=True)
    assert once["total"] == pytest.approx(2 * t.compliance(*load) + hertz_compliance(0.05, E, NU))
    assert twice["total"] - once["total"] == pytest.approx(once["hertz"])


def test_foundation_term_sainsot():
    # Sainsot, Velex & Duverger (2004): evaluated here by hand at one point
    t = _tooth(2, root_radius=0.03, bore_radius=0.008)
    hc, phi = 0.0026, math.radians(20)
    h_f, theta_f = 0.03 / 0.008, 0.006144 / (2 * 0.03)

    def x(a, b, c, d, e, f):
        return a / theta_f**2 + b * h_f**2 + c * h_f / theta_f + d / theta_f + e * h_f + f

    L = x(-5.574e-5, -1.9986e-3, -2.3015e-4, 4.7702e-3, 0.0271, 6.8045)
    M = x(60.111e-5, 28.100e-3, -83.431e-4, -9.9256e-3, 0.1624, 0.9086)
    P = x(-50.952e-5, 185.50e-3, 0.0538e-4, 53.300e-3, 0.2895, 0.9236)
    Q = x(-6.2042e-5, 9.0889e-3, -4.0964e-4, 7.8297e-3, -0.1472, 0.6904)
    u = (hc - 0.0006) / 0.006144
    expected = math.cos(phi) ** 2 / (E * 0.05) * (L * u**2 + M * u + P * (1 + Q * math.tan(phi) ** 2))
    assert t.compliances(hc, phi)["foundation"] == pytest.approx(expected, rel=1e-12)
    with pytest.warns(ModelWarning, match="outside the range of the Sainsot fit"):
        _tooth(2, root_radius=0.02, bore_radius=0.019)


def test_rigid_foundation_and_wide_face_limits():
    flexible = _tooth(2, root_radius=0.03, bore_radius=0.008)
    rigid = _tooth(2)
    load = (0.0026, math.radians(20))
    assert rigid.stiffness(*load) > flexible.stiffness(*load)
    # plane model: every term, Hertz included, scales as 1/f, so stiffness per unit width is constant
    narrow, wide = _tooth(2, f=0.01), _tooth(2, f=1.0)
    assert wide.stiffness(*load) / 1.0 == pytest.approx(narrow.stiffness(*load) / 0.01, rel=1e-12)
    k = [1 / pair_compliance(t, load, t, load)["total"] / t.face_width for t in (narrow, wide)]
    assert k[0] == pytest.approx(k[1], rel=1e-12)


@pytest.mark.parametrize(
    ("kwargs", "field", "message"),
    [
        ({"tip_thickness": 0.007}, "tip_thickness", "must be smaller than the root thickness"),
        ({"tip_thickness": 0.006144}, "tip_thickness", "must be smaller than the root thickness"),
        ({"root_thickness": -0.006}, "root_thickness", "must be positive"),
        ({"tip_height": 0.0005}, "tip_height", "must be above the root height"),
        ({"poisson_ratio": 0.5}, "poisson_ratio", r"must lie in \(−1, 0.5\)"),
        ({"root_radius": 0.02}, "bore_radius", "give both"),
        ({"root_radius": 0.02, "bore_radius": 0.03}, "bore_radius", "below the root radius"),
    ],
)
def test_bad_tooth_data_are_named(kwargs, field, message):
    data = dict(
        tip_height=0.0046,
        root_height=0.0006,
        tip_thickness=0.003146,
        root_thickness=0.006144,
        face_width=0.05,
        youngs_modulus=E,
    )
    data.update(kwargs)
    with pytest.raises(ModelError, match=f"element 'tooth', field '{field}': .*{message}"):
        TruncatedTooth(**data)


@pytest.mark.parametrize(("hc", "message"), [(0.005, "outside the tooth"), (0.0004, "outside the tooth")])
def test_load_point_must_be_on_the_flank(hc, message):
    with pytest.raises(ModelError, match=f"field 'load_height': load height {hc:g} m lies {message}"):
        _tooth(2).compliances(hc, math.radians(20))


# -- geometry and the mesh cycle -------------------------------------------------------------------


def _standard(b=0.02, bores=(0.02, 0.04)):
    return GearPair(
        SpurGear(20, 0.002, b, bore_diameter=bores[0], name="pinion"),
        SpurGear(40, 0.002, b, bore_diameter=bores[1], name="gear"),
    )


def test_involute_geometry():
    g = SpurGear(20, "2 mm", "20 mm", pressure_angle="20 deg")
    assert g.base_radius == pytest.approx(0.02 * math.cos(math.radians(20)))
    assert (g.tip_radius, g.root_radius) == pytest.approx((0.022, 0.0175))
    assert g.thickness(g.pitch_radius) == pytest.approx(math.pi * 0.002 / 2)
    shifted = SpurGear(20, 0.002, 0.02, profile_shift=0.3)
    assert shifted.thickness(shifted.pitch_radius) == pytest.approx(
        0.002 * (math.pi / 2 + 0.6 * math.tan(math.radians(20)))
    )


def test_contact_ratio_against_the_angle_formula():
    # ε_α = [z1 (tan α_a1 − tan α_w) + z2 (tan α_a2 − tan α_w)] / 2π, a second textbook form
    pair = _standard()
    p, g = pair.pinion, pair.gear
    tan_a = [math.tan(math.acos(x.base_radius / x.tip_radius)) for x in (p, g)]
    tw = math.tan(pair.working_pressure_angle)
    eps = (20 * (tan_a[0] - tw) + 40 * (tan_a[1] - tw)) / (2 * math.pi)
    assert pair.contact_ratio == pytest.approx(eps, rel=1e-12)
    cycle = pair.mesh_cycle(2000)
    assert cycle.double_contact_share == pytest.approx(eps - 1, abs=1e-3)
    assert set(np.unique(cycle.pairs_in_contact)) == {1, 2}


def test_mesh_cycle_is_the_sum_of_pair_stiffnesses():
    pair = _standard()
    cycle = pair.mesh_cycle(50)
    s0 = pair.path_start + cycle.position[0]
    assert cycle.stiffness[0] == pytest.approx(
        pair.pair_stiffness(s0) + pair.pair_stiffness(s0 + pair.pinion.base_pitch)
    )
    single = cycle.stiffness[cycle.pairs_in_contact == 1]
    double = cycle.stiffness[cycle.pairs_in_contact == 2]
    assert single.max() < double.min()
    assert single.min() < cycle.mean < double.max()


def test_standard_steel_pair_lands_near_iso():
    # SPEC §4: ISO 6336-1 c′ of a standard steel spur pair is about 12–14 N/(mm·µm) and a pair of
    # teeth in series with one Hertz term should land near it. ISO Method B is a regression; we
    # accept 25 % either way, and record the figures: the generated tooth (fillet and involute, the
    # default) 14.1 against 12.7 and 20.8 against 18.7; the truncated triangle 10.7 and 15.6.
    pair = _standard()
    iso = iso_stiffness(pair)
    assert 12 <= iso.c_prime <= 14
    for model, expected in (("involute", (14.12, 20.77)), ("truncated", (10.75, 15.57))):
        p = dataclasses.replace(pair, tooth_model=model)
        per_width = p.pair_stiffness(p.pitch_point) / 0.02 * 1e-9
        mean = p.mesh_cycle(400).mean / 0.02 * 1e-9
        assert (per_width, mean) == pytest.approx(expected, abs=0.01), model
        assert 0.75 < per_width / iso.c_prime < 1.25 and 0.75 < mean / iso.c_gamma_alpha < 1.25


def test_iso_method_b_by_hand():
    pair = _standard()
    iso = iso_stiffness(pair)
    q = 0.04723 + 0.15551 / 20 + 0.25791 / 40
    assert iso.q_prime == pytest.approx(q)
    assert iso.C_B == pytest.approx((1 + 0.5 * (1.2 - 1.25)) * 1.0)
    assert iso.c_prime == pytest.approx(0.8 * 0.975 / q)
    assert iso.c_gamma_alpha == pytest.approx(iso.c_prime * (0.75 * pair.contact_ratio + 0.25))
    light = iso_stiffness(pair, specific_load=50.0)
    assert light.c_prime == pytest.approx(iso.c_prime * 0.5**0.25)
    cast = GearPair(SpurGear(20, 0.002, 0.02, youngs_modulus=110e9), SpurGear(40, 0.002, 0.02))
    e = 2 * 110e9 * 206e9 / (316e9)
    assert iso_stiffness(cast).material_factor == pytest.approx(e / 206e9)
    webbed = iso_stiffness(pair, rim_thickness_ratio=3.0, web_width_ratio=0.5)
    assert webbed.C_R == pytest.approx(1 + math.log(0.5) / (5 * math.exp(3.0 / 5)))


def test_published_tooth_data_and_the_printed_stiffness():
    # SPEC §4: the printed k_c cannot all be reproduced from the tooth table. With steel, 20° and a
    # 50 mm face, both printed values are 1.28–1.32 × the pair stiffness with Hertz counted once,
    # and 1.62–1.71 × with Hertz counted per tooth. Pair 2 at 50 mm (3.04e9 once, 2.26e9 twice)
    # brackets the value printed for pair 1 (2.71e9), as the SPEC notes.
    result = {}
    for n, (_, _, hc, _, _, printed) in PUBLISHED.items():
        t = _tooth(n)
        load = (hc, math.radians(20))
        once = 1 / pair_compliance(t, load, t, load)["total"]
        twice = 1 / pair_compliance(t, load, t, load, hertz_per_tooth=True)["total"]
        result[n] = (once, twice, printed / once, printed / twice)
    assert result[1][2] == pytest.approx(1.3189, abs=1e-3) and result[2][2] == pytest.approx(1.2784, abs=1e-3)
    assert result[1][3] == pytest.approx(1.6235, abs=1e-3) and result[2][3] == pytest.approx(1.7149, abs=1e-3)
    assert result[2][1] < PUBLISHED[1][5] < result[2][0]


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (lambda: SpurGear(20, 0.002, 0.02, profile_shift=2.0), "pointed"),
        (lambda: GearPair(SpurGear(20, 0.002, 0.02), SpurGear(40, 0.0025, 0.02)), "share module"),
        (
            lambda: GearPair(SpurGear(8, 0.002, 0.02, name="pinion"), SpurGear(60, 0.002, 0.02)),
            "interference",
        ),
        (
            lambda: GearPair(SpurGear(20, 0.002, 0.02), SpurGear(40, 0.002, 0.02), center_distance=0.07),
            "does not let the gears mesh",
        ),
        (lambda: SpurGear(20, 0.002, 0.02, bore_diameter=0.05), "bore diameter"),
        (lambda: SpurGear(20, 0.002, 0.02, pressure_angle="50 deg"), "between 10° and 35°"),
    ],
)
def test_bad_gear_data_are_named(make, message):
    with pytest.raises(ModelError, match=message):
        make()


# -- into the drivetrain ---------------------------------------------------------------------------


def test_mesh_from_a_gear_pair():
    from mechdyn.drivetrain import Disk, Drivetrain, GearMesh, modal

    pair = _standard()
    mesh = GearMesh.from_gear_pair("m", ("p", "g"), pair)
    assert mesh.teeth == (20, 40) and mesh.speed_ratio == 2.0
    assert mesh.base_radii == pytest.approx((pair.pinion.base_radius, pair.gear.base_radius))
    assert mesh.stiffness == pytest.approx(pair.mesh_cycle(400).mean)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # teeth and base radii agree: no ratio warning
        dt = Drivetrain([Disk("p", 1e-4), Disk("g", 1e-3)], [mesh])
    ra, rb = mesh.base_radii
    assert modal(dt).omega[0] == pytest.approx(math.sqrt(mesh.stiffness * (ra**2 / 1e-4 + rb**2 / 1e-3)))


# -- the potential-energy alternative over the involute ------------------------------------------


@pytest.mark.parametrize("n", [1, 2])
def test_profile_tooth_with_a_straight_taper_equals_the_closed_forms(n):
    from mechdyn.gears.profile import ProfileTooth

    t = _tooth(n, root_radius=0.03, bore_radius=0.008)
    p = ProfileTooth(
        lambda y: t.taper * (t.apex_height - np.asarray(y)),
        t.root_height,
        t.tip_height,
        t.face_width,
        E,
        NU,
        0.03,
        0.008,
    )
    for hc in (t.root_height + 1e-4, PUBLISHED[n][2], t.tip_height):
        a, b = t.compliances(hc, math.radians(17)), p.compliances(hc, math.radians(17))
        for k in a:
            assert b[k] == pytest.approx(a[k], rel=1e-9, abs=1e-22), k


def test_the_generated_tooth_matches_the_scalar_geometry_and_is_stiffer_than_the_triangle():
    g = SpurGear(20, 0.002, 0.02)
    r = np.linspace(g.form_radius, g.tip_radius, 7)
    np.testing.assert_allclose(g.chordal_thickness_array(r), [g.chordal_thickness(x) for x in r], rtol=1e-13)
    pair = _standard()
    assert pair.tooth_model == "involute"  # the default
    truncated = dataclasses.replace(pair, tooth_model="truncated")
    ratio = pair.mesh_cycle(200).mean / truncated.mesh_cycle(200).mean
    # the generated tooth is fuller than the straight taper and its fillet widens to the root
    assert ratio == pytest.approx(1.334, abs=0.005)
    with pytest.raises(ModelError, match="tooth model 'fem'"):
        dataclasses.replace(pair, tooth_model="fem")


def test_single_tooth_loaded_at_a_radius():
    g = SpurGear(20, 0.002, 0.02)
    r = g.pitch_radius
    direct = g.tooth().compliances(r - g.root_radius, g.load_angle(r))
    assert g.tooth_compliances("20 mm") == direct
    # the load angle at the pitch point is α − γ_p, with γ_p = (π/2)/z for a standard tooth
    assert g.load_angle(r) == pytest.approx(math.radians(20) - math.pi / 2 / 20)
    # higher on the flank, the tooth is softer
    assert sum(g.tooth_compliances(0.0215).values()) > sum(direct.values())
    with pytest.raises(ModelError, match="field 'load_radius': load radius 23 mm is off the flank"):
        g.tooth_compliances("23 mm")


def test_iso_validity_is_checked_and_rim_and_web_come_from_a_file(tmp_path):
    # ISO 6336-1's q′ regression holds for x1 ≥ x2: outside it the result says so; a rim-and-web
    # blank given in the file (m 2 mm, b 20 mm: s_R/m_n = 3, b_s/b = 0.4) sets
    # C_R = 1 + ln(b_s/b) / (5 e^(s_R/(5 m_n)))
    import mechdyn
    from mechdyn.registry import get

    text = (EXAMPLES / "spur_pair.toml").read_text()
    path = tmp_path / "pair.toml"
    path.write_text(text.replace("[gear]", '[gear]\nrim_thickness = "6 mm"\nweb_width = "8 mm"', 1))
    r = get("gear").run(mechdyn.load(path))
    assert r.iso.C_R == pytest.approx(1 + math.log(0.4) / (5 * math.exp(3 / 5)), rel=1e-12)
    plain = get("gear").run(mechdyn.load(EXAMPLES / "spur_pair.toml"))
    assert r.iso.c_prime == pytest.approx(plain.iso.c_prime * r.iso.C_R, rel=1e-12) and not r.warnings
    path.write_text(text.replace("[pinion]", "[pinion]\nprofile_shift = -0.2", 1))
    shifted = get("gear").run(mechdyn.load(path))
    assert any("x1 = -0.2 is below the gear's x2 = 0" in w for w in shifted.warnings)
    with pytest.raises(mechdyn.ModelFileError, match="give both rim_thickness and web_width"):
        path.write_text(text.replace("[gear]", '[gear]\nrim_thickness = "6 mm"', 1))
        mechdyn.load(path)


def test_without_a_bore_the_foundation_is_not_rigid_and_the_guess_is_said():
    # a standard pair (m 2, z 20/40, b 20 mm) with no bores was 2.6× stiffer than with them (a rigid
    # foundation, silently); now it takes half the root diameter, close to the bored pair and ISO
    from dataclasses import replace

    import mechdyn
    from mechdyn.gears.results import gear_pair_stiffness

    pair = mechdyn.load(EXAMPLES / "spur_pair.toml").model
    bored = gear_pair_stiffness(pair)
    solid = gear_pair_stiffness(
        replace(
            pair, pinion=replace(pair.pinion, bore_diameter=None), gear=replace(pair.gear, bore_diameter=None)
        )
    )
    iso = bored.iso.c_gamma_alpha  # N/(mm·µm)
    per_face = solid.cycle.mean / bored.face_width / 1e9
    assert per_face == pytest.approx(bored.cycle.mean / bored.face_width / 1e9, rel=0.05)
    assert 0.75 < per_face / iso < 1.25
    assert len(solid.warnings) == 2 and all("no bore_diameter" in w for w in solid.warnings)
    assert not bored.warnings


def test_the_gear_command_runs_with_the_involute_tooth_model(tmp_path, capsys):
    """The geometry table shows the truncated-triangle dimensions whichever model computes the
    stiffness (it raised AttributeError with ``tooth_model = "involute"``, found by the type checker)."""
    from mechdyn.cli.main import main

    path = tmp_path / "involute.toml"
    path.write_text(
        '[model]\ntype = "gear_pair"\n[pinion]\nteeth = 20\nmodule = "2 mm"\nface_width = "20 mm"\n'
        '[gear]\nteeth = 40\nmodule = "2 mm"\nface_width = "20 mm"\n[mesh]\ntooth_model = "involute"\n'
    )
    assert main(["gear", str(path), "--db", str(tmp_path / "r.db")]) == 0
    out = capsys.readouterr().out
    assert "truncated-triangle tooth" in out and "mesh stiffness" in out


# -- the published tooth model (SPEC §4), term by term -------------------------------------------

PUBLISHED_PAIRS = {  # h_a, h_b, h_c, t_a, t_b (m), SPEC §4
    1: (0.004025, 0.000525, 0.002275, 0.002749, 0.003073),
    2: (0.0046, 0.0006, 0.0026, 0.003146, 0.006144),
}


def _published_by_quadrature(ha, hb, hc, ta, tb, E=206e9, nu=0.3, phi_deg=20.0, f=0.05):
    """The published deflections integrated numerically over the whole tooth from the root: a
    uniform segment of t_b up to h_b, then the linear taper (an independent reference). The radial
    term is the moment F sin φ · t_c/2 acting on the transverse deflection, as published (eq. 3)."""
    from scipy.integrate import quad

    def t(y):
        return tb if y < hb else tb + (ta - tb) * (y - hb) / (ha - hb)

    G, phi = E / (2 * (1 + nu)), math.radians(phi_deg)
    c, s, e = math.cos(phi), math.sin(phi), t(hc) / 2

    def integral(g):
        return quad(g, 0.0, hc, points=[hb], limit=200, epsabs=0, epsrel=1e-12)[0]

    return {
        "bending_transverse": integral(lambda y: 12 * c * c * (hc - y) ** 2 / (E * f * t(y) ** 3)),
        "bending_radial": integral(lambda y: -12 * s * c * e * (hc - y) / (E * f * t(y) ** 3)),
        "shear": integral(lambda y: 1.2 * c * c / (G * f * t(y))),
        "foundation": 24 * c * c * hc**2 / (math.pi * E * f * tb**2),
        "hertz": 4 * (1 - nu**2) / (math.pi * E * f),
    }


@pytest.mark.parametrize("pair", [1, 2])
def test_the_published_tooth_formulas_against_quadrature(pair):
    ha, hb, hc, ta, tb = PUBLISHED_PAIRS[pair]
    tooth = TruncatedTooth(
        tip_height=ha, root_height=hb, tip_thickness=ta, root_thickness=tb, face_width=0.05,
        youngs_modulus=206e9, poisson_ratio=0.3,
    )  # fmt: skip
    terms = tooth.published_compliances(hc, math.radians(20.0))
    reference = _published_by_quadrature(ha, hb, hc, ta, tb)
    assert set(terms) == set(reference)
    for k, v in reference.items():
        assert terms[k] == pytest.approx(v, rel=1e-9), k


def test_one_tooth_of_published_pair_2_gives_the_value_printed_for_pair_1(tmp_path, capsys):
    """SPEC §4: with steel and a 50 mm face, a single pair-2 tooth gives the k_c printed for pair 1
    (2.7082e9 N/m) to 0.013 %: the published table's mix-up, shown by the command
    (tests/test_gears_published.py holds the published terms by hand)."""
    from mechdyn.cli.main import main

    assert (
        main(["gear", str(EXAMPLES / "tooth_pair2_published.toml"), "--json", "--db", str(tmp_path / "r.db")])
        == 0
    )
    doc = json.loads(capsys.readouterr().out)
    assert doc["formulas"] == "published"
    assert doc["tooth_stiffness_N_per_m"][0] == pytest.approx(2.7082e9, rel=5e-4)
    # the refined model of before stays as a named option, with its own numbers
    text = (
        (EXAMPLES / "tooth_pair1_published.toml")
        .read_text()
        .replace('face_width = "50 mm"', 'face_width = "50 mm"\nformulas = "refined"')
    )
    (tmp_path / "refined.toml").write_text(text)
    assert main(["gear", str(tmp_path / "refined.toml"), "--json", "--db", str(tmp_path / "r.db")]) == 0
    refined = json.loads(capsys.readouterr().out)
    assert refined["formulas"] == "refined"
    assert refined["pair_stiffness_N_per_m"] == pytest.approx(2.0534e9, rel=1e-4)


# -- the whole tooth from the root circle: trends with tooth count, module and profile shift ----


def _bored_pair(z1, z2, m=0.003, b=0.03, x=0.0, model="involute"):
    gears = [  # bores of half the root diameter
        SpurGear(z, m, b, profile_shift=x, bore_diameter=m * (z / 2 - 1.25 + x), name=f"z{z}")
        for z in (z1, z2)
    ]
    return GearPair(gears[0], gears[1], tooth_model=model)


def _mean_and_iso(pair, b=0.03):
    with warnings.catch_warnings():  # z = 16: the Sainsot fit is extrapolated a little (said so)
        warnings.simplefilter("ignore", ModelWarning)
        return pair.mesh_cycle(400).mean / b / 1e9, iso_stiffness(pair).c_gamma_alpha


def _stated_table(page):
    """A page's table of standard pairs: {(z1, z2): (truncated, generated, ISO, generated / ISO)}."""
    text = (Path(__file__).parents[1] / page).read_text(encoding="utf-8")
    rows = re.findall(r"^\| (\d+)/(\d+) \| ([\d.]+) \| ([\d.]+) \| ([\d.]+) \| ([\d.]+) \|$", text, re.M)
    return {(int(z1), int(z2)): tuple(map(float, v)) for z1, z2, *v in rows}


def test_mesh_stiffness_follows_iso_with_tooth_count_module_and_profile_shift():
    """Issue: clamped at max(r_b, r_f), the tooth lost the part between root and base circles and the
    mean mesh stiffness fell 16 % from z 16/32 to 45/90 where ISO c_γα·b rises 34 % (and the
    potential-energy method of a rotordynamics package 18 %). With the whole tooth it rises, and the
    generated tooth (fillet and involute, the default) lands within 11 % of ISO."""
    counts = [(16, 32), (20, 40), (25, 50), (30, 60), (45, 90)]
    means, isos = zip(*(_mean_and_iso(_bored_pair(z1, z2)) for z1, z2 in counts), strict=True)
    # the generated tooth is the default
    assert means[0] == _mean_and_iso(_bored_pair(*counts[0], model="involute"))[0]
    truncated = [_mean_and_iso(_bored_pair(z1, z2, model="truncated"))[0] for z1, z2 in counts]
    # the README and the gear page state this table: every number is recomputed here
    for page in ("README.md", "docs/capabilities/gears.md"):
        table = _stated_table(page)
        assert sorted(table) == counts, page
        for (z, row), kt, k, iso in zip(table.items(), truncated, means, isos, strict=True):
            assert row == pytest.approx((kt, k, iso, k / iso), abs=0.051), (page, z)
    # both rise with tooth count, as ISO does: the generated tooth by 17 % (the potential-energy
    # method of a rotordynamics package 18 %), the truncated triangle by 29 %, ISO by 34 %
    for model in (means, truncated):
        assert all(a < b for a, b in itertools.pairwise(model))
    assert means[-1] / means[0] == pytest.approx(1.17, abs=0.01)
    assert truncated[-1] / truncated[0] == pytest.approx(1.29, abs=0.01)
    assert isos[-1] / isos[0] == pytest.approx(1.343, abs=0.005)
    ratios = [k / i for k, i in zip(means, isos, strict=True)]
    assert all(0.95 < r < 1.12 for r in ratios), ratios
    # per unit face width it does not depend on the module (nor does ISO's)
    for model in ("involute", "truncated"):
        per_module = [_mean_and_iso(_bored_pair(20, 40, m=m, model=model))[0] for m in (0.002, 0.003, 0.005)]
        assert max(per_module) / min(per_module) < 1 + 1e-6, model
    # a positive profile shift stiffens the mesh, as ISO says (generated tooth 3.5 %, ISO 7 % at 0.5)
    shifted = [_mean_and_iso(_bored_pair(20, 40, x=x)) for x in (0.0, 0.3, 0.5)]
    assert shifted[0][0] < shifted[1][0] < shifted[2][0] and shifted[0][1] < shifted[1][1] < shifted[2][1]
    assert shifted[2][0] / shifted[0][0] == pytest.approx(1.035, abs=0.002)


# -- the generated tooth: the fillet that the rack's rounded tip cuts, then the involute ----------


def _iso_6336_3_sfn(z, x, rho=0.38, hfp=1.25, alpha_deg=20.0):
    """ISO 6336-3 (method B): the root chord s_Fn/m at the 30° tangents, by its E, G, H, θ iteration."""
    alpha = math.radians(alpha_deg)
    E = math.pi / 4 - hfp * math.tan(alpha) - (1 - math.sin(alpha)) * rho / math.cos(alpha)
    G, H = rho - hfp + x, 2 / z * (math.pi / 2 - E) - math.pi / 3
    theta = math.pi / 6
    for _ in range(200):
        theta = 2 * G / z * math.tan(theta) - H
    return z * math.sin(math.pi / 3 - theta) + math.sqrt(3) * (G / math.cos(theta) - rho)


@pytest.mark.parametrize(("z", "x"), [(20, 0.0), (40, 0.0), (16, 0.0), (25, 0.3), (60, -0.2)])
def test_the_generated_fillet_against_iso(z, x):
    g = SpurGear(z, 1.0, 10.0, profile_shift=x)  # module 1: lengths in modules
    a, rho, hfp = g.pressure_angle, 0.38, 1.25
    # the root chord at the 30° tangents, ISO 6336-3
    r = np.linspace(g.root_radius, g.involute_start_radius, 200_001)
    half = np.arcsin(g.generated_thickness_array(r) / (2 * r))
    across, along = r * np.sin(half), r * np.cos(half)
    i = np.argmin(np.abs(np.gradient(across, along) + math.tan(math.pi / 6)))
    assert 2 * across[i] == pytest.approx(_iso_6336_3_sfn(z, x), rel=5e-4)
    # the root land, from the rack's tip between its roundings: half-angle u_c / r
    uc = math.pi / 4 - (hfp - rho) * math.tan(a) - rho / math.cos(a)
    root = g.generated_thickness_array(np.array([g.root_radius]))[0]
    assert root == pytest.approx(2 * g.root_radius * math.sin(math.pi / z - uc / g.pitch_radius), rel=1e-9)
    # on the involute above its start, the involute's own chord
    above = np.linspace(g.involute_start_radius, g.tip_radius, 7)
    np.testing.assert_allclose(
        g.generated_thickness_array(above), g.chordal_thickness_array(above), rtol=1e-12
    )
    if z >= 17 or x > 0.2:  # no undercut: the form radius of ISO 21771
        r_ff = math.hypot(
            g.base_radius, g.pitch_radius * math.sin(a) - (hfp - rho * (1 - math.sin(a)) - x) / math.sin(a)
        )
        assert g.involute_start_radius == pytest.approx(r_ff, rel=1e-10)


def test_an_undercut_tooth_is_thinner_than_its_involute():
    # 12 teeth, no shift: the fillet cuts into the involute above the base circle
    g = SpurGear(12, 1.0, 10.0)
    r = np.linspace(g.base_radius * 1.0001, g.base_radius + 0.5, 50)
    cut = g.generated_thickness_array(r) < g.chordal_thickness_array(r) * (1 - 1e-6)
    assert cut.any() and not cut[-1]
    with pytest.raises(ModelError, match=r"fillet radius 0.6 modules must lie between 0 and 0.47"):
        SpurGear(20, 0.002, 0.02, fillet_radius=0.6)


def test_the_generated_tooth_terms_against_quadrature():
    # Gauss–Legendre split at the fillet's end against adaptive quadrature of the same integrals
    g = SpurGear(20, 0.002, 0.02, bore_diameter=0.02)
    tooth = g.profile_tooth()
    r = g.pitch_radius
    hc, phi = r - g.root_radius, g.load_angle(r)
    terms = tooth.compliances(hc, phi)

    def t(y):
        return float(g.generated_thickness_array(np.array([g.root_radius + y]))[0])

    f, G = g.face_width, E / (2 * (1 + NU))
    c, s_, e = math.cos(phi), math.sin(phi), t(hc) / 2
    kink = [g.involute_start_radius - g.root_radius]

    def integral(fn):
        with warnings.catch_warnings():  # the fillet is interpolated on a fine grid: quad sees kinks
            warnings.simplefilter("ignore", IntegrationWarning)
            return quad(fn, 0.0, hc, points=kink, limit=2000, epsabs=1e-22, epsrel=1e-9)[0]

    reference = {
        "bending_transverse": integral(lambda y: 12 * c * c * (hc - y) ** 2 / (E * f * t(y) ** 3)),
        "bending_radial": integral(
            lambda y: 12 * (s_ * s_ * e * e - 2 * s_ * c * e * (hc - y)) / (E * f * t(y) ** 3)
        ),
        "compression": integral(lambda y: s_ * s_ / (E * f * t(y))),
        "shear": integral(lambda y: 1.2 * c * c / (G * f * t(y))),
    }
    for k, v in reference.items():
        assert terms[k] == pytest.approx(v, rel=1e-5), k


def test_drivetrain_meshes_from_gear_data_take_the_generated_tooth_or_the_named_model(tmp_path):
    import mechdyn

    text = (EXAMPLES / "turret_milling_gear_data.toml").read_text()
    default = mechdyn.load(EXAMPLES / "turret_milling_gear_data.toml").model.element("mesh 1")
    path = tmp_path / "truncated.toml"
    path.write_text(
        text.replace('name = "19/19 spur pair"\n', 'name = "19/19 spur pair"\ntooth_model = "truncated"\n')
    )
    truncated = mechdyn.load(path).model.element("mesh 1")
    gear = SpurGear(19, 0.002119, 0.0143, bore_diameter=0.006)
    for mesh, model in ((default, "involute"), (truncated, "truncated")):
        expected = GearPair(gear, gear, tooth_model=model).mesh_cycle(400).mean
        assert mesh.stiffness == pytest.approx(expected, rel=1e-12), model
    assert default.stiffness / truncated.stiffness == pytest.approx(1.22, abs=0.01)


def test_small_pinions_warn_only_beyond_the_extrapolation_tolerance():
    # θ_f at the root circle of the generated tooth: 0.150 rad at z = 20, above the fit's 0.12, but
    # the extrapolation carries 1.6 % of the tooth's compliance: no warning; a 12-tooth pinion
    # shifted by 0.5 on a thin rim (h_f 1.45, θ_f 0.25) carries 6.5 %, and says so
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        tooth = SpurGear(20, 0.002, 0.02, bore_diameter=0.02, name="pinion").profile_tooth()
        SpurGear(40, 0.002, 0.02, bore_diameter=0.0375).profile_tooth()
    assert tooth.foundation_extrapolation() == pytest.approx(0.0163, abs=5e-4)
    with pytest.warns(ModelWarning, match=r"pinion generated tooth: .*θ_f = 0.248 rad .* up to 6.5 %"):
        SpurGear(
            12, 0.002, 0.02, profile_shift=0.5, bore_diameter=2 * 0.0105 / 1.45, name="pinion"
        ).profile_tooth()
