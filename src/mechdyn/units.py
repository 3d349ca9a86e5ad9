"""The package's one unit registry and the conversion to SI at the edges.

Model files, the command line and public constructors accept quantities ("0.019 m", "80.8 GPa",
"1500 rpm", a :class:`pint.Quantity`); everything behind them works on bare SI floats and NumPy arrays.
A bare number given where a dimensional quantity is expected is rejected rather than guessed.
Results go the other way: :func:`convert` shows an SI value in a display unit (``"tonf"``,
``"kN/mm"``), and :func:`key_unit` reads the unit from the end of a result key (``stroke_m``).

The registry (``ureg``, ``Q_``) is created on first use, so that commands which convert nothing do
not pay for importing pint.
"""

from __future__ import annotations

import functools
import math
import re
from typing import TYPE_CHECKING, Any

from mechdyn.errors import MechdynError

if TYPE_CHECKING:
    import pint

# ``Q_`` and ``ureg`` come from the module ``__getattr__`` below
__all__ = [  # noqa: F822
    "Q_",
    "SHOWN_UNITS",
    "STANDARD_GRAVITY",
    "UnitError",
    "check_poisson_ratio",
    "convert",
    "key_label",
    "key_suffix",
    "key_unit",
    "readable",
    "readable_unit",
    "show",
    "si_field",
    "si_unit",
    "to_si",
    "ureg",
]

STANDARD_GRAVITY = 9.80665
"""g_n, m/s²: exact by definition (3rd CGPM, 1901); the default gravity and the mass of a weight."""


@functools.cache
def registry() -> pint.UnitRegistry:
    """The package-wide :class:`pint.UnitRegistry` (``mechdyn.units.ureg``), made on first use."""
    import pint

    reg: Any = pint.UnitRegistry()
    reg.formatter.default_format = "~P"
    # The press literature quotes forces in metric tonnes-force (1000 kgf), written "tf" or "tonf";
    # pint knows only the short and long ton-force, so the metric one is defined here.
    reg.define("tonne_force = 1000 * kilogram_force = tf = tonf")
    return reg


def __getattr__(name: str) -> Any:
    # ``ureg`` and ``Q_`` are module attributes made on first access (PEP 562)
    if name == "ureg":
        return registry()
    if name == "Q_":
        return registry().Quantity
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


class UnitError(MechdynError, ValueError):
    """A value could not be read as a quantity of the expected dimension."""


def _dimension_text(unit: str) -> str:
    return str(registry().Quantity(1.0, unit).dimensionality)


def _coerce(value: Any, unit: str) -> pint.Quantity:
    import numpy as np
    import pint

    ureg = registry()
    if isinstance(value, pint.Quantity):
        if value._REGISTRY is not ureg:
            # Quantities of another registry cannot be compared with ours.
            value = ureg.Quantity(value.magnitude, str(value.units))
        return value
    if isinstance(value, str):
        text = value.strip()
        if not text:
            raise UnitError(f"empty text; expected a quantity in {unit}, e.g. '1 {unit}'")
        try:
            q: Any = ureg.Quantity(text)
        except (pint.errors.PintError, ValueError, AttributeError, TypeError, SyntaxError) as exc:
            expected = (
                "a plain number, e.g. 0.05"
                if not unit
                else f"a number and a unit of {_dimension_text(unit)}, e.g. '1 {unit}'"
            )
            raise UnitError(f"cannot read {value!r} as a quantity ({exc}); expected {expected}") from None
        if not isinstance(q, pint.Quantity):  # a plain number written as text
            q = ureg.Quantity(float(q), "")
        return q
    if isinstance(value, bool):
        raise UnitError(f"got a boolean {value!r}; expected a quantity in {unit}")
    if isinstance(value, (int, float, np.integer, np.floating)):
        return ureg.Quantity(float(value), "")
    raise UnitError(f"got {type(value).__name__} {value!r}; expected a quantity in {unit}")


