"""Issue 17 ("nothing silent"), items 1-2: the issue's examples and the legitimate limits.

Every example of the issue that concerns riccati, kalman, fading, power, event, models and
``particle.psd_factor`` is a test here: the silently wrong number is now a ``ValueError`` naming
the argument, or the right number. Every legitimate limit (zero noise variances, ``a = 0``,
singular covariances, one sensor, one trial, NumPy scalars and seeds) is checked against the
closed form of the limit.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
import scipy.integrate
import scipy.special

from fusioncenter import event, fading, kalman, models, montecarlo, particle, power, riccati
from fusioncenter._validate import covariance, finite_result, integer
from fusioncenter.fading import Nakagami, Rayleigh

NAN = float("nan")


# =============================================================== the issue's examples (item 1)
@pytest.mark.parametrize("call, match", [
    (lambda: riccati.scalar_update(1, NAN, 1), "^c must be finite"),  # was 0.0
    (lambda: riccati.scalar_steady_state(.5, 1, NAN, 1), "^c must be finite"),  # was 1.333
    (lambda: riccati.scalar_steady_state(2.0, 1.0, 0.0, 1.0), "^no steady state: c = 0"),  # inf
    (lambda: fading.exp_e1(NAN), "^x must not be NaN"),  # was 0.0196
    (lambda: riccati.steady_state([[.5]], [[1.]], [[1.]], [[-1.]]),
     "^R must be positive semi-definite"),  # was [[-1.28]]
    (lambda: riccati.measurement_update([[-5.0]], [[1.0]], [[1.0]]),
     "^P must be positive semi-definite"),
    (lambda: riccati.measurement_update([[2.0, 1.0], [0.0, 2.0]], [[1.0, 0.0]], [[1.0]]),
     "^P must be symmetric"),
    (lambda: riccati.measurement_update(np.eye(2), np.eye(2), [[1.0, 2.0], [2.0, 1.0]]),
     "^R must be positive semi-definite"),
    (lambda: particle.psd_factor(np.full((2, 2), NAN)), "^M must be finite"),  # was 2x0
])
def test_issue_examples_are_errors_naming_the_argument(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_power_steady_state_at_huge_snr_is_the_limit_not_inf():
    # P_inf = q + a^2 q / (1 + q S) + O(1/S^2) -> sigma_w2 = 1 (it returned inf)
    assert power.steady_state(.5, 1., 1e160) == 1.0
    assert riccati.scalar_steady_state(.5, 1.0, 1e200, 1.0) == 1.0  # c^2 itself overflows
    # and the rewritten path agrees with the direct one where both are finite
    for S in (1e100, 1e150):
        assert power.steady_state(.5, 1.0, S) == pytest.approx(1.0 + 0.25 / S, rel=1e-15)


@pytest.mark.parametrize("access", power.ACCESS)
def test_snr_at_huge_alpha_is_the_limit(access):
    h, c, sv = np.array([1.0, 2.0]), np.array([1.0, -0.5]), np.array([1.0, 4.0])
    alpha = np.array([1e200, 3e199])
    got = power.snr(access, alpha, h, c, sv, 1.0)
    if access == "multi-access":  # the noise is negligible: (sum a h c)^2 / sum a^2 h^2 sv
        ah = alpha / 1e200 * h
        want = (ah @ c) ** 2 / (ah**2 @ sv)
    else:  # every sensor reaches c^2 / sigma_v2
        want = np.sum(c**2 / sv)
    assert np.isfinite(got)
    assert got == pytest.approx(want, rel=1e-14)
    # the overflow-free path is only taken where the direct formula fails: same bits elsewhere
    small = alpha / 1e198
    ah = small * h
    direct = ((ah @ c) ** 2 / (ah**2 @ sv + 1.0) if access == "multi-access"
              else np.sum(ah**2 * c**2 / (ah**2 * sv + 1.0)))
    assert power.snr(access, small, h, c, sv, 1.0) == direct


def test_validators_reject_what_the_rule_forbids():
    with pytest.raises(ValueError, match="^x must be symmetric"):
        covariance("x", [[1.0, 0.5], [0.0, 1.0]])
    with pytest.raises(ValueError, match="^x must be positive definite"):
        covariance("x", np.zeros((2, 2)), definite=True)
    with pytest.raises(ValueError, match=r"^x must be a square matrix \(n, n\)"):
        covariance("x", np.zeros((2, 2, 2)))
    with pytest.raises(ValueError, match="^x must be finite"):
        covariance("x", [[np.inf]])
    assert covariance("x", np.zeros((3, 2, 2)), batch=True).shape == (3, 2, 2)
    with pytest.raises(ValueError, match="^seed must be an integer"):
        integer("seed", True)
    assert integer("seed", np.int64(7)) == 7
    with pytest.raises(ValueError, match="^y is not finite: why"):
        finite_result("y", [1.0, np.inf], "why")


# ======================================================================= limits (item 2)
def test_fading_a_zero_is_the_closed_form_sigma_w2():
    """a = 0: p_{k+1} = sigma_w2 on every path (it raised ZeroDivisionError)."""
    for ch in (Rayleigh(1.0), Nakagami(0.5, 2.0)):
        mean, se = fading.scalar_mc(0.0, 1.5, 1.0, 2.0, ch, 7.0, 4, 50, 0)
        np.testing.assert_array_equal(mean, [7.0, 1.5, 1.5, 1.5, 1.5])
        np.testing.assert_array_equal(se, 0.0)
        b = fading.scalar_bounds(0.0, 1.5, 1.0, 2.0, ch, 7.0, 4)
        np.testing.assert_array_equal(b["s"], [7.0, 1.5, 1.5, 1.5, 1.5])
        np.testing.assert_array_equal(b["q"], [7.0, 1.5, 1.5, 1.5, 1.5])
        assert fading.scalar_bound_limits(0.0, 1.5, 1.0, 2.0, ch)["s"] == pytest.approx(1.5)


def test_fading_noise_free_sensor_sigma_v2_zero():
    """sigma_v2 = 0: E_r[posterior] = p E[sigma_n2 / (r p + sigma_n2)] = p g(sigma_n2 / p)."""
    lam, sn2 = 2.0, 3.0
    for p in (0.1, 1.0, 40.0):
        want = scipy.integrate.quad(lambda r, p=p: lam * math.exp(-lam * r) * p * sn2
                                    / (r * p + sn2), 0, np.inf, epsabs=0, epsrel=1e-12)[0]
        m = lam * sn2 / p
        assert fading.expected_posterior(p, 0.0, sn2, Rayleigh(lam)) == pytest.approx(want,
                                                                                      rel=1e-10)
        assert want == pytest.approx(p * m * math.exp(m) * scipy.special.exp1(m), rel=1e-10)
    assert fading.expected_posterior(0.0, 0.0, sn2, Rayleigh(lam)) == 0.0  # known state
    # the bounds and the Monte Carlo accept it and are continuous at sigma_v2 -> 0
    args = (0.9, 1.0, 0.0, sn2, Rayleigh(lam), 1.0, 30)
    b0 = fading.scalar_bounds(*args)
    b1 = fading.scalar_bounds(0.9, 1.0, 1e-12, sn2, Rayleigh(lam), 1.0, 30)
    np.testing.assert_allclose(b0["s"], b1["s"], rtol=1e-9)
    np.testing.assert_allclose(b0["q"], b1["q"], rtol=1e-9)
    mean, se = fading.scalar_mc(*args, 4000, 1)
    assert np.all(mean <= b0["s"] + 4 * se + 1e-12)  # Theorem: E[p_k] <= s_k
    assert np.all(b0["s"] <= b0["q"] + 1e-12)
    # multisensor and vector: sigma_v2 = 0 for one sensor, starting from a known state
    mb = fading.multisensor_bounds("multi-access", 0.9, [1.0, 1.0], [0.0, 1.0], sn2, [lam, lam],
                                   1.0, 0.0, 10)
    assert np.all(np.isfinite(mb["s"])) and np.all(np.isfinite(mb["t"]))
    Z = fading.vector_bound(np.eye(2) * 0.9, [1.0, 0.0], np.diag([0.0, 1.0]), 0.0, sn2,
                            Rayleigh(lam), np.zeros((2, 2)), 5)
    assert np.all(np.isfinite(Z))
    np.testing.assert_array_equal(Z[:, 0, 0], 0.0)  # the measured component stays known


def test_fading_one_sensor_multisensor_is_the_scalar_bound():
    a, sw2, sv2, sn2, lam = 0.95, 1.0, 2.0, 3.0, 1.5
    one = fading.multisensor_bounds("orthogonal", a, [1.0], [sv2], sn2, [lam], sw2, 1.0, 25)
    ref = fading.scalar_bounds(a, sw2, sv2, sn2, Rayleigh(lam), 1.0, 25)
    np.testing.assert_allclose(one["s"], ref["s"], rtol=1e-12)


def test_fading_one_trial_and_numpy_scalars_and_seeds():
    mean, se = fading.scalar_mc(np.float32(0.5), np.float64(1.0), np.int64(2), 3.0,
                                Rayleigh(np.float64(1.0)), 1.0, 5, 1, np.int64(3))
    assert np.all(np.isfinite(mean))
    assert np.all(np.isnan(se))  # a standard error of one trial is undefined: documented NaN
    res = fading.scalar_paths(0.5, 1.0, 2.0, 3.0, Rayleigh(1.0), 1.0, 5, 1, np.uint8(3))
    np.testing.assert_array_equal(res.samples[0], mean)  # float32(0.5) == 0.5 exactly
    with pytest.raises(ValueError, match="^seed must be an integer"):
        fading.scalar_mc(0.9, 1.0, 2.0, 3.0, Rayleigh(1.0), 1.0, 5, 2, True)
    with pytest.raises(ValueError, match="^seed must be an integer"):
        montecarlo.simulate(lambda rng, n: np.zeros((n, 1)), 2, True)
    m = models.tracking_model(np.int64(2))
    with pytest.raises(ValueError, match="^seed must be a non-negative integer"):
        event.calibrate_delta(m, 0.5, n_trials=4, steps=4, burn_in=1, seed=True)


def test_kalman_noise_free_sensor_R_zero():
    """R = 0: the measured component is known exactly after the update (it was rejected)."""
    model = kalman.LinearGaussianModel(A=[[0.8]], Q=[[1.0]], C=[[2.0]], R=[[0.0]], m0=[1.0],
                                       P0=[[3.0]])
    x, y = model.sample(np.random.default_rng(0), 5, 6)
    xhat, P = model.filter(y)
    np.testing.assert_array_equal(P, 0.0)
    np.testing.assert_allclose(xhat, x, rtol=1e-14)
    # a known state measured without noise: C P C^T + R = 0, the gain is the R -> 0 limit
    trk = models.tracking_model(2, r=0.0)  # P0 = 0 as well
    x, y = trk.sample(np.random.default_rng(1), 3, 4)
    xhat, P = trk.filter(y)
    np.testing.assert_array_equal(xhat[:, 0], x[:, 0])
    assert np.all(np.isfinite(P)) and np.all(np.linalg.eigvalsh(P) > -1e-9)
    np.testing.assert_allclose(P[1:, 0, 0], 0.0, atol=1e-9)  # position known exactly
    np.testing.assert_allclose(xhat[:, :, 0], x[:, :, 0], rtol=1e-12, atol=1e-9)
    cv = kalman.constant_velocity(r=0.0)
    assert cv.R[0, 0] == 0.0


def test_riccati_zero_noise_limits():
    # measurement_update with R = 0: P - P C^T (C P C^T)^{-1} C P; full C gives 0
    P = np.array([[2.0, 0.5], [0.5, 1.0]])
    np.testing.assert_allclose(riccati.measurement_update(P, np.eye(2), np.zeros((2, 2))), 0.0,
                               atol=1e-15)
    # R = 0 measuring a direction the prior already knows: S = 0, nothing changes
    Pk = np.diag([0.0, 1.0])
    np.testing.assert_array_equal(riccati.measurement_update(Pk, [[1.0, 0.0]], [[0.0]]), Pk)
    # scalar steady states: r = 0 -> q; q = 0 -> 0 (stable) or r (a^2 - 1) / c^2 (unstable)
    assert riccati.scalar_steady_state(0.5, 2.0, 1.0, 0.0) == 2.0
    assert riccati.scalar_steady_state(0.5, 0.0, 1.0, 3.0) == 0.0
    assert riccati.scalar_steady_state(1.5, 0.0, 2.0, 3.0) == pytest.approx(3.0 * 1.25 / 4.0)
    assert riccati.steady_state([[0.5]], [[2.0]], [[1.0]], [[0.0]])[0, 0] == pytest.approx(2.0)
    assert riccati.scalar_update(np.float64(2.0), np.float32(1.0), np.int64(0)) == 0.0
    # c^2 underflows: only c^2 / r matters (noise-free: p = q; tiny information: no information)
    assert riccati.scalar_steady_state(1.0, 0.0, 2.6e-272, 0.0) == 0.0
    assert riccati.scalar_steady_state(0.5, 1.0, 1e-200, 1e-300) == pytest.approx(4 / 3)
    with pytest.raises(ValueError, match="^c is too small"):
        riccati.scalar_steady_state(1.0, 1.0, 1e-200, 1.0)


def test_power_zero_variance_and_zero_power_limits():
    a, h, c, sv = 0.5, np.array([1.0, 0.5]), np.array([1.0, 2.0]), np.array([1.0, 2.0])
    # sigma_w2 = 0: deterministic dynamics
    assert power.stationary_variance(a, 0.0) == 0.0
    np.testing.assert_array_equal(power.kappa(a, 0.0, c, sv), sv)
    assert power.steady_state(a, 0.0, 2.0) == 0.0
    assert power.steady_state(1.5, 0.0, 2.0) == pytest.approx((1.5**2 - 1) / 2.0)
    assert power.steady_state(a, 0.0, 0.0) == 0.0
    with pytest.raises(ValueError, match="^sigma_w2 must be positive .*no target D"):
        power.min_power("multi-access", 0.5, a, 0.0, h, c, sv, 1.0)
    # sigma_n2 = 0: an ideal channel
    alpha = np.array([0.3, -0.7])
    ah = alpha * h
    assert power.snr("multi-access", alpha, h, c, sv, 0.0) == pytest.approx(
        (ah @ c) ** 2 / (ah**2 @ sv), rel=1e-15)
    assert power.snr("orthogonal", alpha, h, c, sv, 0.0) == pytest.approx(np.sum(c**2 / sv))
    assert power.snr("multi-access", np.zeros(2), h, c, sv, 0.0) == 0.0  # nothing sent
    for access in power.ACCESS:  # the best SNR is sum c_i^2 / sigma_v2_i (Cauchy-Schwarz)
        best = power.min_error(access, 2.0, a, 1.0, h, c, sv, 0.0)
        assert power.snr(access, best, h, c, sv, 0.0) == pytest.approx(np.sum(c**2 / sv),
                                                                       rel=1e-12)
        spent = power.transmit_power(best, a, 1.0, c, sv).sum()
        assert spent == pytest.approx(2.0, rel=1e-12)
        with pytest.raises(ValueError, match="^sigma_n2 must be positive"):
            power.min_power(access, 1.2, a, 1.0, h, c, sv, 0.0)
    # gamma_total = 0: no power, no information
    for access in power.ACCESS:
        zero = power.min_error(access, 0.0, a, 1.0, h, c, sv, 1.0)
        np.testing.assert_array_equal(zero, 0.0)
        assert power.snr(access, zero, h, c, sv, 1.0) == 0.0
        P, S, spent = power.greedy_min_error(access, 0.0, a, 1.0, np.ones((3, 2)), c, sv, 1.0)
        np.testing.assert_allclose(P, 1 / 0.75, rtol=1e-15)
    np.testing.assert_array_equal(power.equal_power(a, 1.0, c, sv, gamma_total=0.0), 0.0)


def test_power_one_sensor_and_numpy_scalars():
    # one sensor: S = alpha^2 h^2 c^2 / (alpha^2 h^2 sigma_v2 + sigma_n2) for both schemes
    for access in power.ACCESS:
        alpha = power.min_error(access, np.float64(2.0), np.float32(0.5), np.int64(1), [1.5],
                                [2.0], [1.0], 0.5)
        kap = 4.0 / 0.75 + 1.0
        assert alpha[0] == pytest.approx(math.sqrt(2.0 / kap), rel=1e-12)
        a2h2 = alpha[0] ** 2 * 2.25
        assert power.snr(access, alpha, 1.5, 2.0, 1.0, 0.5) == pytest.approx(
            a2h2 * 4.0 / (a2h2 + 0.5), rel=1e-12)


def test_event_singular_covariances_and_one_sensor():
    r, delta = np.array([1.0, 2.0]), np.array([0.5, 3.0])
    C = np.array([[1.0, 0.0], [1.0, 1.0]])
    # Sigma = 0 (known state): y_i ~ N(c_i xbar, r_i)
    xbar = np.array([0.3, -0.2])
    got = event.communication_rate(np.zeros((2, 2)), C, r, delta, xbar)
    mu = C @ xbar
    want = 1 - np.sqrt(delta / (delta + r)) * np.exp(-mu**2 / (2 * (delta + r)))
    np.testing.assert_allclose(got, want, rtol=1e-14)
    # rank one: Sigma = v v^T, s_i = r_i + (c_i v)^2
    v = np.array([1.0, 2.0])
    got = event.communication_rate(np.outer(v, v), C, r, delta)
    np.testing.assert_allclose(got, 1 - 1 / np.sqrt(1 + (r + (C @ v) ** 2) / delta),
                               rtol=1e-14)
    # posterior of a known state: unchanged
    xhat, P = event.posterior(xbar, np.zeros((2, 2)), C, r, delta, [1, 0], [1.0, 5.0])
    np.testing.assert_array_equal(xhat, xbar)
    np.testing.assert_array_equal(P, 0.0)
    # one sensor, noise-free, scalar state: sending reveals x exactly
    xhat, P = event.posterior([0.0], [[2.0]], [[1.0]], [0.0], 1.0, [1], [0.7])
    assert xhat[0] == pytest.approx(0.7) and P[0, 0] == pytest.approx(0.0, abs=1e-15)
    # the filter with noise-free sensors and a known start (S = 0 at the first step)
    run = event.event_kf_run(models.tracking_model(1, r=0.0), 5, "all-send",
                             np.random.default_rng(0), 3)
    assert np.all(np.isfinite(run.xhat)) and np.all(np.isfinite(run.P))
    np.testing.assert_allclose(run.xhat[..., 0], run.x[..., 0], rtol=1e-12, atol=1e-9)


def test_psd_factor_of_valid_singular_and_zero_matrices():
    Q = 4 * np.array([[0.25, 0.5], [0.5, 1.0]])  # rank 1
    L = particle.psd_factor(Q)
    assert L.shape == (2, 1)
    np.testing.assert_allclose(L @ L.T, Q, rtol=1e-14, atol=1e-15)
    assert particle.psd_factor(np.zeros((2, 2))).shape == (2, 0)
    with pytest.raises(ValueError, match="^M must be positive semi-definite"):
        particle.psd_factor(-np.eye(2))
    with pytest.raises(ValueError, match="^M must be symmetric"):
        particle.psd_factor([[1.0, 1.0], [0.0, 1.0]])


def test_registry_seed_accepts_numpy_integers_and_rejects_bool():
    """The registry's seed check (it accepted True and refused np.int64)."""
    from fusioncenter import figures

    entry = figures.get("dey2009-fig1")
    with pytest.raises(ValueError, match="^seed must be a non-negative integer"):
        entry.run_compute("fast", True)
    with pytest.raises(ValueError, match="^seed must be a non-negative integer"):
        entry.run_compute("fast", np.int64(-1))


