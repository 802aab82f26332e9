"""Build the Jupyter Book site in one profile, chapters executed in parallel, never stale.

    python tools/build_book.py --profile paper            # the published site: _build/html
    python tools/build_book.py --profile fast --strict    # the test build: _build/fast/_build/html
    python tools/build_book.py --profile paper --edition student  # no solutions: _build/student

Two stages:

1. **execution**: every notebook chapter not yet in the execution cache (jupyter-cache, in
   ``<out>/_build/.jupyter_cache``, where jupyter-book looks) is executed, ``--jobs`` at a time
   (default: one per core), each in its own kernel, longest first (one worker process per
   lane runs its chapters one after another: :func:`serve`; its kernels are forked from a
   process that has imported the chapters' libraries once, tools/kernel_fork.py); the executed
   notebooks are stored in the cache exactly as myst-nb stores them (same reader, same hash of
   the code cells), so that:
2. **rendering**: ``jupyter-book build`` finds every chapter cached and only renders.

What it prints: a line per chapter executed, then jupyter-book's, quiet (``-q``: Sphinx's
warnings, not its progress through each file), then the times and the site's ``index.html``.
The kernels talk to their clients over IPC sockets (``kernel_fork.LOCAL_KERNELS``), so
ipykernel has no unencrypted TCP to warn about.

Registry results are shared between the chapters (and their parallel kernels) through
``FUSIONCENTER_COMPUTE_CACHE`` (atomic writes: see ``Entry.run_compute``): a folder of the build,
wiped with it, or the one ``--compute-cache`` names (whoever passes it keeps it current).
The executor of the heavy entries is ``FUSIONCENTER_EXECUTOR`` if set; else, with two or more
lanes, ``serial``: the lanes already keep every core busy, and a pool of worker processes per
chapter only adds their start (about 3 s of CPU each) and more processes than cores (a fresh
paper build on 2 cores: 7:32 with the paper profile's ``processes`` default, 6:48 with
``serial``, bootstrap included); with one lane, the library's default.

jupyter-cache keys a notebook's cached outputs on its cell sources only, so a change to the
library (``src/``), to the pinned environment (``requirements/lock.txt`` and its uv overrides,
``requirements/overrides.txt``), to the configuration, to the local Sphinx extensions
(``book/_ext``), to this tool or to the profile would otherwise leave old outputs on the site.
Each output folder therefore records a fingerprint of those inputs, written only after a
successful build; when it differs or is missing (a failed or an interrupted build), the folder's
whole ``_build`` (HTML, doctrees, the execution and compute caches) is removed first and
everything is executed again.

The library's wheel is built beside the execution stage and put under the site as
``_wheels/fusioncenter-<version>-py3-none-any.whl`` (tools/site_wheel.py): deploying the site is
all it takes for the downloaded notebooks' install cell to find the library.

The per-chapter record (profile, seconds, executed now or taken from the cache, date) goes to
``<out>/_build/execution-status.json``; the book's status page renders it. Ctrl-C or SIGTERM
stops every child (kernels included), says which stage was interrupted and exits 130 / 143.
"""

from __future__ import annotations

import argparse
import contextlib
import datetime as dt
import hashlib
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import procs  # noqa: E402
import site_wheel  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
OUTPUTS = {"paper": ROOT, "fast": ROOT / "_build" / "fast"}
#: The student edition (book/_ext/student_edition.py) builds apart, so it never overwrites the
#: instructor's site nor shares its execution cache key.
STUDENT_OUTPUTS = {"paper": ROOT / "_build" / "student", "fast": ROOT / "_build" / "fast-student"}
FINGERPRINT_INPUTS = ["src", "requirements/lock.txt", "requirements/overrides.txt",
                      "pyproject.toml", "_config.yml", "book/_ext", "tools/build_book.py",
                      "tools/site_wheel.py"]
STAMP = ".fusioncenter-fingerprint"
STATUS = "execution-status.json"
TIMEOUT = 1800  # as _config.yml execute.timeout
#: Chapters started first, longest first (seconds of a fresh paper build on an idle 2-core
#: machine, issue 16), so that the lanes finish together; the others follow in table-of-contents
#: order. ``reading`` gathers the entries of results, vector and nonlinear: it runs last
#: (:data:`LAST`), when they are in the compute cache, instead of waiting on their locks.
LONGEST = ("book/zheng2014/vector",             # 112 s
           "book/zheng2014/results",            # 109 s
           "book/zheng2014/nonlinear",          # 86 s
           "book/zheng2014/likelihood",         # 43 s
           "book/synthesis/one-problem",        # 40 s
           "book/zheng2014/particle-filter",    # 38 s
           "book/mo2015/event-kf",              # 35 s
           "book/leong2011/fading",             # 30 s
           "book/dey2009/vector",               # 24 s
           "book/dey2009/multisensor",          # 21 s
           "book/leong2011/allocation",         # 19 s
           "book/zheng2014/censoring-kl")       # 17 s
