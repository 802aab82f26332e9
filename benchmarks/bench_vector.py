"""Vector observations (zheng2014 Part IV(b)): the silent probability and the paper-scale runs.

Groups (the first case of a group is its baseline):

* ``silent probability, 4096 particles``: ``P(q^T q < eta)`` for the particles of one trial-step
  (the filter's typical cloud at l = 1, N = 2), by the paper's sampling estimate with
  ``N_q = 1000`` draws per particle (relative error ~2 %), by the accurate quadrature
  (:func:`fusioncenter.censoring.ellipse.log_censored_probability`, relative error ~1e-13), by
  the filter's fixed-ellipse table (error < 1e-6 in the log) and by the per-trial tables of
  CFwMD2 (error < 2e-5).
* ``filter, 256 trials x 1000 particles x 20 steps``: one block of each configuration of
  Figs. 4-6 (fused engine).
* ``paper scale, Figs. 4-6 + Table II``: every registry entry of the vector chapter in the paper
  profile (5000 trials x 1000 particles, two worker processes). Several minutes, so it is
  included only when the environment variable ``BENCH_VECTOR_PAPER`` is set (then every case
  runs once after its warm-up). ``python benchmarks/bench_vector.py --paper`` runs it once and
  prints the per-entry wall times, the workers' CPU time, the peak memory and the machine's
  load average.
"""

from __future__ import annotations

import math
import os
import resource
import sys
import time

import numpy as np

from fusioncenter import censoring as cs
from fusioncenter.censoring import ellipse, vector, vector_fusion, vector_likelihood

REPEATS = 3
SC2, SC4 = vector.VectorScenario(), vector.VectorScenario(N=4)
ETA = cs.threshold(1, 2, dof=2)


def _cloud(n: int = 4096, seed: int = 1):
    """Canonical coordinates of a particle cloud like the filter's (l = 1, N = 2, t = 20)."""
    lf = SC2.local_filters()
    rng = np.random.default_rng(seed)
    dev = rng.multivariate_normal([0.0, 0.0], lf["P_pred"][-1, 0], size=n)
    a = math.sqrt(ETA) * lf["a_scale"][-1, 0]
    return dev @ lf["A"][-1, 0].T, a


B, A = _cloud()
MEAN_Q, COV_Q = B / A, np.diag(1.0 / A**2)


def sampled():
    rng = np.random.default_rng(2)
    return vector_likelihood.censored_probability_sampled(MEAN_Q, COV_Q, 1.0, n_samples=1000,
                                                          rng=rng)


def quadrature():
    return ellipse.log_censored_probability(MEAN_Q, COV_Q, 1.0)


def table():
    return ellipse.log_silent_table((B[:, 0], B[:, 1]), A)


def per_trial_tables():
    b = B.reshape(4, 1024, 2)
    a = np.broadcast_to(A, (4, 2)).copy()
    return ellipse.eval_silent(b, a)


def _block(sc, scheme, feedback, l, likelihood="exact"):
    def fn():
        return vector_fusion.run(sc, scheme, l=l, n_trials=256, n_particles=1000, seed=3,
                                 feedback=feedback, likelihood=likelihood)
    return fn


def paper_scale() -> dict:
    """Every vector entry in the paper profile; returns per-entry wall times and memory."""
    from fusioncenter import figures
    from fusioncenter.figures.zheng2014 import vector as zv

    for f in (zv._fig4_runs, zv._fig5_runs, zv._fig6_runs):
        f.cache_clear()
    out = {}
    for eid in ("zheng2014-fig4", "zheng2014-fig5", "zheng2014-table2", "zheng2014-fig6"):
        t0 = time.perf_counter()
        data = figures.get(eid).run_compute("paper")
        out[eid] = (time.perf_counter() - t0, data)
    return out


def _peak_mib() -> tuple[float, float]:
    """Peak resident set size of this process and of its (finished) children, MiB."""
    own = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    kids = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
    return own, kids


def _check_accuracy() -> None:
    exact = quadrature()
    assert np.max(np.abs(table() - exact)) < 1e-6
    assert np.max(np.abs(per_trial_tables().ravel() - exact)) < 2e-5
    est = sampled()
    assert np.median(np.abs(est - np.exp(exact)) / np.exp(exact)) < 0.05


_check_accuracy()

