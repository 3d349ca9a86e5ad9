"""Natural frequencies of ill-conditioned drivetrains against a 60-digit reference.

Inertias or stiffnesses spread over many decades make the fast eigen paths lose the low frequencies
(their error is absolute, about ε‖M^-½ K M^-½‖); :func:`mechdyn.drivetrain.modal` must give every
flexible frequency to 1e-6 (relative) or warn with the condition estimate. The reference is written
here, independently of mechdyn, in mpmath at 60 digits: Sturm-sequence bisection on the tridiagonal
M^-½ K M^-½ of a chain, and ``mpmath.eigsy`` for small branched models.
"""

from __future__ import annotations

import warnings

import mpmath
import numpy as np
import pytest

from mechdyn.drivetrain import Disk, Drivetrain, GearMesh, GroundSpring, Shaft, assemble, modal
from mechdyn.errors import ModelWarning
from mechdyn.vibration import solve_eigen

RTOL = 1e-6  # promised on every flexible natural frequency
DPS = 60

# -- the reference: plain mpmath, nothing from mechdyn ------------------------------------------------


def _chain_reference(J, links, grounds=(), n_rigid=1, modes=None):
    """Lowest flexible ω (rad/s) of a chain, Sturm bisection at 60 digits.

    Coordinate p has inertia J[p]; links[p] = (c_a, c_b, k) is the spring k (c_a θ_p + c_b θ_(p+1))²/2
    between p and p + 1; grounds holds (p, k), springs k θ_p²/2. A = M^-½ K M^-½ is tridiagonal:
    A_pp = Σ k c²/J_p, A_(p,p+1)² = (k c_a c_b)²/(J_p J_(p+1)).
    """
    with mpmath.workdps(DPS):
        m = [mpmath.mpf(float(v)) for v in J]
        n = len(m)
        K_diag = [mpmath.mpf(0)] * n
        off2 = []
        for p, (ca, cb, k) in enumerate(links):
            ca, cb, k = mpmath.mpf(float(ca)), mpmath.mpf(float(cb)), mpmath.mpf(float(k))
            K_diag[p] += k * ca * ca
            K_diag[p + 1] += k * cb * cb
            off2.append((k * ca * cb) ** 2 / (m[p] * m[p + 1]))
        for p, k in grounds:
            K_diag[p] += mpmath.mpf(float(k))
        diag = [K_diag[p] / m[p] for p in range(n)]
        tiny = mpmath.mpf(10) ** (-4 * DPS)

        def count_below(x):  # negative pivots of the LDLᵀ of A − x I (Sylvester's law of inertia)
            count, d = 0, mpmath.mpf(1)
            for p in range(n):
                d = diag[p] - x - (off2[p - 1] / d if p else 0)
                if d == 0:
                    d = tiny
                count += d < 0
            return count

        top = 4 * max(diag)  # above every eigenvalue (Gershgorin)
        first, end = n_rigid, n if modes is None else n_rigid + modes
        found = {}
        # eigenvalue j (0-based) lies in (lo, hi] where count_below(lo) ≤ j < count_below(hi): each
        # interval holds the wanted j in [a, b) and is halved (geometrically) until it is narrow, so
        # that the eigenvalues share the halvings that their intervals share (each j sees the same
        # mid-points as a bisection of its own)
        stack = [(mpmath.mpf(10) ** -80, top, first, end)]
        while stack:
            lo, hi, a, b = stack.pop()
            if a >= b:
                continue
            if hi / lo - 1 <= mpmath.mpf(10) ** -14:
                found.update({j: float(mpmath.sqrt(lo)) for j in range(a, b)})
                continue
            mid = mpmath.sqrt(lo * hi)
            c = min(max(count_below(mid), a), b)
            stack += [(lo, mid, a, c), (mid, hi, c, b)]
        return np.array([found[j] for j in range(first, end)])


