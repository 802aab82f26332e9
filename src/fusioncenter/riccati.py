"""Kalman-filter covariance (Riccati) recursions and steady states.

Model: ``x_{k+1} = A x_k + w_k``, ``y_k = C x_k + v_k`` with ``w ~ N(0, Q)``, ``v ~ N(0, R)``.
``P`` denotes the *prediction* covariance ``P_{k|k-1}`` unless a name says otherwise:

* measurement update  ``P_{k|k}   = P - P C^T (C P C^T + R)^{-1} C P``
  (equivalently ``(P^{-1} + C^T R^{-1} C)^{-1}`` by the matrix inversion lemma);
* time update         ``P_{k+1|k} = A P_{k|k} A^T + Q``;
* one Riccati step    ``P_{k+1|k} = A P A^T + Q - A P C^T (C P C^T + R)^{-1} C P A^T``.

The matrix functions accept a leading batch axis (or several) on every argument and broadcast
them, so one call advances many Monte Carlo paths at once (random ``C_k`` as in fading channels).
The scalar functions broadcast like NumPy ufuncs.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg

__all__ = [
    "scalar_update",
    "scalar_step",
    "scalar_sequence",
    "scalar_steady_state",
    "measurement_update",
    "riccati_step",
    "riccati_sequence",
    "steady_state",
]


def _nonneg(name: str, value) -> np.ndarray:
    arr = np.asarray(value, dtype=float)
    if np.any(~np.isfinite(arr)):
        raise ValueError(f"{name} must be finite")
    if np.any(arr < 0):
        raise ValueError(f"{name} must be non-negative (it is a variance)")
    return arr


# ---------------------------------------------------------------------------- scalar
def scalar_update(p, c, r):
    """Posterior variance after observing ``y = c x + v``: ``p r / (c^2 p + r)``.

    Written in this form (not ``p - p^2 c^2 / (c^2 p + r)``) to avoid cancellation; ``r = 0``
    with ``c != 0`` gives 0, ``c = 0`` gives ``p``.
    """
    p = _nonneg("p", p)
    r = _nonneg("r", r)
    c2 = np.asarray(c, dtype=float) ** 2
    den = c2 * p + r
    with np.errstate(invalid="ignore", divide="ignore"):
        out = np.where(den > 0, p * r / np.where(den > 0, den, 1.0), 0.0)
    return out[()] if out.ndim == 0 else out


def scalar_step(p, a, q, c, r):
    """One Riccati step for a scalar state: ``a^2 * scalar_update(p, c, r) + q``."""
    q = _nonneg("q", q)
    return np.asarray(a, dtype=float) ** 2 * scalar_update(p, c, r) + q


def scalar_sequence(p0, a, q, c, r, steps: int) -> np.ndarray:
    """``[p_0, p_1, ..., p_steps]`` of the scalar recursion (broadcast over array arguments)."""
    if int(steps) != steps or steps < 0:
        raise ValueError(f"steps must be a non-negative integer, got {steps!r}")
    p = np.asarray(_nonneg("p0", p0), dtype=float)
    out = [p]
    for _ in range(int(steps)):
        p = np.asarray(scalar_step(p, a, q, c, r))
        out.append(p)
    return np.stack(np.broadcast_arrays(*out))


def scalar_steady_state(a, q, c, r):
    """Positive fixed point of :func:`scalar_step` (prediction variance).

    It is the positive root of ``c^2 p^2 + (r (1 - a^2) - q c^2) p - q r = 0``. With ``c = 0``
    (no information) it is ``q / (1 - a^2)``, finite only for ``|a| < 1``.
    """
    a = np.asarray(a, dtype=float)
    q = _nonneg("q", q)
    r = _nonneg("r", r)
    c2 = np.asarray(c, dtype=float) ** 2
    b = r * (1.0 - a**2) - q * c2
    disc = np.sqrt(b**2 + 4.0 * c2 * q * r)
    with np.errstate(invalid="ignore", divide="ignore"):
        # Stable root of the quadratic: avoid subtracting nearly equal numbers.
        root_pos_b = np.where(b > 0, 2.0 * q * r / np.where(b + disc > 0, b + disc, 1.0), 0.0)
        root_neg_b = np.where(c2 > 0, (disc - b) / (2.0 * np.where(c2 > 0, c2, 1.0)), 0.0)
        p = np.where(b > 0, root_pos_b, root_neg_b)
        no_obs = q / (1.0 - a**2)
        p = np.where(c2 > 0, p, np.where(np.abs(a) < 1, no_obs, np.inf))
    return p[()] if p.ndim == 0 else p


# ---------------------------------------------------------------------------- matrix
def _as_matrix(name: str, value, ndim_min: int = 2) -> np.ndarray:
    arr = np.asarray(value, dtype=float)
    if arr.ndim < ndim_min:
        raise ValueError(f"{name} must be at least {ndim_min}-D (..., rows, cols), got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite")
    return arr


def _check_square(name: str, arr: np.ndarray) -> None:
    if arr.shape[-1] != arr.shape[-2]:
        raise ValueError(f"{name} must be square in its last two axes, got {arr.shape}")


def _sym(m: np.ndarray) -> np.ndarray:
    return 0.5 * (m + np.swapaxes(m, -1, -2))


def measurement_update(P, C, R) -> np.ndarray:
    """``P - P C^T (C P C^T + R)^{-1} C P`` (batched), symmetrized."""
    P = _as_matrix("P", P)
    C = _as_matrix("C", C)
    R = _as_matrix("R", R)
    _check_square("P", P)
    _check_square("R", R)
    if C.shape[-1] != P.shape[-1]:
        raise ValueError(f"C has {C.shape[-1]} columns but P is {P.shape[-1]}x{P.shape[-1]}")
    if R.shape[-1] != C.shape[-2]:
        raise ValueError(f"R is {R.shape[-1]}x{R.shape[-1]} but C has {C.shape[-2]} rows")
    Ct = np.swapaxes(C, -1, -2)
    PCt = P @ Ct
    S = C @ PCt + R
    # K^T = S^{-1} (P C^T)^T, solved rather than inverted.
    Kt = np.linalg.solve(S, np.swapaxes(PCt, -1, -2))
    return _sym(P - PCt @ Kt)


def riccati_step(P, A, Q, C, R) -> np.ndarray:
    """One step ``P_{k+1|k} = A P_{k|k} A^T + Q``, ``P_{k|k}`` from :func:`measurement_update`."""
    A = _as_matrix("A", A)
    Q = _as_matrix("Q", Q)
    _check_square("A", A)
    _check_square("Q", Q)
    post = measurement_update(P, C, R)
    return _sym(A @ post @ np.swapaxes(A, -1, -2) + Q)


def riccati_sequence(P0, A, Q, C, R, steps: int, *, time_varying: bool = False) -> np.ndarray:
    """``[P_0, ..., P_steps]`` stacked on a new leading axis.

    With ``time_varying=True``, ``C`` and ``R`` carry a leading time axis of length ``steps``
    (``C[k]``, ``R[k]`` are used at step ``k``), e.g. random measurement gains of a fading channel.
    """
    if int(steps) != steps or steps < 0:
        raise ValueError(f"steps must be a non-negative integer, got {steps!r}")
    P = _as_matrix("P0", P0)
    C = np.asarray(C, dtype=float)
    R = np.asarray(R, dtype=float)
    if time_varying:
        for name, arr in (("C", C), ("R", R)):
            if arr.ndim < 3 or arr.shape[0] != steps:
                raise ValueError(
                    f"time_varying=True needs {name} shaped (steps={steps}, ..., rows, cols), "
                    f"got {arr.shape}"
                )
    out = [P]
    for k in range(int(steps)):
        Ck, Rk = (C[k], R[k]) if time_varying else (C, R)
        P = riccati_step(P, A, Q, Ck, Rk)
        out.append(P)
    return np.stack(np.broadcast_arrays(*out))


def steady_state(A, Q, C, R) -> np.ndarray:
    """Stabilizing solution of the discrete algebraic Riccati equation (prediction form).

    Uses :func:`scipy.linalg.solve_discrete_are` on the dual system ``(A^T, C^T)``; raises
    ``ValueError`` when no stabilizing solution exists (e.g. (A, C) not detectable).
    """
    A = _as_matrix("A", A)
    Q = _as_matrix("Q", Q)
    C = _as_matrix("C", C)
    R = _as_matrix("R", R)
    for name, arr in (("A", A), ("Q", Q), ("C", C), ("R", R)):
        if arr.ndim != 2:
            raise ValueError(f"{name} must be a 2-D matrix for steady_state, got {arr.shape}")
    try:
        P = scipy.linalg.solve_discrete_are(A.T, C.T, Q, R)
    except (np.linalg.LinAlgError, ValueError) as exc:
        raise ValueError(f"no stabilizing Riccati solution for these (A, Q, C, R): {exc}") from exc
    return _sym(P)
