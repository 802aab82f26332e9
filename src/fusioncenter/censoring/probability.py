"""Probabilities of the censoring decisions (zheng2014 Propositions 1-3).

``threshold`` (eq. (8)); ``prob_inside(m, h, log=...)``, the careful ``P(|Z + m| < h)``, and
``log_prob_inside(m, h)``, its fast log for the particle filters (the one implementation the
scalar, nonlinear and lossy-link filters share, with one cut-off); the sensor-level
``censored_probability`` / ``log_censored_probability``; the bivariate normal CDF and rectangle
probabilities; ``log_region_probability`` (the region of the corrected Proposition 3);
``log_silent_constant``; ``truncated_normal`` (inverse-cdf draws). The functions here check
their arguments; the filters call the same computations unchecked, in
:mod:`fusioncenter._compiled.censored_normal` (one normal variable) and
:mod:`fusioncenter._compiled.bivariate_normal` (two, and the regions of Proposition 3)."""

from __future__ import annotations

import inspect

import numpy as np
import scipy.stats

from fusioncenter import _validate as _v
from fusioncenter._compiled import bivariate_normal, censored_normal
from fusioncenter._docstrings import Glossary
from fusioncenter._validate import finite as _finite
from fusioncenter._validate import nonneg as _nonneg
from fusioncenter._validate import posint as _posint
from fusioncenter._validate import positive as _positive


# ----------------------------------------------------------------------------- threshold
def threshold(l, N, dof: int = 1) -> float:
    """``eta = chi2_dof(l / N)``: the upper ``l/N`` quantile of the chi-square law, eq. (8).

    If every sensor's normalized innovation squared is ``chi2_dof`` distributed, each sends with
    probability ``P(chi2_dof >= eta) = l / N``, so ``l`` of the ``N`` sensors send on average.
    ``l = N`` gives ``eta = 0`` (every sensor always sends). Requires ``0 < l <= N``.

    Parameters
    ----------
    l : float
        Target average number of sending sensors, ``0 < l <= N``.
    N : int
        Number of sensors.
    dof : int, optional
        Degrees of freedom (the measurement dimension ``m``).

    Returns
    -------
    float
        The threshold ``eta >= 0``.
    """
    N = _posint("N", N)
    dof = _posint("dof", dof)
    bad = ValueError(f"l (average number of sending sensors) must be a number in (0, N] = "
                     f"(0, {N}], got {l!r}")
    if isinstance(l, bool | np.bool_ | str | bytes) or np.ndim(l) != 0:  # 0-d array: a number
        raise bad
    try:
        lf = float(l)
    except (TypeError, ValueError):
        raise bad from None
    if not np.isfinite(lf) or not 0 < lf <= N:
        raise bad
    return float(scipy.stats.chi2.isf(lf / N, dof))


# ----------------------------------------------------------------------------- censored probability
#: Below this probability :func:`log_prob_inside` switches from the difference of two normal
#: distribution functions to the careful :func:`prob_inside` (one cut-off for every filter).
INSIDE_CUTOFF = censored_normal.INSIDE_CUTOFF


def _censored_args(mu, s, r, eta):
    mu = _finite("mu", mu)
    s = _nonneg("s", s)
    r = _positive("r", r)
    eta = _nonneg("eta", eta)
    sd = np.sqrt(r)
    return mu / sd, np.sqrt(eta * s) / sd


def censored_probability(mu, s, r, eta):
    """``P(|nu| < sqrt(eta s))`` for ``nu ~ N(mu, r)``: the probability that a sensor stays silent.

    In Proposition 1 this is ``Q(xi_1) - Q(xi_2)``, ``xi_{1,2} = (-/+ sqrt(eta s) - mu)/sqrt(r)``,
    with ``mu = h^T (x - xhat_{k|k-1})`` the innovation's mean given the state, ``r`` its variance
    given the state, and ``s`` the innovation variance the sensor normalizes by. Broadcasts like a
    ufunc; ``r > 0``, ``s >= 0``, ``eta >= 0``. Computed without cancellation: see
    :func:`log_censored_probability` (the same two branches without the log). Underflows to 0
    only where the probability is below ~1e-308; use the log version there.

    Parameters
    ----------
    mu, s, r, eta : array_like
        As in :func:`log_censored_probability` (broadcast).

    Returns
    -------
    numpy.ndarray or float
        The probabilities, in ``[0, 1]``.
    """
    m, h = _censored_args(mu, s, r, eta)
    out = censored_normal.prob_inside(m, h, log=False)
    return out[()] if out.ndim == 0 else out


