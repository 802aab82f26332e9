"""The static example of mo2015's chapters 3 and 4 and the closed forms its figures need.

A state ``x ~ N(xbar, Sigma)`` observed by scalar sensors ``y_i = a_i x + v_i`` (the rows
``a_i`` of ``C``), ``v_i ~ N(0, r_i)``; sensor ``i`` sends when the notes' stochastic trigger
fires, ``P(gamma_i = 0 | y_i) = exp(-y_i^2 / (2 delta_i))``. The module gives the joint
probability of a transmission pattern, the exact expected trace of the posterior covariance
under the trigger and under random selection, and the posterior of a centre that simply drops
silent sensors: what the library (:mod:`fusioncenter.event`) does not provide. The entries of
:mod:`fusioncenter.figures.mo2015` use them, and it re-exports them for the chapters; so is
:data:`Z_TOL`, the tolerance of the three entries' checks.
"""

from __future__ import annotations

import itertools

import numpy as np

from fusioncenter import event, riccati
from fusioncenter._docstrings import Glossary

#: A z-score beyond this is a failed check. Under the claim each z is about N(0, 1) and
#: P(|Z| > 4) = 6.3e-5, so the 60-odd z-scores of one entry raise a false alarm with probability
#: below 0.5 %; the power tests show that the same tolerance rejects a wrong claim.
Z_TOL = 4.0

#: The static example of chapters 3 and 4: x ~ N(xbar, Sigma) in R^2, three scalar sensors
#: y_i = a_i x + v_i (the rows of C), v_i ~ N(0, r_i). Sensor 3 measures x_1 + x_2, whose prior
#: mean is 0, so its rate does not depend on xbar; sensors 1 and 2 see means +1 and -1.
EXAMPLE = {
    "xbar": [1.0, -1.0],
    "Sigma": [[2.0, 0.6], [0.6, 1.0]],
    "C": [[1.0, 0.0], [0.0, 1.0], [1.0, 1.0]],
    "r": [0.5, 0.5, 1.0],
}


#: The arguments of the closed forms (``nx`` states, ``m`` sensors); none raises of its own.
document = Glossary("""
xbar : array_like, shape (nx,), optional
    The prior mean of the state (default: zero).
Sigma : array_like, shape (nx, nx)
    The prior covariance of the state.
C : array_like, shape (m, nx)
    The sensors' measurement rows ``a_i``.
r : array_like, shape (m,)
    The sensors' measurement-noise variances ``r_i``.
delta : float or array_like, shape (m,)
    The trigger parameters ``delta_i`` (one value: the same for every sensor).
p : float or array_like, shape (m,)
    The send probabilities of random selection (one value: the same for every sensor).
m : int
    The number of sensors.
gamma : array_like of bool, shape (..., m)
    Transmission patterns (``True``: the sensor sent).
y : array_like, shape (..., m)
    The measurements (those of silent sensors are not used).
rng : numpy.random.Generator
    The source of randomness.
n : int
    The number of independent instances drawn.
""")


def example():
    """``(xbar, Sigma, C, r)`` of :data:`EXAMPLE` as arrays.

    Returns
    -------
    xbar, Sigma, C, r : numpy.ndarray
        The prior mean (2,), the prior covariance (2, 2), the sensors' rows (3, 2) and their
        noise variances (3,).
    """
    return (np.array(EXAMPLE["xbar"]), np.array(EXAMPLE["Sigma"]), np.array(EXAMPLE["C"]),
            np.array(EXAMPLE["r"]))


@document(returns=("numpy.ndarray, shape (m,)", ""))
def output_variances(Sigma, C, r) -> np.ndarray:
    """``s_i = a_i Sigma a_i^T + r_i``: the variance of each sensor's measurement."""
    return np.einsum("ij,jk,ik->i", C, Sigma, C) + np.asarray(r, dtype=float)


# ------------------------------------------------------------------------- closed forms
@document(returns=("float", ""), subset=("sequence of int, optional",
                                          "The sensors (indices from 0); default: all."))
