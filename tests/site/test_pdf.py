"""The whole book as one PDF (tools/pdf_book.py): ``<site>/../pdf/book.pdf``.

Written by ``make pdf`` (paper site) or, in ``make test`` (fast site), by the browser check of
the ``site`` stage from the pages it checks (the same ``pdf_book.Printer``). A missing PDF is a
failure, not a skip.
"""

from __future__ import annotations

import os
import re
import sys
from html.parser import HTMLParser
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DEFAULT_SITE = ROOT / "_build" / "fast" / "_build" / "html"
sys.path.insert(0, str(ROOT / "tools"))
from pdf_book import APPENDIX, toc_entries  # noqa: E402

pytestmark = pytest.mark.site


def _public_site() -> str:
    """The site's public address, as _config.yml sets it (html.baseurl)."""
    import yaml

    return yaml.safe_load((ROOT / "_config.yml").read_text())["html"]["baseurl"]


@pytest.fixture(scope="module")
def site() -> Path:
    return Path(os.environ.get("FUSIONCENTER_SITE", DEFAULT_SITE))


@pytest.fixture(scope="module")
def pdf(site):
    from pypdf import PdfReader

    path = site.parent / "pdf" / "book.pdf"
    if not path.is_file():
        pytest.fail(f"{path} not found: run `python tools/pdf_book.py --site {site}`")
    return PdfReader(path)


def _outline(reader) -> list[tuple[int, str, int]]:
    """(depth, title, page index) of every bookmark."""
    out = []

    def walk(items, depth):
        for item in items:
            if isinstance(item, list):
                walk(item, depth + 1)
            else:
                out.append((depth, item.title, reader.get_destination_page_number(item)))

    walk(reader.outline, 0)
    return out


def book_entries() -> list[tuple[str | None, str]]:
    """The pages of book.pdf: every page of the table of contents but the API reference's
    module pages (api.pdf)."""
    return [e for e in toc_entries() if not e[1].startswith(APPENDIX)]


def test_one_bookmark_per_chapter_in_toc_order(pdf):
    entries = book_entries()
    parts = {p for p, _ in entries if p}
    marks = [m for m in _outline(pdf) if m[0] <= 1]  # parts and chapters (not sections)
    chapters = [m for m in marks if not (m[0] == 0 and m[1] in parts)]
    assert len(chapters) == len(entries)
    assert all(title.strip() for _, title, _ in chapters)
    pages = [p for _, _, p in chapters]
    assert pages == sorted(pages) and len(set(pages)) == len(pages)
    assert pages[0] >= 2  # a title page and a table of contents come first


