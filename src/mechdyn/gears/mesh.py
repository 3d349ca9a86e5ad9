"""A spur gear pair: path of contact, contact ratio, tooth-pair and mesh stiffness over a mesh cycle.

Contact moves along the line of action from A (the gear's tip circle) to E (the pinion's tip
circle); with T₁ and T₂ the tangent points on the base circles, a contact at distance s from T₁ lies
on the pinion at r₁ = √(r_b1² + s²) and on the gear at r₂ = √(r_b2² + (T₁T₂ − s)²), T₁T₂ = a sin α_w.
Teeth pairs follow each other at the base pitch p_b, so the mesh stiffness over one cycle is the sum
of the pair stiffnesses of every pair in contact, k(x) = Σ_j k_pair(s_A + x + j p_b) for
s_A + x + j p_b ≤ s_E (the contact ratio ε_α = g_α / p_b says how many). E.g. Niemann & Winter,
*Maschinenelemente* II, and Yang & Lin (1987) for the stiffness of one pair.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from mechdyn.checks import check_count, check_number
from mechdyn.errors import ModelError
from mechdyn.gears.geometry import SpurGear, inverse_involute, involute
from mechdyn.gears.profile import ProfileTooth
from mechdyn.gears.tooth import TruncatedTooth, hertz_compliance
from mechdyn.units import convert, show

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["MAX_POINTS", "GearPair", "MeshCycle"]

MAX_POINTS = 100_000
"""The most positions a mesh cycle may be evaluated at (each is one or two tooth-pair solutions)."""


@dataclass(frozen=True)
class GearPair:
    """Two external spur gears in mesh.

    Parameters
    ----------
    pinion, gear : SpurGear
        Equal module and pressure angle.
    center_distance : float or quantity, optional
        a, m; by default the zero-backlash distance for the profile shifts.
    tooth_model : {"involute", "truncated"}
        ``involute`` (default): the tooth as the basic rack generates it, root fillet and involute,
        with the potential-energy terms integrated over its thickness
        (:meth:`SpurGear.profile_tooth`). ``truncated``: the published truncated-triangle tooth
        (closed forms), the fillet taken at the thickness where the involute starts.
    """

    pinion: SpurGear
    gear: SpurGear
    center_distance: float | None = None
    tooth_model: Literal["truncated", "involute"] = "involute"

    def __post_init__(self) -> None:
        p, g = self.pinion, self.gear
        if self.tooth_model not in ("truncated", "involute"):
            raise ModelError(
                f"tooth model {self.tooth_model!r} must be 'truncated' or 'involute'", element=g.name
            )
        if not math.isclose(p.module, g.module, rel_tol=1e-9) or not math.isclose(
            p.pressure_angle, g.pressure_angle, rel_tol=1e-9
        ):
            raise ModelError(
                f"pinion (m {show(p.module, 'm', 'mm')}, α {math.degrees(p.pressure_angle):g}°) and gear "
                f"(m {show(g.module, 'm', 'mm')}, α {math.degrees(g.pressure_angle):g}°) must share module "
                "and pressure angle",
                element=g.name,
                field="module",
            )
        if self.center_distance is None:
            # zero backlash: inv α_w = inv α + 2 tan α (x₁ + x₂)/(z₁ + z₂)
            inv_w = involute(p.pressure_angle) + 2 * math.tan(p.pressure_angle) * (
                p.profile_shift + g.profile_shift
            ) / (p.teeth + g.teeth)
            alpha_w = inverse_involute(inv_w)
            object.__setattr__(self, "center_distance", (p.base_radius + g.base_radius) / math.cos(alpha_w))
        a = self.center_distance
        assert a is not None  # set just above when not given
        if not p.base_radius + g.base_radius < a < p.tip_radius + g.tip_radius:
            raise ModelError(
                f"centre distance {a:g} m does not let the gears mesh",
                element=g.name,
                field="center_distance",
            )
        if self.contact_ratio < 1.0:
            raise ModelError(
                f"contact ratio ε_α = {self.contact_ratio:.3f} is below 1: the mesh cannot run continuously",
                element=g.name,
            )
        for gear, s in ((p, self.path_start), (g, self.line_of_action - self.path_end)):
            r = math.hypot(gear.base_radius, s)
            if r < gear.form_radius * (1 - 1e-9) or s < 0:
                raise ModelError(
                    f"contact reaches radius {show(r, 'm', 'mm', '.3f')}, below the start of the involute "
                    f"({show(gear.form_radius, 'm', 'mm', '.3f')}): interference; use a profile shift",
                    element=gear.name,
                    field="profile_shift",
                )

    # -- kinematics of the contact -----------------------------------------------------------
    @property
    def working_pressure_angle(self) -> float:
        """α_w = acos((r_b1 + r_b2)/a), rad."""
        a = self.center_distance
        assert a is not None  # set in __post_init__ when not given
        return math.acos((self.pinion.base_radius + self.gear.base_radius) / a)

    @property
    def line_of_action(self) -> float:
        """T₁T₂ = a sin α_w, m."""
        a = self.center_distance
        assert a is not None  # set in __post_init__ when not given
        return a * math.sin(self.working_pressure_angle)

    @property
    def path_start(self) -> float:
        """s_A: where contact starts (gear tip), distance from T₁, m."""
        g = self.gear
        return self.line_of_action - math.sqrt(g.tip_radius**2 - g.base_radius**2)

    @property
    def path_end(self) -> float:
        """s_E: where contact ends (pinion tip), distance from T₁, m."""
        p = self.pinion
        return math.sqrt(p.tip_radius**2 - p.base_radius**2)

    @property
    def contact_ratio(self) -> float:
        """Transverse contact ratio ε_α = g_α / p_b."""
        return (self.path_end - self.path_start) / self.pinion.base_pitch

    @property
    def ratio(self) -> float:
        """z₂ / z₁."""
        return self.gear.teeth / self.pinion.teeth

    @cached_property
    def teeth(self) -> tuple[TruncatedTooth | ProfileTooth, TruncatedTooth | ProfileTooth]:
        """The two teeth of the chosen tooth model."""
        if self.tooth_model == "involute":
            return self.pinion.profile_tooth(), self.gear.profile_tooth()
        return self.pinion.tooth(), self.gear.tooth()

    # -- stiffness ---------------------------------------------------------------------------
    def pair_compliances(self, s: float) -> dict[str, float]:
        """Compliance terms of one tooth pair in contact at ``s``, m/N.

        Parameters
        ----------
        s : float
            Distance of the contact from T₁ (the pinion's tangent point) along the line of action, m,
            within the path of contact (:attr:`path_start` to :attr:`path_end`).

        Keys ``pinion_<term>``, ``gear_<term>`` for each tooth term, ``hertz`` and ``total``.

        Raises
        ------
        mechdyn.errors.ModelError
            For an ``s`` that is not finite or off the path of contact.
        """
        p, g = self.pinion, self.gear
        s = check_number(p.name, "s", s, "m")
        lo, hi = self.path_start, self.path_end
        slack = 1e-9 * (hi - lo)
        if not lo - slack <= s <= hi + slack:
            raise ModelError(
                f"s = {s:g} m is off the path of contact, {lo:g} m to {hi:g} m from the pinion's "
                "tangent point",
                element=p.name,
                field="s",
            )
        t1, t2 = self.teeth
        r1 = math.hypot(p.base_radius, s)
        r2 = math.hypot(g.base_radius, self.line_of_action - s)
        out: dict[str, float] = {}
        for label, gear, tooth, r in (("pinion", p, t1, r1), ("gear", g, t2, r2)):
            for k, v in tooth.compliances(r - gear.root_radius, gear.load_angle(r)).items():
                out[f"{label}_{k}"] = v
        out["hertz"] = hertz_compliance(
            min(p.face_width, g.face_width),
            p.youngs_modulus,
            p.poisson_ratio,
            g.youngs_modulus,
            g.poisson_ratio,
        )
        out["total"] = sum(out.values())
        return out

    def pair_stiffness(self, s: float) -> float:
        """Stiffness of one tooth pair in contact at ``s``, N/m (both teeth in series, Hertz once).

        Parameters
        ----------
        s : float
            Distance of the contact from T₁ along the line of action, m.
        """
        return 1.0 / self.pair_compliances(s)["total"]

    @property
    def pitch_point(self) -> float:
        """s at the pitch point, r_b1 tan α_w, m."""
        return self.pinion.base_radius * math.tan(self.working_pressure_angle)

    def mesh_cycle(self, points: int = 400) -> MeshCycle:
        """Mesh stiffness over one mesh cycle (the pinion turning one base pitch).

        Parameters
        ----------
        points : int
            Positions per cycle, a whole number from 4 to :data:`MAX_POINTS`.
        """
        points = check_count(self.pinion.name, "points", points, low=4, high=MAX_POINTS, what="positions")
        pb = self.pinion.base_pitch
        x = np.linspace(0.0, pb, points, endpoint=False)
        k = np.zeros(points)
        pairs = np.zeros(points, dtype=int)
        s_end = self.path_end * (1 + 1e-12)
        for i, xi in enumerate(x):
            s = self.path_start + xi
            while s <= s_end:
                k[i] += self.pair_stiffness(s)
                pairs[i] += 1
                s += pb
        return MeshCycle(self, x, k, pairs)


@dataclass(frozen=True)
class MeshCycle:
    """Mesh stiffness over one mesh cycle.

    Attributes
    ----------
    pair : GearPair
    position : ndarray
        Travel of the contact along the line of action from the start of contact, m (one base pitch).
    stiffness : ndarray
        Mesh stiffness along the line of action, N/m.
    pairs_in_contact : ndarray
        1 or 2 (or more for high contact ratios).
    """

    pair: GearPair
    position: np.ndarray
    stiffness: np.ndarray
    pairs_in_contact: np.ndarray

    @property
    def mean(self) -> float:
        """Mean mesh stiffness over the cycle, N/m."""
        return float(self.stiffness.mean())

    @property
    def fluctuation(self) -> float:
        """(max − min) / mean."""
        return float((self.stiffness.max() - self.stiffness.min()) / self.stiffness.mean())

    @property
    def pinion_angle(self) -> np.ndarray:
        """Pinion rotation through the cycle, rad (position / r_b1)."""
        return self.position / self.pair.pinion.base_radius

    @property
    def double_contact_share(self) -> float:
        """Share of the cycle with more than one pair in contact (ε_α − 1 for 1 < ε_α < 2)."""
        return float(np.mean(self.pairs_in_contact > 1))

    def to_frame(self) -> pd.DataFrame:
        """The cycle as a table: position along the line of action (m), pinion angle (rad), pairs in
        contact and mesh stiffness (N/m), one row per position."""
        import pandas as pd

        return pd.DataFrame(
            {
                "position_m": self.position,
                "pinion_angle_rad": self.pinion_angle,
                "stiffness_N_per_m": self.stiffness,
                "pairs_in_contact": self.pairs_in_contact,
            }
        )

    def plot(self, ax: Any = None) -> Any:
        """Mesh stiffness over the cycle; returns the matplotlib axes.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Axes to draw on (default: a new figure).
        """
        from mechdyn.plotting import new_axes

        ax = new_axes(ax)
        cycle = self.position / self.pair.pinion.base_pitch
        ax.plot(cycle, convert(self.stiffness, "N/m", "N/µm"), label="mesh stiffness")
        mean = show(self.mean, "N/m", "N/µm", ".4g")
        ax.axhline(convert(self.mean, "N/m", "N/µm"), color="0.5", ls="--", label=f"mean {mean}")
        ax.set_xlabel("mesh cycle (contact travel / base pitch)")
        ax.set_ylabel("stiffness along the line of action (N/µm)")
        ax.set_title(
            f"z {self.pair.pinion.teeth}/{self.pair.gear.teeth}, "
            f"m {show(self.pair.pinion.module, 'm', 'mm')}, "
            f"ε_α = {self.pair.contact_ratio:.3f}"
        )
        ax.legend(fontsize="small")
        return ax
