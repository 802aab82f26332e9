"""zheng2014's results read across its three settings (scalar, vector, nonlinear).

Compute only (plain NumPy data and :class:`~fusioncenter.figures.registry.Claim` lists, no
plotting). The inputs are the ``compute`` outputs of the registry entries: Tables I-III
(``zheng2014-table1``, ``-table2``, ``-table3``) and the four-scheme figures (``zheng2014-fig1``,
``-fig3``, ``-fig4``, ``-fig6``, ``-fig8``, ``-fig9``). :func:`load_tables` and
:func:`load_payoff` compute them through the registry; the other functions take them as given,
so that the tests can feed corrupted data.

Entry points (signature, one line each):

* ``delta_bound(gradient, stderr) -> float``: an upper bound on a delta-method standard error
  when only the marginal standard errors of the inputs are known.
* ``variance_ratio(sent, sent_se, l, N, dof=1) -> (v, v_se)``: the innovation variance, in units
  of the sensors' own normalizer, that makes ``sent`` of ``N`` sensors send at threshold
  ``censoring.threshold(l, N, dof)``.
* ``bandwidth_table(data, *, paper_trials, N, dof)``: one table (I, II or III) in a common form;
  ``side_by_side(tables, meta)`` all three; ``load_tables(profile, seed=None)`` from the registry.
* ``bandwidth_claims(tables) -> list[Claim]``: the paper's statements about the tables, and
  the differences of ours from the printed values, checked on the data.
* ``payoff_rows(data) -> list[dict]``: what CFwMD wins back against CFoMD, all-send and random
  selection, one row per setting; ``gain_by_l(fig9)``: the nonlinear gain as ``l`` grows;
  ``load_payoff(profile, seed=None)`` both from the registry; ``payoff_claims(rows, sweep)``.

Standard errors of combined estimates. The registry gives paired standard errors of single
differences (for example CFoMD minus CFwMD, and CFwMD minus all-send), not their covariances. A
smooth function ``f`` of such estimates has the delta-method variance ``g^T C g`` (``g`` the
gradient, ``C`` the covariance); since ``|C_ij| <= se_i se_j`` (Cauchy-Schwarz),
``g^T C g <= (sum_i |g_i| se_i)^2`` whatever the correlations. :func:`delta_bound` returns that
bound: a conservative standard error.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np
import scipy.stats

from fusioncenter import censoring
from fusioncenter._validate import posint as _posint
from fusioncenter.figures.registry import Claim

__all__ = [
    "SETTINGS",
    "TABLE_IDS",
    "TABLE_NAMES",
    "SCHEMES",
    "Z_ORDER",
    "Z_AGREE",
    "delta_bound",
    "variance_ratio",
    "bandwidth_table",
    "side_by_side",
    "table_meta",
    "load_tables",
    "bandwidth_claims",
    "PAYOFF_IDS",
    "payoff_rows",
    "gain_by_l",
    "load_payoff",
    "payoff_claims",
]

#: The three settings of Section VII, in the paper's order.
SETTINGS = ("scalar", "vector", "nonlinear")
#: The registry entry of each setting's table of transmissions.
TABLE_IDS = {"scalar": "zheng2014-table1", "vector": "zheng2014-table2",
             "nonlinear": "zheng2014-table3"}
TABLE_NAMES = {"scalar": "Table I", "vector": "Table II", "nonlinear": "Table III"}
#: The two feedback schemes of the tables, in their order in the arrays below.
SCHEMES = ("cfwmd", "cfwmd2")
#: A difference counts as an ordering when it exceeds Z_ORDER (conservative) standard errors.
Z_ORDER = 4.0
#: Agreement with a printed value: |z| below Z_AGREE.
Z_AGREE = 4.0


# ------------------------------------------------------------------------- error arithmetic
def delta_bound(gradient: Sequence[float], stderr: Sequence[float]) -> float:
    """An upper bound on a delta-method standard error, valid for any correlation.

    Parameters
    ----------
    gradient : sequence of float
        The gradient ``g`` of the smooth function ``f`` at the estimates ``x``.
    stderr : sequence of float
        The marginal standard errors ``se_i`` of the estimates (finite, non-negative), one per
        entry of ``gradient``.

    Returns
    -------
    float
        ``sum_i |g_i| se_i``, which is at least ``sqrt(g^T C g)`` whatever the covariance ``C``
        of the estimates.

    Raises
    ------
    ValueError
        If the two are not 1-d of one length, or a standard error is negative or not finite.
    """
    g = np.asarray(gradient, dtype=float)
    s = np.asarray(stderr, dtype=float)
    if g.shape != s.shape or g.ndim != 1:
        raise ValueError(f"gradient and stderr must be 1-d of one length, got shapes {g.shape} "
                         f"and {s.shape}")
    if np.any(s < 0) or not np.all(np.isfinite(s)):
        raise ValueError("stderr must be finite and non-negative")
    return float(np.sum(np.abs(g) * s))


def variance_ratio(sent, sent_se, l, N: int, dof: int = 1):
    """The innovation variance that makes ``sent`` of ``N`` sensors send at the threshold for ``l``.

    ``v`` is in units of the normalizer the sensors divide by. If a sensor's normalized
    innovation squared is ``v`` times a ``chi2_dof`` variable, it sends with probability
    ``P(chi2_dof >= eta / v)``; setting that to ``sent / N`` gives
    ``v = eta / chi2_dof.isf(sent / N)``. ``v = 1`` is the design; ``v < 1`` means the innovations
    are narrower than the sensors assume, and fewer than ``l`` send. For a vector innovation
    ``v`` is the isotropic equivalent. Arrays broadcast.

    Parameters
    ----------
    sent : array_like
        Measured average number of transmissions per step, in ``(0, N)``.
    sent_se : array_like
        Its standard error (0 for a printed value).
    l : array_like
        The target number of transmissions the threshold was designed for, in ``(0, N)``.
    N : int
        Number of sensors.
    dof : int, default 1
        Dimension of a sensor's innovation (the degrees of freedom of the chi-square law).

    Returns
    -------
    v : numpy.ndarray
        The variance ratio, broadcast shape of the inputs.
    v_se : numpy.ndarray
        Its standard error by the delta method from ``sent_se``.

    Raises
    ------
    ValueError
        If ``N`` is not a positive integer or ``l`` or ``sent`` lie outside ``(0, N)``.
    """
    N = _posint("N", N)
    sent, sent_se, l = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in
                                             (sent, sent_se, l)))
    if np.any((l <= 0) | (l >= N)):
        raise ValueError(f"l must lie in (0, N) = (0, {N}) (at l = N the threshold is 0)")
    if np.any((sent <= 0) | (sent >= N)):
        raise ValueError(f"sent (average transmissions per step) must lie in (0, {N})")
    eta = np.vectorize(lambda x: censoring.threshold(float(x), N, dof))(l)
    q = scipy.stats.chi2.isf(sent / N, dof)
    v = eta / q
    # dv/d(sent) = eta / (q^2 pdf(q)) / N, since dq/d(rate) = -1 / pdf(q)
    dv = eta / (q**2 * scipy.stats.chi2.pdf(q, dof)) / N
    return v, np.abs(dv) * sent_se


# ------------------------------------------------------------------------- Tables I-III
def bandwidth_table(data: Mapping, *, paper_trials: int, N: int, dof: int) -> dict:
    """One of the registry's tables of transmissions (I, II or III) in a common form.

    Parameters
    ----------
    data : mapping
        The ``compute`` output of ``zheng2014-table1``, ``-table2`` (keys ``cfwmd``,
        ``paper_cfwmd``, ``closer_z``, ``n_trials``, ...) or ``-table3``
        (``cfwmd_transmissions``, ``printed_cfwmd``, ``closer``, ``closer_stderr``, ``trials``).
    paper_trials : int
        The paper's number of Monte Carlo trials for this table (keyword-only).
    N : int
        Number of sensors.
    dof : int
        Dimension of a sensor's innovation.

    Returns
    -------
    dict
        Keys below; arrays ``(2, L)`` have rows CFwMD, CFwMD2.

    Raises
    ------
    ValueError
        If ``data`` is none of the three tables, or its arrays have the wrong shape, are not
        finite, or have non-positive standard errors.

    Notes
    -----
    Keys of the result:

    * ``l`` (L,); ``ours``, ``stderr``, ``printed`` (2, L): transmissions per step;
    * ``diff`` = ours - printed; ``paper_stderr`` (2, L): the printed values' Monte Carlo error,
      estimated as ours scaled to the paper's trial count (per-trial spread assumed equal);
      ``z_printed`` = diff / hypot(stderr, paper_stderr);
    * ``closer`` (L,) = |CFwMD - l| - |CFwMD2 - l| (> 0: CFwMD2 meets l more closely),
      ``closer_stderr`` and ``closer_z`` (paired over trials, from the entry);
      ``printed_closer`` the same for the printed values, and ``closer_vs_printed_z`` the z-score
      of ours minus the printed one;
    * ``v``, ``v_stderr`` (2, L): :func:`variance_ratio` of ours, ``v_printed`` of the printed;
    * ``n_trials``, ``paper_trials``, ``N``, ``dof``.
    """
    paper_trials = _posint("paper_trials", paper_trials)
    if "cfwmd_transmissions" in data:  # zheng2014-table3
        ours = [data[f"{s}_transmissions"] for s in SCHEMES]
        se = [data[f"{s}_transmissions_stderr"] for s in SCHEMES]
        printed = [data[f"printed_{s}"] for s in SCHEMES]
        n = data["trials"]
        closer_z = np.asarray(data["closer"], float) / np.asarray(data["closer_stderr"], float)
    elif "paper_cfwmd" in data:  # zheng2014-table1, zheng2014-table2
        ours = [data[s] for s in SCHEMES]
        se = [data[f"{s}_stderr"] for s in SCHEMES]
        printed = [data[f"paper_{s}"] for s in SCHEMES]
        n = data["n_trials"]
        closer_z = np.asarray(data["closer_z"], float)
    else:
        raise ValueError("data must be the compute output of zheng2014-table1, -table2 or "
                         "-table3 (no 'cfwmd_transmissions' or 'paper_cfwmd' key)")
    n = _posint("n_trials", int(n))
    l = np.asarray(data["l"], dtype=float)
    ours, se, printed = (np.array(a, dtype=float) for a in (ours, se, printed))
    for name, arr in (("transmissions", ours), ("stderr", se), ("printed", printed)):
        if arr.shape != (2, l.size):
            raise ValueError(f"{name} must have shape (2, {l.size}), got {arr.shape}")
        if not np.all(np.isfinite(arr)):
            raise ValueError(f"{name} must be finite")
    if np.any(se <= 0):
        raise ValueError("standard errors must be positive")
    if closer_z.shape != l.shape:
        raise ValueError(f"closer_z must have shape {l.shape}, got {closer_z.shape}")
    scale = math.sqrt(n / paper_trials)
    paper_se = se * scale
    closer = np.abs(ours[0] - l) - np.abs(ours[1] - l)
    with np.errstate(divide="ignore", invalid="ignore"):
        closer_se = np.where(closer_z != 0, np.abs(closer / closer_z), np.nan)
    printed_closer = np.abs(printed[0] - l) - np.abs(printed[1] - l)
    v, v_se = variance_ratio(ours, se, l, N, dof)
    v_printed, _ = variance_ratio(printed, 0.0, l, N, dof)
    return {
        "l": l, "ours": ours, "stderr": se, "printed": printed, "diff": ours - printed,
        "paper_stderr": paper_se, "z_printed": (ours - printed) / np.hypot(se, paper_se),
        "closer": closer, "closer_stderr": closer_se, "closer_z": closer_z,
        "printed_closer": printed_closer,
        "closer_vs_printed_z": (closer - printed_closer) / (closer_se * math.hypot(1, scale)),
        "v": v, "v_stderr": v_se, "v_printed": v_printed,
        "n_trials": n, "paper_trials": paper_trials, "N": int(N), "dof": int(dof),
    }


def side_by_side(tables: Mapping[str, Mapping], meta: Mapping[str, Mapping]) -> dict[str, dict]:
    """:func:`bandwidth_table` of each of the three settings.

    Parameters
    ----------
    tables : mapping of str to mapping
        ``tables[setting]`` is the ``compute`` output of the setting's table entry
        (:data:`TABLE_IDS`), for every setting of :data:`SETTINGS`.
    meta : mapping of str to mapping
        ``meta[setting]`` holds ``paper_trials``, ``N`` and ``dof`` (see :func:`table_meta`).

    Returns
    -------
    dict of str to dict
        The :func:`bandwidth_table` of each setting, keyed by setting.

    Raises
    ------
    ValueError
        If a setting is missing from ``tables`` or ``meta``.
    """
    missing = [s for s in SETTINGS if s not in tables or s not in meta]
    if missing:
        raise ValueError(f"tables and meta need the settings {SETTINGS}; missing {missing}")
    return {s: bandwidth_table(tables[s], **meta[s]) for s in SETTINGS}


def table_meta() -> dict[str, dict]:
    """The paper's trial count, ``N`` and the innovation's dimension for each table.

    They are read from the registry modules (Sections VII.A and VII.B: 5000 trials, N = 4;
    VII.C: 200 trials, N = 9).

    Returns
    -------
    dict of str to dict
        For each setting of :data:`SETTINGS`, the keyword arguments ``paper_trials``, ``N``
        and ``dof`` of :func:`bandwidth_table`.
    """
    from fusioncenter.figures.zheng2014 import linear, nonlinear, vector

    return {
        "scalar": {"paper_trials": linear.TRIALS_FIG2["paper"], "N": linear.FIG2["N"],
                   "dof": 1},
        "vector": {"paper_trials": vector.TRIALS_FIG5["paper"], "N": vector.FIG5["N"],
                   "dof": 2},
        "nonlinear": {"paper_trials": nonlinear.TABLE3_PRINTED["trials"],
                      "N": nonlinear.SCENARIO.N, "dof": 1},
    }


def load_tables(profile: str, seed: int | None = None) -> dict[str, dict]:
    """Compute Tables I-III through the registry and put them side by side.

    Parameters
    ----------
    profile : str
        ``"fast"`` or ``"paper"``.
    seed : int, optional
        Seed of every entry (default: each entry's own).

    Returns
    -------
    dict of str to dict
        :func:`side_by_side` of the three tables with :func:`table_meta`.
    """
    from fusioncenter import figures

    data = {s: figures.get(TABLE_IDS[s]).run_compute(profile, seed) for s in SETTINGS}
    return side_by_side(data, table_meta())


def _cells(tables: Mapping[str, dict], fn) -> str:
    return "; ".join(f"{TABLE_NAMES[s]}: " + ", ".join(fn(t, j) for j in range(t["l"].size))
                     for s, t in tables.items())


def bandwidth_claims(tables: Mapping[str, dict]) -> list[Claim]:
    """The statements of the chapter ``book/zheng2014/reading`` about Tables I-III, checked.

    Parameters
    ----------
    tables : mapping of str to dict
        :func:`side_by_side` data (ours in the selected profile, and the printed values).

    Returns
    -------
    list of fusioncenter.figures.registry.Claim
        One claim per statement, each with the numbers it was decided on.
    """
    T = {s: tables[s] for s in SETTINGS}
    hi = {s: t["l"] > 1 for s, t in T.items()}

    def every(fn):
        return bool(all(np.all(fn(t)[hi[s]]) for s, t in T.items()))

    closer_all = every(lambda t: t["closer"] > 0)
    closer_sig = bool(all(np.all(t["closer_z"][t["l"] >= 1.5] > Z_ORDER) for t in T.values()))
    printed_closer = bool(all(np.all(t["printed_closer"] > 0) for t in T.values()))
    under = every(lambda t: (t["ours"][0] - t["l"]) / t["stderr"][0] < -Z_ORDER)
    under_printed = every(lambda t: t["printed"][0] < t["l"])
    more = every(lambda t: t["ours"][1] > t["ours"][0])
    agree2 = every(lambda t: np.abs(t["z_printed"][1]) < Z_AGREE)
    below = bool(all(np.all(T[s]["diff"][0] < 0) for s in ("scalar", "nonlinear")))
    v1 = T["vector"]
    i1 = int(np.flatnonzero(v1["l"] == 1.0)[0])
    t2_l1 = bool(v1["z_printed"][0, i1] > Z_ORDER and v1["closer_vs_printed_z"][i1] < -Z_ORDER)
    v_under = every(lambda t: t["v"][0] + Z_ORDER * t["v_stderr"][0] < 1)
    return [
        Claim("for every l > 1 in every table, CFwMD2 sends closer to l than CFwMD (point "
              "estimates), and by more than 4 paired standard errors wherever l ≥ 1.5",
              closer_all and closer_sig,
              "paired z = " + _cells(T, lambda t, j: f"{t['closer_z'][j]:.1f}")),
        Claim("the printed tables say the same at every l, l = 1 included",
              printed_closer,
              "printed |CFwMD − l| − |CFwMD2 − l| = "
              + _cells(T, lambda t, j: f"{t['printed_closer'][j]:+.4f}")),
        Claim("with state feedback only, CFwMD sends fewer than l for every l > 1 in every "
              "table (ours by more than 4 standard errors; the printed values too)",
              under and under_printed,
              "CFwMD − l = " + _cells(T, lambda t, j: f"{t['ours'][0, j] - t['l'][j]:+.3f}")),
        Claim("hence at the same target l > 1 CFwMD2 spends more transmissions than CFwMD "
              "(the comparisons of Figs. 2, 5 and 10 are not at equal bandwidth)", more,
              "CFwMD2 − CFwMD = "
              + _cells(T, lambda t, j: f"{t['ours'][1, j] - t['ours'][0, j]:+.3f}")),
        Claim("for l > 1, our CFwMD2 agrees with the printed value in every table (|z| < 4, the "
              "paper's Monte Carlo error estimated from its trial count)", agree2,
              "z = " + _cells(T, lambda t, j: f"{t['z_printed'][1, j]:+.1f}")),
        Claim("our CFwMD sends fewer than printed at every l of Tables I and III", below,
              "ours − printed = " + ", ".join(
                  f"{TABLE_NAMES[s]}: " + ", ".join(f"{v:+.3f}" for v in T[s]["diff"][0])
                  for s in ("scalar", "nonlinear"))),
        Claim("Table II, l = 1: our CFwMD sends more than the printed 0.93 (z > 4), and the "
              "printed lead of CFwMD2 in meeting l is not reproduced (z < -4)", t2_l1,
              f"ours {v1['ours'][0, i1]:.4f} vs printed {v1['printed'][0, i1]:.4f} (z = "
              f"{v1['z_printed'][0, i1]:.1f}); lead ours {v1['closer'][i1]:+.4f}, printed "
              f"{v1['printed_closer'][i1]:+.4f} (z = {v1['closer_vs_printed_z'][i1]:.1f})"),
        Claim("for l > 1, CFwMD's innovations are narrower than the sensors' own normalizer in "
              "every table: variance ratio v below 1 by more than 4 standard errors", v_under,
              "v = " + _cells(T, lambda t, j: f"{t['v'][0, j]:.3f}")),
    ]


# ------------------------------------------------------------------------- what silence buys
#: The registry entries :func:`payoff_rows` reads.
PAYOFF_IDS = ("zheng2014-fig1", "zheng2014-fig3", "zheng2014-fig4", "zheng2014-fig6",
              "zheng2014-fig8", "zheng2014-fig9")


def _pair(data: Mapping, a: str, b: str, diff_key: str, se_key: str) -> tuple[float, float]:
    """``(value, stderr)`` of the paired difference ``a - b`` (or ``-(b - a)``) in ``data``."""
    pairs = [tuple(str(x) for x in p) for p in data["pairs"]]
    if (a, b) in pairs:
        j = pairs.index((a, b))
        return float(data[diff_key][j]), float(data[se_key][j])
    if (b, a) in pairs:
        j = pairs.index((b, a))
        return -float(data[diff_key][j]), float(data[se_key][j])
    raise ValueError(f"no paired difference {a} - {b} in the data (pairs {pairs})")


def _row(setting, figure, feedback, N, l, rmse, rmse_se, sent, gain, rest=None, loss=None,
         random_excess=None, z_needed=Z_ORDER, extra=None) -> dict:
    """One row of :func:`payoff_rows`.

    ``gain`` = CFoMD - CFwMD; either ``rest`` = CFwMD - all-send or ``loss`` = CFoMD - all-send;
    ``random_excess`` = random - CFoMD, or a list of terms whose sum is random - all-send (each
    ``(value, se)``, paired over trials).
    """
    g, sg = gain
    if rest is not None:
        h, sh = rest
        L = g + h
        share = g / L
        grad, inputs = [h / L**2, -g / L**2], [sg, sh]
        L_terms = [(g, sg), (h, sh)]
    else:
        L, sL = loss
        h = L - g
        share = g / L
        grad, inputs = [1 / L, -g / L**2], [sg, sL]
        L_terms = [(L, sL)]
    share_se = delta_bound(grad, inputs)
    # R = (random - all-send) / (CFoMD - all-send)
    if isinstance(random_excess, tuple):  # random - CFoMD: R = 1 + D / L
        D, sD = random_excess
        R = 1 + D / L
        R_se = delta_bound([1 / L] + [-D / L**2] * len(L_terms), [sD] + [s for _, s in L_terms])
    else:  # terms of random - all-send: R = A / L
        A = sum(v for v, _ in random_excess)
        R = A / L
        R_se = delta_bound([1 / L] * len(random_excess) + [-A / L**2] * len(L_terms),
                           [s for _, s in random_excess] + [s for _, s in L_terms])
    return {
        "setting": setting, "figure": figure, "feedback": feedback, "N": int(N), "l": float(l),
        "rmse": {k: float(v) for k, v in rmse.items()},
        "rmse_stderr": {k: float(v) for k, v in rmse_se.items()}, "cfwmd_sent": float(sent),
        "gain": float(g), "gain_stderr": float(sg), "gain_z": float(g / sg) if sg > 0 else math.inf,
        "loss": float(L), "rest": float(h), "share": float(share), "share_stderr": share_se,
        "share_gradient": [float(x) for x in grad],
        "share_input_stderr": [float(x) for x in inputs],
        "random_ratio": float(R), "random_ratio_stderr": R_se, "z_needed": float(z_needed),
        **(extra or {}),
    }


def payoff_rows(data: Mapping[str, Mapping]) -> list[dict]:
    """What using the silences (CFwMD) buys, one row per setting.

    Parameters
    ----------
    data : mapping of str to mapping
        The ``compute`` outputs of the entries of :data:`PAYOFF_IDS`, keyed by entry id.

    Returns
    -------
    list of dict
        One row per setting and feedback, described below.

    Raises
    ------
    ValueError
        If an entry of :data:`PAYOFF_IDS` is missing.

    Notes
    -----
    Each row: ``setting``, ``figure``, ``feedback``, ``N``, ``l``; ``rmse`` and ``rmse_stderr``
    (time-averaged position RMSE of all-send, random, CFoMD and CFwMD, m); ``cfwmd_sent``
    (transmissions per step); ``gain`` = CFoMD - CFwMD with its paired ``gain_stderr`` and
    ``gain_z``; ``loss`` = CFoMD - all-send and ``rest`` = CFwMD - all-send; ``share`` = gain /
    loss, the part of CFoMD's loss that CFwMD wins back, with the conservative ``share_stderr``
    (:func:`delta_bound` of ``share_gradient`` with ``share_input_stderr``, the paired errors of
    the inputs: gain and rest with feedback, gain and loss without); ``random_ratio`` =
    (random - all-send) / (CFoMD - all-send) with ``random_ratio_stderr``; ``z_needed``, the
    z-score the registry asks of an ordering in that setting.

    Rows without feedback use the exact filter as CFwMD and add ``printed_gain``, CFoMD minus
    CFwMD with the printed Proposition 3 or 6, and ``printed_max_abs_diff``, the largest
    difference of their squared errors. The nonlinear rows are ``l = 1`` (Fig. 9) and ``l = 2``
    (Fig. 8).
    """
    from fusioncenter.figures.zheng2014.nonlinear import Z_ORDER as Z_NL
    from fusioncenter.figures.zheng2014.nonlinear import z_required

    missing = [e for e in PAYOFF_IDS if e not in data]
    if missing:
        raise ValueError(f"payoff_rows needs the data of {PAYOFF_IDS}; missing {missing}")
    rows = []
    for eid, setting in (("zheng2014-fig1", "scalar"), ("zheng2014-fig4", "vector")):
        d = data[eid]
        sch = [str(s) for s in d["schemes"]]
        keys = ("pair_diff_position", "pair_stderr_position")
        rows.append(_row(
            setting, eid, "state", d["N"], d["l"],
            dict(zip(sch, d["tavg_position"], strict=True)),
            dict(zip(sch, d["tavg_position_stderr"], strict=True)),
            d["transmissions"][sch.index("cfwmd")],
            gain=_pair(d, "cfomd", "cfwmd", *keys), rest=_pair(d, "cfwmd", "all-send", *keys),
            random_excess=_pair(d, "random", "cfomd", *keys)))
    for eid, setting in (("zheng2014-fig3", "scalar"), ("zheng2014-fig6", "vector")):
        d = data[eid]
        cur = [str(c) for c in d["curves"]]
        name = {"all-send": "all-send", "random": "random", "cfomd": "cfomd", "cfwmd": "exact"}
        keys = ("pair_diff", "pair_stderr")
        rows.append(_row(
            setting, eid, "none", d["N"], d["l"],
            {k: d["tavg_position"][cur.index(c)] for k, c in name.items()},
            {k: d["tavg_position_stderr"][cur.index(c)] for k, c in name.items()},
            d["transmissions"][cur.index("exact")],
            gain=_pair(d, "cfomd", "exact", *keys), loss=_pair(d, "cfomd", "all-send", *keys),
            random_excess=_pair(d, "random", "cfomd", *keys),
            extra={"printed_gain": float(d["tavg_position"][cur.index("cfomd")]
                                         - d["tavg_position"][cur.index("printed")]),
                   "printed_max_abs_diff": float(d["printed_max_abs_diff"])}))
    d9, d8 = data["zheng2014-fig9"], data["zheng2014-fig8"]
    zq = z_required(Z_NL, int(d9["trials"]))
    s9 = list(d9["schemes"])
    j = list(d9["l"]).index(1.0)
    i = s9.index("cfomd")
    rows.append(_row(
        "nonlinear", "zheng2014-fig9", "state", 9, 1.0,
        {**{s: d9["tavg_position"][s9.index(s), j] for s in s9},
         "all-send": d9["all_send_position"]},
        {**{s: d9["tavg_position_stderr"][s9.index(s), j] for s in s9},
         "all-send": d9["all_send_position_stderr"]},
        d9["transmissions"][s9.index("cfwmd"), j],
        gain=(-d9["diff_cfwmd-cfomd"][j], d9["diff_cfwmd-cfomd_stderr"][j]),
        loss=(d9["excess_at_min_l"][i], d9["excess_at_min_l_stderr"][i]),
        random_excess=(d9["diff_random-cfomd"][j], d9["diff_random-cfomd_stderr"][j]),
        z_needed=zq))
    s8 = list(d8["schemes"])
    rows.append(_row(
        "nonlinear", "zheng2014-fig8", "state", 9, d8["l"],
        dict(zip(s8, d8["tavg_position"], strict=True)),
        dict(zip(s8, d8["tavg_position_stderr"], strict=True)),
        d8["transmissions"][s8.index("cfwmd")],
        gain=(-d8["diff_cfwmd-cfomd"], d8["diff_cfwmd-cfomd_stderr"]),
        loss=(d8["diff_cfomd-all-send"], d8["diff_cfomd-all-send_stderr"]),
        random_excess=[(-d8["diff_cfwmd-random"], d8["diff_cfwmd-random_stderr"]),
                       (d8["diff_cfwmd-all-send"], d8["diff_cfwmd-all-send_stderr"])],
        z_needed=zq))
    return rows


def gain_by_l(fig9: Mapping) -> dict:
    """Fig. 9 (the nonlinear setting) as a sweep over ``l``.

    Parameters
    ----------
    fig9 : mapping
        The ``compute`` output of ``zheng2014-fig9``.

    Returns
    -------
    dict
        ``l`` (L,); ``schemes``; ``sent`` (3, L) the measured transmissions of random, CFoMD
        and CFwMD; ``gain``, ``gain_stderr`` (L,) = CFoMD - CFwMD (paired);
        ``random_minus_cfomd``, ``random_minus_cfomd_stderr`` (L,); ``shrink`` = gain at the
        smallest ``l`` minus gain at the largest, with the conservative ``shrink_stderr``.
    """
    g = -np.asarray(fig9["diff_cfwmd-cfomd"], dtype=float)
    sg = np.asarray(fig9["diff_cfwmd-cfomd_stderr"], dtype=float)
    return {
        "l": np.asarray(fig9["l"], dtype=float), "schemes": list(fig9["schemes"]),
        "sent": np.asarray(fig9["transmissions"], dtype=float), "gain": g, "gain_stderr": sg,
        "random_minus_cfomd": np.asarray(fig9["diff_random-cfomd"], dtype=float),
        "random_minus_cfomd_stderr": np.asarray(fig9["diff_random-cfomd_stderr"], dtype=float),
        "shrink": float(g[0] - g[-1]), "shrink_stderr": delta_bound([1, -1], [sg[0], sg[-1]]),
    }


def load_payoff(profile: str, seed: int | None = None) -> tuple[list[dict], dict]:
    """Compute the entries of :data:`PAYOFF_IDS` through the registry and summarize them.

    Parameters
    ----------
    profile : {"fast", "paper"}
        The registry profile the entries are computed with.
    seed : int, optional
        One seed for all of the entries; by default each entry keeps its own.

    Returns
    -------
    rows : list of dict
        :func:`payoff_rows` of the entries.
    sweep : dict
        :func:`gain_by_l` of ``zheng2014-fig9``.
    """
    from fusioncenter import figures

    data = {e: figures.get(e).run_compute(profile, seed) for e in PAYOFF_IDS}
    return payoff_rows(data), gain_by_l(data["zheng2014-fig9"])


def _conservative_z(a: float, sa: float, b: float, sb: float) -> float:
    """``(a - b) / (sa + sb)``: a z-score of ``a - b`` valid for any correlation."""
    return (a - b) / (sa + sb)


def payoff_claims(rows: Sequence[Mapping], sweep: Mapping) -> list[Claim]:
    """The chapter's statements about :func:`payoff_rows` and :func:`gain_by_l`, checked.

    Parameters
    ----------
    rows : sequence of mapping
        The output of :func:`payoff_rows`.
    sweep : mapping
        The output of :func:`gain_by_l`.

    Returns
    -------
    list of fusioncenter.figures.registry.Claim
        One claim per statement, each with the numbers it was decided on.

    Raises
    ------
    ValueError
        If ``rows`` lacks a setting the statements are about.
    """
    def fmt(fn, sel=None):
        return "; ".join(f"{r['setting']}, feedback {r['feedback']}, l = {r['l']:g}: {fn(r)}"
                         for r in rows if sel is None or sel(r))

    def pick(setting, feedback):
        got = [r for r in rows if r["setting"] == setting and r["feedback"] == feedback]
        if not got:
            raise ValueError(f"rows lack the setting {setting!r} with feedback {feedback!r}")
        return got

    lin_fb = pick("scalar", "state") + pick("vector", "state")
    nonlin = pick("nonlinear", "state")
    nofb = pick("scalar", "none") + pick("vector", "none")
    linear = lin_fb + nofb
    gain_ok = all(r["gain_z"] > r["z_needed"] for r in rows)
    printed_zero = all(abs(r["printed_gain"]) < 1e-9 and r["printed_max_abs_diff"] < 1e-9
                       for r in nofb)
    between = all(r["share"] - 2 * r["share_stderr"] > 0
                  and r["share"] + 2 * r["share_stderr"] < 1 for r in rows)
    z_big = [_conservative_z(n["gain"], n["gain_stderr"], r["gain"], r["gain_stderr"])
             for n in nonlin for r in linear]
    sc, ve = pick("scalar", "state")[0], pick("vector", "state")[0]
    z_share = _conservative_z(sc["share"], sc["share_stderr"], ve["share"], ve["share_stderr"])
    z_fb = []
    for setting in ("scalar", "vector"):
        a, b = pick(setting, "none")[0], pick(setting, "state")[0]
        for s in ("cfomd", "cfwmd"):
            z_fb.append(_conservative_z(a["rmse"][s], a["rmse_stderr"][s], b["rmse"][s],
                                        b["rmse_stderr"][s]))
    lo_lin = min(r["random_ratio"] - 2 * r["random_ratio_stderr"] for r in lin_fb)
    rand_nl = all(r["random_ratio"] + 2 * r["random_ratio_stderr"] < lo_lin for r in nonlin)
    z_shrink = sweep["shrink"] / sweep["shrink_stderr"]
    return [
        Claim("using the silences pays wherever the FC can compute their likelihood: CFoMD − "
              "CFwMD > 0 in every setting, by more than the registry's z for an ordering",
              gain_ok, fmt(lambda r: f"{r['gain']:+.3f} m (z = {r['gain_z']:.1f}, needed "
                           f"{r['z_needed']:.2f})")),
        Claim("without feedback, the printed Propositions 3 and 6 win back nothing: the same "
              "estimates as CFoMD (to rounding)", printed_zero,
              fmt(lambda r: f"max |difference of squared errors| {r['printed_max_abs_diff']:.0e}",
                  lambda r: r["feedback"] == "none")),
        Claim("CFwMD wins back part, never all, of CFoMD's loss against all-send: 0 < share < 1 "
              "by two conservative standard errors, in every setting", between,
              fmt(lambda r: f"{r['share']:.2f} ± {r['share_stderr']:.2f}")),
        Claim("in metres, the silences are worth most on the nonlinear grid (9 sensors, most of "
              "them silent at every step): its gain exceeds every linear one by more than 2 "
              "conservative standard errors", bool(min(z_big) > 2),
              f"smallest conservative z = {min(z_big):.1f}"),
        Claim("with feedback, the share won back is larger for scalar than for vector "
              "observations (2 conservative standard errors)", bool(z_share > 2),
              f"{sc['share']:.3f} vs {ve['share']:.3f} (z = {z_share:.1f})"),
        Claim("feedback helps twice in the linear settings: CFoMD and CFwMD are both better "
              "with feedback than without (4 conservative standard errors)",
              bool(min(z_fb) > Z_ORDER),
              "z (scalar CFoMD, CFwMD; vector CFoMD, CFwMD) = "
              + ", ".join(f"{z:.1f}" for z in z_fb)),
        Claim("with feedback and N = 2, l = 1 (linear), random selection loses more than twice "
              "as much as CFoMD against all-send; on the nonlinear grid its handicap is smaller "
              "than in either linear setting (two conservative standard errors each)",
              bool(lo_lin > 2 and rand_nl),
              fmt(lambda r: f"{r['random_ratio']:.2f} ± {r['random_ratio_stderr']:.2f}",
                  lambda r: r["feedback"] == "state")),
        Claim("on the nonlinear grid the gain shrinks as l approaches N: gain at the smallest l "
              "minus gain at the largest, more than 2 conservative standard errors",
              bool(z_shrink > 2),
              f"{sweep['gain'][0]:.3f} at l = {sweep['l'][0]:g}, {sweep['gain'][-1]:.3f} at "
              f"l = {sweep['l'][-1]:g} (z = {z_shrink:.1f})"),
    ]
