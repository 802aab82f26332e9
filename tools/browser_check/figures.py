"""The registry figures (book/_ext/registry_figure.py), measured as a reader sees them.

Every ``{registry-figure}`` of a page at a 1280 px window and at a 400 px one (a phone):
numbered, described by its alt text, linked to its full resolution, its data downloadable, its
panels and fonts legible as displayed (:func:`check_registry_figures`). Totals are kept in
:data:`FIGURE_STATS` across the pages of one run (:func:`registry_figure_summary`).
"""

from __future__ import annotations

import re
import urllib.request

from .layout import NARROW_VIEWPORT

FIGURE_VIEWPORT = {"width": 1280, "height": 900}
MIN_PANEL_PX = 500
MIN_FONT_PX = 11
FIGURE_STATS: dict = {"figures": 0, "pages": 0, "min_panel_px": None, "min_font_px": None,
                      "narrow_panel_px": None, "narrow_font_px": None, "narrow_scrolling": 0}

FIGURES_JS = r"""
async () => {
  const out = [];
  for (const fig of document.querySelectorAll('figure.fc-registry-figure')) {
    const img = fig.querySelector('img');
    const facts = fig.querySelector('.fc-facts');
    const r = {id: fig.id, hasImg: !!img, hasFacts: !!facts,
               book: fig.classList.contains('fc-book-figure'),
               number: (fig.querySelector('.caption-number') || {}).textContent || '',
               alt: img ? img.getAttribute('alt') || '' : '',
               linked: !!(img && img.closest('a[href]')), links: []};
    if (img) {
      if (!img.complete) await new Promise(res => { img.onload = img.onerror = res; });
      r.displayed = img.getBoundingClientRect().width;
      r.natural = img.naturalWidth;
      const box = img.closest('a') || img.parentElement;
      const main = fig.closest('article') || document.body;
      r.boxScrolls = /^(auto|scroll)$/.test(getComputedStyle(box).overflowX);
      r.boxInside = box.getBoundingClientRect().right
                    <= main.getBoundingClientRect().right + 1;
    }
    if (facts) {
      r.panels = +facts.dataset.panels; r.fraction = +facts.dataset.panelFraction;
      r.fontPt = +facts.dataset.minFontPt; r.dpi = +facts.dataset.dpi;
    }
    for (const a of fig.querySelectorAll('.fc-figure-data a[href]')) {
      r.links.push({href: a.getAttribute('href'), url: a.href});
    }
    out.push(r);
  }
  return out;
}
"""


# ============================================================================================
# Page layout: clipped content and unrendered markup (the "page" block of this file).
#
# Clipped content. Every page is laid out at 1280 px (VIEWPORT). In the main text column
# (``article.bd-article``) every block element of the kinds in _OVERFLOW_SELECTOR is measured
# after all collapsed blocks (``<details>``, toggled admonitions) were opened: it is *clipped*
# when its content is wider than its own box (``scrollWidth > clientWidth``) or its box sticks
# out of the column. Only the outermost clipped element of a nest is counted. The one exception
# is a code listing the page marks as scrollable (class ``fc-scroll-code``, set by
# book/_ext/scroll_code.py) whose ``<pre>`` really scrolls (``overflow-x: auto|scroll``):
# counted apart. At 1280 px such a listing is still a problem (a code line is never cut at the
# column's edge: chapters keep their code within 79 characters, tools/lint_chapters.py); at
# 400 px it scrolls in its box. The page's height at 1280 px (collapsed blocks closed) is at
# most MAX_PAGE_HEIGHT.
#
# Every page is then laid out at 400 px (NARROW_VIEWPORT, a phone) and measured again. There,
# content wider than its box may also sit in a box that scrolls sideways (``overflow-x:
# auto|scroll``, the element itself or an ancestor in the column) and does not itself stick out
# of the column: a table of numbers, a long display equation, a figure kept at its legible
# width. Such elements are counted apart ("in a scrolling box"); anything else is clipped.
#
# Unrendered markup. The served HTML (text outside math, code and scripts; page titles; link
# texts) and the search index (page and section titles of searchindex.js) must contain no
# MyST or LaTeX source: no TeX control word (``\tilde``, ``\text{``), no role (``{cite}``,
# ``{eq}``, ``{glue}``...) and no pair of ``$`` around text.
# ============================================================================================


def _sizes(f: dict) -> tuple[float, float]:
    """A figure's narrowest panel and smallest font as displayed (CSS px)."""
    return (f["displayed"] * f["fraction"],
            f["fontPt"] * f["dpi"] / 72 * f["displayed"] / f["natural"])



