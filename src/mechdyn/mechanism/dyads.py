"""The fast path: closed-form dyads, vectorised over crank angles *and* design variants.

Most linkages decompose into a crank and Assur groups of class II — RRR dyads (a joint between two
links whose other ends are known) and RRP dyads (a link end sliding on a frame guide) — plus rigid
bodies whose points follow from two known ones. For those, positions have closed forms (circle and
circle-line intersections, the branch taken from each variant's drawing), and velocities and
accelerations come from the differentiated constraints of each dyad, 2×2 and 1×1 linear systems
solved in closed form: the constraint Jacobian is block-triangular in this order. (E.g. Norton,
*Design of Machinery*, ch. 4–7; Hansen's Assur-group method.) No Newton iterations, no loops over
angles or variants: the whole study is a few array expressions.

Every load follows, in the same compiled pass, from the constraint multipliers λ, solved group by
group from the output back to the crank (Assur groups are statically determinate: each dyad's six
Newton–Euler equations reduce, by moments about its inner pin, to a 2×2 system solved by Cramer's
rule; e.g. Norton, *Design of Machinery*, ch. 11; Uicker, Pennock & Shigley, ch. 14): the joint
forces, the driving torque −λ_last, and the frame's share (its joints' reactions and the motor's).
They are the multipliers of the general engine's equations Φ_qᵀ λ = Q − M q̈, solved here in their
block-triangular order; the tests compare every load with the general engine's dense solve.
Mechanisms that do not decompose (closed loops of higher class, sliders on moving guides) are
refused here and run on the general engine.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, cast

import numpy as np

from mechdyn.checks import check_array
from mechdyn.errors import ModelError
from mechdyn.mechanism.kinematics import AssemblyError, SingularPositionError, check_angles, crank_angles
from mechdyn.mechanism.model import GROUND, Mechanism, Prismatic, _point
from mechdyn.mechanism.motion import output_rocker
from mechdyn.mechanism.screening import SCREEN, Finding, screen
from mechdyn.results import Result

__all__ = ["CycleBatch", "DesignBatch", "NotDecomposable", "cycle", "plan", "variants"]


class NotDecomposable(ModelError):
    """The mechanism is not a crank with RRR/RRP dyads; use the general engine."""


@dataclass(frozen=True)
class Step:
    """One step of the solution order: which point(s) it finds and from what."""

    kind: str  # "crank", "rigid", "rrr", "rrp"
    target: str | tuple[str, ...]
    known: tuple[str, ...]
    body: str | None = None
    guide: Prismatic | None = None


def plan(mechanism: Mechanism) -> list[Step]:
    """The order in which the points become known; :class:`NotDecomposable` if there is none."""
    m = mechanism
    for j in m.joints:
        if not (j.pins or j.slides):
            raise NotDecomposable(
                f"joint {j.name!r} is neither a pin nor a slider; it runs on the general engine",
                element=j.name,
            )
    pts_of = {b.name: set(b.points) for b in m.bodies}
    grounded = {j.point for j in m.joints if j.pins and GROUND in j.bodies}
    for j in m.joints:
        if j.slides and j.bodies[0] == GROUND:
            raise NotDecomposable(
                "the frame cannot slide on a body here; swap the joint's bodies", element=j.name
            )
        if j.slides and j.bodies[1] != GROUND:
            raise NotDecomposable(
                f"slider {j.name!r} runs on a moving guide; use the general engine", element=j.name
            )
    d = m.driver
    if d.pivot not in grounded:
        raise NotDecomposable(f"the crank's pivot {d.pivot!r} is not a frame pivot", element="driver")
    known = set(grounded)
    steps = [Step("crank", tuple(sorted(pts_of[d.body] - {d.pivot})), (d.pivot,), d.body)]
    known |= pts_of[d.body]
    done_bodies = {d.body}
    sliders = {j.bodies[0]: cast(Prismatic, j) for j in m.joints if j.slides}
    revolutes = [j for j in m.joints if j.pins]
    while len(done_bodies) < len(m.bodies):
        progress = False
        for b in m.bodies:  # rigid: two known points fix the rest
            if b.name in done_bodies:
                continue
            k = sorted(pts_of[b.name] & known)
            if len(k) >= 2:
                rest = tuple(sorted(pts_of[b.name] - known))
                steps.append(Step("rigid", rest, (k[0], k[1]), b.name))
                known |= pts_of[b.name]
                done_bodies.add(b.name)
                progress = True
        for j in revolutes:  # RRR: an unknown pin between two links each with a known point
            p = j.point
            if p in known or GROUND in j.bodies:
                continue
            b1, b2 = j.bodies
            k1 = sorted((pts_of[b1] & known) - {p})
            k2 = sorted((pts_of[b2] & known) - {p})
            if k1 and k2 and b1 not in sliders and b2 not in sliders:
                steps.append(Step("rrr", p, (k1[0], k2[0])))
                known.add(p)
                progress = True
        for s, g in sliders.items():  # RRP: a link end on a frame guide
            p = g.point
            if p in known:
                continue
            links = [
                j.bodies[0] if j.bodies[1] == s else j.bodies[1]
                for j in revolutes
                if j.point == p and s in j.bodies
            ]
            for b1 in links:
                k1 = sorted((pts_of[b1] & known) - {p})
                if k1:
                    steps.append(Step("rrp", p, (k1[0],), s, g))
                    known.add(p)
                    progress = True
                    break
        for s, g in sliders.items():  # a slider body translates with its guide point
            if s not in done_bodies and g.point in known:
                rest = tuple(sorted(pts_of[s] - known))
                steps.append(Step("rigid", rest, (g.point,), s, g))
                known |= pts_of[s]
                done_bodies.add(s)
                progress = True
        if not progress:
            missing = ", ".join(b.name for b in m.bodies if b.name not in done_bodies)
            raise NotDecomposable(
                f"no RRR or RRP dyad closes the remaining bodies ({missing}); use the general engine"
            )
    return steps


@dataclass(frozen=True, repr=False)  # the short repr of Result
class CycleBatch(Result):
    """Kinematics and frame loads of many design variants over one revolution.

    Arrays have shape (V, N, ...) for V variants (1 when none were given) and N crank angles.

    Attributes
    ----------
    angle : ndarray
        (V, N) crank angle from each variant's datum, rad (every variant starts its cycle at its
        own datum; with ``angle_datum = "bdc"`` at its own bottom dead centre).
    driving_torque : ndarray
        (V, N) N·m.
    frame_moment : ndarray
        (V, N) moment on the frame about the origin, N·m (motor reaction included).
    output_position : ndarray or None
        (V, N) along the upward output axis, m.
    mechanism : Mechanism
        The base design the variants were made from.
    failures : dict of int to str
        Variant index → why it could not be computed (its rows are NaN).
    """

    mechanism: Mechanism
    angle: np.ndarray
    driving_torque: np.ndarray
    frame_moment: np.ndarray
    output_position: np.ndarray | None
    _force: np.ndarray  # complex (V, N): the load on the frame
    _inertia: np.ndarray  # complex (V, N): −Σ m a_G
    _z: dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]
    _rates: dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]
    _dyad_measure: np.ndarray  # (V, N, dyads) sine of each dyad's transmission angle, signed
    _steps: list[Step]
    _raw: tuple[np.ndarray, ...]  # (pos, vel, acc, rates) as the kernel wrote them
    _body_mass: np.ndarray  # (V, bodies) kg
    _body_inertia: np.ndarray  # (V, bodies) kg·m²
    _lam: np.ndarray | None  # (V, N, m) the multipliers, with the motions kept
    _peaks: np.ndarray  # (V, joints) each joint's largest force, N
    failures: dict[int, str] = field(default_factory=dict)
    """Variant → why it was not computed (``errors="nan"``): the angle, the loop and the joint."""

    @property
    def shaking_force(self) -> np.ndarray:
        """(V, N, 2) force on the frame, N."""
        return np.stack([self._force.real, self._force.imag], axis=-1)

    @property
    def inertia_force(self) -> np.ndarray:
        """(V, N, 2) −Σ m a_G, N."""
        return np.stack([self._inertia.real, self._inertia.imag], axis=-1)

    def _stored(self, key: str) -> None:
        if key not in self._z:
            raise ModelError(
                f"the motion of {key.removeprefix('__com__')!r} was not kept; "
                "run cycle(..., store_points=True)",
                element="cycle",
            )

    def point(self, name: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Position, velocity and acceleration of a drawing point, each (V, N, 2).

        Parameters
        ----------
        name : str
            A point of the drawing; m, m/s and m/s² in the drawing's axes.
        """
        self._stored(name)
        p, v, a = (np.stack([z.real, z.imag], axis=-1) for z in self._z[name])
        return p, v, a

    def coordinates(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Body coordinates q, q̇, q̈, each (V, N, n), as in
        :class:`~mechdyn.mechanism.kinematics.KinematicsResult` (x_G, y_G, φ per body)."""
        m = self.mechanism
        self._stored(f"__com__{m.bodies[0].name}")
        pos, vel, acc, rates = self._raw
        nb = len(m.bodies)
        z = np.stack([pos[..., -nb:], vel[..., -nb:], acc[..., -nb:]])  # the centres of mass come last
        out = np.empty((*z.shape, 3))
        out[..., 0], out[..., 1], out[..., 2] = z.real, z.imag, np.moveaxis(rates, -1, 0)
        q, qd, qdd = out.reshape(3, *self.angle.shape, 3 * nb)
        return q, qd, qdd

    @property
    def q(self) -> np.ndarray:
        """(V, N, n) body coordinates (see :meth:`coordinates`)."""
        return self.coordinates()[0]

    @property
    def multipliers(self) -> np.ndarray:
        """(V, N, m) the constraint multipliers λ of every variant: every load comes from them (the
        driving torque −λ_last, the joint forces, the frame's share); kept with the motions."""
        if self._lam is None:
            raise ModelError(
                "the multipliers are kept with the motions; run cycle(..., store_points=True)",
                element="cycle",
            )
        return self._lam

    def joint_force(self, joint: str) -> np.ndarray:
        """(V, N, 2) force that ``joint`` puts on its second body, N (as
        :meth:`DynamicsResult.joint_load` gives it, without the moment).

        Parameters
        ----------
        joint : str
            The joint's name."""
        m = self.mechanism
        names = [j.name for j in m.joints]
        if joint not in names:
            raise KeyError(joint)
        k = names.index(joint)
        j = m.joints[k]
        rows = self.multipliers[..., m.joint_rows[k]]
        if j.pins:
            return rows
        # a slider on a frame guide: the normal force λ₂ n on the guide (−λ₂ n on the slider)
        axis = cast(Prismatic, j).axis
        n = np.array([-math.sin(axis), math.cos(axis)])
        return rows[..., 1:2] * n

    @property
    def joint_force_peaks(self) -> dict[str, np.ndarray]:
        """Joint → (V,) largest force magnitude over the cycle on its second body, N."""
        return {j.name: self._peaks[:, k] for k, j in enumerate(self.mechanism.joints)}

    @property
    def status(self) -> tuple[str, ...]:
        """Per variant: ``"ok"``, or why it was not computed (the angle, the loop and the joint)."""
        return tuple(self.failures.get(v, "ok") for v in range(self.angle.shape[0]))

    @property
    def assembled(self) -> np.ndarray:
        """(V,) True for the variants that assemble over the whole cycle."""
        return np.isfinite(self.driving_torque).all(axis=1)

    def shaking_moment(self, about: Any = (0.0, 0.0)) -> np.ndarray:
        """(V, N) moment on the frame about a point, N·m.

        Parameters
        ----------
        about : (float, float)
            The point, m, in the drawing's axes (each coordinate at most 1e3 m in magnitude).
        """
        px, py = _point("shaking moment", "about", about)
        F = self._force
        return self.frame_moment - (px * F.imag - py * F.real)

    def to_frame(self) -> Any:
        """One row per variant: whether it assembles and its :meth:`summary` figures (units in the names)."""
        import pandas as pd

        cols: dict[str, Any] = {"variant": np.arange(self.angle.shape[0]), "assembled": self.assembled}
        for key, value in self.summary().items():
            if isinstance(value, dict):  # joint → peak: one column per joint
                cols |= {f"joint_{name}_force_peak_N": v for name, v in value.items()}
            else:
                cols[key] = value
        return pd.DataFrame(cols)

    def summary(self) -> dict[str, Any]:
        """Per variant (arrays over V): the torque and frame-load figures, the output's stroke, dead
        centres and inertia-force extremes, and (motions kept) each joint's force peak; the same
        functions as one design's :meth:`DynamicsResult.summary`."""
        from mechdyn.mechanism.extrema import load_figures, output_figures

        deg = np.degrees(self.angle)
        out: dict[str, Any] = load_figures(self.driving_torque, self.shaking_force, self.shaking_moment())
        s = self.output_position
        j = self.mechanism.output_joint()
        if s is not None and j is not None:
            f = _dot(self._inertia, complex(math.cos(j.axis), math.sin(j.axis)))
            out.update(output_figures(deg, s, f, self.mechanism.angle_datum == "bdc"))
        ends = self.mechanism.output_link()
        pivot = self.mechanism.driver.pivot
        if s is not None and j is not None and ends is not None and all(p in self._z for p in (*ends, pivot)):
            from mechdyn.mechanism.extrema import layout_figures

            za, zb = (self._z[p][0] for p in ends)
            out.update(layout_figures(zb - za, j.axis, self._z[pivot][0][:, 0], zb[:, 0]))
        out.update(self._motion_figures(deg))
        out["joint_force_peak_N"] = self.joint_force_peaks
        return out

    def _motion_figures(self, deg: np.ndarray) -> dict[str, np.ndarray]:
        """Each variant's smallest transmission angle (from the kernel's sin μ of every dyad) and a
        rocker output's swing: the functions of one design's :meth:`DynamicsResult.summary`."""
        from mechdyn.mechanism.extrema import bdc_origin, swing_figures, transmission_figures

        s = self.output_position
        origin = bdc_origin(deg, s) if s is not None and self.mechanism.angle_datum == "bdc" else None
        out: dict[str, np.ndarray] = {}
        if self._dyad_measure.shape[-1]:
            mu = np.degrees(np.arcsin(np.minimum(np.abs(self._dyad_measure), 1.0)))
            mu[list(self.failures)] = np.nan
            out.update(transmission_figures(deg, mu, origin)[0])
        rocker = output_rocker(self.mechanism)
        if rocker is not None and all(p in self._z for p in rocker[1:]):
            _, pivot, tip = rocker
            out.update(swing_figures(deg, self._z[tip][0] - self._z[pivot][0], origin))
        return out


def _z(xy: Any) -> np.ndarray:
    a = np.asarray(xy, dtype=float)
    return a[..., 0] + 1j * a[..., 1]


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a × b for plane vectors written as complex numbers: Im(conj(a) b)."""
    return a.real * b.imag - a.imag * b.real


def _dot(a: np.ndarray, b: np.ndarray | complex) -> np.ndarray:
    return a.real * b.real + a.imag * b.imag


# operation codes of the compiled kernel
_CRANK, _RIGID, _GUIDE, _PLACE, _RRR, _RRP = range(6)


def _encode(m: Mechanism, steps: list[Step], draw: dict[str, np.ndarray]):
    """The plan as integer operations and per-variant data for the kernel.

    Slots 0..P−1 hold the drawing points, P..P+nb−1 the bodies' centres of mass.
    """
    names = list(m.points)
    slot = {n: i for i, n in enumerate(names)}
    nb = len(m.bodies)
    P = len(names)
    for i, b in enumerate(m.bodies):
        slot[f"__com__{b.name}"] = P + i
    V = next(iter(draw.values())).shape[0]
    dz = np.empty((V, P + nb), dtype=complex)
    for n, i in slot.items():
        dz[:, i] = draw[n] if i < P else _com(m.bodies[i - P], draw)
    n_ops = sum(1 if st.kind in ("rrr", "rrp") else 1 + len(st.target) + 1 for st in steps)
    ops = np.full((n_ops, 6), -1, dtype=np.int64)  # kind, target, k1, k2, body, dyad number
    fdata = np.zeros((V, n_ops, 4))  # per-operation per-variant float data
    grounded = sorted({slot[j.point] for j in m.joints if j.pins and GROUND in j.bodies})
    o = 0
    dyad = 0
    for st in steps:
        bi = m.body_index[st.body] if st.body is not None else -1
        if st.kind in ("rrr", "rrp"):
            assert isinstance(st.target, str)  # a dyad finds one point
            t, k1 = slot[st.target], slot[st.known[0]]
            d1 = dz[:, t] - dz[:, k1]
            fdata[:, o, 0] = np.abs(d1)
            if st.kind == "rrr":
                k2 = slot[st.known[1]]
                ops[o] = (_RRR, t, k1, k2, -1, dyad)
                fdata[:, o, 1] = np.abs(dz[:, t] - dz[:, k2])
                fdata[:, o, 2] = np.sign(_cross(dz[:, k2] - dz[:, k1], d1))
            else:
                assert st.guide is not None  # an RRP dyad slides on its guide
                u = complex(math.cos(st.guide.axis), math.sin(st.guide.axis))
                ops[o] = (_RRP, t, k1, -1, -1, dyad)
                fdata[:, o, 1] = np.where(_dot(d1, u) >= 0, 1.0, -1.0)
                fdata[:, o, 2:] = u.real, u.imag
            o += 1
            dyad += 1
            continue
        k1 = slot[st.known[0]]
        if st.kind == "crank":
            ops[o, [0, 2, 4]] = _CRANK, k1, bi
        elif st.guide is not None:
            ops[o, [0, 2, 4]] = _GUIDE, k1, bi
        else:
            k2 = slot[st.known[1]]
            ops[o, [0, 2, 3, 4]] = _RIGID, k1, k2, bi
            fdata[:, o, 0] = 1.0 / np.abs(dz[:, k2] - dz[:, k1]) ** 2
        # place every remaining point of the body and its centre of mass from k1
        for tname in (*st.target, f"__com__{m.bodies[bi].name}"):
            o += 1
            ops[o, :5] = _PLACE, slot[tname], k1, -1, bi
        o += 1
    return slot, dz, ops, fdata, np.array(grounded, dtype=np.int64)


def _kernel(parallel: bool = True):
    """The compiled kernel: over the variants in parallel threads, or serially (one design: no
    threads to start)."""
    from mechdyn._compiled import announce
    from mechdyn.mechanism import _dyad_kernel

    kernel = _dyad_kernel.run_parallel if parallel else _dyad_kernel.run_serial
    announce(kernel)

    def run(*args: Any) -> None:  # the kernel takes its arguments as one tuple (see _dyad_kernel)
        kernel(args)

    return run


def _body(m: Mechanism, name: str, field: str) -> str:
    """``name`` if it is one of the mechanism's bodies; a ModelError naming the field otherwise."""
    if name not in m.body_index:
        raise ModelError(
            f"body {name!r} is not in the mechanism; its bodies: {', '.join(m.body_index)}",
            element="cycle",
            field=field,
        )
    return name


def cycle(
    mechanism: Mechanism,
    n_angles: int = 360,
    points: Mapping[str, Any] | None = None,
    masses: Mapping[str, Any] | None = None,
    *,
    inertias: Mapping[str, Any] | None = None,
    store_points: bool = True,
    errors: str = "raise",
) -> CycleBatch:
    """Kinematics, driving torque and frame loads of a mechanism and its variants, in one call.

    Parameters
    ----------
    mechanism : Mechanism
        The nominal design (topology, masses, inertias, driver, loads).
    n_angles : int
        Crank angles per revolution, a whole number from 4 to 100 000.
    points : mapping of point name → array (V, 2), optional
        Drawing coordinates (m, finite, each at most 1e3 m in magnitude) that differ between
        variants; the others keep their nominal values. Each variant's drawing fixes its own link
        lengths and assembly branch.
    masses : mapping of body name → array (V,), optional
        Body masses (kg, from 0 to 1e8) that differ between variants (inertias scale with them
        unless ``inertias`` gives them).
    inertias : mapping of body name → array (V,), optional
        Moments of inertia about the centre of mass (kg·m², from 0 to 1e10) that differ between
        variants.
    store_points : bool
        Keep every point's and body's motion (for :meth:`CycleBatch.point` and ``q``); off, only
        the loads, the output and the points that carry process forces are kept, which a large
        study needs (memory grows as V × N × points).
    errors : {"raise", "nan"}
        What a variant that cannot be assembled does: raise (naming it, the angle and the joint),
        or leave NaN in its rows (see :attr:`CycleBatch.assembled`) so that a study keeps the rest.

    Returns
    -------
    CycleBatch

    Raises
    ------
    NotDecomposable
        When the mechanism is not a crank with RRR/RRP dyads (use :func:`inverse_dynamics`).
    AssemblyError
        Naming the variant that cannot be assembled.
    """
    m = mechanism
    n_angles = check_angles(n_angles)
    steps = plan(m)
    given = {}
    for name, arr in (points or {}).items():
        if name not in m.points:
            raise ModelError(f"point {name!r} is not in the drawing", element="points")
        given[name] = _z(
            check_array("cycle", f"points[{name!r}]", arr, "m", what="coordinates").reshape(-1, 2)
        )
    masses = {
        name: check_array("cycle", f"masses[{_body(m, name, 'masses')!r}]", arr, "kg", nonnegative=True)
        for name, arr in (masses or {}).items()
    }
    inertias = {
        name: check_array(
            "cycle", f"inertias[{_body(m, name, 'inertias')!r}]", arr, "kg*m^2", nonnegative=True
        )
        for name, arr in (inertias or {}).items()
    }
    V = max([1, *(a.size for a in given.values()), *(a.size for a in (*masses.values(), *inertias.values()))])
    draw = {
        k: np.broadcast_to(given[k], (V,)).copy() if k in given else np.full(V, complex(*v))
        for k, v in m.points.items()
    }
    nb = len(m.bodies)
    mass = np.tile(m.masses, (V, 1))
    inertia = np.tile(m.inertias, (V, 1))
    for name, arr in masses.items():
        i = m.body_index[name]
        new = np.broadcast_to(arr.reshape(-1), (V,))
        ratio = np.divide(new, mass[:, i], out=np.zeros(V), where=mass[:, i] > 0)
        inertia[:, i] *= ratio
        mass[:, i] = new
    for name, arr in inertias.items():
        inertia[:, m.body_index[name]] = np.broadcast_to(arr.reshape(-1), (V,))
    slot, dz, ops, fdata, grounded = _encode(m, steps, draw)
    j = m.output_joint()
    wanted = (
        list(m.points) + [f"__com__{b.name}" for b in m.bodies]
        if store_points
        else sorted(
            {pf.point for pf in m.process_forces}
            | {f"__com__{pf.body}" for pf in m.process_forces}
            | ({m.driver.pivot, *link} if (link := m.output_link()) else set())  # for layout_figures
            | (set(rocker[1:]) if (rocker := output_rocker(m)) else set())  # for swing_figures
        )
    )
    keep = np.array([slot[n] for n in wanted], dtype=np.int64)
    N = n_angles
    omega = m.driver.speed
    theta_draw = np.angle(draw[m.driver.tip] - draw[m.driver.pivot])
    step = 2 * math.pi / N * math.copysign(1.0, omega)
    pos = np.empty((V, N, keep.size), dtype=complex)
    vel = np.empty_like(pos)
    acc = np.empty_like(pos)
    rates = np.empty((V, N, nb, 3) if store_points else (0, 0, 0, 0))
    force = np.empty((V, N), dtype=complex)
    inertia_force = np.empty((V, N), dtype=complex)
    moment = np.empty((V, N))
    torque = np.empty((V, N))
    out_slot = slot[j.point] if j is not None else -1
    u_out = complex(math.cos(j.axis), math.sin(j.axis)) if j is not None else 0j
    s_out = np.empty((V, N)) if j is not None else np.empty((0, 0))
    turn = np.exp(1j * step * np.arange(N))  # the crank's rotation from the drawing, the same for all
    # θ̇, θ̈ per variant and step, read at the crank angle from the datum; "bdc" is found from the motion
    # first (positions do not depend on the speed) when a speed profile needs it
    profile_after_motion = m.angle_datum == "bdc" and m.driver.profile is not None
    if m.angle_datum == "bdc":
        omega_k, alpha_k = np.full((V, N), omega), np.zeros((V, N))
        read_at = None
    else:
        read_at = crank_angles(m, theta_draw, step, None, N)
        omega_k, alpha_k = m.driver.rates(read_at)
    n_dyads = int(sum(1 for st in steps if st.kind in ("rrr", "rrp")))
    dyad_meas = np.empty((V, N, n_dyads))  # every variant's, for the screening below
    kops, kf, gops, gf, jkind = _encode_loads(m, steps, slot)
    n_lam = m.n_constraints
    lam_out = np.empty((V, N, n_lam) if store_points else (0, 0, 0))
    peaks = np.empty((V, len(m.joints)))

    def run(loads: np.ndarray, applied: np.ndarray) -> None:
        w, a = (np.ascontiguousarray(x, dtype=float) for x in (omega_k, alpha_k))
        _kernel(parallel=V > 8)(
            dz, ops, fdata, grounded, turn, w, a, mass, inertia, complex(*m.gravity), keep,
            out_slot, u_out, pos, vel, acc, rates, force, inertia_force, moment, torque, s_out, dyad_meas,
            loads, kf, gops, gf, jkind, n_lam, applied, lam_out, peaks,
        )  # fmt: skip

    no_applied = np.zeros((0, 0, 0, 0))
    if m.process_forces or profile_after_motion:  # the motion first, then the loads
        run(np.zeros((0, 16), dtype=np.int64), no_applied)
        angle0 = crank_angles(m, theta_draw, step, s_out if j is not None else None, N)
        if profile_after_motion:
            read_at = angle0
            omega_k, alpha_k = m.driver.rates(read_at)
        applied = no_applied
        if m.process_forces:
            z0 = {n: pos[..., i] for i, n in enumerate(wanted)}
            applied = _process_loads(m, angle0, s_out if j is not None else None, z0, V, N)
        run(kops, applied)
    else:
        run(kops, no_applied)
    if errors not in ("raise", "nan"):
        raise ModelError(f"errors={errors!r} must be 'raise' or 'nan'")
    # the positions the samples may have stepped over, refined between them (mechanism.screening)
    failures: dict[int, str] = {}
    suspect = np.isnan(dyad_meas).any(axis=(1, 2)) | (np.abs(dyad_meas) < SCREEN).any(axis=(1, 2))
    for v in np.flatnonzero(suspect):
        measure = _measure(
            m,
            steps,
            {n: a[v : v + 1] for n, a in draw.items()},
            mass[v : v + 1],
            inertia[v : v + 1],
            0.0 if read_at is None else float(read_at[v, 0]),
        )
        finding = screen(measure, dyad_meas[v], abs(step))
        if finding is None:
            continue
        failures[int(v)] = _message(
            m, steps, finding, float(theta_draw[v]), math.copysign(1.0, omega), v if V > 1 else None
        )
        if errors == "raise":
            cls = SingularPositionError if finding.kind == "singular" else AssemblyError
            raise cls(failures[int(v)])
        for arr in (torque, moment, force, inertia_force, pos, vel, acc, peaks):
            arr[v] = np.nan
        if lam_out.size:
            lam_out[v] = np.nan
        if s_out.size:
            s_out[v] = np.nan
    z = {n: (pos[..., i], vel[..., i], acc[..., i]) for i, n in enumerate(wanted)}
    stroke = None if j is None else s_out
    angle = crank_angles(m, theta_draw, step, stroke, N)
    body_rates = (
        {b.name: (rates[..., i, 0], rates[..., i, 1], rates[..., i, 2]) for i, b in enumerate(m.bodies)}
        if store_points
        else {}
    )
    return CycleBatch(
        m,
        angle,
        torque,
        moment,
        stroke,
        force,
        inertia_force,
        z,
        body_rates,
        dyad_meas,
        steps,
        (pos, vel, acc, rates),
        mass,
        inertia,
        lam_out if store_points else None,
        peaks,
        failures,
    )


# the kernel's load arguments when only the motion is wanted
_NO_LOADS = (
    np.zeros((0, 16), dtype=np.int64),
    np.zeros((0, 2)),
    np.zeros((0, 4), dtype=np.int64),
    np.zeros((0, 2)),
    np.zeros(0, dtype=np.int64),
    0,
    np.zeros((0, 0, 0, 0)),
    np.zeros((0, 0, 0)),
    np.zeros((1, 0)),
)


def _measure(m: Mechanism, steps: list[Step], draw, mass: np.ndarray, inertia: np.ndarray, start: float):
    """``measure(turned) -> (M, dyads)``: one variant's dyad measures at any crank angles turned
    from the drawing (rad), by the same compiled kernel; ``start`` is the drawing's crank angle from
    the datum (rad), where a speed profile is read from."""
    _, dz, ops, fdata, grounded = _encode(m, steps, draw)
    n_dyads = int(sum(1 for st in steps if st.kind in ("rrr", "rrp")))
    sign = math.copysign(1.0, m.driver.speed)
    empty = np.empty((1, 0, 0), dtype=complex)
    kernel = _kernel(parallel=False)

    def measure(turned: np.ndarray) -> np.ndarray:
        M = turned.size
        omega_k, alpha_k = (x[None] for x in m.driver.rates(start + sign * turned))
        out = np.empty((1, M, n_dyads))
        kernel(
            dz,
            ops,
            fdata,
            grounded,
            np.exp(1j * sign * turned),
            omega_k,
            alpha_k,
            mass,
            inertia,
            complex(*m.gravity),
            np.empty(0, dtype=np.int64),
            -1,
            0j,
            np.empty((1, M, 0), dtype=complex) if M else empty,
            np.empty((1, M, 0), dtype=complex),
            np.empty((1, M, 0), dtype=complex),
            np.empty((0, 0, 0, 0)),
            np.empty((1, M), dtype=complex),
            np.empty((1, M), dtype=complex),
            np.empty((1, M)),
            np.empty((1, M)),
            np.empty((0, 0)),
            out,
            *_NO_LOADS,
        )
        return out[0]

    return measure


def _message(m: Mechanism, steps: list[Step], f: Finding, theta_draw: float, sign: float, variant) -> str:
    """The error of a screening finding: the angle (to 0.01°), the dyad's loop and its joint."""
    dyad = [st for st in steps if st.kind in ("rrr", "rrp")][f.dyad]
    p = dyad.target
    joint = next((j for j in m.joints if j.pins and j.point == p and GROUND not in j.bodies), None)
    links = " and ".join(f"{b!r}" for b in joint.bodies) if joint is not None else repr(dyad.body)
    name = joint.name if joint is not None else p
    theta = math.degrees(theta_draw + sign * f.turned) % 360
    where = f"crank angle {theta:.2f}° ({math.degrees(f.turned):.2f}° turned from the drawing)"
    which = f"variant {variant}: " if variant is not None else ""
    if f.kind == "singular":
        return (
            f"{which}singular (toggle or dead-centre) position at {where}: the links {links} of the "
            f"{dyad.kind.upper()} dyad at point {p!r} (joint {name!r}) fall in line, so the loop "
            f"through joint {name!r} locks or changes branch there and velocities and forces are "
            "unbounded; change the link lengths"
        )
    span = (
        f", over {math.degrees(f.until - f.turned):.2f}° of the turn (it closes again at "
        f"{math.degrees(f.until):.2f}°)"
        if f.until is not None
        else ""
    )
    return (
        f"{which}cannot assemble at {where}{span}: the loop through joint {name!r} "
        f"({dyad.kind.upper()} dyad at point {p!r}, links {links}) does not close; a link is too "
        "short to reach"
    )


def _com(body, draw: Mapping[str, np.ndarray]) -> np.ndarray | complex:
    """A body's centre of mass in each variant's drawing (the same in all when given as coordinates)."""
    c = body.center_of_mass
    if c is None:
        return sum(draw[p] for p in body.points) / len(body.points)
    if isinstance(c, str):
        return draw[c]
    return complex(c[0], c[1])


def variants(
    models: Sequence[Mechanism], n_angles: int = 360, *, store_points: bool = True, method: Any = "auto"
) -> CycleBatch | DesignBatch:
    """Many variant models of one mechanism in one batched evaluation; variant i of the result is
    the single-design result of ``models[i]``.

    Parameters
    ----------
    models : sequence of Mechanism
        Variants of one topology: they may differ in their drawing's point coordinates, their bodies'
        masses and inertias (and their names), nothing else.
    n_angles : int
        Crank angles per revolution, a whole number from 4 to 100 000.
    store_points : bool
        Keep the motions (and with them every joint force); see :func:`cycle`.
    method : {"auto", "dyads", "newton"} or callable
        The motion solver, as for :func:`~mechdyn.mechanism.kinematics`: ``"auto"`` and ``"dyads"``
        run one compiled batch where the mechanism decomposes; ``"newton"`` or a callable
        ``(mechanism, n_angles) -> KinematicsResult`` run design by design.

    Returns
    -------
    CycleBatch or DesignBatch
        One variant per model, in order, each with its ``status`` (``"ok"`` or why it was not
        computed: the angle, the loop and the joint); the others are computed. A crank with RRR/RRP
        dyads runs as one compiled batch (:class:`CycleBatch`); any other mechanism (gear trains,
        sliders on moving guides) runs design by design on the general engine
        (:class:`DesignBatch`, with the same summary keys).

    Raises
    ------
    ModelError
        When a model differs from the first in more than points, masses and inertias (naming the
        variant and what differs).
    """
    if not models:
        raise ModelError("give at least one model", element="variants")
    n_angles = check_angles(n_angles)
    base = models[0]
    for i, m in enumerate(models[1:], start=1):
        _same_topology(base, m, i)
    if method not in ("auto", "dyads"):
        return DesignBatch.run(models, n_angles, method)
    try:
        plan(base)
    except NotDecomposable:
        if method == "dyads":
            raise
        return DesignBatch.run(models, n_angles)
    changed = [p for p in base.points if any(m.points[p] != base.points[p] for m in models)]
    points = {p: np.array([m.points[p] for m in models]) for p in changed}
    masses, inertias = {}, {}
    for k, b in enumerate(base.bodies):
        if any(m.bodies[k].mass != b.mass for m in models):
            masses[b.name] = np.array([m.bodies[k].mass for m in models])
        # each model's own inertia, also where only the mass changes (cycle() would scale it)
        if b.name in masses or any(m.bodies[k].inertia != b.inertia for m in models):
            inertias[b.name] = np.array([m.bodies[k].inertia for m in models])
    if len(models) > 1 and not (points or masses or inertias):  # identical variants: still one each
        points = {p: np.array([base.points[p]] * len(models)) for p in list(base.points)[:1]}
    return cycle(
        base,
        n_angles,
        points,
        masses,
        inertias=inertias,
        store_points=store_points,
        errors="nan",
    )


def _same_topology(base: Mechanism, m: Mechanism, i: int) -> None:
    """Refuse a variant that differs from the first in more than points, masses and inertias."""

    def differs(what: str) -> None:
        raise ModelError(
            f"variant {i} differs from variant 0 in its {what}; a batch holds variants of one "
            "topology that differ in points, masses and inertias; run the others one by one",
            element="variants",
        )

    if set(m.points) != set(base.points):
        differs("point names")
    if len(m.bodies) != len(base.bodies):
        differs("bodies")
    for a, b in zip(m.bodies, base.bodies, strict=True):
        if (a.name, a.points, a.center_of_mass) != (b.name, b.points, b.center_of_mass):
            differs(f"body {b.name!r} (its name, points or centre of mass)")
    for what in ("joints", "driver", "gravity", "process_forces", "output", "angle_datum"):
        if getattr(m, what) != getattr(base, what):
            differs(what.replace("_", " "))


@dataclass(frozen=True, repr=False)  # the short repr of Result
class DesignBatch(Result):
    """Variants run design by design on the general engine: one result per variant, with its status.

    Attributes
    ----------
    results : tuple of DynamicsResult or None
        None for a variant that could not be computed.
    status : tuple of str
        ``"ok"``, or the error that stopped the variant.
    """

    results: tuple[Any, ...]
    status: tuple[str, ...]

    @classmethod
    def run(cls, models: Sequence[Mechanism], n_angles: int, method: Any = "auto") -> DesignBatch:
        """Each model's :func:`~mechdyn.mechanism.inverse_dynamics` with the motion solver
        ``method``; an error is kept, not raised.

        Parameters
        ----------
        models : sequence of Mechanism
            Variants of one topology.
        n_angles : int
            Crank positions over one revolution, a whole number from 4 to 100 000.
        method : str or callable
            The motion solver (see :func:`~mechdyn.mechanism.inverse_dynamics`)."""
        from mechdyn.mechanism.dynamics import inverse_dynamics

        n_angles = check_angles(n_angles)
        results: list[Any] = []
        status: list[str] = []
        for i, m in enumerate(models):
            try:
                results.append(inverse_dynamics(m, n_angles, method))
                status.append("ok")
            except ModelError as exc:
                results.append(None)
                status.append(f"variant {i}: {exc.detail}")
        return cls(tuple(results), tuple(status))

    @property
    def assembled(self) -> np.ndarray:
        """(V,) True for the variants that were computed."""
        return np.array([r is not None for r in self.results])

    def summary(self) -> dict[str, Any]:
        """Per variant (arrays over V, NaN for a failed one): the scalar figures of each design's
        :meth:`DynamicsResult.summary`, and the joint-force peaks."""
        rows = [r.summary() if r is not None else None for r in self.results]
        done = [row for row in rows if row is not None]
        if not done:
            return {}
        keys = [k for k, v in done[0].items() if isinstance(v, (int, float)) and not isinstance(v, bool)]
        out: dict[str, Any] = {
            k: np.array([row.get(k, np.nan) if row is not None else np.nan for row in rows], dtype=float)
            for k in keys
        }
        joints = list(done[0]["joint_force_peak_N"])
        out["joint_force_peak_N"] = {
            j: np.array([row["joint_force_peak_N"][j] if row is not None else np.nan for row in rows])
            for j in joints
        }
        return out

    def to_frame(self) -> Any:
        """One row per variant: its status and its figures."""
        import pandas as pd

        cols: dict[str, Any] = {"variant": np.arange(len(self.results)), "status": list(self.status)}
        for key, value in self.summary().items():
            if isinstance(value, dict):
                cols |= {f"joint_{name}_force_peak_N": v for name, v in value.items()}
            else:
                cols[key] = value
        return pd.DataFrame(cols)


def _encode_loads(m: Mechanism, steps: list[Step], slot: dict[str, int]):
    """The loads' program for the kernel: the dyads from the output back to the crank, the frame's
    joints, and each joint's kind (pin or slider) for its force peak."""
    joints = list(m.joints)
    idx = m.body_index

    def body(name: str) -> int:
        return -1 if name == GROUND else idx[name]

    def joint_at(point: str, on: str, other: str | None = None) -> int:
        for k, jt in enumerate(joints):
            if jt.pins and jt.point == point and on in jt.bodies:
                o = jt.bodies[1] if jt.bodies[0] == on else jt.bodies[0]
                if other is None or o != other:
                    return k
        raise KeyError((point, on))

    def record(k: int, on: str) -> list[int]:
        """[joint, sign of λ for a force on ``on``, the other body that takes its reaction]."""
        jt = joints[k]
        other = jt.bodies[0] if on == jt.bodies[1] else jt.bodies[1]
        return [k, 1 if on == jt.bodies[1] else -1, body(other)]

    kops, kf = [], []
    for st in reversed(steps):
        row = [0] * 16
        if st.kind == "rrr":
            assert isinstance(st.target, str)  # an RRR dyad finds one point
            p = st.target
            k1, k2 = st.known
            kp = next(
                k for k, jt in enumerate(joints) if jt.pins and jt.point == p and GROUND not in jt.bodies
            )
            jb = joints[kp].bodies
            b1 = jb[0] if k1 in m.bodies[idx[jb[0]]].points else jb[1]
            b2 = jb[1] if b1 == jb[0] else jb[0]
            row[:6] = [0, slot[p], slot[k1], slot[k2], idx[b1], idx[b2]]
            row[6:9] = record(joint_at(k1, b1, b2), b1)
            row[9:12] = record(joint_at(k2, b2, b1), b2)
            row[12:14] = [kp, 1 if joints[kp].bodies[1] == b2 else -1]
            kf.append((0.0, 0.0))
        elif st.kind == "rrp":
            target, (k1,), sl = st.target, st.known, st.body
            assert isinstance(target, str) and sl is not None and st.guide is not None  # one point
            p = target
            kg = joints.index(st.guide)
            kp = joint_at(p, sl)
            b1 = joints[kp].bodies[0] if joints[kp].bodies[1] == sl else joints[kp].bodies[1]
            row[:6] = [1, slot[p], slot[k1], -1, idx[b1], idx[sl]]
            row[6:9] = record(joint_at(k1, b1, sl), b1)
            row[9:12] = [kp, 1 if joints[kp].bodies[1] == sl else -1, kg]
            kf.append((-math.sin(st.guide.axis), math.cos(st.guide.axis)))
        else:
            continue
        kops.append(row)
    crank = m.driver.body
    k0 = joint_at(m.driver.pivot, crank)
    row = [0] * 16
    row[:8] = [
        2,
        slot[m.driver.pivot],
        -1,
        -1,
        idx[crank],
        -1,
        k0,
        1 if joints[k0].bodies[1] == crank else -1,
    ]
    kops.append(row)
    kf.append((0.0, 0.0))
    gops, gf = [], []
    for k, jt in enumerate(joints):
        if GROUND not in jt.bodies:
            continue
        if jt.pins:
            gops.append((0, k, 1 if jt.bodies[1] == GROUND else -1, slot[jt.point]))
            gf.append((0.0, 0.0))
        else:  # a slider on a frame guide (the planner allows no other)
            axis = cast(Prismatic, jt).axis
            gops.append((1, k, 0, slot[jt.point]))
            gf.append((-math.sin(axis), math.cos(axis)))
    return (
        np.array(kops, dtype=np.int64).reshape(-1, 16),
        np.array(kf, dtype=float).reshape(-1, 2),
        np.array(gops, dtype=np.int64).reshape(-1, 4),
        np.array(gf, dtype=float).reshape(-1, 2),
        np.array([0 if jt.pins else 1 for jt in joints], dtype=np.int64),
    )


def _process_loads(
    m: Mechanism, angle: np.ndarray, s: np.ndarray | None, pos: dict, V: int, N: int
) -> np.ndarray:
    """(V, N, bodies, 3) the process forces as generalised loads on the bodies (force, moment about
    the centre of mass)."""
    Q = np.zeros((V, N, len(m.bodies), 3))
    for pf in m.process_forces:
        i = m.body_index[pf.body]
        position = s if s is not None else np.zeros((V, N))
        arm = pos[pf.point] - pos[f"__com__{pf.body}"]
        valid = np.isfinite(angle) & np.isfinite(position) & np.isfinite(arm)  # NaN: a variant that failed
        fx, fy = pf.values(np.broadcast_to(angle, (V, N)), position, valid)
        F = fx + 1j * fy
        Q[..., i, 0] += F.real
        Q[..., i, 1] += F.imag
        Q[..., i, 2] += _cross(arm, F)
    return Q
