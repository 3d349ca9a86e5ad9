"""Named tolerance classes: a value bought "to a tolerance" as a distribution, with its source.

The classes and their sources are data (``tolerance_classes.toml`` beside this module): elastomer
hardness ±5 Shore A, the gear single pitch deviation of an ISO 1328-1:2013 flank tolerance class,
concrete and soil stiffness scatter (engineering assumptions, their basis stated), and a plain band
±t. :func:`tolerance` turns a class and a nominal value into a :class:`~mechdyn.uncertainty.Variable`.
"""

from __future__ import annotations

import functools
import math
from typing import Any

from mechdyn.errors import ModelError
from mechdyn.uncertainty.distributions import Variable, _si, lognormal, normal, truncated, uniform
from mechdyn.units import convert

__all__ = ["iso1328_single_pitch_tolerance", "tolerance", "tolerance_classes"]

SHAPES = ("normal", "uniform")


@functools.cache
def _classes() -> dict[str, dict[str, Any]]:
    import tomllib
    from importlib.resources import files

    text = files("mechdyn.uncertainty").joinpath("tolerance_classes.toml").read_text(encoding="utf-8")
    return tomllib.loads(text)


def tolerance_classes() -> dict[str, dict[str, Any]]:
    """The named tolerance classes: name → its data (title, kind, source, parameters).

    Returns
    -------
    dict
        A copy of ``tolerance_classes.toml``; every class has a ``title`` and a ``source``, and
        ``engineering_assumption = True`` where no standard gives the value.
    """
    return {k: dict(v) for k, v in _classes().items()}


def iso1328_single_pitch_tolerance(grade: int, d: Any, m_n: Any, *, rounded: bool = True) -> float:
    """The single pitch tolerance f_pT of an ISO 1328-1:2013 flank tolerance class, in m.

    ``f_pT = (0.001 d + 0.4 m_n + 5)·(√2)^(A − 5)`` µm with d and m_n in mm (ISO 1328-1:2013,
    eq. (5); the class step √2 of 5.2.2), rounded by 5.2.3 (above 10 µm to 1 µm, 5 … 10 µm to
    0.5 µm, below 5 µm to 0.1 µm). The standard's scope: classes 1 … 11,
    0.5 mm ≤ m_n ≤ 70 mm, 5 mm ≤ d ≤ 15 000 mm; it is not extrapolated.

    Parameters
    ----------
    grade : int
        The flank tolerance class A, 1 … 11.
    d : float, str or quantity
        Reference diameter, m when a plain number.
    m_n : float, str or quantity
        Normal module, m when a plain number.
    rounded : bool
        Round as the standard's tables do (5.2.3).

    Returns
    -------
    float
        f_pT, m.

    Examples
    --------
    >>> from mechdyn.uncertainty import iso1328_single_pitch_tolerance
    >>> round(iso1328_single_pitch_tolerance(5, "100 mm", "2 mm") * 1e6, 1)  # (0.1 + 0.8 + 5) µm
    6.0
    """
    name = f"ISO 1328-1 class {grade}"
    if isinstance(grade, bool) or not isinstance(grade, int) or not 1 <= grade <= 11:
        raise ModelError(
            f"grade = {grade!r}: ISO 1328-1:2013 has flank tolerance classes 1 … 11; give an integer in "
            "that range (grade 6 for a ground industrial gear)",
            element=name,
            field="grade",
        )
    d_mm = convert(_si(name, "d", d, "m", positive=True), "m", "mm")
    m_mm = convert(_si(name, "m_n", m_n, "m", positive=True), "m", "mm")
    if not 5.0 <= d_mm <= 15000.0:
        raise ModelError(
            f"d = {d!r} ({d_mm:.4g} mm) is outside ISO 1328-1:2013's scope 5 mm … 15 000 mm; "
            "the formula is not extrapolated",
            element=name,
            field="d",
        )
    if not 0.5 <= m_mm <= 70.0:
        raise ModelError(
            f"m_n = {m_n!r} ({m_mm:.4g} mm) is outside ISO 1328-1:2013's scope 0.5 mm … 70 mm; "
            "the formula is not extrapolated",
            element=name,
            field="m_n",
        )
    # ISO 1328-1:2013 eq. (5), its numbers in mm and µm as the standard writes it
    # (0.001 d/mm is the number of d in metres)
    f_um = (convert(d_mm, "mm", "m") + 0.4 * m_mm + 5.0) * math.sqrt(2.0) ** (grade - 5)
    if rounded:
        f_um = _round_iso1328(f_um)
    return convert(f_um, "um", "m")


