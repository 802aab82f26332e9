"""What the registry entries of Part IV share (zheng2014, Sections VII.A-D).

The scalar entries (:mod:`fusioncenter.figures.zheng2014.linear`,
:mod:`fusioncenter.figures.zheng2014.choices`), the vector ones
(:mod:`fusioncenter.figures.zheng2014.vector`) and the nonlinear ones
(:mod:`fusioncenter.figures.zheng2014.nonlinear`) use these pieces:

* the settable parameters (:func:`settable`) and the run sizes they give (:func:`run_size`);
* the data of a run as curves (:func:`curves`, :func:`stacked`), paired differences
  (:func:`pair_differences`), the data of a figure of the four schemes (:func:`schemes_data`)
  and of CFwMD against CFwMD2 at every ``l`` (:func:`by_l_runs`, :func:`by_l_data`,
  :func:`transmissions_data`);
* the plots (:func:`rmse_panels`, :func:`by_l_panels`, :func:`transmissions_plot`), the claims
  (:func:`z_claim_ordered`, :func:`checks_schemes`) and the registration
  (:func:`add_entry`).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable

import matplotlib
import matplotlib.ticker
import numpy as np

from fusioncenter import censoring as cs
from fusioncenter import montecarlo, plotting
from fusioncenter.context import Parameter
from fusioncenter.figures.common import checks_doc, document
from fusioncenter.figures.registry import Claim, Entry, register
from fusioncenter.profile import by_profile

#: The four schemes of Figs. 1, 4 and 8, in the order of their curves.
SCHEMES = ("all-send", "random", "cfomd", "cfwmd")
#: Legend labels of the schemes and of the variants of CFwMD (scalar observations).
LABELS = {"all-send": "all-send", "random": "random selection", "cfomd": "CFoMD",
          "cfwmd": "CFwMD", "cfwmd2": "CFwMD2", "printed": "CFwMD, Prop. 3 as printed",
          "corrected": "CFwMD, Prop. 3 corrected", "exact": "CFwMD, exact filter"}
#: A paired difference counts as an ordering when it exceeds Z_ORDER standard errors.
Z_ORDER = 4.0
#: Agreement of a Monte Carlo estimate with a printed value: |z| < Z_TOL, with the standard
#: error of the difference taken as sqrt(2) times ours (the paper's own Monte Carlo error, from
#: the same number of trials, is assumed equal to ours; it is not stated).
Z_TOL = 4.0
#: The ``Raises`` section of the entries' compute functions (``compute_doc(..., raises=RAISES)``):
#: they read ``over`` with ``dict.get``; its keys and values are checked by
#: :meth:`fusioncenter.figures.registry.Entry.run_compute`.
RAISES = (("ValueError", "For a ``profile`` other than ``\"fast\"`` and ``\"paper\"`` when a "
           "default size is read from it. Called directly, an unknown key of ``over`` is "
           "ignored."),)


def settable(trials: dict, particles: dict, *, N: int | None = None,
             l: float | None = None) -> tuple[Parameter, ...]:
    """The overridable parameters of an entry.

    Parameters
    ----------
    trials, particles : dict
        The profile defaults (``{"fast": ..., "paper": ...}``) of the Monte Carlo trials and
        of the particles of the fusion centre's filter (accuracy only).
    N : int, optional
        If given, the number of sensors is settable, with this default (the paper's setting:
        ``model=True``).
    l : float, optional
        If given, the target number of transmissions per step is settable (``model=True``).

    Returns
    -------
    tuple of Parameter
        ``trials``, ``particles``, then ``N`` and ``l`` if given.
    """
    out = [Parameter("trials", "int", "Monte Carlo trials", dict(trials), minimum=2),
           Parameter("particles", "int", "particles of the fusion centre's filter",
                     dict(particles), minimum=10)]
    if N is not None:
        out.append(Parameter("N", "int", "number of sensors (the paper's scalar sensors, "
                             "h = (1, 0), r = 1)", N, minimum=1, maximum=64, model=True))
    if l is not None:
        out.append(Parameter("l", "float", "target number of transmissions per step", l,
                             minimum=0.0, exclusive_minimum=True,
                             at_most="N" if N is not None else None, model=True))
    return tuple(out)


def run_size(profile: str, trials: dict, particles: dict, over: dict) -> tuple[int, int]:
    """Trials and particles of a run.

    Parameters
    ----------
    profile : str
        ``fast`` or ``paper``.
    trials, particles : dict
        The profile defaults.
    over : dict
        The overrides of the run (keys ``trials`` and ``particles`` win if present).

    Returns
    -------
    tuple of int
        ``(trials, particles)``.

    Raises
    ------
    ValueError
        If one block of trials of the particle filter would need more memory than the
        machine has (the message names ``particles`` and gives the estimate); the memory of
        the trials' results is checked by :func:`fusioncenter.montecarlo.simulate`.
    """
    n = over.get("trials") or by_profile(profile, **trials)
    P = over.get("particles") or by_profile(profile, **particles)
    check_block(P, min(n, montecarlo.DEFAULT_BLOCK_SIZE))
    return n, P


def check_block(P: int, block: int, per_particle: int = 0) -> int:
    """Check that a block of the particle filter fits in memory.

    Parameters
    ----------
    P, block, per_particle : int
        Particles, trials of a block, bytes a particle and trial (0: :data:`PARTICLE_BYTES`).

    Returns
    -------
    int
        ``P``; a ``ValueError`` naming ``particles`` with the estimate if it does not fit.
    """
    montecarlo.check_memory("particles", P, block * P * (per_particle or PARTICLE_BYTES),
                            f"the particle filter's arrays for a block of {block} trials")
    return P


#: Bytes the particle filter holds per particle and trial of a block, about (states, their
#: copy and noise for resampling and prediction, ancestors, weights: ten doubles).
PARTICLE_BYTES = 80


def run_scheme(sc, scheme: str, *, feedback: str, l: float, n: int, P: int, seed: int,
               likelihood: str = "corrected", executor=None,
               chunk_size: int | None = None) -> cs.CensoringResult:
    """One run of an entry: :func:`fusioncenter.censoring.run` under short names.

    Parameters
    ----------
    sc : LinearScenario or VectorScenario
        The scenario (a vector one is handed to the vector filter).
    scheme, feedback, l, likelihood, executor, chunk_size
        As in :func:`fusioncenter.censoring.run`.
    n, P : int
        Trials and particles.
    seed : int
        The seed (the same for every run of an entry: its runs share their trials).

    Returns
    -------
    CensoringResult
    """
    return cs.run(sc, scheme, l=l, n_trials=n, n_particles=P, seed=seed, feedback=feedback,
                  likelihood=likelihood, executor=executor, chunk_size=chunk_size)


def subset(res: cs.CensoringResult, n: int) -> cs.CensoringResult:
    """The first ``n`` trials of a run (whole blocks: the same trials as a run of ``n``).

    Parameters
    ----------
    res : CensoringResult
        A run.
    n : int
        The number of trials kept: ``res``'s own, or a multiple of its block size.

    Returns
    -------
    CensoringResult
        ``res`` itself if ``n`` is its number of trials, else a copy with the first ``n``.
    """
    if n == res.mc.n_trials:
        return res
    if n % res.mc.block_size:
        raise ValueError(f"n must be a multiple of the block size {res.mc.block_size}, got {n}")
    mc = montecarlo.MonteCarloResult(samples=res.mc.samples[:n], seed=res.mc.seed,
                                     block_size=res.mc.block_size)
    return dataclasses.replace(res, mc=mc)


def curves(res: cs.CensoringResult) -> dict:
    """The summaries of one run, under short keys.

    Parameters
    ----------
    res : CensoringResult
        A run.

    Returns
    -------
    dict
        ``rp, rpe, rv, rve`` (position and velocity RMSE against time, with stderrs), ``tp,
        tpe, tv, tve`` (their time averages), ``tr, tre`` (transmissions per step) and ``col``
        (collapsed steps).
    """
    p, v = res.rmse_position, res.rmse_velocity
    tp, tpe = res.time_averaged_rmse("position")
    tv, tve = res.time_averaged_rmse("velocity")
    tr, tre = res.average_transmissions
    return {"rp": p.value, "rpe": p.stderr, "rv": v.value, "rve": v.stderr, "tp": tp,
            "tpe": tpe, "tv": tv, "tve": tve, "tr": tr, "tre": tre, "col": res.collapsed}


def stack(cur: list[dict], key: str) -> np.ndarray:
    """One row per run.

    Parameters
    ----------
    cur : list of dict
        The :func:`curves` of several runs.
    key : str
        One of their keys.

    Returns
    -------
    numpy.ndarray
        The values of ``key``, stacked along a first axis.
    """
    return np.array([c[key] for c in cur])


def stacked(cur: list[dict], *, velocity_average: bool = True) -> dict:
    """The curves of several runs as data keys, one row per run.

    Parameters
    ----------
    cur : list of dict
        The :func:`curves` of the runs.
    velocity_average : bool
        Whether to include the time-averaged velocity RMSE.

    Returns
    -------
    dict
        ``rmse_position``, ``rmse_velocity`` (against time), ``tavg_position`` (and
        ``tavg_velocity``), ``transmissions``, each with its ``_stderr``.
    """
    out = {"rmse_position": stack(cur, "rp"), "rmse_position_stderr": stack(cur, "rpe"),
           "rmse_velocity": stack(cur, "rv"), "rmse_velocity_stderr": stack(cur, "rve"),
           "tavg_position": stack(cur, "tp"), "tavg_position_stderr": stack(cur, "tpe")}
    if velocity_average:
        out |= {"tavg_velocity": stack(cur, "tv"), "tavg_velocity_stderr": stack(cur, "tve")}
    return out | {"transmissions": stack(cur, "tr"), "transmissions_stderr": stack(cur, "tre")}


def printed_max_abs_diff(by: dict) -> float:
    """How far CFwMD with the no-feedback likelihood as printed is from CFoMD.

    Parameters
    ----------
    by : dict
        Runs by name, with ``printed`` and ``cfomd`` on the same trials.

    Returns
    -------
    float
        The largest difference of their squared errors.
    """
    return float(np.max(np.abs(by["printed"].mc.samples[..., :2]
                               - by["cfomd"].mc.samples[..., :2])))


def z_claim_ordered(name: str, pairs, diff, se) -> Claim:
    """The claim that each paired difference ``diff`` (better minus worse) is negative by more
    than :data:`Z_ORDER` standard errors.

    Parameters
    ----------
    name : str
        The claim's name.
    pairs : sequence of (str, str)
        The names of the pairs (for the detail).
    diff, se : array_like
        The paired differences and their standard errors.

    Returns
    -------
    Claim
    """
    z = -np.asarray(diff) / np.asarray(se)
    detail = "; ".join(f"{a} − {b} = {d:+.4f} ± {s:.4f} (z = {zz:.1f})"
                       for (a, b), d, s, zz in zip(pairs, diff, se, z, strict=True))
    return Claim(name, bool(np.all(z > Z_ORDER)), detail)


def pick_pairs(names: list, diff, se, *want) -> tuple:
    """The pairs ``want`` out of ``names``, with their differences and standard errors.

    Parameters
    ----------
    names : list of (str, str)
        The pairs of the data.
    diff, se : numpy.ndarray
        Their differences and standard errors, in the same order.
    *want : (str, str)
        The pairs to keep.

    Returns
    -------
    tuple
        ``(pairs, diff, se)`` of the pairs kept (the arguments of :func:`z_claim_ordered`).
    """
    idx = [names.index(w) for w in want]
    return [names[i] for i in idx], diff[idx], se[idx]


def pair_differences(by: dict, pairs) -> tuple:
    """Paired differences of the time-averaged RMSE.

    Parameters
    ----------
    by : dict
        Runs by name, on the same trials.
    pairs : sequence of (str, str)
        The pairs ``(a, b)``: each difference is ``by[a] - by[b]``.

    Returns
    -------
    tuple of numpy.ndarray
        ``(diff, stderr)`` of the position, then of the velocity.
    """
    dp = [cs.paired_difference(by[a], by[b], "position") for a, b in pairs]
    dv = [cs.paired_difference(by[a], by[b], "velocity") for a, b in pairs]
    return (np.array([d for d, _ in dp]), np.array([s for _, s in dp]),
            np.array([d for d, _ in dv]), np.array([s for _, s in dv]))


def schemes_data(runs, N: int, l: float) -> dict:
    """The data of a figure of the four :data:`SCHEMES` with state feedback (Figs. 1 and 4).

    Parameters
    ----------
    runs : sequence of CensoringResult
        One run per scheme, in the order of :data:`SCHEMES`, on the same trials.
    N : int
        The number of sensors.
    l : float
        The target number of transmissions per step.

    Returns
    -------
    dict
        The curves of :func:`stacked`, the paired differences of consecutive schemes in the
        order all-send < CFwMD < CFoMD < random, ``collapsed``, ``n_trials``, ``n_particles``,
        ``N``, ``l`` and ``eta``.
    """
    cur = [curves(r) for r in runs]
    pairs = [("all-send", "cfwmd"), ("cfwmd", "cfomd"), ("cfomd", "random")]
    dp, sp, dv, sv = pair_differences(dict(zip(SCHEMES, runs, strict=True)), pairs)
    return {
        "time": runs[0].time.astype(float), "schemes": np.array(SCHEMES),
        **stacked(cur),
        "pairs": np.array(pairs), "pair_diff_position": dp, "pair_stderr_position": sp,
        "pair_diff_velocity": dv, "pair_stderr_velocity": sv,
        "collapsed": stack(cur, "col"),
        "n_trials": runs[0].mc.n_trials, "n_particles": runs[0].n_particles,
        "N": N, "l": l, "eta": runs[-1].eta,
    }


def by_l_runs(run: Callable, sc, ls, **kw) -> tuple:
    """CFwMD with state feedback and with state and covariance feedback at every ``l``.

    Parameters
    ----------
    run : callable
        ``run(sc, "cfwmd", feedback=..., l=..., **kw)`` returns a run (:func:`run_scheme`).
    sc : Scenario
        The scenario.
    ls : sequence of float
        The targets ``l``.
    **kw
        The other arguments of ``run`` (trials, particles, seed, executor).

    Returns
    -------
    tuple
        ``(CFwMD runs, CFwMD2 runs)``, one per ``l``.
    """
    return tuple(tuple(run(sc, "cfwmd", feedback=fb, l=l, **kw) for l in ls)
                 for fb in ("state", "state+cov"))


def by_l_data(a, b, ls, N: int, **extra) -> dict:
    """The data of a figure of CFwMD against CFwMD2 at every ``l`` (Figs. 2 and 5).

    Parameters
    ----------
    a, b : sequence of CensoringResult
        The CFwMD and the CFwMD2 runs, one per ``l``, on the same trials.
    ls : sequence of float
        The targets ``l``.
    N : int
        The number of sensors.
    **extra
        More data keys.

    Returns
    -------
    dict
        ``time``, ``l``, the position RMSE and its time average (shape ``(2, len(ls), ...)``),
        ``diff`` and ``diff_stderr`` (CFwMD2 minus CFwMD, paired), ``extra``, ``n_trials``,
        ``n_particles`` and ``N``.
    """
    ca, cb = [curves(r) for r in a], [curves(r) for r in b]
    diff, dse = [], []
    for ra, rb in zip(a, b, strict=True):
        d, s = cs.paired_difference(rb, ra)
        diff.append(d)
        dse.append(s)
    return {
        "time": a[0].time.astype(float), "l": np.array(ls),
        "rmse_position": np.array([stack(ca, "rp"), stack(cb, "rp")]),
        "rmse_position_stderr": np.array([stack(ca, "rpe"), stack(cb, "rpe")]),
        "tavg_position": np.array([stack(ca, "tp"), stack(cb, "tp")]),
        "tavg_position_stderr": np.array([stack(ca, "tpe"), stack(cb, "tpe")]),
        "diff": np.array(diff), "diff_stderr": np.array(dse), **extra,
        "n_trials": a[0].mc.n_trials, "n_particles": a[0].n_particles, "N": N,
    }


def closer_z(a, b, l) -> list[float]:
    """How much closer to ``l`` CFwMD2 sends than CFwMD, in paired standard errors.

    Parameters
    ----------
    a, b : sequence of CensoringResult
        The CFwMD and the CFwMD2 runs, one per ``l``.
    l : sequence of float
        The targets.

    Returns
    -------
    list of float
        For every ``l``: ``|CFwMD - l| - |CFwMD2 - l|`` (transmissions per step) over its
        paired standard error (per-trial time averages).
    """
    closer = []
    for ra, rb, li in zip(a, b, l, strict=True):
        sa = ra.mc.samples[..., ra.scenario.d].mean(axis=1)
        sb = rb.mc.samples[..., rb.scenario.d].mean(axis=1)
        da, db = sa.mean() - li, sb.mean() - li
        per = np.sign(da) * (sa - li) - np.sign(db) * (sb - li)
        closer.append((abs(da) - abs(db)) / (per.std(ddof=1) / math.sqrt(per.size)))
    return closer


def transmissions_data(a, b, ls, paper: dict, N: int) -> dict:
    """Transmissions per step of CFwMD and CFwMD2 next to a paper's table (Tables I, II).

    Parameters
    ----------
    a, b : sequence of CensoringResult
        The CFwMD and the CFwMD2 runs, one per ``l``.
    ls : sequence of float
        The targets ``l``.
    paper : dict
        The printed values, under ``cfwmd`` and ``cfwmd2``.
    N : int
        The number of sensors.

    Returns
    -------
    dict
        ``l``, ``cfwmd``, ``cfwmd2`` (with ``_stderr``), ``paper_cfwmd``, ``paper_cfwmd2``,
        ``z_cfwmd``, ``z_cfwmd2`` (ours minus printed over sqrt(2) stderr), ``closer_z``
        (:func:`closer_z`), ``n_trials``, ``n_particles`` and ``N``.
    """
    l = np.array(ls)
    ta = np.array([r.average_transmissions for r in a])
    tb = np.array([r.average_transmissions for r in b])
    pa, pb = np.array(paper["cfwmd"]), np.array(paper["cfwmd2"])
    return {
        "l": l, "cfwmd": ta[:, 0], "cfwmd_stderr": ta[:, 1], "cfwmd2": tb[:, 0],
        "cfwmd2_stderr": tb[:, 1], "paper_cfwmd": pa, "paper_cfwmd2": pb,
        "z_cfwmd": (ta[:, 0] - pa) / (math.sqrt(2) * ta[:, 1]),
        "z_cfwmd2": (tb[:, 0] - pb) / (math.sqrt(2) * tb[:, 1]),
        "closer_z": np.array(closer_z(a, b, l)),
        "n_trials": a[0].mc.n_trials, "n_particles": a[0].n_particles, "N": N,
    }


# ------------------------------------------------------------------------- claims
@checks_doc("The ordering all-send < CFwMD < CFoMD < random (position and velocity, "
            "paired), the transmission rates of random selection and of the censoring schemes, "
            "no collapse.", data="The data of :func:`schemes_data`.")
def checks_schemes(data: dict) -> list[Claim]:
    """The statements on Fig. 1, which the paper makes of Fig. 4 too (vector observations).

    The entries of both figures use it as their ``checks``.
    """
    pairs = [tuple(p) for p in data["pairs"]]
    tr, tre = data["transmissions"], data["transmissions_stderr"]
    sch = list(data["schemes"])
    z_rand = abs(tr[sch.index("random")] - data["l"]) / tre[sch.index("random")]
    cens = [tr[sch.index("cfwmd")], tr[sch.index("cfomd")]]
    return [
        z_claim_ordered("time-averaged position RMSE: all-send < CFwMD < CFoMD < random "
                        "selection (paired differences)", pairs,
                        data["pair_diff_position"], data["pair_stderr_position"]),
        z_claim_ordered("time-averaged velocity RMSE: all-send < CFwMD < CFoMD < random "
                        "selection (paired differences)", pairs,
                        data["pair_diff_velocity"], data["pair_stderr_velocity"]),
        Claim("random selection sends l sensors per step on average",
              bool(z_rand < Z_TOL), f"{tr[sch.index('random')]:.4f} (z = {z_rand:.2f})"),
        Claim("the censoring schemes save about half of the transmissions: within 10 % of "
              "l = 1 per step (with state feedback the design rate holds only approximately, "
              "Remark 1 (III))",
              bool(all(abs(c - data["l"]) < 0.1 * data["l"] for c in cens)),
              f"CFwMD {cens[0]:.4f}, CFoMD {cens[1]:.4f} per step"),
        Claim("no step lost its data to a collapse of the weights",
              bool(np.all(data["collapsed"] == 0)), "collapsed (trial, step) pairs: " + ", ".join(
                  f"{LABELS[str(s)]} {int(n)}" for s, n in zip(sch, data["collapsed"],
                                                             strict=True))),
    ]


@document(returns=("fusioncenter.figures.registry.Claim", "Its detail lists the time-averaged "
                   "position RMSE of both at every ``l``."), raises=(),
          data="The data of :func:`by_l_data`.")
def claim_rmse_decreases(data: dict) -> Claim:
    """The claim that the RMSE of CFwMD and of CFwMD2 decreases as ``l`` grows (Figs. 2, 5)."""
    return Claim("the RMSE of both schemes decreases as l grows",
                 bool(np.all(np.diff(data["tavg_position"], axis=1) < 0)),
                 "CFwMD " + ", ".join(f"{v:.3f}" for v in data["tavg_position"][0])
                 + "; CFwMD2 " + ", ".join(f"{v:.3f}" for v in data["tavg_position"][1]))


# ------------------------------------------------------------------------- plots
def log_y(ax) -> None:
    """A log y axis with plain tick labels at 1, 2, 5 x 10^k (and 1.5, 3, 7 between).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The axes.

    Returns
    -------
    None
    """
    ax.set_yscale("log")
    ax.yaxis.set_major_locator(matplotlib.ticker.LogLocator(base=10.0, subs=(1.0, 2.0, 5.0)))
    ax.yaxis.set_minor_locator(matplotlib.ticker.LogLocator(base=10.0, subs=(1.5, 3.0, 7.0)))
    fmt = matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}")
    ax.yaxis.set_major_formatter(fmt)
    ax.yaxis.set_minor_formatter(fmt)


def rmse_panels(data: dict, names, labels):
    """Position and velocity RMSE against time, one curve per name, on log axes.

    Parameters
    ----------
    data : dict
        With ``time``, ``rmse_position``, ``rmse_velocity`` and their ``_stderr`` (one row per
        name).
    names : list of str
        The curves' names, in the rows' order.
    labels : dict
        Their legend labels.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, axes = plotting.subplots(1, 2, stack=True)
    t = data["time"]
    for name in names:
        kw = plotting.look(name, markersize=4)
        plotting.errorband(axes[0], t, data["rmse_position"][names.index(name)],
                           data["rmse_position_stderr"][names.index(name)], label=labels[name],
                           **kw)
        plotting.errorband(axes[1], t, data["rmse_velocity"][names.index(name)],
                           data["rmse_velocity_stderr"][names.index(name)], label=labels[name],
                           **kw)
    axes[0].set(xlabel="time (s)", ylabel="position RMSE (m)", title="(a) position")
    axes[1].set(xlabel="time (s)", ylabel="velocity RMSE (m/s)", title="(b) velocity")
    for ax in axes:
        log_y(ax)
        ax.set_xticks([1, 5, 10, 15, 20])
    axes[0].legend(ncol=2)
    return fig