def _dense_reference(J, springs, n_rigid):
    """Flexible ω (rad/s) and unit eigenvectors y of A = M^-½ K M^-½, ``mpmath.eigsy`` at 60 digits.

    springs: (coefficients {coordinate: c}, k), each adding k (Σ c θ)²/2 to the strain energy.
    """
    with mpmath.workdps(DPS):
        n = len(J)
        K = mpmath.zeros(n, n)
        for coef, k in springs:
            for a, ca in coef.items():
                for b, cb in coef.items():
                    K[a, b] += mpmath.mpf(float(k)) * mpmath.mpf(float(ca)) * mpmath.mpf(float(cb))
        D = mpmath.diag([1 / mpmath.sqrt(mpmath.mpf(float(j))) for j in J])
        lam, Y = mpmath.eigsy(D * K * D)
        order = sorted(range(n), key=lambda i: lam[i])[n_rigid:]
        omega = np.array([float(mpmath.sqrt(lam[i])) for i in order])
        vectors = np.array([[float(Y[r, i]) for i in order] for r in range(n)])
        return omega, vectors


# -- models -------------------------------------------------------------------------------------------


def _chain(J, k, grounds=()):
    disks = [Disk(f"d{i}", j) for i, j in enumerate(J)]
    shafts = [Shaft(f"s{i}", (f"d{i}", f"d{i + 1}"), v) for i, v in enumerate(k)]
    springs = [GroundSpring(f"g{i}", f"d{p}", v) for i, (p, v) in enumerate(grounds)]
    return Drivetrain(disks, [*shafts, *springs])


