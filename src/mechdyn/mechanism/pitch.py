"""Pitch curves of gear pairs: circular, eccentric, elliptic and general noncircular gears.

A gear's pitch curve is r(θ) in its own frame (polar about its pivot). Two gears rolling without slip
at a fixed centre distance a touch on the line of centres: with gear 1 turned by ψ₁ from the drawing
(relative to the carrier that holds both pivots), the contact is at r₁(ψ₁) = r(β − ψ₁ − θ₀) from
pivot 1 (β: direction of the line of centres, θ₀: the gear's drawing orientation), and the mate turns
by dψ₂/dψ₁ = −r₁/(a − r₁) (external; Litvin & Fuentes, *Gear Geometry and Applied Theory*, ch. 16
"Noncircular gears"). The mate closes over one turn of gear 1 when the mean of r₁/(a − r₁) is 1;
:func:`closing_centre_distance` solves it. The law ψ₂ = g(ψ₁) = −(k ψ₁ + P(ψ₁)), with P periodic, is
held as a Fourier series of the sampled ratio, so g, g′ and g″ are smooth to round-off.

Checks: a pitch curve is convex where r² + 2 r′² − r r″ > 0 (θ-derivatives; a concave stretch would
need internal teeth and undercuts the generating rack); the pitch tangent leans from the normal of
the line of centres by ν = atan(r′/r), which adds to the working pressure angle as the pair turns.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np
from scipy.optimize import brentq

from mechdyn.errors import ModelError
from mechdyn.units import show

__all__ = [
    "PitchCurve",
    "PitchLaw",
    "circle",
    "closing_centre_distance",
    "conjugate",
    "eccentric_circle",
    "ellipse_about_focus",
    "mate_curve",
    "pitch_law",
    "report",
    "sampled",
]

_N = 4096  # samples of one turn for the Fourier representation


@dataclass(frozen=True)
class PitchCurve:
    """r(θ) of a gear about its pivot, with its θ-derivatives (callable on arrays, m).

    ``coefficients``, where the curve is a Fourier series already (:func:`sampled`), are its
    coefficients weighted for the real series, r(θ) = Re Σ_h c_h e^{ihθ} (h = 0, 1, …); otherwise
    they come from 4096 samples of ``radius`` over one turn.
    """

    name: str
    radius: Callable[[np.ndarray], np.ndarray]
    circular: bool = False
    coefficients: np.ndarray | None = field(default=None, compare=False, repr=False)

    @cached_property
    def _series(self) -> tuple[np.ndarray, np.ndarray]:
        """Fourier coefficients of r (weighted for the real series) and their orders, trimmed to
        the terms that matter."""
        if self.coefficients is not None:  # a series already: the same terms as its samples' FFT
            cw = np.asarray(self.coefficients, dtype=complex)
        else:
            c = np.fft.rfft(self.radius(2 * np.pi * np.arange(_N) / _N)) / _N
            w = np.where(np.arange(c.size) == 0, 1.0, 2.0)
            w[-1] = 1.0
            cw = c * w
        h = np.arange(cw.size)
        keep = np.nonzero(np.abs(cw) > 1e-14 * np.abs(cw).max())[0]  # above round-off
        n = int(keep.max()) + 1 if keep.size else 1
        return cw[:n], h[:n]

    @cached_property
    def _derivative_terms(self) -> tuple[np.ndarray, np.ndarray]:
        """The orders h and the (h, 3) coefficients of r, r′ and r″ in e^{ihθ}."""
        cw, h = self._series
        return h, np.stack([cw, 1j * h * cw, -(h**2) * cw], axis=-1)

    def derivatives(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """r, r′, r″ at θ, by the Fourier series of r over one turn (exact for smooth curves)."""
        h, terms = self._derivative_terms
        s = (np.exp(1j * np.multiply.outer(np.asarray(theta, dtype=float), h)) @ terms).real
        return s[..., 0], s[..., 1], s[..., 2]

    def convexity(self) -> float:
        """min over θ of (r² + 2r′² − r r″)/r²: positive for a convex curve."""
        th = 2 * np.pi * np.arange(720) / 720
        r, r1, r2 = self.derivatives(th)
        return float(np.min((r**2 + 2 * r1**2 - r * r2) / r**2))

    def length(self) -> float:
        """Perimeter, m: ∫ √(r² + r′²) dθ."""
        th = 2 * np.pi * np.arange(_N) / _N
        r, r1, _ = self.derivatives(th)
        return float(np.mean(np.sqrt(r**2 + r1**2)) * 2 * np.pi)


def circle(radius: float) -> PitchCurve:
    """A circular gear of pitch radius ``radius`` (m)."""
    if not radius > 0:
        raise ModelError(f"{radius:g} m must be positive", element="pitch curve", field="radius")
    return PitchCurve("circle", lambda th: np.full(np.shape(th), float(radius)), circular=True)


def eccentric_circle(radius: float, eccentricity: float) -> PitchCurve:
    """A circle of radius ρ pivoted at e from its centre (θ = 0 towards the centre):
    r(θ) = e cos θ + √(ρ² − e² sin² θ) (SPEC §6)."""
    rho, e = float(radius), float(eccentricity)
    if not (rho > 0 and 0 <= e < rho):
        raise ModelError(
            f"need 0 ≤ e < ρ (e = {e:g} m, ρ = {rho:g} m)", element="pitch curve", field="eccentricity"
        )
    return PitchCurve(
        "eccentric circle",
        lambda th: e * np.cos(th) + np.sqrt(rho**2 - (e * np.sin(th)) ** 2),
        circular=e == 0,
    )


def ellipse_about_focus(semi_major: float, eccentricity: float) -> PitchCurve:
    """An ellipse turning about a focus: r(θ) = A(1 − ε²)/(1 − ε cos θ) (θ = 0 towards the far vertex).

    Two equal ellipses about their foci are exact conjugates at centre distance 2A.
    """
    A, eps = float(semi_major), float(eccentricity)
    if not (A > 0 and 0 <= eps < 1):
        raise ModelError(
            f"need A > 0 and 0 ≤ ε < 1 (got {A:g}, {eps:g})", element="pitch curve", field="eccentricity"
        )
    return PitchCurve(
        "ellipse about a focus", lambda th: A * (1 - eps**2) / (1 - eps * np.cos(th)), circular=eps == 0
    )


def sampled(radii: Any, name: str = "sampled curve") -> PitchCurve:
    """A closed pitch curve from radii at equal angles over one turn (m), interpolated by its
    Fourier series."""
    r = np.asarray(radii, dtype=float)
    if r.ndim != 1 or r.size < 8 or np.any(r <= 0):
        raise ModelError("give at least 8 positive radii over one turn", element=name, field="radii")
    c = np.fft.rfft(r) / r.size
    h = np.arange(c.size)
    w = np.where(h == 0, 1.0, 2.0)
    if r.size % 2 == 0:
        w[-1] = 1.0

    def radius(th):
        return (np.exp(1j * np.multiply.outer(np.asarray(th, dtype=float), h)) * (c * w)).real.sum(-1)

    return PitchCurve(name, radius, coefficients=c * w)


@dataclass(frozen=True)
class PitchLaw:
    """The motion law of a gear pair: ψ₂ = g(ψ₁) and where and how the gears touch.

    Attributes
    ----------
    curve : PitchCurve
        Gear 1's pitch curve.
    centre_distance : float
        a, m.
    line_angle : float
        β − θ₀: where the line of centres points in gear 1's frame at the drawing, rad.
    internal : bool
        Gear 2 is an annulus (circular gears only).
    ratio : float
        k, the mean of dψ₂/dψ₁ in magnitude (1 for a closing noncircular pair).
    """

    curve: PitchCurve
    centre_distance: float
    line_angle: float
    internal: bool
    ratio: float
    _coef: np.ndarray  # Fourier coefficients of the periodic part of h = |dψ₂/dψ₁| − k

    def contact_radius(self, psi1: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """r₁ and its ψ-derivatives at the contact, m."""
        r, r1, r2 = self.curve.derivatives(self.line_angle - np.asarray(psi1, dtype=float))
        return r, -r1, r2

    @cached_property
    def _terms(self) -> tuple[np.ndarray, np.ndarray, float]:
        """The orders h, the (h, 3) coefficients of P, P′ and P″ in e^{ihψ}, and P's constant."""
        h = np.arange(self._coef.size)
        c = np.where(h > 0, 2 * self._coef, 0)
        terms = np.stack([c / (1j * np.where(h == 0, 1, h)), c, c * 1j * h], axis=-1)
        return h, terms, float(terms[:, 0].sum().real)

    def __call__(self, psi1: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """ψ₂, dψ₂/dψ₁, d²ψ₂/dψ₁² at ψ₁ (external pairs turn opposite ways)."""
        psi = np.asarray(psi1, dtype=float)
        h, terms, constant = self._terms
        # P(ψ) = Σ_{h≥1} 2 Re(c_h (e^{ihψ} − 1)/(ih)), P′ = h-series of the ratio's periodic part
        p = (np.exp(1j * np.multiply.outer(psi, h)) @ terms).real
        s = 1.0 if self.internal else -1.0
        return s * (self.ratio * psi + p[..., 0] - constant), s * (self.ratio + p[..., 1]), s * p[..., 2]

    def pitch_tangent_lean(self, psi1: Any) -> np.ndarray:
        """ν = atan(dr/dθ / r): how far the common pitch tangent leans from the normal to the line
        of centres, rad (0 for circular gears). The pressure angle against the line of centres
        varies by this much."""
        r, dr_dpsi, _ = self.contact_radius(psi1)
        return np.arctan2(-dr_dpsi, r)


def _ratio_samples(curve: PitchCurve, a: float, line_angle: float, internal: bool) -> np.ndarray:
    psi = 2 * np.pi * np.arange(_N) / _N
    r = curve.radius(line_angle - psi)
    other = a + r if internal else a - r
    if np.any(other <= 0):
        raise ModelError(
            f"the centre distance {a:g} m is too short for the pitch curve (up to {r.max():g} m)",
            element=curve.name,
            field="centre_distance",
        )
    return r / other


def closing_centre_distance(curve: PitchCurve) -> float:
    """The centre distance at which the external conjugate of ``curve`` closes over one turn, m
    (mean r/(a − r) = 1; for a circle, the diameter)."""
    th = 2 * np.pi * np.arange(_N) / _N
    r = curve.radius(th)

    def mean_ratio(a: float) -> float:
        return float(np.mean(r / (a - r))) - 1.0

    lo, hi = r.max() * (1 + 1e-9), 4 * r.max()
    return float(brentq(mean_ratio, lo, hi, xtol=1e-15, rtol=1e-14))


def pitch_law(
    curve: PitchCurve,
    centre_distance: float,
    line_angle: float = 0.0,
    internal: bool = False,
    closing_tolerance: float = 1e-6,
) -> PitchLaw:
    """The motion law of gear 1 (``curve``) with its pure-rolling mate at ``centre_distance`` (m).

    For a noncircular curve the mate must close over one turn: the mean ratio must be 1 (to
    ``closing_tolerance``); otherwise :class:`ModelError` names the centre distance that closes.
    """
    if internal and not curve.circular:
        raise ModelError("internal meshes are for circular gears only", element=curve.name, field="internal")
    h = _ratio_samples(curve, centre_distance, line_angle, internal)
    k = float(np.mean(h))
    if not curve.circular and abs(k - 1) > closing_tolerance:
        raise ModelError(
            "the mate does not close over one turn at centre distance "
            f"{show(centre_distance, 'm', 'mm', '.6g')} "
            f"(mean ratio {k:.6g}); it closes at {show(closing_centre_distance(curve), 'm', 'mm', '.6g')}",
            element=curve.name,
            field="centre_distance",
        )
    if not curve.circular:
        k = 1.0  # exactly: the closing residual is below the tolerance
    c = np.fft.rfft(h - np.mean(h)) / _N
    c[-1] *= 0.5
    big = np.nonzero(np.abs(c) > 1e-14 * max(abs(k), np.abs(c).max()))[0]
    c = c[: int(big.max()) + 1] if big.size else c[:1]  # the terms that matter
    return PitchLaw(curve, float(centre_distance), float(line_angle), bool(internal), k, c)


def conjugate(law: PitchLaw, n: int = 720) -> tuple[np.ndarray, np.ndarray]:
    """The mate's pitch curve as (θ₂, r₂) samples in its own frame, for plots and checks."""
    psi = 2 * np.pi * np.arange(n) / n
    r1, _, _ = law.contact_radius(psi)
    psi2, _, _ = law(psi)
    r2 = law.centre_distance + r1 if law.internal else law.centre_distance - r1
    theta2 = np.mod(np.pi + law.line_angle - psi2, 2 * np.pi)
    return theta2, r2


def mate_curve(law: PitchLaw, n: int = 2048) -> PitchCurve:
    """The mate's pitch curve in its own frame, as a sampled curve (for its convexity and length)."""
    theta2, r2 = conjugate(law, 4 * n)
    o = np.argsort(theta2)
    grid = 2 * np.pi * np.arange(n) / n
    return sampled(np.interp(grid, theta2[o], r2[o], period=2 * np.pi), f"mate of {law.curve.name}")


def report(law: PitchLaw, pressure_angle: float) -> dict[str, float | bool]:
    """What a designer checks on a gear pair: centre distance, mean ratio, convexity of both pitch
    curves (a concave stretch undercuts), and the range of the pressure angle against the line of
    centres as the pitch tangent leans (rad → degrees in the result)."""
    psi = 2 * np.pi * np.arange(720) / 720
    lean = law.pitch_tangent_lean(psi)
    mate = law.curve if law.curve.circular else mate_curve(law)
    return {
        "centre_distance_m": law.centre_distance,
        "mean_ratio": law.ratio,
        "convex": bool(law.curve.convexity() > 0 and mate.convexity() > 0),
        "pressure_angle_min_deg": math.degrees(pressure_angle + lean.min()),
        "pressure_angle_max_deg": math.degrees(pressure_angle + lean.max()),
    }
