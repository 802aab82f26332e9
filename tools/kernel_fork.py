"""Jupyter kernels forked from one process that has already imported the book's libraries.

    python tools/kernel_fork.py serve SOCKET [MODULE,...]   # the warm process (tests/golden)
    python tools/kernel_fork.py launch -f FILE    # what the kernelspec runs (jupyter_client)

Every chapter of the book starts a new kernel, and before its first result each one imports
IPython and ipykernel, NumPy, SciPy, SymPy, numba, matplotlib and the library: 2 to 6 s of CPU
per chapter on this 2-core machine. nbval on the 29 reference notebooks, one process on an idle
machine: 282 s (286 s CPU) with new processes, 208 s (208 s CPU) with forked kernels. In
``make test`` from a fresh clone (two shards side by side on two cores, a cold bytecode and
numba cache) the gain is smaller: 160 and 163 s against 175 s and a failed shard for the tree
before, run back to back. There the warm process also takes the first imports out of the
kernels' 60 s start-up deadline; the tree before lost a shard's first kernel that way once
("Kernel died before replying to kernel_info").

``serve`` imports those once (:data:`PRELOAD`) and waits on a Unix socket; ``launch`` is the
kernel command of the kernelspec :data:`KERNEL_NAME`: a small process that hands its connection
file, environment, working directory and standard streams to the warm process, which forks. The
child becomes an ordinary ipykernel (``ipykernel_launcher -f FILE``) in the state a new process
would have reached after the same imports, with the launcher's working directory, environment
and streams. The launcher stays in place as the process jupyter_client manages: it forwards
every signal it is sent (interrupt, terminate) to the kernel and exits when the kernel has; the
kernel exits when the launcher dies (even by SIGKILL).

Nothing is shared that a new process would not have: the warm process runs no user code, starts
no thread (:func:`serve` checks) and only imports, in the environment the kernels get.
``launch`` falls back to a new process (``exec`` of ``python -m ipykernel_launcher``) whenever
forking would not be equivalent: the warm process is not reachable, or the kernel's
environment differs from the one it imported in (other than :data:`PER_KERNEL` variables).
It says so on its standard error.

matplotlib is imported with ``MPLBACKEND`` set as ipykernel sets it (to the inline backend,
unless already set); pyplot resolves the backend only when the first figure is made, in the
kernel, where the inline backend hooks into the kernel's shell. Checked against kernels started
as new processes, on the 29 reference notebooks: every printed text is the same (up to where
ipykernel splits a stream), and 53 of the 54 PNG outputs are the same bytes; the 54th is the
synthesis chapter's cost figure, which plots measured run times.
"""

from __future__ import annotations

import contextlib
import json
import os
import re
import signal
import socket
import struct
import subprocess
import sys
import time
from pathlib import Path

KERNEL_NAME = "fusioncenter-fork"
#: How the book's tools start local kernels (jupyter_client's own settings,
#: ``KernelManager.transport`` and ``.ip``): kernel and client talk over Unix sockets (IPC) in
#: Jupyter's runtime folder (mode 0700), not over TCP on the loopback. ipykernel >= 7.3 warns at
#: every kernel started over TCP without CurveZMQ keys ("Kernel is running over TCP without
#: encryption...": 29 times in a build); over IPC nothing goes through the network stack, and
#: no two kernels started at the same moment can race for a port. :func:`local_kernel_config`
#: is what nbclient takes: it adds the sockets' absolute path prefix, one per kernel (the
#: default, a relative ``kernel-ipc``, is resolved by the kernel in the chapter's folder and by
#: the client in its own, and they never meet).
LOCAL_KERNELS = {"KernelManager": {"transport": "ipc"}}
#: ipykernel's default backend (IPKernelApp.init_gui_pylab sets it unless MPLBACKEND is set)
INLINE = "module://matplotlib_inline.backend_inline"
SOCKET_ENV = "FUSIONCENTER_KERNEL_FORK"
#: The folder of a warm process that another process started and stops (:func:`start`): set
#: by tools/run_tests.py for its nbval shards, which then share one warm process
#: (tests/golden/conftest.py waits for it, :func:`wait_ready`, instead of starting its own).
SHARED_ENV = "FUSIONCENTER_KERNEL_FORK_SHARED"
#: set for each kernel (by jupyter_client, by pytest for the test that starts it, by the
#: terminal size): no module reads them when it is imported, only when it is called
PER_KERNEL = frozenset({"JPY_PARENT_PID", "JPY_SESSION_NAME", "PYTEST_CURRENT_TEST", "COLUMNS",
                        "LINES"})
