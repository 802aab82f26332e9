"""The one plotting style of the book: one look per scheme and per quantity.

Colours are the Okabe–Ito palette (distinguishable with the common colour-vision deficiencies)
plus two of Paul Tol's muted colours. Every scheme of the four papers has ONE colour and ONE
marker (:data:`SCHEMES`), with zheng2014's own marker key (circle random selection, triangle
CFoMD, square CFwMD, plus all-send); every quantity drawn against them (Monte Carlo, bounds,
closed forms, the paper's printed values) has one line style (:data:`QUANTITIES`). A plot asks
for a look with :func:`look`; :func:`classify` reads a legend label back into the scheme and
quantity it names, which is how the tests check that every plot keeps the mapping.

Every registry ``plot`` builds its figure with :func:`subplots` and hands it to :func:`finish`.
:func:`subplots` (``stack=True``) stacks panels in one column (a panel keeps the full width of
the page's text column instead of shrinking); :func:`finish` refuses an unlabelled axis, moves
every legend out of the data area (above its panel, with the panel's title as the legend's
heading) and raises any text smaller than :data:`MIN_FONT_PT`. :func:`render` turns a finished
figure into PNG bytes and the facts the book's site checks (panel widths, smallest font);
:func:`describe` writes its alt text.

The backend is left alone: notebooks keep their inline backend, and the command line selects
Agg itself (``fusioncenter.cli``).
"""

from __future__ import annotations

import collections
import io
import math
import numbers
import re
import struct
import textwrap
from contextlib import contextmanager

import matplotlib
import matplotlib.figure
import matplotlib.pyplot as plt
import numpy as np
from cycler import cycler

__all__ = ["OKABE_ITO", "MARKERS", "RC", "SCHEMES", "QUANTITIES", "MIN_FONT_PT", "SAVE_DPI",
           "style", "use_style", "subplots", "finish", "errorband", "errorbar_log", "log_axis",
           "letter_panels", "panel_heading", "look", "classify", "render", "layout_facts",
           "describe"]

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
_WINE, _OLIVE = "#882255", "#999933"  # Paul Tol's muted palette (also colour-blind safe)
_LINESTYLES = ["-", "--", "-.", ":", "-", "--", "-.", ":"]
#: Markers in the same order, for plots that mark points of a parameter sweep (not schemes).
MARKERS = ["o", "s", "^", "D", "v", "P", "X", "*"]

#: One colour and one marker per scheme, everywhere in the book (``look(scheme)``).
#: zheng2014's key: circle random selection, triangle CFoMD, square CFwMD, plus all-send.
SCHEMES: dict[str, dict] = {
    "all-send": {"color": "#000000", "marker": "P", "linestyle": "-"},
    "random": {"color": "#D55E00", "marker": "o", "linestyle": "-"},
    "cfomd": {"color": "#009E73", "marker": "^", "linestyle": "-"},
    "cfwmd": {"color": "#0072B2", "marker": "s", "linestyle": "-"},
    "cfwmd2": {"color": "#CC79A7", "marker": "D", "linestyle": "--"},
    # CFwMD without feedback (zheng2014 Figs. 3 and 6): the likelihood as printed, corrected,
    # and the exact filter
    "printed": {"color": "#E69F00", "marker": "x", "linestyle": ":"},
    "corrected": {"color": _OLIVE, "marker": "v", "linestyle": "-."},
    "exact": {"color": "#56B4E9", "marker": "s", "linestyle": "-", "linewidth": 2.2},
    # mo2015's stochastic trigger (a scheme of its own wherever it appears)
    "trigger": {"color": _WINE, "marker": "*", "linestyle": "-"},
    # leong2011's power allocations
    "optimal": {"color": "#0072B2", "marker": "o", "linestyle": "-"},
    "equal": {"color": "#D55E00", "marker": "s", "linestyle": "--"},
    "full-csi": {"color": "#009E73", "marker": "D", "linestyle": "-"},
    "no-csi": {"color": "#E69F00", "marker": "v", "linestyle": "--"},
}

#: One line style per quantity (its colour is the scheme's or the parameter's, else the one
#: given here): the Monte Carlo mean is solid, bounds dashed (tight/upper) or dotted
#: (loose/lower), closed-form limits dash-dotted, the paper's printed values crosses.
QUANTITIES: dict[str, dict] = {
    "monte-carlo": {"color": "0.25", "linestyle": "-"},
    "p-inf": {"color": "#000000", "linestyle": "-", "linewidth": 2.0},
    "tight-bound": {"color": "0.25", "linestyle": "--"},
    "loose-bound": {"color": "0.25", "linestyle": ":"},
    "upper-bound": {"color": "#D55E00", "linestyle": "--"},
    "lower-bound": {"color": "#0072B2", "linestyle": "--"},
    "exact-upper": {"color": "#D55E00", "linestyle": (0, (1, 1.5)), "linewidth": 2.2},
    "exact-lower": {"color": "#0072B2", "linestyle": (0, (1, 1.5)), "linewidth": 2.2},
    "limit": {"color": "0.45", "linestyle": "-.", "linewidth": 1.0},
    "paper": {"marker": "x", "linestyle": "none", "markersize": 8},
}

