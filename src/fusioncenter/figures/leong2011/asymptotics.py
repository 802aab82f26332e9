"""Part III (leong2011), Figs. 1-2: the steady state against the number of sensors with
``alpha_i = 1/sqrt(M)`` (multi-access), the 1/M law (13) and the Lemma 4 bounds (37).
"""

from __future__ import annotations

import numpy as np

from fusioncenter import plotting, power
from fusioncenter.figures.common import (
    checks_doc,
    compute_doc,
    plot_doc,
    register_figure,
    settings,
)
from fusioncenter.figures.leong2011.common import (
    CH_ASYMPTOTICS,
    FIG1,
    FIG2,
    SETTABLE_FIG1,
    SETTABLE_FIG2,
)
from fusioncenter.figures.registry import Claim


@compute_doc("""``M`` (M_max,) the numbers of sensors, ``S`` and ``P_inf`` the SNR and the steady
             state (8) at each, ``P_iterated`` the fixed point of (4) by iteration, ``sigma_w2``,
             the limit and constant ``limit``, ``K`` of (13) and ``asymptotic`` (M_max,) ``limit
             + K/M``.""", profile="Unused: the figure is deterministic.",
             seed="Unused.")
def compute_fig1(profile: str, seed: int, **over) -> dict:
    """Data of ``leong2011-fig1`` (deterministic: profile and seed do not matter); ``over``
    sets the model of :data:`FIG1` and ``M_max`` (:data:`SETTABLE_FIG1`)."""
    v = settings("leong2011-fig1", SETTABLE_FIG1, profile, over)
    p = {**FIG1, **{k: x for k, x in v.items() if k != "M_max"}}
    M = np.arange(p["M"][0], v["M_max"] + 1)
    alpha = 1 / np.sqrt(M)
    # symmetric case: S = M h^2 c^2 / (h^2 sigma_v2 + sigma_n2) (alpha = 1/sqrt(M))
    S = np.array([power.snr("multi-access", np.full(m, al), np.full(m, p["h"]),
                            np.full(m, p["c"]), np.full(m, p["sigma_v2"]), p["sigma_n2"])
                  for m, al in zip(M, alpha, strict=True)])
    P = power.steady_state(p["a"], p["sigma_w2"], S)
    limit, K = power.symmetric_asymptotics("multi-access", "sqrt", p["a"], p["sigma_w2"],
                                           p["h"], p["c"], p["sigma_v2"], p["sigma_n2"])
    # independent: iterate the Riccati recursion (4) to its fixed point
    Pit = np.full(M.shape, p["sigma_w2"] / (1 - p["a"] ** 2))
    for _ in range(2000):
        Pit = power.steady_recursion(Pit, p["a"], p["sigma_w2"], S)
    return {"M": M, "S": S, "P_inf": P, "P_iterated": Pit, "sigma_w2": p["sigma_w2"],
            "limit": float(limit), "K": float(K), "asymptotic": limit + K / M}


@plot_doc()
def plot_fig1(data: dict):
    """(a) ``P_inf`` and ``sigma_w2 + K/M`` against M; (b) ``P_inf - sigma_w2`` against
    ``K/M`` (log-log)."""
    fig, (ax1, ax2) = plotting.subplots(1, 2, stack=True)
    M = data["M"]
    ax1.plot(M, data["P_inf"], label=r"$P_\infty$ (8)", **plotting.look(quantity="p-inf"))
    ax1.plot(M, data["asymptotic"], label=r"$\sigma_w^2 + K/M$ (13)",
             **plotting.look(quantity="upper-bound"))
    ax1.axhline(data["sigma_w2"], label=r"$\sigma_w^2$", **plotting.look(quantity="limit"))
    ax1.set(xlabel="number of sensors $M$",
            ylabel=r"steady-state error variance $P_\infty$ (state units$^2$)",
            title="(a) $P_\\infty$ and its asymptotic expression")
    ax1.legend()
    ax2.loglog(M, data["P_inf"] - data["sigma_w2"], label=r"$P_\infty - \sigma_w^2$",
               **plotting.look(quantity="p-inf"))
    ax2.loglog(M, data["K"] / M, label=f"$K/M$, $K$ = {data['K']:.4f}",
               **plotting.look(quantity="upper-bound"))
    ax2.set(xlabel="number of sensors $M$",
            ylabel=r"$P_\infty - \sigma_w^2$ (state units$^2$)", title="(b) the 1/M law")
    ax2.legend()
    return plotting.finish(fig)


