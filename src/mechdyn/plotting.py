"""Shared plotting helpers: matplotlib is imported lazily and runs headless (Agg) for files."""

from __future__ import annotations

from pathlib import Path
from typing import Any

__all__ = [
    "dead_centre_marks",
    "display_unit",
    "fit_titles",
    "keep_layout",
    "legend",
    "new_axes",
    "overlaid",
    "plain_text",
    "save_figure",
]


def display_unit(values: Any, unit: str) -> tuple[str, float]:
    """The display unit for values of one quantity and the factor from SI to it: the unit its largest
    magnitude reads best in, by the rule the tables use (:func:`mechdyn.units.readable_unit`: a force
    in kN from 10⁴ N, in MN from 10⁷ N), so that a plot and its table agree.

    Parameters
    ----------
    values : array_like
        The values, in ``unit``.
    unit : str
        Their SI unit as pint reads it (``"N"``, ``"N*m"``, ``"N/m"``, ``"m"``; others are shown as
        they are).

    Returns
    -------
    (str, float)
        The unit as a label shows it (``"kN·m"``) and the factor to multiply the values by.
    """
    import numpy as np

    from mechdyn.units import SHOWN_UNITS, convert, readable_unit

    peak = float(np.nanmax(np.abs(values))) if np.size(values) else 0.0
    display, shown = readable_unit(peak, SHOWN_UNITS.get(unit, unit))
    if shown == SHOWN_UNITS.get(unit, unit):
        return shown, 1.0
    return shown, float(convert(1.0, unit, display))


OVERLAP = 5e-3
"""Curves closer than this fraction of the largest value everywhere would hide one another."""


def overlaid(curves: dict[str, Any]) -> list[tuple[str, Any]]:
    """Curves to draw, those that would hide one another drawn once: a machine's symmetric joints or
    mounts carry equal forces, and the second line would cover the first. The label names them all,
    ``"front left = rear left"`` where equal to round-off, ``"A ≈ B"`` where within :data:`OVERLAP`
    of the largest value.

    Parameters
    ----------
    curves : dict of str to ndarray
        Label → values over one abscissa, all in the unit the plot shows them in.

    Returns
    -------
    list of (str, ndarray)
        One entry per distinct curve, in the order of the first of each group.
    """
    import numpy as np

    arrays = {k: np.asarray(v, dtype=float) for k, v in curves.items()}
    scale = max((float(np.nanmax(np.abs(a))) for a in arrays.values() if a.size), default=0.0)
    groups: list[dict[str, Any]] = []  # names, the first curve, whether all are equal to round-off
    for name, a in arrays.items():
        for g in groups:
            gap = float(np.nanmax(np.abs(g["curve"] - a))) if g["curve"].shape == a.shape else np.inf
            if gap <= OVERLAP * scale:
                g["names"].append(name)
                g["exact"] = g["exact"] and gap <= 1e-12 * scale
                break
        else:
            groups.append({"names": [name], "curve": a, "exact": True})
    return [((" = " if g["exact"] else " ≈ ").join(g["names"]), g["curve"]) for g in groups]


def plain_text(fig: Any) -> None:
    """Show every text of a figure as written: a ``$`` in a study's, a parameter's or a body's name is
    a dollar sign, never the start of mathtext (which would draw it as a formula, or fail to draw).
    mechdyn writes no mathtext of its own.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure, about to be drawn.
    """
    for t in _named_texts(fig):
        t.set_parse_math(False)


def _named_texts(artist: Any) -> Any:
    """Every text of an artist that can carry a name: all but the tick labels a number formatter
    writes (a log axis writes 10⁻³ as mathtext, and asking an axis for those labels makes its ticks,
    which is much of a figure's cost); labels that name things (categories, a fixed list, a function's
    words) are worked out here, as the draw will."""
    from matplotlib.axis import Axis
    from matplotlib.text import Text
    from matplotlib.ticker import LogFormatter, NullFormatter, ScalarFormatter

    for child in artist.get_children():
        if isinstance(child, Axis):
            yield child.label
            for which in ("major", "minor"):
                formatter = child.get_major_formatter() if which == "major" else child.get_minor_formatter()
                if not isinstance(formatter, ScalarFormatter | LogFormatter | NullFormatter):
                    child.get_ticklabels(which=which)  # labels them as the draw will
                    ticks = child.majorTicks if which == "major" else child.minorTicks
                    yield from (label for t in ticks for label in (t.label1, t.label2))
        elif isinstance(child, Text):
            yield child
        else:
            yield from _named_texts(child)


