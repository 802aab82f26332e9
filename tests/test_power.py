"""fusioncenter.power (leong2011): steady states, 1/M laws, the four allocation problems against an
independent numerical optimizer, the errata, fading with and without CSI."""

from __future__ import annotations

import functools
import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from fusioncenter import montecarlo, power, riccati

N_INSTANCES = 50
REL = 1e-6


# ------------------------------------------------------------------------------ instances
def random_instance(rng: np.random.Generator, M: int | None = None):
    """A static instance with mixed-sign c_i, unequal kappa_i, order-one scales."""
    M = int(rng.integers(2, 9)) if M is None else M
    a = rng.uniform(-0.95, 0.95)
    sw = rng.uniform(0.2, 3.0)
    sn = rng.uniform(0.05, 2.0)
    h = rng.uniform(0.2, 2.0, M)
    c = rng.uniform(0.2, 2.0, M) * rng.choice([-1.0, 1.0], M)
    c[0], c[1] = abs(c[0]), -abs(c[1])  # always mixed signs
    sv = rng.uniform(0.1, 3.0, M)
    return a, sw, h, c, sv, sn


def feasible_D(rng, a, sw, c, sv, margin=1.05):
    """A target D in (sigma_w2, sigma_w2/(1-a^2)) that condition (20) allows."""
    total = np.sum(c**2 / sv)
    lo, hi = sw, sw / (1 - a**2)
    for _ in range(1000):
        D = rng.uniform(lo, hi)
        if total > margin * power.required_snr(D, a, sw):
            return D
    raise AssertionError("no feasible D found")


def instances(seed: int):
    rng = np.random.default_rng(seed)
    for _ in range(N_INSTANCES):
        a, sw, h, c, sv, sn = random_instance(rng)
        yield rng, a, sw, h, c, sv, sn


def rel(a, b):
    return abs(a - b) / abs(b)


# ============================================================= the closed forms vs SLSQP
def test_coherent_min_power_equals_numerical_optimum():
    """(19)-(22) vs SLSQP on the convex SOC form, and the public min_power meets D exactly."""
    kappas_unequal = 0
    for rng, a, sw, h, c, sv, sn in instances(1):
        D = feasible_D(rng, a, sw, c, sv)
        rho, tau, kap = power.static_coefficients(a, sw, h, c, sv)
        kappas_unequal += np.ptp(kap) > 0.1
        x, y = a**2 * D + sw - D, D * (D - sw)
        alpha = power.coherent_min_power(rho, tau, kap, sn, x, y)
        assert np.allclose(alpha, power.min_power("multi-access", D, a, sw, h, c, sv, sn))
        value = alpha**2 @ kap
        _, num = power.solve_numerically("coherent-min-power", rho, tau, kap, sn, x=x, y=y)
        assert rel(value, num) < REL
        assert value <= num * (1 + 1e-12)  # SLSQP's point is feasible: never below the optimum
        # (22): the minimum is lambda sigma_n2 x with lambda from the secular equation
        lam = value / (sn * x)
        assert rel(np.sum(lam * rho**2 / (kap + lam * tau * x)), 1 / y) < 1e-10
        # (21): alpha_i proportional to rho_i / (kappa_i + lambda tau_i x), with mu from (21)
        mu2 = sn * x / np.sum(rho**2 * kap / (4 * lam * (kap + lam * tau * x) ** 2))
        assert np.allclose(alpha, np.sqrt(mu2) * rho / (2 * (kap + lam * tau * x)), rtol=1e-9)
        S = power.snr("multi-access", alpha, h, c, sv, sn)
        assert rel(power.steady_state(a, sw, S), D) < 1e-12
        assert np.all(np.sign(alpha) == np.sign(c))  # mixed signs are followed, not clipped
    assert kappas_unequal > 40


def test_coherent_max_snr_equals_numerical_optimum():
    """(23) vs multi-start SLSQP; our (24) spends exactly gamma_total."""
    for rng, a, sw, h, c, sv, sn in instances(2):
        g = rng.uniform(0.05, 20.0)
        rho, tau, kap = power.static_coefficients(a, sw, h, c, sv)
        alpha = power.coherent_max_snr(rho, tau, kap, sn, g)
        assert np.allclose(alpha, power.min_error("multi-access", g, a, sw, h, c, sv, sn))
        S = power.snr("multi-access", alpha, h, c, sv, sn)
        _, num = power.solve_numerically("coherent-max-snr", rho, tau, kap, sn, gamma_total=g,
                                         starts=4, seed=3)
        assert rel(S, num) < REL and S >= num * (1 - 1e-12)
        assert rel(alpha**2 @ kap, g) < 1e-12
        assert rel(S, np.sum(rho**2 * g / (g * tau + kap * sn))) < 1e-12  # the maximal SNR


