"""Registry entries of Part IV(a) (zheng2014), Section VII.A: linear tracking, scalar observations.

* ``zheng2014-fig1``: feedback of the predicted state, ``N = 2``, ``l = 1``: position and velocity
  RMSE of all-send, random selection, CFoMD and CFwMD.
* ``zheng2014-fig2``: ``N = 4``, ``l`` in {1, 1.2, 1.5, 2, 3}: CFwMD (state fed back) against
  CFwMD2 (state and covariance fed back).
* ``zheng2014-table1``: the average number of transmissions per step of the same runs, next to
  the paper's printed values.

Fig. 3 (no feedback) is in :mod:`fusioncenter.figures.zheng2014.no_feedback`, the book's own
``zheng2014-table1-choices`` in :mod:`fusioncenter.figures.zheng2014.choices`, the pieces shared
with the vector and nonlinear entries in :mod:`fusioncenter.figures.zheng2014.common`. Fig. 3
takes this module's chapter, run sizes and :func:`scenario_parameters`; :data:`DATA_KEYS` lists
the data of every scalar entry.

Every choice the paper leaves open is listed in each entry's ``parameters`` (from
:attr:`~fusioncenter.censoring.scenarios.linear.LinearScenario.choices`). All runs go through
:func:`fusioncenter.censoring.run`: for one seed the trials (truth and measurements) are shared
by every scheme and every ``l`` of an entry, so differences between curves are paired.

Data keys (plain NumPy arrays and numbers; the chapter ``book/zheng2014/results`` prints them):
see :data:`DATA_KEYS`.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from fusioncenter import censoring as cs
from fusioncenter import context, plotting
from fusioncenter.figures.common import checks_doc, compute_doc, plot_doc
from fusioncenter.figures.registry import Claim
from fusioncenter.figures.zheng2014.common import (
    LABELS,
    RAISES,
    SCHEMES,
    Z_ORDER,
    Z_TOL,
    add_entry,
    run_size,
    settable,
)
from fusioncenter.figures.zheng2014.comparisons import (
    by_l_data,
    by_l_runs,
    checks_schemes,
    claim_rmse_decreases,
    schemes_data,
    transmissions_data,
)
from fusioncenter.figures.zheng2014.contrasts import z_score
from fusioncenter.figures.zheng2014.panels import by_l_panels, rmse_panels, transmissions_plot
from fusioncenter.figures.zheng2014.runs import kept_run

#: Ids of the book's own figures registered here (not figures of the paper).
OWN_IDS: tuple[str, ...] = ("zheng2014-table1-choices",)

CHAPTER = "book/zheng2014/results"

#: Monte Carlo trials and particles (paper: 5000 trials, N_s = 1000 particles).
TRIALS = {"fast": 200, "paper": 5000}
PARTICLES = {"fast": 300, "paper": 1000}
#: Fig. 2 and Table I resolve differences of a few per cent: more trials (fewer particles) in
#: the fast profile.
TRIALS_FIG2 = {"fast": 1024, "paper": 5000}
PARTICLES_FIG2 = {"fast": 300, "paper": 1000}

L_FIG2 = (1.0, 1.2, 1.5, 2.0, 3.0)
FIG2 = {"N": 4, "l": list(L_FIG2), "feedback": ["state (CFwMD)", "state+cov (CFwMD2)"]}
#: Table I of the paper (average number of transmissions per step, N = 4).
PAPER_TABLE1 = {"cfwmd": (1.0625, 1.1709, 1.3536, 1.7399, 2.7838),
                "cfwmd2": (1.0530, 1.2230, 1.4992, 2.0002, 3.0095)}

#: What ``compute`` returns, per entry (the chapter may print any of these).
DATA_KEYS = {
    "zheng2014-fig1": (
        "time (T,) s; schemes (4,) names; rmse_position, rmse_position_stderr, rmse_velocity, "
        "rmse_velocity_stderr (4, T); tavg_position, tavg_position_stderr, tavg_velocity, "
        "tavg_velocity_stderr (4,); transmissions, transmissions_stderr (4,) per step; "
        "pairs (3, 2) names, pair_diff_position, pair_stderr_position, pair_diff_velocity, "
        "pair_stderr_velocity (3,) [consecutive schemes of all-send < CFwMD < CFoMD < random]; "
        "collapsed (4,); n_trials, n_particles, N, l, eta"),
    "zheng2014-fig2": (
        "time (T,); l (5,); rmse_position, rmse_position_stderr (2, 5, T) [CFwMD, CFwMD2]; "
        "tavg_position, tavg_position_stderr (2, 5); diff (5,), diff_stderr (5,) [CFwMD2 minus "
        "CFwMD, paired]; rel_gain (5,), rel_gain_stderr (5,) [(CFwMD - CFwMD2) / CFwMD]; "
        "n_trials, n_particles, N"),
    "zheng2014-table1": (
        "l (5,); cfwmd, cfwmd_stderr, cfwmd2, cfwmd2_stderr (5,) transmissions per step; "
        "paper_cfwmd, paper_cfwmd2 (5,); z_cfwmd, z_cfwmd2 (5,) [(ours - paper) / "
        "(sqrt 2 stderr)]; closer_z (5,) [(|CFwMD - l| - |CFwMD2 - l|) / stderr]; p_none (5, 2) "
        "fraction of steps with no transmission [CFwMD, CFwMD2], p_none_independent (5,) "
        "(1 - l/N)^N; silent_pairs, silent_pairs_stderr (5, 2) mean number per trial of "
        "consecutive steps k, k+1 both without transmission; silent_pairs_z (5,) paired z of "
        "CFwMD2 minus CFwMD; n_trials, n_particles, N"),
    "zheng2014-fig3": (
        "time (T,); curves (6,) names [all-send, random, cfomd, printed, corrected, exact]; "
        "rmse_position, rmse_position_stderr, rmse_velocity, rmse_velocity_stderr (6, T); "
        "tavg_position, tavg_position_stderr (6,); n_trials (6,); printed_max_abs_diff; "
        "pair names (k, 2), pair_diff, pair_stderr, pair_trials (k,); transmissions, "
        "transmissions_stderr (6,); collapsed (6,); l, N"),
    "zheng2014-table1-choices": (
        "variants (V,) names; l (5,); cfwmd, cfwmd_stderr, cfwmd2, cfwmd2_stderr (V, 5); "
        "closer_z (V, 5); tavg_cfwmd, tavg_cfwmd2 (V, 5) position RMSE; diff_z (V, 5) paired "
        "z-score of CFwMD2 minus CFwMD position RMSE; n_trials, "
        "n_particles, N"),
}


# ------------------------------------------------------------------------- running
# Where the trials run is the execution context's (fusioncenter.context.executor(): a process
# pool, a Dask cluster or serial); the data do not depend on it.


def scenario_parameters(sc: cs.LinearScenario, **extra) -> dict:
    """The ``parameters`` of a scalar entry: its scenario, the run sizes and the open choices.

    Parameters
    ----------
    sc : fusioncenter.censoring.LinearScenario
        The entry's scenario.
    **extra
        The entry's own parameters (``l``, ``feedback``, ...), listed before the choices.

    Returns
    -------
    dict
        ``N``, ``r``, ``sigma2``, ``T``, ``x0``, ``dt``, ``h``, ``trials`` and ``particles``
        (``TRIALS``, ``PARTICLES``), then ``extra``, then ``choices`` (the scenario's
        :attr:`~fusioncenter.censoring.scenarios.linear.LinearScenario.choices`).
    """
    return {"N": sc.N, "r": sc.r, "sigma2": sc.sigma2, "T": sc.T, "x0": list(sc.x0),
            "dt": sc.dt, "h": list(sc.h), "trials": dict(TRIALS), "particles": dict(PARTICLES),
            **extra, "choices": sc.choices}


# ============================================================== Fig. 1 (feedback)
FIG1 = {"N": 2, "l": 1.0, "feedback": "state"}


@functools.lru_cache(maxsize=4)
def _fig1_runs(seed: int, n: int, P: int, N: int, l: float) -> tuple:
    sc = cs.LinearScenario(N=N)
    ex = context.executor()
    return tuple(kept_run(sc, s, feedback="state", l=l, n=n, P=P, seed=seed, executor=ex)
                 for s in SCHEMES)


@compute_doc("See :data:`DATA_KEYS` (``zheng2014-fig1``).", raises=RAISES)
def compute_fig1(profile: str, seed: int, **over) -> dict:
    """Fig. 1: the four schemes (:data:`~fusioncenter.figures.zheng2014.common.SCHEMES`) with
    the predicted state fed back, ``N`` sensors (default 2) and target ``l`` (default 1), on
    shared trials (:func:`~fusioncenter.figures.zheng2014.comparisons.schemes_data`)."""
    n, P = run_size(profile, TRIALS, PARTICLES, over)
    N, l = over.get("N", FIG1["N"]), over.get("l", FIG1["l"])
    return schemes_data(_fig1_runs(seed, n, P, N, l), N, l)


@plot_doc()
def plot_fig1(data: dict):
    """Fig. 1: position (a) and velocity (b) RMSE against time of the four schemes, with 95 %
    bands, on log axes."""
    fig = rmse_panels(data, list(data["schemes"]), LABELS)
    return plotting.finish(fig, title=f"feedback of the predicted state, N = {data['N']}, "
                                      f"l = {data['l']:g} ({data['n_trials']} trials, "
                                      f"{data['n_particles']} particles; bands: 95 %)")


#: The claims on Fig. 1 (the paper makes them of Fig. 4 too).
checks_fig1 = checks_schemes


add_entry(
    "zheng2014-fig1", "figure", "reproduced", (compute_fig1, plot_fig1, checks_fig1),
    chapter=CHAPTER,
    parameters=scenario_parameters(cs.LinearScenario(N=2), l=1.0, feedback="state"),
    settable=settable(TRIALS, PARTICLES, N=FIG1["N"], l=FIG1["l"]),
    caption="Linear tracking, scalar observations, N = 2 sensors, feedback of the predicted "
    "state, l = 1: position and velocity RMSE against time of all-send, random selection, "
    "CFoMD and CFwMD (Monte Carlo, 95 % bands).",
    note="The paper's ordering all-send < CFwMD < CFoMD < random holds for position and "
    "velocity with large paired z-scores. The figure's axes are not given numerically in the "
    "text, so only the ordering and the transmission rate are compared. Open choices (x₀ "
    "known, what is fed back, random selection) are listed in the parameters.")


# ============================================================== Fig. 2 and Table I


@functools.lru_cache(maxsize=4)
def _fig2_runs(seed: int, n: int, P: int, N: int) -> tuple:
    """(CFwMD runs, CFwMD2 runs) at every l: shared by Fig. 2 and Table I."""
    return by_l_runs(kept_run, cs.LinearScenario(N=N), L_FIG2, n=n, P=P, seed=seed,
                     executor=context.executor())


def _fig2_args(profile: str, seed: int, over: dict) -> tuple:
    n, P = run_size(profile, TRIALS_FIG2, PARTICLES_FIG2, over)
    return seed, n, P, over.get("N", FIG2["N"])


@compute_doc("See :data:`DATA_KEYS` (``zheng2014-fig2``).", raises=RAISES)
def compute_fig2(profile: str, seed: int, **over) -> dict:
    """Fig. 2: CFwMD and CFwMD2 at every ``l`` of ``L_FIG2`` with ``N`` sensors (default
    4), and the relative gain ``(CFwMD - CFwMD2) / CFwMD`` of the time-averaged position RMSE
    (standard error by the delta method). The runs are Table I's (cached)."""
    args = _fig2_args(profile, seed, over)
    a, b = _fig2_runs(*args)
    gain, gse = [], []
    for ra, rb in zip(a, b, strict=True):
        va, ia = cs.results.tavg_influence(ra, "position")
        vb, ib = cs.results.tavg_influence(rb, "position")
        # relative gain (va - vb) / va by the delta method, per trial
        g = (va - vb) / va
        infl = (ia - ib) / va - (va - vb) * ia / va**2
        gain.append(g)
        gse.append(float(infl.std(ddof=1) / math.sqrt(infl.size)))
    return by_l_data(a, b, L_FIG2, args[-1], rel_gain=np.array(gain),
                     rel_gain_stderr=np.array(gse))


