"""The process forces between the kinematics' samples: their demand on the crank at any crank angle,
its exact largest value, and the work per stroke.

A tabulated forming force is linear between its rows, and it starts, rises, holds and breaks off
between two crank-angle samples; read only at the samples, its peak against the press's capacity is
missed (by 0.7 % on press A at 720 angles) and its work per stroke converges unsteadily with the
number of angles. Here every point a process force acts on follows a cubic Hermite curve in the crank
angle turned, through its sampled positions with their exact slopes dp/dφ = v/|θ̇| (the kinematics'
own velocities), and so does the output slide's position; each sample interval is cut where a force
has a kink (a table's rows, a forming force's start and full load) and integrated there by
Gauss–Legendre quadrature. For a force given against the slide's position along its axis the work is
then exact to round-off (∫ F ds depends only on the end positions, which are samples), for one given
against the crank angle it converges as h⁴. The demand's largest value is found on the intervals where
the samples put it, by bounded scalar search between the kinks (Brent's method).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

__all__ = ["ProcessPath", "process_path"]

GAUSS_POINTS = 6
"""Gauss–Legendre points on each piece between kinks: exact for the degree-5 integrand of a force
linear in the position along a cubic path."""

_NEAR = 0.9
"""Smooth pieces of the cycle (between samples and kinks) whose end values reach this fraction of the
largest end value are searched inside for the peak. A smooth piece of one sample step rising more
than 11 % above both its ends is beyond what the cubic interpolation of the samples represents."""


def _hermite(u: np.ndarray, p0: np.ndarray, p1: np.ndarray, m0: np.ndarray, m1: np.ndarray) -> tuple:
    """Cubic Hermite value and derivative in u ∈ [0, 1] (p, m with trailing shape of the points)."""
    u = u[..., None] if p0.ndim > u.ndim else u
    u2, u3 = u * u, u * u * u
    value = (2 * u3 - 3 * u2 + 1) * p0 + (u3 - 2 * u2 + u) * m0 + (-2 * u3 + 3 * u2) * p1 + (u3 - u2) * m1
    slope = (6 * u2 - 6 * u) * p0 + (3 * u2 - 4 * u + 1) * m0 + (-6 * u2 + 6 * u) * p1 + (3 * u2 - 2 * u) * m1
    return value, slope


@dataclass(frozen=True)
class _Acting:
    """One process force and the sampled path of its point: positions (N, 2), m, and dp/dφ (N, 2),
    m/rad, φ the crank angle turned."""

    force: Any
    position: np.ndarray
    rate: np.ndarray


@dataclass(frozen=True)
class ProcessPath:
    """The process forces' demand on the crank, T_p = −Σ F · dp/dφ (N·m in the sense the crank turns;
    positive where they resist), at any crank angle of the cycle.

    Attributes
    ----------
    angle : ndarray
        (N,) crank angle from the datum of each sample, rad, in the order the crank turns.
    sense : float
        +1 when the crank angle grows as it turns, −1 otherwise, dimensionless.
    step : float
        h, crank angle between samples, rad.
    slide : tuple of ndarray or None
        The output slide's position along its axis (N,), m, and ds/dφ (N,), m/rad.
    acting : tuple
        Each process force with its point's path.
    axis : float
        The slide's axis (up), rad from +x.
    """

    angle: np.ndarray
    sense: float
    step: float
    slide: tuple[np.ndarray, np.ndarray] | None
    acting: tuple[_Acting, ...]
    axis: float = math.pi / 2

    @property
    def size(self) -> int:
        return int(self.angle.size)

    @cached_property
    def _cuts(self) -> dict[int, list[float]]:
        """Where in each sample interval (u ∈ (0, 1)) a force has a kink: a table's rows against the
        crank angle or the slide's position, a forming force's start, full load and end; intervals
        without one are left out."""
        h = self.step
        cuts: dict[int, set[float]] = {}
        for a in self.acting:
            for versus, rows in _breaks(a.force):
                for x in rows:
                    if versus == "angle":
                        u = np.mod((x - self.angle) * self.sense, 2 * math.pi) / h
                        for i in np.nonzero((u > 0.0) & (u < 1.0))[0]:
                            cuts.setdefault(int(i), set()).add(float(u[i]))
                    elif versus == "position" and self.slide is not None:
                        s, ds = self.slide
                        s1, ds1 = np.roll(s, -1), np.roll(ds, -1)
                        reach = 0.5 * h * (np.abs(ds) + np.abs(ds1))  # a cubic's overshoot bound
                        near = (np.minimum(s, s1) - reach <= x) & (x <= np.maximum(s, s1) + reach)
                        for i in np.nonzero(near)[0]:
                            c = _cubic(s[i], s1[i], h * ds[i], h * ds1[i])
                            c[-1] -= x
                            for r in np.roots(c):
                                if abs(r.imag) < 1e-12 and 0.0 < r.real < 1.0:
                                    cuts.setdefault(int(i), set()).add(float(r.real))
        return {i: sorted(v) for i, v in cuts.items()}

    def _kinks(self, i: int) -> list[float]:
        """The kinks in sample interval i, u ∈ (0, 1), in order."""
        return self._cuts.get(i, [])

    def torque(self, i: Any, u: Any) -> np.ndarray:
        """T_p at fraction ``u`` ∈ [0, 1] of sample interval ``i`` (arrays broadcast), N·m."""
        i = np.asarray(i, dtype=int)
        u = np.asarray(u, dtype=float)
        n, h = self.size, self.step
        j = (i + 1) % n
        lo = float(self.angle.min())  # the datum's range of angles, [lo, lo + 2π)
        theta = lo + np.mod(self.angle[i] + self.sense * u * h - lo, 2 * math.pi)
        theta = np.where(u == 0.0, self.angle[i], theta)  # a sample's own angle, to the bit
        if self.slide is not None:
            s, ds = self.slide
            position = _hermite(u, s[i], s[j], h * ds[i], h * ds[j])[0]
        else:
            position = np.zeros_like(u)
        T = np.zeros(np.broadcast(i, u).shape)
        for a in self.acting:
            p, m = a.position, a.rate
            _, dp = _hermite(u, p[i], p[j], h * m[i], h * m[j])
            fx, fy = a.force(theta, position)
            T -= (np.asarray(fx) * dp[..., 0] + np.asarray(fy) * dp[..., 1]) / h
        return T

    def pieces(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Every sample interval cut at its kinks: (interval, u from, u to) of each piece."""
        n = self.size
        idx, lo, hi = [np.arange(n)], [np.zeros(n)], [np.ones(n)]
        cut = np.array(sorted(self._cuts), dtype=int)
        keep = np.ones(n, dtype=bool)
        keep[cut] = False
        idx, lo, hi = [idx[0][keep]], [lo[0][keep]], [hi[0][keep]]
        for i in cut:
            edges = [0.0, *self._cuts[int(i)], 1.0]
            idx.append(np.full(len(edges) - 1, i))
            lo.append(np.array(edges[:-1]))
            hi.append(np.array(edges[1:]))
        return np.concatenate(idx), np.concatenate(lo), np.concatenate(hi)

    def interval_work(self) -> np.ndarray:
        """(N,) ∫ T_p dφ over each sample interval, J (positive where the process absorbs work)."""
        x, w = np.polynomial.legendre.leggauss(GAUSS_POINTS)
        i, a, b = self.pieces()
        u = a[:, None] + (b - a)[:, None] * (x[None, :] + 1) / 2
        T = self.torque(np.broadcast_to(i[:, None], u.shape), u)
        return np.bincount(i, np.sum(T * w[None, :], axis=1) * (b - a) / 2 * self.step, minlength=self.size)

    def work(self) -> float:
        """∮ T_p dφ over one revolution, J (the process's work per stroke; positive where it absorbs)."""
        return float(self.interval_work().sum())

    def peak(self, sampled: np.ndarray) -> tuple[float, int, float]:
        """The largest T_p over the cycle, between samples too.

        Parameters
        ----------
        sampled : ndarray
            (N,) T_p at the samples, N·m.

        Returns
        -------
        (float, int, float)
            The largest T_p, N·m; the sample interval it lies in and its fraction u there.
        """
        from scipy.optimize import minimize_scalar

        best = int(np.argmax(sampled))
        top, where = float(sampled[best]), (best, 0.0)
        # The pieces: every sample interval cut at its kinks (table rows, the forming force's ends).
        # Every piece's ends are evaluated; the smooth pieces whose ends reach _NEAR of the largest
        # end are searched inside, the interval of a kink wherever it lies.
        ends = np.maximum(sampled, np.roll(sampled, -1))
        near = np.nonzero(ends >= _NEAR * top)[0].tolist() if top > 0.0 else []
        intervals = sorted({*near, *self._cuts})
        pieces = []
        for i in intervals:
            edges = [0.0, *self._kinks(int(i)), 1.0]
            values = [float(self.torque(i, u)) for u in edges]
            for u, v in zip(edges, values, strict=True):
                if v > top:
                    top, where = v, (int(i), u)
            ends = itertools.pairwise(zip(edges, values, strict=True))
            pieces += [(int(i), a, b, max(va, vb)) for (a, va), (b, vb) in ends]
        for i, a, b, end in pieces:
            if b - a < 1e-12 or top <= 0.0 or end < _NEAR * top:
                continue
            r = minimize_scalar(
                lambda u, i=i: -float(self.torque(i, u)),
                bounds=(a, b),
                method="bounded",
                options={"xatol": 1e-10},
            )
            if -r.fun > top:
                top, where = float(-r.fun), (i, float(r.x))
        return top, *where

    def angle_at(self, i: int, u: float) -> float:
        """The crank angle from the datum at fraction ``u`` of sample interval ``i``, rad, in
        [min(angle), min(angle) + 2π)."""
        lo = float(self.angle.min())
        return (float(self.angle[i]) + self.sense * u * self.step - lo) % (2 * math.pi) + lo

    def locate(self, angle: float) -> tuple[int, float]:
        """The sample interval and the fraction u of it at a crank angle from the datum (rad)."""
        x = ((angle - float(self.angle[0])) * self.sense) % (2 * math.pi) / self.step
        i = min(int(x), self.size - 1)
        return i, x - i

    def slide_position_at(self, angle: float) -> float:
        """The output slide's position at a crank angle from the datum, m."""
        return self.slide_position(*self.locate(angle))

    def slide_speed(self, angle: float) -> float:
        """ds/dφ of the output slide at a crank angle from the datum, m/rad (negative on the way
        down)."""
        if self.slide is None:
            return math.nan
        i, u = self.locate(angle)
        s, ds = self.slide
        j = (i + 1) % self.size
        h = self.step
        return float(_hermite(np.asarray(u), s[i], s[j], h * ds[i], h * ds[j])[1]) / h

    def moving_down(self, angle: float) -> bool:
        """Whether the slide moves down (its working stroke) at a crank angle from the datum."""
        return self.slide_speed(angle) < 0.0

    def angle_of_position(self, position: float) -> float | None:
        """The crank angle from the datum (rad) at which the slide passes ``position`` (m) on its way
        down; None when it never does."""
        if self.slide is None:
            return None
        s, ds = self.slide
        s1, ds1 = np.roll(s, -1), np.roll(ds, -1)
        h = self.step
        for i in np.nonzero((np.minimum(s, s1) <= position) & (position <= np.maximum(s, s1)))[0]:
            c = _cubic(s[i], s1[i], h * ds[i], h * ds1[i])
            c[-1] -= position
            for r in sorted(r.real for r in np.roots(c) if abs(r.imag) < 1e-12 and 0.0 <= r.real <= 1.0):
                angle = self.angle_at(int(i), float(r))
                if self.moving_down(angle):
                    return angle
        return None

    def slide_position(self, i: int, u: float) -> float:
        """The output slide's position at fraction ``u`` of sample interval ``i``, m."""
        if self.slide is None:
            return math.nan
        s, ds = self.slide
        j = (i + 1) % self.size
        h = self.step
        return float(_hermite(np.asarray(u), s[i], s[j], h * ds[i], h * ds[j])[0])

    def bdc_position(self) -> float:
        """The slide's lowest position, located between the samples on the same cubic that
        :meth:`slide_position` reads (not the lowest sample), m; NaN without a slide."""
        if self.slide is None:
            return math.nan
        s, ds = self.slide
        low = int(np.argmin(s))
        best = float(s[low])
        for i in ((low - 1) % self.size, low):
            j = (i + 1) % self.size
            c = _cubic(s[i], s[j], self.step * ds[i], self.step * ds[j])
            for r in np.roots(np.polyder(c)):
                if abs(r.imag) < 1e-12 and 0.0 < r.real < 1.0:
                    best = min(best, float(np.polyval(c, r.real)))
        return best


