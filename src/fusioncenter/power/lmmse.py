"""Fading channels without CSI (leong2011 Section V.B): the linear MMSE estimator (32)-(33).

The sensors beamform on the mean channel (:func:`beamformed`); :func:`lmmse_matrices` gives the
estimator's ``(Cbar, Rbar)`` (with the covariance term the printed ``Rbar`` omits),
:func:`lmmse_snr` its SNR, :func:`lmmse_steady_state` its steady state, :func:`lmmse_filter` runs
it, :func:`simulate_nocsi` simulates the system and runs it; :func:`lmmse_coefficients`,
:func:`lmmse_min_power` and :func:`lmmse_min_error` are the allocation problems without CSI.
"""

from __future__ import annotations

import numpy as np

from fusioncenter._validate import covariance as _covariance
from fusioncenter._validate import finite as _finite
from fusioncenter._validate import integer as _integer
from fusioncenter._validate import is_text
from fusioncenter._validate import nonneg as _nonneg
from fusioncenter._validate import positive as _positive
from fusioncenter.power._common import (
    ALPHA,
    COEFFICIENTS,
    INFEASIBLE,
    SN2_POSITIVE,
    SW2_TARGET,
    check_a,
    check_access,
    check_sensors,
    target_xy,
)
from fusioncenter.power._common import document as _doc
from fusioncenter.power.allocation import InfeasibleError, general_max_snr, general_min_power
from fusioncenter.power.model import kappa, stationary_variance, steady_state

__all__ = ["beamformed", "lmmse_matrices", "lmmse_snr", "lmmse_coefficients", "lmmse_steady_state",
           "lmmse_min_power", "lmmse_min_error", "lmmse_filter", "simulate_nocsi"]


@_doc(returns=("numpy.ndarray", "Complex ``alpha~``."))
def beamformed(alpha, h_mean) -> np.ndarray:
    """``alpha~_i = alpha_i conj(E h~_i) / |E h~_i|``: beamforming on the mean channel."""
    if is_text(h_mean):
        raise ValueError(f"h_mean must be (complex) numbers, not text, got {h_mean!r}")
    s = check_sensors(alpha=alpha, h_mean=np.abs(np.asarray(h_mean)))
    m = np.asarray(h_mean, dtype=complex)
    if np.any(np.abs(m) == 0):
        raise ValueError("h_mean must be non-zero (zero-mean fading carries no information "
                         "to the linear estimator)")
    return s["alpha"] * np.conj(m) / np.abs(m)


def _channel_stats(alpha_t, h_mean, h_var_re, h_var_im):
    """Moments of ``g = alpha~ h~`` (independent real/imaginary parts of ``h~``)."""
    p, q = np.real(alpha_t), np.imag(alpha_t)
    mr, mi = np.real(h_mean), np.imag(h_mean)
    mean_re, mean_im = p * mr - q * mi, q * mr + p * mi
    var_re = p**2 * h_var_re + q**2 * h_var_im
    var_im = q**2 * h_var_re + p**2 * h_var_im
    cov = p * q * (h_var_re - h_var_im)
    return mean_re, mean_im, var_re, var_im, cov