@plot_doc()
def plot_fig2(data: dict):
    """Fig. 2: the position RMSE against time, one curve per ``l``, of (a) CFwMD and (b)
    CFwMD2, and (c) their time averages against ``l``
    (:func:`~fusioncenter.figures.zheng2014.panels.by_l_panels`)."""
    return plotting.finish(by_l_panels(data))


@checks_doc()
def checks_fig2(data: dict) -> list[Claim]:
    """Fig. 2: CFwMD beats CFwMD2 at ``l = 1`` and loses for ``1 < l < 3`` (paired), the
    relative gain is smaller at ``l = 3`` than at ``l = 2``, and both RMSEs decrease in ``l``."""
    l, d, s = data["l"], data["diff"], data["diff_stderr"]
    z = d / s
    mid = (l > 1) & (l < 3)
    g, gs = data["rel_gain"], data["rel_gain_stderr"]
    i2, i3 = int(np.flatnonzero(l == 2.0)[0]), int(np.flatnonzero(l == 3.0)[0])
    return [
        Claim("l = 1: CFwMD beats CFwMD2 (the covariance feedback makes silent runs longer)",
              bool(z[l == 1.0][0] > Z_ORDER),
              f"CFwMD2 − CFwMD = {d[l == 1.0][0]:+.4f} ± {s[l == 1.0][0]:.4f} m "
              f"(z = {z[l == 1.0][0]:.1f})"),
        Claim("1 < l < 3: CFwMD2 beats CFwMD (paired differences of the time-averaged position "
              "RMSE)", bool(np.all(-z[mid] > Z_ORDER)),
              "; ".join(f"l = {li:g}: {di:+.4f} (z = {zi:.1f})"
                        for li, di, zi in zip(l[mid], d[mid], z[mid], strict=True))),
        Claim("l = 3: the covariance feedback helps less than at l = 2 (relative gain)",
              bool(g[i3] < g[i2]),
              f"relative gain {g[i2]:.4f} ± {gs[i2]:.4f} at l = 2, "
              f"{g[i3]:.4f} ± {gs[i3]:.4f} at l = 3"),
        claim_rmse_decreases(data),
    ]


