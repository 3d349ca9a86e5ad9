"""Reading model files: TOML text → validated schema → immutable model.

A model file names its type in ``[model] type = "..."``; each capability registers its types (a
:class:`mechdyn.registry.ModelType`: builder, schema, model and settings) next to its analyses, and
this module finds them in the registry, naming no capability. Every failure becomes a
:class:`~mechdyn.errors.ModelFileError` naming the file, the table and field, the value and what was
expected.
"""

from __future__ import annotations

import difflib
import hashlib
import tomllib
import warnings
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TypeVar

from pydantic import BaseModel, ValidationError

from mechdyn.errors import ModelError, ModelFileError
from mechdyn.registry import LoadedModel, ModelType, model_types, resolve

__all__ = [
    "SCATTER_TABLES",
    "LoadedModel",
    "ModelSource",
    "field_context",
    "file_types",
    "load",
    "load_model",
    "load_source",
    "load_with_source",
    "read_toml",
    "referenced",
    "register_model_type",
    "schema_of",
    "strip",
    "validate",
]

M = TypeVar("M", bound=BaseModel)

SCATTER_TABLES = ("scatter", "correlations")
"""The top-level tables of a model file that give its scatter (no model type's schema reads them)."""


def register_model_type(name: str, builder: str, schema: str | None = None) -> None:
    """Register a model-file type (the former interface; a thin wrapper of the registry's).

    The same as ``mechdyn.registry.register_model_type(ModelType(name, builder, schema))``: the
    builder's record is both the model and the settings of the :class:`LoadedModel`. A capability
    registers a :class:`mechdyn.registry.ModelType` itself, which can also name the record's model
    attribute, a settings function and a writer.

    Parameters
    ----------
    name : str
        The type as files name it, ``[model] type = name``.
    builder : str
        ``"module:function"`` that turns a :class:`ModelSource` of that type into a loaded model.
    schema : str, optional
        ``"module:Class"``, the pydantic schema of the whole file, for :func:`schema_of` and the
        documentation's model-file reference.

    Raises
    ------
    ValueError
        When another type of that name is registered (a capability's own, say).
    """
    from mechdyn.registry import register_model_type as register

    model_types()  # the capabilities' types first, so that a clash is reported here
    register(ModelType(name, builder, schema))


def _schemas() -> dict[str, str]:
    """File type → ``"module:Class"`` of its schema, for every registered type that has one."""
    return {name: t.schema for name, t in model_types().items() if t.schema is not None}


def file_types() -> list[str]:
    """The file types that have a schema, sorted: the model types and ``"study"``.

    Returns
    -------
    list of str
        What :func:`schema_of`, ``mechdyn fields`` and ``mechdyn new`` take.
    """
    return sorted(_schemas())


def schema_of(file_type: str) -> type[BaseModel]:
    """The pydantic schema that validates a whole file of ``file_type``.

    Parameters
    ----------
    file_type : str
        A model type (``"drivetrain"``, ``"mechanism"``, …) or ``"study"`` for a study file.

    Returns
    -------
    type
        The schema class; its fields are the file's tables.

    Raises
    ------
    KeyError
        For an unknown type, naming the known ones.
    """
    schemas = _schemas()
    if file_type not in schemas:
        raise KeyError(f"no schema for file type {file_type!r}; known: {', '.join(sorted(schemas))}")
    schema: type[BaseModel] = resolve(schemas[file_type])
    return schema


@dataclass(frozen=True)
class ModelSource:
    """The file a model was read from: its path, exact text and SHA-256 of that text.

    Attributes
    ----------
    path, text, sha256 : str
        The file, its text and the SHA-256 of its bytes.
    data : mapping
        The parsed TOML.
    includes : mapping of str → ModelSource
        Files this one refers to (a support's mechanism, a mount file), by resolved path, given in
        memory instead of read from disk: a design study's variant changes values in them without
        writing files (:func:`referenced`).
    """

    path: str
    text: str
    sha256: str
    data: Mapping[str, Any]
    includes: Mapping[str, ModelSource] = field(default_factory=dict)

    @property
    def model_type(self) -> str:
        return str(self.data["model"]["type"])


