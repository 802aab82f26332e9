"""The nonlinear tracker of zheng2014 (Sections VI, VII.C): model, EKFs, Propositions 7-8, run.

Every random test is seeded. Monte Carlo checks are z-scores below 4.5; orderings of schemes
are paired differences (same truth and measurements) beyond 3 standard errors.
"""

from __future__ import annotations

import concurrent.futures
import dataclasses

import numpy as np
import pytest
import scipy.stats
from filterpy.kalman import ExtendedKalmanFilter
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import integrate

from fusioncenter import censoring as cs
from fusioncenter.censoring import nonlinear as cn

SC = cn.NonlinearScenario()


# ----------------------------------------------------------------------------- the scenario
def test_scenario_defaults_are_the_papers_and_choices_are_stated():
    assert (SC.N, SC.region, SC.power, SC.alpha, SC.exponent, SC.r, SC.sigma2, SC.dt, SC.T) == \
        (9, 20.0, 1e3, 1.0, 2.0, 1.0, 0.1, 0.5, 20)
    assert SC.x0 == (-8.0, 2.0, -8.0, 2.0) and SC.P0 == (9.0, 4.0, 9.0, 4.0)
    assert SC.d == 4 and SC.position_index == (0, 2) and SC.velocity_index == (1, 3)
    dt = 0.5
    F1 = np.array([[1, dt], [0, 1]])
    q = np.array([[dt**4 / 4, dt**3 / 2], [dt**3 / 2, dt**2]])
    assert np.array_equal(SC.F, np.kron(np.eye(2), F1))
    assert np.allclose(SC.Q, 0.1 * np.kron(np.eye(2), q), rtol=1e-15, atol=0)
    assert np.allclose(SC.dynamics.P0, np.diag([9.0, 4, 9, 4]))
    c = 20 / 3
    assert np.allclose(np.unique(SC.positions[:, 0]), [-c, 0, c])
    assert np.allclose(np.unique(SC.positions[:, 1]), [-c, 0, c])
    ch = SC.choices
    for key in ("region", "sensor positions", "measurement", "time axis", "initial state",
                "PF prior", "local EKFs", "feedback 'state'", "feedback 'state+cov'",
                "feedback 'none'", "Jacobian", "threshold", "random selection", "resampling"):
        assert key in ch and ch[key]
    assert "given" in cn.NonlinearScenario(sensors=[[0, 0], [1, 1]]).choices["sensor positions"]
    assert "drawn" in cn.NonlinearScenario(initial_truth="random").choices["initial state"]


def test_scenario_is_hashable_and_comparable():
    a, b = cn.NonlinearScenario(), cn.NonlinearScenario()
    assert a == b and hash(a) == hash(b)
    assert a != dataclasses.replace(a, r=2.0)
    s = cn.NonlinearScenario(r=[1.0] * 9, P0=np.eye(4).tolist())
    assert s.r == (1.0,) * 9 and s.P0 == tuple(tuple(row) for row in np.eye(4))


@pytest.mark.parametrize("kwargs, name", [
    ({"region": -1}, "region"), ({"region": np.nan}, "region"), ({"power": 0}, "power"),
    ({"alpha": -1}, "alpha"), ({"exponent": 0}, "exponent"), ({"sigma2": 0}, "sigma2"),
    ({"dt": -0.5}, "dt"), ({"T": 0}, "T"), ({"T": 2.5}, "T"), ({"r": (1.0, 2.0)}, "r"),
    ({"r": -1}, "r"), ({"x0": (1, 2)}, "x0"), ({"P0": (1, 1, 1)}, "P0"),
    ({"P0": (1, -1, 1, 1)}, "P0"), ({"P0": [[1, 2, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0],
                                             [0, 0, 0, 1]]}, "P0"),
    ({"sensors": [1, 2]}, "sensors"), ({"sensors": [[0, np.inf]]}, "sensors"),
    ({"initial_truth": "fixed"}, "initial_truth"), ({"power": "a"}, "power"),
])
def test_scenario_validation(kwargs, name):
    with pytest.raises(ValueError, match=name):
        cn.NonlinearScenario(**kwargs)


