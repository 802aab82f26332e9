"""``synthesis-cost``: what the particle filter costs against the Kalman filter.

Operations per step of the Kalman filter and of the particle filter (an operation-count model,
the deterministic claim), measured run time (shown, never asserted), and what the particles buy:
the all-send particle filter's excess RMSE over the exact filter.
"""

from __future__ import annotations

import time

import numpy as np

from fusioncenter import censoring, comparison, plotting
from fusioncenter.figures import common
from fusioncenter.figures.registry import Claim
from fusioncenter.figures.synthesis.problem import CHAPTER, PROBLEM, Z_TOL, scenario
from fusioncenter.profile import by_profile

#: Particle counts of the cost entry.
COST_PARTICLES = {"fast": (25, 50, 100, 200, 500), "paper": (25, 50, 100, 200, 500, 1000)}
#: Monte Carlo trials per particle count, per profile, and the overridable parameter.
COST_TRIALS = {"fast": 256, "paper": 1024}
SETTABLE_COST = (common.trials_parameter(COST_TRIALS, "Monte Carlo trials per particle count"),)


@common.compute_doc(
    """``particles`` and ``particles_fine`` (the counts timed, the counts of the model);
             ``kf_flops``, ``kf_special``, ``pf_flops_S`` (S in all-send, cfomd, cfwmd),
             ``pf_special_cfwmd``, ``pf_flops_at`` (the operation-count model); ``kf_time``,
             ``pf_time_allsend``, ``pf_time_cfwmd`` (seconds per step and trial); ``kf_rmse``,
             ``excess``, ``excess_se`` (all-send PF minus KF, paired); ``n_trials``, ``seed``.""")
def compute_cost(profile: str, seed: int, **over) -> dict:
    """Data of ``synthesis-cost``: operations, times and the PF's excess error, by particles."""
    sc = scenario()
    n = common.settings("synthesis-cost", SETTABLE_COST, profile, over)["trials"]
    particles = np.array(by_profile(profile, **COST_PARTICLES))
    steps = n * sc.T
    kf = comparison.run_kf(sc, [comparison.KFRun("all-send")], n_trials=n, seed=seed)[0]
    n_kf = 16 * n  # the KF's per-step overhead is amortized over many trials, as in the book
    t0 = time.perf_counter()
    comparison.run_kf(sc, [comparison.KFRun("all-send")], n_trials=n_kf, seed=seed)
    kf_time = (time.perf_counter() - t0) / (n_kf * sc.T)
    pf_time = {"all-send": [], "cfwmd": []}
    for scheme in pf_time:  # warm-up (imports, caches) so that the first timing is not inflated
        censoring.run(sc, scheme, l=1.0, n_trials=8, n_particles=int(particles[0]), seed=seed)
    excess, excess_se = [], []
    for n_p in particles:
        for scheme in pf_time:
            t0 = time.perf_counter()
            res = censoring.run(sc, scheme, l=1.0, n_trials=n, n_particles=int(n_p), seed=seed)
            pf_time[scheme].append((time.perf_counter() - t0) / steps)
            if scheme == "all-send":
                d, se = comparison.summary_from_censoring(res).paired_difference(kf)
                excess.append(d)
                excess_se.append(se)
    fine = np.unique(np.geomspace(10, 5000, 40).astype(int))
    kf_f = comparison.kf_flops(2, sc.N)
    return {
        "particles": particles, "particles_fine": fine,
        "kf_flops": kf_f["flops"], "kf_special": kf_f["special"],
        **{f"pf_flops_{s}": np.array([comparison.pf_flops(2, sc.N, int(p), s)["flops"]
                                      for p in fine]) for s in ("all-send", "cfomd", "cfwmd")},
        "pf_special_cfwmd": np.array([comparison.pf_flops(2, sc.N, int(p), "cfwmd")["special"]
                                      for p in fine]),
        "pf_flops_at": np.array([comparison.pf_flops(2, sc.N, int(p), "cfwmd")["flops"]
                                 for p in particles]),
        "kf_time": kf_time, "pf_time_allsend": np.array(pf_time["all-send"]),
        "pf_time_cfwmd": np.array(pf_time["cfwmd"]),
        "kf_rmse": kf.tavg_rmse()[0], "excess": np.array(excess),
        "excess_se": np.array(excess_se), "n_trials": n, "seed": seed,
    }


