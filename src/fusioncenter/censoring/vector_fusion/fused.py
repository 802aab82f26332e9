"""The vector scenario's fusion centre organized for speed (:class:`FusedVectorFC`): the model
of the reference :mod:`~fusioncenter.censoring.vector_fusion.reference` with the silent factor
from the interpolation tables of :mod:`fusioncenter.censoring.ellipse`, the particles stored
component by component and the weights computed on sub-blocks of trials (what
:func:`~fusioncenter.censoring.vector_fusion.run` uses by default)."""

from __future__ import annotations

import math

import numpy as np

from fusioncenter import particle
from fusioncenter._compiled import transitions, vector_terms, ziggurat
from fusioncenter.censoring import fusion
from fusioncenter.censoring.ellipse import canonical_map, log_silent_per_trial, log_silent_table
from fusioncenter.censoring.vector import VectorScenario
from fusioncenter.censoring.vector_fusion.reference import (
    VectorExactFC,
    VectorFC,
    sample_in_ellipse,
)

#: Particles per sub-block of the fused filter (whole trials): the ~60 array passes of a step
#: then run over arrays that stay in the core's cache.
_SUB_PARTICLES = 1 << 14


def _lin(M, c0, c1):
    """Rows of ``M (m, 2)`` applied to the components ``(c0, c1)``: a list of ``m`` arrays."""
    return [M[j, 0] * c0 + M[j, 1] * c1 for j in range(M.shape[0])]


class FusedVectorFC(fusion.FusionCentreModel):
    """The FC's model of :func:`fusioncenter.particle.run_filter` for every scheme, with the
    silent factor from the interpolation tables (what :func:`run` uses by default).

    The same model as :class:`~fusioncenter.censoring.vector_fusion.reference.VectorFC` /
    :class:`~fusioncenter.censoring.vector_fusion.reference.VectorExactFC` with
    ``probability="table"`` -- it draws the same random numbers in the same order and the tests
    check that the two agree to rounding -- organized for speed: particles stored component by
    component (:func:`fusioncenter.particle.by_component`: position, velocity and, for the exact
    no-feedback filter, every sensor's local prediction), the weights computed over sub-blocks of
    whole trials of about 16k particles (every operation is row-wise, so a trial's result depends
    neither on the sub-blocks nor on the other trials), and additive per-trial constants of the
    log weights dropped.

    Parameters
    ----------
    sc, scheme, feedback, eta, l, z, sel_u
        As in :class:`~fusioncenter.censoring.vector_fusion.reference.VectorFC`.
    likelihood : str
        As in :func:`~fusioncenter.censoring.vector_fusion.run` (``"exact"``: the exact
        no-feedback filter's particles).
    """

    def __init__(self, sc: VectorScenario, scheme: str, feedback: str, likelihood: str,
                 eta: float, l: float, z: np.ndarray, sel_u: np.ndarray):
        self.ref = VectorFC(sc, scheme, feedback, eta, l, z, sel_u, "table", 1, None)
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
            self.xref = VectorExactFC(sc, eta, z, self.sent, "table", 1, None)
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
                u, left = sample_in_ellipse(rng, bs, a[i])
                self.unconverged += left
                nus = u @ xr.ALinv[k, i].T
            vector_terms.local_update(self.local["gain"][k, i], F, nu, nus, sil, h0, h1)

    # --- FilterModel (fusioncenter.particle.run_filter on the whole block)
    def initial(self, rng: np.random.Generator, n: int, P: int) -> np.ndarray:
        # x_0 drawn from the prior, then (exact filter) every sensor's local prediction F x0,
        # stored component by component
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
        # the exact filter's local Kalman updates of step t - 1 (they draw the missing
        # measurements), then F x + L g for the target (in place)
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
        # computed on sub-blocks of about 16k particles (whole trials; every operation is
        # row-wise, so the sub-blocks do not change a trial's weights)
        n, P = x.shape[:2]
        lw = np.empty((n, P))
        sub = max(1, _SUB_PARTICLES // P)
        for s0 in range(0, n, sub):
            R = slice(s0, min(n, s0 + sub))
            self._log_weight(R, t - 1, x[R, :, 0], x[R, :, 1], self._local_views(x, R), lw[R])
        return lw

    def observe(self, t: int, mean: np.ndarray, cov: np.ndarray | None) -> None:
        # what is fed back at t + 1 (feedback_moments="analytic"): F mean and F cov F^T + Q of
        # the target's components
        if self.fb and self.analytic:
            self.ref.pred_mean[:, 0] = mean[:, 0] + self.dt * mean[:, 1]
            self.ref.pred_mean[:, 1] = mean[:, 1]
            if self.need_cov:
                F, Q = self.sc.F, self.sc.Q
                pc = F @ cov[:, :2, :2] @ F.T + Q
                self.ref.pred_cov = 0.5 * (pc + np.swapaxes(pc, -1, -2))
