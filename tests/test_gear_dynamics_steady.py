"""Periodic steady state of geared drivetrains over speed: harmonic balance against the closed form of a
single mesh and the drivetrain FRF (constant stiffness), against shooting (varying stiffness), against
brute-force time integration, with backlash, and bad input."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp

from mechdyn.drivetrain import Disk, Drivetrain, GearMesh, GroundSpring, RayleighDamping, Shaft, frf
from mechdyn.errors import ModelError
from mechdyn.gear_dynamics import GearSystem
from mechdyn.gear_dynamics.floquet import interpolate, product_harmonics
from mechdyn.gear_dynamics.steady import speed_sweep, steady_state

RA, RB, ZA = 0.0188, 0.047, 20


def _pair(J_ref: float = 0.05, *, c_mesh: float = 800.0) -> Drivetrain:
    """Pinion (reference) ~ flexible mesh ~ gear."""
    return Drivetrain(
        [Disk("pinion", J_ref), Disk("gear", 0.03)],
        [
            GearMesh(
                "m", ("pinion", "gear"), teeth=(ZA, 50), base_radii=(RA, RB), stiffness=3e8, damping=c_mesh
            )
        ],
        name="pair",
    )


def _train(J_motor: float = 0.05) -> Drivetrain:
    """Motor — shaft — pinion ~ flexible mesh ~ gear — shaft — load, damped."""
    return Drivetrain(
        [Disk("motor", J_motor), Disk("pinion", 0.002), Disk("gear", 0.03), Disk("load", 0.2)],
        [
            Shaft("s1", ("motor", "pinion"), 2e4, damping=20.0),
            GearMesh(
                "m", ("pinion", "gear"), teeth=(ZA, 50), base_radii=(RA, RB), stiffness=3e8, damping=1500.0
            ),
            Shaft("s2", ("gear", "load"), 5e4, damping=60.0),
        ],
        name="train",
    )


def _cosine(P: int, eps: float) -> np.ndarray:
    return 1.0 + eps * np.cos(2 * np.pi * np.arange(P) / P) + 0.3 * eps * np.sin(4 * np.pi * np.arange(P) / P)


def _quad_harmonic(samples: np.ndarray, h: int) -> complex:
    """The Fourier coefficient of order h of the samples' periodic linear interpolant, by quadrature
    (independent of the closed forms under test)."""
    P = samples.size
    points = np.arange(1, P) / P

    def part(fn):
        return quad(fn, 0.0, 1.0, points=points, limit=400, epsabs=1e-16, epsrel=1e-13)[0]

    re = part(lambda t: interpolate(samples, t) * np.cos(2 * np.pi * h * t))
    im = part(lambda t: -interpolate(samples, t) * np.sin(2 * np.pi * h * t))
    return re + 1j * im


# -- (a) constant stiffness: the closed form and the drivetrain FRF ------------------------------------
def test_constant_stiffness_harmonic_balance_is_the_single_mesh_closed_form():
    """Pinion held at Ω: J_b ẍ + c r_b² ẋ + k r_b² x = r_b (k e + c ė) + T_load, one degree of freedom;
    each harmonic h of the (interpolated, coarsely sampled) error gives X_h = r_b (k + i h ω c) E_h /
    (k r_b² − (h ω)² J_b + i h ω c r_b²) with ω = z_a Ω."""
    P, H = 8, 24
    error = 4e-6 * np.sin(2 * np.pi * np.arange(P) / P + 0.3) + 1e-6 * np.cos(6 * np.pi * np.arange(P) / P)
    system = GearSystem.from_drivetrain(_pair(), errors={"m": error})
    speed, load, k, c, J = 90.0, 25.0, 3e8, 800.0, 0.03
    s = steady_state(
        system, speed, reference="pinion", drive="speed", load={"gear": load}, harmonics=H, points=256
    )
    w = ZA * speed
    t = s.time
    x = np.full(t.size, 0.0, complex)
    for h in range(-H, H + 1):
        E = _quad_harmonic(error, h)
        X = RB * (k + 1j * h * w * c) * E / (k * RB**2 - (h * w) ** 2 * J + 1j * h * w * c * RB**2)
        x += X * np.exp(1j * h * w * t)
    x = x.real + load / (k * RB**2)  # the gear turns backwards: the load torque acts forwards on it
    got = s.coordinates[:, 1]
    assert np.abs(got - x).max() <= 1e-8 * np.abs(x - x.mean()).max()
    np.testing.assert_allclose(s.static_force, [load / RB], rtol=1e-12)


def test_constant_stiffness_harmonic_balance_is_the_drivetrain_frf():
    """The mesh-frequency harmonic of a four-disk train equals :func:`mechdyn.drivetrain.frf` at the mesh
    frequency, the error's harmonic applied as the torques r (k + iωc) E_1 on the mesh's disks and the
    motor's inertia made 10¹¹ times the others' so that it turns at the held speed."""
    P = 12
    error = 3e-6 * np.sin(2 * np.pi * np.arange(P) / P)
    speed = 70.0
    s = steady_state(
        GearSystem.from_drivetrain(_train(), errors={"m": error}),
        speed,
        reference="motor",
        drive="speed",
        harmonics=4,
    )
    N = s.time.size
    X1 = np.fft.fft(s.coordinates, axis=0)[1] / N * 2  # complex amplitude of exp(i ω t)
    w = ZA * speed
    E1 = 2 * _quad_harmonic(error, 1)
    F = (3e8 + 1j * w * 1500.0) * E1
    big = frf(
        _train(J_motor=1e9),
        [w / (2 * np.pi)],
        {"pinion": RA * F, "gear": RB * F},
        damping=RayleighDamping(0.0, 0.0),
        method="direct",
    )
    theta = big.angles[0]
    assert abs(theta[0]) <= 1e-10 * np.abs(theta).max()  # the motor holds its speed
    np.testing.assert_allclose(X1[1:], theta[1:], rtol=1e-8, atol=1e-8 * np.abs(theta).max())


# -- (b) varying stiffness: harmonic balance against shooting -------------------------------------------
@pytest.mark.parametrize("speed", [40.0, 150.0])
def test_harmonic_balance_equals_shooting_with_varying_stiffness(speed):
    """A smooth stiffness profile finely sampled (the interpolant's corners are then small, and the
    harmonic series converges fast): harmonic balance and the Magnus shooting to 1e-6 of the vibration."""
    P = 256
    system = GearSystem.from_drivetrain(
        _train(), mesh_profiles={"m": _cosine(P, 0.2)}, errors={"m": {"amplitude": 2e-6, "samples": P}}
    )
    sh = steady_state(system, speed, reference="motor", drive="speed", load={"load": 40.0}, method="shooting")
    hb = steady_state(
        system,
        speed,
        reference="motor",
        drive="speed",
        load={"load": 40.0},
        harmonics=20,
        points=sh.time.size,
    )
    dynamic = np.abs(sh.coordinates - sh.coordinates.mean(axis=0)).max()
    assert np.abs(hb.coordinates - sh.coordinates).max() <= 1e-6 * dynamic
    np.testing.assert_allclose(hb.mesh_force, sh.mesh_force, rtol=0, atol=1e-6 * np.ptp(sh.mesh_force))
    assert sh.method == "shooting (magnus)" and hb.method.startswith(
        "harmonic balance (20 harmonics per mesh"
    )


def test_shooting_by_solve_ivp_equals_the_magnus_product():
    """A coarse profile (16 samples): the corners make the harmonic series converge slowly (about H⁻³),
    so the two shootings are compared with each other and with 200 harmonics."""
    P = 16
    system = GearSystem.from_drivetrain(
        _train(), mesh_profiles={"m": _cosine(P, 0.2)}, errors={"m": {"amplitude": 2e-6, "samples": P}}
    )
    kw = {"reference": "motor", "drive": "speed", "load": {"load": 40.0}}
    ivp = steady_state(system, 150.0, method="shooting", integrator="ivp", **kw)
    assert ivp.time.size == P
    magnus = steady_state(system, 150.0, method="shooting", substeps=8, **kw)
    step = magnus.time.size // P
    dynamic = np.abs(ivp.coordinates - ivp.coordinates.mean(axis=0)).max()
    assert np.abs(magnus.coordinates[::step] - ivp.coordinates).max() <= 1e-7 * dynamic
    hb = steady_state(system, 150.0, harmonics=200, points=P, **kw)
    assert np.abs(hb.coordinates - ivp.coordinates).max() <= 2e-6 * dynamic


def test_product_harmonics_are_exact():
    """The error's excitation k(τ) e(τ), a piecewise quadratic, against quadrature."""
    rng = np.random.default_rng(3)
    a, b = rng.random(7), rng.random(7)
    h = np.arange(-20, 21)
    exact = np.array([_quad_harmonic(a * 0 + 1, 0)])  # the quadrature itself: mean of 1
    assert abs(exact[0] - 1) < 1e-14
    got = product_harmonics(a, b, h)
    P = a.size
    points = np.arange(1, P) / P
    for hh, g in zip(h, got, strict=True):
        f = lambda t, hh=hh: interpolate(a, t) * interpolate(b, t) * np.exp(-2j * np.pi * hh * t)  # noqa: E731
        re = quad(lambda t, f=f: f(t).real, 0, 1, points=points, limit=400, epsabs=1e-14)[0]
        im = quad(lambda t, f=f: f(t).imag, 0, 1, points=points, limit=400, epsabs=1e-14)[0]
        assert abs(g - (re + 1j * im)) < 1e-12