def by_l_panels(data: dict, *, l_ticks: bool = False):
    """CFwMD against CFwMD2 at every ``l`` (Figs. 2 and 5).

    Parameters
    ----------
    data : dict
        The data of :func:`by_l_data`.
    l_ticks : bool
        Whether the x ticks of the last panel are the ``l`` values.

    Returns
    -------
    matplotlib.figure.Figure
        The position RMSE against time, one curve per ``l``, of (a) CFwMD and (b) CFwMD2;
        (c) their time averages against ``l``.
    """
    fig, (ax1, ax1b, ax2) = plotting.subplots(3, 1, stack=True)
    t = data["time"]
    for j, (ax, name, letter) in enumerate(((ax1, "cfwmd", "a"), (ax1b, "cfwmd2", "b"))):
        shades = matplotlib.colormaps["viridis"](np.linspace(0.0, 0.85, len(data["l"])))
        for i, l in enumerate(data["l"]):  # an ordered parameter: a sequential palette
            ax.plot(t, data["rmse_position"][j, i], color=shades[i],
                    ls=plotting.SCHEMES[name]["linestyle"], label=f"l = {l:g}")
        ax.set(xlabel="time (s)", ylabel="position RMSE (m)",
               title=f"({letter}) {LABELS[name]}, N = {data['N']}, by l")
        ax.legend(ncol=5)
    lo = min(ax1.get_ylim()[0], ax1b.get_ylim()[0])
    hi = max(ax1.get_ylim()[1], ax1b.get_ylim()[1])
    for ax in (ax1, ax1b):
        ax.set_ylim(lo, hi)
    for j, name in enumerate(("cfwmd", "cfwmd2")):
        ax2.errorbar(data["l"], data["tavg_position"][j],
                     yerr=1.96 * data["tavg_position_stderr"][j], capsize=3,
                     label=LABELS[name], **plotting.look(name))
    ax2.set(xlabel="target number of transmissions per step l (-)",
            ylabel="time-averaged position RMSE (m)", title="(c) time average, 95 % bars")
    if l_ticks:
        ax2.set_xticks(data["l"])
    ax2.legend(ncol=2)
    return fig


