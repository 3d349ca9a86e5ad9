"""Errors and warnings that reach the user.

Every error names what is wrong and where: the file and field of a model file, or the element of a
model, the offending value, and what was expected instead. The command line prints them without a
traceback.
"""

from __future__ import annotations

from typing import Any

__all__ = [
    "MechdynError",
    "ModelCheckError",
    "ModelError",
    "ModelFileError",
    "ModelWarning",
]


class MechdynError(Exception):
    """Base of every error mechdyn raises on purpose."""


class ModelError(MechdynError, ValueError):
    """A model (built in Python) is invalid.

    Parameters
    ----------
    message : str
        What is wrong and what is expected.
    element : str, optional
        Name of the element (disk, shaft, mesh, ...) responsible.
    field : str, optional
        The element's field, e.g. ``"stiffness"``.
    """

    def __init__(self, message: str, *, element: str | None = None, field: str | None = None):
        self.element = element
        self.field = field
        self.detail = message
        where = ""
        if element is not None:
            where = f"element {element!r}"
            if field is not None:
                where += f", field {field!r}"
            where += ": "
        super().__init__(where + message)


class ModelCheckError(ModelError):
    """An assembled model fails a physical check (symmetry, semi-definiteness, rigid-body modes)."""


SHOWN_PROBLEMS = 20  # problems of a model file listed in its error; the rest are counted


class ModelFileError(MechdynError, ValueError):
    """A model file cannot be read or is invalid.

    Parameters
    ----------
    path : str
        The file.
    location : str
        The table and field, e.g. ``"[[meshes]] #2 (name = 'G1') → stiffness"``.
    message : str
        What is wrong, with the bad value and what was expected.
    value : Any, optional
        The offending value as read from the file.
    problems : list of (location, message), optional
        Every problem of the file when there are several (the first is ``location`` and
        ``message``); the error's text lists them all, one per line.
    """

    def __init__(
        self,
        path: str,
        location: str,
        message: str,
        value: Any = None,
        problems: list[tuple[str, str]] | None = None,
    ):
        self.path = str(path)
        self.location = location
        self.value = value
        self.detail = message
        self.problems = list(problems) if problems else [(location, message)]
        if len(self.problems) > 1:
            shown = self.problems[:SHOWN_PROBLEMS]
            lines = "\n".join(f"  - {loc}: {msg}" if loc else f"  - {msg}" for loc, msg in shown)
            more = len(self.problems) - len(shown)
            if more:  # a generated file with one slip repeated: the first few say what it is
                lines += f"\n  … and {more} more"
            super().__init__(f"{self.path}: {len(self.problems)} problems:\n{lines}")
            return
        loc = f" {location}:" if location else ""
        super().__init__(f"{self.path}:{loc} {message}")


class ModelWarning(UserWarning):
    """A model is valid but contains something the user should know (e.g. inconsistent gear data)."""


class LongRunWarning(ModelWarning):
    """A run will take long (its cost estimated before the work): the command line says so at once."""
