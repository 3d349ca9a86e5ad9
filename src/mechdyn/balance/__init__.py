"""Counterweights on a mechanism's links that cut what reaches the floor.

:func:`balance` finds point-mass counterweights on chosen links (:class:`CounterweightSlot`: mass and
radius bounds) that minimise the fluctuation of the shaking force, the shaking moment, the driving
torque, the floor force through a support model (:mod:`mechdyn.support`), or a weighted sum. All of
them are linear in four numbers per link (:mod:`.influence`, Berkof & Lowen 1969), so the force
problem is solved exactly and the rest is polished from there (:mod:`.solve`). The counterweights
found go back into the model (:class:`mechdyn.mechanism.Counterweight`, ``[[counterweights]]`` in a
mechanism file). ``mechdyn balance FILE`` runs it on a mechanism or a support file.
"""

from mechdyn._lazy import attach

__all__ = attach(
    __name__,
    {
        "BalanceResult": "result",
        "Budget": "exact",
        "CounterweightSlot": "solve",
        "Evaluator": "solve",
        "FloorMap": "floor",
        "Influence": "influence",
        "balance": "design",
        "floor_map": "floor",
        "influence": "influence",
        "metric": "objectives",
        "reference_point": "influence",
    },
)