def transmissions_plot(data: dict, labels: dict, table: str, title: str, *,
                       l_ticks: bool = False):
    """Transmissions per step minus ``l`` of CFwMD and CFwMD2 against ``l``, with the paper's.

    Parameters
    ----------
    data : dict
        The data of :func:`transmissions_data`.
    labels : dict
        Legend labels of ``cfwmd`` and ``cfwmd2``.
    table : str
        The paper's number of the table (``"I"``).
    title : str
        The axes' title.
    l_ticks : bool
        Whether the x ticks are the ``l`` values.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = plotting.subplots(stack=True)
    l = data["l"]
    for name in ("cfwmd", "cfwmd2"):
        ax.errorbar(l, data[name] - l, yerr=1.96 * data[f"{name}_stderr"], capsize=3,
                    label=f"{labels[name]} (ours)", **plotting.look(name))
        ax.plot(l, data[f"paper_{name}"] - l, label=f"{labels[name]} (paper, Table {table})",
                **plotting.look(name, "paper"))
    ax.axhline(0.0, color="0.4", lw=0.8, ls=":", label="target: l per step")
    if l_ticks:
        ax.set_xticks(l)
    ax.set(xlabel="target number of transmissions per step l (-)",
           ylabel="transmissions per step minus l (-)", title=title)
    ax.legend(ncol=2)
    return plotting.finish(fig)


# ------------------------------------------------------------------------- registration
def add_entry(entry_id: str, kind: str, status: str, functions: tuple, **fields) -> Entry:
    """Register an entry of zheng2014, labelled ``sec-<id>`` in its chapter.

    Parameters
    ----------
    entry_id : str
        The id (``zheng2014-...``).
    kind : str
        ``figure`` or ``table``.
    status : str
        ``reproduced`` or ``differs``.
    functions : tuple
        ``(compute, plot, checks)``.
    **fields
        The other fields of :class:`~fusioncenter.figures.registry.Entry` (``caption``,
        ``chapter``, ``parameters``, ``settable``, ``note``, ...).

    Returns
    -------
    Entry
        The registered entry.
    """
    compute, plot, checks = functions
    return register(Entry(id=entry_id, paper="zheng2014", kind=kind, label=f"sec-{entry_id}",
                          compute=compute, plot=plot, checks=checks, status=status, **fields))
