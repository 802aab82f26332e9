"""Registry entries of Part IV(a) (zheng2014), Section VII.A: linear tracking, scalar observations.

* ``zheng2014-fig1``: feedback of the predicted state, ``N = 2``, ``l = 1``: position and velocity
  RMSE of all-send, random selection, CFoMD and CFwMD.
* ``zheng2014-fig2``: ``N = 4``, ``l`` in {1, 1.2, 1.5, 2, 3}: CFwMD (state fed back) against
  CFwMD2 (state and covariance fed back).
* ``zheng2014-table1``: the average number of transmissions per step of the same runs, next to
  the paper's printed values.
* ``zheng2014-fig3``: no feedback, ``N = 2``, ``l = 1``: the four schemes, with CFwMD's
  Proposition 3 as printed (it equals CFoMD: erratum), corrected, and the exact filter.
* ``zheng2014-table1-choices`` (the book's own): Table I under the choices the paper leaves open.

The entries of Part IV(b) are registered by the package's modules
:mod:`~fusioncenter.figures.zheng2014.vector` (Section VII.B: Figs. 4-6 and Table II) and
:mod:`~fusioncenter.figures.zheng2014.nonlinear` (Section VII.C: Figs. 7-10 and Table III);
they are not imported here (the registry loads them).

The scalar entries are split in five: :mod:`~fusioncenter.figures.zheng2014.common` (what these
entries share with those of :mod:`~fusioncenter.figures.zheng2014.vector` and
:mod:`~fusioncenter.figures.zheng2014.nonlinear`: run sizes, curves, paired differences, plots,
claims, registration), :mod:`~fusioncenter.figures.zheng2014.linear` (Figs. 1-2 and Table I,
with feedback), :mod:`~fusioncenter.figures.zheng2014.no_feedback` (Fig. 3),
:mod:`~fusioncenter.figures.zheng2014.choices` (the book's own sensitivity table) and
:mod:`~fusioncenter.figures.zheng2014.contrasts` (the paired contrasts of the nonlinear
entries). The names of the first four are re-exported here.

Every choice the paper leaves open is listed in each entry's ``parameters`` (from
:attr:`~fusioncenter.censoring.scenarios.linear.LinearScenario.choices`). All runs go through
:func:`fusioncenter.censoring.run`: for one seed the trials (truth and measurements) are shared
by every scheme and every ``l`` of an entry, so differences between curves are paired.

Data keys (plain NumPy arrays and numbers; the chapter ``book/zheng2014/results`` prints them):
see :data:`~fusioncenter.figures.zheng2014.linear.DATA_KEYS`.
"""

from fusioncenter.figures.zheng2014.common import LABELS, SCHEMES, Z_ORDER, Z_TOL

# The modules register their entries when imported: this order is the registry's.
# isort: off
from fusioncenter.figures.zheng2014.linear import (
    CHAPTER,
    DATA_KEYS,
    FIG1,
    FIG2,
    L_FIG2,
    OWN_IDS,
    PAPER_TABLE1,
    PARTICLES,
    PARTICLES_FIG2,
    TRIALS,
    TRIALS_FIG2,
    checks_fig1,
    checks_fig2,
    checks_table1,
    compute_fig1,
    compute_fig2,
    compute_table1,
    plot_fig1,
    plot_fig2,
    plot_table1,
)
from fusioncenter.figures.zheng2014.no_feedback import (
    FIG3,
    FIG3_CURVES,
    TRIALS_NOFB_HEAVY,
    checks_fig3,
    compute_fig3,
    plot_fig3,
)
from fusioncenter.figures.zheng2014.choices import (
    CHOICES,
    PARTICLES_CHOICES,
    TRIALS_CHOICES,
    checks_choices,
    compute_choices,
    plot_choices,
)
# isort: on

__all__ = [
    "CHAPTER", "CHOICES", "DATA_KEYS", "FIG1", "FIG2", "FIG3", "FIG3_CURVES", "LABELS", "L_FIG2",
    "OWN_IDS", "PAPER_TABLE1", "PARTICLES", "PARTICLES_CHOICES", "PARTICLES_FIG2", "SCHEMES",
    "TRIALS", "TRIALS_CHOICES", "TRIALS_FIG2", "TRIALS_NOFB_HEAVY", "Z_ORDER", "Z_TOL",
    "checks_choices", "checks_fig1", "checks_fig2", "checks_fig3", "checks_table1",
    "compute_choices", "compute_fig1", "compute_fig2", "compute_fig3", "compute_table1",
    "plot_choices", "plot_fig1", "plot_fig2", "plot_fig3", "plot_table1",
]