def _strict_modal(model, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return modal(model, **kwargs)


def _assert_frequencies(result, reference):
    assert result.omega.size == reference.size
    np.testing.assert_allclose(result.omega, reference, rtol=RTOL, atol=0)


@pytest.mark.parametrize(
    ("heavy", "light", "n"),
    [(1e10, 1e-5, 21), (1.0, 1e-15, 20)],
    ids=["1e10-1e-5", "1-1e-15"],
)
def test_free_chain_with_alternating_inertias(heavy, light, n):
    # before: the lowest flexible mode of the first came out as 0 Hz, the second's 45 % off
    J = np.where(np.arange(n) % 2, light, heavy)
    k = np.full(n - 1, 1e3)
    reference = _chain_reference(J, [(1.0, -1.0, v) for v in k])
    result = _strict_modal(_chain(J, k))
    assert result.rigid_body_modes == 1
    _assert_frequencies(result, reference)


@pytest.mark.parametrize("solver", ["auto", "dense", "banded"])
def test_free_chain_with_log_spread_inertias_and_stiffnesses(solver):
    # inertias over 18 decades, stiffnesses over 15 (before: errors up to 70 000 %)
    rng = np.random.default_rng(20261126)
    n = 40
    J = 10 ** rng.uniform(-9, 9, n)
    k = 10 ** rng.uniform(-3, 12, n - 1)
    result = _strict_modal(_chain(J, k), solver=solver)
    _assert_frequencies(result, _chain_reference(J, [(1.0, -1.0, v) for v in k]))


def test_grounded_chain_with_spread_data():
    rng = np.random.default_rng(7)
    n = 30
    J = 10 ** rng.uniform(-9, 9, n)
    k = 10 ** rng.uniform(-3, 12, n - 1)
    grounds = [(0, 1e-9), (17, 3e4), (n - 1, 1e14)]
    result = _strict_modal(_chain(J, k, grounds))
    assert result.rigid_body_modes == 0
    reference = _chain_reference(J, [(1.0, -1.0, v) for v in k], grounds, n_rigid=0)
    _assert_frequencies(result, reference)


# a branched geared train: the pinion drives two wheels through flexible meshes, one of them on to a
# third gear through a rigid mesh; inertias 1e-9…1e9 kg·m², stiffnesses 1e-3…1e14
_INERTIAS = {
    "motor": 1e-9,
    "pinion": 1e-7,
    "wheel": 1e3,
    "load": 1e9,
    "gear2": 1e-5,
    "out2": 1e6,
    "gear3": 2e-3,
    "out3": 1e-8,
}
_RATIO = 3.0  # rigid external mesh gear2–gear3: θ_gear3 = −θ_gear2 / 3


def _branched(grounded: bool) -> Drivetrain:
    elements = [
        Shaft("motor shaft", ("motor", "pinion"), 1e-3),
        GearMesh("mesh 1", ("pinion", "wheel"), base_radii=(0.01, 1.0), stiffness=1e14),
        Shaft("load shaft", ("wheel", "load"), 1e12),
        GearMesh("mesh 2", ("pinion", "gear2"), kind="internal", base_radii=(0.01, 0.05), stiffness=1e6),
        Shaft("shaft 2", ("gear2", "out2"), 1e5),
        GearMesh("rigid mesh", ("gear2", "gear3"), ratio=_RATIO),
        Shaft("shaft 3", ("gear3", "out3"), 1e9),
    ]
    if grounded:
        elements.append(GroundSpring("brake", "load", 1e-9))
    return Drivetrain([Disk(name, j) for name, j in _INERTIAS.items()], elements)


def _branched_reference(grounded: bool):
    # coordinates: every disk but gear3, which follows gear2 (its inertia adds J/n² to gear2's)
    names = [d for d in _INERTIAS if d != "gear3"]
    at = {d: i for i, d in enumerate(names)}
    J = [_INERTIAS[d] for d in names]
    J[at["gear2"]] += _INERTIAS["gear3"] / _RATIO**2
    springs = [
        ({at["motor"]: 1.0, at["pinion"]: -1.0}, 1e-3),
        ({at["pinion"]: 0.01, at["wheel"]: 1.0}, 1e14),  # external: δ = r_a θ_a + r_b θ_b
        ({at["wheel"]: 1.0, at["load"]: -1.0}, 1e12),
        ({at["pinion"]: 0.01, at["gear2"]: -0.05}, 1e6),  # internal: δ = r_a θ_a − r_b θ_b
        ({at["gear2"]: 1.0, at["out2"]: -1.0}, 1e5),
        ({at["gear2"]: -1.0 / _RATIO, at["out3"]: -1.0}, 1e9),  # θ_gear3 − θ_out3
    ]
    if grounded:
        springs.append(({at["load"]: 1.0}, 1e-9))
    omega, Y = _dense_reference(J, springs, n_rigid=0 if grounded else 1)
    return omega, Y, names, np.array(J)


@pytest.mark.parametrize("grounded", [False, True], ids=["free", "grounded"])
def test_branched_geared_train_with_extreme_spreads(grounded):
    result = _strict_modal(_branched(grounded))
    omega, Y, names, J = _branched_reference(grounded)
    _assert_frequencies(result, omega)
    # the mass-normalised shapes too: M^½ φ is the unit eigenvector of A, up to its sign
    rows = [result.disk_names.index(d) for d in names]
    scaled = np.sqrt(J)[:, None] * result.shapes[rows]
    sign = np.sign(np.sum(scaled * Y, axis=0))
    np.testing.assert_allclose(scaled * sign, Y, atol=1e-6)
    # the disk the rigid mesh removed follows gear2
    g2, g3 = result.disk_names.index("gear2"), result.disk_names.index("gear3")
    np.testing.assert_allclose(result.shapes[g3], -result.shapes[g2] / _RATIO, rtol=1e-12)


def test_long_chain_over_15_decades():
    # beyond the dense Jacobi limit: the bidiagonal path (before: the four lowest modes at 0 Hz)
    rng = np.random.default_rng(11)
    n = 2100
    J = 10 ** rng.uniform(-6, 9, n)
    k = 10 ** rng.uniform(-3, 12, n - 1)
    result = _strict_modal(_chain(J, k), n_modes=4)
    _assert_frequencies(result, _chain_reference(J, [(1.0, -1.0, v) for v in k], modes=4))
    assert result.solver == "bidiagonal"
    # mass-normalised shapes whose Rayleigh quotient is ω² (strain energy / kinetic, per unit ω²)
    phi = result.shapes
    np.testing.assert_allclose(np.sum(J[:, None] * phi**2, axis=0), 1.0, rtol=1e-9)
    strain = np.sum(k[:, None] * np.diff(phi, axis=0) ** 2, axis=0)
    np.testing.assert_allclose(strain, result.omega**2, rtol=1e-9)


def test_long_geared_chain_grounded_at_one_end():
    # a chain of 2100 disks with a rigid and a flexible mesh in it, held by a soft spring at one end
    rng = np.random.default_rng(12)
    n = 2100
    J = 10 ** rng.uniform(-9, 6, n)
    k = 10 ** rng.uniform(-3, 12, n - 1)
    elements = [Shaft(f"s{i}", (f"d{i}", f"d{i + 1}"), k[i]) for i in range(n - 1) if i not in (700, 1400)]
    elements += [
        GearMesh("rigid", ("d700", "d701"), ratio=4.0),  # θ_701 = −θ_700 / 4
        GearMesh("flexible", ("d1400", "d1401"), base_radii=(0.02, 0.3), stiffness=1e13),
        GroundSpring("ground", "d0", 1e-6),
    ]
    result = _strict_modal(Drivetrain([Disk(f"d{i}", J[i]) for i in range(n)], elements), n_modes=5)
    # reference coordinates: d701 follows d700 (θ_701 = −θ_700/4, adding J_701/16), the rest shift by one
    Jr = np.delete(J, 701)
    Jr[700] += J[701] / 16

    def coordinate(i):
        return (i, 1.0) if i <= 700 else ((700, -0.25) if i == 701 else (i - 1, 1.0))

    links = [None] * (n - 2)
    for i in range(n - 1):
        if i == 700:  # the rigid mesh: no spring
            continue
        (p, ca), (q, cb) = coordinate(i), coordinate(i + 1)
        assert q == p + 1
        # the flexible (external) mesh: k_c (r_a θ_a + r_b θ_b)²/2; a shaft: k (θ_a − θ_b)²/2
        links[p] = (0.02 * ca, 0.3 * cb, 1e13) if i == 1400 else (ca, -cb, k[i])
    reference = _chain_reference(Jr, links, [(0, 1e-6)], n_rigid=0, modes=5)
    _assert_frequencies(result, reference)
    assert result.solver == "bidiagonal"


def test_a_ring_of_shafts_with_spread_data_needs_no_warning():
    # a loop of shafts is still D₁ S D₂ with S an incidence matrix: the Jacobi SVD stays accurate
    rng = np.random.default_rng(4)
    m = 12
    J = 10 ** rng.uniform(-9, 9, m)
    k = 10 ** rng.uniform(-3, 12, m)
    disks = [Disk(f"d{i}", J[i]) for i in range(m)]
    shafts = [Shaft(f"s{i}", (f"d{i}", f"d{(i + 1) % m}"), k[i]) for i in range(m)]
    result = _strict_modal(Drivetrain(disks, shafts))
    assert result.rigid_body_modes == 1
    omega, _ = _dense_reference(J, [({i: 1.0, (i + 1) % m: -1.0}, k[i]) for i in range(m)], n_rigid=1)
    _assert_frequencies(result, omega)


def test_a_loop_of_flexible_meshes_warns_with_the_condition_estimate():
    # ratios around the loop disagree by 2e-9: the loop locks the train (no rigid-body mode) and its
    # lowest frequency depends on that small difference, beyond what double precision can vouch for
    rng = np.random.default_rng(3)
    m = 12
    J = 10 ** rng.uniform(-9, 9, m)
    kc = 10 ** rng.uniform(3, 14, m)
    radii = [(0.05, 0.05 * (1 + 2e-9) if i == m - 1 else 0.05) for i in range(m)]
    meshes = [
        GearMesh(f"m{i}", (f"g{i}", f"g{(i + 1) % m}"), kind="internal", base_radii=radii[i], stiffness=kc[i])
        for i in range(m)
    ]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)  # the radii disagree with the ratio: said elsewhere
        model = Drivetrain([Disk(f"g{i}", J[i]) for i in range(m)], meshes)
    with pytest.warns(ModelWarning, match=r"loop of springs has the scaled condition estimate \d"):
        result = modal(model)
    assert result.rigid_body_modes == 0
    # the higher modes do not hang on the loop's ratio: still accurate
    springs = [({i: r[0], (i + 1) % m: -r[1]}, kc[i]) for i, r in enumerate(radii)]
    omega, _ = _dense_reference(J, springs, n_rigid=0)
    np.testing.assert_allclose(result.omega[1:], omega[1:], rtol=RTOL)


