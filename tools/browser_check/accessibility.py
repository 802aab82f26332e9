"""Accessibility: axe-core's WCAG 2 A and AA rules, and the keyboard focus of every control.

axe-core (tools/vendor/axe.min.js, vendored from npm: no network at test time) runs on every
page, the WCAG 2 A and AA rules only, in the theme's light colours and its colour rules again
in the dark ones (:func:`axe_violations`, :func:`check_accessibility`); every visible control
takes the keyboard focus and shows it (:func:`check_focus`). Totals across the pages of one
run are kept in :data:`AXE_STATS` (:func:`axe_summary`).
"""

from __future__ import annotations

import time
from pathlib import Path

from .result import PageResult

AXE_JS = Path(__file__).resolve().parents[1] / "vendor" / "axe.min.js"
AXE_TAGS = ["wcag2a", "wcag2aa"]
#: The rules whose outcome depends on the colours: the only ones run again in the dark theme
#: (names, roles and ARIA are the same markup in both).
AXE_COLOUR_RULES = ["color-contrast", "link-in-text-block"]
THEMES = ("light", "dark")
#: seconds spent in axe (injecting it and its runs), runs, and per "rule theme impact" the
#: elements and the pages found; merged from every browser (:func:`merge_axe_stats`)
AXE_STATS: dict = {"seconds": 0.0, "runs": 0, "pages": 0, "rules": {}}

#: Markup that is the same on every page, whatever the page says: MathJax's typeset output
#: (most of a math page's elements: 9 690 of 15 329 on the vector chapter) and the highlighted
#: code listings (one element per token; outputs are not among them), whose colours come from
#: MathJax's and Pygments' stylesheets. Each browser checks them on the first page that has
#: them; on the others axe runs with them set aside (and put back): on the zheng2014 results
#: chapter, 2.9 s of axe with them, 1.0 s without.
AXE_UNIFORM = {"math": "mjx-container",
               "code": "div.highlight:not(.cell_output div.highlight)"}

# Runs axe in the page in one theme of pydata-sphinx-theme (``data-theme`` and ``data-mode`` on
# <html>, as its theme switch sets them), with the elements ``aside`` selects set aside, then
# puts the page back as it was.
_AXE_JS = r"""
async ([theme, options, aside]) => {
  const root = document.documentElement;
  const was = {theme: root.dataset.theme, mode: root.dataset.mode};
  const still = document.createElement('style');  // colours read at once, not mid-transition
  still.textContent = '*, *::before, *::after { transition: none !important; }';
  document.head.appendChild(still);
  root.dataset.theme = theme;
  root.dataset.mode = theme;
  const parked = [];
  if (aside) {
    for (const el of document.querySelectorAll(aside)) {
      if (!el.isConnected) continue;  // inside another one set aside
      const mark = document.createComment('mjx');
      el.replaceWith(mark);
      parked.push([mark, el]);
    }
  }
  try {
    const result = await axe.run(document, options);
    return result.violations.map(v => ({
      id: v.id, impact: v.impact || '', help: v.help, count: v.nodes.length,
      nodes: v.nodes.slice(0, 3).map(n => ({target: n.target.join(' '),
        why: (n.failureSummary || '').split('\n').slice(1, 2).join(' ').trim().slice(0, 160)}))}));
  } finally {
    for (const [mark, el] of parked) mark.replaceWith(el);
    for (const key of ['theme', 'mode']) {
      if (was[key] === undefined) delete root.dataset[key]; else root.dataset[key] = was[key];
    }
    still.remove();
  }
}
"""


def axe_violations(page, *, aside: str | None = None) -> list[dict]:
    """Run axe-core's WCAG 2 A/AA rules on the page loaded in ``page``: every rule in the
    light theme, the colour rules (:data:`AXE_COLOUR_RULES`) again in the dark one. Returns
    the violations, each ``{"id", "impact", "help", "count", "nodes", "theme"}``.
    ``aside``: a CSS selector of elements set aside during the runs (see
    :data:`AXE_UNIFORM`). Raises ``FileNotFoundError`` if the vendored axe is missing."""
    if not AXE_JS.is_file():
        raise FileNotFoundError(f"{AXE_JS} missing (vendored axe-core: see tools/vendor/)")
    t0 = time.monotonic()
    if not page.evaluate("() => typeof window.axe === 'object'"):
        page.add_script_tag(path=str(AXE_JS))
    found = []
    for theme in THEMES:
        rules = ({"type": "tag", "values": AXE_TAGS} if theme == "light"
                 else {"type": "rule", "values": AXE_COLOUR_RULES})
        options = {"runOnly": rules, "resultTypes": ["violations"]}
        for v in page.evaluate(_AXE_JS, [theme, options, aside]):
            found.append({**v, "theme": theme})
        AXE_STATS["runs"] += 1
    AXE_STATS["seconds"] += time.monotonic() - t0
    return found