# =================================================== issue 29: the classes still silent or refused
def test_singular_innovation_covariance_contradicting_measurement_is_refused():
    """P = 0 and R = 0 along a measured direction: the measurement must equal its prediction
    there (it returned numbers whatever it was); a consistent one still gives the posterior."""
    C, x = np.array([[1.0, 0.0]]), np.zeros((1, 2))
    for P in (np.zeros((2, 2)), np.zeros((1, 2, 2))):  # shared and per-trial arithmetic
        with pytest.raises(ValueError, match="^innov contradicts the model"):
            kalman.kalman_step(x, P, np.ones((1, 1)), C, np.zeros((1, 1)), np.eye(2), np.eye(2))
        ok = kalman.kalman_step(x, P, np.zeros((1, 1)), C, np.zeros((1, 1)), np.eye(2),
                                np.eye(2))
        np.testing.assert_array_equal(ok.x_post, 0.0)
    with pytest.raises(ValueError, match="^y at step 0 contradicts the model"):
        models.tracking_model(1, r=0.0).filter(np.full((1, 2, 1), 5.0))  # x0 = 0 is known
    # event.posterior with R = 0: Sigma = 0, and Sigma of rank one measured off its range
    for Sigma in (np.zeros((2, 2)), np.diag([1.0, 0.0])):
        with pytest.raises(ValueError, match="^y contradicts the model"):
            event.posterior(np.zeros(2), Sigma, np.eye(2), [0.0, 0.0], 1.0, [1, 1], [1.0, 1.0])
    xhat, P = event.posterior(np.zeros(2), np.diag([1.0, 0.0]), np.eye(2), [0.0, 0.0], 1.0,
                              [1, 1], [0.7, 0.0])
    np.testing.assert_allclose(xhat, [0.7, 0.0], atol=1e-15)
    np.testing.assert_allclose(P, 0.0, atol=1e-15)
    # merely ill-conditioned (a huge delta beside a small r) is not singular: accepted
    xhat, _ = event.posterior(np.zeros(2), np.eye(2), np.eye(2), [0.5, 0.5], 1e12, [1, 0],
                              [3.0, np.nan])
    assert xhat[0] == pytest.approx(3.0 / 1.5) and xhat[1] == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize("call, name", [
    (lambda: models.tracking_model(2, dt="1"), "dt"),
    (lambda: models.tracking_model(2, sigma2="4"), "sigma2"),
    (lambda: models.tracking_model(2, r="1"), "r"),
    (lambda: models.wna_model("1"), "dt"),
    (lambda: kalman.constant_velocity(dt="1"), "dt"),
    (lambda: kalman.constant_velocity(q=["1"]), "q"),
    (lambda: fading.Rayleigh("1"), "lam"),
    (lambda: riccati.scalar_update(np.array(["1"]), 1.0, 1.0), "p"),
])
def test_numbers_written_as_text_are_refused(call, name):
    """NumPy turns "1" into 1.0: the validators refuse text instead (issue 29)."""
    with pytest.raises(ValueError, match=f"^{name} must be"):
        call()


