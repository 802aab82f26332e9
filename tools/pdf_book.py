"""Print the built site as one PDF: title page, table of contents, every page in TOC order.

    python tools/pdf_book.py                                   # _build/html -> _build/pdf/book.pdf
    python tools/pdf_book.py --site _build/fast/_build/html    # -> _build/fast/_build/pdf/book.pdf

No TeX: each page of the built HTML site is loaded in headless Chromium (Debian's
``/usr/bin/chromium`` driven by playwright, as in tools/browser_check.py), MathJax typesets it,
print CSS wraps code and outputs instead of clipping them and opens every collapsed block
(hidden inputs, solutions), and Chromium prints it. pypdf then merges the pages behind a title
page and a table of contents (with the page where each chapter starts), stamps page numbers
and adds one bookmark per chapter under one per part. The PDF is written next to the site:
``<site>/../pdf/book.pdf``.

The printing is :class:`Printer`'s; in ``make test`` the browser check (tools/browser_check.py)
drives it from the pages it has just loaded and checked, and the PDF is the same: its 775 pages
render to the same pixels as this script's.
"""

from __future__ import annotations

import argparse
import functools
import html
import http.server
import io
import socketserver
import sys
import threading
import time
from pathlib import Path

import yaml

sys.path.insert(0, str(Path(__file__).resolve().parent))
# VIEWPORT: the window build_pdf prints from, the browser check's; the print layout does not
# depend on it (the 238 pages of the API page print the same from 1000 x 1400 and 400 x 900)
from browser_check import CHROMIUM, CHROMIUM_ARGS, LOOPBACK_ONLY, VIEWPORT  # noqa: E402
from chapters import ROOT  # noqa: E402

PAGE = {"format": "A4", "margin": {"top": "16mm", "bottom": "18mm", "left": "14mm",
                                   "right": "14mm"}}

# Print styles on top of the theme's own print CSS: nothing clipped, nothing collapsed. They
# apply to the print only (``@media print``): added to the page as it is on screen, they cost
# no relayout of the screen page (emulating print media first, and the screen after, took 21 s
# of the 76 s that 16 big pages took to print, for the same pixels).
PRINT_CSS = """
@page { size: A4; }
@media print {
html, body { font-size: 10.5pt !important; }
*, *::before, *::after { animation: none !important; transition: none !important;
  box-shadow: none !important; text-shadow: none !important; }
.bd-header, .bd-sidebar-primary, .bd-sidebar-secondary, .bd-header-article, .bd-footer,
.bd-footer-article, .prev-next-area, .header-article-items, .bd-search, #pst-back-to-top,
.headerlink, .toggle-details__summary .tb-icon, .copybtn { display: none !important; }
.bd-main, .bd-content, .bd-article-container, .bd-page-width, .bd-container,
.bd-container__inner, .bd-article { max-width: 100% !important; width: 100% !important;
  padding: 0 !important; margin: 0 !important; overflow: visible !important; }
pre, .highlight pre, .output pre, .cell_output pre, div.highlight {
  white-space: pre-wrap !important; overflow-wrap: anywhere !important;
  word-break: break-word !important; overflow: visible !important; max-height: none !important;
  font-size: 8pt !important; }
.cell_output, .output, .cell_input, div.cell, .table-wrapper, .pst-scrollable-table-container,
.math-wrapper, div.math, mjx-container { overflow: visible !important;
  max-height: none !important; }
mjx-container[display="true"] { max-width: 100% !important; }
table { font-size: 8pt !important; table-layout: auto; }
td, th { word-break: normal !important; overflow-wrap: break-word !important;
  hyphens: auto; }
img { max-width: 100% !important; height: auto !important; page-break-inside: avoid;
      break-inside: avoid; }
figure.fc-registry-figure img { min-width: 0 !important; }  /* a phone's rule, not paper's */
h1, h2, h3 { break-after: avoid; }
details > *:not(summary) { display: block !important; opacity: 1 !important; }
details.hide > summary { display: none !important; }
.cell_output img { display: block; margin: 0 auto; }
}
"""

OPEN_AND_TYPESET_JS = """
async () => {
  document.querySelectorAll('details').forEach(d => d.open = true);
  document.querySelectorAll('.toggle-hidden, .toggle-details').forEach(
      e => e.classList.remove('toggle-hidden'));
  const imgs = Array.from(document.images);
  imgs.forEach(i => { if (i.loading === 'lazy') i.loading = 'eager'; });
  await Promise.all(imgs.map(i => i.complete ? null : new Promise(done => {
    i.addEventListener('load', done, {once: true}); i.addEventListener('error', done, {once: true});
    setTimeout(done, 10000); })));
  if (window.MathJax && MathJax.startup && MathJax.startup.promise) {
    await MathJax.startup.promise;
    if (MathJax.typesetPromise) { await MathJax.typesetPromise(); }
  }
  if (document.fonts && document.fonts.ready) { await document.fonts.ready; }
  const h1 = document.querySelector('article h1, main h1, h1');
  const title = h1 ? h1.textContent.replace(/[#\\u00b6]/g, '').trim() : document.title;
  const raw = Array.from(document.querySelectorAll('.math')).filter(el => {
    const c = el.cloneNode(true); c.querySelectorAll('mjx-container').forEach(m => m.remove());
    return /\\$\\$|\\\\\\(|\\\\\\[/.test(c.textContent); }).length;
  return {title: title, rawMath: raw, images: imgs.filter(i => i.naturalWidth > 0).length};
}
"""


