"""Displays that break where they must (issue 48): MathJax 4 as the site serves it.

A small page, no built site: the book's MathJax 4 tree (book/_ext/mathjax4.py), its
configuration, the book's stylesheet and book/_static/wide-math.js, served on loopback. At
1280 px a display broken by hand although it fits one line is reported
(:func:`browser_check.needless_splits`), a chain of relations is not; at 400 px the long
display is broken by MathJax to the column after the window was narrowed
(:func:`browser_check.layout.resize` waits for wide-math.js to lay the formulas out again).
"""

from __future__ import annotations

import functools
import json
import shutil
import sys
import threading
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

pytestmark = pytest.mark.site

sys.path.insert(0, str(ROOT / "tools"))
sys.path.insert(0, str(ROOT / "book" / "_ext"))
import browser_check as bc  # noqa: E402  (tools/ is not a package)
import mathjax4  # noqa: E402
from browser_check.layout import NARROW_VIEWPORT, resize  # noqa: E402
from headless import LOCAL_HOST, LoopbackServer, QuietHandler, launch  # noqa: E402

HAND_SPLIT = r"""\begin{aligned}
P_\infty = {} & A P_\infty A^\top + Q \\
& - A P_\infty C^\top (C P_\infty C^\top + R)^{-1} C P_\infty A^\top
\end{aligned}"""
CHAIN = r"""\begin{aligned}
\phi(K, X) &= \phi(K^*, X) + (K - K^*) S (K - K^*)^\top \\
&\succeq \phi(K^*, X)
\end{aligned}"""
ONE_LINE = (r"p(z, m \mid x) = \prod_{i=1}^N \mathcal N\bigl(z^i; h^{i\top} x, r^i\bigr)^{m^i}"
            r"\bigl[Q(\xi^i_1) - Q(\xi^i_2)\bigr]^{1 - m^i} + \sum_{j=1}^M \alpha_j \beta_j")


def _site(tmp_path: Path, displays: list[str]) -> Path:
    shutil.copytree(mathjax4.fetch(mathjax4.tree()), tmp_path / "_static" / "mathjax")
    for name in ("fusioncenter.css", "wide-math.js"):
        shutil.copy(ROOT / "book" / "_static" / name, tmp_path / "_static" / name)
    body = "".join(f'<div class="math notranslate nohighlight">\\[{d}\\]</div>' for d in displays)
    (tmp_path / "index.html").write_text(
        '<!doctype html><html lang="en"><head><meta charset="utf-8"><title>t</title>'
        '<link rel="stylesheet" href="_static/fusioncenter.css">'
        "<style>div.math { display: flex; flex-direction: row-reverse; }</style>"
        f"<script>window.MathJax = {json.dumps(mathjax4.CONFIG)}</script>"
        '<script src="_static/wide-math.js"></script>'
        '<script defer src="_static/mathjax/tex-chtml.js"></script></head>'
        f'<body><article class="bd-article" style="max-width: 46rem">{body}</article>'
        "</body></html>")
    return tmp_path


@pytest.fixture(scope="module")
def browser():
    from playwright.sync_api import sync_playwright

    with sync_playwright() as pw:
        b = launch(pw)
        yield b
        b.close()


def _open(browser, site: Path):
    server = LoopbackServer((LOCAL_HOST, 0), functools.partial(QuietHandler, directory=site))
    threading.Thread(target=server.serve_forever, daemon=True).start()
    page = browser.new_page(viewport=bc.VIEWPORT)
    page.goto(f"http://{LOCAL_HOST}:{server.server_address[1]}/index.html")
    page.wait_for_function("window.MathJax && MathJax.startup && MathJax.startup.document")
    page.evaluate("MathJax.startup.promise")
    return server, page


def test_a_hand_split_that_fits_is_reported_and_a_chain_is_not(browser, tmp_path):
    server, page = _open(browser, _site(tmp_path, [HAND_SPLIT, CHAIN]))
    try:
        found = bc.needless_splits(page)
    finally:
        page.close()
        server.shutdown()
        server.server_close()
    assert [(f["row"], f["tex"].split()[1]) for f in found] == [(1, "-")], found


def test_a_long_display_breaks_at_400_px_after_a_resize(browser, tmp_path):
    server, page = _open(browser, _site(tmp_path, [ONE_LINE]))
    width = "() => document.querySelector('mjx-container[display=true]').getBoundingClientRect()"
    try:
        wide = page.evaluate(width + ".width")
        resize(page, NARROW_VIEWPORT)
        narrow = page.evaluate(width + ".width")
        column = page.evaluate("() => document.querySelector('article').clientWidth")
        lines = page.evaluate("() => new Set([...document.querySelectorAll('mjx-linebox')]"
                              ".map(e => Math.round(e.getBoundingClientRect().top))).size")
    finally:
        page.close()
        server.shutdown()
        server.server_close()
    assert wide > NARROW_VIEWPORT["width"], wide  # one line at 1280 px
    assert narrow <= column and lines >= 2, (narrow, column, lines)
