"""Model values addressed by their path, as the model file spells them, and variants built from them.

A path walks the file's tables: ``support.stiffness``, ``points.C`` (a point: its coordinates are
``points.C.x`` and ``points.C.y``), ``bodies.slide.mass`` (an array of tables is indexed by the
``name`` of its rows, or by position from 1: ``disks.3.inertia``), ``mounts.*.stiffness`` (every
row). A value that names another model file (a support's ``excitation.mechanism``, a mount row's
``mount``) is entered as if its tables were written there: ``excitation.mechanism.points.C``.

A value is a *quantity* (a number, with its unit or without), a *whole number* (a tooth count, a
number of crank angles: a field the file's schema reads as an integer) or a *choice* (an option the
schema names, a material by its name in the materials database, another model file of the same type,
true or false); the file's schema (:func:`mechdyn.io.modelfile.schema_of`) tells which. Names (of
rows, of the disks a shaft joins) and free text are not values a study varies.

A variant is the base files with some values replaced, built in memory
(:attr:`mechdyn.io.ModelSource.includes`); the files on disk and the base model are never changed.
"""

from __future__ import annotations

import copy
import difflib
import hashlib
import json
import re
import tomllib
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal, get_args, get_origin

from mechdyn.errors import MechdynError
from mechdyn.io.modelfile import ModelSource, reference_path, referenced
from mechdyn.studies.schema_walk import bounds_at, leaves_at

__all__ = ["Entry", "Location", "ModelTree", "Nature", "PathError"]

_COMPONENTS = ("x", "y", "z")
_NUMBER = re.compile(r"^\s*[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?(?:\s|$)")
# a table that a file of one type holds inline in the form of another type's file
_UNKNOWN: tuple[Any, ...] = ()
# the mount tables whose material is an elastomer (a material of kind "rubber")
_ELASTOMER_TABLES = ("pad", "damping_pad")


class PathError(MechdynError):
    """A parameter path names no value of the model."""


@dataclass(frozen=True)
class Location:
    """One value in the model files: the chain of file references from the base file, then the keys.

    Attributes
    ----------
    files : tuple of str
        Resolved paths of the referenced files entered, from the base file's (empty: the base file).
    keys : tuple of str or int
        Keys into the parsed TOML (int: a list index, from 0).
    path : str
        The path as the user writes it.
    """

    files: tuple[str, ...]
    keys: tuple[str | int, ...]
    path: str


@dataclass(frozen=True)
class Nature:
    """What a model value is to a study.

    Attributes
    ----------
    kind : {"quantity", "integer", "choice"}
        A quantity (a number, with its unit or without) takes ranges and levels; a whole number (a
        tooth count) and a choice take levels only.
    choices : tuple
        A choice: the values the model accepts, as the file writes them (for a model file, the files
        of its type beside it; any file of that type is accepted).
    of : str
        A choice: what its values are (``"material"``, ``"option"``, ``"true or false"``, ``"mount model
        file"``).
    model_type : str
        A reference to another model file: the type that file must have (``""`` otherwise).
    """

    kind: str
    choices: tuple[Any, ...] = ()
    of: str = ""
    model_type: str = ""

    def describe(self) -> str:
        """The value's kind in words, with the valid choices (for ``mechdyn study --paths``)."""
        if self.kind == "quantity":
            return ""
        if self.kind == "integer":
            return "a whole number"
        listed = ", ".join(file_text(c) for c in self.choices)
        if self.model_type:
            return f"a {self.of}" + (f"; beside it: {listed}" if listed else "")
        if self.of == "option":
            return f"one of {listed}"
        return f"a {self.of}: {listed}" if self.of != "true or false" else "true or false"


_QUANTITY = Nature("quantity")
_INTEGER = Nature("integer")


