"""Response of a machine on its mounts to a periodic load: steady state and start-up.

Steady state, exactly, in the frequency domain: for each harmonic h of the load (Ω = 2π/T),
(K − h²Ω² M + i hΩ C) X_h = B c_h, and the response is the Fourier series of the X_h (e.g. Rao,
*Mechanical Vibrations*, §4.2 "Response under a general periodic force"); no integrating until
transients die. Start-up from rest, by time integration: Duhamel's convolution in state-space form
(:func:`scipy.signal.lsim`, exact for a force that is linear between time steps) or any
:func:`scipy.integrate.solve_ivp` method. Both converge onto the steady state; the tests check it.

The force a mount passes to the floor is K_m u + C_m u̇ with u the body's displacement there (z up:
positive is the floor being pulled up); the machine's equation is M q̈ = B f − Σ Tᵀ(K_m u + C_m u̇),
so the mount forces sum to the applied force minus m a_G at every instant.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from mechdyn.checks import check_array, check_count, check_number
from mechdyn.errors import ModelError
from mechdyn.results import Result
from mechdyn.support.excitation import PeriodicLoad, series, series_on_grid
from mechdyn.support.model import DOFS, MountedMachine
from mechdyn.support.modes import modes

MAX_STEPS = 2e7  # time steps a start-up integration may take (and a steady state may be given at)
MAX_EVALUATIONS = 2_000_000
"""Evaluations of the equations of motion a ``solve_ivp`` start-up may take (a minute or so): past
it the integration stops with an error instead of running on (a stiff model, e.g. a huge damping,
under an explicit method)."""
# solve_ivp's methods; for the explicit ones, the stability interval on the negative real axis
# (|h λ| at which a decaying mode goes unstable: Hairer & Wanner, Solving ODEs II, §IV.2) and the
# evaluations per step
METHODS = ("exact", "duhamel", "RK23", "RK45", "DOP853", "Radau", "BDF", "LSODA")
_EXPLICIT = {"RK23": (2.5, 3), "RK45": (3.3, 6), "DOP853": (6.0, 12)}

__all__ = ["SupportResponse", "harmonic_response", "periodic_response", "startup_response"]


def extremes(y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Least and largest values of periodic signals over one period, located between the samples.

    The steady state is a Fourier series sampled at equal steps; its extremes lie between samples
    (64 samples a period read a harmonic's peak up to 0.12 % low). They are located as the
    mechanism's extremes are: the quartic through the extreme sample and two neighbours on each
    side, its stationary point (:func:`mechdyn.mechanism.extrema.peak`, error O(h⁴) in the step).

    Parameters
    ----------
    y : ndarray
        (..., N) equally spaced samples over one period (the last axis).

    Returns
    -------
    (ndarray, ndarray)
        (...) the least and the largest value.
    """
    from mechdyn.mechanism.extrema import peak

    y = np.asarray(y, dtype=float)
    if y.shape[-1] < 5:  # too few samples for the quartic: the samples themselves
        return y.min(axis=-1), y.max(axis=-1)
    return peak(y, -1.0)[1], peak(y, 1.0)[1]