def _clear(box: Any, width: float, margin: float) -> bool:
    """Whether a text's box lies within the figure's width, ``margin`` from each edge (pixels)."""
    return bool(box.x0 >= margin and box.x1 <= width - margin)


def fit_titles(fig: Any) -> None:
    """Shrink, then wrap, every title that reaches past the figure's edge, so that none is clipped.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure, about to be saved.
    """
    import textwrap

    renderer = fig.canvas.get_renderer()
    width = fig.bbox.width
    texts = [a.title for a in fig.axes] + [t for a in fig.axes for t in (a._left_title, a._right_title)]
    if fig._suptitle is not None:
        texts.append(fig._suptitle)
    texts = [t for t in texts if t.get_text()]
    # the layout moves the axes by their margins only: a title that keeps a tenth of the figure's
    # width from both edges where the axes stand before it cannot be clipped after it, and the
    # figure is not drawn here (a draw with its layout is most of what a plot costs)
    # (without a layout engine nothing moves: the places before the draw are the places after it)
    margin = 0.0 if fig.get_layout_engine() is None else 0.1 * width
    if all(_clear(t.get_window_extent(renderer), width, margin) for t in texts):
        return
    fig.draw_without_rendering()  # the layout and every artist placed, nothing rasterised
    # the figure is laid out once, for the titles' places; a title's extent then follows its own text
    # and size without drawing the figure again (once per title, that was most of a run with --plots)
    for t in texts:
        for _ in range(4):
            if _clear(t.get_window_extent(renderer), width, 0.0):
                break
            if t.get_fontsize() > 8:
                t.set_fontsize(t.get_fontsize() - 1)
            else:
                text = t.get_text().replace("\n", " ")
                t.set_text(textwrap.fill(text, max(20, len(text) * 2 // 3)))


def dead_centre_marks(ax: Any, angles_deg: dict[str, float]) -> None:
    """Vertical lines at the dead centres, labelled inside the axes at the top (never over a title).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Axes with the crank angle, deg, on x.
    angles_deg : dict of str to float
        Label → crank angle, deg (e.g. ``{"BDC": 0.0, "TDC": 128.9}``).
    """
    for label, angle in angles_deg.items():
        ax.axvline(angle, color="0.5", ls=":", lw=1)
        ax.annotate(
            label,
            (angle, 0.98),
            xycoords=("data", "axes fraction"),
            xytext=(3, 0),
            textcoords="offset points",
            fontsize="small",
            va="top",
            color="0.3",
            bbox={"fc": "white", "ec": "none", "alpha": 0.8, "pad": 1},
        )


CORNERS = ("upper right", "upper left", "lower right", "lower left")
"""Where a legend may go, in the order it is preferred when the corners are equally clear."""


def legend(ax: Any, **kwargs: Any) -> Any:
    """The axes' legend in the corner its curves leave clearest, chosen here and given to matplotlib.

    Matplotlib's ``loc="best"`` searches every candidate place against every drawn point, and on a
    loaded machine with long curves it takes seconds and says so in a warning; this counts a
    subsample of the drawn points (at most 2000 per artist; of a patch, a bar or a band, the points of
    a 50 × 50 lattice over the axes that it covers) in each corner's 40 % × 40 % box, in axes
    coordinates, and takes the emptiest (the first of :data:`CORNERS` on a tie).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The axes with labelled artists.
    **kwargs
        Passed to ``ax.legend``; a ``loc`` given is kept.

    Returns
    -------
    matplotlib.legend.Legend
    """
    import numpy as np

    if "loc" not in kwargs:
        to_axes = ax.transData + ax.transAxes.inverted()
        points = []
        for line in ax.get_lines():
            xy = np.column_stack(
                [np.asarray(line.get_xdata(), dtype=float), np.asarray(line.get_ydata(), dtype=float)]
            )
            points.append(xy[:: max(1, len(xy) // 2000)])
        for coll in ax.collections:
            xy = np.asarray(coll.get_offsets(), dtype=float).reshape(-1, 2)
            points.append(xy[:: max(1, len(xy) // 2000)])
        u_parts = [to_axes.transform(xy) for xy in points if len(xy)]
        lattice = (np.arange(50) + 0.5) / 50
        for patch in ax.patches:  # bars and bands: the points of a 50 × 50 lattice of the axes they cover
            (x0, x1), (y0, y1) = np.sort(
                ax.transAxes.inverted().transform(patch.get_window_extent().get_points()).T, axis=1
            )
            gx, gy = np.meshgrid(
                lattice[(lattice >= x0) & (lattice <= x1)], lattice[(lattice >= y0) & (lattice <= y1)]
            )
            u_parts.append(np.column_stack([gx.ravel(), gy.ravel()]))
        counts = dict.fromkeys(CORNERS, 0)
        if u_parts:
            u = np.concatenate(u_parts)
            u = u[np.isfinite(u).all(axis=1)]
            if len(u):
                for corner in CORNERS:
                    right, upper = "right" in corner, "upper" in corner
                    inx = u[:, 0] > 0.6 if right else u[:, 0] < 0.4
                    iny = u[:, 1] > 0.6 if upper else u[:, 1] < 0.4
                    counts[corner] = int(np.count_nonzero(inx & iny))
        kwargs["loc"] = min(CORNERS, key=lambda c: counts[c])
    return ax.legend(**kwargs)


def new_axes(ax: Any = None, *, figsize: tuple[float, float] = (7.0, 4.5)) -> Any:
    """Return ``ax`` or the axes of a new figure.

    Parameters
    ----------
    ax : matplotlib.axes.Axes, optional
        Axes to draw on.
    figsize : (float, float)
        Size of a new figure, inches.
    """
    if ax is not None:
        return ax
    import matplotlib.pyplot as plt  # falls back to the headless Agg backend without a display

    _, ax = plt.subplots(figsize=figsize, layout="constrained")
    return ax


def keep_layout(fig: Any) -> None:
    """Keep the axes where the figure's layout engine has put them, and remove the engine: with one
    left (even matplotlib's ``"none"``, a placeholder), ``savefig`` draws the whole figure once more,
    without rendering, before it draws it into the file (and a writer of animations saves each frame).

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        A figure laid out already (its engine executed, or drawn once).
    """
    import matplotlib as mpl

    # no engine, whatever the user's matplotlib settings would put in its place
    with mpl.rc_context({"figure.autolayout": False, "figure.constrained_layout.use": False}):
        fig.set_layout_engine(None)


def save_figure(ax: Any, path: str | Path, *, dpi: int = 130) -> Path:
    """Save the figure of ``ax`` to ``path`` (PNG/SVG by suffix), close it and return the path.

    Parameters
    ----------
    ax : matplotlib.axes.Axes or Figure
        What to save.
    path : str or Path
        The file; its folder is made if missing.
    dpi : int
        Resolution of a PNG, dots per inch.
    """
    import matplotlib.pyplot as plt

    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    fig = ax.figure if hasattr(ax, "figure") else ax
    fig.set_dpi(dpi)  # the layout and the titles' fit worked out at the resolution saved
    plain_text(fig)
    fit_titles(fig)
    engine = fig.get_layout_engine()
    if engine is not None:  # once, here: savefig would first draw the whole figure only to run it
        engine.execute(fig)
        keep_layout(fig)
    # zlib's fastest level: a tenth larger than its default and a fifth of the drawing time less
    png = {"pil_kwargs": {"compress_level": 1}} if p.suffix.lower() == ".png" else {}
    fig.savefig(p, dpi=dpi, **png)
    plt.close(fig)
    return p
