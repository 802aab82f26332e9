"""Censoring and fusion with missing data for a nonlinear tracker (zheng2014 Sections VI, VII.C).

A source moves in the plane with the white-noise-acceleration model, ``x = [x, xdot, y, ydot]``
(eq. (41) with a linear ``f``), and ``N = 9`` sensors on a 3 x 3 grid measure the amplitude of
its signal (Section VII.C)

    z_k^i = sqrt(P_0 / (1 + alpha d_k^i ** n)) + n_k^i,   n_k^i ~ N(0, r_i)      (42)

(``d_k^i`` the distance from the source to sensor ``i``). Each sensor runs an extended Kalman
filter (EKF) and sends ``z_k^i`` only if its normalized innovation squared is large,
``(z_k^i - h^i(xhat_{k|k-1}))^2 / s_k^i >= eta``, ``eta = chi2_1(l / N)`` (eq. (43)). The fusion
centre (FC) runs a particle filter and broadcasts after every step

* ``feedback="state"`` (Proposition 7, "CFwMD"): its estimate ``xhat_{k-1|k-1}``; every sensor
  predicts ``xhat_{k|k-1} = F xhat_{k-1|k-1}``, linearizes ``h^i`` there (``g_k^i``) and
  normalizes by its own EKF covariance, ``s_k^i = g_k^i P^i_{k|k-1} g_k^iT + r_i``;
* ``feedback="state+cov"`` (Proposition 8, "CFwMD2"): also ``Phat_{k-1|k-1}``; the sensors use
  ``s'^i_k = g_k^i (F Phat_{k-1|k-1} F^T + Q) g_k^iT + r_i``;
* ``feedback="none"``: nothing; each sensor runs a complete EKF on its own measurements. The
  paper gives no full likelihood for this case (Remark 4 (III)), so only all-send, random
  selection and CFoMD accept it.

Given the broadcast the FC knows every ``s_k^i`` (it replays the sensors' EKF covariance
recursions, Remark 3 (I)), and the likelihood of Propositions 7-8 is *exact*: a silent sensor
contributes ``P(|h^i(x_k) + n - h^i(xhat_{k|k-1})| < sqrt(eta s_k^i))``, a Gaussian interval
probability in the particle's own amplitude. The Gaussian approximation of the innovation
enters only the threshold design, i.e. how many sensors send on average (Table III).

For ``10^4`` particles the silent factors dominate the cost. Within one trial and sensor they are
a smooth function of one variable (log-concave, curvature in ``[-1, 0]``), so the FC tabulates
them with exact values and slopes and interpolates (cubic Hermite, error below ``1e-9`` in the
log weights, :func:`silent_terms`); for CFoMD and random selection it computes the amplitudes of the
received sensors only.

Entry points (signature, one line each):

* ``NonlinearScenario(...)``: the model of Section VII.C; ``.choices`` states every open choice.
* ``amplitude(scenario, pos) -> (..., N)``, ``jacobian(scenario, x) -> (..., N, 4)``: ``h`` and
  its gradient ``g`` (zero in the velocity components).
* ``ekf_covariance_step(P, g, F, Q, r) -> (P_pred, s, P_upd)``: one EKF covariance recursion,
  vectorized over any leading axes (trials, sensors).
* ``local_ekf(scenario, z) -> dict``: every sensor's own EKF on its own data (no feedback).
* ``log_silent_probability(m, h)``: ``log P(|Z + m| < h)``, ``Z ~ N(0, 1)``, for the particles.
* ``log_likelihood(sent, z, hx, hx_pred, s, r, eta, scheme="cfwmd")``: Propositions 7-8 (or
  the received sensors only, CFoMD) for given amplitudes.
* ``run(scenario, scheme, *, l, n_trials, n_particles, seed, feedback="state", ...)
  -> censoring.CensoringResult``: the four schemes, through ``montecarlo.simulate``; the same
  signature and result type as :func:`fusioncenter.censoring.run`."""

from __future__ import annotations

import math

import numpy as np

