"""Tests that kill mutations which the rest of the suite let pass (issue 48, point 3).

Each test states the mutation it kills and how that was checked: the mutation was applied to the
source by hand, the test run and seen to fail, and the source restored byte for byte (the test then
passing again). Every expected value is computed here, independently of the code under test.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import mechdyn
from conftest import EXAMPLES
from mechdyn.drivetrain import Disk, Drivetrain, GearMesh
from mechdyn.gear_dynamics import GearSystem
from mechdyn.gear_dynamics.steady import speed_sweep, steady_state
from mechdyn.gears import GearPair, SpurGear
from mechdyn.mechanism import cycle, inverse_dynamics


# -- ISO 6336-1 K_v beside the computed dynamic factor ---------------------------------------------------
def _iso_kv_by_hand(load: float, J1: float, J2: float, ratios: np.ndarray) -> tuple[float, np.ndarray]:
    """n_E1 (min⁻¹) and K_v at the resonance ratios N of the standard 20/40-tooth, 3 mm, 30 mm wide
    steel spur pair (20°, no profile shift, solid blanks, grade 6, no tip relief, case-hardened) whose
    gear is loaded by ``load`` N·m, the pinion and gear inertias J1, J2 kg·m². ISO 6336-1:2006 Method
    B in the standard's own units (mm, µm, N, kg, min⁻¹), equation numbers of that edition."""
    m, b, z1, z2, alpha = 3.0, 30.0, 20, 40, math.radians(20.0)
    r1, r2 = m * z1 / 2, m * z2 / 2
    rb1, rb2 = r1 * math.cos(alpha), r2 * math.cos(alpha)
    ra1, ra2 = r1 + m, r2 + m
    # transverse contact ratio (spur: ε_γ = ε_α)
    eps = (math.sqrt(ra1**2 - rb1**2) + math.sqrt(ra2**2 - rb2**2) - (r1 + r2) * math.sin(alpha)) / (
        math.pi * m * math.cos(alpha)
    )
    # the mesh force along the line of action from the gear's load, the pinion torque T1 = F_bn r_b1
    # (the pinion's base radius), the tangential force at the pinion's reference circle
    f_bn = load / (rb2 / 1000.0)
    t1 = f_bn * rb1 / 1000.0
    w = t1 / (r1 / 1000.0) / b  # F_t K_A / b, N/mm, K_A = 1
    # clause 9: q′ = C1 + C2/z_n1 + C3/z_n2 (x = 0), c′ = c′_th C_M C_R C_B (load/100)^0.25 (w < 100)
    q = 0.04723 + 0.15551 / z1 + 0.25791 / z2
    c_b = (1 + 0.5 * (1.2 - 1.25)) * (1 - 0.02 * (20 - 20))
    c_p = 1 / q * 0.8 * 1.0 * c_b * ((w / 100) ** 0.25 if w < 100 else 1.0)
    c_ga = c_p * (0.75 * eps + 0.25)  # ε_α ≥ 1.2
    # (7): m_red = J1* J2* / (J1* r_b2² + J2* r_b1²), J* = J/b, kg·mm²/mm; (6): n_E1
    js1, js2 = J1 * 1e6 / b, J2 * 1e6 / b
    m_red = js1 * js2 / (js1 * rb2**2 + js2 * rb1**2)  # kg/mm
    n_e1 = 30000 / (math.pi * z1) * math.sqrt(c_ga / m_red)
    # ISO 1328-1:1995 grade 6 (× 2^((6 − 5)/2) of grade 5) at the larger gear (d = 120 mm), µm
    step, d = 2**0.5, 2 * r2
    f_pb = (0.3 * (m + 0.4 * math.sqrt(d)) + 4) * step * math.cos(alpha)
    f_fa = (2.5 * math.sqrt(m) + 0.17 * math.sqrt(d) + 0.5) * step
    y_p, y_f = min(0.075 * f_pb, 3.0), min(0.075 * f_fa, 3.0)  # running-in, case-hardened
    c_a = (1500 / 97 - 18.45) ** 2 / 18 + 1.5  # C_ay (18), σ_Hlim 1500 N/mm², µm
    bp, bf, bk = c_p * (f_pb - y_p) / w, c_p * (f_fa - y_f) / w, abs(1 - c_p * c_a / w)  # (15)–(17)
    # table 8, 1.5 < ε_γ ≤ 2
    cv = (0.32, 0.34, 0.23, 0.90, 0.47, 0.47, 0.125 * math.sin(math.pi * (eps - 2)) + 0.875)
    n_s = 0.5 + 0.35 * math.sqrt(w / 100) if w < 100 else 0.85  # (11), (12)
    main = cv[0] * bp + cv[1] * bf + cv[3] * bk + 1  # (20)
    sup = cv[4] * bp + cv[5] * bf + cv[6]  # (21)

    def kv(n: float) -> float:
        if n <= n_s:  # (13), (14)
            return n * (cv[0] * bp + cv[1] * bf + cv[2] * bk) + 1
        if n <= 1.15:
            return main
        if n >= 1.5:
            return sup
        return sup + (main - sup) * (1.5 - n) / 0.35  # (22)

    assert w < 100 and 0.5 < n_s < 0.85  # the light-load branches of c′ and N_S are the ones taken
    return n_e1, np.array([kv(n) for n in ratios])


