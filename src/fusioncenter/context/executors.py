"""The executors: the pool of processes or the Dask cluster that runs the active context's Monte
Carlo tasks (``executor``, ``workers``), started on first use, one per spec, and kept
for the life of the process until :func:`shutdown` (also registered with ``atexit``).

``auto`` is a pool of the cores that :func:`fusioncenter.montecarlo.simulate` starts only for a
run whose remaining blocks would take longer than :data:`AUTO_POOL_SECONDS` serially. A worker
process ignores Ctrl-C (the parent stops the pool) and runs one BLAS / OpenMP thread
(:data:`THREAD_VARS`).
"""

from __future__ import annotations

import atexit
import contextlib
import os
import threading
from collections.abc import Iterator
from concurrent.futures import Executor
from typing import Any

from fusioncenter.context.active import current
from fusioncenter.context.specs import cores

__all__ = ["AUTO_POOL_SECONDS", "THREAD_VARS", "executor", "workers", "shutdown"]

#: ``auto`` starts a process pool only for a Monte Carlo run whose remaining blocks would take
#: longer than this serially (seconds; at twice the ~5 s start-up of a pool, a pool of two
#: workers is then at worst as fast as serial).
AUTO_POOL_SECONDS = 10.0
#: Variables that cap the BLAS / OpenMP threads of a worker process.
THREAD_VARS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS",
               "VECLIB_MAXIMUM_THREADS", "NUMEXPR_NUM_THREADS")



def executor() -> Executor | None:
    """The active context's executor (started on first use), ``None`` when serial.

    A compute passes it to :func:`fusioncenter.montecarlo.simulate` (or a ``run`` built on
    it). Outside any context (a direct call of a compute function) it is ``None``.

    Returns
    -------
    concurrent.futures.Executor or None
        ``None`` outside a context or when its spec is ``serial``. For ``processes:N``, a
        ``concurrent.futures.ProcessPoolExecutor`` of ``N`` workers (``spawn`` start method,
        one BLAS / OpenMP thread each, Ctrl-C ignored in the workers); for ``dask:...``, the
        ``get_executor()`` of a ``dask.distributed.Client`` (of a new ``LocalCluster`` with
        one single-threaded worker process per core for ``dask:local``). One pool per spec is
        started on first use and reused until :func:`shutdown`.

    Raises
    ------
    RuntimeError
        If the scheduler of ``dask:ADDRESS`` cannot be reached (within 30 s).
    """
    ctx = current()
    if ctx is None or ctx.executor == "serial":
        return None
    if ctx.executor == "auto":
        return _AutoPool()
    return _pool(ctx.executor)


class _AutoPool:
    """The executor of ``auto``: a pool of the cores, started only when
    :func:`fusioncenter.montecarlo.simulate` (seeing ``adaptive``) finds a run that repays it."""

    adaptive = True
    spec = staticmethod(lambda: f"processes:{cores()}")

    def choose(self, serial_seconds: float):
        """The pool if the rest of the run (``serial_seconds`` serially) repays starting it
        (over :data:`AUTO_POOL_SECONDS`) or it runs already, else ``None`` (serial)."""
        if cores() > 1 and (self.spec() in _POOLS or serial_seconds > AUTO_POOL_SECONDS):
            return _pool(self.spec())
        return None

    def submit(self, fn, *args, **kwargs):  # used as a plain executor: the pool
        return _pool(self.spec()).submit(fn, *args, **kwargs)


def workers() -> int:
    """How many tasks the active executor runs at once (1 when serial).

    Returns
    -------
    int
        1 outside a context or when serial; ``N`` for ``processes:N``; for ``dask:...`` the
        total threads of the scheduler's workers (at least 1), or
        :func:`~fusioncenter.context.specs.cores` if the scheduler cannot be asked. It is only
        a hint for cutting work into chunks.

    Raises
    ------
    RuntimeError
        If the scheduler of ``dask:ADDRESS`` cannot be reached (the pool is started here if
        it was not yet).
    """
    ctx = current()
    if ctx is None or ctx.executor == "serial":
        return 1
    if ctx.executor == "auto":
        return cores()
    if ctx.executor.startswith("processes:"):
        return int(ctx.executor.split(":", 1)[1])
    ex = _pool(ctx.executor)
    try:
        return max(1, sum(w["nthreads"] for w in ex._client.scheduler_info()["workers"].values()))
    except Exception:  # noqa: BLE001 (only a hint for chunking)
        return cores()