@checks_doc()
def checks_fig1(data: dict) -> list[Claim]:
    """The closed form (8), monotonicity in M, the 1/M law (13) and its accuracy at M = 20."""
    M, P, sw, K = data["M"], data["P_inf"], data["sigma_w2"], data["K"]
    scaled = M * (P - sw)
    err = np.abs(scaled - K)
    fixed = np.max(np.abs(data["P_iterated"] - P) / P)
    rel20 = float(np.abs(P - data["asymptotic"])[M == 20][0] / P[M == 20][0])
    second = M * err  # M^2 |P - sw - K/M| should settle to the 1/M^2 coefficient
    tail = second[M >= 50]
    return [
        Claim("closed form (8) equals the fixed point of the recursion (4)", fixed < 1e-12,
              f"max relative difference {fixed:.1e}"),
        Claim("P∞ decreases with M and stays above σ_w²",
              bool(np.all(np.diff(P) < 0) and np.all(P > sw)), f"P∞ = {P[-1]:.5f} at M = 100"),
        Claim("1/M law (13): M (P∞ − σ_w²) → K = a²(σᵥ² + σₙ²/h²)/c², "
              "with an O(1/M) error (M times the error levels off)",
              bool(np.all(np.diff(err[M >= 5]) < 0) and np.ptp(tail) < 0.05 * tail[-1]),
              f"K = {K:.4f}; M (P∞ − σ_w²) = {scaled[0]:.4f} at M = 1, {scaled[-1]:.4f} at "
              f"M = 100; M²|P∞ − σ_w² − K/M| between {tail.min():.4f} and {tail.max():.4f} "
              "for M ≥ 50"),
        Claim("the asymptotic expression is accurate at 20 sensors (relative error < 1 %)",
              rel20 < 0.01, f"relative error at M = 20: {rel20:.2e}", paper_specific=True),
    ]


def _fig2_sensors(seed: int, n: int):
    p = FIG2
    rng = np.random.default_rng(seed)
    c = rng.uniform(*p["c_range"], n)
    sv = rng.uniform(*p["sigma_v2_range"], n)
    h = rng.uniform(*p["h_range"], n)
    return h, c, sv


@compute_doc("""``M`` the numbers of sensors, ``P_inf`` the steady state with the first ``M``
             sensors, ``lower``, ``upper`` the bounds (37) and ``exact_lower``, ``exact_upper``
             the exact bounds, ``sigma_w2``, the drawn ``h``, ``c``, ``sigma_v2`` (M_max,) and
             ``seed``.""", profile="Unused.",
             seed="Fixes the draw of the sensor parameters.")
def compute_fig2(profile: str, seed: int, **over) -> dict:
    """Data of ``leong2011-fig2``: one seeded draw of the sensors; ``over`` sets ``a``,
    ``sigma_w2``, ``sigma_n2`` and ``M_max`` (:data:`SETTABLE_FIG2`)."""
    v = settings("leong2011-fig2", SETTABLE_FIG2, profile, over)
    p = {**FIG2, **{k: x for k, x in v.items() if k != "M_max"}, "M": [FIG2["M"][0], v["M_max"]]}
    h, c, sv = _fig2_sensors(seed, v["M_max"])
    M = np.arange(p["M"][0], p["M"][1] + 1)
    S = np.array([power.snr("multi-access", np.full(m, 1 / np.sqrt(m)), h[:m], c[:m], sv[:m],
                            p["sigma_n2"]) for m in M])
    P = power.steady_state(p["a"], p["sigma_w2"], S)
    ranges = (p["h_range"], p["c_range"], p["sigma_v2_range"])
    lo, hi = power.lemma4_bounds(M, p["a"], p["sigma_w2"], p["sigma_n2"], *ranges)
    elo, ehi = power.lemma4_bounds(M, p["a"], p["sigma_w2"], p["sigma_n2"], *ranges, exact=True)
    return {"M": M, "P_inf": P, "lower": lo, "upper": hi, "exact_lower": elo,
            "exact_upper": ehi, "sigma_w2": p["sigma_w2"], "h": h, "c": c, "sigma_v2": sv,
            "seed": seed}


