"""The one Monte Carlo runner.

Every simulation in the book goes through :func:`simulate`. Its contract:

* The trials ``0 .. n_trials-1`` are cut into fixed *blocks* of ``block_size`` trials. Block ``b``
  draws all of its randomness from its own generator, seeded by the ``b``-th child of
  ``numpy.random.SeedSequence(seed)``. The blocks therefore depend only on ``(seed, n_trials,
  block_size)``.
* ``chunk_size`` and ``executor`` decide only how blocks are grouped into tasks and where tasks
  run. The per-trial results are put back in trial order before any reduction, so ``.mean`` and
  ``.stderr`` are bitwise identical for every ``chunk_size`` and every executor (serial, a
  ``concurrent.futures.ProcessPoolExecutor``, or ``dask.distributed.Client(...).get_executor()``).
* ``chunk_fn(rng, n)`` simulates ``n`` independent trials with the generator ``rng`` and returns an
  array shaped ``(n, ...)`` (vectorize across trials inside it). For a process pool or a cluster it
  must be picklable: a module-level function or a ``functools.partial`` of one.

Registry entries take their executor from the execution context (:mod:`fusioncenter.context`:
``serial``, ``processes[:N]``, ``dask:local`` or ``dask:ADDRESS``), set by ``--executor`` on the
command line and ``FUSIONCENTER_EXECUTOR`` for the book.
"""

from __future__ import annotations

import math
import os
import sys
import time
from collections.abc import Callable
from concurrent.futures import Executor, as_completed
from dataclasses import dataclass, field

import numpy as np

__all__ = ["PerTrial", "MonteCarloResult", "simulate", "DEFAULT_BLOCK_SIZE"]

#: Trials per independent random stream of :func:`simulate` (part of what fixes the draws).
DEFAULT_BLOCK_SIZE = 256


class PerTrial:
    """What results keeping per-trial ``samples`` (first axis: the trials) of :func:`simulate`
    share; the ``seed`` and ``block_size`` that drew them identify the trials.

    Attributes
    ----------
    samples : numpy.ndarray
        The per-trial results, shaped ``(n_trials, ...)``.
    seed : int
        The seed of :func:`simulate` that drew them.
    block_size : int
        The trials per random stream of that run.
    """

    samples: np.ndarray
    seed: int
    block_size: int

    @property
    def n_trials(self) -> int:
        """The number of trials (the length of the first axis of ``samples``)."""
        return int(self.samples.shape[0])

    def same_trials(self, other: PerTrial) -> bool:
        """Whether ``other`` was simulated on the same trials (equal ``seed``, ``block_size`` and
        ``n_trials``), so that the two can be compared trial by trial (paired).

        Parameters
        ----------
        other : PerTrial
            Another result.

        Returns
        -------
        bool
        """
        return (self.seed, self.block_size, self.n_trials) == \
            (other.seed, other.block_size, other.n_trials)


@dataclass(frozen=True)
class MonteCarloResult(PerTrial):
    """Per-trial samples and their summary.

    ``mean`` and ``stderr`` (standard error of the mean, ``std(ddof=1) / sqrt(n)``) have the shape
    of one trial's result. ``samples`` keeps every trial, shaped ``(n_trials, ...)``, for
    quantiles and histograms.

    Parameters
    ----------
    samples : numpy.ndarray, shape (n_trials, ...)
        One row per trial, in trial order.
    seed : int
        The seed the trials were drawn with.
    block_size : int
        The trials per random stream they were drawn with (see :func:`simulate`).
    """

    samples: np.ndarray = field(repr=False)
    seed: int
    block_size: int

    @property
    def mean(self) -> np.ndarray:
        """The mean over the trials, shaped like one trial's result (``samples.shape[1:]``)."""
        return self.samples.mean(axis=0)

    @property
    def std(self) -> np.ndarray:
        """The sample standard deviation over the trials (``ddof=1``), shaped like one trial's
        result; all NaN with fewer than 2 trials."""
        if self.n_trials < 2:
            return np.full(self.samples.shape[1:], np.nan)
        return self.samples.std(axis=0, ddof=1)

    @property
    def stderr(self) -> np.ndarray:
        """The standard error of the mean, ``std / sqrt(n_trials)`` (NaN with 1 trial)."""
        return self.std / math.sqrt(self.n_trials)

    def ci(self, z: float = 1.96) -> tuple[np.ndarray, np.ndarray]:
        """Normal-approximation confidence band ``mean -/+ z * stderr``.

        Parameters
        ----------
        z : float, default 1.96
            The half-width in standard errors (1.96: a 95 % band).

        Returns
        -------
        lower, upper : numpy.ndarray
            ``mean - z * stderr`` and ``mean + z * stderr``, each shaped like :attr:`mean`.
        """
        return self.mean - z * self.stderr, self.mean + z * self.stderr