def paper_m1_rule(rho, tau, kap, sn, x, y):
    """Every M_1 satisfying the paper's three conditions after (27) (with the square root
    ending before ``- sigma_n2``), and sqrt(lambda) at the first one."""
    order = np.argsort(-(rho**2 / kap))
    r, t, k = np.abs(rho[order]), tau[order], kap[order]

    def sqrt_lam(m):
        return np.sum(r[:m] / t[:m] * np.sqrt(k[:m] * sn)) / (np.sum(r[:m] ** 2 / t[:m]) - x / y)

    def on(m):  # uses lambda of the first m sensors, as printed
        return sqrt_lam(m) * np.sqrt(r[m - 1] ** 2 * sn / k[m - 1]) - sn > 0

    found = [m for m in range(1, len(r) + 1)
             if np.sum(r[:m] ** 2 / t[:m]) - x / y >= 0 and on(m)
             and (m == len(r) or not on(m + 1))]
    return found, (sqrt_lam(found[0]) if found else np.nan)


def test_orthogonal_min_power_equals_numerical_optimum_and_paper_m1_rule():
    """(26)-(27) vs SLSQP in alpha^2 >= 0; M_1 by the paper's rule (with the corrected root)."""
    switched_off = 0
    for rng, a, sw, h, c, sv, sn in instances(3):
        D = feasible_D(rng, a, sw, c, sv)
        rho, tau, kap = power.static_coefficients(a, sw, h, c, sv)
        x, y = a**2 * D + sw - D, D * (D - sw)
        alpha, m1 = power.orthogonal_min_power(rho, tau, kap, sn, x, y, return_m1=True)
        assert np.allclose(alpha, power.min_power("orthogonal", D, a, sw, h, c, sv, sn))
        assert np.all(alpha >= 0) and int(np.sum(alpha > 0)) == m1
        switched_off += m1 < len(c)
        value = alpha**2 @ kap
        _, num = power.solve_numerically("orthogonal-min-power", rho, tau, kap, sn, x=x, y=y)
        assert rel(value, num) < REL and value <= num * (1 + 1e-12)
        S = power.snr("orthogonal", alpha, h, c, sv, sn)
        assert rel(power.steady_state(a, sw, S), D) < 1e-12
        # the paper's M_1 conditions (sqrt(lambda) of M_1 and of M_1 + 1), corrected root
        paper, sqrt_lam = paper_m1_rule(rho, tau, kap, sn, x, y)
        assert paper == [m1]
        # (27) as printed in our copy, sqrt(lambda rho^2 sigma_n2 / kappa - sigma_n2), is not it
        lam = sqrt_lam ** 2
        arg = lam * rho**2 * sn / kap - sn
        printed = np.sqrt(np.maximum(arg, 0)) / tau
        S_printed = np.sum(printed * rho**2 / (printed * tau + sn))
        assert rel(S_printed, x / y) > 1e-3
    assert switched_off > 5  # water-filling switched sensors off on some instances


def test_orthogonal_max_snr_equals_numerical_optimum():
    """(28)-(29) vs SLSQP in alpha^2 >= 0, budget spent exactly."""
    for rng, a, sw, h, c, sv, sn in instances(4):
        g = rng.uniform(0.05, 20.0)
        rho, tau, kap = power.static_coefficients(a, sw, h, c, sv)
        alpha, m1 = power.orthogonal_max_snr(rho, tau, kap, sn, g, return_m1=True)
        assert np.allclose(alpha, power.min_error("orthogonal", g, a, sw, h, c, sv, sn))
        assert int(np.sum(alpha > 0)) == m1
        # the paper's M_1 conditions after (29), each with lambda of its own prefix
        order = np.argsort(-(rho**2 / kap))
        r, t, k = np.abs(rho[order]), tau[order], kap[order]

        def on(m, r=r, t=t, k=k, g=g, sn=sn):
            inv = (g + np.sum(k[:m] / t[:m] * sn)) / np.sum(r[:m] / t[:m] * np.sqrt(k[:m] * sn))
            return inv * np.sqrt(r[m - 1] ** 2 * sn / k[m - 1]) - sn > 0

        paper = [m for m in range(1, len(r) + 1) if on(m) and (m == len(r) or not on(m + 1))]
        assert paper == [m1]
        S = power.snr("orthogonal", alpha, h, c, sv, sn)
        _, num = power.solve_numerically("orthogonal-max-snr", rho, tau, kap, sn, gamma_total=g)
        assert rel(S, num) < REL and S >= num * (1 - 1e-12)
        assert rel(alpha**2 @ kap, g) < 1e-12


