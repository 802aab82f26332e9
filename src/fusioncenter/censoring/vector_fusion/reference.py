"""The reference fusion centres of the vector scenario for :func:`fusioncenter.particle.run_filter`
(zheng2014 Section V): :class:`VectorFC` (every scheme except the exact no-feedback filter) and
:class:`VectorExactFC` (the exact no-feedback filter), with the silent factor evaluated at every
particle by any of the three methods of :func:`~fusioncenter.censoring.ellipse.eval_silent`, and
the imputation of a silent sensor's measurement (:func:`sample_in_ellipse`)."""

from __future__ import annotations

import math

import numpy as np

from fusioncenter._compiled import censored_normal, vector_terms, ziggurat
from fusioncenter.censoring import fusion
from fusioncenter.censoring.ellipse import canonical_map, eval_silent
from fusioncenter.censoring.vector import VectorScenario, local_decisions, whitening

_LOG_2PI = math.log(2.0 * math.pi)


class VectorFC(fusion.FeedbackModel):
    """The FC's particle-filter model (a :class:`fusioncenter.particle.FilterModel`) for one
    block of trials and every scheme except the exact no-feedback filter. It also plays the
    sensors: with feedback their decisions at step ``t`` depend on the FC's broadcast.

    The reference implementation: the silent factor by any of
    :data:`~fusioncenter.censoring.ellipse.PROBABILITIES` at every particle
    (:func:`~fusioncenter.censoring.ellipse.eval_silent`);
    :class:`~fusioncenter.censoring.vector_fusion.fused.FusedVectorFC` is the same model with
    the tables, organized for speed.

    Parameters
    ----------
    sc : VectorScenario
        The scenario.
    scheme, feedback : str
        As in :func:`~fusioncenter.censoring.vector_fusion.run`.
    eta : float
        Censoring threshold.
    l : float
        Average number of sending sensors (random selection sends with probability ``l / N``).
    z : numpy.ndarray
        Measurements ``(n, T, N, m)``.
    sel_u : numpy.ndarray
        Random-selection uniforms ``(n, T, N)``.
    probability : str
        How the silent factor is evaluated (``"table"``, ``"quadrature"`` or ``"sampled"``).
    n_q : int
        Draws per particle for ``probability="sampled"``.
    rng_q : numpy.random.Generator or None
        The stream of those draws.
    """

    def __init__(self, sc: VectorScenario, scheme: str, feedback: str, eta: float, l: float,
                 z: np.ndarray, sel_u: np.ndarray, probability: str, n_q: int,
                 rng_q: np.random.Generator | None):
        self.sc, self.scheme, self.feedback, self.eta = sc, scheme, feedback, eta
        self.probability, self.n_q, self.rng_q = probability, n_q, rng_q
        self.z = z
        n, T, N, m = z.shape
        self.n, self.N, self.m = n, N, m
        self.dim = 2
        self.H, self.R = sc.Hs, sc.Rs
        self.groups = sc.sensor_groups()
        self.local = sc.local_filters()
        self._first_prediction(n)
        self.censor = scheme in ("cfomd", "cfwmd")
        self.fb = self.censor and feedback != "none"
        self.needs_cov = self.fb and feedback == "state+cov" and sc.feedback_moments == "analytic"
        self.sent = fusion.decisions_in_advance(scheme, feedback, l, sel_u, (n, T, N),
                                                lambda: local_decisions(sc, eta, z))
        # received likelihood per group: whitened particles x @ G and measurements
        self.white = {}
        for g in self.groups:
            Linv, logdet = whitening(self.R[g[0]])
            G = (Linv @ self.H[g[0]]).T  # (2, m)
            cw = z[:, :, g] @ Linv.T  # (n, T, |g|, m)
            self.white[int(g[0])] = (G, cw, logdet)
        self.Sinv_local = np.linalg.inv(self.local["S"])  # (T, N, m, m)

    # --- sensors
    def _feedback_decisions(self, k: int, x: np.ndarray):
        self._cloud_moments(x)
        nu = self.z[:, k] - np.einsum("nk,imk->nim", self.pred_mean, self.H)
        if self.feedback == "state+cov":
            S = np.einsum("imk,nkl,ijl->nimj", self.H, self.pred_cov, self.H) + self.R
            S = 0.5 * (S + np.swapaxes(S, -1, -2))
            nis = np.einsum("nim,nim->ni", nu, np.linalg.solve(S, nu[..., None])[..., 0])
        else:
            S = None
            nis = np.einsum("nim,imj,nij->ni", nu, self.Sinv_local[k], nu)
        self.sent[:, k] = nis >= self.eta
        return S

    # --- FilterModel (initial, transition, observe: see fusion.FeedbackModel)
    def log_weight(self, t: int, x: np.ndarray) -> np.ndarray:
        k = t - 1
        S = self._feedback_decisions(k, x) if self.fb else None
        sent = self.sent[:, k]
        n, P, _ = x.shape
        out = np.zeros((n, P))
        for g in self.groups:
            g0 = int(g[0])
            G, cw, logdet = self.white[g0]
            sg = sent[:, g]
            n_obs = sg.sum(axis=1).astype(float)
            if np.any(n_obs):
                # sum over the received of |Linv (z_i - H x)|^2 = n |w - cbar|^2 + sum |c_i -
                # cbar|^2 (w = Linv H x, c_i = Linv z_i): one pass over the particles
                c = np.where(sg[..., None], cw[:, k], 0.0)  # (n, |g|, m)
                cbar = c.sum(axis=1) / np.maximum(n_obs, 1.0)[:, None]
                ss = (np.where(sg[..., None], c - cbar[:, None, :], 0.0) ** 2).sum(axis=(1, 2))
                d = x @ G - cbar[:, None, :]
                out += (-0.5 * n_obs[:, None]) * (d * d).sum(axis=-1) \
                    - (0.5 * ss + 0.5 * n_obs * (self.m * _LOG_2PI + logdet))[:, None]
            silent = fusion.silent_rows(self, g, n_obs)
            if silent is None:
                continue
            n_sil, rows = silent
            dev = x[rows] - self.pred_mean[rows, None, :]
            if self.feedback == "state":
                A = self.local["A"][k, g0]
                a = math.sqrt(self.eta) * self.local["a_scale"][k, g0]
                b = dev @ A.T
            else:
                AL, asc = canonical_map(S[rows, g0], self.R[g0])
                A = AL @ self.H[g0]  # (r, m, 2)
                a = math.sqrt(self.eta) * asc  # (r, m)
                b = dev @ np.swapaxes(A, -1, -2)
            val = eval_silent(b, a, probability=self.probability, rng=self.rng_q, n_q=self.n_q)
            out[rows] += n_sil[rows, None] * val
        return out


