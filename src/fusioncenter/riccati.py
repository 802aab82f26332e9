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

from fusioncenter import _validate as _v

__all__ = [
    "scalar_update",
    "scalar_step",
    "scalar_sequence",
    "scalar_steady_state",
    "measurement_update",
    "riccati_step",
    "riccati_sequence",
    "steady_state",
    "solve_psd",
    "singular",
    "PINV_RCOND",
]


def _nonneg(name: str, value) -> np.ndarray:
    return _v.nonneg(name, value, "it is a variance")


def _steps(steps) -> int:
    if isinstance(steps, bool):
        raise ValueError(f"steps must be a non-negative integer, got {steps!r}")
    try:
        ok = int(steps) == steps and steps >= 0
    except (TypeError, ValueError, OverflowError):
        ok = False
    if not ok:
        raise ValueError(f"steps must be a non-negative integer, got {steps!r}")
    return int(steps)


#: Below this a product of two floats has lost digits (subnormal range, with a margin).
_SMALL = np.finfo(float).tiny / np.finfo(float).eps


def _out(arr: np.ndarray):
    return arr[()] if arr.ndim == 0 else arr


# ---------------------------------------------------------------------------- scalar
def scalar_update(p, c, r):
    """Posterior variance after observing ``y = c x + v``: ``p r / (c^2 p + r)``.

    Written in this form (not ``p - p^2 c^2 / (c^2 p + r)``) to avoid cancellation; ``r = 0``
    with ``c != 0`` gives 0 (a noise-free measurement), ``c = 0`` gives ``p``. Where ``c^2 p``
    or ``p r`` overflow, the equivalent ``1 / (1/p + c^2/r)`` is used. Broadcasts like a ufunc.

    Parameters
    ----------
    p : array_like
        Prior variance(s), ``>= 0``.
    c : array_like
        Measurement gain(s), finite.
    r : array_like
        Measurement-noise variance(s), ``>= 0``.

    Returns
    -------
    float or numpy.ndarray
        The posterior variance(s), in ``[0, p]``.

    Raises
    ------
    ValueError
        If ``p`` or ``r`` is negative, or any argument is NaN or infinite.
    """
    p = _nonneg("p", p)
    c = _v.finite("c", c)
    r = _nonneg("r", r)
    with np.errstate(over="ignore"):
        c2 = c**2
        den = c2 * p + r
        num = p * r
    with np.errstate(invalid="ignore", divide="ignore"):
        # den = 0: p = 0, or c = 0 with r = 0 (no information): the posterior is p
        out = np.where(den > 0, num / np.where(den > 0, den, 1.0), p)
        bad = ~np.isfinite(out)
        if np.any(bad):  # overflow of c^2 p or p r: the harmonic form has no large products
            harm = 1.0 / (1.0 / p + c2 / r)
            out = np.where(bad, np.minimum(harm, p), out)
    return _out(out)


def scalar_step(p, a, q, c, r):
    """One Riccati step for a scalar state: ``a^2 * scalar_update(p, c, r) + q``.

    Parameters
    ----------
    p : array_like
        Prediction variance(s) ``p_{k|k-1}``, ``>= 0``.
    a : array_like
        State transition(s), finite.
    q : array_like
        Process-noise variance(s), ``>= 0``.
    c, r : array_like
        As in :func:`scalar_update`.

    Returns
    -------
    float or numpy.ndarray
        ``p_{k+1|k}``.

    Raises
    ------
    ValueError
        If an argument is NaN, infinite or (a variance) negative, or if the result overflows.
    """
    a = _v.finite("a", a)
    q = _nonneg("q", q)
    with np.errstate(over="ignore"):
        out = a**2 * scalar_update(p, c, r) + q
    return _v.finite_result("p_{k+1}", out, "a^2 p overflows the float range")[()]


