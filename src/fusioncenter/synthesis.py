"""One tracking problem, four ideas: the schemes of Parts I-IV on the same data, over a faded link.

What the other modules cannot express, and only that:

* the Kalman-filter family (all-send, random selection, mo2015's stochastic trigger with its
  exact filter) run on *given* data, so that it can be paired trial by trial with
  :func:`fusioncenter.censoring.run` (the particle-filter family of zheng2014);
* a packet link with Rayleigh block fading between each sensor and the fusion centre (FC), for
  both families, with two receivers: one that knows the channel gains (dey2009's channel-state
  information at the receiver) and a naive one that reads every missing packet as silence.

The model is :class:`fusioncenter.censoring.LinearScenario` (zheng2014 Section VII.A). Time runs
``t = 1..T``; ``x_0`` is the prior mean (known when ``P0 = 0``), as in ``censoring``.

The link. Sensor ``i``'s packet at step ``t`` goes through a channel whose power gain
``g = h^2`` is exponential with mean ``1 / lam`` (Rayleigh fading, dey2009 Section 3.1.1;
:class:`fusioncenter.fading.Rayleigh`), drawn independently per sensor and step (block fading). A
packet is decoded iff ``g >= g_th``: the outage probability is
``eps = P(g < g_th) = 1 - exp(-lam g_th)`` (:func:`outage_threshold` inverts it). Transmit power
enters only through ``g_th`` (a receiver needs ``g P / sigma_n^2 >= theta``, so ``g_th = theta
sigma_n^2 / P``): spending the same average energy on fewer packets lowers their outage,
``eps(rate) = 1 - (1 - eps_1)^rate`` (:func:`energy_matched_outage`).

Receivers. ``"csi"``: the FC knows every channel gain (estimated from pilots, dey2009 Remark 1),
so it knows which sensors were in outage; a sensor in outage tells it nothing (whether the sensor
sent or not, nothing arrives), a sensor with a good channel that delivered nothing was silent.
Then every filter here stays exact: mo2015's silent sensor is still the measurement ``0`` with
variance ``r_i + delta_i``, and zheng2014's silent-sensor probability is still the right
likelihood. ``"naive"``: the FC ignores the channel and treats every missing packet as silence
(what Parts I and IV do, since they assume a perfect link). All-send, random selection and CFoMD
drop missing packets, which is exact (all-send, random: the loss is independent of the data) or
already an approximation (CFoMD) whatever the receiver.

Entry points (each documented below): the model :func:`scenario_model`, the channel
(:func:`outage_threshold`, :func:`energy_matched_outage`, :func:`draw`), the Kalman filters
(:func:`kf_filter`, :class:`KFRun`, :func:`kf_chunk`, :func:`run_kf`), the particle filters
(:func:`run_pf`, :class:`Summary`, :func:`summary_from_censoring`) and the operation counts
(:func:`kf_flops`, :func:`pf_flops`).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from fusioncenter import _kalman_core, censoring, montecarlo, particle
from fusioncenter import _validate as _v
from fusioncenter._compiled import censored_normal
from fusioncenter._docstrings import Glossary
from fusioncenter._validate import finite as _finite
from fusioncenter.fading import Rayleigh
from fusioncenter.kalman import LinearGaussianModel

__all__ = [
    "KF_SCHEMES",
    "PF_SCHEMES",
    "RECEIVERS",
    "scenario_model",
    "outage_threshold",
    "energy_matched_outage",
    "Draw",
    "draw",
    "KFOutput",
    "kf_filter",
    "KFRun",
    "kf_chunk",
    "run_kf",
    "run_pf",
    "Summary",
    "summary_from_censoring",
    "kf_flops",
    "pf_flops",
]

#: Kalman-filter schemes: every sensor sends; each sends with probability ``p`` independently of
#: the data (missing at random); mo2015's stochastic trigger on the innovation, exact filter.
KF_SCHEMES = ("all-send", "random", "stochastic")
#: Particle-filter schemes of zheng2014 (state feedback): silent sensors dropped or used.
PF_SCHEMES = ("cfomd", "cfwmd")
#: How the FC reads a missing packet (see the module docstring).
RECEIVERS = ("csi", "naive")

#: The arguments of the module's functions, by name.
_doc = Glossary("""
scenario : fusioncenter.censoring.LinearScenario
    The tracking problem.
