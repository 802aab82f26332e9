"""The synthesis's explorable figure, ``synthesis-explore``: the bandwidth budget.

The problem of ``synthesis-frontier`` (zheng2014 Section VII.A, two sensors, 20 steps, ``x_0``
known) at one budget ``b`` of transmissions per step that the reader moves: the four schemes
(mo2015's stochastic trigger with its exact Kalman filter, NIS censoring with the CFwMD and
CFoMD particle filters, random selection) and all-send on the accuracy–communication plane.
It is the frontier's compute at one budget: the particle filters run with ``l = b``
(:func:`fusioncenter.censoring.run`), the trigger and random selection are tuned to the rate
CFwMD measured (:func:`fusioncenter.figures.synthesis.calibrate`,
:func:`fusioncenter.comparison.run_kf`), every scheme on the same trials (paired). For reference,
each frame also holds the Kalman-filter schemes' frontier curves (a grid of trigger parameters
and of send probabilities, each point at the rate it measured on the same trials): they do not
depend on ``b`` and are computed once per process.
"""

from __future__ import annotations

import functools

import numpy as np

from fusioncenter import censoring, comparison, plotting
from fusioncenter.context import Parameter
from fusioncenter.figures import common
from fusioncenter.figures import synthesis as fs
from fusioncenter.figures.explorable import declare
from fusioncenter.figures.registry import Claim

OWN_IDS = ("synthesis-explore",)

SE_ID = "synthesis-explore"
#: The slider's grid: the budget b from 0.2 to 1.6 transmissions per step, in steps of 0.1.
SE_BUDGETS = tuple(round(0.2 + 0.1 * k, 1) for k in range(15))
#: The tracks of the trigger's calibration per profile (the trials and particles, of the entry
#: and of every frame, are :data:`~fusioncenter.figures.explorable.declare.PF_TRIALS` and
#: :data:`~fusioncenter.figures.explorable.declare.PF_PARTICLES`).
SE_CALIBRATION = {"fast": 256, "paper": 256}
SETTABLE_SE = (
    *declare.pf_sizes("Monte Carlo trials (shared by every scheme)",
                      "particles of each particle filter"),
    common.trials_parameter(SE_CALIBRATION, "tracks of the calibration of the trigger's delta",
                            name="calibration_trials"),
    Parameter("budget", "float", "the budget b: target transmissions per step (of 2 sensors)",
              1.0, minimum=0.1, maximum=1.9, model=True),
)
#: The slider over the grid: its text beside the value, the first frame and those of print.
SLIDER_SE = {"parameter": "budget", "values": SE_BUDGETS,
             "label": "bandwidth budget b (transmissions per step, of 2 sensors)",
             "symbol": "b", "fmt": "{:.1f}", "unit": "per step", "start": 8,
             "print_at": (0, 3, 8, 14), "fixed": declare.fixed_sizes(SETTABLE_SE)}
#: The reference curves: trigger parameters (units of y²) and per-sensor send probabilities.
SE_REF_DELTA = tuple(float(d) for d in np.geomspace(0.05, 500.0, 25))
SE_REF_P = tuple(round(0.05 * k, 2) for k in range(1, 20))
#: The fixed axes of every frame (metres).
SE_YLIM = (0.5, 30.0)
SE_ZOOM = (0.6, 2.0)
#: A reversed ordering by more than this many paired standard errors fails a frame's check; a
#: claimed difference needs Z_CLAIM; the trigger's calibration tolerance per sensor.
Z_REVERSE = 3.0
Z_CLAIM = 4.0
CAL_TOL = 1e-3
#: The schemes of a frame: data-key prefix, legend label, look.
SE_SCHEMES = (
    ("trigger", "trigger + exact KF (mo2015)", "trigger"),
    ("cfwmd", "censoring + CFwMD PF (zheng2014)", "cfwmd"),
    ("cfomd", "censoring + CFoMD PF", "cfomd"),
    ("random", "random selection + exact KF", "random"),
    ("allsend", "all-send, exact KF", "all-send"),
)


