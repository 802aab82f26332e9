"""Steady states, 1/M laws and optimal power allocation for analog forwarding (leong2011).

Model (scalar state, ``M`` sensors, |a| < 1)::

    x_{k+1} = a x_k + w_k,          w_k ~ N(0, sigma_w2)
    y_{i,k} = c_i x_k + v_{i,k},    v_{i,k} ~ N(0, sigma_v2[i])

Sensor ``i`` forwards ``alpha_i y_{i,k}`` over a channel of gain ``h_i > 0`` (after transmit
beamforming with channel-state information, CSI). The fusion centre receives either the sum
(``"multi-access"``, eq. (2)) or every signal on its own channel (``"orthogonal"``), each with
receiver noise of variance ``sigma_n2``. The Kalman filter's steady-state prediction variance is
eq. (8) in the signal-to-noise ratio

* multi-access  ``S   = (sum alpha_i h_i c_i)^2 / (sum alpha_i^2 h_i^2 sigma_v2_i + sigma_n2)``
* orthogonal    ``S^o = sum alpha_i^2 h_i^2 c_i^2 / (alpha_i^2 h_i^2 sigma_v2_i + sigma_n2)``

and sensor ``i`` spends ``gamma_i = alpha_i^2 kappa_i`` with ``kappa_i = E[y_i^2] = c_i^2
sigma_w2 / (1 - a^2) + sigma_v2_i``.

Conventions: every variance is a variance (never a standard deviation); ``h``, ``c``,
``sigma_v2`` and ``alpha`` are per-sensor arrays whose *last* axis indexes the sensors (leading
axes, if any, broadcast: many realizations at once); ``access`` is ``"multi-access"`` or
``"orthogonal"``. Bad input raises ``ValueError`` naming the argument; an unreachable error target
raises :class:`InfeasibleError` (a ``ValueError``) whose message states the threshold.

The four allocation problems of Section IV are solved in the paper's general form
(``rho_i``, ``tau_i``, ``kappa_i``, ``sigma_n2`` and ``x, y`` or ``gamma_total``):

==========================  =====================================  =========================
problem                     general solver                         printed solution
==========================  =====================================  =========================
(19) coherent, min power    :func:`coherent_min_power`             (20)-(22), correct
(23) coherent, max SNR      :func:`coherent_max_snr`               (24) has an erratum
(26) orthogonal, min power  :func:`orthogonal_min_power`           (27) + M_1 rule, erratum
(28) orthogonal, max SNR    :func:`orthogonal_max_snr`             (29) + M_1 rule, correct
==========================  =====================================  =========================

The static problems (18)/(25) and their converses are :func:`min_power` / :func:`min_error`;
with fading and CSI the greedy per-step problems (30)/(31) and their orthogonal counterparts are
:func:`csi_min_power_step`, :func:`csi_min_error_step` and the time loops :func:`greedy_min_power`
/ :func:`greedy_min_error`; without CSI the linear MMSE estimator (32)-(33) is
:func:`lmmse_matrices`, :func:`lmmse_filter` and its steady state :func:`lmmse_steady_state`.
:func:`solve_numerically` solves the same problems with SciPy's SLSQP (an independent check of
the closed forms). The errata are on the book's errata page, ``book/errata.md``.
"""

from __future__ import annotations

import numpy as np

from fusioncenter import riccati
from fusioncenter._validate import covariance as _covariance
from fusioncenter._validate import finite as _finite
from fusioncenter._validate import finite_result as _finite_result
from fusioncenter._validate import integer as _integer
from fusioncenter._validate import nonneg as _nonneg
from fusioncenter._validate import positive as _positive

__all__ = [
    "ACCESS",
    "InfeasibleError",
    "stationary_variance",
    "kappa",
    "transmit_power",
    "steady_state",
    "required_snr",
    "snr",
    "symmetric_asymptotics",
    "lemma4_bounds",
    "coherent_min_power",
    "coherent_max_snr",
    "coherent_max_snr_printed",
    "orthogonal_min_power",
    "orthogonal_max_snr",
    "static_coefficients",
    "min_power",
    "min_error",
    "equal_power",
    "equal_power_min_power",
    "csi_min_power_step",
    "csi_min_error_step",
    "greedy_min_power",
    "greedy_min_error",
    "beamformed",
    "lmmse_matrices",
    "lmmse_snr",
    "lmmse_coefficients",
    "lmmse_steady_state",
    "lmmse_min_power",
    "lmmse_min_error",
    "lmmse_filter",
    "simulate_nocsi",
    "solve_numerically",
]

ACCESS = ("multi-access", "orthogonal")

#: Below this a product of two floats has lost digits (subnormal range, with a margin).
_SMALL = np.finfo(float).tiny / np.finfo(float).eps


class InfeasibleError(ValueError):
    """The error-covariance target cannot be met with any amplification factors."""


# =========================================================================== validation
def _access(access) -> str:
    if access not in ACCESS:
        raise ValueError(f"access must be one of {ACCESS}, got {access!r}")
    return access


def _a(a, *, stable: bool = True) -> np.ndarray:
    arr = _finite("a", a)
    if stable and np.any(np.abs(arr) >= 1):
        raise ValueError(
            f"a must satisfy |a| < 1 (a stable system: the transmit power uses the stationary "
            f"variance sigma_w2 / (1 - a^2)), got a = {a!r}"
        )
    return arr


def _sensors(**arrays) -> dict[str, np.ndarray]:
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
_TARGET_NEEDS_NOISE = ("a variance; with sigma_w2 = 0 the steady state is 0 whatever alpha, so "
                       "no target D in (sigma_w2, sigma_w2 / (1 - a^2)) exists")


def _check_D(D, a, sigma_w2) -> np.ndarray:
    D = _finite("D", D)
    upper = sigma_w2 / (1.0 - a**2)
    if np.any(D <= sigma_w2) or np.any(D >= upper):
        raise ValueError(
            f"D must lie strictly between sigma_w2 = {float(np.max(sigma_w2)):g} (the best "
            f"possible) and sigma_w2 / (1 - a^2) = {float(np.min(upper)):g} (no measurement at "
            f"all), got D = {D!r}"
        )
    return D


# ============================================================================== basics
def stationary_variance(a, sigma_w2) -> np.ndarray:
    """``E[x_k^2] = sigma_w2 / (1 - a^2)`` of the stationary state (|a| < 1).

    Parameters
    ----------
    a : array_like
        State transition, ``|a| < 1``.
    sigma_w2 : array_like
        Process-noise variance, ``>= 0`` (``0``: deterministic dynamics).

    Returns
    -------
    numpy.ndarray
        ``sigma_w2 / (1 - a^2)``.

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
    """
    a = _a(a)
    return _nonneg("sigma_w2", sigma_w2, "a variance") / (1.0 - a**2)


def kappa(a, sigma_w2, c, sigma_v2) -> np.ndarray:
    """``kappa_i = E[y_i^2] = c_i^2 sigma_w2 / (1 - a^2) + sigma_v2_i``: power per unit alpha^2.

    Parameters
    ----------
    a : array_like
        State transition, ``|a| < 1``.
    sigma_w2 : array_like
        Process-noise variance, ``>= 0`` (``0``: deterministic dynamics).
    c : array_like
        ``(..., M)``, finite.
    sigma_v2 : array_like
        ``(..., M)``, ``> 0``.

    Returns
    -------
    numpy.ndarray
        ``kappa`` ``(..., M)``, finite.

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
    """
    s = _sensors(c=c, sigma_v2=sigma_v2)
    _positive("sigma_v2", s["sigma_v2"])
    with np.errstate(over="ignore"):
        out = s["c"] ** 2 * stationary_variance(a, sigma_w2)[..., None] + s["sigma_v2"]
    return _finite_result("kappa", out, "c_i^2 sigma_w2 / (1 - a^2) overflows")


def transmit_power(alpha, a, sigma_w2, c, sigma_v2) -> np.ndarray:
    """Per-sensor transmit powers ``gamma_i = alpha_i^2 kappa_i`` (Section II.C).

    Parameters
    ----------
    alpha : array_like
        ``(..., M)``, finite.
    a : array_like
        State transition, ``|a| < 1``.
    sigma_w2 : array_like
        Process-noise variance, ``>= 0`` (``0``: deterministic dynamics).
    c, sigma_v2 : array_like
        As in :func:`kappa`.

    Returns
    -------
    numpy.ndarray
        ``gamma_i`` ``(..., M)``, finite.

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
    """
    s = _sensors(alpha=alpha, c=c)
    with np.errstate(over="ignore"):
        out = s["alpha"] ** 2 * kappa(a, sigma_w2, s["c"], sigma_v2)
    return _finite_result("the transmit power", out, "alpha_i^2 kappa_i overflows")


def steady_state(a, sigma_w2, S) -> np.ndarray:
    """Steady-state prediction variance ``P_inf`` of eq. (8) (= (7), (10)) for SNR ``S >= 0``.

    ``S = 0`` (no information) gives ``sigma_w2 / (1 - a^2)``, which needs ``|a| < 1``; for
    ``S > 0`` any real ``a`` is allowed (Remark III.E.2). Reuses
    :func:`fusioncenter.riccati.scalar_steady_state` with ``c = sqrt(S)``, ``r = 1``.
    Broadcasts like a ufunc.

    Parameters
    ----------
    a : array_like
        State transition, finite (``|a| >= 1`` allowed when ``S > 0``).
    sigma_w2 : array_like
        Process-noise variance, ``>= 0`` (``0``: deterministic dynamics).
    S : array_like
        Signal-to-noise ratio, ``>= 0`` (arbitrarily large: ``S -> inf`` gives ``sigma_w2``).

    Returns
    -------
    numpy.ndarray
        ``P_inf``, finite, in ``[sigma_w2, sigma_w2 / (1 - a^2)]`` for ``|a| < 1``.

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
    """
    a = _a(a, stable=False)
    sigma_w2 = _nonneg("sigma_w2", sigma_w2, "a variance")
    S = _finite("S", S)
    if np.any(S < 0):
        raise ValueError(f"S must be non-negative (it is a signal-to-noise ratio), got {S!r}")
    if np.any((S == 0) & (np.abs(a) >= 1)):
        raise ValueError("a must satisfy |a| < 1 when S = 0: without measurements an unstable "
                         "state has no steady-state variance")
    return riccati.scalar_steady_state(a, sigma_w2, np.sqrt(S), 1.0)


def required_snr(D, a, sigma_w2) -> np.ndarray:
    """The SNR at which ``P_inf = D``: ``(a^2 D + sigma_w2 - D) / (D (D - sigma_w2))``.

    The inverse of :func:`steady_state` (which is decreasing in ``S``, Lemma 1); the right-hand
    side of (25) and ``x / y`` of problem (19).

    Parameters
    ----------
    D : array_like
        Error target, strictly between ``sigma_w2`` and ``sigma_w2 / (1 - a^2)``.
    a : array_like
        State transition, ``|a| < 1``.
    sigma_w2 : array_like
        Process-noise variance, ``> 0`` (with 0 no error target exists).

    Returns
    -------
    numpy.ndarray
        The SNR at which ``P_inf = D``.

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
    """
    a = _a(a)
    sigma_w2 = _positive("sigma_w2", sigma_w2, _TARGET_NEEDS_NOISE)
    D = _check_D(D, a, sigma_w2)
    return (a**2 * D + sigma_w2 - D) / (D * (D - sigma_w2))


