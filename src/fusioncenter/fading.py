"""Kalman filtering over fading channels (dey2009): the random Riccati equation and its bounds.

A sensor amplifies and forwards its measurement over a fading channel with power gain
``r = h^2``; the fusion centre knows ``h`` and runs the Kalman filter. For a scalar state
(the paper's model (5), ``c = 1``) the prediction variance obeys the random Riccati equation (15)

    ``p_{k+1} = sigma_w2 + a^2 p_k (r sigma_v2 + sigma_n2) / (r (p_k + sigma_v2) + sigma_n2)``.

Everything here is written in terms of one expectation of the channel law,

    ``g(b) = E[b / (r + b)]``  (:meth:`Rayleigh.ratio_mean`),

because the posterior variance is ``p - p^2 / (p + sigma_v2) * r / (r + b)`` with
``b = sigma_n2 / (p + sigma_v2)``, so ``E_r[posterior] = p (sigma_v2 + p g(b)) / (p + sigma_v2)``.
For Rayleigh fading ``g(b) = m e^m E1(m)`` with ``m = lam b`` (the paper's (17)); for
Nakagami(1/2) ``g(b) = sqrt(pi) u erfcx(u)`` with ``u = sqrt(lam b / 2)`` ((19)); for general
Nakagami-m ``g(b) = z^m U(m, m, z)`` with ``z = lam m b`` (Tricomi's confluent hypergeometric U).

Entry points (the variances are passed as variances):

* channel laws :class:`Rayleigh` and :class:`Nakagami` (sampling, the expectations, the
  inequalities the loose bounds use);
* :func:`scalar_mc` / :func:`scalar_paths`: ``E[p_k]`` by Monte Carlo of (15) through
  :func:`fusioncenter.montecarlo.simulate`; :func:`scalar_bounds` the tight and loose bound
  sequences ((17)-(18) Rayleigh, (19)-(20) Nakagami(1/2)); :func:`scalar_bound_limits` their
  fixed points;
* :func:`multisensor_mc` / :func:`multisensor_paths` and :func:`multisensor_bounds` (the
  worst-sensor bound ``s`` and the AM-HM bound ``t``) for the multi-access (7) and orthogonal (8)
  schemes under Rayleigh fading;
* :func:`vector_mc` / :func:`vector_paths` and :func:`vector_bound` (the sequence ``Zbar_k`` of
  the vector-state, scalar-measurement section 3.2);
* :func:`exp_e1`, a numerically safe ``e^x E1(x)``.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import scipy.optimize
import scipy.special

from fusioncenter import montecarlo
from fusioncenter._validate import covariance as _covariance
from fusioncenter._validate import finite as _finite
from fusioncenter._validate import finite_result as _finite_result
from fusioncenter._validate import nonneg as _nonneg
from fusioncenter._validate import positive as _positive

__all__ = [
    "ACCESS_SCHEMES",
    "Nakagami",
    "Rayleigh",
    "exp_e1",
    "expected_posterior",
    "multisensor_bound_limits",
    "multisensor_bounds",
    "multisensor_mc",
    "multisensor_paths",
    "nakagami_q_as_printed",
    "scalar_bound_limits",
    "scalar_bounds",
    "scalar_mc",
    "scalar_paths",
    "triu_to_symmetric",
    "vector_bound",
    "vector_mc",
    "vector_paths",
]

ACCESS_SCHEMES = ("multi-access", "orthogonal")

#: Below this argument ``exp(x) * scipy.special.exp1(x)`` is accurate to a few ulp (it would
#: underflow/overflow beyond ~700); above it the continued fraction with :data:`_E1_CF_DEPTH`
#: terms is (both checked against mpmath on a log grid in the tests).
_E1_SWITCH = 50.0
_E1_CF_DEPTH = 16
#: The same for the general Nakagami-m expectation ``z^m U(m, m, z)`` (scipy's ``hyperu`` loses
#: digits for large ``z``).
_CF_SWITCH = 2.0
_CF_DEPTH = 64


# ------------------------------------------------------------------------ special functions
def _notnan(name: str, value) -> np.ndarray:
    """Floats, no NaN (infinities are the documented limits of the special functions)."""
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a real number or array, got {value!r}") from None
    if np.any(np.isnan(arr)):
        raise ValueError(f"{name} must not be NaN, got {value!r}")
    return arr


def _cf_tail(x: np.ndarray, m: float, depth: int = _CF_DEPTH) -> np.ndarray:
    """``z^m U(m, m, z)`` for ``z >= 2`` by the Legendre continued fraction (backward, fixed depth).

    ``z^m e^z Gamma(1 - m, z) = z / (z + m - 1 m / (z + m + 2 - 2 (m + 1) / (z + m + 4 - ...)))``;
    for ``m = 1`` it is ``x e^x E1(x)``.
    """
    t = np.zeros_like(x)
    for n in range(depth, 0, -1):
        t = n * (n - 1 + m) / (x + 2 * n + m - t)
    return x / (x + m - t)


def exp_e1(x):
    """``e^x E1(x) = int_0^inf e^{-u} / (u + x) du`` for ``x >= 0``, without overflow.

    ``scipy.special.exp1`` underflows (and ``exp`` overflows) beyond ``x ~ 700``; for
    ``x >= 50`` the continued fraction
    ``e^x E1(x) = 1 / (x + 1 - 1 / (x + 3 - 4 / (x + 5 - 9 / (x + 7 - ...))))`` is used instead.
    Relative error below ``1e-15`` on ``[1e-8, 1e8]`` against mpmath (tested).
    ``exp_e1(0) = inf`` (the integral diverges), ``exp_e1(inf) = 0``.

    Parameters
    ----------
    x : array_like
        Arguments ``>= 0`` (``+inf`` allowed: the limit 0).

    Returns
    -------
    float or numpy.ndarray
        ``e^x E1(x)``, in ``(0, inf]``.

    Raises
    ------
    ValueError
        If an entry is NaN or negative.
    """
    x = _notnan("x", x)
    if np.any(x < 0):
        raise ValueError("x must be non-negative for exp_e1 (E1 of a negative argument is not "
                         "real)")
    small = x < _E1_SWITCH
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        lo = np.exp(np.where(small, x, 0.0)) * scipy.special.exp1(np.where(small, x, 1.0))
        xl = np.where(small | ~np.isfinite(x), _E1_SWITCH, x)
        hi = _cf_tail(xl, 1.0, _E1_CF_DEPTH) / xl
    out = np.where(small, lo, hi)
    out = np.where(np.isposinf(x), 0.0, out)
    return out[()] if out.ndim == 0 else out


def _x_exp_e1(m: np.ndarray) -> np.ndarray:
    """``m e^m E1(m)`` in (0, 1), with the limits 0 at ``m = 0`` and 1 at ``m = inf``."""
    m = np.asarray(m, dtype=float)
    with np.errstate(invalid="ignore"):
        out = np.where(m > 0, m * exp_e1(np.where(m > 0, m, 1.0)), 0.0)
    return np.where(np.isposinf(m), 1.0, out)


def _gamma_ratio(z: np.ndarray, m: float) -> np.ndarray:
    """``z^m U(m, m, z) = E[b / (r + b)]`` for ``r ~ Gamma(m, rate lam m)``, ``z = lam m b``.

    ``z >= 2``: continued fraction. ``z < 2``: ``scipy.special.hyperu`` for ``m <= 2``; for larger
    ``m`` (where ``hyperu`` returns nan at small ``z``) start from ``m0 = m - k`` in (1, 2] and
    recurse upwards with ``J_{a+1} = (1 - z J_a) / a``, ``J_a(z) = E_{x ~ Gamma(a)}[1/(x + z)]``
    (stable: errors shrink by ``z / a`` per step).
    """
    z = np.asarray(z, dtype=float)
    small = z < _CF_SWITCH
    zs = np.where(small & (z > 0), z, 1.0)
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        if m <= 2.0:
            lo = zs**m * scipy.special.hyperu(m, m, zs)
        else:
            k = math.ceil(m - 2.0)
            a = m - k
            J = zs ** (a - 1.0) * scipy.special.hyperu(a, a, zs)  # G_a / z
            for _ in range(k):
                J = (1.0 - zs * J) / a
                a += 1.0
            lo = zs * J
        # tiny z: hyperu overflows (nan) or z^m underflows (0); the leading term of the
        # expansion at z = 0 is then exact to the float resolution or better: z E[1/r']
        # = z / (m - 1) for m > 1, Gamma(1 - m) z^m for m < 1
        failed = small & (z > 0) & ~(np.isfinite(lo) & (lo > 0))
        if np.any(failed):
            lead = zs / (m - 1.0) if m > 1.0 else scipy.special.gamma(1.0 - m) * zs**m
            lo = np.where(failed, lead, lo)
        zl = np.where(small | ~np.isfinite(z), _CF_SWITCH, z)
        hi = _cf_tail(zl, m)
    out = np.where(small, lo, hi)
    out = np.where(z == 0, 0.0, out)
    return np.where(np.isposinf(z), 1.0, out)


# ----------------------------------------------------------------------------- validation
#: The reason given when a variance is negative.
_VARIANCE = "it is a variance"


def _shift(name: str, value) -> np.ndarray:
    """A non-negative shift ``b``; ``+inf`` is allowed (the limit of a noiseless channel)."""
    arr = _notnan(name, value)
    if np.any(arr < 0):
        raise ValueError(f"{name} must be non-negative, got {value!r}")
    return arr


def _scalar(name: str, arr: np.ndarray) -> float:
    if arr.ndim != 0:
        raise ValueError(f"{name} must be a scalar, got shape {arr.shape}")
    return float(arr)


def _int(name: str, value, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int | np.integer):
        raise ValueError(f"{name} must be an integer, got {value!r}")
    if value < minimum:
        raise ValueError(f"{name} must be >= {minimum}, got {value}")
    return int(value)


def _rate(name: str, value) -> float:
    try:
        ok = not isinstance(value, bool) and math.isfinite(float(value)) and float(value) > 0
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise ValueError(f"{name} must be a positive finite number (1 / mean power gain), "
                         f"got {value!r}")
    return float(value)


def _channel(channel):
    if not isinstance(channel, Rayleigh | Nakagami):
        raise ValueError(f"channel must be Rayleigh(lam) or Nakagami(m, lam), got {channel!r}")
    return channel


def _scalar_args(a, sigma_w2, sigma_v2, sigma_n2, p0, steps):
    return (_scalar("a", _finite("a", a)),
            _scalar("sigma_w2", _nonneg("sigma_w2", sigma_w2, _VARIANCE)),
            _scalar("sigma_v2", _nonneg("sigma_v2", sigma_v2, _VARIANCE)),
            _scalar("sigma_n2", _positive("sigma_n2", sigma_n2)),
            _scalar("p0", _nonneg("p0", p0, _VARIANCE)),
            _int("steps", steps, 0))


# --------------------------------------------------------------------------- channel laws
@dataclass(frozen=True)
class Rayleigh:
    """Rayleigh fading: the power gain ``r = h^2`` is exponential with mean ``1 / lam``.

    Density ``lam exp(-lam r)``, as in the paper's Section 3.1.1.
    """

    lam: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "lam", _rate("lam", self.lam))

    m = 1.0  # as a Nakagami-m law

    @property
    def name(self) -> str:
        return f"Rayleigh (lam = {self.lam:g})"

    @property
    def mean_gain(self) -> float:
        """``E[r] = 1 / lam``."""
        return 1.0 / self.lam

    def sample(self, rng: np.random.Generator, size) -> np.ndarray:
        """Power gains ``r = h^2`` drawn with ``rng``."""
        return rng.standard_exponential(size) / self.lam

    def pdf(self, r):
        """The density of ``r`` (0 for ``r < 0``); ``r`` must not be NaN."""
        r = _notnan("r", r)
        return np.where(r >= 0, self.lam * np.exp(-self.lam * np.maximum(r, 0.0)), 0.0)

    def inverse_mean(self, b):
        """``E[1 / (r + b)] = lam e^{lam b} E1(lam b)`` for ``b > 0``."""
        b = _positive("b", b, "a shift")
        return self.lam * exp_e1(self.lam * b)

    def ratio_mean(self, b):
        """``g(b) = E[b / (r + b)] = m e^m E1(m)``, ``m = lam b`` (in [0, 1]; 0 at ``b = 0``)."""
        return _x_exp_e1(self.lam * _shift("b", b))

    def ratio_mean_bound(self, b):
        """``m ln(1 + 1/m) >= g(b)``: the inequality ``e^x E1(x) < ln(1 + 1/x)`` used for (18)."""
        m = self.lam * _shift("b", b)
        with np.errstate(divide="ignore", invalid="ignore"):
            out = np.where(m > 0, m * np.log1p(1.0 / np.where(m > 0, m, 1.0)), 0.0)
        return np.where(np.isposinf(m), 1.0, out)


@dataclass(frozen=True)
class Nakagami:
    """Nakagami-m fading: ``r = h^2`` is Gamma with shape ``m`` and mean ``1 / lam``.

    Density ``m^m lam^m r^{m-1} exp(-lam m r) / Gamma(m)`` (Section 3.1.2), ``m >= 1/2``;
    ``m = 1`` is Rayleigh, ``m = 1/2`` the most severe fading the model allows.
    """

    m: float
    lam: float

    def __post_init__(self) -> None:
        try:
            ok = not isinstance(self.m, bool) and math.isfinite(float(self.m)) and self.m >= 0.5
        except (TypeError, ValueError):
            ok = False
        if not ok:
            raise ValueError(f"m must be a finite number >= 1/2 (Nakagami fading parameter), "
                             f"got {self.m!r}")
        object.__setattr__(self, "m", float(self.m))
        object.__setattr__(self, "lam", _rate("lam", self.lam))

    @property
    def name(self) -> str:
        return f"Nakagami (m = {self.m:g}, lam = {self.lam:g})"

    @property
    def mean_gain(self) -> float:
        return 1.0 / self.lam

    def sample(self, rng: np.random.Generator, size) -> np.ndarray:
        """Power gains drawn with ``rng`` (``m = 1/2``: ``Z^2 / lam``, ``Z`` standard normal)."""
        if self.m == 0.5:
            return rng.standard_normal(size) ** 2 / self.lam
        return rng.gamma(self.m, 1.0 / (self.lam * self.m), size)

    def pdf(self, r):
        """The density of ``r`` (0 for ``r <= 0``); ``r`` must not be NaN."""
        r = _notnan("r", r)
        m, lam = self.m, self.lam
        rp = np.where(r > 0, r, 1.0)
        logp = (m * np.log(m * lam) + (m - 1) * np.log(rp) - lam * m * rp
                - scipy.special.gammaln(m))
        return np.where(r > 0, np.exp(logp), 0.0)

    def ratio_mean(self, b):
        """``g(b) = E[b / (r + b)]``.

        ``m = 1/2``: ``sqrt(pi) u erfcx(u)``, ``u = sqrt(lam b / 2)`` (the paper's
        ``exp(u^2) erfc(u)`` term of (19)); ``m = 1``: as :class:`Rayleigh`; otherwise
        ``z^m U(m, m, z)`` with ``z = lam m b``.
        """
        b = _shift("b", b)
        if self.m == 0.5:
            u = np.sqrt(self.lam * b / 2.0)
            with np.errstate(invalid="ignore"):
                out = np.sqrt(np.pi) * u * scipy.special.erfcx(u)
            return np.where(np.isposinf(u), 1.0, out)
        if self.m == 1.0:
            return _x_exp_e1(self.lam * b)
        return _gamma_ratio(self.lam * self.m * b, self.m)

    def inverse_mean(self, b):
        """``E[1 / (r + b)]`` for ``b > 0`` (``= g(b) / b``)."""
        b = _positive("b", b, "a shift")
        return self.ratio_mean(b) / b

    def ratio_mean_bound(self, b):
        """An upper bound on ``g(b)`` (only ``m = 1/2``: Abramowitz & Stegun 7.1.13).

        ``(sqrt(pi)/2) e^{u^2} erfc(u) <= 1 / (u + sqrt(u^2 + 4/pi))`` gives
        ``g <= 2 u / (u + sqrt(u^2 + 4/pi))``.
        """
        if self.m != 0.5:
            raise ValueError("ratio_mean_bound is the paper's inequality for m = 1/2 only")
        u = np.sqrt(self.lam * _shift("b", b) / 2.0)
        with np.errstate(invalid="ignore"):
            out = 2.0 * u / (u + np.sqrt(u * u + 4.0 / np.pi))
        return np.where(np.isposinf(u), 1.0, out)


# ------------------------------------------------------------------------ scalar: Monte Carlo
#: channel draws per batch of steps in :func:`_scalar_chunk` (about 0.4 MB: stays in cache)
_BATCH_ELEMENTS = 50_000


def _scalar_chunk(rng, n, *, a, sigma_w2, sigma_v2, sigma_n2, channel, p0, steps):
    """``n`` paths of (15), shaped ``(n, steps + 1)``: ``p_0, ..., p_steps``.

    (15) is evaluated in harmonic form: with ``u = r sigma_v2 + sigma_n2`` the posterior
    variance is ``p u / (r p + u) = 1 / (1/p + r/u)``, so
    ``p' = sigma_w2 + 1 / (1/(a^2 p) + c)`` with ``c = 1 / (a^2 (sigma_v2 + sigma_n2 / r))``.
    ``p = 0`` and ``r = 0`` (a deep fade) are exact limits of this form (``1/0 = inf``).
    The channel is drawn in batches of steps (time-major, so the draws are the same numbers as
    one ``(steps, n)`` draw: the generator fills arrays in order), ``c`` is computed in place
    for the batch, and each step is four in-place operations on one contiguous row.
    """
    out = np.empty((steps + 1, n))
    out[0] = p0
    if a * a == 0.0:  # p_{k+1} = sigma_w2 whatever the channel (the harmonic form needs 1/a^2)
        out[1:] = sigma_w2
        return out.T
    tmp = np.empty(n)
    a2, inv_a2 = a * a, 1.0 / (a * a)
    batch = max(1, _BATCH_ELEMENTS // max(n, 1))
    with np.errstate(divide="ignore", over="ignore"):
        for k0 in range(0, steps, batch):
            c = channel.sample(rng, (min(batch, steps - k0), n))
            np.divide(sigma_n2, c, out=c)
            c += sigma_v2
            c *= a2
            np.divide(1.0, c, out=c)
            for j in range(c.shape[0]):
                k = k0 + j
                nxt = out[k + 1]
                np.divide(inv_a2, out[k], out=tmp)
                tmp += c[j]
                np.divide(1.0, tmp, out=nxt)
                nxt += sigma_w2
    return out.T


def scalar_paths(a, sigma_w2, sigma_v2, sigma_n2, channel, p0, steps, n_paths, seed, **runner):
    """Sample paths of (15) as a :class:`~fusioncenter.montecarlo.MonteCarloResult`.

    ``samples`` is ``(n_paths, steps + 1)``; ``p_0 = p0`` on every path. ``runner`` keywords
    (``chunk_size``, ``executor``, ``progress``) go to :func:`fusioncenter.montecarlo.simulate`.

    Parameters
    ----------
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

    Returns
    -------
    MonteCarloResult
        ``samples`` ``(n_paths, steps + 1)``, finite.

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, negative where a variance is expected, of the
        wrong shape or type, or if the variances overflow (``|a|`` too large for ``steps``).
    """
    a, sw2, sv2, sn2, p0, steps = _scalar_args(a, sigma_w2, sigma_v2, sigma_n2, p0, steps)
    fn = functools.partial(_scalar_chunk, a=a, sigma_w2=sw2, sigma_v2=sv2, sigma_n2=sn2,
                           channel=_channel(channel), p0=p0, steps=steps)
    return _finite_paths(montecarlo.simulate(fn, _int("n_paths", n_paths, 1),
                                             _int("seed", seed, 0), **runner))


def _finite_paths(res):
    """A Monte Carlo result whose variances stayed finite (else ``ValueError``)."""
    _finite_result("p_k", res.samples, "the variance overflows the float range (|a| too large "
                   "for this many steps)")
    return res


def scalar_mc(a, sigma_w2, sigma_v2, sigma_n2, channel, p0, steps, n_paths, seed, **runner):
    """``(mean, stderr)`` of ``p_k``, ``k = 0..steps``, over ``n_paths`` Monte Carlo paths.

    Parameters
    ----------
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

    Returns
    -------
    mean, stderr : numpy.ndarray
        ``(steps + 1,)``; ``stderr`` is NaN for one path (undefined).

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, negative where a variance is expected, of the
        wrong shape or type, or if the variances overflow (``|a|`` too large for ``steps``).
    """
    res = scalar_paths(a, sigma_w2, sigma_v2, sigma_n2, channel, p0, steps, n_paths, seed,
                       **runner)
    return res.mean, res.stderr


# ---------------------------------------------------------------------------- scalar: bounds
def expected_posterior(p, sigma_v2, sigma_n2, channel):
    """``E_r[p (r sigma_v2 + sigma_n2) / (r (p + sigma_v2) + sigma_n2)]`` (the bracket of (16)).

    Equals ``p (sigma_v2 + p g(b)) / (p + sigma_v2)`` with ``b = sigma_n2 / (p + sigma_v2)``.

    Parameters
    ----------
    p : array_like
        Prior variance(s), ``>= 0``.
    sigma_v2 : array_like
        Measurement-noise variance, ``>= 0``.
    sigma_n2 : array_like
        Channel-noise variance, ``> 0``.
    channel : Rayleigh or Nakagami
        The law of the power gain.

    Returns
    -------
    float or numpy.ndarray
        ``E_r[posterior variance]``, in ``[0, p]``.

    Raises
    ------
    ValueError
        If an argument is NaN, infinite or out of range.
    """
    p = _nonneg("p", p, _VARIANCE)
    sv2 = _nonneg("sigma_v2", sigma_v2, _VARIANCE)
    sn2 = _positive("sigma_n2", sigma_n2)
    with np.errstate(divide="ignore", invalid="ignore", under="ignore"):
        g = _channel(channel).ratio_mean(sn2 / (p + sv2))
        num = p * (sv2 + p * g)
        out = num / (p + sv2)
        # a subnormal numerator (p ~ 1e-160) has lost digits: the same ratio, grouped so
        # that no product of two small numbers is formed (only there: same bits elsewhere)
        tiny = num < np.finfo(float).tiny
        if np.any(tiny):
            out = np.where(tiny, p * ((sv2 + p * g) / np.where(p + sv2 > 0, p + sv2, 1.0)), out)
    # p = sigma_v2 = 0: a known state stays known (the limit of the formula, 0)
    out = np.where((p + sv2) == 0, 0.0, out)
    return out[()] if out.ndim == 0 else out


def _loose_map(a, sw2, sv2, sn2, channel) -> Callable[[float], float]:
    """Right-hand side of the loose recursion: (18) for Rayleigh, (20) for Nakagami(1/2).

    General Nakagami-m: ``m >= 1`` is less dispersed than Rayleigh (convex order, same mean)
    and ``1/2 <= m < 1`` less dispersed than Nakagami(1/2), so (18) resp. (20) with the same
    ``lam`` still bounds; that is what is used.
    """
    lam = channel.lam
    if channel.m >= 1.0:
        ln = lam * sn2

        def loose(q):
            return sw2 + a * a * (sv2 + ln * np.log1p((q + sv2) / ln))
    else:
        half = sn2 * lam / 2.0

        def loose(q):  # (20), with the two square roots added (see ERRATA: printed nested)
            den = np.sqrt(half) + np.sqrt(half + 4.0 / np.pi * (q + sv2))
            return sw2 + a * a * (sv2 + np.sqrt(sn2) * np.sqrt(2.0 * lam) * q / den)
    return loose


def _tight_map(a, sw2, sv2, sn2, channel) -> Callable[[float], float]:
    """``s -> sigma_w2 + a^2 E_r[...]``: (17) Rayleigh, (19) Nakagami(1/2), Z_k of (14) else."""

    def tight(s):
        return sw2 + a * a * expected_posterior(s, sv2, sn2, channel)
    return tight


def _iterate(fn: Callable[[float], float], x0: float, steps: int) -> np.ndarray:
    out = np.empty(steps + 1)
    out[0] = x = x0
    with np.errstate(over="ignore", invalid="ignore"):
        for k in range(steps):
            x = float(fn(x))
            out[k + 1] = x
    return _finite_result("the bound", out, "it overflows the float range (|a| too large for "
                          "this many steps)")


def _fixed_point(fn: Callable[[float], float], lo: float) -> float:
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


def scalar_bounds(a, sigma_w2, sigma_v2, sigma_n2, channel, p0, steps) -> dict:
    """The tight ``s`` and loose ``q`` upper-bound sequences on ``E[p_k]``, length ``steps + 1``.

    Rayleigh: ``s`` is (17), ``q`` is (18). Nakagami(1/2): ``s`` is (19), ``q`` is (20) (with the
    denominator corrected, see the errata). Other Nakagami-m: ``s`` is the scalar case of the
    paper's ``Z_k`` (14) with the exact expectation, ``q`` the loose bound of the more severe of
    the two paper cases (see :func:`_loose_map`). Both start at ``p0 = E[p_0]``.

    Parameters
    ----------
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

    Returns
    -------
    dict
        ``"s"`` and ``"q"``, each ``(steps + 1,)``, finite, ``s <= q``.

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, negative where a variance is expected, of the
        wrong shape or type, or if the variances overflow (``|a|`` too large for ``steps``).
    """
    a, sw2, sv2, sn2, p0, steps = _scalar_args(a, sigma_w2, sigma_v2, sigma_n2, p0, steps)
    ch = _channel(channel)
    return {"s": _iterate(_tight_map(a, sw2, sv2, sn2, ch), p0, steps),
            "q": _iterate(_loose_map(a, sw2, sv2, sn2, ch), p0, steps)}


def scalar_bound_limits(a, sigma_w2, sigma_v2, sigma_n2, channel) -> dict:
    """The limits ``s*`` and ``q*`` of :func:`scalar_bounds` (fixed points, by root finding).

    Parameters
    ----------
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

    Returns
    -------
    dict
        ``"s"`` and ``"q"``: the fixed points (floats).

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, negative where a variance is expected, of the
        wrong shape or type, or if the variances overflow (``|a|`` too large for ``steps``).
    """
    a, sw2, sv2, sn2, _, _ = _scalar_args(a, sigma_w2, sigma_v2, sigma_n2, 0.0, 0)
    ch = _channel(channel)
    return {"s": _fixed_point(_tight_map(a, sw2, sv2, sn2, ch), sw2),
            "q": _fixed_point(_loose_map(a, sw2, sv2, sn2, ch), sw2)}


def nakagami_q_as_printed(a, sigma_w2, sigma_v2, sigma_n2, lam, p0, steps) -> np.ndarray:
    """(20) exactly as printed, with the nested root ``sqrt(s2 l/2 + sqrt(s2 l/2 + ...))``.

    Kept only as evidence for the errata: it is not what the derivation before (20) gives.

    Parameters
    ----------
    a, sigma_w2, sigma_v2, sigma_n2
        As in :func:`scalar_bounds`.
    lam : float
        The Nakagami(1/2) parameter ``1 / E[r]``, ``> 0``.
    p0 : float
        ``E[p_0]``, ``>= 0``.
    steps : int
        Number of steps, ``>= 0``.

    Returns
    -------
    numpy.ndarray
        ``(steps + 1,)``.

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, negative where a variance is expected, of the
        wrong shape or type, or if the variances overflow (``|a|`` too large for ``steps``).
    """
    a, sw2, sv2, sn2, p0, steps = _scalar_args(a, sigma_w2, sigma_v2, sigma_n2, p0, steps)
    lam = _scalar("lam", _positive("lam", lam, "1 / mean power gain"))
    half = sn2 * lam / 2.0

    def printed(q):
        den = np.sqrt(half + np.sqrt(half + 4.0 / np.pi * (q + sv2)))
        return sw2 + a * a * (sv2 + np.sqrt(sn2) * np.sqrt(2.0 * lam) * q / den)
    return _iterate(printed, p0, steps)


# ------------------------------------------------------------------------------ multisensor
def _multi_args(access, a, c, sigma_v2, sigma_n2, lams, sigma_w2, p0, steps):
    if access not in ACCESS_SCHEMES:
        raise ValueError(f"access must be one of {ACCESS_SCHEMES}, got {access!r}")
    c = _finite("c", c)
    sv2 = _nonneg("sigma_v2", sigma_v2, _VARIANCE)
    lams = _positive("lams", lams, "1 / mean power gain of each sensor's channel")
    for name, arr in (("c", c), ("sigma_v2", sv2), ("lams", lams)):
        if arr.ndim != 1 or arr.size == 0:
            raise ValueError(f"{name} must be a non-empty 1-D sequence (one per sensor), "
                             f"got shape {arr.shape}")
    if not (c.size == sv2.size == lams.size):
        raise ValueError(f"c, sigma_v2 and lams must have one entry per sensor; got lengths "
                         f"{c.size}, {sv2.size}, {lams.size}")
    sn2 = _positive("sigma_n2", sigma_n2)
    if access == "multi-access":
        if sn2.ndim != 0:
            raise ValueError("sigma_n2 must be a scalar for the multi-access scheme (one "
                             "receiver noise)")
        if np.any(c <= 0):
            raise ValueError("c must be positive for the multi-access scheme (model (7) assumes "
                             "c_i > 0: flip the sign of a sensor's amplifier instead)")
        sn2 = float(sn2)
    else:
        if sn2.ndim > 1 or (sn2.ndim == 1 and sn2.size != c.size):
            raise ValueError(f"sigma_n2 must be a scalar or one per sensor ({c.size}), got "
                             f"shape {sn2.shape}")
        sn2 = np.broadcast_to(sn2, c.shape).astype(float)
    return (access, _scalar("a", _finite("a", a)), c, sv2, sn2, lams,
            _scalar("sigma_w2", _nonneg("sigma_w2", sigma_w2, _VARIANCE)),
            _scalar("p0", _nonneg("p0", p0, _VARIANCE)), _int("steps", steps, 0))


def _multi_chunk(rng, n, *, access, a, c, sigma_v2, sigma_n2, lams, sigma_w2, p0, steps):
    """``n`` paths of the multi-access or orthogonal recursion, ``(n, steps + 1)``.

    Both are ``p_{k+1} = sigma_w2 + a^2 p_k / (1 + p_k I_k)`` with the information
    ``I_k = (sum_i h_i c_i)^2 / (sum_i h_i^2 sigma_i^2 + sigma_n^2)`` (multi-access) or
    ``I_k = sum_i h_i^2 c_i^2 / (h_i^2 sigma_i^2 + sigma_n_i^2)`` (orthogonal).
    """
    r = rng.standard_exponential((c.size, steps, n))  # sensor, time, path
    r /= lams[:, None, None]
    if access == "multi-access":
        gain = np.tensordot(c, np.sqrt(r), axes=1) ** 2  # (sum_i h_i c_i)^2
        info = gain / (np.tensordot(sigma_v2, r, axes=1) + sigma_n2)
    else:
        info = np.zeros((steps, n))
        for i in range(c.size):
            info += c[i] ** 2 * r[i] / (r[i] * sigma_v2[i] + sigma_n2[i])
    out = np.empty((steps + 1, n))
    p = out[0] = np.full(n, p0)
    a2 = a * a
    for k in range(steps):
        p = sigma_w2 + a2 * p / (1.0 + p * info[k])
        out[k + 1] = p
    return out.T


def multisensor_paths(access, a, c, sigma_v2, sigma_n2, lams, sigma_w2, p0, steps, n_paths, seed,
                      **runner):
    """Sample paths of the multisensor recursion (Section 3.3) under Rayleigh fading.

    ``c``, ``sigma_v2`` and ``lams`` have one entry per sensor; ``sigma_n2`` is the receiver
    noise (multi-access) or per-channel noise(s) (orthogonal, scalar or one per sensor).

    Parameters
    ----------
    access : str
        ``"multi-access"`` (model (7)) or ``"orthogonal"`` (model (8)).
    a : float
        State transition, finite.
    c : array_like
        Measurement gains, one per sensor (``> 0`` for multi-access).
    sigma_v2 : array_like
        Measurement-noise variances, one per sensor, ``>= 0``.
    sigma_n2 : array_like
        Channel noise, ``> 0``: a scalar (multi-access), a scalar or one per channel (orthogonal).
    lams : array_like
        Rayleigh parameters ``1 / E[r_i]``, one per sensor, ``> 0``.
    sigma_w2 : float
        Process-noise variance, ``>= 0``.
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

    Returns
    -------
    MonteCarloResult
        ``samples`` ``(n_paths, steps + 1)``.

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, negative where a variance is expected, of the
        wrong shape or type, or if the variances overflow (``|a|`` too large for ``steps``).
    """
    access, a, c, sv2, sn2, lams, sw2, p0, steps = _multi_args(
        access, a, c, sigma_v2, sigma_n2, lams, sigma_w2, p0, steps)
    fn = functools.partial(_multi_chunk, access=access, a=a, c=c, sigma_v2=sv2, sigma_n2=sn2,
                           lams=lams, sigma_w2=sw2, p0=p0, steps=steps)
    return _finite_paths(montecarlo.simulate(fn, _int("n_paths", n_paths, 1),
                                             _int("seed", seed, 0), **runner))


def multisensor_mc(access, a, c, sigma_v2, sigma_n2, lams, sigma_w2, p0, steps, n_paths, seed,
                   **runner):
    """``(mean, stderr)`` of ``p_k``, ``k = 0..steps``, for the multisensor schemes.

    Parameters
    ----------
    access : str
        ``"multi-access"`` (model (7)) or ``"orthogonal"`` (model (8)).
    a : float
        State transition, finite.
    c : array_like
        Measurement gains, one per sensor (``> 0`` for multi-access).
    sigma_v2 : array_like
        Measurement-noise variances, one per sensor, ``>= 0``.
    sigma_n2 : array_like
        Channel noise, ``> 0``: a scalar (multi-access), a scalar or one per channel (orthogonal).
    lams : array_like
        Rayleigh parameters ``1 / E[r_i]``, one per sensor, ``> 0``.
    sigma_w2 : float
        Process-noise variance, ``>= 0``.
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

    Returns
    -------
    mean, stderr : numpy.ndarray
        ``(steps + 1,)``.

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, negative where a variance is expected, of the
        wrong shape or type, or if the variances overflow (``|a|`` too large for ``steps``).
    """
    res = multisensor_paths(access, a, c, sigma_v2, sigma_n2, lams, sigma_w2, p0, steps, n_paths,
                            seed, **runner)
    return res.mean, res.stderr


def _ratio_expect(alpha, beta, x, y, lam):
    """``E[(alpha r + x) / (beta r + y)]`` for ``r ~ Exp(lam)`` (``beta, y > 0``).

    ``= alpha / beta + (x - alpha y / beta) / beta * E[1 / (r + y / beta)]``; in the paper's
    notation ``sigma^2 / (c^2 g + sigma^2) [1 + (A - B) e^B E1(B)]``. ``beta = 0`` (a known
    state seen by a noise-free sensor) is the limit ``(alpha / lam + x) / y``.
    """
    if beta == 0:
        return (alpha / lam + x) / y
    b = y / beta
    return alpha / beta + (x - alpha * b) / beta * lam * exp_e1(lam * b)


def _multi_maps(access, a, c, sv2, sn2, lams, sw2, last_sensor):
    m = c.size
    a2 = a * a
    with np.errstate(divide="ignore"):
        snr = c**2 / sv2  # inf for a noise-free sensor
    if access == "multi-access":
        if last_sensor is None:
            worst = np.flatnonzero(np.isclose(snr, snr.min(), rtol=1e-12, atol=0.0))
        else:
            worst = np.array([last_sensor])

        def s_map(s):  # worst sensor alone; any order of tied sensors satisfies (22)
            vals = [_ratio_expect(sv2[j], c[j] ** 2 * s + sv2[j], sn2, sn2, lams[j])
                    for j in worst]
            return sw2 + a2 * s * min(vals)

        w = sv2 / lams  # E[r_j] sigma_j^2

        def t_map(t):  # (24)
            tot = sum(_ratio_expect(sv2[i], c[i] ** 2 * t + sv2[i], w.sum() - w[i] + sn2,
                                    sn2 / m, lams[i]) for i in range(m))
            return sw2 + a2 * t / m**2 * tot
    else:
        def s_map(s):  # min over which sensor is integrated last
            vals = [_ratio_expect(sv2[i], c[i] ** 2 * s + sv2[i], sn2[i], sn2[i], lams[i])
                    for i in range(m)]
            return sw2 + a2 * s * min(vals)

        def t_map(t):  # (25)-(26)
            tot = sum(_ratio_expect(m * sv2[i], m * c[i] ** 2 * t + sv2[i], m * sn2[i], sn2[i],
                                    lams[i]) for i in range(m))
            return sw2 + a2 * t / m**2 * tot
    return s_map, t_map


def _last_sensor(access, last_sensor, m):
    if last_sensor is None:
        return None
    if access != "multi-access":
        raise ValueError("last_sensor applies to the multi-access scheme only (the orthogonal "
                         "bound takes the minimum over every order)")
    last = _int("last_sensor", last_sensor, 0)
    if last >= m:
        raise ValueError(f"last_sensor must be a sensor index in 0..{m - 1}, got {last}")
    return last


def multisensor_bounds(access, a, c, sigma_v2, sigma_n2, lams, sigma_w2, p0, steps, *,
                       last_sensor: int | None = None) -> dict:
    """The bound sequences ``s`` (one sensor integrated last) and ``t`` (AM-HM), Section 3.3.

    Multi-access: ``s`` keeps only the worst sensor by ``c_i^2 / sigma_i^2`` (the ordering (22)
    puts it last); ``last_sensor`` overrides that choice, which violates (22) unless the sensor is
    a worst one, and then ``s`` need not bound ``E[p_k]`` (figure ``dey2009-ordering``).
    Orthogonal: ``s`` is the minimum over sensors (no ordering is needed). ``t`` is (24)/(26).

    Parameters
    ----------
    access : str
        ``"multi-access"`` (model (7)) or ``"orthogonal"`` (model (8)).
    a : float
        State transition, finite.
    c : array_like
        Measurement gains, one per sensor (``> 0`` for multi-access).
    sigma_v2 : array_like
        Measurement-noise variances, one per sensor, ``>= 0``.
    sigma_n2 : array_like
        Channel noise, ``> 0``: a scalar (multi-access), a scalar or one per channel (orthogonal).
    lams : array_like
        Rayleigh parameters ``1 / E[r_i]``, one per sensor, ``> 0``.
    sigma_w2 : float
        Process-noise variance, ``>= 0``.
    p0 : float
        ``E[p_0]``, ``>= 0``.
    steps : int
        Number of steps, ``>= 0``.
    last_sensor : int, optional
        Multi-access only: the sensor integrated last (default: a worst one).

    Returns
    -------
    dict
        ``"s"`` and ``"t"``, each ``(steps + 1,)``.

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, negative where a variance is expected, of the
        wrong shape or type, or if the variances overflow (``|a|`` too large for ``steps``).
    """
    access, a, c, sv2, sn2, lams, sw2, p0, steps = _multi_args(
        access, a, c, sigma_v2, sigma_n2, lams, sigma_w2, p0, steps)
    last = _last_sensor(access, last_sensor, c.size)
    s_map, t_map = _multi_maps(access, a, c, sv2, sn2, lams, sw2, last)
    return {"s": _iterate(s_map, p0, steps), "t": _iterate(t_map, p0, steps)}


def multisensor_bound_limits(access, a, c, sigma_v2, sigma_n2, lams, sigma_w2, *,
                             last_sensor: int | None = None) -> dict:
    """The limits ``s*`` and ``t*`` of :func:`multisensor_bounds` (fixed points).

    Parameters
    ----------
    access : str
        ``"multi-access"`` (model (7)) or ``"orthogonal"`` (model (8)).
    a : float
        State transition, finite.
    c : array_like
        Measurement gains, one per sensor (``> 0`` for multi-access).
    sigma_v2 : array_like
        Measurement-noise variances, one per sensor, ``>= 0``.
    sigma_n2 : array_like
        Channel noise, ``> 0``: a scalar (multi-access), a scalar or one per channel (orthogonal).
    lams : array_like
        Rayleigh parameters ``1 / E[r_i]``, one per sensor, ``> 0``.
    sigma_w2 : float
        Process-noise variance, ``>= 0``.
    last_sensor : int, optional
        As in :func:`multisensor_bounds`.

    Returns
    -------
    dict
        ``"s"`` and ``"t"``: the fixed points.

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, negative where a variance is expected, of the
        wrong shape or type, or if the variances overflow (``|a|`` too large for ``steps``).
    """
    access, a, c, sv2, sn2, lams, sw2, _, _ = _multi_args(
        access, a, c, sigma_v2, sigma_n2, lams, sigma_w2, 0.0, 0)
    last = _last_sensor(access, last_sensor, c.size)
    s_map, t_map = _multi_maps(access, a, c, sv2, sn2, lams, sw2, last)
    return {"s": _fixed_point(s_map, sw2), "t": _fixed_point(t_map, sw2)}


# ------------------------------------------------------------- vector state, scalar measurement
def _vector_args(A, c, Sigma_w, sigma_v2, sigma_n2, P0, steps):
    A = _finite("A", A)
    if A.ndim != 2 or A.shape[0] != A.shape[1]:
        raise ValueError(f"A must be a square matrix, got shape {A.shape}")
    n = A.shape[0]
    c = _finite("c", c)
    if c.shape != (n,):
        raise ValueError(f"c must be a row of length {n} (as A), got shape {c.shape}")
    Sigma_w = _finite("Sigma_w", Sigma_w)
    P0 = _finite("P0", P0)
    for name, M in (("Sigma_w", Sigma_w), ("P0", P0)):
        if M.shape != (n, n):
            raise ValueError(f"{name} must be {n}x{n} (as A), got shape {M.shape}")
        _covariance(name, M)
    return (A, c, Sigma_w, _scalar("sigma_v2", _nonneg("sigma_v2", sigma_v2, _VARIANCE)),
            _scalar("sigma_n2", _positive("sigma_n2", sigma_n2)), P0, _int("steps", steps, 0))


def _vector_step(P, A, c, Sigma_w, sigma_v2, weight):
    """(21): ``Sigma_w + A [P - P c' c P / (c P c' + sigma_v2) * weight] A'`` (batched)."""
    Pc = P @ c
    S = Pc @ c + sigma_v2
    # S = 0 (P c = 0 and a noise-free sensor): nothing to learn, the update is 0
    coef = np.where(S > 0, weight / np.where(S > 0, S, 1.0), 0.0)
    post = P - coef[..., None, None] * Pc[..., :, None] * Pc[..., None, :]
    out = A @ post @ A.T + Sigma_w
    return 0.5 * (out + np.swapaxes(out, -1, -2))


