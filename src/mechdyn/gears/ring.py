"""The rim of an internal gear (a ring gear) as a curved beam clamped at its supports.

A thin planetary ring is held in its housing at a few points (bolts, pins, spline teeth): between two
of them its rim bends, twists and stretches under the mesh force, and the teeth move with it. Chen &
Shao, "Mesh stiffness of an internal spur gear pair with ring gear rim deformation", *Mechanism and
Machine Theory* 69 (2013) 1–12, model this by taking the rim between two adjacent supports as a
curved beam clamped at both, loaded by the tooth force, and putting its deflection along the line of
action in series with the teeth. The same is done here, with the curved beam written out by the
energy (flexibility) method:

- the rim is the ring of rectangular section b × s_R between the root circle r_f and r_f + s_R, its
  centroidal radius R = r_f + s_R/2, I = b s_R³/12, A = b s_R; N_s supports evenly spaced, each
  span an arc of Φ = 2π/N_s clamped (no displacement, no rotation) at both ends;
- the strain energy of a thin curved beam, U = ∫ [M²/(2EI) + N²/(2EA) + κ V²/(2GA)] R dθ (κ = 1.2,
  G = E/(2(1 + ν)); bending, hoop stretching and shear, as in Young & Budynas, *Roark's Formulas for
  Stress and Strain*, 7th ed., 2002, ch. 9, circular rings and arches); the three reactions at one
  support are the redundants (Castigliano: that support does not move), and the flexibility at the
  load point in (radial, tangential, rotation) is C = f_PP − f_PR f_RR⁻¹ f_RP, the integrals by
  Gauss–Legendre quadrature on each side of the load;
- the tooth stands rigidly on the rim: the unit normal force along the line of action, at the load
  angle φ to the perpendicular of the tooth's centre line (α_c + γ_c of an internal gear), moved to the
  rim's centroid under the tooth, is sin φ radially outward, cos φ tangentially and the moment
  r_b − R cos φ (its moment about the gear's axis is r_b, the line of action being tangent to the base
  circle); the rim moves the contact along the line of action by c = gᵀ C g per unit force,
  g = (sin φ, cos φ, r_b − R cos φ).

The tests check the curved beam against closed forms: a thin ring clamped at one point and loaded
radially at the opposite one deflects (π/4 − 2/π) F R³/(EI) (the classic ring under two opposite
loads, e.g. Roark's Table 9.2, case 1), and a shallow span is the clamped straight Timoshenko beam
(F L³/(192 EI) + κ F L/(4 GA), F L/(4 EA) and, without shear, M L/(16 EI) at mid-span).

What is left out: the other planets' loads on the same rim, the supports' own flexibility, the rim's
twist by a helical mesh's axial force, and the local yielding of the ring body under the tooth (the
ring's tooth stands on the rim rigidly, as without a rim). Thin-ring theory holds for s_R well below
R; for a rim as thick as the ring's radius the beam's compliance no longer vanishes (the geometry
scales with s_R), a stand-in for the body's own yielding that the rigid ring leaves out.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from mechdyn.checks import check_count
from mechdyn.errors import ModelError
from mechdyn.gears.tooth import SHEAR_COEFFICIENT
from mechdyn.units import check_poisson_ratio, show, si_field

__all__ = ["RIM_POSITIONS", "RingRim", "ring_rim_supports"]

RIM_POSITIONS = 32
"""Mesh positions along a span between two supports over which the rim's effect is averaged (Gauss–
Legendre nodes: the series stiffness is smooth in the position)."""

_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(48)  # along the beam, each side of the load
_SPAN_NODES, _SPAN_WEIGHTS = np.polynomial.legendre.leggauss(RIM_POSITIONS)


class RimGear(Protocol):
    """What :meth:`RingRim.from_gear` reads of an internal gear (:class:`mechdyn.gears.SpurGear`).

    Attributes
    ----------
    name : str
        The gear, for messages.
    root_radius : float
        r_f, m.
    face_width : float
        b, m.
    rim_thickness : float or None
        s_R, the rim's radial thickness outside the root circle, m.
    rim_supports : int or None
        N_s, the number of evenly spaced supports.
    youngs_modulus : float
        E, Pa.
    poisson_ratio : float
        ν, dimensionless.
    """

    @property
    def name(self) -> str: ...
    @property
    def root_radius(self) -> float: ...
    @property
    def face_width(self) -> float: ...
    @property
    def rim_thickness(self) -> float | None: ...
    @property
    def rim_supports(self) -> int | None: ...
    @property
    def youngs_modulus(self) -> float: ...
    @property
    def poisson_ratio(self) -> float: ...


@dataclass(frozen=True)
class RingRim:
    """The rim of a ring gear between two of its evenly spaced supports: a curved beam clamped at both.

    Parameters
    ----------
    radius : float or quantity
        R, the rim's centroidal radius, m (r_f + s_R/2 of a ring gear), from 1e-9 to 1e3 m.
    thickness : float or quantity
        s_R, the rim's radial thickness, m, positive and below 2R.
    face_width : float or quantity
        b, the rim's axial width, m, from 1e-9 to 1e3 m.
    supports : int
        N_s, the number of evenly spaced supports, a whole number from 1 to 10⁶; each span is the arc
        2π/N_s.
    youngs_modulus : float or quantity
        E, Pa, from 1e-3 to 1e13 Pa.
    poisson_ratio : float
        ν, in (−1, 0.5), for G = E/(2(1 + ν)).

    Raises
    ------
    mechdyn.errors.ModelError
        For a value that is not finite or out of its range, naming the field.

    Notes
    -----
    Chen & Shao, *Mech. Mach. Theory* 69 (2013) 1–12 (the rim between supports as a clamped curved
    beam in series with the teeth); the curved beam by the energy method of Young & Budynas, *Roark's
    Formulas for Stress and Strain*, 7th ed. (2002), ch. 9 (see the module's notes). Built from a gear by
    :meth:`mechdyn.gears.SpurGear.ring_rim`.
    """

    radius: float
    thickness: float
    face_width: float
    supports: int
    youngs_modulus: float
    poisson_ratio: float

    def __post_init__(self) -> None:
        n = "ring rim"
        for f, unit in (("radius", "m"), ("thickness", "m"), ("face_width", "m"), ("youngs_modulus", "Pa")):
            object.__setattr__(self, f, si_field(n, f, getattr(self, f), unit, positive=True))
        object.__setattr__(self, "poisson_ratio", check_poisson_ratio(n, "poisson_ratio", self.poisson_ratio))
        object.__setattr__(self, "supports", check_count(n, "supports", self.supports, low=1, high=10**6))
        if not self.thickness < 2.0 * self.radius:
            raise ModelError(
                f"thickness {self.thickness:g} m must be below twice the centroidal radius {self.radius:g} m "
                "(the rim's inner radius R − s_R/2 must be positive)",
                element=n,
                field="thickness",
            )

    @classmethod
    def from_gear(cls, gear: RimGear) -> RingRim:
        """The rim of an internal gear with ``rim_thickness`` s_R and ``rim_supports``: centroidal
        radius r_f + s_R/2, section face width × s_R, the gear's E and ν.

        Parameters
        ----------
        gear : SpurGear
            An internal gear with both (or anything with what :class:`RimGear` names).
        """
        if gear.rim_thickness is None or gear.rim_supports is None:
            raise ModelError("the rim's curved beam needs rim_thickness and rim_supports", element=gear.name)
        return cls(
            radius=gear.root_radius + 0.5 * gear.rim_thickness,
            thickness=gear.rim_thickness,
            face_width=gear.face_width,
            supports=gear.rim_supports,
            youngs_modulus=gear.youngs_modulus,
            poisson_ratio=gear.poisson_ratio,
        )

    @property
    def span(self) -> float:
        """Φ = 2π/N_s, the angle between two supports, rad."""
        return 2.0 * math.pi / self.supports

    @property
    def _rigidities(self) -> tuple[float, float, float]:
        """EI (N·m²), EA (N) and GA/κ (N) of the rim's section."""
        b, h, e = self.face_width, self.thickness, self.youngs_modulus
        shear_modulus = e / (2.0 * (1.0 + self.poisson_ratio))
        return e * b * h**3 / 12.0, e * b * h, shear_modulus * b * h / SHEAR_COEFFICIENT

    def flexibility(self, position: np.ndarray) -> np.ndarray:
        """The rim's flexibility at points of the span, in (radial outward, tangential, rotation).

        Parameters
        ----------
        position : array_like
            θ of each point from one support, rad, in [0, Φ].

        Returns
        -------
        ndarray, shape (..., 3, 3)
            Displacements (m, m, rad) per unit load (N, N, N·m) at the point: symmetric and positive
            semi-definite, zero at the supports.
        """
        a = np.asarray(position, dtype=float)
        shape = a.shape
        a = a.reshape(-1)
        ei, ea, kga = self._rigidities
        span, r = self.span, self.radius

        def nodes(lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            half = 0.5 * (hi - lo)
            return lo[:, None] + half[:, None] * (_NODES + 1.0), half[:, None] * _WEIGHTS

        def resultants(s: np.ndarray, at: np.ndarray | float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
            # moment, normal and shear force at sections s, from unit Fx, Fy, M applied at angle ``at``
            # on the free side (global axes; the clamp at θ = Φ holds the rest)
            sin, cos = np.sin(s), np.cos(s)
            moment = np.stack([r * (sin - np.sin(at)), r * (np.cos(at) - cos), np.ones_like(s)])
            normal = np.stack([-sin, cos, np.zeros_like(s)])
            shear = np.stack([cos, sin, np.zeros_like(s)])
            return moment, normal, shear

        def energy(x: tuple, y: tuple, w: np.ndarray) -> np.ndarray:
            (mx, nx, vx), (my, ny, vy) = x, y
            terms = mx[:, None] * my[None, :] / ei + nx[:, None] * ny[None, :] / ea
            terms = terms + vx[:, None] * vy[None, :] / kga
            return np.moveaxis(np.sum(terms * w * r, axis=-1), (0, 1), (-2, -1))

        s1, w1 = nodes(np.zeros_like(a), a)  # from the released support to the load: redundants only
        s2, w2 = nodes(a, np.full_like(a, span))  # from the load to the clamped support: both
        redundant1, redundant2 = resultants(s1, 0.0), resultants(s2, 0.0)
        load = resultants(s2, a[:, None])
        f_rr = energy(redundant1, redundant1, w1) + energy(redundant2, redundant2, w2)
        f_rp = energy(redundant2, load, w2)
        f_pp = energy(load, load, w2)
        c = f_pp - np.swapaxes(f_rp, -1, -2) @ np.linalg.solve(f_rr, f_rp)
        # global (x, y, rotation) to the point's (radial, tangential, rotation)
        cos, sin = np.cos(a), np.sin(a)
        t = np.zeros((len(a), 3, 3))
        t[:, 0, 0], t[:, 0, 1], t[:, 1, 0], t[:, 1, 1], t[:, 2, 2] = cos, sin, -sin, cos, 1.0
        local = t @ c @ np.swapaxes(t, -1, -2)
        return 0.5 * (local + np.swapaxes(local, -1, -2)).reshape((*shape, 3, 3))

    def compliance(self, position: np.ndarray, load_angle: float, base_radius: float) -> np.ndarray:
        """Deflection of the contact along the line of action per unit normal force, m/N, from the rim.

        c = gᵀ C g, g = (sin φ, cos φ, r_b − R cos φ): the unit force along the line of action moved to
        the rim's centroid under the tooth (see the module's notes).

        Parameters
        ----------
        position : array_like
            θ of the loaded tooth from one support, rad, in [0, Φ].
        load_angle : float
            φ, rad: the line of action's angle to the perpendicular of the tooth's centre line.
        base_radius : float
            r_b of the ring, m (the line of action is tangent to its base circle).

        Returns
        -------
        ndarray
            c at each position, m/N.
        """
        g = np.array(
            [math.sin(load_angle), math.cos(load_angle), base_radius - self.radius * math.cos(load_angle)]
        )
        return np.einsum("i,...ij,j->...", g, self.flexibility(position), g)

    def positions(self) -> tuple[np.ndarray, np.ndarray]:
        """Gauss–Legendre positions over a span, rad, and their weights (summing to 1) for a mean."""
        return 0.5 * self.span * (_SPAN_NODES + 1.0), 0.5 * _SPAN_WEIGHTS

    def series_stiffness(self, stiffness: np.ndarray, load_angle: float, base_radius: float) -> np.ndarray:
        """A mesh stiffness in series with the rim, averaged over the mesh's positions along a span.

        k(x) = (1/Φ) ∫₀^Φ dθ / (1/k_teeth(x) + c(θ)): the teeth in contact (one or more, a base pitch
        apart, close against the span) load the rim at one place, which moves along the span as the
        carrier turns, evenly in time.

        Parameters
        ----------
        stiffness : ndarray
            The teeth's mesh stiffness over a mesh cycle, N/m.
        load_angle : float
            φ at the ring's working pitch circle, rad.
        base_radius : float
            The ring's base radius, m.

        Returns
        -------
        ndarray
            The mesh stiffness with the rim, N/m, at the same positions of the cycle.
        """
        theta, weight = self.positions()
        c = self.compliance(theta, load_angle, base_radius)
        k = np.asarray(stiffness, dtype=float)
        return np.sum(weight / (1.0 / k[:, None] + c[None, :]), axis=1)


def ring_rim_supports(name: str, teeth: int, rim_thickness: float | None, rim_supports: object) -> int | None:
    """An internal gear's ``rim_supports``, checked: given with ``rim_thickness`` (a flexible rim) or
    neither (a rigid rim), a whole number from 1 to the gear's teeth.

    Parameters
    ----------
    name : str
        The gear, for messages.
    teeth : int
        The gear's number of teeth, the most supports accepted.
    rim_thickness : float or None
        s_R, m, already checked positive.
    rim_supports : int or None
        N_s as given.

    Returns
    -------
    int or None
        N_s.

    Raises
    ------
    mechdyn.errors.ModelError
        Naming the field, the value and what to give.
    """
    supports = None
    if rim_supports is not None:
        supports = check_count(name, "rim_supports", rim_supports, low=1, high=teeth, what="supports")
    if rim_thickness is not None and supports is None:
        raise ModelError(
            f"rim thickness {show(rim_thickness, 'm', 'mm', '.4g')} makes the ring's rim a curved beam "
            "between its supports: give rim_supports, the number of evenly spaced bolts, pins or spline "
            "teeth that hold it (or leave rim_thickness out for a rigid rim)",
            element=name,
            field="rim_supports",
        )
    if supports is not None and rim_thickness is None:
        raise ModelError(
            f"rim_supports = {supports} needs the rim's thickness: give rim_thickness (the rim's radial "
            "thickness outside the root circle, e.g. '6 mm'), or leave rim_supports out for a rigid rim",
            element=name,
            field="rim_thickness",
        )
    return supports
