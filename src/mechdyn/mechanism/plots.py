"""Plots of mechanism results: output motion, inertia forces, driving torque, a frame sheet, the
transmission angles and the coupler curves."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Protocol, cast

import numpy as np

from mechdyn.plotting import dead_centre_marks, display_unit, legend, new_axes, overlaid
from mechdyn.units import convert

if TYPE_CHECKING:
    from mechdyn.mechanism.kinematics import KinematicsResult
    from mechdyn.mechanism.model import GearJoint, Mechanism

__all__ = [
    "CycleResult",
    "coupler_points",
    "plot_coupler_curves",
    "plot_frames",
    "plot_inertia_forces",
    "plot_joint_forces",
    "plot_output_motion",
    "plot_shaking_polar",
    "plot_tonnage",
    "plot_torque",
    "plot_trajectory",
    "plot_transmission_angle",
]


class CycleResult(Protocol):
    """What the figures here read of one design's cycle, a
    :class:`~mechdyn.mechanism.DynamicsResult` (arrays over the N crank angles)."""

    @property
    def mechanism(self) -> Mechanism:
        """The mechanism."""
        ...

    @property
    def kinematics(self) -> KinematicsResult:
        """Its motion over the cycle."""
        ...

    @property
    def angle(self) -> np.ndarray:
        """(N,) crank angle from the datum, rad."""
        ...

    @property
    def driving_torque(self) -> np.ndarray:
        """(N,) the torque the motor applies to the crank, N·m."""
        ...

    @property
    def inertia_force(self) -> np.ndarray:
        """(N, 2) the total inertia force −Σ m a_G, N."""
        ...

    @property
    def inertia_forces(self) -> np.ndarray:
        """(N, bodies, 2) each body's inertia force, N."""
        ...

    @property
    def shaking_force(self) -> np.ndarray:
        """(N, 2) the force on the frame, N."""
        ...

    @property
    def output_position(self) -> np.ndarray | None:
        """(N,) the output slide's position along its axis, m (None without a slide)."""
        ...

    @property
    def trace(self) -> tuple[str, ...]:
        """The drawing points whose paths are drawn."""
        ...

    @property
    def _columns(self) -> dict[str, np.ndarray]:
        """The per-angle table's columns, each name ending with its unit."""
        ...

    @property
    def _tonnage(self) -> tuple[dict[str, Any], dict[str, np.ndarray]] | None:
        """The tonnage figures and columns (with a press rating), else None."""
        ...

    def summary(self) -> dict[str, Any]:
        """The cycle's scalar figures, SI (angles in degrees)."""
        ...

    def joint_load(self, joint: str, body: str) -> np.ndarray:
        """(N, 3) the load ``joint`` puts on ``body``: force (N) and moment (N·m)."""
        ...


def _dead_centres(ax: Any, result: CycleResult) -> None:
    s = result.summary()
    if "bdc_deg" in s:
        dead_centre_marks(ax, {"BDC": s["bdc_deg"], "TDC": s["tdc_deg"]})
    elif "output_swing_deg" in s:  # a rocker's two limits
        dead_centre_marks(
            ax,
            {
                "rocker at its least angle": s["crank_angle_at_output_angle_min_deg"],
                "rocker at its greatest angle": s["crank_angle_at_output_angle_max_deg"],
            },
        )


def plot_output_motion(result: CycleResult, ax: Any = None) -> Any:
    """Displacement, velocity and acceleration of the output along its axis (a slide), or its angle,
    angular velocity and angular acceleration (a rocker), against crank angle.

    Parameters
    ----------
    result : DynamicsResult
        The cycle.
    ax : matplotlib.axes.Axes, optional
        Unused: the three panels make their own figure.
    """
    import matplotlib.pyplot as plt

    from mechdyn.mechanism.motion import output_rocker

    frame = result._columns
    _fig, axes = plt.subplots(3, 1, figsize=(7.5, 7.0), sharex=True, layout="constrained")
    rocker = output_rocker(result.mechanism) if result.output_position is None else None
    if rocker is not None:
        i = result.mechanism.body_index[rocker[0]]
        curves = [
            (frame["output_angle_deg"], f"angle of {rocker[0]} (deg)"),
            (frame["output_angular_velocity_rad_s"], "angular velocity (rad/s)"),
            (result.kinematics.qdd[:, 3 * i + 2], "angular acceleration (rad/s²)"),
        ]
    else:
        curves = [
            (convert(frame["output_position_m"], "m", "mm"), "displacement (mm)"),
            (frame["output_velocity_m_per_s"], "velocity (m/s)"),
            (frame["output_acceleration_m_per_s2"], "acceleration (m/s²)"),
        ]
    for a, (y, label) in zip(axes, curves, strict=True):
        a.plot(frame["angle_deg"], y)
        a.set_ylabel(label)
        a.grid(alpha=0.3)
        _dead_centres(a, result)
    axes[-1].set_xlabel("crank angle (deg)")
    axes[0].set_title(f"{result.mechanism.name}: output motion")
    return axes[0]