def test_speed_sweep_iso_dynamic_factor_is_iso_6336_method_b_by_hand():
    """Kills: ISO 6336-1's K_v in :func:`speed_sweep` fed the gear's base radius instead of the
    pinion's (the pinion torque T₁ = F_bn r_b2 in ``_iso_factors``); the test beside it checked only
    that K_v is finite and at least 1.

    The sweep's ISO K_v of a 20/40-tooth pair at the pinion speeds of N = 0.3, 1.0, 1.3 and 2.0
    (subcritical, main resonance, intermediate, supercritical) equals ISO 6336-1:2006 Method B worked
    by hand from the gear data (:func:`_iso_kv_by_hand`), 1e-9 relative, and its resonance speed n_E1
    too. Checked: with ``pair.gear.base_radius`` for ``pair.pinion.base_radius`` in ``_iso_factors``
    the K_v are 12 % to 28 % off and the test fails; restored, it passes (agreement measured 2e-16)."""
    pair = GearPair(SpurGear(20, 0.003, 0.03, name="pinion"), SpurGear(40, 0.003, 0.03, name="gear"))
    J1, J2, load = 0.002, 0.01, 80.0
    ratios = np.array([0.3, 1.0, 1.3, 2.0])  # one in each range of K_v
    n_e1, hand = _iso_kv_by_hand(load, J1, J2, ratios)
    assert pair.contact_ratio == pytest.approx(1.6351859635714587, rel=1e-12)
    dt = Drivetrain(
        [Disk("pinion", J1), Disk("gear", J2)],
        [GearMesh.from_gear_pair("m", ("pinion", "gear"), pair, damping=1500.0, points=40)],
    )
    system = GearSystem.from_drivetrain(dt, mesh_profiles={"m": pair.mesh_cycle(40)})
    speeds = ratios * n_e1 * math.pi / 30  # rad/s of the pinion, the reference
    r = speed_sweep(
        system,
        speeds,
        reference="pinion",
        drive="speed",
        load={"gear": load},
        gear_pairs={"m": pair},
        refine=0,
        harmonics=4,
        stability=False,
    )
    np.testing.assert_allclose(r.speeds, speeds, rtol=1e-15)
    np.testing.assert_allclose(r.iso_dynamic_factor[:, 0], hand, rtol=1e-9)
    assert r.iso_resonance_speed[0] == pytest.approx(n_e1 * math.pi / 30, rel=1e-9)


# -- the back flanks in the periodic steady state --------------------------------------------------------
RA, RB, ZA = 0.0188, 0.047, 20
K_MESH, C_MESH, BACKLASH, J_GEAR, LOAD = 3e8, 8000.0, 2e-6, 0.03, 20.0


def _event(fn, sense):
    """A terminal event of solve_ivp: ``fn`` crossing zero in the sense ``sense`` only."""

    def event(t, yy):
        return fn(t, yy)

    event.direction, event.terminal = sense, True
    return event


