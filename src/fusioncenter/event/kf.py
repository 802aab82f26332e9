"""The event-triggered Kalman filter of :mod:`fusioncenter.event`: the fusion centre's exact
filter under mo2015's stochastic trigger (and the baselines of ``SCHEMES``), its Monte Carlo
summary, and the choice of the trigger parameter for a target send rate."""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from fusioncenter import _validate as _v
from fusioncenter import riccati
from fusioncenter._compiled import kalman_step as step_kernel
from fusioncenter.event._common import fires, per_sensor
from fusioncenter.event.trigger import delta_for_rate, trigger_probability
from fusioncenter.kalman import LinearGaussianModel

__all__ = ["SCHEMES", "EventKFRun", "event_kf_run", "event_kf_chunk", "split_summary",
           "steady_state_delta", "Calibration", "calibrate_delta"]


#: Transmission schemes of :func:`event_kf_run`.
#:
#: ``"stochastic"``        the notes' trigger on the innovation; the centre uses the silence
#:                         (silent sensor = measurement 0 with variance ``r_i + delta_i``): exact.
#:
#: ``"stochastic-ignore"`` same trigger, but the centre drops silent sensors as if the silence
#:                         carried no information (zheng2014's "CFoMD" idea): *not* exact, its
#:                         ``P`` is not the error covariance. A baseline.
#:
#: ``"random"``            sensor ``i`` sends with probability ``p_i`` independently of the data
#:                         (the notes' "previous lecture"); a silent sensor is simply dropped.
#:
#: ``"all-send"``          every sensor sends at every step (the ordinary Kalman filter).
SCHEMES = ("stochastic", "stochastic-ignore", "random", "all-send")


# ----------------------------------------------------------------------------- the filter
@dataclass(frozen=True)
class EventKFRun:
    """Output of :func:`event_kf_run` for ``n`` trials and ``T = steps + 1`` measurement times.

    Attributes
    ----------
    x : numpy.ndarray
        True states ``(n, T, nx)``.
    xhat : numpy.ndarray
        Filtered states ``(n, T, nx)``.
    P : numpy.ndarray
        Each trial's filtered covariance ``P_{k|k}`` ``(n, T, nx, nx)``.
    gamma : numpy.ndarray
        Who sent, ``(n, T, m)`` (bool).
    send_prob : numpy.ndarray
        Each sensor's send probability given the past, as the centre computes it
        (``trigger_probability(s_{i,k}, delta_i)`` for the trigger, ``p_i`` for random
        selection, 1 for all-send), ``(n, T, m)``.
    scheme : str
        The transmission scheme, one of :data:`SCHEMES`.
    """

    x: np.ndarray
    xhat: np.ndarray
    P: np.ndarray
    gamma: np.ndarray
    send_prob: np.ndarray
    scheme: str

    @property
    def sq_err(self) -> np.ndarray:
        """Squared filtering error per component ``(n, T, nx)``."""
        return (self.xhat - self.x) ** 2

    @property
    def transmissions(self) -> np.ndarray:
        """Number of sensors that sent, ``(n, T)``."""
        return self.gamma.sum(axis=-1)


def _model(model) -> tuple[LinearGaussianModel, np.ndarray]:
    if not isinstance(model, LinearGaussianModel):
        raise ValueError("model must be a fusioncenter.kalman.LinearGaussianModel "
                         "(e.g. fusioncenter.models.tracking_model())")
    R = model.R
    if np.any(R - np.diag(np.diag(R)) != 0):
        raise ValueError("model.R must be diagonal: the stochastic trigger assumes independent "
                         "sensor noises")
    return model, np.diag(R).copy()


