"""Open every page of the built site in headless Chromium and check that it really renders.

    python tools/browser_check _build/fast/_build/html [--min-pages 8] [--min-math-pages 3]
                                                       [--min-images 2] [--workers 2]

The site is served from a loopback HTTP server (127.0.0.1, random free port) and every page is
loaded in headless Chromium (Debian's ``/usr/bin/chromium`` driven by playwright; playwright's
own browser downloads are never used): ``--workers`` browsers side by side (default
``$FUSIONCENTER_BROWSER_WORKERS``, else 2), each loading every ``workers``-th page, the others
than the first in child processes of this script whose findings (and printed pages) are merged
into one report. Any request to a host other than 127.0.0.1 is reported and fails (Chromium
resolves no other host). For each page it checks:

* the page is served with HTTP 200 and no sub-resource fails (HTTP >= 400 or a network error);
* no console message of type "error" and no uncaught JavaScript exception; the page declares
  an icon (``<link rel="icon">``) that the site serves (``check_favicon``: without one every
  page asks for ``/favicon.ico`` and gets 404);
* accessibility (``check_accessibility``): axe-core 4 (vendored, ``tools/vendor/axe.min.js``)
  finds no violation of the WCAG 2 A and AA rules at 1280 px with every collapsed block open,
  in the theme's light colours, and none of the colour rules in its dark ones (names of
  toggles, contrast >= 4.5:1, valid ARIA...); the seconds axe took are printed; every visible
  control (toggle, button, dropdown, tab, input) takes the keyboard focus and shows it
  (``check_focus``);
* every ``<img>`` finished loading with a non-zero natural width;
* on pages whose served HTML has math elements (class ``math``: ``span.math``, ``div.math``),
  MathJax started (``MathJax.startup.promise``), produced at least one ``mjx-container`` per
  math element, left no raw TeX delimiters (``\\(``, ``\\[``, ``$$``) visible in them, reported no
  TeX error (``mjx-merror``) nor undefined macro (drawn in red by MathJax's noundefined
  extension), and its woff fonts were loaded from the site itself.
* at 1280 px, no element of the main text (tables, outputs, display math, paragraphs, code
  listings...) has content wider than its box, and no page is taller than 60 000 px; counts
  per page and in total are printed (``check_layout``); no ``aligned`` display is broken by
  hand where the row and its continuation fit one line (``check_splits``: MathJax 4 breaks
  what does not fit);
* at 400 px (a phone), the same (the formulas broken again for the new width first), except that
  content may also sit in a box that scrolls sideways inside the column (a wide table of
  numbers, a long equation, a figure kept at its legible width); each registry figure there
  keeps panels >= 500 px wide and fonts >= 11 px in such a box;
* no page (text, titles, link texts) and no title of the search index contains unrendered
  MyST or LaTeX: ``\\tilde``, ``\\text{``, ``{cite}``, ``{eq}``, ``{glue}``, ``$...$``
  (``check_markup``);
* a chapter reads as a book (``check_reading``, from the served HTML): no image in a cell's
  output outside a numbered, captioned figure; no output that prints a dict or list repr, a
  bare ``True``/``False``, ``array(`` or ``Matrix(``; no ASCII stand-in for mathematics
  (``x_hat``, ``sigma_v``, ``h^T``, ``sqrt(``) in a chapter's prose, tables, headings, captions
  or printed output; the median chapter page shows at most 80 lines of unfolded code.

Importable (with ``tools/`` on ``sys.path``): ``browser_check.check_site(html_dir) ->
list[str]`` returns the problems (empty when all is well). A missing browser or playwright is a
problem, never a skip. Exit status 1 on any problem.

One module per family of detectors: :mod:`~browser_check.page` (the page as it loads: HTTP,
icon, images, MathJax), :mod:`~browser_check.explorables` (the sliders),
:mod:`~browser_check.figures` (the registry figures), :mod:`~browser_check.layout` (clipped
content, page height), :mod:`~browser_check.displays` (displays broken by hand),
:mod:`~browser_check.accessibility` (axe-core, keyboard focus),
:mod:`~browser_check.markup` (unrendered MyST/LaTeX), :mod:`~browser_check.reading` (a chapter
reads as a book); :mod:`~browser_check.driver` serves the site and drives the browsers over it,
:mod:`~browser_check.workers` runs several side by side, and ``__main__`` is the command line.
The browser itself and the local server are ``tools/headless.py``'s, shared with
``tools/pdf_book.py``.
"""

from .accessibility import axe_violations, check_accessibility, check_focus
from .displays import check_splits, needless_splits
from .driver import check_site
from .explorables import check_explorables
from .layout import VIEWPORT, LayoutResult, check_layout
from .markup import check_markup, find_raw_markup, raw_markup_in_html, raw_markup_in_search_index
from .page import check_favicon, list_pages
from .reading import (
                      check_reading,
                      find_ascii_math,
                      find_contradicted_numbers,
                      find_doubled_words,
                      find_repr_output,
                      is_chapter,
                      read_page,
)
from .result import PageResult
from .workers import WORKERS_ENV, default_workers

__all__ = [
    "VIEWPORT", "WORKERS_ENV", "LayoutResult", "PageResult", "axe_violations",
    "check_accessibility", "check_explorables", "check_favicon", "check_focus", "check_layout",
    "check_markup", "check_reading", "check_site", "check_splits", "default_workers",
    "find_ascii_math", "needless_splits",
    "find_contradicted_numbers", "find_doubled_words", "find_raw_markup", "find_repr_output",
    "is_chapter", "list_pages", "raw_markup_in_html", "raw_markup_in_search_index",
    "read_page",
]
