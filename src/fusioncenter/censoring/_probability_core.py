"""The unchecked kernels of :mod:`fusioncenter.censoring.probability` (zheng2014 Propositions
1-3): ``P(|Z + m| < h)`` and its log (:func:`prob_inside`, and :func:`log_prob_inside`, the silent
factor every scalar, nonlinear and lossy-link filter shares, with one cut-off), the bivariate
normal distribution function and rectangle probabilities (Owen's T; a log-domain quadrature
where they cancel), the degenerate-covariance silent probability, the region of the corrected
Proposition 3, the all-silent constant and inverse-cdf truncated normal draws.

The filters call these on their own (already checked) arrays, in their inner loops. The public
functions of :mod:`fusioncenter.censoring.probability` of the same names check their arguments
(naming the bad one) and then call these, so a valid call gives the same bits. The docstrings
of :func:`prob_inside`, :func:`log_prob_inside`, :func:`log_inside_degenerate`,
:func:`log_region_probability`, :func:`log_silent_constant` and :func:`truncated_normal` are
the public functions' documentation (their references are to the public names).
"""

from __future__ import annotations

import math

import numpy as np
import scipy.stats
from scipy import special

from fusioncenter._compiled import normal_cdf

__all__ = ["prob_inside", "log_prob_inside", "INSIDE_CUTOFF", "cdf_owen", "CAREFUL_BELOW",
           "RHO_DEGENERATE", "bivariate_rectangle", "log_bivariate_rectangle",
           "log_inside_degenerate", "log_region_probability", "log_silent_constant",
           "truncated_normal", "log_gauss"]

_R2 = 1.0 / math.sqrt(2.0)
_LOG_HALF = math.log(0.5)
_LOG_2PI = math.log(2.0 * math.pi)


def log_gauss(z, mean, r):
    """:func:`fusioncenter.censoring.likelihood.log_gauss` without its checks (the filters'
    received-measurement term, per particle).

    Parameters
    ----------
    z, mean, r : array_like
        Value, mean and variance (broadcast; the caller has checked them).

    Returns
    -------
    numpy.ndarray
        ``log N(z; mean, r)``.
    """
    return -0.5 * (_LOG_2PI + np.log(r)) - 0.5 * (z - mean) ** 2 / r


# ----------------------------------------------------------------------------- censored probability
def _log1mexp(d):
    """``log(1 - exp(d))`` for ``d <= 0`` without cancellation (Maechler's switch at -log 2)."""
    d = np.asarray(d, dtype=float)
    with np.errstate(divide="ignore"):
        return np.where(d > -math.log(2.0), np.log(-np.expm1(d)), np.log1p(-np.exp(d)))


