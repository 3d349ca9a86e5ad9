"""Time simulation of geared drivetrains, checked against closed forms, the modal analysis, the energy
balance, a motor's steady speed and an independent single-degree-of-freedom model (Kahraman & Singh
1990) written here from the textbook equations."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from mechdyn.drive import InductionMotor, TorqueSpeedCurve
from mechdyn.drivetrain import Disk, Drivetrain, GearMesh, GroundSpring, RayleighDamping, Shaft, frf, modal
from mechdyn.errors import ModelError
from mechdyn.gear_dynamics import (
    BrakeStop,
    ConstantTorque,
    GearSystem,
    HarmonicTorque,
    MotorTorque,
    RampTorque,
    StepTorque,
    TabulatedTorque,
    simulate,
)
from mechdyn.units import convert

RA, RB, Z = 0.02, 0.04, 20  # base radii (m) and pinion teeth of the test pair


def _pair(ja=0.001, jb=0.004, k=1e8, c=0.0) -> Drivetrain:
    return Drivetrain(
        [Disk("a", ja), Disk("b", jb)],
        [GearMesh("m", ("a", "b"), teeth=(Z, 2 * Z), base_radii=(RA, RB), stiffness=k, damping=c)],
        name="pair",
    )


def _effective_mass(ja: float, jb: float) -> float:
    """m_e = 1 / (r_a²/J_a + r_b²/J_b), kg."""
    return 1.0 / (RA**2 / ja + RB**2 / jb)


def _crossings(t: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Times of upward zero crossings, linearly interpolated."""
    i = np.flatnonzero((x[:-1] < 0) & (x[1:] >= 0))
    return t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i])


# -- (a) free vibration at the modal frequency --------------------------------------------------------
@pytest.mark.parametrize("with_shaft", [False, True])
def test_free_vibration_at_the_modal_frequency(with_shaft):
    if with_shaft:  # a motor disk on a stiff shaft: the mesh mode is still the lowest, others far above
        dt = Drivetrain(
            [Disk("motor", 0.0005), Disk("a", 0.001), Disk("b", 0.004)],
            [
                Shaft("s", ("motor", "a"), 5e5),
                GearMesh("m", ("a", "b"), teeth=(Z, 2 * Z), base_radii=(RA, RB), stiffness=1e8, damping=0.5),
            ],
        )
    else:
        dt = _pair(c=0.5)
    f_modal = modal(dt).frequencies_hz
    system = GearSystem.from_drivetrain(dt)
    # a torque switched on at rest: the train accelerates and rings about the static deflection
    result = simulate(
        system,
        0.02,
        inputs=[ConstantTorque("a", 20.0)],
        start="rest",
        rtol=1e-11,
        atol=1e-15,
        output_step=2e-6,
    )
    x = result.dte[0] - result.static_mesh_forces[0] / 1e8
    if with_shaft:  # take out the higher (shaft) mode: both are in the response; keep the mesh one
        spectrum = np.abs(np.fft.rfft(x * np.hanning(x.size)))
        freqs = np.fft.rfftfreq(x.size, 2e-6)
        assert abs(freqs[np.argmax(spectrum)] - f_modal[0]) < 2 / 0.02
        return
    up = _crossings(result.time, x)
    f_sim = (up.size - 1) / (up[-1] - up[0])
    # small damping lowers the frequency by ζ²/2 ≈ 1e-8: the undamped modal value holds to 1e-4
    assert f_sim == pytest.approx(f_modal[0], rel=1e-5)
    assert f_modal[0] == pytest.approx(math.sqrt(1e8 / _effective_mass(0.001, 0.004)) / (2 * math.pi))
    # at the default tolerances too
    default = simulate(system, 0.02, inputs=[ConstantTorque("a", 20.0)], start="rest", output_step=2e-6)
    up = _crossings(default.time, default.dte[0] - default.static_mesh_forces[0] / 1e8)
    assert (up.size - 1) / (up[-1] - up[0]) == pytest.approx(f_modal[0], rel=1e-4)


