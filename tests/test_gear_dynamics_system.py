"""The time-domain gear system: matrices equal to the drivetrain's, mesh geometry and sign convention,
the backlash force, and the profile harmonics against closed forms."""

from __future__ import annotations

import numpy as np
import pytest

from mechdyn.drivetrain import Disk, Drivetrain, GearMesh, GroundSpring, Shaft
from mechdyn.errors import ModelError
from mechdyn.gear_dynamics import GearSystem, rectangular_profile


def _train(kind: str = "external", *, grounded: bool = False, damping: float = 0.0) -> Drivetrain:
    """Motor — shaft — pinion ~ flexible mesh ~ gear — shaft — pinion2 = rigid mesh = gear2 — flexible
    internal mesh ~ ring — shaft — load."""
    disks = [
        Disk("motor", 0.05),
        Disk("pinion", 0.002),
        Disk("gear", 0.03),
        Disk("pinion2", 0.004),
        Disk("gear2", 0.06),
        Disk("ring", 0.2),
        Disk("load", 1.5),
    ]
    elements = [
        Shaft("s1", ("motor", "pinion"), 2.0e4, damping=3.0),
        GearMesh(
            "m1",
            ("pinion", "gear"),
            teeth=(20, 50),
            base_radii=(0.0188, 0.047),
            stiffness=3e8,
            damping=damping,
        ),
        Shaft("s2", ("gear", "pinion2"), 5.0e4),
        GearMesh("m2", ("pinion2", "gear2"), teeth=(18, 36)),
        GearMesh("m3", ("gear2", "ring"), kind=kind, teeth=(30, 90), base_radii=(0.03, 0.09), stiffness=5e8),
        Shaft("s3", ("ring", "load"), 1.0e5),
    ]
    if grounded:
        elements.append(GroundSpring("clamp", "load", 1e6))
    return Drivetrain(disks, elements, name="test train")


@pytest.mark.parametrize("kind", ["external", "internal"])
@pytest.mark.parametrize("grounded", [False, True])
def test_mean_matrices_are_the_assembly(kind, grounded):
    dt = _train(kind, grounded=grounded, damping=250.0)
    system = GearSystem.from_drivetrain(dt)
    asm = dt.assembly
    K, C = asm.K.toarray(), asm.C.toarray()
    assert np.abs(system.K_mean - K).max() <= 1e-12 * np.abs(K).max()
    assert np.abs(system.C_mean - C).max() <= 1e-12 * np.abs(C).max()
    np.testing.assert_array_equal(np.diag(system.M), asm.mass)
    assert system.coordinate_names == asm.coordinate_names
    # the rigid mesh m2 is reduced out: one coordinate fewer than disks
    assert system.n == len(dt.disks) - 1
    assert [m.name for m in system.meshes] == ["m1", "m3"]
    # the structure alone carries no mesh stiffness
    for m in system.meshes:
        assert abs(m.g @ system.K @ m.g) < abs(m.g @ system.K_mean @ m.g)


@pytest.mark.parametrize("kind, sign", [("external", 1.0), ("internal", -1.0)])
def test_deflection_row_from_base_radii_and_sign(kind, sign):
    dt = Drivetrain(
        [Disk("a", 0.01), Disk("b", 0.05)],
        [GearMesh("m", ("a", "b"), kind=kind, teeth=(20, 40), base_radii=(0.02, 0.04), stiffness=1e8)],
    )
    system = GearSystem.from_drivetrain(dt)
    (mesh,) = system.meshes
    np.testing.assert_array_equal(mesh.g, [0.02, sign * 0.04])
    np.testing.assert_array_equal(mesh.phase_row, [1.0, 0.0])
    assert mesh.teeth == 20 and mesh.backlash is None
    # δ of a pure rotation of a alone is r_a θ_a; the mesh phase counts teeth of a
    q = np.array([2 * np.pi / 20, 0.0])
    assert mesh.g @ q == pytest.approx(0.02 * 2 * np.pi / 20)
    assert system.mesh_phases(q) == pytest.approx([1.0])
    # the rigid rotation turns b by ∓ r_a / r_b and does not deflect the mesh
    np.testing.assert_allclose(system.speed_ratios("a"), [1.0, -sign * 0.5])
    assert mesh.g @ system.speed_ratios("a") == pytest.approx(0.0, abs=1e-15)


