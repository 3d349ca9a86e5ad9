"""A model file's own scatter read and checked: its ``[[scatter]]`` rows as study parameters.

The tables are described, stripped from the model type's schema and written back in
:mod:`mechdyn.io.scatter`; reading them needs the study's path resolver
(:class:`mechdyn.studies.paths.ModelTree`) and its parameter reader
(:meth:`mechdyn.studies.spec.Parameter.from_spec`), so that a row in a model file and the same row in
a study's ``[[parameters]]`` make the same variable. :func:`read_scatter` checks the rows (the path a
value of this model, each name once, each value scattered once, the correlations a valid matrix) and
gives a :class:`ModelScatter`. The files beneath the studies (:func:`mechdyn.load`,
:func:`mechdyn.save`, :attr:`mechdyn.registry.LoadedModel.scatter`) reach it through
:func:`mechdyn.registry.model_scatter`.
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from mechdyn.errors import ModelError, ModelFileError
from mechdyn.io.scatter import CORRELATION_FIELDS, SCATTER_TABLES

if TYPE_CHECKING:
    import numpy as np

    from mechdyn.io.modelfile import ModelSource
    from mechdyn.studies.parameters import Parameter
    from mechdyn.studies.paths import ModelTree
    from mechdyn.uncertainty import InputSpace, Variable

__all__ = ["ModelScatter", "ScatterRow", "read_scatter"]

_ROW_FIELDS = ("path", "name")


@dataclass(frozen=True)
class ScatterRow:
    """One ``[[scatter]]`` row as the file writes it.

    Attributes
    ----------
    path : str
        The value's path into the model (a study's path).
    name : str or None
        The row's name (None: the path names it).
    spec : mapping
        The rest of the row: the scatter table (``distribution = ...`` or ``tolerance = ...`` with
        its parameters), values as the file writes them.
    """

    path: str
    name: str | None
    spec: Mapping[str, Any]


@dataclass(frozen=True, eq=False)
class ModelScatter:
    """The scatter of a model file's values: its ``[[scatter]]`` and ``[[correlations]]`` rows, checked.

    Attributes
    ----------
    path : str
        The model file.
    rows : tuple of ScatterRow
        The rows as written, in file order.
    parameters : tuple of Parameter
        One per row, in the same order: the study parameter the row makes (its ``scatter`` the
        :class:`~mechdyn.uncertainty.Variable`, SI; its ``locations`` the values it moves).
    correlations : tuple of (str, str, float, str)
        Each ``[[correlations]]`` row: the two names, the coefficient (dimensionless) and its measure
        (``"normal"`` or ``"spearman"``), as a tolerance study holds them.
    R : ndarray or None
        The Gaussian copula's correlation matrix (normal space), rows in the order of ``parameters``;
        None for independent values.
    """

    path: str
    rows: tuple[ScatterRow, ...]
    parameters: tuple[Parameter, ...]
    correlations: tuple[tuple[str, str, float, str], ...] = ()
    R: np.ndarray | None = None

    @property
    def names(self) -> list[str]:
        """The scattered values' names, in row order."""
        return [p.name for p in self.parameters]

    @property
    def variables(self) -> tuple[Variable, ...]:
        """Each row's :class:`~mechdyn.uncertainty.Variable` (SI), in row order."""
        return tuple(p.scatter for p in self.parameters)

    @property
    def space(self) -> InputSpace:
        """The rows as one :class:`~mechdyn.uncertainty.InputSpace`: their variables tied by the
        correlations (the copula's matrix :attr:`R`), what a tolerance study on this file samples
        when it names no parameter of its own."""
        from mechdyn.uncertainty import InputSpace

        return InputSpace(self.variables, self.R)

    def describe(self) -> list[str]:
        """One line per scattered value and per correlated pair, for a report or the command line."""
        return self.space.describe()

    def __repr__(self) -> str:
        tied = f", {len(self.correlations)} correlated pair(s)" if self.correlations else ""
        return f"<ModelScatter of {self.path}: {', '.join(self.names)}{tied}>"


# -- reading ---------------------------------------------------------------------------------------------


def _label(rows: Any, i: int, table: str = "scatter") -> str:
    """``[[scatter]] #2 (name = 'x')``, as the file reader names a row."""
    label = f"[[{table}]] #{i + 1}"
    row = rows[i] if isinstance(rows, list) and i < len(rows) else None
    if isinstance(row, Mapping) and isinstance(row.get("name"), str):
        label += f" (name = {row['name']!r})"
    return label


def _tables(source: ModelSource, table: str, fix: str) -> list[Mapping[str, Any]]:
    """The rows of the array of tables ``table`` (none where the file has none); an error naming the
    file, the table, the value and ``fix`` (what to write) where it is not an array of tables."""
    raw = source.data.get(table, [])
    if not isinstance(raw, list) or not all(isinstance(r, Mapping) for r in raw):
        raise ModelFileError(
            source.path, f"[[{table}]]", f"{raw!r} is not an array of tables; write {fix}", raw
        )
    return raw


