"""The compiled reductions of a cycle (numba): each variant's per-angle curves reduced to the scalar
figures of its summary, in parallel threads, with the formulas of :mod:`mechdyn.mechanism.extrema`
written out per variant (the same five-sample quartic, the same Newton steps, the same ties).

Imported on first use by :mod:`mechdyn.mechanism.dyads.summary` and by
:func:`mechdyn.mechanism.kinematics.crank_angles`; compiled once and cached on disk. The figures'
columns are :data:`COLUMNS`, in this order.
"""

import math

import numba
import numpy as np

from mechdyn.mechanism.dyads._kernel import variant

__all__ = ["COLUMNS", "bdc_degrees", "between", "run_and_summarise", "run_lanes", "summarise"]

LOAD = (
    "driving_torque_max_Nm",
    "driving_torque_min_Nm",
    "driving_torque_range_Nm",
    "driving_torque_peak_Nm",
    "driving_torque_rms_Nm",
    "shaking_force_max_N",
    "shaking_moment_range_Nm",
    "shaking_force_x_range_N",
    "shaking_force_y_range_N",
)
OUTPUT = (
    "stroke_m",
    "bdc_deg",
    "tdc_deg",
    "return_stroke_deg",
    "working_stroke_deg",
    "inertia_force_max_N",
    "inertia_force_max_deg",
    "inertia_force_min_N",
    "inertia_force_min_deg",
    "inertia_force_fluctuation_N",
)
LAYOUT = ("output_link_obliquity_max_deg", "guide_offset_m")
TRANSMISSION = ("transmission_angle_min_deg", "crank_angle_at_transmission_angle_min_deg")
COLUMNS = LOAD + OUTPUT + LAYOUT + TRANSMISSION
"""The summary keys a row of :func:`summarise` holds, in order (those of
:func:`~mechdyn.mechanism.extrema.load_figures`, :func:`~mechdyn.mechanism.extrema.output_figures`,
:func:`~mechdyn.mechanism.extrema.layout_figures` and
:func:`~mechdyn.mechanism.extrema.transmission_figures`)."""
TIE_DEG = 1e-7  # as mechdyn.mechanism.extrema.TIE_DEG


@numba.njit(cache=True, error_model="numpy")
def _peak(y, sense, k):
    """(position in samples, value) of the extreme of the periodic samples ``y`` near sample ``k``
    (−1: the first largest of sense·y), as :func:`mechdyn.mechanism.extrema.peak` for one row."""
    N = y.shape[0]
    if k < 0:
        k = 0
        best = -np.inf
        for i in range(N):
            val = sense * y[i] if np.isfinite(y[i]) else -np.inf
            if val > best:
                best = val
                k = i
    ym2, ym1, y0, y1, y2 = y[(k - 2) % N], y[(k - 1) % N], y[k], y[(k + 1) % N], y[(k + 2) % N]
    s1, d1, s2, d2 = y1 + ym1, y1 - ym1, y2 + ym2, y2 - ym2
    c0 = y0
    c1 = (8.0 * d1 - d2) / 12.0
    c2 = (16.0 * s1 - s2 - 30.0 * y0) / 24.0
    c3 = (d2 - 2.0 * d1) / 12.0
    c4 = (s2 - 4.0 * s1 + 6.0 * y0) / 24.0
    t = 0.0
    for _ in range(30):  # Newton on the derivative, from the sample
        g1 = c1 + 2 * c2 * t + 3 * c3 * t**2 + 4 * c4 * t**3
        g2 = 2 * c2 + 6 * c3 * t + 12 * c4 * t**2
        t_new = t - (g1 / g2 if g2 != 0 else 0.0)
        if t_new < -1.0:
            t_new = -1.0
        elif t_new > 1.0:
            t_new = 1.0
        if t_new == t:  # a fixed point: the remaining steps would repeat it exactly
            break
        t = t_new
    value = c0 + c1 * t + c2 * t**2 + c3 * t**3 + c4 * t**4
    if not np.isfinite(value) or sense * value < sense * y0:  # a flat or ragged neighbourhood
        return float(k), y0
    return k + t, value


@numba.njit(cache=True, error_model="numpy")
def between(s, lowest, out):
    """Into ``out`` (V,): where, in steps from sample ``lowest[v]``, the least value of row v of
    ``s`` (V, n) lies, within half a step (0 where the five samples about it are not all finite or
    the quartic's minimum lies farther): :func:`mechdyn.mechanism.kinematics.crank_angles`' BDC."""
    V, n = s.shape
    for v in range(V):
        k = lowest[v]
        ok = n >= 5
        for i in range(-2, 3):
            if not np.isfinite(s[v, (k + i) % n]):
                ok = False
        out[v] = 0.0
        if ok:
            pos, _ = _peak(s[v], -1.0, k)
            if abs(pos - k) <= 0.5:
                out[v] = pos - k