@dataclass(frozen=True, repr=False)  # the short repr of Result
class SupportResponse(Result):
    """Motion of the machine and the forces through its mounts, over time.

    Attributes
    ----------
    machine : MountedMachine
    load : PeriodicLoad
    time : ndarray
        (N,) s.
    displacement, velocity, acceleration : ndarray
        (N, n) in the machine's kept coordinates (m and rad, and their rates).
    kind : str
        ``"steady state"`` or ``"start-up"``.
    method : str
        How a start-up was computed (:func:`startup_response`'s ``method``, or what ran instead);
        empty for a steady state.
    """

    machine: MountedMachine
    load: PeriodicLoad
    time: np.ndarray
    displacement: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    kind: str = "steady state"
    method: str = ""

    @cached_property
    def applied(self) -> np.ndarray:
        """(N, 6) the load (Fx, Fy, Fz, Mx, My, Mz about the origin) at each time."""
        return series(self.load.coefficients, self.load.period, self.time)  # times already checked

    @property
    def exciting_force(self) -> np.ndarray:
        """(N,) vertical force the load puts on the machine, N (positive up)."""
        return self.applied[:, 2]

    @cached_property
    def mount_forces(self) -> np.ndarray:
        """(N, mounts, 3) force each mount passes to the floor, machine axes, N (dynamic part)."""
        m = self.machine
        out = np.empty((self.time.size, len(m.mounts), 3))
        for i, mount in enumerate(m.mounts):
            T = m.mount_transform(mount)
            u, v = self.displacement @ T.T, self.velocity @ T.T
            out[:, i] = u @ mount.stiffness_matrix.T + v @ mount.damping_matrix.T
        return out

    @property
    def floor_force(self) -> np.ndarray:
        """(N, 3) total force on the floor, N."""
        return self.mount_forces.sum(axis=1)

    @property
    def transmitted_force(self) -> np.ndarray:
        """(N,) vertical force on the floor, N (F_T = k z + c ż for one degree of freedom)."""
        return self.floor_force[:, 2]

    def coordinate(self, name: str) -> np.ndarray:
        """(N,) one of the kept coordinates (``"z"``, ``"ry"``, …), zero when it is not kept.

        Parameters
        ----------
        name : str
            ``x``, ``y``, ``z`` (m) or ``rx``, ``ry``, ``rz`` (rad).
        """
        if name not in DOFS:
            raise KeyError(name)
        d = self.machine.dofs
        return self.displacement[:, d.index(name)] if name in d else np.zeros(self.time.size)

    @property
    def vertical_displacement(self) -> np.ndarray:
        """(N,) z of the centre of mass, m (the bed displacement of the one-DOF model)."""
        return self.coordinate("z")

    def displacement_at(self, point: Any) -> np.ndarray:
        """(N, 3) displacement of a point of the machine (machine coordinates, m).

        Parameters
        ----------
        point : sequence of float
            The point, m, in machine coordinates.
        """
        from mechdyn.support.model import Mount

        probe = Mount("probe", point, (0.0, 0.0, 0.0))
        return self.displacement @ self.machine.mount_transform(probe).T

    @property
    def force_balance_residual(self) -> np.ndarray:
        """(N, 3) Σ mount forces − (F − m a_G) for the kept translations (zero elsewhere), N."""
        m = self.machine
        res = np.zeros((self.time.size, 3))
        for k, d in enumerate(("x", "y", "z")):
            if d in m.dofs:
                a = self.acceleration[:, m.dofs.index(d)]
                res[:, k] = self.floor_force[:, k] - (self.applied[:, k] - m.body.mass * a)
        return res

    def summary(self) -> dict[str, Any]:
        """Extremes and ranges of the exciting and transmitted forces and of the bed displacement
        (SI), each located between the samples of the period (:func:`extremes`)."""
        F, FT, z = self.exciting_force, self.transmitted_force, self.vertical_displacement
        # a steady state on equal steps over one period: its extremes lie between the samples;
        # anything else (a start-up, given times): the samples' own
        n, scale = self.time.size, self.load.period
        one_period = self.kind == "steady state" and np.allclose(
            self.time, scale * np.arange(n) / n, rtol=0.0, atol=1e-9 * scale
        )
        ends = extremes if one_period else (lambda y: (np.min(y, axis=-1), np.max(y, axis=-1)))
        (f_lo, f_hi), (t_lo, t_hi), (z_lo, z_hi) = (ends(y) for y in (F, FT, z))
        floor = ends(self.floor_force.T)
        peaks = ends(np.linalg.norm(self.mount_forces, axis=2).T)[1]
        out: dict[str, Any] = {
            "inertia_force_max_N": float(f_hi),
            "inertia_force_min_N": float(f_lo),
            "inertia_force_range_N": float(f_hi - f_lo),
            "transmitted_force_max_N": float(t_hi),
            "transmitted_force_min_N": float(t_lo),
            "transmitted_force_range_N": float(t_hi - t_lo),
            "transmitted_to_inertia_force_range": (
                float((t_hi - t_lo) / (f_hi - f_lo)) if f_hi > f_lo else None
            ),
            "displacement_max_m": float(z_hi),
            "displacement_min_m": float(z_lo),
            "floor_force_range_N": [float(v) for v in floor[1] - floor[0]],
            "mount_force_peak_N": {mt.name: float(peaks[i]) for i, mt in enumerate(self.machine.mounts)},
        }
        return out

    def plots(self, **display_units: str) -> dict[str, Any]:
        """The exciting and transmitted forces over time, F_T against F, and (mounts) each mount's force."""
        from mechdyn.support import plots as sp

        fu = display_units.get("force_unit")
        out = {
            "forces.png": lambda: sp.plot_forces(self, force_unit=fu),
            "transmitted_vs_exciting.png": lambda: sp.plot_transmitted_vs_exciting(self, force_unit=fu),
        }
        if len(self.machine.mounts) > 1:
            out["mount_forces.png"] = lambda: sp.plot_mount_forces(self, force_unit=fu)
        return out

    def to_frame(self):
        """The response as a pandas DataFrame, one row per time step, columns named with units."""
        import pandas as pd

        cols: dict[str, np.ndarray] = {"time_s": self.time}
        if (
            self.load.angle is not None
            and self.kind == "steady state"
            and self.time.size == self.load.angle.size
        ):
            cols["crank_angle_deg"] = np.degrees(self.load.angle)
        for k, d in enumerate(self.machine.dofs):
            unit = "m" if d in ("x", "y", "z") else "rad"
            cols[f"{d}_{unit}"] = self.displacement[:, k]
        cols["exciting_force_z_N"] = self.exciting_force
        for k, axis in enumerate("xyz"):
            cols[f"floor_force_{axis}_N"] = self.floor_force[:, k]
        for i, mt in enumerate(self.machine.mounts):
            for k, axis in enumerate("xyz"):
                cols[f"mount_{mt.name}_force_{axis}_N"] = self.mount_forces[:, i, k]
        return pd.DataFrame(cols)


