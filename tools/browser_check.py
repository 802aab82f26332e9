"""Open every page of the built site in headless Chromium and check that it really renders.

    python tools/browser_check.py _build/fast/_build/html [--min-pages 8] [--min-math-pages 3]
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
  per page and in total are printed (``check_layout``);
* at 400 px (a phone), the same, except that content may also sit in a box that scrolls
  sideways inside the column (a wide table of numbers, a long equation, a figure kept at its
  legible width); each registry figure there keeps panels >= 500 px wide and fonts >= 11 px in
  such a box;
* no page (text, titles, link texts) and no title of the search index contains unrendered
  MyST or LaTeX: ``\\tilde``, ``\\text{``, ``{cite}``, ``{eq}``, ``{glue}``, ``$...$``
  (``check_markup``);
* a chapter reads as a book (``check_reading``, from the served HTML): no image in a cell's
  output outside a numbered, captioned figure; no output that prints a dict or list repr, a
  bare ``True``/``False``, ``array(`` or ``Matrix(``; no ASCII stand-in for mathematics
  (``x_hat``, ``sigma_v``, ``h^T``, ``sqrt(``) in a chapter's prose, tables, headings, captions
  or printed output; the median chapter page shows at most 80 lines of unfolded code.

Importable: ``check_site(html_dir) -> list[str]`` returns the problems (empty when all is well).
A missing browser or playwright is a problem, never a skip. Exit status 1 on any problem.
"""

from __future__ import annotations

import argparse
import functools
import http.server
import json
import os
import re
import shutil
import socketserver
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import quote, urlsplit

#: Debian's old headless shell (package chromium-headless-shell: the same Blink, no browser UI),
#: else Debian's chromium. On the fast site the shell takes 75.6 s for this check against 88.1 s
#: and 75.7 s against 87.7 s for the PDF's pages, with the same layout and figure measurements.
HEADLESS_SHELL = "/usr/lib/chromium/chromium-headless-shell"
CHROMIUM = (os.environ.get("FUSIONCENTER_CHROMIUM")
            or (HEADLESS_SHELL if os.access(HEADLESS_SHELL, os.X_OK) else None)
            or shutil.which("chromium") or "/usr/bin/chromium")
#: Chromium's resolver knows no host but the loopback (``LOCAL_HOST`` is an IP literal).
LOOPBACK_ONLY = "--host-resolver-rules=MAP * ~NOTFOUND, EXCLUDE 127.0.0.1"
CHROMIUM_ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]
INSTALL_HINT = ("install Debian's browser with `apt-get install chromium "
                "chromium-headless-shell`")
LOCAL_HOST = "127.0.0.1"
NAV_TIMEOUT_MS = 30_000
MATHJAX_TIMEOUT_MS = 20_000
# Not pages: the theme's Jinja macro files that Sphinx copies into _static, source copies, and
# the listing of the library's wheel (_wheels/index.html, written by tools/site_wheel.py).
SKIP_DIRS = {"_static", "_sources", "_wheels"}
RAW_TEX = ("\\(", "\\)", "\\[", "\\]", "$$")


@dataclass
class PageResult:
    path: str
    problems: list[str] = field(default_factory=list)
    math_expected: int = 0
    math_typeset: int = 0
    images: int = 0
    images_ok: int = 0
    fonts_loaded: int = 0
    failed_urls: list[str] = field(default_factory=list)
    explorables: int = 0
    explorables_moved: int = 0

    @property
    def ok(self) -> bool:
        return not self.problems

    def line(self) -> str:
        status = "PASS" if self.ok else "FAIL"
        math = f"math {self.math_typeset}/{self.math_expected}" if self.math_expected else "math -"
        fonts = f" mathjax-fonts {self.fonts_loaded}" if self.math_expected else ""
        moved = (f", explorable figures moved {self.explorables_moved}/{self.explorables}"
                 if self.explorables else "")
        return (f"{status} {self.path}: {math}, images {self.images_ok}/{self.images}{fonts}"
                f"{moved}")


class _MathCounter(HTMLParser):
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


class _QuietHandler(http.server.SimpleHTTPRequestHandler):
    """Serves the site. Pages (HTML) and every answer but a 200 are never cached; a static
    file answered 200 (theme CSS and JavaScript, MathJax and its fonts, images) is kept by
    Chromium for the run, so that the next page takes it, already compiled, from the cache
    instead of fetching and compiling MathJax again: on the fast site (114 pages checked and
    printed, one browser) 184.1 s -> 158.5 s, the same findings and the same text on all 619
    PDF pages. A cached answer still reaches the page's ``response`` listener, with its
    status: every math page's fonts are still counted and checked."""

    _status = 0

    def log_message(self, format: str, *args: object) -> None:
        pass

    def send_response(self, code, message=None) -> None:
        self._status = code
        super().send_response(code, message)

    def end_headers(self) -> None:
        path = urlsplit(self.path).path
        page = path.endswith((".html", "/")) or "." not in path.rsplit("/", 1)[-1]
        self.send_header("Cache-Control", "no-store" if page or self._status != 200
                         else "max-age=3600")
        super().end_headers()


class _Server(socketserver.ThreadingMixIn, http.server.HTTPServer):
    daemon_threads = True
    allow_reuse_address = True


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


def _launch(playwright):
    if not Path(CHROMIUM).exists():
        raise FileNotFoundError(f"{CHROMIUM} not found")
    # every host but the loopback fails to resolve at once, inside Chromium: an external
    # request is reported by the "request" listener of check_site and cannot reach anything
    return playwright.chromium.launch(
        executable_path=CHROMIUM, args=[*CHROMIUM_ARGS, LOOPBACK_ONLY], headless=True)


#: Browsers that check the pages side by side: ``FUSIONCENTER_BROWSER_WORKERS``, else 2 (one
#: per core of the 2-core machine). One Chromium uses about 1.3 cores on this check (218 s of
#: CPU in 173 s on the fast site, 114 pages printed too), so in ``make test``, where the library
#: stage shares the cores, a second browser takes up the core the first leaves idle.
WORKERS_ENV = "FUSIONCENTER_BROWSER_WORKERS"


