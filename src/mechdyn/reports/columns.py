"""A study's values as its study file shows them: one column per parameter and per output, each with
the unit it is shown in and the conversion from the SI value the results database holds.

The HTML report of a study, the dashboard's study page and ``mechdyn results export --csv`` show a
study's variants through these columns (``mechdyn results list --study`` and ``results compare`` show
the outputs the same way, through :func:`mechdyn.studies.run.display_units`): a parameter in the unit
its model file writes it in (:attr:`Parameter.unit <mechdyn.studies.Parameter>`), an output in the
unit of its ``[[outputs]]`` row (:class:`~mechdyn.studies.Watched`), else in SI. A study built in
Python has no file units: its values are shown in SI, with the SI unit named. Nothing here converts
by itself: a parameter is divided by its :attr:`factor` as :meth:`Parameter.shown` does, an output
goes through :meth:`Watched.show`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

__all__ = ["Column", "stored_columns", "study_columns"]


def _identity(value: float) -> float:
    return value


@dataclass(frozen=True)
class Column:
    """One parameter or output of a study as shown.

    Attributes
    ----------
    key : str
        The parameter's name or the output's summary key, as the database names it.
    role : {"parameter", "output"}
        Which of the two it is.
    unit : str
        The unit it is shown in (the study file's, else its SI unit); ``""`` for a pure number or a
        unit that is not known.
    si_unit : str
        Its SI unit, as the database holds it; ``""`` for a pure number or a unit that is not known.
    convert : callable
        ``SI value -> shown value``.
    """

    key: str
    role: str
    unit: str
    si_unit: str
    convert: Callable[[float], Any] = field(default=_identity, compare=False, repr=False)
    """(a choice's column: the index → its name)"""
    levels: tuple[str, ...] = ()
    """A choice's names, in the order of the indices the database holds; empty for a number."""

    def number(self, variant: Any) -> float | None:
        """This column's value of a stored variant as a number for a plot axis: the shown value, or a
        choice's index (its axis labelled with :attr:`levels`).

        Parameters
        ----------
        variant : StoredVariant
            A variant, its parameters and outputs in SI.
        """
        if not self.levels:
            return self.of(variant)
        x = (variant.parameters if self.role == "parameter" else variant.outputs).get(self.key)
        return float(x) if isinstance(x, (int, float)) and math.isfinite(x) else None

    @property
    def label(self) -> str:
        """``key [unit]`` (``key`` alone without a unit), as a column header or an axis title."""
        return f"{self.key} [{self.unit}]" if self.unit else self.key

    def shown(self, value: Any) -> Any:
        """A value in the shown unit; None for a missing or non-finite value.

        Parameters
        ----------
        value : float or None
            The value in its SI unit, as stored.
        """
        if value is None or isinstance(value, bool):
            return None
        try:
            x = float(value)  # a float, or a numpy scalar
        except (TypeError, ValueError):
            return None
        return self.convert(x) if math.isfinite(x) else None

    def shown_array(self, values: Any) -> Any:
        """Many SI values in the shown unit at once (NaN where missing): a unit conversion is affine,
        so two values of :meth:`shown` give it for all (checked on a third); any other conversion
        goes value by value.

        Parameters
        ----------
        values : array_like
            Values in the SI unit, as stored (NaN or None where missing).

        Returns
        -------
        ndarray
        """
        import numpy as np

        x = np.array(
            [np.nan if v is None else v for v in values] if isinstance(values, list) else values, dtype=float
        )
        probe = 17.0  # any third value: an affine map through 0 and 1 meets it
        zero, one, far = self.shown(0.0), self.shown(1.0), self.shown(probe)
        if None not in (zero, one, far) and not self.levels:
            a, b = float(one) - float(zero), float(zero)
            if math.isclose(a * probe + b, float(far), rel_tol=1e-12, abs_tol=1e-300):
                return a * x + b
        out = [self.shown(v) if math.isfinite(v) else None for v in x]
        return np.array([np.nan if v is None else float(v) for v in out], dtype=float)

    def of(self, variant: Any) -> Any:
        """This column's value of a stored variant, in the shown unit.

        Parameters
        ----------
        variant : StoredVariant
            A variant, its parameters and outputs in SI.
        """
        values = variant.parameters if self.role == "parameter" else variant.outputs
        return self.shown(values.get(self.key))


def _si_unit(unit: str, factor: float) -> str:
    """The SI unit of ``unit`` as a result key names it (``"mm"`` → ``"m"``, ``"kN/mm"`` → ``"N/m"``),
    or ``unit`` itself when it is SI (``factor`` 1) and no key names it; ``""`` for a pure number or
    a unit that is not known."""
    from mechdyn.units import key_suffix, key_unit

    suffix = key_suffix(unit) if unit else ""
    si = key_unit("x_" + suffix) if suffix else None
    if si in (None, "1"):
        return unit if unit and factor == 1.0 else ""
    return str(si)


def _key_si_unit(key: str) -> str:
    """The SI unit a summary key or parameter name ends with (``"stroke_m"`` → ``"m"``), else ``""``."""
    from mechdyn.units import key_unit

    u = key_unit(key.split(".")[-1])
    return "" if u in (None, "1") else str(u)


def _parameter(p: Any) -> Column:
    if getattr(p, "choices", ()):  # a choice's value is the index of its level: shown by its name
        return Column(p.name, "parameter", "", "", p.shown, tuple(p.shown(i) for i in range(len(p.choices))))
    unit = "" if p.unit in ("1", "dimensionless") else p.unit
    factor = float(p.factor)
    return Column(p.name, "parameter", unit, _si_unit(unit, factor), lambda v: v / factor)


def _output(w: Any) -> Column:
    def show(v: float) -> float | None:
        shown = w.show(v)
        return None if shown is None else float(shown)

    return Column(w.key, "output", w.shown_unit, "" if w.unit in ("", "1") else w.unit, show)


def study_columns(study: Any) -> list[Column]:
    """The columns of a study: its parameters, then its outputs, each in the unit the study shows it
    in.

    Parameters
    ----------
    study : Study
        Read from a study file (:func:`mechdyn.studies.load_study`, or rebuilt from the database by
        :func:`mechdyn.studies.run.stored_study`) or built in Python.

    Returns
    -------
    list of Column
    """
    return [*(_parameter(p) for p in study.parameters), *(_output(w) for w in study.watched)]


def stored_columns(store: Any, name: str, variants: Sequence[Any] = ()) -> list[Column]:
    """The columns of a stored study, in the order the database names its parameters and outputs:
    in the study file's units, rebuilt from the stored definition
    (:func:`mechdyn.studies.run.stored_study`, as :func:`~mechdyn.studies.run.display_units` does for
    the outputs); in SI, the SI unit named, for a study built in Python (no file units) or one whose
    definition this mechdyn cannot rebuild.

    Parameters
    ----------
    store : ResultStore
        The results database (read-only is enough).
    name : str
        The study's name.
    variants : sequence of StoredVariant
        Its variants, if read already: the SI unit of a Python parameter is read from the text it
        was stored with.

    Returns
    -------
    list of Column
    """
    from mechdyn.errors import MechdynError
    from mechdyn.store.store import StoreError
    from mechdyn.studies.run import stored_study
    from mechdyn.studies.storage import StudyStore

    st = StudyStore(store).study(name)
    try:
        shown = {(c.role, c.key): c for c in study_columns(stored_study(store, name))}
    except StoreError:
        raise
    except MechdynError:  # built in Python (or not to be rebuilt): SI, the unit named
        shown = {}
    params = list(st.parameter_names) or list(dict.fromkeys(k for v in variants for k in v.parameters))
    outputs = list(st.output_names) or list(dict.fromkeys(k for v in variants for k in v.outputs))
    columns = []
    for key in params:
        columns.append(shown.get(("parameter", key)) or _given_parameter(key, variants))
    for key in outputs:
        si = _key_si_unit(key)
        columns.append(shown.get(("output", key)) or Column(key, "output", si, si))
    return columns


def _given_parameter(name: str, variants: Sequence[Any]) -> Column:
    """A parameter of a study built in Python, in the unit its variants' text names (the text a
    parameter is stored with: ``"12.5 kg"``; a :meth:`Parameter.function <mechdyn.studies.Parameter>`
    is given in SI), else in SI with the unit its name ends with."""
    from mechdyn.units import registry

    unit = _key_si_unit(name)
    for v in variants:
        text = v.given.get(name)
        if isinstance(text, str) and text.strip():
            parts = text.strip().split(None, 1)
            if len(parts) == 2:
                unit = parts[1]
            break
    if not unit:
        return Column(name, "parameter", "", "")
    import pint

    try:
        factor = float(registry().Quantity(1.0, unit).to_base_units().magnitude)
    except (pint.errors.PintError, ValueError, AttributeError, TypeError):  # not a unit: SI, unnamed
        return Column(name, "parameter", "", "")
    return Column(name, "parameter", unit, _si_unit(unit, factor), lambda v: v / factor)
