"""Reference machine A: the link-drive press (examples/press_link_drive.toml) and its dimensional
synthesis (examples/studies/press_synthesis.toml)."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

import mechdyn
from conftest import EXAMPLES
from mechdyn.mechanism.dynamics import inverse_dynamics

TONF = 9806.65


def closed_form_positions(p: np.ndarray, theta: np.ndarray) -> dict[str, np.ndarray]:
    """The independent reference: the press's joints over the crank angles from the published
    loop closures (SPEC §1), written out dyad by dyad — B on the crank; C closing B–C–D (branch +1);
    E at the angle c from BC on the ternary link (−1); F on the guide y = y_F (+1)."""
    r, r1, r2, r3, l1, l2, dx, dy, yf = p
    B = np.stack([r * np.cos(theta), r * np.sin(theta)], -1)
    D = np.array([dx, dy])
    d = np.linalg.norm(D - B, axis=-1)
    x = (d**2 + r1**2 - l1**2) / (2 * d)
    e = (D - B) / d[:, None]
    C = B + x[:, None] * e + np.sqrt(r1**2 - x**2)[:, None] * np.stack([-e[:, 1], e[:, 0]], -1)
    c = math.acos((r1**2 + r2**2 - r3**2) / (2 * r1 * r2))
    ang = np.arctan2(C[:, 1] - B[:, 1], C[:, 0] - B[:, 0]) - c
    E = B + r2 * np.stack([np.cos(ang), np.sin(ang)], -1)
    F = np.stack([E[:, 0] + np.sqrt(l2**2 - (yf - E[:, 1]) ** 2), np.full(theta.shape, yf)], -1)
    return {"C": C, "E": E, "F": F}


@pytest.fixture(scope="module")
def press():
    return mechdyn.load(EXAMPLES / "press_link_drive.toml").model


@pytest.fixture(scope="module")
def press_result(press):
    return inverse_dynamics(press, 360)


def test_shipped_press_reproduces_the_published_signature(press_result):
    # SPEC §1: stroke 1495 mm, BDC 0°, TDC 129°, −29 tonf at 31°, +54 tonf at 114°, fluctuation 83 tonf.
    # Tolerances are the fit that the synthesis reaches (README): 2 mm, 1°, 1 tonf.
    s = press_result.summary()
    assert s["stroke_m"] == pytest.approx(1.495, abs=0.002)
    assert s["bdc_deg"] == 0.0 and s["tdc_deg"] == pytest.approx(129.0, abs=1.0)
    assert s["inertia_force_max_N"] / TONF == pytest.approx(54.0, abs=0.5)
    assert s["inertia_force_max_deg"] == pytest.approx(114.0, abs=1.0)
    assert s["inertia_force_min_N"] / TONF == pytest.approx(-29.0, abs=1.0)
    assert s["inertia_force_min_deg"] == pytest.approx(31.0, abs=1.0)
    assert s["inertia_force_fluctuation_N"] / TONF == pytest.approx(83.0, abs=1.5)
    assert s["power_balance_residual_relative"] < 1e-12
    # both extremes fall in the return stroke (0–129°), away from the forming at the bottom
    assert s["inertia_force_min_deg"] < s["tdc_deg"] and s["inertia_force_max_deg"] < s["tdc_deg"]


def test_links_inertia_is_small_next_to_the_slide(press_result):
    f = press_result.inertia_forces  # (N, bodies, 2)
    slide = np.abs(f[:, -1, 0]).max()
    assert all(np.abs(f[:, i, 0]).max() < 0.05 * slide for i in range(4))


def _dimensions():
    text = (EXAMPLES / "press_link_drive.toml").read_text()
    line = next(ln for ln in text.splitlines() if ln.startswith("# r = "))
    return np.array([float(v) / 1000 for v in re.findall(r"= (-?[\d.]+) mm", line)])


def test_closed_form_dyads_agree_with_the_engine(press, press_result):
    # SPEC §1: where the mechanism decomposes into dyads, the closed form and Newton must agree
    k = press_result.kinematics
    p = _dimensions()
    closed = closed_form_positions(p, k.crank_angle)
    for body, point in (("ternary", "C"), ("ternary", "E"), ("slide", "F")):
        np.testing.assert_allclose(k.point(body, point)[0], closed[point], atol=1e-8)


@pytest.mark.slow  # a synthesis study (over 10 s): CI's heavy step
def test_the_synthesis_study_keeps_its_limits_and_nears_the_signature(tmp_path):
    """The quick form of examples/studies/press_synthesis.toml: a fit that keeps the connecting rod
    within 15° of the slide's axis and the guide within 300 mm of the crank, and reaches the published
    signature within its tolerances."""
    from dataclasses import replace

    from mechdyn.studies import load_study, run_study
    from mechdyn.studies.outputs import HOLD_TOLERANCE

    study = load_study(EXAMPLES / "studies" / "press_synthesis.toml")
    result = run_study(replace(study, samples=25, name="synthesis-quick"), str(tmp_path / "r.db"))
    best = result.findings["best"]
    assert result.findings["feasible"] and all(c["holds"] for c in best["constraints"])
    # kept to the round-off an optimizer ends with on an active limit (HOLD_TOLERANCE of the limit)
    assert best["outputs"]["output_link_obliquity_max_deg"] <= 15.0 * (1 + HOLD_TOLERANCE)
    assert best["outputs"]["guide_offset_m"] <= 0.3 * (1 + HOLD_TOLERANCE)
    assert result.findings["base"]["constraints"][0]["holds"] is False  # 66°: the reason for the study
    # the evolution's best then polished with the limits as constraints: every published target
    # within its tolerance (300 generations of evolution alone missed two), each with its verdict
    assert all(t["holds"] and t["margin"] >= 0 for t in result.findings["targets"])
    assert result.findings["missed_because"] is None
    verdicts = next(t for t in result.tables() if t.title.endswith("targets"))
    assert all(str(row[4]).startswith("holds") for row in verdicts.rows)


def test_dead_centres_and_force_extremes_are_located_between_samples(press):
    # the top dead centre lies at 128.92°, between the samples 128° and 129°; coarser sampling finds
    # the same angles, and the batch gives each variant the single design's figures
    from mechdyn.mechanism import cycle

    fine = inverse_dynamics(press, 3600).summary()
    for n, tol, stroke_tol in ((360, 0.001, 1e-8), (72, 0.02, 1e-5)):  # 1° and 5° between samples
        s = inverse_dynamics(press, n).summary()
        assert s["bdc_deg"] == 0.0
        for key in ("tdc_deg", "inertia_force_max_deg", "inertia_force_min_deg"):
            assert s[key] == pytest.approx(fine[key], abs=tol), (n, key)
        assert s["stroke_m"] == pytest.approx(fine["stroke_m"], rel=stroke_tol)
    assert fine["tdc_deg"] == pytest.approx(128.92, abs=0.005)
    batch = cycle(press, 360).summary()
    single = inverse_dynamics(press, 360).summary()
    for key, v in batch.items():
        if isinstance(v, dict):
            for name, peaks in v.items():
                assert peaks[0] == pytest.approx(single[key][name], rel=1e-12), (key, name)
        else:
            assert v[0] == pytest.approx(single[key], rel=1e-12, abs=1e-9), key


def test_an_extreme_a_round_off_before_the_datum_is_at_0_deg_not_360():
    # an extreme located a round-off before the datum read 359.99999999999994°, where the same
    # design in another batch gave 3e-13°: an angle figure is in [0, 360) and that round-off is 0
    from mechdyn.mechanism.extrema import output_figures

    deg = np.arange(72) * 5.0
    th = np.radians(deg)
    f = np.cos(th + 1e-12)  # its maximum 6e-11° before the datum
    assert output_figures(deg, np.cos(th + 0.3), -f, bdc_datum=False)["inertia_force_min_deg"] == 0.0
    out = output_figures(deg, -np.cos(th), f, bdc_datum=True)
    assert out["inertia_force_max_deg"] == 0.0 and out["bdc_deg"] == 0.0
