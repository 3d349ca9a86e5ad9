"""Vibration verdicts of a machine on its supports (issue 29, part 4): the ISO 20816-3 zones, the VDI 2062
isolation efficiency against the single-DOF closed form, the band RMS of a sine, the separation of the
modes from the running speed's harmonics, the floor criteria, and the examples' verdicts in words."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from conftest import EXAMPLES
from mechdyn.cli.main import main
from mechdyn.errors import ModelError
from mechdyn.support import MountedMachine, PeriodicLoad
from mechdyn.support.assessment import vibration_verdicts
from mechdyn.support.verdicts import (
    VIBRATION_CRITERIA,
    band_rms,
    criterion_velocity,
    floor_criteria,
    foundation_class,
    harmonic_band_rms,
    iso_band,
    iso_zone,
    isolation_efficiency,
    mode_separation,
    third_octave_bands,
    transmissibility,
    zone_boundaries,
)

RPM = 2 * math.pi / 60  # rad/s per rpm

# ISO 20816-3:2022 Tables A.1 (group 1) and A.2 (group 2), mm/s RMS
TABLE = {
    (1, "rigid"): (2.3, 4.5, 7.1),
    (1, "flexible"): (3.5, 7.1, 11.0),
    (2, "rigid"): (1.4, 2.8, 4.5),
    (2, "flexible"): (2.3, 4.5, 7.1),
}


@pytest.mark.parametrize(("group", "foundation"), sorted(TABLE))
def test_the_zone_boundaries_of_each_group_and_foundation(group, foundation):
    bounds = TABLE[group, foundation]
    assert zone_boundaries(group, foundation) == pytest.approx([b / 1000 for b in bounds], rel=1e-12)
    assert iso_zone(0.0, group, foundation) == "A"
    for b, below, above in zip(bounds, "ABC", "BCD", strict=True):
        v = b / 1000
        assert iso_zone(v * (1 - 1e-6), group, foundation) == below
        assert iso_zone(v, group, foundation) == below  # a boundary is the largest value of its zone
        assert iso_zone(v * (1 + 1e-6), group, foundation) == above


@pytest.mark.parametrize(("group", "foundation"), [(3, "rigid"), (1, "soft")])
def test_an_unknown_group_or_foundation_is_refused(group, foundation):
    with pytest.raises(ModelError, match="groups 1 and 2"):
        zone_boundaries(group, foundation)


def test_the_band_and_the_foundation_class():
    assert iso_band(1480 * RPM) == (10.0, 1000.0)
    assert iso_band(600 * RPM) == (2.0, 1000.0)  # at 600 r/min or less from 2 Hz
    assert iso_band(15 * RPM) == (2.0, 1000.0)
    assert foundation_class(1.25, 1.0) == "rigid"  # 25 % above the running frequency
    assert foundation_class(1.2499, 1.0) == "flexible"


@pytest.mark.parametrize(("r", "zeta"), [(0.5, 0.05), (1.0, 0.1), (2.45, 0.05), (4.0, 0.2)])
def test_the_isolation_efficiency_of_one_spring_and_damper_is_one_minus_the_closed_form(r, zeta):
    """A machine of mass m on one spring k and damper c, a vertical harmonic force at Ω = r ω_n:
    V = √((1 + (2ζr)²)/((1 − r²)² + (2ζr)²)), η = 1 − V (VDI 2062 Blatt 1; Rao §9.10)."""
    m, k = 400.0, 1.6e6
    wn = math.sqrt(k / m)
    machine = MountedMachine.single_dof(m, k, zeta)
    load = PeriodicLoad.from_harmonics(2 * math.pi / (r * wn), {1: 1000.0})
    got = vibration_verdicts(machine, load)
    V = math.sqrt((1 + (2 * zeta * r) ** 2) / ((1 - r**2) ** 2 + (2 * zeta * r) ** 2))
    assert transmissibility(r, zeta) == pytest.approx(V, rel=1e-14)
    assert got.transmissibility == pytest.approx(V, rel=1e-9)
    assert got.harmonic_transmissibility == pytest.approx([V], rel=1e-9)
    assert got.summary()["isolation_efficiency_percent"] == pytest.approx(100 * (1 - V), rel=1e-9)
    assert isolation_efficiency(V) == pytest.approx(1 - V, rel=1e-14)
    assert got.exciting[1] == pytest.approx(1000.0, rel=1e-12)  # the amplitude given
    word = "amplify" if V > 1 else "floor takes"
    assert word in got.isolation_verdict


def test_the_band_rms_of_a_pure_sine():
    fs, n, f, A = 1024.0, 4096, 32.0, 3.0  # 128 whole periods
    x = A * np.sin(2 * math.pi * f * np.arange(n) / fs + 0.3)
    assert band_rms(x, fs, (10.0, 1000.0)) == pytest.approx(A / math.sqrt(2), rel=1e-12)
    assert band_rms(x, fs, (32.0, 32.0)) == pytest.approx(A / math.sqrt(2), rel=1e-12)  # edges count
    assert band_rms(x, fs, (40.0, 1000.0)) == pytest.approx(0.0, abs=1e-12)
    assert band_rms(x, fs, (1.0, 31.0)) == pytest.approx(0.0, abs=1e-12)
    # from the series' coefficients c_h (x = c₀ + 2 Re Σ c_h e^{ihΩt}): amplitude 2|c_h|
    c = np.zeros(5, dtype=complex)
    c[2] = 0.5 * A * np.exp(0.3j)
    assert harmonic_band_rms(c, 16.0, (30.0, 40.0)) == pytest.approx(A / math.sqrt(2), rel=1e-14)
    assert harmonic_band_rms(c, 16.0, (33.0, 40.0)) == 0.0


def test_the_mode_separation_against_hand_numbers():
    rows = mode_separation([2.5, 3.1, 0.9, 10.0], 1.0, [1, 2, 3])
    # 2.5 Hz: 2 → +25 %, 3 → −16.7 %: the nearest is 3
    assert [r["order"] for r in rows] == [3, 3, 1, 3]
    assert [r["margin_percent"] for r in rows] == pytest.approx(
        [-100 / 6, 100 * 0.1 / 3, -10.0, 100 * 7 / 3], rel=1e-12
    )
    assert [r["close"] for r in rows] == [True, True, True, False]
    assert [r["close"] for r in mode_separation([2.5], 1.0, [1, 2, 3], margin=0.1)] == [False]
    assert mode_separation([2.0], 1.0, [])[0]["order"] is None


def test_third_octave_bands_and_the_floor_criteria():
    bands = third_octave_bands()
    assert bands[0, 1] == pytest.approx(1.0) and bands[-1, 1] == pytest.approx(10**1.9)  # 79.4 Hz
    assert bands.shape == (20, 3)
    np.testing.assert_allclose(bands[:, 2] / bands[:, 0], 10**0.1, rtol=1e-12)
    # two lines in the 16 Hz band add as mean squares; 20 µm/s passes VC-B, fails VC-C
    out = floor_criteria([15.5, 16.5], [12e-6, 16e-6])
    k = out["band_centre_hz"].index(pytest.approx(10**1.2))
    assert out["band_velocity_m_per_s"][k] == pytest.approx(20e-6, rel=1e-12)
    assert out["strictest_met"] == "VC-B"
    assert "VC-C" not in out["met"] and "VC-A" in out["met"]
    assert list(VIBRATION_CRITERIA)[-1] == "VC-E"
    assert criterion_velocity("VC-C", 2.0) == pytest.approx(12.5e-6)
    # the ISO base curve: flat 100 µm/s from 8 Hz; 5 mm/s² of acceleration from 4 Hz to 8 Hz
    assert criterion_velocity("operating theatre (ISO)", 20.0) == pytest.approx(100e-6)
    assert criterion_velocity("office (ISO)", 5.0) == pytest.approx(4 * 5e-3 / (2 * math.pi * 5.0))


def test_the_points_the_group_and_the_foundation_are_checked():
    machine = MountedMachine.single_dof(400.0, 1.6e6, 0.05)
    load = PeriodicLoad.from_harmonics(0.1, {1: 1000.0})
    with pytest.raises(ModelError, match="auto, rigid, flexible"):
        vibration_verdicts(machine, load, foundation="stiff")
    with pytest.raises(ModelError, match="groups 1 and 2"):
        vibration_verdicts(machine, load, machine_group=3)
    got = vibration_verdicts(machine, load, machine_group=1, foundation="flexible", points=[(0, 0, 1.0)])
    assert got.points == ("point 1",) and got.foundation == "flexible" and not got.group_by_default
    # 10 Hz is in the 10 Hz–1 kHz band: the band RMS is all of it
    assert got.velocity_band.max() == pytest.approx(got.velocity_all.max(), rel=1e-12)


def run_json(capsys, *argv):
    assert main([*argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("example", ["press_on_mounts.toml", "press_on_support.toml", "press_on_pads.toml"])
def test_the_press_examples_state_their_verdicts(example, capsys, tmp_path):
    s = run_json(capsys, "support", str(EXAMPLES / example), "--cycles", "1", "--db", str(tmp_path / "r.db"))
    assert s["iso20816_applies"] is False  # 15 rpm: below the 120 r/min ISO 20816-3 covers
    assert "ISO 20816-3 does not apply" in s["vibration_verdict"]
    assert "15 rpm" in s["vibration_verdict"] and "Assessed instead" in s["vibration_verdict"]
    assert "group 2 (by default, the stricter)" in s["vibration_verdict"]
    assert s["iso20816_zone"] in "ABCD" and s["iso20816_band_hz"] == [2.0, 1000.0]
    assert s["frame_velocity_rms_band_m_per_s"] < s["frame_velocity_rms_all_harmonics_m_per_s"]
    assert s["isolation_orders"][0] == 1
    assert s["isolation_efficiency_percent"] < 0  # quasi-static: the mounts cannot isolate at 0.25 Hz
    assert "do not isolate" in s["isolation_verdict"]
    assert "VDI 2062" in s["isolation_verdict"]
    assert "needs a floor or foundation model" in s["floor_vibration_verdict"]
    assert s["mode_separation_limit_percent"] == 20.0
    assert len(s["mode_nearest_harmonic"]) == len(s["natural_frequencies_hz"])
    assert "±20 %" in s["mode_separation_verdict"]
    text_args = ["support", str(EXAMPLES / example), "--cycles", "1", "--db", str(tmp_path / "r.db")]
    assert main(text_args) == 0
    out = capsys.readouterr().out
    for title in ("frame vibration (ISO 20816-3)", "isolation by harmonic (VDI 2062)", "modes against"):
        assert title in out
    assert "ISO 20816-3 does not apply" in out


def test_the_pump_set_is_judged_by_iso_20816_3_and_options_override_the_file(capsys, tmp_path):
    ex = str(EXAMPLES / "pump_set_unbalance.toml")
    db = str(tmp_path / "r.db")
    s = run_json(capsys, "support", ex, "--cycles", "1", "--db", db)
    assert s["iso20816_applies"] is True and s["iso20816_band_hz"] == [10.0, 1000.0]
    assert f"is in zone {s['iso20816_zone']} of ISO 20816-3" in s["vibration_verdict"]
    # one rotor: the isolation is the unbalance sweep's at the running speed
    assert s["isolation_efficiency_percent"] == pytest.approx(
        s["unbalance_isolation_efficiency_percent"], rel=1e-9
    )
    s = run_json(
        capsys, "support", ex, "--cycles", "1", "--db", db, "--machine-group", "1", "--foundation", "flexible"
    )
    assert s["iso20816_machine_group"] == 1 and s["iso20816_foundation"] == "flexible"
    assert s["iso20816_zone_boundaries_m_per_s"] == pytest.approx([3.5e-3, 7.1e-3, 11e-3])
    assert "by default" not in s["vibration_verdict"]
