"""Validation of the censoring package's arguments: the threshold ``eta`` and covariances,
positive definite or semi-definite (named in every message)."""

from __future__ import annotations

import numpy as np

from fusioncenter._validate import PSD_RTOL
from fusioncenter._validate import finite as _finite

#: A covariance whose smallest eigenvalue is at most this times its largest counts as singular.
SINGULAR_RTOL = 1e-12


def check_eta(value) -> float:
    """A censoring threshold ``eta``: a finite non-negative number (``ValueError`` otherwise).

    Parameters
    ----------
    value : float
        The threshold to check (a real number, not ``bool``).

    Returns
    -------
    float
        ``eta`` as a float, finite and ``>= 0``.
    """
    if (isinstance(value, bool | str | bytes) or not np.isscalar(value)
            or not np.isfinite(value) or value < 0):
        raise ValueError(f"eta must be a finite non-negative number, got {value!r}")
    return float(value)


def check_pd(name: str, value, m: int | None = None, *,
             why: str = "a covariance of full rank") -> np.ndarray:
    """Symmetric positive-definite matrices ``(..., m, m)``.

    Parameters
    ----------
    name : str
        The argument's name, used in the messages.
    value : array_like
        Matrices ``(..., m, m)``, finite.
    m : int, optional
        The required size (any square size if omitted).
    why : str
        Why the matrices must be positive definite, quoted in the message.

    Returns
    -------
    numpy.ndarray
        The matrices, symmetrized (``(A + A^T) / 2``; asymmetry up to ``1e-10`` relative is
        accepted).

    Raises
    ------
    ValueError
        Naming ``name`` if the matrices are not finite, not square of size ``m``, not symmetric
        or not positive definite.
    """
    arr = _symmetric(name, value, m)
    if np.any(np.linalg.eigvalsh(arr) <= 0):
        raise ValueError(f"{name} must be positive definite ({why})")
    return arr


def check_psd(name: str, value, m: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Symmetric positive semi-definite matrices ``(..., m, m)``, singular ones allowed.

    Parameters
    ----------
    name : str
        The argument's name, used in the messages.
    value, m
        The matrices and their required size, as for :func:`check_pd`.

    Returns
    -------
    matrices : numpy.ndarray
        The matrices, symmetrized as by :func:`check_pd`.
    singular : numpy.ndarray
        Bool ``(...)``: smallest eigenvalue at most :data:`SINGULAR_RTOL` times the largest
        (the ellipse quadrature cannot resolve such an elongated law: the exact singular limit
        is used there instead).

    Raises
    ------
    ValueError
        Naming ``name`` if the matrices are not finite, not square of size ``m``, not symmetric
        or not positive semi-definite.
    """
    arr = _symmetric(name, value, m)
    lam = np.linalg.eigvalsh(arr)
    if np.any(lam[..., 0] < -PSD_RTOL * np.abs(lam).max(axis=-1)):
        raise ValueError(f"{name} must be positive semi-definite (a covariance)")
    return arr, lam[..., 0] <= SINGULAR_RTOL * lam[..., -1]


def _symmetric(name: str, value, m: int | None) -> np.ndarray:
    arr = _finite(name, value)
    if arr.ndim < 2 or arr.shape[-1] != arr.shape[-2] or (m is not None and arr.shape[-1] != m):
        want = f"(..., {m}, {m})" if m is not None else "(..., m, m)"
        raise ValueError(f"{name} must be square matrices {want}, got shape {arr.shape}")
    scale = np.maximum(1.0, np.abs(arr).max(axis=(-1, -2), keepdims=True))
    if np.any(np.abs(arr - np.swapaxes(arr, -1, -2)) > 1e-10 * scale):
        raise ValueError(f"{name} must be symmetric")
    return 0.5 * (arr + np.swapaxes(arr, -1, -2))
