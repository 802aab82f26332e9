"""Helpers shared by the modules of :mod:`fusioncenter.event` (the trigger rule, per-sensor
parameters)."""

from __future__ import annotations

import numpy as np

from fusioncenter._validate import finite as _finite

__all__ = ["per_sensor", "fires"]


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
