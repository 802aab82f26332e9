"""The event-triggered Kalman filter of :mod:`fusioncenter.event`: the fusion centre's exact
filter under mo2015's stochastic trigger (and the baselines of ``SCHEMES``) and its Monte Carlo
summary. The choice of the trigger parameter for a target send rate is in
:mod:`fusioncenter.event.rate`."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from fusioncenter import _validate as _v
from fusioncenter._compiled import kalman_step as step_kernel
from fusioncenter.event._common import check_model, check_steps, fires, per_sensor
from fusioncenter.event.trigger import trigger_probability
from fusioncenter.kalman import LinearGaussianModel

__all__ = ["SCHEMES", "EventKFRun", "event_kf_run", "event_kf_chunk", "split_summary"]


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
    model, r = check_model(model)
    steps = check_steps(steps)
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
