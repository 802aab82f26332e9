"""The matrix Riccati recursion, one step at a time and batched: the measurement update
(:func:`measurement_update`, with the solve of a symmetric PSD system :func:`solve_psd` and the
test :func:`singular` for noise-free sensors), one step :func:`riccati_step` and a run of
steps :func:`riccati_sequence`.

Every argument may carry leading batch axes, broadcast together, so one call advances many
Monte Carlo paths at once (random ``C_k`` as in fading channels).
"""

from __future__ import annotations

import numpy as np

from fusioncenter import _validate as _v
from fusioncenter.riccati._args import (
    as_matrix,
    check_square,
    check_update_shapes,
    steps_arg,
    sym,
)

__all__ = ["PINV_RCOND", "singular", "solve_psd", "measurement_update", "riccati_step",
           "riccati_sequence"]


#: Relative threshold below which an eigenvalue of an innovation covariance counts as zero
#: when the noise covariance is singular (:func:`solve_psd` with ``singular=True``).
PINV_RCOND = 1e-10


def singular(R) -> bool:
    """Whether any matrix of a (batch of) symmetric PSD ``R`` is singular, i.e. has an
    eigenvalue ``<= PINV_RCOND * max |R|`` (a noise-free sensor, or a zero matrix).

    Parameters
    ----------
    R : numpy.ndarray
        ``(..., m, m)``, symmetric PSD (only finiteness and shape are checked).

    Returns
    -------
    bool

    Raises
    ------
    ValueError
        If ``R`` is not finite or not a (stack of) square matrices.
    """
    R = as_matrix("R", R)
    check_square("R", R)
    if R.size == 0:
        return False
    d = np.diagonal(R, axis1=-2, axis2=-1)
    scale = np.abs(R).max(axis=(-2, -1))
    if not np.any(R - d[..., None] * np.eye(R.shape[-1])):  # diagonal: the eigenvalues are d
        return bool(np.any(d.min(axis=-1) <= PINV_RCOND * scale))
    low = np.linalg.eigvalsh(R)[..., 0]
    return bool(np.any(low <= PINV_RCOND * scale))


def solve_psd(S, B, *, singular: bool = False, check: bool = True) -> np.ndarray:
    """``S^{-1} B`` for a (batch of) symmetric PSD ``S``, e.g. an innovation covariance.

    With ``singular=False`` this is ``numpy.linalg.solve``, falling back to the pseudo-inverse
    where ``S`` is exactly singular. With ``singular=True`` (the noise covariance is singular,
    see :func:`singular`) it is the pseudo-inverse with eigenvalues below ``PINV_RCOND`` times
    the largest treated as zero: noise-free sensors measuring directions the prior already knows
    up to rounding, the limit of the Kalman gain as ``R -> 0``. Where the diagonal of ``S``
    spans more than ``1 / PINV_RCOND`` the rows and columns are first scaled to a unit diagonal,
    so that a well-determined small direction is not taken for a zero one. Finiteness and
    shapes are always checked; with ``check=True`` (default) also that ``S`` is symmetric PSD
    (the library's own callers, whose ``S = C P C^T + R`` comes from checked covariances, pass
    ``check=False``: the eigenvalue test would cost as much as the solve).

    Parameters
    ----------
    S : numpy.ndarray
        ``(..., m, m)``, symmetric positive semi-definite.
    B : numpy.ndarray
        ``(..., m, k)``.
    singular : bool
        Use the thresholded pseudo-inverse.
    check : bool
        Check that ``S`` is symmetric PSD (tolerances of
        :func:`fusioncenter._validate.covariance`).

    Returns
    -------
    numpy.ndarray
        ``(..., m, k)``.

    Raises
    ------
    ValueError
        If ``S`` or ``B`` is text or has a NaN or infinite entry, ``S`` is not a (stack of)
        square matrices, ``B`` does not have ``m`` rows, or (``check=True``) ``S`` is not
        symmetric PSD.
    """
    if check:
        S = _v.covariance("S", S, batch=True)
        B = _v.finite("B", B)
    elif not (np.all(np.isfinite(S)) and np.all(np.isfinite(B))):
        raise ValueError("S and B must be finite (an innovation covariance and its right-hand "
                         "side)")
    if np.ndim(S) < 2 or np.shape(S)[-1] != np.shape(S)[-2]:
        raise ValueError(f"S must be a (stack of) square matrices (..., m, m), got shape "
                         f"{np.shape(S)}")
    if np.ndim(B) < 2 or np.shape(B)[-2] != np.shape(S)[-1]:
        raise ValueError(f"B must be shaped (..., m, k) with m = {np.shape(S)[-1]} rows (S is "
                         f"{np.shape(S)[-1]}x{np.shape(S)[-1]}), got shape {np.shape(B)}")
    if singular:
        out = np.linalg.pinv(S, rcond=PINV_RCOND, hermitian=True) @ B
        return _rescaled(S, B, out)
    try:
        return np.linalg.solve(S, B)
    except np.linalg.LinAlgError:
        return np.linalg.pinv(S, rcond=PINV_RCOND, hermitian=True) @ B


