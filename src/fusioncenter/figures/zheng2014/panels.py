"""How the entries of Part IV (zheng2014) draw their data: the panels the settings share.

RMSE against time for a set of schemes (:func:`rmse_panels`), CFwMD and CFwMD2 by ``l``
(:func:`by_l_panels`), transmissions per step against ``l`` next to a printed table
(:func:`transmissions_plot`), and the log axis they use (:func:`log_y`).
"""

from __future__ import annotations

import matplotlib
import matplotlib.ticker
import numpy as np

from fusioncenter import plotting
from fusioncenter.figures.zheng2014.common import LABELS


# ------------------------------------------------------------------------- plots
def log_y(ax) -> None:
    """A log y axis with plain tick labels at 1, 2, 5 x 10^k (and 1.5, 3, 7 between).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The axes.

    Returns
    -------
    None
    """
    ax.set_yscale("log")
    ax.yaxis.set_major_locator(matplotlib.ticker.LogLocator(base=10.0, subs=(1.0, 2.0, 5.0)))
    ax.yaxis.set_minor_locator(matplotlib.ticker.LogLocator(base=10.0, subs=(1.5, 3.0, 7.0)))
    fmt = matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}")
    ax.yaxis.set_major_formatter(fmt)
    ax.yaxis.set_minor_formatter(fmt)


def rmse_panels(data: dict, names, labels):
    """Position and velocity RMSE against time, one curve per name, on log axes.

    Parameters
    ----------
    data : dict
        With ``time``, ``rmse_position``, ``rmse_velocity`` and their ``_stderr`` (one row per
        name).
    names : list of str
        The curves' names, in the rows' order.
    labels : dict
        Their legend labels.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, axes = plotting.subplots(1, 2, stack=True)
    t = data["time"]
    for name in names:
        kw = plotting.look(name, markersize=4)
        plotting.errorband(axes[0], t, data["rmse_position"][names.index(name)],
                           data["rmse_position_stderr"][names.index(name)], label=labels[name],
                           **kw)
        plotting.errorband(axes[1], t, data["rmse_velocity"][names.index(name)],
                           data["rmse_velocity_stderr"][names.index(name)], label=labels[name],
                           **kw)
    axes[0].set(xlabel="time (s)", ylabel="position RMSE (m)", title="(a) position")
    axes[1].set(xlabel="time (s)", ylabel="velocity RMSE (m/s)", title="(b) velocity")
    for ax in axes:
        log_y(ax)
        ax.set_xticks([1, 5, 10, 15, 20])
    axes[0].legend(ncol=2)
    return fig


def by_l_panels(data: dict, *, l_ticks: bool = False):
    """CFwMD against CFwMD2 at every ``l`` (Figs. 2 and 5).

    Parameters
    ----------
    data : dict
        The data of :func:`~fusioncenter.figures.zheng2014.comparisons.by_l_data`.
    l_ticks : bool
        Whether the x ticks of the last panel are the ``l`` values.

    Returns
    -------
    matplotlib.figure.Figure
        The position RMSE against time, one curve per ``l``, of (a) CFwMD and (b) CFwMD2;
        (c) their time averages against ``l``.
    """
    fig, (ax1, ax1b, ax2) = plotting.subplots(3, 1, stack=True)
    t = data["time"]
    for j, (ax, name, letter) in enumerate(((ax1, "cfwmd", "a"), (ax1b, "cfwmd2", "b"))):
        shades = matplotlib.colormaps["viridis"](np.linspace(0.0, 0.85, len(data["l"])))
        for i, l in enumerate(data["l"]):  # an ordered parameter: a sequential palette
            ax.plot(t, data["rmse_position"][j, i], color=shades[i],
                    ls=plotting.SCHEMES[name]["linestyle"], label=f"l = {l:g}")
        ax.set(xlabel="time (s)", ylabel="position RMSE (m)",
               title=f"({letter}) {LABELS[name]}, N = {data['N']}, by l")
        ax.legend(ncol=5)
    lo = min(ax1.get_ylim()[0], ax1b.get_ylim()[0])
    hi = max(ax1.get_ylim()[1], ax1b.get_ylim()[1])
    for ax in (ax1, ax1b):
        ax.set_ylim(lo, hi)
    for j, name in enumerate(("cfwmd", "cfwmd2")):
        ax2.errorbar(data["l"], data["tavg_position"][j],
                     yerr=1.96 * data["tavg_position_stderr"][j], capsize=3,
                     label=LABELS[name], **plotting.look(name))
    ax2.set(xlabel="target number of transmissions per step l (-)",
            ylabel="time-averaged position RMSE (m)", title="(c) time average, 95 % bars")
    if l_ticks:
        ax2.set_xticks(data["l"])
    ax2.legend(ncol=2)
    return fig


def transmissions_plot(data: dict, labels: dict, table: str, title: str, *,
                       l_ticks: bool = False):
    """Transmissions per step minus ``l`` of CFwMD and CFwMD2 against ``l``, with the paper's.

    Parameters
    ----------
    data : dict
        The data of :func:`~fusioncenter.figures.zheng2014.comparisons.transmissions_data`.
    labels : dict
        Legend labels of ``cfwmd`` and ``cfwmd2``.
    table : str
        The paper's number of the table (``"I"``).
    title : str
        The axes' title.
    l_ticks : bool
        Whether the x ticks are the ``l`` values.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = plotting.subplots(stack=True)
    l = data["l"]
    for name in ("cfwmd", "cfwmd2"):
        ax.errorbar(l, data[name] - l, yerr=1.96 * data[f"{name}_stderr"], capsize=3,
                    label=f"{labels[name]} (ours)", **plotting.look(name))
        ax.plot(l, data[f"paper_{name}"] - l, label=f"{labels[name]} (paper, Table {table})",
                **plotting.look(name, "paper"))
    ax.axhline(0.0, color="0.4", lw=0.8, ls=":", label="target: l per step")
    if l_ticks:
        ax.set_xticks(l)
    ax.set(xlabel="target number of transmissions per step l (-)",
           ylabel="transmissions per step minus l (-)", title=title)
    ax.legend(ncol=2)
    return plotting.finish(fig)

