"""Internal gear pairs: geometry of the ring, path of contact, the ring's tooth, the mesh cycle, files."""

from __future__ import annotations

import math

import numpy as np
import pytest

import mechdyn
from mechdyn.errors import ModelError
from mechdyn.gears import GearPair, SpurGear, iso_stiffness
from mechdyn.gears.results import gear_pair_stiffness

pytestmark = pytest.mark.filterwarnings("ignore:.*range of the Sainsot fit:mechdyn.errors.ModelWarning")


def _ring_pair(z1=20, z2=80, model="involute", **ring):
    return GearPair(
        SpurGear(z1, "2 mm", "20 mm", bore_diameter="20 mm", name="pinion"),
        SpurGear(z2, "2 mm", "20 mm", name="ring", internal=True, **ring),
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