class _Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, format, *args):  # noqa: A002 (the base class's name)
        pass


class _Server(socketserver.ThreadingMixIn, http.server.HTTPServer):
    daemon_threads = True


def toc_entries() -> list[tuple[str | None, str]]:
    """``(part caption or None, docname)`` for every page of ``_toc.yml`` in order."""
    toc = yaml.safe_load((ROOT / "_toc.yml").read_text())
    out: list[tuple[str | None, str]] = [(None, toc["root"])]

    def walk(node, part):
        for ch in node.get("chapters", []) or []:
            out.append((part, ch["file"]))
            walk(ch, part)
        for sec in node.get("sections", []) or []:
            out.append((part, sec["file"]))
            walk(sec, part)

    for part in toc.get("parts", []):
        walk(part, part.get("caption"))
    walk(toc, None)
    return out


def _html_doc(body: str, css: str = "") -> str:
    return ("<!doctype html><html><head><meta charset='utf-8'><style>"
            "body{font-family:'DejaVu Serif',serif;} " + css + "</style></head><body>"
            + body + "</body></html>")


def _front_matter(title: str, author: str, entries, starts: list[int] | None) -> tuple[str, str]:
    title_html = _html_doc(
        f"<div style='margin-top:35%;text-align:center'><h1 style='font-size:26pt'>"
        f"{html.escape(title)}</h1><p style='font-size:13pt'>{html.escape(author)}</p>"
        f"<p style='font-size:11pt;color:#555'>Printed from the book's site on "
        f"{time.strftime('%Y-%m-%d')}.</p></div>")
    rows, last_part = [], object()
    for i, (part, _doc, name) in enumerate(entries):
        if part != last_part and part:
            rows.append(f"<tr><td colspan=2 style='padding-top:9pt'><b>{html.escape(part)}</b>"
                        "</td></tr>")
        last_part = part
        page = str(starts[i]) if starts else "000"
        rows.append(f"<tr><td style='padding-left:{12 if part else 0}pt'>{html.escape(name)}"
                    f"</td><td style='text-align:right'>{page}</td></tr>")
    toc_html = _html_doc("<h1>Contents</h1><table style='width:100%;font-size:10.5pt'>"
                         + "".join(rows) + "</table>")
    return title_html, toc_html


def _numbers_html(n: int, skip: int) -> str:
    pages = "".join(
        f"<div class='p'><span>{i + 1 if i >= skip else ''}</span></div>" for i in range(n))
    return _html_doc(pages, "@page{size:A4;margin:0} body{margin:0} "
                     ".p{height:297mm;width:210mm;position:relative;page-break-after:always;"
                     "overflow:hidden} .p span{position:absolute;bottom:8mm;width:100%;"
                     "text-align:center;font-size:9pt;color:#333}")


