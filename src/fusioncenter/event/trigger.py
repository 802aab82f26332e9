"""The one-shot problem of mo2015's notes: the stochastic trigger, its send probability and the
exact posterior of the fusion centre (see :mod:`fusioncenter.event`)."""

from __future__ import annotations

import numpy as np
import scipy.optimize

from fusioncenter import _validate as _v
from fusioncenter import riccati
from fusioncenter._validate import covariance as _psd
from fusioncenter._validate import finite as _finite
from fusioncenter.event._common import fires, per_sensor

__all__ = ["trigger_probability", "communication_rate", "delta_for_rate", "sample_trigger",
           "posterior"]


# ----------------------------------------------------------------------------- validation
def _obs_matrix(C) -> np.ndarray:
    C = _finite("C", C)
    if C.ndim != 2 or C.shape[0] < 1 or C.shape[1] < 1:
        raise ValueError(f"C must be a 2-D matrix (m sensors, n states), got shape {C.shape}")
    return C


def _noise_variances(R, m: int) -> np.ndarray:
    """``r`` from ``R`` given as a vector ``(m,)`` (or scalar) or a diagonal ``(m, m)`` matrix."""
    arr = _finite("R", R)
    if arr.ndim == 2:
        if arr.shape != (m, m):
            raise ValueError(f"R must be ({m}, {m}) (C has {m} rows), got {arr.shape}")
        off = arr - np.diag(np.diag(arr))
        if np.any(off != 0):
            raise ValueError(
                "R must be diagonal: the stochastic trigger assumes independent sensor noises"
            )
        arr = np.diag(arr).copy()
    elif arr.ndim > 2:
        raise ValueError(f"R must be a vector ({m},) or a diagonal ({m}, {m}) matrix, "
                         f"got shape {arr.shape}")
    return per_sensor("R", arr, m, positive=False)


def _covariance(name: str, value, n: int | None = None) -> np.ndarray:
    """Symmetric positive semi-definite ``(..., n, n)`` (singular is fine: a known component);
    returned symmetrized."""
    arr = _finite(name, value)
    if arr.ndim < 2 or arr.shape[-1] != arr.shape[-2]:
        raise ValueError(f"{name} must be a square matrix (..., n, n), got shape {arr.shape}")
    if n is not None and arr.shape[-1] != n:
        raise ValueError(f"{name} must be {n}x{n} (C has {n} columns), got {arr.shape}")
    arr = _psd(name, arr, batch=True)
    return 0.5 * (arr + np.swapaxes(arr, -1, -2))


def _gamma(value, m: int) -> np.ndarray:
    arr = np.asarray(value)
    if arr.ndim < 1 or arr.shape[-1] != m:
        raise ValueError(f"gamma must have shape (..., {m}) (one entry per sensor), "
                         f"got {arr.shape}")
    if arr.dtype != bool:
        num = np.asarray(arr, dtype=float)
        if not np.all((num == 0) | (num == 1)):
            raise ValueError("gamma must contain only 0 and 1 (or booleans)")
        arr = num == 1
    return arr


def _state_mean(xbar, n: int) -> np.ndarray:
    if xbar is None:
        return np.zeros(n)
    arr = _finite("xbar", xbar)
    if arr.ndim < 1 or arr.shape[-1] != n:
        raise ValueError(f"xbar must have shape (..., {n}) (C has {n} columns), got {arr.shape}")
    return arr


# ----------------------------------------------------------------------------- closed forms
def trigger_probability(s, delta, mu=0.0):
    """Probability that a sensor with ``y ~ N(mu, s)`` sends: ``1 - E exp(-y^2 / (2 delta))``.

    ``E exp(-y^2/(2 delta)) = sqrt(delta / (delta + s)) exp(-mu^2 / (2 (delta + s)))``; computed as
    ``-expm1(-log1p(s/delta)/2 - mu^2/(2 (delta + s)))`` so small rates keep full relative
    accuracy. Broadcasts like a ufunc; ``s >= 0``, ``delta > 0``.

    Parameters
    ----------
    s : array_like
        Variance of ``y``, ``>= 0``.
    delta : array_like
        Trigger parameter, ``> 0``.
    mu : array_like
        Mean of ``y``.

    Returns
    -------
    float or numpy.ndarray
        The send probability, in ``[0, 1]``.

    Raises
    ------
    ValueError
        If an argument is NaN or infinite, ``s < 0`` or ``delta <= 0``.
    """
    s = _finite("s", s)
    delta = _finite("delta", delta)
    mu = _finite("mu", mu)
    if np.any(s < 0):
        raise ValueError("s must be non-negative (a variance)")
    if np.any(delta <= 0):
        raise ValueError("delta must be positive")
    with np.errstate(over="ignore"):  # s / delta or mu^2 overflows: the probability is 1
        out = -np.expm1(-0.5 * np.log1p(s / delta) - mu**2 / (2.0 * (delta + s)))
    return out[()] if out.ndim == 0 else out


