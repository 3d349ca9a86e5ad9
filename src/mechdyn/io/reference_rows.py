"""The rows of the model-file reference: a table of a file type (:class:`FileTable`) and its fields
(:class:`FieldRow`).

:func:`mechdyn.io.reference.reference` lists a type's tables in them, and
:func:`mechdyn.io.scatter.reference_tables` the scatter tables every type takes.
"""

from __future__ import annotations

from dataclasses import dataclass, field

__all__ = ["FieldRow", "FileTable"]


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
