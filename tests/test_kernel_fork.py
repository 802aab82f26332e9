"""Kernels forked from a warm process (tools/kernel_fork.py), as nbval starts them in make test.

The warm process here preloads a few modules only: these tests are about the mechanism (what
a forked kernel inherits, signals, the fallback). The real preload runs in every ``make test``,
where nbval compares all 29 reference notebooks' outputs from forked kernels."""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))
import kernel_fork  # noqa: E402

PROBE = """
import os, sys, threading
import matplotlib
print(repr([os.getcwd(), os.path.basename(sys.argv[0]), sys.argv[1:2], sys.path[0],
            os.environ.get("FORK_TEST_SHARED"), matplotlib.get_backend(),
            threading.active_count() >= 1, __name__]))
"""


def _run(km, code: str, timeout: float = 30) -> tuple[str, dict]:
    kc = km.client()
    kc.start_channels()
    try:
        kc.wait_for_ready(timeout=60)
        out: list[str] = []
        reply = kc.execute_interactive(
            code, timeout=timeout,
            output_hook=lambda m: out.append(m["content"].get("text", ""))
            if m["msg_type"] == "stream" else None)
        return "".join(out), reply["content"]
    finally:
        kc.stop_channels()


@pytest.fixture(scope="module")
def warm(tmp_path_factory):
    os.environ["FORK_TEST_SHARED"] = "seen"
    try:
        with kernel_fork.warm_kernels(tmp_path_factory.mktemp("fork"),
                                      preload=["ipykernel.kernelapp", "matplotlib"]) as log:
            yield log
    finally:
        os.environ.pop("FORK_TEST_SHARED", None)


def _start(name: str, cwd: Path):
    from jupyter_client.manager import KernelManager

    km = KernelManager(kernel_name=name)
    km.start_kernel(cwd=str(cwd))
    return km


def test_a_forked_kernel_has_what_a_new_kernel_has(warm, tmp_path):
    """Working directory, argv, sys.path, environment and matplotlib backend as in a kernel
    started as a new process from the same place."""
    answers = {}
    for name in (kernel_fork.KERNEL_NAME, "python3"):
        km = _start(name, tmp_path)
        try:
            answers[name] = _run(km, PROBE)[0]
        finally:
            km.shutdown_kernel(now=True)
    assert answers[kernel_fork.KERNEL_NAME] == answers["python3"]
    assert str(tmp_path) in answers["python3"] and "seen" in answers["python3"]
    assert "module://matplotlib_inline.backend_inline" in answers["python3"]
    assert "kernel_fork: forked" in warm.read_text()


def test_local_kernels_talk_over_ipc_and_print_no_tcp_warning(warm, tmp_path):
    """With :func:`kernel_fork.local_kernel_config` (build_book, make_golden) a forked kernel
    runs on IPC sockets, and ipykernel's warning about unencrypted TCP, which the same kernel
    prints over TCP, is not printed."""
    from jupyter_client.manager import KernelManager

    warning = "Kernel is running over TCP without encryption"
    seen = {}
    for transport, config in (("tcp", None), ("ipc", kernel_fork.local_kernel_config())):
        err = tmp_path / f"{transport}.err"
        km = KernelManager(kernel_name=kernel_fork.KERNEL_NAME, config=config)
        with err.open("w") as stream:
            km.start_kernel(cwd=str(tmp_path), stderr=stream)
        try:
            assert km.transport == transport
            assert _run(km, "print(6 * 7)")[0] == "42\n"
            info = km.get_connection_info()
            assert info["transport"] == transport
            if transport == "ipc":
                assert os.path.isabs(info["ip"]) and not list(tmp_path.glob("kernel-ipc*"))
        finally:
            km.shutdown_kernel(now=True)
        seen[transport] = warning in err.read_text()
    assert seen == {"tcp": True, "ipc": False}