def harmonic_response(machine: MountedMachine, load: PeriodicLoad) -> np.ndarray:
    """(H + 1, n) complex response coefficients X_h of the kept coordinates, per harmonic.

    (K − (hΩ)² M + i hΩ C) X_h = B c_h, one small complex solve per harmonic
    (:func:`mechdyn.vibration.harmonic_solve`).

    Parameters
    ----------
    machine : MountedMachine
        The machine on its mounts.
    load : PeriodicLoad
        The periodic load.
    """
    from mechdyn.vibration.harmonic import harmonic_solve

    omega = 2 * math.pi / load.period * load.orders()
    Q = load.coefficients @ machine.load_matrix().T  # (H + 1, n)
    m = machine
    return harmonic_solve(m.stiffness_matrix, m.damping_matrix, m.mass_matrix, Q, omega)


def periodic_response(
    machine: MountedMachine, load: PeriodicLoad, n_samples: int | None = None, time: Any = None
) -> SupportResponse:
    """Steady-state response to a periodic load, in the frequency domain.

    Parameters
    ----------
    machine : MountedMachine
    load : PeriodicLoad
    n_samples : int, optional
        Time steps over one period from t = 0 (default: the load's own samples, else 16 per
        period of its highest harmonic); a whole number from 2 to 2e7.
    time : array_like, optional
        Evaluate at these times instead, s (the series holds for any t); finite, at most 1e7 s in
        magnitude.

    Returns
    -------
    SupportResponse
    """
    if n_samples is not None:
        n_samples = check_count(
            "steady state", "n_samples", n_samples, low=2, high=int(MAX_STEPS), what="steps"
        )
    if time is not None:
        time = check_array("steady state", "time", time, "s", what="times")
    X = harmonic_response(machine, load)
    w = 2 * math.pi / load.period * load.orders()[:, None]
    n = n_samples or load.default_samples
    if time is None and n >= 2 * load.n_harmonics:  # equal steps over one period: inverse FFTs
        t = load.time(n)
        q, qd, qdd = (series_on_grid(c, n) for c in (X, 1j * w * X, -(w**2) * X))
    else:
        t = load.time(n) if time is None else time
        q, qd, qdd = (series(c, load.period, t) for c in (X, 1j * w * X, -(w**2) * X))
    return SupportResponse(machine, load, t, q, qd, qdd, "steady state")


