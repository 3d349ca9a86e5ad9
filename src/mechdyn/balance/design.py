"""The counterweight design of a mechanism from end to end: the links and their bounds, the budget,
the influence of each link (:mod:`~mechdyn.balance.influence`), the optimum
(:mod:`~mechdyn.balance.solve`), the trade-off and mass fronts (:mod:`~mechdyn.balance.fronts`) and
the result (:class:`~mechdyn.balance.result.BalanceResult`)."""

from __future__ import annotations

import math
import time
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from mechdyn.balance.exact import Budget
from mechdyn.balance.fronts import mass_front, weight_front
from mechdyn.balance.influence import influence
from mechdyn.balance.objectives import parse_objective
from mechdyn.balance.result import BalanceResult
from mechdyn.balance.solve import Evaluator, optimise, slots_of
from mechdyn.errors import ModelError
from mechdyn.units import si_field

__all__ = ["balance"]


def _budget(max_added_mass: Any, max_added_inertia: Any, slack: float) -> Budget:
    el = "balance"
    mass = (
        math.inf
        if max_added_mass is None
        else si_field(el, "max_added_mass", max_added_mass, "kg", nonnegative=True)
    )
    inertia = (
        math.inf
        if max_added_inertia is None
        else si_field(el, "max_added_inertia", max_added_inertia, "kg*m^2", nonnegative=True)
    )
    if not (np.isfinite(slack) and 0 <= slack < 1):
        raise ModelError(f"slack {slack!r} must be a fraction, 0 ≤ slack < 1", element=el, field="slack")
    return Budget(mass, inertia, float(slack))


def balance(
    mechanism: Any,
    slots: Sequence[Any],
    objective: str | Mapping[str, float] = "shaking_force_rms",
    *,
    support: Any = None,
    placement: Any = None,
    n_angles: int = 360,
    front: bool = True,
    max_added_mass: Any = None,
    max_added_inertia: Any = None,
    slack: float = 0.0,
) -> Any:
    """Counterweights on the given links that minimise the objective (:class:`BalanceResult`).

    Parameters
    ----------
    mechanism : Mechanism
        The mechanism (its own counterweights, if any, are part of it).
    slots : sequence of CounterweightSlot or str
        The links that may carry a counterweight and their bounds (a link name alone: mass 0 to
        1e4 kg, radius 0 to 1 m).
    objective : str or mapping
        A metric (``shaking_force_rms``, ``shaking_force_peak``, ``shaking_force_range``,
        ``shaking_moment_*``, ``driving_torque_*``, ``floor_force_*`` with a support), or a mapping
        of metrics to dimensionless weights: the weighted sum of each relative to its value without
        counterweights (:mod:`mechdyn.balance.objectives`).
    support : MountedMachine, optional
        The machine on its mounts (:mod:`mechdyn.support`), for the floor force.
    placement : Placement, optional
        Where the mechanism sits in the machine (default :meth:`Placement.output_up`).
    n_angles : int
        Crank angles over one revolution.
    front : bool
        Also sweep the weights between the force (floor force with a support, else shaking force),
        shaking moment and driving torque RMS (the trade-off front), and the objective against the
        total added mass allowed (the mass front: what each tonne buys).
    max_added_mass : float or quantity, optional
        Largest total mass of all the counterweights, kg (plain numbers) or a quantity ("60 t").
    max_added_inertia : float or quantity, optional
        Largest total rotary inertia Σ m r² of the counterweights, each about its link's reference
        point, kg·m² or a quantity.
    slack : float
        Dimensionless, 0 ≤ slack < 1: among designs whose objective is within this fraction of the
        best, the lightest is taken (0: among equal ones, to 1e-9; 0.01 gives up 1 % of the
        objective for less mass).

    Returns
    -------
    BalanceResult

    Notes
    -----
    Linearity of shaking force, moment and torque in (m, m u, m v, J + m r²) per link (Berkof &
    Lowen, J. Eng. Ind. 91 (1969) 21–26); the force objectives as exact least squares or cone
    programmes (:mod:`mechdyn.balance.exact`), SLSQP from that solution otherwise (module
    docstring); then the lightest design within the slack.
    """
    budget = _budget(max_added_mass, max_added_inertia, slack)
    t0 = time.perf_counter()
    slots_ = slots_of(slots)
    infl = influence(mechanism, [s.link for s in slots_], n_angles)
    floor = None
    if support is not None:
        from mechdyn.balance.floor import floor_map

        floor = floor_map(infl, support, placement)
    ev = Evaluator(infl, floor)
    weights = parse_objective(objective, floor is not None)
    t_setup = time.perf_counter() - t0
    t1 = time.perf_counter()
    found = optimise(ev, slots_, weights, budget)
    t_solve = time.perf_counter() - t1
    rows: list[dict[str, float]] = []
    masses: list[dict[str, float]] = []
    if front:
        rows = weight_front(ev, slots_, budget)
        masses = mass_front(ev, slots_, weights, budget, found.design)
    return BalanceResult(
        influence=infl,
        floor=floor,
        slots=slots_,
        objective=weights,
        design=found.design,
        method=found.method,
        exact=found.exact,
        front=tuple(rows),
        setup_seconds=t_setup,
        solve_seconds=t_solve,
        budget=budget,
        bound=found.bound,
        mass_front=tuple(masses),
    )