def plot_inertia_forces(result: CycleResult, ax: Any = None) -> Any:
    """Each body's inertia force along the output axis (or its magnitude) and the total, in the unit
    the largest reads best in (N, kN or MN: :func:`mechdyn.plotting.display_unit`)."""
    ax = new_axes(ax)
    deg = np.degrees(result.angle)
    j = result.mechanism.output_joint()
    u = np.array([np.cos(j.axis), np.sin(j.axis)]) if j is not None else None
    label = "along the output axis" if u is not None else "magnitude"
    total = result.inertia_force @ u if u is not None else np.linalg.norm(result.inertia_force, axis=1)
    # the unit the largest force reads best in, as the tables choose it
    unit, factor = display_unit(np.append(np.ravel(result.inertia_forces), total), "N")
    for i, b in enumerate(result.mechanism.bodies):
        f = result.inertia_forces[:, i, :]
        ax.plot(deg, (f @ u if u is not None else np.linalg.norm(f, axis=1)) * factor, lw=1, label=b.name)
    ax.plot(deg, total * factor, color="k", lw=2, label="total")
    _dead_centres(ax, result)
    ax.set_xlabel("crank angle (deg)")
    ax.set_ylabel(f"inertia force {label} ({unit})")
    ax.set_title(f"{result.mechanism.name}: inertia forces")
    ax.grid(alpha=0.3)
    legend(ax, fontsize="small")
    return ax


def plot_torque(result: CycleResult, ax: Any = None) -> Any:
    """Driving torque (the torque the motor applies to the crank), in N·m or kN·m by its size."""
    ax = new_axes(ax)
    deg = np.degrees(result.angle)
    unit, factor = display_unit(result.driving_torque, "N*m")
    T = result.driving_torque * factor
    ax.plot(deg, T, color="C3")
    ax.axhline(float(np.sqrt(np.mean(T**2))), color="0.5", ls="--", lw=1, label="RMS")
    _dead_centres(ax, result)
    ax.set_xlabel("crank angle (deg)")
    ax.set_ylabel(f"driving torque ({unit})")
    ax.set_title(f"{result.mechanism.name}: driving torque")
    ax.grid(alpha=0.3)
    legend(ax, fontsize="small")
    return ax


def _mm(value: Any) -> Any:
    return convert(value, "m", "mm")


def _pitch_circles(result: CycleResult) -> list[tuple[np.ndarray, float]]:
    """Both gears of every gear pair: (centre over the cycle (N, 2), mean pitch radius), m, from the
    rolling law at the drawing's centre distance."""
    m, k = result.mechanism, result.kinematics
    out = []
    grid = 2 * np.pi * np.arange(360) / 360
    N = k.angle.size
    for j in m.joints:
        law = m.gear_laws.get(j.name)
        if law is None:
            continue
        pivots = cast("GearJoint", j).points  # a joint with a rolling law is a gear pair
        carrier = getattr(j, "carrier", "ground")
        centres = [
            np.tile(np.asarray(m.points[p], dtype=float), (N, 1))
            if carrier == "ground"
            else k.point(carrier, p)[0]
            for p in pivots
        ]
        r1 = float(np.mean(law.contact_radius(grid)[0]))
        a = float(np.linalg.norm(np.asarray(m.points[pivots[1]]) - np.asarray(m.points[pivots[0]])))
        internal = bool(getattr(j, "internal", False))
        r2 = r1 + a if internal else a - r1
        out += [(centres[0], r1), (centres[1], r2)]
    return out


