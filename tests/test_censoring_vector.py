"""fusioncenter.censoring, vector observations (zheng2014 Part IV(b)): the generalized chi-square
probability, Propositions 4-6, the scenario of Section VII.B and the particle filter."""

from __future__ import annotations

import concurrent.futures
import math

import mpmath as mp
import numpy as np
import pytest
import scipy.stats
from filterpy.kalman import KalmanFilter

from fusioncenter import censoring as cs
from fusioncenter import particle
from fusioncenter.censoring import ellipse, vector, vector_fusion, vector_likelihood


def _z(diff, se):
    return abs(diff) / se


# ----------------------------------------------------------------------------- threshold
@pytest.mark.parametrize("l,N", [(1, 2), (1, 4), (2, 4), (3, 4), (0.5, 2)])
def test_threshold_is_the_chi2_m_quantile(l, N):
    # chi2 with 2 degrees of freedom: P(chi2_2 >= eta) = exp(-eta / 2)
    assert cs.threshold(l, N, dof=2) == pytest.approx(-2.0 * math.log(l / N), rel=1e-12)
    for m in (1, 2, 3):
        eta = cs.threshold(l, N, dof=m)
        assert scipy.stats.chi2.sf(eta, m) == pytest.approx(l / N, rel=1e-10)


# ----------------------------------------------------------------------------- the probability
def _mp_isotropic(a, r):
    """log P(|u| < a), u ~ N((r, 0), I): mpmath, split quadrature (exact to ~1e-15)."""
    with mp.workdps(40):  # this reference's precision only, not the other tests'
        f = lambda rho: rho * mp.e ** (-(rho - r) ** 2 / 2 - rho * r) * mp.besseli(0, rho * r)  # noqa: E731
        return float(mp.log(mp.quad(f, mp.linspace(0, a, 200))))


def _mp_theta(b1, b2, a1, a2):
    """The theta integral of the module docstring in mpmath (an independent evaluation)."""
    b2 = abs(b2)
    with mp.workdps(20):
        f = lambda th: (a1 * mp.cos(th) * mp.npdf(a1 * mp.sin(th) - b1)  # noqa: E731
                        * (mp.ncdf(a2 * mp.cos(th) - b2) - mp.ncdf(-a2 * mp.cos(th) - b2)))
        return float(mp.log(mp.quad(f, mp.linspace(-mp.pi / 2, mp.pi / 2, 40))))


@pytest.mark.parametrize("sigma2", [0.3, 1.0, 2.5])
def test_isotropic_case_is_scipy_ncx2(sigma2):
    """cov = sigma2 I: q^T q / sigma2 is non-central chi-square (2 dof, nc = |mean|^2/sigma2),
    both tails: the lower (log cdf down to -60) and the upper (log P near 0, via ncx2.sf)."""
    rng = np.random.default_rng(0)
    for eta in (0.2, 1.386, 5.0, 20.0):
        for r in (0.0, 0.5, 1.0, 2.0, 4.0, 6.0, 9.0):
            ang = rng.uniform(0, 2 * np.pi)
            mean = r * np.array([np.cos(ang), np.sin(ang)])
            got = ellipse.log_censored_probability(mean, sigma2 * np.eye(2), eta)
            nc = r * r / sigma2
            x = eta / sigma2
            lcdf = scipy.stats.ncx2.logcdf(x, 2, nc) if nc else scipy.stats.chi2.logcdf(x, 2)
            if lcdf < -60:
                continue
            assert got == pytest.approx(lcdf, rel=1e-9, abs=1e-12)
            sf = scipy.stats.ncx2.sf(x, 2, nc) if nc else scipy.stats.chi2.sf(x, 2)
            if sf < 1e-3:  # upper tail: log P = log1p(-sf), relative accuracy of the small sf
                assert -got == pytest.approx(-math.log1p(-sf), rel=1e-8)


@pytest.mark.parametrize("a,r", [(2.0, 20.0), (0.3, 30.0), (1.0, 38.0), (8.0, 38.0)])
def test_far_tail_no_underflow_against_mpmath(a, r):
    """Where scipy's ncx2.logcdf loses accuracy or returns -inf (log P ~ -170 .. -720)."""
    got = ellipse.log_censored_probability([0.0, r], np.eye(2), a * a)
    assert np.isfinite(got)
    assert got == pytest.approx(_mp_isotropic(a, r), rel=1e-12)


def test_anisotropic_against_mpmath():
    rng = np.random.default_rng(1)
    for _ in range(3):
        a1, a2 = np.sort(np.exp(rng.uniform(np.log(0.3), np.log(6.0), 2)))
        r = rng.choice([0.5, 3.0, 8.0, 20.0])
        ang = rng.uniform(0, 2 * np.pi)
        b1, b2 = r * np.cos(ang), r * np.sin(ang)
        got = ellipse.log_canon(b1, b2, a1, a2)
        assert got == pytest.approx(_mp_theta(abs(b1), b2, a1, a2), rel=1e-11)