#: what the chapters import (tests/golden/*.ipynb)
PRELOAD = [
    "ipykernel.kernelapp", "ipykernel.ipkernel", "IPython.display", "numpy", "scipy.stats",
    "scipy.integrate", "scipy.optimize", "scipy.special", "scipy.linalg", "sympy", "sympy.stats",
    "mpmath", "filterpy.kalman", "matplotlib", "matplotlib.figure", "fusioncenter",
    "fusioncenter.figures", "fusioncenter.censoring", "fusioncenter.censoring.vector",
    "fusioncenter.censoring.nonlinear", "fusioncenter.event", "fusioncenter.fading",
    "fusioncenter.power", "fusioncenter.comparison", "fusioncenter.particle",
    "fusioncenter.riccati", "fusioncenter.kalman", "fusioncenter.models", "matplotlib.pyplot",
    "fusioncenter.plotting", "fusioncenter.book",
    # what a chapter's first glue() imports (fusioncenter.glue calls MyST-NB's): nbformat and
    # jsonschema, whose format checkers build a grammar at import; 1.8 s in every chapter that
    # glues a number (23 of 29), 41 s of the nbval shards' CPU in a fresh make test
    "myst_nb.ext.glue",
]


def local_kernel_config():
    """A traitlets ``Config`` of :data:`LOCAL_KERNELS` for one kernel, for
    ``NotebookClient(config=...)`` (and jupyter-cache's ``single_nb_execution``, which passes
    it on): its kernel manager starts the kernel on IPC sockets named
    ``<runtime dir>/fusioncenter-<random>-ipc-<n>``, which it removes at the kernel's shutdown.
    """
    import copy
    import uuid

    from jupyter_core.paths import jupyter_runtime_dir
    from jupyter_core.utils import ensure_dir_exists
    from traitlets.config import Config

    runtime = jupyter_runtime_dir()
    ensure_dir_exists(runtime, 0o700)
    config = Config(copy.deepcopy(LOCAL_KERNELS))
    # a Unix socket's path has at most 107 bytes: the runtime folder is short enough
    config.KernelManager.ip = os.path.join(runtime, f"fusioncenter-{uuid.uuid4().hex[:12]}-ipc")
    return config


def _send(sock: socket.socket, obj: dict, fds: list[int] = ()) -> None:
    data = json.dumps(obj).encode()
    socket.send_fds(sock, [struct.pack("!I", len(data)) + data], list(fds))


def _recv(sock: socket.socket, maxfds: int = 0) -> tuple[dict, list[int]]:
    buf, fds, _flags, _addr = socket.recv_fds(sock, 1 << 16, maxfds)
    if len(buf) < 4:
        raise ConnectionError("short message")
    (n,) = struct.unpack("!I", buf[:4])
    buf = buf[4:]
    while len(buf) < n:
        more = sock.recv(n - len(buf))
        if not more:
            raise ConnectionError("connection closed mid-message")
        buf += more
    return json.loads(buf), fds


def _differences(env: dict, mine: dict) -> list[str]:
    keys = (set(env) | set(mine)) - PER_KERNEL
    return sorted(k for k in keys if env.get(k) != mine.get(k))


