"""The compiled inner loops of the fused particle filter against plain NumPy."""

from __future__ import annotations

import warnings

import numba
import numpy as np
import pytest
from scipy import special

from fusioncenter import particle
from fusioncenter._compiled import (
    amplitude_terms,
    censoring_decisions,
    log_table,
    normal_cdf,
    resampling,
    transitions,
    vector_terms,
    weights,
)
from fusioncenter._compiled import censored_normal as pc


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
    resampling.systematic_ancestors(w, S, u, np.ones(m, dtype=bool), anc)
    idx = _numpy_systematic(w, u)
    assert np.array_equal(anc, idx)
    for d in (1, 2, 5):  # the d = 2 case is written out in the kernel
        x = rng.standard_normal((m, P, d))
        for layout in (x, particle.by_component(x)):
            new = np.empty_like(layout)
            resampling.take_rows(layout, anc, new)
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
    resampling.systematic_ancestors(w, S, u, todo, anc)
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
    resampling.systematic_ancestors(w, S, np.arange(n_u) / n_u, np.ones(n_u, dtype=bool), anc)
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
    weights.weighted_moments(w, particle.by_component(x), S, mean, ess)
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
    transitions.propagate_wna(y, dt, g, L)
    assert np.array_equal(y[..., 0], p) and np.array_equal(y[..., 1], v)
    F = np.array([[1.0, dt], [0.0, 1.0]])
    np.testing.assert_allclose(y, x @ F.T + g @ L.T, rtol=1e-13, atol=1e-13)


@pytest.mark.parametrize("d,k", [(2, 0), (2, 1), (4, 2), (4, 4), (6, 3)])
@pytest.mark.parametrize("P", [2, 7, 1000])
def test_linear_transition_kernel_is_bitwise_matmul(d, k, P):
    """``x @ F.T + g @ L.T`` on dense random matrices. The kernel's arithmetic (a chain of
    correctly rounded fused multiply-adds, LLVM's ``fma``) is the same on every machine; it is
    the one OpenBLAS's x86-64 ``dgemm`` uses here, so it equals ``matmul`` bit for bit on this
    machine, but another BLAS may round differently: bitwise where BLAS uses FMA, else to
    rounding. (With one particle NumPy calls ``dgemv`` instead, and
    :meth:`fusioncenter.particle.LinearGaussianDynamics.transition` keeps ``matmul``.)"""
    rng = np.random.default_rng(d * 100 + k * 10 + P)
    x = rng.standard_normal((3, P, d)) * 10
    g = rng.standard_normal((3, P, k))
    F = rng.standard_normal((d, d))
    L = rng.standard_normal((d, k))
    want = x @ F.T
    if k:
        want += g @ L.T
    got = np.empty_like(x)
    transitions.linear_transition(x, F, g, L, got)
    np.testing.assert_allclose(got, want, rtol=1e-13, atol=1e-12)
    if _BLAS_FMA:
        np.testing.assert_array_equal(got, want)


def _blas_uses_fma() -> bool:
    """Whether this BLAS's ``dgemm`` rounds ``a b + c`` once: ``(1 + e)(1 - e) - 1`` is
    ``-e^2`` with a fused multiply-add and ``0`` without."""
    e = 2.0**-30
    x = np.array([[[1 + e, 1.0]] * 4])
    F = np.array([[1 - e, -1.0]])
    return bool((x @ F.T)[0, 0, 0] != 0.0)


_BLAS_FMA = _blas_uses_fma()


def test_linear_gaussian_transition_draws_and_values_unchanged():
    """The compiled branch of ``LinearGaussianDynamics.transition`` equals the NumPy one."""
    dt = 0.3
    F = np.kron(np.eye(2), [[1.0, dt], [0.0, 1.0]])
    Q = np.kron(np.eye(2), [[dt**4 / 4, dt**3 / 2], [dt**3 / 2, dt**2]]) * 0.1
    dyn = particle.LinearGaussianDynamics(F, Q, np.zeros(4), np.eye(4))
    x = np.random.default_rng(1).standard_normal((4, 50, 4))
    got = dyn.transition(np.random.default_rng(2), 1, x)
    rng = np.random.default_rng(2)
    want = x @ F.T + rng.standard_normal((4, 50, dyn._LQ.shape[1])) @ dyn._LQ.T
    np.testing.assert_allclose(got, want, rtol=1e-13, atol=1e-13)
    if _BLAS_FMA:
        np.testing.assert_array_equal(got, want)
    for xs in (x[:, ::2], x[:, :1]):  # not contiguous, one particle: NumPy's matmul
        rng = np.random.default_rng(2)
        want = xs @ F.T + rng.standard_normal((*xs.shape[:2], dyn._LQ.shape[1])) @ dyn._LQ.T
        got = dyn.transition(np.random.default_rng(2), 1, xs)
        np.testing.assert_array_equal(got, want)


