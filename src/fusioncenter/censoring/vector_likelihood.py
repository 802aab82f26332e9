"""The likelihoods of what the fusion centre receives with vector observations (zheng2014
Propositions 4-6): with feedback, and the printed no-feedback Proposition 6 (see
:mod:`fusioncenter.censoring.vector` for its erratum). The silent factor is
:func:`fusioncenter.censoring.ellipse.log_silent_probability`; the paper estimated it by
sampling (:func:`censored_probability_sampled`)."""

from __future__ import annotations

import math

import numpy as np

from fusioncenter._validate import broadcast as _broadcast
from fusioncenter._validate import finite as _finite
from fusioncenter._validate import posint as _posint
from fusioncenter._validate import received as _received
from fusioncenter.censoring.checks import check_eta, check_pd, check_psd
from fusioncenter.censoring.ellipse import log_silent_probability

_LOG_2PI = math.log(2.0 * math.pi)


def log_likelihood_feedback(sent, z, Hx, Hx_pred, S, R, eta):
    """Propositions 4 and 5: ``log p(z_obs, m | x, xhat_{k|k-1})`` with feedback.

    ``sum_{received} log N(z^i; H^i x, R^i) + sum_{silent} log P(nu^T S_i^{-1} nu < eta)`` with
    ``nu ~ N(H^i (x - xhat), R^i)``. Shapes broadcast: ``sent (..., N)`` (bool), ``z``, ``Hx =
    H^i x``, ``Hx_pred = H^i xhat_{k|k-1}``: ``(..., N, m)`` (``z`` is ignored where not sent),
    ``S`` (the sensors' own ``S_k^i``: Proposition 4; ``S'^i_k`` from the fed-back covariance:
    Proposition 5) and ``R``: ``(..., N, m, m)``. Returns ``(...)``.

    Parameters
    ----------
    sent : array_like
        Who sent, bool ``(..., N)``.
    z, Hx, Hx_pred : array_like
        Measurements, ``H^i x`` and ``H^i xhat_{k|k-1}``, ``(..., N, m)``.
    S, R : array_like
        Normalizing and noise covariances ``(..., N, m, m)``, positive definite.
    eta : float
        The censoring threshold (non-negative).

    Returns
    -------
    numpy.ndarray
        ``log p(z_obs, m | x, xhat_{k|k-1})`` per leading index.

    Raises
    ------
    ValueError
        Naming the argument that is not finite (``z`` only where a sensor sent), not positive
        definite (``S``, ``R``), negative (``eta``) or of non-matching shape.
    """
    sent, z = _received(sent, z, axis_extra=1)
    Hx = _finite("Hx", Hx)
    Hx_pred = _finite("Hx_pred", Hx_pred)
    _broadcast(z=z, Hx=Hx, Hx_pred=Hx_pred)
    m = Hx.shape[-1]
    S = check_pd("S", S, m)
    R = check_pd("R", R, m)
    eta = check_eta(eta)
    z = np.where(sent[..., None], z, Hx)
    recv = np.where(sent, _log_gauss_each(z, Hx, R), 0.0)
    with np.errstate(invalid="ignore"):
        sil = np.where(sent, 0.0, log_silent_probability(Hx - Hx_pred, S, R, eta))
    return (recv + sil).sum(axis=-1)


def _log_gauss_each(z, y, R):
    """``log N(z_i; y_i, R_i)`` per sensor: ``z, y (..., N, m)``, ``R (..., N, m, m)``."""
    L = np.linalg.cholesky(R)
    d = np.linalg.solve(L, (z - y)[..., None])[..., 0]
    m = z.shape[-1]
    logdet = 2.0 * np.log(np.diagonal(L, axis1=-2, axis2=-1)).sum(axis=-1)
    return -0.5 * (m * _LOG_2PI + logdet + (d * d).sum(axis=-1))


def log_likelihood_no_feedback_printed(sent, z, Hx, R, log_all_silent):
    """Proposition 6 as printed, under the paper's law (21): ``log p(m, z_obs | x)``.

    With (21) the local prediction errors ``e^j = x - xhat^j`` are ``N(0, Sigma)`` independent
    of ``x``, so ``t^j ~ N(S^{-1/2} H e^j, S^{-1/2} R S^{-1/2})`` of (40) has a law free of
    ``x`` and the integral of the silent factors is the constant ``log_all_silent =
    log P(all silent sensors' V_j^T S_j^{-1} V_j < eta)``, ``V_j = H e^j + n^j`` (see
    :func:`log_all_silent`): only the received Gaussians depend on ``x`` -- the CFoMD weights.

    Parameters
    ----------
    sent : array_like
        Who sent, bool ``(..., N)``.
    z, Hx : array_like
        Measurements and ``H^i x``, ``(..., N, m)``.
    R : array_like
        Noise covariances ``(..., N, m, m)``, positive definite.
    log_all_silent : array_like
        The constant of the silent set, broadcast to ``(...)``.

    Returns
    -------
    numpy.ndarray
        ``log p(m, z_obs | x)``: the received Gaussians plus the constant.
    """
    sent = np.asarray(sent, dtype=bool)
    Hx = _finite("Hx", Hx)
    R = check_pd("R", R, Hx.shape[-1])
    z = np.where(sent[..., None], z, Hx)
    recv = np.where(sent, _log_gauss_each(z, Hx, R), 0.0).sum(axis=-1)
    return recv + np.asarray(log_all_silent, dtype=float)


def censored_probability_sampled(mean, cov, eta, *, n_samples: int, rng: np.random.Generator):
    """The paper's estimate of ``P(q^T q < eta)``: the fraction of ``n_samples`` draws of
    ``q ~ N(mean, cov)`` inside the disc (Section VII.B). Unbiased, standard error
    ``sqrt(P (1 - P) / n_samples)``; ``0`` whenever no draw falls inside.

    Parameters
    ----------
    mean, cov, eta
        As in :func:`fusioncenter.censoring.ellipse.log_censored_probability`
        (``cov`` positive semi-definite, singular allowed).
    n_samples : int
        Draws per point.
    rng : numpy.random.Generator
        Source of the draws.

    Returns
    -------
    numpy.ndarray
        The fraction of the draws inside the disc, per point.
    """
    eta = check_eta(eta)
    n_samples = _posint("n_samples", n_samples)
    mean = _finite("mean", mean)
    if mean.ndim < 1:
        raise ValueError("mean must have a last axis (the dimension m)")
    m = mean.shape[-1]
    cov, singular = check_psd("cov", cov, m)
    if singular.any():  # a factor of a singular covariance: V sqrt(lam)
        lam, V = np.linalg.eigh(cov)
        L = V * np.sqrt(np.maximum(lam, 0.0))[..., None, :]
    else:
        L = np.linalg.cholesky(cov)
    shape = np.broadcast_shapes(mean.shape[:-1], cov.shape[:-2])
    count = np.zeros(shape)
    for _ in range(n_samples):  # one draw per point at a time: memory O(points)
        y = rng.standard_normal((*shape, m))
        q = mean + (L @ y[..., None])[..., 0]
        count += (q * q).sum(axis=-1) < eta
    return count / n_samples
