"""Executable checks of errata found on a second reading (now in their papers' sections of
book/errata.md).

Each test is cited from a row of the errata page. They re-derive a printed formula against the
model it claims to follow: a Kalman step, a quadrature, or a Monte Carlo simulation.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.integrate
import scipy.special

from fusioncenter import event, fading, riccati


# ====================================================================== dey2009, Section 3.3.2
def _orth_step_printed(p, a, sw2, h2, c, sv2, sn2_common):
    """The first display of Section 3.3.2: one channel noise sigma_n^2 for every sensor."""
    return sw2 + a * a * p / (1 + p * np.sum(h2 * c**2 / (h2 * sv2 + sn2_common)))


def test_dey2009_orthogonal_recursion_needs_each_channels_noise():
    """Model (8) gives every channel its own noise sigma_{n_i}^2; the Kalman step is
    p' = sigma_w^2 + a^2 p / (1 + p sum_i h_i^2 c_i^2 / (h_i^2 sigma_i^2 + sigma_{n_i}^2))."""
    rng = np.random.default_rng(1)
    a, sw2 = 1.2, 1.0
    c, sv2, sn2 = np.array([1.0, 0.7, 1.5]), np.array([0.5, 2.0, 1.0]), np.array([0.1, 4.0, 20.0])
    for _ in range(20):
        p, h2 = rng.uniform(0.1, 10), rng.exponential(1.0, 3)
        h = np.sqrt(h2)
        C = (h * c)[:, None]  # z^i = h_i c_i x + h_i v^i + n^i
        R = np.diag(h2 * sv2 + sn2)
        kalman = a * a * riccati.measurement_update([[p]], C, R)[0, 0] + sw2
        corrected = sw2 + a * a * p / (1 + p * np.sum(h2 * c**2 / (h2 * sv2 + sn2)))
        assert kalman == pytest.approx(corrected, rel=1e-12)
        # the printed display with one common noise is a different recursion
        assert abs(_orth_step_printed(p, a, sw2, h2, c, sv2, sn2[0]) - kalman) > 1e-3 * kalman


def test_dey2009_first_expectation_of_3_3_2_with_sigma_n1():
    """E_{r_1}[(r_1 s_1 + n_1) / ((r_1 s_1 + n_1) D + r_1 c_1^2 g)] = s_1 / (s_1 D + c_1^2 g)
    [1 + (A_1 - B_1) e^{B_1} E_1(B_1)] with A_1 = lam_1 n_1 / s_1, B_1 = lam_1 n_1 D / (s_1 D +
    c_1^2 g): the constants carry sensor 1's channel noise n_1 = sigma_{n_1}^2. The identity
    itself holds for any n_1, so the test also takes the constants with the other channel's
    noise n_2 (what one sigma_n^2 for every channel amounts to when the noises differ) and
    sees them miss the quadrature."""
    lam, s1, n1, n2, c1, g = 1.7, 0.8, 2.5, 0.05, 1.3, 3.0
    for D in (1.0, 2.4):  # D = 1 + g * (information of the other sensors)
        quad = scipy.integrate.quad(
            lambda r, D=D: lam * np.exp(-lam * r) * (r * s1 + n1) / ((r * s1 + n1) * D
                                                               + r * c1**2 * g),
            0, np.inf, epsabs=0, epsrel=1e-12)[0]

        def closed(noise, D=D):
            A1, B1 = lam * noise / s1, lam * noise * D / (s1 * D + c1**2 * g)
            return s1 / (s1 * D + c1**2 * g) * (1 + (A1 - B1) * np.exp(B1)
                                                 * scipy.special.exp1(B1))

        assert quad == pytest.approx(closed(n1), rel=1e-10)
        assert abs(closed(n2) / quad - 1) > 0.05


def test_dey2009_printed_orthogonal_bound_with_a_common_noise_can_fail():
    """With unequal channel noises, the printed bound (one sigma_n^2, here the smallest) lies
    below the simulated E[p_k]; with each channel's own noise it bounds it (both via
    fading.multisensor_bounds, which takes one noise per channel)."""
    args = dict(access="orthogonal", a=1.1, c=[1.0, 1.0], sigma_v2=[0.5, 0.5], lams=[1.0, 1.0],
                sigma_w2=1.0, p0=1.0, steps=15)
    sn2 = [0.05, 30.0]
    mean, se = fading.multisensor_mc(**args, sigma_n2=sn2, n_paths=20000, seed=5)
    own = fading.multisensor_bounds(**args, sigma_n2=sn2)
    common = fading.multisensor_bounds(**args, sigma_n2=[sn2[0], sn2[0]])
    assert np.all(mean[1:] <= own["s"][1:] + 4 * se[1:])
    assert np.all(mean[1:] <= own["t"][1:] + 4 * se[1:])
    assert np.all(common["t"][3:] < mean[3:] - 6 * se[3:])  # the printed (26) is violated


