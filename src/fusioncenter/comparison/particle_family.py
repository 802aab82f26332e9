"""The particle-filter family over the faded link: zheng2014's fusion centre with state feedback,
CFoMD and CFwMD (:func:`run_pf`), on the same trials as :func:`fusioncenter.censoring.run` and
the Kalman-filter family."""

from __future__ import annotations

import functools
import math

import numpy as np

from fusioncenter import _validate as _v
from fusioncenter import censoring, montecarlo, particle
from fusioncenter._compiled import censored_normal
from fusioncenter.comparison._args import check_outage, check_receiver, check_scenario, doc
from fusioncenter.comparison.link import draw, outage_threshold
from fusioncenter.comparison.paired import COLUMNS, Summary
from fusioncenter.fading import Rayleigh

__all__ = ["PF_SCHEMES", "run_pf"]

#: Particle-filter schemes of zheng2014 (state feedback): silent sensors dropped or used.
PF_SCHEMES = ("cfomd", "cfwmd")


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


@doc(returns=("Summary", "Per-trial results; ``trace_P`` is NaN."),
     scheme=("str", "One of :data:`PF_SCHEMES`."))
def run_pf(scenario, scheme: str, *, l, n_trials: int, n_particles: int, seed: int,
           outage: float = 0.0, receiver: str = "csi", channel: Rayleigh | None = None,
           block_size: int = montecarlo.DEFAULT_BLOCK_SIZE, executor=None,
           chunk_size: int | None = None) -> Summary:
    """CFoMD or CFwMD (zheng2014, state feedback, threshold ``eta = censoring.threshold(l, N)``,
    resampling at every step) over the faded link.

    The trials are paired with :func:`~fusioncenter.comparison.kalman_family.run_kf` and
    :func:`fusioncenter.censoring.run` (same ``seed``, ``n_trials``, ``block_size``). With
    ``outage = 0`` it is the filter of ``censoring.run`` (a test compares the two); the particles
    come from the block's second spawned stream (PCG64), so the two agree within their
    particle-filter Monte Carlo error, not draw for draw.
    """
    sc = check_scenario(scenario)
    if scheme not in PF_SCHEMES:
        raise ValueError(f"scheme must be one of {PF_SCHEMES}, got {scheme!r}")
    eta = censoring.threshold(l, sc.N)
    n_particles = _v.posint("n_particles", n_particles)
    fn = functools.partial(_pf_chunk, scenario=sc, scheme=scheme, receiver=check_receiver(receiver),
                           eta=eta, outage=check_outage(outage), n_particles=n_particles,
                           channel=channel)
    mc = montecarlo.simulate(fn, n_trials, seed, block_size=block_size, executor=executor,
                             chunk_size=chunk_size)
    label = scheme + (f" (outage {outage:g}, {receiver})" if outage > 0 else "")
    return Summary(label=label, samples=mc.samples, seed=seed, block_size=block_size)
