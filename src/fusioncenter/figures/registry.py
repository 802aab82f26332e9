"""The registry: every figure and table of the book by its stable id, and its index.

Each module of a part registers its entries (:class:`fusioncenter.figures.entry.Entry`) with
:func:`register` when it is imported; :func:`get` finds one by id, importing only the module
that registers it (found in the index, :mod:`fusioncenter.figures._index`), and
:func:`entries` lists them all in the papers' order. :func:`build_index` writes the index
(``python -m fusioncenter.figures`` does, and checks it with ``--check``).

The names of the entries' own modules are also this module's: the papers
(:mod:`fusioncenter.figures.papers`), the entry (:mod:`fusioncenter.figures.entry`), its claims
(:mod:`fusioncenter.figures.claim`), the settable parameters and the cache's names that the
figure modules use (:mod:`fusioncenter._cache`).
"""

from __future__ import annotations

from fusioncenter import _cache
from fusioncenter._cache import (  # noqa: F401 (the cache's names, used by the figure modules)
    CACHE_ENV,
    ComputeCacheError,
    locked,
    read_cached,
    write_cached,
)
from fusioncenter.context import Parameter
from fusioncenter.figures.claim import Claim, nonfinite_keys
from fusioncenter.figures.entry import STATUSES, Entry, EntryNotReady
from fusioncenter.figures.papers import PAPER_IDS, PAPERS

__all__ = [
    "PAPERS",
    "PAPER_IDS",
    "STATUSES",
    "Claim",
    "Entry",
    "EntryNotReady",
    "UnknownEntry",
    "ComputeCacheError",
    "Parameter",
    "nonfinite_keys",
    "REGISTRY",
    "register",
    "get",
    "ids",
    "entries",
]


class UnknownEntry(KeyError):
    """No registry entry has that id."""

    def __str__(self) -> str:  # KeyError quotes its argument; keep the message readable
        return str(self.args[0])


REGISTRY: dict[str, Entry] = {}


def register(entry: Entry) -> Entry:
    """Add an entry to the registry.

    Parameters
    ----------
    entry : Entry
        The entry; its ``id`` must not be registered yet.

    Returns
    -------
    Entry
        ``entry`` itself (so that a module can write ``ENTRY = register(Entry(...))``).

    Raises
    ------
    ValueError
        If an entry with the same id is already registered.
    """
    if entry.id in REGISTRY:
        raise ValueError(f"duplicate registry id {entry.id!r}")
    REGISTRY[entry.id] = entry
    import sys

    frame = sys._getframe(1)
    while frame is not None:  # the module whose import registers it (for the lazy index)
        name = frame.f_globals.get("__name__", "")
        if frame.f_code.co_name == "<module>" and name.startswith("fusioncenter.figures."):
            REGISTERED_BY[entry.id] = name[len("fusioncenter.figures."):]
            break
        frame = frame.f_back
    return entry


#: Registry id -> the module (below ``fusioncenter.figures``) whose import registered it.
REGISTERED_BY: dict[str, str] = {}


def get(entry_id: str) -> Entry:
    """The registered entry with the id ``entry_id``.

    Parameters
    ----------
    entry_id : str
        A registry id.

    Returns
    -------
    Entry
        The entry (the modules that register entries are imported first).

    Raises
    ------
    UnknownEntry
        If no entry has that id (the message suggests close ids).
    """
    if entry_id in REGISTRY:
        return REGISTRY[entry_id]
    from fusioncenter.figures import _index as index

    row = index.find(entry_id)
    if row is not None:  # import only the module that registers it
        import importlib

        importlib.import_module(f"fusioncenter.figures.{row['module']}")
    else:
        _load()
    try:
        return REGISTRY[entry_id]
    except KeyError:
        import difflib

        near = difflib.get_close_matches(entry_id, REGISTRY, n=3)
        hint = f"; did you mean {', '.join(near)}?" if near else ""
        raise UnknownEntry(
            f"unknown figure/table id {entry_id!r}{hint} (`python -m fusioncenter list` shows all)"
        ) from None


def own_ids() -> set[str]:
    """Ids of the book's own figures, as declared by the modules' ``OWN_IDS``.

    Returns
    -------
    set of str
        The union of the registering modules' ``OWN_IDS``.
    """
    import importlib

    _load()
    out: set[str] = set()
    for name in _MODULES:
        out |= set(getattr(importlib.import_module(f"fusioncenter.figures.{name}"), "OWN_IDS", ()))
    return out


def _order(entry: Entry) -> tuple:
    paper_rank = list(PAPERS).index(entry.paper)
    id_rank = PAPER_IDS.index(entry.id) if entry.id in PAPER_IDS else len(PAPER_IDS)
    return (paper_rank, id_rank)


def ids() -> list[str]:
    """The id of every entry, in the order of :func:`entries`.

    Returns
    -------
    list of str
        The ids.
    """
    return [e.id for e in entries()]


def entries() -> list[Entry]:
    """Every entry, ordered by paper (as in ``PAPERS``), then as the paper numbers them.

    Returns
    -------
    list of Entry
        The entries; the book's own keep the order in which they were registered.
    """
    _load()
    return sorted(REGISTRY.values(), key=_order)  # stable: own entries keep their order


def build_index(write: bool = True) -> dict:
    """The registry's index as it is now (imports every figure module): what
    ``fusioncenter list`` and ``params`` read (:mod:`fusioncenter.figures._index`).

    Parameters
    ----------
    write : bool, default True
        Also write it to the index file (where the package folder is writable).

    Returns
    -------
    dict
        ``{"source": fingerprint, "entries": [summary + "module" + "settable_lines"]}``.
    """
    import json as _json

    from fusioncenter.figures import _index

    rows = [{**e.summary(), "module": REGISTERED_BY[e.id], "settable_lines": e.settable_lines()}
            for e in entries() if e.id in REGISTERED_BY]
    index = _json.loads(_json.dumps({"source": _cache.fingerprint(), "entries": rows}))
    if write:
        _index.write(index)
    return index


#: Modules that register entries: the book's own and one per part. Each may list the ids of the
#: book's own figures it registers in ``OWN_IDS``; every id of ``figures.PAPER_IDS`` must be
#: registered by one of them (``tests/test_registry_cli.py`` checks the exact set).
_MODULES = ("background", "mo2015", "dey2009", "leong2011", "zheng2014", "zheng2014.vector",
            "zheng2014.nonlinear", "synthesis", "explorable")
_LOADED = False


def _load() -> None:
    """Import the modules that register entries (once)."""
    global _LOADED
    if _LOADED:
        return
    _LOADED = True
    import importlib

    for name in _MODULES:
        importlib.import_module(f"fusioncenter.figures.{name}")