def test_interrupt_and_kill_reach_the_forked_kernel(warm, tmp_path):
    km = _start(kernel_fork.KERNEL_NAME, tmp_path)
    try:
        pid = int(_run(km, "import os; print(os.getpid())")[0])
        assert pid != km.provisioner.pid  # the kernel is not the launcher
        kc = km.client()
        kc.start_channels()
        msg_id = kc.execute("import time; time.sleep(60)")
        time.sleep(1.0)
        km.interrupt_kernel()  # SIGINT to the launcher, forwarded
        reply = kc.get_shell_msg(timeout=20)
        kc.stop_channels()
        assert reply["parent_header"]["msg_id"] == msg_id
        assert reply["content"]["ename"] == "KeyboardInterrupt"
    finally:
        km.shutdown_kernel(now=True)  # SIGKILL to the launcher: the kernel follows
    deadline = time.monotonic() + 5
    while time.monotonic() < deadline:
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            break
        time.sleep(0.1)
    else:
        os.kill(pid, 9)
        pytest.fail("the forked kernel outlived its launcher")


def test_another_environment_gets_a_new_process(warm, tmp_path, monkeypatch):
    """A variable the warm process did not import with: the launcher starts a new process."""
    before = warm.read_text().count("fallback")
    monkeypatch.setenv("FORK_TEST_OTHER", "1")
    km = _start(kernel_fork.KERNEL_NAME, tmp_path)
    try:
        out, reply = _run(km, "import os; print(os.environ['FORK_TEST_OTHER'], 6 * 7)")
    finally:
        km.shutdown_kernel(now=True)
    assert reply["status"] == "ok" and out.split() == ["1", "42"]
    log = warm.read_text()
    assert log.count("fallback") == before + 1
    assert "environment differs in ['FORK_TEST_OTHER']" in log


def test_the_log_names_the_process_that_started_each_kernel(warm, tmp_path):
    """A warm process may serve several processes (tools/run_tests.py's two nbval shards):
    each kernel's line names the process that started it, and :func:`kernel_fork.mine` keeps
    a process's own lines and the warm process's lines about no kernel, not the others'."""
    km = _start(kernel_fork.KERNEL_NAME, tmp_path)
    try:
        _run(km, "pass")
    finally:
        km.shutdown_kernel(now=True)
    me = os.getpid()
    assert any(x.startswith("kernel_fork: forked ") and x.endswith(f" for {me}")
               for x in kernel_fork.mine(warm))
    log = tmp_path / "log"
    log.write_text(f"kernel_fork: ready (9 modules)\nkernel_fork: forked 11 for {me}\n"
                   "kernel_fork: forked 12 for 7\n"
                   f"kernel_fork: fallback for {me}: environment differs in ['X']\n"
                   "kernel_fork: fallback for 7: environment differs in ['Y']\n"
                   "Traceback (most recent call last): for all\n")
    assert kernel_fork.mine(log) == [
        f"kernel_fork: forked 11 for {me}",
        f"kernel_fork: fallback for {me}: environment differs in ['X']",
        "Traceback (most recent call last): for all"]
    assert kernel_fork.mine(log, parent=7) == [
        "kernel_fork: forked 12 for 7", "kernel_fork: fallback for 7: environment differs in "
        "['Y']", "Traceback (most recent call last): for all"]


def test_a_warm_process_that_cannot_start_fails_with_its_log(tmp_path):
    """:func:`kernel_fork.wait_ready` (what a shard sharing the warm process of
    tools/run_tests.py waits with) ends with the warm process's error, not at its timeout."""
    env = dict(os.environ)
    proc = kernel_fork.start(tmp_path, env, preload=["no_such_module_here"])
    try:
        assert env[kernel_fork.SOCKET_ENV] == str(tmp_path / "socket")
        assert env["JUPYTER_PATH"].split(os.pathsep)[0] == str(tmp_path)
        assert (tmp_path / "kernels" / kernel_fork.KERNEL_NAME / "kernel.json").is_file()
        with pytest.raises(RuntimeError, match="ended before it was ready") as err:
            kernel_fork.wait_ready(tmp_path, timeout=600)
        assert "no_such_module_here" in str(err.value)
    finally:
        proc.kill()
        proc.wait()