LAST = ("book/zheng2014/reading",)
#: The prefix of the lines a ``--serve`` worker answers with (anything else on its standard
#: output, e.g. printed by a kernel's C library, is passed over).
RESULT = "@@build_book-result "

_STAGE = ["preparing"]


def fingerprint(profile: str, edition: str = "instructor") -> str:
    h = hashlib.sha256(f"profile={profile}\nedition={edition}\n".encode())
    for rel in FINGERPRINT_INPUTS:
        path = ROOT / rel
        if not path.exists():
            h.update(f"{rel}: missing\0".encode())
            continue
        files = sorted(p for p in path.rglob("*") if p.is_file()) if path.is_dir() else [path]
        for f in files:
            if "__pycache__" in f.parts or f.suffix == ".pyc" or ".egg-info" in str(f):
                continue
            h.update(str(f.relative_to(ROOT)).encode() + b"\0" + f.read_bytes() + b"\0")
    return h.hexdigest()


def prepare(out: Path, profile: str, edition: str = "instructor") -> str:
    """Wipe ``out/_build`` unless its fingerprint is current; remove the fingerprint (it is
    written back by :func:`finish` after a successful build). Returns the fingerprint."""
    build = out / "_build"
    stamp = build / STAMP
    want = fingerprint(profile, edition)
    have = stamp.read_text().strip() if stamp.exists() else None
    if have != want and build.exists():
        why = "inputs changed since" if have else "no record of a finished"
        print(f"build_book: {why} {profile} build; removing {build.relative_to(ROOT)} "
              f"(HTML, doctrees, execution and compute caches)", file=sys.stderr)
        for child in build.iterdir():
            if out == ROOT and child.name in ("fast", "test-reports", "student",
                                              "fast-student"):
                continue  # the fast build and test reports live in the paper build's folder
            shutil.rmtree(child) if child.is_dir() else child.unlink()
    build.mkdir(parents=True, exist_ok=True)
    stamp.unlink(missing_ok=True)
    return want


def finish(out: Path, want: str) -> None:
    (out / "_build" / STAMP).write_text(want + "\n")


# ------------------------------------------------------------------------------ execution
def _read(path: Path):
    from myst_nb.core.read import myst_nb_reader_plugin

    return myst_nb_reader_plugin(str(path))


#: A kernel that dies before answering its first request ran none of the chapter: most often
#: it lost a race for a TCP port with another kernel started at the same moment ("Address
#: already in use": two lanes, nbval and the tests all start kernels). Such a start is retried.
KERNEL_START_RETRIES = 2


def _kernel_never_started(err, nb) -> bool:
    """Did the execution fail (``err``) before the kernel ran any cell (a failed start)?"""
    return (isinstance(err, RuntimeError) and "Kernel died before replying" in str(err)
            and not any(c.get("execution_count") for c in nb.cells if c.cell_type == "code"))


def execute_one(src: Path, dest: Path, kernel_name: str | None = None) -> dict:
    """Execute ``src`` as myst-nb would (in its folder, in a new kernel) into ``dest``; returns
    ``{"seconds", "error", "traceback"}`` (``error`` the exception's name, or ``None``).
    ``kernel_name``: the kernelspec to run it with (:func:`serve`: the forked kernels of
    tools/kernel_fork.py); nbclient leaves the notebook's kernelspec metadata as it was."""
    import kernel_fork
    import nbformat
    from jupyter_cache.executors.utils import single_nb_execution

    # the kernel on IPC sockets, not loopback TCP (kernel_fork.LOCAL_KERNELS)
    extra = {"config": kernel_fork.local_kernel_config()}
    if kernel_name:
        extra["kernel_name"] = kernel_name
    for attempt in range(1 + KERNEL_START_RETRIES):
        nb = _read(src)
        try:
            res = single_nb_execution(nb, cwd=str(src.parent), timeout=TIMEOUT,
                                      allow_errors=False, meta_override=True, **extra)
        except RuntimeError as exc:
            # jupyter-cache passes on what the kernel's start raises (it keeps only the cells'
            # errors): the same lost race, seen in a fresh paper build ("Address already in
            # use", then "Kernel died before replying to kernel_info")
            err = exc
            if not _kernel_never_started(err, nb) or attempt == KERNEL_START_RETRIES:
                raise
        else:
            err = res.err
            if not _kernel_never_started(err, nb) or attempt == KERNEL_START_RETRIES:
                break
        print(f"build_book: {src.name}: the kernel died before it answered ({err}); "
              "starting a new one", file=sys.stderr, flush=True)
    nbformat.write(nb, str(dest))
    return {"seconds": res.time, "error": type(res.err).__name__ if res.err else None,
            "traceback": res.exc_string}


