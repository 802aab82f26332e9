"""The one plotting style of the book.

Colours are the Okabe–Ito palette (distinguishable with the common colour-vision deficiencies),
cycled together with line styles and markers so curves stay apart in greyscale too. Every
registry ``plot`` builds its figure with :func:`subplots` and hands it to :func:`finish`, which
refuses a figure with an unlabelled axis.

The backend is left alone: notebooks keep their inline backend, and the command line selects
Agg itself (``fusioncenter.cli``).
"""

from __future__ import annotations

from contextlib import contextmanager

import matplotlib
import matplotlib.pyplot as plt
from cycler import cycler

__all__ = ["OKABE_ITO", "MARKERS", "RC", "style", "use_style", "subplots", "finish", "errorband"]

OKABE_ITO = [
    "#0072B2",  # blue
    "#D55E00",  # vermillion
    "#009E73",  # bluish green
    "#CC79A7",  # reddish purple
    "#E69F00",  # orange
    "#56B4E9",  # sky blue
    "#F0E442",  # yellow
    "#000000",  # black
]
_LINESTYLES = ["-", "--", "-.", ":", "-", "--", "-.", ":"]
#: Markers in the same order, for plots that mark points (``marker=MARKERS[i]``).
MARKERS = ["o", "s", "^", "D", "v", "P", "X", "*"]

RC = {
    "axes.prop_cycle": cycler(color=OKABE_ITO) + cycler(linestyle=_LINESTYLES),
    "lines.markersize": 4,
    "lines.linewidth": 1.6,
    "figure.figsize": (6.4, 4.0),
    "figure.dpi": 100,
    "savefig.dpi": 150,
    "savefig.bbox": "tight",
    "font.size": 10,
    "axes.titlesize": 10,
    "axes.labelsize": 10,
    "legend.fontsize": 9,
    "legend.frameon": False,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "mathtext.fontset": "cm",
}


@contextmanager
def style():
    """Context manager applying the book's style."""
    with matplotlib.rc_context(RC):
        yield


def use_style() -> None:
    """Make the book's style the default for every later figure (what the chapters do)."""
    matplotlib.rcParams.update(RC)


def subplots(nrows: int = 1, ncols: int = 1, **kwargs):
    """``plt.subplots`` in the book's style (figure size scales with the grid)."""
    use_style()
    w, h = RC["figure.figsize"]
    kwargs.setdefault("figsize", (w * (0.75 * ncols + 0.25), h * (0.8 * nrows + 0.2)))
    kwargs.setdefault("layout", "constrained")
    return plt.subplots(nrows, ncols, **kwargs)


def errorband(ax, x, mean, stderr, *, z: float = 1.96, label: str | None = None, **kwargs):
    """A curve with a shaded ``mean -/+ z * stderr`` band (Monte Carlo error)."""
    (line,) = ax.plot(x, mean, label=label, **kwargs)
    ax.fill_between(x, mean - z * stderr, mean + z * stderr, color=line.get_color(),
                    alpha=0.2, linewidth=0)
    return line


def finish(fig, *, title: str | None = None):
    """Check that every visible axis has x and y labels, add an optional title, return ``fig``."""
    for ax in fig.get_axes():
        if not ax.get_visible() or not ax.has_data():
            continue
        if not ax.get_xlabel() or not ax.get_ylabel():
            raise ValueError(
                f"figure axis {ax.get_title()!r} lacks a label (x={ax.get_xlabel()!r}, "
                f"y={ax.get_ylabel()!r}): every axis needs a label with units"
            )
    if title:
        fig.suptitle(title)
    return fig