def to_si(value: Any, unit: str, *, plain_is_si: bool = False) -> float:
    """Convert a quantity to a float in the given (SI) unit.

    Parameters
    ----------
    value : str, pint.Quantity or float
        ``"80.8 GPa"``, ``ureg.Quantity(80.8, "GPa")``, or a plain number. A plain number is
        accepted only where ``unit`` is dimensionless or angular (radians); elsewhere it is an error,
        because guessing its unit would hide mistakes.
    unit : str
        The unit the solvers expect, e.g. ``"Pa"``, ``"N*m/rad"``, ``"kg*m^2"``.
    plain_is_si : bool
        Take a plain number as already in ``unit`` (the Python API's contract: floats are SI).
        Model files and the command line leave this off, so a number there must carry its unit.

    Returns
    -------
    float
        The magnitude in ``unit``.

    Raises
    ------
    UnitError
        If the value is not a quantity of the dimension of ``unit``.
    """
    import numpy as np

    if (
        plain_is_si
        and isinstance(value, (int, float, np.integer, np.floating))
        and not isinstance(value, bool)
    ):
        out = float(value)
        if not np.isfinite(out):
            raise UnitError(
                f"{value!r} is not finite; give a finite number" + (f" in {unit}" if unit else "")
            )
        return out
    if isinstance(value, str):
        # a model file holds thousands of "number unit" texts with a handful of distinct units:
        # read the number directly and convert with the unit's factor, parsed once by pint
        m = _NUMBER_UNIT.match(value)
        if m is not None:
            factor = _linear_factor(m.group(2), unit)
            if factor is not None:
                out = float(m.group(1)) * factor
                if np.isfinite(out):
                    return out
    return _slow_to_si(value, unit)


_NUMBER_UNIT = re.compile(r"^\s*([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)\s+(\S.*?)\s*$")


@functools.lru_cache(maxsize=512)
def _linear_factor(unit_text: str, unit: str) -> float | None:
    """``unit_text`` in ``unit`` when the conversion is a pure factor (None: offset units, errors)."""
    try:
        one, zero = _slow_to_si(f"1 {unit_text}", unit), _slow_to_si(f"0 {unit_text}", unit)
    except UnitError:
        return None  # the full path gives the message, naming the user's own text
    return one if zero == 0.0 else None


def _slow_to_si(value: Any, unit: str) -> float:
    import numpy as np

    q = _coerce(value, unit)
    ureg = registry()
    target = ureg.Quantity(1.0, unit)
    if (
        _angular(q)
        and not _angular(target)
        and q.dimensionality == target.dimensionality == ureg.Quantity(1.0, "Hz").dimensionality
    ):
        # a speed asked for as a frequency: "1500 rpm" is 25 Hz (cycles), not 157 1/s (radians)
        q = q.to("turn/s").magnitude * ureg.Quantity(1.0, "1/s")
    elif _angular(target) and not _angular(q) and any(u.endswith("hertz") for u, _ in q.unit_items()):
        # a frequency asked for as a speed: "25 Hz" is 25 turns a second (157 rad/s), not 25 rad/s
        q = ureg.Quantity(q.to("Hz").magnitude, "turn/s")
    if q.dimensionless and not target.dimensionless:
        what = "is an angle" if _angular(q) else "has no unit"
        raise UnitError(
            f"{value!r} {what}; expected a quantity of {_dimension_text(unit)}, "
            f"e.g. '{_example(value)} {unit}'"
        )
    if q.dimensionality != target.dimensionality:
        raise UnitError(
            f"{value!r} is in {q.units:~P} ({q.dimensionality}); expected a quantity of "
            f"{_dimension_text(unit)}, e.g. '{_example(q.magnitude)} {unit}'"
        )
    out = float(q.m_as(unit))
    if not np.isfinite(out):
        raise UnitError(f"{value!r} is not finite; give a finite number" + (f" in {unit}" if unit else ""))
    return out


