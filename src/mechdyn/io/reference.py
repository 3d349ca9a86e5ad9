"""The model-file reference, read from the pydantic schemas that validate the files, so that it
cannot drift: every table of a file type (``[model]``, ``[[disks]]``, …) with each field's type,
unit, default or whether it is required, its limits and its meaning (the docstring under the field).

The documentation renders it (``docs/_ext/modelfile_reference.py``), ``mechdyn fields TYPE``
prints it, ``mechdyn new TYPE`` writes a template from it (:mod:`mechdyn.io.template`), and
``python -m mechdyn.io.reference --markdown docs/model_files/markdown`` writes it as Markdown pages
readable in the checkout.
"""

from __future__ import annotations

import re
import types
import typing
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal, get_args, get_origin

from pydantic import BaseModel
from pydantic.fields import FieldInfo
from pydantic_core import PydanticUndefined

from mechdyn.io.fields import Check
from mechdyn.io.reference_rows import FieldRow, FileTable

__all__ = [
    "MARKDOWN_FOLDER",
    "FieldRow",
    "FileTable",
    "SchemaTable",
    "markdown",
    "markdown_index",
    "markdown_pages",
    "named_value_annotation",
    "reference",
    "schema_tables",
    "write_markdown",
]


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
    # the field's own metadata, and that of an optional value's type (``Annotated[...] | None``)
    optional = [m for a in _union(field.annotation) or [] for m in _unwrap(a)[1] if isinstance(m, Check)]
    for m in [*field.metadata, *optional]:
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


@dataclass(frozen=True)
class SchemaTable:
    """One table of a file type as the schema declares it, for tools that walk the schema (the
    reference, ``mechdyn new``'s templates).

    Attributes
    ----------
    path : str
        Its dotted path (``gear_pairs.pinion``).
    is_array : bool
        An array of tables (``[[path]]``).
    info : FieldInfo
        The field of the enclosing schema that holds the table (its description, whether required).
    schema : type or None
        The pydantic schema of the table; None for a table of named values (a mechanism's
        ``[points]``).
    fields : list of (str, FieldInfo)
        Its fields that are values, not tables, in file order.
    children : list of SchemaTable
        Its sub-tables (``[response.rayleigh]``, ``[[bolted.layers]]``), in file order.
    """

    path: str
    is_array: bool
    info: FieldInfo
    schema: type[BaseModel] | None
    fields: list[tuple[str, FieldInfo]] = field(default_factory=list)
    children: list[SchemaTable] = field(default_factory=list)

    @property
    def name(self) -> str:
        """The table's own key (the last part of its path)."""
        return self.path.rpartition(".")[2]

    @property
    def header(self) -> str:
        """``[path]`` or ``[[path]]``."""
        return f"[[{self.path}]]" if self.is_array else f"[{self.path}]"


