"""Input validators shared by the modules (each raises ``ValueError`` naming the argument).

The rule they enforce at the public surface: a function either returns finite, meaningful
numbers or raises ``ValueError`` (or a named subclass) whose message starts with the name of the
offending argument and states the reason. NaN and infinities are rejected by every numeric
validator; covariances are checked symmetric and positive semi-definite (or definite) with a
relative tolerance. The validators never modify the values they accept (``covariance`` returns
the input unchanged, not symmetrized), so accepting an input does not change any result bit.

* ``posint(name, value) -> int``: a positive integer (``bool`` rejected, NumPy integers
  accepted).
* ``integer(name, value, minimum=0) -> int``: an integer ``>= minimum`` (``bool`` rejected).
* ``finite(name, value) -> ndarray``: a float array with finite entries.
* ``positive(name, value, what="a variance") -> ndarray``: finite and ``> 0``.
* ``nonneg(name, value, what=None) -> ndarray``: finite and ``>= 0``.
* ``one_of(name, value, options)``: ``value`` must be one of ``options``.
* ``covariance(name, value, *, definite=False, n=None, batch=False) -> ndarray``: a finite,
  square, symmetric, positive semi-definite (or definite) matrix, or a stack of them.
* ``square(name, arr) -> ndarray``: a 2-D array must be square (a state transition ``A``).
* ``finite_result(name, value, why) -> ndarray``: a computed result must be finite (raises
  ``ValueError`` saying why it is not: an overflow the inputs caused).

``what`` is the reason stated in the message, e.g. ``"x must be positive (a variance), got 0"``.
"""

from __future__ import annotations

import numpy as np

from fusioncenter._docstrings import Glossary

__all__ = ["posint", "integer", "finite", "positive", "nonneg", "one_of", "covariance",
           "square", "finite_result", "SYMMETRY_RTOL", "PSD_RTOL"]

#: Relative tolerance of the symmetry check of :func:`covariance`: ``|M - M^T| <= SYMMETRY_RTOL
#: * max |M|`` entrywise.
SYMMETRY_RTOL = 1e-10
#: Relative tolerance of the semi-definiteness check: the smallest eigenvalue of ``(M + M^T)/2``
#: must be ``>= -PSD_RTOL * max |M|`` (rounding in a computed covariance gives eigenvalues of
#: order ``-1e-16 * max |M|``); for ``definite=True`` it must be ``> PSD_RTOL * max |M|``.
PSD_RTOL = 1e-10

#: The arguments the validators share, by name.
_doc = Glossary("""
name : str
    The argument's name, used in the message.
value : array_like
    Numbers (Python or NumPy scalars, sequences, arrays).
""")
#: ``value`` of the validators that accept anything and check its type.
_ANY = ("object", "The value to check.")


@_doc(returns=("int", "``value`` as a Python ``int``."), value=_ANY, raises=((
    "ValueError", "If ``value`` is not an integer ``>= 1`` (``True`` is not an integer here)."),))
def posint(name: str, value) -> int:
    """A positive integer (Python or NumPy integer; ``bool`` rejected)."""
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
        raise ValueError(f"{name} must be a positive integer, got {value!r}")
    return int(value)


@_doc(returns=("int", "``value`` as a Python ``int``."),
      value=("object", "The value to check (a seed, a number of steps, an index)."),
      minimum=("int", "The smallest value accepted."),
      raises=(("ValueError", "If ``value`` is not an integer (``True``, ``2.0`` and ``\"3\"`` are "
                             "not) or is below\n``minimum``."),))
def integer(name: str, value, minimum: int = 0) -> int:
    """An integer ``>= minimum`` (Python or NumPy integer; ``bool`` rejected)."""
    if isinstance(value, bool) or not isinstance(value, int | np.integer):
        raise ValueError(f"{name} must be an integer, got {value!r}")
    if value < minimum:
        raise ValueError(f"{name} must be >= {minimum}, got {value}")
    return int(value)


def _as_float(name: str, value) -> np.ndarray:
    try:
        return np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a real number or array of them, got {value!r}") from None


@_doc(returns=("numpy.ndarray", "``numpy.asarray(value, dtype=float)`` (0-d for a scalar)."),
      raises=(("ValueError", "If ``value`` is not convertible to floats or has a NaN or infinite "
                             "entry."),))
def finite(name: str, value) -> np.ndarray:
    """A float array with finite entries."""
    arr = _as_float(name, value)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return arr


@_doc(returns=("numpy.ndarray", "The values as floats."),
      what=("str", "Why the value must be positive, quoted in the message."),
      raises=(("ValueError", "If an entry is NaN, infinite or ``<= 0``."),))
