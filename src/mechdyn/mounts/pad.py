"""Bonded elastomer pads: compression with the shape factor and bulk compressibility, shear with the
bending of tall pads, and where the linear estimate holds.

Compression (Gent & Lindley 1959; Lindley, *Engineering Design with Natural Rubber*):
1/K_c = (h/A)·[1/(E(1 + 2kS²)) + 1/B], S = loaded area / force-free area (l b / (2 h (l + b)) for
a rectangle, D/(4h) for a disc). The published form put 1/B outside the bracket, which is not
dimensionally consistent (a stiffness plus a modulus); here the bulk term is a compliance in series,
inside. Shear: K_s = G A / h, and for a tall pad the bending of a block held parallel at both faces
in series, 1/K_s = h/(G A) + h³/(12 E_b I) with E_b = E(1 + (2/3) k S²) (Gent, *Engineering with
Rubber*, ch. 9).

Rubber is hyperelastic; the linear stiffness holds for compressive strains up to about 10–15 % and
shear strains up to about 50 % (Lindley). :meth:`ElastomerPad.compression_force` offers a
load-dependent estimate beyond: a neo-Hookean block, F = (E_c A / 3)(λ⁻² − λ), λ = 1 − δ/h, whose
slope at δ = 0 is the linear K_c.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from mechdyn.checks import check_array
from mechdyn.errors import ModelError
from mechdyn.mounts.materials import Material
from mechdyn.units import si_field

__all__ = ["ElastomerPad"]

LINEAR_COMPRESSION_STRAIN = 0.10
LINEAR_SHEAR_STRAIN = 0.50


@dataclass(frozen=True)
class ElastomerPad:
    """A rubber pad bonded between two rigid plates.

    Parameters
    ----------
    name : str
    material : Material
        A rubber (E, G, B and the compression coefficient k), e.g. ``default_materials().rubber(60)``:
        a material of kind ``"rubber"`` (steel or concrete is refused: the shape-factor law is
        rubber's).
    thickness : float or quantity
        h, m, from 1e-9 to 1e3 m.
    length, width : float or quantity, optional
        For a rectangular pad, m, from 1e-9 to 1e3 m.
    diameter : float or quantity, optional
        For a disc, m (instead of length and width), from 1e-9 to 1e3 m.
    compression_coefficient : float, optional
        Overrides the material's k (a calibrated pad factor), in (0, 1].
    """

    name: str
    material: Material
    thickness: Any
    length: Any = None
    width: Any = None
    diameter: Any = None
    compression_coefficient: float | None = None

    def __post_init__(self) -> None:
        kind = getattr(self.material, "kind", None)
        if kind != "rubber":
            shown = getattr(self.material, "name", self.material)
            raise ModelError(
                f"{shown!r} is of kind {kind!r}, not an elastomer: a bonded pad's stiffness follows rubber's "
                "shape-factor law; give a rubber, e.g. default_materials().rubber(60) or a Material of "
                "kind 'rubber' (default_materials().names('rubber') lists the shipped ones)",
                element=self.name,
                field="material",
            )
        for f in ("thickness", "length", "width", "diameter"):
            v = getattr(self, f)
            if v is None:
                continue
            object.__setattr__(self, f, si_field(self.name, f, v, "m", positive=True))
        rect = self.length is not None and self.width is not None
        if rect == (self.diameter is not None):
            raise ModelError(
                "give length and width (a rectangular pad) or diameter (a disc), not both",
                element=self.name,
                field="diameter",
            )
        k = self.compression_coefficient
        if k is not None:
            k = si_field(self.name, "compression_coefficient", k, "", low=0.0, high=1.0, low_open=True)
            object.__setattr__(self, "compression_coefficient", k)

    @property
    def k(self) -> float:
        """The compression coefficient in use."""
        return (
            self.material.compression_coefficient
            if self.compression_coefficient is None
            else self.compression_coefficient
        )

    @property
    def area(self) -> float:
        """Loaded area A, m²."""
        if self.diameter is not None:
            return math.pi * self.diameter**2 / 4
        return self.length * self.width

    @property
    def shape_factor(self) -> float:
        """S = loaded area / force-free side area."""
        h = self.thickness
        if self.diameter is not None:
            return self.diameter / (4 * h)
        return self.length * self.width / (2 * h * (self.length + self.width))

    @property
    def compression_modulus(self) -> float:
        """Apparent modulus E_c with the bulk term, Pa: 1/E_c = 1/(E(1 + 2kS²)) + 1/B."""
        m = self.material
        return 1.0 / (
            1.0 / (m.youngs_modulus * (1 + 2 * self.k * self.shape_factor**2)) + 1.0 / m.bulk_modulus
        )

    @property
    def compression_stiffness(self) -> float:
        """K_c = E_c A / h, N/m."""
        return self.compression_modulus * self.area / self.thickness

    # -- the interface every mount estimate shares (mechdyn.mounts.types.MountEstimate) ----------
    adjusts_height = False
    damps = True
    # filled natural rubber at room temperature: η ≈ 0.05–0.15 (Harris & Piersol, *Shock and
    # Vibration Handbook*, 5th ed., ch. 32); the middle of that range
    loss_factor = 0.1

    @property
    def stiffness(self) -> float:
        """Along the mount's axis: the compression stiffness K_c, N/m."""
        return self.compression_stiffness

    @property
    def lateral_stiffness(self) -> float:
        """Across the mount's axis: the shear stiffness K_s with bending, N/m."""
        return self.shear_stiffness

    @property
    def ideal_compression_stiffness(self) -> float:
        """K_c with k = 1, the linear-elastic solid's shape-factor law (what an FE model of E and B
        gives; filled rubbers fall below it, hence the table's k < 1), N/m."""
        m = self.material
        Ec = 1.0 / (1.0 / (m.youngs_modulus * (1 + 2 * self.shape_factor**2)) + 1.0 / m.bulk_modulus)
        return Ec * self.area / self.thickness

    @property
    def _second_moment(self) -> float:
        """Smallest second moment of area of the loaded face, m⁴ (the pad bends about its weak axis)."""
        if self.diameter is not None:
            return math.pi * self.diameter**4 / 64
        a, b = sorted((self.length, self.width))
        return b * a**3 / 12

    @property
    def shear_stiffness(self) -> float:
        """K_s with the bending of the pad in series, N/m (the lower of the two directions)."""
        m, h = self.material, self.thickness
        Eb = m.youngs_modulus * (1 + 2.0 / 3.0 * self.k * self.shape_factor**2)
        return 1.0 / (h / (m.shear_modulus * self.area) + h**3 / (12 * Eb * self._second_moment))

    @property
    def shear_stiffness_without_bending(self) -> float:
        """G A / h, N/m."""
        return self.material.shear_modulus * self.area / self.thickness

    @property
    def linear_limits(self) -> dict[str, float]:
        """Loads up to which the linear estimate holds (≈10 % compression, 50 % shear strain), N."""
        return {
            "compression_N": self.compression_stiffness * LINEAR_COMPRESSION_STRAIN * self.thickness,
            "shear_N": self.shear_stiffness * LINEAR_SHEAR_STRAIN * self.thickness,
        }

    def _deflections(self, deflection: Any) -> np.ndarray:
        """Deflections δ in m, checked: finite and in [0, h) (the neo-Hookean law ends at δ = h)."""
        if isinstance(deflection, str) or hasattr(deflection, "units"):  # a quantity
            deflection = si_field(self.name, "deflection", deflection, "m")
        return check_array(
            self.name,
            "deflection",
            deflection,
            "m",
            low=0.0,
            high=self.thickness,
            high_open=True,
            what="deflections",
        )

    def compression_force(self, deflection: Any) -> np.ndarray:
        """Load-dependent estimate of the compressive force at a deflection δ (m), N.

        A neo-Hookean block scaled by the shape-factor modulus: F = (E_c A / 3)(λ⁻² − λ), λ = 1 − δ/h.

        Parameters
        ----------
        deflection : float or ndarray or quantity
            Compression δ, m (0 ≤ δ < h).

        Raises
        ------
        mechdyn.errors.ModelError
            For a deflection that is not finite or outside [0, h), naming the first.
        """
        lam = 1.0 - self._deflections(deflection) / self.thickness
        return self.compression_modulus * self.area / 3.0 * (lam**-2 - lam)

    def tangent_stiffness(self, deflection: Any) -> np.ndarray:
        """dF/dδ of :meth:`compression_force`, N/m.

        Parameters
        ----------
        deflection : float or ndarray or quantity
            Compression δ, m (0 ≤ δ < h).

        Raises
        ------
        mechdyn.errors.ModelError
            For a deflection that is not finite or outside [0, h), naming the first.
        """
        lam = 1.0 - self._deflections(deflection) / self.thickness
        return self.compression_modulus * self.area / (3.0 * self.thickness) * (2 * lam**-3 + 1)

    def breakdown(self) -> dict[str, float]:
        """The parts of the estimate (SI)."""
        m = self.material
        return {
            "shape_factor": self.shape_factor,
            "compression_coefficient": self.k,
            "youngs_modulus_Pa": m.youngs_modulus,
            "bulk_modulus_Pa": m.bulk_modulus,
            "shear_modulus_Pa": m.shear_modulus,
            "compression_modulus_without_bulk_Pa": m.youngs_modulus * (1 + 2 * self.k * self.shape_factor**2),
            "compression_modulus_Pa": self.compression_modulus,
            "compression_stiffness_N_per_m": self.compression_stiffness,
            "compression_stiffness_ideal_solid_N_per_m": self.ideal_compression_stiffness,
            "shear_stiffness_N_per_m": self.shear_stiffness,
            "shear_stiffness_without_bending_N_per_m": self.shear_stiffness_without_bending,
        }