def test_against_monte_carlo_general_covariance():
    rng = np.random.default_rng(2)
    n = 400_000
    for _ in range(4):
        Aq = rng.normal(size=(2, 2))
        cov = Aq @ Aq.T + 0.2 * np.eye(2)
        mean = rng.normal(size=2) * 1.5
        eta = rng.uniform(0.5, 4.0)
        p = ellipse.censored_probability(mean, cov, eta)
        q = mean + rng.standard_normal((n, 2)) @ np.linalg.cholesky(cov).T
        freq = np.mean((q * q).sum(axis=1) < eta)
        assert _z(freq - p, math.sqrt(p * (1 - p) / n)) < 4


def test_rotation_invariance_and_one_dimension():
    rng = np.random.default_rng(3)
    mean, eta = np.array([0.7, -1.3]), 2.0
    cov = np.array([[1.5, 0.4], [0.4, 0.6]])
    th = 0.83
    Rot = np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]])
    a = ellipse.log_censored_probability(mean, cov, eta)
    b = ellipse.log_censored_probability(Rot @ mean, Rot @ cov @ Rot.T, eta)
    assert a == pytest.approx(b, rel=1e-13)
    # m = 1: the scalar factor Q(xi_1) - Q(xi_2) of Proposition 1
    mu, s, r = rng.normal(size=5) * 2, 1.7, 0.8
    got = ellipse.log_silent_probability(mu[:, None], [[s]], [[r]], eta)
    assert np.allclose(got, cs.log_censored_probability(mu, s, r, eta), rtol=1e-13)


def test_proposition4_q_is_the_whitened_innovation():
    """(35)-(38): P(nu^T S^-1 nu < eta), nu ~ N(mu, R), equals P(q^T q < eta) for
    q ~ N(S^-1/2 mu, S^-1/2 R S^-1/2), with the symmetric square root of the paper."""
    rng = np.random.default_rng(4)
    for _ in range(5):
        Ar, Ap = rng.normal(size=(2, 2)), rng.normal(size=(2, 2))
        R = Ar @ Ar.T + 0.3 * np.eye(2)
        S = R + Ap @ Ap.T
        mu = rng.normal(size=2) * 2
        w, V = np.linalg.eigh(S)
        Sm = V @ np.diag(w ** -0.5) @ V.T
        lhs = ellipse.log_silent_probability(mu, S, R, 1.386)
        rhs = ellipse.log_censored_probability(Sm @ mu, Sm @ R @ Sm, 1.386)
        assert lhs == pytest.approx(rhs, rel=1e-12)


def test_sampled_estimate_is_unbiased_with_the_binomial_error():
    rng = np.random.default_rng(5)
    mean, cov, eta = np.array([1.0, -0.5]), np.array([[0.8, 0.3], [0.3, 0.5]]), 1.386
    p = ellipse.censored_probability(mean, cov, eta)
    est = vector_likelihood.censored_probability_sampled(np.broadcast_to(mean, (2000, 2)), cov,
                                                         eta, n_samples=50, rng=rng)
    assert est.std() == pytest.approx(math.sqrt(p * (1 - p) / 50), rel=0.1)
    assert _z(est.mean() - p, est.std() / math.sqrt(est.size)) < 4


def test_tables_are_accurate():
    """The filter's interpolation: below 1e-6 (fixed ellipse) and 2e-5 (per trial) in log P."""
    rng = np.random.default_rng(6)
    for a1, a2 in [(1.18, 1.6), (1.2, 3.9), (2.5, 2.6), (3.5, 6.0)]:
        b = rng.uniform(-13, 13, (5000, 2))
        val = ellipse.log_silent_table((b[:, 0], b[:, 1]), np.array([a1, a2]))
        ref = ellipse.log_canon(b[:, 0], b[:, 1], a1, a2)
        assert np.max(np.abs(val - ref)) < 1e-6
    n, P = 24, 400
    for eta in (0.575, 2.77):
        mu = rng.uniform(0.3, 3, (n, 2))
        a = np.sort(np.sqrt(eta * (1 + mu)), axis=1)
        b = rng.normal(size=(n, P, 2)) * np.sqrt(mu)[:, None, :] + rng.normal(size=(n, 1, 2))
        val = ellipse.eval_silent(b, a)
        aa = np.broadcast_to(a[:, None, :], b.shape)
        ref = ellipse.log_canon(b[..., 0], b[..., 1], aa[..., 0], aa[..., 1])
        assert np.max(np.abs(val - ref)) < 2e-5


