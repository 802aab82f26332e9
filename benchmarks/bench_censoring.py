"""zheng2014 (Part IV(a)): the CFwMD engine and Fig. 1 at the paper's scale.

Group 1 -- the CFwMD engine: CFwMD with state feedback (N = 2, l = 1), 1024 trials x 1000
particles x 20 steps (2.05e7 particle-steps), one process, ``censoring.run`` of this tree
("after": the fusion centre as a model of the one loop ``particle.run_filter``) against the
same call on an older checkout ("before"; its ``src`` directory in the environment variable
``BENCH_BEFORE_SRC``, e.g. ``git worktree add /tmp/engine-before 21f920c`` and
``BENCH_BEFORE_SRC=/tmp/engine-before/src``; the case is skipped without it). Each runs in its
own interpreter (``PYTHONPATH`` set to the tree's ``src``), best of three after a warm-up, and
prints ns per particle-step in CPU time (less sensitive than wall time to the other jobs of
this 2-core machine) and wall time, and a digest of the per-trial results: equal digests mean
bit-for-bit identical results. Target: after <= 1.1 x before.

Group 2 -- Fig. 1 at the paper's scale: all four schemes (all-send, random selection, CFoMD,
CFwMD), 5000 trials x 1000 particles x 20 steps each (4e8 particle-steps), on a pool of two
processes (``executor`` of ``censoring.run``). Target: <= 30 s wall.

Each case prints the machine's load average: compare minima over repeats, at low load.
"""

from __future__ import annotations

import concurrent.futures
import os
import subprocess
import sys
import time
from pathlib import Path

from fusioncenter import censoring as cs

SC = cs.LinearScenario()
L, SEED, P = 1.0, 2014, 1000
N_ENGINE = 1024
N_PAPER = 5000
HERE_SRC = Path(__file__).resolve().parents[1] / "src"

_ENGINE = f"""
import hashlib, time
from fusioncenter import censoring as cs
sc = cs.LinearScenario()
cs.run(sc, "cfwmd", l={L}, n_trials=64, n_particles={P}, seed=1)  # warm-up (compiled kernels)
best_cpu = best_wall = float("inf")
for _ in range(3):
    t0, c0 = time.perf_counter(), time.process_time()
    res = cs.run(sc, "cfwmd", l={L}, n_trials={N_ENGINE}, n_particles={P}, seed={SEED})
    best_wall = min(best_wall, time.perf_counter() - t0)
    best_cpu = min(best_cpu, time.process_time() - c0)
ps = {N_ENGINE} * {P} * sc.T
digest = hashlib.sha256(res.mc.samples.tobytes()).hexdigest()[:12]
print(f"{{best_cpu / ps * 1e9:.1f}} ns per particle-step CPU, {{best_wall / ps * 1e9:.1f}} wall; "
      f"results {{digest}}")
"""


def _engine(src: str | None, label: str):
    def setup():
        if src is None:
            return lambda: print(f"  [{label}] skipped (set BENCH_BEFORE_SRC)")

        def call():
            env = dict(os.environ, PYTHONPATH=src)
            out = subprocess.run([sys.executable, "-c", _ENGINE], env=env, check=True,
                                 capture_output=True, text=True).stdout.strip()
            print(f"  [{label}] {out}; load average {os.getloadavg()[0]:.2f}")
        return call
    return setup


def fig1_paper_scale() -> float:
    t0 = time.perf_counter()
    with concurrent.futures.ProcessPoolExecutor(2) as ex:
        res = [cs.run(SC, s, l=L, n_trials=N_PAPER, n_particles=P, seed=SEED, feedback="state",
                      executor=ex) for s in ("all-send", "random", "cfomd", "cfwmd")]
    dt = time.perf_counter() - t0
    ps = 4 * N_PAPER * P * SC.T
    print(f"  [Fig. 1, 4 schemes, 2 processes] {dt:.1f} s wall, {dt / ps * 1e9:.1f} ns per "
          f"particle-step wall ({2 * dt / ps * 1e9:.1f} per process); load average "
          f"{os.getloadavg()[0]:.2f}; CFwMD time-averaged position RMSE "
          f"{res[-1].time_averaged_rmse()[0]:.4f}")
    return dt


REPEATS = 1
_G1 = "CFwMD engine, state feedback, 1024 x 1000 x 20, one process"
CASES = [
    (_G1, "before (BENCH_BEFORE_SRC)", _engine(os.environ.get("BENCH_BEFORE_SRC"), "before")),
    (_G1, "after (this tree)", _engine(str(HERE_SRC), "after")),
    ("Fig. 1 paper scale, 4 x 5000 x 1000 x 20, 2 processes", "censoring.run",
     lambda: fig1_paper_scale),
]
