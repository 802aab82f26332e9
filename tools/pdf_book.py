"""Print the built site as one PDF: title page, table of contents, every page in TOC order.

    python tools/pdf_book.py                                   # _build/html -> _build/pdf/book.pdf
    python tools/pdf_book.py --site _build/fast/_build/html    # -> _build/fast/_build/pdf/book.pdf

No TeX: each page of the built HTML site is loaded in headless Chromium (Debian's
``/usr/bin/chromium`` driven by playwright: tools/headless.py), MathJax typesets it,
print CSS wraps code and outputs instead of clipping them and opens every collapsed block
(hidden inputs, solutions), and Chromium prints it. pypdf then merges the pages behind a title
page and a table of contents (with the page where each chapter starts), stamps page numbers
and adds one bookmark per chapter under one per part. The PDF is written next to the site:
``<site>/../pdf/book.pdf``.

The printing is :class:`Printer`'s; in ``make test`` the browser check (tools/browser_check)
drives it from the pages it has just loaded and checked, and the PDF is the same: its 775 pages
render to the same pixels as this script's.
"""

from __future__ import annotations

import argparse
import functools
import html
import io
import json
import shutil
import sys
import threading
import time
from pathlib import Path
from urllib.parse import urlsplit

import yaml

sys.path.insert(0, str(Path(__file__).resolve().parent))
from chapters import ROOT  # noqa: E402

# VIEWPORT: the window build_pdf prints from, the browser check's
from headless import LOCAL_HOST, VIEWPORT, LoopbackServer, QuietHandler, launch  # noqa: E402
from pdf_links import destinations, relink  # noqa: E402
from print_page import (  # noqa: E402
    NUMBER_JS,
    OPEN_AND_TYPESET_JS,
    PAGE,
    PRINT_CSS,
    SECTIONS_JS,
    TARGETS_JS,
    screen_media,
)

#: Pages under this prefix (the API reference's module pages) are printed into api.pdf.
APPENDIX = "book/api/"


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


def chapter_numbers() -> dict[str, str]:
    """The chapter number of every page of a numbered part of ``_toc.yml`` (``numbered`` on the
    part; ``use_multitoc_numbering`` runs the numbers on across the parts): the numbers the
    site gives its figures ("Fig. 25.2") and exercises."""
    toc = yaml.safe_load((ROOT / "_toc.yml").read_text())
    out, n = {}, 0
    for part in toc.get("parts", []):
        for ch in part.get("chapters", []) or []:
            if part.get("numbered"):
                n += 1
                out[ch["file"]] = str(n)
    return out


#: The body's typeface on the page (the theme's system stack, as Chromium resolves it here):
#: the title page, the contents and the running heads use it too.
BODY_FONT = ("-apple-system, BlinkMacSystemFont, 'Segoe UI', 'Liberation Sans', "
             "'DejaVu Sans', sans-serif")


def _html_doc(body: str, css: str = "") -> str:
    return ("<!doctype html><html><head><meta charset='utf-8'><style>"
            f"body{{font-family:{BODY_FONT};}} a{{color:inherit;text-decoration:none}} "
            + css + "</style></head><body>" + body + "</body></html>")


def _front_matter(title: str, author: str, entries, starts: list[int] | None,
                  origin: str = "") -> tuple[str, str]:
    title_html = _html_doc(
        f"<div style='margin-top:35%;text-align:center'><h1 style='font-size:26pt'>"
        f"{html.escape(title)}</h1><p style='font-size:13pt'>{html.escape(author)}</p>"
        f"<p style='font-size:11pt;color:#555'>Printed from the book's site on "
        f"{time.strftime('%Y-%m-%d')}.</p></div>")
    rows, last_part = [], object()
    numbers = chapter_numbers()
    for i, (part, doc, name) in enumerate(entries):
        if part != last_part and part:
            rows.append(f"<tr><td colspan=2 style='padding-top:9pt'><b>{html.escape(part)}</b>"
                        "</td></tr>")
        last_part = part
        page = str(starts[i]) if starts else "000"
        num = f"{numbers[doc]}&ensp;" if doc in numbers else ""
        # a link to the chapter's page on the print server: relink() points it into the PDF
        href = html.escape(f"{origin}/{doc}.html")
        rows.append(f"<tr><td style='padding-left:{12 if part else 0}pt'><a href='{href}'>"
                    f"{num}{html.escape(name)}</a></td><td style='text-align:right'>"
                    f"<a href='{href}'>{page}</a></td></tr>")
    toc_html = _html_doc("<h1>Contents</h1><table style='width:100%;font-size:10.5pt'>"
                         + "".join(rows) + "</table>")
    return title_html, toc_html