_ANGLES = {
    "radian",
    "degree",
    "turn",
    "revolution",
    "revolutions_per_minute",
    "revolutions_per_second",
    "arcminute",
    "arcsecond",
    "gradian",
}


def _angular(q: pint.Quantity) -> bool:
    """Whether a quantity's units carry an angle (pint counts angles as dimensionless)."""
    return any(name in _ANGLES for name, _ in q.unit_items())


def _example(value: Any) -> str:
    try:
        return f"{float(getattr(value, 'magnitude', value)):g}"
    except (TypeError, ValueError):
        return "1"


def si_field(
    element: str | None,
    field: str,
    value: Any,
    unit: str,
    *,
    low: float | None = None,
    high: float | None = None,
    low_open: bool = False,
    high_open: bool = False,
    positive: bool = False,
    nonnegative: bool = False,
    nonzero: bool = False,
    what: str | None = None,
) -> float:
    """:func:`to_si` for a field of a model element (plain numbers are SI), checked, errors naming both.

    The value must be finite and within the magnitude a machine can have in its unit (the bounds of
    the model files, :data:`mechdyn.checks.MAGNITUDE_LIMITS`); the keywords narrow the range
    further (:func:`mechdyn.checks.check_number`).

    Parameters
    ----------
    element : str or None
        The element's name, for the message.
    field : str
        The field's name, for the message.
    value : str, pint.Quantity or float
        The value: a quantity, or a plain number taken as already in ``unit``.
    unit : str
        The SI unit wanted, e.g. ``"N*m/rad"``.
    low, high : float, optional
        Bounds of the accepted range, in ``unit``; closed unless ``low_open`` / ``high_open``.
    low_open, high_open : bool
        Exclude the bound itself.
    positive : bool
        The value must be positive (and at least :data:`mechdyn.checks.SMALLEST_POSITIVE` of its unit).
    nonnegative : bool
        The value must not be negative.
    nonzero : bool
        The value must not be zero (either sign).
    what : str, optional
        What the value is, in words, for the message.

    Raises
    ------
    mechdyn.errors.ModelError
        With the element and field, the value and the expected unit or range.
    """
    from mechdyn.checks import check_number
    from mechdyn.errors import ModelError

    if isinstance(value, str) or not isinstance(value, (int, float)) or isinstance(value, bool):
        try:
            value = to_si(value, unit, plain_is_si=True)
        except UnitError as exc:
            raise ModelError(str(exc), element=element, field=field) from None
    return check_number(
        element,
        field,
        value,
        unit,
        low=low,
        high=high,
        low_open=low_open,
        high_open=high_open,
        positive=positive,
        nonnegative=nonnegative,
        nonzero=nonzero,
        what=what,
    )


def convert(value: Any, unit: str, display: str) -> Any:
    """An SI value (float or array) in ``unit`` shown in the display unit ``display``.

    Parameters
    ----------
    value : float or ndarray
        Magnitude in ``unit``.
    unit : str
        Its unit, e.g. ``"N"``, ``"N/m"``.
    display : str
        The unit to show it in, e.g. ``"tonf"``, ``"kN/mm"``; any unit of the same dimension that
        pint reads.

    Returns
    -------
    float or ndarray
        The magnitude in ``display``. None stays None.

    Raises
    ------
    UnitError
        If ``display`` is not a unit of the dimension of ``unit``.

    Examples
    --------
    >>> from mechdyn.units import convert
    >>> convert(9806.65, "N", "tonf")
    1.0
    >>> convert(1.2e9, "N/m", "N/µm")
    1200.0
    """
    import numpy as np

    if value is None or unit == display:
        return value
    import pint

    ureg = registry()
    try:
        factor = ureg.Quantity(1.0, unit).m_as(display)
    except (pint.errors.PintError, ValueError, AttributeError, TypeError) as exc:
        raise UnitError(
            f"cannot show {unit} in {display!r} ({exc}); give a unit of {_dimension_text(unit)}"
        ) from None
    if isinstance(value, (int, float, np.integer, np.floating)):
        return float(value) * factor
    return np.asarray(value) * factor