def _numpy_amplitudes(x, pos, alpha, power):
    diff = np.stack([x[..., 0], x[..., 2]], axis=-1)[:, None] - pos[:, None, :]
    d2 = np.square(diff[..., 0]) + np.square(diff[..., 1])
    if alpha != 1.0:
        d2 *= alpha
    return np.sqrt(power / (d2 + 1.0))


@pytest.mark.parametrize("alpha", [1.0, 0.3])
def test_nonlinear_kernels_equal_numpy(alpha):
    rng = np.random.default_rng(5)
    n, N, P = 4, 9, 300
    x = rng.standard_normal((n, P, 4)) * 10
    pos = rng.uniform(-10, 10, (N, 2))
    amp = np.empty((n, N, P))
    amplitude_terms.amplitudes(x, pos, alpha, 1e3, amp)
    want = _numpy_amplitudes(x, pos, alpha, 1e3)
    np.testing.assert_array_equal(amp, want)
    sent = rng.random((n, N)) < 0.4
    sent[0] = False
    sent[1] = True
    z = rng.standard_normal((n, N)) + 5
    r = rng.uniform(0.5, 2, N)
    # received only: numpy.add.reduceat over the received sensors (first + pairwise rest)
    out = np.empty((n, P))
    amplitude_terms.received_terms(x, pos, alpha, 1e3, sent, z, -0.5 / r, out)
    e = (want - z[..., None]) ** 2 * (-0.5 / r)[:, None]
    b, i = np.nonzero(sent)
    ref = np.zeros((n, P))
    rows, start = np.unique(b, return_index=True)
    ref[rows] = np.add.reduceat(e[b, i], start, axis=0)
    np.testing.assert_array_equal(out, ref)
    # received and silent terms in place
    hxp = rng.uniform(0, 10, (n, N))
    sd = np.sqrt(r)
    amax = np.full((n, N), np.nan)
    got = amp.copy()
    amplitude_terms.sensor_terms(got, sent, z, -0.5 / r, hxp, sd, amax)
    off = np.abs(want - hxp[..., None]) / sd[:, None]
    np.testing.assert_array_equal(got[sent], e[sent])
    np.testing.assert_array_equal(got[~sent], off[~sent])
    np.testing.assert_array_equal(amax[~sent], off[~sent].max(axis=1))


@pytest.mark.parametrize("N", [1, 2, 9, 20])
@pytest.mark.parametrize("P", [2, 7, 300, 10000])
def test_sum_sensors_kernel_is_bitwise_numpy(N, P):
    amp = np.random.default_rng(N * P).standard_normal((3, N, P)) * 10.0 ** np.arange(N)[:, None]
    out = np.empty((3, P))
    amplitude_terms.sum_sensors(amp, out)
    np.testing.assert_array_equal(out, amp.sum(axis=1))


@pytest.mark.parametrize("kind", ["lognormal", "sparse", "one", "equal"])
@pytest.mark.parametrize("P", [1, 2, 7, 1000])
def test_fused_resampling_is_the_ancestors_then_the_gather(kind, P):
    """``resample_rows`` (the loop's fused resampling) gives bit for bit what
    ``systematic_ancestors`` then ``take_rows`` give, rows not to resample copied."""
    rng = np.random.default_rng(P + 11)
    m = 9
    w = _weights(kind, m, P, rng)
    S = np.array([np.cumsum(row)[-1] for row in w])
    u = rng.random(m)
    u[0] = 0.0
    todo = rng.random(m) < 0.7
    todo[:2] = True, False
    anc = np.empty((m, P), dtype=np.intp)
    resampling.systematic_ancestors(w, S, u, todo, anc)
    for d in (1, 2, 5):  # the d = 2 case is written out in the kernel
        x = rng.standard_normal((m, P, d))
        for layout in (x, particle.by_component(x)):
            want = np.empty_like(layout)
            resampling.take_rows(layout, anc, want)
            got = np.full_like(layout, np.nan)
            resampling.resample_rows(w, S, u, todo, layout, got)
            assert np.array_equal(got, want)


