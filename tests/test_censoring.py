"""Censoring by innovation and fusion with missing data (zheng2014): closed forms and the runs.

Every random test is seeded. Monte Carlo checks are z-scores ``(estimate - claim) / stderr`` below
4.5 (P(|Z| > 4.5) = 6.8e-6 per check under the claim); orderings of schemes are paired
differences (same truth and measurements) that must exceed 4 standard errors.
"""

from __future__ import annotations

import concurrent.futures
import functools
import itertools
import math

import mpmath
import numpy as np
import pytest
import scipy.special
import scipy.stats
from filterpy.kalman import KalmanFilter
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import integrate

from fusioncenter import censoring as cs
from fusioncenter import particle

GH_X, GH_W = np.polynomial.hermite_e.hermegauss(80)  # weight exp(-x^2/2)
GH_W = GH_W / np.sqrt(2 * np.pi)


# ----------------------------------------------------------------------------- threshold
@pytest.mark.parametrize("N", [1, 2, 4, 9])
@pytest.mark.parametrize("dof", [1, 2, 3])
def test_threshold_is_chi2_quantile(N, dof):
    for l in np.linspace(0.05, N, 7):
        eta = cs.threshold(l, N, dof)
        assert eta == pytest.approx(scipy.stats.chi2.isf(l / N, dof), rel=1e-14, abs=1e-300)
        assert scipy.stats.chi2.sf(eta, dof) == pytest.approx(l / N, rel=1e-10)
    assert cs.threshold(N, N, dof) == 0.0  # l = N: everybody sends


def test_threshold_scalar_closed_form():
    # dof = 1: P(Z^2 >= eta) = l/N  <=>  eta = Phi^{-1}(l / (2N))^2
    for l, N in [(1, 2), (1.2, 4), (3, 4)]:
        assert cs.threshold(l, N) == pytest.approx(scipy.stats.norm.ppf(l / (2 * N)) ** 2,
                                                   rel=1e-12)


@pytest.mark.parametrize("l, N, dof, name", [(0, 2, 1, "l"), (-1, 2, 1, "l"), (2.5, 2, 1, "l"),
                                             (np.nan, 2, 1, "l"), (1, 0, 1, "N"),
                                             (1, 1.5, 1, "N"), (1, 2, 0, "dof")])
def test_threshold_validation(l, N, dof, name):
    with pytest.raises(ValueError, match=name):
        cs.threshold(l, N, dof)


# ----------------------------------------------------------------------------- censored probability
def _reference(mu, s, r, eta):
    """scipy's normal cdf difference, on the lower tail (|mu|) where it is accurate."""
    a = np.sqrt(eta * s)
    sd = np.sqrt(r)
    mu = np.abs(mu)
    return scipy.stats.norm.cdf((a - mu) / sd) - scipy.stats.norm.cdf((-a - mu) / sd)


def _mp_log(mu, s, r, eta, dps=60):
    with mpmath.workdps(dps):
        a = mpmath.sqrt(mpmath.mpf(eta) * mpmath.mpf(s))
        sd = mpmath.sqrt(mpmath.mpf(r))
        mu = abs(mpmath.mpf(mu))  # symmetric; the lower tail needs no extra digits
        p = mpmath.ncdf((a - mu) / sd) - mpmath.ncdf((-a - mu) / sd)
        return float(mpmath.log(p))


def test_censored_probability_matches_normal_cdf_differences():
    rng = np.random.default_rng(0)
    mu = rng.normal(0, 3, 2000)
    s = rng.uniform(0.5, 8, 2000)
    r = rng.uniform(0.2, 4, 2000)
    eta = rng.uniform(0.01, 6, 2000)
    ref = _reference(mu, s, r, eta)
    got = cs.censored_probability(mu, s, r, eta)
    ok = ref > 1e-8  # where the scipy difference itself is accurate
    np.testing.assert_allclose(got[ok], ref[ok], rtol=1e-10)
    np.testing.assert_allclose(cs.log_censored_probability(mu, s, r, eta)[ok], np.log(ref[ok]),
                               rtol=1e-10, atol=1e-12)


@pytest.mark.parametrize("mu_sd", [-40.0, -25.0, -8.0, -1.0, 0.0, 0.3, 3.0, 12.0, 40.0, 60.0])
@pytest.mark.parametrize("eta", [1e-6, 0.4549, 2.0, 9.0])
def test_log_censored_probability_against_mpmath(mu_sd, eta):
    s, r = 5.0, 1.5
    mu = mu_sd * np.sqrt(r)
    got = cs.log_censored_probability(mu, s, r, eta)
    assert np.isfinite(got)  # no underflow, even at 40-60 sd where P < 1e-300
    assert got == pytest.approx(_mp_log(mu, s, r, eta), rel=1e-11, abs=1e-13)
    lin = cs.censored_probability(mu, s, r, eta)
    assert lin == pytest.approx(np.exp(_mp_log(mu, s, r, eta)), rel=1e-11, abs=1e-320)


def test_narrow_interval_keeps_relative_accuracy():
    """l close to N: a tiny eta makes the silent interval narrow; no cancellation near the mean."""
    for eta in [1e-12, 1e-18]:
        for mu in [0.0, 0.7, 5.0]:
            got = cs.log_censored_probability(mu, 2.0, 1.0, eta)
            assert got == pytest.approx(_mp_log(mu, 2.0, 1.0, eta), rel=1e-9)


def test_censored_probability_edge_values_and_validation():
    assert cs.censored_probability(0.3, 4.0, 1.0, 0.0) == 0.0
    assert cs.log_censored_probability(0.3, 4.0, 1.0, 0.0) == -np.inf
    assert cs.censored_probability(0.0, 1.0, 1.0, 1e6) == pytest.approx(1.0)
    assert np.shape(cs.censored_probability(np.zeros((3, 1)), np.ones(4), 1.0, 1.0)) == (3, 4)
    for kwargs, name in [({"r": 0.0}, "r"), ({"r": -1.0}, "r"), ({"s": -1.0}, "s"),
                         ({"eta": -0.1}, "eta"), ({"mu": np.inf}, "mu")]:
        args = {"mu": 0.0, "s": 1.0, "r": 1.0, "eta": 1.0} | kwargs
        with pytest.raises(ValueError, match=name):
            cs.censored_probability(**args)


@settings(max_examples=60, deadline=None)
@given(mu=st.floats(-50, 50), s=st.floats(0.01, 50), r=st.floats(0.01, 50),
       eta=st.floats(0, 30), dmu=st.floats(0, 5), deta=st.floats(0, 5))
def test_censored_probability_properties(mu, s, r, eta, dmu, deta):
    p = cs.censored_probability(mu, s, r, eta)
    assert 0.0 <= p <= 1.0
    assert cs.censored_probability(-mu, s, r, eta) == pytest.approx(p, rel=1e-12, abs=1e-300)
    # farther from the centre: less likely to be silent; larger threshold: more likely silent
    assert cs.censored_probability(abs(mu) + dmu, s, r, eta) <= p * (1 + 1e-12) + 1e-300
    assert cs.censored_probability(mu, s, r, eta + deta) >= p * (1 - 1e-12)
    lp = cs.log_censored_probability(mu, s, r, eta)
    if p > 1e-300:
        assert lp == pytest.approx(np.log(p), rel=1e-11, abs=1e-14)


def test_censored_probability_against_monte_carlo():
    rng = np.random.default_rng(1)
    for mu, s, r, eta in [(0.0, 5.0, 1.0, 0.455), (1.3, 6.8, 1.0, 0.455), (-2.0, 3.0, 2.0, 2.7)]:
        nu = rng.normal(mu, np.sqrt(r), 400_000)
        silent = np.abs(nu) < np.sqrt(eta * s)
        se = silent.std() / np.sqrt(silent.size)
        assert abs(silent.mean() - cs.censored_probability(mu, s, r, eta)) / se < 4.5


