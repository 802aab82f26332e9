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
from pdf_book import toc_entries  # noqa: E402

pytestmark = pytest.mark.site


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


def test_one_bookmark_per_chapter_in_toc_order(pdf):
    entries = toc_entries()
    parts = {p for p, _ in entries if p}
    marks = _outline(pdf)
    chapters = [m for m in marks if not (m[0] == 0 and m[1] in parts)]
    assert len(chapters) == len(entries)
    assert all(title.strip() for _, title, _ in chapters)
    pages = [p for _, _, p in chapters]
    assert pages == sorted(pages) and len(set(pages)) == len(pages)
    assert pages[0] >= 2  # a title page and a table of contents come first


def test_page_count_and_numbers(pdf):
    n = len(pdf.pages)
    assert n >= 3 * len(toc_entries())
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