from fusioncenter import _validate as _v
from fusioncenter import montecarlo, particle
from fusioncenter._compiled import amplitude_ekf, amplitude_terms, censored_normal
from fusioncenter._validate import one_of as _one_of
from fusioncenter._validate import posint as _posint
from fusioncenter.censoring import fusion, results, scenarios
from fusioncenter.censoring import probability as cprob
from fusioncenter.censoring.likelihood import check_feedback_arguments
from fusioncenter.censoring.nonlinear_model import (
    NonlinearScenario,
    amplitude,  # noqa: F401 (re-exported)
    ekf_covariance_step,  # noqa: F401 (re-exported)
    grid_positions,  # noqa: F401 (re-exported)
    jacobian,  # noqa: F401 (re-exported)
    local_ekf,
)

#: The schemes of :func:`run` (as in :mod:`fusioncenter.censoring`).
SCHEMES = scenarios.SCHEMES
#: What the FC broadcasts: its estimate (Proposition 7), estimate and covariance (Proposition 8,
#: CFwMD2), or nothing (no likelihood for CFwMD: Remark 4 (III)).
FEEDBACK = ("state", "state+cov", "none")


# ----------------------------------------------------------------------------- likelihood
def log_silent_probability(m, h):
    """``log P(|Z + m| < h)`` for ``Z ~ N(0, 1)``, ``h >= 0``: a silent sensor's factor.

    The one implementation of the package,
    :func:`fusioncenter.censoring.probability.log_prob_inside` (two ``ndtr`` calls, the careful
    branch deep in the tails and for tiny ``h``).

    Parameters
    ----------
    m, h : array_like
        The interval's offset and half-width, in units of the noise standard deviation
        (broadcast).

    Returns
    -------
    numpy.ndarray
        ``log P(|Z + m| < h)``, finite for any finite ``m`` and ``h > 0``; ``-inf`` for
        ``h = 0`` (an empty interval), ``0`` for ``h = +inf``.

    Raises
    ------
    ValueError
        If ``m`` is not finite, ``h`` is NaN or negative (a half-width), or the shapes do not
        broadcast.
    """
    return cprob.log_prob_inside(m, h)


def log_likelihood(sent, z, hx, hx_pred, s, r, eta, scheme: str = "cfwmd"):
    """Propositions 7 and 8: ``log p(z_obs, m | x, broadcast)`` up to a constant.

    ``sum_{received} log N(z^i; h^i(x), r_i) + sum_{silent} log P(|nu^i| < sqrt(eta s_i))``,
    ``nu^i ~ N(h^i(x) - h^i(xhat_{k|k-1}), r_i)``; ``scheme="cfomd"`` keeps the first sum only.
    Shapes broadcast: ``sent``, ``z``, ``hx`` (the amplitudes ``h^i(x)``), ``hx_pred``
    (``h^i(xhat_{k|k-1})``), ``s`` (``s_k^i`` for Proposition 7, ``s'^i_k`` for 8): ``(..., N)``;
    ``r (N,)``. Returns ``(...)``. The normalizing constants ``-log(2 pi r_i)/2`` are kept.

    Parameters
    ----------
    sent, z, hx, hx_pred, s : array_like
        As above, ``(..., N)``.
    r : array_like
        Noise variances ``(N,)``, ``> 0``.
    eta : float
        Threshold.
    scheme : str, optional
        ``"cfwmd"`` or ``"cfomd"``.

    Returns
    -------
    numpy.ndarray
        ``log p(z_obs, m | x, broadcast)`` ``(...)`` (the received sensors' terms only for
        ``"cfomd"``).

    Raises
    ------
    ValueError
        For an unknown ``scheme``, or from
        :func:`~fusioncenter.censoring.likelihood.check_feedback_arguments`.
    """
    if scheme not in ("cfwmd", "cfomd"):
        raise ValueError(f"scheme must be 'cfwmd' or 'cfomd', got {scheme!r}")
    sent, z, hx, hx_pred, s, r, eta = check_feedback_arguments(sent, z, hx, hx_pred, s, r, eta)
    recv = np.where(sent, -0.5 * np.log(2 * np.pi * r) - 0.5 * (np.where(sent, z, 0.0) - hx)
                    ** 2 / r, 0.0)
    out = recv.sum(axis=-1)
    if scheme == "cfwmd":
        sd = np.sqrt(r)
        sil = censored_normal.log_prob_inside((hx - hx_pred) / sd, np.sqrt(eta * s) / sd)
        out = out + np.where(sent, 0.0, sil).sum(axis=-1)
    return out