def test_grid_positions():
    c = cn.grid_positions(3, 20.0)
    assert c.shape == (9, 2) and np.allclose(c[0], [-20 / 3, -20 / 3]) and np.allclose(c[4], 0)
    e = cn.grid_positions(3, 20.0, layout="edges")
    assert np.allclose(e[0], [-10, -10]) and np.allclose(e[-1], [10, 10])
    assert cn.grid_positions(1, 4.0).tolist() == [[0.0, 0.0]]
    for kwargs, name in [({"per_side": 0}, "per_side"), ({"side": 0}, "side"),
                         ({"layout": "x"}, "layout")]:
        with pytest.raises(ValueError, match=name):
            cn.grid_positions(**kwargs)


def test_sample_starts_at_x0_and_follows_the_model():
    rng = np.random.default_rng(0)
    x, z = SC.sample(rng, 4000)
    assert x.shape == (4000, 21, 4) and z.shape == (4000, 20, 9)
    assert np.all(x[:, 0] == SC.x0)  # initial_truth="mean"
    # one-step increments: x_t - F x_{t-1} ~ N(0, Q) (rank 2: check the covariance)
    u = x[:, 5] - x[:, 4] @ SC.F.T
    C = np.cov(u.T)
    assert np.allclose(C, SC.Q, atol=5 * np.sqrt(2 / 4000) * np.sqrt(np.outer(np.diag(SC.Q),
                                                                               np.diag(SC.Q))))
    noise = z - cn.amplitude(SC, x[:, 1:, [0, 2]])
    assert abs(noise.mean()) < 4.5 / np.sqrt(noise.size)
    assert abs(noise.var() - 1.0) < 4.5 * np.sqrt(2 / noise.size)
    xr, _ = cn.NonlinearScenario(initial_truth="random").sample(np.random.default_rng(1), 4000)
    m = xr[:, 0].mean(axis=0)
    assert np.all(np.abs(m - SC.x0) < 4.5 * np.sqrt(np.array(SC.P0) / 4000))


# ----------------------------------------------------------------------------- measurement model
def test_amplitude_closed_form():
    pos = SC.positions
    h = cn.amplitude(SC, pos)  # target on each sensor in turn
    assert np.allclose(np.diag(h), np.sqrt(1e3))
    d = np.linalg.norm(pos[0] - pos[8])
    assert h[0, 8] == pytest.approx(np.sqrt(1e3 / (1 + d**2)), rel=1e-14)
    s3 = cn.NonlinearScenario(alpha=0.5, exponent=3.0, power=50.0)
    h3 = cn.amplitude(s3, np.array([3.0, 4.0]))
    d0 = np.linalg.norm(np.array([3.0, 4.0]) - s3.positions, axis=-1)
    assert np.allclose(h3, np.sqrt(50 / (1 + 0.5 * d0**3)), rtol=1e-14)
    with pytest.raises(ValueError, match="pos"):
        cn.amplitude(SC, np.zeros(3))


@pytest.mark.parametrize("scenario", [SC, cn.NonlinearScenario(alpha=0.3, exponent=3.0)])
def test_jacobian_against_finite_differences(scenario):
    rng = np.random.default_rng(2)
    x = rng.normal(0, 6, (20, 4))
    g = cn.jacobian(scenario, x)
    assert g.shape == (20, 9, 4)
    eps = 1e-6
    for j in range(4):
        e = np.zeros(4)
        e[j] = eps
        fd = (cn.amplitude(scenario, (x + e)[:, [0, 2]])
              - cn.amplitude(scenario, (x - e)[:, [0, 2]])) / (2 * eps)
        assert np.allclose(g[..., j], fd, rtol=1e-6, atol=1e-8)
    assert np.all(g[..., [1, 3]] == 0)
    with pytest.raises(ValueError, match="x"):
        cn.jacobian(SC, np.zeros(2))