@compute_doc("See :data:`DATA_KEYS` (``zheng2014-table1``).", raises=RAISES)
def compute_table1(profile: str, seed: int, **over) -> dict:
    """Table I: the transmissions per step of Fig. 2's runs next to :data:`PAPER_TABLE1`, with
    how often no sensor sends in a step and in two consecutive steps (the paper's explanation
    of CFwMD2's loss at ``l = 1``)."""
    args = _fig2_args(profile, seed, over)
    a, b = _fig2_runs(*args)
    N = args[-1]
    l = np.array(L_FIG2)
    # the paper's explanation at l = 1: steps where nobody sends, and runs of them
    none, runs, runs_se, runs_z = [], [], [], []
    for ra, rb in zip(a, b, strict=True):
        za, zb = (r.mc.samples[..., r.scenario.d] == 0 for r in (ra, rb))
        none.append([za.mean(), zb.mean()])
        qa = (za[:, 1:] & za[:, :-1]).sum(axis=1)  # consecutive silent pairs per trial
        qb = (zb[:, 1:] & zb[:, :-1]).sum(axis=1)
        runs.append([qa.mean(), qb.mean()])
        runs_se.append([qa.std(ddof=1) / math.sqrt(qa.size), qb.std(ddof=1) / math.sqrt(qb.size)])
        dd = qb - qa
        # 0 when the runs are identical (few trials, or no silent pair in either)
        runs_z.append(z_score(float(dd.mean()), float(dd.std(ddof=1) / math.sqrt(dd.size))))
    return {
        "p_none": np.array(none), "p_none_independent": (1 - l / N) ** N,
        "silent_pairs": np.array(runs), "silent_pairs_stderr": np.array(runs_se),
        "silent_pairs_z": np.array(runs_z),
        **transmissions_data(a, b, L_FIG2, PAPER_TABLE1, N),
    }