rng : numpy.random.Generator
    The block's generator (spawned as :func:`draw` says).
n : int
    Trials of the block.
channel : Rayleigh, optional
    The law of the power gains (default ``Rayleigh(1)``, mean gain 1).
z : array_like
    Measurements ``(n, T, N)``.
xi : array_like
    Uniforms in ``[0, 1]`` ``(n, T, N)``, used as in :class:`Draw`.
lost : array_like
    Boolean ``(n, T, N)``: the channel was in outage (a packet sent then is not decoded).
scheme : str
    One of :data:`KF_SCHEMES`.
delta : float or array_like, optional
    ``"stochastic"`` only: the trigger parameter, ``> 0``, shared or one per sensor.
p : float or array_like, optional
    ``"random"`` only: the send probability in ``[0, 1]``, shared or one per sensor.
outage : float
    Outage probability of every packet, in ``[0, 1)``.
receiver : str
    How the FC reads a missing packet, one of :data:`RECEIVERS`.
runs : sequence of KFRun
    The configurations, run on the same trials.
l : float
    Average number of sensors sending per step (sets ``eta = censoring.threshold(l, N)``).
n_trials : int
    Number of Monte Carlo trials.
n_particles : int
    Particles per trial, ``>= 1``.
seed : int
    Non-negative seed; with ``n_trials`` and ``block_size`` it fixes the trials.
block_size, executor, chunk_size
    As in :func:`fusioncenter.montecarlo.simulate`.
""", raises="""
ValueError
    If an argument is invalid (the message names it).
