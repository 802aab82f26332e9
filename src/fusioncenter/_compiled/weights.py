"""A particle-filter step's weights, compiled: the log weights shifted by their row's maximum
(:func:`shift_by_row_max`), then the weight sum, the weighted means and the effective sample
size in one pass (:func:`weighted_moments`), for :func:`fusioncenter.particle.run_filter`.

Once the weights of a step are known, NumPy needs several passes over the ``(trials,
particles)`` arrays for what the filter does with them (the maximum and subtraction, then three
weighted sums); these kernels do the same work in one or two passes per trial. They go row by
row, so a trial's result never depends on the other trials of a block (results stay
independent of chunking), and they draw no random numbers. The arithmetic is the NumPy code's,
operation for operation, except the order of the weighted sums (sequential here, pairwise in
NumPy), which changes results by rounding only (``tests/test_kernels.py``,
``tests/test_censoring.py``). Particles may be stored in any memory layout
(:func:`fusioncenter.particle.by_component` keeps each component's row contiguous).
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["shift_by_row_max", "weighted_moments"]


@numba.njit(cache=True, nogil=True)
def _moments_row2(w, x, b, S, mean, ess):
    """:func:`weighted_moments` of row ``b`` for ``d = 2``, written out (twice as fast as the
    general loop)."""
    s = 0.0
    s0 = 0.0
    s1 = 0.0
    s2 = 0.0
    for i in range(w.shape[1]):
        wi = w[b, i]
        s += wi
        s0 += wi * x[b, i, 0]
        s1 += wi * x[b, i, 1]
        s2 += wi * wi
    S[b] = s
    mean[b, 0] = s0 / s
    mean[b, 1] = s1 / s
    ess[b] = s * s / s2

@numba.njit(cache=True, nogil=True)
def shift_by_row_max(lw, mx):
    """``mx[b] = max(lw[b])`` (NaN if the row has one, as NumPy's ``max``) and, for a finite
    maximum, ``lw[b] -= mx[b]`` while the row is in the cache: NumPy's ``lw.max(axis=1)`` and
    ``lw -= mx[:, None]``, the same floats. A row whose maximum is ``-inf`` (no particle
    compatible with the data) is set to 0; one with NaN or ``+inf`` is left as it is."""
    m, P = lw.shape
    for b in range(m):
        row = np.ascontiguousarray(lw[b])  # a view typed contiguous: the loops are vectorized
        # the maximum in 8 interleaved chains (an exact operation in any order; one chain
        # waits on every comparison), NaN noted apart
        h = np.full(8, -np.inf)
        nan = 0
        P8 = P - P % 8
        for i in range(0, P8, 8):
            for j in range(8):
                v = row[i + j]
                h[j] = v if v > h[j] else h[j]
                nan |= np.int64(v != v)
        for i in range(P8, P):
            v = row[i]
            h[0] = v if v > h[0] else h[0]
            nan |= np.int64(v != v)
        hi = h[0]
        for j in range(1, 8):
            hi = h[j] if h[j] > hi else hi
        if nan:
            mx[b] = np.nan
        elif hi == -np.inf:
            mx[b] = hi
            for i in range(P):
                row[i] = 0.0
        else:
            mx[b] = hi
            if hi != np.inf:
                for i in range(P):
                    row[i] = row[i] - hi


@numba.njit(cache=True, nogil=True)
def weighted_moments(w, x, S, mean, ess):
    """Per row ``b`` of the (unnormalized) weights ``w (m, P)`` and particles ``x (m, P, d)``:
    ``S[b] = sum_i w[b, i]``, the weighted means ``mean[b, j] = sum_i w[b, i] x[b, i, j] / S[b]``
    and ``ess[b] = S[b]^2 / sum_i w[b, i]^2``, in one sequential pass over the particles."""
    m, P = w.shape
    d = x.shape[2]
    if d == 2:  # the common case
        for b in range(m):
            _moments_row2(w, x, b, S, mean, ess)
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