# ----------------------------------------------------------------------------- bivariate normal
def test_bivariate_normal_cdf_against_scipy():
    rng = np.random.default_rng(2)
    pts = list(itertools.product([-2.5, -0.7, 0.0, 0.4, 1.9], repeat=2))
    rhos = [-0.999, -0.6, 0.0, 0.35, 0.9, 0.99999]
    for rho in rhos:
        mvn = scipy.stats.multivariate_normal(mean=[0, 0], cov=[[1, rho], [rho, 1]])
        for h, k in pts:
            ref = mvn.cdf([h, k])
            assert cs.bivariate_normal_cdf(h, k, rho) == pytest.approx(ref, abs=2e-7)
    h, k, rho = rng.normal(size=(3, 200))
    rho = np.tanh(rho)
    got = cs.bivariate_normal_cdf(h, k, rho)  # vectorized
    for i in range(0, 200, 25):
        mvn = scipy.stats.multivariate_normal(mean=[0, 0], cov=[[1, rho[i]], [rho[i], 1]])
        assert got[i] == pytest.approx(mvn.cdf([h[i], k[i]]), abs=2e-7)
    # degenerate correlations and infinite bounds
    assert cs.bivariate_normal_cdf(0.3, 1.0, 1.0) == pytest.approx(scipy.stats.norm.cdf(0.3))
    assert cs.bivariate_normal_cdf(0.3, 1.0, -1.0) == pytest.approx(
        scipy.stats.norm.cdf(0.3) + scipy.stats.norm.cdf(1.0) - 1)
    assert cs.bivariate_normal_cdf(np.inf, 0.5, 0.3) == pytest.approx(scipy.stats.norm.cdf(0.5))
    assert cs.bivariate_normal_cdf(-np.inf, 0.5, 0.3) == 0.0
    # exact Owen's-T identity at the origin: 1/4 + arcsin(rho) / (2 pi)
    for rho in [-0.8, 0.0, 0.5]:
        assert cs.bivariate_normal_cdf(0.0, 0.0, rho) == pytest.approx(
            0.25 + np.arcsin(rho) / (2 * np.pi), abs=1e-14)


def test_bivariate_rectangle_against_scipy():
    rng = np.random.default_rng(3)
    for _ in range(10):
        lo = rng.normal(size=2) - 1
        hi = lo + rng.uniform(0.1, 3, 2)
        rho = rng.uniform(-0.95, 0.95)
        mvn = scipy.stats.multivariate_normal(mean=[0, 0], cov=[[1, rho], [rho, 1]])
        ref = mvn.cdf(hi, lower_limit=lo)
        got = cs.bivariate_rectangle(lo[0], hi[0], lo[1], hi[1], rho)
        assert got == pytest.approx(ref, abs=5e-7)


# ----------------------------------------------------------------------------- likelihoods
def _feedback_sensor_total(hx, hx_pred, s, r, eta):
    """sum over outcomes of Proposition 1 for one sensor: the send region's integral + silent."""
    a = np.sqrt(eta * s)

    def dens(zz):
        return np.exp(cs.log_likelihood_feedback([True], [zz], [hx], [hx_pred], [s], [r], eta))

    sent = (integrate.quad(dens, -np.inf, hx_pred - a, epsabs=1e-13)[0]
            + integrate.quad(dens, hx_pred + a, np.inf, epsabs=1e-13)[0])
    silent = np.exp(cs.log_likelihood_feedback([False], [0.0], [hx], [hx_pred], [s], [r], eta))
    return sent + silent


@pytest.mark.parametrize("hx, hx_pred, s, r, eta", [(0.0, 0.0, 5.0, 1.0, 0.455),
                                                     (3.1, 1.0, 6.8, 1.0, 0.455),
                                                     (-2.0, 4.0, 2.5, 0.7, 2.7),
                                                     (10.0, 0.0, 1.0, 1.0, 0.1)])
def test_feedback_likelihood_sums_to_one(hx, hx_pred, s, r, eta):
    """Propositions 1-2: as a density on the possible outcomes (a sent z lies in the send region)
    the full likelihood sums to one; sensors are independent given x and the feedback."""
    assert _feedback_sensor_total(hx, hx_pred, s, r, eta) == pytest.approx(1.0, abs=1e-9)
    two = cs.log_likelihood_feedback([True, False], [0.4, 9.9], [hx, hx + 1], [hx_pred, 0.0],
                                     [s, 2 * s], [r, r], eta)
    one_a = cs.log_likelihood_feedback([True], [0.4], [hx], [hx_pred], [s], [r], eta)
    one_b = cs.log_likelihood_feedback([False], [9.9], [hx + 1], [0.0], [2 * s], [r], eta)
    assert two == pytest.approx(one_a + one_b, rel=1e-14)


def _no_feedback_total(hx, C, r, eta, version):
    """Sum over the 4 patterns (N = 2) of the integral of exp(log-likelihood) over the received
    values. Gauss-Hermite around h^T x: the integrand is N(z; h^T x, r) g(z) with g smooth, so
    the integral is sum_k W_k g(z_k), g = exp(log-likelihood) / N(z; h^T x, r)."""
    sd = np.sqrt(r)
    parts = {}
    for pat in itertools.product([True, False], repeat=2):
        obs = [i for i in range(2) if pat[i]]
        grids = [hx[i] + sd[i] * GH_X if i in obs else np.zeros(1) for i in range(2)]
        wts = [GH_W if i in obs else np.ones(1) for i in range(2)]
        z1, z2 = np.meshgrid(*grids, indexing="ij")
        z = np.stack([z1, z2], axis=-1)
        w = np.outer(*wts)
        sent = np.broadcast_to(np.array(pat), z.shape)
        ll = cs.log_likelihood_no_feedback(sent, z, np.broadcast_to(hx, z.shape), C, r, eta,
                                           version=version)
        gauss = np.where(sent, scipy.stats.norm.logpdf(z, hx, sd), 0.0).sum(axis=-1)
        parts[pat] = float(np.sum(w * np.exp(ll - gauss)))
    return sum(parts.values()), parts


@pytest.mark.parametrize("t", [0, 1, 5, 19])
@pytest.mark.parametrize("l", [1.0, 0.5, 1.6])
def test_no_feedback_printed_does_not_sum_to_one_corrected_does(t, l):
    """Proposition 3: the printed (16) sums to 1 + P(1 silent) + P(2 silent) + P(both silent)
    (2.25 for independent innovations and l/N = 1/2); the corrected likelihood sums to one.
    t = 0 (the first step with x0 known) has perfectly correlated local errors (rho = 1)."""
    sc = cs.LinearScenario()
    C = sc.local_filters()["C"][t]
    r = sc.rvec
    eta = cs.threshold(l, 2)
    hx = np.array([3.0, 3.0])
    tot_c, _ = _no_feedback_total(hx, C, r, eta, "corrected")
    # at t = 0 (rho = 1) the integrand has kinks and Gauss-Hermite converges slowly; the
    # simulation test below checks that case to Monte Carlo accuracy
    assert tot_c == pytest.approx(1.0, abs=1e-7 if t else 5e-3)
    tot_p, parts = _no_feedback_total(hx, C, r, eta, "printed")
    q = 1 - l / 2  # P(one given sensor silent) = P(chi2_1 < eta)
    s = np.diag(C) + r
    rho = C[0, 1] / np.sqrt(s[0] * s[1])
    b = np.sqrt(eta)
    both = cs.bivariate_rectangle(-b, b, -b, b, rho)
    assert tot_p == pytest.approx(1 + 2 * q + both, abs=1e-7)
    assert tot_p > 1.2


