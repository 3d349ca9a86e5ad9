"""The dyad path's runs: :func:`cycle` (one mechanism and its point and mass arrays over a revolution)
and :func:`variants` (a sequence of variant models), each one pass of the compiled kernel over every
crank angle and design variant, with the positions the samples may have stepped over screened between
them (:mod:`mechdyn.mechanism.screening`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

from mechdyn.checks import check_array
from mechdyn.errors import ModelError
from mechdyn.mechanism.dyads.arguments import KernelArgs, _cross, encode, encode_loads, motion_only
from mechdyn.mechanism.dyads.decomposition import NotDecomposable, Step, plan
from mechdyn.mechanism.dyads.results import CycleBatch, DesignBatch
from mechdyn.mechanism.kinematics import AssemblyError, SingularPositionError, check_angles, crank_angles
from mechdyn.mechanism.model import GROUND, Mechanism
from mechdyn.mechanism.motion import output_rocker
from mechdyn.mechanism.screening import SCREEN, Finding, screen

__all__ = ["cycle", "variants"]


def _z(xy: Any) -> np.ndarray:
    a = np.asarray(xy, dtype=float)
    return a[..., 0] + 1j * a[..., 1]


def _kernel(parallel: bool = True) -> Callable[[KernelArgs], None]:
    """The compiled kernel: over the variants in parallel threads, or serially (one design: no
    threads to start)."""
    from mechdyn._compiled import announce
    from mechdyn.mechanism.dyads import _kernel as compiled

    kernel: Callable[[KernelArgs], None] = compiled.run_parallel if parallel else compiled.run_serial
    announce(kernel)
    return kernel


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
    slot, dz, ops, fdata, grounded = encode(m, steps, draw)
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
    kops, kf, gops, gf, jkind = encode_loads(m, steps, slot)
    n_lam = m.n_constraints
    lam_out = np.empty((V, N, n_lam) if store_points else (0, 0, 0))
    peaks = np.empty((V, len(m.joints)))

    def run(loads: np.ndarray, applied: np.ndarray) -> None:
        w, a = (np.ascontiguousarray(x, dtype=float) for x in (omega_k, alpha_k))
        args = KernelArgs(
            drawing=dz,
            ops=ops,
            op_data=fdata,
            grounded=grounded,
            turn=turn,
            omega=w,
            alpha=a,
            mass=mass,
            inertia=inertia,
            gravity=complex(*m.gravity),
            keep=keep,
            output_slot=out_slot,
            output_axis=u_out,
            pos=pos,
            vel=vel,
            acc=acc,
            rates=rates,
            force=force,
            inertia_force=inertia_force,
            moment=moment,
            torque=torque,
            stroke=s_out,
            dyad_measure=dyad_meas,
            load_ops=loads,
            load_data=kf,
            frame_ops=gops,
            frame_data=gf,
            joint_kind=jkind,
            n_multipliers=n_lam,
            applied=applied,
            multipliers=lam_out,
            peaks=peaks,
        )
        _kernel(parallel=V > 8)(args)

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


def _measure(m: Mechanism, steps: list[Step], draw, mass: np.ndarray, inertia: np.ndarray, start: float):
    """``measure(turned) -> (M, dyads)``: one variant's dyad measures at any crank angles turned
    from the drawing (rad), by the same compiled kernel; ``start`` is the drawing's crank angle from
    the datum (rad), where a speed profile is read from."""
    _, dz, ops, fdata, grounded = encode(m, steps, draw)
    n_dyads = int(sum(1 for st in steps if st.kind in ("rrr", "rrp")))
    sign = math.copysign(1.0, m.driver.speed)
    kernel = _kernel(parallel=False)

    def measure(turned: np.ndarray) -> np.ndarray:
        M = turned.size
        omega_k, alpha_k = (x[None] for x in m.driver.rates(start + sign * turned))
        out = np.empty((1, M, n_dyads))
        turn = np.exp(1j * sign * turned)
        gravity = complex(*m.gravity)
        kernel(motion_only(dz, ops, fdata, grounded, turn, omega_k, alpha_k, mass, inertia, gravity, out))
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
