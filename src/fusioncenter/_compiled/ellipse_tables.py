"""The vector silent probability's tables of :mod:`fusioncenter.censoring.ellipse`, evaluated
compiled: the per-trial bicubic Hermite tables (:func:`hermite_tables`) and the shared bicubic
power-basis table (:func:`power_table`), at every particle.

Operation for operation the NumPy evaluation of :mod:`fusioncenter.censoring.ellipse`, in its
order (``tests/test_kernels.py`` and the censoring tests compare the two, bit for bit).
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["hermite_tables", "power_table"]


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