def _one_period(err: np.ndarray, T: float, y: np.ndarray, t_out: np.ndarray) -> tuple[np.ndarray, ...]:
    """One period of the pinion-held pair written out here: the gear's deflection along the line of
    action δ obeys δ̈ = (r_b²/J)(F_s − f), F_s = T_load/r_b, with f = k u + c u̇ on the drive flanks
    (u = δ − e > 0), k (u + b) + c u̇ on the back flanks (u < −b) and 0 in the backlash, e(t) the
    periodic linear interpolant of ``err`` over T. Integrated (DOP853, rtol 1e-12) piece by piece
    between the error's corners, each contact change located as a direction-aware terminal event.
    Returns the state after T and δ and f at the times ``t_out`` (ascending, in [0, T))."""
    P, a, fs, b = err.size, RB**2 / J_GEAR, LOAD / RB, BACKLASH

    def force(u, du, mode):
        return {0: K_MESH * u + C_MESH * du, 1: 0.0 * u, 2: K_MESH * (u + b) + C_MESH * du}[mode]

    delta, f = np.full(t_out.size, np.nan), np.full(t_out.size, np.nan)
    u0 = y[0] - err[0]
    mode = 0 if u0 > 0 else (2 if u0 < -b else 1)
    for i in range(P):
        t_start, t_end = i * T / P, (i + 1) * T / P
        e0, de = err[i], (err[(i + 1) % P] - err[i]) * P / T
        t0 = t_start
        while True:

            def e(t, e0=e0, de=de, t_start=t_start):
                return e0 + de * (t - t_start)

            def rhs(t, yy, e=e, de=de, mode=mode):
                return [yy[1], a * (fs - force(yy[0] - e(t), yy[1] - de, mode))]

            def drive_edge(t, yy, e=e):
                return yy[0] - e(t)

            def back_edge(t, yy, e=e):
                return yy[0] - e(t) + b

            # the ways out of each mode: drive → gap falling through 0, back → gap rising through −b,
            # gap → drive rising through 0, gap → back falling through −b
            exits = {
                0: [(drive_edge, -1, 1)],
                2: [(back_edge, 1, 1)],
                1: [(drive_edge, 1, 0), (back_edge, -1, 2)],
            }
            events = [_event(fn, sense) for fn, sense, _ in exits[mode]]
            sol = solve_ivp(
                rhs, (t0, t_end), y, method="DOP853", rtol=1e-12, atol=1e-20, dense_output=True, events=events
            )
            hit = [k for k, te in enumerate(sol.t_events) if te.size]
            reached = sol.t[-1]
            mask = (t_out >= t0) & (t_out < (reached if hit else t_end))
            if mask.any():
                yy = sol.sol(t_out[mask])
                delta[mask] = yy[0]
                f[mask] = force(yy[0] - e(t_out[mask]), yy[1] - de, mode)
            y = sol.y[:, -1]
            if not hit:
                break
            mode, t0 = exits[mode][hit[0]][2], reached
    return y, delta, f


