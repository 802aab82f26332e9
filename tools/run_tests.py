"""Run every test of the project (``make test``) and print one summary line with counts.

    python tools/run_tests.py [--with pythons,student]

Stages (all run; the exit code is 1 if any failed):

1. ruff        lint of src/, tests/, tools/, benchmarks/, book/_ext/
   chapters    ruff on the chapters' code cells, lines of at most 79 characters
               (tools/lint_chapters.py)
   index       the registry's index (src/fusioncenter/figures/_index.json) is current
2. nbval k     strict nbval (``--nbval``) on the executed reference notebooks tests/golden/, in
               two shards, the first longer (:func:`nbval_shards`, :data:`SHARD_1_SHARE`),
               each kernel forked from one process for both shards that has imported the
               chapters' libraries (tools/kernel_fork.py, :class:`Warm`; a kernel whose
               environment differs starts anew); the summary shows that process as the
               line ``kernels``, with the kernels' CPU
3. site build  the book in the ``fast`` profile with ``-n -W --keep-going``, raise_on_error
4. site        the headless-Chromium check of the built site (two browsers side by side:
               tools/browser_check, :data:`BROWSER_CHECK`), which also prints the site as
               one PDF (tools/pdf_book.py's Printer) from the pages it has loaded and checked
5. library     pytest on the library and the repository (not the site, not `slow`)
6. site pages  pytest on the built site but the browser check and the PDF: no external
               resources, the pages as a reader sees them, the downloads
7. lab         a chapter opened in JupyterLab shows its MyST rendered (tests/site/test_lab.py;
               it reads the chapter's source, not the built site)
8. pdf tests   pytest on the PDF (tests/site/test_pdf.py)

and, with ``--with`` (``make test WITH="pythons student"``, what ``.ci/run`` and the GitHub
workflow run), in the same schedule:

9. pythons     the library's tests again on Python 3.12, from the installed wheel, but those
               marked ``heavy`` (``make test-pythons`` runs them all on 3.12 and 3.13)
10. student    three downloaded notebooks run offline in a fresh Python 3.12
               (tools/student_path.py; alone: ``make test-student``)

Without ``--with``, every test in tests/ and every reference notebook runs, on the book's
Python (3.11). Issue 14 lets the other Python's run and the student's path live in a target
that CI runs; the plain ``make test`` leaves them out because they cost 196 s of CPU (122 + 74
in the last fresh run with them), about 100 s on the two cores, and ``make test`` is to take
at most 7 minutes from a fresh clone (issue 16).

Each chapter is executed once: nbval's kernels run the reference notebooks (the chapters'
code, checked by tests/test_golden.py), ``tests/golden/conftest.py`` keeps every notebook whose
cells all passed, with the kernel's outputs, and the site build stores those in its execution
cache when their code cells are the chapter's (``build_book.py --executed``); a chapter nbval
did not pass is executed by the site build itself, which then fails on it as before. Registry
results are shared by the kernels through the run's compute cache
(``FUSIONCENTER_COMPUTE_CACHE``, a folder emptied at the start of every run, as is the folder of
executed notebooks: nothing from an earlier run or another source tree is read).

A skipped test in the site, site-pages and pdf-tests stages counts as a failure: the browser
check may not be skipped.

The lint stages (1.) run beside the others, one after the other in a third thread (5 s); the
stages after them run on two workers (one per core of the 2-core machine), each worker
taking the first stage of the list above whose inputs are ready: the two nbval shards first,
then the site build after both and the browser check (with the PDF) after it, while the
library stage takes the other worker (then, with ``--with``, the 3.12 tests); the site pages,
JupyterLab's test, the pdf tests (and the student's path) go to whichever worker is free first,
so that neither waits idle for the other at the end. (JupyterLab's test, 12 s, is a stage of
its own: in the site pages, 40 s, it left one worker idle for the last 25 s of a fresh run
while the other ran them after its browser check.) The library stage's registry-entry tests
read the entries from the run's compute cache too (``FUSIONCENTER_TEST_SHARED_CACHE``:
tests/figure_helpers.py), instead of computing them again. Output goes to
``_build/test-reports/<stage>.log`` and is printed whole when the stage ends; each stage
reports its wall and CPU seconds (the CPU of its process tree as ``wait4`` counts it: a
process orphaned before it ends is not counted, such as Chromium's renderers when the browser
closes, so the site stage counts too little; the forked kernels are reaped by their warm
process and count as its, the line ``kernels``).
``FUSIONCENTER_TEST_LANES=1`` runs the stages one after the other, in that order, nbval in one
shard.

Ctrl-C or SIGTERM stops every running stage with its whole process tree (kernels, jupyter-book,
pytest workers: see ``tools/procs.py``), starts no further stage, prints which stages were
interrupted and exits 130 (SIGINT) or 143 (SIGTERM). The interrupted site build leaves no
fingerprint, so the next run builds it from scratch.
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import kernel_fork  # noqa: E402
import procs  # noqa: E402
from build_book import bytecode_env, one_blas_thread  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
PY = sys.executable
REPORTS = ROOT / "_build" / "test-reports"


@dataclass
class Stage:
    name: str
    ok: bool
    seconds: float
    passed: int = 0
    failed: int = 0
    skipped: int = 0
    cpu: float | None = None  # user + system seconds of the stage's process tree


def _junit_counts(path: Path) -> tuple[int, int, int]:
    if not path.exists():
        return 0, 0, 0
    root = ET.parse(path).getroot()
    suites = [root] if root.tag == "testsuite" else root.findall("testsuite")
    tests = sum(int(s.get("tests", 0)) for s in suites)
    failed = sum(int(s.get("failures", 0)) + int(s.get("errors", 0)) for s in suites)
    skipped = sum(int(s.get("skipped", 0)) for s in suites)
    return tests - failed - skipped, failed, skipped


_PRINT = threading.Lock()


def run(name: str, cmd: list[str], *, junit: Path | None = None, env: dict | None = None,
        skips_fail: bool = False, log: bool = False) -> Stage:
    """Run one stage; with ``log`` its output goes to a file, printed whole when it ends."""
    with _PRINT:
        print(f"\n===== {name}: {' '.join(cmd)}", flush=True)
    t0 = time.perf_counter()
    env = {**os.environ, **(env or {})}
    if log:
        path = REPORTS / f"{name.replace(' ', '-')}.log"
        with path.open("w") as fh:
            rc, cpu = procs.run_timed(name, cmd, cwd=ROOT, env=env, stdout=fh,
                                      stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL)
        with _PRINT:
            print(f"\n===== {name}: output ({path.relative_to(ROOT)})", flush=True)
            sys.stdout.write(path.read_text(errors="replace"))
            sys.stdout.flush()
    else:
        rc, cpu = procs.run_timed(name, cmd, cwd=ROOT, env=env, stdin=subprocess.DEVNULL)
    dt = time.perf_counter() - t0
    stage = Stage(name, rc == 0, dt, cpu=cpu)
    if junit is not None:
        stage.passed, stage.failed, stage.skipped = _junit_counts(junit)
        if rc != 0 and stage.failed == 0:
            stage.failed = 1  # collection error, crash or "no tests ran"
        if skips_fail and stage.skipped:
            stage.ok = False
            print(f"{name}: {stage.skipped} skipped test(s) count as failures here", flush=True)
    else:
        stage.passed, stage.failed = (1, 0) if rc == 0 else (0, 1)
    with _PRINT:
        print(f"===== {name}: {'ok' if stage.ok else 'FAILED'} in {dt:.1f} s"
              + (f" ({cpu:.1f} s CPU)" if cpu is not None else ""), flush=True)
    return stage


@dataclass
class Job:
    """A stage to schedule: ``fn`` runs it; it starts once every stage in ``after`` has ended."""
    name: str
    fn: object
    after: tuple[str, ...] = ()


def schedule(jobs: list[Job], workers: int) -> list[Stage]:
    """Run ``jobs`` on ``workers`` threads: each free worker takes the first job, in list
    order, whose ``after`` stages have all ended (passed or failed: every stage runs and
    reports). Returns the stages in list order."""
    done: dict[str, Stage] = {}
    todo = list(jobs)
    cond = threading.Condition()
    errors: list[BaseException] = []

    def ready():
        return next((j for j in todo if all(a in done for a in j.after)), None)

    def worker():
        while True:
            with cond:
                job = ready()
                while job is None and todo and not errors:
                    cond.wait()
                    job = ready()
                if job is None:
                    return
                todo.remove(job)
            try:
                stage = job.fn()
            except BaseException as exc:  # reported below: a crashed stage fails the run
                with cond:
                    errors.append(exc)
                    cond.notify_all()
                return
            with cond:
                done[job.name] = stage
                cond.notify_all()

    threads = [threading.Thread(target=worker) for _ in range(max(1, workers))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    if errors:
        raise errors[0]
    return [done[j.name] for j in jobs]


class Warm:
    """The warm process (tools/kernel_fork.py) whose forks are both nbval shards' kernels,
    started here in :attr:`env`, the shards' environment (the kernels' as nbval starts them:
    this process's, ``extra``, the variables of :func:`kernel_fork.start`, and
    ``PYTEST_VERSION``, which pytest sets in its process). A registered process
    (``tools/procs.py``): an interrupt stops it with the stages. Stopped when the last shard
    ends; :meth:`stop` returns it as a stage ``kernels``: its CPU is the kernels' (the shards'
    CPU is then their pytest processes'), and it fails if it ended before it was stopped."""

    def __init__(self, extra: dict, shards: int) -> None:
        from importlib.metadata import version

        self.tmp = Path(tempfile.mkdtemp(prefix="fusioncenter-fork-"))
        self.env = {**os.environ, **extra, kernel_fork.SHARED_ENV: str(self.tmp),
                    "PYTEST_VERSION": version("pytest")}
        self.t0 = time.perf_counter()
        self.proc = kernel_fork.start(self.tmp, self.env,
                                      popen=lambda cmd, **kw: procs.start("kernels", cmd, **kw))
        self.left, self.lock, self.stage = shards, threading.RLock(), None

    def shard_ended(self) -> None:
        with self.lock:
            self.left -= 1
            if self.left <= 0:
                self.stop()

    def stop(self) -> Stage:
        with self.lock:
            if self.stage is None:
                alive = self.proc.poll() is None
                if alive:
                    self.proc.terminate()
                rc = procs.wait(self.proc)
                self.stage = Stage("kernels", alive, time.perf_counter() - self.t0,
                                   cpu=self.proc.cpu_seconds, failed=int(not alive))
                if not alive:
                    log = (self.tmp / "log").read_text(errors="replace")[-3000:]
                    with _PRINT:
                        print(f"===== kernels: the warm process ended (exit {rc}) before the "
                              f"shards did:\n{log}", flush=True)
                shutil.rmtree(self.tmp, ignore_errors=True)
            return self.stage