# ----------------------------------------------------------------------------- the local EKFs
def test_local_ekfs_match_filterpy():
    """The vectorized EKFs (all trials and sensors at once) against filterpy, one at a time.

    Each step starts filterpy from the library's previous update: a lone amplitude sensor
    cannot tell the target from its mirror image, and on the mean path (the diagonal through
    the sensors 1, 5, 9) its EKF sits on that symmetry, where rounding differences grow
    exponentially from step to step (1e-16 to order 1 within 20 steps). Step by step the two
    implementations agree to rounding."""
    rng = np.random.default_rng(3)
    _, z = SC.sample(rng, 3)
    loc = cn.local_ekf(SC, z)
    for b in range(3):
        for i in (0, 2, 4, 8):
            ekf = ExtendedKalmanFilter(dim_x=4, dim_z=1)
            ekf.F, ekf.Q, ekf.R = SC.F, SC.Q, np.array([[1.0]])

            def hx(x, i=i):
                return cn.amplitude(SC, x[[0, 2]])[i:i + 1]

            def H(x, i=i):
                return cn.jacobian(SC, x)[i:i + 1]

            for t in range(SC.T):
                if t == 0:
                    ekf.x = np.array(SC.x0, dtype=float)
                    ekf.P = np.diag(np.array(SC.P0, dtype=float))
                else:
                    ekf.x = loc["x_upd"][b, t - 1, i].copy()
                    ekf.P = loc["P_upd"][b, t - 1, i].copy()
                ekf.predict()
                scale = np.abs(ekf.P).max()
                assert np.allclose(ekf.x, loc["x_pred"][b, t, i], rtol=1e-13, atol=1e-12)
                assert np.allclose(ekf.P, loc["P_pred"][b, t, i], rtol=0, atol=1e-12 * scale)
                ekf.update(np.array([z[b, t, i]]), H, hx)
                assert ekf.S[0, 0] == pytest.approx(loc["s"][b, t, i], rel=1e-12)
                assert ekf.y[0] == pytest.approx(loc["nu"][b, t, i], rel=1e-12, abs=1e-12)
                assert np.allclose(ekf.x, loc["x_upd"][b, t, i], rtol=1e-12, atol=1e-11)
                assert np.allclose(ekf.P, loc["P_upd"][b, t, i], rtol=0, atol=1e-11 * scale)
    with pytest.raises(ValueError, match="z"):
        cn.local_ekf(SC, z[:, :5])


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**31), r=st.floats(0.1, 10))
def test_ekf_covariance_step_is_the_kalman_update(seed, r):
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(5, 4, 4))
    P = A @ np.swapaxes(A, -1, -2) + 0.1 * np.eye(4)
    g = rng.normal(size=(5, 4))
    Pp, s, Pu = cn.ekf_covariance_step(P, g, SC.F, SC.Q, r)
    for k in range(5):
        Ppk = SC.F @ P[k] @ SC.F.T + SC.Q
        sk = g[k] @ Ppk @ g[k] + r
        w = Ppk @ g[k] / sk
        Puk = (np.eye(4) - np.outer(w, g[k])) @ Ppk  # the simple form, equal in exact arithmetic
        assert np.allclose(Pp[k], Ppk) and s[k] == pytest.approx(sk)
        assert np.allclose(Pu[k], Puk, atol=1e-10 * np.abs(Ppk).max())
        assert np.allclose(Pu[k], Pu[k].T) and np.linalg.eigvalsh(Pu[k]).min() > -1e-10


# ----------------------------------------------------------------------------- the likelihood
@pytest.mark.parametrize("m", [0.0, 0.3, 2.0, 8.0, 30.0, -5.0])
@pytest.mark.parametrize("h", [1e-8, 0.05, 0.14, 1.2, 3.0, 11.0])
def test_log_silent_probability_against_the_careful_function(m, h):
    got = cn.log_silent_probability(np.array([m]), np.array([h]))[0]
    ref = cs.log_censored_probability(m, h * h, 1.0, 1.0)
    assert got == pytest.approx(ref, rel=1e-11, abs=1e-14)