def test_truncated_draws_have_the_conditional_mean():
    """Imputation of a missing measurement: u ~ N(b, I) given the ellipse; its mean is
    b + grad log P(b) (differentiate P = int_E phi(u - b) du under the integral)."""
    rng = np.random.default_rng(7)
    a = np.array([1.2, 2.1])
    for b in ([0.3, -0.4], [1.5, 1.0], [3.0, 0.5]):
        b = np.array(b)
        u, left = cs.vector_fusion.sample_in_ellipse(rng, np.broadcast_to(b, (100_000, 2)), a)
        assert left == 0 and np.all(((u / a) ** 2).sum(axis=1) < 1)
        f, f1, f2, _ = ellipse.grid_terms(np.array([b[0]]), np.array([b[1]]), a[0], a[1], 64)
        mean = b + np.array([f1[0, 0], f2[0, 0]])
        se = u.std(axis=0) / math.sqrt(u.shape[0])
        assert np.all(np.abs(u.mean(axis=0) - mean) < 4 * se)


def _rejection_reference(rng, b, a, rounds):
    """The NumPy rejection rounds that ``vector_terms.ellipse_reject`` replaced."""
    inv_a2 = 1.0 / (a * a)
    out = rng.standard_normal(b.shape)
    out += b
    todo = np.flatnonzero(((out * out) * inv_a2).sum(axis=1) >= 1.0)
    for _ in range(rounds - 1):
        if todo.size == 0:
            break
        u = rng.standard_normal((todo.size, b.shape[1]))
        u += b[todo]
        ok = ((u * u) * inv_a2).sum(axis=1) < 1.0
        out[todo[ok]] = u[ok]
        todo = todo[~ok]
    return out, todo


@pytest.mark.parametrize("m", [1, 2])
def test_compiled_rejection_rounds_draw_as_the_numpy_rounds(m):
    """The rejection rounds of the silent draws (compiled) take the same draws and keep the
    same points as the NumPy rounds; with no rounds left over nothing else is drawn."""
    for seed in range(6):
        r = np.random.default_rng(seed)
        a = 1.0 + r.random(m)
        b = r.uniform(-0.7, 0.7, size=(int(r.integers(1, 3000)), m)) * a  # inside: accepted
        g1, g2 = (np.random.Generator(np.random.SFC64(seed)) for _ in range(2))
        ref, todo = _rejection_reference(g1, b, a, 40)
        assert todo.size == 0  # 40 rounds accept every point here: the sequential part idles
        got, left = cs.vector_fusion.sample_in_ellipse(g2, b, a, rounds=40)
        assert left == 0 and np.array_equal(got, ref) and g1.random() == g2.random()


def test_compiled_tables_evaluate_as_the_numpy_code():
    """The fixed table and the per-trial tables (compiled evaluation) give the NumPy
    evaluation's values bit for bit, the fixed table's fall-back beyond its extent included."""
    from fusioncenter.censoring import ellipse
    rng = np.random.default_rng(3)
    tab = ellipse.tables._fixed_table(1.3, 2.2)
    x1, x2 = np.abs(rng.normal(size=(2, 40, 70)) * 5)
    x1[0, 0] = 12.5
    t1, t2 = x1 / tab.h, x2 / tab.h
    far = np.maximum(t1, t2) >= tab.G - 1
    t1, t2 = np.where(far, 0.0, t1), np.where(far, 0.0, t2)
    i, j = t1.astype(np.intp), t2.astype(np.intp)
    t1, t2 = t1 - i, t2 - j
    c = tab.coef[:, i * (tab.G - 1) + j]
    ref = None
    for p in (3, 2, 1, 0):
        r = ((c[4 * p + 3] * t2 + c[4 * p + 2]) * t2 + c[4 * p + 1]) * t2 + c[4 * p]
        ref = r if ref is None else ref * t1 + r
    ref[far] = ellipse.log_canon(x1[far], x2[far], 1.3, 2.2)
    assert far.any() and np.array_equal(tab(x1, x2), ref)
    k, G = 5, 24
    f, f1, f2, f12 = rng.normal(size=(4, k, G, G))
    o1, o2, h1, h2 = rng.normal(size=k), rng.normal(size=k), rng.random(k) + 0.1, rng.random(k)
    per = ellipse.tables._Hermite2D(f, f1, f2, f12, o1, o2, h1, h2 + 0.1)
    y1 = o1[:, None] + (G - 1) * h1[:, None] * rng.uniform(-0.1, 1.1, (k, 300))
    y2 = o2[:, None] + (G - 1) * (h2[:, None] + 0.1) * rng.uniform(-0.1, 1.1, (k, 300))
    assert np.array_equal(per.rows(y1, y2), per(np.arange(k)[:, None], y1, y2)[0])


