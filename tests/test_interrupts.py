"""Ctrl-C and SIGTERM of `make test` and `make book` stop every child and leave nothing finished.

A fake driver uses the tools' own process handling (tools/procs.py, as tools/run_tests.py and
tools/build_book.py do): its stage starts a grandchild in a new session, as a Jupyter kernel
does. After the signal the driver must exit 130 / 143, say which stage was interrupted, start
no further stage, and the grandchild must be gone.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

TOOLS = Path(__file__).resolve().parent.parent / "tools"
sys.path.insert(0, str(TOOLS))

import build_book  # noqa: E402
import procs  # noqa: E402

CHILD = textwrap.dedent("""
    import subprocess, sys, time
    k = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(120)"],
                         start_new_session=True)
    open(sys.argv[1], "w").write(str(k.pid))
    time.sleep(120)
""")

DRIVER = textwrap.dedent("""
    import os, sys
    sys.path.insert(0, {tools!r})
    import procs

    def on_interrupt(signum, stages):
        print("interrupted during", ", ".join(stages), flush=True)
        os._exit(procs.exit_code(signum))

    procs.install_handlers(on_interrupt)
    procs.run("fake stage", [sys.executable, "-c", {child!r}, {pidfile!r}])
    print("next stage started", flush=True)
    procs.run("second stage", [sys.executable, "-c", "pass"])
