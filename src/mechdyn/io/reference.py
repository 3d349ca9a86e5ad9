"""The model-file reference, read from the pydantic schemas that validate the files, so that it
cannot drift: every table of a file type (``[model]``, ``[[disks]]``, …) with each field's type,
unit, default or whether it is required, its limits and its meaning (the docstring under the field).

The documentation renders it (``docs/_ext/modelfile_reference.py``) and ``mechdyn fields TYPE``
prints it.
"""

from __future__ import annotations

import types
import typing
from dataclasses import dataclass, field
from typing import Any, Literal, get_args, get_origin

from pydantic import BaseModel
from pydantic.fields import FieldInfo
from pydantic_core import PydanticUndefined

__all__ = ["FieldRow", "FileTable", "reference"]


@dataclass(frozen=True)
class FieldRow:
    """One field of a table: its ``name``, ``kind`` (how it is written, with its unit and limits),
    ``default`` (``**required**``, ``optional`` or the value) and ``meaning``. Literal values are
    marked as reST literals (````"x"````)."""

    name: str
    kind: str
    default: str
    meaning: str


@dataclass(frozen=True)
class FileTable:
    """One table of a file type: its dotted ``path``, whether it is an array of tables
    (``[[path]]``), whether it is ``required``, its ``description``, its ``fields``, and for a table of
    named values (a mechanism's ``[points]``) what each value is (``values``)."""

    path: str
    is_array: bool
    required: bool
    description: str
    fields: list[FieldRow] = field(default_factory=list)
    values: str = ""

    @property
    def header(self) -> str:
        """``[path]`` or ``[[path]]``."""
        return f"[[{self.path}]]" if self.is_array else f"[{self.path}]"


def _unwrap(annotation: Any) -> tuple[Any, list[Any]]:
    """The annotation without ``Annotated``, and its metadata."""
    metadata: list[Any] = []
    while get_origin(annotation) is typing.Annotated:
        args = get_args(annotation)
        annotation, metadata = args[0], [*metadata, *args[1:]]
    return annotation, metadata


def _union(annotation: Any) -> list[Any] | None:
    if get_origin(annotation) in (typing.Union, types.UnionType):
        return list(get_args(annotation))
    return None


def _table_of(annotation: Any) -> tuple[type[BaseModel] | None, bool]:
    """The schema of a table field and whether it is an array of tables (``[[name]]``)."""
    annotation, _ = _unwrap(annotation)
    options = _union(annotation) or [annotation]
    for a in options:
        a, _ = _unwrap(a)
        if isinstance(a, type) and issubclass(a, BaseModel):
            return a, False
        if get_origin(a) is list:
            (item,) = get_args(a)
            item, _ = _unwrap(item)
            if isinstance(item, type) and issubclass(item, BaseModel):
                return item, True
    return None, False


def _unit(metadata: list[Any]) -> str | None:
    for m in metadata:
        unit = getattr(m, "unit", None)
        if isinstance(unit, str):
            return unit
    return None


def _shown_unit(unit: str) -> str:
    from mechdyn.units import ureg

    if unit in ("", "1", "dimensionless"):
        return "dimensionless"
    return f"{ureg.Unit(unit):~P}"


def _type(annotation: Any, extra: list[Any] | None = None) -> str:
    """How the value is written in a file, in words, with its unit (``extra``: metadata pydantic moved
    from the annotation to the field)."""
    annotation, metadata = _unwrap(annotation)
    unit = _unit([*metadata, *(extra or [])])
    if unit is not None:
        shown = _shown_unit(unit)
        return "number (dimensionless)" if shown == "dimensionless" else f"quantity in {shown}"
    options = _union(annotation)
    if options is not None:
        kept = [o for o in options if o is not type(None)]
        return " or ".join(dict.fromkeys(_type(o) for o in kept))
    origin = get_origin(annotation)
    if origin is Literal:
        return "one of " + ", ".join(
            f'``"{v}"``' if isinstance(v, str) else f"``{v}``" for v in get_args(annotation)
        )
    if origin is tuple:
        args = get_args(annotation)
        if len(args) == 2 and args[1] is Ellipsis:
            return f"array of {_type(args[0])}"
        kinds = list(dict.fromkeys(_type(a) for a in args))
        return f"array of {len(args)} × {kinds[0]}" if len(kinds) == 1 else "array [" + ", ".join(kinds) + "]"
    if origin is list:
        return f"array of {_type(get_args(annotation)[0])}"
    if origin is dict:
        return "table"
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return "table"
    names = {float: "number", int: "integer", str: "string", bool: "true or false", Any: "any value"}
    return names.get(annotation, getattr(annotation, "__name__", str(annotation)))


def _limits(field: FieldInfo) -> str:
    words = {"ge": "≥", "gt": ">", "le": "≤", "lt": "<", "min_length": "at least", "max_length": "at most"}
    out = []
    for m in field.metadata:
        for attr, word in words.items():
            value = getattr(m, attr, None)
            if value is not None:
                out.append(f"{word} {value:g}" if isinstance(value, float) else f"{word} {value}")
    return ", ".join(out)


def _default(field: FieldInfo) -> str:
    if field.is_required():
        return "**required**"
    if field.default_factory is not None:
        value = field.default_factory()  # type: ignore[call-arg]
    else:
        value = field.default
    if value is None or value is PydanticUndefined:
        return "optional"
    if isinstance(value, BaseModel):
        return "optional"
    if isinstance(value, str):
        return f'``"{value}"``'
    if isinstance(value, bool):
        return f"``{str(value).lower()}``"
    return f"``{value!r}``"


def _text(text: str) -> str:
    return " ".join(text.split())


def reference(file_type: str) -> tuple[list[FileTable], list[str]]:
    """Every table of a file type, in file order, and the fields that have no description.

    Parameters
    ----------
    file_type : str
        A model type (``"drivetrain"``, ``"mechanism"``, …) or ``"study"``.

    Raises
    ------
    KeyError
        For an unknown type, naming the known ones (:func:`mechdyn.io.modelfile.schema_of`).
    """
    from mechdyn.io.modelfile import schema_of

    schema = schema_of(file_type)
    tables: list[FileTable] = []
    undocumented: list[str] = []

    def table(cls: type[BaseModel], path: str, is_array: bool, f: FieldInfo) -> None:
        rows = []
        subtables = []
        for name, sf in cls.model_fields.items():
            sub, sub_is_array = _table_of(sf.annotation)
            if sub is not None and sub is not cls:
                subtables.append((f"{path}.{name}", sub, sub_is_array, sf))
                continue
            if not sf.description:
                undocumented.append(f"[{path}] {name}")
            kind, limits = _type(sf.annotation, sf.metadata), _limits(sf)
            rows.append(
                FieldRow(
                    name, f"{kind}, {limits}" if limits else kind, _default(sf), _text(sf.description or "")
                )
            )
        tables.append(FileTable(path, is_array, f.is_required(), _text(f.description or ""), rows))
        for sub_path, sub, sub_is_array, sf in subtables:
            table(sub, sub_path, sub_is_array, sf)

    for name, f in schema.model_fields.items():
        sub, is_array = _table_of(f.annotation)
        if sub is not None:
            table(sub, name, is_array, f)
            continue
        # a table of named values (e.g. a mechanism's [points]: name = [x, y])
        if not f.description:
            undocumented.append(f"[{name}]")
        value = get_args(_unwrap(f.annotation)[0])
        shown = _type(value[1]) if len(value) == 2 else _type(f.annotation)
        tables.append(FileTable(name, False, f.is_required(), _text(f.description or ""), values=shown))
    return tables, undocumented