def scalar_sequence(p0, a, q, c, r, steps: int) -> np.ndarray:
    """``[p_0, p_1, ..., p_steps]`` of the scalar recursion (broadcast over array arguments).

    Parameters
    ----------
    p0 : array_like
        Initial prediction variance(s), ``>= 0``.
    a, q, c, r : array_like
        As in :func:`scalar_step`.
    steps : int
        Number of steps, ``>= 0``.

    Returns
    -------
    numpy.ndarray
        Shaped ``(steps + 1, *broadcast_shape)``.

    Raises
    ------
    ValueError
        As :func:`scalar_step`; also if ``steps`` is not a non-negative integer.
    """
    steps = _steps(steps)
    p = np.asarray(_nonneg("p0", p0), dtype=float)
    out = [p]
    for _ in range(steps):
        p = np.asarray(scalar_step(p, a, q, c, r))
        out.append(p)
    return np.stack(np.broadcast_arrays(*out))


def scalar_steady_state(a, q, c, r):
    """Positive fixed point of :func:`scalar_step` (prediction variance).

    It is the positive root of ``c^2 p^2 + (r (1 - a^2) - q c^2) p - q r = 0`` (the stabilizing
    one). Limits: ``r = 0`` gives ``q`` (a noise-free measurement); ``q = 0`` gives 0 for
    ``|a| < 1`` and ``r (a^2 - 1) / c^2`` for ``|a| > 1``; ``c = 0`` (no information) gives
    ``q / (1 - a^2)``, which exists only for ``|a| < 1`` (for ``|a| >= 1`` the prediction
    variance diverges and there is no steady state: ``ValueError``). Where ``b^2``
    of the quadratic overflows, the root is computed with ``hypot`` (``c^2 = 1e160`` gives
    ``q``, not inf).

    Parameters
    ----------
    a, q : array_like
        As in :func:`scalar_step`.
    c, r : array_like
        As in :func:`scalar_update`.

    Returns
    -------
    float or numpy.ndarray
        The steady-state prediction variance(s), ``>= q``, always finite.

    Raises
    ------
    ValueError
        If an argument is NaN, infinite or (a variance) negative; if ``c = 0`` and
        ``|a| >= 1`` (no steady state: the prediction variance diverges); or if the result
        overflows (``c`` non-zero but ``c^2 / r`` below the float range with ``|a| >= 1``), or
        the steady state itself is beyond the float range (a documented limit: for ``|a| > 1``
        it is about ``q + (a^2 - 1) r / c^2``, e.g. ``a = 1e300`` gives ``1e600``; the message
        names ``a`` and gives the values).
    """
    a = _v.finite("a", a)
    q = _nonneg("q", q)
    c = _v.finite("c", c)
    r = _nonneg("r", r)
    with np.errstate(over="ignore", invalid="ignore", under="ignore", divide="ignore"):
        c2 = c**2
        tiny = (c2 == 0) & (c != 0)
        if np.any(tiny):  # c^2 underflows: only c^2 / r matters, use c = 1, r / c^2 instead
            rr = np.where(tiny, r / np.abs(np.where(tiny, c, 1.0)) / np.abs(
                np.where(tiny, c, 1.0)), r)
            c2 = np.where(tiny & np.isfinite(rr), 1.0, c2)  # r / c^2 = inf: no information
            r = np.where(tiny & np.isfinite(rr), rr, r)
        b = r * (1.0 - a**2) - q * c2
        disc = np.sqrt(b**2 + 4.0 * c2 * q * r)
        # b^2 or c^2 q r overflowed, or underflowed below the normal range: hypot has neither
        lim = _SMALL
        off = ~np.isfinite(disc) | ((b != 0) & (b * b < lim)) | ((c2 * q * r != 0)
                                                                 & (c2 * q * r < lim))
        if np.any(off):
            disc = np.where(off, np.hypot(b, 2.0 * np.sqrt(c2 * q * r)), disc)
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        # Stable root of the quadratic: avoid subtracting nearly equal numbers.
        root_pos_b = np.where(b > 0, 2.0 * q * r / np.where(b + disc > 0, b + disc, 1.0), 0.0)
        root_neg_b = np.where(c2 > 0, (disc - b) / (2.0 * np.where(c2 > 0, c2, 1.0)), 0.0)
        p = np.where(b > 0, root_pos_b, root_neg_b)
        if not np.all(np.isfinite(p) | (c2 == 0)):
            # c^2 or b overflowed: scale the quadratic by 1/c^2 (terms of order q and r/c^2)
            inv = 1.0 / c2
            bs = r * (1.0 - a**2) * inv - q
            ds = np.hypot(bs, 2.0 * np.sqrt(q * r * inv))
            ps = np.where(bs > 0, 2.0 * q * r * inv / np.where(bs + ds > 0, bs + ds, 1.0),
                          (ds - bs) / 2.0)
            p = np.where(np.isfinite(p), p, ps)
        no_obs = q / (1.0 - a**2)
        if np.any((c2 == 0) & (c != 0) & (np.abs(a) >= 1)):
            raise ValueError("c is too small for |a| >= 1: the information c^2 / r is below "
                             "the float range and the steady-state variance overflows")
        if np.any((c == 0) & (np.abs(a) >= 1)):
            raise ValueError("no steady state: c = 0 (no information) and |a| >= 1: the "
                             "prediction variance diverges")
        p = np.where(c2 > 0, p, no_obs)
    # anything else that is not finite is an overflow: the answer is not a float
    if not np.all(np.isfinite(p)):
        raise ValueError(f"a (with q, c, r) gives a steady-state variance beyond the float range "
                         f"(about q + (a^2 - 1) r / c^2 > 1.8e308 for |a| > 1): a = {_show(a)}, "
                         f"q = {_show(q)}, c = {_show(c)}, r = {_show(r)}")
    return _out(p)


