"""The error arithmetic of the reading of zheng2014's results: conservative standard errors and
z-scores of combined estimates when only the marginal standard errors of the inputs are known.

The registry gives paired standard errors of single differences (for example CFoMD minus CFwMD,
and CFwMD minus all-send), not their covariances. A smooth function ``f`` of such estimates has
the delta-method variance ``g^T C g`` (``g`` the gradient, ``C`` the covariance); since
``|C_ij| <= se_i se_j`` (Cauchy-Schwarz), ``g^T C g <= (sum_i |g_i| se_i)^2`` whatever the
correlations. :func:`delta_bound` returns that bound: a conservative standard error;
:func:`conservative_z` is the z-score of a difference built on it."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

#: A difference counts as an ordering when it exceeds Z_ORDER (conservative) standard errors.
Z_ORDER = 4.0


def delta_bound(gradient: Sequence[float], stderr: Sequence[float]) -> float:
    """An upper bound on a delta-method standard error, valid for any correlation.

    Parameters
    ----------
    gradient : sequence of float
        The gradient ``g`` of the smooth function ``f`` at the estimates ``x``.
    stderr : sequence of float
        The marginal standard errors ``se_i`` of the estimates (finite, non-negative), one per
        entry of ``gradient``.

    Returns
    -------
    float
        ``sum_i |g_i| se_i``, which is at least ``sqrt(g^T C g)`` whatever the covariance ``C``
        of the estimates.

    Raises
    ------
    ValueError
        If the two are not 1-d of one length, or a standard error is negative or not finite.
    """
    g = np.asarray(gradient, dtype=float)
    s = np.asarray(stderr, dtype=float)
    if g.shape != s.shape or g.ndim != 1:
        raise ValueError(f"gradient and stderr must be 1-d of one length, got shapes {g.shape} "
                         f"and {s.shape}")
    if np.any(s < 0) or not np.all(np.isfinite(s)):
        raise ValueError("stderr must be finite and non-negative")
    return float(np.sum(np.abs(g) * s))


def conservative_z(a: float, sa: float, b: float, sb: float) -> float:
    """``(a - b) / (sa + sb)``: a z-score of ``a - b`` valid for any correlation.

    Parameters
    ----------
    a, b : float
        The two estimates.
    sa, sb : float
        Their standard errors.

    Returns
    -------
    float
        ``(a - b) / (sa + sb)`` (:func:`delta_bound` of the gradient ``(1, -1)``).
    """
    return (a - b) / (sa + sb)