def test_dey2009_riccati_10_and_11_agree():
    """(11) with L_k = H_k Sigma_n^{-1} H_k is (10) rewritten (H_k invertible). The paper is right
    here: this is a check of the paper, no erratum's evidence (the notation slip in the channel
    history after (9) and (12) is found by reading). It can fail: with L_k = H_k Sigma_n H_k
    (Sigma_n not inverted) the two recursions differ."""
    rng = np.random.default_rng(2)
    n, m = 3, 2
    A = rng.standard_normal((n, n))
    C = rng.standard_normal((m, n))
    Sv, Sn, Sw = np.diag([0.5, 2.0]), np.diag([1.0, 0.3]), np.eye(n)
    M = rng.standard_normal((n, n))
    P = M @ M.T + np.eye(n)
    for _ in range(10):
        H = np.diag(rng.exponential(1.0, m) ** 0.5)
        R = H @ Sv @ H + Sn
        ten = A @ (P - P @ C.T @ H @ np.linalg.solve(H @ C @ P @ C.T @ H + R, H @ C @ P)) @ A.T + Sw
        L = H @ np.linalg.inv(Sn) @ H
        eleven = A @ (P - P @ C.T @ np.linalg.solve(np.linalg.inv(L) + C @ P @ C.T + Sv, C @ P)) \
            @ A.T + Sw
        np.testing.assert_allclose(ten, eleven, rtol=1e-10, atol=1e-12)
        L_wrong = H @ Sn @ H
        wrong = A @ (P - P @ C.T @ np.linalg.solve(np.linalg.inv(L_wrong) + C @ P @ C.T + Sv,
                                                   C @ P)) @ A.T + Sw
        assert np.max(np.abs(wrong - ten)) > 1e-5 * np.max(np.abs(ten))  # agreement: 1e-10


# ================================================================= mo2015, Section 2, m sensors
def test_mo2015_multisensor_formulas_by_quadrature():
    """Section 2's m-sensor x_hat and P, with C the matrix of rows a_i and R = diag(r_i) (the
    notes never define C and R), equal the posterior computed by brute-force quadrature of
    p(x) prod_i p(gamma_i, gamma_i y_i | x) on a grid, for a non-zero prior mean; the
    information form and the covariance form of P agree."""
    xbar = np.array([0.4, -0.3])
    Sigma = np.array([[1.0, 0.3], [0.3, 0.6]])
    a = np.array([[1.0, 0.5], [0.0, 1.0], [1.0, -1.0]])
    r = np.array([0.5, 1.0, 0.3])
    delta = np.array([2.0, 0.7, 1.5])
    gamma = np.array([1, 0, 0])
    y = np.array([0.9, np.nan, np.nan])  # silent sensors: y unknown to the fusion centre
    g = np.linspace(-5, 5, 801)
    X1, X2 = np.meshgrid(g, g, indexing="ij")
    X = np.stack([X1, X2], axis=-1)
    d = X - xbar
    logp = -0.5 * np.einsum("...i,ij,...j->...", d, np.linalg.inv(Sigma), d)
    for i in range(3):
        ax = X @ a[i]
        if gamma[i]:  # p(y_i | x) (1 - g(y_i)); the last factor is constant in x
            logp += -0.5 * (y[i] - ax) ** 2 / r[i]
        else:  # E[g(y_i) | x] = sqrt(delta/(delta + r)) exp(-(a x)^2 / (2 (r + delta)))
            logp += -0.5 * ax**2 / (r[i] + delta[i])
    w = np.exp(logp - logp.max())
    w /= w.sum()
    mean = np.einsum("ij,ijk->k", w, X)
    dd = X - mean
    cov = np.einsum("ij,ijk,ijl->kl", w, dd, dd)
    C, R = a, np.diag(r)
    Gam, Del = np.diag(gamma), np.diag(delta)
    S = C @ Sigma @ C.T + R + (np.eye(3) - Gam) @ Del
    xhat = xbar + Sigma @ C.T @ np.linalg.solve(S, Gam @ np.nan_to_num(y) - C @ xbar)
    P_cov = Sigma - Sigma @ C.T @ np.linalg.solve(S, C @ Sigma)
    P_info = np.linalg.inv(np.linalg.inv(Sigma) + sum(
        np.outer(a[i], a[i]) / (r[i] + (1 - gamma[i]) * delta[i]) for i in range(3)))
    np.testing.assert_allclose(xhat, mean, atol=1e-6)
    np.testing.assert_allclose(P_cov, cov, atol=1e-6)
    np.testing.assert_allclose(P_info, P_cov, rtol=1e-12)
    lib = event.posterior(xbar, Sigma, C, r, delta, gamma, y)
    np.testing.assert_allclose(lib[0], xhat, rtol=1e-12)
    np.testing.assert_allclose(lib[1], P_cov, rtol=1e-12)