def log_censored_probability(mu, s, r, eta):
    """``log P(|nu| < sqrt(eta s))`` for ``nu ~ N(mu, r)``, finite for any finite ``mu``.

    With ``m = |mu|/sqrt(r)``, ``h = sqrt(eta s / r)``, ``lo = m - h``: if ``lo <= 0``,
    ``log((erf((m+h)/sqrt2) + erf((h-m)/sqrt2))/2)``; otherwise
    ``log(1/2) - lo^2/2 + log erfcx(lo/sqrt2) + log(1 - exp(d))``,
    ``d = log(erfcx((m+h)/sqrt2)/erfcx(lo/sqrt2)) - 2 m h``; for a narrow interval off the mean
    (``h < 0.1``, ``m h < 0.1``) a Taylor series in ``h`` (see :func:`prob_inside`). Relative error
    ~1e-13 or better everywhere (checked against mpmath). ``-inf`` if ``eta s = 0``.

    Parameters
    ----------
    mu : array_like
        Innovation mean(s) given the state.
    s : array_like
        Innovation variance(s) the sensor normalizes by, ``>= 0``.
    r : array_like
        Innovation variance(s) given the state, ``> 0``.
    eta : array_like
        Threshold(s), ``>= 0``.

    Returns
    -------
    numpy.ndarray or float
        The log probabilities (``<= 0``).
    """
    m, h = _censored_args(mu, s, r, eta)
    out = censored_normal.prob_inside(m, h, log=True)
    return out[()] if out.ndim == 0 else out


# ----------------------------------------------------------------------------- bivariate normal
#: Below this value the inclusion-exclusion of Owen's-T distribution functions (absolute accuracy
#: ~1e-16) is replaced by a quadrature in the log domain (see :func:`log_bivariate_rectangle`).
CAREFUL_BELOW = bivariate_normal.CAREFUL_BELOW
#: Below ``|rho| = 1 - RHO_DEGENERATE`` the quadrature resolves the conditional law of ``Y``.
RHO_DEGENERATE = bivariate_normal.RHO_DEGENERATE

#: The arguments of the bivariate probabilities, and what they raise.
_bivariate = Glossary("""
h, k : array_like
    Upper bounds (``-inf`` / ``inf`` allowed), broadcast together.
l1, u1, l2, u2 : array_like
    Bounds (``-inf`` / ``inf`` allowed), broadcast together; an empty interval (``u <= l``) has
    probability 0.
rho : array_like
    Correlation in ``[-1, 1]``.
""", raises="""
ValueError
    Naming the bound that is text or NaN, or if ``rho`` is NaN or outside ``[-1, 1]``.
""")


@_bivariate(returns=("numpy.ndarray", "The probabilities, in ``[0, 1]`` (a float for scalar "
                     "inputs)."),
            raises=(("ValueError", "If ``h``, ``k`` or ``rho`` is NaN, or ``|rho| > 1``."),))
def bivariate_normal_cdf(h, k, rho):
    """``P(X <= h, Y <= k)`` for a standard bivariate normal with correlation ``rho``.

    Owen's T formula (absolute accuracy ~1e-16,
    :func:`fusioncenter._compiled.bivariate_normal.cdf_owen`) where the probability is at
    least :data:`CAREFUL_BELOW`; below, ``exp`` of :func:`log_bivariate_rectangle`
    ``(-inf, h, -inf, k)``, relative accuracy ~1e-12 down to ~1e-300.
    """
    out = bivariate_normal.cdf_owen(h, k, rho)
    small = np.atleast_1d(out < CAREFUL_BELOW)
    if small.any():
        out = np.atleast_1d(np.array(out, dtype=float))
        hh, kk, rr = (np.broadcast_to(np.asarray(v, dtype=float), out.shape)[small]
                      for v in (h, k, rho))
        with np.errstate(under="ignore"):
            out[small] = np.exp(log_bivariate_rectangle(-np.inf, hh, -np.inf, kk, rr))
        out = out.reshape(np.broadcast_shapes(np.shape(h), np.shape(k), np.shape(rho)))
        return out[()] if out.ndim == 0 else out
    return out


@_bivariate(returns=("numpy.ndarray", "The probabilities, in ``[0, 1]``."))
def bivariate_rectangle(l1, u1, l2, u2, rho):
    """``P(l1 < X < u1, l2 < Y < u2)`` for a standard bivariate normal, correlation ``rho``.

    ``exp`` of :func:`log_bivariate_rectangle`: relative accuracy ~1e-12 wherever the result is
    above ~1e-300 (below, it underflows: use the log version).
    """
    _no_nan_bounds(l1=l1, u1=u1, l2=l2, u2=u2)
    return bivariate_normal.bivariate_rectangle(l1, u1, l2, u2, rho)


def _no_nan_bounds(**bounds) -> None:
    """The bounds of a rectangle: numbers (infinities allowed), not NaN, named in the message."""
    for name, value in bounds.items():
        if np.any(np.isnan(_v.as_float(name, value))):
            raise ValueError(f"{name} must not be NaN (a bound; -inf and inf are allowed), got "
                             f"{value!r}")


@_bivariate(returns=("numpy.ndarray", "The log probabilities (``<= 0``; ``-inf`` for an empty "
                     "rectangle)."))