@pytest.mark.parametrize("layout", ["component", "interleaved"])
@pytest.mark.parametrize("add", [False, True])
def test_gauss_terms_kernel_is_bitwise_numpy(add, layout):
    """Rows of a particle component (contiguous rows, a view typed contiguous in the kernel)
    and rows with a stride (the kernel reads a copy of each row)."""
    rng = np.random.default_rng(12)
    m, P = 7, 300
    x = 1e3 * rng.standard_normal((m, P, 2))
    y = (particle.by_component(x) if layout == "component" else x)[..., 0]
    assert not y.flags.c_contiguous
    zbar = rng.standard_normal(m)
    coef = -0.5 / 0.7 * rng.integers(0, 4, m)  # including rows with no sensor received (0)
    base = rng.standard_normal((m, P))
    want = np.subtract(y, zbar[:, None])
    np.square(want, out=want)
    want *= coef[:, None]
    if add:
        want = base + want
    got = base.copy()
    log_table.gauss_terms(y, zbar, coef, got, add)
    assert np.array_equal(got, want)


def test_silent_table_fused_add_is_bitwise_the_table_then_the_sums():
    """``LogTable.shifted_add`` (CFwMD's silent factor in the loop) against the NumPy steps it
    replaces: the table at every point (``shifted``), rows without a silent sensor zeroed, the
    product by the number of silent sensors, the sum; with points beyond the table (exact
    function) in some rows."""
    from fusioncenter.censoring.tables import silent_table

    rng = np.random.default_rng(13)
    m, P = 8, 400
    table = silent_table(1.3)
    y = 3.0 * rng.standard_normal((m, P))
    y[2, 5] = 80.0  # beyond the table (|x| >= 48): evaluated exactly
    y[5, 0] = -1e3
    hp = rng.standard_normal(m)
    ns = np.array([1, 0, 2, 1, 3, 2, 0, 1])
    base = rng.standard_normal((m, P))
    val = table.shifted(y, hp, 0.9, np.empty((m, P)))
    assert np.isfinite(val).all()
    val[ns == 0] = 0.0
    val *= ns[:, None]
    want = base + val
    got = base.copy()
    table.shifted_add(y, hp, 0.9, ns, got, np.empty((m, P)))
    assert np.array_equal(got, want)
    # the far rows went through the exact path: the kernel alone reports them
    rows = np.empty(m, dtype=np.intp)
    k = log_table.table_shifted_add(table.coef, table.n_int, y, hp, 0.9 / table.step, ns,
                                    base.copy(), rows)
    assert rows[:k].tolist() == [2, 5]



@pytest.mark.parametrize("add", [False, True])
def test_gauss_and_table_in_one_call_is_bitwise_the_two_kernels(add):
    """``shifted_add(..., gauss=...)`` (one compiled call: the received sensors' terms, then the
    silent factor, row by row) against ``gauss_terms`` followed by ``shifted_add``; strided
    rows, rows with no silent sensor, several silent sensors, far points (exact path)."""
    from fusioncenter.censoring.tables import silent_table

    rng = np.random.default_rng(14)
    m, P = 8, 400
    table = silent_table(0.7)
    y = particle.by_component(3.0 * rng.standard_normal((m, P, 2)))[..., 0]
    y[3, 7] = 90.0  # beyond the table: the row goes through the exact path
    hp = rng.standard_normal(m)
    ns = np.array([1, 0, 2, 1, 3, 0, 1, 2])
    zbar = rng.standard_normal(m)
    coef = -0.5 / 1.3 * np.array([1, 2, 0, 1, 0, 2, 1, 0])
    base = rng.standard_normal((m, P))
    want = base.copy()
    log_table.gauss_terms(y, zbar, coef, want, add)
    table.shifted_add(y, hp, 1.1, ns, want, np.empty((m, P)))
    got = base.copy()
    table.shifted_add(y, hp, 1.1, ns, got, np.empty((m, P)), (zbar, coef, add))
    assert np.array_equal(got, want)
    rows = np.empty(m, dtype=np.intp)
    k = log_table.gauss_table_add(table.coef, table.n_int, y, hp, 1.1 / table.step, ns,
                                  base.copy(), rows, zbar, coef, add)
    assert rows[:k].tolist() == [3]


