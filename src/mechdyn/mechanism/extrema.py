"""Extremes over the crank cycle located between the samples: dead centres and force peaks.

The largest (or smallest) sample and its two neighbours on each side determine the quartic through
five equally spaced samples; its stationary point next to the sample is the extreme, to O(h⁴) in the
sample spacing h (with 360 samples, 1e-7 rad on press A's top dead centre; with 72, a few
thousandths of a degree). Vectorised over leading axes (design variants), so that one design and
each variant of a batch get the same figures from the same function.
"""

from __future__ import annotations

import numpy as np

__all__ = ["layout_figures", "load_figures", "output_figures", "peak"]


def peak(y: np.ndarray, sense: float) -> tuple[np.ndarray, np.ndarray]:
    """Where ``sense · y`` is largest over the last axis, between samples.

    Parameters
    ----------
    y : ndarray
        (..., N) values over one periodic cycle of equally spaced samples.
    sense : {1, -1}
        Maximum or minimum.

    Returns
    -------
    index : ndarray
        (...) position in samples (fractional; k + t with |t| ≤ 1 from the extreme sample k).
    value : ndarray
        (...) the extreme value.
    """
    y = np.asarray(y, dtype=float)
    N = y.shape[-1]
    k = np.argmax(np.where(np.isfinite(y), sense * y, -np.inf), axis=-1)
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
        t = np.clip(t - np.divide(d1, d2, out=np.zeros_like(t), where=d2 != 0), -1.0, 1.0)
    value = c[..., 0] + c[..., 1] * t + c[..., 2] * t**2 + c[..., 3] * t**3 + c[..., 4] * t**4
    # a flat or ragged neighbourhood: keep the sample
    keep = ~np.isfinite(value) | (sense * value < sense * np.take_along_axis(y, k[..., None], -1)[..., 0])
    t = np.where(keep, 0.0, t)
    value = np.where(keep, np.take_along_axis(y, k[..., None], -1)[..., 0], value)
    return k + t, value


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
    N = deg.shape[-1]
    step = (deg[..., 1] - deg[..., 0] + 180.0) % 360.0 - 180.0  # signed spacing, degrees

    def wrap(a: np.ndarray) -> np.ndarray:  # in [0, 360); a round-off below 360 is 0 (not 359.99999999999994)
        a = np.asarray(a) % 360.0
        return np.where(a > 360.0 - 1e-9, 0.0, a)

    def angle(pos: np.ndarray) -> np.ndarray:
        k = np.floor(pos).astype(int) % N
        return wrap(np.take_along_axis(deg, k[..., None], -1)[..., 0] + (pos - np.floor(pos)) * step)

    ib, s_min = peak(s, -1.0)
    it, s_max = peak(s, 1.0)
    fa, f_max = peak(f, 1.0)
    fb, f_min = peak(f, -1.0)
    bdc, tdc, at_max, at_min = angle(ib), angle(it), angle(fa), angle(fb)
    if bdc_datum:
        tdc, at_max, at_min = (wrap(a - bdc) for a in (tdc, at_max, at_min))
        bdc = np.zeros_like(bdc)
    ret = wrap(tdc - bdc)
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
