"""The Background chapter's own figures: the Riccati recursion and what it predicts."""

from __future__ import annotations

import functools

import numpy as np

from fusioncenter import montecarlo, plotting, riccati
from fusioncenter.context import Parameter
from fusioncenter.figures import common
from fusioncenter.figures.registry import Claim
from fusioncenter.kalman import constant_velocity

CHAPTER = "book/background/kalman-riccati"
OWN_IDS = ("background-riccati", "background-kf-montecarlo")

#: Scalar example: an unstable scalar system observed in noise (a = 1.25 as in dey2009).
SCALAR = {"a": 1.25, "q": 1.0, "c": 1.0, "r": 4.0, "p0": 0.0, "steps": 30}
#: Vector example: constant velocity, position measured.
VECTOR = {"dt": 1.0, "q": 0.5, "r": 4.0, "m0": [0.0, 1.0], "P0": [[10.0, 0.0], [0.0, 1.0]],
          "steps": 30}
#: Monte Carlo trials of ``background-kf-montecarlo``.
MC_TRIALS = {"fast": 2_000, "paper": 50_000}

#: The overridable parameters of ``background-riccati``: the scalar system (its vector example
#: is fixed).
SETTABLE_RICCATI = (
    Parameter("a", "float", "state transition of the scalar system", SCALAR["a"], model=True),
    Parameter("q", "float", "process-noise variance of the scalar system", SCALAR["q"],
              minimum=0.0, model=True),
    Parameter("r", "float", "measurement-noise variance of the scalar system", SCALAR["r"],
              minimum=1e-9, model=True),
)
#: The overridable parameters of ``background-kf-montecarlo``.
SETTABLE_MC = (
    common.trials_parameter(MC_TRIALS, "Monte Carlo trials (simulated tracks)"),
    Parameter("q", "float", "process-noise intensity of the constant-velocity model",
              VECTOR["q"], minimum=1e-9, model=True),
    Parameter("r", "float", "position measurement-noise variance (m^2)", VECTOR["r"],
              minimum=1e-9, model=True),
)


def vector_model(q: float | None = None, r: float | None = None):
    """The constant-velocity example :data:`VECTOR` as a model.

    Parameters
    ----------
    q, r : float, optional
        Override the noise levels of :data:`VECTOR` (``q`` of the process, ``r`` of the
        position measurement).

    Returns
    -------
    fusioncenter.kalman.LinearGaussianModel
        Position and velocity, position measured, with the noise levels, initial mean and
        covariance of :data:`VECTOR`.
    """
    return constant_velocity(dt=VECTOR["dt"], q=VECTOR["q"] if q is None else q,
                             r=VECTOR["r"] if r is None else r, m0=VECTOR["m0"],
                             P0=np.array(VECTOR["P0"]))


def filterpy_covariances(model, steps: int) -> tuple[np.ndarray, np.ndarray]:
    """Prediction and filtered covariances from filterpy's ``KalmanFilter`` (the reference).

    Parameters
    ----------
    model : fusioncenter.kalman.LinearGaussianModel
        The model; its matrices are copied into a ``filterpy.kalman.KalmanFilter``.
    steps : int
        Number of time updates.

    Returns
    -------
    pred : numpy.ndarray, shape (steps + 1, nx, nx)
        ``P_{k|k-1}`` for ``k = 0, ..., steps`` (``pred[0]`` is the prior covariance ``P0``).
    post : numpy.ndarray, shape (steps + 1, nx, nx)
        ``P_{k|k}`` after each measurement update. Covariances do not depend on the measured
        values, so zeros are fed as measurements.
    """
    from filterpy.kalman import KalmanFilter

    kf = KalmanFilter(dim_x=model.nx, dim_z=model.ny)
    kf.F, kf.Q, kf.H, kf.R = model.A, model.Q, model.C, model.R
    kf.x, kf.P = model.m0.reshape(-1, 1), model.P0.copy()
    pred, post = [kf.P.copy()], []
    for k in range(steps + 1):
        kf.update(np.zeros((model.ny, 1)))  # covariances do not depend on the measured value
        post.append(kf.P.copy())
        if k < steps:
            kf.predict()
            pred.append(kf.P.copy())
    return np.array(pred), np.array(post)


# ------------------------------------------------------------------------ riccati convergence
@common.compute_doc("""``k`` (steps + 1,) the time steps; ``p_scalar`` (steps + 1,) the scalar
             prediction
             variances of :data:`SCALAR` from ``p0``; ``p_scalar_inf`` (float) their closed-form
             limit and ``p_scalar_dare`` (float) scipy's DARE solution; ``P_vector`` (steps + 1,
             2, 2) the prediction covariances of :data:`VECTOR`, ``P_vector_filterpy`` the same
             from filterpy, ``P_vector_inf`` (2, 2) the DARE solution; with an override,
             ``scalar`` (dict) the scalar system used.""",
             profile="Unused (deterministic).",
             seed="Unused.")