def test_harmonic_steady_state_is_the_frequency_response():
    """A grounded train (a clamp on the load) under a harmonic torque: after the transient has died
    (the slowest mode decays in 18 ms, the run lasts 300 ms) the disks move as
    :func:`mechdyn.drivetrain.frf` says, amplitude and phase."""
    dt = Drivetrain(
        [Disk("motor", 0.002), Disk("a", 0.001), Disk("b", 0.004)],
        [
            Shaft("s", ("motor", "a"), 2e4, damping=20.0),
            GearMesh("m", ("a", "b"), teeth=(Z, 2 * Z), base_radii=(RA, RB), stiffness=1e8, damping=150.0),
            GroundSpring("clamp", "b", 5e4),
        ],
    )
    f = 400.0  # Hz, between the first two modes
    torque = HarmonicTorque("motor", 3.0, f, phase=0.3)
    period = 1.0 / f
    result = simulate(
        GearSystem.from_drivetrain(dt), 120 * period, inputs=[torque], start="rest", rtol=1e-10, atol=1e-15
    )
    reference = frf(dt, [f], {"motor": 3.0 * np.exp(0.3j)}, damping=RayleighDamping(0.0, 0.0))
    last = result.time > result.time[-1] - 4 * period
    t = result.time[last]
    basis = np.column_stack([np.cos(2 * np.pi * f * t), -np.sin(2 * np.pi * f * t)])
    for i, disk in enumerate(result.disk_names):
        (re, im), *_ = np.linalg.lstsq(basis, result.angles[i, last], rcond=None)
        expected = reference.angles[0, reference.disk_names.index(disk)]
        assert abs((re + 1j * im) - expected) <= 1e-5 * abs(expected), disk


# -- (b) energy balance -------------------------------------------------------------------------------
@pytest.mark.parametrize(
    "kwargs",
    [
        {},
        {"mesh_profiles": {"m": {"fluctuation": 0.3, "contact_ratio": 1.6}}},
        {
            "mesh_profiles": {"m": {"fluctuation": 0.3, "contact_ratio": 1.6}},
            "errors": {"m": {"amplitude": 4e-6}},
            "backlash": {"m": 2e-5},
        },
    ],
    ids=["constant", "varying", "varying-error-backlash"],
)
def test_energy_balance(kwargs):
    dt = Drivetrain(
        [Disk("motor", 0.002), Disk("a", 0.001), Disk("b", 0.004)],
        [
            Shaft("s", ("motor", "a"), 2e4, damping=0.3),
            GearMesh("m", ("a", "b"), teeth=(Z, 2 * Z), base_radii=(RA, RB), stiffness=1e8, damping=60.0),
        ],
    )
    system = GearSystem.from_drivetrain(dt, **kwargs)
    w = 2 * math.pi * 1400 / Z  # mesh frequency near the mesh mode
    result = simulate(
        system,
        0.003 if "backlash" in kwargs else 0.01,
        inputs=[ConstantTorque("motor", 6.0), ConstantTorque("b", 11.0)],
        initial_speed=w,
        start="rest",
        rtol=1e-9,
        atol=1e-13,
        energy_atol=1e-12,
    )
    e = result.energy
    balance = result.energy_balance
    residual = np.abs(balance - balance[0]).max()
    # against the vibration's energies (the rigid rotation's kinetic energy is a thousand times more)
    scale = e["strain"].max() + e["dissipated"][-1] + np.abs(e["parametric_work"]).max()
    # (with backlash the located contact changes add their root-finding error: 1e-5)
    assert residual <= (1e-5 if "backlash" in kwargs else 1e-6) * scale
    assert e["dissipated"][-1] > 0
    assert e["input_work"][-1] > 10 * scale
    if kwargs:  # the parametric term matters: without it the balance would miss by far more
        assert np.abs(e["parametric_work"]).max() > 1e4 * residual
    else:
        assert np.abs(e["parametric_work"]).max() == 0.0
    if "backlash" in kwargs:
        assert result.contact_losses  # the balance holds through contact changes


