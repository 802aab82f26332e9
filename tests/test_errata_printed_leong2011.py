"""Printed-form tests of the leong2011 errata (book/errata.md, "Leong, Dey and Evans (2011)").

Each test evaluates what the paper prints (a formula, a value, a statement) and asserts that the
erratum's check rejects it, and that the correction passes the same check. The checks are the
chapters' (book/leong2011/*.md), restated here with the library and the same kind of numbers.
"""

from __future__ import annotations

import numpy as np
import pytest
from errata_marks import erratum

from fusioncenter import power

# The no-CSI example of the fading chapter: three sensors, Rician gains, beamformed on the mean
EX = {"a": 0.9, "sw2": 1.0, "sn2": 0.1, "c": np.array([1.0, -0.7, 0.5]),
      "sv2": np.array([0.5, 1.0, 0.3]),
      "h_mean": np.array([1 + 0.5j, 0.8 - 0.6j, -0.4 + 0.9j]),
      "var": np.array([0.2, 0.3, 0.25]), "alpha": np.array([1.0, -0.8, 1.2])}


def _ex_matrices(access="multi-access", var_re=None, var_im=None, alpha_t=None):
    alpha_t = power.beamformed(EX["alpha"], EX["h_mean"]) if alpha_t is None else alpha_t
    var_re = EX["var"] if var_re is None else var_re
    var_im = EX["var"] if var_im is None else var_im
    return power.lmmse_matrices(access, alpha_t, EX["a"], EX["sw2"], EX["c"], EX["sv2"],
                                EX["sn2"], EX["h_mean"], var_re, var_im)


def _z_score(samples):
    return float(samples.mean() / (samples.std(ddof=1) / np.sqrt(samples.size)))


# ---------------------------------------------------------------- §II.D, (6)

def _solves_eq6(P, a, sw2, gain2, rbar):
    """Check: P is a fixed point of (6) with ``gain2`` in the denominator."""
    return abs(P - (a**2 * P * rbar / (gain2 * P + rbar) + sw2)) < 1e-10


@erratum("erratum-leong2011-2-d-eq6-denominator")
def test_eq6_denominator_needs_cbar():
    # symmetric network, alpha_i = 1, Fig. 1's parameters, M = 4: cbar = M h c
    a, sw2, c, sv2, sn2, h, M = 0.8, 1.5, 1.0, 1.0, 1.0, 0.8, 4
    cbar, rbar = M * h * c, M * h**2 * sv2 + sn2
    P7 = float(power.steady_state(a, sw2, cbar**2 / rbar))  # (7)
    assert not _solves_eq6(P7, a, sw2, c**2, rbar)  # printed: c^2
    assert _solves_eq6(P7, a, sw2, cbar**2, rbar)  # corrected: cbar^2


# ---------------------------------------------------------------- Lemma 1

def _strictly_decreasing(values):
    return bool(np.all(np.diff(values) < 0))


def _non_increasing(values):  # to rounding: P_inf(S) is computed in floating point
    return bool(np.all(np.diff(values) <= 4 * np.finfo(float).eps * np.abs(values[1:])))


@erratum("erratum-leong2011-lemma1-decreasing")
def test_lemma1_is_not_strict_at_a_zero():
    S = np.geomspace(1e-3, 1e3, 200)
    flat = power.steady_state(0.0, 1.0, S)
    # printed: "a decreasing function of S" -- rejected at a = 0
    assert not _strictly_decreasing(flat)
    # corrected: non-increasing for every a, strictly decreasing for a != 0
    for a in (0.0, -0.6, 0.3, 0.9):
        assert _non_increasing(power.steady_state(a, 1.0, S))
    assert _strictly_decreasing(power.steady_state(0.3, 1.0, S))


# ---------------------------------------------------------------- §III.B, after (14)