def test_paper_scale_instances_match_the_optimizer():
    """The figures' scales (h ~ 1e-3, sigma_n2 = 1e-9, chi2(1) noise) are handled too."""
    rng = np.random.default_rng(5)
    a, sw, sn, D, g = 0.9, 1.0, 1e-9, 2.0, 1e-3
    x, y = a**2 * D + sw - D, D * (D - sw)
    for _ in range(10):
        M = int(rng.integers(2, 15))
        h = rng.uniform(20, 100, M) ** -2.0
        sv = rng.chisquare(1, M)
        rho, tau, kap = power.static_coefficients(a, sw, h, np.ones(M), sv)
        if np.sum(1 / sv) <= x / y:
            continue
        for prob, fn in (("coherent-min-power", power.coherent_min_power),
                         ("orthogonal-min-power", power.orthogonal_min_power)):
            al = fn(rho, tau, kap, sn, x, y)
            assert rel(al**2 @ kap, power.solve_numerically(prob, rho, tau, kap, sn, x=x,
                                                            y=y)[1]) < REL
        al = power.orthogonal_max_snr(rho, tau, kap, sn, g)
        num = power.solve_numerically("orthogonal-max-snr", rho, tau, kap, sn, gamma_total=g)[1]
        assert rel(np.sum(al**2 * rho**2 / (al**2 * tau + sn)), num) < REL
        assert rel(al**2 @ kap, g) < 1e-12


def test_batched_solvers_equal_one_by_one():
    rng = np.random.default_rng(6)
    M, n = 5, 30
    a, sw, sn = 0.7, 1.0, 0.5
    h = rng.uniform(0.2, 2, (n, M))
    c = rng.uniform(0.5, 2, (n, M)) * rng.choice([-1, 1], (n, M))
    sv = rng.uniform(0.1, 1, (n, M))
    D = 1.2
    for access in power.ACCESS:
        batch = power.min_power(access, D, a, sw, h, c, sv, sn)
        one = np.array([power.min_power(access, D, a, sw, h[i], c[i], sv[i], sn)
                        for i in range(n)])
        assert np.allclose(batch, one, rtol=1e-12)
        batch = power.min_error(access, 2.0, a, sw, h, c, sv, sn)
        one = np.array([power.min_error(access, 2.0, a, sw, h[i], c[i], sv[i], sn)
                        for i in range(n)])
        assert np.allclose(batch, one, rtol=1e-12)


# ======================================================================== the errata
def test_printed_eq24_is_not_optimal_unless_kappas_are_equal():
    """Erratum in (24): kappa_j belongs in the numerator of the normalizing sum."""
    worse, overspent = 0, 0
    for rng, a, sw, h, c, sv, sn in instances(7):
        g = rng.uniform(0.05, 20.0)
        rho, tau, kap = power.static_coefficients(a, sw, h, c, sv)
        best = power.coherent_max_snr(rho, tau, kap, sn, g)
        printed = power.coherent_max_snr_printed(rho, tau, kap, sn, g)
        overspent += rel(printed**2 @ kap, g) > 1e-3  # violates or under-uses the budget
        scaled = printed * np.sqrt(g / (printed**2 @ kap))  # give it exactly the budget
        s_best = power.snr("multi-access", best, h, c, sv, sn)
        s_scaled = power.snr("multi-access", scaled, h, c, sv, sn)
        assert s_scaled <= s_best * (1 + 1e-12)
        worse += s_scaled < s_best * (1 - 1e-4)
    assert overspent == N_INSTANCES and worse >= 45
    # with equal kappa_i the printed direction is right but it spends kappa * gamma_total;
    # only with every kappa_i = 1 is the printed formula the optimum
    rho, tau = np.array([1.0, -0.5, 2.0]), np.array([0.3, 1.0, 0.7])
    for k in (2.5, 1.0):
        kap = np.full(3, k)
        assert np.allclose(power.coherent_max_snr_printed(rho, tau, kap, 0.4, 3.0),
                           np.sqrt(k) * power.coherent_max_snr(rho, tau, kap, 0.4, 3.0),
                           rtol=1e-12)


def test_printed_time_update_of_eq32_lacks_sigma_w2():
    """(32) as printed, P_{k+1|k} = a^2 P_{k|k}, drives P to 0; the error cannot go below
    sigma_w2."""
    a, sw, S = 0.9, 1.0, 2.0
    p = 5.0
    for _ in range(200):
        p = a**2 * p / (1 + p * S)
    assert p < 1e-6 < sw
    assert power.steady_state(a, sw, S) > sw