# -- (c) rigid-body acceleration ----------------------------------------------------------------------
@pytest.mark.parametrize("start", ["static", "rest"])
def test_constant_torque_accelerates_the_rigid_body(start):
    ja, jb, torque = 0.001, 0.004, 3.0
    # from rest the stiffness varies too; from the static deflection it is constant, so that the train
    # turns as a rigid body with a constant deflection
    profile = {"m": {"fluctuation": 0.2, "contact_ratio": 1.5}} if start == "rest" else None
    system = GearSystem.from_drivetrain(_pair(ja, jb, c=20.0), mesh_profiles=profile)
    duration = 0.01
    result = simulate(
        system,
        duration,
        inputs=[ConstantTorque("a", torque)],
        initial_speed=50.0,
        start=start,
        rtol=1e-10,
        atol=1e-14,
    )
    j_total = ja + jb * (RA / RB) ** 2  # inertia reduced to disk a
    # the rigid-body momentum Rᵀ M q̇ grows by the torque's work on the rigid motion, exactly
    r = system.speed_ratios("a")
    qd = np.linalg.lstsq(system.T, result.speeds, rcond=None)[0]
    momentum = r @ system.M @ qd
    np.testing.assert_allclose(momentum - momentum[0], torque * (result.time - result.time[0]), atol=1e-9)
    mean_acc = (momentum[-1] - momentum[0]) / j_total / duration
    assert mean_acc == pytest.approx(torque / j_total, rel=1e-9)
    if start == "static":  # no vibration: the disks themselves accelerate uniformly
        acc = np.diff(result.speed("a")) / np.diff(result.time)
        np.testing.assert_allclose(acc, torque / j_total, rtol=1e-6)
        np.testing.assert_allclose(result.mesh_forces[0], result.static_mesh_forces[0], rtol=1e-6)


def test_a_train_with_rigid_and_internal_meshes_accelerates_with_its_static_mesh_forces():
    """Motor — shaft — pinion ~ m1 ~ gear — shaft — pinion2 = rigid m2 = gear2 ~ internal m3 ~ ring —
    shaft — load: from the d'Alembert static start the train turns as a rigid body and every mesh
    carries the force the torque balance of the disks behind it gives."""
    dt = Drivetrain(
        [Disk("motor", 0.05), Disk("pinion", 0.002), Disk("gear", 0.03), Disk("pinion2", 0.004),
         Disk("gear2", 0.06), Disk("ring", 0.2), Disk("load", 1.5)],
        [
            Shaft("s1", ("motor", "pinion"), 2.0e4, damping=3.0),
            GearMesh("m1", ("pinion", "gear"), teeth=(20, 50), base_radii=(0.0188, 0.047), stiffness=3e8),
            Shaft("s2", ("gear", "pinion2"), 5.0e4),
            GearMesh("m2", ("pinion2", "gear2"), teeth=(18, 36)),
            GearMesh("m3", ("gear2", "ring"), kind="internal", teeth=(30, 90), base_radii=(0.03, 0.09),
                     stiffness=5e8, damping=100.0),
            Shaft("s3", ("ring", "load"), 1.0e5),
        ],
    )  # fmt: skip
    system = GearSystem.from_drivetrain(dt)
    torque = 40.0
    result = simulate(
        system, 0.02, inputs=[ConstantTorque("motor", torque)], initial_speed=10.0, rtol=1e-10, atol=1e-14
    )
    ratios = system.T @ system.speed_ratios("motor")  # every disk's rigid rotation per motor rotation
    J = dt.inertias
    alpha = torque / (J @ ratios**2)
    idx = dt.disk_index
    # m1: the motor and pinion are driven by the torque and decelerated by their inertia
    f1 = (torque - (J[idx["motor"]] + J[idx["pinion"]]) * alpha) / 0.0188
    # m3 (internal, δ = r_a θ_a − r_b θ_b): the ring and the load are driven by + r_b f
    f3 = (J[idx["ring"]] * ratios[idx["ring"]] + J[idx["load"]] * ratios[idx["load"]]) * alpha / 0.09
    np.testing.assert_allclose(result.mesh_force("m1"), f1, rtol=1e-6)
    np.testing.assert_allclose(result.mesh_force("m3"), f3, rtol=1e-6)
    assert ratios[idx["ring"]] > 0 > ratios[idx["gear"]]  # internal keeps the sense, external reverses
    np.testing.assert_allclose(result.static_mesh_forces, [f1, f3], rtol=1e-9)
    # the shafts' torques from their load rows, k (θ_b − θ_a): s3 accelerates the load alone, so it
    # twists the load behind the ring
    np.testing.assert_allclose(
        result.element_torques["s3"], -J[idx["load"]] * ratios[idx["load"]] * alpha, rtol=1e-6
    )


