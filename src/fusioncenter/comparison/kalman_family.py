"""The Kalman-filter family on given data: all-send, random selection and mo2015's stochastic
trigger with its exact filter (:func:`kf_filter`), run over the faded link on the trials of
:func:`fusioncenter.censoring.run` so that it pairs with the particle-filter family
(:class:`KFRun`, :func:`kf_chunk`, :func:`run_kf`)."""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from fusioncenter import _validate as _v
from fusioncenter import montecarlo
from fusioncenter._compiled import kalman_step as step_kernel
from fusioncenter._validate import finite as _finite
from fusioncenter.comparison._args import (
    check_outage,
    check_receiver,
    check_scenario,
    doc,
    per_sensor,
)
from fusioncenter.comparison.link import draw, outage_threshold
from fusioncenter.comparison.paired import COLUMNS, Summary
from fusioncenter.fading import Rayleigh
from fusioncenter.kalman import LinearGaussianModel

__all__ = ["KF_SCHEMES", "scenario_model", "KFOutput", "kf_filter", "KFRun", "kf_chunk", "run_kf"]

#: Kalman-filter schemes: every sensor sends; each sends with probability ``p`` independently of
#: the data (missing at random); mo2015's stochastic trigger on the innovation, exact filter.
KF_SCHEMES = ("all-send", "random", "stochastic")


@doc(returns=("LinearGaussianModel", "The scenario's model (one row of ``C`` per sensor)."))
def scenario_model(scenario) -> LinearGaussianModel:
    """The scenario as a :class:`~fusioncenter.kalman.LinearGaussianModel` (``A = F``, ``C = H``,
    ``R = diag(r)``, ``m0 = x0``, ``P0``); for the defaults this is
    :func:`fusioncenter.models.tracking_model` with two sensors."""
    sc = check_scenario(scenario)
    dyn = sc.dynamics
    return LinearGaussianModel(A=sc.F, Q=sc.Q, C=sc.H, R=np.diag(sc.rvec), m0=dyn.m0,
                               P0=dyn.P0)


@dataclass(frozen=True)
class KFOutput:
    """Output of :func:`kf_filter`.

    Attributes
    ----------
    xhat : numpy.ndarray
        Filtered means ``(n, T, 2)``.
    P : numpy.ndarray
        Filtered covariances ``(n, T, 2, 2)``.
    sent : numpy.ndarray
        Boolean ``(n, T, N)``: who sent.
    arrived : numpy.ndarray
        Boolean ``(n, T, N)``: whose packet arrived.
    """

    xhat: np.ndarray
    P: np.ndarray
    sent: np.ndarray
    arrived: np.ndarray


def _scheme_params(scheme: str, N: int, delta, p):
    if scheme not in KF_SCHEMES:
        raise ValueError(f"scheme must be one of {KF_SCHEMES}, got {scheme!r}")
    if scheme == "stochastic":
        if delta is None or p is not None:
            raise ValueError("scheme 'stochastic' needs delta (and no p)")
        d = per_sensor("delta", delta, N)
        if np.any(d <= 0):
            raise ValueError(f"delta must be positive, got {delta!r}")
        return d, None
    if delta is not None:
        raise ValueError(f"delta is only used by scheme 'stochastic', not {scheme!r}")
    if scheme == "random":
        if p is None:
            raise ValueError("scheme 'random' needs p (send probabilities)")
        pp = per_sensor("p", p, N)
        if np.any((pp < 0) | (pp > 1)):
            raise ValueError(f"p must lie in [0, 1], got {p!r}")
        return None, pp
    if p is not None:
        raise ValueError("p is only used by scheme 'random'")
    return None, None