@numba.njit(cache=True, error_model="numpy")
def _bdc_row(s, step, out):
    """One row of :func:`bdc_degrees`: ``s`` (N,) output positions, m; ``out`` (N,) degrees."""
    N = s.shape[0]
    half = 0.5 * abs(step)
    lowest, least = np.int64(0), np.inf
    for k in range(N):
        x = s[k] if np.isfinite(s[k]) else np.inf
        if x < least:
            least = x
            lowest = k
    t = 0.0
    ok = N >= 5
    for i in range(-2, 3):
        if not np.isfinite(s[(lowest + i) % N]):
            ok = False
    if ok:
        pos, _ = _peak(s, -1.0, lowest)
        if abs(pos - lowest) <= 0.5:
            t = pos - lowest
    offset = -step * (lowest + t)
    for k in range(N):
        out[k] = np.degrees(np.mod(step * k + offset + half, 2 * np.pi) - half)


@numba.njit(parallel=True, cache=True, error_model="numpy")
def bdc_degrees(stroke, step, out):
    """Into ``out`` (W, N): the crank angle from each variant's located bottom dead centre at every
    step of its cycle, degrees, from its output positions ``stroke`` (W, N), m, and the signed crank
    step, rad: :func:`mechdyn.mechanism.kinematics.crank_angles` with ``angle_datum = "bdc"``, row
    by row (the sample nearest BDC first, at about 0)."""
    for v in numba.prange(stroke.shape[0]):
        _bdc_row(stroke[v], step, out[v])


@numba.njit(cache=True, error_model="numpy")
def _wrap(a):
    a = a % 360.0
    return 0.0 if a > 360.0 - 1e-9 else a


@numba.njit(cache=True, error_model="numpy")
def _angle_at(deg, pos):
    N = deg.shape[0]
    step = (deg[1] - deg[0] + 180.0) % 360.0 - 180.0
    f = math.floor(pos)
    return _wrap(deg[int(f) % N] + (pos - f) * step)


@numba.njit(cache=True, error_model="numpy")
def _cosine(link, axis):
    """abs(cos) of the angle between a link (complex) and a unit axis, within [0, 1] (NaN stays)."""
    c = abs(axis.real * link.real + axis.imag * link.imag) / abs(link)
    return np.nan if np.isnan(c) else min(max(c, 0.0), 1.0)


@numba.njit(cache=True, error_model="numpy")
def _range(y):
    """(largest, smallest) of y; NaN when any sample is NaN (as ndarray.max)."""
    hi, lo = -np.inf, np.inf
    for x in y:
        if np.isnan(x):
            return np.nan, np.nan
        hi = max(hi, x)
        lo = min(lo, x)
    return hi, lo