""")


# ----------------------------------------------------------------------------- validation
def _scenario(scenario) -> censoring.LinearScenario:
    if not isinstance(scenario, censoring.LinearScenario):
        raise ValueError("scenario must be a fusioncenter.censoring.LinearScenario")
    return scenario


def _outage(outage) -> float:
    try:
        ok = not isinstance(outage, bool | str | bytes) and 0.0 <= float(outage) < 1.0
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise ValueError(f"outage must be a probability in [0, 1), got {outage!r}")
    return float(outage)


def _receiver(receiver: str) -> str:
    if receiver not in RECEIVERS:
        raise ValueError(f"receiver must be one of {RECEIVERS}, got {receiver!r}")
    return receiver


def _per_sensor(name: str, value, N: int) -> np.ndarray:
    arr = _finite(name, value)
    if arr.ndim == 0:
        arr = np.full(N, float(arr))
    if arr.shape != (N,) or not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be a finite scalar or one value per sensor ({N},), "
                         f"got {value!r}")
    return arr


# ----------------------------------------------------------------------------- model, link
@_doc(returns=("LinearGaussianModel", "The scenario's model (one row of ``C`` per sensor)."))
def scenario_model(scenario) -> LinearGaussianModel:
    """The scenario as a :class:`~fusioncenter.kalman.LinearGaussianModel` (``A = F``, ``C = H``,
    ``R = diag(r)``, ``m0 = x0``, ``P0``); for the defaults this is
    :func:`fusioncenter.models.tracking_model` with two sensors."""
    sc = _scenario(scenario)
    dyn = sc.dynamics
    return LinearGaussianModel(A=sc.F, Q=sc.Q, C=sc.H, R=np.diag(sc.rvec), m0=dyn.m0,
                               P0=dyn.P0)


@_doc(returns=("float", "``g_th >= 0``."))
def outage_threshold(outage, channel: Rayleigh | None = None) -> float:
    """The power-gain threshold ``g_th`` with ``P(g < g_th) = outage`` for a Rayleigh channel.

    ``g ~ Exp(mean 1/lam)``: ``g_th = -log(1 - outage) / lam``.
    """
    eps = _outage(outage)
    channel = Rayleigh(1.0) if channel is None else channel
    if not isinstance(channel, Rayleigh):
        raise ValueError(f"channel must be a fusioncenter.fading.Rayleigh, got {channel!r}")
    return float(-math.log1p(-eps) / channel.lam)


@_doc(returns=("float or numpy.ndarray", "The outage probability, broadcast over the arguments."),
      outage_full=("array_like", "Outage when sending at every step, in ``[0, 1)``."),
      rate=("array_like", "Fraction of the steps with a packet, in ``[0, 1]``."))
def energy_matched_outage(outage_full, rate):
    """Outage of a sensor that sends a fraction ``rate`` of the steps with the energy that
    sending at every step with outage ``outage_full`` would use.

    Per-packet power ``P / rate`` lowers the threshold to ``rate g_th``, so
    ``eps = 1 - exp(-lam rate g_th) = 1 - (1 - outage_full)^rate``. Broadcasts.
    """
    eps = _finite("outage_full", outage_full)
    rate = _finite("rate", rate)
    if np.any((eps < 0) | (eps >= 1)) or not np.all(np.isfinite(eps)):
        raise ValueError(f"outage_full must lie in [0, 1), got {outage_full!r}")
    if np.any((rate < 0) | (rate > 1)) or not np.all(np.isfinite(rate)):
        raise ValueError(f"rate must lie in [0, 1], got {rate!r}")
    out = -np.expm1(rate * np.log1p(-eps))
    return out[()] if out.ndim == 0 else out


class Draw(NamedTuple):
    """One block of trials (:func:`draw`).

    Attributes
    ----------
    x : numpy.ndarray
        The truth ``(n, T+1, 2)`` (``x[:, 0] = x_0``).
    z : numpy.ndarray
        The measurements ``(n, T, N)``.
    xi : numpy.ndarray
        Uniforms ``(n, T, N)``: random selection sends iff ``xi < p``, the trigger iff
        ``xi > exp(-nu^2 / (2 delta))``.
    gain : numpy.ndarray
        Channel power gains ``(n, T, N)``.
    rng_pf : numpy.random.Generator
        The generator left for the particle filter.
    """

    x: np.ndarray
    z: np.ndarray
    xi: np.ndarray
    gain: np.ndarray
    rng_pf: np.random.Generator


@_doc(returns=("Draw", "The block's truth, measurements, uniforms, gains and particle stream."))
def draw(rng: np.random.Generator, n: int, scenario, channel: Rayleigh | None = None) -> Draw:
    """Draw a block of trials exactly as :func:`fusioncenter.censoring.run` does, plus the link.

    ``rng.spawn(3)``: the first child draws the truth, the measurements and the uniforms in
    ``censoring``'s documented order (so a run here with the same ``seed``, ``n_trials`` and
    ``block_size`` as ``censoring.run`` sees the same trajectories and measurements), the second
    is the particle filter's, the third draws the channel gains. The gains do not depend on the
    outage probability, so the lost packets at a larger outage include those at a smaller one
    (nested losses, for paired comparisons).
    """
    sc = _scenario(scenario)
    channel = Rayleigh(1.0) if channel is None else channel
    rng_data, rng_pf, rng_chan = _v.generator("rng", rng).spawn(3)
    x, z = sc.sample(rng_data, _v.integer("n", n))
    xi = rng_data.random(z.shape)
    gain = channel.sample(rng_chan, z.shape)
    return Draw(x, z, xi, gain, rng_pf)


# ----------------------------------------------------------------------------- Kalman family
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
        d = _per_sensor("delta", delta, N)
        if np.any(d <= 0):
            raise ValueError(f"delta must be positive, got {delta!r}")
        return d, None
    if delta is not None:
        raise ValueError(f"delta is only used by scheme 'stochastic', not {scheme!r}")
    if scheme == "random":
        if p is None:
            raise ValueError("scheme 'random' needs p (send probabilities)")
        pp = _per_sensor("p", p, N)
        if np.any((pp < 0) | (pp > 1)):
            raise ValueError(f"p must lie in [0, 1], got {p!r}")
        return None, pp
    if p is not None:
        raise ValueError("p is only used by scheme 'random'")
    return None, None


@_doc(returns=("KFOutput", "The filtered moments and who sent and arrived, per trial and step."))
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
    sc = _scenario(scenario)
    receiver = _receiver(receiver)
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
        xhat[:, t], Ps[:, t], xpred, Ppred = _kalman_core.kalman_step(  # R_k = diag(noise)
            xpred, Ppred, np.where(arrived, nu, 0.0), Ck, Rk, A, Q,
            r_singular=bool(np.any(noise == 0)))
        sent_all[:, t], arr_all[:, t] = sent, arrived
    return KFOutput(xhat=xhat, P=Ps, sent=sent_all, arrived=arr_all)


@_doc.attributes()
@dataclass(frozen=True)
class KFRun:
    """One Kalman-filter configuration for :func:`run_kf` (validated when run)."""

    scheme: str
    delta: float | tuple | None = None
    p: float | tuple | None = None
    outage: float = 0.0
    receiver: str = "csi"


#: Columns of a per-trial summary: squared error of position and velocity, trace of the FC's
#: covariance (NaN for particle filters), number of sensors that sent, number whose packet
#: arrived.
COLUMNS = ("sq_pos", "sq_vel", "trace_P", "sent", "arrived")


@_doc(returns=("numpy.ndarray", "``(n, T, len(runs), 5)``, the columns :data:`COLUMNS`."))
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


@_doc(returns=("list of Summary", "One per run, in the order of ``runs``."))
def run_kf(scenario, runs, *, n_trials: int, seed: int, channel: Rayleigh | None = None,
           block_size: int = montecarlo.DEFAULT_BLOCK_SIZE, executor=None,
           chunk_size: int | None = None) -> list[Summary]:
    """Run every :class:`KFRun` of ``runs`` on the same trials; one :class:`Summary` each.

    With the same ``seed``, ``n_trials`` and ``block_size`` the trials are those of
    :func:`fusioncenter.censoring.run` and :func:`run_pf` (paired).
    """
    sc = _scenario(scenario)
    runs = tuple(runs)
    if not runs or not all(isinstance(r, KFRun) for r in runs):
        raise ValueError("runs must be a non-empty sequence of KFRun")
    for r in runs:  # validate before simulating
        _scheme_params(r.scheme, sc.N, r.delta, r.p)
        _outage(r.outage)
        _receiver(r.receiver)
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


# ----------------------------------------------------------------------------- particle family
class _LossyCensoring:
    """zheng2014's fusion centre with state feedback (``feedback="state"``, analytic moments)
    over the faded link: a :class:`fusioncenter.particle.FilterModel` that also plays the sensors.

    Sensor ``i`` sends iff ``nu_i^2 >= eta s_i`` (``nu_i`` against the broadcast
    ``xhat_{t|t-1} = F xhat_{t-1|t-1}``, ``s_i`` from its own Kalman filter). Log weight: the
    Gaussian log-likelihood of every arrived value; for CFwMD also, for every sensor the receiver
    believes silent, ``log P(|h_i x + n - h_i xhat_{t|t-1}| < sqrt(eta s_i))``.
    """

    needs_cov = False
    dim = 2

    def __init__(self, sc, scheme, receiver, eta, z, lost):
        self.sc, self.scheme, self.receiver, self.eta = sc, scheme, receiver, eta
        self.z, self.lost = z, lost
        n, T, N = z.shape
        self.H, self.r = sc.H, sc.rvec
        self.sd = np.sqrt(self.r)
        self.s = sc.local_filters()["s"]  # (T, N)
        self.groups = sc.sensor_groups()
        dyn = sc.dynamics
        self.pred_mean = np.broadcast_to(dyn.F @ dyn.m0, (n, 2)).copy()
        self.sent = np.zeros((n, T, N), dtype=bool)
        self.arrived = np.zeros((n, T, N), dtype=bool)

    def initial(self, rng, n, P):
        return self.sc.dynamics.initial(rng, n, P)

    def transition(self, rng, t, x):
        return self.sc.dynamics.transition(rng, t, x)

    def log_weight(self, t, x):
        k = t - 1
        s = self.s[k]
        nu = self.z[:, k] - self.pred_mean @ self.H.T  # (n, N)
        sent = nu * nu >= self.eta * s
        arrived = sent & ~self.lost[:, k]
        self.sent[:, k], self.arrived[:, k] = sent, arrived
        silent = None
        if self.scheme == "cfwmd":
            silent = ~arrived if self.receiver == "naive" else ~arrived & ~self.lost[:, k]
        zk = self.z[:, k]
        out = np.zeros(x.shape[:2])
        for g in self.groups:  # sensors with equal (h, r) share every term
            i0 = g[0]
            y = x @ self.H[i0]  # (n, P): h^T x of every particle
            ar = arrived[:, g]
            n_obs = ar.sum(axis=1).astype(float)
            if n_obs.any():  # sum_i (z_i - y)^2 = n (y - zbar)^2 + sum_i (z_i - zbar)^2
                zs = np.where(ar, zk[:, g], 0.0)
                zbar = zs.sum(axis=1) / np.maximum(n_obs, 1.0)
                ss = np.where(ar, zs - zbar[:, None], 0.0) ** 2
                out += (-0.5 / self.r[i0]) * (n_obs[:, None] * (y - zbar[:, None]) ** 2
                                              + ss.sum(axis=1)[:, None])
            if silent is None:
                continue
            n_sil = silent[:, g].sum(axis=1)
            rows = n_sil > 0
            if rows.any():
                mu = (y[rows] - (self.pred_mean[rows] @ self.H[i0])[:, None]) / self.sd[i0]
                h = np.full(mu.shape, math.sqrt(self.eta * s[i0]) / self.sd[i0])
                out[rows] += n_sil[rows, None] * censored_normal.log_prob_inside(mu, h)
        return out

    def observe(self, t, mean, cov):
        self.pred_mean = mean @ self.sc.F.T


def _pf_chunk(rng, n, *, scenario, scheme, receiver, eta, outage, n_particles, channel):
    d = draw(rng, n, scenario, channel)
    ch = Rayleigh(1.0) if channel is None else channel
    lost = d.gain < outage_threshold(outage, ch)
    fc = _LossyCensoring(scenario, scheme, receiver, eta, d.z, lost)
    res = particle.run_filter(fc, d.rng_pf, n, n_particles, scenario.T)
    out = np.empty((n, scenario.T, len(COLUMNS)))
    out[..., 0:2] = (res.mean - d.x[:, 1:]) ** 2
    out[..., 2] = np.nan
    out[..., 3] = fc.sent.sum(axis=-1)
    out[..., 4] = fc.arrived.sum(axis=-1)
    return out


@_doc(returns=("Summary", "Per-trial results; ``trace_P`` is NaN."),
      scheme=("str", "One of :data:`PF_SCHEMES`."))
def run_pf(scenario, scheme: str, *, l, n_trials: int, n_particles: int, seed: int,
           outage: float = 0.0, receiver: str = "csi", channel: Rayleigh | None = None,
           block_size: int = montecarlo.DEFAULT_BLOCK_SIZE, executor=None,
           chunk_size: int | None = None) -> Summary:
    """CFoMD or CFwMD (zheng2014, state feedback, threshold ``eta = censoring.threshold(l, N)``,
    resampling at every step) over the faded link.

    The trials are paired with :func:`run_kf` and :func:`fusioncenter.censoring.run` (same
    ``seed``, ``n_trials``, ``block_size``). With ``outage = 0`` it is the filter of
    ``censoring.run`` (a test compares the two); the particles come from the block's second
    spawned stream (PCG64), so the two agree within their particle-filter Monte Carlo error, not
    draw for draw.
    """
    sc = _scenario(scenario)
    if scheme not in PF_SCHEMES:
        raise ValueError(f"scheme must be one of {PF_SCHEMES}, got {scheme!r}")
    eta = censoring.threshold(l, sc.N)
    n_particles = _v.posint("n_particles", n_particles)
    fn = functools.partial(_pf_chunk, scenario=sc, scheme=scheme, receiver=_receiver(receiver),
                           eta=eta, outage=_outage(outage), n_particles=n_particles,
                           channel=channel)
    mc = montecarlo.simulate(fn, n_trials, seed, block_size=block_size, executor=executor,
                             chunk_size=chunk_size)
    label = scheme + (f" (outage {outage:g}, {receiver})" if outage > 0 else "")
    return Summary(label=label, samples=mc.samples, seed=seed, block_size=block_size)


# ----------------------------------------------------------------------------- summaries
@_doc.attributes(label=("str", "The scheme (and link) it summarizes."),
                 samples=("numpy.ndarray", "``(n_trials, T, 5)``, the columns :data:`COLUMNS`."))
@dataclass(frozen=True)
class Summary(montecarlo.PerTrial):
    """Per-trial results of one scheme; ``seed`` and ``block_size`` identify the trials: two
    summaries with equal ``seed``, ``block_size`` and ``n_trials`` are paired (same trials)."""

    label: str
    samples: np.ndarray = field(repr=False)
    seed: int
    block_size: int

    def _sq(self, component: str) -> np.ndarray:
        cols = {"position": [0], "velocity": [1], "state": [0, 1]}.get(component)
        if cols is None:
            raise ValueError(f"component must be 'position', 'velocity' or 'state', "
                             f"got {component!r}")
        return self.samples[..., cols].sum(axis=-1)  # (n, T)

    def _influence(self, component: str):
        sq = self._sq(component)
        rm = np.sqrt(sq.mean(axis=0))
        with np.errstate(divide="ignore", invalid="ignore"):
            infl = np.where(rm > 0, sq / (2 * rm), 0.0).mean(axis=1)
        return float(rm.mean()), infl

    def tavg_rmse(self, component: str = "position") -> tuple[float, float]:
        """``mean_t sqrt(mean_trials e_t^2)`` and its standard error (delta method over trials,
        as :meth:`fusioncenter.censoring.CensoringResult.time_averaged_rmse`)."""
        value, infl = self._influence(component)
        return value, _se(infl)

    def rmse_k(self, component: str = "position") -> tuple[np.ndarray, np.ndarray]:
        """RMSE per step and its standard error, both ``(T,)``."""
        sq = self._sq(component)
        rm = np.sqrt(sq.mean(axis=0))
        se = sq.std(axis=0, ddof=1) / math.sqrt(sq.shape[0])
        with np.errstate(divide="ignore", invalid="ignore"):
            return rm, np.where(rm > 0, se / (2 * rm), 0.0)

    def rate(self, column: str = "sent") -> tuple[float, float]:
        """Average number of sensors per step that sent (or whose packet ``"arrived"``), with
        its standard error across trials."""
        j = {"sent": 3, "arrived": 4}.get(column)
        if j is None:
            raise ValueError(f"column must be 'sent' or 'arrived', got {column!r}")
        per = self.samples[..., j].mean(axis=1)
        return float(per.mean()), _se(per)

    def calibration(self) -> tuple[float, float]:
        """Mean over trials and steps of ``||x - xhat||^2 - tr P`` (0 for an exact filter), with
        its standard error; NaN for particle filters."""
        per = (self._sq("state") - self.samples[..., 2]).mean(axis=1)
        return float(per.mean()), _se(per)

    def paired_difference(self, other: Summary, component: str = "position",
                          rate: bool = False) -> tuple[float, float]:
        """This summary's time-averaged RMSE (or, with ``rate=True``, transmissions per step)
        minus ``other``'s, with the paired standard error (trials differenced one by one)."""
        if not isinstance(other, Summary):
            raise ValueError("other must be a Summary")
        if not self.same_trials(other):
            raise ValueError("the two summaries are not paired (seed, block_size and n_trials "
                             "must agree)")
        if rate:
            a, b = self.samples[..., 3].mean(axis=1), other.samples[..., 3].mean(axis=1)
            return float(a.mean() - b.mean()), _se(a - b)
        va, ia = self._influence(component)
        vb, ib = other._influence(component)
        return va - vb, _se(ia - ib)


