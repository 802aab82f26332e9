"""The interpolation tables of the silent probability that the particle filter evaluates for
every particle of every trial at every step.

There the quadrature of :mod:`~fusioncenter.censoring.ellipse.quadrature` is *separable*: on a
grid ``(b_1^g, b_2^h)`` the integral is a matrix product ``sum_k N_gk M_hk`` of ``exp`` and
``ndtr`` values, and so are its derivatives (:func:`grid_terms`). Bicubic Hermite interpolation
of ``log P`` (values and exact derivatives on a grid of step 1/8) then costs ~16 gathers and ~60
arithmetic operations per particle, with an error below 1e-7 (tested). With state feedback (and
for the exact no-feedback filter) the ellipse depends only on the step, so one table per step
serves every trial (:func:`log_silent_table`); with covariance feedback (CFwMD2) the ellipse
differs per trial and a small table over each trial's particle cloud is built per step (48 x 48
nodes, error < 1e-6; :func:`log_silent_per_trial`). :func:`eval_silent` evaluates the factor by
any of :data:`PROBABILITIES`."""

from __future__ import annotations

import functools
import math

import numpy as np
from scipy import special

from fusioncenter._compiled import ellipse_tables
from fusioncenter.censoring.ellipse.quadrature import (
    log_canon,
    log_canonical,
    log_inside_1d,
    theta_rule,
)

#: How the particle filter evaluates the silent factor: ``"table"`` (interpolation of the exact
#: quadrature, error < 1e-6 in the log), ``"quadrature"`` (the accurate quadrature at every
#: particle: slow, for checks) or ``"sampled"`` (the paper's Monte Carlo estimate with ``n_q``
#: draws per particle).
PROBABILITIES = ("table", "quadrature", "sampled")

_INV_SQRT_2PI = 1.0 / math.sqrt(2.0 * math.pi)


