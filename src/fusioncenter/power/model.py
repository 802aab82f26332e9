"""The model of leong2011: stationary variance, transmit power, SNR and the steady state (8).

Scalar state ``x_{k+1} = a x_k + w_k``, sensors ``y_i = c_i x + v_i`` forwarding ``alpha_i y_i``
over channels of gain ``h_i``: :func:`kappa` (power per unit ``alpha^2``),
:func:`transmit_power`, :func:`snr` (multi-access ``S`` or orthogonal ``S^o``),
:func:`steady_state` (eq. (8)) and its inverse :func:`required_snr`, one step
:func:`steady_recursion` of (4)/(5), and :func:`static_coefficients` (the ``rho, tau, kappa`` of
the allocation problems for static channels).
"""

from __future__ import annotations

import numpy as np

from fusioncenter import riccati
from fusioncenter._validate import finite as _finite
from fusioncenter._validate import finite_result as _finite_result
from fusioncenter._validate import nonneg as _nonneg
from fusioncenter._validate import positive as _positive
from fusioncenter.power._common import (
    A_ANY,
    COEFFICIENTS,
    SW2_TARGET,
    check_a,
    check_access,
    check_sensors,
    target_xy,
)
from fusioncenter.power._common import document as _doc

__all__ = ["stationary_variance", "kappa", "transmit_power", "steady_state", "required_snr", "snr",
           "static_coefficients", "steady_recursion"]


#: Below this a product of two floats has lost digits (subnormal range, with a margin).
_SMALL = np.finfo(float).tiny / np.finfo(float).eps


@_doc(returns=("numpy.ndarray", "``sigma_w2 / (1 - a^2)``."))
def stationary_variance(a, sigma_w2) -> np.ndarray:
    """``E[x_k^2] = sigma_w2 / (1 - a^2)`` of the stationary state (|a| < 1)."""
    a = check_a(a)
    return _nonneg("sigma_w2", sigma_w2, "a variance") / (1.0 - a**2)


@_doc(returns=("numpy.ndarray", "``kappa`` ``(..., M)``, finite."), c="``(..., M)``, finite.",
      sigma_v2="``(..., M)``, ``> 0``.")
def kappa(a, sigma_w2, c, sigma_v2) -> np.ndarray:
    """``kappa_i = E[y_i^2] = c_i^2 sigma_w2 / (1 - a^2) + sigma_v2_i``: power per unit alpha^2."""
    s = check_sensors(c=c, sigma_v2=sigma_v2)
    _positive("sigma_v2", s["sigma_v2"])
    with np.errstate(over="ignore"):
        out = s["c"] ** 2 * stationary_variance(a, sigma_w2)[..., None] + s["sigma_v2"]
    return _finite_result("kappa", out, "c_i^2 sigma_w2 / (1 - a^2) overflows")


@_doc(returns=("numpy.ndarray", "``gamma_i`` ``(..., M)``, finite."),
      alpha="``(..., M)``, finite.")
def transmit_power(alpha, a, sigma_w2, c, sigma_v2) -> np.ndarray:
    """Per-sensor transmit powers ``gamma_i = alpha_i^2 kappa_i`` (Section II.C)."""
    s = check_sensors(alpha=alpha, c=c)
    with np.errstate(over="ignore"):
        out = s["alpha"] ** 2 * kappa(a, sigma_w2, s["c"], sigma_v2)
    return _finite_result("the transmit power", out, "alpha_i^2 kappa_i overflows")


@_doc(
      returns=("numpy.ndarray", "``P_inf``, finite, in ``[sigma_w2, sigma_w2 / (1 - a^2)]`` for "
                                "``|a| < 1``."),
      a=A_ANY)
def steady_state(a, sigma_w2, S) -> np.ndarray:
    """Steady-state prediction variance ``P_inf`` of eq. (8) (= (7), (10)) for SNR ``S >= 0``.

    ``S = 0`` (no information) gives ``sigma_w2 / (1 - a^2)``, which needs ``|a| < 1``; for
    ``S > 0`` any real ``a`` is allowed (Remark III.E.2), up to a documented limit: for
    ``|a| > 1`` ``P_inf`` is about ``sigma_w2 + (a^2 - 1) / S``, and where that exceeds the
    float range (``a = 1e300``, ``S = 2``: ``5e599``) a ``ValueError`` naming ``a`` says so.
    Reuses :func:`fusioncenter.riccati.scalar_steady_state` with ``c = sqrt(S)``, ``r = 1``.
    Broadcasts like a ufunc.
    """
    a = check_a(a, stable=False)
    sigma_w2 = _nonneg("sigma_w2", sigma_w2, "a variance")
    S = _finite("S", S)
    if np.any(S < 0):
        raise ValueError(f"S must be non-negative (it is a signal-to-noise ratio), got {S!r}")
    if np.any((S == 0) & (np.abs(a) >= 1)):
        raise ValueError("a must satisfy |a| < 1 when S = 0: without measurements an unstable "
                         "state has no steady-state variance")
    try:
        return riccati.scalar_steady_state(a, sigma_w2, np.sqrt(S), 1.0)
    except ValueError as err:
        if "beyond the float range" not in str(err):
            raise
        raise ValueError(f"a (with sigma_w2, S) gives a steady-state variance beyond the float "
                         f"range (about sigma_w2 + (a^2 - 1) / S > 1.8e308): a = {a!r}, "
                         f"sigma_w2 = {sigma_w2!r}, S = {S!r}") from None