def log_bivariate_rectangle(l1, u1, l2, u2, rho):
    """``log P(l1 < X < u1, l2 < Y < u2)`` for a standard bivariate normal, correlation ``rho``.

    Where the probability is at least :data:`CAREFUL_BELOW`, the inclusion-exclusion of four
    :func:`bivariate_normal_cdf` values (Owen's T; absolute accuracy ~1e-16, so relative
    ~1e-11 or better there). Below, where that difference cancels (a small rectangle, a rectangle
    in the tails), a quadrature in ``x`` of ``phi(x) P(l2 < Y < u2 | x)`` in the log domain
    (``_log_rectangle_quadrature`` of :mod:`fusioncenter._compiled.bivariate_normal`):
    relative accuracy ~1e-12 however small the probability (checked against mpmath down to
    1e-300 and below). ``|rho| > 1 - 1e-6`` keeps the inclusion-exclusion (the conditional law
    is too narrow for the quadrature).
    """
    _no_nan_bounds(l1=l1, u1=u1, l2=l2, u2=u2)
    return bivariate_normal.log_bivariate_rectangle(l1, u1, l2, u2, rho)


# ----------------------------------------------------------------------------- checked entry points
# The filters' kernels are in fusioncenter._compiled.censored_normal and .bivariate_normal (no
# checks: the callers validated their inputs once); the public names below check their arguments
# and then call the same kernel, so a valid call gives the same bits.
def _half_widths(name: str, h) -> np.ndarray:
    h = _v.as_float(name, h)
    if np.any(np.isnan(h)) or np.any(h < 0):
        raise ValueError(f"{name} must be a non-negative half-width (+inf allowed), got {h!r}")
    return h


def _check_inside(m, h, **_) -> dict:
    m, h = _finite("m", m), _half_widths("h", h)
    _v.broadcast(m=m, h=h)
    return dict(m=m, h=h)


def _check_truncated(u, lo, hi) -> dict:
    u = _finite("u", u)
    if np.any((u < 0) | (u > 1)):
        raise ValueError(f"u must lie in [0, 1] (uniforms), got {u!r}")
    lo, hi = _v.as_float("lo", lo), _v.as_float("hi", hi)
    if np.any(np.isnan(lo)) or np.any(np.isnan(hi)):
        raise ValueError("lo and hi must not be NaN (interval bounds; +-inf allowed)")
    ub, lob, hib = _v.broadcast(u=u, lo=lo, hi=hi)
    if np.any(lob > hib):
        raise ValueError("lo must not exceed hi (an empty interval has no conditional law)")
    return dict(u=u, lo=lo, hi=hi)


def _check_silent_constant(Vcov, a) -> dict:
    a = _v.nonneg("a", a, "a half-width")
    _v.shape_is("a", a, (None,), "(K,)")
    return dict(Vcov=_v.covariance("Vcov", Vcov, n=a.shape[0]), a=a)


def _check_region(c, cov, a, outside) -> dict:
    a = _v.shape_is("a", _v.nonneg("a", a, "a half-width"), (None,), "(K,)")
    K = a.shape[0]
    c = _v.shape_is("c", _finite("c", c), (..., K), f"a has K = {K} entries")
    cov = _v.covariance("cov", cov, n=K)
    if len(outside) != K:
        raise ValueError(f"outside must have K = {K} entries, got {len(outside)}")
    return dict(c=c, cov=cov, a=a, outside=outside)


def _check_degenerate(mean, cov, eta) -> dict:
    mean = _v.shape_is("mean", _finite("mean", mean), (None, None), "(k, m)")
    cov = _v.covariance("cov", cov, batch=True)
    _v.shape_is("cov", cov, (mean.shape[0], mean.shape[1], mean.shape[1]), "(k, m, m) as mean")
    return dict(mean=mean, cov=cov, eta=float(_nonneg("eta", eta, "a threshold")))


_RAISES = """

    Raises
    ------
    ValueError
        Naming the argument that is not finite (bounds and half-widths may be ``+inf``), is
        negative where it is a half-width or threshold, is not a covariance, or whose shape does
        not match (the message states the expected shape).
"""


def _checked(kernel, check):
    sig = inspect.signature(kernel)

    def public(*args, **kwargs):
        bound = sig.bind(*args, **kwargs)
        bound.arguments.update(check(**bound.arguments))  # the arrays, converted
        return kernel(*bound.args, **bound.kwargs)
    public.__name__ = public.__qualname__ = kernel.__name__
    public.__module__ = __name__
    public.__doc__ = (kernel.__doc__ or "").replace(" No validation.", "").rstrip() + _RAISES
    public.__signature__ = sig
    return public


prob_inside = _checked(censored_normal.prob_inside, _check_inside)
log_prob_inside = _checked(censored_normal.log_prob_inside, _check_inside)
truncated_normal = _checked(censored_normal.truncated_normal, _check_truncated)
log_inside_degenerate = _checked(censored_normal.log_inside_degenerate, _check_degenerate)
log_silent_constant = _checked(bivariate_normal.log_silent_constant, _check_silent_constant)
log_region_probability = _checked(bivariate_normal.log_region_probability, _check_region)
