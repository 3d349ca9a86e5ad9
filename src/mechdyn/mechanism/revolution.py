"""One crank revolution as the analyses sample it: how many crank angles it takes
(:func:`check_angles`, at most :data:`MAX_ANGLES`), and the errors of a motion that cannot be
followed round it (:class:`AssemblyError`, :class:`SingularPositionError`).

Both motion solvers share them: the general engine (:func:`~mechdyn.mechanism.kinematics.newton_motion`)
and the closed-form dyads (:mod:`mechdyn.mechanism.dyads`).
"""

from __future__ import annotations

from typing import Any

from mechdyn.checks import check_count
from mechdyn.errors import ModelError

__all__ = ["MAX_ANGLES", "AssemblyError", "SingularPositionError", "check_angles"]

MAX_ANGLES = 100_000
"""The most crank angles per revolution an analysis takes (as a model file's ``n_angles``)."""


def check_angles(n_angles: Any) -> int:
    """The number of crank angles per revolution, checked: a whole number from 4 to :data:`MAX_ANGLES`.

    Parameters
    ----------
    n_angles : int
        Crank angles per revolution.

    Raises
    ------
    mechdyn.errors.ModelError
        Naming ``n_angles``, its value and the range.
    """
    return check_count(None, "n_angles", n_angles, low=4, high=MAX_ANGLES, what="crank angles")


class AssemblyError(ModelError):
    """The mechanism cannot be assembled at some crank angle."""


class SingularPositionError(ModelError):
    """The constraint Jacobian is singular (a toggle or dead-centre position)."""