def test_no_feedback_printed_closed_form_independent_sensors():
    """With uncorrelated local errors the printed sum is (2 - l/N)^N."""
    C = np.diag([4.5, 4.5])
    r = np.ones(2)
    eta = cs.threshold(1, 2)
    tot, _ = _no_feedback_total(np.array([0.0, 1.0]), C, r, eta, "printed")
    assert tot == pytest.approx((2 - 0.5) ** 2, abs=1e-7)


@pytest.mark.parametrize("t", [0, 4])
def test_no_feedback_corrected_matches_simulation_of_the_papers_model(t):
    """Simulate the paper's model (21): local errors e ~ N(0, C) independent of x, n ~ N(0, r).
    Pattern frequencies and E[z_1 ; pattern] agree with the corrected likelihood's integrals
    (at t = 0 the pattern (sent, sent) follows as 1 minus the smooth patterns)."""
    sc = cs.LinearScenario()
    C = sc.local_filters()["C"][t]
    r = sc.rvec
    eta = cs.threshold(1, 2)
    hx = np.array([1.0, 1.0])
    rng = np.random.default_rng(4)
    M = 400_000
    eps = rng.multivariate_normal(np.zeros(2), C, M, method="eigh")
    n = rng.normal(0, 1, (M, 2)) * np.sqrt(r)
    z = hx + n
    nu = n + eps  # z - h^T xhat with xhat = x - e
    sent = nu**2 >= eta * (np.diag(C) + r)
    _, parts = _no_feedback_total(hx, C, r, eta, "corrected")
    parts[True, True] = 1 - parts[True, False] - parts[False, True] - parts[False, False]
    for pat, prob in parts.items():
        hit = np.all(sent == np.array(pat), axis=1)
        se = np.sqrt(prob * (1 - prob) / M)
        assert abs(hit.mean() - prob) / se < 4.5
    # first moment of z_1 on the pattern (True, False), by quadrature
    sd = np.sqrt(r[0])
    zi = hx[0] + sd * GH_X
    zz = np.zeros((GH_X.size, 2))
    zz[:, 0] = zi
    ll = cs.log_likelihood_no_feedback(np.broadcast_to([True, False], zz.shape), zz,
                                       np.broadcast_to(hx, zz.shape), C, r, eta)
    dens_w = GH_W * np.exp(ll - scipy.stats.norm.logpdf(zi, hx[0], sd))
    m1 = np.sum(dens_w * zi)
    hit = np.all(sent == [True, False], axis=1)
    vals = np.where(hit, z[:, 0], 0.0)
    assert abs(vals.mean() - m1) / (vals.std() / np.sqrt(M)) < 4.5


def test_printed_proposition3_is_constant_in_x():
    """With the paper's law (21) the printed (16) differs from the CFoMD likelihood by a
    constant in x: the missing-data factor carries no information about the state."""
    sc = cs.LinearScenario()
    C = sc.local_filters()["C"][6]
    eta = cs.threshold(1, 2)
    hx = np.linspace(-5, 5, 11)[:, None] * np.ones(2)
    for pat in [(True, False), (False, False), (True, True)]:
        sent = np.broadcast_to(pat, hx.shape)
        z = np.full(hx.shape, 0.7)
        printed = cs.log_likelihood_no_feedback(sent, z, hx, C, sc.rvec, eta, version="printed")
        gauss = np.where(sent, scipy.stats.norm.logpdf(z, hx, 1.0), 0.0).sum(axis=-1)
        diff = printed - gauss
        np.testing.assert_allclose(diff, diff[0], atol=1e-12)
        corrected = cs.log_likelihood_no_feedback(sent, z, hx, C, sc.rvec, eta)
        if any(pat):  # the corrected version depends on x through the received sensors
            assert np.ptp(corrected - gauss) > 0.01


def test_no_feedback_validation():
    with pytest.raises(ValueError, match="N <= 2"):
        cs.log_likelihood_no_feedback(np.ones(3, bool), np.zeros(3), np.zeros(3), np.eye(3),
                                      1.0, 1.0)
    with pytest.raises(ValueError, match="version"):
        cs.log_likelihood_no_feedback(np.ones(2, bool), np.zeros(2), np.zeros(2), np.eye(2),
                                      1.0, 1.0, version="typo")


def test_truncated_normal_sampler():
    rng = np.random.default_rng(7)
    for lo, hi in [(-1.0, 0.5), (0.3, 2.0), (-3.0, -2.5), (4.0, 4.5), (38.0, 39.0), (-60.0, -59.0),
                   (-0.01, 0.01)]:
        u = rng.random(100_000)
        zz = cs.probability.truncated_normal(u, np.full_like(u, lo), np.full_like(u, hi))
        assert np.all((zz >= lo) & (zz <= hi)) and np.all(np.isfinite(zz))
        if abs(lo) < 30:
            ref = scipy.stats.truncnorm(lo, hi)
            se = ref.std() / np.sqrt(u.size)
            assert abs(zz.mean() - ref.mean()) / se < 4.5
        else:  # beyond double precision tails: exponential approximation next to the bound
            near = lo if lo > 0 else hi
            assert abs(zz.mean() - near) < 1.5 / abs(near)


# ----------------------------------------------------------------------------- scenario
def test_scenario_defaults_are_the_papers_and_choices_are_stated():
    sc = cs.LinearScenario()
    assert (sc.N, sc.r, sc.sigma2, sc.T, sc.x0, sc.dt) == (2, 1.0, 4.0, 20, (0.0, 10.0), 1.0)
    np.testing.assert_allclose(sc.F, [[1, 1], [0, 1]])
    np.testing.assert_allclose(sc.Q, 4 * np.array([[0.25, 0.5], [0.5, 1.0]]))
    np.testing.assert_allclose(sc.H, [[1, 0], [1, 0]])
    for key in ["PF prior", "initial state", "initial cross-covariance", "feedback 'state'",
                "feedback 'state+cov'", "feedback moments", "random selection", "time axis"]:
        assert key in sc.choices and sc.choices[key]
    sc4 = cs.LinearScenario(N=4, r=(1, 1, 2, 2), sigma2=1.0, T=5)
    assert sc4.rvec.tolist() == [1, 1, 2, 2] and len(sc4.sensor_groups()) == 2


@pytest.mark.parametrize("kwargs, name", [({"N": 0}, "N"), ({"N": 1.5}, "N"), ({"r": 0.0}, "r"),
                                          ({"r": -1.0}, "r"), ({"r": (1.0, -1.0)}, "r"),
                                          ({"sigma2": -4}, "sigma2"),
                                          ({"sigma2": float("nan")}, "sigma2"),
                                          ({"T": 0}, "T"), ({"x0": (1, 2, 3)}, "x0"),
                                          ({"P0": -np.eye(2)}, "P0"), ({"h": (0, 0)}, "h"),
                                          ({"feedback_moments": "x"}, "feedback_moments")])
def test_scenario_validation(kwargs, name):
    with pytest.raises(ValueError, match=name):
        cs.LinearScenario(**kwargs)


