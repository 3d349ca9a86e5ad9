"""Checks of the numbers that enter the Python API: finite, of a magnitude a machine can have, in range.

Model files bound every quantity as they read it (:mod:`mechdyn.io.fields`); the Python API takes
plain floats and arrays, which are SI by contract, and checks them here, at the edge, with the same
bounds (:data:`MAGNITUDE_LIMITS` is the one table: the model files' field types import it). A NaN,
an infinity or a slipped exponent (a damping of 1e300, a length of 1e-300 m) is refused with a
:class:`~mechdyn.errors.ModelError` that names the parameter, its value and what is accepted,
instead of overflowing a solver, returning NaN or running for ever.

:func:`~mechdyn.units.si_field` (every public constructor's conversion to SI) applies
:func:`check_number` to what it converts; analyses check their own numerical arguments with
:func:`check_number`, :func:`check_array` and :func:`check_count`.

Examples
--------
>>> from mechdyn.checks import check_number
>>> from mechdyn.errors import ModelError
>>> check_number("support", "damping_ratio", 0.05, low=0.0, high=10.0)
0.05
>>> try:
...     check_number("support", "damping_ratio", 1e300, low=0.0, high=10.0)
... except ModelError as e:
...     print(e.element, e.field, e.detail, sep="\n")
support
damping_ratio
1e+300 is beyond any machine this package models; give a finite damping ratio between 0 and 10
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from mechdyn.errors import ModelError

__all__ = [
    "DEFAULT_LIMIT",
    "DEFAULT_SMALLEST",
    "MAGNITUDE_LIMITS",
    "SMALLEST_POSITIVE",
    "check_array",
    "check_count",
    "check_number",
    "magnitude_limit",
    "smallest_positive",
]

DEFAULT_LIMIT = 1e15
"""The largest magnitude of a quantity whose unit :data:`MAGNITUDE_LIMITS` does not list."""

# The largest magnitude a quantity may have, by its SI unit: generous bounds for machines (a 1 km
# length, a 100 000 t mass, 10 MHz), so that a slipped exponent or a wrong unit is refused at the edge
# instead of overflowing a solver. The model files' field types (mechdyn.io.fields) bound their values
# with this same table.
MAGNITUDE_LIMITS = {
    "m": 1e3,
    "m^2": 1e6,
    "kg": 1e8,
    "kg*m^2": 1e10,
    "s": 1e7,
    "Hz": 1e7,
    "1/s": 1e8,
    "rad/s": 1e8,
    "rad": 1e6,
    "N": 1e11,
    "N*m": 1e11,
    "Pa": 1e13,
    "N/m": 1e15,
    "N*m/rad": 1e14,
    "N*s/m": 1e13,
    "kg/m^3": 1e5,
    "m/s": 1e5,
    "m/s^2": 1e6,
    "": 1e9,
}
"""SI unit → the largest magnitude accepted (``""``: a dimensionless number)."""

DEFAULT_SMALLEST = 1e-12
"""The smallest positive magnitude of a quantity whose unit :data:`SMALLEST_POSITIVE` does not list."""

# The smallest magnitude a quantity that must be positive (a size, a mass, a stiffness, a period) may
# have: far below any machine part (a nanometre, a microgram), far above where the formulas built on
# them (h³, 1/h, d⁴) leave the floating-point range.
SMALLEST_POSITIVE = {
    "m": 1e-9,
    "m^2": 1e-18,
    "kg": 1e-9,
    "kg*m^2": 1e-18,
    "s": 1e-7,
    "Hz": 1e-7,
    "rad/s": 1e-6,
    "rad": 1e-9,
    "N": 1e-9,
    "N*m": 1e-9,
    "Pa": 1e-3,
    "N/m": 1e-6,
    "N*m/rad": 1e-9,
    "N*s/m": 1e-12,
    "N*m*s/rad": 1e-12,
    "kg/m^3": 1e-3,
    "": 1e-12,
}
"""SI unit → the smallest magnitude accepted where a quantity must be positive."""


def magnitude_limit(unit: str) -> float:
    """The largest magnitude accepted for a quantity in ``unit`` (:data:`MAGNITUDE_LIMITS`).

    Parameters
    ----------
    unit : str
        The SI unit as pint spells it (``"N*m/rad"``), ``""`` for a dimensionless number.
    """
    return MAGNITUDE_LIMITS.get(unit, DEFAULT_LIMIT)


def smallest_positive(unit: str) -> float:
    """The smallest magnitude accepted for a positive quantity in ``unit`` (:data:`SMALLEST_POSITIVE`).

    Parameters
    ----------
    unit : str
        The SI unit as pint spells it, ``""`` for a dimensionless number.
    """
    return SMALLEST_POSITIVE.get(unit, DEFAULT_SMALLEST)


def _g(x: Any) -> str:
    if isinstance(x, complex | np.complexfloating):
        return f"{complex(x):g}".strip("()")
    try:
        return f"{float(x):g}"
    except (TypeError, ValueError):
        return repr(x)


def _accepted(
    what: str,
    unit: str,
    low: float | None,
    high: float,
    low_open: bool,
    high_open: bool,
    finite_word: str = "a finite",
) -> str:
    """``"a finite damping ratio between 0 and 10"``: what is accepted, for a message."""
    u = f" {unit}" if unit else ""
    if low is None and high == math.inf:
        return f"{finite_word} {what}"
    if low is None and high == magnitude_limit(unit):
        span = f"of at most {_g(high)}{u} in magnitude"
    elif low is None:
        span = f"{'less than' if high_open else 'at most'} {_g(high)}{u}"
    elif not low_open and not high_open:
        span = f"between {_g(low)} and {_g(high)}{u}"
    else:
        span = f"in {'(' if low_open else '['}{_g(low)}, {_g(high)}{')' if high_open else ']'}{u}"
    return f"{finite_word} {what} {span}"


def _bounds(
    unit: str,
    low: float | None,
    high: float | None,
    low_open: bool,
    high_open: bool,
    positive: bool,
    nonnegative: bool,
) -> tuple[float | None, float, bool, bool]:
    """The accepted interval: the given bounds, tightened by the sign and the magnitude limit (a
    lower bound of None: down to minus the limit)."""
    cap = magnitude_limit(unit)
    if positive:
        low, low_open = max(smallest_positive(unit), low or 0.0), False
    elif nonnegative and (low is None or low < 0):
        low, low_open = 0.0, False
    if high is None or high > cap:
        high, high_open = cap, False
    if low is not None and low < -cap:
        low, low_open = None, False
    return low, high, low_open, high_open


def check_number(
    element: str | None,
    field: str,
    value: Any,
    unit: str = "",
    *,
    low: float | None = None,
    high: float | None = None,
    low_open: bool = False,
    high_open: bool = False,
    positive: bool = False,
    nonnegative: bool = False,
    nonzero: bool = False,
    what: str | None = None,
) -> float:
    """A real number, checked: finite, within the magnitude a machine can have, within its range.

    Parameters
    ----------
    element : str or None
        The element (or analysis) the number belongs to, for the message.
    field : str
        The parameter's name, for the message.
    value : float
        The number, in ``unit`` (SI).
    unit : str
        Its SI unit (``"m"``, ``"N*s/m"``), ``""`` for a dimensionless number; sets the largest
        magnitude accepted (:data:`MAGNITUDE_LIMITS`) and, with ``positive``, the smallest
        (:data:`SMALLEST_POSITIVE`).
    low, high : float, optional
        Bounds of the accepted range, in ``unit``; closed unless ``low_open`` / ``high_open``.
    low_open, high_open : bool
        Exclude the bound itself.
    positive : bool
        The number must be positive, and at least the smallest positive magnitude of its unit.
    nonnegative : bool
        The number must not be negative.
    nonzero : bool
        The number must not be zero (either sign), nor smaller in magnitude than the smallest
        positive magnitude of its unit.
    what : str, optional
        What the number is, in words, for the message (default: the field's name in words).

    Returns
    -------
    float
        The number, as a float.

    Raises
    ------
    mechdyn.errors.ModelError
        Naming the element, the parameter, the value and what is accepted.
    """
    words = what or field.replace("_", " ")
    lo, hi, lo_open, hi_open = _bounds(unit, low, high, low_open, high_open, positive, nonnegative)
    u = f" {unit}" if unit else ""
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        shown = repr(value) if element is not None else f"{field} = {value!r}"
        raise ModelError(
            f"{shown} is not a number; give {_accepted(words, unit, lo, hi, lo_open, hi_open)}",
            element=element,
            field=field,
        )
    v = float(value)
    problem = None
    if not math.isfinite(v):
        problem = "is not finite"
    elif abs(v) > magnitude_limit(unit):
        problem = "is beyond any machine this package models"
    elif positive and v <= 0:
        problem = "must be positive"
    elif nonnegative and v < 0:
        problem = "must not be negative"
    elif positive and lo is not None and v < lo:
        problem = "is too small to be meant"
    elif nonzero and abs(v) < smallest_positive(unit):
        problem = "must not be zero" if v == 0 else "is too small to be meant"
    elif (lo is not None and (v < lo or (lo_open and v == lo))) or v > hi or (hi_open and v == hi):
        problem = "is out of range"
    if problem is None:
        return v
    if nonzero and not positive:
        small = smallest_positive(unit)
        need = f"a finite {words} of magnitude between {_g(small)} and {_g(magnitude_limit(unit))}{u}"
    else:
        need = _accepted(words, unit, lo, hi, lo_open, hi_open)
    # with an element, the error's own prefix names the field ("element 'pad', field 'thickness': ")
    shown = f"{_g(v)}{u}" if element is not None else f"{field} = {_g(v)}{u}"
    raise ModelError(f"{shown} {problem}; give {need}", element=element, field=field)


def check_array(
    element: str | None,
    field: str,
    values: Any,
    unit: str = "",
    *,
    complex_values: bool = False,
    low: float | None = None,
    high: float | None = None,
    low_open: bool = False,
    high_open: bool = False,
    positive: bool = False,
    nonnegative: bool = False,
    bounded: bool = True,
    what: str | None = None,
) -> np.ndarray:
    """An array of numbers, checked entry by entry like :func:`check_number`; the message names the
    first bad entry by its index (``samples[12, 2] = nan``).

    Parameters
    ----------
    element : str or None
        The element (or analysis) the array belongs to, for the message.
    field : str
        The parameter's name, for the message.
    values : array_like
        The numbers, in ``unit`` (SI).
    unit : str
        Their SI unit, ``""`` for dimensionless numbers.
    complex_values : bool
        Complex numbers (amplitudes): their magnitude is bounded, and ``low`` / ``high`` do not apply.
    low, high : float, optional
        Bounds of the accepted range, in ``unit``.
    low_open, high_open : bool
        Exclude the bound itself.
    positive, nonnegative : bool
        Every entry must be positive (and at least the smallest positive magnitude of the unit) /
        not negative.
    bounded : bool
        Apply the magnitude limit of the unit; False for numbers of arbitrary scale (mode shapes),
        which need only be finite (and within ``low`` / ``high``).
    what : str, optional
        What the entries are, in words and in the plural (``"frequencies"``), for the message.

    Returns
    -------
    ndarray
        The values as a float (or complex) array.

    Raises
    ------
    mechdyn.errors.ModelError
        Naming the element, the array, the first bad index and value, and what is accepted.
    """
    words = what or field.replace("_", " ")
    try:
        a = np.asarray(values, dtype=complex if complex_values else float)
    except (TypeError, ValueError):
        raise ModelError(
            f"{field} = {values!r} is not an array of numbers; give finite {words} values in SI"
            + (f" ({unit})" if unit else ""),
            element=element,
            field=field,
        ) from None
    cap = magnitude_limit(unit) if bounded else math.inf
    if complex_values:
        bad = ~np.isfinite(a) | (np.abs(np.where(np.isfinite(a), a, 0)) > cap)
    else:
        lo, hi, lo_open, hi_open = _bounds(unit, low, high, low_open, high_open, positive, nonnegative)
        if not bounded and high is None:
            hi = math.inf
        with np.errstate(invalid="ignore"):
            bad = ~np.isfinite(a)
            bad |= np.abs(a) > cap
            if lo is not None:
                bad |= (a < lo) | ((a == lo) if lo_open else False)
            bad |= (a > hi) | ((a == hi) if hi_open else False)
    if not bad.any():
        return a
    k = tuple(int(i) for i in np.argwhere(bad)[0])
    index = ", ".join(map(str, k))
    v = a[k]
    u = f" {unit}" if unit else ""
    if complex_values:
        need = f"finite {words}" + (f" of at most {_g(cap)}{u} in magnitude" if bounded else "")
        problem = "is not finite" if not np.isfinite(v) else "is beyond any machine this package models"
    else:
        need = _accepted(words, unit, lo, hi, lo_open, hi_open, finite_word="finite")
        if not np.isfinite(v):
            problem = "is not finite"
        elif abs(v) > cap:
            problem = "is beyond any machine this package models"
        else:
            problem = "is out of range"
    if k:
        shown = f"{field}[{index}] = {_g(v)}{u}"
    else:  # one number
        shown = f"{_g(v)}{u}" if element is not None else f"{field} = {_g(v)}{u}"
    raise ModelError(f"{shown} {problem}; give {need}", element=element, field=field)


def check_count(
    element: str | None, field: str, value: Any, *, low: int = 1, high: int = 10**7, what: str | None = None
) -> int:
    """A whole number (a count of steps, angles, points or elements) within ``[low, high]``.

    Parameters
    ----------
    element : str or None
        The element (or analysis) the count belongs to, for the message.
    field : str
        The parameter's name, for the message.
    value : int
        The count; a float that is a whole number is accepted.
    low, high : int
        The smallest and the largest count accepted.
    what : str, optional
        What is counted, in words, for the message.

    Returns
    -------
    int
        The count.

    Raises
    ------
    mechdyn.errors.ModelError
        Naming the element, the parameter, the value and the range accepted.
    """
    words = what or field.replace("_", " ")
    whole = (isinstance(value, int | np.integer) and not isinstance(value, bool)) or (
        isinstance(value, float | np.floating) and math.isfinite(value) and float(value).is_integer()
    )
    if whole and low <= int(value) <= high:
        return int(value)
    number = isinstance(value, int | float | np.integer | np.floating) and not isinstance(value, bool)
    shown = _g(value) if number else repr(value)
    problem = "is out of range" if whole else "is not a whole number"
    if element is None:
        shown = f"{field} = {shown}"
    raise ModelError(
        f"{shown} {problem}; give a whole number of {words} between {low} and {high}",
        element=element,
        field=field,
    )
