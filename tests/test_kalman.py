"""The vectorized Kalman filter against filterpy, and the model's input checks."""

from __future__ import annotations

import numpy as np
import pytest
from filterpy.kalman import KalmanFilter

from fusioncenter import riccati
from fusioncenter.kalman import LinearGaussianModel, constant_velocity


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
