"""The press's whole load cycle: the capacity check between the samples, the forming energy converged
and exact for a piecewise-linear table, the forming force applied where it is given, and the reverse
load at break-through against an independent integration of the frame's spring-back."""

from __future__ import annotations

import math
import warnings
from dataclasses import replace

import numpy as np
import pytest

import mechdyn
from conftest import EXAMPLES
from mechdyn.mechanism import inverse_dynamics
from mechdyn.mechanism.kinematics import kinematics, output_position
from mechdyn.mechanism.model import ProcessForce, TabulatedForce
from mechdyn.mechanism.process import process_path
from mechdyn.mechanism.tonnage import Frame


@pytest.fixture(scope="module")
def tonnage():
    return mechdyn.load(EXAMPLES / "press_tonnage.toml")


def _summary(loaded, n, **rating):
    spec = loaded.settings
    r = inverse_dynamics(loaded.model, n)
    return r.with_rating(
        rating.get("torque", spec.rated_torque), spec.rated_force, rating.get("frame", spec.frame)
    ).summary()


def test_the_capacity_check_finds_the_peak_between_the_samples(tonnage):
    """The table's full load starts at 346.9°, between the 0.5° samples: the largest ratio of process to
    available force is there (0.83615), 0.66 % above the largest sampled ratio (0.83060); a grid of
    36 000 angles, which nearly lands on it, agrees to 2e-6."""
    s = _summary(tonnage, 720)
    fine = _summary(tonnage, 36000)
    assert s["crank_angle_at_process_force_to_capacity_max_deg"] == pytest.approx(346.9, abs=1e-6)
    assert s["process_force_to_capacity_max_ratio"] == pytest.approx(0.836150, rel=2e-6)
    assert fine["process_force_to_capacity_max_ratio"] == pytest.approx(
        s["process_force_to_capacity_max_ratio"], rel=2e-6
    )
    k = kinematics(tonnage.model, 720)
    sampled = process_path(k).torque(np.arange(720), np.zeros(720)).max() / tonnage.settings.rated_torque
    assert sampled == pytest.approx(0.8306, rel=1e-4)  # what the samples alone saw


def test_a_verdict_within_one_percent_of_the_limit_does_not_flip_with_the_grid(tonnage):
    """Rated so that the true peak is 0.3 % over the capacity: over, at every grid; the samples alone
    (0.3 % under at 720 angles) called it within."""
    exact = _summary(tonnage, 720)["process_force_to_capacity_max_ratio"] * tonnage.settings.rated_torque
    torque = exact / 1.003
    for n in (360, 720, 1000):
        s = _summary(tonnage, n, torque=torque)
        assert s["tonnage_verdict"].startswith("exceeds capacity"), (n, s["tonnage_verdict"])
        assert s["process_force_to_capacity_max_ratio"] == pytest.approx(1.003, rel=1e-5)


def test_the_forming_energy_converges_and_is_exact_for_a_table_against_position(tonnage):
    """Against the crank angle the energy per stroke agrees to 5e-9 on grids of 720 to 1777 angles
    (the samples' rule swung by 0.4 %); against the slide's position it is the table's own area, to
    round-off."""
    # any grid: the "bdc" datum is BDC itself, located between the samples (it was the lowest sample,
    # which moved a table against the angle by up to half a step from grid to grid)
    energies = [_summary(tonnage, n)["process_energy_per_stroke_J"] for n in (720, 1000, 1440, 1777)]
    assert max(energies) - min(energies) < 5e-9 * energies[0]
    # the same press with a table against the slide's position: ∫ F ds is the table's area
    m = tonnage.model
    k = kinematics(m, 720)
    s = output_position(m, k.q)
    bdc = float(s.min())
    rows = bdc + np.array([0.0, 0.004, 0.012, 0.02, 0.025])
    load = np.array([9e6, 9e6, 6e6, 2e6, 0.0])
    axis = m.output_joint().axis  # "up" along the slide's guide: against the slide going down
    force = TabulatedForce("position", rows, load, axis)
    # the force acts on the way up too (a table against position knows no stroke): it resists on the
    # way down and helps on the way up, so the cycle's net work is zero and the work down is the area
    pressed = replace(m, process_forces=(ProcessForce("slide", "F", force),))
    area = float(np.trapezoid(load, rows))
    for n in (360, 720, 1111):
        path = process_path(kinematics(pressed, n))
        w = path.interval_work()
        position = path.slide[0]
        top, bottom = int(np.argmax(position)), int(np.argmin(position))
        down = np.arange(top, bottom + (n if bottom < top else 0)) % n  # the intervals TDC → BDC
        # down to this grid's lowest sample, which lies a little above the true BDC where the table's
        # first row (9 MN) sits: short of the area by 9 MN times that height, exactly
        short = 9e6 * (position[bottom] - rows[0])
        assert w[down].sum() == pytest.approx(area - short, rel=1e-12)
        assert abs(w.sum()) < 1e-9 * area