# ============================================================ steady state and its inverse
def test_steady_state_with_S_zero_and_validation():
    assert power.steady_state(0.5, 2.0, 0.0) == pytest.approx(2.0 / 0.75, rel=1e-15)
    assert np.allclose(power.steady_state(-0.9, 1.0, [0.0, 0.0]), 1 / 0.19)
    with pytest.raises(ValueError, match=r"\ba\b.*\|a\| < 1"):
        power.steady_state(1.0, 1.0, 0.0)
    # unstable systems are fine with information (Remark III.E.2)
    assert power.steady_state(1.2, 1.0, 0.5) == pytest.approx(
        riccati.scalar_steady_state(1.2, 1.0, np.sqrt(0.5), 1.0), rel=1e-14)
    with pytest.raises(ValueError, match="S must be non-negative"):
        power.steady_state(0.5, 1.0, -0.1)
    with pytest.raises(ValueError, match="sigma_w2"):
        power.steady_state(0.5, -1.0, 1.0)  # sigma_w2 = 0 is a limit (test_power_limits)


@settings(max_examples=60, deadline=None)
@given(a=st.floats(-0.99, 0.99), sw=st.floats(0.01, 10), s1=st.floats(1e-4, 1e3),
       s2=st.floats(1e-4, 1e3))
def test_lemma1_decreasing_and_fixed_point(a, sw, s1, s2):
    p1, p2 = power.steady_state(a, sw, s1), power.steady_state(a, sw, s2)
    if s1 < s2:
        assert p1 >= p2 * (1 - 1e-13)
    assert p1 == pytest.approx(power.steady_recursion(p1, a, sw, s1), rel=1e-12)
    assert sw * (1 - 1e-14) <= p1 <= sw / (1 - a**2) * (1 + 1e-12)


@settings(max_examples=40, deadline=None)
@given(a=st.floats(-0.95, 0.95), sw=st.floats(0.1, 5), u=st.floats(0.01, 0.99))
def test_required_snr_inverts_steady_state(a, sw, u):
    D = sw + u * (sw / (1 - a**2) - sw)
    if not sw < D < sw / (1 - a**2):
        return
    assert power.steady_state(a, sw, power.required_snr(D, a, sw)) == pytest.approx(D, rel=1e-9)


def test_snr_matches_the_matrix_riccati_equation():
    """S and S^o give the steady state of the matrix DARE of the equivalent system (3)/(5)."""
    rng = np.random.default_rng(8)
    for _ in range(10):
        a, sw, h, c, sv, sn = random_instance(rng)
        alpha = rng.uniform(-1, 1, len(c))
        ahc = alpha * h * c
        noise = alpha**2 * h**2 * sv
        P_multi = riccati.steady_state([[a]], [[sw]], [[ahc.sum()]], [[noise.sum() + sn]])
        S = power.snr("multi-access", alpha, h, c, sv, sn)
        assert power.steady_state(a, sw, S) == pytest.approx(P_multi[0, 0], rel=1e-9)
        P_orth = riccati.steady_state([[a]], [[sw]], ahc[:, None], np.diag(noise + sn))
        So = power.snr("orthogonal", alpha, h, c, sv, sn)
        assert power.steady_state(a, sw, So) == pytest.approx(P_orth[0, 0], rel=1e-9)


# ================================================================ asymptotics in M
@pytest.mark.parametrize("access,scaling", [("multi-access", "none"), ("orthogonal", "none"),
                                            ("multi-access", "sqrt")])
def test_one_over_m_laws(access, scaling):
    """Lemma 3 / (11), (12), (13): M (P_inf - sigma_w2) -> K with an O(1/M) error."""
    a, sw, h, c, sv, sn = 0.8, 1.5, 0.8, -1.3, 0.7, 1.1
    limit, K = power.symmetric_asymptotics(access, scaling, a, sw, h, c, sv, sn)
    assert limit == sw
    errs = []
    for M in (10**3, 10**4, 10**5):
        al = 1.0 if scaling == "none" else 1 / np.sqrt(M)
        S = power.snr(access, np.full(M, al), np.full(M, h), np.full(M, c), np.full(M, sv), sn)
        errs.append(abs(M * (power.steady_state(a, sw, S) - sw) - K))
    assert errs[-1] < 1e-3 * K
    assert errs[0] / errs[1] == pytest.approx(10, rel=0.05)  # the error is O(1/M)
    assert errs[1] / errs[2] == pytest.approx(10, rel=0.05)


