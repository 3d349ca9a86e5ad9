import math

import pytest

from mechdyn.units import Q_, UnitError, to_si


@pytest.mark.parametrize(
    ("text", "unit", "expected"),
    [
        ("0.019 m", "m", 0.019),
        ("19 mm", "m", 0.019),
        ("80.8 GPa", "Pa", 80.8e9),
        ("1500 rpm", "rad/s", 1500 * 2 * 3.141592653589793 / 60),
        ("2.6e6 psi", "Pa", 2.6e6 * 6894.757293168361),
        ("0.95131987e6 N*m/rad", "N*m/rad", 0.95131987e6),
        ("4.03689425e-3 kg*m^2", "kg*m^2", 4.03689425e-3),
        ("4036.89425 kg*mm^2", "kg*m^2", 4.03689425e-3),
        ("20 deg", "rad", 0.3490658503988659),
        (Q_(3.0, "kN*m/rad"), "N*m/rad", 3000.0),
        ("54 tonf", "N", 54 * 9806.65),
        ("29 tf", "N", 29 * 9806.65),
    ],
)
def test_quantities_convert_to_si(text, unit, expected):
    assert to_si(text, unit) == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize(
    ("value", "unit", "fragment"),
    [
        ("3 kg", "N*m/rad", "expected a quantity of"),
        (3.0, "m", "has no unit"),
        ("banana m", "m", "cannot read"),
        ("", "m", "empty"),
        (True, "m", "boolean"),
        ("inf m", "m", "not finite"),
    ],
)
def test_bad_quantities_are_named(value, unit, fragment):
    with pytest.raises(UnitError, match=fragment):
        to_si(value, unit)


def test_plain_numbers_are_si_only_when_asked():
    assert to_si(2.5, "m", plain_is_si=True) == 2.5
    assert to_si(4, "", plain_is_si=False) == 4.0  # dimensionless needs no unit
    assert to_si(0.5, "rad") == 0.5  # radians are dimensionless in pint


def test_a_speed_given_for_a_frequency_counts_cycles():
    # pint counts a revolution as 2π rad, so "1500 rpm" in 1/s would be 157; as a frequency it is 25 Hz
    assert to_si("1500 rpm", "Hz") == pytest.approx(25.0)
    assert to_si("314.159265 rad/s", "Hz") == pytest.approx(50.0)
    assert to_si("2 kHz", "Hz") == 2000.0
    assert to_si("1500 rpm", "rad/s") == pytest.approx(157.0796, rel=1e-6)


def test_a_frequency_given_for_a_speed_counts_turns():
    # and back: pint takes 1 Hz as 1/s, so "25 Hz" as an angular speed was 25 rad/s, 2π too slow
    assert to_si("25 Hz", "rad/s") == pytest.approx(2 * math.pi * 25, rel=1e-15)
    assert to_si("1 kHz", "rad/s") == pytest.approx(2 * math.pi * 1000, rel=1e-15)
    assert to_si("25 Hz", "rpm") == pytest.approx(1500.0, rel=1e-15)
    assert to_si("10 rad/s", "rad/s") == 10.0  # a speed in radians stays


def test_an_angle_where_a_frequency_goes_is_refused_as_an_angle():
    """'0 deg' for a frequency reached pint's DimensionalityError (a traceback), found by the property
    test of tests/test_bad_input.py; an angular speed ('900 rpm') is still read as cycles."""
    from mechdyn.units import UnitError, to_si

    with pytest.raises(UnitError, match=r"'0\.0 deg' is an angle; expected a quantity of 1 / \[time\]"):
        to_si("0.0 deg", "Hz")
    assert to_si("900 rpm", "Hz") == pytest.approx(15.0)
