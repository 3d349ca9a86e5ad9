"""The error of a study that is not valid."""

from __future__ import annotations

from mechdyn.errors import MechdynError

__all__ = ["StudyError"]


class StudyError(MechdynError):
    """A study is not valid: names the file or field, the value and the fix."""
