"""The checks of the Riccati recursions' arguments shared by their modules (a step count, a
stack of matrices and its shapes), and the symmetrization of a computed covariance."""

from __future__ import annotations

import numpy as np

from fusioncenter import _validate as _v


def steps_arg(steps) -> int:
    """``steps`` as an ``int``, or a ``ValueError`` if it is not a non-negative integer."""
    if isinstance(steps, bool):
        raise ValueError(f"steps must be a non-negative integer, got {steps!r}")
    try:
        ok = int(steps) == steps and steps >= 0
    except (TypeError, ValueError, OverflowError):
        ok = False
    if not ok:
        raise ValueError(f"steps must be a non-negative integer, got {steps!r}")
    return int(steps)



def as_matrix(name: str, value, ndim_min: int = 2) -> np.ndarray:
    """``value`` as a finite float array of at least ``ndim_min`` axes (``..., rows, cols``)."""
    arr = _v.finite(name, value)
    if arr.ndim < ndim_min:
        raise ValueError(f"{name} must be at least {ndim_min}-D (..., rows, cols), got {arr.shape}")
    return arr


def check_square(name: str, arr: np.ndarray) -> None:
    """A ``ValueError`` unless the last two axes of ``arr`` have equal lengths."""
    if arr.shape[-1] != arr.shape[-2]:
        raise ValueError(f"{name} must be square in its last two axes, got {arr.shape}")


def sym(m: np.ndarray) -> np.ndarray:
    """``(m + m^T) / 2`` over the last two axes: a computed covariance made symmetric."""
    return 0.5 * (m + np.swapaxes(m, -1, -2))



def check_update_shapes(P, C, R) -> None:
    """A ``ValueError`` unless ``C`` has as many columns as ``P`` and ``R`` as many rows as
    ``C`` (the shapes of a measurement update)."""
    if C.shape[-1] != P.shape[-1]:
        raise ValueError(f"C has {C.shape[-1]} columns but P is {P.shape[-1]}x{P.shape[-1]}")
    if R.shape[-1] != C.shape[-2]:
        raise ValueError(f"R is {R.shape[-1]}x{R.shape[-1]} but C has {C.shape[-2]} rows")
