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
"""

from __future__ import annotations

import argparse
import contextlib
import csv
import json
import math
import os
import signal
import sys
import time
from pathlib import Path

from fusioncenter.profile import ENV_VAR as PROFILE_ENV
from fusioncenter.profile import PROFILES, current_profile

CACHE_ENV = "FUSIONCENTER_COMPUTE_CACHE"
EXECUTOR_ENV = "FUSIONCENTER_EXECUTOR"

EXIT_OK, EXIT_CLAIM, EXIT_USAGE, EXIT_RUNTIME, EXIT_INTERNAL = 0, 1, 2, 3, 4
EXIT_INTERRUPTED, EXIT_TERMINATED = 130, 143

#: How non-finite floats are written in JSON (strict JSON has no NaN or infinity).
NONFINITE_JSON = {"nan": "NaN", "inf": "Infinity", "-inf": "-Infinity"}


def _float(x: float):
    if math.isfinite(x):
        return x
    return NONFINITE_JSON["nan" if math.isnan(x) else ("inf" if x > 0 else "-inf")]


def jsonable(value):
    """``value`` as plain JSON types: arrays to lists, NumPy scalars to Python numbers,
    non-finite floats to the strings of :data:`NONFINITE_JSON`, complex numbers to
    ``[re, im]``; anything else that JSON cannot hold to its ``str``.

    Parameters
    ----------
    value : object
        Typically the dict a registry ``compute`` returns; nested dicts, lists, tuples, sets
        and arrays are converted recursively.

    Returns
    -------
    object
        A ``dict`` (keys converted with ``str``), ``list``, ``str``, ``int``, ``float``
        (finite), ``bool`` or ``None``, which ``json.dumps(..., allow_nan=False)`` accepts.
        Tuples and sets become lists (a set in its iteration order).
    """
    np = sys.modules.get("numpy")  # no NumPy object exists before NumPy is imported

    if isinstance(value, dict):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple | set | frozenset):
        return [jsonable(v) for v in value]
    if np is not None and isinstance(value, np.ndarray):
        return jsonable(value.tolist())
    if np is not None and isinstance(value, np.generic):
        return jsonable(value.item())
    if isinstance(value, bool) or value is None or isinstance(value, str):
        return value
    if isinstance(value, int):
        return value
    if isinstance(value, float):
        return _float(value)
    if isinstance(value, complex):
        return [_float(value.real), _float(value.imag)]
    return str(value)


def dumps(value) -> str:
    """Strict JSON of :func:`jsonable` applied to ``value`` (``allow_nan=False``).

    Parameters
    ----------
    value : object
        What to encode (see :func:`jsonable`).

    Returns
    -------
    str
        One line of JSON (RFC 8259): no ``NaN`` or ``Infinity`` tokens.
    """
    return json.dumps(jsonable(value), allow_nan=False)


def write_csv(data: dict, path, run: dict | None = None) -> None:
    """Long format ``name,index,value``: one row per element of every array or scalar.

    ``index`` is the element's position (``i`` or ``i;j;...`` for arrays of several axes), empty
    for scalars. Non-numeric values are written as JSON text; non-finite floats as ``nan``,
    ``inf``, ``-inf``. With ``run``, its items come first as rows ``_run,KEY,VALUE``.

    Parameters
    ----------
    data : dict
        Name to value, as a registry ``compute`` returns. Each value goes through
        ``numpy.asarray``: a number or a numeric (or string) array gives one row per element;
        a value NumPy can only hold as an ``object`` array (a dict, ``None``, a ragged list)
        gives one row whose value is :func:`dumps` of it.
    path : str or pathlib.Path or file
        The file to write (created or overwritten), or an open text file (``sys.stdout``).
    run : dict, optional
        How the data were computed (the ``"_run"`` record of the command line): a ``str`` or
        ``int`` value is written as it is, anything else as :func:`dumps` of it.

    Returns
    -------
    None
        The CSV file is written, with the header row ``name,index,value``.

    Raises
    ------
    OSError
        If ``path`` cannot be opened for writing.
    """
    import numpy as np

    with contextlib.nullcontext(path) if hasattr(path, "write") else \
            open(path, "w", newline="") as fh:
        w = csv.writer(fh, lineterminator="\n" if hasattr(path, "write") else "\r\n")
        w.writerow(["name", "index", "value"])
        for key, value in (run or {}).items():
            w.writerow(["_run", key, value if isinstance(value, str | int) else dumps(value)])
        for name, value in data.items():
            arr = np.asarray(value)
            if arr.dtype == object:
                w.writerow([name, "", dumps(value)])
            elif arr.ndim == 0:
                w.writerow([name, "", arr.item()])
            else:
                for idx in np.ndindex(arr.shape):
                    w.writerow([name, ";".join(map(str, idx)), arr[idx].item()])


EPILOG = f"""environment:
  {PROFILE_ENV}      default profile (fast or paper)
  {EXECUTOR_ENV}     default executor (auto, serial, processes[:N], dask:...)
  {CACHE_ENV}  a folder: computed entries are kept there and read back
      (npz files keyed by id, profile, seed, overrides and the library's version and
      source fingerprint, with an integrity check; a stale or altered file is computed
      again); unset: every run computes

