"""Run every ``benchmarks/bench_*.py`` and print a table of medians and ratios (``make bench``).

A benchmark module defines ``CASES``: a list of ``(group, name, setup)`` where ``setup()`` returns
a zero-argument callable to time, and the first case of each group is that group's baseline.
Each callable is timed ``REPEATS`` times (after one warm-up); the table shows the median, the
spread (min-max), and the ratio baseline_median / median (how many times faster). Results are
also written to benchmarks/results/latest.json.

``bench_particle_floor.py`` (``python benchmarks/run.py floor``) times its variants itself, in
one interleaved run (CPU time, medians), and prints ns per particle-step and the ratios to the
hand-fused reference kernel; its row in this table is only the duration of that whole run.
"""

from __future__ import annotations

import importlib.util
import json
import platform
import statistics
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPEATS = 7


def load(path: Path):
    spec = importlib.util.spec_from_file_location(path.stem, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def time_it(fn, repeats: int) -> list[float]:
    fn()  # warm-up
    out = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t0)
    return out


def main(argv: list[str]) -> int:
    files = sorted(HERE.glob("bench_*.py"))
    if argv:
        files = [f for f in files if any(a in f.name for a in argv)]
    rows = []
    for f in files:
        mod = load(f)
        baselines: dict[str, float] = {}
        for group, name, setup in mod.CASES:
            times = time_it(setup(), getattr(mod, "REPEATS", REPEATS))
            med = statistics.median(times)
            baselines.setdefault(group, med)
            rows.append({"file": f.name, "group": group, "case": name, "median_s": med,
                         "min_s": min(times), "max_s": max(times),
                         "speedup_vs_baseline": baselines[group] / med})
    w = max((len(r["group"]) + len(r["case"]) for r in rows), default=20) + 3
    print(f"{'benchmark':<{w}} {'median':>10} {'min':>10} {'max':>10} {'speedup':>9}")
    for r in rows:
        label = f"{r['group']} / {r['case']}"
        print(f"{label:<{w}} {r['median_s'] * 1e3:>8.2f}ms {r['min_s'] * 1e3:>8.2f}ms "
              f"{r['max_s'] * 1e3:>8.2f}ms {r['speedup_vs_baseline']:>8.1f}x")
    out = HERE / "results"
    out.mkdir(exist_ok=True)
    (out / "latest.json").write_text(json.dumps(
        {"python": platform.python_version(), "machine": platform.machine(), "rows": rows},
        indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
