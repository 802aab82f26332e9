"""Part II's explorable figure, ``dey2009-explore``: the mean power gain of a Rayleigh channel.

One sensor, a scalar state and the parameters of the paper's Fig. 1 with σᵥ = 1 and
``p₀ = 1``, at the mean power gain ``1/λ`` of the slider (the paper's ``λ = 100`` is a mean
gain of 0.01): the Monte Carlo mean ``E[p_k]`` with its standard-error band between two
deterministic sequences,

- above, the tight bound ``s_k`` (17) and the loose bound ``q_k`` (18) of the library
  (:func:`fusioncenter.fading.scalar_bounds`);
- below, the Riccati sequence of a perfect channel (``r → ∞``), ``ℓ_{k+1} = σ_w² +
  a² ℓ_k σᵥ²/(ℓ_k + σᵥ²)`` from ``ℓ₀ = p₀`` (:func:`fusioncenter.riccati.scalar_sequence`).
  It is a lower bound on every path, not only on the mean: the posterior variance
  ``p (r σᵥ² + σₙ²)/(r (p + σᵥ²) + σₙ²)`` decreases in ``r`` (its derivative in ``r`` has the
  sign of ``−σₙ² p``) towards ``p σᵥ²/(p + σᵥ²)``, and increases in ``p``, so ``p_k ≥ ℓ_k``
  by induction. (The deterministic sequence with the *mean* gain is not a bound: the
  posterior variance is convex in the channel but concave in ``p``, and the two Jensen steps
  point in opposite directions.)

Every frame uses the same seed, so the paths of two frames differ only by the scale of the
channel draws (``r = e/λ`` with the same exponential ``e``): a larger mean gain lowers every
path, and the Monte Carlo means fall exactly, not only in expectation.
"""

from __future__ import annotations

import functools

import numpy as np

from fusioncenter import context, fading, plotting, riccati
from fusioncenter.context import Parameter
from fusioncenter.figures import common
from fusioncenter.figures.dey2009.common import (
    BLOCK,
    CH_SCALAR,
    P0,
    REL_SLACK,
    SCALAR,
    STEPS,
    Z_TOL,
    abs_z,
    converged_claim,
    dominance_claim,
    excess_z,
    max_finite,
)
from fusioncenter.figures.explorable import declare
from fusioncenter.figures.registry import Claim

OWN_IDS = ("dey2009-explore",)

#: The measurement noise of the figure (Fig. 1's first σᵥ).
SIGMA_V = 1.0
#: The slider's grid: the mean power gain 1/λ = 10^(k/3), k = -9..6 (10⁻³ to 100; the
#: paper's λ = 100 is the fourth value, 0.01).
GAINS = tuple(float(10.0 ** (k / 3)) for k in range(-9, 7))
#: The steady-state curves of panel (b): 41 gains from 10⁻³ to 100 (the same in every frame).
CURVE_GAINS = np.geomspace(1e-3, 1e2, 41)
#: Monte Carlo paths per frame (the paper's Fig. 1 has 50 000 for three curves).
PATHS = {"fast": 1_000, "paper": 10_000}
#: The vertical range of both panels (the same in every frame).
YLIM = (1.0, 2e4)
SETTABLE = (
    Parameter("mean_gain", "float", "mean power gain 1/λ of the Rayleigh channel "
              "(dimensionless)", 0.01, minimum=0.0, exclusive_minimum=True, model=True),
    common.trials_parameter(PATHS, "Monte Carlo paths of E[p_k]", name="paths"),
)
#: The slider over the grid: its text beside the value, the first frame and those of print.
SLIDER = {"parameter": "mean_gain", "values": GAINS,
          "label": "mean power gain 1/λ of the channel (dimensionless)", "symbol": "1/λ",
          "fmt": "{:.3g}", "start": 3, "print_at": (0, 3, 9, 15)}


def _model(gain: float) -> tuple:
    s = SCALAR
    return s["a"], s["sigma_w2"], SIGMA_V**2, s["sigma_n2"], fading.Rayleigh(1.0 / gain)


@functools.cache
def _limit_curve() -> tuple[tuple[float, ...], tuple[float, ...]]:
    """``(s*, q*)`` at :data:`CURVE_GAINS` (root finding; computed once per process)."""
    lims = [fading.scalar_bound_limits(*_model(g)) for g in CURVE_GAINS]
    return tuple(float(x["s"]) for x in lims), tuple(float(x["q"]) for x in lims)


@common.compute_doc("""``mean_gain`` and ``lam`` (= 1/mean_gain); ``k`` (101,) the steps;
             ``mean``, ``stderr`` (101,) the Monte Carlo ``E[p_k]``; ``s``, ``q`` (101,) the
             tight and loose bounds and ``s_limit``, ``q_limit`` their fixed points;
             ``lower`` (101,) the perfect channel's Riccati sequence and ``lower_limit`` its
             steady state; ``min_lower_gap`` the smallest ``(p_k - lower_k)/lower_k`` over
             every path and step; ``n_paths``; ``curve_gain``, ``curve_s``, ``curve_q`` (41,)
             the fixed points along the gain.""",
             profile="Sets the number of paths (:data:`PATHS`).")