def communication_rate(Sigma, C, R, delta, xbar=None) -> np.ndarray:
    """``P(gamma_i = 1)`` for each sensor, shape ``(m,)``.

    ``y_i ~ N(a_i xbar, r_i + a_i Sigma a_i^T)`` and :func:`trigger_probability`. With
    ``xbar = None`` (zero mean) this is the notes'
    ``1 - 1/sqrt(1 + (r_i + a_i Sigma a_i^T)/delta_i)``.
    ``R``: vector ``(m,)`` or diagonal ``(m, m)``; ``delta``: ``(m,)`` or a scalar.

    Parameters
    ----------
    Sigma : array_like
        Prior covariance of ``x`` ``(n, n)``, symmetric PSD (singular allowed).
    C : array_like
        Rows ``a_i`` ``(m, n)``.
    R : array_like
        Noise variances ``(m,)`` or a diagonal ``(m, m)``, ``>= 0``.
    delta : array_like
        Trigger parameters ``(m,)`` or a scalar, ``> 0``.
    xbar : array_like, optional
        Prior mean ``(n,)`` (default 0).

    Returns
    -------
    numpy.ndarray
        ``(m,)`` send probabilities in ``[0, 1]``.

    Raises
    ------
    ValueError
        Naming the argument that is not finite, of the wrong shape, not a covariance, a negative
        variance, a non-positive ``delta`` or a non-diagonal ``R``.
    """
    C = _obs_matrix(C)
    m, n = C.shape
    Sigma = _covariance("Sigma", Sigma, n)
    if Sigma.ndim != 2:
        raise ValueError(f"Sigma must be a single {n}x{n} matrix, got shape {Sigma.shape}")
    r = _noise_variances(R, m)
    delta = per_sensor("delta", delta, m, positive=True)
    xbar = _state_mean(xbar, n)
    if xbar.ndim != 1:
        raise ValueError(f"xbar must have shape ({n},), got {xbar.shape}")
    s = r + np.einsum("ij,jk,ik->i", C, Sigma, C)
    return np.asarray(trigger_probability(s, delta, C @ xbar), dtype=float).reshape(m)


def delta_for_rate(rate, s, mu=0.0):
    """The trigger parameter ``delta`` at which a sensor with ``y ~ N(mu, s)`` sends w.p. ``rate``.

    The send probability decreases strictly from 1 (``delta -> 0``) to 0 (``delta -> inf``)
    whenever ``s > 0`` or ``mu != 0``: with ``h(delta) = log P(silent) =
    log(delta/(delta+s))/2 - mu^2/(2(delta+s))``, ``h'(delta) = s/(2 delta (delta+s)) +
    mu^2/(2 (delta+s)^2) > 0``. So every ``rate`` in the open interval ``(0, 1)`` has exactly one
    ``delta``.

    * ``mu = 0``: closed form ``delta = s / ((1 - rate)^{-2} - 1) = s (1-rate)^2 / (rate (2-rate))``
      (the second form avoids cancellation).
    * ``mu != 0``: :func:`scipy.optimize.brentq` on ``log delta``, bracketed by (``q = 1 - rate``,
      ``L = log q``) ``lo = max(s q^2/(1-q^2), mu^2/(-2L) - s)`` where ``h <= L`` (each term alone
      already gives ``h <= L``, and ``h`` increases), and ``hi = max(s q/(1-q), mu^2/(-L))``
      where each of the two terms of ``h`` is ``>= L/2``, so ``h(hi) >= L``.

    Broadcasts over ``rate``, ``s``, ``mu``.

    Parameters
    ----------
    rate : array_like
        Target send probabilities in ``(0, 1)``.
    s : array_like
        Variances of ``y``, ``>= 0``.
    mu : array_like
        Means of ``y``.

    Returns
    -------
    float or numpy.ndarray
        ``delta > 0``.

    Raises
    ------
    ValueError
        If an argument is NaN or infinite, ``rate`` is outside ``(0, 1)``, ``s < 0``, or
        ``s = mu = 0`` (no ``delta`` gives a positive rate); or if ``rate`` is so small that
        the ``delta`` it needs exceeds the float range (``delta ~ s / (2 rate)``: a documented
        limit, e.g. ``rate = 1e-300`` with ``s = 1e10``).
    """
    rate = _finite("rate", rate)
    s = _finite("s", s)
    mu = _finite("mu", mu)
    if np.any((rate <= 0) | (rate >= 1)):
        raise ValueError(f"rate must lie in the open interval (0, 1), got {rate}")
    if np.any(s < 0):
        raise ValueError("s must be non-negative (a variance)")
    rate, s, mu = np.broadcast_arrays(rate, s, mu)
    if np.any((s == 0) & (mu == 0)):
        raise ValueError("s and mu are both 0: y = 0 never triggers, no delta gives that rate")
    with np.errstate(over="ignore"):
        out = s * (1.0 - rate) ** 2 / (rate * (2.0 - rate))
    if np.any(~np.isfinite(out) & (mu == 0)):
        raise ValueError(f"rate is too small for s: the delta it needs (s (1 - rate)^2 / "
                         f"(rate (2 - rate))) exceeds the float range, got rate = {rate!r}, "
                         f"s = {s!r}")
    out = np.array(out, dtype=float)
    for idx in np.ndindex(out.shape):
        if mu[idx] != 0:
            out[idx] = _delta_for_rate_mu(float(rate[idx]), float(s[idx]), float(mu[idx]))
    return out[()] if out.ndim == 0 else out