def read_toml(path: str | Path, what: str = "a .toml model file") -> ModelSource:
    """Read and parse a TOML file; every failure is a ModelFileError naming the file.

    Parameters
    ----------
    path : str or Path
    what : str
        What the file should be, for the error when it is missing (``"a .toml materials file"``).
    """
    p = Path(path)
    if not p.is_file():
        raise ModelFileError(str(p), "", f"no such file; give the path of {what}")
    raw = p.read_bytes()
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ModelFileError(str(p), "", f"not UTF-8 text ({exc}); save the file as UTF-8") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ModelFileError(str(p), "", f"not valid TOML: {exc}") from None
    return ModelSource(str(p), text, hashlib.sha256(raw).hexdigest(), data)


def read(path: str | Path) -> ModelSource:
    """Read and parse a TOML model file without building the model.

    Parameters
    ----------
    path : str or Path
        The model file (TOML).

    Returns
    -------
    ModelSource
        Its path, text, SHA-256 and parsed data, with the files it refers to.
    """
    return read_check(read_toml(path))


def read_check(source: ModelSource) -> ModelSource:
    """Check that parsed TOML is a model file of a known type (its ``[model] type``)."""
    _model_type(source)
    return source


def _model_type(source: ModelSource) -> ModelType:
    """The registered type of a model file, which loads a model; an error lists the types that do."""
    model = source.data.get("model")
    if not isinstance(model, dict):
        raise ModelFileError(
            source.path,
            "[model]",
            'missing; start the file with [model] and its type, e.g. type = "drivetrain"',
        )
    kind = model.get("type")
    loadable = {name: t for name, t in model_types().items() if t.loads}
    if not isinstance(kind, str) or kind not in loadable:
        expected = ", ".join(repr(k) for k in sorted(loadable))
        raise ModelFileError(
            source.path, "[model] → type", f"{kind!r} is not a model type; expected one of {expected}", kind
        )
    return loadable[kind]


def reference_path(source: ModelSource, relative: str) -> str:
    """The path of a file that ``source`` names relative to itself."""
    return str(Path(source.path).parent / relative)


def referenced(source: ModelSource, relative: str) -> ModelSource | None:
    """The model file that ``source`` names (relative to itself): from ``source.includes`` when
    given there, else read from disk; None when there is no such file."""
    path = reference_path(source, relative)
    if path in source.includes:
        return source.includes[path]
    return read(path) if Path(path).is_file() else None


def build_source(source: ModelSource) -> Any:
    """Build the model of a parsed model file (its type's builder's record)."""
    kind = _model_type(source)
    assert kind.builder is not None  # a type without one is not loadable
    builder: Callable[[ModelSource], Any] = resolve(kind.builder)
    return builder(source)


def load_with_source(path: str | Path) -> tuple[Any, ModelSource]:
    """Load a model file and return the model with the :class:`ModelSource` it came from.

    Parameters
    ----------
    path : str or Path
        The model file (TOML).
    """
    source = read(path)
    return build_source(source), source


def load_model(path: str | Path) -> LoadedModel:
    """Load a model file into a :class:`LoadedModel` (one shape for every model type).

    The same as :func:`mechdyn.load`.

    Parameters
    ----------
    path : str or Path
        A TOML model file.

    Returns
    -------
    LoadedModel

    Raises
    ------
    ModelFileError
        As :func:`load`.
    """
    from mechdyn.registry import model_scatter

    loaded = load_source(read(path))
    model_scatter(loaded.source)  # the file's [[scatter]] checked: a path of this model, a valid table
    return loaded


