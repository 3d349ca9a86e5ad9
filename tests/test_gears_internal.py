"""Internal gear pairs: geometry of the ring, path of contact, the ring's tooth, the mesh cycle, files."""

from __future__ import annotations

import itertools
import math
import re
from pathlib import Path

import numpy as np
import pytest

import mechdyn
from mechdyn.errors import ModelError
from mechdyn.gears import GearPair, SpurGear, iso_stiffness
from mechdyn.gears.results import gear_pair_stiffness

pytestmark = pytest.mark.filterwarnings("ignore:.*range of the Sainsot fit:mechdyn.errors.ModelWarning")


def _ring_pair(z1=20, z2=80, model="involute", helix_angle=0.0, **ring):
    return GearPair(
        SpurGear(z1, "2 mm", "20 mm", bore_diameter="20 mm", name="pinion", helix_angle=helix_angle),
        SpurGear(z2, "2 mm", "20 mm", name="ring", internal=True, helix_angle=helix_angle, **ring),
        tooth_model=model,
    )


def test_contact_ratio_against_the_textbook_formula_by_hand():
    # m 2 mm, α 20°, z 20/80, x = 0: r₁ = 20, r₂ = 80, r_b1 = 18.793852, r_b2 = 75.175410,
    # r_a1 = 22, r_a2 = 78 (inside), a = r₂ − r₁ = 60 mm, α_w = α
    # ε_α = [√(r_a1² − r_b1²) − √(r_a2² − r_b2²) + a sin α_w] / (π m cos α)
    #     = [11.436394 − 20.800427 + 20.521209] / 5.904263 = 11.157175 / 5.904263 = 1.889681
    pair = _ring_pair()
    assert pair.internal
    assert pair.center_distance == pytest.approx(60e-3, rel=1e-12)
    assert pair.working_pressure_angle == pytest.approx(math.radians(20), rel=1e-9)
    rb1, rb2 = 20 * math.cos(math.radians(20)), 80 * math.cos(math.radians(20))
    g = math.sqrt(22**2 - rb1**2) - math.sqrt(78**2 - rb2**2) + 60 * math.sin(math.radians(20))
    assert g == pytest.approx(11.157175, abs=1e-6)
    assert pair.contact_ratio == pytest.approx(g / (math.pi * 2 * math.cos(math.radians(20))), rel=1e-12)
    assert pair.contact_ratio == pytest.approx(1.889681, abs=1e-6)
    # the ring's radius at a contact is √(r_b2² + (T₁T₂ + s)²): at the pinion's tip it is inside the
    # ring's root circle, at the start of contact it is the ring's tip circle
    assert pair.gear_contact_radius(pair.path_start) == pytest.approx(78e-3, rel=1e-12)
    assert pair.gear_contact_radius(pair.pitch_point) == pytest.approx(80e-3, rel=1e-12)


def test_the_ring_tooth_geometry():
    ring = SpurGear(80, "2 mm", "20 mm", name="ring", internal=True)
    assert ring.tip_radius == pytest.approx(78e-3) and ring.root_radius == pytest.approx(82.5e-3)
    assert ring.thickness(ring.pitch_radius) == pytest.approx(math.pi * 2e-3 / 2, rel=1e-12)
    # thicker toward the root (outside), thinnest at the tip; the load angle is α_c + γ_c
    assert (
        ring.thickness(ring.root_radius) > ring.thickness(ring.pitch_radius) > ring.thickness(ring.tip_radius)
    )
    r = ring.pitch_radius
    assert ring.load_angle(r) == pytest.approx(math.radians(20) + math.pi / (4 * 80) * 2, rel=1e-12)
    assert ring.load_height(r) == pytest.approx(2.5e-3, rel=1e-12)
    # the ring's tooth against the same-size external gear's, loaded at the pitch circle: less bending
    # (thicker toward its root) and no foundation term (a rigid ring here)
    ext = SpurGear(80, "2 mm", "20 mm", name="gear")
    t_ring = ring.profile_tooth().compliances(ring.load_height(r), ring.load_angle(r))
    t_ext = ext.profile_tooth().compliances(ext.load_height(r), ext.load_angle(r))
    assert t_ring["bending_transverse"] < t_ext["bending_transverse"]
    assert t_ring["foundation"] == 0.0 < t_ext["foundation"]
    # both tooth models give a tooth tapering to the tip
    tooth = ring.tooth()
    assert tooth.tip_thickness < tooth.root_thickness
    assert tooth.tip_height == pytest.approx(4.5e-3, rel=1e-12)


