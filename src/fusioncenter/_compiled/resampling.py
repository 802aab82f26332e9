"""Compiled inner loops of the particle filter :func:`fusioncenter.particle.run_filter` and of
its fusion-centre models (:class:`fusioncenter.censoring.LinearFusionCentre`, the vector
observations' model in :mod:`fusioncenter.censoring.vector`, the nonlinear model's amplitudes
and silent factors in :mod:`fusioncenter.censoring.nonlinear`). The transitions (and the
noise they draw inline) are in :mod:`fusioncenter._transition_kernels`.

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

__all__ = ["amplitudes", "ellipse_reject", "hermite_rows", "hermite_tables",
           "power_table", "received_terms", "sensor_terms", "sum_sensors",
           "systematic_ancestors", "table_shifted", "take_rows", "weighted_moments",
           "resample_rows", "gauss_terms", "table_shifted_add", "gauss_table_add"]

#: Unsigned offsets of a cubic table's coefficients (:func:`_table_row`).
_U1, _U2, _U3, _U4 = np.uint64(1), np.uint64(2), np.uint64(3), np.uint64(4)


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
def resample_rows(w, S, u, todo, src, dst):
    """Systematic resampling fused with the gather: for every row ``b`` with ``todo[b]``,
    ``dst[b, k, :] = src[b, a_k, :]`` with the ancestors ``a_k`` of
    :func:`systematic_ancestors`, computed the same way (the same arithmetic, so the same
    integers) into a scratch row that stays in the cache; its running maximum and the gather are
    one pass. The other rows are copied. ``S[b]`` must be the row's sequential sum, as
    :func:`weighted_moments` computes it."""
    m, P = w.shape
    d = src.shape[2]
    anc = np.empty(P, dtype=np.intp)
    for b in range(m):
        if not todo[b]:
            for k in range(P):
                for j in range(d):
                    dst[b, k, j] = src[b, k, j]
            continue
        for k in range(P):
            anc[k] = 0
        total = S[b]
        ub = u[b]
        c = 0.0
        lo = 0
        for i in range(P - 1):
            c += w[b, i]
            if lo < P:
                anc[lo] = i
            lo = int(math.ceil(c / total * P - ub))
        if lo < P:
            anc[lo] = P - 1
        a = 0
        if d == 2:
            for k in range(P):
                a = max(a, anc[k])
                dst[b, k, 0] = src[b, a, 0]
                dst[b, k, 1] = src[b, a, 1]
        else:
            for k in range(P):
                a = max(a, anc[k])
                for j in range(d):
                    dst[b, k, j] = src[b, a, j]


@numba.njit(cache=True, nogil=True)
def gauss_terms(y, zbar, coef, out, add):
    """The received sensors' Gaussian log-likelihood of a group, per row ``b``: ``e = (y[b, i] -
    zbar[b])^2 * coef[b]`` (subtract, square, multiply, in this order: the NumPy arithmetic of
    ``censoring.fusion``), written to ``out[b, i]`` or, if ``add``, added to it. One pass."""
    m, P = y.shape
    for b in range(m):
        yb = np.ascontiguousarray(y[b])  # a view typed contiguous: the loop is vectorized
        zb = zbar[b]
        c = coef[b]
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
def ellipse_reject(u, b, todo, inv_a2, out):
    """One round of rejection sampling in the ellipse ``sum_j u_j^2 inv_a2[j] < 1``: for
    ``t < todo.size`` the proposal for point ``i = todo[t]`` is ``u[t] + b[i]``; if inside it is
    stored in ``out[i]``, otherwise ``i`` is kept. The kept points are packed at the front of
    ``todo`` (in their order); returns how many. ``u (k, m)`` (standard normal draws; ``k >=
    todo.size``), ``b, out (K, m)``, ``inv_a2 (m,)``; the arithmetic of
    ``censoring.vector_fusion``'s NumPy rounds (the draw plus the mean, then ``u_1^2 inv_1``,
    ``+ u_2^2 inv_2``, ...)."""
    m = b.shape[1]
    kept = 0
    for t in range(todo.shape[0]):
        i = todo[t]
        q = 0.0
        for j in range(m):
            uj = u[t, j] + b[i, j]
            u[t, j] = uj
            if j == 0:
                q = uj * uj * inv_a2[0]
            else:
                q += uj * uj * inv_a2[j]
        if q < 1.0:
            for j in range(m):
                out[i, j] = u[t, j]
        else:
            todo[kept] = i
            kept += 1
    return kept


@numba.njit(cache=True, nogil=True)
def _basis(t):
    """The cubic Hermite weights ``A0, D0, D1`` at ``t`` (``censoring.ellipse``'s arithmetic)."""
    u = 1.0 - t
    D0 = u * u
    A0 = (2.0 * t + 1.0) * D0
    D0 = D0 * t
    D1 = t * t
    D1 = D1 * -u
    return A0, D0, D1


@numba.njit(cache=True, nogil=True)
def hermite_tables(f, f1, f2, f12, o1, o2, h1, h2, G1, G2, x1, x2, out):
    """Bicubic Hermite interpolation, row ``r`` of the points ``x1, x2 (k, P)`` in table ``r``
    of the flattened ``(k, G1, G2)`` tables ``f, f1, f2, f12`` (derivatives already times the
    steps) on the grids ``o + i h`` (``(k,)`` each), into ``out (k, P)``; points outside their
    grid are clamped to it. Operation for operation the NumPy evaluation of
    ``censoring.ellipse``'s per-trial tables."""
    k, P = x1.shape
    for r in range(k):
        inv1 = 1.0 / h1[r]
        inv2 = 1.0 / h2[r]
        for p in range(P):
            t1 = (x1[r, p] - o1[r]) * inv1
            t2 = (x2[r, p] - o2[r]) * inv2
            t1 = min(max(t1, 0.0), G1 - 1.0)
            t2 = min(max(t2, 0.0), G2 - 1.0)
            i = min(np.intp(t1), G1 - 2)
            j = min(np.intp(t2), G2 - 2)
            t1 = t1 - i
            t2 = t2 - j
            ka = (i + r * G1) * G2 + j
            A0, D0, D1 = _basis(t1)
            B0, E0, E1 = _basis(t2)
            kb = ka + G2
            fb = f[kb]
            rr = (f[ka] - fb) * A0 + fb + f1[ka] * D0 + f1[kb] * D1
            gb = f2[kb]
            q = (f2[ka] - gb) * A0 + gb + f12[ka] * D0 + f12[kb] * D1
            v = rr * B0 + q * E0
            ka += 1
            kb += 1
            fb = f[kb]
            rr = (f[ka] - fb) * A0 + fb + f1[ka] * D0 + f1[kb] * D1
            gb = f2[kb]
            q = (f2[ka] - gb) * A0 + gb + f12[ka] * D0 + f12[kb] * D1
            v = v + rr * (1.0 - B0)
            out[r, p] = v + q * E1


@numba.njit(cache=True, nogil=True)
def power_table(coef, G, inv_h, x1, x2, out, far):
    """The bicubic power-basis table of ``censoring.ellipse`` (``coef (16, (G-1)^2)``, grid
    step ``1 / inv_h``) at the points ``x1, x2 >= 0`` (C-contiguous, one shape; flat loop) into
    ``out``: a 2-D Horner scheme in the point's cell, ``far`` set (and ``out`` the value of
    cell 0 at ``t = 0``) where ``max(x1, x2) inv_h >= G - 1``. Operation for operation the
    NumPy evaluation."""
    o = out.reshape(-1)
    fr = far.reshape(-1)
    y1 = x1.reshape(-1)
    y2 = x2.reshape(-1)
    top = G - 1.0
    for n in range(y1.shape[0]):
        t1 = y1[n] * inv_h
        t2 = y2[n] * inv_h
        f = max(t1, t2) >= top
        fr[n] = f
        if f:
            t1 = 0.0
            t2 = 0.0
        i = np.intp(t1)
        j = np.intp(t2)
        t1 = t1 - i
        t2 = t2 - j
        c = i * (G - 1) + j
        v = 0.0
        for p in range(3, -1, -1):
            r = coef[4 * p + 3, c] * t2
            r = r + coef[4 * p + 2, c]
            r = r * t2
            r = r + coef[4 * p + 1, c]
            r = r * t2
            r = r + coef[4 * p, c]
            v = r if p == 3 else v * t1 + r
        o[n] = v


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


@numba.njit(cache=True, nogil=True)
def table_shifted_add(coef, n_int, y, shift, scale, ns, out, far_rows):
    """``out[b, i] += ns[b] f(|y[b, i] - shift[b]| * scale)`` (``f`` the table of
    :func:`table_shifted`, ``+ 0.0`` where ``ns[b] = 0``, no product where ``ns[b] = 1``),
    row by row: the arithmetic, in its order, of :func:`table_shifted`, then zeroing the rows
    without a silent sensor, the product by ``ns`` and the addition. A row with a point beyond
    the table (or on an interval with a non-finite node) is left unchanged and its index is
    stored in ``far_rows``; returns how many such rows (the caller evaluates them exactly)."""
    m, P = y.shape
    deg = coef.shape[1]
    cf = coef.ravel()  # C-contiguous: a view
    val = np.empty(P)
    kk = np.empty(P, dtype=np.uint64)
    sink = np.empty(1)
    n_far = 0
    for b in range(m):
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
def gauss_table_add(coef, n_int, y, shift, scale, ns, out, far_rows, zbar, gcoef, add):
    """:func:`gauss_terms` (``zbar``, ``gcoef``, ``add``) then :func:`table_shifted_add`, row by
    row in one call: per element the same operations in the same order as the two kernels one
    after the other (so the same floats), with a row's values still in the cache for the second
    part. Returns the number of far rows (their ``out`` holds the Gaussian terms only)."""
    m, P = y.shape
    deg = coef.shape[1]
    cf = coef.ravel()  # C-contiguous: a view
    val = np.empty(P)
    kk = np.empty(P, dtype=np.uint64)
    sink = np.empty(1)
    n_far = 0
    for b in range(m):
        yb = np.ascontiguousarray(y[b])  # a view typed contiguous: the loop is vectorized
        zb = zbar[b]
        c = gcoef[b]
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

# ----------------------------------------------------------------------------- nonlinear model
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
