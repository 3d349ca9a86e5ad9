"""What a linkage designer reads off the motion: transmission angles, the output's swing, the motion of
every body and traced point, the coupler curves.

**Transmission angle** (Norton, *Design of Machinery*, §4.10; Uicker, Pennock & Shigley, *Theory of
Machines and Mechanisms*, §1.14): the angle μ between the output link and the coupler at the joint
where they meet, taken as the acute angle of the pair (0° to 90°). It is 90° where the coupler's
force turns the output link best and 0° at a toggle, where the linkage locks. Here every dyad of the
mechanism (:func:`~mechdyn.mechanism.dyads.plan`) has one:

- an RRR dyad (two links pinned together at P, their other ends at K₁ and K₂): the angle between
  P→K₁ and P→K₂, folded to the acute one, tan μ = |a₁ × a₂| / |a₁ · a₂|;
- an RRP dyad (a link K₁P whose end P slides on a frame guide of direction u): the slider is an
  output link of infinite length whose line is normal to the guide, so μ is the angle between the
  link and the *normal* to the slider's travel, tan μ = |a · u| / |a × u| — 90° when the link pushes
  straight along the guide, 0° when it stands across it. (It is 90° minus the link's obliquity, the
  angle between the link and the guide that ``output_link_obliquity_max_deg`` reports.)

In a six-bar such as the press, the "coupler" of the first dyad is the ternary link's side from the
dyad's joint to its other pin. sin μ is the singularity measure the dyad path screens for toggles.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from mechdyn.mechanism.dyads.decomposition import NotDecomposable, plan
from mechdyn.mechanism.model import GROUND, Mechanism, _other

__all__ = [
    "Dyad",
    "Motion",
    "coupler_bodies",
    "mechanism_dyads",
    "motion_columns",
    "output_rocker",
    "point_motion",
    "rocker_link",
    "transmission_angle",
]


class Motion(Protocol):
    """What the functions here read of a motion over the crank cycle
    (:class:`~mechdyn.mechanism.kinematics.KinematicsResult`)."""

    @property
    def mechanism(self) -> Mechanism:
        """The mechanism that moves."""
        ...

    @property
    def angle(self) -> np.ndarray:
        """(N,) crank angle from the datum, rad."""
        ...

    @property
    def q(self) -> np.ndarray:
        """(N, n) body coordinates (x_G, y_G in m, φ in rad per body)."""
        ...

    @property
    def qd(self) -> np.ndarray:
        """(N, n) their rates, m/s and rad/s."""
        ...

    @property
    def qdd(self) -> np.ndarray:
        """(N, n) their accelerations, m/s² and rad/s²."""
        ...

    @property
    def transmission_angles(self) -> dict[str, np.ndarray]:
        """Each dyad's transmission angle over the cycle, rad, by the joint at its inner point."""
        ...

    def point(self, body: str, point: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Position, velocity and acceleration of a drawing point on a body, each (N, 2): m, m/s,
        m/s²."""
        ...


@dataclass(frozen=True)
class Dyad:
    """One dyad of a mechanism, in the order the dyad path solves them.

    Attributes
    ----------
    kind : {"RRR", "RRP"}
        Two links pinned together, or a link whose end slides on a frame guide.
    joint : str
        The joint at the dyad's inner point (its transmission angle is measured there).
    point : str
        The inner point P.
    links : (str, str)
        The bodies: RRR, the link from P to ``ends[0]`` and the link from P to ``ends[1]``; RRP, the
        link and the slider.
    ends : tuple of str
        The links' other points: (K₁, K₂) for RRR, (K₁,) for RRP.
    axis : float or None
        RRP: the guide's direction, rad from +x.
    """

    kind: str
    joint: str
    point: str
    links: tuple[str, str]
    ends: tuple[str, ...]
    axis: float | None = None

    @property
    def label(self) -> str:
        """The dyad in words: its joint and its two bodies (``"B (coupler–rocker)"``)."""
        return f"{self.joint} ({self.links[0]}–{self.links[1]})"


def mechanism_dyads(mechanism: Mechanism) -> tuple[Dyad, ...]:
    """The dyads of a mechanism that decomposes into a crank and RRR/RRP dyads; () for one that does
    not (gear trains, sliders on moving guides), which has no transmission angle here.

    Parameters
    ----------
    mechanism : Mechanism
        The mechanism, as drawn.
    """
    try:
        steps = plan(mechanism)
    except NotDecomposable:
        return ()
    m = mechanism
    points = {b.name: set(b.points) for b in m.bodies}
    out = []
    for st in steps:
        if st.kind not in ("rrr", "rrp"):
            continue
        assert isinstance(st.target, str)  # a dyad finds one point
        p = st.target
        pins = [j for j in m.joints if j.pins and j.point == p and GROUND not in j.bodies]
        if st.kind == "rrr":
            k1, k2 = st.known

            def joins(j: Any, k1: str = k1, k2: str = k2) -> bool:  # the pin between the two links
                first, second = (points[b] for b in j.bodies)
                return (k1 in first and k2 in second) or (k2 in first and k1 in second)

            joint = next(j for j in pins if joins(j))
            b1, b2 = joint.bodies if k1 in points[joint.bodies[0]] else joint.bodies[::-1]
            out.append(Dyad("RRR", joint.name, p, (b1, b2), (k1, k2)))
        else:
            assert st.body is not None and st.guide is not None  # an RRP dyad slides on its guide
            slider = st.body
            joint = next(j for j in pins if slider in j.bodies and st.known[0] in points[_other(j, slider)])
            out.append(Dyad("RRP", joint.name, p, (_other(joint, slider), slider), st.known, st.guide.axis))
    return tuple(out)


def transmission_angle(dyad: Dyad, z: dict[str, np.ndarray]) -> np.ndarray:
    """A dyad's transmission angle (see the module docstring), rad, from 0 to π/2.

    Parameters
    ----------
    dyad : Dyad
        The dyad.
    z : dict of str → ndarray
        Positions of its points as complex numbers x + iy, m, each (...).
    """
    p = z[dyad.point]
    if dyad.kind == "RRR":
        # |a₁||a₂| (cos γ + i sin γ), γ the angle between the links at P
        w = np.conj(z[dyad.ends[0]] - p) * (z[dyad.ends[1]] - p)
    else:
        assert dyad.axis is not None  # an RRP dyad has its guide's axis
        a = (p - z[dyad.ends[0]]) * np.exp(-1j * dyad.axis)  # the link in the guide's axes
        w = a.imag + 1j * a.real  # measured from the guide's normal: across the guide is μ = 0
    return np.arctan2(np.abs(w.imag), np.abs(w.real))


def output_rocker(mechanism: Mechanism) -> tuple[str, str, str] | None:
    """The output as a rocker: (body, frame pivot, the point whose direction from the pivot is the
    rocker's angle); None when the output is a slide (its stroke is the output's travel) or there is
    no single link pinned to the frame besides the crank (:meth:`Mechanism.output_rocker`).

    The output named in the model (``output = [body, point]``) is used when it is pinned to the frame;
    otherwise the one body other than the crank that is pinned to the frame (a four-bar's rocker).

    Parameters
    ----------
    mechanism : Mechanism
        The mechanism, as drawn.
    """
    return mechanism.output_rocker()


def coupler_bodies(mechanism: Mechanism) -> tuple[str, ...]:
    """The bodies in general plane motion: neither pinned to the frame nor sliding on it (a four-bar's
    coupler, a slider-crank's connecting rod, the press's ternary link and rod).

    Parameters
    ----------
    mechanism : Mechanism
        The mechanism, as drawn.
    """
    on_frame = {b for j in mechanism.joints if GROUND in j.bodies for b in j.bodies}
    carriers = {getattr(j, "carrier", GROUND) for j in mechanism.joints}
    return tuple(b.name for b in mechanism.bodies if b.name not in on_frame | carriers)


def point_motion(kinematics: Motion, point: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Position, velocity and acceleration of a drawing point over the cycle, each (N, 2): m, m/s, m/s².

    Parameters
    ----------
    kinematics : Motion
        The motion (a :class:`~mechdyn.mechanism.kinematics.KinematicsResult`).
    point : str
        A point of the drawing; one on no body stays where the drawing puts it.
    """
    m = kinematics.mechanism
    body = next((b.name for b in m.bodies if point in b.points), None)
    if body is not None:
        return kinematics.point(body, point)
    N = kinematics.angle.size
    fixed = np.tile(np.asarray(m.points[point], dtype=float), (N, 1))
    return fixed, np.zeros((N, 2)), np.zeros((N, 2))


def _deg_wrapped(phi: np.ndarray) -> np.ndarray:
    """Angles in degrees within (−180, 180]."""
    return -np.degrees(np.angle(np.exp(-1j * np.asarray(phi))))


def motion_columns(kinematics: Motion, traced: tuple[str, ...] = ()) -> dict[str, np.ndarray]:
    """The per-angle motion columns of a result table, each name ending with its unit.

    Per body ``body_NAME_x_m``, ``_y_m`` (centre of mass), ``_angle_deg`` (rotation from the drawing,
    within ±180°), their velocities ``_velocity_x_m_per_s``, ``_velocity_y_m_per_s``,
    ``_angular_velocity_rad_s``, and accelerations ``_acceleration_x_m_per_s2``,
    ``_acceleration_y_m_per_s2`` and (where the unit registry names rad/s²)
    ``_angular_acceleration_rad_s2``; per traced point ``point_NAME_x_m``, ``_y_m`` (its coupler
    curve), ``_velocity_…`` and ``_acceleration_…``; per dyad ``transmission_angle_JOINT_deg``; with a
    rocker output ``output_angle_deg`` (from +x) and ``output_angular_velocity_rad_s``.

    Parameters
    ----------
    kinematics : Motion
        The motion (a :class:`~mechdyn.mechanism.kinematics.KinematicsResult`).
    traced : tuple of str
        Points of the drawing whose motion is tabulated.
    """
    k = kinematics
    m = k.mechanism
    cols: dict[str, np.ndarray] = {}
    for i, b in enumerate(m.bodies):
        x, xd, xdd = (a[:, 3 * i : 3 * i + 3] for a in (k.q, k.qd, k.qdd))
        name = f"body_{b.name}"
        cols |= {f"{name}_x_m": x[:, 0], f"{name}_y_m": x[:, 1], f"{name}_angle_deg": _deg_wrapped(x[:, 2])}
        cols |= {
            f"{name}_velocity_x_m_per_s": xd[:, 0],
            f"{name}_velocity_y_m_per_s": xd[:, 1],
            f"{name}_angular_velocity_rad_s": xd[:, 2],
            f"{name}_acceleration_x_m_per_s2": xdd[:, 0],
            f"{name}_acceleration_y_m_per_s2": xdd[:, 1],
            f"{name}_angular_acceleration_rad_s2": xdd[:, 2],
        }
    for p in traced:
        pos, vel, acc = point_motion(k, p)
        name = f"point_{p}"
        cols |= {f"{name}_x_m": pos[:, 0], f"{name}_y_m": pos[:, 1]}
        cols |= {f"{name}_velocity_x_m_per_s": vel[:, 0], f"{name}_velocity_y_m_per_s": vel[:, 1]}
        cols |= {f"{name}_acceleration_x_m_per_s2": acc[:, 0], f"{name}_acceleration_y_m_per_s2": acc[:, 1]}
    for joint, mu in k.transmission_angles.items():
        cols[f"transmission_angle_{joint}_deg"] = np.degrees(mu)
    rocker = output_rocker(m)
    if rocker is not None:
        from mechdyn.mechanism.extrema import rocker_angle

        body, pivot, tip = rocker
        i = m.body_index[body]
        angle = rocker_angle(_link(k, pivot, tip))
        cols |= {
            "output_angle_deg": angle,
            "output_angular_velocity_rad_s": k.qd[:, 3 * i + 2],
            "output_angular_acceleration_rad_s2": k.qdd[:, 3 * i + 2],
        }
    return cols


def _link(kinematics: Motion, pivot: str, tip: str) -> np.ndarray:
    """(N,) complex: from ``pivot`` to ``tip`` over the cycle, m."""
    (p, _, _), (t, _, _) = point_motion(kinematics, pivot), point_motion(kinematics, tip)
    return (t[:, 0] - p[:, 0]) + 1j * (t[:, 1] - p[:, 1])


def rocker_link(kinematics: Motion) -> np.ndarray | None:
    """(N,) complex: the rocker output's direction, from its frame pivot to its other point, m (None
    without a rocker output, see :func:`output_rocker`).

    Parameters
    ----------
    kinematics : Motion
        The motion (a :class:`~mechdyn.mechanism.kinematics.KinematicsResult`).
    """
    rocker = output_rocker(kinematics.mechanism)
    if rocker is None:
        return None
    return _link(kinematics, *rocker[1:])
