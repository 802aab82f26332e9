"""The vectorized bootstrap particle filter: weights, resampling, moments, and the whole loop.

Every random test is seeded. Monte Carlo checks are z-scores ``(estimate - claim) / stderr`` that
must stay below 4.5 (P(|Z| > 4.5) = 6.8e-6 per check under the claim).
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from fusioncenter import particle
from fusioncenter.censoring import LinearScenario
from fusioncenter.kalman import LinearGaussianModel


def random_logw(rng, shape, spread=5.0):
    return rng.standard_normal(shape) * spread


# ----------------------------------------------------------------------------- weights
def test_log_normalize_sums_to_one_and_is_shift_invariant():
    rng = np.random.default_rng(0)
    lw = random_logw(rng, (7, 50))
    out, lse = particle.log_normalize(lw)
    np.testing.assert_allclose(np.exp(out).sum(axis=-1), 1.0, rtol=1e-14)
    out2, lse2 = particle.log_normalize(lw + 1e4)  # no overflow: exp(1e4) would be inf
    np.testing.assert_allclose(out2, out, atol=1e-10)
    np.testing.assert_allclose(lse2 - lse, 1e4, rtol=1e-14)
    np.testing.assert_allclose(lse, np.log(np.exp(lw).sum(axis=-1)), rtol=1e-13)


def test_log_normalize_dead_row_is_uniform_and_flagged():
    lw = np.array([[0.0, -np.inf, 1.0], [-np.inf, -np.inf, -np.inf]])
    out, lse = particle.log_normalize(lw)
    np.testing.assert_allclose(np.exp(out[1]), 1 / 3)
    assert lse[1] == -np.inf and np.isfinite(lse[0])
    assert np.exp(out[0, 1]) == 0.0
    with pytest.raises(ValueError, match="NaN"):
        particle.log_normalize(np.array([0.0, np.nan]))


def test_ess_limits():
    P = 40
    assert particle.ess(np.zeros(P)) == pytest.approx(P)
    one_hot = np.full(P, -np.inf)
    one_hot[3] = 0.0
    assert particle.ess(one_hot) == pytest.approx(1.0)
    w = np.array([0.5, 0.25, 0.25])
    assert particle.ess(np.log(w)) == pytest.approx(1 / np.sum(w**2))


# ----------------------------------------------------------------------------- resampling
def test_systematic_counts_sum_and_bound():
    rng = np.random.default_rng(1)
    lw = random_logw(rng, (20, 100), spread=3.0)
    u = rng.random(20)
    counts = particle.systematic_counts(lw, u)
    assert counts.dtype == np.int64 and np.all(counts >= 0)
    assert np.all(counts.sum(axis=-1) == 100)
    w = np.exp(particle.log_normalize(lw)[0])
    assert np.all(np.abs(counts - 100 * w) < 1 + 1e-9)  # systematic: within one of P w


def test_systematic_counts_are_unbiased():
    """E_u[count_j] = P w_j exactly: average over a fine deterministic grid of u."""
    rng = np.random.default_rng(2)
    P, M = 30, 20000
    lw = random_logw(rng, (P,), spread=2.0)
    w = np.exp(particle.log_normalize(lw)[0])
    u = (np.arange(M) + 0.5) / M
    counts = particle.systematic_counts(np.broadcast_to(lw, (M, P)), u)
    np.testing.assert_allclose(counts.mean(axis=0), P * w, atol=2.0 / M)
    # and with random uniforms, a z-score per particle
    ur = rng.random(M)
    cr = particle.systematic_counts(np.broadcast_to(lw, (M, P)), ur)
    se = cr.std(axis=0, ddof=1) / np.sqrt(M)
    ok = se > 0
    z = (cr.mean(axis=0) - P * w)[ok] / se[ok]
    assert np.max(np.abs(z)) < 4.5


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 12), P=st.integers(1, 60),
       split=st.integers(0, 12))
def test_resampling_identical_for_any_chunking(seed, n, P, split):
    rng = np.random.default_rng(seed)
    lw = random_logw(rng, (n, P), spread=4.0)
    u = rng.random(n)
    k = min(split, n)
    whole = particle.systematic_resample(lw, u)
    parts = np.concatenate([particle.systematic_resample(lw[:k], u[:k]),
                            particle.systematic_resample(lw[k:], u[k:])]) if 0 < k < n else whole
    assert np.array_equal(whole, parts)
    for b in range(n):  # one row at a time as well
        assert np.array_equal(particle.systematic_resample(lw[b], u[b]), whole[b])
    assert np.all(np.diff(whole, axis=-1) >= 0)
    counts = particle.systematic_counts(lw, u)
    for b in range(n):
        assert np.array_equal(np.bincount(whole[b], minlength=P), counts[b])


def test_resample_gathers_rows():
    x = np.arange(2 * 3 * 2, dtype=float).reshape(2, 3, 2)
    idx = np.array([[2, 2, 0], [1, 0, 0]])
    out = particle.resample(x, idx)
    assert np.array_equal(out[0], x[0][[2, 2, 0]]) and np.array_equal(out[1], x[1][[1, 0, 0]])


def test_systematic_counts_validates_u():
    with pytest.raises(ValueError, match="u"):
        particle.systematic_counts(np.zeros((2, 3)), np.array([0.5, 1.0]))
    with pytest.raises(ValueError, match="u"):
        particle.systematic_counts(np.zeros((2, 3)), np.array([0.5]))


# ----------------------------------------------------------------------------- moments
def test_weighted_mean_cov_match_numpy():
    rng = np.random.default_rng(3)
    x = rng.standard_normal((4, 200, 3)) + np.array([100.0, -5.0, 0.0])
    lw = random_logw(rng, (4, 200), spread=1.0)
    m, C = particle.weighted_mean_cov(x, lw)
    w = np.exp(particle.log_normalize(lw)[0])
    for b in range(4):
        np.testing.assert_allclose(m[b], np.average(x[b], axis=0, weights=w[b]), rtol=1e-13)
        np.testing.assert_allclose(C[b], np.cov(x[b].T, aweights=w[b], bias=True), atol=1e-11)
    np.testing.assert_allclose(particle.weighted_mean(x, lw), m, rtol=1e-13)


def test_psd_factor_rank_one_q():
    sc = LinearScenario()
    L = particle.psd_factor(sc.Q)
    assert L.shape == (2, 1)  # white-noise acceleration: one scalar acceleration per step
    np.testing.assert_allclose(L @ L.T, sc.Q, atol=1e-12)
    assert particle.psd_factor(np.zeros((2, 2))).shape == (2, 0)


def test_dynamics_moments():
    rng = np.random.default_rng(4)
    dyn = particle.LinearGaussianDynamics(A=[[1.0, 1.0], [0.0, 1.0]],
                                          Q=4.0 * np.array([[0.25, 0.5], [0.5, 1.0]]),
                                          m0=[1.0, 2.0], P0=np.diag([2.0, 0.5]))
    x0 = dyn.initial(rng, 4, 50000)
    x1 = dyn.transition(rng, 1, x0)
    flat = x1.reshape(-1, 2)
    mean = dyn.F @ dyn.m0
    cov = dyn.F @ dyn.P0 @ dyn.F.T + dyn.Q
    se = flat.std(axis=0, ddof=1) / np.sqrt(len(flat))
    assert np.all(np.abs(flat.mean(axis=0) - mean) / se < 4.5)
    np.testing.assert_allclose(np.cov(flat.T), cov, rtol=0.02)
    with pytest.raises(ValueError, match="Q"):
        particle.LinearGaussianDynamics(F=np.eye(2), Q=-np.eye(2), m0=[0, 0], P0=np.eye(2))


def test_dynamics_letters():
    """The library's ``A``; zheng2014's ``F`` is accepted as the keyword and read as an alias."""
    kw = dict(Q=np.eye(2), m0=[0.0, 0.0], P0=np.eye(2))
    by_a = particle.LinearGaussianDynamics(A=[[1.0, 1.0], [0.0, 1.0]], **kw)
    by_f = particle.LinearGaussianDynamics(F=[[1.0, 1.0], [0.0, 1.0]], **kw)
    assert np.array_equal(by_a.A, by_f.A) and by_f.F is by_f.A
    with pytest.raises(ValueError, match="once"):
        particle.LinearGaussianDynamics(A=np.eye(2), F=np.eye(2), **kw)
    with pytest.raises(ValueError, match="F must be square"):
        particle.LinearGaussianDynamics(F=np.ones((2, 3)), **kw)


# ----------------------------------------------------------------------------- the loop
class _AllSend:
    """Every sensor sends: a linear Gaussian observation model (a FilterModel)."""

    needs_cov = True

    def __init__(self, sc: LinearScenario, z: np.ndarray):
        self.sc, self.z = sc, z
        self.dim = 2

    def initial(self, rng, n, P):
        return self.sc.dynamics.initial(rng, n, P)

    def transition(self, rng, t, x):
        return self.sc.dynamics.transition(rng, t, x)

    def log_weight(self, t, x):
        hx = x @ self.sc.H.T  # (n, P, N)
        r = self.sc.rvec
        d = self.z[:, None, t - 1, :] - hx
        return (-0.5 * d * d / r - 0.5 * np.log(2 * np.pi * r)).sum(axis=-1)

    def observe(self, t, mean, cov):
        pass


def _kalman(sc: LinearScenario, z: np.ndarray):
    """The exact posterior at t = 1..T (library Kalman filter, prior of x_1 as its 'x_0')."""
    dyn = sc.dynamics
    model = LinearGaussianModel(A=dyn.F, Q=dyn.Q, C=sc.H, R=np.diag(sc.rvec),
                                m0=dyn.F @ dyn.m0, P0=dyn.F @ dyn.P0 @ dyn.F.T + dyn.Q)
    mean, P = model.filter(z)
    # log-likelihood of the data: sum of log N(innovation; 0, S)
    n, T, N = z.shape
    m = np.broadcast_to(model.m0, (n, 2))
    Pp = model.P0
    ll = np.zeros(n)
    for k in range(T):
        S = sc.H @ Pp @ sc.H.T + np.diag(sc.rvec)
        nu = z[:, k] - m @ sc.H.T
        ll += -0.5 * (np.einsum("ni,ij,nj->n", nu, np.linalg.inv(S), nu)
                      + np.log(np.linalg.det(2 * np.pi * S)))
        m = mean[:, k] @ dyn.F.T
        Pp = dyn.F @ P[k] @ dyn.F.T + dyn.Q
    return mean, P, ll


@pytest.mark.parametrize("P0", [None, ((1.0, 0.0), (0.0, 0.5))])
def test_all_send_particle_filter_matches_kalman(P0):
    """With every sensor sending, the PF mean converges to the Kalman mean (the exact posterior).

    Per trial and step, ``(pf - kf) / sqrt(P_kk)`` is Monte Carlo noise of order
    ``1/sqrt(ESS)``; its mean square over trials must be below ``10 / P`` (it is about ``2/P``:
    the ESS after weighting is about P/3), and its mean must show no bias (z-score).
    """
    sc = LinearScenario(N=2, P0=P0)
    rng = np.random.default_rng(5)
    n, P = 48, 2000
    _, z = sc.sample(rng, n)
    out = particle.run_filter(_AllSend(sc, z), rng, n, P, sc.T)
    kf_mean, kf_P, kf_ll = _kalman(sc, z)
    sd = np.sqrt(np.diagonal(kf_P, axis1=-2, axis2=-1))  # (T, 2)
    zerr = (out.mean - kf_mean) / sd
    assert np.mean(zerr**2) < 10.0 / P
    zb = zerr.mean(axis=0) / (zerr.std(axis=0, ddof=1) / np.sqrt(n))
    assert np.max(np.abs(zb)) < 4.5
    # the weighted covariance approaches the Kalman covariance
    np.testing.assert_allclose(out.cov.mean(axis=0), kf_P, rtol=0.05)
    # the log evidence (log-sum-exp with all constants) estimates the data's log-likelihood:
    # unbiased in the linear domain, so in the log domain a bias of about -var/2 (Jensen)
    d = out.log_evidence - kf_ll
    assert abs(d.mean()) < 4.5 * d.std(ddof=1) / np.sqrt(n) + 0.5 * d.var()
    assert d.std() < 1.0
    assert not out.collapsed.any()


def test_run_filter_collapse_is_flagged_not_nan():
    sc = LinearScenario()
    rng = np.random.default_rng(6)
    _, z = sc.sample(rng, 3)

    class Dead(_AllSend):
        def log_weight(self, t, x):
            lw = super().log_weight(t, x)
            if t == 2:
                lw[1] = -np.inf  # trial 1: no particle compatible at t = 2
            return lw

    out = particle.run_filter(Dead(sc, z), rng, 3, 100, sc.T)
    assert out.collapsed[1, 1] and out.collapsed.sum() == 1
    assert np.all(np.isfinite(out.mean)) and np.all(np.isfinite(out.log_evidence))


def test_ess_threshold_zero_never_resamples_and_matches_importance_sampling():
    """Without resampling the filter is plain importance sampling from the prior paths."""
    sc = LinearScenario(T=3)
    rng = np.random.default_rng(7)
    _, z = sc.sample(rng, 2)
    m1 = _AllSend(sc, z)
    out = particle.run_filter(m1, np.random.default_rng(8), 2, 500, sc.T, ess_threshold=0.0)
    # replay the same draws by hand: initial (no draws, P0 = 0), then per step noise and u
    r2 = np.random.default_rng(8)
    x = sc.dynamics.initial(r2, 2, 500)
    lw = np.zeros((2, 500))
    for t in range(1, 4):
        x = sc.dynamics.transition(r2, t, x)
        r2.random(2)
        lw = lw + m1.log_weight(t, x)
    np.testing.assert_allclose(out.mean[:, -1], particle.weighted_mean(x, lw), rtol=1e-12)


def test_run_filter_validation():
    sc = LinearScenario()
    m = _AllSend(sc, np.zeros((1, sc.T, 2)))
    rng = np.random.default_rng(0)
    with pytest.raises(ValueError, match="n_particles"):
        particle.run_filter(m, rng, 1, 0, 3)
    with pytest.raises(ValueError, match="n_trials"):
        particle.run_filter(m, rng, 0, 10, 3)
    with pytest.raises(ValueError, match="ess_threshold"):
        particle.run_filter(m, rng, 1, 10, 3, ess_threshold=1.5)
