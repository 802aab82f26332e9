"""The papers the book reproduces, and the ids of their own figures and tables.

Every registry entry names one key of :data:`PAPERS` (``"book"`` for the book's own figures);
:data:`PAPER_IDS` fixes the ids of the papers' figures and tables, in the order the papers
number them, which is also the order of :func:`fusioncenter.figures.registry.entries`.
"""

from __future__ import annotations

__all__ = ["PAPERS", "PAPER_IDS"]

#: The four papers: short id -> (bibtex key, short title).
PAPERS: dict[str, tuple[str, str]] = {
    "mo2015": ("mo2015", "Event-based estimation (lecture notes)"),
    "dey2009": ("dey2009", "Kalman filtering with faded measurements"),
    "leong2011": ("leong2011", "Asymptotics and power allocation for state estimation over "
                  "fading channels"),
    "zheng2014": ("zheng2014", "Sequential Bayesian estimation with censored data for "
                  "multi-sensor systems"),
    "book": ("", "This book's own figures"),
}

#: The ids of the papers' own figures and tables (fixed by the foundation issue); each is
#: registered by the module of its part.
PAPER_IDS: tuple[str, ...] = (
    *(f"dey2009-fig{i}" for i in range(1, 5)),
    "leong2011-fig1",
    "leong2011-fig2",
    *(f"leong2011-fig{i}{p}" for i in range(3, 7) for p in "ab"),
    *(f"zheng2014-fig{i}" for i in range(1, 11)),
    *(f"zheng2014-table{i}" for i in range(1, 4)),
)
