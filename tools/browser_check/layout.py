"""Clipped content and page height: the layout of a page at 1280 px and at 400 px.

Every page is laid out at 1280 px (VIEWPORT). In the main text column
(``article.bd-article``) every block element of the kinds in _OVERFLOW_SELECTOR is measured
after all collapsed blocks (``<details>``, toggled admonitions) were opened: it is *clipped*
when its content is wider than its own box (``scrollWidth > clientWidth``) or its box sticks
out of the column. Only the outermost clipped element of a nest is counted. The one exception
is a code listing the page marks as scrollable (class ``fc-scroll-code``, set by
book/_ext/scroll_code.py) whose ``<pre>`` really scrolls (``overflow-x: auto|scroll``):
counted apart. At 1280 px such a listing is still a problem (a code line is never cut at the
column's edge: chapters keep their code within 79 characters, tools/lint_chapters.py); at
400 px it scrolls in its box. The page's height at 1280 px (collapsed blocks closed) is at
most MAX_PAGE_HEIGHT.

Every page is then laid out at 400 px (NARROW_VIEWPORT, a phone) and measured again. There,
content wider than its box may also sit in a box that scrolls sideways (``overflow-x:
auto|scroll``, the element itself or an ancestor in the column) and does not itself stick out
of the column: a table of numbers, a long display equation, a figure kept at its legible
width. Such elements are counted apart ("in a scrolling box"); anything else is clipped.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from headless import VIEWPORT

NARROW_VIEWPORT = {"width": 400, "height": 900}  # a phone
#: No page is taller than this at 1280 px (CSS px, collapsed blocks closed): about 67 screens.
MAX_PAGE_HEIGHT = 60_000
LAYOUT_VIEWPORTS = (VIEWPORT, NARROW_VIEWPORT)
SCROLL_CODE_CLASS = "fc-scroll-code"
_OVERFLOW_SELECTOR = ", ".join([
    "table", "pre", "div.math", "mjx-container", "p", "dt", "dd", "li",
    "div.cell_output", "div.output", "blockquote", "h1", "h2", "h3", "h4", "h5", "h6",
    "figure", "img", "div.admonition", "div.highlight", "div.proof", "div.exercise",
])

# Runs in a loaded (and typeset) page; returns the clipped elements and the scrollable code.
_OVERFLOW_JS = r"""
async ([selector, scrollClass, boxes]) => {
  const STATEMENTS = ['theorem', 'lemma', 'proposition', 'corollary', 'definition',
                      'conjecture', 'criterion'].map(k => 'div.proof.' + k).join(', ');
  document.querySelectorAll('details').forEach(d => { d.open = true; });
  document.querySelectorAll('.toggle-hidden').forEach(e => e.classList.remove('toggle-hidden'));
  await new Promise(done => requestAnimationFrame(() => requestAnimationFrame(done)));
  const main = document.querySelector('article.bd-article') || document.querySelector('main');
  if (!main) return {clipped: [], scrollable: 0, measured: 0, column: 0, inBox: 0, scrolled: []};
  const col = main.getBoundingClientRect();
  const flagged = [];
  const clipped = [];
  const scrolled = [];  // code listings wider than their box (the first three)
  let scrollable = 0, measured = 0, inBox = 0;
  const scrollBox = el => {  // the nearest box (el or an ancestor in the column) that scrolls
    for (let e = el; e && e !== main.parentElement; e = e.parentElement) {
      if (/^(auto|scroll)$/.test(getComputedStyle(e).overflowX)) return e;
    }
    return null;
  };
  for (const el of main.querySelectorAll(selector)) {
    const cs = getComputedStyle(el);
    if (cs.display === 'none' || cs.display === 'inline' || cs.visibility === 'hidden') continue;
    const r = el.getBoundingClientRect();
    if (r.width === 0 && r.height === 0) continue;
    measured += 1;
    if (flagged.some(f => f.contains(el))) continue;
    // inline math: its glyphs overhang its own box by a few px (scripts, accents); only a
    // formula that sticks out of the column is clipped
    const inlineMath = el.tagName === 'MJX-CONTAINER' && el.getAttribute('display') !== 'true';
    const inner = inlineMath ? 0 : el.scrollWidth - el.clientWidth;
    const outer = Math.max(r.right - col.right, col.left - r.left);
    // a formula wider than its line scrolls in its own box (book/_static/wide-math.js): fine
    // at 400 px, clipped at 1280 px (no formula may need it there)
    const wide = inlineMath && el.classList.contains('fc-wide-math');
    // a theorem's statement is read without scrolling sideways, on a phone too
    const statement = el.closest(STATEMENTS);
    if (wide && boxes && !statement) {
      inBox += 1;
      flagged.push(el);
      continue;
    }
    // in a statement, a wide inline formula counts only if its own box really scrolls
    const scrolls = wide && statement ? el.scrollWidth - el.clientWidth > 1 : wide;
    if (inner <= 1 && outer <= 1 && !scrolls) continue;
    const code = el.closest('.' + scrollClass);
    const pre = code && (el.tagName === 'PRE' ? el : el.querySelector('pre'));
    if (code && pre && /^(auto|scroll)$/.test(getComputedStyle(pre).overflowX)) {
      scrollable += 1;
      flagged.push(el);
      if (scrolled.length < 3) {
        const line = (pre.textContent || '').split('\n')
          .reduce((a, b) => (b.length > a.length ? b : a), '');
        scrolled.push({excess: Math.round(inner), text: line.trim().slice(0, 70)});
      }
      continue;
    }
    flagged.push(el);
    const box = boxes && !statement ? scrollBox(el) : null;
    if (box) {
      const b = box.getBoundingClientRect();
      if (b.right - col.right <= 1 && col.left - b.left <= 1) { inBox += 1; continue; }
    }
    const cls = (el.getAttribute('class') || '').split(/\s+/).slice(0, 3).join('.');
    clipped.push({what: el.tagName.toLowerCase() + (cls ? '.' + cls : ''),
                  excess: Math.round(Math.max(inner, outer)), width: Math.round(r.width),
                  text: (el.textContent || '').replace(/\s+/g, ' ').trim().slice(0, 70)});
  }
  return {clipped, scrollable, scrolled, inBox, measured, column: Math.round(col.width)};
}
"""



_SETTLE_JS = """async () => {
  await new Promise(done => requestAnimationFrame(() => requestAnimationFrame(done)));
  if (window.fcMathSettled) await window.fcMathSettled();
}"""


def resize(page, viewport: dict) -> None:
    """Set the window to ``viewport`` and wait until the page's formulas are broken again for
    the new width (book/_static/wide-math.js: MathJax 4 breaks displays at the width the page
    had when it was typeset)."""
    page.set_viewport_size(viewport)
    page.evaluate(_SETTLE_JS)


def _at(page, viewport: dict, js):
    """Evaluate ``js`` (a script, or a function of no argument) with the window at
    ``viewport``, then put the window back."""
    before = page.viewport_size
    if before != viewport:
        resize(page, viewport)
    try:
        return js() if callable(js) else page.evaluate(js)
    finally:
        if before is not None and before != viewport:
            resize(page, before)


@dataclass
class LayoutResult:
    """What the layout check found on one page."""

    path: str
    clipped: list[dict] = field(default_factory=list)
    scrollable_code: int = 0
    measured: int = 0
    column: int = 0
    width: int = VIEWPORT["width"]
    in_box: int = 0
    scrolled: list[dict] = field(default_factory=list)
    height: int = 0

    def line(self) -> str:
        boxed = f", {self.in_box} in a scrolling box" if self.width != VIEWPORT["width"] else ""
        return (f"    layout {self.path} at {self.width} px: {len(self.clipped)} clipped, "
                f"{self.scrollable_code} scrollable code{boxed}, {self.measured} elements "
                f"measured in a {self.column} px column")

    def problems(self) -> list[str]:
        out = [f"page {self.path}: content wider than its box at {self.width} px: "
               f"{c['what']} ({c['width']} px, {c['excess']} px too wide): {c['text']!r}"
               for c in self.clipped]
        if self.width == VIEWPORT["width"]:
            # at 1280 px a code listing fits its box: no line is cut at the column's edge
            out += [f"page {self.path}: {self.scrollable_code} code listing(s) wider than "
                    f"their box at {self.width} px, e.g. {c['excess']} px too wide: "
                    f"{c['text']!r}" for c in self.scrolled[:1]]
            if self.height > MAX_PAGE_HEIGHT:
                out.append(f"page {self.path}: {self.height} px tall at {self.width} px "
                           f"(> {MAX_PAGE_HEIGHT}): split it")
        return out


def check_layout(page, path: str, viewport: dict = VIEWPORT) -> LayoutResult:
    """Measure the clipped elements of the page that is loaded (and typeset) in ``page``, with
    the window at ``viewport``; below 1280 px a box that scrolls sideways holds its content."""
    boxes = viewport["width"] != VIEWPORT["width"]

    def measure():
        # the height as the reader first sees it (collapsed blocks closed), then the layout
        height = page.evaluate("() => document.documentElement.scrollHeight")
        return height, page.evaluate(_OVERFLOW_JS, [_OVERFLOW_SELECTOR, SCROLL_CODE_CLASS,
                                                    boxes])

    height, info = _at(page, viewport, measure)
    return LayoutResult(path, info["clipped"], info["scrollable"], info["measured"],
                        info["column"], viewport["width"], info["inBox"], info["scrolled"],
                        int(height))


def layout_summary(results: list[LayoutResult]) -> str:
    lines = []
    for width in sorted({r.width for r in results}, reverse=True):
        rs = [r for r in results if r.width == width]
        pages = sum(1 for r in rs if r.clipped)
        boxed = (f", {sum(r.in_box for r in rs)} elements in a scrolling box"
                 if width != VIEWPORT["width"] else "")
        tall = max(rs, key=lambda r: r.height)
        lines.append(f"layout: {sum(len(r.clipped) for r in rs)} clipped elements on {pages} "
                     f"of {len(rs)} pages at {width} px, "
                     f"{sum(r.scrollable_code for r in rs)} code listings wider than their "
                     f"box{boxed}; tallest page {tall.height} px ({tall.path})")
    return "\n".join(lines)

