"""Campbell diagram, forced response and the rigid/flexible comparison."""

from __future__ import annotations

import numpy as np
import pytest

from mechdyn.drivetrain import Disk, Drivetrain, GroundSpring, Shaft, modal
from mechdyn.drivetrain.campbell import campbell
from mechdyn.drivetrain.compare import compare_rigid, mac
from mechdyn.drivetrain.response import ModalDamping, RayleighDamping, frf
from mechdyn.errors import ModelError

# -- Campbell ------------------------------------------------------------------------------------


def test_turret_c_lines_and_mesh_order(turret_c):
    c = campbell(turret_c, ("0 rpm", "6000 rpm"), shaft_orders=(1, 2), mesh_orders=(1,))
    per_rev = {ln.label: ln.per_rev for ln in c.lines}
    # ratio-1 meshes: every shaft line turns at motor speed; the mesh frequency is 19 × motor speed
    # so coinciding lines are merged into one each
    assert per_rev == pytest.approx(
        {
            "1× shaft lines 1–2, 3–5, 6–7": 1.0,
            "2× shaft lines 1–2, 3–5, 6–7": 2.0,
            "1× mesh frequency of mesh 1 (19/19 teeth), mesh 2 (19/19 teeth)": 19.0,
        }
    )


def test_turret_b_speed_ratios_follow_the_tooth_ratios(turret_b):
    c = campbell(turret_b, ("0 rpm", "6000 rpm"), shaft_orders=(1,))
    per_rev = {ln.label: ln.per_rev for ln in c.lines}
    assert per_rev == pytest.approx(
        {"1× shaft line 1–2": 1.0, "1× shaft line 3–4": 1 / 4, "1× shaft line 5–6": 1 / 24}
    )
    assert not [ln for ln in c.lines if ln.kind == "mesh"]  # the teeth were not published


def test_crossings_are_exactly_where_order_times_speed_equals_a_natural_frequency(turret_c):
    lo, hi = 0.0, 6000 * 2 * np.pi / 60
    c = campbell(turret_c, (lo, hi), shaft_orders=(1, 2), mesh_orders=(1, 2))
    found = {(x["line"], x["mode"]) for x in c.crossings}
    expected = set()
    for ln in c.lines:
        for m, f in enumerate(c.modal.frequencies_hz):
            if ln.frequency_hz(lo) <= f <= ln.frequency_hz(hi):
                expected.add((ln.label, m + 1))
    assert found == expected and found  # at 6000 rpm the 19× and 38× mesh lines reach modes 1–4
    for x in c.crossings:
        per_rev = next(ln.per_rev for ln in c.lines if ln.label == x["line"])
        assert per_rev * x["speed_rpm"] / 60 == pytest.approx(x["frequency_hz"], rel=1e-12)


def test_campbell_reference_disk_scales_the_speeds(turret_b):
    a = campbell(turret_b, ("0 rpm", "6000 rpm"), reference="1")
    b = campbell(turret_b, ("0 rpm", "250 rpm"), reference="6")  # disk 6 turns 24× slower
    la = {ln.label: ln.per_rev for ln in a.lines}
    lb = {ln.label: ln.per_rev for ln in b.lines}
    assert lb["1× shaft line 1–2"] == pytest.approx(24 * la["1× shaft line 1–2"])
    with pytest.raises(ModelError, match="reference disk 'x' is not defined"):
        campbell(turret_b, ("0 rpm", "10 rpm"), reference="x")
    with pytest.raises(ModelError, match="speed range"):
        campbell(turret_b, ("100 rpm", "10 rpm"))


# -- forced response -----------------------------------------------------------------------------


def _single(J=0.02, k=8e4):
    return Drivetrain([Disk("d", J)], [GroundSpring("k", "d", k)]), J, k


def test_frf_single_dof_rayleigh_matches_closed_form():
    # |Θ/T| = 1 / √((k − ω²J)² + (ω c)²), c = α J + β k (Rayleigh)
    dt, J, k = _single()
    alpha, beta = 3.0, 2e-5
    f = np.linspace(1, 600, 500)
    r = frf(dt, f, {"d": 1.0}, damping=RayleighDamping(alpha, beta))
    w = 2 * np.pi * f
    c = alpha * J + beta * k
    np.testing.assert_allclose(r.angles[:, 0], 1 / (k - w**2 * J + 1j * w * c), rtol=1e-12)
    # the spring torque equals kΘ
    np.testing.assert_allclose(r.element_loads[:, 0], k * r.angles[:, 0], rtol=1e-12)


def test_frf_single_dof_modal_damping_matches_closed_form():
    dt, J, k = _single()
    zeta = 0.05
    wn = np.sqrt(k / J)
    f = np.geomspace(1, 1000, 300)
    w = 2 * np.pi * f
    r = frf(dt, f, {"d": "2 N*m"}, damping=ModalDamping(zeta))
    np.testing.assert_allclose(r.angles[:, 0], 2 / (k - w**2 * J + 2j * zeta * wn * J * w), rtol=1e-10)
    _, at = r.peak("d")
    assert at == pytest.approx(wn * np.sqrt(1 - 2 * zeta**2) / (2 * np.pi), rel=0.02)


def test_frf_equals_modal_superposition_with_the_rigid_body_mode(turret_c):
    zeta = np.linspace(0.01, 0.06, 6)
    f = np.geomspace(50, 5e4, 400)
    w = 2 * np.pi * f
    r = frf(turret_c, f, {"7": 1.0}, damping=ModalDamping(tuple(zeta)))
    m = modal(turret_c)
    phi = m.shapes
    H = (
        (
            phi[:, None, :]
            * phi[6][None, None, :]
            / (m.omega**2 - w[:, None] ** 2 + 2j * zeta * m.omega * w[:, None])[None]
        )
        .sum(-1)
        .T
    )
    psi = m.rigid_body_shapes[:, 0] / np.sqrt(turret_c.inertias @ m.rigid_body_shapes[:, 0] ** 2)
    H = H + np.outer(-1 / w**2, psi * psi[6])
    np.testing.assert_allclose(r.angles, H, rtol=1e-7, atol=1e-12 * np.abs(H).max())


