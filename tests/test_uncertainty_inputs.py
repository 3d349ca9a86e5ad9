"""Uncertain inputs: the distributions with units, from Python and from a file's table, the named
tolerance classes with their sources, and the errors on bad input naming the field, the value and the
fix."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

from mechdyn.errors import ModelError
from mechdyn.uncertainty import (
    InputSpace,
    Limit,
    iso1328_single_pitch_tolerance,
    levels,
    lognormal,
    normal,
    propagate,
    small_probability,
    tolerance,
    tolerance_classes,
    triangular,
    truncated,
    uniform,
    variable_from_dict,
)


def test_units_are_converted_to_si_at_the_constructor():
    a = normal("gap", "2 mm", "50 um", "m")
    b = normal("gap", 0.002, 5e-5, "m")
    assert a.mean == pytest.approx(b.mean) and a.std == pytest.approx(b.std)
    k = lognormal("k", median="2 kN/mm", cov=0.15, unit="N/m")
    assert k.parameters["median"] == pytest.approx(2e6)


def test_lognormal_parameters_agree_however_they_are_given():
    med, cov = 2e6, 0.15
    mean = med * math.sqrt(1 + cov**2)
    by = [
        lognormal("k", median=med, cov=cov, unit="N/m"),
        lognormal("k", mean=mean, cov=cov, unit="N/m"),
        lognormal("k", mean=mean, std=mean * cov, unit="N/m"),
        lognormal("k", median=med, std=mean * cov, unit="N/m"),
        lognormal("k", median=med, sigma_ln=math.sqrt(math.log1p(cov**2)), unit="N/m"),
    ]
    for v in by:
        assert v.mean == pytest.approx(mean, rel=1e-9) and v.std == pytest.approx(mean * cov, rel=1e-9)


@pytest.mark.parametrize(
    "variable, mean, std",
    [
        (uniform("x", 1.0, 3.0), 2.0, 2 / math.sqrt(12)),
        (triangular("x", 0.0, 1.0, 4.0), 5 / 3, math.sqrt((0 + 1 + 16 - 0 - 0 - 4) / 18)),
        (levels("x", [1.0, 2.0, 4.0], [0.5, 0.25, 0.25]), 2.0, math.sqrt(1.5)),
        (
            truncated(normal("x", 0.0, 1.0), -1.0, 2.0),
            stats.truncnorm(-1, 2).mean(),
            stats.truncnorm(-1, 2).std(),
        ),
        (truncated(lognormal("x", median=1.0, cov=0.5), high=1.5), None, None),
    ],
)
def test_moments_and_the_nataf_map_are_those_of_the_distribution(variable, mean, std):
    if mean is not None:
        assert variable.mean == pytest.approx(mean, rel=1e-7)
        assert variable.std == pytest.approx(std, rel=1e-7)
    z = np.linspace(-6, 6, 41)
    x = variable.from_standard_normal(z)
    assert np.all(np.diff(x) >= 0)
    if variable.continuous:
        assert variable.cdf(x) == pytest.approx(stats.norm.cdf(z), abs=1e-9)


def test_a_truncated_normal_keeps_its_upper_tail_digits():
    v = truncated(normal("x", 0.0, 1.0), -10.0, 10.0)
    assert v.from_standard_normal(np.array([7.0]))[0] == pytest.approx(7.0, rel=1e-6)


def test_a_file_table_gives_the_same_variable_as_python():
    cases = [
        (
            {"distribution": "lognormal", "median": "2 MN/m", "cov": 0.15},
            lognormal("k", median=2e6, cov=0.15, unit="N/m"),
        ),
        ({"distribution": "normal", "mean": "2 MN/m", "std": "0.1 MN/m"}, normal("k", 2e6, 1e5, "N/m")),
        ({"distribution": "normal", "cov": 0.05}, normal("k", 2e6, 1e5, "N/m")),
        ({"distribution": "uniform", "low": "1 MN/m", "high": "3 MN/m"}, uniform("k", 1e6, 3e6, "N/m")),
        (
            {"distribution": "triangular", "low": "1 MN/m", "mode": "2 MN/m", "high": "4 MN/m"},
            triangular("k", 1e6, 2e6, 4e6, "N/m"),
        ),
        (
            {"distribution": "levels", "values": ["1 MN/m", "2 MN/m"], "probabilities": [0.3, 0.7]},
            levels("k", [1e6, 2e6], [0.3, 0.7], "N/m"),
        ),
        (
            {"distribution": "normal", "std": "0.5 MN/m", "lower": "1.5 MN/m"},
            truncated(normal("k", 2e6, 5e5, "N/m"), 1.5e6),
        ),
        ({"tolerance": "soil_stiffness"}, lognormal("k", median=2e6, cov=0.35, unit="N/m")),
        ({"tolerance": "band", "plus_minus": "20 %", "shape": "uniform"}, uniform("k", 1.6e6, 2.4e6, "N/m")),
    ]
    for spec, expected in cases:
        got = variable_from_dict("k", spec, "N/m", nominal="2 MN/m")
        assert got.kind == expected.kind, spec
        assert got.mean == pytest.approx(expected.mean, rel=1e-9) and got.std == pytest.approx(
            expected.std, rel=1e-9
        ), spec


@pytest.mark.parametrize(
    "grade, d_mm, m_mm, expected_um",
    [
        (5, 100, 2, 6.0),  # 0.1 + 0.8 + 5 = 5.9 → 6.0 (rounded to 0.5 µm)
        (6, 120, 3, 9.0),  # 6.32·√2 = 8.94 → 9.0
        (7, 500, 8, 17.0),  # 8.7·2 = 17.4 → 17 (rounded to 1 µm)
        (1, 10, 1, 1.4),  # 5.41/4 = 1.35 → 1.4 (rounded to 0.1 µm)
        (11, 1000, 20, 120.0),  # 14·8 = 112 → 112; see below
    ],
)
def test_iso1328_single_pitch_tolerance_by_eq_5(grade, d_mm, m_mm, expected_um):
    raw = (0.001 * d_mm + 0.4 * m_mm + 5) * math.sqrt(2) ** (grade - 5)
    assert iso1328_single_pitch_tolerance(grade, d_mm / 1e3, m_mm / 1e3, rounded=False) == pytest.approx(
        raw * 1e-6
    )
    got = iso1328_single_pitch_tolerance(grade, f"{d_mm} mm", f"{m_mm} mm") * 1e6
    step = 1.0 if raw > 10 else 0.5 if raw >= 5 else 0.1
    assert got == pytest.approx(round(raw / step) * step) and abs(got - raw) <= step / 2 + 1e-9


def test_a_grade_6_pitch_deviation_spreads_within_its_band():
    v = tolerance("mesh.pitch_deviation", "iso1328_fpt", grade=6, d="120 mm", m_n="3 mm", unit="m")
    half = 9.0e-6
    assert float(v.ppf(0.0)) == pytest.approx(-half) and float(v.ppf(1.0)) == pytest.approx(half)
    assert v.std == pytest.approx(stats.truncnorm(-3, 3, scale=half / 3).std(), rel=1e-6)
    assert "ISO 1328-1:2013" in v.source


def test_every_tolerance_class_names_its_source():
    classes = tolerance_classes()
    assert {"shore_a_5", "iso1328_fpt", "concrete_modulus", "soil_stiffness", "band"} <= set(classes)
    for name, data in classes.items():
        assert data["source"].strip() and data["title"], name
        if data.get("engineering_assumption"):
            assert data["source"].startswith("Engineering assumption"), name
    pad = tolerance("pad.shore_a", "shore_a_5", nominal=60, shape="uniform")
    assert (pad.kind, pad.parameters["low"], pad.parameters["high"]) == ("uniform", 55.0, 65.0)
    assert "ASTM D2000" in pad.source


def _error(call) -> ModelError:
    with pytest.raises(ModelError) as info:
        call()
    return info.value


@pytest.mark.parametrize(
    "call, field, says",
    [
        (lambda: normal("gap", "2 mm", "-1 mm", "m"), "std", ["'-1 mm'", "positive"]),
        (lambda: normal("gap", "2 kg", "1 mm", "m"), "mean", ["'2 kg'", "expected a quantity of [length]"]),
        (
            lambda: lognormal("k", median="2 MN/m", unit="N/m"),
            "cov",
            ["give exactly one of cov, std or sigma_ln", "cov = 0.15"],
        ),
        (lambda: uniform("x", 3.0, 1.0), "high", ["high = 1.0", "low < high"]),
        (lambda: triangular("x", 0.0, 5.0, 1.0), "mode", ["mode = 5.0", "between"]),
        (
            lambda: levels("x", [1.0, 2.0], [0.5, 0.6]),
            "probabilities",
            ["[0.5, 0.6]", "sum to 1", "scale them"],
        ),
        (lambda: truncated(normal("x", 0, 1), 5.0, 4.0), "upper", ["upper = 4.0", "lower < upper"]),
        (
            lambda: tolerance("pad", "shore_a5", nominal=60),
            "tolerance",
            ["'shore_a5'", "did you mean 'shore_a_5'"],
        ),
        (
            lambda: tolerance("g", "iso1328_fpt", grade=13, d="1 m", m_n="3 mm", unit="m"),
            "grade",
            ["grade = 13", "1 … 11"],
        ),
        (
            lambda: tolerance("g", "iso1328_fpt", grade=6, d="1 m", m_n="100 mm", unit="m"),
            "m_n",
            ["'100 mm'", "0.5 mm … 70 mm"],
        ),
        (
            lambda: tolerance("k", "band", nominal="2 MN/m", unit="N/m"),
            "plus_minus",
            ["needs plus_minus", "'20 %'"],
        ),
        (
            lambda: tolerance("pad", "shore_a_5", nominal=60, shape="gauss"),
            "shape",
            ["'gauss'", "'normal', 'uniform'"],
        ),
        (
            lambda: variable_from_dict(
                "k", {"distribution": "lognorml", "median": "2 MN/m", "cov": 0.1}, "N/m"
            ),
            "distribution",
            ["'lognorml'", "did you mean 'lognormal'"],
        ),
        (
            lambda: variable_from_dict(
                "k", {"distribution": "normal", "mean": "2 MN/m", "sd": "1 N/m"}, "N/m"
            ),
            "sd",
            ["'sd'", "did you mean 'std'"],
        ),
        (
            lambda: variable_from_dict("k", {"distribution": "normal", "std": "1 N/m"}, "N/m"),
            "mean",
            ["needs its mean", "mean = "],
        ),
        (
            lambda: variable_from_dict("k", {"median": "2 MN/m"}, "N/m"),
            "distribution",
            ["neither distribution nor tolerance", 'distribution = "lognormal"'],
        ),
        (
            lambda: variable_from_dict(
                "k", {"tolerance": "band", "plus_minus": "twenty %"}, "N/m", nominal=1.0
            ),
            "plus_minus",
            ["'twenty %'", "'20 %'"],
        ),
        (
            lambda: variable_from_dict("k", {"distribution": "uniform", "low": "1 MN/m"}, "N/m"),
            "high",
            ["needs high", "high = "],
        ),
        (
            lambda: InputSpace([normal("a", 0, 1), normal("b", 0, 1)], {("a", "b"): 1.2}),
            "correlation",
            ["1.2", "(-1, 1)"],
        ),
        (
            lambda: InputSpace([normal("a", 0, 1), normal("b", 0, 1)], {("a", "c"): 0.2}),
            "correlation",
            ["('a', 'c')", "give (name_a, name_b)"],
        ),
        (lambda: InputSpace([normal("a", 0, 1)] * 2), "variables", ["['a']", "each input once"]),
        (lambda: Limit("y", 1.0, "over"), "side", ["'over'", "'above'"]),
        (
            lambda: propagate(lambda X: X[:, 0], [normal("a", 0, 1)], 100, method="qmc", replicates=3),
            "replicates",
            ["n = 100", "multiple"],
        ),
        (
            lambda: propagate(
                lambda X: X[:, 0], [normal("a", 0, 1)], 64, limits=[Limit("z", 1.0)], outputs=["y"]
            ),
            "output",
            ["'z'", "['y']"],
        ),
        (
            lambda: propagate(lambda X: np.where(X[:, 0] > 0, X[:, 0], np.nan), [normal("a", 0, 1)], 64),
            "outputs",
            ["non-finite", "truncate"],
        ),
        (
            lambda: small_probability(
                lambda X: X[:, 0], [levels("a", [0.0, 1.0])], Limit("y", 0.5), method="form"
            ),
            "method",
            ["['a']", "method = 'subset'"],
        ),
    ],
)
def test_bad_input_names_the_field_the_value_and_the_fix(call, field, says):
    err = _error(call)
    assert err.field == field, (err.field, str(err))
    for text in says:
        assert text in str(err), (text, str(err))
