"""Registry entries of Part IV(b), nonlinear tracking (zheng2014 Section VI, VII.C-D).

* ``zheng2014-fig7``: the sensor grid and a sample trajectory (no filtering).
* ``zheng2014-fig8``: position and velocity RMSE of the four schemes, ``l = 2``, state feedback.
* ``zheng2014-fig9``: time-averaged RMSE against the average number of transmissions per step,
  ``l`` in :data:`L_FIG9`.
* ``zheng2014-fig10`` and ``zheng2014-table3``: CFwMD (state feedback, Proposition 7) against
  CFwMD2 (state and covariance feedback, Proposition 8), ``l`` in {2, 4, 6}; one computation.

Every run is a :func:`fusioncenter.censoring.nonlinear.run` of the scenario :data:`SCENARIO`
with the same seed, trial count, particle count and block size, so all runs of one profile and
seed share the truth and the measurements: schemes are compared by paired differences, and
runs used by several entries (Figs. 8 and 9 at ``l = 2``; Figs. 9 and 10 for CFwMD at
``l = 2, 4, 6``; Fig. 10 and Table III entirely) are computed once and kept in :data:`_RUNS`.
The blocks of 25 trials of every missing run are spread over the execution context's executor
(:func:`fusioncenter.context.executor`: by default a process pool in the paper profile); the
results do not depend on it.
"""

from __future__ import annotations

import dataclasses
import functools
import math

import numpy as np

from fusioncenter import censoring, context, plotting
from fusioncenter.censoring import nonlinear as cn
from fusioncenter.context import Parameter
from fusioncenter.figures.common import checks_doc, compute_doc, document, plot_doc
from fusioncenter.figures.registry import Claim
from fusioncenter.figures.zheng2014.common import RAISES, add_entry, check_block, settable
from fusioncenter.figures.zheng2014.contrasts import contrast, tx_contrast, z_score
from fusioncenter.profile import by_profile

#: Ids of the book's own figures registered here (not figures of the paper).
OWN_IDS: tuple[str, ...] = ()

CHAPTER = "book/zheng2014/nonlinear"
#: The scenario of Section VII.C (our choices for what the paper leaves open: see ``choices``).
SCENARIO = cn.NonlinearScenario()
#: Monte Carlo sizes: the paper's 200 trials and 10^4 particles; fast: seconds per entry.
SIZES = {"fast": {"trials": 40, "particles": 5000}, "paper": {"trials": 200, "particles": 10_000}}
#: Trials per independent random stream (part of the random-number design) and per task: at
#: 10^4 particles a block needs about 100 MB.
BLOCK = 25
L_FIG8 = 2
#: The target numbers of transmissions per step l swept in Fig. 9.
L_FIG9 = (1, 2, 4, 6, 8)
L_FIG10 = (2, 4, 6)
#: Table III as printed: average number of transmissions per step.
TABLE3_PRINTED = {"l": (2, 4, 6), "cfwmd": (1.5978, 3.3480, 5.4835),
                  "cfwmd2": (1.8970, 3.8775, 5.9533), "trials": 200}
#: z-score a paper's ordering claim must reach (paired Monte Carlo error) at paper scale.
Z_ORDER = 3.0
#: z-score for the weaker, time-resolved claims of Fig. 10, and for "not significantly worse".
Z_WEAK = 2.0
#: |z| within which a number counts as agreeing with the printed one.
Z_AGREE = 3.0


@document(returns=("float", "``z sqrt(min(1, trials / 200))``."), raises=(),
          z=("float", "The z-score required at 200 trials."), trials=("int", "The trials."))
def z_required(z: float, trials: int) -> float:
    """The z-score a claim needs with ``trials`` trials: ``z`` at the paper's 200 trials, and
    the same *effect size* (mean over per-trial standard deviation, ``z / sqrt(200)``) with
    fewer trials, ``z sqrt(trials / 200)``. The fast profile is a smoke test with a fifth of the
    trials; at paper scale every claim is checked at the full ``z``."""
    return z * math.sqrt(min(1.0, trials / SIZES["paper"]["trials"]))


PARAMS = {
    "N": 9, "region_m": 20.0, "P0_signal": 1e3, "alpha": 1.0, "n_exponent": 2.0, "r": 1.0,
    "sigma2": 0.1, "dt_s": 0.5, "T": 20, "x0_mean": [-8.0, 2.0, -8.0, 2.0],
    "x0_cov_diag": [9.0, 4.0, 9.0, 4.0],
    "trials": {p: s["trials"] for p, s in SIZES.items()},
    "particles": {p: s["particles"] for p, s in SIZES.items()},
    "block_size": BLOCK,
    "sensors_m": [list(p) for p in SCENARIO.sensors],
    "choices": SCENARIO.choices,
}


