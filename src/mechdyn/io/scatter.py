"""The scatter a model file gives its own values: ``[[scatter]]`` and ``[[correlations]]``.

Any model file may say how its values scatter, in the tables a tolerance study's parameters use::

    [[scatter]]
    path = "support.stiffness"          # a study's path into this model (`mechdyn study --paths`)
    name = "support stiffness"          # optional (default: the path)
    distribution = "lognormal"          # the study parameter's `scatter` table, written in the row
    cov = 0.15                          # median: the model's value

    [[scatter]]
    path = "support.damping_ratio"
    distribution = "uniform"
    low = 0.03
    high = 0.07

    [[correlations]]                    # optional; the form of a tolerance study's [[correlations]]
    between = ["support stiffness", "support.damping_ratio"]
    coefficient = 0.3
    measure = "normal"                  # or "spearman"

Each row but its ``path`` and ``name`` is read exactly as a study parameter's ``scatter`` table
(:func:`mechdyn.uncertainty.variable_from_dict`: normal, lognormal, uniform, triangular, levels,
truncated by lower/upper, or a named tolerance class with its source), on the parameter the study's
path resolver makes of the path (:meth:`mechdyn.studies.spec.Parameter.from_spec`), so that a row
here and the same row in a study give the same variable. The model type's own schema never sees these
tables (:func:`strip`); every analysis ignores them. :func:`read_scatter` checks them (the path a
value of this model, each name once, each value scattered once, the correlations a valid matrix) and
gives a :class:`ModelScatter`; :func:`mechdyn.load` checks them as it loads the file, a ``tolerance``
study takes them as the default scatter of its model, and :func:`mechdyn.save` writes them back
(:func:`scatter_text`).
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from mechdyn.errors import MechdynError, ModelError, ModelFileError

if TYPE_CHECKING:
    import numpy as np

    from mechdyn.io.modelfile import ModelSource
    from mechdyn.studies.paths import ModelTree
    from mechdyn.studies.spec import Parameter
    from mechdyn.uncertainty import InputSpace, Variable

__all__ = [
    "CORRELATION_FIELDS",
    "SCATTER_TABLES",
    "ModelScatter",
    "ScatterRow",
    "check_written",
    "read_scatter",
    "reference_tables",
    "scatter_text",
    "strip",
]

SCATTER_TABLES = ("scatter", "correlations")
"""The top-level tables of a model file that give its scatter (no model type's schema reads them)."""

CORRELATION_FIELDS = ("between", "coefficient", "measure")
"""The fields of a ``[[correlations]]`` row, as a tolerance study's."""

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


# -- reading --------------------------------------------------------------------------------------------


def strip(data: Mapping[str, Any]) -> Mapping[str, Any]:
    """A model file's parsed TOML without its scatter tables, for its type's schema: every model
    type accepts them and none reads them (a file that is no model file, without ``[model]``, is
    given back as it is).

    Parameters
    ----------
    data : mapping
        The parsed TOML.
    """
    if not isinstance(data.get("model"), Mapping) or not any(k in data for k in SCATTER_TABLES):
        return data
    return {k: v for k, v in data.items() if k not in SCATTER_TABLES}


def _label(rows: Any, i: int, table: str = "scatter") -> str:
    """``[[scatter]] #2 (name = 'x')``, as the file reader names a row."""
    label = f"[[{table}]] #{i + 1}"
    row = rows[i] if isinstance(rows, list) and i < len(rows) else None
    if isinstance(row, Mapping) and isinstance(row.get("name"), str):
        label += f" (name = {row['name']!r})"
    return label


def _rows(source: ModelSource) -> list[ScatterRow]:
    """The ``[[scatter]]`` rows, their form checked (a table each, a text path, an optional name)."""
    raw = source.data.get("scatter", [])
    if not isinstance(raw, list) or not all(isinstance(r, Mapping) for r in raw):
        raise ModelFileError(
            source.path,
            "[[scatter]]",
            f"{raw!r} is not an array of tables; write each scattered value as a [[scatter]] table "
            'with path = "..." and its distribution',
            raw,
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
    from mechdyn.studies.paths import PathError
    from mechdyn.studies.spec import Parameter
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

    raw = source.data.get("correlations", [])
    if not isinstance(raw, list) or not all(isinstance(r, Mapping) for r in raw):
        raise ModelFileError(
            source.path,
            "[[correlations]]",
            f"{raw!r} is not an array of tables; write each correlated pair as a [[correlations]] table "
            "with between = [name_a, name_b] and coefficient",
            raw,
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


# -- writing --------------------------------------------------------------------------------------------


def scatter_text(source: ModelSource | None) -> str:
    """The ``[[scatter]]`` and ``[[correlations]]`` tables of a model file, as it writes them (each
    value as read, so that a saved file gives the same scatter); ``""`` when it has none.

    Parameters
    ----------
    source : ModelSource or None
        The file a model was loaded from.
    """
    from mechdyn.io.writing import TomlDocument

    if source is None or not any(k in source.data for k in SCATTER_TABLES):
        return ""
    doc = TomlDocument()
    doc.comment("how the model's values scatter (a tolerance study's default; no analysis reads it)")
    for table in SCATTER_TABLES:
        for row in source.data.get(table, []):
            doc.table(table, row, array=True)
    return doc.text()


def check_written(text: str, path: str, source: ModelSource) -> None:
    """Check that a saved file's scatter still addresses its values (a writer may write a table in
    another form than the file it read: a mount estimated from its drawing written as numbers).

    Parameters
    ----------
    text : str
        The saved file's text.
    path : str
        Where it is written (the files it refers to are named relative to it).
    source : ModelSource
        The file the model was loaded from.

    Raises
    ------
    MechdynError
        Naming the row whose value the saved file does not hold.
    """
    import hashlib
    import tomllib

    from mechdyn.io.modelfile import ModelSource

    written = ModelSource(path, text, hashlib.sha256(text.encode()).hexdigest(), tomllib.loads(text))
    try:
        read_scatter(written)
    except ModelFileError as exc:
        raise MechdynError(
            f"mechdyn.save: {source.path}: {exc.location}: the saved file cannot hold this scatter "
            f"({exc.detail}); write the file's [[scatter]] for the saved form by hand"
        ) from None


# -- the model-file reference ---------------------------------------------------------------------------


def reference_tables() -> list[Any]:
    """The ``[[scatter]]`` and ``[[correlations]]`` tables as the model-file reference lists them for
    every model type (:func:`mechdyn.io.reference.reference`), their fields read from the scatter
    reader's own (:data:`mechdyn.uncertainty.tables.DISTRIBUTION_KEYS`), so that they cannot drift.

    Returns
    -------
    list of mechdyn.io.reference.FileTable
    """
    from mechdyn.io.reference import FieldRow, FileTable
    from mechdyn.uncertainty.tables import DISTRIBUTION_KEYS, TOLERANCE_KEYS
    from mechdyn.uncertainty.tolerances import tolerance_classes

    kinds = ", ".join(f"``{k}`` ({', '.join(v)})" for k, v in DISTRIBUTION_KEYS.items())
    classes = ", ".join(f"``{k}``" for k in tolerance_classes())
    scatter = FileTable(
        "scatter",
        True,
        False,
        "How one value of the model scatters, as a tolerance study's parameter's ``scatter`` table "
        "written in the row. No analysis reads it; a tolerance study on the file takes it as its "
        "default (its own [[parameters]] override a row of the same value).",
        [
            FieldRow(
                "path",
                "text",
                "**required**",
                "The value, as a study's path (``support.stiffness``, ``mounts.*.stiffness``; "
                "``mechdyn study --paths FILE`` lists them); a quantity.",
            ),
            FieldRow("name", "text", "the path", "The value's name in a study's tables."),
            FieldRow(
                "distribution",
                "text",
                "optional",
                f"One of {kinds}; ``lower`` and ``upper`` truncate any of them. The model's value is the "
                "default ``mean`` of a normal and ``median`` of a lognormal.",
            ),
            FieldRow(
                "tolerance",
                "text",
                "optional",
                f"Instead of a distribution, a named tolerance class with its source: {classes}; its "
                f"fields {', '.join(TOLERANCE_KEYS)}. The model's value is its nominal.",
            ),
        ],
    )
    correlations = FileTable(
        "correlations",
        True,
        False,
        "Two of the file's scattered values correlated (the Gaussian copula), as a tolerance study's "
        "``[[correlations]]``.",
        [
            FieldRow("between", "list of 2 texts", "**required**", "The two ``[[scatter]]`` rows' names."),
            FieldRow(
                "coefficient", "number", "**required**", "The correlation, between -1 and 1 (exclusive)."
            ),
            FieldRow(
                "measure",
                "text",
                "``normal``",
                "``normal``: the copula's own correlation; ``spearman``: a rank correlation.",
            ),
        ],
    )
    return [scatter, correlations]
