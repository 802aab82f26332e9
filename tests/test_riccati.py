"""Riccati recursions: closed forms, invariants (hypothesis), batching, and input checks."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg
from hypothesis import given, settings
from hypothesis import strategies as st

from fusioncenter import riccati

pos = st.floats(0.05, 20.0)
gain = st.floats(-3.0, 3.0).filter(lambda c: abs(c) > 0.05)


@given(p=pos, a=st.floats(-2.0, 2.0), q=pos, c=gain, r=pos)
def test_scalar_step_matches_textbook_form(p, a, q, c, r):
    textbook = a**2 * (p - p**2 * c**2 / (c**2 * p + r)) + q
    assert riccati.scalar_step(p, a, q, c, r) == pytest.approx(textbook, rel=1e-10)


@given(a=st.floats(-2.0, 2.0), q=pos, c=gain, r=pos)
def test_scalar_steady_state_is_positive_fixed_point(a, q, c, r):
    p = riccati.scalar_steady_state(a, q, c, r)
    assert p > 0
    assert riccati.scalar_step(p, a, q, c, r) == pytest.approx(p, rel=1e-9)
    dare = scipy.linalg.solve_discrete_are([[a]], [[c]], [[q]], [[r]])[0, 0]
    assert p == pytest.approx(dare, rel=1e-7)


def test_scalar_steady_state_without_measurements():
    assert riccati.scalar_steady_state(0.5, 1.0, 0.0, 1.0) == pytest.approx(1 / 0.75)
    for a in (1.5, 1.0, -1.0):  # no information and |a| >= 1: no steady state (never inf)
        with pytest.raises(ValueError, match="^no steady state: c = 0"):
            riccati.scalar_steady_state(a, 1.0, 0.0, 1.0)
    with pytest.raises(ValueError, match="^no steady state"):  # one element of an array
        riccati.scalar_steady_state(np.array([0.5, 2.0]), 1.0, 0.0, 1.0)


def test_scalar_sequence_broadcasts_and_converges():
    a = np.array([0.5, 1.25])
    seq = riccati.scalar_sequence(0.0, a, 1.0, 1.0, 4.0, 60)
    assert seq.shape == (61, 2)
    assert np.allclose(seq[-1], riccati.scalar_steady_state(a, 1.0, 1.0, 4.0), rtol=1e-10)


def _spd(rng, n, scale=1.0):
    M = rng.standard_normal((n, n))
    return scale * (M @ M.T + n * np.eye(n))


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 4), m=st.integers(1, 3))
def test_measurement_update_information_form_and_psd(seed, n, m):
    rng = np.random.default_rng(seed)
    P, R = _spd(rng, n), _spd(rng, m)
    C = rng.standard_normal((m, n))
    post = riccati.measurement_update(P, C, R)
    info = np.linalg.inv(np.linalg.inv(P) + C.T @ np.linalg.solve(R, C))
    assert np.allclose(post, info, rtol=1e-8, atol=1e-10)
    assert np.array_equal(post, post.T)
    assert np.linalg.eigvalsh(post).min() > -1e-12
    # the update never increases uncertainty: P - post is PSD
    assert np.linalg.eigvalsh(P - post).min() > -1e-9 * np.abs(P).max()


def test_matrix_recursion_agrees_with_scalar():
    seq = riccati.riccati_sequence([[0.0]], [[1.25]], [[1.0]], [[1.0]], [[4.0]], 20)
    ref = riccati.scalar_sequence(0.0, 1.25, 1.0, 1.0, 4.0, 20)
    assert np.allclose(seq[:, 0, 0], ref, rtol=1e-13)


def test_batched_random_gains_match_a_loop():
    rng = np.random.default_rng(0)
    steps, batch = 15, 7
    C = rng.standard_normal((steps, batch, 1, 2))
    R = np.broadcast_to(np.eye(1) * 2.0, (steps, batch, 1, 1))
    A = np.array([[1.0, 1.0], [0.0, 1.0]])
    Q = np.eye(2) * 0.1
    P0 = np.broadcast_to(np.eye(2), (batch, 2, 2))
    batched = riccati.riccati_sequence(P0, A, Q, C, R, steps, time_varying=True)
    assert batched.shape == (steps + 1, batch, 2, 2)
    for b in range(batch):
        P = np.eye(2)
        for k in range(steps):
            S = C[k, b] @ P @ C[k, b].T + R[k, b]
            P = A @ (P - P @ C[k, b].T @ np.linalg.solve(S, C[k, b] @ P)) @ A.T + Q
            assert np.allclose(batched[k + 1, b], P, rtol=1e-12, atol=1e-14)


def test_steady_state_matches_long_recursion():
    A = np.array([[1.0, 1.0], [0.0, 1.0]])
    Q = np.diag([0.1, 0.2])
    C = np.array([[1.0, 0.0]])
    R = np.array([[2.0]])
    P = riccati.riccati_sequence(np.eye(2), A, Q, C, R, 200)[-1]
    assert np.allclose(riccati.steady_state(A, Q, C, R), P, rtol=1e-9)


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: riccati.scalar_update(-1.0, 1.0, 1.0), "p must be non-negative"),
        (lambda: riccati.scalar_update(1.0, 1.0, -1.0), "r must be non-negative"),
        (lambda: riccati.scalar_step(1.0, 1.0, -1.0, 1.0, 1.0), "q must be non-negative"),
        (lambda: riccati.scalar_sequence(1.0, 1.0, 1.0, 1.0, 1.0, -1), "steps"),
        (lambda: riccati.measurement_update(np.eye(2), np.ones((1, 3)), np.eye(1)), "columns"),
        (lambda: riccati.measurement_update(np.eye(2), np.ones((1, 2)), np.eye(2)), "rows"),
        (lambda: riccati.measurement_update(np.ones((2, 3)), np.ones((1, 3)), np.eye(1)),
         "square"),
        (lambda: riccati.riccati_step(np.eye(2), np.ones((2, 3)), np.eye(2), np.ones((1, 2)),
                                      np.eye(1)), "A must be square"),
        (lambda: riccati.riccati_sequence(np.eye(2), np.eye(2), np.eye(2), np.ones((1, 2)),
                                          np.eye(1), 3, time_varying=True), "time_varying"),
        (lambda: riccati.steady_state([[2.0]], [[1.0]], [[0.0]], [[1.0]]), "stabilizing"),
    ],
)
def test_bad_input_raises_value_error(call, match):
    with pytest.raises(ValueError, match=match):
        call()
