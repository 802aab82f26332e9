"""Part II (dey2009), Figs. 3-4: two sensors, multi-access resp. orthogonal channels:
``E[p_k]`` against the worst-sensor bound ``s_k`` and the AM-HM bound ``t_k``.
"""

from __future__ import annotations

import itertools

import numpy as np

from fusioncenter import fading, plotting
from fusioncenter.figures.common import checks_doc, compute_doc, plot_doc, register_figure
from fusioncenter.figures.dey2009.common import (
    BLOCK,
    CH_MULTI,
    GRID_PATHS,
    LAM_GRID,
    LAMS,
    MULTI,
    NOTE_CHOICE,
    P0,
    PATHS,
    SETTABLE_PATHS,
    STEPS,
    bounded_runs,
    converged_claim,
    dominance_claim,
    mc_paths,
    plain_log_ticks,
    stationary_claim,
)
from fusioncenter.figures.registry import Claim


def _multi_runs(access: str, lam_pairs, n: int, seed: int, keep_window: bool) -> dict:
    m = MULTI

    def model(lams):
        return (access, m["a"], m["c"], m["sigma_v2"], m["sigma_n2"], lams, m["sigma_w2"]), P0

    return bounded_runs(lam_pairs, model, fading.multisensor_paths, fading.multisensor_bounds,
                        fading.multisensor_bound_limits, ("s", "t"), n, seed, keep_window)


def _compute_multi(access: str, profile: str, seed: int, **over) -> dict:
    n, ng = mc_paths(profile, over)
    grid = list(itertools.product(LAM_GRID, LAM_GRID))
    data = {"access": access, "k": np.arange(STEPS + 1), "lams": np.array(LAMS), "p0": P0,
            "n_paths": n, "n_grid_paths": ng, "seed": seed, "grid_lams": np.array(grid)}
    data.update(_multi_runs(access, LAMS, n, seed, keep_window=True))
    data.update({f"grid_{k}": v for k, v in
                 _multi_runs(access, grid, ng, seed + 100, keep_window=False).items()})
    return data


@compute_doc("""``access`` (``"multi-access"``); ``k`` (101,); ``lams`` (3, 2) the settings of
             :data:`LAMS`; ``p0``, ``n_paths``, ``n_grid_paths``, ``seed``; per setting (rows):
             ``mean``, ``stderr`` (3, 101) the Monte Carlo ``E[p_k]``, ``s`` and ``t`` (3, 101)
             the worst-sensor and AM-HM bound sequences, ``s_limit`` and ``t_limit`` (3,) their
             fixed points, ``window_diff`` and ``window_diff_stderr`` (3,); the same prefixed
             ``grid_`` (no window statistic) for the 16 pairs ``grid_lams`` (16, 2) of
             :data:`LAM_GRID`.""",
             profile="Sets the number of paths (:data:`PATHS`, :data:`GRID_PATHS`).")
def compute_fig3(profile: str, seed: int, **over) -> dict:
    """Data of ``dey2009-fig3``: two sensors, multi-access channel, E[p_k] against s_k, t_k."""
    return _compute_multi("multi-access", profile, seed, **over)


@compute_doc('The keys of :func:`compute_fig3`, with ``access`` ``"orthogonal"``.')
def compute_fig4(profile: str, seed: int, **over) -> dict:
    """Data of ``dey2009-fig4``: two sensors, orthogonal channels, E[p_k] against s_k, t_k."""
    return _compute_multi("orthogonal", profile, seed, **over)


@plot_doc()
def plot_multi(data: dict):
    """Figs. 3 and 4: one panel per (lambda_1, lambda_2), and which bound is tighter on the grid."""
    fig, axes = plotting.subplots(2, 2, stack=True)
    k = data["k"]
    for i, (ax, (l1, l2)) in enumerate(zip(axes.flat, data["lams"], strict=False)):
        plotting.errorband(ax, k, data["mean"][i], data["stderr"][i], color=plotting.OKABE_ITO[0],
                           ls="-", label=r"Monte Carlo $E[p_k]$ ± 1.96 s.e.")
        ax.plot(k, data["s"][i], color=plotting.OKABE_ITO[1], ls="--",
                label="$s_k$ (worst sensor)" if data["access"] == "multi-access"
                else r"$s_k$ (min over sensors)")
        ax.plot(k, data["t"][i], color=plotting.OKABE_ITO[2], ls="-.", label=r"$t_k$ (AM-HM)")
        ax.set(xlabel="time step $k$", ylabel=r"$E[p_k]$ and bounds (units of $x^2$)",
               title=rf"$\lambda_1 = {l1:g}$, $\lambda_2 = {l2:g}$")
        ax.legend()
    ax = axes.flat[-1]
    gm = data["grid_mean"][:, -1]
    xs, ys = data["grid_s_limit"] / gm, data["grid_t_limit"] / gm
    for j, (l1, l2) in enumerate(data["grid_lams"]):
        ax.plot(xs[j], ys[j], ls="none", marker=plotting.MARKERS[int(np.log10(l1)) + 1],
                color=plotting.OKABE_ITO[int(np.log10(l2)) + 1], mfc="none")
    for j, lam in enumerate(LAM_GRID):  # legend: marker = lambda_1, colour = lambda_2
        ax.plot([], [], ls="none", marker=plotting.MARKERS[j], color="0.3", mfc="none",
                label=rf"$\lambda_1 = {lam:g}$")
    lo, hi = 0.9, 1.1 * max(xs.max(), ys.max())
    ax.plot([lo, hi], [lo, hi], color="0.3", lw=0.8, ls=":", label="equally tight")
    for j, lam in enumerate(LAM_GRID):
        ax.plot([], [], ls="-", color=plotting.OKABE_ITO[j], label=rf"$\lambda_2 = {lam:g}$")
    ax.set(xscale="log", yscale="log", xlabel=r"$s^*/E[p_{100}]$ (dimensionless)",
           ylabel=r"$t^*/E[p_{100}]$ (dimensionless)",
           title=f"{len(xs)} alternative settings ({data['n_grid_paths']} paths each)")
    plain_log_ticks(ax.xaxis)
    plain_log_ticks(ax.yaxis)
    ax.legend(loc="center left", bbox_to_anchor=(1.0, 0.5))
    scheme = "multi-access" if data["access"] == "multi-access" else "orthogonal"
    return plotting.finish(fig, title=f"Two sensors, {scheme} scheme; {data['n_paths']} paths")


