"""A figure's panels: laid out in the book's style and finished for the page.

Every registry ``plot`` builds its figure with :func:`subplots` and hands it to :func:`finish`.
:func:`subplots` (``stack=True``) stacks panels in one column (a panel keeps the full width of
the page's text column instead of shrinking); :func:`finish` refuses an unlabelled axis, moves
every legend out of the data area (above its panel, with the panel's title as the legend's
heading) and raises any text smaller than :data:`MIN_FONT_PT`. :func:`letter_panels` gives the
panels of a figure their letters, (a), (b), ..., in the heading :func:`panel_heading` finds.
"""

from __future__ import annotations

import re
import textwrap

import matplotlib
import matplotlib.pyplot as plt
import matplotlib.text

from fusioncenter.plotting.theme import RC, use_style

__all__ = ["MIN_FONT_PT", "subplots", "finish", "letter_panels", "panel_heading"]

#: No text of a finished figure is smaller (points): 8 pt is about 12 px on the page.
MIN_FONT_PT = 8.0

_PANEL = (6.4, 3.3)  # one stacked panel: full text width, inches


def subplots(nrows: int = 1, ncols: int = 1, *, stack: bool = False, figsize=None, **kwargs):
    """``plt.subplots`` in the book's style (figure size scales with the grid).

    With ``stack=True`` (every registry figure) a grid of ``nrows x ncols`` panels is laid out
    as ``nrows * ncols`` full-width rows (read in row-major order), and the axes are returned
    with the grid's shape, so ``axes[i, j]`` or ``ax1, ax2 = axes`` work as with
    ``plt.subplots``: on a page column about 700 px wide each panel keeps its full width instead
    of shrinking to a half or a third of it.

    Parameters
    ----------
    nrows, ncols : int, default 1
        The grid of panels.
    stack : bool, default False
        Lay the ``nrows * ncols`` panels out in one column (keyword-only).
    figsize : tuple of float, optional
        Width and height in inches. Default: with ``stack``, 6.4 wide and 3.3 per panel plus
        0.6; otherwise :data:`~fusioncenter.plotting.theme.RC`'s 6.4 x 4.0 scaled by
        ``0.75 * ncols + 0.25`` and ``0.8 * nrows + 0.2``.
    **kwargs
        Passed to ``matplotlib.pyplot.subplots`` (``layout`` defaults to
        ``"constrained"``). With ``stack``, ``squeeze`` (default ``True``) applies to the
        ``(nrows, ncols)`` grid and ``sharex``/``sharey`` to the column of panels.

    Returns
    -------
    fig : matplotlib.figure.Figure
        The new figure.
    axes : matplotlib.axes.Axes or numpy.ndarray of them
        As from ``plt.subplots``: one ``Axes`` for a single panel, else an array of shape
        ``(nrows, ncols)`` with the axes of length 1 squeezed out (unless
        ``squeeze=False``).

    Notes
    -----
    It calls :func:`~fusioncenter.plotting.theme.use_style` first, so the book's style stays
    the default afterwards.
    """
    use_style()
    kwargs.setdefault("layout", "constrained")
    if not stack:
        w, h = RC["figure.figsize"]
        if figsize is None:
            figsize = (w * (0.75 * ncols + 0.25), h * (0.8 * nrows + 0.2))
        return plt.subplots(nrows, ncols, figsize=figsize, **kwargs)
    n = nrows * ncols
    w, h = _PANEL
    if figsize is None:
        figsize = (w, h * n + 0.6)
    squeeze = kwargs.pop("squeeze", True)
    fig, axes = plt.subplots(n, 1, figsize=figsize, squeeze=False, **kwargs)
    axes = axes.reshape(nrows, ncols)
    if squeeze:
        axes = axes.squeeze()
        if axes.ndim == 0:
            axes = axes.item()
    return fig, axes



#: A panel's letter at the start of its title: "(a) position".
_PANEL_LETTER = re.compile(r"\(([a-z])\)(\s|$)")


