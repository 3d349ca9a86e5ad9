"""A gear pair: path of contact, contact ratio, tooth-pair and mesh stiffness over a mesh cycle.

Contact moves along the line of action from A (the gear's tip circle) to E (the pinion's tip
circle); with T₁ and T₂ the tangent points on the base circles, a contact at distance s from T₁ lies
on the pinion at r₁ = √(r_b1² + s²) and on the gear at r₂ = √(r_b2² + (T₁T₂ − s)²), T₁T₂ = a sin α_w.
Teeth pairs follow each other at the base pitch p_b, so the mesh stiffness over one cycle is the sum
of the pair stiffnesses of every pair in contact, k(x) = Σ_j k_pair(s_A + x + j p_b) for
s_A + x + j p_b ≤ s_E (the contact ratio ε_α = g_α / p_b says how many). E.g. Niemann & Winter,
*Maschinenelemente* II, and Yang & Lin (1987) for the stiffness of one pair.

Internal pairs (an external pinion in a ring gear): a = r_w2 − r_w1, cos α_w = (r_b2 − r_b1)/a, both
tangent points on the same side, the contact at s from T₁ lies on the ring at
r₂ = √(r_b2² + (T₁T₂ + s)²), and contact runs from the ring's tip circle, s_A = √(r_a2² − r_b2²) − T₁T₂,
to the pinion's: ε_α = [√(r_a1² − r_b1²) − √(r_a2² − r_b2²) + a sin α_w] / p_b (ISO 21771:2007, 5.4,
with z₂ < 0; Niemann & Winter II, 21.2). Tip interference of internal pairs (fouling of the tips
outside the path of contact) is not checked.

Helical pairs: the transverse section is a spur pair (see :mod:`mechdyn.gears.geometry`); the face is
cut into thin transverse slices, the slice at axial position z meshing as the transverse section
shifted along the path of contact by z tan β_b, so that over the face the contact lines sweep
b tan β_b = ε_β p_bt (overlap ratio ε_β = b sin β/(π m_n)). The mesh stiffness is the sum of the
slices' stiffnesses, k(x) = cos β_b (1/b) ∫₀^b k_t(x + z tan β_b) dz, with k_t the transverse
section's mesh stiffness over the whole face width (the slicing method of e.g. Wan et al., *Mech.
Mach. Theory* 92 (2015) 447–463, here in the limit of thin slices: the integral is exact for k_t
interpolated linearly between the cycle's positions). Each slice's stiffness along the transverse line of
action is the transverse tooth pair's per unit width times cos β_b: a modelling choice, the
counterpart of ISO 6336-1's cos β on c′ (clause 9, Method B): the transverse section's teeth are thicker
than the normal section's (s_t = s_n / cos β), and the normal force has the transverse component
F_n cos β_b that the section's model takes. With ε_β whole, the contact length, and so k, is
constant over the cycle.

A ring gear with ``rim_thickness`` and ``rim_supports`` (:meth:`SpurGear.ring_rim`): its rim, a curved
beam clamped between its supports (Chen & Shao, *Mech. Mach. Theory* 69 (2013) 1–12;
:mod:`mechdyn.gears.ring`), is in series with the whole mesh, k(x) = (1/Φ) ∫₀^Φ dθ / (1/k_teeth(x) +
c_rim(θ)): the teeth in contact, a base pitch apart, load the rim at one place, which travels evenly
along each span between two supports as the carrier turns (the mean over the span; the slow change
with the carrier's angle is not kept as a function of time). The rim's compliance c_rim is taken for
the load at the ring's working pitch circle (its load angle and moment arm there).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, replace
from functools import cached_property
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from mechdyn.checks import check_count, check_number
from mechdyn.errors import ModelError
from mechdyn.gears.geometry import SpurGear, inverse_involute, involute
from mechdyn.gears.profile import ProfileTooth
from mechdyn.gears.ring import RingRim
from mechdyn.gears.tooth import TruncatedTooth, hertz_compliance
from mechdyn.plotting import legend
from mechdyn.units import convert, show
from mechdyn.units import si_field as _q

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["MAX_POINTS", "GearPair", "MeshCycle"]

MAX_POINTS = 100_000
"""The most positions a mesh cycle may be evaluated at (each is one or two tooth-pair solutions)."""


@dataclass(frozen=True)
class GearPair:
    """Two gears in mesh: spur or helical, external, or an external pinion in an internal gear.

    Parameters
    ----------
    pinion, gear : SpurGear
        Equal module, pressure angle and helix angle; the gear may be internal (a ring gear with more
        teeth than the pinion; with ``rim_thickness`` and ``rim_supports`` its rim yields, see
        :attr:`ring_rim`), the pinion may not.
    center_distance : float or quantity, optional
        a, m; by default the zero-backlash distance for the profile shifts (r_w2 − r_w1 for an internal
        pair).
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
        if not math.isclose(p.helix_angle, g.helix_angle, rel_tol=1e-9, abs_tol=1e-12):
            raise ModelError(
                f"pinion (β {math.degrees(p.helix_angle):g}°) and gear (β {math.degrees(g.helix_angle):g}°) "
                "must share the helix angle (of opposite hands for an external pair, the same hand for an "
                "internal one)",
                element=g.name,
                field="helix_angle",
            )
        if p.internal:
            raise ModelError(
                "the pinion cannot be internal: give the ring gear as the pair's gear",
                element=p.name,
                field="internal",
            )
        if g.internal and g.teeth <= p.teeth:
            raise ModelError(
                f"an internal gear of {g.teeth} teeth cannot mesh around a pinion of {p.teeth}: give the "
                "ring more teeth than the pinion",
                element=g.name,
                field="teeth",
            )
        sign = -1.0 if g.internal else 1.0
        if self.center_distance is None:
            # zero backlash: inv α_wt = inv α_t + 2 tan α_n (x₁ + x₂)/(z₁ + z₂), z₂ < 0 for an internal gear
            inv_w = involute(p.transverse_pressure_angle) + 2 * math.tan(p.pressure_angle) * (
                p.profile_shift + g.profile_shift
            ) / (p.teeth + sign * g.teeth)
            if inv_w <= 0:
                raise ModelError(
                    f"profile shifts x₁ + x₂ = {p.profile_shift + g.profile_shift:g} leave no working "
                    "pressure angle; give smaller shifts or a center_distance",
                    element=g.name,
                    field="profile_shift",
                )
            alpha_w = inverse_involute(inv_w)
            object.__setattr__(
                self, "center_distance", (g.base_radius + sign * p.base_radius) / math.cos(alpha_w)
            )
        a = self.center_distance
        assert a is not None  # set just above when not given
        a = _q(g.name, "center_distance", a, "m", positive=True)
        object.__setattr__(self, "center_distance", a)
        low = g.base_radius + sign * p.base_radius
        if g.internal:
            meshes = low < a and g.tip_radius < a + p.tip_radius
        else:
            meshes = low < a < p.tip_radius + g.tip_radius
        if not meshes:
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
        for gear, r, s in (
            (p, math.hypot(p.base_radius, self.path_start), self.path_start),
            (g, self.gear_contact_radius(self.path_end), self.line_of_action - self.path_end),
        ):
            if gear.internal:
                outside = r > gear.form_radius * (1 + 1e-9)
            else:
                outside = r < gear.form_radius * (1 - 1e-9) or s < 0
            if outside:
                edge = "beyond the root circle" if gear.internal else "below the start of the involute"
                raise ModelError(
                    f"contact reaches radius {show(r, 'm', 'mm', '.3f')}, {edge} "
                    f"({show(gear.form_radius, 'm', 'mm', '.3f')}): interference; use a profile shift",
                    element=gear.name,
                    field="profile_shift",
                )

    # -- kinematics of the contact -----------------------------------------------------------
    @property
    def internal(self) -> bool:
        """True for an external pinion in an internal gear."""
        return self.gear.internal

    @property
    def working_pressure_angle(self) -> float:
        """α_w = acos((r_b1 + r_b2)/a), acos((r_b2 − r_b1)/a) for an internal pair, rad (transverse)."""
        a = self.center_distance
        assert a is not None  # set in __post_init__ when not given
        if self.internal:
            return math.acos((self.gear.base_radius - self.pinion.base_radius) / a)
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
        if self.internal:
            return math.sqrt(g.tip_radius**2 - g.base_radius**2) - self.line_of_action
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
    def face_width(self) -> float:
        """Common face width b = min(b₁, b₂), m."""
        return min(self.pinion.face_width, self.gear.face_width)

    @property
    def helix_angle(self) -> float:
        """β, rad (0 for spur gears)."""
        return self.pinion.helix_angle

    @property
    def overlap_ratio(self) -> float:
        """ε_β = b sin β / (π m_n) (ISO 21771:2007, 5.4.3); 0 for spur gears."""
        return self.face_width * math.sin(self.helix_angle) / (math.pi * self.pinion.module)

    @property
    def total_contact_ratio(self) -> float:
        """ε_γ = ε_α + ε_β."""
        return self.contact_ratio + self.overlap_ratio

    def gear_contact_radius(self, s: float) -> float:
        """Radius on the gear of the contact at ``s``, m: √(r_b2² + (T₁T₂ − s)²), with T₁T₂ + s for an
        internal gear.

        Parameters
        ----------
        s : float
            Distance of the contact from T₁ along the line of action, m.
        """
        arm = self.line_of_action + s if self.internal else self.line_of_action - s
        return math.hypot(self.gear.base_radius, arm)

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

        Keys ``pinion_<term>``, ``gear_<term>`` for each tooth term, ``hertz`` and ``total``: the
        teeth's; a ring gear's flexible rim is in series with the whole mesh, not with one pair
        (:meth:`mesh_cycle`).

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
        r2 = self.gear_contact_radius(s)
        out: dict[str, float] = {}
        for label, gear, tooth, r in (("pinion", p, t1, r1), ("gear", g, t2, r2)):
            for k, v in tooth.compliances(gear.load_height(r), gear.load_angle(r)).items():
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
        """Mesh stiffness over one mesh cycle (the pinion turning one transverse base pitch).

        Spur pairs sum the pairs in contact at each position; helical pairs integrate the transverse
        section's cycle over the face (the slicing of the module's notes); a ring gear's flexible rim
        (:attr:`ring_rim`) is then put in series with the whole mesh, averaged over a span between
        its supports (the module's notes).

        Parameters
        ----------
        points : int
            Positions per cycle, a whole number from 4 to :data:`MAX_POINTS`.
        """
        points = check_count(self.pinion.name, "points", points, low=4, high=MAX_POINTS, what="positions")
        return _mesh_cycle(self, points)

    @property
    def ring_rim(self) -> RingRim | None:
        """The ring gear's flexible rim (:meth:`SpurGear.ring_rim`), None for a rigid rim or an external
        pair."""
        return self.gear.ring_rim()

    def rim_load(self) -> tuple[float, float]:
        """Load angle φ (rad) and base radius (m) of the ring at its working pitch circle, where the
        rim's compliance along the line of action is taken (:meth:`RingRim.compliance`)."""
        g = self.gear
        return g.load_angle(self.gear_contact_radius(self.pitch_point)), g.base_radius

    def rigid_rim(self) -> GearPair:
        """The same pair with the ring's rim rigid (and no blank data): its teeth alone."""
        if self.ring_rim is None:
            return self
        rigid = replace(self.gear, rim_thickness=None, web_width=None, rim_supports=None)
        return replace(self, gear=rigid)

    def _mesh_cycle(self, points: int) -> MeshCycle:
        rim = self.ring_rim
        if rim is not None:  # the teeth's cycle (worked out once), then the rim in series with it
            teeth = _mesh_cycle(self.rigid_rim(), points)
            k = rim.series_stiffness(teeth.stiffness, *self.rim_load())
            return MeshCycle(self, teeth.position, k, teeth.pairs_in_contact)
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
        if not self.helix_angle:
            return MeshCycle(self, x, k, pairs)
        sweep = self.face_width * math.tan(self.pinion.base_helix_angle)  # ε_β p_bt
        k_helical = math.cos(self.pinion.base_helix_angle) * _window_mean(k, pb, sweep)
        # pairs whose contact line lies on the face somewhere: -sweep < x + j p_b <= g_α
        g_alpha = self.path_end - self.path_start
        j = np.arange(-math.ceil(sweep / pb) - 1, math.ceil(g_alpha / pb) + 2)
        start = x[:, None] + j[None, :] * pb
        on_face = (start > -sweep * (1 - 1e-12)) & (start <= g_alpha * (1 + 1e-12))
        return MeshCycle(self, x, k_helical, on_face.sum(axis=1))


