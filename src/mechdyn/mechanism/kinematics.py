"""Position, velocity and acceleration analysis over the crank cycle.

Position: Newton–Raphson on Φ(q, θ) = 0 at every crank angle, started from the drawing (which fixes
the assembly branch) and continued angle by angle with a second-order predictor
q(θ + Δθ) ≈ q + q′Δθ + ½ q″Δθ², so the branch is tracked through the whole turn. Velocity and
acceleration come from the linear systems Φ_q q̇ = −Φ_t and Φ_q q̈ = γ (Nikravesh 1988, ch. 4) —
never from differences of positions. Every step is vectorised over design variants (leading axes).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import Any, NoReturn

import numpy as np

from mechdyn.errors import ModelError
from mechdyn.mechanism.constraints import ConstraintSet
from mechdyn.mechanism.dyads import NotDecomposable, cycle
from mechdyn.mechanism.dyads.angles import crank_angles
from mechdyn.mechanism.linalg import solve_with_det
from mechdyn.mechanism.model import GROUND, Mechanism
from mechdyn.mechanism.motion import mechanism_dyads, point_motion, transmission_angle
from mechdyn.mechanism.revolution import MAX_ANGLES, AssemblyError, SingularPositionError, check_angles
from mechdyn.mechanism.screening import ANGLE_TOL

__all__ = [
    "MAX_ANGLES",
    "MOTION_SOLVERS",
    "AssemblyError",
    "KinematicsResult",
    "SingularPositionError",
    "angle_order",
    "check_angles",
    "crank_angles",
    "dyad_motion",
    "kinematics",
    "newton_motion",
]

TOL = 1e-11  # residual tolerance relative to the mechanism's size
MAX_ITER = 30
SINGULAR_RATIO = 1e-12  # |det Φ_q| / Π ‖rows‖ below this counts as singular


@dataclass(frozen=True)
class KinematicsResult:
    """Body coordinates and their derivatives over the cycle.

    Attributes
    ----------
    mechanism : Mechanism
    crank_angle : ndarray
        (N,) θ, rad (absolute, from +x).
    angle : ndarray
        (N,) crank angle from the datum, rad (what tables and plots show).
    time : ndarray
        (N,) s, for constant speed θ = θ₀ + ω t.
    q, qd, qdd : ndarray
        (N, n) body coordinates (x_G, y_G, φ per body), velocities and accelerations.
    constraints : ConstraintSet
        Assembled on first use (the dyad path needs none).
    dyads : CycleBatch or None
        The closed-form dyad solution it came from, if any (its joint forces follow by dyad
        kinetostatics in the compiled kernel, without the full Jacobian).
    """

    @cached_property
    def evaluation(self):
        """The constraints at every angle (Φ, Φ_q, the frame's Jacobian), computed once."""
        return self.constraints.evaluate(self.q, self.crank_angle, forces=True)

    mechanism: Mechanism
    crank_angle: np.ndarray
    angle: np.ndarray
    time: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    dyads: Any = None

    @cached_property
    def constraints(self) -> ConstraintSet:
        return ConstraintSet(self.mechanism)

    def point(self, body: str, point: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Position, velocity and acceleration of a drawing point on a body, each (N, 2).

        Parameters
        ----------
        body : str
            The body that carries the point.
        point : str
            A drawing point of that body; m, m/s and m/s² in the drawing's axes.
        """
        m = self.mechanism
        i = m.body_index[body]
        s = m.local(body, point)
        phi, w, a = self.q[:, 3 * i + 2], self.qd[:, 3 * i + 2], self.qdd[:, 3 * i + 2]
        c, sn = np.cos(phi), np.sin(phi)
        As = np.stack([c * s[0] - sn * s[1], sn * s[0] + c * s[1]], axis=-1)
        Bs = np.stack([-As[:, 1], As[:, 0]], axis=-1)
        pos = self.q[:, 3 * i : 3 * i + 2] + As
        vel = self.qd[:, 3 * i : 3 * i + 2] + Bs * w[:, None]
        acc = self.qdd[:, 3 * i : 3 * i + 2] + Bs * a[:, None] - As * (w**2)[:, None]
        return pos, vel, acc

    @cached_property
    def transmission_angles(self) -> dict[str, np.ndarray]:
        """Each dyad's transmission angle over the cycle, rad from 0 to π/2, keyed by the joint at the
        dyad's inner point (see :mod:`mechdyn.mechanism.motion` for the definition); empty for a
        mechanism that does not decompose into RRR/RRP dyads."""
        out = {}
        for dyad in mechanism_dyads(self.mechanism):
            z = {}
            for p in (dyad.point, *dyad.ends):
                xy = point_motion(self, p)[0]
                z[p] = xy[:, 0] + 1j * xy[:, 1]
            out[dyad.joint] = transmission_angle(dyad, z)
        return out


def _solve(J: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.linalg.solve(J, b[..., None])[..., 0]


def _scale(mechanism: Mechanism) -> float:
    pts = np.array(list(mechanism.points.values()))
    return float(max(np.ptp(pts, axis=0).max(), 1e-3))


def _newton(cs: ConstraintSet, q0: np.ndarray, theta: float, scale: float) -> tuple[np.ndarray, int]:
    q = q0.copy()
    for it in range(MAX_ITER):
        ev = cs.evaluate(q, np.asarray(theta))
        err = np.abs(ev.residual).max()
        if err < TOL * scale:
            return q, it
        try:
            dq = _solve(ev.jacobian, ev.residual)
        except np.linalg.LinAlgError:
            raise SingularPositionError(
                f"the constraint Jacobian is singular at θ = {math.degrees(theta):.6g}°"
            ) from None
        q = q - dq
    return q, -1


def _check_conditioning(J: np.ndarray, angle: np.ndarray, closes: bool) -> None:
    """Refuse a cycle that passes a singular position.

    Following a branch through a toggle or change point, det Φ_q changes sign between neighbouring
    angles, or the branch is lost and the cycle does not close on itself; landing on one makes Φ_q
    ill-conditioned. The angle reported is where |det Φ_q| is smallest: where the branch was lost.
    """
    det = solve_with_det(J, np.zeros(J.shape[:-1]))[1]
    # Hadamard's inequality |det J| ≤ Π ‖row‖: the ratio is a scale-free measure of singularity
    ratio = np.abs(det) / np.prod(np.linalg.norm(J, axis=-1), axis=-1)
    crossing = np.sign(det) != np.sign(np.roll(det, -1))
    bad = ~np.isfinite(ratio) | (ratio < SINGULAR_RATIO) | crossing
    if bad.any() or not closes:
        k = int(np.argmin(np.abs(det)))
        raise SingularPositionError(
            f"singular (toggle or dead-centre) position at crank angle {math.degrees(angle[k]):.6g}° "
            "(the constraint Jacobian becomes singular there); the mechanism locks or bifurcates, so "
            "velocities and forces are unbounded; change the link lengths"
        )


def kinematics(mechanism: Mechanism, n_angles: int = 360, method: Any = "auto") -> KinematicsResult:
    """Positions, velocities and accelerations over one crank revolution.

    Parameters
    ----------
    mechanism : Mechanism
    n_angles : int
        Crank angles per revolution, equally spaced from the datum: a whole number from 4 to
        :data:`MAX_ANGLES` (100 000).
    method : {"auto", "dyads", "newton"} or callable
        The motion solver: ``newton`` (:func:`newton_motion`, Newton–Raphson continuation on the
        assembled constraints, any mechanism), ``dyads`` (:func:`dyad_motion`, closed-form dyads for
        a crank with RRR/RRP dyads), ``auto`` (dyads where the mechanism decomposes, else Newton), or
        any callable ``(mechanism, n_angles) -> KinematicsResult``. Both built-in solvers take
        velocities and accelerations from the differentiated constraints and agree to round-off;
        the loads follow from the motion in one place (:func:`~mechdyn.mechanism.inverse_dynamics`).

    Returns
    -------
    KinematicsResult

    Raises
    ------
    AssemblyError
        Naming the crank angle and the joint whose loop does not close.
    SingularPositionError
        Naming the crank angle of a toggle position.
    """
    n_angles = check_angles(n_angles)
    if callable(method):
        return method(mechanism, n_angles)
    if method not in MOTION_SOLVERS and method != "auto":
        raise ModelError(
            f"method {method!r} must be 'auto', {', '.join(map(repr, MOTION_SOLVERS))} or a callable "
            "(mechanism, n_angles) -> KinematicsResult"
        )
    if method != "auto":
        return MOTION_SOLVERS[method](mechanism, n_angles)
    try:
        return dyad_motion(mechanism, n_angles)
    except NotDecomposable:
        return newton_motion(mechanism, n_angles)


def dyad_motion(mechanism: Mechanism, n_angles: int) -> KinematicsResult:
    """The motion by closed-form dyads (the compiled kernel of :mod:`mechdyn.mechanism.dyads`).

    Parameters
    ----------
    mechanism : Mechanism
        The mechanism, as drawn.
    n_angles : int
        Crank positions over one revolution, a whole number from 4 to 100 000.

    Raises
    ------
    NotDecomposable
        When the mechanism is not a crank with RRR/RRP dyads.
    """
    return _from_cycle(mechanism, cycle(mechanism, check_angles(n_angles)))


def newton_motion(mechanism: Mechanism, n_angles: int) -> KinematicsResult:
    """The motion by Newton continuation on the assembled constraints (any mechanism).

    Parameters
    ----------
    mechanism : Mechanism
        The mechanism, as drawn.
    n_angles : int
        Crank positions over one revolution, a whole number from 4 to 100 000.
    """
    n_angles = check_angles(n_angles)
    cs = ConstraintSet(mechanism)
    scale = _scale(mechanism)
    omega = mechanism.driver.speed
    theta_draw = mechanism.drawing_crank_angle
    step = 2.0 * math.pi / n_angles * math.copysign(1.0, omega)
    # assemble the drawing (it may be slightly off) and go round once from there
    q, it = _newton(cs, mechanism.drawing_coordinates, theta_draw, scale)
    if it < 0:
        raise AssemblyError(
            f"the drawing does not assemble at θ = {math.degrees(theta_draw):.6g}°; "
            "check its point coordinates"
        )
    n = cs.n
    thetas = theta_draw + step * np.arange(n_angles)
    Q = np.empty((n_angles, n))
    V = np.empty((n_angles, n))
    A = np.empty((n_angles, n))
    turned = np.abs(step) * np.arange(n_angles)
    datum = _datum(mechanism, n_angles)
    wk, ak = mechanism.driver.rates(thetas - datum)
    for k, th in enumerate(thetas):
        if k:
            # second-order predictor in the crank angle: q′ = q̇/θ̇, q″ = (q̈ − q′ θ̈)/θ̇²
            dq = V[k - 1] / wk[k - 1]
            ddq = (A[k - 1] - dq * ak[k - 1]) / wk[k - 1] ** 2
            q, it = _newton(cs, Q[k - 1] + dq * step + 0.5 * ddq * step**2, th, scale)
            if it < 0:
                _raise_lost(cs, mechanism, Q[k - 1], V[k - 1], A[k - 1], thetas[k - 1], th, scale, datum)
        ev = cs.evaluate(q, np.asarray(th))
        Q[k] = q
        rhs_v = np.zeros(cs.m)
        rhs_v[-1] = wk[k]
        V[k] = _solve(ev.jacobian, rhs_v)
        ev = cs.evaluate(q, np.asarray(th), V[k])
        assert ev.gamma is not None  # velocities were given
        ev.gamma[-1] = ak[k]  # the driver: φ̈_crank = θ̈
        A[k] = _solve(ev.jacobian, ev.gamma)
    # one more step must bring the mechanism back to where it started: the branch was kept
    dq = V[-1] / wk[-1]
    q_end, it = _newton(
        cs, Q[-1] + dq * step + 0.5 * (A[-1] - dq * ak[-1]) / wk[-1] ** 2 * step**2, thetas[-1] + step, scale
    )
    closes = it >= 0 and _same_pose(mechanism, q_end, Q[0], scale)
    if not closes and it >= 0:
        _check_gear_period(mechanism, q_end, Q[0], scale)
    s_out = output_position(mechanism, Q)
    angle = crank_angles(
        mechanism, np.array([theta_draw]), step, None if s_out is None else s_out[None], n_angles
    )[0]
    order = np.argsort(angle)
    result = KinematicsResult(
        mechanism,
        thetas[order],
        angle[order],
        mechanism.driver.time(turned, theta_draw - datum)[order],
        Q[order],
        V[order],
        A[order],
    )
    try:
        _check_conditioning(result.evaluation.jacobian, angle[order], closes)
    except SingularPositionError:
        _raise_singular(cs, mechanism, Q, V, A, thetas, scale, datum)
        raise
    return result


def _datum(mechanism: Mechanism, n_angles: int) -> float:
    """The absolute crank angle of the angle datum, rad, where a speed profile is read from.

    A fixed datum is itself; ``"bdc"`` is the lowest sampled output position, found from the motion
    at constant speed first (positions do not depend on the speed), only when a profile needs it.
    """
    if mechanism.angle_datum != "bdc":
        return float(mechanism.angle_datum)
    if mechanism.driver.profile is None:
        return 0.0  # constant speed: read nowhere
    from dataclasses import replace

    steady = newton_motion(replace(mechanism, driver=replace(mechanism.driver, profile=None)), n_angles)
    return float(steady.crank_angle[0] - steady.angle[0])


def _advance(
    cs: ConstraintSet,
    mechanism: Mechanism,
    q: np.ndarray,
    qd: np.ndarray,
    qdd: np.ndarray,
    th0: float,
    th: float,
    scale: float,
    datum: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """Position, velocity and acceleration at θ from a solution at θ₀ (second-order predictor and
    Newton); None where the loops do not close. ``datum``: the absolute angle of the angle datum."""
    w, a = mechanism.driver.rates(np.array([th0, th]) - datum)
    h = th - th0
    dq = qd / w[0]
    ddq = (qdd - dq * a[0]) / w[0] ** 2
    q1, it = _newton(cs, q + dq * h + 0.5 * ddq * h**2, th, scale)
    if it < 0 or np.abs(q1 - q).max() > 0.5 * scale:  # not converged, or jumped to another branch
        return None
    ev = cs.evaluate(q1, np.asarray(th))
    rhs = np.zeros(cs.m)
    rhs[-1] = w[1]
    v1 = _solve(ev.jacobian, rhs)
    ev = cs.evaluate(q1, np.asarray(th), v1)
    assert ev.gamma is not None  # velocities were given
    ev.gamma[-1] = a[1]
    return q1, v1, _solve(ev.jacobian, ev.gamma)


def _where(mechanism: Mechanism, th: float) -> str:
    turned = math.degrees(abs(th - mechanism.drawing_crank_angle))
    return f"crank angle {math.degrees(th) % 360:.2f}° ({turned:.2f}° turned from the drawing)"


def _raise_lost(
    cs: ConstraintSet,
    mechanism: Mechanism,
    q: np.ndarray,
    qd: np.ndarray,
    qdd: np.ndarray,
    lo: float,
    hi: float,
    scale: float,
    datum: float,
) -> NoReturn:
    """The loops stop closing between θ = lo (solved) and hi: bisect to ANGLE_TOL and name the joint."""
    state = (q, qd, qdd)
    while abs(hi - lo) > ANGLE_TOL:
        mid = 0.5 * (lo + hi)
        nxt = _advance(cs, mechanism, *state, lo, mid, scale, datum)
        if nxt is None:
            hi = mid
        else:
            lo, state = mid, nxt
    q_try, _ = _newton(cs, state[0], hi, scale)
    ev = cs.evaluate(q_try, np.asarray(hi))
    row = int(np.argmax(np.abs(ev.residual)))
    joint, _ = cs.rows[row]
    raise AssemblyError(
        f"cannot assemble at {_where(mechanism, hi)}: the loop through joint {joint!r} does not close; "
        "a link is too short to reach"
    )


def _raise_singular(
    cs: ConstraintSet,
    mechanism: Mechanism,
    Q: np.ndarray,
    V: np.ndarray,
    A: np.ndarray,
    thetas: np.ndarray,
    scale: float,
    datum: float,
) -> None:
    """Locate a singular position (det Φ_q changes sign, or the branch is lost) between the samples
    to ANGLE_TOL and raise naming it and the joints whose constraints become dependent there.
    Returns when no sign change is found (the caller then raises its sampled report)."""
    n = thetas.size
    det = solve_with_det(cs.evaluate(Q, thetas).jacobian, np.zeros((n, cs.m)))[1]
    for k in range(n):
        k1 = (k + 1) % n
        if k1 == 0:
            break  # the last step's partner is the start of the next turn, checked by the closing
        if np.sign(det[k]) == np.sign(det[k1]) and det[k] != 0:
            continue
        lo, hi, state, d_lo = thetas[k], thetas[k1], (Q[k], V[k], A[k]), det[k]
        while abs(hi - lo) > ANGLE_TOL:
            mid = 0.5 * (lo + hi)
            nxt = _advance(cs, mechanism, *state, lo, mid, scale, datum)
            if nxt is None:  # the loops stop closing inside: a jam, not a toggle
                _raise_lost(cs, mechanism, *state, lo, mid, scale, datum)
            d_mid = solve_with_det(cs.evaluate(nxt[0], np.asarray(mid)).jacobian[None], np.zeros((1, cs.m)))[
                1
            ][0]
            if np.sign(d_mid) == np.sign(d_lo) and d_mid != 0:
                lo, state, d_lo = mid, nxt, d_mid
            else:
                hi = mid
        J = cs.evaluate(state[0], np.asarray(lo)).jacobian
        u = np.linalg.svd(J)[0][:, -1]  # the rows that become dependent
        weight: dict[str, float] = {}
        for r, (joint, _) in enumerate(cs.rows):
            weight[joint] = max(weight.get(joint, 0.0), abs(u[r]))
        top = max(weight.values())
        names = [j for j, w in weight.items() if w > 0.3 * top and j != "driver"]
        raise SingularPositionError(
            f"singular (toggle or dead-centre) position at {_where(mechanism, lo)}: the constraints of "
            f"joint(s) {', '.join(map(repr, names))} become dependent (the loop through them locks or "
            "changes branch), so velocities and forces are unbounded; change the link lengths"
        )


def angle_order(angle: np.ndarray) -> np.ndarray | slice:
    """The order that sorts a cycle's crank angles (rad): a whole slice where they are in order
    already (a datum at the first sample: the arrays are then views, not copies), else the
    ``argsort``.

    Parameters
    ----------
    angle : ndarray
        (N,) crank angle from the datum at each step of the cycle, rad.
    """
    if angle.size < 2 or bool((angle[1:] > angle[:-1]).all()):
        return slice(None)
    return np.argsort(angle)


def _from_cycle(mechanism: Mechanism, c) -> KinematicsResult:
    """A KinematicsResult from the dyad path (one variant), ordered by angle and checked."""
    order = angle_order(c.angle[0])
    n = c.angle.shape[1]
    step = 2.0 * math.pi / n * math.copysign(1.0, mechanism.driver.speed)
    turned = np.abs(step) * np.arange(n)
    theta = (mechanism.drawing_crank_angle + step * np.arange(n))[order]
    q, qd, qdd = (a[0][order] for a in c.coordinates())
    angle = c.angle[0][order]
    time = mechanism.driver.time(turned, float(c.angle[0, 0]))[order]  # c.angle: in cycle order
    result = KinematicsResult(mechanism, theta, angle, time, q, qd, qdd, c)
    # (N, dyads) in cycle order: Φ_q is singular exactly where one of these is zero, or changes sign
    # between neighbouring angles (NaN where a loop does not close)
    meas = c._dyad_measure[0]
    nxt = np.concatenate([meas[1:], meas[:1]])
    bad = ~((meas * nxt > 0) & (np.abs(meas) >= 1e-9)).all(axis=1)
    if bad.any():
        k = int(np.argmin(np.abs(meas).min(axis=1, initial=1.0)))
        raise SingularPositionError(
            f"singular (toggle or dead-centre) position at crank angle {math.degrees(c.angle[0, k]):.6g}° "
            "(a dyad's links fall in line there); the mechanism locks or bifurcates, so velocities and "
            "forces are unbounded; change the link lengths"
        )
    return result


def _same_pose(mechanism: Mechanism, a: np.ndarray, b: np.ndarray, scale: float) -> bool:
    """Every body's centre of mass and drawing points in the same place (rotations up to whole
    turns; a body with one point, such as a gear on its pivot, may end turned by any angle)."""
    pa, pb = a.reshape(-1, 3), b.reshape(-1, 3)
    if np.abs(pa[:, :2] - pb[:, :2]).max() >= 1e-6 * scale:
        return False
    for i, body in enumerate(mechanism.bodies):
        s = np.array([mechanism.local(body.name, p) for p in body.points])
        c, sn = math.cos(pa[i, 2] - pb[i, 2]), math.sin(pa[i, 2] - pb[i, 2])
        turned = s @ np.array([[c, sn], [-sn, c]])  # R(Δφ) s, row by row
        if np.abs(turned - s).max() >= 1e-6 * scale:
            return False
    return True


def _check_gear_period(mechanism: Mechanism, a: np.ndarray, b: np.ndarray, scale: float) -> None:
    """A gear that has not come back after one crank turn: the train's period is several turns."""
    joints = {j.name: j for j in mechanism.joints}
    geared = {g for name in mechanism.gear_laws for g in joints[name].bodies}
    for i, body in enumerate(mechanism.bodies):
        if body.name not in geared:
            continue
        s = np.array([mechanism.local(body.name, p) for p in body.points])
        d = a[3 * i + 2] - b[3 * i + 2]
        turned = s @ np.array([[math.cos(d), math.sin(d)], [-math.sin(d), math.cos(d)]])
        if np.abs(turned - s).max() >= 1e-6 * scale:
            raise ModelError(
                f"gear {body.name!r} is turned by {math.degrees(d):.6g}° from its drawing pose after one "
                "turn of the crank: the gear train repeats only after several crank turns, and its "
                "points with it. Drive the gear that turns slowest, or pick ratios that repeat every turn",
                element=body.name,
            )


def output_position(mechanism: Mechanism, q: np.ndarray) -> np.ndarray | None:
    """Position of the output point along its prismatic axis, m (None without a prismatic output)."""
    j = mechanism.output_joint()
    if j is None:
        return None
    body = j.bodies[1] if j.bodies[0] == GROUND else j.bodies[0]  # the side that moves
    i = mechanism.body_index[body]
    s = mechanism.local(body, j.point)
    phi = q[..., 3 * i + 2]
    p = q[..., 3 * i : 3 * i + 2] + np.stack(
        [np.cos(phi) * s[0] - np.sin(phi) * s[1], np.sin(phi) * s[0] + np.cos(phi) * s[1]], axis=-1
    )
    u = np.array([math.cos(j.axis), math.sin(j.axis)])
    return (p - np.asarray(mechanism.points[j.point])) @ u


MOTION_SOLVERS = {"dyads": dyad_motion, "newton": newton_motion}
"""The built-in motion solvers by name; :func:`kinematics` also takes any callable of this form."""
