"""Registry entries of Part V (the side-by-side comparison chapter); the book's own figures.

One tracking problem (zheng2014 Section VII.A, two sensors, 20 steps, ``x_0`` known) and one
budget (transmissions per step), four ideas:

* ``synthesis-frontier`` (:mod:`~fusioncenter.figures.synthesis.frontier`): RMSE against the
  *measured* average transmissions per step for mo2015's stochastic trigger with its exact
  Kalman filter, zheng2014's NIS censoring with CFwMD and CFoMD (particle filters), random
  selection (exact Kalman filter) and all-send; every scheme on the same simulated trials
  (paired), the Kalman-filter schemes calibrated to the rates the particle-filter schemes
  actually reach.
* ``synthesis-cost`` (:mod:`~fusioncenter.figures.synthesis.cost`): operations per step of the
  Kalman filter and of the particle filter (an operation-count model, the deterministic claim),
  measured run time (shown, never asserted), and what the particles buy: the all-send particle
  filter's excess RMSE over the exact filter.
* ``synthesis-fading`` (:mod:`~fusioncenter.figures.synthesis.fading`): the links through a
  Rayleigh block-fading packet channel (dey2009's channel law, outage when the power gain falls
  below a threshold): RMSE and transmissions against the outage probability, with a receiver
  that knows the channel gains and a naive one that reads every missing packet as silence; and
  the same with energy rather than packets as the budget (where power allocation in the spirit
  of leong2011 enters).

The common problem, its calibration and the data helpers the three share are in
:mod:`~fusioncenter.figures.synthesis.problem`. Importing the package registers the three
entries; the names the chapter uses (``fs.scenario``, ``fs.calibrate``, ``fs.energy_runs``, ...)
are re-exported here.
"""

from __future__ import annotations

from fusioncenter.figures.synthesis.problem import (
    CALIBRATION_TRIALS,
    CHAPTER,
    PARTICLES,
    PROBLEM,
    SETTABLE_FRONTIER,
    TRIALS,
    Z_TOL,
    calibrate,
    scenario,
)

# isort: off
# (the registration order is the order of the entries in the registry)
from fusioncenter.figures.synthesis.frontier import (  # registers synthesis-frontier
    FRONTIER_GRID,
    FRONTIER_L,
    checks_frontier,
    compute_frontier,
    plot_frontier,
)
from fusioncenter.figures.synthesis.cost import (  # registers synthesis-cost
    COST_PARTICLES,
    COST_TRIALS,
    SETTABLE_COST,
    checks_cost,
    compute_cost,
    plot_cost,
)
from fusioncenter.figures.synthesis.fading import (  # registers synthesis-fading
    ENERGY_ITERATIONS,
    FADING_L,
    OUTAGES,
    SETTABLE_FADING,
    checks_fading,
    compute_fading,
    energy_runs,
    plot_fading,
)
# isort: on

#: Ids of the book's own figures registered here (not figures of the paper).
OWN_IDS: tuple[str, ...] = ("synthesis-frontier", "synthesis-fading", "synthesis-cost")

__all__ = [
    "CALIBRATION_TRIALS",
    "CHAPTER",
    "COST_PARTICLES",
    "COST_TRIALS",
    "ENERGY_ITERATIONS",
    "FADING_L",
    "FRONTIER_GRID",
    "FRONTIER_L",
    "OUTAGES",
    "OWN_IDS",
    "PARTICLES",
    "PROBLEM",
    "SETTABLE_COST",
    "SETTABLE_FADING",
    "SETTABLE_FRONTIER",
    "TRIALS",
    "Z_TOL",
    "calibrate",
    "checks_cost",
    "checks_fading",
    "checks_frontier",
    "compute_cost",
    "compute_fading",
    "compute_frontier",
    "energy_runs",
    "plot_cost",
    "plot_fading",
    "plot_frontier",
    "scenario",
]