def _window_mean(k: np.ndarray, period: float, window: float) -> np.ndarray:
    """(1/w) ∫₀^w k(x_i + u) du at each x_i = i p/n of a periodic k sampled there, k interpolated
    linearly between samples (exact for that interpolant; the thin-slice limit of the slicing method).

    Parameters
    ----------
    k : ndarray
        n samples over one period.
    period : float
        p, the period, m.
    window : float
        w > 0, the width of the window, m (any multiple of the period).
    """
    n = len(k)
    h = period / n
    k_next = np.roll(k, -1)
    cumulative = np.concatenate([[0.0], np.cumsum(0.5 * h * (k + k_next))])  # ∫₀^{x_i}, i = 0 … n
    # each window starts on a sample: count the whole steps it spans, then the part of the last one
    # (no difference of two large running integrals, which would cancel for a narrow window)
    steps = window / h
    whole = math.floor(steps)
    f = steps - whole
    i = np.arange(n)
    turns, j = np.divmod(i + whole, n)
    inside = turns * cumulative[n] + cumulative[j] - cumulative[i]
    return (inside + h * (f * k[j] + 0.5 * f * f * (k_next[j] - k[j]))) / window


@functools.lru_cache(maxsize=32)
def _mesh_cycle(pair: GearPair, points: int) -> MeshCycle:
    """A pair's mesh cycle, worked out once per pair and number of positions (a drivetrain file's
    meshes on one pair, its mean stiffness and its profile for a simulation, take the same); its
    arrays are read-only, being shared."""
    cycle = pair._mesh_cycle(points)
    for value in vars(cycle).values():
        if isinstance(value, np.ndarray):
            value.flags.writeable = False
    return cycle


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
        1 or 2 (or more for high contact ratios); for a helical pair, the tooth pairs in contact
        anywhere across the face.
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
        """Pinion rotation through the cycle, rad (position / r_b1, transverse)."""
        return self.position / self.pair.pinion.base_radius

    def profile(self, points: int | None = None) -> np.ndarray:
        """The mesh stiffness over one cycle relative to its mean, k(τ)/k̄, at τ = i/points, i = 0 …
        points − 1, dimensionless.

        τ is the mesh cycle's phase: 0 where the cycle starts (a tooth pair entering contact at the
        gear's tip, A), 1 one transverse base pitch later, when the next pair enters; τ grows with the
        pinion's rotation, τ = θ₁ r_b1 / p_b = θ₁ z₁ / (2π). The profile is periodic: k(τ + 1) = k(τ).
        A time integrator takes k(t) = k̄ · profile(τ(t)), τ(t) = z₁ θ₁(t)/(2π) mod 1, interpolating
        this array (it is sampled uniformly over [0, 1), without the end point).

        Parameters
        ----------
        points : int, optional
            Samples over the cycle, a whole number from 4 to :data:`MAX_POINTS`; by default the
            cycle's own positions, returned exactly (``stiffness / mean``); otherwise the cycle is
            interpolated linearly and periodically.

        Returns
        -------
        ndarray
            ``points`` values, mean about 1.
        """
        own = self.stiffness / self.mean
        if points is None:
            return own
        points = check_count(self.pair.pinion.name, "points", points, low=4, high=MAX_POINTS, what="samples")
        n = len(own)
        tau = np.arange(points) / points
        return np.interp(tau * n, np.arange(n + 1), np.append(own, own[0]))

    def harmonics(self, orders: int = 10) -> tuple[np.ndarray, np.ndarray]:
        """Fourier harmonics of the mesh stiffness, in orders of the mesh frequency.

        k(τ) = k̄ [1 + Σₙ aₙ cos(2π n τ + φₙ)], n = 1 … ``orders``, τ the cycle's phase (see
        :meth:`profile`), from the discrete Fourier transform of the cycle's samples (rfft: aₙ =
        2 abs(Xₙ)/X₀, φₙ = arg Xₙ).

        Parameters
        ----------
        orders : int
            Number of harmonics, a whole number from 1 to half the cycle's positions less one.

        Returns
        -------
        (ndarray, ndarray)
            Amplitudes aₙ relative to the mean (dimensionless) and phases φₙ (rad), for n = 1 …
            ``orders``.
        """
        n = len(self.stiffness)
        orders = check_count(self.pair.pinion.name, "orders", orders, low=1, high=n // 2 - 1, what="orders")
        spectrum = np.fft.rfft(self.stiffness)
        amplitude = 2.0 * np.abs(spectrum[1 : orders + 1]) / spectrum[0].real
        return amplitude, np.angle(spectrum[1 : orders + 1])

    def plot_harmonics(self, ax: Any = None, orders: int = 10) -> Any:
        """Bar chart of the harmonics' amplitudes relative to the mean (:meth:`harmonics`), in percent;
        returns the matplotlib axes.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Axes to draw on (default: a new figure).
        orders : int
            Number of harmonics shown.
        """
        from mechdyn.plotting import new_axes

        ax = new_axes(ax)
        amplitude, _ = self.harmonics(orders)
        n = np.arange(1, len(amplitude) + 1)
        ax.bar(n, 100.0 * amplitude, color="C0")
        ax.set_xticks(n)
        ax.set_xlabel("order of the mesh frequency")
        ax.set_ylabel("amplitude relative to the mean (%)")
        ax.set_title(f"harmonics of the mesh stiffness, {self._title()}")
        return ax

    def _title(self) -> str:
        pair = self.pair
        words = (
            f"z {pair.pinion.teeth}/{pair.gear.teeth}{' internal' if pair.internal else ''}, "
            f"m {show(pair.pinion.module, 'm', 'mm')}, ε_α = {pair.contact_ratio:.3f}"
        )
        if pair.helix_angle:
            words += f", β = {math.degrees(pair.helix_angle):.4g}°, ε_β = {pair.overlap_ratio:.3f}"
        return words

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
        ax.set_title(self._title())
        legend(ax, fontsize="small")
        return ax
