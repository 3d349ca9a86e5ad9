"""How a study's tables write what they hold, by the rules the summaries follow.

- Every number is written on its own by the one rule of :mod:`mechdyn.numbers` (five significant
  digits), in the table's cells (:func:`table`: :attr:`mechdyn.results.Table.per_value`) and in its
  sentences (:func:`number`): never a format a column shares, which would show an output's change of
  a few millionths beside one of 40 % as 0.00.
- An output is named in words as a summary names its key (``displacement_max_m`` → ``displacement
  max``: :attr:`Watched.words <mechdyn.studies.outputs.Watched.words>`), in the unit its study file
  gives it, else in the unit its size reads best in (:meth:`Watched.readable
  <mechdyn.studies.outputs.Watched.readable>`, by :func:`mechdyn.units.readable_unit`, the choice
  the summaries and the plots make).
- A value the study file gives (a level, a limit, a tolerance) keeps its digits as written, never
  fewer than three significant ones: :func:`given`.
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING, Any

from mechdyn.numbers import DIGITS, number_text
from mechdyn.results import Table

if TYPE_CHECKING:
    from mechdyn.studies.parameters import Parameter

__all__ = [
    "LEAST_DIGITS",
    "MEASURE_DIGITS",
    "given",
    "number",
    "parameter_text",
    "percent",
    "signed",
    "significant",
    "table",
    "unit_text",
]

LEAST_DIGITS = 3
"""No number a study's table shows has fewer significant digits than this."""

MEASURE_DIGITS = 3
"""Significant digits of a first-order measure or a relative difference (``3.64e-17``): its further
digits are round-off."""


def table(title: str, columns: list[str], rows: list[list[Any]], note: str = "") -> Table:
    """A study's table, each of its numbers written on its own (:attr:`Table.per_value
    <mechdyn.results.Table.per_value>`).

    Parameters
    ----------
    title : str
    columns : list of str
        Headers, each output's with its unit in brackets.
    rows : list of list
        Numbers in the unit of their column (or row), text, or None for none.
    note : str
        A sentence under the table.
    """
    return Table(title, columns, rows, note, per_value=True)


def number(value: float | None, digits: int = DIGITS) -> str:
    """A number computed by the study, inside a sentence of a table (``broken by 0.10540 tonf``), by
    the rule a cell is written by (:func:`mechdyn.numbers.number_text`); ``"—"`` for none.

    Parameters
    ----------
    value : float or None
        The number, in the unit the sentence names.
    digits : int
        Significant digits (at least :data:`LEAST_DIGITS`): fewer than five for a measure whose
        further digits are round-off, such as a first-order residual.
    """
    if value is None:
        return "—"
    return number_text(float(value), digits=max(digits, LEAST_DIGITS))


def signed(value: float | None, digits: int = DIGITS) -> str:
    """:func:`number` with its sign always written (a change, a rank correlation): ``+0.571``.

    Parameters
    ----------
    value : float or None
        The number.
    digits : int
        Significant digits.
    """
    text = number(value, digits)
    return text if text.startswith("-") or text in ("—", "0") else "+" + text


def significant(text: str) -> int:
    """The significant digits a number is written with: ``"1496.3"`` 5, ``"0.045"`` 2, ``"2.1e-16"``
    2, ``"1805450"`` 7.

    Parameters
    ----------
    text : str
        A number as written.
    """
    mantissa = text.lstrip("+-").split("e")[0].split("E")[0]
    return len(mantissa.replace(".", "").lstrip("0"))


def given(value: float) -> str:
    """A value as a study file gives it (a level, a limit, a tolerance): its digits as written, up to
    six, but never fewer than :data:`LEAST_DIGITS` significant ones; a whole number as it is.

    Parameters
    ----------
    value : float
        The value, in the unit the file writes it in.

    Examples
    --------
    >>> from mechdyn.studies.cells import given
    >>> given(1496.3), given(0.045), given(15.0), given(4.05e8)
    ('1496.3', '0.0450', '15', '4.05e+08')
    """
    text = f"{value:.6g}"
    if ("." in text or "e" in text) and significant(text) < LEAST_DIGITS:
        text = f"{value:#.{LEAST_DIGITS}g}"
    return text


def percent(value: float) -> str:
    """A level's change from the base in %, signed, as the study file gives it: ``-10 %``,
    ``+2.50 %``.

    Parameters
    ----------
    value : float
        The change, in %.
    """
    return ("+" if value > 0 else "") + f"{given(value)} %"


def parameter_text(p: Parameter, value: float) -> str:
    """A parameter's value as its study file would give it: a choice by its name, a whole number as
    the number, a quantity by :func:`given` in the file's unit (``"0.0450"``, ``"69.12 mm"``).

    Parameters
    ----------
    p : Parameter
        The parameter.
    value : float
        Its value, SI (a choice: the index of the choice).
    """
    if p.choices or p.integer:
        return p.shown(value)
    return f"{given(value / p.factor)} {p.unit}".strip()


# how pint writes a unit against how a reader writes it
_UNIT_SIGNS = (("*", "·"), ("^2", "²"), ("^3", "³"))


def unit_text(unit: str) -> str:
    """A unit as pint reads it, written for a reader: ``"N*m"`` as ``"N·m"``, ``"kg*m^2"`` as
    ``"kg·m²"``, ``"um"`` as ``"µm"``; ``""`` for a pure number (``"1"``).

    Parameters
    ----------
    unit : str
        A unit as pint reads it.
    """
    from mechdyn.units import SHOWN_UNITS

    if unit in SHOWN_UNITS:
        return SHOWN_UNITS[unit]
    for pint_sign, sign in _UNIT_SIGNS:
        unit = unit.replace(pint_sign, sign)
    return re.sub(r"\bum\b", "µm", unit)