CASES = [
    ("silent probability, 4096 particles", "sampled, N_q = 1000 (paper)", lambda: sampled),
    ("silent probability, 4096 particles", "quadrature (accurate)", lambda: quadrature),
    ("silent probability, 4096 particles", "fixed-ellipse table (filter)", lambda: table),
    ("silent probability, 4096 particles", "per-trial tables (CFwMD2)",
     lambda: per_trial_tables),
    ("filter, 256 trials x 1000 particles x 20 steps", "Fig. 4 all-send",
     lambda: _block(SC2, "all-send", "state", 1)),
    ("filter, 256 trials x 1000 particles x 20 steps", "Fig. 4 CFwMD",
     lambda: _block(SC2, "cfwmd", "state", 1)),
    ("filter, 256 trials x 1000 particles x 20 steps", "Fig. 5 CFwMD, l = 1",
     lambda: _block(SC4, "cfwmd", "state", 1)),
    ("filter, 256 trials x 1000 particles x 20 steps", "Fig. 5 CFwMD2, l = 1",
     lambda: _block(SC4, "cfwmd", "state+cov", 1)),
    ("filter, 256 trials x 1000 particles x 20 steps", "Fig. 6 CFwMD exact",
     lambda: _block(SC2, "cfwmd", "none", 1)),
]
if os.environ.get("BENCH_VECTOR_PAPER"):
    REPEATS = 1
    CASES.append(("paper scale, Figs. 4-6 + Table II", "all four entries, 2 workers",
                  lambda: paper_scale))


def _print_results(res: dict) -> None:
    """The paper-scale numbers the report quotes (time-averaged RMSE, Table II)."""
    for eid in ("zheng2014-fig4", "zheng2014-fig6"):
        d = res[eid][1]
        names = d["schemes"] if "schemes" in d else d["curves"]
        for i, name in enumerate(names):
            print(f"{eid} {name:>9}: position {d['tavg_position'][i]:.4f} +/- "
                  f"{d['tavg_position_stderr'][i]:.4f} m, velocity {d['tavg_velocity'][i]:.4f}"
                  f" +/- {d['tavg_velocity_stderr'][i]:.4f} m/s, transmissions "
                  f"{d['transmissions'][i]:.4f} +/- {d['transmissions_stderr'][i]:.4f}")
    d = res["zheng2014-fig5"][1]
    for i, l in enumerate(d["l"]):
        print(f"fig5 l = {l:g}: CFwMD {d['tavg_position'][0, i]:.4f} +/- "
              f"{d['tavg_position_stderr'][0, i]:.4f}, CFwMD2 {d['tavg_position'][1, i]:.4f} "
              f"+/- {d['tavg_position_stderr'][1, i]:.4f} m; CFwMD2 - CFwMD = "
              f"{d['diff'][i]:+.4f} +/- {d['diff_stderr'][i]:.4f}; silent steps "
              f"{d['silent_steps'][0, i]:.4f} / {d['silent_steps'][1, i]:.4f}")
    d = res["zheng2014-table2"][1]
    for i, l in enumerate(d["l"]):
        print(f"table2 l = {l:g}: CFwMD {d['cfwmd'][i]:.4f} +/- {d['cfwmd_stderr'][i]:.4f} "
              f"(paper {d['paper_cfwmd'][i]}, z {d['z_cfwmd'][i]:+.2f}); CFwMD2 "
              f"{d['cfwmd2'][i]:.4f} +/- {d['cfwmd2_stderr'][i]:.4f} (paper "
              f"{d['paper_cfwmd2'][i]}, z {d['z_cfwmd2'][i]:+.2f}); closer z "
              f"{d['closer_z'][i]:.1f}")


def main() -> int:
    load = os.getloadavg()
    print(f"load average before: {load[0]:.2f} {load[1]:.2f} {load[2]:.2f} "
          f"({os.cpu_count()} cores)")
    t0, c0 = time.perf_counter(), resource.getrusage(resource.RUSAGE_CHILDREN)
    res = paper_scale()
    wall = time.perf_counter() - t0
    c1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu_kids = (c1.ru_utime + c1.ru_stime) - (c0.ru_utime + c0.ru_stime)
    from fusioncenter import figures

    for eid, (dt, data) in res.items():
        print(f"{eid}: {dt:7.1f} s wall")
        for c in figures.get(eid).run_checks(data):
            print(f"  {'PASS' if c else 'FAIL'}: {c.name} [{c.detail}]")
    _print_results(res)
    own, kids = _peak_mib()
    load = os.getloadavg()
    print(f"total {wall:.1f} s wall, {cpu_kids:.1f} s CPU in the workers; peak RSS: main "
          f"{own:.0f} MiB, largest worker {kids:.0f} MiB; load average after: {load[0]:.2f} "
          f"{load[1]:.2f} {load[2]:.2f}")
    return 0


if __name__ == "__main__":
    if "--paper" in sys.argv:
        sys.exit(main())
    print(__doc__)
