"""What a study varies and what it looks at: parameters with their ranges, outputs, objectives and
constraints, all with units and all structured data (nothing is evaluated as code).

The parameters (ranges, levels, ties, whole numbers and choices) are
:mod:`mechdyn.studies.parameters`; the outputs, objectives and constraints
:mod:`mechdyn.studies.outputs`; a study that is not valid raises
:class:`~mechdyn.studies.errors.StudyError`; the kinds that take levels
:func:`mechdyn.studies.kinds.base.level_kinds`. This module gathers them under the names they have
always been imported by.
"""

from __future__ import annotations

from mechdyn.studies.errors import StudyError
from mechdyn.studies.kinds.base import level_kinds
from mechdyn.studies.outputs import Constraint, Objective, Watched, output_problem, output_value
from mechdyn.studies.parameters import Parameter, parse_relative

__all__ = [
    "Constraint",
    "Objective",
    "Parameter",
    "StudyError",
    "Watched",
    "level_kinds",
    "output_problem",
    "output_value",
    "parse_relative",
]
