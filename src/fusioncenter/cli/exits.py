"""The command line's exit codes, and which errors end a run with which of them.

``0`` success, ``1`` a claim failed, ``2`` bad usage (:func:`usage_errors`), ``3`` a runtime or
I/O error (:func:`is_runtime_error`), ``4`` an internal error, ``130`` interrupted and ``143``
terminated (:class:`Terminated`, raised by :func:`on_sigterm`); :func:`stop_workers` kills the
worker processes of an interrupted or failed run.
"""

from __future__ import annotations

import sys

__all__ = ["EXIT_OK", "EXIT_CLAIM", "EXIT_USAGE", "EXIT_RUNTIME", "EXIT_INTERNAL",
           "EXIT_INTERRUPTED", "EXIT_TERMINATED", "UnknownId", "Terminated", "on_sigterm",
           "is_runtime_error", "usage_errors", "stop_workers"]

EXIT_OK, EXIT_CLAIM, EXIT_USAGE, EXIT_RUNTIME, EXIT_INTERNAL = 0, 1, 2, 3, 4
EXIT_INTERRUPTED, EXIT_TERMINATED = 130, 143


class UnknownId(ValueError):
    """An id that neither the index nor the registry knows (exit 2)."""


class Terminated(BaseException):
    """SIGTERM arrived (raised in the main thread by the command line's handler)."""


def on_sigterm(signum, frame):
    """The command line's SIGTERM handler: stop the run where it is.

    Parameters
    ----------
    signum : int
        The signal's number (SIGTERM).
    frame : frame or None
        The frame it interrupted.

    Raises
    ------
    Terminated
        Always: :func:`fusioncenter.cli.main` stops the workers and exits with
        ``EXIT_TERMINATED`` (143).
    """
    raise Terminated


def is_runtime_error(exc: BaseException) -> bool:
    """Whether ``exc`` is an error of the run's environment (exit 3): I/O, workers, a Dask
    scheduler lost.

    Parameters
    ----------
    exc : BaseException
        The error that ended the run.

    Returns
    -------
    bool
        ``True`` for an ``OSError``, ``RuntimeError``, ``MemoryError``, ``TimeoutError``, a
        cancelled or timed-out future, or an error of ``distributed``, ``tornado`` or ``dask``.
    """
    import concurrent.futures

    if isinstance(exc, OSError | RuntimeError | MemoryError | TimeoutError |
                  concurrent.futures.CancelledError | concurrent.futures.TimeoutError):
        return True
    mod = type(exc).__module__ or ""
    return mod.split(".")[0] in ("distributed", "tornado", "dask")


def usage_errors() -> tuple:
    """The errors of bad usage (exit 2).

    Returns
    -------
    tuple of type
        :class:`UnknownId` and ``ValueError``, and the registry's ``UnknownEntry`` and
        ``EntryNotReady`` once the registry is imported.
    """
    registry = sys.modules.get("fusioncenter.figures.registry")
    extra = (registry.UnknownEntry, registry.EntryNotReady) if registry is not None else ()
    return (UnknownId, ValueError, *extra)


def stop_workers() -> None:
    """Kill the worker processes of the run's executors, if any were started.

    Returns
    -------
    None
        :func:`fusioncenter.context.shutdown` with ``kill=True``, when the execution context
        was imported (nothing else can have started workers).
    """
    ctx = sys.modules.get("fusioncenter.context")
    if ctx is not None:
        ctx.shutdown(kill=True)