def load_source(source: ModelSource) -> LoadedModel:
    """A :class:`LoadedModel` from a parsed model file (e.g. a study's variant, built in memory).

    One way for every type (:class:`mechdyn.registry.ModelType`): its builder's record, the model
    one attribute of it (or the record), the settings what its settings function reads (or the
    record).
    """
    kind = _model_type(source)
    record = build_source(source)
    model = record if kind.model_attribute is None else getattr(record, kind.model_attribute)
    settings = record if kind.settings is None else resolve(kind.settings)(source, record)
    return LoadedModel(kind.name, model, settings, source)


def load(path: str | Path) -> LoadedModel:
    """Load a model file (TOML with units): the model, its settings and the file, one shape for all.

    Loading validates and builds; it computes no analysis (a support file whose load comes from a
    mechanism runs that mechanism's inverse dynamics when its load is first asked for).

    Parameters
    ----------
    path : str or Path
        A model file whose ``[model]`` table names its ``type`` (e.g. ``"drivetrain"``).

    Returns
    -------
    LoadedModel
        ``.model`` is what the analyses run on (a :class:`mechdyn.drivetrain.Drivetrain`, a
        :class:`mechdyn.mechanism.Mechanism`, a :class:`mechdyn.support.MountedMachine`, ...);
        ``.settings`` is the rest of the file; ``.source`` the file itself; ``.type`` its type;
        ``.scatter`` how the file says its values scatter (its ``[[scatter]]`` rows, a
        :class:`mechdyn.studies.model_scatter.ModelScatter`, or None), which no analysis reads and a
        ``tolerance`` study takes as its default.

    Raises
    ------
    ModelFileError
        With the file, the table and field, the bad value and what was expected (a ``[[scatter]]``
        row's too: :func:`mechdyn.studies.model_scatter.read_scatter`).

    Examples
    --------
    >>> import mechdyn
    >>> loaded = mechdyn.load("examples/fourbar.toml")  # doctest: +SKIP
    >>> loaded.type, type(loaded.model).__name__  # doctest: +SKIP
    ('mechanism', 'Mechanism')
    """
    return load_model(path)


def _describe_location(loc: tuple[Any, ...], data: Mapping[str, Any]) -> str:
    """Render a pydantic location as the TOML reader sees it: ``[[meshes]] #2 (name = 'G1') → stiffness``."""
    parts: list[str] = []
    node: Any = data
    i = 0
    while i < len(loc):
        key = loc[i]
        if isinstance(key, str):
            child = node.get(key) if isinstance(node, Mapping) else None
            nxt = loc[i + 1] if i + 1 < len(loc) else None
            if (
                isinstance(nxt, int)
                and isinstance(child, list)
                and 0 <= nxt < len(child)
                and isinstance(child[nxt], Mapping)
            ):
                item = child[nxt]
                label = f"[[{key}]] #{nxt + 1}"
                if "name" in item:
                    label += f" (name = {item['name']!r})"
                parts.append(label)
                node = item
                i += 2
                continue
            parts.append(f"[{key}]" if not parts and isinstance(child, Mapping) else key)
            node = child
        else:
            parts.append(f"item {key + 1}")
            node = node[key] if isinstance(node, list) and 0 <= key < len(node) else None
        i += 1
    return " → ".join(parts)


def _error_message(err: Mapping[str, Any], model: type[BaseModel] | None) -> str:
    kind = err.get("type", "")
    msg = str(err.get("msg", "invalid"))
    loc = err.get("loc", ())
    value = err.get("input")
    if kind == "extra_forbidden":
        field = str(loc[-1]) if loc else "?"
        hint = ""
        known = _known_fields(model, loc)
        close = difflib.get_close_matches(field, known, n=1)
        if close:
            hint = f"; did you mean {close[0]!r}?"
        elif known:
            hint = f"; expected one of {', '.join(sorted(known))}"
        return f"unknown field {field!r}{hint}"
    if kind == "missing":
        return "required field is missing"
    if kind == "value_check":  # a field's value check (io.fields.Check): it names the value itself
        return msg
    msg = msg.removeprefix("Value error, ")
    if value is None or isinstance(value, (dict, list)) or repr(value) in msg:
        return msg
    return f"{value!r}: {msg}"