def test_tabulated_silent_terms_match_the_exact_ones():
    rng = np.random.default_rng(4)
    for P in (50, 3000):
        a = np.abs(rng.normal(0, rng.uniform(0.05, 12, (40, 1)), (40, P)))
        a[0] = np.linspace(0, 31, P)  # a whole range in one row
        h = rng.uniform(0.01, 9, 40)
        got = cn.silent_terms(a, h)
        ref = cn.log_silent_probability(a, h[:, None])
        assert np.max(np.abs(got - ref)) < 1e-9
    assert cn.silent_terms(np.empty((0, 5)), np.empty(0)).shape == (0, 5)


@pytest.mark.parametrize("hx, hx_pred, s, l", [(3.0, 2.0, 1.7, 2), (10.0, 4.0, 5.0, 1),
                                               (1.0, 1.1, 1.0, 8), (0.5, 6.0, 3.0, 4)])
def test_likelihood_sums_to_one_over_the_outcomes(hx, hx_pred, s, l):
    """One sensor (Propositions 7-8): P(silent | x) + integral of the send-region density = 1.

    The sensor sends z if |z - h(xhat)| >= sqrt(eta s); z ~ N(h(x), r)."""
    eta = cs.threshold(l, 9)
    r = 1.0
    a = np.sqrt(eta * s)
    silent = np.exp(cn.log_likelihood(np.array([False]), np.array([0.0]), np.array([hx]),
                                      np.array([hx_pred]), np.array([s]), np.array([r]), eta))

    def dens(z):
        return float(np.exp(cn.log_likelihood(np.array([True]), np.array([z]), np.array([hx]),
                                              np.array([hx_pred]), np.array([s]),
                                              np.array([r]), eta)))

    lo, _ = integrate.quad(dens, -np.inf, hx_pred - a)
    hi, _ = integrate.quad(dens, hx_pred + a, np.inf)
    assert silent + lo + hi == pytest.approx(1.0, abs=1e-9)
    # and the silent probability is what simulated sensors do
    rng = np.random.default_rng(5)
    zz = hx + rng.standard_normal(200_000)
    freq = np.mean(np.abs(zz - hx_pred) < a)
    assert abs(freq - silent) < 4.5 * np.sqrt(silent * (1 - silent) / zz.size) + 1e-12


def test_log_likelihood_cfomd_and_validation():
    args = (np.array([True, False]), np.array([3.0, 0.0]), np.array([2.5, 1.0]),
            np.array([2.0, 1.2]), np.array([1.5, 1.5]), np.array([1.0, 1.0]), 1.5)
    full = cn.log_likelihood(*args)
    recv = cn.log_likelihood(*args, scheme="cfomd")
    assert recv == pytest.approx(scipy.stats.norm.logpdf(3.0, 2.5, 1.0))
    assert full - recv == pytest.approx(cs.log_censored_probability(1.0 - 1.2, 1.5, 1.0, 1.5))
    with pytest.raises(ValueError, match="scheme"):
        cn.log_likelihood(*args, scheme="random")
    with pytest.raises(ValueError, match="r"):
        cn.log_likelihood(*args[:5], np.array([1.0, -1.0]), 1.5)
    with pytest.raises(ValueError, match="eta"):
        cn.log_likelihood(*args[:6], -1.0)


