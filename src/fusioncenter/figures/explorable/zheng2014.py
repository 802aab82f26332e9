"""Part IV's explorable figure, ``zheng2014-explore``: the censoring level ``l``.

Fig. 1's problem (zheng2014 Section VII.A: two scalar sensors, the predicted state fed back)
at a target ``l`` of transmissions per step that the reader moves: where all-send, random
selection, CFoMD and CFwMD sit on the plane of (measured transmissions per step, time-averaged
position RMSE), and their position RMSE against time. Each frame runs the four schemes on the
same trials (paired differences, :func:`fusioncenter.figures.zheng2014.comparisons.schemes_data`),
through :func:`fusioncenter.figures.zheng2014.runs.kept_run` serially (one core); all-send
ignores ``l`` and is run once, at ``l = N``.
"""

from __future__ import annotations

import numpy as np

from fusioncenter import censoring as cs
from fusioncenter import plotting
from fusioncenter.context import Parameter
from fusioncenter.figures import common
from fusioncenter.figures.explorable import declare
from fusioncenter.figures.registry import Claim
from fusioncenter.figures.zheng2014.common import LABELS, SCHEMES
from fusioncenter.figures.zheng2014.comparisons import schemes_data
from fusioncenter.figures.zheng2014.panels import log_y
from fusioncenter.figures.zheng2014.runs import kept_run

OWN_IDS = ("zheng2014-explore",)

ZE_ID = "zheng2014-explore"
#: Fig. 1's problem: N = 2 scalar sensors, the predicted state fed back.
ZE = {"N": 2, "feedback": "state"}
#: The slider's grid: l from 0.2 to 1.8 transmissions per step, in steps of 0.1.
ZE_LS = tuple(round(0.2 + 0.1 * k, 1) for k in range(17))
SETTABLE_ZE = (
    *declare.pf_sizes("Monte Carlo trials (shared by the four schemes)",
                      "particles of the fusion centre's filter"),
    Parameter("l", "float", "target number of transmissions per step (of N = 2 sensors)",
              1.0, minimum=0.0, exclusive_minimum=True, maximum=2.0, model=True),
)
#: The slider over the grid: its text beside the value, the first frame and those of print.
SLIDER_ZE = {"parameter": "l", "values": ZE_LS,
             "label": "target transmissions per step l (of 2 sensors)", "symbol": "l",
             "fmt": "{:.1f}", "unit": "per step", "start": 8, "print_at": (0, 4, 8, 16),
             "fixed": declare.fixed_sizes(SETTABLE_ZE)}
#: The fixed axes of every frame (metres): every frame's values lie inside.
ZE_YLIM_TAVG = (0.5, 30.0)
ZE_YLIM_TIME = (0.4, 50.0)
#: A reversed pair of the order all-send < CFwMD < CFoMD < random selection by more than this
#: many paired standard errors fails a frame's check; a claimed difference needs Z_CLAIM.
Z_REVERSE = 3.0
Z_CLAIM = 4.0


@common.compute_doc("""Those of :func:`fusioncenter.figures.zheng2014.comparisons.schemes_data`
             (``schemes`` all-send, random, cfomd, cfwmd; ``tavg_position`` and its stderr,
             ``transmissions`` and its stderr, ``rmse_position`` against ``time``, the
             paired ``pair_diff_position`` of all-send − CFwMD, CFwMD − CFoMD, CFoMD − random,
             ``collapsed``, ``n_trials``, ``n_particles``, ``N``, ``l``, ``eta``).""")
def compute_ze(profile: str, seed: int, **over) -> dict:
    """Data of ``zheng2014-explore``: the four schemes of Fig. 1 at the target ``l``."""
    v = common.settings(ZE_ID, SETTABLE_ZE, profile, over)
    N, l = ZE["N"], float(v["l"])
    sc = cs.LinearScenario(N=N)
    runs = tuple(kept_run(sc, s, feedback=ZE["feedback"], l=float(N) if s == "all-send" else l,
                          n=v["trials"], P=v["particles"], seed=seed) for s in SCHEMES)
    return schemes_data(runs, N, l)


def _i(data: dict, scheme: str) -> int:
    return list(data["schemes"]).index(scheme)


