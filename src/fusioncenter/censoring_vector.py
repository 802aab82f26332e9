"""Censoring with vector observations (zheng2014 Section V; Figs. 4-6, Table II).

Sensor ``i`` observes ``z_k^i = H^i x_k + n_k^i`` (``n ~ N(0, R^i)``, dimension ``m``) and sends it
only if its normalized innovation squared is large (eq. (31)):
``nu^T S^{-1} nu >= eta``, ``nu = z - H xhat_{k|k-1}``, ``S = R + H P_{k|k-1} H^T``, with
``eta = chi2_m(l / N)`` (eq. (32), :func:`fusioncenter.censoring.threshold` with ``dof=m``).

A silent sensor contributes ``P(nu^T S^{-1} nu < eta | x)`` to the full likelihood, with
``nu ~ N(H (x - xhat), R)`` given the state: Proposition 4 writes it as ``P(q^T q < eta)`` for
``q = S^{-1/2} nu ~ N(S^{-1/2} H (x - xhat), S^{-1/2} R S^{-1/2})`` -- the distribution function of
a *generalized* non-central chi-square (a weighted sum of non-central chi-squares with one degree
of freedom each). The paper estimated it by sampling; here it is computed.

Entry points (signature, one line each):

* ``log_censored_probability(mean, cov, eta)`` / ``censored_probability(...)``:
  ``P(q^T q < eta)`` for ``q ~ N(mean, cov)``, ``m`` in {1, 2}; accurate to ~1e-13 relative in
  the log, no underflow however far the mean lies outside the disc.
* ``censored_probability_sampled(mean, cov, eta, *, n_samples, rng)``: the paper's estimate
  ``n_q / N_q`` (Section VII.B), for comparison.
* ``log_silent_probability(mu, S, R, eta)``: the factor of Propositions 4-6 in the sensor's
  terms, ``P(nu^T S^{-1} nu < eta)`` for ``nu ~ N(mu, R)``.
* ``log_likelihood_feedback(sent, z, Hx, Hx_pred, S, R, eta)``: Propositions 4 and 5.
* ``log_likelihood_no_feedback_printed(sent, z, Hx, R, log_all_silent)``: Proposition 6 as
  printed, under the paper's law (21) for the local predictions: the silent factor is a constant.
* ``printed_mass(scenario, l, t)``: what the printed Proposition 6 sums to over all outcomes;
  ``log_all_silent(cov, S, eta)``: its constant; ``silent_covariance(scenario, Sigma)``: the
  covariance of the sensors' own innovations under (21)-(23); ``local_decisions(scenario, eta,
  z)``: who sends without feedback.
* ``VectorScenario(N=2, R=diag(2, 4), H=I, sigma2=4, T=20, x0=(0, 10), ...)``: Section VII.B.
* ``run(scenario, scheme, *, l, n_trials, n_particles, seed, feedback="state", ...)
  -> censoring.CensoringResult``: the four schemes at the FC, through ``montecarlo.simulate``.

How the probability is computed. Diagonalize: with ``R = L L^T`` and ``L^T S^{-1} L =
V diag(lambda) V^T``, the variable ``u = V^T L^{-1} nu`` is ``N(b, I)`` with ``b = V^T L^{-1} mu``
and the silent region is the ellipse ``sum_j u_j^2 / a_j^2 < 1``, ``a_j = sqrt(eta / lambda_j)``.
Integrating ``u_2`` exactly (a difference of normal distribution functions) and substituting
``u_1 = a_1 sin(theta)`` (which removes the square-root zero of the chord length at the ends),

    P = int_{-pi/2}^{pi/2} a_1 cos(theta) phi(a_1 sin(theta) - b_1)
                                    [Phi(a_2 cos(theta) - b_2) - Phi(-a_2 cos(theta) - b_2)] dtheta,

a smooth, positive integrand: Gauss-Legendre nodes in ``theta`` and a log-sum-exp give ``log P``
with no cancellation. In the tails the integrand is a narrow peak (the point of the ellipse
nearest the mean): the rule is applied again on the window where the integrand is within
``e^-40`` of its largest node value (twice), which keeps full relative accuracy down to
``log P ~ -700`` and beyond.

The particle filter evaluates this for every particle of every trial at every step; there the
same formula is *separable*: on a grid ``(b_1^g, b_2^h)`` the integral is a matrix product
``sum_k N_gk M_hk`` of ``exp`` and ``ndtr`` values, and so are its derivatives. Bicubic Hermite
interpolation of ``log P`` (values and exact derivatives on a grid of step 1/8) then costs ~16
gathers and ~60 arithmetic operations per particle, with an error below 1e-7 (tested). With state
feedback (and for the exact no-feedback filter) the ellipse depends only on the step, so one table
per step serves every trial; with covariance feedback (CFwMD2) the ellipse differs per trial and a
small table over each trial's particle cloud is built per step (48 x 48 nodes, error < 1e-6).

Proposition 6 (no feedback) has the erratum of the scalar Proposition 3 (see
``fusioncenter.censoring``): the received sensors' factor ``p(m^i = 1 | z^i, xhat^i, x) = 1`` is
dropped although ``xhat^i`` is integrated out, so (40) does not sum to one over the outcomes
(:func:`printed_mass`), and under the law (21) the silent factor does not depend on ``x``:
CFwMD as printed *is* CFoMD. ``run(..., feedback="none", likelihood="exact")`` runs the exact
no-feedback filter instead (particles carry every sensor's local prediction).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field

import numpy as np
from scipy import special

from fusioncenter import _kernels, montecarlo, particle
from fusioncenter import censoring as cs
from fusioncenter._validate import finite as _finite
from fusioncenter._validate import one_of as _one_of
from fusioncenter._validate import posint as _posint

__all__ = [
    "SCHEMES",
    "FEEDBACK",
    "LIKELIHOODS",
    "PROBABILITIES",
    "censored_probability",
    "log_censored_probability",
    "censored_probability_sampled",
    "log_silent_probability",
    "log_likelihood_feedback",
    "log_likelihood_no_feedback_printed",
    "log_all_silent",
    "printed_mass",
    "silent_covariance",
    "local_decisions",
    "VectorScenario",
    "run",
]

SCHEMES = cs.SCHEMES
FEEDBACK = cs.FEEDBACK
#: How ``scheme="cfwmd"`` fuses without feedback: ``"exact"`` (particles carry the local
#: predictions) or Proposition 6 ``"printed"`` (equivalent to CFoMD, see the module docstring).
LIKELIHOODS = ("exact", "printed")
#: How the particle filter evaluates the silent factor: ``"table"`` (interpolation of the exact
#: quadrature, error < 1e-6 in the log), ``"quadrature"`` (the accurate quadrature at every
#: particle: slow, for checks) or ``"sampled"`` (the paper's Monte Carlo estimate with ``n_q``
#: draws per particle).
PROBABILITIES = ("table", "quadrature", "sampled")

_LOG_2PI = math.log(2.0 * math.pi)
_INV_SQRT_2PI = 1.0 / math.sqrt(2.0 * math.pi)


# ----------------------------------------------------------------------------- validation
def _eta(value) -> float:
    if isinstance(value, bool) or not np.isscalar(value) or not np.isfinite(value) or value < 0:
        raise ValueError(f"eta must be a finite non-negative number, got {value!r}")
    return float(value)


def _pd(name: str, value, m: int | None = None) -> np.ndarray:
    """Symmetric positive-definite matrices ``(..., m, m)``."""
    arr = _finite(name, value)
    if arr.ndim < 2 or arr.shape[-1] != arr.shape[-2] or (m is not None and arr.shape[-1] != m):
        want = f"(..., {m}, {m})" if m is not None else "(..., m, m)"
        raise ValueError(f"{name} must be square matrices {want}, got shape {arr.shape}")
    scale = np.maximum(1.0, np.abs(arr).max(axis=(-1, -2), keepdims=True))
    if np.any(np.abs(arr - np.swapaxes(arr, -1, -2)) > 1e-10 * scale):
        raise ValueError(f"{name} must be symmetric")
    arr = 0.5 * (arr + np.swapaxes(arr, -1, -2))
    if np.any(np.linalg.eigvalsh(arr) <= 0):
        raise ValueError(f"{name} must be positive definite (a covariance of full rank)")
    return arr


# ----------------------------------------------------------------------------- canonical form
def _canonical_map(S, R):
    """``(A_L, a_scale)`` with ``b = A_L @ nu_mean`` and ``a = sqrt(eta) * a_scale``.

    ``S``, ``R``: ``(..., m, m)`` positive definite. With ``R = L L^T`` and ``L^T S^{-1} L =
    V diag(lam) V^T``: ``A_L = V^T L^{-1}`` (rows ordered so that ``a`` is ascending:
    ``lam`` descending) and ``a_scale = 1 / sqrt(lam)``. Then ``P(nu^T S^{-1} nu < eta)`` for
    ``nu ~ N(mu, R)`` equals ``P(sum_j u_j^2 / a_j^2 < 1)`` for ``u ~ N(A_L mu, I)``.
    """
    L = np.linalg.cholesky(R)
    Linv = np.linalg.inv(L)
    M = np.swapaxes(L, -1, -2) @ np.linalg.solve(S, L)
    M = 0.5 * (M + np.swapaxes(M, -1, -2))
    lam, V = np.linalg.eigh(M)  # ascending
    lam, V = lam[..., ::-1], V[..., :, ::-1]
    A = np.swapaxes(V, -1, -2) @ Linv
    return A, 1.0 / np.sqrt(lam)


@functools.cache
def _theta_rule(K: int):
    x, w = np.polynomial.legendre.leggauss(K)
    th = 0.5 * math.pi * x
    return np.sin(th), np.cos(th), 0.5 * math.pi * w


def _log_inside_1d(b, a):
    """``log P(|Z + b| < a)``, ``Z ~ N(0, 1)``: two ``ndtr`` where safe, else the careful scalar
    function of :mod:`fusioncenter.censoring` (deep tails, tiny ``a``)."""
    b = np.abs(b)
    with np.errstate(divide="ignore", invalid="ignore"):
        p = special.ndtr(a - b) - special.ndtr(-a - b)
        out = np.log(p)
    bad = ~(p > 1e-250) | (np.broadcast_to(a, p.shape) < 1e-6)
    if bad.any():
        bb = np.broadcast_to(b, p.shape)[bad]
        aa = np.broadcast_to(a, p.shape)[bad]
        out[bad] = cs.log_censored_probability(bb, aa * aa, 1.0, 1.0)
    return out


def _log_theta_integrand(th_s, th_c, b1, b2, a1, a2):
    """Log of the integrand in ``theta`` (nodes given by their sine and cosine)."""
    with np.errstate(divide="ignore"):
        lp = np.log(a1 * th_c) - 0.5 * _LOG_2PI - 0.5 * (a1 * th_s - b1) ** 2
    h = a2 * th_c
    return lp + cs.log_censored_probability(b2, h * h, 1.0, 1.0)


def _log_canon(b1, b2, a1, a2, *, K: int = 64, zooms: int = 2, drop: float = 40.0):
    """``log P(u_1^2/a_1^2 + u_2^2/a_2^2 < 1)``, ``u ~ N((b_1, b_2), I)``: accurate.

    Gauss-Legendre in ``theta`` (``K`` nodes), then up to ``zooms`` passes on the window of
    nodes within ``e^-drop`` of the largest (plus one node each side): the integrand is
    unimodal, so the window holds its peak, and outside it the mass is below ``e^-drop`` of the
    total. Points whose window is already the whole interval are not zoomed.
    """
    b1, b2, a1, a2 = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (b1, b2, a1, a2)))
    shape = b1.shape
    b1, b2, a1, a2 = (np.abs(v).reshape(-1, 1) for v in (b1, b2, a1, a2))
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


def _log_canonical(b, a):
    """``log P(sum_j u_j^2 / a_j^2 < 1)`` for ``u ~ N(b, I)``: ``b``, ``a`` ``(..., m)``, ``m``
    in {1, 2} (accurate: :func:`_log_inside_1d`, :func:`_log_canon`)."""
    if b.shape[-1] == 1:
        return _log_inside_1d(b[..., 0], a[..., 0])
    return _log_canon(b[..., 0], b[..., 1], a[..., 0], a[..., 1])


def _means(name: str, value) -> np.ndarray:
    """Mean vectors ``(..., m)``, ``m`` in {1, 2}."""
    arr = _finite(name, value)
    if arr.ndim < 1 or arr.shape[-1] not in (1, 2):
        raise ValueError(f"{name} must have its last axis of length m in (1, 2), got {arr.shape}")
    return arr


def _log_in_ellipse(A, a_scale, mean, eta: float):
    """:func:`_log_canonical` at ``b = A mean``, semi-axes ``sqrt(eta) a_scale`` (a canonical map
    of :func:`_canonical_map`); a scalar for a single point."""
    b = (A @ mean[..., None])[..., 0]
    out = _log_canonical(b, math.sqrt(eta) * a_scale)
    return out[()] if out.ndim == 0 else out


def log_censored_probability(mean, cov, eta):
    """``log P(q^T q < eta)`` for ``q ~ N(mean, cov)``: the silent factor of Propositions 4-6.

    ``mean (..., m)``, ``cov (..., m, m)`` positive definite (they broadcast), ``m`` in {1, 2},
    ``eta >= 0``. ``q^T q`` has a generalized non-central chi-square law; with
    ``cov = sigma^2 I`` it is ``sigma^2`` times a non-central chi-square with ``m`` degrees of
    freedom and non-centrality ``|mean|^2 / sigma^2`` (``scipy.stats.ncx2``). Computed by the
    quadrature of the module docstring: relative error ~1e-13 (checked against mpmath), finite
    however far the mean lies outside the disc. ``-inf`` if ``eta = 0``.
    """
    eta = _eta(eta)
    mean = _means("mean", mean)
    m = mean.shape[-1]
    cov = _pd("cov", cov, m)
    A, asc = _canonical_map(np.broadcast_to(np.eye(m), cov.shape), cov)
    return _log_in_ellipse(A, asc, mean, eta)


def censored_probability(mean, cov, eta):
    """``P(q^T q < eta)`` for ``q ~ N(mean, cov)`` (see :func:`log_censored_probability`)."""
    return np.exp(log_censored_probability(mean, cov, eta))


def censored_probability_sampled(mean, cov, eta, *, n_samples: int, rng: np.random.Generator):
    """The paper's estimate of ``P(q^T q < eta)``: the fraction of ``n_samples`` draws of
    ``q ~ N(mean, cov)`` inside the disc (Section VII.B). Unbiased, standard error
    ``sqrt(P (1 - P) / n_samples)``; ``0`` whenever no draw falls inside."""
    eta = _eta(eta)
    n_samples = _posint("n_samples", n_samples)
    mean = _finite("mean", mean)
    if mean.ndim < 1:
        raise ValueError("mean must have a last axis (the dimension m)")
    m = mean.shape[-1]
    cov = _pd("cov", cov, m)
    L = np.linalg.cholesky(cov)
    shape = np.broadcast_shapes(mean.shape[:-1], cov.shape[:-2])
    count = np.zeros(shape)
    for _ in range(n_samples):  # one draw per point at a time: memory O(points)
        y = rng.standard_normal((*shape, m))
        q = mean + (L @ y[..., None])[..., 0]
        count += (q * q).sum(axis=-1) < eta
    return count / n_samples


def log_silent_probability(mu, S, R, eta):
    """``log P(nu^T S^{-1} nu < eta)`` for ``nu ~ N(mu, R)``: a silent sensor's factor.

    ``mu = H (x - xhat)``: the innovation's mean given the state; ``R``: its covariance given the
    state; ``S``: the covariance the sensor normalizes by (its own ``S_k^i`` for Proposition 4,
    ``S'^i_k`` for Proposition 5). Equal to :func:`log_censored_probability` of
    ``q = S^{-1/2} nu ~ N(S^{-1/2} mu, S^{-1/2} R S^{-1/2})`` (eqs. (35)-(38)).
    """
    eta = _eta(eta)
    mu = _means("mu", mu)
    m = mu.shape[-1]
    S = _pd("S", S, m)
    R = _pd("R", R, m)
    S, R = np.broadcast_arrays(S, R)
    A, asc = _canonical_map(S, R)
    return _log_in_ellipse(A, asc, mu, eta)


# ----------------------------------------------------------------------------- fast tables
def _grid_terms(g1, g2, a1, a2, K: int):
    """``log P`` and its derivatives on the grid ``g1 x g2`` (canonical coordinates).

    ``g1 (..., G1)``, ``g2 (..., G2)``, ``a1``, ``a2`` ``(...)``. Returns ``f, f1, f2, f12``
    ``(..., G1, G2)``: ``log P``, ``d/db1``, ``d/db2``, ``d2/db1 db2``, from the separable form
    ``P = N M^T`` of the ``theta`` quadrature (``K`` nodes, ``K`` even): ``N_gk = w_k a_1 cos
    phi(a_1 sin - b_1^g)`` and ``M_hk = Phi(a_2 cos - b_2^h) - Phi(-a_2 cos - b_2^h)`` (``cos``
    takes only ``K/2`` values: the nodes are symmetric); derivatives by differentiating ``N``
    and ``M`` (``phi`` terms), so everything is four matrix products.
    """
    s, c, w = _theta_rule(K)
    a1, a2 = np.asarray(a1, dtype=float)[..., None], np.asarray(a2, dtype=float)[..., None]
    coef = (w * c * _INV_SQRT_2PI) * a1  # (..., K)
    d = (a1 * s)[..., None, :] - g1[..., :, None]  # (..., G1, K)
    N = coef[..., None, :] * np.exp(-0.5 * d * d)
    N1 = N * d
    half = K // 2  # nodes k and K-1-k share their cosine
    h = (a2 * c[:half])[..., None, :]  # (..., 1, K/2)
    bb = np.abs(g2)[..., :, None]  # (..., G2, 1)
    Mh = special.ndtr(h - bb) - special.ndtr(-h - bb)
    sg = np.sign(g2)[..., :, None]
    M2h = sg * _INV_SQRT_2PI * (np.exp(-0.5 * (h + bb) ** 2) - np.exp(-0.5 * (h - bb) ** 2))
    # fold N onto the K/2 distinct cosines: N_k + N_{K-1-k}
    Nf = N[..., :half] + N[..., ::-1][..., :half]
    N1f = N1[..., :half] + N1[..., ::-1][..., :half]
    Mt, M2t = np.swapaxes(Mh, -1, -2), np.swapaxes(M2h, -1, -2)
    P = Nf @ Mt
    with np.errstate(divide="ignore", invalid="ignore"):
        f1 = (N1f @ Mt) / P
        f2 = (Nf @ M2t) / P
        f12 = (N1f @ M2t) / P - f1 * f2
        f = np.log(P)
    return f, f1, f2, f12


#: Cubic Hermite basis (value at 0, value at 1, derivative at 0, derivative at 1) in powers of t.
_HERMITE = np.array([[1.0, 0.0, -3.0, 2.0], [0.0, 0.0, 3.0, -2.0], [0.0, 1.0, -2.0, 1.0],
                     [0.0, 0.0, -1.0, 1.0]])


class _PowerTable:
    """Bicubic Hermite interpolation of ``log P`` over ``0 <= b_1, b_2 <= B`` for one ellipse.

    Values and exact derivatives on the grid of step ``h`` (:func:`_grid_terms`) are turned into
    the 16 power-basis coefficients of every cell once, so a point costs one gather of 16
    numbers and a 2-D Horner scheme. Points beyond ``B`` are evaluated by the accurate quadrature
    (:func:`_log_canon`). The value at a point depends only on its cell.
    """

    def __init__(self, a1: float, a2: float, h: float, B: float, K: int):
        self.a1, self.a2 = a1, a2
        G = int(round(B / h)) + 1
        self.G, self.h, self.inv_h = G, h, 1.0 / h
        g = np.arange(G) * h
        f, f1, f2, f12 = _grid_terms(g, g, a1, a2, K)
        V = np.empty((G - 1, G - 1, 4, 4))
        by_order = {(0, 0): f, (1, 0): f1, (0, 1): f2, (1, 1): f12}
        ends = ((0, 0), (1, 0), (0, 1), (1, 1))  # (corner, derivative order): value 0/1, deriv 0/1
        for r, (di, ti) in enumerate(ends):
            for q, (dj, tj) in enumerate(ends):
                V[..., r, q] = by_order[(ti, tj)][di:G - 1 + di, dj:G - 1 + dj] * h ** (ti + tj)
        C = _HERMITE.T @ V @ _HERMITE  # (G-1, G-1, 4, 4): coefficient of t1^p t2^q
        self.coef = np.ascontiguousarray(np.moveaxis(C, (2, 3), (0, 1)).reshape(16, (G - 1) ** 2))

    def __call__(self, x1, x2):
        """``log P`` at ``(|b_1|, |b_2|) = (x1, x2)`` (non-negative arrays of one shape)."""
        G = self.G
        t1 = x1 * self.inv_h
        t2 = x2 * self.inv_h
        far = np.maximum(t1, t2) >= G - 1
        if far.any():
            t1 = np.where(far, 0.0, t1)
            t2 = np.where(far, 0.0, t2)
        i = t1.astype(np.intp)
        j = t2.astype(np.intp)
        t1 -= i
        t2 -= j
        i *= G - 1
        i += j
        c = np.take(self.coef, i, axis=1)  # (16, ...)
        out = None
        for p in (3, 2, 1, 0):
            r = c[4 * p + 3] * t2
            r += c[4 * p + 2]
            r *= t2
            r += c[4 * p + 1]
            r *= t2
            r += c[4 * p]
            if out is None:
                out = r
            else:
                out *= t1
                out += r
        if far.any():
            out[far] = _log_canon(x1[far], x2[far], self.a1, self.a2)
        return out


class _Hermite2D:
    """Bicubic Hermite interpolation of stacked 2-D tables (values and exact derivatives).

    ``f, f1, f2, f12``: ``(n_tab, G1, G2)`` on the grids ``o1 + i h1``, ``o2 + j h2`` (``o``,
    ``h``: ``(n_tab,)``). ``__call__(tab, x1, x2)`` interpolates table ``tab`` (an int array
    broadcasting with the points) at ``(x1, x2)`` from the 16 numbers at the corners of the
    point's cell; points outside their table's grid are clamped to it and reported in
    ``outside``.
    """

    def __init__(self, f, f1, f2, f12, o1, o2, h1, h2):
        self.n, self.G1, self.G2 = f.shape
        self.o1, self.o2 = np.asarray(o1, dtype=float), np.asarray(o2, dtype=float)
        self.h1, self.h2 = np.asarray(h1, dtype=float), np.asarray(h2, dtype=float)
        self.f = np.ascontiguousarray(f).ravel()
        self.f1 = np.ascontiguousarray(f1 * self.h1[:, None, None]).ravel()
        self.f2 = np.ascontiguousarray(f2 * self.h2[:, None, None]).ravel()
        self.f12 = np.ascontiguousarray(f12 * (self.h1 * self.h2)[:, None, None]).ravel()

    def __call__(self, tab, x1, x2):
        t1 = (x1 - self.o1[tab]) * (1.0 / self.h1[tab])
        t2 = (x2 - self.o2[tab]) * (1.0 / self.h2[tab])
        eps = 1e-9  # rounding at the edges of a box built from the points themselves
        outside = ~((t1 >= -eps) & (t1 <= self.G1 - 1 + eps) & (t2 >= -eps)
                    & (t2 <= self.G2 - 1 + eps))
        np.clip(t1, 0.0, self.G1 - 1, out=t1)
        np.clip(t2, 0.0, self.G2 - 1, out=t2)
        i = t1.astype(np.intp)
        j = t2.astype(np.intp)
        np.minimum(i, self.G1 - 2, out=i)
        np.minimum(j, self.G2 - 2, out=j)
        t1 -= i
        t2 -= j
        i += tab * self.G1
        i *= self.G2
        i += j
        k00 = i
        # cubic Hermite basis: A0 + A1 = 1 (values at 0 and 1), D0, D1 (derivatives times h)
        u1 = 1.0 - t1
        D0 = u1 * u1
        A0 = (2.0 * t1 + 1.0) * D0
        D0 *= t1
        D1 = t1 * t1
        D1 *= -u1
        u2 = 1.0 - t2
        E0 = u2 * u2
        B0 = (2.0 * t2 + 1.0) * E0
        E0 *= t2
        E1 = t2 * t2
        E1 *= -u2
        out = None
        for dj in (0, 1):
            ka = k00 + dj if dj else k00
            kb = ka + self.G2
            fa, fb = self.f[ka], self.f[kb]
            r = (fa - fb) * A0
            r += fb
            r += self.f1[ka] * D0
            r += self.f1[kb] * D1
            ga, gb = self.f2[ka], self.f2[kb]
            q = (ga - gb) * A0
            q += gb
            q += self.f12[ka] * D0
            q += self.f12[kb] * D1
            if dj == 0:
                q *= E0
                r *= B0
                r += q
                out = r
            else:  # B1 = 1 - B0
                r *= 1.0 - B0
                out += r
                q *= E1
                out += q
        return out, outside


#: Fixed tables: grid step, extent ``|b_j| <= B`` in canonical coordinates, quadrature nodes.
_FIXED_H = 0.125
_FIXED_B = 12.0
_FIXED_K = 64
#: Per-trial tables (covariance feedback): largest grid step, nodes per axis, quadrature nodes.
_TRIAL_STEP = 0.3
_TRIAL_SIZES = (16, 24, 32, 48, 64)
_TRIAL_K = 24


@functools.lru_cache(maxsize=1024)
def _fixed_table(a1: float, a2: float) -> _PowerTable:
    """The table of ``log P`` over ``0 <= b_1, b_2 <= 12`` (step 1/8) for the ellipse ``a``."""
    return _PowerTable(a1, a2, _FIXED_H, _FIXED_B, _FIXED_K)


def _log_silent_fixed(b, a):
    """``log P`` at canonical points given as component arrays ``b = (b_1[, b_2])`` for one
    ellipse ``a (m,)`` (table, exact where it does not reach)."""
    if len(b) == 1:
        return _log_inside_1d(b[0], a[0])
    return _fixed_table(float(a[0]), float(a[1]))(np.abs(b[0]), np.abs(b[1]))


def _log_silent_trials(b, a):
    """``log P`` at canonical points ``b = (b_1[, b_2])`` (arrays ``(r, P)``), one ellipse per
    trial ``a (r, m)``.

    One table per trial over the box of its particles: bicubic Hermite from values and exact
    derivatives at ``G x G`` nodes, ``G`` the smallest of :data:`_TRIAL_SIZES` that makes the
    step at most ``_TRIAL_STEP`` (a trial's table depends only on its own particles). Trials
    spreading wider, or lying beyond ``|b| = 30``, use the accurate quadrature.
    """
    if len(b) == 1:
        return _log_inside_1d(b[0], a[:, :1])
    b1, b2 = b
    r, P = b1.shape
    lo = np.stack([b1.min(axis=1), b2.min(axis=1)], axis=1)
    hi = np.stack([b1.max(axis=1), b2.max(axis=1)], axis=1)
    span = np.maximum(hi - lo, 1e-6).max(axis=1)
    need = np.ceil(span / _TRIAL_STEP) + 1
    sizes = np.asarray(_TRIAL_SIZES)
    which = np.searchsorted(sizes, need)  # index of the smallest G >= need
    far = (np.maximum(np.abs(lo), np.abs(hi)) > 30.0).any(axis=1) | (which >= sizes.size)
    out = np.empty((r, P))
    for q, G in enumerate(_TRIAL_SIZES):
        ok = np.flatnonzero((which == q) & ~far)
        if ok.size == 0:
            continue
        step = np.maximum(hi[ok] - lo[ok], 1e-6) / (G - 1)
        grid = lo[ok, :, None] + step[:, :, None] * np.arange(G)  # (k, 2, G)
        f, f1, f2, f12 = _grid_terms(grid[:, 0], grid[:, 1], a[ok, 0], a[ok, 1], _TRIAL_K)
        good = np.isfinite(f).all(axis=(1, 2)) & np.isfinite(f12).all(axis=(1, 2))
        if not good.all():  # a node underflowed (not expected for |b| <= 30): exact instead
            far[ok[~good]] = True
        tab = _Hermite2D(f, f1, f2, f12, lo[ok, 0], lo[ok, 1], step[:, 0], step[:, 1])
        val, _ = tab(np.arange(ok.size)[:, None], b1[ok], b2[ok])
        out[ok] = val
    bad = np.flatnonzero(far)
    if bad.size:
        aa = a[bad]
        out[bad] = _log_canon(b1[bad], b2[bad], aa[:, :1], aa[:, 1:])
    return out


def _eval_silent(b, a, *, probability: str = "table", rng=None, n_q: int = 0):
    """``log P`` at canonical points ``b (n, P, m)``; ``a`` is ``(m,)`` (one ellipse) or
    ``(n, m)`` (one per trial). Sub-blocks of trials keep the arrays in cache."""
    n, P, m = b.shape
    per_trial = a.ndim == 2
    if probability == "quadrature":
        return _log_canonical(b, np.broadcast_to(a[:, None, :] if per_trial else a, b.shape))
    if probability == "sampled":
        aa = np.broadcast_to(a[:, None, :] if per_trial else a, b.shape)
        count = np.zeros((n, P))
        for _ in range(n_q):  # u ~ N(b, I) inside the ellipse sum u_j^2 / a_j^2 < 1
            u = b + rng.standard_normal(b.shape)
            count += ((u / aa) ** 2).sum(axis=-1) < 1.0
        with np.errstate(divide="ignore"):
            return np.log(count / n_q)
    out = np.empty((n, P))
    sub = max(1, _SUB_POINTS // P)
    for s0 in range(0, n, sub):
        R = slice(s0, min(n, s0 + sub))
        comps = tuple(np.ascontiguousarray(b[R, :, j]) for j in range(m))
        out[R] = _log_silent_trials(comps, a[R]) if per_trial else _log_silent_fixed(comps, a)
    return out


#: Points per sub-block of the table evaluations (keeps the temporaries in cache).
_SUB_POINTS = 1 << 13


# ----------------------------------------------------------------------------- likelihoods
def log_likelihood_feedback(sent, z, Hx, Hx_pred, S, R, eta):
    """Propositions 4 and 5: ``log p(z_obs, m | x, xhat_{k|k-1})`` with feedback.

    ``sum_{received} log N(z^i; H^i x, R^i) + sum_{silent} log P(nu^T S_i^{-1} nu < eta)`` with
    ``nu ~ N(H^i (x - xhat), R^i)``. Shapes broadcast: ``sent (..., N)`` (bool), ``z``, ``Hx =
    H^i x``, ``Hx_pred = H^i xhat_{k|k-1}``: ``(..., N, m)`` (``z`` is ignored where not sent),
    ``S`` (the sensors' own ``S_k^i``: Proposition 4; ``S'^i_k`` from the fed-back covariance:
    Proposition 5) and ``R``: ``(..., N, m, m)``. Returns ``(...)``.
    """
    sent = np.asarray(sent, dtype=bool)
    Hx = _finite("Hx", Hx)
    Hx_pred = _finite("Hx_pred", Hx_pred)
    m = Hx.shape[-1]
    S = _pd("S", S, m)
    R = _pd("R", R, m)
    eta = _eta(eta)
    z = np.where(sent[..., None], np.asarray(z, dtype=float), Hx)
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
    """
    sent = np.asarray(sent, dtype=bool)
    Hx = _finite("Hx", Hx)
    R = _pd("R", R, Hx.shape[-1])
    z = np.where(sent[..., None], np.asarray(z, dtype=float), Hx)
    recv = np.where(sent, _log_gauss_each(z, Hx, R), 0.0).sum(axis=-1)
    return recv + np.asarray(log_all_silent, dtype=float)


# ----------------------------------------------------------------------------- the scenario
@dataclass(frozen=True)
class VectorScenario(cs._Scenario):
    """The tracking model of zheng2014 Section VII.B (vector observations).

    The target of Section VII.A (``x = [position, velocity]``, ``F = [[1, dt], [0, 1]]``,
    ``Q = sigma2 [[dt^4/4, dt^3/2], [dt^3/2, dt^2]]``) observed by ``N`` sensors
    ``z^i = H^i x + n^i``, ``n^i ~ N(0, R^i)`` of dimension ``m``.

    Paper values (the defaults): ``N = 2`` (Figs. 4 and 6; ``N = 4`` for Fig. 5 and Table II),
    ``H = I_2``, ``R = diag(2, 4)``, ``sigma2 = 4``, ``dt = 1``, ``x0 = [0, 10]``, ``T = 20``,
    1000 particles, 5000 trials. Every field can be overridden:

    * ``H``: ``(m, 2)`` for every sensor or ``(N, m, 2)`` per sensor (a vector ``(2,)`` is one
      row, ``m = 1``: the scalar model of Section VII.A); ``m`` in {1, 2};
    * ``R``: ``(m, m)`` for every sensor, ``(N, m, m)`` per sensor, or ``(m,)`` its diagonal;
    * ``P0``, ``feedback_moments``: as in :class:`fusioncenter.censoring.LinearScenario`.

    The choices the paper leaves open are listed, with the value used, in :attr:`choices`.
    """

    N: int = 2
    R: tuple = ((2.0, 0.0), (0.0, 4.0))
    H: tuple = ((1.0, 0.0), (0.0, 1.0))
    sigma2: float = 4.0
    T: int = 20
    x0: tuple = (0.0, 10.0)
    dt: float = 1.0
    P0: tuple | None = None
    feedback_moments: str = "analytic"
    _cache: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        N = _posint("N", self.N)
        _posint("T", self.T)
        dt = _finite("dt", self.dt)
        if dt.ndim or dt <= 0:
            raise ValueError(f"dt must be a positive number, got {self.dt!r}")
        dt = float(dt)
        sigma2 = _finite("sigma2", self.sigma2)
        if sigma2.ndim or sigma2 <= 0:
            raise ValueError(f"sigma2 must be a positive number, got {self.sigma2!r}")
        H = _finite("H", self.H)
        if H.ndim == 1:
            H = H[None, :]
        if H.ndim not in (2, 3) or H.shape[-1] != 2 or H.shape[-2] not in (1, 2) or \
                (H.ndim == 3 and H.shape[0] != N):
            raise ValueError(f"H must be (m, 2) or one per sensor ({N}, m, 2) with m in (1, 2), "
                             f"got shape {H.shape}")
        m = H.shape[-2]
        R = _finite("R", self.R)
        if R.ndim == 1:
            if R.shape != (m,):
                raise ValueError(f"R given as a diagonal must have length m = {m}, got {R.shape}")
            R = np.diag(R)
        if R.ndim == 0 and m == 1:
            R = R.reshape(1, 1)
        if R.ndim not in (2, 3) or R.shape[-2:] != (m, m) or (R.ndim == 3 and R.shape[0] != N):
            raise ValueError(f"R must be ({m}, {m}) or one per sensor ({N}, {m}, {m}), "
                             f"got shape {R.shape}")
        R = _pd("R", R, m)
        x0 = cs._check_x0_pair(self.x0)
        cs._check_feedback_moments(self.feedback_moments)
        P0 = np.zeros((2, 2)) if self.P0 is None else np.asarray(self.P0, dtype=float)
        F, q = cs._wna(dt)
        dyn = cs._dynamics(F, float(sigma2) * q, x0, P0)
        object.__setattr__(self, "N", N)
        object.__setattr__(self, "T", int(self.T))
        object.__setattr__(self, "dt", dt)
        object.__setattr__(self, "sigma2", float(sigma2))
        object.__setattr__(self, "H", cs._nested(H))
        object.__setattr__(self, "R", cs._nested(R))
        object.__setattr__(self, "x0", cs._nested(x0))
        if self.P0 is not None:
            object.__setattr__(self, "P0", cs._nested(P0))
        self._cache["dynamics"] = dyn

    # --- model pieces (dynamics, d, F, Q: see censoring._Scenario)
    @property
    def m(self) -> int:
        """Dimension of every sensor's measurement."""
        return np.asarray(self.H).shape[-2]

    @property
    def Hs(self) -> np.ndarray:
        """Measurement matrices, one per sensor ``(N, m, 2)``."""
        H = np.asarray(self.H, dtype=float)
        return np.broadcast_to(H, (self.N, self.m, 2)).copy()

    @property
    def Rs(self) -> np.ndarray:
        """Measurement-noise covariances, one per sensor ``(N, m, m)``."""
        R = np.asarray(self.R, dtype=float)
        return np.broadcast_to(R, (self.N, self.m, self.m)).copy()

    @property
    def choices(self) -> dict[str, str]:
        """Every choice the paper leaves open, with the value this scenario uses."""
        P0 = "0 (x_0 = x0 known exactly)" if self.P0 is None else f"{self.P0}"
        return {
            "time axis": cs._time_axis_choice(self.T),
            "initial state": f"x_0 ~ N(x0, P0), x0 = {self.x0}, P0 = {P0}; the PF's particles "
                             "start from the same law",
            "motion model": f"the target of Section VII.A: sigma^2 = {self.sigma2} (Section "
                            "VII.B says 'the same one-dimensional moving target')",
            "sensors": f"H = {self.H}, R = {self.R} for every sensor unless given per sensor "
                       "(the paper states R^i = diag(2, 4) for i = 1, 2 only; sensors 3, 4 "
                       "of Fig. 5 use the same)",
            "local Kalman filters": "every sensor's KF starts from (x0, P0) and uses all of its "
                                    "own measurements; its covariance recursion is "
                                    "data-independent, so the FC knows every S_k^i",
            "initial cross-covariance": "P^{ij}_{0|0} = P0 (the paper's 0 when P0 = 0)",
            "feedback 'state'": "x_hat_{k|k-1} broadcast at the start of step k; sensors use it in "
                                "the innovation and normalize by their own S_k^i",
            "feedback 'state+cov'": "also P_hat_{k|k-1}; sensors and FC use S'^i_k = R^i + H^i "
                                    "P_hat_{k|k-1} H^iT (Proposition 5, 'CFwMD2')",
            "feedback moments": (
                "analytic: x_hat_{k|k-1} = F x_hat_{k-1|k-1}, P_hat_{k|k-1} = F P_hat_{k-1|k-1} "
                "F^T + Q from the weighted particle mean and covariance at k-1 (before "
                "resampling)" if self.feedback_moments == "analytic" else
                "particles: mean and covariance of the propagated particle cloud at step k"),
            "threshold": f"eta = chi2_m upper-(l/N) quantile with m = {self.m} (eq. (32))",
            "silent probability": "P(q^T q < eta) by quadrature (interpolated tables in the "
                                  "filter, error < 1e-6 in the log); the paper sampled it",
            **cs._SCHEME_CHOICES,
            "no-feedback likelihood": "'exact' (particles carry every local prediction; "
                                      "default) or 'printed' Proposition 6 (= CFoMD)",
        }

    def sample(self, rng: np.random.Generator, n: int):
        """Truth ``x (n, T+1, 2)`` and measurements ``z (n, T, N, m)`` of ``n`` trials: draws
        ``x_0``, then ``T`` transitions, then all measurement noises ``(n, T, N, m)``."""
        x = self._truth(rng, n)
        noise = rng.standard_normal((n, self.T, self.N, self.m))
        L = np.linalg.cholesky(self.Rs)
        z = np.einsum("ntk,imk->ntim", x[:, 1:], self.Hs) + np.einsum("ntij,imj->ntim", noise, L)
        return x, z

    def local_filters(self) -> dict[str, np.ndarray]:
        """Data-independent quantities of the sensors' own Kalman filters, ``t = 1..T``.

        ``P_pred (T, N, 2, 2)``, ``gain (T, N, 2, m)``, ``S (T, N, m, m)``; ``Sigma (T, 2N, 2N)``:
        covariance of the joint local prediction errors ``(e^1, ..., e^N)`` (eqs. (21)-(23));
        ``A (T, N, m, 2)`` and ``a_scale (T, N, m)``: the canonical map of each sensor's silent
        region (``b = A (x - xhat)``, semi-axes ``sqrt(eta) * a_scale``, see
        :func:`_canonical_map`).
        """
        if "local" in self._cache:
            return self._cache["local"]
        N, T, m = self.N, self.T, self.m
        H, R = self.Hs, self.Rs
        P_pred = np.empty((T, N, 2, 2))
        gain = np.empty((T, N, 2, m))
        S = np.empty((T, N, m, m))
        Sigma = np.empty((T, 2 * N, 2 * N))

        def update(t, Sig):  # the joint recursion: cs._local_error_recursion
            Sigma[t] = Sig
            A = np.zeros((2 * N, 2 * N))
            Wn = np.zeros((2 * N, 2 * N))
            for i in range(N):
                blk = slice(2 * i, 2 * i + 2)
                Pi = Sig[blk, blk]
                P_pred[t, i] = Pi
                Si = H[i] @ Pi @ H[i].T + R[i]
                S[t, i] = 0.5 * (Si + Si.T)
                W = np.linalg.solve(S[t, i], H[i] @ Pi).T  # P H^T S^{-1}
                gain[t, i] = W
                A[blk, blk] = np.eye(2) - W @ H[i]
                Wn[blk, blk] = W @ R[i] @ W.T
            return A, Wn

        cs._local_error_recursion(self, update)
        Acan, asc = _canonical_map(S, np.broadcast_to(R, S.shape))
        out = {"P_pred": P_pred, "gain": gain, "S": S, "Sigma": Sigma,
               "A": Acan @ H, "a_scale": asc}
        self._cache["local"] = out
        return out

    def sensor_groups(self) -> list[np.ndarray]:
        """Indices of sensors with identical ``(H^i, R^i)`` (they share every likelihood term)."""
        key = np.concatenate([self.Hs.reshape(self.N, -1), self.Rs.reshape(self.N, -1)], axis=1)
        _, inv = np.unique(key, axis=0, return_inverse=True)
        inv = inv.ravel()
        order = sorted(range(inv.max() + 1), key=lambda g: int(np.flatnonzero(inv == g)[0]))
        return [np.flatnonzero(inv == g) for g in order]


# ----------------------------------------------------------------------------- Proposition 6
def _ellipse_rule(a, K: int):
    """Nodes ``u (K^2, m)`` and weights of ``int_{sum u_j^2/a_j^2 < 1} g(u) phi(u) du``.

    ``m = 2``: ``u_1 = a_1 sin(theta)``, ``u_2 = a_2 cos(theta) sin(psi)``, Gauss-Legendre in
    both angles (the Jacobian ``a_1 a_2 cos^2(theta) cos(psi)`` removes the square roots at the
    boundary); ``m = 1``: ``u = a sin(theta)``. The standard normal density is in the weights.
    """
    s, c, w = _theta_rule(K)
    if len(a) == 1:
        u = (a[0] * s)[:, None]
        wt = w * a[0] * c * np.exp(-0.5 * u[:, 0] ** 2) * _INV_SQRT_2PI
        return u, wt
    S1, S2 = np.meshgrid(s, s, indexing="ij")
    C1, C2 = np.meshgrid(c, c, indexing="ij")
    W = np.outer(w, w) * a[0] * a[1] * C1 * C1 * C2
    u = np.stack([a[0] * S1, a[1] * C1 * S2], axis=-1).reshape(-1, 2)
    wt = (W.ravel() * np.exp(-0.5 * (u * u).sum(axis=1)) / (2.0 * math.pi))
    return u, wt


def log_all_silent(cov, S, eta, *, K: int = 48) -> float:
    """``log P(V_j^T S_j^{-1} V_j < eta for every j)`` for jointly Gaussian ``V ~ N(0, cov)``.

    ``S``: ``(k, m, m)`` for ``k`` in {1, 2} sensors, ``cov``: ``(k m, k m)``. This is the
    constant of the printed Proposition 6 for the silent set (``V_j = H^j e^j + n^j``, with
    ``cov`` from (21)-(23)). ``k = 1``: exactly ``log P(chi2_m < eta)``-like quadrature;
    ``k = 2``: ``V_2 | V_1`` is Gaussian, so the probability is ``E[1{V_1 silent}
    P(V_2 silent | V_1)]``, a 2-D quadrature over the first ellipse (``K x K`` nodes) of the
    accurate conditional probability.
    """
    eta = _eta(eta)
    S = _finite("S", S)
    if S.ndim != 3 or S.shape[0] not in (1, 2) or S.shape[1] != S.shape[2]:
        raise ValueError(f"S must be (k, m, m) with k in (1, 2) silent sensors, got {S.shape}")
    k, m = S.shape[0], S.shape[1]
    S = _pd("S", S, m)
    cov = _pd("cov", cov, k * m)
    if k == 1:
        return float(log_silent_probability(np.zeros(m), S[0], cov, eta))
    C11, C12, C22 = cov[:m, :m], cov[:m, m:], cov[m:, m:]
    B = np.linalg.solve(C11, C12).T  # E[V2 | V1] = B V1
    Ccond = C22 - B @ C12
    A, asc = _canonical_map(S[0], C11)  # u = A V1 ~ N(0, I), silent: sum u^2 / a^2 < 1
    u, wt = _ellipse_rule(math.sqrt(eta) * asc, K)
    V1 = np.linalg.solve(A, u.T).T
    inner = log_silent_probability(V1 @ B.T, S[1], Ccond, eta)
    return float(special.logsumexp(inner, b=wt))


def printed_mass(scenario: VectorScenario, l, t: int) -> float:
    """What the printed Proposition 6 sums to over all outcomes at step ``t`` (``N <= 2``).

    Integrating (40) over the received values (each ``p(z^i | x)`` integrates to one, since the
    send region depends on the unknown local prediction) and summing over the patterns ``m``
    gives ``sum_{silent sets A} P(every sensor of A silent)`` under (21)-(23): ``1 + P_1 + P_2 +
    P_12`` for ``N = 2``, ``P_j = 1 - l/N``; a likelihood would give 1.
    """
    if not isinstance(scenario, VectorScenario):
        raise ValueError("scenario must be a VectorScenario")
    if scenario.N > 2:
        raise ValueError(f"printed_mass is implemented for N <= 2 sensors, got N = {scenario.N}")
    t = _posint("t", t)
    if t > scenario.T:
        raise ValueError(f"t must lie in 1..T = 1..{scenario.T}, got {t}")
    eta = cs.threshold(l, scenario.N, dof=scenario.m)
    lf = scenario.local_filters()
    cov = silent_covariance(scenario, lf["Sigma"][t - 1])
    m, N = scenario.m, scenario.N
    total = 1.0
    for i in range(N):
        blk = slice(i * m, (i + 1) * m)
        total += math.exp(log_all_silent(cov[blk, blk], lf["S"][t - 1][i:i + 1], eta))
    if N == 2:
        total += math.exp(log_all_silent(cov, lf["S"][t - 1], eta))
    return total


def silent_covariance(sc: VectorScenario, Sigma: np.ndarray) -> np.ndarray:
    """``Cov(V) (N m, N m)`` of the sensors' own innovations ``V_j = H^j e^j + n^j`` under
    (21)-(23), from the joint local prediction-error covariance ``Sigma (2N, 2N)`` (one step of
    ``VectorScenario.local_filters()["Sigma"]``)."""
    N, m = sc.N, sc.m
    Hb = np.zeros((N * m, 2 * N))
    for i in range(N):
        Hb[i * m:(i + 1) * m, 2 * i:2 * i + 2] = sc.Hs[i]
    Rb = np.zeros((N * m, N * m))
    for i in range(N):
        Rb[i * m:(i + 1) * m, i * m:(i + 1) * m] = sc.Rs[i]
    C = Hb @ Sigma @ Hb.T + Rb
    return 0.5 * (C + C.T)


# ----------------------------------------------------------------------------- sensors
def local_decisions(sc: VectorScenario, eta: float, z: np.ndarray) -> np.ndarray:
    """Without feedback: every sensor runs its own Kalman filter on its measurements ``z (n, T,
    N, m)`` and sends when its NIS reaches ``eta``; returns ``sent (n, T, N)``."""
    lf = sc.local_filters()
    F, H = sc.F, sc.Hs
    n, T, N, m = z.shape
    sent = np.empty((n, T, N), dtype=bool)
    xhat = np.broadcast_to(F @ sc.dynamics.m0, (n, N, 2)).copy()
    Sinv = np.linalg.inv(lf["S"])
    for t in range(T):
        nu = z[:, t] - np.einsum("nik,imk->nim", xhat, H)
        sent[:, t] = np.einsum("nim,imj,nij->ni", nu, Sinv[t], nu) >= eta
        xhat = (xhat + np.einsum("ikm,nim->nik", lf["gain"][t], nu)) @ F.T
    return sent


def _whitening(R):
    """``(Linv, logdet)`` with ``R = L L^T``: ``|Linv d|^2 = d^T R^{-1} d``."""
    L = np.linalg.cholesky(R)
    return np.linalg.inv(L), 2.0 * float(np.log(np.diag(L)).sum())


class _VectorFC(cs._FeedbackModel):
    """The FC's particle-filter model (a :class:`fusioncenter.particle.FilterModel`) for one
    block of trials and every scheme except the exact no-feedback filter. It also plays the
    sensors: with feedback their decisions at step ``t`` depend on the FC's broadcast."""

    def __init__(self, sc: VectorScenario, scheme: str, feedback: str, eta: float, l: float,
                 z: np.ndarray, sel_u: np.ndarray, probability: str, n_q: int,
                 rng_q: np.random.Generator | None):
        self.sc, self.scheme, self.feedback, self.eta = sc, scheme, feedback, eta
        self.probability, self.n_q, self.rng_q = probability, n_q, rng_q
        self.z = z
        n, T, N, m = z.shape
        self.n, self.N, self.m = n, N, m
        self.dim = 2
        self.H, self.R = sc.Hs, sc.Rs
        self.groups = sc.sensor_groups()
        self.local = sc.local_filters()
        self._first_prediction(n)
        self.censor = scheme in ("cfomd", "cfwmd")
        self.fb = self.censor and feedback != "none"
        self.needs_cov = self.fb and feedback == "state+cov" and sc.feedback_moments == "analytic"
        if self.censor and feedback == "none":
            self.sent = local_decisions(sc, eta, z)
        elif scheme == "random":
            self.sent = sel_u < l / N
        elif scheme == "all-send":
            self.sent = np.ones((n, T, N), dtype=bool)
        else:
            self.sent = np.zeros((n, T, N), dtype=bool)
        # received likelihood per group: whitened particles x @ G and measurements
        self.white = {}
        for g in self.groups:
            Linv, logdet = _whitening(self.R[g[0]])
            G = (Linv @ self.H[g[0]]).T  # (2, m)
            cw = z[:, :, g] @ Linv.T  # (n, T, |g|, m)
            self.white[int(g[0])] = (G, cw, logdet)
        self.Sinv_local = np.linalg.inv(self.local["S"])  # (T, N, m, m)

    # --- sensors
    def _feedback_decisions(self, k: int, x: np.ndarray):
        self._cloud_moments(x)
        nu = self.z[:, k] - np.einsum("nk,imk->nim", self.pred_mean, self.H)
        if self.feedback == "state+cov":
            S = np.einsum("imk,nkl,ijl->nimj", self.H, self.pred_cov, self.H) + self.R
            S = 0.5 * (S + np.swapaxes(S, -1, -2))
            nis = np.einsum("nim,nim->ni", nu, np.linalg.solve(S, nu[..., None])[..., 0])
        else:
            S = None
            nis = np.einsum("nim,imj,nij->ni", nu, self.Sinv_local[k], nu)
        self.sent[:, k] = nis >= self.eta
        return S

    # --- FilterModel (initial, transition, observe: see censoring._FeedbackModel)
    def log_weight(self, t: int, x: np.ndarray) -> np.ndarray:
        k = t - 1
        S = self._feedback_decisions(k, x) if self.fb else None
        sent = self.sent[:, k]
        n, P, _ = x.shape
        out = np.zeros((n, P))
        for g in self.groups:
            g0 = int(g[0])
            G, cw, logdet = self.white[g0]
            sg = sent[:, g]
            n_obs = sg.sum(axis=1).astype(float)
            if np.any(n_obs):
                # sum over the received of |Linv (z_i - H x)|^2 = n |w - cbar|^2 + sum |c_i -
                # cbar|^2 (w = Linv H x, c_i = Linv z_i): one pass over the particles
                c = np.where(sg[..., None], cw[:, k], 0.0)  # (n, |g|, m)
                cbar = c.sum(axis=1) / np.maximum(n_obs, 1.0)[:, None]
                ss = (np.where(sg[..., None], c - cbar[:, None, :], 0.0) ** 2).sum(axis=(1, 2))
                d = x @ G - cbar[:, None, :]
                out += (-0.5 * n_obs[:, None]) * (d * d).sum(axis=-1) \
                    - (0.5 * ss + 0.5 * n_obs * (self.m * _LOG_2PI + logdet))[:, None]
            if self.scheme != "cfwmd" or not self.fb:
                continue
            n_sil = len(g) - n_obs
            rows = np.flatnonzero(n_sil)
            if rows.size == 0:
                continue
            dev = x[rows] - self.pred_mean[rows, None, :]
            if self.feedback == "state":
                A = self.local["A"][k, g0]
                a = math.sqrt(self.eta) * self.local["a_scale"][k, g0]
                b = dev @ A.T
            else:
                AL, asc = _canonical_map(S[rows, g0], self.R[g0])
                A = AL @ self.H[g0]  # (r, m, 2)
                a = math.sqrt(self.eta) * asc  # (r, m)
                b = dev @ np.swapaxes(A, -1, -2)
            val = _eval_silent(b, a, probability=self.probability, rng=self.rng_q, n_q=self.n_q)
            out[rows] += n_sil[rows, None] * val
        return out


def _truncated_std_normal(rng, lo, hi):
    """Draws of ``Z ~ N(0, 1)`` conditioned on ``lo < Z < hi``: the inverse cdf of
    :func:`fusioncenter.censoring._truncated_normal` at uniforms drawn from ``rng``."""
    return cs._truncated_normal(rng.random(np.broadcast_shapes(np.shape(lo), np.shape(hi))),
                                lo, hi)


def _sample_in_ellipse(rng, b, a, rounds: int = 16):
    """``u ~ N(b, I)`` conditioned on ``sum_j u_j^2 / a_j^2 < 1``; ``b (k, m)``, ``a (m,)``.

    Plain rejection for ``rounds`` rounds (acceptance = the silent probability, which the
    resampled particles make large: about 0.6 on average in the filter); then for what is left
    an exact sequential proposal: ``u_1`` from ``N(b_1, 1)`` truncated to ``(-a_1, a_1)``,
    ``u_2`` from ``N(b_2, 1)`` truncated to the chord at ``u_1``, accepted with probability
    ``Pin(b_2, chord(u_1)) / Pin(b_2, a_2)`` (the ratio of target to proposal, at most 1).
    After 200 such rounds a remaining draw keeps its last proposal (never seen in practice; the
    number is returned).
    """
    k, m = b.shape
    inv_a2 = 1.0 / (a * a)

    def inside(u):
        q = u[:, 0] * u[:, 0] * inv_a2[0]
        for j in range(1, m):
            q += u[:, j] * u[:, j] * inv_a2[j]
        return q < 1.0

    out = rng.standard_normal((k, m))
    out += b
    todo = np.flatnonzero(~inside(out))
    for _ in range(rounds - 1):
        if todo.size == 0:
            return out, 0
        u = rng.standard_normal((todo.size, m))
        u += b[todo]
        ok = inside(u)
        out[todo[ok]] = u[ok]
        todo = todo[~ok]
    if todo.size == 0:
        return out, 0
    if m == 1:
        bb = b[todo, 0]
        out[todo, 0] = bb + _truncated_std_normal(rng, -a[0] - bb, a[0] - bb)
        return out, 0
    for _ in range(200):
        b1, b2 = b[todo, 0], b[todo, 1]
        u1 = b1 + _truncated_std_normal(rng, -a[0] - b1, a[0] - b1)
        h = a[1] * np.sqrt(np.clip(1.0 - (u1 / a[0]) ** 2, 0.0, None))
        u2 = b2 + _truncated_std_normal(rng, -h - b2, h - b2)
        ratio = np.exp(_log_inside_1d(b2, h) - _log_inside_1d(b2, np.full_like(b2, a[1])))
        ok = rng.random(todo.size) < ratio
        out[todo, 0], out[todo, 1] = u1, u2
        todo = todo[~ok]
        if todo.size == 0:
            break
    return out, int(todo.size)


class _VectorExactFC(cs._ExactModel):
    """CFwMD without feedback, exact: a particle is ``(x_t, xhat^1_{t|t-1}, ..., xhat^N_{t|t-1})``.

    Given a particle, a sensor's decision is a deterministic function of its measurement, so the
    weight is exact: ``N(z^i; H x, R) 1{nu^T S^{-1} nu >= eta}`` (``nu = z^i - H xhat^i``) for a
    received ``z^i``, and ``P(nu^T S^{-1} nu < eta)``, ``nu ~ N(H (x - xhat^j), R)``, for a silent
    sensor (the same generalized chi-square probability as with feedback). Before the next
    propagation each particle runs the sensors' Kalman updates with the received ``z^i`` or with
    a draw of the missing ``z^j`` from ``N(H x, R)`` conditioned on the silent ellipse (its exact
    conditional law). As in the scalar library, a step where no particle of a trial is compatible
    with who sent is relaxed (the indicators dropped) and counted.
    """

    def __init__(self, sc: VectorScenario, eta: float, z: np.ndarray, sent: np.ndarray,
                 probability: str, n_q: int, rng_q):
        self.sc, self.eta, self.z, self.sent = sc, eta, z, sent
        self.probability, self.n_q, self.rng_q = probability, n_q, rng_q
        n, T, N, m = z.shape
        self.N, self.m = N, m
        self.relaxed = np.zeros((n, T), dtype=bool)
        self.unconverged = 0
        self.dim = 2 * (N + 1)
        self.H, self.R = sc.Hs, sc.Rs
        self.local = sc.local_filters()
        self.Sinv = np.linalg.inv(self.local["S"])
        self.white = [_whitening(self.R[i]) for i in range(N)]
        # u -> nu: nu = A_L^{-1} u with A_L = V^T L^{-1} (per step and sensor)
        AL, _ = _canonical_map(self.local["S"], np.broadcast_to(self.R, self.local["S"].shape))
        self.ALinv = np.linalg.inv(AL)

    def transition(self, rng, t, xa):
        out = np.empty_like(xa)
        if t > 1:  # the sensors' KF updates at step k = t - 1 (index t - 2), then predictions
            k = t - 2
            F = self.sc.F
            x = xa[..., :2]
            a = math.sqrt(self.eta) * self.local["a_scale"][k]
            for i in range(self.N):
                xh = xa[..., 2 + 2 * i:4 + 2 * i]
                nu = self.z[:, k, i][:, None, :] - xh @ self.H[i].T  # received: z - H xhat
                sil = np.flatnonzero(~self.sent[:, k, i])
                if sil.size:
                    b = (x[sil] - xh[sil]) @ self.local["A"][k, i].T  # (r, P, m)
                    u, left = _sample_in_ellipse(rng, b.reshape(-1, self.m), a[i])
                    self.unconverged += left
                    nu[sil] = (u @ self.ALinv[k, i].T).reshape(b.shape)
                out[..., 2 + 2 * i:4 + 2 * i] = (xh + nu @ self.local["gain"][k, i].T) @ F.T
        else:
            out[..., 2:] = xa[..., 2:]
        out[..., :2] = self.sc.dynamics.transition(rng, t, np.ascontiguousarray(xa[..., :2]))
        return out

    def log_weight(self, t, xa):
        k = t - 1
        n, P, _ = xa.shape
        x = xa[..., :2]
        full = np.zeros((n, P))
        ok = np.ones((n, P), dtype=bool)
        a = math.sqrt(self.eta) * self.local["a_scale"][k]
        for i in range(self.N):
            xh = xa[..., 2 + 2 * i:4 + 2 * i]
            sent = self.sent[:, k, i]
            rows = np.flatnonzero(sent)
            if rows.size:
                Linv, logdet = self.white[i]
                zi = self.z[rows, k, i][:, None, :]
                d = (zi - x[rows] @ self.H[i].T) @ Linv.T
                full[rows] += -0.5 * ((d * d).sum(axis=-1) + self.m * _LOG_2PI + logdet)
                nu = zi - xh[rows] @ self.H[i].T
                ok[rows] &= np.einsum("npm,mj,npj->np", nu, self.Sinv[k, i], nu) >= self.eta
            sil = np.flatnonzero(~sent)
            if sil.size:
                b = (x[sil] - xh[sil]) @ self.local["A"][k, i].T
                full[sil] += _eval_silent(b, a[i], probability=self.probability, rng=self.rng_q,
                                          n_q=self.n_q)
        return self._consistent(full, ok, k)

    def observe(self, t, mean, cov):
        pass


#: Particles per sub-block of the fused filter (whole trials): the ~60 array passes of a step
#: then run over arrays that stay in the core's cache.
_SUB_PARTICLES = 1 << 14


def _lin(M, c0, c1):
    """Rows of ``M (m, 2)`` applied to the components ``(c0, c1)``: a list of ``m`` arrays."""
    return [M[j, 0] * c0 + M[j, 1] * c1 for j in range(M.shape[0])]


class _FusedVector:
    """The FC's model of :func:`fusioncenter.particle.run_filter` for every scheme, with the
    silent factor from the interpolation tables (what :func:`run` uses by default).

    The same model as :class:`_VectorFC` / :class:`_VectorExactFC` with
    ``probability="table"`` -- it draws the same random numbers in the same order and the tests
    check that the two agree to rounding -- organized for speed: particles stored component by
    component (:func:`fusioncenter.particle.by_component`: position, velocity and, for the exact
    no-feedback filter, every sensor's local prediction), the weights computed over sub-blocks of
    whole trials of about 16k particles (every operation is row-wise, so a trial's result depends
    neither on the sub-blocks nor on the other trials), and additive per-trial constants of the
    log weights dropped.
    """

    def __init__(self, sc: VectorScenario, scheme: str, feedback: str, likelihood: str,
                 eta: float, l: float, z: np.ndarray, sel_u: np.ndarray):
        self.ref = _VectorFC(sc, scheme, feedback, eta, l, z, sel_u, "table", 1, None)
        self.sc, self.scheme, self.feedback, self.eta = sc, scheme, feedback, eta
        self.z = z
        n, T, N, m = z.shape
        self.n, self.T, self.N, self.m = n, T, N, m
        self.H, self.R = sc.Hs, sc.Rs
        self.local = sc.local_filters()
        self.sent = self.ref.sent
        self.fb = self.ref.fb
        self.exact = scheme == "cfwmd" and feedback == "none" and likelihood == "exact"
        self.silent_fb = scheme == "cfwmd" and self.fb
        self.analytic = sc.feedback_moments == "analytic"
        self.need_cov = self.ref.needs_cov
        self.relaxed = np.zeros((n, T), dtype=bool)
        self.unconverged = 0
        if self.exact:
            self.xref = _VectorExactFC(sc, eta, z, self.sent, "table", 1, None)
        self.sqeta = math.sqrt(eta)
        self.dim = 2 + 2 * N if self.exact else 2
        self.needs_cov = self.need_cov
        self.LQ = particle.psd_factor(sc.Q)  # the factor LinearGaussianDynamics draws with
        self.dt = float(sc.F[0, 1])

    # --- sensors with feedback (rows R, step k)
    def _decide(self, R: slice, k: int, p, v):
        ref = self.ref
        if not self.analytic:  # moments of the propagated cloud
            P = p.shape[1]
            mp, mv = p.mean(axis=1), v.mean(axis=1)
            ref.pred_mean[R, 0], ref.pred_mean[R, 1] = mp, mv
            if self.feedback == "state+cov":
                dp, dv = p - mp[:, None], v - mv[:, None]
                cpp, cpv, cvv = ((dp * dp).sum(1) / P, (dp * dv).sum(1) / P,
                                 (dv * dv).sum(1) / P)
                ref.pred_cov[R] = np.stack([np.stack([cpp, cpv], -1),
                                            np.stack([cpv, cvv], -1)], -2)
        pm = ref.pred_mean[R]
        nu = self.z[R, k] - np.einsum("nk,imk->nim", pm, self.H)
        if self.feedback == "state+cov":
            S = np.einsum("imk,nkl,ijl->nimj", self.H, ref.pred_cov[R], self.H) + self.R
            S = 0.5 * (S + np.swapaxes(S, -1, -2))
            nis = np.einsum("nim,nim->ni", nu, np.linalg.solve(S, nu[..., None])[..., 0])
        else:
            S = None
            nis = np.einsum("nim,imj,nij->ni", nu, ref.Sinv_local[k], nu)
        self.sent[R, k] = nis >= self.eta
        return S

    # --- log weights of rows R at step k (per-trial additive constants dropped)
    def _log_weight(self, R: slice, k: int, p, v, lp, lw) -> None:
        S = self._decide(R, k, p, v) if self.fb else None
        sent = self.sent[R, k]
        lw.fill(0.0)
        ref = self.ref
        if self.exact:
            self._log_weight_exact(R, k, p, v, lp, lw)
            return
        for g in ref.groups:
            g0 = int(g[0])
            G, cw, _ = ref.white[g0]
            sg = sent[:, g]
            n_obs = sg.sum(axis=1)
            if n_obs.any():
                c = np.where(sg[..., None], cw[R, k], 0.0)
                cbar = c.sum(axis=1) / np.maximum(n_obs, 1)[:, None]
                acc = None
                for j, wj in enumerate(_lin(G.T, p, v)):
                    wj -= cbar[:, j, None]
                    wj *= wj
                    acc = wj if acc is None else acc + wj
                acc *= (-0.5 * n_obs)[:, None]
                lw += acc
            if not self.silent_fb:
                continue
            n_sil = len(g) - n_obs
            rows = np.flatnonzero(n_sil)
            if rows.size == 0:
                continue
            every = rows.size == n_sil.size
            pm = ref.pred_mean[R][rows]
            dp = (p if every else p[rows]) - pm[:, 0, None]
            dv = (v if every else v[rows]) - pm[:, 1, None]
            if self.feedback == "state":
                b = _lin(self.local["A"][k, g0], dp, dv)
                val = _log_silent_fixed(b, self.sqeta * self.local["a_scale"][k, g0])
            else:
                AL, asc = _canonical_map(S[rows, g0], self.R[g0])
                A = AL @ self.H[g0]  # (r, m, 2)
                b = [A[:, j, 0, None] * dp + A[:, j, 1, None] * dv for j in range(self.m)]
                val = _log_silent_trials(b, self.sqeta * asc)
            if np.any(n_sil[rows] != 1):
                val *= n_sil[rows, None]
            if every:
                lw += val
            else:
                lw[rows] += val

    def _log_weight_exact(self, R: slice, k: int, p, v, lp, lw) -> None:
        xr = self.xref
        sent = self.sent[R, k]
        ok = None
        a = self.sqeta * self.local["a_scale"][k]
        for i in range(self.N):
            h0, h1 = lp[i]
            rows = np.flatnonzero(sent[:, i])
            if rows.size:
                Linv, _ = xr.white[i]
                zi = self.z[R, k, i][rows]  # (r, m)
                pr, vr = p[rows], v[rows]
                acc = None
                for j, wj in enumerate(_lin(Linv @ self.H[i], pr, vr)):
                    d = (Linv @ zi.T)[j][:, None] - wj
                    d *= d
                    acc = d if acc is None else acc + d
                lw[rows] += -0.5 * acc
                nu = [zi[:, j, None] - hj for j, hj in enumerate(_lin(self.H[i], h0[rows],
                                                                       h1[rows]))]
                Si = xr.Sinv[k, i]
                nis = sum(Si[j, jj] * nu[j] * nu[jj] for j in range(self.m)
                          for jj in range(self.m))
                good = nis >= self.eta
                if ok is None:
                    ok = np.ones(lw.shape, dtype=bool)
                ok[rows] &= good
            sil = np.flatnonzero(~sent[:, i])
            if sil.size:
                every = sil.size == sent.shape[0]
                dp = (p if every else p[sil]) - (h0 if every else h0[sil])
                dv = (v if every else v[sil]) - (h1 if every else h1[sil])
                val = _log_silent_fixed(_lin(self.local["A"][k, i], dp, dv), a[i])
                if every:
                    lw += val
                else:
                    lw[sil] += val
        if ok is not None:
            dead = ~ok.any(axis=1)
            keep = ok | dead[:, None]  # no compatible particle: relax the indicators
            lw[~keep] = -np.inf
            if dead.any():
                self.relaxed[np.arange(R.start, R.stop)[dead], k] = True

    # --- the exact filter's local Kalman updates at step k (whole block: it draws)
    def _local_update(self, rng, k: int, pos, vel, lp) -> None:
        xr = self.xref
        F = self.sc.F
        a = self.sqeta * self.local["a_scale"][k]
        for i in range(self.N):
            h0, h1 = lp[i]
            nu = [self.z[:, k, i, j, None] - hj for j, hj in enumerate(_lin(self.H[i], h0, h1))]
            sil = np.flatnonzero(~self.sent[:, k, i])
            if sil.size:
                b = _lin(self.local["A"][k, i], pos[sil] - h0[sil], vel[sil] - h1[sil])
                bs = np.stack([bj.ravel() for bj in b], axis=1)
                u, left = _sample_in_ellipse(rng, bs, a[i])
                self.unconverged += left
                nus = u @ xr.ALinv[k, i].T
                for j in range(self.m):
                    nu[j][sil] = nus[:, j].reshape(sil.size, -1)
            W = self.local["gain"][k, i]  # (2, m)
            u0 = h0 + sum(W[0, j] * nu[j] for j in range(self.m))
            u1 = h1 + sum(W[1, j] * nu[j] for j in range(self.m))
            h0[...] = F[0, 0] * u0 + F[0, 1] * u1
            h1[...] = F[1, 0] * u0 + F[1, 1] * u1

    # --- FilterModel (fusioncenter.particle.run_filter on the whole block)
    def initial(self, rng: np.random.Generator, n: int, P: int) -> np.ndarray:
        """``(n, P, dim)``: ``x_0`` drawn from the prior, then (exact filter) every sensor's
        local prediction ``F x0``."""
        dyn = self.sc.dynamics
        x = particle.by_component(np.empty((n, P, self.dim)))
        x[..., :2] = dyn.initial(rng, n, P)
        if self.exact:
            start = self.sc.F @ dyn.m0
            x[..., 2::2] = start[0]
            x[..., 3::2] = start[1]
        return x

    def _local_views(self, x, R=slice(None)):
        return [(x[R, :, 2 + 2 * i], x[R, :, 3 + 2 * i]) for i in range(self.N)] \
            if self.exact else None

    def transition(self, rng: np.random.Generator, t: int, x: np.ndarray) -> np.ndarray:
        """The exact filter's local Kalman updates of step ``t - 1`` (they draw the missing
        measurements), then ``F x + L g`` for the target (in place)."""
        if self.exact and t > 1:
            self._local_update(rng, t - 2, x[..., 0], x[..., 1], self._local_views(x))
        kq = self.LQ.shape[1]
        g = rng.standard_normal((*x.shape[:2], kq)) if kq else np.empty((*x.shape[:2], 0))
        _kernels.propagate_wna(x, self.dt, g, self.LQ)
        return x

    def log_weight(self, t: int, x: np.ndarray) -> np.ndarray:
        """Log weights ``(n, P)``, computed on sub-blocks of about 16k particles (whole trials;
        every operation is row-wise, so the sub-blocks do not change a trial's weights)."""
        n, P = x.shape[:2]
        lw = np.empty((n, P))
        sub = max(1, _SUB_PARTICLES // P)
        for s0 in range(0, n, sub):
            R = slice(s0, min(n, s0 + sub))
            self._log_weight(R, t - 1, x[R, :, 0], x[R, :, 1], self._local_views(x, R), lw[R])
        return lw

    def observe(self, t: int, mean: np.ndarray, cov: np.ndarray | None) -> None:
        """What is fed back at ``t + 1`` (``feedback_moments="analytic"``)."""
        if self.fb and self.analytic:
            self.ref.pred_mean[:, 0] = mean[:, 0] + self.dt * mean[:, 1]
            self.ref.pred_mean[:, 1] = mean[:, 1]
            if self.need_cov:
                F, Q = self.sc.F, self.sc.Q
                pc = F @ cov[:, :2, :2] @ F.T + Q
                self.ref.pred_cov = 0.5 * (pc + np.swapaxes(pc, -1, -2))


def _chunk(rng: np.random.Generator, n: int, *, scenario: VectorScenario, scheme: str,
           feedback: str, likelihood: str, eta: float, l: float, n_particles: int,
           ess_threshold: float, probability: str, n_q: int) -> np.ndarray:
    """``chunk_fn`` for :func:`fusioncenter.montecarlo.simulate`: ``(n, T, 5)`` per trial.

    Columns ``[squared error of position, of velocity | number of sensors that sent |
    ESS / n_particles | 1 if the weights collapsed]`` (the layout of
    :class:`fusioncenter.censoring.CensoringResult`). Streams spawned from ``rng``: the first
    draws the truth, the measurements and the random-selection uniforms (the same for every
    scheme: trials are paired), the second the filter's particles, resampling uniforms and the
    exact filter's imputations, the third the samples of ``probability="sampled"``.
    Every filter is a model of :func:`fusioncenter.particle.run_filter`: with
    ``probability="table"`` :class:`_FusedVector` (interpolation tables, sub-blocks), otherwise
    :class:`_VectorFC` / :class:`_VectorExactFC` (quadrature or sampled probabilities).
    """
    rng_data, rng_pf, rng_q = rng.spawn(3)
    # the filter's stream: SFC64 from the same spawned seed sequence (its normal draws, the
    # largest single cost of the filter, are ~15 % cheaper than PCG64's)
    rng_pf = np.random.Generator(np.random.SFC64(rng_pf.bit_generator.seed_seq))
    x, z = scenario.sample(rng_data, n)
    sel_u = rng_data.random(z.shape[:-1])
    if probability == "table":
        fused = _FusedVector(scenario, scheme, feedback, likelihood, eta, l, z, sel_u)
        out = particle.run_filter(fused, rng_pf, n, n_particles, scenario.T,
                                  ess_threshold=ess_threshold)
        return cs.trial_columns(out, x, fused.sent, n_particles, fused.relaxed)
    fc = _VectorFC(scenario, scheme, feedback, eta, l, z, sel_u, probability, n_q, rng_q)
    model = fc
    if scheme == "cfwmd" and feedback == "none" and likelihood == "exact":
        model = _VectorExactFC(scenario, eta, z, fc.sent, probability, n_q, rng_q)
    out = particle.run_filter(model, rng_pf, n, n_particles, scenario.T,
                              ess_threshold=ess_threshold)
    return cs.trial_columns(out, x, fc.sent, n_particles, getattr(model, "relaxed", None))


# ----------------------------------------------------------------------------- run
def run(scenario: VectorScenario, scheme: str, *, l, n_trials: int, n_particles: int, seed: int,
        feedback: str = "state", likelihood: str = "exact", ess_threshold: float = 1.0,
        chunk_size: int | None = None, executor=None, progress: bool = False,
        block_size: int = montecarlo.DEFAULT_BLOCK_SIZE, probability: str = "table",
        n_q: int = 100) -> cs.CensoringResult:
    """Simulate ``n_trials`` trials of ``scenario`` and track them with the FC's particle filter.

    The same contract as :func:`fusioncenter.censoring.run` (and the same result type,
    :class:`fusioncenter.censoring.CensoringResult`, usable with
    :func:`fusioncenter.censoring.paired_difference`): ``scheme`` in :data:`SCHEMES`,
    ``feedback`` in :data:`FEEDBACK` (``"state+cov"`` is the paper's CFwMD2), ``l`` the target
    average number of sending sensors, ``eta = threshold(l, N, dof=m)``. ``likelihood`` selects
    how ``scheme="cfwmd"`` fuses without feedback: ``"exact"`` (default: particles of dimension
    ``2 (N + 1)`` carry the local predictions) or Proposition 6 ``"printed"`` (which equals
    CFoMD; ``"corrected"`` of the scalar library -- the received sensors' conditions kept under
    the law (21) -- is a ``2 N m``-dimensional integral per particle and raises ``ValueError``
    for ``scheme="cfwmd"`` without feedback; like every value it is ignored by the other scheme
    and feedback combinations, so the scalar library's default can be passed through).
    ``probability`` (``"table"``, ``"quadrature"``, ``"sampled"`` with ``n_q`` draws per particle)
    selects how the silent factor is evaluated (see :data:`PROBABILITIES`).

    Runs through :func:`fusioncenter.montecarlo.simulate`: results are bitwise identical for any
    ``chunk_size`` and executor; trials are paired across schemes for the same ``seed``,
    ``n_trials`` and ``block_size``.
    """
    if not isinstance(scenario, VectorScenario):
        raise ValueError("scenario must be a VectorScenario")
    cs._check_scheme(scheme, feedback)
    if likelihood not in (*LIKELIHOODS, "corrected"):
        raise ValueError(f"likelihood must be one of {LIKELIHOODS}, got {likelihood!r}")
    if likelihood == "corrected" and scheme == "cfwmd" and feedback == "none":
        raise ValueError("likelihood='corrected' is not implemented for vector observations (it "
                         "is an integral over every sensor's local prediction per particle): "
                         f"use one of {LIKELIHOODS}")
    _one_of("probability", probability, PROBABILITIES)
    n_q = _posint("n_q", n_q)
    eta = cs.threshold(l, scenario.N, dof=scenario.m)
    n_particles = _posint("n_particles", n_particles)
    cs._check_resampling(scenario, ess_threshold)
    return cs._run_chunks(_chunk, scenario, scheme, feedback, likelihood, l=l, eta=eta,
                          n_particles=n_particles, ess_threshold=ess_threshold,
                          n_trials=n_trials, seed=seed, chunk_size=chunk_size, executor=executor,
                          progress=progress, block_size=block_size,
                          chunk_kwargs={"likelihood": likelihood, "probability": probability,
                                        "n_q": n_q})