@erratum("erratum-leong2011-3-b-after-14-strictly-above")
def test_limit_after_14_is_not_always_strictly_above_sigma_w2():
    sw2, h, c, sv2 = 1.5, 0.8, 1.0, 1.0  # Fig. 1's parameters

    def limit(a, sn2):
        return float(power.symmetric_asymptotics("orthogonal", "sqrt", a, sw2, h, c, sv2,
                                                 sn2)[0])

    cases = [(0.8, 1.0), (0.0, 1.0), (0.8, 0.0), (-0.5, 0.3)]

    def printed_claim(a, sn2):  # "strictly greater than sigma_w^2"
        return limit(a, sn2) > sw2 + 1e-12

    def corrected_claim(a, sn2):  # >= sigma_w^2, equality iff a = 0 or sigma_n^2 = 0
        lim = limit(a, sn2)
        equal = abs(lim - sw2) < 1e-12
        return lim > sw2 - 1e-12 and equal == (a == 0 or sn2 == 0)

    assert not all(printed_claim(*case) for case in cases)
    assert all(corrected_claim(*case) for case in cases)


# ---------------------------------------------------------------- Lemma 4 (signs)

def _within_lemma4(alpha, c, a=0.9, sw2=1.0, sn2=1.0):
    """Check: P_inf below the bound of Lemma 4's proof that gives sigma_w2 + O(1/M)."""
    M = c.size
    ones = np.ones(M)
    _, upper = power.lemma4_bounds(M, a, sw2, sn2, (1.0, 1.0), (1.0, 1.0), (1.0, 1.0),
                                   exact=True)
    S = power.snr("multi-access", alpha, ones, c, ones, sn2)
    return float(power.steady_state(a, sw2, S)) <= float(upper) * (1 + 1e-12)