def _check_explicit(A: np.ndarray, method: str, duration: float) -> None:
    """Refuse an explicit method on a model it cannot integrate in :data:`MAX_EVALUATIONS`.

    An explicit Runge–Kutta step h is stable only while h |λ| stays within the method's stability
    interval for every eigenvalue λ of the state matrix; a heavily damped mode (λ ≈ −c/m) then forces
    steps far below the load's period, whatever the tolerance.
    """
    if method not in _EXPLICIT:
        return
    reach, per_step = _EXPLICIT[method]
    rate = float(np.abs(np.linalg.eigvals(A)).max(initial=0.0))
    evaluations = rate * duration / reach * per_step
    if evaluations > MAX_EVALUATIONS:
        raise ModelError(
            f"the model is too stiff for the explicit method {method}: its fastest mode decays or turns "
            f"at {rate:.4g} 1/s, which over {duration:.4g} s needs about {evaluations:.2g} evaluations "
            f"(more than {MAX_EVALUATIONS:.0e}); use method='duhamel' or 'Radau', or check the mounts' "
            "damping and stiffness against the mass",
            element="start-up",
            field="method",
        )


def _state_space(machine: MountedMachine) -> tuple[np.ndarray, np.ndarray]:
    M, K, C = machine.mass_matrix, machine.stiffness_matrix, machine.damping_matrix
    n = M.shape[0]
    Minv = np.linalg.inv(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-Minv @ K, -Minv @ C]])
    Bs = np.vstack([np.zeros((n, n)), Minv])
    return A, Bs


