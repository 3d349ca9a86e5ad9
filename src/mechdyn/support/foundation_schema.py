"""The ``[foundation]`` table of a support model file: a foundation block on soil under the mounts.

``[foundation]`` is the block, by its ``size`` (length along x, width along y, depth) and ``density``
with its top face centred at ``top`` (the mounts stand on it), or by ``mass``, ``center_of_mass``,
``inertia``, the centre of its ``base`` and its ``footprint``. ``[foundation.soil]`` is the soil,
by its ``shear_modulus`` (or ``shear_wave_speed``), ``poisson_ratio`` and ``density`` (the springs
and dashpots of a rigid surface footing on an elastic half-space,
:func:`mechdyn.support.foundation.gazetas_static_stiffness`), or by its springs given directly
(``stiffness`` and ``rotational_stiffness`` at the centre of the base, with ``damping`` and
``rotational_damping``). ``floor_points`` are the block's points judged against the vibration
criteria (default: the mounts' feet). See ``examples/press_on_mounts_foundation.toml``.
"""

from __future__ import annotations

from typing import Any

from pydantic import Field, model_validator

from mechdyn.io.fields import (
    Density,
    Dimensionless,
    FileModel,
    Inertia,
    Length,
    LinearDamping,
    LinearStiffness,
    Mass,
    Pressure,
    TorsionalDamping,
    TorsionalStiffness,
    Velocity,
)
from mechdyn.io.modelfile import ModelSource, field_context

__all__ = ["build_foundation"]

L3 = tuple[Length, Length, Length]


class SoilTable(FileModel):
    shear_modulus: Pressure | None = Field(default=None, gt=0.0)
    """The soil's small-strain shear modulus G, e.g. "60 MPa" (or give shear_wave_speed)."""
    shear_wave_speed: Velocity | None = Field(default=None, gt=0.0)
    """The soil's shear-wave speed V_s, e.g. "180 m/s" (G = ρ V_s²; instead of shear_modulus)."""
    poisson_ratio: Dimensionless | None = None
    """Poisson's ratio ν of the soil (0.25 to 0.35 for sand, 0.4 to 0.5 for saturated clay)."""
    density: Density | None = None
    """The soil's mass density ρ, e.g. "1900 kg/m^3"."""
    stiffness: tuple[LinearStiffness, LinearStiffness, LinearStiffness] | None = None
    """The soil's springs along x, y, z at the centre of the base, given directly (instead of the
    half-space)."""
    rotational_stiffness: tuple[TorsionalStiffness, TorsionalStiffness, TorsionalStiffness] | None = None
    """The soil's springs about x, y, z at the centre of the base, given directly."""
    damping: tuple[LinearDamping, LinearDamping, LinearDamping] = (0.0, 0.0, 0.0)
    """The soil's dashpots along x, y, z, with springs given directly."""
    rotational_damping: tuple[TorsionalDamping, TorsionalDamping, TorsionalDamping] = (0.0, 0.0, 0.0)
    """The soil's dashpots about x, y, z, with springs given directly."""

    @model_validator(mode="after")
    def _one_soil(self) -> SoilTable:
        modulus = [k for k in ("shear_modulus", "shear_wave_speed") if getattr(self, k) is not None]
        springs = self.stiffness is not None or self.rotational_stiffness is not None
        if springs == bool(modulus):
            raise ValueError(
                "give the soil either as a half-space (shear_modulus or shear_wave_speed, with "
                "poisson_ratio and density) or as springs (stiffness and rotational_stiffness), one of "
                f"the two; got {modulus + (['stiffness'] if springs else []) or 'none'}"
            )
        if springs:
            if self.stiffness is None or self.rotational_stiffness is None:
                raise ValueError(
                    'soil springs need both stiffness = ["kx N/m", "ky N/m", "kz N/m"] and '
                    'rotational_stiffness = ["krx N*m/rad", "kry N*m/rad", "krz N*m/rad"]'
                )
            if self.poisson_ratio is not None or self.density is not None:
                raise ValueError("poisson_ratio and density belong to a half-space; remove them")
            return self
        if len(modulus) > 1:
            raise ValueError("give shear_modulus or shear_wave_speed, not both (G = ρ V_s²)")
        if self.poisson_ratio is None or self.density is None:
            raise ValueError(
                'a half-space needs poisson_ratio (e.g. 0.33) and density (e.g. "1900 kg/m^3") too'
            )
        if not 0.0 <= self.poisson_ratio < 0.5:
            raise ValueError(f"poisson_ratio {self.poisson_ratio:g} must be from 0 to below 0.5")
        if self.damping != (0.0, 0.0, 0.0) or self.rotational_damping != (0.0, 0.0, 0.0):
            raise ValueError(
                "a half-space's dashpots follow from it (radiation damping); damping and "
                "rotational_damping belong to springs given directly"
            )
        return self