def test_mesh_through_rigid_reduction_and_rigid_body():
    dt = _train()
    system = GearSystem.from_drivetrain(dt)
    asm = dt.assembly
    m3 = system.meshes[1]
    # g = Tᵀ v with v on the full disk vector
    v = np.zeros(len(dt.disks))
    v[dt.disk_index["gear2"]], v[dt.disk_index["ring"]] = 0.03, 0.09
    np.testing.assert_allclose(m3.g, asm.T.toarray().T @ v)
    # gear2 follows pinion2 through the rigid mesh: θ_gear2 = −θ_pinion2 / 2
    np.testing.assert_allclose(m3.phase_row, system.T[dt.disk_index["gear2"]])
    assert system.rigid_body.shape == (system.n, 1)
    r = system.rigid_body[:, 0]
    assert np.abs(system.K_mean @ r).max() <= 1e-12 * np.abs(system.K_mean).max() * np.abs(r).max()
    for m in system.meshes:
        assert abs(m.g @ r) <= 1e-15
    # the varying stiffness, at any phase, still does not resist the rigid rotation
    assert np.abs(system.K_at([0.3, 0.7]) @ r).max() <= 1e-12 * np.abs(system.K_mean).max()
    grounded = GearSystem.from_drivetrain(_train(grounded=True))
    assert grounded.rigid_body.shape == (grounded.n, 0)
    with pytest.raises(ModelError, match="does not turn freely"):
        grounded.speed_ratios("motor")


def test_input_vector_is_the_disks_row_of_T():
    dt = _train()
    system = GearSystem.from_drivetrain(dt)
    u = system.input_vector("gear2")
    assert u @ system.speed_ratios("motor") == pytest.approx(system.T[4] @ system.speed_ratios("motor"))
    np.testing.assert_array_equal(u, dt.assembly.T.toarray()[dt.disk_index["gear2"]])
    with pytest.raises(ModelError, match="'nowhere' is not a disk"):
        system.input_vector("nowhere")


def test_backlash_force_is_piecewise():
    dt = Drivetrain(
        [Disk("a", 0.01), Disk("b", 0.05)],
        [GearMesh("m", ("a", "b"), teeth=(20, 40), base_radii=(0.02, 0.04), stiffness=1e8, damping=50.0)],
    )
    system = GearSystem.from_drivetrain(dt, backlash={"m": "100 um"})
    (mesh,) = system.meshes
    k, c, b = 1e8, 50.0, mesh.backlash
    assert b == pytest.approx(1e-4)
    assert mesh.force(2e-5, 0.1, 0.3, 10.0) == pytest.approx(k * 2e-5 + c * 0.1)  # drive side
    assert mesh.force(-5e-5, 0.1, 0.3, 10.0) == 0.0  # in the gap
    assert mesh.force(0.0, 0.1, 0.3, 10.0) == 0.0
    assert mesh.force(-b, 0.1, 0.3, 10.0) == 0.0
    assert mesh.force(-b - 3e-5, -0.2, 0.3, 10.0) == pytest.approx(-k * 3e-5 - c * 0.2)  # back side
    linear = GearSystem.from_drivetrain(dt).meshes[0]
    assert linear.force(-5e-5, 0.0, 0.3, 10.0) == pytest.approx(-k * 5e-5)