# -- (d) backlash -------------------------------------------------------------------------------------
def _rattling_pair(error: float, fluctuation: float = 0.0):
    dt = _pair(c=60.0)
    profiles = {"m": {"fluctuation": fluctuation, "contact_ratio": 1.6}} if fluctuation else None
    errors = {"m": {"amplitude": error}} if error else None
    system = GearSystem.from_drivetrain(dt, mesh_profiles=profiles, errors=errors, backlash={"m": 3e-5})
    f_n = modal(dt).frequencies_hz[0]
    w = 2 * math.pi * f_n / Z  # mesh frequency at the mesh resonance
    torque = 1.0  # light: the static deflection 0.2 µm (F = T / r_a = 50 N)
    inputs = [ConstantTorque("a", torque), ConstantTorque("b", torque * RB / RA)]
    return simulate(system, 0.01, inputs=inputs, initial_speed=w, rtol=1e-9, atol=1e-13)


def test_light_load_near_resonance_loses_contact():
    result = _rattling_pair(error=2e-6)
    losses = result.contact_losses
    assert len(losses) >= 5
    for c in losses:
        assert c.mesh == "m"
        inside = (result.time > c.start) & (result.time < (c.end if c.end is not None else np.inf))
        assert np.all(result.dte[0][inside] <= 1e-12)  # the drive flanks are apart
        assert np.all(result.mesh_forces[0][inside & (result.contact_modes[0] == 1)] == 0.0)
    back = result.dte[0] < -3e-5
    impacts = sum(c.back_impacts for c in losses)
    assert (impacts > 0) == bool(back.any())
    s = result.summary()
    assert s["contact_losses"]["m"] == len(losses)
    assert s["first_contact_loss_s"]["m"] == pytest.approx(losses[0].start)
    assert s["dynamic_factor"]["m"] > 2.0


def test_without_excitation_the_contact_holds():
    result = _rattling_pair(error=0.0)
    assert result.contact_losses == ()
    assert np.all(result.contact_modes == 0)
    np.testing.assert_allclose(result.mesh_forces[0], 50.0, rtol=1e-6)
    assert result.summary()["dynamic_factor"]["m"] == pytest.approx(1.0, abs=1e-6)


