"""Part II (dey2009): Figs. 1-4 of the paper and the book's own figures on faded measurements.

* ``dey2009-fig1`` / ``dey2009-fig2``: one sensor, scalar state, Rayleigh resp. Nakagami(1/2)
  fading: ``E[p_k]`` by Monte Carlo against the tight and loose bound sequences (17)-(20).
* ``dey2009-fig3`` / ``dey2009-fig4``: two sensors, multi-access resp. orthogonal channels:
  ``E[p_k]`` against the worst-sensor bound ``s_k`` and the AM-HM bound ``t_k``.
* ``dey2009-vector``: a 2-state example of Section 3.2: ``E[P_k]`` against ``Zbar_k``.
* ``dey2009-ordering``: what goes wrong on the multi-access channel when ordering (22) is ignored.
* ``dey2009-distribution``: the whole distribution of ``p_k`` (the paper's future work).

The paper leaves some parameters out (Figs. 1-2: the sigma_v values and E[p_0]; Figs. 3-4:
lambda_1, lambda_2). Our choices are in :data:`SIGMA_V`, :data:`P0` and :data:`LAMS`; each entry
also runs a grid of alternatives and checks that the conclusions hold on all of them.

The package is split by figure group: :mod:`~fusioncenter.figures.dey2009.common` (the
parameters and the shared checks), :mod:`~fusioncenter.figures.dey2009.scalar` (Figs. 1-2),
:mod:`~fusioncenter.figures.dey2009.multisensor` (Figs. 3-4),
:mod:`~fusioncenter.figures.dey2009.ordering`, :mod:`~fusioncenter.figures.dey2009.vector` and
:mod:`~fusioncenter.figures.dey2009.distribution`; each registers its entries when imported
(in this order), and the names below are re-exported here.
"""

from fusioncenter.figures.dey2009.common import (
    BLOCK,
    CH_DIST,
    CH_MULTI,
    CH_SCALAR,
    CH_VECTOR,
    DIST,
    DIST_PATHS,
    GRID_PATHS,
    KS_LEVEL,
    LAM_GRID,
    LAMS,
    MULTI,
    N_DIRECTIONS,
    ORDERING,
    OWN_IDS,
    P0,
    PATHS,
    REL_SLACK,
    SCALAR,
    SCALAR_GRID,
    SETTABLE_PATHS,
    SIGMA_V,
    STEPS,
    VECTOR,
    WINDOWS,
    Z_TOL,
)

# The submodules register their entries when imported: this order is the registry's.
# isort: off
from fusioncenter.figures.dey2009.scalar import (
    compute_fig1,
    compute_fig2,
    plot_fig1,
    plot_fig2,
)
from fusioncenter.figures.dey2009.multisensor import (
    checks_multi,
    compute_fig3,
    compute_fig4,
    plot_multi,
)
from fusioncenter.figures.dey2009.ordering import (
    checks_ordering,
    compute_ordering,
    plot_ordering,
)
from fusioncenter.figures.dey2009.vector import (
    checks_vector,
    SETTABLE_VECTOR,
    compute_vector,
    plot_vector,
)
from fusioncenter.figures.dey2009.distribution import (
    checks_distribution,
    SETTABLE_DIST,
    compute_distribution,
    plot_distribution,
)
# isort: on

__all__ = [
    "CH_SCALAR",
    "CH_MULTI",
    "CH_VECTOR",
    "CH_DIST",
    "OWN_IDS",
    "STEPS",
    "PATHS",
    "GRID_PATHS",
    "BLOCK",
    "Z_TOL",
    "REL_SLACK",
    "WINDOWS",
    "KS_LEVEL",
    "SCALAR",
    "SIGMA_V",
    "P0",
    "SCALAR_GRID",
    "MULTI",
    "LAMS",
    "LAM_GRID",
    "ORDERING",
    "VECTOR",
    "N_DIRECTIONS",
    "DIST_PATHS",
    "DIST",
    "SETTABLE_PATHS",
    "SETTABLE_VECTOR",
    "SETTABLE_DIST",
    "compute_fig1",
    "compute_fig2",
    "plot_fig1",
    "plot_fig2",
    "compute_fig3",
    "compute_fig4",
    "plot_multi",
    "checks_multi",
    "compute_ordering",
    "plot_ordering",
    "checks_ordering",
    "compute_vector",
    "plot_vector",
    "checks_vector",
    "compute_distribution",
    "plot_distribution",
    "checks_distribution",
]