def _cubic(p0: float, p1: float, m0: float, m1: float) -> np.ndarray:
    """Coefficients (highest first) of the cubic Hermite curve in u through p0, p1 with slopes m0, m1."""
    return np.array([2 * p0 + m0 - 2 * p1 + m1, -3 * p0 - 2 * m0 + 3 * p1 - m1, m0, p0])


def _breaks(force: Any) -> list[tuple[str, tuple[float, ...]]]:
    """A force's kinks: pairs of what they are read against ("angle", rad from the datum, or
    "position", m along the output axis) and where; a force that tells none (a smooth callable, or
    one without a ``kinks()`` method) has none."""
    kinks = getattr(force, "kinks", None)
    if kinks is None:
        return []
    return [(versus, tuple(float(x) for x in rows)) for versus, rows in kinks()]


def process_path(kinematics: Any) -> ProcessPath:
    """The process forces of a mechanism along its sampled motion.

    Parameters
    ----------
    kinematics : KinematicsResult
        The mechanism's kinematics (equally spaced crank angles over one revolution).

    Returns
    -------
    ProcessPath
    """
    from mechdyn.mechanism.kinematics import output_position
    from mechdyn.mechanism.model import GROUND

    k = kinematics
    m = k.mechanism
    w = k.qd[:, 3 * m.body_index[m.driver.body] + 2]
    sense = 1.0 if m.driver.speed > 0 else -1.0
    n = k.angle.size
    step = 2 * math.pi / n
    # the samples in the order the crank turns
    turned = np.mod((k.angle - k.angle[0]) * sense, 2 * math.pi)
    order = np.argsort(turned, kind="stable")
    speed = np.abs(w)[order][:, None]
    acting = []
    for pf in m.process_forces:
        p, v, _ = k.point(pf.body, pf.point)
        acting.append(_Acting(pf.force, p[order], v[order] / speed))
    slide = None
    j = m.output_joint()
    if j is not None:
        body = j.bodies[1] if j.bodies[0] == GROUND else j.bodies[0]
        _, v, _ = k.point(body, j.point)
        up = np.array([math.cos(j.axis), math.sin(j.axis)])
        s = output_position(m, k.q)
        assert s is not None  # an output joint gives a position
        slide = (s[order], (v[order] @ up) / speed[:, 0])
    axis = float(j.axis) if j is not None else math.pi / 2
    return ProcessPath(np.asarray(k.angle)[order], sense, step, slide, tuple(acting), axis)