@pytest.mark.parametrize("model", ["involute", "truncated"])
def test_the_mesh_cycle_of_an_internal_pair(model):
    pair = _ring_pair(model=model)
    cycle = pair.mesh_cycle(400)
    assert set(np.unique(cycle.pairs_in_contact)) == {1, 2}
    assert cycle.double_contact_share == pytest.approx(pair.contact_ratio - 1, abs=2 / 400)
    single = cycle.stiffness[cycle.pairs_in_contact == 1]
    double = cycle.stiffness[cycle.pairs_in_contact == 2]
    assert double.min() > single.max()
    # with the same pinion, the ring (concave flanks, rigid rim) meshes stiffer than an external
    # 80-tooth gear, and its contact ratio is larger (1.890 against 1.757)
    external = GearPair(pair.pinion, SpurGear(80, "2 mm", "20 mm", name="gear"), tooth_model=model)
    assert pair.contact_ratio > external.contact_ratio
    assert cycle.mean > external.mesh_cycle(400).mean


def test_iso_takes_the_ring_as_a_rack_and_says_so():
    # q′ = C1 + C2/z_n1 (1/z_n2 = 0) = 0.04723 + 0.15551/20 = 0.0550055
    iso = iso_stiffness(_ring_pair())
    assert iso.q_prime == pytest.approx(0.0550055, rel=1e-12)
    assert any("internal gear: 1/z_n2 = 0" in n for n in iso.notes)


def test_bad_internal_pairs_are_refused():
    with pytest.raises(ModelError, match=r"field 'bore_diameter'.*internal gear has no bore"):
        SpurGear(80, "2 mm", "20 mm", name="ring", internal=True, bore_diameter="100 mm")
    with pytest.raises(ModelError, match="pinion cannot be internal"):
        GearPair(
            SpurGear(60, "2 mm", "20 mm", name="pinion", internal=True),
            SpurGear(80, "2 mm", "20 mm", name="gear"),
        )
    with pytest.raises(ModelError, match="give the ring more teeth"):
        GearPair(
            SpurGear(40, "2 mm", "20 mm", name="pinion"),
            SpurGear(40, "2 mm", "20 mm", name="ring", internal=True),
        )
    with pytest.raises(ModelError, match="does not let the gears mesh"):
        GearPair(
            SpurGear(20, "2 mm", "20 mm", name="pinion"),
            SpurGear(80, "2 mm", "20 mm", name="ring", internal=True),
            center_distance="50 mm",
        )


def test_an_internal_pair_from_a_file(tmp_path):
    from conftest import EXAMPLES

    text = (EXAMPLES / "spur_pair.toml").read_text()
    text = text.replace("teeth = 40", "teeth = 80").replace('bore_diameter = "40 mm"\n', "")
    text = text.replace("[mesh]", '[mesh]\nkind = "internal"')
    path = tmp_path / "ring.toml"
    path.write_text(text)
    loaded = mechdyn.load(path)
    assert loaded.model.internal and loaded.model.gear.internal
    assert loaded.model.center_distance == pytest.approx(60e-3, rel=1e-12)
    result = gear_pair_stiffness(loaded.model, points=100)
    summary = result.summary()
    assert summary["internal"] is True
    assert summary["contact_ratio"] == pytest.approx(1.889681, abs=1e-6)
    out = tmp_path / "saved.toml"
    mechdyn.save(loaded.model, out)
    assert 'kind = "internal"' in out.read_text()
    assert mechdyn.load(out).model == loaded.model
    # a bore on the ring is refused with the file's location
    path.write_text(text.replace("teeth = 80", 'teeth = 80\nbore_diameter = "100 mm"'))
    with pytest.raises(mechdyn.ModelFileError, match="no bore"):
        mechdyn.load(path)


