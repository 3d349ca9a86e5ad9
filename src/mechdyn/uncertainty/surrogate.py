"""A polynomial-chaos surrogate of an expensive batched model, by OpenTURNS.

Where one evaluation costs seconds (a time simulation of a geared drivetrain, a start-up), a few
hundred evaluations fit a polynomial chaos expansion in the independent standard normal space ξ of
the :class:`~mechdyn.uncertainty.InputSpace` (Hermite polynomials, total degree ``degree``,
coefficients by least squares with LARS selection and corrected leave-one-out; Blatman & Sudret,
*J. Comput. Phys.* 230, 2011). The surrogate then answers the mean and variance and the Sobol indices
of every output from its coefficients (Sudret, *Reliab. Eng. Syst. Saf.* 93, 2008), and is itself a
batched model that :func:`~mechdyn.uncertainty.propagate` and
:func:`~mechdyn.uncertainty.small_probability` take in place of the model.

Its accuracy is measured, not assumed: ``q2`` is the share of each output's variance it predicts on
points that were not used to fit it. A probability computed on the surrogate inherits its error in
the tail, which ``q2`` does not measure: check the design point on the model.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from mechdyn.errors import ModelError
from mechdyn.results import Result, Table
from mechdyn.uncertainty.propagation import evaluate
from mechdyn.uncertainty.space import InputSpace, as_space

if TYPE_CHECKING:
    import pandas as pd

    from mechdyn.uncertainty.distributions import Variable

__all__ = ["ChaosSurrogate", "polynomial_chaos"]

Q2_WARNING = 0.99
"""Below this validation Q² (fraction of variance predicted) a surrogate warns."""


@dataclass(frozen=True, repr=False)
class ChaosSurrogate(Result):
    """A polynomial chaos expansion of a batched model, itself a batched model ``surrogate(X) -> Y``.

    Attributes
    ----------
    space : InputSpace
        The inputs (continuous).
    outputs : tuple of str
        The outputs' names.
    degree : int
        Total polynomial degree (count).
    evaluations : int
        Model evaluations spent: fit and validation (count).
    q2 : dict
        Output → the share of its variance predicted on the validation points, fraction (1 is exact).
    mean : dict
        Output → its mean from the coefficients, in the output's unit.
    std : dict
        Output → its standard deviation from the coefficients, in the output's unit.
    S1, ST : dict
        Output → {input → first- and total-order Sobol index from the coefficients}, fraction.
    metamodel : object
        The OpenTURNS function of ξ.
    """

    space: InputSpace
    outputs: tuple[str, ...]
    degree: int
    evaluations: int
    q2: dict[str, float]
    mean: dict[str, float]
    std: dict[str, float]
    S1: dict[str, dict[str, float]]
    ST: dict[str, dict[str, float]]
    metamodel: Any = field(compare=False)

    def __call__(self, X: Any) -> np.ndarray:
        """The surrogate's outputs (n × m) at input points X (n × d, SI).

        Parameters
        ----------
        X : array_like
            Input points, n × d, SI.
        """
        xi = self.space.to_standard_normal(np.atleast_2d(np.asarray(X, dtype=float)))
        return np.asarray(self.metamodel(xi), dtype=float)

    def summary(self) -> dict[str, Any]:
        """Per output: mean, standard deviation (its unit) and validation Q²; the evaluations."""
        out: dict[str, Any] = {"degree": self.degree, "evaluations": self.evaluations}
        for name in self.outputs:
            out[name] = {"mean": self.mean[name], "std": self.std[name], "q2": self.q2[name]}
        return out

    def to_frame(self) -> pd.DataFrame:
        """One row per (output, input): the Sobol indices from the coefficients."""
        import pandas as pd

        rows = [
            {"output": o, "input": i, "S1": self.S1[o][i], "ST": self.ST[o][i]}
            for o in self.outputs
            for i in self.space.names
        ]
        return pd.DataFrame(rows, columns=["output", "input", "S1", "ST"])

    def tables(self, **display_units: str) -> list[Table]:
        """The moments and the validation of each output.

        Parameters
        ----------
        **display_units : str
            Not used: values are SI.
        """
        rows = [[o, self.mean[o], self.std[o], self.q2[o]] for o in self.outputs]
        note = f"polynomial chaos of degree {self.degree}, {self.evaluations} model evaluations"
        return [Table("polynomial chaos surrogate", ["output", "mean", "std", "validation Q²"], rows, note)]

    @property
    def warnings(self) -> tuple[str, ...]:
        """Outputs the surrogate predicts poorly on its validation points."""
        return tuple(
            f"{o}: the surrogate predicts {self.q2[o]:.3f} of the variance on its validation points "
            f"(below {Q2_WARNING}); raise n or the degree, or use the model"
            for o in self.outputs
            if self.q2[o] < Q2_WARNING
        )


def polynomial_chaos(
    f: Callable[[np.ndarray], Any],
    inputs: InputSpace | Sequence[Variable] | Variable,
    n: int = 256,
    *,
    outputs: Sequence[str] | None = None,
    degree: int = 4,
    validation: int | None = None,
    seed: Any = None,
) -> ChaosSurrogate:
    """Fit a polynomial chaos surrogate of the batched model ``f`` on n evaluations, validated on more.

    Parameters
    ----------
    f : callable
        ``f(X) -> Y``: X of shape (n, d) in SI, Y of shape (n, m) or (n,).
    inputs : InputSpace, Variable or sequence of Variable
        The uncertain inputs (continuous).
    n : int
        Fitting evaluations (count); a few times the number of polynomials at least.
    outputs : sequence of str, optional
        The outputs' names, one per column of Y.
    degree : int
        Total polynomial degree (count).
    validation : int, optional
        Validation evaluations (count); n/4 by default.
    seed : int or numpy.random.Generator, optional
        Random seed of the design (a scrambled Sobol sequence) and the validation points.

    Returns
    -------
    ChaosSurrogate
    """
    import openturns as ot  # type: ignore[import-untyped]
    from scipy.special import comb, ndtri
    from scipy.stats import qmc

    space = as_space(inputs)
    discrete = [v.name for v in space.variables if not v.continuous]
    if discrete:
        raise ModelError(
            f"a polynomial chaos needs continuous inputs ({discrete} take discrete levels); propagate the "
            "model itself",
            element="surrogate",
            field="inputs",
        )
    d = space.dimension
    if isinstance(degree, bool) or not (isinstance(degree, int) and 1 <= degree <= 10):
        raise ModelError(f"degree = {degree!r}: give an integer 1 … 10", element="surrogate", field="degree")
    terms = int(comb(d + degree, degree))
    if n < 2 * terms:
        raise ModelError(
            f"n = {n}: degree {degree} in {d} inputs has {terms} polynomials; give n ≥ {2 * terms} "
            "(a few times more is safer) or a lower degree",
            element="surrogate",
            field="samples",
        )
    rng = np.random.default_rng(seed)

    u = np.clip(qmc.Sobol(d, scramble=True, seed=rng).random(n), 1e-16, 1 - 1e-16)
    xi = ndtri(u)
    Y = evaluate(f, space.from_standard_normal(xi), outputs)
    names = list(outputs) if outputs is not None else [f"y{j}" for j in range(Y.shape[1])]
    m = Y.shape[1]

    basis = ot.OrthogonalProductPolynomialFactory([ot.HermiteFactory()] * d)
    size = basis.getEnumerateFunction().getStrataCumulatedCardinal(degree)
    selection = ot.LeastSquaresMetaModelSelectionFactory(ot.LARS(), ot.CorrectedLeaveOneOut())
    algo = ot.FunctionalChaosAlgorithm(
        ot.Sample(xi),
        ot.Sample(Y),
        ot.Normal(d),
        ot.FixedStrategy(basis, size),
        ot.LeastSquaresStrategy(selection),
    )
    algo.run()
    result = algo.getResult()
    metamodel = result.getMetaModel()

    n_valid = int(validation) if validation is not None else max(n // 4, 16)
    xi_valid = rng.standard_normal((n_valid, d))
    Y_valid = evaluate(f, space.from_standard_normal(xi_valid), outputs)
    predicted = np.asarray(metamodel(xi_valid), dtype=float)
    spread = np.var(Y_valid, axis=0)
    q2 = 1.0 - np.mean((predicted - Y_valid) ** 2, axis=0) / np.where(spread > 0, spread, 1.0)

    vector = ot.FunctionalChaosRandomVector(result)
    mean = np.asarray(vector.getMean(), dtype=float)
    std = np.sqrt(np.diag(np.asarray(vector.getCovariance(), dtype=float)))
    sobol = ot.FunctionalChaosSobolIndices(result)
    S1 = {
        names[j]: {space.names[i]: float(sobol.getSobolIndex(i, j)) if std[j] > 0 else 0.0 for i in range(d)}
        for j in range(m)
    }
    ST = {
        names[j]: {
            space.names[i]: float(sobol.getSobolTotalIndex(i, j)) if std[j] > 0 else 0.0 for i in range(d)
        }
        for j in range(m)
    }
    return ChaosSurrogate(
        space,
        tuple(names),
        degree,
        n + n_valid,
        {names[j]: float(q2[j]) for j in range(m)},
        {names[j]: float(mean[j]) for j in range(m)},
        {names[j]: float(std[j]) for j in range(m)},
        S1,
        ST,
        metamodel,
    )
