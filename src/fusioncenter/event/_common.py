"""Helpers shared by the modules of :mod:`fusioncenter.event` (the trigger rule, per-sensor
parameters, the checks of a filter's model and number of steps)."""

from __future__ import annotations

import numpy as np

from fusioncenter._validate import finite as _finite
from fusioncenter.kalman import LinearGaussianModel

__all__ = ["per_sensor", "fires", "check_model", "check_steps"]


def per_sensor(name: str, value, m: int, *, positive: bool) -> np.ndarray:
    """A per-sensor parameter: shape ``(m,)`` or a scalar (the same for every sensor)."""
    arr = _finite(name, value)
    if arr.ndim == 0:
        arr = np.full(m, float(arr))
    if arr.shape != (m,):
        raise ValueError(f"{name} must have shape ({m},) (one value per sensor), got {arr.shape}")
    if positive and np.any(arr <= 0):
        raise ValueError(f"{name} must be positive, got {arr}")
    if not positive and np.any(arr < 0):
        raise ValueError(f"{name} must be non-negative (a variance), got {arr}")
    return arr



def fires(xi: np.ndarray, y: np.ndarray, delta: np.ndarray) -> np.ndarray:
    """``gamma = xi > exp(-y^2 / (2 delta))`` (the notes' rule; ``xi <= g`` stays silent)."""
    return xi > np.exp(-(y**2) / (2.0 * delta))


def check_model(model) -> tuple[LinearGaussianModel, np.ndarray]:
    """``(model, r)``: a linear-Gaussian model with a diagonal ``R``, and that diagonal."""
    if not isinstance(model, LinearGaussianModel):
        raise ValueError("model must be a fusioncenter.kalman.LinearGaussianModel "
                         "(e.g. fusioncenter.models.tracking_model())")
    R = model.R
    if np.any(R - np.diag(np.diag(R)) != 0):
        raise ValueError("model.R must be diagonal: the stochastic trigger assumes independent "
                         "sensor noises")
    return model, np.diag(R).copy()


def check_steps(steps) -> int:
    """``steps`` as an ``int``, if it is a non-negative integer (``bool`` refused)."""
    if isinstance(steps, bool) or not isinstance(steps, int | np.integer) or steps < 0:
        raise ValueError(f"steps must be a non-negative integer, got {steps!r}")
    return int(steps)