def test_steady_state_back_flank_forces_are_an_independent_integration():
    """Kills: the back-flank force with its sign flipped in the steady-state path (no steady-state
    test reached the back flanks): in ``steady._mesh_forces`` (the forces reported) or in
    ``_nonsmooth.NonsmoothFlow.field`` (the flow Newton's method shoots on).

    A pinion-held pair with 2 µm backlash, an error of 2 µm at 0.9 of the gear's resonance and a light
    load: the teeth leave the drive flanks and strike the back flanks every mesh cycle (the force
    reaches −2.9 kN beside +3.8 kN). Its periodic steady state (shooting with Newton on the backlash
    flow) is compared with a one-degree-of-freedom integration written in the test
    (:func:`_one_period`), settled from the static deflection over 40 periods (its deflection and
    speed then close on themselves over the next one to 1e-6, measured 5e-8): the deflections agree
    to 1e-6 of their swing, and so do the forces except at the error's corners, where the damping
    force jumps with ė and either side is right (measured 5e-8).
    Checked: with ``-(x_rel + b)`` for ``x_rel + b`` in ``_mesh_forces`` the back-flank forces
    change sign and the test fails; with ``-(xr + gap)`` in ``NonsmoothFlow.field`` Newton's
    method no longer converges (a back flank that pulls has no such orbit) and it fails; restored, it
    passes."""
    P = 24
    wn = math.sqrt(K_MESH * RB**2 / J_GEAR)
    speed = 0.9 * wn / ZA
    dt = Drivetrain(
        [Disk("pinion", 0.05), Disk("gear", J_GEAR)],
        [
            GearMesh(
                "m", ("pinion", "gear"), teeth=(ZA, 50), base_radii=(RA, RB), stiffness=K_MESH, damping=C_MESH
            )
        ],
    )
    system = GearSystem.from_drivetrain(
        dt, errors={"m": {"amplitude": 2e-6, "samples": P}}, backlash={"m": BACKLASH}
    )
    s = steady_state(system, speed, reference="pinion", drive="speed", load={"gear": LOAD}, method="shooting")
    assert s.converged
    T, t = s.period, s.time
    assert T == pytest.approx(2 * math.pi / (ZA * speed), rel=1e-12)
    err = np.asarray(system.meshes[0].error, float)
    y = np.array([LOAD / RB / K_MESH + err[0], 0.0])  # the static deflection
    for _ in range(40):
        y = _one_period(err, T, y, t[:0])[0]
    end, delta, f = _one_period(err, T, y, t)
    assert (np.abs(end - y) <= 1e-6 * np.abs(y)).all()  # settled on the periodic orbit
    e = np.interp(t / T, np.arange(P + 1) / P, np.append(err, err[0]))
    back = delta - e < -BACKLASH
    assert back.sum() > 50 and f.min() < -0.5 * f.max()  # long on the back flanks, pushed hard there
    np.testing.assert_allclose(s.deflection[:, 0], delta, rtol=0, atol=1e-6 * np.ptp(delta))
    corner = np.isclose((np.arange(t.size) * P / t.size) % 1, 0)
    swing = np.ptp(f)
    np.testing.assert_allclose(s.mesh_force[~corner, 0], f[~corner], rtol=0, atol=1e-6 * swing)
    assert s.mesh_force[:, 0].min() < -0.5 * s.mesh_force[:, 0].max()


# -- the shaking moment about a point --------------------------------------------------------------------
def test_batch_shaking_moment_about_a_point_is_the_transfer_of_moments():
    """Kills: ``CycleBatch.shaking_moment(about=P)`` with the sign of its P × F term flipped (the
    batch's moment was only ever asked about the origin); and the same flip in
    ``DynamicsResult.shaking_moment``.

    Press A (examples/press_link_drive.toml) and a variant with its pivot D moved: for each, the
    batch's moment about P = (0.8, −1.5) m equals the single design's (:func:`inverse_dynamics`) and
    M_P = M_O − (P × F) = M_O − (p_x F_y − p_y F_x) worked here from that design's shaking force F
    and its moment about the origin M_O, to 1e-9 of the largest moment (round-off); the transfer
    term is larger than M_P itself, so a flipped sign is far off. Checked: with ``+`` for ``-`` before
    ``(px * F.imag - py * F.real)`` in ``CycleBatch.shaking_moment`` the test fails, and so it does
    with the flip in ``DynamicsResult.shaking_moment``; restored, it passes."""
    press = mechdyn.load(EXAMPLES / "press_link_drive.toml").model
    D = np.asarray(press.points["D"], float)
    moved = D + np.array([0.03, -0.02])
    batch = cycle(press, 72, points={"D": np.array([D, moved])})
    assert batch.assembled.all()
    px, py = 0.8, -1.5
    about_p = batch.shaking_moment(about=(px, py))
    assert about_p.shape == batch.angle.shape
    for v, design in enumerate((press, replace(press, points={**press.points, "D": tuple(moved)}))):
        d = inverse_dynamics(design, 72)
        order = np.argsort(batch.angle[v])  # the single design's arrays are ordered by angle
        np.testing.assert_allclose(batch.angle[v][order], d.angle, atol=1e-9)
        F, M_O = d.shaking_force, d.shaking_moment()
        transfer = px * F[:, 1] - py * F[:, 0]  # P × F
        hand = M_O - transfer
        scale = np.abs(hand).max()
        assert np.abs(transfer).max() > 0.5 * scale  # the transfer term matters
        np.testing.assert_allclose(d.shaking_moment(about=(px, py)), hand, rtol=0, atol=1e-9 * scale)
        np.testing.assert_allclose(about_p[v][order], hand, rtol=0, atol=1e-9 * scale)
