"""Bolted joints and anchor bolts into concrete: bolt stiffness, clamped members by pressure cones,
joint stiffness and load factor.

Members (Shigley's Mechanical Engineering Design, Budynas & Nisbett, §8-5, Eq. 8-20): a frustum of
half-angle α, thickness t, smaller diameter D, hole d, modulus E has
k = π E d tan α / ln[((2 t tan α + D − d)(D + d)) / ((2 t tan α + D + d)(D − d))]; the clamped
stack is cut at mid-grip, a cone grows from each bearing face towards the middle, one frustum per
layer and all in series. α = 30° by default; VDI 2230 gives the cone angle from the joint geometry
(tan φ = 0.362 + 0.032 ln(β_L/2) + 0.153 ln y for a through-bolted joint, β_L = l_K/d_W,
y = D_A/d_W), offered as an option.

Bolt (the published mount-stiffness estimate, SPEC §5): k_b = A_d E / L_eq with the *shank* area
A_d = π d²/4 and L_eq = L + (1.95 − β/2 − ν) d (β = head or washer diameter over bolt diameter; the
term in d stands for the head and the nut or anchor). Where the drawing gives the length l_t of free
thread in the grip, shank and thread act as springs in series, the thread with the tensile stress
area A_s (Shigley, Budynas & Nisbett, §8-4, Eq. 8-17; VDI 2230 Part 1, 2015, §5.1.1 sums the
sections the same way): 1/k_b = (L − l_t + (1.95 − β/2 − ν) d)/(E A_d) + l_t/(E A_s). Also offered:
the VDI 2230 section-by-section resilience
δ_S = δ_head + Σ l_i/(E A_i) + δ_thread + δ_nut with δ_head = 0.5 d/(E A_N) (hexagon head),
δ_thread = 0.5 d/(E A_d3) (engaged thread), δ_nut = 0.4 d/(E A_N) for a nut, 0.33 d/(E A_N) for a
tapped hole or a cast-in anchor (VDI 2230 Part 1, 2015, §5.1.1).

For an external load the bolt and the members work in parallel: k_t = k_b + k_m; the bolt takes the
share C = k_b/(k_b + k_m) of it (the load factor). (The published captions swap "series" and
"parallel"; the physics is as here: under preload the two are in series, in the force loop.)
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from itertools import pairwise
from typing import Any

from mechdyn.checks import check_number
from mechdyn.errors import ModelError
from mechdyn.mounts.materials import Material
from mechdyn.units import convert, show, si_field

__all__ = [
    "CONE_ANGLES",
    "ISO_COARSE_PITCH",
    "BoltedJoint",
    "Layer",
    "coarse_pitch",
    "frustum_stiffness",
    "vdi2230_cone_angle",
]

ISO_COARSE_PITCH = {
    3: 0.5, 4: 0.7, 5: 0.8, 6: 1.0, 8: 1.25, 10: 1.5, 12: 1.75, 14: 2.0, 16: 2.0, 18: 2.5, 20: 2.5,
    22: 2.5, 24: 3.0, 27: 3.0, 30: 3.5, 33: 3.5, 36: 4.0, 39: 4.0, 42: 4.5, 45: 4.5, 48: 5.0, 52: 5.0,
    56: 5.5, 60: 5.5, 64: 6.0,
}  # fmt: skip
"""Nominal diameter (mm) → coarse thread pitch (mm), ISO 261 / ISO 262 (M3 to M64)."""


def coarse_pitch(owner: str, diameter: float) -> float:
    """The ISO metric coarse pitch of a nominal diameter, m.

    Raises
    ------
    ModelError
        When the diameter is not an ISO metric size (then the pitch must be given).
    """
    mm = float(convert(diameter, "m", "mm"))
    size = round(mm)
    if abs(mm - size) > 1e-6 or size not in ISO_COARSE_PITCH:
        sizes = ", ".join(f"M{k}" for k in ISO_COARSE_PITCH)
        raise ModelError(
            f"{show(diameter, 'm', 'mm')} is not an ISO metric coarse-thread size ({sizes}); give pitch",
            element=owner,
            field="pitch",
        )
    return float(convert(ISO_COARSE_PITCH[size], "mm", "m"))


CONE_ANGLES = (math.radians(1.0), math.radians(89.0))
"""The cone half-angles accepted, rad: VDI 2230's fits give 20° to 40°, calibrations search 1° to 80°."""


