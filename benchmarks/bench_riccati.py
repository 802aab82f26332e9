"""Batched Riccati recursion (one call advances every Monte Carlo path) vs a plain Python loop.

Workload: a 2-state system observed through a random scalar gain per path and step (as over a
fading channel), 2000 paths x 50 steps. The loop baseline advances one path at a time with the
same formulas; both results are checked equal before timing.
"""

from __future__ import annotations

import numpy as np

from fusioncenter import riccati

PATHS, STEPS = 2000, 50
A = np.array([[1.0, 1.0], [0.0, 1.0]])
Q = np.diag([0.1, 0.2])
R = np.array([[1.0]])
_rng = np.random.default_rng(0)
GAINS = _rng.exponential(size=(STEPS, PATHS))
C = GAINS[..., None, None] * np.array([[1.0, 0.0]])  # (steps, paths, 1, 2)


def loop() -> np.ndarray:
    out = np.empty((PATHS, 2, 2))
    for b in range(PATHS):
        P = np.eye(2)
        for k in range(STEPS):
            c = C[k, b]
            S = c @ P @ c.T + R
            P = A @ (P - P @ c.T @ np.linalg.solve(S, c @ P)) @ A.T + Q
        out[b] = P
    return out


def batched() -> np.ndarray:
    P0 = np.broadcast_to(np.eye(2), (PATHS, 2, 2))
    Rb = np.broadcast_to(R, (STEPS, PATHS, 1, 1))
    return riccati.riccati_sequence(P0, A, Q, C, Rb, STEPS, time_varying=True)[-1]


def _checked(fn):
    def setup():
        assert np.allclose(fn(), loop_result, rtol=1e-10, atol=1e-12)
        return fn
    return setup


loop_result = loop()
REPEATS = 5
CASES = [
    ("riccati 2000 paths x 50 steps", "python loop over paths", _checked(loop)),
    ("riccati 2000 paths x 50 steps", "batched (fusioncenter.riccati)", _checked(batched)),
]