# -- (c) brute-force time integration -------------------------------------------------------------------
def _brute_force(system: GearSystem, speed: float, load: float, periods: int) -> np.ndarray:
    """Plain solve_ivp of the gear's J ẍ + r_b f = T_load with the pinion held at Ω, the mesh force from
    :meth:`MeshLink.force` at the nominal phase, from rest over ``periods`` mesh periods; the last
    period's mesh force at 61 instants (N)."""
    mesh = system.meshes[0]
    g, J = mesh.g[1], system.M[1, 1]
    rate = mesh.teeth * speed / (2 * np.pi)  # dτ/dt, cycles/s
    T = 1.0 / rate

    def rhs(t, y):
        return [y[1], (load - g * mesh.force(g * y[0], g * y[1], rate * t, rate)) / J]

    y = [0.0, 0.0]
    P = mesh.samples
    t_eval = T * (periods - 1 + np.arange(61) / 61)
    out = []
    for k in range(periods * P):  # sample interval by interval: no step across a corner
        a, b = k * T / P, (k + 1) * T / P
        inside = t_eval[(t_eval >= a) & (t_eval < b)]
        sol = solve_ivp(rhs, (a, b), y, method="DOP853", rtol=1e-10, atol=1e-14, t_eval=np.append(inside, b))
        for t, x, v in zip(sol.t[:-1], *sol.y[:, :-1], strict=True):
            out.append(mesh.force(g * x, g * v, rate * t, rate))
        y = sol.y[:, -1]
    return np.array(out)