def test_force_with_varying_stiffness_and_error():
    dt = Drivetrain(
        [Disk("a", 0.01), Disk("b", 0.05)],
        [GearMesh("m", ("a", "b"), teeth=(20, 40), base_radii=(0.02, 0.04), stiffness=1e8, damping=50.0)],
    )
    amp = 4e-6
    system = GearSystem.from_drivetrain(
        dt, mesh_profiles={"m": {"fluctuation": 0.4, "contact_ratio": 1.5}}, errors={"m": {"amplitude": amp}}
    )
    (mesh,) = system.meshes
    assert mesh.samples == 360 and mesh.profile.mean() == pytest.approx(1.0, abs=1e-14)
    assert mesh.stiffness(0.2) == pytest.approx(1e8 * 1.2)  # double contact (2 − ε) f above the mean
    assert mesh.stiffness(0.7) == pytest.approx(1e8 * 0.8)
    assert mesh.stiffness(1.7) == pytest.approx(1e8 * 0.8)  # periodic
    assert mesh.transmission_error(0.25) == pytest.approx(amp)
    # e′ = 2π A cos(2π τ) within the interpolation error
    tau, rate = 0.1, 30.0
    e_slope = 2 * np.pi * amp * np.cos(2 * np.pi * tau)
    f = mesh.force(1e-5, 0.02, tau, rate)
    x = 1e-5 - mesh.transmission_error(tau)
    assert f == pytest.approx(1e8 * 1.2 * x + 50.0 * (0.02 - e_slope * rate), rel=1e-4)
    K = system.K_at([0.7])
    np.testing.assert_allclose(K, 0.8e8 * np.outer(mesh.g, mesh.g))


def test_rectangular_wave_harmonics_against_its_fourier_series():
    eps, f, p = 1.625, 0.3, 256
    d = eps - 1.0
    dt = Drivetrain(
        [Disk("a", 0.01), Disk("b", 0.05)],
        [GearMesh("m", ("a", "b"), teeth=(20, 40), base_radii=(0.02, 0.04), stiffness=1e8)],
    )
    profile = {"fluctuation": f, "contact_ratio": eps, "samples": p}
    (mesh,) = GearSystem.from_drivetrain(dt, mesh_profiles={"m": profile}).meshes
    c = mesh.harmonics(12)
    h = np.arange(1, 13)
    # ideal wave 1 + f (1[0 ≤ τ < d] − d): one-sided c_h = 2 f (1 − exp(−2πi h d)) / (2πi h)
    ideal = 2 * f * (1 - np.exp(-2j * np.pi * h * d)) / (2j * np.pi * h)
    # sampled at τ = i/P and joined by straight lines, each jump becomes a ramp of width 1/P: the ideal
    # wave shifted by −1/(2P) and averaged over 1/P, i.e. × exp(iπh/P) sinc(h/P)
    sampled = ideal * np.exp(1j * np.pi * h / p) * np.sinc(h / p)
    assert c[0] == pytest.approx(1.0, abs=1e-14)
    np.testing.assert_allclose(c[1:], sampled, atol=1e-13)
    np.testing.assert_allclose(c[1:], ideal, atol=2 * np.pi * f * 12 / p)
    # the series rebuilds the interpolated profile (to the truncation of the series, far from jumps)
    tau = np.array([0.2, 0.4, 0.8])
    series = np.real(np.exp(2j * np.pi * np.outer(tau, np.arange(2001))) @ mesh.harmonics(2000))
    np.testing.assert_allclose(series, mesh.stiffness(tau) / 1e8, atol=2e-3)


