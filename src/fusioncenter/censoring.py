"""Censoring by the normalized innovation squared, and fusion with the missing data (zheng2014).

Each sensor ``i`` observes ``z_k^i = h_i^T x_k + n_k^i`` (``n ~ N(0, r_i)``) and sends it to the
fusion centre (FC) only if its normalized innovation squared is large (eq. (4)):
``nu^2 / s >= eta``, ``nu = z - h^T xhat_{k|k-1}``, ``s = r + h^T P_{k|k-1} h``. The threshold
``eta = chi2_{n_nu}(l / N)`` (eq. (8)) makes ``l`` of the ``N`` sensors send on average when
``nu ~ N(0, s)``. A silent sensor is *not missing at random*; the FC's particle filter can use
the full likelihood ``p(z_obs, m | x)`` (CFwMD) or drop the silent sensors (CFoMD).

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
  :class:`LinearFusionCentre` for every scheme, :class:`_ExactFusionCentre` for the exact
  no-feedback filter.
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

import functools
import math
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
import scipy.stats
from scipy import special

from fusioncenter import _kernels, montecarlo, particle
from fusioncenter._validate import finite as _finite
from fusioncenter._validate import nonneg as _nonneg
from fusioncenter._validate import one_of as _one_of
from fusioncenter._validate import posint as _posint
from fusioncenter._validate import positive as _positive

__all__ = [
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
]

#: Schemes of :func:`run`: every sensor sends; each sends independently with probability
#: ``l / N`` (missing completely at random); NIS censoring with the silent sensors dropped
#: (CFoMD); NIS censoring with the full likelihood (CFwMD).
SCHEMES = ("all-send", "random", "cfomd", "cfwmd")
#: What the FC broadcasts at the start of each step: its predicted state (CFwMD, Propositions 1),
#: predicted state and covariance (CFwMD2, Proposition 2), or nothing (Proposition 3).
FEEDBACK = ("state", "state+cov", "none")
#: How ``scheme="cfwmd"`` fuses without feedback: Proposition 3 ``"corrected"`` or as
#: ``"printed"`` (both under the paper's law (21) for the local predictions), or ``"exact"``: the
#: particles also carry every sensor's local prediction, which makes the likelihood exact.
LIKELIHOODS = ("corrected", "printed", "exact")

_R2 = 1.0 / math.sqrt(2.0)
_LOG_HALF = math.log(0.5)
_LOG_2PI = math.log(2.0 * math.pi)


# ----------------------------------------------------------------------------- threshold
def threshold(l, N, dof: int = 1) -> float:
    """``eta = chi2_dof(l / N)``: the upper ``l/N`` quantile of the chi-square law, eq. (8).

    If every sensor's normalized innovation squared is ``chi2_dof`` distributed, each sends with
    probability ``P(chi2_dof >= eta) = l / N``, so ``l`` of the ``N`` sensors send on average.
    ``l = N`` gives ``eta = 0`` (every sensor always sends). Requires ``0 < l <= N``.
    """
    N = _posint("N", N)
    dof = _posint("dof", dof)
    if isinstance(l, bool) or not np.isscalar(l) or not np.isfinite(l) or not 0 < l <= N:
        raise ValueError(f"l (average number of sending sensors) must lie in (0, N] = (0, {N}], "
                         f"got {l!r}")
    return float(scipy.stats.chi2.isf(float(l) / N, dof))


# ----------------------------------------------------------------------------- censored probability
def _log1mexp(d):
    """``log(1 - exp(d))`` for ``d <= 0`` without cancellation (Maechler's switch at -log 2)."""
    d = np.asarray(d, dtype=float)
    with np.errstate(divide="ignore"):
        return np.where(d > -math.log(2.0), np.log(-np.expm1(d)), np.log1p(-np.exp(d)))


def _inside(m, h, *, log: bool):
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


def _log_inside_fast(m, h):
    """``log P(|Z + m| < h)`` for the particle filter: ``log(Phi(h - |m|) - Phi(-h - |m|))``.

    Two ``ndtr`` calls (``Phi`` of a negative argument is evaluated through ``erfc``, with full
    relative accuracy), so the difference loses only ``~eps / (1 - exp(-2 |m| h))`` relative
    accuracy; where it falls below 1e-250 (deep in the tail, ``|m| - h > 33``) or ``h < 1e-6``
    the careful :func:`_inside` is used instead. Agrees with :func:`_inside` to ~1e-13 relative.
    """
    m = np.abs(m)
    p = special.ndtr(h - m)
    a = np.subtract(-h, m)
    p -= special.ndtr(a, out=a)
    bad = p < 1e-250
    if np.any(np.asarray(h) < 1e-6):
        bad |= np.broadcast_to(h, p.shape) < 1e-6
    with np.errstate(divide="ignore"):
        out = np.log(p, out=p)
    if bad.any():
        out[bad] = _inside(np.broadcast_to(m, p.shape)[bad], np.broadcast_to(h, p.shape)[bad],
                           log=True)
    return out


def _log_outside(m, h):
    """``log P(|Z + m| >= h)`` for ``Z ~ N(0, 1)``: ``log(Phi(|m| - h) + Phi(-|m| - h))``."""
    m = np.abs(np.asarray(m, dtype=float))
    return np.logaddexp(special.log_ndtr(m - h), special.log_ndtr(-m - h))


def _censored_args(mu, s, r, eta):
    mu = _finite("mu", mu)
    s = _nonneg("s", s)
    r = _positive("r", r)
    eta = _nonneg("eta", eta)
    sd = np.sqrt(r)
    return mu / sd, np.sqrt(eta * s) / sd


def censored_probability(mu, s, r, eta):
    """``P(|nu| < sqrt(eta s))`` for ``nu ~ N(mu, r)``: the probability that a sensor stays silent.

    In Proposition 1 this is ``Q(xi_1) - Q(xi_2)``, ``xi_{1,2} = (-/+ sqrt(eta s) - mu)/sqrt(r)``,
    with ``mu = h^T (x - xhat_{k|k-1})`` the innovation's mean given the state, ``r`` its variance
    given the state, and ``s`` the innovation variance the sensor normalizes by. Broadcasts like a
    ufunc; ``r > 0``, ``s >= 0``, ``eta >= 0``. Computed without cancellation: see
    :func:`log_censored_probability` (the same two branches without the log). Underflows to 0
    only where the probability is below ~1e-308; use the log version there.
    """
    m, h = _censored_args(mu, s, r, eta)
    out = _inside(m, h, log=False)
    return out[()] if out.ndim == 0 else out


def log_censored_probability(mu, s, r, eta):
    """``log P(|nu| < sqrt(eta s))`` for ``nu ~ N(mu, r)``, finite for any finite ``mu``.

    With ``m = |mu|/sqrt(r)``, ``h = sqrt(eta s / r)``, ``lo = m - h``: if ``lo <= 0``,
    ``log((erf((m+h)/sqrt2) + erf((h-m)/sqrt2))/2)``; otherwise
    ``log(1/2) - lo^2/2 + log erfcx(lo/sqrt2) + log(1 - exp(d))``,
    ``d = log(erfcx((m+h)/sqrt2)/erfcx(lo/sqrt2)) - 2 m h``; for a narrow interval off the mean
    (``h < 0.1``, ``m h < 0.1``) a Taylor series in ``h`` (see :func:`_inside`). Relative error
    ~1e-13 or better everywhere (checked against mpmath). ``-inf`` if ``eta s = 0``.
    """
    m, h = _censored_args(mu, s, r, eta)
    out = _inside(m, h, log=True)
    return out[()] if out.ndim == 0 else out


# ----------------------------------------------------------------------------- bivariate normal
def bivariate_normal_cdf(h, k, rho):
    """``P(X <= h, Y <= k)`` for a standard bivariate normal with correlation ``rho``.

    Owen (1956): ``Phi2 = (Phi(h) + Phi(k))/2 - T(h, a_h) - T(k, a_k) - beta`` with
    ``a_h = (k - rho h)/(h sqrt(1 - rho^2))``, ``a_k = (h - rho k)/(k sqrt(1 - rho^2))``,
    ``beta = 1/2`` if ``h k < 0`` and 0 otherwise (exact zeros of ``h`` or ``k`` are nudged to
    ``1e-300``; the limit is continuous). ``|rho| = 1`` (up to ``1e-12``) uses the degenerate
    laws ``Phi(min(h, k))`` and ``max(Phi(h) + Phi(k) - 1, 0)``. Infinite ``h``, ``k`` are
    allowed. Vectorized through ``scipy.special.owens_t``; absolute accuracy ~1e-15.
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


def bivariate_rectangle(l1, u1, l2, u2, rho):
    """``P(l1 < X < u1, l2 < Y < u2)`` for a standard bivariate normal, correlation ``rho``.

    Inclusion-exclusion of four :func:`bivariate_normal_cdf` values, clipped to ``[0, 1]``.
    """
    F = bivariate_normal_cdf
    out = F(u1, u2, rho) - F(l1, u2, rho) - F(u1, l2, rho) + F(l1, l2, rho)
    return np.clip(out, 0.0, 1.0)


# ----------------------------------------------------------------------------- likelihoods
def _log_gauss(z, mean, r):
    return -0.5 * (_LOG_2PI + np.log(r)) - 0.5 * (z - mean) ** 2 / r


def log_likelihood_feedback(sent, z, hx, hx_pred, s, r, eta):
    """Propositions 1 and 2: ``log p(z_obs, m | x, xhat_{k|k-1})`` with feedback.

    ``sum_{received} log N(z^i; h_i^T x, r_i) + sum_{silent} log P(|nu^i| < sqrt(eta s_i))``,
    ``nu^i ~ N(h_i^T (x - xhat_{k|k-1}), r_i)``. Shapes broadcast: ``sent`` (bool) and ``z``
    ``(..., N)`` (``z`` is ignored where not sent), ``hx = h_i^T x`` ``(..., N)``,
    ``hx_pred = h_i^T xhat_{k|k-1}``, ``s`` (the local ``s_k^i`` for Proposition 1, the
    covariance-feedback ``s'^i_k`` for Proposition 2), ``r`` ``(N,)``; returns ``(...)``.

    As a density on the outcomes it integrates to one: a sent ``z^i`` can only lie in the send
    region ``|z^i - h_i^T xhat| >= sqrt(eta s_i)``, where the printed ``[p(z^i | x)]^{m^i}`` is
    the density of ``(m^i = 1, z^i)`` (the indicator is 1 on every possible outcome).
    """
    sent = np.asarray(sent, dtype=bool)
    hx = _finite("hx", hx)
    r = _positive("r", r)
    s = _nonneg("s", s)
    eta = float(_nonneg("eta", eta))
    z = np.asarray(z, dtype=float)
    recv = np.where(sent, _log_gauss(np.where(sent, z, 0.0), hx, r), 0.0)
    sd = np.sqrt(r)
    with np.errstate(invalid="ignore"):
        sil = np.where(sent, 0.0, _inside((hx - hx_pred) / sd, np.sqrt(eta * s) / sd, log=True))
    return (recv + sil).sum(axis=-1)


def _log_rect_prob(c, cov, a, outside):
    """``log P(region)`` for a bivariate (or univariate) Gaussian with means ``c (..., K)``.

    Component ``i`` must satisfy ``|W_i| >= a_i`` if ``outside[i]`` else ``|W_i| < a_i``;
    ``W ~ N(c, cov)``, ``K`` in {1, 2}.
    """
    K = len(outside)
    sd = np.sqrt(np.diag(cov))
    if K == 1:
        m, h = c[..., 0] / sd[0], a[0] / sd[0]
        return _log_outside(m, h) if outside[0] else _inside(m, h, log=True)
    rho = float(np.clip(cov[0, 1] / (sd[0] * sd[1]), -1.0, 1.0))
    lo = (-a - c) / sd  # (..., 2)
    hi = (a - c) / sd
    both_in = bivariate_rectangle(lo[..., 0], hi[..., 0], lo[..., 1], hi[..., 1], rho)
    p_in = [np.exp(_inside(c[..., i] / sd[i], a[i] / sd[i], log=True)) for i in range(2)]
    if outside[0] and outside[1]:
        p = 1.0 - p_in[0] - p_in[1] + both_in
    elif outside[0]:
        p = p_in[1] - both_in
    elif outside[1]:
        p = p_in[0] - both_in
    else:
        p = both_in
    with np.errstate(divide="ignore"):
        return np.log(np.clip(p, 0.0, None))


def log_likelihood_no_feedback(sent, z, hx, C, r, eta, *, version: str = "corrected"):
    """Proposition 3: ``log p(m, z_obs | x)`` without feedback, under the paper's law (21)-(23).

    ``C (N, N)``: covariance of the local prediction errors in measurement space,
    ``C_ij = h_i^T Sigma^{ij}_{k|k-1} h_j`` (``C_ii = s_i - r_i``); ``s_i = C_ii + r_i``,
    ``a_i = sqrt(eta s_i)``. ``sent``, ``z``, ``hx`` as in :func:`log_likelihood_feedback`.

    * ``"printed"``: eq. (16) as printed, ``sum_{received} log N(z^i; h_i^T x, r_i) +
      log P(|V_j| < a_j for the silent j)`` with ``V_j = eps_j + n^j``: the second term does not
      depend on ``x`` (see the module docstring); any ``N``. Does not sum to one.
    * ``"corrected"``: the received sensors' conditions ``|U_i| >= a_i``,
      ``U_i = z^i - h_i^T x + eps_i``, are kept; a bivariate normal rectangle probability;
      ``N <= 2``. Sums to one.
    """
    if version not in ("corrected", "printed"):
        raise ValueError(f"version must be 'corrected' or 'printed', got {version!r}")
    sent = np.asarray(sent, dtype=bool)
    hx = _finite("hx", hx)
    N = hx.shape[-1]
    r = np.broadcast_to(_positive("r", r), (N,))
    eta = float(_nonneg("eta", eta))
    C = _finite("C", C)
    if C.shape != (N, N):
        raise ValueError(f"C must be ({N}, {N}), got {C.shape}")
    if version == "corrected" and N > 2:
        raise ValueError(f"the corrected no-feedback likelihood is implemented for N <= 2 "
                         f"sensors (a bivariate normal probability), got N = {N}")
    z = np.asarray(z, dtype=float)
    sent, z, hx = np.broadcast_arrays(sent, z, hx)
    recv = np.where(sent, _log_gauss(np.where(sent, z, 0.0), hx, r), 0.0).sum(axis=-1)
    region = _no_feedback_region(sent, z, hx[..., None, :], C, r, eta, version)[..., 0]
    return recv + region


def _no_feedback_region(sent, z, hx, C, r, eta, version):
    """The non-Gaussian factor of Proposition 3 (printed or corrected); no checks.

    ``sent`` (bool) and ``z``: ``(..., N)``, one pattern per row (a trial); ``hx``:
    ``(..., P, N)`` for ``P`` particles. Returns ``(..., P)``. Patterns are handled one at a
    time on the rows that have them.
    """
    N = hx.shape[-1]
    s = np.diag(C) + r
    a = np.sqrt(eta * s)
    out = np.zeros(hx.shape[:-1])
    for pat in np.unique(sent.reshape(-1, N), axis=0):
        rows = np.all(sent == pat, axis=-1)  # (lead,)
        silent = np.flatnonzero(~pat)
        if version == "printed":
            if silent.size:
                Vcov = C[np.ix_(silent, silent)] + np.diag(r[silent])
                out[rows] += _log_silent_constant(Vcov, a[silent])
            continue
        cov = C + np.diag(np.where(pat, 0.0, r))  # V_j = eps_j + n^j adds r_j
        if not pat.any():  # all silent: a constant in x
            out[rows] += _log_silent_constant(cov, a)
            continue
        # U_i has mean z^i - h_i^T x (per particle), V_j mean 0
        mean = np.where(pat, z[rows][..., None, :] - hx[rows], 0.0)
        out[rows] += _log_rect_prob(mean, cov, a, pat)
    return out


def _log_silent_constant(Vcov, a) -> float:
    """``log P(|V_j| < a_j for all j)``, ``V ~ N(0, Vcov)`` (a constant in ``x``)."""
    K = len(a)
    sd = np.sqrt(np.diag(Vcov))
    if K == 1:
        return float(_inside(0.0, a[0] / sd[0], log=True))
    if K == 2:
        rho = float(np.clip(Vcov[0, 1] / (sd[0] * sd[1]), -1.0, 1.0))
        b = a / sd
        return float(np.log(bivariate_rectangle(-b[0], b[0], -b[1], b[1], rho)))
    mvn = scipy.stats.multivariate_normal(mean=np.zeros(K), cov=Vcov, allow_singular=True)
    return float(np.log(mvn.cdf(a, lower_limit=-a)))


# ----------------------------------------------------------------------------- the scenario
def _as_tuple(value):
    arr = np.asarray(value, dtype=float)
    return float(arr) if arr.ndim == 0 else tuple(np.asarray(arr).tolist())


def _nested(arr: np.ndarray):
    """A float array (``ndim >= 1``) as nested tuples of floats (hashable dataclass fields)."""
    return tuple(_nested(a) for a in arr) if arr.ndim > 1 else tuple(float(v) for v in arr)


def _wna(dt: float) -> tuple[np.ndarray, np.ndarray]:
    """``(F, Q / sigma2)`` of the white-noise-acceleration model in one axis, step ``dt``:
    ``F = [[1, dt], [0, 1]]``, ``Q / sigma2 = [[dt^4/4, dt^3/2], [dt^3/2, dt^2]]``."""
    return (np.array([[1.0, dt], [0.0, 1.0]]),
            np.array([[dt**4 / 4, dt**3 / 2], [dt**3 / 2, dt**2]]))


def _dynamics(F, Q, x0, P0) -> particle.LinearGaussianDynamics:
    """The target's law; an invalid ``P0`` is reported as such (``"P0: ..."``)."""
    try:
        return particle.LinearGaussianDynamics(F=F, Q=Q, m0=x0, P0=P0)
    except ValueError as err:
        raise ValueError(f"P0: {err}") from None


def _check_x0_pair(value) -> np.ndarray:
    x0 = _finite("x0", value)
    if x0.shape != (2,):
        raise ValueError(f"x0 must be a [position, velocity] pair, got {value!r}")
    return x0


def _check_feedback_moments(value) -> None:
    if value not in ("analytic", "particles"):
        raise ValueError(f"feedback_moments must be 'analytic' or 'particles', got {value!r}")


def _time_axis_choice(T: int) -> str:
    return (f"x_0 at t = 0 is not measured; the sensors measure at t = 1..T (T = {T}); RMSE and "
            "transmissions are reported for t = 1..T")


#: The choices of :attr:`LinearScenario.choices` that every scenario shares (the schemes and the
#: particle filter).
_SCHEME_CHOICES = {
    "random selection": "each sensor sends independently with probability l/N",
    "all-send": "every sensor sends at every step (l is ignored)",
    "CFoMD": "same censoring as CFwMD (and the same feedback), silent sensors dropped",
    "resampling": "systematic, at every step (A1.6); the estimate is the weighted mean "
                  "before resampling (A1.5)",
}


def _local_error_recursion(sc, update) -> None:
    """The covariance ``Sigma`` of the joint prediction errors ``(e^1, ..., e^N)`` of the
    sensors' own Kalman filters (eqs. (21)-(23)) of a linear scenario ``sc``, step by step.

    From ``Sigma_{0|0} = 1 1^T (x) P0``, for ``t = 0..T-1``: ``Sigma_{t+1|t} = (I (x) F)
    Sigma_{t|t} (I (x) F)^T + 1 1^T (x) Q``; ``update(t, Sigma_{t+1|t})`` records what it needs
    and returns ``(A, W)`` (``2N x 2N``, block diagonal: ``I - w^i h_i^T`` and the gain times the
    noise covariance times the gain transposed), and ``Sigma_{t+1|t+1} = A Sigma A^T + W``. Both
    covariances are symmetrized.
    """
    N = sc.N
    ones = np.ones((N, N))
    Sig = np.kron(ones, sc.dynamics.P0)
    IF = np.kron(np.eye(N), sc.F)
    for t in range(sc.T):
        Sig = IF @ Sig @ IF.T + np.kron(ones, sc.Q)
        Sig = 0.5 * (Sig + Sig.T)
        A, W = update(t, Sig)
        Sig = A @ Sig @ A.T + W
        Sig = 0.5 * (Sig + Sig.T)


class _Scenario:
    """What the scenarios (:class:`LinearScenario`, ``censoring_vector.VectorScenario``,
    ``censoring_nonlinear.NonlinearScenario``: frozen dataclasses keeping their
    :class:`fusioncenter.particle.LinearGaussianDynamics` in ``_cache["dynamics"]``) share: the
    target's law, and the simulation of the true trajectories."""

    position_index = (0,)
    velocity_index = (1,)

    @property
    def dynamics(self) -> particle.LinearGaussianDynamics:
        """Initial law and transition (for the PF and for simulating the truth)."""
        return self._cache["dynamics"]

    @property
    def d(self) -> int:
        """Dimension of the state."""
        return self.dynamics.dim

    @property
    def F(self) -> np.ndarray:
        return self.dynamics.F

    @property
    def Q(self) -> np.ndarray:
        return self.dynamics.Q

    def _truth(self, rng: np.random.Generator, n: int, *, draw_x0: bool = True) -> np.ndarray:
        """True trajectories ``x (n, T+1, d)`` of ``n`` trials: draws ``x_0`` (else ``x_0`` is
        the prior mean), then ``T`` transitions."""
        dyn = self.dynamics
        x = np.empty((n, self.T + 1, self.d))
        if draw_x0:
            x[:, 0] = dyn.initial(rng, n, 1)[:, 0]
        else:
            x[:, 0] = dyn.m0
        for t in range(1, self.T + 1):
            x[:, t] = dyn.transition(rng, t, x[:, t - 1])
        return x


@dataclass(frozen=True)
class LinearScenario(_Scenario):
    """The linear tracking model of zheng2014 Section VII.A (scalar observations).

    ``x_k = [position, velocity]``, ``x_{k+1} = F x_k + u_k``, ``F = [[1, dt], [0, 1]]``,
    ``Q = sigma2 [[dt^4/4, dt^3/2], [dt^3/2, dt^2]]`` (white-noise acceleration; rank one);
    ``N`` sensors ``z_k^i = h_i^T x_k + n_k^i``, ``n^i ~ N(0, r_i)``, ``h = [1, 0]``.

    Paper values (the defaults): ``N = 2`` (Figs. 1, 3; ``N = 4`` for Fig. 2 and Table I),
    ``r = 1``, ``sigma2 = 4``, ``dt = 1``, ``x0 = [0, 10]``, ``T = 20`` steps, ``N_s = 1000``
    particles, 5000 trials. Every field can be overridden (``dataclasses.replace`` or keywords):

    * ``r``: one variance for every sensor or one per sensor; ``h``: one measurement vector for
      every sensor, or one row per sensor (shape ``(N, 2)``);
    * ``P0``: covariance of ``x_0`` (``None``: zero, ``x_0 = x0`` known);
    * ``feedback_moments``: how the FC forms what it feeds back, ``"analytic"`` (default:
      ``xhat_{k|k-1} = F xhat_{k-1|k-1}``, ``P_{k|k-1} = F P_{k-1|k-1} F^T + Q`` from the weighted
      particle mean and covariance at ``k-1``) or ``"particles"`` (mean and covariance of the
      propagated particle cloud; requires resampling at every step).

    The choices the paper leaves open are listed, with the value used, in :attr:`choices`.
    """

    N: int = 2
    r: float | tuple = 1.0
    sigma2: float = 4.0
    T: int = 20
    x0: tuple = (0.0, 10.0)
    dt: float = 1.0
    h: tuple = (1.0, 0.0)
    P0: tuple | None = None
    feedback_moments: str = "analytic"
    _cache: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        N = _posint("N", self.N)
        _posint("T", self.T)
        dt = float(_positive("dt", self.dt))
        sigma2 = float(_positive("sigma2", self.sigma2))
        r = _positive("r", self.r)
        if r.ndim > 1 or (r.ndim == 1 and r.shape != (N,)):
            raise ValueError(f"r must be a scalar or have one variance per sensor ({N},), "
                             f"got shape {r.shape}")
        x0 = _check_x0_pair(self.x0)
        h = _finite("h", self.h)
        if h.shape not in ((2,), (N, 2)) or np.any(np.all(h.reshape(-1, 2) == 0, axis=-1)):
            raise ValueError(f"h must be a non-zero vector (2,) or one per sensor ({N}, 2), "
                             f"got {self.h!r}")
        _check_feedback_moments(self.feedback_moments)
        P0 = np.zeros((2, 2)) if self.P0 is None else np.asarray(self.P0, dtype=float)
        F, q = _wna(dt)
        dyn = _dynamics(F, sigma2 * q, x0, P0)  # validates P0
        object.__setattr__(self, "N", N)
        object.__setattr__(self, "T", int(self.T))
        object.__setattr__(self, "r", _as_tuple(r))
        object.__setattr__(self, "h", _as_tuple(h) if h.ndim == 1 else _nested(h))
        object.__setattr__(self, "x0", _as_tuple(x0))
        if self.P0 is not None:
            object.__setattr__(self, "P0", _nested(P0))
        self._cache["dynamics"] = dyn

    # --- model pieces (dynamics, d, F, Q: see _Scenario)
    @property
    def H(self) -> np.ndarray:
        """Measurement vectors, one row per sensor ``(N, 2)``."""
        return np.broadcast_to(np.asarray(self.h, dtype=float), (self.N, 2)).copy()

    @property
    def rvec(self) -> np.ndarray:
        """Measurement-noise variances ``(N,)``."""
        return np.broadcast_to(np.asarray(self.r, dtype=float), (self.N,)).copy()

    @property
    def choices(self) -> dict[str, str]:
        """Every choice the paper leaves open, with the value this scenario uses."""
        P0 = "0 (x_0 = x0 known exactly)" if self.P0 is None else f"{self.P0}"
        return {
            "time axis": _time_axis_choice(self.T),
            "initial state": f"x_0 ~ N(x0, P0), x0 = {self.x0}, P0 = {P0} (the paper: the "
                             "initial state 'is chosen to be [0 10]')",
            "PF prior": "particles at t = 0 drawn from N(x0, P0): all equal to x0 when P0 = 0",
            "local Kalman filters": "every sensor's KF starts from (x0, P0) and uses all of its "
                                    "own measurements (censoring only decides what is sent); "
                                    "its covariance recursion is data-independent, so the FC "
                                    "knows every s_k^i (Remark 1 (I))",
            "initial cross-covariance": "P^{ij}_{0|0} = P0 (all sensors start from the same x0; "
                                        "the paper's P^{ij}_{0|0} = 0 is this with P0 = 0)",
            "feedback 'state'": "x_hat_{k|k-1} broadcast at the start of step k; sensors use it in "
                                "the innovation but normalize by their own s_k^i = r + h^T "
                                "P^i_{k|k-1} h (Remark 1 (III))",
            "feedback 'state+cov'": "also P_hat_{k|k-1}; sensors and FC use s'^i_k = r + h^T "
                                    "P_hat_{k|k-1} h (Proposition 2, 'CFwMD2')",
            "feedback moments": (
                "analytic: x_hat_{k|k-1} = F x_hat_{k-1|k-1}, P_hat_{k|k-1} = F P_hat_{k-1|k-1} "
                "F^T + Q, from the weighted particle mean and covariance at k-1 (before "
                "resampling); x_hat_{1|0} = F x0, P_hat_{1|0} = F P0 F^T + Q"
                if self.feedback_moments == "analytic" else
                "particles: mean and covariance of the propagated particle cloud at step k"),
            "threshold": "eta = chi2_1 upper-(l/N) quantile, the same for every sensor and step "
                         "(eq. (8))",
            **_SCHEME_CHOICES,
            "no-feedback likelihood": "'corrected' (default) or 'printed' Proposition 3, both with "
                                      "the paper's law (21)-(23) for the local predictions, or "
                                      "'exact' (particles carry the local predictions)",
        }

    def sample(self, rng: np.random.Generator, n: int):
        """Truth and measurements of ``n`` trials: ``x (n, T+1, 2)`` (``x[:, 0] = x_0``), ``z (n,
        T, N)`` (``z[:, t-1]`` measured at time ``t``). Draws ``x_0``, then ``T`` transitions,
        then all measurement noises."""
        x = self._truth(rng, n)
        noise = rng.standard_normal((n, self.T, self.N)) * np.sqrt(self.rvec)
        z = x[:, 1:] @ self.H.T + noise
        return x, z

    def local_filters(self) -> dict[str, np.ndarray]:
        """Data-independent quantities of the sensors' own Kalman filters, ``t = 1..T``.

        ``P_pred (T, N, 2, 2)``: ``P^i_{t|t-1}``; ``gain (T, N, 2)``: ``w_t^i``;
        ``s (T, N)``: ``s_t^i``; ``C (T, N, N)``: covariance of the local prediction errors in
        measurement space, ``h_i^T Sigma^{ij}_{t|t-1} h_j`` (eqs. (21)-(23); diagonal
        ``s_t^i - r_i``). Computed on the joint error vector ``(e^1, ..., e^N)``
        (:func:`_local_error_recursion`): ``Sigma_{t|t} = A Sigma_{t|t-1} A^T +
        blockdiag(w r w^T)`` with ``A = blockdiag(I - w^i h_i^T)``.
        """
        if "local" in self._cache:
            return self._cache["local"]
        N, T = self.N, self.T
        H, r = self.H, self.rvec
        P_pred = np.empty((T, N, 2, 2))
        gain = np.empty((T, N, 2))
        s = np.empty((T, N))
        Cm = np.empty((T, N, N))
        Hblk = np.zeros((N, 2 * N))
        for i in range(N):
            Hblk[i, 2 * i:2 * i + 2] = H[i]

        def update(t, Sig):
            A = np.zeros((2 * N, 2 * N))
            W = np.zeros((2 * N, 2 * N))
            for i in range(N):
                Pi = Sig[2 * i:2 * i + 2, 2 * i:2 * i + 2]
                P_pred[t, i] = Pi
                s[t, i] = H[i] @ Pi @ H[i] + r[i]
                w = Pi @ H[i] / s[t, i]
                gain[t, i] = w
                A[2 * i:2 * i + 2, 2 * i:2 * i + 2] = np.eye(2) - np.outer(w, H[i])
                W[2 * i:2 * i + 2, 2 * i:2 * i + 2] = r[i] * np.outer(w, w)
            Cm[t] = Hblk @ Sig @ Hblk.T
            return A, W

        _local_error_recursion(self, update)
        out = {"P_pred": P_pred, "gain": gain, "s": s, "C": Cm}
        self._cache["local"] = out
        return out

    def sensor_groups(self) -> list[np.ndarray]:
        """Indices of sensors with identical ``(h_i, r_i)`` (they share every likelihood term)."""
        key = np.concatenate([self.H, self.rvec[:, None]], axis=1)
        _, inv = np.unique(key, axis=0, return_inverse=True)
        return [np.flatnonzero(inv.ravel() == g) for g in range(inv.max() + 1)]


# ----------------------------------------------------------------------------- the fusion centre
class _ReferenceFC:
    """What the reference FC models (:class:`fusioncenter.particle.FilterModel`, particles of
    the target's state) share: the initial law and transition of the scenario ``self.sc``, and
    the sensors' decisions that do not depend on the FC's broadcast."""

    def initial(self, rng, n, P):
        return self.sc.dynamics.initial(rng, n, P)

    def transition(self, rng, t, x):
        return self.sc.dynamics.transition(rng, t, x)

    def _fixed_decisions(self, feedback: str, l: float, sel_u: np.ndarray) -> None:
        """Fill ``self.sent`` where the decisions are known in advance: censoring without
        feedback (``self._local_decisions()``), random selection, all-send."""
        if self.censor and feedback == "none":
            self._local_decisions()
        elif self.scheme == "random":
            self.sent[:] = sel_u < l / self.N
        elif self.scheme == "all-send":
            self.sent[:] = True


class _FeedbackModel(_ReferenceFC):
    """The FC's feedback of a linear target (``self.sc.feedback_moments``): the predicted mean
    ``pred_mean (n, d)`` and covariance ``pred_cov (n, d, d)`` it broadcasts at every step."""

    def _first_prediction(self, n: int) -> None:
        """The broadcast of step 1: ``F x0`` and ``F P0 F^T + Q`` for every trial."""
        dyn = self.sc.dynamics
        self.pred_mean = np.broadcast_to(dyn.F @ dyn.m0, (n, dyn.dim)).copy()
        self.pred_cov = np.broadcast_to(dyn.F @ dyn.P0 @ dyn.F.T + dyn.Q,
                                        (n, dyn.dim, dyn.dim)).copy()

    def _cloud_moments(self, x: np.ndarray) -> None:
        """``feedback_moments="particles"``: broadcast the mean and covariance of the propagated
        particle cloud ``x (n, P, d)``."""
        if self.sc.feedback_moments == "particles":
            self.pred_mean = x.mean(axis=1)
            dev = x - self.pred_mean[:, None, :]
            self.pred_cov = np.swapaxes(dev, -1, -2) @ dev / x.shape[1]

    def observe(self, t: int, mean: np.ndarray, cov: np.ndarray | None) -> None:
        if self.sc.feedback_moments == "analytic":
            F, Q = self.sc.F, self.sc.Q
            self.pred_mean = mean @ F.T
            if cov is not None:
                pc = F @ cov @ F.T + Q
                self.pred_cov = 0.5 * (pc + np.swapaxes(pc, -1, -2))


def _truncated_normal(u, lo, hi):
    """Inverse-cdf draws of ``Z ~ N(0, 1)`` conditioned on ``lo < Z < hi`` (``u ~ U[0, 1)``).

    An interval in the upper tail is reflected into the lower tail, where ``Phi`` keeps full
    relative accuracy; if even that underflows (the interval beyond ~38 sd), the draw uses the
    exponential approximation of the tail next to the bound nearest the mean.
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


class _ExactModel:
    """What the exact no-feedback filters share: a particle is ``(x_t, xhat^1_{t|t-1}, ...,
    xhat^N_{t|t-1})`` (``self.dim`` components, the state's first two), and a step where no
    particle of a trial is consistent with who sent is relaxed and recorded in
    ``self.relaxed (n, T)``."""

    needs_cov = False

    def initial(self, rng, n, P):
        out = np.empty((n, P, self.dim))
        out[..., :2] = self.sc.dynamics.initial(rng, n, P)
        out[..., 2:] = np.tile(self.sc.F @ self.sc.dynamics.m0, self.N)
        return out

    def _consistent(self, full: np.ndarray, ok: np.ndarray, k: int) -> np.ndarray:
        """The log weights ``full (n, P)`` where ``ok`` (the particle explains who sent), ``-inf``
        elsewhere; a trial with no such particle keeps ``full`` (the constraint relaxed)."""
        w = np.where(ok, full, -np.inf)
        dead = ~ok.any(axis=1)
        if dead.any():  # no particle's local predictions explain who sent: relax the constraint
            w[dead] = full[dead]
            self.relaxed[dead, k] = True
        return w


class _ExactFusionCentre(_ExactModel):
    """CFwMD without feedback, exact: a particle is ``(x_t, xhat^1_{t|t-1}, ..., xhat^N_{t|t-1})``.

    Given a particle, a sensor's decision is deterministic in its measurement, so the weight is
    exact: ``N(z^i; h^T x, r) 1{|z^i - h^T xhat^i| >= a_i}`` for a received ``z^i`` and
    ``P(|h^T x + n - h^T xhat^j| < a_j)`` for a silent sensor. Before the next propagation each
    particle runs the sensors' Kalman updates, with the received ``z^i`` or with a draw of the
    missing ``z^j`` from ``N(h^T x, r)`` truncated to the silent interval (its exact conditional
    law). As the number of particles grows this is the Bayes filter of the FC's data, which
    Proposition 3 approximates. State dimension ``2 (N + 1)``; the estimate is its first two
    components. If in a trial no particle satisfies the received sensors' constraints (rare: a
    few per thousand trial-steps with 250 particles), that step uses the weights without those
    indicators and is counted in ``relaxed`` (reported as ``CensoringResult.collapsed``).
    """

    def __init__(self, sc: LinearScenario, eta: float, z: np.ndarray, sent: np.ndarray):
        self.sc, self.eta, self.z, self.sent = sc, eta, z, sent
        self.relaxed = np.zeros(sent.shape[:2], dtype=bool)
        N = self.N = sc.N
        self.dim = 2 * (N + 1)
        self.H, self.r, self.sd = sc.H, sc.rvec, np.sqrt(sc.rvec)
        self.local = sc.local_filters()
        self.a = np.sqrt(eta * self.local["s"])  # (T, N)
        # flat layout of the local predictions (2N,): h^T xhat^i for every i, and the KF step
        # xhat^i_{t+1|t} = F xhat^i + F w_t^i nu^i in matrix form (all stacked matmuls)
        self.Hblk = np.zeros((2 * N, N))
        for i in range(N):
            self.Hblk[2 * i:2 * i + 2, i] = self.H[i]
        self.Fblk = np.kron(np.eye(N), sc.F).T
        self.G = np.zeros((self.local["gain"].shape[0], N, 2 * N))
        for i in range(N):
            self.G[:, i, 2 * i:2 * i + 2] = self.local["gain"][:, i] @ sc.F.T

    def transition(self, rng, t, xa):
        n, P, _ = xa.shape
        out = np.empty_like(xa)
        xh = xa[..., 2:]
        if t > 1:  # the sensors' KF updates at t - 1, then their predictions for t
            k = t - 2
            hxh = xh @ self.Hblk  # (n, P, N)
            mu = xa[..., :2] @ self.H.T  # E[z | x] per sensor
            sent = np.broadcast_to(self.sent[:, k][:, None, :], hxh.shape)
            zk = np.broadcast_to(self.z[:, k][:, None, :], hxh.shape).copy()
            u = rng.random(hxh.shape)
            sil = ~sent
            if sil.any():
                sd = np.broadcast_to(self.sd, hxh.shape)[sil]
                c, m, a = hxh[sil], mu[sil], np.broadcast_to(self.a[k], hxh.shape)[sil]
                zk[sil] = m + sd * _truncated_normal(u[sil], (c - a - m) / sd, (c + a - m) / sd)
            out[..., 2:] = xh @ self.Fblk + (zk - hxh) @ self.G[k]
        else:
            out[..., 2:] = xh
        out[..., :2] = self.sc.dynamics.transition(rng, t, np.ascontiguousarray(xa[..., :2]))
        return out

    def log_weight(self, t, xa):
        k = t - 1
        hx = xa[..., :2] @ self.H.T
        hxh = xa[..., 2:] @ self.Hblk
        sent = self.sent[:, k][:, None, :]
        z = self.z[:, k][:, None, :]
        out = np.where(sent, _log_gauss(np.where(sent, z, 0.0), hx, self.r), 0.0)
        if not np.all(sent):
            silent = np.broadcast_to(~sent, hx.shape)
            out[silent] = _log_inside_fast(((hx - hxh) / self.sd)[silent],
                                           np.broadcast_to(self.a[k] / self.sd, hx.shape)[silent])
        full = out.sum(axis=-1)
        ok = (~sent | (np.abs(z - hxh) >= self.a[k])).all(axis=-1)  # (n, P)
        return self._consistent(full, ok, k)

    def observe(self, t, mean, cov):
        pass


# ----------------------------------------------------------------------------- tables, the FC model
#: The tables cover ``|x| < 48`` (beyond, the exact function is evaluated).
_TABLE_EXTENT = 48.0
#: Trials per sub-block of :class:`LinearFusionCentre`: about 32k particles, so that a sub-block's
#: arrays stay in the core's cache while the ~40 array passes of a step run over them.
_SUB_PARTICLES = 1 << 15


class _LogTable:
    """A smooth log-probability ``f(x)`` tabulated for fast evaluation at many particles.

    ``f`` is evaluated exactly at the fixed nodes ``x_k = k * step``; on ``[x_j, x_{j+1})`` the
    table holds the polynomial of degree ``degree`` (odd) through the ``degree + 1`` nodes
    around the interval (Horner form in ``x / step - j``). The interpolation error is about
    ``C step^(degree+1) max |f^(degree+1)|`` (``C = 0.014`` for cubics, ``0.005`` for quintics):
    below ``1e-12`` in absolute value for the functions and steps used here (checked against
    ``f`` itself in the tests), far below any Monte Carlo effect. The value at ``x`` depends only
    on ``f`` at the nodes around it, never on which other points are evaluated, so a trial's
    weights do not depend on the other trials. Outside ``|x| < 48`` and on intervals with a
    non-finite node, ``f`` is evaluated exactly. ``even=True``: ``f(-x) = f(x)``, tabulated on
    ``[0, 48)``.
    """

    def __init__(self, fn, *, even: bool, step: float, degree: int):
        self.fn, self.even, self.step = fn, even, step
        kmax = int(round(_TABLE_EXTENT / step))
        self.k0 = 0 if even else -kmax
        self.n_int = kmax - self.k0
        lo = -(degree // 2)  # nodes j + lo .. j + lo + degree
        vinv = _vinv(degree)
        k = np.arange(self.k0 + lo, kmax + lo + degree + 1)
        vals = np.asarray(fn(k * step), dtype=float)
        win = np.lib.stride_tricks.sliding_window_view(vals, degree + 1)[: self.n_int]
        coef = win @ vinv.T  # (n_int, degree + 1): increasing powers
        finite = np.all(np.isfinite(win), axis=1)
        coef[~finite] = np.nan  # evaluated exactly instead
        self.all_finite = bool(finite.all())
        self.coef = np.ascontiguousarray(coef[:, ::-1])  # Horner order

    def __call__(self, x: np.ndarray) -> np.ndarray:
        t = np.abs(x) if self.even else x - self.k0 * self.step
        t *= 1.0 / self.step
        return self._finish(t, lambda far: x[far])

    def shifted(self, y: np.ndarray, shift: np.ndarray, scale: float,
                work: np.ndarray) -> np.ndarray:
        """``f((y - shift[:, None]) * scale)`` for an even table, using ``work`` (the shape of
        ``y``) as scratch (saves three array passes over ``__call__``)."""
        out = work
        if _kernels.table_shifted(self.coef, self.n_int, y, shift, scale / self.step, out):
            far = np.isnan(out)  # beyond the table, or an interval with a non-finite node
            out[far] = self.fn((y - shift[:, None])[far] * scale)
        return out

    def _finish(self, t: np.ndarray, exact_x) -> np.ndarray:
        """Interpolate at ``t = (x - x_k0) / step`` (overwritten); ``exact_x(mask)`` gives the
        arguments where the exact function is needed."""
        j = t.astype(np.intp)
        t -= j
        c = np.take(self.coef, j, axis=0, mode="clip")  # (..., degree + 1)
        out = np.multiply(c[..., 0], t)
        out += c[..., 1]
        for i in range(2, c.shape[-1]):
            out *= t
            out += c[..., i]
        far = j >= self.n_int
        if not self.even:
            far |= j < 0
            far |= t < 0  # x below the table (astype truncates towards zero)
        if not self.all_finite:
            far |= np.isnan(out)
        if far.any():
            out[far] = self.fn(exact_x(far))
        return out


def _interp_rows(fn, c: np.ndarray, *, step: float = 1.0 / 16, degree: int = 7) -> np.ndarray:
    """``f_b(c[b, j])`` for every row ``b`` of ``c (rows, P)``, interpolated like
    :class:`_LogTable` from exact values at the fixed nodes ``k * step`` that a row's particles
    need (``fn(row_indices, x)`` evaluates ``f_b(x)`` elementwise). Degree 7 on a 1/16 grid:
    error about ``0.002 step^8 max |f^(8)|`` (below 1e-11 here, checked in the tests). Used
    when each row has its own function of one variable; a row's values depend only on its own
    function and particles. Points whose nodes include a non-finite value are evaluated exactly.
    """
    rows_n = c.shape[0]
    lo = -(degree // 2)
    vinv = _vinv(degree)
    kmin = np.floor(c.min(axis=1) / step).astype(np.intp)
    kmax = np.floor(c.max(axis=1) / step).astype(np.intp)
    n_node = kmax - kmin + 1 + degree  # nodes kmin + lo .. kmax + lo + degree
    start = np.concatenate([[0], np.cumsum(n_node)[:-1]])
    owner = np.repeat(np.arange(rows_n), n_node)
    k = np.arange(int(n_node.sum())) - np.repeat(start - (kmin + lo), n_node)
    vals = np.asarray(fn(owner, k * step), dtype=float)
    win = np.lib.stride_tricks.sliding_window_view(vals, degree + 1)
    coef = np.ascontiguousarray((win @ vinv.T)[:, ::-1])
    t = c / step
    kk = np.floor(t)
    t -= kk
    idx = start[:, None] + (kk.astype(np.intp) - kmin[:, None])
    cf = np.take(coef, idx, axis=0)
    out = np.multiply(cf[..., 0], t)
    out += cf[..., 1]
    for i in range(2, degree + 1):
        out *= t
        out += cf[..., i]
    if not np.all(np.isfinite(vals)):
        bad = ~np.all(np.isfinite(np.take(win, idx, axis=0)), axis=-1)
        if bad.any():
            rb = np.broadcast_to(np.arange(rows_n)[:, None], c.shape)[bad]
            out[bad] = fn(rb, c[bad])
    return out


@functools.lru_cache(maxsize=8)
def _vinv(degree: int) -> np.ndarray:
    """Maps the values at the nodes ``lo .. lo + degree`` (``lo = -(degree // 2)``) to the
    coefficients (increasing powers) of the interpolating polynomial."""
    lo = -(degree // 2)
    offsets = np.arange(lo, lo + degree + 1).astype(float)
    return np.linalg.inv(np.vander(offsets, degree + 1, increasing=True))


@functools.lru_cache(maxsize=256)
def _silent_table(h: float) -> _LogTable:
    """``m -> log P(|Z + m| < h)``: the silent factor of Propositions 1-2 in units of ``sd``."""
    return _LogTable(lambda m: _inside(m, h, log=True), even=True, step=1.0 / 256, degree=3)


@functools.lru_cache(maxsize=256)
def _region_table(a: tuple, cov: tuple, outside: tuple, which: int) -> _LogTable:
    """``c -> log P(region)`` of :func:`_log_rect_prob` with component ``which`` of the mean at
    ``c`` and the others at 0 (Proposition 3 corrected, one sensor received)."""
    a_arr, cov_arr = np.array(a), np.array(cov)

    def fn(c):
        mean = np.zeros((*np.shape(c), len(a)))
        mean[..., which] = c
        return _log_rect_prob(mean, cov_arr, a_arr, outside)

    return _LogTable(fn, even=False, step=1.0 / 32, degree=5)


def _local_decisions(sc: LinearScenario, eta: float, z: np.ndarray) -> np.ndarray:
    """No feedback: every sensor runs its own KF; ``sent (n, T, N)`` from its innovations."""
    loc = sc.local_filters()
    F, H = sc.F, sc.H
    n, T, N = z.shape
    sent = np.empty((n, T, N), dtype=bool)
    xhat = np.broadcast_to(F @ sc.dynamics.m0, (n, N, 2)).copy()
    for t in range(T):
        nu = z[:, t] - np.einsum("nik,ik->ni", xhat, H)
        sent[:, t] = nu * nu >= eta * loc["s"][t]
        xhat = (xhat + loc["gain"][t] * nu[..., None]) @ F.T
    return sent


def _sub_blocks(n: int, P: int) -> list[slice]:
    """The sub-blocks of a block of ``n`` trials with ``P`` particles: about
    :data:`_SUB_PARTICLES` particles each (whole trials). The filter's random numbers are drawn
    sub-block by sub-block, so this partition is part of what fixes them (with the seed,
    ``n_trials``, ``block_size`` and ``n_particles``)."""
    sub = max(1, _SUB_PARTICLES // P)
    return [slice(s0, min(n, s0 + sub)) for s0 in range(0, n, sub)]


class LinearFusionCentre:
    """The FC of a :class:`LinearScenario` as a model of :func:`fusioncenter.particle.run_filter`
    (every scheme except the exact no-feedback filter, :class:`_ExactFusionCentre`).

    A model for one block of trials (``z (n, T, N)``): it also plays the sensors, because with
    feedback their decisions at step ``t`` depend on what the FC broadcast after step ``t - 1``.
    Particles ``(n, P, 2)`` (position, velocity). Organized for speed:

    * the transition is one compiled pass (:func:`fusioncenter._kernels.propagate_wna`);
    * the silent factor with state feedback is the interpolation table :func:`_silent_table`
      (its ``h`` is the same for every trial at a step), evaluated by a compiled kernel, as is the
      corrected Proposition 3 with one sensor received (:func:`_region_table`) and, per trial,
      with both received (:func:`_interp_rows`); CFwMD2's factor (``h`` differs per trial) uses
      two ``ndtr`` per particle;
    * additive constants of a trial's log weights are dropped, and the covariance is computed
      (by the loop) only when CFwMD2 feeds it back.

    :func:`run` gives the loop sub-blocks of about 32k particles (whole trials,
    :func:`_sub_blocks`), one model each, so that the ~40 array passes of a step work on data
    in the core's cache.

    Parameters
    ----------
    sc : LinearScenario
        The model.
    scheme, feedback, likelihood : str
        As in :func:`run`.
    eta : float
        Censoring threshold.
    l : float
        Average number of sending sensors (random selection sends with probability ``l / N``).
    z : numpy.ndarray
        Measurements ``(n, T, N)``.
    sel_u : numpy.ndarray
        Random-selection uniforms ``(n, T, N)``.
    """

    dim = 2

    def __init__(self, sc: LinearScenario, scheme: str, feedback: str, likelihood: str,
                 eta: float, l: float, z: np.ndarray, sel_u: np.ndarray):
        self.sc, self.scheme, self.feedback, self.likelihood = sc, scheme, feedback, likelihood
        self.eta = eta
        self.z = z
        n, T, N = z.shape
        self.n, self.T, self.N = n, T, N
        self.H, self.r = sc.H, sc.rvec
        self.groups = sc.sensor_groups()
        self.local = sc.local_filters()
        dyn = sc.dynamics
        self.dt = float(dyn.F[0, 1])
        self.LQ = particle.psd_factor(dyn.Q)
        self.censor = scheme in ("cfomd", "cfwmd")
        self.fb = self.censor and feedback != "none"
        self.analytic = sc.feedback_moments == "analytic"
        self.need_cov = self.fb and feedback == "state+cov" and self.analytic
        self.pred_mean = np.broadcast_to(dyn.F @ dyn.m0, (n, 2)).copy()
        self.pred_cov = np.broadcast_to(dyn.F @ dyn.P0 @ dyn.F.T + dyn.Q, (n, 2, 2)).copy()
        if self.censor and feedback == "none":
            self.sent = _local_decisions(sc, eta, z)
        elif scheme == "random":
            self.sent = sel_u < l / N
        elif scheme == "all-send":
            self.sent = np.ones((n, T, N), dtype=bool)
        else:
            self.sent = np.zeros((n, T, N), dtype=bool)
        self.nf_region = scheme == "cfwmd" and feedback == "none"
        self.needs_cov = self.need_cov
        self._tmp = np.empty((n, 0))
        self._g = np.empty((n, 0, 0))

    # --- the sensors' decisions at step k = t - 1 (feedback)
    def _decide(self, k: int, pos, vel) -> np.ndarray | None:
        if not self.analytic:  # moments of the propagated cloud
            P = pos.shape[1]
            mp, mv = pos.mean(axis=1), vel.mean(axis=1)
            self.pred_mean[:, 0], self.pred_mean[:, 1] = mp, mv
            if self.feedback == "state+cov":
                dp, dv = pos - mp[:, None], vel - mv[:, None]
                cpp, cpv, cvv = ((dp * dp).sum(1) / P, (dp * dv).sum(1) / P,
                                 (dv * dv).sum(1) / P)
                self.pred_cov = np.stack([np.stack([cpp, cpv], -1),
                                             np.stack([cpv, cvv], -1)], -2)
        if self.feedback == "state+cov":
            s = np.einsum("ik,nkl,il->ni", self.H, self.pred_cov, self.H) + self.r
        else:
            s = self.local["s"][k]
        nu = self.z[:, k] - self.pred_mean @ self.H.T
        self.sent[:, k] = nu * nu >= self.eta * s
        return s

    # --- log weights at step k (additive per-row constants dropped)
    def _log_weight(self, k: int, pos, vel, lw, tmp) -> None:
        s = self._decide(k, pos, vel) if self.fb else None
        sent, z = self.sent[:, k], self.z[:, k]
        ys = {}
        started = False  # lw holds a value (the first term is written, not added)
        for g in self.groups:
            hg, rg = self.H[g[0]], float(self.r[g[0]])
            if hg[0] == 1.0 and hg[1] == 0.0:
                y = pos
            else:
                y = hg[0] * pos + hg[1] * vel
            ys[int(g[0])] = y
            sg = sent[:, g]
            n_obs = sg.sum(axis=1)
            if n_obs.any():
                # sum over the received sensors of log N(z_i; y, r) = -n (y - zbar)^2 / (2 r) +
                # a constant per trial (centred: no cancellation however large the positions)
                zbar = np.where(sg, z[:, g], 0.0).sum(axis=1) / np.maximum(n_obs, 1)
                dst = tmp if started else lw
                np.subtract(y, zbar[:, None], out=dst)
                np.square(dst, out=dst)
                dst *= (-0.5 / rg * n_obs)[:, None]
                if started:
                    lw += tmp
                started = True
            if self.scheme != "cfwmd" or not self.fb:
                continue
            n_sil = len(g) - n_obs
            rows = np.flatnonzero(n_sil)
            if rows.size == 0:
                continue
            sd = math.sqrt(rg)
            hp = self.pred_mean @ hg
            # most trials have a silent sensor: evaluate every row (no fancy indexing) and
            # zero the others, unless few rows need it
            every = 2 * rows.size >= n_sil.size
            if self.feedback == "state+cov":  # h differs per trial
                mu = np.subtract(y, hp[:, None], out=tmp) if every else y[rows] - hp[rows, None]
                mu *= 1.0 / sd
                hh = np.sqrt(self.eta * s[rows if not every else slice(None), g[0]]) / sd
                with np.errstate(invalid="ignore"):
                    val = _log_inside_fast(mu, hh[:, None])
            else:
                table = _silent_table(math.sqrt(self.eta * s[g[0]]) / sd)
                if every:
                    val = table.shifted(y, hp, 1.0 / sd, tmp)
                else:  # the same arithmetic on the rows that need it
                    val = table.shifted(y[rows], hp[rows], 1.0 / sd, tmp[:rows.size])
            ns = n_sil if every else n_sil[rows]
            if every and not ns.all():
                val[ns == 0] = 0.0
            if np.any(ns > 1):
                val *= ns[:, None]
            if not started:
                lw.fill(0.0)
                started = True
            if every:
                lw += val
            else:
                lw[rows] += val
        if not started:
            lw.fill(0.0)
        if self.nf_region:
            self._no_feedback_region(k, sent, z, ys, lw)

    def _no_feedback_region(self, k, sent, z, ys, lw) -> None:
        """Proposition 3 (printed or corrected) for rows of a sub-block, pattern by pattern."""
        C, r, eta, N = self.local["C"][k], self.r, self.eta, self.N
        gid = {int(i): int(g[0]) for g in self.groups for i in g}
        if self.likelihood == "printed":  # a constant per trial: cheap through the generic code
            lw += _no_feedback_region(sent, z, np.zeros((sent.shape[0], 1, N)), C, r, eta,
                                      "printed")
            return
        s_ = np.diag(C) + r
        a = np.sqrt(eta * s_)
        for pat in np.unique(sent, axis=0):
            rows = np.flatnonzero(np.all(sent == pat, axis=-1))
            cov = C + np.diag(np.where(pat, 0.0, r))
            recv = np.flatnonzero(pat)
            if recv.size == 0:
                lw[rows] += _log_silent_constant(cov, a)
            elif N == 2 and abs(cov[0, 1]) >= (1 - 1e-9) * math.sqrt(cov[0, 0] * cov[1, 1]):
                # degenerate law (k = 1 with x_0 known: identical local predictions): the
                # region probability has kinks, which the tables would smooth; exact
                hx = np.stack([ys[gid[i]][rows] for i in range(N)], axis=-1)
                mean = np.where(pat, z[rows][:, None, :] - hx, 0.0)
                lw[rows] += _log_rect_prob(mean, cov, a, pat)
            elif recv.size == 1:
                i = int(recv[0])
                tab = _region_table(tuple(a.tolist()), tuple(map(tuple, cov.tolist())),
                                    tuple(bool(p) for p in pat), i)
                c = z[rows, i][:, None] - ys[gid[i]][rows]
                lw[rows] += tab(c)
            elif len(self.groups) == 1 or np.all(self.H == self.H[0]):
                # both received, one projection y = h^T x: per trial a function of
                # c_0 = z_0 - y (c_1 = c_0 + z_1 - z_0), interpolated from exact values
                d = z[rows, 1] - z[rows, 0]

                def fn(b, c0, d=d, cov=cov, pat=pat):
                    return _log_rect_prob(np.stack([c0, c0 + d[b]], axis=-1), cov, a, pat)

                lw[rows] += _interp_rows(fn, z[rows, 0][:, None] - ys[gid[0]][rows])
            else:
                hx = np.stack([ys[gid[i]][rows] for i in range(N)], axis=-1)
                mean = np.where(pat, z[rows][:, None, :] - hx, 0.0)
                lw[rows] += _log_rect_prob(mean, cov, a, pat)

    # --- FilterModel
    def initial(self, rng: np.random.Generator, n: int, P: int) -> np.ndarray:
        """``(n, P, 2)`` draws of ``x_0`` (:meth:`LinearGaussianDynamics.initial`), stored
        component by component (:func:`fusioncenter.particle.by_component`)."""
        return particle.by_component(self.sc.dynamics.initial(rng, n, P))

    def transition(self, rng: np.random.Generator, t: int, x: np.ndarray) -> np.ndarray:
        """A1.3 in place: ``x <- F x + L g`` with ``g`` standard normal ``(n, P, rank Q)``."""
        shape = (*x.shape[:2], self.LQ.shape[1])
        if self._g.shape != shape:
            self._g = np.empty(shape)
        if shape[2]:
            rng.standard_normal(out=self._g)
        _kernels.propagate_wna(x, self.dt, self._g, self.LQ)
        return x

    def log_weight(self, t: int, x: np.ndarray) -> np.ndarray:
        """A1.4: the log-likelihood of what the FC received at ``t`` (per-trial constants
        dropped), ``(n, P)``."""
        if self._tmp.shape != x.shape[:2]:
            self._tmp = np.empty(x.shape[:2])
        lw = np.empty(x.shape[:2])
        self._log_weight(t - 1, x[..., 0], x[..., 1], lw, self._tmp)
        return lw

    def observe(self, t: int, mean: np.ndarray, cov: np.ndarray | None) -> None:
        """What is fed back at ``t + 1`` (``feedback_moments="analytic"``): ``F mean`` and
        ``F cov F^T + Q``."""
        if self.analytic:
            self.pred_mean[:, 0] = mean[:, 0] + self.dt * mean[:, 1]
            self.pred_mean[:, 1] = mean[:, 1]
            if self.need_cov:
                F, Q = self.sc.F, self.sc.Q
                pc = F @ cov @ F.T + Q
                self.pred_cov = 0.5 * (pc + np.swapaxes(pc, -1, -2))


def _streams(rng: np.random.Generator) -> tuple[np.random.Generator, np.random.Generator]:
    """The two streams of a block: ``(data, particle filter)`` (see :func:`_chunk`)."""
    rng_data, rng_pf = rng.spawn(2)
    return rng_data, np.random.Generator(np.random.SFC64(rng_pf.bit_generator.seed_seq))


def _chunk(rng: np.random.Generator, n: int, *, scenario: LinearScenario, scheme: str,
           feedback: str, likelihood: str, eta: float, l: float, n_particles: int,
           ess_threshold: float) -> np.ndarray:
    """``chunk_fn`` for :func:`fusioncenter.montecarlo.simulate`: ``(n, T, d + 3)`` per trial.

    Columns: see :func:`trial_columns`. Two independent streams are spawned from ``rng``: the
    first draws the truth, the measurements and the random-selection uniforms (in that order, for
    every scheme: trials are paired across schemes), the second the filter's particles and
    resampling uniforms; the latter is an SFC64 generator seeded by the spawned seed sequence
    (its normal draws are 10-20 % cheaper than PCG64's here, and they are the largest single cost
    of the filter). :class:`LinearFusionCentre` runs through
    :func:`fusioncenter.particle.run_filter` sub-block by sub-block (:func:`_sub_blocks`); the
    exact no-feedback filter :class:`_ExactFusionCentre` on the whole block at once.
    """
    rng_data, rng_pf = _streams(rng)
    x, z = scenario.sample(rng_data, n)
    sel_u = rng_data.random(z.shape)
    T = scenario.T
    if scheme == "cfwmd" and feedback == "none" and likelihood == "exact":
        fc = LinearFusionCentre(scenario, scheme, feedback, likelihood, eta, l, z, sel_u)
        model = _ExactFusionCentre(scenario, eta, z, fc.sent)
        out = particle.run_filter(model, rng_pf, n, n_particles, T, ess_threshold=ess_threshold)
        return trial_columns(out, x, fc.sent, n_particles, model.relaxed)
    parts = []
    for R in _sub_blocks(n, n_particles):
        fc = LinearFusionCentre(scenario, scheme, feedback, likelihood, eta, l, z[R], sel_u[R])
        out = particle.run_filter(fc, rng_pf, R.stop - R.start, n_particles, T,
                                  ess_threshold=ess_threshold)
        parts.append(trial_columns(out, x[R], fc.sent, n_particles))
    return np.concatenate(parts, axis=0)


def trial_columns(out: particle.FilterOutput, x_true: np.ndarray, sent: np.ndarray,
                  n_particles: int, relaxed: np.ndarray | None = None) -> np.ndarray:
    """The per-trial columns of a :class:`CensoringResult` from a filter's output.

    Parameters
    ----------
    out : fusioncenter.particle.FilterOutput
        The filter's output for ``n`` trials and ``T`` steps.
    x_true : numpy.ndarray
        True states ``(n, T + 1, d')``; the first two components are compared with the estimate.
    sent : numpy.ndarray
        Who sent, bool ``(n, T, N)`` (or ``(n, T, N)`` of a vector scenario).
    n_particles : int
        Particles per trial (to express the ESS as a fraction).
    relaxed : numpy.ndarray, optional
        Bool ``(n, T)``: steps whose constraints an exact filter relaxed (counted as collapsed).

    Returns
    -------
    numpy.ndarray
        ``(n, T, 5)``: squared error of the two state components, number of sensors that sent,
        ESS / ``n_particles``, 1 if the weights collapsed.
    """
    sq = (out.mean[..., :2] - x_true[:, 1:, :2]) ** 2
    collapsed = out.collapsed if relaxed is None else out.collapsed | relaxed
    n_sent = sent.reshape(*sent.shape[:2], -1).sum(axis=-1)
    return np.concatenate([sq, n_sent[..., None].astype(float),
                           out.ess[..., None] / n_particles,
                           collapsed[..., None].astype(float)], axis=-1)


# ----------------------------------------------------------------------------- results
class Curve(NamedTuple):
    """A per-step estimate and its Monte Carlo standard error, both ``(T,)``."""

    value: np.ndarray
    stderr: np.ndarray


@dataclass(frozen=True)
class CensoringResult:
    """Output of :func:`run`. ``mc.samples`` keeps every trial: ``(n_trials, T, d + 3)``."""

    scenario: LinearScenario
    scheme: str
    feedback: str
    likelihood: str
    l: float
    eta: float
    n_particles: int
    mc: montecarlo.MonteCarloResult = field(repr=False)

    @property
    def time(self) -> np.ndarray:
        return np.arange(1, self.scenario.T + 1)

    def _sq(self, component: str) -> np.ndarray:
        idx = {"position": self.scenario.position_index,
               "velocity": self.scenario.velocity_index}.get(component)
        if idx is None:
            raise ValueError(f"component must be 'position' or 'velocity', got {component!r}")
        return self.mc.samples[..., list(idx)].sum(axis=-1)  # (n, T)

    def rmse(self, component: str) -> Curve:
        """RMSE per step ``sqrt(mean_trials squared error)``; stderr by the delta method
        ``stderr(MSE) / (2 RMSE)``."""
        sq = self._sq(component)
        mse = sq.mean(axis=0)
        se = sq.std(axis=0, ddof=1) / math.sqrt(sq.shape[0]) if sq.shape[0] > 1 \
            else np.full(mse.shape, np.nan)
        rm = np.sqrt(mse)
        with np.errstate(divide="ignore", invalid="ignore"):
            return Curve(rm, np.where(rm > 0, se / (2 * rm), 0.0))

    @property
    def rmse_position(self) -> Curve:
        return self.rmse("position")

    @property
    def rmse_velocity(self) -> Curve:
        return self.rmse("velocity")

    def _col(self, j: int) -> Curve:
        d = self.scenario.d
        return Curve(self.mc.mean[:, d + j], self.mc.stderr[:, d + j])

    @property
    def transmissions(self) -> Curve:
        """Mean number of sensors that sent, per step."""
        return self._col(0)

    @property
    def average_transmissions(self) -> tuple[float, float]:
        """Transmissions per step averaged over time and trials (Table I), with its stderr
        (computed from the per-trial time averages)."""
        per = self.mc.samples[..., self.scenario.d].mean(axis=1)
        se = per.std(ddof=1) / math.sqrt(per.size) if per.size > 1 else math.nan
        return float(per.mean()), float(se)

    @property
    def ess(self) -> Curve:
        """Mean effective sample size after weighting, as a fraction of the particles."""
        return self._col(1)

    @property
    def collapsed(self) -> int:
        """Number of (trial, step) pairs where no particle was compatible with the data (all
        weights zero: the step's data were ignored; for the exact no-feedback filter: the received
        sensors' constraints were relaxed for that step)."""
        return int(self.mc.samples[..., self.scenario.d + 2].sum())

    def time_averaged_rmse(self, component: str = "position") -> tuple[float, float]:
        """``mean_t RMSE_t`` with its stderr (delta method over trials)."""
        value, infl = _tavg_influence(self, component)
        se = infl.std(ddof=1) / math.sqrt(infl.size) if infl.size > 1 else math.nan
        return value, float(se)


def _tavg_influence(res: CensoringResult, component: str):
    sq = res._sq(component)
    rm = np.sqrt(sq.mean(axis=0))
    with np.errstate(divide="ignore", invalid="ignore"):
        infl = np.where(rm > 0, sq / (2 * rm), 0.0).mean(axis=1)
    return float(rm.mean()), infl


def paired_difference(a: CensoringResult, b: CensoringResult,
                      component: str = "position") -> tuple[float, float]:
    """Time-averaged RMSE of ``a`` minus that of ``b``, with its paired standard error.

    ``a`` and ``b`` must come from the same scenario, seed, ``n_trials`` and ``block_size``: then
    their trials share the truth and the measurements (see :func:`_chunk`), and the per-trial
    influence values ``sum_t sq_t / (2 T RMSE_t)`` of the two runs are differenced trial by
    trial (delta method), which removes most of the common Monte Carlo noise.
    """
    if (a.scenario != b.scenario or a.mc.seed != b.mc.seed or a.mc.n_trials != b.mc.n_trials
            or a.mc.block_size != b.mc.block_size):
        raise ValueError("a and b must share scenario, seed, n_trials and block_size to be paired")
    va, ia = _tavg_influence(a, component)
    vb, ib = _tavg_influence(b, component)
    diff = ia - ib
    se = diff.std(ddof=1) / math.sqrt(diff.size) if diff.size > 1 else math.nan
    return va - vb, float(se)


# ----------------------------------------------------------------------------- run
def _check_scheme(scheme: str, feedback: str) -> None:
    _one_of("scheme", scheme, SCHEMES)
    _one_of("feedback", feedback, FEEDBACK)


def _check_resampling(scenario, ess_threshold: float) -> None:
    if scenario.feedback_moments == "particles" and ess_threshold < 1.0:
        raise ValueError("feedback_moments='particles' needs resampling at every step "
                         "(ess_threshold=1.0)")


def _run_chunks(chunk, scenario, scheme: str, feedback: str, likelihood: str, *, l, eta: float,
                n_particles: int, ess_threshold: float, n_trials: int, seed: int,
                chunk_size: int | None, executor, progress: bool, block_size: int,
                chunk_kwargs: dict) -> CensoringResult:
    """The trials of a ``run`` (arguments checked): ``chunk`` (the module's ``_chunk``, given
    also ``chunk_kwargs``) through :func:`fusioncenter.montecarlo.simulate`, as a
    :class:`CensoringResult`."""
    fn = functools.partial(chunk, scenario=scenario, scheme=scheme, feedback=feedback, eta=eta,
                           l=float(l), n_particles=n_particles,
                           ess_threshold=float(ess_threshold), **chunk_kwargs)
    mc = montecarlo.simulate(fn, n_trials, seed, chunk_size=chunk_size, executor=executor,
                             progress=progress, block_size=block_size)
    return CensoringResult(scenario=scenario, scheme=scheme, feedback=feedback,
                           likelihood=likelihood, l=float(l), eta=eta, n_particles=n_particles,
                           mc=mc)


def run(scenario: LinearScenario, scheme: str, *, l, n_trials: int, n_particles: int, seed: int,
        feedback: str = "state", likelihood: str = "corrected", ess_threshold: float = 1.0,
        chunk_size: int | None = None, executor=None, progress: bool = False,
        block_size: int = montecarlo.DEFAULT_BLOCK_SIZE) -> CensoringResult:
    """Simulate ``n_trials`` trials of ``scenario`` and track them with the FC's particle filter.

    ``scheme`` in :data:`SCHEMES`, ``feedback`` in :data:`FEEDBACK` (``"state+cov"`` is the
    paper's CFwMD2), ``l`` the target average number of sending sensors (``0 < l <= N``; sets
    ``eta = threshold(l, N)`` for the censoring schemes and ``p = l / N`` for random selection;
    ignored by all-send). ``likelihood`` selects how ``scheme="cfwmd"`` fuses with
    ``feedback="none"``: Proposition 3 ``"corrected"`` (``N <= 2``) or ``"printed"``, or the
    ``"exact"`` filter (particles of dimension ``2 (N + 1)``; about 10x the cost per particle). The
    filter resamples when ``ESS <= ess_threshold * n_particles`` (default: every step, as
    Algorithm 1).

    Runs through :func:`fusioncenter.montecarlo.simulate`: results are bitwise identical for any
    ``chunk_size`` and executor; trials are paired across schemes for the same ``seed``,
    ``n_trials`` and ``block_size``. Every scheme except the exact no-feedback filter runs
    :class:`LinearFusionCentre` through :func:`fusioncenter.particle.run_filter`, sub-block by
    sub-block: on the project's 2-core machine about 20-30 ns per particle and step for CFwMD
    with state feedback (``benchmarks/bench_censoring.py``), of which about 7 are the normal
    draws, 3 the silent factor and 4 the resampling; less for the schemes without a silent
    factor, more for CFwMD2 (two ``ndtr`` per particle) and for the corrected Proposition 3
    (bivariate normal probabilities). Peak memory of a task (tracemalloc): a few MiB for
    :class:`LinearFusionCentre` (it works on sub-blocks of about 32k particles: 5 MiB for the
    default 256 trials x 1000 particles), 340 bytes per particle of a block for the exact no-
    feedback filter (83 MiB), plus the per-trial results (``n_trials * T * 5 * 8`` bytes).

    A :class:`fusioncenter.censoring_vector.VectorScenario` or a
    :class:`fusioncenter.censoring_nonlinear.NonlinearScenario` is handed to that module's
    ``run`` with the same arguments (Part IV(b)).
    """
    # local imports: those modules import this one
    from fusioncenter import censoring_nonlinear, censoring_vector

    for mod, cls in ((censoring_vector, "VectorScenario"),
                     (censoring_nonlinear, "NonlinearScenario")):
        if isinstance(scenario, getattr(mod, cls)):
            return mod.run(scenario, scheme, l=l, n_trials=n_trials, n_particles=n_particles,
                           seed=seed, feedback=feedback, likelihood=likelihood,
                           ess_threshold=ess_threshold, chunk_size=chunk_size,
                           executor=executor, progress=progress, block_size=block_size)
    if not isinstance(scenario, LinearScenario):
        raise ValueError("scenario must be a LinearScenario, VectorScenario or "
                         "NonlinearScenario")
    _check_scheme(scheme, feedback)
    _one_of("likelihood", likelihood, LIKELIHOODS)
    eta = threshold(l, scenario.N)
    n_particles = _posint("n_particles", n_particles)
    if scheme == "cfwmd" and feedback == "none" and likelihood == "corrected" and scenario.N > 2:
        raise ValueError(f"likelihood='corrected' without feedback is implemented for N <= 2, "
                         f"got N = {scenario.N} (use likelihood='printed')")
    _check_resampling(scenario, ess_threshold)
    return _run_chunks(_chunk, scenario, scheme, feedback, likelihood, l=l, eta=eta,
                       n_particles=n_particles, ess_threshold=ess_threshold, n_trials=n_trials,
                       seed=seed, chunk_size=chunk_size, executor=executor, progress=progress,
                       block_size=block_size, chunk_kwargs={"likelihood": likelihood})

