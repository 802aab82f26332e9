"""Cross-checks of fusioncenter.event against the SymPy derivations of book/mo2015/derivation.md.

The expressions are derived here as in the chapter: integrate the measurement out of the joint
density of a silent sensor, complete the square in the state, and apply Bayes' rule with the
trigger factor for a transmitting sensor. Each derivation step is asserted, then lambdified and
compared with the library on seeded random inputs: the probability of silence given the state
(``trigger_probability``), the probability of silence (``communication_rate`` with a non-zero
prior mean), and the posterior mean and covariance (``posterior``) for one and two states, one
and two sensors and every pattern of transmissions.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import sympy as sp

from fusioncenter import event

y, u = sp.symbols("y u", real=True)
r, delta = sp.symbols("r delta", positive=True)


def _zero(expr) -> bool:
    def canonical(e):
        return sp.cancel(sp.together(e))

    if isinstance(expr, sp.MatrixBase):
        return sp.simplify(expr.applyfunc(canonical)) == sp.zeros(*expr.shape)
    return sp.simplify(canonical(expr)) == 0


def _tidy_exp(expr):
    return expr.replace(sp.exp, lambda z: sp.exp(sp.factor(z)))


def _complete_square(E, xs):
    """``E(x) = (x - m)^T J (x - m) + const`` for a quadratic ``E``; the identity is asserted."""
    at_zero = {v: 0 for v in xs}
    J = sp.hessian(E, list(xs)) / 2
    b_lin = sp.Matrix([sp.diff(E, v) for v in xs]).subs(at_zero)
    m = (-J.inv() * b_lin / 2).applyfunc(sp.cancel)
    const = sp.cancel(E.subs(at_zero) - (m.T * J * m)[0, 0])
    d = xs - m
    assert _zero(E - ((d.T * J * d)[0, 0] + const))
    return J, m, const


def _example(n: int):
    if n == 1:
        x = sp.Matrix([sp.Symbol("x", real=True)])
        xbar = sp.Matrix([sp.Symbol("xbar", real=True)])
        Sigma = sp.Matrix([[sp.Symbol("Sigma", positive=True)]])
        a = sp.Matrix([[sp.Symbol("a", real=True)]])
    else:
        x = sp.Matrix(sp.symbols("x1 x2", real=True))
        xbar = sp.Matrix(sp.symbols("xbar1 xbar2", real=True))
        s11, s22 = sp.symbols("s11 s22", positive=True)
        s12 = sp.Symbol("s12", real=True)
        Sigma = sp.Matrix([[s11, s12], [s12, s22]])
        a = sp.Matrix([sp.symbols("a1 a2", real=True)])
    return x, xbar, Sigma, a


@pytest.fixture(scope="module")
def silence_given_state():
    """Steps 2-3: int N(y; u, r) exp(-y^2 / (2 delta)) dy, with u = a x, by the notes' square."""
    c_y = sp.sqrt((r + delta) / (r * delta))
    c_u = sp.sqrt(delta / (r * (r + delta)))
    exponent = (y - u) ** 2 / r + y**2 / delta
    assert sp.simplify(exponent - ((c_y * y - c_u * u) ** 2 + u**2 / (r + delta))) == 0
    t = sp.Symbol("t", real=True)  # t = c_y y - c_u u, dy = dt / c_y
    gauss = sp.integrate(sp.exp(-(t**2) / 2), (t, -sp.oo, sp.oo)) / c_y
    integral = gauss * sp.exp(-(u**2) / (2 * (r + delta))) / sp.sqrt(2 * sp.pi * r)
    claim = sp.sqrt(delta / (r + delta)) * sp.exp(-(u**2) / (2 * (r + delta)))
    assert sp.simplify(integral - claim) == 0
    return claim


@pytest.fixture(scope="module")
def single_sensor():
    """Steps 4-7 for n = 1 and n = 2: posterior after a silence and after a transmission."""
    out = {}
    for n in (1, 2):
        x, xbar, Sigma, a = _example(n)
        ax = (a * x)[0, 0]
        prior = ((x - xbar).T * Sigma.inv() * (x - xbar))[0, 0]
        J0, m0, _ = _complete_square(prior + ax**2 / (r + delta), x)
        J1, m1, _ = _complete_square(prior + (y - ax) ** 2 / r, x)
        s = (a * Sigma * a.T)[0, 0] + r
        mu = (a * xbar)[0, 0]
        gamma = sp.Symbol("gamma")
        noise = r + (1 - gamma) * delta
        x_uni = xbar + Sigma * a.T * (gamma * y - mu) / (s - r + noise)
        for gv, m_case in ((0, m0), (1, m1)):
            assert _zero(x_uni.subs(gamma, gv) - m_case)
        out[n] = {"symbols": (xbar, Sigma, a), "silent": (m0, J0.inv()),
                  "sent": (m1, J1.inv()), "unified": (x_uni, (Sigma.inv() + a.T * a / noise).inv()),
                  "gamma": gamma}
    return out