#: Node spacing of the tabulated silent-sensor term (units of the noise standard deviation):
#: cubic Hermite interpolation error below 5e-10 in the log weight (tested).
SILENT_STEP = 0.025
_LOG_SQRT_2PI = 0.5 * math.log(2.0 * math.pi)


def silent_terms(a: np.ndarray, h: np.ndarray, step: float = SILENT_STEP) -> np.ndarray:
    """``log P(|Z + a| < h)`` for every row of ``a (rows, P) >= 0`` with its own ``h (rows,)``.

    Within a row ``h`` is fixed, and ``g(a) = log P(|Z + a| < h)`` is a smooth function of one
    variable: ``g(a) = -a^2/2 + K(a) + const``, ``K`` the cumulant generating function of a
    standard normal truncated to ``(-h, h)``, so ``g'' = Var - 1`` lies in ``[-1, 0]`` and the
    fourth derivative is a fourth cumulant of a law on an interval of length ``2 h``. Each row
    is tabulated on the nodes ``0, step, 2 step, ...`` up to its largest ``a``, with the exact
    values (:func:`log_silent_probability`) and derivatives ``g'(a) = -(phi(h - a) -
    phi(h + a)) / P``, and evaluated by cubic Hermite interpolation: 4 table look-ups and a
    cubic per particle instead of two normal cdfs and a log. Rows whose range would need more
    nodes than a quarter of their particles are evaluated directly.

    Parameters
    ----------
    a : numpy.ndarray
        Offsets ``(rows, P)``, non-negative, in noise standard deviations.
    h : numpy.ndarray
        Half-widths ``(rows,)``.
    step : float, optional
        Node spacing (:data:`SILENT_STEP`).

    Returns
    -------
    numpy.ndarray
        ``log P(|Z + a| < h)`` ``(rows, P)`` (error below 5e-10).

    Raises
    ------
    ValueError
        If ``a`` is not a finite non-negative ``(rows, P)`` array, ``h`` not finite
        non-negative ``(rows,)``, or ``step`` not a positive number.
    """
    a = _v.shape_is("a", _v.nonneg("a", a, "an offset |m|"), (None, None), "(rows, P)")
    h = _v.shape_is("h", _v.nonneg("h", h, "a half-width"), (a.shape[0],), "one per row of a")
    step = float(_v.positive("step", step, "a node spacing"))
    rows, P = a.shape
    out = np.array(a, dtype=float)
    if rows == 0:
        return out
    _silent_rows(out[:, None, :], np.arange(rows), np.zeros(rows, dtype=np.int64),
                 a.max(axis=1), h, step)
    return out


