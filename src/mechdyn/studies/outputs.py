"""What a study looks at: the outputs it reads from each variant's summary, the objectives it
minimises or maximises and the constraints it keeps, each with the unit to show it in.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any

__all__ = [
    "Constraint",
    "Objective",
    "Statistic",
    "Watched",
    "output_problem",
    "output_value",
    "statistic_level",
]


@dataclass(frozen=True)
class Watched:
    """An output of the analysis a study looks at: a summary key (nested keys with dots, e.g.
    ``joint_force_peak_N.F`` or ``excitation.stroke_m``) and the unit to show it in.

    Parameters
    ----------
    key : str
        The summary key.
    unit : str
        Its SI unit (from the key or the registry).
    display : str
        The unit to show it in (``""``: SI).
    """

    key: str
    unit: str
    display: str

    def show(self, value: float | None) -> float | None:
        """``value`` (SI) in the display unit; None for a missing or non-finite value.

        Parameters
        ----------
        value : float or None
            The output's value, in its SI unit.
        """
        from mechdyn.units import convert

        if value is None or not math.isfinite(value):
            return None
        return float(convert(value, self.unit, self.display)) if self.display else value

    def difference(self, value: float | None) -> float | None:
        """A difference of the output (an effect, a margin: ``value`` SI) in the display unit: a scale,
        no offset (a difference of 1 K is 1 °C); None for a missing value.

        Parameters
        ----------
        value : float or None
            The difference, in the output's SI unit.
        """
        from mechdyn.units import convert

        if value is None:
            return None
        if not self.display or self.display == self.unit:
            return float(value)
        return float(value) / float(convert(1.0, self.display, self.unit))

    @property
    def shown_unit(self) -> str:
        """The unit the output is shown in (its display unit, else SI; ``""`` for a pure number)."""
        unit = self.display or self.unit
        return "" if unit in ("", "1") else unit

    @property
    def words(self) -> str:
        """The output in words, as a summary table names it (``excitation · stroke`` for
        ``excitation.stroke_m``, a list entry by its number: ``frequencies 2``)."""
        from mechdyn.units import key_label

        named: list[str] = []
        for part in self.key.split("."):
            if part.isdigit() and named:  # the n-th entry of a list: "frequencies 2"
                named[-1] += f" {part}"
            else:
                named.append(key_label(part)[0])
        return " · ".join(named)

    @property
    def label(self) -> str:
        """The output in words with the unit it is shown in, as a reader writes it
        (``transmitted force range [tonf]``, ``driving torque range [N·m]``)."""
        from mechdyn.studies.cells import unit_text

        unit = unit_text(self.shown_unit)
        return f"{self.words} [{unit}]" if unit else self.words

    def readable(self, values: Iterable[float | None]) -> Watched:
        """This output in the unit its values read best in, where the study file names none: the
        unit a summary shows a value of that size in (:func:`mechdyn.units.readable_unit`: a length
        in mm or µm, a force in kN or MN, by the largest of ``values``), so that a study's table, its
        plots and the analysis' own summary agree. An output with a display unit keeps it.

        Parameters
        ----------
        values : iterable of float or None
            The values it is shown with (a table's column), in its SI unit.

        Examples
        --------
        >>> from mechdyn.studies.outputs import Watched
        >>> Watched("stroke_m", "m", "").readable([1.4963]).label
        'stroke [mm]'
        """
        from dataclasses import replace

        from mechdyn.units import SHOWN_UNITS, readable_unit

        if self.display or self.unit in ("", "1"):
            return self
        sizes = [abs(float(v)) for v in values if v is not None and math.isfinite(v)]
        display, _ = readable_unit(max(sizes, default=0.0), SHOWN_UNITS.get(self.unit, self.unit))
        return self if display == self.unit else replace(self, display=display)


@dataclass(frozen=True)
class Statistic(Watched):
    """A statistic of an output over the scatter of an ``optimize`` study with scatter (robust
    design): its value at each design, estimated from the study's common samples
    (:mod:`mechdyn.studies.kinds.robust`), stored under ``key`` = ``OUTPUT.STATISTIC``
    (``displacement_max_m.q95``), its confidence interval's ends under ``KEY_low`` and ``KEY_high``.

    Parameters
    ----------
    key, unit, display : str
        As :class:`Watched`: the stored key, its SI unit (the output's; ``""`` for a probability) and
        the display unit.
    of : str
        The output's summary key.
    statistic : str
        ``"mean"``, ``"std"``, ``"qNN"`` (the NN % quantile, e.g. ``"q95"``) or ``"p_exceed"`` (the
        probability of the output's limit, fraction).
    bound : str
        ``""`` for the estimate, ``"low"`` or ``"high"`` for an end of its interval.
    """

    of: str = ""
    statistic: str = ""
    bound: str = ""

    @property
    def words(self) -> str:
        """The statistic in words: ``q95 of displacement max``, ``P(exceed) of ...``, with ``(low)``
        or ``(high)`` for an end of its interval."""
        name = "P(exceed)" if self.statistic == "p_exceed" else self.statistic
        tail = f" ({self.bound})" if self.bound else ""
        return f"{name} of {Watched(self.of, self.unit, '').words}{tail}"

    def with_bound(self, bound: str) -> Statistic:
        """The companion that holds one end of the estimate's interval.

        Parameters
        ----------
        bound : {"low", "high"}
        """
        from dataclasses import replace

        return replace(self, key=f"{self.key}_{bound}", bound=bound)


def statistic_level(statistic: str) -> float | None:
    """The probability of a quantile statistic (``"q95"`` → 0.95), None for ``mean``, ``std`` and
    ``p_exceed``.

    Parameters
    ----------
    statistic : str
        A statistic's name, as :class:`Statistic` takes it.

    Raises
    ------
    ValueError
        For a name that is no statistic, saying which are.
    """
    import re

    if statistic in ("mean", "std", "p_exceed"):
        return None
    m = re.fullmatch(r"q(\d+(?:\.\d+)?)", statistic)
    q = float(m.group(1)) / 100.0 if m else math.nan
    if not 0.0 < q < 1.0:
        raise ValueError(
            f"{statistic!r} is not a statistic; give mean, std, p_exceed (with the output's limit) or a "
            'quantile qNN with 0 < NN < 100 (e.g. "q95", "q5")'
        )
    return q


@dataclass(frozen=True)
class Objective:
    """Minimise or maximise an output.

    Parameters
    ----------
    output : Watched
        The output.
    sense : {"minimize", "maximize"}
        The goal.
    """

    output: Watched
    sense: str  # "minimize" or "maximize"

    @property
    def sign(self) -> float:
        return 1.0 if self.sense == "minimize" else -1.0


#: How far beyond its limit an output may end and its constraint still hold, relative to that side's
#: scale (:meth:`Constraint.sides`): an optimizer's round-off at an active limit (SLSQP ends a few
#: ulps outside it), far below any engineering margin.
HOLD_TOLERANCE = 1e-9


@dataclass(frozen=True)
class Constraint:
    """A limit on an output: ``max``, ``min``, or ``equals`` within ``tolerance``, SI.

    :meth:`violation` is ≤ 0 when the constraint holds (Optuna's convention), in the output's unit;
    :meth:`holds` allows the round-off of an optimizer that ends on the limit (:data:`HOLD_TOLERANCE`).

    Parameters
    ----------
    output : Watched
        The output it limits.
    max, min, equals : float, optional
        The limits, in the output's SI unit.
    tolerance : float, optional
        Allowed deviation from ``equals``, in the output's SI unit.
    """

    output: Watched
    max: float | None = None
    min: float | None = None
    equals: float | None = None
    tolerance: float | None = None

    def violation(self, value: float | None) -> float:
        """How far ``value`` is outside the limits (≤ 0 inside), in the output's SI unit; infinite for
        a missing or non-finite value.

        Parameters
        ----------
        value : float or None
            The output's value, SI.
        """
        if value is None or not math.isfinite(value):
            return math.inf
        parts = []
        if self.max is not None:
            parts.append(value - self.max)
        if self.min is not None:
            parts.append(self.min - value)
        if self.equals is not None:
            parts.append(abs(value - self.equals) - (self.tolerance or 0.0))
        return max(parts) if parts else -math.inf

    def sides(self) -> list[tuple[str, float, float]]:
        """Each side of the constraint as (``"max"`` or ``"min"``, limit, scale), SI: an ``equals``
        is the two sides of its band. The scale, which sets how far beyond its side a value may end
        and still hold and compares limits in different units, is the band's tolerance, else the
        size of that side's limit (1 for a limit of 0)."""
        out: list[tuple[str, float, float]] = []
        if self.equals is not None:
            tol = float(self.tolerance or 0.0)
            band = tol if tol > 0 else (abs(float(self.equals)) or 1.0)
            out += [("max", self.equals + tol, band), ("min", self.equals - tol, band)]
        for side, limit in (("max", self.max), ("min", self.min)):
            if limit is not None:
                out.append((side, float(limit), abs(float(limit)) or 1.0))
        return out

    def relative_violation(self, value: float | None) -> float:
        """The worst side's violation over its scale (≤ 0 where it holds), dimensionless; infinite for
        a missing or non-finite value.

        Parameters
        ----------
        value : float or None
            The output's value, SI.
        """
        if value is None or not math.isfinite(value):
            return math.inf
        parts = [
            (value - limit if side == "max" else limit - value) / scale for side, limit, scale in self.sides()
        ]
        return max(parts) if parts else -math.inf

    def holds(self, value: float | None) -> bool:
        """Whether the output keeps the constraint, each side to :data:`HOLD_TOLERANCE` of its scale
        (:meth:`sides`).

        Parameters
        ----------
        value : float or None
            The output's value, SI.
        """
        return self.relative_violation(value) <= HOLD_TOLERANCE

    def describe(self) -> str:
        """The constraint in words, its limits as the study file gives them, in the output's display
        unit (e.g. ``excitation · stroke = 1496.3 mm ± 1 mm``, ``guide offset ≤ 300 mm``)."""
        from mechdyn.studies.cells import given, unit_text

        o = self.output
        unit = unit_text(o.shown_unit)

        def q(v: float | None, scale: bool = False) -> str:
            shown = o.difference(v) if scale else o.show(v)
            return f"{given(shown)} {unit}".strip() if shown is not None else "—"

        if self.equals is not None:
            return f"{o.words} = {q(self.equals)} ± {q(self.tolerance or 0.0, scale=True)}"
        bits = []
        if self.min is not None:
            bits.append(f"≥ {q(self.min)}")
        if self.max is not None:
            bits.append(f"≤ {q(self.max)}")
        return f"{o.words} " + " and ".join(bits)


def output_problem(summary: Mapping[str, Any], key: str) -> str | None:
    """Why a dotted key names no number in a summary (None when it names one): a list or table that
    needs an entry, an entry that is not there (list entries count from 1), a list that is empty, or a
    value that is not a number.

    Parameters
    ----------
    summary : mapping
        An analysis' summary (SI).
    key : str
        The output, nested with dots (``crossings.1.speed_rpm``).
    """
    node: Any = summary
    path = ""
    for part in key.split("."):
        here = f"{path}.{part}" if path else part
        if isinstance(node, Mapping):
            if part not in node:
                names = ", ".join(map(str, list(node)[:8])) + (", …" if len(node) > 8 else "")
                return f"{here!r} is not in the result ({path or 'it'} holds: {names})"
            node = node[part]
        elif isinstance(node, list):
            if not node:
                return (
                    f"{here!r}: {path} is empty for the base design (a list without entries), so there is "
                    f"nothing to read; choose an output the base design has, or change what leaves {path} "
                    "empty (the model, or the analysis' options)"
                )
            if not (part.isdigit() and 1 <= int(part) <= len(node)):
                return (
                    f"{here!r}: {path} is a list of {len(node)}, its entries count from 1 "
                    f"({path}.1" + (f" … {path}.{len(node)}" if len(node) > 1 else "") + ")"
                )
            node = node[int(part) - 1]
        else:
            return f"{here!r}: {path} is a single value, it has no entries; use {path!r}"
        path = here
    if isinstance(node, Mapping):
        names = ", ".join(map(str, list(node)[:8])) + (", …" if len(node) > 8 else "")
        return f"{key!r} is a table: name one of its entries, {key}.NAME ({names})"
    if isinstance(node, list):
        if not node:
            return f"{key!r} is an empty list for the base design: nothing to read"
        return f"{key!r} is a list of {len(node)}: name one entry, counting from 1 ({key}.1)"
    if output_value(summary, key) is None and node is not None:
        return f"{key!r} is {node!r}, not a number"
    return None


def output_value(summary: Mapping[str, Any], key: str) -> float | None:
    """The scalar at a dotted key of a summary (None when absent or not a number)."""
    node: Any = summary
    for part in key.split("."):
        if isinstance(node, Mapping) and part in node:
            node = node[part]
        elif isinstance(node, list) and part.isdigit() and 1 <= int(part) <= len(node):
            node = node[int(part) - 1]
        else:
            return None
    if isinstance(node, bool) or not isinstance(node, (int, float)):
        try:
            import numpy as np

            if isinstance(node, np.generic):
                return float(node)
        except ImportError:  # pragma: no cover
            pass
        return None
    return float(node)