def _vector_chunk(rng, n, *, A, c, Sigma_w, sigma_v2, sigma_n2, channel, P0, steps):
    """``n`` paths of (21); returns the upper-triangle entries, ``(n, steps + 1, d(d+1)/2)``.

    ``P`` is kept flattened, ``(n, d*d)``, so that ``A X A'`` is one product with
    ``kron(A, A)`` and every operation is a plain 2-D array operation (fast for small ``d``).
    """
    d = A.shape[0]
    iu = np.triu_indices(d)
    flat_iu = iu[0] * d + iu[1]
    K = np.kron(A, A).T  # vec(A X A') = kron(A, A) vec(X) for row-major vec
    Cm = np.kron(np.eye(d), c).T  # (d*d, d): vec(X) @ Cm = X c
    r = channel.sample(rng, (n, steps))
    P = np.tile(P0.reshape(-1), (n, 1))
    sw = Sigma_w.reshape(-1)
    out = np.empty((n, steps + 1, flat_iu.size))
    out[:, 0] = P[:, flat_iu]
    for k in range(steps):
        Pc = P @ Cm
        S = Pc @ c + sigma_v2
        rk = r[:, k]
        wt = rk / (rk * S + sigma_n2)  # (r / (r + beta)) / S with beta = sigma_n2 / S
        post = P - wt[:, None] * (Pc[:, :, None] * Pc[:, None, :]).reshape(n, d * d)
        P = post @ K + sw
        out[:, k + 1] = P[:, flat_iu]
    return out


