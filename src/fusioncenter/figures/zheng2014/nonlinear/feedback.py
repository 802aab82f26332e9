"""zheng2014 Fig. 10 and Table III: state feedback against state and covariance feedback.

CFwMD (state feedback, Proposition 7) against CFwMD2 (state and covariance feedback,
Proposition 8) at ``l`` in :data:`L_FIG10`: the RMSE curves (Fig. 10) and the transmissions per
step next to the printed :data:`TABLE3_PRINTED` (Table III), from one computation
(``_fig10_table3``, cached) on the shared runs of
:func:`~fusioncenter.figures.zheng2014.nonlinear.scenario.runs`.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from fusioncenter import plotting
from fusioncenter.figures.common import checks_doc, compute_doc, plot_doc
from fusioncenter.figures.registry import Claim
from fusioncenter.figures.zheng2014.common import RAISES
from fusioncenter.figures.zheng2014.contrasts import contrast, tx_contrast, z_score
from fusioncenter.figures.zheng2014.nonlinear.scenario import (
    SCENARIO,
    SIZE_KEYS,
    Z_ORDER,
    Z_WEAK,
    entry,
    runs,
    size_info,
    sizes,
    spec,
    stack_curves,
    z_required,
)

#: The target numbers of transmissions per step of Fig. 10 and Table III.
L_FIG10 = (2, 4, 6)
#: Table III as printed: average number of transmissions per step.
TABLE3_PRINTED = {"l": (2, 4, 6), "cfwmd": (1.5978, 3.3480, 5.4835),
                  "cfwmd2": (1.8970, 3.8775, 5.9533), "trials": 200}


@functools.lru_cache(maxsize=8)
def _fig10_table3(profile: str, seed: int, trials: int | None = None,
                  particles: int | None = None) -> dict:
    """The shared computation of Fig. 10 and Table III (cached: the two entries use one run
    set)."""
    over = {"trials": trials, "particles": particles}
    specs = [spec("cfwmd", l, fb) for l in L_FIG10 for fb in ("state", "state+cov")]
    got = runs(profile, seed, specs, **over)
    T = SCENARIO.T
    first, later = slice(0, T // 2), slice(T // 2, T)
    out = {**size_info(profile, seed, **over), "l": np.array(L_FIG10, dtype=float),
           "time": np.arange(1, T + 1) * SCENARIO.dt}
    keys = ("rmse_position", "rmse_position_stderr", "rmse_velocity", "rmse_velocity_stderr")
    for name, fb in (("cfwmd", "state"), ("cfwmd2", "state+cov")):
        rs = [got[spec("cfwmd", l, fb)] for l in L_FIG10]
        for key in keys:
            out[f"{name}_{key}"] = stack_curves(rs, key)
        tav = np.array([r.time_averaged_rmse() for r in rs])
        out[f"{name}_tavg_position"], out[f"{name}_tavg_position_stderr"] = tav[:, 0], tav[:, 1]
        tx = np.array([r.average_transmissions for r in rs])
        out[f"{name}_transmissions"], out[f"{name}_transmissions_stderr"] = tx[:, 0], tx[:, 1]
        out[f"{name}_eta"] = np.array([r.eta for r in rs])
    for part, steps in (("all", slice(None)), ("first", first), ("later", later)):
        d = [contrast([(1, got[spec("cfwmd", l, "state+cov")]),
                       (-1, got[spec("cfwmd", l, "state")])], steps=steps) for l in L_FIG10]
        out[f"diff_{part}"] = np.array([v for v, _ in d])
        out[f"diff_{part}_stderr"] = np.array([e for _, e in d])
    both = [(w, got[spec("cfwmd", l, fb)]) for l in L_FIG10
            for w, fb in ((1, "state+cov"), (-1, "state"))]
    out["pooled_later"], out["pooled_later_stderr"] = contrast(both, steps=later)
    out["pooled_all"], out["pooled_all_stderr"] = contrast(both)
    # growth of CFwMD2's advantage from the first to the second half, summed over l (paired)
    terms = []
    for l in L_FIG10:
        r1, r2 = got[spec("cfwmd", l, "state")], got[spec("cfwmd", l, "state+cov")]
        terms += [(1, r2, later), (-1, r1, later), (-1, r2, first), (1, r1, first)]
    out["growth"], out["growth_stderr"] = contrast(terms)
    # closeness to the target: |l - lbar_1| - |l - lbar_2| (paired over trials)
    close = []
    for l in L_FIG10:
        r1, r2 = got[spec("cfwmd", l, "state")], got[spec("cfwmd", l, "state+cov")]
        s1 = np.sign(l - r1.average_transmissions[0])
        s2 = np.sign(l - r2.average_transmissions[0])
        v, e = tx_contrast([(-s1, r1), (s2, r2)])
        close.append(((s1 - s2) * l + v, e))
    out["closer"] = np.array([v for v, _ in close])
    out["closer_stderr"] = np.array([e for _, e in close])
    # covariance feedback removes at least half of the shortfall: (l - lbar_1)/2 - (l - lbar_2)
    half = [tx_contrast([(-0.5, got[spec("cfwmd", l, "state")]),
                          (1, got[spec("cfwmd", l, "state+cov")])]) for l in L_FIG10]
    out["half_shortfall"] = np.array([v - l / 2 for (v, _), l in zip(half, L_FIG10,
                                                                      strict=True)])
    out["half_shortfall_stderr"] = np.array([e for _, e in half])
    out["printed_cfwmd"] = np.array(TABLE3_PRINTED["cfwmd"])
    out["printed_cfwmd2"] = np.array(TABLE3_PRINTED["cfwmd2"])
    # the paper's own Monte Carlo error: 200 trials, scaled from ours
    scale = math.sqrt(out["trials"] / TABLE3_PRINTED["trials"])
    for name in ("cfwmd", "cfwmd2"):
        se = out[f"{name}_transmissions_stderr"]
        out[f"{name}_z_vs_printed"] = (out[f"{name}_transmissions"] - out[f"printed_{name}"]) \
            / (se * math.sqrt(1 + scale**2))
    return out


@compute_doc(SIZE_KEYS + "``l``, ``time``; for ``cfwmd_`` and ``cfwmd2_``, the RMSE curves, "
             "``tavg_position``, ``transmissions``, ``eta``; CFwMD2 minus CFwMD ``diff_all``, "
             "``diff_first``, ``diff_later``, ``pooled_all``, ``pooled_later``, ``growth``; "
             "each with its ``_stderr``; the keys of :func:`compute_table3`.", raises=RAISES)
def compute_fig10(profile: str, seed: int, **over) -> dict:
    """Fig. 10: CFwMD and CFwMD2 at ``l = 2, 4, 6`` (one computation with Table III)."""
    return dict(_fig10_table3(profile, seed, *sizes(profile, over)))


@compute_doc(raises=RAISES, returns=SIZE_KEYS + "``l``; ``cfwmd_transmissions``, "
             "``cfwmd2_transmissions``; ``printed_cfwmd``, ``printed_cfwmd2``, "
             "``cfwmd_z_vs_printed``, ``cfwmd2_z_vs_printed``; ``closer`` (CFwMD's "
             "``|l - lbar|`` minus CFwMD2's), ``half_shortfall`` (half of CFwMD's shortfall l - "
             "lbar minus CFwMD2's); each with its ``_stderr``; ``cfwmd_eta``.")
def compute_table3(profile: str, seed: int, **over) -> dict:
    """Table III: the transmissions of Fig. 10's runs next to :data:`TABLE3_PRINTED`."""
    d = _fig10_table3(profile, seed, *sizes(profile, over))
    keep = ("profile", "seed", "trials", "particles", "block_size", "l", "cfwmd_transmissions",
            "cfwmd_transmissions_stderr", "cfwmd2_transmissions", "cfwmd2_transmissions_stderr",
            "printed_cfwmd", "printed_cfwmd2", "cfwmd_z_vs_printed", "cfwmd2_z_vs_printed",
            "closer", "closer_stderr", "half_shortfall", "half_shortfall_stderr", "cfwmd_eta")
    return {k: d[k] for k in keep}