def snr(access, alpha, h, c, sigma_v2, sigma_n2) -> np.ndarray:
    """``S`` (multi-access) or ``S^o`` (orthogonal) of Section II.D for static channels.

    Parameters
    ----------
    access : str
        ``"multi-access"`` or ``"orthogonal"``.
    alpha : array_like
        ``(..., M)``, finite (any magnitude: the formula is rescaled where it would overflow).
    h : array_like
        Channel gains ``(..., M)``, ``> 0``.
    c : array_like
        Measurement gains ``(..., M)``, finite.
    sigma_v2 : array_like
        Measurement-noise variances ``(..., M)``, ``> 0``.
    sigma_n2 : array_like
        Receiver-noise variance, ``>= 0`` (``0``: an ideal channel).

    Returns
    -------
    float or numpy.ndarray
        ``S >= 0``, at most ``sum_i c_i^2 / sigma_v2_i``.

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
    """
    access = _access(access)
    s = _sensors(alpha=alpha, h=h, c=c, sigma_v2=sigma_v2)
    _positive("h", s["h"], "a channel gain magnitude")
    _positive("sigma_v2", s["sigma_v2"])
    sigma_n2 = _nonneg("sigma_n2", sigma_n2, "a variance")
    ah = s["alpha"] * s["h"]
    c, sv = s["c"], s["sigma_v2"]
    with np.errstate(over="ignore", invalid="ignore", divide="ignore", under="ignore"):
        if access == "multi-access":
            num = np.sum(ah * c, axis=-1) ** 2
            den0 = np.sum(ah**2 * sv, axis=-1) + sigma_n2
            out = num / den0
            bad = ~np.isfinite(out) | (den0 < _SMALL)  # overflow, or digits lost to underflow
            if np.any(bad):
                # (alpha h)^2 overflowed, or 0/0 with sigma_n2 = 0: divide through by the
                # largest |alpha_i h_i| (S is then a ratio of order-one sums)
                amax = np.max(np.abs(ah), axis=-1, keepdims=True)
                u = ah / np.where(amax > 0, amax, 1.0)
                am = np.where(amax > 0, amax, 1.0)[..., 0]
                den = np.sum(u**2 * sv, axis=-1) + sigma_n2 / am / am
                scaled = np.where(amax[..., 0] > 0, np.sum(u * c, axis=-1) ** 2 / den, 0.0)
                out = np.where(bad, scaled, out)
        else:
            den0 = ah**2 * sv + sigma_n2[..., None]
            term = ah**2 * c**2 / den0
            bad = ~np.isfinite(term) | (den0 < _SMALL)
            if np.any(bad):  # c^2 / (sigma_v2 + sigma_n2 / (alpha h)^2); alpha_i = 0 sends nothing
                aa = np.abs(np.where(ah != 0, ah, 1.0))
                alt = np.where(ah != 0, c**2 / (sv + sigma_n2[..., None] / aa / aa), 0.0)
                term = np.where(bad, alt, term)
            out = np.sum(term, axis=-1)
    return out[()] if np.ndim(out) == 0 else out


# ======================================================================== asymptotics
def symmetric_asymptotics(access, scaling, a, sigma_w2, h, c, sigma_v2, sigma_n2):
    """``(limit, coefficient)`` with ``P_inf = limit + coefficient / M + O(1/M^2)``.

    Symmetric sensors (scalars ``h``, ``c``, ``sigma_v2``); ``scaling`` is ``"none"``
    (``alpha_i = 1``) or ``"sqrt"`` (``alpha_i = 1/sqrt(M)``):

    * multi-access, none:  Lemma 3 / (11): ``(sigma_w2, a^2 sigma_v2 / c^2)``
    * orthogonal, none:    (12):           ``(sigma_w2, a^2 (sigma_v2 + sigma_n2/h^2) / c^2)``
    * multi-access, sqrt:  (13):           the same as (12)
    * orthogonal, sqrt:    (14): the limit exceeds ``sigma_w2`` (no 1/M law to ``sigma_w2``).

    Parameters
    ----------
    access : str
        ``"multi-access"`` or ``"orthogonal"``.
    scaling : str
        ``"none"`` or ``"sqrt"``.
    a : array_like
        State transition, finite (``|a| >= 1`` allowed when ``S > 0``).
    sigma_w2 : array_like
        Process-noise variance, ``>= 0`` (``0``: deterministic dynamics).
    h, c, sigma_v2 : array_like
        Scalars: ``h > 0``, ``c != 0``, ``sigma_v2 > 0``.
    sigma_n2 : array_like
        Receiver-noise variance, ``>= 0`` (``0``: an ideal channel).

    Returns
    -------
    limit, coefficient : numpy.ndarray

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
    """
    access = _access(access)
    if scaling not in ("none", "sqrt"):
        raise ValueError(f"scaling must be 'none' or 'sqrt', got {scaling!r}")
    a = _a(a, stable=False)
    sw = _nonneg("sigma_w2", sigma_w2, "a variance")
    h = _positive("h", h, "a channel gain magnitude")
    c = _finite("c", c)
    if np.any(c == 0):
        raise ValueError("c must be non-zero for a 1/M law")
    sv = _positive("sigma_v2", sigma_v2)
    sn = _nonneg("sigma_n2", sigma_n2, "a variance")
    if access == "orthogonal" and scaling == "sqrt" and np.any((sw == 0) & (sn == 0)):
        raise ValueError("sigma_w2 and sigma_n2 must not both be 0 for (14): its 1/M "
                         "coefficient divides by their combination")
    if access == "multi-access" and scaling == "none":
        return sw, a**2 * sv / c**2
    if scaling == "none" or access == "multi-access":
        return sw, a**2 * (sv + sn / h**2) / c**2
    # (14)
    root = np.sqrt((a**2 - 1) ** 2 * sn**2 + 2 * (a**2 + 1) * sn * h**2 * c**2 * sw
                   + h**4 * c**4 * sw**2)
    limit = ((a**2 - 1) * sn + h**2 * c**2 * sw + root) / (2 * h**2 * c**2)
    coef = ((a**2 - 1) * sv / (2 * c**2)
            + ((a**2 + 1) * h**4 * sv * c**2 * sw + (a**2 - 1) ** 2 * sn * h**2 * sv)
            / (2 * h**2 * c**2 * root))
    return limit, coef


def lemma4_bounds(M, a, sigma_w2, sigma_n2, h_range, c_range, sigma_v2_range, *,
                  scaling: str = "sqrt", exact: bool = False):
    """Bounds on the multi-access ``P_inf`` for general sensors (Lemma 4), ``(lower, upper)``.

    Ranges are ``(min, max)`` of ``h_i``, ``|c_i|`` and ``sigma_v2_i``; ``alpha_i = +-1/sqrt(M)``
    (``scaling="sqrt"``, eq. (37)) or ``+-1`` (``"none"``) with ``alpha_i c_i > 0``.

    ``exact=False`` gives the printed asymptotic bounds ``sigma_w2 + a^2 r_lo / M`` and
    ``sigma_w2 + a^2 r_hi / M`` (dropping their O(1/M^2) terms). ``exact=True`` gives
    ``steady_state`` at the smallest and largest SNR the ranges allow, which bound ``P_inf`` for
    every ``M`` (Lemma 1). The printed upper bound is itself exact (``P_inf < sigma_w2 + a^2/S``
    for every S > 0); the printed lower bound is not guaranteed for small ``M``.

    Parameters
    ----------
    M : array_like
        Number of sensors, ``> 0``.
    a : array_like
        State transition, finite (``|a| >= 1`` allowed when ``S > 0``).
    sigma_w2 : array_like
        Process-noise variance, ``>= 0`` (``0``: deterministic dynamics).
    sigma_n2 : array_like
        Receiver-noise variance, ``>= 0`` (``0``: an ideal channel).
    h_range, c_range, sigma_v2_range : tuple
        ``(min, max)``, ``> 0``.
    scaling : str
        ``"sqrt"`` or ``"none"``.
    exact : bool
        Bounds valid for every ``M`` instead of the printed asymptotic ones.

    Returns
    -------
    lower, upper : numpy.ndarray

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
    """
    if scaling not in ("none", "sqrt"):
        raise ValueError(f"scaling must be 'none' or 'sqrt', got {scaling!r}")
    M = _positive("M", M, "a number of sensors")
    a = _a(a, stable=False)
    sw = _nonneg("sigma_w2", sigma_w2, "a variance")
    sn = _nonneg("sigma_n2", sigma_n2, "a variance")
    (h_lo, h_hi), (c_lo, c_hi), (s_lo, s_hi) = (
        _positive(n, r, "a range of positive values") for n, r in
        (("h_range", h_range), ("c_range", c_range), ("sigma_v2_range", sigma_v2_range)))
    # bounds on rbar / cbar^2 = 1/S, multiplied by M
    if scaling == "sqrt":
        lo = (h_lo**2 * s_lo + sn) / (h_hi**2 * c_hi**2)
        hi = (h_hi**2 * s_hi + sn) / (h_lo**2 * c_lo**2)
    else:
        lo = (h_lo**2 * s_lo + sn / M) / (h_hi**2 * c_hi**2)
        hi = (h_hi**2 * s_hi + sn / M) / (h_lo**2 * c_lo**2)
    if exact:
        return steady_state(a, sw, M / lo), steady_state(a, sw, M / hi)
    if scaling == "none":  # the printed constants drop sigma_n2 / M as O(1/M^2)
        lo = h_lo**2 * s_lo / (h_hi**2 * c_hi**2)
        hi = h_hi**2 * s_hi / (h_lo**2 * c_lo**2)
    return sw + a**2 * lo / M, sw + a**2 * hi / M


# ================================================================ the general problems
def _general(rho, tau, kappa_, sigma_n2):
    s = _sensors(rho=rho, tau=tau, kappa=kappa_)
    _positive("tau", s["tau"])
    _positive("kappa", s["kappa"], "a power per unit alpha^2")
    sn = _nonneg("sigma_n2", sigma_n2, "a variance")
    rho, tau, kap = np.broadcast_arrays(s["rho"], s["tau"], s["kappa"])
    return rho, tau, kap, sn


#: Why the minimum-power problems need receiver noise.
_IDEAL_CHANNEL = ("with an ideal channel (sigma_n2 = 0) the SNR does not depend on the scale of "
                  "alpha, so the infimum 0 of the power is approached but not attained")


def _noisy(sn):
    if np.any(sn == 0):
        raise ValueError(f"sigma_n2 must be positive for a minimum-power problem: "
                         f"{_IDEAL_CHANNEL}")
    return sn


def _xy(x, y, shape):
    x = _positive("x", x, "a2 D + sigma_w2 - D > 0")
    y = _positive("y", y, "D (D - sigma_w2) > 0")
    return np.broadcast_to(x, shape), np.broadcast_to(y, shape)


def _infeasible_message(total, target) -> str:
    return (f"infeasible: sum_i rho_i^2 / tau_i = {float(np.min(total)):.6g} must exceed "
            f"x / y = {float(np.max(target)):.6g} (condition (20))")


def _finish(alpha, feasible, infeasible, message):
    if infeasible not in ("raise", "nan"):
        raise ValueError(f"infeasible must be 'raise' or 'nan', got {infeasible!r}")
    if not np.all(feasible):
        if infeasible == "raise":
            raise InfeasibleError(message)
        alpha = np.where(feasible[..., None], alpha, np.nan)
    return alpha


