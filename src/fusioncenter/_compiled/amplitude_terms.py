"""The nonlinear model's sensor amplitudes and log-weight terms, compiled: the amplitudes
``h^i(x) = sqrt(power / (1 + alpha d^2))`` of every sensor at every particle
(:func:`amplitudes`), the received sensors' Gaussian terms (:func:`received_terms`,
:func:`sensor_terms`), the silent sensors' factors from their tables (:func:`hermite_rows`) and
the sum over the sensors (:func:`sum_sensors`), for :mod:`fusioncenter.censoring.nonlinear`.

Row by row (a trial's result never depends on the other trials of a block), the NumPy
arithmetic of :mod:`fusioncenter.censoring.nonlinear` operation for operation, in its order,
sums included (``tests/test_kernels.py`` compares each kernel with that code, bit for bit).
"""

from __future__ import annotations

import math

import numba
import numpy as np

__all__ = ["amplitudes", "received_terms", "sensor_terms", "sum_sensors", "hermite_rows"]


@numba.njit(cache=True, nogil=True)
def _amp(px, py, sx, sy, alpha, power):
    """``sqrt(power / (1 + alpha d^2))`` at ``(px, py)`` for a sensor at ``(sx, sy)``: the
    NumPy arithmetic of ``censoring._nonlinear_core.amplitude_from_d2`` (exponent 2), in its
    order."""
    dx = px - sx
    dy = py - sy
    d2 = dx * dx + dy * dy
    if alpha != 1.0:
        d2 = d2 * alpha
    return math.sqrt(power / (d2 + 1.0))


@numba.njit(cache=True, nogil=True)
def amplitudes(x, pos, alpha, power, out):
    """``out[b, i, p] = h^i(x[b, p])`` (sensor ``i`` at ``pos[i]``, positions in the state's
    components 0 and 2, exponent 2) for particles ``x (n, P, d)``; ``out (n, N, P)``."""
    n, P = x.shape[0], x.shape[1]
    N = pos.shape[0]
    for b in range(n):
        for i in range(N):
            sx = pos[i, 0]
            sy = pos[i, 1]
            for p in range(P):
                out[b, i, p] = _amp(x[b, p, 0], x[b, p, 2], sx, sy, alpha, power)


@numba.njit(cache=True, nogil=True)
def _pairwise(t, lo, n):
    """NumPy's pairwise sum of ``t[lo:lo + n]`` (``n <= 128``: one block), in its order."""
    if n < 8:
        res = 0.0
        for i in range(lo, lo + n):
            res += t[i]
        return res
    r0, r1, r2, r3 = t[lo], t[lo + 1], t[lo + 2], t[lo + 3]
    r4, r5, r6, r7 = t[lo + 4], t[lo + 5], t[lo + 6], t[lo + 7]
    i = 8
    while i < n - (n % 8):
        r0 += t[lo + i]
        r1 += t[lo + i + 1]
        r2 += t[lo + i + 2]
        r3 += t[lo + i + 3]
        r4 += t[lo + i + 4]
        r5 += t[lo + i + 5]
        r6 += t[lo + i + 6]
        r7 += t[lo + i + 7]
        i += 8
    res = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while i < n:
        res += t[lo + i]
        i += 1
    return res


@numba.njit(cache=True, nogil=True)
def received_terms(x, pos, alpha, power, sent, z, cr, out):
    """``out[b, p] = sum_{i: sent[b, i]} cr[i] (h^i(x[b, p]) - z[b, i])^2`` (``cr = -1 / (2
    r)``; 0 where none sent): the log weights of the received measurements only, summed as
    ``numpy.add.reduceat`` over the received sensors does (the first term plus the pairwise
    sum of the others; at most 129 received sensors per trial)."""
    n, P = x.shape[0], x.shape[1]
    N = pos.shape[0]
    t = np.empty(N)
    for b in range(n):
        m = 0
        for i in range(N):
            if sent[b, i]:
                m += 1
        for p in range(P):
            if m == 0:
                out[b, p] = 0.0
                continue
            px = x[b, p, 0]
            py = x[b, p, 2]
            q = 0
            for i in range(N):
                if sent[b, i]:
                    e = _amp(px, py, pos[i, 0], pos[i, 1], alpha, power) - z[b, i]
                    e = e * e
                    t[q] = e * cr[i]
                    q += 1
            out[b, p] = t[0] + _pairwise(t, 1, m - 1)


@numba.njit(cache=True, nogil=True)
def sensor_terms(amp, sent, z, cr, hxp, sd, amax):
    """In place on the amplitudes ``amp (n, N, P)``: a received sensor's row becomes ``cr[i]
    (amp - z[b, i])^2``, a silent one's the offset ``|amp - hxp[b, i]| / sd[i]`` (its maximum
    in ``amax[b, i]``), for :func:`hermite_rows` or the exact silent factor."""
    n, N, P = amp.shape
    for b in range(n):
        for i in range(N):
            if sent[b, i]:
                zi = z[b, i]
                c = cr[i]
                for p in range(P):
                    e = amp[b, i, p] - zi
                    e = e * e
                    amp[b, i, p] = e * c
            else:
                h = hxp[b, i]
                s = sd[i]
                m = -np.inf
                for p in range(P):
                    a = abs(amp[b, i, p] - h) / s
                    amp[b, i, p] = a
                    if a > m:
                        m = a
                amax[b, i] = m


@numba.njit(cache=True, nogil=True)
def sum_sensors(amp, out):
    """``out[b, p] = amp[b, 0, p] + amp[b, 1, p] + ...`` in this order: ``amp.sum(axis=1)``
    of a C-contiguous ``(n, N, P)`` array with ``P >= 2`` (NumPy then adds the sensors' rows
    one after another)."""
    n, N, P = amp.shape
    for b in range(n):
        for p in range(P):
            out[b, p] = amp[b, 0, p]
        for i in range(1, N):
            for p in range(P):
                out[b, p] = out[b, p] + amp[b, i, p]


@numba.njit(cache=True, nogil=True)
def hermite_rows(a, rb, ri, off, inv, c0, c1, c2, c3):
    """In place on the rows ``a[rb[k], ri[k], :]``: the piecewise cubic of row ``k``
    (coefficients from ``off[k]``) at ``a * inv``: ``((c3 f + c2) f + c1) f + c0`` on the
    interval ``j = int(a * inv)`` with ``f`` the fractional part (the NumPy arithmetic of
    ``censoring.nonlinear.silent_terms``)."""
    P = a.shape[2]
    for k in range(rb.shape[0]):
        b = rb[k]
        i = ri[k]
        o = off[k]
        for p in range(P):
            sv = a[b, i, p] * inv
            j = np.int64(sv)
            sv = sv - j
            j += o
            v = c3[j] * sv
            v = v + c2[j]
            v = v * sv
            v = v + c1[j]
            v = v * sv
            v = v + c0[j]
            a[b, i, p] = v
