"""Model values addressed by their path, as the model file spells them, and variants built from them.

A path walks the file's tables: ``support.stiffness``, ``points.C`` (a point: its coordinates are
``points.C.x`` and ``points.C.y``), ``bodies.slide.mass`` (an array of tables is indexed by the
``name`` of its rows, or by position from 1: ``disks.3.inertia``), ``mounts.*.stiffness`` (every
row). A value that names another model file (a support's ``excitation.mechanism``, a mount row's
``mount``) is entered as if its tables were written there: ``excitation.mechanism.points.C``.

A variant is the base files with some values replaced, built in memory
(:attr:`mechdyn.io.ModelSource.includes`); the files on disk and the base model are never changed.
"""

from __future__ import annotations

import copy
import difflib
import hashlib
import json
import re
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from mechdyn.errors import MechdynError
from mechdyn.io.modelfile import ModelSource, reference_path, referenced

__all__ = ["Location", "ModelTree", "PathError"]

_COMPONENTS = ("x", "y", "z")
_NUMBER = re.compile(r"^\s*[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?(?:\s|$)")


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


def split(path: str) -> list[str]:
    """The segments of a path; a segment with dots or spaces may be quoted: ``bodies."rod 1".mass``."""
    parts = re.findall(r'"([^"]*)"|([^.]+)', path.strip())
    return [a or b for a, b in parts]


def _quantity(value: Any) -> bool:
    """A value a study can vary: a float, or text that starts with a number (``"4.5e8 N/m"``).

    Integers are counts (angles per revolution, disk numbers), not design values."""
    if isinstance(value, float):
        return True
    return isinstance(value, str) and bool(_NUMBER.match(value)) and not value.endswith(".toml")


def _vector(value: Any) -> bool:
    return isinstance(value, list) and 1 <= len(value) <= 3 and all(_quantity(v) for v in value)


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
            self.paths()  # enters every file the model refers to
        return self._files[files[-1]]

    def _enter(self, parent: ModelSource, relative: str) -> ModelSource | None:
        if not relative.endswith(".toml"):
            return None
        path = reference_path(parent, relative)
        if path not in self._files:
            found = referenced(parent, relative)
            if found is None:
                return None
            self._files[path] = found
        return self._files[path]

    @property
    def texts(self) -> dict[str, str]:
        """Every file of the model (the base and the files it refers to) by path: its exact text."""
        self.paths()  # enters every reference
        return {p: s.text for p, s in self._files.items()}

    @property
    def sha256(self) -> str:
        """One hash over every file of the model."""
        h = hashlib.sha256()
        for p, text in sorted(self.texts.items()):
            h.update(p.encode() + b"\0" + text.encode() + b"\0")
        return h.hexdigest()

    # -- paths --------------------------------------------------------------------------------
    def _walk(
        self, node: Any, files: tuple[str, ...], keys: tuple[str | int, ...], words: tuple[str, ...]
    ) -> Iterator[tuple[tuple[str, ...], tuple[str, ...], tuple[str | int, ...], Any]]:
        """Every (words, files, keys, value) of a quantity or a vector below ``node``."""
        if isinstance(node, Mapping):
            for k, v in node.items():
                if k in ("model", "name"):
                    continue
                yield from self._walk(v, files, (*keys, k), (*words, k))
        elif isinstance(node, list) and node and all(isinstance(r, Mapping) for r in node):
            for i, row in enumerate(node):
                yield from self._walk(row, files, (*keys, i), (*words, _Row(_label(row, i))))
        elif isinstance(node, str) and words and words[-1] != "name":
            inner = self._enter(self.file(files), node)
            if inner is not None and inner.path not in files:
                yield from self._walk(inner.data, (*files, inner.path), (), words)
        if _quantity(node) or _vector(node):
            yield words, files, keys, node

    def paths(self) -> list[str]:
        """Every path of a value a study can vary (vectors also by component); a value in the rows of
        a table array also by its ``*`` form (every row at once, e.g. ``mounts.*.stiffness``), listed
        before the rows."""
        out: list[str] = []
        every: set[tuple[str, ...]] = set()
        for words, _files, _keys, value in self._walk(self.source.data, (), (), ()):
            forms = [words]
            if any(isinstance(w, _Row) for w in words):
                star = tuple("*" if isinstance(w, _Row) else w for w in words)
                if star not in every:
                    every.add(star)
                    forms.insert(0, star)
            for form in forms:
                path = ".".join(f'"{w}"' if "." in w else w for w in form)
                if _vector(value):
                    out.extend(f"{path}.{c}" for c in _COMPONENTS[: len(value)])
                out.append(path)
        return out

    def resolve(self, path: str) -> list[Location]:
        """The values a path names (several with ``*``), each a quantity (vectors by component).

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
            if _vector(node):
                found.extend(Location(files, (*keys, i), path) for i in range(len(node)))
            elif _quantity(node):
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
                self._resolve(node[k], files, (*keys, k), rest, path, found)
        elif isinstance(node, list):
            if _vector(node) and word in _COMPONENTS[: len(node)] and not rest:
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
        ``"0.61 m"`` or ``0.05``), built in memory; the base is left as it is.

        Parameters
        ----------
        values : mapping of Location to value
            The new file values."""
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
        # every changed file sees every other one, however deep it refers (one shared mapping)
        includes: dict[str, ModelSource] = {}
        for p, d in data.items():
            if p != self.source.path:
                includes[p] = ModelSource(p, self._files[p].text, stamp, d, includes)
        base = data.get(self.source.path, self.source.data)
        return ModelSource(self.source.path, self.source.text, stamp, base, includes)


def _key(loc: Location) -> str:
    return "/".join(loc.files) + ":" + "/".join(map(str, loc.keys))
