"""Part II (dey2009), Figs. 1-2: one sensor, scalar state, Rayleigh resp. Nakagami(1/2)
fading: ``E[p_k]`` by Monte Carlo against the tight and loose bound sequences (17)-(20).
"""

from __future__ import annotations

import itertools

import numpy as np

from fusioncenter import fading, plotting
from fusioncenter.figures.common import compute_doc, plot_doc, register_figure
from fusioncenter.figures.dey2009 import common
from fusioncenter.figures.registry import Claim


def _scalar_runs(kind: str, sigma_vs, p0s, n: int, seed: int, keep_window: bool) -> dict:
    s = common.SCALAR
    ch = common.scalar_channel(kind)

    def model(sp):
        sv, p0 = sp
        return (s["a"], s["sigma_w2"], sv**2, s["sigma_n2"], ch), p0

    return common.bounded_runs(list(zip(sigma_vs, p0s, strict=True)), model, fading.scalar_paths,
                        fading.scalar_bounds, fading.scalar_bound_limits, ("s", "q"), n, seed,
                        keep_window)


def _compute_scalar(kind: str, profile: str, seed: int, **over) -> dict:
    n, ng = common.mc_paths(profile, over)
    main = _scalar_runs(kind, common.SIGMA_V, [common.P0] * len(common.SIGMA_V), n, seed,
                        keep_window=True)
    grid = list(itertools.product(common.SCALAR_GRID["sigma_v"], common.SCALAR_GRID["p0"]))
    gsv = np.array([g[0] for g in grid])
    gp0 = np.array([g[1] for g in grid])
    alt = _scalar_runs(kind, gsv, gp0, ng, seed + 100, keep_window=False)
    data = {"kind": kind, "k": np.arange(common.STEPS + 1), "sigma_v": np.array(common.SIGMA_V),
            "p0": common.P0, "n_paths": n, "n_grid_paths": ng, "seed": seed,
            "grid_sigma_v": gsv, "grid_p0": gp0}
    data.update(main)
    data.update({f"grid_{k}": v for k, v in alt.items()})
    if kind == "nakagami":
        ray = _scalar_runs("rayleigh", common.SIGMA_V, [common.P0] * len(common.SIGMA_V), n,
                           seed + 50, False)
        data.update({f"rayleigh_{k}": v for k, v in ray.items()})
        # Rayleigh's tight bound on the grid (deterministic), for "Nakagami is worse" there too
        s = common.SCALAR
        data["grid_rayleigh_s"] = np.array([
            fading.scalar_bounds(s["a"], s["sigma_w2"], sv**2, s["sigma_n2"],
                                 common.scalar_channel("rayleigh"), p0, common.STEPS)["s"]
            for sv, p0 in grid])
        data["q_as_printed"] = np.array([
            fading.nakagami_q_as_printed(s["a"], s["sigma_w2"], sv**2, s["sigma_n2"], s["lam"],
                                         common.P0, common.STEPS) for sv in common.SIGMA_V])
    return data


@compute_doc("""``kind`` (``"rayleigh"``); ``k`` (101,) the time steps; ``sigma_v`` (3,) and ``p0``
             the settings of :data:`SIGMA_V` and :data:`P0`; ``n_paths``, ``n_grid_paths``,
             ``seed``; for each sigma_v (rows): ``mean``, ``stderr`` (3, 101) the Monte Carlo
             ``E[p_k]`` and its standard error, ``s``, ``q`` (3, 101) the tight and loose bound
             sequences and ``s_limit``, ``q_limit`` (3,) their fixed points, ``window_diff`` and
             ``window_diff_stderr`` (3,) the convergence statistic of :data:`WINDOWS`; the same
             arrays prefixed ``grid_`` (no window statistic) for the settings ``grid_sigma_v``,
             ``grid_p0`` of :data:`SCALAR_GRID`.""",
             profile="Sets the number of paths (:data:`PATHS`, :data:`GRID_PATHS`).")
def compute_fig1(profile: str, seed: int, **over) -> dict:
    """Data of ``dey2009-fig1``: one sensor, Rayleigh fading, E[p_k] against (17)-(18)."""
    return _compute_scalar("rayleigh", profile, seed, **over)


@compute_doc("""The keys of :func:`compute_fig1` (``kind`` ``"nakagami"``), and also
             ``rayleigh_mean``, ``rayleigh_stderr``, ``rayleigh_s``, ... (Fig. 1's runs, for the
             comparison), ``grid_rayleigh_s`` and ``q_as_printed`` (3, 101), the loose bound with
             the paper's printed (20).""")
def compute_fig2(profile: str, seed: int, **over) -> dict:
    """Data of ``dey2009-fig2``: one sensor, Nakagami(1/2) fading, E[p_k] against (19)-(20)."""
    return _compute_scalar("nakagami", profile, seed, **over)


