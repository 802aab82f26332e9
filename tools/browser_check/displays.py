"""Display equations broken by hand where one line fits (issue 48).

MathJax 4 breaks a display that is wider than its column (book/_ext/mathjax4.py), so a
display is written as one line and a reader on a phone still sees it whole. A hand-made break
that only served a narrow screen reads, at 1280 px, as a formula in a narrow column. At
1280 px, in every ``aligned`` display, a row that *continues* the row above (it starts with a
binary operator, ``+ - \\cdot \\times``, or with ``\\quad``-indented ``=``/``\\succeq``/``\\le``)
is a needless split when the row above and the continuation together are narrower than the
width MathJax measured for the display. The widths are upper bounds (the row above is measured
as the whole table's width, the continuation as its cells), so a reported split always fits.
A new line of a chain of relations (``&= ...`` with no indentation) is not a continuation, and
a display MathJax numbers itself (``\\tag``) is left alone: its label takes width that the
rows' measure does not show (leong2011's (24, printed) overflowed by 9 px as one line).
"""

from __future__ import annotations

from .result import PageResult

_SPLITS_JS = r"""
() => {
  const mj = window.MathJax;
  if (!(mj && mj.startup && mj.startup.document)) return [];
  const QUAD = String.raw`(?:\\q?quad\s*)+`;
  const CONT = new RegExp(String.raw`^\s*&\s*(?:\{\}\s*)?(?:` + QUAD +
    String.raw`(?:=|\\succeq|\\le\b)|(?:` + QUAD + String.raw`)?(?:\\cdot|\\times|\+|-))`);
  const out = [];
  for (const item of mj.startup.document.math) {
    if (!item.display || !item.typesetRoot) continue;
    // a display MathJax numbers itself (\\tag): its label takes width the rows do not show
    if (/\\tag\b/.test(item.math) || item.typesetRoot.querySelector('mjx-mlabeledtr')) continue;
    const m = item.math.match(/\\begin\{aligned\}([\s\S]*?)\\end\{aligned\}/);
    const tables = [...item.typesetRoot.querySelectorAll('mjx-mtable')]
      .filter(t => !t.querySelector('mjx-mtable'));
    if (!m || tables.length !== 1) continue;
    const rows = m[1].split(/\\\\/);
    const trs = tables[0].querySelectorAll('mjx-mtr, mjx-mlabeledtr');
    if (trs.length !== rows.length && trs.length !== rows.length - 1) continue;
    const avail = item.metrics.containerWidth;
    for (let i = 1; i < trs.length; i++) {
      if (!CONT.test(rows[i])) continue;
      const above = trs[i - 1].getBoundingClientRect().width;
      const cells = trs[i].querySelectorAll(':scope > mjx-mtd');
      let rest = 0;
      cells.forEach((c, j) => {
        if (j > 0 || cells.length === 1) rest += c.getBoundingClientRect().width;
      });
      if (above + rest <= avail - 4) {
        out.push({row: i, width: Math.round(above + rest), avail: Math.round(avail),
                  tex: rows[i].replace(/\s+/g, ' ').trim().slice(0, 60)});
        break;
      }
    }
  }
  return out;
}
"""


def needless_splits(page) -> list[dict]:
    """The displays of the loaded (typeset) page with a row that continues the row above
    although both fit one line: ``{row, width, avail, tex}`` for the first such row of each."""
    return page.evaluate(_SPLITS_JS)


def check_splits(page, res: PageResult) -> None:
    """Record each display of the page (at 1280 px) that is broken by hand where it fits."""
    for s in needless_splits(page):
        res.problems.append(f"page {res.path}: a display is broken by hand where one line fits "
                            f"({s['width']} of {s['avail']} px), row {s['row']}: {s['tex']!r}")
