"""Probabilities of a bivariate normal, unchecked (zheng2014 Proposition 3, corrected): the
distribution function by Owen's T (:func:`cdf_owen`), the probability of a rectangle and its log
(:func:`bivariate_rectangle`, :func:`log_bivariate_rectangle`: the inclusion-exclusion of four
distribution functions where that is accurate, a log-domain quadrature where it would cancel),
the region of the corrected Proposition 3, a union of such rectangles
(:func:`log_region_probability`), and the all-silent constant of the printed one
(:func:`log_silent_constant`; SciPy's multivariate normal beyond two sensors).

NumPy and SciPy, not numba: the unchecked kernels the filters and their tables call on arrays
they have checked. :mod:`fusioncenter.censoring.probability` documents and checks the public
functions of the same names (``log_region_probability`` and ``log_silent_constant`` take their
documentation from here; their references are to the public names).
"""

from __future__ import annotations

import math

import numpy as np
import scipy.stats
from scipy import special

from fusioncenter._compiled.censored_normal import prob_inside

__all__ = ["cdf_owen", "CAREFUL_BELOW", "RHO_DEGENERATE", "bivariate_rectangle",
           "log_bivariate_rectangle", "log_region_probability", "log_silent_constant"]

_LOG_2PI = math.log(2.0 * math.pi)


# --------------------------------------------------------------------------------- bivariate normal
def cdf_owen(h, k, rho):
    """``P(X <= h, Y <= k)`` for a standard bivariate normal with correlation ``rho``.

    Owen (1956): ``Phi2 = (Phi(h) + Phi(k))/2 - T(h, a_h) - T(k, a_k) - beta`` with
    ``a_h = (k - rho h)/(h sqrt(1 - rho^2))``, ``a_k = (h - rho k)/(k sqrt(1 - rho^2))``,
    ``beta = 1/2`` if ``h k < 0`` and 0 otherwise (exact zeros of ``h`` or ``k`` are nudged to
    ``1e-300``; the limit is continuous). ``|rho| = 1`` (up to ``1e-12``) uses the degenerate
    laws ``Phi(min(h, k))`` and ``max(Phi(h) + Phi(k) - 1, 0)``. Infinite ``h``, ``k`` are
    allowed. Vectorized through ``scipy.special.owens_t``; absolute accuracy ~1e-15. The
    arguments broadcast as those of
    :func:`fusioncenter.censoring.probability.bivariate_normal_cdf` (which uses this where the
    probability is not small); the result is clipped to ``[0, 1]``, a float for scalar inputs.
    A NaN argument or ``|rho| > 1`` raises a ``ValueError``.
    """
    h, k, rho = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (h, k, rho)))
    if np.any(np.isnan(h)) or np.any(np.isnan(k)) or np.any(np.isnan(rho)):
        raise ValueError("h, k and rho must not be NaN")
    if np.any(np.abs(rho) > 1):
        raise ValueError("rho must lie in [-1, 1]")
    out = np.empty(h.shape)
    deg = np.abs(rho) >= 1 - 1e-12
    inf = ~np.isfinite(h) | ~np.isfinite(k)
    reg = ~deg & ~inf
    if reg.any():
        hh, kk, rr = h[reg], k[reg], rho[reg]
        hh = np.where(hh == 0, 1e-300, hh)
        kk = np.where(kk == 0, 1e-300, kk)
        q = np.sqrt((1 - rr) * (1 + rr))
        with np.errstate(over="ignore"):
            ah = (kk - rr * hh) / (hh * q)
            ak = (hh - rr * kk) / (kk * q)
        beta = np.where(hh * kk < 0, 0.5, 0.0)
        out[reg] = (0.5 * (special.ndtr(hh) + special.ndtr(kk)) - special.owens_t(hh, ah)
                    - special.owens_t(kk, ak) - beta)
    if inf.any():  # one bound infinite: a univariate probability (or 0 / 1)
        hh, kk = h[inf], k[inf]
        out[inf] = np.where((hh == -np.inf) | (kk == -np.inf), 0.0,
                            np.where(hh == np.inf, special.ndtr(kk), special.ndtr(hh)))
    d = deg & ~inf
    if d.any():
        hh, kk, rr = h[d], k[d], rho[d]
        pos = np.minimum(special.ndtr(hh), special.ndtr(kk))
        neg = np.maximum(special.ndtr(hh) + special.ndtr(kk) - 1.0, 0.0)
        out[d] = np.where(rr > 0, pos, neg)
    out = np.clip(out, 0.0, 1.0)
    return out[()] if out.ndim == 0 else out


