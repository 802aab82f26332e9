"""The execution context of a registry compute: where its Monte Carlo tasks run.

A registry entry's ``compute`` is a function of the profile, the seed and its documented
parameters only; *where* its trials run is the executor of the active context:

``serial``
    in the calling process;
``auto``
    serial, unless a Monte Carlo run is long enough to repay starting a process pool of the
    cores (about 5 s): :func:`fusioncenter.montecarlo.simulate` times the run's first block in
    the calling process and sends the remaining blocks to the pool only when their serial time
    would exceed :data:`AUTO_POOL_SECONDS` (a pool already started is used at once). The
    default, so that it is never slower than serial by more than a second or so;
``processes`` or ``processes:N``
    a pool of ``N`` worker processes (default: the number of usable cores), started with the
    ``spawn`` method (safe in notebooks, scripts and threads) and limited to one BLAS / OpenMP
    thread each;
``dask:local``
    a ``dask.distributed.LocalCluster`` of one single-threaded worker process per core;
``dask:ADDRESS``
    the ``dask.distributed`` scheduler at ``ADDRESS`` (e.g. ``tcp://10.0.0.5:8786``); its
    workers need the same environment (``requirements/lock.txt`` and this package).

Because :func:`fusioncenter.montecarlo.simulate` fixes every random draw by the seed and its
blocks, the data are bitwise identical under every executor: the executor is a matter of speed.

:func:`Entry.run_compute <fusioncenter.figures.registry.Entry.run_compute>` activates the
context; a compute that pays for parallel work asks for
:func:`~fusioncenter.context.executors.executor` (``None`` means serial) and passes it to
the Monte Carlo runner. The default spec is the environment variable
:data:`EXECUTOR_ENV` (how the book build sets it) or, unset, :func:`default_spec`: ``auto`` in
the ``paper`` profile on a machine with several cores, serial otherwise (the fast profile's
runs are too short to repay starting workers).

Pools are started on first use and kept for the life of the process (one per spec), so that a
chapter computing several entries starts its workers once; :func:`shutdown` stops them (also
registered with ``atexit``).

The package: :mod:`~fusioncenter.context.specs` (the executor specs and the default one),
:mod:`~fusioncenter.context.active` (the context and its activation),
:mod:`~fusioncenter.context.executors` (the pools and clusters behind the specs) and
:mod:`~fusioncenter.context.parameters` (an entry's documented parameters and the checks of a
run's overrides); the names are re-exported here.
"""

from __future__ import annotations

from fusioncenter.context.active import ExecutionContext, activate, current
from fusioncenter.context.executors import (
    AUTO_POOL_SECONDS,
    THREAD_VARS,
    executor,
    shutdown,
    workers,
)
from fusioncenter.context.parameters import Parameter, check_overrides
from fusioncenter.context.specs import EXECUTOR_ENV, cores, default_spec, parse_executor

__all__ = ["EXECUTOR_ENV", "AUTO_POOL_SECONDS", "THREAD_VARS", "ExecutionContext",
           "parse_executor", "default_spec", "cores", "activate", "current", "executor",
           "workers", "shutdown", "Parameter", "check_overrides"]
