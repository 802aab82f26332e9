"""Part II (dey2009): the parameters shared by the figures and the checks they share.

The paper leaves some parameters out (Figs. 1-2: the sigma_v values and E[p_0]; Figs. 3-4:
lambda_1, lambda_2). Our choices are in :data:`SIGMA_V`, :data:`P0` and :data:`LAMS`.
"""

from __future__ import annotations

import matplotlib.ticker
import numpy as np

from fusioncenter import context, fading
from fusioncenter.context import Parameter
from fusioncenter.figures.registry import Claim
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

#: The note of an entry whose parameters are partly our choice ({what}, {grid} filled in).
NOTE_CHOICE = ("Our choice: the paper does not state {what}. The checks re-run the claims on a "
                "grid of alternatives ({grid}) and they hold on every one.")


# ---------------------------------------------------------------------------- shared checks
def excess_z(mean, se, bound) -> np.ndarray:
    """z-scores of ``mean - bound`` (``+inf`` where a zero-error mean exceeds the bound).

    Parameters
    ----------
    mean, se, bound : array_like
        Monte Carlo means, their standard errors and the bound (broadcast together).

    Returns
    -------
    numpy.ndarray
        ``(mean - bound - REL_SLACK |bound|) / se``; where ``se = 0``, ``+inf`` if the mean is
        above the bound and ``-inf`` otherwise.
    """
    mean, se, bound = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (mean, se, bound)))
    excess = mean - bound - REL_SLACK * np.abs(bound)
    with np.errstate(divide="ignore", invalid="ignore"):
        z = np.where(se > 0, excess / np.where(se > 0, se, 1.0),
                     np.where(excess > 0, np.inf, -np.inf))
    return z


