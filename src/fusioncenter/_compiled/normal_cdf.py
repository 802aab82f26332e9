"""The standard normal distribution function, compiled, bit for bit SciPy's ``special.ndtr``.

:func:`ndtr` follows the algorithm of SciPy's ``ndtr`` (Cephes, as translated into SciPy's
``xsf`` library): ``Phi(a) = (1 + erf(a / sqrt 2)) / 2`` near the centre (``|a| < sqrt 2``, a
rational function of ``x^2``) and ``erfc(|a| / sqrt 2) / 2`` elsewhere (``exp(-x^2)`` times one
of two rational functions of ``x``, zero beyond ``x^2 > 709.78``), with the same coefficients,
evaluated in the same order (Horner's scheme; no fused multiply-add), and ``exp`` from the
same C library. So it returns SciPy's numbers exactly; ``tests/test_kernels.py`` compares the
two on millions of points over the whole range, on the branch boundaries and on the special
values (``nan``, ``+-inf``, ``+-0``, subnormals).

:func:`inside_difference` is the probability of :func:`fusioncenter._compiled.censored_normal
.log_prob_inside` (``Phi(h - |m|) - Phi(-h - |m|)``) in one pass over the particles, without the
three temporary arrays of the NumPy expression: the two ``ndtr`` of CFwMD2's silent factor (its
threshold differs per trial, so no table serves it) and of every scalar filter's exact one.
"""

from __future__ import annotations

import math

import numba
import numpy as np

__all__ = ["ndtr", "inside_difference"]

# The coefficients of SciPy's ``ndtr``/``erf``/``erfc`` (Cephes ``ndtr.c``): erfc on
# ``1 <= x < 8`` is ``exp(-x^2) P(x) / Q(x)``, on ``x >= 8`` ``exp(-x^2) R(x) / S(x)``; erf on
# ``|x| < 1`` is ``x T(x^2) / U(x^2)``; ``Q``, ``S`` and ``U`` are monic (leading 1 omitted).
_P = np.array([2.46196981473530512524E-10, 5.64189564831068821977E-1, 7.46321056442269912687E0,
               4.86371970985681366614E1, 1.96520832956077098242E2, 5.26445194995477358631E2,
               9.34528527171957607540E2, 1.02755188689515710272E3, 5.57535335369399327526E2])
_Q = np.array([1.32281951154744992508E1, 8.67072140885989742329E1, 3.54937778887819891062E2,
               9.75708501743205489753E2, 1.82390916687909736289E3, 2.24633760818710981792E3,
               1.65666309194161350182E3, 5.57535340817727675546E2])
_R = np.array([5.64189583547755073984E-1, 1.27536670759978104416E0, 5.01905042251180477414E0,
               6.16021097993053585195E0, 7.40974269950448939160E0, 2.97886665372100240670E0])
_S = np.array([2.26052863220117276590E0, 9.39603524938001434673E0, 1.20489539808096656605E1,
               1.70814450747565897222E1, 9.60896809063285878198E0, 3.36907645100081516050E0])
_T = np.array([9.60497373987051638749E0, 9.00260197203842689217E1, 2.23200534594684319226E3,
               7.00332514112805075473E3, 5.55923013010394962768E4])
_U = np.array([3.35617141647503099647E1, 5.21357949780152679795E2, 4.59432382970980127987E3,
               2.26290000613890934246E4, 4.92673942608635921086E4])
#: ``log`` of the largest double: ``exp(-x^2)`` is taken as 0 below ``-_MAXLOG``
_MAXLOG = 7.09782712893383996843E2
_SQRT1_2 = 7.07106781186547524401E-1


@numba.njit(cache=True, nogil=True, inline="always")
def _horner(x, c):
    """``c[0] x^n + ... + c[n]`` (Cephes ``polevl``)."""
    a = c[0]
    for i in range(1, c.size):
        a = a * x + c[i]
    return a


@numba.njit(cache=True, nogil=True, inline="always")
def _horner_monic(x, c):
    """``x^(n+1) + c[0] x^n + ... + c[n]`` (Cephes ``p1evl``)."""
    a = x + c[0]
    for i in range(1, c.size):
        a = a * x + c[i]
    return a


@numba.njit(cache=True, nogil=True)
def ndtr(a: float) -> float:
    """``Phi(a)``, the standard normal distribution function: ``scipy.special.ndtr(a)``."""
    if a != a:
        return a
    x = a * _SQRT1_2
    z = abs(x)
    if z < 1.0:  # 0.5 + 0.5 erf(x)
        zz = x * x
        return 0.5 + 0.5 * (x * _horner(zz, _T) / _horner_monic(zz, _U))
    # 0.5 erfc(z), z >= 1
    e = -z * z
    if e < -_MAXLOG:
        y = 0.0
    else:
        e = math.exp(e)
        if z < 8.0:
            y = 0.5 * ((e * _horner(z, _P)) / _horner_monic(z, _Q))
        else:
            y = 0.5 * ((e * _horner(z, _R)) / _horner_monic(z, _S))
    if x > 0:
        y = 1.0 - y
    return y


@numba.njit(cache=True, nogil=True)
def inside_difference(m, h, out, cutoff: float, h_small: float) -> int:
    """``out = ndtr(h - m) - ndtr(-h - m)`` over 2-D arrays of one shape (broadcast views
    allowed; ``m >= 0``), the operations of the NumPy expression in its order. Returns how many
    entries are below ``cutoff`` or have ``h < h_small`` (0: none needs the careful formula)."""
    n, P = out.shape
    bad = 0
    for i in range(n):
        for j in range(P):
            mm, hh = m[i, j], h[i, j]
            p = ndtr(hh - mm) - ndtr(-hh - mm)
            out[i, j] = p
            if p < cutoff or hh < h_small:
                bad += 1
    return bad
