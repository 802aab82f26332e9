"""The probability that a Gaussian innovation falls inside a sensor's silent ellipse, computed
accurately (zheng2014 Propositions 4-6): the canonical form of the ellipse and the quadrature.

Diagonalize: with ``R = L L^T`` and ``L^T S^{-1} L = V diag(lambda) V^T``, the variable
``u = V^T L^{-1} nu`` is ``N(b, I)`` with ``b = V^T L^{-1} mu`` and the silent region is the
ellipse ``sum_j u_j^2 / a_j^2 < 1``, ``a_j = sqrt(eta / lambda_j)`` (:func:`canonical_map`).
Integrating ``u_2`` exactly (a difference of normal distribution functions) and substituting
``u_1 = a_1 sin(theta)`` (which removes the square-root zero of the chord length at the ends),

    P = int_{-pi/2}^{pi/2} a_1 cos(theta) phi(a_1 sin(theta) - b_1)
                                    [Phi(a_2 cos(theta) - b_2) - Phi(-a_2 cos(theta) - b_2)] dtheta,

a smooth, positive integrand: Gauss-Legendre nodes in ``theta`` and a log-sum-exp give ``log P``
with no cancellation (:func:`log_canon`). In the tails the integrand is a narrow peak (the point
of the ellipse nearest the mean): the rule is applied again on the window where the integrand is
within ``e^-40`` of its largest node value (twice), which keeps full relative accuracy down to
``log P ~ -700`` and beyond."""

from __future__ import annotations

import functools
import math

import numpy as np
from scipy import special

from fusioncenter._compiled import censored_normal
from fusioncenter._validate import finite as _finite
from fusioncenter._validate import posint as _posint
from fusioncenter.censoring import probability as cprob
from fusioncenter.censoring.checks import (
    check_cholesky,
    check_eta,
    check_offsets,
    check_pd,
    check_psd,
)

_LOG_2PI = math.log(2.0 * math.pi)


# ----------------------------------------------------------------------------- canonical form
def canonical_map(S, R):
    """``(A_L, a_scale)`` with ``b = A_L @ nu_mean`` and ``a = sqrt(eta) * a_scale``.

    ``S``, ``R``: ``(..., m, m)`` positive definite. With ``R = L L^T`` and ``L^T S^{-1} L =
    V diag(lam) V^T``: ``A_L = V^T L^{-1}`` (rows ordered so that ``a`` is ascending:
    ``lam`` descending) and ``a_scale = 1 / sqrt(lam)``. Then ``P(nu^T S^{-1} nu < eta)`` for
    ``nu ~ N(mu, R)`` equals ``P(sum_j u_j^2 / a_j^2 < 1)`` for ``u ~ N(A_L mu, I)``.

    Parameters
    ----------
    S, R : numpy.ndarray
        Positive-definite matrices ``(..., m, m)`` (broadcast together).

    Returns
    -------
    A : numpy.ndarray
        ``A_L = V^T L^{-1}`` ``(..., m, m)``.
    a_scale : numpy.ndarray
        ``1 / sqrt(lam)`` ``(..., m)``, ascending.

    Raises
    ------
    ValueError
        Naming ``S`` or ``R`` if it is not finite or not positive definite.
    """
    check_cholesky("S", _finite("S", S))
    L = check_cholesky("R", _finite("R", R))
    Linv = np.linalg.inv(L)
    M = np.swapaxes(L, -1, -2) @ np.linalg.solve(S, L)
    M = 0.5 * (M + np.swapaxes(M, -1, -2))
    lam, V = np.linalg.eigh(M)  # ascending
    lam, V = lam[..., ::-1], V[..., :, ::-1]
    A = np.swapaxes(V, -1, -2) @ Linv
    return A, 1.0 / np.sqrt(lam)


@functools.cache
def theta_rule(K: int):
    """The ``K``-node Gauss-Legendre rule in ``theta`` on ``[-pi/2, pi/2]``.

    Parameters
    ----------
    K : int
        Number of Gauss-Legendre nodes.

    Returns
    -------
    tuple of numpy.ndarray
        ``(sin(theta_k), cos(theta_k), weights)`` of the rule on ``[-pi/2, pi/2]`` (cached).
    """
    x, w = np.polynomial.legendre.leggauss(K)
    th = 0.5 * math.pi * x
    return np.sin(th), np.cos(th), 0.5 * math.pi * w