# ============================================================ zheng2014, Section III, after (23)
def test_zheng2014_cross_covariance_starts_at_P0_not_zero():
    """Two local Kalman filters started from the same prior (x_hat_{0|0} = m0, P_{0|0} = P0)
    have identical initial errors: their cross-covariance at 0|0 is P0, and (22)-(23) started
    there match the simulated cross-covariance of the prediction errors; started at 0 (as
    printed) they are wrong by F P0 F^T at k = 1 unless P0 = 0 (a known x_0)."""
    F = np.array([[1.0, 1.0], [0.0, 1.0]])
    Q = 4 * np.array([[0.25, 0.5], [0.5, 1.0]])
    P0 = np.diag([3.0, 1.0])
    h = [np.array([1.0, 0.0]), np.array([1.0, 0.5])]
    rr = [1.0, 2.0]
    n, steps = 200_000, 4
    rng = np.random.default_rng(11)
    x = rng.multivariate_normal(np.zeros(2), P0, n)  # m0 = 0
    xh = [np.zeros((n, 2)), np.zeros((n, 2))]
    P = [P0.copy(), P0.copy()]
    cross_from_P0, cross_from_0 = P0.copy(), np.zeros((2, 2))
    for _ in range(steps):
        x = x @ F.T + rng.multivariate_normal(np.zeros(2), Q, n)
        for i in range(2):
            xh[i] = xh[i] @ F.T
            P[i] = F @ P[i] @ F.T + Q
        pred = [F @ C @ F.T + Q for C in (cross_from_P0, cross_from_0)]  # (22)
        e = [x - xh[0], x - xh[1]]
        emp = e[0].T @ e[1] / n
        scale = np.abs(pred[0]).max()
        np.testing.assert_allclose(emp, pred[0], atol=0.02 * scale)
        if _ == 0:
            assert np.abs(emp - pred[1]).max() > 0.3 * scale  # the printed initialisation
        w = []
        for i in range(2):  # local measurement updates
            z = x @ h[i] + rng.standard_normal(n) * np.sqrt(rr[i])
            s = h[i] @ P[i] @ h[i] + rr[i]
            wi = P[i] @ h[i] / s
            xh[i] = xh[i] + (z - xh[i] @ h[i])[:, None] * wi
            P[i] = P[i] - np.outer(wi, wi) * s
            w.append(wi)
        Ia, Ib = np.eye(2) - np.outer(w[0], h[0]), np.eye(2) - np.outer(w[1], h[1])
        cross_from_P0 = Ia @ pred[0] @ Ib.T  # (23)
        cross_from_0 = Ia @ pred[1] @ Ib.T


def test_mo2015_constants_alpha_and_beta():
    """The y-integral of the second display: int exp(-((y - ax)^2 / r + y^2 / delta) / 2) dy
    = sqrt(2 pi r delta / (r + delta)) exp(-(ax)^2 / (2 (r + delta))), so beta / alpha =
    sqrt(2 pi r delta / (r + delta))."""
    for r, delta, ax in ((0.5, 2.0, 0.3), (2.0, 0.1, -1.7), (1.0, 1.0, 0.0)):
        quad = scipy.integrate.quad(
            lambda y, r=r, delta=delta, ax=ax: np.exp(-0.5 * ((y - ax) ** 2 / r + y**2 / delta)),
            -np.inf, np.inf, epsabs=0, epsrel=1e-12)[0]
        want = np.sqrt(2 * np.pi * r * delta / (r + delta)) * np.exp(-ax**2 / (2 * (r + delta)))
        assert quad == pytest.approx(want, rel=1e-10)
