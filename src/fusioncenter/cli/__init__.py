"""Command line: regenerate any figure or table without the book.

Usage::

    python -m fusioncenter list [--json]
    python -m fusioncenter params ID
    python -m fusioncenter compute ID [common options] (--json | --csv FILE)
    python -m fusioncenter plot ID -o DIR [common options] [--format png|pdf|svg]
    python -m fusioncenter verify ID [common options]

Common options: ``--profile fast|paper`` (default: the environment variable
FUSIONCENTER_PROFILE, else fast), ``--seed N``,
``--executor serial|processes[:N]|dask:local|dask:ADDRESS`` (default: FUSIONCENTER_EXECUTOR,
else ``auto``: serial, switching to a pool of the cores only for a Monte Carlo run long enough
to repay its start-up) and ``--set KEY=VALUE`` (repeatable, each key once) for the entry's
documented parameters (``params ID`` lists them with every bound). Flags win over the
environment. Values read Python's number syntax (``4_00`` is 400; ``1e3`` is 1000, also for an
integer parameter when the value is whole). Every bound, also one between two parameters
(``0 < l <= N``), is checked before computing starts, and so is the memory a run needs.

The environment variable FUSIONCENTER_COMPUTE_CACHE, if it names a folder, keeps every computed
entry there (one ``.npz`` file per id, profile, seed and overrides, keyed by the library's
version and source fingerprint, with an integrity check; a stale, edited or planted file is
never served) and later runs read it back; unset, every run computes.

Data go to stdout (or the named file; ``--csv -`` is stdout), progress and messages to stderr.
``--json`` is strict JSON (RFC 8259): NumPy arrays become lists, NumPy scalars numbers, and the
non-finite floats the strings ``"NaN"``, ``"Infinity"`` and ``"-Infinity"`` (the only encoding
of them). The output records how it was computed under the key ``"_run"`` (id, profile, seed,
executor, parameters).

Exit codes:

* 0 success;
* 1 a claim failed (``verify``);
* 2 bad usage: unknown id or option, an entry not started yet, a bad or repeated ``--set`` key
  or value, a bound broken, a run too large for the machine's memory (the estimate is in the
  message), or any other invalid value (a ``ValueError`` of the library);
* 3 a runtime or I/O error: an unwritable output path, an unreadable compute-cache file, an
  unreachable or lost Dask scheduler, a crashed worker, memory exhausted while computing;
* 4 an internal error (a bug: the traceback is printed; please report it);
* 130 interrupted (Ctrl-C), 143 terminated (SIGTERM): the run and its worker processes stop.

Errors of codes 2, 3, 130 and 143 print one line ``error: ...`` and no traceback.

The package: :mod:`~fusioncenter.cli.parsing` (the arguments), :mod:`~fusioncenter.cli.commands`
(what each subcommand does), :mod:`~fusioncenter.cli.output` (the JSON and CSV formats) and
:mod:`~fusioncenter.cli.exits` (the exit codes and the errors behind them); :func:`main` runs
them.
"""

from __future__ import annotations

import signal
import sys

from fusioncenter.cli.commands import run_command
from fusioncenter.cli.exits import (
    EXIT_CLAIM,
    EXIT_INTERNAL,
    EXIT_INTERRUPTED,
    EXIT_OK,
    EXIT_RUNTIME,
    EXIT_TERMINATED,
    EXIT_USAGE,
    Terminated,
    is_runtime_error,
    on_sigterm,
    stop_workers,
    usage_errors,
)
from fusioncenter.cli.output import NONFINITE_JSON, dumps, jsonable, write_csv
from fusioncenter.cli.parsing import CACHE_ENV, EPILOG, EXECUTOR_ENV, build_parser

__all__ = ["main", "jsonable", "dumps", "write_csv", "NONFINITE_JSON", "CACHE_ENV",
           "EXECUTOR_ENV", "EPILOG", "EXIT_OK", "EXIT_CLAIM", "EXIT_USAGE", "EXIT_RUNTIME",
           "EXIT_INTERNAL", "EXIT_INTERRUPTED", "EXIT_TERMINATED", "Terminated"]


def main(argv: list[str] | None = None) -> int:
    """Run the command line (``fusioncenter`` or ``python -m fusioncenter``; see the module's
    description).

    Parameters
    ----------
    argv : list of str, optional
        The arguments after the program name; default ``sys.argv[1:]``.

    Returns
    -------
    int
        The exit code: 0 success, 1 a claim failed (``verify``), 2 bad usage (an unknown id,
        an entry not ready, a ``ValueError`` such as a bad ``--set``, ``--seed`` or
        ``--executor``, a bound broken, a run too large for the memory), 3 a runtime or I/O
        error (an ``OSError``, ``RuntimeError``, ``MemoryError``, a lost Dask scheduler or
        worker), 4 an internal error (traceback printed), 130 interrupted, 143 terminated
        (SIGTERM). For codes 2, 3, 130 and 143 one line ``error: ...`` goes to stderr
        instead of a traceback; on 130 and 143 the worker processes are killed.

    Raises
    ------
    SystemExit
        From ``argparse``, when the arguments do not parse (code 2, with its usage message)
        or for ``--help`` (code 0).
    """
    args = build_parser().parse_args(argv)
    old = None
    if __import__("threading").current_thread() is __import__("threading").main_thread():
        old = signal.signal(signal.SIGTERM, on_sigterm)
    try:
        return run_command(args)
    except KeyboardInterrupt:
        stop_workers()
        print("error: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except Terminated:
        stop_workers()
        print("error: terminated (SIGTERM)", file=sys.stderr)
        return EXIT_TERMINATED
    except Exception as exc:  # noqa: BLE001 (sorted into the exit codes below)
        if isinstance(exc, usage_errors()):
            print(f"error: {exc}", file=sys.stderr)
            return EXIT_USAGE
        if is_runtime_error(exc):
            stop_workers()
            msg = str(exc) or type(exc).__name__
            if isinstance(exc, MemoryError):
                msg = f"out of memory while computing ({msg}); use smaller sizes (--set)"
            if isinstance(exc, OSError) and exc.filename and str(exc.filename) not in msg:
                msg = f"{msg}: {exc.filename}"
            print(f"error: {type(exc).__name__}: {' '.join(msg.split())}", file=sys.stderr)
            return EXIT_RUNTIME
        import traceback

        traceback.print_exc()
        print(f"error: internal error ({type(exc).__name__}); please report it with the "
              "traceback above", file=sys.stderr)
        return EXIT_INTERNAL
    finally:
        if old is not None:
            signal.signal(signal.SIGTERM, old)
