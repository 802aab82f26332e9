"""Tables I-III of zheng2014 (the average number of transmissions of CFwMD and CFwMD2 against
the target ``l``) read side by side across the three settings, and the chapter's statements about
them (:func:`bandwidth_claims`).

Compute only (plain NumPy data and :class:`~fusioncenter.figures.registry.Claim` lists, no
plotting). The inputs are the ``compute`` outputs of the registry entries ``zheng2014-table1``,
``-table2`` and ``-table3``: :func:`load_tables` computes them through the registry, the other
functions take them as given, so that the tests can feed corrupted data."""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np
import scipy.stats

from fusioncenter import censoring
from fusioncenter._validate import posint as _posint
from fusioncenter.figures.registry import Claim
from fusioncenter.figures.zheng2014.reading.bounds import Z_ORDER

#: The three settings of Section VII, in the paper's order.
SETTINGS = ("scalar", "vector", "nonlinear")
#: The registry entry of each setting's table of transmissions.
TABLE_IDS = {"scalar": "zheng2014-table1", "vector": "zheng2014-table2",
             "nonlinear": "zheng2014-table3"}
TABLE_NAMES = {"scalar": "Table I", "vector": "Table II", "nonlinear": "Table III"}
#: The two feedback schemes of the tables, in their order in the arrays below.
SCHEMES = ("cfwmd", "cfwmd2")
#: Agreement with a printed value: |z| below Z_AGREE.
Z_AGREE = 4.0


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

