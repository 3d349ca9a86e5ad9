"""The other mount types of the published survey, and the isolation figures a vendor calculator gives.

Every mount answers the same questions: its stiffness along its main (vertical) axis, whether it
adjusts the machine's height, whether it damps (and its loss factor), and the parts of its estimate.

- Levelling wedge mount: hardened steel wedges in a housing, adjusted by a screw. Catalogue
  stiffness when given; otherwise the steel stack in compression, k = E A / h, an upper bound (the
  contact joints between the parts make real mounts softer; vendors list 1–5 kN/µm for mid sizes).
- Screw levelling foot: the spindle in compression over its free length in series with its base
  (a steel disc or an elastomer pad), k = 1/(L/(E A_s) + 1/k_base).
- Damping pad: an elastomer pad (:class:`~mechdyn.mounts.pad.ElastomerPad`) with a loss factor.
- Spring isolator: n helical springs in parallel, k = n G d⁴/(8 D³ N_a) (Shigley §10-3, Eq. 10-9).

Isolation (e.g. Rao, *Mechanical Vibrations*, §9.10): static deflection δ = W/k, natural frequency
f_n = √(k/m)/(2π) = √(g/δ)/(2π), transmissibility T = √((1 + (2ζr)²)/((1 − r²)² + (2ζr)²)) with
r = f/f_n and ζ = η/2 for a loss factor η, isolation efficiency 1 − T (negative: amplification).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Protocol, runtime_checkable

from mechdyn.checks import check_count
from mechdyn.errors import ModelError
from mechdyn.mounts.materials import Material
from mechdyn.mounts.pad import ElastomerPad
from mechdyn.units import STANDARD_GRAVITY, si_field

__all__ = ["DampingPad", "LevellingWedge", "MountEstimate", "ScrewFoot", "SpringIsolator", "isolation"]

G0 = STANDARD_GRAVITY


MAX_LOSS_FACTOR = 2.0
"""Loss factors η are accepted in [0, 2): ζ = η/2 below critical damping (rubber ≈ 0.1, steel ≈ 0.005)."""
MAX_COUNT = 10_000
"""The most active coils, and springs in parallel, a spring isolator may have."""


def _positive(owner: str, field: str, value: Any, unit: str) -> float:
    """A positive quantity in ``unit`` (SI), finite and within the magnitude a machine can have."""
    return si_field(owner, field, value, unit, positive=True)


def _loss_factor(owner: str, value: Any) -> float:
    """A loss factor η, dimensionless, in [0, 2)."""
    return si_field(
        owner, "loss_factor", value, "", low=0.0, high=MAX_LOSS_FACTOR, high_open=True, what="loss factor"
    )


@runtime_checkable
class MountEstimate(Protocol):
    """What every mount estimate answers, whatever its type (pad, bolted joint or anchor, wedge,
    screw foot, damping pad, spring isolator): the one interface a support model, the mount
    analysis and the calibration use.

    Attributes
    ----------
    name : str
    stiffness : float
        Along the mount's axis (vertical under a machine), N/m.
    lateral_stiffness : float or None
        Across the axis, N/m; None where the drawing does not give it (then the support model asks
        for it).
    loss_factor : float
        η of the mount's material (viscous equivalent ζ = η/2 at resonance).
    damps, adjusts_height : bool
    """

    name: str

    @property
    def stiffness(self) -> float: ...

    @property
    def lateral_stiffness(self) -> float | None: ...

    @property
    def loss_factor(self) -> float: ...

    @property
    def damps(self) -> bool: ...

    @property
    def adjusts_height(self) -> bool: ...

    def breakdown(self) -> dict[str, Any]:
        """Every part of the estimate, SI values keyed with their unit (e.g. ``bolt_N_per_m``), for
        tables and the JSON summary."""
        ...


@dataclass(frozen=True)
class LevellingWedge:
    """A levelling wedge mount.

    Parameters
    ----------
    name : str
    bearing_area : float or quantity
        Load-bearing area of the wedge stack, m².
    height : float or quantity
        Stack height, m.
    material : Material
        The wedges' steel.
    catalogue_stiffness : float or quantity, optional
        The vendor's vertical stiffness, N/m; used when given.
    adjusts_height : bool
        Whether the mount levels the machine (True for a wedge).
    damps : bool
        Whether it adds damping (False for steel).
    loss_factor : float
        η of the mount, dimensionless, in [0, 2).
    """

    name: str
    bearing_area: Any
    height: Any
    material: Material
    catalogue_stiffness: Any = None
    adjusts_height: bool = True
    damps: bool = False
    loss_factor: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(
            self, "bearing_area", _positive(self.name, "bearing_area", self.bearing_area, "m^2")
        )
        object.__setattr__(self, "height", _positive(self.name, "height", self.height, "m"))
        if self.catalogue_stiffness is not None:
            object.__setattr__(
                self,
                "catalogue_stiffness",
                _positive(self.name, "catalogue_stiffness", self.catalogue_stiffness, "N/m"),
            )
        object.__setattr__(self, "loss_factor", _loss_factor(self.name, self.loss_factor))

    lateral_stiffness = None  # the housing's friction: not estimated

    @property
    def solid_stiffness(self) -> float:
        """E A / h of the steel stack, N/m (an upper bound)."""
        return self.material.youngs_modulus * self.bearing_area / self.height

    @property
    def stiffness(self) -> float:
        """Vertical stiffness, N/m: the catalogue's, else the solid stack's."""
        return self.catalogue_stiffness if self.catalogue_stiffness is not None else self.solid_stiffness

    def breakdown(self) -> dict[str, Any]:
        """Every part of the estimate, SI values keyed with their unit (e.g. ``spindle_N_per_m``),
        for tables and the JSON summary."""
        return {
            "solid_steel_stack_N_per_m": self.solid_stiffness,
            "catalogue_N_per_m": self.catalogue_stiffness,
            "used": "catalogue"
            if self.catalogue_stiffness is not None
            else "solid steel stack (upper bound)",
        }


@dataclass(frozen=True)
class ScrewFoot:
    """A screw levelling foot: a threaded spindle standing on a base.

    Parameters
    ----------
    name : str
    diameter : float or quantity
        Spindle nominal diameter, m.
    free_length : float or quantity
        Spindle length between the machine and the base, m.
    material : Material
    base : ElastomerPad or float or quantity, optional
        An elastomer base pad, or the base's stiffness (N/m); none means a rigid steel base.
    pitch : float or quantity, optional
        Spindle thread pitch, m, positive and below d/0.9382; by default the ISO 261 coarse pitch of
        its diameter (a diameter that is no ISO metric size then needs the pitch).
    adjusts_height : bool
        True: the screw levels the machine.
    """

    name: str
    diameter: Any
    free_length: Any
    material: Material
    base: Any = None
    adjusts_height: bool = True
    pitch: Any = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "diameter", _positive(self.name, "diameter", self.diameter, "m"))
        object.__setattr__(self, "free_length", _positive(self.name, "free_length", self.free_length, "m"))
        if self.base is not None and not isinstance(self.base, ElastomerPad):
            object.__setattr__(self, "base", _positive(self.name, "base", self.base, "N/m"))
        if self.pitch is not None:
            object.__setattr__(self, "pitch", _positive(self.name, "pitch", self.pitch, "m"))
        self._pitch()  # a diameter without an ISO coarse pitch, or a pitch that leaves no core: refused now

    def _pitch(self) -> float:
        """The thread pitch P in use, m, checked against the diameter."""
        from mechdyn.mounts.bolted import coarse_pitch

        P = coarse_pitch(self.name, self.diameter) if self.pitch is None else float(self.pitch)
        if not 0.9382 * P < self.diameter:
            raise ModelError(
                f"pitch {P:g} m leaves no stress area in a {self.diameter:g} m spindle "
                "(π/4 (d − 0.9382 P)²); "
                "check the pitch",
                element=self.name,
                field="pitch",
            )
        return P

    lateral_stiffness = None  # the spindle's bending and the base's friction: not estimated

    @property
    def spindle_stiffness(self) -> float:
        """A_s E / L, N/m (stress area π/4 (d − 0.9382 P)² with the ISO 261 coarse pitch P)."""
        P = self._pitch()
        a_s = math.pi / 4 * (self.diameter - 0.9382 * P) ** 2
        return a_s * self.material.youngs_modulus / self.free_length

    @property
    def base_stiffness(self) -> float | None:
        if self.base is None:
            return None
        return self.base.compression_stiffness if isinstance(self.base, ElastomerPad) else self.base

    @property
    def stiffness(self) -> float:
        """Spindle and base in series, N/m."""
        kb = self.base_stiffness
        return self.spindle_stiffness if kb is None else 1.0 / (1.0 / self.spindle_stiffness + 1.0 / kb)

    @property
    def damps(self) -> bool:
        return isinstance(self.base, ElastomerPad)

    @property
    def loss_factor(self) -> float:
        return 0.1 if self.damps else 0.0

    def breakdown(self) -> dict[str, Any]:
        """Every part of the estimate, SI values keyed with their unit (e.g. ``spindle_N_per_m``),
        for tables and the JSON summary."""
        return {"spindle_N_per_m": self.spindle_stiffness, "base_N_per_m": self.base_stiffness}


@dataclass(frozen=True)
class DampingPad:
    """An elastomer damping pad: a bonded pad with a loss factor (does not adjust height).

    Parameters
    ----------
    name : str
        The mount's name.
    pad : ElastomerPad
        The pad, whose compression and shear stiffness the mount takes.
    loss_factor : float
        η of the damping compound, dimensionless, in [0, 2).
    adjusts_height : bool
        False: a pad does not level the machine.
    damps : bool
        True.
    """

    name: str
    pad: ElastomerPad
    loss_factor: float = 0.1
    adjusts_height: bool = False
    damps: bool = True

    def __post_init__(self) -> None:
        object.__setattr__(self, "loss_factor", _loss_factor(self.name, self.loss_factor))

    @property
    def stiffness(self) -> float:
        """The pad's compression stiffness, N/m."""
        return self.pad.compression_stiffness

    @property
    def lateral_stiffness(self) -> float:
        """The pad's shear stiffness, N/m."""
        return self.pad.shear_stiffness

    def breakdown(self) -> dict[str, Any]:
        """Every part of the estimate, SI values keyed with their unit (e.g. ``spindle_N_per_m``),
        for tables and the JSON summary."""
        return self.pad.breakdown() | {"loss_factor": self.loss_factor}