def _scheme_params(scheme: str, m: int, delta, p):
    if scheme not in SCHEMES:
        raise ValueError(f"scheme must be one of {SCHEMES}, got {scheme!r}")
    if scheme in ("stochastic", "stochastic-ignore"):
        if delta is None:
            raise ValueError(f"delta is required for scheme {scheme!r}")
        if p is not None:
            raise ValueError(f"p is only used by scheme 'random', not {scheme!r}")
        return per_sensor("delta", delta, m, positive=True), None
    if delta is not None:
        raise ValueError(f"delta is only used by the stochastic schemes, not {scheme!r}")
    if scheme == "random":
        if p is None:
            raise ValueError("p (send probabilities) is required for scheme 'random'")
        p = per_sensor("p", p, m, positive=False)
        if np.any(p > 1):
            raise ValueError(f"p must be probabilities in [0, 1], got {p}")
        return None, p
    if p is not None:
        raise ValueError("p is only used by scheme 'random'")
    return None, None


def _steps(steps) -> int:
    if isinstance(steps, bool) or not isinstance(steps, int | np.integer) or steps < 0:
        raise ValueError(f"steps must be a non-negative integer, got {steps!r}")
    return int(steps)


def event_kf_run(model: LinearGaussianModel, steps: int, scheme: str,
                 rng: np.random.Generator, n_trials: int, *, delta=None, p=None) -> EventKFRun:
    """Simulate ``n_trials`` trajectories and run the fusion centre's filter under ``scheme``.

    ``x_0 ~ N(model.m0, model.P0)``, ``x_{k+1} = A x_k + w_k``, ``y_k = C x_k + v_k`` for
    ``k = 0..steps``; the filter starts from ``(m0, P0)`` as its prediction for ``k = 0``.
    ``scheme`` is one of :data:`SCHEMES`; ``delta`` (``(m,)`` or scalar) for the stochastic
    schemes, ``p`` (``(m,)`` or scalar, in ``[0, 1]``) for ``"random"``.

    Common random numbers: all state and noise draws come first (``model.sample(rng, n, steps)``),
    then one uniform array ``xi`` shaped ``(n, steps+1, m)``, drawn for every scheme. The
    stochastic trigger sends iff ``xi > exp(-z^2/(2 delta))`` (``z`` the innovation); random
    selection sends iff ``xi < p``. So the same ``rng`` state gives the same trajectories,
    measurements and uniforms under every scheme, and with a tiny ``delta`` the stochastic scheme
    reproduces all-send exactly.

    Per step, vectorized over trials (each trial has its own ``P``), one
    :func:`fusioncenter.kalman.kalman_step` with the innovation ``Gamma z`` and
    ``R_k = R + (I - Gamma_k) Delta`` (stochastic; all-send is ``Gamma = I``), or with the silent
    rows of ``C`` zeroed (random, stochastic-ignore), which drops those sensors exactly:
    ``S = C_k P C_k^T + R_k``, ``xhat += P C_k^T S^{-1} (Gamma z)``, ``P_{k|k}`` by
    :func:`fusioncenter.riccati.measurement_update`.

    Parameters
    ----------
    model : LinearGaussianModel
        The system; ``model.R`` must be diagonal (independent sensor noises).
    steps : int
        Number of transitions, ``>= 0``.
    scheme : str
        One of :data:`SCHEMES`.
    rng : numpy.random.Generator
        The source of randomness.
    n_trials : int
        Number of trials, ``>= 1``.
    delta : array_like, optional
        Trigger parameters ``(m,)`` or a scalar, ``> 0`` (stochastic schemes only).
    p : array_like, optional
        Send probabilities ``(m,)`` or a scalar, in ``[0, 1]`` (``"random"`` only).

    Returns
    -------
    EventKFRun

    Raises
    ------
    ValueError
        Naming the argument that is missing, superfluous or out of range.
    """
    model, r = _model(model)
    steps = _steps(steps)
    if isinstance(n_trials, bool) or not isinstance(n_trials, int | np.integer) or n_trials < 1:
        raise ValueError(f"n_trials must be a positive integer, got {n_trials!r}")
    if not isinstance(rng, np.random.Generator):
        raise ValueError("rng must be a numpy.random.Generator")
    n = int(n_trials)
    C, A, Q = model.C, model.A, model.Q
    m, nx = C.shape
    delta, p = _scheme_params(scheme, m, delta, p)
    T = steps + 1

    x, y = model.sample(rng, n, steps)  # state and noise draws first ...
    xi = rng.random((n, T, m))  # ... then the trigger's uniforms (every scheme draws them)

    xhat = np.empty((n, T, nx))
    Ppost = np.empty((n, T, nx, nx))
    gamma = np.empty((n, T, m), dtype=bool)
    send_prob = np.empty((n, T, m))
    xpred = np.broadcast_to(model.m0, (n, nx)).copy()
    Ppred = np.broadcast_to(model.P0, (n, nx, nx)).copy()
    eye = np.eye(m)
    zeros = np.zeros(m)
    for k in range(T):
        z = y[:, k] - xpred @ C.T  # innovations (n, m)
        if scheme in ("stochastic", "stochastic-ignore"):
            s = np.einsum("ij,njk,ik->ni", C, Ppred, C) + r
            send_prob[:, k] = trigger_probability(s, delta)
            g = fires(xi[:, k], z, delta)
        elif scheme == "random":
            send_prob[:, k] = p
            g = xi[:, k] < p
        else:
            send_prob[:, k] = 1.0
            g = np.ones((n, m), dtype=bool)
        gamma[:, k] = g
        if scheme in ("stochastic", "all-send"):
            extra = delta if scheme == "stochastic" else zeros
            Ck = np.broadcast_to(C, (n, m, nx))
            Rk = (r + np.where(g, 0.0, extra))[:, :, None] * eye
        else:  # drop silent sensors: a zero row of C carries no information
            Ck = C * g[:, :, None]
            Rk = np.broadcast_to(r[:, None] * eye, (n, m, m))
        sing = bool(np.any(np.diagonal(Rk, axis1=-2, axis2=-1) == 0))  # R_k is diagonal
        xhat[:, k], Ppost[:, k], xpred, Ppred = step_kernel.kalman_step(  # P0, r checked
            xpred, Ppred, np.where(g, z, 0.0), Ck, Rk, A, Q, r_singular=sing)
    return EventKFRun(x=x, xhat=xhat, P=Ppost, gamma=gamma, send_prob=send_prob, scheme=scheme)


