"""A foundation block on soil under the mounts: the block, the soil and the soil's springs and dashpots.

The block (an inertia block of concrete) is one rigid body; the soil acts on it at the centre of its
base as six springs and dashpots (three translations, three rotations about the base's axes). They
are given directly, or follow from the soil's shear modulus G, Poisson's ratio ν and density ρ by
the closed forms for a rigid rectangular footing on the surface of a homogeneous elastic half-space:

- **static stiffness**: Gazetas, G. (1991), "Formulas and charts for impedances of surface and
  embedded foundations", *J. Geotech. Eng.* 117(9), 1363–1381, Table 1 (surface foundation, footing
  2L × 2B with L ≥ B, the x axis along L): K_z = 2GL/(1 − ν) (0.73 + 1.54 χ^0.75) with
  χ = A_b/(4L²); K_y = 2GL/(2 − ν) (2 + 2.5 χ^0.85); K_x = K_y − 0.2/(0.75 − ν) G L (1 − B/L);
  K_rx = G/(1 − ν) I_bx^0.75 (L/B)^0.25 (2.4 + 0.5 B/L); K_ry = 3G/(1 − ν) I_by^0.75 (L/B)^0.15;
  K_t = G J_t^0.75 (4 + 11 (1 − B/L)^10); I_bx, I_by the base's area moments about x and y,
  J_t = I_bx + I_by.
- **radiation damping** of the translations, as frequency-independent dashpots: Gazetas (1991),
  Table 1, C_z = ρ V_La A_b and C_x = C_y = ρ V_s A_b, with V_s = √(G/ρ) and Lysmer's analog
  wave speed V_La = 3.4 V_s / (π (1 − ν)) (the charts' factors c̃ taken as 1, their value over most
  of the frequency range);
- **radiation damping of rocking and torsion**, which is small at low frequency and depends on the
  block's inertia: Richart, Hall & Woods (1970), *Vibrations of Soils and Foundations*, § 7.3, for
  the disc of the same area moment, r⁴ = 4 I_b/π (rocking) and r⁴ = 2 J_t/π (torsion): damping ratio
  D_ψ = 0.15 / ((1 + B_ψ) √B_ψ), B_ψ = 3 (1 − ν) I_ψ / (8 ρ r⁵), and D_θ = 0.5 / (1 + 2 B_θ),
  B_θ = I_θ / (ρ r⁵), I_ψ and I_θ the block's mass moments about the base's axes; the dashpot is
  c = 2 D √(K I).

The soil's springs act on the block alone: the machine on its mounts is far lighter than the block
or isolated from it above its mount frequencies, so its inertia is left out of the rocking and
torsion damping (Richart, Hall & Woods' B_ψ counts the foundation and the machine rigidly fixed to
it; counting a machine on soft mounts would overstate the rocking inertia).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from mechdyn.errors import ModelError
from mechdyn.support.model import RigidBody, _vector
from mechdyn.units import si_field

__all__ = [
    "Foundation",
    "Soil",
    "gazetas_radiation_damping",
    "gazetas_static_stiffness",
    "rectangular_block",
]

SOIL_AXES = ("x", "y", "z", "rx", "ry", "rz")
"""The soil's six springs at the centre of the block's base: along and about the machine axes."""


@dataclass(frozen=True)
class Soil:
    """A homogeneous elastic half-space under the foundation.

    Parameters
    ----------
    shear_modulus : float or quantity
        G, Pa (small-strain dynamic modulus, G = ρ V_s²), from 1e5 Pa (very soft clay) to 1e11 Pa.
    poisson_ratio : float
        ν, dimensionless, from 0 to below 0.5 (saturated clay approaches 0.5).
    density : float or quantity
        ρ, kg/m³, from 500 to 5000 kg/m³.
    """

    shear_modulus: Any
    poisson_ratio: float
    density: Any

    def __post_init__(self) -> None:
        G = si_field("soil", "shear_modulus", self.shear_modulus, "Pa", low=1e5, high=1e11)
        nu = si_field("soil", "poisson_ratio", self.poisson_ratio, "", low=0.0, high=0.5, high_open=True)
        rho = si_field("soil", "density", self.density, "kg/m^3", low=500.0, high=5000.0)
        object.__setattr__(self, "shear_modulus", G)
        object.__setattr__(self, "poisson_ratio", nu)
        object.__setattr__(self, "density", rho)

    @classmethod
    def from_shear_wave_speed(cls, speed: Any, poisson_ratio: float, density: Any) -> Soil:
        """The soil of a measured shear-wave speed: G = ρ V_s².

        Parameters
        ----------
        speed : float or quantity
            V_s, m/s, from 10 to 5000 m/s.
        poisson_ratio : float
            ν, dimensionless.
        density : float or quantity
            ρ, kg/m³.
        """
        vs = si_field("soil", "shear_wave_speed", speed, "m/s", low=10.0, high=5000.0)
        rho = si_field("soil", "density", density, "kg/m^3", low=500.0, high=5000.0)
        return cls(rho * vs**2, poisson_ratio, rho)

    @property
    def shear_wave_speed(self) -> float:
        """V_s = √(G/ρ), m/s."""
        return math.sqrt(self.shear_modulus / self.density)

    @property
    def lysmer_speed(self) -> float:
        """Lysmer's analog wave speed V_La = 3.4 V_s / (π (1 − ν)), m/s (Gazetas 1991)."""
        return 3.4 * self.shear_wave_speed / (math.pi * (1.0 - self.poisson_ratio))


