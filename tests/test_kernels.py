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
    for d in (1, 2, 5):  # the d = 2 case is written out in the kernel
        x = rng.standard_normal((m, P, d))
        for layout in (x, particle.by_component(x)):
            new = np.empty_like(layout)
            _kernels.take_rows(layout, anc, new)
            assert np.array_equal(new, np.take_along_axis(x, idx[..., None], axis=1))
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


@pytest.mark.parametrize("d", [1, 2, 6])
def test_weighted_moments_kernel_equals_numpy(d):
    rng = np.random.default_rng(5)
    m, P = 11, 777
    w = np.exp(2 * rng.standard_normal((m, P)))
    x = rng.normal(100, 3, (m, P, d))
    S, ess = np.empty((2, m))
    mean = np.empty((m, d))
    _kernels.weighted_moments(w, particle.by_component(x), S, mean, ess)
    np.testing.assert_allclose(S, w.sum(axis=1), rtol=1e-13)
    np.testing.assert_allclose(mean, particle.weighted_mean(x, np.log(w)), rtol=1e-13)
    np.testing.assert_allclose(ess, particle.ess(np.log(w)), rtol=1e-12)
    assert np.array_equal(S, [np.cumsum(row)[-1] for row in w])  # sequential, as resampling


@pytest.mark.parametrize("dt, k", [(1.0, 1), (0.5, 1), (0.25, 2), (1.0, 0)])
def test_propagate_kernel_equals_numpy(dt, k):
    """x F^T + g L^T for F = [[1, dt], [0, 1]], bit for bit the NumPy in-place arithmetic."""
    rng = np.random.default_rng(6)
    x = rng.standard_normal((4, 30, 2))
    g = rng.standard_normal((4, 30, k))
    L = rng.standard_normal((2, k))
    p, v = x[..., 0].copy(), x[..., 1].copy()
    p += v * dt
    for j in range(k):
        p += g[..., j] * L[0, j]
        v += g[..., j] * L[1, j]
    y = particle.by_component(x)
    _kernels.propagate_wna(y, dt, g, L)
    assert np.array_equal(y[..., 0], p) and np.array_equal(y[..., 1], v)
    F = np.array([[1.0, dt], [0.0, 1.0]])
    np.testing.assert_allclose(y, x @ F.T + g @ L.T, rtol=1e-13, atol=1e-13)