def test_orthogonal_scaled_limit_eq14():
    a, sw, h, c, sv, sn = 0.8, 1.5, 0.8, 1.0, 1.0, 1.0
    limit, coef = power.symmetric_asymptotics("orthogonal", "sqrt", a, sw, h, c, sv, sn)
    assert limit > sw  # no convergence to sigma_w2
    for M in (10**3, 10**4):
        S = power.snr("orthogonal", np.full(M, M**-0.5), np.full(M, h), np.full(M, c),
                      np.full(M, sv), sn)
        P = power.steady_state(a, sw, S)
        assert abs(P - limit - coef / M) < 5 / M**2


def test_lemma4_bounds_hold():
    """Exact bounds always; printed (37) upper always, printed lower for M >= 20."""
    rng = np.random.default_rng(9)
    rng_h, rng_c, rng_s = (0.5, 1.0), (0.5, 1.0), (0.5, 1.0)
    for _ in range(20):
        a, sw, sn = rng.uniform(-0.95, 0.95), rng.uniform(0.3, 2), rng.uniform(0.2, 2)
        n = 120
        h, cabs, sv = (rng.uniform(*r, n) for r in (rng_h, rng_c, rng_s))
        c = cabs * rng.choice([-1, 1], n)
        for scaling in ("sqrt", "none"):
            for M in (1, 2, 5, 20, 60, 120):
                al = np.sign(c[:M]) * (1 / np.sqrt(M) if scaling == "sqrt" else 1.0)
                P = power.steady_state(a, sw, power.snr("multi-access", al, h[:M], c[:M],
                                                        sv[:M], sn))
                lo, hi = power.lemma4_bounds(M, a, sw, sn, rng_h, rng_c, rng_s, scaling=scaling)
                elo, ehi = power.lemma4_bounds(M, a, sw, sn, rng_h, rng_c, rng_s,
                                               scaling=scaling, exact=True)
                assert elo <= P * (1 + 1e-12) and P <= ehi * (1 + 1e-12)
                assert P <= hi * (1 + 1e-12)
                if M >= 20:
                    assert lo <= P


def test_lemma5_equal_power():
    """(15): multi-access and orthogonal P_inf -> sigma_w2 at rate 1/M; (16) orthogonal does
    not reach sigma_w2."""
    rng = np.random.default_rng(10)
    a, sw, sn = 0.9, 1.0, 1.0
    n = 20000
    h, c, sv = rng.uniform(0.5, 1, n), rng.uniform(0.5, 1, n), rng.uniform(0.5, 1, n)
    vals = {}
    for M in (2000, 20000):
        for key, kw in (("15", {"gamma": 1.0}), ("16", {"gamma_total": 1.0})):
            al = power.equal_power(a, sw, c[:M], sv[:M], **kw)
            for access in power.ACCESS:
                S = power.snr(access, al, h[:M], c[:M], sv[:M], sn)
                vals[key, access, M] = M * (power.steady_state(a, sw, S) - sw)
    for access in power.ACCESS:
        assert vals["15", access, 20000] == pytest.approx(vals["15", access, 2000], rel=0.1)
    assert vals["16", "multi-access", 20000] == pytest.approx(vals["16", "multi-access", 2000],
                                                              rel=0.1)
    assert vals["16", "orthogonal", 20000] > 5 * vals["16", "orthogonal", 2000]


# ============================================================= equal power and feasibility
def test_equal_power_formulas_and_never_better_than_optimal():
    rng = np.random.default_rng(11)
    for _ in range(30):
        a, sw, h, c, sv, sn = random_instance(rng)
        g = rng.uniform(0.1, 5)
        al = power.equal_power(a, sw, c, sv, gamma=g)
        assert np.allclose(np.abs(al), np.sqrt(g * (1 - a**2) / (c**2 * sw + sv * (1 - a**2))))
        assert np.allclose(power.transmit_power(al, a, sw, c, sv), g)
        alt = power.equal_power(a, sw, c, sv, gamma_total=g)
        assert np.allclose(power.transmit_power(alt, a, sw, c, sv), g / len(c))
        for access in power.ACCESS:
            opt = power.min_error(access, g, a, sw, h, c, sv, sn)
            assert power.snr(access, opt, h, c, sv, sn) >= power.snr(access, alt, h, c, sv,
                                                                     sn) * (1 - 1e-12)
            D = feasible_D(rng, a, sw, c, sv, margin=3.0)
            try:
                eq = power.equal_power_min_power(access, D, a, sw, h, c, sv, sn)
            except power.InfeasibleError:
                assert access == "multi-access"  # the coherent ceiling is lower
                continue
            S = power.snr(access, eq, h, c, sv, sn)
            assert power.steady_state(a, sw, S) == pytest.approx(D, rel=1e-9)
            opt = power.min_power(access, D, a, sw, h, c, sv, sn)
            assert (power.transmit_power(opt, a, sw, c, sv).sum()
                    <= power.transmit_power(eq, a, sw, c, sv).sum() * (1 + 1e-12))


