"""A chapter's own figure: ``fusioncenter.book.figure`` and the ``{book-figure}`` directive.

Builds the one-page fixture book tests/fixtures/figure_book (the same strict flags as the site
build) and checks that the figure is numbered, captioned, described by its alt text and
carries the facts the browser check measures.
"""

from __future__ import annotations

import re
from pathlib import Path

import matplotlib
import pytest
from test_failing_book import build

from fusioncenter import book, plotting

matplotlib.use("Agg")


def test_the_figure_is_numbered_captioned_and_described(tmp_path: Path) -> None:
    result = build("figure_book", tmp_path)
    assert result.returncode == 0, (result.stdout + result.stderr)[-3000:]
    page = (tmp_path / "_build" / "html" / "index.html").read_text(encoding="utf-8")
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


@pytest.mark.parametrize("name", ["curves", "fig-Curves", "fig-a_b", "fig-", "", None, 3])
def test_a_figure_name_that_is_not_a_label_is_refused(name) -> None:
    fig, ax = plotting.subplots()
    ax.plot([0, 1], [0, 1])
    ax.set(xlabel="x (units)", ylabel="y (units)")
    with pytest.raises(ValueError, match="name must look like"):
        book.figure(name, fig)


def test_an_unlabelled_axis_is_refused() -> None:
    fig, ax = plotting.subplots()
    ax.plot([0, 1], [0, 1])
    with pytest.raises(ValueError, match="lacks a label"):
        book.figure("fig-fixture-bare", fig)
