"""One normal measurement as the fusion centre sees it, unchecked (zheng2014 Propositions 1-2):
its log density where it was received (:func:`log_gauss`), the probability ``P(|Z + m| < h)``
that it stayed inside the silent interval and its log (:func:`prob_inside`, and
:func:`log_prob_inside`, the silent factor every scalar, nonlinear and lossy-link filter shares,
with one cut-off), the same probability for a vector measurement whose covariance is singular
(:func:`log_inside_degenerate`), and inverse-cdf draws conditioned on an interval
(:func:`truncated_normal`). The bivariate probabilities of Proposition 3 are in
:mod:`fusioncenter._compiled.bivariate_normal`.

NumPy and SciPy, not numba (the one compiled pass, :func:`log_prob_inside`'s, is
:func:`fusioncenter._compiled.normal_cdf.inside_difference`): these are the unchecked kernels the
filters call on their own (already checked) arrays, in their inner loops. The public functions of
:mod:`fusioncenter.censoring.probability` of the same names check their arguments (naming the bad
one) and then call these, so a valid call gives the same bits. The docstrings of
:func:`prob_inside`, :func:`log_prob_inside`, :func:`log_inside_degenerate` and
:func:`truncated_normal` are the public functions' documentation (their references are to the
public names).
"""

from __future__ import annotations

import math

import numpy as np
from scipy import special

from fusioncenter._compiled import normal_cdf

__all__ = ["log_gauss", "prob_inside", "log_prob_inside", "INSIDE_CUTOFF",
           "log_inside_degenerate", "truncated_normal"]

_R2 = 1.0 / math.sqrt(2.0)
_LOG_HALF = math.log(0.5)
_LOG_2PI = math.log(2.0 * math.pi)


def log_gauss(z, mean, r):
    """:func:`fusioncenter.censoring.likelihood.log_gauss` without its checks: ``log N(z; mean,
    r)``, the filters' received-measurement term, per particle."""
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


# -------------------------------------------------------------------------------- degenerate, draws
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