@pytest.mark.slow  # an integration until the transient dies (over 10 s): CI's heavy step
@pytest.mark.parametrize("fraction", [1.1])
def test_steady_state_is_reached_by_time_integration(fraction):
    """Above the mesh resonance (ζ ≈ 0.2): 20 decay times of plain integration reach the
    harmonic-balance steady state to 5e-6 of the force's swing (the truncation of 200 harmonics of a
    24-sample profile; 61 instants, none on a corner of the
    profile, where the error's rate jumps)."""
    P = 24
    system = GearSystem.from_drivetrain(
        _pair(c_mesh=15000.0),
        mesh_profiles={"m": _cosine(P, 0.15)},
        errors={"m": {"amplitude": 1e-6, "samples": P}},
    )
    wn = np.sqrt(3e8 * RB**2 / 0.03)
    speed = fraction * wn / ZA
    decay = 15000.0 * RB**2 / (2 * 0.03)  # ζ ω_n, 1/s
    periods = int(np.ceil(20 / decay * ZA * speed / (2 * np.pi)))
    f = _brute_force(system, speed, 50.0, periods)
    hb = steady_state(
        system, speed, reference="pinion", drive="speed", load={"gear": 50.0}, harmonics=200, points=61
    )
    assert np.abs(hb.mesh_force[:, 0] - f).max() <= 5e-6 * np.ptp(f)