def test_deterministic_motion_sigma2_zero_is_a_legitimate_limit():
    """sigma2 = 0 (no process noise) with a known start: the target moves at constant velocity,
    every local filter's covariance stays 0 (exact knowledge) and the fusion centre's particles
    all sit on the true track, so the position error is exactly 0 for every scheme."""
    sc = cs.LinearScenario(sigma2=0.0, T=5)
    x, z = sc.sample(np.random.default_rng(1), 3)
    truth = sc.x0[0] + sc.x0[1] * np.arange(sc.T + 1)
    np.testing.assert_allclose(x[..., 0], np.broadcast_to(truth, x.shape[:-1]), rtol=0,
                               atol=1e-12)
    assert np.all(np.isfinite(z))
    for scheme in ("all-send", "cfwmd", "cfomd", "random"):
        rmse = cs.run(sc, scheme, l=1, n_trials=4, n_particles=20, seed=3).rmse_position
        assert np.all(np.isfinite(rmse.value)) and np.max(rmse.value) < 1e-9, (scheme, rmse)


@pytest.mark.parametrize("l", [np.array(1.0), np.float64(1.0), np.int64(1), 1])
def test_threshold_takes_numpy_scalars_and_0d_arrays(l):
    assert cs.threshold(l, 2) == cs.threshold(1.0, 2)


@pytest.mark.parametrize("l", [np.array([1.0]), True, np.bool_(True), "1", float("nan"), 0, 3])
def test_threshold_rejects_non_numbers_and_out_of_range(l):
    with pytest.raises(ValueError, match="l "):
        cs.threshold(l, 2)


def test_local_filters_match_filterpy_and_cross_covariance_recursion():
    """The sensors' own KFs (filterpy) and the paper's cross-covariance recursion (22)-(23)."""
    sc = cs.LinearScenario(P0=np.diag([2.0, 1.0]))
    loc = sc.local_filters()
    kf = KalmanFilter(dim_x=2, dim_z=1)
    kf.F, kf.Q, kf.H, kf.R = sc.F, sc.Q, np.array([[1.0, 0.0]]), np.array([[1.0]])
    kf.x, kf.P = np.array(sc.x0), sc.dynamics.P0.copy()
    Pij = sc.dynamics.P0.copy()  # P^{ij}_{0|0}: both sensors start from the same x0
    h = np.array([1.0, 0.0])
    for t in range(sc.T):
        kf.predict()
        np.testing.assert_allclose(loc["P_pred"][t, 0], kf.P, rtol=1e-12)
        np.testing.assert_allclose(loc["s"][t, 0], kf.P[0, 0] + 1.0, rtol=1e-12)
        Ptilde = sc.F @ Pij @ sc.F.T + sc.Q  # (22)
        np.testing.assert_allclose(loc["C"][t], [[kf.P[0, 0], Ptilde[0, 0]],
                                                 [Ptilde[0, 0], kf.P[0, 0]]], rtol=1e-12)
        kf.update(np.array([0.0]))
        w = loc["gain"][t, 0]
        np.testing.assert_allclose(w, kf.K[:, 0], rtol=1e-12)
        A = np.eye(2) - np.outer(w, h)
        Pij = A @ Ptilde @ A.T  # (23)


def test_local_decisions_send_at_the_design_rate():
    """Without feedback each sensor's innovation is exactly N(0, s): it sends w.p. l/N."""
    sc = cs.LinearScenario(N=2, P0=np.eye(2))
    rng = np.random.default_rng(5)
    x, z = sc.sample(rng, 20000)
    fc = cs.LinearFusionCentre(sc, "cfwmd", "none", "corrected", cs.threshold(0.7, 2), 0.7, z,
                               rng.random(z.shape))
    rate = fc.sent.mean(axis=0)  # (T, N)
    se = np.sqrt(0.35 * 0.65 / 20000)
    assert np.max(np.abs(rate - 0.35)) / se < 4.5


@pytest.mark.parametrize("offset", [0.0, 1e7])
def test_filter_weights_equal_proposition_1_and_2(offset):
    """The FC's fast grouped log-weights equal log_likelihood_feedback up to a constant per
    trial (which the filter drops), also far from the origin (the grouped Gaussian term is
    centred: no cancellation)."""
    sc = cs.LinearScenario(N=3, x0=(offset, 10.0))
    rng = np.random.default_rng(6)
    _, z = sc.sample(rng, 5)
    eta = cs.threshold(1.2, 3)
    x = rng.normal([9.0 + offset, 10.0], [2.0, 1.0], (5, 40, 2))
    for feedback in ["state", "state+cov"]:
        fc = cs.LinearFusionCentre(sc, "cfwmd", feedback, "corrected", eta, 1.2, z,
                                   rng.random(z.shape))
        fc.pred_mean = rng.normal([10.0 + offset, 10.0], 1.0, (5, 2))
        fc.pred_cov = np.broadcast_to(np.diag([3.0, 2.0]), (5, 2, 2)).copy()
        got = fc.log_weight(1, x)
        sent = fc.sent[:, 0]
        s = (np.full((5, 3), sc.local_filters()["s"][0]) if feedback == "state"
             else np.full((5, 3), 3.0 + 1.0))
        ref = cs.log_likelihood_feedback(sent[:, None], z[:, None, 0], x @ sc.H.T,
                                         (fc.pred_mean @ sc.H.T)[:, None], s[:, None], sc.rvec,
                                         eta)
        # at 1e7 the inputs carry an absolute rounding of ~2e-9 (the expanded form
        # n y^2 - 2 y sum z + sum z^2 would lose everything: 1e14 * eps = 1e-2)
        np.testing.assert_allclose(got - got[:, :1], ref - ref[:, :1], rtol=1e-11,
                                   atol=1e-11 + 1e-14 * offset)
        assert 0 < sent.sum() < sent.size


# ----------------------------------------------------------------------------- runs
SMALL = dict(n_trials=320, n_particles=250, seed=11)


@functools.cache
def _run(scheme, feedback="state", N=2, l=1.0, likelihood="corrected", **kw):
    opts = SMALL | kw
    return cs.run(cs.LinearScenario(N=N), scheme, l=l, feedback=feedback, likelihood=likelihood,
                  **opts)


def test_run_identical_for_any_chunking_and_executor():
    sc = cs.LinearScenario(T=6)
    base = dict(l=1, n_trials=70, n_particles=60, seed=3, block_size=16)
    for scheme, fb in [("cfwmd", "state+cov"), ("cfwmd", "none"), ("random", "state")]:
        a = cs.run(sc, scheme, feedback=fb, **base)
        b = cs.run(sc, scheme, feedback=fb, chunk_size=16, **base)
        with concurrent.futures.ThreadPoolExecutor(2) as ex:
            c = cs.run(sc, scheme, feedback=fb, chunk_size=32, executor=ex, **base)
        assert np.array_equal(a.mc.samples, b.mc.samples)
        assert np.array_equal(a.mc.samples, c.mc.samples)
        assert np.array_equal(a.rmse_position.value, c.rmse_position.value)


def test_result_fields():
    res = _run("cfwmd")
    T = res.scenario.T
    for curve in (res.rmse_position, res.rmse_velocity, res.transmissions, res.ess):
        assert curve.value.shape == curve.stderr.shape == (T,)
        assert np.all(np.isfinite(curve.value)) and np.all(curve.stderr > 0)
    assert res.time.tolist() == list(range(1, T + 1))
    assert res.collapsed == 0
    v, se = res.time_averaged_rmse("velocity")
    assert v > 0 and se > 0
    with pytest.raises(ValueError, match="component"):
        res.rmse("acceleration")


def test_scheme_ordering_feedback():
    """Fig. 1's claim with paired errors: all-send < CFwMD < CFoMD < random selection."""
    order = [_run("all-send"), _run("cfwmd"), _run("cfomd"), _run("random")]
    for better, worse in itertools.pairwise(order):
        diff, se = cs.paired_difference(better, worse)
        assert diff < 0 and -diff / se > 4, (better.scheme, worse.scheme, diff, se)