def check_registry_figures(res, found: list[dict], narrow: list[dict]) -> None:
    """Each registry figure at a 1280 px window (``found``, :data:`FIGURES_JS` evaluated at
    FIGURE_VIEWPORT): numbered, alt text, linked to its full resolution, its data downloadable,
    every panel >= MIN_PANEL_PX wide and its smallest font >= MIN_FONT_PX as displayed (font pt
    x dpi/72 x displayed/natural width). At a 400 px window (``narrow``, at NARROW_VIEWPORT) the
    same sizes, the image wider than the column then scrolling sideways in its own box inside
    the column. Both are measured with every collapsed block open (after :func:`check_layout`
    at that window)."""
    narrow = {f["id"]: f for f in narrow}
    if found:
        FIGURE_STATS["pages"] += 1
    for f in found:
        FIGURE_STATS["figures"] += 1
        where = f"page {res.path}: figure {f['id']}"
        if not f["hasImg"] or not f["hasFacts"]:
            res.problems.append(f"{where}: no image or no figure facts")
            continue
        if not f["number"].strip():
            res.problems.append(f"{where}: no figure number")
        if len(f["alt"]) < 40 or re.fullmatch(r"[0-9a-f]{16,}(\.png)?", f["alt"]):
            res.problems.append(f"{where}: alt text does not describe it: {f['alt'][:60]!r}")
        if not f["linked"]:
            res.problems.append(f"{where}: image not linked to its full resolution")
        for x in f["links"]:  # asked from here, not from the page: no browser request events
            try:
                with urllib.request.urlopen(urllib.request.Request(x["url"], method="HEAD"),
                                            timeout=10) as r:
                    x["status"] = r.status
            except OSError as exc:
                x["status"] = str(exc)
        if not f.get("book") and (len(f["links"]) < 2
                                  or any(x["status"] != 200 for x in f["links"])):
            res.problems.append(f"{where}: data downloads missing or broken: {f['links']}")
        if not f.get("natural"):
            continue
        n = narrow.get(f["id"])
        if not n or not n.get("natural"):
            res.problems.append(f"{where}: not measured at {NARROW_VIEWPORT['width']} px")
            continue
        for (panel, font), at, keys in (
                (_sizes(f), FIGURE_VIEWPORT["width"], ("min_panel_px", "min_font_px")),
                (_sizes(n), NARROW_VIEWPORT["width"], ("narrow_panel_px", "narrow_font_px"))):
            for key, v in zip(keys, (panel, font), strict=True):
                old = FIGURE_STATS[key]
                FIGURE_STATS[key] = v if old is None else min(old, v)
            if panel < MIN_PANEL_PX:
                res.problems.append(f"{where}: a panel is {panel:.0f} px wide at {at} px "
                                    f"(< {MIN_PANEL_PX})")
            if font < MIN_FONT_PX:
                res.problems.append(f"{where}: smallest font {font:.1f} px as displayed at "
                                    f"{at} px (< {MIN_FONT_PX})")
        if n["displayed"] > NARROW_VIEWPORT["width"] - 20:  # wider than a phone's column
            if n["boxScrolls"] and n["boxInside"]:
                FIGURE_STATS["narrow_scrolling"] += 1
            else:
                res.problems.append(f"{where}: at {NARROW_VIEWPORT['width']} px the image "
                                    f"({n['displayed']:.0f} px) is not in a box that scrolls "
                                    "inside the column")


def registry_figure_summary() -> str:
    s = FIGURE_STATS
    if not s["figures"]:
        return "registry figures: none found"
    return (f"registry figures: {s['figures']} on {s['pages']} pages; narrowest panel "
            f"{s['min_panel_px']:.0f} px (>= {MIN_PANEL_PX}), smallest font "
            f"{s['min_font_px']:.1f} px (>= {MIN_FONT_PX}) at 1280 px; at "
            f"{NARROW_VIEWPORT['width']} px {s['narrow_panel_px']:.0f} px and "
            f"{s['narrow_font_px']:.1f} px, {s['narrow_scrolling']} in a box that scrolls "
            "sideways")
# ------------------------------------------------------------ end of registry figures block


def merge_figure_stats(other: dict) -> None:
    """Add another browser's :data:`FIGURE_STATS` to this process's."""
    for key in ("figures", "pages", "narrow_scrolling"):
        FIGURE_STATS[key] += other[key]
    for key in ("min_panel_px", "min_font_px", "narrow_panel_px", "narrow_font_px"):
        vals = [v for v in (FIGURE_STATS[key], other[key]) if v is not None]
        FIGURE_STATS[key] = min(vals) if vals else None
