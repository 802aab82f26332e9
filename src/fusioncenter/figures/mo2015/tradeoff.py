"""``mo2015-tradeoff``: mean squared error against communication rate, static example.

The stochastic trigger with the closed-form MMSE estimator, random selection at the same
per-sensor rate, and all-send, on the 2-state, 3-sensor static example: exact curves (pattern
probabilities in closed form, :mod:`fusioncenter.figures.mo2015.static`) and Monte Carlo points
at the rates :data:`TRADEOFF_RATES`.
"""

from __future__ import annotations

import functools

import numpy as np

from fusioncenter import event, montecarlo, plotting, riccati
from fusioncenter.figures import common
from fusioncenter.figures.mo2015.static import (
    EXAMPLE,
    Z_TOL,
    document,
    draw_example,
    drop_posterior,
    example,
    expected_trace_random,
    expected_trace_stochastic,
    output_variances,
    pattern_probabilities,
)
from fusioncenter.figures.registry import Claim

CHAPTER_CM = "book/mo2015/conditional-mean"
#: Per-sensor target rates of the trade-off figure (Monte Carlo points).
TRADEOFF_RATES = np.round(np.linspace(0.1, 0.9, 9), 10)
TRADEOFF_TRIALS = {"fast": 4_000, "paper": 100_000}
#: The overridable parameter (``--set key=value``).
SETTABLE_TRADEOFF = (common.trials_parameter(TRADEOFF_TRIALS,
                                      "Monte Carlo draws of the example's state and measurements"),)


@document(returns=("numpy.ndarray, shape (L, m)", ""),
          rates=("array_like, shape (L,)", "Send rates in (0, 1)."))
def tradeoff_deltas(rates) -> np.ndarray:
    """Per-sensor ``delta`` giving each sensor of :data:`EXAMPLE` each send rate of ``rates``."""
    xbar, Sigma, C, r = example()
    s, mu = output_variances(Sigma, C, r), C @ xbar
    rates = np.asarray(rates, dtype=float)
    return np.asarray(event.delta_for_rate(rates[:, None], s[None, :], mu[None, :]))


def _tradeoff_chunk(rng: np.random.Generator, n: int, *, rates, deltas) -> np.ndarray:
    """Per trial: all-send ``(sq, trP)``, then per rate level ``(sq, trP, sent)`` of the trigger
    and of random selection: ``(n, 2 + 6 L)``. Common random numbers across schemes and levels."""
    xbar, Sigma, C, r = example()
    m = len(r)
    x, y, xi = draw_example(rng, n)
    cols = []
    xa, Pa = event.posterior(xbar, Sigma, C, r, 1.0, np.ones((n, m), dtype=bool), y)
    cols += [np.sum((xa - x) ** 2, axis=1), np.trace(Pa, axis1=-2, axis2=-1)]
    for rate, delta in zip(rates, deltas, strict=True):
        g = xi > np.exp(-(y**2) / (2 * np.asarray(delta)))  # the notes' rule, these uniforms
        xs, Ps = event.posterior(xbar, Sigma, C, r, delta, g, np.where(g, y, np.nan))
        gr = xi < rate  # random selection: independent of y
        xr, Pr = drop_posterior(xbar, Sigma, C, r, gr, y)
        cols += [np.sum((xs - x) ** 2, axis=1), np.trace(Ps, axis1=-2, axis2=-1), g.sum(axis=1),
                 np.sum((xr - x) ** 2, axis=1), np.trace(Pr, axis1=-2, axis2=-1), gr.sum(axis=1)]
    return np.stack(cols, axis=1)


@common.compute_doc(
    """``rate_fine`` (49,) with ``mse_exact_stochastic_fine``, ``mse_exact_random_fine``
             the exact MSE curves; at the Monte Carlo rates ``rate`` (L,) (``delta`` (L, m)):
             ``mse_exact_*``, and for ``stochastic`` and ``random`` the simulated ``mse_*``,
             ``rate_*`` (and ``trP_stochastic``), each with ``*_stderr``; ``diff`` and ``resid``
             (paired trigger minus random, squared error minus tr P) with their ``*_stderr``;
             ``trace_all_send``, ``trace_prior``, ``mse_all_send(_stderr)``, ``pattern_prob_sum``
             (L,), ``n_trials``, ``seed``.""")
