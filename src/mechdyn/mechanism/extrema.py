"""Extremes over the crank cycle located between the samples: dead centres and force peaks.

The largest (or smallest) sample and its two neighbours on each side determine the quartic through
five equally spaced samples; its stationary point next to the sample is the extreme, to O(h⁴) in the
sample spacing h (with 360 samples, 1e-7 rad on press A's top dead centre; with 72, a few
thousandths of a degree). Vectorised over leading axes (design variants), so that one design and
each variant of a batch get the same figures from the same function.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "bdc_origin",
    "layout_figures",
    "load_figures",
    "output_figures",
    "peak",
    "rocker_angle",
    "swing_figures",
    "transmission_figures",
]


def peak(y: np.ndarray, sense: float, sample: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Where ``sense · y`` is largest over the last axis, between samples.

    Parameters
    ----------
    y : ndarray
        (..., N) values over one periodic cycle of equally spaced samples.
    sense : {1, -1}
        Maximum or minimum.
    sample : ndarray of int, optional
        (...) index of the extreme sample, where the caller picks it among equal extremes (by default
        the first largest of ``sense · y``).

    Returns
    -------
    index : ndarray
        (...) position in samples (fractional; k + t with |t| ≤ 1 from the extreme sample k).
    value : ndarray
        (...) the extreme value.
    """
    y = np.asarray(y, dtype=float)
    N = y.shape[-1]
    k = np.argmax(np.where(np.isfinite(y), sense * y, -np.inf), axis=-1) if sample is None else sample
    idx = (k[..., None] + np.arange(-2, 3)) % N
    five = np.take_along_axis(y, idx, axis=-1)
    # c0 + c1 t + c2 t² + c3 t³ + c4 t⁴ from the central differences of the five samples (the rows of
    # V⁻¹): elementwise, so a design's figures do not depend on how many variants share its batch, and
    # a symmetric neighbourhood gives c1 = c3 = 0 exactly (the extreme stays on its sample)
    ym2, ym1, y0, y1, y2 = (five[..., i] for i in range(5))
    s1, d1, s2, d2 = y1 + ym1, y1 - ym1, y2 + ym2, y2 - ym2
    c = np.stack(
        [y0, (8.0 * d1 - d2) / 12.0, (16.0 * s1 - s2 - 30.0 * y0) / 24.0, (d2 - 2.0 * d1) / 12.0,
         (s2 - 4.0 * s1 + 6.0 * y0) / 24.0],
        axis=-1,
    )  # fmt: skip
    t = np.zeros(k.shape)
    for _ in range(30):  # Newton on the derivative, from the sample
        d1 = c[..., 1] + 2 * c[..., 2] * t + 3 * c[..., 3] * t**2 + 4 * c[..., 4] * t**3
        d2 = 2 * c[..., 2] + 6 * c[..., 3] * t + 12 * c[..., 4] * t**2
        step = np.clip(t - np.divide(d1, d2, out=np.zeros_like(t), where=d2 != 0), -1.0, 1.0)
        if np.array_equal(step, t, equal_nan=True):  # a fixed point: the steps left change nothing
            break
        t = step
    value = c[..., 0] + c[..., 1] * t + c[..., 2] * t**2 + c[..., 3] * t**3 + c[..., 4] * t**4
    # a flat or ragged neighbourhood: keep the sample
    keep = ~np.isfinite(value) | (sense * value < sense * np.take_along_axis(y, k[..., None], -1)[..., 0])
    t = np.where(keep, 0.0, t)
    value = np.where(keep, np.take_along_axis(y, k[..., None], -1)[..., 0], value)
    return k + t, value


def _wrap(a: np.ndarray) -> np.ndarray:
    """Degrees in [0, 360); a round-off below 360 is 0 (not 359.99999999999994)."""
    a = np.asarray(a) % 360.0
    return np.where(a > 360.0 - 1e-9, 0.0, a)


def _angle_at(deg: np.ndarray, pos: np.ndarray) -> np.ndarray:
    """The crank angle (degrees, in [0, 360)) at a fractional sample position ``pos`` (...) of the
    equally spaced samples ``deg`` (..., N)."""
    N = deg.shape[-1]
    step = (deg[..., 1] - deg[..., 0] + 180.0) % 360.0 - 180.0  # signed spacing, degrees
    k = np.floor(pos).astype(int) % N
    return _wrap(np.take_along_axis(deg, k[..., None], -1)[..., 0] + (pos - np.floor(pos)) * step)