@_doc(returns=("Cbar, Rbar : numpy.ndarray", ""), sigma_n2=SN2_POSITIVE)
def lmmse_matrices(access, alpha_t, a, sigma_w2, c, sigma_v2, sigma_n2, h_mean, h_var_re,
                   h_var_im):
    """``(Cbar, Rbar)`` of the linear MMSE estimator (32) without CSI.

    ``alpha_t`` complex amplification factors, ``h_mean`` the complex channel means and
    ``h_var_re``, ``h_var_im`` the variances of their real and imaginary parts (independent,
    i.i.d. over time, and independent across sensors: ``Rbar`` is a sum over the sensors and has
    no cross-sensor terms, an assumption the paper uses before (32) without stating it). The
    observation is ``(Re z~, Im z~)``: multi-access gives ``Cbar`` shaped ``(..., 2)`` and
    ``Rbar`` ``(..., 2, 2)``; orthogonal stacks the sensors, ``Cbar`` ``(..., 2M)`` and
    block-diagonal ``Rbar`` ``(..., 2M, 2M)``. ``Rbar`` includes the covariance ``Cov(Re g, Im
    g) (c_i^2 sigma_w2/(1-a^2) + sigma_v2_i)`` of the off-diagonal term, which the printed
    ``Rbar`` omits; it vanishes when ``Var Re h~ = Var Im h~`` (as in the paper's Rician
    example) or ``alpha~`` is real or imaginary.
    """
    access = check_access(access)
    s = check_sensors(c=c, sigma_v2=sigma_v2, h_var_re=h_var_re, h_var_im=h_var_im,
                 alpha_t=np.abs(np.asarray(alpha_t)), h_mean=np.abs(np.asarray(h_mean)))
    _positive("sigma_v2", s["sigma_v2"])
    for name in ("h_var_re", "h_var_im"):
        if np.any(s[name] < 0):
            raise ValueError(f"{name} must be non-negative (it is a variance)")
    sn = _positive("sigma_n2", sigma_n2)
    Pi = stationary_variance(a, sigma_w2)
    alpha_t = np.asarray(alpha_t, dtype=complex)
    h_mean = np.asarray(h_mean, dtype=complex)
    c, sv = s["c"], s["sigma_v2"]
    mre, mim, vre, vim, cov = _channel_stats(alpha_t, h_mean, s["h_var_re"], s["h_var_im"])
    cx = c**2 * Pi
    r11 = vre * cx + (vre + mre**2) * sv
    r22 = vim * cx + (vim + mim**2) * sv
    r12 = cov * cx + (cov + mre * mim) * sv
    if access == "multi-access":
        C = np.stack([np.sum(mre * c, axis=-1), np.sum(mim * c, axis=-1)], axis=-1)
        R = np.stack([np.stack([np.sum(r11, -1) + sn, np.sum(r12, -1)], -1),
                      np.stack([np.sum(r12, -1), np.sum(r22, -1) + sn], -1)], -2)
        return C, R
    C = np.stack([mre * c, mim * c], axis=-1)  # (..., M, 2)
    blocks = np.stack([np.stack([r11 + sn, r12], -1), np.stack([r12, r22 + sn], -1)], -2)
    M = c.shape[-1]
    R = np.zeros(blocks.shape[:-3] + (2 * M, 2 * M))
    for i in range(M):
        R[..., 2 * i:2 * i + 2, 2 * i:2 * i + 2] = blocks[..., i, :, :]
    return C.reshape(C.shape[:-2] + (2 * M,)), R


@_doc(returns=("numpy.ndarray", "``S`` ``(...)``, ``>= 0``."),
      raises=(("ValueError", "If ``Cbar`` is not finite, ``Rbar`` not symmetric positive "
                             "definite, or the shapes\n"
                             "disagree."),))
def lmmse_snr(Cbar, Rbar) -> np.ndarray:
    """``S = Cbar^T Rbar^{-1} Cbar`` (the printed ``S^o`` lacks the inverse)."""
    Cbar = _finite("Cbar", Cbar)
    Rbar = _covariance("Rbar", Rbar, definite=True, batch=True)
    if Cbar.ndim < 1 or Cbar.shape[-1] != Rbar.shape[-1]:
        raise ValueError(f"Cbar must have {Rbar.shape[-1]} entries on its last axis (as Rbar), "
                         f"got shape {Cbar.shape}")
    return np.einsum("...i,...i->...", Cbar,
                     np.linalg.solve(Rbar, Cbar[..., None])[..., 0])


@_doc(returns=COEFFICIENTS,
      h_var_re="``>= 0``; equal where the mean is neither real nor imaginary.",
      h_var_im="``>= 0``; equal where the mean is neither real nor imaginary.")
def lmmse_coefficients(a, sigma_w2, c, sigma_v2, h_mean, h_var_re, h_var_im):
    """``(rho, tau, kappa)`` of the no-CSI problems with ``alpha~ = beamformed(alpha, h_mean)``.

    Then ``S = (sum alpha_i rho_i)^2 / (sum alpha_i^2 tau_i + sigma_n2)`` (multi-access) and
    ``S^o = sum alpha_i^2 rho_i^2 / (alpha_i^2 tau_i + sigma_n2)`` (orthogonal): variants of
    problems (19), (23), (26), (28) with ``rho_i = |E h~_i| c_i`` and ``tau_i = Var[Re g_i] c_i^2
    sigma_w2/(1-a^2) + E[Re^2 g_i] sigma_v2_i`` per unit ``alpha_i^2`` (from (33)). The reduction
    needs ``Cov(Re g_i, Im g_i) = 0``: equal variances of Re and Im of ``h~_i`` (as in the
    paper's Rician example) or a real or imaginary mean; otherwise ``ValueError``.
    """
    s = check_sensors(c=c, sigma_v2=sigma_v2, h_var_re=h_var_re, h_var_im=h_var_im,
                 h_mean=np.abs(np.asarray(h_mean)))
    for name in ("h_var_re", "h_var_im"):
        if np.any(s[name] < 0):
            raise ValueError(f"{name} must be non-negative (it is a variance)")
    m = np.asarray(h_mean, dtype=complex)
    unit = beamformed(np.ones(np.shape(m)), m)
    mre, _, vre, _, cov = _channel_stats(unit, m, s["h_var_re"], s["h_var_im"])
    if np.any(np.abs(cov) > 1e-12 * (s["h_var_re"] + s["h_var_im"])):
        raise ValueError(
            "h_var_re and h_var_im must be equal where the channel mean is neither real nor "
            "imaginary: otherwise Re and Im of alpha~ h~ are correlated, Rbar_12 != 0 and S does "
            "not reduce to the scalar form of (33); use lmmse_matrices and lmmse_snr")
    kap = kappa(a, sigma_w2, s["c"], s["sigma_v2"])
    Pi = stationary_variance(a, sigma_w2)[..., None]
    tau = vre * s["c"] ** 2 * Pi + (vre + mre**2) * s["sigma_v2"]
    return np.abs(m) * s["c"], tau, kap


