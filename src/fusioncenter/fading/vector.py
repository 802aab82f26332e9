"""A vector state seen by one scalar measurement (dey2009 Section 3.2).

:func:`vector_paths` / :func:`vector_mc` sample the random Riccati recursion (21) of the
covariance ``P_k``; :func:`vector_bound` is the bounding sequence ``Zbar_k`` of Theorem 3.3;
:func:`triu_to_symmetric` unpacks the sampled upper triangles.
"""

from __future__ import annotations

import functools

import numpy as np

from fusioncenter._validate import covariance as _covariance
from fusioncenter._validate import finite as _finite
from fusioncenter._validate import finite_result as _finite_result
from fusioncenter._validate import integer as _int
from fusioncenter._validate import nonneg as _nonneg
from fusioncenter._validate import positive as _positive
from fusioncenter.fading._common import (
    VARIANCE,
    check_channel,
    check_scalar,
    document,
    simulate_paths,
)

__all__ = ["vector_paths", "vector_mc", "vector_bound", "triu_to_symmetric"]


_doc = document.extend("""
sigma_v2 : float
    Measurement-noise variance, ``>= 0``.
c : array_like
    Measurement row ``(n,)``, finite.
""")


def _vector_args(A, c, Sigma_w, sigma_v2, sigma_n2, P0, steps):
    A = _finite("A", A)
    if A.ndim != 2 or A.shape[0] != A.shape[1]:
        raise ValueError(f"A must be a square matrix, got shape {A.shape}")
    if A.shape[0] == 0:
        raise ValueError("A must not be empty (a state of dimension 0 is not a model), got "
                         "shape (0, 0)")
    n = A.shape[0]
    c = _finite("c", c)
    if c.shape != (n,):
        raise ValueError(f"c must be a row of length {n} (as A), got shape {c.shape}")
    Sigma_w = _finite("Sigma_w", Sigma_w)
    P0 = _finite("P0", P0)
    for name, M in (("Sigma_w", Sigma_w), ("P0", P0)):
        if M.shape != (n, n):
            raise ValueError(f"{name} must be {n}x{n} (as A), got shape {M.shape}")
        _covariance(name, M)
    return (A, c, Sigma_w, check_scalar("sigma_v2", _nonneg("sigma_v2", sigma_v2, VARIANCE)),
            check_scalar("sigma_n2", _positive("sigma_n2", sigma_n2)), P0, _int("steps", steps, 0))


def _vector_step(P, A, c, Sigma_w, sigma_v2, weight):
    """(21): ``Sigma_w + A [P - P c' c P / (c P c' + sigma_v2) * weight] A'`` (batched)."""
    Pc = P @ c
    S = Pc @ c + sigma_v2
    # S = 0 (P c = 0 and a noise-free sensor): nothing to learn, the update is 0
    coef = np.where(S > 0, weight / np.where(S > 0, S, 1.0), 0.0)
    post = P - coef[..., None, None] * Pc[..., :, None] * Pc[..., None, :]
    out = A @ post @ A.T + Sigma_w
    return 0.5 * (out + np.swapaxes(out, -1, -2))


def _vector_chunk(rng, n, *, A, c, Sigma_w, sigma_v2, sigma_n2, channel, P0, steps):
    """``n`` paths of (21); returns the upper-triangle entries, ``(n, steps + 1, d(d+1)/2)``.

    ``P`` is kept flattened, ``(n, d*d)``, so that ``A X A'`` is one product with
    ``kron(A, A)`` and every operation is a plain 2-D array operation (fast for small ``d``).
    """
    d = A.shape[0]
    iu = np.triu_indices(d)
    flat_iu = iu[0] * d + iu[1]
    K = np.kron(A, A).T  # vec(A X A') = kron(A, A) vec(X) for row-major vec
    Cm = np.kron(np.eye(d), c).T  # (d*d, d): vec(X) @ Cm = X c
    r = channel.sample(rng, (n, steps))
    P = np.tile(P0.reshape(-1), (n, 1))
    sw = Sigma_w.reshape(-1)
    out = np.empty((n, steps + 1, flat_iu.size))
    out[:, 0] = P[:, flat_iu]
    for k in range(steps):
        Pc = P @ Cm
        S = Pc @ c + sigma_v2
        rk = r[:, k]
        wt = rk / (rk * S + sigma_n2)  # (r / (r + beta)) / S with beta = sigma_n2 / S
        post = P - wt[:, None] * (Pc[:, :, None] * Pc[:, None, :]).reshape(n, d * d)
        P = post @ K + sw
        out[:, k + 1] = P[:, flat_iu]
    return out