@dataclass(frozen=True)
class SpringIsolator:
    """Helical compression springs in parallel under a housing.

    Parameters
    ----------
    name : str
    wire_diameter, coil_diameter : float or quantity
        d and mean coil diameter D, m, from 1e-9 to 1e3 m.
    active_coils : float
        Number of active coils N_a (k = G d⁴/(8 D³ N_a)), positive, at most :data:`MAX_COUNT`.
    springs : int
        How many in parallel, a whole number from 1 to :data:`MAX_COUNT`.
    material : Material
        Spring steel (its shear modulus G).
    adjusts_height : bool
        Whether the mount levels the machine (True for a wedge).
    damps : bool
        Whether it adds damping (False for steel).
    loss_factor : float
        η of the mount, dimensionless, in [0, 2).
    """

    name: str
    wire_diameter: Any
    coil_diameter: Any
    active_coils: float
    material: Material
    springs: int = 1
    adjusts_height: bool = False
    damps: bool = False
    loss_factor: float = 0.005

    def __post_init__(self) -> None:
        d = _positive(self.name, "wire_diameter", self.wire_diameter, "m")
        D = _positive(self.name, "coil_diameter", self.coil_diameter, "m")
        if D <= d:
            raise ModelError(
                f"coil diameter {D:g} m must exceed the wire {d:g} m",
                element=self.name,
                field="coil_diameter",
            )
        coils = si_field(self.name, "active_coils", self.active_coils, "", positive=True, high=MAX_COUNT)
        springs = check_count(self.name, "springs", self.springs, high=MAX_COUNT)
        object.__setattr__(self, "wire_diameter", d)
        object.__setattr__(self, "coil_diameter", D)
        object.__setattr__(self, "active_coils", coils)
        object.__setattr__(self, "springs", springs)
        object.__setattr__(self, "loss_factor", _loss_factor(self.name, self.loss_factor))

    lateral_stiffness = None  # a spring's lateral rate depends on its end fixing: give it

    @property
    def stiffness(self) -> float:
        """n G d⁴ / (8 D³ N_a), N/m."""
        d, D = self.wire_diameter, self.coil_diameter
        return self.springs * self.material.shear_modulus * d**4 / (8 * D**3 * self.active_coils)

    def breakdown(self) -> dict[str, Any]:
        """Every part of the estimate, SI values keyed with their unit (e.g. ``spindle_N_per_m``),
        for tables and the JSON summary."""
        return {"spring_N_per_m": self.stiffness / self.springs, "springs": self.springs}