def abs_z(mean, se, ref) -> np.ndarray:
    """``|mean - ref| / se``, 0 where the difference is within rounding of a zero-error mean.

    Parameters
    ----------
    mean, se, ref : array_like
        Monte Carlo means, their standard errors and the reference values.

    Returns
    -------
    numpy.ndarray
        The absolute z-scores (``inf`` where ``se = 0`` and the difference is not rounding).
    """
    mean, se, ref = (np.asarray(x, dtype=float) for x in (mean, se, ref))
    diff = np.maximum(np.abs(mean - ref) - REL_SLACK * np.abs(ref), 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(se > 0, diff / np.where(se > 0, se, 1.0), np.where(diff > 0, np.inf, 0.0))


def max_finite(z) -> float:
    """The largest z-score, ``inf`` if any is ``+inf``, ignoring ``-inf`` and NaN.

    Parameters
    ----------
    z : array_like
        z-scores, e.g. of :func:`excess_z`.

    Returns
    -------
    float
        ``inf``, the largest finite value, or ``-inf`` if there is none.
    """
    z = np.asarray(z, dtype=float)
    if np.any(np.isposinf(z)):
        return float("inf")
    fin = z[np.isfinite(z)]
    return float(fin.max()) if fin.size else float("-inf")


def window_stats(samples: np.ndarray) -> tuple[float, float]:
    """Mean and s.e. of the per-path difference of the two window averages of :data:`WINDOWS`.

    Parameters
    ----------
    samples : numpy.ndarray
        ``(paths, steps + 1)`` sampled sequences.

    Returns
    -------
    tuple of float
        The mean difference (late window minus early window) and its standard error.
    """
    (a0, a1), (b0, b1) = WINDOWS
    d = samples[:, b0:b1].mean(axis=1) - samples[:, a0:a1].mean(axis=1)
    return float(d.mean()), float(d.std(ddof=1) / np.sqrt(d.size))


def dominance_claim(name: str, mean, se, bound) -> Claim:
    """The claim "``mean <= bound`` within :data:`Z_TOL` s.e." at every ``k >= 1``.

    Parameters
    ----------
    name : str
        The claim's text.
    mean, se, bound : numpy.ndarray
        Monte Carlo means, their standard errors and the bound, time along the last axis.

    Returns
    -------
    fusioncenter.figures.registry.Claim
        With the largest z-score and the smallest relative gap in its detail.
    """
    z = excess_z(mean[..., 1:], se[..., 1:], bound[..., 1:])
    zmax = max_finite(z)
    gap = (np.asarray(bound)[..., 1:] - np.asarray(mean)[..., 1:]) / np.asarray(bound)[..., 1:]
    return Claim(name, bool(zmax < Z_TOL),
                 f"max z = {zmax:.2f} (MC mean above the bound in s.e.); smallest relative gap "
                 f"{float(np.min(gap)):.4f}")


def stationary_claim(name: str, diff, diff_se, paper_specific: bool = False) -> Claim:
    """The claim "the window averages of :func:`window_stats` agree within :data:`Z_TOL` s.e.".

    Parameters
    ----------
    name : str
        The claim's text.
    diff, diff_se : array_like
        Window differences and their standard errors.
    paper_specific : bool
        Whether the claim is about the entry's own setting (see
        :class:`fusioncenter.figures.registry.Claim`).

    Returns
    -------
    fusioncenter.figures.registry.Claim
        With the z-scores in its detail.
    """
    z = np.asarray(diff) / np.asarray(diff_se)
    return Claim(name, bool(np.all(np.abs(z) < Z_TOL)),
                 f"window differences z = {', '.join(f'{x:.2f}' for x in np.ravel(z))}",
                 paper_specific=paper_specific)


def converged_claim(name: str, seqs: dict, limits: dict) -> Claim:
    """The claim "each sequence's last value is its limit (relative 1e-6)".

    Parameters
    ----------
    name : str
        The claim's text.
    seqs, limits : dict
        Sequences (time along the last axis) and their fixed points, by the same names.

    Returns
    -------
    fusioncenter.figures.registry.Claim
        With the relative differences in its detail.
    """
    rel = {k: abs(seqs[k][..., -1] - limits[k]) / limits[k] for k in seqs}
    worst = max(float(np.max(v)) for v in rel.values())
    return Claim(name, worst <= 1e-6,
                 "; ".join(f"|{k}₁₀₀ − {k}*|/{k}* ≤ {float(np.max(v)):.1e}"
                           for k, v in rel.items()))


def plain_log_ticks(axis) -> None:
    """Plain numbers at 1, 2, 5 x 10^k on a log axis that spans only a few decades.

    Parameters
    ----------
    axis : matplotlib.axis.Axis
        The log-scaled axis (``ax.xaxis`` or ``ax.yaxis``).

    Returns
    -------
    None
    """
    axis.set_major_locator(matplotlib.ticker.LogLocator(base=10.0, subs=(1.0, 2.0, 5.0)))
    axis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
    axis.set_minor_formatter(matplotlib.ticker.NullFormatter())



def scalar_channel(kind: str):
    """The fading law of Figs. 1-2 with :data:`SCALAR`'s ``lam``.

    Parameters
    ----------
    kind : str
        ``"rayleigh"`` or ``"nakagami"`` (Nakagami with m = 1/2).

    Returns
    -------
    fusioncenter.fading.Rayleigh or fusioncenter.fading.Nakagami
    """
    lam = SCALAR["lam"]
    return fading.Rayleigh(lam) if kind == "rayleigh" else fading.Nakagami(0.5, lam)


#: The overridable parameters of Figs. 1-4 (Monte Carlo accuracy only: every claim applies).
SETTABLE_PATHS = (
    Parameter("paths", "int", "Monte Carlo paths of each main curve", dict(PATHS), minimum=2),
    Parameter("grid_paths", "int", "Monte Carlo paths of each point of the parameter grid",
              dict(GRID_PATHS), minimum=2),
)


def mc_paths(profile: str, over: dict) -> tuple[int, int]:
    """The paths of the main curves and of the grid points of a run.

    Parameters
    ----------
    profile : str
        ``"fast"`` or ``"paper"``.
    over : dict
        The overrides (``paths``, ``grid_paths`` of :data:`SETTABLE_PATHS`).

    Returns
    -------
    tuple of int
        ``(paths, grid_paths)``: the overrides, else :data:`PATHS` and :data:`GRID_PATHS`.
    """
    return (over.get("paths") or by_profile(profile, **PATHS),
            over.get("grid_paths") or by_profile(profile, **GRID_PATHS))


def bounded_runs(settings, model, paths, bounds, limits, names, n: int, seed: int,
                 keep_window: bool) -> dict:
    """Monte Carlo ``E[p_k]`` and the bound sequences of each setting, stacked by rows.

    Parameters
    ----------
    settings : sequence
        The settings (one row each).
    model : callable
        ``model(setting) -> (args, p0)``: the model arguments of ``paths``, ``bounds`` and
        ``limits`` and the initial value.
    paths, bounds, limits : callable
        ``paths(*args, p0, STEPS, n, seed, block_size=, executor=)`` (a
        :class:`fusioncenter.montecarlo.MonteCarloResult`), ``bounds(*args, p0, STEPS)`` and
        ``limits(*args)`` (dicts of the bound sequences and of their fixed points), e.g.
        :func:`fusioncenter.fading.scalar_paths`, :func:`fusioncenter.fading.scalar_bounds`,
        :func:`fusioncenter.fading.scalar_bound_limits`.
    names : tuple of str
        The bounds to keep (``("s", "q")`` or ``("s", "t")``).
    n, seed : int
        Paths per setting, and the seed of the first setting (then ``seed + i``).
    keep_window : bool
        Also keep the statistic of :func:`window_stats`.

    Returns
    -------
    dict
        ``mean``, ``stderr`` (settings, STEPS + 1); each bound of ``names`` (settings,
        STEPS + 1) and its limit ``<name>_limit`` (settings,); with ``keep_window``,
        ``window_diff`` and ``window_diff_stderr`` (settings,).
    """
    cols: dict = {k: [] for k in ("mean", "stderr", *names, *(f"{b}_limit" for b in names))}
    wd, wse = [], []
    for i, setting in enumerate(settings):
        args, p0 = model(setting)
        res = paths(*args, p0, STEPS, n, seed + i, block_size=BLOCK,
                    executor=context.executor())
        cols["mean"].append(res.mean)
        cols["stderr"].append(res.stderr)
        b, lim = bounds(*args, p0, STEPS), limits(*args)
        for name in names:
            cols[name].append(b[name])
            cols[f"{name}_limit"].append(lim[name])
        if keep_window:
            d, dse = window_stats(res.samples)
            wd.append(d)
            wse.append(dse)
    out = {k: np.array(v) for k, v in cols.items()}
    if keep_window:
        out["window_diff"] = np.array(wd)
        out["window_diff_stderr"] = np.array(wse)
    return out