# -- (e) motor start-up -------------------------------------------------------------------------------
@pytest.mark.parametrize("kind", ["kloss", "curve"])
def test_motor_start_up_reaches_the_speed_of_the_motor_curve(kind):
    if kind == "kloss":
        motor = InductionMotor.from_rating("1.5 kW", "1500 rpm", "1440 rpm", 2.5)
        low, high = motor.pullout_speed, motor.synchronous_speed
    else:  # a maker's curve: the steady speed lies on its last segment, 1400 + 100 · 14/20 rpm
        rows = [("0 rpm", "30 N*m"), ("1400 rpm", "20 N*m"), ("1500 rpm", "0 N*m")]
        motor = TorqueSpeedCurve.from_table(rows)
        low, high = motor.speeds[1], motor.speeds[2]
    dt = Drivetrain(
        [Disk("rotor", 0.004), Disk("a", 0.001), Disk("b", 0.01)],
        [
            Shaft("s", ("rotor", "a"), 2e4, damping=1.0),
            GearMesh("m", ("a", "b"), teeth=(Z, 2 * Z), base_radii=(RA, RB), stiffness=1e8, damping=100.0),
        ],
    )
    system = GearSystem.from_drivetrain(dt)
    load = 12.0  # N·m on b, against its rotation (b turns backwards: a positive torque brakes it)
    inputs = [MotorTorque("rotor", motor), ConstantTorque("b", load)]
    result = simulate(system, 0.4, inputs=inputs, rtol=1e-8)
    # steady state: the motor gives the load reflected through the mesh, T_m(ω) = T_L r_a / r_b
    w = brentq(lambda x: motor.torque(x) - load * RA / RB, low, high)
    if kind == "curve":
        assert w == pytest.approx(convert(1470.0, "rpm", "rad/s"), rel=1e-12)
    assert result.speed("rotor")[-1] == pytest.approx(w, rel=1e-5)
    assert result.speed("b")[-1] == pytest.approx(-w * RA / RB, rel=1e-5)
    assert result.speed("rotor").max() < motor.no_load_speed
    # the static mesh force is the load's: T_L / r_b
    assert result.static_mesh_forces[0] == pytest.approx(load / RB, rel=1e-9)
    s = result.summary()
    assert s["final_speed_rad_s"]["rotor"] == pytest.approx(w, rel=1e-5)


def test_brake_stop_and_other_inputs():
    ja, jb = 0.001, 0.004
    j_total = ja + jb * (RA / RB) ** 2
    system = GearSystem.from_drivetrain(_pair(ja, jb, c=50.0))
    w0, brake = 100.0, 10.0
    stop = BrakeStop(ConstantTorque("a", 0.5), time=0.002, brake=brake, hold_speed=0.1)
    result = simulate(system, 0.03, inputs=[stop], initial_speed=w0, rtol=1e-9)
    # before the stop: 0.5 N·m accelerates; after: the brake decelerates at brake / J to standstill
    w_stop = w0 + 0.5 / j_total * 0.002
    t_zero = 0.002 + w_stop * j_total / brake
    # the rigid speed (momentum over inertia): the disks ring about it after the torque's jump
    rigid = (ja * result.speed("a") - jb * result.speed("b") * RA / RB) / j_total
    i = np.searchsorted(result.time, 0.002 + 0.5 * (t_zero - 0.002))
    w_mid = w_stop - brake / j_total * (result.time[i] - 0.002)
    assert rigid[i] == pytest.approx(w_mid, rel=1e-6)
    assert abs(rigid[-1]) < 1e-4 * w0  # held by the brake (the disks still ring about standstill)
    assert 0.002 in result.time or np.any(np.isclose(result.time, 0.002, rtol=0, atol=1e-12))
    # step, ramp and table agree where they describe the same torque
    ramp = RampTorque("a", 1.0, start=0.001, end=0.003)
    table = TabulatedTorque.from_table("a", [("1 ms", "0 N*m"), ("3 ms", "1 N*m")])
    assert [ramp.torque(t, 0.0) for t in (0.0, 0.002, 0.004)] == [0.0, 0.5, 1.0]
    assert table.torque(0.002, 0.0) == pytest.approx(0.5)
    step = StepTorque("a", "2 N*m", "1 ms")
    assert (step.torque(0.0009, 0.0), step.torque(0.001, 0.0)) == (0.0, 2.0)
    r1 = simulate(system, 0.004, inputs=[ramp], rtol=1e-10, start="rest")
    r2 = simulate(system, 0.004, inputs=[table], rtol=1e-10, start="rest")
    assert r1.speed("a")[-1] == pytest.approx(r2.speed("a")[-1], rel=1e-8)
    rigid_end = (ja * r1.speed("a")[-1] - jb * r1.speed("b")[-1] * RA / RB) / j_total
    assert rigid_end == pytest.approx(0.002 / j_total, rel=1e-8)  # ∫T dt = 1 ms·1 + 2 ms·0.5