@numba.njit(cache=True, error_model="numpy")
def _summarise_one(
    v, deg, torque, force, moment, stroke, inertia, axis, pos, ends, measure, failed, bdc, row
):
    """The figures of row ``v`` of the curves into ``row`` (the other arguments are those of
    :func:`summarise`)."""
    N = torque.shape[1]
    D = measure.shape[2]
    row[:] = np.nan
    d = deg[v]
    hi, lo = _range(torque[v])
    peak_t, sq = 0.0, 0.0
    for k in range(N):
        peak_t = max(peak_t, abs(torque[v, k]))
        sq += torque[v, k] * torque[v, k]
    fmax = 0.0
    fx = np.empty(N)
    fy = np.empty(N)
    for k in range(N):
        fx[k], fy[k] = force[v, k].real, force[v, k].imag
        fmax = max(fmax, math.sqrt(fx[k] * fx[k] + fy[k] * fy[k]))
    mhi, mlo = _range(moment[v])
    xhi, xlo = _range(fx)
    yhi, ylo = _range(fy)
    row[0], row[1], row[2] = hi, lo, hi - lo
    row[3] = peak_t if np.isfinite(hi) else np.nan
    row[4] = math.sqrt(sq / N)
    row[5] = fmax if np.isfinite(xhi) and np.isfinite(yhi) else np.nan
    row[6], row[7], row[8] = mhi - mlo, xhi - xlo, yhi - ylo
    origin = np.nan
    if stroke.shape[0] > 0:
        s = stroke[v]
        f = np.empty(N)
        for k in range(N):
            f[k] = inertia[v, k].real * axis.real + inertia[v, k].imag * axis.imag
        ib, s_min = _peak(s, -1.0, np.int64(-1))
        it, s_max = _peak(s, 1.0, np.int64(-1))
        fa, f_max = _peak(f, 1.0, np.int64(-1))
        fb, f_min = _peak(f, -1.0, np.int64(-1))
        b_at, t_at, a_max, a_min = _angle_at(d, ib), _angle_at(d, it), _angle_at(d, fa), _angle_at(d, fb)
        origin = b_at
        if bdc:
            t_at, a_max, a_min = _wrap(t_at - b_at), _wrap(a_max - b_at), _wrap(a_min - b_at)
            b_at = 0.0
        ret = _wrap(t_at - b_at)
        row[9], row[10], row[11], row[12], row[13] = s_max - s_min, b_at, t_at, ret, 360.0 - ret
        row[14], row[15], row[16], row[17] = f_max, a_max, f_min, a_min
        row[18] = f_max - f_min
        if ends[0] >= 0:
            # the obliquity arccos(c) is largest where c is least: locate the sample on c, and
            # take the arc cosine at the five samples the quartic goes through
            obl = np.empty(N)
            kk, least = np.int64(0), np.inf
            for k in range(N):
                c = _cosine(pos[v, k, ends[1]] - pos[v, k, ends[0]], axis)
                if c < least:
                    least = c
                    kk = k
            for i in range(-2, 3):
                k = (kk + i) % N
                obl[k] = math.degrees(math.acos(_cosine(pos[v, k, ends[1]] - pos[v, k, ends[0]], axis)))
            worst = _peak(obl, 1.0, kk)[1]
            row[19] = np.nan if np.isnan(worst) else min(worst, 90.0)
            w = pos[v, 0, ends[2]] - pos[v, 0, ends[1]]
            row[20] = abs(axis.real * w.imag - axis.imag * w.real)
    if D:
        lowest = np.empty(D)
        at = np.empty(D)
        mu = np.empty(N)
        for j in range(D):
            # μ = arcsin(min(abs(sin μ), 1)) grows with abs(sin μ): its least value is at the least
            # abs(sin μ), and only samples within 1e-8 of that in sine (≥ 5.7e-7° in μ) can tie
            least = np.inf
            for k in range(N):
                x = min(abs(measure[v, k, j]), 1.0)
                if not failed[v] and x < least:
                    least = x
            low = math.degrees(math.asin(least)) if least < np.inf else np.inf
            # equal minima (round-off apart): the one at the smallest crank angle from the datum
            kk, first = np.int64(0), np.inf
            for k in range(N):
                x = min(abs(measure[v, k, j]), 1.0)
                if least < np.inf and not x <= least + 1e-8:
                    continue
                filled = math.degrees(math.asin(x)) if least < np.inf and not failed[v] else np.inf
                if filled <= low + TIE_DEG and d[k] < first:
                    first = d[k]
                    kk = k
            for i in range(-2, 3):
                k = (kk + i) % N
                x = abs(measure[v, k, j])
                mu[k] = np.nan if failed[v] or np.isnan(x) else math.degrees(math.asin(min(x, 1.0)))
            p, lowest[j] = _peak(mu, -1.0, kk)
            a = _angle_at(d, p)
            if stroke.shape[0] > 0 and bdc:
                a = _wrap(a - origin)
            at[j] = np.nan if np.isnan(lowest[j]) else a
        low = np.inf
        for j in range(D):
            if not np.isnan(lowest[j]):
                low = min(low, lowest[j])
        jj, first = 0, np.inf
        for j in range(D):
            lj = lowest[j] if not np.isnan(lowest[j]) else np.inf
            key = at[j] if not np.isnan(at[j]) else np.inf
            if lj <= low + TIE_DEG and key < first:
                first = key
                jj = j
        row[21], row[22] = lowest[jj], at[jj]


