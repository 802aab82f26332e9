"""Printed-form tests of the mo2015 errata (book/errata.md, "Mo (2015)").

Each test evaluates what the notes print, asserts that the erratum's check rejects it, and
asserts that the correction passes the same check. The checks restate those of the chapters
book/mo2015/trigger.md and book/mo2015/derivation.md.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.integrate
import scipy.optimize
from errata_marks import erratum
from scipy.special import ndtr
from scipy.stats import multivariate_normal, norm

from fusioncenter import event


def _random_instance(rng, n):
    B = rng.standard_normal((n, n))
    Sigma = B @ B.T + 0.3 * np.eye(n)
    a = rng.standard_normal((1, n))
    return rng.standard_normal(n), Sigma, a, rng.uniform(0.2, 2.0), rng.uniform(0.1, 5.0)


# --------------------------------------------------------------- E1: Section 1, independence
@erratum("erratum-mo2015-1-independence")
def test_linear_independence_admits_a_noise_for_which_the_closed_form_fails():
    """x ~ N(0, 1), a = 1, r = 0.5, delta = 1. The printed assumption ("linearly independent":
    uncorrelated) admits v = sqrt(r) z(x), z(x) = x for |x| > c and -x otherwise: exactly
    N(0, r) and uncorrelated with x, yet Var(x | silent) is not P_tilde. With v independent of x
    (the correction), the closed form holds."""
    r, delta = 0.5, 1.0
    p_tilde = 1 / (1 + 1 / (r + delta))

    def g(y):
        return np.exp(-y * y / (2 * delta))

    c = scipy.optimize.brentq(lambda t: 2 * ndtr(t) - 1 - 2 * t * norm.pdf(t) - 0.5, 0.5, 3)

    def v_flip(x):
        return np.sqrt(r) * (x if abs(x) > c else -x)

    def integral(h):
        pieces = [(-12.0, -c), (-c, c), (c, 12.0)]
        return sum(scipy.integrate.quad(h, lo, hi, limit=200)[0] for lo, hi in pieces)

    assert abs(integral(lambda x: x * v_flip(x) * norm.pdf(x))) < 1e-9  # uncorrelated
    assert integral(lambda x: v_flip(x) ** 2 * norm.pdf(x)) == pytest.approx(r, abs=1e-9)

    def weight(x):
        return norm.pdf(x) * g(x + v_flip(x))

    z = integral(weight)
    mean = integral(lambda x: x * weight(x)) / z
    var_printed = integral(lambda x: (x - mean) ** 2 * weight(x)) / z
    assert abs(var_printed - p_tilde) > 0.02  # the closed form fails
    # independent v: E[g(x + v) | x] = sqrt(delta / (delta + r)) exp(-x^2 / (2 (r + delta)))

    def weight_ind(x):
        return norm.pdf(x) * np.sqrt(delta / (delta + r)) * np.exp(-x * x / (2 * (r + delta)))

    z_i = scipy.integrate.quad(weight_ind, -12, 12)[0]
    var_i = scipy.integrate.quad(lambda x: x * x * weight_ind(x), -12, 12)[0] / z_i
    assert var_i == pytest.approx(p_tilde, rel=1e-9)
    assert z_i == pytest.approx(np.sqrt(delta / (1 + r + delta)), rel=1e-9)


# -------------------------------------------------------- E3: Section 2, first display, line 1
@erratum("erratum-mo2015-2-product-of-events")
def test_printed_product_of_event_probabilities_is_not_the_joint_probability():
    """x ~ N(0, 1), a = r = delta = 1, X = Y = [0, inf). The frequency of {x in X, y in Y,
    gamma = 0} in 10^6 simulated triples (x, y, xi) agrees with the integral of p(x) p(y|x) g(y)
    over X x Y (the display's second line, the correction) and is far from the printed product
    P(X) P(Y | X) P(gamma = 0 | Y)."""
    def g(y):
        return np.exp(-y * y / 2)

    joint = scipy.integrate.dblquad(lambda y, x: norm.pdf(x) * norm.pdf(y, x, 1.0) * g(y),
                                    0.0, 14.0, 0.0, 14.0, epsabs=0, epsrel=1e-9)[0]
    p_XY = 0.25 + np.arcsin(np.sqrt(0.5)) / (2 * np.pi)  # orthant probability, corr 1/sqrt 2
    p_sil_given_Y = np.sqrt(1 / 3)  # y ~ N(0, 2): E[g(y) | y >= 0] = sqrt(1/3)
    printed = p_XY * p_sil_given_Y  # P(X) P(Y | X) = P(X, Y)
    rng = np.random.default_rng(3)
    n = 1_000_000
    x = rng.standard_normal(n)
    y = x + rng.standard_normal(n)
    freq = np.mean((x >= 0) & (y >= 0) & (rng.uniform(size=n) <= g(y)))
    se = np.sqrt(freq * (1 - freq) / n)
    assert abs(joint - freq) < 4 * se
    assert abs(printed - freq) > 20 * se


# ------------------------------------------------------- E2: Section 2, (2 pi)^k with k undefined
@erratum("erratum-mo2015-2-normalising-constant")
def test_prior_density_integrates_to_one_only_with_2pi_to_the_n():
    """n = 2: the density with (2 pi)^k has total mass 1 only for k = n (grid quadrature), and
    matches scipy's multivariate normal for n = 2, 3, 4 only with k = n."""
    Sigma = np.array([[1.0, 0.6], [0.6, 2.0]])
    g1 = np.linspace(-12.0, 12.0, 961)
    X1, X2 = np.meshgrid(g1, g1, indexing="ij")
    X = np.stack([X1, X2], -1)
    qf = np.einsum("...i,ij,...j->...", X, np.linalg.inv(Sigma), X)
    for k in (1, 2, 3):
        dens = np.exp(-qf / 2) / np.sqrt((2 * np.pi) ** k * np.linalg.det(Sigma))
        mass = np.trapezoid(np.trapezoid(dens, g1, axis=1), g1)
        assert (abs(mass - 1) < 1e-9) == (k == 2)
    rng = np.random.default_rng(1)
    for n in (2, 3, 4):
        xbar, S, *_ = _random_instance(rng, n)
        pts = xbar + rng.standard_normal((5, n))
        d = pts - xbar
        quad = np.einsum("ki,ij,kj->k", d, np.linalg.inv(S), d)
        ref = multivariate_normal(xbar, S).pdf(pts)
        for k in (n - 1, n, n + 1):
            ours = np.exp(-quad / 2) / np.sqrt((2 * np.pi) ** k * np.linalg.det(S))
            assert np.allclose(ours, ref, rtol=1e-12, atol=0) == (k == n)


# ------------------------------------------------- E6: Section 2, lambda is not the rate
@erratum("erratum-mo2015-2-lambda-constant")
def test_constant_of_the_silent_case_is_not_the_communication_rate():
    """The constant in P(x in X, gamma = 0) = lambda int_X exp[-(x - x~)' P~^{-1} (x - x~)/2] dx
    is lambda_0 = P(gamma = 0) / sqrt((2 pi)^n det P~), computed directly from the prefactors
    and c_0 of the derivation; reading lambda as Section 3's rate P(gamma = 1) fails."""
    rng = np.random.default_rng(7)
    for _ in range(10):
        xbar, Sigma, a, r, d = _random_instance(rng, 3)
        s = (a @ Sigma @ a.T).item() + r
        c0 = (a @ xbar).item() ** 2 / (s + d)
        lam0_direct = (np.sqrt(d / (r + d)) * np.exp(-c0 / 2)
                       / np.sqrt((2 * np.pi) ** 3 * np.linalg.det(Sigma)))
        P_tilde = np.linalg.inv(np.linalg.inv(Sigma) + a.T @ a / (r + d))
        p_silent = np.sqrt(d / (s + d)) * np.exp(-(a @ xbar).item() ** 2 / (2 * (s + d)))
        lam0 = p_silent / np.sqrt((2 * np.pi) ** 3 * np.linalg.det(P_tilde))
        rate = event.communication_rate(Sigma, a, [r], [d], xbar=xbar)[0]
        assert lam0 == pytest.approx(lam0_direct, rel=1e-12)
        assert abs(rate - lam0_direct) > 1e-3 * max(rate, lam0_direct)


# ---------------------------------------------------- E4 and E5: Section 2, P where P~ belongs
@erratum("erratum-mo2015-2-xtilde")
def test_printed_mean_with_P_is_not_the_posterior_mean_after_silence():
    """x~ = P Sigma^{-1} x_bar with the notes' P = (Sigma^{-1} + a'a/r)^{-1} against the posterior
    mean given gamma = 0 (grid quadrature, n = 2, and event.posterior); x~ = P~ Sigma^{-1} x_bar
    passes."""
    xbar, Sigma = np.array([0.8, -0.5]), np.array([[1.0, 0.3], [0.3, 0.6]])
    a, r, d = np.array([[1.0, 0.5]]), 0.5, 2.0
    g = np.linspace(-6, 6, 601)
    X = np.stack(np.meshgrid(g, g, indexing="ij"), -1)
    dx = X - xbar
    logw = (-0.5 * np.einsum("...i,ij,...j->...", dx, np.linalg.inv(Sigma), dx)
            - 0.5 * (X @ a[0]) ** 2 / (r + d))  # p(x) E[g(y) | x]
    w = np.exp(logw - logw.max())
    mean = np.einsum("ij,ijk->k", w, X) / w.sum()
    P_sent = np.linalg.inv(np.linalg.inv(Sigma) + a.T @ a / r)
    P_tilde = np.linalg.inv(np.linalg.inv(Sigma) + a.T @ a / (r + d))
    prior_info = np.linalg.solve(Sigma, xbar)
    lib_mean, _ = event.posterior(xbar, Sigma, a, [r], [d], [0], [np.nan])
    np.testing.assert_allclose(P_tilde @ prior_info, mean, atol=1e-8)
    np.testing.assert_allclose(P_tilde @ prior_info, lib_mean, rtol=1e-12)
    assert np.max(np.abs(P_sent @ prior_info - mean)) > 0.05


def _mean_gap(xbar, Sigma, a, r, d):
    """The printed mean minus the posterior mean after a silence:
    (P - P~) Sigma^{-1} x_bar, P = (Sigma^{-1} + a'a/r)^{-1}, P~ = (Sigma^{-1} + a'a/(r+d))^{-1}."""
    P_sent = np.linalg.inv(np.linalg.inv(Sigma) + a.T @ a / r)
    P_tilde = np.linalg.inv(np.linalg.inv(Sigma) + a.T @ a / (r + d))
    return (P_sent - P_tilde) @ np.linalg.solve(Sigma, xbar)


@erratum("erratum-mo2015-2-xtilde")
def test_printed_mean_is_off_by_a_term_that_saturates_in_delta():
    """How the printed mean is off: P Sigma^{-1} x_bar - P~ Sigma^{-1} x_bar
    = -Sigma a' (a x_bar) delta / (s (s + delta)), s = a Sigma a' + r. Not proportional to
    delta (doubling delta does not double it; it tends to -Sigma a' (a x_bar) / s), and zero
    for every delta when a x_bar = 0."""
    rng = np.random.default_rng(15)
    deltas = np.array([0.1, 1.0, 10.0, 1e3, 1e6])
    for n in (1, 2, 3):
        xbar, Sigma, a, r, _ = _random_instance(rng, n)
        s = (a @ Sigma @ a.T).item() + r
        limit = -(Sigma @ a[0]) * (a @ xbar).item() / s
        gaps = [_mean_gap(xbar, Sigma, a, r, d) for d in deltas]
        np.testing.assert_allclose(gaps, [limit * d / (s + d) for d in deltas],
                                   rtol=1e-6, atol=1e-12)
        doubled = [np.linalg.norm(_mean_gap(xbar, Sigma, a, r, 2 * d)) / np.linalg.norm(g)
                   for d, g in zip(deltas, gaps, strict=True)]
        assert max(abs(q - 2) for q in doubled) > 0.5  # "proportional to delta" fails
        assert all(np.linalg.norm(g) < np.linalg.norm(limit) for g in gaps)  # bounded
        if n > 1:  # a x_bar = 0 with x_bar != 0: no gap for any delta
            xb0 = xbar - a[0] * (a @ xbar).item() / (a @ a.T).item()
            assert np.linalg.norm(xb0) > 0.01
            assert np.max(np.abs(_mean_gap(xb0, Sigma, a, r, 5.0))) < 1e-10


@erratum("erratum-mo2015-2-ptilde")
def test_printed_covariance_P_is_not_the_covariance_after_silence():
    """The conclusion "Gaussian with mean x~ and covariance P": the covariance given gamma = 0
    (grid quadrature, n = 2) is P~, not the notes' P = (Sigma^{-1} + a'a/r)^{-1}."""
    xbar, Sigma = np.array([0.8, -0.5]), np.array([[1.0, 0.3], [0.3, 0.6]])
    a, r, d = np.array([[1.0, 0.5]]), 0.5, 2.0
    g = np.linspace(-6, 6, 601)
    X = np.stack(np.meshgrid(g, g, indexing="ij"), -1)
    dx = X - xbar
    logw = (-0.5 * np.einsum("...i,ij,...j->...", dx, np.linalg.inv(Sigma), dx)
            - 0.5 * (X @ a[0]) ** 2 / (r + d))
    w = np.exp(logw - logw.max())
    w /= w.sum()
    mean = np.einsum("ij,ijk->k", w, X)
    dd = X - mean
    cov = np.einsum("ij,ijk,ijl->kl", w, dd, dd)
    P_sent = np.linalg.inv(np.linalg.inv(Sigma) + a.T @ a / r)
    P_tilde = np.linalg.inv(np.linalg.inv(Sigma) + a.T @ a / (r + d))
    np.testing.assert_allclose(P_tilde, cov, atol=1e-8)
    assert np.max(np.abs(P_sent - cov)) > 0.05


# ------------------------------------------------------- E7: Section 2, the case gamma = 1
@erratum("erratum-mo2015-2-gamma1-events")
def test_printed_cancellation_with_events_is_false_and_holds_for_densities():
    """x ~ N(0, 1), a = r = delta = 1. For sets X = [0, inf), Y = [0, 1] the printed
    P(x in X | y in Y, gamma = 1) = P(x in X | y in Y) is false; for a point y (densities,
    the correction) p(x | y, gamma = 1) = p(x | y) holds at every x."""
    def g(y):
        return np.exp(-y * y / 2)

    def p_xy(y, x):
        return norm.pdf(x) * norm.pdf(y, x, 1.0)

    def dbl(h, xlo, xhi):
        return scipy.integrate.dblquad(h, xlo, xhi, 0.0, 1.0, epsabs=0, epsrel=1e-10)[0]

    def sent(y, x):
        return p_xy(y, x) * (1 - g(y))

    with_trigger = dbl(sent, 0.0, 14.0) / dbl(sent, -14.0, 14.0)
    without = dbl(p_xy, 0.0, 14.0) / dbl(p_xy, -14.0, 14.0)
    assert abs(with_trigger - without) > 0.01
    y0, xs = 0.7, np.linspace(-3, 3, 13)
    dens_with = sent(y0, xs) / scipy.integrate.quad(lambda x: sent(y0, x), -14, 14)[0]
    dens_without = p_xy(y0, xs) / scipy.integrate.quad(lambda x: p_xy(y0, x), -14, 14)[0]
    np.testing.assert_allclose(dens_with, dens_without, rtol=1e-10)


# ----------------------------------------------------- E8: Section 3, the communication rate
@erratum("erratum-mo2015-3-rate")
def test_printed_rate_is_wrong_for_a_nonzero_prior_mean():
    """lambda_i = P(gamma_i = 1) = 1 - E g(y_i) with y_i ~ N(a_i x_bar, s_i), by quadrature.
    The printed 1 - 1/sqrt(1 + s_i/delta_i) (derived for x_bar = 0) fails for x_bar != 0; the
    corrected 1 - sqrt(delta/(delta + s)) exp(-mu^2 / (2 (delta + s))) passes, and so does the
    library's event.communication_rate."""
    Sigma = np.array([[1.0, 0.3], [0.3, 0.6]])
    C = np.array([[1.0, 0.5], [0.0, 1.0]])
    r, delta = np.array([0.5, 1.0]), np.array([2.0, 0.7])
    xbar = np.array([1.5, -1.0])
    s = np.einsum("ij,jk,ik->i", C, Sigma, C) + r
    mu = C @ xbar
    quad = np.array([1 - scipy.integrate.quad(
        lambda y, i=i: norm.pdf(y, mu[i], np.sqrt(s[i])) * np.exp(-y * y / (2 * delta[i])),
        -40, 40, epsabs=0, epsrel=1e-12)[0] for i in range(2)])
    printed = 1 - 1 / np.sqrt(1 + s / delta)
    corrected = 1 - np.sqrt(delta / (delta + s)) * np.exp(-mu**2 / (2 * (delta + s)))
    np.testing.assert_allclose(corrected, quad, rtol=1e-10)
    np.testing.assert_allclose(event.communication_rate(Sigma, C, r, delta, xbar=xbar), quad,
                               rtol=1e-10)
    assert np.all(np.abs(printed - quad) > 0.05)
    # with x_bar = 0 both forms agree: the printed rate is the special case
    np.testing.assert_allclose(printed, event.communication_rate(Sigma, C, r, delta),
                               rtol=1e-12)
