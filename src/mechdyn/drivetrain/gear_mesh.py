"""The gear mesh between two disks of a drivetrain, rigid (a constraint) or flexible (a spring along
the line of action): :class:`GearMesh`, an element of :mod:`mechdyn.drivetrain.elements`' protocol.

The sign convention and the accepted values are those of :mod:`mechdyn.drivetrain.elements`.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field, replace
from typing import Any, ClassVar, Literal

import numpy as np

from mechdyn.drivetrain.elements import (
    MAX_TEETH,
    MIN_RATIO,
    RATIO_TOLERANCE,
    Element,
    ElementBlocks,
    _name,
    _pair,
    _si,
)
from mechdyn.errors import ModelError, ModelWarning

__all__ = ["GearMesh"]


@dataclass(frozen=True)
class GearMesh(Element):
    """A gear mesh between two disks, rigid or flexible.

    Parameters
    ----------
    name : str
    disks : (str, str)
        Gear a and gear b.
    kind : {"external", "internal"}
        External meshes reverse the sense of rotation, internal ones keep it.
    teeth : (int, int), optional
        N_a, N_b; sets the ratio n = N_b / N_a and the gear-mesh excitation orders.
    ratio : float, optional
        n = ``|θ_a / θ_b|`` when the teeth are not known, dimensionless, from 1e-4 to 1e4 (as must be
        the ratio the teeth or the base radii give; each gear has at most 10 000 teeth).
    base_radii : (float, float) or quantities, optional
        r_a, r_b in m, from 1e-9 to 1e3 m. Required for a flexible mesh.
    stiffness : float or quantity, optional
        Mesh stiffness k_c along the line of action, N/m, from 1e-6 to 1e15 N/m. None makes the mesh
        rigid.
    damping : float or quantity, optional
        Mesh damping along the line of action, N·s/m, from 0 to 1e13 N·s/m.

    Notes
    -----
    A rigid mesh is the constraint θ_a = ∓n θ_b, reduced out by a transformation (the driven side
    then contributes n² J). A flexible mesh is the spring k_c on δ = r_a θ_a ± r_b θ_b, giving the block
    k_c [[r_a², ±r_a r_b], [±r_a r_b, r_b²]] (+ external, − internal); see Friswell, Penny, Garvey
    & Lees, *Dynamics of Rotating Machines* (2010), ch. 9 (torsional vibration of geared systems).
    The rigid ratio comes from the teeth, else ``ratio``, else the base radii; when teeth or ratio
    and base radii disagree by more than 0.5 % a :class:`~mechdyn.errors.ModelWarning` says so (the
    published turret data do), since the flexible mesh's no-load motion then follows the base radii,
    not the teeth.
    """

    name: str
    disks: tuple[str, str]
    kind: Literal["external", "internal"] = "external"
    teeth: tuple[int, int] | None = None
    ratio: float | None = None
    base_radii: tuple[float, float] | None = None
    stiffness: float | None = None
    damping: float = 0.0
    _rigid_ratio: float = field(init=False, repr=False, compare=False, default=1.0)
    VALUES: ClassVar[dict[str, tuple[str, str]]] = {
        "stiffness": ("N/m", "positive"),
        "damping": ("N*s/m", "nonnegative"),
    }

    def __post_init__(self) -> None:
        name = _name(self.name)
        object.__setattr__(self, "name", name)
        object.__setattr__(self, "disks", _pair(name, self.disks))
        if self.kind not in ("external", "internal"):
            raise ModelError(f"{self.kind!r} must be 'external' or 'internal'", element=name, field="kind")
        sources: list[tuple[str, float]] = []
        if self.teeth is not None:
            teeth = tuple(self.teeth) if not isinstance(self.teeth, str) else ()
            whole = all(
                isinstance(z, (int, np.integer)) or (isinstance(z, float) and z.is_integer()) for z in teeth
            )
            if len(teeth) != 2 or not whole or any(not 1 <= z <= MAX_TEETH for z in teeth):
                raise ModelError(
                    f"{self.teeth!r} must be two whole numbers between 1 and {MAX_TEETH}",
                    element=name,
                    field="teeth",
                )
            teeth = (int(teeth[0]), int(teeth[1]))
            object.__setattr__(self, "teeth", teeth)
            sources.append(("teeth", teeth[1] / teeth[0]))
        if self.ratio is not None:
            ratio = _si(name, "ratio", self.ratio, "", low=MIN_RATIO, high=1.0 / MIN_RATIO, what="gear ratio")
            object.__setattr__(self, "ratio", ratio)
            sources.append(("given ratio" if not sources else "ratio", ratio))
        if self.base_radii is not None:
            if isinstance(self.base_radii, str) or len(self.base_radii) != 2:
                raise ModelError(f"{self.base_radii!r} must be two radii", element=name, field="base_radii")
            radii = tuple(
                _si(name, "base_radii", r, "m", positive=True, what="base radius") for r in self.base_radii
            )
            object.__setattr__(self, "base_radii", radii)
            sources.append(("base_radii", radii[1] / radii[0]))
        if not sources:
            raise ModelError("give the teeth, the ratio or the base radii", element=name, field="teeth")
        for source, value in sources:
            if not MIN_RATIO <= value <= 1.0 / MIN_RATIO:
                raise ModelError(
                    f"the {source.replace('_', ' ')} give a gear ratio of {value:g}; give a ratio between "
                    f"{MIN_RATIO:g} and {1.0 / MIN_RATIO:g}",
                    element=name,
                    field=source.removeprefix("given "),
                )
        if self.stiffness is not None:
            k = _si(name, "stiffness", self.stiffness, "N/m", positive=True)
            object.__setattr__(self, "stiffness", k)
            if self.base_radii is None:
                raise ModelError(
                    "a flexible mesh (with stiffness) needs base_radii", element=name, field="base_radii"
                )
        object.__setattr__(self, "damping", _si(name, "damping", self.damping, "N*s/m", nonnegative=True))
        first_name, first = sources[0]
        for other_name, other in sources[1:]:
            if abs(other / first - 1.0) > RATIO_TOLERANCE:
                if other_name == "ratio":  # teeth and a ratio are both kinematic: they must agree
                    raise ModelError(
                        f"ratio {other:g} disagrees with the teeth ratio {first:g}; give one of them",
                        element=name,
                        field="ratio",
                    )
                use = (
                    "the rigid mesh and the speed ratios use"
                    if self.stiffness is None
                    else ("the flexible mesh uses the base radii; --rigid-gears and the speed ratios use")
                )
                warnings.warn(
                    f"mesh {name!r}: ratio {first:.4g} (from the {first_name}) but the base radii give "
                    f"{other:.4g} ({100 * abs(other / first - 1):.1f} % apart); {use} {first:.4g}",
                    ModelWarning,
                    stacklevel=3,
                )
        object.__setattr__(self, "_rigid_ratio", first)

    @classmethod
    def from_gear_pair(
        cls,
        name: str,
        disks: tuple[str, str],
        pair: Any,
        *,
        damping: Any = 0.0,
        points: int = 400,
    ) -> GearMesh:
        """A flexible mesh whose data come from a :class:`mechdyn.gears.GearPair` (spur or helical,
        external or internal: the mesh's kind is the pair's).

        Teeth (ratio and mesh orders) and base radii from the gears (transverse, for a helical pair);
        stiffness k_c = the mean mesh stiffness over one mesh cycle along the transverse line of action
        (:meth:`mechdyn.gears.GearPair.mesh_cycle`), N/m. Disk a is the pinion.

        Parameters
        ----------
        name : str
            The mesh's name, unique in its drivetrain.
        disks : tuple of str
            The disks that carry the pinion and the gear.
        pair : mechdyn.gears.GearPair
            The gear pair (teeth, base radii, tooth stiffness).
        damping : float or quantity
            Viscous mesh damping along the line of action, N·s/m.
        points : int
            Positions over one mesh cycle for its mean stiffness.
        """
        k = pair.mesh_cycle(points).mean
        return cls(
            name,
            disks,
            kind="internal" if getattr(pair, "internal", False) else "external",
            teeth=(pair.pinion.teeth, pair.gear.teeth),
            base_radii=(pair.pinion.base_radius, pair.gear.base_radius),
            stiffness=k,
            damping=damping,
        )

    @property
    def rigid(self) -> bool:
        """True when the mesh is a kinematic constraint (no stiffness given)."""
        return self.stiffness is None

    @property
    def speed_ratio(self) -> float:
        """n = ``|θ_a / θ_b| = |ω_a / ω_b|`` from teeth, ratio or base radii (in that order)."""
        return self._rigid_ratio

    @property
    def _sign(self) -> float:
        return 1.0 if self.kind == "external" else -1.0

    def as_rigid(self) -> GearMesh:
        """The same mesh as a rigid constraint (its ratio from teeth, ratio or base radii)."""
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ModelWarning)  # already said for this mesh
            return replace(self, stiffness=None, damping=0.0)

    def blocks(self) -> ElementBlocks:
        if self.rigid:
            # θ_a ∓ n θ_b = 0, written as c·θ = 0
            return ElementBlocks(self.disks, constraint=np.array([1.0, self._sign * self._rigid_ratio]))
        radii = self.base_radii
        assert radii is not None  # a flexible mesh has them (__post_init__)
        ra, rb = radii
        v = np.array([ra, self._sign * rb])
        outer = np.outer(v, v)
        return ElementBlocks(
            self.disks,
            stiffness=self.stiffness * outer,
            damping=self.damping * outer if self.damping else None,
            load_row=self.stiffness * v,
            load_rate_row=self.damping * v if self.damping else None,
            load_unit="N",
        )

    def transmission(self) -> float:
        if self.rigid:
            return -self._sign / self._rigid_ratio
        radii = self.base_radii
        assert radii is not None  # a flexible mesh has them (__post_init__)
        ra, rb = radii
        return -self._sign * ra / rb
