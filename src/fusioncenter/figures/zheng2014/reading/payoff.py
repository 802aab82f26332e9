"""What using the silences (CFwMD) buys in each of zheng2014's three settings: the payoff table
(:func:`payoff_rows`), the nonlinear gain as ``l`` grows (:func:`gain_by_l`) and the chapter's
statements about them (:func:`payoff_claims`).

Compute only (plain NumPy data and :class:`~fusioncenter.figures.registry.Claim` lists, no
plotting). The inputs are the ``compute`` outputs of the four-scheme figures
(:data:`PAYOFF_IDS`): :func:`load_payoff` computes them through the registry, the other functions
take them as given, so that the tests can feed corrupted data. Standard errors of the combined
estimates are the conservative bounds of :mod:`~fusioncenter.figures.zheng2014.reading.bounds`."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np

from fusioncenter.figures.registry import Claim
from fusioncenter.figures.zheng2014.reading.bounds import Z_ORDER, conservative_z, delta_bound

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
    z_big = [conservative_z(n["gain"], n["gain_stderr"], r["gain"], r["gain_stderr"])
             for n in nonlin for r in linear]
    sc, ve = pick("scalar", "state")[0], pick("vector", "state")[0]
    z_share = conservative_z(sc["share"], sc["share_stderr"], ve["share"], ve["share_stderr"])
    z_fb = []
    for setting in ("scalar", "vector"):
        a, b = pick(setting, "none")[0], pick(setting, "state")[0]
        for s in ("cfomd", "cfwmd"):
            z_fb.append(conservative_z(a["rmse"][s], a["rmse_stderr"][s], b["rmse"][s],
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
