"""The linkage animated over one crank cycle, as every mechanism tool shows it: the links drawn as in
the frame sheet (:class:`~mechdyn.mechanism.plots.LinkagePose`), the frame's pivots, the coupler curves
traced as the crank turns, the crank angle; equal axes in mm, the view fixed round the whole motion.

Written as an animated GIF with Pillow (matplotlib's ``PillowWriter``) or, where ffmpeg is installed,
as an MP4. Each frame moves the same artists (no re-plotting); a GIF is written by blitting: the
still parts (axes, pivots, legend) drawn once, then only the moving artists on a copy of them.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from mechdyn.errors import MechdynError
from mechdyn.units import convert

if TYPE_CHECKING:
    from mechdyn.mechanism.plots import CycleResult

__all__ = ["animate", "check_animation_path"]

FRAMES = 72
"""Frames of an animation by default: one per 5° of crank angle."""

_SUFFIXES = (".gif", ".mp4")


def check_animation_path(path: str | Path) -> Path:
    """The file an animation can be written to: a ``.gif``, or an ``.mp4`` where ffmpeg is installed.

    Parameters
    ----------
    path : str or Path
        The file to write.

    Raises
    ------
    MechdynError
        For another suffix, or an ``.mp4`` without ffmpeg, saying what to do instead.
    """
    p = Path(path)
    suffix = p.suffix.lower()
    if suffix not in _SUFFIXES:
        raise MechdynError(
            f"cannot write an animation to {str(path)!r}: give a file ending .gif (or .mp4, with ffmpeg)"
        )
    if suffix == ".mp4":
        from matplotlib import animation

        if not animation.writers.is_available("ffmpeg"):
            raise MechdynError(
                f"cannot write {str(path)!r}: an MP4 needs ffmpeg, which is not installed; write a .gif "
                "instead, or install ffmpeg (e.g. `apt install ffmpeg`, `conda install ffmpeg`) and run again"
            )
    return p


def _cycle_order(result: CycleResult) -> np.ndarray:
    """The samples in the order the crank passes them, from the first (the angle datum): the arrays
    are sorted by crank angle counted counter-clockwise, and a crank turning clockwise passes them
    backwards."""
    order = np.argsort(result.kinematics.time, kind="stable")
    return np.roll(order, -int(np.flatnonzero(order == 0)[0]))


def animate(
    result: CycleResult,
    path: str | Path | None = None,
    frames: int = FRAMES,
    *,
    period: float = 4.8,
    dpi: int = 80,
) -> Any:
    """The linkage animated over one crank cycle, and written to ``path`` when one is given.

    Each frame draws the links as the frame sheet does (``frames.png``), the frame's pivots (▲) and
    guides (dashed), the gears' pitch circles, the coupler curves
    (:func:`~mechdyn.mechanism.plots.coupler_points`: the traced points, else the centres of mass of
    the coupler links) traced up to the current angle, and the crank angle; equal axes in mm, their
    limits fixed round the whole motion. The frames are equally spaced crank angles in the order the
    crank turns, starting at the angle datum.

    Parameters
    ----------
    result : DynamicsResult
        The cycle (:func:`~mechdyn.mechanism.inverse_dynamics`).
    path : str or Path, optional
        A ``.gif`` (written with Pillow) or an ``.mp4`` (needs ffmpeg); its folder is made if missing.
    frames : int
        Number of frames (count), at most one per sampled crank angle (more are cut to that).
    period : float
        Playing time of one crank cycle, s (not the machine's: the press's 4 s and the four-bar's
        0.5 s play alike).
    dpi : int
        Resolution, dots per inch (the figure is 5 inches wide).

    Returns
    -------
    matplotlib.animation.FuncAnimation
        Its artists show the first frame; ``to_jshtml()`` shows it in a notebook. With a ``path`` the
        figure is closed once written.

    Raises
    ------
    MechdynError
        For a path that is not a ``.gif`` or ``.mp4``, or an ``.mp4`` without ffmpeg (checked before
        anything is drawn).
    """
    target = None if path is None else check_animation_path(path)
    if int(frames) < 1:
        raise MechdynError(f"an animation needs at least one frame, not {frames}")
    import matplotlib.pyplot as plt
    from matplotlib.animation import FuncAnimation
    from matplotlib.layout_engine import ConstrainedLayoutEngine
    from matplotlib.lines import Line2D

    from mechdyn.mechanism.plots import (
        LinkagePose,
        coupler_points,
        draw_frame_marks,
        linkage_legend,
        linkage_tracks,
        linkage_view,
    )
    from mechdyn.plotting import keep_layout, plain_text

    m, k = result.mechanism, result.kinematics
    order = _cycle_order(result)
    N = order.size
    n = min(int(frames), N)
    shown = np.linspace(0, N, n, endpoint=False).astype(int)  # positions in the crank's order
    tracks = linkage_tracks(result)
    curves = {label: convert(c, "m", "mm")[order] for label, c in coupler_points(result).items()}
    lo, hi, pad = linkage_view(result, tracks, *curves.values())
    span = hi - lo + 2 * pad
    width = 5.0  # inches; the height follows the motion's shape, room kept for the title and legend
    fig, ax = plt.subplots(
        figsize=(width, float(np.clip(0.8 * width * span[1] / span[0] + 1.5, 3.0, 6.5))),
        dpi=dpi,
        layout=ConstrainedLayoutEngine(w_pad=0.08, h_pad=0.08),  # the default pads: 3 pixels at 80 dpi
    )
    draw_frame_marks(ax, result, float((hi - lo).max()))
    traced = [
        (c, ax.plot([], [], "-", color=f"C{(len(m.bodies) + j) % 10}", lw=1.2, zorder=1)[0])
        for j, c in enumerate(curves.values())
    ]
    dots = [ax.plot([], [], "o", color=line.get_color(), ms=3, zorder=3)[0] for _, line in traced]
    pose = LinkagePose(ax, result, tracks)
    label = ax.text(
        0.02,
        0.98,
        "",
        transform=ax.transAxes,
        va="top",
        fontsize="small",
        bbox={"fc": "white", "ec": "0.8", "alpha": 0.85, "pad": 2},
    )
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)", fontsize="small")
    ax.set_ylabel("y (mm)", fontsize="small")
    ax.tick_params(labelsize="x-small")
    ax.grid(alpha=0.2)
    ax.set_title(m.name, fontsize="medium")
    handles, labels = linkage_legend(result)
    for name, (_, line) in zip(curves, traced, strict=True):
        handles.append(Line2D([], [], color=line.get_color(), lw=1.2))
        labels.append(f"path of {name}")
    fig.legend(handles, labels, loc="outside lower center", ncols=min(len(labels), 3), fontsize="x-small")
    plain_text(fig)  # a "$" in a body's name is a dollar sign
    # the layout once (its second pass places the title clear of the edge), then kept: every frame
    # draws the same box
    for _ in range(2):
        fig.draw_without_rendering()
    keep_layout(fig)

    digits = 0 if 360.0 / n >= 1.0 else 1  # frames less than a degree apart show tenths

    def frame(f: int) -> list[Any]:
        at = shown[f]
        i = int(order[at])
        changed = pose.show(i)
        for (c, line), dot in zip(traced, dots, strict=True):
            line.set_data(c[: at + 1, 0], c[: at + 1, 1])
            dot.set_data(c[at : at + 1, 0], c[at : at + 1, 1])
        label.set_text(f"crank angle {round(float(np.degrees(k.angle[i])), digits) % 360:.{digits}f}°")
        return [*changed, *(line for _, line in traced), *dots, label]

    artists = frame(0)
    anim = FuncAnimation(
        fig,
        frame,
        frames=n,
        init_func=lambda: frame(0),
        interval=float(convert(period / n, "s", "ms")),
        blit=True,
    )
    if target is not None:
        _write(anim, fig, frame, n, artists, target, period / n)
        plt.close(fig)
        frame(0)  # the artists show the first frame again
    return anim


def _write(anim: Any, fig: Any, frame: Any, n: int, artists: list[Any], path: Path, step: float) -> None:
    """Write the frames: a GIF by blitting (the still parts drawn once, then only the moving artists
    on a copy of them) and one palette for every frame; an MP4 through ffmpeg, frame by frame.
    ``step``: time from one frame to the next, s."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    path.parent.mkdir(parents=True, exist_ok=True)
    if path.suffix.lower() == ".mp4" or not isinstance(fig.canvas, FigureCanvasAgg):
        from matplotlib.animation import FFMpegWriter, PillowWriter

        fps = max(1, round(1.0 / step))
        writer = FFMpegWriter(fps=fps) if path.suffix.lower() == ".mp4" else PillowWriter(fps=fps)
        anim.save(str(path), writer=writer, dpi=fig.dpi)
        return
    from PIL import Image

    canvas = fig.canvas
    for a in artists:
        a.set_animated(True)
    canvas.draw()  # everything that stays
    still = canvas.copy_from_bbox(fig.bbox)
    images = []
    for f in range(n):
        canvas.restore_region(still)
        for a in frame(f):
            fig.draw_artist(a)
        images.append(Image.fromarray(np.asarray(canvas.buffer_rgba())[..., :3].copy()))
    for a in artists:
        a.set_animated(False)
    # one palette for all frames, from the first and the last (every path drawn): each frame is then
    # mapped onto it, far quicker than a palette of its own, and the GIF stores what changed
    both = Image.fromarray(np.vstack([np.asarray(images[0]), np.asarray(images[-1])]))
    palette = both.quantize(colors=128, method=Image.Quantize.MEDIANCUT)
    frames = [im.quantize(palette=palette, dither=Image.Dither.NONE) for im in images]
    frames[0].save(
        path,
        save_all=True,
        append_images=frames[1:],
        duration=round(float(convert(step, "s", "ms"))),
        loop=0,
        disposal=1,
    )
    anim._draw_was_started = True  # written: no warning that it was never drawn