def _check_int(name: str, value, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int | np.integer):
        raise ValueError(f"{name} must be an integer, got {value!r}")
    if value < minimum:
        raise ValueError(f"{name} must be >= {minimum}, got {value}")
    return int(value)


#: Bytes a block's seed (a ``SeedSequence`` and its place in the task list) costs, about.
_SEED_BYTES = 600


def available_memory() -> int | None:
    """The memory this process can still allocate, about.

    Returns
    -------
    int or None
        Bytes: ``MemAvailable`` of ``/proc/meminfo`` (else the available physical pages),
        capped by an address-space limit (``RLIMIT_AS``); ``None`` where it is unknown.
    """
    avail = None
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    avail = int(line.split()[1]) * 1024
                    break
    except (OSError, ValueError, IndexError):
        pass
    if avail is None:
        try:
            avail = os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
        except (ValueError, OSError, AttributeError):
            return None
    try:
        import resource

        soft = resource.getrlimit(resource.RLIMIT_AS)[0]
        if soft != resource.RLIM_INFINITY:
            avail = min(avail, soft)
    except (ImportError, OSError, ValueError):
        pass
    return avail


def _gib(nbytes: float) -> str:
    return f"{nbytes / 2**30:.3g} GiB" if nbytes >= 2**28 else f"{nbytes / 2**20:.3g} MiB"


def check_memory(name: str, value: int, nbytes: float, what: str) -> None:
    """Refuse, before allocating, a size whose memory exceeds what the machine has.

    Parameters
    ----------
    name : str
        The parameter that sets the size (named in the message).
    value : int
        Its value.
    nbytes : float
        The estimated bytes the run needs.
    what : str
        What the memory is for (in the message).

    Returns
    -------
    None
        Nothing when the size fits (or the memory available is unknown).

    Raises
    ------
    ValueError
        If ``nbytes`` exceeds 90 % of :func:`available_memory`; the message gives the
        estimate and what is available.
    """
    avail = available_memory()
    if avail is not None and nbytes > 0.9 * avail:
        raise ValueError(f"{name} = {value}: {what} would need about {_gib(nbytes)} of memory, "
                         f"more than the {_gib(avail)} available; use a smaller {name}")


def _duration(seconds: float) -> str:
    if seconds < 90:
        return f"{seconds:.0f} s"
    if seconds < 5400:
        return f"{seconds / 60:.0f} min"
    if seconds < 2 * 86400:
        return f"{seconds / 3600:.1f} h"
    return f"{seconds / 86400:.1f} days"