def _round_iso1328(value_um: float) -> float:
    """ISO 1328-1:2013, 5.2.3: above 10 µm to the micrometre, 5 … 10 µm to 0.5 µm, else to 0.1 µm
    (halves away from zero, as the standard's tables)."""
    step = 1.0 if value_um > 10.0 else 0.5 if value_um >= 5.0 else 0.1
    return math.floor(value_um / step + 0.5) * step


def _band(
    name: str, nominal: float, half: float, shape: str, sigmas: float, unit: str, source: str
) -> Variable:
    if shape == "uniform":
        return uniform(name, nominal - half, nominal + half, unit, source=source)
    base = normal(name, nominal, half / sigmas, unit, source=source)
    return truncated(base, nominal - half, nominal + half)


def _shape(name: str, shape: Any) -> str:
    if shape not in SHAPES:
        raise ModelError(
            f"shape = {shape!r}: give one of {', '.join(map(repr, SHAPES))} (how the parts spread "
            "over the tolerance band)",
            element=name,
            field="shape",
        )
    return str(shape)


def tolerance(
    name: str,
    tolerance_class: str,
    *,
    nominal: Any = None,
    unit: str = "",
    shape: str | None = None,
    plus_minus: Any = None,
    grade: int | None = None,
    d: Any = None,
    m_n: Any = None,
    cov: Any = None,
    magnitude: bool = False,
) -> Variable:
    """A value of a named tolerance class as a distribution.

    ========================  ===============================================================
    class                     the distribution
    ========================  ===============================================================
    ``"shore_a_5"``           hardness ``nominal`` ±5 Shore A (ASTM D2000 grades)
    ``"iso1328_fpt"``         single pitch deviation within ±f_pT of class ``grade`` (ISO 1328-1),
                              m, centred on 0 (or ``nominal``)
    ``"concrete_modulus"``    lognormal, median ``nominal``, cov 0.15 (engineering assumption)
    ``"soil_stiffness"``      lognormal, median ``nominal``, cov 0.35 (engineering assumption)
    ``"band"``                ``nominal`` ± ``plus_minus`` (absolute, or ``"20 %"`` of nominal)
    ========================  ===============================================================

    A band is a normal distribution with the band at ±3 σ truncated at the band (``shape="normal"``)
    or a uniform one (``shape="uniform"``); see ``tolerance_classes.toml``.

    Parameters
    ----------
    name : str
        The variable's name.
    tolerance_class : str
        One of :func:`tolerance_classes`.
    nominal : float, str or quantity, optional
        The nominal value, in ``unit`` when a plain number (required except for ``iso1328_fpt``).
    unit : str
        The SI unit of the variable (``"m"`` for a pitch deviation, ``""`` for Shore A).
    shape : str, optional
        ``"normal"`` or ``"uniform"``: the spread over a band (the class's own by default).
    plus_minus : float, str or quantity, optional
        The half-width of a ``band``, in ``unit`` when a plain number, or a percentage (``"20 %"``).
    grade : int, optional
        ISO 1328-1 flank tolerance class, 1 … 11 (``iso1328_fpt``).
    d : float, str or quantity, optional
        Reference diameter, m when a plain number (``iso1328_fpt``).
    m_n : float, str or quantity, optional
        Normal module, m when a plain number (``iso1328_fpt``).
    cov : float, optional
        Coefficient of variation replacing the class's assumed one (``concrete_modulus``,
        ``soil_stiffness``), dimensionless.
    magnitude : bool
        ``iso1328_fpt``: the size of the deviation, abs(f_pt), on [0, f_pT] (for a value that cannot
        be negative, such as the amplitude of a transmission error): the band centred on 0 folded at
        0, which is exactly the band's distribution truncated to [0, f_pT] (normal: a half-normal of
        σ = f_pT / 3 cut at f_pT; uniform: uniform on [0, f_pT]). No ``nominal`` with it.

    Examples
    --------
    >>> from mechdyn.uncertainty import tolerance
    >>> pad = tolerance("pad.shore_a", "shore_a_5", nominal=60)
    >>> float(pad.ppf(0.0)), float(pad.ppf(1.0))
    (55.0, 65.0)
    """
    classes = _classes()
    if tolerance_class not in classes:
        import difflib

        close = difflib.get_close_matches(str(tolerance_class), list(classes), n=1)
        hint = f"did you mean {close[0]!r}? " if close else ""
        raise ModelError(
            f"tolerance = {tolerance_class!r} is not a tolerance class; {hint}give one of "
            f"{', '.join(map(repr, classes))}",
            element=name,
            field="tolerance",
        )
    data = classes[tolerance_class]
    source = f"{data['title']}: {data['source']}"
    kind = data["kind"]
    chosen = _shape(name, shape if shape is not None else data.get("shape", "normal"))
    sigmas = float(data.get("sigmas", 3.0))

    def need(value: Any, field_name: str, example: str) -> Any:
        if value is None:
            raise ModelError(
                f"tolerance class {tolerance_class!r} needs {field_name}; "
                f"give it, e.g. {field_name} = {example}",
                element=name,
                field=field_name,
            )
        return value

    if magnitude and kind != "iso1328_fpt":
        raise ModelError(
            f"magnitude = true is for the iso1328_fpt class (a signed deviation), not {tolerance_class!r}; "
            "remove it",
            element=name,
            field="magnitude",
        )
    if kind == "iso1328_fpt":
        if unit != "m":
            raise ModelError(
                f"a pitch deviation is a length: unit {unit!r} should be 'm'", element=name, field="tolerance"
            )
        need(grade, "grade", "6")
        half = iso1328_single_pitch_tolerance(grade, need(d, "d", "'120 mm'"), need(m_n, "m_n", "'3 mm'"))  # type: ignore[arg-type]
        shown = f" Class {grade}: f_pT = {convert(half, 'm', 'um'):g} µm."
        if magnitude:
            if not isinstance(magnitude, bool):
                raise ModelError(
                    f"magnitude = {magnitude!r}: give true or false", element=name, field="magnitude"
                )
            if nominal is not None:
                raise ModelError(
                    f"nominal = {nominal!r} with magnitude = true: the size of a deviation centred on 0 "
                    "has no nominal; remove one of them",
                    element=name,
                    field="nominal",
                )
            folded = " Its size abs(f_pt): the band folded at 0."
            if chosen == "uniform":
                return uniform(name, 0.0, half, unit, source=source + shown + folded)
            return truncated(
                normal(name, 0.0, half / sigmas, unit, source=source + shown + folded), 0.0, half
            )
        centre = 0.0 if nominal is None else _si(name, "nominal", nominal, unit)
        return _band(name, centre, half, chosen, sigmas, unit, source + shown)
    centre = _si(name, "nominal", need(nominal, "nominal", "'2 MN/m'" if unit else "60"), unit)
    if kind == "lognormal":
        c = data["cov"] if cov is None else cov
        return lognormal(name, median=centre, cov=c, unit=unit, source=source)
    # a band: the class's own half-width or the caller's
    if plus_minus is None and "plus_minus" in data:
        half = float(data["plus_minus"])
    else:
        half = _half_width(name, need(plus_minus, "plus_minus", "'20 %'"), centre, unit)
    return _band(name, centre, half, chosen, sigmas, unit, source)


def _half_width(name: str, plus_minus: Any, nominal: float, unit: str) -> float:
    text = plus_minus.strip() if isinstance(plus_minus, str) else None
    if text and text.endswith("%"):
        try:
            share = float(text[:-1].strip().lstrip("±")) / 100.0
        except ValueError:
            raise ModelError(
                f"plus_minus = {plus_minus!r} is not a percentage; give e.g. '20 %'",
                element=name,
                field="plus_minus",
            ) from None
        half = abs(nominal) * share
        if not half > 0:
            raise ModelError(
                f"plus_minus = {plus_minus!r} of nominal {nominal:g} is no band; give a positive percentage "
                "of a non-zero nominal, or an absolute half-width",
                element=name,
                field="plus_minus",
            )
        return half
    if text and text.startswith("±"):
        plus_minus = text[1:]
    return _si(name, "plus_minus", plus_minus, unit, positive=True)
