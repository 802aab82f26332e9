"""NumPy's standard normals drawn inside compiled loops, bit for bit: the bit generators SFC64
and PCG64 and NumPy's 256-layer ziggurat, as helpers that numba inlines into the kernels that
draw (:mod:`fusioncenter._compiled.transitions`) and as two fill kernels
(:func:`sfc64_normals`, :func:`pcg64_normals`).

A generator's state is four unsigned 64-bit words: SFC64's own four, or PCG64's 128-bit state
(high, low) then its increment (high, low) (the layout of
:func:`fusioncenter._compiled.ziggurat.draw_state`). A kernel keeps the state in four local
variables while it draws (in registers: an array's state goes through memory at every draw, as
the compiler cannot tell it from the particles' arrays) and passes the array only to the
ziggurat's rare branches. One draw, :func:`normal`, is written once for both generators: its
``pcg`` flag is a constant of the kernel that calls it (each kernel is made for one generator by
a small factory, :func:`normals_kernel` here and the linear transition's in
:mod:`fusioncenter._compiled.transitions`), so the compiler keeps one branch.

The tables ``ki, wi, fi`` and the tail constants ``r, inv_r`` are NumPy's
(:func:`fusioncenter._compiled.ziggurat.tables`); ``tests/test_kernels.py`` compares the draws
with ``standard_normal`` bit for bit, and the state left behind with NumPy's.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numba import types
from numba.extending import intrinsic

__all__ = ["normal", "normals_kernel", "sfc64_normals", "pcg64_normals"]

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
        return _pcg64_step(a, b, c, w)
    return _sfc64_step(a, b, c, w)


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
def normal(pcg, a, b, c, w, s, ki, wi, fi, r, inv_r):
    """One standard normal, NumPy's: the ziggurat's layer test on one 64-bit output of the
    state ``(a, b, c, w)`` (PCG64 if ``pcg``, else SFC64), the rare branches through the state
    array ``s`` (written before, read back after). Returns ``(value, a, b, c, w)``, the state
    advanced; ``s`` is current only after the caller writes the state back."""
    while True:
        u, a, b, c, w = _step(pcg, a, b, c, w)
        idx = np.intp(u & _M8)
        u = u >> _U8
        rabs = (u >> _U1) & _M52
        x = np.float64(rabs) * wi[idx]
        if u & _U1:
            x = -x
        if rabs < ki[idx]:
            return x, a, b, c, w
        s[0], s[1], s[2], s[3] = a, b, c, w
        ok, x = _normal_rare(pcg, s, idx, rabs, x, fi, r, inv_r)
        a, b, c, w = s[0], s[1], s[2], s[3]
        if ok:
            return x, a, b, c, w


def normals_kernel(pcg: bool):
    """The compiled fill kernel ``(s, ki, wi, fi, r, inv_r, out)`` of one generator (PCG64 if
    ``pcg``, else SFC64): ``out`` (flat order) filled with standard normals drawn from the
    state ``s (4,) uint64``, which is left advanced; ``standard_normal``'s numbers.

    Parameters
    ----------
    pcg : bool
        The generator: PCG64 (true) or SFC64.

    Returns
    -------
    numba.core.registry.CPUDispatcher
        The kernel, compiled and cached for that generator.
    """

    @numba.njit(cache=True, nogil=True)
    def fill(s, ki, wi, fi, r, inv_r, out):
        o = out.reshape(-1)
        a, b, c, w = s[0], s[1], s[2], s[3]
        for n in range(o.shape[0]):
            o[n], a, b, c, w = normal(pcg, a, b, c, w, s, ki, wi, fi, r, inv_r)
        s[0], s[1], s[2], s[3] = a, b, c, w

    return fill


#: ``(s, ki, wi, fi, r, inv_r, out)``: ``out`` filled with NumPy's standard normals from the
#: SFC64 state ``s`` (:func:`normals_kernel`).
sfc64_normals = normals_kernel(False)
#: :data:`sfc64_normals` for NumPy's PCG64.
pcg64_normals = normals_kernel(True)
