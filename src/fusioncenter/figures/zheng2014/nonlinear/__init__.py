"""Registry entries of Part IV(b), nonlinear tracking (zheng2014 Section VI, VII.C-D).

* ``zheng2014-fig7``: the sensor grid and a sample trajectory, no filtering
  (:mod:`~fusioncenter.figures.zheng2014.nonlinear.trajectory`).
* ``zheng2014-fig8``: position and velocity RMSE of the four schemes, ``l = 2``, state feedback;
  ``zheng2014-fig9``: time-averaged RMSE against the average number of transmissions per step,
  ``l`` in :data:`L_FIG9` (:mod:`~fusioncenter.figures.zheng2014.nonlinear.schemes`).
* ``zheng2014-fig10`` and ``zheng2014-table3``: CFwMD (state feedback, Proposition 7) against
  CFwMD2 (state and covariance feedback, Proposition 8), ``l`` in {2, 4, 6}; one computation
  (:mod:`~fusioncenter.figures.zheng2014.nonlinear.feedback`).

The scenario, the run sizes and the runs all the filtering entries share (computed once per
profile, seed and size) are in :mod:`~fusioncenter.figures.zheng2014.nonlinear.scenario`.
Importing the package registers the five entries; the names the chapters and
:mod:`fusioncenter.figures.zheng2014.reading` use are re-exported here.
"""

from __future__ import annotations

from fusioncenter.figures.zheng2014.nonlinear.feedback import (
    L_FIG10,
    TABLE3_PRINTED,
    checks_fig10,
    checks_table3,
    compute_fig10,
    compute_table3,
    plot_fig10,
    plot_table3,
)
from fusioncenter.figures.zheng2014.nonlinear.scenario import (
    BLOCK,
    CHAPTER,
    PARAMS,
    SCENARIO,
    SETTABLE,
    SIZE_KEYS,
    SIZES,
    Z_AGREE,
    Z_ORDER,
    Z_WEAK,
    runs,
    z_required,
)
from fusioncenter.figures.zheng2014.nonlinear.schemes import (
    FIG8_SCHEMES,
    FIG9_SCHEMES,
    L_FIG8,
    L_FIG9,
    checks_fig8,
    checks_fig9,
    compute_fig8,
    compute_fig9,
    plot_fig8,
    plot_fig9,
)
from fusioncenter.figures.zheng2014.nonlinear.trajectory import (
    SETTABLE_FIG7,
    TRAJECTORIES,
    checks_fig7,
    compute_fig7,
    plot_fig7,
)

#: Ids of the book's own figures registered here (not figures of the paper).
OWN_IDS: tuple[str, ...] = ()

__all__ = [
    "BLOCK",
    "CHAPTER",
    "FIG8_SCHEMES",
    "FIG9_SCHEMES",
    "L_FIG10",
    "L_FIG8",
    "L_FIG9",
    "OWN_IDS",
    "PARAMS",
    "SCENARIO",
    "SETTABLE",
    "SETTABLE_FIG7",
    "SIZES",
    "SIZE_KEYS",
    "TABLE3_PRINTED",
    "TRAJECTORIES",
    "Z_AGREE",
    "Z_ORDER",
    "Z_WEAK",
    "checks_fig10",
    "checks_fig7",
    "checks_fig8",
    "checks_fig9",
    "checks_table3",
    "compute_fig10",
    "compute_fig7",
    "compute_fig8",
    "compute_fig9",
    "compute_table3",
    "plot_fig10",
    "plot_fig7",
    "plot_fig8",
    "plot_fig9",
    "plot_table3",
    "runs",
    "z_required",
]