@functools.lru_cache(maxsize=4)
def _reference(n: int, seed: int) -> dict:
    """The Kalman-filter schemes' frontier curves on the trials of ``(n, seed)``."""
    runs = [comparison.KFRun("stochastic", delta=d) for d in SE_REF_DELTA]
    runs += [comparison.KFRun("random", p=p) for p in SE_REF_P]
    res = comparison.run_kf(fs.scenario(), runs, n_trials=n, seed=seed)
    k = len(SE_REF_DELTA)
    return {"ref_delta": np.array(SE_REF_DELTA), "ref_p": np.array(SE_REF_P),
            "ref_trigger_rate": np.array([s.rate()[0] for s in res[:k]]),
            "ref_trigger_pos": np.array([s.tavg_rmse()[0] for s in res[:k]]),
            "ref_random_rate": np.array([s.rate()[0] for s in res[k:]]),
            "ref_random_pos": np.array([s.tavg_rmse()[0] for s in res[k:]])}


def _put(out: dict, key: str, value: tuple[float, float]) -> None:
    out[key], out[f"{key}_se"] = float(value[0]), float(value[1])


@common.compute_doc("""``budget``, ``N``, ``n_trials``, ``n_particles``, ``seed``, ``rho``
             (CFwMD's measured rate per sensor: the target of the trigger and of random
             selection), ``delta`` (the trigger's, calibrated); for ``S`` in ``trigger``,
             ``cfwmd``, ``cfomd``, ``random``, ``allsend``: ``S_rate`` (transmissions per step)
             and ``S_pos`` (time-averaged position RMSE, m), each with ``_se``; paired
             differences (with ``_se``) ``cfwmd_minus_trigger``, ``cfwmd_minus_cfomd``,
             ``trigger_minus_random``, ``cfwmd_minus_random``, ``cfomd_minus_random``,
             ``allsend_minus_S`` (the budgeted schemes), ``rate_trigger_minus_cfwmd``,
             ``rate_random_minus_cfwmd``; ``trigger_calibration`` (mean of ‖e‖² − tr P, with
             ``_se``); the reference curves ``ref_delta``, ``ref_trigger_rate``,
             ``ref_trigger_pos``, ``ref_p``, ``ref_random_rate``, ``ref_random_pos``.""")
def compute_se(profile: str, seed: int, **over) -> dict:
    """Data of ``synthesis-explore``: every scheme at the budget ``b``, on the same trials."""
    v = common.settings(SE_ID, SETTABLE_SE, profile, over)
    sc = fs.scenario()
    n, n_p, b, N = v["trials"], v["particles"], float(v["budget"]), sc.N
    pf = {s: comparison.summary_from_censoring(
        censoring.run(sc, s, l=b, n_trials=n, n_particles=n_p, seed=seed))
        for s in comparison.PF_SCHEMES}
    rho = pf["cfwmd"].rate()[0] / N
    delta = float(fs.calibrate([rho], profile, seed, v["calibration_trials"])[0])
    kf = comparison.run_kf(sc, [comparison.KFRun("all-send"),
                                comparison.KFRun("stochastic", delta=delta),
                                comparison.KFRun("random", p=rho)], n_trials=n, seed=seed)
    runs = {"allsend": kf[0], "trigger": kf[1], "random": kf[2], **pf}
    out: dict = {"budget": b, "N": N, "n_trials": n, "n_particles": n_p, "seed": seed,
                 "rho": float(rho), "delta": delta}
    for key, s in runs.items():
        _put(out, f"{key}_rate", s.rate())
        _put(out, f"{key}_pos", s.tavg_rmse())
    for a, c in [("cfwmd", "trigger"), ("cfwmd", "cfomd"), ("trigger", "random"),
                 ("cfwmd", "random"), ("cfomd", "random"), ("allsend", "trigger"),
                 ("allsend", "cfwmd"), ("allsend", "cfomd"), ("allsend", "random")]:
        _put(out, f"{a}_minus_{c}", runs[a].paired_difference(runs[c]))
    for a in ("trigger", "random"):
        _put(out, f"rate_{a}_minus_cfwmd", runs[a].paired_difference(runs["cfwmd"], rate=True))
    _put(out, "trigger_calibration", runs["trigger"].calibration())
    return {**out, **_reference(n, seed)}


def _point(ax, x: float, y: float, dx: float, dy: float, label: str, scheme: str) -> None:
    """A scheme's point with its 95 % bars in both directions (two lines: cheaper to draw
    fifteen times than an errorbar container)."""
    look = plotting.look(scheme, ls="none", markersize=9)
    ax.plot([x - dx, x + dx, np.nan, x, x], [y, y, np.nan, y - dy, y + dy],
            color=look["color"], lw=1.2)
    ax.plot([x], [y], label=label, **look)


