"""Commented model-file templates, written from the schemas that validate the files (``mechdyn new``).

A template names every table and field of its file type, in file order, each with a comment giving
its meaning, its type and unit, and whether it is required or its default. The fields of a small
sound example model (a two-disk drivetrain, a four-bar, a machine on four mounts, …; see
:mod:`mechdyn.io.template_examples`) are written as values with their units, so that the template
loads and its analysis runs as written; every other field is commented out with its default, or with
an example value where it has none, ready to be uncommented.

The walk over the schema is the model-file reference's (:func:`mechdyn.io.reference.schema_tables`),
so a field added to a schema appears in the templates, the reference and ``mechdyn fields`` at once.
"""

from __future__ import annotations

import re
import textwrap
from collections.abc import Mapping, Sequence
from typing import Any, Literal, get_args, get_origin

from pydantic import BaseModel
from pydantic.fields import FieldInfo
from pydantic_core import PydanticUndefined

from mechdyn.io.reference import (
    SchemaTable,
    _limits,
    _type,
    _union,
    _unit,
    _unwrap,
    named_value_annotation,
    schema_tables,
)
from mechdyn.io.writing import _key, quantity_text, toml_value

__all__ = ["template"]

WIDTH = 100
"""Lines of a template are wrapped at this many characters."""

_ROLE = re.compile(r":[a-z:]+:`~?([^`]+)`")  # a reST role, :mod:`x`, shown as x


# -- defaults as values -----------------------------------------------------------------------------


def _value_for(annotation: Any, value: Any, extra: list[Any] | None = None) -> Any:
    """A schema default as the value a file would write (quantities with their unit)."""
    inner, metadata = _unwrap(annotation)
    unit = _unit([*metadata, *(extra or [])])
    if unit is not None and isinstance(value, int | float) and not isinstance(value, bool):
        return quantity_text(value, unit, exact=False)
    options = _union(inner)
    if options is not None:
        kept = [o for o in options if o is not type(None)]
        for o in kept:  # the branch the value belongs to
            o_inner, _ = _unwrap(o)
            if get_origin(o_inner) is Literal and value in get_args(o_inner):
                return value
        for o in kept:
            o_inner, o_meta = _unwrap(o)
            if _unit(o_meta) is not None and isinstance(value, int | float):
                return _value_for(o, value)
        return _value_for(kept[0], value) if kept else value
    origin = get_origin(inner)
    if origin in (tuple, list) and isinstance(value, tuple | list):
        args = get_args(inner)
        if origin is tuple and args and args[-1] is not Ellipsis and len(args) == len(value):
            return [_value_for(a, v) for a, v in zip(args, value, strict=True)]
        element = args[0] if args else Any
        return [_value_for(element, v) for v in value]
    if isinstance(value, BaseModel):
        return None  # a default table: its fields carry the defaults
    return value


def _default_of(f: FieldInfo) -> Any:
    """The default of a field (None when it has none, or when it is required)."""
    if f.is_required():
        return None
    value = f.default_factory() if f.default_factory is not None else f.default  # type: ignore[call-arg]
    return None if value is PydanticUndefined else value


def _placeholder(annotation: Any, extra: list[Any] | None = None) -> Any:
    """A value to fill in, shaped as the field's type, for a field with neither default nor example."""
    inner, metadata = _unwrap(annotation)
    unit = _unit([*metadata, *(extra or [])])
    if unit is not None:
        return f"… {unit}".rstrip() if unit not in ("", "1") else "…"
    options = _union(inner)
    if options is not None:
        kept = [o for o in options if o is not type(None)]
        return _placeholder(kept[0]) if kept else "…"
    origin = get_origin(inner)
    if origin is Literal:
        return get_args(inner)[0]
    if origin is tuple:
        args = get_args(inner)
        if args and args[-1] is Ellipsis:
            return [_placeholder(args[0])]
        return [_placeholder(a) for a in args]
    if origin is list:
        return [_placeholder(get_args(inner)[0])]
    if origin is dict:
        return {}
    if inner is bool:
        return False
    return "…"


# -- the template ---------------------------------------------------------------------------------


def _comment(text: str, indent: str = "") -> list[str]:
    """``text`` as wrapped comment lines (reST literals shown plain)."""
    plain = " ".join(_ROLE.sub(r"\1", text).replace("``", "").replace("**", "").split())
    if not plain:
        return []
    prefix = f"{indent}# "
    return textwrap.wrap(
        plain, WIDTH, initial_indent=prefix, subsequent_indent=prefix, break_on_hyphens=False
    )


def _status(f: FieldInfo, shown_default: Any) -> str:
    """``(type and unit; required | default …)`` of a field."""
    kind = _type(f.annotation, f.metadata)
    limits = _limits(f)
    kind = (f"{kind}, {limits}" if limits else kind).replace("``", "")
    if f.is_required():
        return f"({kind}; required)"
    if shown_default is None:
        return f"({kind}; optional, no default)"
    quantity = kind.startswith("quantity") or ("quantity" in kind and isinstance(shown_default, list))
    shown = toml_value(shown_default)
    if quantity:  # "0 m" rather than "\"0 m\""
        shown = shown.replace('"', "")
    return f"({kind}; default {shown})"