def _se(per: np.ndarray) -> float:
    return float(per.std(ddof=1) / math.sqrt(per.size)) if per.size > 1 else math.nan


@_doc(returns=("Summary", "Labelled with the result's scheme; ``trace_P`` is NaN."),
      result=("fusioncenter.censoring.CensoringResult", "A run of the particle-filter family."))
def summary_from_censoring(result) -> Summary:
    """A :class:`Summary` of a :class:`fusioncenter.censoring.CensoringResult` (its documented
    ``mc.samples`` columns ``[sq error (2) | sensors that sent | ESS | collapsed]``); every
    packet arrives (a perfect link)."""
    if not isinstance(result, censoring.CensoringResult):
        raise ValueError("result must be a fusioncenter.censoring.CensoringResult")
    s = result.mc.samples
    out = np.empty(s.shape[:2] + (len(COLUMNS),))
    out[..., 0:2] = s[..., 0:2]
    out[..., 2] = np.nan
    out[..., 3] = s[..., 2]
    out[..., 4] = s[..., 2]
    return Summary(label=result.scheme, samples=out, seed=result.mc.seed,
                   block_size=result.mc.block_size)


# ----------------------------------------------------------------------------- cost model
def _matmul(a: int, b: int, c: int) -> int:
    """Floating-point operations of an ``(a, b) @ (b, c)`` product: ``a c (2 b - 1)``."""
    return a * c * (2 * b - 1)


