"""Part I (mo2015): the book's own figures on the stochastic event trigger.

The notes have no figures; these three entries check their formulas and extend them:

* ``mo2015-rate``: the communication rate against the trigger parameter ``delta``, in closed form
  (the notes' zero-mean formula and our extension to a non-zero prior mean) and by simulation.
* ``mo2015-tradeoff``: mean squared error against communication rate for a static 2-state,
  3-sensor example: stochastic trigger vs random selection at the same rate vs all-send, with
  exact curves (pattern probabilities in closed form) and Monte Carlo points.
* ``mo2015-tracking``: the event-triggered Kalman filter on the tracking model of zheng2014,
  Section VII.A: RMSE against average transmissions per step.

The static example and the closed forms that the figures need and the library does not (yet)
provide (the joint probability of a transmission pattern, the exact expected trace of the
posterior covariance under each scheduler, the posterior of a centre that simply drops silent
sensors) are in :mod:`fusioncenter.figures.mo2015_static`; they are re-exported here, where the
chapters find them.
"""

from __future__ import annotations

import functools

import numpy as np

from fusioncenter import event, montecarlo, plotting, riccati
from fusioncenter.context import Parameter
from fusioncenter.figures.common import (
    checks_doc,
    compute_doc,
    plot_doc,
    register_figure,
    settings,
    trials_parameter,
)
from fusioncenter.figures.mo2015_static import (  # noqa: F401 (re-exported for the chapters)
    EXAMPLE,
    all_silent_probability,
    conditional_chunk,
    document,
    draw_example,
    drop_covariances,
    drop_posterior,
    example,
    expected_trace_random,
    expected_trace_stochastic,
    output_variances,
    pattern_code,
    pattern_covariances,
    pattern_probabilities,
    patterns,
)
from fusioncenter.figures.registry import Claim
from fusioncenter.models import tracking_model

#: The book's own figures that this module registers (the notes have no figures of their own).
OWN_IDS = ("mo2015-rate", "mo2015-tradeoff", "mo2015-tracking")

CHAPTER_RATE = "book/mo2015/rate"
CHAPTER_CM = "book/mo2015/conditional-mean"
CHAPTER_KF = "book/mo2015/event-kf"

#: Trigger parameters (the same for every sensor) at which the rate is simulated.
RATE_DELTAS = np.geomspace(0.02, 50.0, 13)
#: Per-sensor target rates of the trade-off figure (Monte Carlo points).
TRADEOFF_RATES = np.round(np.linspace(0.1, 0.9, 9), 10)
#: Tracking entry: zheng2014 Section VII.A with N = 2 sensors, 20 measurement times.
TRACKING = {"n_sensors": 2, "steps": 19, "rates": [0.15, 0.25, 0.35, 0.5, 0.65, 0.8],
            "sigma2": 4.0, "r": 1.0, "x0": [0.0, 10.0], "P0": "0 (x0 known)"}

#: Monte Carlo sizes (fast, paper).
RATE_TRIALS = {"fast": 4_000, "paper": 100_000}
TRADEOFF_TRIALS = {"fast": 4_000, "paper": 100_000}
TRACKING_TRIALS = {"fast": 2_000, "paper": 20_000}
CALIBRATION_TRIALS = {"fast": 500, "paper": 5_000}

#: The overridable parameters of each entry (``--set key=value``).
SETTABLE_RATE = (trials_parameter(RATE_TRIALS, "Monte Carlo draws of the example's measurements"),)
SETTABLE_TRADEOFF = (trials_parameter(TRADEOFF_TRIALS,
                                      "Monte Carlo draws of the example's state and measurements"),)
SETTABLE_TRACKING = (
    trials_parameter(TRACKING_TRIALS, "Monte Carlo tracks per scheme and rate"),
    trials_parameter(CALIBRATION_TRIALS, "tracks of the calibration of each delta",
                     name="calibration_trials"),
    Parameter("sigma2", "float", "process-noise intensity of the tracking model (m^2/s^3)",
              TRACKING["sigma2"], minimum=1e-6, model=True),
    Parameter("r", "float", "measurement-noise variance of each sensor (m^2)", TRACKING["r"],
              minimum=1e-6, model=True),
)