def compute(profile: str, seed: int, **over) -> dict:
    """Data of ``dey2009-explore``: ``E[p_k]`` and its bounds at one mean gain."""
    par = common.settings("dey2009-explore", SETTABLE, profile, over)
    gain, n = float(par["mean_gain"]), int(par["paths"])
    model = _model(gain)
    res = fading.scalar_paths(*model, P0, STEPS, n, seed, block_size=BLOCK,
                              executor=context.executor())
    bounds = fading.scalar_bounds(*model, P0, STEPS)
    limits = fading.scalar_bound_limits(*model)
    s = SCALAR
    lower = riccati.scalar_sequence(P0, s["a"], s["sigma_w2"], 1.0, SIGMA_V**2, STEPS)
    curve_s, curve_q = _limit_curve()
    return {
        "mean_gain": gain, "lam": 1.0 / gain, "k": np.arange(STEPS + 1),
        "mean": res.mean, "stderr": res.stderr, "s": bounds["s"], "q": bounds["q"],
        "s_limit": float(limits["s"]), "q_limit": float(limits["q"]),
        "lower": lower,
        "lower_limit": float(riccati.scalar_steady_state(s["a"], s["sigma_w2"], 1.0,
                                                         SIGMA_V**2)),
        "min_lower_gap": float(np.min((res.samples - lower) / lower)),
        "n_paths": n, "curve_gain": CURVE_GAINS.copy(), "curve_s": np.array(curve_s),
        "curve_q": np.array(curve_q),
    }


@common.plot_doc()
def plot(data: dict):
    """Two panels: (a) ``E[p_k]`` between its bounds against ``k``; (b) the limits against the
    mean gain, with this frame's Monte Carlo ``E[p₁₀₀]``."""
    fig, (ax1, ax2) = plotting.subplots(2, 1, stack=True)
    k = data["k"]
    plotting.errorband(ax1, k, data["mean"], data["stderr"], color=plotting.OKABE_ITO[1],
                       label=r"Monte Carlo $E[p_k]$ ± 1.96 s.e.")
    ax1.plot(k, data["q"], label=r"loose bound $q_k$ (18)", **plotting.look(quantity="loose-bound"))
    ax1.plot(k, data["s"], label=r"tight bound $s_k$ (17)", **plotting.look(quantity="tight-bound"))
    ax1.plot(k, data["lower"], label=r"lower bound $\ell_k$: perfect channel",
             **plotting.look(quantity="lower-bound"))
    ax1.set_yscale("log")
    ax1.set(xlim=(0, k[-1]), ylim=YLIM, xlabel="time step $k$ (steps)",
            ylabel=r"$E[p_k]$ and its bounds (units of $x^2$)",
            title=f"(a) mean power gain 1/λ = {data['mean_gain']:.3g} (λ = {data['lam']:.3g});"
                  f" {data['n_paths']} paths")
    ax1.legend(loc="upper right", ncol=2)
    g = data["curve_gain"]
    ax2.plot(g, data["curve_q"], label=r"loose limit $q^*$", **plotting.look(quantity="limit",
                                                                           ls=":"))
    ax2.plot(g, data["curve_s"], label=r"tight limit $s^*$", **plotting.look(quantity="limit",
                                                                           ls="--"))
    ax2.axhline(data["lower_limit"], label=r"lower bound $\bar p$: perfect channel",
                **plotting.look(quantity="lower-bound"))
    ax2.errorbar([data["mean_gain"]], [data["mean"][-1]], yerr=[1.96 * data["stderr"][-1]],
                 marker="o", ms=8, ls="none", color=plotting.OKABE_ITO[1], capsize=3,
                 label=r"Monte Carlo $E[p_{100}]$ at this gain")
    ax2.axvline(data["mean_gain"], color="0.6", lw=0.8)
    ax2.set(xscale="log", yscale="log", xlim=(g[0], g[-1]), ylim=YLIM,
            xlabel=r"mean power gain $1/\lambda$ (dimensionless)",
            ylabel=r"limit as $k \to \infty$ (units of $x^2$)",
            title=f"(b) E[p₁₀₀] = {data['mean'][-1]:.3g}, s* = {data['s_limit']:.3g}, "
                  f"q* = {data['q_limit']:.3g}")
    ax2.legend(loc="upper right", ncol=2)
    return plotting.finish(fig)


