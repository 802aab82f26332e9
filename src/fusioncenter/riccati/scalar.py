"""The scalar Riccati recursion and its steady state: one state, one measurement.

Prediction variance ``p``, state transition ``a``, process noise ``q``, measurement gain ``c``,
measurement noise ``r``: :func:`scalar_update` (the measurement update), :func:`scalar_step`
(one step ``p_{k|k-1} -> p_{k+1|k}``), :func:`scalar_sequence` (a run of steps) and
:func:`scalar_steady_state` (the positive fixed point in closed form). Every function
broadcasts like a NumPy ufunc and stays accurate where the obvious formulas overflow or cancel.
"""

from __future__ import annotations

import numpy as np

from fusioncenter import _validate as _v
from fusioncenter.riccati._args import steps_arg

__all__ = ["scalar_update", "scalar_step", "scalar_sequence", "scalar_steady_state"]


def _nonneg(name: str, value) -> np.ndarray:
    return _v.nonneg(name, value, "it is a variance")



#: Below this a product of two floats has lost digits (subnormal range, with a margin).
_SMALL = np.finfo(float).tiny / np.finfo(float).eps


def _out(arr: np.ndarray):
    return arr[()] if arr.ndim == 0 else arr



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
    steps = steps_arg(steps)
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
