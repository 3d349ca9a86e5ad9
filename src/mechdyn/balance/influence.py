"""What a counterweight changes, exactly: the shaking force, shaking moment and driving torque are
linear in four numbers per link.

A point mass m fixed on a link at (u, v) from the link's reference point P (in the link's frame,
drawing axes at the drawing pose) moves with the link; the mechanism's motion does not change (the
driver imposes it). Its d'Alembert force and moment and its kinetic energy then give, at every crank
angle, with the link's angle φ, rates ω, α, E₁ = (cos φ, sin φ), E₂ = (−sin φ, cos φ), g gravity:

- shaking force  ΔF = m (g − a_P) + (m u)(ω² E₁ − α E₂) + (m v)(α E₁ + ω² E₂);
- shaking moment about the origin  ΔM = r_P × ΔF + (m u) E₁ × (g − a_P) + (m v) E₂ × (g − a_P)
  − α (J + m (u² + v²)), J the counterweight's own inertia;
- driving torque  ΔT θ̇ = d/dt (½ m v_c² + ½ J ω²) − m g · v_c (the virtual power of the
  one-degree-of-freedom mechanism).

So every one is linear in x = (m, m u, m v, J + m (u² + v²)) per link (Berkof & Lowen, "A new
method for completely force balancing simple linkages", J. Eng. Ind. 91 (1969) 21–26, for the
force; Lowen, Tepper & Berkof, "Balancing of linkages — an update", Mech. Mach. Theory 18 (1983)
213–220, for moment and torque). :class:`Influence` holds the columns of that linear map, worked out
from one inverse dynamics of the mechanism as it is; a design is then evaluated by one matrix
product.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from mechdyn.errors import ModelError
from mechdyn.mechanism.model import GROUND, Counterweight, Mechanism

__all__ = ["Influence", "influence", "reference_point"]

PER_LINK = 4
"""Coefficients per link: m, m·u, m·v, J + m(u² + v²)."""


def reference_point(mechanism: Mechanism, body: str) -> str:
    """The point a counterweight's position on a link is measured from: the link's pivot on the frame
    when it has one (then the mass alone adds no shaking force), else its first point.

    Parameters
    ----------
    mechanism : Mechanism
        The mechanism.
    body : str
        The link's name.
    """
    if body not in mechanism.body_index:
        raise ModelError(
            f"body {body!r} is not defined; links: {', '.join(mechanism.body_index)}",
            element="balance",
            field="links",
        )
    b = mechanism.bodies[mechanism.body_index[body]]
    for j in mechanism.joints:
        if j.pins and GROUND in j.bodies and body in j.bodies:
            return str(j.point)
    return b.points[0]


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _perp(a: np.ndarray) -> np.ndarray:
    """k × a for a planar vector a."""
    return np.stack([-a[..., 1], a[..., 0]], axis=-1)


@dataclass(frozen=True)
class Influence:
    """The shaking force, shaking moment and driving torque as linear functions of counterweights.

    Attributes
    ----------
    mechanism : Mechanism
        The mechanism as it is (its own counterweights, if any, included in ``base``).
    links : tuple of str
        The links that may carry a counterweight.
    points : tuple of str
        Each link's reference point (:func:`reference_point`).
    angle : ndarray
        (N,) crank angle from the datum, rad.
    base : ndarray
        (N, 4) the mechanism as it is: shaking force x, y (N), shaking moment about the origin (N·m),
        driving torque (N·m).
    columns : ndarray
        (N, 4, 4 L) the change of those per unit of each link's x = (m [kg], m u [kg·m], m v [kg·m],
        J + m (u² + v²) [kg·m²]), link by link.
    dynamics : DynamicsResult
        The inverse dynamics they came from.
    """

    mechanism: Mechanism
    links: tuple[str, ...]
    points: tuple[str, ...]
    angle: np.ndarray
    base: np.ndarray
    columns: np.ndarray
    dynamics: Any

    def channels(self, x: np.ndarray) -> np.ndarray:
        """(..., N, 4) shaking force x, y (N), moment about the origin (N·m) and driving torque (N·m).

        Parameters
        ----------
        x : ndarray
            (..., 4 L) coefficients per link: m in kg, m u and m v in kg·m, J + m (u² + v²) in kg·m².
        """
        return self.base + np.einsum("nck,...k->...nc", self.columns, np.asarray(x, dtype=float))

    def origin(self, k: int) -> np.ndarray:
        """Drawing position of link ``k``'s reference point, m.

        Parameters
        ----------
        k : int
            The link's index in :attr:`links` (a count).
        """
        return np.asarray(self.mechanism.points[self.points[k]], dtype=float)

    def counterweights(self, design: np.ndarray) -> tuple[Counterweight, ...]:
        """The counterweights of a design (L, 3): per link mass (kg) and position (u, v) from its
        reference point (m, drawing axes); links with no mass get none.

        Parameters
        ----------
        design : ndarray
            (L, 3) mass, kg, and u, v, m.
        """
        out = []
        for k, (m, u, v) in enumerate(np.asarray(design, dtype=float)):
            if m > 0:
                p = self.origin(k) + np.array([u, v])
                out.append(Counterweight(self.links[k], float(m), (float(p[0]), float(p[1]))))
        return tuple(out)


def influence(mechanism: Mechanism, links: Any, n_angles: int = 360) -> Influence:
    """The linear map from counterweights on ``links`` to shaking force, moment and driving torque.

    Parameters
    ----------
    mechanism : Mechanism
        The mechanism (counterweights it already has count as part of it).
    links : sequence of str
        The links that may carry a counterweight, each once.
    n_angles : int
        Crank angles over one revolution (dimensionless count).

    Returns
    -------
    Influence

    Notes
    -----
    Formulas in the module docstring (d'Alembert force and moment of a point mass on a moving link,
    virtual power for the torque; Berkof & Lowen 1969).
    """
    from mechdyn.mechanism.dynamics import inverse_dynamics

    links = tuple(links)
    if not links:
        raise ModelError("give at least one link to carry a counterweight", element="balance", field="links")
    if len(set(links)) != len(links):
        raise ModelError(f"{list(links)}: name each link once", element="balance", field="links")
    points = tuple(reference_point(mechanism, b) for b in links)
    dyn = inverse_dynamics(mechanism, n_angles)
    kin = dyn.kinematics
    n = dyn.angle.size
    base = np.column_stack([dyn.shaking_force, dyn.shaking_moment(), dyn.driving_torque])
    g = np.asarray(mechanism.gravity, dtype=float)
    theta_dot = dyn.crank_speed
    cols = np.zeros((n, 4, PER_LINK * len(links)))
    for k, (body, point) in enumerate(zip(links, points, strict=True)):
        i = mechanism.body_index[body]
        q, qd, qdd = (a[:, 3 * i : 3 * i + 3] for a in (kin.q, kin.qd, kin.qdd))
        phi, w, al = q[:, 2], qd[:, 2], qdd[:, 2]
        E1 = np.column_stack([np.cos(phi), np.sin(phi)])
        E2 = _perp(E1)
        cx, cy = mechanism.local(body, point)
        arm = cx * E1 + cy * E2
        rP = q[:, :2] + arm
        vP = qd[:, :2] + w[:, None] * _perp(arm)
        aP = qdd[:, :2] + al[:, None] * _perp(arm) - (w**2)[:, None] * arm
        ga = g - aP
        f_u = (w**2)[:, None] * E1 - al[:, None] * E2
        f_v = al[:, None] * E1 + (w**2)[:, None] * E2
        lin = -al[:, None] * _perp(vP) - (w**2)[:, None] * vP - w[:, None] * _perp(aP) + w[:, None] * _perp(g)
        c = slice(PER_LINK * k, PER_LINK * k + PER_LINK)
        force = np.stack([ga, f_u, f_v, np.zeros_like(ga)], axis=-1)  # (N, 2, 4)
        moment = np.column_stack(
            [
                _cross(rP, ga),
                _cross(rP, f_u) + _cross(E1, ga),
                _cross(rP, f_v) + _cross(E2, ga),
                -al,
            ]
        )
        torque = (
            np.column_stack(
                [
                    np.sum(vP * aP, axis=1) - vP @ g,
                    np.sum(E1 * lin, axis=1),
                    np.sum(E2 * lin, axis=1),
                    w * al,
                ]
            )
            / theta_dot[:, None]
        )
        cols[:, :2, c] = force
        cols[:, 2, c] = moment
        cols[:, 3, c] = torque
    if not np.all(np.isfinite(cols)):
        raise ModelError(
            "the mechanism's motion is not finite over the cycle; it cannot be balanced",
            element="balance",
        )
    return Influence(mechanism, links, points, dyn.angle, base, cols, dyn)