# label text -> scheme; the first match wins (CFwMD2 before CFwMD, variants before CFwMD)
_SCHEME_PATTERNS = [
    ("cfwmd2", r"CFwMD2"),
    ("printed", r"as printed"),
    ("corrected", r"corrected"),
    ("exact", r"exact filter"),
    ("cfwmd", r"CFwMD"),
    ("cfomd", r"CFoMD"),
    ("random", r"random selection"),
    ("all-send", r"all-send"),
    ("trigger", r"\btrigger\b"),
    ("optimal", r"optimal allocation"),
    ("equal", r"equal power"),
    ("full-csi", r"full CSI"),
    ("no-csi", r"no CSI"),
]
_QUANTITY_PATTERNS = [
    ("paper", r"\(paper|\(Table [IVX]+\)"),
    ("exact-upper", r"exact upper bound"),
    ("exact-lower", r"exact lower bound"),
    ("upper-bound", r"^upper bound"),
    ("lower-bound", r"^lower bound"),
    ("tight-bound", r"^tight "),
    ("loose-bound", r"^loose "),
]

#: No text of a finished figure is smaller (points): 8 pt is about 12 px on the page.
MIN_FONT_PT = 8.0
#: Resolution of the figures the book saves (a 6.4 in wide figure is 1280 px).
SAVE_DPI = 200
#: Padding around the tight bounding box of a saved figure, inches (matplotlib's default).
_PAD_IN = 0.1

_PANEL = (6.4, 3.3)  # one stacked panel: full text width, inches

#: The book's matplotlib ``rcParams`` (applied by :func:`style`, :func:`use_style` and
#: :func:`subplots`).
RC = {
    "axes.prop_cycle": cycler(color=OKABE_ITO) + cycler(linestyle=_LINESTYLES),
    "lines.markersize": 5,
    "lines.linewidth": 1.6,
    "figure.figsize": (6.4, 4.0),
    "figure.dpi": 100,
    "savefig.dpi": 150,
    "savefig.bbox": "tight",
    "font.size": 10,
    "axes.titlesize": 10,
    "axes.labelsize": 10,
    "xtick.labelsize": 9,
    "ytick.labelsize": 9,
    "legend.fontsize": 9,
    "legend.title_fontsize": 10,
    "legend.frameon": False,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "mathtext.fontset": "cm",
}


@contextmanager
def style():
    """Context manager applying the book's style.

    Yields
    ------
    None
        Inside the ``with`` block matplotlib's ``rcParams`` are updated with :data:`RC`; they
        are restored when the block exits (``matplotlib.rc_context``).
    """
    with matplotlib.rc_context(RC):
        yield


def use_style() -> None:
    """Make the book's style the default for every later figure (what the chapters do).

    Returns
    -------
    None
        ``matplotlib.rcParams`` is updated with :data:`RC`, for the rest of the process.
    """
    matplotlib.rcParams.update(RC)


