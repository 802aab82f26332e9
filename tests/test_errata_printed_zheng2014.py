"""Printed-form tests of the zheng2014 errata (book/errata.md, section on Zheng, Niu and
Varshney (2014)).

Each test evaluates what the paper prints (a formula, a value or a statement) and asserts that
the erratum's check rejects it, then that the correction passes the same check. The checks use
the library (``fusioncenter.censoring``); where a check lives only in a chapter it is re-stated
here with the chapter's numbers. Every Monte Carlo has a fixed seed and runs in under a second,
except Proposition 6's pattern frequencies (40 000 simulated local filters) and Fig. 2's
no-sender fractions (four small particle-filter runs): a few seconds each.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.integrate
import scipy.stats
from errata_marks import erratum

from fusioncenter import censoring as cs
from fusioncenter.censoring import nonlinear_model as nm
from fusioncenter.censoring import vector

ETA1 = cs.threshold(1, 2)  # l = 1 of N = 2, one degree of freedom


# ======================================================================= Section III, Prop. 1
def _silent_by_quadrature(mu, s, r, eta):
    """P(|nu| < sqrt(eta s)) for nu ~ N(mu, r), by quadrature of the Gaussian density."""
    a = math.sqrt(eta * s)
    return scipy.integrate.quad(lambda v: scipy.stats.norm.pdf(v, mu, math.sqrt(r)), -a, a,
                                epsabs=1e-13, epsrel=1e-12)[0]


def _is_the_silent_probability(formula, s=3.7, r=1.0, eta=ETA1) -> bool:
    """The check of (9)/(14): ``formula(mu)`` is the silent probability for every mean mu of
    the innovation, including means beyond the threshold (here eta s = 1.68)."""
    for mu in (-2.5, -1.2, -0.3, 0.0, 0.4, 1.2, 2.5):
        with np.errstate(invalid="ignore"):
            value = formula(mu, s, r, eta)
        if not abs(value - _silent_by_quadrature(mu, s, r, eta)) < 1e-9:  # NaN fails too
            return False
    return True


def _q_difference(xi1, xi2):
    return scipy.stats.norm.sf(xi1) - scipy.stats.norm.sf(xi2)


@erratum("erratum-zheng2014-prop1-xi-definitions")
def test_prop1_xi_as_printed_is_not_the_silent_probability():
    def printed(mu, s, r, eta):  # mu under the square root, as after (9)
        root = np.sqrt(eta * s - mu)
        return _q_difference(-root / math.sqrt(r), root / math.sqrt(r))

    def corrected(mu, s, r, eta):  # (14): mu outside the root
        a = math.sqrt(eta * s)
        return _q_difference((-a - mu) / math.sqrt(r), (a - mu) / math.sqrt(r))

    assert not _is_the_silent_probability(printed)
    assert _is_the_silent_probability(corrected)
    assert _is_the_silent_probability(cs.censored_probability)  # the library's (14)


# ================================================================= Section III, Remark 2 (II)
@erratum("erratum-zheng2014-remark2-ii-exact")
def test_remark2_likelihood_is_exact_for_the_broadcast_covariance():
    """Remark 2 (II) calls (12)-(14) approximate because the broadcast covariance is an
    empirical estimate, i.e. the exact silent probability would use the true prediction
    covariance. Given x_k and what was broadcast, the sensor's decision is a function of its
    noise only: the simulated silent frequency is (14) with the *broadcast* s', whatever its
    accuracy, and not (14) with the true innovation variance."""
    sc = cs.LinearScenario()
    r, h = 1.0, sc.H[0]
    s_true = float(sc.local_filters()["s"][-1, 0])  # r + h^T P h in steady state (about 6.85)
    s_broadcast = 3.0  # an inaccurate empirical estimate, as the PF's can be
    rng = np.random.default_rng(28)
    n = 400_000
    x = np.array([1.3, 9.0])
    x_pred = np.array([0.4, 10.5])  # the broadcast prediction
    nu = h @ x + rng.standard_normal(n) * math.sqrt(r) - h @ x_pred
    freq = np.mean(nu**2 < ETA1 * s_broadcast)
    mu = h @ (x - x_pred)

    def passes(p):
        return abs(freq - p) < 4 * math.sqrt(p * (1 - p) / n)

    assert not passes(cs.censored_probability(mu, s_true, r, ETA1))  # the printed reading
    assert passes(cs.censored_probability(mu, s_broadcast, r, ETA1))


# ============================================================ Section III, Prop. 3, (16)-(18)
def _total_mass(version, C, eta, hx, r):
    """Sum over the four send patterns (N = 2) of the integral of the no-feedback likelihood
    over the received values: trapezoid grids on hx -/+ 11 standard deviations."""
    u = np.linspace(-11.0, 11.0, 1401)
    total = 0.0
    for pat in ((0, 0), (1, 0), (0, 1), (1, 1)):
        recv = [i for i in range(2) if pat[i]]
        if not recv:
            zz = np.zeros((1, 2))
        elif len(recv) == 1:
            zz = np.zeros((u.size, 2))
            zz[:, recv[0]] = hx[recv[0]] + u * math.sqrt(r[recv[0]])
        else:
            g1, g2 = np.meshgrid(u[::4], u[::4], indexing="ij")
            zz = np.stack([hx[0] + g1.ravel() * math.sqrt(r[0]),
                           hx[1] + g2.ravel() * math.sqrt(r[1])], axis=-1)
        sent = np.broadcast_to(np.array(pat, dtype=bool), zz.shape)
        f = np.exp(cs.log_likelihood_no_feedback(sent, zz, np.broadcast_to(hx, zz.shape), C, r,
                                                 eta, version=version))
        if not recv:
            total += float(f[0])
        elif len(recv) == 1:
            total += scipy.integrate.trapezoid(f, zz[:, recv[0]])
        else:
            m = u[::4].size
            step = (u[4] - u[0]) ** 2 * math.sqrt(r[0] * r[1])
            total += float(scipy.integrate.trapezoid(
                scipy.integrate.trapezoid(f.reshape(m, m), axis=1), axis=0)) * step
    return total


@erratum("erratum-zheng2014-prop3-received-factor")
def test_prop3_as_printed_does_not_sum_to_one():
    sc = cs.LinearScenario()
    C, r, hx = sc.local_filters()["C"][0], np.ones(2), np.array([0.7, 0.7])
    printed = _total_mass("printed", C, ETA1, hx, r)
    corrected = _total_mass("corrected", C, ETA1, hx, r)
    assert not abs(printed - 1) < 1e-3 and printed == pytest.approx(2.28, abs=0.01)
    assert abs(corrected - 1) < 1e-3


# ====================================================================== Section III, (21)
@erratum("erratum-zheng2014-eq21-local-predictions")
def test_eq21_prediction_errors_are_correlated_with_the_state():
    """(21) gives the local predictions the law N(x_k, Sigma) given x_k, i.e. prediction errors
    e = x_k - xhat independent of x_k: Cov(e, x_k) = 0. Simulating a local Kalman filter of the
    Section VII.A model gives Cov(e, x_k) = P_{k|k-1} (e is orthogonal to xhat)."""
    sc = cs.LinearScenario()
    lf = sc.local_filters()
    rng = np.random.default_rng(31)
    n, k = 40_000, 4
    x, z = sc.sample(rng, n)
    xh = np.broadcast_to(np.asarray(sc.x0, float), (n, 2)).copy()  # known x_0
    h = sc.H[0]
    for t in range(1, k + 1):
        xh = xh @ sc.F.T
        if t < k:
            xh = xh + (z[:, t - 1, 0] - xh @ h)[:, None] * lf["gain"][t - 1, 0]
    e = x[:, k] - xh
    emp = (e - e.mean(0)).T @ (x[:, k] - x[:, k].mean(0)) / n
    P = lf["P_pred"][k - 1, 0]
    tol = 0.05 * np.abs(P).max()

    def passes(claim):
        return np.abs(emp - claim).max() < tol

    assert not passes(np.zeros((2, 2)))
    assert passes(P)


# ==================================================== Section III, (16) with (21); Fig. 3
@erratum("erratum-zheng2014-eq16-printed-equals-cfomd")
def test_printed_prop3_weights_are_cfomd_weights():
    """The check: CFwMD's normalized particle weights differ from CFoMD's (else the two
    filters give the same estimates and CFwMD cannot beat CFoMD in Fig. 3)."""
    sc = cs.LinearScenario()
    C, r = sc.local_filters()["C"][2], np.ones(2)
    rng = np.random.default_rng(32)
    hx = rng.normal(0.0, 2.0, (300, 2))  # h^T x of 300 particles

    def weights(lw):
        w = np.exp(lw - lw.max())
        return w / w.sum()

    def differs(version, sent, zz):
        cfomd = np.where(sent, scipy.stats.norm.logpdf(zz, hx, 1.0), 0.0).sum(-1)
        lw = cs.log_likelihood_no_feedback(sent, zz, hx, C, r, ETA1, version=version)
        # total variation distance between the two weight vectors
        return 0.5 * np.abs(weights(lw) - weights(cfomd)).sum() > 0.02

    # (the all-silent pattern is a constant in x under (21) in both versions: erratum on (21))
    for pattern, z in (((1, 0), (0.9, 0.0)), ((1, 1), (0.9, -0.4))):
        sent = np.broadcast_to(np.array(pattern, dtype=bool), hx.shape)
        zz = np.broadcast_to(np.array(z), hx.shape)
        assert not differs("printed", sent, zz)
        assert differs("corrected", sent, zz)


# ================================================================ Section III, after (23)
@erratum("erratum-zheng2014-cross-covariance-initialisation")
def test_cross_covariance_initialisation_p0_not_zero():
    """Two local filters started from the common prior N(m0, P0) (P0 != 0): at k = 1 their
    prediction errors are both F (x0 - m0) + u0, so (22) must give F P0 F^T + Q, which needs
    P^{ij}_{0|0} = P0; the printed 0 gives Q."""
    F = np.array([[1.0, 1.0], [0.0, 1.0]])
    Q = 4 * np.array([[0.25, 0.5], [0.5, 1.0]])
    P0 = np.diag([3.0, 1.0])
    rng = np.random.default_rng(43)
    n = 50_000
    x0 = rng.multivariate_normal(np.zeros(2), P0, n)  # m0 = 0: both filters start at 0
    x1 = x0 @ F.T + rng.multivariate_normal(np.zeros(2), Q, n)
    e1 = e2 = x1 - 0.0  # both predictions are F m0 = 0
    emp = e1.T @ e2 / n

    def passes(init):
        pred = F @ init @ F.T + Q  # (22)
        return np.abs(emp - pred).max() < 0.03 * np.abs(pred).max()

    assert not passes(np.zeros((2, 2)))
    assert passes(P0)


# ================================================================== Section IV, Theorem 1
def _nis_rule_is_a_kl_rule(P, h, r, eta, nus) -> bool:
    """Is there a KL threshold zeta with {nu^2/s >= eta} = {KL(prior || posterior) >= zeta} on
    the innovations ``nus``? The divergence is taken on the range of P (P may be singular)."""
    g = h @ P @ h
    s = g + r
    w = P @ h / s
    P_up = P - s * np.outer(w, w)
    evals, evecs = np.linalg.eigh(P)
    U = evecs[:, evals > 1e-9 * evals.max()]
    Pp, Pu, wr = U.T @ P @ U, U.T @ P_up @ U, U.T @ w
    Pu_inv = np.linalg.inv(Pu)
    const = 0.5 * (np.trace(Pu_inv @ Pp) - U.shape[1] + np.linalg.slogdet(Pu)[1]
                   - np.linalg.slogdet(Pp)[1])
    kl = const + 0.5 * (wr @ Pu_inv @ wr) * nus**2
    send = nus**2 / s >= eta
    return bool(send.any() and (~send).any() and kl[~send].max() < kl[send].min())


@erratum("erratum-zheng2014-theorem1-scalars")
def test_theorem1_scalars_are_not_enough():
    """The proof concludes equivalence because w^T P_post^{-1} w and s are scalars. Both are
    scalars for every (P, h); the equivalence needs g = h^T P h > 0. With a singular P whose
    range misses h (g = 0) the KL divergence is the same for every innovation."""
    sc = cs.LinearScenario()
    r, h = 1.0, sc.H[0]
    nus = np.linspace(-4, 4, 81)
    cases = {"P_{1|0} = Q (rank one, g = 1)": sc.Q,
             "steady state": sc.local_filters()["P_pred"][-1, 0],
             "g = 0": np.diag([0.0, 2.0])}
    observed = {name: _nis_rule_is_a_kl_rule(P, h, r, ETA1, nus) for name, P in cases.items()}
    printed = {name: True for name in cases}  # "both are scalars. Hence ... equivalent"
    corrected = {name: bool(h @ P @ h > 0) for name, P in cases.items()}
    assert printed != observed
    assert corrected == observed


# ===================================================================== Section V, Prop. 6
@erratum("erratum-zheng2014-prop6-received-factor")
def test_prop6_as_printed_gives_patterns_the_wrong_mass():
    """N = 2, l = 1, vector model of Section VII.B: the printed (40) integrated over the
    received values gives the pattern (sensor 1 silent, sensor 2 sent) the mass P_1 (the
    received factor integrates to one), in total 1 + P_1 + P_2 + P_12; the corrected
    likelihood gives P_1 - P_12, which the simulated frequency confirms, in total 1."""
    sc = vector.VectorScenario()
    t = 6
    eta = cs.threshold(1, 2, dof=2)
    lf = sc.local_filters()
    cov = vector.silent_covariance(sc, lf["Sigma"][t - 1])
    p1 = math.exp(vector.log_all_silent(cov[:2, :2], lf["S"][t - 1][:1], eta))
    p12 = math.exp(vector.log_all_silent(cov, lf["S"][t - 1], eta))
    rng = np.random.default_rng(34)
    n = 40_000
    _, z = sc.sample(rng, n)
    sent = vector.local_decisions(sc, eta, z)[:, t - 1]
    freq = np.mean(~sent[:, 0] & sent[:, 1])

    def passes(mass_of_pattern, total):
        se = math.sqrt(mass_of_pattern * (1 - mass_of_pattern) / n)
        return abs(freq - mass_of_pattern) < 4 * se and abs(total - 1) < 1e-9

    printed_total = vector.printed_mass(sc, 1, t)
    assert printed_total == pytest.approx(1 + 2 * p1 + p12, rel=1e-9)
    assert not passes(p1, printed_total)
    corrected = [p12, p1 - p12, p1 - p12, 1 - 2 * p1 + p12]
    assert passes(p1 - p12, sum(corrected))


# ==================================================================== Section VI, Prop. 7
@erratum("erratum-zheng2014-prop7-mu-index")
def test_prop7_mu_needs_the_same_sensor_twice():
    """Sensor i = 1 (index 0), the broadcast prediction xp, the target at x: the simulated
    silent frequency of its censoring against h^1(xp) is (44)'s factor with
    mu = h^1(x) - h^1(xp), not with the printed h^j(x) - h(xp) (here j = 5)."""
    sc = nm.NonlinearScenario()
    r = 1.0
    eta = cs.threshold(2, 9)
    s = 2.5
    x, xp = np.array([-4.0, -6.0]), np.array([-3.0, -5.0])
    hx, hxp = nm.amplitude(sc, x), nm.amplitude(sc, xp)
    i, j = 0, 4
    rng = np.random.default_rng(36)
    n = 200_000
    nu = hx[i] + rng.standard_normal(n) * math.sqrt(r) - hxp[i]
    freq = np.mean(nu**2 < eta * s)

    def passes(mu):
        p = cs.censored_probability(mu, s, r, eta)
        return abs(freq - p) < 4 * math.sqrt(p * (1 - p) / n)

    assert not passes(hx[j] - hxp[i])  # printed: another sensor's function at x
    assert passes(hx[i] - hxp[i])


@erratum("erratum-zheng2014-prop7-conditioning")
def test_prop7_likelihood_depends_on_every_broadcast():
    """(44) conditions on the last broadcast only. Two broadcast histories with the same
    xhat_{1|1} but different xhat_{0|0} give the sensors different s_2 (their EKF covariance
    recursion linearized at F xhat_{0|0} at step 1), hence different likelihoods (44) at k = 2:
    the likelihood is not a function of (x_2, xhat_{1|1}). With the whole history fixed, s_2 is
    fixed."""
    sc = nm.NonlinearScenario()
    F, Q, P0, r = sc.F, sc.Q, sc.dynamics.P0, 1.0

    def s2(history):
        P = P0
        for b in history:  # b = xhat_{k-1|k-1}, the broadcast at step k
            g = nm.jacobian(sc, F @ b)[0]  # sensor 1's gradient at the broadcast prediction
            _, s, P = nm.ekf_covariance_step(P, g, F, Q, r)
        return float(s)

    last = np.array([-6.0, 2.0, -6.0, 2.0])
    a = s2([np.array([-8.0, 2.0, -8.0, 2.0]), last])
    b = s2([np.array([5.0, 0.0, -2.0, 1.0]), last])
    printed_is_a_function_of_the_last_broadcast = abs(a - b) < 1e-9 * abs(a)
    assert not printed_is_a_function_of_the_last_broadcast
    assert s2([np.array([-8.0, 2.0, -8.0, 2.0]), last]) == a  # the full history decides


# ================================================================ Section VII.A.1, Fig. 2
@pytest.fixture(scope="module")
def no_sender_fractions():
    """Fraction of steps at which none of N = 4 sensors sends, CFwMD and CFwMD2, l = 1 and 2
    (100 trials, 200 particles): (mean, standard error over trials)."""
    sc = cs.LinearScenario(N=4)
    out = {}
    for l in (1.0, 2.0):
        for fb in ("state", "state+cov"):
            res = cs.run(sc, "cfwmd", l=l, n_trials=100, n_particles=200, seed=38, feedback=fb)
            per_trial = (res.mc.samples[..., res.scenario.d] == 0).mean(axis=1)
            out[l, fb] = (per_trial.mean(), per_trial.std(ddof=1) / math.sqrt(per_trial.size))
    return out


@erratum("erratum-zheng2014-fig2-no-sender-probability")
@pytest.mark.parametrize("l, printed, corrected", [
    (1.0, 0.32, {"state": 0.55, "state+cov": 0.54}),  # (3/4)^4
    (2.0, 0.06, {"state": 0.28, "state+cov": 0.18}),  # (1/2)^4
])
def test_fig2_probability_that_no_sensor_sends(no_sender_fractions, l, printed, corrected):
    assert printed == pytest.approx((1 - l / 4) ** 4, abs=0.005)

    def passes(fb, claim):
        mean, se = no_sender_fractions[l, fb]
        return abs(mean - claim) < 4 * se

    for fb in ("state", "state+cov"):
        assert not passes(fb, printed)
        assert passes(fb, corrected[fb])


# ================================================================ Section VII.C, Fig. 8
@erratum("erratum-zheng2014-fig8-saving")
def test_fig8_saving_of_cfwmd():
    """The saving against all-send is 1 - lbar / N with the measured lbar; the paper's own
    Table III gives lbar = 1.5978 for CFwMD at l = 2 (N = 9)."""
    lbar, N = 1.5978, 9

    def passes(saving):
        return abs(saving - (1 - lbar / N)) < 0.005

    assert not passes(0.78)  # printed
    assert passes(0.82)
    assert 0.78 == pytest.approx(1 - 2 / 9, abs=0.005)  # what 78 % is: the design value


# ================================================================ Appendix A, (48)
def _kalman_pieces(P, h, r):
    g = h @ P @ h
    s = g + r
    w = P @ h / s
    return g, s, w, P - s * np.outer(w, w)


@erratum("erratum-zheng2014-eq48-proportional")
def test_eq48_coefficient_is_not_a_constant_times_one_over_s():
    """(48): w^T (P_post^{-1} + P^{-1}) w = c / s_k with one constant c. On the Section VII.A
    model (k = 2..20, where P_{k|k-1} is invertible) c_k = coefficient * s_k moves; the
    corrected (g_k / s_k)(1/r + 1/s_k) matches the coefficient at every k."""
    sc = cs.LinearScenario()
    r, h = 1.0, sc.H[0]
    coef, corrected = [], []
    for P in sc.local_filters()["P_pred"][1:, 0]:
        g, s, w, P_up = _kalman_pieces(P, h, r)
        coef.append(w @ (np.linalg.inv(P_up) + np.linalg.inv(P)) @ w)
        corrected.append(g / s * (1 / r + 1 / s))
    coef = np.array(coef)
    s_k = sc.local_filters()["s"][1:, 0]

    def passes(model):
        return np.allclose(coef, model, rtol=1e-9)

    c = coef[-1] * s_k[-1]  # the constant that fits in steady state
    assert not passes(c / s_k)
    assert passes(np.array(corrected))


def _gaussian_kl_on_range(m_p, P_p, m_q, P_q, U):
    Pp, Pq, dm = U.T @ P_p @ U, U.T @ P_q @ U, U.T @ (m_q - m_p)
    inv = np.linalg.inv(Pq)
    return 0.5 * (np.trace(inv @ Pp) - U.shape[1] + dm @ inv @ dm
                  + np.linalg.slogdet(Pq)[1] - np.linalg.slogdet(Pp)[1])


@erratum("erratum-zheng2014-eq48-proportional")
def test_eq48_kl_thresholds_one_way_and_symmetric():
    """The KL thresholds equivalent to eta(l = 1) on the Section VII.A model (N = 2), from the
    two Gaussians at nu^2 = eta s_k: Theorem 1's one-way divergence moves from 0.381 to 3.296
    nats over k = 1..20, Corollary 2's symmetric divergence (Appendix A, (46)-(48)) from 0.591
    to 4.026 nats; the one-way numbers are not the symmetric ones."""
    sc = cs.LinearScenario()
    r, h = 1.0, sc.H[0]
    one_way, symmetric = [], []
    for P in sc.local_filters()["P_pred"][:, 0]:
        g, s, w, P_up = _kalman_pieces(P, h, r)
        evals, evecs = np.linalg.eigh(P)
        U = evecs[:, evals > 1e-9 * evals.max()]  # P_{1|0} = Q has rank one
        m, m_post = np.zeros(2), w * math.sqrt(ETA1 * s)
        fwd = _gaussian_kl_on_range(m, P, m_post, P_up, U)
        rev = _gaussian_kl_on_range(m_post, P_up, m, P, U)
        one_way.append(fwd)
        symmetric.append(fwd + rev)

    def passes(values, lo, hi):
        return abs(values[0] - lo) < 5e-4 and abs(values[-1] - hi) < 5e-4

    assert passes(one_way, 0.381, 3.296)
    assert not passes(symmetric, 0.381, 3.296)  # the page's former attribution to (48)
    assert passes(symmetric, 0.591, 4.026)


# ===================================================== Section V, before (32): equal dimensions
def _nis_of_mixed_sensors(n=20_000, T=20, seed=32):
    """Local Kalman filters of the Section VII model (known x_0) for two sensors of different
    measurement dimension: sensor 1 sees the position (r = 1), sensor 2 the whole state
    (R = diag(2, 4), as in Section VII.B). Returns each sensor's NIS, shape (n, T)."""
    rng = np.random.default_rng(seed)
    F = np.array([[1.0, 1.0], [0.0, 1.0]])
    Q = 4.0 * np.array([[0.25, 0.5], [0.5, 1.0]])
    sensors = [(np.array([[1.0, 0.0]]), np.array([[1.0]])), (np.eye(2), np.diag([2.0, 4.0]))]
    x = np.tile([0.0, 10.0], (n, 1))
    est = [x.copy() for _ in sensors]
    P = [np.zeros((2, 2)) for _ in sensors]
    nis = [np.empty((n, T)) for _ in sensors]
    g = np.array([1.0, 2.0])  # Q = g g^T has rank one
    for k in range(T):
        x = x @ F.T + rng.standard_normal((n, 1)) * g
        for i, (H, R) in enumerate(sensors):
            z = x @ H.T + rng.standard_normal((n, H.shape[0])) @ np.linalg.cholesky(R).T
            est[i] = est[i] @ F.T
            P[i] = F @ P[i] @ F.T + Q
            S = H @ P[i] @ H.T + R
            nu = z - est[i] @ H.T
            nis[i][:, k] = np.einsum("ni,ij,nj->n", nu, np.linalg.inv(S), nu)
            K = P[i] @ H.T @ np.linalg.inv(S)
            est[i] = est[i] + nu @ K.T
            P[i] = P[i] - K @ S @ K.T
    return nis


