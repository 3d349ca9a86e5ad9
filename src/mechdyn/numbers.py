"""How a number is written for a reader: one rule for the terminal, the reports and the dashboard.

Each value is written on its own with :data:`DIGITS` significant digits: fixed point from 10⁻³ to
10⁷ (every digit of a whole number up to there: 1805450, not 1.8055e+06), exponents beyond; zero as
``0``, a negative zero without its sign, a value that is not finite as ``—``. A column of one
quantity (a table without a unit column) may share one format instead, so that its decimals line
up: :func:`column_format`.
"""

from __future__ import annotations

import math
from typing import Any

__all__ = ["DIGITS", "column_format", "is_number", "number_text"]

DIGITS = 5
"""Significant digits of a value written on its own."""

# values below this fraction of a column's largest are shown as near zero, not given digits of their own
_MATTERS = 1e-3


def is_number(v: Any) -> bool:
    """Whether ``v`` is a number to format (int, float or a NumPy scalar; not a bool).

    Parameters
    ----------
    v : any
        A table cell.
    """
    if isinstance(v, bool):
        return False
    return isinstance(v, (int, float)) or type(v).__module__ == "numpy"


def _no_negative_zero(text: str) -> str:
    """``-0``, ``-0.000`` and ``-0.0000e+00`` are zero: written without the sign."""
    mantissa = text[1:].split("e")[0]
    return text[1:] if text.startswith("-") and not mantissa.strip("0.") else text


def number_text(v: float, spec: str | None = None, *, digits: int = DIGITS) -> str:
    """One number as text.

    Parameters
    ----------
    v : float
        The value, in the unit it is shown in.
    spec : str, optional
        A column's format (:func:`column_format`); by default the value is written on its own.
    digits : int
        Significant digits of a value written on its own.

    Returns
    -------
    str
        ``"26.762"``, ``"0.0040369"``, ``"1805450"``, ``"6.8403e-06"``; ``"—"`` when not finite.

    Examples
    --------
    >>> from mechdyn.numbers import number_text
    >>> number_text(1496.3), number_text(6.84031e-6), number_text(-0.0)
    ('1496.3', '6.8403e-06', '0')
    """
    v = float(v)
    if not math.isfinite(v):
        return "—"
    if spec is None:
        a = abs(v)
        if a == 0:
            return "0"
        if 1e-3 <= a < 1e7:
            spec = f".{max(0, digits - 1 - math.floor(math.log10(a)))}f"
        else:
            spec = f".{digits - 1}e"
    return _no_negative_zero(format(v, spec))


def column_format(values: list[Any]) -> str | None:
    """One number format for a column of one quantity: fixed point with four significant digits for
    the smallest magnitude that matters (at least a thousandth of the largest; smaller ones show as
    near zero), and with two of the column's spread where its values differ only further on (a
    stroke of 1495.3 mm beside its limit of 1496.3 ± 1 mm), unless the largest would then need more
    than nine digits (then exponents for the whole column). None when the column holds anything but
    numbers (each row is then another quantity, written on its own).

    Parameters
    ----------
    values : list
        The column's cells.
    """
    numbers = [float(v) for v in values if is_number(v) and math.isfinite(float(v)) and _is_float(v)]
    if not numbers or any(not (is_number(v) or v is None) for v in values):
        return None
    largest = max(abs(x) for x in numbers)
    if largest == 0:
        return ".0f"
    smallest = min(abs(x) for x in numbers if abs(x) >= _MATTERS * largest)
    decimals = max(0, 3 - math.floor(math.log10(smallest)))
    spread = max(numbers) - min(numbers)
    if 0 < spread:  # values that differ only beyond four digits still read apart (1495.3 and 1496.3)
        decimals = max(decimals, min(6, 1 - math.floor(math.log10(spread))))
    width = math.floor(math.log10(largest)) + 1 + decimals
    if largest < 1e7 and width <= 9 and decimals <= 6:
        return f".{decimals}f"
    return ".4e"


def _is_float(v: Any) -> bool:
    return isinstance(v, float) or (is_number(v) and "float" in type(v).__name__)
