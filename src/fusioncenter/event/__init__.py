"""Event-based estimation with a stochastic trigger (mo2015), and the event-triggered Kalman filter.

The one-shot problem of the notes: ``x ~ N(xbar, Sigma)`` (``n`` states), ``m`` sensors
``y_i = a_i x + v_i`` with ``v_i ~ N(0, r_i)``; the rows of ``C`` (shape ``(m, n)``) are the
``a_i`` and ``R = diag(r_1, ..., r_m)``. Sensor ``i`` draws ``xi_i ~ U[0, 1]`` and sends
(``gamma_i = 1``) iff ``xi_i > exp(-y_i^2 / (2 delta_i))``. We assume, as the derivation needs but
the notes leave implicit, that ``x, v_1, ..., v_m, xi_1, ..., xi_m`` are mutually independent (and,
in the filter, independent across time). The fusion centre knows ``gamma`` and ``gamma_i y_i``.

Because ``E[exp(-y^2/(2 delta)) | x] = sqrt(delta/(delta + r)) exp(-(a x)^2 / (2 (r + delta)))``,
a silent sensor acts exactly like the measurement ``0 = a_i x + noise`` with noise variance
``r_i + delta_i``; the posterior stays Gaussian:

    xhat = xbar + Sigma C^T (C Sigma C^T + R + (I - Gamma) Delta)^{-1} (Gamma y - C xbar)
    P    = Sigma - Sigma C^T (C Sigma C^T + R + (I - Gamma) Delta)^{-1} C Sigma.

Send probability of a sensor whose ``y ~ N(mu, s)`` (``s = r_i + a_i Sigma a_i^T``,
``mu = a_i xbar``): ``1 - sqrt(delta / (delta + s)) exp(-mu^2 / (2 (delta + s)))``.

The event-triggered Kalman filter (not in the notes): ``x_{k+1} = A x_k + w_k``,
``y_{i,k} = c_i x_k + v_{i,k}``. Sensor ``i`` triggers on its *innovation*
``z_{i,k} = y_{i,k} - c_i xhat_{k|k-1}``. It needs ``xhat_{k|k-1}``: the fusion centre broadcasts
it (zheng2014's "feedback system"), or broadcasts what it received so that every sensor can run
a replica of the centre's filter, which depends on received data only. Given the past, the
centre's prior for ``x_k`` is ``N(xhat_{k|k-1}, P_{k|k-1})``, so the innovation has a zero-mean
Gaussian prior and the one-shot result applies exactly at every step: a silent sensor is the
measurement ``z_i = 0`` with variance ``r_i + delta_i``. The filter is the exact MMSE filter;
its covariance follows the Riccati recursion with the random noise covariance
``R_k = R + (I - Gamma_k) Delta``, so every Monte Carlo trial carries its own ``P``.

Functions (signature, one line each):

* ``trigger_probability(s, delta, mu=0.0)``: P(send) for one sensor with ``y ~ N(mu, s)``.
* ``communication_rate(Sigma, C, R, delta, xbar=None) -> (m,)``: P(gamma_i = 1) per sensor.
* ``delta_for_rate(rate, s, mu=0.0)``: the ``delta`` giving a send probability ``rate``.
* ``sample_trigger(rng, y, delta) -> bool (..., m)``: draw the stochastic trigger.
* ``posterior(xbar, Sigma, C, R, delta, gamma, y) -> (xhat (..., n), P (..., n, n))``:
  ``E(x | I)`` and ``Cov(x | I)``, batched over leading axes.
* ``steady_state_delta(model, rate, method="mean-information") -> (m,)``: per-sensor ``delta``
  for a target long-run send rate in the filter (deterministic approximation; see its docstring).
* ``calibrate_delta(model, rate, *, n_trials=2000, steps=60, burn_in=30, seed=0, ...)
  -> Calibration``: ``delta`` that hits the target long-run rate in simulation (secant search
  with common random numbers), with the achieved rate and its standard error.
* ``event_kf_run(model, steps, scheme, rng, n_trials, *, delta=None, p=None) -> EventKFRun``:
  the event-triggered Kalman filter on ``n_trials`` simulated trajectories at once.
* ``event_kf_chunk(rng, n, *, model, steps, scheme, delta=None, p=None) -> (n, steps+1, cols)``:
  per-trial summary for :func:`fusioncenter.montecarlo.simulate`; ``split_summary`` names it.
* ``split_summary(arr, nx) -> dict``: the columns of an ``event_kf_chunk`` array by name.

The package: :mod:`~fusioncenter.event.trigger` (the one-shot closed forms and the posterior),
:mod:`~fusioncenter.event.kf` (the filter, which advances with
:func:`fusioncenter.kalman.kalman_step`) and :mod:`~fusioncenter.event.rate` (the trigger
parameter for a target send rate); the names above are re-exported here.
"""

from __future__ import annotations

from fusioncenter.event.kf import SCHEMES, EventKFRun, event_kf_chunk, event_kf_run, split_summary
from fusioncenter.event.rate import Calibration, calibrate_delta, steady_state_delta
from fusioncenter.event.trigger import (
    communication_rate,
    delta_for_rate,
    posterior,
    sample_trigger,
    trigger_probability,
)

__all__ = [
    "SCHEMES",
    "trigger_probability",
    "communication_rate",
    "delta_for_rate",
    "sample_trigger",
    "posterior",
    "steady_state_delta",
    "Calibration",
    "calibrate_delta",
    "EventKFRun",
    "event_kf_run",
    "event_kf_chunk",
    "split_summary",
]