def schema_tables(file_type: str) -> list[SchemaTable]:
    """The tables of a file type as a tree, in file order, read from its schema.

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

    def table(cls: type[BaseModel], path: str, is_array: bool, f: FieldInfo) -> SchemaTable:
        node = SchemaTable(path, is_array, f, cls)
        for name, sf in cls.model_fields.items():
            sub, sub_is_array = _table_of(sf.annotation)
            if sub is not None and sub is not cls:
                node.children.append(table(sub, f"{path}.{name}", sub_is_array, sf))
            else:
                node.fields.append((name, sf))
        return node

    out = []
    for name, f in schema_of(file_type).model_fields.items():
        sub, is_array = _table_of(f.annotation)
        out.append(table(sub, name, is_array, f) if sub is not None else SchemaTable(name, False, f, None))
    return out


def named_value_annotation(t: SchemaTable) -> Any:
    """The annotation of each value of a table of named values (``[points]``: ``name = [x, y]``)."""
    value = get_args(_unwrap(t.info.annotation)[0])
    return value[1] if len(value) == 2 else t.info.annotation


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
    tables: list[FileTable] = []
    undocumented: list[str] = []

    def add(t: SchemaTable) -> None:
        f = t.info
        if t.schema is None:  # a table of named values (e.g. a mechanism's [points]: name = [x, y])
            if not f.description:
                undocumented.append(f"[{t.path}]")
            shown = _type(named_value_annotation(t))
            tables.append(FileTable(t.path, False, f.is_required(), _text(f.description or ""), values=shown))
            return
        rows = []
        for name, sf in t.fields:
            if not sf.description:
                undocumented.append(f"[{t.path}] {name}")
            kind, limits = _type(sf.annotation, sf.metadata), _limits(sf)
            rows.append(
                FieldRow(
                    name, f"{kind}, {limits}" if limits else kind, _default(sf), _text(sf.description or "")
                )
            )
        tables.append(FileTable(t.path, t.is_array, f.is_required(), _text(f.description or ""), rows))
        for child in t.children:
            add(child)

    for t in schema_tables(file_type):
        add(t)
    return tables, undocumented


# -- the reference as Markdown, readable in the checkout ----------------------------------------------

#: Where the generated Markdown lives, relative to the repository root (a folder of its own: the Sphinx
#: pages of the built site are the ``.rst`` files beside it, and a ``.md`` of the same name would clash).
MARKDOWN_FOLDER = "docs/model_files/markdown"

#: The title of each file type's page, in the order of the index.
TITLES = {
    "drivetrain": "Drivetrain files",
    "mechanism": "Mechanism files",
    "planting_mechanism": "Planting-mechanism files",
    "support": "Support files (a machine on its supports)",
    "mount": "Mount files",
    "gear_pair": "Gear-pair files",
    "tooth_pair": "Tooth-pair files",
    "study": "Study files",
}

_REGENERATE = f"python -m mechdyn.io.reference --markdown {MARKDOWN_FOLDER}"

# Sphinx reads every .md under docs/ (myst); ``orphan`` keeps these pages, which no toctree lists, from
# being a build warning. The built site's reference is docs/model_files/<type>.rst.
_FRONT_MATTER = ["---", "orphan: true", "---", ""]

_LITERAL = re.compile(r"``(.+?)``|:[a-z:]+:`(.+?)`|`(.+?)`")
_ESCAPE = str.maketrans({c: "\\" + c for c in "\\*_|$[]"} | {"<": "&lt;", ">": "&gt;"})


def _md(text: str) -> str:
    """reST text (````x````, ``:mod:`x```, ```x```) as Markdown for a table cell or a paragraph:
    literals as code spans, the rest escaped so that ``*``, ``_``, ``|`` and ``$`` stay themselves."""
    out, end = [], 0
    for m in _LITERAL.finditer(text):
        out.append(text[end : m.start()].translate(_ESCAPE))
        code = next(g for g in m.groups() if g is not None).replace("|", "\\|")
        out.append(f"`{code}`")
        end = m.end()
    out.append(text[end:].translate(_ESCAPE))
    return "".join(out)


def _md_default(default: str) -> str:
    return "**required**" if default == "**required**" else _md(default)


def markdown(file_type: str) -> str:
    """The reference of one file type as a Markdown page: every table with each field's type and unit,
    default and meaning (what ``mechdyn fields TYPE`` prints and the built site shows), and for a model
    type the ``[[scatter]]`` and ``[[correlations]]`` every model file may hold
    (:func:`mechdyn.io.scatter.reference_tables`).

    Parameters
    ----------
    file_type : str
        A model type (``"drivetrain"``, ``"mechanism"``, …) or ``"study"``.

    Returns
    -------
    str
        The page, generated: ``python -m mechdyn.io.reference --markdown docs/model_files/markdown``
        writes every type's.
    """
    tables, _ = reference(file_type)
    if file_type != "study":  # every model file may say how its values scatter (mechdyn.io.scatter)
        from mechdyn.io.scatter import reference_tables

        tables += reference_tables()
    title = TITLES.get(file_type, f"{file_type} files")
    first = "a `[study]` table" if file_type == "study" else f'`[model] type = "{file_type}"`'
    lines = [
        *_FRONT_MATTER,
        f"<!-- Generated from the schema that validates the files; do not edit. Regenerate with\n"
        f"     {_REGENERATE}\n"
        "     (tests/test_model_templates.py checks that this page is current). -->",
        "",
        f"# {title}",
        "",
        f'A file with {first}. Every quantity is a string with its unit (`"12 mm"`, `"80.8 GPa"`); a bare '
        "number is refused where a unit is needed. These tables are generated from the schema that "
        "validates the files, so they list exactly what the program accepts.",
        "",
        f"- `mechdyn new {file_type} FILE` writes a commented template of such a file that loads and runs;",
        f"- `mechdyn fields {file_type}` prints this reference in the terminal;",
        "- [every file type](index.md).",
        "",
    ]
    for t in tables:
        need = "required" if t.required else "optional"
        each = ", one table per element" if t.is_array else ""
        lines += [f"## `{t.header}`", "", f"*{need}{each}.* {_md(t.description)}".rstrip(), ""]
        if t.values:
            lines += [f"Each entry is `name = value`, the value {_md(t.values)}.", ""]
            continue
        if t.fields:
            lines += ["| field | type | default | meaning |", "|---|---|---|---|"]
            for f in t.fields:
                meaning = _md(f.meaning) or "—"
                lines.append(f"| `{f.name}` | {_md(f.kind)} | {_md_default(f.default)} | {meaning} |")
            lines.append("")
    return "\n".join(lines)


def _file_types() -> list[str]:
    """Every registered file type, those with a title in :data:`TITLES` first in its order."""
    from mechdyn.io.modelfile import file_types

    known = file_types()
    return [t for t in TITLES if t in known] + [t for t in known if t not in TITLES]


def markdown_index() -> str:
    """The index page of the Markdown reference: one link per file type.

    Returns
    -------
    str
        The page (``index.md`` of :data:`MARKDOWN_FOLDER`).
    """
    types = _file_types()
    lines = [
        *_FRONT_MATTER,
        f"<!-- Generated; do not edit. Regenerate with\n     {_REGENERATE} -->",
        "",
        "# Model-file reference",
        "",
        "Models are TOML files with units in the values. Every file names its type in `[model] type`; a "
        "study file has a `[study]` table instead. Errors in a file name the file, the table, the field, "
        "the value and the fix, and list every problem at once.",
        "",
        "Each page lists every table and field of one file type with its unit, default and meaning, "
        "generated from the schema that validates the files. `mechdyn new TYPE FILE` writes a commented "
        "template that loads and runs; `mechdyn fields TYPE` prints the reference in the terminal.",
        "",
        *[f"- [{TITLES.get(t, t)}]({t}.md): `{t}`" for t in types],
        "",
    ]
    return "\n".join(lines)


def markdown_pages() -> dict[str, str]:
    """Every page of the Markdown reference by file name (``index.md``, ``drivetrain.md``, …).

    Returns
    -------
    dict of str to str
        File name → text.
    """
    pages = {"index.md": markdown_index()}
    for file_type in _file_types():
        pages[f"{file_type}.md"] = markdown(file_type)
    return pages


def write_markdown(folder: str | Path) -> list[Path]:
    """Write the Markdown reference (:func:`markdown_pages`) into ``folder``.

    Parameters
    ----------
    folder : str or Path
        Where to write it (created if missing); :data:`MARKDOWN_FOLDER` in the repository.

    Returns
    -------
    list of Path
        The files written.
    """
    target = Path(folder)
    target.mkdir(parents=True, exist_ok=True)
    written = []
    for name, text in markdown_pages().items():
        path = target / name
        path.write_text(text, encoding="utf-8")
        written.append(path)
    return written


def main(argv: list[str] | None = None) -> int:
    """``python -m mechdyn.io.reference --markdown DIR``: write the Markdown reference.

    Parameters
    ----------
    argv : list of str, optional
        The arguments (default: the command line's).

    Returns
    -------
    int
        The exit status.
    """
    import argparse

    p = argparse.ArgumentParser(
        prog="python -m mechdyn.io.reference",
        description="Write the model-file reference as Markdown, one page per file type.",
    )
    p.add_argument("--markdown", metavar="DIR", required=True, help=f"the folder, e.g. {MARKDOWN_FOLDER}")
    args = p.parse_args(argv)
    for path in write_markdown(args.markdown):
        print(path)
    return 0


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