#: Below this value the inclusion-exclusion of Owen's-T distribution functions (absolute accuracy
#: ~1e-16) is replaced by the quadrature of :func:`_log_rectangle_quadrature`.
CAREFUL_BELOW = 1e-5


#: Below ``|rho| = 1 - RHO_DEGENERATE`` the quadrature resolves the conditional law of ``Y``.
RHO_DEGENERATE = 1e-6


def _rectangle_owen(l1, u1, l2, u2, rho):
    """Inclusion-exclusion of four :func:`cdf_owen` values (absolute accuracy ~1e-16): what
    the fast path of :func:`log_bivariate_rectangle` and :func:`log_region_probability`."""
    F = cdf_owen
    return F(u1, u2, rho) - F(l1, u2, rho) - F(u1, l2, rho) + F(l1, l2, rho)


def _log_interval(A, B):
    """``log P(A < Z < B)`` for ``Z ~ N(0, 1)``, elementwise, without cancellation."""
    out = np.zeros(np.broadcast_shapes(A.shape, B.shape))
    A, B = np.broadcast_arrays(A, B)
    both = np.isfinite(A) & np.isfinite(B)
    lo_only = np.isfinite(A) & ~np.isfinite(B)
    hi_only = ~np.isfinite(A) & np.isfinite(B)
    if both.any():
        c, h = 0.5 * (A[both] + B[both]), 0.5 * (B[both] - A[both])
        out[both] = prob_inside(-c, np.maximum(h, 0.0), log=True)
    if lo_only.any():
        out[lo_only] = special.log_ndtr(-A[lo_only])
    if hi_only.any():
        out[hi_only] = special.log_ndtr(B[hi_only])
    return out


def _log_rectangle_quadrature(l1, u1, l2, u2, rho, *, K: int = 48, zooms: int = 4,
                              drop: float = 45.0):
    """``log P(l1 < X < u1, l2 < Y < u2)`` by quadrature in ``x`` of
    ``phi(x) P(l2 < Y < u2 | x)``, in the log domain (1-d arrays, ``l1 < u1``, ``l2 < u2``,
    ``|rho| < 1``).

    The integrand is log-concave (a product of log-concave factors), hence unimodal: a
    ``K``-point Gauss-Legendre rule on the window ``[max(l1, m - 40), min(u1, m + 40)]``
    (``m`` the point of ``[l1, u1]`` nearest 0) is narrowed ``zooms`` times to the nodes where
    the log integrand is within ``drop`` of its largest value, then applied with a log-sum-exp.
    The conditional probability is :func:`_log_interval` of the standardized bounds: no
    cancellation anywhere, so the relative accuracy holds however small the probability.
    """
    q = np.sqrt((1.0 - rho) * (1.0 + rho))
    m0 = np.clip(0.0, l1, u1)
    a = np.maximum(l1, m0 - 40.0)
    b = np.minimum(u1, m0 + 40.0)
    t, w = np.polynomial.legendre.leggauss(K)

    def log_f(x):
        r, qq = rho[:, None], q[:, None]
        inner = _log_interval((l2[:, None] - r * x) / qq, (u2[:, None] - r * x) / qq)
        return -0.5 * x * x - 0.5 * _LOG_2PI + inner

    for _ in range(zooms):
        mid, half = 0.5 * (a + b), 0.5 * (b - a)
        x = mid[:, None] + half[:, None] * t
        lf = log_f(x)
        keep = lf >= lf.max(axis=1, keepdims=True) - drop
        first = np.argmax(keep, axis=1)
        last = K - 1 - np.argmax(keep[:, ::-1], axis=1)
        rows = np.arange(len(a))
        a = np.where(first > 0, x[rows, np.maximum(first - 1, 0)], a)
        b = np.where(last < K - 1, x[rows, np.minimum(last + 1, K - 1)], b)
    mid, half = 0.5 * (a + b), 0.5 * (b - a)
    x = mid[:, None] + half[:, None] * t
    lf = log_f(x) + np.log(w)
    mx = lf.max(axis=1)
    return mx + np.log(np.exp(lf - mx[:, None]).sum(axis=1)) + np.log(half)