class Printer:
    """Prints the site's pages into one PDF, a page of the browser at a time.

    :func:`build_pdf` loads every page of the table of contents for it; the browser check of
    ``make test`` (``tools/browser_check.py``) hands it each page it has just checked instead,
    so that the site is loaded and typeset once for both. Either way a page is printed by
    :meth:`add` from the same state: loaded, :data:`PRINT_CSS` added, every collapsed block
    opened and MathJax's typesetting awaited.
    """

    def __init__(self, site: Path, out: Path) -> None:
        self.site, self.out = site, out
        self.cfg = yaml.safe_load((ROOT / "_config.yml").read_text())
        self.entries = toc_entries()
        missing = [d for _, d in self.entries if not (site / f"{d}.html").exists()]
        if missing:
            raise FileNotFoundError(f"pages missing from {site}: {missing}")
        self.printed: dict[str, tuple[str, object]] = {}  # doc -> (title, PdfReader)
        self.raw_math = 0
        self.t0 = time.perf_counter()

    def wants(self, doc: str) -> bool:
        return any(d == doc for _, d in self.entries) and doc not in self.printed

    def add(self, page, doc: str) -> None:
        """Print the page loaded in ``page`` (the site's ``doc``) at whatever window it has:
        the print is laid out on the paper (the browser check prints from its last window,
        400 px wide, :func:`build_pdf` from :data:`VIEWPORT`, 1280 px: the 775 pages render to
        the same pixels). The page stays on screen media: :data:`PRINT_CSS` applies to the
        print alone."""
        from pypdf import PdfReader

        page.add_style_tag(content=PRINT_CSS)
        info = page.evaluate(OPEN_AND_TYPESET_JS)
        pdf = page.pdf(**PAGE, print_background=True, prefer_css_page_size=False)
        reader = PdfReader(io.BytesIO(pdf))
        self.printed[doc] = (info["title"], reader)
        self.raw_math += info["rawMath"]
        print(f"pdf: {doc:<40} {len(reader.pages):3d} pages  {info['images']:2d} images"
              + (f"  RAW MATH {info['rawMath']}" if info["rawMath"] else ""), flush=True)

    def write(self, page) -> dict:
        """Front matter and page numbers (printed in ``page``), then the whole PDF to ``out``."""
        from pypdf import PdfReader, PdfWriter

        missing = [d for _, d in self.entries if d not in self.printed]
        if missing:
            raise RuntimeError(f"pages not printed: {missing}")
        chapters = [(part, doc, *self.printed[doc]) for part, doc in self.entries]

        def render(doc_html: str) -> PdfReader:
            page.set_content(doc_html, wait_until="load")
            return PdfReader(io.BytesIO(page.pdf(**PAGE, print_background=True)))

        cfg = self.cfg
        named = [(p, d, t) for p, d, t, _ in chapters]
        title_html, toc_html = _front_matter(cfg["title"], cfg.get("author", ""), named, None)
        front = len(render(title_html).pages) + len(render(toc_html).pages)
        starts, n = [], front
        for *_, r in chapters:
            starts.append(n + 1)
            n += len(r.pages)
        title_html, toc_html = _front_matter(cfg["title"], cfg.get("author", ""), named, starts)
        title_pdf, toc_pdf = render(title_html), render(toc_html)
        if len(title_pdf.pages) + len(toc_pdf.pages) != front:
            raise RuntimeError("the table of contents changed length between two passes")
        page.set_content(_numbers_html(n, skip=1), wait_until="load")
        numbers = PdfReader(io.BytesIO(page.pdf(format="A4", margin={
            "top": "0", "bottom": "0", "left": "0", "right": "0"})))

        writer = PdfWriter()
        for r in (title_pdf, toc_pdf):
            for p in r.pages:
                writer.add_page(p)
        parts: dict[str, object] = {}
        for (part, _doc, title, r), start in zip(chapters, starts, strict=True):
            first = len(writer.pages)
            for p in r.pages:
                writer.add_page(p)
            parent = None
            if part:
                if part not in parts:
                    parts[part] = writer.add_outline_item(title=part, page_number=first)
                parent = parts[part]
            writer.add_outline_item(title=title, page_number=first, parent=parent)
            assert first + 1 == start
        for i, p in enumerate(writer.pages):
            p.merge_page(numbers.pages[i])
            p.compress_content_streams()
        writer.add_metadata({"/Title": cfg["title"], "/Author": cfg.get("author", "")})
        writer.compress_identical_objects()
        out = self.out
        out.parent.mkdir(parents=True, exist_ok=True)
        with out.open("wb") as fh:
            writer.write(fh)
        return {"pages": {d: len(r.pages) for _, d, _, r in chapters}, "raw_math": self.raw_math,
                "total_pages": len(writer.pages), "chapters": len(chapters),
                "front_pages": front, "seconds": time.perf_counter() - self.t0,
                "bytes": out.stat().st_size}


def build_pdf(site: Path, out: Path) -> dict:
    from playwright.sync_api import sync_playwright

    printer = Printer(site, out)
    handler = functools.partial(_Quiet, directory=str(site))
    server = _Server(("127.0.0.1", 0), handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    base = f"http://127.0.0.1:{server.server_address[1]}"
    try:
        with sync_playwright() as pw:
            # nothing but this server is reachable: any other host fails to resolve at once
            # (in Chromium itself: intercepting every request in Python cost a fifth of the
            # page loads; the browser check is the one that reports external requests)
            browser = pw.chromium.launch(
                executable_path=CHROMIUM, headless=True,
                args=[*CHROMIUM_ARGS, LOOPBACK_ONLY])
            page = browser.new_page(viewport=VIEWPORT)
            for _part, doc in printer.entries:
                page.goto(f"{base}/{doc}.html", wait_until="load", timeout=60_000)
                printer.add(page, doc)
            stats = printer.write(page)
            browser.close()
    finally:
        server.shutdown()
    return stats


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--site", type=Path, default=ROOT / "_build" / "html")
    ap.add_argument("--out", type=Path, default=None, help="default: <site>/../pdf/book.pdf")
    args = ap.parse_args(argv)
    site = args.site.resolve()
    out = args.out or site.parent / "pdf" / "book.pdf"
    stats = build_pdf(site, out)
    print(f"pdf: wrote {out} ({stats['total_pages']} pages, {stats['chapters']} chapters, "
          f"{stats['bytes'] / 1e6:.1f} MB) in {stats['seconds']:.0f} s")
    if stats["raw_math"]:
        print(f"pdf: {stats['raw_math']} math elements left untypeset", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