def prob_inside(m, h, *, log: bool):
    """``P(|Z + m| < h)`` (or its log) for ``Z ~ N(0, 1)``, ``h >= 0``; no validation.

    By symmetry only ``|m|`` matters. With ``lo = |m| - h`` and ``hi = |m| + h``:

    * ``lo <= 0`` (the interval contains the mean): ``(erf(hi/sqrt2) + erf(-lo/sqrt2)) / 2``, a
      sum of two non-negative terms (no cancellation, full relative accuracy even for tiny ``h``);
      the log of a probability above 1/2 is ``log1p(-(erfc(-lo/sqrt2) + erfc(hi/sqrt2))/2)``, so
      that ``log P`` near 0 keeps its relative accuracy too;
    * ``lo > 0`` and a narrow interval (``h < 0.1`` and ``|m| h < 0.1``): the Taylor series
      ``2 phi(m) sum_k He_{2k}(m) h^{2k+1} / (2k+1)!`` (Hermite polynomials; from
      ``exp(-(m -/+ u)^2/2) = exp(-m^2/2) sum_n He_n(m) (+/-u)^n / n!``), 9 terms, dominated by
      its first term: full relative accuracy where a difference of tails would cancel;
    * ``lo > 0`` otherwise (the interval lies in one tail): ``Q(lo) - Q(hi) = exp(-lo^2/2)/2 *
      erfcx(lo/sqrt2) * (1 - exp(d))`` with ``d = log(erfcx(hi/sqrt2)/erfcx(lo/sqrt2)) - 2|m|h``
      (because ``hi^2 - lo^2 = 4|m|h``), and ``1 - exp(d)`` by ``expm1``/``log1p``; here
      ``|m| h >= 0.01``, so the relative error stays below ~1e-13. Nothing underflows in the log
      version: at ``|m| = 40`` the log is about ``-800`` and exact to ~1e-15 relative.

    Parameters
    ----------
    m : array_like
        Offset of the interval's centre, in standard deviations.
    h : array_like
        Half-width (``>= 0``), broadcast with ``m``.
    log : bool
        Return ``log P`` (finite far in the tails) instead of ``P``.

    Returns
    -------
    numpy.ndarray
        ``P(|Z + m| < h)`` or its log, of the broadcast shape.
    """
    m, h = np.broadcast_arrays(np.abs(np.asarray(m, dtype=float)), np.asarray(h, dtype=float))
    lo = m - h
    out = np.empty(m.shape)
    a = lo <= 0
    c = ~a & (h < 0.1) & (m * h < 0.1)
    b = ~a & ~c
    with np.errstate(divide="ignore", invalid="ignore", under="ignore"):
        if a.any():
            ma, ha = m[a], h[a]
            pa = 0.5 * (special.erf((ma + ha) * _R2) + special.erf((ha - ma) * _R2))
            if log:  # near 1, log1p of minus the two (accurate) tail probabilities
                big = pa > 0.5
                la = np.log(pa)
                la[big] = np.log1p(-0.5 * (special.erfc((ha[big] - ma[big]) * _R2)
                                           + special.erfc((ha[big] + ma[big]) * _R2)))
                out[a] = la
            else:
                out[a] = pa
        if c.any():
            mc, hc = m[c], h[c]
            he_prev, he = np.ones_like(mc), mc.copy()  # He_0, He_1
            term = hc.copy()  # He_0 h^1 / 1!
            total = term.copy()
            h2 = hc * hc
            for k in range(1, 9):
                n = 2 * k  # advance He to degree n: He_{j+1} = m He_j - j He_{j-1}
                he_prev, he = he, mc * he - (n - 1) * he_prev  # He_n
                he_prev, he = he, mc * he - n * he_prev  # He_{n+1}
                term = term * h2 / ((n) * (n + 1))
                total += he_prev * term
            if log:
                out[c] = math.log(2.0) - 0.5 * mc * mc - 0.5 * _LOG_2PI + np.log(total)
            else:
                out[c] = 2.0 * np.exp(-0.5 * mc * mc) / math.sqrt(2 * math.pi) * total
        if b.any():
            mb, hb, lob = m[b], h[b], lo[b]
            ex_lo = special.erfcx(lob * _R2)
            d = np.log(special.erfcx((mb + hb) * _R2) / ex_lo) - 2.0 * mb * hb
            if log:
                out[b] = _LOG_HALF - 0.5 * lob * lob + np.log(ex_lo) + _log1mexp(d)
            else:
                out[b] = 0.5 * np.exp(-0.5 * lob * lob) * ex_lo * -np.expm1(d)
    return out


#: Below this probability :func:`log_prob_inside` switches from the difference of two normal
#: distribution functions to the careful :func:`prob_inside` (one cut-off for every filter).
INSIDE_CUTOFF = 1e-250


