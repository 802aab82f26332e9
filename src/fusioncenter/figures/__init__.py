"""The registry of every figure and table of the four papers, plus the book's own.

>>> from fusioncenter import figures
>>> entry = figures.get("dey2009-fig1")
>>> entry.status
'reproduced'

Importing this package is cheap: the registry (:mod:`fusioncenter.figures.registry`) is imported
on first use of one of its names, and :func:`get` imports only the module that registers the
entry asked for (found in the index :mod:`fusioncenter.figures._index`).
"""

from __future__ import annotations

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


def __getattr__(name: str):
    if name in __all__:
        from fusioncenter.figures import registry

        return getattr(registry, name)
    if name in ("registry", "_index"):
        import importlib

        return importlib.import_module(f"fusioncenter.figures.{name}")
    raise AttributeError(f"module 'fusioncenter.figures' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted([*__all__, "registry"])
