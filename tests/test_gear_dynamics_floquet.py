"""Floquet stability of geared drivetrains: the single mesh as the Mathieu equation against its closed-form
transition curves (Nayfeh & Mook, *Nonlinear Oscillations*, 1979, §5.3), damping exactly, the two
monodromy integrators, the rigid-body removal, brute-force growth rates, the chart, and bad input."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from mechdyn.drivetrain import Disk, Drivetrain, GearMesh
from mechdyn.errors import ModelError
from mechdyn.gear_dynamics import GearSystem
from mechdyn.gear_dynamics.floquet import floquet, monodromy, stability_chart

RA, RB, ZA, K, JB = 0.0188, 0.047, 20, 3e8, 0.03
WN = np.sqrt(K * RB**2 / JB)  # the gear's natural frequency with the pinion held, rad/s


def _pair(
    eps: float,
    *,
    c_mesh: float = 0.0,
    P: int = 2048,
    k: float = K,
    J_pinion: float = 0.05,
    J_gear: float = JB,
):
    dt = Drivetrain(
        [Disk("pinion", J_pinion), Disk("gear", J_gear)],
        [GearMesh("m", ("pinion", "gear"), teeth=(ZA, 50), base_radii=(RA, RB), stiffness=k, damping=c_mesh)],
    )
    profile = 1.0 + eps * np.cos(2 * np.pi * np.arange(P) / P)
    return GearSystem.from_drivetrain(dt, mesh_profiles={"m": profile})


def _speed(delta: float) -> float:
    """The pinion speed at which δ = (ω_n / ω_mesh)² of the gear's Mathieu equation, rad/s."""
    return WN / (ZA * np.sqrt(delta))


def _trace(system: GearSystem, delta: float) -> float:
    return abs(np.trace(monodromy(system, _speed(delta), reference="pinion", substeps=1))) - 2.0


def _boundaries(eps: float, center: float, width: float) -> tuple[float, float]:
    """The two δ around ``center`` where the undamped pair turns unstable (|tr Φ| = 2): a scan, then
    Brent's method on each sign change."""
    system = _pair(eps)
    grid = center + width * np.linspace(-1, 1, 41)
    f = np.array([_trace(system, d) for d in grid])
    changes = np.flatnonzero(np.sign(f[:-1]) != np.sign(f[1:]))
    assert changes.size == 2, f"expected one instability tongue, sign changes at {grid[changes]}"
    return tuple(  # type: ignore[return-value]
        brentq(lambda d: _trace(system, d), grid[i], grid[i + 1], xtol=1e-14, rtol=1e-13) for i in changes
    )


# -- (d) the Mathieu equation ----------------------------------------------------------------------------
@pytest.mark.parametrize("eps", [0.2, 0.4])
def test_principal_instability_matches_the_mathieu_transition_curves(eps):
    """Pinion held, no damping: J x'' + k̄ r_b² (1 + ε cos ω_m t) x = 0 is ẍ + (δ + ε_M cos s) x = 0 with
    s = ω_m t, δ = (ω_n/ω_m)², ε_M = δ ε. Its first tongue is bounded by δ = 1/4 ± ε_M/2 − ε_M²/8 ∓ ε_M³/32
    + O(ε_M⁴) (Nayfeh & Mook 1979, eq. 5.3.22; the ε⁴ term is ε_M⁴/384): the computed boundary points
    agree with the first-order curves to O(ε²), the second-order to O(ε³), the third-order to O(ε⁴)."""
    lo, hi = _boundaries(eps, 0.25, 0.25 * eps)
    for delta, sign in ((lo, -1.0), (hi, 1.0)):
        e = delta * eps
        first = 0.25 + sign * e / 2
        second = first - e**2 / 8
        third = second - sign * e**3 / 32
        assert abs(delta - first) == pytest.approx(e**2 / 8, rel=0.3)  # the error is the next term
        assert abs(delta - second) <= e**3 / 16
        assert abs(delta - third) <= e**4 / 100