# ============================================================================ shared runs
#: ``(profile, seed, trials, particles, scheme, l, feedback) -> CensoringResult``, shared by the
#: entries.
_RUNS: dict[tuple, censoring.CensoringResult] = {}


def _run_one(scheme: str, l: float, feedback: str, n: int, P: int, seed: int, executor=None):
    """One run of :data:`SCENARIO`; with an executor its blocks are spread over the workers."""
    return cn.run(SCENARIO, scheme, l=l, n_trials=n, n_particles=P, seed=seed,
                  feedback=feedback, block_size=BLOCK, chunk_size=BLOCK, executor=executor)


def _sizes(profile: str, over: dict) -> tuple[int, int]:
    """Trials and particles of a run (checked to fit: 400 bytes a particle in a block)."""
    n, P = (over.get(k) or by_profile(profile, **SIZES)[k] for k in ("trials", "particles"))
    return n, check_block(P, min(n, BLOCK), 400)


#: The overridable parameters of the filtering entries (Figs. 8-10, Table III).
SETTABLE = settable({p: s["trials"] for p, s in SIZES.items()},
                    {p: s["particles"] for p, s in SIZES.items()})
#: Trajectories simulated for the statements of Fig. 7 (cheap: no filtering).
TRAJECTORIES = 10_000
#: The overridable parameters of Fig. 7.
SETTABLE_FIG7 = (
    Parameter("trajectories", "int", "simulated trajectories (the ensemble of the statements)",
              TRAJECTORIES, minimum=2),
    Parameter("sigma2", "float", "process noise intensity sigma^2 of the white-noise "
              "acceleration (m^2/s^3)", SCENARIO.sigma2, minimum=1e-12, model=True),
)


@document(returns=("dict", "``{spec: CensoringResult}``, in the order of ``specs``."),
          specs=("iterable of tuple", "``(scheme, l, feedback)`` of each run."), raises=RAISES,
          over="The sizes ``trials`` and ``particles`` (other keys are ignored).")
def runs(profile: str, seed: int, specs, **over) -> dict[tuple, censoring.CensoringResult]:
    """The runs ``(scheme, l, feedback)`` of ``specs`` for ``profile``, ``seed`` and the
    overrides ``over`` (trials, particles), computing only those not yet in :data:`_RUNS`, on
    the execution context's executor (one task per block of 25 trials, 8 per run at paper
    scale: every worker stays busy to the end)."""
    n, P = _sizes(profile, over)
    specs = list(dict.fromkeys(specs))
    key = (profile, seed, n, P)
    todo = [s for s in specs if (*key, *s) not in _RUNS]
    ex = context.executor() if todo else None
    for s in todo:
        _RUNS[(*key, *s)] = _run_one(*s, n, P, seed, executor=ex)
    return {s: _RUNS[(*key, *s)] for s in specs}


def _curves(res) -> dict[str, np.ndarray]:
    return {"rmse_position": res.rmse_position.value,
            "rmse_position_stderr": res.rmse_position.stderr,
            "rmse_velocity": res.rmse_velocity.value,
            "rmse_velocity_stderr": res.rmse_velocity.stderr}


def _stack(results, key):
    return np.stack([_curves(r)[key] for r in results])


def _size_info(profile: str, seed: int, **over) -> dict:
    n, P = _sizes(profile, over)
    return {"profile": profile, "seed": seed, "trials": n, "particles": P, "block_size": BLOCK}


#: The run sizes at the head of the filtering entries' data (for their docstrings).
SIZE_KEYS = "``profile``, ``seed``, ``trials``, ``particles``, ``block_size`` (the run sizes); "


# ============================================================================ Fig. 7
@compute_doc(
    "``time`` (T+1,) s; ``trajectory``, ``velocity`` (T+1, 2) of the sample; ``mean_path`` "
    "(T+1, 2); ``sensors`` (N, 2), ``region_half_width``; ``fraction_outside`` and "
    "``nearest_distance`` (T+1,) over the ensemble, ``nearest_distance_increase`` (last 5 s) "
    "with its ``_stderr``; ``ensemble`` (its size), ``x0``, ``seed``.", raises=(),
    profile="Unused: the data are the same in both profiles.")