def event_kf_chunk(rng: np.random.Generator, n: int, *, model: LinearGaussianModel, steps: int,
                   scheme: str, delta=None, p=None) -> np.ndarray:
    """Per-trial summary of :func:`event_kf_run`, a ``chunk_fn`` for ``montecarlo.simulate``.

    Use ``functools.partial(event_kf_chunk, model=..., steps=..., scheme=..., delta=...)``.
    Returns ``(n, steps+1, 2 nx + 2 m)``: columns ``[sq_err (nx) | diag P_{k|k} (nx) | gamma (m) |
    send_prob (m)]``; :func:`split_summary` splits a sample array or a mean/stderr by name.

    Parameters
    ----------
    rng : numpy.random.Generator
        The source of randomness.
    n : int
        Number of trials, ``>= 0`` (``0``: an empty chunk, after checking the other
        arguments).
    model : LinearGaussianModel
        The system; ``model.R`` must be diagonal (independent sensor noises).
    steps, scheme, delta, p
        As in :func:`event_kf_run`.

    Returns
    -------
    numpy.ndarray
        ``(n, steps + 1, 2 nx + 2 m)``.

    Raises
    ------
    ValueError
        As :func:`event_kf_run`; naming ``n`` if it is not an integer ``>= 0``.
    """
    n = _v.integer("n", n, 0)
    if n == 0:  # the arguments are checked by a one-trial run on a throw-away generator
        return event_kf_chunk(np.random.default_rng(0), 1, model=model, steps=steps,
                              scheme=scheme, delta=delta, p=p)[:0]
    run = event_kf_run(model, steps, scheme, rng, n, delta=delta, p=p)
    diagP = np.diagonal(run.P, axis1=-2, axis2=-1)
    return np.concatenate([run.sq_err, diagP, run.gamma.astype(float), run.send_prob], axis=-1)


