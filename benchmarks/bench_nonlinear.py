"""The nonlinear tracker (zheng2014 Section VII.C, Figs. 7-10 and Table III): cost at paper scale.

Cases (``REPEATS = 1``: the paper-scale case takes minutes; ``run.py`` adds one warm-up call):

* ``silent term``: the CFwMD factors of the silent sensors for one step of a block of 25 trials x
  10^4 particles (about 190 silent trial-sensor pairs): exact (two normal cdfs and a log per
  particle, ``log_silent_probability``) against the tabulated cubic Hermite interpolation the
  fusion centre uses (``_silent_terms``, error below 1e-9 in the log weight);
* ``one block``: one block of 25 trials x 10^4 particles x 20 steps (1/8 of a paper-scale run)
  for CFoMD, CFwMD and CFwMD2;
* ``paper scale``: the five registry entries from a cold cache, as the book's paper profile runs
  them: 19 runs of 200 trials x 10^4 particles on :func:`fusioncenter.context.cores` worker
  processes. Each call prints the wall time per entry, the peak resident memory of the whole
  process tree (sampled every 0.2 s from ``/proc``) and the load average of the machine.

``python benchmarks/bench_nonlinear.py`` runs the paper-scale case once and prints its report.
"""

from __future__ import annotations

import os
import threading
import time

import numpy as np

from fusioncenter import censoring as cs
from fusioncenter import context
from fusioncenter.censoring import nonlinear as cn
from fusioncenter.figures.zheng2014.nonlinear import feedback as zn_fb
from fusioncenter.figures.zheng2014.nonlinear import scenario as zn_sc

#: The paper profile's default executor is a pool of one process per core.
WORKERS = context.cores()

REPEATS = 1
IDS = ("zheng2014-fig7", "zheng2014-fig8", "zheng2014-fig9", "zheng2014-fig10",
       "zheng2014-table3")


def _tree_rss(root: int) -> int:
    """Resident memory (bytes) of ``root`` and all its descendants (Linux ``/proc``)."""
    children: dict[int, list[int]] = {}
    for p in os.listdir("/proc"):
        if not p.isdigit():
            continue
        try:
            with open(f"/proc/{p}/stat") as fh:
                ppid = int(fh.read().rsplit(")", 1)[1].split()[1])
        except (OSError, IndexError, ValueError):
            continue
        children.setdefault(ppid, []).append(int(p))
    total, stack = 0, [root]
    page = os.sysconf("SC_PAGE_SIZE")
    while stack:
        pid = stack.pop()
        try:
            with open(f"/proc/{pid}/statm") as fh:
                total += int(fh.read().split()[1]) * page
        except (OSError, IndexError, ValueError):
            pass
        stack.extend(children.get(pid, []))
    return total


def _cpu_seconds() -> float:
    """User + system CPU time of this process and of its terminated children (the workers)."""
    import resource

    me = resource.getrusage(resource.RUSAGE_SELF)
    ch = resource.getrusage(resource.RUSAGE_CHILDREN)
    return me.ru_utime + me.ru_stime + ch.ru_utime + ch.ru_stime


def paper_scale(verbose: bool = True) -> dict:
    """Compute the five entries at paper scale from a cold cache; returns timings and memory."""
    from fusioncenter import figures

    zn_sc._RUNS.clear()
    zn_fb._fig10_table3.cache_clear()
    peak, stop = [0], threading.Event()

    def sample():
        while not stop.is_set():
            peak[0] = max(peak[0], _tree_rss(os.getpid()))
            stop.wait(0.2)

    th = threading.Thread(target=sample, daemon=True)
    load0 = os.getloadavg()
    cpu0 = _cpu_seconds()
    th.start()
    times = {}
    t0 = time.perf_counter()
    try:
        for entry_id in IDS:
            t = time.perf_counter()
            figures.get(entry_id).run_compute("paper")
            times[entry_id] = time.perf_counter() - t
    finally:
        stop.set()
        th.join()
    cpu = _cpu_seconds() - cpu0
    out = {"wall_s": time.perf_counter() - t0, "per_entry_s": times, "cpu_s": cpu,
           "peak_rss_mib": peak[0] / 2**20, "load_before": load0, "load_after": os.getloadavg(),
           "workers": WORKERS, "runs": len(zn_sc._RUNS)}
    if verbose:
        per = ", ".join(f"{k.removeprefix('zheng2014-')} {v:.1f} s" for k, v in times.items())
        print(f"\n[paper scale] {out['runs']} runs, {WORKERS} workers: {out['wall_s']:.1f} s "
              f"({per}); CPU {cpu:.0f} s (this process and its finished workers; "
              f"CPU / {WORKERS} = {cpu / WORKERS:.0f} s: the wall time on "
              f"{WORKERS} idle cores); peak RSS of the process tree "
              f"{out['peak_rss_mib']:.0f} MiB; load average before {load0[0]:.2f}, after "
              f"{out['load_after'][0]:.2f} (1 min)")
    return out


def _silent_input():
    rng = np.random.default_rng(0)
    rows, P = 190, 10_000
    a = np.abs(rng.normal(0.0, rng.uniform(0.3, 3.0, (rows, 1)), (rows, P)))
    h = rng.uniform(1.0, 3.0, rows)
    return a, h


def _exact_setup():
    a, h = _silent_input()
    return lambda: cn.log_silent_probability(a, h[:, None])


def _table_setup():
    a, h = _silent_input()
    assert np.max(np.abs(cn.silent_terms(a, h) - cn.log_silent_probability(a, h[:, None]))) < 1e-9
    return lambda: cn.silent_terms(a, h)


def _block(scheme: str, feedback: str):
    def setup():
        return lambda: cn.run(cn.NonlinearScenario(), scheme, l=2, n_trials=25,
                              n_particles=10_000, seed=1, feedback=feedback, block_size=25)
    return setup


CASES = [
    ("nonlinear: silent term, 190 x 10^4", "exact (ndtr)", _exact_setup),
    ("nonlinear: silent term, 190 x 10^4", "tabulated (Hermite)", _table_setup),
    ("nonlinear: one block 25 x 10^4 x 20", "CFoMD", _block("cfomd", "state")),
    ("nonlinear: one block 25 x 10^4 x 20", "CFwMD", _block("cfwmd", "state")),
    ("nonlinear: one block 25 x 10^4 x 20", "CFwMD2", _block("cfwmd", "state+cov")),
    ("nonlinear: paper scale (Figs. 7-10, Table III)", "19 runs of 200 x 10^4",
     lambda: lambda: paper_scale()),
]

if __name__ == "__main__":
    assert cs.SCHEMES == cn.SCHEMES
    paper_scale()