@plot_doc()
def plot_fig2(data: dict):
    """(a) ``P_inf`` between the bounds against M; (b) each bound's distance to ``P_inf``."""
    fig, (ax, ax2) = plotting.subplots(2, 1, stack=True)
    M = data["M"]
    curves = [("upper", "upper bound (37)", "upper-bound"),
              ("exact_upper", r"exact upper bound: $P_\infty$ at the lowest SNRs", "exact-upper"),
              ("exact_lower", r"exact lower bound: $P_\infty$ at the highest SNRs",
               "exact-lower"),
              ("lower", "lower bound (37)", "lower-bound")]
    for key, label, q in curves:
        ax.plot(M, data[key], label=label, **plotting.look(quantity=q))
    ax.plot(M, data["P_inf"], label=r"$P_\infty$, one draw of the sensor parameters",
            zorder=3, **plotting.look(quantity="p-inf"))
    ax.axhline(data["sigma_w2"], label=r"$\sigma_w^2$", **plotting.look(quantity="limit"))
    ax.set_ylim(data["sigma_w2"] * 0.95, float(np.max(data["upper"][M >= 5])) * 1.02)
    ax.set(xlabel="number of sensors $M$",
           ylabel=r"steady-state error variance $P_\infty$ (state units$^2$)",
           title=r"(a) multi-access, $\alpha_i = 1/\sqrt{M}$, general parameters")
    ax.legend(ncol=2)
    # (b) the distances to P_inf, which (a) cannot show apart for large M
    for key, label, q in curves:
        gap = np.abs(data[key] - data["P_inf"])
        ok = gap > 0
        ax2.loglog(M[ok], gap[ok], label=label, **plotting.look(quantity=q))
    ax2.set(xlabel="number of sensors $M$",
            ylabel=r"$|$bound $- P_\infty|$ (state units$^2$)",
            title=r"(b) distance of each bound to $P_\infty$ (log scales)")
    ax2.legend(ncol=2)
    return plotting.finish(fig)


@checks_doc()
def checks_fig2(data: dict) -> list[Claim]:
    """``P_inf`` between the bounds (37) and the exact bounds; both bounds' 1/M rate."""
    M, P, sw = data["M"], data["P_inf"], data["sigma_w2"]
    # (37) drops O(1/M^2) terms: at M = 1 the lower bound exceeds P_inf for about 16 % of
    # draws (any seed), so the printed bounds are checked from M = 2 on, the exact ones at all M
    big = M >= 2
    within = ((data["lower"] <= P) & (P <= data["upper"]))[big]
    exact = (data["exact_lower"] <= P * (1 + 1e-12)) & (P <= data["exact_upper"] * (1 + 1e-12))
    lo_c, hi_c = M * (data["lower"] - sw), M * (data["upper"] - sw)
    return [
        Claim("P∞ lies between the bounds (37) at every M ≥ 2 (asymptotic bounds)",
              bool(np.all(within)),
              f"{int(np.sum(~within))} of {int(np.sum(big))} values of M outside",
              paper_specific=True),
        Claim("P∞ lies between the exact bounds (steady state at the extreme SNRs)",
              bool(np.all(exact)), f"{int(np.sum(~exact))} outside"),
        Claim("both bounds converge to σ_w² at rate 1/M: M (bound − σ_w²) is constant",
              bool(np.ptp(lo_c) < 1e-12 and np.ptp(hi_c) < 1e-12),
              f"constants {lo_c[0]:.4f} and {hi_c[0]:.4f}"),
        Claim("P∞ − σ_w² = O(1/M): M (P∞ − σ_w²) stays between the bounds' "
              "constants (M ≥ 2)",
              bool(np.all(((M * (P - sw) >= lo_c) & (M * (P - sw) <= hi_c))[big])),
              f"M (P∞ − σ_w²) between {np.min(M * (P - sw)):.4f} and {np.max(M * (P - sw)):.4f}",
              paper_specific=True),
    ]


# Figs. 1-2 share the part, the chapter and the form of their ids and labels; a row holds the rest.
for _fig, _functions, _parameters, _settable, _caption, _note in (
        ("1", (compute_fig1, plot_fig1, checks_fig1), FIG1, SETTABLE_FIG1,
         "Multi-access, symmetric sensors, αᵢ = 1/√M: (a) the steady-state error P∞ against M "
         "and the asymptotic expression σ_w² + K/M of (13); (b) P∞ − σ_w² against K/M (log-log).",
         "Deterministic. The range M = 1, …, 100 is our choice (not stated). As the paper says, "
         "the 1/M expression is accurate from 20–30 sensors on."),
        ("2", (compute_fig2, plot_fig2, checks_fig2), FIG2, SETTABLE_FIG2,
         "Multi-access with general sensor parameters (cᵢ, σᵢ², hᵢ each between 0.5 and 1), "
         "αᵢ = 1/√M: P∞ against M between the asymptotic lower and upper bounds (37) of Lemma 4 "
         "(and the exact bounds at the extreme SNRs).",
         "One seeded draw (uniform on the ranges, which the paper does not specify). The paper's "
         "notation Cᵢ, Rᵢ in this passage stands for cᵢ, σᵢ². P∞ lies between the bounds, as in "
         "the paper; (37) drops O(1/M²) terms, so we check it from M = 2 on (at M = 1 about 16 % "
         "of draws fall below the lower one) and add exact bounds valid at all M.")):
    register_figure(id=f"leong2011-fig{_fig}", paper="leong2011", caption=_caption,
                    chapter=CH_ASYMPTOTICS, label=f"sec-leong2011-fig{_fig}",
                    parameters=_parameters, functions=_functions, settable=_settable, note=_note)
