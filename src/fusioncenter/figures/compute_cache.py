"""The entries' compute cache: computed data kept in a folder, shared between processes.

If the environment variable :data:`~fusioncenter._cache.CACHE_ENV` names a folder, the data of
:meth:`fusioncenter.figures.entry.Entry.run_compute` are stored there (one ``.npz`` file per id,
profile, seed and overrides, in a format that cannot run code when read:
:mod:`fusioncenter._cache`) and read back by later calls, in any process, as long as the
library's version and source fingerprint are those the file was written with (otherwise the
entry is computed again and the file replaced). A file that fails its integrity check (edited,
truncated, planted), or holds no dict, is never served: a warning names it and the entry is
computed again. The book's build sets it to a folder inside its output that it wipes whenever
the library, the lock or the configuration change (``tools/build_book.py``), so that a chapter
that gathers other chapters' entries does not run them a second time. Chapters executing in
parallel share the folder safely: writes are atomic (a temporary file renamed), and a process
computing an entry holds a lock on it, so that another one needing the same entry waits and
reads it instead of computing it again. A file that cannot be read at all (permissions) is a
:class:`~fusioncenter._cache.ComputeCacheError`. Unset (the tests, nbval, the command line by
default), every call computes.
"""

from __future__ import annotations

import hashlib
import json
import os
from collections.abc import Callable
from pathlib import Path

from fusioncenter import _cache
from fusioncenter._cache import CACHE_ENV, locked, read_cached, write_cached

__all__ = ["cached"]


def cached(entry_id: str, profile: str, seed: int, overrides: dict,
           compute: Callable[[], dict]) -> dict:
    """The data of one run of an entry: read from the cache folder, else computed (and stored).

    Parameters
    ----------
    entry_id : str
        The registry id.
    profile : str
        ``"fast"`` or ``"paper"``.
    seed : int
        The run's seed.
    overrides : dict
        The run's parsed overrides (part of the file's name and key).
    compute : callable
        ``compute()`` returns the run's data; called unless the cache holds them.

    Returns
    -------
    dict
        The data; ``compute()`` itself where :data:`~fusioncenter._cache.CACHE_ENV` is unset.

    Raises
    ------
    fusioncenter._cache.ComputeCacheError
        If a file of the cache cannot be read at all.
    """
    folder = os.environ.get(CACHE_ENV, "").strip()
    if not folder:
        return compute()
    tag = ""
    if overrides:
        blob = json.dumps(sorted(overrides.items()), default=str).encode()
        tag = "." + hashlib.sha256(blob).hexdigest()[:12]
    path = Path(folder) / f"{entry_id}.{profile}.{seed}{tag}{_cache.SUFFIX}"
    key = {"id": entry_id, "profile": profile, "seed": seed,
           "overrides": sorted(overrides.items())}
    path.parent.mkdir(parents=True, exist_ok=True)
    with locked(path.with_suffix(".lock")):  # a parallel chapter computing it: wait
        if path.exists():
            found, data = read_cached(path, key)
            if found and isinstance(data, dict):
                return data
            if found:
                _cache.distrust(path, f"it holds a {type(data).__name__}, not a dict")
        data = compute()
        write_cached(path, data, key)
    return data