@common.plot_doc()
def plot_cost(data: dict):
    """(a) Operation count (CFoMD dashed on all-send's equal count), (b) time, (c) excess RMSE."""
    fig, axes = plotting.subplots(1, 3, stack=True)
    ax = axes[0]
    fine = data["particles_fine"]
    same = np.array_equal(data["pf_flops_cfomd"], data["pf_flops_all-send"])
    for k, (s, name) in enumerate((("cfwmd", "CFwMD"), ("all-send", "all-send"),
                                   ("cfomd", "CFoMD" + " (same count as all-send)" * same))):
        ax.loglog(fine, data[f"pf_flops_{s}"], label=f"particle filter, {name}", zorder=2 + k,
                  markevery=(2 * k, 6), **plotting.look(s, ls="-" if k < 2 else "--"))
    ax.axhline(data["kf_flops"], color="0.35", ls="-.", label="Kalman filter (any scheme)")
    ax.set(xlabel="particles $N_s$", ylabel="operations per step and trial (flops)",
           title="(a) operation count (model)")
    ax.legend()
    ax = axes[1]
    p = data["particles"]
    ax.loglog(p, 1e6 * data["pf_time_cfwmd"], label="particle filter, CFwMD",
              **plotting.look("cfwmd"))
    ax.loglog(p, 1e6 * data["pf_time_allsend"], label="particle filter, all-send",
              **plotting.look("all-send"))
    ax.axhline(1e6 * data["kf_time"], color="0.35", ls="-.", label="Kalman filter")  # grey
    ax.set_xticks(p, [str(int(q)) for q in p], minor=False)
    ax.minorticks_off()
    ax.set(xlabel="particles $N_s$", ylabel="wall time per step and trial (µs)",
           title="(b) measured on this machine (varies)")
    ax.legend()
    ax = axes[2]
    rel = 100 * data["excess"] / data["kf_rmse"]
    rel_se = 100 * data["excess_se"] / data["kf_rmse"]
    ax.errorbar(p, rel, yerr=1.96 * rel_se, capsize=2,
                label="all-send PF minus exact KF (paired)", **plotting.look("all-send"))
    ax.axhline(0.0, color="0.3", lw=0.8)
    ax.set_xscale("log")
    ax.set_xticks(p, [str(int(q)) for q in p], minor=False)
    ax.minorticks_off()
    ax.set(xlabel="particles $N_s$", ylabel="excess position RMSE (% of the KF's)",
           title=f"(c) what the particles buy ({data['n_trials']} trials)")
    ax.legend()
    return plotting.finish(fig)


@common.checks_doc()
def checks_cost(data: dict) -> list[Claim]:
    """The operation-count claims and what the particles buy (the times are not checked)."""
    ratio = data["pf_flops_at"] / data["kf_flops"]
    big = data["particles"] >= 500
    fine = data["particles_fine"]
    per = data["pf_flops_cfwmd"] / fine
    order = bool(np.all(data["pf_flops_cfwmd"] > data["pf_flops_cfomd"])
                 and np.all(data["pf_flops_cfomd"] >= data["pf_flops_all-send"]))
    z = data["excess"] / data["excess_se"]
    rel = data["excess"] / data["kf_rmse"]
    dec = bool(np.all(np.diff(data["excess"]) < Z_TOL * np.hypot(data["excess_se"][1:],
                                                                  data["excess_se"][:-1])))
    return [
        Claim("a CFwMD particle-filter step costs at least 100× the Kalman filter's operations "
              "from 500 particles on (two orders of magnitude)",
              bool(np.all(ratio[big] >= 100)),
              f"KF {data['kf_flops']} flops; ratios " + ", ".join(
                  f"{int(q)}: {r:.0f}×" for q, r in zip(data["particles"], ratio, strict=True))),
        Claim("the particle filter's cost grows in proportion to the particles and CFwMD "
              "costs more than CFoMD (silent-sensor probabilities)",
              bool(np.allclose(per, per[0]) and order), f"{per[0]:.0f} flops per particle"),
        Claim("the particles are needed: with 25 particles the all-send PF is worse than the "
              "exact KF by more than 4 s.e. (paired)", bool(z[0] > Z_TOL),
              f"excess {100 * rel[0]:.1f}% (z = {z[0]:.1f})"),
        Claim("the PF's excess error falls as particles are added (no increase beyond 4 s.e.) "
              "and is below 1% at the largest count",
              dec and bool(rel[-1] < 0.01), f"excess at {int(data['particles'][-1])} particles: "
              f"{100 * rel[-1]:.2f}%"),
    ]


common.register_figure(
    id="synthesis-cost",
    paper="book",
    caption="Computational cost per step of the Kalman filter (mo2015's trigger, random "
    "selection, all-send) and of zheng2014's particle filter against the number of particles: "
    "(a) an operation-count model, (b) measured wall time, and (c) the all-send particle "
    "filter's excess RMSE over the exact Kalman filter.",
    chapter=CHAPTER,
    label="sec-synthesis-cost",
    parameters={**PROBLEM, "particles": COST_PARTICLES, "trials": COST_TRIALS},
    functions=(compute_cost, plot_cost, checks_cost),
    settable=SETTABLE_COST,
    note="Our own figure; the cost claim uses the operation-count model (deterministic), the "
    "measured times are shown for orientation only.",
)

