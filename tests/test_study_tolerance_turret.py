"""Turret C's K_v given ISO 1328-1 class 6 pitch deviations (issue 46,
``examples/studies/turret_kv_tolerance.toml``; its quick form runs in ``tests/test_tables.py``).

The mesh's transmission-error amplitude cannot be negative, so the study scatters the size of the
single pitch deviation, abs(f_pt): the ``iso1328_fpt`` class with ``magnitude = true``. Checked: that
distribution is exactly the signed band's folded at zero (normal and uniform shapes), its bad uses
are refused, and the example's class-6 band is the one ISO 1328-1 gives for the model's own gears."""

from __future__ import annotations

import math

import numpy as np
import pytest

from conftest import EXAMPLES
from mechdyn.errors import ModelError
from mechdyn.studies import load_study
from mechdyn.uncertainty import iso1328_single_pitch_tolerance, tolerance, variable_from_dict

GEAR = {"grade": 6, "d": "40.26 mm", "m_n": "2.119 mm"}


@pytest.mark.parametrize("shape", ["normal", "uniform"])
def test_the_size_of_a_pitch_deviation_is_the_signed_band_folded_at_zero(shape):
    """P(abs(f_pt) ≤ t) = F(t) − F(−t) of the signed deviation, at every t of the band."""
    signed = tolerance("f", "iso1328_fpt", unit="m", shape=shape, **GEAR)
    size = tolerance("f", "iso1328_fpt", unit="m", shape=shape, magnitude=True, **GEAR)
    half = iso1328_single_pitch_tolerance(6, "40.26 mm", "2.119 mm")
    assert half == pytest.approx(8.5e-6, abs=1e-12)  # (0.04026 + 0.8476 + 5)·√2 = 8.33 → 8.5 µm
    t = np.linspace(0.0, half, 9)
    folded = signed.cdf(t) - signed.cdf(-t)
    assert size.cdf(t) == pytest.approx(folded, abs=1e-12)
    assert float(size.ppf(0.0)) == 0.0 and float(size.ppf(1.0)) == pytest.approx(half)
    if shape == "normal":  # a half-normal of σ = f_pT/3 cut at 3σ: mean σ·√(2/π)·(1 − e^(−4.5))/(2Φ(3) − 1)
        from scipy.stats import norm

        sigma = half / 3
        mean = sigma * math.sqrt(2 / math.pi) * (1 - math.exp(-4.5)) / (2 * norm.cdf(3) - 1)
        assert size.mean == pytest.approx(mean, rel=1e-9)


def test_a_magnitude_is_refused_with_a_nominal_or_another_class():
    with pytest.raises(ModelError, match=r"nominal .* with magnitude = true"):
        tolerance("f", "iso1328_fpt", unit="m", nominal="3 um", magnitude=True, **GEAR)
    with pytest.raises(ModelError, match="magnitude = true is for the iso1328_fpt class"):
        tolerance("h", "shore_a_5", nominal=60, magnitude=True)
    # in a file, the model's value is no nominal for a magnitude: the band is centred on 0
    v = variable_from_dict("f", {"tolerance": "iso1328_fpt", "magnitude": True, **GEAR}, "m", nominal=3e-6)
    assert float(v.ppf(0.0)) == 0.0


def test_the_turret_example_scatters_its_own_gears_class_6_pitch_deviation_size():
    """The example's band is f_pT of ISO 1328-1 class 6 for the model's 19-tooth, 2.119 mm gears
    (d = z·m_n = 40.26 mm), as a size; its outputs are both meshes' K_v with a limit each."""
    study = load_study(EXAMPLES / "studies" / "turret_kv_tolerance.toml")
    (p,) = study.parameters
    pair = study.source.data["gear_pairs"][0]["pinion"]
    assert pair["teeth"] == 19 and pair["module"] == "2.119 mm"
    half = iso1328_single_pitch_tolerance(6, f"{19 * 2.119} mm", "2.119 mm")
    assert p.scatter.kind == "truncated normal"
    assert float(p.scatter.ppf(0.0)) == 0.0 and float(p.scatter.ppf(1.0)) == pytest.approx(half)
    assert [lim.output for lim in study.limits] == [
        "meshes.mesh 1.dynamic_factor_max_ratio",
        "meshes.mesh 2.dynamic_factor_max_ratio",
    ]