class FoundationTable(FileModel):
    size: L3 | None = None
    """The block's length along x, width along y and depth (with ``density``; its base is its
    footprint)."""
    density: Density | None = None
    """The block's density (reinforced concrete about 2400 kg/m³), with ``size``."""
    top: L3 = (0.0, 0.0, 0.0)
    """The centre of the block's top face, where the mounts stand (with ``size``)."""
    mass: Mass | None = Field(default=None, gt=0.0)
    """The block's mass, instead of ``size`` and ``density``."""
    center_of_mass: L3 | None = None
    """The block's centre of mass (with ``mass``)."""
    inertia: tuple[Inertia, Inertia, Inertia] | None = None
    """The block's moments of inertia about its centre of mass, [I_xx, I_yy, I_zz] (with ``mass``)."""
    base: L3 | None = None
    """The centre of the block's base, where the soil acts (with ``mass``)."""
    footprint: tuple[Length, Length] | None = None
    """The base's plan dimensions [along x, along y] (with ``mass``, for soil given as a half-space)."""
    soil: SoilTable
    """The soil under the block: a half-space or springs."""
    floor_points: list[L3] | None = Field(default=None, min_length=1)
    """Points of the block [x, y, z] whose vibration is set against the criteria curves (default: the
    mounts' feet)."""

    @model_validator(mode="after")
    def _one_block(self) -> FoundationTable:
        by_size = self.size is not None or self.density is not None
        by_mass = any(getattr(self, k) is not None for k in ("mass", "center_of_mass", "inertia", "base"))
        if by_size == by_mass:
            raise ValueError(
                "give the block by its size and density (with top), or by its mass, center_of_mass, "
                "inertia and base (with footprint), one of the two"
            )
        if by_size:
            if self.size is None or self.density is None:
                raise ValueError(
                    'a block by its size needs both size = [a, b, h] and density = "2400 kg/m^3"'
                )
            if self.footprint is not None:
                raise ValueError("a block given by its size stands on its own footprint; remove footprint")
            if min(self.size) <= 0:
                raise ValueError(f"size {list(self.size)} m: every dimension must be above 0")
            return self
        missing = [k for k in ("mass", "center_of_mass", "inertia", "base") if getattr(self, k) is None]
        if missing:
            raise ValueError(f"a block by its mass needs {', '.join(missing)} too")
        if self.footprint is None and self.soil.stiffness is None:
            raise ValueError("soil given as a half-space needs the base's footprint = [along x, along y]")
        return self


def build_foundation(table: FoundationTable, source: ModelSource) -> Any:
    """The :class:`~mechdyn.support.foundation.Foundation` a ``[foundation]`` table describes.

    Parameters
    ----------
    table : FoundationTable
        The table as read.
    source : ModelSource
        The model file, for errors.
    """
    import numpy as np

    from mechdyn.support.foundation import Foundation, Soil, rectangular_block
    from mechdyn.support.model import RigidBody

    with field_context(source, "[foundation]"):
        footprint: tuple[float, float] | None
        if table.size is not None:
            block, base = rectangular_block(table.size, table.density, table.top)
            footprint = (table.size[0], table.size[1])
        else:
            block = RigidBody(table.mass, table.center_of_mass, table.inertia)
            base, footprint = np.asarray(table.base, dtype=float), table.footprint
    s = table.soil
    with field_context(source, "[foundation] → soil"):
        if s.stiffness is not None:
            K = [*s.stiffness, *(s.rotational_stiffness or ())]
            C = [*s.damping, *s.rotational_damping]
            fp = None if footprint is None else (float(footprint[0]), float(footprint[1]))
            return Foundation(block, base, K, C, fp)
        assert s.poisson_ratio is not None  # a half-space has both (SoilTable checks)
        if s.shear_modulus is not None:
            soil = Soil(s.shear_modulus, s.poisson_ratio, s.density)
        else:
            soil = Soil.from_shear_wave_speed(s.shear_wave_speed, s.poisson_ratio, s.density)
        return Foundation.on_half_space(block, base, footprint, soil)