# -- (f) an independent single-degree-of-freedom model -------------------------------------------------
@pytest.mark.parametrize("backlash", [None, 3e-6])
def test_against_the_single_degree_of_freedom_dte_model(backlash):
    """m_e x″ + c x′ + k(t) h(x) = F − m_e e″(t) (Kahraman & Singh 1990), written here from the textbook
    with a cosine stiffness and a sine error at the mesh frequency of a constant speed Ω."""
    ja, jb, kbar, c = 1.0, 0.004, 1e8, 40.0  # a heavy pinion: its speed holds, as the model assumes
    alpha, amp, samples = 0.25, 2e-6, 4096
    me = _effective_mass(ja, jb)
    wn = math.sqrt(kbar / me)
    omega = 1.15 * wn / Z  # mesh frequency above the resonance
    wm = Z * omega
    force = 20.0
    tau = np.arange(samples) / samples
    system = GearSystem.from_drivetrain(
        _pair(ja, jb, k=kbar, c=c),
        mesh_profiles={"m": 1.0 + alpha * np.cos(2 * np.pi * tau)},
        errors={"m": amp * np.sin(2 * np.pi * tau)},
        backlash=None if backlash is None else {"m": backlash},
    )
    inputs = [ConstantTorque("a", force * RA), ConstantTorque("b", force * RB)]
    duration, step = 0.004, 2e-6
    result = simulate(
        system, duration, inputs=inputs, initial_speed=omega, rtol=1e-11, atol=1e-15, output_step=step
    )

    def k_of(t):
        return kbar * (1 + alpha * math.cos(wm * t))

    def h(x):
        if backlash is None or x > 0:
            return x, True
        if x < -backlash:
            return x + backlash, True
        return 0.0, False

    def sdof(t, y):
        x, v = y
        hx, contact = h(x)
        e_dd = -amp * wm**2 * math.sin(wm * t)
        f = k_of(t) * hx + (c * v if contact else 0.0)
        return [v, (force - f) / me - e_dd]

    x0 = force / k_of(0.0)  # the static start of simulate(): x = F/k(τ₀), δ̇ = 0 so ẋ = −ė
    v0 = -amp * wm
    ref = solve_ivp(
        sdof,
        (0, duration),
        [x0, v0],
        method="DOP853",
        rtol=1e-12,
        atol=1e-16,
        max_step=1 / wm / 50,
        t_eval=result.time,
        dense_output=False,
    )
    scale = np.ptp(ref.y[0])
    assert scale > 1e-7
    # differences: the pinion's own vibration shifts the mesh phase (κ δ, κ ≈ 0.05 rad/m here) and the
    # stiffness and error are sampled 4096 times per cycle; measured 8e-6 of the response (4e-6 with
    # backlash)
    np.testing.assert_allclose(result.dte[0], ref.y[0], atol=5e-5 * scale)
    if backlash is not None:
        assert result.contact_losses and np.any(ref.y[0] < 0)