@doc(returns=("KFOutput", "The filtered moments and who sent and arrived, per trial and step."))
def kf_filter(scenario, z, xi, lost, scheme: str, *, delta=None, p=None,
              receiver: str = "csi") -> KFOutput:
    """The Kalman-filter family on given data, vectorized over trials.

    At step ``t`` every sensor computes its innovation against the FC's broadcast prediction,
    ``nu_i = z_i - h_i xhat_{t|t-1}``, and decides: all-send always sends; random selection iff
    ``xi < p_i``; the stochastic trigger iff ``xi > exp(-nu_i^2 / (2 delta_i))`` (mo2015). A
    packet arrives iff sent and not lost. The FC updates with the arrived measurements (noise
    ``r_i``) and, for the trigger only, with every sensor it believes silent as the measurement
    ``nu_i = 0`` with noise ``r_i + delta_i``: receiver ``"csi"`` believes silent the sensors
    whose channel was good, ``"naive"`` every sensor whose packet is missing. All other missing
    sensors are dropped (a zero row of ``C``). Each step is one
    :func:`fusioncenter.kalman.kalman_step` with that ``C_k`` and ``R_k = diag(noise)`` (the
    library's letters: ``A`` is the scenario's ``F``, ``C`` its ``H``).
    """
    sc = check_scenario(scenario)
    receiver = check_receiver(receiver)
    z = _finite("z", z)
    n, T, N = z.shape if z.ndim == 3 else (None, None, None)
    if z.ndim != 3 or T != sc.T or N != sc.N:
        raise ValueError(f"z must be shaped (n, T={sc.T}, N={sc.N}), got {z.shape}")
    xi = _finite("xi", xi)
    if np.any((xi < 0) | (xi > 1)):
        raise ValueError("xi must be uniforms in [0, 1]")
    lost = _v.flags("lost", lost)
    if xi.shape != z.shape or lost.shape != z.shape:
        raise ValueError(f"xi and lost must have z's shape {z.shape}, got {xi.shape}, "
                         f"{lost.shape}")
    delta, p = _scheme_params(scheme, N, delta, p)
    A, Q, C, r = sc.F, sc.Q, sc.H, sc.rvec  # zheng2014 F, H
    dyn = sc.dynamics
    xpred = np.broadcast_to(A @ dyn.m0, (n, 2)).copy()
    Ppred = np.broadcast_to(A @ dyn.P0 @ A.T + Q, (n, 2, 2)).copy()
    xhat = np.empty((n, T, 2))
    Ps = np.empty((n, T, 2, 2))
    sent_all = np.empty((n, T, N), dtype=bool)
    arr_all = np.empty((n, T, N), dtype=bool)
    eye = np.eye(N)
    for t in range(T):
        nu = z[:, t] - xpred @ C.T  # (n, N)
        if scheme == "stochastic":
            sent = xi[:, t] > np.exp(-(nu**2) / (2.0 * delta))
        elif scheme == "random":
            sent = xi[:, t] < p
        else:
            sent = np.ones((n, N), dtype=bool)
        arrived = sent & ~lost[:, t]
        if scheme == "stochastic":
            silent = ~arrived if receiver == "naive" else ~arrived & ~lost[:, t]
            noise = r + np.where(silent, delta, 0.0)
        else:
            silent = np.zeros((n, N), dtype=bool)
            noise = np.broadcast_to(r, (n, N))
        use = arrived | silent
        Ck = C * use[:, :, None]  # (n, N, 2): a dropped sensor is a zero row
        Rk = noise[:, :, None] * eye
        xhat[:, t], Ps[:, t], xpred, Ppred = step_kernel.kalman_step(  # R_k = diag(noise)
            xpred, Ppred, np.where(arrived, nu, 0.0), Ck, Rk, A, Q,
            r_singular=bool(np.any(noise == 0)))
        sent_all[:, t], arr_all[:, t] = sent, arrived
    return KFOutput(xhat=xhat, P=Ps, sent=sent_all, arrived=arr_all)


@doc.attributes()
@dataclass(frozen=True)
class KFRun:
    """One Kalman-filter configuration for :func:`run_kf` (validated when run)."""

    scheme: str
    delta: float | tuple | None = None
    p: float | tuple | None = None
    outage: float = 0.0
    receiver: str = "csi"


@doc(returns=("numpy.ndarray", "``(n, T, len(runs), 5)``, the columns "
                               ":data:`~fusioncenter.comparison.paired.COLUMNS`."))
def kf_chunk(rng: np.random.Generator, n: int, *, scenario, runs: tuple,
             channel: Rayleigh | None = None) -> np.ndarray:
    """``chunk_fn`` for :func:`fusioncenter.montecarlo.simulate`: every run of ``runs`` on the
    same ``n`` trials."""
    d = draw(rng, n, scenario, channel)
    ch = Rayleigh(1.0) if channel is None else channel
    out = np.empty((n, scenario.T, len(runs), len(COLUMNS)))
    for j, run in enumerate(runs):
        lost = d.gain < outage_threshold(run.outage, ch)
        res = kf_filter(scenario, d.z, d.xi, lost, run.scheme, delta=run.delta, p=run.p,
                        receiver=run.receiver)
        sq = (res.xhat - d.x[:, 1:]) ** 2
        out[:, :, j, 0:2] = sq
        out[:, :, j, 2] = np.trace(res.P, axis1=-2, axis2=-1)
        out[:, :, j, 3] = res.sent.sum(axis=-1)
        out[:, :, j, 4] = res.arrived.sum(axis=-1)
    return out


@doc(returns=("list of Summary", "One per run, in the order of ``runs``."))
def run_kf(scenario, runs, *, n_trials: int, seed: int, channel: Rayleigh | None = None,
           block_size: int = montecarlo.DEFAULT_BLOCK_SIZE, executor=None,
           chunk_size: int | None = None) -> list[Summary]:
    """Run every :class:`KFRun` of ``runs`` on the same trials; one
    :class:`~fusioncenter.comparison.paired.Summary` each.

    With the same ``seed``, ``n_trials`` and ``block_size`` the trials are those of
    :func:`fusioncenter.censoring.run` and
    :func:`~fusioncenter.comparison.particle_family.run_pf` (paired).
    """
    sc = check_scenario(scenario)
    runs = tuple(runs)
    if not runs or not all(isinstance(r, KFRun) for r in runs):
        raise ValueError("runs must be a non-empty sequence of KFRun")
    for r in runs:  # validate before simulating
        _scheme_params(r.scheme, sc.N, r.delta, r.p)
        check_outage(r.outage)
        check_receiver(r.receiver)
    fn = functools.partial(kf_chunk, scenario=sc, runs=runs, channel=channel)
    mc = montecarlo.simulate(fn, n_trials, seed, block_size=block_size, executor=executor,
                             chunk_size=chunk_size)
    return [Summary(label=_label(r), samples=mc.samples[:, :, j], seed=seed,
                    block_size=block_size) for j, r in enumerate(runs)]


def _label(run: KFRun) -> str:
    out = run.scheme
    if run.outage > 0:
        out += f" (outage {run.outage:g}, {run.receiver})"
    return out