def _inline_tables():
    import platform
    import sys

    from fusioncenter._compiled import ziggurat

    zig = ziggurat.tables()
    if zig is None and not (sys.platform == "linux" and platform.machine() == "x86_64"):
        # another platform: the loop draws through NumPy (same numbers, slower)
        pytest.skip("NumPy's ziggurat tables are not readable here")
    # on the project's machines (Linux x86-64, NumPy's wheel) they must be found and pass
    # the check of ziggurat.tables (inline draws equal to standard_normal)
    assert zig is not None
    return zig


@pytest.mark.parametrize("bits", [np.random.SFC64, np.random.PCG64, np.random.Philox])
@pytest.mark.parametrize("shape", [(7, 2), (5000, 2), (3, 4096)])
def test_standard_normal_is_numpys_numbers_and_state(bits, shape):
    """``ziggurat.standard_normal(rng, shape)`` (what the vector FC's rejection sampler draws
    with): ``rng.standard_normal(shape)``'s numbers, and the generator left where NumPy leaves
    it, whether the draws are inline (SFC64, PCG64, at least INLINE_MIN) or NumPy's."""
    from fusioncenter._compiled import ziggurat

    _inline_tables()
    mine, ref = np.random.Generator(bits(11)), np.random.Generator(bits(11))
    mine.random(3)
    ref.random(3)
    got = ziggurat.standard_normal(mine, shape)
    assert got.shape == shape and np.array_equal(got, ref.standard_normal(shape))
    assert np.array_equal(mine.random(5), ref.random(5))
    assert np.array_equal(ziggurat.standard_normal(mine, (0, 2)), np.empty((0, 2)))


@pytest.mark.parametrize("seed", [0, 2014])
def test_inline_pcg64_normals_are_numpys_bit_for_bit(seed):
    """The same for NumPy's default generator, PCG64 (128-bit state and increment): the
    kernels' draws are ``standard_normal``'s numbers and leave its state where NumPy does."""
    from fusioncenter._compiled import ziggurat

    _inline_tables()
    zig = ziggurat.pcg64_tables()
    assert zig is not None
    rng = np.random.default_rng(seed)
    rng.random(3)  # anywhere in the stream
    s = ziggurat.draw_state(rng)
    n = 400_000
    got = np.empty(n)
    transitions.pcg64_normals(s, *zig, got)
    want = rng.standard_normal(n)
    assert np.array_equal(got, want)
    assert np.array_equal(s, ziggurat.draw_state(rng))
    assert np.sum(np.abs(want) > zig[3]) > 20  # the tail was drawn
    mine = np.random.default_rng(seed)
    mine.random(3)
    s = ziggurat.draw_state(mine)
    transitions.pcg64_normals(s, *zig, got)
    ziggurat.set_state(mine, s)  # the state goes back into the generator
    assert np.array_equal(mine.random(5), rng.random(5))


@pytest.mark.parametrize("seed", [0, 2014])
def test_inline_normals_are_numpys_bit_for_bit(seed):
    """The kernels' SFC64 + ziggurat draws are ``standard_normal``'s numbers, and leave the
    stream where NumPy leaves it; the draws include the tail and the wedges."""
    from fusioncenter._compiled import ziggurat

    zig = _inline_tables()
    rng = np.random.Generator(np.random.SFC64(seed))
    s = ziggurat.draw_state(rng)
    n = 400_000
    got = np.empty(n)
    transitions.sfc64_normals(s, *zig, got)
    want = rng.standard_normal(n)
    assert np.array_equal(got, want)
    assert np.array_equal(s, ziggurat.draw_state(rng))
    assert np.sum(np.abs(want) > zig[3]) > 20  # the tail was drawn
    assert s[3] - np.uint64(ziggurat.draw_state(
        np.random.Generator(np.random.SFC64(seed)))[3]) > n  # so were rejections