@plot_doc()
def plot_fig10(data: dict):
    """Fig. 10: position RMSE of CFwMD and CFwMD2 against time, one panel per ``l``."""
    L = data["l"]
    fig, axes = plotting.subplots(1, len(L), sharey=True, stack=True)
    t = data["time"]
    for ax, j in zip(axes, range(len(L)), strict=True):
        for name, lab in (("cfwmd", "CFwMD (state)"), ("cfwmd2", "CFwMD2 (state + covariance)")):
            plotting.errorband(ax, t, data[f"{name}_rmse_position"][j],
                               data[f"{name}_rmse_position_stderr"][j],
                               label=f"{lab}, {data[f'{name}_transmissions'][j]:.2f} sent/step",
                               markevery=2, **plotting.look(name))
        ax.set(xlabel="time (s)", ylabel="position RMSE (m)", title=f"l = {L[j]:g}")
        ax.legend()
    return plotting.finish(fig, title=f"{data['trials']} trials, {data['particles']} particles")


@checks_doc()
def checks_fig10(data: dict) -> list[Claim]:
    """Fig. 10: CFwMD2 beats CFwMD in the second half and over the whole track (pooled over
    ``l``), and is not significantly worse at any ``l``."""
    zl = data["diff_later"] / data["diff_later_stderr"]
    za = data["diff_all"] / data["diff_all_stderr"]
    zp = z_score(data["pooled_later"], data["pooled_later_stderr"])
    zpa = z_score(data["pooled_all"], data["pooled_all_stderr"])
    zq = z_required(Z_WEAK, data["trials"])
    per_l = ", ".join(f"l = {l:g}: {d:+.3f} m (z = {z:.1f})"
                      for l, d, z in zip(data["l"], data["diff_later"], zl, strict=True))
    return [
        Claim("as time goes along CFwMD2 performs better than CFwMD: second half of the track "
              "(t > 5 s), pooled over l (paired), and at no l significantly worse",
              bool(zp < -zq and np.all(zl < Z_WEAK)),
              f"pooled {data['pooled_later']:+.3f} m (z = {zp:.1f}, needed {-zq:.2f}); "
              + per_l),
        Claim("over the whole track CFwMD2 is better than CFwMD, pooled over l (paired)",
              bool(zpa < -zq), f"{data['pooled_all']:+.3f} m (z = {zpa:.1f}, needed "
              f"{-zq:.2f})"),
        Claim("over the whole track CFwMD2 is not significantly worse than CFwMD at any l",
              bool(np.all(za < Z_WEAK)), "z = " + ", ".join(f"{v:.1f}" for v in za)),
    ]


