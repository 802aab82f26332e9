"""Part II (dey2009): Figs. 1-4 of the paper and the book's own figures on faded measurements.

* ``dey2009-fig1`` / ``dey2009-fig2``: one sensor, scalar state, Rayleigh resp. Nakagami(1/2)
  fading: ``E[p_k]`` by Monte Carlo against the tight and loose bound sequences (17)-(20).
* ``dey2009-fig3`` / ``dey2009-fig4``: two sensors, multi-access resp. orthogonal channels:
  ``E[p_k]`` against the worst-sensor bound ``s_k`` and the AM-HM bound ``t_k``.
* ``dey2009-vector``: a 2-state example of Section 3.2: ``E[P_k]`` against ``Zbar_k``.
* ``dey2009-ordering``: what goes wrong on the multi-access channel when ordering (22) is ignored.
* ``dey2009-distribution``: the whole distribution of ``p_k`` (the paper's future work).

The paper leaves some parameters out (Figs. 1-2: the sigma_v values and E[p_0]; Figs. 3-4:
lambda_1, lambda_2). Our choices are in :data:`SIGMA_V`, :data:`P0` and :data:`LAMS`; each entry
also runs a grid of alternatives and checks that the conclusions hold on all of them.
"""

from __future__ import annotations

import itertools

import matplotlib.ticker
import numpy as np
import scipy.integrate
import scipy.stats

from fusioncenter import context, fading, plotting, riccati
from fusioncenter.context import Parameter
from fusioncenter.figures.registry import Claim, Entry, register
from fusioncenter.profile import by_profile

CH_SCALAR = "book/dey2009/scalar-bounds"
CH_MULTI = "book/dey2009/multisensor"
CH_VECTOR = "book/dey2009/vector"
CH_DIST = "book/dey2009/distribution"

#: Ids of the book's own figures registered here (not figures of the paper).
OWN_IDS: tuple[str, ...] = ("dey2009-vector", "dey2009-ordering", "dey2009-distribution")

# ------------------------------------------------------------------------------- parameters
STEPS = 100
#: Sample paths per curve (paper: 50 000 paths of length 100).
PATHS = {"fast": 2_000, "paper": 50_000}
#: Sample paths per setting of the alternative-parameter grids.
GRID_PATHS = {"fast": 400, "paper": 10_000}
#: Trials per random stream of the Monte Carlo runner (part of what fixes the draws).
BLOCK = 1024
#: A Monte Carlo mean more than Z_TOL standard errors above a bound is a failed check. Each
#: z-score is about N(0, 1) or below it under the claim; P(Z > 4) = 3.2e-5, so even the ~10^4
#: (strongly correlated) z-scores of one entry raise a false alarm with small probability.
Z_TOL = 4.0
#: Relative slack for floating-point rounding where a Monte Carlo standard error is 0
#: (e.g. p_1 when p_0 = 0 is deterministic).
REL_SLACK = 1e-9
#: Windows of the convergence check: per-path averages over k in [60, 80) and [80, 100].
WINDOWS = ((60, 80), (80, STEPS + 1))
#: The significance level of the Kolmogorov-Smirnov checks of dey2009-distribution.
KS_LEVEL = 1e-3

#: Figs. 1-2 as captioned: a = 1.25, c = 1, sigma_w = 1, sigma_n = 2, lambda = 100.
SCALAR = {"a": 1.25, "c": 1.0, "sigma_w2": 1.0, "sigma_n2": 4.0, "lam": 100.0}
#: Our choice (not stated in the paper): the sigma_v values of Figs. 1-2.
SIGMA_V = (1.0, 5.0, 10.0)
#: Our choice (not stated in the paper): E[p_0] = p_0 (deterministic) for every figure.
P0 = 1.0
#: Alternatives on which Figs. 1-2's conclusions are re-checked.
SCALAR_GRID = {"sigma_v": (0.1, 2.0, 20.0), "p0": (0.0, 1000.0)}

#: Figs. 3-4 as captioned: a = 1.25, c = (1, 1), sigma_w = 1, sigma = (1, 2), sigma_n = 2.
MULTI = {"a": 1.25, "c": (1.0, 1.0), "sigma_v2": (1.0, 4.0), "sigma_n2": 4.0, "sigma_w2": 1.0}
#: Our choice (not stated in the paper): the (lambda_1, lambda_2) settings of Figs. 3-4.
LAMS = ((1.0, 1.0), (1.0, 10.0), (10.0, 1.0))
#: Alternatives: every pair from this list.
LAM_GRID = (0.1, 1.0, 10.0, 100.0)

#: dey2009-ordering: Fig. 3's sensors; lambda_1 fixed, lambda_2 swept; main setting marked.
ORDERING = {"lam1": 0.1, "lam2": (0.001, 0.003, 0.01, 0.03, 0.1, 0.3, 1.0), "main_lam2": 0.01}

#: dey2009-vector: a 2-state example of Section 3.2 (our choice), Rayleigh as in Fig. 1.
VECTOR = {"A": [[1.25, 1.0], [0.0, 0.9]], "c": [1.0, 0.0], "Sigma_w": [[1.0, 0.0], [0.0, 1.0]],
          "sigma_v2": 1.0, "sigma_n2": 4.0, "lam": 100.0, "P0": [[1.0, 0.0], [0.0, 1.0]]}
#: Directions v (angles in [0, pi)) along which v' E[P_k] v <= v' Zbar_k v is checked.
N_DIRECTIONS = 48

#: Sample paths per law for dey2009-distribution (its fast profile needs more paths to resolve
#: the lower tail; it is cheap).
DIST_PATHS = {"fast": 10_000, "paper": 50_000}
#: dey2009-distribution: Fig. 1's channel with sigma_v = 1, both fading laws.
DIST = {"sigma_v": 1.0, "quantiles": (0.05, 0.25, 0.5, 0.75, 0.95), "p0_alt": 1000.0}

_NOTE_CHOICE = ("Our choice: the paper does not state {what}. The checks re-run the claims on a "
                "grid of alternatives ({grid}) and they hold on every one.")


# ---------------------------------------------------------------------------- shared checks
def _excess_z(mean, se, bound) -> np.ndarray:
    """z-scores of ``mean - bound`` (``+inf`` where a zero-error mean exceeds the bound)."""
    mean, se, bound = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (mean, se, bound)))
    excess = mean - bound - REL_SLACK * np.abs(bound)
    with np.errstate(divide="ignore", invalid="ignore"):
        z = np.where(se > 0, excess / np.where(se > 0, se, 1.0),
                     np.where(excess > 0, np.inf, -np.inf))
    return z