def test_inline_draws_in_the_filter_change_no_bit(monkeypatch):
    """The linear FC's transition with the normals drawn inside the pass against the same
    filter drawing them through NumPy: the same estimates and the same generator state."""
    from fusioncenter import censoring as cs
    from fusioncenter._compiled import ziggurat
    from fusioncenter.censoring.fusion import LinearFusionCentre

    _inline_tables()
    sc = cs.LinearScenario()
    z = sc.sample(np.random.default_rng(5), 6)[1]
    sel = np.random.default_rng(6).random(z.shape)
    outs = []
    for inline in (True, False):
        if not inline:
            monkeypatch.setattr(ziggurat, "tables", lambda: None)
        rng = np.random.Generator(np.random.SFC64(7))
        fc = LinearFusionCentre(sc, "cfwmd", "state", "corrected", cs.threshold(1.0, 2), 1.0,
                                z, sel)
        out = particle.run_filter(fc, rng, 6, 300, sc.T)
        outs.append((out.mean, out.ess, out.log_evidence, fc.sent, rng.random(3)))
    for a, b in zip(*outs, strict=True):
        assert np.array_equal(a, b)


@pytest.mark.parametrize(("d", "k"), [(2, 1), (4, 2), (3, 3)])
def test_linear_gaussian_transition_inline_draws_change_no_bit(d, k, monkeypatch):
    """``LinearGaussianDynamics.transition`` on an SFC64 stream draws its normals inside the
    compiled pass (``linear_transition_draw``): the same values and the same stream position as
    with ``standard_normal`` then ``linear_transition``."""
    from fusioncenter._compiled import ziggurat

    _inline_tables()
    rng0 = np.random.default_rng(d + k)
    A = rng0.standard_normal((d, d))
    B = rng0.standard_normal((d, k))
    dyn = particle.LinearGaussianDynamics(A, B @ B.T, np.zeros(d), np.eye(d))
    assert dyn._LQ.shape[1] == k
    x = rng0.standard_normal((5, 60, d))
    outs = []
    for inline in (True, False):
        if not inline:
            monkeypatch.setattr(ziggurat, "tables", lambda: None)
        rng = np.random.Generator(np.random.SFC64(9))
        outs.append((dyn.transition(rng, 1, x), dyn.transition(rng, 2, x), rng.random(4)))
    for a, b in zip(*outs, strict=True):
        assert np.array_equal(a, b)


@pytest.mark.parametrize(("d", "k"), [(2, 1), (4, 2), (3, 3)])
def test_linear_gaussian_transition_pcg64_inline_draws_change_no_bit(d, k, monkeypatch):
    """The same on NumPy's default generator (PCG64, ``linear_transition_draw_pcg64``): the
    values and the stream position of ``standard_normal`` then ``linear_transition``."""
    from fusioncenter._compiled import ziggurat

    _inline_tables()
    rng0 = np.random.default_rng(d + k)
    A = rng0.standard_normal((d, d))
    B = rng0.standard_normal((d, k))
    dyn = particle.LinearGaussianDynamics(A, B @ B.T, np.zeros(d), np.eye(d))
    x = rng0.standard_normal((5, 60, d))
    drawn = []
    monkeypatch.setattr(transitions, "linear_transition_draw_pcg64",
                        lambda *a, f=transitions.linear_transition_draw_pcg64:
                        drawn.append(1) or f(*a))
    outs = []
    for inline in (True, False):
        if not inline:
            monkeypatch.setattr(ziggurat, "pcg64_tables", lambda: None)
        rng = np.random.default_rng(9)
        outs.append((dyn.transition(rng, 1, x), dyn.transition(rng, 2, x), rng.random(4)))
    assert len(drawn) == 2  # the inline path was taken (twice), then NumPy's
    for a, b in zip(*outs, strict=True):
        assert np.array_equal(a, b)