@common.plot_doc()
def plot_se(data: dict):
    """Position RMSE against measured transmissions per step at the budget: (a) every scheme
    with the Kalman-filter schemes' frontier curves, log scale; (b) a zoom on the schemes that
    decide on their data."""
    fig, axes = plotting.subplots(2, 1, stack=True)
    b = data["budget"]
    for c, ax in enumerate(axes):
        ax.axvline(b, color="0.5", ls=":", label=f"budget b = {b:.1f}")
        ax.plot(data["ref_trigger_rate"], data["ref_trigger_pos"], lw=1.0, alpha=0.6,
                label="trigger, every δ (curve)", **plotting.look("trigger", marker="None"))
        ax.plot(data["ref_random_rate"], data["ref_random_pos"], lw=1.0, alpha=0.6,
                label="random selection, every p (curve)",
                **plotting.look("random", marker="None"))
        for key, name, scheme in SE_SCHEMES:
            _point(ax, data[f"{key}_rate"], data[f"{key}_pos"], 1.96 * data[f"{key}_rate_se"],
                   1.96 * data[f"{key}_pos_se"], name, scheme)
        ax.set(xlim=(0, 2.1), xlabel="measured transmissions per step (of 2 sensors)",
               ylabel="position RMSE, 20-step average (m)")
        if c == 0:
            plotting.log_axis(ax)
            ax.set_ylim(*SE_YLIM)
            ax.set_title(f"(a) every scheme at b = {b:.1f} ({data['n_trials']} paired trials, "
                         f"{data['n_particles']} particles; bars: 95 %)")
            ax.legend(ncol=2)
        else:
            ax.set(xlim=(0.2, 2.1), ylim=SE_ZOOM,
                   title="(b) zoom: the schemes that decide on their data")
    return plotting.finish(fig)


def _z(data: dict, key: str) -> float:
    return data[key] / data[f"{key}_se"]


@common.checks_doc()
def checks_se(data: dict) -> list[Claim]:
    """Matched budgets, the trigger's exact filter, and no ordering of the frontier reversed
    by more than 3 paired standard errors."""
    tol = data["N"] * CAL_TOL
    z_t = max(abs(data["rate_trigger_minus_cfwmd"]) - tol, 0.0) \
        / data["rate_trigger_minus_cfwmd_se"]
    z_r = abs(_z(data, "rate_random_minus_cfwmd"))
    z_cal = _z(data, "trigger_calibration")
    worse = {"random selection above the trigger": _z(data, "trigger_minus_random"),
             "random selection above CFwMD": _z(data, "cfwmd_minus_random"),
             "random selection above CFoMD": _z(data, "cfomd_minus_random"),
             "all-send below the trigger": _z(data, "allsend_minus_trigger"),
             "all-send below CFwMD": _z(data, "allsend_minus_cfwmd"),
             "all-send below CFoMD": _z(data, "allsend_minus_cfomd")}
    return [
        Claim("budgets matched: the trigger and random selection reach CFwMD's measured rate "
              "(paired, within 4 s.e. beyond the calibration tolerance)",
              bool(z_t < Z_CLAIM and z_r < Z_CLAIM),
              f"trigger z = {z_t:.2f}, random selection z = {z_r:.2f}"),
        Claim("the trigger's Kalman filter is exact: mean(‖e‖² − tr P) = 0 within 4 s.e.",
              bool(abs(z_cal) < Z_CLAIM), f"z = {z_cal:.2f}"),
        Claim("random selection is above and all-send below every scheme that decides on its "
              "data, never reversed by more than 3 paired s.e.",
              bool(all(v < Z_REVERSE for v in worse.values())),
              "; ".join(f"{k}: z of the reversal {v:.1f}" for k, v in worse.items())),
    ]


def _facts_se(data: dict) -> dict[str, str]:
    gap = 100 * (data["trigger_pos"] - data["cfwmd_pos"]) / data["trigger_pos"]
    return {"b": f"{data['budget']:.1f}", "rate": f"{data['cfwmd_rate']:.2f}",
            "cfwmd": f"{data['cfwmd_pos']:.3f}", "trigger": f"{data['trigger_pos']:.3f}",
            "cfomd": f"{data['cfomd_pos']:.3f}", "random": f"{data['random_pos']:.2f}",
            "allsend": f"{data['allsend_pos']:.3f}", "gap_pct": f"{gap:+.0f}",
            "trials": f"{data['n_trials']}", "particles": f"{data['n_particles']}"}


