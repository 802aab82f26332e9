"""The runs of the zheng2014 particle-filter entries, kept for the life of the process.

Several entries need the same run: Fig. 3's all-send and random selection are Fig. 1's, Fig. 6's
are Fig. 4's (all-send and random selection use neither what is fed back nor the likelihood:
:data:`BLIND`), and the "as chosen" row of ``zheng2014-table1-choices`` is the first trials of
Fig. 2's runs. :func:`kept_run` runs a scheme once per process and hands the run (or its first
trials) to every entry of :mod:`fusioncenter.figures.zheng2014` and
:mod:`fusioncenter.figures.zheng2014.vector` that asks for it again.

A run is identified by everything that fixes its numbers: the scenario (all its fields; scalar
or vector observations), the scheme, what is fed back and the likelihood (where they matter),
``l``, the particles and the seed, and the trials. A request for ``n`` trials is met by a kept
run of more trials when ``n`` is a multiple of the block size
(:data:`fusioncenter.montecarlo.DEFAULT_BLOCK_SIZE`): its first ``n`` trials are then those of a
run of ``n`` (:func:`~fusioncenter.figures.zheng2014.common.subset`).
The executor and the chunking are not part of the identity: they do not change the numbers.

If the environment variable ``FUSIONCENTER_COMPUTE_CACHE`` names a folder (the
book's build sets it), a run is also stored in its subfolder ``zheng2014-runs`` (one ``.npz``
file per identity without the trials, holding the longest run made, in the cache's format that
cannot run code and is checked when read, :mod:`fusioncenter._cache`; written atomically, under
a lock, so that a process needing a run another process is making waits and reads it): an entry
computed in a fresh process then takes the runs another process made. That folder is the registry's
compute cache, and is wiped with it (the book's build wipes it whenever the library changes).
Unset (the tests, the command line), a fresh process keeps nothing and computes every run.
"""

from __future__ import annotations

import dataclasses
import hashlib
import os
import threading
from collections import OrderedDict
from pathlib import Path

from fusioncenter import censoring as cs
from fusioncenter import montecarlo
from fusioncenter.censoring import vector as cv
from fusioncenter.figures.registry import CACHE_ENV, locked, read_cached, write_cached
from fusioncenter.figures.zheng2014.common import run_scheme, subset

#: The most runs kept (the least recently used is dropped first). A paper-profile run of the
#: scalar entries holds about 4 MB (5000 trials x 20 steps x 5 columns); the five entries of
#: ``book/zheng2014/results`` make 48 distinct runs.
MAX_RUNS = 64

_KEPT: OrderedDict = OrderedDict()
_GUARD = threading.Lock()  # threads of one process computing entries at once

#: The schemes whose run depends neither on the feedback nor on the likelihood: their decisions
#: are known in advance and their weights have no silent factor (only the censoring schemes read
#: the broadcast, and only CFwMD without feedback reads ``likelihood``).
BLIND = ("all-send", "random")


def _identity(sc, scheme: str, feedback: str, l: float, likelihood: str, P: int,
              seed: int) -> tuple:
    if scheme in BLIND:
        feedback, likelihood = "none", "exact"
    return (sc, scheme, feedback, float(l), likelihood, int(P), int(seed))


def _usable(m: int, n: int) -> bool:
    """A run of ``m`` trials gives the numbers of a run of ``n``."""
    return m == n or (m > n and n % montecarlo.DEFAULT_BLOCK_SIZE == 0)


def _store(ident: tuple) -> Path | None:
    """The file of the compute cache holding the runs of ``ident``, or ``None`` (unset)."""
    folder = os.environ.get(CACHE_ENV, "").strip()
    if not folder:
        return None
    # the repr of a scenario lists every field (floats exactly): it identifies the run
    digest = hashlib.sha256(repr(ident).encode()).hexdigest()[:24]
    return Path(folder) / "zheng2014-runs" / f"{digest}.npz"


def _stored_or_run(ident: tuple, path: Path | None, n: int, run) -> cs.CensoringResult:
    """The run of ``ident`` from the file ``path`` if it has a usable one, else ``run()`` (then
    stored there if it is longer than what the file holds)."""
    if path is None:
        return run()
    path.parent.mkdir(parents=True, exist_ok=True)
    with locked(path.with_suffix(".lock")):
        key = {"zheng2014-run": repr(ident)}
        found, old = read_cached(path, key) if path.exists() else (False, None)
        if found and not isinstance(old, cs.CensoringResult):
            found, old = False, None
        if found and _usable(old.mc.n_trials, n):
            return old
        res = run()
        if old is None or res.mc.n_trials > old.mc.n_trials:
            write_cached(path, res, key)
        return res


def kept_run(sc, scheme: str, *, feedback: str, l: float, n: int, P: int, seed: int,
             likelihood: str = "corrected", executor=None,
             chunk_size: int | None = None) -> cs.CensoringResult:
    """:func:`~fusioncenter.figures.zheng2014.common.run_scheme`, run once per process.

    Parameters
    ----------
    sc, scheme, feedback, l, n, P, seed, likelihood, executor, chunk_size
        As in :func:`~fusioncenter.figures.zheng2014.common.run_scheme`; ``sc`` a
        :class:`~fusioncenter.censoring.scenarios.LinearScenario` or a
        :class:`~fusioncenter.censoring.vector.VectorScenario`. The executor and the chunks
        do not change the numbers.

    Returns
    -------
    CensoringResult
        The same numbers as ``run_scheme(sc, scheme, ...)`` with these arguments, taken from a
        run kept in this process or stored in the compute cache when there is one (see the
        module docstring); its ``feedback`` and ``likelihood`` are the ones asked for.

    Raises
    ------
    ValueError
        If ``sc`` is neither a :class:`~fusioncenter.censoring.scenarios.LinearScenario` nor a
        :class:`~fusioncenter.censoring.vector.VectorScenario` (and as
        :func:`fusioncenter.censoring.run` for bad arguments).
    OSError
        (``ComputeCacheError``) If the stored file of the run cannot be read (permissions);
        a file that fails its integrity check is not used (a warning names it) and the run is
        made again.
    """
    if not isinstance(sc, cs.LinearScenario | cv.VectorScenario):
        raise ValueError(f"sc must be a LinearScenario or a VectorScenario, got "
                         f"{type(sc).__name__}")
    ident = _identity(sc, scheme, feedback, l, likelihood, P, seed)
    with _GUARD:
        found = next((key for key in _KEPT if key[0] == ident and _usable(key[1], n)), None)
        if found is not None:
            _KEPT.move_to_end(found)
            res = _KEPT[found]
    if found is None:
        res = _stored_or_run(ident, _store(ident), n, lambda: run_scheme(
            sc, scheme, feedback=feedback, l=l, n=n, P=P, seed=seed, likelihood=likelihood,
            executor=executor, chunk_size=chunk_size))
        with _GUARD:
            _KEPT[(ident, res.mc.n_trials)] = res
            while len(_KEPT) > MAX_RUNS:
                _KEPT.popitem(last=False)
    res = subset(res, n)
    if (res.feedback, res.likelihood) != (feedback, likelihood):
        res = dataclasses.replace(res, feedback=feedback, likelihood=likelihood)
    return res


def forget_runs() -> None:
    """Drop every run kept in this process (the next requests compute again, or read the
    compute cache).

    Returns
    -------
    None
    """
    with _GUARD:
        _KEPT.clear()
