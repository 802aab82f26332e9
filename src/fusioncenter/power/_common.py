"""What the modules of :mod:`fusioncenter.power` share: argument checks and the glossary.

The validators raise ``ValueError`` naming the argument (:mod:`fusioncenter._validate` for the
rule); :data:`document` holds the description of every argument name that recurs in the
package, written once (:class:`fusioncenter._docstrings.Glossary`), and the variants a few
functions use (an error target needs ``sigma_w2 > 0``, a minimum-power problem ``sigma_n2 > 0``).
"""

from __future__ import annotations

import numpy as np

from fusioncenter._docstrings import Glossary
from fusioncenter._validate import finite as _finite
from fusioncenter._validate import nonneg as _nonneg
from fusioncenter._validate import positive as _positive

__all__ = ["ACCESS", "check_access", "check_a", "check_sensors", "TARGET_NEEDS_NOISE", "check_D",
           "check_general", "IDEAL_CHANNEL", "check_target", "target_xy", "document",
           "SW2_TARGET", "SN2_MIN_POWER", "SN2_POSITIVE", "A_ANY", "ALPHA", "COEFFICIENTS",
           "INVALID", "INFEASIBLE"]


#: The two schemes: every signal summed on one channel, or each on its own.
ACCESS = ("multi-access", "orthogonal")


def check_access(access) -> str:
    """``access``, which must be one of :data:`ACCESS`."""
    if access not in ACCESS:
        raise ValueError(f"access must be one of {ACCESS}, got {access!r}")
    return access


def check_a(a, *, stable: bool = True) -> np.ndarray:
    """The state transition: finite, and ``|a| < 1`` unless ``stable=False``."""
    arr = _finite("a", a)
    if stable and np.any(np.abs(arr) >= 1):
        raise ValueError(
            f"a must satisfy |a| < 1 (a stable system: the transmit power uses the stationary "
            f"variance sigma_w2 / (1 - a^2)), got a = {a!r}"
        )
    return arr


def check_sensors(**arrays) -> dict[str, np.ndarray]:
    """Check per-sensor arrays: finite, and the same number of sensors on the last axis."""
    out: dict[str, np.ndarray] = {}
    n_sensors: tuple[str, int] | None = None
    for name, value in arrays.items():
        arr = _finite(name, value)
        if arr.ndim == 0:
            arr = arr[None]
        if n_sensors is None:
            n_sensors = (name, arr.shape[-1])
        elif arr.shape[-1] != n_sensors[1]:
            raise ValueError(
                f"{name} has {arr.shape[-1]} sensors (last axis) but {n_sensors[0]} has "
                f"{n_sensors[1]}: per-sensor arrays must have the same length"
            )
        out[name] = arr
    try:
        np.broadcast_shapes(*(a.shape for a in out.values()))
    except ValueError:
        shapes = {k: v.shape for k, v in out.items()}
        raise ValueError(f"per-sensor arrays do not broadcast: {shapes}") from None
    return out


#: Why an error target needs process noise.
TARGET_NEEDS_NOISE = ("a variance; with sigma_w2 = 0 the steady state is 0 whatever alpha, so "
                       "no target D in (sigma_w2, sigma_w2 / (1 - a^2)) exists")


def check_D(D, a, sigma_w2) -> np.ndarray:
    """An error target strictly between ``sigma_w2`` and ``sigma_w2 / (1 - a^2)``."""
    D = _finite("D", D)
    upper = sigma_w2 / (1.0 - a**2)
    if np.any(D <= sigma_w2) or np.any(D >= upper):
        raise ValueError(
            f"D must lie strictly between sigma_w2 = {float(np.max(sigma_w2)):g} (the best "
            f"possible) and sigma_w2 / (1 - a^2) = {float(np.min(upper)):g} (no measurement at "
            f"all), got D = {D!r}"
        )
    return D


def check_general(rho, tau, kappa_, sigma_n2):
    """``(rho, tau, kappa, sigma_n2)`` of a general problem, the per-sensor arrays broadcast."""
    s = check_sensors(rho=rho, tau=tau, kappa=kappa_)
    _positive("tau", s["tau"])
    _positive("kappa", s["kappa"], "a power per unit alpha^2")
    sn = _nonneg("sigma_n2", sigma_n2, "a variance")
    if np.any(np.all(s["rho"] == 0, axis=-1)):
        raise ValueError("rho must have a non-zero entry in every row (all zero: no sensor "
                         "carries information, S = 0 whatever alpha)")
    rho, tau, kap = np.broadcast_arrays(s["rho"], s["tau"], s["kappa"])
    return rho, tau, kap, sn


