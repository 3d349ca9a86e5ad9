"""Pseudo-arclength continuation of the periodic orbit with backlash, through its folds.

The periodic orbit of the backlash flow at reference speed Ω is the fixed point of the period map,

    F(y, Ω) = φ(T(Ω); y, Ω) − y = 0,

y the state (x, ẋ) at the start of a period and φ the event-located flow of :mod:`._nonsmooth` (the
same flow and contact law as :mod:`.shooting`'s Newton at one speed). With the speed an unknown the
solutions form curves in (y, Ω); where the softening backlash nonlinearity bends a curve over
(Kahraman & Singh, *J. Sound Vib.* 142 (1990) 49–75) the curve turns back in Ω at a **fold** (a
saddle-node: a real Floquet multiplier crosses +1) and a natural continuation in Ω cannot pass it.
Pseudo-arclength continuation (H. B. Keller, "Numerical solution of bifurcation and nonlinear
eigenvalue problems", in *Applications of Bifurcation Theory*, Academic Press 1977, 359–384; Seydel,
*Practical Bifurcation and Stability Analysis*, 3rd ed., Springer 2010, ch. 4; Nayfeh &
Balachandran, *Applied Nonlinear Dynamics*, Wiley 1995, ch. 7) parametrises the curve by its
arclength s instead:

* **predictor** along the unit tangent t of the curve, z₀ = z_k + Δs t_k (z = (y, Ω) scaled);
* **corrector**: Newton on the bordered system

      [ F_y   F_Ω ] [δy]      [ F                 ]
      [    t_kᵀ   ] [δΩ] = −  [ t_kᵀ (z − z₀)     ],

  F_y = Φ − I from the variational equations with the saltation matrices of the contact changes
  (:class:`._nonsmooth.NonsmoothFlow`), F_Ω by a forward difference in Ω at each iterate (one more
  run of the flow, without the variational equations);
* the **tangent** at the new point: the null vector of [F_y F_Ω] (its last right singular vector),
  in the sense of the secant from the last point;
* **step-size control**: Δs grows by 1.5 after a corrector that converged in at most three iterations
  with the tangent turned by less than :data:`MAX_TURN`/2, and halves after one that needed more than
  five; a failed corrector, a point that lands farther than 2Δs from its predictor (a jump to another
  curve) or a tangent turned by more than :data:`MAX_TURN` halves it and tries again, down to
  :data:`MIN_STEP`;
* a **fold** is where the speed component t_Ω of the tangent changes sign between two points; it is
  then located by Illinois' regula falsi on t_Ω between them, each trial predicted on the chord
  between the bracket's ends and corrected normal to it, until the speeds of the bracket's ends
  agree to :data:`FOLD_RTOL`, and the fold's speed is the vertex of the parabola Ω(τ) through the
  last three points (τ along the chord);
* **stability** at every point from the orbit's monodromy matrix (its Floquet multipliers); a loss of
  stability without a fold (a flip, a Neimark–Sacker) is located the same way on ρ − 1.

The unknowns are scaled (deflections by the orbit's largest deflection, speeds of the state by its
largest speed, Ω by :data:`SPEED_SCALE` of the starting speed) so that the arclength weighs them
alike; the rigid-body angle of a free train (:attr:`.periodic.LinearPeriodic.idle`), on which nothing
depends, is left out. :func:`follow` is what :func:`.sweep.speed_sweep` calls where a branch ends
between two of its speeds; :class:`ContinuedBranch` is what it returns.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from mechdyn.gear_dynamics._nonsmooth import FlowError, NonsmoothFlow
from mechdyn.gear_dynamics._stability import UNSTABLE_MARGIN
from mechdyn.gear_dynamics.periodic import LinearPeriodic, PeriodPlan

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["ContinuedBranch", "follow"]

#: The relative width in speed to which a fold (or a loss of stability) is located along the arclength.
FOLD_RTOL = 1e-7
#: A fold within this fraction of the speed of one already located is that fold.
KNOWN_RTOL = 1e-5
#: The residual of the period map, relative to the orbit's largest deflection and speed, at which the
#: corrector has converged (the closure :mod:`.shooting` asks of an orbit is 1e-7).
CORRECTOR_TOL = 1e-8
#: The speed's unit in the arclength, a fraction of the starting speed: a unit step along a branch
#: whose orbit does not change moves the speed by this fraction.
SPEED_SCALE = 0.05
#: Largest, first and smallest arclength step (scaled units).
MAX_STEP, FIRST_STEP, MIN_STEP = 0.3, 0.05, 1e-5
#: The largest turn of the tangent from one point to the next, rad.
MAX_TURN = np.pi / 6
#: Continuation points (corrected orbits) before a branch is given up.
MAX_POINTS = 250
_MAX_ITER = 8
_DIVERGED = 1e3
"""A corrector step whose residual grows by this factor over the last is taken as diverging."""
_FOLD_CHORD = 0.01  # a fold's bracket shrunk to this fraction of the step that crossed it
_FD_RTOL = 1e-6  # the forward difference of F in Ω, relative to Ω


@dataclass(frozen=True, repr=False)
class ContinuedBranch:
    """A branch of periodic orbits followed by pseudo-arclength continuation.

    Attributes
    ----------
    speeds : ndarray
        (n,) reference speeds Ω of the points, in the order followed, rad/s.
    arclength : ndarray
        (n,) arclength s of each point from the first, scaled units (dimensionless).
    speed_tangent : ndarray
        (n,) the speed component t_Ω of the unit tangent at each point, in the sense followed
        (dimensionless): it changes sign at a fold.
    multipliers : ndarray
        (n, k) Floquet multipliers of each orbit, largest modulus first (without the rigid-body
        angle's), dimensionless, complex.
    states : ndarray
        (n, 2m) the orbit's state (x, ẋ) at the start of its period, rad and rad/s.
    force_max, force_min : ndarray
        (n, J) largest and smallest mesh force over the period, N (NaN where not computed).
    static_force : ndarray
        (n, J) mesh force of the mean load at mean stiffness, N (NaN where not computed).
    closure : ndarray
        (n,) the residual of the period map at each point, the largest mismatch of the deflections
        and of the speeds relative to their largest values, dimensionless.
    iterations : ndarray
        (n,) Newton iterations of the corrector, count.
    cpu_seconds : ndarray
        (n,) CPU time of each point (its corrector, its tangent, the failed tries before it), s.
    kinds : tuple of str
        Per point: ``"start"``, ``"point"``, ``"fold"`` (located), ``"loss of stability"`` (located)
        or ``"target"`` (the orbit at the speed the sweep asked for).
    folds : tuple of float
        The located folds' speeds, rad/s, in the order met.
    stability_losses : tuple of float
        The located losses of stability without a fold (a flip, a torus), rad/s.
    end : str
        Why the continuation stopped, in words.
    failed : bool
        True where the corrector failed before the first fold (or loss of stability, or the target)
        was reached: the sweep falls back to bisection.
    mesh_names : tuple of str
    samples : ndarray or None
        (n, 2m, N) each orbit sampled over its period (x, ẋ at N instants), rad and rad/s; dropped
        (None) once the sweep has taken what it needs.
    """

    speeds: np.ndarray
    arclength: np.ndarray
    speed_tangent: np.ndarray
    multipliers: np.ndarray
    states: np.ndarray
    force_max: np.ndarray
    force_min: np.ndarray
    static_force: np.ndarray
    closure: np.ndarray
    iterations: np.ndarray
    cpu_seconds: np.ndarray
    kinds: tuple[str, ...]
    folds: tuple[float, ...] = ()
    stability_losses: tuple[float, ...] = ()
    end: str = ""
    failed: bool = False
    mesh_names: tuple[str, ...] = field(default=())
    samples: np.ndarray | None = None

    @property
    def spectral_radius(self) -> np.ndarray:
        """(n,) largest Floquet multiplier modulus of each orbit, dimensionless."""
        return np.abs(self.multipliers[:, 0]) if self.multipliers.size else np.zeros(self.speeds.size)

    @property
    def stable(self) -> np.ndarray:
        """(n,) True where every Floquet multiplier lies inside the unit circle (ρ ≤ 1 + 1e-9)."""
        return ~(self.spectral_radius > 1.0 + UNSTABLE_MARGIN)

    @property
    def force_amplitude(self) -> np.ndarray:
        """(n, J) half peak-to-peak mesh force, N."""
        return 0.5 * (self.force_max - self.force_min)

    @property
    def dynamic_factor(self) -> np.ndarray:
        """(n, J) K_v = largest mesh force in the sense of the static one / static mesh force,
        dimensionless (NaN without load), as :attr:`.sweep_result.SpeedSweepResult.dynamic_factor`."""
        sense = np.sign(self.static_force)
        extreme = np.where(sense >= 0, self.force_max, -self.force_min)
        loaded = np.abs(self.static_force) > 1e-9 * np.maximum(np.abs(self.force_max), np.abs(self.force_min))
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(loaded, extreme / np.abs(self.static_force), np.nan)

    @property
    def fold_indices(self) -> np.ndarray:
        """Indices of the located folds among the points."""
        return np.array([i for i, k in enumerate(self.kinds) if k == "fold"], int)

    def leading_real_multiplier(self) -> np.ndarray:
        """(n,) each orbit's real Floquet multiplier of largest value (the one that crosses +1 at a
        fold), dimensionless; NaN where none is real."""
        out = np.full(self.speeds.size, np.nan)
        for i, mu in enumerate(self.multipliers):
            real = mu[np.abs(mu.imag) <= 1e-7 * np.maximum(np.abs(mu), 1e-300)].real
            if real.size:
                out[i] = float(real.max())
        return out

    def to_frame(self) -> pd.DataFrame:
        """One row per point: speed (rad/s), arclength, t_Ω, ρ, the real multiplier nearest +1's side,
        stable, per mesh the force extremes (N), Newton iterations and CPU time (s)."""
        import pandas as pd

        cols: dict[str, Any] = {
            "speed_rad_s": self.speeds,
            "arclength_ratio": self.arclength,
            "speed_tangent_ratio": self.speed_tangent,
            "spectral_radius_ratio": self.spectral_radius,
            "leading_real_multiplier_ratio": self.leading_real_multiplier(),
            "stable": self.stable,
            "fold": np.array([k == "fold" for k in self.kinds], bool),
        }
        for j, n in enumerate(self.mesh_names or tuple(f"mesh {j}" for j in range(self.force_max.shape[1]))):
            cols[f"{n}_force_max_N"] = self.force_max[:, j]
            cols[f"{n}_force_min_N"] = self.force_min[:, j]
        cols["newton_iterations"] = self.iterations
        cols["cpu_s"] = self.cpu_seconds
        return pd.DataFrame(cols)


class _Failed(RuntimeError):
    """The corrector did not converge."""


@dataclass
class _Point:
    z: np.ndarray  # scaled unknowns (y without the idle angle, Ω)
    y: np.ndarray  # the full state
    speed: float
    tangent: np.ndarray  # unit, scaled
    Phi: np.ndarray  # the monodromy (full state)
    F_speed: np.ndarray  # ∂F/∂Ω (kept rows, scaled)
    samples: np.ndarray  # (2m, N) the orbit sampled over its period
    iterations: int
    cpu: float
    closure: float = float("nan")
    s: float = 0.0
    kind: str = "point"
    mu: np.ndarray = field(default_factory=lambda: np.zeros(0, complex))


class _Curve:
    """The scaled period map of ``lin`` over (y, Ω) and the predictor–corrector on it."""

    def __init__(self, lin: LinearPeriodic, plan: PeriodPlan, speed: float, y0: np.ndarray, N: int) -> None:
        self.lin, self.plan, self.N = lin, plan, N
        m = lin.m
        d = 2 * m
        self.m, self.d = m, d
        self.keep = np.delete(np.arange(d), [] if lin.idle is None else [lin.idle])
        x_scale = max(float(np.abs(y0[:m]).max()), 1e-300)
        v_scale = max(float(np.abs(y0[m:]).max()), 1e-300)
        self.y_scale = np.concatenate([np.full(m, x_scale), np.full(m, v_scale)])[self.keep]
        self.speed_scale = SPEED_SCALE * speed
        self.base = np.asarray(y0, float).copy()  # the idle angle's value stays
        self.t_eval = np.arange(N) / N

    # -- the map -------------------------------------------------------------------------------------
    def state(self, z: np.ndarray) -> tuple[np.ndarray, float]:
        y = self.base.copy()
        y[self.keep] = z[:-1] * self.y_scale
        return y, float(z[-1] * self.speed_scale)

    def scaled(self, y: np.ndarray, speed: float) -> np.ndarray:
        return np.append(y[self.keep] / self.y_scale, speed / self.speed_scale)

    def flow(self, speed: float) -> NonsmoothFlow:
        return NonsmoothFlow(self.lin.at_speed(speed), self.plan, speed)

    def residual(
        self, z: np.ndarray, variational: bool = True
    ) -> tuple[np.ndarray, np.ndarray | None, np.ndarray | None, float]:
        """The scaled residual F (kept rows), the full monodromy, the sampled orbit and the residual's
        size as :mod:`.shooting` measures it (largest relative mismatch of deflections and speeds)."""
        y, speed = self.state(z)
        if not speed > 0:
            raise _Failed("the speed left the positive axis")
        try:
            samples, end, _ = self.flow(speed).run(y, self.t_eval if variational else None, 1, variational)
        except (FlowError, ValueError) as err:
            raise _Failed(str(err)) from None
        d = self.d
        r = end[:d] - y
        m = self.m
        scale = np.concatenate([np.full(m, np.abs(y[:m]).max()), np.full(m, np.abs(y[m:]).max())]) + 1e-300
        size = float(np.abs(r / scale).max())
        Phi = end[d:].reshape(d, d) if variational else None
        return r[self.keep] / self.y_scale, Phi, samples if variational else None, size

    def jacobian_y(self, Phi: np.ndarray) -> np.ndarray:
        """∂F/∂y of the kept rows and columns, scaled."""
        k = self.keep
        A = Phi[np.ix_(k, k)] - np.eye(k.size)
        return A * self.y_scale[None, :] / self.y_scale[:, None]

    def speed_column(self, z: np.ndarray, r: np.ndarray) -> np.ndarray:
        """∂F/∂Ω (scaled) by a forward difference of relative step :data:`_FD_RTOL`."""
        h = _FD_RTOL * z[-1]
        z2 = z.copy()
        z2[-1] += h
        return (self.residual(z2, variational=False)[0] - r) / h

    # -- predictor–corrector ---------------------------------------------------------------------------
    def tangent(self, Jy: np.ndarray, Fs: np.ndarray, sense: np.ndarray) -> np.ndarray:
        """The unit null vector of [F_y F_Ω] (its last right singular vector), in the sense of
        ``sense`` (t · sense > 0)."""
        t = np.linalg.svd(np.column_stack([Jy, Fs]))[2][-1]
        return -t if t @ sense < 0 else t

    def correct(
        self,
        z0: np.ndarray,
        direction: np.ndarray,
        F_speed: np.ndarray,
        sense: np.ndarray,
        fixed_speed: bool = False,
    ) -> _Point:
        """Newton from the predictor ``z0`` on the hyperplane through it normal to ``direction`` (or at
        the speed of z0, ``fixed_speed``), then the tangent there, in the sense of ``sense``."""
        start = time.process_time()
        z = z0.copy()
        n = z.size
        constraint = np.zeros(n) if fixed_speed else direction
        if fixed_speed:
            constraint[-1] = 1.0
        size_before = np.inf
        for it in range(_MAX_ITER + 1):
            r, found, sampled, size = self.residual(z)
            if not np.isfinite(size) or size > _DIVERGED * max(size_before, 1e-3):
                raise _Failed("the corrector diverged")
            assert found is not None and sampled is not None
            Phi, samples = found, sampled
            if size <= CORRECTOR_TOL:
                break
            if it == _MAX_ITER:
                raise _Failed(f"the corrector did not converge in {_MAX_ITER} iterations")
            if it > 0:  # ∂F/∂Ω afresh at each iterate (the one given is the last point's)
                F_speed = self.speed_column(z, r)
            A = np.vstack([np.column_stack([self.jacobian_y(Phi), F_speed]), constraint[None, :]])
            rhs = -np.append(r, constraint @ (z - z0))
            try:
                z = z + np.linalg.solve(A, rhs)
            except np.linalg.LinAlgError:
                raise _Failed("the bordered system is singular") from None
            size_before = size
        Fs = self.speed_column(z, r)
        t = self.tangent(self.jacobian_y(Phi), Fs, sense)
        y, speed = self.state(z)
        mu = _multipliers(self.lin, Phi)
        return _Point(z, y, speed, t, Phi, Fs, samples, it, time.process_time() - start, size, mu=mu)


def _multipliers(lin: LinearPeriodic, Phi: np.ndarray) -> np.ndarray:
    mu = np.linalg.eigvals(lin.deflate(Phi))
    return mu[np.argsort(-np.abs(mu), kind="stable")]


def _rho(p: _Point) -> float:
    return float(np.abs(p.mu[0])) if p.mu.size else 0.0


def follow(
    lin: LinearPeriodic,
    plan: PeriodPlan,
    speed: float,
    state: np.ndarray,
    *,
    toward: float,
    bounds: tuple[float, float],
    through: bool = True,
    samples: int = 256,
    known_folds: tuple[float, ...] = (),
    mesh_forces: Any = None,
    static_forces: Any = None,
) -> ContinuedBranch:
    """Follow the branch of periodic orbits through ``state`` at ``speed`` towards ``toward``.

    The continuation starts in the sense of ``toward`` and stops at the first of: the orbit at exactly
    ``toward`` (the branch reaches it, stable); a loss of stability without a fold (located); a fold
    (located), after which, with ``through``, it goes on along the unstable branch beyond it to the
    next fold (located) or until the speed leaves ``bounds``. A fold within :data:`KNOWN_RTOL` of one
    of ``known_folds`` (found by an earlier sweep that traced the branch beyond it) ends it there.

    Parameters
    ----------
    lin : LinearPeriodic
        The model (with backlash).
    plan : PeriodPlan
        Its period.
    speed : float
        Reference speed Ω of the starting orbit, rad/s.
    state : ndarray
        (2m,) the starting orbit's state (x, ẋ) at the start of its period, rad and rad/s (a converged
        orbit: Newton's at one speed).
    toward : float
        The speed the sweep wants next, rad/s.
    bounds : tuple of float
        The speeds (rad/s) outside which the branch beyond a fold is no longer followed.
    through : bool
        Follow the branch beyond the first fold to the next.
    samples : int
        Time samples of each orbit over its period (for its force extremes), count.
    known_folds : tuple of float
        Folds already located, rad/s.
    mesh_forces : callable, optional
        ``(speed, t_over_T, x, v) → (N, J) forces``: the mesh forces along an orbit (the sweep's
        :func:`.steady._mesh_forces`); without it the force extremes are NaN.
    static_forces : callable, optional
        ``speed → (J,) static mesh forces`` (N); without it they are NaN.

    Returns
    -------
    ContinuedBranch

    Notes
    -----
    Keller's pseudo-arclength method with a bordered Newton corrector (Seydel 2010, ch. 4); folds
    detected by the sign of the tangent's speed component, a test function, and located by regula
    falsi on the arclength (Seydel 2010, ch. 5), the fold's speed the vertex of a parabola through the
    last points. The multipliers come from the monodromy matrix with the saltation matrices of the contact
    changes, so that the non-smooth orbit's stability is exact up to the integration error (Leine &
    Nijmeijer, *Dynamics and Bifurcations of Non-Smooth Mechanical Systems*, Springer 2004, §7.2).
    """
    curve = _Curve(lin, plan, speed, np.asarray(state, float), samples)
    sense = 1.0 if toward >= speed else -1.0
    low, high = bounds
    points: list[_Point] = []
    folds: list[float] = []
    losses: list[float] = []

    def finish(end: str, failed: bool = False) -> ContinuedBranch:
        return _branch(lin, points, folds, losses, end, failed, mesh_forces, static_forces)

    # the start: the orbit given, corrected at its own speed, and its tangent in the sense of `toward`
    z_start = curve.scaled(np.asarray(state, float), speed)
    guess = np.zeros(z_start.size)
    guess[-1] = sense
    try:
        r, _, _, _ = curve.residual(z_start, variational=False)
        Fs0 = curve.speed_column(z_start, r)
        first = curve.correct(z_start, guess, Fs0, guess, fixed_speed=True)
    except _Failed as err:
        return finish(f"the starting orbit could not be corrected ({err})", failed=True)
    if first.tangent[-1] * sense < 0:
        first.tangent = -first.tangent
    first.kind = "start"
    points.append(first)
    if _rho(first) > 1.0 + UNSTABLE_MARGIN:
        return finish("the orbit it starts from is unstable", failed=True)
    step = FIRST_STEP
    after_fold = False
    while len(points) < MAX_POINTS:
        a = points[-1]
        try:
            b, step = _step(curve, a, step)
        except _Failed as err:
            if folds:
                return finish(f"the branch beyond the fold was followed until the corrector failed ({err})")
            return finish(f"the corrector failed at {a.speed:.6g} rad/s ({err})", failed=True)
        b.s = a.s + float(np.linalg.norm(b.z - a.z))
        turned = a.tangent[-1] * b.tangent[-1] < 0
        if turned:
            fold = _locate(curve, a, b, "fold")
            folds.append(fold.speed)
            points.append(fold)
            if not through or any(abs(fold.speed - k) <= KNOWN_RTOL * fold.speed for k in known_folds):
                return finish("at the fold")
            if after_fold:
                return finish("at the second fold")
            after_fold = True
            points.append(b)
            continue
        if not after_fold:
            if (b.speed - toward) * sense >= 0:  # past the speed asked for: the orbit there
                w = (toward - a.speed) / (b.speed - a.speed)
                z0 = a.z + w * (b.z - a.z)
                z0[-1] = toward / curve.speed_scale
                try:
                    at = curve.correct(z0, a.tangent, a.F_speed, a.tangent, fixed_speed=True)
                except _Failed as err:
                    return finish(f"the orbit at the speed asked for was not found ({err})", failed=True)
                at.s = a.s + float(np.linalg.norm(at.z - a.z))
                if at.tangent @ (at.z - a.z) < 0:
                    at.tangent = -at.tangent
                if _rho(at) <= 1.0 + UNSTABLE_MARGIN:
                    at.kind = "target"
                    points.append(at)
                    return finish("at the speed asked for")
                b = at
            if _rho(b) > 1.0 + UNSTABLE_MARGIN:  # stability lost without a fold: a flip, a torus
                loss = _locate(curve, a, b, "loss of stability")
                losses.append(loss.speed)
                points.append(loss)
                return finish("where the orbit loses its stability without a fold")
        points.append(b)
        if after_fold and not low <= b.speed <= high:
            return finish("where the branch beyond the fold leaves the swept range")
    return finish(f"after {MAX_POINTS} points", failed=not (folds or losses))


def _step(curve: _Curve, a: _Point, step: float) -> tuple[_Point, float]:
    """The next point from ``a`` with step-size control; the step to try after it. The point's CPU
    time includes the failed tries before it. A step is refused where the corrector fails, lands
    farther than 2Δs from its predictor, or the tangent turns by more than :data:`MAX_TURN` (so that
    the sense of the tangent, carried by the secant, is never lost), unless the step is already
    below 1e-3 (a corner of the non-smooth curve)."""
    spent = time.process_time()
    while step >= MIN_STEP:
        z0 = a.z + step * a.tangent
        try:
            b: _Point | None = curve.correct(z0, a.tangent, a.F_speed, a.tangent)
        except _Failed:
            b = None
        if b is not None:
            secant = b.z - a.z
            if b.tangent @ secant < 0:
                b.tangent = -b.tangent
            turn = float(np.clip(a.tangent @ b.tangent, -1.0, 1.0))
            if np.linalg.norm(b.z - z0) <= 2 * step and (turn >= np.cos(MAX_TURN) or step < 1e-3):
                b.cpu = time.process_time() - spent
                grow = 1.5 if b.iterations <= 3 and turn > np.cos(MAX_TURN / 2) else 1.0
                if b.iterations > 5:
                    grow = 0.5
                return b, min(MAX_STEP, step * grow)
        step *= 0.5
    raise _Failed(f"the step fell below {MIN_STEP}")


def _locate(curve: _Curve, a: _Point, b: _Point, what: str) -> _Point:
    """The fold (the sign change of t_Ω) or the loss of stability (ρ − 1) between ``a`` and ``b``.

    Illinois' regula falsi on the bracket: each trial predicted on the chord between the bracket's
    ends and corrected on the hyperplane normal to it, its tangent in the sense of the chord, until
    the speeds of the bracket's ends agree to :data:`FOLD_RTOL` (for a fold also the chord shrunk to
    a twentieth); a fold's speed is the vertex of the parabola Ω(τ) through the last three points, τ
    the position along the chord. A trial whose corrector fails ends the search with the bracket
    found so far."""
    spent = time.process_time()
    ref = 1.0 if a.tangent[-1] >= 0 else -1.0

    def g(p: _Point) -> float:
        return float(p.tangent[-1] * ref) if what == "fold" else _rho(p) - 1.0

    lo, hi = a, b
    glo, ghi = g(a), g(b)
    first_chord = float(np.linalg.norm(b.z - a.z))
    tried = [a, b]
    side = 0
    for _ in range(60):
        chord = hi.z - lo.z
        length = float(np.linalg.norm(chord))
        close = abs(lo.speed - hi.speed) <= FOLD_RTOL * abs(b.speed)
        if close and (what != "fold" or length <= _FOLD_CHORD * first_chord):
            break
        theta = glo / (glo - ghi) if ghi != glo else 0.5
        theta = float(np.clip(theta, 0.05, 0.95))
        try:
            p = curve.correct(lo.z + theta * chord, chord / length, lo.F_speed, chord)
        except _Failed:
            try:
                p = curve.correct(lo.z + 0.5 * chord, chord / length, lo.F_speed, chord)
            except _Failed:
                break
        tried.append(p)
        gp = g(p)
        if (gp > 0) == (glo > 0):
            lo, glo = p, gp
            if side == -1:
                ghi *= 0.5
            side = -1
        else:
            hi, ghi = p, gp
            if side == 1:
                glo *= 0.5
            side = 1
    best = lo if abs(g(lo)) <= abs(g(hi)) else hi
    speed = best.speed
    if what == "fold":  # the vertex of Ω over the position along the last chord
        chord = hi.z - lo.z
        direction = chord.copy()
        direction[-1] = 0.0
        norm = float(np.linalg.norm(direction))
        near = sorted(tried, key=lambda q: float(np.linalg.norm(q.z - 0.5 * (lo.z + hi.z))))[:3]
        if norm > 0 and len(near) == 3:
            tau = np.array([float((q.z - lo.z) @ direction) / norm for q in near])
            omega = np.array([q.speed for q in near])
            if np.unique(tau).size == 3:
                c = np.polyfit(tau - tau.mean(), omega, 2)
                if c[0] != 0:
                    vertex = -c[1] / (2 * c[0])
                    if abs(vertex) <= np.ptp(tau):
                        speed = float(np.polyval(c, vertex))
    return _Point(
        best.z,
        best.y,
        speed,
        best.tangent,
        best.Phi,
        best.F_speed,
        best.samples,
        best.iterations,
        time.process_time() - spent,
        best.closure,
        a.s + float(np.linalg.norm(best.z - a.z)),
        what,
        best.mu,
    )


def _branch(
    lin: LinearPeriodic,
    points: list[_Point],
    folds: list[float],
    losses: list[float],
    end: str,
    failed: bool,
    mesh_forces: Any,
    static_forces: Any,
) -> ContinuedBranch:
    J = len(lin.names)
    n = len(points)
    m = lin.m
    fmax = np.full((n, J), np.nan)
    fmin = np.full((n, J), np.nan)
    static = np.full((n, J), np.nan)
    for i, p in enumerate(points):
        if mesh_forces is not None:
            N = p.samples.shape[1]
            f = mesh_forces(p.speed, np.arange(N) / N, p.samples[:m].T, p.samples[m : 2 * m].T)
            fmax[i], fmin[i] = f.max(axis=0), f.min(axis=0)
        if static_forces is not None:
            static[i] = static_forces(p.speed)
    k = max((p.mu.size for p in points), default=0)
    mu = np.full((n, k), np.nan + 0j)
    for i, p in enumerate(points):
        mu[i, : p.mu.size] = p.mu
    return ContinuedBranch(
        speeds=np.array([p.speed for p in points]),
        arclength=np.array([p.s for p in points]),
        speed_tangent=np.array([p.tangent[-1] for p in points]),
        multipliers=mu,
        states=np.array([p.y for p in points]).reshape(n, 2 * m),
        force_max=fmax,
        force_min=fmin,
        static_force=static,
        closure=np.array([p.closure for p in points]),
        iterations=np.array([p.iterations for p in points], int),
        cpu_seconds=np.array([p.cpu for p in points]),
        kinds=tuple(p.kind for p in points),
        folds=tuple(folds),
        stability_losses=tuple(losses),
        end=end,
        failed=failed,
        mesh_names=lin.names,
        samples=np.array([p.samples for p in points]) if points else None,
    )
