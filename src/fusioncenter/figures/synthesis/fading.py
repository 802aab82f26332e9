"""``synthesis-fading``: the common problem's links through a fading packet channel.

The links through a Rayleigh block-fading packet channel (dey2009's channel law, outage when the
power gain falls below a threshold): RMSE and transmissions against the outage probability,
with a receiver that knows the channel gains and a naive one that reads every missing packet as
silence; and the same with energy rather than packets as the budget (where power allocation in
the spirit of leong2011 enters, :func:`energy_runs`).
"""

from __future__ import annotations

import functools

import numpy as np

from fusioncenter import comparison, plotting
from fusioncenter.figures import common
from fusioncenter.figures.registry import Claim
from fusioncenter.figures.synthesis import problem

#: Outage probabilities of the fading entry, and its budget (l = 1: one transmission per step).
OUTAGES = (0.0, 0.1, 0.2, 0.4)
FADING_L = 1.0
#: The overridable parameters: the frontier's (trials, particles, calibration trials).
SETTABLE_FADING = problem.SETTABLE_FRONTIER
#: Iterations of the energy-matched fixed point (per-packet power from the measured rate).
ENERGY_ITERATIONS = 3


@common.document(
    returns=(("allsend, random, trigger : list of fusioncenter.comparison.Summary",
              "One run per outage of ``eps_full``."),
             ("design, measured : numpy.ndarray",
              "The trigger's per-sensor rate (the outages' design, then measured).")),
    raises=(), sc=("fusioncenter.censoring.LinearScenario", "The problem."),
    eps_full=("numpy.ndarray", "All-send's outages."), n=("int", "Trials per run."),
    p=("float", "Random selection's send probability."), delta=("float", "The trigger's."))
def energy_runs(sc, eps_full, p: float, delta: float, n: int, seed: int):
    """Energy-matched runs at all-send outage ``eps_full``: all-send at ``eps_full``, random
    selection and the trigger (CSI receiver) at ``energy_matched_outage(eps_full, rate)``, the
    trigger's rate found by a short fixed-point iteration on its measured send rate."""
    N = sc.N
    rho = np.full(len(eps_full), p)
    for _ in range(ENERGY_ITERATIONS):
        used = rho
        runs = [comparison.KFRun("stochastic", delta=delta,
                                outage=float(comparison.energy_matched_outage(e, r)))
                for e, r in zip(eps_full, used, strict=True)]
        trig = comparison.run_kf(sc, runs, n_trials=n, seed=seed)
        rho = np.array([t.rate()[0] / N for t in trig])
    runs = [comparison.KFRun("all-send", outage=float(e)) for e in eps_full]
    runs += [comparison.KFRun("random", p=p, outage=float(comparison.energy_matched_outage(e, p)))
             for e in eps_full]
    res = comparison.run_kf(sc, runs, n_trials=n, seed=seed)
    k = len(eps_full)
    return res[:k], res[k:], trig, used, rho


@common.compute_doc(
    f"""``outage``, ``gain_threshold``, ``p``, ``delta``, ``N``, ``l``, ``n_trials``,
              ``n_particles``, ``seed``; for the groups ``allsend``, ``random``, ``trigger_csi``,
              ``trigger_naive``, ``cfomd``, ``cfwmd_csi``, ``cfwmd_naive`` (per outage),
              ``energy_allsend``, ``energy_random``, ``energy_trigger`` (per
              ``energy_outage_full``): {problem.STATS_DOC} (``G_step``, ``G_rate_step``,
              ``G_rate_span``,
              ``cfwmd_naive_minus_csi``, ...); ``G_calibration(_se)``;
              ``energy_trigger_rho_design``, ``energy_trigger_rho``, ``energy_*_outage``.""")