def default_workers() -> int:
    """:data:`WORKERS_ENV` if set (a positive integer), else 2."""
    raw = os.environ.get(WORKERS_ENV, "").strip()
    if not raw:
        return 2
    try:
        n = int(raw)
    except ValueError:
        n = 0
    if n < 1:
        raise ValueError(f"{WORKERS_ENV} must be a positive integer, got {raw!r}")
    return n


class _NoBrowser(Exception):
    """Chromium could not be started: the message is the problem to report."""


def check_site(
    html_dir: str | os.PathLike[str],
    *,
    min_pages: int = 0,
    min_math_pages: int = 0,
    min_images: int = 0,
    log: Callable[[str], None] | None = None,
    printer=None,
    workers: int | None = None,
) -> list[str]:
    """Check every page of ``html_dir`` in headless Chromium; return the list of problems.

    With ``printer`` (a ``tools/pdf_book.py`` ``Printer``), every page of the book's table of
    contents is also printed once its checks are done, from the same load, and the PDF is
    written at the end: ``make test`` loads and typesets the site once for both.

    ``workers`` browsers (default :func:`default_workers`) check every ``workers``-th page
    each, side by side: this process drives the first, a ``--part`` child process of this
    script each of the others, against the same local server (so the printed links name the
    same origin); the children's findings and printed pages are merged here, and the report,
    the checks on the totals and the PDF are the same as with one browser."""
    html_dir = Path(html_dir).resolve()
    say = log or (lambda _msg: None)
    if not (html_dir / "index.html").is_file():
        return [f"{html_dir}: no index.html (build the site first)"]
    workers = default_workers() if workers is None else workers
    if workers < 1:
        raise ValueError(f"workers must be at least 1, got {workers}")
    pages = list_pages(html_dir)
    workers = max(1, min(workers, len(pages)))
    FIGURE_STATS.update(figures=0, pages=0, min_panel_px=None, min_font_px=None,
                        narrow_panel_px=None, narrow_font_px=None, narrow_scrolling=0)
    AXE_STATS.update(seconds=0.0, runs=0, pages=0, rules={}, focus_tried=0)

    try:
        import playwright.sync_api  # noqa: F401
    except ImportError as exc:
        return [f"playwright is not importable ({exc}); install the Python package `playwright` "
                f"in the environment and {INSTALL_HINT} (browser check cannot run)"]

    handler = functools.partial(_QuietHandler, directory=str(html_dir))
    server = _Server((LOCAL_HOST, 0), handler)
    port = server.server_address[1]
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    base = f"http://{LOCAL_HOST}:{port}/"

    site_problems: list[str] = []
    children: list[tuple[int, subprocess.Popen, Path]] = []
    parts_dir = Path(tempfile.mkdtemp(prefix="browser-check-")) if workers > 1 else None
    try:
        for k in range(1, workers):
            out = parts_dir / str(k)
            cmd = [sys.executable, str(Path(__file__).resolve()), str(html_dir), "--part",
                   f"{k}/{workers}", "--base", base, "--part-out", str(out)]
            if printer is not None:
                cmd += ["--print-to", str(printer.out)]
            with (parts_dir / f"{k}.err").open("wb") as err:
                children.append((k, subprocess.Popen(cmd, stdout=subprocess.DEVNULL,
                                                     stderr=err), out))

        extra_results: list[PageResult] = []
        extra_layouts: list[LayoutResult] = []

        def finish(page) -> None:
            """The other browsers' findings and printed pages, then the PDF (in ``page``)."""
            from playwright.sync_api import Error as PlaywrightError

            for k, proc, out in children:
                rc = proc.wait()
                found = _read_part(out)
                if rc != 0 or found is None:
                    err = (out.parent / f"{k}.err").read_text(errors="replace").strip()
                    site_problems.append(f"browser worker {k + 1} of {workers} failed (exit "
                                         f"{rc}): {err.splitlines()[-1] if err else 'no output'}")
                    continue
                part_results, part_layouts, part_problems, stats, lines = found
                extra_results.extend(part_results)
                extra_layouts.extend(part_layouts)
                site_problems.extend(part_problems)
                _merge_figure_stats(stats)
                for line in lines:
                    say(line)
                if printer is not None:
                    try:
                        printer.load(out / "print")
                    except (OSError, ValueError) as exc:
                        site_problems.append(f"browser worker {k + 1} of {workers}: its printed "
                                             f"pages not merged: {exc}")
            if printer is not None:
                try:
                    stats = printer.write(page)
                    say(f"pdf: wrote {printer.out} ({stats['total_pages']} pages, "
                        f"{stats['chapters']} chapters, {stats['bytes'] / 1e6:.1f} MB)")
                    if stats["raw_math"]:
                        site_problems.append(f"PDF: {stats['raw_math']} math elements left "
                                             "untypeset")
                except (PlaywrightError, RuntimeError) as exc:
                    site_problems.append(f"PDF not written: {exc}")

        try:
            results, layouts, problems = _browse(base, html_dir, pages[0::workers], printer,
                                                 say, finish)
        except _NoBrowser as exc:
            return [str(exc)]
        results += extra_results
        layouts += extra_layouts
        site_problems[:0] = problems
    finally:
        for _k, proc, _out in children:
            if proc.poll() is None:
                proc.kill()
                proc.wait()
        server.shutdown()
        server.server_close()
        if parts_dir is not None:
            shutil.rmtree(parts_dir, ignore_errors=True)

    order = {p.relative_to(html_dir).as_posix(): i for i, p in enumerate(pages)}
    results.sort(key=lambda r: order.get(r.path, len(order)))
    layouts.sort(key=lambda r: order.get(r.path, len(order)))
    missing = sorted(set(order) - {r.path for r in results}, key=order.get)
    if missing and not any(p.startswith("browser worker") for p in site_problems):
        site_problems.append(f"{len(missing)} pages not checked: {missing[:5]}")
    math_pages = sum(1 for r in results if r.math_expected and r.math_typeset)
    images = sum(r.images_ok for r in results)
    if len(results) < min_pages:
        site_problems.append(f"only {len(results)} pages checked, expected at least {min_pages}")
    if math_pages < min_math_pages:
        site_problems.append(f"only {math_pages} pages with typeset math, "
                             f"expected at least {min_math_pages}")
    if images < min_images:
        site_problems.append(f"only {images} images loaded, expected at least {min_images}")
    say(layout_summary(layouts))
    markup_problems, markup_counts = check_markup(html_dir)
    say(f"markup: {sum(markup_counts.values())} pieces of unrendered MyST/LaTeX in "
        f"{sum(1 for v in markup_counts.values() if v)} of {len(markup_counts)} files "
        "(pages and searchindex.js)")
    site_problems += markup_problems
    reading_problems, code_lines = check_reading(html_dir)
    if code_lines:
        import statistics

        worst = max(code_lines, key=code_lines.get)
        say(f"reading: {len(code_lines)} chapter pages, unfolded code lines median "
            f"{statistics.median(code_lines.values()):g}, most {code_lines[worst]} ({worst}); "
            f"{len(reading_problems)} problems (loose images, reprs, ASCII mathematics)")
    site_problems += reading_problems
    n_ok = sum(r.ok for r in results)
    say(f"{len(results)} pages, {math_pages} with typeset math, {images} images loaded")
    say(registry_figure_summary())
    say(axe_summary())
    for prob in site_problems:
        say(f"SITE: {prob}")
    say(f"browser check: {n_ok} passed, {len(results) - n_ok} failed")
    return [p for r in results for p in r.problems] + site_problems


