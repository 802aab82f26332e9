"""A notebook cell that raises must fail the book build; a passing one must not; a chapter's
own figure (``fusioncenter.book.figure`` and ``{book-figure}``) is a numbered, captioned figure.

Builds two fixture books (tests/fixtures/failing_book, one page, and tests/fixtures/figure_book,
a page with a figure and a page with a plain passing cell: execute_notebooks: force,
raise_on_error: true) with the same strict flags as ``tools/build_book.py --strict``; the
passing book is built once for both of its tests (each build is a jupyter-book process and a
kernel, about 8 s).
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

FIXTURES = Path(__file__).resolve().parent / "fixtures"
JUPYTER_BOOK = Path(sys.executable).with_name("jupyter-book")


def build(book: str, out: Path) -> subprocess.CompletedProcess[str]:
    if not JUPYTER_BOOK.exists():
        pytest.fail(f"{JUPYTER_BOOK} not found: jupyter-book must be installed in this env")
    cmd = [str(JUPYTER_BOOK), "build", str(FIXTURES / book), "--path-output", str(out),
           "-n", "-W", "--keep-going"]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=300, cwd=out)


def test_failing_cell_fails_the_build(tmp_path: Path) -> None:
    result = build("failing_book", tmp_path)
    output = result.stdout + result.stderr
    assert result.returncode != 0, "a book whose cell raises was built successfully:\n" + output
    assert "deliberate failure" in output, output[-3000:]
    assert "RuntimeError" in output, output[-3000:]


@pytest.fixture(scope="module")
def passing_book(tmp_path_factory) -> tuple[subprocess.CompletedProcess[str], Path]:
    out = tmp_path_factory.mktemp("figure_book")
    return build("figure_book", out), out


def test_passing_cell_builds(passing_book) -> None:
    result, out = passing_book
    output = result.stdout + result.stderr
    assert result.returncode == 0, output[-3000:]
    page = out / "_build" / "html" / "passing.html"
    assert page.is_file(), f"no {page}:\n{output[-3000:]}"
    text = page.read_text(encoding="utf-8")
    assert "Passing fixture" in text, text[-3000:]
    assert re.search(r"cell_output.*?<pre><span></span>2\s*</pre>", text, re.S), text[-3000:]


def test_the_figure_is_numbered_captioned_and_described(passing_book) -> None:
    result, out = passing_book
    assert result.returncode == 0, (result.stdout + result.stderr)[-3000:]
    page = (out / "_build" / "html" / "index.html").read_text(encoding="utf-8")
    m = re.search(r'<figure class="[^"]*fc-book-figure[^"]*" id="fig-fixture-curves">(.*?)'
                  r"</figure>", page, re.S)
    assert m, "no book figure in the page"
    fig = m[1]
    assert '<span class="caption-number">Fig. 1 </span>' in fig
    assert "the square, (b) the root" in fig
    assert "A second paragraph of the legend." in fig
    alt = re.search(r'<img alt="([^"]*)"', fig)[1]
    assert alt.startswith("2-panel figure.") and "root of x (units) against x (units)" in alt
    assert 'data-panels="2"' in fig and 'data-columns="1"' in fig
    assert re.search(r"figure#fig-fixture-curves img \{ min-width: \d+px; \}", fig)
    assert re.search(r'href="#fig-fixture-curves"><span class="std std-numref">Fig\. 1', page)