def test_the_drive_takes_the_forming_energy_exactly_at_every_grid():
    """Press A driven: 10 MN over 25 mm before BDC, rising over the first 5 mm, is F (d − r/2) =
    225 kJ a stroke at any number of angles (the samples' rule gave 224.74 kJ at 720, −0.11 %)."""
    from mechdyn.drive import drive_analysis

    press = mechdyn.load(EXAMPLES / "press_driven.toml").model
    for n in (360, 720, 1000, 1777):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            s = drive_analysis(press, n, startup=False).summary()
        assert s["process_energy_per_stroke_J"] == pytest.approx(10e6 * (0.025 - 0.0025), rel=1e-8), n
        assert s["energy_balance_residual_relative"] < 1e-12


def test_the_forming_force_stops_at_bottom_dead_centre():
    """Placed on a mechanism, the forming force acts down to BDC and not past it (it acted half a step
    past); BDC is located between the samples."""
    from mechdyn.drive import FormingForce

    press = mechdyn.load(EXAMPLES / "press_link_drive.toml").model
    placed = FormingForce("10 MN", "25 mm", "5 mm").on(press, 720)
    f = placed.process_forces[-1].force
    bdc = f.tdc + f.direction * f.span
    h = 2 * math.pi / 720
    k = kinematics(press, 72000)
    s = output_position(press, k.q)
    i = int(np.argmin(s))
    # BDC to a thousandth of the 720-grid's step, found from that grid
    assert (bdc - float(k.angle[i]) + math.pi) % (2 * math.pi) - math.pi == pytest.approx(0.0, abs=1e-3 * h)
    low = f.bdc_position
    before = np.hypot(*f(np.array([bdc - 0.25 * h]), np.array([low])))
    after = np.hypot(*f(np.array([bdc + 0.25 * h]), np.array([low])))
    assert before[0] == pytest.approx(10e6)
    assert after[0] == 0.0


def _spring_back(F, t_d, m, k, zeta):
    """The press's force at its first reverse peak after the load falls from F to 0 over t_d, by an
    independent integration of m x″ + c x′ + k x = F(t) from rest at x = F/k (solve_ivp)."""
    from scipy.integrate import solve_ivp

    w = math.sqrt(k / m)
    c = 2 * zeta * m * w

    def load(t):
        return F * min(max(1 - t / t_d, 0.0), 1.0) if t_d > 0 else 0.0

    def rhs(t, y):
        return [y[1], (load(t) - c * y[1] - k * y[0]) / m]

    T = 2 * math.pi / w
    sol = solve_ivp(
        rhs,
        (0, t_d + T),
        [F / k, 0.0],
        method="DOP853",
        rtol=1e-11,
        atol=1e-14,
        max_step=T / 400,
        dense_output=True,
    )
    t = np.linspace(t_d, t_d + T, 400001)
    return -k * float(sol.sol(t)[0].min())


@pytest.mark.parametrize("zeta", [0.0, 0.05])
def test_the_reverse_load_at_break_through_against_an_integration_in_time(zeta):
    """The blanking example's break-through (8 MN falling over 0.23° of crank at 15 rpm, 2.6 ms, on a
    110 t slide and 5 MN/mm): the reverse load equals an independent integration of the slide on the
    frame's spring, to 1e-6 undamped and 1 % with 5 % damping; the frame releases F²/(2k) = 6.4 kJ."""
    loaded = mechdyn.load(EXAMPLES / "press_blanking.toml")
    frame = replace(loaded.settings.frame, damping_ratio=zeta)
    s = _summary(loaded, 720, frame=frame)
    assert s["breakthrough_force_N"] == pytest.approx(8e6, rel=1e-12)
    assert s["frame_energy_released_J"] == pytest.approx(8e6**2 / (2 * 5e9), rel=1e-12)
    assert s["breakthrough_before_bdc_m"] == pytest.approx(0.0105, abs=2e-5)
    t_d = math.radians(350.83 - 350.60) / (15 * 2 * math.pi / 60)
    assert s["breakthrough_release_time_s"] == pytest.approx(t_d, rel=1e-9)
    reference = _spring_back(8e6, t_d, 110191.0, 5e9, zeta)
    assert s["reverse_load_peak_N"] == pytest.approx(reference, rel=1e-6 if zeta == 0 else 1e-2)
    assert s["reverse_load_to_capacity_ratio"] == pytest.approx(s["reverse_load_peak_N"] / 1e6, rel=1e-12)
    assert s["reverse_load_verdict"].startswith("exceeds reverse capacity")