def _rectangle(l1, u1, l2, u2, rho):
    """``(p, careful, log_careful)``: the inclusion-exclusion ``p`` (clipped to ``[0, 1]``,
    shaped like the broadcast inputs), where it is replaced (``careful``: below
    :data:`CAREFUL_BELOW`, a non-empty rectangle, ``|rho| < 1 - RHO_DEGENERATE``), and the log
    probabilities there (:func:`_log_rectangle_quadrature`)."""
    l1, u1, l2, u2, rho = np.broadcast_arrays(
        *(np.asarray(v, dtype=float) for v in (l1, u1, l2, u2, rho)))
    if np.any(np.isnan(rho)) or np.any(np.abs(rho) > 1):
        raise ValueError("rho must lie in [-1, 1]")
    fast = np.array(np.clip(_rectangle_owen(l1, u1, l2, u2, rho), 0.0, 1.0), dtype=float)
    empty = (u1 <= l1) | (u2 <= l2)
    fast[empty] = 0.0
    careful = (fast < CAREFUL_BELOW) & ~empty & (np.abs(rho) < 1.0 - RHO_DEGENERATE)
    logs = np.empty(0)
    if careful.any():
        logs = _log_rectangle_quadrature(l1[careful], u1[careful], l2[careful], u2[careful],
                                         rho[careful])
    return fast, careful, np.minimum(logs, 0.0)


def bivariate_rectangle(l1, u1, l2, u2, rho):
    """:func:`fusioncenter.censoring.probability.bivariate_rectangle` without the check of the
    bounds (documented there)."""
    fast, careful, logs = _rectangle(l1, u1, l2, u2, rho)
    with np.errstate(under="ignore"):
        fast[careful] = np.exp(logs)
    return fast[()] if fast.ndim == 0 else fast


def log_bivariate_rectangle(l1, u1, l2, u2, rho):
    """:func:`fusioncenter.censoring.probability.log_bivariate_rectangle` without the check of
    the bounds (documented there)."""
    fast, careful, logs = _rectangle(l1, u1, l2, u2, rho)
    with np.errstate(divide="ignore"):
        out = np.array(np.log(fast))
    out[careful] = logs
    return out[()] if out.ndim == 0 else out


# -------------------------------------------------------------------------- Proposition 3's regions
def _log_outside(m, h):
    """``log P(|Z + m| >= h)`` for ``Z ~ N(0, 1)``: ``log(Phi(|m| - h) + Phi(-|m| - h))``."""
    m = np.abs(np.asarray(m, dtype=float))
    return np.logaddexp(special.log_ndtr(m - h), special.log_ndtr(-m - h))


