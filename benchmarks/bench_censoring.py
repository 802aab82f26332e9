"""zheng2014 (Part IV(a)): the fused particle filter and Fig. 1 at the paper's scale.

Group 1 -- CFwMD with state feedback (N = 2, l = 1), 1024 trials x 1000 particles x 20 steps
(2.05e7 particle-steps), one process: the reference engine (``_FusionCentre`` through the generic
``particle.run_filter``) against the fused engine that ``censoring.run`` uses. Both draw the same
random numbers; their per-trial results are checked equal to 1e-9 before timing. The target of
the fused engine: <= 60 ns per particle-step.

Group 2 -- Fig. 1 at the paper's scale: all four schemes (all-send, random selection, CFoMD,
CFwMD), 5000 trials x 1000 particles x 20 steps each (4e8 particle-steps), on a pool of two
processes (``executor`` of ``censoring.run``). Target: <= 30 s wall.

Each case prints its cost in ns per particle-step (wall clock) and the machine's load average:
other jobs share this 2-core machine, so compare minima over repeats, at low load.
"""

from __future__ import annotations

import concurrent.futures
import functools
import os
import time

import numpy as np

from fusioncenter import censoring as cs
from fusioncenter import montecarlo

SC = cs.LinearScenario()
L, SEED, P = 1.0, 2014, 1000
N_ENGINE = 1024
N_PAPER = 5000


def _engine_fn(engine: str, n: int = N_ENGINE):
    fn = functools.partial(cs._chunk, scenario=SC, scheme="cfwmd", feedback="state",
                           likelihood="corrected", eta=cs.threshold(L, SC.N), l=L,
                           n_particles=P, ess_threshold=1.0, engine=engine)

    def call():
        t0 = time.perf_counter()
        out = montecarlo.simulate(fn, n, SEED).samples
        dt = time.perf_counter() - t0
        print(f"  [{engine}] {dt / (n * P * SC.T) * 1e9:.1f} ns per particle-step "
              f"({dt:.2f} s; load average {os.getloadavg()[0]:.2f})")
        return out

    return call


def _checked_engine(engine: str):
    def setup():
        small = 64
        a = _engine_fn("fused", small)()
        b = _engine_fn("reference", small)()
        np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-12)
        return _engine_fn(engine)
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
_G1 = "CFwMD state feedback, 1024 x 1000 x 20, one process"
CASES = [
    (_G1, "reference engine (particle.run_filter)", _checked_engine("reference")),
    (_G1, "fused engine (censoring.run)", _checked_engine("fused")),
    ("Fig. 1 paper scale, 4 x 5000 x 1000 x 20, 2 processes", "censoring.run",
     lambda: fig1_paper_scale),
]
