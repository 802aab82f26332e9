"""The one plotting style of the book: one look per scheme and per quantity.

The package, one idea per module:

- :mod:`~fusioncenter.plotting.theme`     the palette, one look per scheme and per quantity
  (:func:`look`, :func:`classify`) and the book's ``rcParams`` (:data:`RC`);
- :mod:`~fusioncenter.plotting.panels`    a figure's panels: :func:`subplots` stacks them at the
  page's full width, :func:`finish` checks the labels, moves legends out of the data area and
  raises small text to :data:`MIN_FONT_PT`; :func:`letter_panels` letters them;
- :mod:`~fusioncenter.plotting.axes`      drawing on one panel: :func:`errorband`,
  :func:`log_axis`, :func:`errorbar_log`;
- :mod:`~fusioncenter.plotting.saving`    a finished figure as PNG bytes with the facts the
  book's site checks (:func:`render`, :func:`layout_facts`);
- :mod:`~fusioncenter.plotting.alt_text`  its alt text (``describe``).

Every registry ``plot`` builds its figure with :func:`subplots` and hands it to :func:`finish`.
The names above are re-exported here, so ``plotting.look`` and ``plotting.subplots`` are what
the chapters and the figure modules use.

The backend is left alone: notebooks keep their inline backend, and the command line selects
Agg itself (``fusioncenter.cli``).
"""

from __future__ import annotations

from fusioncenter.plotting.alt_text import describe
from fusioncenter.plotting.axes import errorband, errorbar_log, log_axis
from fusioncenter.plotting.panels import MIN_FONT_PT, finish, letter_panels, panel_heading, subplots
from fusioncenter.plotting.saving import SAVE_DPI, layout_facts, render
from fusioncenter.plotting.theme import (
    MARKERS,
    OKABE_ITO,
    QUANTITIES,
    RC,
    SCHEMES,
    classify,
    look,
    style,
    use_style,
)

__all__ = ["OKABE_ITO", "MARKERS", "RC", "SCHEMES", "QUANTITIES", "MIN_FONT_PT", "SAVE_DPI",
           "style", "use_style", "subplots", "finish", "errorband", "errorbar_log", "log_axis",
           "letter_panels", "panel_heading", "look", "classify", "render", "layout_facts",
           "describe"]