def _cone_angle(owner: str, field: str, value: Any) -> float:
    """A cone half-angle in rad (or a quantity), checked against :data:`CONE_ANGLES`."""
    a = si_field(owner, field, value, "rad")
    if not CONE_ANGLES[0] * (1 - 1e-12) <= a <= CONE_ANGLES[1] * (1 + 1e-12):  # "1 deg" may round below
        raise ModelError(
            f"{math.degrees(a):g}° must lie between 1° and 89° (VDI 2230: 20° to 40°)",
            element=owner,
            field=field,
        )
    return a


def frustum_stiffness(E: float, d: float, D: float, t: float, alpha: float) -> float:
    """Stiffness of one pressure-cone frustum, N/m (Shigley Eq. 8-20).

    Parameters
    ----------
    E : float
        Pa, from 1e-3 to 1e13 Pa.
    d : float
        Hole diameter, m, from 1e-9 to 1e3 m.
    D : float
        Diameter of the frustum's smaller face, m (> d).
    t : float
        Thickness, m, from 1e-9 to 1e3 m.
    alpha : float
        Cone half-angle, rad, from 1° to 89° (:data:`CONE_ANGLES`).

    Raises
    ------
    mechdyn.errors.ModelError
        For a number that is not finite or out of its range, naming it.
    """
    E = check_number("frustum", "E", E, "Pa", positive=True, what="Young's modulus")
    d = check_number("frustum", "d", d, "m", positive=True, what="hole diameter")
    D = check_number("frustum", "D", D, "m", low=d, low_open=True, what="face diameter (above the hole's)")
    t = check_number("frustum", "t", t, "m", positive=True, what="thickness")
    alpha = _cone_angle("frustum", "alpha", alpha)
    ta = math.tan(alpha)
    return (
        math.pi * E * d * ta / math.log(((2 * t * ta + D - d) * (D + d)) / ((2 * t * ta + D + d) * (D - d)))
    )


def vdi2230_cone_angle(
    grip: float, bearing_diameter: float, outer_diameter: float, tapped: bool = False
) -> float:
    """Cone half-angle φ of VDI 2230 Part 1 (2015), rad, with β_L = l_K / d_W and y = D_A′ / d_W.

    Through-bolted joint (DSV), Eq. (5.1/13): tan φ = 0.362 + 0.032 ln(β_L / 2) + 0.153 ln y;
    tapped-thread joint (ESV), Eq. (5.1/14): tan φ = 0.348 + 0.013 ln β_L + 0.193 ln y.

    Parameters
    ----------
    grip : float
        Clamp length l_K, m, from 1e-9 to 1e3 m.
    bearing_diameter : float
        Outer bearing diameter d_W of the head or washer, m, from 1e-9 to 1e3 m.
    outer_diameter : float
        Outer diameter D_A′ of the clamped parts, m, from 1e-9 to 1e3 m.
    tapped : bool
        A tapped-thread joint (ESV) rather than a through-bolted one (DSV).

    Raises
    ------
    mechdyn.errors.ModelError
        For a length that is not finite or out of its range, or a geometry outside the fits (a cone
        angle outside 1° to 89°).
    """
    grip = check_number("VDI 2230", "grip", grip, "m", positive=True)
    bearing_diameter = check_number("VDI 2230", "bearing_diameter", bearing_diameter, "m", positive=True)
    outer_diameter = check_number("VDI 2230", "outer_diameter", outer_diameter, "m", positive=True)
    beta_l = grip / bearing_diameter
    y = max(outer_diameter / bearing_diameter, 1.0)
    if tapped:
        phi = math.atan(0.348 + 0.013 * math.log(beta_l) + 0.193 * math.log(y))
    else:
        phi = math.atan(0.362 + 0.032 * math.log(beta_l / 2) + 0.153 * math.log(y))
    if not CONE_ANGLES[0] <= phi <= CONE_ANGLES[1]:
        raise ModelError(
            f"the fit gives a cone angle of {math.degrees(phi):.3g}° for l_K/d_W = {beta_l:.3g} and "
            f"D_A/d_W = {y:.3g}, outside 1° to 89°: check the grip and the diameters",
            element="VDI 2230",
            field="grip",
        )
    return phi


@dataclass(frozen=True)
class Layer:
    """One clamped layer: its thickness and material (top to bottom).

    Parameters
    ----------
    thickness : float or quantity
        Thickness along the bolt, m, from 1e-9 to 1e3 m.
    material : Material
        The layer's material (its E).
    """

    thickness: Any
    material: Material

    def __post_init__(self) -> None:
        t = si_field(self.material.name, "thickness", self.thickness, "m", positive=True)
        object.__setattr__(self, "thickness", t)


