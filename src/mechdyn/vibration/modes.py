"""The modal interface every linear model shares: frequencies in one unit, shapes, energy shares.

A model's undamped modes solve K φ = ω² M φ with φ mass-normalised (φᵀ M φ = 1). The kinetic energy
of mode k splits over the coordinates as e_jk = φ_jk (M φ_k)_j; the shares sum to one, and a mode with
one share near 1 is decoupled (Harris & Piersol, *Shock and Vibration Handbook*, 5th ed., ch. 30;
the "kinetic energy distribution" tables of mount calculators). A drivetrain reports them per disk,
a machine on mounts per rigid-body coordinate: both through :class:`Modes`.
"""

from __future__ import annotations

from functools import cached_property

import numpy as np

__all__ = ["Modes"]


class Modes:
    """Mixin for a modal result: ``omega`` (rad/s) and mass-normalised ``shapes`` in, the rest out.

    A subclass provides ``omega`` ((n_modes,) rad/s, ascending), ``shapes`` ((n_coordinates,
    n_modes)), :attr:`coordinate_names` and :meth:`coordinate_mass` (the mass matrix on the
    coordinates the shapes are given in, or its diagonal).
    """

    omega: np.ndarray
    shapes: np.ndarray

    @property
    def frequencies_hz(self) -> np.ndarray:
        """Natural frequencies, Hz, ascending (ω / 2π)."""
        return self.omega / (2.0 * np.pi)

    @property
    def coordinate_names(self) -> tuple[str, ...]:
        raise NotImplementedError

    def coordinate_mass(self) -> np.ndarray:
        """The mass matrix (kg, kg·m²) on the shapes' coordinates, (n, n), or its diagonal (n,)."""
        raise NotImplementedError

    @cached_property
    def kinetic_energy(self) -> np.ndarray:
        """(n_coordinates, n_modes) share of each coordinate in each mode's kinetic energy.

        e_jk = φ_jk (M φ_k)_j, each column normalised to sum to 1.
        """
        M = self.coordinate_mass()
        phi = self.shapes
        e = phi * (M[:, None] * phi if M.ndim == 1 else M @ phi)
        total = e.sum(axis=0)
        return e / np.where(total == 0, 1.0, total)

    @property
    def dominant(self) -> list[str]:
        """The coordinate that carries most of each mode's kinetic energy."""
        names = self.coordinate_names
        return [names[int(j)] for j in np.argmax(self.kinetic_energy, axis=0)]

    @property
    def decoupling(self) -> np.ndarray:
        """(n_modes,) the largest kinetic-energy share of each mode: 1 for a fully decoupled mode."""
        return self.kinetic_energy.max(axis=0) if self.shapes.size else np.zeros(0)