exit codes: 0 ok, 1 a claim failed, 2 bad usage (bad id, option, --set value or bound,
  a run too large for the memory), 3 runtime or I/O error (output, cache, workers,
  scheduler, memory exhausted), 4 internal error, 130 interrupted, 143 terminated
"""


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="fusioncenter", description=__doc__.split("\n")[0],
                                epilog=EPILOG,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="cmd", required=True)

    def add(name, **kw):
        return sub.add_parser(name, epilog=EPILOG,
                              formatter_class=argparse.RawDescriptionHelpFormatter, **kw)

    sp = add("list", help="list every figure and table with its status")
    sp.add_argument("--json", action="store_true", help="machine-readable output")

    sp = add("params", help="list an entry's parameters that --set may override")
    sp.add_argument("id", help="registry id, e.g. zheng2014-table1")

    def common(sp):
        sp.add_argument("id", help="registry id, e.g. dey2009-fig1")
        sp.add_argument("--profile", choices=PROFILES, default=None,
                        help=f"default: ${PROFILE_ENV}, else fast")
        sp.add_argument("--seed", type=int, default=None, help="non-negative integer")
        sp.add_argument("--executor", default=None, metavar="SPEC",
                        help="auto, serial, processes[:N], dask:local or dask:ADDRESS "
                        f"(default: ${EXECUTOR_ENV}, else auto: serial, or a pool of the "
                        "cores for a Monte Carlo run long enough to repay its ~5 s start-up)")
        sp.add_argument("--set", dest="overrides", action="append", default=[],
                        metavar="KEY=VALUE", help="override a parameter (see `params ID`); "
                        "each key at most once")

    sp = add("compute", help="compute an entry's data")
    common(sp)
    out = sp.add_mutually_exclusive_group(required=True)
    out.add_argument("--json", action="store_true", help="write JSON to stdout")
    out.add_argument("--csv", metavar="FILE", type=Path,
                     help="write long-format CSV to FILE (`-`: standard output)")

    sp = add("plot", help="compute and plot an entry into a directory")
    common(sp)
    sp.add_argument("-o", "--outdir", type=Path, required=True)
    sp.add_argument("--format", choices=["png", "pdf", "svg"], default="png")

    sp = add("verify", help="compute an entry and check the paper's claims on it")
    common(sp)
    return p


def _overrides(pairs: list[str]) -> dict:
    out = {}
    for item in pairs:
        key, sep, value = item.partition("=")
        if not sep or not key.strip():
            raise ValueError(f"--set expects KEY=VALUE, got {item!r}")
        key = key.strip()
        if key in out:
            raise ValueError(f"--set {key} given twice ({out[key]!r} and {value!r}); give each "
                             "key once")
        out[key] = value
    return out


class _UnknownId(ValueError):
    """An id that neither the index nor the registry knows (exit 2)."""


def _known(entry_id: str) -> None:
    """Refuse an unknown id from the index, before importing any figure module."""
    from fusioncenter.figures import _index as index

    registry = sys.modules.get("fusioncenter.figures.registry")
    if registry is not None and entry_id in registry.REGISTRY:
        return
    rows = index.load()
    if rows is None:  # no current index: the registry decides (imports every module)
        return
    ids = [r["id"] for r in rows]
    if entry_id in ids:
        return
    import difflib

    near = difflib.get_close_matches(entry_id, ids, n=3)
    hint = f"; did you mean {', '.join(near)}?" if near else ""
    raise _UnknownId(f"unknown figure/table id {entry_id!r}{hint} (`fusioncenter list` shows "
                     "all)")


def _writable_file(path: Path) -> None:
    """Fail before computing if ``path`` cannot be written (an ``OSError``: exit 3)."""
    if path.is_dir():
        raise IsADirectoryError(f"output {path} is a directory")
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise FileNotFoundError(f"output folder {parent} does not exist")
    if not os.access(parent, os.W_OK) or (path.exists() and not os.access(path, os.W_OK)):
        raise PermissionError(f"output {path} is not writable")


def _writable_dir(path: Path) -> None:
    if path.exists() and not path.is_dir():
        raise NotADirectoryError(f"output folder {path} is a file")
    probe = path
    while not probe.exists():
        probe = probe.parent
    if not os.access(probe, os.W_OK):
        raise PermissionError(f"output folder {path} is not writable")


def _run_info(entry, args, over: dict) -> dict:
    return {"id": entry.id, "profile": args.profile,
            "seed": entry.seed if args.seed is None else args.seed,
            "executor": args.executor,
            "parameters": entry.resolved_parameters(args.profile, over),
            "overridden": sorted(over)}


def _compute(entry, args, over: dict):
    t0 = time.perf_counter()
    print(f"computing {entry.id} (profile {args.profile}, executor {args.executor}"
          + (f", {', '.join(f'{k}={v}' for k, v in over.items())}" if over else "") + ")...",
          file=sys.stderr)
    data = entry.run_compute(args.profile, args.seed, executor=args.executor, progress=True,
                             **over)
    print(f"computed {entry.id} in {time.perf_counter() - t0:.1f} s", file=sys.stderr)
    return data


def _list(as_json: bool) -> int:
    from fusioncenter.figures import _index as index

    rows = index.load()
    if rows is None:  # the source changed since the index was written: build it again
        from fusioncenter.figures import registry

        rows = registry.build_index()["entries"]
    rows = [{k: v for k, v in r.items() if k not in ("module", "settable_lines")}
            for r in rows]
    registry = sys.modules.get("fusioncenter.figures.registry")
    if registry is not None:  # entries registered in this process but not by the modules
        known = {r["id"] for r in rows}
        rows += [e.summary() for e in registry.REGISTRY.values() if e.id not in known]
    if as_json:
        sys.stdout.write(dumps(rows) + "\n")
        return EXIT_OK
    width = max(len(r["id"]) for r in rows)
    for r in rows:
        print(f"{r['id']:<{width}}  {r['status']:<11}  {r['caption'][:70]}")
    return EXIT_OK


def _params(entry_id: str) -> int:
    from fusioncenter.figures import _index as index

    row = index.find(entry_id)
    registry = sys.modules.get("fusioncenter.figures.registry")
    if row is not None and not (registry is not None and entry_id in registry.REGISTRY
                                and registry.REGISTRY[entry_id].settable_lines()
                                != row["settable_lines"]):
        lines = row["settable_lines"]
    else:
        from fusioncenter import figures

        lines = figures.get(entry_id).settable_lines()
    for line in lines:
        print(line)
    print("Bounds are checked before computing; --executor auto (the paper profile's default) "
          "starts a pool only for a Monte Carlo run of more than about "
          "10 s serially (a pool's start-up is about 5 s).")
    return EXIT_OK


def _main(args) -> int:
    if args.cmd == "list":
        return _list(args.json)
    _known(args.id)
    if args.cmd == "params":
        return _params(args.id)

    import matplotlib

    matplotlib.use("Agg")  # the command line only writes files; before pyplot is imported

    from fusioncenter import context, figures

    entry = figures.get(args.id)
    if args.seed is not None and args.seed < 0:
        raise ValueError(f"--seed must be a non-negative integer, got {args.seed}")
    args.profile = args.profile or current_profile()
    args.executor = context.parse_executor(args.executor) if args.executor is not None \
        else context.default_spec(args.profile)
    over = entry.check_overrides(_overrides(args.overrides))
    entry.check_bounds(args.profile, over)
    if args.executor.startswith("dask:"):  # its client logs tracebacks of a lost scheduler
        import logging

        with contextlib.suppress(ImportError):  # it configures its loggers: quieten them
            import distributed  # noqa: F401

        for name in list(logging.root.manager.loggerDict):
            if name.split(".")[0] in ("distributed", "tornado"):
                logging.getLogger(name).setLevel(logging.CRITICAL)
        for name in ("distributed", "tornado"):
            logging.getLogger(name).setLevel(logging.CRITICAL)
    to_stdout = args.cmd == "compute" and args.csv is not None and str(args.csv) == "-"
    if args.cmd == "compute":
        if args.csv is not None and not to_stdout:
            _writable_file(args.csv)
        data = _compute(entry, args, over)
        run = _run_info(entry, args, over)
        if args.json:
            sys.stdout.write(dumps({**data, "_run": run}) + "\n")
        elif to_stdout:
            write_csv(data, sys.stdout, run)
            sys.stdout.flush()
        else:
            write_csv(data, args.csv, run)
            print(f"wrote {args.csv}", file=sys.stderr)
        return EXIT_OK
    if args.cmd == "plot":
        if entry.plot is None:
            raise figures.EntryNotReady(f"{entry.id}: no plot yet (status {entry.status!r})")
        _writable_dir(args.outdir)
        data = _compute(entry, args, over)
        fig = entry.run_plot(data)
        args.outdir.mkdir(parents=True, exist_ok=True)
        path = args.outdir / f"{entry.id}.{args.format}"
        fig.savefig(path)
        print(path)
        return EXIT_OK
    # verify
    if entry.checks is None:
        raise figures.EntryNotReady(f"{entry.id}: no checks yet (status {entry.status!r})")
    claims = entry.run_checks(_compute(entry, args, over))
    checked, skipped = entry.split_claims(claims, over)
    for c in checked:
        print(f"{'PASS' if c.passed else 'FAIL'}  {c.name}  [{c.detail}]")
    for c in skipped:
        print(f"SKIP  {c.name}  [paper-specific: {', '.join(entry.model_overridden(over))} "
              f"overridden]")
    failed = sum(not c.passed for c in checked)
    tail = f", {len(skipped)} skipped (paper-specific)" if skipped else ""
    print(f"{entry.id}: {len(checked) - failed} passed, {failed} failed{tail}")
    return EXIT_CLAIM if failed else EXIT_OK


class Terminated(BaseException):
    """SIGTERM arrived (raised in the main thread by the command line's handler)."""


def _on_sigterm(signum, frame):
    raise Terminated


def _runtime_error(exc: BaseException) -> bool:
    """Errors of the run's environment (exit 3): I/O, workers, a Dask scheduler lost."""
    import concurrent.futures

    if isinstance(exc, OSError | RuntimeError | MemoryError | TimeoutError |
                  concurrent.futures.CancelledError | concurrent.futures.TimeoutError):
        return True
    mod = type(exc).__module__ or ""
    return mod.split(".")[0] in ("distributed", "tornado", "dask")


def _usage_errors() -> tuple:
    registry = sys.modules.get("fusioncenter.figures.registry")
    extra = (registry.UnknownEntry, registry.EntryNotReady) if registry is not None else ()
    return (_UnknownId, ValueError, *extra)


def _stop_workers() -> None:
    ctx = sys.modules.get("fusioncenter.context")
    if ctx is not None:
        ctx.shutdown(kill=True)


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
    args = _parser().parse_args(argv)
    old = None
    if __import__("threading").current_thread() is __import__("threading").main_thread():
        old = signal.signal(signal.SIGTERM, _on_sigterm)
    try:
        return _main(args)
    except KeyboardInterrupt:
        _stop_workers()
        print("error: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except Terminated:
        _stop_workers()
        print("error: terminated (SIGTERM)", file=sys.stderr)
        return EXIT_TERMINATED
    except Exception as exc:  # noqa: BLE001 (sorted into the exit codes below)
        if isinstance(exc, _usage_errors()):
            print(f"error: {exc}", file=sys.stderr)
            return EXIT_USAGE
        if _runtime_error(exc):
            _stop_workers()
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
