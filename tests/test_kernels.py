"""The compiled inner loops of the fused particle filter against plain NumPy."""

from __future__ import annotations

import numpy as np
import pytest

from fusioncenter import _kernels, particle


def _numpy_systematic(w, u):
    """The NumPy systematic resampling the kernel replaces: ``cumsum``, ``ceil``, ``repeat``."""
    m, P = w.shape
    c = np.cumsum(w, axis=1)
    c /= c[:, -1:]
    c *= P
    c -= u[:, None]
    c = np.ceil(c)
    c[:, -1] = P
    cnt = np.diff(c, axis=1, prepend=0.0).astype(np.intp)
    return np.repeat(np.arange(m * P), cnt.ravel()).reshape(m, P) % P


def _weights(kind, m, P, rng):
    if kind == "lognormal":
        return np.exp(3 * rng.standard_normal((m, P)))
    if kind == "sparse":  # most particles have zero weight
        w = np.exp(rng.standard_normal((m, P)))
        w[rng.random((m, P)) < 0.9] = 0.0
        w[:, rng.integers(P)] += 1.0
        return w
    if kind == "one":  # all the mass on one particle
        w = np.zeros((m, P))
        w[np.arange(m), rng.integers(0, P, m)] = 1.0
        return w
    return np.ones((m, P))


@pytest.mark.parametrize("kind", ["lognormal", "sparse", "one", "equal"])
@pytest.mark.parametrize("P", [1, 2, 7, 1000])
def test_systematic_resampling_kernel_equals_numpy(kind, P):
    rng = np.random.default_rng(P)
    m = 9
    w = _weights(kind, m, P, rng)
    p, v = rng.standard_normal((2, m, P))
    u = rng.random(m)
    u[0] = 0.0
    S = w.sum(axis=1)
    S[:] = [np.cumsum(row)[-1] for row in w]  # the kernel's contract: the sequential sum
    anc = np.empty((m, P), dtype=np.intp)
    _kernels.systematic_ancestors(w, S, u, np.ones(m, dtype=bool), anc)
    idx = _numpy_systematic(w, u)
    assert np.array_equal(anc, idx)
    new_p = np.empty_like(p)
    _kernels.take_rows(p, anc, new_p)
    assert np.array_equal(new_p, np.take_along_axis(p, idx, axis=1))
    # the ancestors are the library's systematic resampling (it normalizes the weights first:
    # the same counts up to rounding, exact when the mass is on one particle)
    if kind == "one":
        with np.errstate(divide="ignore"):
            lw = np.log(w)
        assert np.array_equal(idx, particle.systematic_resample(lw, u))


def test_systematic_resampling_kernel_leaves_rows_not_to_resample():
    rng = np.random.default_rng(3)
    m, P = 6, 50
    w = np.exp(rng.standard_normal((m, P)))
    S = np.array([np.cumsum(row)[-1] for row in w])
    u = rng.random(m)
    todo = np.array([True, False, True, False, False, True])
    anc = np.empty((m, P), dtype=np.intp)
    _kernels.systematic_ancestors(w, S, u, todo, anc)
    assert np.array_equal(anc[~todo], np.broadcast_to(np.arange(P), (int((~todo).sum()), P)))
    assert np.array_equal(anc[todo], _numpy_systematic(w[todo], u[todo]))


def test_systematic_resampling_kernel_is_unbiased():
    """Over a grid of uniforms the offspring counts average to ``P w`` (to the grid's 1/n)."""
    rng = np.random.default_rng(4)
    P, n_u = 40, 4000
    w = np.exp(2 * rng.standard_normal((n_u, P)))
    w[:] = w[0]
    S = np.full(n_u, np.cumsum(w[0])[-1])
    anc = np.empty((n_u, P), dtype=np.intp)
    _kernels.systematic_ancestors(w, S, np.arange(n_u) / n_u, np.ones(n_u, dtype=bool), anc)
    counts = np.bincount(anc.ravel(), minlength=P) / n_u
    np.testing.assert_allclose(counts, P * w[0] / S[0], atol=2.0 / n_u)
    assert np.array_equal(anc, np.sort(anc, axis=1))  # ancestors in order within a row


def test_weighted_moments_kernel_equals_numpy():
    rng = np.random.default_rng(5)
    m, P = 11, 777
    w = np.exp(2 * rng.standard_normal((m, P)))
    p, v = rng.normal(100, 3, (2, m, P))
    S, mp, mv, ess = np.empty((4, m))
    _kernels.weighted_moments(w, p, v, S, mp, mv, ess)
    np.testing.assert_allclose(S, w.sum(axis=1), rtol=1e-13)
    np.testing.assert_allclose(mp, (w * p).sum(axis=1) / w.sum(axis=1), rtol=1e-13)
    np.testing.assert_allclose(mv, (w * v).sum(axis=1) / w.sum(axis=1), rtol=1e-13)
    np.testing.assert_allclose(ess, w.sum(axis=1) ** 2 / (w * w).sum(axis=1), rtol=1e-12)
    assert np.array_equal(S, [np.cumsum(row)[-1] for row in w])  # sequential, as resampling