# -- discontinuous stiffness: the step limit per mesh cycle keeps the accuracy ----------------------------
def test_stiffness_jumps_are_resolved(monkeypatch):
    """Far above the resonance the response is smooth and the error control alone takes steps of a
    large part of the mesh period, long enough to step over the jumps of the stiffness on some machines
    (how far it goes follows the rounding, which follows the CPU); the step limit of ``cycle_steps``
    per mesh cycle keeps every step within that part of the period, and the response within 1 % of a
    reference run."""
    import scipy.integrate

    steps: list[float] = []

    class Recorded(scipy.integrate.LSODA):  # the default method, every step's length kept
        def step(self):
            t = self.t
            message = super().step()
            steps.append(self.t - t)
            return message

    monkeypatch.setattr(scipy.integrate, "LSODA", Recorded)
    profile = {"m": {"fluctuation": 0.4, "contact_ratio": 1.55}}
    system = GearSystem.from_drivetrain(_pair(c=400.0), mesh_profiles=profile)
    inputs = [ConstantTorque("a", 2.0), ConstantTorque("b", 4.0)]
    w = 2 * math.pi * 6 * 1423.5 / Z  # mesh frequency six times the mesh mode's
    mesh_period = 2 * math.pi / (w * Z)
    kw = {"inputs": inputs, "initial_speed": w, "output_step": 2e-6}
    fine = simulate(system, 0.003, rtol=1e-10, atol=1e-14, cycle_steps=64, **kw)
    scale = np.ptp(fine.dte[0])
    steps.clear()
    default = simulate(system, 0.003, **kw)
    assert max(steps) <= mesh_period / 8 * 1.01  # 8 steps a cycle at least (the speed drifts a little)
    assert np.abs(default.dte[0] - fine.dte[0]).max() < 0.01 * scale
    steps.clear()
    simulate(system, 0.003, cycle_steps=1, **kw)
    assert max(steps) > 1.5 * mesh_period / 8  # without the limit the steps grow past it: it binds


@pytest.mark.parametrize("method", ["Radau", "BDF", "DOP853"])
def test_every_integrator_gives_the_same_rattle(method):
    """The integrator is an argument: each finds the same contact changes and the same motion."""
    system = GearSystem.from_drivetrain(
        _pair(c=60.0), errors={"m": {"amplitude": 2e-6}}, backlash={"m": 3e-5}
    )
    w = 2 * math.pi * 1423.5 / Z
    kw = {"inputs": [ConstantTorque("a", 1.0), ConstantTorque("b", 2.0)], "initial_speed": w}
    kw |= {"output_step": 5e-6, "rtol": 1e-10, "atol": 1e-14}
    reference = simulate(system, 0.001, **kw)
    other = simulate(system, 0.001, method=method, **kw)
    assert reference.contact_losses
    assert [c.mesh for c in other.contact_losses] == [c.mesh for c in reference.contact_losses]
    np.testing.assert_allclose(
        [c.start for c in other.contact_losses], [c.start for c in reference.contact_losses], atol=1e-9
    )
    np.testing.assert_allclose(other.dte[0], reference.dte[0], atol=1e-4 * np.ptp(reference.dte[0]))
    np.testing.assert_allclose(other.time, reference.time, rtol=0, atol=1e-15)


