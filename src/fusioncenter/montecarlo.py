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
import sys
from collections.abc import Callable
from concurrent.futures import Executor, as_completed
from dataclasses import dataclass, field

import numpy as np

__all__ = ["PerTrial", "MonteCarloResult", "simulate", "DEFAULT_BLOCK_SIZE"]

#: Trials per independent random stream of :func:`simulate` (part of what fixes the draws).
DEFAULT_BLOCK_SIZE = 256


class PerTrial:
    """What results keeping per-trial ``samples`` (first axis: the trials) of :func:`simulate`
    share; the ``seed`` and ``block_size`` that drew them identify the trials."""

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
        or is below its minimum; if ``executor`` has no ``submit``; or if ``chunk_fn`` returns
        something whose first axis is not ``n`` long (raised when that block runs).
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
    sizes = [block_size] * (n_blocks - 1) + [n_trials - block_size * (n_blocks - 1)]
    children = np.random.SeedSequence(seed).spawn(n_blocks)
    blocks = list(zip(children, sizes, strict=True))

    if chunk_size is None:
        per_task = n_blocks if executor is None else max(1, math.ceil(n_blocks / 8))
    else:
        per_task = max(1, math.ceil(chunk_size / block_size))
    tasks = [blocks[i : i + per_task] for i in range(0, n_blocks, per_task)]

    bar = None
    if progress:
        from tqdm.auto import tqdm

        bar = tqdm(total=n_trials, desc="Monte Carlo", unit="trial", file=sys.stderr)

    results: list[list | None] = [None] * len(tasks)
    try:
        if executor is None:
            for i, task in enumerate(tasks):
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

    parts = [arr for task_result in results for arr in task_result]
    samples = np.concatenate(parts, axis=0)
    return MonteCarloResult(samples=samples, seed=seed, block_size=block_size)
