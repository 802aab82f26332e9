"""Input validators shared by the modules (each raises ``ValueError`` naming the argument).

* ``posint(name, value) -> int``: a positive integer (``bool`` rejected).
* ``finite(name, value) -> ndarray``: a float array with finite entries.
* ``positive(name, value, what="a variance") -> ndarray``: finite and ``> 0``.
* ``nonneg(name, value, what=None) -> ndarray``: finite and ``>= 0``.
* ``one_of(name, value, options)``: ``value`` must be one of ``options``.

``what`` is the reason stated in the message, e.g. ``"x must be positive (a variance), got 0"``.
"""

from __future__ import annotations

import numpy as np

__all__ = ["posint", "finite", "positive", "nonneg", "one_of"]


def posint(name: str, value) -> int:
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
        raise ValueError(f"{name} must be a positive integer, got {value!r}")
    return int(value)


def finite(name: str, value) -> np.ndarray:
    arr = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return arr


def positive(name: str, value, what: str = "a variance") -> np.ndarray:
    arr = finite(name, value)
    if np.any(arr <= 0):
        raise ValueError(f"{name} must be positive ({what}), got {value!r}")
    return arr


def nonneg(name: str, value, what: str | None = None) -> np.ndarray:
    arr = finite(name, value)
    if np.any(arr < 0):
        why = f" ({what})" if what else ""
        raise ValueError(f"{name} must be non-negative{why}, got {value!r}")
    return arr



def one_of(name: str, value, options) -> None:
    if value not in options:
        raise ValueError(f"{name} must be one of {options}, got {value!r}")
