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
tables (:func:`strip`); every analysis ignores them. Reading and checking them (the path a value of
this model, each name once, each value scattered once, the correlations a valid matrix) needs the
study's path resolver, and lives with the studies (:func:`mechdyn.studies.model_scatter.read_scatter`,
reached from here through :func:`mechdyn.registry.model_scatter`): :func:`mechdyn.load` checks them
as it loads the file, a ``tolerance`` study takes them as the default scatter of its model, and
:func:`mechdyn.save` writes them back (:func:`scatter_text`, :func:`check_written`).
"""

from __future__ import annotations

from typing import Any

from mechdyn.errors import MechdynError, ModelFileError
from mechdyn.io.modelfile import SCATTER_TABLES, ModelSource, strip
from mechdyn.io.reference_rows import FieldRow, FileTable

__all__ = [
    "CORRELATION_FIELDS",
    "SCATTER_TABLES",
    "check_written",
    "reference_tables",
    "scatter_text",
    "strip",
]

CORRELATION_FIELDS = ("between", "coefficient", "measure")
"""The fields of a ``[[correlations]]`` row, as a tolerance study's."""

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

    from mechdyn.registry import model_scatter

    written = ModelSource(path, text, hashlib.sha256(text.encode()).hexdigest(), tomllib.loads(text))
    try:
        model_scatter(written)
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
    list of mechdyn.io.reference_rows.FileTable
    """
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
