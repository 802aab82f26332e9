"""The steady state of the matrix recursion: the stabilizing solution of the discrete algebraic
Riccati equation (``steady_state``), from SciPy's Schur solver or, where that fails near the
unit circle, the structured doubling algorithm."""

from __future__ import annotations

import numpy as np
import scipy.linalg

from fusioncenter import _validate as _v
from fusioncenter.riccati._args import as_matrix, check_square, check_update_shapes, sym

__all__ = ["steady_state"]


def _doubling(A, Q, C, R, max_iter: int = 200) -> np.ndarray | None:
    """The structured doubling algorithm for ``P = A P A^T - A P C^T (C P C^T + R)^{-1} C P A^T
    + Q`` (Chu, Fan and Lin 2005); ``None`` if ``R`` is singular, it does not converge, or the
    result is not a finite PSD fixed point (relative residual above ``1e-9``)."""
    n = A.shape[0]
    try:
        G = C.T @ np.linalg.solve(R, C)
    except np.linalg.LinAlgError:
        return None
    if not np.all(np.isfinite(G)):
        return None
    Ak, Gk, Hk = A.T.copy(), 0.5 * (G + G.T), Q.copy()
    eye = np.eye(n)
    with np.errstate(over="ignore", invalid="ignore"):
        for _ in range(max_iter):
            W = eye + Gk @ Hk
            try:
                WA = np.linalg.solve(W, Ak)
                WG = np.linalg.solve(W, Gk)
            except np.linalg.LinAlgError:
                return None
            H_new = Hk + Ak.T @ Hk @ WA
            Gk = Gk + Ak @ WG @ Ak.T
            Ak = Ak @ WA
            H_new = 0.5 * (H_new + H_new.T)
            if not np.all(np.isfinite(H_new)):
                return None
            done = np.abs(H_new - Hk).max() <= 1e-15 * np.abs(H_new).max()
            Hk = H_new
            if done:
                break
        else:
            return None
        P = Hk
        S = C @ P @ C.T + R
        nxt = A @ P @ A.T - A @ P @ C.T @ np.linalg.solve(S, C @ P @ A.T) + Q
    scale = np.abs(P).max()
    if not (np.all(np.isfinite(nxt)) and np.abs(nxt - P).max() <= 1e-9 * max(scale, 1e-300)):
        return None
    return P


def steady_state(A, Q, C, R) -> np.ndarray:
    """Stabilizing solution of the discrete algebraic Riccati equation (prediction form).

    Uses :func:`scipy.linalg.solve_discrete_are` on the dual system ``(A^T, C^T)``; where that
    fails (closed-loop eigenvalues near the unit circle: very little information, e.g. a random
    walk measured with noise variance ``1e12``) and ``R`` is non-singular, the structured
    doubling algorithm, whose result must be a fixed point to ``1e-9`` relative. Raises
    ``ValueError`` when no stabilizing solution exists (e.g. (A, C) not detectable). ``R`` may
    be singular (noise-free sensors) when the solver finds the solution.

    Parameters
    ----------
    A : array_like
        State transition ``(n, n)``, finite.
    Q : array_like
        Process-noise covariance ``(n, n)``, symmetric PSD.
    C : array_like
        Measurement matrix ``(m, n)``, finite.
    R : array_like
        Measurement-noise covariance ``(m, m)``, symmetric PSD.

    Returns
    -------
    numpy.ndarray
        The steady-state prediction covariance ``(n, n)``, symmetric PSD and finite.

    Raises
    ------
    ValueError
        If an argument is not finite or 2-D, has inconsistent shapes, ``A`` is ``0x0`` (no
        state), ``Q`` or ``R`` is not symmetric PSD, or no finite stabilizing PSD solution
        exists.
    """
    A = as_matrix("A", A)
    C = as_matrix("C", C)
    for name, arr in (("A", A), ("Q", Q), ("C", C), ("R", R)):
        if np.ndim(arr) != 2:
            raise ValueError(f"{name} must be a 2-D matrix for steady_state, got shape "
                             f"{np.shape(arr)}")
    Q = _v.covariance("Q", Q)
    R = _v.covariance("R", R)
    check_square("A", A)
    _v.nonempty("A", A)
    if Q.shape != A.shape:
        raise ValueError(f"Q must be {A.shape[0]}x{A.shape[0]} (as A), got {Q.shape}")
    check_update_shapes(A, C, R)
    try:
        P = scipy.linalg.solve_discrete_are(A.T, C.T, Q, R)
    except (np.linalg.LinAlgError, ValueError) as exc:
        # the Schur method fails where the closed loop has eigenvalues close to the unit circle
        # (little information, e.g. r = 1e12 on a random walk): the doubling algorithm converges
        # there (only for a non-singular R; the result is checked as a fixed point)
        P = _doubling(A, Q, C, R)
        if P is None:
            raise ValueError(f"no stabilizing Riccati solution for these (A, Q, C, R): "
                             f"{exc}") from exc
    P = sym(P)
    try:
        _v.covariance("the Riccati solution", P)
    except ValueError as exc:
        raise ValueError(f"no stabilizing Riccati solution for these (A, Q, C, R): {exc}") from exc
    return P