def _rescaled(S: np.ndarray, B: np.ndarray, out: np.ndarray) -> np.ndarray:
    """Redo the pseudo-inverse solve where the diagonal of ``S`` spans more than
    ``1 / PINV_RCOND`` (e.g. a noise-free sensor beside a silent one with ``delta = 1e12``):
    there the relative threshold would drop a direction that is well determined (a variance
    of 1.5 beside 1e12) and ignore its measurement. The rows and columns are scaled to a unit
    diagonal first (zero diagonal entries, directions known exactly, keep scale 1). Elsewhere
    ``out`` is returned unchanged."""
    d = np.diagonal(S, axis1=-2, axis2=-1)
    pos = d > 0
    big = np.where(pos, d, 0.0).max(axis=-1)
    small = np.where(pos, d, np.inf).min(axis=-1)
    wide = big > small / PINV_RCOND
    if not np.any(wide):
        return out
    sc = 1.0 / np.sqrt(np.where(pos, d, 1.0))  # (..., m)
    Ss = sc[..., :, None] * S * sc[..., None, :]
    redo = sc[..., :, None] * (np.linalg.pinv(Ss, rcond=PINV_RCOND, hermitian=True)
                               @ (sc[..., :, None] * B))
    return np.where(wide[..., None, None], redo, out) if np.ndim(wide) else redo


def _update(P: np.ndarray, C: np.ndarray, R: np.ndarray, sing: bool | None = None) -> np.ndarray:
    Ct = np.swapaxes(C, -1, -2)
    PCt = P @ Ct
    S = C @ PCt + R
    # K^T = S^{-1} (P C^T)^T, solved rather than inverted.
    Kt = solve_psd(S, np.swapaxes(PCt, -1, -2), singular=singular(R) if sing is None else sing,
                   check=False)
    return sym(P - PCt @ Kt)



def measurement_update(P, C, R, *, check: bool = True,
                       r_singular: bool | None = None) -> np.ndarray:
    """``P - P C^T (C P C^T + R)^{-1} C P`` (batched), symmetrized.

    ``R`` may be singular (noise-free sensors, ``R = 0``): where ``C P C^T + R`` is singular the
    pseudo-inverse gives the limit of the update as ``R -> 0``.

    A filter that propagates covariances it computed itself passes ``check=False`` after its
    first step: a computed covariance that is zero up to rounding (a state known exactly) has
    eigenvalues of order ``-1e-18`` *relative to the prior*, which no tolerance relative to the
    matrix itself can tell from an indefinite input. Shapes and finiteness are always checked.

    Parameters
    ----------
    P : array_like
        Prior covariance(s) ``(..., n, n)``, symmetric positive semi-definite.
    C : array_like
        Measurement matrix (matrices) ``(..., m, n)``, finite.
    R : array_like
        Measurement-noise covariance(s) ``(..., m, m)``, symmetric positive semi-definite.
    check : bool
        Check that ``P`` and ``R`` are symmetric PSD (default); ``False`` checks only shapes
        and finiteness.
    r_singular : bool, optional
        Whether ``R`` is singular (see :func:`singular`), if the caller knows it already (a
        diagonal ``R`` of known variances); computed when omitted.

    Returns
    -------
    numpy.ndarray
        The posterior covariance(s), the broadcast of the batch axes ``(..., n, n)``.

    Raises
    ------
    ValueError
        If an argument is not finite, has the wrong shape, ``P`` is ``0x0`` (no state), or
        ``P`` or ``R`` is not symmetric positive semi-definite (tolerances of
        :func:`fusioncenter._validate.covariance`).
    """
    if check:
        P = _v.covariance("P", P, batch=True)
        R = _v.covariance("R", R, batch=True)
    else:
        P, R = as_matrix("P", P), as_matrix("R", R)
        check_square("P", P)
        check_square("R", R)
    _v.nonempty("P", P)
    C = as_matrix("C", C)
    check_update_shapes(P, C, R)
    return _update(P, C, R, r_singular)


