"""Cross-checks of fusioncenter.riccati against the Background chapter's SymPy derivations.

The expressions are derived here the same way as in book/background/kalman-riccati.md (completing
the square, composing the time update, solving the fixed-point equation), lambdified, and compared
with the library on seeded random inputs, including unstable systems (|a| > 1).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg
import sympy as sp

from fusioncenter import riccati

x, m, y = sp.symbols("x m y", real=True)
a, c = sp.symbols("a c", real=True)
p, q, r = sp.symbols("p q r", positive=True)
pbar = sp.Symbol("pbar", real=True)


@pytest.fixture(scope="module")
def derived():
    """The chapter's derivations, each step asserted, returned as SymPy expressions."""
    E = (x - m) ** 2 / p + (y - c * x) ** 2 / r
    poly = sp.Poly(sp.expand(E), x)
    alpha = poly.coeff_monomial(x**2)
    mu = -poly.coeff_monomial(x) / (2 * alpha)
    assert sp.simplify(E - (alpha * (x - mu) ** 2 + E.subs(x, mu))) == 0
    update = 1 / alpha
    assert sp.simplify(update - p * r / (c**2 * p + r)) == 0
    assert sp.simplify(update - (p - p**2 * c**2 / (c**2 * p + r))) == 0

    step = a**2 * update + q
    roots = sp.solve(sp.Eq(step.subs(p, pbar), pbar), pbar)
    assert len(roots) == 2
    b = r * (1 - a**2) - q * c**2
    quadratic = c**2 * pbar**2 + b * pbar - q * r
    assert sp.simplify((step.subs(p, pbar) - pbar) * (c**2 * pbar + r) + quadratic) == 0
    assert sp.simplify(roots[0] * roots[1] + q * r / c**2) == 0
    positive = (-b + sp.sqrt(b**2 + 4 * c**2 * q * r)) / (2 * c**2)
    assert any(sp.simplify(root - positive) == 0 for root in roots)
    return {"update": update, "step": step, "steady": positive}


def _scalar_params(rng: np.random.Generator, n: int):
    a_s = rng.uniform(-2.0, 2.0, n)  # about half unstable
    q_s = rng.uniform(0.05, 5.0, n)
    c_s = rng.uniform(0.1, 3.0, n) * rng.choice([-1.0, 1.0], n)
    r_s = rng.uniform(0.05, 5.0, n)
    return a_s, q_s, c_s, r_s


def test_scalar_update_matches_derivation(derived):
    fn = sp.lambdify((p, c, r), derived["update"], "numpy")
    rng = np.random.default_rng(101)
    p_s = rng.uniform(1e-3, 1e3, 2000)
    c_s = rng.normal(0, 3, 2000)
    r_s = rng.uniform(1e-3, 1e3, 2000)
    np.testing.assert_allclose(riccati.scalar_update(p_s, c_s, r_s), fn(p_s, c_s, r_s),
                               rtol=1e-12, atol=0)


def test_scalar_step_matches_derivation(derived):
    fn = sp.lambdify((p, a, q, c, r), derived["step"], "numpy")
    rng = np.random.default_rng(102)
    a_s, q_s, c_s, r_s = _scalar_params(rng, 2000)
    p_s = rng.uniform(1e-3, 1e2, 2000)
    np.testing.assert_allclose(riccati.scalar_step(p_s, a_s, q_s, c_s, r_s),
                               fn(p_s, a_s, q_s, c_s, r_s), rtol=1e-12, atol=0)


def test_scalar_steady_state_matches_derivation(derived):
    fn = sp.lambdify((a, q, c, r), derived["steady"], "numpy")
    rng = np.random.default_rng(103)
    a_s, q_s, c_s, r_s = _scalar_params(rng, 2000)
    assert np.sum(np.abs(a_s) > 1) > 500
    lib = riccati.scalar_steady_state(a_s, q_s, c_s, r_s)
    assert np.all(lib > 0)
    np.testing.assert_allclose(lib, fn(a_s, q_s, c_s, r_s), rtol=1e-10, atol=0)
    # and it is a fixed point of the library's own step
    np.testing.assert_allclose(riccati.scalar_step(lib, a_s, q_s, c_s, r_s), lib, rtol=1e-12)