@pytest.mark.parametrize(("x1", "x2", "beta_deg"), [(0.3, 0.2, 0.0), (0.0, -0.3, 0.0), (0.2, 0.1, 12.0)])
def test_the_default_centre_distance_leaves_no_backlash(x1, x2, beta_deg):
    # independent of the involute-function formula: at the working pitch circles r_w = r_b / cos α_w
    # the pinion's tooth fills the ring's space, and a = r_w2 − r_w1
    from mechdyn.gears.geometry import involute

    beta = math.radians(beta_deg)
    p = SpurGear(20, "2 mm", "20 mm", name="pinion", profile_shift=x1, helix_angle=beta)
    g = SpurGear(80, "2 mm", "20 mm", name="ring", internal=True, profile_shift=x2, helix_angle=beta)
    pair = GearPair(p, g)
    aw = pair.working_pressure_angle
    rw1, rw2 = p.base_radius / math.cos(aw), g.base_radius / math.cos(aw)
    assert pair.center_distance == pytest.approx(rw2 - rw1, rel=1e-12)
    tooth = (
        2 * rw1 * (p.thickness(p.pitch_radius) / (2 * p.pitch_radius) + involute(p.transverse_pressure_angle))
    )
    tooth -= 2 * rw1 * involute(aw)
    ring_tooth = g.thickness(rw2)
    space = 2 * math.pi * rw2 / 80 - ring_tooth
    assert space - tooth == pytest.approx(0.0, abs=1e-15)
    assert pair.mesh_cycle(50).mean > 0


def test_a_drivetrain_mesh_from_an_internal_pair_turns_both_gears_the_same_way(tmp_path):
    """A ``[[gear_pairs]]`` row with ``kind = "internal"``: the mesh is internal (δ = r_a θ_a − r_b θ_b),
    its ratio and mean stiffness the pair's, and the drivetrain's frequency that of the same mesh built
    by hand; the same mesh set internal on the mesh row is refused with where to say it."""
    from mechdyn.drivetrain import Disk, Drivetrain, GearMesh, modal

    pair = _ring_pair()
    mesh = GearMesh.from_gear_pair("m", ("sun", "ring"), pair)
    assert mesh.kind == "internal" and mesh.speed_ratio == pytest.approx(4.0)
    assert mesh.transmission() > 0  # the ring turns the pinion's way
    assert mesh.stiffness == pytest.approx(pair.mesh_cycle(400).mean, rel=1e-12)
    disks = (Disk("sun", "0.01 kg*m^2"), Disk("ring", "0.5 kg*m^2"))
    by_hand = GearMesh(
        "m",
        ("sun", "ring"),
        kind="internal",
        teeth=(20, 80),
        base_radii=(pair.pinion.base_radius, pair.gear.base_radius),
        stiffness=mesh.stiffness,
    )
    f = modal(Drivetrain(disks, (mesh,))).frequencies_hz
    assert f == pytest.approx(modal(Drivetrain(disks, (by_hand,))).frequencies_hz, rel=1e-12)
    text = """
[model]
type = "drivetrain"
name = "ring"
[[disks]]
name = "sun"
inertia = "0.01 kg*m^2"
[[disks]]
name = "ring"
inertia = "0.5 kg*m^2"
[[gear_pairs]]
name = "p"
kind = "internal"
pinion = { teeth = 20, module = "2 mm", face_width = "20 mm", bore_diameter = "20 mm" }
gear = { teeth = 80, module = "2 mm", face_width = "20 mm" }
[[meshes]]
name = "m"
disks = ["sun", "ring"]
gear_pair = "p"
"""
    path = tmp_path / "ring_train.toml"
    path.write_text(text)
    loaded = mechdyn.load(path)
    assert loaded.model.element("m").kind == "internal"
    assert modal(loaded.model).frequencies_hz == pytest.approx(f, rel=1e-9)
    path.write_text(text.replace('gear_pair = "p"', 'gear_pair = "p"\nkind = "internal"'))
    with pytest.raises(mechdyn.ModelFileError, match=r"\[\[gear_pairs\]\] row"):
        mechdyn.load(path)


# -- the ring's rim: a curved beam between its supports (Chen & Shao 2013) -------------------------


def _rim_pair(rim_modules, supports, model="involute"):
    """The 20/80 pair of module 2 mm with a ring rim of ``rim_modules`` modules on ``supports``."""
    return _ring_pair(model=model, rim_thickness=rim_modules * 2e-3, rim_supports=supports)