@dataclass(frozen=True)
class BoltedJoint:
    """A bolt clamping layers: a machine base on concrete with an anchor, or plates with a nut.

    Parameters
    ----------
    name : str
    diameter : float or quantity
        Nominal bolt diameter d, m.
    layers : sequence of Layer
        The clamped members, from the bolt head down.
    bolt_material : Material
    head_diameter : float or quantity
        Bearing diameter under the head or washer d_W, m (> hole).
    lower_bearing_diameter : float or quantity, optional
        Bearing diameter at the other end (nut, or the anchor's embedded head), m; by default d_W.
    hole_diameter : float or quantity, optional
        m; by default d.
    stress_area : float or quantity, optional
        Tensile stress area A_s of the thread, m²; by default the ISO metric value
        π/4 (d − 0.9382 P)² (ISO 898-1). The bolt's stiffness uses it for the free thread only
        (``thread_length``); the shank has its full area π d²/4.
    nut : {"nut", "tapped", "anchor"}
        What holds the lower end (VDI 2230 nut resilience 0.4 d, or 0.33 d).
    cone_angle : float or quantity or "vdi2230"
        Half-angle α of the pressure cones, rad or quantity, from 1° to 89°; ``"vdi2230"`` takes it
        from the joint's geometry.
    outer_diameter : float or quantity, optional
        Diameter D_A of the clamped parts, m; by default 3 d_W. A pressure cone that reaches it goes
        on as a sleeve of that diameter (VDI 2230 Part 1, 2015, §5.1.2.2: cone and sleeve where
        D_A < D_A,Gr = d_W + w l_K tan φ).
    pitch : float or quantity, optional
        Thread pitch P, m; by default the ISO 261 coarse pitch of the nominal diameter.
    thread_length : float or quantity, optional
        Length of free (unengaged) thread within the grip, m, from 0 to the grip. Without it the
        bolt is shank over the whole grip, as the published estimate takes it.
    """

    name: str
    diameter: Any
    layers: Sequence[Layer]
    bolt_material: Material
    head_diameter: Any
    lower_bearing_diameter: Any = None
    hole_diameter: Any = None
    stress_area: Any = None
    nut: str = "nut"
    cone_angle: Any = "30 deg"
    outer_diameter: Any = None
    pitch: Any = None
    thread_length: Any = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "layers", tuple(self.layers))
        if not self.layers:
            raise ModelError("a joint needs at least one clamped layer", element=self.name, field="layers")
        d = self._length("diameter", self.diameter)
        object.__setattr__(self, "diameter", d)
        hole = d if self.hole_diameter is None else self._length("hole_diameter", self.hole_diameter)
        if hole < d:
            raise ModelError(
                f"{hole:g} m is smaller than the bolt ({d:g} m)", element=self.name, field="hole_diameter"
            )
        object.__setattr__(self, "hole_diameter", hole)
        for f in ("head_diameter", "lower_bearing_diameter"):
            v = getattr(self, f)
            v = self.head_diameter if v is None else v
            v = self._length(f, v)
            if v <= hole:
                raise ModelError(
                    f"{show(v, 'm', 'mm')} is not larger than the hole ({show(hole, 'm', 'mm')}): a "
                    "washer or head must be wider than the bolt to bear on the members",
                    element=self.name,
                    field=f,
                )
            object.__setattr__(self, f, v)
        P = coarse_pitch(self.name, d) if self.pitch is None else self._length("pitch", self.pitch)
        if not P < d / 1.2269:
            raise ModelError(
                f"pitch {show(P, 'm', 'mm')} leaves no core in a {show(d, 'm', 'mm')} bolt (minor diameter "
                "d − 1.2269 P, ISO 68-1); check the pitch",
                element=self.name,
                field="pitch",
            )
        object.__setattr__(self, "pitch", P)
        if self.stress_area is None:
            object.__setattr__(self, "stress_area", math.pi / 4 * (d - 0.9382 * P) ** 2)
        else:
            a = si_field(self.name, "stress_area", self.stress_area, "m^2", positive=True)
            if not 0 < a <= math.pi / 4 * d**2:
                raise ModelError(
                    f"{a:g} m² must be positive and below π d²/4", element=self.name, field="stress_area"
                )
            object.__setattr__(self, "stress_area", a)
        if self.nut not in ("nut", "tapped", "anchor"):
            raise ModelError(
                f"{self.nut!r} must be 'nut', 'tapped' or 'anchor'", element=self.name, field="nut"
            )
        outer = (
            3 * self.head_diameter
            if self.outer_diameter is None
            else self._length("outer_diameter", self.outer_diameter)
        )
        object.__setattr__(self, "outer_diameter", outer)
        if isinstance(self.cone_angle, str) and self.cone_angle.strip().lower() == "vdi2230":
            a = vdi2230_cone_angle(self.grip, self.head_diameter, outer, tapped=self.nut == "tapped")
        else:
            a = _cone_angle(self.name, "cone_angle", self.cone_angle)
        object.__setattr__(self, "cone_angle", a)
        if self.thread_length is not None:
            lt = si_field(self.name, "thread_length", self.thread_length, "m", nonnegative=True)
            if not lt <= self.grip:
                raise ModelError(
                    f"{show(lt, 'm', 'mm')} of free thread is more than the grip "
                    f"({show(self.grip, 'm', 'mm')})",
                    element=self.name,
                    field="thread_length",
                )
            object.__setattr__(self, "thread_length", lt)

    def _length(self, f: str, v: Any) -> float:
        return si_field(self.name, f, v, "m", positive=True)

    @property
    def grip(self) -> float:
        """Clamped length l_K, m."""
        return sum(layer.thickness for layer in self.layers)

    # -- members -----------------------------------------------------------------------------
    def frusta(self, alpha: float | None = None) -> list[dict[str, float]]:
        """The cone frusta of the member stack, each with its layer, thickness, D, E and stiffness.

        A cone grows from the head down and one from the lower bearing face up; they meet at
        mid-grip. Each cone is cut wherever it crosses a layer boundary, and where it reaches the
        parts' outer diameter D_A it goes on as a sleeve, k = E π (D_A² − d_h²)/(4 t) (the
        cone-and-sleeve body of VDI 2230 Part 1, 2015, Eq. 5.1/23; ``"sleeve": True``).

        Parameters
        ----------
        alpha : float, optional
            Cone half-angle, rad, from 1° to 89° (default: the joint's).
        """
        a = self.cone_angle if alpha is None else _cone_angle(self.name, "alpha", alpha)
        half = self.grip / 2
        out = []
        bounds = [0.0]
        for layer in self.layers:
            bounds.append(bounds[-1] + layer.thickness)
        for start, direction, D0 in (
            (0.0, 1, self.head_diameter),
            (self.grip, -1, self.lower_bearing_diameter),
        ):
            cuts = sorted({start, half, *[b for b in bounds if min(start, half) < b < max(start, half)]})
            if direction < 0:
                cuts = cuts[::-1]
            for z0, z1 in pairwise(cuts):
                t = abs(z1 - z0)
                if t <= 1e-12 * self.grip:  # a boundary at mid-grip but for round-off: nothing there
                    continue
                mid = 0.5 * (z0 + z1)
                i = next(k for k in range(len(self.layers)) if bounds[k] <= mid <= bounds[k + 1])
                D = min(D0 + 2 * abs(z0 - start) * math.tan(a), self.outer_diameter)
                E = self.layers[i].material.youngs_modulus
                # the cone reaches the parts' outer diameter after t_cone; beyond, a sleeve of D_A
                t_cone = min(t, (self.outer_diameter - D) / (2 * math.tan(a)))
                row = {"layer": i, "material": self.layers[i].material.name, "youngs_modulus_Pa": E}
                if t_cone > 0:
                    k = frustum_stiffness(E, self.hole_diameter, D, t_cone, a)
                    out.append(row | {"thickness_m": t_cone, "diameter_m": D, "stiffness_N_per_m": k})
                if t - t_cone > 0:
                    DA, dh, ts = self.outer_diameter, self.hole_diameter, t - t_cone
                    k = E * math.pi * (DA**2 - dh**2) / (4 * ts)
                    out.append(
                        row | {"thickness_m": ts, "diameter_m": DA, "stiffness_N_per_m": k, "sleeve": True}
                    )
        return out

    def member_stiffness(self, alpha: float | None = None) -> float:
        """k_m, the frusta in series, N/m.

        Parameters
        ----------
        alpha : float, optional
            Cone half-angle, rad, from 1° to 89° (default: the joint's).
        """
        return 1.0 / sum(1.0 / f["stiffness_N_per_m"] for f in self.frusta(alpha))

    # -- bolt ----------------------------------------------------------------------------------
    @property
    def bolt_stiffness(self) -> float:
        """k_b, N/m: the published estimate A_d E / L_eq with the shank area A_d = π d²/4 and
        L_eq = L + (1.95 − β/2 − ν) d; with ``thread_length`` l_t, shank and free thread in series,
        1/k_b = (L_eq − l_t)/(E A_d) + l_t/(E A_s) (Shigley Eq. 8-17)."""
        m = self.bolt_material
        beta = self.head_diameter / self.diameter
        L_eq = self.grip + (1.95 - beta / 2 - m.poissons_ratio) * self.diameter
        if not L_eq > 0:
            raise ModelError(
                f"the bearing diameter {show(self.head_diameter, 'm', 'mm')} is out of proportion to the "
                f"{show(self.diameter, 'm', 'mm')} bolt and the {show(self.grip, 'm', 'mm')} grip: the "
                "published estimate's equivalent length L + (1.95 − d_W/(2d) − ν) d is not positive",
                element=self.name,
                field="head_diameter",
            )
        lt = 0.0 if self.thread_length is None else self.thread_length
        E = m.youngs_modulus
        return 1.0 / ((L_eq - lt) / (E * self.shank_area) + lt / (E * self.stress_area))

    @property
    def shank_area(self) -> float:
        """A_d = π d²/4, the bolt's nominal (shank) cross-section, m²."""
        return math.pi / 4 * self.diameter**2

    def bolt_stiffness_vdi2230(self, shank_length: float | None = None) -> float:
        """k_b from the VDI 2230 section-by-section resilience, N/m.

        The grip is plain shank (A_N) over ``shank_length`` (by default the grip less the joint's
        ``thread_length``, or less one diameter where that is not given) and free loaded thread
        (A_d3) over the rest; plus head, engaged thread and nut or tapped hole.

        Parameters
        ----------
        shank_length : float, optional
            Length of plain shank in the grip, m, not negative (at most the grip counts).
        """
        if shank_length is not None:
            shank_length = si_field(self.name, "shank_length", shank_length, "m", nonnegative=True)
        d, E = self.diameter, self.bolt_material.youngs_modulus
        A_N = math.pi / 4 * d**2
        d3 = d - 1.2269 * self.pitch  # ISO 68-1 minor diameter of the external thread
        A_d3 = math.pi / 4 * d3**2
        if shank_length is not None:
            ls = min(shank_length, self.grip)
        elif self.thread_length is not None:
            ls = self.grip - self.thread_length
        else:
            ls = max(self.grip - d, 0.0)
        lt = self.grip - ls
        nut = 0.4 if self.nut == "nut" else 0.33
        resilience = (0.5 * d + nut * d) / (E * A_N) + ls / (E * A_N) + (lt + 0.5 * d) / (E * A_d3)
        return 1.0 / resilience

    # -- the joint ---------------------------------------------------------------------------
    @property
    def joint_stiffness(self) -> float:
        """k_t = k_b + k_m for an external load (bolt and members in parallel), N/m."""
        return self.bolt_stiffness + self.member_stiffness()

    # -- the interface every mount estimate shares (mechdyn.mounts.types.MountEstimate) ----------
    adjusts_height = False
    damps = False
    loss_factor = 0.0
    lateral_stiffness = None  # friction and dowels: not estimated from the drawing

    @property
    def stiffness(self) -> float:
        """Along the bolt's axis: the joint stiffness k_b + k_m, N/m."""
        return self.joint_stiffness

    @property
    def load_factor(self) -> float:
        """C = k_b / (k_b + k_m): the share of an external load the bolt takes."""
        kb = self.bolt_stiffness
        return kb / (kb + self.member_stiffness())

    def breakdown(self) -> dict[str, Any]:
        """Every part of the estimate (SI)."""
        return {
            "bolt_stiffness_N_per_m": self.bolt_stiffness,
            "bolt_free_thread_m": 0.0 if self.thread_length is None else self.thread_length,
            "bolt_stiffness_vdi2230_N_per_m": self.bolt_stiffness_vdi2230(),
            "member_stiffness_N_per_m": self.member_stiffness(),
            "joint_stiffness_N_per_m": self.joint_stiffness,
            "load_factor": self.load_factor,
            "cone_half_angle_deg": math.degrees(self.cone_angle),
            "grip_m": self.grip,
            "frusta": self.frusta(),
        }