@pytest.mark.parametrize("access", power.ACCESS)
def test_feasibility_threshold_and_message(access):
    a, sw, sn = 0.9, 1.0, 0.5
    h = np.array([1.0, 0.5, 2.0])
    c = np.array([1.0, -1.0, 0.5])
    sv = np.array([2.0, 4.0, 8.0])
    total = np.sum(c**2 / sv)  # 0.78125
    # D at which the threshold equals the total sensor SNR: solve required_snr(D) = total
    Ds = np.linspace(1.0001, 1 / (1 - 0.81) - 1e-4, 200001)
    thr = power.required_snr(Ds, a, sw)
    D_star = Ds[np.argmin(np.abs(thr - total))]
    alpha = power.min_power(access, D_star * 1.001, a, sw, h, c, sv, sn)
    assert np.all(np.isfinite(alpha))
    D_bad = D_star * 0.999
    with pytest.raises(power.InfeasibleError) as info:
        power.min_power(access, D_bad, a, sw, h, c, sv, sn)
    assert isinstance(info.value, ValueError)
    msg = str(info.value)
    assert "0.78125" in msg  # the sum of sensor SNRs
    shown = float(re.search(r"= ([0-9.]+) \(condition \(20\)\)", msg).group(1))
    assert shown == pytest.approx(power.required_snr(D_bad, a, sw), rel=1e-5)
    assert shown > total


def test_validation_names_the_argument():
    h, c, sv = np.ones(3), np.ones(3), np.ones(3)
    good = dict(a=0.5, sigma_w2=1.0, h=h, c=c, sigma_v2=sv, sigma_n2=1.0)

    def call(**kw):
        args = {**good, **kw}
        return power.min_power("orthogonal", 1.1, **args)

    with pytest.raises(ValueError, match=r"^a must satisfy \|a\| < 1"):
        call(a=1.0)
    with pytest.raises(ValueError, match="^sigma_w2 must be positive"):
        call(sigma_w2=0.0)
    with pytest.raises(ValueError, match="^sigma_v2 must be positive"):
        call(sigma_v2=np.array([1.0, -1.0, 1.0]))
    with pytest.raises(ValueError, match="^sigma_n2 must be positive"):
        call(sigma_n2=0.0)
    with pytest.raises(ValueError, match="^h must be positive"):
        call(h=np.array([1.0, 0.0, 1.0]))
    with pytest.raises(ValueError, match="c has 2 sensors.*h has 3"):
        call(c=np.ones(2))
    with pytest.raises(ValueError, match="^D must lie strictly between"):
        power.min_power("orthogonal", 1.0, **good)
    with pytest.raises(ValueError, match="^D must lie strictly between"):
        power.min_power("orthogonal", 1 / 0.75, **good)
    with pytest.raises(ValueError, match="^access must be one of"):
        power.min_power("tdma", 1.1, **good)
    with pytest.raises(ValueError, match="^gamma_total must be non-negative"):
        power.min_error("multi-access", -1.0, **good)  # 0 is a limit (test_power_limits)
    with pytest.raises(ValueError, match="h has 3 sensors .* but alpha has 2"):
        power.snr("multi-access", np.ones(2), h, c, sv, 1.0)
    with pytest.raises(ValueError, match="^c must be finite"):
        call(c=np.array([1.0, np.nan, 1.0]))
    with pytest.raises(ValueError, match="exactly one of gamma"):
        power.equal_power(0.5, 1.0, c, sv)


# ===================================================================== fading, with CSI
def _fading_instance(rng, M=4, steps=30):
    a, sw, sn = 0.8, 1.0, 0.2
    c = rng.uniform(0.5, 1.5, M) * rng.choice([-1, 1], M)
    sv = rng.uniform(0.2, 1.0, M)
    h = np.abs(rng.standard_normal((steps, M)) + 1j * rng.standard_normal((steps, M)))
    return a, sw, sn, c, sv, h


def test_greedy_min_power_keeps_the_target_and_matches_a_step_loop():
    rng = np.random.default_rng(12)
    a, sw, sn, c, sv, h = _fading_instance(rng)
    D = 1.4
    for access in power.ACCESS:
        for P0 in (sw / (1 - a**2), D):
            P, spent = power.greedy_min_power(access, D, a, sw, h, c, sv, sn, P0=P0)
            assert np.all(P[1:] <= D * (1 + 1e-12)) and np.allclose(P[1:], D, rtol=1e-12)
            # an independent loop over the steps with the one-step solver
            p, loop = P0, []
            kap = power.kappa(a, sw, c, sv)
            for k in range(h.shape[0]):
                al = power.csi_min_power_step(access, p, D, a, sw, h[k], c, sv, sn)
                loop.append(np.sum(al**2 * kap))
                p = power.steady_recursion(p, a, sw, power.snr(access, al, h[k], c, sv, sn))
            assert np.allclose(spent, loop, rtol=1e-9)
        # below the target: the step can be met without transmitting
        al = power.csi_min_power_step(access, 0.3, D, a, sw, h[0], c, sv, sn)
        assert np.all(al == 0) and a**2 * 0.3 + sw <= D


