"""The nonlinear model's measurement and its EKF, unchecked (zheng2014 Section VII.C): the
amplitudes (42) from squared distances or positions, their gradient and the EKF covariance
recursion, as the filters call them on arrays they have already checked (the sensors' EKFs of
:func:`fusioncenter.censoring.nonlinear_model.local_ekf`, the fusion centre of
:mod:`fusioncenter.censoring.nonlinear`), in NumPy (not compiled).

The public, checked versions, where these are documented, are
:func:`~fusioncenter.censoring.nonlinear_model.amplitude_from_d2`,
:func:`~fusioncenter.censoring.nonlinear_model.amplitude`,
:func:`~fusioncenter.censoring.nonlinear_model.jacobian` and
:func:`~fusioncenter.censoring.nonlinear_model.ekf_covariance_step`; they call these, so a valid
call gives the same bits either way. ``sc`` and ``scenario`` are a
:class:`~fusioncenter.censoring.nonlinear_model.NonlinearScenario` (only its fields are used).
"""

from __future__ import annotations

import numpy as np

__all__ = ["amplitude_from_d2", "amplitude", "jacobian", "ekf_step"]


def amplitude_from_d2(sc, d2):
    """:func:`fusioncenter.censoring.nonlinear_model.amplitude_from_d2`: ``sqrt(power / (1 +
    alpha d^n))`` from the squared distances, in place on ``d2`` (returned)."""
    if sc.exponent != 2.0:
        np.power(d2, sc.exponent / 2, out=d2)
    if sc.alpha != 1.0:
        d2 *= sc.alpha
    d2 += 1.0
    np.divide(sc.power, d2, out=d2)
    return np.sqrt(d2, out=d2)


def amplitude(scenario, pos) -> np.ndarray:
    """:func:`fusioncenter.censoring.nonlinear_model.amplitude` without the NaN check (the
    filters' own calls): ``h^i`` at the positions ``pos (..., 2)``, ``(..., N)``."""
    pos = np.asarray(pos, dtype=float)
    if pos.shape[-1:] != (2,):
        raise ValueError(f"pos must end in an (x, y) axis of length 2, got {pos.shape}")
    diff = pos[..., None, :] - scenario.positions  # (..., N, 2)
    d2 = np.einsum("...k,...k->...", diff, diff)
    return amplitude_from_d2(scenario, d2)


def jacobian(scenario, x) -> np.ndarray:
    """:func:`fusioncenter.censoring.nonlinear_model.jacobian` without the finiteness check (the
    filters' own calls): ``g^i`` at the states ``x (..., 4)``, ``(..., N, 4)``."""
    x = np.asarray(x, dtype=float)
    if x.shape[-1:] != (4,):
        raise ValueError(f"x must end in a state axis of length 4, got {x.shape}")
    sc = scenario
    diff = x[..., None, [0, 2]] - sc.positions  # (..., N, 2)
    d2 = np.einsum("...k,...k->...", diff, diff)
    h = amplitude_from_d2(sc, d2.copy())
    coef = -0.5 * sc.alpha * sc.exponent * h**3 / sc.power
    if sc.exponent != 2.0:
        with np.errstate(divide="ignore", invalid="ignore"):
            dn = np.where(d2 > 0, d2 ** (sc.exponent / 2 - 1), 0.0)
        coef = coef * dn
    g = np.zeros((*diff.shape[:-1], 4))
    g[..., 0] = coef * diff[..., 0]
    g[..., 2] = coef * diff[..., 1]
    return g


def ekf_step(P, g, F, Q, r):
    """:func:`fusioncenter.censoring.nonlinear_model.ekf_covariance_step` without checks (the
    filters' own calls, where ``s > 0``): ``(P_pred, s, P_upd)``."""
    Pp = F @ P @ F.T + Q
    Pg = (Pp @ g[..., None])[..., 0]  # (..., d)
    s = np.einsum("...k,...k->...", g, Pg) + r
    w = Pg / s[..., None]
    A = np.eye(P.shape[-1]) - w[..., :, None] * g[..., None, :]
    Pu = A @ Pp @ np.swapaxes(A, -1, -2) + np.asarray(r)[..., None, None] * (
        w[..., :, None] * w[..., None, :])
    Pu = 0.5 * (Pu + np.swapaxes(Pu, -1, -2))
    return Pp, s, Pu
