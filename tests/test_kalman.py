"""The vectorized Kalman filter against filterpy, and the model's input checks."""

from __future__ import annotations

import numpy as np
import pytest
from filterpy.kalman import KalmanFilter

from fusioncenter import riccati
from fusioncenter.kalman import LinearGaussianModel, constant_velocity, kalman_step


def test_vectorized_filter_equals_filterpy_trial_by_trial():
    model = constant_velocity(q=0.3, r=2.0)
    rng = np.random.default_rng(11)
    x, y = model.sample(rng, 5, 25)
    xhat, P = model.filter(y)
    for t in range(5):
        kf = KalmanFilter(dim_x=2, dim_z=1)
        kf.F, kf.Q, kf.H, kf.R = model.A, model.Q, model.C, model.R
        kf.x, kf.P = model.m0.reshape(-1, 1).copy(), model.P0.copy()
        for k in range(26):
            if k:
                kf.predict()
            kf.update(y[t, k].reshape(-1, 1))
            assert np.allclose(kf.x.ravel(), xhat[t, k], rtol=1e-10, atol=1e-12)
            assert np.allclose(kf.P, P[k], rtol=1e-10, atol=1e-12)


def test_filter_covariance_is_the_riccati_recursion():
    model = constant_velocity(q=0.3, r=2.0)
    _, P_post = model.filter(np.zeros((1, 11, 1)))
    P_pred = riccati.riccati_sequence(model.P0, model.A, model.Q, model.C, model.R, 10)
    for k in range(11):
        assert np.allclose(P_post[k], riccati.measurement_update(P_pred[k], model.C, model.R))


def test_sample_shapes_and_statistics():
    model = constant_velocity(q=0.0, r=1.0, m0=(0.0, 1.0), P0=np.zeros((2, 2)))
    x, y = model.sample(np.random.default_rng(0), 4000, 3)
    assert x.shape == (4000, 4, 2) and y.shape == (4000, 4, 1)
    assert np.allclose(x[:, 3], [3.0, 1.0])  # no process noise, known start
    resid = y[..., 0] - x[..., 0]
    assert abs(resid.var() - 1.0) < 0.05


@pytest.mark.parametrize(
    "change, match",
    [
        ({"A": np.ones((2, 3))}, "A must be square"),
        ({"C": np.ones((1, 3))}, "C must have 2 columns"),
        ({"Q": np.array([[1.0, 2.0], [0.0, 1.0]])}, "Q must be symmetric"),
        ({"R": np.array([[-1.0]])}, "R must be positive semi-definite"),
        ({"R": np.array([[np.nan]])}, "R must be finite"),
        ({"P0": -np.eye(2)}, "P0 must be positive semi-definite"),
        ({"m0": np.zeros(3)}, "m0 must have length 2"),
    ],
)
def test_model_validation(change, match):
    base = dict(A=np.eye(2), Q=np.eye(2), C=np.array([[1.0, 0.0]]), R=np.eye(1),
                m0=np.zeros(2), P0=np.eye(2))
    with pytest.raises(ValueError, match=match):
        LinearGaussianModel(**{**base, **change})


def test_constant_velocity_validation():
    with pytest.raises(ValueError, match="dt"):
        constant_velocity(dt=0)
    with pytest.raises(ValueError, match="r must be non-negative"):
        constant_velocity(r=-1.0)
    with pytest.raises(ValueError, match="q must be finite"):
        constant_velocity(q=np.nan)


def test_kalman_step_shared_and_per_trial_forms_agree():
    """The two arithmetic forms of the one step (gain shared by the trials, or a solve per
    trial) are the same update up to rounding."""
    model = constant_velocity(q=0.3, r=2.0)
    rng = np.random.default_rng(3)
    x = rng.standard_normal((6, 2))
    innov = rng.standard_normal((6, 1))
    shared = kalman_step(x, model.P0, innov, model.C, model.R, model.A, model.Q)
    per = kalman_step(x, np.broadcast_to(model.P0, (6, 2, 2)), innov,
                      np.broadcast_to(model.C, (6, 1, 2)), np.broadcast_to(model.R, (6, 1, 1)),
                      model.A, model.Q)
    for a, b in zip(shared, per, strict=True):
        assert np.allclose(np.broadcast_to(a, b.shape), b, rtol=1e-12, atol=1e-14)
    assert np.allclose(shared.x_pred, shared.x_post @ model.A.T)


def test_kalman_step_zero_row_drops_the_sensor():
    """A zero row of C_k (and a zero innovation) is the update without that sensor."""
    A, Q = np.array([[1.0, 1.0], [0.0, 1.0]]), 0.1 * np.eye(2)
    C, R = np.array([[1.0, 0.0], [0.5, 1.0]]), np.diag([1.0, 2.0])
    P = np.broadcast_to(np.array([[2.0, 0.3], [0.3, 1.0]]), (2, 2, 2))
    x = np.array([[0.0, 1.0], [1.0, -1.0]])
    innov = np.array([[0.7, 0.0], [0.7, -0.2]])
    Ck = np.stack([C * [[1.0], [0.0]], C])  # trial 0 drops sensor 2
    out = kalman_step(x, P, innov, Ck, np.broadcast_to(R, (2, 2, 2)), A, Q)
    alone = kalman_step(x[:1], P[0], innov[:1, :1], C[:1], R[:1, :1], A, Q)
    assert np.allclose(out.x_post[0], alone.x_post[0])
    assert np.allclose(out.P_post[0], alone.P_post)
    assert np.allclose(out.P_pred[0], alone.P_pred)


def test_zheng2014_letters_are_aliases():
    model = constant_velocity()
    assert model.F is model.A and model.H is model.C
