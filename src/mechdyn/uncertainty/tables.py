"""An uncertain value written as a table of a model or study file.

The forms a file may hold (TOML shown; every number with its unit unless the value has none)::

    stiffness = {distribution = "lognormal", median = "2 MN/m", cov = 0.15}
    gap       = {distribution = "normal", mean = "2 mm", std = "0.05 mm"}
    gap       = {distribution = "normal", std = "0.05 mm"}              # mean: the model's value
    force     = {distribution = "normal", mean = "80 kN", std = "8 kN", lower = "60 kN"}  # truncated
    length    = {distribution = "uniform", low = "0.99 m", high = "1.01 m"}
    mass      = {distribution = "triangular", low = "95 kg", mode = "100 kg", high = "110 kg"}
    grade     = {distribution = "levels", values = ["1 MN/m", "2 MN/m"], probabilities = [0.3, 0.7]}
    hardness  = {tolerance = "shore_a_5"}                                # nominal: the model's value
    pitch     = {tolerance = "iso1328_fpt", grade = 6, d = "120 mm", m_n = "3 mm"}
    amplitude = {tolerance = "iso1328_fpt", grade = 6, d = "120 mm", m_n = "3 mm", magnitude = true}
    mounts    = {tolerance = "band", plus_minus = "20 %", shape = "uniform"}

:func:`variable_from_dict` reads one; its errors (:class:`mechdyn.errors.ModelError`) name the field,
the value and the fix, and the file reader adds the file and the table.
"""

from __future__ import annotations

import difflib
from collections.abc import Mapping
from typing import Any

from mechdyn.errors import ModelError
from mechdyn.uncertainty.distributions import (
    Variable,
    levels,
    lognormal,
    normal,
    triangular,
    truncated,
    uniform,
)
from mechdyn.uncertainty.tolerances import tolerance

__all__ = ["DISTRIBUTION_KEYS", "TOLERANCE_KEYS", "variable_from_dict"]

_TRUNCATION = ("lower", "upper")
DISTRIBUTION_KEYS: dict[str, tuple[str, ...]] = {
    "normal": ("mean", "std", "cov", *_TRUNCATION),
    "lognormal": ("median", "mean", "cov", "std", "sigma_ln", *_TRUNCATION),
    "uniform": ("low", "high"),
    "triangular": ("low", "mode", "high"),
    "levels": ("values", "probabilities"),
}
"""The keys each distribution accepts besides ``distribution`` (``lower``/``upper`` truncate)."""

_TOLERANCE_KEYS = ("nominal", "shape", "plus_minus", "grade", "d", "m_n", "cov", "magnitude")
TOLERANCE_KEYS = _TOLERANCE_KEYS
"""The keys a tolerance table accepts besides ``tolerance`` (the model-file reference lists them)."""


def _unknown(name: str, key: str, allowed: tuple[str, ...], what: str) -> ModelError:
    close = difflib.get_close_matches(key, allowed, n=1)
    hint = f"did you mean {close[0]!r}? " if close else ""
    return ModelError(
        f"{key!r} is not a field of {what}; {hint}its fields are {', '.join(allowed)}",
        element=name,
        field=key,
    )


