"""Periodic loads on the machine: a force and a moment over one period, held as a Fourier series.

A load has six channels in machine coordinates (z up): the force (Fx, Fy, Fz), N, and the moment
about the machine origin (Mx, My, Mz), N·m. It is held as the coefficients of its real Fourier
series, f(t) = c₀ + 2 Re Σ_{h≥1} c_h exp(i h Ω t), Ω = 2π/T; from N equally spaced samples the
series is the trigonometric interpolant, which passes through every sample (the Nyquist term
halved so that it does). Both the frequency-domain steady state and the time integration of the
start-up see this same continuous force.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from mechdyn.checks import check_array, check_count, check_number
from mechdyn.errors import ModelError
from mechdyn.units import si_field

MAX_HARMONIC = 100_000
"""The highest harmonic order a load may have."""
MAX_TIME_STEPS = 20_000_000
"""The most times a load is evaluated at over one period (as a start-up's steps in all)."""

__all__ = ["CHANNELS", "PeriodicLoad", "Placement"]

CHANNELS = ("Fx", "Fy", "Fz", "Mx", "My", "Mz")


@dataclass(frozen=True)
class PeriodicLoad:
    """A periodic load on the machine.

    Attributes
    ----------
    period : float
        s, from 1e-7 to 1e7 s.
    coefficients : ndarray
        (H + 1, 6) complex Fourier coefficients c_h of (Fx, Fy, Fz, Mx, My, Mz about the origin),
        N and N·m, finite and at most 1e11 in magnitude.
    angle : ndarray or None
        (N,) crank angle of each sample, rad, when the load came from a mechanism (for plots); for
        rotors, the angle 2π t/T of their common fundamental (the shaft angle when they turn at one
        speed).
    n_samples : int or None
        N, when the load came from samples: results are given at the same instants by default.
    rotors : tuple of Rotor
        The unbalanced rotors the load came from (:meth:`from_unbalance`), else empty: a speed sweep
        (:func:`mechdyn.support.unbalance_sweep`) rebuilds the load at other speeds from them.

    Raises
    ------
    mechdyn.errors.ModelError
        When a number is not finite or out of range, naming the array and its first bad index.
    """

    period: float
    coefficients: np.ndarray
    angle: np.ndarray | None = None
    n_samples: int | None = None
    rotors: tuple[Any, ...] = ()

    def __post_init__(self) -> None:
        T = si_field("load", "period", self.period, "s", positive=True)
        object.__setattr__(self, "period", T)
        c = check_array("load", "coefficients", self.coefficients, "N", complex_values=True, what="forces")
        if c.ndim != 2 or c.shape[1] != 6 or c.shape[0] < 1 or c.shape[0] > MAX_HARMONIC + 1:
            raise ModelError(
                f"shape {c.shape} must be (harmonics + 1, 6), at most {MAX_HARMONIC} harmonics",
                element="load",
                field="coefficients",
            )
        object.__setattr__(self, "coefficients", c)
        if self.angle is not None:
            object.__setattr__(self, "angle", check_array("load", "angle", self.angle, "rad", what="angles"))
        if self.n_samples is not None:
            object.__setattr__(self, "n_samples", check_count("load", "n_samples", self.n_samples, low=2))
        object.__setattr__(self, "rotors", tuple(self.rotors))

    # -- constructors --------------------------------------------------------------------------
    @classmethod
    def from_samples(cls, period: Any, samples: Any, angle: Any = None) -> PeriodicLoad:
        """From N equally spaced samples over one period, starting at t = 0.

        Parameters
        ----------
        period : float or quantity
            s, from 1e-7 to 1e7 s.
        samples : array_like
            (N, 6) force N and moment about the origin N·m, or (N,) a vertical force Fz alone; finite,
            at most 1e11 N (N·m) in magnitude. A NaN is refused naming its index.
        angle : array_like, optional
            (N,) crank angle of each sample, rad.
        """
        f = check_array("load", "samples", samples, "N", what="forces")
        if f.ndim == 1:
            f = np.column_stack([np.zeros_like(f), np.zeros_like(f), f, *(np.zeros_like(f),) * 3])
        if f.ndim != 2 or f.shape[1] != 6 or f.shape[0] < 2:
            raise ModelError(
                f"shape {f.shape}: give (N, 6) samples of (Fx, Fy, Fz, Mx, My, Mz) or (N,) of Fz, N ≥ 2",
                element="load",
                field="samples",
            )
        n = f.shape[0]
        if n > MAX_HARMONIC * 2:
            raise ModelError(
                f"{n} samples: give at most {2 * MAX_HARMONIC} per period", element="load", field="samples"
            )
        if angle is not None:
            angle = check_array("load", "angle", angle, "rad", what="angles")
            if angle.shape != (n,):
                raise ModelError(
                    f"{angle.shape[0] if angle.ndim else 1} angles for {n} samples: give one per sample",
                    element="load",
                    field="angle",
                )
        c = np.fft.rfft(f, axis=0) / n
        if n % 2 == 0:
            c[-1] *= 0.5  # the Nyquist term appears once in the real series
        return cls(period, c, angle, n)

    @classmethod
    def from_times(
        cls, period: Any, time: Any, samples: Any, angle: Any = None, n: int | None = None
    ) -> PeriodicLoad:
        """From samples at arbitrary increasing times within one period (a periodic cubic spline
        resamples them onto ``n`` equal steps, by default as many as given).

        Parameters
        ----------
        period : float or quantity
            The load's period, s, from 1e-7 to 1e7 s.
        time : array_like
            Increasing sample times within one period, s, finite.
        samples : array_like
            (N, 6) load at those times (N and N·m), or (N,) Fz alone, N; finite, at most 1e11 in
            magnitude.
        angle : array_like, optional
            Crank angle of each sample, rad, for plots.
        n : int, optional
            Equal steps to resample onto.
        """
        from scipy.interpolate import CubicSpline

        T = si_field("load", "period", period, "s", positive=True)
        t = check_array("load", "time", time, "s", what="times")
        f = check_array("load", "samples", samples, "N", what="forces")
        if n is not None:
            n = check_count("load", "n", n, low=2, high=2 * MAX_HARMONIC, what="steps")
        if angle is not None:
            angle = check_array("load", "angle", angle, "rad", what="angles")
        if (
            t.ndim != 1
            or f.ndim == 0
            or t.size != f.shape[0]
            or t.size < 2
            or np.any(np.diff(t) <= 0)
            or t[-1] - t[0] >= T
        ):
            raise ModelError(
                "times must increase and span less than one period", element="load", field="time"
            )
        n = n or t.size
        spline = CubicSpline(np.append(t, t[0] + T), np.concatenate([f, f[:1]]), bc_type="periodic", axis=0)
        tn = t[0] + T * np.arange(n) / n
        out = spline(tn)
        a = None
        if angle is not None:
            a_spline = CubicSpline(np.append(t, t[0] + T), np.unwrap(np.append(angle, angle[0])), axis=0)
            a = np.mod(a_spline(tn), 2 * math.pi)
        return cls.from_samples(T, out, a)

    @classmethod
    def from_harmonics(cls, period: Any, harmonics: dict[int, Any], mean: Any = None) -> PeriodicLoad:
        """From harmonic amplitudes: f(t) = mean + Σ_h Re(A_h exp(i h Ω t)).

        Parameters
        ----------
        period : float or quantity
            The load's period, s.
        harmonics : dict of order h ≥ 1 → complex amplitude A_h
            A 6-vector (N, N·m) or a scalar for Fz alone; ``|A_h|`` is the amplitude, arg A_h the phase.
            Orders are whole numbers from 1 to 100 000; amplitudes finite, at most 1e11 in magnitude.
        mean : 6-vector or scalar, optional
            The mean load, N and N·m (a scalar: Fz alone).
        """
        for h in harmonics:
            check_count("load", "harmonics", h, low=1, high=MAX_HARMONIC, what="harmonic order")
        H = int(max(harmonics, default=0))
        c = np.zeros((H + 1, 6), dtype=complex)

        def vec(field: str, a: Any) -> np.ndarray:
            a = check_array("load", field, a, "N", complex_values=True, what="forces")
            if a.shape == (6,):
                return a
            if a.ndim != 0:
                raise ModelError(
                    f"shape {a.shape}: give a scalar Fz or six components (Fx, Fy, Fz, Mx, My, Mz)",
                    element="load",
                    field=field,
                )
            return np.array([0, 0, complex(a), 0, 0, 0])

        for h, a in harmonics.items():
            c[int(h)] = 0.5 * vec(f"harmonics[{h}]", a)
        if mean is not None:
            c[0] = vec("mean", mean)
        return cls(period, c)

    @classmethod
    def from_mechanism(
        cls, dynamics: Any, placement: Placement | None = None, period: Any = None
    ) -> PeriodicLoad:
        """The load a mechanism puts on the machine: its shaking force and moment (frame loads).

        The samples are placed in time by the kinematics' own times: at constant crank speed they
        are equally spaced and are the series' samples; otherwise (a speed profile, a driven
        mechanism) a periodic cubic spline in time resamples them onto equal time steps
        (:meth:`from_times`), so that the series is periodic in time with the fundamental 1/T.

        Parameters
        ----------
        dynamics : mechdyn.mechanism.DynamicsResult
            One revolution; the load starts (t = 0) at the mechanism's angle datum (the press:
            bottom dead centre). Process forces stay inside the machine (their reaction is on the
            bed). With gravity in the mechanism model its moving parts' weight is part of the mean
            load: then leave them out of the machine's rigid-body mass, or model the mechanism
            without gravity (the dynamic response is the same either way).
        placement : Placement, optional
            Where the mechanism's plane sits in the machine; by default
            :meth:`Placement.output_up`.
        period : float or quantity, optional
            Time of one revolution, s, from 1e-7 to 1e7 s; by default the driver's (2π over its
            speed, or the integral of dθ/θ̇ over its speed profile).
        """
        mech = dynamics.mechanism
        place = placement or Placement.output_up(mech)
        f2 = dynamics.shaking_force.copy()  # (N, 2) in the mechanism's plane
        m0 = dynamics.shaking_moment().copy()  # about the mechanism's origin
        if mech.process_forces:
            # the work pushes back on the bed where the tool meets it: inside the machine, so the
            # process force does not reach the floor (the linkage carries it to the frame)
            s = dynamics.output_position
            s = np.zeros(len(dynamics.angle)) if s is None else s
            for pf in mech.process_forces:
                fx, fy = pf.force(dynamics.angle, s)
                F = np.stack(np.broadcast_arrays(np.asarray(fx, float), np.asarray(fy, float)), axis=-1)
                pos = dynamics.kinematics.point(pf.body, pf.point)[0]
                f2 -= F
                m0 -= pos[:, 0] * F[:, 1] - pos[:, 1] * F[:, 0]
        F = f2[:, :1] * place.x_axis + f2[:, 1:] * place.y_axis
        M = m0[:, None] * np.cross(place.x_axis, place.y_axis) + np.cross(place.origin, F)
        samples = np.hstack([F, M])
        angle = dynamics.angle
        if period is None:
            period = abs(float(mech.driver.time(np.array([2 * math.pi]))[0]))
        else:
            period = si_field("load", "period", period, "s", positive=True)
        t = np.asarray(dynamics.kinematics.time, dtype=float)
        t = np.mod(t - t[np.argmin(angle)], period)
        order = np.argsort(t)
        if np.allclose(np.diff(t[order]), period / t.size, rtol=1e-9, atol=1e-12 * period):
            return cls.from_samples(period, samples[order], angle[order])
        return cls.from_times(period, t[order], samples[order], angle[order])

    @classmethod
    def from_drive(cls, result: Any, placement: Placement | None = None) -> PeriodicLoad:
        """The load of a mechanism driven by a motor, at its real, fluctuating speed.

        The shaking force and moment of the drive's periodic steady state
        (:func:`mechdyn.drive.drive_analysis`: the inverse dynamics at the solved θ̇(θ) and θ̈(θ),
        exact at equal steps of crank angle) over one period T of the drive. Those samples are not
        equally spaced in time when the speed fluctuates (the crank dwells where it is slow), so a
        periodic cubic spline in time resamples them onto as many equal time steps over T
        (:meth:`from_times`; de Boor, *A Practical Guide to Splines*, ch. V): the load's fundamental
        is 1/T and its harmonics are those of the force in time, not in crank angle. As in
        :meth:`from_mechanism`, t = 0 is the mechanism's angle datum and the process (forming) force
        stays inside the machine.

        Parameters
        ----------
        result : mechdyn.drive.DriveResult
            The drive's analysis (its ``loads`` at the real speed and its steady state's period, s).
        placement : Placement, optional
            Where the mechanism's plane sits in the machine; by default
            :meth:`Placement.output_up`.
        """
        return cls.from_mechanism(result.loads, placement, period=result.steady.period)

    @classmethod
    def from_unbalance(cls, rotors: Any) -> PeriodicLoad:
        """The rotating force and moment of one or several unbalanced rotors.

        Each rotor's force U Ω² turns in the plane normal to its axis, its moment about the machine
        origin is r × F (Rao, *Mechanical Vibrations*, §3.7); the rotors add. Their speeds must be
        whole multiples of a common fundamental Ω₀ (the same speed, a 2:1 gear): the load's period is
        2π/Ω₀ and each rotor's force its harmonic of order ``abs(Ω/Ω₀)``
        (:func:`mechdyn.support.unbalance.unbalance_coefficients`). Results are given at 16 steps a
        period of the highest order (at least 64), against the fundamental's angle.

        Parameters
        ----------
        rotors : Rotor or sequence of Rotor
            The rotors (:class:`mechdyn.support.Rotor`: unbalance kg·m, speed rad/s, axis, position m,
            phase rad), with distinct names.

        Raises
        ------
        mechdyn.errors.ModelError
            When two speeds are not in a whole-number ratio (naming both, and the fix).

        Examples
        --------
        >>> from mechdyn.support import PeriodicLoad, Rotor
        >>> load = PeriodicLoad.from_unbalance(Rotor("0.02 kg*m", "1500 rpm", "y"))
        >>> round(load.period, 6), round(float(abs(load.value(0.0)[2])), 1)  # s; N, up at t = 0
        (0.04, 493.5)
        """
        from mechdyn.support.unbalance import rotor_tuple, unbalance_coefficients

        rotors = rotor_tuple(rotors)
        period, c = unbalance_coefficients(rotors)
        n = max(16 * (c.shape[0] - 1), 64)
        return cls(period, c, 2 * math.pi * np.arange(n) / n, n, rotors)

    # -- evaluation ----------------------------------------------------------------------------
    @property
    def n_harmonics(self) -> int:
        return self.coefficients.shape[0] - 1

    @property
    def frequency(self) -> float:
        """Fundamental, Hz."""
        return 1.0 / self.period

    def orders(self) -> np.ndarray:
        """(H + 1,) harmonic orders 0..H."""
        return np.arange(self.coefficients.shape[0])

    @property
    def default_samples(self) -> int:
        """Time steps per period for results: the samples the load came from, else 16 per period of
        the highest harmonic (at least 64), so that a harmonic's peaks are not missed."""
        return self.n_samples or max(16 * self.n_harmonics, 64)

    def time(self, n: int | None = None) -> np.ndarray:
        """(n,) equally spaced times over one period from 0, s (by default :attr:`default_samples`).

        Parameters
        ----------
        n : int, optional
            How many, a whole number from 1 to 2e7.
        """
        n = (
            self.default_samples
            if n is None
            else check_count("load", "n", n, high=MAX_TIME_STEPS, what="times")
        )
        return self.period * np.arange(n) / n

    def value(self, t: Any) -> np.ndarray:
        """(…, 6) the load at times t, s.

        Parameters
        ----------
        t : float or ndarray
            Times, s, finite (at most 1e7 s in magnitude).
        """
        return series(self.coefficients, self.period, check_array("load", "t", t, "s", what="times"))

    def scaled(self, factor: float) -> PeriodicLoad:
        """The same load multiplied by ``factor``.

        Parameters
        ----------
        factor : float
            Dimensionless, finite (the scaled load must stay within its own bounds).
        """
        factor = check_number("load", "factor", factor, what="scale factor")
        # rotors scaled by a positive factor are the scaled load's rotors; by another, no rotors are
        rotors = tuple(r.scaled(factor) for r in self.rotors) if factor > 0 else ()
        return PeriodicLoad(self.period, self.coefficients * factor, self.angle, self.n_samples, rotors)


def series_on_grid(coefficients: np.ndarray, n: int) -> np.ndarray:
    """The series at t = k T / n, k = 0..n−1, by one inverse real FFT (n ≥ 2 H; shape (n, …)).

    With Y_h = n c_h (2 n c_h at the Nyquist bin, of which the FFT keeps the real part, as the
    series does: 2 Re(c e^{iπk}) = 2 Re(c) (−1)^k), ``irfft`` returns c₀ + 2 Re Σ c_h e^{2πi hk/n}.
    """
    H = coefficients.shape[0] - 1
    if n < 2 * H:
        raise ValueError(f"{n} steps cannot carry {H} harmonics; need at least {2 * H}")
    Y = np.zeros((n // 2 + 1, *coefficients.shape[1:]), dtype=complex)
    Y[: H + 1] = n * coefficients
    if n % 2 == 0 and H == n // 2:
        Y[H] *= 2.0
    return np.fft.irfft(Y, n, axis=0)


def _steps_of(t: np.ndarray, period: float) -> int | None:
    """Steps per period where ``t`` is 0, h, 2h, … with period / h a whole number (to round-off);
    else None."""
    if t.ndim != 1 or t.size < 64 or t[0] != 0.0:
        return None
    h = float(t[1])
    steps = round(period / h) if h > 0 else 0
    if steps < 2 or abs(steps * h - period) > 1e-12 * period:
        return None
    if np.abs(t - period * np.arange(t.size) / steps).max() > 1e-12 * max(float(t[-1]), period):
        return None
    return steps


def series(coefficients: np.ndarray, period: float, t: Any) -> np.ndarray:
    """c₀ + 2 Re Σ c_h exp(i h Ω t) for (H + 1, …) coefficients at times t: shape (t…, …)."""
    t = np.asarray(t, dtype=float)
    steps = _steps_of(t, period)
    if steps is not None and steps >= 2 * (coefficients.shape[0] - 1):
        # equal steps from 0, a whole number of them a period: one period by an inverse FFT, repeated
        return series_on_grid(coefficients, steps)[np.arange(t.size) % steps]
    h = np.arange(coefficients.shape[0])
    w = np.where(h == 0, 1.0, 2.0)
    phase = np.exp(1j * 2 * math.pi / period * np.multiply.outer(t, h))  # (t…, H+1)
    flat = coefficients.reshape(coefficients.shape[0], -1) * w[:, None]
    out = (phase @ flat).real
    return out.reshape(*t.shape, *coefficients.shape[1:])


@dataclass(frozen=True)
class Placement:
    """Where a planar mechanism sits in the machine.

    Parameters
    ----------
    origin : (x, y, z)
        The machine coordinates of the mechanism drawing's origin, m.
    x_axis, y_axis : (3,)
        The drawing's x and y directions in machine coordinates (unit, perpendicular).
    """

    origin: Any = (0.0, 0.0, 0.0)
    x_axis: Any = (1.0, 0.0, 0.0)
    y_axis: Any = (0.0, 0.0, 1.0)

    def __post_init__(self) -> None:
        o = np.array([si_field("placement", "origin", v, "m") for v in self.origin])
        ex, ey = np.asarray(self.x_axis, dtype=float), np.asarray(self.y_axis, dtype=float)
        if o.shape != (3,) or ex.shape != (3,) or ey.shape != (3,):
            raise ModelError("origin, x_axis and y_axis must have three components each", element="placement")
        for name, v in (("x_axis", ex), ("y_axis", ey)):
            if not math.isclose(np.linalg.norm(v), 1.0, rel_tol=1e-6):
                raise ModelError(f"{v.tolist()} must be a unit vector", element="placement", field=name)
        if abs(ex @ ey) > 1e-6:
            raise ModelError("x_axis and y_axis must be perpendicular", element="placement", field="y_axis")
        object.__setattr__(self, "origin", o)
        object.__setattr__(self, "x_axis", ex)
        object.__setattr__(self, "y_axis", ey)

    @classmethod
    def output_up(cls, mechanism: Any, origin: Any = (0.0, 0.0, 0.0)) -> Placement:
        """The drawing in the machine's x–z plane with the mechanism's output axis pointing up (+z).

        Without a prismatic output the drawing's y axis points up.

        Parameters
        ----------
        mechanism : mechdyn.mechanism.Mechanism
            The mechanism.
        origin : sequence of float
            Where its drawing's origin sits in the machine, m.
        """
        j = mechanism.output_joint()
        a = j.axis if j is not None else math.pi / 2
        c, s = math.cos(a), math.sin(a)
        # drawing vector v: its part along the output axis u goes to +z, along u turned +90° to −x
        return cls(origin, (s, 0.0, c), (-c, 0.0, s))
