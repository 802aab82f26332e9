"""A finished figure saved for the page: its PNG bytes and the layout facts the site checks.

:func:`render` turns a finished figure into PNG bytes and the facts the book's site checks
(panel widths, smallest font); :func:`layout_facts` computes the same facts from one layout
pass without rasterising (what the legibility tests use).
"""

from __future__ import annotations

import collections
import io
import math
import numbers
import struct

import matplotlib
import matplotlib.figure
import matplotlib.text

__all__ = ["SAVE_DPI", "render", "layout_facts"]

#: Resolution of the figures the book saves (a 6.4 in wide figure is 1280 px).
SAVE_DPI = 200
#: Padding around the tight bounding box of a saved figure, inches (matplotlib's default).
_PAD_IN = 0.1


def _texts(fig):
    return [t for t in fig.findobj(matplotlib.text.Text)
            if t.get_visible() and t.get_text().strip() and t.get_figure() is not None]


def render(fig, *, dpi: int = SAVE_DPI) -> tuple[bytes, dict]:
    """PNG bytes of ``fig`` (tight bounding box, ``dpi``) and the facts a page check needs.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure (normally finished by :func:`~fusioncenter.plotting.panels.finish`), laid
        out (:func:`layout_facts`) and drawn once into the PNG.
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
