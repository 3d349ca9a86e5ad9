"""Mount stiffness: closed forms, a textbook bolted joint, the FE reference, calibration, materials."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from conftest import EXAMPLES
from mechdyn.errors import ModelError
from mechdyn.mounts import (
    BoltedJoint,
    ElastomerPad,
    Layer,
    Material,
    MaterialDatabase,
    SpringIsolator,
    anchor_members,
    apply,
    default_materials,
    fit_cone_angle,
    fit_frf,
    fit_pad_factor,
    frustum_stiffness,
    isolation,
    load_calibration,
    pad_compression,
    save_materials,
)
from mechdyn.store import ResultStore
from mechdyn.units import to_si

DB = default_materials()
E_CONCRETE = to_si("2.6e6 psi", "Pa")


# -- closed forms -------------------------------------------------------------------------------


@pytest.mark.parametrize("order", [1, 2])
def test_a_free_bar_by_fe_is_ea_over_l_to_round_off(order):
    r = pad_compression(0.08, 0.05, 2.1e11, 0.3, bonded=False, n=3, order=order)
    assert r.stiffness == pytest.approx(2.1e11 * math.pi * 0.04**2 / 0.05, rel=1e-12)


def test_gent_lindley_limits():
    rubber = DB["rubber shore 50"]
    E, B = rubber.youngs_modulus, rubber.bulk_modulus
    thin = ElastomerPad("thin", rubber, "0.1 mm", diameter="500 mm")  # S = 1250: bulk-limited
    assert thin.compression_modulus == pytest.approx(B, rel=1e-3)
    tall = ElastomerPad("tall", rubber, "1000 mm", diameter="10 mm")  # S → 0: E, with B in series
    assert tall.compression_modulus == pytest.approx(E * B / (E + B), rel=1e-4)
    square = ElastomerPad("sq", rubber, "10 mm", length="100 mm", width="100 mm")
    S = 100 * 100 / (2 * 10 * 200)
    assert square.shape_factor == pytest.approx(S)
    assert 1 / square.compression_modulus == pytest.approx(
        1 / (E * (1 + 2 * rubber.compression_coefficient * S**2)) + 1 / B
    )


@pytest.mark.parametrize("S", [0.5, 1.0, 2.0, 4.0])
def test_fe_pad_follows_the_shape_factor_law_of_an_elastic_solid(S):
    # a linear-elastic solid of E and B is the k = 1 law's; agreement found: within 4 % for S ≥ 1,
    # 8 % at S = 0.5 (where E(1 + 2S²) is known to be low: the bulging is not parabolic)
    rubber = DB["rubber shore 40"]
    h = 0.01
    pad = ElastomerPad("p", rubber, h, diameter=4 * S * h)
    fe = pad_compression(pad.diameter, h, rubber.youngs_modulus, rubber.poissons_ratio, n=8)
    assert fe.stiffness / pad.ideal_compression_stiffness == pytest.approx(1.0, abs=0.08 if S < 1 else 0.04)


def test_pad_shear_with_bending_and_the_load_dependent_curve():
    rubber = DB.rubber(60)
    low = ElastomerPad("low", rubber, "10 mm", diameter="100 mm")
    tall = ElastomerPad("tall", rubber, "80 mm", diameter="100 mm")
    assert low.shear_stiffness == pytest.approx(low.shear_stiffness_without_bending, rel=0.01)
    # a block held parallel at both faces: shear and bending in series (Gent, ch. 9)
    Eb = rubber.youngs_modulus * (1 + 2 / 3 * rubber.compression_coefficient * tall.shape_factor**2)
    second_moment = math.pi * 0.1**4 / 64
    expected = 1 / (0.08 / (rubber.shear_modulus * tall.area) + 0.08**3 / (12 * Eb * second_moment))
    assert tall.shear_stiffness == pytest.approx(expected, rel=1e-12)
    assert tall.shear_stiffness < 0.9 * tall.shear_stiffness_without_bending
    d = np.array([0.0, 1e-7, 2e-3])
    F = low.compression_force(d)
    assert F[0] == 0 and F[1] / 1e-7 == pytest.approx(low.compression_stiffness, rel=1e-4)
    assert low.tangent_stiffness(2e-3) > low.compression_stiffness  # rubber stiffens in compression


def test_member_stiffness_against_shigleys_worked_example():
    # Budynas & Nisbett, Shigley's Mechanical Engineering Design, 8th ed., solution of problem 8-22:
    # M12 cap screw, d_w = 18 mm, 20 mm steel (207 GPa) over 25 mm cast iron (100 GPa), α = 30°:
    # frusta 4470, 52 230 and 2074 MN/m, k_m = 1379 MN/m
    steel = Material("steel 207", "steel", "207 GPa", 0.3)
    iron = Material("cast iron 100", "cast_iron", "100 GPa", 0.26)
    j = BoltedJoint(
        "ex", "12 mm", [Layer("20 mm", steel), Layer("25 mm", iron)], steel, "18 mm", nut="tapped"
    )
    k = [f["stiffness_N_per_m"] / 1e6 for f in j.frusta()]
    assert k == pytest.approx([4470, 52230, 2074], rel=5e-4)
    assert j.member_stiffness() / 1e6 == pytest.approx(1379, rel=5e-4)
    # and the single frustum of the same solutions: 207 GPa, t 20 mm, d 10 mm, D 15 mm: 3503 MN/m
    assert frustum_stiffness(207e9, 0.010, 0.015, 0.020, math.radians(30)) / 1e6 == pytest.approx(
        3503, rel=5e-4
    )


def _anchor(**kw):
    layers = [Layer("20 mm", DB["steel"]), Layer("40 mm", DB["concrete (published anchor case)"])]
    return BoltedJoint(
        "anchor", "12 mm", layers, DB["bolt steel"], "24 mm", hole_diameter="13 mm", nut="anchor", **kw
    )


def test_bolt_and_members_act_in_parallel_for_an_external_load():
    j = _anchor()
    kb, km = j.bolt_stiffness, j.member_stiffness()
    assert j.joint_stiffness == pytest.approx(kb + km)
    assert j.load_factor == pytest.approx(kb / (kb + km)) and 0 < j.load_factor < 1
    # the published L_eq estimate (shank area throughout) is the stiffer: VDI 2230 takes one diameter
    # of the grip as free thread of the core area, and the head and anchor with their own allowances
    assert 0.75 < j.bolt_stiffness_vdi2230() / kb < 1.0
    # a wider cone spreads the load: stiffer members
    assert j.member_stiffness(math.radians(40)) > km > j.member_stiffness(math.radians(20))
    assert 15 < math.degrees(_anchor(cone_angle="vdi2230").cone_angle) < 45
    # VDI 2230's tapped-thread joint (ESV) has its own cone law
    from mechdyn.mounts import vdi2230_cone_angle

    assert math.tan(vdi2230_cone_angle(0.03, 0.02, 0.06, tapped=True)) == pytest.approx(
        0.348 + 0.013 * math.log(1.5) + 0.193 * math.log(3.0)
    )


# -- the FE reference ---------------------------------------------------------------------------


ANCHOR_FE = dict(
    plate_thickness=0.02,
    plate_radius=0.06,
    embedment=0.04,
    concrete_radius=0.15,
    hole_diameter=0.013,
    washer_diameter=0.024,
    anchor_head_diameter=0.024,
    plate_E=2.1e11,
    plate_nu=0.3,
    concrete_E=E_CONCRETE,
    concrete_nu=0.2,
)


@pytest.fixture(scope="module")
def anchor_fe():
    return [anchor_members(**ANCHOR_FE, n=n) for n in (4, 8)]


def test_anchor_fe_contact_carries_the_preload_and_the_mesh_converges(anchor_fe):
    coarse, fine = anchor_fe
    # the contact pressure carries the whole preload (the plate's vertical balance)
    r = fine.contact_radius
    edges = np.concatenate([[r[0]], 0.5 * (r[1:] + r[:-1]), [r[-1]]])
    area = np.pi * (edges[1:] ** 2 - edges[:-1] ** 2)
    assert np.sum(fine.pressure(4000.0) * area) == pytest.approx(4000.0, rel=1e-9)
    assert np.all(fine.contact_pressure >= 0)
    # highest next to the bolt, zero where the plate has lifted off, inside the plate
    assert np.argmax(fine.contact_pressure) == 0
    assert 0.0125 < fine.lift_off_radius < 0.06
    assert np.all(fine.contact_pressure[r > fine.lift_off_radius] == 0)
    # linear: pressure scales with the preload; the stiffness settles with refinement
    assert fine.radius_above(1.7e6, 2000.0) < fine.radius_above(1.7e6, 6000.0)
    assert abs(fine.stiffness / coarse.stiffness - 1) < 0.1


@pytest.mark.slow
def test_anchor_fe_fine_meshes_converge():
    k = [anchor_members(**ANCHOR_FE, n=n).stiffness for n in (8, 16, 32)]
    assert abs(k[2] - k[1]) < 0.5 * abs(k[1] - k[0])
    pads = [
        pad_compression(0.1, 0.0125, 4.45e6, 0.5 - 4.45e6 / 6 / 1.15e9, n=n).stiffness for n in (8, 16, 32)
    ]
    assert abs(pads[2] - pads[1]) < 0.5 * abs(pads[1] - pads[0])


# -- calibration --------------------------------------------------------------------------------


def test_calibration_recovers_a_known_cone_angle_and_pad_factor():
    j = _anchor()
    alpha = math.radians(34.0)
    c = fit_cone_angle(j, j.member_stiffness(alpha), "synthetic: α = 34°")
    assert c.value == pytest.approx(alpha, rel=1e-10)
    assert apply(c, j).member_stiffness() == pytest.approx(j.member_stiffness(alpha), rel=1e-10)
    pad = ElastomerPad("pad", DB.rubber(55), "10 mm", length="80 mm", width="60 mm")
    target = replace(pad, compression_coefficient=0.42).compression_stiffness
    assert fit_pad_factor(pad, target, "synthetic").value == pytest.approx(0.42, rel=1e-9)
    with pytest.raises(ModelError, match="no cone_angle in"):
        fit_cone_angle(j, 1e3, "impossible")


def test_calibrations_are_stored_with_their_provenance_and_read_back(store_url):
    j = _anchor()
    with ResultStore(store_url) as store:
        c = fit_cone_angle(j, 4.0e8, "FE, 16 elements")
        c.save(store)
        newer = fit_cone_angle(j, 4.2e8, "FE, 32 elements")
        newer.save(store)
        back = load_calibration(store, "anchor")
    assert back.value == pytest.approx(newer.value) and back.provenance == "FE, 32 elements"


@pytest.mark.parametrize("kind", ["receptance", "mobility", "accelerance"])
def test_frf_fit_recovers_stiffness_damping_and_mass(kind):
    k, m, zeta = 2.5e6, 180.0, 0.06
    c = 2 * zeta * math.sqrt(k * m)
    f = np.linspace(2.0, 40.0, 50)
    w = 2 * np.pi * f
    H = (1j * w) ** ["receptance", "mobility", "accelerance"].index(kind) / (k - m * w**2 + 1j * c * w)
    fit = fit_frf(f, H, kind)
    assert (fit.stiffness, fit.damping, fit.mass) == pytest.approx((k, c, m), rel=1e-8)
    assert fit.damping_ratio == pytest.approx(zeta, rel=1e-8)
    noisy = H * (1 + 0.02 * np.random.default_rng(1).normal(size=f.size))
    assert fit_frf(f, noisy, kind).stiffness == pytest.approx(k, rel=0.03)


# -- other mounts, isolation ------------------------------------------------------------------


def test_isolation_figures():
    out = isolation("1e6 N/m", "9806.65 N", "10 Hz")
    assert out["static_deflection_m"] == pytest.approx(9.80665e-3)
    assert out["natural_frequency_hz"] == pytest.approx(math.sqrt(9.80665 / 9.80665e-3) / (2 * math.pi))
    at_root2 = isolation(1e6, 1000 * 9.80665, math.sqrt(2) * out["natural_frequency_hz"], loss_factor=0.3)
    assert at_root2["transmissibility"] == pytest.approx(1.0)  # every damping crosses T = 1 at r = √2
    assert isolation("1e6 N/m", "1000 kg", "30 Hz")["isolation_efficiency"] > 0.8


def test_spring_isolator_rate():
    s = SpringIsolator("s", "8 mm", "60 mm", 6, DB["steel"], springs=4)
    G = DB["steel"].shear_modulus
    assert s.stiffness == pytest.approx(4 * G * 0.008**4 / (8 * 0.06**3 * 6))


# -- materials and bad input -------------------------------------------------------------------


def test_the_shipped_materials_have_sources_and_every_kind():
    kinds = {m.kind for m in DB.materials.values()}
    assert {"steel", "cast_iron", "concrete", "rubber"} <= kinds
    assert all(m.source for m in DB.materials.values())
    assert all(0.15 <= DB[n].poissons_ratio <= 0.25 for n in DB.names("concrete"))
    e = [DB.rubber(h).youngs_modulus for h in range(30, 76, 5)]
    assert e == sorted(e)
    mid = DB.rubber(57.5)
    assert DB.rubber(55).youngs_modulus < mid.youngs_modulus < DB.rubber(60).youngs_modulus
    assert "interpolated" in mid.source


def test_user_materials_extend_the_database_and_go_into_the_store(tmp_path, store_url):
    f = tmp_path / "mine.toml"
    f.write_text(
        '[[materials]]\nname = "my polyurethane"\nkind = "rubber"\nyoungs_modulus = "12 MPa"\n'
        'bulk_modulus = "2 GPa"\nsource = "supplier data sheet PU-80, 2026"\n'
    )
    db = DB.with_file(f)
    assert db["my polyurethane"].poissons_ratio == pytest.approx(0.5 - 12e6 / 12e9)
    assert "steel" in db and "my polyurethane" not in DB
    with ResultStore(store_url) as store:
        save_materials(
            store, MaterialDatabase({"my polyurethane": db["my polyurethane"]}), "lab test 2026-11"
        )
        back = MaterialDatabase.from_store(store)
        rec = store.latest_record("material", "my polyurethane")
    assert back["my polyurethane"] == db["my polyurethane"]
    assert rec.provenance == "lab test 2026-11"


def test_bad_inputs_are_refused_by_name():
    with pytest.raises(ModelError, match=r"element 'gum', field 'poissons_ratio'.*between −1 and 0.5"):
        Material("gum", "rubber", "2 MPa", 0.5)
    with pytest.raises(ModelError, match=r"field 'head_diameter'.*not larger than the hole"):
        _anchor_with(head_diameter="10 mm")
    with pytest.raises(ModelError, match=r"field 'thickness'.*must be positive"):
        Layer("-20 mm", DB["steel"])
    with pytest.raises(ModelError, match=r"element 'p', field 'thickness'.*must be positive"):
        ElastomerPad("p", DB.rubber(50), "-5 mm", diameter="50 mm")
    with pytest.raises(ModelError, match="did you mean 'steel"):
        DB["steal"]
    with pytest.raises(ModelError, match="Shore A 95 is outside the table"):
        DB.rubber(95)
    with pytest.raises(ModelError, match=r"poissons_ratio.*0\.5 must lie"):
        pad_compression(0.1, 0.01, 1e6, 0.5)


def _anchor_with(**kw):
    layers = [Layer("20 mm", DB["steel"])]
    return BoltedJoint("a", "12 mm", layers, DB["bolt steel"], kw.pop("head_diameter", "24 mm"), **kw)


@pytest.mark.parametrize(
    ("body", "message"),
    [
        (
            '[pad]\nshore_a = 60\nmaterial = "rubber shore 60"\nthickness = "10 mm"\ndiameter = "50 mm"\n',
            "one of the two",
        ),
        (
            '[pad]\nshore_a = 60\nthickness = "-10 mm"\ndiameter = "50 mm"\n',
            "[pad] → thickness: -0.01 m must be positive",
        ),
        (
            '[bolted]\ndiameter = "12 mm"\nhead_diameter = "24 mm"\n[[bolted.layers]]\nthickness = "20 mm"\n'
            'material = "steal"\n',
            "[[bolted.layers]] #1 → material: no material 'steal' in the database; did you mean 'steel'?",
        ),
        (
            '[wedge]\nbearing_area = "1e-2 m^2"\nheight = "50 mm"\n[fe]\n',
            "the FE reference models pads and bolted",
        ),
        (
            '[pad]\nshore_a = 60\nthickness = "10 mm"\ndiameter = "50 mm"\n'
            '[spring]\nwire_diameter = "5 mm"\ncoil_diameter = "40 mm"\nactive_coils = 5\n',
            "describe exactly one mount",
        ),
    ],
)
def test_mount_file_errors_name_the_table(tmp_path, body, message):
    import mechdyn
    from mechdyn.errors import ModelFileError

    p = tmp_path / "m.toml"
    p.write_text('[model]\ntype = "mount"\nname = "m"\n' + body)
    with pytest.raises(ModelFileError) as info:
        mechdyn.load(p)
    assert message in str(info.value)


@pytest.mark.parametrize(
    "row, where, what",
    [
        (
            'name = "x"\nkind = "steel"\nyoungs_modulus = 210e9\npoissons_ratio = 0.3\nsource = "s"',
            "youngs_modulus",
            "unit",
        ),
        (
            'name = "x"\nkind = "brass"\nyoungs_modulus = "100 GPa"\npoissons_ratio = 0.3\nsource = "s"',
            "kind",
            "brass",
        ),
        ('name = "x"\nkind = "steel"\nyoungs_modulus = "210 GPa"\npoissons_ratio = 0.3', "source", "missing"),
        (
            'name = "x"\nkind = "steel"\nyoungs_modulus = "210 GPa"\npoissons_ratio = 0.7\nsource = "s"',
            "poissons_ratio",
            "between",
        ),
        (
            'name = "x"\nkind = "steel"\nyoung_modulus = "210 GPa"\nsource = "s"',
            "young_modulus",
            "youngs_modulus",
        ),
    ],
)
def test_a_materials_file_goes_through_the_model_file_checks(tmp_path, row, where, what):
    # the same validated loader and the same errors as a model file: file, table, field, value, fix
    from mechdyn.errors import ModelFileError
    from mechdyn.mounts import default_materials

    p = tmp_path / "my_materials.toml"
    p.write_text("[[materials]]\n" + row + "\n")
    with pytest.raises(ModelFileError) as info:
        default_materials().with_file(p)
    text = str(info.value)
    assert text.startswith(str(p)) and "[[materials]] #1" in text and where in text and what in text


def test_a_mount_file_names_the_bad_materials_file(tmp_path):
    import mechdyn
    from mechdyn.errors import ModelFileError

    (tmp_path / "mine.toml").write_text("[[materials]]\nname = 1\n")
    p = tmp_path / "m.toml"
    p.write_text(
        '[model]\ntype = "mount"\nname = "m"\n[materials]\nfiles = ["mine.toml"]\n'
        '[pad]\nshore_a = 60\nthickness = "10 mm"\ndiameter = "50 mm"\n'
    )
    with pytest.raises(ModelFileError) as info:
        mechdyn.load(p)
    assert str(info.value).startswith(str(tmp_path / "mine.toml"))


def test_richardson_recovers_a_known_limit_and_order():
    from mechdyn.mounts.fe import richardson

    # f_h = f + C h^p on meshes halved each time: the limit and the order come back exactly, and two
    # successive extrapolations agree (more in test_mounts_convergence.py)
    ex = richardson([2.5 + 0.7 * h**1.7 for h in (0.4, 0.2, 0.1, 0.05)], expected_order=2.0)
    assert ex.value == pytest.approx(2.5, rel=1e-12) and ex.order == pytest.approx(1.7, rel=1e-12)
    assert ex.verified and ex.error < 1e-12
    assert ex.finest_error == pytest.approx(0.7 * 0.05**1.7 / 2.5, rel=1e-9)
    # an oscillating sequence has no order: the error is the last change, and bounds nothing
    osc = richardson([1.0, 1.1, 1.05])
    assert osc.order is None and osc.value == 1.05 and osc.error == pytest.approx(0.05 / 1.05)
    assert not osc.verified


@pytest.mark.parametrize(("d_mm", "As_mm2"), [(6, 20.1), (12, 84.3), (20, 245.0), (36, 817.0)])
def test_the_stress_area_takes_the_iso_coarse_pitch(d_mm, As_mm2):
    # ISO 898-1 Table 4: tensile stress areas of coarse threads (M12: 84.3 mm², M20: 245 mm²)
    steel = DB["bolt steel"]
    j = BoltedJoint("b", f"{d_mm} mm", [Layer("20 mm", steel)], steel, f"{1.8 * d_mm} mm")
    assert j.stress_area * 1e6 == pytest.approx(As_mm2, rel=2e-3)
    with pytest.raises(ModelError, match=r"13 mm is not an ISO metric coarse-thread size .*give pitch"):
        BoltedJoint("b", "13 mm", [Layer("20 mm", steel)], steel, "24 mm")
    assert BoltedJoint("b", "13 mm", [Layer("20 mm", steel)], steel, "24 mm", pitch="1.5 mm").pitch == 0.0015


def _vdi_members(E, dh, dW, DA, lK, phi):
    """VDI 2230 Part 1 (2015) §5.1.2.2, through-bolted joint (w = 1): the members' resilience for a
    cone (D_A ≥ D_A,Gr), a cone and a sleeve (d_W < D_A < D_A,Gr) or a sleeve (D_A ≤ d_W)."""
    t = math.tan(phi)
    DAGr = dW + lK * t
    if DA >= DAGr:
        delta = (
            2
            * math.log((dW + dh) * (dW + lK * t - dh) / ((dW - dh) * (dW + lK * t + dh)))
            / (E * math.pi * dh * t)
        )
    elif DA > dW:
        cone = 2 / (dh * t) * math.log((dW + dh) * (DA - dh) / ((dW - dh) * (DA + dh)))
        sleeve = 4 / (DA**2 - dh**2) * (lK - (DA - dW) / t)
        delta = (cone + sleeve) / (E * math.pi)
    else:
        delta = 4 * lK / (E * math.pi * (DA**2 - dh**2))
    return 1 / delta


@pytest.mark.parametrize("DA_mm", [60.0, 24.0, 20.0, 16.0])
def test_members_switch_to_cone_and_sleeve_where_the_parts_are_narrow(DA_mm):
    # M12 through 40 mm of steel, d_W = 18 mm, d_h = 13 mm, φ = 30°: D_A,Gr = 41.1 mm
    steel = Material("steel 210", "steel", "210 GPa", 0.3)
    j = BoltedJoint(
        "j",
        "12 mm",
        [Layer("40 mm", steel)],
        steel,
        "18 mm",
        hole_diameter="13 mm",
        outer_diameter=f"{DA_mm} mm",
    )
    expected = _vdi_members(210e9, 0.013, 0.018, DA_mm / 1e3, 0.040, math.radians(30))
    assert j.member_stiffness() == pytest.approx(expected, rel=1e-12)
    if DA_mm < 41.0:  # the full cone of before overestimates narrow parts
        full = _vdi_members(210e9, 0.013, 0.018, 1.0, 0.040, math.radians(30))
        assert full > expected


def test_pitch_and_outer_diameter_reach_the_bolted_joint_from_a_file(tmp_path):
    # a 13 mm bolt is not an ISO size: the file gives its pitch; D_A from the file limits the cones
    import mechdyn

    text = (EXAMPLES / "anchor_concrete.toml").read_text()
    text = text.replace(
        'diameter = "12 mm"', 'diameter = "13 mm"\npitch = "1.5 mm"\nouter_diameter = "30 mm"', 1
    )
    text = text.replace('hole_diameter = "13 mm"', 'hole_diameter = "14 mm"').replace("[fe]", "[fe_off]")
    text = text.split("[fe_off]")[0]
    path = tmp_path / "m.toml"
    path.write_text(text)
    j = mechdyn.load(path).model
    assert j.pitch == pytest.approx(0.0015) and j.outer_diameter == pytest.approx(0.030)
    assert any(f.get("sleeve") for f in j.frusta())
    foot = tmp_path / "foot.toml"
    foot.write_text(
        '[model]\ntype = "mount"\n[screw_foot]\ndiameter = "13 mm"\nfree_length = "40 mm"\npitch = "1.5 mm"\n'
    )
    assert mechdyn.load(foot).model.stiffness > 0
