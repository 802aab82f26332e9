"""The channel laws of dey2009 and the special functions of their expectations.

:class:`Rayleigh` and :class:`Nakagami` (sampling, density, ``E[1 / (r + b)]`` and the ratio
``g(b) = E[b / (r + b)]`` everything in the package is written in, and the inequalities the
loose bounds use); :func:`exp_e1` is a numerically safe ``e^x E1(x)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.special

from fusioncenter._docstrings import Glossary
from fusioncenter._validate import as_float as _as_float
from fusioncenter._validate import positive as _positive

__all__ = ["exp_e1", "Rayleigh", "Nakagami"]


#: Below this argument ``exp(x) * scipy.special.exp1(x)`` is accurate to a few ulp (it would
#: underflow/overflow beyond ~700); above it the continued fraction with :data:`_E1_CF_DEPTH`
#: terms is (both checked against mpmath on a log grid in the tests).
_E1_SWITCH = 50.0


_E1_CF_DEPTH = 16


#: The same for the general Nakagami-m expectation ``z^m U(m, m, z)`` (scipy's ``hyperu`` loses
#: digits for large ``z``).
_CF_SWITCH = 2.0


_CF_DEPTH = 64


def _notnan(name: str, value) -> np.ndarray:
    """Floats, no NaN (infinities are the documented limits of the special functions)."""
    arr = _as_float(name, value)  # text refused: NumPy would read "1" as 1.0
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
        If ``x`` is text, or an entry is NaN or negative.
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


def _x_exp_e1(mu: np.ndarray) -> np.ndarray:
    """``μ e^μ E1(μ)`` in (0, 1), with the limits 0 at ``μ = 0`` and 1 at ``μ = inf``."""
    mu = np.asarray(mu, dtype=float)
    with np.errstate(invalid="ignore"):
        out = np.where(mu > 0, mu * exp_e1(np.where(mu > 0, mu, 1.0)), 0.0)
    return np.where(np.isposinf(mu), 1.0, out)


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


def _shift(name: str, value) -> np.ndarray:
    """A non-negative shift ``b``; ``+inf`` is allowed (the limit of a noiseless channel)."""
    arr = _notnan(name, value)
    if np.any(arr < 0):
        raise ValueError(f"{name} must be non-negative, got {value!r}")
    return arr


def _rate(name: str, value) -> float:
    try:
        ok = (not isinstance(value, bool | str | bytes) and math.isfinite(float(value))
              and float(value) > 0)
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise ValueError(f"{name} must be a positive finite number (1 / mean power gain), "
                         f"got {value!r}")
    return float(value)


#: The parameters of the two laws.
_doc = Glossary("""
lam : float
    ``1 / E[r]``, the inverse of the mean power gain: finite and ``> 0``.
m : float
    The Nakagami fading parameter (shape of the Gamma law), finite and ``>= 1/2``.
rng : numpy.random.Generator
    The generator to draw with.
size : int or tuple of int
    The shape of the draw.
r : array_like
    Power gains (not NaN).
b : array_like
    Shifts ``b >= 0`` (``+inf`` allowed: the limit of a noiseless channel).
