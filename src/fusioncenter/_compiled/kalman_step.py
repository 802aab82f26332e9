"""The Kalman step of :func:`fusioncenter.kalman.kalman_step` without its shape checks.

The per-step kernel of the library's Kalman-filter loops (:meth:`fusioncenter.kalman.
LinearGaussianModel.filter`, :func:`fusioncenter.event.event_kf_run`,
:func:`fusioncenter.comparison.kf_filter`), whose shapes are fixed and checked once at entry.
The public, checked step is :func:`fusioncenter.kalman.kalman_step`; it calls this one, so a
valid call gives the same bits either way. NumPy, not numba: it is a kernel by its place (the
inner step of the loops, inputs checked by its callers), and its matrices are small.
"""

from __future__ import annotations

import numpy as np

from fusioncenter import _validate as _v
from fusioncenter.riccati import measurement_update, singular, solve_psd

__all__ = ["kalman_step"]


def kalman_step(x, P, innov, C, R, A, Q, *, r_singular: bool | None = None,
                check: bool = False) -> tuple:
    """:func:`fusioncenter.kalman.kalman_step` without the shape checks (the filters' per-step
    kernel: their shapes are fixed at entry). The consistency check of a singular ``S`` stays
    (it costs nothing unless ``R`` is singular). Returns ``(x_post, P_post, x_pred, P_pred)``,
    the fields of :class:`fusioncenter.kalman.KalmanStep`."""
    if r_singular is None:
        r_singular = singular(R)
    # the covariance update first: with check=True it validates P and R (naming them) before
    # anything else uses them; it is a pure function of P, C, R, so the order changes no bit
    P_post = measurement_update(P, C, R, check=check, r_singular=r_singular)
    if P.ndim == 2 and np.ndim(C) == 2 and np.ndim(R) == 2:
        S = C @ P @ C.T + R
        K = solve_psd(S, C @ P, singular=r_singular, check=False).T  # R = 0: the R -> 0 limit
        if r_singular:  # S may be singular: the innovations must lie in its range
            _v.consistent("innov", S, innov.T, _scale(x, C, innov))
        x_post = x + innov @ K.T
        return x_post, P_post, x_post @ A.T, A @ P_post @ A.T + Q
    PCt = P @ np.swapaxes(C, -1, -2)  # (n, nx, m)
    S = C @ PCt + R
    w = solve_psd(S, innov[..., None], singular=r_singular, check=False)  # S^{-1} innov
    if r_singular:
        _v.consistent("innov", S, innov[..., None], _scale(x, C, innov))
    x_post = x + (PCt @ w)[..., 0]
    P_pred = A @ P_post @ A.T + Q
    return x_post, P_post, x_post @ A.T, 0.5 * (P_pred + np.swapaxes(P_pred, -1, -2))


def _scale(x, C, innov) -> float:
    """The magnitude of a step's measurements (the rounding scale of its innovations)."""
    return float(np.abs(innov).max(initial=0.0) + np.abs(x).max(initial=0.0)
                 * np.abs(C).max(initial=0.0))