def _browse(base: str, html_dir: Path, pages: list[Path], printer, say,
            finish: Callable | None = None) -> tuple[list, list, list[str]]:
    """Load and check ``pages`` in one headless Chromium against the server at ``base``;
    returns ``(page results, layout results, problems outside any page)`` and adds to
    :data:`FIGURE_STATS`. ``printer``: print each page of the table of contents after its
    checks. ``finish(page)`` runs last, with the browser still open (the PDF is written
    there). Raises :class:`_NoBrowser` if Chromium cannot start."""
    from playwright.sync_api import Error as PlaywrightError
    from playwright.sync_api import sync_playwright

    results: list[PageResult] = []
    layouts: list[LayoutResult] = []
    site_problems: list[str] = []
    with sync_playwright() as pw:
        try:
            browser = _launch(pw)
        except (PlaywrightError, FileNotFoundError) as exc:
            first = str(exc).strip().splitlines()[0] if str(exc).strip() else repr(exc)
            raise _NoBrowser(f"cannot start headless Chromium at {CHROMIUM}: {first}; "
                             f"{INSTALL_HINT} (browser check cannot run)") from None
        context = browser.new_context(service_workers="block", viewport=VIEWPORT)
        current: dict[str, PageResult | None] = {"page": None}
        aborted: set[str] = set()

        def on_request(req) -> None:
            # a listener, not a route: routing every request through Python cost a fifth
            # of the page loads; the request itself fails in Chromium's resolver
            url = req.url
            parts = urlsplit(url)
            if parts.scheme in ("data", "blob", "about") or parts.hostname == LOCAL_HOST:
                return
            aborted.add(url)
            res = current["page"]
            if res is not None:
                res.problems.append(f"page {res.path} requested external URL {url}")
            else:
                site_problems.append(f"external request outside any page: {url}")

        context.on("request", on_request)
        page = context.new_page()
        fonts: list[tuple[str, int]] = []

        def on_console(msg) -> None:
            res = current["page"]
            if res is None or msg.type != "error":
                return
            loc = (msg.location or {}).get("url", "")
            if any(u in msg.text or u == loc for u in aborted):
                return  # already reported as an external request
            res.problems.append(f"page {res.path}: console error: {msg.text[:300]}"
                                + (f" ({loc})" if loc else ""))

        def on_pageerror(exc) -> None:
            res = current["page"]
            if res is not None:
                res.problems.append(f"page {res.path}: uncaught JavaScript error: {exc}")

        def on_response(resp) -> None:
            res = current["page"]
            url = resp.url
            if "/mathjax/" in url and re.search(r"\.woff2?(\?|$)", url):
                fonts.append((url, resp.status))
            if res is None or resp.status < 400:
                return
            res.failed_urls.append(url)
            res.problems.append(f"page {res.path}: HTTP {resp.status} for {url}")

        def on_requestfailed(req) -> None:
            res = current["page"]
            if res is None or req.url in aborted:
                return
            res.failed_urls.append(req.url)
            res.problems.append(f"page {res.path}: request failed: {req.url} "
                                f"({req.failure})")

        page.on("console", on_console)
        page.on("pageerror", on_pageerror)
        page.on("response", on_response)
        page.on("requestfailed", on_requestfailed)

        printed = False  # the last page was printed (and left in print media)
        axe_seen: set[str] = set()  # the uniform markup axe has checked (AXE_UNIFORM)
        for path in pages:
            rel = path.relative_to(html_dir).as_posix()
            res = PageResult(rel)
            parser = _MathCounter()
            parser.feed(path.read_text(encoding="utf-8", errors="replace"))
            res.math_expected = parser.count
            if page.viewport_size != VIEWPORT or printed:
                # every page loads at 1280 px (the theme lays a page loaded at 400 px out
                # differently at 1280 px) and on screen (the printer leaves a page in print
                # media); resized on a blank page, which costs nothing
                page.goto("about:blank")
                if printed:
                    page.emulate_media(media="null")
                    printed = False
                page.set_viewport_size(VIEWPORT)
            current["page"] = res
            fonts.clear()
            try:
                _check_page(page, base + quote(rel), res, parser.refresh_target, fonts)
            except PlaywrightError as exc:
                res.problems.append(f"page {rel}: browser error: "
                                    f"{str(exc).strip().splitlines()[0]}")
            if parser.refresh_target is None:
                # 1280 px, then 400 px: one resize of the page (each resize lays the whole
                # page out again: the 112 of measuring each figure and layout at a window
                # and resizing back took 25 s of 150)
                measured: dict[int, LayoutResult] = {}
                shown: dict[int, list] = {}
                for viewport in LAYOUT_VIEWPORTS:
                    try:
                        if page.viewport_size != viewport:
                            page.set_viewport_size(viewport)
                        measured[viewport["width"]] = check_layout(page, rel, viewport)
                        shown[viewport["width"]] = page.evaluate(_FIGURES_JS)
                        if viewport == VIEWPORT:
                            # at 1280 px, every collapsed block open (check_layout): the
                            # evidence tables and solutions are read too
                            check_accessibility(page, res, seen=axe_seen)
                            check_focus(page, res)
                    except PlaywrightError as exc:
                        measured.setdefault(viewport["width"],
                                            LayoutResult(rel, width=viewport["width"]))
                        res.problems.append(f"page {rel}: layout not measured at "
                                            f"{viewport['width']} px: "
                                            f"{str(exc).strip().splitlines()[0]}")
                for viewport in LAYOUT_VIEWPORTS:
                    layouts.append(measured[viewport["width"]])
                    res.problems += measured[viewport["width"]].problems()
                check_registry_figures(res, shown.get(FIGURE_VIEWPORT["width"], []),
                                       shown.get(NARROW_VIEWPORT["width"], []))
            doc = rel.removesuffix(".html")
            if printer is not None and parser.refresh_target is None and printer.wants(doc):
                try:
                    printed = True
                    printer.add(page, doc)
                except PlaywrightError as exc:
                    res.problems.append(f"page {rel}: not printed: "
                                        f"{str(exc).strip().splitlines()[0]}")
            current["page"] = None
            res.problems = list(dict.fromkeys(res.problems))  # e.g. one 404 seen twice
            results.append(res)
            say(res.line())
            for prob in res.problems:
                say(f"    {prob}")
            if parser.refresh_target is None:
                for layout in layouts[-len(LAYOUT_VIEWPORTS):]:
                    say(layout.line())
        if finish is not None:
            finish(page)
        context.close()
        browser.close()
    return results, layouts, site_problems