def all_silent_probability(Sigma, C, r, delta, xbar=None, subset=None) -> float:
    """``P(gamma_i = 0 for every i in subset)``; ``subset`` defaults to all sensors.

    ``E prod_i exp(-y_i^2 / (2 delta_i))`` for ``y_S ~ N(mu_S, V_SS)``, ``V = C Sigma C^T + R``,
    is a Gaussian integral: ``det(I + V_SS D^{-1})^{-1/2} exp(-mu_S^T (V_SS + D)^{-1} mu_S / 2)``
    with ``D = diag(delta_S)``. The decisions of sensors with correlated measurements are
    dependent, so this is not the product of the marginal silence probabilities.
    """
    C = np.asarray(C, dtype=float)
    m, n = C.shape
    idx = list(range(m)) if subset is None else list(subset)
    if not idx:
        return 1.0
    xbar = np.zeros(n) if xbar is None else np.asarray(xbar, dtype=float)
    delta = np.broadcast_to(np.asarray(delta, dtype=float), (m,))
    V = C @ np.asarray(Sigma, dtype=float) @ C.T + np.diag(np.asarray(r, dtype=float))
    Vs = V[np.ix_(idx, idx)]
    D = np.diag(delta[idx])
    mu = (C @ xbar)[idx]
    _, logdet = np.linalg.slogdet(np.eye(len(idx)) + Vs / delta[idx][None, :])
    return float(np.exp(-0.5 * logdet - 0.5 * mu @ np.linalg.solve(Vs + D, mu)))


@document(returns=("numpy.ndarray of bool, shape (2**m, m)", ""))
def patterns(m: int) -> np.ndarray:
    """All ``2^m`` transmission patterns, ``(2^m, m)`` booleans, sensor 1 most significant."""
    return np.array(list(itertools.product([False, True], repeat=m)))


@document(returns=("numpy.ndarray of int, shape (...)",
                   "The pattern read as a binary number, sensor 1 the most significant bit."))
def pattern_code(gamma) -> np.ndarray:
    """Index of each pattern in :func:`patterns` (``gamma`` shaped ``(..., m)``)."""
    gamma = np.asarray(gamma, dtype=int)
    m = gamma.shape[-1]
    return gamma @ (2 ** np.arange(m - 1, -1, -1))


@document(returns=("numpy.ndarray, shape (2**m,)",
                   "In the order of :func:`patterns`; they sum to 1."))
def pattern_probabilities(Sigma, C, r, delta, xbar=None) -> np.ndarray:
    """``P(gamma = g)`` for every pattern ``g`` of :func:`patterns`, by inclusion-exclusion.

    ``P(silent on Z, sending on the rest) = E prod_{Z} g_i prod_{not Z} (1 - g_j)``; expanding the
    second product gives a signed sum of :func:`all_silent_probability` over supersets of ``Z``.
    """
    m = np.asarray(C).shape[0]
    cache: dict[tuple, float] = {}

    def q(S):
        key = tuple(sorted(S))
        if key not in cache:
            cache[key] = all_silent_probability(Sigma, C, r, delta, xbar, key)
        return cache[key]

    probs = []
    for g in patterns(m):
        silent = [i for i in range(m) if not g[i]]
        send = [i for i in range(m) if g[i]]
        total = 0.0
        for k in range(len(send) + 1):
            for U in itertools.combinations(send, k):
                total += (-1) ** k * q(silent + list(U))
        probs.append(total)
    return np.array(probs)


@document(returns=("numpy.ndarray, shape (2**m, nx, nx)", "In the order of :func:`patterns`."))
def pattern_covariances(Sigma, C, r, delta) -> np.ndarray:
    """``P(g) = Cov(x | gamma = g, gamma y)`` for every pattern: ``(2^m, nx, nx)``.

    The notes' formula: a silent sensor is a measurement with noise variance ``r_i + delta_i``.
    """
    r = np.asarray(r, dtype=float)
    pats = patterns(len(r))
    noise = r + np.where(pats, 0.0, np.asarray(delta, dtype=float))
    return riccati.measurement_update(np.asarray(Sigma, dtype=float), np.asarray(C, dtype=float),
                                      noise[:, :, None] * np.eye(len(r)))


@document(returns=("numpy.ndarray, shape (2**m, nx, nx)", "In the order of :func:`patterns`."))
def drop_covariances(Sigma, C, r) -> np.ndarray:
    """Posterior covariance when silent sensors are simply dropped, for every pattern."""
    C = np.asarray(C, dtype=float)
    pats = patterns(C.shape[0])
    Ck = C * pats[:, :, None]
    R = np.broadcast_to(np.diag(np.asarray(r, dtype=float)), (len(pats),) + (C.shape[0],) * 2)
    return riccati.measurement_update(np.asarray(Sigma, dtype=float), Ck, R)