def coherent_min_power(rho, tau, kappa, sigma_n2, x, y, *, infeasible: str = "raise"):
    """Problem (19): ``min sum alpha_i^2 kappa_i`` s.t. ``(sum alpha_i^2 tau_i + sigma_n2) x <=
    y (sum alpha_i rho_i)^2``. Returns the optimal ``alpha`` (the ``mu > 0`` branch of (21)).

    ``lambda`` solves ``sum lambda rho_i^2 / (kappa_i + lambda tau_i x) = 1/y`` (unique when
    (20) holds); ``alpha_i = mu rho_i / (2 (kappa_i + lambda tau_i x))`` with ``mu`` from the
    printed formula, and the minimum is ``lambda sigma_n2 x`` (22). Internally ``nu = 1/lambda``
    is found by Newton's method on ``1/F(nu) - y``, ``F(nu) = sum rho_i^2 / (nu kappa_i +
    x tau_i)``, which is concave and increasing, so the iterates from ``nu = 0`` increase
    monotonically to the root. Leading axes broadcast; ``infeasible="nan"`` returns NaN rows
    instead of raising :class:`InfeasibleError`.

    Parameters
    ----------
    rho : array_like
        ``(..., M)``, finite, not all zero.
    tau : array_like
        ``(..., M)``, ``> 0``.
    kappa : array_like
        ``(..., M)``, ``> 0``.
    sigma_n2 : array_like
        Receiver-noise variance, ``> 0`` (with an ideal channel the minimum power is not attained).
    x, y : array_like
        The constants of the constraint, ``> 0``.
    infeasible : str
        ``"raise"`` or ``"nan"``.

    Returns
    -------
    numpy.ndarray
        The amplification factors ``alpha`` ``(..., M)``.

    Raises
    ------
    InfeasibleError
        If the target cannot be met (a ``ValueError`` stating the threshold).
    ValueError
        Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
    """
    rho, tau, kap, sn = _general(rho, tau, kappa, sigma_n2)
    sn = _noisy(sn)
    lead = np.broadcast_shapes(rho.shape[:-1], np.shape(x), np.shape(y), np.shape(sn))
    x, y = _xy(x, y, lead)
    rho2 = rho**2
    xt = x[..., None] * tau
    total = np.sum(rho2 / tau, axis=-1)
    feasible = total > x / y
    nu = np.zeros(lead)
    with np.errstate(divide="ignore", invalid="ignore"):
        for _ in range(200):
            den = nu[..., None] * kap + xt
            F = np.sum(rho2 / den, axis=-1)
            dF = np.sum(rho2 * kap / den**2, axis=-1)  # = -F'(nu)
            step = (1.0 / F - y) / (-dF / F**2)  # phi / phi'
            step = np.where(feasible & (step > 0), step, 0.0)
            nu = nu + step
            if not np.any(step > 1e-15 * nu):
                break
        w = rho / (nu[..., None] * kap + xt)  # direction of (21)
        p_star = x * np.broadcast_to(sn, lead) / nu  # (22): lambda sigma_n2 x
        alpha = w * np.sqrt(p_star / np.sum(w**2 * kap, axis=-1))[..., None]
    return _finish(alpha, feasible, infeasible, _infeasible_message(total, x / y))


def coherent_max_snr(rho, tau, kappa, sigma_n2, gamma_total):
    """Problem (23): maximize ``(sum alpha_i rho_i)^2 / (sum alpha_i^2 tau_i + sigma_n2)``
    s.t. ``sum alpha_i^2 kappa_i <= gamma_total``.

    ``alpha_i^2 = gamma_total w_i^2 / sum_j w_j^2 kappa_j`` with ``w_i = rho_i / (kappa_i +
    gamma_total tau_i / sigma_n2)``: the generalized Rayleigh quotient's maximizer, scaled to
    use all the power. The maximal SNR is ``sum_i rho_i^2 gamma_total / (gamma_total tau_i +
    kappa_i sigma_n2)``. **Erratum**: the printed (24) divides by ``kappa_j`` inside the sum and
    by ``kappa_i`` outside; that misses the power budget and is suboptimal unless all
    ``kappa_i`` are equal, and spends ``gamma_total`` only if moreover every ``kappa_i = 1``
    (see :func:`coherent_max_snr_printed`).

    Parameters
    ----------
    rho : array_like
        ``(..., M)``, finite, not all zero.
    tau : array_like
        ``(..., M)``, ``> 0``.
    kappa : array_like
        ``(..., M)``, ``> 0``.
    sigma_n2 : array_like
        Receiver-noise variance, ``>= 0`` (``0``: an ideal channel).
    gamma_total : array_like
        Total power, ``>= 0`` (``0``: nothing is sent).

    Returns
    -------
    numpy.ndarray
        The amplification factors ``alpha`` ``(..., M)``.

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
    """
    rho, tau, kap, sn = _general(rho, tau, kappa, sigma_n2)
    g = _nonneg("gamma_total", gamma_total, "a power")
    g_, sn_ = np.asarray(g)[..., None], np.asarray(sn)[..., None]
    if np.any(sn_ == 0):  # ideal channel: the limit sigma_n2 -> 0 of the direction, rho / tau
        with np.errstate(divide="ignore", invalid="ignore"):
            w = np.where(sn_ == 0, rho / tau, rho / (kap + g_ * tau / np.where(sn_ == 0, 1.0,
                                                                             sn_)))
    else:
        w = rho / (kap + g_ * tau / sn_)
    norm = np.sum(w**2 * kap, axis=-1)
    if np.any(norm == 0):
        raise ValueError("rho must have a non-zero entry (otherwise S = 0 whatever alpha)")
    return w * np.sqrt(g / norm)[..., None]


def coherent_max_snr_printed(rho, tau, kappa, sigma_n2, gamma_total):
    """Eq. (24) *as printed* (positive roots, signs of ``rho``): kept to document the erratum.

    ``alpha_i^2 = gamma (sum_j rho_j^2 / ((kappa_j + gamma tau_j / sigma_n2)^2 kappa_j))^-1
    rho_i^2 / ((kappa_i + gamma tau_i / sigma_n2)^2 kappa_i)``. Its direction is optimal only
    when all ``kappa_i`` are equal, and then it spends ``kappa gamma_total``: it is the optimum
    only if every ``kappa_i = 1``. Use :func:`coherent_max_snr`.

    Parameters
    ----------
    rho : array_like
        ``(..., M)``, finite, not all zero.
    tau : array_like
        ``(..., M)``, ``> 0``.
    kappa : array_like
        ``(..., M)``, ``> 0``.
    sigma_n2 : array_like
        ``> 0``.
    gamma_total : array_like
        ``> 0``.

    Returns
    -------
    numpy.ndarray
        The amplification factors ``alpha`` ``(..., M)``.

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
    """
    rho, tau, kap, sn = _general(rho, tau, kappa, sigma_n2)
    sn = _positive("sigma_n2", sn)
    g = _positive("gamma_total", gamma_total, "a power")
    g_, sn_ = np.asarray(g)[..., None], np.asarray(sn)[..., None]
    q = rho**2 / ((kap + g_ * tau / sn_) ** 2 * kap)
    return np.sign(rho) * np.sqrt(g_ * q / np.sum(q, axis=-1, keepdims=True))


def _others(v, active):
    """``sum_{j active, j != i} v_j`` for every ``i`` (prefix + suffix sums: no cancellation
    against a dominant ``v_i``)."""
    vm = np.where(active, v, 0.0)
    zero = np.zeros(vm.shape[:-1] + (1,))
    before = np.concatenate([zero, np.cumsum(vm, axis=-1)[..., :-1]], axis=-1)
    after = np.concatenate([np.cumsum(vm[..., ::-1], axis=-1)[..., -2::-1], zero], axis=-1)
    return before + after


def _unsort(v, order):
    out = np.empty_like(v)
    np.put_along_axis(out, order, v, axis=-1)
    return out


def _sorted_by_quality(rho, tau, kap):
    """Sort sensors by ``rho_i^2 / kappa_i`` (descending) along the last axis."""
    order = np.argsort(-(rho**2 / kap), axis=-1, kind="stable")
    return tuple(np.take_along_axis(v, order, axis=-1) for v in (np.abs(rho), tau, kap)) + (
        order,)


def orthogonal_min_power(rho, tau, kappa, sigma_n2, x, y, *, infeasible: str = "raise",
                         return_m1: bool = False):
    """Problem (26): ``min sum alpha_i^2 kappa_i`` s.t. ``sum alpha_i^2 rho_i^2 / (alpha_i^2
    tau_i + sigma_n2) >= x / y``; returns ``alpha >= 0`` (and ``M_1`` with ``return_m1``).

    Water-filling (27), corrected: ``alpha_i^2 = (sqrt(lambda rho_i^2 sigma_n2 / kappa_i) -
    sigma_n2)^+ / tau_i`` (the printed (27) puts ``- sigma_n2`` inside the square root), with
    ``sqrt(lambda) = sum_{i<=M_1} |rho_i| sqrt(kappa_i sigma_n2) / tau_i / (sum_{i<=M_1}
    rho_i^2 / tau_i - x/y)`` for sensors sorted by ``rho_i^2 / kappa_i``. ``M_1`` is the number
    of sensors the KKT conditions keep on: the ``m`` for which sensor ``m`` is on and sensor
    ``m + 1`` is off under ``lambda(m)``.

    Parameters
    ----------
    rho : array_like
        ``(..., M)``, finite, not all zero.
    tau : array_like
        ``(..., M)``, ``> 0``.
    kappa : array_like
        ``(..., M)``, ``> 0``.
    sigma_n2 : array_like
        Receiver-noise variance, ``> 0`` (with an ideal channel the minimum power is not attained).
    x, y : array_like
        The constants of the constraint, ``> 0``.
    infeasible : str
        ``"raise"`` or ``"nan"``.
    return_m1 : bool
        Also return ``M_1``.

    Returns
    -------
    numpy.ndarray
        The amplification factors ``alpha`` ``(..., M)``.

    Raises
    ------
    InfeasibleError
        If the target cannot be met (a ``ValueError`` stating the threshold).
    ValueError
        Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
    """
    rho, tau, kap, sn = _general(rho, tau, kappa, sigma_n2)
    sn = _noisy(sn)
    lead = np.broadcast_shapes(rho.shape[:-1], np.shape(x), np.shape(y), np.shape(sn))
    x, y = _xy(x, y, lead)
    sn = np.broadcast_to(sn, lead)
    sig = np.sqrt(sn)[..., None]
    r, t, k, order = _sorted_by_quality(rho, tau, kap)
    r, t, k, order = (np.broadcast_to(v, lead + rho.shape[-1:]) for v in (r, t, k, order))
    A = np.cumsum(r * np.sqrt(k) * sig / t, axis=-1)
    E = np.cumsum(r**2 / t, axis=-1) - (x / y)[..., None]
    feasible = E[..., -1] > 0
    q = r / np.sqrt(k)  # sensor i is on under lambda iff sqrt(lambda) q_i > sigma_n
    with np.errstate(divide="ignore", invalid="ignore"):
        sqrt_lam = np.where(E > 0, A / E, np.inf)
        on_m = (E > 0) & (sqrt_lam * q > sig)
        q_next = np.concatenate([q[..., 1:], np.zeros(q.shape[:-1] + (1,))], axis=-1)
        next_off = ~(sqrt_lam * q_next > sig)
        valid = on_m & next_off
        m1 = np.argmax(valid, axis=-1)  # first consistent m (the KKT point is unique)
        # alpha_i^2 = (sigma_n / tau_i) (sqrt(lambda) q_i - sigma_n), rewritten without the
        # cancellation of the two terms (w_j = kappa_j / tau_j reaches 1e13 when a sensor's
        # sigma_v2 is tiny): sigma_n2 (q_i Q_-i - R_-i + x/y) / (tau_i E), sums over the
        # other active sensors.
        active = np.arange(r.shape[-1]) <= m1[..., None]
        w = k / t
        Em = np.take_along_axis(E, m1[..., None], axis=-1)
        num = q * _others(w * q, active) - _others(w * q**2, active) + (x / y)[..., None]
        a2 = np.where(active, np.maximum(sn[..., None] * num / (t * Em), 0.0), 0.0)
        a2 = _unsort(a2, order)
    alpha = _finish(np.sqrt(a2), feasible & np.any(valid, axis=-1), infeasible,
                    _infeasible_message(E[..., -1] + x / y, x / y))
    return (alpha, m1 + 1) if return_m1 else alpha


