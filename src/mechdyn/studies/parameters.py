"""A study's parameters: the model values each sets, with its range or its levels, SI.

A parameter's range is absolute (``["1.2 m", "1.6 m"]``), relative to the model's value
(``"±10 %"``), or a list of levels (``["0 %", "-10 %", "-20 %"]``, or absolute values). A parameter
may move several values together (``mounts.*.stiffness``, or ``tie`` = more paths): each moves by the
same factor from its own base value. In Python a parameter may instead be any function
``(model, value) -> model``.

A value that is not a quantity takes levels only: a whole number (a tooth count: ``[17, 19]``, or
relative levels that land on whole numbers) or a choice (a material by name, an option, another model
file of the same type, true or false: the names themselves). A choice's value in a variant's row is
the index of its level in :attr:`Parameter.choices` (the model's own value first), so that every
variant is still a row of numbers; :meth:`Parameter.shown` gives the name.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from mechdyn.studies.errors import StudyError
from mechdyn.studies.paths import Location, ModelTree, Nature, file_text

__all__ = ["Parameter", "parse_relative"]


_RELATIVE = re.compile(r"^\s*(±|\+/-|\+-|[+-])?\s*(\d+(?:\.\d*)?|\.\d+)\s*%\s*$")


def parse_relative(text: Any) -> tuple[str, float] | None:
    """``"±10 %"`` → ``("±", 0.10)``; ``"-20 %"`` → ``("", -0.20)``; None when not a percentage."""
    if not isinstance(text, str):
        return None
    m = _RELATIVE.match(text)
    if m is None:
        return None
    sign, number = m.group(1) or "", float(m.group(2)) / 100.0
    if sign in ("±", "+/-", "+-"):
        return "±", number
    return "", -number if sign == "-" else number


def _file_unit(value: Any) -> str:
    """The unit a file value is written in (``"576 mm"`` → ``"mm"``; a bare number → ``""``)."""
    if isinstance(value, str):
        parts = value.strip().split(None, 1)
        return parts[1] if len(parts) == 2 else ""
    return ""


def _si(value: Any, unit: str) -> tuple[float, float]:
    """(SI magnitude, factor from the unit to SI) of a file value or a user's quantity."""
    from mechdyn.units import registry

    ureg = registry()
    if not isinstance(value, str):
        return float(value), 1.0
    q: Any = ureg.Quantity(value)
    if not hasattr(q, "to_base_units"):
        return float(q), 1.0
    base = q.to_base_units()
    factor = ureg.Quantity(1.0, unit).to_base_units().magnitude if unit else 1.0
    return float(base.magnitude), float(factor)