def _numbers_html(n: int, skip: int, heads: dict[int, str] | None = None) -> str:
    """Page numbers (from page ``skip + 1`` on) and running heads (``heads``: page index ->
    text), one A4 page each, to be laid over the printed pages."""
    heads = heads or {}
    pages = "".join(
        f"<div class='p'>{f'<b>{html.escape(heads[i])}</b>' if heads.get(i) else ''}"
        f"<span>{i + 1 if i >= skip else ''}</span></div>" for i in range(n))
    return _html_doc(pages, "@page{size:A4;margin:0} body{margin:0} "
                     ".p{height:297mm;width:210mm;position:relative;page-break-after:always;"
                     "overflow:hidden} .p span{position:absolute;bottom:8mm;width:100%;"
                     "text-align:center;font-size:9pt;color:#333} .p b{position:absolute;"
                     "top:7mm;left:14mm;right:14mm;font-weight:normal;font-style:italic;"
                     "font-size:8.5pt;color:#555;border-bottom:0.3pt solid #999;"
                     "padding-bottom:1mm;white-space:nowrap;overflow:hidden}")



class Printer:
    """Prints the site's pages into one PDF, a page of the browser at a time.

    :func:`build_pdf` loads every page of the table of contents for it; the browser check of
    ``make test`` (``tools/browser_check``) hands it each page it has just checked instead,
    so that the site is loaded and typeset once for both. Either way a page is printed by
    :meth:`add` from the same state: loaded, :data:`PRINT_CSS` added, every collapsed block
    opened and MathJax's typesetting awaited.
    """

    def __init__(self, site: Path, out: Path) -> None:
        self.site, self.out = site, out
        self.cfg = yaml.safe_load((ROOT / "_config.yml").read_text())
        # the API reference's module pages go to api.pdf: the book keeps its index (a line
        # per module), so that the reference stays an appendix, not a third of the book
        self.entries = [e for e in toc_entries() if not e[1].startswith(APPENDIX)]
        self.appendix = [e for e in toc_entries() if e[1].startswith(APPENDIX)]
        self.numbers = chapter_numbers()
        missing = [d for _, d in self.entries + self.appendix
                   if not (site / f"{d}.html").exists()]
        if missing:
            raise FileNotFoundError(f"pages missing from {site}: {missing}")
        self.printed: dict[str, tuple[str, object]] = {}  # doc -> (title, PdfReader)
        self.raw: dict[str, bytes] = {}  # doc -> the PDF Chromium printed (for dump())
        self.raw_math = 0
        self.origin = ""  # the local server's http://127.0.0.1:PORT, seen in add()
        self.sections: dict[str, list] = {}  # doc -> [(id, title)] of its second-level sections
        self.t0 = time.perf_counter()

    def wants(self, doc: str) -> bool:
        return (any(d == doc for _, d in self.entries + self.appendix)
                and doc not in self.printed)

    def add(self, page, doc: str) -> None:
        """Print the page loaded in ``page`` (the site's ``doc``) at whatever window it has:
        the print is laid out on the paper (the browser check prints from its last window,
        400 px wide, :func:`build_pdf` from :data:`VIEWPORT`, 1280 px: the 775 pages render to
        the same pixels). The page is left in print media: load the next one after
        :func:`screen_media`."""
        from pypdf import PdfReader

        page.add_style_tag(content=PRINT_CSS)
        page.evaluate(NUMBER_JS, self.numbers.get(doc, ""))
        info = page.evaluate(OPEN_AND_TYPESET_JS)
        page.evaluate(TARGETS_JS)
        self.sections[doc] = page.evaluate(SECTIONS_JS)
        url = urlsplit(page.url)
        self.origin = f"{url.scheme}://{url.netloc}"
        page.emulate_media(media="print")
        pdf = page.pdf(**PAGE, print_background=True, prefer_css_page_size=False)
        reader = PdfReader(io.BytesIO(pdf))
        self.printed[doc] = (info["title"], reader)
        self.raw[doc] = pdf
        self.raw_math += info["rawMath"]
        print(f"pdf: {doc:<40} {len(reader.pages):3d} pages  {info['images']:2d} images"
              + (f"  RAW MATH {info['rawMath']}" if info["rawMath"] else ""), flush=True)

    def dump(self, folder: Path) -> None:
        """Write what :meth:`add` printed to ``folder`` (the PDFs as Chromium printed them,
        titles, sections, the origin): a second browser's share, for :meth:`load`."""
        folder.mkdir(parents=True, exist_ok=True)
        docs = {}
        for i, doc in enumerate(self.raw):
            (folder / f"{i}.pdf").write_bytes(self.raw[doc])
            docs[doc] = {"file": f"{i}.pdf", "title": self.printed[doc][0],
                         "sections": self.sections.get(doc, [])}
        meta = {"docs": docs, "raw_math": self.raw_math, "origin": self.origin}
        (folder / "printed.json").write_text(json.dumps(meta), encoding="utf-8")

    def load(self, folder: Path) -> None:
        """Take the pages another printer :meth:`dump`-ed to ``folder``; ValueError if they
        were printed from another server (their links would not be rewritten)."""
        from pypdf import PdfReader

        meta = json.loads((folder / "printed.json").read_text(encoding="utf-8"))
        if meta["docs"] and self.origin and meta["origin"] != self.origin:
            raise ValueError(f"pages printed from {meta['origin']}, not {self.origin}")
        self.origin = self.origin or meta["origin"]
        for doc, d in meta["docs"].items():
            pdf = (folder / d["file"]).read_bytes()
            self.printed[doc] = (d["title"], PdfReader(io.BytesIO(pdf)))
            self.raw[doc] = pdf
            self.sections[doc] = d["sections"]
        self.raw_math += meta["raw_math"]

    def write_chapters(self, chapters, cfg) -> None:
        """One PDF per page of the book (a lecture's handout): ``<out>/../chapters/<doc>.pdf``
        and, for the site's download menu, ``<site>/_pdf/<doc>.pdf``. Links inside the page
        stay in its PDF; links to other pages go to the published site."""
        from pypdf import PdfWriter

        baseurl = cfg.get("html", {}).get("baseurl", "")
        for _part, doc, title, r in chapters:
            w = PdfWriter()
            for p in r.pages:
                w.add_page(p)
            relink(w, destinations([(doc, r, 0)]), self.origin, baseurl)
            num = self.numbers.get(doc)
            w.add_outline_item(title=f"{num}  {title}" if num else title, page_number=0)
            w.add_metadata({"/Title": f"{num}  {title}" if num else title,
                            "/Author": cfg.get("author", "")})
            w.compress_identical_objects()
            first, *others = [folder / f"{doc}.pdf"
                              for folder in (self.out.parent / "chapters", self.site / "_pdf")]
            first.parent.mkdir(parents=True, exist_ok=True)
            with first.open("wb") as fh:
                w.write(fh)
            for target in others:  # the same bytes: written once
                target.parent.mkdir(parents=True, exist_ok=True)
                shutil.copyfile(first, target)

    def write_appendix(self, pages, cfg, out: Path) -> None:
        """The API reference's module pages as one PDF (``api.pdf``), a bookmark each."""
        from pypdf import PdfWriter

        w = PdfWriter()
        docs = []
        for _part, doc, _title, r in pages:
            docs.append((doc, r, len(w.pages)))
            for p in r.pages:
                w.add_page(p)
        relink(w, destinations(docs), self.origin, cfg.get("html", {}).get("baseurl", ""))
        for doc, _r, start in docs:
            w.add_outline_item(title=self.printed[doc][0], page_number=start)
        w.add_metadata({"/Title": f"{cfg['title']}: API reference",
                        "/Author": cfg.get("author", "")})
        w.compress_identical_objects()
        with out.open("wb") as fh:
            w.write(fh)

    def write(self, page) -> dict:
        """Front matter and page numbers (printed in ``page``), then the whole PDF to ``out``."""
        from pypdf import PdfReader, PdfWriter

        missing = [d for _, d in self.entries + self.appendix if d not in self.printed]
        if missing:
            raise RuntimeError(f"pages not printed: {missing}")
        chapters = [(part, doc, *self.printed[doc]) for part, doc in self.entries]

        screen_media(page)  # the front matter as before: laid out on screen, then printed

        def render(doc_html: str) -> PdfReader:
            page.set_content(doc_html, wait_until="load")
            return PdfReader(io.BytesIO(page.pdf(**PAGE, print_background=True)))

        cfg = self.cfg
        named = [(p, d, t) for p, d, t, _ in chapters]
        title_html, toc_html = _front_matter(cfg["title"], cfg.get("author", ""), named, None,
                                             self.origin)
        front = len(render(title_html).pages) + len(render(toc_html).pages)
        starts, n = [], front
        for *_, r in chapters:
            starts.append(n + 1)
            n += len(r.pages)
        title_html, toc_html = _front_matter(cfg["title"], cfg.get("author", ""), named, starts,
                                             self.origin)
        title_pdf, toc_pdf = render(title_html), render(toc_html)
        if len(title_pdf.pages) + len(toc_pdf.pages) != front:
            raise RuntimeError("the table of contents changed length between two passes")
        heads = {}
        for (_part, doc, title, r), start in zip(chapters, starts, strict=True):
            num = self.numbers.get(doc)
            for k in range(1, len(r.pages)):  # not on the chapter's first page
                heads[start - 1 + k] = f"{num}  {title}" if num else title
        page.set_content(_numbers_html(n, skip=1, heads=heads), wait_until="load")
        numbers = PdfReader(io.BytesIO(page.pdf(format="A4", margin={
            "top": "0", "bottom": "0", "left": "0", "right": "0"})))

        writer = PdfWriter()
        for r in (title_pdf, toc_pdf):
            for p in r.pages:
                writer.add_page(p)
        for (_part, _doc, _title, r), start in zip(chapters, starts, strict=True):
            assert len(writer.pages) + 1 == start
            for p in r.pages:
                writer.add_page(p)
        docs = [(doc, r, start - 1) for (_p, doc, _t, r), start
                in zip(chapters, starts, strict=True)]
        dests = destinations(docs)
        links = relink(writer, dests, self.origin, cfg.get("html", {}).get("baseurl", ""))
        parts: dict[str, object] = {}
        for (part, doc, title, _r), start in zip(chapters, starts, strict=True):
            parent = None
            if part:
                if part not in parts:
                    parts[part] = writer.add_outline_item(title=part, page_number=start - 1)
                parent = parts[part]
            num = self.numbers.get(doc)
            mark = writer.add_outline_item(title=f"{num}  {title}" if num else title,
                                           page_number=start - 1, parent=parent)
            for sid, snum, stitle in self.sections.get(doc, []) if part else []:
                where = dests[0].get(doc, {}).get(sid)
                if where is not None:
                    writer.add_outline_item(title=f"{snum}  {stitle}" if snum else stitle,
                                            page_number=where[0], parent=mark)
        for i, p in enumerate(writer.pages):
            p.merge_page(numbers.pages[i])
            p.compress_content_streams()
        writer.add_metadata({"/Title": cfg["title"], "/Author": cfg.get("author", "")})
        writer.compress_identical_objects()
        out = self.out
        out.parent.mkdir(parents=True, exist_ok=True)
        with out.open("wb") as fh:
            writer.write(fh)
        self.write_chapters(chapters, cfg)
        appendix = [(part, doc, *self.printed[doc]) for part, doc in self.appendix]
        if appendix:
            self.write_chapters(appendix, cfg)
            self.write_appendix(appendix, cfg, self.out.parent / "api.pdf")
            shutil.copyfile(self.out.parent / "api.pdf", self.site / "api.pdf")
        # the site's download menus link the whole book (book.pdf) and each page's own PDF
        # (_pdf/<page>.pdf, book/_ext/ipynb_download.py): the site carries them
        shutil.copyfile(out, self.site / "book.pdf")
        return {"pages": {d: len(r.pages) for _, d, _, r in chapters}, "raw_math": self.raw_math,
                "total_pages": len(writer.pages), "chapters": len(chapters), "links": links,
                "front_pages": front, "seconds": time.perf_counter() - self.t0,
                "bytes": out.stat().st_size}



def build_pdf(site: Path, out: Path) -> dict:
    from playwright.sync_api import sync_playwright

    printer = Printer(site, out)
    handler = functools.partial(QuietHandler, directory=str(site))
    server = LoopbackServer((LOCAL_HOST, 0), handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    base = f"http://{LOCAL_HOST}:{server.server_address[1]}"
    try:
        with sync_playwright() as pw:
            # nothing but this server is reachable: any other host fails to resolve at once
            # (in Chromium itself: intercepting every request in Python cost a fifth of the
            # page loads; the browser check is the one that reports external requests)
            browser = launch(pw)
            page = browser.new_page(viewport=VIEWPORT)
            for _part, doc in printer.entries + printer.appendix:
                screen_media(page)
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