def test_profile_from_a_gear_pairs_mesh_cycle():
    from mechdyn.gears import GearPair, SpurGear

    pair = GearPair(
        SpurGear(20, 0.002, 0.02, name="pinion"),
        SpurGear(40, 0.002, 0.02, name="gear"),
        tooth_model="truncated",
    )
    cycle = pair.mesh_cycle(64)
    dt = Drivetrain(
        [Disk("a", 0.01), Disk("b", 0.05)], [GearMesh.from_gear_pair("m", ("a", "b"), pair, points=64)]
    )
    (mesh,) = GearSystem.from_drivetrain(dt, mesh_profiles={"m": cycle}).meshes
    assert mesh.mean_stiffness == pytest.approx(cycle.mean)
    np.testing.assert_allclose(mesh.stiffness(np.arange(64) / 64), cycle.stiffness, rtol=1e-12)
    np.testing.assert_allclose(mesh.g, [pair.pinion.base_radius, pair.gear.base_radius])
    assert mesh.teeth == 20


def test_rectangular_profile_has_mean_one_and_its_shares():
    p = rectangular_profile(0.5, 1.4, 100)
    assert p.mean() == pytest.approx(1.0, abs=1e-14)
    assert np.ptp(p) == pytest.approx(0.5)
    assert np.mean(p > 1) == pytest.approx(0.4)


@pytest.mark.parametrize(
    "kwargs, element, field",
    [
        ({"mesh_profiles": {"m9": np.ones(4)}}, "m9", "mesh_profiles"),
        ({"backlash": {"m": -1e-5}}, "m", "backlash"),
        ({"backlash": {"m": "3 kg"}}, "m", "backlash"),
        ({"errors": {"m": {"amp": 1e-6}}}, "m", "errors"),
        ({"mesh_profiles": {"m": [1.0, -0.5, 1.0]}}, "m", "mesh_profiles"),
        ({"mesh_profiles": {"m": {"fluctuation": 0.3}}}, "m", "mesh_profiles"),
        (
            {"mesh_profiles": {"m": {"fluctuation": 0.3, "contact_ratio": 2.5}}},
            "mesh profile",
            "contact_ratio",
        ),
    ],
)
def test_bad_input_names_the_mesh_and_field(kwargs, element, field):
    dt = Drivetrain(
        [Disk("a", 0.01), Disk("b", 0.05)],
        [GearMesh("m", ("a", "b"), teeth=(20, 40), base_radii=(0.02, 0.04), stiffness=1e8)],
    )
    with pytest.raises(ModelError) as info:
        GearSystem.from_drivetrain(dt, **kwargs)
    assert info.value.element == element and info.value.field == field


def test_varying_profile_needs_teeth():
    dt = Drivetrain(
        [Disk("a", 0.01), Disk("b", 0.05)],
        [GearMesh("m", ("a", "b"), base_radii=(0.02, 0.04), stiffness=1e8)],
    )
    assert GearSystem.from_drivetrain(dt).meshes[0].teeth == 0
    with pytest.raises(ModelError, match="needs the gears' teeth"):
        GearSystem.from_drivetrain(dt, errors={"m": {"amplitude": 1e-6}})


def test_shafts_with_inertia_and_inner_nodes():
    """A shaft with its own (consistent) inertia, divided into elements: M is the assembly's (not
    diagonal), the nodes inside the shaft are rows of T, and the matrices still match."""
    dt = Drivetrain(
        [Disk("motor", 0.05), Disk("a", 0.001), Disk("b", 0.004)],
        [
            Shaft("s", ("motor", "a"), 2e4, inertia=0.002, elements=3),
            GearMesh("m", ("a", "b"), teeth=(20, 40), base_radii=(0.02, 0.04), stiffness=1e8),
        ],
    )
    system = GearSystem.from_drivetrain(dt)
    asm = dt.assembly
    np.testing.assert_allclose(system.M, asm.M.toarray(), rtol=0, atol=0)
    assert np.count_nonzero(system.M - np.diag(np.diag(system.M))) > 0
    K = asm.K.toarray()
    assert np.abs(system.K_mean - K).max() <= 1e-12 * np.abs(K).max()
    assert system.T.shape[0] == len(dt.dof_names) == 5
    r = system.rigid_body[:, 0]
    assert np.abs(system.K_mean @ r).max() <= 1e-12 * np.abs(K).max()