def serve() -> int:
    """Child process of one execution lane: for each line ``{"src", "dest"}`` read from standard
    input, execute that chapter (:func:`execute_one`, a new kernel each time) and print one line
    :data:`RESULT` + JSON. One such process runs a lane's chapters one after another, so that
    myst-nb and jupyter-cache are imported once per lane (about 3 s each time), not per chapter.

    Each kernel is forked from a warm process of the lane that has imported the chapters'
    libraries once (tools/kernel_fork.py, as nbval's kernels in ``make test``): a new kernel
    process spends 2 to 6 s of CPU on those imports, 29 times per build. A kernel whose
    environment differs from the warm process's starts as a new process (kernel_fork's
    fallback), and so does every kernel if the warm process cannot start."""
    import kernel_fork

    with contextlib.ExitStack() as stack:
        kernel_name = None
        try:
            tmp = Path(stack.enter_context(tempfile.TemporaryDirectory()))
            stack.enter_context(kernel_fork.warm_kernels(tmp))
            kernel_name = kernel_fork.KERNEL_NAME
        except RuntimeError as exc:
            print(f"build_book: no forked kernels ({exc}); each chapter starts a new process",
                  file=sys.stderr, flush=True)
        return _serve_lines(kernel_name)


def _serve_lines(kernel_name: str | None) -> int:
    for line in sys.stdin:
        if not line.strip():
            continue
        req = json.loads(line)
        try:
            info = execute_one(Path(req["src"]), Path(req["dest"]), kernel_name)
        except Exception as exc:  # noqa: BLE001 (reported to the parent as the chapter's error)
            import traceback

            info = {"seconds": None, "error": type(exc).__name__,
                    "traceback": traceback.format_exc()}
        print(RESULT + json.dumps(info), flush=True)
    return 0


def adopt(cache, doc: str, src: Path, nb, executed: Path, profile: str) -> dict | None:
    """Store the chapter's execution by nbval (``make test``: ``tests/golden/conftest.py``
    writes ``executed/<golden name>.ipynb`` for each reference notebook whose cells all passed)
    in the execution cache, if its code cells are the chapter's, cell for cell; the chapter's
    own notebook ``nb`` (as myst-nb reads it: its markdown, tags and cache key) gets their
    outputs. Returns the status row, or ``None`` (no such execution, or other code: the
    chapter is then executed here)."""
    import nbformat
    from chapters import golden_path
    from jupyter_cache.base import CacheBundleIn

    path = executed / golden_path(doc).name
    if not path.is_file():
        return None
    ran = nbformat.read(str(path), as_version=4)
    meta = ran.metadata.get("fusioncenter_nbval") or {}
    mine = [c for c in nb.cells if c.cell_type == "code"]
    theirs = [c for c in ran.cells if c.cell_type == "code"]
    if meta.get("profile") != profile or [c.source for c in mine] != \
            [c.source for c in theirs]:
        print(f"build_book: {doc}: nbval's execution does not match the chapter; executing it",
              file=sys.stderr, flush=True)
        return None
    for cell, done in zip(mine, theirs, strict=True):
        cell.outputs = done.outputs
        cell.execution_count = done.execution_count
    cache.cache_notebook_bundle(
        CacheBundleIn(nb, str(src), data={"execution_seconds": meta.get("seconds"),
                                          "executed_by": "nbval"}),
        check_validity=False, overwrite=True)
    return {"doc": doc, "profile": profile, "seconds": meta.get("seconds"), "from_cache": False,
            "by": "nbval", "executed": meta.get("executed") or
            dt.datetime.now().isoformat(timespec="seconds"), "status": "ok"}


