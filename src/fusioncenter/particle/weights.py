"""The functions on a weighted particle set, in NumPy: log weights normalized, the effective
sample size, the weighted mean and covariance, and systematic resampling (offspring counts,
ancestors, the gather).

They work on any leading axes (``logw (..., P)``, ``x (..., P, d)``), row by row: a row's
result never depends on the other rows of the batch. They check their inputs. The loop
:func:`fusioncenter.particle.loop.run_filter` does the same work in compiled passes
(:mod:`fusioncenter._compiled.weights`, :mod:`fusioncenter._compiled.resampling`); these are the
reference its tests compare it with, and the functions the chapters call.
"""

from __future__ import annotations

import numpy as np

from fusioncenter._docstrings import Glossary
from fusioncenter._validate import finite as _finite

__all__ = ["log_normalize", "ess", "systematic_counts", "systematic_resample", "resample",
           "weighted_mean", "weighted_mean_cov"]


#: The arguments of the weight and resampling functions, by name.
_doc = Glossary("""
logw : array_like
    Log weights ``(..., P)``, not necessarily normalized; ``-inf`` (weight zero) allowed, NaN
    and ``+inf`` not.
x : array_like
    Particles ``(..., P, d)``.
u : array_like
    One uniform in ``[0, 1)`` per row, shaped like the leading axes ``(...)`` of ``logw``.
idx : array_like
    Ancestor indices ``(..., P)``, integers in ``[0, P)``.
""", raises="""
ValueError
    If ``logw`` has no particle on its last axis or holds NaN or ``+inf``.
""")
#: The ``Raises`` section of the functions that also take resampling uniforms.
_RAISES_U = (("ValueError", "If ``logw`` has no particle on its last axis or holds NaN or "
                            "``+inf``, or ``u``\nis not one uniform in ``[0, 1)`` per row."),)



@_doc(returns=(("numpy.ndarray", "The normalized log weights ``(..., P)`` (uniform for a row "
                                 "without weight)."),
               ("numpy.ndarray", "``log sum exp logw`` per row ``(...)`` (``-inf`` for such a "
                                 "row).")))
def log_normalize(logw):
    """Normalize log weights over the last axis: ``(logw - log sum exp logw, log sum exp logw)``.

    The maximum is subtracted before exponentiating, so weights never overflow and at least one
    weight per row is exactly representable. A row whose weights are all zero (all ``-inf``: no
    particle is compatible with the data) has no normalization; it is returned as *uniform*
    weights with ``log_sum = -inf``, so the caller can detect and count the collapse (the filter
    then simply ignores that step's data for that trial).
    """
    logw = np.asarray(logw, dtype=float)
    if logw.ndim < 1 or logw.shape[-1] < 1:
        raise ValueError(f"logw must have at least one particle on its last axis, got {logw.shape}")
    if np.any(np.isnan(logw)) or np.any(logw == np.inf):
        raise ValueError("logw must not contain NaN or +inf")
    mx = logw.max(axis=-1, keepdims=True)
    dead = mx == -np.inf
    mx_safe = np.where(dead, 0.0, mx)
    with np.errstate(divide="ignore"):
        lse = mx_safe + np.log(np.exp(logw - mx_safe).sum(axis=-1, keepdims=True))
    out = np.where(dead, -np.log(logw.shape[-1]), logw - np.where(dead, 0.0, lse))
    lse = np.where(dead, -np.inf, lse)
    return out, lse[..., 0]


@_doc(returns=("numpy.ndarray", "``(...)``, in ``[1, P]``."))
def ess(logw):
    """Effective sample size ``1 / sum_j w_j^2`` per row (weights normalized first), in [1, P]."""
    lw, _ = log_normalize(logw)
    return np.exp(-np.log(np.exp(2.0 * lw).sum(axis=-1)))


def _check_u(u, lead: tuple[int, ...]) -> np.ndarray:
    u = np.asarray(u, dtype=float)
    if u.shape != lead:
        raise ValueError(f"u must have one uniform per row, shape {lead}, got {u.shape}")
    if np.any((u < 0) | (u >= 1)) or not np.all(np.isfinite(u)):
        raise ValueError("u must lie in [0, 1)")
    return u


@_doc(returns=("numpy.ndarray", "``int64 (..., P)``; every row sums to ``P``."), raises=_RAISES_U)
def systematic_counts(logw, u) -> np.ndarray:
    """Number of offspring of each particle under systematic resampling, ``int64 (..., P)``.

    Row ``b`` places the ``P`` points ``(u_b + i) / P``, ``i = 0..P-1``, on the cumulative
    normalized weights ``c_j``; particle ``j`` gets the points in ``[c_{j-1}, c_j)``:
    ``count_j = ceil(P c_j - u) - ceil(P c_{j-1} - u)`` (with ``c_{-1} = 0`` and ``c_{P-1} = 1``
    set exactly, so every row's counts sum to ``P``). ``E[count_j] = P w_j`` for ``u ~ U[0, 1)``
    (unbiased), and ``|count_j - P w_j| < 1``. Rows are computed independently of each other
    (sequential ``cumsum`` within a row), so the result of a row does not depend on which other
    rows are in the batch.
    """
    lw, _ = log_normalize(logw)
    u = _check_u(u, lw.shape[:-1])
    return _counts(np.exp(lw), u)


