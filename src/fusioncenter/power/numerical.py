"""An independent numerical solution of the allocation problems (SciPy's SLSQP, no closed form).

:func:`solve_numerically` solves one instance of (19), (23), (26) or (28): the tests check the
closed forms of :mod:`fusioncenter.power.allocation` against it.
"""

from __future__ import annotations

import numpy as np

from fusioncenter._validate import integer as _integer
from fusioncenter._validate import positive as _positive
from fusioncenter.power._common import IDEAL_CHANNEL, INFEASIBLE, check_general
from fusioncenter.power._common import document as _doc
from fusioncenter.power.allocation import InfeasibleError

__all__ = ["solve_numerically"]


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


@_doc(returns=(("alpha : numpy.ndarray", ""), ("value : float", "")), raises=INFEASIBLE,
      sigma_n2=("float", "``> 0``."),
      x=("float, optional", "Constraint constants of the min-power problems, ``> 0``."),
      y=("float, optional", "Constraint constants of the min-power problems, ``> 0``."),
      gamma_total=("float, optional", "Budget of the max-SNR problems, ``> 0``."))
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
    """
    from scipy.optimize import minimize

    problems = ("coherent-min-power", "coherent-max-snr", "orthogonal-min-power",
                "orthogonal-max-snr")
    if problem not in problems:
        raise ValueError(f"problem must be one of 'coherent-min-power', 'coherent-max-snr', "
                         f"'orthogonal-min-power', 'orthogonal-max-snr'; got {problem!r}")
    rho, tau, kap, sn = check_general(rho, tau, kappa, sigma_n2)
    if rho.ndim != 1 or np.ndim(sn) != 0:
        raise ValueError(f"rho, tau, kappa must be 1-D (one instance) and sigma_n2 a scalar, got "
                         f"shapes {rho.shape}, {np.shape(sn)}")
    sn = float(_positive("sigma_n2", sn, f"a variance; {IDEAL_CHANNEL}"))
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
