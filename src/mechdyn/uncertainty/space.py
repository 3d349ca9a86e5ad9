"""The joint distribution of the uncertain inputs: marginals tied by a Gaussian copula (Nataf).

Each input ``x_i = F_i⁻¹(Φ(z_i))`` where ``z = L ξ`` is normal with correlation matrix ``R = L Lᵀ``
and ``ξ`` independent standard normal (Nataf, 1962; Liu & Der Kiureghian, *Prob. Eng. Mech.* 1, 1986).
``R`` is the copula's own (normal-space) correlation; a Spearman rank correlation ``ρ_S`` given instead
is converted exactly, ``R = 2 sin(π ρ_S / 6)`` (Kruskal, *JASA* 53, 1958). The Pearson correlation of
the physical values then differs slightly from ``R`` for non-normal marginals.

Every method that samples or integrates works through :meth:`InputSpace.from_standard_normal`, so
that Monte Carlo, quasi-Monte Carlo, subset simulation and FORM see the same model.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from mechdyn.errors import ModelError
from mechdyn.uncertainty.distributions import Variable

__all__ = ["InputSpace"]

CORRELATION_KINDS = ("normal", "spearman")


@dataclass(frozen=True, repr=False)
class InputSpace:
    """The uncertain inputs of a study and their dependence.

    Parameters
    ----------
    variables : sequence of Variable
        The inputs, in the order of the columns of the samples (names distinct).
    correlation : array_like or dict, optional
        The correlation matrix (d × d, symmetric, unit diagonal, positive definite), or a dict
        ``{(name_a, name_b): rho}`` of the pairs that are correlated, dimensionless; independent
        inputs when omitted.
    correlation_kind : str
        ``"normal"``: the Gaussian copula's correlation; ``"spearman"``: rank correlation.

    Attributes
    ----------
    R : ndarray
        The copula's correlation matrix (normal space), d × d, dimensionless.
    """

    variables: tuple[Variable, ...]
    correlation: Any = None
    correlation_kind: str = "normal"
    R: np.ndarray = field(init=False, compare=False)
    _L: np.ndarray | None = field(init=False, compare=False)

    def __post_init__(self) -> None:
        variables = tuple(self.variables)
        object.__setattr__(self, "variables", variables)
        if not variables or not all(isinstance(v, Variable) for v in variables):
            raise ModelError(
                f"variables = {self.variables!r}: give a list of Variable (normal(...), lognormal(...), ...)",
                element="inputs",
                field="variables",
            )
        names = [v.name for v in variables]
        twice = sorted({n for n in names if names.count(n) > 1})
        if twice:
            raise ModelError(
                f"{twice} appear twice; give each input once", element="inputs", field="variables"
            )
        R = self._matrix(names)
        object.__setattr__(self, "R", R)
        object.__setattr__(
            self, "_L", None if np.array_equal(R, np.eye(len(names))) else np.linalg.cholesky(R)
        )

    def _matrix(self, names: list[str]) -> np.ndarray:
        d = len(names)
        where = {"element": "inputs", "field": "correlation"}
        if self.correlation_kind not in CORRELATION_KINDS:
            raise ModelError(
                f"correlation_kind = {self.correlation_kind!r}: give 'normal' (the copula's) "
                "or 'spearman' (rank)",
                element="inputs",
                field="correlation_kind",
            )
        if self.correlation is None:
            return np.eye(d)
        if isinstance(self.correlation, dict):
            R = np.eye(d)
            for pair, rho in self.correlation.items():
                if not (isinstance(pair, tuple) and len(pair) == 2 and all(p in names for p in pair)):
                    raise ModelError(
                        f"{pair!r} is not a pair of input names; give (name_a, name_b) from {names}", **where
                    )
                i, j = names.index(pair[0]), names.index(pair[1])
                if i == j:
                    raise ModelError(
                        f"{pair!r} pairs an input with itself; give two different inputs", **where
                    )
                R[i, j] = R[j, i] = float(rho)
        else:
            R = np.array(self.correlation, dtype=float)
            if R.shape != (d, d):
                raise ModelError(
                    f"the matrix is {R.shape}; give one of {d} × {d} (one row per input)", **where
                )
        if not np.all(np.isfinite(R)) or not np.allclose(R, R.T) or not np.allclose(np.diag(R), 1.0):
            raise ModelError(
                f"{R.tolist()} is not a correlation matrix; give a symmetric one with 1 on the diagonal",
                **where,
            )
        if np.any(np.abs(R - np.eye(d)) >= 1.0):
            raise ModelError(
                f"{R.tolist()} has a coefficient of magnitude 1 or more; give each in (-1, 1)", **where
            )
        if self.correlation_kind == "spearman":
            R = 2.0 * np.sin(np.pi * R / 6.0)
            np.fill_diagonal(R, 1.0)
        if np.linalg.eigvalsh(R).min() <= 1e-12:
            raise ModelError(
                f"{R.tolist()} is not positive definite (the coefficients contradict each other); "
                "weaken the correlations",
                **where,
            )
        return R

    @property
    def dimension(self) -> int:
        """The number of inputs d (count)."""
        return len(self.variables)

    @property
    def names(self) -> list[str]:
        """The inputs' names, in column order."""
        return [v.name for v in self.variables]

    @property
    def units(self) -> list[str]:
        """The inputs' SI units, in column order."""
        return [v.unit for v in self.variables]

    @property
    def independent(self) -> bool:
        """Whether the inputs are independent (no correlation given)."""
        return self._L is None

    def correlate(self, xi: Any) -> np.ndarray:
        """Independent standard normal values ξ (n × d) made correlated: ``z = ξ Lᵀ``.

        Parameters
        ----------
        xi : array_like
            Independent standard normal values, n × d, dimensionless.
        """
        xi = np.atleast_2d(np.asarray(xi, dtype=float))
        return xi if self._L is None else xi @ self._L.T

    def from_standard_normal(self, xi: Any) -> np.ndarray:
        """The inputs (n × d, SI) at independent standard normal points ξ (n × d): the Nataf map.

        Parameters
        ----------
        xi : array_like
            Points of the independent standard normal space, n × d, dimensionless.
        """
        z = self.correlate(xi)
        return np.column_stack([v.from_standard_normal(z[:, i]) for i, v in enumerate(self.variables)])

    def to_standard_normal(self, X: Any) -> np.ndarray:
        """The independent standard normal points ξ (n × d) of inputs X (n × d, SI): the inverse of
        :meth:`from_standard_normal` (continuous inputs).

        Parameters
        ----------
        X : array_like
            Input points, n × d, SI.
        """
        from scipy.linalg import solve_triangular

        X = np.atleast_2d(np.asarray(X, dtype=float))
        z = np.column_stack([v.to_standard_normal(X[:, i]) for i, v in enumerate(self.variables)])
        return z if self._L is None else solve_triangular(self._L, z.T, lower=True).T

    def from_unit_cube(self, u: Any) -> np.ndarray:
        """The inputs (n × d, SI) at points of the unit hypercube (n × d, fraction): ``ξ = Φ⁻¹(u)``,
        then :meth:`from_standard_normal`. Points exactly on a face are moved inside by 1e-16.

        Parameters
        ----------
        u : array_like
            Points in (0, 1)^d, fraction.
        """
        from scipy.special import ndtri

        u = np.clip(np.asarray(u, dtype=float), 1e-16, 1.0 - 1e-16)
        return self.from_standard_normal(ndtri(u))

    def sample(self, n: int, *, method: str = "mc", seed: Any = None) -> np.ndarray:
        """Draw n input points (n × d, SI).

        Parameters
        ----------
        n : int
            Number of points (a power of 2 for ``"qmc"``), count.
        method : str
            ``"mc"``: independent pseudo-random points (NumPy's PCG64); ``"qmc"``: a scrambled Sobol
            sequence (:class:`scipy.stats.qmc.Sobol`).
        seed : int or numpy.random.Generator, optional
            The random seed, for a repeatable draw.
        """
        rng = np.random.default_rng(seed)
        d = self.dimension
        if method == "mc":
            return self.from_standard_normal(rng.standard_normal((n, d)))
        if method == "qmc":
            from scipy.stats import qmc

            if n < 1 or n & (n - 1):
                raise ModelError(
                    f"n = {n}: a Sobol sequence keeps its balance only at powers of 2; "
                    f"give e.g. {_power_of_2(n)}",
                    element="sampling",
                    field="samples",
                )
            return self.from_unit_cube(qmc.Sobol(d, scramble=True, seed=rng).random(n))
        raise ModelError(f"method = {method!r}: give 'mc' or 'qmc'", element="sampling", field="method")

    def describe(self) -> list[str]:
        """One line per input, and one per correlated pair, for a report."""
        lines = [v.describe() for v in self.variables]
        names = self.names
        for i in range(self.dimension):
            for j in range(i + 1, self.dimension):
                if self.R[i, j] != 0.0:
                    lines.append(f"correlation (normal space) {names[i]} – {names[j]}: {self.R[i, j]:.4g}")
        return lines

    def __repr__(self) -> str:
        return f"<InputSpace: {', '.join(self.names)}{'' if self.independent else ', correlated'}>"


def _power_of_2(n: int) -> int:
    return 1 << max(int(n - 1).bit_length(), 1)


def as_space(inputs: InputSpace | Sequence[Variable] | Variable) -> InputSpace:
    """An :class:`InputSpace` from one, from a list of variables (independent), or from one variable.

    Parameters
    ----------
    inputs : InputSpace, Variable or sequence of Variable
        The uncertain inputs.
    """
    if isinstance(inputs, InputSpace):
        return inputs
    if isinstance(inputs, Variable):
        return InputSpace((inputs,))
    return InputSpace(tuple(inputs))