def test_covariance_feedback_meets_the_bandwidth_target_better():
    """Table I's claim at N = 4, l = 2: CFwMD2 (state+cov feedback) sends l on average, CFwMD
    (state only, local s) clearly fewer."""
    a = _run("cfwmd", "state", N=4, l=2.0, n_trials=160)
    b = _run("cfwmd", "state+cov", N=4, l=2.0, n_trials=160)
    va, sa = a.average_transmissions
    vb, sb = b.average_transmissions
    assert (2 - va) / sa > 6
    assert abs(vb - 2) / sb < 4.5
    assert abs(vb - 2) < abs(va - 2)


def test_transmissions_meet_the_design_target():
    """Without feedback the local innovations are exactly N(0, s): E[#sent] = l at every step.
    Random selection: l; all-send: N."""
    for scheme in ["cfomd", "random"]:
        res = _run(scheme, "none", l=1.0)
        v, se = res.average_transmissions
        assert abs(v - 1.0) / se < 4.5
        tr = res.transmissions
        assert np.max(np.abs(tr.value - 1.0) / tr.stderr) < 4.5
    assert _run("all-send").average_transmissions == (2.0, 0.0)


def test_printed_proposition3_reproduces_cfomd_and_corrected_differs():
    """Printed (16): weights = CFoMD weights times a constant, so the filter is CFoMD's (up to
    rounding). The corrected likelihood changes the estimates."""
    small = dict(n_trials=128, n_particles=150)
    cfomd = _run("cfomd", "none", **small)
    printed = _run("cfwmd", "none", likelihood="printed", **small)
    corrected = _run("cfwmd", "none", likelihood="corrected", **small)
    np.testing.assert_allclose(printed.mc.samples, cfomd.mc.samples, rtol=1e-8, atol=1e-10)
    assert not np.allclose(corrected.mc.samples, cfomd.mc.samples)
    assert np.array_equal(corrected.transmissions.value, cfomd.transmissions.value)


def test_three_or_more_silent_sensors_give_the_same_bits_on_every_run():
    """Beyond two sensors the all-silent constant is SciPy's randomized quasi-Monte Carlo
    integral: it is seeded, so a run's estimates are the same bits every time (they differed
    by ~1e-13 from run to run before, in the printed likelihood with four sensors)."""
    from fusioncenter._compiled.bivariate_normal import log_silent_constant

    cov = np.eye(3) + 0.3
    a = np.array([1.0, 0.8, 1.2])
    assert log_silent_constant(cov, a) == log_silent_constant(cov, a)
    sc = cs.LinearScenario(N=4, r=(0.5, 1.0, 2.0, 1.0))
    runs = [cs.run(sc, "cfwmd", l=1.0, n_trials=16, n_particles=200, seed=7, feedback="none",
                   likelihood="printed").mc.samples for _ in range(2)]
    assert np.array_equal(runs[0], runs[1])


def _calibration(model, x, n_particles, seed):
    """Per-trial time-averaged (squared position error - posterior position variance)."""
    model.needs_cov = True
    out = particle.run_filter(model, np.random.default_rng(seed), x.shape[0], n_particles,
                              x.shape[1] - 1)
    err2 = (out.mean[..., 0] - x[:, 1:, 0]) ** 2
    d = (err2 - out.cov[..., 0, 0]).mean(axis=1)
    return d.mean() / (d.std(ddof=1) / np.sqrt(d.size))


def test_exact_filters_are_calibrated_and_proposition3_is_not():
    """A Bayes filter's mean squared error equals its mean posterior variance. That holds for
    CFwMD with feedback (Proposition 1 is exact) and for the exact no-feedback filter, and fails
    by a wide margin for CFoMD and for Proposition 3 (its law (21) ignores what the FC knows)."""
    sc = cs.LinearScenario()
    rng = np.random.default_rng(8)
    n, P = 240, 240
    x, z = sc.sample(rng, n)
    eta = cs.threshold(1, 2)
    u = rng.random(z.shape)
    fb = cs.LinearFusionCentre(sc, "cfwmd", "state", "corrected", eta, 1.0, z, u)
    nofb = cs.LinearFusionCentre(sc, "cfwmd", "none", "corrected", eta, 1.0, z, u)
    cfomd = cs.LinearFusionCentre(sc, "cfomd", "none", "corrected", eta, 1.0, z, u)
    exact = cs.fusion.ExactFusionCentre(sc, eta, z, nofb.sent)
    assert abs(_calibration(fb, x, P, 1)) < 4.5
    assert abs(_calibration(exact, x, P, 2)) < 4.5
    # their posterior variance is far too large (z about -12 here; -6 to -13 across seeds)
    assert _calibration(cfomd, x, P, 3) < -4.5
    assert _calibration(nofb, x, P, 4) < -4.5


def test_exact_no_feedback_beats_cfomd():
    """Without feedback the silent sensors still carry information, if the likelihood is exact.
    At l = 1.5 the paired gain is 6-12 standard errors across seeds; at the paper's l = 1 it is
    4-6 (heavy-tailed errors: runs of silent steps), at l = 0.5 not detectable with 320 trials
    (the RMSE is dominated by trials where nobody sends for several steps)."""
    exact = _run("cfwmd", "none", l=1.5, likelihood="exact")
    cfomd = _run("cfomd", "none", l=1.5)
    diff, se = cs.paired_difference(exact, cfomd)
    assert diff < 0 and -diff / se > 4, (diff, se)
    # the received sensors' hard constraints leave no consistent particle only rarely
    assert exact.collapsed < 0.01 * exact.mc.n_trials * exact.scenario.T


def test_run_validation():
    sc = cs.LinearScenario()
    good = dict(l=1, n_trials=2, n_particles=5, seed=0)
    for kwargs, name in [({"l": 0}, "l"), ({"l": 2.5}, "l"), ({"l": -1}, "l"),
                         ({"n_particles": 0}, "n_particles"), ({"n_trials": 0}, "n_trials"),
                         ({"feedback": "both"}, "feedback"), ({"likelihood": "x"}, "likelihood")]:
        with pytest.raises(ValueError, match=name):
            cs.run(sc, "cfwmd", **(good | kwargs))
    with pytest.raises(ValueError, match="scheme"):
        cs.run(sc, "cfwmd2", **good)
    with pytest.raises(ValueError, match="scenario"):
        cs.run(object(), "cfwmd", **good)
    with pytest.raises(ValueError, match="N <= 2"):
        cs.run(cs.LinearScenario(N=3), "cfwmd", feedback="none", **good)
    with pytest.raises(ValueError, match="paired"):
        cs.paired_difference(_run("cfwmd"), cs.run(sc, "cfomd", **good))


@settings(max_examples=10, deadline=None)
@given(scheme=st.sampled_from(cs.SCHEMES), feedback=st.sampled_from(cs.FEEDBACK),
       likelihood=st.sampled_from(cs.LIKELIHOODS), l=st.floats(0.2, 2.0),
       seed=st.integers(0, 1000))
def test_run_is_finite_for_any_configuration(scheme, feedback, likelihood, l, seed):
    res = cs.run(cs.LinearScenario(T=4), scheme, l=l, feedback=feedback, likelihood=likelihood,
                 n_trials=6, n_particles=30, seed=seed)
    assert np.all(np.isfinite(res.mc.samples))
    assert np.all((res.transmissions.value >= 0) & (res.transmissions.value <= 2))