def test_greedy_min_error_is_the_max_snr_each_step():
    rng = np.random.default_rng(13)
    a, sw, sn, c, sv, h = _fading_instance(rng)
    g = 2.0
    for access in power.ACCESS:
        P, S, spent = power.greedy_min_error(access, g, a, sw, h, c, sv, sn)
        assert np.allclose(spent, g, rtol=1e-12)
        rho, tau, kap = power.static_coefficients(a, sw, h, c, sv)
        if access == "multi-access":
            assert np.allclose(S, np.sum(rho**2 * g / (g * tau + kap * sn), -1), rtol=1e-12)
        prob = "coherent-max-snr" if access == "multi-access" else "orthogonal-max-snr"
        for k in (0, 7):
            _, num = power.solve_numerically(prob, rho[k], tau[k], kap, sn, gamma_total=g,
                                             starts=3)
            assert rel(S[k], num) < REL
        assert np.allclose(P[1:], power.steady_recursion(P[:-1], a, sw, S), rtol=1e-14)


# ================================================================== fading, no CSI
def test_eq33_moments_and_the_reduction_to_rho_tau():
    rng = np.random.default_rng(14)
    M = 4
    a, sw, sn = 0.9, 1.0, 0.3
    c, sv = rng.uniform(-1, 1, M), rng.uniform(0.2, 1, M)
    hm = rng.uniform(0.2, 1, M) + 1j * rng.uniform(-1, 1, M)
    vr, vi = rng.uniform(0.1, 1, M), rng.uniform(0.1, 1, M)
    al = rng.uniform(0.2, 1, M)
    at = power.beamformed(al, hm)
    mre, mim, var_re, _, _ = power.lmmse._channel_stats(at, hm, vr, vi)
    m_r, m_i, ab2 = hm.real, hm.imag, np.abs(hm) ** 2
    # (33) as printed (for alpha~ = alpha conj(E h)/|E h|)
    assert np.allclose(mre, al * np.abs(hm)) and np.allclose(mim, 0, atol=1e-15)
    assert np.allclose(var_re, al**2 / ab2 * (m_r**2 * vr + m_i**2 * vi))
    e2 = al**2 / ab2 * (m_r**2 * (vr + m_r**2) + 2 * m_r**2 * m_i**2 + m_i**2 * (vi + m_i**2))
    assert np.allclose(var_re + mre**2, e2)
    # the scalar form of S needs Cov(Re g, Im g) = 0: equal Re/Im variances (or axis means)
    with pytest.raises(ValueError, match="h_var_re and h_var_im must be equal"):
        power.lmmse_coefficients(a, sw, c, sv, hm, vr, vi)
    vr = vi = (vr + vi) / 2
    for access in power.ACCESS:
        rho, tau, kap = power.lmmse_coefficients(a, sw, c, sv, hm, vr, vi)
        C, R = power.lmmse_matrices(access, at, a, sw, c, sv, sn, hm, vr, vi)
        S = power.lmmse_snr(C, R)
        if access == "multi-access":
            assert S == pytest.approx((al @ rho) ** 2 / (al**2 @ tau + sn), rel=1e-12)
        else:
            assert S == pytest.approx(np.sum(al**2 * rho**2 / (al**2 * tau + sn)), rel=1e-12)


def _nocsi_trial(rng, n, *, access, steps, burn, args):
    x, xp, P = power.simulate_nocsi(rng, n, steps, access, *args)
    return ((x - xp) ** 2 / P - 1)[:, burn:].mean(-1)


def _lmmse_z(access, at, a, sw, c, sv, sn, hm, vr, vi, *, n=3000, seed=15):
    fn = functools.partial(_nocsi_trial, access=access, steps=40, burn=0,
                           args=(at, a, sw, c, sv, sn, hm, vr, vi))
    res = montecarlo.simulate(fn, n, seed)
    return float(res.mean / res.stderr)