@dataclass(frozen=True)
class Parameter:
    """A design parameter: the model values it sets and its range or levels, SI.

    Build one with :meth:`from_spec` (paths with units, as in a study file) or :meth:`function`.

    Attributes
    ----------
    name : str
        How tables and the database name it (the path by default).
    locations : tuple of Location
        The values it sets (several: they move together, each by the same factor from its base).
    base : float
        The model's value at the first location, SI.
    unit : str
        The unit the file writes it in (for display), ``""`` for a bare number.
    factor : float
        SI per display unit.
    low, high : float or None
        Continuous range, SI (for Latin hypercube, Sobol, optimization, synthesis).
    levels : tuple of float
        Discrete values, SI (one-at-a-time and factorial); the base value is not among them unless
        given.
    bases : tuple of float
        Every location's base value, SI.
    apply : callable or None
        ``(model, value) -> model`` for a parameter that is a Python function.
    choices : tuple
        A choice (a material, an option, a model file, true or false): the values it sets, as the
        file writes them, the model's own first; the parameter's value is the index of one of them
        (``base`` 0, ``levels`` the indices of the study's levels). Empty for a number.
    integer : bool
        A whole number (a tooth count): levels only, and the file gets whole numbers.
    scatter : mechdyn.uncertainty.Variable or None
        How the value scatters (SI), for a ``tolerance`` study: a study file's ``scatter`` table
        (:func:`mechdyn.uncertainty.variable_from_dict`); None for a range or levels. An ``optimize``
        study's design variable may have both a range and a scatter (robust design): the scatter is
        then centred on each design's value.
    scatter_table : tuple of (mapping, str) or None
        The ``scatter`` table as read and the SI unit it was read in, to centre the scatter on another
        value (:func:`mechdyn.uncertainty.variable_from_dict` with ``nominal=``).
    """

    name: str
    locations: tuple[Location, ...]
    base: float
    unit: str
    factor: float
    low: float | None = None
    high: float | None = None
    levels: tuple[float, ...] = ()
    bases: tuple[float, ...] = ()
    apply: Callable[[Any, float], Any] | None = field(default=None, compare=False)
    choices: tuple[Any, ...] = ()
    integer: bool = False
    scatter: Any = field(default=None, compare=False)
    scatter_table: Any = field(default=None, compare=False)

    # -- construction ------------------------------------------------------------------------
    @classmethod
    def from_spec(
        cls,
        tree: ModelTree,
        path: str,
        *,
        range: Any = None,
        levels: Sequence[Any] | None = None,
        tie: Sequence[str] = (),
        name: str | None = None,
        where: str = "",
        scatter: Any = None,
        design_scatter: bool = False,
        level_kinds: Sequence[str] = (),
    ) -> list[Parameter]:
        """The parameter(s) a study file's row names: a vector (``points.C``) gives one parameter
        per component (``points.C.x``, ``points.C.y``).

        Parameters
        ----------
        tree : ModelTree
            The base model.
        path : str
            The value's path (:mod:`mechdyn.studies.paths`).
        range : str or [low, high], optional
            ``"±10 %"``, or two quantities with units (``["1.2 m", "1.6 m"]``).
        levels : list, optional
            Relative (``"-10 %"``) or absolute (``"1.2 m"``) values; whole numbers for a whole
            number (``[17, 19]``), names for a choice (``["rubber shore 50", "rubber shore 70"]``).
        tie : list of str
            More paths that move with this one, by the same factor.
        name : str, optional
            The parameter's name in tables (default: the path); a point's coordinates are named
            ``NAME.x`` and ``NAME.y``.
        where : str
            The study file and row, for errors.
        scatter : mapping, optional
            How the value scatters, for a ``tolerance`` study, instead of a range or levels: a table
            of :func:`mechdyn.uncertainty.variable_from_dict` (``{distribution = "lognormal", median
            = "2 MN/m", cov = 0.15}``, ``{tolerance = "shore_a_5"}``), the model's value its default
            nominal.
        design_scatter : bool
            Take a range and a scatter together (an ``optimize`` study's design variable whose value
            scatters about each design's: robust design).
        level_kinds : sequence of str
            The study kinds that take levels (:func:`mechdyn.studies.kinds.base.level_kinds`), named
            when a whole number or a choice is given a range.
        """
        if scatter is not None:
            if levels is not None or (range is not None and not design_scatter):
                raise StudyError(
                    f"{where}: give the parameter {path!r} a scatter or a range or levels, not both (a "
                    "tolerance study takes scatter, the other kinds a range or levels; an optimize study's "
                    "design variable may take a range and a scatter)"
                )
        if scatter is None and (range is None) == (levels is None):
            raise StudyError(f"{where}: give the parameter {path!r} either a range or levels (one of them)")
        locations = tree.resolve(path)
        tied = [loc for p in tie for loc in tree.resolve(p)]
        groups: list[tuple[str, list[Location]]] = [(path, [*locations, *tied])]
        # a point: each coordinate is a parameter of its own
        if tree.nature(locations[0]).kind == "quantity" and _coordinates(tree, locations):
            n = len(locations)
            head = name or path
            groups = [(f"{head}.{'xyz'[i]}", [loc, *tied[i::n]]) for i, loc in enumerate(locations)]
        elif name:
            groups = [(name, groups[0][1])]
        out = []
        for label, locs in groups:
            out.append(cls._one(tree, label, locs, range, levels, where, level_kinds))
        if scatter is not None:
            return [_scattered(p, scatter, len(groups), where) for p in out]
        return out

    @classmethod
    def _one(
        cls,
        tree: ModelTree,
        name: str,
        locs: list[Location],
        range_: Any,
        levels: Any,
        where: str,
        level_kinds: Sequence[str] = (),
    ) -> Parameter:
        natures = [tree.nature(loc) for loc in locs]
        if any(n.kind != natures[0].kind or n.of != natures[0].of for n in natures):
            kinds = sorted({_what(n) for n in natures})
            raise StudyError(
                f"{where}: {name!r} moves values of different kinds together ({', '.join(kinds)}); give "
                "each kind a parameter of its own"
            )
        if natures[0].kind != "quantity":
            return cls._discrete(tree, name, locs, natures[0], range_, levels, where, level_kinds)
        values = [tree.value(loc) for loc in locs]
        unit = _file_unit(values[0])
        bases = []
        for v in values:
            si, _ = _si(v, _file_unit(v))
            bases.append(si)
        base, factor = _si(values[0], unit)

        def absolute(q: Any, what: str) -> float:
            if isinstance(q, (int, float)) and not isinstance(q, bool):
                if unit:
                    raise StudyError(
                        f"{where}: {what} {q!r} for {name!r} needs its unit "
                        f"(the model writes {values[0]!r}), "
                        f'e.g. "{q} {unit}"'
                    )
                return float(q)
            from mechdyn.units import UnitError, to_si

            try:
                return to_si(q, unit or "", plain_is_si=False) * factor
            except UnitError as exc:
                raise StudyError(
                    f"{where}: {what} {q!r} for {name!r}: {exc}; the model writes {values[0]!r}, so give a "
                    f"quantity in {unit or 'plain numbers'}"
                ) from None

        def relative(q: Any) -> float | None:
            r = parse_relative(q)
            if r is None:
                return None
            if r[0] == "±":
                raise StudyError(f'{where}: level {q!r} for {name!r}: a level is one value, e.g. "-10 %"')
            if base == 0:
                raise StudyError(
                    f"{where}: {name!r} is 0 in the model, so a relative level {q!r} moves nothing; give "
                    "absolute levels with units"
                )
            return base * (1.0 + r[1])

        low = high = None
        lv: tuple[float, ...] = ()
        if levels is not None:
            if not isinstance(levels, (list, tuple)) or not levels:
                raise StudyError(
                    f'{where}: levels of {name!r} must be a non-empty list, e.g. ["-10 %", "10 %"]'
                )
            lv = tuple(r if (r := relative(q)) is not None else absolute(q, "level") for q in levels)
        elif range_ is not None:  # neither: a scatter (from_spec)
            rel = parse_relative(range_)
            if rel is not None:
                if rel[0] != "±":
                    raise StudyError(
                        f'{where}: range {range_!r} for {name!r}: a relative range is written "±10 %"'
                    )
                if rel[1] == 0:
                    raise StudyError(f'{where}: range {range_!r} for {name!r} is empty; give e.g. "±10 %"')
                if base == 0:
                    raise StudyError(
                        f"{where}: {name!r} is 0 in the model, so {range_!r} of it is empty; give an "
                        f'absolute range with units, e.g. ["-0.1 {unit or "m"}", "0.1 {unit or "m"}"]'
                    )
                a, b = base * (1 - rel[1]), base * (1 + rel[1])
                low, high = min(a, b), max(a, b)
            elif isinstance(range_, (list, tuple)) and len(range_) == 2:
                low, high = (absolute(q, "range bound") for q in range_)
                if not low < high:
                    raise StudyError(f"{where}: range {list(range_)!r} for {name!r} must go from low to high")
            else:
                raise StudyError(
                    f'{where}: range {range_!r} for {name!r}: give "±10 %" or two quantities '
                    f'["low {unit}", "high {unit}"]'
                )
        made = cls(name, tuple(locs), base, unit, factor, low, high, lv, tuple(bases))
        made._refuse_outside_the_file(tree, where)
        return made

    @classmethod
    def _discrete(
        cls,
        tree: ModelTree,
        name: str,
        locs: list[Location],
        nature: Nature,
        range_: Any,
        levels: Any,
        where: str,
        level_kinds: Sequence[str] = (),
    ) -> Parameter:
        """A whole number or a choice: levels only, checked against what the model accepts."""
        values = [tree.value(loc) for loc in locs]
        shown = file_text(values[0])
        what = _what(nature)
        integer = nature.kind == "integer"
        if integer:
            b = int(values[0])
            example = f"[{b - 1}, {b + 1}]" if b > 1 else f"[{b + 1}, {b + 2}]"
        else:
            others = [c for c in nature.choices if c != values[0]][:2] or [values[0]]
            example = "[" + ", ".join(file_text(c) for c in others) + "]"
        if range_ is not None:
            kinds = f" (studies of kind {' or '.join(level_kinds)} take levels)" if level_kinds else ""
            raise StudyError(
                f"{where}: {name!r} is {what} ({shown} in the model), not a quantity: it takes levels, "
                f"not a range; give levels = {example}{kinds}"
            )
        if not isinstance(levels, (list, tuple)) or not levels:
            raise StudyError(f"{where}: levels of {name!r} must be a non-empty list, e.g. {example}")
        if integer:
            bases = tuple(float(v) for v in values)
            lv = tuple(_whole_level(q, name, bases, shown, example, where) for q in levels)
            made = cls(name, tuple(locs), bases[0], "", 1.0, None, None, lv, bases, integer=True)
            made._refuse_outside_the_file(tree, where)
            return made
        if any(v != values[0] for v in values):
            held = ", ".join(sorted({file_text(v) for v in values}))
            raise StudyError(
                f"{where}: {name!r} names {len(values)} values that differ in the model ({held}); a choice "
                "sets them all to one value: give each its own parameter (one row each)"
            )
        choices = [values[0]]
        lv_choice: list[float] = []
        for q in levels:
            c = _choice_level(tree, locs[0], nature, q, name, shown, where)
            if c not in choices:
                choices.append(c)
            lv_choice.append(float(choices.index(c)))
        zeros = tuple(0.0 for _ in locs)
        return cls(
            name, tuple(locs), 0.0, "", 1.0, None, None, tuple(lv_choice), zeros, choices=tuple(choices)
        )

    @classmethod
    def function(
        cls,
        name: str,
        apply: Callable[[Any, float], Any],
        base: float,
        *,
        low: float | None = None,
        high: float | None = None,
        levels: Sequence[float] = (),
        unit: str = "",
    ) -> Parameter:
        """A parameter that is any function ``apply(model, value) -> model`` (Python API).

        Parameters
        ----------
        name : str
        apply : callable
            Returns a new model with the parameter set to ``value`` (SI); it must not change its input.
        base : float
            The value of the base model, SI.
        low, high : float, optional
            Continuous range, SI.
        levels : sequence of float
            Discrete values, SI.
        unit : str
            The parameter's SI unit, for display.
        """
        return cls(name, (), float(base), unit, 1.0, low, high, tuple(levels), (), apply)

    def _refuse_outside_the_file(self, tree: ModelTree, where: str) -> None:
        """Refuse, as the study is read, a range or a level that takes a value beyond what its model
        file accepts (a Shore A hardness of 80 where the file takes 30 to 75, a negative thickness):
        every variant there would fail, each only once it is evaluated.

        Raises
        ------
        StudyError
            Naming the study file and row, the parameter, the value and what the file accepts.
        """
        ends = (
            [("the low end of its range", self.low), ("the high end of its range", self.high)]
            if self.levels == ()
            else [("a level", x) for x in self.levels]
        )
        for loc in self.locations:
            bounds = tree.bounds(loc)
            if not bounds:
                continue
            field = str(loc.keys[-1]) if isinstance(loc.keys[-1], str) else str(loc.keys[-2])
            file = Path(tree.file(loc.files).path).name
            for which, x in ends:
                if x is None:
                    continue
                v = float(self.location_values(x)[loc])
                problem = next((p for b in bounds if (p := _bound_problem(b, v, field)) is not None), None)
                if problem is None:
                    continue
                there = ""
                if v != x:  # a value tied to the parameter, moved by the same factor from its own base
                    there = f", which sets {loc.path} to {v / self.factor:g} {self.unit}".rstrip()
                raise StudyError(
                    f"{where}: {self.name!r} at {which}, {self.shown(x)}{there}, takes a value {file} does "
                    f"not accept: {problem}. Every variant there would fail: keep the "
                    f"{'levels' if self.levels else 'range'} within what the model file accepts"
                )

    # -- values -------------------------------------------------------------------------------
    def location_values(self, value: Any) -> dict[Location, Any]:
        """SI value at each location (``value`` a float or an array of variants): each location
        moves by the same factor from its own base value.

        Parameters
        ----------
        value : float or ndarray
            The parameter's value(s), in its SI unit."""
        return {
            loc: value if self.base == 0 or b == self.base else b * (value / self.base)
            for loc, b in zip(self.locations, self.bases, strict=True)
        }

    def file_values(self, value: float) -> dict[Location, Any]:
        """The file values (text in the file's unit, or a number) that set this parameter to
        ``value`` (SI).

        Parameters
        ----------
        value : float
            The parameter's value, in its SI unit."""
        if self.choices:
            choice = self.choice(value)
            return dict.fromkeys(self.locations, choice)
        if self.integer:
            return {loc: round(v) for loc, v in self.location_values(value).items()}
        return {
            loc: f"{v / self.factor!r} {self.unit}" if self.unit else v
            for loc, v in self.location_values(value).items()
        }

    def choice(self, value: float) -> Any:
        """The file value that a choice's ``value`` (the index of one of :attr:`choices`) stands for.

        Parameters
        ----------
        value : float
            An index into :attr:`choices`.

        Raises
        ------
        StudyError
            For a value that is not the index of one of them.
        """
        i = round(value) if math.isfinite(value) else -1
        if not (self.choices and abs(value - i) < 1e-9 and 0 <= i < len(self.choices)):
            raise StudyError(
                f"{self.name!r}: {value!r} is not one of its choices' indices (0 to {len(self.choices) - 1}: "
                + ", ".join(file_text(c) for c in self.choices)
                + ")"
            )
        return self.choices[i]

    @property
    def discrete(self) -> bool:
        """A whole number or a choice: levels only (one-at-a-time and factorial studies)."""
        return bool(self.choices) or self.integer

    def shown(self, value: float) -> str:
        """The value in the file's unit, as text (a choice: its name; a whole number: the number).

        Parameters
        ----------
        value : float
            The parameter's value, in its SI unit (a choice: the index of the choice).
        """
        if self.choices:
            try:
                c = self.choice(value)
            except StudyError:
                return f"{value:g}"
            return c if isinstance(c, str) else file_text(c)
        if self.integer and math.isfinite(value) and value == round(value):
            return f"{round(value):d}"
        v = value / self.factor
        return f"{v:.6g} {self.unit}".strip()

    def relative(self, value: float) -> float | None:
        """Change from the base value, as a fraction (None when the base is 0, and for a choice).

        Parameters
        ----------
        value : float
            The parameter's value, in its SI unit.
        """
        if self.choices:
            return None
        return value / self.base - 1.0 if self.base else None

    @property
    def bounded(self) -> bool:
        return self.low is not None and self.high is not None and math.isfinite(self.high - self.low)


