"""A bootstrap particle filter vectorized across Monte Carlo trials.

The design follows Chopin's ``particles`` package: the *model* (initial law, transition, the
log-likelihood of whatever the fusion centre received) is kept apart from the *algorithm* (the
one sequential Monte Carlo loop :func:`run_filter`), with one more leading axis for Monte Carlo
trials. Shapes:

* particles ``x``: ``(n, P, d)`` -- ``n`` independent trials, ``P`` particles, state dimension
  ``d``;
* log weights ``logw``: ``(n, P)``; every trial is normalized on its own (log-sum-exp);
* per-trial uniforms ``u``: ``(n,)`` (one systematic-resampling uniform per trial and step).

Everything that touches one trial's particles uses only that trial's row, so splitting the trials
into blocks (as :func:`fusioncenter.montecarlo.simulate` does) never changes a row's result.

The package is split by concept, and its names are re-exported here:
:mod:`~fusioncenter.particle.weights` (the NumPy functions on a weighted particle set:
normalization, ESS, weighted moments, systematic resampling),
:mod:`~fusioncenter.particle.dynamics` (:class:`LinearGaussianDynamics` and :func:`psd_factor`)
and :mod:`~fusioncenter.particle.loop` (:func:`run_filter`, :class:`FilterModel`,
:class:`FilterOutput` and the particles' layout :func:`by_component`).

Letters: the library's linear-Gaussian vocabulary (:mod:`fusioncenter.kalman`), ``x_t = A x_{t-1}
+ u``, ``u ~ N(0, Q)``, measurements ``C x + v``; zheng2014's ``F`` (for ``A``) and ``H`` (for
``C``) are aliases where a public class uses them (``LinearGaussianDynamics.F``, the censoring
scenarios' ``F`` and ``H``).

A model for :func:`run_filter` is any object with (see :class:`FilterModel`)

* ``dim`` -- the state dimension ``d``;
* ``initial(rng, n, P) -> (n, P, d)`` -- draw the particles of the prior of ``x_0``;
* ``transition(rng, t, x) -> (n, P, d)`` -- draw ``x_t`` given ``x_{t-1}`` for every particle;
* ``log_weight(t, x) -> (n, P)`` -- the incremental log weight at time ``t`` (the log-likelihood
  of the data received at ``t``; additive constants may be dropped); the loop normalizes it in
  place, so the model must not rely on its content afterwards (it may reuse the buffer);
* ``observe(t, mean, cov)`` -- called after weighting with the filter's estimate ``E[x_t | data]``
  ``(n, d)`` and its covariance ``(n, d, d)``: this is where a fusion centre records its estimate
  and prepares what it feeds back to the sensors for time ``t + 1``. May do nothing;
* optional ``needs_cov`` (default ``True``): ``False`` skips the weighted covariance (then
  ``observe`` receives ``cov=None`` and ``FilterOutput.cov`` is NaN).

Functions (signature, one line each):

* ``log_normalize(logw) -> (logw_normalized, log_sum)``: log-sum-exp over the last axis.
* ``ess(logw) -> (...)``: effective sample size ``1 / sum w^2`` of (any) log weights.
* ``systematic_counts(logw, u) -> int (..., P)``: offspring counts of systematic resampling.
* ``systematic_resample(logw, u) -> int (..., P)``: ancestor indices (sorted within a row).
* ``resample(x, idx)``: ``x[..., idx, :]`` row by row.
* ``weighted_mean(x, logw)``, ``weighted_mean_cov(x, logw)``: posterior mean (and covariance).
* ``LinearGaussianDynamics(A, Q, m0, P0)``: ``x_0 ~ N(m0, P0)``, ``x_t = A x_{t-1} + u``,
  ``u ~ N(0, Q)``; its ``initial`` / ``transition`` draw only ``rank(P0)`` / ``rank(Q)`` normals
  per particle.
* ``run_filter(model, rng, n_trials, n_particles, steps, *, ess_threshold=1.0) -> FilterOutput``.
"""

from fusioncenter.particle.dynamics import LinearGaussianDynamics, psd_factor
from fusioncenter.particle.loop import FilterModel, FilterOutput, by_component, run_filter
from fusioncenter.particle.weights import (
    ess,
    log_normalize,
    resample,
    systematic_counts,
    systematic_resample,
    weighted_mean,
    weighted_mean_cov,
)

__all__ = [
    "log_normalize",
    "ess",
    "systematic_counts",
    "systematic_resample",
    "resample",
    "weighted_mean",
    "weighted_mean_cov",
    "by_component",
    "psd_factor",
    "LinearGaussianDynamics",
    "FilterModel",
    "FilterOutput",
    "run_filter",
]
