"""zheng2014's heavy registry entries (issue 16 item 3): CPU time per entry, before and after.

Each case computes the registry entries of :data:`SIZES` (paper profile, paper particles,
reduced trials; serial executor, so one process does all the work) in a fresh interpreter with
``PYTHONPATH`` set to a tree's ``src``: this tree ("after") and an older checkout ("before"; its
``src`` directory in the environment variable ``BENCH_BEFORE_SRC``, e.g. ``git worktree add
/tmp/hot-before 0b4a498`` and ``BENCH_BEFORE_SRC=/tmp/hot-before/src``; skipped without it).
It prints, per entry, the CPU seconds of the compute (``time.process_time``: less sensitive
than wall time to the other jobs of a shared machine; the compiled kernels are warmed up
first) and a digest of the entry's data: equal digests before and after mean bit-for-bit
identical data. Then the ratio before / after of the summed CPU time, and the load average.

``python benchmarks/bench_hotpaths.py`` runs both cases once and prints the table.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

HERE_SRC = Path(__file__).resolve().parents[1] / "src"
REPEATS = 1

#: ``(entry, overrides)``: paper particles, reduced trials.
SIZES = (
    ("zheng2014-table1", {"trials": 100}),
    ("zheng2014-fig8", {"trials": 25}),
    ("zheng2014-table3", {"trials": 25}),
)

_SCRIPT = """
import hashlib, json, pickle, sys, time
from fusioncenter import censoring as cs
from fusioncenter.figures import registry
from fusioncenter.figures.zheng2014 import nonlinear as zn
cs.run(cs.LinearScenario(), "cfwmd", l=1.0, n_trials=4, n_particles=50, seed=1)  # warm-up
for s, fb in (("cfwmd", "state"), ("cfwmd", "state+cov"), ("cfomd", "state")):
    cs.run(zn.SCENARIO, s, l=2.0, n_trials=2, n_particles=50, seed=1, feedback=fb)
out = {}
for eid, over in json.loads(sys.argv[1]):
    t0 = time.process_time()
    data = registry.get(eid).run_compute("paper", executor="serial", **over)
    cpu = time.process_time() - t0
    data.pop("_run", None)
    out[eid] = (cpu, hashlib.sha256(pickle.dumps(data, protocol=4)).hexdigest()[:12])
print(json.dumps(out))
"""


def measure(src: str) -> dict:
    """``{entry: (cpu seconds, digest)}`` computed with the library in ``src``."""
    env = dict(os.environ, PYTHONPATH=src, FUSIONCENTER_COMPUTE_CACHE="")
    res = subprocess.run([sys.executable, "-c", _SCRIPT, json.dumps(SIZES)], env=env,
                         check=True, capture_output=True, text=True)
    return json.loads(res.stdout.strip().splitlines()[-1])


def report(before: dict | None, after: dict) -> None:
    """Print the per-entry table and the ratio of the summed CPU times."""
    for eid, _ in SIZES:
        a = after[eid]
        if before is None:
            print(f"  {eid:<20} after {a[0]:7.1f} s CPU  {a[1]}")
            continue
        b = before[eid]
        same = "identical" if a[1] == b[1] else "DIFFERENT"
        print(f"  {eid:<20} before {b[0]:7.1f} s  after {a[0]:7.1f} s CPU  x{b[0] / a[0]:.2f}"
              f"  data {same} ({a[1]})")
    if before is not None:
        tb, ta = sum(v[0] for v in before.values()), sum(v[0] for v in after.values())
        print(f"  total before {tb:.1f} s, after {ta:.1f} s CPU: x{tb / ta:.2f}")
    print(f"  load average {os.getloadavg()[0]:.2f}")


def _case():
    def call():
        old = os.environ.get("BENCH_BEFORE_SRC")
        before = measure(old) if old else None
        if before is None:
            print("  [before] skipped (set BENCH_BEFORE_SRC)")
        report(before, measure(str(HERE_SRC)))
    return call


CASES = [("zheng2014 heavy entries, paper particles, reduced trials, serial", "before/after",
          _case)]

if __name__ == "__main__":
    _case()()