# --------------------------------------------------------------------------- the warm process
def serve(path: str, preload: list[str] = PRELOAD) -> None:
    import importlib
    import threading

    env = dict(os.environ)  # the environment the kernels must have, as they will see it
    # the path a kernel has while it loads (ipykernel_launcher drops the script's folder;
    # IPKernelApp.init_path puts '' back)
    if sys.path and os.path.abspath(sys.path[0]) == os.path.dirname(os.path.abspath(__file__)):
        del sys.path[0]
    os.environ["MPLBACKEND"] = os.environ.get("MPLBACKEND") or INLINE  # before matplotlib
    for name in preload:
        importlib.import_module(name)
    if threading.active_count() != 1:
        raise RuntimeError(f"kernel_fork: the preload started threads: {threading.enumerate()}")

    def reap(_signum, _frame):  # at once, so that a kernel's CPU time counts as this tree's
        try:
            while os.waitpid(-1, os.WNOHANG)[0] > 0:
                pass
        except ChildProcessError:
            pass

    signal.signal(signal.SIGCHLD, reap)
    listener = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    listener.bind(path)
    listener.listen(64)
    print(f"kernel_fork: ready ({len(sys.modules)} modules)", flush=True)
    # one line per kernel: "forked PID for PARENT" or "fallback for PARENT: why", PARENT the
    # process that started it (a warm process may serve several: tools/run_tests.py's shards)
    log = sys.stdout
    while True:
        conn, _ = listener.accept()
        try:
            req, fds = _recv(conn, maxfds=3)
        except (OSError, ValueError, ConnectionError):
            conn.close()
            continue
        diff = _differences(req["env"], env)
        who = f" for {req.get('parent', '?')}"  # the process that started the kernel
        if diff or len(fds) != 3:
            why = f"environment differs in {diff[:8]}" if diff else "no standard streams"
            _send(conn, {"fallback": why})
            print(f"kernel_fork: fallback{who}: {why}", file=log, flush=True)
            conn.close()
            for fd in fds:
                os.close(fd)
            continue
        pid = os.fork()
        if pid == 0:
            listener.close()
            _become_kernel(conn, fds, req)  # never returns
        print(f"kernel_fork: forked {pid}{who}", file=log, flush=True)
        conn.close()
        for fd in fds:
            os.close(fd)


def _become_kernel(conn: socket.socket, fds: list[int], req: dict) -> None:
    import atexit
    import threading

    code = 1
    try:
        os.setsid()  # a session of its own, as jupyter_client starts kernels
        for fd, target in zip(fds, (0, 1, 2), strict=True):
            os.dup2(fd, target)
            os.close(fd)
        signal.signal(signal.SIGCHLD, signal.SIG_DFL)
        _send(conn, {"pid": os.getpid()})
        conn.close()
        os.chdir(req["cwd"])
        os.environ.clear()
        os.environ.update(req["env"], MPLBACKEND=req["env"].get("MPLBACKEND") or INLINE)
        import importlib.util

        # argv[0] as `python -m ipykernel_launcher` has it
        sys.argv = [importlib.util.find_spec("ipykernel_launcher").origin, *req["argv"]]
        launcher = int(req["launcher"])

        def watch() -> None:  # the launcher is what jupyter_client kills
            while True:
                time.sleep(0.2)
                try:
                    os.kill(launcher, 0)
                except ProcessLookupError:
                    os._exit(1)

        threading.Thread(target=watch, daemon=True, name="kernel_fork-watch").start()
        from ipykernel import kernelapp

        try:
            kernelapp.launch_new_instance()
            code = 0
        except SystemExit as exc:
            code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
    except BaseException:  # noqa: BLE001 - report, then leave the warm process's stack
        import traceback

        traceback.print_exc()
    finally:
        try:
            atexit._run_exitfuncs()
            sys.stdout.flush()
            sys.stderr.flush()
        finally:
            os._exit(code)


def start(tmp: Path, env: dict, *, preload: list[str] | None = None,
          popen=subprocess.Popen) -> subprocess.Popen:
    """Start a warm process in ``tmp``: the kernelspec :data:`KERNEL_NAME` in ``tmp/kernels``,
    the socket ``tmp/socket``, its log ``tmp/log`` (one line per kernel) and its pid in
    ``tmp/pid``. ``env`` is the environment the kernels will have: it gets ``JUPYTER_PATH``
    (``tmp`` first) and :data:`SOCKET_ENV`, in place, and the warm process starts in it.
    ``popen(cmd, **kw)`` starts the process (``tools/procs.py``'s, for one that an interrupt
    stops; ``None`` from it is a RuntimeError). Wait for it with :func:`wait_ready`."""
    spec = tmp / "kernels" / KERNEL_NAME
    spec.mkdir(parents=True)
    spec.joinpath("kernel.json").write_text(json.dumps({
        "argv": [sys.executable, os.path.abspath(__file__), "launch", "-f", "{connection_file}"],
        "display_name": "Python 3 (forked)", "language": "python",
        "metadata": {"debugger": True}}))
    env["JUPYTER_PATH"] = os.pathsep.join(p for p in (str(tmp), env.get("JUPYTER_PATH")) if p)
    env[SOCKET_ENV] = str(tmp / "socket")
    with (tmp / "log").open("w") as fh:
        proc = popen([sys.executable, os.path.abspath(__file__), "serve", str(tmp / "socket"),
                      *([",".join(preload)] if preload is not None else [])],
                     env=dict(env), stdin=subprocess.DEVNULL, stdout=fh,
                     stderr=subprocess.STDOUT)
    if proc is None:
        raise RuntimeError("tools/kernel_fork.py serve not started (interrupted)")
    (tmp / "pid").write_text(str(proc.pid))
    return proc


