"""The reader's page as it loads: HTTP status, failed requests, the icon, images and MathJax.

:func:`check_page` loads one page in a browser page and records in a :class:`PageResult` what
a reader would see broken there: an answer other than 200, a meta-refresh redirect that is not
followed, a missing or unserved icon (:func:`check_favicon`), an image that did not load, and
on pages whose served HTML has math elements (counted by :class:`MathCounter`) MathJax not
starting, math left untypeset, raw TeX delimiters, TeX errors, undefined macros and its woff
fonts not loaded from the site. :func:`list_pages` says which files of the site are pages.
"""

from __future__ import annotations

import re
import time
import urllib.request
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import urlsplit

from headless import LOCAL_HOST

from .explorables import check_explorables
from .result import PageResult

NAV_TIMEOUT_MS = 30_000
MATHJAX_TIMEOUT_MS = 20_000
# Not pages: the theme's Jinja macro files that Sphinx copies into _static, source copies, and
# the listing of the library's wheel (_wheels/index.html, written by tools/site_wheel.py).
SKIP_DIRS = {"_static", "_sources", "_wheels"}
RAW_TEX = ("\\(", "\\)", "\\[", "\\]", "$$")


class MathCounter(HTMLParser):
    """Count the elements of the served HTML whose class list contains the token ``math``."""

    def __init__(self) -> None:
        super().__init__()
        self.count = 0
        self.refresh_target: str | None = None

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        a = {k: (v or "") for k, v in attrs}
        if "math" in a.get("class", "").split():
            self.count += 1
        if tag == "meta" and a.get("http-equiv", "").lower() == "refresh":
            m = re.search(r"url\s*=\s*(\S+)", a.get("content", ""), re.I)
            if m:
                self.refresh_target = m.group(1).strip("'\"")


def list_pages(html_dir: Path) -> list[Path]:
    return sorted(
        p for p in html_dir.rglob("*.html")
        if not (set(p.relative_to(html_dir).parts[:-1]) & SKIP_DIRS)
    )


# Runs in the page once it has loaded: wait for every image (lazy ones are made eager first).
_IMAGES_JS = """
async () => {
  const imgs = Array.from(document.images);
  for (const img of imgs) { if (img.loading === 'lazy') img.loading = 'eager'; }
  await Promise.all(imgs.map(img => img.complete ? null : new Promise(done => {
    img.addEventListener('load', done, {once: true});
    img.addEventListener('error', done, {once: true});
    setTimeout(done, 10000);
  })));
  return imgs.map(img => ({src: img.currentSrc || img.src,
                           ok: img.complete && img.naturalWidth > 0}));
}
"""

# Runs after MathJax.startup.promise resolved: inspect every math element.
_MATH_JS = r"""
async (rawTex) => {
  if (document.fonts && document.fonts.ready) { await document.fonts.ready; }
  const els = Array.from(document.querySelectorAll('.math'));
  const raw = [];
  for (const el of els) {
    // Text that is not inside an mjx-container is what MathJax left untouched.
    const clone = el.cloneNode(true);
    clone.querySelectorAll('mjx-container').forEach(c => c.remove());
    const left = clone.textContent;
    if (rawTex.some(d => left.includes(d))) raw.push(left.trim().slice(0, 80));
  }
  const errors = Array.from(document.querySelectorAll('mjx-merror')).map(
    e => (e.getAttribute('data-mjx-error') || e.textContent || '').slice(0, 80));
  // MathJax's noundefined extension renders an unknown macro as red text, not as an error.
  const undefinedMacros = [];
  try {
    for (const item of MathJax.startup.document.math) {
      const mml = MathJax.startup.toMML(item.root);
      for (const m of mml.matchAll(/<mtext mathcolor="red">(\\[A-Za-z]+)<\/mtext>/g)) {
        undefinedMacros.push(m[1]);
      }
    }
  } catch (e) { undefinedMacros.push('(could not inspect MathJax output: ' + e + ')'); }
  return {elements: els.length,
          containers: document.querySelectorAll('mjx-container').length,
          raw: raw, errors: errors, undefinedMacros: [...new Set(undefinedMacros)]};
}
"""