""")
#: The ``Raises`` sections of the laws' methods.
_BAD_R = (("ValueError", "If ``r`` is text or NaN."),)
_BAD_B = (("ValueError", "If ``b`` is text, NaN or negative."),)
#: ``b`` of :meth:`Rayleigh.inverse_mean` and :meth:`Nakagami.inverse_mean`.
_POSITIVE_B = dict(b=("array_like", "Shifts ``b > 0``, finite."),
                   raises=(("ValueError", "If ``b`` is not finite and positive."),))


class _PowerGainLaw:
    """What both laws share: the rate ``lam = 1 / E[r]`` of the power gain."""

    @property
    def mean_gain(self) -> float:
        """``E[r] = 1 / lam``."""
        return 1.0 / self.lam


@_doc.attributes(raises=(("ValueError", "If ``lam`` is not a finite number ``> 0``."),))
@dataclass(frozen=True)
class Rayleigh(_PowerGainLaw):
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

    @_doc(returns=("numpy.ndarray", "Exponential power gains of shape ``size``."), raises=())
    def sample(self, rng: np.random.Generator, size) -> np.ndarray:
        """Power gains ``r = h^2`` drawn with ``rng``."""
        return rng.standard_exponential(size) / self.lam

    @_doc(returns=("numpy.ndarray", "``lam exp(-lam r)``, broadcast over ``r``."), raises=_BAD_R)
    def pdf(self, r):
        """The density of ``r`` (0 for ``r < 0``); ``r`` must not be NaN."""
        r = _notnan("r", r)
        return np.where(r >= 0, self.lam * np.exp(-self.lam * np.maximum(r, 0.0)), 0.0)

    @_doc(returns=("float or numpy.ndarray", "``E[1 / (r + b)]``, broadcast over ``b``."),
          **_POSITIVE_B)
    def inverse_mean(self, b):
        """``E[1 / (r + b)] = lam e^{lam b} E1(lam b)`` for ``b > 0``."""
        b = _positive("b", b, "a shift")
        return self.lam * exp_e1(self.lam * b)

    @_doc(returns=("numpy.ndarray", "``g(b)`` in ``[0, 1]``, broadcast over ``b``."),
          raises=_BAD_B)
    def ratio_mean(self, b):
        """``g(b) = E[b / (r + b)] = μ e^μ E1(μ)``, ``μ = lam b`` (in [0, 1]; 0 at ``b = 0``)."""
        return _x_exp_e1(self.lam * _shift("b", b))

    @_doc(returns=("numpy.ndarray", "The bound, in ``[0, 1]``, broadcast over ``b``."),
          raises=_BAD_B)
    def ratio_mean_bound(self, b):
        """``μ ln(1 + 1/μ) >= g(b)``, ``μ = lam b``: the inequality ``e^x E1(x) < ln(1 + 1/x)``
        used for (18)."""
        mu = self.lam * _shift("b", b)
        with np.errstate(divide="ignore", invalid="ignore"):
            out = np.where(mu > 0, mu * np.log1p(1.0 / np.where(mu > 0, mu, 1.0)), 0.0)
        return np.where(np.isposinf(mu), 1.0, out)


@_doc.attributes(raises=(("ValueError", "If ``m`` or ``lam`` is out of range (the message names "
                                       "it)."),))
@dataclass(frozen=True)
class Nakagami(_PowerGainLaw):
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

    @_doc(returns=("numpy.ndarray", "Gamma power gains of shape ``size``."), raises=())
    def sample(self, rng: np.random.Generator, size) -> np.ndarray:
        """Power gains drawn with ``rng`` (``m = 1/2``: ``Z^2 / lam``, ``Z`` standard normal)."""
        if self.m == 0.5:
            return rng.standard_normal(size) ** 2 / self.lam
        return rng.gamma(self.m, 1.0 / (self.lam * self.m), size)

    @_doc(returns=("numpy.ndarray", "The Gamma density, broadcast over ``r``."), raises=_BAD_R)
    def pdf(self, r):
        """The density of ``r`` (0 for ``r <= 0``); ``r`` must not be NaN."""
        r = _notnan("r", r)
        m, lam = self.m, self.lam
        rp = np.where(r > 0, r, 1.0)
        logp = (m * np.log(m * lam) + (m - 1) * np.log(rp) - lam * m * rp
                - scipy.special.gammaln(m))
        return np.where(r > 0, np.exp(logp), 0.0)

    @_doc(returns=("numpy.ndarray", "``g(b)`` in ``[0, 1]``, broadcast over ``b``."),
          raises=_BAD_B)
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

    @_doc(returns=("float or numpy.ndarray", "``E[1 / (r + b)]``, broadcast over ``b``."),
          **_POSITIVE_B)
    def inverse_mean(self, b):
        """``E[1 / (r + b)]`` for ``b > 0`` (``= g(b) / b``)."""
        b = _positive("b", b, "a shift")
        return self.ratio_mean(b) / b

    @_doc(returns=("numpy.ndarray", "The bound, in ``[0, 1]``, broadcast over ``b``."),
          raises=(("ValueError", "If ``m`` is not 1/2, or ``b`` is text, NaN or negative."),))
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