def _tighter(s, t) -> tuple[bool, bool]:
    return bool(np.any(s < t * (1 - 1e-3))), bool(np.any(t < s * (1 - 1e-3)))


@checks_doc("""Dominance and convergence of ``s_k`` and ``t_k``, stationarity, and that each bound
            is the tighter one in some setting (main settings and grid).""")
def checks_multi(data: dict) -> list[Claim]:
    """The claims of Figs. 3 and 4: both bounds dominate E[p_k], converge, and either can win."""
    s_wins, t_wins = _tighter(data["s_limit"], data["t_limit"])
    gs, gt = _tighter(data["grid_s_limit"], data["grid_t_limit"])
    return [
        dominance_claim("E[pₖ] ≤ sₖ at every k and setting (MC mean − 4 s.e.)",
                         data["mean"], data["stderr"], data["s"]),
        dominance_claim("E[pₖ] ≤ tₖ at every k and setting (MC mean − 4 s.e.)",
                         data["mean"], data["stderr"], data["t"]),
        converged_claim("sₖ and tₖ converge to their fixed points",
                         {"s": data["s"], "t": data["t"]},
                         {"s": data["s_limit"], "t": data["t_limit"]}),
        stationary_claim("E[pₖ] has converged: per-path averages over 60 ≤ k < 80 and "
                          "80 ≤ k ≤ 100 agree within 4 s.e.", data["window_diff"],
                          data["window_diff_stderr"]),
        Claim("each of s and t is the tighter bound in some setting (λ₁, λ₂)",
              s_wins and t_wins,
              "s*, t* = " + "; ".join(f"{s:.2f}, {t:.2f}" for s, t in
                                      zip(data["s_limit"], data["t_limit"], strict=True))),
        dominance_claim("alternative (λ₁, λ₂) grid: E[pₖ] ≤ min(sₖ, tₖ) at "
                         "every k", data["grid_mean"], data["grid_stderr"],
                         np.minimum(data["grid_s"], data["grid_t"])),
        Claim("alternative grid: each of s and t is the tighter bound somewhere", gs and gt,
              f"s tighter in {int(np.sum(data['grid_s_limit'] < data['grid_t_limit']))} of "
              f"{len(data['grid_s_limit'])} settings"),
    ]


_MULTI_PARAMS = {
    **MULTI, "lams": [list(x) for x in LAMS], "E[p_0]": P0, "steps": STEPS, "paths": PATHS,
    "grid_lams": list(LAM_GRID), "grid_paths": GRID_PATHS, "block_size": BLOCK,
    "note": NOTE_CHOICE.format(what="lambda_1, lambda_2 (nor E[p_0])",
                                grid="every (lambda_1, lambda_2) in {0.1, 1, 10, 100}^2"),
}

#: The captions and notes of Figs. 3 and 4: one template, the scheme filled in.
_MULTI_TEXT = (
    "Two sensors, {channel}: (a)–(c) E[pₖ] by Monte Carlo against {s} and the AM-HM bound "
    "tₖ{eq} for three (λ₁, λ₂); (d) which bound is tighter over a grid of alternatives.",
    "Both bounds dominate E[pₖ] and converge; {which}, as the paper says. λ₁, λ₂ "
    "are our choice (not stated) and the conclusions hold on a 4 × 4 grid of alternatives.",
)
for _fig, _compute, _text in (
        ("3", compute_fig3, {"channel": "multi-access (coherent sum) channel", "eq": "",
                             "s": "the worst-sensor bound sₖ",
                             "which": "sometimes s, sometimes t is tighter"}),
        ("4", compute_fig4, {"channel": "orthogonal channels", "eq": " (26)",
                             "s": "sₖ (minimum over which sensor is integrated last)",
                             "which": "each is tighter in some setting"})):
    register_figure(id=f"dey2009-fig{_fig}", paper="dey2009",
                    caption=_MULTI_TEXT[0].format(**_text), chapter=CH_MULTI,
                    label=f"sec-dey2009-fig{_fig}", parameters=_MULTI_PARAMS,
                    functions=(_compute, plot_multi, checks_multi), settable=SETTABLE_PATHS,
                    note=_MULTI_TEXT[1].format(**_text))