def _truncated_std_normal(rng, lo, hi):
    """Draws of ``Z ~ N(0, 1)`` conditioned on ``lo < Z < hi``: the inverse cdf of
    :func:`fusioncenter.censoring.probability.truncated_normal` at uniforms drawn from ``rng``."""
    u = rng.random(np.broadcast_shapes(np.shape(lo), np.shape(hi)))
    return censored_normal.truncated_normal(u, lo, hi)


def sample_in_ellipse(rng, b, a, rounds: int = 16):
    """``u ~ N(b, I)`` conditioned on ``sum_j u_j^2 / a_j^2 < 1``; ``b (k, m)``, ``a (m,)``.

    Plain rejection for ``rounds`` rounds (acceptance = the silent probability, which the
    resampled particles make large: about 0.6 on average in the filter); then for what is left
    an exact sequential proposal: ``u_1`` from ``N(b_1, 1)`` truncated to ``(-a_1, a_1)``,
    ``u_2`` from ``N(b_2, 1)`` truncated to the chord at ``u_1``, accepted with probability
    ``Pin(b_2, chord(u_1)) / Pin(b_2, a_2)`` (the ratio of target to proposal, at most 1).
    After 200 such rounds a remaining draw keeps its last proposal (never seen in practice; the
    number is returned).

    Parameters
    ----------
    rng : numpy.random.Generator
        The stream of the draws.
    b : numpy.ndarray
        Means ``(k, m)`` in canonical coordinates.
    a : numpy.ndarray
        Semi-axes ``(m,)``.
    rounds : int, optional
        Rounds of plain rejection before the sequential proposal.

    Returns
    -------
    u : numpy.ndarray
        The draws ``(k, m)``.
    left : int
        How many draws kept an unaccepted proposal (0 in practice).
    """
    k, m = b.shape
    inv_a2 = 1.0 / (a * a)
    # the rounds of plain rejection, compiled (vector_terms.ellipse_reject): the same draws, in the
    # same order, as ``u = standard_normal((len(todo), m)) + b[todo]`` per round
    # (the normals: rng.standard_normal's, drawn by the compiled ziggurat: ziggurat)
    out = ziggurat.standard_normal(rng, (k, m))
    todo = np.arange(k)
    left = vector_terms.ellipse_reject(out, b, todo, inv_a2, out)
    for _ in range(rounds - 1):
        if left == 0:
            return out, 0
        left = vector_terms.ellipse_reject(ziggurat.standard_normal(rng, (left, m)), b,
                                           todo[:left], inv_a2, out)
    todo = todo[:left]
    if todo.size == 0:
        return out, 0
    if m == 1:
        bb = b[todo, 0]
        out[todo, 0] = bb + _truncated_std_normal(rng, -a[0] - bb, a[0] - bb)
        return out, 0
    for _ in range(200):
        b1, b2 = b[todo, 0], b[todo, 1]
        u1 = b1 + _truncated_std_normal(rng, -a[0] - b1, a[0] - b1)
        h = a[1] * np.sqrt(np.clip(1.0 - (u1 / a[0]) ** 2, 0.0, None))
        u2 = b2 + _truncated_std_normal(rng, -h - b2, h - b2)
        ratio = np.exp(censored_normal.log_prob_inside(b2, h)
                       - censored_normal.log_prob_inside(b2, np.full_like(b2, a[1])))
        ok = rng.random(todo.size) < ratio
        out[todo, 0], out[todo, 1] = u1, u2
        todo = todo[~ok]
        if todo.size == 0:
            break
    return out, int(todo.size)