def riccati_step(P, A, Q, C, R, *, check: bool = True) -> np.ndarray:
    """One step ``P_{k+1|k} = A P_{k|k} A^T + Q``, ``P_{k|k}`` from :func:`measurement_update`.

    Parameters
    ----------
    P : array_like
        Prediction covariance(s) ``(..., n, n)``, symmetric PSD.
    A : array_like
        State transition(s) ``(..., n, n)``, finite.
    Q : array_like
        Process-noise covariance(s) ``(..., n, n)``, symmetric PSD.
    C, R : array_like
        As in :func:`measurement_update`.
    check : bool
        As in :func:`measurement_update` (for ``P`` only; ``Q`` and ``R`` are always checked).

    Returns
    -------
    numpy.ndarray
        ``P_{k+1|k}`` ``(..., n, n)``.

    Raises
    ------
    ValueError
        As :func:`measurement_update`; also if ``A`` or ``Q`` is not finite and square, ``Q``
        not PSD, or the result overflows.
    """
    A = as_matrix("A", A)
    check_square("A", A)
    Q = _v.covariance("Q", Q, batch=True)
    if not check:
        R = _v.covariance("R", R, batch=True)
    post = measurement_update(P, C, R, check=check)
    n = post.shape[-1]
    if A.shape[-1] != n or Q.shape[-1] != n:
        bad = "A" if A.shape[-1] != n else "Q"
        raise ValueError(f"{bad} must be {n}x{n} (P is {n}x{n}), got shape "
                         f"{(A if bad == 'A' else Q).shape}")
    with np.errstate(over="ignore", invalid="ignore"):
        out = sym(A @ post @ np.swapaxes(A, -1, -2) + Q)
    return _v.finite_result("P_{k+1|k}", out, "A P A^T overflows the float range")


def riccati_sequence(P0, A, Q, C, R, steps: int, *, time_varying: bool = False) -> np.ndarray:
    """``[P_0, ..., P_steps]`` stacked on a new leading axis.

    With ``time_varying=True``, ``C`` and ``R`` carry a leading time axis of length ``steps``
    (``C[k]``, ``R[k]`` are used at step ``k``), e.g. random measurement gains of a fading channel.

    Parameters
    ----------
    P0 : array_like
        Initial prediction covariance(s) ``(..., n, n)``, symmetric PSD.
    A, Q, C, R : array_like
        As in :func:`riccati_step` (``C``, ``R`` with a leading time axis if ``time_varying``).
    steps : int
        Number of steps, ``>= 0``.
    time_varying : bool
        Whether ``C`` and ``R`` carry a leading time axis.

    Returns
    -------
    numpy.ndarray
        Shaped ``(steps + 1, ..., n, n)``.

    Raises
    ------
    ValueError
        As :func:`riccati_step`; also if ``steps`` is not a non-negative integer or the time
        axis does not have length ``steps``.
    """
    steps = steps_arg(steps)
    P = _v.nonempty("P0", _v.covariance("P0", P0, batch=True))
    C = _v.finite("C", C)
    R = _v.finite("R", R)
    if time_varying:
        for name, arr in (("C", C), ("R", R)):
            if arr.ndim < 3 or arr.shape[0] != steps:
                raise ValueError(
                    f"time_varying=True needs {name} shaped (steps={steps}, ..., rows, cols), "
                    f"got {arr.shape}"
                )
    out = [P]
    for k in range(steps):
        Ck, Rk = (C[k], R[k]) if time_varying else (C, R)
        P = riccati_step(P, A, Q, Ck, Rk, check=k == 0)  # later P: computed here
        out.append(P)
    return np.stack(np.broadcast_arrays(*out))