def test_a_large_ring_warns_with_the_condition_estimate():
    # a loop of 2100 shafts: neither a chain nor small enough for dense Jacobi, so a warning
    rng = np.random.default_rng(5)
    n = 2100
    J = 10 ** rng.uniform(-6, 9, n)
    k = 10 ** rng.uniform(-3, 12, n)
    disks = [Disk(f"d{i}", J[i]) for i in range(n)]
    shafts = [Shaft(f"s{i}", (f"d{i}", f"d{(i + 1) % n}"), k[i]) for i in range(n)]
    with pytest.warns(ModelWarning, match=r"condition estimate ‖M\^-½ K M\^-½‖/λ [=≥] \d"):
        modal(Drivetrain(disks, shafts), n_modes=3)


def test_solve_eigen_without_a_factor_warns_with_the_condition_estimate():
    J = np.where(np.arange(21) % 2, 1e-5, 1e10)
    asm = assemble(_chain(J, np.full(20, 1e3)))
    with pytest.warns(ModelWarning, match=r"condition estimate .* no stiffness factor"):
        solve_eigen(asm.K, asm.mass, n_rigid=1)


def _published_like_train() -> Drivetrain:
    return Drivetrain(
        [Disk("m", 7e-4), Disk("p", 4e-5), Disk("g", 3e-3), Disk("q", 6e-5), Disk("h", 3e-2), Disk("t", 1.4)],
        [
            Shaft("s1", ("m", "p"), 7e4),
            GearMesh("g1", ("p", "g"), base_radii=(0.0315, 0.136), stiffness=2e9),
            Shaft("s2", ("g", "q"), 9.5e5),
            GearMesh("g2", ("q", "h"), kind="internal", base_radii=(0.034, 0.224), stiffness=2e9),
            Shaft("s3", ("h", "t"), 5.7e6),
            GroundSpring("motor", "m", 1e3),
        ],
    )


