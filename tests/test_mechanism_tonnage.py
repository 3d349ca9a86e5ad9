"""Tonnage and energy of a press (mechdyn.mechanism.tonnage) against the in-line slider-crank's closed
form: F = T_r / |ds/dθ| with ds/dθ = r sin θ (1 + r cos θ / √(l² − r² sin² θ))."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

import mechdyn
from mechdyn.errors import MechdynError
from mechdyn.mechanism.dynamics import inverse_dynamics
from mechdyn.mechanism.model import Body, Driver, Mechanism, Prismatic, ProcessForce, Revolute
from mechdyn.mechanism.tonnage import (
    CURVE_CUTOFF_BEFORE_BDC,
    slider_crank_velocity_ratio,
    stroke_energy,
    tonnage_capacity,
)

R, L, W = 0.1, 0.4, 10.0  # crank and rod, m; crank speed, rad/s
T_R, F_R = 2.0e4, 5.0e5  # rated torque N·m, rated force N


def slider_crank(process_forces=()) -> Mechanism:
    """Crank at the origin, slider on +x; the guide's axis (0°) points up: BDC is x = l − r."""
    return Mechanism(
        points={"O": (0.0, 0.0), "A": (R, 0.0), "B": (R + L, 0.0)},
        bodies=(
            Body("crank", ("O", "A"), 2.0, 0.002),
            Body("rod", ("A", "B"), 3.0, 0.04),
            Body("slider", ("B",), 5.0, 0.0),
        ),
        joints=(
            Revolute("O", ("ground", "crank"), "O"),
            Revolute("A", ("crank", "rod"), "A"),
            Revolute("B", ("rod", "slider"), "B"),
            Prismatic("guide", ("slider", "ground"), "B", 0.0),
        ),
        driver=Driver("crank", "O", "A", W),
        process_forces=tuple(process_forces),
        angle_datum="bdc",
    )


def distance_before_bdc(theta_from_tdc):
    """x − (l − r), m, θ from top dead centre."""
    return R * np.cos(theta_from_tdc) + np.sqrt(L**2 - (R * np.sin(theta_from_tdc)) ** 2) - (L - R)


def forming(force: float, before_bdc: float) -> ProcessForce:
    """A constant force pushing the slider up over the last ``before_bdc`` of the working stroke."""

    def f(theta, position):
        down = np.sin(theta) < 0  # from BDC, counter-clockwise: the working stroke is 180°..360°
        on = down & (position + 2 * R <= before_bdc)  # the position is from the drawing's TDC
        return np.where(on, force, 0.0), np.zeros_like(theta)

    return ProcessForce("slider", "B", f)


@pytest.fixture(scope="module")
def rated():
    return inverse_dynamics(slider_crank(), 720).with_rating(T_R, F_R)


def test_the_velocity_ratio_and_the_curve_match_the_closed_form(rated):
    frame = rated.to_frame()
    theta_tdc = rated.angle + math.pi  # datum at BDC, θ = π there from TDC
    g = slider_crank_velocity_ratio(theta_tdc, R, L)
    v = frame["output_velocity_m_per_s"].to_numpy()
    np.testing.assert_allclose(v / rated.crank_speed, g, atol=1e-12)
    curve = frame["tonnage_capacity_N"].to_numpy()
    working = np.isfinite(curve)
    assert working.any()
    np.testing.assert_allclose(curve[working], T_R / np.abs(g[working]), rtol=1e-9)
    d = frame["distance_before_bdc_m"].to_numpy()
    np.testing.assert_allclose(d, distance_before_bdc(theta_tdc), atol=1e-12)
    # the curve is drawn on the working stroke only (the slide going down) and stops 1 mm before BDC
    assert np.all(v[working] < 0) and d[working].min() >= CURVE_CUTOFF_BEFORE_BDC
    assert rated.summary()["tonnage_capacity_min_N"] == pytest.approx(
        T_R / np.abs(slider_crank_velocity_ratio(np.linspace(0, math.pi, 20001), R, L)).max(), rel=1e-4
    )


def test_capacity_is_infinite_at_the_dead_centres():
    assert np.isinf(tonnage_capacity(1.0, [0.0]))[0]
    assert tonnage_capacity(3.0, [-0.5])[0] == pytest.approx(6.0)


def test_the_rated_point_against_a_hand_computation(rated):
    # where T_R / |ds/dθ| = F_R on the way down (θ from TDC in (π/2, π))
    theta = brentq(lambda t: abs(slider_crank_velocity_ratio(t, R, L)) - T_R / F_R, math.pi / 2, math.pi)
    s = rated.summary()
    assert s["rated_point_before_bdc_m"] == pytest.approx(float(distance_before_bdc(theta)), rel=1e-5)
    assert s["rated_point_before_bdc_deg"] == pytest.approx(math.degrees(math.pi - theta), rel=1e-5)
    assert s["tonnage_at_rated_point_N"] == pytest.approx(F_R, rel=1e-9)
    # the rated torque's work from there to BDC is ∫F ds = T_r Δθ
    assert s["rated_energy_below_rated_point_J"] == pytest.approx(T_R * (math.pi - theta), rel=1e-5)