def _plot_scalar(data: dict, eqs: tuple[str, str], law: str):
    fig, (ax, ax2) = plotting.subplots(1, 2, stack=True)
    k = data["k"]
    for i, sv in enumerate(data["sigma_v"]):
        col = plotting.OKABE_ITO[i]
        plotting.errorband(ax, k, data["mean"][i], data["stderr"][i], color=col, ls="-",
                           label=rf"$\sigma_v={sv:g}$")
        ax.plot(k, data["s"][i], color=col, ls="--")
        ax.plot(k, data["q"][i], color=col, ls=":")
        if "rayleigh_mean" in data:
            ax.plot(k, data["rayleigh_mean"][i], color=col, ls="-", lw=0.7, alpha=0.6)
    # line styles say what a curve is; colours say which sigma_v
    ax.plot([], [], color="0.3", ls="-", label=r"Monte Carlo $E[p_k]$ ± 1.96 s.e.")
    ax.plot([], [], color="0.3", ls="--", label=f"tight {eqs[0]}")
    ax.plot([], [], color="0.3", ls=":", label=f"loose {eqs[1]}")
    if "rayleigh_mean" in data:
        ax.plot([], [], color="0.3", ls="-", lw=0.7, label="Rayleigh MC (Fig. 1)")
    ax.set(xlabel="time step $k$", ylabel=r"$E[p_k]$ and its bounds (units of $x^2$)",
           title=f"{law}, $\\lambda$ = {common.SCALAR['lam']:g}, $E[p_0]$ = {data['p0']:g}; "
           f"{data['n_paths']} paths")
    ax.legend(ncol=2, loc="lower right")
    for j, (sv, p0) in enumerate(zip(data["grid_sigma_v"], data["grid_p0"], strict=True)):
        col = plotting.OKABE_ITO[j % len(plotting.OKABE_ITO)]
        s = data["grid_s"][j][1:]  # from k = 1: s_0 = E[p_0] may be 0
        ax2.plot(k[1:], data["grid_mean"][j][1:] / s, color=col, ls="-",
                 label=rf"$\sigma_v={sv:g}$, $E[p_0]={p0:g}$")
        ax2.plot(k[1:], data["grid_q"][j][1:] / s, color=col, ls=":")
    ax2.axhline(1.0, color="0.2", lw=0.8)
    ax2.set_yscale("log")
    ax2.set_ylim(0.5, 5.0)  # clips the first steps of q_k / s_k from E[p_0] = 0 (up to ~10^3)
    ax2.set_yticks([0.5, 1.0, 2.0, 5.0])
    common.plain_log_ticks(ax2.yaxis)
    ax2.set(xlabel="time step $k$",
            ylabel=r"$E[p_k]/s_k$ (solid), $q_k/s_k$ (dotted) (dimensionless)",
            title=f"alternative parameters (clipped at 5); {data['n_grid_paths']} paths each")
    ax2.legend(loc="upper right", ncol=2)
    return plotting.finish(fig)


@plot_doc()
def plot_fig1(data: dict):
    """Fig. 1: E[p_k] with its bounds, one panel per sigma_v, then the ratios on the alternative
    grid."""
    return _plot_scalar(data, ("$s_k$ (17)", "$q_k$ (18)"), "Rayleigh")


@plot_doc()
def plot_fig2(data: dict):
    """Fig. 2: as :func:`plot_fig1` for Nakagami(1/2), with Fig. 1's means for comparison."""
    return _plot_scalar(data, (r"$\tilde s_k$ (19)", r"$\tilde q_k$ (20)"), "Nakagami(1/2)")


