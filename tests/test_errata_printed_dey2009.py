"""Printed-form tests of the dey2009 errata (book/errata.md, "Dey, Leong and Evans (2009)").

Each test evaluates what the paper prints, asserts that the erratum's check rejects it, and
asserts that the correction passes the same check. The checks restate those of the chapters
(book/dey2009/scalar-bounds.md, vector.md, multisensor.md) with the same kind of numbers.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.integrate
import scipy.special
from errata_marks import erratum

from fusioncenter import fading, riccati


def _eE1(x):
    return np.exp(x) * scipy.special.exp1(x)


def _quad_exp(f, lam):
    """E[f(r)] for r ~ Exp(lam) (mean 1/lam), by quadrature."""
    return scipy.integrate.quad(lambda t: lam * np.exp(-lam * t) * f(t), 0.0, np.inf,
                                epsabs=0.0, epsrel=1e-12, limit=200)[0]


# ---------------------------------------------------------------- (20)'s denominator
@erratum("erratum-dey2009-eq20-denominator")
def test_printed_20_is_not_the_bound_derived_before_it():
    """The bound displayed before (19), once gamma/(gamma + sigma_v^2) <= 1 is dropped, is the map
    of (20): sigma_w^2 + a^2 (sigma_v^2 + sigma_n sqrt(2 lam) q / (sqrt(q + sigma_v^2)
    (u + sqrt(u^2 + 4/pi)))), u = sqrt(sigma_n^2 lam / (2 (sigma_v^2 + q))). The sum of two
    roots is that map; the printed nested root is not, and its iterates (Fig. 2's parameters)
    settle in the millions instead of a few hundred."""
    a, sw2, sv2, sn2, lam = 1.25, 1.0, 1.0, 4.0, 100.0  # Fig. 2, sigma_v = 1
    half = sn2 * lam / 2

    def derived(q):
        u = np.sqrt(sn2 * lam / (2 * (sv2 + q)))
        return sw2 + a * a * (sv2 + np.sqrt(sn2) * np.sqrt(2 * lam) * q
                              / (np.sqrt(q + sv2) * (u + np.sqrt(u * u + 4 / np.pi))))

    def printed(q):
        return sw2 + a * a * (sv2 + np.sqrt(sn2) * np.sqrt(2 * lam) * q
                              / np.sqrt(half + np.sqrt(half + 4 / np.pi * (q + sv2))))

    def corrected(q):
        return sw2 + a * a * (sv2 + np.sqrt(sn2) * np.sqrt(2 * lam) * q
                              / (np.sqrt(half) + np.sqrt(half + 4 / np.pi * (q + sv2))))

    q = np.logspace(-2, 6, 41)
    np.testing.assert_allclose(corrected(q), derived(q), rtol=1e-12)
    assert np.all(np.abs(printed(q) / derived(q) - 1) > 1e-3)  # 0.6 % at q = 0.01
    # the library's two sequences: printed limit far above the derived one
    lib_printed = fading.nakagami_q_as_printed(a, sw2, sv2, sn2, lam, 1.0, 400)
    lib_derived = fading.scalar_bounds(a, sw2, sv2, sn2, fading.Nakagami(0.5, lam), 1.0,
                                       400)["q"]
    np.testing.assert_allclose(lib_derived[1:], corrected(lib_derived[:-1]), rtol=1e-10)
    assert lib_printed[-1] > 1e6 and lib_derived[-1] < 1e3


# ------------------------------------------------------- beta_k in the display after (21)
@erratum("erratum-dey2009-vbar-beta")
def test_printed_weight_with_random_beta_is_not_the_factor_of_zbar():
    """The factor of Z_bar is 1 - m e^m E1(m), m = lam beta_bar. The corrected weight
    E_r[1 - beta_bar / (r + beta_bar)] equals it; the printed E_r[1 - beta_bar / (r + beta_k)],
    with beta_k = sigma_n^2 / (c P_k c' + sigma_v^2) from a P_k spread around V_bar, does not."""
    lam, sv2, sn2 = 1.0, 0.5, 4.0
    c = np.array([1.0, 0.5])
    P_paths = [np.array([[2.0, 0.3], [0.3, 1.0]]), np.array([[8.0, -0.5], [-0.5, 3.0]])]
    Vbar = sum(P_paths) / 2  # two equally likely P_k, mean V_bar
    bbar = sn2 / (c @ Vbar @ c + sv2)
    m = lam * bbar
    factor = 1 - m * _eE1(m)
    corrected = _quad_exp(lambda r: 1 - bbar / (r + bbar), lam)
    printed = np.mean([_quad_exp(lambda r, b=sn2 / (c @ P @ c + sv2): 1 - bbar / (r + b), lam)
                       for P in P_paths])
    assert corrected == pytest.approx(factor, rel=1e-9)
    assert abs(printed / factor - 1) > 0.01


# -------------------------------------------------------------- (23) needs x_i > 0
@erratum("erratum-dey2009-amhm-positive")
def test_printed_23_domain_admits_a_point_where_it_is_undefined():
    """(23), 1 / sum x_i <= (1/M^2) sum 1/x_i, is checked on random points of its stated domain.
    The printed domain x_i >= 0 contains x with a zero component, where the right side is not
    a number; on x_i > 0 the inequality holds everywhere."""
    rng = np.random.default_rng(23)

    def holds(x):
        with np.errstate(divide="ignore"):
            rhs = np.sum(1.0 / x) / x.size**2
        return bool(np.isfinite(rhs) and 1.0 / np.sum(x) <= rhs * (1 + 1e-12))

    positive = [rng.uniform(1e-3, 10.0, rng.integers(1, 6)) for _ in range(2000)]
    assert all(holds(x) for x in positive)  # corrected domain
    boundary = np.array([0.0, 1.0, 2.0])  # in the printed domain x_i >= 0
    assert not holds(boundary)


# ---------------------------------------------------------------- Appendix B, A X A'
@erratum("erratum-dey2009-appb-transpose")
def test_printed_bound_without_transpose_is_not_an_upper_bound():
    """Condition (v): E_H[f_H(X*) | ...] <= Sigma_w + A X* A'. For a non-symmetric A the printed
    Sigma_w + A X A is not symmetric and Sigma_w + A X A - f_H(X) is indefinite; with A' the
    difference is positive semidefinite on every draw."""
    rng = np.random.default_rng(10)
    A = np.array([[1.2, 0.5], [0.0, 0.9]])
    c, Sw, sv2, sn2 = np.array([[1.0, 0.3]]), np.eye(2), 0.5, 2.0
    printed_fails = 0
    for _ in range(200):
        B = rng.standard_normal((2, 2))
        X = B @ B.T + 0.1 * np.eye(2)
        h = rng.rayleigh(1.0)
        f = riccati.riccati_step(X, A, Sw, h * c, [[h * h * sv2 + sn2]])
        assert np.linalg.eigvalsh(Sw + A @ X @ A.T - f).min() > -1e-9
        printed = Sw + A @ X @ A
        sym = (printed - f + (printed - f).T) / 2
        if not np.allclose(printed, printed.T) or np.linalg.eigvalsh(sym).min() < -1e-9:
            printed_fails += 1
    assert printed_fails > 150


# ---------------------------------------- Section 3.3.2 uses one channel noise sigma_n^2
@erratum("erratum-dey2009-3-3-2-channel-noise")
def test_printed_orthogonal_step_with_one_channel_noise_is_not_the_kalman_step():
    """Model (8)'s Kalman step carries sigma_{n_i}^2 in sensor i's term. With unequal channel
    noises the printed display (one sigma_n^2, whichever channel's) is not the Kalman step, and
    the one-sensor integral behind A'_1 matches quadrature only with sensor 1's own noise."""
    a, sw2, p = 1.1, 1.0, 3.0
    c, sv2, sn2 = np.array([1.0, 0.7]), np.array([0.5, 2.0]), np.array([0.05, 30.0])
    h2 = np.array([0.8, 1.7])
    kalman = riccati.riccati_step([[p]], [[a]], [[sw2]], (np.sqrt(h2) * c)[:, None],
                                  np.diag(h2 * sv2 + sn2))[0, 0]

    def step(noise):
        return sw2 + a * a * p / (1 + p * np.sum(h2 * c**2 / (h2 * sv2 + noise)))

    assert step(sn2) == pytest.approx(kalman, rel=1e-12)  # corrected
    for common in sn2:  # printed: one sigma_n^2 for both channels
        assert abs(step(common) / kalman - 1) > 0.01
    lam, gam = 1.5, 2.0
    quad = _quad_exp(lambda r: 1 / (1 + gam * r * c[0] ** 2 / (r * sv2[0] + sn2[0])), lam)

    def closed(noise):
        A, B = lam * noise / sv2[0], lam * noise / (sv2[0] + c[0] ** 2 * gam)
        return sv2[0] / (c[0] ** 2 * gam + sv2[0]) * (1 + (A - B) * _eE1(B))

    assert closed(sn2[0]) == pytest.approx(quad, rel=1e-10)
    assert abs(closed(sn2[1]) / quad - 1) > 0.01


# -------------------------- new: Section 3.3.2, the factor outside the expectation over r_2..r_M
def _orthogonal_two_sensors():
    c, sv2, sn2, lam, gam = (1.0, 1.0), (1.0, 4.0), 4.0, (1.0, 1.0), 2.0

    def S(r2):
        return 1 + gam * r2 * c[1] ** 2 / (r2 * sv2[1] + sn2)

    def factor(r2):
        return sv2[0] / (sv2[0] * S(r2) + c[0] ** 2 * gam)

    def bracket(r2):
        A = lam[0] * sn2 / sv2[0]
        B = lam[0] * sn2 * S(r2) / (sv2[0] * S(r2) + c[0] ** 2 * gam)
        return 1 + (A - B) * _eE1(B)

    def integrand(r1, r2):
        density = lam[0] * lam[1] * np.exp(-lam[0] * r1 - lam[1] * r2)
        return density / (S(r2) + gam * r1 * c[0] ** 2 / (r1 * sv2[0] + sn2))

    lhs = scipy.integrate.dblquad(integrand, 0.0, np.inf, 0.0, np.inf,
                                  epsabs=0.0, epsrel=1e-11)[0]
    return lhs, factor, bracket, lam[1]


@erratum("erratum-dey2009-3-3-2-factor-inside-expectation")
def test_printed_first_expectation_of_3_3_2_with_the_factor_outside_fails():
    """E_r[1 / (1 + gamma sum_i I_i)] (2-D quadrature, M = 2, one common sigma_n^2 so that only
    this slip is at stake) equals E_{r_2}[factor(r_2) (1 + (A_1 - B_1) e^{B_1} E1(B_1))]; the
    printed factor(r_2) E_{r_2}[...] is a function of r_2, wrong at every r_2 we try, and the
    reading that averages factor and bracket apart is wrong by about 0.14 %."""
    lhs, factor, bracket, lam2 = _orthogonal_two_sensors()
    inside = _quad_exp(lambda r2: factor(r2) * bracket(r2), lam2)
    assert inside == pytest.approx(lhs, rel=1e-9)
    e_bracket = _quad_exp(bracket, lam2)
    printed = [factor(r2) * e_bracket for r2 in (0.0, 0.5, 1.0, 2.0, 1e9)]
    assert min(abs(v / lhs - 1) for v in printed) > 0.005
    apart = _quad_exp(factor, lam2) * e_bracket
    assert abs(apart / lhs - 1) > 1e-4  # 100 times the quadrature tolerance


# ------------------------- Section 3, after Lemma 3.1: the quantifiers of the stability definition
def _stable_printed(log_norm, n_max=20_000, k_max=50):
    """The printed definition on a grid: for each eps > 0 *some* gamma > 0 and J work. We offer
    gamma = eps / 2 and the smallest J for that gamma; the bound log||M_{k-1}...M_{k-n}|| <= log J
    - n gamma + (|k| + n) eps must then hold for all n <= n_max, |k| <= k_max."""
    n = np.arange(1, n_max + 1)
    for eps in (1.0, 0.1, 0.01, 0.001):
        gamma = eps / 2
        log_J = max(0.0, float(np.max(log_norm(n) + n * gamma - n * eps)))
        k = np.arange(-k_max, k_max + 1)[:, None]
        bound = log_J - n * gamma + (np.abs(k) + n) * eps
        if not np.all(log_norm(n)[None, :] <= bound + 1e-9):
            return False
    return True


def _stable_corrected(log_norm, gamma, log_J, eps):
    """The corrected order (gamma > 0 fixed first, then every eps): violated at some n <= 10^5
    with k = 0 for this gamma, J and eps < gamma?"""
    n = np.arange(1, 100_001)
    return bool(np.all(log_norm(n) <= log_J - n * gamma + n * eps))


@erratum("erratum-dey2009-3-stability-quantifiers")
def test_printed_stability_definition_admits_products_that_do_not_decay():
    """M_k = 1 (the closed loop of a random walk that receives nothing: p_k = p_0 + k sigma_w^2
    diverges) and the Jordan block [[1, 1], [0, 1]] (||M^n|| grows like n) satisfy the printed
    definition, where gamma is chosen after eps; with gamma chosen first, no J saves them, and
    the exponentially decaying M_k = 0.9 passes."""
    def one(n):
        return np.zeros_like(n, dtype=float)

    def jordan(n):  # ||[[1, n], [0, 1]]||_2 = (n + sqrt(n^2 + 4)) / 2
        return np.log((n + np.sqrt(n * n + 4.0)) / 2)

    def decaying(n):
        return n * np.log(0.9)

    assert _stable_printed(one) and _stable_printed(jordan)  # printed: "stable"
    for gamma in (1.0, 0.1, 0.01):
        for log_J in (np.log(1e3), np.log(1e9)):
            assert not _stable_corrected(one, gamma, log_J, gamma / 2)
            assert not _stable_corrected(jordan, gamma, log_J, gamma / 2)
    gamma = -np.log(0.9) / 2
    for eps in (gamma / 2, gamma / 10, 1e-6):
        assert _stable_corrected(decaying, gamma, 0.0, eps)
    # the random walk with M_k = 1: its prediction variance grows without bound
    p = 1.0 + np.arange(1000) * 1.0
    assert p[-1] > 900


# ------------------------------- Lemma 3.2, proof: almost-sure convergence and the means
FIG1 = {"a": 1.25, "sw2": 1.0, "sv2": 1.0, "sn2": 4.0, "lam": 100.0}  # Fig. 1, sigma_v^2 = 1


def _f15(p, r, a=FIG1["a"], sw2=FIG1["sw2"], sv2=FIG1["sv2"], sn2=FIG1["sn2"]):
    """The scalar Riccati step (15), c = 1, power gain r."""
    b = sv2 + sn2 / r
    return sw2 + a * a * p * b / (p + b)


def _backward(r, k, p0):
    """Q_k(p0) = f_{r_1}(f_{r_2}(... f_{r_k}(p0))): the law of p_k, path by path monotone in k
    from p0 = 0 (Loynes)."""
    p = np.full(r.shape[1], float(p0))
    for j in range(k - 1, -1, -1):
        p = _f15(p, r[j])
    return p


@erratum("erratum-dey2009-lemma32-mean-convergence")
def test_almost_sure_convergence_does_not_give_the_means_but_domination_does():
    """Printed step: P_k -> stationary a.s., "hence" E[P_k] -> E[P_bar]. The same inference
    on X_k = k 1{U < 1/k} (X_k -> 0 for every U > 0) gives E[X_k] -> 0, but E[X_k] = 1 for
    every k. Repair: Q_k(0) increases path by path, and Q_k(p0) <= t Q_{k+1}(0) <= t P_bar
    with t = max(1, p0 / sigma_w^2) (f(t p) <= t f(p) for t >= 1, by concavity and
    f(0) = sigma_w^2 >= 0), so dominated convergence applies: on Fig. 1's parameters
    E[p_k] from p0 = 0, 1 and 1000 meets one limit, below s*."""
    u = (np.arange(1, 100_001) - 0.5) / 100_000  # a fine midpoint grid for U ~ U(0, 1)
    for k in (10, 100, 1000):
        X_k = k * (u < 1 / k)
        assert X_k.mean() == pytest.approx(1.0, abs=1e-9)  # E[X_k] = 1, not -> 0
    assert np.all(1000 * (u[u > 1e-3] < 1e-3) == 0)  # yet X_k(U) = 0 once k > 1/U

    rng = np.random.default_rng(32)
    r = fading.Rayleigh(FIG1["lam"]).sample(rng, (81, 4000))
    q0 = np.array([_backward(r, k, 0.0) for k in range(82)])
    assert np.all(np.diff(q0, axis=0) >= -1e-9)  # monotone in k, path by path
    t = 1000.0 / FIG1["sw2"]
    for k in (0, 1, 5, 20, 80):
        assert np.all(_backward(r, k, 1000.0) <= t * q0[k + 1] * (1 + 1e-12))  # domination
    means = [_backward(r, 80, p0).mean() for p0 in (0.0, 1.0, 1000.0)]
    assert max(means) - min(means) < 1e-6 * means[0]  # one limit, whatever p0
    s_star = fading.scalar_bound_limits(FIG1["a"], FIG1["sw2"], FIG1["sv2"], FIG1["sn2"],
                                        fading.Rayleigh(FIG1["lam"]))["s"]
    se = q0[81].std() / np.sqrt(q0.shape[1])
    assert means[0] < s_star - 5 * se


# ------------------------------- Appendix B, condition (v): "for sufficiently small h*"
def _pstar(r, a=FIG1["a"], sw2=FIG1["sw2"], sv2=FIG1["sv2"], sn2=FIG1["sn2"]):
    """The fixed point of f_{r*}: every X* with f_{r*}(X*) < X* is larger than it."""
    b = sv2 + sn2 / r
    B = b - sw2 - a * a * b
    return (-B + np.sqrt(B * B + 4 * sw2 * b)) / 2


@erratum("erratum-dey2009-appb-small-h-limit")
def test_bad_channel_term_of_condition_v_does_not_vanish_as_h_star_goes_to_zero():
    """The printed step lets P(H < H*) -> 0 with X* (which depends on h*) held still. The
    term it needs to vanish, (sigma_w^2 + a^2 X*) P(r < r*), is at least (sigma_w^2 + a^2
    p*(r*)) P(r < r*): for Rayleigh fading (Fig. 1) it tends to a^2 (a^2 - 1) sigma_n^2 lam =
    351.6, for Nakagami(1/2) it grows without bound. Repair: fix r* with a^2 P(r < r*) < 1 and
    take X* the fixed point of g(X) = P(r >= r*) f_{r*}(X) + P(r < r*) (a^2 X + sigma_w^2);
    then T(X*) <= g(X*) = X*."""
    a, sw2, sv2, sn2, lam = (FIG1[k] for k in ("a", "sw2", "sv2", "sn2", "lam"))
    laws = {"Rayleigh": (fading.Rayleigh(lam), lambda t: -np.expm1(-lam * t)),
            "Nakagami(1/2)": (fading.Nakagami(0.5, lam),
                              lambda t: scipy.special.erf(np.sqrt(lam * t / 2)))}
    r_star = 10.0 ** -np.arange(2, 8)
    ray_term = (sw2 + a * a * _pstar(r_star)) * laws["Rayleigh"][1](r_star)
    assert np.all(ray_term > 200) and ray_term[-1] == pytest.approx(a * a * (a * a - 1)
                                                                     * sn2 * lam, rel=1e-3)
    nak_term = (sw2 + a * a * _pstar(r_star)) * laws["Nakagami(1/2)"][1](r_star)
    assert np.all(np.diff(nak_term) > 0) and nak_term[-1] > 1e4
    for law, cdf in laws.values():  # the repaired argument
        rs = 1e-3
        q = cdf(rs)
        assert a * a * q < 1
        X = 1.0
        for _ in range(3000):
            X = (1 - q) * _f15(X, rs) + q * (a * a * X + sw2)
        assert abs((1 - q) * _f15(X, rs) + q * (a * a * X + sw2) - X) < 1e-9 * X
        T = sw2 + a * a * fading.expected_posterior(X, sv2, sn2, law)
        assert T <= X
        assert fading.scalar_bound_limits(a, sw2, sv2, sn2, law)["s"] <= X


# ------------------------------ Appendix A, the third line of the concavity display (correct)
def test_appendix_a_third_line_holds_in_the_loewner_order():
    """No erratum (see N8): min_X [alpha f(X, P1) + (1 - alpha) f(X, P2)] >= alpha min f(., P1)
    + (1 - alpha) min f(., P2) holds in the Loewner order because each minimum over the gain
    exists in that order (completed square: f(K, P) - f(K*, P) = (K - K*) S (K - K*)' >= 0).
    The gap is strictly positive, so the check is not vacuous."""
    rng = np.random.default_rng(11)
    A = np.array([[1.25, 1.0], [0.0, 0.9]])
    C, Sw, Sv, Sn = np.array([[1.0, 0.0], [1.0, 1.0]]), np.eye(2), np.diag([1.0, 2.0]), 4.0

    def f(K, P, Rt):
        M = A - K @ C
        return M @ P @ M.T + Sw + K @ Rt @ K.T

    def kstar(P, Rt):
        return A @ P @ C.T @ np.linalg.inv(C @ P @ C.T + Rt)

    gaps = []
    for _ in range(200):
        h2 = rng.exponential(1.0, 2)
        Rt = Sv + Sn * np.diag(1 / h2)  # Sigma_v + L^{-1}
        B1, B2 = rng.standard_normal((2, 2, 2))
        P1, P2, al = 5 * B1 @ B1.T, 5 * B2 @ B2.T, rng.uniform()
        K = rng.standard_normal((2, 2))
        for P in (P1, P2):
            assert np.linalg.eigvalsh(f(K, P, Rt) - f(kstar(P, Rt), P, Rt)).min() > -1e-9
        W = al * P1 + (1 - al) * P2
        gap = f(kstar(W, Rt), W, Rt) - al * f(kstar(P1, Rt), P1, Rt) \
            - (1 - al) * f(kstar(P2, Rt), P2, Rt)
        gaps.append(np.linalg.eigvalsh(gap))
    gaps = np.array(gaps)
    assert gaps.min() > -1e-9 and np.median(gaps[:, 1]) > 1e-3
