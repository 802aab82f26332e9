"""The caption of a registry figure on the site (``book/_ext/registry_figure.py``): it says
which paper figure the entry reproduces or, for an entry whose status is *differs*, that it
differs from it and how, in one line."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from fusioncenter import figures

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "book" / "_ext"))
import registry_figure  # noqa: E402 (the extension lives with the book)

META = {"profile": "fast", "seed": 7}


@pytest.mark.parametrize("entry", figures.entries(), ids=lambda e: e.id)
def test_caption_says_reproduces_or_differs(entry):
    if entry.status == "not-started":
        pytest.skip("no figure yet")
    text, suffix = registry_figure.caption_source(entry, META)
    assert text == entry.caption
    fig = registry_figure.paper_figure(entry.id)
    if entry.status == "differs":
        reason = entry.differs_reason()
        assert reason and "\n" not in reason and len(reason) <= 200, reason
        assert "Reproduces" not in suffix and f": {reason}." in suffix
        assert suffix.startswith(f"Differs from {fig} of" if fig else "This book's own")
    else:
        assert entry.differs_reason() == ""
        if fig:
            assert suffix.startswith(f"Reproduces {fig} of {{cite:t}}`{entry.paper}`.")
    assert suffix.endswith("; seed 7.")


def test_the_reason_defaults_to_the_notes_first_sentence():
    entry = figures.Entry(id="book-x", paper="book", kind="figure", caption="X.",
                          chapter="book/x", compute=lambda p, s: {}, checks=lambda d: [],
                          status="differs", note="Same runs as Fig. 2. The rest, e.g. more.")
    assert entry.differs_reason() == "Same runs as Fig. 2"
    entry.reason = "shorter."
    assert entry.differs_reason() == "shorter"
    _, suffix = registry_figure.caption_source(entry, META)
    assert suffix.startswith("This book's own figure. Differs from what the paper states: "
                             "shorter.")