def linkage_tracks(result: CycleResult) -> dict[tuple[str, str], np.ndarray]:
    """Every body's points over the cycle: (body, point) → (N, 2) positions, mm.

    Parameters
    ----------
    result : DynamicsResult
        The cycle.
    """
    k = result.kinematics
    return {(b.name, p): _mm(k.point(b.name, p)[0]) for b in result.mechanism.bodies for p in b.points}


def linkage_view(
    result: CycleResult, tracks: dict[tuple[str, str], np.ndarray], *extra: np.ndarray
) -> tuple[np.ndarray, np.ndarray, float]:
    """The box that holds the whole motion: lower and upper corners and a margin, mm.

    Parameters
    ----------
    result : DynamicsResult
        The cycle (its drawing's points are inside too).
    tracks : dict
        :func:`linkage_tracks`, mm.
    *extra : ndarray
        Further (N, 2) paths to keep in view (coupler curves), mm.
    """
    points = _mm(np.array(list(result.mechanism.points.values()), dtype=float))
    allpts = np.concatenate([*tracks.values(), points, *extra])
    lo, hi = allpts.min(axis=0), allpts.max(axis=0)
    return lo, hi, 0.08 * float((hi - lo).max())


def draw_frame_marks(ax: Any, result: CycleResult, reach: float, zorder: float | None = None) -> None:
    """The frame's pivots (▲) and guides (dashed lines ``reach`` mm either side of their point), mm.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Axes in mm.
    result : DynamicsResult
        The cycle.
    reach : float
        Half the length of a guide's line, mm.
    zorder : float, optional
        Drawing order of the marks (matplotlib's default when None).
    """
    m = result.mechanism
    z = {} if zorder is None else {"zorder": zorder}
    for j in m.joints:
        if "ground" not in j.bodies or getattr(j, "point", None) is None:
            continue
        p = _mm(np.asarray(m.points[j.point]))
        if j.slides:  # a guide: its line on the frame
            axis = getattr(j, "axis", 0.0)
            u = np.array([np.cos(axis), np.sin(axis)]) * reach
            ax.plot(*np.stack([p - u, p + u]).T, "k--", lw=0.8, **z)
        else:
            ax.plot(p[0], p[1], "k^", ms=6, **z)


class LinkagePose:
    """The linkage drawn at one crank angle: each link in its colour (a line through its points, closed
    round a link of three or more), the gears' pitch circles dotted, lengths in mm. :meth:`show` moves
    the same artists to another angle: the frame sheet draws one pose per panel, the animation moves
    one pose round the cycle.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Axes in mm.
    result : DynamicsResult
        The cycle.
    tracks : dict, optional
        :func:`linkage_tracks` (mm), to share between poses.
    """

    def __init__(self, ax: Any, result: CycleResult, tracks: dict[tuple[str, str], np.ndarray] | None = None):
        self.tracks = linkage_tracks(result) if tracks is None else tracks
        self.links = [
            (b, ax.plot([], [], "-o", color=f"C{n % 10}", ms=3, lw=2, label=b.name)[0])
            for n, b in enumerate(result.mechanism.bodies)
        ]
        self.circles = [
            (_mm(centre), float(_mm(radius)), ax.plot([], [], ":", color="0.4", lw=0.9)[0])
            for centre, radius in _pitch_circles(result)
        ]
        self._theta = np.linspace(0, 2 * np.pi, 120)

    @property
    def artists(self) -> list[Any]:
        """The lines drawn: the links', then the pitch circles'."""
        return [line for _, line in self.links] + [line for *_, line in self.circles]

    def show(self, i: int) -> list[Any]:
        """Move the linkage to sample ``i`` of the cycle; returns the artists it changed.

        Parameters
        ----------
        i : int
            Index of the crank angle (count, into the result's arrays).
        """
        for b, line in self.links:
            pts = np.array([self.tracks[(b.name, p)][i] for p in b.points])
            closed = np.vstack([pts, pts[:1]]) if len(pts) > 2 else pts
            line.set_data(closed[:, 0], closed[:, 1])
        for centre, radius, line in self.circles:
            line.set_data(
                centre[i, 0] + radius * np.cos(self._theta), centre[i, 1] + radius * np.sin(self._theta)
            )
        return self.artists


