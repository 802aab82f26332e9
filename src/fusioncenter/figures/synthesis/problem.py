"""The common problem of Part V and what its three entries share.

One tracking problem (zheng2014 Section VII.A, two sensors, 20 steps, ``x_0`` known,
:data:`PROBLEM`, built by :func:`scenario`), the Monte Carlo sizes of the entries that run the
particle filters, the calibration of mo2015's trigger to a target send rate
(:func:`calibrate`), and how a list of run summaries becomes the entries' data
(:func:`summary_stats`, :func:`stack`, :func:`paired`).
"""

from __future__ import annotations

import numpy as np

from fusioncenter import censoring, comparison, event
from fusioncenter.figures.common import document, trials_parameter
from fusioncenter.models import tracking_model
from fusioncenter.profile import by_profile

CHAPTER = "book/synthesis/one-problem"

#: The common problem: zheng2014 Section VII.A with N = 2 sensors (LinearScenario defaults).
PROBLEM = {"N": 2, "T": 20, "r": 1.0, "sigma2": 4.0, "dt": 1.0, "x0": [0.0, 10.0],
           "P0": "0 (x0 known)", "feedback": "state (the FC broadcasts xhat_{t|t-1})"}

#: Monte Carlo trials and particles of the frontier and fading entries, per profile.
TRIALS = {"fast": 512, "paper": 2048}
PARTICLES = {"fast": 500, "paper": 500}
#: Trials of the Monte Carlo calibration of each trigger parameter, per profile.
CALIBRATION_TRIALS = {"fast": 500, "paper": 2000}
#: The overridable parameters of the frontier and fading entries (Monte Carlo sizes only:
#: every claim applies).
SETTABLE_FRONTIER = (
    trials_parameter(TRIALS, "Monte Carlo trials per scheme and budget"),
    trials_parameter(PARTICLES, "particles of each particle filter", name="particles"),
    trials_parameter(CALIBRATION_TRIALS, "trials of the calibration of each delta",
                     name="calibration_trials"),
)

#: A z-score beyond this is a failed check (see mo2015.Z_TOL for the reasoning).
Z_TOL = 4.0

#: What the compute functions store for a group ``G`` of runs (one value per run of the group).
STATS_DOC = ("``G_rate``, ``G_arrived`` (transmissions, packets arrived per step), ``G_pos``, "
             "``G_vel`` (time-averaged RMSE), each with ``G_*_se``, ``G_mse_state``, ``G_trace`` "
             "(mean squared error, mean tr P: NaN for a PF); a paired difference ``D`` (RMSE, "
             "or transmissions for ``rate_*``) as ``D`` and ``D_se``")


def scenario() -> censoring.LinearScenario:
    """The common problem (the defaults of :class:`fusioncenter.censoring.LinearScenario`).

    Returns
    -------
    fusioncenter.censoring.LinearScenario
    """
    return censoring.LinearScenario(N=PROBLEM["N"], T=PROBLEM["T"], r=PROBLEM["r"],
                                    sigma2=PROBLEM["sigma2"], dt=PROBLEM["dt"],
                                    x0=tuple(PROBLEM["x0"]))


@document(returns=("numpy.ndarray, shape (len(rates),)", "One ``delta`` per rate."),
          raises=(), rates=("array_like of float", "Per-sensor target send rates in (0, 1)."),
          n_trials=("int, optional", "Calibration tracks (default: by ``profile``)."))
def calibrate(rates, profile: str, seed: int, n_trials: int | None = None) -> np.ndarray:
    """One trigger parameter ``delta`` per per-sensor target rate, the same for both sensors.

    The sensors are identical, so they share ``delta``. Sensor ``i`` sends at step ``k`` with
    Part I's probability ``1 - sqrt(delta / (delta + s_{i,k}))``, ``s_{i,k}`` its innovation
    variance ``c_i^T P_{k|k-1} c_i + r_i``; but ``P_{k|k-1}`` is random (it depends on who sent
    before), so the 20-step average has no closed form: :func:`fusioncenter.event.calibrate_delta`
    finds ``delta`` by simulation (common random numbers, tolerance 1e-3 on its own sample),
    averaging steps ``k = 1..20`` (``burn_in = 1`` skips the library's step 0, where ``x_0`` is
    known), on ``n_trials`` tracks (default: :data:`CALIBRATION_TRIALS` of the profile).
    """
    model = tracking_model(PROBLEM["N"], sigma2=PROBLEM["sigma2"], r=PROBLEM["r"],
                           x0=PROBLEM["x0"])
    n_cal = by_profile(profile, **CALIBRATION_TRIALS) if n_trials is None else n_trials
    return np.array([float(event.calibrate_delta(model, float(rho), n_trials=n_cal,
                                                 steps=PROBLEM["T"], burn_in=1,
                                                 seed=seed + 1).delta[0]) for rho in rates])



def summary_stats(s: comparison.Summary) -> dict:
    """The statistics an entry stores for one run.

    Parameters
    ----------
    s : fusioncenter.comparison.Summary
        The run's summary.

    Returns
    -------
    dict
        ``rate``, ``arrived`` (transmissions, packets arrived per step), ``pos``, ``vel``
        (time-averaged RMSE), each with its ``_se``; ``mse_state`` (mean squared error of the
        state) and ``trace`` (mean tr P; NaN for a particle filter, which has none).
    """
    rate, rate_se = s.rate()
    arr, arr_se = s.rate("arrived")
    pos, pos_se = s.tavg_rmse("position")
    vel, vel_se = s.tavg_rmse("velocity")
    return {"rate": rate, "rate_se": rate_se, "arrived": arr, "arrived_se": arr_se,
            "pos": pos, "pos_se": pos_se, "vel": vel, "vel_se": vel_se,
            "mse_state": float(s._sq("state").mean()),
            "trace": float(np.nanmean(s.samples[..., 2])) if np.isfinite(
                s.samples[..., 2]).all() else np.nan}


def stack(summaries, prefix: str, out: dict) -> None:
    """Store the statistics of a list of summaries as arrays ``{prefix}_{stat}``.

    Parameters
    ----------
    summaries : list of fusioncenter.comparison.Summary
        One run per point of the group.
    prefix : str
        The group's name ``G`` (the keys are ``G_rate``, ``G_pos``, ...).
    out : dict
        The entry's data, filled in place.
    """
    rows = [summary_stats(s) for s in summaries]
    for key in rows[0]:
        out[f"{prefix}_{key}"] = np.array([r[key] for r in rows])


def paired(a, b, out: dict, name: str, rate: bool = False) -> None:
    """Paired differences ``a - b`` (lists of summaries) as ``{name}`` and ``{name}_se``.

    Parameters
    ----------
    a, b : list of fusioncenter.comparison.Summary
        Runs on the same trials, element by element.
    out : dict
        The entry's data, filled in place.
    name : str
        The key of the differences.
    rate : bool, default False
        Difference of the transmissions per step rather than of the time-averaged RMSE.
    """
    d = [x.paired_difference(y, rate=rate) for x, y in zip(a, b, strict=True)]
    out[name] = np.array([v for v, _ in d])
    out[f"{name}_se"] = np.array([e for _, e in d])