def _silent_rows(a: np.ndarray, rb: np.ndarray, ri: np.ndarray, amax: np.ndarray,
                 h: np.ndarray, step: float = SILENT_STEP) -> None:
    """:func:`silent_terms` in place on the rows ``a[rb[k], ri[k], :]`` of ``a (n, N, P)``
    (offsets, maxima ``amax (rows,)``, half-widths ``h (rows,)``)."""
    P = a.shape[2]
    J = np.floor(amax / step).astype(np.int64) + 2  # nodes per row
    direct = J > max(64, P // 4)
    if direct.any():
        db, di = rb[direct], ri[direct]
        a[db, di] = censored_normal.log_prob_inside(a[db, di], h[direct][:, None])
    tab = np.flatnonzero(~direct)
    if tab.size == 0:
        return
    Jt = J[tab]
    off = np.cumsum(Jt) - Jt
    owner = np.repeat(np.arange(tab.size), Jt)
    node = np.arange(owner.size) - off[owner]
    an = node * step
    hn = h[tab][owner]
    g = censored_normal.log_prob_inside(an, hn)
    with np.errstate(over="ignore", under="ignore"):
        dg = (np.exp(-0.5 * (hn + an) ** 2 - _LOG_SQRT_2PI - g)
              - np.exp(-0.5 * (hn - an) ** 2 - _LOG_SQRT_2PI - g)) * step
    # interval [node, node + 1] of each row: c0 + f (c1 + f (c2 + f c3)); the last node of a
    # row starts no interval (its coefficients are never read)
    gn = np.append(g[1:], 0.0)
    dn = np.append(dg[1:], 0.0)
    diff = gn - g
    c2 = 3.0 * diff - 2.0 * dg - dn
    c3 = -2.0 * diff + dg + dn
    amplitude_terms.hermite_rows(a, rb[tab], ri[tab], off, 1.0 / step, g, dg, c2, c3)


# ----------------------------------------------------------------------------- the fusion centre
class _FusionCentre(fusion.ReferenceFC):
    """The FC's particle-filter model (a :class:`fusioncenter.particle.FilterModel`) for one
    block of trials; it also plays the sensors (with feedback their decisions at step ``t``
    depend on the FC's broadcast after step ``t - 1``)."""

    dim = 4

    def __init__(self, sc: NonlinearScenario, scheme: str, feedback: str, eta: float, l: float,
                 z: np.ndarray, sel_u: np.ndarray):
        self.sc, self.scheme, self.feedback, self.eta = sc, scheme, feedback, eta
        self.z = z
        n, T, N = z.shape
        self.n, self.N = n, N
        self.pos = sc.positions
        self.r = sc.rvec
        self.sd = np.sqrt(self.r)
        self.sent = np.zeros((n, T, N), dtype=bool)
        self.s = np.full((n, T, N), np.nan)  # what the sensors normalized by
        self.censor = scheme in ("cfomd", "cfwmd")
        self.live = self.censor and feedback != "none"  # decisions depend on the broadcast
        self.needs_cov = self.live and feedback == "state+cov"
        dyn = sc.dynamics
        self.est = np.broadcast_to(dyn.m0, (n, 4)).copy()  # xhat_{t-1|t-1} broadcast
        self.est_cov = np.broadcast_to(dyn.P0, (n, 4, 4)).copy()
        self.P_loc = np.broadcast_to(dyn.P0, (n, N, 4, 4)).copy()  # P^i_{t-1|t-1}
        self.hx_pred = None
        self.hh = None
        self._fixed_decisions(feedback, l, sel_u)

    # --- sensors
    def _local_decisions(self) -> None:
        """No feedback: every sensor runs a full EKF on its own measurements."""
        loc = local_ekf(self.sc, self.z)
        self.sent[:] = loc["nu"] ** 2 >= self.eta * loc["s"]
        self.s[:] = loc["s"]

    def _feedback_decisions(self, k: int) -> None:
        """Decisions at step ``k + 1`` from the broadcast ``xhat_{k|k}`` (and ``Phat_{k|k}``)."""
        sc = self.sc
        xp = self.est @ sc.F.T  # xhat_{k+1|k}, every sensor's prediction
        g = amplitude_ekf.jacobian(sc, xp)  # (n, N, 4)
        if self.feedback == "state":
            _, s, self.P_loc = amplitude_ekf.ekf_step(self.P_loc, g, sc.F, sc.Q, self.r)
        else:
            Pp = sc.F @ self.est_cov @ sc.F.T + sc.Q  # (n, 4, 4)
            s = np.einsum("nik,nkl,nil->ni", g, Pp, g) + self.r
        self.hx_pred = amplitude_ekf.amplitude(sc, xp[:, [0, 2]])  # (n, N)
        nu = self.z[:, k] - self.hx_pred
        self.sent[:, k] = nu * nu >= self.eta * s
        self.s[:, k] = s
        self.hh = np.sqrt(self.eta * s) / self.sd  # half-width of the silent interval / sd

    # --- FilterModel (initial, transition: see fusion.ReferenceFC)
    def log_weight(self, t: int, x: np.ndarray) -> np.ndarray:
        k = t - 1
        if self.live:
            self._feedback_decisions(k)
        sent = self.sent[:, k]  # (n, N)
        if self.scheme != "cfwmd" and not sent.all():
            return self._received_only(k, x)
        amp = self._amplitudes(x)  # (n, N, P): h^i(x) for every particle
        # amp becomes the per-sensor log-likelihood terms, in place (compiled): received,
        # log N(z; h(x), r); silent (CFwMD), the offsets, then their factors
        amax = np.empty(sent.shape)
        amplitude_terms.sensor_terms(amp, sent, self.z[:, k], -0.5 / self.r, self.hx_pred
                                     if self.hx_pred is not None else amax, self.sd, amax)
        if not sent.all():
            rb, ri = np.nonzero(~sent)
            _silent_rows(amp, rb, ri, amax[rb, ri], self.hh[rb, ri])
        if amp.shape[2] < 2:
            return amp.sum(axis=1)
        out = np.empty((amp.shape[0], amp.shape[2]))
        amplitude_terms.sum_sensors(amp, out)  # amp.sum(axis=1), one pass
        return out

    def _received_only(self, k: int, x: np.ndarray) -> np.ndarray:
        """``sum_{received} log N(z^i; h^i(x), r_i)`` computing ``h^i`` only where needed
        (compiled for the exponent 2)."""
        n, P = x.shape[:2]
        out = np.zeros((n, P))
        if self.sc.exponent == 2.0 and self.N <= 129:
            amplitude_terms.received_terms(x, self.pos, float(self.sc.alpha), float(self.sc.power),
                                           self.sent[:, k], self.z[:, k], -0.5 / self.r, out)
            return out
        b, i = np.nonzero(self.sent[:, k])  # row-major: b is non-decreasing
        if b.size == 0:
            return out
        d2 = x[b, :, 0] - self.pos[i, 0][:, None]
        d2 *= d2
        dy = x[b, :, 2] - self.pos[i, 1][:, None]
        dy *= dy
        d2 += dy
        e = amplitude_ekf.amplitude_from_d2(self.sc, d2)
        e -= self.z[b, k, i][:, None]
        e *= e
        e *= (-0.5 / self.r[i])[:, None]
        rows, start = np.unique(b, return_index=True)
        out[rows] = np.add.reduceat(e, start, axis=0)
        return out

    def _amplitudes(self, x: np.ndarray) -> np.ndarray:
        """``h^i(x)`` for every trial, sensor and particle: ``(n, N, P)`` (compiled for the
        exponent 2). The squared distances are assembled from the distinct sensor abscissae
        and ordinates (3 + 3 on a grid)."""
        n, P = x.shape[:2]
        if self.sc.exponent == 2.0:
            out = np.empty((n, self.N, P))
            amplitude_terms.amplitudes(x, self.pos, float(self.sc.alpha), float(self.sc.power), out)
            return out
        px = np.ascontiguousarray(x[..., 0])
        py = np.ascontiguousarray(x[..., 2])
        ux, ix = np.unique(self.pos[:, 0], return_inverse=True)
        uy, iy = np.unique(self.pos[:, 1], return_inverse=True)
        dx2 = np.square(px[:, None, :] - ux[None, :, None])  # (n, #x, P)
        dy2 = np.square(py[:, None, :] - uy[None, :, None])
        d2 = np.empty((n, self.N, P))
        for i in range(self.N):
            np.add(dx2[:, ix[i]], dy2[:, iy[i]], out=d2[:, i])
        return amplitude_ekf.amplitude_from_d2(self.sc, d2)

    def observe(self, t: int, mean: np.ndarray, cov: np.ndarray | None) -> None:
        self.est = mean
        if cov is not None:
            self.est_cov = cov


def _chunk(rng: np.random.Generator, n: int, *, scenario: NonlinearScenario, scheme: str,
           feedback: str, eta: float, l: float, n_particles: int,
           ess_threshold: float) -> np.ndarray:
    """``chunk_fn`` for :func:`fusioncenter.montecarlo.simulate`: ``(n, T, d + 3)`` per trial,
    the layout of :class:`fusioncenter.censoring.CensoringResult` (squared error per state
    component, number of sensors that sent, ESS / particles, collapsed). As in
    :mod:`fusioncenter.censoring`, the first of two spawned streams draws the truth, the
    measurements and the random-selection uniforms (trials are paired across schemes, ``l`` and
    feedback), the second the filter's particles and resampling uniforms."""
    rng_data, rng_pf = rng.spawn(2)
    x, z = scenario.sample(rng_data, n)
    sel_u = rng_data.random(z.shape)
    fc = _FusionCentre(scenario, scheme, feedback, eta, l, z, sel_u)
    out = particle.run_filter(fc, rng_pf, n, n_particles, scenario.T,
                              ess_threshold=ess_threshold)
    sq = (out.mean - x[:, 1:]) ** 2
    return np.concatenate([sq, fc.sent.sum(axis=-1, keepdims=True).astype(float),
                           out.ess[..., None] / n_particles,
                           out.collapsed[..., None].astype(float)], axis=-1)


# ----------------------------------------------------------------------------- run
def run(scenario: NonlinearScenario, scheme: str, *, l, n_trials: int, n_particles: int,
        seed: int, feedback: str = "state", likelihood: str = "corrected",
        ess_threshold: float = 1.0, chunk_size: int | None = None, executor=None,
        progress: bool = False,
        block_size: int = montecarlo.DEFAULT_BLOCK_SIZE) -> results.CensoringResult:
    """Simulate ``n_trials`` trials of ``scenario`` and track them with the FC's particle filter.

    The signature and the result of :func:`fusioncenter.censoring.run`: ``scheme`` in
    :data:`SCHEMES`, ``feedback`` in :data:`FEEDBACK` (``"state"``: Proposition 7, CFwMD;
    ``"state+cov"``: Proposition 8, CFwMD2; ``"none"``: not for ``"cfwmd"``), ``l`` the target
    average number of sending sensors (``eta = threshold(l, N)``; ``p = l / N`` for random
    selection). ``likelihood`` only concerns CFwMD without feedback in the linear model; it is
    validated and recorded, and has no effect here. Runs through
    :func:`fusioncenter.montecarlo.simulate`: results are bitwise identical for any
    ``chunk_size`` and executor, and trials are paired across schemes for the same ``seed``,
    ``n_trials`` and ``block_size``.

    Peak memory of a task (tracemalloc): about 350 bytes per particle of a block (``block_size
    * n_particles`` particles) for CFwMD, 290 for all-send, 150 for CFoMD, so ``block_size=25``
    with ``10^4`` particles needs about 85 MB per worker on top of the interpreter (about 100 MB
    with numpy and scipy).

    Parameters
    ----------
    scenario : NonlinearScenario
        The source and the sensors of Section VII.C.
    likelihood : str, optional
        Validated and recorded in the result, with no effect on the numbers (see above: it
        concerns the linear model only).
    scheme, l, n_trials, n_particles, seed, feedback, ess_threshold, chunk_size, executor
        Those of :func:`fusioncenter.censoring.run`.
    progress, block_size : optional
        Likewise.

    Returns
    -------
    CensoringResult
        Per-trial results (``d = 4``).
    """
    if not isinstance(scenario, NonlinearScenario):
        raise ValueError("scenario must be a NonlinearScenario")
    results.check_scheme(scheme, feedback)
    if scheme == "cfwmd" and feedback == "none":
        raise ValueError("feedback='none' is not available for scheme='cfwmd': without feedback "
                         "the paper gives no full likelihood for the nonlinear system (Remark 4 "
                         "(III)); use feedback='state' or 'state+cov'")
    _one_of("likelihood", likelihood, scenarios.LIKELIHOODS)
    eta = cprob.threshold(l, scenario.N)
    n_particles = _posint("n_particles", n_particles)
    return results.run_chunks(_chunk, scenario, scheme, feedback, likelihood, l=l, eta=eta,
                                 n_particles=n_particles, ess_threshold=ess_threshold,
                                 n_trials=n_trials, seed=seed, chunk_size=chunk_size,
                                 executor=executor, progress=progress, block_size=block_size,
                                 chunk_kwargs={})
