"""The registry: one entry per figure or table, with a stable id.

An entry knows its paper, caption and parameters; ``compute(profile, seed, **overrides)``
returns plain data (a dict of named NumPy arrays and scalars, no matplotlib), where the
overrides are the entry's ``settable`` parameters (:class:`fusioncenter.context.Parameter`)
and the executor comes from the execution context (:mod:`fusioncenter.context`); ``plot(data)``
returns a matplotlib Figure; ``checks(data)`` returns the paper's claims about that figure,
each evaluated on the data. Its ``status`` is honest: ``not-started`` (no compute yet),
``reproduced`` (matches the paper within the stated Monte Carlo error) or ``differs`` (the
note says how and why).
"""

from __future__ import annotations

import hashlib
import json
import os
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from fusioncenter import _cache, context
from fusioncenter._cache import (  # noqa: F401 (the cache's names, used by the figure modules)
    CACHE_ENV,
    ComputeCacheError,
    locked,
    read_cached,
    write_cached,
)
from fusioncenter.context import Parameter
from fusioncenter.profile import check_profile

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



class EntryNotReady(RuntimeError):
    """The entry has no compute (or plot, or checks) yet: its status is ``not-started``."""


class UnknownEntry(KeyError):
    """No registry entry has that id."""

    def __str__(self) -> str:  # KeyError quotes its argument; keep the message readable
        return str(self.args[0])


@dataclass(frozen=True)
class Claim:
    """One claim of a paper, checked on computed data.

    ``passed`` must be a real ``bool`` (a NumPy bool is converted): anything else, such as the
    string ``"False"``, is a ``TypeError``, never a pass. ``paper_specific`` marks a claim about
    the paper's own setting (its printed numbers, its ``N`` or ``l``): ``verify`` skips it when
    a model parameter is overridden.

    Attributes
    ----------
    name : str
        What is claimed, in words.
    passed : bool
        Whether the data bear the claim out.
    detail : str
        The numbers behind the verdict (shown next to it), or ``""``.
    paper_specific : bool
        The claim is about the paper's own setting.

    Raises
    ------
    TypeError
        If ``passed`` or ``paper_specific`` is not a ``bool`` (``passed`` may be a NumPy bool).
    """

    name: str
    passed: bool
    detail: str = ""
    paper_specific: bool = False

    def __post_init__(self) -> None:
        if isinstance(self.passed, np.bool_):
            object.__setattr__(self, "passed", bool(self.passed))
        if not isinstance(self.passed, bool):
            raise TypeError(f"claim {self.name!r}: passed must be a bool, got "
                            f"{type(self.passed).__name__} {self.passed!r}")
        if not isinstance(self.paper_specific, bool):
            raise TypeError(f"claim {self.name!r}: paper_specific must be a bool")

    def __bool__(self) -> bool:
        return self.passed


def nonfinite_keys(data: dict, allowed=()) -> list[str]:
    """The keys of ``data`` (outside ``allowed``) whose numbers include NaN or an infinity.

    Floats, complex numbers and numeric arrays are inspected, also inside lists, tuples and
    nested dicts (``outer.inner``); text and integers are never non-finite.

    Parameters
    ----------
    data : dict
        An entry's computed data.
    allowed : container of str
        Keys whose values may be non-finite (skipped).

    Returns
    -------
    list of str
        The offending top-level keys, as strings, in the order of ``data``.
    """
    bad = []

    def has_nonfinite(v) -> bool:
        if isinstance(v, dict):
            return any(has_nonfinite(x) for x in v.values())
        if isinstance(v, float | complex | np.floating | np.complexfloating):
            return not np.isfinite(v)
        if isinstance(v, list | tuple):
            return any(has_nonfinite(x) for x in v)
        if isinstance(v, np.ndarray):
            if v.dtype.kind in "fc":
                return not bool(np.isfinite(v).all())
            if v.dtype == object:
                return any(has_nonfinite(x) for x in v.ravel())
        return False

    for key, value in data.items():
        if key not in allowed and has_nonfinite(value):
            bad.append(str(key))
    return bad