#: Seconds of each reference notebook under nbval, kernel and registry entries included (the
#: mean of two fresh ``make test`` runs, 2 lanes, issue 16): what :func:`nbval_shards` splits.
#: A chapter missing here counts as :data:`DEFAULT_SECONDS`.
NBVAL_SECONDS = {
    "book/zheng2014/vector": 19, "book/zheng2014/results": 19, "book/zheng2014/nonlinear": 18,
    "book/synthesis/one-problem": 18, "book/zheng2014/likelihood": 16,
    "book/mo2015/derivation": 14, "book/mo2015/event-kf": 13, "book/leong2011/allocation": 12,
    "book/dey2009/multisensor": 12, "book/dey2009/random-riccati": 11, "book/dey2009/vector": 11,
    "book/leong2011/asymptotics": 11, "book/zheng2014/particle-filter": 9,
    "book/leong2011/fading": 9, "book/mo2015/rate": 9, "book/background/kalman-riccati": 8,
    "book/zheng2014/censoring-kl": 8, "book/leong2011/steady-state": 7,
    "book/dey2009/scalar-bounds": 7, "book/dey2009/distribution": 7, "book/mo2015/trigger": 6,
    "book/mo2015/conditional-mean": 5, "book/zheng2014/reading": 4,
}
DEFAULT_SECONDS = 1
#: Chapters that gather other chapters' registry entries: last in their shard, so that the
#: entries are in the run's compute cache (or being computed, under its lock) by then.
GATHERING = ("book/zheng2014/reading",)
#: With two lanes, shard 1's share of the execution time. The worker whose shard ends first
#: takes the library stage (225 s in a fresh ``make test``); the other waits for both shards,
#: then takes the site build and the browser check with the PDF (50 + 137 s), then the site
#: pages (41 s); the pdf tests (11 s) go to the library worker when it ends first. That chain
#: starts after the later shard: equal shards (both workers ended within 7 s of each other).
SHARD_1_SHARE = 0.5
#: The same with ``--with pythons,student``: the library worker then also takes the 3.12 tests
#: (344 s with the library); the other the site chain and the student's path (312 s). Equal
#: shards (140 s and 140 s) left the second worker ending 32 s after the first (484 s against
#: 452 s); shard 1 longer by that much (0.56 of 280 s) lets both end together. Since the
#: browser check keeps the site's static files cached (199 s for the site stage, was 215 s),
#: 0.56 left the library worker ending about 40 s after the other (478 s against 439 s, shards
#: 119 and 106 s): 0.62 (about 162 and 97 s of the estimates below) moves about 20 s across.
#: With the site pages a stage of their own, both workers still ended together (446 s).
SHARD_1_SHARE_WITH = 0.62
#: The browser check, which also prints the PDF: the site stage. The site's other tests are the
#: site pages stage, which can fill a worker's end while the other still runs a long stage.
BROWSER_CHECK = "tests/site/test_site.py::test_browser_check_of_every_page"
#: Stages that run only when asked for (``--with``): CI asks for both.
OPTIONAL = ("pythons", "student")


