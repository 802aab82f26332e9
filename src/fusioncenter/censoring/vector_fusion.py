"""The fusion-centre models of the vector scenario for :func:`fusioncenter.particle.run_filter`,
and its ``run`` (zheng2014 Section V; Figs. 4-6, Table II)."""

from __future__ import annotations

import math

import numpy as np

from fusioncenter import montecarlo, particle
from fusioncenter._compiled import censored_normal, transitions, vector_terms, ziggurat
from fusioncenter._validate import one_of as _one_of
from fusioncenter._validate import posint as _posint
from fusioncenter.censoring import fusion, results
from fusioncenter.censoring import probability as cprob
from fusioncenter.censoring.ellipse import (
    LIKELIHOODS,
    PROBABILITIES,
    canonical_map,
    eval_silent,
    log_silent_per_trial,
    log_silent_table,
)
from fusioncenter.censoring.vector import VectorScenario, local_decisions, whitening

_LOG_2PI = math.log(2.0 * math.pi)

class _VectorFC(fusion.FeedbackModel):
    """The FC's particle-filter model (a :class:`fusioncenter.particle.FilterModel`) for one
    block of trials and every scheme except the exact no-feedback filter. It also plays the
    sensors: with feedback their decisions at step ``t`` depend on the FC's broadcast."""

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


def _sample_in_ellipse(rng, b, a, rounds: int = 16):
    """``u ~ N(b, I)`` conditioned on ``sum_j u_j^2 / a_j^2 < 1``; ``b (k, m)``, ``a (m,)``.

    Plain rejection for ``rounds`` rounds (acceptance = the silent probability, which the
    resampled particles make large: about 0.6 on average in the filter); then for what is left
    an exact sequential proposal: ``u_1`` from ``N(b_1, 1)`` truncated to ``(-a_1, a_1)``,
    ``u_2`` from ``N(b_2, 1)`` truncated to the chord at ``u_1``, accepted with probability
    ``Pin(b_2, chord(u_1)) / Pin(b_2, a_2)`` (the ratio of target to proposal, at most 1).
    After 200 such rounds a remaining draw keeps its last proposal (never seen in practice; the
    number is returned).
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


class _VectorExactFC(fusion.ExactModel):
    """CFwMD without feedback, exact: a particle is ``(x_t, xhat^1_{t|t-1}, ..., xhat^N_{t|t-1})``.

    Given a particle, a sensor's decision is a deterministic function of its measurement, so the
    weight is exact: ``N(z^i; H x, R) 1{nu^T S^{-1} nu >= eta}`` (``nu = z^i - H xhat^i``) for a
    received ``z^i``, and ``P(nu^T S^{-1} nu < eta)``, ``nu ~ N(H (x - xhat^j), R)``, for a silent
    sensor (the same generalized chi-square probability as with feedback). Before the next
    propagation each particle runs the sensors' Kalman updates with the received ``z^i`` or with
    a draw of the missing ``z^j`` from ``N(H x, R)`` conditioned on the silent ellipse (its exact
    conditional law). As in the scalar library, a step where no particle of a trial is compatible
    with who sent is relaxed (the indicators dropped) and counted.
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
                    u, left = _sample_in_ellipse(rng, b.reshape(-1, self.m), a[i])
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

    def observe(self, t, mean, cov):
        pass


#: Particles per sub-block of the fused filter (whole trials): the ~60 array passes of a step
#: then run over arrays that stay in the core's cache.
_SUB_PARTICLES = 1 << 14


def _lin(M, c0, c1):
    """Rows of ``M (m, 2)`` applied to the components ``(c0, c1)``: a list of ``m`` arrays."""
    return [M[j, 0] * c0 + M[j, 1] * c1 for j in range(M.shape[0])]


