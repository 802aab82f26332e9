"""The registry: one entry per figure or table, with a stable id.

An entry knows its paper, caption and parameters; ``compute(profile, seed)`` returns plain data
(a dict of named NumPy arrays and scalars, no matplotlib); ``plot(data)`` returns a matplotlib
Figure; ``checks(data)`` returns the paper's claims about that figure, each evaluated on the data.
Its ``status`` is honest: ``not-started`` (no compute yet), ``reproduced`` (matches the paper
within the stated Monte Carlo error) or ``differs`` (the note says how and why).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
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
        check_profile(profile)
        if seed is not None and (not isinstance(seed, int) or seed < 0):
            raise ValueError(f"seed must be a non-negative integer, got {seed!r}")
        data = self._need("compute")(profile, self.seed if seed is None else seed)
        if not isinstance(data, dict):
            raise TypeError(f"{self.id}: compute must return a dict, got {type(data).__name__}")
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


def ids() -> list[str]:
    _load()
    return list(REGISTRY)


def entries() -> list[Entry]:
    _load()
    return list(REGISTRY.values())


_LOADED = False


def _load() -> None:
    """Import the modules that register entries (once)."""
    global _LOADED
    if _LOADED:
        return
    _LOADED = True
    from fusioncenter.figures import background, catalog  # noqa: F401
