"""The command line's subcommands: what ``list``, ``params``, ``compute``, ``plot`` and
``verify`` do with the parsed arguments (:func:`run_command`). An unknown id is refused from the
index before any figure module is imported, and an output path is checked writable before
computing starts."""

from __future__ import annotations

import contextlib
import os
import sys
import time
from pathlib import Path

from fusioncenter.cli.exits import EXIT_CLAIM, EXIT_OK, UnknownId
from fusioncenter.cli.output import dumps, write_csv
from fusioncenter.cli.parsing import parse_overrides
from fusioncenter.profile import current_profile

__all__ = ["run_command"]


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
    raise UnknownId(f"unknown figure/table id {entry_id!r}{hint} (`fusioncenter list` shows "
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


def run_command(args) -> int:
    """Run the parsed command (``list``, ``params``, ``compute``, ``plot`` or ``verify``).

    Parameters
    ----------
    args : argparse.Namespace
        What :func:`~fusioncenter.cli.parsing.build_parser` parsed; ``profile`` and
        ``executor`` are filled in with their defaults here.

    Returns
    -------
    int
        ``EXIT_OK`` (0), or for ``verify``
        ``EXIT_CLAIM`` (1) if a checked claim failed.

    Raises
    ------
    Exception
        Whatever the run raises; :func:`fusioncenter.cli.main` sorts it into an exit code.
    """
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
    over = entry.check_overrides(parse_overrides(args.overrides))
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