# ----------------------------------------------------------------------------- the one loop
def _numpy_filter(model, rng, n, P, T, ess_threshold=1.0):
    """particle.run_filter written with the NumPy functions of particle (log_normalize,
    weighted_mean_cov, systematic_resample, resample): the loop the compiled kernels replace.
    Same draws in the same order."""
    x = np.array(model.initial(rng, n, P))
    logw = np.full((n, P), -np.log(P))
    means, esss = np.empty((n, T, model.dim)), np.empty((n, T))
    for t in range(1, T + 1):
        x = np.array(model.transition(rng, t, x))
        u = rng.random(n)
        lw, _ = particle.log_normalize(logw + model.log_weight(t, x))
        mean, cov = particle.weighted_mean_cov(x, lw)
        means[:, t - 1], esss[:, t - 1] = mean, particle.ess(lw)
        model.observe(t, mean, cov if getattr(model, "needs_cov", True) else None)
        todo = esss[:, t - 1] <= ess_threshold * P
        idx = particle.systematic_resample(lw, u)
        x = np.where(todo[:, None, None], particle.resample(x, idx), x)
        logw = np.where(todo[:, None], -np.log(P), lw)
    return means, esss


def _both(sc, scheme, feedback, likelihood="corrected", l=1.0, n=12, P=120, seed=5,
          ess_threshold=1.0):
    """The FC model through run_filter (compiled kernels) and through the NumPy loop."""
    rng = np.random.default_rng(seed)
    x, z = sc.sample(rng, n)
    u = rng.random(z.shape)
    eta = cs.threshold(l, sc.N)
    args = (sc, scheme, feedback, likelihood, eta, l, z, u)
    a = particle.run_filter(cs.LinearFusionCentre(*args), np.random.default_rng(seed + 1), n, P,
                            sc.T, ess_threshold=ess_threshold)
    fc = cs.LinearFusionCentre(*args)
    mean, ess = _numpy_filter(fc, np.random.default_rng(seed + 1), n, P, sc.T, ess_threshold)
    return a, mean, ess


_ENGINE_CASES = [
    *[(dict(), s, f, "corrected") for s in cs.SCHEMES for f in cs.FEEDBACK],
    (dict(), "cfwmd", "none", "printed"),
    *[(dict(N=4), "cfwmd", f, "corrected") for f in ("state", "state+cov")],
    (dict(N=4), "cfwmd", "none", "printed"),
    (dict(feedback_moments="particles"), "cfwmd", "state+cov", "corrected"),
    (dict(feedback_moments="particles"), "cfwmd", "state", "corrected"),
    (dict(N=3, h=((1, 0), (1, 0), (0.5, 1.0)), r=(1.0, 1.0, 2.0), P0=np.eye(2)), "cfwmd",
     "state", "corrected"),
    (dict(N=2, h=((1, 0), (1, 0.5))), "cfwmd", "none", "corrected"),
    (dict(N=2, r=(1.0, 2.0), P0=np.eye(2)), "cfwmd", "none", "corrected"),
    (dict(N=1), "cfwmd", "none", "corrected"),
    (dict(dt=0.5, sigma2=2.0), "cfwmd", "state+cov", "corrected"),
]


@pytest.mark.parametrize("kw, scheme, feedback, likelihood", _ENGINE_CASES)
def test_loop_with_kernels_equals_the_numpy_loop(kw, scheme, feedback, likelihood):
    """run_filter (compiled weight moments and resampling) and the same loop written with
    particle's NumPy functions draw the same random numbers and give the same estimates, up to
    rounding (sequential against pairwise sums)."""
    a, mean, ess = _both(cs.LinearScenario(T=8, **kw), scheme, feedback, likelihood)
    np.testing.assert_allclose(a.mean, mean, rtol=1e-8, atol=1e-9)
    np.testing.assert_allclose(a.ess, ess, rtol=1e-8)


def test_loop_adaptive_resampling_equals_the_numpy_loop():
    a, mean, ess = _both(cs.LinearScenario(T=10), "cfwmd", "state", ess_threshold=0.5)
    np.testing.assert_allclose(a.mean, mean, rtol=1e-8, atol=1e-9)
    np.testing.assert_allclose(a.ess, ess, rtol=1e-8)
    assert np.any(a.ess < 0.5 * 120) and np.any(a.ess > 0.5 * 120)


def test_sub_blocks_only_split_the_random_stream(monkeypatch):
    """Every operation of the FC model is row-wise; the sub-blocks only decide the order in
    which the filter's random numbers are drawn. With one sub-block per trial, _chunk equals
    run_filter run trial by trial on the same stream."""
    sc = cs.LinearScenario(T=8, N=3, h=((1, 0), (1, 0), (0.5, 1)))
    kw = dict(scenario=sc, scheme="cfwmd", feedback="state", likelihood="corrected",
              eta=cs.threshold(1.0, 3), l=1.0, n_particles=120, ess_threshold=1.0)
    monkeypatch.setattr(cs.fusion.linear, "_SUB_PARTICLES", 1)
    a = cs.dispatch._chunk(np.random.default_rng(3), 6, **kw)
    rng_data, rng_pf = cs.results.streams(np.random.default_rng(3))
    x, z = sc.sample(rng_data, 6)
    u = rng_data.random(z.shape)
    for i in range(6):
        fc = cs.LinearFusionCentre(sc, "cfwmd", "state", "corrected", kw["eta"], 1.0,
                                   z[i:i + 1], u[i:i + 1])
        out = particle.run_filter(fc, rng_pf, 1, 120, sc.T)
        assert np.array_equal(a[i:i + 1], cs.trial_columns(out, x[i:i + 1], fc.sent, 120))
    monkeypatch.setattr(cs.fusion.linear, "_SUB_PARTICLES", 1 << 15)
    c = cs.dispatch._chunk(np.random.default_rng(3), 6, **kw)
    assert not np.allclose(a, c)  # another split of the stream: other draws


@pytest.mark.parametrize("h", [1e-3, 0.05, 0.3, 0.6744897501960817, 1.0, 1.5, 2.5, 4.0, 7.0])
def test_silent_table_matches_the_exact_log_probability(h):
    tab = cs.tables.silent_table(h)
    rng = np.random.default_rng(0)
    m = np.concatenate([rng.uniform(-8, 8, 200_000), rng.uniform(-60, 60, 50_000),
                        np.arange(-4000, 4000) / 256, [47.999999, 48.0, 48.000001, 1e3]])
    ref = cs.probability.prob_inside(m, h, log=True)
    got = tab(m)
    assert np.all(np.isfinite(got))
    np.testing.assert_allclose(got, ref, rtol=1e-14, atol=5e-12)
    # the shifted form is the same arithmetic
    y = m.reshape(-1, 2)
    shift = rng.normal(0, 2, y.shape[0])
    got2 = tab.shifted(y, shift, 0.7, np.empty_like(y))
    exact = cs.probability.prob_inside((y - shift[:, None]) * 0.7, h, log=True)
    np.testing.assert_allclose(got2, exact, rtol=1e-14, atol=5e-12)


