"""Time a clean build of the book, bootstrap included, with the split of its stages.

    python benchmarks/bench_book.py                      # paper profile, fresh clone, fresh venv
    python benchmarks/bench_book.py --profile fast       # the test build instead
    python benchmarks/bench_book.py --venv .venv         # reuse an environment (no bootstrap)
    python benchmarks/bench_book.py --keep /work/b2      # keep the clone and its venv there

What ``make book`` does on a fresh machine: the working tree's committed state (``git clone`` of
HEAD into a temporary folder, so no ``_build`` and no caches), ``tools/bootstrap.sh`` into a new
virtual environment (pip's own download cache is not cleared: the packages are not
re-downloaded, they are re-installed), then ``tools/build_book.py``. The stages are:

* ``bootstrap``: creating the environment from ``requirements/lock.txt``;
* ``execution``: executing every chapter into the execution cache (in parallel, one per core);
* ``rendering``: ``jupyter-book build`` from the cache;

the last two as ``tools/build_book.py`` measures them (``_build/execution-status.json``). The
load average before and after is printed with the result: on a shared machine the times are
those of the load, not of an idle machine. The result is also written to
``benchmarks/results/book-<profile>.json``.

This is not a ``CASES`` benchmark (one build takes minutes): ``benchmarks/run.py`` skips it.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CASES: list = []  # nothing for benchmarks/run.py: run this file directly


def _timed(cmd: list[str], **kw) -> float:
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, **kw)
    return time.perf_counter() - t0


def bench(profile: str = "paper", venv: str | None = None, jobs: int | None = None,
          keep: str | None = None) -> dict:
    load0 = os.getloadavg()
    if keep is not None:
        Path(keep).mkdir(parents=True, exist_ok=False)  # a new folder: never over earlier work
    with (contextlib.nullcontext(keep) if keep else
          tempfile.TemporaryDirectory(prefix="bench-book-")) as tmp:
        clone = Path(tmp) / "repo"
        subprocess.run(["git", "clone", "--quiet", str(ROOT), str(clone)], check=True)
        t_all = time.perf_counter()
        if venv is None:
            env_dir = Path(tmp) / "venv"
            boot = _timed(["bash", "tools/bootstrap.sh"], cwd=clone,
                          env=dict(os.environ, VENV=str(env_dir)))
            py = env_dir / "bin" / "python"
            # the clone's own src/ must be the one installed (editable install above)
        else:
            boot = 0.0
            py = Path(venv).resolve() / "bin" / "python"
        cmd = [str(py), "tools/build_book.py", "--profile", profile]
        if jobs:
            cmd += ["--jobs", str(jobs)]
        env = dict(os.environ, PYTHONPATH=str(clone / "src"))
        build = _timed(cmd, cwd=clone, env=env)
        total = time.perf_counter() - t_all
        out = clone if profile == "paper" else clone / "_build" / "fast"
        status = json.loads((out / "_build" / "execution-status.json").read_text())
    chapters = sorted(status["chapters"], key=lambda r: -(r["seconds"] or 0))
    return {
        "profile": profile, "jobs": status["jobs"], "cores": len(os.sched_getaffinity(0)),
        "bootstrap_s": round(boot, 1), "execution_s": status["stages"]["execution_s"],
        "rendering_s": status["stages"]["rendering_s"], "build_s": round(build, 1),
        "total_s": round(total, 1),
        "chapter_seconds_sum": round(sum(r["seconds"] or 0 for r in chapters), 1),
        "longest": [(r["doc"], round(r["seconds"], 1)) for r in chapters[:5]],
        "load_before": load0, "load_after": os.getloadavg(),
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--profile", choices=("fast", "paper"), default="paper")
    ap.add_argument("--venv", default=None, help="reuse this environment (skip the bootstrap)")
    ap.add_argument("--jobs", type=int, default=None)
    ap.add_argument("--keep", default=None, metavar="DIR",
                    help="build in this new folder and keep it (the clone in DIR/repo, the "
                         "environment in DIR/venv), e.g. to look at the built site")
    args = ap.parse_args(argv)
    res = bench(args.profile, args.venv, args.jobs, args.keep)
    prep = res["build_s"] - res["execution_s"] - res["rendering_s"]
    print(json.dumps(res, indent=1))
    print(f"\n[{res['profile']}] total {res['total_s']:.0f} s = bootstrap {res['bootstrap_s']:.0f}"
          f" s + execution {res['execution_s']:.0f} s ({res['jobs']} jobs; the chapters' own "
          f"times add up to {res['chapter_seconds_sum']:.0f} s) + rendering "
          f"{res['rendering_s']:.0f} s (+ {prep:.0f} s of preparation); load average "
          f"{res['load_before'][0]:.2f} before, "
          f"{res['load_after'][0]:.2f} after (1 min) on {res['cores']} cores")
    results = ROOT / "benchmarks" / "results"
    results.mkdir(exist_ok=True)
    (results / f"book-{res['profile']}.json").write_text(json.dumps(res, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