def _scattered(p: Parameter, spec: Any, groups: int, where: str) -> Parameter:
    """The parameter ``p`` (made without range or levels) with the scatter a study file's ``scatter``
    table gives it (:func:`mechdyn.uncertainty.variable_from_dict`, SI, the model's value its nominal).

    Parameters
    ----------
    p : Parameter
    spec : mapping
        The ``scatter`` table as read.
    groups : int
        How many parameters the row makes (a point: one per coordinate, which a scatter refuses).
    where : str
        The study file and row, for errors.
    """
    from dataclasses import replace

    from mechdyn.errors import ModelError
    from mechdyn.uncertainty import variable_from_dict
    from mechdyn.units import si_unit

    if p.discrete or p.apply is not None or groups > 1:
        what = "a point" if groups > 1 else ("a whole number" if p.integer else "a choice")
        raise StudyError(
            f"{where} → scatter: {p.name!r} is {what}; a scatter is given to one quantity (a point: "
            'give each coordinate a row of its own, e.g. path = "points.C.x")'
        )
    # the unit the file writes where it is SI already (N/m, not kg/s²): errors then speak the file's
    si = p.unit if p.factor == 1.0 else si_unit(p.unit)
    try:
        variable = variable_from_dict(p.name, spec, si, nominal=p.base)
    except ModelError as exc:
        raise StudyError(f"{where} → scatter: {exc}") from None
    return replace(p, scatter=variable, scatter_table=(dict(spec), si))