def test_second_instability_matches_the_mathieu_transition_curves():
    """The second tongue, mesh frequency = ω_n: δ = 1 − ε_M²/12 and δ = 1 + 5 ε_M²/12 + O(ε_M⁴)
    (Nayfeh & Mook 1979, eqs. 5.3.23–24; the ε⁴ terms are 5ε⁴/3456 and −763ε⁴/13824, and the upper
    curve's higher terms are large: a third of ε⁴ at ε = 0.2)."""
    eps = 0.2  # ε_M ≈ 0.2 at δ ≈ 1
    lo, hi = _boundaries(eps, 1.0 + 0.1 * eps**2, 0.5 * eps**2)
    assert abs(lo - (1 - (lo * eps) ** 2 / 12)) <= (lo * eps) ** 4 / 100
    assert abs(hi - (1 + 5 * (hi * eps) ** 2 / 12)) <= (hi * eps) ** 4 / 2


def test_damping_scales_the_multipliers_exactly():
    """With mesh damping, x = e^(−μt) y turns J ẍ + c r_b² ẋ + k(t) r_b² x = 0 (μ = c r_b² / 2J) into the
    undamped equation of stiffness k(t) − μ² J / r_b²: the multipliers are e^(−μT) times the latter's
    (Nayfeh & Mook 1979, §5.3.4)."""
    eps, c = 0.3, 2000.0
    mu = c * RB**2 / (2 * JB)
    speed = 2 * WN / ZA
    T = 2 * np.pi / (ZA * speed)
    damped = np.linalg.eigvals(monodromy(_pair(eps, c_mesh=c, P=256), speed, reference="pinion"))
    k_shift = mu**2 * JB / RB**2
    shifted = Drivetrain(
        [Disk("pinion", 0.05), Disk("gear", JB)],
        [GearMesh("m", ("pinion", "gear"), teeth=(ZA, 50), base_radii=(RA, RB), stiffness=K - k_shift)],
    )
    profile = (K * (1 + eps * np.cos(2 * np.pi * np.arange(256) / 256)) - k_shift) / (K - k_shift)
    undamped = np.linalg.eigvals(
        monodromy(
            GearSystem.from_drivetrain(shifted, mesh_profiles={"m": profile}), speed, reference="pinion"
        )
    )
    np.testing.assert_allclose(
        np.sort_complex(damped), np.sort_complex(np.exp(-mu * T) * undamped), rtol=1e-9
    )


@pytest.mark.parametrize("speed_factor", [0.8, 2.0])
def test_magnus_product_and_solve_ivp_agree(speed_factor):
    system = _pair(0.25, c_mesh=500.0, P=64)
    speed = speed_factor * WN / ZA
    a = monodromy(system, speed, reference="pinion", method="magnus")
    b = monodromy(system, speed, reference="pinion", method="ivp")
    np.testing.assert_allclose(np.linalg.eigvals(a), np.linalg.eigvals(b), rtol=1e-8)


def test_free_boundary_removes_the_rigid_body_multipliers():
    """Neither disk held: the rigid rotation (multiplier 1, double) is projected out and the mesh mode
    remains, ω_n² = k̄ (r_a²/J_a + r_b²/J_b): the same multipliers as a held pinion with the gear's
    inertia r_b² / (r_a²/J_a + r_b²/J_b)."""
    Ja = 0.004
    free = _pair(0.2, c_mesh=300.0, P=128, J_pinion=Ja)
    J_equiv = RB**2 / (RA**2 / Ja + RB**2 / JB)
    held = _pair(0.2, c_mesh=300.0, P=128, J_gear=J_equiv)
    speed = 0.9 * np.sqrt(K * RB**2 / J_equiv) / ZA
    mu_free = floquet(free, [speed], reference="pinion", boundary="free").multipliers[0]
    mu_held = floquet(held, [speed], reference="pinion").multipliers[0]
    assert mu_free.size == 2  # 4 states less the rigid-body pair
    np.testing.assert_allclose(np.sort_complex(mu_free), np.sort_complex(mu_held), rtol=1e-9)