def _show(x) -> str:
    """A short text of a scalar or array argument for a message."""
    x = np.asarray(x)
    return f"{float(x):.3g}" if x.ndim == 0 else np.array2string(x, precision=3, threshold=6)


# ---------------------------------------------------------------------------- matrix
def _as_matrix(name: str, value, ndim_min: int = 2) -> np.ndarray:
    arr = _v.finite(name, value)
    if arr.ndim < ndim_min:
        raise ValueError(f"{name} must be at least {ndim_min}-D (..., rows, cols), got {arr.shape}")
    return arr


def _check_square(name: str, arr: np.ndarray) -> None:
    if arr.shape[-1] != arr.shape[-2]:
        raise ValueError(f"{name} must be square in its last two axes, got {arr.shape}")


def _sym(m: np.ndarray) -> np.ndarray:
    return 0.5 * (m + np.swapaxes(m, -1, -2))


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
    R = _as_matrix("R", R)
    _check_square("R", R)
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
    return _sym(P - PCt @ Kt)


def _check_update_shapes(P, C, R) -> None:
    if C.shape[-1] != P.shape[-1]:
        raise ValueError(f"C has {C.shape[-1]} columns but P is {P.shape[-1]}x{P.shape[-1]}")
    if R.shape[-1] != C.shape[-2]:
        raise ValueError(f"R is {R.shape[-1]}x{R.shape[-1]} but C has {C.shape[-2]} rows")


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
        P, R = _as_matrix("P", P), _as_matrix("R", R)
        _check_square("P", P)
        _check_square("R", R)
    _v.nonempty("P", P)
    C = _as_matrix("C", C)
    _check_update_shapes(P, C, R)
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
    A = _as_matrix("A", A)
    _check_square("A", A)
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
        out = _sym(A @ post @ np.swapaxes(A, -1, -2) + Q)
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
    steps = _steps(steps)
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
    A = _as_matrix("A", A)
    C = _as_matrix("C", C)
    for name, arr in (("A", A), ("Q", Q), ("C", C), ("R", R)):
        if np.ndim(arr) != 2:
            raise ValueError(f"{name} must be a 2-D matrix for steady_state, got shape "
                             f"{np.shape(arr)}")
    Q = _v.covariance("Q", Q)
    R = _v.covariance("R", R)
    _check_square("A", A)
    _v.nonempty("A", A)
    if Q.shape != A.shape:
        raise ValueError(f"Q must be {A.shape[0]}x{A.shape[0]} (as A), got {Q.shape}")
    _check_update_shapes(A, C, R)
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
    P = _sym(P)
    try:
        _v.covariance("the Riccati solution", P)
    except ValueError as exc:
        raise ValueError(f"no stabilizing Riccati solution for these (A, Q, C, R): {exc}") from exc
    return P
