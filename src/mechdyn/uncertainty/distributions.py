"""One uncertain value: a named variable with its unit and its probability distribution.

The distributions are SciPy's (:mod:`scipy.stats`): normal, lognormal, uniform, triangular; a
truncation of any continuous one and a set of discrete levels are thin wrappers here that keep the
same calls (``ppf``, ``isf``, ``cdf``, ``mean``, ``std``). Every parameter is converted to SI at the
constructor (:func:`mechdyn.units.to_si`: a plain number is already SI, a text or a pint quantity
carries its unit), so the samples a propagation draws are bare SI floats.

A bad parameter raises :class:`mechdyn.errors.ModelError` naming the variable, the field, the value and
what to give instead.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from mechdyn.errors import ModelError

__all__ = [
    "Variable",
    "levels",
    "lognormal",
    "normal",
    "triangular",
    "truncated",
    "uniform",
]


@dataclass(frozen=True, repr=False)
class Variable:
    """An uncertain input: its name, SI unit and distribution.

    Build it with :func:`normal`, :func:`lognormal`, :func:`uniform`, :func:`triangular`,
    :func:`levels`, :func:`truncated`, a tolerance class (:func:`mechdyn.uncertainty.tolerance`) or
    from a model file's table (:func:`mechdyn.uncertainty.variable_from_dict`).

    Attributes
    ----------
    name : str
        What the value is, e.g. ``"mount.stiffness"`` (the study's parameter path).
    unit : str
        The SI unit of the samples (``"N/m"``; ``""`` for a number without unit).
    kind : str
        ``"normal"``, ``"lognormal"``, ``"uniform"``, ``"triangular"``, ``"levels"`` or
        ``"truncated <kind>"``.
    parameters : dict
        The parameters as given, in SI (mean, std, median, cov, low, high, ...), for reports.
    distribution : object
        The frozen SciPy distribution (or a wrapper with the same calls) in SI.
    source : str
        Where the scatter comes from (a standard, a tolerance class, an assumption).
    """

    name: str
    unit: str
    kind: str
    parameters: dict[str, Any]
    distribution: Any = field(compare=False)
    source: str = ""

    @property
    def continuous(self) -> bool:
        """Whether the distribution is continuous (FORM and SORM need it; sampling does not)."""
        return self.kind != "levels" and not self.kind.endswith(" levels")

    def ppf(self, q: Any) -> np.ndarray:
        """The quantile function (inverse CDF) at probabilities ``q`` (fraction), in the unit.

        Parameters
        ----------
        q : array_like
            Probabilities, fraction in [0, 1].
        """
        return np.asarray(self.distribution.ppf(q), dtype=float)

    def isf(self, q: Any) -> np.ndarray:
        """The inverse survival function at probabilities ``q`` (fraction): exact in the upper tail
        where ``ppf(1 - q)`` loses digits.

        Parameters
        ----------
        q : array_like
            Probabilities of exceedance, fraction in [0, 1].
        """
        return np.asarray(self.distribution.isf(q), dtype=float)

    def cdf(self, x: Any) -> np.ndarray:
        """The cumulative distribution function at ``x`` (in the variable's unit).

        Parameters
        ----------
        x : array_like
            Values, in the variable's unit.
        """
        return np.asarray(self.distribution.cdf(x), dtype=float)

    def sf(self, x: Any) -> np.ndarray:
        """The survival function ``1 − F(x)`` at ``x`` (in the variable's unit), exact in the upper tail.

        Parameters
        ----------
        x : array_like
            Values, in the variable's unit.
        """
        return np.asarray(self.distribution.sf(x), dtype=float)

    def to_standard_normal(self, x: Any) -> np.ndarray:
        """The standard normal values with the probabilities of ``x``: ``Φ⁻¹(F(x))``, the inverse of
        :meth:`from_standard_normal` (continuous variables), from the upper tail above the median.

        Parameters
        ----------
        x : array_like
            Values, in the variable's unit.
        """
        from scipy.special import ndtri

        x = np.asarray(x, dtype=float)
        c, s = self.cdf(x), self.sf(x)
        tiny = 1e-300
        return np.where(c <= 0.5, ndtri(np.maximum(c, tiny)), -ndtri(np.maximum(s, tiny)))

    @property
    def mean(self) -> float:
        """The mean, in the unit."""
        return float(self.distribution.mean())

    @property
    def std(self) -> float:
        """The standard deviation, in the unit."""
        return float(self.distribution.std())

    def from_standard_normal(self, z: Any) -> np.ndarray:
        """The values whose probabilities are those of standard normal values ``z`` (the Nataf map):
        ``F⁻¹(Φ(z))``, computed from the upper tail where ``z > 0`` so that no digit is lost there.

        Parameters
        ----------
        z : array_like
            Standard normal values (dimensionless).
        """
        from scipy.special import ndtr

        z = np.asarray(z, dtype=float)
        out = np.empty_like(z)
        low = z <= 0
        out[low] = self.ppf(ndtr(z[low]))
        out[~low] = self.isf(ndtr(-z[~low]))
        return out

    def describe(self) -> str:
        """One line for a report: the name, the kind and its parameters in the unit."""
        shown = ", ".join(f"{k} {_number(v)}" for k, v in self.parameters.items())
        unit = f" [{self.unit}]" if self.unit else ""
        return f"{self.name}{unit}: {self.kind} ({shown})"

    def __repr__(self) -> str:
        return f"<Variable {self.describe()}>"


def _number(v: Any) -> str:
    if isinstance(v, float):
        return f"{v:.6g}"
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_number(x) for x in v) + "]"
    return str(v)


def _si(name: str, field_name: str, value: Any, unit: str, *, positive: bool = False) -> float:
    """A parameter in SI, or a ModelError naming the variable, the field, the value and the fix."""
    from mechdyn.units import UnitError, to_si

    try:
        out = to_si(value, unit, plain_is_si=True)
    except UnitError as exc:
        raise ModelError(str(exc), element=name, field=field_name) from None
    if not math.isfinite(out):
        raise ModelError(f"{value!r} is not finite; give a finite number", element=name, field=field_name)
    if positive and out <= 0:
        raise ModelError(
            f"{value!r} must be positive; give a value above zero"
            + (f" in {unit}" if unit else "")
            + (" (a scatter of zero is no scatter: leave the value fixed instead)" if out == 0 else ""),
            element=name,
            field=field_name,
        )
    return out


def normal(name: str, mean: Any, std: Any, unit: str = "", *, source: str = "") -> Variable:
    """A normally distributed value.

    Parameters
    ----------
    name : str
        The variable's name (the study's parameter path).
    mean : float, str or quantity
        The mean, in ``unit`` when a plain number.
    std : float, str or quantity
        The standard deviation (positive), in ``unit`` when a plain number.
    unit : str
        The SI unit of the variable (``""`` for a number without unit).
    source : str
        Where the scatter comes from.

    Examples
    --------
    >>> from mechdyn.uncertainty import normal
    >>> round(normal("gap", "2 mm", "0.1 mm", "m").std, 6)
    0.0001
    """
    from scipy import stats

    mu = _si(name, "mean", mean, unit)
    sigma = _si(name, "std", std, unit, positive=True)
    return Variable(name, unit, "normal", {"mean": mu, "std": sigma}, stats.norm(mu, sigma), source)


def lognormal(
    name: str,
    *,
    median: Any = None,
    mean: Any = None,
    cov: Any = None,
    std: Any = None,
    sigma_ln: Any = None,
    unit: str = "",
    source: str = "",
) -> Variable:
    """A lognormally distributed (positive) value, given by its median or mean and its scatter.

    ``ln X`` is normal with standard deviation ``σ_ln = √(ln(1 + cov²))``; the median is ``exp(µ_ln)``
    and the mean ``median·√(1 + cov²)`` (e.g. Ang & Tang, *Probability Concepts in Engineering*, 2nd ed.,
    2007, §3.2.3).

    Parameters
    ----------
    name : str
        The variable's name.
    median : float, str or quantity, optional
        The median (positive), in ``unit`` when a plain number; give it or ``mean``.
    mean : float, str or quantity, optional
        The mean (positive), in ``unit`` when a plain number.
    cov : float, optional
        Coefficient of variation (std / mean), dimensionless; give one of ``cov``, ``std``,
        ``sigma_ln``.
    std : float, str or quantity, optional
        Standard deviation, in ``unit`` when a plain number.
    sigma_ln : float, optional
        Standard deviation of ``ln X``, dimensionless.
    unit : str
        The SI unit of the variable.
    source : str
        Where the scatter comes from.

    Examples
    --------
    >>> from mechdyn.uncertainty import lognormal
    >>> k = lognormal("mount.stiffness", median="2 MN/m", cov=0.15, unit="N/m")
    >>> round(k.ppf(0.5).item())
    2000000
    """
    from scipy import stats

    centres = {"median": median, "mean": mean}
    given = [k for k, v in centres.items() if v is not None]
    if len(given) != 1:
        raise ModelError(
            f"give exactly one of median or mean (got {', '.join(given) or 'neither'}), "
            "e.g. median = '2 MN/m'",
            element=name,
            field="median" if not given else given[1],
        )
    spreads = {"cov": cov, "std": std, "sigma_ln": sigma_ln}
    said = [k for k, v in spreads.items() if v is not None]
    if len(said) != 1:
        raise ModelError(
            f"give exactly one of cov, std or sigma_ln (got {', '.join(said) or 'none'}), e.g. cov = 0.15",
            element=name,
            field="cov" if not said else said[1],
        )
    centre = _si(name, given[0], centres[given[0]], unit, positive=True)
    if said[0] == "cov":
        c = _si(name, "cov", cov, "", positive=True)
    elif said[0] == "std":
        c = _si(name, "std", std, unit, positive=True) / (
            centre if given[0] == "mean" else _mean_from_median_std(name, centre, std, unit)
        )
    else:
        s = _si(name, "sigma_ln", sigma_ln, "", positive=True)
        c = math.sqrt(math.expm1(s * s))
    s_ln = math.sqrt(math.log1p(c * c))
    med = centre if given[0] == "median" else centre / math.sqrt(1.0 + c * c)
    params = {"median": med, "cov": c, "sigma_ln": s_ln}
    return Variable(name, unit, "lognormal", params, stats.lognorm(s_ln, scale=med), source)


def _mean_from_median_std(name: str, median: float, std: Any, unit: str) -> float:
    # mean m and std s with median M: m = M·√(1+c²), s = m·c → solve s² = M²(1+c²)c² for c²
    s = _si(name, "std", std, unit, positive=True)
    c2 = (-1.0 + math.sqrt(1.0 + 4.0 * (s / median) ** 2)) / 2.0
    return median * math.sqrt(1.0 + c2)


def uniform(name: str, low: Any, high: Any, unit: str = "", *, source: str = "") -> Variable:
    """A value uniformly distributed between ``low`` and ``high``.

    Parameters
    ----------
    name : str
        The variable's name.
    low, high : float, str or quantity
        The bounds (``low < high``), in ``unit`` when plain numbers.
    unit : str
        The SI unit of the variable.
    source : str
        Where the scatter comes from.
    """
    from scipy import stats

    a, b = _si(name, "low", low, unit), _si(name, "high", high, unit)
    if not a < b:
        raise ModelError(
            f"high = {high!r} is not above low = {low!r}; give low < high", element=name, field="high"
        )
    return Variable(name, unit, "uniform", {"low": a, "high": b}, stats.uniform(a, b - a), source)


def triangular(name: str, low: Any, mode: Any, high: Any, unit: str = "", *, source: str = "") -> Variable:
    """A triangular distribution between ``low`` and ``high`` peaking at ``mode``.

    Parameters
    ----------
    name : str
        The variable's name.
    low, mode, high : float, str or quantity
        The bounds and the most likely value (``low ≤ mode ≤ high``, ``low < high``), in ``unit``
        when plain numbers.
    unit : str
        The SI unit of the variable.
    source : str
        Where the scatter comes from.
    """
    from scipy import stats

    a, c, b = (_si(name, f, v, unit) for f, v in (("low", low), ("mode", mode), ("high", high)))
    if not a < b:
        raise ModelError(
            f"high = {high!r} is not above low = {low!r}; give low < high", element=name, field="high"
        )
    if not a <= c <= b:
        raise ModelError(
            f"mode = {mode!r} is outside [low, high] = [{low!r}, {high!r}]; give a mode between them",
            element=name,
            field="mode",
        )
    dist = stats.triang((c - a) / (b - a), loc=a, scale=b - a)
    return Variable(name, unit, "triangular", {"low": a, "mode": c, "high": b}, dist, source)


class _Truncated:
    """A continuous distribution restricted to [low, high], by its own CDF and quantile function:
    ``F_T⁻¹(p) = F⁻¹(F(low) + p (F(high) − F(low)))`` (exact, no rejection)."""

    def __init__(self, base: Any, low: float, high: float):
        self.base, self.low, self.high = base, low, high
        self.c_low = float(base.cdf(low))
        self.s_high = float(base.sf(high))
        self.mass = 1.0 - self.c_low - self.s_high

    def ppf(self, q: Any) -> np.ndarray:
        q = np.asarray(q, dtype=float)
        # the side of the median where the base keeps its digits: its lower or its upper tail
        lower = self.c_low + q * self.mass
        upper = self.s_high + (1.0 - q) * self.mass
        out = np.where(lower <= 0.5, self.base.ppf(lower), self.base.isf(upper))
        return np.clip(out, self.low, self.high)

    def isf(self, q: Any) -> np.ndarray:
        return self.ppf(1.0 - np.asarray(q, dtype=float))

    def cdf(self, x: Any) -> np.ndarray:
        x = np.clip(np.asarray(x, dtype=float), self.low, self.high)
        return np.clip((self.base.cdf(x) - self.c_low) / self.mass, 0.0, 1.0)

    def sf(self, x: Any) -> np.ndarray:
        return 1.0 - self.cdf(x)

    def _expect(self, g: Any) -> float:
        # the base's density over [low, high] renormalised: quad on the pdf keeps ~1e-10 where quad
        # on the quantile function loses digits at a band's steep ends; an open side is cut where
        # the base has 1e-15 left, so that quad sees a finite range
        lb = max(self.low, float(self.base.ppf(1e-15)))
        ub = min(self.high, float(self.base.isf(1e-15)))
        return float(self.base.expect(g, lb=lb, ub=ub, conditional=True))

    def mean(self) -> float:
        return self._expect(lambda x: x)

    def std(self) -> float:
        m = self.mean()
        return math.sqrt(max(self._expect(lambda x: (x - m) ** 2), 0.0))


def truncated(variable: Variable, low: Any = None, high: Any = None) -> Variable:
    """A continuous variable restricted to ``[low, high]`` (parts outside a tolerance band rejected).

    Parameters
    ----------
    variable : Variable
        The distribution before truncation (normal, lognormal, triangular, ...).
    low, high : float, str or quantity, optional
        The bounds, in the variable's unit when plain numbers; at least one.

    Examples
    --------
    >>> from mechdyn.uncertainty import normal, truncated
    >>> h = truncated(normal("pad.shore_a", 60, 5 / 3), 55, 65)
    >>> float(h.ppf(0.0)), float(h.ppf(1.0))
    (55.0, 65.0)
    """
    name, unit = variable.name, variable.unit
    if not variable.continuous:
        raise ModelError(
            f"a {variable.kind} variable cannot be truncated; drop the levels outside the range instead",
            element=name,
            field="lower",
        )
    if low is None and high is None:
        raise ModelError(
            "give a lower or an upper bound (or both) to truncate at", element=name, field="lower"
        )
    a = -math.inf if low is None else _si(name, "lower", low, unit)
    b = math.inf if high is None else _si(name, "upper", high, unit)
    if not a < b:
        raise ModelError(
            f"upper = {high!r} is not above lower = {low!r}; give lower < upper", element=name, field="upper"
        )
    dist = _Truncated(variable.distribution, a, b)
    if not dist.mass > 1e-12:
        raise ModelError(
            f"the range [{low!r}, {high!r}] holds no probability of {variable.describe()}; "
            "give bounds around its values",
            element=name,
            field="lower",
        )
    params = dict(variable.parameters) | {"lower": a, "upper": b}
    return Variable(name, unit, f"truncated {variable.kind}", params, dist, variable.source)


class _Levels:
    """Discrete values with probabilities: the quantile function is a step function."""

    def __init__(self, values: np.ndarray, probabilities: np.ndarray):
        order = np.argsort(values)
        self.values, self.p = values[order], probabilities[order]
        self.cum = np.cumsum(self.p)
        self.cum[-1] = 1.0

    def ppf(self, q: Any) -> np.ndarray:
        q = np.asarray(q, dtype=float)
        i = np.searchsorted(self.cum, q, side="left")
        return self.values[np.clip(i, 0, len(self.values) - 1)]

    def isf(self, q: Any) -> np.ndarray:
        return self.ppf(1.0 - np.asarray(q, dtype=float))

    def cdf(self, x: Any) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        i = np.searchsorted(self.values, x, side="right")
        return np.concatenate([[0.0], self.cum])[i]

    def sf(self, x: Any) -> np.ndarray:
        return 1.0 - self.cdf(x)

    def mean(self) -> float:
        return float(self.p @ self.values)

    def std(self) -> float:
        m = self.mean()
        return math.sqrt(max(float(self.p @ (self.values - m) ** 2), 0.0))


def levels(
    name: str,
    values: Sequence[Any],
    probabilities: Sequence[float] | None = None,
    unit: str = "",
    *,
    source: str = "",
) -> Variable:
    """A value that takes one of a few discrete levels (a catalogue's stiffness grades, a shim set).

    Parameters
    ----------
    name : str
        The variable's name.
    values : sequence of float, str or quantity
        The levels, in ``unit`` when plain numbers; distinct.
    probabilities : sequence of float, optional
        The probability of each level, fraction summing to 1; equal when omitted.
    unit : str
        The SI unit of the variable.
    source : str
        Where the scatter comes from.
    """
    if isinstance(values, (str, bytes)) or not isinstance(values, Sequence) or len(values) < 2:
        raise ModelError(
            f"values = {values!r}: give a list of at least two levels, e.g. ['1 MN/m', '2 MN/m']",
            element=name,
            field="values",
        )
    v = np.array([_si(name, f"values[{i}]", x, unit) for i, x in enumerate(values)])
    if len(np.unique(v)) != len(v):
        raise ModelError(
            f"values = {values!r} repeat a level; give each level once", element=name, field="values"
        )
    if probabilities is None:
        p = np.full(len(v), 1.0 / len(v))
    else:
        if isinstance(probabilities, (str, bytes)) or len(probabilities) != len(v):
            raise ModelError(
                f"probabilities = {probabilities!r}: give one probability per level ({len(v)})",
                element=name,
                field="probabilities",
            )
        p = np.array([_si(name, f"probabilities[{i}]", x, "") for i, x in enumerate(probabilities)])
        if (p < 0).any() or not math.isclose(p.sum(), 1.0, abs_tol=1e-9):
            raise ModelError(
                f"probabilities = {probabilities!r} must be non-negative and sum to 1 (they sum to "
                f"{p.sum():.6g}); scale them",
                element=name,
                field="probabilities",
            )
    params = {"values": [float(x) for x in v], "probabilities": [float(x) for x in p]}
    return Variable(name, unit, "levels", params, _Levels(v, p), source)