def test_nonlinear_censoring_refuses_nan_and_negative_thresholds():
    from fusioncenter.censoring import nonlinear as nl

    for h in (-1.0, NAN):  # it returned NaN (and a RuntimeWarning)
        with pytest.raises(ValueError, match="^h must be a non-negative half-width"):
            nl.log_silent_probability(0.0, h)
    with pytest.raises(ValueError, match="^m must be finite"):
        nl.log_silent_probability(NAN, 1.0)
    assert nl.log_silent_probability(0.0, np.inf) == 0.0  # the whole line: probability 1
    assert nl.log_silent_probability(0.0, 0.0) == -np.inf  # an empty interval
    sc = nl.NonlinearScenario()
    with pytest.raises(ValueError, match="^pos must not be NaN"):
        nl.amplitude(sc, [NAN, 0.0])
    np.testing.assert_array_equal(nl.amplitude(sc, [np.inf, 0.0]), 0.0)  # infinitely far
    with pytest.raises(ValueError, match="^x must be finite"):
        nl.jacobian(sc, [NAN, 0.0, 0.0, 0.0])


def test_ekf_covariance_step_zero_information_and_its_arguments():
    from fusioncenter.censoring import nonlinear as nl

    P, F, Q = np.diag([1.0, 2.0, 3.0, 4.0]), np.eye(4), 0.5 * np.eye(4)
    # r = 0 and a zero gradient: s = 0, no information, P_upd = P_pred (it returned NaN)
    Pp, s, Pu = nl.ekf_covariance_step(P, np.zeros(4), F, Q, 0.0)
    assert s == 0.0
    np.testing.assert_array_equal(Pu, Pp)
    np.testing.assert_array_equal(Pp, P + Q)
    # s > 0 is the Joseph form as before, bit for bit (the filters call the same kernel)
    from fusioncenter._compiled.amplitude_ekf import ekf_step
    g = np.array([0.3, 0.0, -0.2, 0.0])
    for got, want in zip(nl.ekf_covariance_step(P, g, F, Q, 1.0), ekf_step(P, g, F, Q, 1.0),
                         strict=True):
        np.testing.assert_array_equal(got, want)
    for kw, match in ((dict(r=-1.0), "^r must be non-negative"), (dict(r=NAN), "^r must be"),
                      (dict(g=np.ones(3)), r"^g must have shape \(\.\.\., 4\)"),
                      (dict(F=np.eye(3)), r"^F must have shape \(4, 4\)"),
                      (dict(P=P + np.triu(np.ones((4, 4)), 1)), "^P must be symmetric")):
        args = dict(P=P, g=g, F=F, Q=Q, r=1.0) | kw
        with pytest.raises(ValueError, match=match):
            nl.ekf_covariance_step(**args)