def test_the_rim_beam_against_roarks_thin_ring_and_the_clamped_straight_beam():
    from mechdyn.gears.ring import RingRim

    E, nu, b = 206e9, 0.3, 0.02
    # a thin ring clamped at one point, loaded radially at the opposite one: as a free ring under two
    # opposite loads (the clamp's section neither moves nor turns, by symmetry), whose diameter
    # changes by (π/4 − 2/π) F R³/(E I) (the classic thin ring, e.g. Roark, 7th ed., Table 9.2, case 1)
    R, h = 1.0, 1e-3
    ring = RingRim(R, h, b, 1, E, nu)
    c = ring.flexibility(np.array([math.pi]))[0]
    inertia = b * h**3 / 12
    assert c[0, 0] == pytest.approx((math.pi / 4 - 2 / math.pi) * R**3 / (E * inertia), rel=1e-5)
    # a shallow span (2000 supports) is the straight beam clamped at both ends, loaded at mid-span:
    # F L³/(192 EI) + κ F L/(4 GA) across, F L/(4 EA) along, and a moment turns it (Timoshenko, a
    # propped half each side) by M L/(4 EI) (1 − 3/(4(1 + φ))), φ = 12 κ EI/(G A L²): M L/(16 EI) as φ → 0
    L, h = 0.1, 0.005
    beam = RingRim(2000 * L / (2 * math.pi), h, b, 2000, E, nu)
    assert beam.span * beam.radius == pytest.approx(L, rel=1e-12)
    c = beam.flexibility(np.array([beam.span / 2]))[0]
    inertia, area, G = b * h**3 / 12, b * h, E / (2 * (1 + nu))
    phi = 12 * 1.2 * E * inertia / (G * area * L**2)
    assert c[0, 0] == pytest.approx(L**3 / (192 * E * inertia) + 1.2 * L / (4 * G * area), rel=2e-4)
    assert c[1, 1] == pytest.approx(L / (4 * E * area), rel=1e-4)
    assert c[2, 2] == pytest.approx(L / (4 * E * inertia) * (1 - 3 / (4 * (1 + phi))), rel=1e-4)
    # Maxwell: symmetric and positive definite inside a span; nothing moves at the supports
    ring = _rim_pair(3, 6).ring_rim
    c = ring.flexibility(np.linspace(0.0, ring.span, 13))
    np.testing.assert_allclose(c, np.swapaxes(c, -1, -2), rtol=0, atol=1e-12 * np.abs(c).max())
    assert np.all(np.linalg.eigvalsh(c[1:-1]) > 0)
    assert np.abs(c[[0, -1]]).max() < 1e-12 * np.abs(c).max()


def test_the_rim_beam_stiffens_as_its_section_thickens():
    """At a fixed radius the rim's compliance falls as its thickness grows: ∝ 1/s_R³ while bending
    carries it, more slowly once hoop stretching and shear take a share; a rim's inner radius
    R − s_R/2 must stay positive."""
    from mechdyn.gears.ring import RingRim

    theta = np.linspace(0.0, math.pi / 3, 9)[1:-1]
    c = {
        h: RingRim(0.085, h, 0.02, 6, 206e9, 0.3).compliance(theta, 0.37, 0.075).max()
        for h in (1e-4, 2e-4, 1e-3, 1e-2, 0.1, 0.169)
    }
    assert all(a > b for a, b in itertools.pairwise(c.values()))
    assert c[2e-4] / c[1e-4] == pytest.approx(1 / 8, rel=0.01)
    assert 1 / 8 < c[0.169] / c[0.1] < 1  # no longer bending alone
    assert c[0.169] < 1e-4 * c[1e-3]
    with pytest.raises(ModelError, match=r"field 'thickness': thickness 0.17 m must be below twice"):
        RingRim(0.085, 0.17, 0.02, 6, 206e9, 0.3)
    with pytest.raises(ModelError, match=r"field 'supports'"):
        RingRim(0.085, 0.01, 0.02, 0, 206e9, 0.3)


def test_a_thinning_rim_softens_the_mesh_monotonically_and_a_thick_one_nears_the_rigid_rim():
    """(b) the mean mesh stiffness falls monotonically as the rim thins; (a) it rises towards the
    rigid rim's as the rim thickens: 0.93, 0.96, 0.98 of it at 200 modules on 6, 12, 24 supports. What
    stays of the gap for a rim far thicker than its span (5.5, 2.9, 1.5 %) is the compliance of a
    curved beam whose geometry scales with s_R (docs/capabilities/gears.md)."""
    rigid = _ring_pair().mesh_cycle(400).mean
    modules = (1, 2, 3, 5, 10, 20, 50, 200, 1000, 2000)
    for supports, at_200, gap in ((6, 0.93, 0.055), (12, 0.96, 0.029), (24, 0.98, 0.015)):
        ratio = [_rim_pair(s, supports).mesh_cycle(400).mean / rigid for s in modules]
        assert all(a < b < 1 for a, b in itertools.pairwise(ratio)), supports
        assert ratio[modules.index(200)] == pytest.approx(at_200, abs=0.005)
        assert 1 - ratio[-1] == pytest.approx(gap, abs=0.0005)
        assert ratio[-1] - ratio[-2] < 0.002  # a constant, not a rim that stiffens further
    # more supports, shorter spans, a stiffer mesh
    assert _rim_pair(3, 6).mesh_cycle(100).mean < _rim_pair(3, 12).mesh_cycle(100).mean