@pytest.mark.parametrize("t", [1, 2, 5, 19])
def test_no_feedback_tables_match_the_exact_region_probability(t):
    """The corrected Proposition 3: one sensor received (a table in c = z - h^T x) and both
    received (per-trial interpolation in c_0), against _log_rect_prob. (At t = 0 with x_0
    known the two local predictions are identical, the law is degenerate and the region
    probability has kinks: the fused filter evaluates it exactly there.)"""
    sc = cs.LinearScenario()
    assert abs(sc.local_filters()["C"][0][0, 1] - sc.local_filters()["C"][0][0, 0]) < 1e-12
    eta = cs.threshold(1, 2)
    C, r = sc.local_filters()["C"][t], sc.rvec
    a = np.sqrt(eta * (np.diag(C) + r))
    rng = np.random.default_rng(t)
    c = np.concatenate([rng.uniform(-10, 10, 4000), rng.uniform(-50, 50, 1000)])
    for pat, which in [((True, False), 0), ((False, True), 1)]:
        cov = C + np.diag(np.where(pat, 0.0, r))
        tab = cs.tables.region_table(tuple(a), tuple(map(tuple, cov)), pat, which)
        mean = np.zeros((c.size, 2))
        mean[:, which] = c
        ref = cs.probability.log_region_probability(mean, cov, a, pat)
        ok = ref > -700  # where the exact function still resolves the probability
        np.testing.assert_allclose(tab(c)[ok], ref[ok], rtol=1e-11, atol=1e-10)
    # both received: per-trial functions of c_0, with c_1 = c_0 + d_b
    pat = (True, True)
    d = rng.normal(0, 2, 6)
    c0 = rng.normal(rng.normal(0, 3, 6)[:, None], 2.0, (6, 300))

    def fn(b, x):
        return cs.probability.log_region_probability(np.stack([x, x + d[b]], -1), C, a, pat)

    got = cs.tables.interp_rows(fn, c0)
    ref = fn(np.arange(6)[:, None], c0)
    np.testing.assert_allclose(got, ref, rtol=1e-11, atol=1e-10)


def _log_region_accurate(mean, cov, a, pat):
    """The corrected Proposition 3 region probability as a log-sum-exp of the rectangles of
    ``log_bivariate_rectangle`` (relative-accurate in the log domain, no cancellation)."""
    sd = np.sqrt(np.diag(cov))
    rho = cov[0, 1] / (sd[0] * sd[1])
    lo, hi = (-a - mean) / sd, (a - mean) / sd
    inf = np.full(lo.shape[:-1], np.inf)
    ivs = [[(-inf, lo[..., i]), (hi[..., i], inf)] if pat[i] else [(lo[..., i], hi[..., i])]
           for i in range(2)]
    terms = [cs.probability.log_bivariate_rectangle(x[0], x[1], y[0], y[1], rho)
             for x in ivs[0] for y in ivs[1]]
    return scipy.special.logsumexp(np.stack(terms), axis=0)


@pytest.mark.parametrize("t", [0, 1, 19])
def test_no_feedback_region_probability_needs_no_log_domain_rectangle(t):
    """Issue 17 item 4, measured: over what the fig3 filter evaluates (N = 2, l = 1, one or both
    received, |c| <= 48) the region probability never enters a tail (it stays above e^-5), so
    the fast absolute-accuracy rectangle of ``log_region_probability`` is relative-accurate to
    1e-13 there against the log-domain ``log_bivariate_rectangle``; the interpolation table
    itself is the larger error (~4e-8 at the first step, where the two local predictions are
    identical and the function has large high derivatives; ~3e-11 later)."""
    sc = cs.LinearScenario()
    eta = cs.threshold(1, 2)
    C, r = sc.local_filters()["C"][t], sc.rvec
    a = np.sqrt(eta * (np.diag(C) + r))
    rng = np.random.default_rng(17)
    c = np.concatenate([rng.uniform(-10, 10, 150), rng.uniform(-48, 48, 50), [-0.016, 0.0]])
    for pat, which in [((True, False), 0), ((False, True), 1)]:
        cov = C + np.diag(np.where(pat, 0.0, r))
        mean = np.zeros((c.size, 2))
        mean[:, which] = c
        acc = _log_region_accurate(mean, cov, a, np.array(pat))
        assert acc.min() > -5.0
        fast = cs.probability.log_region_probability(mean, cov, a, pat)
        assert np.max(np.abs(np.expm1(fast - acc))) < 1e-13
        tab = cs.tables.region_table(tuple(a), tuple(map(tuple, cov)), pat, which)
        assert np.max(np.abs(np.expm1(tab(c.copy()) - acc))) < (1e-7 if t == 0 else 1e-10)
    if t:  # both received (at t = 0 the law is degenerate: evaluated exactly by the filter)
        mean = rng.uniform(-12, 12, (150, 2))
        acc = _log_region_accurate(mean, C, a, np.array([True, True]))
        assert acc.min() > -5.0
        fast = cs.probability.log_region_probability(mean, C, a, (True, True))
        assert np.max(np.abs(np.expm1(fast - acc))) < 1e-13


def test_every_public_function_and_class_has_numpydoc_sections():
    """Issue 15 item 5 for the censoring package: ``Parameters`` (where there are any) and
    ``Returns`` (functions) in every public function and class of every submodule."""
    import importlib
    import inspect
    import pkgutil

    mods = [cs] + [importlib.import_module(m.name)  # the subpackages' modules too
                   for m in pkgutil.walk_packages(cs.__path__, "fusioncenter.censoring.")]
    missing, n = [], 0
    for mod in mods:
        for name, obj in vars(mod).items():
            f = inspect.unwrap(obj) if callable(obj) else obj
            if name.startswith("_") or not (inspect.isfunction(f) or inspect.isclass(f)) \
                    or f.__module__ != mod.__name__:
                continue
            n += 1
            doc = inspect.getdoc(f) or ""
            params = [p for p in inspect.signature(f).parameters if p != "self"]
            need = (["Parameters"] if params else []) + ([] if inspect.isclass(f) else ["Returns"])
            missing += [f"{mod.__name__}.{name}: {s}" for s in need if f"{s}\n---" not in doc]
    assert n > 70 and not missing, missing


def test_streams_are_pcg64_for_the_data_and_sfc64_for_the_filter():
    rng = np.random.default_rng(np.random.SeedSequence(3).spawn(1)[0])
    data, pf = cs.results.streams(rng)
    assert isinstance(data.bit_generator, np.random.PCG64)
    assert isinstance(pf.bit_generator, np.random.SFC64)
    again = np.random.default_rng(np.random.SeedSequence(3).spawn(1)[0]).spawn(2)[0]
    assert np.array_equal(data.random(5), again.random(5))  # the data stream is rng.spawn's