def log_inside_1d(b, a):
    """``log P(|Z + b| < a)``, ``Z ~ N(0, 1)``:
    :func:`fusioncenter.censoring.probability.log_prob_inside` (broadcast).

    Parameters
    ----------
    b, a : array_like
        Offsets and half-widths (broadcast together).

    Returns
    -------
    numpy.ndarray
        ``log P(|Z + b| < a)``.

    Raises
    ------
    ValueError
        If ``b`` or ``a`` is NaN or ``a`` is negative (infinities are the limits).
    """
    check_offsets(("a",), b=b, a=a)
    b, a = np.broadcast_arrays(np.asarray(b, dtype=float), np.asarray(a, dtype=float))
    return censored_normal.log_prob_inside(b, a)


def _log_theta_integrand(th_s, th_c, b1, b2, a1, a2):
    """Log of the integrand in ``theta`` (nodes given by their sine and cosine)."""
    with np.errstate(divide="ignore"):
        lp = np.log(a1 * th_c) - 0.5 * _LOG_2PI - 0.5 * (a1 * th_s - b1) ** 2
    h = a2 * th_c
    return lp + cprob.log_censored_probability(b2, h * h, 1.0, 1.0)


def log_canon(b1, b2, a1, a2, *, K: int = 64, zooms: int = 2, drop: float = 40.0):
    """``log P(u_1^2/a_1^2 + u_2^2/a_2^2 < 1)``, ``u ~ N((b_1, b_2), I)``: accurate.

    Gauss-Legendre in ``theta`` (``K`` nodes), then up to ``zooms`` passes on the window of
    nodes within ``e^-drop`` of the largest (plus one node each side): the integrand is
    unimodal, so the window holds its peak, and outside it the mass is below ``e^-drop`` of the
    total. Points whose window is already the whole interval are not zoomed.

    Parameters
    ----------
    b1, b2 : array_like
        Mean of ``u`` in canonical coordinates (broadcast with ``a1``, ``a2``).
    a1, a2 : array_like
        Semi-axes of the ellipse, ``> 0``.
    K : int, optional
        Gauss-Legendre nodes per pass.
    zooms : int, optional
        Passes on the narrowed window.
    drop : float, optional
        Width of the window in the log integrand.

    Returns
    -------
    numpy.ndarray
        ``log P``, shaped like the broadcast inputs.

    Raises
    ------
    ValueError
        If ``b1`` or ``b2`` is not finite, ``a1`` or ``a2`` not positive and finite, or ``K``
        not a positive integer.
    """
    check_offsets(("a1", "a2"), True, b1=b1, b2=b2, a1=a1, a2=a2)
    K = _posint("K", K)  # numpy's leggauss would say "deg"
    b1, b2, a1, a2 = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (b1, b2, a1, a2)))
    shape = b1.shape
    b1, b2, a1, a2 = (np.abs(v).reshape(-1, 1) for v in (b1, b2, a1, a2))
    # the substituted axis (u_1 = a_1 sin theta) is the longer one: the chord along the short
    # axis is then a smooth function of theta (with a_2 >> a_1 it would jump from ~1 to 0 near
    # theta = +/- pi/2 and cost accuracy: 2e-9 at a = (2, 30), b = (0, 12))
    swap = a1 < a2
    b1, b2 = np.where(swap, b2, b1), np.where(swap, b1, b2)
    a1, a2 = np.where(swap, a2, a1), np.where(swap, a1, a2)
    out = np.empty(b1.shape[0])
    x, w = np.polynomial.legendre.leggauss(K)
    logw = np.log(w)
    idx = np.arange(K)
    todo = np.arange(b1.shape[0])
    lo = np.full((b1.shape[0], 1), -0.5 * math.pi)
    hi = -lo
    for it in range(zooms + 1):
        if todo.size == 0:
            break
        half, mid = 0.5 * (hi[todo] - lo[todo]), 0.5 * (hi[todo] + lo[todo])
        th = mid + half * x
        lf = _log_theta_integrand(np.sin(th), np.cos(th), b1[todo], b2[todo], a1[todo],
                                  a2[todo])
        val = special.logsumexp(lf + logw, axis=1) + np.log(half[:, 0])
        out[todo] = val
        if it == zooms:
            break
        mx = lf.max(axis=1, keepdims=True)
        keep = lf >= mx - drop
        first = np.where(keep, idx, K).min(axis=1, keepdims=True) - 1
        last = np.where(keep, idx, -1).max(axis=1, keepdims=True) + 1
        whole = (first < 0) & (last > K - 1)
        new_lo = np.where(first >= 0, np.take_along_axis(th, np.clip(first, 0, K - 1), 1),
                          lo[todo])
        new_hi = np.where(last <= K - 1, np.take_along_axis(th, np.clip(last, 0, K - 1), 1),
                          hi[todo])
        lo[todo], hi[todo] = new_lo, new_hi
        todo = todo[~whole[:, 0]]
    return out.reshape(shape)


