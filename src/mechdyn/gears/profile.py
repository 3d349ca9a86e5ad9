"""Potential-energy tooth compliance over an arbitrary thickness profile (Yang–Lin / Tian type).

The same Castigliano terms as :class:`~mechdyn.gears.tooth.TruncatedTooth`, but with the tooth's
true thickness t(y), e.g. the involute of a spur gear, integrated numerically (Gauss–Legendre) from
the root section to the load point. This is the potential-energy method of Yang & Lin (1987) as
extended by Tian (2004, M.Sc. thesis, University of Alberta) and most later mesh-stiffness papers,
with the fillet-foundation term of Sainsot et al. (2004). A straight taper reproduces the
truncated-triangle closed forms, which the tests use as a check.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from mechdyn.errors import ModelError
from mechdyn.gears.tooth import (
    SHEAR_COEFFICIENT,
    _default_loads,
    foundation_compliance,
    foundation_extrapolation,
    warn_outside_sainsot_range,
)

__all__ = ["ProfileTooth"]

_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(64)


@dataclass(frozen=True)
class ProfileTooth:
    """A tooth of any thickness profile, clamped at its root section.

    Parameters
    ----------
    thickness : callable
        t(y), m, for heights y (m, array) between ``root_height`` and ``tip_height``.
    root_height, tip_height : float
        Heights of the root section and the tip, m.
    face_width : float
        f, m.
    youngs_modulus : float
        E, Pa.
    poisson_ratio : float
    root_radius, bore_radius : float, optional
        For the Sainsot foundation (rigid without them).
    name : str
    breaks : tuple of float
        Heights, m, where the profile has a kink (e.g. where a gear's fillet meets its involute):
        the quadrature is split there, so that each piece is smooth.
    flank_loads : tuple of (float, float)
        (load height, m; load angle, rad) pairs where the tooth is loaded in service, at which
        :meth:`foundation_extrapolation` is evaluated (a gear gives its involute flank). Empty: 16
        heights from the root to the tip, each at 0°, 10°, 20°, 30° and 40°.
    """

    thickness: Callable[[np.ndarray], np.ndarray]
    root_height: float
    tip_height: float
    face_width: float
    youngs_modulus: float
    poisson_ratio: float = 0.3
    root_radius: float | None = None
    bore_radius: float | None = None
    name: str = "tooth"
    breaks: tuple[float, ...] = ()
    flank_loads: tuple[tuple[float, float], ...] = ()

    def __post_init__(self) -> None:
        if self.root_radius is not None and self.bore_radius is not None:
            warn_outside_sainsot_range(
                self.name, *self._foundation_parameters, self.foundation_extrapolation, stacklevel=4
            )

    def foundation_extrapolation(self) -> float:
        """Share of this tooth's compliance that rests on extrapolating the Sainsot fit (0 inside its
        range), over ``flank_loads`` (:func:`~mechdyn.gears.tooth.foundation_extrapolation`)."""
        loads = self.flank_loads or _default_loads(self.root_height, self.tip_height)
        return foundation_extrapolation(self, loads)

    @property
    def _foundation_parameters(self) -> tuple[float, float]:
        """h_f = r_root / r_bore and θ_f = t(h_0) / (2 r_root) of the Sainsot fit."""
        r_root, r_bore = self.root_radius, self.bore_radius
        assert r_root is not None and r_bore is not None  # asked for only when there is a foundation
        t0 = float(np.asarray(self.thickness(np.array([self.root_height])))[0])
        return r_root / r_bore, t0 / (2.0 * r_root)

    @property
    def shear_modulus(self) -> float:
        return self.youngs_modulus / (2.0 * (1.0 + self.poisson_ratio))

    def compliances(self, load_height: float, load_angle: float) -> dict[str, float]:
        """Deflection along the line of action per unit force, m/N, term by term (see TruncatedTooth)."""
        hc, phi = float(load_height), float(load_angle)
        h0 = self.root_height
        if not h0 < hc <= self.tip_height * (1 + 1e-12):
            raise ModelError(
                f"load height {hc:g} m lies outside the tooth (root {h0:g} m, tip {self.tip_height:g} m)",
                element=self.name,
                field="load_height",
            )
        edges = [h0, *sorted(b for b in self.breaks if h0 < b < hc), hc]
        halves = [0.5 * (b - a) for a, b in itertools.pairwise(edges)]
        y = np.concatenate([h * _NODES + a + h for a, h in zip(edges[:-1], halves, strict=True)])
        w = np.concatenate([h * _WEIGHTS for h in halves])
        t = np.asarray(self.thickness(y), dtype=float)
        if np.any(t <= 0):
            raise ModelError(
                "the thickness profile is not positive over the loaded height", element=self.name
            )
        e = 0.5 * float(np.asarray(self.thickness(np.array([hc])))[0])
        E, G, f = self.youngs_modulus, self.shear_modulus, self.face_width
        inertia, area = f * t**3 / 12.0, f * t
        cos, sin = math.cos(phi), math.sin(phi)
        arm = hc - y
        foundation = self._foundation(hc, phi)
        return {
            "bending_transverse": float(np.sum(w * cos**2 * arm**2 / (E * inertia))),
            "bending_radial": float(np.sum(w * (sin**2 * e**2 - 2.0 * sin * cos * e * arm) / (E * inertia))),
            "compression": float(np.sum(w * sin**2 / (E * area))),
            "shear": float(np.sum(w * SHEAR_COEFFICIENT * cos**2 / (G * area))),
            "foundation": foundation,
        }

    def _foundation(self, hc: float, phi: float, parameters: tuple[float, float] | None = None) -> float:
        """The Sainsot foundation term, m/N, at the tooth's own (h_f, θ_f) or at ``parameters``; the
        root chord S_f = 2 θ_f r_root is the tooth's own in both."""
        if self.root_radius is None:
            return 0.0
        if self.bore_radius is None:
            raise ModelError(
                "give both root_radius and bore_radius (foundation), or neither",
                element=self.name,
                field="bore_radius",
            )
        own = self._foundation_parameters
        h_f, theta_f = parameters or own
        chord = 2.0 * own[1] * self.root_radius
        return foundation_compliance(
            hc - self.root_height, chord, h_f, theta_f, phi, self.youngs_modulus, self.face_width
        )

    def compliance(self, load_height: float, load_angle: float) -> float:
        """Total tooth compliance (all terms but Hertz), m/N."""
        return sum(self.compliances(load_height, load_angle).values())