def nbval_shards(n: int, shares: tuple[float, ...] | None = None) -> list[list[str]]:
    """The reference notebooks split into ``n`` lists whose execution times are in the ratio
    ``shares`` (default: equal; :data:`SHARD_1_SHARE` for two): longest first, each to the list
    furthest below its share so far; every gathering chapter at the end."""
    from chapters import golden_path, notebook_chapters

    if shares is None:
        shares = (SHARD_1_SHARE, 1 - SHARD_1_SHARE) if n == 2 else (1.0,) * max(1, n)
    if len(shares) != max(1, n) or min(shares) <= 0:
        raise ValueError(f"shares must be {max(1, n)} positive numbers, got {shares!r}")
    docs = sorted(notebook_chapters(), key=lambda d: (d in GATHERING,
                                                      -NBVAL_SECONDS.get(d, DEFAULT_SECONDS)))
    shards: list[list[str]] = [[] for _ in shares]
    load = [0.0] * len(shards)
    for doc in docs:
        k = min(range(len(shards)), key=lambda i: load[i] / shares[i])
        shards[k].append(str(golden_path(doc).relative_to(ROOT)))
        load[k] += NBVAL_SECONDS.get(doc, DEFAULT_SECONDS)
    return [s for s in shards if s]


def _on_interrupt(signum: int, stages: list[str]) -> None:
    name = signal.Signals(signum).name
    with _PRINT:
        print(f"\n===== make test: {name}: interrupted during "
              f"{', '.join(stages) if stages else 'no running stage'}; every child stopped, "
              f"no further stage started", flush=True)
    os._exit(procs.exit_code(signum))