""")


def _alive(pid: int) -> bool:
    return procs._alive(pid)


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_signal_stops_every_child_and_no_next_stage(tmp_path, sig):
    pidfile = tmp_path / "kernel.pid"
    script = tmp_path / "driver.py"
    script.write_text(DRIVER.format(tools=str(TOOLS), child=CHILD, pidfile=str(pidfile)))
    proc = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    while not (pidfile.exists() and pidfile.read_text().strip()):
        assert time.monotonic() < deadline, "the fake stage did not start"
        assert proc.poll() is None
        time.sleep(0.05)
    kernel = int(pidfile.read_text())
    assert _alive(kernel)
    proc.send_signal(sig)
    out, _ = proc.communicate(timeout=30)
    assert proc.returncode == 128 + sig
    assert "interrupted during fake stage" in out
    assert "next stage started" not in out
    deadline = time.monotonic() + 10
    while _alive(kernel) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not _alive(kernel), "the grandchild (a kernel in its own session) survived"


def test_no_stage_starts_after_an_interrupt(monkeypatch):
    monkeypatch.setattr(procs, "INTERRUPTED", [(signal.SIGINT, [])])
    assert procs.run("late", [sys.executable, "-c", "raise SystemExit(0)"]) == 130


@pytest.fixture
def fake_root(tmp_path, monkeypatch):
    for rel in ("src/pkg/a.py", "requirements/lock.txt", "pyproject.toml", "_config.yml",
                "book/_ext/ext.py", "tools/build_book.py"):
        p = tmp_path / rel
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(rel)
    monkeypatch.setattr(build_book, "ROOT", tmp_path)
    return tmp_path


def test_book_ext_is_in_the_fingerprint(fake_root):
    a = build_book.fingerprint("fast")
    (fake_root / "book/_ext/ext.py").write_text("changed")
    assert build_book.fingerprint("fast") != a
    assert build_book.fingerprint("paper") != build_book.fingerprint("fast")


def test_fingerprint_only_after_success(fake_root, monkeypatch):
    out = fake_root / "_build" / "fast"
    want = build_book.prepare(out, "fast")
    stamp = out / "_build" / build_book.STAMP
    assert not stamp.exists()  # a build under way is not finished
    (out / "_build" / "html").mkdir()
    (out / "_build" / "html" / "page.html").write_text("old")
    build_book.finish(out, want)
    assert stamp.read_text().strip() == want
    # unchanged inputs and a finished build: kept (and the stamp removed until it finishes)
    build_book.prepare(out, "fast")
    assert (out / "_build" / "html" / "page.html").exists() and not stamp.exists()
    # the previous build did not finish (no stamp): everything goes
    build_book.prepare(out, "fast")
    assert not (out / "_build" / "html").exists()


def test_build_book_interrupt_handler_removes_the_fingerprint(fake_root, monkeypatch, capsys):
    out = fake_root / "_build" / "fast"
    (out / "_build").mkdir(parents=True)
    (out / "_build" / build_book.STAMP).write_text("x\n")
    codes = []
    monkeypatch.setattr(os, "_exit", codes.append)
    monkeypatch.setattr(build_book, "_STAGE", ["execution"])
    build_book._on_interrupt(out)(signal.SIGTERM, ["execute book/intro"])
    assert codes == [143]
    assert not (out / "_build" / build_book.STAMP).exists()
    err = capsys.readouterr().err
    assert "SIGTERM: interrupted during the execution stage (execute book/intro)" in err


def test_descendants_and_kill_tree(tmp_path):
    pidfile = tmp_path / "k.pid"
    p = subprocess.Popen([sys.executable, "-c", CHILD, str(pidfile)], start_new_session=True)
    deadline = time.monotonic() + 60
    while not (pidfile.exists() and pidfile.read_text().strip()):
        assert time.monotonic() < deadline
        time.sleep(0.05)
    kernel = int(pidfile.read_text())
    assert kernel in procs.descendants(p.pid)
    procs.kill_tree(p.pid)
    p.wait(timeout=10)
    deadline = time.monotonic() + 10
    while _alive(kernel) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not _alive(kernel)


# --------------------------------------------------- the command line's own process pool
@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_cli_signal_ends_the_run_and_its_pool(sig):
    """SIGTERM (like Ctrl-C) to ``fusioncenter compute --executor processes:2``: exit 143
    (130), one line ``error: ...``, and no worker or resource tracker left behind."""
    root = Path(__file__).resolve().parent.parent
    env = {**os.environ, "PYTHONPATH": str(root / "src")}
    env.pop("FUSIONCENTER_COMPUTE_CACHE", None)
    proc = subprocess.Popen(
        [sys.executable, "-m", "fusioncenter", "compute", "zheng2014-fig1", "--json",
         "--executor", "processes:2", "--set", "trials=20000", "--set", "particles=1000"],
        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, env=env)
    deadline = time.monotonic() + 180
    kids: list[int] = []
    while len(kids) < 3:  # two workers and the resource tracker
        assert proc.poll() is None, "the run ended before the signal"
        assert time.monotonic() < deadline, "the pool did not start"
        time.sleep(0.2)
        kids = procs.descendants(proc.pid)
    time.sleep(1.0)  # the workers are computing
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 128 + sig, err
    errors = [ln for ln in err.splitlines() if ln.startswith("error:")]
    assert errors == ["error: interrupted" if sig == signal.SIGINT
                      else "error: terminated (SIGTERM)"], err
    assert "Traceback" not in err
    deadline = time.monotonic() + 10
    while any(_alive(k) for k in kids) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not [k for k in kids if _alive(k)], "pool workers or the resource tracker survived"


def _free_port() -> int:
    import socket

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_cli_a_dask_scheduler_killed_mid_run_exits_3():
    """The scheduler of ``--executor dask:ADDRESS`` dies while the trials run: one line
    ``error: ...`` and exit 3 (not 1, which means a failed claim), no traceback."""
    pytest.importorskip("distributed")
    root = Path(__file__).resolve().parent.parent
    env = {**os.environ, "PYTHONPATH": str(root / "src")}
    env.pop("FUSIONCENTER_COMPUTE_CACHE", None)
    port = _free_port()
    address = f"tcp://127.0.0.1:{port}"
    dask = [sys.executable, "-m", "distributed.cli.dask_scheduler"]
    sched = subprocess.Popen([*dask, "--host", "127.0.0.1", "--port", str(port),
                              "--no-dashboard"], stdout=subprocess.DEVNULL,
                             stderr=subprocess.DEVNULL, env=env, start_new_session=True)
    worker = subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_worker", address,
                               "--nthreads", "1", "--nworkers", "2", "--no-dashboard"],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env,
                              start_new_session=True)
    try:
        cli = subprocess.Popen(
            [sys.executable, "-m", "fusioncenter", "compute", "zheng2014-fig1", "--json",
             "--executor", f"dask:{address}", "--set", "trials=20000", "--set",
             "particles=1000"], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
            env=env)
        line = ""
        while not line.startswith("Monte Carlo:"):  # the blocks are on the cluster
            line = cli.stderr.readline()
            assert line or cli.poll() is None, "the run ended before the scheduler was killed"
        time.sleep(2.0)
        sched.kill()
        err = line + cli.stderr.read()
        cli.wait(timeout=120)
        assert cli.returncode == 3, err
        errors = [ln for ln in err.splitlines() if ln.startswith("error:")]
        assert len(errors) == 1 and "Traceback" not in err, err
    finally:
        for p in (worker, sched):
            if p.poll() is None:
                procs.kill_tree(p.pid)
            p.wait(timeout=30)
