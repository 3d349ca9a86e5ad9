"""Tonnage and energy of a press: the slide force a rated crank torque can deliver at each crank
angle, the rated point, the energy the process takes per stroke, and the process force checked
against the available force.

Quasi-static, as a press builder rates a mechanical press: the rated crank torque T_r is turned into
slide force through the linkage's velocity ratio ds/dθ alone, F(θ) = T_r / |ds/dθ| (virtual work,
friction and the linkage's own inertia neglected). Source: Schuler GmbH, *Metal Forming Handbook*
(Springer 1998), §3.2 (force–stroke characteristic of crank and link drives, "rated press force at
X mm before BDC"); Lange (ed.), *Handbook of Metal Forming* (McGraw-Hill 1985), ch. 13 (crank presses:
torque, force and work capacity). The velocity ratio comes from the kinematics: ds/dθ = v_slide / θ̇.

Positions are along the slide's guide axis, which points *up*: bottom dead centre (BDC) is the least
position, the working stroke the part of the cycle where the slide moves down.

At break-through (a punch through its blank) the process force falls within a short travel and the
press frame, stretched by it, springs back: its stored energy F²/(2k) swings the slide and the frame
past their unloaded position and loads the press in reverse. The frame and slide are taken as one
mode, the slide's mass on the press's stiffness k (T_n = 2π√(m/k)); a release over the time t_d
leaves a free vibration of amplitude ΔF |sin(π t_d/T_n)/(π t_d/T_n)| about the force left after it
(the residual spectrum of a ramp, e.g. Harris and Piersol, *Shock and Vibration Handbook*, 5th ed.,
ch. 8), damped by exp(−πζ/√(1 − ζ²)) over the half period to the first reverse peak. It is checked
against the press's reverse-load capacity, a fraction of its rated force (commonly 10 %; press
builders' ratings, e.g. Schuler, *Metal Forming Handbook*, §4.2 on blanking: reverse load limits;
give the maker's figure).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from mechdyn.units import convert, show, si_field

__all__ = [
    "CURVE_CUTOFF_BEFORE_BDC",
    "Frame",
    "breakthrough",
    "rated_point",
    "slider_crank_velocity_ratio",
    "stroke_energy",
    "tonnage_capacity",
    "tonnage_figures",
    "tonnage_table",
    "velocity_ratio",
]

#: The tonnage curve is drawn down to this distance before BDC, m (1 mm): it rises without bound at
#: BDC, where ds/dθ = 0 and the die, the frame and the drive's clutch limit the force instead.
CURVE_CUTOFF_BEFORE_BDC: float = float(convert(1.0, "mm", "m"))


def velocity_ratio(velocity: Any, crank_speed: Any) -> np.ndarray:
    """The slide's velocity ratio ds/dθ = v / θ̇, m/rad.

    Parameters
    ----------
    velocity : array_like
        The slide's velocity along its axis, m/s.
    crank_speed : array_like
        The crank's angular speed θ̇, rad/s (nonzero).

    Returns
    -------
    ndarray
        ds/dθ, m/rad: the slide travel per radian of crank (kinematics only, independent of speed).
    """
    return np.asarray(velocity, dtype=float) / np.asarray(crank_speed, dtype=float)


def slider_crank_velocity_ratio(theta: Any, crank: float, rod: float) -> np.ndarray:
    """ds/dθ of an in-line slider-crank in closed form, m/rad.

    ds/dθ = −r sin θ (1 + r cos θ / √(l² − r² sin² θ)), with θ from top dead centre and s the slide's
    distance from the crank's pivot (Norton, *Design of Machinery*, 5th ed., §7.6; Schuler, *Metal
    Forming Handbook*, §3.2).

    Parameters
    ----------
    theta : array_like
        Crank angle from top dead centre, rad.
    crank : float
        Crank radius r, m.
    rod : float
        Connecting-rod length l, m (longer than r).

    Returns
    -------
    ndarray
        ds/dθ, m/rad.
    """
    t = np.asarray(theta, dtype=float)
    root = np.sqrt(rod**2 - crank**2 * np.sin(t) ** 2)
    return -crank * np.sin(t) * (1.0 + crank * np.cos(t) / root)


def tonnage_capacity(rated_torque: float, ds_dtheta: Any) -> np.ndarray:
    """The slide force a rated crank torque can deliver, F = T_r / |ds/dθ|, N.

    Quasi-static virtual work (friction and inertia neglected): Schuler, *Metal Forming Handbook*,
    §3.2; Lange, *Handbook of Metal Forming*, ch. 13.

    Parameters
    ----------
    rated_torque : float
        The rated crank torque T_r, N·m.
    ds_dtheta : array_like
        The slide's velocity ratio, m/rad.

    Returns
    -------
    ndarray
        N; infinite where ds/dθ = 0 (the dead centres).
    """
    r = np.abs(np.asarray(ds_dtheta, dtype=float))
    with np.errstate(divide="ignore"):
        return np.where(r > 0, rated_torque / np.where(r > 0, r, 1.0), np.inf)


def rated_point(
    distance_before_bdc: Any,
    ds_dtheta: Any,
    angle_before_bdc: Any,
    rated_torque: float,
    rated_force: float,
) -> tuple[float, float]:
    """Where the rated force is first available on the way down: "rated tonnage at X mm before BDC".

    The available force T_r / |ds/dθ| rises toward BDC; the rated point is the farthest distance
    before BDC from which it stays at or above the rated force F_r down to BDC (Schuler, *Metal
    Forming Handbook*, §3.2). Between two samples |ds/dθ| is interpolated linearly in crank angle and
    the distance by a cubic Hermite curve through both samples' distances and slopes.

    Parameters
    ----------
    distance_before_bdc : array_like
        Distance of the slide above BDC, m, at the working stroke's samples in the order the crank
        turns (the last one nearest BDC).
    ds_dtheta : array_like
        The velocity ratio there, m/rad.
    angle_before_bdc : array_like
        Crank angle still to turn to BDC, rad.
    rated_torque : float
        T_r, N·m.
    rated_force : float
        F_r, N.

    Returns
    -------
    (float, float)
        The distance before BDC, m, and the crank angle before BDC, rad; the whole working stroke
        (its first sample) when the rated force is available all along it.
    """
    d = np.asarray(distance_before_bdc, dtype=float)
    g = np.abs(np.asarray(ds_dtheta, dtype=float))
    a = np.asarray(angle_before_bdc, dtype=float)
    limit = rated_torque / rated_force  # |ds/dθ| at which the available force is F_r
    short = np.nonzero(g > limit)[0]  # where the force falls short of F_r
    if short.size == 0:
        return float(d[0]), float(a[0])
    i = int(short[-1])
    if i == d.size - 1:  # short at the last sample: BDC itself lies beyond the samples
        return float(d[i]), float(a[i])
    t = (g[i] - limit) / (g[i] - g[i + 1])
    h = a[i] - a[i + 1]  # the crank angle between the two samples, rad
    # distance as a cubic in the angle turned, with slopes −|ds/dθ| (the slide moves down)
    h00, h10, h01, h11 = 2 * t**3 - 3 * t**2 + 1, t**3 - 2 * t**2 + t, -2 * t**3 + 3 * t**2, t**3 - t**2
    dist = h00 * d[i] + h10 * h * (-g[i]) + h01 * d[i + 1] + h11 * h * (-g[i + 1])
    return float(dist), float(a[i] - t * h)


def stroke_energy(torque: Any) -> float:
    """The work a torque does over one crank revolution sampled at equal crank angles, J.

    W = ∮ T dθ (the periodic trapezoidal rule, spectrally accurate for a smooth periodic torque).

    Parameters
    ----------
    torque : array_like
        N·m at N equal crank angles over one revolution, in the sense the crank turns.

    Returns
    -------
    float
        J.
    """
    T = np.asarray(torque, dtype=float)
    return float(T.sum() * 2.0 * math.pi / T.size)


def _verdict(ratio: np.ndarray, distance: np.ndarray, working: np.ndarray) -> str:
    k = int(np.argmax(ratio))
    where = f"{float(convert(distance[k], 'm', 'mm')):.4g} mm before BDC" if working[k] else "on the return"
    if ratio[k] <= 1.0:
        return (
            f"within capacity: the process force reaches at most {ratio[k]:.3g} times the available "
            f"force, at {where}"
        )
    over = np.nonzero((ratio > 1.0) & working)[0]
    span = ""
    if over.size:
        lo, hi = (float(convert(x, "m", "mm")) for x in (distance[over].min(), distance[over].max()))
        span = f" from {hi:.4g} to {lo:.4g} mm before BDC"
    return (
        f"exceeds capacity{span}: the process force is up to {ratio[k]:.3g} times the available force, "
        f"at {where}"
    )


def tonnage_figures(
    angle: Any,
    position: Any,
    velocity: Any,
    crank_speed: Any,
    process_torque: Any,
    rated_torque: float,
    rated_force: float | None = None,
    cutoff: float = CURVE_CUTOFF_BEFORE_BDC,
    path: Any = None,
) -> tuple[dict[str, Any], dict[str, np.ndarray]]:
    """The tonnage curve, the rated point, the energy per stroke and the capacity check of a press.

    Available force F(θ) = T_r / |ds/dθ| (Schuler, *Metal Forming Handbook*, §3.2); the process
    force's demand on the crank T_p = −P / |θ̇| (P the power of the process forces on the linkage),
    its equivalent force on the slide T_p / |ds/dθ| and its ratio to the available force T_p / T_r
    (the same ratio, defined at BDC too); the energy per stroke ∮ T_p dθ = ∫ F ds.

    Parameters
    ----------
    angle : array_like
        (N,) equal crank angles over one revolution, rad, from the datum.
    position : array_like
        (N,) slide position along its axis (up), m.
    velocity : array_like
        (N,) slide velocity along its axis, m/s.
    crank_speed : array_like
        (N,) θ̇, rad/s.
    process_torque : array_like
        (N,) the process forces' demand on the crank in the sense it turns, −P / |θ̇|, N·m.
    rated_torque : float
        T_r, N·m, positive.
    rated_force : float, optional
        F_r, N, positive: the rated point is reported with it.
    cutoff : float
        The curve stops this distance before BDC, m.
    path : ProcessPath, optional
        The process forces between the samples (:func:`mechdyn.mechanism.process.process_path`): the
        energy per stroke is then integrated piece by piece between the forces' kinks and the largest
        ratio to the available force is found between the samples too (else both come from the
        samples alone).

    Returns
    -------
    (dict, dict)
        The summary figures (keys with unit suffixes, angles in degrees) and the per-angle columns:
        ``distance_before_bdc_m``, ``tonnage_capacity_N`` (NaN off the working stroke and within
        ``cutoff`` of BDC), ``process_force_on_slide_N`` and ``process_torque_Nm`` (T_p; its ratio to
        T_r is the process force's to the available force).
    """
    theta = np.asarray(angle, dtype=float)
    s = np.asarray(position, dtype=float)
    w = np.asarray(crank_speed, dtype=float)
    g = velocity_ratio(velocity, w)
    Tp = np.asarray(process_torque, dtype=float)
    b = int(np.argmin(s))
    distance = s - s[b]
    sense = np.sign(w)
    # crank angle still to turn to BDC, in the sense the crank turns
    to_bdc = np.mod((theta[b] - theta) * sense, 2 * math.pi)
    working = np.asarray(velocity, dtype=float) < 0  # the slide moves down
    capacity = tonnage_capacity(rated_torque, g)
    curve = np.where(working & (distance >= cutoff), capacity, np.nan)
    with np.errstate(divide="ignore", invalid="ignore"):
        on_slide = np.where(np.abs(g) > 0, Tp / np.abs(g), np.nan)
    ratio = Tp / rated_torque
    out: dict[str, Any] = {"rated_torque_Nm": float(rated_torque)}
    out["tonnage_capacity_min_N"] = float(np.min(capacity[working])) if working.any() else math.nan
    if rated_force is not None:
        order = np.argsort(-to_bdc[working])  # the working stroke in the order the crank turns
        # ending at BDC itself, where ds/dθ = 0
        d_w, g_w, a_w = (np.append(x[working][order], 0.0) for x in (distance, g, to_bdc))
        d_r, a_r = rated_point(d_w, g_w, a_w, rated_torque, rated_force)
        out["rated_force_N"] = float(rated_force)
        out["rated_point_before_bdc_m"] = d_r
        out["rated_point_before_bdc_deg"] = math.degrees(a_r)
        slope = float(np.interp(a_r, a_w[::-1], np.abs(g_w[::-1])))
        out["tonnage_at_rated_point_N"] = float(rated_torque / slope) if slope > 0 else math.inf
        out["rated_energy_below_rated_point_J"] = float(rated_torque * a_r)
    out["process_energy_per_stroke_J"] = stroke_energy(Tp) if path is None else path.work()
    n_working = int(np.count_nonzero(Tp > 0))
    out["rated_torque_energy_over_process_J"] = float(rated_torque * n_working * 2 * math.pi / Tp.size)
    if np.any(Tp > 0):
        k = int(np.argmax(ratio))
        peak, angle_peak, distance_peak = float(ratio[k]), float(theta[k]), float(distance[k])
        checked: tuple[np.ndarray, ...] = (ratio, distance, working)
        if path is not None:
            top, i, u = path.peak(path.torque(np.arange(path.size), np.zeros(path.size)))
            if top / rated_torque > peak:
                peak, angle_peak = top / rated_torque, path.angle_at(i, u)
                distance_peak = path.slide_position(i, u) - float(s[b])
                # the verdict reads the peak between samples too
                extra = (peak, distance_peak, True)
                checked = tuple(np.append(x, y) for x, y in zip(checked, extra, strict=True))
        out["process_force_to_capacity_max_ratio"] = peak
        out["crank_angle_at_process_force_to_capacity_max_deg"] = math.degrees(angle_peak)
        out["process_force_to_capacity_max_before_bdc_m"] = distance_peak
        out["tonnage_verdict"] = _verdict(checked[0], checked[1], checked[2])
    else:
        out["tonnage_verdict"] = "no process force resists the slide: nothing to check against the curve"
    columns = {
        "distance_before_bdc_m": distance,
        "tonnage_capacity_N": curve,
        "process_force_on_slide_N": on_slide,
        "process_torque_Nm": Tp,
    }
    return out, columns


DEAD_CENTRE = 1e-4
"""A fall where the slide moves slower than this fraction of its fastest (ds/dθ) is at a dead centre:
the force there releases as the slide turns back, not by breaking through."""


@dataclass(frozen=True)
class Frame:
    """What the press's frame takes: its stiffness under the slide's load and its reverse-load capacity.

    Parameters
    ----------
    stiffness : float or quantity
        k, the press's stiffness between the slide and the bed (frame, drive and bearings together),
        N/m (e.g. ``"5 MN/mm"``), positive.
    reverse_capacity : float
        The reverse load it is rated for, as a fraction of the rated force, dimensionless, in (0, 1]
        (default 0.1).
    damping_ratio : float
        ζ of the frame-and-slide mode, dimensionless, in [0, 1) (default 0: undamped, an upper bound).
    """

    stiffness: Any
    reverse_capacity: Any = 0.1
    damping_ratio: Any = 0.0

    def __post_init__(self) -> None:
        k = si_field("press frame", "stiffness", self.stiffness, "N/m", positive=True)
        r = si_field(
            "press frame", "reverse_capacity", self.reverse_capacity, "", low=0.0, high=1.0, low_open=True
        )
        z = si_field(
            "press frame", "damping_ratio", self.damping_ratio, "", low=0.0, high=1.0, high_open=True
        )
        object.__setattr__(self, "stiffness", k)
        object.__setattr__(self, "reverse_capacity", r)
        object.__setattr__(self, "damping_ratio", z)


def _falls(path: Any) -> list[tuple[float, float, float, float, str]]:
    """The falls of the tabulated process forces on the working stroke, in the order the slide meets
    them: (force before, force after along the slide's axis, N; the travel or crank angle over which
    it falls, m or rad; its start as a crank angle, rad)."""
    out = []
    slide = path.slide
    fastest = float(np.abs(slide[1]).max()) if slide is not None else 0.0
    for a in path.acting:
        force = a.force
        rows, magnitude = getattr(force, "x", None), getattr(force, "magnitude", None)
        versus, direction = getattr(force, "versus", None), getattr(force, "direction", None)
        if rows is None or versus not in ("angle", "position") or slide is None:
            continue
        x = np.concatenate([[rows[0]], rows, [rows[-1]]])
        f = np.concatenate([[0.0], magnitude, [0.0]])  # zero outside the rows: a fall at an end
        along = math.cos(direction - path.axis)  # the share along the slide's axis (up: resisting)
        if versus == "angle":
            order = np.arange(x.size) if path.sense > 0 else np.arange(x.size)[::-1]
        else:  # the working stroke runs down the positions
            order = np.arange(x.size)[::-1]
        x, f = x[order], f[order] * along
        for k in range(x.size - 1):
            if f[k] > f[k + 1] and f[k] > 0:
                angle = float(x[k]) if versus == "angle" else path.angle_of_position(float(x[k]))
                if angle is None or path.slide_speed(angle) > -DEAD_CENTRE * fastest:
                    continue  # on the return, or at a dead centre: the force releases with the slide
                span = abs(float(x[k + 1] - x[k]))
                out.append((float(f[k]), float(max(f[k + 1], 0.0)), span, angle, versus))
    return out


def breakthrough(
    path: Any, frame: Frame, slide_mass: float, crank_speed: float, rated_force: float | None
) -> dict[str, Any]:
    """The reverse load when a tabulated process force breaks off on the working stroke.

    Parameters
    ----------
    path : ProcessPath
        The process forces along the motion (:func:`mechdyn.mechanism.process.process_path`).
    frame : Frame
        The press's stiffness, reverse capacity and damping.
    slide_mass : float
        m, the mass the frame swings (the slide with its upper die), kg.
    crank_speed : float
        |θ̇|, rad/s, to turn a fall over a crank angle into a time.
    rated_force : float or None
        F_r, N: the reverse capacity is a fraction of it.

    Returns
    -------
    dict
        Summary figures (keys with unit suffixes): the fall's force, where it happens, the energy the
        frame releases, the reverse load and its verdict; only a verdict saying so when no force
        breaks off.
    """
    falls = _falls(path)
    if not falls:
        return {"reverse_load_verdict": "no tabulated process force breaks off on the working stroke"}
    k, zeta = frame.stiffness, frame.damping_ratio
    Tn = 2 * math.pi * math.sqrt(slide_mass / k) if slide_mass > 0 else 0.0
    decay = math.exp(-math.pi * zeta / math.sqrt(1 - zeta * zeta))
    best = None
    for before, after, span, angle, versus in falls:
        if versus == "angle":
            t_d = span / abs(crank_speed)
        else:
            t_d = span / max(abs(path.slide_speed(angle) * crank_speed), 1e-300)
        shape = abs(float(np.sinc(t_d / Tn))) if Tn > 0 else 0.0
        reverse = max(0.0, (before - after) * shape * decay - after)
        if best is None or reverse > best[0]:
            best = (reverse, before, after, t_d, angle, shape)
    assert best is not None
    reverse, before, after, t_d, angle, shape = best
    s_bdc = path.bdc_position()
    out: dict[str, Any] = {
        "breakthrough_force_N": before,
        "breakthrough_crank_angle_deg": math.degrees(angle),
        "breakthrough_before_bdc_m": path.slide_position_at(angle) - s_bdc,
        "breakthrough_release_time_s": t_d,
        "press_stiffness_N_per_m": k,
        "frame_period_s": Tn,
        "frame_energy_released_J": (before * before - after * after) / (2 * k),
        "reverse_load_peak_N": reverse,
    }
    if rated_force is None:
        out["reverse_load_verdict"] = (
            "give rated_force to check the reverse load against the press's capacity"
        )
        return out
    allowed = frame.reverse_capacity * rated_force
    ratio = reverse / allowed
    out["reverse_load_to_capacity_ratio"] = ratio
    out["reverse_capacity_N"] = allowed
    undamped = " (undamped: an upper bound)" if zeta == 0 else ""
    what = "within" if ratio <= 1 else "exceeds"
    where = float(convert(out["breakthrough_before_bdc_m"], "m", "mm"))
    out["reverse_load_verdict"] = (
        f"{what} reverse capacity: break-through at {where:.4g} mm before BDC releases "
        f"{show(before, 'N', 'kN', '.4g')} in {show(t_d, 's', 'ms', '.3g')} (the frame's period "
        f"{show(Tn, 's', 'ms', '.3g')}); the press springs back with {show(reverse, 'N', 'kN', '.4g')}"
        f"{undamped}, {ratio:.3g} times its reverse capacity of {show(allowed, 'N', 'kN', '.4g')} "
        f"({frame.reverse_capacity:.3g} of the rated force)"
    )
    return out


#: Distances before BDC at which the tonnage table reads the curve, mm (the press chart's scale).
TABLE_DISTANCES_MM: tuple[float, ...] = (1.0, 2.0, 3.0, 5.0, 10.0, 20.0, 30.0, 50.0, 100.0, 200.0, 500.0)


def tonnage_table(
    figures: dict[str, Any], columns: dict[str, np.ndarray], length_unit: str = "mm", name: str = ""
) -> Any:
    """The tonnage curve read at round distances before BDC, with the verdict as its note.

    Parameters
    ----------
    figures, columns : dict
        As :func:`tonnage_figures` returns them (SI).
    length_unit : str
        Display unit of the distances (any length unit).
    name : str
        The machine's name, for the title.

    Returns
    -------
    mechdyn.results.Table
        Distance before BDC (``length_unit``), available force and the process force on the slide
        (kN), on the working stroke, within the stroke.
    """
    from mechdyn.results import Table

    d = columns["distance_before_bdc_m"]
    cap = columns["tonnage_capacity_N"]
    proc = columns["process_force_on_slide_N"]
    keep = np.isfinite(cap)
    order = np.argsort(d[keep])
    dk, ck, pk = d[keep][order], cap[keep][order], proc[keep][order]
    rows = []
    for mm in TABLE_DISTANCES_MM:
        x = float(convert(mm, "mm", "m"))
        if dk.size == 0 or x < dk[0] or x > dk[-1]:
            continue
        rows.append(
            [
                float(convert(x, "m", length_unit)),
                float(convert(np.interp(x, dk, ck), "N", "kN")),
                float(convert(np.interp(x, dk, pk), "N", "kN")),
            ]
        )
    head = f"{name}: " if name else ""
    torque = float(convert(figures["rated_torque_Nm"], "N*m", "kN*m"))
    verdict = str(figures["tonnage_verdict"])
    note = (
        f"Quasi-static: F = T_r/|ds/dθ| with T_r = {torque:g} kN·m, friction and inertia neglected "
        f"(Schuler, Metal Forming Handbook, §3.2). {verdict[0].upper()}{verdict[1:]}."
    )
    reverse = figures.get("reverse_load_verdict")
    if reverse and "breakthrough_force_N" in figures:
        note += f" Reverse load at break-through (one mode, the slide on the press's stiffness): {reverse}."
    return Table(
        f"{head}tonnage (force available on the working stroke)",
        [f"before BDC [{length_unit}]", "available force [kN]", "process force [kN]"],
        rows,
        note=note,
    )