def test_likelihoods_refuse_a_nan_measurement_where_a_sensor_sent():
    from fusioncenter import censoring
    from fusioncenter.censoring import nonlinear as nl
    from fusioncenter.censoring import vector_likelihood as vl

    args = dict(hx=[0.0, 0.0], hx_pred=[0.0, 0.0], s=[1.0, 1.0], r=[1.0, 1.0], eta=1.0)
    for f in (censoring.log_likelihood_feedback, nl.log_likelihood):
        with pytest.raises(ValueError, match="^z must be finite where a sensor sent"):
            f(sent=[True, False], z=[NAN, 0.0], **args)
        # a silent sensor's z is ignored, NaN included
        assert np.isfinite(f(sent=[False, False], z=[NAN, NAN], **args))
        with pytest.raises(ValueError, match="^sent and z must have shapes that broadcast"):
            f(sent=[True, True], z=[0.0, 0.0, 0.0], **args)
    with pytest.raises(ValueError, match="^z must be finite where a sensor sent"):
        vl.log_likelihood_feedback([True], [[NAN, 0.0]], np.zeros((1, 2)), np.zeros((1, 2)),
                                   np.eye(2)[None], np.eye(2)[None], 1.0)


def test_resample_refuses_ancestors_out_of_range():
    x = np.arange(6.0).reshape(3, 2)
    for idx, match in (([0, 5, 1], r"^idx must lie in \[0, 3\)"),  # was IndexError
                       ([0, -1, 1], r"^idx must lie in \[0, 3\)"),  # was wrapped around
                       ([0.0, 1.0, 1.0], "^idx must be an integer array"),
                       (np.zeros((2, 3), int), r"^idx must have shape \(")):
        with pytest.raises(ValueError, match=match):
            particle.resample(x, np.asarray(idx))
    np.testing.assert_array_equal(particle.resample(x, np.array([2, 0])), x[[2, 0]])
    with pytest.raises(ValueError, match=r"^x must have shape \(4, 'd'\)"):
        particle.weighted_mean(x, np.zeros(4))  # was NumPy's matmul message


