"""Censoring by the normalized innovation squared, and fusion with the missing data (zheng2014).

Each sensor ``i`` observes ``z_k^i = h_i^T x_k + n_k^i`` (``n ~ N(0, r_i)``) and sends it to the
fusion centre (FC) only if its normalized innovation squared is large (eq. (4)):
``nu^2 / s >= eta``, ``nu = z - h^T xhat_{k|k-1}``, ``s = r + h^T P_{k|k-1} h``. The threshold
``eta = chi2_{n_nu}(l / N)`` (eq. (8)) makes ``l`` of the ``N`` sensors send on average when
``nu ~ N(0, s)``. A silent sensor is *not missing at random*; the FC's particle filter can use
the full likelihood ``p(z_obs, m | x)`` (CFwMD) or drop the silent sensors (CFoMD).

The package is split by concern (no module imports one that imports it back):
:mod:`~fusioncenter.censoring.probability` (the threshold, ``log P(|Z + m| < h)``, bivariate
normal probabilities), :mod:`~fusioncenter.censoring.tables` (interpolation tables),
:mod:`~fusioncenter.censoring.likelihood` (Propositions 1-3),
:mod:`~fusioncenter.censoring.scenarios` (the
:class:`~fusioncenter.censoring.scenarios.Scenario` base and :class:`LinearScenario`),
:mod:`~fusioncenter.censoring.fusion` (the fusion-centre models of
:func:`fusioncenter.particle.run_filter`: what they share, the linear FC and the exact
no-feedback filter), :mod:`~fusioncenter.censoring.results`
(:class:`CensoringResult`), :mod:`~fusioncenter.censoring.dispatch`
(:func:`~fusioncenter.censoring.dispatch.run`, the one dispatcher), and for Part IV(b)
:mod:`~fusioncenter.censoring.ellipse` (the vector silent probability: its quadrature and the
filter's tables), :mod:`~fusioncenter.censoring.vector`,
:mod:`~fusioncenter.censoring.vector_fusion` (the vector FCs, reference and fused, and their
``run``) and :mod:`~fusioncenter.censoring.nonlinear`. The names below are re-exported here.

Entry points (signature, one line each):

* ``threshold(l, N, dof=1) -> eta``: the chi-square upper ``l/N`` quantile, eq. (8).
* ``censored_probability(mu, s, r, eta)``: ``P(|nu| < sqrt(eta s))`` for ``nu ~ N(mu, r)``
  (the factor ``Q(xi_1) - Q(xi_2)`` of Propositions 1-3); ``log_censored_probability`` its log,
  finite far in the tails.
* ``bivariate_normal_cdf(h, k, rho)``, ``bivariate_rectangle(l1, u1, l2, u2, rho)``: standard
  bivariate normal probabilities through Owen's T (``scipy.special.owens_t``), vectorized.
* ``log_likelihood_feedback(sent, z, hx, hx_pred, s, r, eta)``: Propositions 1 and 2.
* ``log_likelihood_no_feedback(sent, z, hx, C, r, eta, version="corrected"|"printed")``:
  Proposition 3 as printed, and corrected (see below); ``run(..., likelihood="exact")`` uses the
  exact no-feedback filter instead.
* ``LinearScenario(N=2, r=1.0, sigma2=4.0, T=20, x0=(0, 10), ...)``: the model of Section VII.A.
* ``run(scenario, scheme, *, l, n_trials, n_particles, seed, feedback="state", ...)
  -> CensoringResult``: the four schemes at the FC, through ``montecarlo.simulate``. Every
  fusion centre is a model of the one particle-filter loop :func:`fusioncenter.particle.run_filter`:
  :class:`LinearFusionCentre` for every scheme,
  :class:`~fusioncenter.censoring.fusion.ExactFusionCentre` for the exact no-feedback filter.
* ``paired_difference(a, b, component="position") -> (diff, stderr)``: time-averaged RMSE of
  ``a`` minus that of ``b`` on the same trials, with its paired standard error.

Proposition 3 (no feedback). In (17)-(18) the paper sets ``p(m^i = 1 | z^i, xhat^i, x) = 1``
"again", as in the feedback case. Without feedback the local prediction ``xhat^i_{k|k-1}`` is
unknown to the FC and is integrated out, and for a received ``z^i`` the indicator
``1{|z^i - h^T xhat^i| >= sqrt(eta s^i)}`` restricts that integral: it is not 1. As printed, (16)
does not sum to one over the outcomes: summing over ``m`` and integrating over the received
values gives ``E[prod_i (1 + 1{|nu^i| < sqrt(eta s^i)})] = sum_{S} P(all sensors in S silent)``,
``(2 - l/N)^N`` for independent innovations (2.25 for ``N = 2, l = 1``). Worse, with the paper's
law (21) for the local predictions (``xhat^i = x - e^i``, ``e ~ N(0, Sigma_{k|k-1})`` independent
of ``x``), every factor of the printed (16) except the received Gaussians becomes a constant in
``x``: the printed CFwMD weights equal the CFoMD weights. The corrected likelihood keeps the
indicators: with ``eps_i = h_i^T e^i`` (covariance ``C_ij = h_i^T Sigma^{ij} h_j``),
``U_i = z^i - h_i^T x + eps_i`` for the received and ``V_j = eps_j + n^j`` for the silent sensors,

    p(m, z_obs | x) = prod_{i received} N(z^i; h_i^T x, r_i)
                      * P(|U_i| >= a_i for the received, |V_j| < a_j for the silent),

``a_i = sqrt(eta s_i)``: for ``N <= 2`` a bivariate normal rectangle probability. It sums to one
under the paper's model. It remains an approximation, because (21) treats the local prediction
errors as independent of ``x_k`` and of the FC's past data, which they are not (at ``k = 1`` with a
known ``x_0`` the FC even knows every local prediction exactly). ``likelihood="exact"`` removes
the approximation: the particles carry ``(x_k, xhat^1_{k|k-1}, ..., xhat^N_{k|k-1})``, a received
sensor contributes ``N(z^i; h^T x, r) 1{|z^i - h^T xhat^i| >= a_i}``, a silent one
``P(|h^T x + n - h^T xhat^j| < a_j)``, and each particle updates the local filters with the
received values or with draws of the missing ones from their truncated conditional law. With
feedback, Propositions 1-2 are already exact (the sensors' decisions depend on the broadcast,
which the FC knows). A test checks the consequence: the exact filters are calibrated (mean
squared error = mean posterior variance), CFoMD and Proposition 3 are not.
"""