def compute_fading(profile: str, seed: int, **over) -> dict:
    """Data of ``synthesis-fading``: the schemes through Rayleigh block-fading links."""
    sc = problem.scenario()
    v = common.settings("synthesis-fading", SETTABLE_FADING, profile, over)
    n, n_p = v["trials"], v["particles"]
    N = sc.N
    eps = np.array(OUTAGES)
    pf = functools.partial(comparison.run_pf, sc, l=FADING_L, n_trials=n, n_particles=n_p,
                           seed=seed)
    cfomd = [pf("cfomd", outage=float(e)) for e in eps]
    cfwmd_csi = [pf("cfwmd", outage=float(e), receiver="csi") for e in eps]
    cfwmd_naive = [cfwmd_csi[0]] + [pf("cfwmd", outage=float(e), receiver="naive")
                                    for e in eps[1:]]  # at outage 0 the receivers coincide
    # the KF schemes at CFwMD's measured rate on the perfect link
    p = cfwmd_csi[0].rate()[0] / N
    delta = float(problem.calibrate([p], profile, seed, v["calibration_trials"])[0])
    runs = []
    for e in eps:
        runs += [comparison.KFRun("all-send", outage=float(e)),
                 comparison.KFRun("random", p=p, outage=float(e)),
                 comparison.KFRun("stochastic", delta=delta, outage=float(e), receiver="csi"),
                 comparison.KFRun("stochastic", delta=delta, outage=float(e), receiver="naive")]
    res = comparison.run_kf(sc, runs, n_trials=n, seed=seed)
    kf = {name: res[j::4] for j, name in enumerate(("allsend", "random", "trigger_csi",
                                                    "trigger_naive"))}
    out: dict = {"outage": eps, "p": p, "delta": delta, "N": N, "n_trials": n,
                 "n_particles": n_p, "seed": seed, "l": FADING_L,
                 "gain_threshold": np.array([comparison.outage_threshold(float(e)) for e in eps])}
    groups = {**kf, "cfomd": cfomd, "cfwmd_csi": cfwmd_csi, "cfwmd_naive": cfwmd_naive}
    for name, lst in groups.items():
        problem.stack(lst, name, out)
        problem.paired(lst[1:], lst[:-1], out, f"{name}_step")  # RMSE increase per outage step
        problem.paired(lst[1:], lst[:-1], out, f"{name}_rate_step", rate=True)
        problem.paired(lst[-1:], lst[:1], out, f"{name}_rate_span", rate=True)
    problem.paired(cfwmd_naive, cfwmd_csi, out, "cfwmd_naive_minus_csi")
    problem.paired(kf["trigger_naive"], kf["trigger_csi"], out, "trigger_naive_minus_csi")
    problem.paired(cfwmd_naive, cfomd, out, "cfwmd_naive_minus_cfomd")
    problem.paired(cfwmd_csi, cfomd, out, "cfwmd_csi_minus_cfomd")
    for name in ("trigger_csi", "trigger_naive", "allsend"):
        c = [s.calibration() for s in kf[name]]
        out[f"{name}_calibration"] = np.array([v for v, _ in c])
        out[f"{name}_calibration_se"] = np.array([e for _, e in c])
    # energy, not packets, as the budget
    eps_full = eps[1:]
    e_all, e_rand, e_trig, used, rho = energy_runs(sc, eps_full, p, delta, n, seed)
    out["energy_outage_full"] = eps_full
    out["energy_trigger_rho_design"] = used  # per-packet power = budget / this rate
    out["energy_trigger_rho"] = rho  # the rate it then measured
    out["energy_trigger_outage"] = comparison.energy_matched_outage(eps_full, used)
    out["energy_random_outage"] = comparison.energy_matched_outage(eps_full, p)
    problem.stack(e_all, "energy_allsend", out)
    problem.stack(e_rand, "energy_random", out)
    problem.stack(e_trig, "energy_trigger", out)
    problem.paired(e_trig, e_all, out, "energy_trigger_minus_allsend")
    return out


_FADING_SERIES = [  # key, label, scheme (its look), line style (naive: dotted, hollow)
    ("allsend", "all-send, exact KF", "all-send", "-"),
    ("random", "random selection, exact KF", "random", "--"),
    ("trigger_csi", "trigger, KF, receiver knows the channel", "trigger", "-"),
    ("trigger_naive", "trigger, KF, missing = silent (naive)", "trigger", ":"),
    ("cfomd", "CFoMD particle filter", "cfomd", "-."),
    ("cfwmd_csi", "CFwMD, receiver knows the channel", "cfwmd", "-"),
    ("cfwmd_naive", "CFwMD, missing = silent (naive)", "cfwmd", ":"),
]


#: The schemes whose decisions depend on the data (their send rate reacts to the channel).
_EVENT = ("trigger_csi", "trigger_naive", "cfomd", "cfwmd_csi", "cfwmd_naive")


