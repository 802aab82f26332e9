"""Compiled inner loops of the fused particle filters (:class:`fusioncenter.censoring._FusedFilter`
and the vector observations' filter in :mod:`fusioncenter.censoring_vector`).

Once the weights of a step are known, NumPy needs about a dozen passes over the
``(trials, particles)`` arrays for what a particle filter does with them: three weighted sums
for the estimate and the effective sample size, then ``cumsum``, divide, ``ceil``, differences,
``repeat`` and a gather per coordinate for systematic resampling; evaluating an interpolation
table takes another dozen. The functions here do the same work in one or two passes per trial,
compiled by Numba. They go row by row, so a trial's result never depends on the other trials of
a block (results stay independent of chunking), and they draw no random numbers (the filters
draw them with NumPy, in the same order as the reference engine).

The arithmetic is the NumPy code's, operation for operation, except the order of the weighted
sums (sequential here, pairwise in NumPy), which changes results by rounding only; the tests
compare the fused engines with the reference engine (:func:`fusioncenter.particle.run_filter`)
to ``1e-9`` and each kernel with its NumPy counterpart (``tests/test_kernels.py``).
"""

from __future__ import annotations

import math

import numba
import numpy as np

__all__ = ["systematic_ancestors", "table_shifted", "take_rows", "weighted_moments"]


@numba.njit(cache=True, nogil=True)
def weighted_moments(w, p, v, S, mp, mv, ess):
    """Per row ``b`` of the (unnormalized) weights ``w``: ``S = sum w``, the weighted means
    ``mp = sum(w p) / S``, ``mv = sum(w v) / S`` and ``ess = S^2 / sum w^2``, in one pass."""
    m, P = w.shape
    for b in range(m):
        s = 0.0
        sp = 0.0
        sv = 0.0
        s2 = 0.0
        for i in range(P):
            x = w[b, i]
            s += x
            sp += x * p[b, i]
            sv += x * v[b, i]
            s2 += x * x
        S[b] = s
        mp[b] = sp / s
        mv[b] = sv / s
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
    """``dst[b, k] = src[b, anc[b, k]]`` (resampled particles, row by row)."""
    m, P = anc.shape
    for b in range(m):
        for k in range(P):
            dst[b, k] = src[b, anc[b, k]]


@numba.njit(cache=True, nogil=True)
def table_shifted(coef, n_int, y, shift, scale, out):
    """Interpolation table (:class:`fusioncenter.censoring._LogTable`, even) at
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