class _Progress:
    """Progress of a long run on stderr: a tqdm bar on a terminal, else a line every 30 s;
    nothing for a run expected to end within a few seconds."""

    def __init__(self, total: int, done: int, eta: float, force: bool) -> None:
        self.total, self.done, self.t0 = total, done, time.monotonic()
        self.bar = None
        self.last = self.t0
        tty = sys.stderr.isatty()
        self.active = force or eta > (2.0 if tty else 10.0)
        if not self.active:
            return
        if force or tty:
            from tqdm.auto import tqdm

            self.bar = tqdm(total=total, initial=done, desc="Monte Carlo", unit="trial",
                            file=sys.stderr)
        else:
            print(f"Monte Carlo: {total} trials, about {_duration(eta)} (estimated from the "
                  "first block)", file=sys.stderr, flush=True)

    def update(self, n: int) -> None:
        self.done += n
        if not self.active:
            return
        if self.bar is not None:
            self.bar.update(n)
            return
        now = time.monotonic()
        if now - self.last >= 30 and self.done < self.total:
            self.last = now
            rate = (self.done) / max(now - self.t0, 1e-9)
            print(f"Monte Carlo: {self.done} of {self.total} trials "
                  f"({100 * self.done / self.total:.1f} %), about "
                  f"{_duration((self.total - self.done) / max(rate, 1e-12))} left",
                  file=sys.stderr, flush=True)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


def _run_blocks(chunk_fn: Callable, blocks: list[tuple[np.random.SeedSequence, int]]) -> list:
    """Run one task: each block with its own generator. Top level so that it pickles."""
    out = []
    for seed_seq, n in blocks:
        rng = np.random.default_rng(seed_seq)
        res = np.asarray(chunk_fn(rng, n))
        if res.ndim == 0 or res.shape[0] != n:
            raise ValueError(
                f"chunk_fn(rng, n={n}) must return an array shaped (n, ...); got shape {res.shape}"
            )
        out.append(res)
    return out


def _context_progress() -> bool:
    """Whether the active execution context asks for progress (the command line does)."""
    ctx_mod = sys.modules.get("fusioncenter.context")
    ctx = ctx_mod.current() if ctx_mod is not None else None
    return bool(ctx is not None and getattr(ctx, "progress", False))