def compute_fig7(profile: str, seed: int, **over) -> dict:
    """Fig. 7: one sample trajectory, and an ensemble of ``trajectories`` (default
    :data:`TRAJECTORIES`, process noise ``sigma2``) for where the target goes (no filtering)."""
    sc = SCENARIO
    if "sigma2" in over:
        sc = dataclasses.replace(sc, sigma2=over["sigma2"])
    rng = np.random.default_rng(seed)
    x, _ = sc.sample(rng, 1)
    ens, _ = sc.sample(rng, over.get("trajectories", TRAJECTORIES))
    half = sc.region / 2
    pos = ens[..., [0, 2]]  # (n, T+1, 2)
    outside = np.any(np.abs(pos) > half, axis=-1)
    dist = np.linalg.norm(pos[:, :, None, :] - sc.positions, axis=-1).min(axis=-1)
    dist_d = dist[:, -1] - dist[:, sc.T // 2]
    return {"time": np.arange(sc.T + 1) * sc.dt, "trajectory": x[0][:, [0, 2]],
            "velocity": x[0][:, [1, 3]], "mean_path": pos.mean(axis=0),
            "sensors": sc.positions, "region_half_width": half,
            "fraction_outside": outside.mean(axis=0), "nearest_distance": dist.mean(axis=0),
            "nearest_distance_increase": float(dist_d.mean()),
            "nearest_distance_increase_stderr": float(dist_d.std(ddof=1) / math.sqrt(dist_d.size)),
            "ensemble": int(ens.shape[0]), "x0": np.asarray(sc.x0), "seed": seed}


@plot_doc()
def plot_fig7(data: dict):
    """Fig. 7: the region, the numbered sensors, the sample trajectory and the mean path."""
    fig, ax = plotting.subplots(figsize=(6.4, 7.4), stack=True)  # a square map, full width
    h = data["region_half_width"]
    ax.plot([-h, h, h, -h, -h], [-h, -h, h, h, -h], color="0.4", lw=1.0, ls="-",
            label="region of interest")
    s = data["sensors"]
    ax.plot(s[:, 0], s[:, 1], ls="none", marker="^", markersize=8, color=plotting.OKABE_ITO[1],
            label="sensors")
    for i, (px, py) in enumerate(s):
        ax.annotate(str(i + 1), (px, py), textcoords="offset points", xytext=(5, 4), fontsize=8)
    tr = data["trajectory"]
    ax.plot(tr[:, 0], tr[:, 1], marker="o", markersize=3, color=plotting.OKABE_ITO[0],
            ls="-", label="sample trajectory (0.5 s steps)")
    ax.plot(*data["mean_path"].T, color="0.3", ls="--", lw=1.0, label="mean path")
    ax.plot(*tr[0], marker="s", color="k", ls="none", label="start ($t = 0$)")
    ax.set(xlabel="x (m)", ylabel="y (m)", aspect="equal",
           title="Sensor grid and target trajectory")
    ax.legend(ncol=2)
    return plotting.finish(fig)


@checks_doc()
def checks_fig7(data: dict) -> list[Claim]:
    """Fig. 7: the grid, the start, the target leaving, the nearest sensor receding at the end."""
    s, h = data["sensors"], data["region_half_width"]
    xs, ys = np.unique(np.round(s[:, 0], 9)), np.unique(np.round(s[:, 1], 9))
    grid = len(s) == 9 and len(xs) == 3 and len(ys) == 3 and np.all(np.abs(s) <= h)
    tr = data["trajectory"]
    inside = np.all(np.abs(tr) <= h, axis=-1)
    fo = data["fraction_outside"]
    T = len(fo) - 1
    z_d = z_score(data["nearest_distance_increase"], data["nearest_distance_increase_stderr"])
    xy = [censoring.scenarios.values_text(np.round(v, 2)) for v in (xs, ys, tr[0], tr[-1])]
    return [
        Claim("N = 9 sensors on a 3 × 3 grid inside the 20 m × 20 m region", bool(grid),
              f"abscissae {xy[0]} m, ordinates {xy[1]} m, half-width {h:g} m"),
        Claim("the sample trajectory starts at x₀ = (−8, −8) m inside the region and crosses it",
              bool(np.allclose(tr[0], data["x0"][[0, 2]]) and inside[: T // 2].all()
                   and np.ptp(tr[:, 0]) > h and np.ptp(tr[:, 1]) > h),
              f"start {xy[2]} m, end {xy[3]} m", paper_specific=True),
        Claim("the target moves out of the region near the end (most trajectories are inside at "
              "t = 5 s and outside at t = 10 s)", bool(fo[T // 2] < 0.1 and fo[-1] > 0.5),
              f"fraction outside: {fo[T // 2]:.3f} at 5 s, {fo[-1]:.3f} at 10 s "
              f"({data['ensemble']} trajectories)", paper_specific=True),
        Claim("so the distance to the nearest sensor grows over the last 5 s (less information "
              "at the end)", bool(z_d > Z_ORDER),
              f"mean increase {data['nearest_distance_increase']:.2f} m, z = {z_d:.1f}",
              paper_specific=True),
    ]


# ============================================================================ Fig. 8
FIG8_SCHEMES = ("all-send", "random", "cfomd", "cfwmd")


def _spec(scheme: str, l: float, feedback: str = "state") -> tuple:
    return (scheme, float(SCENARIO.N if scheme == "all-send" else l), feedback)


@compute_doc(SIZE_KEYS + "``l``, ``eta``, ``time``, ``schemes``; the RMSE curves (4, T), "
             "their time averages and ``transmissions`` (4,); the paired differences of the "
             "time-averaged position RMSE ``diff_cfwmd-cfomd``, ``diff_cfwmd-random``, "
             "``diff_cfwmd-all-send``, ``diff_cfomd-all-send``; ``rise_end`` (4,), "
             "``rise_pooled`` (RMSE at 10 s minus at 5 s); each with its ``_stderr``; "
             "``collapsed``.", raises=RAISES)
def compute_fig8(profile: str, seed: int, **over) -> dict:
    """Fig. 8: the four schemes at ``l = 2`` with state feedback (runs shared by :func:`runs`)."""
    specs = [_spec(s, L_FIG8) for s in FIG8_SCHEMES]
    got = runs(profile, seed, specs, **over)
    res = [got[s] for s in specs]
    R = dict(zip(FIG8_SCHEMES, res, strict=True))
    out = {**_size_info(profile, seed, **over), "l": L_FIG8, "eta": R["cfwmd"].eta,
           "time": R["cfwmd"].time * SCENARIO.dt, "schemes": list(FIG8_SCHEMES)}
    for key in ("rmse_position", "rmse_position_stderr", "rmse_velocity",
                "rmse_velocity_stderr"):
        out[key] = _stack(res, key)
    for comp in ("position", "velocity"):
        tav = [r.time_averaged_rmse(comp) for r in res]
        out[f"tavg_{comp}"] = np.array([v for v, _ in tav])
        out[f"tavg_{comp}_stderr"] = np.array([e for _, e in tav])
    tx = [r.average_transmissions for r in res]
    out["transmissions"] = np.array([v for v, _ in tx])
    out["transmissions_stderr"] = np.array([e for _, e in tx])
    pairs = {"cfwmd-cfomd": ("cfwmd", "cfomd"), "cfwmd-random": ("cfwmd", "random"),
             "cfwmd-all-send": ("cfwmd", "all-send"), "cfomd-all-send": ("cfomd", "all-send")}
    for name, (a, b) in pairs.items():
        out[f"diff_{name}"], out[f"diff_{name}_stderr"] = contrast([(1, R[a]), (-1, R[b])])
    # RMSE at the last step minus RMSE at t = 5 s (middle), per scheme, paired over trials
    T = SCENARIO.T
    rise = [contrast([(1, r, slice(T - 1, T)), (-1, r, slice(T // 2 - 1, T // 2))])
            for r in res]
    out["rise_end"] = np.array([v for v, _ in rise])
    out["rise_end_stderr"] = np.array([e for _, e in rise])
    out["rise_pooled"], out["rise_pooled_stderr"] = contrast(
        [t for r in res for t in ((1, r, slice(T - 1, T)), (-1, r, slice(T // 2 - 1, T // 2)))])
    out["collapsed"] = np.array([r.collapsed for r in res])
    return out


@plot_doc()
def plot_fig8(data: dict):
    """Fig. 8: position and velocity RMSE against time of the four schemes (95 % bands)."""
    fig, axes = plotting.subplots(1, 2, stack=True)
    t = data["time"]
    names = {"all-send": "all-send", "random": "random selection", "cfomd": "CFoMD",
             "cfwmd": "CFwMD"}
    for j, s in enumerate(data["schemes"]):
        for ax, comp in zip(axes, ("position", "velocity"), strict=True):
            plotting.errorband(ax, t, data[f"rmse_{comp}"][j], data[f"rmse_{comp}_stderr"][j],
                               label=f"{names[s]} ({data['transmissions'][j]:.2f} sent/step)",
                               markevery=2, **plotting.look(str(s)))
    axes[0].set(xlabel="time (s)", ylabel="position RMSE (m)",
                title=f"position, l = {data['l']:g} of 9, state feedback")
    axes[1].set(xlabel="time (s)", ylabel="velocity RMSE (m/s)", title="velocity")
    axes[0].legend(ncol=2)
    return plotting.finish(fig, title=f"{data['trials']} trials, {data['particles']} particles")


@checks_doc()
def checks_fig8(data: dict) -> list[Claim]:
    """Fig. 8: CFwMD beats CFoMD and random selection, all-send beats CFwMD, CFwMD sends at
    most ``l``, the RMSEs rise at the end (paired, at :func:`z_required`)."""
    def zd(name):
        return data[f"diff_{name}"], z_score(data[f"diff_{name}"], data[f"diff_{name}_stderr"])

    d1, z1 = zd("cfwmd-cfomd")
    d2, z2 = zd("cfwmd-random")
    d3, z3 = zd("cfwmd-all-send")
    i = data["schemes"].index("cfwmd")
    tx, tx_se = data["transmissions"][i], data["transmissions_stderr"][i]
    saving = 1 - tx / 9
    z_tx = z_score(tx - data["l"], tx_se)
    z_rise = data["rise_end"] / data["rise_end_stderr"]
    z_pool = z_score(data["rise_pooled"], data["rise_pooled_stderr"])
    zq = z_required(Z_ORDER, data["trials"])
    return [
        Claim("CFwMD outperforms CFoMD under the same bandwidth constraint (time-averaged "
              "position RMSE, paired)", bool(z1 < -zq),
              f"difference {d1:+.3f} m, z = {z1:.1f} (needed {-zq:.2f})"),
        Claim("CFwMD outperforms random selection (paired)", bool(z2 < -zq),
              f"difference {d2:+.3f} m, z = {z2:.1f} (needed {-zq:.2f})"),
        Claim("compared to all-send CFwMD loses some accuracy (all-send is the best), but less "
              "than CFoMD does", bool(z3 > zq and z1 < -zq),
              f"CFwMD − all-send {d3:+.3f} m (z = {z3:.1f}); CFoMD − all-send "
              f"{data['diff_cfomd-all-send']:+.3f} m"),
        Claim("CFwMD saves at least 78 % of the transmissions of all-send (at most l = 2 of 9 "
              "sensors per step on average)", bool(z_tx < Z_AGREE),
              f"{tx:.3f} ± {tx_se:.3f} sensors per step: saving {100 * saving:.1f} %"),
        Claim("the RMSEs increase at the later steps (the target leaves the region): RMSE at "
              "10 s exceeds RMSE at 5 s, summed over the schemes, and for no scheme "
              "significantly less", bool(z_pool > zq and np.all(z_rise > -Z_WEAK)),
              f"sum {data['rise_pooled']:+.3f} m (z = {z_pool:.1f}, needed {zq:.2f}); "
              + ", ".join(f"{s}: {v:+.3f} m (z = {z:.1f})" for s, v, z in
                          zip(data["schemes"], data["rise_end"], z_rise, strict=True))),
    ]


# ============================================================================ Fig. 9
FIG9_SCHEMES = ("random", "cfomd", "cfwmd")


@compute_doc(SIZE_KEYS + "``l`` (5,), ``schemes`` (3,); ``tavg_position``, ``tavg_velocity``, "
             "``transmissions`` (3, 5), ``all_send_position``, ``all_send_velocity``; paired "
             "``diff_cfwmd-cfomd``, ``diff_cfwmd-random``, ``diff_random-cfomd`` (5,), "
             "``spread`` (2,), ``spread_shrink``, ``more_tx_gain``, "
             "``excess_at_min_l``, ``excess_at_max_l`` (3,); each with its ``_stderr``.",
             raises=RAISES)
def compute_fig9(profile: str, seed: int, **over) -> dict:
    """Fig. 9: random selection, CFoMD and CFwMD at every ``l`` of :data:`L_FIG9`, and all-send."""
    specs = [_spec(s, l) for s in FIG9_SCHEMES for l in L_FIG9] + [_spec("all-send", 9)]
    got = runs(profile, seed, specs, **over)
    R = {(s, l): got[_spec(s, l)] for s in FIG9_SCHEMES for l in L_FIG9}
    alls = got[_spec("all-send", 9)]
    nL = len(L_FIG9)
    out = {**_size_info(profile, seed, **over), "l": np.array(L_FIG9, dtype=float),
           "schemes": list(FIG9_SCHEMES)}
    for comp in ("position", "velocity"):
        v = np.empty((3, nL))
        e = np.empty((3, nL))
        for a, s in enumerate(FIG9_SCHEMES):
            for b, l in enumerate(L_FIG9):
                v[a, b], e[a, b] = R[(s, l)].time_averaged_rmse(comp)
        out[f"tavg_{comp}"], out[f"tavg_{comp}_stderr"] = v, e
        out[f"all_send_{comp}"], out[f"all_send_{comp}_stderr"] = alls.time_averaged_rmse(comp)
    tx = np.array([[R[(s, l)].average_transmissions for l in L_FIG9] for s in FIG9_SCHEMES])
    out["transmissions"], out["transmissions_stderr"] = tx[..., 0], tx[..., 1]
    for a, b in (("cfwmd", "cfomd"), ("cfwmd", "random"), ("random", "cfomd")):
        d = [contrast([(1, R[(a, l)]), (-1, R[(b, l)])]) for l in L_FIG9]
        out[f"diff_{a}-{b}"] = np.array([v for v, _ in d])
        out[f"diff_{a}-{b}_stderr"] = np.array([e for _, e in d])
    # spread of the four schemes (largest minus smallest time-averaged RMSE, all-send
    # included) at the smallest and at the largest l, and its decrease (paired; which scheme is
    # largest and smallest is taken as observed)
    lo, hi = L_FIG9[0], L_FIG9[-1]
    spread = {}
    for l in (lo, hi):
        cand = [R[(s, l)] for s in FIG9_SCHEMES] + [alls]
        vals = [r.time_averaged_rmse()[0] for r in cand]
        spread[l] = (cand[int(np.argmax(vals))], cand[int(np.argmin(vals))])
    out["spread"] = np.array([contrast([(1, spread[l][0]), (-1, spread[l][1])])[0]
                              for l in (lo, hi)])
    out["spread_shrink"], out["spread_shrink_stderr"] = contrast(
        [(1, spread[lo][0]), (-1, spread[lo][1]), (-1, spread[hi][0]), (1, spread[hi][1])])
    # more transmissions help: RMSE at the smallest l minus RMSE at the largest, per scheme
    dl = [contrast([(1, R[(s, lo)]), (-1, R[(s, hi)])]) for s in FIG9_SCHEMES]
    out["more_tx_gain"] = np.array([v for v, _ in dl])
    out["more_tx_gain_stderr"] = np.array([e for _, e in dl])
    # distance from all-send at the largest l, per scheme
    da = [contrast([(1, R[(s, hi)]), (-1, alls)]) for s in FIG9_SCHEMES]
    out["excess_at_max_l"] = np.array([v for v, _ in da])
    out["excess_at_max_l_stderr"] = np.array([e for _, e in da])
    da = [contrast([(1, R[(s, lo)]), (-1, alls)]) for s in FIG9_SCHEMES]
    out["excess_at_min_l"] = np.array([v for v, _ in da])
    out["excess_at_min_l_stderr"] = np.array([e for _, e in da])
    return out


@plot_doc()
def plot_fig9(data: dict):
    """Fig. 9: time-averaged position and velocity RMSE against transmissions per step."""
    fig, axes = plotting.subplots(1, 2, stack=True)
    names = {"random": "random selection", "cfomd": "CFoMD", "cfwmd": "CFwMD"}
    for ax, comp, unit in zip(axes, ("position", "velocity"), ("m", "m/s"), strict=True):
        for j, s in enumerate(data["schemes"]):
            ax.errorbar(data["transmissions"][j], data[f"tavg_{comp}"][j],
                        xerr=1.96 * data["transmissions_stderr"][j],
                        yerr=1.96 * data[f"tavg_{comp}_stderr"][j], capsize=2, label=names[s],
                        **plotting.look(str(s)))
        ax.errorbar([9.0], [data[f"all_send_{comp}"]],
                    yerr=[1.96 * data[f"all_send_{comp}_stderr"]], capsize=2, label="all-send",
                    **plotting.look("all-send", ls="none", markersize=9))
        ax.set(xlabel="average transmissions per step (-)",
               ylabel=f"time-averaged {comp} RMSE ({unit})", title=comp)
    axes[0].legend(ncol=2)
    return plotting.finish(fig, title="l = " + ", ".join(f"{v:g}" for v in data["l"])
                           + f"; {data['trials']} trials, {data['particles']} particles")


@checks_doc()
def checks_fig9(data: dict) -> list[Claim]:
    """Fig. 9: CFwMD's advantage at ``l = 1, 2``, never significantly worse, more transmissions
    help, the curves approach each other as ``l`` nears ``N``."""
    L = list(data["l"])
    small = [L.index(v) for v in (1.0, 2.0) if v in L]
    zo = data["diff_cfwmd-cfomd"] / data["diff_cfwmd-cfomd_stderr"]
    zr = data["diff_cfwmd-random"] / data["diff_cfwmd-random_stderr"]
    z_sp = z_score(data["spread_shrink"], data["spread_shrink_stderr"])
    z_gain = data["more_tx_gain"] / data["more_tx_gain_stderr"]
    zq = z_required(Z_ORDER, data["trials"])
    return [
        Claim("with few transmissions (l = 1, 2) CFwMD has a clear advantage over CFoMD and "
              "random selection (paired)",
              bool(np.all(zo[small] < -zq) and np.all(zr[small] < -zq)),
              "z vs CFoMD " + ", ".join(f"{zo[i]:.1f}" for i in small)
              + "; z vs random " + ", ".join(f"{zr[i]:.1f}" for i in small)
              + f" (needed {-zq:.2f})"),
        Claim("CFwMD is never significantly worse than CFoMD or random selection at any l",
              bool(np.all(zo < Z_WEAK) and np.all(zr < Z_WEAK)),
              "z vs CFoMD " + ", ".join(f"{v:.1f}" for v in zo)
              + "; vs random " + ", ".join(f"{v:.1f}" for v in zr)),
        Claim("more transmissions help every scheme: RMSE at l = 1 exceeds RMSE at l = 8",
              bool(np.all(z_gain > zq)), "z = " + ", ".join(f"{v:.1f}" for v in z_gain)
              + f" (needed {zq:.2f})"),
        Claim("as l approaches N = 9 the four curves approach each other: the spread of the "
              "time-averaged RMSEs (all-send included) at l = 8 is below that at l = 1 "
              "(paired)", bool(z_sp > zq),
              f"spread {data['spread'][0]:.3f} m at l = {L[0]:g}, {data['spread'][1]:.3f} m at "
              f"l = {L[-1]:g} (z = {z_sp:.1f}, needed {zq:.2f})"),
    ]


# ============================================================================ Fig. 10, Table III
@functools.lru_cache(maxsize=8)
def _fig10_table3(profile: str, seed: int, trials: int | None = None,
                  particles: int | None = None) -> dict:
    """The shared computation of Fig. 10 and Table III (cached: the two entries use one run
    set)."""
    over = {"trials": trials, "particles": particles}
    specs = [_spec("cfwmd", l, fb) for l in L_FIG10 for fb in ("state", "state+cov")]
    got = runs(profile, seed, specs, **over)
    T = SCENARIO.T
    first, later = slice(0, T // 2), slice(T // 2, T)
    out = {**_size_info(profile, seed, **over), "l": np.array(L_FIG10, dtype=float),
           "time": np.arange(1, T + 1) * SCENARIO.dt}
    keys = ("rmse_position", "rmse_position_stderr", "rmse_velocity", "rmse_velocity_stderr")
    for name, fb in (("cfwmd", "state"), ("cfwmd2", "state+cov")):
        rs = [got[_spec("cfwmd", l, fb)] for l in L_FIG10]
        for key in keys:
            out[f"{name}_{key}"] = _stack(rs, key)
        tav = np.array([r.time_averaged_rmse() for r in rs])
        out[f"{name}_tavg_position"], out[f"{name}_tavg_position_stderr"] = tav[:, 0], tav[:, 1]
        tx = np.array([r.average_transmissions for r in rs])
        out[f"{name}_transmissions"], out[f"{name}_transmissions_stderr"] = tx[:, 0], tx[:, 1]
        out[f"{name}_eta"] = np.array([r.eta for r in rs])
    for part, steps in (("all", slice(None)), ("first", first), ("later", later)):
        d = [contrast([(1, got[_spec("cfwmd", l, "state+cov")]),
                       (-1, got[_spec("cfwmd", l, "state")])], steps=steps) for l in L_FIG10]
        out[f"diff_{part}"] = np.array([v for v, _ in d])
        out[f"diff_{part}_stderr"] = np.array([e for _, e in d])
    both = [(w, got[_spec("cfwmd", l, fb)]) for l in L_FIG10
            for w, fb in ((1, "state+cov"), (-1, "state"))]
    out["pooled_later"], out["pooled_later_stderr"] = contrast(both, steps=later)
    out["pooled_all"], out["pooled_all_stderr"] = contrast(both)
    # growth of CFwMD2's advantage from the first to the second half, summed over l (paired)
    terms = []
    for l in L_FIG10:
        r1, r2 = got[_spec("cfwmd", l, "state")], got[_spec("cfwmd", l, "state+cov")]
        terms += [(1, r2, later), (-1, r1, later), (-1, r2, first), (1, r1, first)]
    out["growth"], out["growth_stderr"] = contrast(terms)
    # closeness to the target: |l - lbar_1| - |l - lbar_2| (paired over trials)
    close = []
    for l in L_FIG10:
        r1, r2 = got[_spec("cfwmd", l, "state")], got[_spec("cfwmd", l, "state+cov")]
        s1 = np.sign(l - r1.average_transmissions[0])
        s2 = np.sign(l - r2.average_transmissions[0])
        v, e = tx_contrast([(-s1, r1), (s2, r2)])
        close.append(((s1 - s2) * l + v, e))
    out["closer"] = np.array([v for v, _ in close])
    out["closer_stderr"] = np.array([e for _, e in close])
    # covariance feedback removes at least half of the shortfall: (l - lbar_1)/2 - (l - lbar_2)
    half = [tx_contrast([(-0.5, got[_spec("cfwmd", l, "state")]),
                          (1, got[_spec("cfwmd", l, "state+cov")])]) for l in L_FIG10]
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
    return dict(_fig10_table3(profile, seed, *_sizes(profile, over)))


@compute_doc(raises=RAISES, returns=SIZE_KEYS + "``l``; ``cfwmd_transmissions``, "
             "``cfwmd2_transmissions``; ``printed_cfwmd``, ``printed_cfwmd2``, "
             "``cfwmd_z_vs_printed``, ``cfwmd2_z_vs_printed``; ``closer`` (CFwMD's "
             "``|l - lbar|`` minus CFwMD2's), ``half_shortfall`` (half of CFwMD's shortfall l - "
             "lbar minus CFwMD2's); each with its ``_stderr``; ``cfwmd_eta``.")
def compute_table3(profile: str, seed: int, **over) -> dict:
    """Table III: the transmissions of Fig. 10's runs next to :data:`TABLE3_PRINTED`."""
    d = _fig10_table3(profile, seed, *_sizes(profile, over))
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


# ============================================================================ registration
_NOTE_SCENARIO = (
    "Scenario: the paper's parameters; sensors at the centres of the 3 × 3 cells of "
    "[−10, 10]² m and the true trajectory starting at x₀ = (−8, 2, −8, 2) in every trial (the "
    "filters' prior N(x₀, diag(9, 4, 9, 4))): neither is stated in the paper. ")


def _entry(entry_id: str, kind: str, status: str, functions: tuple, parameters: dict,
           caption: str, note: str, settable=SETTABLE, **extra) -> None:
    """Register an entry of this chapter: the scenario's parameters and note, and those given."""
    add_entry(entry_id, kind, status, functions, chapter=CHAPTER, settable=settable, **extra,
              parameters={**PARAMS, **parameters}, caption=caption, note=_NOTE_SCENARIO + note)


_entry(
    "zheng2014-fig7", "figure", "reproduced", (compute_fig7, plot_fig7, checks_fig7),
    {"trajectories": TRAJECTORIES},
    "Nonlinear tracking: the 3 × 3 sensor grid in the 20 m × 20 m region and a sample "
    "target trajectory (with the mean path).",
    "The sensor positions are our choice (the paper draws them but does "
    "not list them); the statements checked are where the target goes (it leaves the region "
    "near the end), from 10⁴ simulated trajectories.", settable=SETTABLE_FIG7)

_entry(
    "zheng2014-fig8", "figure", "reproduced", (compute_fig8, plot_fig8, checks_fig8),
    {"l": L_FIG8, "feedback": "state (Proposition 7)"},
    "Nonlinear tracking with state feedback, l = 2 of N = 9: position and velocity "
    "RMSE of all-send, random selection, CFoMD and CFwMD.",
    "The orderings the paper states hold with paired errors (CFwMD < "
    "CFoMD < random; all-send best; RMSE rising at the end). Our copy of the paper has no "
    "numbers for the curves, so only the orderings are compared. CFwMD sends about 1.5 "
    "measurements per step (target 2): it saves more than the 78 % the paper quotes.")

_entry(
    "zheng2014-fig9", "figure", "reproduced", (compute_fig9, plot_fig9, checks_fig9),
    {"l": list(L_FIG9), "feedback": "state (Proposition 7)",
     "x_axis": "measured average transmissions per step; all-send at 9"},
    "Nonlinear tracking: time-averaged RMSE against the average number of transmissions "
    "per step, l ∈ {1, 2, 4, 6, 8}, state feedback.",
    "The values of l are our choice (the paper does not list them). "
    "Runs at l = 2 are those of Fig. 8 and the CFwMD runs at l = 2, 4, 6 those of Fig. 10. "
    "Beyond the paper: at paper scale random selection beats CFoMD from l = 6 on (paired z = "
    "-4.7, -10.0): dropping the silences biases CFoMD.")

_entry(
    "zheng2014-fig10", "figure", "reproduced", (compute_fig10, plot_fig10, checks_fig10),
    {"l": list(L_FIG10), "feedback": "state (Proposition 7) vs state+cov (Proposition 8)"},
    "Nonlinear tracking: position RMSE of CFwMD (state feedback) and CFwMD2 (state and "
    "covariance feedback) for l = 2, 4, 6.",
    "Shares its runs with Table III (one computation).")

_entry(
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