def compute_tradeoff(profile: str, seed: int, **over) -> dict:
    """Data of ``mo2015-tradeoff``: mean squared error against rate on :data:`EXAMPLE`, exact
    and simulated (the same draws for every scheme and rate)."""
    xbar, Sigma, C, r = example()
    m = len(r)
    fine = np.round(np.linspace(0.02, 0.98, 49), 10)
    d_fine = tradeoff_deltas(fine)
    exact_s = np.array([expected_trace_stochastic(Sigma, C, r, d, xbar) for d in d_fine])
    exact_r = np.array([expected_trace_random(Sigma, C, r, p) for p in fine])
    rates = TRADEOFF_RATES
    deltas = tradeoff_deltas(rates)
    n = common.settings("mo2015-tradeoff", SETTABLE_TRADEOFF, profile, over)["trials"]
    res = montecarlo.simulate(functools.partial(_tradeoff_chunk, rates=rates, deltas=deltas),
                              n, seed)
    L = len(rates)
    per = res.samples[:, 2:].reshape(n, L, 6)
    mean, se = per.mean(axis=0), per.std(axis=0, ddof=1) / np.sqrt(n)
    diff = per[:, :, 0] - per[:, :, 3]  # paired: trigger minus random, same draws
    resid = per[:, :, 0] - per[:, :, 1]  # squared error minus tr P (mean 0 if P is exact)
    exact_s_mc = np.array([expected_trace_stochastic(Sigma, C, r, d, xbar) for d in deltas])
    exact_r_mc = np.array([expected_trace_random(Sigma, C, r, p) for p in rates])
    psum = np.array([pattern_probabilities(Sigma, C, r, d, xbar).sum() for d in deltas])
    return {
        "rate_fine": fine, "mse_exact_stochastic_fine": exact_s, "mse_exact_random_fine": exact_r,
        "rate": rates.copy(), "delta": deltas,
        "mse_exact_stochastic": exact_s_mc, "mse_exact_random": exact_r_mc,
        "trace_all_send": float(np.trace(riccati.measurement_update(Sigma, C, np.diag(r)))),
        "trace_prior": float(np.trace(Sigma)),
        "pattern_prob_sum": psum,
        "mse_stochastic": mean[:, 0], "mse_stochastic_stderr": se[:, 0],
        "trP_stochastic": mean[:, 1], "trP_stochastic_stderr": se[:, 1],
        "rate_stochastic": mean[:, 2] / m, "rate_stochastic_stderr": se[:, 2] / m,
        "mse_random": mean[:, 3], "mse_random_stderr": se[:, 3],
        "rate_random": mean[:, 5] / m, "rate_random_stderr": se[:, 5] / m,
        "diff": diff.mean(axis=0), "diff_stderr": diff.std(axis=0, ddof=1) / np.sqrt(n),
        "resid": resid.mean(axis=0), "resid_stderr": resid.std(axis=0, ddof=1) / np.sqrt(n),
        "mse_all_send": float(res.mean[0]), "mse_all_send_stderr": float(res.stderr[0]),
        "n_trials": n, "seed": seed,
    }


@common.plot_doc()
def plot_tradeoff(data: dict):
    """MSE against rate: exact curves and Monte Carlo points of both schedulers, all-send and
    the prior as horizontal lines."""
    fig, ax = plotting.subplots(stack=True)
    for key, scheme, name in [("stochastic", "trigger", "stochastic trigger (MMSE)"),
                              ("random", "random", "random selection, same rate")]:
        ax.plot(data["rate_fine"], data[f"mse_exact_{key}_fine"], label=f"{name}: exact",
                **plotting.look(scheme, marker="None"))
        ax.errorbar(data[f"rate_{key}"], data[f"mse_{key}"],
                    yerr=1.96 * data[f"mse_{key}_stderr"], mfc="none", capsize=2,
                    label=f"{name}: Monte Carlo ± 1.96 s.e.", **plotting.look(scheme, ls="none"))
    ax.axhline(data["trace_all_send"], lw=1, label=r"all-send: $\mathrm{tr}\,P$ (rate 1)",
               **plotting.look("all-send", marker="None", ls="--"))
    ax.axhline(data["trace_prior"], color="0.5", lw=1, ls=":",
               label=r"nobody sends: $\mathrm{tr}\,\Sigma$ (rate 0)")
    ax.set(xlabel=r"communication rate per sensor $P(\gamma_i = 1)$",
           ylabel=r"mean squared error $\mathbb{E}\,\|x - \hat x\|^2$ (units of $x^2$)",
           title=f"2 states, 3 sensors; {data['n_trials']} trials", xlim=(0, 1))
    ax.legend()
    return plotting.finish(fig)