def test_without_a_process_force_there_is_nothing_to_check(rated):
    s = rated.summary()
    assert s["process_energy_per_stroke_J"] == 0.0
    assert "process_force_to_capacity_max_ratio" not in s
    assert s["tonnage_verdict"].startswith("no process force")


def test_a_constant_process_force_over_a_known_travel_takes_f_times_d():
    F, d = 2.0e5, 0.02
    result = inverse_dynamics(slider_crank([forming(F, d)]), 3600).with_rating(T_R, F_R)
    s = result.summary()
    # sampled at 0.1°: the force switches on between samples; the travel between them bounds the error
    assert s["process_energy_per_stroke_J"] == pytest.approx(F * d, rel=5e-3)
    assert stroke_energy(np.full(8, 2.0)) == pytest.approx(4 * math.pi)
    assert s["process_force_to_capacity_max_ratio"] < 1
    assert s["tonnage_verdict"].startswith("within capacity")
    # its ratio to the available force, F |ds/dθ| / T_r, is largest where the force starts, d before BDC
    assert s["process_force_to_capacity_max_before_bdc_m"] == pytest.approx(d, abs=2e-4)
    on_slide = result.to_frame()["process_force_on_slide_N"].to_numpy()
    assert np.nanmax(on_slide) == pytest.approx(F, rel=1e-9)


def test_a_process_force_above_the_curve_is_reported_with_where():
    F, d = 8.0e5, 0.03  # above the rated 0.5 MN, which is available only from a few mm before BDC
    s = inverse_dynamics(slider_crank([forming(F, d)]), 720).with_rating(T_R, F_R).summary()
    assert s["process_force_to_capacity_max_ratio"] > 1
    assert s["tonnage_verdict"].startswith("exceeds capacity from")
    assert "mm before BDC" in s["tonnage_verdict"]


def test_without_a_rating_the_summary_is_unchanged():
    s = inverse_dynamics(slider_crank(), 72).summary()
    assert not any("tonnage" in k or "rated" in k for k in s)
    assert "tonnage_capacity_N" not in inverse_dynamics(slider_crank(), 72).to_frame()


@pytest.mark.parametrize(("torque", "force"), [("-5 kN*m", None), ("5 kN", None), ("5 kN*m", "0 N")])
def test_a_bad_rating_is_refused_clearly(torque, force):
    with pytest.raises(MechdynError, match="rated_"):
        inverse_dynamics(slider_crank(), 36).with_rating(torque, force)


MODEL = """
[model]
type = "mechanism"
[points]
O = ["0 mm", "0 mm"]
A = ["100 mm", "0 mm"]
B = ["500 mm", "0 mm"]
[[bodies]]
name = "crank"
points = ["O", "A"]
mass = "2 kg"
[[bodies]]
name = "rod"
points = ["A", "B"]
mass = "3 kg"
[[bodies]]
name = "slider"
points = ["B"]
mass = "5 kg"
[[joints]]
name = "O"
type = "revolute"
bodies = ["ground", "crank"]
point = "O"
[[joints]]
name = "A"
type = "revolute"
bodies = ["crank", "rod"]
point = "A"
[[joints]]
name = "B"
type = "revolute"
bodies = ["rod", "slider"]
point = "B"
[[joints]]
name = "guide"
type = "prismatic"
bodies = ["slider", "ground"]
point = "B"
axis = "0 deg"
[driver]
body = "crank"
pivot = "O"
tip = "A"
speed = "10 rad/s"
[settings]
angle_datum = "bdc"
n_angles = 360
"""


def test_the_file_fields_carry_their_units(tmp_path):
    path = tmp_path / "press.toml"
    path.write_text(MODEL + 'rated_torque = "20 kN*m"\nrated_force = "0.5 MN"\n')
    spec = mechdyn.load(path).settings
    assert spec.rated_torque == pytest.approx(T_R) and spec.rated_force == pytest.approx(F_R)


@pytest.mark.parametrize(
    ("lines", "says"),
    [
        ('rated_torque = "20 kN"\n', "rated_torque"),
        ('rated_torque = "-20 kN*m"\n', "rated_torque"),
        ('rated_force = "0.5 MN"\n', "rated_force needs rated_torque"),
    ],
)
def test_a_bad_file_value_gives_a_clear_error(tmp_path, lines, says):
    path = tmp_path / "press.toml"
    path.write_text(MODEL + lines)
    with pytest.raises(MechdynError, match=says):
        mechdyn.load(path)


def test_the_tonnage_plot_and_table_are_written(rated, tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    plots = rated.plots()
    assert "tonnage.png" in plots
    ax = plots["tonnage.png"]()
    out = tmp_path / "tonnage.png"
    ax.figure.savefig(out)
    plt.close(ax.figure)
    assert out.stat().st_size > 0
    assert ax.get_xscale() == "log"
    shown = [t.get_text() for t in ax.get_xticklabels() if t.get_text()]
    assert shown and set(shown) <= {"0.1", "1", "10", "100", "1000", "10000"}  # millimetres, not 10⁰…
    table = next(t for t in rated.tables() if "tonnage" in t.title)
    assert table.rows and "No process force" in table.note