def log_prob_inside(m, h):
    """``log P(|Z + m| < h)`` for ``Z ~ N(0, 1)``: the silent factor of every scalar filter.

    ``log(Phi(h - |m|) - Phi(-h - |m|))``: two ``ndtr`` calls (``Phi`` of a negative argument is
    evaluated through ``erfc``, with full relative accuracy; for one- and two-dimensional
    arrays both in one compiled pass, :func:`fusioncenter._compiled.normal_cdf.inside_difference`,
    SciPy's numbers bit for bit), so the difference loses only
    ``~eps / (1 - exp(-2 |m| h))`` relative accuracy; where it falls below
    :data:`INSIDE_CUTOFF` (deep in the tail, ``|m| - h > 33``) or ``h < 1e-6`` the careful
    :func:`prob_inside` is used instead. Agrees with :func:`prob_inside` to ~1e-13 relative. No
    validation (the filters call it on their particles).

    Parameters
    ----------
    m : array_like
        Offset of the interval's centre from the mean, in standard deviations.
    h : array_like
        Half-width of the interval, in standard deviations (``>= 0``); broadcasts with ``m``.

    Returns
    -------
    numpy.ndarray
        ``log P(|Z + m| < h)`` (``-inf`` where ``h = 0``), of the broadcast shape.
    """
    m = np.abs(np.asarray(m, dtype=float))
    h = np.asarray(h, dtype=float)
    if m.ndim == 0 and h.ndim == 0:
        return log_prob_inside(m[None], h[None])[0]
    shape = np.broadcast_shapes(m.shape, h.shape)
    if 1 <= len(shape) <= 2:  # one compiled pass, SciPy's ndtr bit for bit (normal_cdf)
        # a read-only view: numba reads the writeable flag, which NumPy warns about on the
        # output of np.broadcast_arrays unless it was set explicitly
        h = h.view()
        h.flags.writeable = False
        mb, hb = np.broadcast_to(m, shape), np.broadcast_to(h, shape)
        p = np.empty(shape)
        two = shape if len(shape) == 2 else (1, shape[0])
        n_bad = normal_cdf.inside_difference(mb.reshape(two), hb.reshape(two),
                                                  p.reshape(two), INSIDE_CUTOFF, 1e-6)
        bad = (p < INSIDE_CUTOFF) | (hb < 1e-6) if n_bad else None
    else:
        p = special.ndtr(h - m)
        a = np.subtract(-h, m)
        p -= special.ndtr(a, out=a)
        bad = p < INSIDE_CUTOFF
        if np.any(h < 1e-6):
            bad |= np.broadcast_to(h, p.shape) < 1e-6
    with np.errstate(divide="ignore"):
        out = np.log(p, out=p)
    if bad is not None and bad.any():
        out[bad] = prob_inside(np.broadcast_to(m, p.shape)[bad], np.broadcast_to(h, p.shape)[bad],
                               log=True)
    return out


def _log_outside(m, h):
    """``log P(|Z + m| >= h)`` for ``Z ~ N(0, 1)``: ``log(Phi(|m| - h) + Phi(-|m| - h))``."""
    m = np.abs(np.asarray(m, dtype=float))
    return np.logaddexp(special.log_ndtr(m - h), special.log_ndtr(-m - h))


