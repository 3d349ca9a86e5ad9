"""Writing model files: values as TOML text, quantities with their SI unit, tables in file order.

:func:`toml_value` and :func:`quantity_text` write values so that reading them back gives the same
floats (``repr`` of each, with its SI unit); :class:`TomlDocument` collects the tables of a file. The
templates of ``mechdyn new`` (:mod:`mechdyn.io.template`) and :func:`mechdyn.save` use them.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

__all__ = ["TomlDocument", "quantity_text", "toml_value"]


# -- TOML values --------------------------------------------------------------------------------------


def toml_value(value: Any) -> str:
    """A Python value as a TOML value: a string quoted, a float as its ``repr`` (exact), an array or a
    table inline.

    Parameters
    ----------
    value : str, bool, int, float, sequence or mapping
        The value; floats are written with ``repr`` so that reading them back gives the same float.

    Returns
    -------
    str
        Its TOML text.
    """
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)  # a JSON string is a TOML basic string
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ValueError(f"{value!r} has no place in a model file; give a finite number")
        return repr(float(value))  # a NumPy float's repr names its type
    if hasattr(value, "tolist") and not isinstance(value, str | bytes):  # a NumPy array or scalar
        return toml_value(value.tolist())
    if isinstance(value, Mapping):
        inner = ", ".join(f"{_key(k)} = {toml_value(v)}" for k, v in value.items())
        return "{ " + inner + " }" if inner else "{}"
    if isinstance(value, Sequence):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    raise TypeError(f"{type(value).__name__} {value!r} cannot be written to TOML")


def _key(key: str) -> str:
    """A TOML key: bare when it can be, else quoted."""
    bare = key and all(c.isascii() and (c.isalnum() or c in "-_") for c in key)
    return key if bare else json.dumps(key, ensure_ascii=False)


def quantity_text(value: float, unit: str, *, exact: bool = True) -> str | float:
    """An SI value as a model file writes it: ``"0.05 kg*m^2"``, or the bare number when ``unit`` is
    dimensionless.

    Parameters
    ----------
    value : float
        The magnitude in ``unit`` (SI).
    unit : str
        Its unit as pint spells it (``"N*m/rad"``), ``""`` for a dimensionless number.
    exact : bool
        Write ``repr(value)`` in ``unit``, so that reading it back gives the same float (what
        :func:`mechdyn.save` writes); else a short display form (angles in degrees, speeds in rpm).

    Returns
    -------
    str or float
        The quantity string (a float for a dimensionless value).
    """
    value = float(value)
    if unit in ("", "1", "dimensionless"):
        return value
    if exact:
        return f"{value!r} {unit}"
    shown = {"rad": "deg", "rad/s": "rpm"}.get(unit)
    if unit == "Pa" and abs(value) >= 1e6:
        shown = "GPa" if abs(value) >= 1e9 else "MPa"
    if shown is None or value == 0.0:
        return f"{_short(value)} {unit}"
    from mechdyn.units import convert

    return f"{_short(float(convert(value, unit, shown)))} {shown}"


def _short(x: float) -> str:
    """A number in at most 12 significant digits, rounding away the last bits of a unit conversion."""
    return f"{float(f'{x:.10g}'):.12g}"


@dataclass
class TomlDocument:
    """A TOML file being written: comment lines and tables, in order.

    Attributes
    ----------
    lines : list of str
        The text so far, one line each.
    """

    lines: list[str] = field(default_factory=list)

    def comment(self, text: str) -> None:
        """Add comment lines (each line of ``text`` after ``# ``).

        Parameters
        ----------
        text : str
            The comment; several lines allowed.
        """
        self.lines += [f"# {line}".rstrip() for line in text.splitlines()]

    def table(self, header: str, values: Mapping[str, Any], *, array: bool = False, note: str = "") -> None:
        """Add a table: ``[header]`` (``[[header]]`` for an ``array`` of tables) and its values; a value
        None is left out.

        Parameters
        ----------
        header : str
            The table's dotted path (``"meshes"``, ``"excitation.rotors"``).
        values : mapping
            Its fields, written in order with :func:`toml_value`.
        array : bool
            One table of an array of tables.
        note : str
            A comment written under the header (where a value came from).
        """
        if self.lines:
            self.lines.append("")
        self.lines.append(f"[[{header}]]" if array else f"[{header}]")
        if note:
            self.comment(note)
        self.lines += [f"{_key(k)} = {toml_value(v)}" for k, v in values.items() if v is not None]

    def text(self) -> str:
        """The file's text, ending with a newline."""
        return "\n".join(self.lines) + "\n"