@pytest.mark.parametrize(
    ("model", "n_modes", "solver"),
    [
        (_published_like_train(), None, "dense"),
        (_chain(np.full(1000, 1e-2), np.full(999, 1e5)), None, "banded"),
        (_chain(np.full(1000, 1e-2), np.full(999, 1e5)), 6, "banded"),
    ],
    ids=["geared", "chain-all", "chain-lowest"],
)
def test_a_well_conditioned_model_keeps_the_fast_result_without_a_warning(model, n_modes, solver):
    result = _strict_modal(model, n_modes=n_modes)
    asm = assemble(model)
    want = None if n_modes is None else n_modes + asm.n_rigid_body
    lam, _, used = solve_eigen(asm.K, asm.mass, n_modes=want)  # the fast path alone, unchecked
    assert result.solver == used == solver
    np.testing.assert_array_equal(result.omega, np.sqrt(np.clip(lam[asm.n_rigid_body :], 0.0, None)))


@pytest.mark.parametrize("branched", [False, True], ids=["chain", "branched"])
def test_solve_eigen_takes_the_factor_and_finds_the_rigid_body_modes_itself(branched):
    from mechdyn.drivetrain.modal import stiffness_factor

    if branched:
        model = _branched(grounded=False)
        reference = _branched_reference(grounded=False)[0]
    else:
        J = np.where(np.arange(21) % 2, 1e-5, 1e10)
        model = _chain(J, np.full(20, 1e3))
        reference = _chain_reference(J, [(1.0, -1.0, 1e3)] * 20)
    asm = assemble(model)
    lam, Q, used = solve_eigen(asm.K, asm.mass, factor=stiffness_factor(asm))
    assert used == ("jacobi" if branched else "bidiagonal")
    assert lam[0] == 0.0
    np.testing.assert_allclose(np.sqrt(lam[1:]), reference, rtol=RTOL)
    np.testing.assert_allclose(Q.T @ (asm.mass[:, None] * Q), np.eye(asm.n), atol=1e-9)