def look(scheme: str | None = None, quantity: str | None = None, **overrides) -> dict:
    """Keyword arguments for ``ax.plot``/``ax.errorbar`` drawing ``scheme`` and/or ``quantity``.

    Parameters
    ----------
    scheme : str, optional
        A key of :data:`SCHEMES`: sets the colour and the marker (and a default line style).
    quantity : str, optional
        A key of :data:`QUANTITIES`: sets the line style (and the colour when no scheme is
        given; the marker for the paper's printed values).
    **overrides
        Anything else (``markersize``, ``alpha``, ``color`` of a parameter for a quantity...);
        a scheme's colour and marker cannot be overridden (``marker="None"`` draws none).

    Returns
    -------
    dict
        ``color``, ``marker``, ``linestyle`` and any further keywords: ``marker`` is always
        there (``"None"`` unless the scheme, the quantity or an override sets one); ``color``
        and ``linestyle`` when the scheme, the quantity or an override sets them. With both,
        the scheme gives the colour and the marker (``"x"`` for ``quantity="paper"``) and the
        quantity the line style. The short names ``ls``, ``lw``, ``c`` and ``ms`` of the
        overrides are written out in full.

    Raises
    ------
    ValueError
        If ``scheme`` or ``quantity`` is not a key of its table, or an override changes the
        colour or the marker fixed by ``scheme``.
    """
    if scheme is not None and scheme not in SCHEMES:
        raise ValueError(f"scheme must be one of {sorted(SCHEMES)}, got {scheme!r}")
    if quantity is not None and quantity not in QUANTITIES:
        raise ValueError(f"quantity must be one of {sorted(QUANTITIES)}, got {quantity!r}")
    aliases = {"ls": "linestyle", "lw": "linewidth", "c": "color", "ms": "markersize"}
    overrides = {aliases.get(k, k): v for k, v in overrides.items()}
    out: dict = {"marker": "None"}
    if quantity is not None:
        out.update(QUANTITIES[quantity])
    if scheme is not None:
        s = SCHEMES[scheme]
        if quantity is not None and "linestyle" in QUANTITIES[quantity]:
            out.update({k: v for k, v in s.items() if k != "linestyle"})
            out["linestyle"] = QUANTITIES[quantity]["linestyle"]
        else:
            out.update(s)
        if quantity == "paper":
            out["marker"] = "x"
    fixed = ("color", "marker") if scheme is not None else ()
    clash = [k for k in fixed if k in overrides and overrides[k] != out[k]
             and not (k == "marker" and overrides[k] in ("None", "none", ""))]
    if clash:
        raise ValueError(f"look({scheme!r}): {clash} are fixed by the scheme")
    out.update(overrides)
    return out


def classify(label: str) -> tuple[str | None, str | None]:
    """The ``(scheme, quantity)`` a legend label names (``None`` where it names none).

    Parameters
    ----------
    label : str
        A legend label, e.g. ``"CFwMD (paper)"``.

    Returns
    -------
    scheme : str or None
        The key of :data:`SCHEMES` the label names ("CFwMD", "random selection", "full
        CSI", ...). The patterns are case-sensitive and tried in a fixed order, the first one
        the label contains wins ("CFwMD2" and "as printed" before "CFwMD").
    quantity : str or None
        The key of :data:`QUANTITIES` the label names; only the paper's values (a label
        containing ``(paper`` or a table such as ``(Table IV)``), the exact upper and lower
        bounds, and labels starting with ``upper bound``, ``lower bound``, ``tight`` or
        ``loose`` are recognised.
    """
    scheme = next((k for k, p in _SCHEME_PATTERNS if re.search(p, label)), None)
    quantity = next((k for k, p in _QUANTITY_PATTERNS if re.search(p, label)), None)
    return scheme, quantity


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
        0.6; otherwise :data:`RC`'s 6.4 x 4.0 scaled by ``0.75 * ncols + 0.25`` and
        ``0.8 * nrows + 0.2``.
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
    It calls :func:`use_style` first, so the book's style stays the default afterwards.
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


def _texts(fig):
    return [t for t in fig.findobj(matplotlib.text.Text)
            if t.get_visible() and t.get_text().strip() and t.get_figure() is not None]


def render(fig, *, dpi: int = SAVE_DPI) -> tuple[bytes, dict]:
    """PNG bytes of ``fig`` (tight bounding box, ``dpi``) and the facts a page check needs.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure (normally finished by :func:`finish`), laid out (:func:`layout_facts`) and
        drawn once into the PNG.
    dpi : int, default 200
        Resolution of the PNG (:data:`SAVE_DPI`).

    Returns
    -------
    png : bytes
        The PNG file (0.1 in padding around the tight bounding box).
    facts : dict
        ``width_px``, ``height_px`` (of the PNG), ``dpi``, ``panels`` (axes with data),
        ``columns`` (side by side), ``panel_fraction`` (narrowest data area / width),
        ``min_font_pt``.
    """
    facts = layout_facts(fig, dpi=dpi)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi, bbox_inches="tight", pad_inches=_PAD_IN)
    png = buf.getvalue()
    w, h = struct.unpack(">II", png[16:24])
    return png, {**facts, "width_px": int(w), "height_px": int(h)}


