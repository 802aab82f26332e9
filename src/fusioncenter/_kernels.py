"""Compiled inner loops of the particle filter :func:`fusioncenter.particle.run_filter` and of
its fusion-centre models (:class:`fusioncenter.censoring.LinearFusionCentre`, the vector
observations' model in :mod:`fusioncenter.censoring_vector`).

Once the weights of a step are known, NumPy needs about a dozen passes over the
``(trials, particles)`` arrays for what a particle filter does with them: three weighted sums
for the estimate and the effective sample size, then ``cumsum``, divide, ``ceil``, differences,
``repeat`` and a gather for systematic resampling; evaluating an interpolation table takes
another dozen. The functions here do the same work in one or two passes per trial, compiled by
Numba. They go row by row, so a trial's result never depends on the other trials of a block
(results stay independent of chunking), and they draw no random numbers.

The arithmetic is the NumPy code's, operation for operation, except the order of the weighted
sums (sequential here, pairwise in NumPy), which changes results by rounding only; the tests
compare each kernel with its NumPy counterpart (``tests/test_kernels.py``) and the loop with the
same loop written with :mod:`fusioncenter.particle`'s NumPy functions
(``tests/test_censoring.py``). Particles may be stored in any memory layout
(:func:`fusioncenter.particle.by_component` keeps each component's row contiguous).
"""

from __future__ import annotations

import math

import numba
import numpy as np

__all__ = ["propagate_wna", "systematic_ancestors", "table_shifted", "take_rows",
           "weighted_moments"]


@numba.njit(cache=True, nogil=True)
def weighted_moments(w, x, S, mean, ess):
    """Per row ``b`` of the (unnormalized) weights ``w (m, P)`` and particles ``x (m, P, d)``:
    ``S[b] = sum_i w[b, i]``, the weighted means ``mean[b, j] = sum_i w[b, i] x[b, i, j] / S[b]``
    and ``ess[b] = S[b]^2 / sum_i w[b, i]^2``, in one sequential pass over the particles."""
    m, P = w.shape
    d = x.shape[2]
    if d == 2:  # the common case, written out (twice as fast as the general loop)
        for b in range(m):
            s = 0.0
            s0 = 0.0
            s1 = 0.0
            s2 = 0.0
            for i in range(P):
                wi = w[b, i]
                s += wi
                s0 += wi * x[b, i, 0]
                s1 += wi * x[b, i, 1]
                s2 += wi * wi
            S[b] = s
            mean[b, 0] = s0 / s
            mean[b, 1] = s1 / s
            ess[b] = s * s / s2
        return
    acc = np.empty(d)
    for b in range(m):
        s = 0.0
        s2 = 0.0
        for j in range(d):
            acc[j] = 0.0
        for i in range(P):
            wi = w[b, i]
            s += wi
            for j in range(d):
                acc[j] += wi * x[b, i, j]
            s2 += wi * wi
        S[b] = s
        for j in range(d):
            mean[b, j] = acc[j] / s
        ess[b] = s * s / s2


@numba.njit(cache=True, nogil=True)
def systematic_ancestors(w, S, u, todo, anc):
    """Ancestors ``anc (m, P)`` of systematic resampling for every row ``b`` with ``todo[b]``
    (one uniform ``u[b]``); the other rows get the identity. Particle ``i`` is kept
    ``c_i - c_{i-1}`` times, with ``c_i = ceil(P C_i / S - u)`` from the running sum ``C`` of
    the weights, ``c_{-1} = 0`` and ``c_{P-1} = P``: the arithmetic, in its order, of the NumPy
    version (``cumsum``, divide, multiply, subtract, ``ceil``). ``S[b]`` must be the row's
    sequential sum ``C_{P-1}``, as :func:`weighted_moments` computes it.

    Branch-light: particle ``i`` is written as the ancestor of slot ``c_{i-1}`` (particles with
    no offspring write the same slot before the one that owns it), then a running maximum
    fills the runs of repeated ancestors."""
    m, P = w.shape
    for b in range(m):
        if not todo[b]:
            for k in range(P):
                anc[b, k] = k
            continue
        for k in range(P):
            anc[b, k] = 0
        total = S[b]
        ub = u[b]
        c = 0.0
        lo = 0
        for i in range(P - 1):
            c += w[b, i]
            if lo < P:
                anc[b, lo] = i
            lo = int(math.ceil(c / total * P - ub))
        if lo < P:
            anc[b, lo] = P - 1
        a = 0
        for k in range(P):
            a = max(a, anc[b, k])
            anc[b, k] = a


@numba.njit(cache=True, nogil=True)
def take_rows(src, anc, dst):
    """``dst[b, k, :] = src[b, anc[b, k], :]`` (resampled particles ``(m, P, d)``, row by row)."""
    m, P = anc.shape
    d = src.shape[2]
    if d == 2:
        for b in range(m):
            for k in range(P):
                a = anc[b, k]
                dst[b, k, 0] = src[b, a, 0]
                dst[b, k, 1] = src[b, a, 1]
        return
    for b in range(m):
        for k in range(P):
            a = anc[b, k]
            for j in range(d):
                dst[b, k, j] = src[b, a, j]


@numba.njit(cache=True, nogil=True)
def propagate_wna(x, dt, g, L):
    """The white-noise-acceleration transition in place: for every particle ``x[b, i] = (p, v)``,
    ``p <- p + dt v``, then for each noise column ``j``: ``p <- p + g[b, i, j] L[0, j]`` and
    ``v <- v + g[b, i, j] L[1, j]`` (``L L^T = Q``), in this order (the NumPy arithmetic of
    ``x F^T + g L^T`` written out for ``F = [[1, dt], [0, 1]]``)."""
    m, P = x.shape[0], x.shape[1]
    k = g.shape[2]
    for b in range(m):
        for i in range(P):
            p = x[b, i, 0]
            v = x[b, i, 1]
            p = p + v * dt
            for j in range(k):
                gj = g[b, i, j]
                p = p + gj * L[0, j]
                v = v + gj * L[1, j]
            x[b, i, 0] = p
            x[b, i, 1] = v


@numba.njit(cache=True, nogil=True)
def table_shifted(coef, n_int, y, shift, scale, out):
    """Interpolation table (:class:`fusioncenter.censoring.tables.LogTable`, even) at
    ``|y[b, i] - shift[b]| * scale`` in units of the table's step: ``out[b, i]`` is the Horner
    polynomial of the interval's coefficients ``coef[j]`` at the fractional part. Points beyond
    the table or on an interval with a non-finite node get NaN (the caller evaluates the exact
    function there). Returns the number of such points."""
    m, P = y.shape
    deg = coef.shape[1]
    n_far = 0
    for b in range(m):
        sh = shift[b]
        for i in range(P):
            t = abs(y[b, i] - sh) * scale
            if not t < n_int:  # beyond the table (or not finite)
                out[b, i] = np.nan
                n_far += 1
                continue
            j = int(t)
            t -= j
            acc = coef[j, 0] * t + coef[j, 1]
            for q in range(2, deg):
                acc = acc * t + coef[j, q]
            if acc != acc:
                n_far += 1
            out[b, i] = acc
    return n_far
