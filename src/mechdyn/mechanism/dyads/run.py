"""The dyad path's runs: :func:`cycle` (one mechanism and its point and mass arrays over a revolution),
one pass of the compiled kernel over every crank angle and design variant, with the positions the
samples may have stepped over screened between them (:mod:`mechdyn.mechanism.screening`); and its
steps (:class:`Setup`, :func:`run_block`, :func:`screen_block`), which the summary-only batch
(:mod:`.summary`) runs block by block. A sequence of variant models: :mod:`mechdyn.mechanism.designs`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from typing import Any, NamedTuple, cast

import numpy as np

from mechdyn.checks import check_array
from mechdyn.errors import ModelError
from mechdyn.mechanism.dyads.angles import crank_angles
from mechdyn.mechanism.dyads.arguments import (
    KernelArgs,
    _cross,
    encode,
    encode_loads,
    kernel_args,
    motion_only,
)
from mechdyn.mechanism.dyads.decomposition import Step, plan
from mechdyn.mechanism.dyads.results import CycleBatch
from mechdyn.mechanism.model import GROUND, Mechanism
from mechdyn.mechanism.revolution import AssemblyError, SingularPositionError, check_angles
from mechdyn.mechanism.screening import SCREEN, Finding, screen

__all__ = ["Outputs", "Setup", "cycle", "dyad_plan", "nominal_setup", "run_block", "screen_block"]


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


def checked_variants(
    m: Mechanism,
    points: Mapping[str, Any] | None,
    masses: Mapping[str, Any] | None,
    inertias: Mapping[str, Any] | None,
) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray], dict[str, np.ndarray]]:
    """The variants' points (complex, m), masses (kg) and inertias (kg·m²), checked finite and
    named in the drawing, as :func:`cycle` and :func:`~mechdyn.mechanism.dyads.cycle_summary` take
    them."""
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
    return given, masses, inertias


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
    steps = dyad_plan(m)
    given, masses, inertias = checked_variants(m, points, masses, inertias)
    if given or masses or inertias:
        setup = _setup(m, steps, n_angles, given, masses, inertias, store_points)
    else:  # the design as drawn: its encoded plan is kept with the (immutable) model
        setup = nominal_setup(m, n_angles, store_points)
    if errors not in ("raise", "nan"):
        raise ModelError(f"errors={errors!r} must be 'raise' or 'nan'")
    V, N, nb = setup.V, setup.N, len(m.bodies)
    K = setup.keep.size
    out = Outputs(
        pos=np.empty((V, N, K), dtype=complex),
        vel=np.empty((V, N, K), dtype=complex),
        acc=np.empty((V, N, K), dtype=complex),
        rates=np.empty((V, N, nb, 3) if store_points else (0, 0, 0, 0)),
        force=np.empty((V, N), dtype=complex),
        inertia_force=np.empty((V, N), dtype=complex),
        moment=np.empty((V, N)),
        torque=np.empty((V, N)),
        stroke=np.empty((V, N)) if setup.output_slot >= 0 else np.empty((0, 0)),
        dyad_measure=np.empty((V, N, setup.n_dyads)),  # every variant's, for the screening
        multipliers=np.empty((V, N, m.n_constraints) if store_points else (0, 0, 0)),
        peaks=np.empty((V, len(m.joints))),
    )
    read_at = run_block(setup, 0, V, out)
    failures: dict[int, str] = {}
    screen_block(setup, 0, out, read_at, errors, failures)
    pos, vel, acc, rates = out.pos, out.vel, out.acc, out.rates
    z = {n: (pos[..., i], vel[..., i], acc[..., i]) for i, n in enumerate(setup.wanted)}
    stroke = out.stroke if setup.output_slot >= 0 else None
    angle = crank_angles(m, setup.theta_draw, setup.step, stroke, N)
    body_rates = (
        {b.name: (rates[..., i, 0], rates[..., i, 1], rates[..., i, 2]) for i, b in enumerate(m.bodies)}
        if store_points
        else {}
    )
    return CycleBatch(
        m,
        angle,
        out.torque,
        out.moment,
        stroke,
        out.force,
        out.inertia_force,
        z,
        body_rates,
        out.dyad_measure,
        list(steps),  # the result's own: the plan and the setup may be the model's cached ones
        (pos, vel, acc, rates),
        setup.mass.copy(),
        setup.inertia.copy(),
        out.multipliers if store_points else None,
        out.peaks,
        failures,
    )


class Setup(NamedTuple):
    """Everything a run of the kernel needs that does not depend on which variants it runs: the
    encoded plan, the variants' drawings, masses and inertias (rows over V), the loads' program."""

    m: Mechanism
    steps: list[Step]
    V: int
    N: int
    draw: dict[str, np.ndarray]
    mass: np.ndarray
    inertia: np.ndarray
    dz: np.ndarray | None  # None: encoded block by block (the summary-only batch)
    ops: np.ndarray
    fdata: np.ndarray | None
    grounded: np.ndarray
    wanted: list[str]
    keep: np.ndarray
    theta_draw: np.ndarray
    step: float
    turn: np.ndarray
    output_slot: int
    output_axis: complex
    n_dyads: int
    load_ops: np.ndarray
    load_data: np.ndarray
    frame_ops: np.ndarray
    frame_data: np.ndarray
    joint_kind: np.ndarray


class Outputs(NamedTuple):
    """The kernel's outputs for a block of variants (rows: the block's variants), as
    :class:`~mechdyn.mechanism.dyads.arguments.KernelArgs` names them."""

    pos: np.ndarray
    vel: np.ndarray
    acc: np.ndarray
    rates: np.ndarray
    force: np.ndarray
    inertia_force: np.ndarray
    moment: np.ndarray
    torque: np.ndarray
    stroke: np.ndarray
    dyad_measure: np.ndarray
    multipliers: np.ndarray
    peaks: np.ndarray


def _cache(m: Mechanism) -> dict[Any, Any]:
    """What the dyad path keeps with a model: a model is immutable (a variant is a new object), so
    its plan and its drawing's encoding hold for its lifetime (stored as ``cached_property`` stores,
    beside the dataclass fields, which equality and ``replace`` ignore). Its drawing is a plain dict,
    though: one edited in place (not a supported use, but an easy one) empties the cache."""
    cache = cast(dict[Any, Any], m.__dict__.setdefault("_dyad_cache", {}))
    drawn = cache.get("drawing")
    if drawn is not None and drawn != m.points:
        cache.clear()
    if not cache:
        cache["drawing"] = dict(m.points)
    return cache


def dyad_plan(m: Mechanism) -> list[Step]:
    """:func:`~mechdyn.mechanism.dyads.plan` of ``m``, worked out once per model.

    Parameters
    ----------
    m : Mechanism
        The model.

    Raises
    ------
    NotDecomposable
        When the mechanism is not a crank with RRR/RRP dyads (not kept: asked again each time).
    """
    cache = _cache(m)
    if "plan" not in cache:
        cache["plan"] = plan(m)
    return cast(list[Step], cache["plan"])


def nominal_setup(m: Mechanism, n_angles: int, store_points: bool) -> Setup:
    """The :class:`Setup` of the design as drawn (one variant), worked out once per model, number of
    angles and ``store_points`` (the kernel and the results only read its arrays).

    Parameters
    ----------
    m : Mechanism
        The model.
    n_angles : int
        Crank angles per revolution (checked by the caller).
    store_points : bool
        Whether every point's motion is kept.
    """
    cache = _cache(m)
    key = ("setup", n_angles, store_points)
    if key not in cache:
        setup = _setup(m, dyad_plan(m), n_angles, {}, {}, {}, store_points)
        setups = [k for k in list(cache) if isinstance(k, tuple)]  # a snapshot: threads may share it
        if len(setups) > 16:  # a model analysed at many resolutions: keep the latest few
            cache.pop(setups[0], None)
        cache[key] = setup
    return cast(Setup, cache[key])


def _setup(m, steps, n_angles, given, masses, inertias, store_points, encode_all=True) -> Setup:
    """The variants' data (checked inputs) and the encoded plan, once per call (``encode_all``
    False: each variant's encoded drawing is left to :func:`run_block`, block by block)."""
    V = max([1, *(a.size for a in given.values()), *(a.size for a in (*masses.values(), *inertias.values()))])
    draw = {
        k: np.broadcast_to(given[k], (V,)).copy() if k in given else np.full(V, complex(*v))
        for k, v in m.points.items()
    }
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
    if encode_all:
        slot, dz, ops, fdata, grounded = encode(m, steps, draw)
    else:
        slot, _, ops, _, grounded = encode(m, steps, {k: v[:1] for k, v in draw.items()})
        dz = fdata = None
    j = m.output_joint()
    wanted = (
        list(m.points) + [f"__com__{b.name}" for b in m.bodies]
        if store_points
        else sorted(
            {pf.point for pf in m.process_forces}
            | {f"__com__{pf.body}" for pf in m.process_forces}
            | ({m.driver.pivot, *link} if (link := m.output_link()) else set())  # for layout_figures
            | (set(rocker[1:]) if (rocker := m.output_rocker()) else set())  # for swing_figures
        )
    )
    N = n_angles
    step = 2 * math.pi / N * math.copysign(1.0, m.driver.speed)
    kops, kf, gops, gf, jkind = encode_loads(m, steps, slot)
    return Setup(
        m=m,
        steps=steps,
        V=V,
        N=N,
        draw=draw,
        mass=mass,
        inertia=inertia,
        dz=dz,
        ops=ops,
        fdata=fdata,
        grounded=grounded,
        wanted=wanted,
        keep=np.array([slot[n] for n in wanted], dtype=np.int64),
        theta_draw=np.angle(draw[m.driver.tip] - draw[m.driver.pivot]),
        step=step,
        turn=np.exp(1j * step * np.arange(N)),  # the crank's rotation from the drawing, the same for all
        output_slot=slot[j.point] if j is not None else -1,
        output_axis=complex(math.cos(j.axis), math.sin(j.axis)) if j is not None else 0j,
        n_dyads=int(sum(1 for st in steps if st.kind in ("rrr", "rrp"))),
        load_ops=kops,
        load_data=kf,
        frame_ops=gops,
        frame_data=gf,
        joint_kind=jkind,
    )