@pytest.mark.parametrize("speed", [60.0, 150.0])
def test_steady_state_matches_simulate(speed):
    """:func:`mechdyn.gear_dynamics.simulate` run 0.12 s to steady state (motor 10⁵ times heavier, so that
    it keeps its speed, driven by the load's torque), sampled 512 times a period: its largest and
    smallest mesh force match the periodic solution's to 3e-3 of the swing. They differ by more than the
    integrations' errors because simulate takes the mesh phase from the actual pinion angle and the
    periodic solution from the nominal one (the pinion's vibration shifts the phase by z θ_vib / 2π)."""
    from mechdyn.gear_dynamics.loads import ConstantTorque
    from mechdyn.gear_dynamics.simulate import simulate

    P, load = 36, 40.0
    kw = {"mesh_profiles": {"m": _cosine(P, 0.15)}, "errors": {"m": {"amplitude": 3e-6, "samples": P}}}
    hb = steady_state(
        GearSystem.from_drivetrain(_train(), **kw),
        speed,
        reference="motor",
        drive="speed",
        load={"load": load},
    )
    big = GearSystem.from_drivetrain(_train(J_motor=1e4), **kw)
    r = big.speed_ratios("motor")
    inputs = [ConstantTorque("load", load), ConstantTorque("motor", load * abs(r[-1]))]
    sim = simulate(
        big,
        0.12,
        inputs=inputs,
        initial_speed=speed,
        reference="motor",
        method="DOP853",
        rtol=1e-9,
        output_step=hb.period / 512,
    )
    f = sim.mesh_forces[0][sim.time > sim.time[-1] - hb.period]
    swing = np.ptp(hb.mesh_force)
    assert abs(f.max() - hb.mesh_force.max()) <= 3e-3 * swing
    assert abs(f.min() - hb.mesh_force.min()) <= 3e-3 * swing


# -- backlash: Newton shooting ---------------------------------------------------------------------------
def test_backlash_sweep_by_newton_continuation():
    """Teeth that stay in contact: the orbit found by Newton's method on the nonlinear flow (started by
    a run from the static deflection, then continued from the speed before) is the linear steady state
    (harmonic balance with 16 harmonics on the same instants: 2e-5 of the force swing, its truncation),
    stable, and its multipliers come from the orbit's own monodromy matrix."""
    P = 24
    kw = {"mesh_profiles": {"m": _cosine(P, 0.1)}, "errors": {"m": {"amplitude": 1e-6, "samples": P}}}
    loose = GearSystem.from_drivetrain(_pair(c_mesh=3000.0), backlash={"m": 2e-5}, **kw)
    tight = GearSystem.from_drivetrain(_pair(c_mesh=3000.0), **kw)
    wn = np.sqrt(3e8 * RB**2 / 0.03)
    speeds = np.array([0.7, 0.75]) * wn / ZA
    nl = speed_sweep(loose, speeds, reference="pinion", drive="speed", load={"gear": 50.0}, refine=0)
    assert nl.converged.all() and "Newton" in nl.method
    linear = speed_sweep(tight, speeds, reference="pinion", drive="speed", load={"gear": 50.0}, refine=0)
    swing = (linear.force_max - linear.force_min).max()
    np.testing.assert_allclose(nl.force_max, linear.force_max, rtol=0, atol=2e-5 * swing)
    np.testing.assert_allclose(nl.force_min, linear.force_min, rtol=0, atol=2e-5 * swing)
    assert (nl.force_min > 0).all()  # in contact throughout
    np.testing.assert_allclose(nl.spectral_radius, linear.spectral_radius, rtol=1e-4)