@_doc(
      returns=("MonteCarloResult", "``samples`` ``(n_paths, steps + 1, n (n + 1) / 2)`` (upper "
                                   "triangles)."))
def vector_paths(A, c, Sigma_w, sigma_v2, sigma_n2, channel, P0, steps, n_paths, seed, **runner):
    """Paths of (21); ``samples`` hold the upper triangle of ``P_k`` (row-major ``triu``)."""
    A, c, Sw, sv2, sn2, P0, steps = _vector_args(A, c, Sigma_w, sigma_v2, sigma_n2, P0, steps)
    fn = functools.partial(_vector_chunk, A=A, c=c, Sigma_w=Sw, sigma_v2=sv2, sigma_n2=sn2,
                           channel=check_channel(channel), P0=P0, steps=steps)
    return simulate_paths(fn, n_paths, seed, **runner)


@_doc(returns=("numpy.ndarray", "``(..., n, n)``."),
      raises=(("ValueError", "If ``x`` is not finite or its last axis is not ``n (n + 1) / 2``."),))
def triu_to_symmetric(x, n: int) -> np.ndarray:
    """Symmetric ``(..., n, n)`` matrices from row-major upper triangles ``(..., n(n+1)/2)``
    (the layout of :func:`vector_paths` samples).
    """
    n = _int("n", n, 1)
    x = _finite("x", x)
    if x.ndim < 1 or x.shape[-1] != n * (n + 1) // 2:
        raise ValueError(f"x must have n (n + 1) / 2 = {n * (n + 1) // 2} entries on its last "
                         f"axis, got shape {x.shape}")
    iu = np.triu_indices(n)
    out = np.zeros((*x.shape[:-1], n, n))
    out[..., iu[0], iu[1]] = x
    out[..., iu[1], iu[0]] = x
    return out


@_doc(returns=("mean, stderr : numpy.ndarray", "``(steps + 1, n, n)``."))
def vector_mc(A, c, Sigma_w, sigma_v2, sigma_n2, channel, P0, steps, n_paths, seed, **runner):
    """``(mean, stderr)`` of ``P_k`` entrywise, each shaped ``(steps + 1, n, n)``."""
    res = vector_paths(A, c, Sigma_w, sigma_v2, sigma_n2, channel, P0, steps, n_paths, seed,
                       **runner)
    n = np.asarray(A).shape[0]
    return triu_to_symmetric(res.mean, n), triu_to_symmetric(res.stderr, n)


@_doc(returns=("numpy.ndarray", "``Zbar`` ``(steps + 1, n, n)``."))
def vector_bound(A, c, Sigma_w, sigma_v2, sigma_n2, channel, P0, steps) -> np.ndarray:
    """The bounding sequence ``Zbar_k`` of Section 3.2, shaped ``(steps + 1, n, n)``.

    ``Zbar_{k+1} = Sigma_w + A Zbar A' - A Zbar c' c Zbar A' / (c Zbar c' + sigma_v2) (1 - g)``
    with ``g = E[b / (r + b)]``, ``b = sigma_n2 / (c Zbar c' + sigma_v2)``; for Rayleigh
    ``g = mbar e^mbar E1(mbar)`` as printed. ``E[P_k] <= Zbar_k`` (Theorem 3.3).
    """
    A, c, Sw, sv2, sn2, P0, steps = _vector_args(A, c, Sigma_w, sigma_v2, sigma_n2, P0, steps)
    ch = check_channel(channel)
    out = np.empty((steps + 1, *P0.shape))
    out[0] = Z = P0
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        for k in range(steps):
            S = c @ Z @ c + sv2
            Z = _vector_step(Z, A, c, Sw, sv2, 1.0 - float(ch.ratio_mean(sn2 / S)))
            out[k + 1] = Z
    return _finite_result("the bound", out, "it overflows the float range (A too large for "
                          "this many steps)")
