"""The four allocation problems of leong2011 (Section IV) in their general form.

Each takes the coefficients ``rho_i``, ``tau_i``, ``kappa_i``, the receiver noise ``sigma_n2``
and either the constraint constants ``x, y`` (minimum power) or the budget ``gamma_total``
(maximum SNR): :func:`coherent_min_power` (19), :func:`coherent_max_snr` (23) (and the printed
(24), :func:`coherent_max_snr_printed`), :func:`orthogonal_min_power` (26) and
:func:`orthogonal_max_snr` (28); :func:`general_min_power` and :func:`general_max_snr` pick the
scheme's solver. An unreachable target raises :class:`InfeasibleError`.
"""

from __future__ import annotations

import numpy as np

from fusioncenter._validate import nonneg as _nonneg
from fusioncenter._validate import positive as _positive
from fusioncenter.power._common import (
    ALPHA,
    IDEAL_CHANNEL,
    INFEASIBLE,
    SN2_MIN_POWER,
    check_access,
    check_general,
)
from fusioncenter.power._common import document as _doc

__all__ = ["InfeasibleError", "coherent_min_power", "coherent_max_snr", "coherent_max_snr_printed",
           "orthogonal_min_power", "orthogonal_max_snr", "general_min_power", "general_max_snr"]


class InfeasibleError(ValueError):
    """The error-covariance target cannot be met with any amplification factors."""


def _noisy(sn):
    if np.any(sn == 0):
        raise ValueError(f"sigma_n2 must be positive for a minimum-power problem: "
                         f"{IDEAL_CHANNEL}")
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


@_doc(returns=ALPHA, raises=INFEASIBLE, sigma_n2=SN2_MIN_POWER)
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
    """
    rho, tau, kap, sn = check_general(rho, tau, kappa, sigma_n2)
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


@_doc(returns=ALPHA)
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
    """
    rho, tau, kap, sn = check_general(rho, tau, kappa, sigma_n2)
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
        wmax = np.abs(w).max(axis=-1)
        if np.any((norm == 0) & (wmax == 0)):
            raise ValueError("rho must have a non-zero entry (otherwise S = 0 whatever alpha)")
        # w^2 underflowed (a huge gamma_total makes w ~ rho sigma_n2 / (gamma tau)): only the
        # direction of w matters, so rescale it where that happened (elsewhere: the same bits)
        ws = w / np.where(norm == 0, wmax, 1.0)[..., None]
        norm_s = np.sum(ws**2 * kap, axis=-1)
        return np.where((norm == 0)[..., None], ws * np.sqrt(g / norm_s)[..., None],
                        w * np.sqrt(g / np.where(norm == 0, 1.0, norm))[..., None])
    return w * np.sqrt(g / norm)[..., None]


@_doc(returns=ALPHA, sigma_n2="``> 0``.", gamma_total="``> 0``.")
def coherent_max_snr_printed(rho, tau, kappa, sigma_n2, gamma_total):
    """Eq. (24) *as printed* (positive roots, signs of ``rho``): kept to document the erratum.

    ``alpha_i^2 = gamma (sum_j rho_j^2 / ((kappa_j + gamma tau_j / sigma_n2)^2 kappa_j))^-1
    rho_i^2 / ((kappa_i + gamma tau_i / sigma_n2)^2 kappa_i)``. Its direction is optimal only
    when all ``kappa_i`` are equal, and then it spends ``kappa gamma_total``: it is the optimum
    only if every ``kappa_i = 1``. Use :func:`coherent_max_snr`.
    """
    rho, tau, kap, sn = check_general(rho, tau, kappa, sigma_n2)
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


@_doc(returns=ALPHA, raises=INFEASIBLE, sigma_n2=SN2_MIN_POWER)
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
    """
    rho, tau, kap, sn = check_general(rho, tau, kappa, sigma_n2)
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


@_doc(returns=ALPHA, return_m1="Also return ``M_1`` (0 when ``gamma_total = 0``).")
def orthogonal_max_snr(rho, tau, kappa, sigma_n2, gamma_total, *, return_m1: bool = False):
    """Problem (28): maximize ``S^o = sum alpha_i^2 rho_i^2 / (alpha_i^2 tau_i + sigma_n2)``
    s.t. ``sum alpha_i^2 kappa_i <= gamma_total``; returns ``alpha >= 0``.

    Water-filling (29): ``alpha_i^2 = (sqrt(rho_i^2 sigma_n2 / (lambda kappa_i)) -
    sigma_n2)^+ / tau_i`` with ``1/sqrt(lambda) = (gamma_total + sum_{i<=M_1} kappa_i sigma_n2 /
    tau_i) / sum_{i<=M_1} |rho_i| sqrt(kappa_i sigma_n2) / tau_i``; ``M_1`` is the last ``m``
    whose sensor is on under ``lambda(m)`` (the printed rule).
    """
    rho, tau, kap, sn = check_general(rho, tau, kappa, sigma_n2)
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


@_doc(returns=ALPHA, raises=INFEASIBLE, sigma_n2=SN2_MIN_POWER)
def general_min_power(access, rho, tau, kappa, sigma_n2, x, y, *, infeasible: str = "raise"):
    """The minimum-power problem of either scheme: (19) by :func:`coherent_min_power`
    (multi-access) or (26) by :func:`orthogonal_min_power` (orthogonal).
    """
    solver = coherent_min_power if check_access(access) == "multi-access" else orthogonal_min_power
    return solver(rho, tau, kappa, sigma_n2, x, y, infeasible=infeasible)


@_doc(returns=ALPHA)
def general_max_snr(access, rho, tau, kappa, sigma_n2, gamma_total):
    """The maximum-SNR problem of either scheme: (23) by :func:`coherent_max_snr` (multi-access)
    or (28) by :func:`orthogonal_max_snr` (orthogonal).
    """
    if check_access(access) == "multi-access":
        return coherent_max_snr(rho, tau, kappa, sigma_n2, gamma_total)
    return orthogonal_max_snr(rho, tau, kappa, sigma_n2, gamma_total)
