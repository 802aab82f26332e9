"""The scalar random Riccati equation (15) of dey2009: Monte Carlo and the bounds (16)-(20).

:func:`scalar_paths` / :func:`scalar_mc` sample ``p_k`` through
:func:`fusioncenter.montecarlo.simulate`; :func:`expected_posterior` is the bracket of (16);
:func:`scalar_bounds` gives the tight and loose bound sequences ((17)-(18) Rayleigh, (19)-(20)
Nakagami(1/2)) and :func:`scalar_bound_limits` their fixed points;
:func:`nakagami_q_as_printed` is (20) as printed (for the errata).
"""

from __future__ import annotations

import functools
from collections.abc import Callable

import numpy as np

from fusioncenter._validate import finite as _finite
from fusioncenter._validate import integer as _int
from fusioncenter._validate import nonneg as _nonneg
from fusioncenter._validate import positive as _positive
from fusioncenter.fading._common import (
    VARIANCE,
    check_channel,
    check_scalar,
    fixed_point,
    iterate,
    simulate_paths,
)
from fusioncenter.fading._common import document as _doc

__all__ = ["scalar_paths", "scalar_mc", "expected_posterior", "scalar_bounds",
           "scalar_bound_limits", "nakagami_q_as_printed"]


def _scalar_args(a, sigma_w2, sigma_v2, sigma_n2, p0, steps):
    return (check_scalar("a", _finite("a", a)),
            check_scalar("sigma_w2", _nonneg("sigma_w2", sigma_w2, VARIANCE)),
            check_scalar("sigma_v2", _nonneg("sigma_v2", sigma_v2, VARIANCE)),
            check_scalar("sigma_n2", _positive("sigma_n2", sigma_n2)),
            check_scalar("p0", _nonneg("p0", p0, VARIANCE)),
            _int("steps", steps, 0))


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


@_doc(returns=("MonteCarloResult", "``samples`` ``(n_paths, steps + 1)``, finite."))
def scalar_paths(a, sigma_w2, sigma_v2, sigma_n2, channel, p0, steps, n_paths, seed, **runner):
    """Sample paths of (15) as a :class:`~fusioncenter.montecarlo.MonteCarloResult`.

    ``samples`` is ``(n_paths, steps + 1)``; ``p_0 = p0`` on every path. ``runner`` keywords
    (``chunk_size``, ``executor``, ``progress``) go to :func:`fusioncenter.montecarlo.simulate`.
    """
    a, sw2, sv2, sn2, p0, steps = _scalar_args(a, sigma_w2, sigma_v2, sigma_n2, p0, steps)
    fn = functools.partial(_scalar_chunk, a=a, sigma_w2=sw2, sigma_v2=sv2, sigma_n2=sn2,
                           channel=check_channel(channel), p0=p0, steps=steps)
    return simulate_paths(fn, n_paths, seed, **runner)


@_doc(
      returns=("mean, stderr : numpy.ndarray", "``(steps + 1,)``; ``stderr`` is NaN for one "
                                               "path (undefined)."))
def scalar_mc(a, sigma_w2, sigma_v2, sigma_n2, channel, p0, steps, n_paths, seed, **runner):
    """``(mean, stderr)`` of ``p_k``, ``k = 0..steps``, over ``n_paths`` Monte Carlo paths."""
    res = scalar_paths(a, sigma_w2, sigma_v2, sigma_n2, channel, p0, steps, n_paths, seed,
                       **runner)
    return res.mean, res.stderr


@_doc(returns=("float or numpy.ndarray", "``E_r[posterior variance]``, in ``[0, p]``."),
      raises=(("ValueError", "If an argument is NaN, infinite or out of range."),),
      sigma_v2=("array_like", "Measurement-noise variance, ``>= 0``."),
      sigma_n2=("array_like", "Channel-noise variance, ``> 0``."))
def expected_posterior(p, sigma_v2, sigma_n2, channel):
    """``E_r[p (r sigma_v2 + sigma_n2) / (r (p + sigma_v2) + sigma_n2)]`` (the bracket of (16)).

    Equals ``p (sigma_v2 + p g(b)) / (p + sigma_v2)`` with ``b = sigma_n2 / (p + sigma_v2)``.
    """
    p = _nonneg("p", p, VARIANCE)
    sv2 = _nonneg("sigma_v2", sigma_v2, VARIANCE)
    sn2 = _positive("sigma_n2", sigma_n2)
    with np.errstate(divide="ignore", invalid="ignore", under="ignore"):
        g = check_channel(channel).ratio_mean(sn2 / (p + sv2))
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


@_doc(returns=("dict", '``"s"`` and ``"q"``, each ``(steps + 1,)``, finite, ``s <= q``.'))
def scalar_bounds(a, sigma_w2, sigma_v2, sigma_n2, channel, p0, steps) -> dict:
    """The tight ``s`` and loose ``q`` upper-bound sequences on ``E[p_k]``, length ``steps + 1``.

    Rayleigh: ``s`` is (17), ``q`` is (18). Nakagami(1/2): ``s`` is (19), ``q`` is (20) (with the
    denominator corrected, see the errata). Other Nakagami-m: ``s`` is the scalar case of the
    paper's ``Z_k`` (14) with the exact expectation, ``q`` the loose bound of the more severe of
    the two paper cases (see :func:`_loose_map`). Both start at ``p0 = E[p_0]``.
    """
    a, sw2, sv2, sn2, p0, steps = _scalar_args(a, sigma_w2, sigma_v2, sigma_n2, p0, steps)
    ch = check_channel(channel)
    return {"s": iterate(_tight_map(a, sw2, sv2, sn2, ch), p0, steps),
            "q": iterate(_loose_map(a, sw2, sv2, sn2, ch), p0, steps)}


@_doc(returns=("dict", '``"s"`` and ``"q"``: the fixed points (floats).'))
def scalar_bound_limits(a, sigma_w2, sigma_v2, sigma_n2, channel) -> dict:
    """The limits ``s*`` and ``q*`` of :func:`scalar_bounds` (fixed points, by root finding)."""
    a, sw2, sv2, sn2, _, _ = _scalar_args(a, sigma_w2, sigma_v2, sigma_n2, 0.0, 0)
    ch = check_channel(channel)
    return {"s": fixed_point(_tight_map(a, sw2, sv2, sn2, ch), sw2),
            "q": fixed_point(_loose_map(a, sw2, sv2, sn2, ch), sw2)}


@_doc(returns=("numpy.ndarray", "``(steps + 1,)``."))
def nakagami_q_as_printed(a, sigma_w2, sigma_v2, sigma_n2, lam, p0, steps) -> np.ndarray:
    """(20) exactly as printed, with the nested root ``sqrt(s2 l/2 + sqrt(s2 l/2 + ...))``.

    Kept only as evidence for the errata: it is not what the derivation before (20) gives.
    """
    a, sw2, sv2, sn2, p0, steps = _scalar_args(a, sigma_w2, sigma_v2, sigma_n2, p0, steps)
    lam = check_scalar("lam", _positive("lam", lam, "1 / mean power gain"))
    half = sn2 * lam / 2.0

    def printed(q):
        den = np.sqrt(half + np.sqrt(half + 4.0 / np.pi * (q + sv2)))
        return sw2 + a * a * (sv2 + np.sqrt(sn2) * np.sqrt(2.0 * lam) * q / den)
    return iterate(printed, p0, steps)