class _FusedVector:
    """The FC's model of :func:`fusioncenter.particle.run_filter` for every scheme, with the
    silent factor from the interpolation tables (what :func:`run` uses by default).

    The same model as :class:`_VectorFC` / :class:`_VectorExactFC` with
    ``probability="table"`` -- it draws the same random numbers in the same order and the tests
    check that the two agree to rounding -- organized for speed: particles stored component by
    component (:func:`fusioncenter.particle.by_component`: position, velocity and, for the exact
    no-feedback filter, every sensor's local prediction), the weights computed over sub-blocks of
    whole trials of about 16k particles (every operation is row-wise, so a trial's result depends
    neither on the sub-blocks nor on the other trials), and additive per-trial constants of the
    log weights dropped.
    """

    def __init__(self, sc: VectorScenario, scheme: str, feedback: str, likelihood: str,
                 eta: float, l: float, z: np.ndarray, sel_u: np.ndarray):
        self.ref = _VectorFC(sc, scheme, feedback, eta, l, z, sel_u, "table", 1, None)
        self.sc, self.scheme, self.feedback, self.eta = sc, scheme, feedback, eta
        self.z = z
        n, T, N, m = z.shape
        self.n, self.T, self.N, self.m = n, T, N, m
        self.H, self.R = sc.Hs, sc.Rs
        self.local = sc.local_filters()
        self.sent = self.ref.sent
        self.fb = self.ref.fb
        self.exact = scheme == "cfwmd" and feedback == "none" and likelihood == "exact"
        self.silent_fb = scheme == "cfwmd" and self.fb
        self.analytic = sc.feedback_moments == "analytic"
        self.need_cov = self.ref.needs_cov
        self.relaxed = np.zeros((n, T), dtype=bool)
        self.unconverged = 0
        if self.exact:
            self.xref = _VectorExactFC(sc, eta, z, self.sent, "table", 1, None)
        self.sqeta = math.sqrt(eta)
        self.dim = 2 + 2 * N if self.exact else 2
        self.needs_cov = self.need_cov
        self.LQ = particle.psd_factor(sc.Q)  # the factor LinearGaussianDynamics draws with
        self.dt = float(sc.F[0, 1])

    # --- sensors with feedback (rows R, step k)
    def _decide(self, R: slice, k: int, p, v):
        ref = self.ref
        if not self.analytic:  # moments of the propagated cloud
            P = p.shape[1]
            mp, mv = p.mean(axis=1), v.mean(axis=1)
            ref.pred_mean[R, 0], ref.pred_mean[R, 1] = mp, mv
            if self.feedback == "state+cov":
                dp, dv = p - mp[:, None], v - mv[:, None]
                cpp, cpv, cvv = ((dp * dp).sum(1) / P, (dp * dv).sum(1) / P,
                                 (dv * dv).sum(1) / P)
                ref.pred_cov[R] = np.stack([np.stack([cpp, cpv], -1),
                                            np.stack([cpv, cvv], -1)], -2)
        pm = ref.pred_mean[R]
        nu = self.z[R, k] - np.einsum("nk,imk->nim", pm, self.H)
        if self.feedback == "state+cov":
            S = np.einsum("imk,nkl,ijl->nimj", self.H, ref.pred_cov[R], self.H) + self.R
            S = 0.5 * (S + np.swapaxes(S, -1, -2))
            nis = np.einsum("nim,nim->ni", nu, np.linalg.solve(S, nu[..., None])[..., 0])
        else:
            S = None
            nis = np.einsum("nim,imj,nij->ni", nu, ref.Sinv_local[k], nu)
        self.sent[R, k] = nis >= self.eta
        return S

    # --- log weights of rows R at step k (per-trial additive constants dropped)
    def _log_weight(self, R: slice, k: int, p, v, lp, lw) -> None:
        S = self._decide(R, k, p, v) if self.fb else None
        sent = self.sent[R, k]
        lw.fill(0.0)
        ref = self.ref
        if self.exact:
            self._log_weight_exact(R, k, p, v, lp, lw)
            return
        for g in ref.groups:
            g0 = int(g[0])
            G, cw, _ = ref.white[g0]
            sg = sent[:, g]
            n_obs = sg.sum(axis=1)
            if n_obs.any():
                c = np.where(sg[..., None], cw[R, k], 0.0)
                cbar = c.sum(axis=1) / np.maximum(n_obs, 1)[:, None]
                vector_terms.white_gauss_add(np.ascontiguousarray(G.T), p, v, cbar, -0.5 * n_obs,
                                         lw)
            if not self.silent_fb:
                continue
            n_sil = len(g) - n_obs
            rows = np.flatnonzero(n_sil)
            if rows.size == 0:
                continue
            every = rows.size == n_sil.size
            pm = ref.pred_mean[R][rows]
            dp = (p if every else p[rows]) - pm[:, 0, None]
            dv = (v if every else v[rows]) - pm[:, 1, None]
            if self.feedback == "state":
                b = _lin(self.local["A"][k, g0], dp, dv)
                val = log_silent_table(b, self.sqeta * self.local["a_scale"][k, g0])
            else:
                AL, asc = canonical_map(S[rows, g0], self.R[g0])
                A = AL @ self.H[g0]  # (r, m, 2)
                b = [A[:, j, 0, None] * dp + A[:, j, 1, None] * dv for j in range(self.m)]
                val = log_silent_per_trial(b, self.sqeta * asc)
            if np.any(n_sil[rows] != 1):
                val *= n_sil[rows, None]
            if every:
                lw += val
            else:
                lw[rows] += val

    def _log_weight_exact(self, R: slice, k: int, p, v, lp, lw) -> None:
        xr = self.xref
        sent = self.sent[R, k]
        ok = None
        a = self.sqeta * self.local["a_scale"][k]
        for i in range(self.N):
            h0, h1 = lp[i]
            rows = np.flatnonzero(sent[:, i])
            if rows.size:
                Linv, _ = xr.white[i]
                zi = self.z[R, k, i][rows]  # (r, m)
                if ok is None:
                    ok = np.ones(lw.shape, dtype=bool)
                # the whitened Gaussian term and the indicator "would have sent", one pass
                vector_terms.exact_received(Linv @ zi.T, Linv @ self.H[i], zi, self.H[i],
                                        xr.Sinv[k, i], self.eta, p, v, h0, h1, rows, lw, ok)
            sil = np.flatnonzero(~sent[:, i])
            if sil.size:
                every = sil.size == sent.shape[0]
                dp = (p if every else p[sil]) - (h0 if every else h0[sil])
                dv = (v if every else v[sil]) - (h1 if every else h1[sil])
                val = log_silent_table(_lin(self.local["A"][k, i], dp, dv), a[i])
                if every:
                    lw += val
                else:
                    lw[sil] += val
        if ok is not None:
            dead = ~ok.any(axis=1)
            keep = ok | dead[:, None]  # no compatible particle: relax the indicators
            lw[~keep] = -np.inf
            if dead.any():
                self.relaxed[np.arange(R.start, R.stop)[dead], k] = True

    # --- the exact filter's local Kalman updates at step k (whole block: it draws)
    def _local_update(self, rng, k: int, pos, vel, lp) -> None:
        xr = self.xref
        F = self.sc.F
        a = self.sqeta * self.local["a_scale"][k]
        nu = np.empty((self.m, *pos.shape))
        for i in range(self.N):  # compiled passes around the draws (vector_terms)
            h0, h1 = lp[i]
            vector_terms.local_innovations(self.z[:, k, i], self.H[i], h0, h1, nu)
            sil = np.flatnonzero(~self.sent[:, k, i])
            nus = np.empty((0, self.m))
            if sil.size:
                bs = np.empty((sil.size * pos.shape[1], self.m))
                vector_terms.silent_offsets(self.local["A"][k, i], pos, vel, h0, h1, sil, bs)
                u, left = _sample_in_ellipse(rng, bs, a[i])
                self.unconverged += left
                nus = u @ xr.ALinv[k, i].T
            vector_terms.local_update(self.local["gain"][k, i], F, nu, nus, sil, h0, h1)

    # --- FilterModel (fusioncenter.particle.run_filter on the whole block)
    def initial(self, rng: np.random.Generator, n: int, P: int) -> np.ndarray:
        """``(n, P, dim)``: ``x_0`` drawn from the prior, then (exact filter) every sensor's
        local prediction ``F x0``."""
        dyn = self.sc.dynamics
        x = particle.by_component(np.empty((n, P, self.dim)))
        x[..., :2] = dyn.initial(rng, n, P)
        if self.exact:
            start = self.sc.F @ dyn.m0
            x[..., 2::2] = start[0]
            x[..., 3::2] = start[1]
        return x

    def _local_views(self, x, R=slice(None)):
        return [(x[R, :, 2 + 2 * i], x[R, :, 3 + 2 * i]) for i in range(self.N)] \
            if self.exact else None

    def transition(self, rng: np.random.Generator, t: int, x: np.ndarray) -> np.ndarray:
        """The exact filter's local Kalman updates of step ``t - 1`` (they draw the missing
        measurements), then ``F x + L g`` for the target (in place)."""
        if self.exact and t > 1:
            self._local_update(rng, t - 2, x[..., 0], x[..., 1], self._local_views(x))
        kq = self.LQ.shape[1]
        zig = ziggurat.tables() if type(rng.bit_generator) is np.random.SFC64 else None
        if kq and zig is not None:  # NumPy's normals drawn inside the pass, in the same order
            st = ziggurat.draw_state(rng)
            transitions.propagate_wna_draw(x, self.dt, self.LQ, st, *zig)
            ziggurat.set_state(rng, st)
            return x
        g = rng.standard_normal((*x.shape[:2], kq)) if kq else np.empty((*x.shape[:2], 0))
        transitions.propagate_wna(x, self.dt, g, self.LQ)
        return x

    def log_weight(self, t: int, x: np.ndarray) -> np.ndarray:
        """Log weights ``(n, P)``, computed on sub-blocks of about 16k particles (whole trials;
        every operation is row-wise, so the sub-blocks do not change a trial's weights)."""
        n, P = x.shape[:2]
        lw = np.empty((n, P))
        sub = max(1, _SUB_PARTICLES // P)
        for s0 in range(0, n, sub):
            R = slice(s0, min(n, s0 + sub))
            self._log_weight(R, t - 1, x[R, :, 0], x[R, :, 1], self._local_views(x, R), lw[R])
        return lw

    def observe(self, t: int, mean: np.ndarray, cov: np.ndarray | None) -> None:
        """What is fed back at ``t + 1`` (``feedback_moments="analytic"``)."""
        if self.fb and self.analytic:
            self.ref.pred_mean[:, 0] = mean[:, 0] + self.dt * mean[:, 1]
            self.ref.pred_mean[:, 1] = mean[:, 1]
            if self.need_cov:
                F, Q = self.sc.F, self.sc.Q
                pc = F @ cov[:, :2, :2] @ F.T + Q
                self.ref.pred_cov = 0.5 * (pc + np.swapaxes(pc, -1, -2))


def _chunk(rng: np.random.Generator, n: int, *, scenario: VectorScenario, scheme: str,
           feedback: str, likelihood: str, eta: float, l: float, n_particles: int,
           ess_threshold: float, probability: str, n_q: int) -> np.ndarray:
    """``chunk_fn`` for :func:`fusioncenter.montecarlo.simulate`: ``(n, T, 5)`` per trial.

    Columns ``[squared error of position, of velocity | number of sensors that sent |
    ESS / n_particles | 1 if the weights collapsed]`` (the layout of
    :class:`fusioncenter.censoring.CensoringResult`). Streams spawned from ``rng``: the first
    draws the truth, the measurements and the random-selection uniforms (the same for every
    scheme: trials are paired), the second the filter's particles, resampling uniforms and the
    exact filter's imputations, the third the samples of ``probability="sampled"``.
    Every filter is a model of :func:`fusioncenter.particle.run_filter`: with
    ``probability="table"`` :class:`_FusedVector` (interpolation tables, sub-blocks), otherwise
    :class:`_VectorFC` / :class:`_VectorExactFC` (quadrature or sampled probabilities).
    """
    rng_data, rng_pf, rng_q = rng.spawn(3)
    # the filter's stream: SFC64 from the same spawned seed sequence (its normal draws, the
    # largest single cost of the filter, are ~15 % cheaper than PCG64's)
    rng_pf = np.random.Generator(np.random.SFC64(rng_pf.bit_generator.seed_seq))
    x, z = scenario.sample(rng_data, n)
    sel_u = rng_data.random(z.shape[:-1])
    if probability == "table":
        fused = _FusedVector(scenario, scheme, feedback, likelihood, eta, l, z, sel_u)
        out = particle.run_filter(fused, rng_pf, n, n_particles, scenario.T,
                                  ess_threshold=ess_threshold)
        return results.trial_columns(out, x, fused.sent, n_particles, fused.relaxed)
    fc = _VectorFC(scenario, scheme, feedback, eta, l, z, sel_u, probability, n_q, rng_q)
    model = fc
    if scheme == "cfwmd" and feedback == "none" and likelihood == "exact":
        model = _VectorExactFC(scenario, eta, z, fc.sent, probability, n_q, rng_q)
    out = particle.run_filter(model, rng_pf, n, n_particles, scenario.T,
                              ess_threshold=ess_threshold)
    return results.trial_columns(out, x, fc.sent, n_particles, getattr(model, "relaxed", None))


# ----------------------------------------------------------------------------- run
def run(scenario: VectorScenario, scheme: str, *, l, n_trials: int, n_particles: int, seed: int,
        feedback: str = "state", likelihood: str = "exact", ess_threshold: float = 1.0,
        chunk_size: int | None = None, executor=None, progress: bool = False,
        block_size: int = montecarlo.DEFAULT_BLOCK_SIZE, probability: str = "table",
        n_q: int = 100) -> results.CensoringResult:
    """Simulate ``n_trials`` trials of ``scenario`` and track them with the FC's particle filter.

    The same contract as :func:`fusioncenter.censoring.run` (and the same result type,
    :class:`fusioncenter.censoring.CensoringResult`, usable with
    :func:`fusioncenter.censoring.paired_difference`): ``scheme`` in :data:`SCHEMES`,
    ``feedback`` in :data:`FEEDBACK` (``"state+cov"`` is the paper's CFwMD2), ``l`` the target
    average number of sending sensors, ``eta = threshold(l, N, dof=m)``. ``likelihood`` selects
    how ``scheme="cfwmd"`` fuses without feedback: ``"exact"`` (default: particles of dimension
    ``2 (N + 1)`` carry the local predictions) or Proposition 6 ``"printed"`` (which equals
    CFoMD; ``"corrected"`` of the scalar library -- the received sensors' conditions kept under
    the law (21) -- is a ``2 N m``-dimensional integral per particle and raises ``ValueError``
    for ``scheme="cfwmd"`` without feedback; like every value it is ignored by the other scheme
    and feedback combinations, so the scalar library's default can be passed through).
    ``probability`` (``"table"``, ``"quadrature"``, ``"sampled"`` with ``n_q`` draws per particle)
    selects how the silent factor is evaluated (see :data:`PROBABILITIES`).

    Runs through :func:`fusioncenter.montecarlo.simulate`: results are bitwise identical for any
    ``chunk_size`` and executor; trials are paired across schemes for the same ``seed``,
    ``n_trials`` and ``block_size``.

    Parameters
    ----------
    scenario : VectorScenario
        The model.
    scheme, l, n_trials, n_particles, seed, feedback, ess_threshold : optional
        As in :func:`fusioncenter.censoring.run`.
    chunk_size, executor, progress, block_size : optional
        As there (execution only).
    likelihood : str, optional
        ``"exact"`` or ``"printed"`` (see above).
    probability : str, optional
        One of :data:`PROBABILITIES`.
    n_q : int, optional
        Draws per particle for ``probability="sampled"``.

    Returns
    -------
    CensoringResult
        As :func:`fusioncenter.censoring.run` returns.
    """
    if not isinstance(scenario, VectorScenario):
        raise ValueError("scenario must be a VectorScenario")
    results.check_scheme(scheme, feedback)
    if likelihood not in (*LIKELIHOODS, "corrected"):
        raise ValueError(f"likelihood must be one of {LIKELIHOODS}, got {likelihood!r}")
    if likelihood == "corrected" and scheme == "cfwmd" and feedback == "none":
        raise ValueError("likelihood='corrected' is not implemented for vector observations (it "
                         "is an integral over every sensor's local prediction per particle): "
                         f"use one of {LIKELIHOODS}")
    _one_of("probability", probability, PROBABILITIES)
    n_q = _posint("n_q", n_q)
    eta = cprob.threshold(l, scenario.N, dof=scenario.m)
    n_particles = _posint("n_particles", n_particles)
    results.check_resampling(scenario, ess_threshold)
    return results.run_chunks(_chunk, scenario, scheme, feedback, likelihood, l=l, eta=eta,
                          n_particles=n_particles, ess_threshold=ess_threshold,
                          n_trials=n_trials, seed=seed, chunk_size=chunk_size, executor=executor,
                          progress=progress, block_size=block_size,
                          chunk_kwargs={"likelihood": likelihood, "probability": probability,
                                        "n_q": n_q})