# Unit suffixes of result keys and table columns, longest first where one ends another; what the
# key's end says, in pint's spelling. Results name their keys this way so that a key is its own unit.
_KEY_UNITS: tuple[tuple[str, str], ...] = (
    ("_N_per_mm_um", "N/(mm*um)"),
    ("_Nm_s_per_rad", "N*m*s/rad"),
    ("_Nm_per_rad", "N*m/rad"),
    ("_kg_m2", "kg*m^2"),
    ("_N_s_per_m", "N*s/m"),
    ("_N_per_m", "N/m"),
    ("_m_per_N", "m/N"),
    ("_m_per_s2", "m/s^2"),
    ("_m_per_s", "m/s"),
    ("_rad_s2", "rad/s^2"),
    ("_rad_s", "rad/s"),
    ("_Nm", "N*m"),
    ("_Pa", "Pa"),
    ("_kg", "kg"),
    ("_hz", "Hz"),
    ("_Hz", "Hz"),
    ("_rpm", "rpm"),
    ("_deg", "deg"),
    ("_rad", "rad"),
    ("_mm", "mm"),
    ("_m", "m"),
    ("_N", "N"),
    ("_s", "s"),
    ("_W", "W"),
    ("_J", "J"),
    ("_percent", "%"),
    ("_relative", "1"),
    ("_ratio", "1"),
)


def key_unit(key: str) -> str | None:
    """The unit a result key or column name ends with (``"stroke_m"`` → ``"m"``), None if none.

    Parameters
    ----------
    key : str
        A summary key or column name.

    Dimensionless ratios end in ``_relative`` or ``_ratio`` and give ``"1"``.
    """
    return next((u for suffix, u in _KEY_UNITS if key.endswith(suffix)), None)


def key_suffix(unit: str) -> str:
    """The key suffix of a quantity's SI unit, so that a name built with it reads back its unit with
    :func:`key_unit`: ``"MN/m"`` gives ``"N_per_m"``, ``"mm"`` gives ``"m"``; ``""`` for a number
    without unit (or a unit no suffix names).

    Parameters
    ----------
    unit : str
        Any unit pint reads.
    """
    if not unit or unit in ("1", "dimensionless"):
        return ""
    quantity = registry().Quantity(1.0, unit)
    # pint takes the radian as dimensionless: whether a unit is angular is read from its name
    angular = any(word in unit for word in ("rad", "rpm", "deg", "rev", "°"))
    for suffix, si in _SUFFIXES[0] if angular else _SUFFIXES[1]:
        if quantity.is_compatible_with(si):
            return suffix
    return ""


# (suffix, SI unit), angular then the others; the first of the right dimension names a column
_SUFFIXES = (
    (
        ("Nm_per_rad", "N*m/rad"),
        ("Nm_s_per_rad", "N*m*s/rad"),
        ("rad_s2", "rad/s^2"),
        ("rad_s", "rad/s"),
        ("rad", "rad"),
    ),
    (
        ("N_per_mm_um", "N/(mm*um)"),
        ("N_s_per_m", "N*s/m"),
        ("N_per_m", "N/m"),
        ("m_per_N", "m/N"),
        ("m_per_s2", "m/s^2"),
        ("m_per_s", "m/s"),
        ("Hz", "Hz"),
        ("Nm", "N*m"),
        ("Pa", "Pa"),
        ("kg_m2", "kg*m^2"),
        ("kg", "kg"),
        ("m", "m"),
        ("N", "N"),
        ("s", "s"),
        ("W", "W"),
    ),
)


#: How a unit pint reads is shown to a reader ("N*m" as "N·m", "kg*m^2" as "kg·m²").
SHOWN_UNITS = {
    "kg*m^2": "kg·m²",
    "N*m/rad": "N·m/rad",
    "N*m*s/rad": "N·m·s/rad",
    "N*s/m": "N·s/m",
    "N*m": "N·m",
    "m/s^2": "m/s²",
    "rad/s^2": "rad/s²",
    "N/(mm*um)": "N/(mm·µm)",
    "1": "",
}


