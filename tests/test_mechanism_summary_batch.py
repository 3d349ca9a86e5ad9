"""The summary-only batch (:func:`mechdyn.mechanism.dyads.cycle_summary`) gives the full batch's
figures, variant by variant, without keeping any curve.

Its figures are reduced in compiled code from work buffers that every chunk of variants reuses; here
they are compared with :meth:`CycleBatch.summary` of the full batch (the NumPy reductions of
:mod:`mechdyn.mechanism.extrema` over the stored curves) for every scalar, on mechanisms that
exercise each figure (a slide output with a BDC datum, a rocker output, process forces, a fixed
datum), with variants that fail among them; and with the single-design path, variant by variant.
"""

from __future__ import annotations

import tracemalloc
from dataclasses import replace

import numpy as np
import pytest

import mechdyn
from conftest import EXAMPLES
from mechdyn.mechanism import inverse_dynamics
from mechdyn.mechanism.batch import cycle_columns
from mechdyn.mechanism.dyads import CycleSummary, cycle, cycle_summary

CASES = {  # example → (points moved, scale of the move in m)
    "press_link_drive.toml": (("C", "D"), 0.03),
    "fourbar.toml": (("B", "O4"), 0.002),
    "slider_crank.toml": (("A",), 0.003),
    "press_blanking.toml": (("C", "D"), 0.03),
}


def _variants(name: str, V: int = 37, seed: int = 0):
    mech = mechdyn.load(EXAMPLES / name).model
    moved, scale = CASES[name]
    rng = np.random.default_rng(seed)
    points = {k: np.asarray(mech.points[k]) + rng.normal(scale=scale, size=(V, 2)) for k in moved}
    # one variant whose crank is longer than the rest of its loop can reach: it cannot turn round,
    # and its figures are NaN in both paths
    pivot, tip = (np.asarray(mech.points[p]) for p in (mech.driver.pivot, mech.driver.tip))
    points.setdefault(mech.driver.tip, np.tile(tip, (V, 1)))[5] = pivot + 20.0 * (tip - pivot)
    return mech, points


def _same(full: dict, reduced: dict, what: str) -> None:
    assert set(full) == set(reduced), what
    for key, value in full.items():
        if isinstance(value, dict):
            assert set(value) == set(reduced[key])
            for joint, peaks in value.items():
                np.testing.assert_allclose(reduced[key][joint], peaks, rtol=1e-12, equal_nan=True)
            continue
        scale = np.nanmax(np.abs(value)) if np.isfinite(value).any() else 1.0
        np.testing.assert_allclose(
            reduced[key], value, rtol=1e-9, atol=1e-12 * scale, equal_nan=True, err_msg=f"{what}: {key}"
        )


@pytest.mark.parametrize("name", sorted(CASES))
def test_summary_mode_equals_the_reductions_of_the_full_batch(name):
    mech, points = _variants(name)
    full = cycle(mech, 72, points=points, store_points=False, errors="nan")
    reduced = cycle_summary(mech, 72, points=points, chunk=8)  # several chunks, the last one short
    assert isinstance(reduced, CycleSummary)
    assert reduced.failures == full.failures and 5 in reduced.failures
    np.testing.assert_array_equal(reduced.assembled, full.assembled)
    _same(full.summary(), reduced.summary(), name)
    assert list(reduced.to_frame().columns) == list(full.to_frame().columns)


def test_the_chunk_size_does_not_change_a_figure():
    # process forces: the chunk-by-chunk path (a press without them runs in lanes, one per thread)
    mech, points = _variants("press_blanking.toml", V=20)
    one = cycle_summary(mech, 90, points=points, chunk=1).summary()
    many = cycle_summary(mech, 90, points=points, chunk=64).summary()
    for key, value in one.items():
        if isinstance(value, dict):
            for joint, peaks in value.items():
                np.testing.assert_array_equal(many[key][joint], peaks)
        else:
            np.testing.assert_array_equal(many[key], value)