@erratum("erratum-leong2011-lemma4-signs")
def test_lemma4_needs_alpha_with_the_sign_of_c():
    for M in (2, 20, 200):
        c = np.tile([1.0, -1.0], M // 2)
        assert not _within_lemma4(np.ones(M) / np.sqrt(M), c)  # printed: 1/sqrt(M)
        assert _within_lemma4(np.sign(c) / np.sqrt(M), c)  # corrected: sgn(c_i)/sqrt(M)


# ---------------------------------------------------------------- (24) and Remark 2

RHO = np.array([1.0, 0.6, -0.8, 0.4])
TAU = np.array([0.5, 0.3, 0.8, 0.2])
KAP = np.array([2.0, 0.5, 1.5, 3.0])
SN2, GAMMA = 0.4, 2.0


def _snr(alpha):
    return float((alpha @ RHO) ** 2 / (alpha**2 @ TAU + SN2))


def _is_optimum_of_23(alpha, rng):
    """Check: spends gamma_total and no allocation within the budget has a larger SNR."""
    spent = float(alpha**2 @ KAP)
    if abs(spent - GAMMA) > 1e-9 * GAMMA:
        return False
    trial = rng.standard_normal((20000, RHO.size))
    trial *= np.sqrt(GAMMA / (trial**2 @ KAP))[:, None]  # on the budget
    best_random = float(np.max((trial @ RHO) ** 2 / (trial**2 @ TAU + SN2)))
    return _snr(alpha) >= best_random * (1 - 1e-9)


@erratum("erratum-leong2011-eq24-optimum")
def test_printed_24_is_not_the_optimum_of_23():
    rng = np.random.default_rng(24)
    printed = power.coherent_max_snr_printed(RHO, TAU, KAP, SN2, GAMMA)
    corrected = power.coherent_max_snr(RHO, TAU, KAP, SN2, GAMMA)
    assert not _is_optimum_of_23(printed, rng)
    assert _is_optimum_of_23(corrected, rng)
    # the printed form is the optimum when every kappa_i = 1 (what the correction says)
    ones = np.ones_like(KAP)
    assert np.allclose(power.coherent_max_snr_printed(RHO, TAU, ones, SN2, GAMMA) ** 2,
                       power.coherent_max_snr(RHO, TAU, ones, SN2, GAMMA) ** 2)


@erratum("erratum-leong2011-remark2-broadcast")
def test_printed_broadcast_quantity_misses_the_budget():
    d = KAP + GAMMA * TAU / SN2
    local = (RHO / d) ** 2  # what sensor i knows

    def spends_budget(broadcast):  # check: alpha_i^2 = gamma B local_i spends gamma_total
        alpha2 = GAMMA * broadcast * local
        return abs(float(alpha2 @ KAP) - GAMMA) < 1e-9 * GAMMA

    printed = 1.0 / np.sum(RHO**2 / (d**2 * KAP))
    corrected = 1.0 / np.sum(KAP * RHO**2 / d**2)
    assert not spends_budget(printed)
    assert spends_budget(corrected)
    assert np.allclose(GAMMA * corrected * local,
                       power.coherent_max_snr(RHO, TAU, KAP, SN2, GAMMA) ** 2)


# ---------------------------------------------------------------- (27)

@erratum("erratum-leong2011-eq27-square-root")
def test_printed_27_misses_the_snr_target():
    rho, tau, kap, sn2 = np.array([1.0, 0.8, 0.6]), np.array([0.3, 0.4, 0.5]), \
        np.array([1.0, 1.2, 0.9]), 0.5
    x, y = 2.0, 1.0  # target x / y = 2 < sum rho^2 / tau = 4.92
    best = power.orthogonal_min_power(rho, tau, kap, sn2, x, y)
    on = best > 0
    assert on.all()  # the instance keeps every sensor on
    sqrt_lam = (np.sum(np.abs(rho) * np.sqrt(kap * sn2) / tau)
                / (np.sum(rho**2 / tau) - x / y))
    lam = sqrt_lam**2

    def meets_target_at_least_power(alpha2):  # check: S^o = x/y (KKT: active) = the optimum
        S = float(np.sum(alpha2 * rho**2 / (alpha2 * tau + sn2)))
        return abs(S - x / y) < 1e-9 and np.allclose(alpha2, best**2, rtol=1e-9)

    printed = np.sqrt(np.maximum(lam * rho**2 * sn2 / kap - sn2, 0)) / tau
    corrected = np.maximum(np.sqrt(lam * rho**2 * sn2 / kap) - sn2, 0) / tau
    assert not meets_target_at_least_power(printed)
    assert meets_target_at_least_power(corrected)


# ---------------------------------------------------------------- after (30)

@erratum("erratum-leong2011-after-30-p2")
def test_p2_equals_D_only_when_the_first_step_is_active():
    a, sw2, D, sn2 = 0.9, 1.0, 2.0, 0.1
    c, sv2 = np.ones(3), np.array([0.5, 1.0, 0.3])
    h = np.random.default_rng(30).uniform(0.5, 1.5, (12, 3))
    for P1 in (0.5, 1.5, 3.0):
        P, _ = power.greedy_min_power("multi-access", D, a, sw2, h, c, sv2, sn2, P0=P1)
        printed = abs(P[1] - D) < 1e-9 * D  # "P_2 = D"
        active = a**2 * P1 + sw2 > D
        corrected = (abs(P[1] - D) < 1e-9 * D) if active else (
            abs(P[1] - (a**2 * P1 + sw2)) < 1e-12 and P[1] < D)
        assert corrected
        if P1 == 0.5:
            assert not printed  # the printed claim fails from a small P_1
    # and from the first active step on, P_k = D
    P, _ = power.greedy_min_power("multi-access", D, a, sw2, h, c, sv2, sn2, P0=0.5)
    first = int(np.argmax(a**2 * P[:-1] + sw2 > D))
    assert np.allclose(P[first + 1:], D, rtol=1e-9) and first > 0


# ---------------------------------------------------------------- §IV.E.1, assumptions

SH = {"a": 0.9, "sw2": 1.0, "sn2": 0.1, "c": np.array([1.0, 0.8, 0.6]),
      "sv2": np.array([0.5, 1.0, 0.3]), "h_mean": np.array([1 + 0.5j, 0.8 - 0.6j, 0.6 + 0.9j]),
      "s": np.sqrt([0.2, 0.3, 0.25]), "alpha": np.array([1.0, 0.8, 1.2])}


def _simulate_shared(rng, n, steps, alpha_t, shared):
    Pi = SH["sw2"] / (1 - SH["a"] ** 2)
    x = np.empty((n, steps))
    x[:, 0] = rng.standard_normal(n) * np.sqrt(Pi)
    for k in range(1, steps):
        x[:, k] = SH["a"] * x[:, k - 1] + rng.standard_normal(n) * np.sqrt(SH["sw2"])
    y = SH["c"] * x[..., None] + rng.standard_normal((n, steps, 3)) * np.sqrt(SH["sv2"])
    width = 1 if shared else 3
    u, u2 = (rng.standard_normal((n, steps, width)) for _ in range(2))
    h = SH["h_mean"] + SH["s"] * (u + 1j * u2)
    noise = (rng.standard_normal((n, steps)) + 1j * rng.standard_normal((n, steps)))
    zc = (alpha_t * h * y).sum(-1) + noise * np.sqrt(SH["sn2"])
    return x, np.stack([zc.real, zc.imag], -1)


@erratum("erratum-leong2011-4-e-1-gains-across-sensors")
def test_rbar_needs_gains_uncorrelated_across_sensors():
    at = power.beamformed(SH["alpha"], SH["h_mean"])
    C, R = power.lmmse_matrices("multi-access", at, SH["a"], SH["sw2"], SH["c"], SH["sv2"],
                                SH["sn2"], SH["h_mean"], SH["s"] ** 2, SH["s"] ** 2)
    Pi = SH["sw2"] / (1 - SH["a"] ** 2)
    B = SH["s"][:, None, None] * np.stack([np.stack([at.real, -at.imag], -1),
                                           np.stack([at.imag, at.real], -1)], -2)
    own = Pi * np.einsum("i,ijk,ilk->jl", SH["c"] ** 2, B, B)
    Bs = np.einsum("i,ijk->jk", SH["c"], B)
    R_shared = R - own + Pi * Bs @ Bs.T  # with the cross-sensor terms

    def calibrated(R_filter, z, x):  # check: the filter's e^2/P is 1 within the noise
        xp, P = power.lmmse_filter(z, SH["a"], SH["sw2"], C, R_filter)
        steps = x.shape[1]
        return _z_score(((x - xp[:, :steps]) ** 2 / P[:steps] - 1).mean(axis=1))

    # gains sharing one fading component: every assumption the paper states holds
    x, z = _simulate_shared(np.random.default_rng(36), 3000, 30, at, shared=True)
    assert calibrated(R, z, x) > 6  # printed assumptions: R-bar of (32) is overconfident
    assert abs(calibrated(R_shared, z, x)) < 4
    # corrected assumption (independent across sensors): the printed R-bar is right
    x, z = _simulate_shared(np.random.default_rng(37), 3000, 30, at, shared=False)
    assert abs(calibrated(R, z, x)) < 4


# ---------------------------------------------------------------- (32)

def _variance_limit(time_update):
    C, R = _ex_matrices()
    S = float(power.lmmse_snr(C, R))
    P = EX["sw2"] / (1 - EX["a"] ** 2)
    for _ in range(400):
        Pf = P / (1 + P * S)
        P = time_update(Pf)
    return P, float(power.steady_state(EX["a"], EX["sw2"], S))


@erratum("erratum-leong2011-eq32-time-update")
def test_eq32_time_update_needs_process_noise():
    def check(time_update):  # the prediction variance reaches the steady state (8), >= sigma_w2
        P, P_inf = _variance_limit(time_update)
        return abs(P - P_inf) < 1e-10 and P >= EX["sw2"]

    assert not check(lambda Pf: EX["a"] ** 2 * Pf)  # printed
    assert check(lambda Pf: EX["a"] ** 2 * Pf + EX["sw2"])  # corrected


def _information_form(P):
    C, R = _ex_matrices()
    return P / (1 + P * float(power.lmmse_snr(C, R)))


@erratum("erratum-leong2011-eq32-transpose")
def test_eq32_innovation_covariance_needs_a_transpose():
    C, R = _ex_matrices()
    P = 3.0
    col = C[:, None]  # C-bar is a 2 x 1 column
    with pytest.raises(ValueError):
        col @ np.array([[P]]) @ col  # printed C P C: undefined

    def update(innovation_cov):  # P_{k|k} from the gain form; check: = the information form
        return float(P - P * C @ np.linalg.solve(innovation_cov, C) * P)

    flat = C @ C * P + R  # the printed C P C read with flat arrays: a scalar added to R
    assert abs(update(flat) - _information_form(P)) > 0.1
    assert abs(update(np.outer(C, C) * P + R) - _information_form(P)) < 1e-12


@erratum("erratum-leong2011-eq32-variance-update")
def test_eq32_variance_update_needs_the_closing_cbar_p():
    C, R = _ex_matrices()
    P = 3.0
    inv = np.linalg.inv(np.outer(C, C) * P + R)

    def is_the_variance(value):  # check: a scalar equal to P / (1 + P S)
        value = np.asarray(value)
        return value.size == 1 and abs(float(value.ravel()[0]) - _information_form(P)) < 1e-12

    printed = P - P * C[None, :] @ inv
    corrected = P - P * C[None, :] @ inv @ C[:, None] * P
    assert printed.shape == (1, 2) and not is_the_variance(printed)
    assert is_the_variance(corrected)


# ---------------------------------------------------------------- R-bar off-diagonal, S^o

@erratum("erratum-leong2011-rbar-off-diagonal")
def test_rbar_off_diagonal_needs_the_covariance_term():
    var_re, var_im = np.full(3, 2.0), np.full(3, 0.01)
    at = power.beamformed(EX["alpha"], EX["h_mean"]) * np.exp(1j * np.pi / 4)
    _, R = _ex_matrices(var_re=var_re, var_im=var_im, alpha_t=at)
    g_mean = at * EX["h_mean"]
    printed12 = float(np.sum(g_mean.real * g_mean.imag * EX["sv2"]))
    # check: R12 is the covariance of the real and imaginary noise (simulated, 400 000 draws)
    rng = np.random.default_rng(26)
    n = 400_000
    Pi = EX["sw2"] / (1 - EX["a"] ** 2)
    x = rng.standard_normal((n, 1)) * np.sqrt(Pi)
    h = (EX["h_mean"].real + np.sqrt(var_re) * rng.standard_normal((n, 3))
         + 1j * (EX["h_mean"].imag + np.sqrt(var_im) * rng.standard_normal((n, 3))))
    g = at * h
    v = rng.standard_normal((n, 3)) * np.sqrt(EX["sv2"])
    noise = ((g - g_mean) * EX["c"] * x + g * v).sum(-1)  # receiver noise: Re, Im independent
    prod = (noise.real - noise.real.mean()) * (noise.imag - noise.imag.mean())
    cov, se = prod.mean(), prod.std(ddof=1) / np.sqrt(n)

    def matches(r12):
        return abs(r12 - cov) < 5 * se

    assert abs(R[0, 1] - printed12) > 20 * se  # the example discriminates
    assert not matches(printed12)
    assert matches(float(R[0, 1]))


@erratum("erratum-leong2011-orthogonal-snr-inverse")
def test_orthogonal_snr_needs_the_inverse_of_rbar():
    C, R = _ex_matrices("orthogonal")
    rho, tau, _ = power.lmmse_coefficients(EX["a"], EX["sw2"], EX["c"], EX["sv2"],
                                           EX["h_mean"], EX["var"], EX["var"])
    al2 = EX["alpha"] ** 2
    S_scalar = float(np.sum(al2 * rho**2 / (al2 * tau + EX["sn2"])))  # printed after it
    _, P = power.lmmse_filter(np.zeros((1, 300, C.size)), EX["a"], EX["sw2"], C, R)

    def check(S):  # the scalar form, and the filter's limit is the steady state (8) at S
        return (abs(S / S_scalar - 1) < 1e-12
                and abs(P[-1] - float(power.steady_state(EX["a"], EX["sw2"], S))) < 1e-10)

    assert not check(float(C @ R @ C))  # printed
    assert check(float(C @ np.linalg.solve(R, C)))  # corrected
    assert check(float(power.lmmse_snr(C, R)))


# ---------------------------------------------------------------- (37)

@erratum("erratum-leong2011-eq37-lower-bound")
def test_printed_lower_bound_37_fails_at_small_M():
    a, sw2, sn2, rng_ = 0.9, 1.0, 1.0, (0.5, 1.0)
    M = np.arange(1, 11)
    # the best admissible network: h_i = c_i = 1, sigma_i^2 = 0.5
    P_best = power.steady_state(a, sw2, M * 1.0 / (0.5 + sn2))
    rho_lo = (0.5**2 * 0.5 + sn2) / 1.0

    def is_lower_bound(bound):
        return bool(np.all(bound <= P_best))

    printed, _ = power.lemma4_bounds(M, a, sw2, sn2, rng_, rng_, rng_)
    assert not is_lower_bound(printed)
    assert list(M[printed > P_best]) == [1, 2, 3]
    assert is_lower_bound(sw2 + a**2 * sw2 / (1 + sw2 * M / rho_lo))  # corrected
    assert is_lower_bound(power.lemma4_bounds(M, a, sw2, sn2, rng_, rng_, rng_, exact=True)[0])


# ---------------------------------------------------------------- §VI.A, the inversion lemma

def _vector_network(rng, n, m, M):
    blocks = []
    R_bar = np.zeros((M * m, M * m))
    for i in range(M):
        H = np.diag(rng.uniform(0.5, 1.5, m))
        al = rng.standard_normal((m, m))
        C_i = rng.standard_normal((m, n))
        B = rng.standard_normal((m, m))
        R_i = B @ B.T + np.eye(m)
        blocks.append((H @ al @ C_i, H @ al @ R_i @ al.T @ H.T + 0.3 * np.eye(m)))
        R_bar[i * m:(i + 1) * m, i * m:(i + 1) * m] = blocks[-1][1]
    B = rng.standard_normal((n, n))
    return blocks, np.vstack([g for g, _ in blocks]), R_bar, B @ B.T + np.eye(n)


@erratum("erratum-leong2011-6-a-matrix-inversion-lemma")
def test_vector_inversion_lemma_needs_cbar_not_its_transpose():
    rng = np.random.default_rng(6)

    def identity_holds(C_bar, R_bar, P, X):
        lhs = C_bar.T @ np.linalg.solve(C_bar @ P @ C_bar.T + R_bar, C_bar)
        rhs = X - X @ np.linalg.solve(np.linalg.inv(P) + X, X)
        return float(np.max(np.abs(lhs - rhs))) < 1e-10

    for n, m, M in ((3, 2, 2), (2, 1, 2), (4, 2, 2)):
        blocks, C_bar, R_bar, P = _vector_network(rng, n, m, M)
        X = C_bar.T @ np.linalg.solve(R_bar, C_bar)  # corrected
        assert identity_holds(C_bar, R_bar, P, X)
        # the simplification's right-hand side (printed correctly) equals the corrected X
        assert np.allclose(X, sum(g.T @ np.linalg.solve(r, g) for g, r in blocks),
                           atol=1e-12)
        if M * m != n:
            with pytest.raises(ValueError):
                C_bar.T @ np.linalg.inv(R_bar) @ C_bar.T  # printed: undefined
        else:
            X_printed = C_bar.T @ np.linalg.inv(R_bar) @ C_bar.T
            assert not identity_holds(C_bar, R_bar, P, X_printed)


# ---------------------------------------------------------------- Appendix C, first sentence

@erratum("erratum-leong2011-appc-sum-signs")
def test_appendix_c_first_bound_needs_the_absolute_values():
    """Lemma 4 allows c_i of either sign (c_min <= |c_i| <= c_max). The printed
    M h_min c_min <= sum_i h_i c_i <= M h_max c_max fails for alternating signs (the sum is 0,
    or negative); with |c_i| it holds on every random network, and sum_i h_i |c_i| is the
    c_bar = sum_i alpha_i h_i c_i of the choice alpha_i = sgn(c_i) that the proof then makes."""
    rng = np.random.default_rng(4)

    def holds(M, h, c, cs):
        lo, hi = M * h.min() * np.abs(c).min(), M * h.max() * np.abs(c).max()
        return bool(lo - 1e-12 <= cs <= hi + 1e-12)

    M, h, c = 4, np.full(4, 0.8), np.array([1.0, -1.0, 1.0, -1.0])
    assert not holds(M, h, c, np.sum(h * c))  # printed: 0 < 3.2
    c_neg = -np.array([0.6, 0.9, 0.7])
    assert not holds(3, np.array([0.5, 1.0, 0.7]), c_neg, np.sum(np.array([0.5, 1.0, 0.7]) * c_neg))
    fails = 0
    for _ in range(1000):
        M = int(rng.integers(1, 30))
        h = rng.uniform(0.5, 1.0, M)
        c = rng.uniform(0.5, 1.0, M) * rng.choice([-1.0, 1.0], M)
        assert holds(M, h, c, np.sum(h * np.abs(c)))  # corrected
        assert np.sum(np.sign(c) * h * c) == pytest.approx(np.sum(h * np.abs(c)))
        fails += not holds(M, h, c, np.sum(h * c))
    assert fails > 900
