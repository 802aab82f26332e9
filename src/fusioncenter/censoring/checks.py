"""Validation of the censoring package's arguments: the threshold ``eta`` and covariances,
positive definite or semi-definite (named in every message)."""

from __future__ import annotations

import numpy as np

from fusioncenter._validate import PSD_RTOL
from fusioncenter._validate import as_float as _as_float
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


def check_offsets(widths: tuple = (), positive: bool = False, **values) -> None:
    """Offsets and half-widths (semi-axes) of a censoring interval or ellipse: no NaN, widths
    ``>= 0`` (``> 0`` and finite with ``positive=True``); infinities are limits elsewhere.

    Parameters
    ----------
    widths : tuple of str
        The names among ``values`` that are widths.
    positive : bool
        Widths must be positive and finite, offsets finite.
    **values : array_like
        The arguments, by name.

    Returns
    -------
    None
        The arguments are only checked.

    Raises
    ------
    ValueError
        Naming the argument that is text, NaN, (``positive``) infinite, or a negative (zero)
        width.
    """
    for name, value in values.items():
        arr = _finite(name, value) if positive else _as_float(name, value)
        if np.any(np.isnan(arr)):
            raise ValueError(f"{name} must not be NaN, got {value!r}")
        if name in widths and np.any(arr <= 0 if positive else arr < 0):
            why = "positive" if positive else "non-negative"
            raise ValueError(f"{name} must be {why} (a half-width), got {value!r}")


def check_cholesky(name: str, value) -> np.ndarray:
    """The Cholesky factor of (a stack of) positive-definite matrices, or ``ValueError`` naming
    them (NumPy's ``LinAlgError`` says only "Matrix is not positive definite").

    Parameters
    ----------
    name : str
        The argument's name, used in the message.
    value : numpy.ndarray
        Finite matrices ``(..., m, m)`` (only the lower triangle is read).

    Returns
    -------
    numpy.ndarray
        ``L`` with ``L L^T = value``, lower triangular.

    Raises
    ------
    ValueError
        If a matrix is not positive definite.
    """
    try:
        return np.linalg.cholesky(value)
    except np.linalg.LinAlgError:
        raise ValueError(f"{name} must be positive definite (a covariance of full rank)") from None


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
