"""The particles' random transitions, compiled, with the process noise NumPy would draw: the
white-noise-acceleration step of :class:`fusioncenter.censoring.LinearFusionCentre` and the
vector model (:func:`propagate_wna`), the linear-Gaussian transition of
:class:`fusioncenter.particle.LinearGaussianDynamics` (:func:`linear_transition`), their twins
that draw the noise inline (:func:`propagate_wna_draw`, :data:`linear_transition_draw`,
:data:`linear_transition_draw_pcg64`), and the inline draws alone (:data:`sfc64_normals`,
:data:`pcg64_normals`).

The draws are NumPy's standard normals bit for bit: the bit generators SFC64 and PCG64 and
NumPy's 256-layer ziggurat, with NumPy's tables ``ki, wi, fi`` and tail constants ``r, inv_r``
(:func:`fusioncenter._compiled.ziggurat.tables`). A generator's state is four unsigned 64-bit
words: SFC64's own four, or PCG64's 128-bit state (high, low) then its increment (high, low)
(the layout of :func:`fusioncenter._compiled.ziggurat.draw_state`). A kernel keeps the state in
four local variables while it draws (in registers: an array's state goes through memory at
every draw, as the compiler cannot tell it from the particles' arrays). One draw is written
once for both generators: the layer test of one output, inlined (:func:`_normal_try`), and,
for the 1 % of draws it rejects, the rare branches in a call (:func:`_normal_slow`); each
kernel that draws is made for one generator (its ``pcg`` flag a constant) by a small factory
where it exists for both. (The caller keeps the test: a helper returning the state from either
branch made numba's code of the common draw six times slower.) The inline helpers live in this
module with every kernel that inlines them, since numba's cache of a kernel does not notice a
change in another file.

One pass per trial, row by row (a trial's result never depends on the other trials of a
block), the NumPy code's arithmetic operation for operation (``tests/test_kernels.py`` compares
each kernel with it, the inline draws bit for bit with ``standard_normal``).
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numba import types
from numba.extending import intrinsic

__all__ = ["propagate_wna", "propagate_wna_draw", "linear_transition", "linear_transition_draw",
           "linear_transition_draw_pcg64", "sfc64_normals", "pcg64_normals"]

#: The shift counts of the generators and of the ziggurat, unsigned.
_U1, _U3, _U8, _U11, _U24, _U40, _U58, _U63, _U64 = map(np.uint64, (1, 3, 8, 11, 24, 40, 58, 63,
                                                                    64))
#: The ziggurat's masks: the layer (8 bits) and the abscissa (52 bits) of an output.
_M8, _M52 = np.uint64(0xFF), np.uint64(0xFFFFFFFFFFFFF)
#: NumPy's PCG64 multiplier (``PCG_DEFAULT_MULTIPLIER_128``), high and low 64 bits.
_PCG_MHI = np.uint64(0x2360ED051FC65DA4)
_PCG_MLO = np.uint64(0x4385DF649FCCF645)


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
def _sfc64_step(a, b, c, w):
    """The next 64-bit output of SFC64 (NumPy's algorithm) from the state ``(a, b, c, w)``.
    Returns ``(output, a, b, c, w)``, the state advanced."""
    out = a + b + w
    return out, b ^ (b >> _U11), c + (c << _U3), ((c << _U24) | (c >> _U40)) + out, w + _U1


@numba.njit(cache=True, nogil=True, inline="always")
def _pcg64_step(hi, lo, ihi, ilo):
    """The next 64-bit output of NumPy's PCG64 (``pcg_setseq_128_xsl_rr_64``): the 128-bit
    state ``(hi, lo)`` times the multiplier plus the increment ``(ihi, ilo)``, then the XOR of
    its halves rotated right by its top 6 bits. Returns ``(output, hi, lo, ihi, ilo)``, the
    state advanced."""
    nhi = _umulh(lo, _PCG_MLO) + hi * _PCG_MLO + lo * _PCG_MHI
    nlo = lo * _PCG_MLO
    lo2 = nlo + ilo
    hi2 = nhi + ihi + np.uint64(lo2 < nlo)  # the carry, without a branch
    v = hi2 ^ lo2
    rot = hi2 >> _U58
    return (v >> rot) | (v << ((_U64 - rot) & _U63)), hi2, lo2, ihi, ilo


@numba.njit(cache=True, nogil=True, inline="always")
def _step(pcg, a, b, c, w):
    """:func:`_pcg64_step` if ``pcg``, else :func:`_sfc64_step`."""
    if pcg:
        out, a, b, c, w = _pcg64_step(a, b, c, w)
    else:
        out, a, b, c, w = _sfc64_step(a, b, c, w)
    return out, a, b, c, w


@numba.njit(cache=True, nogil=True, inline="always")
def _double(pcg, s):
    """A uniform in ``[0, 1)`` from the top 53 bits of the next output of the state array
    ``s (4,) uint64`` (NumPy's ``next_double``), ``s`` advanced."""
    out, s[0], s[1], s[2], s[3] = _step(pcg, s[0], s[1], s[2], s[3])
    return np.float64(out >> _U11) * (1.0 / 9007199254740992.0)


@numba.njit(cache=True, nogil=True)
def _normal_rare(pcg, s, idx, rabs, x, fi, r, inv_r):
    """The ziggurat's rare branches (about 1 % of the draws), after the layer test failed for
    the 64-bit output that gave ``idx``, ``rabs`` and ``x``: the tail (layer 0) or the wedge
    test, drawing from the state array ``s``. Returns ``(accepted, value)``; not accepted: the
    caller draws again."""
    if idx == 0:
        while True:
            xx = -inv_r * math.log1p(-_double(pcg, s))
            yy = -math.log1p(-_double(pcg, s))
            if yy + yy > xx * xx:
                return True, (-(r + xx) if (rabs >> _U8) & _U1 else r + xx)
    if (fi[idx - 1] - fi[idx]) * _double(pcg, s) + fi[idx] < math.exp(-0.5 * x * x):
        return True, x
    return False, 0.0


@numba.njit(cache=True, nogil=True, inline="always")
def _normal_try(pcg, a, b, c, w, ki, wi):
    """The ziggurat's layer test on the next 64-bit output of the state ``(a, b, c, w)``
    (PCG64 if ``pcg``, else SFC64): 8 bits pick the layer ``idx``, one the sign, 52 the
    abscissa ``rabs``. Returns ``(accepted, value, idx, rabs, a, b, c, w)``, the state
    advanced; not accepted: :func:`_normal_slow` goes on from there."""
    u, a, b, c, w = _step(pcg, a, b, c, w)
    idx = np.intp(u & _M8)
    u = u >> _U8
    rabs = (u >> _U1) & _M52
    x = np.float64(rabs) * wi[idx]
    if u & _U1:
        x = -x
    return rabs < ki[idx], x, idx, rabs, a, b, c, w


@numba.njit(cache=True, nogil=True)
def _normal_slow(pcg, a, b, c, w, s, idx, rabs, x, ki, wi, fi, r, inv_r):
    """The draw after a failed layer test (``idx``, ``rabs``, ``x``): the rare branches
    through the state array ``s``, then new tries until one is accepted. Returns ``(value, a,
    b, c, w)``, the state advanced (``s`` too holds a state: the caller writes its own back
    at the end)."""
    while True:
        s[0], s[1], s[2], s[3] = a, b, c, w
        ok, x = _normal_rare(pcg, s, idx, rabs, x, fi, r, inv_r)
        a, b, c, w = s[0], s[1], s[2], s[3]
        if ok:
            return x, a, b, c, w
        ok, x, idx, rabs, a, b, c, w = _normal_try(pcg, a, b, c, w, ki, wi)
        if ok:
            return x, a, b, c, w


def _normals_kernel(pcg: bool):
    """The compiled fill kernel ``(s, ki, wi, fi, r, inv_r, out)`` of one generator (PCG64 if
    ``pcg``, else SFC64): ``out`` (flat order) filled with standard normals drawn from the
    state ``s (4,) uint64``, which is left advanced; ``standard_normal``'s numbers."""

    @numba.njit(cache=True, nogil=True)
    def fill(s, ki, wi, fi, r, inv_r, out):
        o = out.reshape(-1)
        a, b, c, w = s[0], s[1], s[2], s[3]
        for n in range(o.shape[0]):
            ok, x, idx, rabs, a, b, c, w = _normal_try(pcg, a, b, c, w, ki, wi)
            if not ok:
                x, a, b, c, w = _normal_slow(pcg, a, b, c, w, s, idx, rabs, x, ki, wi, fi, r,
                                             inv_r)
            o[n] = x
        s[0], s[1], s[2], s[3] = a, b, c, w

    return fill


#: ``(s, ki, wi, fi, r, inv_r, out)``: ``out`` filled with NumPy's standard normals from the
#: SFC64 state ``s`` (flat order), ``s`` left advanced as NumPy leaves its generator.
sfc64_normals = _normals_kernel(False)
#: :data:`sfc64_normals` for NumPy's PCG64.
pcg64_normals = _normals_kernel(True)


@numba.njit(cache=True, nogil=True, inline="always")
def _wna_particle(x, b, i, dt, g, L):
    """Particle ``x[b, i] = (p, v)`` of :func:`propagate_wna`, in place, with its normals
    ``g (k,)``."""
    p = x[b, i, 0]
    v = x[b, i, 1]
    p = p + v * dt
    for j in range(g.shape[0]):
        gj = g[j]
        p = p + gj * L[0, j]
        v = v + gj * L[1, j]
    x[b, i, 0] = p
    x[b, i, 1] = v


@numba.njit(cache=True, nogil=True)
def propagate_wna(x, dt, g, L):
    """The white-noise-acceleration transition in place: for every particle ``x[b, i] = (p, v)``,
    ``p <- p + dt v``, then for each noise column ``j``: ``p <- p + g[b, i, j] L[0, j]`` and
    ``v <- v + g[b, i, j] L[1, j]`` (``L L^T = Q``), in this order (the NumPy arithmetic of
    ``x F^T + g L^T`` written out for ``F = [[1, dt], [0, 1]]``)."""
    m, P = x.shape[0], x.shape[1]
    for b in range(m):
        for i in range(P):
            _wna_particle(x, b, i, dt, g[b, i], L)


@numba.njit(cache=True, nogil=True)
def propagate_wna_draw(x, dt, L, s, ki, wi, fi, r, inv_r):
    """:func:`propagate_wna` with the normals ``g[b, i, j]`` drawn inline from the SFC64
    state ``s`` in the order ``standard_normal(out=g)`` fills ``g (m, P, k)`` (row-major): the
    same numbers, the same arithmetic, without the array of normals."""
    m, P = x.shape[0], x.shape[1]
    k = L.shape[1]
    s0, s1, s2, s3 = s[0], s[1], s[2], s[3]  # the state in registers
    if k == 1 and x.strides[1] == 8 and P > 1:  # stored by component: rows of a component
        l0, l1 = L[0, 0], L[1, 0]
        for b in range(m):
            pb = np.ascontiguousarray(x[b, :, 0])  # views (the rows are contiguous), typed so
            vb = np.ascontiguousarray(x[b, :, 1])
            for i in range(P):
                p = pb[i]
                v = vb[i]
                p = p + v * dt
                ok, gj, idx, rabs, s0, s1, s2, s3 = _normal_try(False, s0, s1, s2, s3, ki, wi)
                if not ok:
                    gj, s0, s1, s2, s3 = _normal_slow(False, s0, s1, s2, s3, s, idx, rabs, gj,
                                                      ki, wi, fi, r, inv_r)
                pb[i] = p + gj * l0
                vb[i] = v + gj * l1
        s[0], s[1], s[2], s[3] = s0, s1, s2, s3
        return
    g = np.empty(k)
    for b in range(m):
        for i in range(P):
            for j in range(k):
                ok, gj, idx, rabs, s0, s1, s2, s3 = _normal_try(False, s0, s1, s2, s3, ki, wi)
                if not ok:
                    gj, s0, s1, s2, s3 = _normal_slow(False, s0, s1, s2, s3, s, idx, rabs, gj,
                                                      ki, wi, fi, r, inv_r)
                g[j] = gj
            _wna_particle(x, b, i, dt, g, L)
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


@numba.njit(cache=True, nogil=True, inline="always")
def _linear_particle(x, b, p, F, g, L, k, out):
    """``out[b, p] = F x[b, p] + L g`` for one particle, the normals ``g[:k]`` given: the
    arithmetic of :func:`linear_transition`, written out for ``d = 4``, ``k = 2`` (the
    nonlinear model's white-noise acceleration in x and y)."""
    d = x.shape[2]
    if d == 4 and k == 2:
        x0, x1, x2, x3 = x[b, p, 0], x[b, p, 1], x[b, p, 2], x[b, p, 3]
        g0, g1 = g[0], g[1]
        out[b, p, 0] = _row_4_2(x0, x1, x2, x3, g0, g1, F, L, 0)
        out[b, p, 1] = _row_4_2(x0, x1, x2, x3, g0, g1, F, L, 1)
        out[b, p, 2] = _row_4_2(x0, x1, x2, x3, g0, g1, F, L, 2)
        out[b, p, 3] = _row_4_2(x0, x1, x2, x3, g0, g1, F, L, 3)
        return
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


@numba.njit(cache=True, nogil=True)
def linear_transition(x, F, g, L, out):
    """``out = x @ F.T + g @ L.T`` for C-contiguous ``x (n, P, d)`` and ``g (n, P, k)``, with
    the arithmetic of the BLAS ``dgemm`` that NumPy's ``matmul`` calls for each trial's
    contiguous ``(P, d)`` block (OpenBLAS on x86-64 with FMA: each element is the chain
    ``x_0 F_j0``, then ``fma(x_m, F_jm, acc)`` for ``m = 1..d-1``), the two products added
    last. ``tests/test_kernels.py`` checks it bit for bit against ``matmul`` on dense random
    matrices, so a machine whose BLAS sums otherwise fails there."""
    n, P = x.shape[0], x.shape[1]
    k = g.shape[2]
    for b in range(n):
        for p in range(P):
            _linear_particle(x, b, p, F, g[b, p], L, k, out)


def _linear_draw_kernel(pcg: bool):
    """:func:`linear_transition` drawing its normals inline from a PCG64 (``pcg``) or SFC64
    state: the compiled kernel ``(x, F, L, s, ki, wi, fi, r, inv_r, out)``."""

    @numba.njit(cache=True, nogil=True)
    def kernel(x, F, L, s, ki, wi, fi, r, inv_r, out):
        n, P = x.shape[0], x.shape[1]
        k = L.shape[1]
        g = np.empty(max(k, 1))
        s0, s1, s2, s3 = s[0], s[1], s[2], s[3]
        for b in range(n):
            for p in range(P):
                for m in range(k):
                    ok, gm, idx, rabs, s0, s1, s2, s3 = _normal_try(pcg, s0, s1, s2, s3, ki, wi)
                    if not ok:
                        gm, s0, s1, s2, s3 = _normal_slow(pcg, s0, s1, s2, s3, s, idx, rabs,
                                                          gm, ki, wi, fi, r, inv_r)
                    g[m] = gm
                _linear_particle(x, b, p, F, g, L, k, out)
        s[0], s[1], s[2], s[3] = s0, s1, s2, s3

    return kernel


#: ``(x, F, L, s, ki, wi, fi, r, inv_r, out)``: :func:`linear_transition` with the normals
#: ``g[b, p, :]`` drawn inline from the SFC64 state ``s``, particle after particle, in the
#: order ``standard_normal`` fills ``g (n, P, k)``: the same numbers and the same arithmetic,
#: without the array of normals.
linear_transition_draw = _linear_draw_kernel(False)
#: :data:`linear_transition_draw` with the normals from a PCG64 state (NumPy's default
#: generator).
linear_transition_draw_pcg64 = _linear_draw_kernel(True)
