"""How the entries of Part IV (zheng2014) compare schemes run on the same trials.

* paired differences of the time-averaged RMSE (:func:`pair_differences`, :func:`pick_pairs`)
  and the claim that an ordering holds (:func:`z_claim_ordered`);
* the data of the figure groups the scalar and vector settings share: the four
  :data:`~fusioncenter.figures.zheng2014.common.SCHEMES` with state feedback (Figs. 1 and 4,
  :func:`schemes_data`, checked by :func:`checks_schemes`) and CFwMD against CFwMD2 at every
  ``l`` (Figs. 2-3, 5-6 and Tables I-II: :func:`by_l_runs`, :func:`by_l_data`,
  :func:`closer_z`, :func:`transmissions_data`, :func:`claim_rmse_decreases`).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from fusioncenter import censoring as cs
from fusioncenter.figures.common import checks_doc, document
from fusioncenter.figures.registry import Claim
from fusioncenter.figures.zheng2014.common import (
    LABELS,
    SCHEMES,
    Z_ORDER,
    Z_TOL,
    curves,
    stack,
    stacked,
)


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
    than :data:`~fusioncenter.figures.zheng2014.common.Z_ORDER` standard errors.

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
    """The data of a figure of the four schemes with state feedback (Figs. 1 and 4).

    Parameters
    ----------
    runs : sequence of CensoringResult
        One run per scheme, in the order of
        :data:`~fusioncenter.figures.zheng2014.common.SCHEMES`, on the same trials.
    N : int
        The number of sensors.
    l : float
        The target number of transmissions per step.

    Returns
    -------
    dict
        The curves of :func:`~fusioncenter.figures.zheng2014.common.stacked`, the paired
        differences of consecutive schemes in the order all-send < CFwMD < CFoMD < random,
        ``collapsed``, ``n_trials``, ``n_particles``, ``N``, ``l`` and ``eta``.
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
        ``run(sc, "cfwmd", feedback=..., l=..., **kw)`` returns a run
        (:func:`~fusioncenter.figures.zheng2014.common.run_scheme`).
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

