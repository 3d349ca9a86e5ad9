"""Tolerances to probabilities: scatter of the inputs, propagated through a batched model.

A designer buys a mount at ±20 %, a pad at ±5 Shore A, a gear of flank tolerance class 6; what must
be signed is the probability that the machine passes on the floor. This subpackage is the core the
``tolerance`` study kind calls:

- **inputs**: :class:`Variable` (:func:`normal`, :func:`lognormal`, :func:`uniform`,
  :func:`triangular`, :func:`levels`, :func:`truncated`; named classes by :func:`tolerance`; a file's
  table by :func:`variable_from_dict`) tied by a Gaussian copula in an :class:`InputSpace`;
- **propagation**: :func:`propagate` (Monte Carlo or randomized quasi-Monte Carlo) gives each output's
  mean, standard deviation and quantiles, and each :class:`Limit`'s probability, all with confidence
  intervals;
- **ranking**: :func:`rank_inputs`, the Sobol indices of each output and of each limit's indicator
  (SALib);
- **small probabilities**: :func:`small_probability` by subset simulation, FORM, SORM or importance
  sampling (OpenTURNS), each with its method, evaluations and error;
- **surrogate**: :func:`polynomial_chaos` for an expensive model (OpenTURNS), validated on points it
  was not fitted to, itself a batched model the functions above take.

The model is one call on all samples, ``f(X) -> Y`` with X (n, d) in SI: the batch engine's shape.
"""

from mechdyn.uncertainty.distributions import (
    Variable,
    levels,
    lognormal,
    normal,
    triangular,
    truncated,
    uniform,
)
from mechdyn.uncertainty.estimates import Interval, Probability
from mechdyn.uncertainty.propagation import Limit, OutputDistribution, PropagationResult, propagate
from mechdyn.uncertainty.reliability import ReliabilityResult, small_probability
from mechdyn.uncertainty.sensitivity import InputRanking, rank_inputs
from mechdyn.uncertainty.space import InputSpace
from mechdyn.uncertainty.surrogate import ChaosSurrogate, polynomial_chaos
from mechdyn.uncertainty.tables import variable_from_dict
from mechdyn.uncertainty.tolerances import iso1328_single_pitch_tolerance, tolerance, tolerance_classes

__all__ = [
    "ChaosSurrogate",
    "InputRanking",
    "InputSpace",
    "Interval",
    "Limit",
    "OutputDistribution",
    "Probability",
    "PropagationResult",
    "ReliabilityResult",
    "Variable",
    "iso1328_single_pitch_tolerance",
    "levels",
    "lognormal",
    "normal",
    "polynomial_chaos",
    "propagate",
    "rank_inputs",
    "small_probability",
    "tolerance",
    "tolerance_classes",
    "triangular",
    "truncated",
    "uniform",
    "variable_from_dict",
]
