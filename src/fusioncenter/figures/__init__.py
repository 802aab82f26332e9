"""The registry of every figure and table of the four papers, plus the book's own.

>>> from fusioncenter import figures
>>> entry = figures.get("dey2009-fig1")
>>> entry.status
'reproduced'
"""

from fusioncenter.figures.registry import (
    PAPERS,
    REGISTRY,
    STATUSES,
    Claim,
    Entry,
    EntryNotReady,
    UnknownEntry,
    entries,
    get,
    ids,
    register,
)

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

__all__ = [
    "PAPERS",
    "PAPER_IDS",
    "REGISTRY",
    "STATUSES",
    "Claim",
    "Entry",
    "EntryNotReady",
    "UnknownEntry",
    "entries",
    "get",
    "ids",
    "register",
]