@dataclass(frozen=True)
class Entry:
    """One addressable value of a model, as ``mechdyn study --paths`` lists it.

    Attributes
    ----------
    path : str
        Its path (a ``*`` form names the value of every row).
    value : Any
        As the file writes it (a ``*`` form: the rows' value when they all hold the same, else None).
    nature : Nature
        What it is to a study.
    rows : int
        A ``*`` form: how many values it names (1 otherwise).
    """

    path: str
    value: Any
    nature: Nature
    rows: int = 1

    def line(self) -> str:
        """``PATH = VALUE``, the value as the file writes it, and what it is when not a quantity."""
        value = "(differs by row)" if self.value is None else file_text(self.value)
        note = self.nature.describe()
        return f"{self.path} = {value}" + (f"  # {note}" if note else "")

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready: ``path``, ``value``, ``kind``, ``choices``, ``of`` and ``rows``."""
        return {
            "path": self.path,
            "value": self.value,
            "kind": self.nature.kind,
            "choices": list(self.nature.choices),
            "of": self.nature.of,
            "rows": self.rows,
        }


def file_text(value: Any) -> str:
    """A value as a TOML file writes it (``"600 t"`` with quotes, ``true``, ``18``, ``[...]``)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, list):
        return "[" + ", ".join(file_text(v) for v in value) + "]"
    return repr(value) if isinstance(value, float) else str(value)


def split(path: str) -> list[str]:
    """The segments of a path; a segment with dots or spaces may be quoted: ``bodies."rod 1".mass``."""
    parts = re.findall(r'"([^"]*)"|([^.]+)', path.strip())
    return [a or b for a, b in parts]


def _numeric(value: Any) -> bool:
    """Text that starts with a number (``"4.5e8 N/m"``), or a float."""
    if isinstance(value, float):
        return True
    return isinstance(value, str) and bool(_NUMBER.match(value)) and not value.endswith(".toml")


class _Row(str):
    """A path word that names a row of a table array (``front left`` of ``mounts``)."""


def _label(row: Any, index: int) -> str:
    return str(row["name"]) if isinstance(row, Mapping) and "name" in row else str(index + 1)