# -- the result protocol ------------------------------------------------------------------------------
def test_result_protocol(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    from mechdyn.units import key_unit

    result = _rattling_pair(error=2e-6)
    s = result.summary()
    for key, value in s.items():
        if isinstance(value, float):
            assert key_unit(key) is not None or key in ("dynamic_factor",), key
    frame = result.to_frame()
    assert {"time_s", "a_speed_rad_s", "m_force_N", "m_dte_m"} <= set(frame.columns)
    assert len(frame) == result.time.size
    tables = {t.title: t for t in result.tables(force_unit="kN")}
    assert list(tables) == ["summary", "speeds", "meshes", "contact losses"]
    # speeds in rpm; the contact losses one row per mesh, adding up the intervals
    from mechdyn.units import convert

    assert tables["speeds"].rows[0][2] == pytest.approx(convert(s["final_speed_rad_s"]["a"], "rad/s", "rpm"))
    (row,) = tables["contact losses"].rows
    lost = result.contact_losses
    assert row[:2] == ["m", len(lost)] and row[-1] == sum(c.back_impacts for c in lost)
    ends = [c.end if c.end is not None else result.time[-1] for c in lost]
    apart = sum(e - c.start for c, e in zip(lost, ends, strict=True))
    assert row[2] == pytest.approx(convert(apart, "s", "ms"))
    arrays = result.arrays()
    assert arrays["m_force_N"][1] == "N" and arrays["energy_kinetic_J"][1] == "J"
    plots = result.plots()
    assert set(plots) == {"speeds.png", "mesh_forces.png", "dte.png"}
    for draw in plots.values():
        ax = draw()
        assert ax.get_lines()
    assert "SimulationResult" in repr(result)
    with pytest.raises(ModelError, match="not a flexible mesh"):
        result.mesh_force("nowhere")


def test_bad_arguments_are_named():
    system = GearSystem.from_drivetrain(_pair())
    with pytest.raises(ModelError) as info:
        simulate(system, -1.0)
    assert info.value.field == "duration"
    with pytest.raises(ModelError, match="'x' is not a disk"):
        simulate(system, 0.01, inputs=[ConstantTorque("x", 1.0)])
    with pytest.raises(ModelError) as info:
        simulate(system, 0.01, method="Euler")
    assert info.value.field == "method"
    with pytest.raises(ModelError) as info:
        RampTorque("a", 1.0, start=0.2, end=0.1)
    assert info.value.field == "end"


def test_a_shaft_with_consistent_inertia_turns_with_the_train():
    """Shaft inertia (a non-diagonal M) and the nodes inside a divided shaft: the d'Alembert static
    start still accelerates the train as a rigid body, and every node has its own speed history."""
    dt = Drivetrain(
        [Disk("motor", 0.05), Disk("a", 0.001), Disk("b", 0.004)],
        [
            Shaft("s", ("motor", "a"), 2e4, inertia=0.002, elements=3),
            GearMesh("m", ("a", "b"), teeth=(Z, 2 * Z), base_radii=(RA, RB), stiffness=1e8, damping=10.0),
        ],
    )
    system = GearSystem.from_drivetrain(dt)
    torque = 5.0
    result = simulate(system, 0.01, inputs=[ConstantTorque("motor", torque)], initial_speed=20.0, atol=1e-14)
    r = system.speed_ratios("motor")
    alpha = torque / (r @ system.M @ r)
    assert result.disk_names == dt.dof_names and result.speeds.shape[0] == 5
    np.testing.assert_allclose(result.speed("motor")[-1], 20.0 + alpha * 0.01, rtol=1e-7)
    # the gear b alone is driven by the mesh: F r_b = J_b α_b
    np.testing.assert_allclose(result.mesh_force("m"), 0.004 * alpha * RA / RB / RB, rtol=1e-6)


def test_a_reversed_load_starts_on_the_back_flanks():
    """A torque that drives the gear backwards loads the back flanks: the static start puts the mesh
    across its backlash, in back-side contact, and it stays there."""
    gap = 3e-5
    system = GearSystem.from_drivetrain(_pair(c=60.0), backlash={"m": gap})
    inputs = [ConstantTorque("a", -1.0), ConstantTorque("b", -2.0)]
    result = simulate(system, 0.002, inputs=inputs, initial_speed=100.0, atol=1e-14)
    assert result.contact_losses == ()
    assert np.all(result.contact_modes == 2)
    np.testing.assert_allclose(result.mesh_forces[0], -50.0, rtol=1e-6)
    np.testing.assert_allclose(result.dte[0], -gap - 50.0 / 1e8, rtol=1e-6)


def test_a_step_torque_on_a_clamped_disk():
    """θ = T/k (1 − cos ω_n (t − t_s)) after a step at t_s (the step a breakpoint: no step straddles it)."""
    k, J, T, ts = 100.0, 0.01, 1.0, 0.5
    dt = Drivetrain([Disk("a", J)], [GroundSpring("clamp", "a", k)])
    system = GearSystem.from_drivetrain(dt)
    kw = {"start": "rest", "rtol": 1e-10, "atol": 1e-14, "output_step": 0.01}
    result = simulate(system, 1.0, inputs=[StepTorque("a", T, ts)], **kw)
    wn = math.sqrt(k / J)
    expected = np.where(result.time < ts, 0.0, T / k * (1 - np.cos(wn * (result.time - ts))))
    np.testing.assert_allclose(result.angles[0], expected, atol=1e-8 * T / k)
    assert result.element_torques["clamp"] == pytest.approx(k * result.angles[0])