def plot_frames(result: CycleResult, frames: int = 12, ax: Any = None) -> Any:
    """The mechanism drawn at equally spaced crank angles: each link in its colour (legend), the
    frame's pivots (▲) and guides (dashed), the gears' pitch circles (dotted), lengths in mm.

    Parameters
    ----------
    result : DynamicsResult
        The cycle.
    frames : int
        How many crank angles.
    ax : matplotlib.axes.Axes, optional
        Unused: the sheet makes its own figure.

    Returns
    -------
    matplotlib.axes.Axes
        The first panel (its ``figure`` holds them all).
    """
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection
    from matplotlib.ticker import FixedLocator, MaxNLocator, NullLocator

    m, k = result.mechanism, result.kinematics
    cols = 4
    rows = int(np.ceil(frames / cols))
    # fixed margins: the constrained layout of twelve panels cost more than drawing them (1.6 s against
    # 0.7 s to save the press's sheet)
    height = 2.8 * rows + 0.8
    fig, axes = plt.subplots(rows, cols, figsize=(3.2 * cols, height), squeeze=False)
    fig.subplots_adjust(
        left=0.07, right=0.99, top=1 - 0.55 / height, bottom=0.85 / height, wspace=0.12, hspace=0.32
    )
    idx = np.linspace(0, len(k.angle), frames, endpoint=False).astype(int)
    tracks = linkage_tracks(result)  # every body's points over the cycle, to fix the view (mm)
    lo, hi, pad = linkage_view(result, tracks)
    xlim, ylim = (lo[0] - pad, hi[0] + pad), (lo[1] - pad, hi[1] + pad)
    # every panel shows the same view, so one set of grid lines serves all; only the outer panels carry
    # ticks (the ticks of 24 axes were half the sheet's drawing time)
    xt = [t for t in MaxNLocator(5).tick_values(*xlim) if xlim[0] <= t <= xlim[1]]
    yt = [t for t in MaxNLocator(5).tick_values(*ylim) if ylim[0] <= t <= ylim[1]]
    grid = [[(x, ylim[0]), (x, ylim[1])] for x in xt] + [[(xlim[0], y), (xlim[1], y)] for y in yt]
    for n, (a, i) in enumerate(zip(np.ravel(axes), idx, strict=False)):
        LinkagePose(a, result, tracks).show(i)
        draw_frame_marks(a, result, float((hi - lo).max()))
        a.add_collection(LineCollection(grid, colors="0.5", linewidths=0.8, alpha=0.2, zorder=0))
        a.set_xlim(*xlim)
        a.set_ylim(*ylim)
        a.set_aspect("equal")
        a.set_title(f"crank at {np.degrees(k.angle[i]):.0f}°", fontsize="small")
        col = n % cols
        last_row = n + cols >= len(idx)
        a.xaxis.set_major_locator(FixedLocator(xt) if last_row else NullLocator())
        a.yaxis.set_major_locator(FixedLocator(yt) if col == 0 else NullLocator())
        a.tick_params(labelsize="x-small")
        if last_row:
            a.set_xlabel("x (mm)", fontsize="small")
        if col == 0:
            a.set_ylabel("y (mm)", fontsize="small")
    for a in np.ravel(axes)[len(idx) :]:
        a.axis("off")
    handles, labels = linkage_legend(result)
    fig.legend(
        handles, labels, loc="lower center", ncols=min(len(labels), 6), fontsize="small", frameon=False
    )
    fig.suptitle(f"{m.name}: the mechanism over one revolution")
    return np.ravel(axes)[0]


def linkage_legend(result: CycleResult) -> tuple[list[Any], list[str]]:
    """Legend entries of a drawn linkage: each link in its colour, the frame's pivot, the pitch circles.

    Parameters
    ----------
    result : DynamicsResult
        The cycle.
    """
    from matplotlib.lines import Line2D

    m = result.mechanism
    handles: list[Any] = [
        Line2D([], [], color=f"C{n % 10}", lw=2, marker="o", ms=3) for n in range(len(m.bodies))
    ]
    labels = [b.name for b in m.bodies]
    handles.append(Line2D([], [], color="k", marker="^", ls="none"))
    labels.append("frame pivot")
    if m.gear_laws:
        handles.append(Line2D([], [], color="0.4", ls=":"))
        labels.append("pitch circle (mean)")
    return handles, labels