def key_label(key: str) -> tuple[str, str]:
    """A result key as a table shows it: words, and the unit its suffix names.

    ``"bolt_stiffness_vdi2230_N_per_m"`` gives ``("bolt stiffness vdi2230", "N/m")``;
    ``"load_factor"`` gives ``("load factor", "")``.

    Parameters
    ----------
    key : str
        A summary or breakdown key.

    Returns
    -------
    (str, str)
        The words and the unit as shown (``"N·m"``, ``""`` for none or a ratio).

    Examples
    --------
    >>> from mechdyn.units import key_label
    >>> key_label("member_stiffness_N_per_m")
    ('member stiffness', 'N/m')
    """
    for suffix, unit in _KEY_UNITS:
        if key.endswith(suffix) and len(key) > len(suffix):
            stem = key[: -len(suffix)]
            shown = SHOWN_UNITS.get(unit, unit)
            if unit == "1":  # a ratio keeps its word
                stem = key
            return _words(stem), shown
    return _words(key), ""


def _words(stem: str) -> str:
    """A key's words: underscores as spaces, a floor criterion's name as written (VC-B, not vc b)."""
    return re.sub(r"\bvc ([a-e])\b", lambda m: f"VC-{m.group(1).upper()}", stem.replace("_", " "))


def show(value: float, unit: str, display: str, spec: str = "g") -> str:
    """An SI value as text in a display unit, for messages and titles: ``show(0.0125, "m", "mm")``
    gives ``"12.5 mm"``.

    Parameters
    ----------
    value : float
        Magnitude in ``unit``.
    unit, display : str
        Its unit and the unit to show it in.
    spec : str
        Format specification of the number (``"g"``, ``".3f"``).
    """
    return f"{convert(value, unit, display):{spec}} {display}"


# (SI unit, [(smallest magnitude, display unit as pint reads it, as shown)], largest first): the unit a
# table shows a quantity in, by its size; a quantity of another unit is shown in its own
_READABLE: dict[str, list[tuple[float, str, str]]] = {
    "m": [(10.0, "m", "m"), (1e-4, "mm", "mm"), (0.0, "um", "µm")],
    "N": [(1e7, "MN", "MN"), (1e4, "kN", "kN"), (0.0, "N", "N")],
    "N·m": [(1e7, "MN*m", "MN·m"), (1e4, "kN*m", "kN·m"), (0.0, "N*m", "N·m")],
    "N/m": [(1e6, "kN/mm", "kN/mm"), (1e3, "N/mm", "N/mm"), (0.0, "N/m", "N/m")],
    "N·m/rad": [(1e7, "MN*m/rad", "MN·m/rad"), (1e4, "kN*m/rad", "kN·m/rad"), (0.0, "N*m/rad", "N·m/rad")],
    "W": [(1e6, "MW", "MW"), (1e3, "kW", "kW"), (0.0, "W", "W")],
    "J": [(1e6, "MJ", "MJ"), (1e3, "kJ", "kJ"), (0.0, "J", "J")],
    "Pa": [(1e6, "MPa", "MPa"), (1e3, "kPa", "kPa"), (0.0, "Pa", "Pa")],
    "m/s": [(10.0, "m/s", "m/s"), (0.0, "mm/s", "mm/s")],  # a vibration velocity is read in mm/s
    "N·s/m": [(1e6, "kN*s/mm", "kN·s/mm"), (1e3, "kN*s/m", "kN·s/m"), (0.0, "N*s/m", "N·s/m")],
}


# the SI units a value is named in, first match wins (pint's base units where none matches)
_NAMED_SI = (
    "m",
    "kg",
    "s",
    "rad",
    "N",
    "N*m",
    "N/m",
    "N*s/m",
    "N*m/rad",
    "N*m*s/rad",
    "Pa",
    "W",
    "kg*m^2",
    "kg/m^3",
    "m/s",
    "m/s^2",
    "rad/s",
    "rad/s^2",
    "1/s",
    "K",
)


