"""Which tolerance to tighten first: the inputs ranked by their share of each output and each probability.

First- and total-order Sobol indices of each output and of each limit's indicator ``1[output beyond
limit]`` — the share of the probability's variance ``P(1 − P)`` each input explains — by SALib
(Saltelli's pick-freeze design on a scrambled Sobol sequence, Saltelli's first-order and Jansen's
total-order estimators, bootstrap confidence intervals; Saltelli et al., *Comput. Phys. Commun.* 181,
2010; Herman & Usher, *JOSS* 2, 2017), the same library as the ``sobol`` study kind.

With correlated inputs the indices are those of the independent parts of the inputs in their order
(the Cholesky factor of the copula): the first input carries all it shares with the later ones.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from mechdyn.errors import ModelError
from mechdyn.results import Result, Table
from mechdyn.uncertainty.propagation import Limit, _check_limits, evaluate
from mechdyn.uncertainty.space import InputSpace, as_space

if TYPE_CHECKING:
    import pandas as pd

    from mechdyn.uncertainty.distributions import Variable

__all__ = ["InputRanking", "first_order_given_data", "rank_inputs"]


@dataclass(frozen=True)
class Indices:
    """The Sobol indices of one quantity (an output or a limit's indicator).

    Attributes
    ----------
    quantity : str
        The output's name or the event in words.
    S1, ST : dict
        Input name → first- and total-order index, fraction.
    S1_conf, ST_conf : dict
        Input name → half-width of the index's bootstrap confidence interval, fraction.
    note : str
        Why the indices are missing or weak (a constant quantity, few failures), else empty.
    """

    quantity: str
    S1: dict[str, float]
    ST: dict[str, float]
    S1_conf: dict[str, float]
    ST_conf: dict[str, float]
    note: str = ""

    def ranked(self) -> list[str]:
        """The input names, the largest total-order index first."""
        return sorted(self.ST, key=lambda k: -self.ST[k])


@dataclass(frozen=True, repr=False)
class InputRanking(Result):
    """The inputs ranked by their Sobol indices, for every output and every limit.

    Attributes
    ----------
    inputs : tuple of str
        The inputs' names.
    base_samples : int
        SALib's base sample N (count); the model ran N (d + 2) times.
    level : float
        Confidence level of the bootstrap intervals, fraction.
    outputs : tuple of Indices
        One per output.
    probabilities : tuple of Indices
        One per limit: the indices of its indicator.
    correlated : bool
        Whether the inputs are correlated (the indices then belong to their independent parts).
    evaluations : int
        Model evaluations spent (count).
    """

    inputs: tuple[str, ...]
    base_samples: int
    level: float
    outputs: tuple[Indices, ...]
    probabilities: tuple[Indices, ...]
    correlated: bool
    evaluations: int = field(default=0)

    def summary(self) -> dict[str, Any]:
        """Per output and per event: each input's ``S1``, ``ST`` and their interval half-widths."""
        out: dict[str, Any] = {"evaluations": self.evaluations, "base_samples": self.base_samples}
        for ind in (*self.outputs, *self.probabilities):
            out[ind.quantity] = (
                {"note": ind.note}
                if not ind.ST
                else {
                    name: {
                        "S1": ind.S1[name],
                        "S1_conf": ind.S1_conf[name],
                        "ST": ind.ST[name],
                        "ST_conf": ind.ST_conf[name],
                    }
                    for name in ind.ranked()
                }
            )
        return out

    def to_frame(self) -> pd.DataFrame:
        """One row per (quantity, input): S1, ST and their interval half-widths."""
        import pandas as pd

        rows = [
            {
                "quantity": ind.quantity,
                "input": name,
                "S1": ind.S1[name],
                "S1_conf": ind.S1_conf[name],
                "ST": ind.ST[name],
                "ST_conf": ind.ST_conf[name],
            }
            for ind in (*self.outputs, *self.probabilities)
            for name in ind.ranked()
        ]
        return pd.DataFrame(rows, columns=["quantity", "input", "S1", "S1_conf", "ST", "ST_conf"])

    def tables(self, **display_units: str) -> list[Table]:
        """One table per quantity, the inputs ranked by total-order index.

        Parameters
        ----------
        **display_units : str
            Not used: indices are fractions.
        """
        pct = round(self.level * 100)
        out = []
        for ind in (*self.outputs, *self.probabilities):
            rows = [[n, ind.S1[n], ind.S1_conf[n], ind.ST[n], ind.ST_conf[n]] for n in ind.ranked()]
            out.append(
                Table(
                    f"Sobol indices of {ind.quantity} ({pct} % intervals), ranked",
                    ["input", "S1", "± S1", "ST", "± ST"],
                    rows,
                    ind.note,
                )
            )
        return out

    @property
    def warnings(self) -> tuple[str, ...]:
        """Notes on indices that are missing or weak."""
        return tuple(
            f"{ind.quantity}: {ind.note}" for ind in (*self.outputs, *self.probabilities) if ind.note
        )


def rank_inputs(
    f: Callable[[np.ndarray], Any],
    inputs: InputSpace | Sequence[Variable] | Variable,
    *,
    outputs: Sequence[str] | None = None,
    limits: Sequence[Limit] = (),
    base_samples: int = 1024,
    level: float = 0.95,
    seed: int | None = None,
) -> InputRanking:
    """Rank the inputs by their first- and total-order Sobol indices, of every output and of every
    limit's indicator (the share of each probability), by SALib.

    Parameters
    ----------
    f : callable
        ``f(X) -> Y``: X of shape (n, d) in SI, Y of shape (n, m) or (n,).
    inputs : InputSpace, Variable or sequence of Variable
        The uncertain inputs.
    outputs : sequence of str, optional
        The outputs' names, one per column of Y.
    limits : sequence of Limit
        The limits whose probabilities are to be shared out.
    base_samples : int
        SALib's base sample N, a power of 2 (count); the model runs N (d + 2) times.
    level : float
        Confidence level of the bootstrap intervals, fraction.
    seed : int, optional
        Random seed of the scrambling and the bootstrap.

    Returns
    -------
    InputRanking
    """
    from SALib.analyze import sobol as analyze
    from SALib.sample import sobol as sample

    space = as_space(inputs)
    n = int(base_samples)
    if n < 2 or n & (n - 1):
        raise ModelError(
            f"base_samples = {base_samples!r}: Saltelli's design needs a power of 2 (e.g. 1024)",
            element="sensitivity",
            field="base_samples",
        )
    d = space.dimension
    problem = {"num_vars": d, "names": space.names, "bounds": [[0.0, 1.0]] * d}
    U = np.asarray(sample.sample(problem, n, calc_second_order=False, seed=seed))
    X = space.from_unit_cube(U)
    Y = evaluate(f, X, outputs)
    names = list(outputs) if outputs is not None else [f"y{j}" for j in range(Y.shape[1])]
    _check_limits(limits, names)

    def indices(quantity: str, y: np.ndarray, note: str = "") -> Indices:
        if np.ptp(y) == 0:
            why = "no sample beyond the limit" if note == "indicator" else "the quantity does not change"
            return Indices(quantity, {}, {}, {}, {}, f"{why} in the {len(y)} ranking samples: no indices")
        r = analyze.analyze(problem, y, calc_second_order=False, conf_level=level, seed=seed)
        weak = ""
        if note == "indicator":
            k = int(y.sum())
            if min(k, len(y) - k) < 30:
                weak = (
                    f"only {min(k, len(y) - k)} of {len(y)} ranking samples on the rarer side of the "
                    "limit: the indices are rough"
                )
        return Indices(
            quantity,
            {p: float(r["S1"][i]) for i, p in enumerate(space.names)},
            {p: float(r["ST"][i]) for i, p in enumerate(space.names)},
            {p: float(r["S1_conf"][i]) for i, p in enumerate(space.names)},
            {p: float(r["ST_conf"][i]) for i, p in enumerate(space.names)},
            weak,
        )

    by_output = tuple(indices(name, Y[:, j]) for j, name in enumerate(names))
    by_limit = tuple(
        indices(lim.event, lim.exceeded(Y[:, names.index(lim.output)]).astype(float), "indicator")
        for lim in limits
    )
    return InputRanking(tuple(space.names), n, level, by_output, by_limit, not space.independent, len(Y))


def first_order_given_data(x: np.ndarray, y: np.ndarray) -> float:
    """The first-order Sobol index of ``y`` on ``x`` from one sample (no design of its own).

    The samples are sorted by x into M = ⌊√n⌋ classes of equal count; the index is the variance of
    the class means over the variance of y (Plischke, Borgonovo & Smith, *Eur. J. Oper. Res.* 226,
    2013), corrected for the scatter of the class means themselves: a ratio r has expectation
    S + (1 − S)·b with b = (M − 1)/(n − 1), so S = (r − b)/(1 − b), at least 0. It is
    ``Var(E[y | x]) / Var(y)`` whatever the other inputs do, so with correlated inputs an input's
    index includes what it shares with those it is correlated with (the indices may then sum above 1).

    Parameters
    ----------
    x : ndarray
        The input's samples (n), any unit.
    y : ndarray
        The output's (or a limit's indicator's) samples (n), any unit.

    Returns
    -------
    float
        The index, fraction (0 for a constant y).
    """
    import math

    n = len(y)
    total = float(np.var(y))
    if n < 4 or total == 0.0:
        return 0.0
    m = max(2, math.isqrt(n))
    classes = np.array_split(np.argsort(x, kind="stable"), m)
    mean = float(np.mean(y))
    between = sum(len(c) * (float(np.mean(y[c])) - mean) ** 2 for c in classes) / n
    bias = (m - 1) / (n - 1)  # E[between / total] = S + (1 - S)·bias: the classes' own scatter
    return max(0.0, (between / total - bias) / (1.0 - bias))
