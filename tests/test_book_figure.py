"""A chapter's own figure: ``fusioncenter.book.figure`` refuses a name that is not a label and a
figure with an unlabelled axis. (The ``{book-figure}`` directive's page is checked in
tests/test_failing_book.py, with the other fixture books.)
"""

from __future__ import annotations

import matplotlib
import pytest

from fusioncenter import book, plotting

matplotlib.use("Agg")


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