def orthogonal_max_snr(rho, tau, kappa, sigma_n2, gamma_total, *, return_m1: bool = False):
    """Problem (28): maximize ``S^o = sum alpha_i^2 rho_i^2 / (alpha_i^2 tau_i + sigma_n2)``
    s.t. ``sum alpha_i^2 kappa_i <= gamma_total``; returns ``alpha >= 0``.

    Water-filling (29): ``alpha_i^2 = (sqrt(rho_i^2 sigma_n2 / (lambda kappa_i)) -
    sigma_n2)^+ / tau_i`` with ``1/sqrt(lambda) = (gamma_total + sum_{i<=M_1} kappa_i sigma_n2 /
    tau_i) / sum_{i<=M_1} |rho_i| sqrt(kappa_i sigma_n2) / tau_i``; ``M_1`` is the last ``m``
    whose sensor is on under ``lambda(m)`` (the printed rule).

    Parameters
    ----------
    rho : array_like
        ``(..., M)``, finite, not all zero.
    tau : array_like
        ``(..., M)``, ``> 0``.
    kappa : array_like
        ``(..., M)``, ``> 0``.
    sigma_n2 : array_like
        Receiver-noise variance, ``>= 0`` (``0``: an ideal channel).
    gamma_total : array_like
        Total power, ``>= 0`` (``0``: nothing is sent).
    return_m1 : bool
        Also return ``M_1`` (0 when ``gamma_total = 0``).

    Returns
    -------
    numpy.ndarray
        The amplification factors ``alpha`` ``(..., M)``.

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
    """
    rho, tau, kap, sn = _general(rho, tau, kappa, sigma_n2)
    g = _nonneg("gamma_total", gamma_total, "a power")
    lead = np.broadcast_shapes(rho.shape[:-1], np.shape(g), np.shape(sn))
    g, sn = np.broadcast_to(g, lead), np.broadcast_to(sn, lead)
    if np.any(sn == 0):
        return _orthogonal_max_snr_ideal(rho, tau, kap, g, sn, lead, return_m1)
    sig = np.sqrt(sn)[..., None]
    r, t, k, order = _sorted_by_quality(rho, tau, kap)
    r, t, k, order = (np.broadcast_to(v, lead + rho.shape[-1:]) for v in (r, t, k, order))
    A = np.cumsum(r * np.sqrt(k) * sig / t, axis=-1)
    B = g[..., None] + np.cumsum(k * sn[..., None] / t, axis=-1)
    if np.any(A[..., -1] == 0):
        raise ValueError("rho must have a non-zero entry (otherwise S = 0 whatever alpha)")
    with np.errstate(divide="ignore", invalid="ignore"):
        inv_sqrt_lam = B / A
        on = inv_sqrt_lam * r / np.sqrt(k) > sig
    m1 = on.shape[-1] - 1 - np.argmax(on[..., ::-1], axis=-1)  # last m that is on
    # gamma_total / (sigma_n2 kappa_1 / tau_1) below the float resolution makes even the best
    # sensor test "off" by rounding; it is always on when gamma_total > 0
    m1 = np.where(np.any(on, axis=-1), m1, 0)
    # alpha_i^2 = (sigma_n / tau_i) (q_i / sqrt(lambda) - sigma_n), rewritten without
    # cancellation: (q_i gamma + sigma_n2 (q_i W_-i - Q_-i)) / (tau_i Q), w_j = kappa_j / tau_j.
    active = np.arange(r.shape[-1]) <= m1[..., None]
    q = r / np.sqrt(k)
    w = k / t
    Q = np.sum(np.where(active, w * q, 0.0), axis=-1, keepdims=True)
    num = q * g[..., None] + sn[..., None] * (q * _others(w, active) - _others(w * q, active))
    a2 = _unsort(np.where(active, np.maximum(num / (t * Q), 0.0), 0.0), order)
    alpha = np.sqrt(a2)
    if np.any(g == 0):  # no power: every sensor off (the rule above is a tie at gamma = 0)
        alpha = np.where(g[..., None] == 0, 0.0, alpha)
        m1 = np.where(g == 0, -1, m1)
    return (alpha, m1 + 1) if return_m1 else alpha


def _orthogonal_max_snr_ideal(rho, tau, kap, g, sn, lead, return_m1):
    """(28) where some ``sigma_n2 = 0``: the limit of (29) as ``sigma_n2 -> 0``.

    Every sensor with ``rho_i != 0`` is on and ``alpha_i^2 = gamma q_i / (tau_i Q)`` with
    ``q_i = |rho_i| / sqrt(kappa_i)``, ``Q = sum_j kappa_j q_j / tau_j`` (the power is spent
    exactly; the SNR is ``sum_{rho_i != 0} rho_i^2 / tau_i``). Instances with ``sigma_n2 > 0``
    are solved as usual.
    """
    rho, tau, kap = (np.broadcast_to(v, lead + rho.shape[-1:]) for v in (rho, tau, kap))
    if np.any(np.all(rho == 0, axis=-1)):
        raise ValueError("rho must have a non-zero entry (otherwise S = 0 whatever alpha)")
    q = np.abs(rho) / np.sqrt(kap)
    Q = np.sum(kap * q / tau, axis=-1, keepdims=True)
    ideal = np.sqrt(g[..., None] * q / (tau * Q))
    m_ideal = np.sum(rho != 0, axis=-1)
    noisy = sn > 0
    if np.any(noisy):
        alpha, m1 = orthogonal_max_snr(rho[noisy], tau[noisy], kap[noisy], sn[noisy], g[noisy],
                                       return_m1=True)
        ideal[noisy] = alpha
        m_ideal[noisy] = m1
    return (ideal, m_ideal) if return_m1 else ideal


# ===================================================================== static channels
def static_coefficients(a, sigma_w2, h, c, sigma_v2):
    """``(rho, tau, kappa)`` of problems (19)/(26) for static channels with CSI:
    ``rho_i = h_i c_i``, ``tau_i = h_i^2 sigma_v2_i``, ``kappa_i = c_i^2 sigma_w2/(1-a^2) +
    sigma_v2_i``.

    Parameters
    ----------
    a : array_like
        State transition, ``|a| < 1``.
    sigma_w2 : array_like
        Process-noise variance, ``>= 0`` (``0``: deterministic dynamics).
    h : array_like
        Channel gains ``(..., M)``, ``> 0``.
    c : array_like
        Measurement gains ``(..., M)``, finite.
    sigma_v2 : array_like
        Measurement-noise variances ``(..., M)``, ``> 0``.

    Returns
    -------
    rho, tau, kappa : numpy.ndarray

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
    """
    s = _sensors(h=h, c=c, sigma_v2=sigma_v2)
    _positive("h", s["h"], "a channel gain magnitude")
    _positive("sigma_v2", s["sigma_v2"])
    return s["h"] * s["c"], s["h"] ** 2 * s["sigma_v2"], kappa(a, sigma_w2, s["c"],
                                                                s["sigma_v2"])


def _xy_of(D, a, sigma_w2):
    a = _a(a)
    sigma_w2 = _positive("sigma_w2", sigma_w2, _TARGET_NEEDS_NOISE)
    D = _check_D(D, a, sigma_w2)
    return a**2 * D + sigma_w2 - D, D * (D - sigma_w2)


def _threshold_message(D, a, sigma_w2, c, sigma_v2, access) -> str:
    total = np.sum(np.asarray(c, float) ** 2 / np.asarray(sigma_v2, float), axis=-1)
    thr = required_snr(D, a, sigma_w2)
    return (f"target D = {float(np.max(D)):g} is infeasible for {access}: the sum of the sensor "
            f"SNRs sum_i c_i^2 / sigma_v2_i = {float(np.min(total)):.6g} must exceed "
            f"(a^2 D + sigma_w2 - D) / (D (D - sigma_w2)) = {float(np.max(thr)):.6g} "
            f"(condition (20))")


def min_power(access, D, a, sigma_w2, h, c, sigma_v2, sigma_n2) -> np.ndarray:
    """Least total transmit power with ``P_inf <= D``: problem (18) (multi-access) or (25)
    (orthogonal). Returns ``alpha``; raises :class:`InfeasibleError` if (20) fails.

    Parameters
    ----------
    access : str
        ``"multi-access"`` or ``"orthogonal"``.
    D : array_like
        Error target, strictly between ``sigma_w2`` and ``sigma_w2 / (1 - a^2)``.
    a : array_like
        State transition, ``|a| < 1``.
    sigma_w2 : array_like
        Process-noise variance, ``> 0`` (with 0 no error target exists).
    h : array_like
        Channel gains ``(..., M)``, ``> 0``.
    c : array_like
        Measurement gains ``(..., M)``, finite.
    sigma_v2 : array_like
        Measurement-noise variances ``(..., M)``, ``> 0``.
    sigma_n2 : array_like
        Receiver-noise variance, ``> 0`` (with an ideal channel the minimum power is not attained).

    Returns
    -------
    numpy.ndarray
        The amplification factors ``alpha`` ``(..., M)``.

    Raises
    ------
    InfeasibleError
        If the target cannot be met (a ``ValueError`` stating the threshold).
    ValueError
        Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
    """
    access = _access(access)
    x, y = _xy_of(D, a, sigma_w2)
    rho, tau, kap = static_coefficients(a, sigma_w2, h, c, sigma_v2)
    sn = _positive("sigma_n2", sigma_n2, f"a variance; {_IDEAL_CHANNEL}")
    solver = coherent_min_power if access == "multi-access" else orthogonal_min_power
    alpha = solver(rho, tau, kap, sn, x, y, infeasible="nan")
    if np.any(np.isnan(alpha)):
        raise InfeasibleError(_threshold_message(D, a, sigma_w2, c, sigma_v2, access))
    return alpha


def min_error(access, gamma_total, a, sigma_w2, h, c, sigma_v2, sigma_n2) -> np.ndarray:
    """Least ``P_inf`` with total power ``<= gamma_total``: problem (23) (multi-access) or (28)
    (orthogonal), both maximizing the SNR (Lemmas 1, 2). Returns ``alpha``.

    Parameters
    ----------
    access : str
        ``"multi-access"`` or ``"orthogonal"``.
    gamma_total : array_like
        Total power, ``>= 0`` (``0``: nothing is sent).
    a : array_like
        State transition, ``|a| < 1``.
    sigma_w2 : array_like
        Process-noise variance, ``>= 0`` (``0``: deterministic dynamics).
    h : array_like
        Channel gains ``(..., M)``, ``> 0``.
    c : array_like
        Measurement gains ``(..., M)``, finite.
    sigma_v2 : array_like
        Measurement-noise variances ``(..., M)``, ``> 0``.
    sigma_n2 : array_like
        Receiver-noise variance, ``>= 0`` (``0``: an ideal channel).

    Returns
    -------
    numpy.ndarray
        The amplification factors ``alpha`` ``(..., M)``.

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
    """
    access = _access(access)
    rho, tau, kap = static_coefficients(a, sigma_w2, h, c, sigma_v2)
    sn = _nonneg("sigma_n2", sigma_n2, "a variance")
    if access == "multi-access":
        return coherent_max_snr(rho, tau, kap, sn, gamma_total)
    return orthogonal_max_snr(rho, tau, kap, sn, gamma_total)