@common.plot_doc()
def plot_ze(data: dict):
    """Two panels: (a) each scheme's time-averaged position RMSE against the transmissions
    per step it measured, with the target ``l``; (b) the position RMSE against time."""
    fig, (ax1, ax2) = plotting.subplots(2, 1, stack=True)
    names = list(data["schemes"])
    l = data["l"]
    ax1.axvline(l, color="0.5", ls=":", label=f"target l = {l:.1f}")
    for s in names:
        i = names.index(s)
        x, y = data["transmissions"][i], data["tavg_position"][i]
        dx, dy = 1.96 * data["transmissions_stderr"][i], 1.96 * data["tavg_position_stderr"][i]
        look = plotting.look(s, ls="none", markersize=9)
        # the 95 % bars as one line (cheaper to draw seventeen times than an errorbar)
        ax1.plot([x - dx, x + dx, np.nan, x, x], [y, y, np.nan, y - dy, y + dy],
                 color=look["color"], lw=1.2)
        ax1.plot([x], [y], label=LABELS[s], **look)
    w, a = _i(data, "cfwmd"), _i(data, "all-send")
    ax1.set(xlim=(0, 2.1), ylim=ZE_YLIM_TAVG,
            xlabel="measured transmissions per step (of 2 sensors)",
            ylabel="position RMSE, 20-step average (m)",
            title=f"(a) l = {l:.1f}: CFwMD sends {data['transmissions'][w]:.2f} per step, RMSE "
                  f"{data['tavg_position'][w]:.3f} m (all-send {data['tavg_position'][a]:.3f} m)")
    log_y(ax1)
    ax1.set_ylim(*ZE_YLIM_TAVG)
    ax1.legend(ncol=3)
    t = data["time"]
    for s in names:
        i = names.index(s)
        plotting.errorband(ax2, t, data["rmse_position"][i], data["rmse_position_stderr"][i],
                           label=LABELS[s], **plotting.look(s, markersize=4))
    ax2.set(xlabel="time (s)", ylabel="position RMSE (m)",
            title=f"(b) position RMSE against time ({data['n_trials']} trials, "
                  f"{data['n_particles']} particles; bars and bands: 95 %)")
    log_y(ax2)
    ax2.set_ylim(*ZE_YLIM_TIME)
    ax2.set_xticks([1, 5, 10, 15, 20])
    ax2.legend(ncol=4)
    return plotting.finish(fig)


@common.checks_doc()
def checks_ze(data: dict) -> list[Claim]:
    """Random selection's rate, no collapse, and the order all-send < CFwMD < CFoMD < random
    selection never reversed by more than 3 paired standard errors."""
    r = _i(data, "random")
    tr, tre = data["transmissions"][r], data["transmissions_stderr"][r]
    z_rand = abs(tr - data["l"]) / tre
    z = data["pair_diff_position"] / data["pair_stderr_position"]
    pairs = [" − ".join(LABELS[str(s)] for s in p) for p in data["pairs"]]
    return [
        Claim("random selection sends l sensors per step on average (within 4 s.e.)",
              bool(z_rand < Z_CLAIM), f"{tr:.4f} at l = {data['l']:.1f} (z = {z_rand:.2f})"),
        Claim("the order all-send < CFwMD < CFoMD < random selection of the time-averaged "
              "position RMSE is never reversed by more than 3 paired s.e.",
              bool(np.all(z < Z_REVERSE)),
              "; ".join(f"{p}: z = {v:.1f}" for p, v in zip(pairs, z, strict=True))),
        Claim("no step lost its data to a collapse of the weights",
              bool(np.all(data["collapsed"] == 0)),
              "collapsed (trial, step) pairs: " + ", ".join(
                  f"{LABELS[str(s)]} {int(n)}" for s, n in zip(data["schemes"],
                                                             data["collapsed"], strict=True))),
    ]


def _facts_ze(data: dict) -> dict[str, str]:
    i = {s: _i(data, s) for s in SCHEMES}
    tp, tr = data["tavg_position"], data["transmissions"]
    return {"l": f"{data['l']:.1f}", "cfwmd_tx": f"{tr[i['cfwmd']]:.2f}",
            "cfomd_tx": f"{tr[i['cfomd']]:.2f}",
            "cfwmd": f"{tp[i['cfwmd']]:.3f}", "cfomd": f"{tp[i['cfomd']]:.3f}",
            "random": f"{tp[i['random']]:.2f}", "allsend": f"{tp[i['all-send']]:.3f}",
            "gap_pct": f"{100 * (tp[i['cfwmd']] / tp[i['all-send']] - 1):+.0f}",
            "trials": f"{data['n_trials']}", "particles": f"{data['n_particles']}"}


@declare.sweep_doc("The four claims, each with its numbers at every ``l`` that it concerns.",
                   ls=("tuple of float", "The slider's values of ``l``, increasing."))