def wait_ready(tmp: Path, timeout: float = 600.0) -> Path:
    """Wait until the warm process that :func:`start` started in ``tmp`` (here or in another
    process) is ready; its log. RuntimeError with the log's end if it ended first or is not
    ready within ``timeout`` s (a fresh clone compiles the bytecode first)."""
    from procs import _alive  # beside this file: ended or a zombie is not alive

    log, pid = tmp / "log", int((tmp / "pid").read_text())
    deadline = time.monotonic() + timeout
    while "kernel_fork: ready" not in log.read_text():
        why = ("ended before it was ready" if not _alive(pid) else
               f"was not ready within {timeout:g} s" if time.monotonic() > deadline else None)
        if why:
            raise RuntimeError(f"tools/kernel_fork.py serve {why}:\n{log.read_text()[-3000:]}")
        time.sleep(0.05)
    return log


def mine(log: Path, parent: int | None = None) -> list[str]:
    """The lines of the warm process's ``log`` about the kernels that ``parent`` (default: this
    process) started, and every line about no kernel (the warm process's own errors)."""
    parent = os.getpid() if parent is None else parent
    out = []
    for line in log.read_text().splitlines():
        m = re.match(r"kernel_fork: (?:forked \d+|fallback) for (\S+?)(?::|$)", line)
        if (m is None and "kernel_fork: ready" not in line) or (m and m[1] == str(parent)):
            out.append(line)
    return out


@contextlib.contextmanager
def warm_kernels(tmp: Path, timeout: float = 600.0, preload: list[str] | None = None):
    """The kernelspec :data:`KERNEL_NAME` (in ``tmp``, put on ``JUPYTER_PATH``) and its warm
    process (socket ``tmp/socket``), for kernels this process starts while the context lasts;
    yields the warm process's log (one line per kernel). ``os.environ`` gets both variables
    before the warm process starts: they are part of the environment the kernels will have.
    ``preload`` replaces :data:`PRELOAD` (the tests of the mechanism)."""
    saved = {k: os.environ.get(k) for k in ("JUPYTER_PATH", SOCKET_ENV)}
    proc = None
    try:
        proc = start(tmp, os.environ, preload=preload)
        yield wait_ready(tmp, timeout)
    finally:
        if proc is not None:
            proc.terminate()
            try:
                proc.wait(10)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait()
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


# --------------------------------------------------------------------------- the kernel command
def _fallback(argv: list[str], why: str) -> None:
    print(f"kernel_fork: starting a new kernel process ({why})", file=sys.stderr, flush=True)
    os.execv(sys.executable, [sys.executable, "-m", "ipykernel_launcher", *argv])


def main(argv: list[str] | None = None) -> int:
    args = list(sys.argv[1:] if argv is None else argv)
    if args[:1] == ["serve"] and len(args) in (2, 3):
        serve(args[1], *([[m for m in args[2].split(",") if m]] if len(args) == 3 else []))
        return 0
    if args[:1] != ["launch"]:
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        return 2
    kargs = args[1:]
    path = os.environ.get(SOCKET_ENV, "").strip()
    if not path:
        _fallback(kargs, f"{SOCKET_ENV} is not set")
    sock = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    try:
        sock.connect(path)
        _send(sock, {"argv": kargs, "env": dict(os.environ), "cwd": os.getcwd(),
                     "launcher": os.getpid(), "parent": os.getppid()}, [0, 1, 2])
        reply, _ = _recv(sock)
    except (OSError, ValueError, ConnectionError) as exc:
        _fallback(kargs, f"the warm process at {path} did not answer: {exc}")
    finally:
        sock.close()
    if "pid" not in reply:
        _fallback(kargs, reply.get("fallback", "refused"))
    pid = int(reply["pid"])

    def forward(signum, _frame):
        try:
            os.kill(pid, signum)
        except ProcessLookupError:
            pass

    for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP, signal.SIGQUIT, signal.SIGUSR1,
                signal.SIGUSR2):
        signal.signal(sig, forward)
    while True:
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            return 0
        time.sleep(0.05)


if __name__ == "__main__":
    sys.exit(main())
