"""Compiled transitions of the particle filters: the white-noise-acceleration step of
:class:`fusioncenter.censoring.LinearFusionCentre` and the vector model
(:func:`propagate_wna`), the linear-Gaussian transition of
:class:`fusioncenter.particle.LinearGaussianDynamics` (:func:`linear_transition`), and their
twins that draw the process noise inline (:func:`propagate_wna_draw`,
:func:`linear_transition_draw`, :func:`linear_transition_draw_pcg64`) with NumPy's own
standard normals (:func:`fusioncenter._compiled.inline_normals.normal`).

One pass per trial, row by row (a trial's result never depends on the other trials of a
block), the NumPy code's arithmetic operation for operation (``tests/test_kernels.py`` compares
each kernel with it, the inline draws bit for bit with ``standard_normal``). A particle's
linear step is written once (:func:`_linear_particle`), inlined into the kernel that takes its
normals and the two that draw them.
"""

from __future__ import annotations

import numba
import numpy as np
from numba import types
from numba.extending import intrinsic

from fusioncenter._compiled.inline_normals import normal

__all__ = ["propagate_wna", "propagate_wna_draw", "linear_transition", "linear_transition_draw",
           "linear_transition_draw_pcg64"]


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
    s0, s1, s2, s3 = s[0], s[1], s[2], s[3]  # the state in registers (inline_normals)
    if k == 1 and x.strides[1] == 8 and P > 1:  # stored by component: rows of a component
        l0, l1 = L[0, 0], L[1, 0]
        for b in range(m):
            pb = np.ascontiguousarray(x[b, :, 0])  # views (the rows are contiguous), typed so
            vb = np.ascontiguousarray(x[b, :, 1])
            for i in range(P):
                p = pb[i]
                v = vb[i]
                p = p + v * dt
                gj, s0, s1, s2, s3 = normal(False, s0, s1, s2, s3, s, ki, wi, fi, r, inv_r)
                pb[i] = p + gj * l0
                vb[i] = v + gj * l1
        s[0], s[1], s[2], s[3] = s0, s1, s2, s3
        return
    g = np.empty(k)
    for b in range(m):
        for i in range(P):
            for j in range(k):
                g[j], s0, s1, s2, s3 = normal(False, s0, s1, s2, s3, s, ki, wi, fi, r, inv_r)
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
                    g[m], s0, s1, s2, s3 = normal(pcg, s0, s1, s2, s3, s, ki, wi, fi, r, inv_r)
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