@document(returns=("float", ""))
def expected_trace_stochastic(Sigma, C, r, delta, xbar=None) -> float:
    """Exact ``E tr P`` (the MSE of the MMSE estimator) under the stochastic trigger."""
    probs = pattern_probabilities(Sigma, C, r, delta, xbar)
    traces = np.trace(pattern_covariances(Sigma, C, r, delta), axis1=-2, axis2=-1)
    return float(probs @ traces)


@document(returns=("float", ""))
def expected_trace_random(Sigma, C, r, p) -> float:
    """Exact MSE of random selection: sensor ``i`` sends w.p. ``p_i``, independently of all."""
    C = np.asarray(C, dtype=float)
    pats = patterns(C.shape[0])
    p = np.broadcast_to(np.asarray(p, dtype=float), (C.shape[0],))
    probs = np.prod(np.where(pats, p, 1.0 - p), axis=1)
    traces = np.trace(drop_covariances(Sigma, C, r), axis1=-2, axis2=-1)
    return float(probs @ traces)


@document(returns=(("xhat : numpy.ndarray, shape (..., nx)", "The posterior means."),
                   ("P : numpy.ndarray, shape (..., nx, nx)", "The posterior covariances.")),
          xbar=("array_like, shape (nx,)", "The prior mean of the state."))
def drop_posterior(xbar, Sigma, C, r, gamma, y):
    """Posterior mean and covariance of a centre that drops silent sensors (batched).

    Exact when ``gamma`` is independent of ``y`` (random selection); with the stochastic trigger
    it ignores what the silence says, which is the naive estimator of chapter 4.
    """
    C = np.asarray(C, dtype=float)
    gamma = np.asarray(gamma, dtype=bool)
    m = C.shape[0]
    Ck = C * gamma[..., :, None]  # a zero row carries no information
    R = np.broadcast_to(np.diag(np.asarray(r, dtype=float)), gamma.shape[:-1] + (m, m))
    SCt = np.asarray(Sigma, dtype=float) @ np.swapaxes(Ck, -1, -2)
    S = Ck @ SCt + R
    innov = np.where(gamma, y, 0.0) - (Ck @ np.asarray(xbar, dtype=float)[..., None])[..., 0]
    xhat = xbar + (SCt @ np.linalg.solve(S, innov[..., None]))[..., 0]
    return xhat, riccati.measurement_update(Sigma, Ck, R)


@document(returns=(("x : numpy.ndarray, shape (n, 2)", "States drawn from N(xbar, Sigma)."),
                   ("y : numpy.ndarray, shape (n, m)",
                    "Measurements ``C x + v`` of the m sensors, with ``v ~ N(0, diag(r))``."),
                   ("xi : numpy.ndarray, shape (n, m)",
                    "Uniform draws on [0, 1) for the sensors' stochastic triggers.")))
def draw_example(rng: np.random.Generator, n: int):
    """Draw ``n`` independent instances of the state, measurements and trigger uniforms.

    The draws use the example of :func:`example` and are taken in a fixed order (all states
    first, then the measurement noise, then the uniforms), so that results depend only on
    ``rng``'s seed.
    """
    xbar, Sigma, C, r = example()
    x = xbar + rng.standard_normal((n, len(xbar))) @ np.linalg.cholesky(Sigma).T
    y = x @ C.T + rng.standard_normal((n, len(r))) * np.sqrt(r)
    xi = rng.random((n, len(r)))
    return x, y, xi


@document(returns=("numpy.ndarray, shape (n, 5)", ""))
def conditional_chunk(rng: np.random.Generator, n: int, *, delta) -> np.ndarray:
    """The experiment of the conditional-mean chapter ("Is it really the conditional mean?") on
    :data:`EXAMPLE`: ``(n, 5)`` columns ``[pattern code, e_1, e_2, naive e_1, naive e_2]`` with
    ``e = x - E(x | I)`` from the notes' formula and the naive error of a centre that drops
    silent sensors (:func:`drop_posterior`)."""
    xbar, Sigma, C, r = example()
    x, y, _ = draw_example(rng, n)
    g = event.sample_trigger(rng, y, delta)
    xhat, _ = event.posterior(xbar, Sigma, C, r, delta, g, np.where(g, y, np.nan))
    xnaive, _ = drop_posterior(xbar, Sigma, C, r, g, y)
    return np.column_stack([pattern_code(g), x - xhat, x - xnaive])
