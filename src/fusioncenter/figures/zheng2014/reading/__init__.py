"""zheng2014's results read across its three settings (scalar, vector, nonlinear): what the
chapter ``book/zheng2014/reading`` computes and checks.

Compute only (plain NumPy data and :class:`~fusioncenter.figures.registry.Claim` lists, no
plotting). The inputs are the ``compute`` outputs of the registry entries: Tables I-III
(``zheng2014-table1``, ``-table2``, ``-table3``) and the four-scheme figures (``zheng2014-fig1``,
``-fig3``, ``-fig4``, ``-fig6``, ``-fig8``, ``-fig9``). :func:`load_tables` and
:func:`load_payoff` compute them through the registry; the other functions take them as given,
so that the tests can feed corrupted data.

* :mod:`~fusioncenter.figures.zheng2014.reading.bounds`: the error arithmetic.
  ``delta_bound(gradient, stderr) -> float``, an upper bound on a delta-method standard error
  when only the marginal standard errors of the inputs are known; ``conservative_z``.
* :mod:`~fusioncenter.figures.zheng2014.reading.bandwidth`: Tables I-III.
  ``variance_ratio(sent, sent_se, l, N, dof=1) -> (v, v_se)``, the innovation variance, in units
  of the sensors' own normalizer, that makes ``sent`` of ``N`` sensors send at threshold
  ``censoring.threshold(l, N, dof)``; ``bandwidth_table(data, *, paper_trials, N, dof)``, one
  table (I, II or III) in a common form; ``side_by_side(tables, meta)`` all three;
  ``load_tables(profile, seed=None)`` from the registry; ``bandwidth_claims(tables) ->
  list[Claim]``, the paper's statements about the tables, and the differences of ours from the
  printed values, checked on the data.
* :mod:`~fusioncenter.figures.zheng2014.reading.payoff`: what the silences buy.
  ``payoff_rows(data) -> list[dict]``, what CFwMD wins back against CFoMD, all-send and random
  selection, one row per setting; ``gain_by_l(fig9)``, the nonlinear gain as ``l`` grows;
  ``load_payoff(profile, seed=None)`` both from the registry; ``payoff_claims(rows, sweep)``.

The names below are re-exported here."""

from __future__ import annotations

from fusioncenter.figures.zheng2014.reading.bandwidth import (
    SCHEMES,
    SETTINGS,
    TABLE_IDS,
    TABLE_NAMES,
    Z_AGREE,
    bandwidth_claims,
    bandwidth_table,
    load_tables,
    side_by_side,
    table_meta,
    variance_ratio,
)
from fusioncenter.figures.zheng2014.reading.bounds import Z_ORDER, conservative_z, delta_bound
from fusioncenter.figures.zheng2014.reading.payoff import (
    PAYOFF_IDS,
    gain_by_l,
    load_payoff,
    payoff_claims,
    payoff_rows,
)

__all__ = [
    "SETTINGS",
    "TABLE_IDS",
    "TABLE_NAMES",
    "SCHEMES",
    "Z_ORDER",
    "Z_AGREE",
    "delta_bound",
    "conservative_z",
    "variance_ratio",
    "bandwidth_table",
    "side_by_side",
    "table_meta",
    "load_tables",
    "bandwidth_claims",
    "PAYOFF_IDS",
    "payoff_rows",
    "gain_by_l",
    "load_payoff",
    "payoff_claims",
]
