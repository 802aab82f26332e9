"""The registry of every figure and table of the four papers, plus the book's own.

>>> from fusioncenter import figures
>>> entry = figures.get("dey2009-fig1")
>>> entry.status
'reproduced'
"""

from fusioncenter.figures.registry import (
    PAPER_IDS,
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
