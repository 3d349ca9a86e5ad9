"""Involute spur and helical gears, external and internal, from ordinary gear data, their generated
teeth and truncated-triangle teeth.

Standard involute geometry (e.g. ISO 21771:2007; Niemann & Winter, *Maschinenelemente* II):
pitch radius r = m z/2, base radius r_b = r cos α, tip radius r_a = r + m (h_a* + x), root radius
r_f = r − m (h_f* − x), tooth thickness on the pitch circle s = m (π/2 + 2 x tan α), and at any radius
r_y ≥ r_b the arc thickness s_y = 2 r_y (s/(2 r) + inv α − inv α_y), inv α = tan α − α,
cos α_y = r_b / r_y.

The generated tooth (the default model of a gear pair): from the root circle, the fillet that the
basic rack's rounded tip (ρ_fP) cuts as it rolls, then the involute to the tip (ISO 6336-3's E, G, H
construction of the same fillet gives its root chord s_Fn, which the tests compare). The truncated
triangle of a gear tooth (heights from the root circle): the root section at the start of the
involute, max(r_b, r_f), the tip at r_a, with the chordal thicknesses there, and below the root
section a segment of the thickness there down to the root circle. Both stand on the foundation of
Sainsot et al. (2004) at the root circle. The load angle at a contact radius r_c is α_c − γ_c
(pressure angle there minus the half tooth angle γ_c = s_c / (2 r_c)), the angle between the line of
action and the perpendicular to the tooth's centre line (ISO 6336-3 uses the same construction for
α_Fen).

Helical gears (helix angle β): the module and pressure angle are the normal ones (m_n, α_n) and every
radius, thickness and pitch here is in the transverse section (ISO 21771:2007, 4.2–4.3): transverse
module m_t = m_n / cos β, tan α_t = tan α_n / cos β, r = m_t z/2, r_b = r cos α_t, addendum, dedendum
and profile shift in normal modules (r_a = r + m_n (h_a* + x)), s_t = m_t π/2 + 2 x m_n tan α_t,
base helix angle tan β_b = tan β cos α_t. The transverse section is the spur gear that the transverse
section of the basic rack generates; the rack's tip rounding, an ellipse in that section, is taken as
a circle of the normal radius ρ_fP (the fillet is approximate for β ≠ 0; the involute is exact).

Internal gears (a ring with its teeth pointing inward): ISO 21771's formulas with z < 0, written here
with a positive z: r_a = r − m_n (h_a* + x), r_f = r + m_n (h_f* − x), s = m (π/2 + 2 x tan α), and the
tooth's arc thickness at r_y, s_y = 2 r_y (s/(2 r) − inv α + inv α_y): the tooth is the space of an
external gear of the same data with the shift −x, and grows toward its root circle (outside). Positive
x moves the profile toward the gear's axis (ISO 21771, 5.2). The load angle at a contact radius is
α_c + γ_c (the radial component still presses the tooth toward its root, now outward); see
:meth:`SpurGear.load_angle`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from mechdyn.checks import check_number, magnitude_limit
from mechdyn.errors import ModelError
from mechdyn.gears.profile import ProfileTooth
from mechdyn.gears.ring import RingRim, ring_rim_supports
from mechdyn.gears.tooth import TruncatedTooth
from mechdyn.units import check_poisson_ratio, show
from mechdyn.units import si_field as _q

__all__ = [
    "MAX_HELIX_DEG",
    "MAX_RACK_FACTOR",
    "MAX_TEETH",
    "VALIDATED_HELIX_DEG",
    "SpurGear",
    "inverse_involute",
    "involute",
]

MAX_TEETH = 10_000
"""The most teeth a gear may have (as a drivetrain mesh's :data:`mechdyn.drivetrain.elements.MAX_TEETH`)."""
MAX_RACK_FACTOR = 3.0
"""The largest addendum, dedendum, fillet radius and profile shift (in magnitude), in modules: ISO 53's
basic racks have 1, 1.25 to 1.4, 0.38 and shifts within about ±1."""
MAX_HELIX_DEG = 45.0
"""The largest helix angle accepted, degrees (industrial helical gears stay below about 35°)."""
VALIDATED_HELIX_DEG = 30.0
"""The largest helix angle at which the sliced helical mesh has been compared with ISO 6336-1, degrees:
from 0° to 30° its mean stays 1.11–1.15 × c_γα (generated tooth, 20/40; 1.11 for the spur pair).
Above it (to :data:`MAX_HELIX_DEG`) a pair is computed and its result states its ratio to ISO
(docs/capabilities/gears.md, "Helical and internal gears")."""


def involute(alpha: float) -> float:
    """inv α = tan α − α."""
    return math.tan(alpha) - alpha


def inverse_involute(value: float) -> float:
    """α with inv α = value (Newton's method; value ≥ 0)."""
    alpha = (3.0 * value) ** (1.0 / 3.0) if value > 0 else 0.0  # inv α ≈ α³/3 for small α
    for _ in range(50):
        f = involute(alpha) - value
        step = f / math.tan(alpha) ** 2 if alpha > 0 else 0.0
        alpha -= step
        if abs(step) < 1e-15:
            break
    return alpha


@dataclass(frozen=True)
class SpurGear:
    """An involute cylindrical gear: spur or helical, external or internal (a ring gear).

    Parameters
    ----------
    teeth : int
        z, a whole number from 5 to :data:`MAX_TEETH`.
    module : float or quantity
        m (the normal module m_n of a helical gear), m (e.g. ``"2 mm"``), from 1e-9 to 1e3 m.
    face_width : float or quantity
        b, m, from 1e-9 to 1e3 m.
    pressure_angle : float or quantity
        α of the basic rack (α_n, in the normal section, of a helical gear), rad (e.g. ``"20 deg"``),
        from 10° to 35°.
    profile_shift : float
        x (addendum modification coefficient), dimensionless, within ±:data:`MAX_RACK_FACTOR`.
    addendum, dedendum : float
        h_a* and h_f* of the basic rack, in modules (1 and 1.25 by default), in (0, 3].
    youngs_modulus : float or quantity
        E, Pa (steel 206 GPa by default, the ISO 6336 reference), from 1e-3 to 1e13 Pa.
    poisson_ratio : float
        ν, dimensionless, in (−1, 0.5).
    bore_diameter : float or quantity, optional
        Diameter of the bore, m, for the elastic tooth foundation (Sainsot et al. 2004). The body of
        a gear yields under its teeth whether or not a bore is given: without one the foundation
        takes a bore of half the root diameter (a hub on its shaft), and :attr:`guesses` says so.
    rim_thickness, web_width : float or quantity, optional
        s_R and b_s of a rim-and-web gear blank, m (ISO 6336-1 gear blank factor C_R); None for a
        solid blank. An internal gear may take ``rim_thickness`` alone: s_R, its rim's radial
        thickness outside the root circle, m (from 1e-9 to 1e3 m), with ``rim_supports``: the rim then
        yields as a curved beam between its supports (:meth:`ring_rim`; Chen & Shao 2013), in series
        with the teeth over the mesh cycle. Without it the ring's rim is rigid.
    name : str
    fillet_radius : float
        ρ_fP* of the basic rack's tip rounding, in modules (0.38 by default, ISO 53 profile A): the
        cutter's rounded tip generates the tooth's root fillet (:meth:`generated_thickness_array`);
        from 0 to the full rounding of the rack's tip.
    helix_angle : float or quantity
        β at the reference circle, rad (e.g. ``"15 deg"``), from 0 to 45° (0: a spur gear); above
        :data:`VALIDATED_HELIX_DEG` (30°) a pair's result states its ratio to ISO 6336-1. The hand
        of the helix is not modelled: a pair takes equal β on both gears.
    internal : bool
        An internal gear (a ring gear, teeth pointing inward; see the module's notes): no bore (its
        teeth stand on its rim: rigid, or a curved beam with ``rim_thickness`` and ``rim_supports``),
        no fillet generated (the involute runs to the root circle).
    rim_supports : int, optional
        N_s, the number of evenly spaced supports (bolts, pins, spline teeth) that hold an internal
        gear's rim in its housing, a whole number from 1 to the gear's number of teeth; given with
        ``rim_thickness``, and only for an internal gear.

    Raises
    ------
    mechdyn.errors.ModelError
        For a number that is not finite or out of its range, naming the gear, the field and the value.
    """

    teeth: int
    module: float
    face_width: float
    pressure_angle: float = math.radians(20.0)
    profile_shift: float = 0.0
    addendum: float = 1.0
    dedendum: float = 1.25
    youngs_modulus: float = 206e9
    poisson_ratio: float = 0.3
    bore_diameter: float | None = None
    name: str = "gear"
    rim_thickness: float | None = None
    web_width: float | None = None
    fillet_radius: float = 0.38
    helix_angle: float = 0.0
    internal: bool = False
    rim_supports: int | None = None

    def __post_init__(self) -> None:
        n = self.name
        beta = _q(n, "helix_angle", self.helix_angle, "rad", nonnegative=True)
        if not beta <= math.radians(MAX_HELIX_DEG):
            raise ModelError(
                f"helix angle {math.degrees(beta):g}° must lie between 0° and {MAX_HELIX_DEG:g}°",
                element=n,
                field="helix_angle",
            )
        object.__setattr__(self, "helix_angle", beta)
        if not isinstance(self.internal, bool | np.bool_):
            raise ModelError(
                f"internal = {self.internal!r} must be true or false", element=n, field="internal"
            )
        object.__setattr__(self, "internal", bool(self.internal))
        if self.internal and self.bore_diameter is not None:
            raise ModelError(
                "an internal gear has no bore: its teeth stand on a rigid ring here; remove bore_diameter",
                element=n,
                field="bore_diameter",
            )
        if (
            isinstance(self.teeth, bool)
            or not isinstance(self.teeth, int | np.integer)
            or not 5 <= self.teeth <= MAX_TEETH
        ):
            raise ModelError(
                f"{self.teeth!r} must be a whole number between 5 and {MAX_TEETH}", element=n, field="teeth"
            )
        object.__setattr__(self, "teeth", int(self.teeth))
        for f, unit in (("module", "m"), ("face_width", "m"), ("youngs_modulus", "Pa")):
            object.__setattr__(self, f, _q(n, f, getattr(self, f), unit, positive=True))
        # the basic rack in modules: ISO 53 and its variants stay well inside these
        for f, low, high in (
            ("profile_shift", -MAX_RACK_FACTOR, MAX_RACK_FACTOR),
            ("addendum", 0.0, MAX_RACK_FACTOR),
            ("dedendum", 0.0, MAX_RACK_FACTOR),
        ):
            opened = f != "profile_shift"
            v = _q(
                n,
                f,
                getattr(self, f),
                "",
                low=low,
                high=high,
                low_open=opened,
                what=f"{f.replace('_', ' ')} (in modules)",
            )
            object.__setattr__(self, f, v)
        object.__setattr__(self, "poisson_ratio", check_poisson_ratio(n, "poisson_ratio", self.poisson_ratio))
        object.__setattr__(
            self,
            "fillet_radius",
            _q(n, "fillet_radius", self.fillet_radius, "", nonnegative=True, high=MAX_RACK_FACTOR),
        )
        alpha = _q(n, "pressure_angle", self.pressure_angle, "rad", positive=True)
        object.__setattr__(self, "pressure_angle", alpha)
        if not math.radians(10) <= self.pressure_angle <= math.radians(35):
            raise ModelError(
                f"{math.degrees(self.pressure_angle):g}° must lie between 10° and 35°",
                element=n,
                field="pressure_angle",
            )
        # the gear these give must itself be a machine part: its tip circle within the lengths accepted
        largest = magnitude_limit("m")
        if self.tip_radius > largest:
            raise ModelError(
                f"{self.module:g} m with {self.teeth} teeth gives a tip radius of {self.tip_radius:g} m, "
                f"beyond any machine this package models ({largest:g} m); give a smaller module (is its "
                "unit right?)",
                element=n,
                field="module",
            )
        if self.bore_diameter is not None:
            object.__setattr__(
                self, "bore_diameter", _q(n, "bore_diameter", self.bore_diameter, "m", positive=True)
            )
            if not 0 < self.bore_diameter < 2 * self.root_radius:
                raise ModelError(
                    f"bore diameter {self.bore_diameter:g} m must be positive and below the root diameter "
                    f"{2 * self.root_radius:g} m",
                    element=n,
                    field="bore_diameter",
                )
        for f in ("rim_thickness", "web_width"):
            if getattr(self, f) is not None:
                object.__setattr__(self, f, _q(n, f, getattr(self, f), "m", positive=True))
        if self.root_radius <= 0:
            raise ModelError(
                f"the root circle's radius {self.root_radius:g} m is not positive: {self.teeth} teeth cannot "
                f"carry a dedendum of {self.dedendum:g} modules with a profile shift of "
                f"{self.profile_shift:g}",
                element=n,
                field="dedendum",
            )
        if self.tip_radius < self.base_radius:
            raise ModelError(
                f"the tip circle ({self.tip_radius:g} m) lies inside the base circle "
                f"({self.base_radius:g} m): "
                f"no involute flank with an addendum of {self.addendum:g} and a profile shift of "
                f"{self.profile_shift:g} modules",
                element=n,
                field="addendum",
            )
        if self.internal:
            supports = ring_rim_supports(n, self.teeth, self.rim_thickness, self.rim_supports)
            object.__setattr__(self, "rim_supports", supports)
        elif self.rim_supports is not None:
            raise ModelError(
                f"rim_supports = {self.rim_supports!r} is for an internal gear (a ring held at its "
                "supports); an external gear's rim-and-web blank takes rim_thickness and web_width: remove "
                "rim_supports",
                element=n,
                field="rim_supports",
            )
        if (self.rim_thickness is None) != (self.web_width is None) and not (
            self.internal and self.web_width is None
        ):
            raise ModelError(
                "give both rim_thickness and web_width of a rim-and-web blank, or neither (solid)",
                element=n,
                field="rim_thickness",
            )
        a = self.pressure_angle
        rho_max = (math.pi / 4 - self.dedendum * math.tan(a)) * math.cos(a) / (1 - math.sin(a))
        if not 0 <= self.fillet_radius <= rho_max:
            raise ModelError(
                f"fillet radius {self.fillet_radius:g} modules must lie between 0 and {rho_max:.4g} (the "
                "full rounding of the basic rack's tip for this dedendum and pressure angle)",
                element=n,
                field="fillet_radius",
            )
        if self.thickness(self.tip_radius) <= 0:
            raise ModelError(
                "the teeth are pointed (no thickness at the tip circle); "
                "reduce the profile shift or addendum",
                element=n,
                field="profile_shift",
            )

    def ring_rim(self) -> RingRim | None:
        """The rim of an internal gear as a curved beam between its supports, or None.

        None for a rigid rim (no ``rim_thickness``) or an external gear. The model is Chen & Shao's,
        *Mech. Mach. Theory* 69 (2013) 1–12 (:class:`~mechdyn.gears.ring.RingRim`).

        Returns
        -------
        RingRim or None
        """
        return RingRim.from_gear(self) if self.internal and self.rim_supports is not None else None

    # -- transverse section ---------------------------------------------------------------------
    @property
    def transverse_module(self) -> float:
        """m_t = m_n / cos β, m (the module of a spur gear)."""
        return self.module / math.cos(self.helix_angle) if self.helix_angle else self.module

    @property
    def transverse_pressure_angle(self) -> float:
        """α_t, tan α_t = tan α_n / cos β, rad (ISO 21771:2007, 4.3; α of a spur gear)."""
        if not self.helix_angle:
            return self.pressure_angle
        return math.atan(math.tan(self.pressure_angle) / math.cos(self.helix_angle))

    @property
    def base_helix_angle(self) -> float:
        """β_b, tan β_b = tan β cos α_t, rad (ISO 21771:2007, 4.4)."""
        return math.atan(math.tan(self.helix_angle) * math.cos(self.transverse_pressure_angle))

    @property
    def virtual_teeth(self) -> float:
        """z_n = z / (cos²β_b cos β), the virtual number of teeth of the normal section (ISO 21771,
        4.7; ISO 6336-3 uses it in place of z for helical gears)."""
        if not self.helix_angle:
            return float(self.teeth)
        return self.teeth / (math.cos(self.base_helix_angle) ** 2 * math.cos(self.helix_angle))

    # -- radii, m --------------------------------------------------------------------------------
    @property
    def pitch_radius(self) -> float:
        """r = m_t z / 2, m."""
        return self.transverse_module * self.teeth / 2.0

    @property
    def base_radius(self) -> float:
        """r_b = r cos α_t, m."""
        return self.pitch_radius * math.cos(self.transverse_pressure_angle)

    @property
    def tip_radius(self) -> float:
        """r_a = r + m_n (h_a* + x), m; inside the pitch circle for an internal gear, r − m_n (h_a* + x)."""
        if self.internal:
            return self.pitch_radius - self.module * (self.addendum + self.profile_shift)
        return self.pitch_radius + self.module * (self.addendum + self.profile_shift)

    @property
    def root_radius(self) -> float:
        """r_f = r − m_n (h_f* − x), m; outside the pitch circle for an internal gear, r + m_n (h_f* − x)."""
        if self.internal:
            return self.pitch_radius + self.module * (self.dedendum - self.profile_shift)
        return self.pitch_radius - self.module * (self.dedendum - self.profile_shift)

    @property
    def base_pitch(self) -> float:
        """Transverse base pitch p_bt = π m_t cos α_t, m (π m cos α for a spur gear)."""
        return math.pi * self.transverse_module * math.cos(self.transverse_pressure_angle)

    @property
    def form_radius(self) -> float:
        """Where the truncated-triangle root section sits: the start of the involute, max(r_b, r_f); for
        an internal gear the root circle (the involute runs to it here)."""
        if self.internal:
            return self.root_radius
        return max(self.base_radius, self.root_radius)

    @property
    def _flank(self) -> tuple[float, float]:
        """Smallest and largest radius of the involute flank, m."""
        if self.internal:
            return self.tip_radius, self.root_radius
        return self.base_radius, self.tip_radius

    @property
    def _pitch_thickness(self) -> float:
        """Transverse arc tooth thickness on the pitch circle, s_t = m_t π/2 + 2 x m_n tan α_t, m."""
        if not self.helix_angle:
            return self.module * (math.pi / 2.0 + 2.0 * self.profile_shift * math.tan(self.pressure_angle))
        return self.transverse_module * math.pi / 2.0 + 2.0 * self.profile_shift * self.module * math.tan(
            self.transverse_pressure_angle
        )

    def load_height(self, radius: float) -> float:
        """Height of a point of the flank above the root circle, m: r − r_f (r_f − r for an internal gear).

        Parameters
        ----------
        radius : float
            Radius on the flank, m.
        """
        return self.root_radius - radius if self.internal else radius - self.root_radius

    # -- thickness ---------------------------------------------------------------------------------
    def thickness(self, radius: float) -> float:
        """Arc tooth thickness at a radius on the involute (transverse section), m.

        s_y = 2 r_y (s/(2 r) + inv α − inv α_y), with s/(2 r) − inv α + inv α_y for an internal gear.

        Parameters
        ----------
        radius : float
            Radius on the involute, m (r_b ≤ r ≤ r_a; r_a ≤ r ≤ r_f for an internal gear).

        Raises
        ------
        mechdyn.errors.ModelError
            For a radius off the involute (inside the base circle, beyond the tip circle, not finite).
        """
        radius = check_number(self.name, "radius", radius, "m", positive=True)
        low, high = self._flank
        if not low * (1 - 1e-12) <= radius <= high * (1 + 1e-9):
            raise ModelError(
                f"radius {radius:g} m is off the involute, which runs from {low:g} m to {high:g} m",
                element=self.name,
                field="radius",
            )
        s = self._pitch_thickness
        a = self.transverse_pressure_angle
        alpha_y = math.acos(min(1.0, self.base_radius / radius))
        if self.internal:
            return 2.0 * radius * (s / (2.0 * self.pitch_radius) - involute(a) + involute(alpha_y))
        return 2.0 * radius * (s / (2.0 * self.pitch_radius) + involute(a) - involute(alpha_y))

    def chordal_thickness(self, radius: float) -> float:
        """Chord across the tooth at a radius, m.

        Parameters
        ----------
        radius : float
            Radius on the involute, m (r_b ≤ r ≤ r_a).
        """
        return 2.0 * radius * math.sin(self.thickness(radius) / (2.0 * radius))

    def load_angle(self, radius: float) -> float:
        """Angle between the line of action and the perpendicular to the tooth centre line, rad:
        α_c − γ_c (α_c + γ_c for an internal gear), γ_c = s_c/(2 r_c), in the transverse section.

        Parameters
        ----------
        radius : float
            Radius on the involute, m (r_b ≤ r ≤ r_a).
        """
        alpha_c = math.acos(min(1.0, self.base_radius / radius))
        if self.internal:  # the involute unwinds the other way (module notes)
            return alpha_c + self.thickness(radius) / (2.0 * radius)
        return alpha_c - self.thickness(radius) / (2.0 * radius)

    def tooth_compliances(self, load_radius: Any) -> dict[str, float]:
        """Compliance terms of one truncated-triangle tooth loaded at a radius on its flank, m/N.

        Parameters
        ----------
        load_radius : float or quantity
            Radius of the load point, m, between the start of the involute and the tip circle.
        """
        r = _q(self.name, "load_radius", load_radius, "m")
        low, high = (
            (self.tip_radius, self.root_radius) if self.internal else (self.form_radius, self.tip_radius)
        )
        if not (low * (1 - 1e-12) <= r < high if self.internal else low < r <= high * (1 + 1e-12)):
            raise ModelError(
                f"load radius {show(r, 'm', 'mm')} is off the flank ({show(low, 'm', 'mm')} to "
                f"{show(high, 'm', 'mm')})",
                element=self.name,
                field="load_radius",
            )
        return self.tooth().compliances(self.load_height(r), self.load_angle(r))

    def chordal_thickness_array(self, radius: np.ndarray) -> np.ndarray:
        """Chordal thickness at radii on the involute (vectorised :meth:`chordal_thickness`), m.

        Parameters
        ----------
        radius : ndarray
            Radii on the involute, m.
        """
        r = np.asarray(radius, dtype=float)
        return 2.0 * r * np.sin(self.arc_thickness_array(r) / (2.0 * r))

    # -- the generated tooth: the fillet cut by the rack's rounded tip, then the involute ----------
    @cached_property
    def _fillet(self) -> tuple[np.ndarray, np.ndarray]:
        """Radius and space half-angle along the fillet, from the root circle to the involute.

        The basic rack (reference line at r + x m, tip at the root circle) rolls on the pitch circle;
        the centre of its tip rounding (radius ρ = ρ_fP* m, tangent to the tip line and to the flank)
        sits at v_c = r_f + ρ and u_c = π m/4 − (h_fP − ρ) tan α − ρ/cos α from the space's centre
        line (ISO 6336-3's E). At rack position u = −r φ the rounding cuts the gear where its normal
        passes through the pitch point (the envelope condition); rotating that point back by φ gives
        the fillet in the gear's frame (a trochoid's offset; e.g. Litvin & Fuentes, *Gear Geometry
        and Applied Theory*, 2004, ch. 10), from φ₀ = u_c/r (the root circle) to where the rounding
        meets the rack's straight flank (the involute's start).
        """
        m, a, r = self.module, self.transverse_pressure_angle, self.pitch_radius
        rho = self.fillet_radius * m  # the normal rounding, taken as a circle in the transverse section
        vc = self.root_radius + rho
        if vc >= r:
            raise ModelError(
                f"profile shift {self.profile_shift:g} lifts the rack's tip rounding to the pitch line: the "
                "generated fillet is not modelled; use tooth_model = 'truncated'",
                element=self.name,
                field="profile_shift",
            )
        uc = (
            math.pi * self.transverse_module / 4 - (self.dedendum * m - rho) * math.tan(a) - rho / math.cos(a)
        )
        phi0, phi1 = uc / r, (uc - (r - vc) / math.tan(a)) / r
        s = np.linspace(0.0, 1.0, 801)
        phi = phi0 + (phi1 - phi0) * s**2  # dense near the root, where the fillet turns fastest
        du, dv = uc - r * phi, vc - r
        length = np.hypot(du, dv)
        pu, pv = uc - r * phi + rho * du / length, vc + rho * dv / length
        x = pu * np.cos(phi) + pv * np.sin(phi)
        y = -pu * np.sin(phi) + pv * np.cos(phi)
        return np.hypot(x, y), np.arctan2(x, y)

    @cached_property
    def _fillet_by_radius(self) -> tuple[np.ndarray, np.ndarray]:
        """The fillet's space half-angle on a grid of radii (dense near the root circle), rad: where
        the fillet turns back (undercut), the largest of its branches at each radius."""
        r_fil, psi_fil = self._fillet
        grid = r_fil[0] + (r_fil.max() - r_fil[0]) * np.linspace(0.0, 1.0, 1201) ** 2
        r0, r1, p0, p1 = r_fil[:-1], r_fil[1:], psi_fil[:-1], psi_fil[1:]
        g = grid[:, None]
        crosses = (g >= np.minimum(r0, r1)) & (g <= np.maximum(r0, r1)) & (r0 != r1)
        w = (g - r0) / np.where(r0 != r1, r1 - r0, 1.0)
        return grid, np.where(crosses, p0 + w * (p1 - p0), -np.inf).max(axis=1)

    @property
    def involute_start_radius(self) -> float:
        """Where the generated fillet meets the involute, m (ISO 21771's form radius r_Ff when the
        teeth are not undercut); the root circle of an internal gear, whose fillet is not modelled."""
        if self.internal:
            return self.root_radius
        return float(self._fillet[0][-1])

    def generated_thickness_array(self, radius: np.ndarray) -> np.ndarray:
        """Chordal thickness of the tooth that the basic rack generates, m: from the root circle, the
        fillet cut by the rack's rounded tip, then the involute to the tip circle;
        where the fillet undercuts the involute, the deeper cut.

        Parameters
        ----------
        radius : ndarray
            Radii between the root and tip circles, m.
        """
        r_fil = self._fillet[0]
        r = np.clip(np.asarray(radius, dtype=float), r_fil[0], self.tip_radius)
        grid, fillet = self._fillet_by_radius
        space = np.where(r <= grid[-1], np.interp(r, grid, fillet), -np.inf)
        on_involute = r >= max(self.base_radius, r_fil[-1] * (1 - 1e-12))
        if np.any(on_involute):
            ri = r[on_involute]
            half = 0.5 * self.arc_thickness_array(ri) / ri
            space[on_involute] = np.maximum(space[on_involute], math.pi / self.teeth - half)
        return 2.0 * r * np.sin(math.pi / self.teeth - space)

    def arc_thickness_array(self, radius: np.ndarray) -> np.ndarray:
        """Arc tooth thickness on the involute (vectorised :meth:`thickness`), m.

        Parameters
        ----------
        radius : ndarray
            Radii on the involute, m (r ≥ r_b).
        """
        r = np.asarray(radius, dtype=float)
        s = self._pitch_thickness
        a = self.transverse_pressure_angle
        alpha_y = np.arccos(np.minimum(1.0, self.base_radius / r))
        if self.internal:
            return 2.0 * r * (s / (2.0 * self.pitch_radius) - involute(a) + (np.tan(alpha_y) - alpha_y))
        return 2.0 * r * (s / (2.0 * self.pitch_radius) + involute(a) - (np.tan(alpha_y) - alpha_y))

    def profile_tooth(self) -> ProfileTooth:
        """The tooth as generated, for the potential-energy model (``tooth_model = "involute"``).

        The whole tooth from the root circle to the tip: the fillet that the basic rack's rounded
        tip cuts, then the true involute (:meth:`generated_thickness_array`), on the foundation of
        Sainsot et al. (2004) at the root circle with the tooth's chord there.

        An internal gear's tooth: the involute from its root circle (outside) to its tip circle, its
        chord integrated the same way (the potential-energy method applied to the ring's tooth as in
        Chen & Shao, *Mech. Mach. Theory* 69 (2013) 1–12), on a rigid foundation (the Sainsot fit holds
        for the body of an external gear only). The rim's deflection, which they model separately, is
        the ring's :meth:`ring_rim` with ``rim_thickness``, in series with the mesh
        (:meth:`GearPair.mesh_cycle`), not a term of the tooth.
        """
        r_f = self.root_radius
        if self.internal:
            return ProfileTooth(
                thickness=lambda y: self.chordal_thickness_array(r_f - np.asarray(y)),
                root_height=0.0,
                tip_height=r_f - self.tip_radius,
                face_width=self.face_width,
                youngs_modulus=self.youngs_modulus,
                poisson_ratio=self.poisson_ratio,
                name=f"{self.name} internal tooth",
            )
        return ProfileTooth(
            thickness=lambda y: self.generated_thickness_array(r_f + np.asarray(y)),
            root_height=0.0,
            tip_height=self.tip_radius - r_f,
            face_width=self.face_width,
            youngs_modulus=self.youngs_modulus,
            poisson_ratio=self.poisson_ratio,
            root_radius=r_f,
            bore_radius=self.bore_radius,
            name=f"{self.name} generated tooth",
            breaks=(self.involute_start_radius - r_f,),
            flank_loads=self._flank_loads(self.involute_start_radius),
        )

    @property
    def bore_radius(self) -> float:
        """Radius of the bore the foundation takes, m: the given one, else half the root radius."""
        return self.bore_diameter / 2.0 if self.bore_diameter is not None else self.root_radius / 2.0

    @property
    def guesses(self) -> tuple[str, ...]:
        """The inputs this gear's stiffness takes by default, each with what was taken."""
        if self.bore_diameter is not None or self.internal:
            return ()
        return (
            f"{self.name}: no bore_diameter: the tooth foundation takes a bore of half the root diameter "
            f"({show(self.root_radius, 'm', 'mm', '.4g')}); give bore_diameter",
        )

    def _flank_loads(self, low_radius: float) -> tuple[tuple[float, float], ...]:
        """(height above the root circle, m; load angle, rad) at 17 radii from ``low_radius`` (or the
        base circle, if higher) to the tip circle: where the flank can be loaded, for the teeth's
        check of the Sainsot foundation's extrapolation.

        Parameters
        ----------
        low_radius : float
            Where the flank starts, m (the start of the involute).
        """
        low = max(low_radius, self.base_radius)
        radii = [low + (self.tip_radius - low) * max(k, 1e-6) / 16.0 for k in range(17)]
        return tuple((self.load_height(r), self.load_angle(r)) for r in radii)

    def tooth(self) -> TruncatedTooth:
        """The truncated-triangle tooth of this gear, heights from the root circle: tapering from the
        start of the involute (max(r_b, r_f)) to the tip, and below it, down to the root circle, a
        segment of the thickness there (the part of the tooth between the root and base circles),
        on the foundation of Sainsot et al. (2004) at the root circle. An internal gear's tooth tapers
        from its root circle (outside) to its tip circle on a rigid foundation (its rim, with
        ``rim_thickness``, is in series with the mesh: see :meth:`profile_tooth`)."""
        if self.internal:
            return TruncatedTooth(
                tip_height=self.root_radius - self.tip_radius,
                root_height=0.0,
                tip_thickness=self.chordal_thickness(self.tip_radius),
                root_thickness=self.chordal_thickness(self.root_radius),
                face_width=self.face_width,
                youngs_modulus=self.youngs_modulus,
                poisson_ratio=self.poisson_ratio,
                name=f"{self.name} internal tooth",
            )
        r0 = self.form_radius
        foundation = {"root_radius": self.root_radius, "bore_radius": self.bore_radius}
        return TruncatedTooth(
            root_segment=True,
            tip_height=self.tip_radius - self.root_radius,
            root_height=r0 - self.root_radius,
            tip_thickness=self.chordal_thickness(self.tip_radius),
            root_thickness=self.chordal_thickness(r0),
            face_width=self.face_width,
            youngs_modulus=self.youngs_modulus,
            poisson_ratio=self.poisson_ratio,
            name=f"{self.name} tooth",
            flank_loads=self._flank_loads(r0),
            **foundation,
        )