def _rows(source: ModelSource) -> list[ScatterRow]:
    """The ``[[scatter]]`` rows, their form checked (a table each, a text path, an optional name)."""
    raw = _tables(
        source,
        "scatter",
        'each scattered value as a [[scatter]] table with path = "..." and its distribution',
    )
    out = []
    for i, row in enumerate(raw):
        where = _label(raw, i)
        path = row.get("path")
        if path is None:
            raise ModelFileError(
                source.path,
                f"{where} → path",
                'required field is missing; give the value\'s path, e.g. path = "support.stiffness" '
                "(`mechdyn study --paths MODEL` lists them)",
            )
        if not isinstance(path, str) or not path.strip():
            raise ModelFileError(
                source.path,
                f"{where} → path",
                f'{path!r} is not a path; give the value\'s path as text, e.g. path = "support.stiffness"',
                path,
            )
        name = row.get("name")
        if name is not None and (not isinstance(name, str) or not name.strip() or len(name) > 200):
            raise ModelFileError(
                source.path,
                f"{where} → name",
                f"{name!r} is not a name; give a text of 1 to 200 characters, or leave name out (the path "
                "names the value)",
                name,
            )
        spec = {k: v for k, v in row.items() if k not in _ROW_FIELDS}
        out.append(ScatterRow(path, name, spec))  # as a study's [[parameters]] row holds them
    return out


def _cause(exc: BaseException) -> ModelError | None:
    """The :class:`~mechdyn.errors.ModelError` a study error was raised from (the study's parameter
    reader re-raises a scatter table's error with the study file's place, ``from None``; the original,
    which names the field, is kept as the context)."""
    seen = exc.__cause__ or exc.__context__
    return seen if isinstance(seen, ModelError) else None


def _parameter(tree: ModelTree, row: ScatterRow, where: str, path: str) -> Parameter:
    """The study parameter a row makes, its errors as the file's (the field the error is about)."""
    from mechdyn.studies.errors import StudyError
    from mechdyn.studies.parameters import Parameter
    from mechdyn.studies.paths import PathError
    from mechdyn.units import UnitError

    try:
        nature = tree.nature(tree.resolve(row.path)[0])
        if nature.kind != "quantity":  # (the parameter reader would ask for its levels)
            raise ModelFileError(
                path,
                f"{where} → path",
                f"{row.path!r} is {nature.describe() or 'not a quantity'}; a scatter is given to a "
                "quantity (a number, with its unit or without): give the path of one",
                row.path,
            )
        (made,) = Parameter.from_spec(tree, row.path, name=row.name, scatter=dict(row.spec), where="")
    except ModelFileError:
        raise
    except PathError as exc:
        message = str(exc).removeprefix(f"{path}: ")
        raise ModelFileError(path, f"{where} → path", message, row.path) from None
    except (StudyError, UnitError, ValueError) as exc:
        cause = _cause(exc)
        if cause is not None:
            field = cause.field or "distribution"
            value = row.spec.get(field)
            raise ModelFileError(path, f"{where} → {field}", cause.detail, value) from None
        message = str(exc).removeprefix(" → scatter").removeprefix(": ").strip()
        raise ModelFileError(path, f"{where} → path", message, row.path) from None
    return made