def _free(xbar, Sigma, a):
    """The free symbols of an example, in a fixed order (Sigma's upper triangle)."""
    n = Sigma.shape[0]
    sig = [Sigma[i, j] for i in range(n) for j in range(i, n)]
    return list(xbar) + sig + list(a)


def _random_args(rng, n: int, k: int):
    """k random (xbar, Sigma, a, r, delta, y) for an n-state, one-sensor problem."""
    xbar = rng.standard_normal((k, n))
    B = rng.standard_normal((k, n, n))
    Sigma = B @ np.swapaxes(B, -1, -2) + 0.3 * np.eye(n)
    a = rng.standard_normal((k, 1, n))
    r_v = rng.uniform(0.05, 5.0, k)
    d_v = rng.uniform(0.05, 10.0, k)
    y_v = rng.normal(0.0, 3.0, k)
    return xbar, Sigma, a, r_v, d_v, y_v


def _flat(xbar, Sigma, a):
    n = Sigma.shape[-1]
    sig = [Sigma[:, i, j] for i in range(n) for j in range(i, n)]
    return [xbar[:, i] for i in range(n)] + sig + [a[:, 0, i] for i in range(n)]


def test_silence_probability_given_the_state_matches_trigger_probability(silence_given_state):
    fn = sp.lambdify((u, r, delta), silence_given_state, "numpy")
    rng = np.random.default_rng(2015)
    u_v = rng.normal(0.0, 3.0, 2000)
    r_v = rng.uniform(1e-3, 10.0, 2000)
    d_v = rng.uniform(1e-3, 50.0, 2000)
    # given x, y ~ N(a x, r): P(silent | x) = 1 - P(send) for a sensor with mean u, variance r
    lib = 1.0 - event.trigger_probability(r_v, d_v, u_v)
    assert np.max(np.abs(fn(u_v, r_v, d_v) - lib)) < 1e-13


def test_probability_of_silence_with_nonzero_mean_matches_communication_rate(silence_given_state):
    """Step 5 for n = 1: integrate P(silent | x) against the prior, including xbar != 0.

    The exponent of prior times likelihood is completed to a square in x; the Gaussian integral
    leaves sqrt(2 pi P_tilde) times exp(-c0 / 2).
    """
    x, xbar, a = sp.symbols("x xbar a", real=True)
    sig = sp.Symbol("Sigma", positive=True)
    E = (x - xbar) ** 2 / sig + (a * x) ** 2 / (r + delta)
    J, _, c0 = _complete_square(E, sp.Matrix([x]))
    prefactor = silence_given_state.subs(u, 0) / sp.sqrt(2 * sp.pi * sig)
    # int exp(-J (x - m)^2 / 2) dx = sqrt(2 pi / J)
    p_silent = prefactor * sp.sqrt(2 * sp.pi / J[0, 0]) * sp.exp(-c0 / 2)
    s = a**2 * sig + r
    claim = sp.sqrt(delta / (s + delta)) * sp.exp(-(a * xbar) ** 2 / (2 * (s + delta)))
    assert sp.simplify(_tidy_exp(sp.simplify(p_silent)) - _tidy_exp(claim)) == 0
    fn = sp.lambdify((xbar, sig, a, r, delta), claim, "numpy")
    rng = np.random.default_rng(2016)
    for _ in range(200):
        xb, sg, av = rng.normal(0, 2), rng.uniform(0.05, 5), rng.normal(0, 2)
        rv, dv = rng.uniform(0.05, 5), rng.uniform(0.05, 10)
        lib = event.communication_rate([[sg]], [[av]], [rv], [dv], xbar=[xb])[0]
        assert abs((1.0 - lib) - fn(xb, sg, av, rv, dv)) < 1e-13


