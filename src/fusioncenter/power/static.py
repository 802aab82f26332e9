"""Static channels with CSI (leong2011 Section IV): the problems (18), (25) and their converses.

:func:`min_power` and :func:`min_error` map the physical parameters to the general problems of
:mod:`fusioncenter.power.allocation` (through
:func:`~fusioncenter.power.model.static_coefficients`);
:func:`equal_power` and :func:`equal_power_min_power` are the equal-power baselines (15)-(16).
"""

from __future__ import annotations

import numpy as np

from fusioncenter._validate import nonneg as _nonneg
from fusioncenter._validate import positive as _positive
from fusioncenter.power._common import (
    ALPHA,
    IDEAL_CHANNEL,
    INFEASIBLE,
    SN2_MIN_POWER,
    SW2_TARGET,
    check_access,
    target_xy,
)
from fusioncenter.power._common import document as _doc
from fusioncenter.power.allocation import InfeasibleError, general_max_snr, general_min_power
from fusioncenter.power.model import kappa, required_snr, static_coefficients

__all__ = ["min_power", "min_error", "equal_power", "equal_power_min_power"]


def _threshold_message(D, a, sigma_w2, c, sigma_v2, access) -> str:
    total = np.sum(np.asarray(c, float) ** 2 / np.asarray(sigma_v2, float), axis=-1)
    thr = required_snr(D, a, sigma_w2)
    return (f"target D = {float(np.max(D)):g} is infeasible for {access}: the sum of the sensor "
            f"SNRs Σᵢ cᵢ²/σᵢ² = {float(np.min(total)):.6g} must exceed "
            f"(a²D + σ_w² − D)/(D(D − σ_w²)) = {float(np.max(thr)):.6g} "
            f"(condition (20))")


@_doc(returns=ALPHA, raises=INFEASIBLE, sigma_w2=SW2_TARGET, sigma_n2=SN2_MIN_POWER)
def min_power(access, D, a, sigma_w2, h, c, sigma_v2, sigma_n2) -> np.ndarray:
    """Least total transmit power with ``P_inf <= D``: problem (18) (multi-access) or (25)
    (orthogonal). Returns ``alpha``; raises :class:`InfeasibleError` if (20) fails.
    """
    access = check_access(access)
    x, y = target_xy(D, a, sigma_w2)
    rho, tau, kap = static_coefficients(a, sigma_w2, h, c, sigma_v2)
    sn = _positive("sigma_n2", sigma_n2, f"a variance; {IDEAL_CHANNEL}")
    alpha = general_min_power(access, rho, tau, kap, sn, x, y, infeasible="nan")
    if np.any(np.isnan(alpha)):
        raise InfeasibleError(_threshold_message(D, a, sigma_w2, c, sigma_v2, access))
    return alpha


@_doc(returns=ALPHA)
def min_error(access, gamma_total, a, sigma_w2, h, c, sigma_v2, sigma_n2) -> np.ndarray:
    """Least ``P_inf`` with total power ``<= gamma_total``: problem (23) (multi-access) or (28)
    (orthogonal), both maximizing the SNR (Lemmas 1, 2). Returns ``alpha``.
    """
    access = check_access(access)
    rho, tau, kap = static_coefficients(a, sigma_w2, h, c, sigma_v2)
    sn = _nonneg("sigma_n2", sigma_n2, "a variance")
    return general_max_snr(access, rho, tau, kap, sn, gamma_total)


