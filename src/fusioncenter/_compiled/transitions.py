"""Compiled transition kernels of the particle filters: the white-noise-acceleration step of
:class:`fusioncenter.censoring.LinearFusionCentre` and the vector model
(:func:`propagate_wna`), the linear-Gaussian transition of
:class:`fusioncenter.particle.LinearGaussianDynamics` (:func:`linear_transition`), and their
twins that draw the process noise inline (:func:`propagate_wna_draw`,
:func:`linear_transition_draw`) with NumPy's own standard normals (:func:`sfc64_normals`: the
SFC64 generator and NumPy's 256-layer ziggurat, whose tables :func:`fusioncenter._ziggurat.tables`
reads and checks).

Split from :mod:`fusioncenter._kernels` (the weights, resampling, tables and the nonlinear
model's terms), with the same rules: one pass per trial, row by row (a trial's result never
depends on the other trials of a block), the NumPy code's arithmetic operation for operation
(``tests/test_kernels.py`` compares each kernel with it, the inline draws bit for bit with
``standard_normal``).
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numba import types
from numba.extending import intrinsic

__all__ = ["propagate_wna", "sfc64_normals", "propagate_wna_draw", "linear_transition",
           "linear_transition_draw", "pcg64_normals", "linear_transition_draw_pcg64"]

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


# ----------------------------------------------------------------------------- inline normals
_U1 = np.uint64(1)
_U3 = np.uint64(3)
_U8 = np.uint64(8)
_U11 = np.uint64(11)
_U24 = np.uint64(24)
_U40 = np.uint64(40)
_M8 = np.uint64(0xFF)
_M52 = np.uint64(0xFFFFFFFFFFFFF)


@numba.njit(cache=True, nogil=True, inline="always")
def _sfc64_next(s):
    """The next 64-bit output of the SFC64 state ``s (4,) uint64`` (NumPy's algorithm)."""
    out = s[0] + s[1] + s[3]
    s[3] = s[3] + _U1
    s[0] = s[1] ^ (s[1] >> _U11)
    s[1] = s[2] + (s[2] << _U3)
    s[2] = ((s[2] << _U24) | (s[2] >> _U40)) + out
    return out


@numba.njit(cache=True, nogil=True, inline="always")
def _sfc64_step(a, b, c, w):
    """:func:`_sfc64_next` on a state held in four variables ``(a, b, c, w)`` (in registers:
    the array's state went through memory at every draw, since the compiler cannot tell it
    from the particles' arrays). Returns ``(output, a, b, c, w)``."""
    out = a + b + w
    return out, b ^ (b >> _U11), c + (c << _U3), ((c << _U24) | (c >> _U40)) + out, w + _U1


@numba.njit(cache=True, nogil=True, inline="always")
def _sfc64_double(s):
    """A uniform in ``[0, 1)`` from the top 53 bits (NumPy's ``next_double``)."""
    return np.float64(_sfc64_next(s) >> _U11) * (1.0 / 9007199254740992.0)


@numba.njit(cache=True, nogil=True)
def _normal_rare(s, idx, rabs, x, fi, r, inv_r):
    """The ziggurat's rare branches (about 1 % of the draws), after the layer test failed for
    the 64-bit output that gave ``idx``, ``rabs`` and ``x``: the tail (layer 0) or the wedge
    test. Returns ``(accepted, value)``; not accepted: the caller draws again."""
    if idx == 0:
        while True:
            xx = -inv_r * math.log1p(-_sfc64_double(s))
            yy = -math.log1p(-_sfc64_double(s))
            if yy + yy > xx * xx:
                return True, (-(r + xx) if (rabs >> _U8) & _U1 else r + xx)
    if (fi[idx - 1] - fi[idx]) * _sfc64_double(s) + fi[idx] < math.exp(-0.5 * x * x):
        return True, x
    return False, 0.0


@numba.njit(cache=True, nogil=True)
def sfc64_normals(s, ki, wi, fi, r, inv_r, out):
    """Fill ``out`` (flat order) with standard normals from the SFC64 state ``s (4,) uint64``:
    NumPy's 256-layer ziggurat with its tables ``ki, wi, fi`` and tail constants
    (:func:`fusioncenter._ziggurat.tables`), so NumPy's ``standard_normal`` numbers. (The
    common branch is written out in each kernel that draws: calling a compiled function with
    the table arrays for every draw costs more than the draw.)"""
    o = out.reshape(-1)
    for n in range(o.shape[0]):
        while True:
            u = _sfc64_next(s)
            idx = np.intp(u & _M8)
            u = u >> _U8
            rabs = (u >> _U1) & _M52
            x = np.float64(rabs) * wi[idx]
            if u & _U1:
                x = -x
            if rabs < ki[idx]:
                break
            ok, x = _normal_rare(s, idx, rabs, x, fi, r, inv_r)
            if ok:
                break
        o[n] = x


@numba.njit(cache=True, nogil=True)
def propagate_wna_draw(x, dt, L, s, ki, wi, fi, r, inv_r):
    """:func:`propagate_wna` with the normals ``g[b, i, j]`` drawn inline (as
    :func:`sfc64_normals`) from the SFC64 state ``s`` in the order ``standard_normal(out=g)``
    fills ``g (m, P, k)`` (row-major): the same numbers, the same arithmetic, without the array
    of normals."""
    m, P = x.shape[0], x.shape[1]
    k = L.shape[1]
    s0, s1, s2, s3 = s[0], s[1], s[2], s[3]  # the state in registers (_sfc64_step)
    # The draw is written out in both paths, as in every kernel that draws (sfc64_normals):
    # as a helper returning the state, numba's code took 44 ns a particle, not 3.
    if k == 1 and x.strides[1] == 8 and P > 1:  # stored by component: rows of a component
        l0, l1 = L[0, 0], L[1, 0]
        for b in range(m):
            pb = np.ascontiguousarray(x[b, :, 0])  # views (the rows are contiguous), typed so
            vb = np.ascontiguousarray(x[b, :, 1])
            for i in range(P):
                p = pb[i]
                v = vb[i]
                p = p + v * dt
                while True:
                    u, s0, s1, s2, s3 = _sfc64_step(s0, s1, s2, s3)
                    idx = np.intp(u & _M8)
                    u = u >> _U8
                    rabs = (u >> _U1) & _M52
                    gj = np.float64(rabs) * wi[idx]
                    if u & _U1:
                        gj = -gj
                    if rabs < ki[idx]:
                        break
                    s[0], s[1], s[2], s[3] = s0, s1, s2, s3
                    ok, gj = _normal_rare(s, idx, rabs, gj, fi, r, inv_r)
                    s0, s1, s2, s3 = s[0], s[1], s[2], s[3]
                    if ok:
                        break
                pb[i] = p + gj * l0
                vb[i] = v + gj * l1
        s[0], s[1], s[2], s[3] = s0, s1, s2, s3
        return
    for b in range(m):
        for i in range(P):
            p = x[b, i, 0]
            v = x[b, i, 1]
            p = p + v * dt
            for j in range(k):
                while True:
                    u, s0, s1, s2, s3 = _sfc64_step(s0, s1, s2, s3)
                    idx = np.intp(u & _M8)
                    u = u >> _U8
                    rabs = (u >> _U1) & _M52
                    gj = np.float64(rabs) * wi[idx]
                    if u & _U1:
                        gj = -gj
                    if rabs < ki[idx]:
                        break
                    s[0], s[1], s[2], s[3] = s0, s1, s2, s3
                    ok, gj = _normal_rare(s, idx, rabs, gj, fi, r, inv_r)
                    s0, s1, s2, s3 = s[0], s[1], s[2], s[3]
                    if ok:
                        break
                p = p + gj * L[0, j]
                v = v + gj * L[1, j]
            x[b, i, 0] = p
            x[b, i, 1] = v
    s[0], s[1], s[2], s[3] = s0, s1, s2, s3


@intrinsic
def _fma(typingctx, a, b, c):
    """``a b + c`` rounded once (the fused multiply-add instruction)."""
    sig = types.float64(types.float64, types.float64, types.float64)

    def codegen(context, builder, signature, args):
        return builder.fma(*args)

    return sig, codegen


@numba.njit(cache=True, nogil=True)
def _row_4_2(x0, x1, x2, x3, g0, g1, F, L, j):
    acc = _fma(x3, F[j, 3], _fma(x2, F[j, 2], _fma(x1, F[j, 1], x0 * F[j, 0])))
    return acc + _fma(g1, L[j, 1], g0 * L[j, 0])


@numba.njit(cache=True, nogil=True)
def _transition_4_2(x, F, g, L, out):
    """:func:`linear_transition` written out for ``d = 4``, ``k = 2`` (the same arithmetic)."""
    n, P = x.shape[0], x.shape[1]
    for b in range(n):
        for p in range(P):
            x0, x1, x2, x3 = x[b, p, 0], x[b, p, 1], x[b, p, 2], x[b, p, 3]
            g0, g1 = g[b, p, 0], g[b, p, 1]
            out[b, p, 0] = _row_4_2(x0, x1, x2, x3, g0, g1, F, L, 0)
            out[b, p, 1] = _row_4_2(x0, x1, x2, x3, g0, g1, F, L, 1)
            out[b, p, 2] = _row_4_2(x0, x1, x2, x3, g0, g1, F, L, 2)
            out[b, p, 3] = _row_4_2(x0, x1, x2, x3, g0, g1, F, L, 3)


@numba.njit(cache=True, nogil=True)
def linear_transition(x, F, g, L, out):
    """``out = x @ F.T + g @ L.T`` for C-contiguous ``x (n, P, d)`` and ``g (n, P, k)``, with
    the arithmetic of the BLAS ``dgemm`` that NumPy's ``matmul`` calls for each trial's
    contiguous ``(P, d)`` block (OpenBLAS on x86-64 with FMA: each element is the chain
    ``x_0 F_j0``, then ``fma(x_m, F_jm, acc)`` for ``m = 1..d-1``), the two products added
    last. ``tests/test_kernels.py`` checks it bit for bit against ``matmul`` on dense random
    matrices, so a machine whose BLAS sums otherwise fails there."""
    n, P, d = x.shape
    k = g.shape[2]
    if d == 4 and k == 2:  # the nonlinear model's (white-noise acceleration in x and y)
        _transition_4_2(x, F, g, L, out)
        return
    for b in range(n):
        for p in range(P):
            for j in range(d):
                acc = x[b, p, 0] * F[j, 0]
                for m in range(1, d):
                    acc = _fma(x[b, p, m], F[j, m], acc)
                if k:
                    noise = g[b, p, 0] * L[j, 0]
                    for m in range(1, k):
                        noise = _fma(g[b, p, m], L[j, m], noise)
                    acc = acc + noise
                out[b, p, j] = acc


@numba.njit(cache=True, nogil=True)
def linear_transition_draw(x, F, L, s, ki, wi, fi, r, inv_r, out):
    """:func:`linear_transition` with the normals ``g[b, p, :]`` drawn inline (as
    :func:`sfc64_normals`) from the SFC64 state ``s``, particle after particle, in the order
    ``standard_normal`` fills ``g (n, P, k)``: the same numbers and the same arithmetic
    (including the written-out ``d = 4``, ``k = 2`` case), without the array of normals."""
    n, P, d = x.shape
    k = L.shape[1]
    g = np.empty(max(k, 1))
    for b in range(n):
        for p in range(P):
            for m in range(k):
                while True:
                    u = _sfc64_next(s)
                    idx = np.intp(u & _M8)
                    u = u >> _U8
                    rabs = (u >> _U1) & _M52
                    gm = np.float64(rabs) * wi[idx]
                    if u & _U1:
                        gm = -gm
                    if rabs < ki[idx]:
                        break
                    ok, gm = _normal_rare(s, idx, rabs, gm, fi, r, inv_r)
                    if ok:
                        break
                g[m] = gm
            if d == 4 and k == 2:
                x0, x1, x2, x3 = x[b, p, 0], x[b, p, 1], x[b, p, 2], x[b, p, 3]
                g0, g1 = g[0], g[1]
                out[b, p, 0] = _row_4_2(x0, x1, x2, x3, g0, g1, F, L, 0)
                out[b, p, 1] = _row_4_2(x0, x1, x2, x3, g0, g1, F, L, 1)
                out[b, p, 2] = _row_4_2(x0, x1, x2, x3, g0, g1, F, L, 2)
                out[b, p, 3] = _row_4_2(x0, x1, x2, x3, g0, g1, F, L, 3)
                continue
            for j in range(d):
                acc = x[b, p, 0] * F[j, 0]
                for q in range(1, d):
                    acc = _fma(x[b, p, q], F[j, q], acc)
                if k:
                    noise = g[0] * L[j, 0]
                    for q in range(1, k):
                        noise = _fma(g[q], L[j, q], noise)
                    acc = acc + noise
                out[b, p, j] = acc


# ----------------------------------------------------------------------------- PCG64
#: NumPy's PCG64 multiplier (``PCG_DEFAULT_MULTIPLIER_128``), high and low 64 bits.
_PCG_MHI = np.uint64(0x2360ED051FC65DA4)
_PCG_MLO = np.uint64(0x4385DF649FCCF645)
_U58 = np.uint64(58)
_U63 = np.uint64(63)
_U64 = np.uint64(64)


@intrinsic
def _umulh(typingctx, a, b):
    """The high 64 bits of the 128-bit product of two unsigned 64-bit integers."""
    sig = types.uint64(types.uint64, types.uint64)

    def codegen(context, builder, signature, args):
        from llvmlite import ir

        i128 = ir.IntType(128)
        p = builder.mul(builder.zext(args[0], i128), builder.zext(args[1], i128))
        return builder.trunc(builder.lshr(p, ir.Constant(i128, 64)), ir.IntType(64))

    return sig, codegen


@numba.njit(cache=True, nogil=True, inline="always")
def _pcg64_next(s):
    """The next 64-bit output of NumPy's PCG64 (``pcg_setseq_128_xsl_rr_64``): the 128-bit
    state ``(s[0], s[1])`` (high, low) times the multiplier plus the increment ``(s[2], s[3])``,
    then the XOR of its halves rotated right by its top 6 bits."""
    hi, lo = s[0], s[1]
    nhi = _umulh(lo, _PCG_MLO) + hi * _PCG_MLO + lo * _PCG_MHI
    nlo = lo * _PCG_MLO
    lo2 = nlo + s[3]
    hi2 = nhi + s[2] + np.uint64(lo2 < nlo)  # the carry, without a branch
    s[0], s[1] = hi2, lo2
    v = hi2 ^ lo2
    rot = hi2 >> _U58
    return (v >> rot) | (v << ((_U64 - rot) & _U63))


@numba.njit(cache=True, nogil=True, inline="always")
def _pcg64_double(s):
    """A uniform in ``[0, 1)`` from the top 53 bits (NumPy's ``next_double``)."""
    return np.float64(_pcg64_next(s) >> _U11) * (1.0 / 9007199254740992.0)


@numba.njit(cache=True, nogil=True)
def _normal_rare_pcg64(s, idx, rabs, x, fi, r, inv_r):
    """:func:`_normal_rare` for a PCG64 state."""
    if idx == 0:
        while True:
            xx = -inv_r * math.log1p(-_pcg64_double(s))
            yy = -math.log1p(-_pcg64_double(s))
            if yy + yy > xx * xx:
                return True, (-(r + xx) if (rabs >> _U8) & _U1 else r + xx)
    if (fi[idx - 1] - fi[idx]) * _pcg64_double(s) + fi[idx] < math.exp(-0.5 * x * x):
        return True, x
    return False, 0.0


@numba.njit(cache=True, nogil=True)
def pcg64_normals(s, ki, wi, fi, r, inv_r, out):
    """:func:`sfc64_normals` for NumPy's PCG64: ``s (4,) uint64`` is the state's high and low
    halves, then the increment's (:func:`fusioncenter._ziggurat.draw_state`)."""
    o = out.reshape(-1)
    for n in range(o.shape[0]):
        while True:  # written out: a helper function here costs six times the draw
            u = _pcg64_next(s)
            idx = np.intp(u & _M8)
            u = u >> _U8
            rabs = (u >> _U1) & _M52
            x = np.float64(rabs) * wi[idx]
            if u & _U1:
                x = -x
            if rabs < ki[idx]:
                break
            ok, x = _normal_rare_pcg64(s, idx, rabs, x, fi, r, inv_r)
            if ok:
                break
        o[n] = x


@numba.njit(cache=True, nogil=True)
def linear_transition_draw_pcg64(x, F, L, s, ki, wi, fi, r, inv_r, out):
    """:func:`linear_transition_draw` with the normals from a PCG64 state (NumPy's default
    generator): the same numbers as ``standard_normal`` on that generator, the same
    arithmetic as :func:`linear_transition`."""
    n, P, d = x.shape
    k = L.shape[1]
    g = np.empty(max(k, 1))
    for b in range(n):
        for p in range(P):
            for m in range(k):
                while True:
                    u = _pcg64_next(s)
                    idx = np.intp(u & _M8)
                    u = u >> _U8
                    rabs = (u >> _U1) & _M52
                    gm = np.float64(rabs) * wi[idx]
                    if u & _U1:
                        gm = -gm
                    if rabs < ki[idx]:
                        break
                    ok, gm = _normal_rare_pcg64(s, idx, rabs, gm, fi, r, inv_r)
                    if ok:
                        break
                g[m] = gm
            if d == 4 and k == 2:
                x0, x1, x2, x3 = x[b, p, 0], x[b, p, 1], x[b, p, 2], x[b, p, 3]
                g0, g1 = g[0], g[1]
                out[b, p, 0] = _row_4_2(x0, x1, x2, x3, g0, g1, F, L, 0)
                out[b, p, 1] = _row_4_2(x0, x1, x2, x3, g0, g1, F, L, 1)
                out[b, p, 2] = _row_4_2(x0, x1, x2, x3, g0, g1, F, L, 2)
                out[b, p, 3] = _row_4_2(x0, x1, x2, x3, g0, g1, F, L, 3)
                continue
            for j in range(d):
                acc = x[b, p, 0] * F[j, 0]
                for q in range(1, d):
                    acc = _fma(x[b, p, q], F[j, q], acc)
                if k:
                    noise = g[0] * L[j, 0]
                    for q in range(1, k):
                        noise = _fma(g[q], L[j, q], noise)
                    acc = acc + noise
                out[b, p, j] = acc