def grid_terms(g1, g2, a1, a2, K: int):
    """``log P`` and its derivatives on the grid ``g1 x g2`` (canonical coordinates).

    ``g1 (..., G1)``, ``g2 (..., G2)``, ``a1``, ``a2`` ``(...)``. Returns ``f, f1, f2, f12``
    ``(..., G1, G2)``: ``log P``, ``d/db1``, ``d/db2``, ``d2/db1 db2``, from the separable form
    ``P = N M^T`` of the ``theta`` quadrature (``K`` nodes, ``K`` even): ``N_gk = w_k a_1 cos
    phi(a_1 sin - b_1^g)`` and ``M_hk = Phi(a_2 cos - b_2^h) - Phi(-a_2 cos - b_2^h)`` (``cos``
    takes only ``K/2`` values: the nodes are symmetric); derivatives by differentiating ``N``
    and ``M`` (``phi`` terms), so everything is four matrix products.

    Parameters
    ----------
    g1, g2 : numpy.ndarray
        Grid abscissae ``(..., G1)`` and ordinates ``(..., G2)``.
    a1, a2 : array_like
        Semi-axes ``(...)``.
    K : int
        Quadrature nodes, even.

    Returns
    -------
    tuple of numpy.ndarray
        ``(f, f1, f2, f12)``, each ``(..., G1, G2)``.
    """
    s, c, w = theta_rule(K)
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

    Values and exact derivatives on the grid of step ``h`` (:func:`grid_terms`) are turned into
    the 16 power-basis coefficients of every cell once, so a point costs one gather of 16
    numbers and a 2-D Horner scheme. Points beyond ``B`` are evaluated by the accurate quadrature
    (:func:`log_canon`). The value at a point depends only on its cell.
    """

    def __init__(self, a1: float, a2: float, h: float, B: float, K: int):
        self.a1, self.a2 = a1, a2
        G = int(round(B / h)) + 1
        self.G, self.h, self.inv_h = G, h, 1.0 / h
        g = np.arange(G) * h
        f, f1, f2, f12 = grid_terms(g, g, a1, a2, K)
        V = np.empty((G - 1, G - 1, 4, 4))
        by_order = {(0, 0): f, (1, 0): f1, (0, 1): f2, (1, 1): f12}
        ends = ((0, 0), (1, 0), (0, 1), (1, 1))  # (corner, derivative order): value 0/1, deriv 0/1
        for r, (di, ti) in enumerate(ends):
            for q, (dj, tj) in enumerate(ends):
                V[..., r, q] = by_order[(ti, tj)][di:G - 1 + di, dj:G - 1 + dj] * h ** (ti + tj)
        C = _HERMITE.T @ V @ _HERMITE  # (G-1, G-1, 4, 4): coefficient of t1^p t2^q
        self.coef = np.ascontiguousarray(np.moveaxis(C, (2, 3), (0, 1)).reshape(16, (G - 1) ** 2))

    def __call__(self, x1, x2):
        """``log P`` at ``(|b_1|, |b_2|) = (x1, x2)`` (non-negative arrays of one shape):
        :func:`fusioncenter._compiled.ellipse_tables.power_table` (the gather and the 2-D
        Horner scheme compiled), then the quadrature beyond the table."""
        x1 = np.ascontiguousarray(x1, dtype=float)
        x2 = np.ascontiguousarray(x2, dtype=float)
        out = np.empty(x1.shape)
        far = np.empty(x1.shape, dtype=bool)
        ellipse_tables.power_table(self.coef, self.G, self.inv_h, x1, x2, out, far)
        if far.any():
            out[far] = log_canon(x1[far], x2[far], self.a1, self.a2)
        return out


def _hermite_basis(t):
    """The cubic Hermite basis at ``t`` in ``[0, 1]``: ``A0`` (``A1 = 1 - A0``: the weights of
    the values at 0 and 1) and ``D0``, ``D1`` (of the derivatives times the step)."""
    u = 1.0 - t
    D0 = u * u
    A0 = (2.0 * t + 1.0) * D0
    D0 *= t
    D1 = t * t
    D1 *= -u
    return A0, D0, D1


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

    def rows(self, x1, x2):
        """``__call__(arange(n_tab)[:, None], x1, x2)`` without ``outside``: row ``r`` of the
        points ``(n_tab, P)`` in table ``r``, compiled
        (:func:`fusioncenter._compiled.ellipse_tables.hermite_tables`, the same arithmetic)."""
        out = np.empty(np.shape(x1))
        ellipse_tables.hermite_tables(self.f, self.f1, self.f2, self.f12, self.o1, self.o2, self.h1,
                                      self.h2, self.G1, self.G2, x1, x2, out)
        return out

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
        A0, D0, D1 = _hermite_basis(t1)
        B0, E0, E1 = _hermite_basis(t2)
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


def log_silent_table(b, a):
    """``log P`` at canonical points given as component arrays ``b = (b_1[, b_2])`` for one
    ellipse ``a (m,)`` (table, exact where it does not reach).

    Parameters
    ----------
    b : tuple of numpy.ndarray
        ``(b_1,)`` or ``(b_1, b_2)``, arrays of one shape.
    a : numpy.ndarray
        Semi-axes ``(m,)``.

    Returns
    -------
    numpy.ndarray
        ``log P`` at the points.
    """
    if len(b) == 1:
        return log_inside_1d(b[0], a[0])
    return _fixed_table(float(a[0]), float(a[1]))(np.abs(b[0]), np.abs(b[1]))


def log_silent_per_trial(b, a):
    """``log P`` at canonical points ``b = (b_1[, b_2])`` (arrays ``(r, P)``), one ellipse per
    trial ``a (r, m)``.

    One table per trial over the box of its particles: bicubic Hermite from values and exact
    derivatives at ``G x G`` nodes, ``G`` the smallest of :data:`_TRIAL_SIZES` that makes the
    step at most ``_TRIAL_STEP`` (a trial's table depends only on its own particles). Trials
    spreading wider, or lying beyond ``|b| = 30``, use the accurate quadrature.

    Parameters
    ----------
    b : tuple of numpy.ndarray
        ``(b_1,)`` or ``(b_1, b_2)``, each ``(r, P)``.
    a : numpy.ndarray
        Semi-axes ``(r, m)``, one ellipse per trial.

    Returns
    -------
    numpy.ndarray
        ``log P`` ``(r, P)``.
    """
    if len(b) == 1:
        return log_inside_1d(b[0], a[:, :1])
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
        f, f1, f2, f12 = grid_terms(grid[:, 0], grid[:, 1], a[ok, 0], a[ok, 1], _TRIAL_K)
        good = np.isfinite(f).all(axis=(1, 2)) & np.isfinite(f12).all(axis=(1, 2))
        if not good.all():  # a node underflowed (not expected for |b| <= 30): exact instead
            far[ok[~good]] = True
        tab = _Hermite2D(f, f1, f2, f12, lo[ok, 0], lo[ok, 1], step[:, 0], step[:, 1])
        out[ok] = tab.rows(b1[ok], b2[ok])
    bad = np.flatnonzero(far)
    if bad.size:
        aa = a[bad]
        out[bad] = log_canon(b1[bad], b2[bad], aa[:, :1], aa[:, 1:])
    return out


def eval_silent(b, a, *, probability: str = "table", rng=None, n_q: int = 0):
    """``log P`` at canonical points ``b (n, P, m)``; ``a`` is ``(m,)`` (one ellipse) or
    ``(n, m)`` (one per trial). Sub-blocks of trials keep the arrays in cache.

    Parameters
    ----------
    b : numpy.ndarray
        Canonical points ``(n, P, m)``.
    a : numpy.ndarray
        Semi-axes ``(m,)`` or ``(n, m)``.
    probability : str, optional
        One of :data:`PROBABILITIES`.
    rng : numpy.random.Generator, optional
        Source of the draws (``probability="sampled"``).
    n_q : int, optional
        Draws per particle (``probability="sampled"``).

    Returns
    -------
    numpy.ndarray
        ``log P`` ``(n, P)``.
    """
    n, P, m = b.shape
    per_trial = a.ndim == 2
    if probability == "quadrature":
        return log_canonical(b, np.broadcast_to(a[:, None, :] if per_trial else a, b.shape))
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
        out[R] = log_silent_per_trial(comps, a[R]) if per_trial else log_silent_table(comps, a)
    return out


#: Points per sub-block of the table evaluations (keeps the temporaries in cache).
_SUB_POINTS = 1 << 13