@_doc(returns=("numpy.ndarray", "The steady-state prediction MSE."), sigma_n2=SN2_POSITIVE)
def lmmse_steady_state(access, alpha, a, sigma_w2, c, sigma_v2, sigma_n2, h_mean, h_var_re,
                       h_var_im) -> np.ndarray:
    """Steady-state prediction MSE of the no-CSI linear MMSE estimator with ``alpha~ =
    beamformed(alpha, h_mean)``: eq. (8) at ``S = Cbar^T Rbar^{-1} Cbar``.
    """
    alpha_t = beamformed(alpha, h_mean)
    C, R = lmmse_matrices(access, alpha_t, a, sigma_w2, c, sigma_v2, sigma_n2, h_mean,
                          h_var_re, h_var_im)
    return steady_state(a, sigma_w2, lmmse_snr(C, R))


@_doc(returns=ALPHA, raises=INFEASIBLE, sigma_w2=SW2_TARGET, sigma_n2=SN2_POSITIVE)
def lmmse_min_power(access, D, a, sigma_w2, c, sigma_v2, sigma_n2, h_mean, h_var_re,
                    h_var_im, *, infeasible: str = "raise") -> np.ndarray:
    """No CSI: least total power with steady-state MSE ``<= D`` (a variant of (19) / (26)).
    Returns the real ``alpha`` (transmit ``beamformed(alpha, h_mean)``).
    """
    access = check_access(access)
    x, y = target_xy(D, a, sigma_w2)
    rho, tau, kap = lmmse_coefficients(a, sigma_w2, c, sigma_v2, h_mean, h_var_re, h_var_im)
    sn = _positive("sigma_n2", sigma_n2)
    alpha = general_min_power(access, rho, tau, kap, sn, x, y, infeasible="nan")
    if infeasible == "raise" and np.any(np.isnan(alpha)):
        total = np.sum(rho**2 / tau, axis=-1)
        raise InfeasibleError(
            f"target D = {float(np.max(D)):g} is infeasible without CSI ({access}): sum_i "
            f"rho_i^2 / tau_i = {float(np.min(total)):.6g} must exceed (a^2 D + sigma_w2 - D) "
            f"/ (D (D - sigma_w2)) = {float(np.max(x / y)):.6g}")
    return alpha


@_doc(returns=ALPHA, sigma_n2=SN2_POSITIVE)
def lmmse_min_error(access, gamma_total, a, sigma_w2, c, sigma_v2, sigma_n2, h_mean, h_var_re,
                    h_var_im) -> np.ndarray:
    """No CSI: least steady-state MSE with total power ``<= gamma_total`` (a variant of (23) /
    (28)). Returns the real ``alpha``.
    """
    access = check_access(access)
    rho, tau, kap = lmmse_coefficients(a, sigma_w2, c, sigma_v2, h_mean, h_var_re, h_var_im)
    sn = _positive("sigma_n2", sigma_n2)
    return general_max_snr(access, rho, tau, kap, sn, gamma_total)


@_doc(
      returns=("xp, P : numpy.ndarray", "Predictions ``(..., steps + 1)`` and variances "
                                        "``(steps + 1,)``."),
      Cbar="``(d,)``.", Rbar="``(d, d)``, symmetric positive definite.",
      P0=("float, optional", "``P_{0|-1} >= 0`` (default the stationary variance)."))