def _solve(k: int, rhs: int) -> int:
    """LU solve of a ``k x k`` system with ``rhs`` right-hand sides: ``2k^3/3 + 2 k^2 rhs``."""
    return (2 * k**3) // 3 + 2 * k * k * rhs


@_doc(returns=("dict", '``{"flops": int, "special": int}``.'),
      n=("int", "State dimension."), m=("int", "Number of sensors."))
def kf_flops(n: int = 2, m: int = 2) -> dict[str, int]:
    """Operation count of one step of :func:`kf_filter` for one trial (``n`` states, ``m``
    sensors), term by term as the code computes it (a dropped or silent sensor costs the same):
    ``flops`` counts additions and multiplications, ``special`` the exponentials of the trigger.
    """
    f, n, m = 0, _v.posint("n", n), _v.posint("m", m)
    f += _matmul(1, n, m) + m  # innovations nu = z - xpred H^T
    f += 3 * m  # the trigger (nu^2 / (2 delta)), or the random-selection comparison
    f += _matmul(n, n, m)  # P C^T
    f += _matmul(m, n, m) + m  # S = C P C^T + R
    f += _solve(m, 1) + _matmul(n, m, 1) + n  # S^{-1} nu, xpost
    f += _solve(m, n) + _matmul(n, m, n) + n * n  # P - P C^T S^{-1} C P
    f += _matmul(1, n, n)  # xpred = F xpost
    f += 2 * _matmul(n, n, n) + n * n  # F P F^T + Q
    return {"flops": int(f), "special": m}