def _stated_rim_table():
    """The gear page's rim table: {rim modules or None (rigid): (6, 12, 24 supports)}."""
    text = (Path(__file__).parents[1] / "docs/capabilities/gears.md").read_text(encoding="utf-8")
    rows = re.findall(r"^\| (\d+|rigid rim) \| ([\d.]+) \| ([\d.]+) \| ([\d.]+) \|$", text, re.M)
    return {None if s == "rigid rim" else int(s): tuple(map(float, v)) for s, *v in rows}


def test_a_thin_planetary_ring_meshes_at_or_below_iso_as_the_gear_page_states():
    """Issue 43, point 6: on a rigid rim the ring meshes 1.47 × ISO's c_γα (ISO takes it as a rack);
    a rim of 2–3 modules brings it to ISO's value or below. The page's table is recomputed."""
    iso = iso_stiffness(_ring_pair()).mesh_stiffness(0.02)
    table = _stated_rim_table()
    assert sorted(table, key=lambda s: s or 10**9) == [2, 3, 5, 10, 20, None]
    for rim, row in table.items():
        if rim is None:
            got = (_ring_pair().mesh_cycle(400).mean / iso,) * 3
        else:
            got = tuple(_rim_pair(rim, n).mesh_cycle(400).mean / iso for n in (6, 12, 24))
        assert row == pytest.approx(got, abs=0.005 + 1e-9), rim
    assert table[None][0] == pytest.approx(1.47)
    for rim in (2, 3):
        assert all(r < 1.0 for r in table[rim])
    assert _rim_pair(2.5, 12, "truncated").mesh_cycle(100).mean < iso


def test_the_rim_is_in_series_with_the_whole_mesh_averaged_over_a_span():
    pair = _rim_pair(3, 8)
    rim, teeth = pair.ring_rim, pair.rigid_rim().mesh_cycle(200)
    assert pair.rigid_rim().gear.ring_rim() is None
    cycle = pair.mesh_cycle(200)
    np.testing.assert_array_equal(cycle.pairs_in_contact, teeth.pairs_in_contact)
    # by hand, on a fine grid of positions along the span (the trapezoidal rule)
    theta = np.linspace(0.0, rim.span, 4001)
    c = rim.compliance(theta, *pair.rim_load())
    k = np.trapezoid(1 / (1 / teeth.stiffness[:, None] + c[None, :]), theta, axis=1) / rim.span
    np.testing.assert_allclose(cycle.stiffness, k, rtol=1e-6)
    # the load at the ring's working pitch circle: its load angle α + γ there, its base circle
    load_angle, base_radius = pair.rim_load()
    assert load_angle == pytest.approx(math.radians(20) + math.pi / (2 * 80), rel=1e-9)
    assert base_radius == pair.gear.base_radius
    # the rim takes the contact away along the line of action: the mesh is softer everywhere
    assert np.all(cycle.stiffness < teeth.stiffness)
    # a helical ring takes its rim the same way, after the slices
    helical = _ring_pair(rim_thickness="6 mm", rim_supports=8, helix_angle="12 deg")
    assert helical.mesh_cycle(100).mean < helical.rigid_rim().mesh_cycle(100).mean