#: Why the minimum-power problems need receiver noise.
IDEAL_CHANNEL = ("with an ideal channel (sigma_n2 = 0) the SNR does not depend on the scale of "
                  "alpha, so the infimum 0 of the power is approached but not attained")


def check_target(D, a, sigma_w2) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(a, sigma_w2, D)`` of an error target: ``|a| < 1``, ``sigma_w2 > 0``, ``D`` in range."""
    a = check_a(a)
    sigma_w2 = _positive("sigma_w2", sigma_w2, TARGET_NEEDS_NOISE)
    return a, sigma_w2, check_D(D, a, sigma_w2)


def target_xy(D, a, sigma_w2):
    """``x = a^2 D + sigma_w2 - D`` and ``y = D (D - sigma_w2)`` of problems (19)/(26)."""
    a, sigma_w2, D = check_target(D, a, sigma_w2)
    return a**2 * D + sigma_w2 - D, D * (D - sigma_w2)


#: The argument descriptions that differ from the glossary's in several functions.
SW2_TARGET = ("array_like", "Process-noise variance, ``> 0`` (with 0 no error target exists).")
SN2_MIN_POWER = ("array_like", "Receiver-noise variance, ``> 0`` (with an ideal channel the "
                 "minimum power is not attained).")
SN2_POSITIVE = ("array_like", "Receiver-noise variance, ``> 0``.")
A_ANY = ("array_like", "State transition, finite (``|a| >= 1`` allowed when ``S > 0``).")
#: The ``Returns`` of the allocation functions and of the coefficient functions.
ALPHA = ("numpy.ndarray", "The amplification factors ``alpha`` ``(..., M)``.")
COEFFICIENTS = ("rho, tau, kappa : numpy.ndarray", "")
#: What every function raises on bad input.
INVALID = ("ValueError", "Naming the argument that is NaN, infinite, out of range or of "
           "inconsistent shape.")
#: ``Raises`` of a function with an error target.
INFEASIBLE = (("InfeasibleError", "If the target cannot be met (a ``ValueError`` stating the "
               "threshold)."), INVALID)

#: The arguments of the package's functions, by name.
document = Glossary("""
a : array_like
    State transition, ``|a| < 1``.
sigma_w2 : array_like
    Process-noise variance, ``>= 0`` (``0``: deterministic dynamics).
c : array_like
    Measurement gains ``(..., M)``, finite.
sigma_v2 : array_like
    Measurement-noise variances ``(..., M)``, ``> 0``.
alpha : array_like
    Real amplification factors ``(..., M)``.
S : array_like
    Signal-to-noise ratio, ``>= 0`` and finite (arbitrarily large: the result tends to
    ``sigma_w2`` as ``S -> inf``; ``inf`` itself is rejected).
D : array_like
    Error target, strictly between ``sigma_w2`` and ``sigma_w2 / (1 - a^2)``.
access : str
    ``"multi-access"`` or ``"orthogonal"``.
h : array_like
    Channel gains ``(..., M)``, ``> 0``.
sigma_n2 : array_like
    Receiver-noise variance, ``>= 0`` (``0``: an ideal channel).
P : array_like
    Prediction variance(s), ``>= 0``.
scaling : str
    ``"none"`` or ``"sqrt"``.
M : array_like
    Number of sensors, ``> 0``.
h_range, c_range, sigma_v2_range : tuple
    ``(min, max)``, ``> 0``.
exact : bool
    Bounds valid for every ``M`` instead of the printed asymptotic ones.
rho : array_like
    ``(..., M)``, finite, not all zero.
tau, kappa : array_like
    ``(..., M)``, ``> 0``.
x, y : array_like
    The constants of the constraint, ``> 0``.
infeasible : str
    ``"raise"`` or ``"nan"``.
gamma_total : array_like
    Total power, ``>= 0`` (``0``: nothing is sent).
return_m1 : bool
    Also return ``M_1``.
gamma : array_like, optional
    Power per sensor, ``>= 0``.
P0 : array_like, optional
    ``P_0`` (default ``D``).
h_mean : array_like
    Complex channel means ``(..., M)``, non-zero.
alpha_t : array_like
    Complex amplification factors ``(..., M)``.
h_var_re, h_var_im : array_like
    Variances of their real and imaginary parts, ``>= 0``.
Cbar : array_like
    ``(..., d)``, finite.
Rbar : array_like
    ``(..., d, d)``, symmetric positive definite.
z : array_like
    Observations ``(..., steps, d)``, finite.
rng : numpy.random.Generator
    The source of randomness.
n, steps : int
    Runs and time steps, ``>= 1``.
problem : str
    One of the four problem names.
starts : int
    Random starts for (23), ``>= 1``.
seed : int
    Non-negative integer seed.
""", raises="""
ValueError
    Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
""")