@_doc(returns=ALPHA, gamma_total=("array_like, optional", "Total power shared equally, ``>= 0``."))
def equal_power(a, sigma_w2, c, sigma_v2, *, gamma=None, gamma_total=None) -> np.ndarray:
    """Equal-power allocation: (15) with power ``gamma`` per sensor, or (16) sharing
    ``gamma_total`` equally among the ``M`` sensors.

    ``alpha_i = sign(c_i) sqrt(gamma (1 - a^2) / (c_i^2 sigma_w2 + sigma_v2_i (1 - a^2)))``: the
    sign makes ``alpha_i c_i >= 0`` as in the proof of Lemma 4, so that the multi-access sum is
    coherent (the paper's (15) writes the positive root; with ``c_i > 0`` they agree).
    """
    if (gamma is None) == (gamma_total is None):
        raise ValueError("give exactly one of gamma (per sensor, (15)) and gamma_total ((16))")
    kap = kappa(a, sigma_w2, c, sigma_v2)
    if gamma is None:
        per = _nonneg("gamma_total", gamma_total, "a power")[..., None] / kap.shape[-1]
    else:
        per = _nonneg("gamma", gamma, "a power")[..., None]
    sign = np.where(np.asarray(c, dtype=float) < 0, -1.0, 1.0)
    return sign * np.sqrt(per / kap)


@_doc(returns=ALPHA, raises=INFEASIBLE, sigma_w2=SW2_TARGET, sigma_n2=SN2_MIN_POWER)
def equal_power_min_power(access, D, a, sigma_w2, h, c, sigma_v2, sigma_n2) -> np.ndarray:
    """Least common per-sensor power (15) with ``P_inf <= D``; returns ``alpha``.

    The SNR with ``alpha_i = sign(c_i) sqrt(gamma / kappa_i)`` increases with ``gamma`` to a
    ceiling: multi-access ``(sum h_i |c_i| / sqrt(kappa_i))^2 / sum h_i^2 sigma_v2_i /
    kappa_i`` (then ``gamma`` solves a linear equation), orthogonal ``sum c_i^2 / sigma_v2_i``
    (the same as the optimal allocation's; ``gamma`` by bisection on the monotone SNR). Raises
    :class:`InfeasibleError` if the target is above the ceiling. Leading axes broadcast; with
    several instances, infeasible ones give NaN rows (and no error) when any is feasible.
    """
    access = check_access(access)
    x, y = target_xy(D, a, sigma_w2)
    rho, tau, kap = static_coefficients(a, sigma_w2, h, c, sigma_v2)
    sn = _positive("sigma_n2", sigma_n2)
    target = x / y
    rho, tau, kap = np.broadcast_arrays(rho, tau, kap)
    lead = rho.shape[:-1]
    target = np.broadcast_to(target, lead)
    sn_b = np.broadcast_to(sn, lead)
    if access == "multi-access":
        u = np.abs(rho) / np.sqrt(kap)  # alpha_i rho_i = sqrt(gamma) u_i
        v = tau / kap
        U2, V = np.sum(u, axis=-1) ** 2, np.sum(v, axis=-1)
        ceiling = U2 / V
        with np.errstate(divide="ignore", invalid="ignore"):
            gamma = target * sn_b / (U2 - target * V)
    else:
        ceiling = np.sum(rho**2 / tau, axis=-1)
        ok = ceiling > target
        lo = np.zeros(lead)
        hi = np.ones(lead) * np.where(ok, 1.0, np.nan)

        def s_of(g):
            a2 = g[..., None] / kap
            return np.sum(a2 * rho**2 / (a2 * tau + sn_b[..., None]), axis=-1)

        with np.errstate(invalid="ignore"):
            for _ in range(400):  # grow the bracket
                short = ok & (s_of(hi) < target)
                if not np.any(short):
                    break
                hi = np.where(short, 2 * hi, hi)
            for _ in range(200):
                mid = 0.5 * (lo + hi)
                below = s_of(mid) < target
                lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
                if np.all(~ok | (hi - lo <= 1e-15 * hi)):
                    break
        gamma = hi
    feasible = ceiling > target
    if not np.any(feasible):
        raise InfeasibleError(
            f"target D = {float(np.max(D)):g} is infeasible for equal power ({access}): the SNR "
            f"ceiling {float(np.max(ceiling)):.6g} must exceed (a^2 D + sigma_w2 - D) / "
            f"(D (D - sigma_w2)) = {float(np.max(target)):.6g}")
    gamma = np.where(feasible, gamma, np.nan)
    sign = np.where(np.asarray(rho) < 0, -1.0, 1.0)
    return sign * np.sqrt(gamma[..., None] / kap)