def _optional(argv: list[str]) -> set[str]:
    """The stages ``--with a,b`` (or ``--with "a b"``) asks for; ValueError naming ``--with``
    on anything else."""
    wanted: set[str] = set()
    args = list(argv)
    while args:
        arg = args.pop(0)
        if arg == "--with" and args:
            value = args.pop(0)
        elif arg.startswith("--with="):
            value = arg.split("=", 1)[1]
        else:
            raise ValueError(f"unknown argument {arg!r}; usage: run_tests.py "
                             f"[--with {','.join(OPTIONAL)}]")
        wanted |= {w for w in value.replace(",", " ").split() if w}
    unknown = sorted(wanted - set(OPTIONAL))
    if unknown:
        raise ValueError(f"--with: unknown stage(s) {unknown}; the optional stages are "
                         f"{list(OPTIONAL)}")
    return wanted


def main(argv: list[str] | None = None) -> int:
    try:
        extra = _optional(sys.argv[1:] if argv is None else argv)
    except ValueError as exc:
        print(f"make test: {exc}", file=sys.stderr)
        return 2
    procs.install_handlers(_on_interrupt)
    REPORTS.mkdir(parents=True, exist_ok=True)
    # matplotlib's font cache of this clone's venv, not the user's: a stale ~/.cache/matplotlib
    # (left by a deleted venv) loses matplotlib's own fonts, and nbval fails on the warning
    os.environ["MPLCONFIGDIR"] = str(REPORTS / "mplconfig")
    # every stage's processes (pytest, kernels, pool workers, the other Pythons' venvs) keep
    # the bytecode they compile, in the environment's pycache: with PYTHONDONTWRITEBYTECODE
    # set, as on this machine, each of them compiled NumPy, SciPy, SymPy... again
    bytecode_env(os.environ, ROOT)
    fast = {"FUSIONCENTER_PROFILE": "fast", "PYTHONHASHSEED": "0",
            "FUSIONCENTER_STATIC_FIGURES": "1"}  # outputs as on the site (fusioncenter.explore)
    # without the pytest plugins a stage does not use: loading them cost 4.5 s of CPU in every
    # pytest process (nbval imports nbformat, whose jsonschema builds rfc3987_syntax's 38
    # parsers; hypothesis's plugin; anyio's), 0.5 s without (``--co`` of tests/site/test_pdf.py)
    pytest = [PY, "-m", "pytest", "-p", "no:cacheprovider", "-p", "no:anyio"]
    lean = [*pytest, "-p", "no:hypothesispytest"]  # no test of these stages uses hypothesis
    site_pytest = [*lean, "-p", "no:nbval"]
    site = ROOT / "_build" / "fast" / "_build" / "html"
    pdf = site.parent / "pdf" / "book.pdf"  # printed by the browser check (tests/site)
    pdf.unlink(missing_ok=True)  # the pdf tests never read an earlier run's
    t0 = time.perf_counter()
    parallel = os.environ.get("FUSIONCENTER_TEST_LANES", "2") != "1"
    if parallel:
        # two stages keep both cores busy: each process's BLAS on one thread (as the book
        # build's lanes: build_book.one_blas_thread), not a thread per core waiting on the other
        one_blas_thread(os.environ)

    # the registry results of this run, shared by nbval's kernels (and the site build's, for
    # a chapter it executes itself); the chapters as nbval executed them, for the site build
    cache = REPORTS / "compute-cache"
    executed = REPORTS / "nbval-executed"
    for folder in (cache, executed):
        shutil.rmtree(folder, ignore_errors=True)
        folder.mkdir(parents=True)
    shared = {**fast, "FUSIONCENTER_COMPUTE_CACHE": str(cache),
              "FUSIONCENTER_NBVAL_EXECUTED": str(executed)}
    share = SHARD_1_SHARE_WITH if "pythons" in extra else SHARD_1_SHARE
    shards = nbval_shards(2, (share, 1 - share)) if parallel else nbval_shards(1)
    # one warm process (tools/kernel_fork.py) for the shards' kernels, started now: its
    # imports (9 s of CPU on a fresh clone) overlap the shards' start, once instead of in each
    warm = Warm(shared, len(shards))

    def nbval(k: int, notebooks: list[str]) -> Job:
        name, xml = f"nbval {k}", REPORTS / f"nbval-{k}.xml"

        def fn() -> Stage:
            try:
                return run(name, [*lean, "--nbval", "--nbval-kernel-name",
                                  kernel_fork.KERNEL_NAME, "--nbval-sanitize-with",
                                  "tests/golden/sanitize.cfg", *notebooks, f"--junitxml={xml}"],
                           junit=xml, env=warm.env, log=parallel)
            finally:
                warm.shard_ended()

        return Job(name, fn)

    jobs = [
        *(nbval(k, nb) for k, nb in enumerate(shards, 1)),
        Job("site build", lambda: run(
            "site build", [PY, "tools/build_book.py", "--profile", "fast", "--strict",
                           "--compute-cache", str(cache), "--executed", str(executed)],
            log=parallel), after=tuple(f"nbval {k}" for k in range(1, len(shards) + 1))),
        Job("site", lambda: run(
            "site", [*site_pytest, BROWSER_CHECK, "-m", "site",
                     f"--junitxml={REPORTS / 'site.xml'}"],
            junit=REPORTS / "site.xml", env={**fast, "FUSIONCENTER_SITE": str(site),
                                              "FUSIONCENTER_PDF_OUT": str(pdf)},
            skips_fail=True, log=parallel), after=("site build",)),
        Job("library", lambda: run(
            "library", [*pytest, "-p", "no:nbval", "tests", "-m", "not site and not slow",
                        "--ignore=tests/golden",
                        f"--junitxml={REPORTS / 'library.xml'}"],
            junit=REPORTS / "library.xml", env={**fast, "FUSIONCENTER_TEST_SHARED_CACHE":
                                                 str(cache)}, log=parallel)),
        Job("pythons", lambda: run("pythons", [PY, "tools/test_pythons.py", "--quick", "3.12"],
                                   log=parallel)),
        Job("site pages", lambda: run(
            "site pages", [*site_pytest, "tests/site", "-m", "site",
                           "--ignore=tests/site/test_pdf.py", "--ignore=tests/site/test_lab.py",
                           f"--deselect={BROWSER_CHECK}",
                           f"--junitxml={REPORTS / 'site-pages.xml'}"],
            junit=REPORTS / "site-pages.xml", env={**fast, "FUSIONCENTER_SITE": str(site)},
            skips_fail=True, log=parallel), after=("site build",)),
        Job("lab", lambda: run(
            "lab", [*site_pytest, "tests/site/test_lab.py", "-m", "site",
                    f"--junitxml={REPORTS / 'lab.xml'}"],
            junit=REPORTS / "lab.xml", env=fast, skips_fail=True, log=parallel)),
        Job("pdf tests", lambda: run(
            "pdf tests", [*site_pytest, "tests/site/test_pdf.py", "-m", "site",
                          f"--junitxml={REPORTS / 'pdf-tests.xml'}"],
            junit=REPORTS / "pdf-tests.xml", env={**fast, "FUSIONCENTER_SITE": str(site)},
            skips_fail=True, log=parallel), after=("site",)),
        Job("student", lambda: run("student", [PY, "tools/student_path.py", "--site", str(site)],
                                   log=parallel), after=("site build",)),
    ]
    jobs = [j for j in jobs if j.name not in OPTIONAL or j.name in extra]
    lint = [("ruff", [PY, "-m", "ruff", "check", "src", "tests", "tools", "benchmarks",
                      "book/_ext"]),
            ("chapters", [PY, "tools/lint_chapters.py"]),
            ("index", [PY, "-m", "fusioncenter.figures", "--check"])]
    try:
        if parallel:
            # the lint (5 s on one core) beside the nbval shards rather than before them, with a
            # core idle: a third process for 5 s, and the shards start at once
            linted: list[Stage] = []
            failure: list[BaseException] = []

            def lint_all() -> None:
                try:
                    linted.extend(run(name, cmd, log=True) for name, cmd in lint)
                except BaseException as exc:  # re-raised below: a crashed stage fails the run
                    failure.append(exc)

            thread = threading.Thread(target=lint_all)
            thread.start()
            stages = schedule(jobs, 2)
            thread.join()
            if failure:
                raise failure[0]
            stages = linted + stages
        else:
            stages = [run(name, cmd) for name, cmd in lint]
            stages += schedule(jobs, 1)
    finally:  # stopped by the last shard, unless a stage crashed before
        kernels = warm.stop()
    stages.append(kernels)
    total = time.perf_counter() - t0
    print("\n===== make test summary")
    for s in stages:
        cpu = f"{s.cpu:7.1f}" if s.cpu is not None else "      -"
        print(f"  {s.name:<11} {'ok' if s.ok else 'FAILED':<7} {s.seconds:7.1f} s {cpu} s CPU   "
              f"{s.passed} passed, {s.failed} failed, {s.skipped} skipped")
    n_pass = sum(s.passed for s in stages)
    n_fail = sum(s.failed for s in stages) + sum(1 for s in stages if not s.ok and not s.failed)
    n_skip = sum(s.skipped for s in stages)
    bad = [s.name for s in stages if not s.ok]
    cpu = sum(s.cpu or 0.0 for s in stages)
    print(f"  total {total:.1f} s, {cpu:.1f} s CPU; stages failed: "
          f"{', '.join(bad) if bad else 'none'}")
    print(f"summary: {n_pass} passed, {n_fail} failed, {n_skip} skipped")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