class VectorExactFC(fusion.ExactModel):
    """CFwMD without feedback, exact: a particle is ``(x_t, xhat^1_{t|t-1}, ..., xhat^N_{t|t-1})``.

    Given a particle, a sensor's decision is a deterministic function of its measurement, so the
    weight is exact: ``N(z^i; H x, R) 1{nu^T S^{-1} nu >= eta}`` (``nu = z^i - H xhat^i``) for a
    received ``z^i``, and ``P(nu^T S^{-1} nu < eta)``, ``nu ~ N(H (x - xhat^j), R)``, for a silent
    sensor (the same generalized chi-square probability as with feedback). Before the next
    propagation each particle runs the sensors' Kalman updates with the received ``z^i`` or with
    a draw of the missing ``z^j`` from ``N(H x, R)`` conditioned on the silent ellipse (its exact
    conditional law). As in the scalar library, a step where no particle of a trial is compatible
    with who sent is relaxed (the indicators dropped) and counted.

    Parameters
    ----------
    sc : VectorScenario
        The scenario.
    eta : float
        Censoring threshold.
    z : numpy.ndarray
        Measurements ``(n, T, N, m)``.
    sent : numpy.ndarray
        Who sent ``(n, T, N)``, bool (the sensors' own decisions).
    probability, n_q, rng_q
        As in :class:`VectorFC`.
    """

    def __init__(self, sc: VectorScenario, eta: float, z: np.ndarray, sent: np.ndarray,
                 probability: str, n_q: int, rng_q):
        self.sc, self.eta, self.z, self.sent = sc, eta, z, sent
        self.probability, self.n_q, self.rng_q = probability, n_q, rng_q
        n, T, N, m = z.shape
        self.N, self.m = N, m
        self.relaxed = np.zeros((n, T), dtype=bool)
        self.unconverged = 0
        self.dim = 2 * (N + 1)
        self.H, self.R = sc.Hs, sc.Rs
        self.local = sc.local_filters()
        self.Sinv = np.linalg.inv(self.local["S"])
        self.white = [whitening(self.R[i]) for i in range(N)]
        # u -> nu: nu = A_L^{-1} u with A_L = V^T L^{-1} (per step and sensor)
        AL, _ = canonical_map(self.local["S"], np.broadcast_to(self.R, self.local["S"].shape))
        self.ALinv = np.linalg.inv(AL)

    def transition(self, rng, t, xa):
        out = np.empty_like(xa)
        if t > 1:  # the sensors' KF updates at step k = t - 1 (index t - 2), then predictions
            k = t - 2
            F = self.sc.F
            x = xa[..., :2]
            a = math.sqrt(self.eta) * self.local["a_scale"][k]
            for i in range(self.N):
                xh = xa[..., 2 + 2 * i:4 + 2 * i]
                nu = self.z[:, k, i][:, None, :] - xh @ self.H[i].T  # received: z - H xhat
                sil = np.flatnonzero(~self.sent[:, k, i])
                if sil.size:
                    b = (x[sil] - xh[sil]) @ self.local["A"][k, i].T  # (r, P, m)
                    u, left = sample_in_ellipse(rng, b.reshape(-1, self.m), a[i])
                    self.unconverged += left
                    nu[sil] = (u @ self.ALinv[k, i].T).reshape(b.shape)
                out[..., 2 + 2 * i:4 + 2 * i] = (xh + nu @ self.local["gain"][k, i].T) @ F.T
        else:
            out[..., 2:] = xa[..., 2:]
        out[..., :2] = self.sc.dynamics.transition(rng, t, np.ascontiguousarray(xa[..., :2]))
        return out

    def log_weight(self, t, xa):
        k = t - 1
        n, P, _ = xa.shape
        x = xa[..., :2]
        full = np.zeros((n, P))
        ok = np.ones((n, P), dtype=bool)
        a = math.sqrt(self.eta) * self.local["a_scale"][k]
        for i in range(self.N):
            xh = xa[..., 2 + 2 * i:4 + 2 * i]
            sent = self.sent[:, k, i]
            rows = np.flatnonzero(sent)
            if rows.size:
                Linv, logdet = self.white[i]
                zi = self.z[rows, k, i][:, None, :]
                d = (zi - x[rows] @ self.H[i].T) @ Linv.T
                full[rows] += -0.5 * ((d * d).sum(axis=-1) + self.m * _LOG_2PI + logdet)
                nu = zi - xh[rows] @ self.H[i].T
                ok[rows] &= np.einsum("npm,mj,npj->np", nu, self.Sinv[k, i], nu) >= self.eta
            sil = np.flatnonzero(~sent)
            if sil.size:
                b = (x[sil] - xh[sil]) @ self.local["A"][k, i].T
                full[sil] += eval_silent(b, a[i], probability=self.probability, rng=self.rng_q,
                                          n_q=self.n_q)
        return self._consistent(full, ok, k)