def isolation(
    stiffness: Any, load: Any, disturbing_frequency: Any, loss_factor: float = 0.0
) -> dict[str, float]:
    """Static deflection, natural frequency, transmissibility and isolation efficiency of a mount.

    Parameters
    ----------
    stiffness : float or quantity
        N/m, from 1e-6 to 1e15 N/m.
    load : float or quantity
        The weight the mount carries, N (or a mass in kg, taken under standard gravity), positive.
    disturbing_frequency : float or quantity
        Hz (or rpm), from 1e-7 to 1e7 Hz.
    loss_factor : float
        η, in [0, 2); the viscous equivalent ζ = η/2.

    Returns
    -------
    dict
        ``static_deflection_m``, ``natural_frequency_hz``, ``frequency_ratio``,
        ``transmissibility`` T and ``isolation_efficiency`` 1 − T (negative: the mount amplifies).
    """
    k = _positive("isolation", "stiffness", stiffness, "N/m")
    if isinstance(load, int | float):
        W = _positive("isolation", "load", load, "N")
    else:
        try:
            W = _positive("isolation", "load", load, "N")
        except ModelError:
            W = _positive("isolation", "load", load, "kg") * G0
    f = _positive("isolation", "disturbing_frequency", disturbing_frequency, "Hz")
    loss_factor = _loss_factor("isolation", loss_factor)
    m = W / G0
    fn = math.sqrt(k / m) / (2 * math.pi)
    r, zeta = f / fn, loss_factor / 2
    T = math.sqrt((1 + (2 * zeta * r) ** 2) / ((1 - r**2) ** 2 + (2 * zeta * r) ** 2))
    return {
        "static_deflection_m": W / k,
        "natural_frequency_hz": fn,
        "frequency_ratio": r,
        "transmissibility": T,
        "isolation_efficiency": 1 - T,
    }
