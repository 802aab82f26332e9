"""The registry: one entry per figure or table, with a stable id.

An entry knows its paper, caption and parameters; ``compute(profile, seed)`` returns plain data
(a dict of named NumPy arrays and scalars, no matplotlib); ``plot(data)`` returns a matplotlib
Figure; ``checks(data)`` returns the paper's claims about that figure, each evaluated on the data.
Its ``status`` is honest: ``not-started`` (no compute yet), ``reproduced`` (matches the paper
within the stated Monte Carlo error) or ``differs`` (the note says how and why).
"""

from __future__ import annotations

import os
import pickle
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from fusioncenter.profile import check_profile

__all__ = [
    "PAPERS",
    "STATUSES",
    "Claim",
    "Entry",
    "EntryNotReady",
    "UnknownEntry",
    "REGISTRY",
    "register",
    "get",
    "ids",
    "entries",
]

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

STATUSES = ("not-started", "reproduced", "differs")

#: Environment variable naming a folder where :meth:`Entry.run_compute` keeps its results.
CACHE_ENV = "FUSIONCENTER_COMPUTE_CACHE"


class EntryNotReady(RuntimeError):
    """The entry has no compute (or plot, or checks) yet: its status is ``not-started``."""


class UnknownEntry(KeyError):
    """No registry entry has that id."""

    def __str__(self) -> str:  # KeyError quotes its argument; keep the message readable
        return str(self.args[0])


@dataclass(frozen=True)
class Claim:
    """One claim of a paper, checked on computed data."""

    name: str
    passed: bool
    detail: str = ""

    def __bool__(self) -> bool:
        return bool(self.passed)


@dataclass
class Entry:
    id: str
    paper: str
    kind: str  # "figure" | "table"
    caption: str
    chapter: str  # Sphinx docname of the chapter, e.g. "book/background/kalman-riccati"
    label: str = ""  # MyST target in that chapter ("" = the chapter itself)
    parameters: dict[str, Any] = field(default_factory=dict)
    compute: Callable[[str, int], dict] | None = None
    plot: Callable[[dict], Any] | None = None
    checks: Callable[[dict], list[Claim]] | None = None
    status: str = "not-started"
    note: str = ""
    seed: int = 20260101

    def __post_init__(self) -> None:
        if self.paper not in PAPERS:
            raise ValueError(f"entry {self.id}: unknown paper {self.paper!r}")
        if self.kind not in ("figure", "table"):
            raise ValueError(f"entry {self.id}: kind must be 'figure' or 'table'")
        if self.status not in STATUSES:
            raise ValueError(f"entry {self.id}: status must be one of {STATUSES}")
        if self.status != "not-started" and (self.compute is None or self.checks is None):
            raise ValueError(f"entry {self.id}: status {self.status!r} needs compute and checks")
        if self.status == "differs" and not self.note:
            raise ValueError(f"entry {self.id}: status 'differs' needs a note saying why")

    # -- running -------------------------------------------------------------------------
    def _need(self, what: str):
        fn = getattr(self, what)
        if fn is None:
            raise EntryNotReady(
                f"{self.id}: no {what} yet (status {self.status!r}); see the issue for its part"
            )
        return fn

    def run_compute(self, profile: str = "fast", seed: int | None = None) -> dict:
        """``compute(profile, seed)``, checked to return a dict.

        If the environment variable :data:`CACHE_ENV` names a folder, the data are stored there
        (one pickle per id, profile and seed) and read back by later calls, in any process:
        the book's build sets it to a folder inside its output that it wipes whenever the
        library, the lock or the configuration change (``tools/build_book.py``), so that a
        chapter that gathers other chapters' entries does not run them a second time. Unset
        (the tests, nbval, the command line), every call computes.
        """
        check_profile(profile)
        if seed is not None and (not isinstance(seed, int) or seed < 0):
            raise ValueError(f"seed must be a non-negative integer, got {seed!r}")
        seed = self.seed if seed is None else seed
        folder = os.environ.get(CACHE_ENV, "").strip()
        path = Path(folder) / f"{self.id}.{profile}.{seed}.pickle" if folder else None
        if path is not None and path.exists():
            with path.open("rb") as fh:
                return pickle.load(fh)
        data = self._need("compute")(profile, seed)
        if not isinstance(data, dict):
            raise TypeError(f"{self.id}: compute must return a dict, got {type(data).__name__}")
        if path is not None:
            path.parent.mkdir(parents=True, exist_ok=True)
            tmp = path.with_suffix(f".{os.getpid()}.tmp")
            with tmp.open("wb") as fh:
                pickle.dump(data, fh, protocol=pickle.HIGHEST_PROTOCOL)
            tmp.replace(path)  # atomic: a reader never sees half a file
        return data

    def run_plot(self, data: dict):
        return self._need("plot")(data)

    def run_checks(self, data: dict) -> list[Claim]:
        claims = list(self._need("checks")(data))
        if not claims:
            raise EntryNotReady(f"{self.id}: checks returned no claims")
        return claims

    def summary(self) -> dict:
        return {
            "id": self.id,
            "paper": self.paper,
            "kind": self.kind,
            "caption": self.caption,
            "chapter": self.chapter,
            "label": self.label,
            "parameters": self.parameters,
            "status": self.status,
            "note": self.note,
            "has_compute": self.compute is not None,
            "has_plot": self.plot is not None,
            "has_checks": self.checks is not None,
        }


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
    return entry


def get(entry_id: str) -> Entry:
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
    """Ids of the book's own figures, as declared by the modules' ``OWN_IDS``."""
    import importlib

    _load()
    out: set[str] = set()
    for name in _MODULES:
        out |= set(getattr(importlib.import_module(f"fusioncenter.figures.{name}"), "OWN_IDS", ()))
    return out


def _order(entry: Entry) -> tuple:
    from fusioncenter.figures import PAPER_IDS

    paper_rank = list(PAPERS).index(entry.paper)
    id_rank = PAPER_IDS.index(entry.id) if entry.id in PAPER_IDS else len(PAPER_IDS)
    return (paper_rank, id_rank)


def ids() -> list[str]:
    return [e.id for e in entries()]


def entries() -> list[Entry]:
    """Every entry, ordered by paper (as in ``PAPERS``), then as the paper numbers them."""
    _load()
    return sorted(REGISTRY.values(), key=_order)  # stable: own entries keep their order


#: Modules that register entries: the book's own and one per part. Each may list the ids of the
#: book's own figures it registers in ``OWN_IDS``; every id of ``figures.PAPER_IDS`` must be
#: registered by one of them (``tests/test_registry_cli.py`` checks the exact set).
_MODULES = ("background", "mo2015", "dey2009", "leong2011", "zheng2014", "zheng2014_vector",
            "zheng2014_nonlinear", "synthesis")
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