@erratum("erratum-zheng2014-5-before-32-equal-dimensions")
def test_one_threshold_for_innovations_of_different_dimensions_misses_l():
    """N = 2, l = 1, innovations of dimension 1 and 2. The assumption of equal dimensions is
    not without loss of generality: the one threshold (32) (whichever n_nu it takes) gives
    on average 0.74 or 1.30 active sensors, not l = 1; per-sensor thresholds chi2_{n_i}(l/N)
    give l (exactly, and in a simulation of the local Kalman filters)."""
    nis = _nis_of_mixed_sensors()
    dims, N, l = (1, 2), 2, 1.0

    def active(etas):
        exact = sum(scipy.stats.chi2.sf(e, d) for e, d in zip(etas, dims, strict=True))
        simulated = sum(np.mean(v >= e) for v, e in zip(nis, etas, strict=True))
        se = math.sqrt(sum(np.var(v >= e) for v, e in zip(nis, etas, strict=True)) / nis[0].size)
        return exact, simulated, se

    for n_nu in dims:  # printed: one threshold chi2_{n_nu}(l/N) for both sensors
        exact, simulated, se = active([cs.threshold(l, N, dof=n_nu)] * 2)
        assert abs(exact - l) > 0.25 and abs(simulated - l) > 0.25
    exact, simulated, se = active([cs.threshold(l, N, dof=d) for d in dims])  # corrected
    assert exact == pytest.approx(l, abs=1e-12)
    assert abs(simulated - l) < 0.01