def preexecute(out: Path, profile: str, env: dict, jobs: int,
               executed: Path | None = None) -> tuple[list[dict], list[str]]:
    """Execute the chapters missing from the cache, ``jobs`` at a time (with ``executed``,
    first adopt nbval's executions from that folder: :func:`adopt`). Returns the status rows
    (one per notebook chapter) and the failed chapters."""
    import nbformat
    from jupyter_cache import get_cache
    from jupyter_cache.base import CacheBundleIn

    sys.path.insert(0, str(ROOT / "tools"))
    from chapters import notebook_chapters, source

    cache = get_cache(str(out / "_build" / ".jupyter_cache"))
    docs = notebook_chapters()
    rows: dict[str, dict] = {}
    todo = []
    for doc in docs:
        src = source(doc)
        nb = _read(src)
        try:
            rec = cache.match_cache_notebook(nb)
        except KeyError:
            row = adopt(cache, doc, src, nb, executed, profile) if executed else None
            if row is None:
                todo.append(doc)
            else:
                rows[doc] = row
            continue
        rows[doc] = {"doc": doc, "profile": profile, "seconds": rec.data.get("execution_seconds"),
                     "from_cache": True, "executed": rec.created.isoformat(timespec="seconds"),
                     "status": "ok"}
    todo.sort(key=lambda d: (d in LAST, LONGEST.index(d) if d in LONGEST else len(LONGEST),
                             docs.index(d)))
    adopted = sum(1 for r in rows.values() if r.get("by") == "nbval")
    print(f"build_book: execution: {len(docs) - len(todo) - adopted} of {len(docs)} chapters "
          f"cached, {adopted} executed by nbval, executing {len(todo)} with {jobs} worker(s)",
          file=sys.stderr, flush=True)
    lock = threading.Lock()
    failed: list[str] = []
    reports = out / "_build" / "reports"

    queue = list(todo)  # taken from the front by the lanes, under ``lock``

    def record(doc: str, src: Path, dest: Path, info: dict, rc: int | None, wall: float) -> None:
        ok = rc is None and dest.exists() and not info.get("error")
        row = {"doc": doc, "profile": profile,
               "seconds": info.get("seconds") if info.get("seconds") is not None else wall,
               "from_cache": False,
               "executed": dt.datetime.now().isoformat(timespec="seconds"),
               "status": "ok" if ok else f"failed ({info.get('error') or f'exit {rc}'})"}
        with lock:
            if ok:
                nb = nbformat.read(str(dest), as_version=4)
                cache.cache_notebook_bundle(
                    CacheBundleIn(nb, str(src), data={"execution_seconds": row["seconds"]}),
                    check_validity=False, overwrite=True)
            else:
                failed.append(doc)
                reports.mkdir(parents=True, exist_ok=True)
                rep = reports / (doc.replace("/", "__") + ".log")
                rep.write_text(info.get("traceback") or f"exit code {rc}\n")
                print(f"build_book: {doc} FAILED ({row['status']}); traceback: {rep}\n"
                      + (info.get("traceback") or "")[-3000:], file=sys.stderr, flush=True)
            rows[doc] = row
            print(f"build_book:   {doc}: {row['status']} in {row['seconds']:.1f} s",
                  file=sys.stderr, flush=True)

    def lane(number: int) -> None:
        """One lane: a ``--serve`` child executing the next chapter of the queue until it is
        empty; a child that dies (the chapter's status says its exit code) is replaced."""
        proc = None
        cmd = [sys.executable, str(Path(__file__).resolve()), "--serve"]
        with tempfile.TemporaryDirectory() as tmp:
            while True:
                with lock:
                    if not queue:
                        break
                    doc = queue.pop(0)
                src, dest = source(doc), Path(tmp) / (doc.replace("/", "__") + ".ipynb")
                dest.unlink(missing_ok=True)
                t0 = time.perf_counter()
                if proc is None:
                    proc = procs.start(f"execute lane {number}", cmd, cwd=ROOT, env=env,
                                       stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
                    if proc is None:  # interrupted
                        return
                procs.rename(proc, f"execute {doc}")
                info, rc = {}, None
                try:
                    proc.stdin.write(json.dumps({"src": str(src), "dest": str(dest)}) + "\n")
                    proc.stdin.flush()
                    for line in proc.stdout:
                        if line.startswith(RESULT):
                            info = json.loads(line[len(RESULT):])
                            break
                    else:
                        raise EOFError
                except (BrokenPipeError, EOFError):
                    rc = procs.wait(proc)
                    proc = None
                record(doc, src, dest, info, rc, time.perf_counter() - t0)
            if proc is not None:
                proc.stdin.close()
                procs.wait(proc)

    with ThreadPoolExecutor(max(1, jobs)) as pool:
        list(pool.map(lane, range(max(1, jobs))))
    return [rows[d] for d in docs if d in rows], failed


def write_status(out: Path, profile: str, rows: list[dict], times: dict) -> Path:
    path = out / "_build" / STATUS
    path.write_text(json.dumps({
        "profile": profile, "built": dt.datetime.now().isoformat(timespec="seconds"),
        "jobs": times.get("jobs"), "stages": {k: v for k, v in times.items() if k != "jobs"},
        "chapters": rows}, indent=1) + "\n")
    return path


# ------------------------------------------------------------------------------ main
def one_blas_thread(env: dict) -> None:
    """One BLAS thread in each kernel of the lanes (a variable already set is kept).

    With two lanes the cores are busy; a kernel's OpenBLAS still starts a thread per core, and
    its threads then wait on each other: zheng2014-fig6 (paper profile) took 36.4 s in a fresh
    build against 17.6 s when it happened to run alone, and alone it burns 33.0 s of CPU for
    23.0 s of wall against 21.8 s for 22.6 s on one thread. The pool workers of
    :mod:`fusioncenter.context` already run on one BLAS thread (these variables:
    :data:`fusioncenter.context.THREAD_VARS`). A paper build's registry data are the same bits
    either way, except SciPy SLSQP's gap to the closed form in leong2011-fig3a/3b/4a/4b
    (``solver_rel_gap``, about 1e-14), whose last bits depend on the thread count.
    """
    from fusioncenter.context import THREAD_VARS

    for k in THREAD_VARS:
        if not env.get(k, "").strip():
            env[k] = "1"


def bytecode_env(env: dict, out: Path) -> None:
    """Let the build's processes keep the bytecode of what they import.

    Every chapter runs in a new kernel, and the heavy ones start two worker processes: some
    60 processes import NumPy, SciPy, SymPy, Matplotlib, IPython and the library. The
    environment installs no bytecode (uv does not compile by default), so with
    ``PYTHONDONTWRITEBYTECODE`` set (as in many container images) each of them compiled those
    sources again: about 4.5 s of CPU per kernel (6.5 s against 2.0 s for the imports of a
    chapter). The children therefore write bytecode, into ``PYTHONPYCACHEPREFIX`` (unless set
    already): the environment's ``pycache`` folder (``out/_build/pycache`` outside a virtual
    environment), never next to the sources. Python checks each file against its source's
    modification time and size, so nothing stale is ever run.
    """
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    if not env.get("PYTHONPYCACHEPREFIX", "").strip():
        venv = sys.prefix != sys.base_prefix
        env["PYTHONPYCACHEPREFIX"] = str(Path(sys.prefix) / "pycache" if venv
                                         else out / "_build" / "pycache")


def _on_interrupt(out: Path):
    def handler(signum: int, stages: list[str]) -> None:
        (out / "_build" / STAMP).unlink(missing_ok=True)
        name = signal.Signals(signum).name
        print(f"\nbuild_book: {name}: interrupted during the {_STAGE[0]} stage"
              + (f" ({', '.join(stages)})" if stages else "")
              + "; every child stopped, no fingerprint written (the next build starts clean)",
              file=sys.stderr, flush=True)
        os._exit(procs.exit_code(signum))

    return handler


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--profile", choices=sorted(OUTPUTS))
    ap.add_argument("--strict", action="store_true",
                    help="nitpicky, warnings are errors (-n -W --keep-going)")
    ap.add_argument("--jobs", type=int, default=None,
                    help="chapters executed at once (default: the number of cores)")
    ap.add_argument("--serve", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--compute-cache", metavar="DIR", default=None,
                    help="share registry results through DIR instead of the build's own "
                         "folder (make test: one folder for the site build and nbval, emptied "
                         "at the start of the run)")
    ap.add_argument("--executed", metavar="DIR", default=None,
                    help="take each chapter's execution from DIR/<golden name>.ipynb where "
                         "nbval wrote one whose code cells are the chapter's (make test: "
                         "tests/golden/conftest.py); execute the others")
    ap.add_argument("--edition", choices=["instructor", "student"], default="instructor",
                    help="student: leave the exercises' solutions out (FUSIONCENTER_EDITION)")
    args = ap.parse_args(argv)
    if args.serve:
        return serve()
    if args.profile is None:
        ap.error("--profile is required")
    jobs = args.jobs or len(os.sched_getaffinity(0))
    if jobs < 1:
        ap.error("--jobs must be >= 1")

    out = (STUDENT_OUTPUTS if args.edition == "student" else OUTPUTS)[args.profile]
    procs.install_handlers(_on_interrupt(out))
    t_all = time.perf_counter()
    want = prepare(out, args.profile, args.edition)
    # registry results are shared between chapters through a folder that prepare() wipes with
    # the rest of the build when the fingerprint changes
    # FUSIONCENTER_STATIC_FIGURES: explorable figures are the static page's slider, never an
    # ipywidgets slider a built page could not move (fusioncenter.explore)
    env = dict(os.environ, FUSIONCENTER_PROFILE=args.profile, PYTHONHASHSEED="0",
               FUSIONCENTER_EDITION=args.edition, FUSIONCENTER_STATIC_FIGURES="1",
               FUSIONCENTER_COMPUTE_CACHE=str(Path(args.compute_cache).resolve()
                                              if args.compute_cache else
                                              out / "_build" / "compute-cache"))
    bytecode_env(env, out)
    if jobs > 1 and not env.get("FUSIONCENTER_EXECUTOR", "").strip():
        env["FUSIONCENTER_EXECUTOR"] = "serial"  # the lanes use the cores (module docstring)
    if jobs > 1:
        one_blas_thread(env)
    times: dict = {"jobs": jobs}

    # the library's wheel, which the site carries (_wheels/: the downloaded notebooks' install
    # cell falls back to it), is built beside the execution stage: no wall time added
    wheel: dict = {}

    def _build_wheel() -> None:
        try:
            wheel["path"] = site_wheel.build_wheel(out / "_build" / "wheel", run=procs.run)
        except (OSError, subprocess.CalledProcessError) as exc:
            wheel["error"] = exc

    wheel_thread = threading.Thread(target=_build_wheel, daemon=True)
    wheel_thread.start()

    _STAGE[0] = "execution"
    t0 = time.perf_counter()
    rows, failed = preexecute(out, args.profile, env, jobs,
                              Path(args.executed).resolve() if args.executed else None)
    times["execution_s"] = round(time.perf_counter() - t0, 1)
    write_status(out, args.profile, rows, times)
    if failed:
        print(f"build_book: FAILED: {len(failed)} chapter(s) raised: {', '.join(failed)}",
              file=sys.stderr)
        return 1

    _STAGE[0] = "rendering"
    jb = Path(sys.executable).with_name("jupyter-book")
    # -q: Sphinx's warnings (errors under --strict) and jupyter-book's summary, not its
    # progress through each of the ~115 files for reading and again for writing
    cmd = [str(jb), "build", str(ROOT), "--path-output", str(out), "--builder", "html", "-q"]
    if args.strict:
        cmd += ["-n", "-W", "--keep-going"]
    print("build_book:", " ".join(cmd), file=sys.stderr, flush=True)
    t0 = time.perf_counter()
    rc = procs.run("jupyter-book", cmd, cwd=ROOT, env=env)
    times["rendering_s"] = round(time.perf_counter() - t0, 1)
    times["total_s"] = round(time.perf_counter() - t_all, 1)
    write_status(out, args.profile, rows, times)
    index = out / "_build" / "html" / "index.html"
    if rc != 0:
        reports = out / "_build" / "html" / "reports"
        print(f"build_book: FAILED (exit {rc}); execution reports, if any: {reports}",
              file=sys.stderr)
        return rc if rc > 0 else 1
    if not index.exists():
        print(f"build_book: FAILED: {index} was not written", file=sys.stderr)
        return 1
    wheel_thread.join()
    if "error" in wheel:
        print(f"build_book: FAILED: the library's wheel for the site: {wheel['error']}",
              file=sys.stderr)
        return 1
    site_wheel.publish(wheel["path"], index.parent)
    finish(out, want)
    print(f"build_book: execution {times['execution_s']:.1f} s ({jobs} jobs), rendering "
          f"{times['rendering_s']:.1f} s, total {times['total_s']:.1f} s", file=sys.stderr)
    print(index)
    return 0


if __name__ == "__main__":
    sys.exit(main())