def _footprint(lx: float, ly: float) -> tuple[float, float, bool]:
    """(L, B, long side along x): half-dimensions of a 2L × 2B footing with L ≥ B."""
    return (lx / 2, ly / 2, True) if lx >= ly else (ly / 2, lx / 2, False)


def gazetas_static_stiffness(
    shear_modulus: float, poisson_ratio: float, length_x: float, length_y: float
) -> np.ndarray:
    """Static stiffness of a rigid rectangular surface footing on an elastic half-space.

    Gazetas (1991), "Formulas and charts for impedances of surface and embedded foundations",
    *J. Geotech. Eng.* 117(9), Table 1 (see the module's docstring for the six formulas); the footing
    is 2L × 2B, L ≥ B, and the formulas' x axis runs along L. A footing longer along the machine's y
    has its sway and rocking stiffnesses exchanged accordingly.

    Parameters
    ----------
    shear_modulus : float
        G, Pa.
    poisson_ratio : float
        ν, dimensionless, below 0.5.
    length_x, length_y : float
        The footing's full plan dimensions along the machine's x and y, m.

    Returns
    -------
    ndarray
        (6,) K_x, K_y, K_z (N/m) and K_rx, K_ry, K_rz (N·m/rad), along and about the machine axes
        through the centre of the base.
    """
    G, nu = float(shear_modulus), float(poisson_ratio)
    L, B, along_x = _footprint(float(length_x), float(length_y))
    chi = B / L  # A_b / (4 L²)
    I_long = 4.0 / 3.0 * L * B**3  # area moment about the long axis
    I_short = 4.0 / 3.0 * B * L**3  # about the short axis
    kz = 2 * G * L / (1 - nu) * (0.73 + 1.54 * chi**0.75)
    k_short = 2 * G * L / (2 - nu) * (2 + 2.5 * chi**0.85)  # sway across the long side (along B)
    k_long = k_short - 0.2 / (0.75 - nu) * G * L * (1 - chi)  # sway along the long side (along L)
    r_long = G / (1 - nu) * I_long**0.75 * (L / B) ** 0.25 * (2.4 + 0.5 * chi)  # rocking about it
    r_short = 3 * G / (1 - nu) * I_short**0.75 * (L / B) ** 0.15
    kt = G * (I_long + I_short) ** 0.75 * (4 + 11 * (1 - chi) ** 10)
    if along_x:
        return np.array([k_long, k_short, kz, r_long, r_short, kt])
    return np.array([k_short, k_long, kz, r_short, r_long, kt])