def _bound_problem(bound: Any, value: float, field: str) -> str | None:
    """What a schema's bound (:class:`mechdyn.io.fields.Check`, or pydantic's ``ge``, ``gt``, ``le``,
    ``lt``) says of ``value`` (SI); None when it holds."""
    if hasattr(bound, "problem"):
        return bound.problem(value, field)
    tests = (
        ("ge", lambda b: value >= b, "at least"),
        ("gt", lambda b: value > b, "above"),
        ("le", lambda b: value <= b, "at most"),
        ("lt", lambda b: value < b, "below"),
    )
    for attr, holds, words in tests:
        b = getattr(bound, attr, None)
        if b is not None and not holds(b):
            return f"{value:g} is out of range; {field} must be {words} {b:g}"
    return None


def _what(nature: Nature) -> str:
    """A value's kind in words, for messages (``"a whole number"``, ``"a material"``)."""
    if nature.kind == "integer":
        return "a whole number"
    if nature.kind == "quantity":
        return "a quantity"
    if nature.of == "true or false":
        return "true or false"
    return "an option" if nature.of == "option" else f"a {nature.of}"


def _whole_level(q: Any, name: str, bases: tuple[float, ...], shown: str, example: str, where: str) -> float:
    """A level of a whole number: a number, or relative to the model's value; it must land on a
    whole number at every value the parameter sets."""
    base = bases[0]
    r = parse_relative(q)
    if r is not None:
        if r[0] == "±":
            raise StudyError(f'{where}: level {q!r} for {name!r}: a level is one value, e.g. "+10 %"')
        if base == 0:
            raise StudyError(
                f"{where}: {name!r} is 0 in the model, so a relative level {q!r} moves nothing; give whole "
                f"numbers, e.g. levels = {example}"
            )
        x = base * (1.0 + r[1])
    elif isinstance(q, bool) or not isinstance(q, (int, float)) or not math.isfinite(q):
        raise StudyError(
            f"{where}: level {q!r} of {name!r}: {name!r} is a whole number ({shown} in the model); give "
            f"whole numbers without a unit or quotes, e.g. levels = {example}"
        )
    else:
        x = float(q)
    for b in bases:
        y = x if b == base else b * x / base
        if abs(y - round(y)) > 1e-9 * max(1.0, abs(y)):
            moved = "" if b == base else f" moves {b:g} to {y:.6g}, which"
            raise StudyError(
                f"{where}: level {q!r} of {name!r}{moved} is {y:.6g}, not a whole number ({name!r} is "
                f"{shown} in the model); give whole numbers, e.g. levels = {example}"
            )
    return float(round(x))