def compute_riccati(profile: str, seed: int, **over) -> dict:
    """Data of ``background-riccati``: the scalar and the vector Riccati recursions.

    Deterministic: the profile and the seed do not matter.
    """
    s = {**SCALAR, **common.settings("background-riccati", SETTABLE_RICCATI, profile, over)}
    k = np.arange(s["steps"] + 1)
    p = riccati.scalar_sequence(s["p0"], s["a"], s["q"], s["c"], s["r"], s["steps"])
    p_inf = riccati.scalar_steady_state(s["a"], s["q"], s["c"], s["r"])
    p_dare = riccati.steady_state([[s["a"]]], [[s["q"]]], [[s["c"]]], [[s["r"]]])[0, 0]

    model = vector_model()
    P = riccati.riccati_sequence(model.P0, model.A, model.Q, model.C, model.R, VECTOR["steps"])
    P_fp, _ = filterpy_covariances(model, VECTOR["steps"])
    P_inf = riccati.steady_state(model.A, model.Q, model.C, model.R)
    out = {
        "k": k,
        "p_scalar": p,
        "p_scalar_inf": float(p_inf),
        "p_scalar_dare": float(p_dare),
        "P_vector": P,
        "P_vector_filterpy": P_fp,
        "P_vector_inf": P_inf,
    }
    if over:
        out["scalar"] = s
    return out


@common.plot_doc()
def plot_riccati(data: dict):
    """The two panels of ``background-riccati``: scalar recursion, vector diagonal (log scale)."""
    fig, (ax1, ax2) = plotting.subplots(1, 2, stack=True)
    k = data["k"]
    s = data.get("scalar", SCALAR)
    ax1.plot(k, data["p_scalar"], label=r"$p_{k}$ (recursion)")
    ax1.axhline(data["p_scalar_inf"], color="0.3", lw=1, ls=":", label=r"$p_\infty$ (closed form)")
    ax1.set(xlabel="time step $k$", ylabel="prediction error variance (units$^2$)",
            title="scalar: " + ", ".join(f"${k}={v:g}$" for k, v in s.items()
                                         if k in ("a", "q", "c", "r")))
    ax1.legend()
    P = data["P_vector"]
    for i, name in enumerate(["position (m$^2$)", "velocity (m$^2$/s$^2$)"]):
        line = ax2.semilogy(k, P[:, i, i], label=f"{name}: recursion")[0]
        ax2.semilogy(k, data["P_vector_filterpy"][:, i, i], ls="none", marker="x",
                     color=line.get_color(), label=f"{name}: filterpy")
        ax2.axhline(data["P_vector_inf"][i, i], color=line.get_color(), lw=1, ls=":")
    ax2.set(xlabel="time step $k$", ylabel="prediction error variance (m$^2$ | m$^2$/s$^2$)",
            title="constant velocity, position measured")
    ax2.legend()
    return plotting.finish(fig)


@common.checks_doc("Five claims, each with the measured gap in its detail.")
def checks_riccati(data: dict) -> list[Claim]:
    """Fixed point, DARE agreement, monotone convergence and agreement with filterpy."""
    p, p_inf = data["p_scalar"], data["p_scalar_inf"]
    gap = np.abs(p - p_inf)
    P, P_inf = data["P_vector"], data["P_vector_inf"]
    rel_fp = np.max(np.abs(P - data["P_vector_filterpy"])) / np.max(np.abs(P))
    s = data.get("scalar", SCALAR)
    fixed = riccati.scalar_step(p_inf, s["a"], s["q"], s["c"], s["r"])
    return [
        Claim("closed-form scalar steady state is a fixed point of the recursion",
              abs(fixed - p_inf) <= 1e-12 * p_inf,
              f"|step(p∞) − p∞| = {abs(fixed - p_inf):.2e}"),
        Claim("closed form equals scipy's DARE solution",
              abs(p_inf - data["p_scalar_dare"]) <= 1e-10 * p_inf,
              f"{p_inf:.12f} vs {data['p_scalar_dare']:.12f}"),
        Claim("scalar recursion from p₀ = 0 increases monotonically to p∞ (within 10⁻⁸ by "
              "the last step)", bool(np.all(np.diff(p) >= 0) and gap[-1] < 1e-8 * p_inf),
              f"final gap {gap[-1]:.2e}", paper_specific=True),
        Claim("vector recursion agrees with filterpy KalmanFilter",
              rel_fp < 1e-12, f"max relative difference {rel_fp:.2e}"),
        Claim("vector recursion converges to the DARE solution",
              np.max(np.abs(P[-1] - P_inf)) < 1e-6 * np.max(np.abs(P_inf)),
              f"max |P₃₀ − P∞| = {np.max(np.abs(P[-1] - P_inf)):.2e}"),
    ]


# ------------------------------------------------------------------ Monte Carlo vs Riccati
def _kf_squared_errors(rng: np.random.Generator, n: int, steps: int, q=None,
                       r=None) -> np.ndarray:
    """Squared filtering errors of ``n`` simulated trials, shaped ``(n, steps+1, 2)``."""
    model = vector_model(q, r)
    x, y = model.sample(rng, n, steps)
    xhat, _ = model.filter(y)
    return (xhat - x) ** 2