def _known_fields(model: type[BaseModel] | None, loc: tuple[Any, ...]) -> list[str]:
    node: Any = model
    for key in loc[:-1]:
        if isinstance(key, int) or node is None:
            continue
        field = getattr(node, "model_fields", {}).get(key)
        if field is None:
            return []
        ann = field.annotation
        for cand in (ann, *getattr(ann, "__args__", ())):
            for c in (cand, *getattr(cand, "__args__", ())):
                if isinstance(c, type) and issubclass(c, BaseModel):
                    node = c
                    break
    return list(getattr(node, "model_fields", {}))


def strip(data: Mapping[str, Any]) -> Mapping[str, Any]:
    """A model file's parsed TOML without its scatter tables, for its type's schema: every model
    type accepts them and none reads them (a file that is no model file, without ``[model]``, is
    given back as it is).

    Parameters
    ----------
    data : mapping
        The parsed TOML.
    """
    if not isinstance(data.get("model"), Mapping) or not any(k in data for k in SCATTER_TABLES):
        return data
    return {k: v for k, v in data.items() if k not in SCATTER_TABLES}


def validate(schema: type[M], source: ModelSource) -> M:
    """Validate parsed TOML against a schema, turning pydantic errors into a ModelFileError that
    lists every problem of the file, each with its table, field, value and what was expected.

    A model file's ``[[scatter]]`` and ``[[correlations]]`` (:mod:`mechdyn.io.scatter`) are left out:
    every model type takes them, :func:`load_model` checks them."""
    try:  # the scatter tables of a model file are every type's, read by mechdyn.io.scatter
        return schema.model_validate(strip(source.data))
    except ValidationError as exc:
        problems = _problems(exc.errors(), source, schema)
        location, message, value = problems[0]
        raise ModelFileError(
            source.path, location, message, value, problems=[(loc, msg) for loc, msg, _ in problems]
        ) from None


def _problems(errors: list[Any], source: ModelSource, schema: type[BaseModel]) -> list[tuple[str, str, Any]]:
    """One (location, message, value) per field in error: a misspelt field first, without the
    "missing" error of the field it was meant to be; one error per field (a union type reports
    each of its branches)."""
    errors = sorted(errors, key=lambda e: e.get("type") != "extra_forbidden")
    misspelt = {
        (tuple(e["loc"][:-1]), str(e["loc"][-1]))
        for e in errors
        if e.get("type") == "extra_forbidden" and e["loc"]
    }
    out: list[tuple[str, str, Any]] = []
    seen: set[str] = set()
    for e in errors:
        loc = tuple(e["loc"])
        if e.get("type") == "missing" and loc:
            siblings = [name for parent, name in misspelt if parent == loc[:-1]]
            if difflib.get_close_matches(str(loc[-1]), siblings, n=1):
                continue  # its misspelling is reported
        location = _describe_location(loc, source.data)
        if location in seen:
            continue
        seen.add(location)
        out.append((location, _error_message(e, schema), e.get("input")))
    return out


@contextmanager
def field_context(
    source: ModelSource, location: str, elements: Mapping[str, str] | None = None
) -> Iterator[None]:
    """Attach a file location to model errors and warnings raised while building one table.

    ``elements`` maps element names to their own tables, for errors raised while assembling a
    whole model: an error naming element ``"G1"`` is then placed at ``[[meshes]] #2 (name = 'G1')``.
    """
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            yield
        except ModelFileError:
            raise
        except ModelError as exc:
            field = f" → {exc.field}" if exc.field else ""
            where = (elements or {}).get(getattr(exc, "element", None) or "", location)
            raise ModelFileError(source.path, where + field, exc.detail) from None
        except ValueError as exc:
            raise ModelFileError(source.path, location, str(exc)) from None
    for w in caught:
        warnings.warn(f"{source.path}: {location}: {w.message}", w.category, stacklevel=3)
