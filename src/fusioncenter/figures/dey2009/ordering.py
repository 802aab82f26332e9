"""Part II (dey2009), ``dey2009-ordering``: what goes wrong on the multi-access channel when
ordering (22) is ignored (the book's own figure).
"""

from __future__ import annotations

import numpy as np

from fusioncenter import fading, plotting
from fusioncenter.figures.common import checks_doc, compute_doc, plot_doc, register_figure
from fusioncenter.figures.dey2009.common import (
    BLOCK,
    CH_MULTI,
    GRID_PATHS,
    MULTI,
    ORDERING,
    P0,
    PATHS,
    SETTABLE_PATHS,
    STEPS,
    Z_TOL,
    dominance_claim,
    excess_z,
    max_finite,
    mc_paths,
)
from fusioncenter.figures.registry import Claim


@compute_doc("""Settings ``k``, ``lam1``, ``lam2`` (the swept lambda_2 of :data:`ORDERING`),
             ``main_lam2``, ``n_paths``, ``n_grid_paths``, ``seed``, ``p0``, ``worst_sensor``; at
             the main setting (101,) each: ``ma_mean``, ``ma_stderr``, ``orth_mean``,
             ``orth_stderr`` (Monte Carlo E[p_k] of both schemes), ``alone_mean``,
             ``alone_stderr`` (sensor 1 alone), ``s_valid`` (the bound with the worst sensor
             last, (22) holds), ``s_sensor1_last`` and ``s_sensor2_last`` (one sensor last),
             ``t_ma``, ``t_orth``; and the same prefixed ``sweep_`` with one row per lambda_2 (7,
             101), without the sensor-alone run.""",
             profile="Sets the paths (:data:`PATHS` at the main setting, :data:`GRID_PATHS` per "
                     "point of the sweep).")
def compute_ordering(profile: str, seed: int, **over) -> dict:
    """Data of ``dey2009-ordering``: the multi-access bound with and without ordering (22)."""
    m = MULTI
    n, ng = mc_paths(profile, over)
    lam1 = ORDERING["lam1"]
    lam2s = np.array(ORDERING["lam2"])
    common = (m["a"], m["c"], m["sigma_v2"], m["sigma_n2"])
    out: dict = {"k": np.arange(STEPS + 1), "lam1": lam1, "lam2": lam2s,
                 "main_lam2": ORDERING["main_lam2"], "n_paths": n, "n_grid_paths": ng,
                 "seed": seed, "p0": P0, "worst_sensor": int(np.argmin(
                     np.array(m["c"]) ** 2 / np.array(m["sigma_v2"])))}

    def seqs(lams, p0, steps):
        ma = fading.multisensor_bounds("multi-access", *common, lams, m["sigma_w2"], p0, steps)
        one = [fading.multisensor_bounds("orthogonal", m["a"], [m["c"][i]], [m["sigma_v2"][i]],
                                         m["sigma_n2"], [lams[i]], m["sigma_w2"], p0,
                                         steps)["s"] for i in range(2)]
        return {"s_valid": ma["s"], "s_sensor1_last": one[0], "s_sensor2_last": one[1],
                "t_ma": ma["t"],
                "t_orth": fading.multisensor_bounds("orthogonal", *common, lams, m["sigma_w2"],
                                                    p0, steps)["t"]}

    def runs(lams, npaths, sd, keep):
        res = {}
        for j, access in enumerate(fading.ACCESS_SCHEMES):
            r = fading.multisensor_paths(access, *common, lams, m["sigma_w2"], P0, STEPS, npaths,
                                         sd + j, block_size=BLOCK)
            key = "ma" if access == "multi-access" else "orth"
            res[f"{key}_mean"], res[f"{key}_stderr"] = r.mean, r.stderr
        if keep:  # sensor 1 alone (a scalar channel with c = 1): the violated bound's model
            r = fading.scalar_paths(m["a"], m["sigma_w2"], m["sigma_v2"][0], m["sigma_n2"],
                                    fading.Rayleigh(lams[0]), P0, STEPS, npaths, sd + 2,
                                    block_size=BLOCK)
            res["alone_mean"], res["alone_stderr"] = r.mean, r.stderr
        return res

    main = (lam1, ORDERING["main_lam2"])
    out.update(runs(main, n, seed, keep=True))
    out.update(seqs(main, P0, STEPS))
    sweep = [runs((lam1, l2), ng, seed + 10 * (i + 1), keep=False) for i, l2 in enumerate(lam2s)]
    bseq = [seqs((lam1, l2), P0, STEPS) for l2 in lam2s]
    for key in sweep[0]:
        out[f"sweep_{key}"] = np.array([x[key] for x in sweep])
    for key in bseq[0]:
        out[f"sweep_{key}"] = np.array([x[key] for x in bseq])
    return out


