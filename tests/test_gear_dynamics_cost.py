"""A speed sweep's and a simulation's cost estimated before the work: absurd runs refused naming the
field and the fix, long ones warned on at once, bad durations and output steps named before the model
is built."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from mechdyn.cli.main import main
from mechdyn.errors import LongRunWarning, ModelError
from mechdyn.gear_dynamics import _cost
from mechdyn.gear_dynamics._cost import simulation_cost, sweep_cost
from mechdyn.gear_dynamics.floquet import period_plan
from mechdyn.gear_dynamics.simulate import simulate
from mechdyn.gear_dynamics.steady import _model, speed_sweep
from mechdyn.gear_dynamics.sweep import _check_sweep_cost

TURRET = Path(__file__).resolve().parents[1] / "examples" / "turret_milling_startup.toml"
RPM = 2 * math.pi / 60


@pytest.fixture
def turret(turret_startup):
    _, system, motor = turret_startup
    return system, motor


def test_a_sweep_from_a_crawl_is_refused_with_the_speed_where_the_harmonics_suffice(turret):
    system, motor = turret
    with pytest.raises(
        ModelError, match=r"'speed_range'.*10 rpm.*8\d\d\d harmonics.*start the range at 8\d\.\d+ rpm"
    ):
        speed_sweep(system, np.array([10.0, 4500.0]) * RPM, reference="1", load={"7": 6.2}, motor=motor)


def test_the_counts_of_a_huge_sweep_refuse_or_warn_before_any_work(turret):
    system, motor = turret
    lin = _model(system, "1", {"7": 6.2}, None, motor)
    plan = period_plan(lin)
    speeds = np.linspace(1200, 4500, 60) * RPM
    kw = {"solver_substeps": 4, "refine": 3}
    _check_sweep_cost(lin, plan, speeds, 74, None, True, True, **kw)  # the shipped sweep: silent
    with pytest.warns(LongRunWarning, match="this run will take about .* h of CPU"):
        _check_sweep_cost(lin, plan, speeds, 2000, 2000, True, False, **kw)
    with pytest.raises(ModelError, match=r"field 'harmonics'.* beyond the memory"):
        _check_sweep_cost(lin, plan, speeds, 6000, 6000, True, False, **kw)
    with pytest.raises(ModelError, match=r"field 'points'.* beyond the time"):
        _check_sweep_cost(lin, plan, np.linspace(1200, 4500, 10**6) * RPM, 74, None, True, True, **kw)


def test_the_estimates_count_what_the_docs_say():
    """A dense LU of N = J (2H + 1) complex unknowns: (8/3) N³ operations and 16 N² bytes."""
    c = sweep_cost(10, 2, 100, 1, 14, 0, False, False)
    N = 2 * 201
    assert c.seconds == pytest.approx(10 * 8 / 3 * N**3 / _cost.FLOPS)
    assert c.bytes == pytest.approx(16 * N**2)
    s = simulation_cost(2.0, 1000.0, 8, 10, 2, None)
    assert s.seconds == pytest.approx(2000 * _cost.SECONDS_PER_CYCLE)
    assert s.bytes == pytest.approx(2000 * 8 * (2 * 10 + 4) * 8)


def test_a_backlash_sweep_is_estimated_at_the_cost_the_docs_state():
    """With backlash, BACKLASH_SECONDS a speed (the docs' "at most 1 s a speed", the continuation
    included: 0.10 s measured on a single pair, 0.71 s on turret C): the shipped turret's 110 speeds
    are not announced as a long run (8 s a speed, the old figure, announced 15 min for a 78 s run)."""
    assert _cost.BACKLASH_SECONDS == 1.0
    c = sweep_cost(110, 2, 74, 1, 14, 0, False, True)
    assert c.seconds == pytest.approx(110 * _cost.BACKLASH_SECONDS, rel=0.05)
    assert c.seconds < _cost.TIME_WARN


def test_a_simulation_of_a_day_is_refused_before_the_work(turret):
    system, motor = turret
    with pytest.raises(ModelError, match=r"field 'output_step'.*mesh cycles.*give a shorter duration"):
        simulate(system, 86400.0, inputs=[motor], output_step=1e-5)
    with pytest.raises(ModelError, match=r"output_step 1 s is longer than the duration"):
        simulate(system, 0.01, inputs=[motor], output_step=1.0)


@pytest.mark.parametrize(
    ("args", "said"),
    [
        (["--duration", "0.01 s", "--output-step", "1 s"], "--output-step: 1 s is longer than the duration"),
        (["--duration", "0 s"], "--duration: 0 s: give a positive time"),
    ],
)
def test_bad_times_are_named_by_the_option_that_gave_them(tmp_path, capsys, args, said):
    assert main(["simulate", str(TURRET), "--db", str(tmp_path / "r.db"), *args]) == 2
    assert said in capsys.readouterr().err


def test_a_long_run_is_announced_before_it_starts_and_said_once(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(_cost, "TIME_WARN", 0.0)
    assert main(["simulate", str(TURRET), "--db", str(tmp_path / "r.db"), "--duration", "5 ms"]) == 0
    err = capsys.readouterr().err
    assert err.count("this run will take about") == 1
