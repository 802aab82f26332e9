"""Several sensors under Rayleigh fading (dey2009 Section 3.3): multi-access (7), orthogonal (8).

:func:`multisensor_paths` / :func:`multisensor_mc` sample the prediction variance;
:func:`multisensor_bounds` gives the bound ``s`` (one sensor integrated last) and the AM-HM
bound ``t`` ((24), (26)), :func:`multisensor_bound_limits` their fixed points.
"""

from __future__ import annotations

import functools

import numpy as np

from fusioncenter._validate import finite as _finite
from fusioncenter._validate import integer as _int
from fusioncenter._validate import nonneg as _nonneg
from fusioncenter._validate import positive as _positive
from fusioncenter.fading._common import (
    VARIANCE,
    check_scalar,
    document,
    fixed_point,
    iterate,
    simulate_paths,
)
from fusioncenter.fading.channels import exp_e1

__all__ = ["ACCESS_SCHEMES", "multisensor_paths", "multisensor_mc", "multisensor_bounds",
           "multisensor_bound_limits"]


_doc = document.extend("""
a : float
    State transition, finite.
sigma_v2 : array_like
    Measurement-noise variances, one per sensor, ``>= 0``.
sigma_n2 : array_like
    Channel noise, ``> 0``: a scalar (multi-access), a scalar or one per channel (orthogonal).
""")


ACCESS_SCHEMES = ("multi-access", "orthogonal")


def _multi_args(access, a, c, sigma_v2, sigma_n2, lams, sigma_w2, p0, steps):
    if access not in ACCESS_SCHEMES:
        raise ValueError(f"access must be one of {ACCESS_SCHEMES}, got {access!r}")
    c = _finite("c", c)
    sv2 = _nonneg("sigma_v2", sigma_v2, VARIANCE)
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
    return (access, check_scalar("a", _finite("a", a)), c, sv2, sn2, lams,
            check_scalar("sigma_w2", _nonneg("sigma_w2", sigma_w2, VARIANCE)),
            check_scalar("p0", _nonneg("p0", p0, VARIANCE)), _int("steps", steps, 0))


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


@_doc(returns=("MonteCarloResult", "``samples`` ``(n_paths, steps + 1)``."))
def multisensor_paths(access, a, c, sigma_v2, sigma_n2, lams, sigma_w2, p0, steps, n_paths, seed,
                      **runner):
    """Sample paths of the multisensor recursion (Section 3.3) under Rayleigh fading.

    ``c``, ``sigma_v2`` and ``lams`` have one entry per sensor; ``sigma_n2`` is the receiver
    noise (multi-access) or per-channel noise(s) (orthogonal, scalar or one per sensor).
    """
    access, a, c, sv2, sn2, lams, sw2, p0, steps = _multi_args(
        access, a, c, sigma_v2, sigma_n2, lams, sigma_w2, p0, steps)
    fn = functools.partial(_multi_chunk, access=access, a=a, c=c, sigma_v2=sv2, sigma_n2=sn2,
                           lams=lams, sigma_w2=sw2, p0=p0, steps=steps)
    return simulate_paths(fn, n_paths, seed, **runner)


@_doc(returns=("mean, stderr : numpy.ndarray", "``(steps + 1,)``."))
def multisensor_mc(access, a, c, sigma_v2, sigma_n2, lams, sigma_w2, p0, steps, n_paths, seed,
                   **runner):
    """``(mean, stderr)`` of ``p_k``, ``k = 0..steps``, for the multisensor schemes."""
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


@_doc(returns=("dict", '``"s"`` and ``"t"``, each ``(steps + 1,)``.'))
def multisensor_bounds(access, a, c, sigma_v2, sigma_n2, lams, sigma_w2, p0, steps, *,
                       last_sensor: int | None = None) -> dict:
    """The bound sequences ``s`` (one sensor integrated last) and ``t`` (AM-HM), Section 3.3.

    Multi-access: ``s`` keeps only the worst sensor by ``c_i^2 / sigma_i^2`` (the ordering (22)
    puts it last); ``last_sensor`` overrides that choice, which violates (22) unless the sensor is
    a worst one, and then ``s`` need not bound ``E[p_k]`` (figure ``dey2009-ordering``).
    Orthogonal: ``s`` is the minimum over sensors (no ordering is needed). ``t`` is (24)/(26).
    """
    access, a, c, sv2, sn2, lams, sw2, p0, steps = _multi_args(
        access, a, c, sigma_v2, sigma_n2, lams, sigma_w2, p0, steps)
    last = _last_sensor(access, last_sensor, c.size)
    s_map, t_map = _multi_maps(access, a, c, sv2, sn2, lams, sw2, last)
    return {"s": iterate(s_map, p0, steps), "t": iterate(t_map, p0, steps)}


@_doc(returns=("dict", '``"s"`` and ``"t"``: the fixed points.'),
      last_sensor="As in :func:`multisensor_bounds`.")
def multisensor_bound_limits(access, a, c, sigma_v2, sigma_n2, lams, sigma_w2, *,
                             last_sensor: int | None = None) -> dict:
    """The limits ``s*`` and ``t*`` of :func:`multisensor_bounds` (fixed points)."""
    access, a, c, sv2, sn2, lams, sw2, _, _ = _multi_args(
        access, a, c, sigma_v2, sigma_n2, lams, sigma_w2, 0.0, 0)
    last = _last_sensor(access, last_sensor, c.size)
    s_map, t_map = _multi_maps(access, a, c, sv2, sn2, lams, sw2, last)
    return {"s": fixed_point(s_map, sw2), "t": fixed_point(t_map, sw2)}
