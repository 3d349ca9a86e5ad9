"""Drivetrain elements: disks, shafts, grounded springs and dampers (gear meshes:
:mod:`mechdyn.drivetrain.gear_mesh`).

Sign convention
---------------
Every disk angle θ is measured in one global sense (counter-clockwise looking along +z, the shafts
being parallel). An *external* mesh turns its gears in opposite senses: the contact compression along
the line of action is δ = r_a θ_a + r_b θ_b, so a rigid external mesh imposes θ_a = −n θ_b. An
*internal* mesh turns both the same way: δ = r_a θ_a − r_b θ_b and θ_a = +n θ_b. Here r are base radii
and n = N_b / N_a (teeth) is the ratio ``|θ_a / θ_b|``.

Every element implements one protocol, :meth:`Element.blocks`, returning the disks it connects and its
contributions to the mass, stiffness and damping matrices and, for a rigid mesh, its constraint row.
The assembler knows no element type by name.

Accepted values
---------------
Every quantity is checked where it enters (:func:`mechdyn.units.si_field`): it must be finite and
within the magnitude a machine can have in its unit, the bounds of the model files
(:data:`mechdyn.checks.MAGNITUDE_LIMITS`: at most 1e10 kg·m², 1e14 N·m/rad, 1e15 N/m, 1e3 m, ...);
a size, an inertia or a stiffness must moreover be positive and not below
:data:`mechdyn.checks.SMALLEST_POSITIVE` of its unit (1e-18 kg·m², 1e-9 N·m/rad, 1e-9 m, ...).
Anything else is a :class:`~mechdyn.errors.ModelError` naming the element, the field and the value.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar, Literal

import numpy as np

from mechdyn.checks import magnitude_limit, smallest_positive
from mechdyn.errors import ModelError
from mechdyn.units import si_field

__all__ = [
    "Disk",
    "Element",
    "ElementBlocks",
    "GroundDamper",
    "GroundSpring",
    "Shaft",
]

#: Relative disagreement above which two sources of a gear ratio are reported.
RATIO_TOLERANCE = 0.005
#: The smallest gear ratio of one mesh accepted (and its inverse the largest): far beyond any real
#: pair of gears (a worm pair reaches about 1:100), well inside what the matrices carry.
MIN_RATIO = 1e-4
#: The most teeth a gear of a mesh may have.
MAX_TEETH = 10_000
#: The most sub-elements one shaft may be divided into (far more than convergence needs: its blocks are
#: dense, (N + 1)², and checked element by element).
MAX_SHAFT_ELEMENTS = 1000
#: How a shaft's own inertia enters the mass matrix.
MASS_MODELS = ("consistent", "lumped")


@dataclass(frozen=True)
class ElementBlocks:
    """What one element contributes to the assembled matrices.

    Attributes
    ----------
    disks : tuple of str
        The disks (degrees of freedom) the blocks refer to, in order.
    mass, stiffness, damping : ndarray or None
        Square blocks over ``disks`` in kg·m², N·m/rad and N·m·s/rad.
    constraint : ndarray or None
        A row ``c`` with ``c @ θ[disks] = 0`` (rigid gear mesh).
    load_row : ndarray or None
        The element's internal load as ``load_row @ θ[disks]`` (shaft torque in N·m, mesh force in N).
    load_rate_row : ndarray or None
        Its damping part, ``load_rate_row @ θ̇[disks]``, in the same unit.
    load_unit : str
        Unit of that load.
    grounds : bool
        True when the element ties its disk to the frame through a stiffness.
    internal : tuple of str
        Degrees of freedom the element creates itself (the nodes inside a shaft divided into elements,
        ``"shaft[1]"``, …), a subset of ``disks``; they turn with the element's ends in a rigid-body
        motion (transmission 1 from one node to the next).
    stiffness_rows : ndarray or None
        (r, k) rows s_j with ``stiffness = Σ_j s_jᵀ s_j``, √(N·m/rad), one per spring, where the stiffness
        block is not of rank one (a divided shaft: one row per sub-element); they let the eigen solver
        work from the springs to high relative accuracy (:func:`mechdyn.drivetrain.stiffness_factor`).
    """

    disks: tuple[str, ...]
    mass: np.ndarray | None = None
    stiffness: np.ndarray | None = None
    damping: np.ndarray | None = None
    constraint: np.ndarray | None = None
    load_row: np.ndarray | None = None
    load_rate_row: np.ndarray | None = None
    load_unit: str = ""
    grounds: bool = False
    internal: tuple[str, ...] = ()
    stiffness_rows: np.ndarray | None = None


def _polar_moment(owner: str, outer_field: str, outer: Any, inner: Any) -> float:
    """Polar second moment of area of an annulus, π (D⁴ − d⁴) / 32, m⁴, with its inputs checked."""
    do = _si(owner, outer_field, outer, "m", positive=True)
    di = _si(owner, "inner_diameter", inner, "m", nonnegative=True)
    if di >= do:
        raise ModelError(
            f"inner diameter {di:g} m must be smaller than the {outer_field.replace('_', ' ')} {do:g} m",
            element=owner,
            field="inner_diameter",
        )
    return math.pi * (do**4 - di**4) / 32.0


#: Plain numbers taken as SI at once when in range (a design study builds many elements).
_PLAIN_FLOATS = (float, np.float64)


def _si(
    owner: str | None,
    field: str,
    value: Any,
    unit: str,
    *,
    positive: bool = False,
    nonnegative: bool = False,
    **bounds: Any,
) -> float:
    """:func:`mechdyn.units.si_field`, with a plain float already in range accepted at once.

    The accepted range is the same as :func:`mechdyn.checks.check_number`'s for ``positive`` (from the
    smallest positive magnitude of the unit) and ``nonnegative`` (from 0), both up to the magnitude
    limit of the unit; a NaN or an infinity fails the comparison and goes, with every other value
    (quantities, text, out of range) and any other keyword, through ``si_field`` and its message.
    """
    if not bounds and type(value) in _PLAIN_FLOATS:
        low = smallest_positive(unit) if positive else 0.0 if nonnegative else -magnitude_limit(unit)
        if low <= value <= magnitude_limit(unit):
            return float(value)
    return si_field(owner, field, value, unit, positive=positive, nonnegative=nonnegative, **bounds)


def _name(name: Any) -> str:
    if not isinstance(name, str) or not name.strip():
        raise ModelError(f"name {name!r} must be a non-empty text")
    return name.strip()


class Element:
    """Base of the drivetrain elements: a name and the :meth:`blocks` protocol.

    ``VALUES`` names the element's value fields (a number each, in the SI unit given, with the sign
    it must have): the ones :meth:`Drivetrain.with_values` may change without rebuilding the model.
    """

    name: str
    VALUES: ClassVar[dict[str, tuple[str, str]]] = {}

    def blocks(self) -> ElementBlocks:  # pragma: no cover - abstract
        """The element's contribution to the model: its blocks of M, K and C on its own disks, or a
        rigid constraint between them.

        Returns
        -------
        ElementBlocks
            Inertia (kg·m²), stiffness (N·m/rad) and damping (N·m·s/rad) blocks in the element's disk
            angles, and/or a constraint row; the assembler adds them without knowing the element type.
        """
        raise NotImplementedError

    def transmission(self) -> float | None:
        """θ_b / θ_a in a motion that loads this two-disk element not at all; None if not a link.

        Returns
        -------
        float or None
            The signed ratio of the second disk's angle to the first's, dimensionless (1 for a
            shaft, ∓1/n for a mesh of ratio n); None for an element on one disk.
        """
        return None


@dataclass(frozen=True)
class Disk(Element):
    """A rigid disk (one torsional degree of freedom).

    Parameters
    ----------
    name : str
        Unique name, referred to by shafts and meshes.
    inertia : float or quantity
        Polar moment of inertia J, kg·m² (e.g. ``"4.0369e-3 kg*m^2"``): from 1e-18 to 1e10 kg·m².
    """

    name: str
    inertia: float
    VALUES: ClassVar[dict[str, tuple[str, str]]] = {"inertia": ("kg*m^2", "positive")}

    def __post_init__(self) -> None:
        object.__setattr__(self, "name", _name(self.name))
        object.__setattr__(self, "inertia", _si(self.name, "inertia", self.inertia, "kg*m^2", positive=True))

    @classmethod
    def from_geometry(
        cls,
        name: str,
        *,
        thickness: Any,
        outer_diameter: Any,
        inner_diameter: Any = 0.0,
        density: Any,
    ) -> Disk:
        """Disk of a hollow cylinder: J = ρ h π (D_o⁴ − D_i⁴) / 32.

        Parameters
        ----------
        name : str
            The disk's name, unique in its drivetrain.
        thickness, outer_diameter, inner_diameter : float or quantity
            h, D_o, D_i in m.
        density : float or quantity
            ρ in kg/m³.

        Notes
        -----
        Polar moment of inertia of an annular cylinder about its axis (any dynamics text, e.g.
        Meriam & Kraige, *Engineering Mechanics: Dynamics*, Appendix B).
        """
        h = _si(name, "thickness", thickness, "m", positive=True)
        polar = _polar_moment(name, "outer_diameter", outer_diameter, inner_diameter)
        rho = _si(name, "density", density, "kg/m^3", positive=True)
        return cls(name, rho * h * polar)

    def blocks(self) -> ElementBlocks:
        return ElementBlocks((self.name,), mass=np.array([[self.inertia]]))


def _pair(owner: str, disks: Any) -> tuple[str, str]:
    if isinstance(disks, str) or len(disks) != 2:
        raise ModelError(f"{disks!r} must name exactly two disks", element=owner, field="disks")
    a, b = (_name(d) for d in disks)
    if a == b:
        raise ModelError(f"connects disk {a!r} to itself", element=owner, field="disks")
    return a, b


@dataclass(frozen=True)
class Shaft(Element):
    """A torsional spring (and optional damper) between two disks, with its own inertia if given.

    Parameters
    ----------
    name : str
    disks : (str, str)
        The disks at its two ends.
    stiffness : float or quantity
        Torsional stiffness K, N·m/rad: from 1e-9 to 1e14 N·m/rad.
    damping : float or quantity, optional
        Torsional damping c, N·m·s/rad: from 0 to 1e15 N·m·s/rad.
    inertia : float or quantity, optional
        The whole shaft's polar mass moment of inertia about its axis, J_s = ρ J_p l, kg·m² (e.g.
        ``"1.2e-4 kg*m^2"``), from 0 (default: a massless spring, the inertia lumped on the disks by
        the user) to 1e10 kg·m².
    mass_model : {"consistent", "lumped"}
        How J_s enters the mass matrix: ``"consistent"`` (default) the mass matrix of a uniform shaft
        element with linear twist, (J_s/6) [[2, 1], [1, 2]]; ``"lumped"`` J_s/2 on each end.
    elements : int
        Number of equal sub-elements the shaft is divided into, from 1 (default) to 1000. Each
        division adds a degree of freedom inside the shaft, named ``"<name>[1]"``, …,
        ``"<name>[elements − 1]"`` from the first disk on; needs ``inertia`` when above 1.

    Notes
    -----
    A uniform shaft of torsional stiffness K = G J_p / l and inertia J_s = ρ J_p l, divided into N
    elements, is N springs of N K in series with the element mass matrices (J_s/N)/6 [[2, 1], [1, 2]]
    (consistent) or (J_s/N)/2 I (lumped): the two-node rod element with linear shape functions
    (e.g. Petyt, *Introduction to Finite Element Vibration Analysis*, 2nd ed., 2010; Cook, Malkus,
    Plesha & Witt, *Concepts and Applications of Finite Element Analysis*, 4th ed., 2002, on
    consistent and lumped mass matrices). As N grows the natural frequencies converge
    to the continuous shaft's, the consistent ones from above and the lumped ones from below, with
    an error ∝ 1/N². The torque the shaft reports is K (θ_b − θ_a), its mean along the length.
    """

    name: str
    disks: tuple[str, str]
    stiffness: float
    damping: float = 0.0
    inertia: float = 0.0
    mass_model: Literal["consistent", "lumped"] = "consistent"
    elements: int = 1
    VALUES: ClassVar[dict[str, tuple[str, str]]] = {
        "stiffness": ("N*m/rad", "positive"),
        "damping": ("N*m*s/rad", "nonnegative"),
        "inertia": ("kg*m^2", "nonnegative"),
    }

    def __post_init__(self) -> None:
        object.__setattr__(self, "name", _name(self.name))
        object.__setattr__(self, "disks", _pair(self.name, self.disks))
        k = _si(self.name, "stiffness", self.stiffness, "N*m/rad", positive=True)
        object.__setattr__(self, "stiffness", k)
        c = _si(self.name, "damping", self.damping, "N*m*s/rad", nonnegative=True)
        object.__setattr__(self, "damping", c)
        j = _si(self.name, "inertia", self.inertia, "kg*m^2", nonnegative=True)
        object.__setattr__(self, "inertia", j)
        if self.mass_model not in MASS_MODELS:
            raise ModelError(
                f"mass_model {self.mass_model!r} must be 'consistent' or 'lumped'",
                element=self.name,
                field="mass_model",
            )
        count = self.elements
        whole = isinstance(count, int | np.integer) and not isinstance(count, bool)
        if not whole or not 1 <= count <= MAX_SHAFT_ELEMENTS:
            raise ModelError(
                f"elements = {count!r} must be a whole number from 1 to {MAX_SHAFT_ELEMENTS} (the number "
                "of sub-elements the shaft is divided into)",
                element=self.name,
                field="elements",
            )
        object.__setattr__(self, "elements", int(count))
        if count > 1 and j == 0.0:
            raise ModelError(
                f"elements = {count} divides the shaft, but it has no inertia: the nodes inside would "
                "have no mass; give its inertia (or its density with its geometry), or elements = 1",
                element=self.name,
                field="elements",
            )

    @classmethod
    def from_geometry(
        cls,
        name: str,
        disks: tuple[str, str],
        *,
        length: Any,
        diameter: Any,
        shear_modulus: Any,
        inner_diameter: Any = 0.0,
        damping: Any = 0.0,
        density: Any = None,
        mass_model: Literal["consistent", "lumped"] = "consistent",
        elements: int = 1,
    ) -> Shaft:
        """Shaft of circular (solid or hollow) section: K = G π (d⁴ − d_i⁴) / (32 l), J_s = ρ J_p l.

        Parameters
        ----------
        name : str
            The shaft's name, unique in its drivetrain.
        disks : tuple of str
            The two disks it connects.
        length, diameter, inner_diameter : float or quantity
            l, d, d_i in m.
        shear_modulus : float or quantity
            G in Pa.
        damping : float or quantity
            Viscous torsional damping between the disks, N·m·s/rad.
        density : float or quantity, optional
            ρ in kg/m³: the shaft then carries its own inertia J_s = ρ J_p l (kg·m²). None (default):
            a massless spring.
        mass_model : {"consistent", "lumped"}
            How J_s enters the mass matrix (see :class:`Shaft`).
        elements : int
            Number of sub-elements (see :class:`Shaft`).

        Notes
        -----
        Saint-Venant torsion of a circular section, J_p = π (d⁴ − d_i⁴)/32 (e.g. Timoshenko & Goodier,
        *Theory of Elasticity*, torsion of circular shafts); the polar mass moment of a cylinder about
        its axis, ρ J_p l (e.g. Meriam & Kraige, *Engineering Mechanics: Dynamics*, Appendix B).
        """
        length_m = _si(name, "length", length, "m", positive=True)
        polar = _polar_moment(name, "diameter", diameter, inner_diameter)
        g = _si(name, "shear_modulus", shear_modulus, "Pa", positive=True)
        inertia = 0.0
        if density is not None:
            rho = _si(name, "density", density, "kg/m^3", positive=True)
            inertia = rho * polar * length_m
        return cls(
            name,
            disks,
            g * polar / length_m,
            damping,
            inertia=inertia,
            mass_model=mass_model,
            elements=elements,
        )

    @property
    def nodes(self) -> tuple[str, ...]:
        """The shaft's degrees of freedom from its first disk to its second: its ends and, for a divided
        shaft, the nodes inside (``"<name>[i]"``)."""
        inside = tuple(f"{self.name}[{i}]" for i in range(1, self.elements))
        return (self.disks[0], *inside, self.disks[1])

    def blocks(self) -> ElementBlocks:
        unit = np.array([[1.0, -1.0], [-1.0, 1.0]])
        if self.elements == 1 and self.inertia == 0.0:  # a massless spring: the blocks as they always were
            return ElementBlocks(
                self.disks,
                stiffness=self.stiffness * unit,
                damping=self.damping * unit if self.damping else None,
                load_row=self.stiffness * np.array([-1.0, 1.0]),
                load_rate_row=self.damping * np.array([-1.0, 1.0]) if self.damping else None,
                load_unit="N*m",
            )
        n = self.elements
        nodes = self.nodes
        j = self.inertia / n
        element_mass = (
            (j / 6.0) * np.array([[2.0, 1.0], [1.0, 2.0]])
            if self.mass_model == "consistent"
            else (j / 2.0) * np.eye(2)
        )
        # every sub-element is a spring n K (n of them in series make K) and a damper n c
        mass, chain = (np.zeros((n + 1, n + 1)) for _ in range(2))
        for i in range(n):
            mass[i : i + 2, i : i + 2] += element_mass
            chain[i : i + 2, i : i + 2] += unit
        ends = np.zeros(n + 1)
        ends[0], ends[-1] = -1.0, 1.0
        rows = None
        if n > 1:  # one spring per sub-element: K = Σ s sᵀ with s = √(n K) (e_i − e_(i+1))
            rows = np.zeros((n, n + 1))
            root = math.sqrt(n * self.stiffness)
            rows[np.arange(n), np.arange(n)] = root
            rows[np.arange(n), np.arange(1, n + 1)] = -root
        return ElementBlocks(
            nodes,
            mass=mass,
            stiffness=(n * self.stiffness) * chain,
            damping=(n * self.damping) * chain if self.damping else None,
            load_row=self.stiffness * ends,
            load_rate_row=self.damping * ends if self.damping else None,
            load_unit="N*m",
            internal=nodes[1:-1],
            stiffness_rows=rows,
        )

    def transmission(self) -> float:
        return 1.0


def _single(owner: str, disk: Any) -> tuple[str]:
    if not isinstance(disk, str):
        raise ModelError(f"{disk!r} must name one disk", element=owner, field="disk")
    return (_name(disk),)


@dataclass(frozen=True)
class GroundSpring(Element):
    """A torsional spring from a disk to the frame (motor stiffness, brake, clamp).

    Parameters
    ----------
    name : str
    disk : str
    stiffness : float or quantity
        N·m/rad, from 1e-9 to 1e14 N·m/rad.
    """

    name: str
    disk: str
    stiffness: float
    VALUES: ClassVar[dict[str, tuple[str, str]]] = {"stiffness": ("N*m/rad", "positive")}

    def __post_init__(self) -> None:
        object.__setattr__(self, "name", _name(self.name))
        _single(self.name, self.disk)
        k = _si(self.name, "stiffness", self.stiffness, "N*m/rad", positive=True)
        object.__setattr__(self, "stiffness", k)

    def blocks(self) -> ElementBlocks:
        return ElementBlocks(
            (self.disk,),
            stiffness=np.array([[self.stiffness]]),
            load_row=np.array([self.stiffness]),
            load_unit="N*m",
            grounds=True,
        )


@dataclass(frozen=True)
class GroundDamper(Element):
    """A torsional viscous damper from a disk to the frame.

    Parameters
    ----------
    name : str
    disk : str
    damping : float or quantity
        N·m·s/rad, from 1e-12 to 1e15 N·m·s/rad.
    """

    name: str
    disk: str
    damping: float
    VALUES: ClassVar[dict[str, tuple[str, str]]] = {"damping": ("N*m*s/rad", "positive")}

    def __post_init__(self) -> None:
        object.__setattr__(self, "name", _name(self.name))
        _single(self.name, self.disk)
        c = _si(self.name, "damping", self.damping, "N*m*s/rad", positive=True)
        object.__setattr__(self, "damping", c)

    def blocks(self) -> ElementBlocks:
        return ElementBlocks((self.disk,), damping=np.array([[self.damping]]))