# -- the sweep -------------------------------------------------------------------------------------------
def _single_mesh_dynamic_factor(
    error: np.ndarray, harmonics: dict[int, complex], speed: float, N: int, c: float, load: float
) -> float:
    """K_v of the pinion-held pair of :func:`_pair` (k = 3e8 N/m, J_b = 0.03 kg·m²) by the closed form
    of :func:`test_constant_stiffness_harmonic_balance_is_the_single_mesh_closed_form` truncated at the
    harmonic balance's H harmonics (``harmonics``: the error's E_h, h = −H … H): δ = r_b x = F_s/k +
    E_0 + Σ r_b X_h e^{ihωt}, the force f = k (δ − e) + c (δ̇ − ė) with e the interpolated error (its
    slope from the right at the corners) on the N instants l T / N, K_v = max f / F_s (F_s = T_load /
    r_b)."""
    k, J, P, H = 3e8, 0.03, error.size, max(harmonics)
    w = ZA * speed
    tau = np.arange(N) / N
    i = np.floor(tau * P).astype(int)
    e = error[i] + (error[(i + 1) % P] - error[i]) * (tau * P - i)
    e_dot = (error[(i + 1) % P] - error[i]) * P * w / (2 * np.pi)
    fs = load / RB
    d = np.full(N, fs / k + harmonics[0].real, complex)
    d_dot = np.zeros(N, complex)
    for h in [*range(-H, 0), *range(1, H + 1)]:
        X = RB * (k + 1j * h * w * c) * harmonics[h] / (k * RB**2 - (h * w) ** 2 * J + 1j * h * w * c * RB**2)
        d += RB * X * np.exp(2j * np.pi * h * tau)
        d_dot += 1j * h * w * RB * X * np.exp(2j * np.pi * h * tau)
    return float(np.max(k * (d.real - e) + c * (d_dot.real - e_dot)) / fs)


def test_speed_sweep_finds_the_mesh_resonance_and_refines_it():
    """Constant stiffness, error excitation, pinion held: the gear's mode k r_b² / J_b is excited at
    z Ω = ω_n; the refined peak lies within 0.5 % of it (damping shifts it by ζ², 1e-4). K_v at every
    speed swept is the single-mesh closed form with the same 4 harmonics on the same 256 instants
    (:func:`_single_mesh_dynamic_factor`), 1e-9 relative (measured 1e-14); its largest, 223.12 (the
    error's 2 µm against the static deflection of 20 N·m), is within 1e-4 of the closed form's peak
    over speed (the refinement's reach; measured 2e-5)."""
    P = 16
    system = GearSystem.from_drivetrain(_pair(c_mesh=400.0), errors={"m": {"amplitude": 2e-6, "samples": P}})
    wn = np.sqrt(3e8 * RB**2 / 0.03)
    speeds = np.linspace(0.5, 1.5, 11) * wn / ZA
    r = speed_sweep(
        system, speeds, reference="pinion", drive="speed", load={"gear": 20.0}, harmonics=4, refine=6
    )
    assert r.speeds.size > speeds.size
    (peak,) = [p for p in r.resonances()["m"] if 0.9 * wn / ZA < p < 1.1 * wn / ZA]
    assert peak == pytest.approx(wn / ZA, rel=5e-3)
    kv = r.dynamic_factor[:, 0]
    error = np.asarray(system.meshes[0].error, float)
    E = {h: _quad_harmonic(error, h) for h in range(-4, 5)}
    closed = [_single_mesh_dynamic_factor(error, E, s, 256, 400.0, 20.0) for s in r.speeds]
    np.testing.assert_allclose(kv, closed, rtol=1e-9)
    fine = np.linspace(0.995, 1.005, 101) * wn / ZA
    top = max(_single_mesh_dynamic_factor(error, E, s, 256, 400.0, 20.0) for s in fine)
    assert np.nanmax(kv) == pytest.approx(top, rel=1e-4)
    assert top == pytest.approx(223.13, rel=1e-4)
    assert r.stable.all()
    frame = r.to_frame()
    assert {"speed_rad_s", "speed_rpm", "m_dynamic_factor_ratio", "m_dte_amplitude_m"} <= set(frame.columns)
    summary = r.summary()
    assert summary["meshes"]["m"]["static_force_N"] == pytest.approx(20.0 / RB)
    assert r.tables()[0].rows[0][0] == "m"
    assert set(r.plots()) == {"speed_sweep.png", "speed_sweep_dte.png"}
    assert set(r.arrays()) >= {"speed_rad_s", "m_force_max_N"}