def test_a_slow_release_springs_back_less_and_a_forming_load_to_bdc_not_at_all(tonnage):
    """Breaking off over a whole frame period leaves no vibration (the ramp's residual is zero); the
    coining load of press_tonnage.toml, held to BDC, does not break off on the working stroke, but the
    same table ending 0.1° before BDC does (the force falls there, as the table says)."""
    loaded = mechdyn.load(EXAMPLES / "press_blanking.toml")
    frame = loaded.settings.frame
    m, k = 110191.0, frame.stiffness
    Tn = 2 * math.pi * math.sqrt(m / k)
    w = 15 * 2 * math.pi / 60
    end = 350.60 + math.degrees(Tn * w)
    table = TabulatedForce(
        "angle", np.radians([349.3, 350.15, 350.60, end]), np.array([0.0, 8e6, 8e6, 0.0]), math.pi
    )
    slow = replace(loaded.model, process_forces=(ProcessForce("slide", "F", table),))
    r = inverse_dynamics(slow, 720).with_rating(
        loaded.settings.rated_torque, loaded.settings.rated_force, frame
    )
    assert r.summary()["reverse_load_peak_N"] < 1e-6 * 8e6
    coin = _summary(tonnage, 720, frame=Frame("5 MN/mm"))
    assert "breakthrough_force_N" not in coin
    assert coin["reverse_load_verdict"].startswith("no tabulated process force breaks off")
    (pf,) = tonnage.model.process_forces
    short = replace(pf.force, x=np.append(pf.force.x[:-1], math.radians(359.9)))
    early = replace(tonnage.model, process_forces=(replace(pf, force=short),))
    r = inverse_dynamics(early, 720).with_rating(tonnage.settings.rated_torque, 10e6, Frame("5 MN/mm"))
    assert r.summary()["breakthrough_crank_angle_deg"] == pytest.approx(359.9)


def test_press_stiffness_without_a_rating_is_refused(tmp_path):
    text = (EXAMPLES / "press_blanking.toml").read_text()
    bad = text.replace('rated_torque = "2000 kN*m"\n', "").replace('rated_force = "10 MN"\n', "")
    path = tmp_path / "p.toml"
    path.write_text(bad)
    with pytest.raises(mechdyn.errors.ModelFileError, match=r"press_stiffness.*rated_torque"):
        mechdyn.load(path)


@pytest.mark.parametrize("floor", [0.0, 1e6])
def test_a_peak_between_two_low_samples_is_found(floor):
    """A table against the angle with a narrow 5 MN spike between two samples whose own values are low
    (or zero): the peak is the spike's, at its row, however low the samples on either side are (the
    search once looked only where a sample reached 90 % of the sampled peak)."""
    press = mechdyn.load(EXAMPLES / "press_link_drive.toml").model
    n = 360
    h = 2 * math.pi / n
    k = kinematics(press, n)
    i = n // 4 + 3  # mid-stroke, where the slide moves
    lo = float(k.angle[i])  # a sample interval [lo, lo + h] in the datum's angle
    spike = lo + 0.37 * h
    rows = np.array([spike - 0.2 * h, spike, spike + 0.2 * h])
    load = np.array([0.0, 5e6, 0.0])
    if floor:  # a broad, low force earlier in the stroke: the samples see it, not the spike
        rows = np.concatenate([[lo - 40 * h, lo - 5 * h, lo - 4 * h], rows])
        load = np.concatenate([[floor, floor, 0.0], load])
    down = press.output_joint().axis + math.pi  # the slide rises here: a force pushing it down resists
    force = TabulatedForce("angle", rows, load, down)
    pressed = replace(press, process_forces=(ProcessForce("slide", "F", force),))
    path = process_path(kinematics(pressed, n))
    sampled = path.torque(np.arange(n), np.zeros(n))
    top, at, u = path.peak(sampled)
    dense = np.linspace(0.0, 1.0, 20001)
    check = path.torque(np.full(dense.size, at), dense)
    assert top == pytest.approx(float(check.max()), rel=1e-6)
    assert top > 1.5 * max(float(sampled.max()), 0.0) + 1.0
    assert path.angle_at(at, u) == pytest.approx(spike, abs=1e-9)


def test_the_break_through_distance_counts_from_the_located_bdc():
    """The blanking example's break-through height above BDC at 360, 720 and 1111 angles against a grid
    of 72 000: within 1e-7 m at every grid (from the lowest sample it was 2.6e-6 m off at 1111)."""
    loaded = mechdyn.load(EXAMPLES / "press_blanking.toml")
    m = loaded.model
    fine = kinematics(m, 72000)
    s = output_position(m, fine.q)
    order = np.argsort(fine.angle)
    for n in (360, 720, 1111):
        out = _summary(loaded, n, frame=loaded.settings.frame)
        at = math.radians(out["breakthrough_crank_angle_deg"])
        height = np.interp(at, fine.angle[order], s[order], period=2 * math.pi) - float(s.min())
        assert out["breakthrough_before_bdc_m"] == pytest.approx(height, abs=1e-7), n