# ----------------------------------------------------------------------------- the fusion centre
@pytest.mark.parametrize("feedback", ["state", "state+cov"])
def test_fc_decisions_and_weights_are_propositions_7_and_8(feedback):
    """The FC's decisions replay the sensors (innovation against the broadcast prediction,
    normalized by the local EKF's s or by s'), and its particle weights are Proposition 7/8."""
    rng = np.random.default_rng(6)
    n, P = 4, 800
    _, z = SC.sample(rng, n)
    eta = cs.threshold(2, 9)
    fc = cs.nonlinear._FusionCentre(SC, "cfwmd", feedback, eta, 2.0, z, rng.random(z.shape))
    x = SC.dynamics.initial(rng, n, P)
    P_loc = np.broadcast_to(SC.dynamics.P0, (n, 9, 4, 4)).copy()
    est, est_cov = np.broadcast_to(SC.dynamics.m0, (n, 4)).copy(), \
        np.broadcast_to(SC.dynamics.P0, (n, 4, 4)).copy()
    for t in range(1, 4):
        x = SC.dynamics.transition(rng, t, x)
        lw = fc.log_weight(t, x)
        # an independent replay, sensor by sensor and trial by trial
        for b in range(n):
            xp = SC.F @ est[b]
            for i in range(9):
                g = cn.jacobian(SC, xp)[i]
                if feedback == "state":
                    Pp = SC.F @ P_loc[b, i] @ SC.F.T + SC.Q
                    s = g @ Pp @ g + 1.0
                    w = Pp @ g / s
                    A = np.eye(4) - np.outer(w, g)
                    P_loc[b, i] = A @ Pp @ A.T + np.outer(w, w)
                else:
                    s = g @ (SC.F @ est_cov[b] @ SC.F.T + SC.Q) @ g + 1.0
                nu = z[b, t - 1, i] - cn.amplitude(SC, xp[[0, 2]])[i]
                assert fc.s[b, t - 1, i] == pytest.approx(s, rel=1e-10)
                assert fc.sent[b, t - 1, i] == (nu * nu >= eta * s)
        hx = cn.amplitude(SC, x[..., [0, 2]])
        ref = cn.log_likelihood(fc.sent[:, t - 1][:, None], z[:, t - 1][:, None], hx,
                                fc.hx_pred[:, None], fc.s[:, t - 1][:, None], SC.rvec, eta)
        ref += 0.5 * np.log(2 * np.pi) * fc.sent[:, t - 1].sum(-1)[:, None]  # constants
        assert np.max(np.abs(lw - ref)) < 1e-8
        w = np.exp(lw - lw.max(axis=1, keepdims=True))
        w /= w.sum(axis=1, keepdims=True)
        est = np.einsum("np,npk->nk", w, x)
        dev = x - est[:, None]
        est_cov = np.einsum("np,npk,npl->nkl", w, dev, dev)
        fc.observe(t, est, est_cov if feedback == "state+cov" else None)


def test_no_feedback_decisions_use_the_local_ekfs():
    rng = np.random.default_rng(7)
    _, z = SC.sample(rng, 50)
    eta = cs.threshold(3, 9)
    fc = cs.nonlinear._FusionCentre(SC, "cfomd", "none", eta, 3.0, z, rng.random(z.shape))
    loc = cn.local_ekf(SC, z)
    assert np.array_equal(fc.sent, loc["nu"] ** 2 >= eta * loc["s"])
    # the local innovations are roughly N(0, s): about l = 3 of 9 send (EKF approximation)
    assert abs(fc.sent.sum(-1).mean() - 3) < 0.6


# ----------------------------------------------------------------------------- run
KW = dict(l=2, n_trials=12, n_particles=300, seed=11)


def test_run_identical_for_any_chunking_and_executor():
    ref = cn.run(SC, "cfwmd", block_size=4, **KW)
    a = cn.run(SC, "cfwmd", block_size=4, chunk_size=4, **KW)
    with concurrent.futures.ThreadPoolExecutor(2) as ex:
        b = cn.run(SC, "cfwmd", block_size=4, chunk_size=8, executor=ex, **KW)
    with concurrent.futures.ProcessPoolExecutor(2) as ex:
        c = cn.run(SC, "cfwmd", block_size=4, executor=ex, feedback="state", **KW)
    for other in (a, b, c):
        assert np.array_equal(ref.mc.samples, other.mc.samples)