def plot_joint_forces(result: CycleResult, joints: list[str] | None = None, ax: Any = None) -> Any:
    """Magnitude of each joint's force over the cycle (on the joint's second body), N or kN or MN;
    with gear pairs, their tooth forces too."""
    ax = new_axes(ax)
    deg = np.degrees(result.angle)
    m = result.mechanism
    forces = {
        j.name: np.linalg.norm(result.joint_load(j.name, j.bodies[1])[:, :2], axis=1)
        for j in m.joints
        if joints is None or j.name in joints
    }
    unit, factor = display_unit(np.concatenate([*forces.values(), [0.0]]), "N")
    for name, f in overlaid({k: f * factor for k, f in forces.items()}):  # equal forces drawn once
        ax.plot(deg, f, lw=1.2, label=name)
    teeth = bool(m.gear_laws)
    ax.set_xlabel("crank angle (deg)")
    ax.set_ylabel(f"{'joint and tooth force' if teeth else 'joint force'} ({unit})")
    ax.set_title(f"{m.name}: {'joint and tooth forces' if teeth else 'joint forces'}")
    ax.grid(alpha=0.3)
    legend(ax, fontsize="small", ncols=2)
    return ax


def plot_shaking_polar(result: CycleResult, ax: Any = None) -> Any:
    """The shaking force vector over the cycle: its tip traced in the (Fx, Fy) plane, N or kN."""
    ax = new_axes(ax, figsize=(6.0, 6.0))
    unit, factor = display_unit(result.shaking_force, "N")
    F = result.shaking_force * factor
    ax.plot(F[:, 0], F[:, 1], lw=1.5)
    ax.plot([0], [0], "k+", ms=10)
    # crank angles along the trace, each labelled point a dot; a label that would print over one
    # already placed (where the force lingers near zero) is left out
    reach = float(np.abs(F).max()) if F.size else 0.0
    placed: list[np.ndarray] = []
    for k in range(0, len(F), max(1, len(F) // 12)):
        if all(np.hypot(*(F[k] - q)) >= 0.08 * reach for q in placed):
            placed.append(F[k])
            ax.plot(*F[k], "o", color="C0", ms=3)
            ax.annotate(
                f"{np.degrees(result.angle[k]):.0f}°",
                F[k],
                (4, 4),
                textcoords="offset points",
                fontsize="x-small",
            )
    ax.set_xlabel(f"shaking force Fx ({unit})")
    ax.set_ylabel(f"shaking force Fy ({unit})")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_title(f"{result.mechanism.name}:\nshaking force on the frame", fontsize=11)
    ax.grid(alpha=0.3)
    return ax


def plot_trajectory(
    result: CycleResult, points: list[str], field_velocity: tuple[float, float] | None = None
) -> Any:
    """Paths of drawing points relative to the machine and, with the machine's velocity over the
    field, over the ground for two revolutions (m)."""
    import matplotlib.pyplot as plt

    k, m = result.kinematics, result.mechanism
    n = 2 if field_velocity is not None else 1
    fig, axes = plt.subplots(1, n, figsize=(6.0 * n, 5.0), layout="constrained", squeeze=False)
    T = float(k.time.max() - k.time.min()) * len(k.time) / max(len(k.time) - 1, 1)
    order = np.argsort(k.time)
    for p in points:
        body = next(b.name for b in m.bodies if p in b.points)
        xy = k.point(body, p)[0][order]
        mm = convert(xy, "m", "mm")
        axes[0, 0].plot(mm[:, 0], mm[:, 1], label=p)
        if field_velocity is not None:
            t = k.time[order] - k.time[order][0]
            v = np.asarray(field_velocity)
            path = np.concatenate([xy + np.outer(t + c * T, v) for c in range(2)])
            path = convert(path, "m", "mm")
            axes[0, 1].plot(path[:, 0], path[:, 1], label=p)
    axes[0, 0].set_title("relative to the machine")
    if field_velocity is not None:
        axes[0, 1].set_title(f"over the field at {np.hypot(*field_velocity):g} m/s")
    for a in axes.ravel():
        a.set_aspect("equal", adjustable="datalim")
        a.set_xlabel("x (mm)")
        a.set_ylabel("y (mm)")
        a.grid(alpha=0.3)
        legend(a, fontsize="small")
    fig.suptitle(f"{m.name}: paths")
    return axes[0, 0]


def plot_transmission_angle(result: CycleResult, ax: Any = None) -> Any:
    """Each dyad's transmission angle against crank angle, deg, its smallest marked, with the band
    below 40° shaded (where Norton, *Design of Machinery* §4.10, advises against running a linkage).

    Parameters
    ----------
    result : DynamicsResult
        The cycle.
    ax : matplotlib.axes.Axes, optional
        Axes to draw on.
    """
    from mechdyn.mechanism.motion import mechanism_dyads

    ax = new_axes(ax)
    deg = np.degrees(result.angle)
    summary = result.summary()
    dyads = {d.joint: d for d in mechanism_dyads(result.mechanism)}
    ax.axhspan(0.0, 40.0, color="C3", alpha=0.08, lw=0, label="below 40°")
    for n, (joint, mu) in enumerate(result.kinematics.transmission_angles.items()):
        fig = summary["dyads"][joint]
        low, at = fig["transmission_angle_min_deg"], fig["crank_angle_at_transmission_angle_min_deg"]
        ax.plot(deg, np.degrees(mu), color=f"C{n % 10}", lw=1.5, label=f"dyad {dyads[joint].label}")
        ax.plot([at], [low], "o", color=f"C{n % 10}", ms=4, clip_on=False)
        ax.annotate(
            f"{low:.1f}° at {at:.0f}°",
            (at, low),
            (4, -12),
            textcoords="offset points",
            fontsize="small",
            color=f"C{n % 10}",
        )
    _dead_centres(ax, result)
    ax.set_xlim(0.0, 360.0)
    ax.set_xticks(np.arange(0, 361, 45))
    ax.set_ylim(0.0, 95.0)
    ax.set_yticks(np.arange(0, 91, 15))
    ax.set_xlabel("crank angle (deg)")
    ax.set_ylabel("transmission angle (deg)")
    ax.set_title(f"{result.mechanism.name}: transmission angles")
    ax.grid(alpha=0.3)
    ax.legend(fontsize="small", loc="lower right")
    return ax


def coupler_points(result: CycleResult) -> dict[str, np.ndarray]:
    """The coupler curves a plot draws: label → (N, 2) path, m. The traced points of the model, or,
    with none traced, the centre of mass of every body in general plane motion (a coupler point).

    Parameters
    ----------
    result : DynamicsResult
        The cycle.
    """
    from mechdyn.mechanism.motion import coupler_bodies, point_motion

    k, m = result.kinematics, result.mechanism
    if result.trace:
        return {p: point_motion(k, p)[0] for p in result.trace}
    return {
        f"{b} (centre of mass)": k.q[:, 3 * m.body_index[b] : 3 * m.body_index[b] + 2]
        for b in coupler_bodies(m)
    }


def plot_coupler_curves(result: CycleResult, ax: Any = None) -> Any:
    """The coupler curves (see :func:`coupler_points`) over one revolution, in mm, over the linkage
    drawn in grey at crank angle 0, with crank angles marked along each curve.

    Parameters
    ----------
    result : DynamicsResult
        The cycle.
    ax : matplotlib.axes.Axes, optional
        Axes to draw on.
    """
    ax = new_axes(ax, figsize=(7.0, 6.0))
    k, m = result.kinematics, result.mechanism
    for b in m.bodies:  # the linkage at the first sample, for orientation
        pts = _mm(np.array([k.point(b.name, p)[0][0] for p in b.points]))
        closed = np.vstack([pts, pts[:1]]) if len(pts) > 2 else pts
        ax.plot(closed[:, 0], closed[:, 1], "-o", color="0.65", ms=3, lw=2, zorder=1)
    curves = {label: _mm(path) for label, path in coupler_points(result).items()}
    reach = max((float(np.ptp(c, axis=0).max()) for c in curves.values()), default=0.0)
    draw_frame_marks(ax, result, 0.3 * max(reach, 1.0), zorder=2)  # pivots (▲), guides (dashed)
    placed: list[np.ndarray] = []
    step = max(1, len(k.angle) // 12)
    for n, (label, c) in enumerate(curves.items()):
        closed = np.vstack([c, c[:1]])
        # each curve thinner and dashed differently from the last, so that one path shared by two
        # points (the transplanter's two forks, half a turn apart) shows both
        style = {"lw": max(2.4 - 0.7 * n, 1.0), "ls": ("-", "--", "-.", ":")[n % 4]}
        ax.plot(closed[:, 0], closed[:, 1], color=f"C{n % 10}", label=label, zorder=3, **style)
        for i in range(0, len(c), step):  # crank angles along the curve, none printed over another
            if all(np.hypot(*(c[i] - q)) >= 0.06 * reach for q in placed):
                placed.append(c[i])
                ax.plot(*c[i], "o", color=f"C{n % 10}", ms=3, zorder=4)
                ax.annotate(
                    f"{np.degrees(k.angle[i]):.0f}°",
                    c[i],
                    (4, 4),
                    textcoords="offset points",
                    fontsize="x-small",
                    in_layout=False,  # beside its point, inside the axes: nothing for the layout to do
                )
    ax.plot([], [], "-o", color="0.65", ms=3, lw=2, label=f"linkage at {np.degrees(k.angle[0]):.0f}°")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_title(f"{m.name}: coupler curves")
    ax.grid(alpha=0.3)
    legend(ax, fontsize="small")
    return ax


def plot_tonnage(result: CycleResult, ax: Any = None, length_unit: str = "mm") -> Any:
    """The tonnage curve: the force the rated crank torque can deliver against the distance before
    BDC on the working stroke (a logarithmic axis, from 1 mm before BDC), with the process force on
    the slide and the rated point over it (:mod:`mechdyn.mechanism.tonnage`).

    Parameters
    ----------
    result : DynamicsResult
        A cycle with a rated torque and a slide output.
    ax : matplotlib.axes.Axes, optional
        Axes to draw on.
    length_unit : str
        Display unit of the distance before BDC (any length unit).
    """
    ax = new_axes(ax)
    tonnage = result._tonnage
    if tonnage is None:
        raise ValueError("the tonnage curve needs a rated torque and a slide output")
    figures, cols = tonnage
    d = cols["distance_before_bdc_m"]
    cap = cols["tonnage_capacity_N"]
    working = np.isfinite(cap)
    order = np.argsort(d[working])
    x = convert(d[working][order], "m", length_unit)
    proc = cols["process_force_on_slide_N"][working][order]
    shown = [float(np.nanmin(cap[working]) if working.any() else 1.0)]
    shown += [float(np.nanmax(np.abs(proc)))] if np.isfinite(proc).any() else []
    if "rated_force_N" in figures:
        shown.append(figures["rated_force_N"])
    unit, factor = display_unit(max(shown), "N")
    ax.plot(x, cap[working][order] * factor, color="C0", lw=2, label="available force (rated torque)")
    if np.nanmax(np.abs(proc), initial=0.0) > 0:
        ax.plot(x, proc * factor, color="C3", lw=1.5, label="process force")
    if "rated_force_N" in figures:
        ax.axhline(figures["rated_force_N"] * factor, color="0.5", ls="--", lw=1, label="rated force")
        ax.plot(
            [convert(figures["rated_point_before_bdc_m"], "m", length_unit)],
            [figures["tonnage_at_rated_point_N"] * factor],
            "o",
            color="k",
            label="rated point",
        )
    ax.set_ylim(0.0, 2.5 * max(shown) * factor)
    ax.set_xscale("log")  # the curve's rise near BDC and the whole stroke on one axis
    from matplotlib.ticker import FuncFormatter

    ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _pos: f"{v:g}"))  # 1, 10, 100 mm, not 10⁰…
    ax.set_xlabel(f"distance before BDC ({length_unit}, logarithmic)")
    ax.set_ylabel(f"slide force ({unit})")
    ax.set_title(f"{result.mechanism.name}: tonnage")
    ax.grid(alpha=0.3)
    legend(ax, fontsize="small")
    return ax