def _correlations(
    source: ModelSource, names: list[str]
) -> tuple[tuple[tuple[str, str, float, str], ...], np.ndarray | None]:
    """The ``[[correlations]]`` rows, checked as a tolerance study checks its own, and the copula's
    matrix: ``R = 2 sin(π ρ_S / 6)`` for a Spearman coefficient (Kruskal, *JASA* 53, 1958)."""
    import numpy as np

    raw = _tables(
        source,
        "correlations",
        "each correlated pair as a [[correlations]] table with between = [name_a, name_b] and coefficient",
    )
    if not raw:
        return (), None
    if not names:
        raise ModelFileError(
            source.path,
            "[[correlations]]",
            "correlates values the file gives no scatter; give the values their [[scatter]] rows, or "
            "remove the [[correlations]]",
        )
    rows: list[tuple[str, str, float, str]] = []
    R = np.eye(len(names))
    given: dict[frozenset[str], int] = {}
    for i, row in enumerate(raw):
        where = f"[[correlations]] #{i + 1}"
        for key in row:
            if key not in CORRELATION_FIELDS:
                near = difflib.get_close_matches(str(key), CORRELATION_FIELDS, n=1)
                hint = (
                    f"did you mean {near[0]!r}?"
                    if near
                    else f"expected one of {', '.join(CORRELATION_FIELDS)}"
                )
                raise ModelFileError(source.path, f"{where} → {key}", f"unknown field {key!r}; {hint}")
        between = row.get("between")
        if not (isinstance(between, list) and len(between) == 2 and all(isinstance(b, str) for b in between)):
            raise ModelFileError(
                source.path,
                f"{where} → between",
                f"{between!r}: give the two scattered values' names, e.g. between = "
                f"[{', '.join(repr(n) for n in names[:2])}]",
                between,
            )
        a, b = between
        for name in (a, b):
            if name not in names:
                near = difflib.get_close_matches(name, names, n=1)
                raise ModelFileError(
                    source.path,
                    f"{where} → between",
                    f"{name!r} is not the name of a [[scatter]] row"
                    + (f" (did you mean {near[0]!r}?)" if near else "")
                    + f"; give two of {', '.join(map(repr, names))}",
                    name,
                )
        if a == b:
            raise ModelFileError(
                source.path,
                f"{where} → between",
                f"{a!r} is paired with itself; give two different values",
                a,
            )
        pair = frozenset((a, b))
        if pair in given:
            raise ModelFileError(
                source.path,
                f"{where} → between",
                f"the pair {a!r}, {b!r} is given already in #{given[pair]}; give each pair once (the "
                "correlation is symmetric)",
                between,
            )
        given[pair] = i + 1
        rho = row.get("coefficient")
        if not (
            isinstance(rho, (int, float))
            and not isinstance(rho, bool)
            and math.isfinite(rho)
            and abs(rho) < 1
        ):
            raise ModelFileError(
                source.path,
                f"{where} → coefficient",
                f"{rho!r} is not a correlation coefficient; give a number between -1 and 1 (exclusive), "
                "e.g. coefficient = 0.5",
                rho,
            )
        measure = row.get("measure", "normal")
        if measure not in ("normal", "spearman"):
            raise ModelFileError(
                source.path,
                f"{where} → measure",
                f"{measure!r}; give 'normal' (the Gaussian copula's own) or 'spearman' (a rank correlation)",
                measure,
            )
        r = 2.0 * math.sin(math.pi * rho / 6.0) if measure == "spearman" else float(rho)
        R[names.index(a), names.index(b)] = R[names.index(b), names.index(a)] = r
        rows.append((a, b, float(rho), measure))
    least = float(np.linalg.eigvalsh(R).min())
    if least <= 1e-10:
        pairs = ", ".join(f"{a} – {b}: {rho:g}" for a, b, rho, _ in rows)
        raise ModelFileError(
            source.path,
            "[[correlations]]",
            f"the coefficients ({pairs}) contradict each other: the correlation matrix is not positive "
            f"definite (its smallest eigenvalue is {least:.3g}); weaken one of them",
        )
    return tuple(rows), R


def read_scatter(source: ModelSource, tree: ModelTree | None = None) -> ModelScatter | None:
    """The scatter a model file gives its values, checked; None when it has no ``[[scatter]]`` rows.

    Each row's path is resolved by the study's path resolver (:class:`mechdyn.studies.paths.ModelTree`)
    and its scatter read as a study parameter's ``scatter`` table
    (:func:`mechdyn.uncertainty.variable_from_dict`, the model's value the default median, mean or
    nominal), so that a row here and the same row in a study's ``[[parameters]]`` make the same
    variable.

    Parameters
    ----------
    source : ModelSource
        The model file (:func:`mechdyn.io.read`), with the files it refers to.
    tree : ModelTree, optional
        The model as a study sees it (a study's own, so that the parameters address its variants);
        made from ``source`` when not given.

    Returns
    -------
    ModelScatter or None

    Raises
    ------
    ModelFileError
        Naming the file, the row and field (``[[scatter]] #2 (name = 'k') → cov``), the value and
        the fix: a path that names no value of the model (with the paths nearby), a value that is not
        one quantity, an unknown distribution or field, a parameter out of its range (a negative
        ``cov``), a name or a value given twice, a bad correlation.
    """
    if not any(k in source.data for k in SCATTER_TABLES):
        return None
    rows = _rows(source)
    if tree is None:
        from mechdyn.studies.paths import ModelTree

        tree = ModelTree(source)
    raw = source.data.get("scatter", [])
    parameters: list[Parameter] = []
    named: dict[str, int] = {}
    moved: dict[Any, int] = {}
    for i, row in enumerate(rows):
        where = _label(raw, i)
        made = _parameter(tree, row, where, source.path)
        if made.name in named:
            raise ModelFileError(
                source.path,
                f"{where} → name",
                f"{made.name!r} names [[scatter]] #{named[made.name]} already; give each row a name of its "
                "own",
                made.name,
            )
        named[made.name] = i + 1
        for loc in made.locations:
            if loc in moved:
                raise ModelFileError(
                    source.path,
                    f"{where} → path",
                    f"{row.path!r} gives a value [[scatter]] #{moved[loc]} scatters already ({loc.path!r}); "
                    "give each value one row",
                    row.path,
                )
            moved[loc] = i + 1
        parameters.append(made)
    correlations, R = _correlations(source, [p.name for p in parameters])
    if not parameters:
        return None
    return ModelScatter(source.path, tuple(rows), tuple(parameters), correlations, R)
