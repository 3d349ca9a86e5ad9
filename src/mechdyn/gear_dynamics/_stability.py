"""When a periodic orbit of a geared drivetrain is stable: the margin, and the Floquet multipliers.

Floquet's theorem (Nayfeh & Mook, *Nonlinear Oscillations*, 1979, §5.2): the free vibration about a
periodic orbit grows where the spectral radius ρ of its monodromy matrix Φ(T), the largest modulus of
the Floquet multipliers, exceeds 1. The Floquet analysis (:mod:`.floquet`), the steady-state solvers
(:mod:`.shooting`, :mod:`.steady`), the continuation (:mod:`.continuation`) and the sweep's result
(:mod:`.sweep_result`) all judge an orbit by the same margin and the same multipliers, kept here.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from mechdyn.gear_dynamics.periodic import LinearPeriodic

__all__ = ["UNSTABLE_MARGIN"]

#: Multipliers above 1 + this are unstable (1e-9 allows for the rounding of an undamped system's
#: multipliers, which lie on the unit circle where stable).
UNSTABLE_MARGIN = 1e-9


def _spectral(Phi: np.ndarray, lin: LinearPeriodic | None = None) -> tuple[np.ndarray, float]:
    """Floquet multipliers (largest first) and spectral radius of ``Phi``, without the rigid-body
    angle's multiplier of ``lin`` where it is in the state.

    Parameters
    ----------
    Phi : ndarray
        (n, n) state-transition matrix over one period (the monodromy), dimensionless.
    lin : LinearPeriodic, optional
        The linear periodic model whose rigid-body angle (multiplier exactly 1) is left out.

    Returns
    -------
    tuple of (ndarray, float)
        The multipliers, complex, largest modulus first, and the spectral radius ρ, dimensionless
        (0 for an empty state).
    """
    mu = np.linalg.eigvals(lin.deflate(Phi) if lin is not None else Phi)
    mu = mu[np.argsort(-np.abs(mu), kind="stable")]
    return mu, float(np.abs(mu[0])) if mu.size else 0.0