@plot_doc()
def plot_table3(data: dict):
    """Table III: transmissions per step against ``l``, ours (95 % bars) and the printed."""
    fig, ax = plotting.subplots(stack=True)
    L = data["l"]
    ax.plot([L.min() - 0.5, L.max() + 0.5], [L.min() - 0.5, L.max() + 0.5], color="0.5", lw=0.8,
            ls=":", label="target $\\bar l = l$")
    for k, (name, lab) in enumerate((("cfwmd", "CFwMD"), ("cfwmd2", "CFwMD2"))):
        ax.errorbar(L + (k - 0.5) * 0.12, data[f"{name}_transmissions"],
                    yerr=1.96 * data[f"{name}_transmissions_stderr"], capsize=3,
                    label=f"{lab} (ours)", **plotting.look(name, ls="none"))
        ax.plot(L + (k - 0.5) * 0.12, data[f"printed_{name}"], label=f"{lab} (Table III)",
                **plotting.look(name, "paper", markersize=9))
    ax.set(xlabel="target transmissions per step $l$ (-)",
           ylabel="average transmissions per step $\\bar l$ (-)",
           title=f"Table III: {data['trials']} trials, {data['particles']} particles")
    ax.legend(ncol=2)
    return plotting.finish(fig)


@checks_doc()
def checks_table3(data: dict) -> list[Claim]:
    """Table III: CFwMD2 is closer to ``l``, CFwMD sends fewer than ``l``, and the covariance
    feedback removes more than half of the shortfall."""
    L = data["l"]
    z_close = data["closer"] / data["closer_stderr"]
    t1, s1 = data["cfwmd_transmissions"], data["cfwmd_transmissions_stderr"]
    z_under = (t1 - L) / s1
    z_half = data["half_shortfall"] / data["half_shortfall_stderr"]
    p1, p2 = data["printed_cfwmd"], data["printed_cfwmd2"]
    printed_half = bool(np.all(L - p2 < 0.5 * (L - p1)))
    zq = z_required(Z_ORDER, data["trials"])
    return [
        Claim("CFwMD2 meets the bandwidth target more closely than CFwMD for each l "
              "(|l − l̄| smaller, paired)", bool(np.all(z_close > zq)),
              "z = " + ", ".join(f"{v:.1f}" for v in z_close) + f" (needed {zq:.2f})"),
        Claim("with state feedback only, the sensors send fewer than l measurements per step "
              "(CFwMD, as in Table III)", bool(np.all(z_under < -zq)),
              ", ".join(f"l = {l:g}: {v:.3f} (printed {p:.4f})"
                        for l, v, p in zip(L, t1, p1, strict=True))),
        Claim("covariance feedback removes more than half of CFwMD's shortfall l − l̄ at "
              "every l, as in the printed table (paired)",
              bool(np.all(z_half > zq) and printed_half),
              ", ".join(f"l = {l:g}: {l - a:.3f} → {l - b:.3f} (printed {l - c:.3f} → "
                        f"{l - d:.3f})" for l, a, b, c, d in
                        zip(L, t1, data["cfwmd2_transmissions"], p1, p2, strict=True))
              + "; z = " + ", ".join(f"{v:.1f}" for v in z_half) + f" (needed {zq:.2f})"),
    ]



entry(
    "zheng2014-fig10", "figure", "reproduced", (compute_fig10, plot_fig10, checks_fig10),
    {"l": list(L_FIG10), "feedback": "state (Proposition 7) vs state+cov (Proposition 8)"},
    "Nonlinear tracking: position RMSE of CFwMD (state feedback) and CFwMD2 (state and "
    "covariance feedback) for l = 2, 4, 6.",
    "Shares its runs with Table III (one computation).")

entry(
    "zheng2014-table3", "table", "differs", (compute_table3, plot_table3, checks_table3),
    {"l": list(L_FIG10), "printed": TABLE3_PRINTED},
    "Average number of transmissions per step, nonlinear system: CFwMD vs CFwMD2 for "
    "l = 2, 4, 6, against the printed Table III.",
    "The paper's statements hold (CFwMD sends fewer than l; CFwMD2 is "
    "closer to l and removes more than half of the shortfall), but the numbers are lower than "
    "printed: at paper scale CFwMD by 5-7 % (z = -4.8 to -9.9, the paper's own 200-trial error "
    "included), CFwMD2 by 1-3 % (z = -1.9, -1.4, -3.2). How far the sensors under-send depends "
    "on the unstated sensor positions and start of the track.",
    reason="the rates are lower than printed (at paper scale CFwMD by 5-7 %, CFwMD2 by 1-3 %)")
