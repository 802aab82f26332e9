"""The exact no-feedback filter of the linear scenario (:class:`ExactFusionCentre`): CFwMD
without feedback, its particles carrying every sensor's local prediction, so that the
likelihood of who sent is exact (the Bayes filter Proposition 3 approximates)."""

from __future__ import annotations

import numpy as np

from fusioncenter._compiled.censored_normal import log_gauss, log_prob_inside, truncated_normal
from fusioncenter.censoring.fusion.base import ExactModel
from fusioncenter.censoring.scenarios import LinearScenario


class ExactFusionCentre(ExactModel):
    """CFwMD without feedback, exact: a particle is ``(x_t, xhat^1_{t|t-1}, ..., xhat^N_{t|t-1})``.

    Given a particle, a sensor's decision is deterministic in its measurement, so the weight is
    exact: ``N(z^i; h^T x, r) 1{|z^i - h^T xhat^i| >= a_i}`` for a received ``z^i`` and
    ``P(|h^T x + n - h^T xhat^j| < a_j)`` for a silent sensor. Before the next propagation each
    particle runs the sensors' Kalman updates, with the received ``z^i`` or with a draw of the
    missing ``z^j`` from ``N(h^T x, r)`` truncated to the silent interval (its exact conditional
    law). As the number of particles grows this is the Bayes filter of the FC's data, which
    Proposition 3 approximates. State dimension ``2 (N + 1)``; the estimate is its first two
    components. If in a trial no particle satisfies the received sensors' constraints (rare: a
    few per thousand trial-steps with 250 particles), that step uses the weights without those
    indicators and is counted in ``relaxed`` (reported as ``CensoringResult.collapsed``).

    Parameters
    ----------
    sc : LinearScenario
        The scenario.
    eta : float
        Threshold.
    z : numpy.ndarray
        Measurements ``(n, T, N)``.
    sent : numpy.ndarray
        Who sent ``(n, T, N)``, bool.
    """

    def __init__(self, sc: LinearScenario, eta: float, z: np.ndarray, sent: np.ndarray):
        self.sc, self.eta, self.z, self.sent = sc, eta, z, sent
        self.relaxed = np.zeros(sent.shape[:2], dtype=bool)
        N = self.N = sc.N
        self.dim = 2 * (N + 1)
        self.H, self.r, self.sd = sc.H, sc.rvec, np.sqrt(sc.rvec)
        self.local = sc.local_filters()
        self.a = np.sqrt(eta * self.local["s"])  # (T, N)
        # flat layout of the local predictions (2N,): h^T xhat^i for every i, and the KF step
        # xhat^i_{t+1|t} = F xhat^i + F w_t^i nu^i in matrix form (all stacked matmuls)
        self.Hblk = np.zeros((2 * N, N))
        for i in range(N):
            self.Hblk[2 * i:2 * i + 2, i] = self.H[i]
        self.Fblk = np.kron(np.eye(N), sc.F).T
        self.G = np.zeros((self.local["gain"].shape[0], N, 2 * N))
        for i in range(N):
            self.G[:, i, 2 * i:2 * i + 2] = self.local["gain"][:, i] @ sc.F.T

    def transition(self, rng, t, xa):
        n, P, _ = xa.shape
        out = np.empty_like(xa)
        xh = xa[..., 2:]
        if t > 1:  # the sensors' KF updates at t - 1, then their predictions for t
            k = t - 2
            hxh = xh @ self.Hblk  # (n, P, N)
            mu = xa[..., :2] @ self.H.T  # E[z | x] per sensor
            zk = np.broadcast_to(self.z[:, k][:, None, :], hxh.shape).copy()
            u = rng.random(hxh.shape)
            for i in range(self.N):  # the trials where sensor i was silent (all particles)
                rows = np.flatnonzero(~self.sent[:, k, i])
                if rows.size:
                    sd, a = self.sd[i], self.a[k, i]
                    c, m = hxh[rows, :, i], mu[rows, :, i]
                    zk[rows, :, i] = m + sd * truncated_normal(u[rows, :, i], (c - a - m) / sd,
                                                               (c + a - m) / sd)
            out[..., 2:] = xh @ self.Fblk + (zk - hxh) @ self.G[k]
        else:
            out[..., 2:] = xh
        out[..., :2] = self.sc.dynamics.transition(rng, t, np.ascontiguousarray(xa[..., :2]))
        return out

    def log_weight(self, t, xa):
        k = t - 1
        hx = xa[..., :2] @ self.H.T
        hxh = xa[..., 2:] @ self.Hblk
        sent = self.sent[:, k][:, None, :]
        z = self.z[:, k][:, None, :]
        out = np.where(sent, log_gauss(np.where(sent, z, 0.0), hx, self.r), 0.0)
        ok = None  # (n, P): the particle's local predictions explain who sent
        for i in range(self.N):  # sensor by sensor: the same elementwise arithmetic
            rows = np.flatnonzero(~self.sent[:, k, i])
            if rows.size:
                sd = self.sd[i]
                out[rows, :, i] = log_prob_inside((hx[rows, :, i] - hxh[rows, :, i]) / sd,
                                                  self.a[k, i] / sd)
            ok_i = ~sent[..., i] | (np.abs(z[..., i] - hxh[..., i]) >= self.a[k, i])
            ok = ok_i if ok is None else np.logical_and(ok, ok_i, out=ok)
        if self.N < 8:  # NumPy's sum over a short axis: 0.0 + out_0 + out_1 + ..., in turn
            full = np.add(0.0, out[..., 0])
            for i in range(1, self.N):
                full += out[..., i]
        else:
            full = out.sum(axis=-1)
        return self._consistent(full, ok, k)