# ----------------------------------------------------------------------------- bivariate normal
def cdf_owen(h, k, rho):
    """``P(X <= h, Y <= k)`` for a standard bivariate normal with correlation ``rho``.

    Owen (1956): ``Phi2 = (Phi(h) + Phi(k))/2 - T(h, a_h) - T(k, a_k) - beta`` with
    ``a_h = (k - rho h)/(h sqrt(1 - rho^2))``, ``a_k = (h - rho k)/(k sqrt(1 - rho^2))``,
    ``beta = 1/2`` if ``h k < 0`` and 0 otherwise (exact zeros of ``h`` or ``k`` are nudged to
    ``1e-300``; the limit is continuous). ``|rho| = 1`` (up to ``1e-12``) uses the degenerate
    laws ``Phi(min(h, k))`` and ``max(Phi(h) + Phi(k) - 1, 0)``. Infinite ``h``, ``k`` are
    allowed. Vectorized through ``scipy.special.owens_t``; absolute accuracy ~1e-15.

    Parameters
    ----------
    h, k : array_like
        Upper bounds (``-inf`` / ``inf`` allowed), broadcast together.
    rho : array_like
        Correlation in ``[-1, 1]``.

    Returns
    -------
    numpy.ndarray or float
        The probabilities, clipped to ``[0, 1]``.

    Raises
    ------
    ValueError
        If ``h``, ``k`` or ``rho`` is NaN, or ``|rho| > 1``.
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
    """:func:`fusioncenter.censoring.probability.bivariate_rectangle` (documented there).

    Parameters
    ----------
    l1, u1, l2, u2 : array_like
        Bounds (``-inf`` / ``inf`` allowed), broadcast together.
    rho : array_like
        Correlation in ``[-1, 1]``.

    Returns
    -------
    numpy.ndarray
        The probabilities, in ``[0, 1]``.
    """
    fast, careful, logs = _rectangle(l1, u1, l2, u2, rho)
    with np.errstate(under="ignore"):
        fast[careful] = np.exp(logs)
    return fast[()] if fast.ndim == 0 else fast


def log_bivariate_rectangle(l1, u1, l2, u2, rho):
    """:func:`fusioncenter.censoring.probability.log_bivariate_rectangle` (documented there).

    Parameters
    ----------
    l1, u1, l2, u2 : array_like
        Bounds (``-inf`` / ``inf`` allowed), broadcast together.
    rho : array_like
        Correlation in ``[-1, 1]``.

    Returns
    -------
    numpy.ndarray
        The log probabilities (``<= 0``).
    """
    fast, careful, logs = _rectangle(l1, u1, l2, u2, rho)
    with np.errstate(divide="ignore"):
        out = np.array(np.log(fast))
    out[careful] = logs
    return out[()] if out.ndim == 0 else out


# ----------------------------------------------------------------------------- regions, draws
def log_inside_degenerate(mean, cov, eta):
    """``log P(q^T q < eta)`` for ``q ~ N(mean, cov)`` with a singular ``cov`` (rank 0 or 1).

    With ``cov = lam v v^T`` (``lam >= 0`` its largest eigenvalue) ``q = mean + sqrt(lam) v z``,
    ``z ~ N(0, 1)``: the component of ``mean`` across ``v`` is fixed, so the event is
    ``|z + w / sqrt(lam)| < sqrt((eta - |mean_perp|^2) / lam)``, ``w = v^T mean``
    (:func:`log_prob_inside`; ``-inf`` if ``eta <= |mean_perp|^2``); ``cov = 0``: ``0`` or
    ``-inf`` as ``|mean|^2 < eta`` or not. No validation.

    Parameters
    ----------
    mean : numpy.ndarray
        Means ``(k, m)``, ``m`` in {1, 2}.
    cov : numpy.ndarray
        Symmetric PSD matrices ``(k, m, m)`` of rank ``< m``.
    eta : float
        Threshold, ``>= 0``.

    Returns
    -------
    numpy.ndarray
        The log probabilities ``(k,)`` (``<= 0``, ``-inf`` where the probability is 0).
    """
    lam, V = np.linalg.eigh(cov)
    lam1 = np.maximum(lam[:, -1], 0.0)
    w = np.einsum("km,km->k", V[:, :, -1], mean)
    mm = np.einsum("km,km->k", mean, mean)
    rest = eta - np.where(lam1 > 0, np.maximum(mm - w * w, 0.0), mm)  # eta - |fixed part|^2
    out = np.full(mean.shape[0], -np.inf)
    line = (lam1 > 0) & (rest > 0)
    sd = np.sqrt(lam1[line])
    out[line] = log_prob_inside(w[line] / sd, np.sqrt(rest[line]) / sd)
    out[(lam1 == 0) & (rest > 0)] = 0.0  # a point mass inside the disc
    return out


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


def truncated_normal(u, lo, hi):
    """Inverse-cdf draws of ``Z ~ N(0, 1)`` conditioned on ``lo < Z < hi`` (``u ~ U[0, 1)``).

    An interval in the upper tail is reflected into the lower tail, where ``Phi`` keeps full
    relative accuracy; if even that underflows (the interval beyond ~38 sd), the draw uses the
    exponential approximation of the tail next to the bound nearest the mean.

    Parameters
    ----------
    u : numpy.ndarray
        Uniforms in ``[0, 1)``.
    lo, hi : numpy.ndarray
        Bounds of the interval (standardized), broadcast with ``u``.

    Returns
    -------
    numpy.ndarray
        The draws, in ``[lo, hi]``.
    """
    flip = lo > 0
    a = np.where(flip, -hi, lo)
    b = np.where(flip, -lo, hi)
    pa, pb = special.ndtr(a), special.ndtr(b)
    with np.errstate(divide="ignore", invalid="ignore"):
        zz = special.ndtri(pa + u * (pb - pa))
        far = ~(pb > 1e-300) | ~np.isfinite(zz)
        if far.any():  # b << 0: density ~ exp(b (z - b)) on (a, b]
            bb = b[far]
            zz[far] = bb + np.log1p(-u[far]) / np.abs(bb)
    zz = np.clip(zz, a, b)
    return np.where(flip, -zz, zz)