@common.compute_doc("""``k`` (T,) time steps; ``mse`` and ``stderr`` (T, 2) the mean squared
             filtering
             error of position and velocity and its standard error; ``n_trials`` and ``seed``;
             ``riccati_diag`` (T, 2) the diagonal of ``P_{k|k}``; ``normalized_mse`` and
             ``normalized_mse_stderr`` (float) the squared error divided by the Riccati variance,
             averaged over steps and components (1 for a correct filter), with its standard error
             over trials.""",
             profile='``"fast"`` (2 000 trials) or ``"paper"`` (50 000 trials).')
def compute_mc(profile: str, seed: int, **over) -> dict:
    """Data of ``background-kf-montecarlo``: simulated Kalman-filter errors against Riccati."""
    steps = VECTOR["steps"]
    v = common.settings("background-kf-montecarlo", SETTABLE_MC, profile, over)
    n = v["trials"]
    res = montecarlo.simulate(functools.partial(_kf_squared_errors, steps=steps, q=v["q"],
                                                r=v["r"]), n, seed)
    model = vector_model(v["q"], v["r"])
    _, P_post = model.filter(np.zeros((1, steps + 1, 1)))
    riccati_diag = np.stack([P_post[:, 0, 0], P_post[:, 1, 1]], axis=1)
    # One number per trial: its squared error averaged over steps, each component scaled by its
    # Riccati variance. Trials are independent, so its mean has an honest standard error.
    per_trial = (res.samples / riccati_diag).mean(axis=(1, 2))
    return {
        "k": np.arange(steps + 1),
        "mse": res.mean,
        "stderr": res.stderr,
        "n_trials": res.n_trials,
        "seed": seed,
        "riccati_diag": riccati_diag,
        "normalized_mse": float(per_trial.mean()),
        "normalized_mse_stderr": float(per_trial.std(ddof=1) / np.sqrt(per_trial.size)),
    }


@common.plot_doc()
def plot_mc(data: dict):
    """Monte Carlo mean squared error with 95 % bands against the Riccati variances."""
    fig, ax = plotting.subplots(stack=True)
    k = data["k"]
    for i, name in enumerate(["position (m$^2$)", "velocity (m$^2$/s$^2$)"]):
        line = plotting.errorband(ax, k, data["mse"][:, i], data["stderr"][:, i],
                                  label=f"{name}: Monte Carlo ± 1.96 s.e.")
        ax.plot(k, data["riccati_diag"][:, i], color=line.get_color(), ls="none", marker="o",
                mfc="none", label=f"{name}: Riccati $P_{{k|k}}$")
    plotting.log_axis(ax)  # plain numbers, not 4x10^0
    ax.set(xlabel="time step $k$",
           ylabel="mean squared error (m$^2$ | m$^2$/s$^2$)",
           title=f"{data['n_trials']} trials")
    ax.legend()
    return plotting.finish(fig)


@common.checks_doc("""Two claims: every z-score below 4.5, and the normalized error within 4
            standard
            errors of 1.""")
def checks_mc(data: dict) -> list[Claim]:
    """The simulated errors agree with the Riccati variances, step by step and on average."""
    z = (data["mse"] - data["riccati_diag"]) / data["stderr"]
    # 62 z-scores: under a correct filter each is ~N(0, 1), so |z| < 4.5 everywhere fails by
    # chance with probability < 62 * 7e-6 = 4e-4.
    zt = (data["normalized_mse"] - 1.0) / data["normalized_mse_stderr"]
    return [
        Claim("every step and component within 4.5 standard errors of the Riccati variance",
              bool(np.all(np.abs(z) < 4.5)), f"max |z| = {np.max(np.abs(z)):.2f}"),
        Claim("squared error / Riccati variance, averaged over steps and components, is 1",
              abs(zt) < 4.0,
              f"{data['normalized_mse']:.4f} ± {data['normalized_mse_stderr']:.4f} "
              f"(z = {zt:.2f})"),
    ]


# The chapter's two figures, both the book's own (paper "book"): each row holds what is theirs.
for _id, _label, _functions, _parameters, _settable, _caption, _note in (
        ("background-riccati", "sec-background-riccati-figure",
         (compute_riccati, plot_riccati, checks_riccati), {"scalar": SCALAR, "vector": VECTOR},
         SETTABLE_RICCATI,
         "The Riccati recursion converging to its steady state: a scalar unstable system "
         "(closed-form root) and a constant-velocity model (checked against filterpy and scipy's "
         "DARE).", "Our own figure; deterministic (no Monte Carlo)."),
        ("background-kf-montecarlo", "sec-background-kf-montecarlo",
         (compute_mc, plot_mc, checks_mc), {"model": VECTOR, "trials": MC_TRIALS}, SETTABLE_MC,
         "What the Riccati recursion predicts: the Monte Carlo mean squared error of the Kalman "
         "filter matches the diagonal of Pₖ|ₖ at every step.",
         "Our own figure; agreement within the stated Monte Carlo error.")):
    common.register_figure(id=_id, paper="book", caption=_caption, chapter=CHAPTER, label=_label,
                           parameters=_parameters, functions=_functions, settable=_settable,
                           note=_note)
