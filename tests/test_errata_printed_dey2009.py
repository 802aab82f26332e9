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


# ---------------------------------------------------------------- E9: (20)'s denominator
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


# ------------------------------------------------------- E11: beta_k in the display after (21)
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


# -------------------------------------------------------------- E12: (23) needs x_i > 0
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


# ---------------------------------------------------------------- E10: Appendix B, A X A'
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


# ---------------------------------------- E42: Section 3.3.2 uses one channel noise sigma_n^2
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
