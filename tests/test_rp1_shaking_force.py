"""RP-1's shaking force against the published 68 N (forward, x) and 62 N (vertical, y) at 300 rpm
(SPEC §6), checked independently of the engine's Newton–Euler solve: the shaking force is −Σ m a_G,
with every centre of mass's acceleration obtained here by differentiating its position over one
period (spectrally; the carrier turns at constant speed).

| 300 rpm | d | x range | y range | how |
|---|---|---|---|---|
| the example's choice | 20 mm | 21.1 N | 22.3 N | engine = −Σ m a_G to 1e-6 |
| the largest d the published planet inertia allows, √(I_o/m) | 32.0 mm | 33.8 N | 35.6 N | engine |
| published | — | 68 N | 62 N | — |
| the planet's rate relative to the arm for its absolute rate | 29.1 (x) / 26.1 (y) mm | 68 N | 62 N | here |

So no d the published inertia allows reaches the published ranges. With the centripetal acceleration
of the planet's centre of mass about its pivot taken with the planet's rate relative to the carrier
instead of its absolute rate, each published range is met by some admissible d, but not both by one
(x/y is 0.983 for every d against the published 1.097: tests/test_rp1_claims.py). The example keeps
d = 20 mm.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from mechdyn.errors import ModelError
from mechdyn.mechanism import inverse_dynamics
from mechdyn.mechanism.planter import PlanterDesign, planter

RPM300 = 300 * 2 * math.pi / 60


def _cycle(d: float):
    design = dataclasses.replace(PlanterDesign(), speed=RPM300, com_offset=d)
    return inverse_dynamics(planter(design), 180)


def _second_derivative(x: np.ndarray, period: float) -> np.ndarray:
    n = x.size
    w = np.fft.fftfreq(n, d=period / n) * 2 * math.pi
    return np.real(np.fft.ifft(-(w**2) * np.fft.fft(x)))


def _shaking_force(result, relative_rate: bool = False) -> np.ndarray:
    """−Σ m a_G from the centres of mass (the body coordinates are their positions); with
    ``relative_rate`` the planets' centripetal term about their pivots uses the rate relative to the arm."""
    k, m = result.kinematics, result.mechanism
    order = np.argsort(k.time)
    q, qd, qdd = k.q[order], k.qd[order], k.qdd[order]
    period = 2 * math.pi / abs(m.driver.speed)  # the carrier turns at constant speed
    names = [b.name for b in m.bodies]
    arm = names.index("arm")
    force = np.zeros((q.shape[0], 2))
    for i, b in enumerate(m.bodies):
        g = q[:, 3 * i : 3 * i + 2]
        if relative_rate and b.name.startswith("planet"):
            pivot = k.point(b.name, "P" + b.name[-1])[0][order]
            r = g - pivot
            a_pivot = np.column_stack([_second_derivative(pivot[:, j], period) for j in range(2)])
            rate = qd[:, 3 * i + 2] - qd[:, 3 * arm + 2]
            a = (
                a_pivot
                + qdd[:, 3 * i + 2, None] * np.column_stack([-r[:, 1], r[:, 0]])
                - rate[:, None] ** 2 * r
            )
        else:
            a = np.column_stack([_second_derivative(g[:, j], period) for j in range(2)])
        force -= b.mass * a
    return force


def _ranges(force: np.ndarray) -> tuple[float, float]:
    return float(np.ptp(force[:, 0])), float(np.ptp(force[:, 1]))


@pytest.fixture(scope="module")
def at_20_mm():
    return _cycle(0.020)


def test_the_engine_shaking_force_is_minus_the_sum_of_m_a(at_20_mm):
    order = np.argsort(at_20_mm.kinematics.time)
    engine = at_20_mm.shaking_force[order]
    here = _shaking_force(at_20_mm)
    scale = np.abs(engine).max()
    # to the accuracy of a spectral second derivative at 180 angles
    np.testing.assert_allclose(engine - engine.mean(axis=0), here - here.mean(axis=0), atol=1e-6 * scale)
    x, y = _ranges(here)
    assert x == pytest.approx(21.09, abs=0.01) and y == pytest.approx(22.26, abs=0.01)


def test_the_largest_offset_the_published_inertia_allows_stays_below_the_published_ranges():
    d = PlanterDesign()
    d_max = math.sqrt(d.planet_inertia / d.planet_mass)  # I_o = I_G + m d² ≥ m d²
    assert d_max == pytest.approx(0.0320, abs=1e-4)
    x, y = _ranges(_shaking_force(_cycle(d_max * (1 - 1e-9))))
    assert x == pytest.approx(33.76, abs=0.02) and y == pytest.approx(35.64, abs=0.02)
    assert x < 68 and y < 62
    with pytest.raises(ModelError, match="com_offset"):
        _cycle(1.01 * d_max)


def test_the_published_ranges_follow_from_the_planets_rate_relative_to_the_arm(at_20_mm):
    # the planets' offset term is linear in d and the rest cancels between the two sides: scale
    x20, y20 = _ranges(_shaking_force(at_20_mm, relative_rate=True))
    d_x, d_y = 0.020 * 68 / x20, 0.020 * 62 / y20
    assert d_x == pytest.approx(0.0291, abs=3e-4) and d_y == pytest.approx(0.0261, abs=3e-4)
    x, _ = _ranges(_shaking_force(_cycle(d_x), relative_rate=True))
    assert x == pytest.approx(68.0, rel=1e-6)