def equal_power(a, sigma_w2, c, sigma_v2, *, gamma=None, gamma_total=None) -> np.ndarray:
    """Equal-power allocation: (15) with power ``gamma`` per sensor, or (16) sharing
    ``gamma_total`` equally among the ``M`` sensors.

    ``alpha_i = sign(c_i) sqrt(gamma (1 - a^2) / (c_i^2 sigma_w2 + sigma_v2_i (1 - a^2)))``: the
    sign makes ``alpha_i c_i >= 0`` as in the proof of Lemma 4, so that the multi-access sum is
    coherent (the paper's (15) writes the positive root; with ``c_i > 0`` they agree).

    Parameters
    ----------
    a : array_like
        State transition, ``|a| < 1``.
    sigma_w2 : array_like
        Process-noise variance, ``>= 0`` (``0``: deterministic dynamics).
    c, sigma_v2 : array_like
        As in :func:`kappa`.
    gamma : array_like, optional
        Power per sensor, ``>= 0``.
    gamma_total : array_like, optional
        Total power shared equally, ``>= 0``.

    Returns
    -------
    numpy.ndarray
        The amplification factors ``alpha`` ``(..., M)``.

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
    """
    if (gamma is None) == (gamma_total is None):
        raise ValueError("give exactly one of gamma (per sensor, (15)) and gamma_total ((16))")
    kap = kappa(a, sigma_w2, c, sigma_v2)
    if gamma is None:
        per = _nonneg("gamma_total", gamma_total, "a power")[..., None] / kap.shape[-1]
    else:
        per = _nonneg("gamma", gamma, "a power")[..., None]
    sign = np.where(np.asarray(c, dtype=float) < 0, -1.0, 1.0)
    return sign * np.sqrt(per / kap)


def equal_power_min_power(access, D, a, sigma_w2, h, c, sigma_v2, sigma_n2) -> np.ndarray:
    """Least common per-sensor power (15) with ``P_inf <= D``; returns ``alpha``.

    The SNR with ``alpha_i = sign(c_i) sqrt(gamma / kappa_i)`` increases with ``gamma`` to a
    ceiling: multi-access ``(sum h_i |c_i| / sqrt(kappa_i))^2 / sum h_i^2 sigma_v2_i /
    kappa_i`` (then ``gamma`` solves a linear equation), orthogonal ``sum c_i^2 / sigma_v2_i``
    (the same as the optimal allocation's; ``gamma`` by bisection on the monotone SNR). Raises
    :class:`InfeasibleError` if the target is above the ceiling. Leading axes broadcast; with
    several instances, infeasible ones give NaN rows (and no error) when any is feasible.

    Parameters
    ----------
    access : str
        ``"multi-access"`` or ``"orthogonal"``.
    D : array_like
        Error target, strictly between ``sigma_w2`` and ``sigma_w2 / (1 - a^2)``.
    a : array_like
        State transition, ``|a| < 1``.
    sigma_w2 : array_like
        Process-noise variance, ``> 0`` (with 0 no error target exists).
    h : array_like
        Channel gains ``(..., M)``, ``> 0``.
    c : array_like
        Measurement gains ``(..., M)``, finite.
    sigma_v2 : array_like
        Measurement-noise variances ``(..., M)``, ``> 0``.
    sigma_n2 : array_like
        Receiver-noise variance, ``> 0`` (with an ideal channel the minimum power is not attained).

    Returns
    -------
    numpy.ndarray
        The amplification factors ``alpha`` ``(..., M)``.

    Raises
    ------
    InfeasibleError
        If the target cannot be met (a ``ValueError`` stating the threshold).
    ValueError
        Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
    """
    access = _access(access)
    x, y = _xy_of(D, a, sigma_w2)
    rho, tau, kap = static_coefficients(a, sigma_w2, h, c, sigma_v2)
    sn = _positive("sigma_n2", sigma_n2)
    target = x / y
    rho, tau, kap = np.broadcast_arrays(rho, tau, kap)
    lead = rho.shape[:-1]
    target = np.broadcast_to(target, lead)
    sn_b = np.broadcast_to(sn, lead)
    if access == "multi-access":
        u = np.abs(rho) / np.sqrt(kap)  # alpha_i rho_i = sqrt(gamma) u_i
        v = tau / kap
        U2, V = np.sum(u, axis=-1) ** 2, np.sum(v, axis=-1)
        ceiling = U2 / V
        with np.errstate(divide="ignore", invalid="ignore"):
            gamma = target * sn_b / (U2 - target * V)
    else:
        ceiling = np.sum(rho**2 / tau, axis=-1)
        ok = ceiling > target
        lo = np.zeros(lead)
        hi = np.ones(lead) * np.where(ok, 1.0, np.nan)

        def s_of(g):
            a2 = g[..., None] / kap
            return np.sum(a2 * rho**2 / (a2 * tau + sn_b[..., None]), axis=-1)

        with np.errstate(invalid="ignore"):
            for _ in range(400):  # grow the bracket
                short = ok & (s_of(hi) < target)
                if not np.any(short):
                    break
                hi = np.where(short, 2 * hi, hi)
            for _ in range(200):
                mid = 0.5 * (lo + hi)
                below = s_of(mid) < target
                lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
                if np.all(~ok | (hi - lo <= 1e-15 * hi)):
                    break
        gamma = hi
    feasible = ceiling > target
    if not np.any(feasible):
        raise InfeasibleError(
            f"target D = {float(np.max(D)):g} is infeasible for equal power ({access}): the SNR "
            f"ceiling {float(np.max(ceiling)):.6g} must exceed (a^2 D + sigma_w2 - D) / "
            f"(D (D - sigma_w2)) = {float(np.max(target)):.6g}")
    gamma = np.where(feasible, gamma, np.nan)
    sign = np.where(np.asarray(rho) < 0, -1.0, 1.0)
    return sign * np.sqrt(gamma[..., None] / kap)


# ======================================================================= fading with CSI
def _csi_xy(P, D, a, sigma_w2):
    """``x_k = a^2 P_k + sigma_w2 - D`` and ``y_k = P_k (D - sigma_w2)`` of (30)."""
    a = _a(a)
    sigma_w2 = _positive("sigma_w2", sigma_w2, _TARGET_NEEDS_NOISE)
    D = _check_D(D, a, sigma_w2)
    P = _positive("P", P, "a prediction variance")
    return a**2 * P + sigma_w2 - D, P * (D - sigma_w2)


def csi_min_power_step(access, P, D, a, sigma_w2, h, c, sigma_v2, sigma_n2, *,
                       infeasible: str = "raise") -> np.ndarray:
    """One greedy step of (30) (or its orthogonal counterpart): the least sum power with
    ``P_{k+1} <= D`` given ``P_k = P`` and this step's channel gains ``h``. Returns ``alpha``.

    When ``a^2 P + sigma_w2 <= D`` the target is met without transmitting (``alpha = 0``).
    Feasibility needs ``sum c_i^2 / sigma_v2_i > (a^2 P + sigma_w2 - D) / (P (D - sigma_w2))``,
    which does not depend on the channel gains.

    Parameters
    ----------
    access : str
        ``"multi-access"`` or ``"orthogonal"``.
    P : array_like
        ``P_k``, ``> 0``.
    D : array_like
        Error target, strictly between ``sigma_w2`` and ``sigma_w2 / (1 - a^2)``.
    a : array_like
        State transition, ``|a| < 1``.
    sigma_w2 : array_like
        Process-noise variance, ``> 0`` (with 0 no error target exists).
    h : array_like
        Channel gains ``(..., M)``, ``> 0``.
    c : array_like
        Measurement gains ``(..., M)``, finite.
    sigma_v2 : array_like
        Measurement-noise variances ``(..., M)``, ``> 0``.
    sigma_n2 : array_like
        Receiver-noise variance, ``> 0`` (with an ideal channel the minimum power is not attained).
    infeasible : str
        ``"raise"`` or ``"nan"``.

    Returns
    -------
    numpy.ndarray
        The amplification factors ``alpha`` ``(..., M)``.

    Raises
    ------
    InfeasibleError
        If the target cannot be met (a ``ValueError`` stating the threshold).
    ValueError
        Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
    """
    access = _access(access)
    x, y = _csi_xy(P, D, a, sigma_w2)
    rho, tau, kap = static_coefficients(a, sigma_w2, h, c, sigma_v2)
    sn = _positive("sigma_n2", sigma_n2)
    free = x <= 0
    xs = np.where(free, 1.0, x)
    solver = coherent_min_power if access == "multi-access" else orthogonal_min_power
    alpha = solver(rho, tau, kap, sn, xs, y, infeasible=infeasible)
    return np.where(np.asarray(free)[..., None], 0.0, alpha)


def csi_min_error_step(access, gamma_total, a, sigma_w2, h, c, sigma_v2, sigma_n2):
    """One greedy step of (31) (or its orthogonal counterpart): maximize this step's SNR with
    power ``gamma_total``; it does not depend on ``P_k``. Returns ``alpha``.

    Parameters
    ----------
    access : str
        ``"multi-access"`` or ``"orthogonal"``.
    gamma_total : array_like
        Total power, ``>= 0`` (``0``: nothing is sent).
    a : array_like
        State transition, ``|a| < 1``.
    sigma_w2 : array_like
        Process-noise variance, ``>= 0`` (``0``: deterministic dynamics).
    h : array_like
        Channel gains ``(..., M)``, ``> 0``.
    c : array_like
        Measurement gains ``(..., M)``, finite.
    sigma_v2 : array_like
        Measurement-noise variances ``(..., M)``, ``> 0``.
    sigma_n2 : array_like
        Receiver-noise variance, ``>= 0`` (``0``: an ideal channel).

    Returns
    -------
    numpy.ndarray
        The amplification factors ``alpha`` ``(..., M)``.

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
    """
    return min_error(access, gamma_total, a, sigma_w2, h, c, sigma_v2, sigma_n2)


def _time_slices(h, c, sigma_v2):
    h = _positive("h", h, "a channel gain magnitude")
    if h.ndim < 2:
        raise ValueError(f"h must be shaped (..., steps, sensors), got {h.shape}")
    c = np.asarray(c, dtype=float)
    sv = np.asarray(sigma_v2, dtype=float)
    c = c[..., None, :] if c.ndim >= 1 else c
    sv = sv[..., None, :] if sv.ndim >= 1 else sv
    return h, c, sv