def run_block(
    s: Setup, lo: int, hi: int, out: Outputs, kernel: Callable[[KernelArgs], None] | None = None
) -> np.ndarray | None:
    """The kernel over variants ``lo:hi`` of ``s``, written into ``out`` (rows: those variants).

    Parameters
    ----------
    s : Setup
        The variants and the encoded plan (:func:`cycle`'s first step).
    lo, hi : int
        The block of variants, indices into the V of ``s``.
    out : Outputs
        The kernel's outputs, hi − lo rows each (an empty array: not kept); joint-force peaks in N.
    kernel : callable, optional
        Runs the pass that computes the loads in place of the compiled kernel (the summary-only
        batch's kernel, which reduces as it goes).

    Returns
    -------
    ndarray or None
        (hi − lo, N) the crank angle from the datum each variant's speed was read at, rad; None
        where the datum is bottom dead centre and the speed constant.
    """
    m, N, W = s.m, s.N, hi - lo
    omega = m.driver.speed
    theta_draw = s.theta_draw[lo:hi]
    # θ̇, θ̈ per variant and step, read at the crank angle from the datum; "bdc" is found from the motion
    # first (positions do not depend on the speed) when a speed profile needs it
    profile_after_motion = m.angle_datum == "bdc" and m.driver.profile is not None
    read_at: np.ndarray | None
    if m.angle_datum == "bdc":
        omega_k, alpha_k = np.full((W, N), omega), np.zeros((W, N))
        read_at = None
    else:
        read_at = crank_angles(m, theta_draw, s.step, None, N)
        omega_k, alpha_k = m.driver.rates(read_at)
    has_output = s.output_slot >= 0
    if s.dz is not None and s.fdata is not None:
        dz, fdata = s.dz[lo:hi], s.fdata[lo:hi]
    else:
        _, dz, _, fdata, _ = encode(m, s.steps, {k: v[lo:hi] for k, v in s.draw.items()})

    def run(loads: np.ndarray, applied: np.ndarray) -> None:
        w, a = (np.ascontiguousarray(x, dtype=float) for x in (omega_k, alpha_k))
        args = kernel_args(
            drawing=dz,
            ops=s.ops,
            op_data=fdata,
            grounded=s.grounded,
            turn=s.turn,
            omega=w,
            alpha=a,
            mass=s.mass[lo:hi],
            inertia=s.inertia[lo:hi],
            gravity=complex(*m.gravity),
            keep=s.keep,
            output_slot=s.output_slot,
            output_axis=s.output_axis,
            load_ops=loads,
            load_data=s.load_data,
            frame_ops=s.frame_ops,
            frame_data=s.frame_data,
            joint_kind=s.joint_kind,
            n_multipliers=m.n_constraints,
            applied=applied,
            **out._asdict(),
        )
        if kernel is not None and loads.shape[0]:
            kernel(args)
        else:
            _kernel(parallel=W > 8)(args)

    no_applied = np.zeros((0, 0, 0, 0))
    if m.process_forces or profile_after_motion:  # the motion first, then the loads
        run(np.zeros((0, 16), dtype=np.int64), no_applied)
        s_out = out.stroke if has_output else None
        angle0 = crank_angles(m, theta_draw, s.step, s_out, N)
        if profile_after_motion:
            read_at = angle0
            omega_k, alpha_k = m.driver.rates(read_at)
        applied = no_applied
        if m.process_forces:
            z0 = {n: out.pos[..., i] for i, n in enumerate(s.wanted)}
            applied = _process_loads(m, angle0, s_out, z0, W, N)
        run(s.load_ops, applied)
    else:
        run(s.load_ops, no_applied)
    return read_at


