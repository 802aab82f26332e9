"""Fading channels with CSI (leong2011 Section V.A): the greedy per-step problems (30), (31).

:func:`csi_min_power_step` and :func:`csi_min_error_step` solve one time step given this step's
channel gains; :func:`greedy_min_power` and :func:`greedy_min_error` run them over a fading
sequence and return the prediction variances and the powers spent.
"""

from __future__ import annotations

import numpy as np

from fusioncenter._validate import finite as _finite
from fusioncenter._validate import nonneg as _nonneg
from fusioncenter._validate import positive as _positive
from fusioncenter.power._common import (
    ALPHA,
    INFEASIBLE,
    SN2_MIN_POWER,
    SW2_TARGET,
    check_access,
    check_target,
)
from fusioncenter.power._common import document as _doc
from fusioncenter.power.allocation import general_min_power
from fusioncenter.power.model import (
    kappa,
    snr,
    static_coefficients,
    stationary_variance,
    steady_recursion,
)
from fusioncenter.power.static import min_error

__all__ = ["csi_min_power_step", "csi_min_error_step", "greedy_min_power", "greedy_min_error"]


def _csi_xy(P, D, a, sigma_w2):
    """``x_k = a^2 P_k + sigma_w2 - D`` and ``y_k = P_k (D - sigma_w2)`` of (30)."""
    a, sigma_w2, D = check_target(D, a, sigma_w2)
    P = _positive("P", P, "a prediction variance")
    return a**2 * P + sigma_w2 - D, P * (D - sigma_w2)


@_doc(returns=ALPHA, raises=INFEASIBLE, P="``P_k``, ``> 0``.", sigma_w2=SW2_TARGET,
      sigma_n2=SN2_MIN_POWER)
def csi_min_power_step(access, P, D, a, sigma_w2, h, c, sigma_v2, sigma_n2, *,
                       infeasible: str = "raise") -> np.ndarray:
    """One greedy step of (30) (or its orthogonal counterpart): the least sum power with
    ``P_{k+1} <= D`` given ``P_k = P`` and this step's channel gains ``h``. Returns ``alpha``.

    When ``a^2 P + sigma_w2 <= D`` the target is met without transmitting (``alpha = 0``).
    Feasibility needs ``sum c_i^2 / sigma_v2_i > (a^2 P + sigma_w2 - D) / (P (D - sigma_w2))``,
    which does not depend on the channel gains.
    """
    access = check_access(access)
    x, y = _csi_xy(P, D, a, sigma_w2)
    rho, tau, kap = static_coefficients(a, sigma_w2, h, c, sigma_v2)
    sn = _positive("sigma_n2", sigma_n2)
    free = x <= 0
    xs = np.where(free, 1.0, x)
    alpha = general_min_power(access, rho, tau, kap, sn, xs, y, infeasible=infeasible)
    return np.where(np.asarray(free)[..., None], 0.0, alpha)


@_doc(returns=ALPHA)
def csi_min_error_step(access, gamma_total, a, sigma_w2, h, c, sigma_v2, sigma_n2):
    """One greedy step of (31) (or its orthogonal counterpart): maximize this step's SNR with
    power ``gamma_total``; it does not depend on ``P_k``. Returns ``alpha``.
    """
    return min_error(access, gamma_total, a, sigma_w2, h, c, sigma_v2, sigma_n2)


def _time_slices(h, c, sigma_v2):
    h = _positive("h", h, "a channel gain magnitude")
    if h.ndim < 2:
        raise ValueError(f"h must be shaped (..., steps, sensors), got {h.shape}")
    c = _finite("c", c)
    sv = _finite("sigma_v2", sigma_v2)
    c = c[..., None, :] if c.ndim >= 1 else c
    sv = sv[..., None, :] if sv.ndim >= 1 else sv
    return h, c, sv


@_doc(returns=("P, power : numpy.ndarray", "``(..., steps + 1)`` and ``(..., steps)``."),
      raises=INFEASIBLE, sigma_w2=SW2_TARGET, h="Channel gains ``(..., steps, M)``, ``> 0``.",
      c="One time slice ``(..., M)``.", sigma_v2="One time slice ``(..., M)``.",
      sigma_n2=SN2_MIN_POWER)