def startup_response(
    machine: MountedMachine,
    load: PeriodicLoad,
    cycles: int = 5,
    method: str = "exact",
    steps_per_period: int | None = None,
    rtol: float = 1e-9,
) -> SupportResponse:
    """Response from rest, the load switched on at t = 0: exact, or by time integration.

    Parameters
    ----------
    machine : MountedMachine
    load : PeriodicLoad
    cycles : int
        Periods to integrate, a whole number from 1 (at most 2e7 steps in all).
    method : str
        ``"exact"`` (the default): the periodic steady state plus the free vibration that starts the
        machine from rest, y(t) = y_p(t) − e^{At} y_p(0) in state form (the solution of a linear
        system with constant coefficients; e^{Ah} by :func:`scipy.linalg.expm`, applied step by
        step), to round-off at any step; an undamped machine with a load harmonic on one of its
        natural frequencies has no periodic solution and is integrated by ``"DOP853"`` instead (the
        result's ``method`` says so). ``"duhamel"``: the convolution integral in state-space form,
        exact for a load linear between steps (:func:`scipy.signal.lsim`); or a
        :func:`scipy.integrate.solve_ivp` method (``"RK23"``, ``"RK45"``, ``"DOP853"``, ``"Radau"``,
        ``"BDF"``, ``"LSODA"``). The explicit
        ones (RK…, DOP853) are refused for a model so stiff (a huge damping) that they would need
        more than :data:`MAX_EVALUATIONS` evaluations; any ``solve_ivp`` method stops with an error
        past that many, so that the integration always ends.
    steps_per_period : int, optional
        Output (and, for ``"duhamel"``, integration) steps per period; by default 40 steps per
        period of the highest natural frequency and of the highest load harmonic above 1e-6 of
        the largest (``"duhamel"``
        then errs by about (2π/40)²/8 ≈ 3e-3 of the response, from the load's linear
        interpolation; the adaptive methods meet ``rtol`` whatever the output steps).
    rtol : float
        Relative tolerance of ``solve_ivp`` (its absolute tolerance scales with the static
        response), dimensionless, from 1e-13 to 0.1.

    Returns
    -------
    SupportResponse
        All ``cycles`` periods, ``kind = "start-up"``.

    Raises
    ------
    mechdyn.errors.ModelError
        For arguments out of range, for more than 2e7 steps, for an explicit method on a model too
        stiff for it, and for an integration that fails or passes :data:`MAX_EVALUATIONS`.
    """
    cycles = check_count("start-up", "cycles", cycles, low=1, high=int(MAX_STEPS), what="periods")
    if method not in METHODS:
        raise ModelError(
            f"{method!r} must be one of {', '.join(map(repr, METHODS))}", element="start-up", field="method"
        )
    if steps_per_period is not None:
        steps_per_period = check_count(
            "start-up", "steps_per_period", steps_per_period, low=2, high=int(MAX_STEPS), what="steps"
        )
    rtol = check_number("start-up", "rtol", rtol, low=1e-13, high=0.1, what="relative tolerance")
    M, K, C = machine.mass_matrix, machine.stiffness_matrix, machine.damping_matrix
    n = M.shape[0]
    f_max = float(modes(machine).frequencies_hz.max())
    if steps_per_period is None:
        c = np.abs(load.coefficients).max(axis=1)
        h_top = int(np.nonzero(c >= 1e-6 * c.max())[0].max()) if c.max() > 0 else 1
        steps_per_period = int(max(40 * f_max * load.period, 40 * h_top, 64))
    if cycles * steps_per_period > MAX_STEPS:
        raise ModelError(
            f"{cycles} periods of {steps_per_period} steps each (the highest natural frequency, "
            f"{f_max:.4g} Hz, is {f_max * load.period:.3g} times the load's frequency) are more than "
            f"{MAX_STEPS:.0e} steps; check the stiffness and the mass, or integrate fewer cycles",
            element="start-up",
            field="cycles",
        )
    t = load.period * np.arange(cycles * steps_per_period + 1) / steps_per_period
    B = machine.load_matrix()
    A, Bs = _state_space(machine)
    asked = method
    x = _exact_startup(machine, load, A, t) if method == "exact" else None
    if method == "exact" and x is None:
        method = "DOP853"
    if x is not None:
        pass
    elif method == "duhamel":
        from scipy.signal import StateSpace, lsim

        Q = series(load.coefficients, load.period, t) @ B.T
        sys = StateSpace(A, Bs, np.eye(2 * n), np.zeros((2 * n, n)))
        _, _, x = lsim(sys, Q, t, interp=True)
        x = np.asarray(x).reshape(t.size, 2 * n)
    else:
        from scipy.integrate import solve_ivp

        _check_explicit(A, method, float(t[-1]))
        scale = (
            np.abs(np.linalg.solve(K, load.coefficients[0] @ B.T)).max()
            + np.abs(np.linalg.solve(K, np.abs(load.coefficients[1:] @ B.T).sum(axis=0) * 2)).max()
        )

        evaluations = 0

        def rhs(time: float, y: np.ndarray) -> np.ndarray:
            nonlocal evaluations
            evaluations += 1
            if evaluations > MAX_EVALUATIONS:
                raise ModelError(
                    f"the time integration ({method}) took {MAX_EVALUATIONS:.0e} evaluations and reached "
                    f"t = {time:.4g} s of {t[-1]:.4g} s: the model is too stiff for it (check the mounts' "
                    "damping and stiffness against the mass); use method='duhamel' or 'Radau', or "
                    "integrate fewer cycles",
                    element="start-up",
                    field="method",
                )
            return A @ y + Bs @ (B @ series(load.coefficients, load.period, time))

        sol = solve_ivp(
            rhs,
            (0.0, t[-1]),
            np.zeros(2 * n),
            method=method,
            t_eval=t,
            rtol=rtol,
            atol=rtol * max(scale, 1e-300),
        )
        if not sol.success:
            raise ModelError(f"time integration failed: {sol.message}", element="start-up", field="method")
        x = sol.y.T
    q, qd = x[:, :n], x[:, n:]
    qdd = (series(load.coefficients, load.period, t) @ B.T - qd @ C.T - q @ K.T) @ np.linalg.inv(M).T
    ran = method if method == asked else f"{method} (no periodic solution for '{asked}': undamped resonance)"
    return SupportResponse(machine, load, t, q, qd, qdd, "start-up", ran)


def _exact_startup(
    machine: MountedMachine, load: PeriodicLoad, A: np.ndarray, t: np.ndarray
) -> np.ndarray | None:
    """(t, 2n) state from rest, y_p(t) − e^{At} y_p(0) on equal steps, or None where the periodic
    solution does not exist (a load harmonic on an undamped natural frequency)."""
    from scipy.linalg import expm

    w = 2 * math.pi / load.period * load.orders()[:, None]
    with np.errstate(all="ignore"):
        try:
            X = harmonic_response(machine, load)
        except (np.linalg.LinAlgError, ModelError):
            return None
    if not np.all(np.isfinite(X)):
        return None
    yp = np.hstack([series(X, load.period, t), series(1j * w * X, load.period, t)])
    free = np.empty_like(yp)
    v = -yp[0]
    E = expm(A * (t[1] - t[0])) if t.size > 1 else np.eye(A.shape[0])
    for k in range(t.size):  # e^{A t_k} v, one step at a time (2n ≤ 12)
        free[k] = v
        v = E @ v
    out = yp + free
    out[0] = 0.0  # at rest, exactly
    return out
