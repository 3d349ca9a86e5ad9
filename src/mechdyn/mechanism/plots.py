"""Plots of mechanism results: output motion, inertia forces, driving torque, a frame sheet."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from mechdyn.plotting import new_axes
from mechdyn.units import convert

if TYPE_CHECKING:
    from mechdyn.mechanism.dynamics import DynamicsResult

__all__ = [
    "plot_frames",
    "plot_inertia_forces",
    "plot_joint_forces",
    "plot_output_motion",
    "plot_shaking_polar",
    "plot_torque",
    "plot_trajectory",
]


def _dead_centres(ax: Any, result: DynamicsResult) -> None:
    s = result.summary()
    if "bdc_deg" in s:
        for key, label in (("bdc_deg", "BDC"), ("tdc_deg", "TDC")):
            ax.axvline(s[key], color="0.5", ls=":", lw=1)
            ax.annotate(
                label, (s[key], 1.0), xycoords=("data", "axes fraction"), fontsize="small", va="bottom"
            )


def plot_output_motion(result: DynamicsResult, ax: Any = None) -> Any:
    """Displacement, velocity and acceleration of the output along its axis, against crank angle."""
    import matplotlib.pyplot as plt

    frame = result.to_frame()
    _fig, axes = plt.subplots(3, 1, figsize=(7.5, 7.0), sharex=True, layout="constrained")
    for a, col, label in zip(
        axes,
        ("output_position_m", "output_velocity_m_per_s", "output_acceleration_m_per_s2"),
        ("displacement (mm)", "velocity (m/s)", "acceleration (m/s²)"),
        strict=True,
    ):
        y = frame[col].to_numpy()
        y = convert(y, "m", "mm") if col == "output_position_m" else y
        a.plot(frame["angle_deg"], y)
        a.set_ylabel(label)
        a.grid(alpha=0.3)
        _dead_centres(a, result)
    axes[-1].set_xlabel("crank angle (deg)")
    axes[0].set_title(f"{result.mechanism.name}: output motion")
    return axes[0]


def plot_inertia_forces(result: DynamicsResult, ax: Any = None) -> Any:
    """Each body's inertia force along the output axis (or its magnitude) and the total, kN."""
    ax = new_axes(ax)
    deg = np.degrees(result.angle)
    j = result.mechanism.output_joint()
    u = np.array([np.cos(j.axis), np.sin(j.axis)]) if j is not None else None
    label = "along the output axis" if u is not None else "magnitude"
    total = result.inertia_force @ u if u is not None else np.linalg.norm(result.inertia_force, axis=1)
    unit = "kN" if np.abs(result.inertia_forces).max() >= 1e3 else "N"
    scale = 1.0 / convert(1.0, "N", unit)
    for i, b in enumerate(result.mechanism.bodies):
        f = result.inertia_forces[:, i, :]
        ax.plot(deg, (f @ u if u is not None else np.linalg.norm(f, axis=1)) / scale, lw=1, label=b.name)
    ax.plot(deg, total / scale, color="k", lw=2, label="total")
    _dead_centres(ax, result)
    ax.set_xlabel("crank angle (deg)")
    ax.set_ylabel(f"inertia force {label} ({unit})")
    ax.set_title(f"{result.mechanism.name}: inertia forces")
    ax.grid(alpha=0.3)
    ax.legend(fontsize="small")
    return ax


def plot_torque(result: DynamicsResult, ax: Any = None) -> Any:
    """Driving torque (the torque the motor applies to the crank), N·m."""
    ax = new_axes(ax)
    deg = np.degrees(result.angle)
    T = result.driving_torque
    ax.plot(deg, T, color="C3")
    ax.axhline(float(np.sqrt(np.mean(T**2))), color="0.5", ls="--", lw=1, label="RMS")
    _dead_centres(ax, result)
    ax.set_xlabel("crank angle (deg)")
    ax.set_ylabel("driving torque (N·m)")
    ax.set_title(f"{result.mechanism.name}: driving torque")
    ax.grid(alpha=0.3)
    ax.legend(fontsize="small")
    return ax