def test_scalar_steady_state_matches_scipy_dare():
    rng = np.random.default_rng(104)
    for a_i, q_i, c_i, r_i in zip(*_scalar_params(rng, 100), strict=True):
        dare = scipy.linalg.solve_discrete_are(np.array([[a_i]]), np.array([[c_i]]),
                                               np.array([[q_i]]), np.array([[r_i]]))[0, 0]
        assert riccati.scalar_steady_state(a_i, q_i, c_i, r_i) == pytest.approx(dare, rel=1e-10)


def test_scalar_steady_state_is_accurate_without_cancellation():
    """Small q with a stable a: the textbook root cancels; the library must not."""
    a_s, c_s, r_s = 0.5, 1.0, 1.0
    for q_s in (1e-8, 1e-12, 1e-16):
        # p = q r / (r (1 - a^2) - q c^2) + O(q^2), so q / (1 - a^2) to relative O(q)
        assert riccati.scalar_steady_state(a_s, q_s, c_s, r_s) == pytest.approx(
            q_s / (1 - a_s**2), rel=1e-6)


def test_scalar_steady_state_limits(derived):
    assert sp.simplify(sp.limit(derived["steady"], r, 0) - q) == 0
    assert riccati.scalar_steady_state(0.5, 2.0, 0.0, 1.0) == pytest.approx(2.0 / 0.75, rel=1e-14)
    with pytest.raises(ValueError, match="^no steady state"):  # the limit is inf: refused
        riccati.scalar_steady_state(1.5, 2.0, 0.0, 1.0)


def test_matrix_inversion_lemma_symbolic():
    p11, p12, p22 = sp.symbols("p11 p12 p22", real=True)
    c1, c2 = sp.symbols("c1 c2", real=True)
    P = sp.Matrix([[p11, p12], [p12, p22]])
    C = sp.Matrix([[c1, c2]])
    R = sp.Matrix([[r]])
    info = (P.inv() + C.T * R.inv() * C).inv()
    cov = P - P * C.T * (C * P * C.T + R).inv() * C * P
    assert sp.simplify(info - cov) == sp.zeros(2, 2)


def _spd(rng: np.random.Generator, n: int) -> np.ndarray:
    B = rng.normal(size=(n, n))
    return B @ B.T + 0.1 * np.eye(n)


@pytest.mark.parametrize(("n", "k"), [(1, 1), (2, 1), (3, 2), (4, 3), (5, 5), (6, 2)])
def test_measurement_update_equals_information_form(n, k):
    rng = np.random.default_rng(1000 + 10 * n + k)
    for _ in range(25):
        P, R = _spd(rng, n), _spd(rng, k)
        C = rng.normal(size=(k, n))
        info = np.linalg.inv(np.linalg.inv(P) + C.T @ np.linalg.solve(R, C))
        got = riccati.measurement_update(P, C, R)
        np.testing.assert_allclose(got, info, rtol=0, atol=1e-10 * max(1.0, np.abs(info).max()))
        np.testing.assert_array_equal(got, got.T)


def test_measurement_update_batched_equals_information_form():
    rng = np.random.default_rng(2000)
    n, k, batch = 3, 2, 40
    P = np.stack([_spd(rng, n) for _ in range(batch)])
    R = np.stack([_spd(rng, k) for _ in range(batch)])
    C = rng.normal(size=(batch, k, n))
    info = np.linalg.inv(np.linalg.inv(P) + np.swapaxes(C, -1, -2) @ np.linalg.solve(R, C))
    np.testing.assert_allclose(riccati.measurement_update(P, C, R), info, rtol=0, atol=1e-9)


def test_scalar_functions_agree_with_matrix_functions():
    rng = np.random.default_rng(3000)
    a_s, q_s, c_s, r_s = _scalar_params(rng, 50)
    p_s = rng.uniform(0.01, 10, 50)
    for args in zip(p_s, a_s, q_s, c_s, r_s, strict=True):
        p_i, a_i, q_i, c_i, r_i = args
        mat = riccati.riccati_step([[p_i]], [[a_i]], [[q_i]], [[c_i]], [[r_i]])[0, 0]
        assert riccati.scalar_step(*args) == pytest.approx(mat, rel=1e-12)
        mat_ss = riccati.steady_state([[a_i]], [[q_i]], [[c_i]], [[r_i]])[0, 0]
        assert riccati.scalar_steady_state(a_i, q_i, c_i, r_i) == pytest.approx(mat_ss, rel=1e-10)