def greedy_min_power(access, D, a, sigma_w2, h, c, sigma_v2, sigma_n2, *, P0=None,
                     infeasible: str = "raise"):
    """Run the greedy scheme (30) over a fading sequence ``h`` shaped ``(..., steps, M)``.

    ``c`` and ``sigma_v2`` have the shape of one time slice (``(..., M)``). Returns ``(P,
    power)``: ``P`` shaped ``(..., steps + 1)`` (``P[..., 0] = P0``, default ``D``) and the sum
    power of each step ``(..., steps)``. Once a step has met the target with equality, ``P_k =
    D`` and every later step solves the same problem: those steps are solved together.

    Parameters
    ----------
    access : str
        ``"multi-access"`` or ``"orthogonal"``.
    D : array_like
        Error target, strictly between ``sigma_w2`` and ``sigma_w2 / (1 - a^2)``.
    a : array_like
        State transition, ``|a| < 1``.
    sigma_w2 : array_like
        Process-noise variance, ``> 0`` (with 0 no error target exists).
    h : array_like
        Channel gains ``(..., steps, M)``, ``> 0``.
    c, sigma_v2 : array_like
        One time slice ``(..., M)``.
    sigma_n2 : array_like
        Receiver-noise variance, ``> 0`` (with an ideal channel the minimum power is not attained).
    P0 : array_like, optional
        ``P_0`` (default ``D``).
    infeasible : str
        ``"raise"`` or ``"nan"``.

    Returns
    -------
    P, power : numpy.ndarray
        ``(..., steps + 1)`` and ``(..., steps)``.

    Raises
    ------
    InfeasibleError
        If the target cannot be met (a ``ValueError`` stating the threshold).
    ValueError
        Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
    """
    access = _access(access)
    h, c, sv = _time_slices(h, c, sigma_v2)
    steps = h.shape[-2]
    lead = h.shape[:-2]
    P = np.empty(lead + (steps + 1,))
    P[..., 0] = D if P0 is None else P0
    power = np.empty(lead + (steps,))
    kap = kappa(a, sigma_w2, c, sv)
    k = 0
    while k < steps:
        Pk = P[..., k]
        if np.all((np.abs(Pk - D) <= 1e-12 * D) | np.isnan(Pk)):  # NaN: infeasible path
            # every later step: the same x, y (P_k = D); solve them all at once
            alpha = csi_min_power_step(access, np.broadcast_to(D, lead)[..., None], D, a,
                                       sigma_w2, h[..., k:, :], c, sv, sigma_n2,
                                       infeasible=infeasible)
            S = snr(access, alpha, h[..., k:, :], c, sv, sigma_n2)
            P[..., k + 1:] = steady_recursion(D, a, sigma_w2, S)
            power[..., k:] = np.sum(alpha**2 * kap, axis=-1)
            break
        alpha = csi_min_power_step(access, Pk, D, a, sigma_w2, h[..., k, :], c[..., 0, :],
                                   sv[..., 0, :], sigma_n2, infeasible=infeasible)
        S = snr(access, alpha, h[..., k, :], c[..., 0, :], sv[..., 0, :], sigma_n2)
        P[..., k + 1] = steady_recursion(Pk, a, sigma_w2, S)
        power[..., k] = np.sum(alpha**2 * kap[..., 0, :], axis=-1)
        k += 1
    return P, power


def steady_recursion(P, a, sigma_w2, S):
    """One step of (4)/(5) in SNR form: ``a^2 P / (1 + P S) + sigma_w2`` (broadcasts).

    Parameters
    ----------
    P : array_like
        Prediction variance(s), ``>= 0``.
    a : array_like
        State transition(s), finite.
    sigma_w2 : array_like
        Process-noise variance(s), ``>= 0``.
    S : array_like
        Signal-to-noise ratio(s), ``>= 0``.

    Returns
    -------
    numpy.ndarray
        The next prediction variance(s).

    Raises
    ------
    ValueError
        If an argument is NaN, infinite or negative (``a`` excepted), or the result overflows.
    """
    P = _nonneg("P", P, "a prediction variance")
    a = _finite("a", a)
    sigma_w2 = _nonneg("sigma_w2", sigma_w2, "a variance")
    S = _nonneg("S", S, "a signal-to-noise ratio")
    with np.errstate(over="ignore", invalid="ignore"):
        out = a**2 * P / (1.0 + P * S) + sigma_w2
    return _finite_result("the next variance", out, "a^2 P overflows the float range")


def greedy_min_error(access, gamma_total, a, sigma_w2, h, c, sigma_v2, sigma_n2, *, P0=None):
    """Run the greedy scheme (31) over ``h`` shaped ``(..., steps, M)``: each step maximizes its
    SNR with power ``gamma_total``. Returns ``(P, S, power)``: ``P`` shaped ``(..., steps + 1)``
    (``P[..., 0] = P0``, default ``sigma_w2 / (1 - a^2)``), the per-step SNR and sum power
    ``(..., steps)``.

    Parameters
    ----------
    access : str
        ``"multi-access"`` or ``"orthogonal"``.
    gamma_total : array_like
        Total power, ``>= 0`` (``0``: nothing is sent).
    a : array_like
        State transition, ``|a| < 1``.
    sigma_w2 : array_like
        Process-noise variance, ``>= 0`` (``0``: deterministic dynamics).
    h : array_like
        Channel gains ``(..., steps, M)``, ``> 0``.
    c, sigma_v2 : array_like
        One time slice ``(..., M)``.
    sigma_n2 : array_like
        Receiver-noise variance, ``>= 0`` (``0``: an ideal channel).
    P0 : array_like, optional
        ``P_0`` (default the stationary variance).

    Returns
    -------
    P, S, power : numpy.ndarray

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
    """
    access = _access(access)
    h, c, sv = _time_slices(h, c, sigma_v2)
    alpha = min_error(access, gamma_total, a, sigma_w2, h, c, sv, sigma_n2)
    S = snr(access, alpha, h, c, sv, sigma_n2)
    spent = np.sum(alpha**2 * kappa(a, sigma_w2, c, sv), axis=-1)
    steps = h.shape[-2]
    P = np.empty(S.shape[:-1] + (steps + 1,))
    P[..., 0] = stationary_variance(a, sigma_w2) if P0 is None else P0
    for k in range(steps):
        P[..., k + 1] = steady_recursion(P[..., k], a, sigma_w2, S[..., k])
    return P, S, spent


# ==================================================================== fading without CSI
def beamformed(alpha, h_mean) -> np.ndarray:
    """``alpha~_i = alpha_i conj(E h~_i) / |E h~_i|``: beamforming on the mean channel.

    Parameters
    ----------
    alpha : array_like
        Real amplification factors ``(..., M)``.
    h_mean : array_like
        Complex channel means, non-zero.

    Returns
    -------
    numpy.ndarray
        Complex ``alpha~``.

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
    """
    s = _sensors(alpha=alpha, h_mean_abs=np.abs(np.asarray(h_mean)))
    m = np.asarray(h_mean, dtype=complex)
    if np.any(np.abs(m) == 0):
        raise ValueError("h_mean must be non-zero (zero-mean fading carries no information "
                         "to the linear estimator)")
    return s["alpha"] * np.conj(m) / np.abs(m)


def _channel_stats(alpha_t, h_mean, h_var_re, h_var_im):
    """Moments of ``g = alpha~ h~`` (independent real/imaginary parts of ``h~``)."""
    p, q = np.real(alpha_t), np.imag(alpha_t)
    mr, mi = np.real(h_mean), np.imag(h_mean)
    mean_re, mean_im = p * mr - q * mi, q * mr + p * mi
    var_re = p**2 * h_var_re + q**2 * h_var_im
    var_im = q**2 * h_var_re + p**2 * h_var_im
    cov = p * q * (h_var_re - h_var_im)
    return mean_re, mean_im, var_re, var_im, cov


def lmmse_matrices(access, alpha_t, a, sigma_w2, c, sigma_v2, sigma_n2, h_mean, h_var_re,
                   h_var_im):
    """``(Cbar, Rbar)`` of the linear MMSE estimator (32) without CSI.

    ``alpha_t`` complex amplification factors, ``h_mean`` the complex channel means and
    ``h_var_re``, ``h_var_im`` the variances of their real and imaginary parts (independent,
    i.i.d. over time). The observation is ``(Re z~, Im z~)``: multi-access gives ``Cbar`` shaped
    ``(..., 2)`` and ``Rbar`` ``(..., 2, 2)``; orthogonal stacks the sensors, ``Cbar`` ``(...,
    2M)`` and block-diagonal ``Rbar`` ``(..., 2M, 2M)``. ``Rbar`` includes the covariance
    ``Cov(Re g, Im g) (c_i^2 sigma_w2/(1-a^2) + sigma_v2_i)`` of the off-diagonal term, which
    the printed ``Rbar`` omits; it vanishes when ``Var Re h~ = Var Im h~`` (as in the paper's
    Rician example) or ``alpha~`` is real or imaginary.

    Parameters
    ----------
    access : str
        ``"multi-access"`` or ``"orthogonal"``.
    alpha_t : array_like
        Complex amplification factors ``(..., M)``.
    a : array_like
        State transition, ``|a| < 1``.
    sigma_w2 : array_like
        Process-noise variance, ``>= 0`` (``0``: deterministic dynamics).
    c, sigma_v2 : array_like
        Per-sensor gains (finite) and noise variances (``> 0``).
    sigma_n2 : array_like
        Receiver-noise variance, ``> 0``.
    h_mean : array_like
        Complex channel means ``(..., M)``, non-zero.
    h_var_re, h_var_im : array_like
        Variances of their real and imaginary parts, ``>= 0``.

    Returns
    -------
    Cbar, Rbar : numpy.ndarray

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
    """
    access = _access(access)
    s = _sensors(c=c, sigma_v2=sigma_v2, h_var_re=h_var_re, h_var_im=h_var_im,
                 alpha_abs=np.abs(np.asarray(alpha_t)), h_mean_abs=np.abs(np.asarray(h_mean)))
    _positive("sigma_v2", s["sigma_v2"])
    for name in ("h_var_re", "h_var_im"):
        if np.any(s[name] < 0):
            raise ValueError(f"{name} must be non-negative (it is a variance)")
    sn = _positive("sigma_n2", sigma_n2)
    Pi = stationary_variance(a, sigma_w2)
    alpha_t = np.asarray(alpha_t, dtype=complex)
    h_mean = np.asarray(h_mean, dtype=complex)
    c, sv = s["c"], s["sigma_v2"]
    mre, mim, vre, vim, cov = _channel_stats(alpha_t, h_mean, s["h_var_re"], s["h_var_im"])
    cx = c**2 * Pi
    r11 = vre * cx + (vre + mre**2) * sv
    r22 = vim * cx + (vim + mim**2) * sv
    r12 = cov * cx + (cov + mre * mim) * sv
    if access == "multi-access":
        C = np.stack([np.sum(mre * c, axis=-1), np.sum(mim * c, axis=-1)], axis=-1)
        R = np.stack([np.stack([np.sum(r11, -1) + sn, np.sum(r12, -1)], -1),
                      np.stack([np.sum(r12, -1), np.sum(r22, -1) + sn], -1)], -2)
        return C, R
    C = np.stack([mre * c, mim * c], axis=-1)  # (..., M, 2)
    blocks = np.stack([np.stack([r11 + sn, r12], -1), np.stack([r12, r22 + sn], -1)], -2)
    M = c.shape[-1]
    R = np.zeros(blocks.shape[:-3] + (2 * M, 2 * M))
    for i in range(M):
        R[..., 2 * i:2 * i + 2, 2 * i:2 * i + 2] = blocks[..., i, :, :]
    return C.reshape(C.shape[:-2] + (2 * M,)), R


def lmmse_snr(Cbar, Rbar) -> np.ndarray:
    """``S = Cbar^T Rbar^{-1} Cbar`` (the printed ``S^o`` lacks the inverse).

    Parameters
    ----------
    Cbar : array_like
        ``(..., d)``, finite.
    Rbar : array_like
        ``(..., d, d)``, symmetric positive definite.

    Returns
    -------
    numpy.ndarray
        ``S`` ``(...)``, ``>= 0``.

    Raises
    ------
    ValueError
        If ``Cbar`` is not finite, ``Rbar`` not symmetric positive definite, or the shapes
        disagree.
    """
    Cbar = _finite("Cbar", Cbar)
    Rbar = _covariance("Rbar", Rbar, definite=True, batch=True)
    if Cbar.ndim < 1 or Cbar.shape[-1] != Rbar.shape[-1]:
        raise ValueError(f"Cbar must have {Rbar.shape[-1]} entries on its last axis (as Rbar), "
                         f"got shape {Cbar.shape}")
    return np.einsum("...i,...i->...", Cbar,
                     np.linalg.solve(Rbar, Cbar[..., None])[..., 0])