def test_page_count_and_numbers(pdf):
    n = len(pdf.pages)
    assert n >= 3 * len(book_entries())
    assert "Contents" in pdf.pages[1].extract_text()
    for i in (1, n // 2, n - 1):
        lines = [x.strip() for x in pdf.pages[i].extract_text().splitlines() if x.strip()]
        assert str(i + 1) in lines, f"page {i + 1} does not show its number"


#: TeX that MathJax should have typeset: none of it may be printed in a proportional font
#: (code and outputs, in monospace, may contain ``$`` legitimately).
RAW_TEX = re.compile(r"\$|\\frac|\\begin\{|\\mathbb|\\tilde")


def unrendered_tex(path: Path) -> list[str]:
    """``"page N: <match>"`` for every page of the PDF at ``path`` whose text outside monospace
    fonts contains :data:`RAW_TEX`. PDFium reads the text (a page's whole text first; the font
    of each character only on the pages where the pattern occurs at all): about 100 times
    faster than pypdf's text extraction, which took 65 s on the fast site's 775 pages."""
    import ctypes

    import pypdfium2 as pdfium
    import pypdfium2.raw as pdfium_c

    found = []
    font = ctypes.create_string_buffer(256)
    doc = pdfium.PdfDocument(path)
    try:
        for i in range(len(doc)):
            text = doc[i].get_textpage()
            if not RAW_TEX.search(text.get_text_range()):
                continue
            chars = []
            for k in range(text.count_chars()):
                pdfium_c.FPDFText_GetFontInfo(text, k, font, len(font), None)
                name = font.value.decode("latin-1").lower()
                mono = "mono" in name or "courier" in name
                chars.append(" " if mono else chr(pdfium_c.FPDFText_GetUnicode(text, k)))
            match = RAW_TEX.search("".join(chars))
            if match:
                found.append(f"page {i + 1}: {match.group()}")
    finally:
        doc.close()
    return found


def test_no_unrendered_math(pdf, site):
    bad = unrendered_tex(site.parent / "pdf" / "book.pdf")
    assert not bad, "unrendered TeX in the PDF: " + ", ".join(bad[:20])


def test_unrendered_tex_is_found_outside_code_only(tmp_path):
    """The check flags TeX in a proportional font and passes it over in a monospace one."""
    import pypdfium2 as pdfium
    import pypdfium2.raw as pdfium_c

    doc = pdfium.PdfDocument.new()
    for font_name, text in (("Helvetica", "the mean $\\frac{a}{b}$"),
                            ("Courier", "print(f'${x:.2f}')"), ("Helvetica", "typeset: a/b")):
        page = doc.new_page(300, 200)
        font = pdfium_c.FPDFText_LoadStandardFont(doc, font_name.encode())
        obj = pdfium_c.FPDFPageObj_CreateTextObj(doc, font, 12)
        pdfium_c.FPDFText_SetText(obj, ctypes_wide(text))
        pdfium_c.FPDFPageObj_Transform(obj, 1, 0, 0, 1, 20, 100)
        pdfium_c.FPDFPage_InsertObject(page, obj)
        pdfium_c.FPDFPage_GenerateContent(page)
    path = tmp_path / "t.pdf"
    doc.save(path)
    doc.close()
    assert unrendered_tex(path) == ["page 1: $"]


def ctypes_wide(text: str):
    """``text`` as PDFium's FPDF_WIDESTRING (UTF-16LE, zero-terminated)."""
    import ctypes

    raw = (text + "\0").encode("utf-16-le")
    buf = ctypes.create_string_buffer(raw, len(raw))
    return ctypes.cast(buf, ctypes.POINTER(ctypes.c_ushort))


class _Images(HTMLParser):
    def __init__(self):
        super().__init__()
        self.src: set[str] = set()

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "img" and "_images/" in (a.get("src") or "") and "logo" not in a["src"]:
            self.src.add(a["src"].split("_images/")[-1])


def test_figures_are_embedded(pdf, site):
    scan = _Images()
    for _, doc in toc_entries():
        scan.feed((site / f"{doc}.html").read_text(encoding="utf-8"))
    images = 0
    for page in pdf.pages:
        resources = page.get("/Resources") or {}
        xobjects = resources.get("/XObject") or {}
        images += sum(1 for x in xobjects.values() if x.get_object().get("/Subtype") == "/Image")
    assert len(scan.src) > 10
    assert images >= len(scan.src), f"{images} images in the PDF, {len(scan.src)} on the site"


# ------------------------------------------------------------- the PDF is a book (issue 28)
LOCAL = re.compile(r"^https?://(?:127\.\d+\.\d+\.\d+|localhost|\[::1\])(?::\d+)?/", re.I)


def links(reader) -> list[tuple[int, str, object]]:
    """``(page index, kind, target)`` of every link: kind ``"uri"`` (target the URI) or
    ``"dest"`` (target the destination)."""
    out = []
    for i, page in enumerate(reader.pages):
        for ref in page.get("/Annots") or []:
            a = ref.get_object()
            if a.get("/Subtype") != "/Link":
                continue
            action = a.get("/A")
            if action is not None and "/URI" in action:
                out.append((i, "uri", str(action["/URI"])))
            elif a.get("/Dest") is not None:
                out.append((i, "dest", a["/Dest"]))
            elif action is not None and "/D" in action:
                out.append((i, "dest", action["/D"]))
    return out


def local_links(reader) -> list[str]:
    """Links to a local address (the print server is gone once the PDF is written)."""
    return [f"page {i + 1}: {t}" for i, kind, t in links(reader)
            if kind == "uri" and LOCAL.match(t)]


def layout_faults(path: Path) -> tuple[list[int], list[str]]:
    """(blank pages, images cut by a page edge) of the PDF at ``path``. A page is blank when
    nothing is drawn between its running head and its page number (rendered at 24 dpi: no
    pixel of its body, the page less 8 % at the top and the bottom, darker than near-white);
    a page with text in its body is not rendered (the rendering took 11 s of the 17 s of
    these tests). An image is cut when its box sticks out of its page by more than 1 pt."""
    import pypdfium2 as pdfium
    import pypdfium2.raw as pdfium_c

    blank, cut = [], []
    doc = pdfium.PdfDocument(path)
    try:
        for i in range(len(doc)):
            page = doc[i]
            w, h = page.get_size()
            text = page.get_textpage()
            try:
                words = text.get_text_bounded(left=0, bottom=0.08 * h, right=w,
                                              top=0.92 * h).strip()
            finally:
                text.close()
            if not words:
                pixels = page.render(scale=24 / 72, grayscale=True).to_numpy()
                rows = pixels.shape[0]
                body = pixels[int(0.08 * rows):int(0.92 * rows)]
                if not (body < 235).any():
                    blank.append(i + 1)
            for obj in page.get_objects(filter=[pdfium_c.FPDF_PAGEOBJ_IMAGE], max_depth=3):
                left, bottom, right, top = obj.get_bounds()
                if bottom < -1 or top > h + 1 or left < -1 or right > w + 1:
                    cut.append(f"page {i + 1}: image at ({left:.0f}, {bottom:.0f}, "
                               f"{right:.0f}, {top:.0f}) on a {w:.0f} x {h:.0f} page")
    finally:
        doc.close()
    return blank, cut


def test_no_link_to_a_local_address(pdf):
    bad = local_links(pdf)
    assert not bad, f"{len(bad)} links to the print server: " + ", ".join(bad[:10])


def test_links_between_pages_are_internal(pdf):
    found = links(pdf)
    internal = sum(1 for _i, kind, _t in found if kind == "dest")
    assert internal >= 500, f"only {internal} internal links of {len(found)}"
    contents = [t for i, kind, t in found if i == 1 and kind == "dest"]
    assert len(contents) >= len(book_entries()), (
        f"the contents page has {len(contents)} internal links")


def test_no_blank_page_and_no_cut_image(pdf, site):
    blank, cut = layout_faults(site.parent / "pdf" / "book.pdf")
    assert not blank, f"blank pages: {blank}"
    assert not cut, "images cut by a page edge: " + "; ".join(cut[:10])


def test_every_numbered_chapter_is_numbered_in_the_outline(pdf):
    from pdf_book import chapter_numbers

    numbers = chapter_numbers()
    titles = [t for d, t, _p in _outline(pdf) if d == 1]
    numbered = [t for t in titles if re.match(r"^\d+  ", t)]
    assert len(numbered) == len(numbers), (len(numbered), len(numbers), titles[:8])
    assert [int(t.split()[0]) for t in numbered] == list(range(1, len(numbers) + 1))


def test_the_api_reference_is_at_most_15_percent(pdf, site):
    marks = _outline(pdf)
    api = [p for d, t, p in marks if d == 1 and "API" in t]
    assert api, "no API reference in the outline"
    start = min(api)
    after = sorted(p for d, _t, p in marks if d <= 1 and p > start)
    end = after[0] if after else len(pdf.pages)
    share = (end - start) / len(pdf.pages)
    assert share <= 0.15, f"the API reference is {end - start} of {len(pdf.pages)} pages"
    if any(doc.startswith(APPENDIX) for _p, doc in toc_entries()):
        assert (site.parent / "pdf" / "api.pdf").is_file(), "no api.pdf for the module pages"


def test_the_detectors_find_local_links_blank_pages_and_cut_images(tmp_path):
    """Each check can fail: a link to the print server, a blank page and an image half off
    its page are found."""
    import pypdfium2 as pdfium
    import pypdfium2.raw as pdfium_c
    from pypdf import PdfReader, PdfWriter
    from pypdf.annotations import Link
    from pypdf.generic import RectangleObject

    doc = pdfium.PdfDocument.new()
    for k in range(3):
        page = doc.new_page(300, 200)
        if k == 1:
            continue  # blank
        font = pdfium_c.FPDFText_LoadStandardFont(doc, b"Helvetica")
        obj = pdfium_c.FPDFPageObj_CreateTextObj(doc, font, 12)
        pdfium_c.FPDFText_SetText(obj, ctypes_wide(f"page {k} of the book"))
        pdfium_c.FPDFPageObj_Transform(obj, 1, 0, 0, 1, 20, 100)
        pdfium_c.FPDFPage_InsertObject(page, obj)
        if k == 2:
            img = pdfium.PdfImage.new(doc)
            bitmap = pdfium.PdfBitmap.new_native(4, 4, pdfium_c.FPDFBitmap_BGRA)
            bitmap.fill_rect((0, 0, 0, 255), 0, 0, 4, 4)
            img.set_bitmap(bitmap)
            img.set_matrix(pdfium.PdfMatrix().scale(100, 100).translate(50, 150))
            page.insert_obj(img)
        page.gen_content()
    path = tmp_path / "faults.pdf"
    doc.save(path)
    doc.close()
    blank, cut = layout_faults(path)
    assert blank == [2]
    assert len(cut) == 1 and cut[0].startswith("page 3:")

    writer = PdfWriter(clone_from=PdfReader(path))
    writer.add_annotation(0, Link(rect=RectangleObject([0, 0, 50, 50]),
                                  url="http://127.0.0.1:41234/book/mo2015/trigger.html"))
    writer.add_annotation(0, Link(rect=RectangleObject([0, 60, 50, 90]),
                                  url=_public_site()))
    out = tmp_path / "links.pdf"
    writer.write(out)
    assert local_links(PdfReader(out)) == ["page 1: http://127.0.0.1:41234/book/mo2015/"
                                           "trigger.html"]


def test_a_pdf_per_page_in_the_site_and_the_whole_book(site):
    from pypdf import PdfReader

    assert (site / "book.pdf").is_file(), "the site's 'whole book' link has no book.pdf"
    for _part, doc in toc_entries():
        for path in (site / "_pdf" / f"{doc}.pdf", site.parent / "pdf" / "chapters" /
                     f"{doc}.pdf"):
            assert path.is_file(), f"no {path}"
    handout = PdfReader(site / "_pdf" / "book" / "zheng2014" / "particle-filter.pdf")
    assert len(handout.pages) >= 3 and not local_links(handout)