@plot_doc()
def plot_table1(data: dict):
    """Table I: the transmissions per step minus ``l`` of CFwMD and CFwMD2 against ``l``, ours
    (95 % bars) and the printed ones."""
    return transmissions_plot(data, LABELS, "I", f"N = {data['N']}: average transmissions per "
                               f"step ({data['n_trials']} trials)")


@checks_doc()
def checks_table1(data: dict) -> list[Claim]:
    """Table I: CFwMD2 sends closer to ``l`` than CFwMD for ``l > 1``, CFwMD fewer than ``l``;
    agreement with the printed values (paper-specific); at ``l = 1`` more silent pairs of steps
    under CFwMD2 and both above ``l``; silent steps more frequent than ``(1 - l/N)^N``."""
    l, cz = data["l"], data["closer_z"]
    hi, mid = l >= 1.5, l > 1
    a, b = data["cfwmd"], data["cfwmd2"]
    closer = np.abs(b - l) < np.abs(a - l)
    zb = data["z_cfwmd2"]
    off = a - data["paper_cfwmd"]
    return [
        Claim("l > 1: CFwMD2 sends closer to l than CFwMD (paired, per-trial averages: by more "
              "than 4 standard errors for l ≥ 1.5, in the point estimates at l = 1.2)",
              bool(np.all(cz[hi] > Z_ORDER) and np.all(closer[mid])),
              "; ".join(f"l = {li:g}: z = {zi:.1f}" for li, zi in
                        zip(l[mid], cz[mid], strict=True))),
        Claim("l ≥ 1.2: CFwMD sends fewer than l (its sₖⁱ ignores the feedback's error, "
              "Remark 1 (III))",
              bool(np.all((a - l)[mid] / data["cfwmd_stderr"][mid] < -Z_ORDER)),
              ", ".join(f"{v:.4f}" for v in a[mid])),
        Claim("l ≥ 1.2: CFwMD2 agrees with the paper's Table I (|z| < 4)",
              bool(np.all(np.abs(zb[mid]) < Z_TOL)),
              "z = " + ", ".join(f"{v:.2f}" for v in zb) + " (l = 1 first)",
              paper_specific=True),
        Claim("CFwMD is within 0.05 transmissions per step of the paper's Table I at every l",
              bool(np.all(np.abs(off) < 0.05)),
              "ours − paper = " + ", ".join(f"{v:+.4f}" for v in off)
              + "; z = " + ", ".join(f"{v:.2f}" for v in data["z_cfwmd"]),
              paper_specific=True),
        Claim("l = 1: CFwMD2 has more pairs of consecutive steps without any transmission "
              "than CFwMD (the paper's explanation of CFwMD2's loss at l = 1)",
              bool(data["silent_pairs_z"][0] > Z_ORDER),
              f"per trial {data['silent_pairs'][0, 1]:.3f} vs {data['silent_pairs'][0, 0]:.3f} "
              f"(paired z = {data['silent_pairs_z'][0]:.1f})"),
        Claim("a step without any transmission is more frequent than the independent-sensor "
              "value (1 − l/N)ᴺ the paper quotes (the decisions share the fed-back prediction "
              "error)", bool(np.all(data["p_none"] > data["p_none_independent"][:, None])),
              "l = 1: " + ", ".join(f"{v:.3f}" for v in data["p_none"][0])
              + f" vs {data['p_none_independent'][0]:.3f}; l = 2: "
              + ", ".join(f"{v:.3f}" for v in data["p_none"][3])
              + f" vs {data['p_none_independent'][3]:.3f}"),
        Claim("l = 1: both schemes send more than l (as in the paper)",
              bool((a[0] - 1) / data["cfwmd_stderr"][0] > Z_ORDER
                   and (b[0] - 1) / data["cfwmd2_stderr"][0] > Z_ORDER),
              f"CFwMD {a[0]:.4f} ± {data['cfwmd_stderr'][0]:.4f}, CFwMD2 "
              f"{b[0]:.4f} ± {data['cfwmd2_stderr'][0]:.4f}"),
    ]