@pytest.mark.parametrize("kwargs, word", [
    ({"mean": [1.0, 2.0], "cov": [[1.0, 2.0], [2.0, 1.0]], "eta": 1.0}, "cov"),
    ({"mean": [1.0, 2.0, 3.0], "cov": np.eye(3), "eta": 1.0}, "mean"),
    ({"mean": [1.0, 2.0], "cov": np.eye(2), "eta": -1.0}, "eta"),
    ({"mean": [np.nan, 2.0], "cov": np.eye(2), "eta": 1.0}, "mean"),
])
def test_probability_validation(kwargs, word):
    with pytest.raises(ValueError, match=word):
        ellipse.log_censored_probability(**kwargs)


# ----------------------------------------------------------------------------- likelihoods
def test_feedback_likelihood_is_the_sum_of_its_factors():
    rng = np.random.default_rng(8)
    sent = np.array([True, False])
    z = rng.normal(size=(2, 2))
    Hx, Hp = rng.normal(size=(2, 2)), rng.normal(size=(2, 2))
    R = np.array([[2.0, 0.0], [0.0, 4.0]])
    S = R + np.array([[1.0, 0.3], [0.3, 2.0]])
    got = vector_likelihood.log_likelihood_feedback(sent, z, Hx, Hp, np.stack([S, S]),
                                                    np.stack([R, R]), 1.386)
    want = (scipy.stats.multivariate_normal(Hx[0], R).logpdf(z[0])
            + ellipse.log_silent_probability(Hx[1] - Hp[1], S, R, 1.386))
    assert got == pytest.approx(want, rel=1e-12)


def test_printed_proposition6_does_not_sum_to_one():
    """N = 2, l = 1: sum over outcomes = 1 + P_1 + P_2 + P_12 (P_j = 1 - l/N = 1/2), about 2.25
    as for independent innovations, never 1; the joint term checked by simulating the two
    sensors' own Kalman filters (the law (21)-(23))."""
    sc = vector.VectorScenario()
    t = 6
    mass = vector.printed_mass(sc, 1, t)
    assert 2.2 < mass < 2.35
    lf = sc.local_filters()
    cov = vector.silent_covariance(sc, lf["Sigma"][t - 1])
    p12 = math.exp(vector.log_all_silent(cov, lf["S"][t - 1], cs.threshold(1, 2, dof=2)))
    assert mass == pytest.approx(1 + 0.5 + 0.5 + p12, rel=1e-9)
    # Monte Carlo of the sensors' innovations at step t (no feedback: local filters only)
    rng = np.random.default_rng(9)
    n = 100_000
    x, z = sc.sample(rng, n)
    eta = cs.threshold(1, 2, dof=2)
    sent = vector.local_decisions(sc, eta, z)
    both = np.mean(~sent[:, t - 1, 0] & ~sent[:, t - 1, 1])
    assert _z(both - p12, math.sqrt(p12 * (1 - p12) / n)) < 4
    one = np.mean(~sent[:, t - 1, 0])
    assert _z(one - 0.5, math.sqrt(0.25 / n)) < 4


def test_printed_constant_single_sensor_is_exact():
    sc = vector.VectorScenario()
    lf = sc.local_filters()
    cov = vector.silent_covariance(sc, lf["Sigma"][3])
    eta = cs.threshold(1, 2, dof=2)
    assert math.exp(vector.log_all_silent(cov[:2, :2], lf["S"][3][:1], eta)) == \
        pytest.approx(0.5, rel=1e-12)


# ----------------------------------------------------------------------------- scenario
def test_scenario_defaults_are_the_papers():
    sc = vector.VectorScenario()
    assert (sc.N, sc.T, sc.x0, sc.sigma2, sc.dt, sc.m) == (2, 20, (0.0, 10.0), 4.0, 1.0, 2)
    assert np.array_equal(sc.Rs[0], np.diag([2.0, 4.0])) and np.array_equal(sc.Hs[1], np.eye(2))
    assert "sensors" in sc.choices and "silent probability" in sc.choices
    assert vector.VectorScenario(N=4, R=(2.0, 4.0)) == vector.VectorScenario(N=4)


