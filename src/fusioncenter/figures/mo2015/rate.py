"""``mo2015-rate``: the communication rate of the stochastic trigger against ``delta``.

The rate of each sensor of the static example in closed form (the notes' zero-mean formula and
our extension to a non-zero prior mean) and by simulation, at the trigger parameters
:data:`RATE_DELTAS`.
"""

from __future__ import annotations

import functools

import numpy as np

from fusioncenter import event, montecarlo, plotting
from fusioncenter.figures import common
from fusioncenter.figures.mo2015.static import (
    EXAMPLE,
    Z_TOL,
    draw_example,
    example,
    output_variances,
)
from fusioncenter.figures.registry import Claim

CHAPTER_RATE = "book/mo2015/rate"
#: Trigger parameters (the same for every sensor) at which the rate is simulated.
RATE_DELTAS = np.geomspace(0.02, 50.0, 13)
RATE_TRIALS = {"fast": 4_000, "paper": 100_000}
#: The overridable parameter (``--set key=value``).
SETTABLE_RATE = (common.trials_parameter(RATE_TRIALS,
                                         "Monte Carlo draws of the example's measurements"),)


def _rate_chunk(rng: np.random.Generator, n: int, *, deltas) -> np.ndarray:
    """``gamma`` at every ``delta``, for prior mean 0 and ``xbar``: ``(n, D, 2, m)``.

    The same ``(x - xbar, v, xi)`` serve every ``delta`` and both means (common random numbers),
    so each trial's ``gamma`` is non-increasing in ``delta``.
    """
    xbar, _, C, _ = example()
    x, y, xi = draw_example(rng, n)
    y0 = y - C @ xbar  # the same draw with prior mean 0
    deltas = np.asarray(deltas, dtype=float)[None, :, None]
    g0 = xi[:, None, :] > np.exp(-(y0[:, None, :] ** 2) / (2 * deltas))
    g1 = xi[:, None, :] > np.exp(-(y[:, None, :] ** 2) / (2 * deltas))
    return np.stack([g0, g1], axis=2).astype(float)


@common.compute_doc("""``s`` (m,) the output variances and ``mu`` (m,) the prior means ``a_i xbar``;
             ``delta_fine`` (201,) and on it ``rate_zero_mean``, ``rate_xbar`` (201, m) the
             closed-form rates, ``rate_notes`` the notes' formula, ``delta_back_zero_mean``,
             ``delta_back_xbar`` the deltas recovered from the rates; ``delta_mc`` (D,) and
             ``rate_mc``, ``rate_mc_stderr``, ``rate_closed_at_mc`` (D, 2, m) the simulated and
             closed-form rates (prior mean 0, then ``xbar``); ``n_trials``, ``seed``.""")
def compute_rate(profile: str, seed: int, **over) -> dict:
    """Data of ``mo2015-rate``: each sensor's communication rate against ``delta``, in closed
    form and by simulation (the same draws at every ``delta``), for prior mean 0 and ``xbar``."""
    xbar, Sigma, C, r = example()
    s = output_variances(Sigma, C, r)
    mu = C @ xbar
    fine = np.geomspace(0.01, 100.0, 201)
    rate0 = np.array([event.communication_rate(Sigma, C, r, d) for d in fine])
    rate1 = np.array([event.communication_rate(Sigma, C, r, d, xbar) for d in fine])
    notes = 1.0 - 1.0 / np.sqrt(1.0 + s[None, :] / fine[:, None])  # the notes' formula, verbatim
    back0 = event.delta_for_rate(rate0, s[None, :], 0.0)
    back1 = event.delta_for_rate(rate1, s[None, :], mu[None, :])
    n = common.settings("mo2015-rate", SETTABLE_RATE, profile, over)["trials"]
    res = montecarlo.simulate(functools.partial(_rate_chunk, deltas=RATE_DELTAS), n, seed)
    closed = np.stack([np.array([event.communication_rate(Sigma, C, r, d) for d in RATE_DELTAS]),
                       np.array([event.communication_rate(Sigma, C, r, d, xbar)
                                 for d in RATE_DELTAS])], axis=1)  # (D, 2, m)
    return {
        "s": s, "mu": mu,
        "delta_fine": fine, "rate_zero_mean": rate0, "rate_xbar": rate1, "rate_notes": notes,
        "delta_back_zero_mean": back0, "delta_back_xbar": back1,
        "delta_mc": RATE_DELTAS.copy(),
        "rate_mc": res.mean, "rate_mc_stderr": res.stderr, "rate_closed_at_mc": closed,
        "n_trials": res.n_trials, "seed": seed,
    }