def test_fast_log_inside_matches_the_careful_one():
    """The ndtr form used by CFwMD2's silent factor, including its fallbacks (deep tail,
    tiny h), against _inside."""
    rng = np.random.default_rng(4)
    m = np.concatenate([rng.normal(0, 3, 20000), rng.uniform(-60, 60, 2000)]).reshape(-1, 11)
    for h in [rng.uniform(0.01, 4, (m.shape[0], 1)), 1.3, 1e-8]:
        got = cs.probability.log_prob_inside(m, h)
        ref = cs.probability.prob_inside(m, np.broadcast_to(h, m.shape), log=True)
        np.testing.assert_allclose(got, ref, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("module, cls, runner", [
    ("vector", "VectorScenario", "vector_fusion"), ("nonlinear", "NonlinearScenario", "nonlinear")])
def test_run_dispatches_part_iv_b_scenarios(module, cls, runner):
    import importlib

    sc = getattr(importlib.import_module(f"fusioncenter.censoring.{module}"), cls)()
    kw = dict(l=2.0, n_trials=3, n_particles=50, seed=11, feedback="state")
    a = cs.run(sc, "cfwmd", **kw)
    b = importlib.import_module(f"fusioncenter.censoring.{runner}").run(sc, "cfwmd", **kw)
    assert np.array_equal(a.mc.samples, b.mc.samples)
    with pytest.raises(ValueError, match="LinearScenario"):
        cs.run(object(), "cfwmd", **kw)


# ----------------------------------------------------------------------------- tails (issue 17)
def _mp_log_rect(l1, u1, l2, u2, rho, dps=20):
    """``log P(l1 < X < u1, l2 < Y < u2)`` by mpmath: the integral of ``phi(x)`` times the
    conditional interval probability of ``Y`` (reflected into the lower tail, no cancellation),
    split at points clustered around the integrand's mode. 20 digits: the 29 references of the
    tests below agree with 30-digit ones to 3e-14 relative (the tests ask 1e-10), in half the
    time."""
    mp = mpmath

    with mp.workdps(dps):
        r = mp.mpf(rho)
        q = mp.sqrt(1 - r * r)

        def f(x):
            A = (l2 - r * x) / q if l2 != -np.inf else -mp.inf
            B = (u2 - r * x) / q if u2 != np.inf else mp.inf
            return mp.npdf(x) * (mp.ncdf(-A) - mp.ncdf(-B) if A > 0 else mp.ncdf(B) - mp.ncdf(A))

        lo, hi = max(float(l1), -80.0), min(float(u1), 80.0)
        grid = np.linspace(lo, hi, 201)
        vals = [f(mp.mpf(g)) for g in grid]  # once per point: f is the costly part
        logs = [float(mp.log(v)) if v > 0 else -np.inf for v in vals]
        xm = grid[int(np.argmax(logs))]
        off = np.concatenate([-np.geomspace(1e-4, 80, 30)[::-1], [0.0], np.geomspace(1e-4, 80, 30)])
        pts = [mp.mpf(p) for p in sorted({float(np.clip(xm + o, lo, hi)) for o in off} | {lo, hi})]
        pts = ([-mp.inf] if l1 == -np.inf else []) + pts + ([mp.inf] if u1 == np.inf else [])
        return float(mp.log(mp.quad(f, pts)))


def test_issue17_rectangle_examples():
    """Inclusion-exclusion gave 0 and 2.2e-16 here (cancellation); the true values are tiny."""
    p1 = cs.bivariate_rectangle(0, 1e-8, 0, 1e-8, 0)
    assert p1 == pytest.approx(1e-16 / (2 * np.pi), rel=1e-10)  # phi(0)^2 times the area
    p2 = cs.bivariate_rectangle(6, 6.001, -1, 1, 0.95)
    assert p2 == pytest.approx(math.exp(_mp_log_rect(6, 6.001, -1, 1, 0.95)), rel=1e-10)
    assert 9.8e-63 < p2 < 1.0e-62


_TAIL_CASES = [
    (-37, -36.7, -1.0, 2.0, 0.5), (10, np.inf, -1.0, 2.0, -0.95), (10, np.inf, 7.0, 10.1, 0.9),
    (37, np.inf, -1.0, 2.0, 0.0), (-np.inf, -20, -np.inf, 0.0, 0.5),
    (-np.inf, -37, -np.inf, -37, 0.99), (-np.inf, -8, -np.inf, -8, -0.95),
    (-8, -7.7, -1.0, 2.0, 0.99), (0.5, 0.50000001, -3.0, 0.6, 0.0), (3.0, 3.3, 0.0, 3.1, -0.5),
    (-1.0, 1.0, 25.0, 25.3, 0.9), (20.0, 20.3, 17.0, 20.1, 0.5), (-37, np.inf, -40.0, -36.9, -0.95),
]


@pytest.mark.parametrize("case", _TAIL_CASES)
def test_bivariate_rectangle_is_relative_accurate_in_the_tails(case):
    """Against mpmath, down to probabilities below 1e-300: relative error <= 1e-10 (the log
    version; the linear one wherever it does not underflow)."""
    ref = _mp_log_rect(*case)
    got = float(cs.probability.log_bivariate_rectangle(*case))
    assert abs(got - ref) <= 1e-10 * max(1.0, abs(ref) / 700), (got, ref)
    if ref > -700:
        lin = float(cs.bivariate_rectangle(*case))
        assert lin == pytest.approx(math.exp(ref), rel=1e-10)
    l1, u1, l2, u2, rho = case
    if l1 == -np.inf and l2 == -np.inf and ref > -700:  # the CDF itself
        assert float(cs.bivariate_normal_cdf(u1, u2, rho)) == pytest.approx(math.exp(ref),
                                                                             rel=1e-10)


def test_bivariate_rectangle_fast_path_unchanged_and_vectorized():
    """Where the probability is not small the inclusion-exclusion is kept, value for value."""
    rng = np.random.default_rng(4)
    l1, l2 = rng.normal(0, 1, (2, 50))
    u1, u2 = l1 + rng.uniform(0.5, 3, 50), l2 + rng.uniform(0.5, 3, 50)
    rho = rng.uniform(-0.9, 0.9, 50)
    got = cs.bivariate_rectangle(l1, u1, l2, u2, rho)
    from fusioncenter._compiled.bivariate_normal import cdf_owen as F
    ref = np.clip(F(u1, u2, rho) - F(l1, u2, rho) - F(u1, l2, rho) + F(l1, l2, rho), 0, 1)
    big = ref >= cs.probability.CAREFUL_BELOW
    assert big.sum() > 40 and np.array_equal(got[big], ref[big])
    assert cs.bivariate_rectangle(1.0, 0.0, 0.0, 1.0, 0.0) == 0.0  # an empty rectangle
    assert np.shape(cs.bivariate_rectangle(0.0, 1.0, 0.0, 1.0, 0.3)) == ()


_REGION_CASES = [((0.1, -0.2), 0.6), ((8.0, 0.3), 0.6), ((12.0, -9.0), -0.4), ((0.0, 14.0), 0.9),
                 ((25.0, 25.0), 0.6), ((-30.0, 3.0), -0.95), ((0.0, 0.0), 0.0)]


@pytest.mark.parametrize("outside", [(False, False), (True, False), (False, True), (True, True)])
@pytest.mark.parametrize("c, corr", _REGION_CASES)
def test_log_region_probability_is_relative_accurate_in_the_tails(c, corr, outside):
    """The corrected Proposition 3's region probability (issue 17): the inclusion-exclusion it
    starts from is accurate to ~1e-16 absolute only, so far from the box it gave -inf or a log
    off by whole units; it is now the log-sum of its disjoint rectangles, each in the log
    domain, and matches mpmath to 1e-10 in relative terms down to probabilities ~1e-115."""
    sd = np.array([math.sqrt(2.0), math.sqrt(1.5)])
    cov = np.array([[2.0, corr * sd[0] * sd[1]], [corr * sd[0] * sd[1], 1.5]])
    a = np.array([1.0, 0.8])
    lo, hi = (-a - np.array(c)) / sd, (a - np.array(c)) / sd
    sides = [[(-np.inf, lo[i]), (hi[i], np.inf)] if outside[i] else [(lo[i], hi[i])]
             for i in range(2)]
    ref = float(mpmath.log(sum(mpmath.exp(_mp_log_rect(a0, b0, a1, b1, corr))
                               for a0, b0 in sides[0] for a1, b1 in sides[1])))
    got = float(cs.probability.log_region_probability(np.array(c), cov, a, outside))
    assert np.isfinite(got)
    assert abs(got - ref) <= 1e-10 * max(1.0, abs(ref)), (got, ref)


def test_groups_of_rows_orders_groups_by_first_sensor_and_names_bad_keys():
    from fusioncenter.censoring.scenarios import groups_of_rows

    groups = groups_of_rows(np.array([[2.0, 1.0], [1.0, 1.0], [2.0, 1.0]]))
    assert [g.tolist() for g in groups] == [[0, 2], [1]]
    for bad in (np.zeros((0, 2)), np.zeros(3), np.array([[np.nan, 1.0]])):
        with pytest.raises(ValueError, match="key"):
            groups_of_rows(bad)