# ------------------------------------------------------------------------------ pools
_POOLS: dict[str, Any] = {}
_CLOSERS: list = []
_LOCK = threading.Lock()


def _worker_init() -> None:
    """Initializer of a pool worker: Ctrl-C is left to the parent (which stops the pool; a
    kernel's shutdown interrupts its whole process group), and one BLAS thread."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    _one_blas_thread()


def _one_blas_thread() -> None:
    """One BLAS / OpenMP thread in this process.

    The variables of :data:`THREAD_VARS` are set for anything the worker starts; the BLAS
    already loaded (a spawned worker imports NumPy while unpickling its first task, possibly
    before this runs) is limited through OpenBLAS's own ``*openblas_set_num_threads*`` (what
    threadpoolctl does); silently nothing where that is not found (not Linux, another BLAS).
    """
    import ctypes

    os.environ.update({k: "1" for k in THREAD_VARS})
    import numpy  # noqa: F401 (loads the BLAS, so that its threads can be set below)

    try:
        with open("/proc/self/maps") as fh:
            paths = {ln.split()[-1] for ln in fh
                     if "openblas" in ln.lower() and ln.split()[-1].startswith("/")}
    except OSError:  # pragma: no cover (not Linux)
        return
    names = ("scipy_openblas_set_num_threads64_", "scipy_openblas_set_num_threads",
             "openblas_set_num_threads64_", "openblas_set_num_threads")
    for path in sorted(paths):
        try:
            lib = ctypes.CDLL(path)
        except OSError:
            continue
        for name in names:
            fn = getattr(lib, name, None)
            if fn is not None:
                fn(1)
                break


@contextlib.contextmanager
def _thread_env() -> Iterator[None]:
    old = {k: os.environ.get(k) for k in THREAD_VARS}
    os.environ.update({k: "1" for k in THREAD_VARS})
    try:
        yield
    finally:
        for k, v in old.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def _start(spec: str):
    if spec.startswith("processes:"):
        import multiprocessing
        from concurrent.futures import ProcessPoolExecutor

        pool = ProcessPoolExecutor(int(spec.split(":", 1)[1]),
                                   mp_context=multiprocessing.get_context("spawn"),
                                   initializer=_worker_init)

        def close(kill: bool = False) -> None:
            if kill:  # interrupted: the workers' running tasks are not waited for
                for proc in list((pool._processes or {}).values()):
                    with contextlib.suppress(Exception):
                        proc.kill()
            pool.shutdown(wait=True, cancel_futures=True)

        close.kills = True
        _CLOSERS.append(close)
        return pool
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError as exc:
        raise RuntimeError(f"executor {spec}: dask.distributed is not installed ({exc})") \
            from None

    address = spec[len("dask:"):]
    if address == "local":
        with _thread_env():  # the nanny also sets them (distributed.nanny.pre-spawn-environ)
            cluster = LocalCluster(n_workers=cores(), threads_per_worker=1, processes=True,
                                   dashboard_address=None, silence_logs=40)
        client = Client(cluster)
        _CLOSERS.append(cluster.close)
    else:
        try:
            client = Client(address, timeout=30)
        except OSError as exc:
            raise RuntimeError(f"executor dask:{address}: cannot reach the scheduler ({exc})") \
                from None
    _CLOSERS.append(client.close)
    ex = client.get_executor()
    ex._client = client  # for workers()
    return ex


def _pool(spec: str):
    with _LOCK:
        pool = _POOLS.get(spec)
        if pool is None:
            pool = _POOLS[spec] = _start(spec)
        return pool


def shutdown(kill: bool = False) -> None:
    """Stop every pool and cluster this process started (the next use starts them again).

    Parameters
    ----------
    kill : bool, default False
        Kill the process pools' workers at once instead of letting their running tasks
        finish (what an interrupt or SIGTERM of the command line does).

    Returns
    -------
    None
        Dask clients are closed before their clusters and process pools are shut down after
        their running tasks finish (queued tasks are cancelled; with ``kill``, the workers
        are killed first); an error while closing one of them is ignored. It is also
        registered with ``atexit``.
    """
    with _LOCK:
        _POOLS.clear()
        closers = _CLOSERS[:]
        _CLOSERS.clear()
    for close in reversed(closers):  # client before cluster
        with contextlib.suppress(Exception):
            if kill and getattr(close, "kills", False):
                close(kill=True)
            else:
                close()


atexit.register(shutdown)
