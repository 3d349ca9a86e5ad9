"""The truncated-triangle tooth: compliance terms along the line of action, and a pair of teeth.

The tooth is a cantilever whose thickness falls linearly from t_b at the root section (height h_b)
to t_a at the tip (height h_a); extended, its flanks meet at the apex height
w = (h_a t_b − h_b t_a)/(t_b − t_a) (SPEC §4). A normal force F at height h_c acts along the line of
action at the load angle φ to the perpendicular of the tooth's centre line; its components are
F cos φ across the tooth and F sin φ along it (compressive), the latter applied at the flank, half a
thickness e = t(h_c)/2 off the centre line.

Each compliance term is the deflection per unit force along the line of action, from Castigliano's
theorem on the strain energy of a Timoshenko beam of rectangular section f × t(y) (the potential
energy method of Yang & Lin, ASME J. Mech. Trans. Autom. Des. 109 (1987) 189–196, here with the
linear taper integrated in closed form):

- bending by the transverse component: ∫ cos²φ (h_c − y)² / (E I) dy;
- what the radial component adds to bending: ∫ [sin²φ e² − 2 sinφ cosφ e (h_c − y)] / (E I) dy
  (its own moment, and the coupling with the transverse moment, which relieves the root);
- axial compression: ∫ sin²φ / (E A) dy;
- shear: ∫ κ cos²φ / (G A) dy with κ = 1.2 for a rectangle;
- foundation (fillet and gear body): Sainsot, Velex & Duverger, ASME J. Mech. Des. 126 (2004)
  748–752, when the root and bore radii are known; a rigid foundation otherwise;

with I = f t³/12, A = f t and the integrals from the root section h_b to the load height h_c. The
published model lists bending (twice), shear, foundation and Hertz; the compression term is kept
separate here so that it can be seen (it is small). Plane stress (E, not E/(1 − ν²)) as in the
published model.

Hertzian contact is a property of the *pair*: δ_h = 4 F (1 − ν²)/(π E f) for two teeth of one
material (Yang & Lin 1987), in general 2 F/(π f E*) with 1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂. It is
counted once per pair; counting it per tooth (as the published formulas seem to) counts it twice.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import Any, Protocol

from mechdyn.errors import ModelError, ModelWarning
from mechdyn.units import check_poisson_ratio
from mechdyn.units import si_field as _q

__all__ = [
    "FOUNDATION_EXTRAPOLATION_TOLERANCE",
    "SHEAR_COEFFICIENT",
    "TruncatedTooth",
    "foundation_extrapolation",
    "hertz_compliance",
    "nearest_in_sainsot_range",
    "pair_compliance",
]

SHEAR_COEFFICIENT = 1.2
"""Timoshenko shear coefficient of a rectangular section (energy form)."""

# Sainsot, Velex & Duverger (2004), table 1: X* = A/θ_f² + B h_f² + C h_f/θ_f + D/θ_f + E h_f + F
_SAINSOT = {
    "L": (-5.574e-5, -1.9986e-3, -2.3015e-4, 4.7702e-3, 0.0271, 6.8045),
    "M": (60.111e-5, 28.100e-3, -83.431e-4, -9.9256e-3, 0.1624, 0.9086),
    "P": (-50.952e-5, 185.50e-3, 0.0538e-4, 53.300e-3, 0.2895, 0.9236),
    "Q": (-6.2042e-5, 9.0889e-3, -4.0964e-4, 7.8297e-3, -0.1472, 0.6904),
}
#: Range of the Sainsot fit: h_f = r_f/r_int and θ_f (rad).
SAINSOT_RANGE = {"h_f": (1.4, 7.0), "theta_f": (0.01, 0.12)}

FOUNDATION_EXTRAPOLATION_TOLERANCE = 0.05
"""Largest share of a tooth's compliance that may rest on the Sainsot fit's extrapolation without a
warning: the change of the foundation term between the tooth's own h_f, θ_f and the nearest point of
the fit's range, over the compliance of the tooth (:func:`foundation_extrapolation`). 5 % of a pinion's
tooth moves a mesh's mean stiffness by about 1 % (12/24, x = 0.5: 6.5 % and 1.25 %; 16/32: 2.4 % and
0.7 %), well inside the spread of the model against ISO 6336-1 (0.97–1.11 × c_γα over 16/32 … 45/90,
docs/capabilities/gears.md)."""

#: Load angles, rad, at which a tooth that was not given its flank's loads is checked.
_CHECK_ANGLES = tuple(math.radians(a) for a in (0.0, 10.0, 20.0, 30.0, 40.0))


@dataclass(frozen=True)
class TruncatedTooth:
    """One tooth as a truncated triangle.

    Parameters
    ----------
    tip_height, root_height : float or quantity
        h_a and h_b, m, measured from one datum (e.g. the root circle); 0 ≤ h_b < h_a ≤ 1e3 m.
    tip_thickness, root_thickness : float or quantity
        t_a and t_b, m, from 1e-9 to 1e3 m; the tooth must taper toward the tip (t_a < t_b).
    face_width : float or quantity
        f, m, from 1e-9 to 1e3 m.
    youngs_modulus : float or quantity
        E, Pa, from 1e-3 to 1e13 Pa.
    poisson_ratio : float
        ν, in (−1, 0.5).
    root_radius, bore_radius : float or quantity, optional
        Radius of the root section and of the gear bore, m. With both, the foundation term of
        Sainsot et al. (2004) is included; without, the foundation is rigid.
    name : str
        For messages.
    root_segment : bool
        The tooth continues below the root section, at the root thickness t_b, down to height 0
        (a gear's tooth between its root circle and the start of the involute): its bending, shear
        and compression are added, and the foundation sits at height 0 (``root_radius`` is then the
        radius at height 0). Off: the tooth is clamped at h_b.
    flank_loads : tuple of (float, float)
        (load height, m; load angle, rad) pairs where the tooth is loaded in service, at which
        :meth:`foundation_extrapolation` is evaluated (a gear gives its flank). Empty: 16 heights
        from the root section to the tip, each at 0°, 10°, 20°, 30° and 40°.
    """

    tip_height: float
    root_height: float
    tip_thickness: float
    root_thickness: float
    face_width: float
    youngs_modulus: float
    poisson_ratio: float = 0.3
    root_radius: float | None = None
    bore_radius: float | None = None
    name: str = "tooth"
    root_segment: bool = False
    flank_loads: tuple[tuple[float, float], ...] = ()

    def __post_init__(self) -> None:
        n = self.name
        positive: dict[str, Any] = {"positive": True}
        nonnegative: dict[str, Any] = {"nonnegative": True}
        for f, unit, sign in (
            ("tip_height", "m", positive),
            ("root_height", "m", nonnegative),
            ("tip_thickness", "m", positive),
            ("root_thickness", "m", positive),
            ("face_width", "m", positive),
            ("youngs_modulus", "Pa", positive),
        ):
            object.__setattr__(self, f, _q(n, f, getattr(self, f), unit, **sign))
        object.__setattr__(self, "poisson_ratio", check_poisson_ratio(n, "poisson_ratio", self.poisson_ratio))
        for f in ("root_radius", "bore_radius"):
            if getattr(self, f) is not None:
                object.__setattr__(self, f, _q(n, f, getattr(self, f), "m", positive=True))
        if self.tip_height <= self.root_height:
            raise ModelError(
                f"tip height {self.tip_height:g} m must be above the root height {self.root_height:g} m",
                element=n,
                field="tip_height",
            )
        if self.tip_thickness >= self.root_thickness:
            raise ModelError(
                f"tip thickness t_a = {self.tip_thickness:g} m must be smaller than the root thickness "
                f"t_b = {self.root_thickness:g} m (a truncated triangle tapers toward the tip)",
                element=n,
                field="tip_thickness",
            )
        if (self.root_radius is None) != (self.bore_radius is None):
            raise ModelError(
                "give both root_radius and bore_radius (foundation), or neither",
                element=n,
                field="bore_radius",
            )
        if self.root_radius is not None and self.bore_radius is not None:  # both or neither (above)
            if not 0 < self.bore_radius < self.root_radius:
                raise ModelError(
                    f"bore radius {self.bore_radius:g} m must be positive and below the root radius "
                    f"{self.root_radius:g} m",
                    element=n,
                    field="bore_radius",
                )
            warn_outside_sainsot_range(
                n, *self._foundation_parameters, self.foundation_extrapolation, stacklevel=4
            )

    def foundation_extrapolation(self) -> float:
        """Share of this tooth's compliance that rests on extrapolating the Sainsot fit (0 inside its
        range): the largest abs(δ_f(h_f, θ_f) − δ_f(nearest point of the range)) / (tooth compliance)
        over ``flank_loads`` (:func:`foundation_extrapolation`)."""
        loads = self.flank_loads or _default_loads(self.root_height, self.tip_height)
        return foundation_extrapolation(self, loads)

    @property
    def _foundation_parameters(self) -> tuple[float, float]:
        """h_f = r_root / r_bore and θ_f = t_b / (2 r_root) of the Sainsot fit."""
        r_root, r_bore = self.root_radius, self.bore_radius
        assert r_root is not None and r_bore is not None  # asked for only when there is a foundation
        return r_root / r_bore, self.root_thickness / (2.0 * r_root)

    # -- geometry ----------------------------------------------------------------------------
    @property
    def apex_height(self) -> float:
        """w = (h_a t_b − h_b t_a)/(t_b − t_a), m: where the extended flanks meet."""
        return (self.tip_height * self.root_thickness - self.root_height * self.tip_thickness) / (
            self.root_thickness - self.tip_thickness
        )

    @property
    def taper(self) -> float:
        """Thickness lost per unit height, (t_b − t_a)/(h_a − h_b)."""
        return (self.root_thickness - self.tip_thickness) / (self.tip_height - self.root_height)

    def thickness(self, height: float) -> float:
        """t(y) = t_b (w − y)/(w − h_b), m.

        Parameters
        ----------
        height : float
            Height y from the tooth's datum, m (h_b ≤ y ≤ h_a; any finite height on the extended
            flanks below the apex is accepted).

        Raises
        ------
        mechdyn.errors.ModelError
            For a height that is not finite or at or above the apex, where the flanks meet.
        """
        y = _q(self.name, "height", height, "m", high=self.apex_height, high_open=True)
        return self.taper * (self.apex_height - y)

    @property
    def shear_modulus(self) -> float:
        """G = E / (2 (1 + ν)), Pa."""
        return self.youngs_modulus / (2.0 * (1.0 + self.poisson_ratio))

    def _load(self, load_height: Any, load_angle: Any) -> tuple[float, float]:
        hc = _q(self.name, "load_height", load_height, "m")
        phi = _q(self.name, "load_angle", load_angle, "rad")
        if not self.root_height < hc <= self.tip_height * (1 + 1e-12):
            raise ModelError(
                f"load height {hc:g} m lies outside the tooth (root {self.root_height:g} m, tip "
                f"{self.tip_height:g} m); the load point must be on the flank, above the root section",
                element=self.name,
                field="load_height",
            )
        if not abs(phi) < math.pi / 2:  # negative near the base circle: the radial part pulls
            raise ModelError(
                f"load angle {math.degrees(phi):g}° must lie in (−90°, 90°)",
                element=self.name,
                field="load_angle",
            )
        return hc, phi

    # -- compliance terms --------------------------------------------------------------------
    def compliances(self, load_height: Any, load_angle: Any) -> dict[str, float]:
        """Deflection along the line of action per unit normal force, m/N, term by term.

        Parameters
        ----------
        load_height : float or quantity
            h_c, m, on the same datum as h_a and h_b.
        load_angle : float or quantity
            φ, rad, between the line of action and the perpendicular to the tooth centre line;
            negative when the radial component pulls (contact near the base circle).

        Returns
        -------
        dict
            ``bending_transverse``, ``bending_radial``, ``compression``, ``shear``, ``foundation``
            (0 for a rigid foundation). The Hertz term is not a tooth property: see
            :func:`hertz_compliance`.
        """
        hc, phi = self._load(load_height, load_angle)
        E, f, tb = self.youngs_modulus, self.face_width, self.root_thickness
        ub = self.apex_height - self.root_height  # distance of the root section from the apex
        x = (hc - self.root_height) / ub  # share of that distance up to the load point, in (0, 1)
        # ∫ (h_c − y)^k / t³ dy (k = 2, 1, 0) and ∫ dy / t over [h_b, h_c] with t = t_b (1 − (y − h_b)/u_b),
        # written in x so that they stay exact as the taper vanishes (u_b → ∞, x → 0)
        i2 = ub**3 / tb**3 * _log_tail(x)
        i1 = ub**2 / tb**3 * x**2 / (2.0 * (1.0 - x))
        i0 = ub / tb**3 * x * (2.0 - x) / (2.0 * (1.0 - x) ** 2)
        j0 = ub / tb * -math.log1p(-x)
        e = 0.5 * tb * (1.0 - x)  # half the thickness at the load point
        if self.root_segment:  # the uniform segment [0, h_b] below the root section, thickness t_b
            hb = self.root_height
            i2 += (hc**3 - (hc - hb) ** 3) / 3.0 / tb**3
            i1 += (hc * hb - 0.5 * hb**2) / tb**3
            i0 += hb / tb**3
            j0 += hb / tb
        cos, sin = math.cos(phi), math.sin(phi)
        return {
            "bending_transverse": 12.0 * cos**2 * i2 / (E * f),
            "bending_radial": 12.0 * (sin**2 * e**2 * i0 - 2.0 * sin * cos * e * i1) / (E * f),
            "compression": sin**2 * j0 / (E * f),
            "shear": SHEAR_COEFFICIENT * cos**2 * j0 / (self.shear_modulus * f),
            "foundation": self._foundation(hc, phi),
        }

    def published_compliances(self, load_height: Any, load_angle: Any) -> dict[str, float]:
        """The deflection terms of the published tooth model (SPEC §4), m/N per unit normal force.

        The published model (SPEC §4; its source is not known) takes the whole tooth from the root
        (height 0): a rectangle of thickness t_b up to h_b, then the truncated triangle, whose flanks
        meet at the apex height w; the normal force F at height h_c and angle φ. SPEC §4 names the
        terms (δ_bp, δ_bn, δ_s, δ_f, δ_h; k = F/Σδ) without printing them; they are written here in
        closed form, numbered in the order the SPEC lists them (the radial bending term is the
        paper's eq. 3 in issue 25). With r = (w − h_c)/(w − h_b), the thickness at the load point is
        t_c = r t_b, and:

        1. w = (h_a t_b − h_b t_a)/(t_b − t_a);
        2. bending by F cos φ, 12 cos²φ/(E f) ∫₀^h_c (h_c − y)²/t³ dy:
           δ_bp/F = 12 cos²φ/(E f t_b³) [h_b (h_c² − h_c h_b + h_b²/3)
           + (w − h_b)³ (r (4 − r) − 2 ln r − 3)/2];
        3. bending by F sin φ, whose moment F sin φ · t_c/2 bends the tooth back against the
           transverse load, along the line of action, −12 sinφ cosφ (t_c/2)/(E f) ∫₀^h_c (h_c − y)/t³ dy:
           δ_bn/F = −6 sinφ cosφ/(E f t_b²) [r h_b (h_c − h_b/2) + (h_c − h_b)²/2];
        4. shear with κ = 1.2 and G = E/(2(1 + ν)), κ cos²φ/(G f) ∫₀^h_c dy/t:
           δ_s/F = 2.4 (1 + ν) cos²φ/(E f t_b) [h_b − (w − h_b) ln r];
        5. foundation: δ_f/F = 24 cos²φ h_c²/(π E f t_b²);
        6. Hertz: δ_h/F = 4 (1 − ν²)/(π E f), counted in each tooth as the published model does (a
           pair's contact compliance is one such term, :func:`hertz_compliance`).

        Term 3 is half the coupling term of Castigliano's theorem, without the sin²φ (t_c/2)² term
        (:meth:`compliances` keeps both); the earlier version of this method used that full form,
        1.52 × (pair 1) and 1.23 × (pair 2) the published term. No axial compression term (the
        published model has none); plane stress. The printed values settle the terms: with steel
        (206 GPa, ν 0.3), 20° and a 50 mm face, one tooth of the published pair 2, k = F/Σδ =
        2.7078·10⁹ N/m, is the value printed for pair 1 (2.7082·10⁹ N/m) to 0.013 % (with the
        earlier radial term 0.93 %, with κ = 1 6 %): the mix-up in the published table that SPEC §4
        remarks. The brackets of terms 2 and 4 are evaluated through ln(1 − x), x = 1 − r, without
        cancellation, so they hold as the taper vanishes.

        Parameters
        ----------
        load_height : float or quantity
            h_c, m, from the root.
        load_angle : float or quantity
            φ, rad.

        Returns
        -------
        dict
            ``bending_transverse`` (δ_bp), ``bending_radial`` (δ_bn), ``shear`` (δ_s),
            ``foundation`` (δ_f), ``hertz`` (δ_h), each per unit force, m/N.
        """
        hc, phi = self._load(load_height, load_angle)
        E, f, tb, hb, nu = (
            self.youngs_modulus,
            self.face_width,
            self.root_thickness,
            self.root_height,
            self.poisson_ratio,
        )
        ub = self.apex_height - hb  # w − h_b
        x = (hc - hb) / ub  # 1 − r
        r = 1.0 - x
        cos, sin = math.cos(phi), math.sin(phi)
        # r (4 − r) − 2 ln r − 3 = 2 (−ln(1 − x) − x − x²/2) = 2 · _log_tail(x), free of cancellation
        bending = hb * (hc * hc - hc * hb + hb * hb / 3.0) + ub**3 * _log_tail(x)  # (2), bracket
        radial = r * hb * (hc - 0.5 * hb) + 0.5 * (hc - hb) ** 2  # (3), bracket
        shear = hb - ub * math.log1p(-x)  # (4), bracket: h_b − (w − h_b) ln r
        return {
            "bending_transverse": 12.0 * cos**2 * bending / (E * f * tb**3),
            "bending_radial": -6.0 * sin * cos * radial / (E * f * tb**2),
            "shear": 2.0 * SHEAR_COEFFICIENT * (1.0 + nu) * cos**2 * shear / (E * f * tb),
            "foundation": 24.0 * cos**2 * hc**2 / (math.pi * E * f * tb**2),
            "hertz": 4.0 * (1.0 - nu**2) / (math.pi * E * f),
        }

    def _foundation(self, hc: float, phi: float, parameters: tuple[float, float] | None = None) -> float:
        """The Sainsot foundation term, m/N, at the tooth's own (h_f, θ_f) or at ``parameters``."""
        if self.root_radius is None:
            return 0.0
        h_f, theta_f = parameters or self._foundation_parameters
        return foundation_compliance(
            hc if self.root_segment else hc - self.root_height,
            self.root_thickness,
            h_f,
            theta_f,
            phi,
            self.youngs_modulus,
            self.face_width,
        )

    def compliance(self, load_height: Any, load_angle: Any) -> float:
        """Total tooth compliance (all terms but Hertz), m/N.

        Parameters
        ----------
        load_height : float or quantity
            Height h_c of the load, m, from the tooth's datum.
        load_angle : float or quantity
            Load angle φ, rad.
        """
        return sum(self.compliances(load_height, load_angle).values())

    def stiffness(self, load_height: Any, load_angle: Any) -> float:
        """Tooth stiffness F/δ without the contact term, N/m.

        Parameters
        ----------
        load_height : float or quantity
            Height h_c of the load, m.
        load_angle : float or quantity
            Load angle φ, rad.
        """
        return 1.0 / self.compliance(load_height, load_angle)


def nearest_in_sainsot_range(h_f: float, theta_f: float) -> tuple[float, float]:
    """The point of the Sainsot fit's range (:data:`SAINSOT_RANGE`) nearest to (h_f, θ_f).

    Parameters
    ----------
    h_f : float
        r_root / r_bore.
    theta_f : float
        Half the tooth's angle at the root circle, rad.
    """
    (lo_h, hi_h), (lo_t, hi_t) = SAINSOT_RANGE["h_f"], SAINSOT_RANGE["theta_f"]
    return min(max(h_f, lo_h), hi_h), min(max(theta_f, lo_t), hi_t)


class _FoundedTooth(Protocol):
    @property
    def _foundation_parameters(self) -> tuple[float, float]: ...

    def _foundation(self, hc: float, phi: float, parameters: tuple[float, float] | None = None) -> float: ...

    def compliances(self, load_height: Any, load_angle: Any) -> dict[str, float]: ...


def foundation_extrapolation(tooth: _FoundedTooth, loads: Iterable[tuple[float, float]]) -> float:
    """Share of a tooth's compliance that rests on extrapolating the Sainsot fit.

    Outside the range of the fit of Sainsot, Velex & Duverger (2004) (:data:`SAINSOT_RANGE`:
    1.4 ≤ h_f ≤ 7, 0.01 ≤ θ_f ≤ 0.12) the foundation term is the fit's polynomial extrapolated. Its
    share is the largest change of the foundation term between the tooth's own (h_f, θ_f) and the
    nearest point of the range, relative to the tooth's whole compliance (bending, shear,
    compression, foundation) at the same load: max abs(δ_f(h_f, θ_f) − δ_f(h_f′, θ_f′)) / Σδ over
    the loads. It measures how much of the result the extrapolation carries (the fit gives no data
    beyond its range to check the extrapolated values against), and is 0 inside the range.

    Parameters
    ----------
    tooth : TruncatedTooth or ProfileTooth
        A tooth on an elastic foundation.
    loads : iterable of (float, float)
        (load height, m; load angle, rad) pairs.

    Returns
    -------
    float
        The share, dimensionless.
    """
    own = tooth._foundation_parameters
    edge = nearest_in_sainsot_range(*own)
    if edge == own:
        return 0.0
    share = 0.0
    for height, angle in loads:
        terms = tooth.compliances(height, angle)
        change = abs(tooth._foundation(height, angle, edge) - terms["foundation"])
        share = max(share, change / sum(terms.values()))
    return share


def _default_loads(low: float, tip: float) -> tuple[tuple[float, float], ...]:
    """16 heights from just above ``low`` to ``tip`` (m), each at every angle of ``_CHECK_ANGLES``."""
    heights = [low + (tip - low) * k / 16.0 for k in range(1, 17)]
    return tuple((h, a) for h in heights for a in _CHECK_ANGLES)


def warn_outside_sainsot_range(
    name: str,
    h_f: float,
    theta_f: float,
    share: Callable[[], float] | None = None,
    stacklevel: int = 2,
) -> None:
    """Warn (``ModelWarning``) when h_f = r_root/r_bore or θ_f = S_f/(2 r_root) lies outside the range
    of the Sainsot fit (:data:`SAINSOT_RANGE`), where :func:`foundation_compliance` extrapolates, and
    the extrapolation carries more than :data:`FOUNDATION_EXTRAPOLATION_TOLERANCE` of the tooth's
    compliance (:func:`foundation_extrapolation`); the message gives that share.

    Parameters
    ----------
    name : str
        The tooth, for the message.
    h_f : float
        r_root / r_bore.
    theta_f : float
        Half the tooth's angle at the root circle, rad.
    share : callable, optional
        Returns the tooth's :func:`foundation_extrapolation` (evaluated only outside the range).
        Without it, any point outside the range is warned about.
    stacklevel : int
        As for :func:`warnings.warn`, counted from the caller.
    """
    (lo_h, hi_h), (lo_t, hi_t) = SAINSOT_RANGE["h_f"], SAINSOT_RANGE["theta_f"]
    if lo_h <= h_f <= hi_h and lo_t <= theta_f <= hi_t:
        return
    tolerance = FOUNDATION_EXTRAPOLATION_TOLERANCE
    x = None if share is None else share()
    if x is not None and x <= tolerance:
        return
    amount = (
        "the foundation term is extrapolated"
        if x is None
        else f"the extrapolated foundation term moves the tooth's compliance by up to {100 * x:.1f} % "
        f"against the fit at the nearest point of its range (above the {100 * tolerance:g} % accepted)"
    )
    warnings.warn(
        f"{name}: foundation parameters h_f = {h_f:.3g}, θ_f = {theta_f:.3g} rad lie outside the "
        f"range of the Sainsot fit (h_f {lo_h}–{hi_h}, θ_f {lo_t}–{hi_t} rad); {amount}",
        ModelWarning,
        stacklevel=stacklevel + 1,
    )


def foundation_compliance(
    height: float,
    root_thickness: float,
    h_f: float,
    theta_f: float,
    phi: float,
    youngs_modulus: float,
    face_width: float,
) -> float:
    """Fillet-foundation compliance of Sainsot, Velex & Duverger (2004), m/N.

    (cos²φ / (E f)) [L* (u_f/S_f)² + M* (u_f/S_f) + P* (1 + Q* tan²φ)], with u_f the height of the
    load point above the root section, S_f the root thickness, and L*, M*, P*, Q* polynomials in
    h_f = r_root/r_bore and θ_f = S_f/(2 r_root) (their table 1).
    """
    x = {
        k: a / theta_f**2 + b * h_f**2 + c * h_f / theta_f + d / theta_f + e * h_f + f
        for k, (a, b, c, d, e, f) in _SAINSOT.items()
    }
    u = height / root_thickness
    return (
        math.cos(phi) ** 2
        / (youngs_modulus * face_width)
        * (x["L"] * u**2 + x["M"] * u + x["P"] * (1.0 + x["Q"] * math.tan(phi) ** 2))
    )


def _log_tail(x: float) -> float:
    """−ln(1 − x) − x − x²/2 = Σ_{k≥3} x^k / k, without cancellation for small x."""
    if x > 0.5:
        return -math.log1p(-x) - x - 0.5 * x * x
    total, term, k = 0.0, x**3, 3
    while term > 1e-17 * max(total, 1e-300) and k < 200:
        total += term / k
        term *= x
        k += 1
    return total


def hertz_compliance(
    face_width: float, e1: float, nu1: float, e2: float | None = None, nu2: float | None = None
) -> float:
    """Hertzian contact compliance of a pair of teeth, m/N.

    δ_h / F = 2 / (π f E*), 1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂; for one material this is
    4 (1 − ν²)/(π E f), the term of SPEC §4 (Yang & Lin 1987). Independent of the load: the
    linearised line-contact stiffness of the potential-energy method.

    Parameters
    ----------
    face_width : float
        Contact length f, m, from 1e-9 to 1e3 m.
    e1, nu1, e2, nu2 : float
        Young's moduli (Pa, from 1e-3 to 1e13) and Poisson ratios (in (−1, 0.5)) of the two teeth
        (the second defaults to the first).

    Raises
    ------
    mechdyn.errors.ModelError
        For a number that is not finite or out of its range, naming it.
    """
    face_width = _q("hertz", "face_width", face_width, "m", positive=True)
    e1 = _q("hertz", "e1", e1, "Pa", positive=True, what="Young's modulus")
    nu1 = check_poisson_ratio("hertz", "nu1", nu1)
    e2 = e1 if e2 is None else _q("hertz", "e2", e2, "Pa", positive=True, what="Young's modulus")
    nu2 = nu1 if nu2 is None else check_poisson_ratio("hertz", "nu2", nu2)
    inv_estar = (1.0 - nu1**2) / e1 + (1.0 - nu2**2) / e2
    return 2.0 * inv_estar / (math.pi * face_width)


def pair_compliance(
    tooth1: TruncatedTooth,
    load1: tuple[Any, Any],
    tooth2: TruncatedTooth,
    load2: tuple[Any, Any],
    *,
    hertz_per_tooth: bool = False,
) -> dict[str, float]:
    """Compliance of a pair of teeth in contact: both teeth in series, Hertz once.

    Parameters
    ----------
    tooth1, tooth2 : TruncatedTooth
    load1, load2 : (load height, load angle)
        Where each tooth is loaded.
    hertz_per_tooth : bool
        Count the Hertz term once per tooth (twice per pair) to reproduce a model that puts it in
        each tooth's compliance; wrong, but useful to compare with such published numbers.

    Returns
    -------
    dict
        ``tooth1``, ``tooth2``, ``hertz`` and ``total``, m/N.
    """
    c1 = tooth1.compliance(*load1)
    c2 = tooth2.compliance(*load2)
    f = min(tooth1.face_width, tooth2.face_width)
    h = hertz_compliance(
        f, tooth1.youngs_modulus, tooth1.poisson_ratio, tooth2.youngs_modulus, tooth2.poisson_ratio
    )
    if hertz_per_tooth:
        h = 2.0 * h
    return {"tooth1": c1, "tooth2": c2, "hertz": h, "total": c1 + c2 + h}
