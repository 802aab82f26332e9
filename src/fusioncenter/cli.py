"""Command line: regenerate any figure or table without the book.

    python -m fusioncenter list [--json]
    python -m fusioncenter compute ID [--profile fast|paper] [--seed N] (--json | --csv FILE)
    python -m fusioncenter plot ID -o DIR [--profile fast|paper] [--seed N] [--format png|pdf|svg]
    python -m fusioncenter verify ID [--profile fast|paper] [--seed N]

Data go to stdout (or the named file), progress and messages to stderr. Exit codes: 0 success,
1 a claim failed, 2 bad usage (unknown id, bad option, entry not started yet).
"""

from __future__ import annotations

import argparse
import csv
import json
import sys
import time
from pathlib import Path

import matplotlib
import numpy as np

matplotlib.use("Agg")  # the command line only writes files; before pyplot is imported anywhere

from fusioncenter import figures  # noqa: E402
from fusioncenter.profile import PROFILES


def _jsonable(value):
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return _jsonable(value.tolist())
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, float) and not np.isfinite(value):
        return None if np.isnan(value) else ("inf" if value > 0 else "-inf")
    return value


def write_csv(data: dict, path: Path) -> None:
    """Long format ``name,index,value``: one row per element of every array or scalar.

    ``index`` is the element's position (``i`` or ``i;j;...`` for arrays of several axes), empty
    for scalars. Non-numeric values are written as text.
    """
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["name", "index", "value"])
        for name, value in data.items():
            arr = np.asarray(value)
            if arr.dtype == object:
                w.writerow([name, "", json.dumps(_jsonable(value))])
            elif arr.ndim == 0:
                w.writerow([name, "", arr.item()])
            else:
                for idx in np.ndindex(arr.shape):
                    w.writerow([name, ";".join(map(str, idx)), arr[idx].item()])


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python -m fusioncenter", description=__doc__.split("\n")[0])
    sub = p.add_subparsers(dest="cmd", required=True)

    sp = sub.add_parser("list", help="list every figure and table with its status")
    sp.add_argument("--json", action="store_true", help="machine-readable output")

    def common(sp):
        sp.add_argument("id", help="registry id, e.g. dey2009-fig1")
        sp.add_argument("--profile", choices=PROFILES, default="fast")
        sp.add_argument("--seed", type=int, default=None, help="non-negative integer")

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


def _compute(entry, args):
    t0 = time.perf_counter()
    print(f"computing {entry.id} (profile {args.profile})...", file=sys.stderr)
    data = entry.run_compute(args.profile, args.seed)
    print(f"computed {entry.id} in {time.perf_counter() - t0:.1f} s", file=sys.stderr)
    return data


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    try:
        if args.cmd == "list":
            rows = [e.summary() for e in figures.entries()]
            if args.json:
                json.dump(rows, sys.stdout, indent=2)
                print()
            else:
                width = max(len(r["id"]) for r in rows)
                for r in rows:
                    print(f"{r['id']:<{width}}  {r['status']:<11}  {r['caption'][:70]}")
            return 0

        if args.seed is not None and args.seed < 0:
            raise ValueError(f"--seed must be a non-negative integer, got {args.seed}")
        entry = figures.get(args.id)
        if args.cmd == "compute":
            data = _compute(entry, args)
            if args.json:
                json.dump(_jsonable(data), sys.stdout)
                print()
            else:
                write_csv(data, args.csv)
                print(f"wrote {args.csv}", file=sys.stderr)
            return 0
        if args.cmd == "plot":
            if entry.plot is None:
                raise figures.EntryNotReady(f"{entry.id}: no plot yet (status {entry.status!r})")
            data = _compute(entry, args)
            fig = entry.run_plot(data)
            args.outdir.mkdir(parents=True, exist_ok=True)
            path = args.outdir / f"{entry.id}.{args.format}"
            fig.savefig(path)
            print(path)
            return 0
        if args.cmd == "verify":
            if entry.checks is None:
                raise figures.EntryNotReady(f"{entry.id}: no checks yet (status {entry.status!r})")
            claims = entry.run_checks(_compute(entry, args))
            for c in claims:
                print(f"{'PASS' if c.passed else 'FAIL'}  {c.name}  [{c.detail}]")
            failed = sum(not c.passed for c in claims)
            print(f"{entry.id}: {len(claims) - failed} passed, {failed} failed")
            return 1 if failed else 0
    except (figures.UnknownEntry, figures.EntryNotReady, ValueError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    return 2  # pragma: no cover (argparse guarantees a command)