@common.plot_doc()
def plot_fading(data: dict):
    """(a) RMSE, (b) what the naive receiver costs, (c) packets, (d) error over tr P, (e) energy."""
    fig, (a, b, c, d, e) = plotting.subplots(5, 1, stack=True, height_ratios=[5, 3, 3, 3, 3])
    eps, xl = data["outage"], r"outage probability $\varepsilon$ per packet"
    for key, name, scheme, ls in _FADING_SERIES:
        style = plotting.look(scheme, ls=ls, capsize=2, mfc="none" if ls == ":" else None)
        if ls == ":":  # a naive receiver (hollow markers): in (b), its cost over its twin
            diff = key.replace("_naive", "_naive_minus_csi")
            b.errorbar(eps, data[diff], yerr=1.96 * data[f"{diff}_se"], **style,
                       label=name.split(",")[0] + ": naive minus channel-aware receiver")
        else:  # the trigger's stars on top: at outage 0 they sit on CFoMD's triangles
            a.errorbar(eps, data[f"{key}_pos"], yerr=1.96 * data[f"{key}_pos_se"], label=name,
                       **style, zorder=3 if scheme == "trigger" else 2)
        if key != "allsend":
            c.errorbar(eps, data[f"{key}_rate"], yerr=1.96 * data[f"{key}_rate_se"], label=name,
                       **style)
        if key in ("allsend", "trigger_csi", "trigger_naive"):
            ratio = data[f"{key}_mse_state"] / data[f"{key}_trace"]
            d.plot(eps, ratio, label=name, **{k: v for k, v in style.items() if k != "capsize"})
    for key, name, scheme in [("energy_allsend", "all-send at $\\varepsilon_1$", "all-send"),
                              ("energy_random", "random selection, same energy", "random"),
                              ("energy_trigger", "trigger (knows channel), same energy",
                               "trigger")]:
        e.errorbar(data["energy_outage_full"], data[f"{key}_pos"], capsize=2, label=name,
                   yerr=1.96 * data[f"{key}_pos_se"], **plotting.look(scheme))
    rmse = "position RMSE, 20-step average (m)"
    a.set(xlabel=xl, ylabel=rmse, title=f"(a) budget l = {data['l']:g}; {data['n_trials']} "
          "paired trials; the naive receivers are in (b)")
    b.set(xlabel=xl, ylabel="RMSE, naive minus aware (m)",
          title="(b) what reading a lost packet as silence costs (paired, 95 % bars)")
    c.set(xlabel=xl, ylabel="transmissions per step (packets sent)",
          title="(c) what each scheme spends (all-send: 2)")
    d.set(xlabel=xl, ylabel=r"mean $\|x - \hat x\|^2$ / mean tr $P$ (-)",
          title="(d) does the Kalman filter know its own error?")
    e.set(xlabel=r"outage $\varepsilon_1$ of one packet per sensor and step", ylabel=rmse,
          title="(e) energy, not packets, as the budget")
    b.axhline(0.0, color="0.5", lw=0.8)
    d.axhline(1.0, color="0.5", lw=0.8)
    for ax in (a, b, c, d, e):
        ax.legend()
    plotting.log_axis(a)
    plotting.log_axis(e)
    return plotting.finish(fig)