@numba.njit(parallel=True, cache=True, error_model="numpy")
def summarise(deg, torque, force, moment, stroke, inertia, axis, pos, ends, measure, failed, bdc, out):
    """Each variant's summary figures (the row :data:`COLUMNS` of ``out``) from its curves.

    Parameters
    ----------
    deg : (W, N) crank angle from the datum at each sample, degrees.
    torque, moment : (W, N) driving torque and moment on the frame about the origin, N·m.
    force, inertia : (W, N) complex: load on the frame and −Σ m a_G, N.
    stroke : (W, N) output position along its axis, m; (0, 0) without a slide output.
    axis : complex, the slide's axis (unit).
    pos : (W, N, K) complex positions of the kept points, m.
    ends : (3,) int: slots in ``pos`` of the output link's far and shared points and the crank's
        pivot; −1 for no layout figures.
    measure : (W, N, D) sine of each dyad's transmission angle.
    failed : (W,) bool: variants not computed (their transmission angles are NaN).
    bdc : bool, the datum is the located bottom dead centre.
    out : (W, len(COLUMNS)) written; NaN for the figures that do not apply.
    """
    for v in numba.prange(torque.shape[0]):
        _summarise_one(
            np.int64(v),
            deg,
            torque,
            force,
            moment,
            stroke,
            inertia,
            axis,
            pos,
            ends,
            measure,
            failed,
            bdc,
            out[v],
        )


@numba.njit(parallel=True, cache=True, error_model="numpy")
def run_and_summarise(args, step, deg, bdc, axis, ends, out):
    """The kernel (:func:`mechdyn.mechanism.dyads._kernel.variant`) and :func:`summarise` of each
    variant of ``args`` in one parallel pass (one start of the threads per chunk of variants): the
    curves go to the work buffers of ``args``, each variant's figures to its row of ``out``.
    ``deg`` (W, N) holds the crank angles from the datum (degrees) of a fixed datum, or is written
    here from each variant's located bottom dead centre (``bdc``, with the signed crank step
    ``step``, rad); no variant counts as failed
    (the screening follows, and a chunk with a failure is summarised again)."""
    failed = np.zeros(args.drawing.shape[0], dtype=np.bool_)
    for v in numba.prange(args.drawing.shape[0]):
        variant(np.int64(v), args, np.int64(v))  # prange's index is unsigned: one signature of variant
        if bdc and args.stroke.shape[0] > 0:
            _bdc_row(args.stroke[v], step, deg[v])
        _summarise_one(
            np.int64(v),  # prange's index is unsigned: one signature of _summarise_one
            deg,
            args.torque,
            args.force,
            args.moment,
            args.stroke,
            args.inertia_force,
            axis,
            args.pos,
            ends,
            args.dyad_measure,
            failed,
            bdc,
            out[v],
        )


@numba.njit(cache=True, error_model="numpy")
def _fixed_row(offset, step, out):
    """Crank angle from a fixed datum at every step, degrees, into ``out`` (N,): ``offset`` is the
    drawing's crank angle from the datum, rad (:func:`mechdyn.mechanism.kinematics.crank_angles`)."""
    for k in range(out.shape[0]):
        out[k] = np.degrees(np.mod(step * k + offset + 1e-12, 2 * np.pi) - 1e-12)


@numba.njit(parallel=True, cache=True, error_model="numpy")
def run_lanes(args, step, bdc, offsets, axis, ends, screen_tol, deg, out, suspect):
    """Every variant of ``args`` through the kernel and :func:`summarise`, in one parallel pass over
    lanes: lane i runs variants i, i + L, i + 2L, … (L the rows of the work buffers in ``args``,
    one per thread), writing its curves to its own row and each variant's figures to its row of
    ``out`` (V, len(COLUMNS)).

    ``offsets`` (V,) each variant's drawing crank angle from a fixed datum, rad (unused with
    ``bdc``); ``deg`` (L, N) work rows for the crank angles, degrees; ``suspect`` (V,) written: the
    variants with a dyad measure that is NaN or below ``screen_tol`` somewhere (the screening's
    candidates, :data:`mechdyn.mechanism.screening.SCREEN`), whose figures the caller works out
    again after screening them.
    """
    L = args.force.shape[0]
    V = args.drawing.shape[0]
    N = args.force.shape[1]
    D = args.dyad_measure.shape[2]
    failed = np.zeros(L, dtype=np.bool_)
    for lane in numba.prange(L):
        for v in range(lane, V, L):
            variant(v, args, np.int64(lane))
            flag = False
            for k in range(N):
                for j in range(D):
                    x = args.dyad_measure[lane, k, j]
                    if np.isnan(x) or abs(x) < screen_tol:
                        flag = True
            suspect[v] = flag
            if bdc:
                _bdc_row(args.stroke[lane], step, deg[lane])
            else:
                _fixed_row(offsets[v], step, deg[lane])
            _summarise_one(
                np.int64(lane),
                deg,
                args.torque,
                args.force,
                args.moment,
                args.stroke,
                args.inertia_force,
                axis,
                args.pos,
                ends,
                args.dyad_measure,
                failed,
                bdc,
                out[v],
            )
