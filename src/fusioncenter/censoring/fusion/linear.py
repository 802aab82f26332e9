"""The fusion centre of the linear scenario for :func:`fusioncenter.particle.run_filter`:
:class:`LinearFusionCentre` (every scheme except the exact no-feedback filter, which is
:class:`~fusioncenter.censoring.fusion.exact.ExactFusionCentre`), organized for speed, and the
sub-blocks of trials it runs on (:func:`sub_blocks`)."""

from __future__ import annotations

import math

import numpy as np

from fusioncenter import particle
from fusioncenter._compiled import censoring_decisions, log_table, transitions, ziggurat
from fusioncenter._compiled.bivariate_normal import log_region_probability, log_silent_constant
from fusioncenter._compiled.censored_normal import log_prob_inside
from fusioncenter.censoring.fusion.base import (
    FusionCentreModel,
    decisions_in_advance,
    silent_rows,
)
from fusioncenter.censoring.likelihood import no_feedback_region
from fusioncenter.censoring.scenarios import LinearScenario
from fusioncenter.censoring.tables import interp_rows, region_table, silent_table

#: Trials per sub-block of :class:`LinearFusionCentre`: about 32k particles, so that a sub-block's
#: arrays stay in the core's cache while the ~40 array passes of a step run over them.
_SUB_PARTICLES = 1 << 15


def _local_decisions(sc: LinearScenario, eta: float, z: np.ndarray) -> np.ndarray:
    """No feedback: every sensor runs its own KF; ``sent (n, T, N)`` from its innovations."""
    loc = sc.local_filters()
    F, H = sc.F, sc.H
    n, T, N = z.shape
    sent = np.empty((n, T, N), dtype=bool)
    xhat = np.broadcast_to(F @ sc.dynamics.m0, (n, N, 2)).copy()
    for t in range(T):
        nu = z[:, t] - np.einsum("nik,ik->ni", xhat, H)
        sent[:, t] = nu * nu >= eta * loc["s"][t]
        xhat = (xhat + loc["gain"][t] * nu[..., None]) @ F.T
    return sent