@plot_doc()
def plot_ordering(data: dict):
    """(a) The violated bound at the main setting and (b) steady states against lambda_2."""
    fig, (ax, ax2) = plotting.subplots(1, 2, stack=True)
    k = data["k"]
    c = plotting.OKABE_ITO
    plotting.errorband(ax, k, data["ma_mean"], data["ma_stderr"], color=c[0], ls="-",
                       label="multi-access: Monte Carlo ± 1.96 s.e.")
    plotting.errorband(ax, k, data["orth_mean"], data["orth_stderr"], color=c[2], ls="-",
                       label="orthogonal: Monte Carlo ± 1.96 s.e.")
    ax.plot(k, data["alone_mean"], color="0.4", ls="-", lw=0.8, label="sensor 1 alone (MC)")
    ax.plot(k, data["s_valid"], color=c[1], ls="--", label="$s_k$, worst sensor last: (22) holds")
    ax.plot(k, data["s_sensor1_last"], color=c[3], ls=":",
            label="$s_k$, best sensor last: (22) violated")
    ax.plot(k, data["t_ma"], color=c[4], ls="-.", label=r"$t_k$ (multi-access)")
    ax.set(xlabel="time step $k$", ylabel=r"$E[p_k]$ and bounds (units of $x^2$)",
           title=rf"$\lambda_1 = {data['lam1']:g}$, $\lambda_2 = {data['main_lam2']:g}$; "
           f"{data['n_paths']} paths", yscale="log")
    ax.legend()
    x = data["lam2"]
    ax2.errorbar(x, data["sweep_ma_mean"][:, -1], yerr=1.96 * data["sweep_ma_stderr"][:, -1],
                 color=c[0], marker=plotting.MARKERS[0], mfc="none", capsize=2,
                 label=r"multi-access $E[p_{100}]$ (MC)")
    ax2.errorbar(x, data["sweep_orth_mean"][:, -1], yerr=1.96 * data["sweep_orth_stderr"][:, -1],
                 color=c[2], marker=plotting.MARKERS[1], mfc="none", capsize=2,
                 label=r"orthogonal $E[p_{100}]$ (MC)")
    ax2.plot(x, data["sweep_s_valid"][:, -1], color=c[1], ls="--", label="$s^*$, (22) holds")
    ax2.plot(x, data["sweep_s_sensor1_last"][:, -1], color=c[3], ls=":",
             label="$s^*$, (22) violated (= orthogonal, sensor 1 last)")
    ax2.plot(x, data["sweep_t_ma"][:, -1], color=c[4], ls="-.", label="$t^*$ (multi-access)")
    ax2.set(xscale="log", yscale="log", xlabel=r"$\lambda_2$ (1 / mean power gain of sensor 2)",
            ylabel=r"steady state, $k = 100$ (units of $x^2$)",
            title=rf"$\lambda_1 = {data['lam1']:g}$; {data['n_grid_paths']} paths each")
    ax2.legend()
    return plotting.finish(fig)


@checks_doc("""The violation of the wrongly ordered bound, the validity of the ordered one and of
            the orthogonal bounds, and the comparisons with sensor 1 alone.""")
def checks_ordering(data: dict) -> list[Claim]:
    """What ordering (22) protects: the bound with the best sensor last fails on multi-access."""
    zviol = excess_z(data["ma_mean"][1:], data["ma_stderr"][1:], data["s_sensor1_last"][1:])
    zalone = ((data["ma_mean"][-1] - data["alone_mean"][-1])
              / np.hypot(data["ma_stderr"][-1], data["alone_stderr"][-1]))
    orth_mean = np.vstack([data["orth_mean"], data["sweep_orth_mean"]])
    orth_se = np.vstack([data["orth_stderr"], data["sweep_orth_stderr"]])
    orth_bound = np.minimum(  # both sequences bound E[p_k] <=> their minimum does
        np.vstack([data["s_sensor1_last"], data["sweep_s_sensor1_last"]]),
        np.vstack([data["s_sensor2_last"], data["sweep_s_sensor2_last"]]))
    return [
        dominance_claim("multi-access, (22) respected (worst sensor last): E[pₖ] ≤ sₖ at "
                         "every k and λ₂", np.vstack([data["ma_mean"],
                                                            data["sweep_ma_mean"]]),
                         np.vstack([data["ma_stderr"], data["sweep_ma_stderr"]]),
                         np.vstack([data["s_valid"], data["sweep_s_valid"]])),
        Claim("multi-access, (22) violated (best sensor last): the sequence falls below E[pₖ] "
              "by more than 4 s.e. (it is not a bound)", bool(max_finite(zviol) > Z_TOL),
              f"max z = {max_finite(zviol):.1f}; at k = 100: E[p] = {data['ma_mean'][-1]:.3f}, "
              f"sequence {data['s_sensor1_last'][-1]:.3f}"),
        Claim("why: on the coherent multi-access channel the noisier sensor hurts: E[p₁₀₀] "
              "with both sensors exceeds sensor 1 alone by > 4 s.e.", bool(zalone > Z_TOL),
              f"z = {zalone:.1f}"),
        dominance_claim("orthogonal: both single-sensor sequences (either order) bound E[pₖ] "
                         "at every k and λ₂ (no ordering needed)",
                         orth_mean, orth_se, orth_bound),
        dominance_claim("multi-access: tₖ (AM-HM, no ordering needed) bounds E[pₖ] at every "
                         "k and λ₂", data["sweep_ma_mean"], data["sweep_ma_stderr"],
                         data["sweep_t_ma"]),
    ]


register_figure(
    id="dey2009-ordering",
    paper="dey2009",
    caption="Ordering (22) matters on the multi-access channel: with the best sensor integrated "
    "last, the 'bound' falls below E[pₖ] (adding the noisier sensor to a coherent sum hurts), "
    "while the same sequence is a valid bound for orthogonal channels.",
    chapter=CH_MULTI,
    label="sec-dey2009-ordering",
    parameters={**MULTI, "ordering": {**ORDERING, "lam2": list(ORDERING["lam2"])},
                "E[p_0]": P0, "steps": STEPS, "paths": PATHS, "sweep_paths": GRID_PATHS,
                "block_size": BLOCK},
    functions=(compute_ordering, plot_ordering, checks_ordering),
    settable=SETTABLE_PATHS,
    note="Our own figure (the paper states (22) but does not show its violation).",
)

