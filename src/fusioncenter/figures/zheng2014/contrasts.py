"""Paired contrasts of runs that share their trials (the nonlinear entries of zheng2014).

The runs of :mod:`fusioncenter.figures.zheng2014.nonlinear` share the truth and the
measurements of every trial, so a weighted sum of their time-averaged RMSEs
(:func:`contrast`) or of their average numbers of transmissions per step
(:func:`tx_contrast`) has a paired standard error: the per-trial (influence) values of the
terms are combined trial by trial before their spread is taken. :func:`z_score` is the
difference over its standard error, infinite for an exact nonzero difference.
"""

from __future__ import annotations

import math

import numpy as np

from fusioncenter import censoring
from fusioncenter.figures.common import document

__all__ = ["contrast", "tx_contrast", "z_score"]


def _sq(res: censoring.CensoringResult, component: str) -> np.ndarray:
    sc = res.scenario
    idx = sc.position_index if component == "position" else sc.velocity_index
    return res.mc.samples[..., list(idx)].sum(axis=-1)  # (n, T)


def _influence(res, component: str = "position", steps=slice(None)):
    """Mean over ``steps`` of the RMSE, and its per-trial influence values (delta method)."""
    sq = _sq(res, component)[:, steps]
    rm = np.sqrt(sq.mean(axis=0))
    with np.errstate(divide="ignore", invalid="ignore"):
        infl = np.where(rm > 0, sq / (2 * rm), 0.0).mean(axis=1)
    return float(rm.mean()), infl


@document(returns=(("float", "The contrast."),
                   ("float", "Its paired standard error (NaN for a single trial).")),
          terms=("sequence of tuple", "``(w_j, run_j)`` or ``(w_j, run_j, steps_j)``: a weight "
                 "and a :class:`~fusioncenter.censoring.results.CensoringResult`, the runs on the "
                 "same trials."),
          component=("str", "``position`` or ``velocity``."), raises=(),
          steps=("slice", "The steps averaged over in the terms that give none (default: all)."))
def contrast(terms, component: str = "position", steps=slice(None)) -> tuple[float, float]:
    """``sum_j w_j RMSEbar_j`` over the runs ``terms = [(w_j, run_j), ...]`` (``RMSEbar`` the
    RMSE averaged over ``steps``; a term ``(w_j, run_j, steps_j)`` uses its own steps), with its
    paired standard error: the runs share their trials, so the per-trial influence values are
    combined trial by trial."""
    value, infl = 0.0, 0.0
    for term in terms:
        w, res = term[0], term[1]
        v, i = _influence(res, component, term[2] if len(term) > 2 else steps)
        value += w * v
        infl = infl + w * i
    n = infl.size
    return float(value), float(infl.std(ddof=1) / math.sqrt(n)) if n > 1 else math.nan


@document(returns=(("float", "The contrast."), ("float", "Its paired standard error.")),
          terms=("sequence of tuple", "``(w_j, run_j)`` pairs, the runs on the same trials."),
          raises=())
def tx_contrast(terms) -> tuple[float, float]:
    """``sum_j w_j lbar_j`` (average transmissions per step) with its paired standard error."""
    per = sum(w * res.mc.samples[..., res.scenario.d].mean(axis=1) for w, res in terms)
    return float(per.mean()), float(per.std(ddof=1) / math.sqrt(per.size))


@document(returns=("float", "``value / se``; for ``se = 0``, infinite with the sign of "
                   "``value``, or 0 if ``value`` is 0 too."), raises=(),
          value=("float", "A difference."), se=("float", "Its standard error."))
def z_score(value: float, se: float) -> float:
    """A difference in standard errors, defined when the standard error is 0 (identical runs)."""
    return value / se if se > 0 else math.copysign(math.inf, value) if value else 0.0
