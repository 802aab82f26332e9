"""What the modules of :mod:`fusioncenter.fading` share: argument checks, the Monte Carlo runner
of the variance paths, the iteration and fixed point of a bound map, and the glossary of the
argument descriptions (:class:`fusioncenter._docstrings.Glossary`).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import scipy.optimize

from fusioncenter import montecarlo
from fusioncenter._docstrings import Glossary
from fusioncenter._validate import finite_result as _finite_result
from fusioncenter._validate import integer as _int
from fusioncenter.fading.channels import Nakagami, Rayleigh

__all__ = ["VARIANCE", "check_scalar", "check_channel", "simulate_paths", "iterate",
           "fixed_point", "document"]


#: The reason given when a variance is negative.
VARIANCE = "it is a variance"


def check_scalar(name: str, arr: np.ndarray) -> float:
    """``arr`` as a float; it must be 0-dimensional."""
    if arr.ndim != 0:
        raise ValueError(f"{name} must be a scalar, got shape {arr.shape}")
    return float(arr)


def check_channel(channel):
    """``channel``, which must be a :class:`Rayleigh` or :class:`Nakagami` law."""
    if not isinstance(channel, Rayleigh | Nakagami):
        raise ValueError(f"channel must be Rayleigh(lam) or Nakagami(m, lam), got {channel!r}")
    return channel


def simulate_paths(fn: Callable, n_paths, seed, **runner) -> montecarlo.MonteCarloResult:
    """``fn``'s paths through :func:`fusioncenter.montecarlo.simulate`, checked finite."""
    res = montecarlo.simulate(fn, _int("n_paths", n_paths, 1), _int("seed", seed, 0), **runner)
    _finite_result("p_k", res.samples, "the variance overflows the float range (|a| too large "
                   "for this many steps)")
    return res


def iterate(fn: Callable[[float], float], x0: float, steps: int) -> np.ndarray:
    """``x0, fn(x0), fn(fn(x0)), ...``: ``steps + 1`` values, checked finite."""
    out = np.empty(steps + 1)
    out[0] = x = x0
    with np.errstate(over="ignore", invalid="ignore"):
        for k in range(steps):
            x = float(fn(x))
            out[k + 1] = x
    return _finite_result("the bound", out, "it overflows the float range (|a| too large for "
                          "this many steps)")


def fixed_point(fn: Callable[[float], float], lo: float) -> float:
    """The fixed point of an increasing map with ``fn(lo) >= lo`` (bracketed, then brentq)."""
    hi = max(2.0 * lo, 1.0)
    for _ in range(2000):
        if fn(hi) < hi:
            break
        hi *= 2.0
    else:  # pragma: no cover - the maps grow sub-linearly
        raise ValueError("no fixed point found: the bound diverges")
    if fn(lo) - lo <= 0:
        return lo
    return float(scipy.optimize.brentq(lambda x: fn(x) - x, lo, hi, xtol=1e-14, rtol=1e-15,
                                       maxiter=500))


#: The arguments of the package's functions, by name.
document = Glossary("""
a : float
    State transition, finite (``a = 0`` allowed: ``p_k = sigma_w2`` for ``k >= 1``).
sigma_w2 : float
    Process-noise variance, ``>= 0``.
sigma_v2 : float
    Measurement-noise variance, ``>= 0`` (``0``: a noise-free sensor).
sigma_n2 : float
    Channel-noise variance, ``> 0``.
channel : Rayleigh or Nakagami
    The law of the power gain ``r = h^2``.
p0 : float
    ``E[p_0]``, ``>= 0``.
steps : int
    Number of steps, ``>= 0``.
n_paths : int
    Number of Monte Carlo paths, ``>= 1``.
seed : int
    Non-negative integer seed (NumPy integers accepted, ``bool`` rejected).
**runner
    ``chunk_size``, ``executor``, ``progress``, ``block_size`` of
    :func:`fusioncenter.montecarlo.simulate`.
p : array_like
    Prior variance(s), ``>= 0``.
lam : float
    The Nakagami(1/2) parameter ``1 / E[r]``, ``> 0``.
access : str
    ``"multi-access"`` (model (7)) or ``"orthogonal"`` (model (8)).
c : array_like
    Measurement gains, one per sensor (``> 0`` for multi-access).
lams : array_like
    Rayleigh parameters ``1 / E[r_i]``, one per sensor, ``> 0``.
last_sensor : int, optional
    Multi-access only: the sensor integrated last (default: a worst one).
A : array_like
    State transition ``(n, n)``, finite.
Sigma_w : array_like
    Process-noise covariance ``(n, n)``, symmetric PSD.
P0 : array_like
    ``E[P_0]`` ``(n, n)``, symmetric PSD.
x : array_like
    Upper triangles ``(..., n (n + 1) / 2)``, finite.
n : int
    Matrix size, ``>= 1``.
""", raises="""
ValueError
    Naming the argument that is NaN, infinite, negative where a variance is expected, of the
    wrong shape or type, or if the variances overflow (``|a|`` too large for ``steps``).
""")
