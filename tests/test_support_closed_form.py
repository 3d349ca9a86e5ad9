"""The machine on its supports against closed forms and an independent time integration."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

from mechdyn.errors import ModelError
from mechdyn.support import (
    PLANAR,
    Mount,
    MountedMachine,
    PeriodicLoad,
    RigidBody,
    elastic_centre,
    harmonic_response,
    modes,
    periodic_response,
    startup_response,
)

M, K = 1000.0, 1.0e6  # kg, N/m: ωn = 31.62 rad/s
WN = math.sqrt(K / M)


@pytest.mark.parametrize("r", [0.2, 0.8, 1.0, 1.5, 3.0])
@pytest.mark.parametrize("zeta", [0.02, 0.1, 0.5])
def test_single_dof_harmonic_response_and_transmissibility(r, zeta):
    # Rao, Mechanical Vibrations, §3.4 and §9.10: X = (F/k) / √((1 − r²)² + (2ζr)²),
    # tan φ = 2ζr / (1 − r²), T_R = F_T/F = √(1 + (2ζr)²) / √((1 − r²)² + (2ζr)²)
    m = MountedMachine.single_dof(M, K, zeta)
    F0 = 2500.0
    load = PeriodicLoad.from_harmonics(2 * math.pi / (r * WN), {1: F0})
    X = 2 * harmonic_response(m, load)[1, 0]  # complex amplitude of z = Re(X e^{iωt})
    D = math.sqrt((1 - r**2) ** 2 + (2 * zeta * r) ** 2)
    assert abs(X) == pytest.approx(F0 / K / D, rel=1e-12)
    assert -np.angle(X) == pytest.approx(math.atan2(2 * zeta * r, 1 - r**2), rel=1e-12)
    c = 2 * zeta * math.sqrt(K * M)
    FT = (K + 1j * r * WN * c) * X
    assert abs(FT) / F0 == pytest.approx(math.sqrt(1 + (2 * zeta * r) ** 2) / D, rel=1e-12)
    # and over time, sampled finely: the transmitted force is k z + c ż
    resp = periodic_response(m, load, n_samples=4000)
    assert np.ptp(resp.transmitted_force) / 2 == pytest.approx(abs(FT), rel=1e-5)
    np.testing.assert_allclose(
        resp.transmitted_force, K * resp.displacement[:, 0] + c * resp.velocity[:, 0], rtol=1e-12, atol=1e-9
    )


def test_natural_frequency_and_static_deflection_of_one_dof():
    m = MountedMachine.single_dof("600 t", "4.5e8 N/m", 0.05)
    assert modes(m).frequencies_hz[0] == pytest.approx(math.sqrt(4.5e8 / 6e5) / (2 * math.pi), rel=1e-12)
    assert m.static_deflection[0] == pytest.approx(6e5 * 9.80665 / 4.5e8, rel=1e-12)


def _multi_harmonic_load():
    # a press-like pulse: several harmonics with phases, and a mean
    amps = {1: 3.0e4 * np.exp(0.3j), 2: 2.0e4 * np.exp(-1.1j), 3: 8.0e3j, 5: 3.0e3, 9: 1.0e3 * np.exp(2j)}
    return PeriodicLoad.from_harmonics(0.8, amps, mean=5.0e3)


def test_frequency_domain_steady_state_equals_a_long_time_integration():
    # independent: scipy integrates m z'' + c z' + k z = F(t) for 40 periods (the transient decays
    # as exp(−ζ ωn t) = e^{−25}); its last period is compared with the frequency-domain solution
    zeta = 0.05
    m = MountedMachine.single_dof(M, K, zeta)
    load = _multi_harmonic_load()
    c = 2 * zeta * math.sqrt(K * M)
    T = load.period

    def rhs(t, y):
        return [y[1], (load.value(t)[2] - c * y[1] - K * y[0]) / M]

    t_last = 39 * T + T * np.arange(200) / 200
    sol = solve_ivp(rhs, (0, 40 * T), [0.0, 0.0], method="DOP853", rtol=1e-11, atol=1e-15, t_eval=t_last)
    steady = periodic_response(m, load, n_samples=200)
    scale = np.abs(steady.displacement).max()
    assert np.abs(sol.y[0] - steady.displacement[:, 0]).max() < 1e-7 * scale


@pytest.mark.parametrize("method", ["exact", "DOP853", "RK45", "duhamel"])
def test_startup_converges_onto_the_steady_state(method):
    zeta = 0.1
    m = MountedMachine.single_dof(M, K, zeta)
    load = _multi_harmonic_load()
    cycles = 12
    start = startup_response(m, load, cycles, method=method, steps_per_period=2000)
    assert start.displacement[0, 0] == 0.0 and start.velocity[0, 0] == 0.0  # from rest
    steady = periodic_response(m, load, time=start.time)
    err = np.abs(start.displacement[:, 0] - steady.displacement[:, 0])
    per_cycle = err[:-1].reshape(cycles, -1).max(axis=1)
    scale = np.ptp(steady.displacement)
    assert per_cycle[0] > 0.05 * scale  # a real transient at the start...
    # ...that dies away, period by period, down to the integrator's accuracy
    tol = {"duhamel": 2e-4, "exact": 1e-12}.get(method, 1e-6)  # duhamel: the force is linear between steps
    assert per_cycle[-1] < tol * scale
    decay = math.exp(-zeta * WN * load.period)
    assert per_cycle[2] < 1.5 * decay**2 * per_cycle[0] + tol * scale


def test_the_exact_start_up_against_a_single_dof_closed_form_and_a_tight_integration():
    """The default start-up is the steady state plus the free vibration from rest: against the
    single-DOF closed form for one harmonic (Duhamel's integral worked by hand) to 1e-12, and against
    DOP853 at rtol 1e-12 on a four-mount machine with a multi-harmonic load to 1e-9."""
    zeta, W = 0.07, 1.3 * WN
    m = MountedMachine.single_dof(M, K, zeta)
    load = PeriodicLoad.from_harmonics(2 * math.pi / W, {1: 1e4}, mean=0.0)
    r = startup_response(m, load, 6, steps_per_period=400)
    assert r.method == "exact"
    t = r.time
    # F(t) = 1e4 cos Wt (an amplitude): x_p = X cos(Wt − φ); x_h from x(0) = x'(0) = 0
    r_ = W / WN
    X = 1e4 / K / math.hypot(1 - r_**2, 2 * zeta * r_)
    phi = math.atan2(2 * zeta * r_, 1 - r_**2)
    wd = WN * math.sqrt(1 - zeta**2)
    A = -X * math.cos(phi)  # x_h(0) = −x_p(0)
    B = (-X * W * math.sin(phi) + zeta * WN * A) / wd  # x_h'(0) = −x_p'(0)
    closed = X * np.cos(W * t - phi) + np.exp(-zeta * WN * t) * (A * np.cos(wd * t) + B * np.sin(wd * t))
    assert np.abs(r.displacement[:, 0] - closed).max() < 1e-12 * X
    # six coordinates, five harmonics with a mean
    mm = _four_mounts(0.3)
    many = _multi_harmonic_load()
    exact = startup_response(mm, many, 4)
    tight = startup_response(mm, many, 4, method="DOP853", rtol=1e-12)
    scale = np.abs(tight.displacement).max()
    assert np.abs(exact.displacement - tight.displacement).max() < 1e-9 * scale


def test_an_undamped_resonance_has_no_periodic_solution_and_is_integrated():
    """A harmonic on an undamped natural frequency: no steady state, so the start-up is integrated
    (DOP853), and the result says why; the response grows as the resonance's t sin ωt."""
    m = MountedMachine.single_dof(M, K, 0.0)
    load = PeriodicLoad.from_harmonics(2 * math.pi / WN, {1: 1e3}, mean=0.0)
    r = startup_response(m, load, 8, steps_per_period=200)
    assert r.method.startswith("DOP853") and "undamped resonance" in r.method
    amp = np.abs(r.displacement[:, 0])
    assert amp[-200:].max() > 6 * amp[:200].max()


def _four_mounts(h, kz=2.0e6, kh=0.5e6, a=1.2, b=0.8, c=300.0):
    body = RigidBody(2000.0, (0.0, 0.0, h), (400.0, 700.0, 900.0))
    mounts = [
        Mount(f"m{i}", (sx * a, sy * b, 0.0), (kh, kh, kz), (c, c, 2 * c))
        for i, (sx, sy) in enumerate([(-1, -1), (1, -1), (-1, 1), (1, 1)])
    ]
    return MountedMachine(body, mounts)


def test_symmetric_four_mounts_with_the_centre_of_mass_in_their_plane():
    # decoupled: bounce 4kz/m, sway 4kh/m, roll 4kz b²/Ixx, pitch 4kz a²/Iyy, yaw 4kh (a²+b²)/Izz
    kz, kh, a, b = 2.0e6, 0.5e6, 1.2, 0.8
    mm = _four_mounts(0.0, kz, kh, a, b)
    expected = np.sqrt(
        [
            4 * kh / 2000,
            4 * kh / 2000,
            4 * kz / 2000,
            4 * kz * b**2 / 400,
            4 * kz * a**2 / 700,
            4 * kh * (a**2 + b**2) / 900,
        ]
    ) / (2 * math.pi)
    md = modes(mm)
    np.testing.assert_allclose(md.frequencies_hz, np.sort(expected), rtol=1e-12)
    assert md.decoupling.min() > 1 - 1e-12
    assert np.allclose(md.kinetic_energy.sum(axis=0), 1.0)


def test_symmetric_four_mounts_with_a_high_centre_of_mass_couple_sway_and_rocking():
    # x and pitch about y couple through h: K = [[4kh, 4kh h], [4kh h, 4kz a² + 4kh h²]], M = diag(m, Iyy)
    kz, kh, a, b, h = 2.0e6, 0.5e6, 1.2, 0.8, 1.5
    mm = _four_mounts(h, kz, kh, a, b)
    Kxp = np.array([[4 * kh, 4 * kh * h], [4 * kh * h, 4 * kz * a**2 + 4 * kh * h**2]])
    Kyr = np.array([[4 * kh, -4 * kh * h], [-4 * kh * h, 4 * kz * b**2 + 4 * kh * h**2]])
    f = []
    for Kp, Ir in ((Kxp, 700.0), (Kyr, 400.0)):
        A = np.diag([1 / 2000.0, 1 / Ir]) @ Kp
        f += list(np.sqrt(np.linalg.eigvals(A).real) / (2 * math.pi))
    f += [math.sqrt(4 * kz / 2000) / (2 * math.pi), math.sqrt(4 * kh * (a**2 + b**2) / 900) / (2 * math.pi)]
    np.testing.assert_allclose(modes(mm).frequencies_hz, np.sort(f), rtol=1e-12)
    # the planar model (x, z, ry) keeps exactly the x–pitch pair and the bounce
    planar = MountedMachine(mm.body, mm.mounts, PLANAR)
    fp = np.sort(
        [*np.sqrt(np.linalg.eigvals(np.diag([1 / 2000.0, 1 / 700.0]) @ Kxp).real), math.sqrt(4 * kz / 2000)]
    )
    np.testing.assert_allclose(modes(planar).frequencies_hz, fp / (2 * math.pi), rtol=1e-12)


def test_assembled_matrices_are_symmetric_and_definite():
    mm = _four_mounts(1.5)
    for A in (mm.mass_matrix, mm.stiffness_matrix, mm.damping_matrix):
        assert np.array_equal(A, A.T)
        assert np.linalg.eigvalsh(A).min() > 0


def test_a_force_through_the_elastic_centre_only_translates_the_machine():
    # planar: a layout with unequal mounts has an elastic centre off the centre of mass; a static
    # force applied there moves the body without turning it
    body = RigidBody(1500.0, (0.2, 0.0, 0.9), (300.0, 500.0, 400.0))
    mounts = [
        Mount("a", (-1.0, 0.0, 0.0), (4e5, 4e5, 3e6)),
        Mount("b", (1.5, 0.0, 0.2), (1e5, 1e5, 1e6)),
        Mount.with_orientation("c", (0.3, 0.0, -0.1), (2e5, 2e5, 2e6), (0.0, 0.4, 0.0)),
    ]
    mm = MountedMachine(body, mounts, PLANAR)
    p, residual = elastic_centre(mm)
    assert residual < 1e-12
    for F in ([1.0e4, 0.0, 0.0], [0.0, 0.0, 1.0e4], [3e3, 0.0, -7e3]):
        F = np.array(F)
        Q = mm.load_matrix() @ np.concatenate([F, np.cross(p, F)])
        q = np.linalg.solve(mm.stiffness_matrix, Q)
        assert abs(q[2]) < 1e-12 * np.abs(q[:2]).max()  # no rotation ry


def test_mount_forces_balance_the_load_minus_the_inertia_force_at_every_instant():
    mm = _four_mounts(1.5)
    load = PeriodicLoad.from_samples(
        0.5,
        np.column_stack(
            [np.sin(np.linspace(0, 2 * np.pi, 64, endpoint=False) * k) * 1e3 for k in range(1, 7)]
        ),
    )
    for r in (periodic_response(mm, load), startup_response(mm, load, 3)):
        assert np.abs(r.force_balance_residual).max() < 1e-9 * np.abs(r.floor_force).max()
        # and the moments: Σ r_i × f_i about the origin = M_O − d/dt(angular momentum) about the origin
        pos = np.array([m.position for m in mm.mounts])
        moment = np.cross(pos[None], r.mount_forces).sum(axis=1)
        G = mm.body.center_of_mass
        a_G = r.acceleration[:, :3]
        expected = (
            r.applied[:, 3:] - np.cross(G, mm.body.mass * a_G) - r.acceleration[:, 3:] @ mm.body.inertia.T
        )
        assert np.abs(moment - expected).max() < 1e-9 * np.abs(moment).max()


def test_samples_are_reproduced_by_the_series():
    rng = np.random.default_rng(3)
    for n in (7, 8):
        samples = rng.normal(size=(n, 6))
        load = PeriodicLoad.from_samples(2.0, samples)
        np.testing.assert_allclose(load.value(load.time(n)), samples, atol=1e-12)


@pytest.mark.parametrize(("H", "n"), [(5, 10), (5, 16), (4, 9), (180, 360)])
def test_the_series_on_an_equal_grid_by_inverse_fft(H, n):
    from mechdyn.support.excitation import series, series_on_grid

    rng = np.random.default_rng(H + n)
    c = rng.normal(size=(H + 1, 3)) + 1j * rng.normal(size=(H + 1, 3))
    t = 2.0 * np.arange(n) / n
    np.testing.assert_allclose(series_on_grid(c, n), series(c, 2.0, t), atol=1e-11)


@st.composite
def mounted_machines(draw):
    n = draw(st.integers(3, 6))
    coord = st.floats(-2.0, 2.0, allow_nan=False)
    stiff = st.floats(1e4, 1e7)
    mounts = [
        Mount.with_orientation(
            f"m{i}",
            (draw(coord), draw(coord), draw(st.floats(-0.5, 0.5))),
            (draw(stiff), draw(stiff), draw(stiff)),
            (draw(st.floats(-0.5, 0.5)), draw(st.floats(-0.5, 0.5)), draw(st.floats(-0.5, 0.5))),
            damping=(draw(st.floats(0.0, 1e4)),) * 3,
            anchored=True,  # bolted: a random layout may have to hold the machine down
        )
        for i in range(n)
    ]
    body = RigidBody(draw(st.floats(100.0, 1e4)), (0.1, -0.2, 0.8), (draw(st.floats(10.0, 1e3)),) * 3)
    try:
        return MountedMachine(body, mounts)
    except ModelError:
        assume(False)


@settings(max_examples=25, deadline=None)
@given(mounted_machines())
def test_random_layouts_assemble_symmetric_definite_matrices_and_balance_forces(mm):
    K, C = mm.stiffness_matrix, mm.damping_matrix
    assert np.array_equal(K, K.T) and np.array_equal(C, C.T)
    assert np.linalg.eigvalsh(K).min() > 0 and np.linalg.eigvalsh(C).min() > -1e-9 * np.abs(C).max()
    md = modes(mm)
    np.testing.assert_allclose(md.kinetic_energy.sum(axis=0), 1.0, atol=1e-9)
    f0 = math.sqrt(np.linalg.eigvalsh(K).max() / 100.0)
    load = PeriodicLoad.from_harmonics(1.0 / max(f0, 1e-3), {1: np.full(6, 1e3), 2: np.full(6, 300j)})
    r = periodic_response(mm, load, 16)
    assert np.abs(r.force_balance_residual).max() < 1e-7 * max(np.abs(r.floor_force).max(), 1e3)


@pytest.mark.parametrize("phase", [0.0, 0.5 * math.pi])
def test_a_harmonic_load_is_sampled_finely_enough_by_default(phase):
    # one harmonic: 2H samples would sit on the Nyquist limit and miss the peaks
    m = MountedMachine.single_dof(M, K, 0.05)
    load = PeriodicLoad.from_harmonics(
        2 * math.pi / (0.8 * WN), {1: 1000.0 * complex(math.cos(phase), math.sin(phase))}
    )
    r = periodic_response(m, load)
    FT = abs(2 * (K + 1j * 0.8 * WN * 2 * 0.05 * math.sqrt(K * M)) * harmonic_response(m, load)[1, 0])
    assert r.time.size >= 64
    assert np.ptp(r.transmitted_force) / 2 == pytest.approx(FT, rel=5e-3)
    assert np.ptp(r.exciting_force) / 2 == pytest.approx(1000.0, rel=5e-3)


@pytest.mark.parametrize("phase", [0.0, 0.7, 2.0])
def test_the_extremes_of_a_harmonic_steady_state_lie_between_the_samples(phase):
    """A harmonic load sampled 64 times a period: its peaks fall between samples, where the samples
    read them up to 0.12 % low. The summary locates them to the closed form |X| = F/|k − ω²m + iωc|."""
    import cmath

    from mechdyn.support.excitation import PeriodicLoad
    from mechdyn.support.response import periodic_response

    m, k, zeta, F0, T = 1000.0, 1e6, 0.05, 1000.0, 0.1
    c, w = 2 * zeta * math.sqrt(k * m), 2 * math.pi / T
    r = periodic_response(
        MountedMachine.single_dof(m, k, zeta), PeriodicLoad.from_harmonics(T, {1: F0 * cmath.exp(1j * phase)})
    )
    s = r.summary()
    X = F0 / abs(k - w**2 * m + 1j * w * c)
    FT = X * abs(k + 1j * w * c)
    assert s["inertia_force_max_N"] == pytest.approx(F0, rel=1e-8)
    assert s["inertia_force_min_N"] == pytest.approx(-F0, rel=1e-8)
    assert s["displacement_max_m"] == pytest.approx(X, rel=1e-8)
    assert s["transmitted_force_range_N"] == pytest.approx(2 * FT, rel=1e-8)
    assert s["mount_force_peak_N"]["support"] == pytest.approx(FT, rel=1e-8)