def test_speed_sweep_flags_parametric_instability():
    """A 30 % stiffness variation with little damping at z Ω = 2 ω_n: the principal parametric
    resonance; the periodic solution exists but is unstable, and the result says so."""
    system = GearSystem.from_drivetrain(_pair(c_mesh=50.0), mesh_profiles={"m": _cosine(32, 0.3)})
    wn = np.sqrt(3e8 * RB**2 / 0.03)
    r = speed_sweep(system, [2 * wn / ZA], reference="pinion", drive="speed", load={"gear": 20.0}, refine=0)
    assert not r.stable[0] and r.spectral_radius[0] > 1.0
    assert any("unstable" in w for w in r.warnings)


def test_no_load_gives_no_dynamic_factor():
    system = GearSystem.from_drivetrain(_pair(), errors={"m": {"amplitude": 1e-6, "samples": 8}})
    r = speed_sweep(system, [50.0, 60.0], reference="pinion", drive="speed", refine=0, stability=False)
    assert np.isnan(r.dynamic_factor).all() and np.isnan(r.spectral_radius).all()
    assert any("no load" in w for w in r.warnings)


def test_several_meshes_share_their_common_period():
    """Two flexible meshes with z 20/50 and 25/40: mesh frequencies 20 Ω and 10 Ω (gear speed 0.4 Ω),
    common fundamental 10 Ω; harmonic balance (40 harmonics of each mesh frequency) equals shooting over
    it to 1e-5 of the force swing."""
    dt = Drivetrain(
        [Disk("motor", 0.05), Disk("p1", 0.002), Disk("g1", 0.03), Disk("p2", 0.004), Disk("g2", 0.05)],
        [
            Shaft("s1", ("motor", "p1"), 2e4, damping=20.0),
            GearMesh(
                "m1", ("p1", "g1"), teeth=(20, 50), base_radii=(0.0188, 0.047), stiffness=3e8, damping=900.0
            ),
            Shaft("s2", ("g1", "p2"), 5e4, damping=30.0),
            GearMesh(
                "m2", ("p2", "g2"), teeth=(25, 40), base_radii=(0.025, 0.04), stiffness=4e8, damping=900.0
            ),
        ],
    )
    system = GearSystem.from_drivetrain(dt, mesh_profiles={"m1": _cosine(128, 0.1), "m2": _cosine(128, 0.1)})
    sh = steady_state(system, 80.0, reference="motor", drive="speed", load={"g2": 30.0}, method="shooting")
    hb = steady_state(
        system, 80.0, reference="motor", drive="speed", load={"g2": 30.0}, harmonics=40, points=sh.time.size
    )
    assert sh.period == pytest.approx(2 * np.pi / (10 * 80.0))
    assert np.abs(hb.mesh_force - sh.mesh_force).max() <= 1e-5 * np.ptp(sh.mesh_force, axis=0).max()