def output_figures(deg: np.ndarray, s: np.ndarray, f: np.ndarray, bdc_datum: bool) -> dict[str, np.ndarray]:
    """Stroke, dead centres and inertia-force extremes of a prismatic output, between samples.

    Parameters
    ----------
    deg : ndarray
        (..., N) crank angle from the datum at each sample, degrees, equally spaced in cycle order.
    s : ndarray
        (..., N) output position along its upward axis, m.
    f : ndarray
        (..., N) total inertia force along the output axis, N.
    bdc_datum : bool
        The datum is bottom dead centre: angles are then counted from the located BDC (0 exactly).

    Returns
    -------
    dict
        ``stroke_m``, ``bdc_deg``, ``tdc_deg``, ``return_stroke_deg``, ``working_stroke_deg``,
        ``inertia_force_max_N``, ``inertia_force_max_deg``, ``inertia_force_min_N``,
        ``inertia_force_min_deg``, ``inertia_force_fluctuation_N``, each (...).
    """
    ib, s_min = peak(s, -1.0)
    it, s_max = peak(s, 1.0)
    fa, f_max = peak(f, 1.0)
    fb, f_min = peak(f, -1.0)
    bdc, tdc, at_max, at_min = (_angle_at(deg, pos) for pos in (ib, it, fa, fb))
    if bdc_datum:
        tdc, at_max, at_min = (_wrap(a - bdc) for a in (tdc, at_max, at_min))
        bdc = np.zeros_like(bdc)
    ret = _wrap(tdc - bdc)
    return {
        "stroke_m": s_max - s_min,
        "bdc_deg": bdc,
        "tdc_deg": tdc,
        "return_stroke_deg": ret,
        "working_stroke_deg": 360.0 - ret,
        "inertia_force_max_N": f_max,
        "inertia_force_max_deg": at_max,
        "inertia_force_min_N": f_min,
        "inertia_force_min_deg": at_min,
        "inertia_force_fluctuation_N": f_max - f_min,
    }


def load_figures(torque: np.ndarray, force: np.ndarray, moment: np.ndarray) -> dict[str, np.ndarray]:
    """The driving-torque and frame-load figures of a cycle (over the last axis; leading axes are
    design variants).

    Parameters
    ----------
    torque : ndarray
        (..., N) driving torque, N·m.
    force : ndarray
        (..., N, 2) force on the frame, N.
    moment : ndarray
        (..., N) moment on the frame about the origin, N·m.

    Returns
    -------
    dict
        ``driving_torque_max_Nm``, ``driving_torque_min_Nm``, ``driving_torque_range_Nm``,
        ``driving_torque_peak_Nm``, ``driving_torque_rms_Nm``, ``shaking_force_max_N``,
        ``shaking_moment_range_Nm``, ``shaking_force_x_range_N``, ``shaking_force_y_range_N``, each (...).
    """
    return {
        "driving_torque_max_Nm": torque.max(axis=-1),
        "driving_torque_min_Nm": torque.min(axis=-1),
        "driving_torque_range_Nm": np.ptp(torque, axis=-1),
        "driving_torque_peak_Nm": np.abs(torque).max(axis=-1),
        "driving_torque_rms_Nm": np.sqrt(np.mean(torque**2, axis=-1)),
        "shaking_force_max_N": np.linalg.norm(force, axis=-1).max(axis=-1),
        "shaking_moment_range_Nm": np.ptp(moment, axis=-1),
        "shaking_force_x_range_N": np.ptp(force[..., 0], axis=-1),
        "shaking_force_y_range_N": np.ptp(force[..., 1], axis=-1),
    }


def layout_figures(
    link: np.ndarray, axis: float, pivot: np.ndarray, slide: np.ndarray
) -> dict[str, np.ndarray]:
    """How a slide is driven: the largest obliquity of the link that drives it, and how far its
    guide runs from the crank's pivot.

    Parameters
    ----------
    link : ndarray
        (..., N) complex: the link's direction (shared point minus far point) at each sample.
    axis : float
        The slide's axis, rad from +x.
    pivot : ndarray
        (...) complex: the crank's pivot.
    slide : ndarray
        (...) complex: a position of the slide's point (any: it moves along the axis).

    Returns
    -------
    dict
        ``output_link_obliquity_max_deg`` (the largest angle between the link and the slide's axis,
        between samples: 0 when the link pushes straight along it) and ``guide_offset_m`` (distance
        from the crank's pivot to the guide's line), each (...).
    """
    u = np.exp(1j * axis)
    along = np.abs((np.conj(u) * link).real)
    obliquity = np.degrees(np.arccos(np.clip(along / np.abs(link), 0.0, 1.0)))
    _, worst = peak(obliquity, 1.0)
    offset = np.abs((np.conj(u) * (pivot - slide)).imag)
    return {"output_link_obliquity_max_deg": np.minimum(worst, 90.0), "guide_offset_m": offset}


TIE_DEG = 1e-7
"""Transmission-angle minima this close (deg) are one minimum, located at the first crank angle."""


def bdc_origin(deg: np.ndarray, s: np.ndarray) -> np.ndarray:
    """The crank angle of the located bottom dead centre, degrees: where angles count from with
    ``angle_datum = "bdc"`` (the samples start at the lowest sample, the located BDC lies between).

    Parameters
    ----------
    deg : ndarray
        (..., N) crank angle from the datum at each sample, degrees, equally spaced in cycle order.
    s : ndarray
        (..., N) output position along its upward axis, m.
    """
    return _angle_at(deg, peak(s, -1.0)[0])


def _from(angle: np.ndarray, origin: np.ndarray | None) -> np.ndarray:
    return angle if origin is None else _wrap(angle - origin)