def lmmse_filter(z, a, sigma_w2, Cbar, Rbar, *, P0=None):
    """Run the linear MMSE estimator (32) (corrected) on observations ``z`` ``(..., steps, d)``.

    ``Cbar`` ``(d,)``, ``Rbar`` ``(d, d)`` from :func:`lmmse_matrices`. Starts from
    ``xhat_{0|-1} = 0``, ``P_{0|-1} = P0`` (default the stationary variance). Returns the
    predictions ``xhat_{k|k-1}`` ``(..., steps + 1)`` and their variances ``P_{k|k-1}``
    ``(steps + 1,)``. The printed (32) lacks ``+ sigma_w2`` in the time update and ``Cbar
    P_{k+1|k}`` at the end of the measurement update.
    """
    a = float(check_a(a))
    sw = float(_nonneg("sigma_w2", sigma_w2, "a variance"))
    z = _finite("z", z)
    C = _finite("Cbar", Cbar)
    R = _covariance("Rbar", Rbar, definite=True)
    if C.shape != (R.shape[0],) or z.ndim < 2 or z.shape[-1] != C.shape[0]:
        raise ValueError(f"Cbar must be ({R.shape[0]},) as Rbar and z shaped (..., steps, "
                         f"{R.shape[0]}); got Cbar {C.shape}, z {z.shape}")
    if P0 is not None:
        P0 = float(_nonneg("P0", P0, "a variance"))
    w = np.linalg.solve(R, C)  # Rbar^{-1} Cbar
    S = float(C @ w)
    steps = z.shape[-2]
    P = np.empty(steps + 1)
    P[0] = sw / (1 - a**2) if P0 is None else P0
    xp = np.zeros(z.shape[:-1][:-1] + (steps + 1,))
    for k in range(steps):
        gain = P[k] / (1.0 + P[k] * S)  # P_{k|k}; the gain is P_{k|k} Cbar^T Rbar^{-1}
        innov = z[..., k, :] - xp[..., k, None] * C
        xf = xp[..., k] + gain * (innov @ w)
        xp[..., k + 1] = a * xf
        P[k + 1] = a**2 * gain + sw
    return xp, P


@_doc(returns=("x, xhat_pred, P : numpy.ndarray", ""), sigma_n2=SN2_POSITIVE)
def simulate_nocsi(rng: np.random.Generator, n: int, steps: int, access, alpha_t, a, sigma_w2,
                   c, sigma_v2, sigma_n2, h_mean, h_var_re, h_var_im):
    """Simulate ``n`` independent runs of the system, the fading channels and the receiver noise
    without CSI, and run :func:`lmmse_filter` on them. Returns ``(x, xhat_pred, P)``: states
    and predictions ``(n, steps)`` and the filter's variances ``(steps,)`` (``x_0`` stationary).

    Channels ``h~_{i,k} = h_mean_i + sqrt(h_var_re_i) N + j sqrt(h_var_im_i) N'``, i.i.d. over
    time; receiver noise with ``sigma_n2`` in each of its real and imaginary parts.
    """
    access = check_access(access)
    if not isinstance(rng, np.random.Generator):
        raise ValueError(f"rng must be a numpy.random.Generator, got {rng!r}")
    n = _integer("n", n, 1)
    steps = _integer("steps", steps, 1)
    a_ = float(check_a(a))
    sw = float(_nonneg("sigma_w2", sigma_w2, "a variance"))
    C, R = lmmse_matrices(access, alpha_t, a, sigma_w2, c, sigma_v2, sigma_n2, h_mean,
                          h_var_re, h_var_im)
    c = np.atleast_1d(np.asarray(c, dtype=float))
    M = c.shape[-1]
    sv = np.broadcast_to(np.asarray(sigma_v2, float), (M,))
    sn = float(sigma_n2)
    x = np.empty((n, steps))
    x[:, 0] = rng.standard_normal(n) * np.sqrt(sw / (1 - a_**2))
    for k in range(1, steps):
        x[:, k] = a_ * x[:, k - 1] + rng.standard_normal(n) * np.sqrt(sw)
    y = c * x[..., None] + rng.standard_normal((n, steps, M)) * np.sqrt(sv)
    hr = np.real(h_mean) + np.sqrt(h_var_re) * rng.standard_normal((n, steps, M))
    hi = np.imag(h_mean) + np.sqrt(h_var_im) * rng.standard_normal((n, steps, M))
    g = np.asarray(alpha_t, dtype=complex) * (hr + 1j * hi) * y
    if access == "multi-access":
        zc = g.sum(-1) + (rng.standard_normal((n, steps))
                          + 1j * rng.standard_normal((n, steps))) * np.sqrt(sn)
        z = np.stack([zc.real, zc.imag], axis=-1)
    else:
        zc = g + (rng.standard_normal((n, steps, M))
                  + 1j * rng.standard_normal((n, steps, M))) * np.sqrt(sn)
        z = np.stack([zc.real, zc.imag], axis=-1).reshape(n, steps, 2 * M)
    xp, P = lmmse_filter(z, a_, sw, C, R)
    return x, xp[:, :steps], P[:steps]
