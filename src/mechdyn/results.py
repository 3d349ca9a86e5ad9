"""The one result protocol every analysis follows.

Every analysis function returns an immutable result object with the same small interface, so that
the command line, the results database, design studies and reports handle all of them alike:

``summary()``
    JSON-ready scalars (and small nested tables of scalars) in SI, each key ending with its unit
    (``stroke_m``, ``driving_torque_peak_Nm``, ``frequencies_hz``); :func:`mechdyn.units.key_unit`
    reads the unit back from the key.
``to_frame()``
    The per-sample table (per crank angle, time step, frequency, mode or mesh position) as a
    :class:`pandas.DataFrame`, with the unit at the end of every column name.
``tables(**display_units)``
    The titled tables the command line prints, in the display units given as keyword arguments
    (``force_unit="tonf"``), converted by the package's one unit registry.
``plots(**display_units)`` / ``plot()``
    The figures: a mapping of file name to a callable that draws one figure and returns its axes;
    ``plot()`` draws the first.
``arrays()``
    Named arrays with their units, kept bit for bit by the results database.
``warnings``
    What the user should know about this result (e.g. a concave pitch curve), as text.

The protocol is a mixin (:class:`Result`) with defaults for the last three; the test suite walks every
registered analysis (:mod:`mechdyn.registry`) and checks it.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import numpy as np
    import pandas as pd

__all__ = ["Result", "Table", "frame_arrays", "summary_table"]


@dataclass(frozen=True)
class Table:
    """A titled table for a terminal or a report.

    Attributes
    ----------
    title : str
    columns : list of str
        Column headers, each with its unit in brackets where it has one.
    rows : list of list
        Rows of values: numbers (formatted by the renderer), text, or None (shown as "—").
    note : str
        A sentence under the table (a verdict, what the numbers mean), shown by every renderer;
        a sentence never sits in a cell, where it would stretch its column.
    per_value : bool
        Every number is written on its own (:func:`mechdyn.numbers.number_text`), never in a format
        its column shares (:func:`mechdyn.numbers.column_format`, which shows a value below a
        thousandth of the column's largest as near zero): a study's tables, whose columns hold an
        output's changes from a few per cent to a few millionths of one. A table with a ``unit``
        column is written so too, each row being another quantity.
    """

    title: str
    columns: list[str]
    rows: list[list[Any]]
    note: str = ""
    per_value: bool = False


def frame_arrays(frame: pd.DataFrame) -> dict[str, tuple[np.ndarray, str]]:
    """The columns of a result table as named arrays with the unit read from each column name.

    Parameters
    ----------
    frame : pandas.DataFrame
        A result's table, each numeric column named with its unit (``angle_deg``).
    """
    from mechdyn.units import key_unit

    return {str(c): (frame[c].to_numpy(), key_unit(str(c)) or "") for c in frame.columns}


def summary_table(
    summary: dict[str, Any], *, skip: tuple[str, ...] = (), display_units: Mapping[str, str] | None = None
) -> Table:
    """The scalars of a summary as a table: each key in words, its value in the unit a designer reads
    it in (:func:`mechdyn.units.readable`: a stroke in mm, a force in kN), that unit.

    The crank angle of an extreme reads "… at" ("inertia force max at 114 deg" beside "inertia force
    max 529.6 kN").

    Parameters
    ----------
    summary : dict
        A result's summary (SI values, keys ending with their unit).
    skip : tuple of str
        Keys to leave out.
    display_units : mapping, optional
        ``force_unit`` (e.g. ``"tonf"``) and ``length_unit`` (e.g. ``"m"``) show every force and
        every length in that unit instead.
    """
    from mechdyn.units import convert, key_label, readable

    display_units = display_units or {}
    chosen = {"N": display_units.get("force_unit"), "m": display_units.get("length_unit")}
    scalars = {
        k: v
        for k, v in summary.items()
        if isinstance(v, (int, float, str)) and not isinstance(v, bool) and k not in skip
    }
    labels = {k: key_label(k) for k in scalars}
    words = [label for label, _ in labels.values()]
    rows = []
    for k, v in scalars.items():
        label, unit = labels[k]
        if unit == "deg" and words.count(label) > 1:  # the angle of an extreme named beside it
            label += " at"
        if isinstance(v, float):  # a count or a text stays as it is
            pick = chosen.get(unit)
            if pick:
                v, unit = float(convert(float(v), unit, pick)), pick
            else:
                v, unit = readable(float(v), unit)
        rows.append([label, v, unit])
    return Table("summary", ["quantity", "value", "unit"], rows)


def figure_text(value: Any, unit: str) -> str | None:
    """A summary value as a headline or a repr writes it: four significant digits in the unit its
    size reads best in (:func:`mechdyn.units.readable`); a list of numbers by its first three values
    in its own unit; None for anything else (text, a table, a count).

    Parameters
    ----------
    value : any
        A summary value, SI.
    unit : str
        Its unit as :func:`mechdyn.units.key_label` shows it.
    """
    from mechdyn.units import readable

    if isinstance(value, list):  # in the key's own unit (natural frequencies in Hz)
        numbers = [f"{v:.4g}" for v in value[:3] if isinstance(v, (int, float)) and math.isfinite(v)]
        more = ", …" if len(value) > 3 else ""
        return f"{', '.join(numbers)}{more} {unit}".strip() if numbers else None
    if not isinstance(value, float) or not math.isfinite(value):
        return None
    v, shown_unit = readable(float(value), unit)
    return f"{v:.4g} {shown_unit}".strip()


def nested_tables(summary: dict[str, Any]) -> list[Table]:
    """The nested values of a summary (a dict per key: peaks per joint, per mount, per mode) as one
    table each, titled in words, each value in the unit a designer reads it in.

    Parameters
    ----------
    summary : dict
        A result's summary (SI values, keys ending with their unit).
    """
    from mechdyn.units import key_label, key_unit, readable

    tables = []
    for key, value in summary.items():
        if not isinstance(value, dict) or not value:
            continue
        title, unit = key_label(key)
        rows: list[list[Any]] = []

        def add(path: list[str], v: Any, unit: str, rows: list[list[Any]] = rows) -> None:
            if isinstance(v, dict):
                for k, x in v.items():
                    words, u = key_label(str(k))
                    add([*path, words], x, u if key_unit(str(k)) else unit)
                return
            if isinstance(v, (list, tuple)):
                v = ", ".join(f"{x:.4g}" if isinstance(x, float) else str(x) for x in v) or "none"
            elif isinstance(v, float):
                v, unit = readable(v, unit)
            rows.append([" · ".join(path), v, unit])

        add([], value, unit)
        tables.append(Table(title, ["quantity", "value", "unit"], rows))
    return tables


def _as_written(plot: Callable[..., Any]) -> Callable[..., Any]:
    """``plot`` returning its whole figure (a result's plot may have several panels), every text shown
    as written (:func:`mechdyn.plotting.plain_text`)."""
    import functools

    @functools.wraps(plot)
    def drawn(self: Any, *args: Any, **kwargs: Any) -> Any:
        return _figure(plot(self, *args, **kwargs))

    return drawn


def _figure(ax: Any) -> Any:
    """The figure of an axes (or an array of them), its texts as written; None stays None."""
    fig = getattr(ax.flat[0] if hasattr(ax, "flat") else ax, "figure", None)  # one axes or an array
    if fig is None:
        return ax
    from mechdyn.plotting import plain_text

    fig.canvas.draw()  # the tick labels are made when the figure is first drawn
    plain_text(fig)
    return fig


class Result:
    """Mixin of the result protocol; subclasses are frozen dataclasses.

    A subclass implements :meth:`summary` and :meth:`to_frame`, and overrides :meth:`tables`,
    :meth:`plots`, :meth:`arrays` and :attr:`warnings` where the defaults do not fit.
    """

    def summary(self) -> dict[str, Any]:
        """Scalars with unit-suffixed keys, SI (see the module docstring)."""
        raise NotImplementedError

    def to_frame(self) -> pd.DataFrame:
        """The per-sample table, one unit-suffixed column per quantity."""
        raise NotImplementedError

    def tables(self, **display_units: str) -> list[Table]:
        """Titled tables for the terminal; the default lists the summary's scalars with units
        (``force_unit`` and ``length_unit``: see :func:`summary_table`)."""
        return [summary_table(self.summary(), display_units=display_units)]

    def plots(self, **display_units: str) -> dict[str, Callable[[], Any]]:
        """File name → callable drawing one figure and returning its matplotlib axes."""
        return {}

    def plot(self, **display_units: Any) -> Any:
        """Draw the first of :meth:`plots` and return its matplotlib Figure, every panel of it (None
        when the result has no plot); a notebook shows it.

        Its texts are shown as written (:func:`mechdyn.plotting.plain_text`), as in saved plots and
        reports: a ``$`` in a name never starts a formula in a notebook either.

        Parameters
        ----------
        **display_units : str
            ``force_unit``, ``length_unit``: as for :meth:`plots`.
        """
        plots = self.plots(**display_units)
        return _figure(next(iter(plots.values()))()) if plots else None

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        if "plot" in cls.__dict__:  # a result's own plot() shows its texts as written too
            cls.plot = _as_written(cls.__dict__["plot"])  # type: ignore[method-assign]

    def __repr__(self) -> str:
        """One line: the class and the first figures of the summary in words and readable units (the
        arrays a result holds would fill a screen). Results are ``@dataclass(repr=False)`` so that
        this one is theirs."""
        from mechdyn.units import key_label

        figures = []
        for key, value in self.summary().items():
            label, unit = key_label(key)
            shown = figure_text(value, unit)
            if shown is not None:
                figures.append(f"{label} {shown}")
            if len(figures) == 4:
                break
        return f"<{type(self).__name__}: {', '.join(figures)}>" if figures else f"<{type(self).__name__}>"

    def _repr_html_(self) -> str:
        """Its tables as HTML, for a notebook (the same cells as the report's)."""
        from mechdyn.cells import tables_html

        return tables_html(self.tables())

    def arrays(self) -> dict[str, tuple[np.ndarray, str]]:
        """Named arrays with units for the results database; by default the columns of :meth:`to_frame`."""
        return frame_arrays(self.to_frame())

    @property
    def warnings(self) -> tuple[str, ...]:
        """Notes on this result that the user should read (also issued as :class:`ModelWarning`)."""
        return ()


Result.plot = _as_written(Result.plot)  # type: ignore[method-assign]