def log_canonical(b, a):
    """``log P(sum_j u_j^2 / a_j^2 < 1)`` for ``u ~ N(b, I)``, ``m`` in {1, 2} (accurate:
    :func:`log_inside_1d`, :func:`log_canon`).

    Parameters
    ----------
    b : numpy.ndarray
        Means ``(..., m)`` in canonical coordinates.
    a : numpy.ndarray
        Semi-axes ``(..., m)``.

    Returns
    -------
    numpy.ndarray
        ``log P`` ``(...)``.
    """
    if b.shape[-1] == 1:
        return log_inside_1d(b[..., 0], a[..., 0])
    return log_canon(b[..., 0], b[..., 1], a[..., 0], a[..., 1])


def _means(name: str, value) -> np.ndarray:
    """Mean vectors ``(..., m)``, ``m`` in {1, 2}."""
    arr = _finite(name, value)
    if arr.ndim < 1 or arr.shape[-1] not in (1, 2):
        raise ValueError(f"{name} must have its last axis of length m in (1, 2), got {arr.shape}")
    return arr


def _log_in_ellipse(A, a_scale, mean, eta: float):
    """:func:`log_canonical` at ``b = A mean``, semi-axes ``sqrt(eta) a_scale`` (a canonical map
    of :func:`canonical_map`); a scalar for a single point."""
    b = (A @ mean[..., None])[..., 0]
    out = log_canonical(b, math.sqrt(eta) * a_scale)
    return out[()] if out.ndim == 0 else out


def log_censored_probability(mean, cov, eta):
    """``log P(q^T q < eta)`` for ``q ~ N(mean, cov)``: the silent factor of Propositions 4-6.

    ``mean (..., m)``, ``cov (..., m, m)`` positive semi-definite (they broadcast; a singular
    ``cov`` is the exact limit :func:`fusioncenter.censoring.probability.log_inside_degenerate`,
    ``-inf`` where the probability is 0), ``m`` in {1, 2},
    ``eta >= 0``. ``q^T q`` has a generalized non-central chi-square law; with
    ``cov = sigma^2 I`` it is ``sigma^2`` times a non-central chi-square with ``m`` degrees of
    freedom and non-centrality ``|mean|^2 / sigma^2`` (``scipy.stats.ncx2``). Computed by the
    quadrature of the module docstring: relative error ~1e-13 (checked against mpmath), finite
    however far the mean lies outside the disc. ``-inf`` if ``eta = 0``.

    Parameters
    ----------
    mean : array_like
        Means ``(..., m)`` of ``q``.
    cov : array_like
        Covariances ``(..., m, m)``, positive semi-definite (singular allowed).
    eta : float
        Threshold, ``>= 0``.

    Returns
    -------
    numpy.ndarray or float
        ``log P(q^T q < eta)``, shape ``(...)``.
    """
    eta = check_eta(eta)
    mean = _means("mean", mean)
    m = mean.shape[-1]
    cov, singular = check_psd("cov", cov, m)
    if singular.any():
        return _split_singular(mean, cov, singular, eta, "cov")
    A, asc = canonical_map(np.broadcast_to(np.eye(m), cov.shape), cov)
    return _log_in_ellipse(A, _resolvable("cov", asc), mean, eta)