@dataclass
class Entry:
    """A figure or table of the book: what it shows, and the functions that compute it, draw it
    and check the paper's claims on it.

    Attributes
    ----------
    id : str
        The stable id (``python -m fusioncenter list``).
    paper : str
        A key of :data:`PAPERS`.
    kind : str
        ``"figure"`` or ``"table"``.
    caption : str
        What the figure or table shows.
    chapter : str
        Sphinx docname of the chapter, e.g. ``"book/background/kalman-riccati"``.
    label : str
        MyST target in that chapter (``""``: the chapter itself).
    parameters : dict
        The model and run parameters behind the figure, as plain data (shown by
        :meth:`summary`).
    compute : callable or None
        ``compute(profile, seed, **overrides) -> dict`` of plain data.
    plot : callable or None
        ``plot(data)`` -> a matplotlib Figure.
    checks : callable or None
        ``checks(data)`` -> a list of :class:`Claim`.
    status : str
        One of ``STATUSES``: "not-started", "reproduced" or "differs".
    note : str
        How and why the result differs from the paper (required for ``"differs"``).
    reason : str
        The note in one line, for the caption of a ``"differs"`` entry ("Differs from Fig. 3
        of ...: <reason>."); ``""``: the note's first sentence (:meth:`differs_reason`).
    seed : int
        The default seed of :meth:`run_compute`.
    settable : tuple of Parameter
        The parameters ``compute`` accepts as keyword overrides (``--set key=value``).
    nonfinite_ok : tuple of str
        Data keys in which NaN or inf are legitimate values (e.g. an undefined z-score); in any
        other key they make every claim fail (see :meth:`run_checks`).

    Raises
    ------
    ValueError
        If ``paper``, ``kind`` or ``status`` is unknown, a status other than ``"not-started"``
        lacks ``compute`` or ``checks``, or ``"differs"`` lacks a ``note``.
    """

    id: str
    paper: str
    kind: str
    caption: str
    chapter: str
    label: str = ""
    parameters: dict[str, Any] = field(default_factory=dict)
    compute: Callable[..., dict] | None = None
    plot: Callable[[dict], Any] | None = None
    checks: Callable[[dict], list[Claim]] | None = None
    status: str = "not-started"
    note: str = ""
    reason: str = ""
    seed: int = 20260101
    settable: tuple[Parameter, ...] = ()
    nonfinite_ok: tuple[str, ...] = ()

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

    def differs_reason(self) -> str:
        """How the entry differs from the paper, in one line (no final full stop).

        Returns
        -------
        str
            :attr:`reason`, else the first sentence of :attr:`note`; ``""`` unless the status
            is ``"differs"``.
        """
        if self.status != "differs":
            return ""
        text = (self.reason or self.note).strip()
        if not self.reason:
            m = re.match(r"(.+?[.!?])(\s+[A-Z(]|$)", text, re.S)
            text = m[1] if m else text
        return text.rstrip(". ")

    # -- running -------------------------------------------------------------------------
    def _need(self, what: str):
        fn = getattr(self, what)
        if fn is None:
            raise EntryNotReady(
                f"{self.id}: no {what} yet (status {self.status!r}); see the issue for its part"
            )
        return fn

    def check_overrides(self, overrides: dict) -> dict:
        """The overrides parsed against :attr:`settable`; ``ValueError`` listing the valid
        keys for an unknown key, naming the parameter for a bad value."""
        return context.check_overrides(self.id, self.settable, overrides)

    def resolved_parameters(self, profile: str, overrides: dict | None = None) -> dict:
        """Every settable parameter's value in a run of ``profile`` with ``overrides``."""
        check_profile(profile)
        over = self.check_overrides(overrides or {})
        return {p.name: over.get(p.name, p.default_for(profile)) for p in self.settable}

    def model_overridden(self, overrides: dict | None) -> list[str]:
        """The overridden parameters that change the paper's setting (not only the accuracy)."""
        by = {p.name: p for p in self.settable}
        return sorted(k for k in (overrides or {}) if k in by and by[k].model)

    def run_compute(self, profile: str = "fast", seed: int | None = None, *,
                    executor: str | None = None, progress: bool = False,
                    **overrides) -> dict:
        """``compute(profile, seed, **overrides)`` in an execution context, checked to return a
        dict.

        Parameters
        ----------
        profile, seed
            The profile (``fast`` or ``paper``) and a non-negative integer seed (default: the
            entry's).
        executor
            Where the Monte Carlo tasks run: ``serial``, ``processes[:N]``, ``dask:local`` or
            ``dask:ADDRESS`` (:func:`fusioncenter.context.parse_executor`). Default
            :func:`fusioncenter.context.default_spec`. The data do not depend on it.
        progress
            Report the progress of long Monte Carlo runs on stderr (the command line does).
        **overrides
            Values of the entry's :attr:`settable` parameters (unknown keys and bad values are
            a ``ValueError``).

        If the environment variable :data:`CACHE_ENV` names a folder, the data are stored there
        (one ``.npz`` file per id, profile, seed and overrides, in a format that cannot run code
        when read: :mod:`fusioncenter._cache`) and read back by later calls, in any process, as
        long as the library's version and source fingerprint are those the file was written
        with (otherwise the entry is computed again and the file replaced). A file that fails
        its integrity check (edited, truncated, planted), or holds no dict, is never served: a
        warning names it and the entry is computed again. The book's build sets it to a folder
        inside its output that it wipes whenever the library, the lock or the configuration
        change (``tools/build_book.py``), so that a
        chapter that gathers other chapters' entries does not run them a second time. Chapters
        executing in parallel share the folder safely: writes are atomic (a temporary file
        renamed), and a process computing an entry holds a lock on it, so that another one
        needing the same entry waits and reads it instead of computing it again. A file that
        cannot be read at all (permissions) is a :class:`ComputeCacheError`. Unset (the tests,
        nbval, the command line by default), every call computes.
        """
        check_profile(profile)
        if seed is not None and (isinstance(seed, bool) or not isinstance(seed, int | np.integer)
                                 or seed < 0):
            raise ValueError(f"seed must be a non-negative integer, got {seed!r}")
        seed = self.seed if seed is None else int(seed)
        spec = context.default_spec(profile) if executor is None else \
            context.parse_executor(executor)
        compute = self._need("compute")
        over = self.check_overrides(overrides)
        self.check_bounds(profile, over)
        folder = os.environ.get(CACHE_ENV, "").strip()
        ctx = context.ExecutionContext(profile, seed, spec, over, progress=bool(progress))
        if not folder:
            return self._compute_in(ctx, compute, over)
        tag = ""
        if over:
            blob = json.dumps(sorted(over.items()), default=str).encode()
            tag = "." + hashlib.sha256(blob).hexdigest()[:12]
        path = Path(folder) / f"{self.id}.{profile}.{seed}{tag}{_cache.SUFFIX}"
        key = {"id": self.id, "profile": profile, "seed": seed,
               "overrides": sorted(over.items())}
        path.parent.mkdir(parents=True, exist_ok=True)
        with locked(path.with_suffix(".lock")):  # a parallel chapter computing it: wait
            if path.exists():
                found, data = read_cached(path, key)
                if found and isinstance(data, dict):
                    return data
                if found:
                    _cache.distrust(path, f"it holds a {type(data).__name__}, not a dict")
            data = self._compute_in(ctx, compute, over)
            write_cached(path, data, key)
        return data

    def check_bounds(self, profile: str, overrides: dict) -> dict:
        """Every bound between parameters (``0 < l <= N``, ``trials_heavy <= trials``) checked
        on the values of a run of ``profile`` with the parsed ``overrides``, before computing.

        Parameters
        ----------
        profile : str
            ``"fast"`` or ``"paper"`` (the defaults of the parameters not overridden).
        overrides : dict
            The overrides parsed by :meth:`check_overrides`.

        Returns
        -------
        dict
            The resolved values (every settable parameter).

        Raises
        ------
        ValueError
            Naming the parameter and the bound it breaks.
        """
        values = {p.name: overrides.get(p.name, p.default_for(profile)) for p in self.settable}
        for p in self.settable:
            p.check_relations(values)
        return values

    def _compute_in(self, ctx, compute, over: dict) -> dict:
        with context.activate(ctx):
            data = compute(ctx.profile, ctx.seed, **over)
        if not isinstance(data, dict):
            raise TypeError(f"{self.id}: compute must return a dict, got {type(data).__name__}")
        return data

    def run_plot(self, data: dict):
        """``plot(data)``, with each panel of a figure of several panels given its own letter
        (:func:`fusioncenter.plotting.letter_panels`)."""
        from fusioncenter import plotting

        return plotting.letter_panels(self._need("plot")(data))

    def run_checks(self, data: dict) -> list[Claim]:
        """The entry's claims evaluated on ``data``.

        A claim is only as good as the numbers it reads: if ``data`` hold NaN or inf outside
        :attr:`nonfinite_ok` (a computation gone wrong, or data tampered with), every claim is
        reported failed, with the offending keys in its detail, whatever its own test says.
        A check that raises on such data fails the same way instead of raising.
        """
        check = self._need("checks")
        bad = nonfinite_keys(data, self.nonfinite_ok)
        try:
            claims = list(check(data))
        except Exception as exc:  # noqa: BLE001 (re-raised below unless the data explain it)
            if not bad:
                raise
            return [Claim(f"{self.id}: the claims", False,
                          f"data have non-finite values in {', '.join(bad)}; the checks "
                          f"raised {type(exc).__name__}: {exc}")]
        if not claims:
            raise EntryNotReady(f"{self.id}: checks returned no claims")
        for c in claims:
            if not isinstance(c, Claim):
                raise TypeError(f"{self.id}: checks must return Claim objects, got {c!r}")
        if bad:
            note = f"FAILED: data have non-finite values in {', '.join(bad)}"
            claims = [Claim(c.name, False, f"{note}; {c.detail}" if c.detail else note,
                            c.paper_specific) for c in claims]
        return claims

    def split_claims(self, claims: list[Claim], overrides: dict | None = None) -> tuple:
        """``(checked, skipped)``: with a model parameter overridden, the paper-specific claims
        are skipped (they are about the paper's setting); otherwise every claim is checked."""
        if not self.model_overridden(overrides):
            return list(claims), []
        return ([c for c in claims if not c.paper_specific],
                [c for c in claims if c.paper_specific])

    def settable_lines(self) -> list[str]:
        """The lines of ``fusioncenter params ID``.

        Returns
        -------
        list of str
            Each parameter with its type, every bound (also one set by another parameter)
            and its default per profile; one line saying there is none otherwise.
        """
        if not self.settable:
            return [f"{self.id}: no parameters to override"]
        return [p.describe() + ("  [changes the paper's setting]" if p.model else "")
                for p in self.settable]

    def summary(self) -> dict:
        return {
            "id": self.id,
            "paper": self.paper,
            "kind": self.kind,
            "caption": self.caption,
            "chapter": self.chapter,
            "label": self.label,
            "parameters": self.parameters,
            "settable": {p.name: p.describe() for p in self.settable},
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