def test_result_is_a_censoring_result():
    res = cn.run(SC, "cfwmd", feedback="state+cov", block_size=6, **KW)
    assert isinstance(res, cs.CensoringResult)
    assert res.mc.samples.shape == (12, 20, 7)
    assert res.rmse_position.value.shape == (20,) and res.rmse_velocity.value.shape == (20,)
    assert np.all(res.rmse_position.value > 0) and np.all(np.isfinite(res.rmse_position.stderr))
    sq = res.mc.samples[..., [0, 2]].sum(-1)
    assert np.allclose(res.rmse_position.value, np.sqrt(sq.mean(0)))
    assert np.array_equal(res.time, np.arange(1, 21))
    v, e = res.time_averaged_rmse("velocity")
    assert v > 0 and e > 0
    assert 0 <= res.transmissions.value.min() and res.transmissions.value.max() <= 9
    assert res.eta == pytest.approx(cs.threshold(2, 9))
    assert (res.scheme, res.feedback, res.l, res.n_particles) == ("cfwmd", "state+cov", 2.0, 300)
    other = cn.run(SC, "cfomd", feedback="state+cov", block_size=6, **KW)
    d, se = cs.paired_difference(res, other)
    assert np.isfinite(d) and se > 0
    with pytest.raises(ValueError, match="paired"):
        cs.paired_difference(res, cn.run(SC, "cfomd", block_size=3, **KW))


def test_all_send_and_random_rates():
    a = cn.run(SC, "all-send", **KW)
    assert np.all(a.mc.samples[..., 4] == 9)
    r = cn.run(SC, "random", **{**KW, "n_trials": 60})
    v, e = r.average_transmissions
    assert abs(v - 2) < 4.5 * e


def test_trials_are_paired_across_schemes_and_feedback():
    """The truth and the measurements depend only on (seed, n_trials, block_size)."""
    a = cn.run(SC, "all-send", **KW)
    b = cn.run(SC, "all-send", **{**KW, "l": 5})  # l is ignored by all-send
    assert np.array_equal(a.mc.samples, b.mc.samples)
    c = cn.run(SC, "cfomd", feedback="none", **KW)
    d = cn.run(SC, "cfomd", feedback="none", **{**KW, "n_particles": 100})
    assert np.array_equal(c.mc.samples[..., 4], d.mc.samples[..., 4])  # same decisions


def test_cfwmd_beats_cfomd_and_covariance_feedback_meets_the_target_better():
    kw = dict(l=2, n_trials=50, n_particles=1500, seed=3, block_size=25)
    w = cn.run(SC, "cfwmd", **kw)
    o = cn.run(SC, "cfomd", **kw)
    d, se = cs.paired_difference(w, o)
    assert d < -3 * se
    w2 = cn.run(SC, "cfwmd", feedback="state+cov", **kw)
    t1, e1 = w.average_transmissions
    t2, e2 = w2.average_transmissions
    assert t1 < 2 - 3 * e1  # state feedback: fewer sends than designed (Table III)
    assert abs(t2 - 2) < abs(t1 - 2)


def test_run_validation():
    with pytest.raises(ValueError, match="scenario"):
        cn.run(cs.LinearScenario(), "cfwmd", **KW)
    with pytest.raises(ValueError, match="scheme"):
        cn.run(SC, "cfwmd2", **KW)
    with pytest.raises(ValueError, match="feedback"):
        cn.run(SC, "cfwmd", feedback="cov", **KW)
    with pytest.raises(ValueError, match="Remark 4"):
        cn.run(SC, "cfwmd", feedback="none", **KW)
    with pytest.raises(ValueError, match="likelihood"):
        cn.run(SC, "cfwmd", likelihood="other", **KW)
    with pytest.raises(ValueError, match="l "):
        cn.run(SC, "cfwmd", **{**KW, "l": 10})
    with pytest.raises(ValueError, match="n_particles"):
        cn.run(SC, "cfwmd", **{**KW, "n_particles": 0})
    with pytest.raises(ValueError, match="n_trials"):
        cn.run(SC, "cfwmd", **{**KW, "n_trials": 0})