def _split_singular(mean, cov, singular, eta, name):
    """:func:`log_censored_probability` of checked arguments, some ``cov`` singular
    (:func:`fusioncenter.censoring.probability.log_inside_degenerate` there)."""
    shp = np.broadcast_shapes(mean.shape[:-1], cov.shape[:-2])
    m = mean.shape[-1]
    mean, cov = np.broadcast_to(mean, (*shp, m)), np.broadcast_to(cov, (*shp, m, m))
    sing = np.broadcast_to(singular, shp)
    out = np.empty(shp)
    if not sing.all():
        A, asc = canonical_map(np.broadcast_to(np.eye(m), cov[~sing].shape), cov[~sing])
        out[~sing] = _log_in_ellipse(A, _resolvable(name, asc), mean[~sing], eta)
    out[sing] = censored_normal.log_inside_degenerate(mean[sing], cov[sing], eta)
    return out[()] if out.ndim == 0 else out


def censored_probability(mean, cov, eta):
    """``P(q^T q < eta)`` for ``q ~ N(mean, cov)`` (see :func:`log_censored_probability`).

    Parameters
    ----------
    mean, cov, eta
        As in :func:`log_censored_probability`.

    Returns
    -------
    numpy.ndarray or float
        ``P(q^T q < eta)`` in ``[0, 1]``.
    """
    return np.exp(log_censored_probability(mean, cov, eta))


def log_silent_probability(mu, S, R, eta):
    """``log P(nu^T S^{-1} nu < eta)`` for ``nu ~ N(mu, R)``: a silent sensor's factor.

    ``mu = H (x - xhat)``: the innovation's mean given the state; ``R``: its covariance given the
    state; ``S``: the covariance the sensor normalizes by (its own ``S_k^i`` for Proposition 4,
    ``S'^i_k`` for Proposition 5). Equal to :func:`log_censored_probability` of
    ``q = S^{-1/2} nu ~ N(S^{-1/2} mu, S^{-1/2} R S^{-1/2})`` (eqs. (35)-(38)).

    Parameters
    ----------
    mu : array_like
        Innovation means ``(..., m)`` given the state.
    S : array_like
        Normalizing covariances ``(..., m, m)``, positive definite.
    R : array_like
        Innovation covariances ``(..., m, m)`` given the state, positive semi-definite
        (singular allowed: the exact degenerate limit).
    eta : float
        Threshold, ``>= 0``.

    Returns
    -------
    numpy.ndarray or float
        ``log P(nu^T S^{-1} nu < eta)``, shape ``(...)``.
    """
    eta = check_eta(eta)
    mu = _means("mu", mu)
    m = mu.shape[-1]
    S = check_pd("S", S, m)
    R, singular = check_psd("R", R, m)
    S, R = np.broadcast_arrays(S, R)
    if singular.any():  # q = L^{-1} nu ~ N(L^{-1} mu, L^{-1} R L^{-T}), S = L L^T
        Li = np.linalg.inv(np.linalg.cholesky(S))
        cov = Li @ R @ np.swapaxes(Li, -1, -2)
        cov, singular = check_psd("R", cov, m)
        return _split_singular((Li @ mu[..., None])[..., 0], cov, singular, eta, "R")
    A, asc = canonical_map(S, R)
    return _log_in_ellipse(A, _resolvable("R", asc), mu, eta)


#: Largest ratio of the canonical semi-axes the quadrature resolves to ~1e-13 (measured against
#: mpmath: 1e-14 at 1800, 2e-10 at 3200, 1e-3 beyond 6000; a covariance eigenvalue ratio
#: below 1e-12 is the exact singular limit instead).
MAX_ELONGATION = 1e3


def _resolvable(name: str, a_scale):
    """``a_scale``, or ``ValueError`` naming ``name`` if the ellipse is too elongated."""
    ratio = a_scale[..., -1] / a_scale[..., 0]
    if np.any(ratio > MAX_ELONGATION):
        raise ValueError(f"{name} is too elongated for the quadrature: semi-axis ratio "
                         f"{float(np.max(ratio)):.3g} > {MAX_ELONGATION:g} (an eigenvalue ratio "
                         "between 1e-12, treated as singular, and 1e-6)")
    return a_scale
