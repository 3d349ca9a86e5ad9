"""The floor force through a support model, as a linear function of counterweights.

The machine on its mounts is linear (:mod:`mechdyn.support`): its steady state is the sum of its
responses to each part of the load. The load is linear in the counterweights' coefficients
(:mod:`mechdyn.balance.influence`), so the floor force is too: it is the support's steady-state
response (:func:`mechdyn.support.periodic_response`, one complex solve per harmonic) to the
mechanism as it is, plus, per coefficient, the response to that coefficient's shaking force and
moment alone. Those responses come from the support's own solver, so the map is exact, not fitted.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from mechdyn.balance.influence import Influence

__all__ = ["FloorMap", "floor_map"]


@dataclass(frozen=True)
class FloorMap:
    """The floor force (machine axes) as a linear function of the counterweights' coefficients.

    Attributes
    ----------
    machine : MountedMachine
        The machine on its mounts.
    placement : Placement
        Where the mechanism sits in the machine.
    time : ndarray
        (N,) s from the load's t = 0 (the mechanism's angle datum).
    order : ndarray
        (N,) index of the crank angle of :class:`Influence` at each time.
    base : ndarray
        (N, 3) floor force of the machine as it is, N.
    columns : ndarray
        (N, 3, K) per unit of each coefficient (units of :attr:`Influence.columns`), N.
    """

    machine: Any
    placement: Any
    time: np.ndarray
    order: np.ndarray
    base: np.ndarray
    columns: np.ndarray

    def force(self, x: np.ndarray) -> np.ndarray:
        """(..., N, 3) floor force, N.

        Parameters
        ----------
        x : ndarray
            (..., K) coefficients per link: m in kg, m u and m v in kg·m, J + m (u² + v²) in kg·m².
        """
        return self.base + np.einsum("nck,...k->...nc", self.columns, np.asarray(x, dtype=float))


def _load(samples: np.ndarray, infl: Influence, placement: Any) -> Any:
    """The machine load of planar samples (N, 3: force x, y in N, moment about the drawing origin in
    N·m) over the crank angles, placed and timed as :meth:`PeriodicLoad.from_mechanism` does."""
    from mechdyn.support.excitation import PeriodicLoad

    dyn = infl.dynamics
    F = samples[:, :1] * placement.x_axis + samples[:, 1:2] * placement.y_axis
    M = samples[:, 2:3] * np.cross(placement.x_axis, placement.y_axis) + np.cross(placement.origin, F)
    six = np.hstack([F, M])
    angle = dyn.angle
    period = abs(float(infl.mechanism.driver.time(np.array([2 * math.pi]))[0]))
    t = np.asarray(dyn.kinematics.time, dtype=float)
    t = np.mod(t - t[np.argmin(angle)], period)
    order = np.argsort(t)
    if np.allclose(np.diff(t[order]), period / t.size, rtol=1e-9, atol=1e-12 * period):
        return PeriodicLoad.from_samples(period, six[order], angle[order]), order
    return PeriodicLoad.from_times(period, t[order], six[order], angle[order]), order


def floor_map(infl: Influence, machine: Any, placement: Any = None) -> FloorMap:
    """The floor force of the machine on its mounts for any counterweights on ``infl``'s links.

    Parameters
    ----------
    infl : Influence
        The mechanism's linear map (:func:`mechdyn.balance.influence.influence`).
    machine : MountedMachine
        The machine on its mounts (:mod:`mechdyn.support`); masses kg, stiffness N/m, damping N·s/m.
    placement : Placement, optional
        Where the mechanism sits in the machine (default :meth:`Placement.output_up`).

    Returns
    -------
    FloorMap

    Notes
    -----
    Exact by superposition: the support's steady state (Fourier series of the load, one frequency
    response per harmonic, SPEC §2) is linear in the load.
    """
    from mechdyn.support.excitation import PeriodicLoad, Placement
    from mechdyn.support.response import periodic_response

    place = placement or Placement.output_up(infl.mechanism)
    base_load = PeriodicLoad.from_mechanism(infl.dynamics, place)
    base = periodic_response(machine, base_load)
    K = infl.columns.shape[2]
    cols = np.zeros((base.time.size, 3, K))
    order = np.arange(infl.angle.size)
    for k in range(K):
        if not np.any(infl.columns[:, :3, k]):
            continue
        load, order = _load(infl.columns[:, :3, k], infl, place)
        cols[:, :, k] = periodic_response(machine, load).floor_force
    return FloorMap(machine, place, np.asarray(base.time), order, np.asarray(base.floor_force), cols)
