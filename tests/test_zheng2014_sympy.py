"""Symbolic facts of zheng2014 Sections II-IV, checked against the library (fast).

The chapters ``book/zheng2014/censoring-kl.md`` and ``book/zheng2014/likelihood.md`` derive these
in SymPy; here the derived expressions are lambdified and compared with ``fusioncenter.censoring``
on random inputs, and the KL identities are checked symbolically and in higher dimensions.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg
import scipy.stats
import sympy as sp

from fusioncenter import censoring as cs


def _zero(expr) -> bool:
    return sp.simplify(sp.cancel(sp.together(expr.rewrite(sp.erf)))) == 0


def _q(t):
    return sp.erfc(t / sp.sqrt(2)) / 2


def _gaussian_kl(m_p, P_p, m_q, P_q):
    d = len(m_p)
    inv = np.linalg.inv(P_q)
    dm = m_q - m_p
    return 0.5 * (np.trace(inv @ P_p) - d + dm @ inv @ dm + np.linalg.slogdet(P_q)[1]
                  - np.linalg.slogdet(P_p)[1])


@pytest.fixture(scope="module")
def silent_expr():
    """P(m = 0 | x, xhat) as the integral of N(z; hx, r) over (c - a, c + a), by SymPy."""
    z = sp.Symbol("z", real=True)
    hx, c = sp.symbols("hx c", real=True)
    a, r = sp.symbols("a r", positive=True)
    dens = sp.exp(-(z - hx) ** 2 / (2 * r)) / sp.sqrt(2 * sp.pi * r)
    antider = sp.erf((z - hx) / sp.sqrt(2 * r)) / 2  # an antiderivative, checked below
    assert sp.simplify(sp.diff(antider, z) - dens) == 0
    silent = antider.subs(z, c + a) - antider.subs(z, c - a)
    return silent, (hx, c, a, r)


def test_silent_probability_is_the_q_difference_with_mu_outside_the_root(silent_expr):
    """Proposition 1, (14): xi_{1,2} = (-/+ sqrt(eta s) - mu) / sqrt(r) (erratum: the printed
    definitions after (9) put mu under the root)."""
    silent, (hx, c, a, r) = silent_expr
    mu = hx - c
    assert _zero(silent - (_q((-a - mu) / sp.sqrt(r)) - _q((a - mu) / sp.sqrt(r))))
    f = sp.lambdify((hx, c, a, r), silent, "scipy")
    rng = np.random.default_rng(0)
    for _ in range(50):
        hx_v, c_v = rng.normal(0, 3, 2)
        s_v, r_v, eta_v = rng.uniform(0.2, 8), rng.uniform(0.1, 3), rng.uniform(0.05, 3)
        lib = cs.censored_probability(hx_v - c_v, s_v, r_v, eta_v)
        assert lib == pytest.approx(f(hx_v, c_v, np.sqrt(eta_v * s_v), r_v), rel=1e-10, abs=1e-14)


def test_printed_xi_is_a_different_function():
    """The printed xi's give an asymmetric function of mu; the silent probability is symmetric."""
    eta, s, r = cs.threshold(1, 2), 3.7, 1.0
    printed = [scipy.stats.norm.cdf(np.sqrt(eta * s - m)) - scipy.stats.norm.cdf(
        -np.sqrt(eta * s - m)) for m in (1.2, -1.2)]
    true = [cs.censored_probability(m, s, r, eta) for m in (1.2, -1.2)]
    assert true[0] == pytest.approx(true[1], rel=1e-14)
    assert abs(printed[0] - printed[1]) > 0.3
    assert abs(printed[0] - true[0]) > 0.01


@pytest.mark.parametrize("l, N", [(1, 2), (0.5, 2), (1.2, 4), (3, 4), (6, 10)])
def test_threshold_closed_forms(l, N):
    """(8): eta = Q^{-1}(l/(2N))^2 for one degree of freedom, 2 ln(N/l) for two."""
    assert cs.threshold(l, N) == pytest.approx(scipy.stats.norm.isf(l / (2 * N)) ** 2, rel=1e-12)
    assert cs.threshold(l, N, dof=2) == pytest.approx(2 * np.log(N / l), rel=1e-12)


@pytest.fixture(scope="module")
def kalman_2state():
    p11, p22, r = sp.symbols("p11 p22 r", positive=True)
    p12 = sp.Symbol("p12", real=True)
    h1, h2, nu = sp.symbols("h1 h2 nu", real=True)
    P = sp.Matrix([[p11, p12], [p12, p22]])
    h = sp.Matrix([h1, h2])
    g = (h.T * P * h)[0, 0]
    s = g + r
    w = P * h / s
    P_post = (P - s * w * w.T).applyfunc(sp.cancel)
    return dict(P=P, h=h, r=r, nu=nu, g=g, s=s, w=w, P_post=P_post,
                P_post_inv=P_post.inv().applyfunc(sp.cancel))