def split_summary(arr, nx: int) -> dict[str, np.ndarray]:
    """Name the last-axis columns of an :func:`event_kf_chunk` array (or its mean or stderr).

    Keys: ``sq_err`` (``nx``), ``p_diag`` (``nx``), ``gamma`` (``m``), ``send_prob`` (``m``).

    Parameters
    ----------
    arr : array_like
        An :func:`event_kf_chunk` array, or its mean or standard error.
    nx : int
        The state dimension.

    Returns
    -------
    dict
        ``sq_err``, ``p_diag``, ``gamma``, ``send_prob`` (views of ``arr``: the values as they
        are, so a NaN standard error of one trial stays NaN).

    Raises
    ------
    ValueError
        If ``arr`` is text or has no axis, ``nx`` is not a positive integer, or the last axis is
        not ``2 nx + 2 m`` for some ``m >= 1``.
    """
    nx = _v.posint("nx", nx)
    arr = _v.as_float("arr", arr)
    if arr.ndim == 0:
        raise ValueError("arr must have a last axis of columns, got a scalar")
    extra = arr.shape[-1] - 2 * nx
    if extra < 2 or extra % 2:
        raise ValueError(f"arr's last axis ({arr.shape[-1]}) is not 2*nx + 2*m for nx={nx}")
    m = extra // 2
    return {
        "sq_err": arr[..., :nx],
        "p_diag": arr[..., nx:2 * nx],
        "gamma": arr[..., 2 * nx:2 * nx + m],
        "send_prob": arr[..., 2 * nx + m:],
    }