def vector_paths(A, c, Sigma_w, sigma_v2, sigma_n2, channel, P0, steps, n_paths, seed, **runner):
    """Paths of (21); ``samples`` hold the upper triangle of ``P_k`` (row-major ``triu``).

    Parameters
    ----------
    A : array_like
        State transition ``(n, n)``, finite.
    c : array_like
        Measurement row ``(n,)``, finite.
    Sigma_w : array_like
        Process-noise covariance ``(n, n)``, symmetric PSD.
    sigma_v2 : float
        Measurement-noise variance, ``>= 0``.
    sigma_n2 : float
        Channel-noise variance, ``> 0``.
    channel : Rayleigh or Nakagami
        The law of the power gain.
    P0 : array_like
        ``E[P_0]`` ``(n, n)``, symmetric PSD.
    steps : int
        Number of steps, ``>= 0``.
    n_paths : int
        Number of Monte Carlo paths, ``>= 1``.
    seed : int
        Non-negative integer seed (NumPy integers accepted, ``bool`` rejected).
    **runner
        ``chunk_size``, ``executor``, ``progress``, ``block_size`` of
        :func:`fusioncenter.montecarlo.simulate`.

    Returns
    -------
    MonteCarloResult
        ``samples`` ``(n_paths, steps + 1, n (n + 1) / 2)`` (upper triangles).

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, negative where a variance is expected, of the
        wrong shape or type, or if the variances overflow (``|a|`` too large for ``steps``).
    """
    A, c, Sw, sv2, sn2, P0, steps = _vector_args(A, c, Sigma_w, sigma_v2, sigma_n2, P0, steps)
    fn = functools.partial(_vector_chunk, A=A, c=c, Sigma_w=Sw, sigma_v2=sv2, sigma_n2=sn2,
                           channel=_channel(channel), P0=P0, steps=steps)
    return _finite_paths(montecarlo.simulate(fn, _int("n_paths", n_paths, 1),
                                             _int("seed", seed, 0), **runner))