def lmmse_coefficients(a, sigma_w2, c, sigma_v2, h_mean, h_var_re, h_var_im):
    """``(rho, tau, kappa)`` of the no-CSI problems with ``alpha~ = beamformed(alpha, h_mean)``.

    Then ``S = (sum alpha_i rho_i)^2 / (sum alpha_i^2 tau_i + sigma_n2)`` (multi-access) and
    ``S^o = sum alpha_i^2 rho_i^2 / (alpha_i^2 tau_i + sigma_n2)`` (orthogonal): variants of
    problems (19), (23), (26), (28) with ``rho_i = |E h~_i| c_i`` and ``tau_i = Var[Re g_i] c_i^2
    sigma_w2/(1-a^2) + E[Re^2 g_i] sigma_v2_i`` per unit ``alpha_i^2`` (from (33)). The reduction
    needs ``Cov(Re g_i, Im g_i) = 0``: equal variances of Re and Im of ``h~_i`` (as in the
    paper's Rician example) or a real or imaginary mean; otherwise ``ValueError``.

    Parameters
    ----------
    a : array_like
        State transition, ``|a| < 1``.
    sigma_w2 : array_like
        Process-noise variance, ``>= 0`` (``0``: deterministic dynamics).
    c, sigma_v2 : array_like
        Per-sensor gains and noise variances (``> 0``).
    h_mean : array_like
        Complex channel means, non-zero.
    h_var_re, h_var_im : array_like
        ``>= 0``; equal where the mean is neither real nor imaginary.

    Returns
    -------
    rho, tau, kappa : numpy.ndarray

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
    """
    s = _sensors(c=c, sigma_v2=sigma_v2, h_var_re=h_var_re, h_var_im=h_var_im,
                 h_mean_abs=np.abs(np.asarray(h_mean)))
    for name in ("h_var_re", "h_var_im"):
        if np.any(s[name] < 0):
            raise ValueError(f"{name} must be non-negative (it is a variance)")
    m = np.asarray(h_mean, dtype=complex)
    unit = beamformed(np.ones(np.shape(m)), m)
    mre, _, vre, _, cov = _channel_stats(unit, m, s["h_var_re"], s["h_var_im"])
    if np.any(np.abs(cov) > 1e-12 * (s["h_var_re"] + s["h_var_im"])):
        raise ValueError(
            "h_var_re and h_var_im must be equal where the channel mean is neither real nor "
            "imaginary: otherwise Re and Im of alpha~ h~ are correlated, Rbar_12 != 0 and S does "
            "not reduce to the scalar form of (33); use lmmse_matrices and lmmse_snr")
    kap = kappa(a, sigma_w2, s["c"], s["sigma_v2"])
    Pi = stationary_variance(a, sigma_w2)[..., None]
    tau = vre * s["c"] ** 2 * Pi + (vre + mre**2) * s["sigma_v2"]
    return np.abs(m) * s["c"], tau, kap


def lmmse_steady_state(access, alpha, a, sigma_w2, c, sigma_v2, sigma_n2, h_mean, h_var_re,
                       h_var_im) -> np.ndarray:
    """Steady-state prediction MSE of the no-CSI linear MMSE estimator with ``alpha~ =
    beamformed(alpha, h_mean)``: eq. (8) at ``S = Cbar^T Rbar^{-1} Cbar``.

    Parameters
    ----------
    access : str
        ``"multi-access"`` or ``"orthogonal"``.
    alpha : array_like
        Real amplification factors ``(..., M)``.
    a : array_like
        State transition, ``|a| < 1``.
    sigma_w2 : array_like
        Process-noise variance, ``>= 0`` (``0``: deterministic dynamics).
    c, sigma_v2 : array_like
        Per-sensor gains (finite) and noise variances (``> 0``).
    sigma_n2 : array_like
        Receiver-noise variance, ``> 0``.
    h_mean : array_like
        Complex channel means ``(..., M)``, non-zero.
    h_var_re, h_var_im : array_like
        Variances of their real and imaginary parts, ``>= 0``.

    Returns
    -------
    numpy.ndarray
        The steady-state prediction MSE.

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
    """
    alpha_t = beamformed(alpha, h_mean)
    C, R = lmmse_matrices(access, alpha_t, a, sigma_w2, c, sigma_v2, sigma_n2, h_mean,
                          h_var_re, h_var_im)
    return steady_state(a, sigma_w2, lmmse_snr(C, R))


def lmmse_min_power(access, D, a, sigma_w2, c, sigma_v2, sigma_n2, h_mean, h_var_re,
                    h_var_im, *, infeasible: str = "raise") -> np.ndarray:
    """No CSI: least total power with steady-state MSE ``<= D`` (a variant of (19) / (26)).
    Returns the real ``alpha`` (transmit ``beamformed(alpha, h_mean)``).

    Parameters
    ----------
    access : str
        ``"multi-access"`` or ``"orthogonal"``.
    D : array_like
        Error target, strictly between ``sigma_w2`` and ``sigma_w2 / (1 - a^2)``.
    a : array_like
        State transition, ``|a| < 1``.
    sigma_w2 : array_like
        Process-noise variance, ``> 0`` (with 0 no error target exists).
    c, sigma_v2 : array_like
        Per-sensor gains (finite) and noise variances (``> 0``).
    sigma_n2 : array_like
        Receiver-noise variance, ``> 0``.
    h_mean : array_like
        Complex channel means ``(..., M)``, non-zero.
    h_var_re, h_var_im : array_like
        Variances of their real and imaginary parts, ``>= 0``.
    infeasible : str
        ``"raise"`` or ``"nan"``.

    Returns
    -------
    numpy.ndarray
        The amplification factors ``alpha`` ``(..., M)``.

    Raises
    ------
    InfeasibleError
        If the target cannot be met (a ``ValueError`` stating the threshold).
    ValueError
        Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
    """
    access = _access(access)
    x, y = _xy_of(D, a, sigma_w2)
    rho, tau, kap = lmmse_coefficients(a, sigma_w2, c, sigma_v2, h_mean, h_var_re, h_var_im)
    sn = _positive("sigma_n2", sigma_n2)
    solver = coherent_min_power if access == "multi-access" else orthogonal_min_power
    alpha = solver(rho, tau, kap, sn, x, y, infeasible="nan")
    if infeasible == "raise" and np.any(np.isnan(alpha)):
        total = np.sum(rho**2 / tau, axis=-1)
        raise InfeasibleError(
            f"target D = {float(np.max(D)):g} is infeasible without CSI ({access}): sum_i "
            f"rho_i^2 / tau_i = {float(np.min(total)):.6g} must exceed (a^2 D + sigma_w2 - D) "
            f"/ (D (D - sigma_w2)) = {float(np.max(x / y)):.6g}")
    return alpha


def lmmse_min_error(access, gamma_total, a, sigma_w2, c, sigma_v2, sigma_n2, h_mean, h_var_re,
                    h_var_im) -> np.ndarray:
    """No CSI: least steady-state MSE with total power ``<= gamma_total`` (a variant of (23) /
    (28)). Returns the real ``alpha``.

    Parameters
    ----------
    access : str
        ``"multi-access"`` or ``"orthogonal"``.
    gamma_total : array_like
        Total power, ``>= 0`` (``0``: nothing is sent).
    a : array_like
        State transition, ``|a| < 1``.
    sigma_w2 : array_like
        Process-noise variance, ``>= 0`` (``0``: deterministic dynamics).
    c, sigma_v2 : array_like
        Per-sensor gains (finite) and noise variances (``> 0``).
    sigma_n2 : array_like
        Receiver-noise variance, ``> 0``.
    h_mean : array_like
        Complex channel means ``(..., M)``, non-zero.
    h_var_re, h_var_im : array_like
        Variances of their real and imaginary parts, ``>= 0``.

    Returns
    -------
    numpy.ndarray
        The amplification factors ``alpha`` ``(..., M)``.

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
    """
    access = _access(access)
    rho, tau, kap = lmmse_coefficients(a, sigma_w2, c, sigma_v2, h_mean, h_var_re, h_var_im)
    sn = _positive("sigma_n2", sigma_n2)
    if access == "multi-access":
        return coherent_max_snr(rho, tau, kap, sn, gamma_total)
    return orthogonal_max_snr(rho, tau, kap, sn, gamma_total)


def lmmse_filter(z, a, sigma_w2, Cbar, Rbar, *, P0=None):
    """Run the linear MMSE estimator (32) (corrected) on observations ``z`` ``(..., steps, d)``.

    ``Cbar`` ``(d,)``, ``Rbar`` ``(d, d)`` from :func:`lmmse_matrices`. Starts from
    ``xhat_{0|-1} = 0``, ``P_{0|-1} = P0`` (default the stationary variance). Returns the
    predictions ``xhat_{k|k-1}`` ``(..., steps + 1)`` and their variances ``P_{k|k-1}``
    ``(steps + 1,)``. The printed (32) lacks ``+ sigma_w2`` in the time update and ``Cbar
    P_{k+1|k}`` at the end of the measurement update.

    Parameters
    ----------
    z : array_like
        Observations ``(..., steps, d)``, finite.
    a : array_like
        State transition, ``|a| < 1``.
    sigma_w2 : array_like
        Process-noise variance, ``>= 0`` (``0``: deterministic dynamics).
    Cbar : array_like
        ``(d,)``.
    Rbar : array_like
        ``(d, d)``, symmetric positive definite.
    P0 : float, optional
        ``P_{0|-1} >= 0`` (default the stationary variance).

    Returns
    -------
    xp, P : numpy.ndarray
        Predictions ``(..., steps + 1)`` and variances ``(steps + 1,)``.

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
    """
    a = float(_a(a))
    sw = float(_nonneg("sigma_w2", sigma_w2, "a variance"))
    z = _finite("z", z)
    C = _finite("Cbar", Cbar)
    R = _covariance("Rbar", Rbar, definite=True)
    if C.shape != (R.shape[0],) or z.ndim < 2 or z.shape[-1] != C.shape[0]:
        raise ValueError(f"Cbar must be ({R.shape[0]},) as Rbar and z shaped (..., steps, "
                         f"{R.shape[0]}); got Cbar {C.shape}, z {z.shape}")
    if P0 is not None:
        P0 = float(_nonneg("P0", P0, "a variance"))
    w = np.linalg.solve(R, C)  # Rbar^{-1} Cbar
    S = float(C @ w)
    steps = z.shape[-2]
    P = np.empty(steps + 1)
    P[0] = sw / (1 - a**2) if P0 is None else P0
    xp = np.zeros(z.shape[:-1][:-1] + (steps + 1,))
    for k in range(steps):
        gain = P[k] / (1.0 + P[k] * S)  # P_{k|k}; the gain is P_{k|k} Cbar^T Rbar^{-1}
        innov = z[..., k, :] - xp[..., k, None] * C
        xf = xp[..., k] + gain * (innov @ w)
        xp[..., k + 1] = a * xf
        P[k + 1] = a**2 * gain + sw
    return xp, P


