"""nbval's executions of the reference notebooks, kept for the site build (``make test``).

nbval runs every code cell of ``tests/golden/*.ipynb`` in a new kernel and compares its outputs
with the stored ones; the strict site build of ``make test`` used to execute the same chapters
(the same code cells, in the same environment and profile) once more. When the environment
variable :data:`ENV` names a folder, this plugin keeps what nbval's kernels answered and, for
every notebook whose cells **all passed** (executed without error, outputs equal to the
reference), writes the executed notebook there: the reference notebook with each code cell's
outputs as the kernel sent them (before nbval merges streams for its comparison: the order of
text and figures is the kernel's), images included, and sequential execution counts.
``tools/build_book.py --executed DIR`` stores those in the site's execution cache when their
code cells are those of the chapter, and executes the rest itself. Without the variable the
plugin does nothing.

With ``--nbval-kernel-name fusioncenter-fork`` (``make test``) the kernels are forked from one
process that has imported the chapters' libraries already (``tools/kernel_fork.py``): this
plugin provides the kernelspec, starts that process before the first notebook and stops it at
the end, and reports how many kernels were forked and why any was not. Under
``tools/run_tests.py`` the two shards share one such process, which it starts and stops
(``FUSIONCENTER_KERNEL_FORK_SHARED`` names its folder): the plugin waits until it is ready.
"""

from __future__ import annotations

import contextlib
import copy
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

import pytest

#: tools/kernel_fork.py's KERNEL_NAME (imported only when asked for: nbval alone needs nothing)
FORK_KERNEL = "fusioncenter-fork"

ENV = "FUSIONCENTER_NBVAL_EXECUTED"
#: metadata key of a kept notebook: ``{"profile", "seconds", "cells", "executed"}``
META = "fusioncenter_nbval"

_FOLDER = os.environ.get(ENV, "").strip()
_running: dict = {}   # "item": the cell being run; "raw": its outputs before nbval merges them
_cells: dict = {}     # nodeid -> {"outputs": [...] | None, "ok": bool, "seconds": float}


def _recording(original):
    def coalesce_streams(outputs):
        if _running.get("item") is not None and "raw" not in _running:
            # the first call of a cell's run is on the kernel's outputs (the reference's
            # follows); merging edits the stream nodes in place, so copy them first
            _running["raw"] = [copy.copy(o) for o in outputs or []]
        return original(outputs)

    return coalesce_streams


if _FOLDER:
    import nbval.plugin as _nbval

    _nbval.coalesce_streams = _recording(_nbval.coalesce_streams)

    @pytest.hookimpl(hookwrapper=True)
    def pytest_runtest_call(item):
        _running.clear()
        _running["item"] = item
        try:
            yield
        finally:
            _cells.setdefault(item.nodeid, {"ok": True, "seconds": 0.0})["outputs"] = \
                _running.get("raw")
            _running.clear()

    def pytest_runtest_logreport(report):
        rec = _cells.setdefault(report.nodeid, {"ok": True, "seconds": 0.0, "outputs": None})
        rec["seconds"] += report.duration
        if report.failed or report.skipped:
            rec["ok"] = False

    def pytest_sessionfinish(session):
        keep(session.items, Path(_FOLDER))


_fork: dict = {}  # "stack", "log": the warm process of tools/kernel_fork.py


def pytest_configure(config):
    if getattr(config.option, "nbval_kernel_name", None) != FORK_KERNEL:
        return
    sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tools"))
    import kernel_fork

    assert kernel_fork.KERNEL_NAME == FORK_KERNEL
    shared = os.environ.get(kernel_fork.SHARED_ENV, "").strip()
    if shared:  # tools/run_tests.py's warm process, for both shards: it starts and stops it
        try:
            log = kernel_fork.wait_ready(Path(shared))
        except (OSError, ValueError, RuntimeError) as exc:
            raise pytest.UsageError(f"the shared warm process ({shared}): {exc}") from None
        _fork.update(stack=contextlib.ExitStack(), log=log)
        return
    tmp = Path(tempfile.mkdtemp(prefix="fusioncenter-fork-"))
    stack = contextlib.ExitStack()
    stack.callback(shutil.rmtree, tmp, ignore_errors=True)
    try:
        log = stack.enter_context(kernel_fork.warm_kernels(tmp))
    except RuntimeError as exc:
        stack.close()
        raise pytest.UsageError(str(exc)) from None
    _fork.update(stack=stack, log=log)


def pytest_terminal_summary(terminalreporter):
    if _fork:
        import kernel_fork

        lines = kernel_fork.mine(_fork["log"])  # a shared warm process also logs the other's
        forked = sum(1 for line in lines if line.startswith("kernel_fork: forked"))
        others = [line for line in lines if not line.startswith("kernel_fork: forked")]
        terminalreporter.write_line(f"kernel_fork: {forked} kernel(s) forked from the warm "
                                    f"process; {len(others)} other line(s)")
        for line in others:
            terminalreporter.write_line(f"    {line}")


def pytest_unconfigure(config):
    if _fork:
        _fork.pop("stack").close()
        _fork.clear()


def _output(raw: dict):
    """An output node as nbclient would store it from the same kernel message."""
    import nbformat

    kind = raw["output_type"]
    if kind == "stream":
        return nbformat.v4.new_output(kind, name=raw["name"], text=raw["text"])
    if kind == "display_data":
        return nbformat.v4.new_output(kind, data=raw["data"], metadata=raw.get("metadata", {}))
    if kind == "execute_result":
        return nbformat.v4.new_output(kind, data=raw["data"], metadata=raw.get("metadata", {}),
                                      execution_count=raw.get("execution_count"))
    raise ValueError(f"unexpected output type {kind!r}")  # errors fail the cell: never kept


def keep(items, folder: Path) -> list[Path]:
    """Write the executed notebook of every file whose cells all passed; the paths written."""
    import nbformat

    by_file: dict[Path, list] = {}
    for item in items:
        if hasattr(item, "cell_num"):  # an nbval cell (IPyNbCell)
            by_file.setdefault(Path(item.parent.path), []).append(item)
    folder.mkdir(parents=True, exist_ok=True)
    written = []
    for path, cells in by_file.items():
        recs = [_cells.get(c.nodeid) for c in cells]
        if not all(r and r["ok"] and r.get("outputs") is not None for r in recs):
            continue
        nb = nbformat.read(str(path), as_version=4)
        code = [c for c in nb.cells if c.cell_type == "code"]
        if [c.cell_num for c in cells] != list(range(len(code))):
            continue  # not every code cell ran, in order: the site build executes it itself
        for count, (cell, rec) in enumerate(zip(code, recs, strict=True), 1):
            cell.outputs = [_output(o) for o in rec["outputs"]]
            cell.execution_count = count
        nb.metadata[META] = {"profile": os.environ.get("FUSIONCENTER_PROFILE") or "fast",
                             "seconds": round(sum(r["seconds"] for r in recs), 1),
                             "cells": len(code),
                             "executed": time.strftime("%Y-%m-%dT%H:%M:%S")}
        dest = folder / path.name
        tmp = dest.with_suffix(f".{os.getpid()}.tmp")
        nbformat.write(nb, str(tmp))
        tmp.replace(dest)
        written.append(dest)
    return written