def _choice_level(
    tree: ModelTree, loc: Location, nature: Nature, q: Any, name: str, shown: str, where: str
) -> Any:
    """A level of a choice, as the file would write it, checked against what the model accepts."""
    import difflib

    listed = ", ".join(file_text(c) for c in nature.choices)
    if nature.of == "true or false":
        if isinstance(q, bool):
            return q
        if isinstance(q, str) and q.strip().lower() in ("true", "false"):
            return q.strip().lower() == "true"
        raise StudyError(f"{where}: level {q!r} of {name!r}: give true or false ({shown} in the model)")
    if not isinstance(q, str) or parse_relative(q) is not None:
        raise StudyError(
            f"{where}: level {q!r} of {name!r}: {name!r} is {_what(nature)} ({shown} in the model); its "
            f"levels are names, not numbers or changes; the choices: {listed}"
        )
    if nature.model_type:
        found = tree.model_file(loc, q)
        if found is None or found.model_type != nature.model_type:
            from mechdyn.io.modelfile import reference_path

            target = reference_path(tree.file(loc.files), q)
            why = "no such model file" if found is None else f"a {found.model_type!r} model"
            raise StudyError(
                f"{where}: level {q!r} of {name!r}: {why} ({target}); give a {nature.of} relative to "
                f"{tree.file(loc.files).path}, e.g. {listed}"
            )
        return q
    if q not in nature.choices:
        near = difflib.get_close_matches(q, [str(c) for c in nature.choices], n=3)
        hint = f" (did you mean {', '.join(map(repr, near))}?)" if near else ""
        raise StudyError(
            f"{where}: level {q!r} of {name!r} is not {_what(nature)} the model accepts{hint}; the choices: "
            f"{listed}"
        )
    return q


def _coordinates(tree: ModelTree, locations: Sequence[Location]) -> bool:
    """The locations are the coordinates of one point (one vector of lengths, named without a
    component): a study varies each coordinate on its own. Other vectors (a mount's three
    stiffnesses) and wildcards move together."""
    if len(locations) < 2 or len({(loc.files, loc.keys[:-1]) for loc in locations}) != 1:
        return False
    if "*" in locations[0].path:
        return False
    from mechdyn.units import registry

    first = tree.value(locations[0])
    if not isinstance(first, str):
        return False
    q: Any = registry().Quantity(first)
    return hasattr(q, "dimensionality") and str(q.dimensionality) == "[length]"