class _Writer:
    """Writes one template: the tables of a schema with the example's values."""

    def __init__(self, file_type: str, example: Any, path: str) -> None:
        self.file_type = file_type
        self.path = path
        self.example = example
        self.lines: list[str] = []

    def note(self, path: str) -> list[str]:
        text = self.example.notes.get(path, "") if self.example is not None else ""
        return _comment(text)

    def hints(self, path: str) -> Mapping[str, Any]:
        if self.example is None:
            return {}
        found = self.example.hints.get(path, {})
        return found[0] if isinstance(found, list) and found else found

    def table(self, t: SchemaTable, data: Any, active: bool, full: bool, top: bool) -> None:
        """Write table ``t``: ``data`` its values (a mapping), ``active`` whether it is written as
        values (else commented out), ``full`` whether each field gets its comment."""
        c = "" if active else "# "
        out = self.lines
        if full:
            out.append("")
            if top:
                out.append("# " + "-" * (WIDTH - 2))
            need = "required" if t.info.is_required() else "optional"
            each = "; one table per element, repeat it for each" if t.is_array else ""
            described = f": {t.info.description}" if t.info.description else ""
            out += _comment(f"{t.header} ({need}{each}){described}")
            out += self.note(t.path)
            if top:
                out.append("# " + "-" * (WIDTH - 2))
        elif not active:
            return
        else:
            out.append("")
        out.append(f"{c}{t.header}")
        if t.schema is None:  # a table of named values
            entries = data if isinstance(data, Mapping) else {}
            if full:
                out += _comment(f"Each entry: name = value, the value {_type(named_value_annotation(t))}")
            for key, value in entries.items():
                out.append(f"{c}{_key(key)} = {toml_value(value)}")
            return
        values = data if isinstance(data, Mapping) else {}
        hints = self.hints(t.path)
        fields = list(t.fields)
        if t.path == "model":  # the file type first: it says what the rest is
            fields.sort(key=lambda nf: nf[0] != "type")
        for name, f in fields:
            default = _value_for(f.annotation, _default_of(f), f.metadata)
            if active and name in values:
                line = f"{name} = {toml_value(values[name])}"
            elif name in hints:
                line = f"# {name} = {toml_value(hints[name])}"
            elif default is not None:
                line = f"# {name} = {toml_value(default)}"
            elif not full:
                continue
            else:
                line = f"# {name} = {toml_value(_placeholder(f.annotation, f.metadata))}"
            if full:
                out += _comment(f.description or "")
                out += _comment(_status(f, default))
            elif line.startswith("#"):
                continue
            out.append(line)
        for child in t.children:
            self.child(child, values.get(child.name) if active else None, active, full)

    def child(self, t: SchemaTable, data: Any, parent_active: bool, full: bool) -> None:
        if t.is_array:
            rows = list(data) if isinstance(data, Sequence) and not isinstance(data, str) else []
            if parent_active and rows:
                for i, row in enumerate(rows):
                    self.table(t, row, True, full and i == 0, False)
                return
            if full:
                self.table(t, self.hints(t.path), False, True, False)
            return
        if parent_active and isinstance(data, Mapping):
            self.table(t, data, True, full, False)
        elif full:
            self.table(t, self.hints(t.path), False, True, False)

    def write(self) -> str:
        ex = self.example
        data = ex.model if ex is not None else {}
        out = self.lines
        kind = "study" if self.file_type == "study" else f'"{self.file_type}" model'
        out += _comment(f"A {kind} file, written by `mechdyn new {self.file_type}`.")
        if ex is not None and ex.intro:
            out += _comment(ex.intro)
        out += _comment(
            'Every quantity is a string with its unit ("12 mm", "80.8 GPa", "1480 rpm"); mechdyn converts '
            "it to SI. Each field has a comment with its meaning, its type and unit, and whether it is "
            "required or its default. Fields and tables that are commented out take their default (or "
            "are absent): uncomment one to give it. "
            f"`mechdyn fields {self.file_type}` prints the same reference."
        )
        if ex is not None and ex.run:
            out.append("#")
            out += _comment(f"Run it: {ex.run.replace('FILE', self.path)}")
        for t in schema_tables(self.file_type):
            value = data.get(t.name)
            if t.is_array:
                rows = list(value) if isinstance(value, Sequence) and not isinstance(value, str) else []
                if rows:
                    for i, row in enumerate(rows):
                        self.table(t, row, True, i == 0, i == 0)
                else:
                    self.table(t, self.hints(t.path), False, True, True)
            elif value is not None:
                self.table(t, value, True, True, True)
            else:
                self.table(t, self.hints(t.path), False, True, True)
        return "\n".join(out).rstrip() + "\n"


def template(file_type: str, path: str = "FILE") -> str:
    """A commented template of a model file of ``file_type`` that loads and runs as written.

    Parameters
    ----------
    file_type : str
        A model type (``"drivetrain"``, ``"mechanism"``, ``"support"``, ``"mount"``, ``"gear_pair"``,
        …) or ``"study"``; ``mechdyn fields`` lists them.
    path : str
        The file's name, shown in the command that runs it.

    Returns
    -------
    str
        The TOML text: every table and field of the type, each with its meaning, unit and default;
        a small sound example model given as values with their units (SI or any unit pint reads),
        everything else commented out with its default.

    Raises
    ------
    KeyError
        For an unknown type, naming the known ones.

    Examples
    --------
    >>> from mechdyn.io.template import template
    >>> text = template("drivetrain")
    >>> 'type = "drivetrain"' in text and "[[disks]]" in text
    True
    """
    from mechdyn.io.template_examples import EXAMPLES

    schema_tables(file_type)  # an unknown type: the KeyError naming the known ones
    return _Writer(file_type, EXAMPLES.get(file_type), path).write()