@pytest.mark.parametrize("call, match", [
    (lambda: riccati.riccati_step(np.eye(2), np.eye(3), np.eye(2), [[1.0, 0.0]], [[1.0]]),
     r"^A must be 2x2 \(P is 2x2\)"),
    (lambda: riccati.riccati_step(np.eye(2), np.eye(2), np.eye(3), [[1.0, 0.0]], [[1.0]]),
     r"^Q must be 2x2 \(P is 2x2\)"),
    (lambda: kalman.kalman_step(np.zeros((3, 2)), np.eye(2), np.ones((3, 2)),
                                np.array([[1.0, 0.0]]), np.eye(1), np.eye(2), np.eye(2)),
     r"^innov must have shape \(\.\.\., 1\) \(C has 1 rows\)"),
    (lambda: kalman.kalman_step(np.zeros((3, 3)), np.eye(2), np.ones((3, 1)),
                                np.array([[1.0, 0.0]]), np.eye(1), np.eye(2), np.eye(2)),
     r"^x must have shape \(\.\.\., 2\)"),
    (lambda: __import__("fusioncenter.censoring.vector", fromlist=["x"]).silent_covariance(
        __import__("fusioncenter.censoring.vector", fromlist=["x"]).VectorScenario(),
        np.eye(3)), r"^Sigma must be 4x4"),
])
def test_shape_errors_name_the_argument_and_the_expected_shape(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_extreme_steady_state_is_a_documented_refusal_naming_a():
    # the steady state of a = 1e300 is about a^2 r / c^2 = 1e600: no float; a documented refusal
    # naming a (it said "an input is too large")
    with pytest.raises(ValueError, match="^a .*beyond the float range"):
        riccati.scalar_steady_state(1e300, 1.0, 1.0, 1.0)
    with pytest.raises(ValueError, match=r"^a \(with sigma_w2, S\).*beyond the float range"):
        power.steady_state(1e300, 1.0, 2.0)
    assert riccati.scalar_steady_state(1e150, 0.0, 1.0, 1.0) == pytest.approx(1e300, rel=1e-12)


def test_extreme_power_budget_multi_access():
    # a huge power budget, multi-access: w^2 underflowed and it said "rho must be non-zero"
    h, c, sv = np.ones(2), np.ones(2), np.ones(2)
    alpha = power.min_error("multi-access", 1e300, 0.5, 1.0, h, c, sv, 1.0)
    assert power.transmit_power(alpha, 0.5, 1.0, c, sv).sum() == pytest.approx(1e300, rel=1e-12)
    np.testing.assert_allclose(alpha, power.min_error("orthogonal", 1e300, 0.5, 1.0, h, c, sv,
                                                      1.0), rtol=1e-12)


def test_extreme_event_rates():
    # a tiny target rate with a non-zero mean: ZeroDivisionError before; rate ~ (s + mu^2) / 2d
    d = event.delta_for_rate(1e-300, 1.0, 3.0)
    assert d == pytest.approx(10.0 / 2e-300, rel=1e-9)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        assert event.trigger_probability(1e300, 1e-300) == 1.0  # no overflow warning
    # steady_state_delta at rates where the Schur solver failed: the doubling algorithm
    trk = models.tracking_model(2)
    for rate in (1e-8, 1e-10):
        delta = event.steady_state_delta(trk, rate)
        assert np.all(np.isfinite(delta)) and np.all(delta > 0)
    R = 1e12 * np.eye(2)
    P = riccati.steady_state(trk.A, trk.Q, trk.C, R)
    np.testing.assert_allclose(riccati.riccati_step(P, trk.A, trk.Q, trk.C, R), P, rtol=1e-9)


def test_zero_samples_give_empty_results():
    trk = models.tracking_model(2)
    x, y = trk.sample(np.random.default_rng(0), 0, 3)
    assert x.shape == (0, 4, 2) and y.shape == (0, 4, 2)
    out = event.event_kf_chunk(np.random.default_rng(0), 0, model=trk, steps=3,
                               scheme="stochastic", delta=1.0)
    assert out.shape == (0, 4, 8)
    with pytest.raises(ValueError, match="^n must be >= 0"):
        event.event_kf_chunk(np.random.default_rng(0), -1, model=trk, steps=3,
                             scheme="stochastic", delta=1.0)