def triu_to_symmetric(x, n: int) -> np.ndarray:
    """Symmetric ``(..., n, n)`` matrices from row-major upper triangles ``(..., n(n+1)/2)``
    (the layout of :func:`vector_paths` samples).

    Parameters
    ----------
    x : array_like
        Upper triangles ``(..., n (n + 1) / 2)``, finite.
    n : int
        Matrix size, ``>= 1``.

    Returns
    -------
    numpy.ndarray
        ``(..., n, n)``.

    Raises
    ------
    ValueError
        If ``x`` is not finite or its last axis is not ``n (n + 1) / 2``.
    """
    n = _int("n", n, 1)
    x = _finite("x", x)
    if x.ndim < 1 or x.shape[-1] != n * (n + 1) // 2:
        raise ValueError(f"x must have n (n + 1) / 2 = {n * (n + 1) // 2} entries on its last "
                         f"axis, got shape {x.shape}")
    iu = np.triu_indices(n)
    out = np.zeros((*x.shape[:-1], n, n))
    out[..., iu[0], iu[1]] = x
    out[..., iu[1], iu[0]] = x
    return out


def vector_mc(A, c, Sigma_w, sigma_v2, sigma_n2, channel, P0, steps, n_paths, seed, **runner):
    """``(mean, stderr)`` of ``P_k`` entrywise, each shaped ``(steps + 1, n, n)``.

    Parameters
    ----------
    A : array_like
        State transition ``(n, n)``, finite.
    c : array_like
        Measurement row ``(n,)``, finite.
    Sigma_w : array_like
        Process-noise covariance ``(n, n)``, symmetric PSD.
    sigma_v2 : float
        Measurement-noise variance, ``>= 0``.
    sigma_n2 : float
        Channel-noise variance, ``> 0``.
    channel : Rayleigh or Nakagami
        The law of the power gain.
    P0 : array_like
        ``E[P_0]`` ``(n, n)``, symmetric PSD.
    steps : int
        Number of steps, ``>= 0``.
    n_paths : int
        Number of Monte Carlo paths, ``>= 1``.
    seed : int
        Non-negative integer seed (NumPy integers accepted, ``bool`` rejected).
    **runner
        ``chunk_size``, ``executor``, ``progress``, ``block_size`` of
        :func:`fusioncenter.montecarlo.simulate`.

    Returns
    -------
    mean, stderr : numpy.ndarray
        ``(steps + 1, n, n)``.

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, negative where a variance is expected, of the
        wrong shape or type, or if the variances overflow (``|a|`` too large for ``steps``).
    """
    res = vector_paths(A, c, Sigma_w, sigma_v2, sigma_n2, channel, P0, steps, n_paths, seed,
                       **runner)
    n = np.asarray(A).shape[0]
    return triu_to_symmetric(res.mean, n), triu_to_symmetric(res.stderr, n)


