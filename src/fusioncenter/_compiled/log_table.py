"""The scalar fusion centre's log-weight terms, compiled: the received sensors' Gaussian
log-likelihood (:func:`gauss_terms`) and the silent sensors' factor read from an interpolation
table (:class:`fusioncenter.censoring.tables.LogTable`: :func:`table_shifted`, and
:func:`table_shifted_add` adding it to the log weights), and the two fused row by row
(:func:`gauss_table_add`), for :class:`fusioncenter.censoring.LinearFusionCentre`.

Evaluating an interpolation table takes NumPy a dozen passes over the ``(trials, particles)``
arrays; these kernels take one or two per trial. Row by row (a trial's result never depends on
the other trials of a block), the NumPy code's arithmetic operation for operation, in its order
(``tests/test_kernels.py`` compares each kernel with it, and the fused kernel with the two
kernels one after the other, bit for bit). :func:`table_shifted_add` and
:func:`gauss_table_add` are one loop (:func:`_table_add_rows`) with or without the Gaussian
part.
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["gauss_terms", "table_shifted", "table_shifted_add", "gauss_table_add"]

#: Unsigned offsets of a cubic table's coefficients (:func:`_table_row`).
_U1, _U2, _U3, _U4 = np.uint64(1), np.uint64(2), np.uint64(3), np.uint64(4)


@numba.njit(cache=True, nogil=True, inline="always")
def _gauss_row(y, b, zb, c, out, add):
    """Row ``b`` of :func:`gauss_terms`: ``e = (y[b, i] - zb)^2 * c``, written to ``out[b, i]``
    or, if ``add``, added to it."""
    P = y.shape[1]
    yb = np.ascontiguousarray(y[b])  # a view typed contiguous: the loop is vectorized
    if add:
        for i in range(P):
            e = yb[i] - zb
            e = e * e
            out[b, i] = out[b, i] + e * c
    else:
        for i in range(P):
            e = yb[i] - zb
            e = e * e
            out[b, i] = e * c


@numba.njit(cache=True, nogil=True)
def gauss_terms(y, zbar, coef, out, add):
    """The received sensors' Gaussian log-likelihood of a group, per row ``b``: ``e = (y[b, i] -
    zbar[b])^2 * coef[b]`` (subtract, square, multiply, in this order: the NumPy arithmetic of
    ``censoring.fusion``), written to ``out[b, i]`` or, if ``add``, added to it. One pass."""
    for b in range(y.shape[0]):
        _gauss_row(y, b, zbar[b], coef[b], out, add)


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


@numba.njit(cache=True, nogil=True, inline="always")
def _add_silent(out, b, val, nsb):
    """Row ``b`` of ``out`` plus ``nsb`` times the silent factor ``val`` (one silent sensor:
    a plain sum, so the floats are those of adding ``val`` once)."""
    P = out.shape[1]
    if nsb == 1:
        for i in range(P):
            out[b, i] = out[b, i] + val[i]
    else:
        c = np.float64(nsb)
        for i in range(P):
            out[b, i] = out[b, i] + val[i] * c


@numba.njit(cache=True, nogil=True, inline="always")
def _touch(cf, deg, kk, P, sink):
    """Read the table ``cf`` in order from its start to the last interval ``kk[:P]`` names,
    one load per 64-byte line (their sum goes to ``sink[0]``, so that the loads stay). The
    table of a step (12288 cubic intervals, 393 kB) is not in the core's caches when the step
    begins; read in order, the hardware prefetcher streams its lines in, where the gathers of
    Horner's pass would have missed one line after another. No value computed changes.
    CFwMD's benchmark (benchmarks/bench_particle_floor.py): 13.1 -> 12.6 ns per
    particle-step."""
    jmax = np.uint64(0)
    for i in range(P):
        jmax = max(jmax, kk[i])
    acc = 0.0
    for q in range(0, (int(jmax) + 1) * deg, 8):
        acc += cf[q]
    sink[0] = acc


@numba.njit(cache=True, nogil=True)
def _table_row(cf, deg, n_int, y, b, sh, scale, val, kk, sink):
    """``val[i]`` = the even table (coefficients ``cf``, flattened rows of ``deg``) at ``|y[b, i]
    - sh| * scale``, for every ``i``; true if a point is beyond the table (then the row's values
    are not computed: the caller drops them) or on an interval with a non-finite node.

    Two passes over the row (``kk``: scratch of ``P`` unsigned integers): the first, without
    a memory access that depends on the data, is vectorized by the compiler (``|y - sh| *
    scale``, its interval ``floor`` and the offset in it); the second gathers each interval's
    coefficients and runs Horner's scheme (after :func:`_touch` if ``sink`` has an element).
    The arithmetic and its order are :func:`table_shifted`'s (``floor(t)`` equals ``int(t)``
    for ``0 <= t < n_int``), so are the floats; the unsigned index spares the negative-index
    wraparound of every coefficient load."""
    P = y.shape[1]
    yb = np.ascontiguousarray(y[b])  # a view typed contiguous (a particle component's rows
    outside = 0                      # are): the first pass is vectorized
    for i in range(P):
        t = abs(yb[i] - sh) * scale
        inside = t < n_int
        t = t if inside else 0.0
        fj = np.floor(t)
        val[i] = t - fj
        kk[i] = np.uint64(fj)
        outside |= np.int64(not inside)
    if outside:
        return True
    if sink.size:
        _touch(cf, deg, kk, P, sink)
    bad = 0
    udeg = np.uint64(deg)
    if deg == 4:  # the cubic tables, written out
        for i in range(P):
            t = val[i]
            k = kk[i] * _U4
            acc = cf[k] * t + cf[k + _U1]
            acc = acc * t + cf[k + _U2]
            acc = acc * t + cf[k + _U3]
            val[i] = acc
            bad |= np.int64(acc != acc)
    else:
        for i in range(P):
            t = val[i]
            k = kk[i] * udeg
            acc = cf[k] * t + cf[k + _U1]
            for q in range(2, deg):
                acc = acc * t + cf[k + np.uint64(q)]
            val[i] = acc
            bad |= np.int64(acc != acc)
    return bad != 0


@numba.njit(cache=True, nogil=True, inline="always")
def _table_add_rows(coef, n_int, y, shift, scale, ns, out, far_rows, zbar, gcoef, add, gauss):
    """The loop of :func:`table_shifted_add` and, if ``gauss``, of :func:`gauss_table_add`
    (each row's Gaussian terms first; ``zbar``, ``gcoef`` and ``add`` are read only then)."""
    m, P = y.shape
    deg = coef.shape[1]
    cf = coef.ravel()  # C-contiguous: a view
    val = np.empty(P)
    kk = np.empty(P, dtype=np.uint64)
    sink = np.empty(1)
    n_far = 0
    for b in range(m):
        if gauss:
            _gauss_row(y, b, zbar[b], gcoef[b], out, add)
        nsb = ns[b]
        if nsb == 0:
            for i in range(P):
                out[b, i] = out[b, i] + 0.0
            continue
        if _table_row(cf, deg, n_int, y, b, shift[b], scale, val, kk, sink):
            far_rows[n_far] = b
            n_far += 1
            continue
        sink = sink[:0]  # the first row with a silent sensor has read the table in
        _add_silent(out, b, val, nsb)
    return n_far


@numba.njit(cache=True, nogil=True)
def table_shifted_add(coef, n_int, y, shift, scale, ns, out, far_rows):
    """``out[b, i] += ns[b] f(|y[b, i] - shift[b]| * scale)`` (``f`` the table of
    :func:`table_shifted`, ``+ 0.0`` where ``ns[b] = 0``, no product where ``ns[b] = 1``),
    row by row: the arithmetic, in its order, of :func:`table_shifted`, then zeroing the rows
    without a silent sensor, the product by ``ns`` and the addition. A row with a point beyond
    the table (or on an interval with a non-finite node) is left unchanged and its index is
    stored in ``far_rows``; returns how many such rows (the caller evaluates them exactly)."""
    return _table_add_rows(coef, n_int, y, shift, scale, ns, out, far_rows, shift, shift,
                           False, False)


@numba.njit(cache=True, nogil=True)
def gauss_table_add(coef, n_int, y, shift, scale, ns, out, far_rows, zbar, gcoef, add):
    """:func:`gauss_terms` (``zbar``, ``gcoef``, ``add``) then :func:`table_shifted_add`, row by
    row in one call: per element the same operations in the same order as the two kernels one
    after the other (so the same floats), with a row's values still in the cache for the second
    part. Returns the number of far rows (their ``out`` holds the Gaussian terms only)."""
    return _table_add_rows(coef, n_int, y, shift, scale, ns, out, far_rows, zbar, gcoef, add,
                           True)
