"""Drivetrain modes against closed forms (tight tolerances: these are exact solutions)."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from mechdyn.drivetrain import Disk, Drivetrain, GearMesh, GroundSpring, Shaft, modal

SOLVERS = ["dense", "banded", "sparse"]


def test_two_inertia_free():
    # ω² = k (1/J1 + 1/J2); shape θ2/θ1 = −J1/J2 (e.g. Rao, Mechanical Vibrations, §5.3)
    J1, J2, k = 2.0, 3.0, 600.0
    r = modal(Drivetrain([Disk("a", J1), Disk("b", J2)], [Shaft("s", ("a", "b"), k)]))
    assert r.rigid_body_modes == 1
    assert r.omega == pytest.approx([np.sqrt(k * (1 / J1 + 1 / J2))], rel=1e-13)
    assert r.shapes[1, 0] / r.shapes[0, 0] == pytest.approx(-J1 / J2, rel=1e-12)
    np.testing.assert_allclose(r.rigid_body_shapes[:, 0], [1.0, 1.0])


@pytest.mark.parametrize("n", [2.0, 3.5, 0.25])
def test_geared_two_inertia_rigid_mesh(n):
    # J1 –k– J2 =rigid mesh θ2 = −n θ3= J3: the driven side adds J3/n², so ω² = k (1/J1 + 1/(J2 + J3/n²))
    J1, J2, J3, k = 1e-3, 2e-4, 5e-2, 4e3
    dt = Drivetrain(
        [Disk("1", J1), Disk("2", J2), Disk("3", J3)],
        [Shaft("s", ("1", "2"), k), GearMesh("g", ("2", "3"), ratio=n)],
    )
    r = modal(dt)
    assert r.omega == pytest.approx([np.sqrt(k * (1 / J1 + 1 / (J2 + J3 / n**2)))], rel=1e-12)
    # the disk removed by the constraint is recovered: θ3 = −θ2 / n (external mesh)
    assert r.shapes[2, 0] == pytest.approx(-r.shapes[1, 0] / n, rel=1e-12)
    rb = r.rigid_body_shapes[:, 0]
    assert rb / rb[0] == pytest.approx([1.0, 1.0, -1.0 / n], rel=1e-12)


@pytest.mark.parametrize("kind", ["external", "internal"])
def test_geared_two_inertia_flexible_mesh(kind):
    # k_c on δ = r_a θ_a ± r_b θ_b: ω² = k_c (r_a²/J_a + r_b²/J_b), no-load motion θ_b = ∓(r_a/r_b) θ_a
    Ja, Jb, ra, rb, kc = 2e-4, 3e-2, 0.03, 0.12, 2e9
    dt = Drivetrain(
        [Disk("a", Ja), Disk("b", Jb)],
        [GearMesh("g", ("a", "b"), kind=kind, base_radii=(ra, rb), stiffness=kc)],
    )
    r = modal(dt)
    assert r.omega == pytest.approx([np.sqrt(kc * (ra**2 / Ja + rb**2 / Jb))], rel=1e-12)
    sign = -1.0 if kind == "external" else 1.0
    assert r.rigid_body_shapes[1, 0] / r.rigid_body_shapes[0, 0] == pytest.approx(sign * ra / rb, rel=1e-12)


def _chain(n: int, J: float = 0.01, k: float = 1e4, grounded: bool = False) -> Drivetrain:
    disks = [Disk(f"d{i}", J) for i in range(n)]
    elements = [Shaft(f"s{i}", (f"d{i}", f"d{i + 1}"), k) for i in range(n - 1)]
    if grounded:
        elements.append(GroundSpring("ground", "d0", k))
    return Drivetrain(disks, elements)


@pytest.mark.parametrize("solver", SOLVERS)
def test_free_chain_all_solvers(solver):
    # N equal disks and shafts, free–free: ω_j = 2 √(k/J) sin(jπ/2N), j = 1..N−1
    n, J, k = 60, 0.01, 1e4
    r = modal(_chain(n, J, k), solver=solver, n_modes=8 if solver == "sparse" else None)
    j = np.arange(1, r.omega.size + 1)
    exact = 2 * np.sqrt(k / J) * np.sin(j * np.pi / (2 * n))
    np.testing.assert_allclose(r.omega, exact, rtol=1e-9)
    assert r.rigid_body_modes == 1
    # mass-normalised shapes: Φᵀ M Φ = I
    np.testing.assert_allclose(r.shapes.T @ (J * r.shapes), np.eye(r.omega.size), atol=1e-9)


@pytest.mark.parametrize("solver", SOLVERS)
def test_grounded_chain_all_solvers(solver):
    # N masses, a spring to ground at one end (fixed–free): ω_j = 2 √(k/J) sin((2j−1)π / (2(2N+1)))
    n, J, k = 40, 0.02, 5e3
    r = modal(_chain(n, J, k, grounded=True), solver=solver, n_modes=6 if solver == "sparse" else None)
    j = np.arange(1, r.omega.size + 1)
    exact = 2 * np.sqrt(k / J) * np.sin((2 * j - 1) * np.pi / (2 * (2 * n + 1)))
    np.testing.assert_allclose(r.omega, exact, rtol=1e-9)
    assert r.rigid_body_modes == 0


@pytest.mark.parametrize("solver", ["auto", "banded", "sparse"])
def test_large_chain_lowest_modes(solver):
    n, J, k = 20_000, 0.01, 1e4
    r = modal(_chain(n, J, k), n_modes=5, solver=solver)
    assert r.solver == ("banded" if solver == "auto" else solver)
    exact = 2 * np.sqrt(k / J) * np.sin(np.arange(1, 6) * np.pi / (2 * n))
    np.testing.assert_allclose(r.omega, exact, rtol=1e-7)


def _geared(kc: float | None) -> Drivetrain:
    # a consistent geared chain: ratio from the base radii alone, so the rigid limit is exact
    return Drivetrain(
        [Disk("m", 7e-4), Disk("p", 4e-5), Disk("g", 3e-3), Disk("q", 6e-5), Disk("h", 3e-2), Disk("t", 1.4)],
        [
            Shaft("s1", ("m", "p"), 7e4),
            GearMesh("g1", ("p", "g"), base_radii=(0.0315, 0.136), stiffness=kc),
            Shaft("s2", ("g", "q"), 9.5e5),
            GearMesh("g2", ("q", "h"), kind="internal", base_radii=(0.034, 0.224), stiffness=kc),
            Shaft("s3", ("h", "t"), 5.7e6),
        ],
    )


def test_rigid_reduction_is_the_stiff_mesh_limit():
    rigid = modal(_geared(None))
    assert rigid.omega.size == 3
    errors = []
    for kc in (1e10, 1e11, 1e12, 1e13):
        flex = modal(_geared(kc))
        assert flex.omega.size == 5  # two extra mesh modes
        errors.append(np.max(np.abs(flex.omega[:3] / rigid.omega - 1)))
        # the shapes converge too, on every disk (including those the reduction removed)
        shapes = flex.unit_shapes[:, :3]
        np.testing.assert_allclose(shapes, rigid.unit_shapes, atol=max(10 * errors[-1], 1e-9))
    assert errors[-1] < 5e-5
    # first-order convergence in 1/k_c: each factor 10 in stiffness cuts the error about 10×
    # (beyond 1e13 N/m the mesh modes sit 1e5 above the shaft modes and round-off takes over)
    assert all(b < a / 8 for a, b in itertools.pairwise(errors))


def test_with_rigid_gears_matches_a_rigid_model():
    a = modal(_geared(2e9), rigid_gears=True)
    b = modal(_geared(None))
    np.testing.assert_allclose(a.omega, b.omega, rtol=1e-12)


PUBLISHED_B = [  # h, D_o, D_i (m), J (1e-3 kg m²), with disk 6 at the h its J implies
    (0.017, 0.027, 0.010, 0.00684032),
    (0.025, 0.035, 0.010, 0.02875616),
    (0.025, 0.140, 0.115, 4.03689425),
    (0.0265, 0.045, 0.032, 0.06241081),
    (0.0265, 0.228, 0.180, 33.79323924),
    (0.070, 0.406, 0.205, 1372.25988504),
]
PUBLISHED_C = [
    (0.05, 0.065, 0.020, 0.68255181),
    (0.0143, 0.0445, 0.006, 0.04325686),
    (0.025, 0.035, 0.022, 0.02442996),
    (0.0175, 0.0445, 0.006, 0.05293671),
    (0.0143, 0.0445, 0.006, 0.04325686),
    (0.0163, 0.0445, 0.006, 0.04930677),
    (0.03, 0.031, 0.014, 0.02048984),
]
PUBLISHED_SHAFTS = [  # d, l (m), K (1e6 N m/rad)
    (0.019, 0.015, 0.06889183),
    (0.036, 0.014, 0.95131987),
    (0.1095, 0.2, 5.69995046),
    (0.03, 0.24, 0.02676199),
    (0.028, 0.185, 0.02634541),
    (0.01, 0.014, 0.00566391),
    (0.025, 0.03, 0.10324841),
]


@pytest.mark.parametrize(("h", "do", "di", "J"), PUBLISHED_B + PUBLISHED_C)
def test_disk_geometry_reproduces_the_published_inertias(h, do, di, J):
    # J = ρ h π (D_o⁴ − D_i⁴)/32 with ρ = 7860 kg/m³ reproduces every printed J to 1e-6
    d = Disk.from_geometry(
        "d", thickness=f"{h} m", outer_diameter=f"{do} m", inner_diameter=f"{di} m", density="7860 kg/m^3"
    )
    assert d.inertia == pytest.approx(J * 1e-3, rel=1e-6)


def test_published_disk_6_thickness_is_a_typing_error():
    printed = Disk.from_geometry(
        "6", thickness=0.0265, outer_diameter=0.406, inner_diameter=0.205, density=7860.0
    )
    assert printed.inertia / 1.37225988504 == pytest.approx(0.3786, abs=1e-3)


@pytest.mark.parametrize(("d", "length", "K"), PUBLISHED_SHAFTS)
def test_shaft_geometry_reproduces_the_published_stiffness(d, length, K):
    # K = G π d⁴ / (32 l) with G = 80.769 GPa reproduces every printed K to 1e-6
    s = Shaft.from_geometry(
        "s", ("a", "b"), length=f"{length} m", diameter=f"{d * 1000} mm", shear_modulus="80.769 GPa"
    )
    assert s.stiffness == pytest.approx(K * 1e6, rel=1e-6)


def test_hollow_shaft():
    s = Shaft.from_geometry(
        "s", ("a", "b"), length=1.0, diameter=0.04, inner_diameter=0.03, shear_modulus=80e9
    )
    assert s.stiffness == pytest.approx(80e9 * np.pi * (0.04**4 - 0.03**4) / 32)