@common.checks_doc()
def checks_fading(data: dict) -> list[Claim]:
    """Outage monotonicity, naive receivers, exactness, packets spent, equal energy."""
    def z(name):
        with np.errstate(divide="ignore", invalid="ignore"):  # 0/0 where the runs coincide
            return data[name] / data[f"{name}_se"]

    mono = {k: z(f"{k}_step") for k, *_ in _FADING_SERIES}
    zmono = np.concatenate(list(mono.values()))
    zn_w, zn_t = z("cfwmd_naive_minus_csi")[1:], z("trigger_naive_minus_csi")[1:]
    cost_naive = data["cfwmd_naive_minus_csi"][1:] / data["cfwmd_csi_pos"][1:]
    cost_naive_t = data["trigger_naive_minus_csi"][1:] / data["trigger_csi_pos"][1:]
    z_nc = z("cfwmd_naive_minus_cfomd")
    z_cc = z("cfwmd_csi_minus_cfomd")
    zc = np.concatenate([data[f"{k}_calibration"] / data[f"{k}_calibration_se"]
                         for k in ("trigger_csi", "allsend")])
    zc_naive = (data["trigger_naive_calibration"] / data["trigger_naive_calibration_se"])[1:]
    zr = np.concatenate([z(f"{k}_rate_step") for k in _EVENT])
    zspan = np.concatenate([z(f"{k}_rate_span") for k in _EVENT])
    ze = z("energy_trigger_minus_allsend")
    energy = data["energy_trigger_rho"] / data["energy_trigger_rho_design"]
    return [
        Claim("every scheme's RMSE grows with the outage probability (each step, paired "
              "z > 4)", bool(np.all(zmono > problem.Z_TOL)), f"smallest z = {np.min(zmono):.1f}"),
        Claim("reading a lost packet as silence costs accuracy: naive receivers above the "
              "channel-aware ones (paired z > 4 for CFwMD at every outage > 0, for the trigger "
              "from outage 0.2), far more for deterministic censoring (CFwMD) than for the "
              "stochastic trigger",
              bool(np.all(zn_w > problem.Z_TOL) and np.all(zn_t > 0)
                   and np.all(zn_t[data["outage"][1:] >= 0.2] > problem.Z_TOL)
                   and np.all(cost_naive > cost_naive_t)),
              "CFwMD +" + ", +".join(f"{100 * v:.0f}%" for v in cost_naive) + "; trigger +"
              + ", +".join(f"{100 * v:.0f}%" for v in cost_naive_t)),
        Claim("silence as information is fragile: the naive CFwMD falls behind CFoMD (which "
              "ignores silence) at the largest outage (z > 4), while the channel-aware CFwMD stays "
              "ahead of CFoMD (z < -4 up to outage 0.2, z < 0 beyond)",
              bool(z_nc[-1] > problem.Z_TOL and np.all(z_cc < 0)
                   and np.all(z_cc[data["outage"] <= 0.2] < -problem.Z_TOL)),
              f"naive - CFoMD z = {z_nc[-1]:.1f}; channel-aware - CFoMD z = "
              + ", ".join(f"{v:.1f}" for v in z_cc)),
        Claim("with channel knowledge the trigger's Kalman filter stays exact (and all-send's): "
              "mean(‖e‖² − tr P) = 0 within 4 s.e.; the naive trigger's P is overconfident "
              "(z > 4) at every outage > 0",
              bool(np.all(np.abs(zc) < problem.Z_TOL) and np.all(zc_naive > problem.Z_TOL)),
              f"max |z| exact = {np.max(np.abs(zc)):.2f}; naive z = "
              + ", ".join(f"{v:.1f}" for v in zc_naive)),
        Claim("event-based schemes spend more packets as the channel worsens: more at the "
              "largest outage than on a perfect link (paired z > 4), never significantly fewer "
              "from one outage to the next",
              bool(np.all(zspan > problem.Z_TOL) and np.all(zr > -problem.Z_TOL)),
              "sent at outage 0 → max: " + ", ".join(
                  f"{data[k + '_rate'][0]:.3f} → {data[k + '_rate'][-1]:.3f}" for k in _EVENT)),
        Claim("at equal energy (within 2%: per-packet power = budget / design rate, the "
              "measured rate then within 2% of it) and the largest outage, the trigger (half the "
              "packets, about twice the power each) beats all-send (paired z < -4)",
              bool(ze[-1] < -problem.Z_TOL and np.all(np.abs(energy - 1) < 0.02)),
              f"z = {ze[-1]:.1f} at ε₁ = {data['energy_outage_full'][-1]:g}; energy used / "
              "budget = " + ", ".join(f"{v:.3f}" for v in energy)),
    ]


common.register_figure(
    id="synthesis-fading",
    paper="book",
    caption="The same schemes over Rayleigh block-fading packet links (dey2009's channel law; "
    "lost below a power-gain threshold), the receiver knowing the gains or naive (a lost packet "
    "read as silence). Against the outage: (a) position RMSE, (b) the naive receivers' paired "
    "excess RMSE, (c) packets sent, (d) mean squared error / mean tr P; (e) RMSE at equal energy.",
    chapter=problem.CHAPTER,
    label="sec-synthesis-fading",
    parameters={**problem.PROBLEM, "l": FADING_L, "outages": list(OUTAGES), "channel":
                "Rayleigh, mean power gain 1, independent per sensor and step",
                "trials": problem.TRIALS, "particles": problem.PARTICLES,
                "energy_iterations": ENERGY_ITERATIONS},
    functions=(compute_fading, plot_fading, checks_fading),
    settable=SETTABLE_FADING,
    # the particle filters have no covariance: their "trace" is NaN by definition
    nonfinite_ok=("cfomd_trace", "cfwmd_csi_trace", "cfwmd_naive_trace"),
    note="Our own figure (the papers do not combine these models); every claim is checked "
    "with paired z-scores.",
)

