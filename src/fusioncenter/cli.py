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
else a process pool in the paper profile) and ``--set KEY=VALUE`` (repeatable) for the entry's
documented parameters (``params ID`` lists them). Flags win over the environment.

Data go to stdout (or the named file), progress and messages to stderr. ``--json`` is strict
JSON (RFC 8259): NumPy arrays become lists, NumPy scalars numbers, and the non-finite floats the
strings ``"NaN"``, ``"Infinity"`` and ``"-Infinity"`` (the only encoding of them). The output
records how it was computed under the key ``"_run"`` (id, profile, seed, executor, parameters).

Exit codes:

* 0 success;
* 1 a claim failed (``verify``);
* 2 bad usage: unknown id or option, an entry not started yet, a bad ``--set`` key or value or
  any other invalid value (a ``ValueError`` of the library);
* 3 a runtime or I/O error: an unwritable output path, an unreadable compute-cache file, an
  unreachable Dask scheduler, a crashed worker;
* 130 interrupted (Ctrl-C).

Errors of the user (codes 2 and 3) print one line ``error: ...`` and no traceback.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import os
import sys
import time
from pathlib import Path

import matplotlib
import numpy as np

matplotlib.use("Agg")  # the command line only writes files; before pyplot is imported anywhere

from fusioncenter import context, figures  # noqa: E402
from fusioncenter.profile import ENV_VAR as PROFILE_ENV  # noqa: E402
from fusioncenter.profile import PROFILES, current_profile  # noqa: E402

EXIT_OK, EXIT_CLAIM, EXIT_USAGE, EXIT_RUNTIME, EXIT_INTERRUPTED = 0, 1, 2, 3, 130

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
    if isinstance(value, dict):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple | set | frozenset):
        return [jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return jsonable(value.tolist())
    if isinstance(value, np.generic):
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


def write_csv(data: dict, path: Path, run: dict | None = None) -> None:
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
    path : str or pathlib.Path
        The file to write (created or overwritten).
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
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
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


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python -m fusioncenter", description=__doc__.split("\n")[0],
                                epilog="exit codes: 0 ok, 1 a claim failed, 2 bad usage, "
                                "3 runtime or I/O error, 130 interrupted")
    sub = p.add_subparsers(dest="cmd", required=True)

    sp = sub.add_parser("list", help="list every figure and table with its status")
    sp.add_argument("--json", action="store_true", help="machine-readable output")

    sp = sub.add_parser("params", help="list an entry's parameters that --set may override")
    sp.add_argument("id", help="registry id, e.g. zheng2014-table1")

    def common(sp):
        sp.add_argument("id", help="registry id, e.g. dey2009-fig1")
        sp.add_argument("--profile", choices=PROFILES, default=None,
                        help=f"default: ${PROFILE_ENV}, else fast")
        sp.add_argument("--seed", type=int, default=None, help="non-negative integer")
        sp.add_argument("--executor", default=None, metavar="SPEC",
                        help="serial, processes[:N], dask:local or dask:ADDRESS (default: "
                        f"${context.EXECUTOR_ENV}, else processes:<cores> in the paper profile)")
        sp.add_argument("--set", dest="overrides", action="append", default=[],
                        metavar="KEY=VALUE", help="override a parameter (see `params ID`)")

    sp = sub.add_parser("compute", help="compute an entry's data")
    common(sp)
    out = sp.add_mutually_exclusive_group(required=True)
    out.add_argument("--json", action="store_true", help="write JSON to stdout")
    out.add_argument("--csv", metavar="FILE", type=Path, help="write long-format CSV to FILE")

    sp = sub.add_parser("plot", help="compute and plot an entry into a directory")
    common(sp)
    sp.add_argument("-o", "--outdir", type=Path, required=True)
    sp.add_argument("--format", choices=["png", "pdf", "svg"], default="png")

    sp = sub.add_parser("verify", help="compute an entry and check the paper's claims on it")
    common(sp)
    return p


def _overrides(pairs: list[str]) -> dict:
    out = {}
    for item in pairs:
        key, sep, value = item.partition("=")
        if not sep or not key.strip():
            raise ValueError(f"--set expects KEY=VALUE, got {item!r}")
        out[key.strip()] = value
    return out


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
    data = entry.run_compute(args.profile, args.seed, executor=args.executor, **over)
    print(f"computed {entry.id} in {time.perf_counter() - t0:.1f} s", file=sys.stderr)
    return data


def _main(args) -> int:
    if args.cmd == "list":
        rows = [e.summary() for e in figures.entries()]
        if args.json:
            sys.stdout.write(dumps(rows) + "\n")
        else:
            width = max(len(r["id"]) for r in rows)
            for r in rows:
                print(f"{r['id']:<{width}}  {r['status']:<11}  {r['caption'][:70]}")
        return EXIT_OK
    entry = figures.get(args.id)
    if args.cmd == "params":
        if not entry.settable:
            print(f"{entry.id}: no parameters to override")
        for p in entry.settable:
            print(p.describe() + ("  [changes the paper's setting]" if p.model else ""))
        return EXIT_OK

    if args.seed is not None and args.seed < 0:
        raise ValueError(f"--seed must be a non-negative integer, got {args.seed}")
    args.profile = args.profile or current_profile()
    args.executor = context.parse_executor(args.executor) if args.executor is not None \
        else context.default_spec(args.profile)
    over = entry.check_overrides(_overrides(args.overrides))
    if args.cmd == "compute":
        if args.csv is not None:
            _writable_file(args.csv)
        data = _compute(entry, args, over)
        run = _run_info(entry, args, over)
        if args.json:
            sys.stdout.write(dumps({**data, "_run": run}) + "\n")
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


def main(argv: list[str] | None = None) -> int:
    """Run the command line (``python -m fusioncenter``; see the module's description).

    Parameters
    ----------
    argv : list of str, optional
        The arguments after the program name; default ``sys.argv[1:]``.

    Returns
    -------
    int
        The exit code: 0 success, 1 a claim failed (``verify``), 2 bad usage (an unknown id,
        an entry not ready, a ``ValueError`` such as a bad ``--set``, ``--seed`` or
        ``--executor``), 3 a runtime or I/O error (an ``OSError`` or ``RuntimeError``), 130
        interrupted. For codes 2, 3 and 130 one line ``error: ...`` goes to stderr instead of
        a traceback.

    Raises
    ------
    SystemExit
        From ``argparse``, when the arguments do not parse (code 2, with its usage message)
        or for ``--help`` (code 0).
    """
    args = _parser().parse_args(argv)
    try:
        return _main(args)
    except (figures.UnknownEntry, figures.EntryNotReady, ValueError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except (OSError, RuntimeError) as exc:  # I/O, the compute cache, workers, a scheduler
        msg = str(exc) or type(exc).__name__
        if isinstance(exc, OSError) and exc.filename and str(exc.filename) not in msg:
            msg = f"{msg}: {exc.filename}"
        print(f"error: {type(exc).__name__}: {msg}", file=sys.stderr)
        return EXIT_RUNTIME
    except KeyboardInterrupt:
        print("error: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
