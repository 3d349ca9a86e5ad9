"""Shared plotting helpers: matplotlib is imported lazily and runs headless (Agg) for files."""

from __future__ import annotations

from pathlib import Path
from typing import Any

__all__ = ["new_axes", "save_figure"]


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
    fig.savefig(p, dpi=dpi)
    plt.close(fig)
    return p