def _delta_for_rate_mu(rate: float, s: float, mu: float) -> float:
    q = 1.0 - rate
    L = np.log1p(-rate)
    # 1 - q^2 and 1 - q vanish in floating point for rate < 1.1e-16 (q rounds to 1): use the
    # exact rate (2 - rate) and rate there (elsewhere the same bits as before)
    one_q2 = 1.0 - q * q
    one_q = 1.0 - q
    with np.errstate(over="ignore"):
        lo = max(s * q * q / (one_q2 if one_q2 > 0 else rate * (2.0 - rate)),
                 mu * mu / (-2.0 * L) - s)
        hi = max(s * q / (one_q if one_q > 0 else rate), mu * mu / (-L))
    if not np.isfinite(hi):
        raise ValueError(f"rate = {rate:.3g} is too small for s = {s:.3g}, mu = {mu:.3g}: the "
                         f"delta it needs exceeds the float range")

    def f(u: float) -> float:
        d = np.exp(u)
        return -0.5 * np.log1p(s / d) - mu * mu / (2.0 * (d + s)) - L

    a, b = np.log(lo), np.log(hi)
    fa, fb = f(a), f(b)
    if fa == 0.0:
        return lo
    if fb == 0.0:
        return hi
    if fa > 0 or fb < 0:  # cannot happen (see the bracket proof); guard against rounding
        a, b = a - 1.0, b + 1.0
    return float(np.exp(scipy.optimize.brentq(f, a, b, xtol=1e-15, rtol=4 * np.finfo(float).eps,
                                             maxiter=200)))


def sample_trigger(rng: np.random.Generator, y, delta) -> np.ndarray:
    """Draw the stochastic trigger for measurements ``y`` shaped ``(..., m)``; boolean ``gamma``.

    ``gamma_i = 1`` iff ``xi_i > exp(-y_i^2 / (2 delta_i))`` with a fresh ``xi_i ~ U[0, 1)`` for
    every entry of ``y``: the ``xi`` are independent across sensors, across the leading (time,
    trial) axes, and of ``x`` and the noises. The notes leave this implicit, but the closed-form
    posterior needs it (it makes ``gamma`` conditionally independent of ``x`` given ``y``, and the
    sensors' likelihoods factorize).

    Parameters
    ----------
    rng : numpy.random.Generator
        The source of the uniforms ``xi``.
    y : array_like
        Measurements ``(..., m)``, finite.
    delta : array_like
        ``(m,)`` or a scalar, ``> 0``.

    Returns
    -------
    numpy.ndarray
        Boolean ``gamma``, shaped like ``y``.

    Raises
    ------
    ValueError
        If ``rng`` is not a Generator, ``y`` is not finite or ``delta`` is not positive.
    """
    if not isinstance(rng, np.random.Generator):
        raise ValueError("rng must be a numpy.random.Generator")
    y = _finite("y", y)
    if y.ndim < 1:
        raise ValueError(f"y must have shape (..., m), got {y.shape}")
    delta = per_sensor("delta", delta, y.shape[-1], positive=True)
    return fires(rng.random(y.shape), y, delta)


