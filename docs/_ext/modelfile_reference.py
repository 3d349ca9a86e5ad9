"""The model-file reference, generated from the validation schemas so that it cannot drift.

``.. mechdyn-file:: drivetrain`` renders every table of that file type (``[model]``, ``[[disks]]``, …)
with each field's type, unit, whether it is required or its default, its limits and its description,
all read from the pydantic schema that validates the files (:func:`mechdyn.io.modelfile.schema_of`).
A field without a description is a build warning (an error under ``-W``).
"""

from __future__ import annotations

import types
import typing
from typing import Any, Literal, get_args, get_origin

from docutils import nodes
from docutils.statemachine import StringList
from pydantic import BaseModel
from pydantic.fields import FieldInfo
from pydantic_core import PydanticUndefined
from sphinx.util import logging
from sphinx.util.docutils import SphinxDirective
from sphinx.util.nodes import nested_parse_with_titles

logger = logging.getLogger(__name__)


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


def _cell(text: str) -> str:
    return " ".join(text.split()).replace("|", "\\|")


def render(schema: type[BaseModel], file_type: str) -> tuple[list[str], list[str]]:
    """reST lines for every table of ``schema`` (one section each, in file order), and the fields that
    have no description."""
    lines: list[str] = []
    undocumented: list[str] = []

    def table(cls: type[BaseModel], path: str, is_array: bool, field: FieldInfo) -> None:
        rows = []
        subtables = []
        for name, f in cls.model_fields.items():
            sub, sub_is_array = _table_of(f.annotation)
            if sub is not None and sub is not cls:
                subtables.append((f"{path}.{name}", sub, sub_is_array, f))
                continue
            description = f.description or ""
            if not description:
                undocumented.append(f"[{path}] {name}")
            rows.append((name, _type(f.annotation, f.metadata), _default(f), _limits(f), description))
        header = f"[[{path}]]" if is_array else f"[{path}]"
        anchor = f"file-{file_type}-{path.replace('.', '-').replace('_', '-')}"
        lines.extend([f".. _{anchor}:", "", header, "-" * len(header), ""])
        need = "required" if field.is_required() else "optional"
        lines.extend(
            [f"*{need}{'; one table per element' if is_array else ''}.* {_cell(field.description or '')}", ""]
        )
        if rows:
            lines.extend([".. list-table::", "   :header-rows: 1", "   :widths: 20 26 14 40", ""])
            lines.extend(["   * - field", "     - type", "     - default", "     - meaning"])
            for name, kind, default, limits, description in rows:
                shown = f"{kind}, {limits}" if limits else kind
                lines.extend(
                    [
                        f"   * - ``{name}``",
                        f"     - {_cell(shown)}",
                        f"     - {default}",
                        f"     - {_cell(description) or '—'}",
                    ]
                )
            lines.append("")
        for sub_path, sub, sub_is_array, f in subtables:
            table(sub, sub_path, sub_is_array, f)

    for name, field in schema.model_fields.items():
        sub, is_array = _table_of(field.annotation)
        if sub is not None:
            table(sub, name, is_array, field)
            continue
        # a table of named values (e.g. a mechanism's [points]: name = [x, y])
        if not field.description:
            undocumented.append(f"[{name}]")
        header = f"[{name}]"
        anchor = f"file-{file_type}-{name.replace('_', '-')}"
        need = "required" if field.is_required() else "optional"
        lines.extend([f".. _{anchor}:", "", header, "-" * len(header), ""])
        lines.extend([f"*{need}.* {_cell(field.description or '')}", ""])
        value = get_args(_unwrap(field.annotation)[0])
        shown = _type(value[1]) if len(value) == 2 else _type(field.annotation)
        lines.extend([f"Each entry is ``name = value``, the value {shown}.", ""])
    return lines, undocumented


class ModelFileDirective(SphinxDirective):
    """``.. mechdyn-file:: TYPE``: the reference of one model-file type."""

    required_arguments = 1
    has_content = False

    def run(self) -> list[nodes.Node]:
        from mechdyn.io.modelfile import schema_of

        file_type = self.arguments[0]
        schema = schema_of(file_type)
        lines, undocumented = render(schema, file_type)
        for what in undocumented:
            logger.warning(
                "model-file reference: %s of %r has no description (add a docstring under the field)",
                what,
                file_type,
                location=self.get_location(),
            )
        node = nodes.section()
        node.document = self.state.document
        nested_parse_with_titles(self.state, StringList(lines, source=f"<schema of {file_type}>"), node)
        return node.children


def setup(app: Any) -> dict[str, Any]:
    app.add_directive("mechdyn-file", ModelFileDirective)
    return {"version": "1", "parallel_read_safe": True}