@pytest.mark.parametrize("kwargs, word", [
    ({"N": 0}, "N"), ({"T": 0}, "T"), ({"sigma2": -1.0}, "sigma2"), ({"dt": 0.0}, "dt"),
    ({"R": ((1.0, 2.0), (2.0, 1.0))}, "R"), ({"R": (1.0, 2.0, 3.0)}, "R"),
    ({"H": ((1.0, 0.0, 0.0),)}, "H"), ({"x0": (0.0,)}, "x0"),
    ({"feedback_moments": "x"}, "feedback_moments"), ({"P0": ((1.0, 0.0), (0.0, -1.0))}, "P0"),
])
def test_scenario_validation(kwargs, word):
    with pytest.raises(ValueError, match=word):
        vector.VectorScenario(**kwargs)


@pytest.mark.parametrize("mean, eta", [((0.3, -0.2), 1.0), ((0.0, 0.0), 0.5), ((3.0, 1.0), 1.0),
                                       ((-2.0, -1.0), 9.0)])
def test_singular_covariance_is_the_exact_degenerate_limit(mean, eta):
    """Issue 17 item 2: a rank-one cov = lam v v^T (q moves on a line) is a valid law, not an
    error: P(q^T q < eta) = P(|z + w / sqrt(lam)| < sqrt((eta - |mean_perp|^2) / lam)) (0 if the
    line misses the disc); cov = 0: 1 or 0 as the mean lies inside or not."""
    v, lam = np.array([0.6, 0.8]), 2.0
    cov = lam * np.outer(v, v)
    mean = np.array(mean)
    w = float(v @ mean)
    rest = eta - (mean @ mean - w * w)
    if rest > 0:
        hw, c = mp.sqrt(rest / lam), w / mp.sqrt(lam)
        ref = float(mp.log(mp.ncdf(hw - c) - mp.ncdf(-hw - c)))
        got = float(ellipse.log_censored_probability(mean, cov, eta))
        assert got == pytest.approx(ref, rel=1e-13)
    else:
        assert ellipse.log_censored_probability(mean, cov, eta) == -np.inf
    assert ellipse.log_censored_probability(mean, np.zeros((2, 2)), eta) == (
        0.0 if mean @ mean < eta else -np.inf)
    # a batch mixing singular and regular covariances: each as on its own
    both = ellipse.log_censored_probability(mean, np.stack([cov, np.eye(2)]), eta)
    assert both[0] == ellipse.log_censored_probability(mean, cov, eta)
    assert both[1] == ellipse.log_censored_probability(mean, np.eye(2), eta)
    # the silent factor with a singular R: the same law after whitening by S
    S = np.diag([2.0, 3.0])
    Li = np.diag(1 / np.sqrt([2.0, 3.0]))
    assert ellipse.log_silent_probability(mean, S, cov, eta) == pytest.approx(
        float(ellipse.log_censored_probability(Li @ mean, Li @ cov @ Li, eta)), rel=1e-12, abs=0)


def test_too_elongated_covariance_is_an_error_not_a_wrong_number():
    """Between the singular limit (eigenvalue ratio <= 1e-12) and ratio 1e-6 the quadrature
    does not resolve the ellipse (it returned -101 for a true -0.653 at ratio 1e-10): refused."""
    assert float(ellipse.log_censored_probability([0.3, 0.2], np.diag([1.0, 1e-6]), 1.0)) == \
        pytest.approx(-0.428670667024070, abs=1e-13)  # mpmath
    for eps in (2e-7, 1e-10):
        with pytest.raises(ValueError, match="^cov is too elongated"):
            ellipse.log_censored_probability([0.0, 0.0], np.diag([1.0, eps]), 0.5)
        with pytest.raises(ValueError, match="^R is too elongated"):
            ellipse.log_silent_probability([0.0, 0.0], np.eye(2), np.diag([1.0, eps]), 0.5)


def test_singular_covariance_sampled_and_refused_when_indefinite():
    cov = 2.0 * np.outer([0.6, 0.8], [0.6, 0.8])
    p = math.exp(ellipse.log_censored_probability([0.3, -0.2], cov, 1.0))
    est = vector_likelihood.censored_probability_sampled(np.array([0.3, -0.2]), cov, 1.0,
                                                         n_samples=4000,
                                                         rng=np.random.default_rng(5))
    assert abs(est - p) < 4 * math.sqrt(p * (1 - p) / 4000)
    with pytest.raises(ValueError, match="^cov must be positive semi-definite"):
        ellipse.log_censored_probability([0.0, 0.0], [[1.0, 2.0], [2.0, 1.0]], 1.0)