@_doc(returns=("dict", '``{"flops": int, "special": int}``, for all the particles.'),
      n=("int", "State dimension."), m=("int", "Number of sensors."),
      scheme=("str", '``"all-send"``, ``"random"``, ``"cfomd"`` or ``"cfwmd"``.'))
def pf_flops(n: int = 2, m: int = 2, n_particles: int = 1000,
             scheme: str = "cfwmd") -> dict[str, int]:
    """Operation count of one step of the particle filter (zheng2014, state feedback) for one
    trial: per particle, the propagation ``F x + L u`` (``rank Q = 1``: one normal), ``h_i^T x``
    for each sensor, the Gaussian term of each received sensor (3 flops), for CFwMD the silent
    sensor's ``log(Phi(b) - Phi(a))`` (4 flops and 3 special functions per sensor), the weight
    normalization (max, exp, sum: 3 flops and 1 exp), the weighted mean (``2 n``), the ESS (2)
    and systematic resampling (cumulative sum and search, ~4). Counted with every sensor both
    received and silent as the worst case, so it is an upper estimate of a step's work;
    ``special`` counts exponentials, logarithms, ``ndtr`` calls and normal draws.
    """
    if scheme not in ("all-send", "random") + PF_SCHEMES:
        raise ValueError(f"scheme must be 'all-send', 'random', 'cfomd' or 'cfwmd', "
                         f"got {scheme!r}")
    n, m, n_particles = _v.posint("n", n), _v.posint("m", m), _v.posint("n_particles", n_particles)
    per = _matmul(1, n, n) + 2 * n  # F x + L u
    per += m * (2 * n - 1)  # h_i^T x
    per += 3 * m  # received: -(z - hx)^2 / (2 r)
    special = 1  # the normal draw of the propagation
    if scheme == "cfwmd":
        per += 4 * m  # (hx - h xpred)/sd, h -/+ m, the difference
        special += 3 * m  # two ndtr and one log per silent sensor
    per += 3  # normalization: subtract the max, sum, divide
    special += 1  # exp of the weight
    per += 2 * n + 2 + 4  # weighted mean, ESS, resampling
    return {"flops": int(per * n_particles), "special": int(special * n_particles)}