@pytest.mark.parametrize("access", power.ACCESS)
def test_lmmse_variance_is_the_simulated_error_rician(access):
    """(32)-(33): the filter's P_{k|k-1} is its error variance (Rician, beamformed alpha~)."""
    rng = np.random.default_rng(16)
    M = 4
    a, sw, sn = 0.9, 1.0, 0.2
    c, sv = np.ones(M), rng.chisquare(1, M) + 0.05
    d, mu = rng.uniform(1, 2, M), rng.uniform(0.5, 1, M)
    hm, vr, vi = d**-2 * mu * (1 + 1j), d**-4, d**-4
    al = power.lmmse_min_error(access, 1.0, a, sw, c, sv, sn, hm, vr, vi)
    z = _lmmse_z(access, power.beamformed(al, hm), a, sw, c, sv, sn, hm, vr, vi)
    assert abs(z) < 4
    # and the steady state is (8) at S = Cbar^T Rbar^-1 Cbar
    _, _, P = power.simulate_nocsi(np.random.default_rng(0), 1, 400, access,
                                   power.beamformed(al, hm), a, sw, c, sv, sn, hm, vr, vi)
    assert P[-1] == pytest.approx(
        power.lmmse_steady_state(access, al, a, sw, c, sv, sn, hm, vr, vi), rel=1e-12)


def test_lmmse_general_rbar_and_the_printed_off_diagonal():
    """Unequal Re/Im variances and a phase-rotated alpha~: our Rbar (with the covariance term)
    is exact; the printed Rbar_12 (without it) misstates the error variance."""
    a, sw, sn = 0.9, 1.0, 0.05
    c, sv = np.array([1.0, 1.5]), np.array([0.1, 0.2])
    hm = np.array([0.3 + 0.3j, 0.4 + 0.2j])
    vr, vi = np.array([2.0, 1.5]), np.array([0.01, 0.02])
    at = np.exp(1j * np.pi / 4) * np.array([1.0, 0.8])
    z = _lmmse_z("multi-access", at, a, sw, c, sv, sn, hm, vr, vi)
    assert abs(z) < 4
    C, R = power.lmmse_matrices("multi-access", at, a, sw, c, sv, sn, hm, vr, vi)
    mre, mim, _, _, cov = power.lmmse._channel_stats(at, hm, vr, vi)
    assert abs(np.sum(cov * (c**2 * sw / (1 - a**2) + sv))) > 0.5  # the omitted term
    R_printed = R.copy()
    R_printed[0, 1] = R_printed[1, 0] = np.sum(mre * mim * sv)

    def trial(rng, n):
        x, xp, P = power.simulate_nocsi(rng, n, 40, "multi-access", at, a, sw, c, sv, sn, hm,
                                        vr, vi)
        # the same data through a filter built on the printed Rbar
        zc = _replay(rng, x, at, c, sv, sn, hm, vr, vi)
        xq, Pq = power.lmmse_filter(zc, a, sw, C, R_printed)
        return ((x - xq[:, :40]) ** 2 / Pq[:40] - 1).mean(-1)

    res = montecarlo.simulate(trial, 3000, 17)
    assert abs(res.mean / res.stderr) > 4


def _replay(rng, x, at, c, sv, sn, hm, vr, vi):
    """Observations of the multi-access no-CSI channel for given states ``x`` (n, steps)."""
    n, steps = x.shape
    M = len(c)
    y = c * x[..., None] + rng.standard_normal((n, steps, M)) * np.sqrt(sv)
    h = (hm.real + np.sqrt(vr) * rng.standard_normal((n, steps, M))
         + 1j * (hm.imag + np.sqrt(vi) * rng.standard_normal((n, steps, M))))
    zc = (at * h * y).sum(-1) + (rng.standard_normal((n, steps))
                                 + 1j * rng.standard_normal((n, steps))) * np.sqrt(sn)
    return np.stack([zc.real, zc.imag], -1)


def test_lmmse_min_power_meets_target_and_raises_when_infeasible():
    rng = np.random.default_rng(18)
    M = 6
    a, sw, sn = 0.9, 1.0, 1e-3
    c, sv = np.ones(M), rng.uniform(0.1, 1, M)
    hm, vr, vi = np.full(M, 0.7 + 0.7j), np.full(M, 1.0), np.full(M, 1.0)
    for access in power.ACCESS:
        al = power.lmmse_min_power(access, 2.0, a, sw, c, sv, sn, hm, vr, vi)
        P = power.lmmse_steady_state(access, al, a, sw, c, sv, sn, hm, vr, vi)
        assert P == pytest.approx(2.0, rel=1e-12)
        with pytest.raises(power.InfeasibleError, match="without CSI"):
            power.lmmse_min_power(access, 1.05, a, sw, c, sv, sn, hm, vr, vi)
    with pytest.raises(ValueError, match="h_mean must be non-zero"):
        power.beamformed(np.ones(2), np.array([1.0, 0.0]))