def steady_state_delta(model: LinearGaussianModel, rate, *, method: str = "mean-information",
                       tol: float = 1e-12, max_iter: int = 1000) -> np.ndarray:
    """Per-sensor ``delta`` aiming at a long-run send probability ``rate`` (``(m,)`` or scalar).

    In the filter, sensor ``i`` sends at step ``k`` with probability
    ``trigger_probability(s_{i,k}, delta_i)``, ``s_{i,k} = c_i P_{k|k-1} c_i^T + r_i``, and
    ``P_{k|k-1}`` is random (it depends on who sent before). No closed form gives the long-run
    average, so both methods replace the random ``s_{i,k}`` by one deterministic value and invert
    the rate there with :func:`delta_for_rate`:

    * ``"all-send"``: ``s_i`` from the all-send steady state (the DARE with ``R``). Since the
      event-triggered ``P_{k|k-1}`` is never smaller, the actual ``s`` is larger and the achieved
      rate is *above* the target (the rate increases with ``s``).
    * ``"mean-information"`` (default): a fixed point. Replace each sensor by its average
      information ``rate_i / r_i + (1 - rate_i) / (r_i + delta_i)``, i.e. a noise variance
      ``r_eff_i``; take ``P`` the steady state of the DARE with ``diag(r_eff)``; set ``s_i`` from
      it and ``delta_i = delta_for_rate(rate_i, s_i)``; repeat. Starting from ``"all-send"`` the
      iteration is monotone (larger ``delta`` -> larger ``r_eff`` -> larger ``P`` -> larger ``s`` ->
      larger ``delta``) and bounded (``r_eff <= r / rate``), so it converges.

    Both are approximations: measure the achieved rate by simulation (``EventKFRun.gamma`` or its
    unbiased, less noisy companion ``send_prob``), or use :func:`calibrate_delta`, which starts
    here and hits the target in simulation. Measured on :func:`fusioncenter.models.tracking_model`
    (long-run rate, steps 30..60): with ``N = 2``, target 0.5 -> 0.508 (``"all-send"``: 0.531),
    target 0.1 -> 0.166 (0.227); with ``N = 4``, target 0.25 -> 0.273 (0.318), 0.75 -> 0.750.
    The approximation is good at moderate and high rates and poor at low rates, where ``P``
    fluctuates most.

    Parameters
    ----------
    model : LinearGaussianModel
        The system; ``model.R`` must be diagonal (independent sensor noises).
    rate : array_like
        Target long-run send probabilities ``(m,)`` or a scalar, in ``(0, 1)``.
    method : str
        ``"mean-information"`` or ``"all-send"``.
    tol : float
        Relative convergence tolerance of the fixed point.
    max_iter : int
        Iterations allowed.

    Returns
    -------
    numpy.ndarray
        ``delta`` ``(m,)``.

    Raises
    ------
    ValueError
        If ``rate`` or ``method`` is invalid, ``model.R`` is not diagonal and positive, or the
        iteration does not converge (the message names ``rate``: for a tiny rate the solver's
        accuracy limits the fixed point); naming ``rate`` if it is so small (``r / rate``
        near ``1e300``) that the steady state leaves the float range (a documented limit).
    """
    model, r = _model(model)
    m = model.ny
    rate = per_sensor("rate", rate, m, positive=True)
    if np.any(rate >= 1):
        raise ValueError(f"rate must lie in the open interval (0, 1), got {rate}")
    if method not in ("all-send", "mean-information"):
        raise ValueError(f"method must be 'all-send' or 'mean-information', got {method!r}")
    if np.any(r <= 0):
        raise ValueError("model.R must be positive definite")
    C = model.C

    def delta_from(R_eff: np.ndarray) -> np.ndarray:
        P = riccati.steady_state(model.A, model.Q, C, np.diag(R_eff))
        s = np.einsum("ij,jk,ik->i", C, P, C) + r
        return np.asarray(delta_for_rate(rate, s), dtype=float).reshape(m)

    delta = delta_from(r)
    if method == "all-send":
        return delta
    for _ in range(max_iter):
        r_eff = 1.0 / (rate / r + (1.0 - rate) / (r + delta))
        try:
            new = delta_from(r_eff)
        except ValueError as err:
            if "no stabilizing Riccati solution" not in str(err):
                raise
            raise ValueError(f"rate = {rate} is too small for a steady state of this model: "
                             f"the silent sensors' effective noise variance r_eff ~ r / rate = "
                             f"{r_eff} leaves the range of the Riccati solver (a documented "
                             f"limit; calibrate_delta simulates instead)") from None
        if np.all(np.abs(new - delta) <= tol * np.maximum(1.0, np.abs(new))):
            return new
        delta = new
    raise ValueError(f"rate = {rate}: no convergence of steady_state_delta in "
                     f"max_iter={max_iter} iterations to tol={tol} (is (A, C) detectable? "
                     f"for a tiny rate the Riccati solver's accuracy, about 1e-10 relative, "
                     f"is the limit: loosen tol)")


class Calibration(NamedTuple):
    """Result of :func:`calibrate_delta`.

    Attributes
    ----------
    delta : numpy.ndarray
        Per-sensor trigger parameter, ``(m,)``.
    rate : numpy.ndarray
        Achieved long-run send probability per sensor on the calibration sample, ``(m,)``.
    stderr : numpy.ndarray
        Its Monte Carlo standard error (across trials), ``(m,)``.
    iterations : int
        Simulations run.
    """

    delta: np.ndarray
    rate: np.ndarray
    stderr: np.ndarray
    iterations: int


def _log_odds(rate):
    """``log(rate (2 - rate) / (1 - rate)^2)``: ``log(s / delta)`` for ``mu = 0`` (see below)."""
    return np.log(rate) + np.log(2.0 - rate) - 2.0 * np.log1p(-rate)