def simulate_nocsi(rng: np.random.Generator, n: int, steps: int, access, alpha_t, a, sigma_w2,
                   c, sigma_v2, sigma_n2, h_mean, h_var_re, h_var_im):
    """Simulate ``n`` independent runs of the system, the fading channels and the receiver noise
    without CSI, and run :func:`lmmse_filter` on them. Returns ``(x, xhat_pred, P)``: states
    and predictions ``(n, steps)`` and the filter's variances ``(steps,)`` (``x_0`` stationary).

    Channels ``h~_{i,k} = h_mean_i + sqrt(h_var_re_i) N + j sqrt(h_var_im_i) N'``, i.i.d. over
    time; receiver noise with ``sigma_n2`` in each of its real and imaginary parts.

    Parameters
    ----------
    rng : numpy.random.Generator
        The source of randomness.
    n, steps : int
        Runs and time steps, ``>= 1``.
    access : str
        ``"multi-access"`` or ``"orthogonal"``.
    alpha_t : array_like
        Complex amplification factors.
    a : array_like
        State transition, ``|a| < 1``.
    sigma_w2 : array_like
        Process-noise variance, ``>= 0`` (``0``: deterministic dynamics).
    c, sigma_v2 : array_like
        Per-sensor gains (finite) and noise variances (``> 0``).
    sigma_n2 : array_like
        Receiver-noise variance, ``> 0``.
    h_mean : array_like
        Complex channel means ``(..., M)``, non-zero.
    h_var_re, h_var_im : array_like
        Variances of their real and imaginary parts, ``>= 0``.

    Returns
    -------
    x, xhat_pred, P : numpy.ndarray

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
    """
    access = _access(access)
    if not isinstance(rng, np.random.Generator):
        raise ValueError(f"rng must be a numpy.random.Generator, got {rng!r}")
    n = _integer("n", n, 1)
    steps = _integer("steps", steps, 1)
    a_ = float(_a(a))
    sw = float(_nonneg("sigma_w2", sigma_w2, "a variance"))
    C, R = lmmse_matrices(access, alpha_t, a, sigma_w2, c, sigma_v2, sigma_n2, h_mean,
                          h_var_re, h_var_im)
    c = np.atleast_1d(np.asarray(c, dtype=float))
    M = c.shape[-1]
    sv = np.broadcast_to(np.asarray(sigma_v2, float), (M,))
    sn = float(sigma_n2)
    x = np.empty((n, steps))
    x[:, 0] = rng.standard_normal(n) * np.sqrt(sw / (1 - a_**2))
    for k in range(1, steps):
        x[:, k] = a_ * x[:, k - 1] + rng.standard_normal(n) * np.sqrt(sw)
    y = c * x[..., None] + rng.standard_normal((n, steps, M)) * np.sqrt(sv)
    hr = np.real(h_mean) + np.sqrt(h_var_re) * rng.standard_normal((n, steps, M))
    hi = np.imag(h_mean) + np.sqrt(h_var_im) * rng.standard_normal((n, steps, M))
    g = np.asarray(alpha_t, dtype=complex) * (hr + 1j * hi) * y
    if access == "multi-access":
        zc = g.sum(-1) + (rng.standard_normal((n, steps))
                          + 1j * rng.standard_normal((n, steps))) * np.sqrt(sn)
        z = np.stack([zc.real, zc.imag], axis=-1)
    else:
        zc = g + (rng.standard_normal((n, steps, M))
                  + 1j * rng.standard_normal((n, steps, M))) * np.sqrt(sn)
        z = np.stack([zc.real, zc.imag], axis=-1).reshape(n, steps, 2 * M)
    xp, P = lmmse_filter(z, a_, sw, C, R)
    return x, xp[:, :steps], P[:steps]


# ======================================================= independent numerical solution
def _restore(b, ok):
    """Smallest ``t >= 1`` (to 1e-15) with ``ok(t b)``: SLSQP may stop a hair infeasible, so
    its reported minimum would undercut the true one; the scaled point is feasible."""
    if ok(b):
        return b
    hi = 1.0 + 1e-12
    while not ok(hi * b):
        hi = 1.0 + 2 * (hi - 1.0)
    lo = 1.0
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if ok(mid * b) else (mid, hi)
        if hi - lo < 1e-16:
            break
    return hi * b


def solve_numerically(problem: str, rho, tau, kappa, sigma_n2, *, x=None, y=None,
                      gamma_total=None, starts: int = 6, seed: int = 0):
    """Solve one instance of (19), (23), (26) or (28) with SciPy's SLSQP (no closed form used).

    ``problem`` is ``"coherent-min-power"`` (19), ``"coherent-max-snr"`` (23),
    ``"orthogonal-min-power"`` (26) or ``"orthogonal-max-snr"`` (28). Returns ``(alpha,
    value)`` with ``value`` the optimal sum power (min-power problems) or SNR (max-SNR ones).

    The instance is rescaled to order-one numbers first (the paper's channel gains are ~1e-3
    and ``sigma_n2 = 1e-9``). (19) is solved in its convex second-order-cone form ``sqrt(y)
    sum beta_i rho_i >= sqrt(x) ||(sqrt(tau) beta, sigma_n)||`` (the ``s > 0`` sheet), (26) and
    (28) are convex in ``alpha_i^2 >= 0``; (23) is a generalized Rayleigh quotient, solved from
    ``starts`` random starts (best kept).

    Parameters
    ----------
    problem : str
        One of the four problem names.
    rho : array_like
        ``(..., M)``, finite, not all zero.
    tau : array_like
        ``(..., M)``, ``> 0``.
    kappa : array_like
        ``(..., M)``, ``> 0``.
    sigma_n2 : float
        ``> 0``.
    x, y : float, optional
        Constraint constants of the min-power problems, ``> 0``.
    gamma_total : float, optional
        Budget of the max-SNR problems, ``> 0``.
    starts : int
        Random starts for (23), ``>= 1``.
    seed : int
        Non-negative integer seed.

    Returns
    -------
    alpha : numpy.ndarray
    value : float

    Raises
    ------
    InfeasibleError
        If the target cannot be met (a ``ValueError`` stating the threshold).
    ValueError
        Naming the argument that is NaN, infinite, out of range or of inconsistent shape.
    """
    from scipy.optimize import minimize

    problems = ("coherent-min-power", "coherent-max-snr", "orthogonal-min-power",
                "orthogonal-max-snr")
    if problem not in problems:
        raise ValueError(f"problem must be one of 'coherent-min-power', 'coherent-max-snr', "
                         f"'orthogonal-min-power', 'orthogonal-max-snr'; got {problem!r}")
    rho, tau, kap, sn = _general(rho, tau, kappa, sigma_n2)
    if rho.ndim != 1 or np.ndim(sn) != 0:
        raise ValueError(f"rho, tau, kappa must be 1-D (one instance) and sigma_n2 a scalar, got "
                         f"shapes {rho.shape}, {np.shape(sn)}")
    sn = float(_positive("sigma_n2", sn, f"a variance; {_IDEAL_CHANNEL}"))
    if problem.endswith("min-power"):
        x = float(_positive("x", x, "a2 D + sigma_w2 - D > 0"))
        y = float(_positive("y", y, "D (D - sigma_w2) > 0"))
    else:
        gamma_total = float(_positive("gamma_total", gamma_total, "a power"))
    starts = _integer("starts", starts, 1)
    seed = _integer("seed", seed, 0)
    M = rho.size
    rng = np.random.default_rng(seed)
    opts = {"ftol": 1e-15, "maxiter": 2000}
    tb, kb = tau.mean(), kap.mean()
    if problem in ("coherent-min-power", "orthogonal-min-power"):
        x, y = float(x), float(y)
        # alpha = u * beta with u^2 = sigma_n2 / tb: constraint x (sum beta^2 tau' + 1) <= ...
        u2 = sn / tb
        t_, r_, k_ = tau / tb, rho / np.sqrt(tb), kap / kb
        if problem == "coherent-min-power":
            Q = np.sum(r_**2 / t_)
            if Q <= x / y:
                raise InfeasibleError("infeasible instance")
            sgn = np.sqrt(y)

            def cons(b):
                return sgn * (b @ r_) - np.sqrt(x) * np.sqrt(b**2 @ t_ + 1.0)

            def cons_jac(b):
                return sgn * r_ - np.sqrt(x) * (b * t_) / np.sqrt(b**2 @ t_ + 1.0)

            t0 = np.sqrt(4 * x / (Q * (y * Q - x)))
            b0 = t0 * r_ / t_
            res = minimize(lambda b: b**2 @ k_, b0, jac=lambda b: 2 * b * k_, method="SLSQP",
                           constraints=[{"type": "ineq", "fun": cons, "jac": cons_jac}],
                           options=opts)
            beta = _restore(res.x, lambda b: cons(b) >= 0)
            alpha = beta * np.sqrt(u2)
        else:
            target = x / y
            if np.sum(r_**2 / t_) <= target:
                raise InfeasibleError("infeasible instance")

            def s_o(b):
                return np.sum(b * r_**2 / (b * t_ + 1.0))

            def s_o_jac(b):
                return r_**2 / (b * t_ + 1.0) ** 2

            b0 = np.full(M, 1.0)
            while s_o(b0) <= target * 1.01:
                b0 *= 2
            res = minimize(lambda b: b @ k_, b0, jac=lambda b: k_, method="SLSQP",
                           bounds=[(0, None)] * M,
                           constraints=[{"type": "ineq", "fun": lambda b: s_o(b) - target,
                                         "jac": s_o_jac}], options=opts)
            b = _restore(np.maximum(res.x, 0), lambda b: s_o(b) >= target)
            alpha = np.sqrt(b * u2)
        return alpha, float(alpha**2 @ kap)
    if problem in ("coherent-max-snr", "orthogonal-max-snr"):
        g = float(gamma_total)
        # alpha = u beta with u^2 = g / kb: constraint sum beta^2 kappa' <= 1
        u2 = g / kb
        k_ = kap / kb
        noise = sn / (u2 * tb)
        t_, r_ = tau / tb, rho / np.sqrt(tb)
        if problem == "coherent-max-snr":
            def neg(b):
                return -(b @ r_) ** 2 / (b**2 @ t_ + noise)

            def neg_jac(b):
                num, den = b @ r_, b**2 @ t_ + noise
                return -(2 * num * r_ * den - num**2 * 2 * b * t_) / den**2

            best = None
            for j in range(starts):
                b0 = r_.copy() if j == 0 else rng.standard_normal(M)
                b0 /= np.sqrt(b0**2 @ k_)
                res = minimize(neg, b0, jac=neg_jac, method="SLSQP",
                               constraints=[{"type": "ineq", "fun": lambda b: 1 - b**2 @ k_,
                                             "jac": lambda b: -2 * b * k_}], options=opts)
                if best is None or res.fun < best.fun:
                    best = res
            beta = best.x / max(1.0, np.sqrt(best.x**2 @ k_))  # exactly within the budget
            alpha = beta * np.sqrt(u2)
            value = (alpha @ rho) ** 2 / (alpha**2 @ tau + sn)
            return alpha, float(value)

        def neg_o(b):
            return -np.sum(b * r_**2 / (b * t_ + noise))

        def neg_o_jac(b):
            return -(r_**2 * noise / (b * t_ + noise) ** 2)

        b0 = np.full(M, 1.0 / np.sum(k_))
        res = minimize(neg_o, b0, jac=neg_o_jac, method="SLSQP", bounds=[(0, None)] * M,
                       constraints=[{"type": "ineq", "fun": lambda b: 1 - b @ k_,
                                     "jac": lambda b: -k_}], options=opts)
        b = np.maximum(res.x, 0)
        alpha = np.sqrt(b / max(1.0, b @ k_) * u2)
        value = np.sum(alpha**2 * rho**2 / (alpha**2 * tau + sn))
        return alpha, float(value)
    raise ValueError(f"problem must be one of 'coherent-min-power', 'coherent-max-snr', "
                     f"'orthogonal-min-power', 'orthogonal-max-snr'; got {problem!r}")