def greedy_min_power(access, D, a, sigma_w2, h, c, sigma_v2, sigma_n2, *, P0=None,
                     infeasible: str = "raise"):
    """Run the greedy scheme (30) over a fading sequence ``h`` shaped ``(..., steps, M)``.

    ``c`` and ``sigma_v2`` have the shape of one time slice (``(..., M)``). Returns ``(P,
    power)``: ``P`` shaped ``(..., steps + 1)`` (``P[..., 0] = P0``, default ``D``) and the sum
    power of each step ``(..., steps)``. Once a step has met the target with equality, ``P_k =
    D`` and every later step solves the same problem: those steps are solved together.
    """
    access = check_access(access)
    D = _finite("D", D)
    h, c, sv = _time_slices(h, c, sigma_v2)
    steps = h.shape[-2]
    lead = h.shape[:-2]
    P = np.empty(lead + (steps + 1,))
    P[..., 0] = D if P0 is None else _positive("P0", P0, "a prediction variance")
    power = np.empty(lead + (steps,))
    kap = kappa(a, sigma_w2, c, sv)
    k = 0
    while k < steps:
        Pk = P[..., k]
        if np.all((np.abs(Pk - D) <= 1e-12 * D) | np.isnan(Pk)):  # NaN: infeasible path
            # every later step: the same x, y (P_k = D); solve them all at once
            alpha = csi_min_power_step(access, np.broadcast_to(D, lead)[..., None], D, a,
                                       sigma_w2, h[..., k:, :], c, sv, sigma_n2,
                                       infeasible=infeasible)
            S = snr(access, alpha, h[..., k:, :], c, sv, sigma_n2)
            P[..., k + 1:] = steady_recursion(D, a, sigma_w2, S)
            power[..., k:] = np.sum(alpha**2 * kap, axis=-1)
            break
        alpha = csi_min_power_step(access, Pk, D, a, sigma_w2, h[..., k, :], c[..., 0, :],
                                   sv[..., 0, :], sigma_n2, infeasible=infeasible)
        S = snr(access, alpha, h[..., k, :], c[..., 0, :], sv[..., 0, :], sigma_n2)
        P[..., k + 1] = steady_recursion(Pk, a, sigma_w2, S)
        power[..., k] = np.sum(alpha**2 * kap[..., 0, :], axis=-1)
        k += 1
    return P, power


@_doc(returns=("P, S, power : numpy.ndarray", ""), h="Channel gains ``(..., steps, M)``, ``> 0``.",
      c="One time slice ``(..., M)``.", sigma_v2="One time slice ``(..., M)``.",
      P0="``P_0`` (default the stationary variance).")
def greedy_min_error(access, gamma_total, a, sigma_w2, h, c, sigma_v2, sigma_n2, *, P0=None):
    """Run the greedy scheme (31) over ``h`` shaped ``(..., steps, M)``: each step maximizes its
    SNR with power ``gamma_total``. Returns ``(P, S, power)``: ``P`` shaped ``(..., steps + 1)``
    (``P[..., 0] = P0``, default ``sigma_w2 / (1 - a^2)``), the per-step SNR and sum power
    ``(..., steps)``.
    """
    access = check_access(access)
    h, c, sv = _time_slices(h, c, sigma_v2)
    alpha = min_error(access, gamma_total, a, sigma_w2, h, c, sv, sigma_n2)
    S = snr(access, alpha, h, c, sv, sigma_n2)
    spent = np.sum(alpha**2 * kappa(a, sigma_w2, c, sv), axis=-1)
    steps = h.shape[-2]
    P = np.empty(S.shape[:-1] + (steps + 1,))
    P[..., 0] = (stationary_variance(a, sigma_w2) if P0 is None
                 else _nonneg("P0", P0, "a prediction variance"))
    for k in range(steps):
        P[..., k + 1] = steady_recursion(P[..., k], a, sigma_w2, S[..., k])
    return P, S, spent