# -- (f) bad input -----------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"reference": "nope"}, "reference"),
        ({"speeds": [-1.0]}, "speeds"),
        ({"speeds": [float("nan")]}, "speeds"),
        ({"speeds": []}, "speeds"),
        ({"method": "euler"}, "method"),
        ({"harmonics": 0}, "harmonics"),
        ({"refine": -1}, "refine"),
        ({"load": {"nope": 1.0}}, "load"),
        ({"load": {"gear": "ten"}}, "load['gear']"),
        ({"gear_pairs": {"nope": None}}, "gear_pairs"),
        ({"integrator": "rk4", "method": "shooting"}, "integrator"),
    ],
)
def test_bad_input_names_the_field(kwargs, field):
    system = GearSystem.from_drivetrain(_pair())
    args = {"speeds": [50.0], "reference": "pinion", **kwargs}
    with pytest.raises(ModelError) as err:
        speed_sweep(system, args.pop("speeds"), **args)
    assert err.value.field == field


def test_harmonic_balance_refuses_backlash_and_a_grounded_train():
    loose = GearSystem.from_drivetrain(_pair(), backlash={"m": 1e-5})
    with pytest.raises(ModelError, match="shooting") as err:
        steady_state(loose, 50.0, reference="pinion", drive="speed", method="harmonic_balance")
    assert err.value.field == "method"
    dt = _pair()
    grounded = Drivetrain(dt.disks, (*dt.elements, GroundSpring("clamp", "gear", 1e5)))
    with pytest.raises(ModelError, match="steady speed") as err:
        steady_state(GearSystem.from_drivetrain(grounded), 50.0, reference="pinion", drive="speed")
    assert err.value.field == "reference"


def test_iso_dynamic_factor_beside_the_computed_one():
    """Gear data given: the sweep carries ISO 6336-1 Method B's K_v of the pair at the pinion's speed and
    torque (:func:`mechdyn.gears.iso_dynamic_factor`), 1 or more, in its table and frame."""
    from mechdyn.gears import GearPair, SpurGear

    pair = GearPair(SpurGear(20, 0.003, 0.03, name="pinion"), SpurGear(40, 0.003, 0.03, name="gear"))
    dt = Drivetrain(
        [Disk("pinion", 0.002), Disk("gear", 0.01)],
        [GearMesh.from_gear_pair("m", ("pinion", "gear"), pair, damping=1500.0, points=40)],
    )
    system = GearSystem.from_drivetrain(dt, mesh_profiles={"m": pair.mesh_cycle(40)})
    r = speed_sweep(
        system, [100.0, 300.0], reference="pinion", drive="speed", load={"gear": 80.0}, gear_pairs={"m": pair}
    )
    iso = r.iso_dynamic_factor[:, 0]
    assert np.isfinite(iso).all() and (iso >= 1.0).all()
    assert np.isfinite(r.to_frame()["m_iso_dynamic_factor_ratio"]).all()
    assert r.tables()[0].rows[0][3] == pytest.approx(iso.max())


def test_meshes_without_a_common_period_use_the_dominant_ones():
    """Teeth 20/89 then 97/50: mesh frequencies in the ratio 97/89, no common period within 64 mesh
    periods; the varying mesh's period is used, the other mesh held at its mean stiffness, and the
    result says so."""
    dt = Drivetrain(
        [Disk("motor", 0.05), Disk("p1", 0.002), Disk("g1", 0.03), Disk("g2", 0.02)],
        [
            Shaft("s1", ("motor", "p1"), 2e4, damping=20.0),
            GearMesh(
                "m1", ("p1", "g1"), teeth=(20, 89), base_radii=(0.0188, 0.0837), stiffness=3e8, damping=900.0
            ),
            GearMesh(
                "m2", ("g1", "g2"), teeth=(97, 50), base_radii=(0.0912, 0.047), stiffness=4e8, damping=900.0
            ),
        ],
    )
    system = GearSystem.from_drivetrain(dt, mesh_profiles={"m1": _cosine(16, 0.2), "m2": _cosine(16, 0.05)})
    r = speed_sweep(system, [60.0], reference="motor", drive="speed", load={"g2": 10.0}, refine=0)
    assert any("no common period" in w and "'m1'" in w for w in r.warnings)
    s = steady_state(system, 60.0, reference="motor", drive="speed", load={"g2": 10.0})
    assert s.period == pytest.approx(2 * np.pi / (20 * 60.0))