def _checks_scalar(data: dict) -> list[Claim]:
    k1 = common.abs_z(data["mean"][:, 1], data["stderr"][:, 1], data["s"][:, 1])
    claims = [
        common.dominance_claim("E[pₖ] ≤ sₖ at every k and σᵥ (MC mean − 4 s.e.)",
                         data["mean"], data["stderr"], data["s"]),
        Claim("sₖ ≤ qₖ at every k (tight below loose)",
              bool(np.all(data["s"] <= data["q"] * (1 + common.REL_SLACK))),
              f"smallest qₖ/sₖ = {float(np.min(data['q'][:, 1:] / data['s'][:, 1:])):.4f}"),
        Claim("the tight bound is exact at k = 1 (p₀ deterministic): MC E[p₁] = s₁ within "
              "4 s.e.", bool(np.all(k1 < common.Z_TOL)),
              f"|z| = {', '.join(f'{x:.2f}' for x in k1)}"),
        common.converged_claim("sₖ and qₖ converge to their fixed points s*, q* (root finding)",
                         {"s": data["s"], "q": data["q"]},
                         {"s": data["s_limit"], "q": data["q_limit"]}),
        Claim("γ* ≤ s* ≤ q* (MC E[p₁₀₀] − 4 s.e. ≤ s*)",
              bool(np.all(common.excess_z(data["mean"][:, -1], data["stderr"][:, -1],
                                    data["s_limit"]) < common.Z_TOL)
                   and np.all(data["s_limit"] <= data["q_limit"])),
              "E[p₁₀₀], s*, q* = " + "; ".join(
                  f"{m:.2f}, {s:.2f}, {q:.2f}" for m, s, q in
                  zip(data["mean"][:, -1], data["s_limit"], data["q_limit"], strict=True))),
        common.stationary_claim("E[pₖ] has converged: per-path averages over 60 ≤ k < 80 and "
                          "80 ≤ k ≤ 100 agree within 4 s.e.", data["window_diff"],
                          data["window_diff_stderr"]),
        common.dominance_claim("alternative σᵥ and E[p₀] (grid): E[pₖ] ≤ sₖ at every k",
                         data["grid_mean"], data["grid_stderr"], data["grid_s"]),
        Claim("alternative σᵥ and E[p₀] (grid): sₖ ≤ qₖ at every k and both converge",
              bool(np.all(data["grid_s"] <= data["grid_q"] * (1 + common.REL_SLACK))
                   and np.all(np.abs(data["grid_s"][:, -1] / data["grid_s_limit"] - 1) < 1e-6)
                   and np.all(np.abs(data["grid_q"][:, -1] / data["grid_q_limit"] - 1) < 1e-6)),
              f"{len(data['grid_p0'])} settings"),
    ]
    if data["kind"] == "nakagami":
        z = ((data["mean"][:, -1] - data["rayleigh_mean"][:, -1])
             / np.hypot(data["stderr"][:, -1], data["rayleigh_stderr"][:, -1]))
        claims += [
            Claim("Nakagami(1/2) is worse than Rayleigh: E[p₁₀₀] larger by > 4 s.e. for every "
                  "σᵥ", bool(np.all(z > common.Z_TOL)), f"z = {', '.join(f'{x:.1f}' for x in z)}"),
            Claim("Nakagami(1/2)'s tight bound is above Rayleigh's at every k ≥ 1 (main and "
                  "grid settings)",
                  bool(np.all(data["s"][:, 1:] > data["rayleigh_s"][:, 1:])
                       and np.all(data["grid_s"][:, 1:] >= data["grid_rayleigh_s"][:, 1:])),
                  "s̃*/s* = " + ", ".join(f"{x:.3f}" for x in
                                           data["s_limit"] / data["rayleigh_s_limit"])
                  + "; loose q̃*/q* = " + ", ".join(
                      f"{x:.3f}" for x in data["q_limit"] / data["rayleigh_q_limit"])
                  + " (not asserted: the paper says 'generally worse')"),
        ]
    return claims


_SCALAR_PARAMS = {
    **common.SCALAR, "sigma_v": list(common.SIGMA_V), "E[p_0]": common.P0, "steps": common.STEPS,
    "paths": common.PATHS, "grid": {k: list(v) for k, v in common.SCALAR_GRID.items()},
    "grid_paths": common.GRID_PATHS, "block_size": common.BLOCK,
    "note": common.NOTE_CHOICE.format(what="the sigma_v values or E[p_0]",
                                      grid="sigma_v in {0.1, 2, 20} x E[p_0] in {0, 1000}"),
}

register_figure(
    id="dey2009-fig1",
    paper="dey2009",
    caption="Rayleigh fading, one sensor: the Monte Carlo average error covariance E[pₖ] "
    "(the paper: 50 000 paths of length 100) against the tight bound sₖ (17) and the loose bound "
    "qₖ (18), for several σᵥ; below: the same ordering on a grid of alternative parameters.",
    chapter=common.CH_SCALAR,
    label="sec-dey2009-fig1",
    parameters=_SCALAR_PARAMS,
    functions=(compute_fig1, plot_fig1, _checks_scalar),
    settable=common.SETTABLE_PATHS,
    note="E[pₖ] ≤ sₖ ≤ qₖ at every k and all three converge, as the paper describes; "
    "σᵥ ∈ {1, 5, 10} and E[p₀] = 1 are our choice (not stated in the paper) and the "
    "conclusions hold on a grid of alternatives.",
)

register_figure(
    id="dey2009-fig2",
    paper="dey2009",
    caption="Nakagami(1/2) fading, one sensor: E[pₖ] by Monte Carlo against the bounds (19) "
    "and (20), with Fig. 1's Rayleigh averages for comparison; below: alternative parameters.",
    chapter=common.CH_SCALAR,
    label="sec-dey2009-fig2",
    parameters={**_SCALAR_PARAMS, "m": 0.5,
                "eq20": "denominator sqrt(s2 l/2) + sqrt(s2 l/2 + 4/pi (q + s_v^2)) as derived; "
                "the printed nested root is kept in the data as q_as_printed (see errata)"},
    functions=(compute_fig2, plot_fig2, _checks_scalar),
    settable=common.SETTABLE_PATHS,
    note="E[pₖ] ≤ s̃ₖ ≤ q̃ₖ, convergence, and worse than Rayleigh (mean and tight bound), "
    "as described; the loose bound (20) is used with its denominator as derived (the printed "
    "(20) has a nested square root, see the errata); the Nakagami loose bound is not above "
    "Rayleigh's for large σᵥ, consistent with the paper's 'generally worse'.",
)

