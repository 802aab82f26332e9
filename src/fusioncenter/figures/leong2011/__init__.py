"""Registry entries of Part III (leong2011): Figs. 1-6 of the paper, ten panels.

* Figs. 1-2 (``book/leong2011/asymptotics``): the steady state against the number of sensors
  with ``alpha_i = 1/sqrt(M)`` (multi-access), the 1/M law (13) and the Lemma 4 bounds (37).
  Deterministic (Fig. 2: one seeded draw of the sensor parameters).
* Figs. 3-4 (``book/leong2011/allocation``): optimal vs equal power allocation on static
  channels, averaged over random sensor parameters (``sigma_v2 ~ chi2(1)``, ``h = d^-2``,
  ``d ~ U(20, 100)`` m), panel (a) at the error target ``D = 2``, panel (b) at the power budget
  ``gamma_total = 1e-3``.
* Figs. 5-6 (``book/leong2011/fading``): Rician fading, greedy allocation with full CSI vs
  the linear MMSE estimator without CSI (allocation optimized once for its steady state).

Everything the paper leaves open is a stated choice in :data:`STATIC`, :data:`FADING`,
:data:`FIG1`, :data:`FIG2` (see each entry's ``parameters``): the range of ``M``, the
distribution of Fig. 2's parameters, the filters' initial variances, and the handling of
realizations for which a target is infeasible (they are redrawn: every point averages the
stated number of *feasible* realizations, and the acceptance rate is reported).

The package is split by figure group: :mod:`~fusioncenter.figures.leong2011.common` (the
parameters), :mod:`~fusioncenter.figures.leong2011.asymptotics` (Figs. 1-2),
:mod:`~fusioncenter.figures.leong2011.static` (Figs. 3-4) and
:mod:`~fusioncenter.figures.leong2011.fading_channels` (Figs. 5-6); each registers its entries
when imported (in this order), and the names below are re-exported here.
"""

from fusioncenter.figures.leong2011.common import (
    CH_ALLOCATION,
    CH_ASYMPTOTICS,
    CH_FADING,
    FADING,
    FIG1,
    FIG2,
    OWN_IDS,
    REL_TOL,
    SETTABLE_FADING,
    SETTABLE_FIG1,
    SETTABLE_FIG2,
    SETTABLE_STATIC,
    STATIC,
    Z_TOL,
)

# The submodules register their entries when imported: this order is the registry's.
# isort: off
from fusioncenter.figures.leong2011.asymptotics import (
    compute_fig1,
    plot_fig1,
    checks_fig1,
    compute_fig2,
    plot_fig2,
    checks_fig2,
)
from fusioncenter.figures.leong2011.static import (
    compute_static,
    plot_static,
    checks_static,
)
from fusioncenter.figures.leong2011.fading_channels import (
    compute_fading,
    plot_fading,
    checks_fading,
)
# isort: on

__all__ = [
    "CH_ASYMPTOTICS",
    "CH_ALLOCATION",
    "CH_FADING",
    "OWN_IDS",
    "FIG1",
    "FIG2",
    "STATIC",
    "FADING",
    "Z_TOL",
    "REL_TOL",
    "SETTABLE_STATIC",
    "SETTABLE_FADING",
    "SETTABLE_FIG1",
    "SETTABLE_FIG2",
    "compute_fig1",
    "plot_fig1",
    "checks_fig1",
    "compute_fig2",
    "plot_fig2",
    "checks_fig2",
    "compute_static",
    "plot_static",
    "checks_static",
    "compute_fading",
    "plot_fading",
    "checks_fading",
]