def test_quasi_static_shaft_torque_of_a_free_pair():
    # far below resonance a free pair accelerates as one body: shaft torque = T J_b / (J_a + J_b)
    Ja, Jb = 1e-3, 3e-3
    dt = Drivetrain([Disk("a", Ja), Disk("b", Jb)], [Shaft("s", ("a", "b"), 1e5)])
    r = frf(dt, [0.01], {"a": 10.0}, damping=ModalDamping(0.0))
    assert abs(r.element_loads[0, 0]) == pytest.approx(10 * Jb / (Ja + Jb), rel=1e-6)


def test_frf_bad_input(turret_c):
    with pytest.raises(ModelError, match="disk 'x', which is not defined"):
        frf(turret_c, [10.0], {"x": 1.0})
    with pytest.raises(ModelError, match="no static response at 0 Hz"):
        frf(turret_c, [0.0, 10.0], {"1": 1.0})
    with pytest.raises(ModelError, match="3 modal damping ratios given for 6"):
        frf(turret_c, [10.0], {"1": 1.0}, damping=ModalDamping((0.01, 0.02, 0.03)))
    with pytest.raises(ModelError, match="modal damping ratio"):
        ModalDamping(1.5)


def test_rayleigh_from_ratios_gives_the_ratio_at_both_frequencies():
    d = RayleighDamping.from_ratios(100.0, 1000.0, 0.03)
    for f in (100.0, 1000.0):
        w = 2 * np.pi * f
        assert d.alpha / (2 * w) + d.beta * w / 2 == pytest.approx(0.03)


# -- rigid against flexible ------------------------------------------------------------------------


def test_mac_properties():
    rng = np.random.default_rng(1)
    a = rng.normal(size=(6, 3))
    np.testing.assert_allclose(np.diag(mac(a, -2.5 * a)), 1.0)
    q, _ = np.linalg.qr(rng.normal(size=(6, 6)))
    np.testing.assert_allclose(mac(q, q), np.eye(6), atol=1e-12)


def test_turret_b_comparison_pairs_by_shape(turret_b):
    cmp = compare_rigid(turret_b)
    rows = cmp.rows
    assert [r["rigid_mode"] for r in rows] == [1, 2, 3, None, None]  # two mesh modes have no rigid twin
    assert all(r["mac"] > 0.99 for r in rows[:3])
    assert [r["dominant_element"] for r in rows[3:]] == ["mesh 2", "mesh 1"]
    assert rows[0]["change_percent"] == pytest.approx(-7.62, abs=0.01)


def test_turret_b_mode_shift_is_mostly_the_published_ratio_inconsistency(turret_b):
    # Of the −7.6 % on mode 1, the rigid model with the base-radius ratios (4.32, 6.59) already takes
    # −6.7 %; the mesh stiffness itself moves mode 1 by only −1.0 %, but mode 2 by −7.2 %.
    from dataclasses import replace

    from mechdyn.drivetrain import GearMesh

    radii_only = tuple(
        GearMesh(e.name, e.disks, kind=e.kind, base_radii=e.base_radii) if isinstance(e, GearMesh) else e
        for e in turret_b.elements
    )
    rigid_radii = modal(replace(turret_b, elements=radii_only)).frequencies_hz
    rigid_teeth = modal(turret_b, rigid_gears=True).frequencies_hz
    flexible = modal(turret_b).frequencies_hz
    assert 100 * (rigid_radii[0] / rigid_teeth[0] - 1) == pytest.approx(-6.68, abs=0.01)
    assert 100 * (flexible[0] / rigid_radii[0] - 1) == pytest.approx(-1.01, abs=0.01)
    assert 100 * (flexible[1] / rigid_radii[1] - 1) == pytest.approx(-7.20, abs=0.01)


def test_comparison_pairs_by_shape_not_by_index():
    # a soft mesh puts the mesh mode (≈ 6 Hz) *below* the shaft mode (≈ 45 Hz): pairing by index
    # would match the rigid model's only mode (39 Hz) with the mesh mode
    from mechdyn.drivetrain import GearMesh

    dt = Drivetrain(
        [Disk("a", 1.0), Disk("b", 1.0), Disk("c", 1.0)],
        [Shaft("s", ("a", "b"), 4e4), GearMesh("g", ("b", "c"), base_radii=(0.1, 0.1), stiffness=1e5)],
    )
    cmp = compare_rigid(dt)
    assert cmp.flexible.frequencies_hz[0] < cmp.rigid.frequencies_hz[0] < cmp.flexible.frequencies_hz[1]
    assert cmp.pairs == ((0, None), (1, 0))
    assert cmp.rows[0]["dominant_element"] == "g"


def test_damped_shaft_torque_includes_the_damper():
    # one disk held by a damped shaft to a very heavy disk: torque = (k + iωc)(θ_b − θ_a)
    dt = Drivetrain([Disk("a", 0.01), Disk("b", 1e6)], [Shaft("s", ("a", "b"), 1e4, damping=5.0)])
    r = frf(dt, [20.0, 80.0], {"a": 1.0}, damping=ModalDamping(0.0))
    w = 2 * np.pi * np.array([20.0, 80.0])
    expected = (1e4 + 1j * w * 5.0) * (r.angles[:, 1] - r.angles[:, 0])
    np.testing.assert_allclose(r.element_loads[:, 0], expected, rtol=1e-12)