@common.checks_doc()
def checks(data: dict) -> list[Claim]:
    """Theorem 3.4's ordering and convergence, and the perfect channel below every path."""
    k1 = float(abs_z(data["mean"][1], data["stderr"][1], data["s"][1]))
    return [
        dominance_claim("E[pₖ] ≤ sₖ at every k (MC mean − 4 s.e.)", data["mean"],
                         data["stderr"], data["s"]),
        Claim("sₖ ≤ qₖ at every k (tight below loose)",
              bool(np.all(data["s"] <= data["q"] * (1 + REL_SLACK))),
              f"smallest qₖ/sₖ = {float(np.min(data['q'][1:] / data['s'][1:])):.4f}"),
        Claim("the perfect channel's Riccati sequence ℓₖ lies below every path pₖ",
              data["min_lower_gap"] >= -REL_SLACK,
              f"smallest (pₖ − ℓₖ)/ℓₖ over {data['n_paths']} paths: "
              f"{data['min_lower_gap']:.2e}"),
        Claim("the tight bound is exact at k = 1 (p₀ deterministic): E[p₁] = s₁ within 4 s.e.",
              k1 < Z_TOL, f"|z| = {k1:.2f}"),
        converged_claim("sₖ and qₖ reach their fixed points s*, q* by k = 100",
                         {"s": data["s"], "q": data["q"]},
                         {"s": data["s_limit"], "q": data["q_limit"]}),
    ]


def _facts(data: dict) -> dict[str, str]:
    mean, se = data["mean"][-1], data["stderr"][-1]
    return {"lam": f"{data['lam']:.3g}", "mean": f"{mean:.4g}", "se": f"{se:.2g}",
            "s_limit": f"{data['s_limit']:.4g}", "q_limit": f"{data['q_limit']:.4g}",
            "gap": f"{100 * (data['s_limit'] / mean - 1):.1f}",
            "lower": f"{data['lower_limit']:.3f}", "paths": f"{data['n_paths']}"}


def _decreasing(values) -> bool:
    return bool(np.all(np.diff(np.asarray(values, dtype=float)) < 0))


@declare.sweep_doc("""``ℓₖ ≤ E[pₖ] ≤ sₖ ≤ qₖ`` at every gain and step (the upper side
                   within 4 s.e.); ``E[p₁₀₀]`` falls from one gain to the next; ``s*`` and
                   ``q*`` fall and stay above the perfect channel's ``p̄``.""",
                   gains=("tuple of float", "The slider's mean power gains, increasing."))
def sweep(gains, frames) -> list[Claim]:
    """Along the slider: the bounds enclose the mean at every gain, and everything falls."""
    z = max(max_finite(excess_z(f["mean"][1:], f["stderr"][1:], f["s"][1:])) for f in frames)
    low = min(f["min_lower_gap"] for f in frames)
    order = all(np.all(f["s"] <= f["q"] * (1 + REL_SLACK)) for f in frames)
    mean = [f["mean"][-1] for f in frames]
    s_lim = [f["s_limit"] for f in frames]
    q_lim = [f["q_limit"] for f in frames]
    p_bar = frames[0]["lower_limit"]
    return [
        Claim(f"the bounds enclose the Monte Carlo mean at all {len(frames)} mean gains: "
              "ℓₖ ≤ E[pₖ] ≤ sₖ ≤ qₖ at every k (upper side within 4 s.e.)",
              bool(z < Z_TOL and low >= -REL_SLACK and order),
              f"largest z of E[pₖ] above sₖ {z:.2f}; smallest (pₖ − ℓₖ)/ℓₖ on a path "
              f"{low:.2e}"),
        Claim("the mean E[p₁₀₀] falls as the mean gain grows", _decreasing(mean),
              f"{mean[0]:.4g} at 1/λ = {gains[0]:.3g} down to {mean[-1]:.4g} at "
              f"1/λ = {gains[-1]:.3g}"),
        Claim("the limits s* and q* fall as the mean gain grows and stay above the perfect "
              "channel's p̄",
              bool(_decreasing(s_lim) and _decreasing(q_lim) and min(s_lim) > p_bar),
              f"s* from {s_lim[0]:.4g} to {s_lim[-1]:.4g}, q* from {q_lim[0]:.4g} to "
              f"{q_lim[-1]:.4g}; p̄ = {p_bar:.4f}"),
    ]


declare.register(
    id="dey2009-explore",
    paper="dey2009",
    caption="One sensor over a Rayleigh channel, at the mean power gain 1/λ of the slider "
    "(Fig. 1's parameters, σᵥ = 1, p₀ = 1): the Monte Carlo mean E[pₖ] between the perfect "
    "channel's Riccati sequence below and the tight (17) and loose (18) bounds above, and "
    "the limits of the bounds against the mean gain.",
    chapter=CH_SCALAR,
    label="sec-dey2009-sb-explore",
    parameters={**SCALAR, "sigma_v": SIGMA_V, "E[p_0]": P0, "steps": STEPS, "paths": PATHS,
                "block_size": BLOCK, "mean_gain_grid": list(GAINS)},
    functions=(compute, plot, checks, sweep, _facts),
    settable=SETTABLE,
    note="Our own figure, on the parameters of the paper's Fig. 1 (σᵥ = 1 and p₀ = 1 are our "
    "choice, as there); the lower bound is ours (a perfect channel), the upper bounds are "
    "the paper's (17)-(18).",
    slider=SLIDER,
)