@common.plot_doc()
def plot_rate(data: dict):
    """Rate against ``delta`` per sensor, panel (a) prior mean 0 and panel (b) ``xbar``, with the
    Monte Carlo points."""
    fig, axes = plotting.subplots(1, 2, sharey=True, stack=True)
    titles = [r"prior mean $\bar x = 0$ (the notes)",
              r"prior mean $\bar x = (1, -1)$ (extension)"]
    keys = ["rate_zero_mean", "rate_xbar"]
    for j, ax in enumerate(axes):
        for i in range(len(data["s"])):
            label = f"sensor {i + 1}: closed form ($s_{i + 1}$ = {data['s'][i]:.1f}"
            if j == 1:
                label += f", $\\mu_{i + 1}$ = {data['mu'][i]:g}"
            line = ax.semilogx(data["delta_fine"], data[keys[j]][:, i], label=label + ")")[0]
            if j == 1:
                ax.semilogx(data["delta_fine"], data["rate_zero_mean"][:, i], lw=0.8, ls=":",
                            color=line.get_color(),
                            label=r"dotted: the same sensor with $\bar x = 0$" if i == 0
                            else None)
            ax.errorbar(data["delta_mc"], data["rate_mc"][:, j, i],
                        yerr=1.96 * data["rate_mc_stderr"][:, j, i], ls="none",
                        marker=plotting.MARKERS[i], color=line.get_color(), mfc="none",
                        capsize=2)
        ax.errorbar([], [], yerr=[], ls="none", marker="o", mfc="none", color="0.3",
                    label=f"Monte Carlo ± 1.96 s.e. ({data['n_trials']} trials)")
        ax.set(xlabel=r"trigger parameter $\delta$ (units of $y^2$)",
               ylabel=r"communication rate $P(\gamma_i = 1)$", title=titles[j])
        ax.legend()
    return plotting.finish(fig)


@common.checks_doc()
def checks_rate(data: dict) -> list[Claim]:
    """The notes' formula, the simulation, monotonicity in ``delta``, the effect of the prior
    mean and the inversion by ``delta_for_rate``."""
    # The z-scores share their draws (common random numbers across delta and the two means), so
    # they are strongly correlated: we check each one, not a chi-square sum of them.
    z = (data["rate_mc"] - data["rate_closed_at_mc"]) / data["rate_mc_stderr"]
    dof = z.size
    notes_err = float(np.max(np.abs(data["rate_zero_mean"] - data["rate_notes"])))
    fine = data["delta_fine"][:, None]
    rt0 = float(np.max(np.abs(data["delta_back_zero_mean"] / fine - 1)))
    rt1 = float(np.max(np.abs(data["delta_back_xbar"] / fine - 1)))
    dec_closed = bool(np.all(np.diff(data["rate_zero_mean"], axis=0) < 0)
                      and np.all(np.diff(data["rate_xbar"], axis=0) < 0))
    dec_mc = bool(np.all(np.diff(data["rate_mc"], axis=0) <= 0))
    zero_mu = data["mu"] == 0
    gap = data["rate_xbar"] - data["rate_zero_mean"]
    return [
        Claim("library rate at x̄ = 0 equals the notes' 1 − 1/√(1 + s/δ)",
              notes_err < 1e-14, f"max abs difference {notes_err:.1e}"),
        Claim(f"Monte Carlo rate within {Z_TOL:.0f} s.e. of the closed form at every δ, "
              "sensor and mean", bool(np.all(np.abs(z) < Z_TOL)),
              f"max |z| = {np.max(np.abs(z)):.2f} over {dof} points"),
        Claim("rate strictly decreasing in δ (closed form) and non-increasing (simulation, "
              "common random numbers)", dec_closed and dec_mc,
              "closed form " + ("strictly decreasing" if dec_closed else "not strictly decreasing")
              + "; simulation " + ("non-increasing" if dec_mc else "increasing somewhere")),
        Claim("a non-zero prior mean raises the rate, and only for sensors with aᵢx̄ ≠ 0",
              bool(np.all(gap[:, ~zero_mu] > 0) and np.all(np.abs(gap[:, zero_mu]) < 1e-15)),
              f"min gap (aᵢx̄ ≠ 0) {np.min(gap[:, ~zero_mu]):.2e}"),
        Claim("the inverse map rate ↦ δ inverts the rate (round trip on 201 values of δ from "
              "0.01 to 100)",
              rt0 < 1e-9 and rt1 < 1e-9,
              f"max relative error {rt0:.1e} (x̄ = 0), {rt1:.1e} (x̄ ≠ 0)"),
    ]


common.register_figure(
    id="mo2015-rate",
    paper="mo2015",
    caption="Communication rate P(γᵢ = 1) against the trigger parameter δ for the three "
    "sensors of the static example: the notes' closed form (prior mean 0), our extension to a "
    "non-zero prior mean, and Monte Carlo estimates with 1.96 standard errors.",
    chapter=CHAPTER_RATE,
    label="sec-mo2015-rate-figure",
    parameters={"example": EXAMPLE, "delta_mc": [round(float(d), 6) for d in RATE_DELTAS],
                "trials": RATE_TRIALS},
    functions=(compute_rate, plot_rate, checks_rate),
    settable=SETTABLE_RATE,
    note="Our own figure (the notes have none); closed form and simulation agree within the "
    "stated Monte Carlo error.",
)