def test_theorem1_kl_is_affine_in_the_nis(kalman_2state):
    """Theorem 1: KL(prior || posterior) = (g/r - ln(1 + g/r))/2 + g/(2r) nu^2/s, g = h^T P h."""
    k = kalman_2state
    g, s, r, nu, w = k["g"], k["s"], k["r"], k["nu"], k["w"]
    assert sp.simplify(sp.cancel(k["P"].det() / k["P_post"].det()) - s / r) == 0
    trace = (k["P_post_inv"] * k["P"]).trace()
    quad = (w.T * k["P_post_inv"] * w)[0, 0] * nu**2
    kl = (trace - 2 + quad - sp.log(s / r)) / 2
    affine = (g / r - sp.log(1 + g / r)) / 2 + g / (2 * r) * nu**2 / s
    assert sp.simplify(sp.expand_log(sp.cancel(sp.together(kl - affine)), force=True)) == 0


def test_corollary2_symmetric_kl_and_eq48_factor(kalman_2state):
    """Corollary 2: the symmetric KL is g^2/(2rs) + g/2 (1/r + 1/s) nu^2/s; (48)'s coefficient
    w^T (P_post^{-1} + P^{-1}) w equals (g/s)(1/r + 1/s), not a constant times 1/s."""
    k = kalman_2state
    g, s, r, nu, w, P = k["g"], k["s"], k["r"], k["nu"], k["w"], k["P"]
    fwd = ((k["P_post_inv"] * P).trace() - 2 + (w.T * k["P_post_inv"] * w)[0, 0] * nu**2) / 2
    rev = ((P.inv() * k["P_post"]).trace() - 2 + (w.T * P.inv() * w)[0, 0] * nu**2) / 2
    target = g**2 / (2 * r * s) + g / 2 * (1 / r + 1 / s) * nu**2 / s
    assert sp.simplify(sp.cancel(sp.together(fwd + rev - target))) == 0
    coef = (w.T * (k["P_post_inv"] + P.inv()) * w)[0, 0]
    assert sp.simplify(sp.cancel(sp.together(coef - g / s * (1 / r + 1 / s)))) == 0


@pytest.mark.parametrize("d", [3, 5])
def test_theorem1_numerically_in_higher_dimension(d):
    rng = np.random.default_rng(d)
    for _ in range(10):
        B = rng.standard_normal((d, d))
        P = B @ B.T + 0.2 * np.eye(d)
        h, r = rng.standard_normal(d), rng.uniform(0.1, 3)
        g = h @ P @ h
        s = g + r
        w = P @ h / s
        nu = rng.normal(0, np.sqrt(s))
        m = rng.standard_normal(d)
        kl = _gaussian_kl(m, P, m + w * nu, P - s * np.outer(w, w))
        assert kl == pytest.approx(0.5 * (g / r - np.log1p(g / r)) + g / (2 * r) * nu**2 / s,
                                   rel=1e-9)


def test_vector_kl_quadratic_term_and_counterexample():
    """Vector case: the quadratic term is nu^T (R^{-1} - S^{-1}) nu, which is not a function of
    the NIS unless H P H^T is proportional to R (Section VII.B model in steady state)."""
    sc = cs.LinearScenario()
    R = np.diag([2.0, 4.0])
    P = scipy.linalg.solve_discrete_are(sc.F.T, np.eye(2), sc.Q, R)
    S = P + R
    W = P @ np.linalg.inv(S)
    P_up = P - W @ S @ W.T
    rng = np.random.default_rng(7)
    for _ in range(5):
        nu = rng.standard_normal(2)
        lhs = nu @ W.T @ np.linalg.inv(P_up) @ W @ nu
        assert lhs == pytest.approx(nu @ (np.linalg.inv(R) - np.linalg.inv(S)) @ nu, rel=1e-10)
    Sh = scipy.linalg.sqrtm(S).real
    eta = cs.threshold(1, 2, dof=2)
    kls = []
    for angle in (0.0, np.pi / 2):
        nu = Sh @ np.array([np.cos(angle), np.sin(angle)]) * np.sqrt(eta)
        assert nu @ np.linalg.solve(S, nu) == pytest.approx(eta, rel=1e-12)
        kls.append(_gaussian_kl(np.zeros(2), P, W @ nu, P_up))
    assert abs(kls[0] - kls[1]) > 0.1


def test_equivalent_kl_threshold_moves_with_k_and_settles():
    """A constant eta corresponds to zeta_k = a_k + b_k eta, which varies with k until the
    local filter reaches the Riccati steady state (Section VII.A model)."""
    sc = cs.LinearScenario()
    g = sc.local_filters()["s"][:, 0] - 1.0
    eta = cs.threshold(1, 2)
    zeta = 0.5 * (g - np.log1p(g)) + g / 2 * eta
    P_inf = scipy.linalg.solve_discrete_are(sc.F.T, sc.H[:1].T, sc.Q, np.array([[1.0]]))
    g_inf = sc.H[0] @ P_inf @ sc.H[0]
    assert g[0] == pytest.approx(1.0)  # P_{1|0} = Q, h^T Q h = sigma^2 / 4
    assert g[-1] == pytest.approx(g_inf, rel=1e-8)
    assert zeta[0] < 0.2 * zeta[-1]
    # the KL rule with the steady-state threshold sends rarely at k = 1
    p1 = scipy.stats.chi2.sf((zeta[-1] - 0.5 * (g[0] - np.log1p(g[0]))) / (g[0] / 2), 1)
    assert p1 < 0.05
