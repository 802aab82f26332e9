"""Censoring with vector observations (zheng2014 Section V; Figs. 4-6, Table II): the silent
probability of a sensor whose measurement is a vector.

Sensor ``i`` observes ``z_k^i = H^i x_k + n_k^i`` (``n ~ N(0, R^i)``, dimension ``m``) and sends it
only if its normalized innovation squared is large (eq. (31)):
``nu^T S^{-1} nu >= eta``, ``nu = z - H xhat_{k|k-1}``, ``S = R + H P_{k|k-1} H^T``, with
``eta = chi2_m(l / N)`` (eq. (32), :func:`fusioncenter.censoring.threshold` with ``dof=m``).

A silent sensor contributes ``P(nu^T S^{-1} nu < eta | x)`` to the full likelihood, with
``nu ~ N(H (x - xhat), R)`` given the state: Proposition 4 writes it as ``P(q^T q < eta)`` for
``q = S^{-1/2} nu ~ N(S^{-1/2} H (x - xhat), S^{-1/2} R S^{-1/2})`` -- the distribution function of
a *generalized* non-central chi-square (a weighted sum of non-central chi-squares with one degree
of freedom each). The paper estimated it by sampling; here it is computed.

* :mod:`~fusioncenter.censoring.ellipse.quadrature`: the canonical form of the ellipse and the
  accurate quadrature (:func:`log_censored_probability`, :func:`log_silent_probability`);
* :mod:`~fusioncenter.censoring.ellipse.tables`: the interpolation tables the particle filter
  evaluates at every particle (:func:`log_silent_table`, :func:`log_silent_per_trial`,
  :func:`eval_silent`).

The vector likelihoods are in :mod:`fusioncenter.censoring.vector_likelihood`. The names below
are re-exported here."""

from __future__ import annotations

from fusioncenter.censoring.ellipse.quadrature import (
    MAX_ELONGATION,
    canonical_map,
    censored_probability,
    log_canon,
    log_canonical,
    log_censored_probability,
    log_inside_1d,
    log_silent_probability,
    theta_rule,
)
from fusioncenter.censoring.ellipse.tables import (
    PROBABILITIES,
    eval_silent,
    grid_terms,
    log_silent_per_trial,
    log_silent_table,
)

__all__ = [
    "MAX_ELONGATION", "PROBABILITIES", "canonical_map", "censored_probability", "eval_silent",
    "grid_terms", "log_canon", "log_canonical", "log_censored_probability", "log_inside_1d",
    "log_silent_per_trial", "log_silent_probability", "log_silent_table", "theta_rule",
]