@_doc(returns=("numpy.ndarray", "The SNR at which ``P_inf = D``."), sigma_w2=SW2_TARGET)
def required_snr(D, a, sigma_w2) -> np.ndarray:
    """The SNR at which ``P_inf = D``: ``(a^2 D + sigma_w2 - D) / (D (D - sigma_w2))``.

    The inverse of :func:`steady_state` (which is decreasing in ``S``, Lemma 1); the right-hand
    side of (25) and ``x / y`` of problem (19).
    """
    x, y = target_xy(D, a, sigma_w2)
    return x / y


@_doc(returns=("float or numpy.ndarray", "``S >= 0``, at most ``sum_i c_i^2 / sigma_v2_i``."),
      alpha="``(..., M)``, finite (any magnitude: the formula is rescaled where it would "
            "overflow).")
def snr(access, alpha, h, c, sigma_v2, sigma_n2) -> np.ndarray:
    """``S`` (multi-access) or ``S^o`` (orthogonal) of Section II.D for static channels."""
    access = check_access(access)
    s = check_sensors(alpha=alpha, h=h, c=c, sigma_v2=sigma_v2)
    _positive("h", s["h"], "a channel gain magnitude")
    _positive("sigma_v2", s["sigma_v2"])
    sigma_n2 = _nonneg("sigma_n2", sigma_n2, "a variance")
    ah = s["alpha"] * s["h"]
    c, sv = s["c"], s["sigma_v2"]
    with np.errstate(over="ignore", invalid="ignore", divide="ignore", under="ignore"):
        if access == "multi-access":
            num = np.sum(ah * c, axis=-1) ** 2
            den0 = np.sum(ah**2 * sv, axis=-1) + sigma_n2
            out = num / den0
            bad = ~np.isfinite(out) | (den0 < _SMALL)  # overflow, or digits lost to underflow
            if np.any(bad):
                # (alpha h)^2 overflowed, or 0/0 with sigma_n2 = 0: divide through by the
                # largest |alpha_i h_i| (S is then a ratio of order-one sums)
                amax = np.max(np.abs(ah), axis=-1, keepdims=True)
                u = ah / np.where(amax > 0, amax, 1.0)
                am = np.where(amax > 0, amax, 1.0)[..., 0]
                den = np.sum(u**2 * sv, axis=-1) + sigma_n2 / am / am
                scaled = np.where(amax[..., 0] > 0, np.sum(u * c, axis=-1) ** 2 / den, 0.0)
                out = np.where(bad, scaled, out)
        else:
            den0 = ah**2 * sv + sigma_n2[..., None]
            term = ah**2 * c**2 / den0
            bad = ~np.isfinite(term) | (den0 < _SMALL)
            if np.any(bad):  # c^2 / (sigma_v2 + sigma_n2 / (alpha h)^2); alpha_i = 0 sends nothing
                aa = np.abs(np.where(ah != 0, ah, 1.0))
                alt = np.where(ah != 0, c**2 / (sv + sigma_n2[..., None] / aa / aa), 0.0)
                term = np.where(bad, alt, term)
            out = np.sum(term, axis=-1)
    return out[()] if np.ndim(out) == 0 else out


@_doc(returns=COEFFICIENTS)
def static_coefficients(a, sigma_w2, h, c, sigma_v2):
    """``(rho, tau, kappa)`` of problems (19)/(26) for static channels with CSI:
    ``rho_i = h_i c_i``, ``tau_i = h_i^2 sigma_v2_i``, ``kappa_i = c_i^2 sigma_w2/(1-a^2) +
    sigma_v2_i``.
    """
    s = check_sensors(h=h, c=c, sigma_v2=sigma_v2)
    _positive("h", s["h"], "a channel gain magnitude")
    _positive("sigma_v2", s["sigma_v2"])
    return s["h"] * s["c"], s["h"] ** 2 * s["sigma_v2"], kappa(a, sigma_w2, s["c"],
                                                                s["sigma_v2"])


@_doc(returns=("numpy.ndarray", "The next prediction variance(s)."),
      raises=(("ValueError", "If an argument is NaN, infinite or negative (``a`` excepted), or "
                             "the result overflows."),),
      a="State transition(s), finite.", sigma_w2="Process-noise variance(s), ``>= 0``.",
      S="Signal-to-noise ratio(s), ``>= 0``.")
def steady_recursion(P, a, sigma_w2, S):
    """One step of (4)/(5) in SNR form: ``a^2 P / (1 + P S) + sigma_w2`` (broadcasts)."""
    P = _nonneg("P", P, "a prediction variance")
    a = _finite("a", a)
    sigma_w2 = _nonneg("sigma_w2", sigma_w2, "a variance")
    S = _nonneg("S", S, "a signal-to-noise ratio")
    with np.errstate(over="ignore", invalid="ignore"):
        out = a**2 * P / (1.0 + P * S) + sigma_w2
    return _finite_result("the next variance", out, "a^2 P overflows the float range")