def test_deterministic_motion_sigma2_zero_is_a_legitimate_limit():
    """sigma2 = 0 (Q = 0) with a known start: the track is x0 moved at constant velocity, the
    local filters know the state exactly (P_pred = 0) and every fusion centre's particles sit on
    the true track, so the position error is 0 for every scheme and feedback."""
    sc = vector.VectorScenario(sigma2=0.0, T=5)
    assert sc.sigma2 == 0.0 and np.array_equal(sc.Q, np.zeros((2, 2)))
    x, z = sc.sample(np.random.default_rng(1), 3)
    truth = sc.x0[0] + sc.x0[1] * np.arange(sc.T + 1)
    np.testing.assert_allclose(x[..., 0], np.broadcast_to(truth, x.shape[:-1]), rtol=0,
                               atol=1e-12)
    assert np.all(np.isfinite(z)) and np.all(sc.local_filters()["P_pred"] == 0.0)
    runs = [(fb, scheme, {}) for fb in ("state", "state+cov", "none")
            for scheme in ("all-send", "cfwmd", "cfomd", "random")]
    runs += [("none", "cfwmd", {"likelihood": "printed"})]
    for fb, scheme, kw in runs:
        if fb == "none" and scheme == "cfwmd" and not kw:
            kw = {"likelihood": "exact"}
        rmse = cs.run(sc, scheme, l=1, n_trials=4, n_particles=20, seed=3, feedback=fb,
                      **kw).rmse_position
        assert np.all(np.isfinite(rmse.value)) and np.max(rmse.value) < 1e-9, (fb, scheme, kw)
    # with an uncertain (even singular) start the filter stays finite
    for P0 in (((1.0, 0.0), (0.0, 0.1)), ((1.0, 1.0), (1.0, 1.0))):
        sc0 = vector.VectorScenario(sigma2=0.0, T=3, P0=P0)
        rmse = cs.run(sc0, "cfwmd", l=1, n_trials=3, n_particles=30, seed=1).rmse_position
        assert np.all(np.isfinite(rmse.value))


@pytest.mark.parametrize("P0, word", [(((1.0, 0.0), (0.0, float("nan"))), "^P0: P0 must be finite"),
                                      (((1.0, 2.0), (2.0, 1.0)), "^P0: P0 must be positive semi"),
                                      (((1.0, 0.5), (0.0, 1.0)), "^P0: P0 must be symmetric")])
def test_p0_is_checked_symmetric_psd(P0, word):
    with pytest.raises(ValueError, match=word):
        vector.VectorScenario(P0=P0)


def test_singular_R_is_refused_with_the_reason():
    with pytest.raises(ValueError, match="^R must be positive definite .*likelihood degenerate"):
        vector.VectorScenario(R=((1.0, 1.0), (1.0, 1.0)))


def test_local_filters_match_filterpy_and_the_cross_covariance():
    sc = vector.VectorScenario(P0=((1.0, 0.2), (0.2, 0.5)))
    lf = sc.local_filters()
    kf = KalmanFilter(dim_x=2, dim_z=2)
    kf.F, kf.Q, kf.H, kf.R = sc.F, sc.Q, sc.Hs[0], sc.Rs[0]
    kf.x, kf.P = np.array(sc.x0, dtype=float), np.array(sc.P0)
    for t in range(sc.T):
        kf.predict()
        assert np.allclose(kf.P, lf["P_pred"][t, 0], rtol=1e-12)
        kf.update(np.zeros(2))
        assert np.allclose(kf.S, lf["S"][t, 0], rtol=1e-12)
        assert np.allclose(kf.K, lf["gain"][t, 0], rtol=1e-12)
    # (22)-(23): the cross-covariance of two sensors' prediction errors, by simulation
    sc = vector.VectorScenario()
    lf = sc.local_filters()
    rng = np.random.default_rng(10)
    n, t = 100_000, 5
    x, z = sc.sample(rng, n)
    xhat = np.broadcast_to(sc.F @ np.array(sc.x0), (n, 2, 2)).copy()
    for k in range(t - 1):
        nu = z[:, k] - xhat  # H = I
        xhat = (xhat + np.einsum("ikm,nim->nik", lf["gain"][k], nu)) @ sc.F.T
    e = (x[:, t][:, None, :] - xhat).reshape(n, 4)
    emp = np.cov(e.T)
    se = np.sqrt((emp ** 2 + np.outer(np.diag(emp), np.diag(emp))) / n)
    assert np.all(np.abs(emp - lf["Sigma"][t - 1]) < 4.5 * se)


# ----------------------------------------------------------------------------- the filter
def _run(sc, scheme, **kw):
    base = {"l": 1, "n_trials": 48, "n_particles": 200, "seed": 5}
    base.update(kw)
    return vector_fusion.run(sc, scheme, **base)