def simulate(
    chunk_fn: Callable[[np.random.Generator, int], np.ndarray],
    n_trials: int,
    seed: int,
    *,
    chunk_size: int | None = None,
    executor: Executor | None = None,
    progress: bool = False,
    block_size: int = DEFAULT_BLOCK_SIZE,
) -> MonteCarloResult:
    """Run ``n_trials`` independent trials of ``chunk_fn`` and summarise them.

    Parameters
    ----------
    chunk_fn : callable
        ``chunk_fn(rng, n) -> array (n, ...)``: simulate ``n`` trials with generator ``rng``
        (a ``numpy.random.Generator``). Picklable when ``executor`` is given.
    n_trials : int
        Number of trials (>= 1).
    seed : int
        Non-negative integer; with ``n_trials`` and ``block_size`` it fixes every random draw.
    chunk_size : int, optional
        Trials per task sent to the executor (>= 1), rounded up to whole blocks. Default: all
        trials in one task when serial, otherwise at most eight tasks of
        ``ceil(n_blocks / 8)`` blocks each. It never changes the results.
    executor : concurrent.futures.Executor, optional
        Any ``concurrent.futures.Executor``-like object with ``submit`` (``None``: serial, in this
        process). It is used, not shut down.
    progress : bool, default False
        Show a tqdm progress bar of the trials on stderr (advanced as each task finishes).
    block_size : int, default 256
        Trials per independent random stream (>= 1; :data:`DEFAULT_BLOCK_SIZE`). Changing it
        changes the random draws (like a different seed); it is part of what makes a result
        reproducible.

    Returns
    -------
    MonteCarloResult
        ``samples`` shaped ``(n_trials, ...)`` in trial order, with ``seed`` and
        ``block_size``.

    Raises
    ------
    ValueError
        If ``chunk_fn`` is not callable; if ``n_trials``, ``seed``, ``block_size`` or
        ``chunk_size`` is not an integer (a ``bool`` is refused; NumPy integers are accepted)
        or is below its minimum; if ``executor`` has no ``submit``; if ``chunk_fn`` returns
        something whose first axis is not ``n`` long (raised when that block runs); or if the
        run would need more memory than the machine has (the message names ``n_trials`` and
        gives the estimate), checked before the blocks' seeds are made and again, from the
        size of the first block's result, before any other block runs.

    Notes
    -----
    The first block always runs in the calling process, first: its result's size gives the
    memory estimate and its time the run's. With the ``auto`` executor of
    :mod:`fusioncenter.context` (an object with ``adaptive = True`` and ``choose(seconds)``)
    the remaining blocks go to a process pool only when their estimated serial time repays
    its start-up. With an execution context asking for progress (the command line), a run
    expected to last more than a few seconds reports on stderr. None of this changes the
    numbers.
    """
    if not callable(chunk_fn):
        raise ValueError("chunk_fn must be callable as chunk_fn(rng, n)")
    n_trials = _check_int("n_trials", n_trials, 1)
    seed = _check_int("seed", seed, 0)
    block_size = _check_int("block_size", block_size, 1)
    if chunk_size is not None:
        chunk_size = _check_int("chunk_size", chunk_size, 1)
    if executor is not None and not hasattr(executor, "submit"):
        raise ValueError("executor must provide submit(fn, *args) like concurrent.futures")

    n_blocks = math.ceil(n_trials / block_size)
    # the seeds of the blocks cost memory too: refuse an absurd count before making them
    check_memory("n_trials", n_trials, n_blocks * _SEED_BYTES, "the random streams of the "
                 f"{n_blocks} blocks")
    sizes = [block_size] * (n_blocks - 1) + [n_trials - block_size * (n_blocks - 1)]
    root = np.random.SeedSequence(seed)
    # The first block runs here, first: its result's size tells the memory of all trials (and
    # its time how long the run takes, which decides the ``auto`` executor). Spawning the
    # children one call after another gives the same children as one call.
    ctx_progress = _context_progress()
    t0 = time.perf_counter()
    first = _run_blocks(chunk_fn, [(root.spawn(1)[0], sizes[0])])
    t_block = time.perf_counter() - t0
    row = first[0].nbytes / max(sizes[0], 1)
    check_memory("n_trials", n_trials, row * n_trials * 2, "the per-trial results of "
                 f"{n_trials} trials ({row:.0f} bytes each, twice while they are put together)")
    rest_serial = t_block * (n_trials - sizes[0]) / max(sizes[0], 1)
    if getattr(executor, "adaptive", False):
        executor = executor.choose(rest_serial)
    blocks = list(zip(root.spawn(n_blocks - 1), sizes[1:], strict=True))
    n_rest = len(blocks)

    if chunk_size is None:
        per_task = n_rest if executor is None else max(1, math.ceil(n_rest / 8))
    else:
        per_task = max(1, math.ceil(chunk_size / block_size))
    per_task = max(per_task, 1)
    tasks = [blocks[i : i + per_task] for i in range(0, n_rest, per_task)]

    bar = None
    if progress:
        from tqdm.auto import tqdm

        bar = tqdm(total=n_trials, initial=sizes[0], desc="Monte Carlo", unit="trial",
                   file=sys.stderr)
    elif ctx_progress and tasks:
        workers = 1 if executor is None else max(1, min(len(tasks), os.cpu_count() or 1))
        bar = _Progress(n_trials, sizes[0], rest_serial / workers, force=False)

    results: list[list | None] = [None] * len(tasks)
    try:
        if executor is None:
            for i, task in enumerate(tasks):
                if bar is not None and len(task) > 1:  # blocks one by one, to show progress
                    results[i] = []
                    for block in task:
                        results[i] += _run_blocks(chunk_fn, [block])
                        bar.update(block[1])
                    continue
                results[i] = _run_blocks(chunk_fn, task)
                if bar is not None:
                    bar.update(sum(n for _, n in task))
        else:
            futures = {
                executor.submit(_run_blocks, chunk_fn, task): i for i, task in enumerate(tasks)
            }
            for fut in as_completed(futures):
                i = futures[fut]
                results[i] = fut.result()
                if bar is not None:
                    bar.update(sum(n for _, n in tasks[i]))
    finally:
        if bar is not None:
            bar.close()

    results.insert(0, first)
    parts = [arr for task_result in results for arr in task_result]
    samples = np.concatenate(parts, axis=0)
    return MonteCarloResult(samples=samples, seed=seed, block_size=block_size)