def plot_frames(result: DynamicsResult, frames: int = 12, ax: Any = None) -> Any:
    """An animation frame sheet: the mechanism drawn at equally spaced crank angles."""
    import matplotlib.pyplot as plt

    m, k = result.mechanism, result.kinematics
    cols = 4
    rows = int(np.ceil(frames / cols))
    fig, axes = plt.subplots(rows, cols, figsize=(3.0 * cols, 2.6 * rows), layout="constrained")
    idx = np.linspace(0, len(k.angle), frames, endpoint=False).astype(int)
    # every body's points over the cycle, to fix the view
    tracks = {(b.name, p): k.point(b.name, p)[0] for b in m.bodies for p in b.points}
    allpts = np.concatenate([*list(tracks.values()), np.array(list(m.points.values()))])
    lo, hi = allpts.min(axis=0), allpts.max(axis=0)
    pad = 0.08 * (hi - lo).max()
    for a, i in zip(np.ravel(axes), idx, strict=False):
        for n, b in enumerate(m.bodies):
            pts = np.array([tracks[(b.name, p)][i] for p in b.points])
            closed = np.vstack([pts, pts[:1]]) if len(pts) > 2 else pts
            a.plot(closed[:, 0], closed[:, 1], "-o", color=f"C{n}", ms=3, lw=2)
        for j in m.joints:
            if "ground" not in j.bodies:
                continue
            p = np.asarray(m.points[j.point])
            if hasattr(j, "axis"):  # a guide: its line on the frame
                u = np.array([np.cos(j.axis), np.sin(j.axis)]) * (hi - lo).max()
                a.plot(*np.stack([p - u, p + u]).T, "k--", lw=0.8)
            else:
                a.plot(p[0], p[1], "k^", ms=6)
        a.set_xlim(lo[0] - pad, hi[0] + pad)
        a.set_ylim(lo[1] - pad, hi[1] + pad)
        a.set_aspect("equal")
        a.set_title(f"{np.degrees(k.angle[i]):.0f}°", fontsize="small")
        a.set_xticks([])
        a.set_yticks([])
    for a in np.ravel(axes)[len(idx) :]:
        a.axis("off")
    fig.suptitle(f"{m.name}: frames over one revolution")
    return np.ravel(axes)[0]


def plot_joint_forces(result: DynamicsResult, joints: list[str] | None = None, ax: Any = None) -> Any:
    """Magnitude of each joint's force over the cycle (on the joint's second body), N."""
    ax = new_axes(ax)
    deg = np.degrees(result.angle)
    m = result.mechanism
    for j in m.joints:
        if joints is not None and j.name not in joints:
            continue
        f = np.linalg.norm(result.joint_load(j.name, j.bodies[1])[:, :2], axis=1)
        ax.plot(deg, f, lw=1.2, label=j.name)
    ax.set_xlabel("crank angle (deg)")
    ax.set_ylabel("joint force (N)")
    ax.set_title(f"{m.name}: joint and tooth forces")
    ax.grid(alpha=0.3)
    ax.legend(fontsize="small", ncols=2)
    return ax


def plot_shaking_polar(result: DynamicsResult, ax: Any = None) -> Any:
    """The shaking force vector over the cycle: its tip traced in the (Fx, Fy) plane, N."""
    ax = new_axes(ax, figsize=(5.5, 5.5))
    F = result.shaking_force
    ax.plot(F[:, 0], F[:, 1], lw=1.5)
    ax.plot([0], [0], "k+", ms=10)
    for k in range(0, len(F), max(1, len(F) // 12)):
        ax.annotate(f"{np.degrees(result.angle[k]):.0f}°", F[k], fontsize="x-small")
    ax.set_xlabel("shaking force Fx (N)")
    ax.set_ylabel("shaking force Fy (N)")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_title(f"{result.mechanism.name}: shaking force (on the frame)")
    ax.grid(alpha=0.3)
    return ax


def plot_trajectory(
    result: DynamicsResult, points: list[str], field_velocity: tuple[float, float] | None = None
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
        a.legend(fontsize="small")
    fig.suptitle(f"{m.name}: paths")
    return axes[0, 0]