@pytest.mark.parametrize("n", [1, 2])
@pytest.mark.parametrize("case", ["silent", "sent", "unified"])
def test_single_sensor_posterior_matches_library(single_sensor, n, case):
    ex = single_sensor[n]
    free = _free(*ex["symbols"])
    mean, cov = ex[case]
    args = (*free, r, delta, y, ex["gamma"])
    mean_fn = sp.lambdify(args, list(mean), "numpy")
    cov_fn = sp.lambdify(args, [cov[i, j] for i in range(n) for j in range(n)], "numpy")
    rng = np.random.default_rng(300 + 10 * n + ["silent", "sent", "unified"].index(case))
    k_inst = 150
    xbar, Sigma, a, r_v, d_v, y_v = _random_args(rng, n, k_inst)
    g_v = {"silent": np.zeros(k_inst, int), "sent": np.ones(k_inst, int),
           "unified": rng.integers(0, 2, k_inst)}[case]
    means = np.array(mean_fn(*_flat(xbar, Sigma, a), r_v, d_v, y_v, g_v), dtype=float).T
    covs = np.array(cov_fn(*_flat(xbar, Sigma, a), r_v, d_v, y_v, g_v), dtype=float).T
    for k in range(k_inst):  # the library takes one (C, r, delta) per call
        y_in = [y_v[k] if g_v[k] else np.nan]
        xhat, P = event.posterior(xbar[k], Sigma[k], a[k], r_v[k:k + 1], d_v[k:k + 1],
                                  [g_v[k]], y_in)
        scale = max(1.0, np.abs(xhat).max())
        assert np.max(np.abs(means[k] - xhat)) < 1e-10 * scale
        assert np.max(np.abs(covs[k].reshape(n, n) - P)) < 1e-10 * max(1.0, np.abs(P).max())


@pytest.fixture(scope="module")
def two_sensors():
    """Step 8 for a scalar state and two sensors: completed square for each pattern.

    The symbolic result is compared with the information form; the library evaluates the gain
    form, so the numerical comparison below also checks the matrix inversion lemma.
    """
    x = sp.Matrix([sp.Symbol("x", real=True)])
    xbar, sig = sp.Symbol("xbar", real=True), sp.Symbol("Sigma", positive=True)
    a_s = sp.symbols("a1 a2", real=True)
    y_s = sp.symbols("y1 y2", real=True)
    r_s = sp.symbols("r1 r2", positive=True)
    d_s = sp.symbols("delta1 delta2", positive=True)
    out = {}
    for pattern in itertools.product([0, 1], repeat=2):
        E = (x[0] - xbar) ** 2 / sig
        for gv, a_k, y_k, r_k, d_k in zip(pattern, a_s, y_s, r_s, d_s, strict=True):
            E += (y_k - a_k * x[0]) ** 2 / r_k if gv else (a_k * x[0]) ** 2 / (r_k + d_k)
        J, m, _ = _complete_square(E, x)
        # the theorem's information form: a silent sensor reports 0 with variance r + delta
        noise = [r_k + (1 - gv) * d_k for gv, r_k, d_k in zip(pattern, r_s, d_s, strict=True)]
        info = 1 / sig + sum(a_k**2 / v for a_k, v in zip(a_s, noise, strict=True))
        vec = xbar / sig + sum(a_k * gv * y_k / v
                               for a_k, gv, y_k, v in zip(a_s, pattern, y_s, noise, strict=True))
        assert _zero(J[0, 0] - info)
        assert _zero(m[0, 0] - vec / info)
        out[pattern] = (m[0, 0], J.inv()[0, 0])
    return (xbar, sig, *a_s, *r_s, *d_s, *y_s), out


def test_two_sensor_posterior_matches_library(two_sensors):
    args, by_pattern = two_sensors
    rng = np.random.default_rng(400)
    k_inst = 100
    xb = rng.normal(0, 2, k_inst)
    sg = rng.uniform(0.05, 5, k_inst)
    a_v = rng.normal(0, 2, (k_inst, 2))
    r_v = rng.uniform(0.05, 5, (k_inst, 2))
    d_v = rng.uniform(0.05, 10, (k_inst, 2))
    y_v = rng.normal(0, 3, (k_inst, 2))
    values = (xb, sg, a_v[:, 0], a_v[:, 1], r_v[:, 0], r_v[:, 1], d_v[:, 0], d_v[:, 1],
              y_v[:, 0], y_v[:, 1])
    for pattern, (mean, var) in by_pattern.items():
        mean_fn = sp.lambdify(args, mean, "numpy")
        var_fn = sp.lambdify(args, var, "numpy")
        means, vars_ = mean_fn(*values), var_fn(*values)
        gam = np.array(pattern)
        for k in range(k_inst):
            xhat, P = event.posterior([xb[k]], [[sg[k]]], a_v[k][:, None], r_v[k], d_v[k], gam,
                                      np.where(gam == 1, y_v[k], np.nan))
            assert abs(means[k] - xhat[0]) < 1e-10 * max(1.0, abs(xhat[0]))
            assert abs(vars_[k] - P[0, 0]) < 1e-10 * max(1.0, P[0, 0])


def test_silent_values_never_enter_the_derived_mean(single_sensor):
    """The unified mean depends on y only through gamma * y: at gamma = 0, d/dy = 0."""
    for n in (1, 2):
        mean = single_sensor[n]["unified"][0].subs(single_sensor[n]["gamma"], 0)
        assert mean.diff(y) == sp.zeros(n, 1)