def test_results_are_independent_of_chunking_and_executor():
    sc = vector.VectorScenario()
    kw = {"feedback": "state", "n_trials": 40, "block_size": 16}
    a = _run(sc, "cfwmd", **kw)
    b = _run(sc, "cfwmd", chunk_size=16, **kw)
    with concurrent.futures.ThreadPoolExecutor(2) as ex:
        c = _run(sc, "cfwmd", executor=ex, chunk_size=16, **kw)
    assert np.array_equal(a.mc.samples, b.mc.samples)
    assert np.array_equal(a.mc.samples, c.mc.samples)
    kw["feedback"] = "none"
    d, e = _run(sc, "cfwmd", **kw), _run(sc, "cfwmd", chunk_size=16, **kw)
    assert np.array_equal(d.mc.samples, e.mc.samples)


@pytest.mark.parametrize("N, scheme, feedback, likelihood, ess", [
    (2, "random", "state", "exact", 1.0), (2, "cfwmd", "state", "exact", 1.0),
    (4, "cfwmd", "state+cov", "exact", 1.0), (2, "cfwmd", "none", "exact", 1.0),
    (2, "cfwmd", "state", "exact", 0.5), (2, "cfwmd", "none", "exact", 0.5),
])
def test_fused_filter_equals_the_reference_model(N, scheme, feedback, likelihood, ess):
    """Two models of the one loop, the tabulated (FusedVectorFC) and the plain one (VectorFC,
    VectorExactFC): the same draws, the same estimates up to rounding and table error."""
    sc = vector.VectorScenario(N=N)
    rng = np.random.default_rng(4)
    x, z = sc.sample(rng, 24)
    u = rng.random(z.shape[:-1])
    eta = cs.threshold(1, sc.N, dof=sc.m)
    fused = cs.vector_fusion.FusedVectorFC(sc, scheme, feedback, likelihood, eta, 1, z, u)
    ref = cs.vector_fusion.VectorFC(sc, scheme, feedback, eta, 1, z, u, "table", 1, None)
    model = ref
    if scheme == "cfwmd" and feedback == "none":
        model = cs.vector_fusion.VectorExactFC(sc, eta, z, ref.sent, "table", 1, None)
    a = particle.run_filter(fused, np.random.default_rng(9), 24, 200, sc.T, ess_threshold=ess)
    b = particle.run_filter(model, np.random.default_rng(9), 24, 200, sc.T, ess_threshold=ess)
    assert np.allclose(a.mean, b.mean, rtol=1e-7, atol=1e-9)
    assert np.allclose(a.ess, b.ess, rtol=1e-7)
    assert np.array_equal(fused.sent, ref.sent)


def test_scalar_special_case_reproduces_the_scalar_library():
    """H = [1, 0], R = 1 is Section VII.A: the same truth and measurements as censoring.run
    (the first spawned stream), hence the same sensor decisions without feedback, and the same
    RMSE within the (paired) Monte Carlo error of the two particle filters."""
    sc = vector.VectorScenario(H=(1.0, 0.0), R=1.0)
    kw = {"l": 1, "n_trials": 160, "n_particles": 300, "seed": 5}
    a = cs.run(cs.LinearScenario(), "cfomd", feedback="none", **kw)
    b = vector_fusion.run(sc, "cfomd", feedback="none", **kw)
    assert np.array_equal(a.mc.samples[..., 2], b.mc.samples[..., 2])
    for feedback in ("state", "state+cov"):
        a = cs.run(cs.LinearScenario(), "cfwmd", feedback=feedback, **kw)
        b = vector_fusion.run(sc, "cfwmd", feedback=feedback, **kw)
        va, ia = cs.results.tavg_influence(a, "position")
        vb, ib = cs.results.tavg_influence(b, "position")
        d = ia - ib
        assert _z(va - vb, d.std(ddof=1) / math.sqrt(d.size)) < 4
        ta, tb = a.average_transmissions, b.average_transmissions
        assert _z(ta[0] - tb[0], math.hypot(ta[1], tb[1])) < 4


def test_printed_no_feedback_is_cfomd_and_exact_beats_it():
    sc = vector.VectorScenario()
    kw = {"feedback": "none", "n_trials": 300, "n_particles": 600}
    printed = _run(sc, "cfwmd", likelihood="printed", **kw)
    cfomd = _run(sc, "cfomd", **kw)
    assert np.array_equal(printed.mc.samples, cfomd.mc.samples)
    exact = _run(sc, "cfwmd", likelihood="exact", **kw)
    diff, se = cs.paired_difference(exact, cfomd)
    assert diff < 0 and diff / se < -3
    assert exact.collapsed <= 0.01 * 300 * sc.T


def test_design_target_is_met_without_feedback():
    """Local innovations are N(0, S): each sensor sends with probability l / N exactly."""
    res = _run(vector.VectorScenario(), "cfomd", feedback="none", n_trials=400, n_particles=20)
    mean, se = res.average_transmissions
    assert _z(mean - 1.0, se) < 4