def check_accessibility(page, res: PageResult, *, seen: set[str] | None = None) -> None:
    """The axe findings of the page loaded in ``page``, as problems of ``res`` (and counted in
    :data:`AXE_STATS`). ``seen``: the kinds of :data:`AXE_UNIFORM` already checked by this
    browser, set aside here; the kinds this page has are added to it."""
    seen = set() if seen is None else seen
    kinds = [k for k in AXE_UNIFORM if k not in seen
             and page.evaluate("(s) => !!document.querySelector(s)", AXE_UNIFORM[k])]
    aside = ", ".join(AXE_UNIFORM[k] for k in sorted(seen)) or None
    seen.update(kinds)
    try:
        found = axe_violations(page, aside=aside)
    except FileNotFoundError as exc:
        res.problems.append(f"page {res.path}: accessibility not checked: {exc}")
        return
    AXE_STATS["pages"] += 1
    for v in found:
        key = f"{v['id']} {v['theme']} {v['impact']}"
        elements, pages = AXE_STATS["rules"].setdefault(key, [0, []])
        AXE_STATS["rules"][key][0] = elements + v["count"]
        pages.append(res.path)
        first = v["nodes"][0] if v["nodes"] else {"target": "?", "why": ""}
        res.problems.append(f"page {res.path}: accessibility ({v['theme']} theme): "
                            f"{v['id']} ({v['impact']}, {v['count']} elements: {v['help']}), "
                            f"e.g. {first['target']}: {first['why']}")


def merge_axe_stats(other: dict) -> None:
    """Add another browser's :data:`AXE_STATS` to this process's."""
    for key in ("seconds", "runs", "pages", "focus_tried"):
        AXE_STATS[key] = AXE_STATS.get(key, 0) + other.get(key, 0)
    for rule, (elements, pages) in other.get("rules", {}).items():
        mine = AXE_STATS["rules"].setdefault(rule, [0, []])
        mine[0] += elements
        mine[1].extend(pages)


def axe_summary() -> str:
    s = AXE_STATS
    head = (f"accessibility: axe-core WCAG 2 A/AA on {s['pages']} pages, light and dark "
            f"themes ({s['runs']} runs, {s['seconds']:.1f} s); keyboard focus visible on "
            f"{s.get('focus_tried', 0)} controls tried")
    if not s["rules"]:
        return head + ": no violation"
    return head + "; " + "; ".join(
        f"{rule}: {elements} elements on {len(set(pages))} pages"
        for rule, (elements, pages) in sorted(s["rules"].items()))


# Every visible control a reader reaches with the Tab key (toggles, buttons, dropdowns, tabs):
# focused as the keyboard focuses it, it is the active element and draws an outline or a
# shadow. Returns the controls that do not (at most 3 described) and how many were tried.
_FOCUS_JS = r"""
() => {
  const sel = 'summary, button, [role="tab"], .dropdown-toggle, input, select, textarea';
  const bad = [];
  let tried = 0;
  for (const el of document.querySelectorAll(sel)) {
    if (el.disabled || el.tabIndex < 0 || el.closest('[inert], [aria-hidden="true"]')) continue;
    const r = el.getBoundingClientRect();
    const cs = getComputedStyle(el);
    if (!r.width || !r.height || cs.visibility === 'hidden') continue;
    tried += 1;
    el.focus({focusVisible: true});
    const now = getComputedStyle(el);
    const ring = (now.outlineStyle !== 'none' && parseFloat(now.outlineWidth) > 0)
      || (now.boxShadow !== 'none' && !/^rgba\(0, 0, 0, 0\)/.test(now.boxShadow));
    if (document.activeElement !== el || !ring) {
      bad.push((el.getAttribute('aria-label') || el.textContent || el.tagName).trim()
        .replace(/\s+/g, ' ').slice(0, 50) + (document.activeElement !== el
        ? ' (cannot take the focus)' : ' (no visible focus)'));
    }
  }
  if (document.activeElement) document.activeElement.blur();
  window.scrollTo(0, 0);
  return {bad, tried};
}
"""


def check_focus(page, res: PageResult) -> None:
    """Every visible control of the page takes the keyboard focus and shows it (WCAG 2.4.7)."""
    found = page.evaluate(_FOCUS_JS)
    AXE_STATS["focus_tried"] = AXE_STATS.get("focus_tried", 0) + found["tried"]
    if found["bad"]:
        res.problems.append(f"page {res.path}: {len(found['bad'])} of {found['tried']} controls "
                            f"show no keyboard focus, e.g. {found['bad'][:3]}")