def test_vector_local_update_kernels_are_the_numpy_arithmetic():
    """The exact no-feedback vector filter's local Kalman step (``local_innovations``,
    ``silent_offsets``, ``local_update``) against the NumPy code it replaced, bit for bit,
    with some silent rows and innovations of both signs and zeros."""
    rng = np.random.default_rng(31)
    n, P, m = 7, 50, 2
    pos, vel, h0, h1 = (rng.standard_normal((n, P)) * 3 for _ in range(4))
    h0[0, :5] = -0.0
    z, H, A = rng.standard_normal((n, m)), rng.standard_normal((m, 2)), rng.standard_normal((m, 2))
    W, F = rng.standard_normal((2, m)), np.array([[1.0, 0.5], [0.0, 1.0]])
    sil = np.array([1, 4, 5])
    nus = rng.standard_normal((sil.size * P, m))

    def lin(M, c0, c1):
        return [M[j, 0] * c0 + M[j, 1] * c1 for j in range(M.shape[0])]

    nu_ref = [z[:, j, None] - hj for j, hj in enumerate(lin(H, h0, h1))]
    b_ref = np.stack([bj.ravel() for bj in lin(A, pos[sil] - h0[sil], vel[sil] - h1[sil])], 1)
    for j in range(m):
        nu_ref[j][sil] = nus[:, j].reshape(sil.size, -1)
    u0 = h0 + sum(W[0, j] * nu_ref[j] for j in range(m))
    u1 = h1 + sum(W[1, j] * nu_ref[j] for j in range(m))
    want0, want1 = F[0, 0] * u0 + F[0, 1] * u1, F[1, 0] * u0 + F[1, 1] * u1

    nu = np.empty((m, n, P))
    vector_terms.local_innovations(z, H, h0, h1, nu)
    assert np.array_equal(nu[0], z[:, 0, None] - (H[0, 0] * h0 + H[0, 1] * h1))
    bs = np.empty((sil.size * P, m))
    vector_terms.silent_offsets(A, pos, vel, h0, h1, sil, bs)
    assert np.array_equal(bs, b_ref)
    g0, g1 = h0.copy(), h1.copy()
    vector_terms.local_update(W, F, nu, nus, sil, g0, g1)
    assert np.array_equal(g0.view(np.int64), want0.view(np.int64))
    assert np.array_equal(g1.view(np.int64), want1.view(np.int64))