#: A z-score beyond this is a failed check. Under the claim each z is about N(0, 1) and
#: P(|Z| > 4) = 6.3e-5, so the 60-odd z-scores of one entry raise a false alarm with probability
#: below 0.5 %; the power tests show that the same tolerance rejects a wrong claim.
Z_TOL = 4.0



# ------------------------------------------------------------------------------ mo2015-rate
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


@compute_doc("""``s`` (m,) the output variances and ``mu`` (m,) the prior means ``a_i xbar``;
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
    n = settings("mo2015-rate", SETTABLE_RATE, profile, over)["trials"]
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


@plot_doc()
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


@checks_doc()
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


register_figure(
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


# -------------------------------------------------------------------------- mo2015-tradeoff
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


@compute_doc("""``rate_fine`` (49,) with ``mse_exact_stochastic_fine``, ``mse_exact_random_fine``
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
    n = settings("mo2015-tradeoff", SETTABLE_TRADEOFF, profile, over)["trials"]
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


@plot_doc()
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


@checks_doc()
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


register_figure(
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


# -------------------------------------------------------------------------- mo2015-tracking
def tracking(sigma2: float | None = None, r: float | None = None) -> object:
    """The tracking model of zheng2014 Section VII.A with :data:`TRACKING`'s sensors.

    Parameters
    ----------
    sigma2, r : float, optional
        The process-noise intensity and the measurement-noise variance (default: those of
        :data:`TRACKING`).

    Returns
    -------
    fusioncenter.kalman.LinearGaussianModel
        The model of :func:`fusioncenter.models.tracking_model`.
    """
    return tracking_model(TRACKING["n_sensors"],
                          sigma2=TRACKING["sigma2"] if sigma2 is None else sigma2,
                          r=TRACKING["r"] if r is None else r, x0=TRACKING["x0"])


def _tracking_run(model, steps: int, scheme: str, n: int, seed: int, **kw) -> dict:
    """One scheme through the runner; per-step and per-trial summaries (samples dropped)."""
    fn = functools.partial(event.event_kf_chunk, model=model, steps=steps, scheme=scheme, **kw)
    res = montecarlo.simulate(fn, n, seed)
    cols = event.split_summary(res.samples, model.nx)
    sq, pd = cols["sq_err"], cols["p_diag"]  # (n, T, nx)
    resid = sq.sum(-1) - pd.sum(-1)  # (n, T): ||e_k||^2 - tr P_{k|k}
    sent = cols["gamma"].mean(-1)  # (n, T): fraction of sensors that sent
    sq_avg = sq.mean(axis=1)  # (n, nx): time-averaged squared error per component
    rt = np.sqrt(n)
    return {
        "mse_k": sq.mean(0), "mse_k_stderr": sq.std(0, ddof=1) / rt,
        "p_k": pd.mean(0),
        "resid_k": resid.mean(0), "resid_k_stderr": resid.std(0, ddof=1) / rt,
        "mse": sq_avg.mean(0), "mse_stderr": sq_avg.std(0, ddof=1) / rt,
        "p_avg": pd.mean(axis=(0, 1)),
        "trace_trial": sq_avg.sum(-1),
        "rate": float(sent.mean()),
        "rate_stderr": float(sent.mean(1).std(ddof=1) / rt),
        "send_prob": float(cols["send_prob"].mean()),
    }


@compute_doc("""``k``, ``rate_target`` (R,), the calibrated ``delta`` (R,) with
             ``calibration_rate``, ``calibration_stderr``, ``calibration_tol``; ``m``,
             ``n_trials``, ``n_calibration``, ``seed``; per scheme (``stochastic_*``,
             ``random_*``: one row per rate; ``all_send_*``) the per-step ``mse_k``, ``p_k``,
             ``resid_k``, the time averages ``mse``, ``p_avg``, the measured ``rate`` and
             ``send_prob`` (``mse_k``, ``resid_k``, ``mse``, ``rate`` with ``*_stderr``);
             ``diff`` and ``allsend_minus_stochastic`` (paired, with ``*_stderr``).""")
def compute_tracking(profile: str, seed: int, **over) -> dict:
    """Data of ``mo2015-tracking``: the event-triggered filter, random selection and all-send
    on :func:`tracking`, one calibrated ``delta`` per target rate (the same tracks for all)."""
    v = settings("mo2015-tracking", SETTABLE_TRACKING, profile, over)
    model = tracking(v["sigma2"], v["r"])
    steps, rates = TRACKING["steps"], np.array(TRACKING["rates"])
    n, n_cal = v["trials"], v["calibration_trials"]
    cal = [event.calibrate_delta(model, float(p), n_trials=n_cal, steps=steps, burn_in=0,
                                 seed=seed + 1) for p in rates]
    delta = np.array([c.delta[0] for c in cal])
    # the same seed for every scheme and rate: common random numbers (same tracks, noises, xi)
    alls = _tracking_run(model, steps, "all-send", n, seed)
    out: dict = {"rate_target": rates, "delta": delta, "m": model.ny,
                 "calibration_rate": np.array([c.rate.mean() for c in cal]),
                 "calibration_stderr": np.array([c.stderr.mean() for c in cal]),
                 "calibration_tol": 1e-3, "n_trials": n, "n_calibration": n_cal, "seed": seed,
                 "k": np.arange(steps + 1)}
    keys = ["mse_k", "mse_k_stderr", "p_k", "resid_k", "resid_k_stderr", "mse", "mse_stderr",
            "p_avg", "rate", "rate_stderr", "send_prob"]
    runs = {"stochastic": [], "random": []}
    diffs, diff_se, lb, lb_se = [], [], [], []
    for p, d in zip(rates, delta, strict=True):
        st = _tracking_run(model, steps, "stochastic", n, seed, delta=d)
        rd = _tracking_run(model, steps, "random", n, seed, p=float(p))
        runs["stochastic"].append(st)
        runs["random"].append(rd)
        dd = st["trace_trial"] - rd["trace_trial"]
        diffs.append(dd.mean())
        diff_se.append(dd.std(ddof=1) / np.sqrt(n))
        da = alls["trace_trial"] - st["trace_trial"]
        lb.append(da.mean())
        lb_se.append(da.std(ddof=1) / np.sqrt(n))
    for scheme, lst in runs.items():
        for key in keys:
            out[f"{scheme}_{key}"] = np.array([x[key] for x in lst])
    for key in keys:
        out[f"all_send_{key}"] = np.asarray(alls[key])
    out.update({"diff": np.array(diffs), "diff_stderr": np.array(diff_se),
                "allsend_minus_stochastic": np.array(lb),
                "allsend_minus_stochastic_stderr": np.array(lb_se)})
    return out


def _rmse(mse, se):
    rmse = np.sqrt(mse)
    return rmse, se / (2 * rmse)


@plot_doc()
def plot_tracking(data: dict):
    """(a) position and (b) velocity RMSE against transmissions per step, per scheme."""
    fig, axes = plotting.subplots(1, 2, stack=True)
    m = data["m"]
    names = ["position", "velocity"]
    units = ["m", "m/s"]
    for c, ax in enumerate(axes):
        for key, scheme, name in [("stochastic", "trigger", "stochastic trigger"),
                                  ("random", "random", "random selection")]:
            rm, se = _rmse(data[f"{key}_mse"][:, c], data[f"{key}_mse_stderr"][:, c])
            ax.errorbar(m * data[f"{key}_rate"], rm, yerr=1.96 * se, mfc="none", capsize=2,
                        label=f"{name}: Monte Carlo ± 1.96 s.e.", **plotting.look(scheme))
            if key == "stochastic":  # on top of the Monte Carlo line, dots and small stars
                ax.plot(m * data[f"{key}_rate"], np.sqrt(data[f"{key}_p_avg"][:, c]),
                        label=r"stochastic trigger: filter's own $\sqrt{\text{mean } P_{k|k}}$",
                        zorder=4, markevery=2, markersize=3.5,
                        **plotting.look("trigger", ls=":", lw=3.0))
        rm, se = _rmse(data["all_send_mse"][c], data["all_send_mse_stderr"][c])
        ax.errorbar([m * data["all_send_rate"]], [rm], yerr=[1.96 * se], capsize=2,
                    label="all-send", **plotting.look("all-send", ls="none", markersize=8))
        ax.axhline(rm, lw=0.8, **plotting.look("all-send", marker="None", ls=":"))
        if c == 0:
            ax.set_yscale("log")  # random selection at low rates loses track for long stretches
        ax.set(xlabel="average transmissions per step (of 2 sensors)",
               ylabel=f"{names[c]} RMSE, 20-step average ({units[c]})",
               title=f"{names[c]}; {data['n_trials']} trials")
        ax.legend()
    return plotting.finish(fig)


@checks_doc()
def checks_tracking(data: dict) -> list[Claim]:
    """The rates, the trigger below random selection, the filters' exactness and all-send the
    lower bound."""
    zd = data["diff"] / data["diff_stderr"]
    se_tot = np.sqrt(data["stochastic_rate_stderr"] ** 2 + data["calibration_stderr"] ** 2)
    rate_gap = np.abs(data["stochastic_rate"] - data["rate_target"])
    rate_ok = rate_gap <= data["calibration_tol"] + Z_TOL * se_tot
    zr = (data["random_rate"] - data["rate_target"]) / data["random_rate_stderr"]
    # exactness, k >= 1 (at k = 0 the state is known and every error is exactly 0)
    z_ex = []
    for key in ("stochastic", "random"):
        z_ex.append(data[f"{key}_resid_k"][:, 1:] / data[f"{key}_resid_k_stderr"][:, 1:])
    z_ex.append((data["all_send_resid_k"][1:] / data["all_send_resid_k_stderr"][1:])[None, :])
    # correlated across steps, rates and schemes (the same tracks): checked one by one
    z_all = np.concatenate([z.ravel() for z in z_ex])
    dof = z_all.size
    zl = data["allsend_minus_stochastic"] / data["allsend_minus_stochastic_stderr"]
    return [
        Claim("measured send rate of the trigger equals the target (calibration tol + 4 s.e.)",
              bool(np.all(rate_ok)),
              "measured " + ", ".join(f"{x:.4f}" for x in data["stochastic_rate"])),
        Claim("random selection's measured rate equals p (4 s.e.)",
              bool(np.all(np.abs(zr) < Z_TOL)), f"max |z| = {np.max(np.abs(zr)):.2f}"),
        Claim(f"trigger's MSE below random selection's at every matched rate by more than "
              f"{Z_TOL:.0f} s.e. (paired)", bool(np.all(zd < -Z_TOL)),
              f"largest z = {np.max(zd):.1f}"),
        Claim("the filters are exact: E‖xₖ − x̂ₖ‖² = E tr Pₖ|ₖ at every step "
              "(4 s.e.)", bool(np.all(np.abs(z_all) < Z_TOL)),
              f"max |z| = {np.max(np.abs(z_all)):.2f} over {dof} steps × rates × schemes"),
        Claim("all-send is the lower bound: below the trigger by more than 4 s.e. (paired)",
              bool(np.all(zl < -Z_TOL)), f"largest z = {np.max(zl):.1f}"),
    ]


register_figure(
    id="mo2015-tracking",
    paper="mo2015",
    caption="The event-triggered Kalman filter (stochastic trigger on the innovation, exact "
    "MMSE filter) on the tracking model of zheng2014 Section VII.A with N = 2 sensors: "
    "position and velocity RMSE against average transmissions per step, against random "
    "selection at the same rate and all-send.",
    chapter=CHAPTER_KF,
    label="sec-mo2015-tracking",
    parameters={**TRACKING, "trials": TRACKING_TRIALS, "calibration_trials": CALIBRATION_TRIALS,
                "delta": "calibrate_delta on the same 20-step horizon (burn_in = 0)"},
    functions=(compute_tracking, plot_tracking, checks_tracking),
    settable=SETTABLE_TRACKING,
    note="Our own figure (the notes stop at one-shot estimation); the filter's covariance "
    "matches its Monte Carlo error within the stated tolerance.",
)