def transmission_figures(
    deg: np.ndarray, mu: np.ndarray, origin: np.ndarray | None = None
) -> tuple[dict[str, np.ndarray], np.ndarray, np.ndarray]:
    """The smallest transmission angle of a mechanism's dyads over the cycle, between samples.

    Parameters
    ----------
    deg : ndarray
        (..., N) crank angle from the datum at each sample, degrees, equally spaced in cycle order.
    mu : ndarray
        (..., N, D) transmission angle of each of the D dyads at each sample, degrees (0 to 90).
    origin : ndarray, optional
        (...) crank angle that angles count from, degrees (the located BDC, see :func:`bdc_origin`).

    Returns
    -------
    figures : dict
        ``transmission_angle_min_deg`` (the smallest over all dyads) and
        ``crank_angle_at_transmission_angle_min_deg``, each (...).
    lowest : ndarray
        (..., D) each dyad's smallest transmission angle, degrees.
    at : ndarray
        (..., D) the crank angle where each dyad's is smallest, degrees.
    """
    y = np.moveaxis(mu, -1, -2)  # (..., D, N)
    filled = np.where(np.isfinite(y), y, np.inf)
    # equal minima (an in-line slider-crank's at 90° and 270°) differ by round-off, which would pick
    # either: the one at the smallest crank angle from the datum is taken, on every solver's samples
    near = filled <= filled.min(axis=-1, keepdims=True) + TIE_DEG
    k = np.argmin(np.where(near, np.broadcast_to(deg[..., None, :], y.shape), np.inf), axis=-1)
    pos, lowest = peak(y, -1.0, k)  # (..., D)
    at = _from(_angle_at(deg[..., None, :], pos), None if origin is None else np.asarray(origin)[..., None])
    at = np.where(np.isnan(lowest), np.nan, at)  # no angle for a variant that failed
    # the dyad with the smallest (of equal ones, the first in crank angle); a failed variant stays NaN
    low = np.where(np.isnan(lowest), np.inf, lowest)
    near = low <= low.min(axis=-1, keepdims=True) + TIE_DEG
    j = np.argmin(np.where(near, np.where(np.isnan(at), np.inf, at), np.inf), axis=-1)[..., None]
    figures = {
        "transmission_angle_min_deg": np.take_along_axis(lowest, j, -1)[..., 0],
        "crank_angle_at_transmission_angle_min_deg": np.take_along_axis(at, j, -1)[..., 0],
    }
    return figures, lowest, at


def rocker_angle(link: np.ndarray) -> np.ndarray:
    """A rocker's angle from +x over the cycle, degrees, continuous from sample to sample, the middle
    of its range taken within ±180° (so that a rocker swinging through 180° has no jump).

    Parameters
    ----------
    link : ndarray
        (..., N) complex: the rocker's direction (from its frame pivot to its other point), m.
    """
    psi = np.degrees(np.unwrap(np.angle(link), axis=-1))
    finite = np.isfinite(psi)
    some = finite.any(axis=-1)  # a variant that failed is NaN throughout
    high = np.where(some, np.where(finite, psi, -np.inf).max(axis=-1), 0.0)
    low = np.where(some, np.where(finite, psi, np.inf).min(axis=-1), 0.0)
    return psi - (360.0 * np.round(0.5 * (high + low) / 360.0))[..., None]


def swing_figures(
    deg: np.ndarray, link: np.ndarray, origin: np.ndarray | None = None
) -> dict[str, np.ndarray]:
    """The swing of a rocker output over the cycle and its two limit positions, between samples.

    Parameters
    ----------
    deg : ndarray
        (..., N) crank angle from the datum at each sample, degrees, equally spaced in cycle order.
    link : ndarray
        (..., N) complex: the rocker's direction (from its frame pivot to its other point), m.
    origin : ndarray, optional
        (...) crank angle that angles count from, degrees (the located BDC, see :func:`bdc_origin`).

    Returns
    -------
    dict
        ``output_swing_deg`` (largest minus smallest angle of the rocker), ``output_angle_min_deg``
        and ``output_angle_max_deg`` (the rocker's angle from +x at its two limits, the middle of
        the swing taken within ±180°), ``crank_angle_at_output_angle_min_deg`` and
        ``crank_angle_at_output_angle_max_deg``, each (...); NaN where the link turns right round
        (it is a crank, not a rocker).
    """
    psi = rocker_angle(link)
    closing = np.degrees(np.angle(link[..., 0] * np.conj(link[..., -1])))  # last sample → first
    rocks = np.round((psi[..., -1] - psi[..., 0] + closing) / 360.0) == 0  # not a whole turn
    i_min, low = peak(psi, -1.0)
    i_max, high = peak(psi, 1.0)
    nan = np.full(np.shape(low), np.nan)
    return {
        "output_swing_deg": np.where(rocks, high - low, nan),
        "output_angle_min_deg": np.where(rocks, low, nan),
        "output_angle_max_deg": np.where(rocks, high, nan),
        "crank_angle_at_output_angle_min_deg": np.where(rocks, _from(_angle_at(deg, i_min), origin), nan),
        "crank_angle_at_output_angle_max_deg": np.where(rocks, _from(_angle_at(deg, i_max), origin), nan),
    }