def positive(name: str, value, what: str = "a variance") -> np.ndarray:
    """A finite float array with entries ``> 0``."""
    arr = finite(name, value)
    if np.any(arr <= 0):
        raise ValueError(f"{name} must be positive ({what}), got {value!r}")
    return arr


@_doc(returns=("numpy.ndarray", "The values as floats."),
      what=("str, optional", "Why the value must be non-negative, quoted in the message."),
      raises=(("ValueError", "If an entry is NaN, infinite or negative."),))
def nonneg(name: str, value, what: str | None = None) -> np.ndarray:
    """A finite float array with entries ``>= 0``."""
    arr = finite(name, value)
    if np.any(arr < 0):
        why = f" ({what})" if what else ""
        raise ValueError(f"{name} must be non-negative{why}, got {value!r}")
    return arr


def one_of(name: str, value, options) -> None:
    """``value`` must be one of ``options``.

    Parameters
    ----------
    name : str
        The argument's name, used in the message.
    value : object
        Checked for membership.
    options : container
        The allowed values.

    Raises
    ------
    ValueError
        If ``value not in options``.
    """
    if value not in options:
        raise ValueError(f"{name} must be one of {options}, got {value!r}")


@_doc(returns=("numpy.ndarray", "The matrix as floats, unchanged (not symmetrized)."),
      value=("array_like", "A matrix ``(n, n)``, or with ``batch=True`` a stack ``(..., n, n)`` "
                           "of them."),
      definite=("bool", "Require positive definiteness (smallest eigenvalue ``> PSD_RTOL * max "
                        "|M|``) instead of\nsemi-definiteness (``>= -PSD_RTOL * max |M|``)."),
      n=("int, optional", "The required size."), batch=("bool", "Allow leading (batch) axes."),
      raises=(("ValueError", "If it is not finite, not a (stack of) square matrices of the right "
                             "size, not symmetric\nto ``SYMMETRY_RTOL``, or has an eigenvalue "
                             "below the tolerance."),))
def covariance(name: str, value, *, definite: bool = False, n: int | None = None,
               batch: bool = False) -> np.ndarray:
    """A covariance matrix: finite, square, symmetric and positive semi-definite (or definite)."""
    arr = finite(name, value)
    if arr.ndim < 2 or (arr.ndim > 2 and not batch) or arr.shape[-1] != arr.shape[-2]:
        want = "a square matrix (..., n, n)" if batch else "a square matrix (n, n)"
        raise ValueError(f"{name} must be {want}, got shape {arr.shape}")
    if n is not None and arr.shape[-1] != n:
        raise ValueError(f"{name} must be {n}x{n}, got shape {arr.shape}")
    if arr.size == 0:
        return arr
    scale = np.abs(arr).max(axis=(-2, -1), keepdims=True)
    asym = np.abs(arr - np.swapaxes(arr, -1, -2))
    if np.any(asym > SYMMETRY_RTOL * scale):
        raise ValueError(f"{name} must be symmetric (a covariance), got {value!r}")
    low = np.linalg.eigvalsh(0.5 * (arr + np.swapaxes(arr, -1, -2)))[..., 0]
    tol = PSD_RTOL * scale[..., 0, 0]
    if definite and np.any(low <= tol):
        raise ValueError(f"{name} must be positive definite, got smallest eigenvalue "
                         f"{float(np.min(low)):.3g}")
    if np.any(low < -tol):
        raise ValueError(f"{name} must be positive semi-definite (a covariance), got smallest "
                         f"eigenvalue {float(np.min(low)):.3g}")
    return arr


@_doc(returns=("numpy.ndarray", "``arr``, unchanged."),
      arr=("numpy.ndarray", "A 2-D array (the caller has converted and checked it)."),
      raises=(("ValueError", "If ``arr`` is not square."),))
def square(name: str, arr: np.ndarray) -> np.ndarray:
    """A matrix must be square."""
    if arr.shape != (arr.shape[0],) * 2:
        raise ValueError(f"{name} must be square, got {arr.shape}")
    return arr


@_doc(returns=("numpy.ndarray", "``value`` as an array, unchanged."),
      name=("str", "What was computed, used in the message."), value=("array_like", "The result."),
      why=("str", "Which inputs make it overflow, quoted in the message."),
      raises=(("ValueError", "If an entry is NaN or infinite."),))
def finite_result(name: str, value, why: str) -> np.ndarray:
    """A computed result must be finite."""
    arr = np.asarray(value)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} is not finite: {why}")
    return arr