def gazetas_radiation_damping(
    soil: Soil, length_x: float, length_y: float, block_moments: Any = None
) -> np.ndarray:
    """Radiation dashpots of a rigid rectangular surface footing, frequency-independent.

    Translations: Gazetas (1991), Table 1, C_z = ρ V_La A_b, C_x = C_y = ρ V_s A_b (the charts'
    factors c̃ taken as 1). Rocking and torsion: Richart, Hall & Woods (1970), § 7.3, for the disc of
    the same area moment (r⁴ = 4 I_b/π; r⁴ = 2 J_t/π): D_ψ = 0.15/((1 + B_ψ) √B_ψ) with
    B_ψ = 3 (1 − ν) I_ψ/(8 ρ r⁵), D_θ = 0.5/(1 + 2 B_θ) with B_θ = I_θ/(ρ r⁵), and c = 2 D √(K I),
    K from :func:`gazetas_static_stiffness`.

    Parameters
    ----------
    soil : Soil
        The half-space.
    length_x, length_y : float
        The footing's full plan dimensions along the machine's x and y, m.
    block_moments : (3,), optional
        The block's mass moments of inertia about the base's x, y, z axes (through the centre of the
        base), kg·m²; without them the rotations get no dashpot.

    Returns
    -------
    ndarray
        (6,) C_x, C_y, C_z (N·s/m) and C_rx, C_ry, C_rz (N·m·s/rad).
    """
    lx, ly = float(length_x), float(length_y)
    area = lx * ly
    rho, vs, vla, nu = soil.density, soil.shear_wave_speed, soil.lysmer_speed, soil.poisson_ratio
    c = np.zeros(6)
    c[:3] = (rho * vs * area, rho * vs * area, rho * vla * area)
    if block_moments is None:
        return c
    K = gazetas_static_stiffness(soil.shear_modulus, nu, lx, ly)
    I_area = (lx * ly**3 / 12.0, ly * lx**3 / 12.0)  # the base's area moments about x and y, m⁴
    for k in (0, 1):  # rocking about x, about y
        r = (4.0 * I_area[k] / math.pi) ** 0.25
        Bpsi = 3.0 * (1.0 - nu) * float(block_moments[k]) / (8.0 * rho * r**5)
        D = 0.15 / ((1.0 + Bpsi) * math.sqrt(Bpsi)) if Bpsi > 0 else 0.0
        c[3 + k] = 2.0 * D * math.sqrt(K[3 + k] * float(block_moments[k]))
    r = (2.0 * sum(I_area) / math.pi) ** 0.25
    Bt = float(block_moments[2]) / (rho * r**5)
    c[5] = 2.0 * (0.5 / (1.0 + 2.0 * Bt)) * math.sqrt(K[5] * float(block_moments[2]))
    return c


def rectangular_block(size: Any, density: Any, top: Any = (0.0, 0.0, 0.0)) -> tuple[RigidBody, np.ndarray]:
    """A solid rectangular block (an inertia block), its top face centred at ``top``.

    m = ρ a b h, centre of mass h/2 below the top, I_xx = m (b² + h²)/12, I_yy = m (a² + h²)/12,
    I_zz = m (a² + b²)/12 (a solid cuboid).

    Parameters
    ----------
    size : (a, b, h)
        Length along x, width along y and depth, m, each above 0 and at most 1e3 m.
    density : float or quantity
        kg/m³ (reinforced concrete about 2400 kg/m³), from 100 to 20000 kg/m³.
    top : (x, y, z)
        The centre of the block's top face in machine coordinates, m (the mounts stand on it).

    Returns
    -------
    (RigidBody, ndarray)
        The block, and the centre of its base (where the soil acts), m.
    """
    a, b, h = _vector("foundation", "size", size, "m", positive=True)
    rho = si_field("foundation", "density", density, "kg/m^3", low=100.0, high=2e4)
    top = _vector("foundation", "top", top, "m")
    m = rho * a * b * h
    inertia = (m * (b * b + h * h) / 12, m * (a * a + h * h) / 12, m * (a * a + b * b) / 12)
    body = RigidBody(m, top - np.array([0.0, 0.0, h / 2]), inertia)
    return body, top - np.array([0.0, 0.0, h])