def sweep_ze(ls, frames) -> list[Claim]:
    """Along the slider: all-send is never beaten, CFwMD's gap to it shrinks, CFwMD's
    transmissions track ``l``, CFwMD beats CFoMD."""
    ls = np.asarray(ls, dtype=float)
    f0 = frames[0]
    w = _i(f0, "cfwmd")
    # pair 0 is all-send − CFwMD, pair 1 CFwMD − CFoMD (paired over the frame's trials)
    d_aw = np.array([f["pair_diff_position"][0] for f in frames])
    s_aw = np.array([f["pair_stderr_position"][0] for f in frames])
    d_wo = np.array([f["pair_diff_position"][1] for f in frames])
    s_wo = np.array([f["pair_stderr_position"][1] for f in frames])
    gap, gse = -d_aw, s_aw
    # the frames share their trials: a difference across l gets the standard error bound
    # se_i + se_j, which holds whatever the correlation between the frames
    step = np.diff(gap) / (gse[1:] + gse[:-1])
    shrink = (gap[0] - gap[-1]) / (gse[0] + gse[-1])
    tr = np.array([f["transmissions"][w] for f in frames])
    tre = np.array([f["transmissions_stderr"][w] for f in frames])
    hi = ls >= 0.8
    rel = np.abs(tr[hi] - ls[hi]) / ls[hi]
    z_lo = (tr[0] - ls[0]) / tre[0]
    z_wo = d_wo / s_wo
    mid = (ls >= 0.8) & (ls <= 1.2)
    return [
        Claim("all-send is never beaten: CFwMD's time-averaged position RMSE is above "
              "all-send's or within 3 paired s.e. of it at every l",
              bool(np.all(d_aw / s_aw < Z_REVERSE)),
              f"largest z of all-send − CFwMD: {np.max(d_aw / s_aw):.1f} "
              f"(at l = {ls[np.argmax(d_aw / s_aw)]:.1f})"),
        Claim("CFwMD's RMSE gap to all-send shrinks from the smallest to the largest l (by "
              "more than 4 s.e.) and never grows by more than 3 s.e. from one l to the next",
              bool(shrink > Z_CLAIM and np.all(step < Z_REVERSE)),
              f"gap {gap[0]:.3f} m at l = {ls[0]:.1f}, {gap[len(gap) // 2]:.3f} m at "
              f"l = {ls[len(ls) // 2]:.1f}, {gap[-1]:.3f} m at l = {ls[-1]:.1f} "
              f"(z = {shrink:.1f}); largest step z = {np.max(step):.1f}"),
        Claim("CFwMD's measured transmissions per step track l: within 10 % of l from l = 0.8 "
              "on, and above l by more than 4 s.e. at the smallest l (the fed-back prediction "
              "is then worse than each sensor's own filter)",
              bool(np.all(rel < 0.1) and z_lo > Z_CLAIM),
              f"{tr[0]:.3f} at l = {ls[0]:.1f} (z = {z_lo:.1f}); largest |measured − l| / l "
              f"from l = 0.8: {100 * np.max(rel):.1f} %"),
        Claim("CFwMD below CFoMD (it reads the silences) by more than 4 paired s.e. for every l "
              "from 0.8 to 1.2, and never above it by more than 3 s.e.",
              bool(np.all(z_wo[mid] < -Z_CLAIM) and np.all(z_wo < Z_REVERSE)),
              "z of CFwMD − CFoMD: " + ", ".join(f"{v:.1f}" for v in z_wo)),
    ]


declare.register(
    id=ZE_ID,
    paper="zheng2014",
    caption="Fig. 1's problem (two scalar sensors, the predicted state fed back) at the target "
    "l of transmissions per step of the slider: (a) each scheme's time-averaged position RMSE "
    "against the transmissions per step it measured, (b) the position RMSE against time.",
    chapter="book/zheng2014/results",
    label="sec-zheng2014-results-explore",
    parameters={**ZE, "l_grid": list(ZE_LS), "trials": declare.PF_TRIALS,
                "particles": declare.PF_PARTICLES,
                "all-send": "run once at l = N (it ignores l)"},
    functions=(compute_ze, plot_ze, checks_ze, sweep_ze, _facts_ze),
    settable=SETTABLE_ZE,
    note="Our own figure, on the model of Fig. 1 at smaller Monte Carlo sizes; every claim "
    "is checked with paired standard errors.",
    slider=SLIDER_ZE,
)