def test_ordering_of_the_schemes_with_feedback():
    sc = vector.VectorScenario()
    kw = {"n_trials": 200, "n_particles": 300}
    r = {s: _run(sc, s, **kw) for s in ("all-send", "cfwmd", "cfomd", "random")}
    for better, worse in (("all-send", "cfwmd"), ("cfwmd", "cfomd"), ("cfomd", "random")):
        diff, se = cs.paired_difference(r[better], r[worse])
        assert diff / se < -3, (better, worse, diff, se)


def test_table_and_quadrature_filters_agree():
    sc = vector.VectorScenario(N=4)
    kw = {"feedback": "state+cov", "n_trials": 8, "n_particles": 100, "l": 2}
    a = _run(sc, "cfwmd", probability="quadrature", **kw)
    b = _run(sc, "cfwmd", **kw)
    same = np.isclose(a.mc.samples, b.mc.samples, rtol=1e-4, atol=1e-6).all(axis=(1, 2))
    assert same.mean() >= 0.75


@pytest.mark.parametrize("kwargs, word", [
    ({"scheme": "x"}, "scheme"), ({"feedback": "x"}, "feedback"),
    ({"likelihood": "corrected", "feedback": "none"}, "corrected"),
    ({"probability": "x"}, "probability"), ({"n_particles": 0}, "n_particles"),
    ({"l": 3}, "l"),
])
def test_run_validation(kwargs, word):
    kw = {"scheme": "cfwmd", "l": 1, "n_trials": 2, "n_particles": 10, "seed": 1}
    kw.update(kwargs)
    scheme = kw.pop("scheme")
    with pytest.raises(ValueError, match=word):
        vector_fusion.run(vector.VectorScenario(), scheme, **kw)
    with pytest.raises(ValueError, match="VectorScenario"):
        vector_fusion.run(cs.LinearScenario(), "cfwmd", l=1, n_trials=2, n_particles=10, seed=1)


def test_scalar_default_likelihood_passes_through_where_unused():
    """censoring.run's default likelihood='corrected' only matters for CFwMD without feedback."""
    res = vector_fusion.run(vector.VectorScenario(), "cfwmd", l=1, n_trials=2, n_particles=10,
                            seed=1, feedback="state", likelihood="corrected")
    assert res.likelihood == "corrected" and res.mc.n_trials == 2


def _mp_log_canon(b1, b2, a1, a2, dps=20):
    """``log P(u_1^2/a_1^2 + u_2^2/a_2^2 < 1)``, ``u ~ N(b, I)``, by mpmath (the theta integral
    of the module docstring, the chord probability reflected into the lower tail). 20 digits:
    on the 13 ellipses of the tests below the logs agree with 30 digits' to 8e-16 relative (the
    tests ask 1e-13), in half the time."""
    with mp.workdps(dps):
        b1, b2, a1, a2 = map(mp.mpf, (b1, b2, a1, a2))

        def f(t):
            cos_t = mp.cos(t)
            c = a2 * cos_t
            A, B = -c - b2, c - b2
            d = mp.ncdf(-A) - mp.ncdf(-B) if A > 0 else mp.ncdf(B) - mp.ncdf(A)
            return a1 * cos_t * mp.npdf(a1 * mp.sin(t) - b1) * d

        return float(mp.log(mp.quad(f, list(mp.linspace(-mp.pi / 2, mp.pi / 2, 81)))))


@pytest.mark.parametrize("mean", [(0.5, 0.3), (0.0, 1.5), (2.0, 1.0), (0.0, 0.8)])
@pytest.mark.parametrize("eta", [0.1, 1.386, 12.0])
def test_elongated_covariance_meets_the_documented_accuracy(mean, eta):
    """cov = diag(1, 0.01): an ellipse ten times longer than wide (issue 17: 2.2e-9 where the
    docstring promises ~1e-13; the long axis is now the substituted one)."""
    got = float(ellipse.log_censored_probability(mean, np.diag([1.0, 0.01]), eta))
    ref = _mp_log_canon(mean[0], mean[1] / 0.1, math.sqrt(eta), math.sqrt(eta) / 0.1)
    assert abs(got - ref) < 1e-13 * max(1.0, abs(ref))
    # the two orders of the axes are the same probability
    assert float(ellipse.log_canon(mean[1] / 0.1, mean[0], math.sqrt(eta) / 0.1, math.sqrt(eta))) \
        == pytest.approx(got, abs=1e-13)


def test_very_elongated_ellipse_against_mpmath():
    got = float(ellipse.log_canon(0.0, 12.0, 2.0, 30.0))
    assert abs(got - _mp_log_canon(0.0, 12.0, 2.0, 30.0)) < 1e-13
