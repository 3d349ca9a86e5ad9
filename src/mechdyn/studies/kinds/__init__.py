"""Study kinds: each one object with the protocol of :class:`~mechdyn.studies.kinds.base.Kind`,
registered once (:data:`KINDS`, :func:`kind`).

========== ================================= =====================================================
kind       design                            findings
========== ================================= =====================================================
oat        the base, each parameter at each  each output's change in % of the base (tornado)
           level, the others at base
factorial  every combination of the levels   main effects, two-way interactions, lowest and highest
lhs        Latin hypercube over the ranges   output ranges, rank correlations, the best design
sobol      Saltelli's sampling               first- and total-order indices with 95 % intervals
optimize   Optuna, then an SLSQP polish      the optimum and its proof, or the Pareto front
synthesis  differential evolution, polish    the fit, a verdict and margin per target
tolerance  each parameter's scatter sampled  each output's distribution, each limit's probability
           (Monte Carlo or quasi-MC)         (with intervals), the tolerances ranked
========== ================================= =====================================================
"""

# the kinds register in the order the docs list them (sweeps, then Sobol, then the searches)
from mechdyn.studies.kinds.base import KINDS, Found, Kind, Ran, kind, register  # noqa: I001
from mechdyn.studies.kinds import sweeps
from mechdyn.studies.kinds import sobol
from mechdyn.studies.kinds import optimize
from mechdyn.studies.kinds import synthesis
from mechdyn.studies.kinds import tolerance

__all__ = [
    "KINDS",
    "Found",
    "Kind",
    "Ran",
    "kind",
    "optimize",
    "register",
    "sobol",
    "sweeps",
    "synthesis",
    "tolerance",
]