@dataclass(frozen=True)
class Foundation:
    """A rigid foundation block on soil springs and dashpots, under the machine's mounts.

    Parameters
    ----------
    block : RigidBody
        The block (mass, centre of mass, inertia), machine coordinates.
    base : (x, y, z)
        The centre of the block's base, where the soil's springs act, m.
    soil_stiffness : (6,)
        K_x, K_y, K_z (N/m) and K_rx, K_ry, K_rz (N·m/rad) along and about the machine axes at the
        base, each from 0 to 1e15.
    soil_damping : (6,)
        C_x, C_y, C_z (N·s/m) and C_rx, C_ry, C_rz (N·m·s/rad), each from 0 to 1e13.
    footprint : (lx, ly), optional
        The base's plan dimensions, m (reported; the closed forms' input).
    soil : Soil, optional
        The half-space the springs come from (None: springs given directly).
    name : str
    """

    block: RigidBody
    base: Any
    soil_stiffness: Any
    soil_damping: Any = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    footprint: tuple[float, float] | None = None
    soil: Soil | None = None
    name: str = "foundation"

    def __post_init__(self) -> None:
        object.__setattr__(self, "base", _vector(self.name, "base", self.base, "m"))
        for f, high in (("soil_stiffness", 1e15), ("soil_damping", 1e13)):
            v = np.asarray(getattr(self, f), dtype=float)
            if v.shape != (6,) or not np.isfinite(v).all() or (v < 0).any() or (v > high).any():
                raise ModelError(
                    f"{np.asarray(getattr(self, f)).tolist()} must be six values from 0 to {high:g} "
                    "(along x, y, z in N/m or N·s/m, then about x, y, z in N·m/rad or N·m·s/rad)",
                    element=self.name,
                    field=f,
                )
            object.__setattr__(self, f, v)

    @classmethod
    def on_half_space(
        cls, block: RigidBody, base: Any, footprint: Any, soil: Soil, name: str = "foundation"
    ) -> Foundation:
        """A block on a rigid rectangular footing on the surface of an elastic half-space.

        Springs by :func:`gazetas_static_stiffness` (Gazetas 1991), dashpots by
        :func:`gazetas_radiation_damping` (Gazetas 1991; Richart, Hall & Woods 1970 for rocking and
        torsion, with the block's mass moments about the base's axes).

        Parameters
        ----------
        block : RigidBody
            The block.
        base : (x, y, z)
            The centre of its base, m.
        footprint : (lx, ly)
            The base's plan dimensions along x and y, m, each above 0.
        soil : Soil
            The half-space.
        name : str
            The foundation's name.
        """
        lx, ly = _vector(name, "footprint", footprint, "m", n=2, positive=True)
        base = _vector(name, "base", base, "m")
        d = block.center_of_mass - base
        J = block.inertia + block.mass * (float(d @ d) * np.eye(3) - np.outer(d, d))
        K = gazetas_static_stiffness(soil.shear_modulus, soil.poisson_ratio, lx, ly)
        C = gazetas_radiation_damping(soil, lx, ly, np.diag(J))
        return cls(block, base, K, C, (float(lx), float(ly)), soil, name)

    @property
    def soil_stiffness_matrix(self) -> np.ndarray:
        """6×6 diagonal soil stiffness at the base (N/m, N·m/rad)."""
        return np.diag(self.soil_stiffness)

    @property
    def soil_damping_matrix(self) -> np.ndarray:
        """6×6 diagonal soil damping at the base (N·s/m, N·m·s/rad)."""
        return np.diag(self.soil_damping)

    def summary(self) -> dict[str, Any]:
        """The block and its soil, SI."""
        out: dict[str, Any] = {
            "foundation_mass_kg": float(self.block.mass),
            "foundation_center_of_mass_m": [float(v) for v in self.block.center_of_mass],
            "soil_stiffness_N_per_m": [float(v) for v in self.soil_stiffness[:3]],
            "soil_rotational_stiffness_Nm_per_rad": [float(v) for v in self.soil_stiffness[3:]],
            "soil_damping_N_s_per_m": [float(v) for v in self.soil_damping[:3]],
            "soil_rotational_damping_Nm_s_per_rad": [float(v) for v in self.soil_damping[3:]],
            "soil_springs_from": "given" if self.soil is None else "Gazetas (1991) half-space",
        }
        if self.soil is not None:
            out["soil_shear_modulus_Pa"] = float(self.soil.shear_modulus)
            out["soil_shear_wave_speed_m_per_s"] = float(self.soil.shear_wave_speed)
        return out