# -- (e) brute force -------------------------------------------------------------------------------------
def _growth(system: GearSystem, speed: float, c: float, periods: int) -> float:
    """Plain solve_ivp of the gear's free vibration J ẍ + c r_b² ẋ + k(τ) r_b² x = 0 (pinion held), from a
    small kick: the rate (1/s) at which the largest |x| of each period grows over the last half."""
    mesh = system.meshes[0]
    rate = ZA * speed / (2 * np.pi)
    T = 1 / rate

    def rhs(t, y):
        return [y[1], -(c * RB**2 * y[1] + mesh.stiffness(rate * t) * RB**2 * y[0]) / JB]

    P = mesh.samples
    y, peaks = [1e-6, 0.0], []
    for n in range(periods):
        top = 0.0
        for k in range(P):  # corner to corner of the profile
            a, b = n * T + k * T / P, n * T + (k + 1) * T / P
            sol = solve_ivp(rhs, (a, b), y, method="DOP853", rtol=1e-11, atol=1e-20, dense_output=True)
            top = max(top, np.abs(sol.sol(np.linspace(a, b, 5))[0]).max())
            y = sol.y[:, -1]
        peaks.append(top)
    half = periods // 2
    slope = np.polyfit(np.arange(half, periods) * T, np.log(peaks[half:]), 1)[0]
    return float(slope)


@pytest.mark.parametrize(
    ("eps", "c", "factor", "unstable"),
    [(0.3, 100.0, 2.0, True), (0.3, 12000.0, 2.0, False)],
)
def test_time_integration_grows_at_the_floquet_rate(eps, c, factor, unstable):
    """In the principal region (real multipliers): lightly damped the vibration grows, heavily damped it
    decays, each at ln ρ / T once the other multiplier's part has died out."""
    system = _pair(eps, c_mesh=c, P=32)
    speed = factor * WN / ZA
    result = floquet(system, [speed], reference="pinion")
    assert bool(result.unstable[0]) is unstable
    rate = _growth(system, speed, c, 40)
    assert rate == pytest.approx(result.growth_rate[0], rel=2e-3)


# -- the result and the chart ------------------------------------------------------------------------------
def test_floquet_over_speed_finds_the_principal_region():
    system = _pair(0.3, c_mesh=100.0, P=64)
    speeds = WN / ZA * np.linspace(1.6, 2.4, 41)
    r = floquet(system, speeds, reference="pinion")
    (lo, hi), *_ = r.unstable_ranges()
    assert lo < 2 * WN / ZA < hi
    s = r.summary()
    assert s["spectral_radius_max_ratio"] > 1 and s["unstable_ranges_rad_s"][0] == [lo, hi]
    assert s["natural_frequencies_hz"] == pytest.approx([WN / (2 * np.pi)])
    frame = r.to_frame()
    assert {"speed_rad_s", "spectral_radius_ratio", "unstable", "m_mesh_frequency_hz"} <= set(frame.columns)
    assert set(r.plots()) == {"floquet.png"} and len(r.tables()) == 2


def test_stability_chart_is_the_ince_strutt_chart_in_speed():
    system = _pair(0.0, c_mesh=100.0, P=64)  # constant stiffness: the chart takes a cosine
    speeds = WN / ZA * np.linspace(1.5, 2.5, 21)
    chart = stability_chart(system, speeds, [0.0, 0.1, 0.3], reference="pinion")
    assert not chart.unstable[0].any()  # no variation, no instability
    assert chart.unstable[2, 10] and chart.unstable[2].sum() > chart.unstable[1].sum()
    assert chart.critical_speeds(1) == pytest.approx([2 * WN / ZA])
    assert chart.summary()["mesh"] == "m" and len(chart.to_frame()) == 63
    assert set(chart.plots()) == {"stability_chart.png"}


# -- (f) bad input -------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("call", "field"),
    [
        (lambda s: floquet(s, [100.0], reference="pinion", method="rk4"), "method"),
        (lambda s: floquet(s, [100.0], reference="pinion", boundary="clamped"), "boundary"),
        (lambda s: floquet(s, [100.0], reference="nope"), "reference"),
        (lambda s: floquet(s, [0.0], reference="pinion"), "speeds"),
        (lambda s: floquet(s, [100.0], reference="pinion", substeps=0), "substeps"),
        (lambda s: monodromy(s, float("inf"), reference="pinion"), "speed"),
        (lambda s: stability_chart(s, [100.0], [1.0], reference="pinion"), "amplitudes"),
        (lambda s: stability_chart(s, [100.0], [0.1], reference="pinion", mesh="nope"), "mesh"),
    ],
)
def test_bad_input_names_the_field(call, field):
    with pytest.raises(ModelError) as err:
        call(_pair(0.1, P=16))
    assert err.value.field == field
