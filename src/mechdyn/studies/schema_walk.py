"""What a file type's schema allows at a path of its tables: the annotations there, the types a
value may take and the bounds its fields check (the schema read as :func:`mechdyn.io.modelfile.schema_of`
gives it; a table written inline in the form of another type's file is read as that type's)."""

from __future__ import annotations

import types
import typing
from collections.abc import Mapping, Sequence
from typing import Any, get_args, get_origin

__all__ = ["bounds_at", "leaves_at"]

# tables written inline in the form of another file type: (file type, key) → that type
_INLINE = {("support", "estimate"): "mount"}


def _unwrap(annotation: Any) -> list[Any]:
    """The types an annotation allows: ``Annotated`` and ``Optional`` taken apart."""
    if annotation is None or annotation is type(None):
        return []
    origin = get_origin(annotation)
    if origin is typing.Annotated:
        return _unwrap(get_args(annotation)[0])
    if origin in (typing.Union, types.UnionType):
        return [t for a in get_args(annotation) for t in _unwrap(a)]
    return [annotation]


def _step(annotation: Any, key: str | int) -> list[Any] | None:
    """The annotations one key below ``annotation`` (None: the schema does not say)."""
    from pydantic import BaseModel

    out: list[Any] = []
    for t in _unwrap(annotation):
        if t is Any:
            return None
        origin = get_origin(t)
        args = get_args(t)
        if origin is None and isinstance(t, type) and issubclass(t, BaseModel):
            if isinstance(key, str) and key in t.model_fields:
                out.append(t.model_fields[key].annotation)
        elif origin in (list, Sequence) and isinstance(key, int) and args:
            out.append(args[0])
        elif origin is tuple and isinstance(key, int) and args:
            if len(args) == 2 and args[1] is Ellipsis:
                out.append(args[0])
            elif key < len(args):
                out.append(args[key])
        elif origin in (dict, Mapping) and isinstance(key, str) and len(args) == 2:
            if args[1] is Any:
                return None
            out.append(args[1])
    return out


def _annotations(file_type: str, keys: tuple[str | int, ...]) -> list[Any] | None:
    """The annotations the schema of a file type has at ``keys`` (None: it does not say)."""
    from mechdyn.io.modelfile import schema_of

    try:
        annotations: list[Any] = [schema_of(file_type)]
    except KeyError:
        return None
    for i, k in enumerate(keys):
        inline = _INLINE.get((file_type, str(k)))
        if inline is not None and i > 0:  # a table written inline in the form of another type's file
            annotations = [schema_of(inline)]
            continue
        below: list[Any] = []
        for a in annotations:
            step = _step(a, k)
            if step is None:
                return None
            below.extend(step)
        annotations = below
    return annotations


def leaves_at(file_type: str, keys: tuple[str | int, ...]) -> tuple[Any, ...] | None:
    """The types the schema of a file type allows at ``keys`` (None: it does not say)."""
    annotations = _annotations(file_type, keys)
    if annotations is None:
        return None
    leaves = tuple(t for a in annotations for t in _unwrap(a))
    return None if any(t is Any for t in leaves) else leaves


def _metadata(annotation: Any) -> list[Any]:
    """The metadata of an annotation: of ``Annotated``, and of each type of a union."""
    origin = get_origin(annotation)
    if origin is typing.Annotated:
        args = get_args(annotation)
        return [*_metadata(args[0]), *args[1:]]
    if origin in (typing.Union, types.UnionType):
        return [m for a in get_args(annotation) for m in _metadata(a)]
    return []


def bounds_at(file_type: str, keys: tuple[str | int, ...]) -> tuple[Any, ...]:
    """The value checks the schema of a file type makes at ``keys``: its fields' bounds
    (:class:`mechdyn.io.fields.Check`, and pydantic's ``ge``, ``gt``, ``le``, ``lt``)."""
    from pydantic import BaseModel

    if not keys:
        return ()
    annotations = _annotations(file_type, keys[:-1])
    if annotations is None:
        return ()
    key = keys[-1]
    found: list[Any] = []
    for a in annotations:
        for t in _unwrap(a):
            if isinstance(t, type) and issubclass(t, BaseModel) and isinstance(key, str):
                info = t.model_fields.get(key)
                if info is not None:  # pydantic keeps a field's own metadata apart from its type
                    found += [*info.metadata, *_metadata(info.annotation)]
            else:
                found += [m for s in _step(t, key) or [] for m in _metadata(s)]
    bounds = ("problem", "ge", "gt", "le", "lt")
    return tuple(dict.fromkeys(m for m in found if any(hasattr(m, b) for b in bounds)))