def panel_heading(ax) -> tuple[str, object]:
    """The heading a reader sees over a panel, and the text object holding it.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        A panel, finished or not (:func:`finish` moves a panel's title into its legend).

    Returns
    -------
    heading : str
        The axes' title, else its legend's title, else ``""``.
    holder : matplotlib.text.Text or None
        The legend's title text when the heading is there (or the panel has a legend and no
        title), else ``None`` (the axes' title).
    """
    leg = ax.get_legend()
    if ax.get_title() or leg is None:
        return ax.get_title(), None
    return leg.get_title().get_text(), leg.get_title()


def letter_panels(fig):
    """Give each panel of a figure of several panels its own letter, ``(a)``, ``(b)``, ...,
    in the order of the panels (top to bottom), at the start of its heading
    (:func:`panel_heading`); a figure whose panels already carry letters is left alone.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure (normally finished by :func:`finish`), modified in place.

    Returns
    -------
    matplotlib.figure.Figure
        ``fig`` itself.

    Raises
    ------
    ValueError
        If some panels carry letters and others do not, or two panels share a letter.
    """
    panels = [ax for ax in fig.get_axes() if ax.get_visible() and ax.has_data()]
    if len(panels) < 2:
        return fig
    headings = [panel_heading(ax) for ax in panels]
    letters = [m[1] if (m := _PANEL_LETTER.match(h)) else None for h, _ in headings]
    if all(letters):
        if len(set(letters)) < len(letters):
            raise ValueError(f"panels share a letter: {letters}")
        return fig
    if any(letters):
        raise ValueError(f"some panels carry a letter, others not: {letters}")
    for k, (ax, (heading, holder)) in enumerate(zip(panels, headings, strict=True)):
        text = f"({'abcdefghijklmnopqrstuvwxyz'[k]}) {heading}".rstrip()
        if holder is None:
            ax.set_title(text)
        else:
            holder.set_text(text)
    return fig



def _legend_outside(ax) -> None:
    """Re-create the axes' legend above its data area, headed by the axes' title."""
    leg = ax.get_legend()
    if leg is None:
        return
    labels = [t.get_text() for t in leg.get_texts()]
    own_handles, own_labels = ax.get_legend_handles_labels()
    handles = own_handles if own_labels == labels else leg.legend_handles
    ncols = leg._ncols if len(labels) > 1 and leg._ncols > 1 else (2 if len(labels) > 3 else 1)
    longest = max((len(s) for s in labels), default=0)
    if longest > 38:
        ncols = 1
    title = ax.get_title()
    ax.set_title("")
    leg.remove()
    ax.legend(handles, labels, loc="lower left", bbox_to_anchor=(0.0, 1.02, 1.0, 0.0),
              borderaxespad=0.0, ncols=ncols, title=textwrap.fill(title, 84) or None,
              alignment="left",
              fontsize=RC["legend.fontsize"], handlelength=2.4)


def finish(fig, *, title: str | None = None):
    """Check that every visible axis has x and y labels, put legends outside the data area,
    raise small text to :data:`MIN_FONT_PT`, add an optional title,
    return ``fig``.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure, modified in place.
    title : str, optional
        A title over all panels (``fig.suptitle``, wrapped at 84 characters).

    Returns
    -------
    matplotlib.figure.Figure
        ``fig`` itself. Each legend is drawn again above its panel, in one column if a label
        is longer than 38 characters, with the panel's title (then removed from the panel) as
        its heading.

    Raises
    ------
    ValueError
        If a visible axis with data lacks an x or a y label.
    """
    for ax in fig.get_axes():
        if not ax.get_visible() or not ax.has_data():
            continue
        if not ax.get_xlabel() or not ax.get_ylabel():
            raise ValueError(
                f"figure axis {ax.get_title()!r} lacks a label (x={ax.get_xlabel()!r}, "
                f"y={ax.get_ylabel()!r}): every axis needs a label with units"
            )
    for ax in fig.get_axes():
        _legend_outside(ax)
    if title:
        fig.suptitle(textwrap.fill(title, 84), fontsize=RC["axes.titlesize"])
    for text in fig.findobj(matplotlib.text.Text):
        if text.get_text() and text.get_fontsize() < MIN_FONT_PT:
            text.set_fontsize(MIN_FONT_PT)
    return fig
