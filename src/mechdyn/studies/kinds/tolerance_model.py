"""The model file's scatter as a tolerance study's default.

A model file may say how its values scatter (``[[scatter]]`` and ``[[correlations]]``,
:mod:`mechdyn.io.scatter`). A ``tolerance`` study on it takes those rows as the default of its
parameters: its own ``[[parameters]]`` first, then every row of the file whose values they do not
name (:func:`with_model_scatter`); a study with no parameters samples the file's scatter alone, the
same samples as the same rows written in the study.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from mechdyn.studies.errors import StudyError

if TYPE_CHECKING:
    from mechdyn.studies.parameters import Parameter
    from mechdyn.studies.paths import ModelTree

__all__ = ["with_model_scatter"]


def with_model_scatter(
    tree: ModelTree,
    parameters: Sequence[Parameter],
    correlations: Sequence[tuple[str, str, float, str]],
    where: str,
) -> tuple[list[Parameter], tuple[tuple[str, str, float, str], ...]]:
    """A tolerance study's parameters and correlations with its model file's scatter as their default
    (the file's ``[[scatter]]`` and ``[[correlations]]``, :func:`mechdyn.studies.model_scatter.read_scatter`).

    The study's own parameters come first, in its order; then each of the file's rows whose values
    the study does not name, in the file's order, made as the same row in the study's
    ``[[parameters]]`` would be (the same variable, so the same samples). A study parameter that moves
    a value of a row overrides the row. The file's correlations hold between the rows taken from it,
    after the study's own; a pair the study correlates itself is the study's.

    Parameters
    ----------
    tree : ModelTree
        The study's model (its base file, with the files it refers to).
    parameters : sequence of Parameter
        The study's ``[[parameters]]``.
    correlations : sequence of (str, str, float, str)
        The study's ``[[correlations]]``: the two names, the coefficient (dimensionless), the measure.
    where : str
        The study file, for errors.

    Returns
    -------
    list of Parameter, tuple of (str, str, float, str)

    Raises
    ------
    StudyError
        For a model file whose scatter is wrong (its file, row and field named), a row named as a
        study parameter that moves other values, or a study with no parameters on a file with no
        scatter.
    """
    from mechdyn.errors import ModelFileError
    from mechdyn.studies.model_scatter import read_scatter

    try:
        found = read_scatter(tree.source, tree)
    except ModelFileError as exc:
        raise StudyError(f"{where}: [study] → model: {exc}") from None
    if found is None:
        if not parameters:
            raise StudyError(
                f"{where}: a tolerance study needs values that scatter: give [[parameters]] rows with a "
                f"scatter, or [[scatter]] rows in its model file ({tree.source.path})"
            )
        return list(parameters), tuple(correlations)
    mine = {loc for p in parameters for loc in p.locations}
    names = {p.name: p for p in parameters}
    taken = []
    for row, p in zip(found.rows, found.parameters, strict=True):
        if mine.intersection(p.locations):
            continue  # the study's parameter overrides the file's row
        if p.name in names:
            raise StudyError(
                f"{where}: [[parameters]]: {p.name!r} names a study parameter and the [[scatter]] row of "
                f"{row.path!r} in {found.path}, which moves other values; give the study's parameter "
                "another name, or give it that row's path to override it"
            )
        taken.append(p)
    kept = {p.name for p in taken}
    pairs = {frozenset((a, b)) for a, b, _, _ in correlations}
    from_file = tuple(c for c in found.correlations if {c[0], c[1]} <= kept and frozenset(c[:2]) not in pairs)
    return [*parameters, *taken], (*correlations, *from_file)