def variable_from_dict(
    name: str, spec: Mapping[str, Any], unit: str = "", *, nominal: Any = None
) -> Variable:
    """A :class:`~mechdyn.uncertainty.Variable` from a file's table (see the module docstring).

    Parameters
    ----------
    name : str
        The variable's name (the study's parameter path), for errors and reports.
    spec : mapping
        The table as read from the file: ``distribution = ...`` with its parameters, or
        ``tolerance = ...`` with the class's.
    unit : str
        The SI unit of the value the table describes (the field's unit; ``""`` for none).
    nominal : float, str or quantity, optional
        The model's own value, in ``unit`` when a plain number: the default of a normal's ``mean``, a
        lognormal's ``median`` and a tolerance class's ``nominal``.

    Raises
    ------
    mechdyn.errors.ModelError
        Naming the variable (element), the field, the value and what to write instead.

    Examples
    --------
    >>> from mechdyn.uncertainty import variable_from_dict
    >>> table = {"distribution": "lognormal", "median": "2 MN/m", "cov": 0.15}
    >>> k = variable_from_dict("mount.stiffness", table, "N/m")
    >>> k.kind, round(k.parameters["median"])
    ('lognormal', 2000000)
    """
    if not isinstance(spec, Mapping):
        raise ModelError(
            f'{spec!r} is not a table; write e.g. {{distribution = "normal", mean = ..., std = ...}} '
            'or {tolerance = "shore_a_5"}',
            element=name,
            field="distribution",
        )
    has_dist, has_tol = "distribution" in spec, "tolerance" in spec
    if has_dist == has_tol:
        raise ModelError(
            (
                "give distribution or tolerance, not both"
                if has_dist
                else "the table has neither distribution nor tolerance"
            )
            + f' (got {dict(spec)!r}); write e.g. distribution = "lognormal" or tolerance = "shore_a_5"',
            element=name,
            field="distribution",
        )
    if has_tol:
        extra = [k for k in spec if k != "tolerance" and k not in _TOLERANCE_KEYS]
        if extra:
            raise _unknown(name, extra[0], _TOLERANCE_KEYS, "a tolerance table")
        options = {k: spec[k] for k in _TOLERANCE_KEYS if k in spec}
        if not options.get("magnitude"):  # a magnitude is folded at zero, whatever the model's value
            options.setdefault("nominal", nominal)
        return tolerance(name, spec["tolerance"], unit=unit, **options)

    kind = spec["distribution"]
    if kind not in DISTRIBUTION_KEYS:
        close = difflib.get_close_matches(str(kind), list(DISTRIBUTION_KEYS), n=1)
        hint = f"did you mean {close[0]!r}? " if close else ""
        raise ModelError(
            f"distribution = {kind!r} is not known; {hint}give one of "
            f"{', '.join(map(repr, DISTRIBUTION_KEYS))} "
            "(truncate any of them with lower/upper)",
            element=name,
            field="distribution",
        )
    allowed = DISTRIBUTION_KEYS[kind]
    for key in spec:
        if key != "distribution" and key not in allowed:
            raise _unknown(name, key, allowed, f"a {kind} distribution")
    p = {k: v for k, v in spec.items() if k != "distribution"}
    lower, upper = p.pop("lower", None), p.pop("upper", None)
    variable = _build(name, kind, p, unit, nominal)
    if lower is not None or upper is not None:
        variable = truncated(variable, lower, upper)
    return variable


def _build(name: str, kind: str, p: dict[str, Any], unit: str, nominal: Any) -> Variable:
    def need(key: str, example: str) -> Any:
        if key not in p:
            raise ModelError(
                f"a {kind} distribution needs {key}; write e.g. {key} = {example}", element=name, field=key
            )
        return p[key]

    if kind == "normal":
        mean = p.get("mean", nominal)
        if mean is None:
            raise ModelError(
                "a normal distribution needs its mean (the model gives none here); write e.g. mean = '2 mm'",
                element=name,
                field="mean",
            )
        if ("std" in p) == ("cov" in p):
            raise ModelError(
                "give exactly one of std or cov"
                + (f" (got std = {p['std']!r} and cov = {p['cov']!r})" if "std" in p else "")
                + "; write e.g. std = '0.05 mm' or cov = 0.05",
                element=name,
                field="std",
            )
        if "cov" in p:
            from mechdyn.uncertainty.distributions import _si

            m = _si(name, "mean", mean, unit)
            return normal(name, m, abs(m) * _si(name, "cov", p["cov"], "", positive=True), unit)
        return normal(name, mean, p["std"], unit)
    if kind == "lognormal":
        centre = {k: p[k] for k in ("median", "mean") if k in p}
        if not centre:
            if nominal is None:
                raise ModelError(
                    "a lognormal distribution needs its median or mean (the model gives none here); "
                    "write e.g. median = '2 MN/m'",
                    element=name,
                    field="median",
                )
            centre = {"median": nominal}
        spread = {k: p[k] for k in ("cov", "std", "sigma_ln") if k in p}
        return lognormal(name, unit=unit, **centre, **spread)
    if kind == "uniform":
        return uniform(name, need("low", "'0.99 m'"), need("high", "'1.01 m'"), unit)
    if kind == "triangular":
        return triangular(
            name, need("low", "'95 kg'"), need("mode", "'100 kg'"), need("high", "'110 kg'"), unit
        )
    return levels(name, need("values", "['1 MN/m', '2 MN/m']"), p.get("probabilities"), unit)