def sub_blocks(n: int, P: int) -> list[slice]:
    """The sub-blocks of a block of ``n`` trials with ``P`` particles: about
    :data:`_SUB_PARTICLES` particles each (whole trials). The filter's random numbers are drawn
    sub-block by sub-block, so this partition is part of what fixes them (with the seed,
    ``n_trials``, ``block_size`` and ``n_particles``).

    Parameters
    ----------
    n : int
        Trials of the block.
    P : int
        Particles per trial.

    Returns
    -------
    list of slice
        Consecutive row ranges covering ``0..n``.
    """
    sub = max(1, _SUB_PARTICLES // P)
    return [slice(s0, min(n, s0 + sub)) for s0 in range(0, n, sub)]


class LinearFusionCentre(FusionCentreModel):
    """The FC of a :class:`LinearScenario` as a model of :func:`fusioncenter.particle.run_filter`
    (every scheme except the exact no-feedback filter, :class:`ExactFusionCentre`).

    A model for one block of trials (``z (n, T, N)``): it also plays the sensors, because with
    feedback their decisions at step ``t`` depend on what the FC broadcast after step ``t - 1``.
    Particles ``(n, P, 2)`` (position, velocity). Organized for speed:

    * the transition is one compiled pass
      (:func:`fusioncenter._compiled.transitions.propagate_wna_draw`) that draws NumPy's normals
      itself (SFC64 and NumPy's ziggurat, the same numbers in the
      same order as ``standard_normal``; :mod:`fusioncenter._compiled.ziggurat`), or, where NumPy's
      tables cannot be read, :func:`fusioncenter._compiled.transitions.propagate_wna` after
      ``standard_normal``;
    * the silent factor with state feedback is the interpolation table :func:`silent_table`
      (its ``h`` is the same for every trial at a step), evaluated by a compiled kernel, as is the
      corrected Proposition 3 with one sensor received (:func:`region_table`) and, per trial,
      with both received (:func:`interp_rows`); CFwMD2's factor (``h`` differs per trial) uses
      two ``ndtr`` per particle, in one compiled pass
      (:func:`fusioncenter._compiled.normal_cdf.inside_difference`);
    * additive constants of a trial's log weights are dropped, and the covariance is computed
      (by the loop) only when CFwMD2 feeds it back.

    :func:`run` gives the loop sub-blocks of about 32k particles (whole trials,
    :func:`sub_blocks`), one model each, so that the ~40 array passes of a step work on data
    in the core's cache.

    Parameters
    ----------
    sc : LinearScenario
        The model.
    scheme, feedback, likelihood : str
        As in :func:`run`.
    eta : float
        Censoring threshold.
    l : float
        Average number of sending sensors (random selection sends with probability ``l / N``).
    z : numpy.ndarray
        Measurements ``(n, T, N)``.
    sel_u : numpy.ndarray
        Random-selection uniforms ``(n, T, N)``.
    """

    dim = 2

    def __init__(self, sc: LinearScenario, scheme: str, feedback: str, likelihood: str,
                 eta: float, l: float, z: np.ndarray, sel_u: np.ndarray):
        self.sc, self.scheme, self.feedback, self.likelihood = sc, scheme, feedback, likelihood
        self.eta = eta
        self.z = z
        n, T, N = z.shape
        self.n, self.T, self.N = n, T, N
        self.H, self.r = sc.H, sc.rvec
        self.groups = sc.sensor_groups()
        self.local = sc.local_filters()
        dyn = sc.dynamics
        self.dt = float(dyn.F[0, 1])
        self.LQ = particle.psd_factor(dyn.Q)
        self.censor = scheme in ("cfomd", "cfwmd")
        self.fb = self.censor and feedback != "none"
        self.analytic = sc.feedback_moments == "analytic"
        self.need_cov = self.fb and feedback == "state+cov" and self.analytic
        self.pred_mean = np.broadcast_to(dyn.F @ dyn.m0, (n, 2)).copy()
        self.pred_cov = np.broadcast_to(dyn.F @ dyn.P0 @ dyn.F.T + dyn.Q, (n, 2, 2)).copy()
        self.sent = decisions_in_advance(scheme, feedback, l, sel_u, (n, T, N),
                                         lambda: _local_decisions(sc, eta, z))
        self.nf_region = scheme == "cfwmd" and feedback == "none"
        self.needs_cov = self.need_cov
        self.uses_silence = scheme == "cfwmd" and self.fb  # silent_rows' condition
        self._tmp = np.empty((n, 0))
        self._g = np.empty((n, 0, 0))
        self._zbar, self._gcoef = np.empty(n), np.empty(n)  # per group (group_stats)
        self._nsil = np.empty(n, dtype=np.int64)

    # --- the sensors' decisions at step k = t - 1 (feedback)
    def _decide(self, k: int, pos, vel) -> np.ndarray | None:
        if not self.analytic:  # moments of the propagated cloud
            P = pos.shape[1]
            mp, mv = pos.mean(axis=1), vel.mean(axis=1)
            self.pred_mean[:, 0], self.pred_mean[:, 1] = mp, mv
            if self.feedback == "state+cov":
                dp, dv = pos - mp[:, None], vel - mv[:, None]
                cpp, cpv, cvv = ((dp * dp).sum(1) / P, (dp * dv).sum(1) / P,
                                 (dv * dv).sum(1) / P)
                self.pred_cov = np.stack([np.stack([cpp, cpv], -1),
                                             np.stack([cpv, cvv], -1)], -2)
        if self.feedback == "state+cov":
            s = np.einsum("ik,nkl,il->ni", self.H, self.pred_cov, self.H) + self.r
        else:
            s = self.local["s"][k]
        # nu * nu >= eta * s, nu = z - hx, in one compiled pass (the same floats)
        censoring_decisions.censor_decisions(self.z, k, self.pred_mean @ self.H.T,
                                             s if s.ndim == 2 else s[None, :], self.eta,
                                             self.sent)
        return s

    # --- log weights at step k (additive per-row constants dropped)
    def _log_weight(self, k: int, pos, vel, lw, tmp) -> None:
        s = self._decide(k, pos, vel) if self.fb else None
        sent, z = self.sent[:, k], self.z[:, k]
        ys = {}
        started = False  # lw holds a value (the first term is written, not added)
        for g in self.groups:
            hg, rg = self.H[g[0]], float(self.r[g[0]])
            if hg[0] == 1.0 and hg[1] == 0.0:
                y = pos
            else:
                y = hg[0] * pos + hg[1] * vel
            ys[int(g[0])] = y
            # the sum over the received sensors of log N(z_i; y, r) is -n (y - zbar)^2 / (2 r)
            # plus a constant per trial (centred: no cancellation however large the
            # positions); gauss = (zbar, -n / (2 r), add): written or added in one compiled pass
            if g.size <= censoring_decisions.GROUP_SUM_MAX:  # zbar, n, silent count: one call
                n_any, n_silent = censoring_decisions.group_stats(
                    self.sent, self.z, k, g, -0.5 / rg, self._zbar, self._gcoef, self._nsil)
                gauss = (self._zbar, self._gcoef, started) if n_any else None
                silent = (self._nsil, None) if n_silent and self.uses_silence else None
            else:  # NumPy's pairwise sum of 8 or more sensors
                sg = sent[:, g]
                n_obs = sg.sum(axis=1)
                gauss = None
                if n_obs.any():
                    zbar = np.where(sg, z[:, g], 0.0).sum(axis=1) / np.maximum(n_obs, 1)
                    gauss = (zbar, -0.5 / rg * n_obs, started)
                silent = silent_rows(self, g, n_obs)
                n_silent = 0 if silent is None else silent[1].size
            # most trials have a silent sensor: evaluate every row (no fancy indexing) and
            # zero the others, unless few rows need it
            every = silent is not None and 2 * n_silent >= silent[0].size
            if silent is not None and not every and silent[1] is None:
                silent = (silent[0], np.flatnonzero(silent[0]))
            fused = every and self.feedback != "state+cov" and gauss is not None
            if gauss is not None and not fused:
                log_table.gauss_terms(y, gauss[0], gauss[1], lw, gauss[2])
                started = True
            if silent is None:
                continue
            n_sil, rows = silent
            sd = math.sqrt(rg)
            hp = self.pred_mean @ hg
            if fused:  # one compiled call: the Gaussian terms, the table, the product, the sum
                silent_table(math.sqrt(self.eta * s[g[0]]) / sd).shifted_add(
                    y, hp, 1.0 / sd, n_sil, lw, tmp, gauss)
                started = True
                continue
            if self.feedback == "state+cov":  # h differs per trial
                mu = np.subtract(y, hp[:, None], out=tmp) if every else y[rows] - hp[rows, None]
                mu *= 1.0 / sd
                hh = np.sqrt(self.eta * s[rows if not every else slice(None), g[0]]) / sd
                with np.errstate(invalid="ignore"):
                    val = log_prob_inside(mu, hh[:, None])
            elif every:  # one compiled pass: the table, the product by ns and the sum
                if not started:
                    lw.fill(0.0)
                    started = True
                silent_table(math.sqrt(self.eta * s[g[0]]) / sd).shifted_add(
                    y, hp, 1.0 / sd, n_sil, lw, tmp)
                continue
            else:  # the same arithmetic on the rows that need it
                table = silent_table(math.sqrt(self.eta * s[g[0]]) / sd)
                val = table.shifted(y[rows], hp[rows], 1.0 / sd, tmp[:rows.size])
            ns = n_sil if every else n_sil[rows]
            if every and not ns.all():
                val[ns == 0] = 0.0
            if np.any(ns > 1):
                val *= ns[:, None]
            if not started:
                lw.fill(0.0)
                started = True
            if every:
                lw += val
            else:
                lw[rows] += val
        if not started:
            lw.fill(0.0)
        if self.nf_region:
            self._region_term(k, sent, z, ys, lw)

    def _region_term(self, k, sent, z, ys, lw) -> None:
        """Proposition 3 (printed or corrected) for rows of a sub-block, pattern by pattern."""
        C, r, eta, N = self.local["C"][k], self.r, self.eta, self.N
        gid = {int(i): int(g[0]) for g in self.groups for i in g}
        if self.likelihood == "printed":  # a constant per trial: cheap through the generic code
            lw += no_feedback_region(sent, z, np.zeros((sent.shape[0], 1, N)), C, r, eta,
                                      "printed")
            return
        s_ = np.diag(C) + r
        a = np.sqrt(eta * s_)
        for pat in np.unique(sent, axis=0):
            rows = np.flatnonzero(np.all(sent == pat, axis=-1))
            cov = C + np.diag(np.where(pat, 0.0, r))
            recv = np.flatnonzero(pat)
            if recv.size == 0:
                lw[rows] += log_silent_constant(cov, a)
            elif N == 2 and abs(cov[0, 1]) >= (1 - 1e-9) * math.sqrt(cov[0, 0] * cov[1, 1]):
                # degenerate law (k = 1 with x_0 known: identical local predictions): the
                # region probability has kinks, which the tables would smooth; exact
                hx = np.stack([ys[gid[i]][rows] for i in range(N)], axis=-1)
                mean = np.where(pat, z[rows][:, None, :] - hx, 0.0)
                lw[rows] += log_region_probability(mean, cov, a, pat)
            elif recv.size == 1:
                i = int(recv[0])
                tab = region_table(tuple(a.tolist()), tuple(map(tuple, cov.tolist())),
                                    tuple(bool(p) for p in pat), i)
                c = z[rows, i][:, None] - ys[gid[i]][rows]
                lw[rows] += tab(c)
            elif len(self.groups) == 1 or np.all(self.H == self.H[0]):
                # both received, one projection y = h^T x: per trial a function of
                # c_0 = z_0 - y (c_1 = c_0 + z_1 - z_0), interpolated from exact values
                d = z[rows, 1] - z[rows, 0]

                def fn(b, c0, d=d, cov=cov, pat=pat):
                    return log_region_probability(np.stack([c0, c0 + d[b]], axis=-1), cov, a, pat)

                lw[rows] += interp_rows(fn, z[rows, 0][:, None] - ys[gid[0]][rows])
            else:
                hx = np.stack([ys[gid[i]][rows] for i in range(N)], axis=-1)
                mean = np.where(pat, z[rows][:, None, :] - hx, 0.0)
                lw[rows] += log_region_probability(mean, cov, a, pat)

    # --- FilterModel
    def initial(self, rng: np.random.Generator, n: int, P: int) -> np.ndarray:
        # draws of x_0 (LinearGaussianDynamics.initial), stored component by component
        return particle.by_component(self.sc.dynamics.initial(rng, n, P))

    def transition(self, rng: np.random.Generator, t: int, x: np.ndarray) -> np.ndarray:
        # A1.3 in place: x <- F x + L g with g standard normal (n, P, rank Q)
        # (rng.standard_normal's numbers, drawn inside the pass for an SFC64 rng)
        shape = (*x.shape[:2], self.LQ.shape[1])
        zig = ziggurat.tables() if type(rng.bit_generator) is np.random.SFC64 else None
        if shape[2] and zig is not None:  # NumPy's normals drawn inside the pass, same order
            st = ziggurat.draw_state(rng)
            transitions.propagate_wna_draw(x, self.dt, self.LQ, st, *zig)
            ziggurat.set_state(rng, st)
            return x
        if self._g.shape != shape:
            self._g = np.empty(shape)
        if shape[2]:
            rng.standard_normal(out=self._g)
        transitions.propagate_wna(x, self.dt, self._g, self.LQ)
        return x

    def log_weight(self, t: int, x: np.ndarray) -> np.ndarray:
        # A1.4, per-trial constants dropped; with feedback the sensors decide first. The log
        # weights are written to a buffer the model reuses at every step.
        if self._tmp.shape != x.shape[:2]:
            self._tmp = np.empty(x.shape[:2])
            self._lw = np.empty(x.shape[:2])
        lw = self._lw  # the loop normalizes it in place; rewritten at every step
        self._log_weight(t - 1, x[..., 0], x[..., 1], lw, self._tmp)
        return lw

    def observe(self, t: int, mean: np.ndarray, cov: np.ndarray | None) -> None:
        # what is fed back at t + 1 (feedback_moments="analytic"): F mean and F cov F^T + Q
        if self.analytic:
            self.pred_mean[:, 0] = mean[:, 0] + self.dt * mean[:, 1]
            self.pred_mean[:, 1] = mean[:, 1]
            if self.need_cov:
                F, Q = self.sc.F, self.sc.Q
                pc = F @ cov @ F.T + Q
                self.pred_cov = 0.5 * (pc + np.swapaxes(pc, -1, -2))