def _fig2_parameters(**extra) -> dict:
    """The parameters of Fig. 2 and Table I (the same runs)."""
    return scenario_parameters(cs.LinearScenario(N=4), l=list(L_FIG2),
                               feedback=["state", "state+cov"], trials=dict(TRIALS_FIG2),
                               particles=dict(PARTICLES_FIG2), **extra)


add_entry(
    "zheng2014-fig2", "figure", "reproduced", (compute_fig2, plot_fig2, checks_fig2),
    chapter=CHAPTER, parameters=_fig2_parameters(),
    settable=settable(TRIALS_FIG2, PARTICLES_FIG2, N=FIG2["N"]),
    caption="N = 4 sensors, l ∈ {1, 1.2, 1.5, 2, 3}: position RMSE against time, one curve per "
    "l, of (a) CFwMD (predicted state fed back) and (b) CFwMD2 (predicted state and covariance "
    "fed back); (c) their time averages against l.",
    note="As in the paper: CFwMD is better at l = 1, CFwMD2 better for 1 < l < 3, and the "
    "covariance feedback helps little at l = 3. r = 1 for every sensor (the paper states it "
    "for sensors 1, 2 only; zheng2014-table1-choices varies it).")

add_entry(
    "zheng2014-table1", "table", "differs", (compute_table1, plot_table1, checks_table1),
    chapter=CHAPTER, parameters=_fig2_parameters(paper_values=PAPER_TABLE1),
    settable=settable(TRIALS_FIG2, PARTICLES_FIG2, N=FIG2["N"]),
    caption="Average number of transmissions per step (N = 4, scalar observations) of CFwMD "
    "and CFwMD2 for each target l, with Monte Carlo standard errors, next to the paper's "
    "Table I.",
    reason="at the paper's scale our CFwMD sends 0.02-0.04 fewer transmissions per step than "
    "printed at every l, and at l = 1 our CFwMD2 about as many as CFwMD (printed: fewer)",
    note="Same runs as Fig. 2. The conclusions hold (CFwMD2 meets the target l more closely "
    "for l > 1; CFwMD sends fewer than l), but at the paper's scale our CFwMD sends 0.02-0.04 "
    "fewer transmissions per step than the printed values at every l (z from -4 to -8, with "
    "the paper's unstated Monte Carlo error taken equal to ours), and at l = 1 our CFwMD2 "
    "sends 0.028 fewer than printed (z about -4.6) and about as many as CFwMD, where the paper "
    "has CFwMD2 below CFwMD. The rates depend on how well the FC predicts (fewer particles "
    "give more transmissions) and on open choices: see zheng2014-table1-choices.")