def calibrate_delta(model: LinearGaussianModel, rate, *, n_trials: int = 2000, steps: int = 60,
                    burn_in: int = 30, seed: int = 0, tol: float = 1e-3,
                    max_iter: int = 30) -> Calibration:
    """Per-sensor ``delta`` whose *simulated* long-run send probability is ``rate`` (to ``tol``).

    The achieved rate of sensor ``i`` is estimated as the mean over trials and over steps
    ``burn_in..steps`` of ``send_prob`` (the send probability given the past, whose mean equals
    that of ``gamma`` and which is less noisy) in :func:`event_kf_run` with the ``"stochastic"``
    scheme. Every iteration reuses the same generator seed (common random numbers), so the
    achieved rate is a deterministic, nearly smooth function of ``delta``.

    Search: for a fixed innovation variance ``s``, ``log(s / delta)`` equals ``_log_odds(rate)``
    (from ``delta = s (1-rate)^2 / (rate (2-rate))``), so we solve
    ``_log_odds(achieved_i) = _log_odds(rate_i)`` in ``u_i = log delta_i`` by a secant step per
    sensor (slope clipped to ``[-1, -0.05]``, first step with slope -1, steps at most 2 in
    ``u``), starting from :func:`steady_state_delta` (``"mean-information"``). Slope -1 is exact
    when ``s`` does not depend on ``delta``; in the filter a larger ``delta`` also enlarges ``s``,
    which is why the deterministic approximations miss at low rates (target 0.1 on the tracking
    model: ``steady_state_delta`` gives ``delta`` near 58 with an achieved 0.166; calibration
    finds about 290).

    The result hits ``rate`` on this sample; the true long-run rate lies within a few ``stderr``
    of it (``stderr`` is computed across trials from per-trial averages). Raises ``ValueError``
    if ``max_iter`` simulations do not reach ``tol``.

    Parameters
    ----------
    model, rate
        As in :func:`steady_state_delta`.
    n_trials, steps, burn_in : int
        Size of the calibration simulation; the rate is averaged over steps ``burn_in..steps``.
    seed : int
        Non-negative integer seed (NumPy integers accepted, ``bool`` rejected).
    tol : float
        Accuracy required of the achieved rate.
    max_iter : int
        Simulations allowed.

    Returns
    -------
    Calibration
        ``delta``, the achieved ``rate``, its ``stderr`` (NaN for one trial: undefined) and the
        number of simulations.

    Raises
    ------
    ValueError
        If an argument is out of range, or the target is not reached in ``max_iter`` simulations.
    """
    model, _ = _model(model)
    m = model.ny
    target = per_sensor("rate", rate, m, positive=True)
    if np.any(target >= 1):
        raise ValueError(f"rate must lie in the open interval (0, 1), got {target}")
    steps = _steps(steps)
    if isinstance(burn_in, bool) or not isinstance(burn_in, int | np.integer) \
            or not 0 <= burn_in <= steps:
        raise ValueError(f"burn_in must be an integer in [0, steps={steps}], got {burn_in!r}")
    if not tol > 0:
        raise ValueError(f"tol must be positive, got {tol}")
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or seed < 0:
        raise ValueError(f"seed must be a non-negative integer, got {seed!r}")
    g_target = _log_odds(target)
    u = np.log(steady_state_delta(model, target))
    u_prev = e_prev = None
    for it in range(1, int(max_iter) + 1):
        run = event_kf_run(model, steps, "stochastic", np.random.default_rng(seed), n_trials,
                           delta=np.exp(u))
        per_trial = run.send_prob[:, burn_in:].mean(axis=1)  # (n, m)
        achieved = per_trial.mean(axis=0)
        stderr = per_trial.std(axis=0, ddof=1) / np.sqrt(per_trial.shape[0]) \
            if per_trial.shape[0] > 1 else np.full(m, np.nan)
        if np.all(np.abs(achieved - target) <= tol):
            return Calibration(np.exp(u), achieved, stderr, it)
        e = _log_odds(np.clip(achieved, 1e-12, 1 - 1e-12)) - g_target
        slope = np.full(m, -1.0)
        if u_prev is not None:
            du = u - u_prev
            ok = np.abs(du) > 1e-12
            slope[ok] = np.clip((e[ok] - e_prev[ok]) / du[ok], -1.0, -0.05)
        u_prev, e_prev = u, e
        u = u + np.clip(-e / slope, -2.0, 2.0)
    raise ValueError(f"calibrate_delta: achieved rate {achieved} not within tol={tol} of {target} "
                     f"after max_iter={max_iter} simulations (raise n_trials or tol)")