def _merge_figure_stats(other: dict) -> None:
    """Add another browser's :data:`FIGURE_STATS` to this process's."""
    for key in ("figures", "pages", "narrow_scrolling"):
        FIGURE_STATS[key] += other[key]
    for key in ("min_panel_px", "min_font_px", "narrow_panel_px", "narrow_font_px"):
        vals = [v for v in (FIGURE_STATS[key], other[key]) if v is not None]
        FIGURE_STATS[key] = min(vals) if vals else None


PART_FILE = "part.json"


def _write_part(out: Path, results, layouts, problems, lines) -> None:
    """What a ``--part`` child found, for :func:`check_site` (JSON, written last)."""
    out.mkdir(parents=True, exist_ok=True)
    data = {"results": [asdict(r) for r in results], "layouts": [asdict(r) for r in layouts],
            "problems": problems, "figure_stats": FIGURE_STATS, "axe_stats": AXE_STATS,
            "lines": lines}
    tmp = out / (PART_FILE + ".tmp")
    tmp.write_text(json.dumps(data), encoding="utf-8")
    tmp.replace(out / PART_FILE)


def _read_part(out: Path):
    """``(results, layouts, problems, figure stats, log lines)`` of a child, or ``None``;
    its :data:`AXE_STATS` are added to this process's."""
    try:
        data = json.loads((out / PART_FILE).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    _merge_axe_stats(data.get("axe_stats", {}))
    return ([PageResult(**r) for r in data["results"]],
            [LayoutResult(**r) for r in data["layouts"]],
            data["problems"], data["figure_stats"], data["lines"])


def _run_part(html_dir: Path, part: str, base: str, out: Path, print_to: Path | None) -> int:
    """A ``--part K/N`` child: check every N-th page from the K-th (0-based) against the
    server at ``base``, print them if ``print_to`` (the book's PDF path: its pages go to
    ``out/print``), and write the findings to ``out``."""
    k, n = (int(x) for x in part.split("/"))
    html_dir = html_dir.resolve()
    pages = list_pages(html_dir)[k::n]
    printer = None
    if print_to is not None:
        from pdf_book import Printer

        printer = Printer(html_dir, print_to)
    lines: list[str] = []
    try:
        results, layouts, problems = _browse(base, html_dir, pages, printer, lines.append)
    except _NoBrowser as exc:
        print(exc, file=sys.stderr)
        return 1
    if printer is not None:
        printer.dump(out / "print")
    _write_part(out, results, layouts, problems, lines)
    return 0


def _check_page(page, url: str, res: PageResult, refresh: str | None,
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
    _check_explorables(page, res)

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


# ------------------------------------------------------------------ explorable figures: every
# slider of book/_ext/explorable.py, moved by the keyboard as a reader would.
_EXPLORE_STATE_JS = r"""
(i) => {
  const box = document.querySelectorAll('.fc-explore')[i];
  const img = box.querySelector('img.fc-explore-frame');
  const input = box.querySelector('input.fc-explore-slider');
  const fig = box.closest('figure') || box;
  const label = document.querySelector(`label[for="${input.id}"]`);
  return {src: img.getAttribute('src'), alt: img.alt, loaded: img.complete && img.naturalWidth > 0,
          value: box.querySelector('output.fc-explore-value').textContent,
          valuetext: input.getAttribute('aria-valuetext') || '',
          facts: Array.from(fig.querySelectorAll('.fc-explore-fact')).map(s => s.textContent),
          at: Number(input.value), max: Number(input.max), ready: box.classList.contains(
            'fc-explore-ready'), label: label ? label.textContent.trim() : '',
          focused: document.activeElement === input,
          outline: document.activeElement === input ? getComputedStyle(input).outlineStyle : ''};
}
"""


def _check_explorables(page, res: PageResult) -> None:
    """Focus every slider, press an arrow key, and see the figure, the value and the caption's
    numbers change to those of the next frame (which loads), with the focus visible."""
    n = page.evaluate("() => document.querySelectorAll('.fc-explore').length")
    res.explorables = n
    for i in range(n):
        where = f"page {res.path}: explorable figure {i + 1}"
        before = page.evaluate(_EXPLORE_STATE_JS, i)
        if not before["ready"]:
            res.problems.append(f"{where}: its script did not start (explorable.js)")
            continue
        if not before["label"]:
            res.problems.append(f"{where}: the slider has no label for a screen reader")
        key = "ArrowRight" if before["at"] < before["max"] else "ArrowLeft"
        page.locator("input.fc-explore-slider").nth(i).focus()
        page.keyboard.press(key)
        try:
            page.wait_for_function(
                "(i) => { const img = document.querySelectorAll('.fc-explore')[i]"
                ".querySelector('img.fc-explore-frame'); "
                "return img.complete && img.naturalWidth > 0; }", arg=i, timeout=5_000)
        except Exception:  # the next frame did not load: reported below
            pass
        after = page.evaluate(_EXPLORE_STATE_JS, i)
        changed = [k for k in ("src", "alt", "value", "valuetext") if after[k] != before[k]]
        if len(changed) < 4:
            res.problems.append(f"{where}: {key} did not move it (unchanged: "
                                f"{sorted({'src', 'alt', 'value', 'valuetext'} - set(changed))})")
        elif not after["loaded"]:
            res.problems.append(f"{where}: the next frame did not load ({after['src']})")
        elif before["facts"] and after["facts"] == before["facts"]:
            res.problems.append(f"{where}: the caption's numbers did not follow the slider")
        elif not after["focused"] or after["outline"] in ("", "none"):
            res.problems.append(f"{where}: the focused slider shows no visible focus")
        else:
            res.explorables_moved += 1
        page.keyboard.press("ArrowLeft" if key == "ArrowRight" else "ArrowRight")


# ---------------------------------------------------------------- registry figures (helper
# "figures"): every {registry-figure} of book/_ext/registry_figure.py, measured at 1280 px.
import urllib.request  # noqa: E402  (kept in this block)

FIGURE_VIEWPORT = {"width": 1280, "height": 900}
NARROW_VIEWPORT = {"width": 400, "height": 900}  # a phone
MIN_PANEL_PX = 500
MIN_FONT_PX = 11
FIGURE_STATS: dict = {"figures": 0, "pages": 0, "min_panel_px": None, "min_font_px": None,
                      "narrow_panel_px": None, "narrow_font_px": None, "narrow_scrolling": 0}

_FIGURES_JS = r"""
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

VIEWPORT = {"width": 1280, "height": 900}
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


def _sizes(f: dict) -> tuple[float, float]:
    """A figure's narrowest panel and smallest font as displayed (CSS px)."""
    return (f["displayed"] * f["fraction"],
            f["fontPt"] * f["dpi"] / 72 * f["displayed"] / f["natural"])


def _at(page, viewport: dict, js):
    """Evaluate ``js`` (a script, or a function of no argument) with the window at
    ``viewport``, then put the window back."""
    before = page.viewport_size
    if before != viewport:
        page.set_viewport_size(viewport)
    try:
        return js() if callable(js) else page.evaluate(js)
    finally:
        if before is not None and before != viewport:
            page.set_viewport_size(before)


def check_registry_figures(res, found: list[dict], narrow: list[dict]) -> None:
    """Each registry figure at a 1280 px window (``found``, :data:`_FIGURES_JS` evaluated at
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


# ------------------------------------------------------------------- accessibility (issue 48):
# axe-core (tools/vendor/axe.min.js, vendored from npm: no network at test time) on every page,
# the WCAG 2 A and AA rules only, in the theme's light and dark colours.
AXE_JS = Path(__file__).resolve().parent / "vendor" / "axe.min.js"
AXE_TAGS = ["wcag2a", "wcag2aa"]
#: The rules whose outcome depends on the colours: the only ones run again in the dark theme
#: (names, roles and ARIA are the same markup in both).
AXE_COLOUR_RULES = ["color-contrast", "link-in-text-block"]
THEMES = ("light", "dark")
#: seconds spent in axe (injecting it and its runs), runs, and per "rule theme impact" the
#: elements and the pages found; merged from every browser (:func:`_merge_axe_stats`)
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


def _merge_axe_stats(other: dict) -> None:
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


# Markup that must never reach the reader.
RAW_MARKUP = [
    ("TeX control word", re.compile(r"\\[A-Za-z]{2,}")),
    ("TeX delimiter", re.compile(r"\\[()\[\]]|\$\$")),
    ("MyST role", re.compile(r"\{(?:cite|cite:[tp]|eq|glue|glue:\w+|ref|doc|numref|term|math|"
                             r"index|download|prf:\w+)\}`?")),
    ("$ pair", re.compile(r"(?<![\\$\w])\$(?=[^\s$])[^$\n]{1,200}?(?<=[^\s\\$])\$(?![\w$])")),
]
# Elements whose text is not prose: math (typeset by MathJax), code, scripts.
_NOT_PROSE_TAGS = {"script", "style", "pre", "code", "kbd", "samp", "textarea", "svg",
                   "mjx-container"}
_NOT_PROSE_CLASSES = {"math", "highlight", "notranslate", "cell_input", "MathJax"}
_VOID_TAGS = {"area", "base", "br", "col", "embed", "hr", "img", "input", "link", "meta",
              "source", "track", "wbr"}


def find_raw_markup(text: str) -> list[tuple[str, str]]:
    """The (kind, excerpt) of every piece of MyST/LaTeX source in ``text``."""
    found = []
    for kind, rx in RAW_MARKUP:
        for m in rx.finditer(text):
            a, b = max(0, m.start() - 30), min(len(text), m.end() + 30)
            found.append((kind, " ".join(text[a:b].split())))
    return found


class _ProseText(HTMLParser):
    """Collect the text of an HTML page that a reader sees as prose (and the page title)."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self._stack: list[bool] = []  # per open element: is it (or an ancestor) not prose?
        self.chunks: list[str] = []
        self._buf: list[str] = []

    def _flush(self) -> None:
        if self._buf:
            self.chunks.append("".join(self._buf))
            self._buf = []

    def handle_starttag(self, tag, attrs):
        if tag in _VOID_TAGS:
            return
        a = {k: (v or "") for k, v in attrs}
        skip = (tag in _NOT_PROSE_TAGS or bool(set(a.get("class", "").split())
                                               & _NOT_PROSE_CLASSES))
        parent = self._stack[-1] if self._stack else False
        if skip != parent:
            self._flush()
        self._stack.append(parent or skip)

    def handle_endtag(self, tag):
        if tag in _VOID_TAGS:
            return
        if self._stack:
            was = self._stack.pop()
            if was != (self._stack[-1] if self._stack else False):
                self._flush()
        if tag in ("p", "a", "li", "td", "th", "title", "h1", "h2", "h3", "h4", "h5", "h6",
                   "dt", "dd", "div", "span"):
            self._flush()

    def handle_data(self, data):
        if not (self._stack and self._stack[-1]):
            self._buf.append(data)

    def close(self):
        super().close()
        self._flush()


def raw_markup_in_html(text: str) -> list[tuple[str, str]]:
    parser = _ProseText()
    parser.feed(text)
    parser.close()
    return [hit for chunk in parser.chunks for hit in find_raw_markup(chunk)]


def raw_markup_in_search_index(text: str) -> list[tuple[str, str]]:
    """Raw markup in the page and section titles of a Sphinx ``searchindex.js``."""
    import json

    start, end = text.find("{"), text.rfind("}")
    data = json.loads(text[start:end + 1])
    titles = list(data.get("titles", [])) + list(data.get("alltitles", {}))
    return [hit for t in titles for hit in find_raw_markup(t)]


def check_markup(html_dir: str | os.PathLike[str]) -> tuple[list[str], dict[str, int]]:
    """Scan every page and the search index for unrendered markup: (problems, counts)."""
    html_dir = Path(html_dir)
    problems: list[str] = []
    counts: dict[str, int] = {}
    for path in list_pages(html_dir):
        rel = path.relative_to(html_dir).as_posix()
        hits = raw_markup_in_html(path.read_text(encoding="utf-8", errors="replace"))
        counts[rel] = len(hits)
        problems += [f"page {rel}: unrendered markup ({kind}): {ex!r}" for kind, ex in hits]
    index = html_dir / "searchindex.js"
    if index.is_file():
        hits = raw_markup_in_search_index(index.read_text(encoding="utf-8"))
        counts["searchindex.js"] = len(hits)
        problems += [f"searchindex.js: unrendered markup in a title ({kind}): {ex!r}"
                     for kind, ex in hits]
    else:
        problems.append("searchindex.js missing: the search index cannot be checked")
    return problems, counts


# ============================================================================================
# A chapter reads as a book (issue 27), read from the served HTML of every chapter page
# (``book/<part>/<chapter>.html``; the API reference and the index pages are not chapters):
# images in a cell's output that are not a numbered, captioned figure; outputs printing a
# Python repr or a bare boolean; ASCII stand-ins for mathematics in prose, tables, headings,
# captions and outputs; lines of unfolded code (cells not tagged hide-input/hide-cell) before
# the Reproduction notes; doubled words in the prose ("the The", "Exercise Exercise"); numbers
# typed in the prose that an output of the same page contradicts (41.8 where it prints 41.60).
# ============================================================================================

#: The median chapter page shows at most this many non-blank lines of unfolded code before its
#: Reproduction notes (issue 46: the argument first, the audit after it).
MAX_MEDIAN_CODE_LINES = 40
#: The heading of the section that holds a chapter's audit; code after it is not counted.
NOTES_HEADING = "Reproduction notes"
#: Elements that end a run of prose: a doubled word is looked for inside one of them only.
_BLOCK_TAGS = {"p", "li", "td", "th", "dt", "dd", "h1", "h2", "h3", "h4", "h5", "h6",
               "figcaption", "caption", "div", "section", "table", "tr", "summary", "blockquote"}
#: Text that is not typed by hand: glued values, the numbers an explorable figure's slider
#: sets, section, figure and equation numbers, and the text of internal links ("Fig. 6.1").
_COMPUTED_CLASSES = ("pasted-text", "pasted-inline", "fc-explore-fact", "section-number",
                     "caption-number", "eqno", "internal")
#: Parts of a page whose typed numbers are compared with their own outputs only.
_SEGMENT_CLASSES = {"solution", "exercise", "admonition", "proof"}
#: A word written twice in a row (case-insensitive): "the The", "Exercise Exercise".
DOUBLED_WORD = re.compile(r"\b([A-Za-z]{2,})\s+\1\b", re.IGNORECASE)
#: A decimal number as text: 41.8, 0.437, -1.25 (not 3, not 1e-3's mantissa alone).
DECIMAL = re.compile(r"(?<![\w.])-?\d+\.\d+(?![\w.]*\d)")
#: Printed output that is a Python repr or a bare boolean, not a result for a reader.
REPR_OUTPUT = [
    ("bare boolean", re.compile(r"^\s*(?:True|False)\s*$|:\s*(?:True|False)\s*$", re.M)),
    ("array repr", re.compile(r"\barray\(")),
    ("Matrix repr", re.compile(r"\b(?:Immutable)?(?:Dense)?Matrix\(\[")),
    ("dict repr", re.compile(r"\{\s*'[^'\n]*'\s*:|\{\s*\"[^\"\n]*\"\s*:")),
    # three numbers or more: [a, b] is an interval, not a repr
    ("list repr", re.compile(r"\[\s*'[^'\n]*'\s*,|\[\s*-?\d[\d.e+-]*(?:\s*,\s*-?\d[\d.e+-]*)"
                             r"{2,}\s*\]|\[\s*-?\d[\d.e+-]*(?:\s+-?\d[\d.e+-]*){2,}\s*\]")),
]
#: ASCII stand-ins for mathematics (typeset them, or write Unicode: x̂, σᵥ, hᵀ, √).
_GREEK = ("alpha|beta|gamma|delta|epsilon|zeta|eta|theta|kappa|lambda|mu|nu|xi|pi|rho|sigma|"
          "tau|phi|chi|psi|omega|Gamma|Delta|Sigma|Phi|Psi|Omega|Lambda|Theta")
ASCII_MATH = [
    ("hat name", re.compile(r"\b[A-Za-z]+_hat(?![A-Za-z])|\bhat_[A-Za-z]")),
    # sigma_v, lambda_12, sigma_w2, zeta_inf, gamma^2; not an identifier (delta_for_rate)
    ("Greek name with index", re.compile(rf"\b(?:{_GREEK})(?:_\{{|_[A-Za-z0-9]{{1,2}}\b|_inf\b|"
                                         r"\^\d)")),
    ("TeX subscript", re.compile(r"\b[A-Za-z]_\{[^}\s]{1,12}\}")),
    ("transpose", re.compile(r"\b[A-Za-z]\^T\b")),
    ("sqrt", re.compile(r"\bsqrt\(")),
]


def find_repr_output(text: str) -> list[tuple[str, str]]:
    """The (kind, excerpt) of every Python repr or bare boolean in printed output ``text``."""
    return [(kind, " ".join(text[max(0, m.start() - 30):m.end() + 30].split()))
            for kind, rx in REPR_OUTPUT for m in rx.finditer(text)]


def find_doubled_words(blocks: list[str]) -> list[str]:
    """Every word written twice in a row inside one block of prose ("the The")."""
    out = []
    for block in blocks:
        text = " ".join(block.split())
        out += [" ".join(text[max(0, m.start() - 30):m.end() + 30].split())
                for m in DOUBLED_WORD.finditer(text)]
    return out


def _significant(token: str) -> int:
    return len(token.lstrip("-").replace(".", "").lstrip("0"))


def find_contradicted_numbers(typed: list[tuple[int, str]],
                              printed: list[tuple[int, str]]) -> list[str]:
    """Numbers typed in the prose that an output of the same part of the page contradicts.

    ``typed`` and ``printed`` are ``(segment, text)`` pairs: the prose and mathematics outside
    glued values, and the outputs (cell outputs, evidence tables), each with the segment of
    the page it stands in (a section, an exercise, a solution, an admonition). A decimal
    number of three or more significant digits typed in a segment is contradicted when no
    output number of that segment rounds to it at its decimals, but one lies within 2 % of it:
    "C ≈ 41.8" in a solution whose output prints 41.60.
    """
    numbers: dict[int, list[float]] = {}
    for seg, text in printed:
        numbers.setdefault(seg, []).extend(float(t) for t in DECIMAL.findall(text))
    out = []
    for seg, text in typed:
        outputs = numbers.get(seg, [])
        for token in DECIMAL.findall(text):
            if _significant(token) < 3:
                continue
            x, decimals = float(token), len(token.split(".")[1])
            if any(abs(y - x) <= 0.5 * 10.0 ** -decimals * 1.0001 for y in outputs):
                continue
            near = [y for y in outputs if y and abs(x - y) <= 0.02 * abs(y)]
            if near:
                out.append(f"{token} in the text, {near[0]:g} in an output")
    return out


def find_ascii_math(text: str) -> list[tuple[str, str]]:
    """The (kind, excerpt) of every ASCII stand-in for mathematics in ``text``."""
    return [(kind, " ".join(text[max(0, m.start() - 30):m.end() + 30].split()))
            for kind, rx in ASCII_MATH for m in rx.finditer(text)]


class _Reading(HTMLParser):
    """What a chapter page shows: unfolded code lines, output texts, output images outside a
    captioned figure, and its prose (outside math, code and outputs)."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.stack: list[tuple[str, set[str]]] = []
        self.code_lines = 0
        self.outputs: list[str] = []
        self.loose_images: list[str] = []
        self.prose: list[str] = []
        self.blocks: list[str] = []  # the prose, one string per block element
        #: (segment, text) of the prose and mathematics outside glued values, and of the
        #: outputs (cell outputs and evidence tables): :func:`find_contradicted_numbers`
        self.typed: list[tuple[int, str]] = []
        self.printed: list[tuple[int, str]] = []
        self._segments: list[tuple[int, int]] = [(0, 0)]  # (depth in the stack, segment)
        self._count = 0
        self.in_notes = False  # past the Reproduction notes' heading
        self._block: list[str] = []
        self._heading: list[str] | None = None
        self._code: list[str] | None = None
        self._out: list[str] | None = None
        self._out_depth = 0

    def _has(self, cls: str) -> bool:
        return any(cls in c for _t, c in self.stack)

    def _tag(self, tag: str) -> bool:
        return any(t == tag for t, _c in self.stack)

    def handle_starttag(self, tag, attrs):
        a = {k: (v or "") for k, v in attrs}
        classes = set(a.get("class", "").split())
        if tag == "img":
            if self._has("cell_output") and not self._tag("figure"):
                self.loose_images.append(a.get("src", "")[-40:])
            return
        if tag in _VOID_TAGS:
            return
        if tag in _BLOCK_TAGS:
            self._flush()
        if tag == "h2":
            self._heading = []
        self.stack.append((tag, classes))
        if tag == "section" or (tag == "div" and classes & _SEGMENT_CLASSES) or (
                tag == "details" and "fc-evidence" in classes):
            self._count += 1
            self._segments.append((len(self.stack), self._count))
        if self._has("math") and len(self.stack) and tag == "span":
            self._block.append(" ∙ ")  # mathematics stands between two words
        if tag == "pre" and self._has("cell_input") and self._code is None:
            folded = (self._has("tag_hide-input") or self._has("tag_hide-cell")
                      or self._tag("details") or self._has("dropdown"))  # a closed solution
            self._code = [] if not (folded or self.in_notes) else None
        if "cell_output" in classes and self._out is None:
            self._out, self._out_depth = [], len(self.stack)

    def _flush(self) -> None:
        if self._block:
            self.blocks.append("".join(self._block))
            self._block = []

    def handle_endtag(self, tag):
        if tag in _VOID_TAGS or not self.stack:
            return
        if tag in _BLOCK_TAGS:
            self._flush()
        if tag == "h2" and self._heading is not None:
            if NOTES_HEADING in " ".join("".join(self._heading).split()):
                self.in_notes = True
            self._heading = None
        while self.stack:
            if self._segments[-1][0] == len(self.stack):
                self._segments.pop()
            t, _c = self.stack.pop()
            if tag == "pre" and t == "pre" and self._code is not None:
                self.code_lines += sum(1 for line in "".join(self._code).splitlines()
                                       if line.strip())
                self._code = None
            if self._out is not None and len(self.stack) < self._out_depth:
                self.outputs.append("".join(self._out))
                self._out = None
            if t == tag:
                break

    def handle_data(self, data):
        if self._heading is not None:
            self._heading.append(data)
        segment = self._segments[-1][1]
        if self._out is not None or self._has("fc-evidence"):
            self.printed.append((segment, data))
        elif not (any(self._has(c) for c in _COMPUTED_CLASSES) or self._tag("pre")
                  or self._tag("script") or self._tag("style") or self._has("cell_input")):
            self.typed.append((segment, data))
        if self._code is not None:
            self._code.append(data)
        math = self._has("math") or self._tag("mjx-container")
        if self._out is not None:
            if not math:
                self._out.append(data)
            return
        if not (math or self._tag("pre") or self._tag("code") or self._tag("script")
                or self._tag("style") or self._has("cell_input") or self._has("highlight")):
            self.prose.append(data)
            if not self._has("fc-evidence"):
                self._block.append(data)

    def close(self):
        super().close()
        self._flush()


def is_chapter(rel: str) -> bool:
    """A chapter page of the book (``book/<part>/<chapter>.html``, not a part's index nor
    the API reference's module pages)."""
    parts = rel.split("/")
    return (len(parts) == 3 and parts[0] == "book" and parts[1] != "api"
            and parts[2] != "index.html")


def read_page(text: str) -> _Reading:
    parser = _Reading()
    parser.feed(text)
    parser.close()
    return parser


def check_reading(html_dir: str | os.PathLike[str]) -> tuple[list[str], dict]:
    """The reading checks of every chapter page: (problems, per-page visible code lines before
    the Reproduction notes)."""
    html_dir = Path(html_dir)
    problems: list[str] = []
    code: dict[str, int] = {}
    for path in list_pages(html_dir):
        rel = path.relative_to(html_dir).as_posix()
        if not is_chapter(rel):
            continue
        page = read_page(path.read_text(encoding="utf-8", errors="replace"))
        code[rel] = page.code_lines
        problems += [f"page {rel}: an output image outside a numbered, captioned figure "
                     f"(...{src})" for src in page.loose_images]
        for out in page.outputs:
            problems += [f"page {rel}: output prints a {kind}: {ex!r}"
                         for kind, ex in find_repr_output(out)]
            problems += [f"page {rel}: ASCII mathematics in an output ({kind}): {ex!r}"
                         for kind, ex in find_ascii_math(out)]
        problems += [f"page {rel}: ASCII mathematics in the text ({kind}): {ex!r}"
                     for kind, ex in find_ascii_math(" ".join(page.prose))]
        problems += [f"page {rel}: a doubled word: {ex!r}"
                     for ex in find_doubled_words(page.blocks)]
        problems += [f"page {rel}: a number typed in the prose contradicts an output "
                     f"({ex}): glue it from the cell" for ex in
                     find_contradicted_numbers(page.typed, page.printed)]
    if code:
        import statistics

        median = statistics.median(code.values())
        if median > MAX_MEDIAN_CODE_LINES:
            problems.append(f"the median chapter page shows {median:g} lines of unfolded code "
                            f"(> {MAX_MEDIAN_CODE_LINES})")
    return problems, code


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("html_dir", type=Path)
    ap.add_argument("--min-pages", type=int, default=0)
    ap.add_argument("--min-math-pages", type=int, default=0)
    ap.add_argument("--min-images", type=int, default=0)
    ap.add_argument("--workers", type=int, default=None,
                    help=f"browsers side by side (default ${WORKERS_ENV}, else 2)")
    # a child of check_site (one browser of several): not for the command line
    ap.add_argument("--part", help=argparse.SUPPRESS)
    ap.add_argument("--base", help=argparse.SUPPRESS)
    ap.add_argument("--part-out", type=Path, help=argparse.SUPPRESS)
    ap.add_argument("--print-to", type=Path, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.part:
        return _run_part(args.html_dir, args.part, args.base, args.part_out, args.print_to)
    if args.workers is not None and args.workers < 1:
        ap.error("--workers must be at least 1")
    start = time.monotonic()
    problems = check_site(args.html_dir, min_pages=args.min_pages,
                          min_math_pages=args.min_math_pages, min_images=args.min_images,
                          log=lambda m: print(m, flush=True), workers=args.workers)
    if problems and not any(p.startswith("page ") or p.startswith("only ") for p in problems):
        # Nothing was checked (no browser, no site): say so on stdout too.
        for p in problems:
            print(f"ERROR: {p}")
        print("browser check: 0 passed, 0 failed")
    print(f"({time.monotonic() - start:.1f} s)", file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
