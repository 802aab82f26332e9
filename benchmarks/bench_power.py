"""All ten leong2011 panels (Figs. 1-6) at paper scale: the issue's target is <= 60 s.

Workload: ``compute("paper")`` of every registry entry leong2011-fig1 ... fig6b, i.e. Figs. 3-4
with 1000 realizations of the sensor parameters per point and Figs. 5-6 with 100 realizations x
1000 fading steps per point (10 values of M each), the SLSQP cross-checks and the no-CSI filter
simulations included. One run takes tens of seconds, so it is timed once (REPEATS = 1, after the
runner's warm-up run).
"""

from __future__ import annotations

from fusioncenter import figures

IDS = ["leong2011-fig1", "leong2011-fig2", "leong2011-fig3a", "leong2011-fig3b",
       "leong2011-fig4a", "leong2011-fig4b", "leong2011-fig5a", "leong2011-fig5b",
       "leong2011-fig6a", "leong2011-fig6b"]


def all_panels() -> None:
    for entry_id in IDS:
        figures.get(entry_id).run_compute("paper")


def _setup():
    for entry_id in IDS:  # fail early (and import scipy.optimize) before timing
        assert figures.get(entry_id).compute is not None
    return all_panels


REPEATS = 1
CASES = [
    ("leong2011 ten panels, paper profile", "vectorized (fusioncenter.power)", _setup),
]