@common.checks_doc()
def checks_tradeoff(data: dict) -> list[Claim]:
    """The closed forms against the simulation, the rates, the trigger below random selection
    and all-send the lower bound."""
    zd = data["diff"] / data["diff_stderr"]
    zs = (data["mse_stochastic"] - data["mse_exact_stochastic"]) / data["mse_stochastic_stderr"]
    zp = data["resid"] / data["resid_stderr"]
    zr = (data["mse_random"] - data["mse_exact_random"]) / data["mse_random_stderr"]
    zrate = np.concatenate([(data["rate_stochastic"] - data["rate"])
                            / data["rate_stochastic_stderr"],
                            (data["rate_random"] - data["rate"]) / data["rate_random_stderr"]])
    za = (data["mse_all_send"] - data["trace_all_send"]) / data["mse_all_send_stderr"]
    exact_gap = data["mse_exact_random"] - data["mse_exact_stochastic"]
    lower = min(float(np.min(data["mse_exact_stochastic_fine"])),
                float(np.min(data["mse_exact_random_fine"]))) - data["trace_all_send"]
    return [
        Claim("pattern probabilities (closed form, inclusion-exclusion) sum to 1",
              bool(np.all(np.abs(data["pattern_prob_sum"] - 1) < 1e-12)),
              f"max |sum - 1| = {np.max(np.abs(data['pattern_prob_sum'] - 1)):.1e}"),
        Claim("measured rates of both schedulers equal the target rate (4 s.e.)",
              bool(np.all(np.abs(zrate) < Z_TOL)), f"max |z| = {np.max(np.abs(zrate)):.2f}"),
        Claim("the exact MSE of the trigger is below random selection's at every rate",
              bool(np.all(exact_gap > 0)
                   and np.all(data["mse_exact_stochastic_fine"]
                              < data["mse_exact_random_fine"])),
              f"smallest exact gap {np.min(exact_gap):.4f} at the Monte Carlo rates"),
        Claim(f"simulation: trigger below random selection by more than {Z_TOL:.0f} s.e. "
              "(paired) at every rate", bool(np.all(zd < -Z_TOL)),
              f"largest z = {np.max(zd):.1f}"),
        Claim("MC MSE of the trigger equals the exact E tr P (pattern closed form), 4 s.e.",
              bool(np.all(np.abs(zs) < Z_TOL)), f"max |z| = {np.max(np.abs(zs)):.2f}"),
        Claim("per trial, squared error minus tr P(γ) has mean 0 (4 s.e.): P is the error "
              "covariance", bool(np.all(np.abs(zp) < Z_TOL)),
              f"max |z| = {np.max(np.abs(zp)):.2f}"),
        Claim("MC MSE of random selection equals its exact value, 4 s.e.",
              bool(np.all(np.abs(zr) < Z_TOL)), f"max |z| = {np.max(np.abs(zr)):.2f}"),
        Claim("all-send is the lower bound: exact curves stay above tr P of all-send, MC all-send "
              "matches it", lower > 0 and abs(za) < Z_TOL,
              f"min exact gap {lower:.2e}; all-send z = {za:.2f}"),
    ]


common.register_figure(
    id="mo2015-tradeoff",
    paper="mo2015",
    caption="Mean squared error against communication rate for a 2-state, 3-sensor static "
    "example: the stochastic trigger with the closed-form MMSE estimator, random selection at "
    "the same per-sensor rate, and all-send; exact curves and Monte Carlo points.",
    chapter=CHAPTER_CM,
    label="sec-mo2015-tradeoff",
    parameters={"example": EXAMPLE, "rates": [float(x) for x in TRADEOFF_RATES],
                "trials": TRADEOFF_TRIALS,
                "delta": "per sensor, delta_for_rate(rate, s_i, a_i xbar)"},
    functions=(compute_tradeoff, plot_tradeoff, checks_tradeoff),
    settable=SETTABLE_TRADEOFF,
    note="Our own figure (the notes have none); simulation matches the exact curves within the "
    "stated Monte Carlo error.",
)