def check_page(page, url: str, res: PageResult, refresh: str | None,
                fonts: list[tuple[str, int]]) -> None:
    resp = page.goto(url, wait_until="load", timeout=NAV_TIMEOUT_MS)
    if resp is None or resp.status != 200:
        res.problems.append(f"page {res.path}: HTTP {resp.status if resp else 'no response'}")
        return
    if refresh is not None:
        # A meta-refresh redirect (the site's index.html): the target must load; it is checked
        # as a page of its own.
        target = refresh.split("#")[0]
        try:
            page.wait_for_url(lambda u: urlsplit(u).path.endswith(target),
                              timeout=NAV_TIMEOUT_MS)
            page.wait_for_load_state("load")
        except Exception as exc:  # any failure to follow is the finding
            res.problems.append(f"page {res.path}: redirect to {refresh} not followed ({exc})")
        return

    check_favicon(page, res)
    images = page.evaluate(_IMAGES_JS)
    res.images = len(images)
    res.images_ok = sum(1 for i in images if i["ok"])
    for img in images:
        if not img["ok"]:
            res.problems.append(f"page {res.path}: image did not load: {img['src']}")
    check_explorables(page, res)

    if not res.math_expected:
        return
    # If a MathJax file already failed to load, do not wait the full timeout for it.
    mathjax_broken = any("mathjax" in u.lower() for u in res.failed_urls)
    try:
        page.wait_for_function(
            "() => window.MathJax && MathJax.startup && MathJax.startup.promise",
            timeout=2_000 if mathjax_broken else MATHJAX_TIMEOUT_MS)
        page.evaluate("() => MathJax.startup.promise.then(() => true)")
    except Exception as exc:  # a timeout or a rejected promise alike
        first = str(exc).strip().splitlines()[0]
        res.problems.append(f"page {res.path}: MathJax did not start/typeset "
                            f"({res.math_expected} math elements): {first}")
        return
    info = page.evaluate(_MATH_JS, list(RAW_TEX))
    res.math_typeset = min(info["containers"], info["elements"])
    if info["elements"] < res.math_expected:
        res.problems.append(f"page {res.path}: {info['elements']} math elements in the DOM, "
                            f"{res.math_expected} in the served HTML")
    if info["containers"] < res.math_expected:
        res.problems.append(f"page {res.path}: MathJax typeset {info['containers']} of "
                            f"{res.math_expected} math elements")
    for raw in info["raw"]:
        res.problems.append(f"page {res.path}: raw TeX left visible: {raw!r}")
    for err in info["errors"]:
        res.problems.append(f"page {res.path}: MathJax TeX error: {err!r}")
    for macro in info["undefinedMacros"]:
        res.problems.append(f"page {res.path}: undefined TeX macro {macro} (shown in red)")
    # Font requests may still be settling right after typesetting.
    deadline = time.monotonic() + 5
    while not fonts and time.monotonic() < deadline:
        page.wait_for_timeout(100)
    res.fonts_loaded = sum(1 for u, s in fonts if s == 200 and urlsplit(u).hostname == LOCAL_HOST)
    if not res.fonts_loaded:
        res.problems.append(f"page {res.path}: no MathJax woff font was loaded from the site")
    for u, s in fonts:
        if s != 200:
            res.problems.append(f"page {res.path}: MathJax font {u} answered HTTP {s}")


#: A favicon's URL -> its HTTP status (asked once per run, from here, like the figure data).
_FAVICONS: dict[str, object] = {}


def check_favicon(page, res: PageResult) -> None:
    """The page declares an icon (``<link rel="icon">``) that the site serves: without one a
    browser asks for ``/favicon.ico``, which answers 404."""
    href = page.evaluate("() => { const l = document.querySelector('link[rel~=\"icon\"]'); "
                         "return l ? l.href : null; }")
    if not href:
        res.problems.append(f"page {res.path}: no <link rel=\"icon\">: browsers ask for "
                            "/favicon.ico (html.favicon in _config.yml)")
        return
    if href not in _FAVICONS:
        try:
            with urllib.request.urlopen(urllib.request.Request(href, method="HEAD"),
                                        timeout=10) as r:
                _FAVICONS[href] = r.status
        except OSError as exc:
            _FAVICONS[href] = str(exc)
    if _FAVICONS[href] != 200:
        res.problems.append(f"page {res.path}: its icon {href} answered {_FAVICONS[href]}")
# ------------------------------------------------------------------ end of accessibility block