def test_bad_rims_are_refused_naming_the_field_the_value_and_the_fix():
    def ring(**kw):
        return SpurGear(80, "2 mm", "20 mm", name="ring", internal=True, **kw)

    with pytest.raises(ModelError, match=r"field 'rim_thickness': -0.005 m must be positive"):
        ring(rim_thickness="-5 mm", rim_supports=6)
    with pytest.raises(ModelError, match=r"field 'rim_thickness': 0 m must be positive"):
        ring(rim_thickness=0.0, rim_supports=6)
    with pytest.raises(ModelError, match=r"field 'rim_thickness'.*expected a quantity of \[length\]"):
        ring(rim_thickness="5 kg", rim_supports=6)
    with pytest.raises(ModelError, match=r"field 'rim_supports': rim thickness 5 mm .* give rim_supports"):
        ring(rim_thickness="5 mm")
    with pytest.raises(
        ModelError, match=r"field 'rim_thickness': rim_supports = 6 needs .* give rim_thickness"
    ):
        ring(rim_supports=6)
    for bad in (0, 2.5, 81, True, float("nan")):
        with pytest.raises(ModelError, match=r"field 'rim_supports'.*between 1 and 80"):
            ring(rim_thickness="5 mm", rim_supports=bad)
    with pytest.raises(ModelError, match=r"field 'rim_supports': rim_supports = 6 is for an internal gear"):
        SpurGear(40, "2 mm", "20 mm", name="gear", rim_thickness="5 mm", web_width="5 mm", rim_supports=6)
    # an external gear's rim_thickness still needs its web (ISO's C_R); a ring's may come alone
    with pytest.raises(ModelError, match="give both rim_thickness and web_width"):
        SpurGear(40, "2 mm", "20 mm", name="gear", rim_thickness="5 mm")
    with pytest.raises(ModelError, match="give both rim_thickness and web_width"):
        ring(web_width="5 mm")
    assert ring(rim_thickness="5 mm", rim_supports=6.0).rim_supports == 6


def test_a_ring_with_its_rim_from_a_file_runs_says_so_and_saves(tmp_path):
    from conftest import EXAMPLES

    text = (EXAMPLES / "spur_pair.toml").read_text()
    text = text.replace("teeth = 40", "teeth = 80").replace('bore_diameter = "40 mm"\n', "")
    text = text.replace("[mesh]", '[mesh]\nkind = "internal"')
    path = tmp_path / "ring.toml"
    path.write_text(text)
    rigid = gear_pair_stiffness(mechdyn.load(path).model, points=100)
    assert any("ring's rim is taken as rigid" in w and "give rim_thickness" in w for w in rigid.warnings)
    s = rigid.summary()
    assert (
        s["ring_rim_compliance_mean_m_per_N"] is None and s["mesh_stiffness_mean_rigid_rim_N_per_m"] is None
    )
    assert s["mesh_stiffness_iso_ratio"] == pytest.approx(1.466, abs=0.002)
    assert "rigid rim" in rigid.tables()[0].rows[1]

    text = text.replace("teeth = 80", 'teeth = 80\nrim_thickness = "5 mm"\nrim_supports = 12')
    path.write_text(text)
    loaded = mechdyn.load(path)
    ring = loaded.model.gear
    assert (ring.rim_thickness, ring.rim_supports) == (pytest.approx(5e-3), 12)
    result = gear_pair_stiffness(loaded.model, points=100)
    assert not any("taken as rigid" in w for w in result.warnings)
    s = result.summary()
    mean_c, max_c = s["ring_rim_compliance_mean_m_per_N"], s["ring_rim_compliance_max_m_per_N"]
    assert 0 < mean_c < max_c
    assert s["mesh_stiffness_mean_N_per_m"] < s["mesh_stiffness_mean_rigid_rim_N_per_m"]
    assert s["mesh_stiffness_mean_rigid_rim_N_per_m"] == pytest.approx(rigid.cycle.mean, rel=1e-12)
    assert s["mesh_stiffness_iso_ratio"] == pytest.approx(0.636, abs=0.001)  # 2.5 modules, 12 supports
    tables = result.tables()
    assert "rim 5 mm on 12 supports (curved beam)" in tables[0].rows[1]
    rows = {r[0]: r[1] for r in tables[2].rows}
    assert rows["ring rim: compliance, mean over a span between supports"] == pytest.approx(mean_c)
    out = tmp_path / "saved.toml"
    mechdyn.save(loaded.model, out)
    assert "rim_supports = 12" in out.read_text()
    assert mechdyn.load(out).model == loaded.model
    # a rim without its supports, or supports below one, are refused with the file's location
    path.write_text(text.replace("rim_supports = 12", ""))
    with pytest.raises(mechdyn.ModelFileError, match="give rim_supports"):
        mechdyn.load(path)
    path.write_text(text.replace("rim_supports = 12", "rim_supports = 0"))
    with pytest.raises(mechdyn.ModelFileError, match="rim_supports"):
        mechdyn.load(path)