def _abs_z(mean, se, ref) -> np.ndarray:
    """``|mean - ref| / se``, 0 where the difference is within rounding of a zero-error mean."""
    mean, se, ref = (np.asarray(x, dtype=float) for x in (mean, se, ref))
    diff = np.maximum(np.abs(mean - ref) - REL_SLACK * np.abs(ref), 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(se > 0, diff / np.where(se > 0, se, 1.0), np.where(diff > 0, np.inf, 0.0))


def _max_finite(z) -> float:
    z = np.asarray(z, dtype=float)
    if np.any(np.isposinf(z)):
        return float("inf")
    fin = z[np.isfinite(z)]
    return float(fin.max()) if fin.size else float("-inf")


def _window_stats(samples: np.ndarray) -> tuple[float, float]:
    """Mean and s.e. of the per-path difference of the two window averages of :data:`WINDOWS`."""
    (a0, a1), (b0, b1) = WINDOWS
    d = samples[:, b0:b1].mean(axis=1) - samples[:, a0:a1].mean(axis=1)
    return float(d.mean()), float(d.std(ddof=1) / np.sqrt(d.size))


def _dominance_claim(name: str, mean, se, bound) -> Claim:
    z = _excess_z(mean[..., 1:], se[..., 1:], bound[..., 1:])
    zmax = _max_finite(z)
    gap = (np.asarray(bound)[..., 1:] - np.asarray(mean)[..., 1:]) / np.asarray(bound)[..., 1:]
    return Claim(name, bool(zmax < Z_TOL),
                 f"max z = {zmax:.2f} (MC mean above the bound in s.e.); smallest relative gap "
                 f"{float(np.min(gap)):.4f}")


def _stationary_claim(name: str, diff, diff_se) -> Claim:
    z = np.asarray(diff) / np.asarray(diff_se)
    return Claim(name, bool(np.all(np.abs(z) < Z_TOL)),
                 f"window differences z = {', '.join(f'{x:.2f}' for x in np.ravel(z))}")


def _converged_claim(name: str, seqs: dict, limits: dict) -> Claim:
    rel = {k: abs(seqs[k][..., -1] - limits[k]) / limits[k] for k in seqs}
    worst = max(float(np.max(v)) for v in rel.values())
    return Claim(name, worst <= 1e-6,
                 "; ".join(f"|{k}_100 - {k}*| / {k}* <= {float(np.max(v)):.1e}"
                           for k, v in rel.items()))


def _plain_log_ticks(axis) -> None:
    """Plain numbers at 1, 2, 5 x 10^k on a log axis that spans only a few decades."""
    axis.set_major_locator(matplotlib.ticker.LogLocator(base=10.0, subs=(1.0, 2.0, 5.0)))
    axis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
    axis.set_minor_formatter(matplotlib.ticker.NullFormatter())


# ------------------------------------------------------------------------- Figs. 1 and 2
def _scalar_channel(kind: str):
    lam = SCALAR["lam"]
    return fading.Rayleigh(lam) if kind == "rayleigh" else fading.Nakagami(0.5, lam)


def _scalar_runs(kind: str, sigma_vs, p0s, n: int, seed: int, keep_window: bool) -> dict:
    s = SCALAR
    ch = _scalar_channel(kind)
    mean, se, sb, qb, sl, ql, wd, wse = [], [], [], [], [], [], [], []
    for i, (sv, p0) in enumerate(zip(sigma_vs, p0s, strict=True)):
        res = fading.scalar_paths(s["a"], s["sigma_w2"], sv**2, s["sigma_n2"], ch, p0, STEPS, n,
                                  seed + i, block_size=BLOCK, executor=context.executor())
        mean.append(res.mean)
        se.append(res.stderr)
        b = fading.scalar_bounds(s["a"], s["sigma_w2"], sv**2, s["sigma_n2"], ch, p0, STEPS)
        lim = fading.scalar_bound_limits(s["a"], s["sigma_w2"], sv**2, s["sigma_n2"], ch)
        sb.append(b["s"])
        qb.append(b["q"])
        sl.append(lim["s"])
        ql.append(lim["q"])
        if keep_window:
            d, dse = _window_stats(res.samples)
            wd.append(d)
            wse.append(dse)
    out = {"mean": np.array(mean), "stderr": np.array(se), "s": np.array(sb), "q": np.array(qb),
           "s_limit": np.array(sl), "q_limit": np.array(ql)}
    if keep_window:
        out["window_diff"] = np.array(wd)
        out["window_diff_stderr"] = np.array(wse)
    return out


#: The overridable parameters of Figs. 1-4 (Monte Carlo accuracy only: every claim applies).
SETTABLE_PATHS = (
    Parameter("paths", "int", "Monte Carlo paths of each main curve", dict(PATHS), minimum=2),
    Parameter("grid_paths", "int", "Monte Carlo paths of each point of the parameter grid",
              dict(GRID_PATHS), minimum=2),
)


def _paths(profile: str, over: dict) -> tuple[int, int]:
    return (over.get("paths") or by_profile(profile, **PATHS),
            over.get("grid_paths") or by_profile(profile, **GRID_PATHS))


def _compute_scalar(kind: str, profile: str, seed: int, **over) -> dict:
    n, ng = _paths(profile, over)
    main = _scalar_runs(kind, SIGMA_V, [P0] * len(SIGMA_V), n, seed, keep_window=True)
    grid = list(itertools.product(SCALAR_GRID["sigma_v"], SCALAR_GRID["p0"]))
    gsv = np.array([g[0] for g in grid])
    gp0 = np.array([g[1] for g in grid])
    alt = _scalar_runs(kind, gsv, gp0, ng, seed + 100, keep_window=False)
    data = {"kind": kind, "k": np.arange(STEPS + 1), "sigma_v": np.array(SIGMA_V), "p0": P0,
            "n_paths": n, "n_grid_paths": ng, "seed": seed,
            "grid_sigma_v": gsv, "grid_p0": gp0}
    data.update(main)
    data.update({f"grid_{k}": v for k, v in alt.items()})
    if kind == "nakagami":
        ray = _scalar_runs("rayleigh", SIGMA_V, [P0] * len(SIGMA_V), n, seed + 50, False)
        data.update({f"rayleigh_{k}": v for k, v in ray.items()})
        # Rayleigh's tight bound on the grid (deterministic), for "Nakagami is worse" there too
        s = SCALAR
        data["grid_rayleigh_s"] = np.array([
            fading.scalar_bounds(s["a"], s["sigma_w2"], sv**2, s["sigma_n2"],
                                 _scalar_channel("rayleigh"), p0, STEPS)["s"]
            for sv, p0 in grid])
        data["q_as_printed"] = np.array([
            fading.nakagami_q_as_printed(s["a"], s["sigma_w2"], sv**2, s["sigma_n2"], s["lam"],
                                         P0, STEPS) for sv in SIGMA_V])
    return data


def compute_fig1(profile: str, seed: int, **over) -> dict:
    """Data of ``dey2009-fig1``: one sensor, Rayleigh fading, E[p_k] against (17)-(18).

    Parameters
    ----------
    profile : str
        ``"fast"`` or ``"paper"``: the number of paths (:data:`PATHS`, :data:`GRID_PATHS`).
    seed : int
        Seed of the first Monte Carlo run; later runs use ``seed + offset``.
    **over
        Overrides of the entry's settable parameters (see ``Entry.settable``).

    Returns
    -------
    dict
        ``kind`` (``"rayleigh"``); ``k`` (101,) the time steps; ``sigma_v`` (3,) and ``p0`` the
        settings of :data:`SIGMA_V` and :data:`P0`; ``n_paths``, ``n_grid_paths``, ``seed``;
        for each sigma_v (rows): ``mean``, ``stderr`` (3, 101) the Monte Carlo ``E[p_k]`` and its
        standard error, ``s``, ``q`` (3, 101) the tight and loose bound sequences and
        ``s_limit``, ``q_limit`` (3,) their fixed points, ``window_diff`` and
        ``window_diff_stderr`` (3,) the convergence statistic of :data:`WINDOWS`; the same
        arrays prefixed ``grid_`` (no window statistic) for the settings
        ``grid_sigma_v``, ``grid_p0`` of :data:`SCALAR_GRID`.
    """
    return _compute_scalar("rayleigh", profile, seed, **over)


def compute_fig2(profile: str, seed: int, **over) -> dict:
    """Data of ``dey2009-fig2``: one sensor, Nakagami(1/2) fading, E[p_k] against (19)-(20).

    Parameters
    ----------
    profile : str
        ``"fast"`` or ``"paper"``: the number of paths (:data:`PATHS`, :data:`GRID_PATHS`).
    seed : int
        Seed of the first Monte Carlo run; later runs use ``seed + offset``.
    **over
        Overrides of the entry's settable parameters (see ``Entry.settable``).

    Returns
    -------
    dict
        ``kind`` (``"nakagami"``); ``k`` (101,) the time steps; ``sigma_v`` (3,) and ``p0`` the
        settings of :data:`SIGMA_V` and :data:`P0`; ``n_paths``, ``n_grid_paths``, ``seed``;
        for each sigma_v (rows): ``mean``, ``stderr`` (3, 101) the Monte Carlo ``E[p_k]`` and its
        standard error, ``s``, ``q`` (3, 101) the tight and loose bound sequences and
        ``s_limit``, ``q_limit`` (3,) their fixed points, ``window_diff`` and
        ``window_diff_stderr`` (3,) the convergence statistic of :data:`WINDOWS`; the same
        arrays prefixed ``grid_`` (no window statistic) for the settings
        ``grid_sigma_v``, ``grid_p0`` of :data:`SCALAR_GRID`. Also ``rayleigh_mean``,
        ``rayleigh_stderr``, ``rayleigh_s``, ... (Fig. 1's runs, for the comparison),
        ``grid_rayleigh_s`` and ``q_as_printed`` (3, 101), the loose bound with the paper's
        printed (20).
    """
    return _compute_scalar("nakagami", profile, seed, **over)


def _plot_scalar(data: dict, eqs: tuple[str, str], law: str):
    fig, (ax, ax2) = plotting.subplots(1, 2, stack=True)
    k = data["k"]
    for i, sv in enumerate(data["sigma_v"]):
        col = plotting.OKABE_ITO[i]
        plotting.errorband(ax, k, data["mean"][i], data["stderr"][i], color=col, ls="-",
                           label=rf"$\sigma_v={sv:g}$")
        ax.plot(k, data["s"][i], color=col, ls="--")
        ax.plot(k, data["q"][i], color=col, ls=":")
        if "rayleigh_mean" in data:
            ax.plot(k, data["rayleigh_mean"][i], color=col, ls="-", lw=0.7, alpha=0.6)
    # line styles say what a curve is; colours say which sigma_v
    ax.plot([], [], color="0.3", ls="-", label=r"Monte Carlo $E[p_k]$ ± 1.96 s.e.")
    ax.plot([], [], color="0.3", ls="--", label=f"tight {eqs[0]}")
    ax.plot([], [], color="0.3", ls=":", label=f"loose {eqs[1]}")
    if "rayleigh_mean" in data:
        ax.plot([], [], color="0.3", ls="-", lw=0.7, label="Rayleigh MC (Fig. 1)")
    ax.set(xlabel="time step $k$", ylabel=r"$E[p_k]$ and its bounds (units of $x^2$)",
           title=f"{law}, $\\lambda$ = {SCALAR['lam']:g}, $E[p_0]$ = {data['p0']:g}; "
           f"{data['n_paths']} paths")
    ax.legend(ncol=2, loc="lower right")
    for j, (sv, p0) in enumerate(zip(data["grid_sigma_v"], data["grid_p0"], strict=True)):
        col = plotting.OKABE_ITO[j % len(plotting.OKABE_ITO)]
        s = data["grid_s"][j][1:]  # from k = 1: s_0 = E[p_0] may be 0
        ax2.plot(k[1:], data["grid_mean"][j][1:] / s, color=col, ls="-",
                 label=rf"$\sigma_v={sv:g}$, $E[p_0]={p0:g}$")
        ax2.plot(k[1:], data["grid_q"][j][1:] / s, color=col, ls=":")
    ax2.axhline(1.0, color="0.2", lw=0.8)
    ax2.set_yscale("log")
    ax2.set_ylim(0.5, 5.0)  # clips the first steps of q_k / s_k from E[p_0] = 0 (up to ~10^3)
    ax2.set_yticks([0.5, 1.0, 2.0, 5.0])
    _plain_log_ticks(ax2.yaxis)
    ax2.set(xlabel="time step $k$",
            ylabel=r"$E[p_k]/s_k$ (solid), $q_k/s_k$ (dotted) (dimensionless)",
            title=f"alternative parameters (clipped at 5); {data['n_grid_paths']} paths each")
    ax2.legend(loc="upper right", ncol=2)
    return plotting.finish(fig)


def plot_fig1(data: dict):
    """Fig. 1: E[p_k] with its bounds per sigma_v (left), ratios on the alternative grid.

    Parameters
    ----------
    data : dict
        The output of :func:`compute_fig1`.

    Returns
    -------
    matplotlib.figure.Figure
    """
    return _plot_scalar(data, ("$s_k$ (17)", "$q_k$ (18)"), "Rayleigh")


def plot_fig2(data: dict):
    """Fig. 2: as :func:`plot_fig1` for Nakagami(1/2), with Fig. 1's means for comparison.

    Parameters
    ----------
    data : dict
        The output of :func:`compute_fig2`.

    Returns
    -------
    matplotlib.figure.Figure
    """
    return _plot_scalar(data, (r"$\tilde s_k$ (19)", r"$\tilde q_k$ (20)"), "Nakagami(1/2)")


def _checks_scalar(data: dict) -> list[Claim]:
    k1 = _abs_z(data["mean"][:, 1], data["stderr"][:, 1], data["s"][:, 1])
    claims = [
        _dominance_claim("E[p_k] <= s_k at every k and sigma_v (MC mean - 4 s.e.)",
                         data["mean"], data["stderr"], data["s"]),
        Claim("s_k <= q_k at every k (tight below loose)",
              bool(np.all(data["s"] <= data["q"] * (1 + REL_SLACK))),
              f"smallest q_k / s_k = {float(np.min(data['q'][:, 1:] / data['s'][:, 1:])):.4f}"),
        Claim("the tight bound is exact at k = 1 (p_0 deterministic): MC E[p_1] = s_1 within "
              "4 s.e.", bool(np.all(k1 < Z_TOL)),
              f"|z| = {', '.join(f'{x:.2f}' for x in k1)}"),
        _converged_claim("s_k and q_k converge to their fixed points s*, q* (root finding)",
                         {"s": data["s"], "q": data["q"]},
                         {"s": data["s_limit"], "q": data["q_limit"]}),
        Claim("gamma* <= s* <= q* (MC E[p_100] - 4 s.e. <= s*)",
              bool(np.all(_excess_z(data["mean"][:, -1], data["stderr"][:, -1],
                                    data["s_limit"]) < Z_TOL)
                   and np.all(data["s_limit"] <= data["q_limit"])),
              "E[p_100], s*, q* = " + "; ".join(
                  f"{m:.2f}, {s:.2f}, {q:.2f}" for m, s, q in
                  zip(data["mean"][:, -1], data["s_limit"], data["q_limit"], strict=True))),
        _stationary_claim("E[p_k] has converged: per-path averages over k in [60, 80) and "
                          "[80, 100] agree within 4 s.e.", data["window_diff"],
                          data["window_diff_stderr"]),
        _dominance_claim("alternative sigma_v and E[p_0] (grid): E[p_k] <= s_k at every k",
                         data["grid_mean"], data["grid_stderr"], data["grid_s"]),
        Claim("alternative sigma_v and E[p_0] (grid): s_k <= q_k at every k and both converge",
              bool(np.all(data["grid_s"] <= data["grid_q"] * (1 + REL_SLACK))
                   and np.all(np.abs(data["grid_s"][:, -1] / data["grid_s_limit"] - 1) < 1e-6)
                   and np.all(np.abs(data["grid_q"][:, -1] / data["grid_q_limit"] - 1) < 1e-6)),
              f"{len(data['grid_p0'])} settings"),
    ]
    if data["kind"] == "nakagami":
        z = ((data["mean"][:, -1] - data["rayleigh_mean"][:, -1])
             / np.hypot(data["stderr"][:, -1], data["rayleigh_stderr"][:, -1]))
        claims += [
            Claim("Nakagami(1/2) is worse than Rayleigh: E[p_100] larger by > 4 s.e. for every "
                  "sigma_v", bool(np.all(z > Z_TOL)), f"z = {', '.join(f'{x:.1f}' for x in z)}"),
            Claim("Nakagami(1/2)'s tight bound is above Rayleigh's at every k >= 1 (main and "
                  "grid settings)",
                  bool(np.all(data["s"][:, 1:] > data["rayleigh_s"][:, 1:])
                       and np.all(data["grid_s"][:, 1:] >= data["grid_rayleigh_s"][:, 1:])),
                  "s~* / s* = " + ", ".join(f"{x:.3f}" for x in
                                           data["s_limit"] / data["rayleigh_s_limit"])
                  + "; loose q~* / q* = " + ", ".join(
                      f"{x:.3f}" for x in data["q_limit"] / data["rayleigh_q_limit"])
                  + " (not asserted: the paper says 'generally worse')"),
        ]
    return claims


_SCALAR_PARAMS = {
    **SCALAR, "sigma_v": list(SIGMA_V), "E[p_0]": P0, "steps": STEPS, "paths": PATHS,
    "grid": {k: list(v) for k, v in SCALAR_GRID.items()}, "grid_paths": GRID_PATHS,
    "block_size": BLOCK,
    "note": _NOTE_CHOICE.format(what="the sigma_v values or E[p_0]",
                                grid="sigma_v in {0.1, 2, 20} x E[p_0] in {0, 1000}"),
}

register(Entry(
    id="dey2009-fig1",
    paper="dey2009",
    kind="figure",
    caption="Rayleigh fading, one sensor: the Monte Carlo average error covariance E[p_k] "
    "(50 000 paths of length 100) against the tight bound s_k (17) and the loose bound q_k (18), "
    "for several sigma_v; below: the same ordering on a grid of alternative parameters.",
    chapter=CH_SCALAR,
    label="sec-dey2009-fig1",
    parameters=_SCALAR_PARAMS,
    compute=compute_fig1,
    settable=SETTABLE_PATHS,
    plot=plot_fig1,
    checks=_checks_scalar,
    status="reproduced",
    note="E[p_k] <= s_k <= q_k at every k and all three converge, as the paper describes; "
    "sigma_v in {1, 5, 10} and E[p_0] = 1 are our choice (not stated in the paper) and the "
    "conclusions hold on a grid of alternatives.",
))

register(Entry(
    id="dey2009-fig2",
    paper="dey2009",
    kind="figure",
    caption="Nakagami(1/2) fading, one sensor: E[p_k] by Monte Carlo against the bounds (19) "
    "and (20), with Fig. 1's Rayleigh averages for comparison; below: alternative parameters.",
    chapter=CH_SCALAR,
    label="sec-dey2009-fig2",
    parameters={**_SCALAR_PARAMS, "m": 0.5,
                "eq20": "denominator sqrt(s2 l/2) + sqrt(s2 l/2 + 4/pi (q + s_v^2)) as derived; "
                "the printed nested root is kept in the data as q_as_printed (see errata)"},
    compute=compute_fig2,
    settable=SETTABLE_PATHS,
    plot=plot_fig2,
    checks=_checks_scalar,
    status="reproduced",
    note="E[p_k] <= s~_k <= q~_k, convergence, and worse than Rayleigh (mean and tight bound), "
    "as described; the loose bound (20) is used with its denominator as derived (the printed "
    "(20) has a nested square root, see the errata); the Nakagami loose bound is not above "
    "Rayleigh's for large sigma_v, consistent with the paper's 'generally worse'.",
))


# ------------------------------------------------------------------------- Figs. 3 and 4
def _multi_runs(access: str, lam_pairs, n: int, seed: int, keep_window: bool,
                p0: float = P0) -> dict:
    m = MULTI
    mean, se, sb, tb, sl, tl, wd, wse = [], [], [], [], [], [], [], []
    for i, lams in enumerate(lam_pairs):
        args = (access, m["a"], m["c"], m["sigma_v2"], m["sigma_n2"], lams, m["sigma_w2"])
        res = fading.multisensor_paths(*args, p0, STEPS, n, seed + i, block_size=BLOCK,
                                       executor=context.executor())
        mean.append(res.mean)
        se.append(res.stderr)
        b = fading.multisensor_bounds(*args, p0, STEPS)
        lim = fading.multisensor_bound_limits(*args)
        sb.append(b["s"])
        tb.append(b["t"])
        sl.append(lim["s"])
        tl.append(lim["t"])
        if keep_window:
            d, dse = _window_stats(res.samples)
            wd.append(d)
            wse.append(dse)
    out = {"mean": np.array(mean), "stderr": np.array(se), "s": np.array(sb), "t": np.array(tb),
           "s_limit": np.array(sl), "t_limit": np.array(tl)}
    if keep_window:
        out["window_diff"] = np.array(wd)
        out["window_diff_stderr"] = np.array(wse)
    return out


def _compute_multi(access: str, profile: str, seed: int, **over) -> dict:
    n, ng = _paths(profile, over)
    grid = list(itertools.product(LAM_GRID, LAM_GRID))
    data = {"access": access, "k": np.arange(STEPS + 1), "lams": np.array(LAMS), "p0": P0,
            "n_paths": n, "n_grid_paths": ng, "seed": seed, "grid_lams": np.array(grid)}
    data.update(_multi_runs(access, LAMS, n, seed, keep_window=True))
    data.update({f"grid_{k}": v for k, v in
                 _multi_runs(access, grid, ng, seed + 100, keep_window=False).items()})
    return data


def compute_fig3(profile: str, seed: int, **over) -> dict:
    """Data of ``dey2009-fig3``: two sensors, multi-access channel, E[p_k] against s_k, t_k.

    Parameters
    ----------
    profile : str
        ``"fast"`` or ``"paper"``: the number of paths (:data:`PATHS`, :data:`GRID_PATHS`).
    seed : int
        Seed of the first Monte Carlo run; later runs use ``seed + offset``.
    **over
        Overrides of the entry's settable parameters (see ``Entry.settable``).

    Returns
    -------
    dict
        ``access`` (``"multi-access"``); ``k`` (101,); ``lams`` (3, 2) the settings of :data:`LAMS`;
        ``p0``, ``n_paths``, ``n_grid_paths``, ``seed``; per setting (rows): ``mean``,
        ``stderr`` (3, 101) the Monte Carlo ``E[p_k]``, ``s`` and ``t`` (3, 101) the
        worst-sensor and AM-HM bound sequences, ``s_limit`` and ``t_limit`` (3,) their fixed
        points, ``window_diff`` and ``window_diff_stderr`` (3,); the same prefixed ``grid_``
        (no window statistic) for the 16 pairs ``grid_lams`` (16, 2) of :data:`LAM_GRID`.
    """
    return _compute_multi("multi-access", profile, seed, **over)


def compute_fig4(profile: str, seed: int, **over) -> dict:
    """Data of ``dey2009-fig4``: two sensors, orthogonal channels, E[p_k] against s_k, t_k.

    Parameters
    ----------
    profile : str
        ``"fast"`` or ``"paper"``: the number of paths (:data:`PATHS`, :data:`GRID_PATHS`).
    seed : int
        Seed of the first Monte Carlo run; later runs use ``seed + offset``.
    **over
        Overrides of the entry's settable parameters (see ``Entry.settable``).

    Returns
    -------
    dict
        ``access`` (``"orthogonal"``); ``k`` (101,); ``lams`` (3, 2) the settings of :data:`LAMS`;
        ``p0``, ``n_paths``, ``n_grid_paths``, ``seed``; per setting (rows): ``mean``,
        ``stderr`` (3, 101) the Monte Carlo ``E[p_k]``, ``s`` and ``t`` (3, 101) the
        worst-sensor and AM-HM bound sequences, ``s_limit`` and ``t_limit`` (3,) their fixed
        points, ``window_diff`` and ``window_diff_stderr`` (3,); the same prefixed ``grid_``
        (no window statistic) for the 16 pairs ``grid_lams`` (16, 2) of :data:`LAM_GRID`.
    """
    return _compute_multi("orthogonal", profile, seed, **over)


def plot_multi(data: dict):
    """Figs. 3 and 4: one panel per (lambda_1, lambda_2), and which bound is tighter on the grid.

    Parameters
    ----------
    data : dict
        The output of :func:`compute_fig3` or :func:`compute_fig4`.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, axes = plotting.subplots(2, 2, stack=True)
    k = data["k"]
    for i, (ax, (l1, l2)) in enumerate(zip(axes.flat, data["lams"], strict=False)):
        plotting.errorband(ax, k, data["mean"][i], data["stderr"][i], color=plotting.OKABE_ITO[0],
                           ls="-", label=r"Monte Carlo $E[p_k]$ ± 1.96 s.e.")
        ax.plot(k, data["s"][i], color=plotting.OKABE_ITO[1], ls="--",
                label="$s_k$ (worst sensor)" if data["access"] == "multi-access"
                else r"$s_k$ (min over sensors)")
        ax.plot(k, data["t"][i], color=plotting.OKABE_ITO[2], ls="-.", label=r"$t_k$ (AM-HM)")
        ax.set(xlabel="time step $k$", ylabel=r"$E[p_k]$ and bounds (units of $x^2$)",
               title=rf"$\lambda_1 = {l1:g}$, $\lambda_2 = {l2:g}$")
        ax.legend()
    ax = axes.flat[-1]
    gm = data["grid_mean"][:, -1]
    xs, ys = data["grid_s_limit"] / gm, data["grid_t_limit"] / gm
    for j, (l1, l2) in enumerate(data["grid_lams"]):
        ax.plot(xs[j], ys[j], ls="none", marker=plotting.MARKERS[int(np.log10(l1)) + 1],
                color=plotting.OKABE_ITO[int(np.log10(l2)) + 1], mfc="none")
    for j, lam in enumerate(LAM_GRID):  # legend: marker = lambda_1, colour = lambda_2
        ax.plot([], [], ls="none", marker=plotting.MARKERS[j], color="0.3", mfc="none",
                label=rf"$\lambda_1 = {lam:g}$")
    lo, hi = 0.9, 1.1 * max(xs.max(), ys.max())
    ax.plot([lo, hi], [lo, hi], color="0.3", lw=0.8, ls=":", label="equally tight")
    for j, lam in enumerate(LAM_GRID):
        ax.plot([], [], ls="-", color=plotting.OKABE_ITO[j], label=rf"$\lambda_2 = {lam:g}$")
    ax.set(xscale="log", yscale="log", xlabel=r"$s^*/E[p_{100}]$ (dimensionless)",
           ylabel=r"$t^*/E[p_{100}]$ (dimensionless)",
           title=f"{len(xs)} alternative settings ({data['n_grid_paths']} paths each)")
    _plain_log_ticks(ax.xaxis)
    _plain_log_ticks(ax.yaxis)
    ax.legend(loc="center left", bbox_to_anchor=(1.0, 0.5))
    scheme = "multi-access" if data["access"] == "multi-access" else "orthogonal"
    return plotting.finish(fig, title=f"Two sensors, {scheme} scheme; {data['n_paths']} paths")


def _tighter(s, t) -> tuple[bool, bool]:
    return bool(np.any(s < t * (1 - 1e-3))), bool(np.any(t < s * (1 - 1e-3)))


def checks_multi(data: dict) -> list[Claim]:
    """The claims of Figs. 3 and 4: both bounds dominate E[p_k], converge, and either can win.

    Parameters
    ----------
    data : dict
        The output of :func:`compute_fig3` or :func:`compute_fig4`.

    Returns
    -------
    list of fusioncenter.figures.registry.Claim
        Dominance and convergence of ``s_k`` and ``t_k``, stationarity, and that each bound is
        the tighter one in some setting (main settings and grid).
    """
    s_wins, t_wins = _tighter(data["s_limit"], data["t_limit"])
    gs, gt = _tighter(data["grid_s_limit"], data["grid_t_limit"])
    return [
        _dominance_claim("E[p_k] <= s_k at every k and setting (MC mean - 4 s.e.)",
                         data["mean"], data["stderr"], data["s"]),
        _dominance_claim("E[p_k] <= t_k at every k and setting (MC mean - 4 s.e.)",
                         data["mean"], data["stderr"], data["t"]),
        _converged_claim("s_k and t_k converge to their fixed points",
                         {"s": data["s"], "t": data["t"]},
                         {"s": data["s_limit"], "t": data["t_limit"]}),
        _stationary_claim("E[p_k] has converged: per-path averages over k in [60, 80) and "
                          "[80, 100] agree within 4 s.e.", data["window_diff"],
                          data["window_diff_stderr"]),
        Claim("each of s and t is the tighter bound in some setting (lambda_1, lambda_2)",
              s_wins and t_wins,
              "s*, t* = " + "; ".join(f"{s:.2f}, {t:.2f}" for s, t in
                                      zip(data["s_limit"], data["t_limit"], strict=True))),
        _dominance_claim("alternative (lambda_1, lambda_2) grid: E[p_k] <= min(s_k, t_k) at "
                         "every k", data["grid_mean"], data["grid_stderr"],
                         np.minimum(data["grid_s"], data["grid_t"])),
        Claim("alternative grid: each of s and t is the tighter bound somewhere", gs and gt,
              f"s tighter in {int(np.sum(data['grid_s_limit'] < data['grid_t_limit']))} of "
              f"{len(data['grid_s_limit'])} settings"),
    ]


_MULTI_PARAMS = {
    **MULTI, "lams": [list(x) for x in LAMS], "E[p_0]": P0, "steps": STEPS, "paths": PATHS,
    "grid_lams": list(LAM_GRID), "grid_paths": GRID_PATHS, "block_size": BLOCK,
    "note": _NOTE_CHOICE.format(what="lambda_1, lambda_2 (nor E[p_0])",
                                grid="every (lambda_1, lambda_2) in {0.1, 1, 10, 100}^2"),
}

register(Entry(
    id="dey2009-fig3",
    paper="dey2009",
    kind="figure",
    caption="Two sensors, multi-access (coherent sum) channel: E[p_k] by Monte Carlo against "
    "the worst-sensor bound s_k and the AM-HM bound t_k for three (lambda_1, lambda_2); last "
    "panel: which bound is tighter over a grid of alternatives.",
    chapter=CH_MULTI,
    label="sec-dey2009-fig3",
    parameters=_MULTI_PARAMS,
    compute=compute_fig3,
    settable=SETTABLE_PATHS,
    plot=plot_multi,
    checks=checks_multi,
    status="reproduced",
    note="Both bounds dominate E[p_k] and converge; sometimes s, sometimes t is tighter, as the "
    "paper says. lambda_1, lambda_2 are our choice (not stated) and the conclusions hold on a "
    "4 x 4 grid of alternatives.",
))

register(Entry(
    id="dey2009-fig4",
    paper="dey2009",
    kind="figure",
    caption="Two sensors, orthogonal channels: E[p_k] by Monte Carlo against s_k (minimum over "
    "which sensor is integrated last) and the AM-HM bound t_k (26) for three (lambda_1, "
    "lambda_2); last panel: which bound is tighter over a grid of alternatives.",
    chapter=CH_MULTI,
    label="sec-dey2009-fig4",
    parameters=_MULTI_PARAMS,
    compute=compute_fig4,
    settable=SETTABLE_PATHS,
    plot=plot_multi,
    checks=checks_multi,
    status="reproduced",
    note="Both bounds dominate E[p_k] and converge; each is tighter in some setting, as the "
    "paper says. lambda_1, lambda_2 are our choice (not stated) and the conclusions hold on a "
    "4 x 4 grid of alternatives.",
))


# ---------------------------------------------------------------------- dey2009-ordering
def compute_ordering(profile: str, seed: int) -> dict:
    """Data of ``dey2009-ordering``: the multi-access bound with and without ordering (22).

    Parameters
    ----------
    profile : str
        ``"fast"`` or ``"paper"``: the number of paths (:data:`PATHS`, :data:`GRID_PATHS`).
    seed : int
        Seed of the first Monte Carlo run; later runs use ``seed + offset``.

    Returns
    -------
    dict
        Settings ``k``, ``lam1``, ``lam2`` (the swept lambda_2 of :data:`ORDERING`),
        ``main_lam2``, ``n_paths``, ``n_grid_paths``, ``seed``, ``p0``, ``worst_sensor``; at
        the main setting (101,) each: ``ma_mean``, ``ma_stderr``, ``orth_mean``, ``orth_stderr``
        (Monte Carlo E[p_k] of both schemes), ``alone_mean``, ``alone_stderr`` (sensor 1 alone),
        ``s_valid`` (the bound with the worst sensor last, (22) holds), ``s_sensor1_last`` and
        ``s_sensor2_last`` (one sensor last), ``t_ma``, ``t_orth``; and the same prefixed
        ``sweep_`` with one row per lambda_2 (7, 101), without the sensor-alone run.
    """
    m = MULTI
    n = by_profile(profile, **PATHS)
    ng = by_profile(profile, **GRID_PATHS)
    lam1 = ORDERING["lam1"]
    lam2s = np.array(ORDERING["lam2"])
    common = (m["a"], m["c"], m["sigma_v2"], m["sigma_n2"])
    out: dict = {"k": np.arange(STEPS + 1), "lam1": lam1, "lam2": lam2s,
                 "main_lam2": ORDERING["main_lam2"], "n_paths": n, "n_grid_paths": ng,
                 "seed": seed, "p0": P0, "worst_sensor": int(np.argmin(
                     np.array(m["c"]) ** 2 / np.array(m["sigma_v2"])))}

    def seqs(lams, p0, steps):
        ma = fading.multisensor_bounds("multi-access", *common, lams, m["sigma_w2"], p0, steps)
        one = [fading.multisensor_bounds("orthogonal", m["a"], [m["c"][i]], [m["sigma_v2"][i]],
                                         m["sigma_n2"], [lams[i]], m["sigma_w2"], p0,
                                         steps)["s"] for i in range(2)]
        return {"s_valid": ma["s"], "s_sensor1_last": one[0], "s_sensor2_last": one[1],
                "t_ma": ma["t"],
                "t_orth": fading.multisensor_bounds("orthogonal", *common, lams, m["sigma_w2"],
                                                    p0, steps)["t"]}

    def runs(lams, npaths, sd, keep):
        res = {}
        for j, access in enumerate(fading.ACCESS_SCHEMES):
            r = fading.multisensor_paths(access, *common, lams, m["sigma_w2"], P0, STEPS, npaths,
                                         sd + j, block_size=BLOCK)
            key = "ma" if access == "multi-access" else "orth"
            res[f"{key}_mean"], res[f"{key}_stderr"] = r.mean, r.stderr
        if keep:  # sensor 1 alone (a scalar channel with c = 1): the violated bound's model
            r = fading.scalar_paths(m["a"], m["sigma_w2"], m["sigma_v2"][0], m["sigma_n2"],
                                    fading.Rayleigh(lams[0]), P0, STEPS, npaths, sd + 2,
                                    block_size=BLOCK)
            res["alone_mean"], res["alone_stderr"] = r.mean, r.stderr
        return res

    main = (lam1, ORDERING["main_lam2"])
    out.update(runs(main, n, seed, keep=True))
    out.update(seqs(main, P0, STEPS))
    sweep = [runs((lam1, l2), ng, seed + 10 * (i + 1), keep=False) for i, l2 in enumerate(lam2s)]
    bseq = [seqs((lam1, l2), P0, STEPS) for l2 in lam2s]
    for key in sweep[0]:
        out[f"sweep_{key}"] = np.array([x[key] for x in sweep])
    for key in bseq[0]:
        out[f"sweep_{key}"] = np.array([x[key] for x in bseq])
    return out


def plot_ordering(data: dict):
    """The violated bound at the main setting (left) and steady states against lambda_2.

    Parameters
    ----------
    data : dict
        The output of :func:`compute_ordering`.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, (ax, ax2) = plotting.subplots(1, 2, stack=True)
    k = data["k"]
    c = plotting.OKABE_ITO
    plotting.errorband(ax, k, data["ma_mean"], data["ma_stderr"], color=c[0], ls="-",
                       label="multi-access: Monte Carlo ± 1.96 s.e.")
    plotting.errorband(ax, k, data["orth_mean"], data["orth_stderr"], color=c[2], ls="-",
                       label="orthogonal: Monte Carlo ± 1.96 s.e.")
    ax.plot(k, data["alone_mean"], color="0.4", ls="-", lw=0.8, label="sensor 1 alone (MC)")
    ax.plot(k, data["s_valid"], color=c[1], ls="--", label="$s_k$, worst sensor last: (22) holds")
    ax.plot(k, data["s_sensor1_last"], color=c[3], ls=":",
            label="$s_k$, best sensor last: (22) violated")
    ax.plot(k, data["t_ma"], color=c[4], ls="-.", label=r"$t_k$ (multi-access)")
    ax.set(xlabel="time step $k$", ylabel=r"$E[p_k]$ and bounds (units of $x^2$)",
           title=rf"$\lambda_1 = {data['lam1']:g}$, $\lambda_2 = {data['main_lam2']:g}$; "
           f"{data['n_paths']} paths", yscale="log")
    ax.legend()
    x = data["lam2"]
    ax2.errorbar(x, data["sweep_ma_mean"][:, -1], yerr=1.96 * data["sweep_ma_stderr"][:, -1],
                 color=c[0], marker=plotting.MARKERS[0], mfc="none", capsize=2,
                 label=r"multi-access $E[p_{100}]$ (MC)")
    ax2.errorbar(x, data["sweep_orth_mean"][:, -1], yerr=1.96 * data["sweep_orth_stderr"][:, -1],
                 color=c[2], marker=plotting.MARKERS[1], mfc="none", capsize=2,
                 label=r"orthogonal $E[p_{100}]$ (MC)")
    ax2.plot(x, data["sweep_s_valid"][:, -1], color=c[1], ls="--", label="$s^*$, (22) holds")
    ax2.plot(x, data["sweep_s_sensor1_last"][:, -1], color=c[3], ls=":",
             label="$s^*$, (22) violated (= orthogonal, sensor 1 last)")
    ax2.plot(x, data["sweep_t_ma"][:, -1], color=c[4], ls="-.", label="$t^*$ (multi-access)")
    ax2.set(xscale="log", yscale="log", xlabel=r"$\lambda_2$ (1 / mean power gain of sensor 2)",
            ylabel=r"steady state, $k = 100$ (units of $x^2$)",
            title=rf"$\lambda_1 = {data['lam1']:g}$; {data['n_grid_paths']} paths each")
    ax2.legend()
    return plotting.finish(fig)


def checks_ordering(data: dict) -> list[Claim]:
    """What ordering (22) protects: the bound with the best sensor last fails on multi-access.

    Parameters
    ----------
    data : dict
        The output of :func:`compute_ordering` (or a corrupted copy, in the tests).

    Returns
    -------
    list of fusioncenter.figures.registry.Claim
        The violation of the wrongly ordered bound, the validity of the ordered one and of
        the orthogonal bounds, and the comparisons with sensor 1 alone.
    """
    zviol = _excess_z(data["ma_mean"][1:], data["ma_stderr"][1:], data["s_sensor1_last"][1:])
    zalone = ((data["ma_mean"][-1] - data["alone_mean"][-1])
              / np.hypot(data["ma_stderr"][-1], data["alone_stderr"][-1]))
    orth_mean = np.vstack([data["orth_mean"], data["sweep_orth_mean"]])
    orth_se = np.vstack([data["orth_stderr"], data["sweep_orth_stderr"]])
    orth_bound = np.minimum(  # both sequences bound E[p_k] <=> their minimum does
        np.vstack([data["s_sensor1_last"], data["sweep_s_sensor1_last"]]),
        np.vstack([data["s_sensor2_last"], data["sweep_s_sensor2_last"]]))
    return [
        _dominance_claim("multi-access, (22) respected (worst sensor last): E[p_k] <= s_k at "
                         "every k and lambda_2", np.vstack([data["ma_mean"],
                                                            data["sweep_ma_mean"]]),
                         np.vstack([data["ma_stderr"], data["sweep_ma_stderr"]]),
                         np.vstack([data["s_valid"], data["sweep_s_valid"]])),
        Claim("multi-access, (22) violated (best sensor last): the sequence falls below E[p_k] "
              "by more than 4 s.e. (it is not a bound)", bool(_max_finite(zviol) > Z_TOL),
              f"max z = {_max_finite(zviol):.1f}; at k = 100: E[p] = {data['ma_mean'][-1]:.3f}, "
              f"sequence {data['s_sensor1_last'][-1]:.3f}"),
        Claim("why: on the coherent multi-access channel the noisier sensor hurts - E[p_100] "
              "with both sensors exceeds sensor 1 alone by > 4 s.e.", bool(zalone > Z_TOL),
              f"z = {zalone:.1f}"),
        _dominance_claim("orthogonal: both single-sensor sequences (either order) bound E[p_k] "
                         "at every k and lambda_2 (no ordering needed)",
                         orth_mean, orth_se, orth_bound),
        _dominance_claim("multi-access: t_k (AM-HM, no ordering needed) bounds E[p_k] at every "
                         "k and lambda_2", data["sweep_ma_mean"], data["sweep_ma_stderr"],
                         data["sweep_t_ma"]),
    ]


register(Entry(
    id="dey2009-ordering",
    paper="dey2009",
    kind="figure",
    caption="Ordering (22) matters on the multi-access channel: with the best sensor integrated "
    "last, the 'bound' falls below E[p_k] (adding the noisier sensor to a coherent sum hurts), "
    "while the same sequence is a valid bound for orthogonal channels.",
    chapter=CH_MULTI,
    label="sec-dey2009-ordering",
    parameters={**MULTI, "ordering": {**ORDERING, "lam2": list(ORDERING["lam2"])},
                "E[p_0]": P0, "steps": STEPS, "paths": PATHS, "sweep_paths": GRID_PATHS,
                "block_size": BLOCK},
    compute=compute_ordering,
    plot=plot_ordering,
    checks=checks_ordering,
    status="reproduced",
    note="Our own figure (the paper states (22) but does not show its violation).",
))


# ------------------------------------------------------------------------ dey2009-vector
def _vector_model():
    v = VECTOR
    return (np.array(v["A"]), np.array(v["c"]), np.array(v["Sigma_w"]), v["sigma_v2"],
            v["sigma_n2"], fading.Rayleigh(v["lam"]), np.array(v["P0"]))


def _theorem33_by_quadrature(Z, A, c, Sw, sv2, sn2, lam) -> np.ndarray:
    """``E_r[f_r(Z)]`` of (14) for Rayleigh ``r``, each entry by ``scipy.integrate.quad``."""
    def f(r):
        S = c @ Z @ c + sv2
        Zc = Z @ c
        post = Z - np.outer(Zc, Zc) / S * r / (r + sn2 / S)
        return A @ post @ A.T + Sw

    out = np.empty_like(Z)
    for i, j in itertools.product(range(Z.shape[0]), repeat=2):
        out[i, j] = scipy.integrate.quad(lambda r, i=i, j=j: f(r)[i, j] * lam * np.exp(-lam * r),
                                         0.0, np.inf, epsabs=0.0, epsrel=1e-12, limit=200)[0]
    return out


def compute_vector(profile: str, seed: int) -> dict:
    """Data of ``dey2009-vector``: E[P_k] of the 2-state example against Zbar_k (Section 3.2).

    Parameters
    ----------
    profile : str
        ``"fast"`` or ``"paper"``: the number of paths (:data:`PATHS`).
    seed : int
        Seed of the first Monte Carlo run; later runs use ``seed + offset``.

    Returns
    -------
    dict
        ``k`` (101,), ``n_paths``, ``seed``; ``mean_triu``, ``stderr_triu`` (101, 3) the Monte
        Carlo mean of (P11, P12, P22) and its standard error; ``Z`` (101, 2, 2) the bounding
        sequence; ``theta`` (:data:`N_DIRECTIONS`,) directions and ``mean_vPv``,
        ``stderr_vPv``, ``Z_vPv`` (101, directions) the quadratic forms v'E[P_k]v and v'Zbar_k v;
        ``min_eig_Z_minus_mean`` (101,); ``quad_k`` (5,) steps at which ``Z_next_quadrature``
        (5, 2, 2) evaluates Theorem 3.3's recursion (14) by quadrature; ``window_diff`` and
        ``window_diff_stderr`` (float) for the trace.
    """
    A, c, Sw, sv2, sn2, ch, P0m = _vector_model()
    n = by_profile(profile, **PATHS)
    res = fading.vector_paths(A, c, Sw, sv2, sn2, ch, P0m, STEPS, n, seed, block_size=BLOCK)
    Z = fading.vector_bound(A, c, Sw, sv2, sn2, ch, P0m, STEPS)
    theta = np.linspace(0.0, np.pi, N_DIRECTIONS, endpoint=False)
    # v' P v from the upper triangle (P11, P12, P22)
    W = np.stack([np.cos(theta) ** 2, 2 * np.cos(theta) * np.sin(theta), np.sin(theta) ** 2], 1)
    quad_form = res.samples @ W.T  # (n, k, directions)
    trace = res.samples[..., 0] + res.samples[..., 2]
    d, dse = _window_stats(trace)
    qk = (0, 1, 10, 50, STEPS - 1)
    return {
        "k": np.arange(STEPS + 1), "n_paths": n, "seed": seed,
        "mean_triu": res.mean, "stderr_triu": res.stderr, "Z": Z,
        "theta": theta, "mean_vPv": quad_form.mean(axis=0),
        "stderr_vPv": quad_form.std(axis=0, ddof=1) / np.sqrt(n),
        "Z_vPv": np.einsum("kij,di,dj->kd", Z, np.stack([np.cos(theta), np.sin(theta)], 1),
                           np.stack([np.cos(theta), np.sin(theta)], 1)),
        "min_eig_Z_minus_mean": np.linalg.eigvalsh(
            Z - fading.triu_to_symmetric(res.mean, 2)).min(axis=1),
        "quad_k": np.array(qk),
        "Z_next_quadrature": np.array([_theorem33_by_quadrature(Z[k], A, c, Sw, sv2, sn2,
                                                                VECTOR["lam"]) for k in qk]),
        "window_diff": d, "window_diff_stderr": dse,
    }


def plot_vector(data: dict):
    """The entries of E[P_k] against Zbar_k (left) and the PSD order by direction (right).

    Parameters
    ----------
    data : dict
        The output of :func:`compute_vector`.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, (ax, ax2) = plotting.subplots(1, 2, stack=True)
    k = data["k"]
    names = [(0, (0, 0), "$[E P_k]_{11}$", r"$\bar Z_{k,11}$"),
             (1, (0, 1), "$[E P_k]_{12}$", r"$\bar Z_{k,12}$"),
             (2, (1, 1), "$[E P_k]_{22}$", r"$\bar Z_{k,22}$")]
    for j, (col, (a, b), mname, zname) in enumerate(names):
        color = plotting.OKABE_ITO[j]
        plotting.errorband(ax, k, data["mean_triu"][:, col], data["stderr_triu"][:, col],
                           color=color, ls="-", label=f"{mname} (MC)")
        ax.plot(k, data["Z"][:, a, b], color=color, ls="--", label=zname)
    ax.set(xlabel="time step $k$", ylabel="error covariance entries (units of $x^2$)",
           yscale="log", title=f"2-state example, Rayleigh $\\lambda$ = {VECTOR['lam']:g}; "
           f"{data['n_paths']} paths")
    ax.legend(ncol=2)
    ratio = data["mean_vPv"][-1] / data["Z_vPv"][-1]
    se = data["stderr_vPv"][-1] / data["Z_vPv"][-1]
    plotting.errorband(ax2, data["theta"], ratio, se, color=plotting.OKABE_ITO[0], ls="-",
                       label=r"$v'E[P_{100}]v\,/\,v'\bar Z_{100}v$ ± 1.96 s.e.")
    ax2.axhline(1.0, color="0.2", lw=0.8, label="bound")
    ax2.set(xlabel=r"direction $v = (\cos\theta, \sin\theta)$: angle $\theta$ (rad)",
            ylabel="ratio of quadratic forms (dimensionless)", title="PSD order, steady state")
    ax2.legend()
    return plotting.finish(fig)


def checks_vector(data: dict) -> list[Claim]:
    """E[P_k] <= Zbar_k in the PSD order, exactness at k = 1, the closed form, convergence.

    Parameters
    ----------
    data : dict
        The output of :func:`compute_vector` (or a corrupted copy, in the tests).

    Returns
    -------
    list of fusioncenter.figures.registry.Claim
        One claim per statement, each with the measured z-score or difference.
    """
    Z = data["Z"]
    iu = np.triu_indices(2)
    z1 = _abs_z(data["mean_triu"][1], data["stderr_triu"][1], Z[1][iu])
    qk = data["quad_k"]
    closed = Z[qk + 1]
    quad_rel = np.max(np.abs(closed - data["Z_next_quadrature"])) / np.max(np.abs(closed))
    conv = np.max(np.abs(Z[-1] - Z[-2])) / np.max(np.abs(Z[-1]))
    return [
        Claim("exact at k = 1 (P_0 deterministic): E[P_1] = Zbar_1 entrywise within 4 s.e.",
              bool(np.all(z1 < Z_TOL)), f"|z| = {', '.join(f'{x:.2f}' for x in z1)} "
              "(0 where the entry is deterministic)"),
        _dominance_claim(f"E[P_k] <= Zbar_k in the PSD order: v'E[P_k]v <= v'Zbar_k v + 4 s.e. "
                         f"for {N_DIRECTIONS} directions and every k",
                         data["mean_vPv"].T, data["stderr_vPv"].T, data["Z_vPv"].T),
        Claim("the closed form of Section 3.2 equals Theorem 3.3's recursion (14) evaluated by "
              "quadrature", bool(quad_rel < 1e-8), f"max relative difference {quad_rel:.1e}"),
        Claim("Zbar_k converges (|Zbar_100 - Zbar_99| <= 1e-9 |Zbar_100|)", bool(conv < 1e-9),
              f"{conv:.1e}"),
        _stationary_claim("E[tr P_k] has converged: windows [60, 80) and [80, 100] agree within "
                          "4 s.e.", [data["window_diff"]], [data["window_diff_stderr"]]),
    ]


register(Entry(
    id="dey2009-vector",
    paper="dey2009",
    kind="figure",
    caption="Vector state, scalar measurement (Section 3.2): the entries of E[P_k] by Monte "
    "Carlo against the bounding sequence Zbar_k for a 2-state example; below: the PSD order at "
    "steady state, direction by direction.",
    chapter=CH_VECTOR,
    label="sec-dey2009-vector",
    parameters={**VECTOR, "steps": STEPS, "paths": PATHS, "directions": N_DIRECTIONS,
                "block_size": BLOCK, "note": "Our own example: an unstable mode (1.25) driving "
                "a stable one (0.9), only the first state measured."},
    compute=compute_vector,
    plot=plot_vector,
    checks=checks_vector,
    status="reproduced",
    note="Our own figure (the paper has none for Section 3.2); E[P_k] <= Zbar_k in the PSD "
    "order within the stated Monte Carlo error.",
))


# ------------------------------------------------------------------ dey2009-distribution
def compute_distribution(profile: str, seed: int) -> dict:
    """Data of ``dey2009-distribution``: the law of p_k beyond its mean, for both fading laws.

    Parameters
    ----------
    profile : str
        ``"fast"`` or ``"paper"``: the number of paths (:data:`DIST_PATHS`, :data:`GRID_PATHS`).
    seed : int
        Seed of the first Monte Carlo run; later runs use ``seed + offset``.

    Returns
    -------
    dict
        Settings ``k``, ``levels`` (the quantile levels of :data:`DIST`), ``n_paths``,
        ``n_alt_paths``, ``seed``, ``p0``, ``p0_alt``, ``laws``, ``bins`` (61,) and
        ``lower_envelope`` (101,) the perfect-channel Riccati sequence; for each law ``L`` in
        ("rayleigh", "nakagami"): ``L_quantiles`` (5, 101), ``L_mean``, ``L_stderr``, ``L_s``
        (101,), ``L_density`` (60,) a histogram of p_100, and the scalars ``L_min_rel_gap``,
        ``L_ks_time``, ``L_ks_p0`` (KS p-values), ``L_above_mean``, ``L_max``,
        ``L_cdf_lo``, ``L_sf_hi``; the pooled 5 % and 95 % quantiles ``x_lo``, ``x_hi``, and
        the survival functions ``L_sf`` (40,) on the grid ``sf_x``.
    """
    s = SCALAR
    sv2 = DIST["sigma_v"] ** 2
    n = by_profile(profile, **DIST_PATHS)
    ng = by_profile(profile, **GRID_PATHS)
    levels = np.array(DIST["quantiles"])
    low = riccati.scalar_sequence(P0, s["a"], s["sigma_w2"], 1.0, sv2, STEPS)
    bins = np.geomspace(10.0, 2e4, 61)
    out: dict = {"k": np.arange(STEPS + 1), "levels": levels, "n_paths": n, "n_alt_paths": ng,
                 "seed": seed, "lower_envelope": low, "bins": bins, "p0": P0,
                 "p0_alt": DIST["p0_alt"], "laws": np.array(["rayleigh", "nakagami"])}
    finals = {}
    for j, kind in enumerate(("rayleigh", "nakagami")):
        ch = _scalar_channel(kind)
        res = fading.scalar_paths(s["a"], s["sigma_w2"], sv2, s["sigma_n2"], ch, P0, STEPS, n,
                                  seed + j, block_size=BLOCK)
        x = res.samples
        h = n // 2
        alt = fading.scalar_paths(s["a"], s["sigma_w2"], sv2, s["sigma_n2"], ch, DIST["p0_alt"],
                                  STEPS, ng, seed + 10 + j, block_size=BLOCK)
        final = x[:, -1]
        finals[kind] = final
        mean = final.mean()
        above = (final > mean).mean()
        out.update({
            f"{kind}_quantiles": np.quantile(x, levels, axis=0),
            f"{kind}_mean": res.mean, f"{kind}_stderr": res.stderr,
            f"{kind}_s": fading.scalar_bounds(s["a"], s["sigma_w2"], sv2, s["sigma_n2"], ch, P0,
                                              STEPS)["s"],
            f"{kind}_density": np.histogram(final, bins=bins, density=True)[0],
            f"{kind}_min_rel_gap": float(np.min((x[:, 1:] - low[1:]) / low[1:])),
            f"{kind}_ks_time": float(scipy.stats.ks_2samp(x[:h, 80], x[h:, -1]).pvalue),
            f"{kind}_ks_p0": float(scipy.stats.ks_2samp(final, alt.samples[:, -1]).pvalue),
            f"{kind}_above_mean": float(above),
            f"{kind}_max": float(final.max()),
        })
    pooled = np.concatenate([finals["rayleigh"], finals["nakagami"]])
    x_lo, x_hi = np.quantile(pooled, [0.05, 0.95])
    out["x_lo"], out["x_hi"] = float(x_lo), float(x_hi)
    for kind, final in finals.items():
        out[f"{kind}_cdf_lo"] = float((final <= x_lo).mean())
        out[f"{kind}_sf_hi"] = float((final > x_hi).mean())
    xs = np.geomspace(np.quantile(pooled, 0.5), pooled.max(), 40)
    out["sf_x"] = xs
    for kind, final in finals.items():
        out[f"{kind}_sf"] = (final[None, :] > xs[:, None]).mean(axis=1)
    return out


def plot_distribution(data: dict):
    """Quantile bands over time, the stationary density and its right tail, both laws.

    Parameters
    ----------
    data : dict
        The output of :func:`compute_distribution`.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, axes = plotting.subplots(1, 3, stack=True)
    k = data["k"]
    lv = data["levels"]
    names = {"rayleigh": "Rayleigh", "nakagami": "Nakagami(1/2)"}
    for j, kind in enumerate(("rayleigh", "nakagami")):
        col = plotting.OKABE_ITO[j]
        qs = data[f"{kind}_quantiles"]
        ax = axes[0]
        ax.fill_between(k, qs[0], qs[-1], color=col, alpha=0.15, linewidth=0)
        ax.fill_between(k, qs[1], qs[-2], color=col, alpha=0.25, linewidth=0)
        ax.plot(k, qs[len(lv) // 2], color=col, ls="-", label=f"{names[kind]}: median "
                f"(bands {lv[1]:.0%}-{lv[-2]:.0%}, {lv[0]:.0%}-{lv[-1]:.0%})")
        ax.plot(k, data[f"{kind}_mean"], color=col, ls="--", label=f"{names[kind]}: mean")
        centers = np.sqrt(data["bins"][1:] * data["bins"][:-1])
        axes[1].plot(centers, data[f"{kind}_density"] * centers, color=col, ls="-",
                     drawstyle="steps-mid", label=f"{names[kind]}")
        axes[1].axvline(data[f"{kind}_mean"][-1], color=col, ls="--", lw=0.8)
        axes[1].axvline(data[f"{kind}_s"][-1], color=col, ls=":", lw=0.8)
        axes[2].plot(data["sf_x"], data[f"{kind}_sf"], color=col, ls="-",
                     marker=plotting.MARKERS[j], mfc="none", label=names[kind])
    axes[0].plot(k, data["lower_envelope"], color="0.3", lw=0.8, ls=":",
                 label="sure lower envelope (perfect channel)")
    axes[0].set(xlabel="time step $k$", ylabel="$p_k$ (units of $x^2$)", yscale="log",
                title=f"quantiles over time; {data['n_paths']} paths")
    axes[0].legend()
    axes[1].set(xscale="log", xlabel=r"$p_{100}$ (units of $x^2$)",
                ylabel=r"density of $\ln p_{100}$ (dimensionless)",
                title="steady state (dashed: mean, dotted: bound $s^*$)")
    axes[1].legend()
    axes[2].set(xscale="log", yscale="log", xlabel=r"$x$ (units of $x^2$)",
                ylabel=r"$P(p_{100} > x)$ (dimensionless)", title="upper tail")
    _plain_log_ticks(axes[2].xaxis)
    axes[2].legend()
    return plotting.finish(fig, title=rf"Distribution of $p_k$: $\sigma_v = {DIST['sigma_v']:g}$,"
                           rf" $\lambda = {SCALAR['lam']:g}$, $E[p_0] = {data['p0']:g}$")


def checks_distribution(data: dict) -> list[Claim]:
    """Lower envelope, stationarity, independence of p_0, skewness and the tails.

    Parameters
    ----------
    data : dict
        The output of :func:`compute_distribution` (or a corrupted copy, in the tests).

    Returns
    -------
    list of fusioncenter.figures.registry.Claim
        One claim per statement, with the measured p-values, fractions or z-scores.
    """
    n = data["n_paths"]
    claims = [
        Claim("every sampled p_k is above the sure lower envelope (the Riccati recursion of a "
              "perfect channel, r -> inf)",
              bool(min(data["rayleigh_min_rel_gap"], data["nakagami_min_rel_gap"])
                   >= -REL_SLACK),
              f"min over paths and k >= 1 of (p_k - l_k) / l_k: "
              f"{data['rayleigh_min_rel_gap']:.3e} (Rayleigh), "
              f"{data['nakagami_min_rel_gap']:.3e} (Nakagami)"),
        Claim(f"stationary by k = 80: two-sample KS (disjoint halves of the paths) of p_80 vs "
              f"p_100 does not reject at level {KS_LEVEL:g}",
              bool(min(data["rayleigh_ks_time"], data["nakagami_ks_time"]) > KS_LEVEL),
              f"p-values {data['rayleigh_ks_time']:.3f}, {data['nakagami_ks_time']:.3f}"),
        Claim(f"the stationary law does not depend on p_0: KS of p_100 from p_0 = {P0:g} vs "
              f"p_0 = {data['p0_alt']:g} does not reject at level {KS_LEVEL:g}",
              bool(min(data["rayleigh_ks_p0"], data["nakagami_ks_p0"]) > KS_LEVEL),
              f"p-values {data['rayleigh_ks_p0']:.3f}, {data['nakagami_ks_p0']:.3f}"),
    ]
    za = [(0.5 - data[f"{k}_above_mean"]) / np.sqrt(0.25 / n) for k in ("rayleigh", "nakagami")]
    claims.append(Claim("right-skewed: P(p_100 > E[p_100]) < 1/2 by more than 4 binomial s.e.",
                        bool(min(za) > Z_TOL),
                        f"{data['rayleigh_above_mean']:.3f}, {data['nakagami_above_mean']:.3f} "
                        f"(z = {za[0]:.1f}, {za[1]:.1f})"))

    def two_prop(p1, p2):
        se = np.sqrt(p1 * (1 - p1) / n + p2 * (1 - p2) / n)
        return (p1 - p2) / se if se > 0 else 0.0
    z_lo = two_prop(data["nakagami_cdf_lo"], data["rayleigh_cdf_lo"])
    z_hi = two_prop(data["nakagami_sf_hi"], data["rayleigh_sf_hi"])
    claims.append(Claim(
        "Nakagami(1/2) spreads p more, not just shifts it: more mass below the pooled 5% "
        "quantile AND above the pooled 95% quantile than Rayleigh (> 4 s.e. each)",
        bool(z_lo > Z_TOL and z_hi > Z_TOL),
        f"P(p <= {data['x_lo']:.1f}): {data['nakagami_cdf_lo']:.3f} vs "
        f"{data['rayleigh_cdf_lo']:.3f} (z = {z_lo:.1f}); P(p > {data['x_hi']:.1f}): "
        f"{data['nakagami_sf_hi']:.3f} vs {data['rayleigh_sf_hi']:.3f} (z = {z_hi:.1f})"))
    zm = _max_finite(np.concatenate([
        _excess_z(data[f"{k}_mean"][1:], data[f"{k}_stderr"][1:], data[f"{k}_s"][1:])
        for k in ("rayleigh", "nakagami")]))
    claims.append(Claim("the mean of the distribution stays below the tight bound s_k (4 s.e.)",
                        bool(zm < Z_TOL), f"max z = {zm:.2f}"))
    return claims


register(Entry(
    id="dey2009-distribution",
    paper="dey2009",
    kind="figure",
    caption="Beyond the mean: the distribution of p_k over time (quantile bands) and at steady "
    "state (density of log p and upper tail) for Rayleigh and Nakagami(1/2) fading, Fig. 1's "
    "channel with sigma_v = 1.",
    chapter=CH_DIST,
    label="sec-dey2009-distribution",
    parameters={**SCALAR, "sigma_v": DIST["sigma_v"], "E[p_0]": P0, "p0_alt": DIST["p0_alt"],
                "quantiles": list(DIST["quantiles"]), "steps": STEPS, "paths": DIST_PATHS,
                "alt_paths": GRID_PATHS, "block_size": BLOCK, "ks_level": KS_LEVEL},
    compute=compute_distribution,
    plot=plot_distribution,
    checks=checks_distribution,
    status="reproduced",
    note="Our own figure: the paper leaves the distribution of the error covariance as future "
    "work.",
))