def screen_block(
    s: Setup, lo: int, out: Outputs, read_at: np.ndarray | None, errors: str, failures: dict[int, str]
) -> None:
    """Screen the positions the samples of variants ``lo:lo + len(out)`` may have stepped over
    (:mod:`mechdyn.mechanism.screening`).

    Parameters
    ----------
    s : Setup
        The variants and the encoded plan.
    lo : int
        The index of the block's first variant in the V of ``s``.
    out : Outputs
        The block's kernel outputs (:func:`run_block`); a failed variant's rows become NaN (its
        dyad measures stay).
    read_at : ndarray or None
        (rows, N) the crank angles the speed was read at, rad (:func:`run_block`'s return).
    errors : {"raise", "nan"}
        Raise at the first variant that fails, or name it in ``failures``.
    failures : dict of int to str
        Written: variant index in the whole batch → why it fails (the angle, the loop, the joint).

    Raises
    ------
    AssemblyError, SingularPositionError
        With ``errors="raise"``, naming the variant, the crank angle and the joint.
    """
    m, steps = s.m, s.steps
    meas = out.dyad_measure
    suspect = np.isnan(meas).any(axis=(1, 2)) | (np.abs(meas) < SCREEN).any(axis=(1, 2))
    for i in np.flatnonzero(suspect):
        v = lo + int(i)
        measure = _measure(
            m,
            steps,
            {n: a[v : v + 1] for n, a in s.draw.items()},
            s.mass[v : v + 1],
            s.inertia[v : v + 1],
            0.0 if read_at is None else float(read_at[i, 0]),
        )
        finding = screen(measure, meas[i], abs(s.step))
        if finding is None:
            continue
        failures[v] = _message(
            m, steps, finding, float(s.theta_draw[v]), math.copysign(1.0, s.step), v if s.V > 1 else None
        )
        if errors == "raise":
            cls = SingularPositionError if finding.kind == "singular" else AssemblyError
            raise cls(failures[v])
        for arr in out:  # every output of the variant that is kept (its dyad measures stay)
            if arr.size and arr is not out.dyad_measure:
                arr[i] = np.nan


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
