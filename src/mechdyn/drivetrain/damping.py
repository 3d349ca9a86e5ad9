"""Damping added to a drivetrain's forced response: a ratio per mode, or Rayleigh's C = α M + β K.

:func:`mechdyn.drivetrain.frf` takes either; its ways of computing the response
(:mod:`mechdyn.drivetrain.frf_paths`) pick theirs by which it is.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mechdyn.checks import check_number
from mechdyn.errors import ModelError

__all__ = ["ModalDamping", "RayleighDamping"]


@dataclass(frozen=True)
class ModalDamping:
    """Viscous damping ratio ζ for every flexible mode (or one per mode, lowest first).

    Parameters
    ----------
    ratio : float or sequence of float
        ζ, dimensionless, in [0, 1): one for all flexible modes, or one per mode from the lowest.
    """

    ratio: float | tuple[float, ...] = 0.02

    def __post_init__(self) -> None:
        try:
            r = np.asarray(self.ratio, dtype=float)
        except (TypeError, ValueError):
            raise ModelError(
                f"{self.ratio!r} is not a number; give modal damping ratios in [0, 1)",
                element="modal damping",
                field="ratio",
            ) from None
        bad = ~(np.isfinite(r) & (r >= 0) & (r < 1))
        if bad.any():
            raise ModelError(
                f"modal damping ratio {r.flat[int(np.argmax(bad))]:g} must lie in [0, 1) (finite; 1 is "
                "critical damping)",
                element="modal damping",
                field="ratio",
            )
        if r.ndim > 1 or r.size == 0:
            raise ModelError(
                f"{self.ratio!r}: give one damping ratio, or one per flexible mode from the lowest",
                element="modal damping",
                field="ratio",
            )


@dataclass(frozen=True)
class RayleighDamping:
    """C = α M + β K, with α in 1/s and β in s (Rayleigh proportional damping; Lord Rayleigh,
    *The Theory of Sound*, vol. 1, 1877).

    Parameters
    ----------
    alpha : float
        Mass-proportional coefficient α, 1/s, from 0 to 1e8 1/s.
    beta : float
        Stiffness-proportional coefficient β, s, from 0 to 1e7 s."""

    alpha: float = 0.0
    beta: float = 0.0

    def __post_init__(self) -> None:
        alpha = check_number("Rayleigh damping", "alpha", self.alpha, "1/s", nonnegative=True, high=1e8)
        beta = check_number("Rayleigh damping", "beta", self.beta, "s", nonnegative=True)
        object.__setattr__(self, "alpha", alpha)
        object.__setattr__(self, "beta", beta)

    @classmethod
    def from_ratios(cls, f1_hz: float, f2_hz: float, zeta: float) -> RayleighDamping:
        """α, β giving damping ratio ζ at the two frequencies f1 and f2 (Hz).

        Parameters
        ----------
        f1_hz, f2_hz : float
            The two frequencies, Hz, positive (from 1e-7 to 1e7 Hz).
        zeta : float
            The damping ratio at both, dimensionless, in [0, 1).

        Notes
        -----
        ζ(ω) = α/(2ω) + βω/2 solved at ω₁ and ω₂ (e.g. Chopra, *Dynamics of Structures*, §11.4).
        """
        owner = "Rayleigh damping"
        f1 = check_number(owner, "f1_hz", f1_hz, "Hz", positive=True, what="frequency")
        f2 = check_number(owner, "f2_hz", f2_hz, "Hz", positive=True, what="frequency")
        zeta = check_number(owner, "zeta", zeta, low=0.0, high=1.0, high_open=True, what="damping ratio")
        w1, w2 = 2 * np.pi * f1, 2 * np.pi * f2
        return cls(alpha=2 * zeta * w1 * w2 / (w1 + w2), beta=2 * zeta / (w1 + w2))
