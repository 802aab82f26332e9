"""The book's theme: one colour and marker per scheme, one line style per quantity, the rcParams.

Colours are the Okabe–Ito palette (distinguishable with the common colour-vision deficiencies)
plus two of Paul Tol's muted colours. Every scheme of the four papers has ONE colour and ONE
marker (:data:`SCHEMES`), with zheng2014's own marker key (circle random selection, triangle
CFoMD, square CFwMD, plus all-send); every quantity drawn against them (Monte Carlo, bounds,
closed forms, the paper's printed values) has one line style (:data:`QUANTITIES`). A plot asks
for a look with :func:`look`; :func:`classify` reads a legend label back into the scheme and
quantity it names, which is how the tests check that every plot keeps the mapping. :data:`RC`
holds the remaining matplotlib settings (sizes, fonts, grid), applied by :func:`style` and
:func:`use_style`.
"""

from __future__ import annotations

import re
from contextlib import contextmanager

import matplotlib
from cycler import cycler

__all__ = ["OKABE_ITO", "MARKERS", "RC", "SCHEMES", "QUANTITIES", "style", "use_style", "look",
           "classify"]

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

#: The book's matplotlib ``rcParams`` (applied by :func:`style`, :func:`use_style` and
#: :func:`fusioncenter.plotting.panels.subplots`).
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