@pytest.mark.parametrize("name", ["press_link_drive.toml", "fourbar.toml"])
def test_a_variant_of_the_summary_batch_is_its_single_design(name):
    mech, points = _variants(name, V=6)
    reduced = cycle_summary(mech, 72, points=points).summary()
    for v in range(6):
        if v == 5:  # the variant that does not assemble
            assert np.isnan(reduced["driving_torque_max_Nm"][v])
            continue
        variant = replace(mech, points={**mech.points, **{k: tuple(a[v]) for k, a in points.items()}})
        single = inverse_dynamics(variant, 72).summary()
        for key, values in reduced.items():
            if isinstance(values, dict):
                for joint, peaks in values.items():
                    assert peaks[v] == pytest.approx(single[key][joint], rel=1e-9), (v, key, joint)
            else:
                assert values[v] == pytest.approx(single[key], rel=1e-9, abs=1e-9), (v, key)


def test_a_study_asks_the_kernel_for_scalars_and_stores_no_curve():
    mech = mechdyn.load(EXAMPLES / "press_link_drive.toml").model
    V = 3000
    rng = np.random.default_rng(1)
    columns = {("points", "D", 0): mech.points["D"][0] + rng.normal(scale=0.02, size=V)}
    cycle_columns(mech, columns, 72, summary_only=True)  # compiled and warm before measuring
    tracemalloc.start()
    try:
        result = cycle_columns(mech, columns, 72, summary_only=True)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert isinstance(result, CycleSummary) and result.n_variants == V
    # the curves alone would be V × 72 angles × (torque, moment, force, inertia, stroke) ≈ 5 KB each
    assert peak / V < 2048
    full = cycle_columns(mech, columns, 72).summary()
    _same(full, result.summary(), "cycle_columns")


def test_a_chunk_that_is_not_a_count_is_refused():
    mech = mechdyn.load(EXAMPLES / "fourbar.toml").model
    with pytest.raises(mechdyn.MechdynError, match="chunk"):
        cycle_summary(mech, 36, chunk=0)


@pytest.mark.parametrize("datum", ["bdc", 0.3])
def test_a_speed_profile_runs_chunk_by_chunk_to_the_same_figures(datum):
    # the speed is read at each variant's crank angle from its datum (with "bdc", found from the
    # motion first): the chunked path, against the full batch
    mech, points = _variants("slider_crank.toml", V=19)
    w = mech.driver.speed

    def speed(theta):
        return w * (1 + 0.3 * np.cos(theta))

    mech = replace(mech, angle_datum=datum, driver=replace(mech.driver, profile=speed))
    full = cycle(mech, 60, points=points, store_points=False, errors="nan")
    reduced = cycle_summary(mech, 60, points=points, chunk=4)
    assert reduced.failures == full.failures and 5 in reduced.failures
    _same(full.summary(), reduced.summary(), f"profile, datum {datum}")


def test_the_model_s_cached_setup_is_not_reached_through_a_result_and_follows_its_drawing():
    """The dyad path keeps its plan and the design's encoding with the model: a result's arrays are
    its own (editing them changes no later call), and a drawing edited in place is drawn anew."""
    from dataclasses import replace

    m = mechdyn.load(EXAMPLES / "press_link_drive.toml").model
    first = cycle(m, 90)
    first._body_mass[...] *= 2
    first._steps.clear()
    again = cycle(m, 90)
    np.testing.assert_array_equal(again.driving_torque, first.driving_torque)
    name = next(iter(m.points))
    x, y = m.points[name]
    m.points[name] = (x + 0.01, y)  # not a supported use: a variant is a new model
    moved = cycle(m, 90)
    assert np.nanmax(np.abs(moved.driving_torque - again.driving_torque)) > 0
    np.testing.assert_array_equal(moved.driving_torque, cycle(replace(m), 90).driving_torque)
