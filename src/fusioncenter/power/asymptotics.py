"""The 1/M laws of leong2011 (Section III): symmetric sensors (Lemma 3, (11)-(14)), Lemma 4.

:func:`symmetric_asymptotics` gives ``(limit, coefficient)`` of ``P_inf = limit + coefficient / M
+ O(1/M^2)``; :func:`lemma4_bounds` the printed (or exact) bounds for general sensors.
"""

from __future__ import annotations

import numpy as np

from fusioncenter._validate import finite as _finite
from fusioncenter._validate import nonneg as _nonneg
from fusioncenter._validate import positive as _positive
from fusioncenter.power._common import A_ANY, check_a, check_access
from fusioncenter.power._common import document as _doc
from fusioncenter.power.model import steady_state

__all__ = ["symmetric_asymptotics", "lemma4_bounds"]


@_doc(returns=("limit, coefficient : numpy.ndarray", ""), a=A_ANY,
      h="Scalars: ``h > 0``, ``c != 0``, ``sigma_v2 > 0``.",
      c="Scalars: ``h > 0``, ``c != 0``, ``sigma_v2 > 0``.",
      sigma_v2="Scalars: ``h > 0``, ``c != 0``, ``sigma_v2 > 0``.")
def symmetric_asymptotics(access, scaling, a, sigma_w2, h, c, sigma_v2, sigma_n2):
    """``(limit, coefficient)`` with ``P_inf = limit + coefficient / M + O(1/M^2)``.

    Symmetric sensors (scalars ``h``, ``c``, ``sigma_v2``); ``scaling`` is ``"none"``
    (``alpha_i = 1``) or ``"sqrt"`` (``alpha_i = 1/sqrt(M)``):

    * multi-access, none:  Lemma 3 / (11): ``(sigma_w2, a^2 sigma_v2 / c^2)``
    * orthogonal, none:    (12):           ``(sigma_w2, a^2 (sigma_v2 + sigma_n2/h^2) / c^2)``
    * multi-access, sqrt:  (13):           the same as (12)
    * orthogonal, sqrt:    (14): the limit is at least ``sigma_w2`` (equal only when a = 0 or
      sigma_n2 = 0; no 1/M law to ``sigma_w2``).
    """
    access = check_access(access)
    if scaling not in ("none", "sqrt"):
        raise ValueError(f"scaling must be 'none' or 'sqrt', got {scaling!r}")
    a = check_a(a, stable=False)
    sw = _nonneg("sigma_w2", sigma_w2, "a variance")
    h = _positive("h", h, "a channel gain magnitude")
    c = _finite("c", c)
    if np.any(c == 0):
        raise ValueError("c must be non-zero for a 1/M law")
    sv = _positive("sigma_v2", sigma_v2)
    sn = _nonneg("sigma_n2", sigma_n2, "a variance")
    if access == "orthogonal" and scaling == "sqrt" and np.any((sw == 0) & (sn == 0)):
        raise ValueError("sigma_w2 and sigma_n2 must not both be 0 for (14): its 1/M "
                         "coefficient divides by their combination")
    if access == "multi-access" and scaling == "none":
        return sw, a**2 * sv / c**2
    if scaling == "none" or access == "multi-access":
        return sw, a**2 * (sv + sn / h**2) / c**2
    # (14)
    root = np.sqrt((a**2 - 1) ** 2 * sn**2 + 2 * (a**2 + 1) * sn * h**2 * c**2 * sw
                   + h**4 * c**4 * sw**2)
    limit = ((a**2 - 1) * sn + h**2 * c**2 * sw + root) / (2 * h**2 * c**2)
    coef = ((a**2 - 1) * sv / (2 * c**2)
            + ((a**2 + 1) * h**4 * sv * c**2 * sw + (a**2 - 1) ** 2 * sn * h**2 * sv)
            / (2 * h**2 * c**2 * root))
    return limit, coef


@_doc(returns=("lower, upper : numpy.ndarray", ""), a=A_ANY, scaling='``"sqrt"`` or ``"none"``.')
def lemma4_bounds(M, a, sigma_w2, sigma_n2, h_range, c_range, sigma_v2_range, *,
                  scaling: str = "sqrt", exact: bool = False):
    """Bounds on the multi-access ``P_inf`` for general sensors (Lemma 4), ``(lower, upper)``.

    Ranges are ``(min, max)`` of ``h_i``, ``|c_i|`` and ``sigma_v2_i``; ``alpha_i = +-1/sqrt(M)``
    (``scaling="sqrt"``, eq. (37)) or ``+-1`` (``"none"``) with ``alpha_i c_i > 0``.

    ``exact=False`` gives the printed asymptotic bounds ``sigma_w2 + a^2 r_lo / M`` and
    ``sigma_w2 + a^2 r_hi / M`` (dropping their O(1/M^2) terms). ``exact=True`` gives
    ``steady_state`` at the smallest and largest SNR the ranges allow, which bound ``P_inf`` for
    every ``M`` (Lemma 1). The printed upper bound is itself exact (``P_inf < sigma_w2 + a^2/S``
    for every S > 0); the printed lower bound is not guaranteed for small ``M``.
    """
    if scaling not in ("none", "sqrt"):
        raise ValueError(f"scaling must be 'none' or 'sqrt', got {scaling!r}")
    M = _positive("M", M, "a number of sensors")
    a = check_a(a, stable=False)
    sw = _nonneg("sigma_w2", sigma_w2, "a variance")
    sn = _nonneg("sigma_n2", sigma_n2, "a variance")
    (h_lo, h_hi), (c_lo, c_hi), (s_lo, s_hi) = (
        _positive(n, r, "a range of positive values") for n, r in
        (("h_range", h_range), ("c_range", c_range), ("sigma_v2_range", sigma_v2_range)))
    for name, lo_, hi_ in (("h_range", h_lo, h_hi), ("c_range", c_lo, c_hi),
                           ("sigma_v2_range", s_lo, s_hi)):
        if lo_ > hi_:
            raise ValueError(f"{name} must be (min, max) with min <= max, got ({lo_:g}, {hi_:g})")
    # bounds on rbar / cbar^2 = 1/S, multiplied by M
    if scaling == "sqrt":
        lo = (h_lo**2 * s_lo + sn) / (h_hi**2 * c_hi**2)
        hi = (h_hi**2 * s_hi + sn) / (h_lo**2 * c_lo**2)
    else:
        lo = (h_lo**2 * s_lo + sn / M) / (h_hi**2 * c_hi**2)
        hi = (h_hi**2 * s_hi + sn / M) / (h_lo**2 * c_lo**2)
    if exact:
        return steady_state(a, sw, M / lo), steady_state(a, sw, M / hi)
    if scaling == "none":  # the printed constants drop sigma_n2 / M as O(1/M^2)
        lo = h_lo**2 * s_lo / (h_hi**2 * c_hi**2)
        hi = h_hi**2 * s_hi / (h_lo**2 * c_lo**2)
    return sw + a**2 * lo / M, sw + a**2 * hi / M
