"""The site crawl: serve the built site, drive the browsers over its pages, gather the report.

:func:`check_site` serves the site from a loopback server (:class:`CachingHandler`), checks
every page in one or more headless Chromium side by side (:func:`browse` in this process, the
others ``--part`` children of ``tools/browser_check``: :mod:`browser_check.workers`), runs the
checks that read the files (markup, reading), and returns every problem found.
"""

from __future__ import annotations

import functools
import os
import re
import shutil
import subprocess
import sys
import tempfile
import threading
from collections.abc import Callable
from pathlib import Path
from urllib.parse import quote, urlsplit

from headless import (
    CHROMIUM,
    INSTALL_HINT,
    LOCAL_HOST,
    VIEWPORT,
    LoopbackServer,
    QuietHandler,
    launch,
)

from .accessibility import AXE_STATS, axe_summary, check_accessibility, check_focus
from .displays import check_splits
from .figures import (
    FIGURE_STATS,
    FIGURE_VIEWPORT,
    FIGURES_JS,
    check_registry_figures,
    merge_figure_stats,
    registry_figure_summary,
)
from .layout import (
    LAYOUT_VIEWPORTS,
    NARROW_VIEWPORT,
    LayoutResult,
    check_layout,
    layout_summary,
    resize,
)
from .markup import check_markup
from .page import MathCounter, check_page, list_pages
from .reading import check_reading
from .result import PageResult
from .workers import default_workers, read_part


class CachingHandler(QuietHandler):
    """Serves the site. Pages (HTML) and every answer but a 200 are never cached; a static
    file answered 200 (theme CSS and JavaScript, MathJax and its fonts, images) is kept by
    Chromium for the run, so that the next page takes it, already compiled, from the cache
    instead of fetching and compiling MathJax again: on the fast site (114 pages checked and
    printed, one browser) 184.1 s -> 158.5 s, the same findings and the same text on all 619
    PDF pages. A cached answer still reaches the page's ``response`` listener, with its
    status: every math page's fonts are still counted and checked."""

    _status = 0

    def send_response(self, code, message=None) -> None:
        self._status = code
        super().send_response(code, message)

    def end_headers(self) -> None:
        path = urlsplit(self.path).path
        page = path.endswith((".html", "/")) or "." not in path.rsplit("/", 1)[-1]
        self.send_header("Cache-Control", "no-store" if page or self._status != 200
                         else "max-age=3600")
        super().end_headers()


class NoBrowser(Exception):
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

    handler = functools.partial(CachingHandler, directory=str(html_dir))
    server = LoopbackServer((LOCAL_HOST, 0), handler)
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
            cmd = [sys.executable, str(Path(__file__).resolve().parent), str(html_dir),
                   "--part", f"{k}/{workers}", "--base", base, "--part-out", str(out)]
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
                found = read_part(out)
                if rc != 0 or found is None:
                    err = (out.parent / f"{k}.err").read_text(errors="replace").strip()
                    site_problems.append(f"browser worker {k + 1} of {workers} failed (exit "
                                         f"{rc}): {err.splitlines()[-1] if err else 'no output'}")
                    continue
                part_results, part_layouts, part_problems, stats, lines = found
                extra_results.extend(part_results)
                extra_layouts.extend(part_layouts)
                site_problems.extend(part_problems)
                merge_figure_stats(stats)
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
            results, layouts, problems = browse(base, html_dir, pages[0::workers], printer,
                                                 say, finish)
        except NoBrowser as exc:
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


def browse(base: str, html_dir: Path, pages: list[Path], printer, say,
            finish: Callable | None = None) -> tuple[list, list, list[str]]:
    """Load and check ``pages`` in one headless Chromium against the server at ``base``;
    returns ``(page results, layout results, problems outside any page)`` and adds to
    :data:`FIGURE_STATS`. ``printer``: print each page of the table of contents after its
    checks. ``finish(page)`` runs last, with the browser still open (the PDF is written
    there). Raises :class:`NoBrowser` if Chromium cannot start."""
    from playwright.sync_api import Error as PlaywrightError
    from playwright.sync_api import sync_playwright

    results: list[PageResult] = []
    layouts: list[LayoutResult] = []
    site_problems: list[str] = []
    with sync_playwright() as pw:
        try:
            browser = launch(pw)
        except (PlaywrightError, FileNotFoundError) as exc:
            first = str(exc).strip().splitlines()[0] if str(exc).strip() else repr(exc)
            raise NoBrowser(f"cannot start headless Chromium at {CHROMIUM}: {first}; "
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
            parser = MathCounter()
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
                check_page(page, base + quote(rel), res, parser.refresh_target, fonts)
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
                            resize(page, viewport)
                        measured[viewport["width"]] = check_layout(page, rel, viewport)
                        shown[viewport["width"]] = page.evaluate(FIGURES_JS)
                        if viewport == VIEWPORT:
                            # at 1280 px, every collapsed block open (check_layout): the
                            # evidence tables and solutions are read too
                            check_accessibility(page, res, seen=axe_seen)
                            check_focus(page, res)
                            check_splits(page, res)
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