@declare.sweep_doc("The claims, each with its numbers along the slider.",
                   budgets=("tuple of float", "The slider's budgets, increasing."))
def sweep_se(budgets, frames) -> list[Claim]:
    """Along the slider: deciding on the data beats random selection, CFwMD beats the
    trigger at budgets up to 1 and not at the largest, all-send is never beaten."""
    b = np.asarray(budgets, dtype=float)

    def col(key):
        return np.array([f[key] for f in frames])

    def zc(key):
        return col(key) / col(f"{key}_se")

    d_wt, s_wt = col("cfwmd_minus_trigger"), col("cfwmd_minus_trigger_se")
    z_wt = d_wt / s_wt
    low = b <= 1.0
    # the frames share their trials: the mean over budgets of the paired differences gets the
    # standard error bound mean(se), which holds whatever the correlation between budgets
    z_avg = float(np.mean(d_wt[low]) / np.mean(s_wt[low]))
    pct = 100 * -d_wt / col("trigger_pos")
    z_rand = np.max([zc("trigger_minus_random"), zc("cfwmd_minus_random"),
                     zc("cfomd_minus_random")], axis=0)
    z_all = np.max([zc(f"allsend_minus_{s}") for s in ("trigger", "cfwmd", "cfomd", "random")],
                   axis=0)
    excess = 100 * (col("cfwmd_pos") / col("allsend_pos") - 1)
    return [
        Claim("CFwMD below the stochastic trigger at every budget up to 1 transmission per "
              "step (each paired difference negative), by more than 3 s.e. on average over "
              "those budgets", bool(np.all(z_wt[low] < 0) and z_avg < -Z_REVERSE),
              f"average z = {z_avg:.1f}; CFwMD below the trigger by " + ", ".join(
                  f"{v:.0f}" for v in pct[low]) + f" % of its RMSE at b = {b[0]:.1f} to 1"),
        Claim("the advantage is gone at the largest budget: there the trigger is at most 2 "
              "paired s.e. above CFwMD, or below it",
              bool(z_wt[-1] > -2.0),
              f"z of CFwMD − trigger = {z_wt[-1]:.1f} at b = {b[-1]:.1f} "
              f"({pct[-1]:+.1f} % of the trigger's RMSE)"),
        Claim("random selection above every scheme that decides on its data (trigger, CFoMD, "
              "CFwMD) at every budget (paired z > 4)", bool(np.all(z_rand < -Z_CLAIM)),
              f"largest z (scheme − random selection): {np.max(z_rand):.1f}"),
        Claim("all-send is never beaten: every budgeted scheme is above it or within 3 paired "
              "s.e. at every budget", bool(np.all(z_all < Z_REVERSE)),
              f"largest z (all-send − scheme): {np.max(z_all):.1f}; CFwMD's excess over "
              f"all-send: {excess[0]:.0f} % at b = {b[0]:.1f}, {excess[-1]:.1f} % at "
              f"b = {b[-1]:.1f}"),
    ]


declare.register(
    id=SE_ID,
    paper="book",
    caption="The four schemes of one tracking problem (zheng2014 Section VII.A, two sensors) "
    "at the budget b of transmissions per step of the slider, on the accuracy–communication "
    "plane: position RMSE against measured transmissions per step of NIS censoring with CFwMD "
    "and CFoMD (l = b), mo2015's trigger and random selection (tuned to CFwMD's measured rate) "
    "and all-send, with the Kalman-filter schemes' frontier curves: (a) every scheme, log "
    "scale; (b) a zoom.",
    chapter=fs.CHAPTER,
    label="sec-synthesis-explore",
    parameters={**fs.PROBLEM, "budget_grid": list(SE_BUDGETS),
                "trials": declare.PF_TRIALS, "particles": declare.PF_PARTICLES,
                "calibration_trials": SE_CALIBRATION,
                "reference_delta": list(SE_REF_DELTA), "reference_p": list(SE_REF_P)},
    functions=(compute_se, plot_se, checks_se, sweep_se, _facts_se),
    settable=SETTABLE_SE,
    note="Our own figure: synthesis-frontier's compute at one budget, at smaller Monte Carlo "
    "sizes; every claim is checked with paired standard errors.",
    slider=SLIDER_SE,
)
