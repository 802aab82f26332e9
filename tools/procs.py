"""Child processes that an interrupt stops completely, shared by build_book.py and run_tests.py.

Every stage runs in its own session (``start_new_session``), so that a Ctrl-C at the terminal
reaches only the tool, which then stops each running stage's whole process tree: the tree is
read from ``/proc`` (Jupyter kernels start their own sessions, so a process group is not
enough), sent SIGTERM, and what is left after a grace period SIGKILL.
"""

from __future__ import annotations

import os
import signal
import subprocess
import threading
import time
from pathlib import Path

_LOCK = threading.Lock()
_RUNNING: dict[int, tuple[str, subprocess.Popen]] = {}
#: Set by :func:`install_handlers` when a SIGINT or SIGTERM arrived: ``(signal number, stage
#: names that were running)``.
INTERRUPTED: list = []


def descendants(pid: int) -> list[int]:
    """Every process below ``pid`` (children first found, then theirs), from ``/proc``."""
    children: dict[int, list[int]] = {}
    for d in Path("/proc").iterdir():
        if not d.name.isdigit():
            continue
        try:
            stat = (d / "stat").read_text()
        except OSError:
            continue
        ppid = int(stat.rsplit(")", 1)[1].split()[1])
        children.setdefault(ppid, []).append(int(d.name))
    out, todo = [], [pid]
    while todo:
        for c in children.get(todo.pop(), []):
            out.append(c)
            todo.append(c)
    return out


def kill_tree(pid: int, grace: float = 5.0) -> None:
    """SIGTERM to ``pid`` and all its descendants, SIGKILL to those alive after ``grace`` s."""
    procs = [pid, *descendants(pid)]
    for p in procs:
        try:
            os.kill(p, signal.SIGTERM)
        except ProcessLookupError:
            pass
    deadline = time.monotonic() + grace
    while time.monotonic() < deadline:
        alive = [p for p in procs if _alive(p)]
        if not alive:
            return
        time.sleep(0.1)
    for p in procs + descendants(pid):
        try:
            os.kill(p, signal.SIGKILL)
        except ProcessLookupError:
            pass


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    try:  # a zombie is dead
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def start(name: str, cmd: list[str], **kw) -> subprocess.Popen | None:
    """Start ``cmd`` in its own session, registered as a running stage (stopped with the others
    on an interrupt); ``None`` once an interrupt has arrived. End it with :func:`wait`."""
    with _LOCK:
        if INTERRUPTED:
            return None
        proc = subprocess.Popen(cmd, start_new_session=True, **kw)
        _RUNNING[proc.pid] = (name, proc)
    return proc


def rename(proc: subprocess.Popen, name: str) -> None:
    """What an interrupt reports a running stage as (e.g. the chapter a worker executes now)."""
    with _LOCK:
        if proc.pid in _RUNNING:
            _RUNNING[proc.pid] = (name, proc)


def wait(proc: subprocess.Popen) -> int:
    """Wait for a process :func:`start` started; its return code. It is no longer a stage.

    Sets ``proc.cpu_seconds``: the user + system CPU time of the process and of every
    descendant that was waited for (kernels, pool workers), from ``wait4``; a descendant
    orphaned before it ends (Chromium's renderers when the browser closes) is not counted."""
    try:
        try:
            _, status, usage = os.wait4(proc.pid, 0)
        except ChildProcessError:  # reaped already (e.g. by Popen itself)
            proc.cpu_seconds = None
            return proc.wait()
        proc.returncode = os.waitstatus_to_exitcode(status)
        proc.cpu_seconds = usage.ru_utime + usage.ru_stime
        return proc.returncode
    finally:
        with _LOCK:
            _RUNNING.pop(proc.pid, None)


def run(name: str, cmd: list[str], **kw) -> int:
    """Run ``cmd`` in its own session and wait; its return code (negative: killed by a signal).

    Refuses to start (returns 130) once an interrupt has arrived.
    """
    return run_timed(name, cmd, **kw)[0]


def run_timed(name: str, cmd: list[str], **kw) -> tuple[int, float | None]:
    """:func:`run`, also returning the CPU seconds of the process tree (see :func:`wait`)."""
    proc = start(name, cmd, **kw)
    if proc is None:
        return 130, None
    rc = wait(proc)
    return rc, proc.cpu_seconds


def running() -> list[str]:
    with _LOCK:
        return [name for name, _ in _RUNNING.values()]


def stop_all() -> list[str]:
    """Stop every running stage's process tree; the names of the stages stopped."""
    with _LOCK:
        items = list(_RUNNING.values())
    for _, proc in items:
        kill_tree(proc.pid)
    return [name for name, _ in items]


def install_handlers(on_interrupt) -> None:
    """On SIGINT or SIGTERM: record it, stop every stage, then call ``on_interrupt(signum,
    stages)`` (which should print and exit). A second signal during that is ignored."""

    def handler(signum, frame):
        if INTERRUPTED:
            return
        INTERRUPTED.append((signum, running()))
        stages = stop_all()
        on_interrupt(signum, INTERRUPTED[0][1] or stages)

    signal.signal(signal.SIGINT, handler)
    signal.signal(signal.SIGTERM, handler)


def exit_code(signum: int) -> int:
    """The shell's convention: 128 + the signal number (130 for SIGINT, 143 for SIGTERM)."""
    return 128 + signum