def test_exact_received_kernel_is_the_numpy_arithmetic():
    """``vector_terms.exact_received`` (a received sensor's whitened Gaussian term and the
    indicator that it would have sent, in the exact no-feedback vector filter) against the NumPy
    code it replaced, bit for bit, on a subset of rows, with both outcomes of the indicator."""
    rng = np.random.default_rng(32)
    n, P, m = 6, 40, 2
    p, v, h0, h1 = (rng.standard_normal((n, P)) * 2 for _ in range(4))
    rows = np.array([0, 2, 3])
    zi = rng.standard_normal((rows.size, m))
    Linv, H = rng.standard_normal((m, m)), rng.standard_normal((m, 2))
    B = rng.standard_normal((m, m))
    Si = B @ B.T + np.eye(m)
    lw0 = rng.standard_normal((n, P))

    def lin(M, c0, c1):
        return [M[j, 0] * c0 + M[j, 1] * c1 for j in range(M.shape[0])]

    want, ok_want = lw0.copy(), np.ones((n, P), dtype=bool)
    acc = None
    for j, wj in enumerate(lin(Linv @ H, p[rows], v[rows])):
        d = (Linv @ zi.T)[j][:, None] - wj
        d *= d
        acc = d if acc is None else acc + d
    want[rows] += -0.5 * acc
    nu = [zi[:, j, None] - hj for j, hj in enumerate(lin(H, h0[rows], h1[rows]))]
    nis = sum(Si[j, jj] * nu[j] * nu[jj] for j in range(m) for jj in range(m))
    eta = float(np.sort(nis, axis=None)[nis.size // 2])  # both outcomes, and a tie
    ok_want[rows] &= nis >= eta

    got, ok = lw0.copy(), np.ones((n, P), dtype=bool)
    vector_terms.exact_received(Linv @ zi.T, Linv @ H, zi, H, Si, eta, p, v, h0, h1, rows,
                                got, ok)
    assert np.array_equal(got, want)
    assert np.array_equal(ok, ok_want)


def test_white_gauss_add_is_the_numpy_arithmetic():
    """``vector_terms.white_gauss_add`` (a group's whitened Gaussian term) against the NumPy
    code it replaced, bit for bit, rows with and without received sensors."""
    rng = np.random.default_rng(33)
    n, P, m = 5, 30, 2
    p, v = rng.standard_normal((n, P)) * 3, rng.standard_normal((n, P))
    G, cbar = rng.standard_normal((2, m)), rng.standard_normal((n, m))
    n_obs = np.array([0, 1, 2, 1, 3])
    lw0 = rng.standard_normal((n, P))
    want = lw0.copy()
    acc = None
    for j in range(m):
        wj = G.T[j, 0] * p + G.T[j, 1] * v
        wj -= cbar[:, j, None]
        wj *= wj
        acc = wj if acc is None else acc + wj
    acc *= (-0.5 * n_obs)[:, None]
    want += acc
    got = lw0.copy()
    vector_terms.white_gauss_add(np.ascontiguousarray(G.T), p, v, cbar, -0.5 * n_obs, got)
    assert np.array_equal(got, want)


@pytest.mark.parametrize("m", [1, 2, 3, 7])
def test_group_stats_is_the_numpy_arithmetic(m):
    """``group_stats`` gives the floats of ``censoring.fusion``'s NumPy expressions (the
    group's sum left to right, as NumPy's ``sum(axis=1)`` adds at most 7 numbers), signed
    zeros and all-silent rows included; beyond 7 NumPy sums pairwise (the caller keeps it)."""
    rng = np.random.default_rng(m)
    n, T, N = 500, 3, 9
    z = rng.standard_normal((n, T, N)) * 10.0 ** rng.integers(-8, 9, (n, T, N))
    z[rng.random((n, T, N)) < 0.05] = -0.0
    sent = rng.random((n, T, N)) < 0.6
    sent[:10] = False  # rows with no received sensor
    g = np.sort(rng.choice(N, m, replace=False)).astype(np.int64)
    k, c = 1, -0.5 / 1.7
    zbar, coef, nsil = np.empty(n), np.empty(n), np.empty(n, dtype=np.int64)
    n_any, n_sil = censoring_decisions.group_stats(sent, z, k, g, c, zbar, coef, nsil)
    sg = sent[:, k][:, g]
    n_obs = sg.sum(axis=1)
    ref = np.where(sg, z[:, k][:, g], 0.0).sum(axis=1) / np.maximum(n_obs, 1)
    assert np.array_equal(zbar.view(np.int64), ref.view(np.int64))  # signs of zeros too
    assert np.array_equal(coef, c * n_obs) and np.array_equal(nsil, m - n_obs)
    assert (n_any, n_sil) == (np.count_nonzero(n_obs), np.count_nonzero(m - n_obs))
    # why the limit: eight numbers are summed pairwise by NumPy, not left to right
    x = np.array([[1e16, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, -1e16]])
    left = 0.0
    for v in x[0, :8]:
        left += v
    assert censoring_decisions.GROUP_SUM_MAX == 7 and x[:, :7].sum(axis=1)[0] == sum(x[0, :7])
    assert x[:, :8].sum(axis=1)[0] != left


def test_censor_decisions_are_the_numpy_comparison():
    rng = np.random.default_rng(3)
    n, T, N = 400, 4, 3
    z = rng.standard_normal((n, T, N)) * 3
    hx = rng.standard_normal((n, N))
    hx[:5] = z[:5, 2]  # nu = 0: sent only if the threshold is 0
    sent = np.zeros((n, T, N), dtype=bool)
    for s in (rng.uniform(0.5, 2, N)[None, :], rng.uniform(0.5, 2, (n, N))):
        for eta in (0.0, 0.45):
            censoring_decisions.censor_decisions(z, 2, hx, s, eta, sent)
            nu = z[:, 2] - hx
            assert np.array_equal(sent[:, 2], nu * nu >= eta * s)
            assert not sent[:, [0, 1, 3]].any()


def test_shift_by_row_max_is_numpys_max_and_subtraction():
    rng = np.random.default_rng(4)
    lw = rng.standard_normal((6, 300)) * 50
    lw[1] = -np.inf  # no compatible particle: the row is set to 0
    lw[2, ::3] = -np.inf
    lw[3, 7] = np.nan
    lw[4, 9] = np.inf
    ref_mx = lw.max(axis=1)
    ref = lw.copy()
    fin = np.isfinite(ref_mx)
    ref[fin] -= ref_mx[fin, None]
    ref[1] = 0.0
    mx = np.empty(6)
    weights.shift_by_row_max(lw, mx)
    assert np.array_equal(mx, ref_mx, equal_nan=True)
    assert np.array_equal(lw, ref, equal_nan=True)


@pytest.mark.parametrize("layout", ["component", "C"])
@pytest.mark.parametrize("k", [1, 2])
def test_propagate_draw_kernel_is_standard_normal_then_propagate(layout, k):
    """Both paths of ``propagate_wna_draw`` (rows of a component contiguous and ``k = 1``;
    any other) give NumPy's ``standard_normal`` then ``propagate_wna``, and leave the
    generator where ``standard_normal`` does."""
    from fusioncenter._compiled import ziggurat

    zig = _inline_tables()
    rng = np.random.default_rng(8)
    x0 = rng.standard_normal((5, 700, 2))
    L = rng.standard_normal((2, k))
    a = particle.by_component(x0) if layout == "component" else x0.copy()
    ref = x0.copy()
    g1, g2 = (np.random.Generator(np.random.SFC64(9)) for _ in range(2))
    st = ziggurat.draw_state(g1)
    transitions.propagate_wna_draw(a, 0.5, L, st, *zig)
    ziggurat.set_state(g1, st)
    transitions.propagate_wna(ref, 0.5, g2.standard_normal((5, 700, k)), L)
    assert np.array_equal(a, ref)
    assert np.array_equal(g1.random(4), g2.random(4))


def _bits(a):
    return np.ascontiguousarray(a, dtype=float).view(np.int64)


@numba.njit
def _ndtr_each(a, out):
    for i in range(a.size):
        out[i] = normal_cdf.ndtr(a[i])


def test_compiled_ndtr_is_scipys_bit_for_bit():
    # every branch (erf near 0, erfc on [1, 8) and beyond 8, the underflow of exp(-x^2)), the
    # boundaries between them and their neighbouring doubles, and the special values
    rng = np.random.default_rng(7)
    s2 = np.sqrt(2.0)
    edges = np.array([s2, 8 * s2, np.sqrt(2 * 709.782712893384), 37.5, 38.5])
    edges = np.concatenate([edges, np.nextafter(edges, 0), np.nextafter(edges, np.inf)])
    a = np.concatenate([
        rng.standard_normal(1_000_000) * 2, rng.standard_normal(500_000) * 15,
        rng.uniform(-40, 40, 500_000), edges, -edges,
        [0.0, -0.0, np.inf, -np.inf, np.nan, 5e-324, -5e-324, 1e-300, -1e-300, 1e300, -1e300]])
    out = np.empty_like(a)
    _ndtr_each(a, out)
    assert np.array_equal(_bits(out), _bits(special.ndtr(a)))


@pytest.mark.parametrize("shapes", [((50, 300), (50, 1)), ((50, 300), ()), ((7,), (7,)),
                                    ((1, 40), (30, 1)), ((0, 5), (0, 1)),
                                    ((0,), ())])
def test_log_prob_inside_compiled_pass_is_the_numpy_expression(shapes):
    # the NumPy code it replaced, operation for operation (SciPy's ndtr); tails (the careful
    # formula), h = 0 and tiny h (the careful formula too), NaN
    rng = np.random.default_rng(len(shapes[0]) + shapes[0][0])
    m = rng.standard_normal(shapes[0]) * 12
    h = np.abs(rng.standard_normal(shapes[1])) * 3
    if m.size:
        m.flat[:3] = [40.0, np.nan, -0.3]
    if h.ndim and h.size:
        h.flat[:2] = [0.0, 1e-8]

    def numpy_version(m, h):
        m, h = np.abs(m), np.asarray(h, dtype=float)
        p = special.ndtr(h - m)
        a = np.subtract(-h, m)
        p -= special.ndtr(a, out=a)
        bad = p < pc.INSIDE_CUTOFF
        if np.any(h < 1e-6):
            bad |= np.broadcast_to(h, p.shape) < 1e-6
        with np.errstate(divide="ignore", invalid="ignore"):
            out = np.log(p, out=p)
        if bad.any():
            out[bad] = pc.prob_inside(np.broadcast_to(m, p.shape)[bad],
                                      np.broadcast_to(h, p.shape)[bad], log=True)
        return out

    with np.errstate(invalid="ignore"):
        got = pc.log_prob_inside(m, h)
    assert got.shape == np.broadcast_shapes(m.shape, np.shape(h))
    assert np.array_equal(_bits(got), _bits(numpy_version(m, h)))


def test_log_prob_inside_takes_broadcast_arrays_without_a_warning():
    # numba reads the writeable flag of its arguments, which NumPy warns about for the output
    # of np.broadcast_arrays (FutureWarning: seen in a chapter's stderr)
    m, h = np.broadcast_arrays(np.linspace(-3, 3, 20)[None, :], np.full((4, 1), 1.5))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        got = pc.log_prob_inside(m, h)
    assert np.array_equal(_bits(got), _bits(pc.log_prob_inside(m.copy(), h.copy())))