class ModelTree:
    """A model file with the files it refers to, parsed: what a study's parameters address.

    Parameters
    ----------
    source : ModelSource
        The base model file (:func:`mechdyn.io.modelfile.read`).
    """

    def __init__(self, source: ModelSource):
        self.source = source
        self._files: dict[str, ModelSource] = {source.path: source}
        self._entered = False
        self._alternatives: dict[str, ModelSource] = {}
        self._leaves: dict[tuple[str, tuple[str | int, ...]], tuple[Any, ...] | None] = {}
        self._materials: dict[str, tuple[str, ...]] = {}
        self._material_kinds: dict[str, tuple[str, ...]] = {}
        self._beside: dict[tuple[str, str], tuple[str, ...]] = {}

    # -- files --------------------------------------------------------------------------------
    def file(self, files: tuple[str, ...]) -> ModelSource:
        """The file at the end of a chain of references (the base file for an empty chain).

        Parameters
        ----------
        files : tuple of str
            The reference fields followed from the base file (e.g. ``("excitation.mechanism",)``).
        """
        if not files:
            return self.source
        if files[-1] not in self._files:
            self._enter_all()
        return self._files[files[-1]]

    def _enter(self, parent: ModelSource, relative: str) -> ModelSource | None:
        if not relative.endswith(".toml"):
            return None
        path = reference_path(parent, relative)
        if path not in self._files:
            found = self._alternatives.get(path) or referenced(parent, relative)
            if found is None:
                return None
            self._files[path] = found
            self._alternatives.pop(path, None)
        return self._files[path]

    def _enter_all(self) -> None:
        """Enter every file the model refers to, however deep."""
        if self._entered:
            return

        def follow(node: Any, source: ModelSource, files: tuple[str, ...]) -> None:
            if isinstance(node, Mapping):
                for k, v in node.items():
                    if k not in ("model", "name"):
                        follow(v, source, files)
            elif isinstance(node, list):
                for v in node:
                    if isinstance(v, Mapping):
                        follow(v, source, files)
            elif isinstance(node, str):
                inner = self._enter(source, node)
                if inner is not None and inner.path not in files:
                    follow(inner.data, inner, (*files, inner.path))

        follow(self.source.data, self.source, ())
        self._entered = True

    @property
    def texts(self) -> dict[str, str]:
        """Every file of the model (the base, the files it refers to, and the model files a study's
        choice may name instead) by path: its exact text."""
        self._enter_all()
        out = {p: s.text for p, s in self.source.includes.items()}
        out.update({p: s.text for p, s in self._alternatives.items()})
        out.update({p: s.text for p, s in self._files.items()})
        return out

    @property
    def alternatives(self) -> dict[str, ModelSource]:
        """The model files that a choice names instead of the model's own (:meth:`model_file`), by
        path: a study's variants read them, so they belong to its model files."""
        return dict(self._alternatives)

    @property
    def sha256(self) -> str:
        """One hash over every file of the model."""
        h = hashlib.sha256()
        for p, text in sorted(self.texts.items()):
            h.update(p.encode() + b"\0" + text.encode() + b"\0")
        return h.hexdigest()

    def model_file(self, loc: Location, relative: Any) -> ModelSource | None:
        """The model file that the reference at ``loc`` would name if it were ``relative`` (None
        when there is no such model file); a file the model does not refer to yet is kept among
        :attr:`alternatives`.

        Parameters
        ----------
        loc : Location
            A reference to another model file (a mount row's ``mount``).
        relative : str
            The file, relative to the file that holds the reference.
        """
        from mechdyn.io.modelfile import read_check

        if not isinstance(relative, str) or not relative.endswith(".toml"):
            return None
        parent = self.file(loc.files)
        path = reference_path(parent, relative)
        self._enter_all()
        if path in self._files:
            return self._files[path]
        if path not in self._alternatives:
            try:
                found = referenced(parent, relative)
                if found is None:
                    return None
                self._alternatives[path] = read_check(found)
            except MechdynError:
                return None
        return self._alternatives[path]

    # -- what a value is ----------------------------------------------------------------------
    def _schema_leaves(self, files: tuple[str, ...], keys: tuple[str | int, ...]) -> tuple[Any, ...] | None:
        """The types the file's schema allows at ``keys`` (None: no schema says)."""
        source = self.file(files)
        model = source.data.get("model")
        file_type = model.get("type") if isinstance(model, Mapping) else None
        if not isinstance(file_type, str):
            return None
        cache = (file_type, keys)
        if cache not in self._leaves:
            self._leaves[cache] = leaves_at(file_type, keys)
        return self._leaves[cache]

    def _nature(self, files: tuple[str, ...], keys: tuple[str | int, ...], value: Any) -> Nature | None:
        """What the value at ``keys`` of a file is to a study (None: not a value a study varies)."""
        if not keys or isinstance(value, (Mapping, list)) or value is None:
            return None
        leaves = self._schema_leaves(files, keys)
        known = leaves is not None
        allowed = leaves or ()
        if isinstance(value, bool):
            return Nature("choice", (False, True), "true or false") if not known or bool in allowed else None
        if isinstance(value, int):
            if known and float in allowed:
                return _QUANTITY  # a number the field reads as a float (a Shore hardness of 60)
            return _INTEGER if not known or int in allowed else None
        if isinstance(value, float):
            return _QUANTITY if not known or float in allowed else None
        if not isinstance(value, str):
            return None
        options = tuple(a for t in allowed if get_origin(t) is Literal for a in get_args(t))
        if value in options:  # (a field that also takes a quantity, "bdc" or an angle: not a choice)
            return Nature("choice", options, "option") if float not in allowed else None
        if _numeric(value) and (not known or float in allowed):
            return _QUANTITY
        if known and str not in allowed:
            return None
        if value.endswith(".toml"):
            parent = self.file(files)
            inner = self._enter(parent, value)
            if inner is None or not isinstance(inner.data.get("model"), Mapping):
                return None
            kind = str(inner.data["model"].get("type", ""))
            return Nature("choice", self._model_files(parent, kind, value), f"{kind} model file", kind)
        if str(keys[-1]).endswith("material"):
            if len(keys) > 1 and keys[-2] in _ELASTOMER_TABLES:  # a pad takes an elastomer, nothing else
                return Nature("choice", self._material_names(files, "rubber"), "rubber")
            return Nature("choice", self._material_names(files), "material")
        return None

    def _vector_nature(
        self, files: tuple[str, ...], keys: tuple[str | int, ...], value: Any
    ) -> Nature | None:
        """A vector of one to three quantities or whole numbers: what its components are."""
        if not isinstance(value, list) or not 1 <= len(value) <= 3:
            return None
        natures = {self._nature(files, (*keys, i), v) for i, v in enumerate(value)}
        if len(natures) == 1 and (n := natures.pop()) in (_QUANTITY, _INTEGER):
            return n
        return None

    def nature(self, loc: Location) -> Nature:
        """What the value at a resolved location is to a study.

        Parameters
        ----------
        loc : Location
            From :meth:`resolve`.
        """
        found = self._nature(loc.files, loc.keys, self.value(loc))
        if found is None:
            raise PathError(f"{self.source.path}: {loc.path!r} names no value a study varies")
        return found

    def bounds(self, loc: Location) -> tuple[Any, ...]:
        """The value checks the file's schema makes where ``loc`` points: each a
        :class:`mechdyn.io.fields.Check` (with its ``problem``) or a pydantic bound (``ge``, ``gt``,
        ``le``, ``lt``), on the value in SI; empty where it makes none.

        Parameters
        ----------
        loc : Location
            From :meth:`resolve`.
        """
        source = self.file(loc.files)
        model = source.data.get("model")
        file_type = model.get("type") if isinstance(model, Mapping) else None
        return bounds_at(file_type, loc.keys) if isinstance(file_type, str) else ()

    def _material_names(self, files: tuple[str, ...], kind: str | None = None) -> tuple[str, ...]:
        """The materials a mount file may name: the shipped ones and those of its ``[materials] files``
        (of one ``kind`` only, e.g. ``"rubber"``, when given)."""
        source = self.file(files)
        if source.path not in self._materials:
            from mechdyn.mounts.materials import default_materials

            db = default_materials()
            table = source.data.get("materials")
            extra = table.get("files", []) if isinstance(table, Mapping) else []
            for name in extra if isinstance(extra, list) else []:
                p = Path(source.path).parent / str(name)
                try:
                    db = db.with_file(p)
                except (MechdynError, OSError):
                    pass  # the model's own check says what is wrong with the file
            self._materials[source.path] = tuple(db.names())
            self._material_kinds[source.path] = tuple(db.materials[n].kind for n in db.names())
        names, kinds = self._materials[source.path], self._material_kinds[source.path]
        return names if kind is None else tuple(n for n, k in zip(names, kinds, strict=True) if k == kind)

    def _model_files(self, parent: ModelSource, model_type: str, current: str) -> tuple[str, ...]:
        """The model files of a type beside the file that refers to one (the current one first)."""
        directory = Path(parent.path).parent
        cache = (str(directory), model_type)
        if cache not in self._beside:
            found = []
            for p in sorted(directory.glob("*.toml")) if directory.is_dir() else []:
                try:
                    data = tomllib.loads(p.read_text(encoding="utf-8"))
                except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError):
                    continue
                model = data.get("model")
                if isinstance(model, dict) and model.get("type") == model_type:
                    found.append(p.name)
            for path, inc in self.source.includes.items():  # a stored study's files
                if Path(path).parent == directory and inc.data.get("model", {}).get("type") == model_type:
                    found.append(Path(path).name)
            self._beside[cache] = tuple(dict.fromkeys(found))
        return tuple(dict.fromkeys((current, *self._beside[cache])))

    # -- paths --------------------------------------------------------------------------------
    def _walk(
        self, node: Any, files: tuple[str, ...], keys: tuple[str | int, ...], words: tuple[str, ...]
    ) -> Iterator[tuple[tuple[str, ...], tuple[str, ...], tuple[str | int, ...], Any, Nature]]:
        """Every (words, files, keys, value, nature) of a value a study varies below ``node``
        (vectors whole; a reference to another file before the values in it)."""
        if isinstance(node, Mapping):
            for k, v in node.items():
                if k in ("model", "name"):
                    continue
                yield from self._walk(v, files, (*keys, k), (*words, k))
            return
        if isinstance(node, list) and node and all(isinstance(r, Mapping) for r in node):
            for i, row in enumerate(node):
                yield from self._walk(row, files, (*keys, i), (*words, _Row(_label(row, i))))
            return
        if not words:
            return
        nature = self._vector_nature(files, keys, node) or self._nature(files, keys, node)
        if nature is not None:
            yield words, files, keys, node, nature
        if isinstance(node, str):
            inner = self._enter(self.file(files), node)
            if inner is not None and inner.path not in files:
                yield from self._walk(inner.data, (*files, inner.path), (), words)

    def entries(self) -> list[Entry]:
        """Every value a study can vary, with its value and what it is (vectors also by component); a
        value in the rows of a table array also by its ``*`` form (every row at once, e.g.
        ``mounts.*.stiffness``), listed before the rows."""
        out: list[Entry] = []
        stars: dict[tuple[str, ...], list[Any]] = {}
        for words, _files, _keys, value, nature in self._walk(self.source.data, (), (), ()):
            forms = [words]
            if any(isinstance(w, _Row) for w in words):
                star = tuple("*" if isinstance(w, _Row) else w for w in words)
                if star not in stars:
                    stars[star] = []
                    forms.insert(0, star)
                stars[star].append(value)
            for form in forms:
                path = ".".join(f'"{w}"' if "." in w else w for w in form)
                if isinstance(value, list):
                    out.extend(
                        Entry(f"{path}.{c}", v, nature) for c, v in zip(_COMPONENTS, value, strict=False)
                    )
                out.append(Entry(path, value, nature))
        # a * form: the rows' value if they all hold the same, and how many rows it names
        by_path = {
            ".".join(f'"{w}"' if "." in w else w for w in star): values for star, values in stars.items()
        }
        for i, e in enumerate(out):
            head, _, component = e.path.rpartition(".")
            if e.path in by_path:
                held = by_path[e.path]
            elif head in by_path and component in _COMPONENTS:
                held = [v[_COMPONENTS.index(component)] for v in by_path[head] if isinstance(v, list)]
            else:
                continue
            same = bool(held) and all(v == held[0] for v in held)
            out[i] = Entry(e.path, held[0] if same else None, e.nature, len(held))
        return out

    def paths(self) -> list[str]:
        """Every path of a value a study can vary (vectors also by component); a value in the rows of
        a table array also by its ``*`` form (every row at once, e.g. ``mounts.*.stiffness``), listed
        before the rows."""
        return [e.path for e in self.entries()]

    def resolve(self, path: str) -> list[Location]:
        """The values a path names (several with ``*``), each one a study varies (vectors by component).

        Parameters
        ----------
        path : str
            As the file spells it, e.g. ``points.C.y`` or ``mounts.*.stiffness``.

        Raises
        ------
        PathError
            Naming the path and the file, with the valid paths nearest to it.
        """
        words = split(path)
        found: list[Location] = []
        self._resolve(self.source.data, (), (), words, path, found)
        if not found:
            raise PathError(self._unknown(path))
        return found

    def _resolve(
        self,
        node: Any,
        files: tuple[str, ...],
        keys: tuple[str | int, ...],
        words: Sequence[str],
        path: str,
        found: list[Location],
    ) -> None:
        if not words:
            if self._vector_nature(files, keys, node) is not None:
                found.extend(Location(files, (*keys, i), path) for i in range(len(node)))
            elif self._nature(files, keys, node) is not None:
                found.append(Location(files, keys, path))
            return
        word, rest = words[0], words[1:]
        if isinstance(node, str):
            inner = self._enter(self.file(files), node)
            if inner is not None:
                self._resolve(inner.data, (*files, inner.path), (), words, path, found)
            return
        if isinstance(node, Mapping):
            for k in node if word == "*" else ([word] if word in node else []):
                if k not in ("model", "name"):
                    self._resolve(node[k], files, (*keys, k), rest, path, found)
        elif isinstance(node, list):
            if self._vector_nature(files, keys, node) and word in _COMPONENTS[: len(node)] and not rest:
                found.append(Location(files, (*keys, _COMPONENTS.index(word)), path))
                return
            for i, row in enumerate(node):
                if word == "*" or word == _label(row, i) or (word.isdigit() and int(word) == i + 1):
                    self._resolve(row, files, (*keys, i), rest, path, found)
                    if word != "*":
                        return

    def _unknown(self, path: str) -> str:
        valid = self.paths()
        near = difflib.get_close_matches(path, valid, n=6, cutoff=0.5)
        if not near:
            head = split(path)[0] if split(path) else ""
            near = [p for p in valid if p.startswith(head)][:8] or valid[:8]
        return f"{self.source.path}: no value at {path!r}; paths nearby: {', '.join(near)}" + (
            f" (and {len(valid) - len(near)} more: `mechdyn study --paths MODEL` lists them)"
        )

    def value(self, loc: Location) -> Any:
        """The value as the file writes it.

        Parameters
        ----------
        loc : Location
            Where it is.
        """
        node: Any = self.file(loc.files).data
        for k in loc.keys:
            node = node[k]
        return node

    # -- variants -----------------------------------------------------------------------------
    def variant(self, values: Mapping[Location, Any]) -> ModelSource:
        """The base model with the values at the given locations replaced (as file values, e.g.
        ``"0.61 m"``, ``0.05``, ``18`` or ``"rubber shore 50"``), built in memory; the base is left as
        it is. Every file of the model, and every model file a choice names, is given to the variant
        in memory (a stored study's files, not those on disk, when the base came from the store).

        Parameters
        ----------
        values : mapping of Location to value
            The new file values."""
        self._enter_all()
        data: dict[str, Any] = {}
        for loc, v in values.items():
            path = loc.files[-1] if loc.files else self.source.path
            if path not in data:
                data[path] = copy.deepcopy(dict(self.file(loc.files).data))
            node = data[path]
            for k in loc.keys[:-1]:
                node = node[k]
            node[loc.keys[-1]] = v
        stamp = hashlib.sha256(
            (
                self.source.sha256 + json.dumps(sorted((_key(loc), repr(v)) for loc, v in values.items()))
            ).encode()
        ).hexdigest()
        # every file sees every other one, however deep it refers (one shared mapping)
        includes: dict[str, ModelSource] = {}
        given = {**self.source.includes, **self._alternatives, **self._files}
        for p, s in given.items():
            if p != self.source.path:
                d = data.get(p, s.data)
                includes[p] = ModelSource(p, s.text, stamp if p in data else s.sha256, d, includes)
        base = data.get(self.source.path, self.source.data)
        return ModelSource(self.source.path, self.source.text, stamp, base, includes)


def _key(loc: Location) -> str:
    return "/".join(loc.files) + ":" + "/".join(map(str, loc.keys))