def _posterior_core(xbar, Sigma, C, r, delta, gamma, y, *, check: bool = False):
    """Unvalidated, batched :func:`posterior` (``Sigma`` may be singular if the ``S`` are not;
    ``check=True``: a measurement must lie in the range of a singular ``S``)."""
    m = C.shape[0]
    noise = r + np.where(gamma, 0.0, delta)  # (..., m)
    Rk = noise[..., :, None] * np.eye(m)
    SCt = Sigma @ C.T  # (..., n, m)
    S = C @ SCt + Rk
    innov = np.where(gamma, y, 0.0) - xbar @ C.T  # (..., m): NaN in silent entries never used
    sing = riccati.singular(Rk)
    w = riccati.solve_psd(S, innov[..., None], singular=sing, check=False)
    if check and sing:
        scale = np.abs(np.where(gamma, y, 0.0)).max(initial=0.0) + np.abs(
            xbar @ C.T).max(initial=0.0)
        _v.consistent("y", S, innov[..., None], scale)
    xhat = xbar + (SCt @ w)[..., 0]
    P = riccati.measurement_update(Sigma, C, Rk, check=False)  # checked by the caller
    return xhat, P


def posterior(xbar, Sigma, C, R, delta, gamma, y):
    """``E(x | I)`` and ``Cov(x | I)`` for ``I = {gamma, gamma * y}`` (the notes' unified formula).

    ``xhat = xbar + Sigma C^T (C Sigma C^T + R + (I - Gamma) Delta)^{-1} (Gamma y - C xbar)`` and
    ``P = Sigma - Sigma C^T (C Sigma C^T + R + (I - Gamma) Delta)^{-1} C Sigma``.

    Shapes: ``C (m, n)``; ``R`` vector ``(m,)`` or diagonal ``(m, m)``; ``delta (m,)`` or a scalar;
    ``gamma``, ``y`` ``(..., m)``; ``xbar (..., n)``; ``Sigma (..., n, n)``. Leading axes broadcast
    together (one call scores a whole Monte Carlo sample); returns ``xhat (..., n)``,
    ``P (..., n, n)``. Entries of ``y`` where ``gamma = 0`` are ignored and may be NaN; where
    ``gamma = 1`` they must be finite.

    Parameters
    ----------
    xbar : array_like
        Prior means ``(..., n)``.
    Sigma : array_like
        Prior covariances ``(..., n, n)``, symmetric PSD (singular allowed: a known component).
    C : array_like
        ``(m, n)``.
    R : array_like
        Noise variances ``(m,)`` or diagonal ``(m, m)``, ``>= 0`` (0: a noise-free sensor).
    delta : array_like
        ``(m,)`` or a scalar, ``> 0``.
    gamma : array_like
        ``(..., m)`` of 0/1 or booleans.
    y : array_like
        ``(..., m)``; finite where ``gamma = 1``.

    Returns
    -------
    xhat : numpy.ndarray
        ``(..., n)``.
    P : numpy.ndarray
        ``(..., n, n)``, symmetric PSD, never above ``Sigma``.

    Raises
    ------
    ValueError
        Naming the argument that is not finite, of the wrong shape, not a covariance, or not
        0/1; naming ``y`` if a received measurement contradicts the model (a noise-free sensor,
        ``R_i = 0``, measuring a direction that ``Sigma`` says is known, ``c_i Sigma c_i^T =
        0``, with ``y_i != c_i xbar``: no posterior exists).
    """
    C = _obs_matrix(C)
    m, n = C.shape
    Sigma = _covariance("Sigma", Sigma, n)
    xbar = _state_mean(xbar, n)
    r = _noise_variances(R, m)
    delta = per_sensor("delta", delta, m, positive=True)
    gamma = _gamma(gamma, m)
    y = np.asarray(y, dtype=float)
    gamma, y = _v.finite_where(gamma, y, mismatch=f"y must have shape (..., {m}) matching gamma "
                               f"{gamma.shape}, got {y.shape}",
                               missing="y must be finite where gamma is 1 (a received measurement)")
    return _posterior_core(xbar, Sigma, C, r, delta, gamma, y, check=True)
