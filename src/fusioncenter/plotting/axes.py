"""Drawing on one panel: a curve with its Monte Carlo error band, readable log axes, and error
bars on a log axis whose lower ends would leave it."""

from __future__ import annotations

import matplotlib
import matplotlib.ticker
import numpy as np

__all__ = ["errorband", "errorbar_log", "log_axis"]


def errorband(ax, x, mean, stderr, *, z: float = 1.96, label: str | None = None, **kwargs):
    """A curve with a shaded ``mean -/+ z * stderr`` band (Monte Carlo error).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The axes to draw on.
    x : array_like, shape (n,)
        The abscissae.
    mean : numpy.ndarray, shape (n,)
        The curve (for example :attr:`fusioncenter.montecarlo.MonteCarloResult.mean`).
    stderr : numpy.ndarray or float
        Its standard error, broadcast against ``mean``.
    z : float, default 1.96
        The band's half-width in standard errors (1.96: a 95 % band).
    label : str, optional
        The curve's legend label (the band has none).
    **kwargs
        Passed to ``ax.plot`` (e.g. ``**look(scheme)``).

    Returns
    -------
    matplotlib.lines.Line2D
        The curve; the band is filled in its colour with opacity 0.2.
    """
    (line,) = ax.plot(x, mean, label=label, **kwargs)
    ax.fill_between(x, mean - z * stderr, mean + z * stderr, color=line.get_color(),
                    alpha=0.2, linewidth=0)
    return line



def log_axis(ax, which: str = "y") -> None:
    """Put one axis of ``ax`` on a log scale with ticks a reader can read: plain numbers
    (``0.5``, ``1``, ``2``, ``5``, ``10``) at 1, 2 and 5 times the powers of ten, and, on an
    axis spanning at most about one decade, also labelled minor ticks at 1.5, 3 and 7 times
    them (never matplotlib's ``4×10⁰``).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The axes.
    which : {"x", "y"}
        The axis.

    Returns
    -------
    None
        The axis of ``ax`` is changed in place.

    Raises
    ------
    ValueError
        If ``which`` is neither ``"x"`` nor ``"y"``.
    """
    if which not in ("x", "y"):
        raise ValueError(f"which must be 'x' or 'y', got {which!r}")
    getattr(ax, f"set_{which}scale")("log")
    axis = getattr(ax, f"{which}axis")
    axis.set_major_locator(matplotlib.ticker.LogLocator(base=10.0, subs=(1.0, 2.0, 5.0)))
    axis.set_minor_locator(matplotlib.ticker.LogLocator(base=10.0, subs=(1.5, 3.0, 7.0)))
    axis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))

    def minor(v, _):
        lo, hi = sorted(getattr(ax, f"get_{which}lim")())
        return f"{v:g}" if lo > 0 and np.log10(hi / lo) <= 1.25 else ""

    axis.set_minor_formatter(matplotlib.ticker.FuncFormatter(minor))


def errorbar_log(ax, x, y, err, *, label: str | None = None, xname: str = "x", **kwargs):
    """``ax.errorbar`` on a log y axis, with ``y -/+ err`` bars whose lower end would reach
    zero or below (and so leave the axis) clipped at the axis bottom and marked.

    The axis bottom is put below the smallest positive ``y`` of every call on ``ax``: at the
    largest power of ten not above ``10**-0.3`` (about half) times it. A bar whose lower end
    reaches the bottom or below is clipped there and ends in a triangle at the axis, which has
    its own legend entry saying where (``xname = value``) the bar was clipped. The axis top is
    1.3 times the largest ``y + err`` of every call. Returns the container.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The axes to draw on; its y axis is set to log scale and its limits as above.
    x, y, err : array_like, shape (n,)
        The abscissae, the values (at least one positive) and the half-lengths of the bars
        (a 95 % interval: the clipped bars' legend entry says so).
    label : str, optional
        The legend label of the points.
    xname : str, default "x"
        The name of ``x`` in the legend entry of the clipped bars.
    **kwargs
        Passed to ``ax.errorbar``.

    Returns
    -------
    matplotlib.container.ErrorbarContainer
        What ``ax.errorbar`` returns.

    Raises
    ------
    ValueError
        If no ``y`` is positive.
    """
    x, y, err = (np.asarray(v, dtype=float) for v in (x, y, err))
    bottom = 10.0 ** np.floor(np.log10(np.min(y[y > 0])) - 0.3)
    bottom = min(bottom, getattr(ax, "_fc_log_bottom", bottom))
    ax._fc_log_bottom = bottom
    clipped = y - err <= bottom
    lower = np.where(clipped, y - bottom, err)
    cont = ax.errorbar(x, y, yerr=np.vstack([lower, err]), label=label, **kwargs)
    ax.set_yscale("log")
    top = max(getattr(ax, "_fc_log_top", 0.0), float(np.max(y + err)) * 1.3)
    ax._fc_log_top = top
    ax.set_ylim(bottom, top)
    if np.any(clipped):
        xs = ", ".join(f"{v:g}" for v in x[clipped])
        ax.plot(x[clipped], np.full(clipped.sum(), bottom), ls="none", marker="v",
                color=cont.lines[0].get_color(), markersize=7, clip_on=False, zorder=4,
                label=f"95 % bar reaches 0, clipped at the axis ({xname} = {xs})")
    return cont