def log_region_probability(c, cov, a, outside):
    """``log P(region)`` for a bivariate (or univariate) Gaussian with means ``c (..., K)``.

    Component ``i`` must satisfy ``|W_i| >= a_i`` if ``outside[i]`` else ``|W_i| < a_i``;
    ``W ~ N(c, cov)``, ``K`` in {1, 2}.

    Parameters
    ----------
    c : numpy.ndarray
        Means ``(..., K)`` of ``W``.
    cov : numpy.ndarray
        Covariance ``(K, K)`` of ``W``.
    a : numpy.ndarray
        Half-widths ``(K,)``.
    outside : sequence of bool
        Per component, ``|W_i| >= a_i`` (True) or ``|W_i| < a_i`` (False).

    Returns
    -------
    numpy.ndarray
        ``log P(region)``, shape ``c.shape[:-1]``: the inclusion-exclusion of Owen's T values
        where the probability is at least :data:`CAREFUL_BELOW`, else the log-sum of the
        region's disjoint rectangles by :func:`log_bivariate_rectangle` (relative accuracy
        ~1e-12 however small; ``|rho| > 1 - 1e-6`` keeps the inclusion-exclusion).
    """
    K = len(outside)
    sd = np.sqrt(np.diag(cov))
    if K == 1:
        m, h = c[..., 0] / sd[0], a[0] / sd[0]
        return _log_outside(m, h) if outside[0] else prob_inside(m, h, log=True)
    rho = float(np.clip(cov[0, 1] / (sd[0] * sd[1]), -1.0, 1.0))
    lo = (-a - c) / sd  # (..., 2)
    hi = (a - c) / sd
    both_in = np.clip(_rectangle_owen(lo[..., 0], hi[..., 0], lo[..., 1], hi[..., 1], rho),
                      0.0, 1.0)
    p_in = [np.exp(prob_inside(c[..., i] / sd[i], a[i] / sd[i], log=True)) for i in range(2)]
    if outside[0] and outside[1]:
        p = 1.0 - p_in[0] - p_in[1] + both_in
    elif outside[0]:
        p = p_in[1] - both_in
    elif outside[1]:
        p = p_in[0] - both_in
    else:
        p = both_in
    with np.errstate(divide="ignore"):
        out = np.array(np.log(np.clip(p, 0.0, None)))
    # below CAREFUL_BELOW the differences above cancel (absolute accuracy ~1e-16 only): the
    # region as a union of disjoint rectangles, each in the log domain (relative ~1e-12)
    careful = (out < math.log(CAREFUL_BELOW)) & (abs(rho) < 1.0 - RHO_DEGENERATE)
    if careful.any():
        out[careful] = _log_region_rectangles(lo[careful], hi[careful], rho, outside)
    return out[()] if out.ndim == 0 else out


def _log_region_rectangles(lo, hi, rho, outside):
    """``log P(region)`` of :func:`log_region_probability` as the log-sum of the disjoint
    rectangles it is made of (standardised bounds ``lo, hi (n, 2)``), each by
    :func:`log_bivariate_rectangle`."""
    pieces = []
    for i in range(2):
        if outside[i]:
            pieces.append([(np.full(len(lo), -np.inf), lo[:, i]),
                           (hi[:, i], np.full(len(lo), np.inf))])
        else:
            pieces.append([(lo[:, i], hi[:, i])])
    logs = [log_bivariate_rectangle(a0, b0, a1, b1, rho)
            for a0, b0 in pieces[0] for a1, b1 in pieces[1]]
    return np.logaddexp.reduce(np.stack(logs), axis=0)


def log_silent_constant(Vcov, a) -> float:
    """``log P(|V_j| < a_j for all j)``, ``V ~ N(0, Vcov)`` (a constant in ``x``).

    Parameters
    ----------
    Vcov : numpy.ndarray
        Covariance ``(K, K)`` of ``V``.
    a : numpy.ndarray
        Half-widths ``(K,)``.

    Returns
    -------
    float
        ``log P(|V_j| < a_j for all j)`` (bivariate rectangle for ``K = 2``, ``scipy``'s
        multivariate normal CDF beyond).
    """
    K = len(a)
    sd = np.sqrt(np.diag(Vcov))
    if K == 1:
        return float(prob_inside(0.0, a[0] / sd[0], log=True))
    if K == 2:
        rho = float(np.clip(Vcov[0, 1] / (sd[0] * sd[1]), -1.0, 1.0))
        b = a / sd
        return float(np.log(bivariate_rectangle(-b[0], b[0], -b[1], b[1], rho)))
    # SciPy integrates K >= 3 by randomized quasi-Monte Carlo (relative error ~1e-5): a seeded
    # generator of its own makes the value, and every result using it, the same on every call
    mvn = scipy.stats.multivariate_normal(mean=np.zeros(K), cov=Vcov, allow_singular=True,
                                          seed=np.random.default_rng(0))
    return float(np.log(mvn.cdf(a, lower_limit=-a)))