def vector_bound(A, c, Sigma_w, sigma_v2, sigma_n2, channel, P0, steps) -> np.ndarray:
    """The bounding sequence ``Zbar_k`` of Section 3.2, shaped ``(steps + 1, n, n)``.

    ``Zbar_{k+1} = Sigma_w + A Zbar A' - A Zbar c' c Zbar A' / (c Zbar c' + sigma_v2) (1 - g)``
    with ``g = E[b / (r + b)]``, ``b = sigma_n2 / (c Zbar c' + sigma_v2)``; for Rayleigh
    ``g = mbar e^mbar E1(mbar)`` as printed. ``E[P_k] <= Zbar_k`` (Theorem 3.3).

    Parameters
    ----------
    A : array_like
        State transition ``(n, n)``, finite.
    c : array_like
        Measurement row ``(n,)``, finite.
    Sigma_w : array_like
        Process-noise covariance ``(n, n)``, symmetric PSD.
    sigma_v2 : float
        Measurement-noise variance, ``>= 0``.
    sigma_n2 : float
        Channel-noise variance, ``> 0``.
    channel : Rayleigh or Nakagami
        The law of the power gain.
    P0 : array_like
        ``E[P_0]`` ``(n, n)``, symmetric PSD.
    steps : int
        Number of steps, ``>= 0``.

    Returns
    -------
    numpy.ndarray
        ``Zbar`` ``(steps + 1, n, n)``.

    Raises
    ------
    ValueError
        Naming the argument that is NaN, infinite, negative where a variance is expected, of the
        wrong shape or type, or if the variances overflow (``|a|`` too large for ``steps``).
    """
    A, c, Sw, sv2, sn2, P0, steps = _vector_args(A, c, Sigma_w, sigma_v2, sigma_n2, P0, steps)
    ch = _channel(channel)
    out = np.empty((steps + 1, *P0.shape))
    out[0] = Z = P0
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        for k in range(steps):
            S = c @ Z @ c + sv2
            Z = _vector_step(Z, A, c, Sw, sv2, 1.0 - float(ch.ratio_mean(sn2 / S)))
            out[k + 1] = Z
    return _finite_result("the bound", out, "it overflows the float range (A too large for "
                          "this many steps)")