def _counts(w, u) -> np.ndarray:
    """Systematic offspring counts from *normalized* weights ``w (..., P)``; no checks."""
    P = w.shape[-1]
    c = np.cumsum(w, axis=-1)
    c /= c[..., -1:]
    c[..., -1] = 1.0
    edges = np.ceil(P * c - u[..., None])
    return np.diff(edges, axis=-1, prepend=0.0).astype(np.int64)


@_doc(returns=("numpy.ndarray", "``int64 (..., P)``, non-decreasing within each row."),
      raises=_RAISES_U)
def systematic_resample(logw, u) -> np.ndarray:
    """Ancestor indices ``int64 (..., P)`` of systematic resampling (see :func:`systematic_counts`).

    Within each row the indices are non-decreasing. Vectorized: one ``np.repeat`` over all rows
    (every row's counts sum to ``P``, so the flat result splits back into rows).
    """
    counts = systematic_counts(logw, u)
    P = counts.shape[-1]
    flat = counts.reshape(-1, P)
    idx = np.repeat(np.tile(np.arange(P), flat.shape[0]), flat.ravel())
    return idx.reshape(counts.shape)


@_doc(returns=("numpy.ndarray", "The selected particles ``(..., K, d)``, a new array."),
      raises=(("ValueError", "If ``x`` is not ``(..., P, d)``, ``idx`` is not an integer array "
                             "whose leading axes\nmatch ``x``'s, or an index lies outside "
                             "``[0, P)`` (negative indices are not\nwrapped around)."),))
def resample(x, idx) -> np.ndarray:
    """Select particles row by row: ``out[..., j, :] = x[..., idx[..., j], :]``."""
    x = np.asarray(x)
    idx = np.asarray(idx)
    if x.ndim < 2:
        raise ValueError(f"x must be particles (..., P, d), got shape {x.shape}")
    if idx.dtype.kind not in "iu":
        raise ValueError(f"idx must be an integer array of ancestor indices, got dtype "
                         f"{idx.dtype}")
    if idx.ndim < 1 or idx.shape[:-1] != x.shape[:-2]:
        raise ValueError(f"idx must have shape {(*x.shape[:-2], 'K')} (the leading axes of x "
                         f"{x.shape}), got {idx.shape}")
    P = x.shape[-2]
    if idx.size and (idx.min() < 0 or idx.max() >= P):
        raise ValueError(f"idx must lie in [0, {P}) (ancestor indices of {P} particles), got "
                         f"values in [{idx.min()}, {idx.max()}]")
    return np.take_along_axis(x, idx[..., None], axis=-2)


def _weighted_args(x, logw) -> np.ndarray:
    """``x (..., P, d)`` finite and matching ``logw (..., P)`` (the weighted statistics)."""
    x = _finite("x", x)
    lw = tuple(np.shape(logw))
    ok = x.ndim >= 2 and x.shape[-2] == lw[-1]
    if ok:
        try:
            np.broadcast_shapes(x.shape[:-2], lw[:-1])
        except ValueError:
            ok = False
    if not ok:
        raise ValueError(f"x must have shape {(*lw, 'd')} (logw is {tuple(lw)}: (..., P)), got "
                         f"{x.shape}")
    return x


@_doc(returns=("numpy.ndarray", "``(..., d)``."))
def weighted_mean(x, logw) -> np.ndarray:
    """``sum_j w_j x_j`` per row: ``x (..., P, d)``, ``logw (..., P)`` -> ``(..., d)``."""
    lw, _ = log_normalize(logw)
    x = _weighted_args(x, logw)
    w = np.exp(lw)
    return (w[..., None, :] @ x)[..., 0, :]


@_doc(returns=(("numpy.ndarray", "The mean ``(..., d)``."),
               ("numpy.ndarray", "The covariance ``(..., d, d)``, symmetric.")))
def weighted_mean_cov(x, logw) -> tuple[np.ndarray, np.ndarray]:
    """Weighted mean ``(..., d)`` and covariance ``sum_j w_j (x_j - m)(x_j - m)^T`` ``(..., d, d)``.

    The covariance is the plug-in (biased, normalized by ``sum w = 1``) estimate, symmetrized.
    """
    lw, _ = log_normalize(logw)
    x = _weighted_args(x, logw)
    w = np.exp(lw)
    mean = (w[..., None, :] @ x)[..., 0, :]
    dev = x - mean[..., None, :]
    cov = np.swapaxes(dev * w[..., None], -1, -2) @ dev
    cov = 0.5 * (cov + np.swapaxes(cov, -1, -2))
    return mean, cov
