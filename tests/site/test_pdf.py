"""The whole book as one PDF (tools/pdf_book.py): ``<site>/../pdf/book.pdf``.

Written by ``make pdf`` (paper site) or the ``pdf`` stage of ``make test`` (fast site). A missing
PDF is a failure, not a skip.
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


def _proportional_text(page) -> str:
    """The page's text outside monospace fonts (code and outputs may contain `$` legitimately)."""
    parts: list[str] = []

    def visit(text, cm, tm, font, size):
        name = str((font or {}).get("/BaseFont", ""))
        if "mono" not in name.lower() and "courier" not in name.lower():
            parts.append(text)

    page.extract_text(visitor_text=visit)
    return "".join(parts)


def test_no_unrendered_math(pdf):
    bad = []
    for i, page in enumerate(pdf.pages):
        text = _proportional_text(page)
        for pattern in (r"\$", r"\\frac", r"\\begin\{", r"\\mathbb", r"\\tilde"):
            if re.search(pattern, text):
                bad.append(f"page {i + 1}: {pattern}")
    assert not bad, "unrendered TeX in the PDF: " + ", ".join(bad[:20])


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