def layout_facts(fig, *, dpi: int = SAVE_DPI) -> dict:
    """:func:`render`'s facts from one layout pass, nothing rasterised (tests of legibility).

    Parameters
    ----------
    fig, dpi : matplotlib.figure.Figure, int (default 200)
        The figure, laid out once, and the resolution the sizes in pixels are for.

    Returns
    -------
    dict
        :func:`render`'s facts; the sizes are the padded tight box's at the figure's own dpi
        (within 3 % of the PNG's on the 39 registry figures).

    Raises
    ------
    ValueError
        If ``fig`` is not a matplotlib figure or ``dpi`` not a positive finite number.
    """
    if not isinstance(fig, matplotlib.figure.Figure):
        raise ValueError(f"fig must be a matplotlib Figure, got {type(fig).__name__}")
    if isinstance(dpi, bool) or not isinstance(dpi, numbers.Real) or not 0 < dpi < math.inf:
        raise ValueError(f"dpi must be a positive finite number, got {dpi!r}")
    fig.draw_without_rendering()
    renderer = fig.canvas.get_renderer()
    bbox = fig.get_tightbbox(renderer)
    width_in, height_in = bbox.width + 2 * _PAD_IN, bbox.height + 2 * _PAD_IN
    axes = [ax for ax in fig.get_axes() if ax.get_visible() and ax.has_data()]
    fractions = [ax.get_window_extent(renderer).width / fig.dpi / width_in for ax in axes]
    rows = collections.Counter(round(ax.get_position().y0, 3) for ax in axes)
    return {
        "width_px": round(width_in * dpi), "height_px": round(height_in * dpi), "dpi": dpi,
        "panels": len(axes), "columns": max(rows.values(), default=1),
        "panel_fraction": round(float(min(fractions, default=1.0)), 4),
        "min_font_pt": round(float(min((t.get_fontsize() for t in _texts(fig)), default=0.0)), 2),
    }


_GREEK = dict(zip(
    "alpha beta gamma delta epsilon varepsilon zeta eta theta kappa lambda mu nu xi pi rho "
    "sigma tau phi varphi chi psi omega Gamma Delta Theta Lambda Xi Pi Sigma Phi Psi "
    "Omega".split(), "αβγδεεζηθκλμνξπρστφφχψωΓΔΘΛΞΠΣΦΨΩ", strict=True))
_SYMBOLS = {"top": "ᵀ", "infty": "∞", "le": "≤", "leq": "≤", "ge": "≥", "geq": "≥",
            "times": "×", "cdot": "·", "pm": "±", "to": "→", "sim": "∼", "approx": "≈",
            "mid": "|", "ell": "ℓ", "sqrt": "√", "log": "log", "exp": "exp", "ln": "ln",
            "min": "min", "max": "max", "quad": " ", "qquad": " ", "left": "", "right": ""}


def _plain(s: str) -> str:
    """Mathtext to readable text for alt text: ``$\\sigma_v^2$`` -> ``σ_v^2``, ``\\mathbf{h}^\\top``
    -> ``hᵀ`` (Greek letters and common symbols in Unicode, font commands and accents
    dropped)."""
    s = s.replace("$", "")
    s = re.sub(r"\\(mathrm|mathbf|mathit|mathcal|text|textbf|operatorname|mathbb|boldsymbol)"
               r"\{([^}]*)\}", r"\2", s)
    s = re.sub(r"\\(tilde|bar|hat|check|vec|overline|widehat|widetilde)\s*", "", s)
    s = re.sub(r"\^\{?\\top\}?", "ᵀ", s)
    s = re.sub(r"\\([A-Za-z]+)",
               lambda m: _GREEK.get(m[1], _SYMBOLS.get(m[1], m[1])), s)
    return re.sub(r"[{}]", "", s).replace("\\,", " ").replace("\\ ", " ").strip()


def describe(fig) -> str:
    """Alt text: for every panel, what it plots against what, and its curves (legend labels).

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure; only visible axes with data are described.

    Returns
    -------
    str
        A sentence naming the number of panels (and the figure's title), then per panel its
        title, "y label against x label" (with "(log scale)" for a log y axis) and its legend
        labels, mathtext turned into plain text.
    """
    axes = [ax for ax in fig.get_axes() if ax.get_visible() and ax.has_data()]
    parts = []
    sup = fig._suptitle.get_text() if fig._suptitle is not None else ""
    head = f"{len(axes)}-panel figure" if len(axes) > 1 else "Figure"
    parts.append(head + (f" ({_plain(sup)})" if sup else "") + ".")
    for i, ax in enumerate(axes):
        leg = ax.get_legend()
        title = ax.get_title() or (leg.get_title().get_text() if leg is not None else "")
        scale = " (log scale)" if ax.get_yscale() == "log" else ""
        s = (f"Panel {i + 1}" + (f", {_plain(title)}" if title else "") + f": "
             f"{_plain(ax.get_ylabel())}{scale} against {_plain(ax.get_xlabel())}")
        if leg is not None:
            labels = [_plain(t.get_text()) for t in leg.get_texts()]
            s += "; curves: " + "; ".join(labels)
        parts.append(s + ".")
    return " ".join(parts)