def si_unit(unit: str) -> str:
    """The SI unit a value given in ``unit`` is held in, by its name where SI has one: ``"MPa"`` →
    ``"Pa"``, ``"kN/mm"`` → ``"N/m"``, ``"rpm"`` → ``"rad/s"``, ``"kN*m/rad"`` → ``"N*m/rad"``
    (pint's radian is a base unit, so a torsional stiffness is not a moment); a unit none of the
    named ones matches is pint's base units (``"kg*m/s"``).

    Parameters
    ----------
    unit : str
        A unit pint reads (``""``: dimensionless).

    Returns
    -------
    str
        The SI unit's text, ``""`` for a dimensionless value.
    """
    if not unit:
        return ""
    ureg = registry()
    base = ureg.Quantity(1.0, unit).to_base_units().units
    if base == ureg.dimensionless:
        return ""
    for name in _NAMED_SI:
        if ureg.Quantity(1.0, name).to_base_units().units == base:
            return name
    return str(base)


def readable_unit(value: float, unit: str) -> tuple[str, str]:
    """The unit a designer reads a value of this size in (see :func:`readable`): as pint reads it and
    as shown, e.g. ``("um", "µm")``; the unit itself where none is listed.

    Parameters
    ----------
    value : float
        The value (or a column's largest magnitude) in ``unit``.
    unit : str
        Its SI unit as :func:`key_label` shows it.
    """
    si = _SHOWN_TO_SI.get(unit, unit)
    choices = _READABLE.get(unit)
    if not choices or not math.isfinite(value) or value == 0:
        return si, unit
    a = abs(value)
    return next(((display, shown) for smallest, display, shown in choices if a >= smallest), (si, unit))


def readable(value: float, unit: str) -> tuple[float, str]:
    """A value in the unit a designer reads it in, picked by its kind and size: a 1.5 m stroke in
    mm, a 20 µm displacement in µm, a 530 kN force in kN, a 2.4 MN force in MN, a mount's 4·10⁸ N/m
    in kN/mm. Units not listed, zero and non-finite values stay as they are.

    Parameters
    ----------
    value : float
        The value in ``unit``.
    unit : str
        Its SI unit as :func:`key_label` shows it (``"m"``, ``"N"``, ``"N·m"``, ``"N/m"``, ``"W"``,
        ``"Pa"``).

    Returns
    -------
    (float, str)
        The value and its unit as shown.

    Examples
    --------
    >>> from mechdyn.units import readable
    >>> readable(1.4963, "m")
    (1496.3, 'mm')
    """
    display, shown = readable_unit(value, unit)
    if shown == unit:
        return value, unit
    return float(convert(value, _SHOWN_TO_SI.get(unit, unit), display)), shown


_SHOWN_TO_SI = {shown: si for si, shown in SHOWN_UNITS.items()}


def check_poisson_ratio(element: str | None, field: str, value: Any) -> float:
    """A Poisson's ratio ν, checked: finite and in (−1, 0.5), the range of a stable isotropic solid
    (E > 0 with a positive bulk and shear modulus; e.g. Timoshenko & Goodier, *Theory of Elasticity*).

    Parameters
    ----------
    element : str or None
        The element (material, gear, tooth) it belongs to, for the message.
    field : str
        The parameter's name, for the message.
    value : float or quantity
        ν, dimensionless.

    Returns
    -------
    float
        ν.

    Raises
    ------
    mechdyn.errors.ModelError
        Naming the element, the parameter, the value and the range.
    """
    from mechdyn.errors import ModelError

    nu = si_field(element, field, value, "", what="Poisson's ratio")
    if not -1.0 < nu < 0.5:
        shown = f"{nu:.6g}" if element is not None else f"{field} = {nu:.6g}"
        raise ModelError(f"{shown} must lie in (−1, 0.5)", element=element, field=field)
    return nu