from __future__ import annotations

from fusioncenter.censoring import (
    dispatch,
    ellipse,
    fusion,
    likelihood,
    nonlinear,
    probability,
    results,
    scenarios,
    tables,
    vector,
    vector_fusion,
)
from fusioncenter.censoring.dispatch import run
from fusioncenter.censoring.fusion import LinearFusionCentre
from fusioncenter.censoring.likelihood import log_likelihood_feedback, log_likelihood_no_feedback
from fusioncenter.censoring.probability import (
    bivariate_normal_cdf,
    bivariate_rectangle,
    censored_probability,
    log_censored_probability,
    threshold,
)
from fusioncenter.censoring.results import CensoringResult, Curve, paired_difference, trial_columns
from fusioncenter.censoring.scenarios import FEEDBACK, LIKELIHOODS, SCHEMES, LinearScenario

__all__ = [
    "dispatch", "ellipse", "fusion", "likelihood", "nonlinear", "probability", "results",
    "scenarios", "tables", "vector", "vector_fusion",
    "SCHEMES",
    "FEEDBACK",
    "LIKELIHOODS",
    "threshold",
    "censored_probability",
    "log_censored_probability",
    "bivariate_normal_cdf",
    "bivariate_rectangle",
    "log_likelihood_feedback",
    "log_likelihood_no_feedback",
    "LinearScenario",
    "Curve",
    "CensoringResult",
    "run",
    "paired_difference",
    "LinearFusionCentre",
    "trial_columns",
]
