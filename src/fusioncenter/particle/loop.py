"""The bootstrap particle filter's loop (:func:`run_filter`), what it needs from a model
(:class:`FilterModel`) and what it returns (:class:`FilterOutput`), with the particles' layout
it keeps (:func:`by_component`).

The loop's hot pieces are compiled (:mod:`fusioncenter._compiled.weights`,
:mod:`fusioncenter._compiled.resampling`); the model supplies the initial law, the transition
and the log weights (see :mod:`fusioncenter.particle`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from fusioncenter._compiled import resampling, weights
from fusioncenter._validate import as_float as _v_as_float

__all__ = ["by_component", "FilterModel", "FilterOutput", "run_filter"]


def by_component(x) -> np.ndarray:
    """The particles ``x (n, P, d)`` stored component by component, seen as ``(n, P, d)``.

    Returns a view of a C-contiguous ``(n, d, P)`` copy: ``out[..., j]`` is then an ``(n, P)``
    array with contiguous rows, which makes elementwise work on one component (a position, a
    velocity) as fast as on a separate array. :func:`run_filter` keeps whatever layout the
    model's ``initial`` returns (its resampling buffer is ``numpy.empty_like`` of the particles).

    Parameters
    ----------
    x : array_like
        Particles ``(n, P, d)``.

    Returns
    -------
    numpy.ndarray
        The same values ``(n, P, d)``, with strides ``(d P, 1, P)`` elements.

    Raises
    ------
    ValueError
        If ``x`` is text or not 3-D (the values are copied as they are: a layout, not a
        computation, so NaN stays NaN).
    """
    x = _v_as_float("x", x)
    if x.ndim != 3:
        raise ValueError(f"x must be particles (n, P, d), got shape {x.shape}")
    return np.ascontiguousarray(np.swapaxes(x, 1, 2)).swapaxes(1, 2)


class FilterModel(Protocol):
    """What :func:`run_filter` needs from a model (see :mod:`fusioncenter.particle`).

    A model may also set ``needs_cov = False`` (default ``True``): the loop then skips the
    weighted covariance, ``observe`` receives ``cov=None`` and :attr:`FilterOutput.cov` is NaN.

    Attributes
    ----------
    dim : int
        The state dimension ``d``.
    """

    dim: int

    def initial(self, rng: np.random.Generator, n: int, P: int) -> np.ndarray:
        """Draw the particles of the prior of ``x_0``.

        Parameters
        ----------
        rng : numpy.random.Generator
            The filter's random stream.
        n, P : int
            Trials and particles per trial.

        Returns
        -------
        numpy.ndarray
            The particles ``(n, P, d)``, in any memory layout (the loop keeps it).
        """

    def transition(self, rng: np.random.Generator, t: int, x: np.ndarray) -> np.ndarray:
        """Draw ``x_t`` given ``x_{t-1}`` for every particle.

        Parameters
        ----------
        rng : numpy.random.Generator
            The filter's random stream (the transition draws before the resampling uniforms).
        t : int
            The time step, ``1..steps``.
        x : numpy.ndarray
            The particles ``x_{t-1}`` ``(n, P, d)``.

        Returns
        -------
        numpy.ndarray
            The particles ``x_t`` ``(n, P, d)`` (``x`` itself may be updated in place and
            returned).
        """

    def log_weight(self, t: int, x: np.ndarray) -> np.ndarray:
        """The incremental log weight at time ``t``: the log-likelihood of the data received
        at ``t`` (additive constants may be dropped).

        Parameters
        ----------
        t : int
            The time step.
        x : numpy.ndarray
            The particles ``x_t`` ``(n, P, d)``.

        Returns
        -------
        numpy.ndarray
            ``(n, P)``. The loop normalizes it in place, so the model must not rely on its
            content afterwards (it may reuse the buffer).
        """

    def observe(self, t: int, mean: np.ndarray, cov: np.ndarray | None) -> None:
        """Receive the filter's estimate after weighting: where a fusion centre records it and
        prepares what it feeds back to the sensors for time ``t + 1``. May do nothing.

        Parameters
        ----------
        t : int
            The time step.
        mean : numpy.ndarray
            ``E[x_t | data]`` ``(n, d)`` (a copy the model may keep).
        cov : numpy.ndarray or None
            Its covariance ``(n, d, d)``, or ``None`` if the model does not ``needs_cov``.
        """


@dataclass(frozen=True)
class FilterOutput:
    """Output of :func:`run_filter` for ``n`` trials and times ``t = 1..steps``.

    Attributes
    ----------
    mean : numpy.ndarray
        ``(n, steps, d)``: the weighted estimate of ``x_t`` given the data up to ``t`` (before
        resampling).
    cov : numpy.ndarray
        ``(n, steps, d, d)``: its weighted covariance; NaN unless the model ``needs_cov``.
    ess : numpy.ndarray
        ``(n, steps)``: effective sample size after weighting.
    log_evidence : numpy.ndarray
        ``(n,)``: ``sum_t log(mean_j w_{t,j})`` (the log-likelihood of the data under the
        weights' model, up to the constants the model dropped).
    collapsed : numpy.ndarray
        ``(n, steps)``, bool: no particle had positive weight (the step's data were ignored for
        that trial).
    """

    mean: np.ndarray
    cov: np.ndarray
    ess: np.ndarray
    log_evidence: np.ndarray
    collapsed: np.ndarray


def run_filter(model: FilterModel, rng: np.random.Generator, n_trials: int, n_particles: int,
               steps: int, *, ess_threshold: float = 1.0) -> FilterOutput:
    """The bootstrap particle filter (zheng2014 Algorithm 1, steps A1.3--A1.6) on ``n_trials``.

    The one sequential Monte Carlo loop of the library: every fusion centre is a model of it
    (:class:`FilterModel`). For ``t = 1..steps``: propagate every particle
    (``model.transition``), add ``model.log_weight(t, x)`` to the log weights, normalize, estimate
    the mean (and the covariance if ``model.needs_cov``), tell the model (``model.observe``), then
    resample (systematic, one uniform per trial) the trials whose ESS is at most
    ``ess_threshold * n_particles`` (``1.0``: every step whatever the ESS, as Algorithm 1 does;
    ``0.0``: never). The uniforms are drawn at every step for every trial whether used or not, so
    the random stream does not depend on the data.

    The hot pieces are compiled (:mod:`fusioncenter._compiled`): after subtracting each trial's
    maximum log weight and exponentiating, one pass per trial gives the weight sum, the weighted
    means and the ESS (:func:`fusioncenter._compiled.weights.weighted_moments`), and one more
    systematic resampling fused with the gather
    (:func:`fusioncenter._compiled.resampling.resample_rows`: the ancestors of
    :func:`fusioncenter._compiled.resampling.systematic_ancestors`, without storing them).
    Everything is row by row: a trial's result
    does not depend on the other trials of the batch. A trial whose weights are all zero (no
    particle compatible with the data) keeps uniform weights for that step and is flagged in
    :attr:`FilterOutput.collapsed`.

    Random-number order per step: ``model.transition`` draws first, then ``u (n_trials,)``.

    Parameters
    ----------
    model : FilterModel
        Initial law, transition, log weights and the estimate's consumer (see
        :class:`FilterModel`); ``model.dim`` is the state dimension ``d``.
    rng : numpy.random.Generator
        The filter's random stream (particles, resampling uniforms, whatever the model draws).
    n_trials, n_particles : int
        Independent trials ``n`` and particles per trial ``P`` (positive).
    steps : int
        Number of time steps (non-negative).
    ess_threshold : float, optional
        Resample a trial when its ESS is at most ``ess_threshold * n_particles``; in ``[0, 1]``.

    Returns
    -------
    FilterOutput
        Means ``(n, steps, d)``, covariances (NaN unless ``model.needs_cov``), ESS after
        weighting, log evidence and the collapsed flags.
    """
    for name, value in (("n_trials", n_trials), ("n_particles", n_particles)):
        if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
            raise ValueError(f"{name} must be a positive integer, got {value!r}")
    if isinstance(steps, bool) or not isinstance(steps, int | np.integer) or steps < 0:
        raise ValueError(f"steps must be a non-negative integer, got {steps!r}")
    if not 0.0 <= ess_threshold <= 1.0:
        raise ValueError(f"ess_threshold must lie in [0, 1], got {ess_threshold}")
    n, P, d = int(n_trials), int(n_particles), int(model.dim)
    need_cov = bool(getattr(model, "needs_cov", True))
    means = np.empty((n, steps, d))
    covs = np.full((n, steps, d, d), np.nan)
    esss = np.empty((n, steps))
    collapsed = np.zeros((n, steps), dtype=bool)
    log_ev = np.zeros(n)
    x = np.asarray(model.initial(rng, n, P))
    if x.dtype != np.float64:
        x = x.astype(float)
    if x.shape != (n, P, d):
        raise ValueError(f"model.initial returned shape {x.shape}, expected {(n, P, d)}")
    every_step = ess_threshold >= 1.0
    # log weights carried over from the last step for the trials not resampled (normalized),
    # 0 for the others; ``offset`` is log(sum of the carried weights) (log P after resampling)
    carried = None if every_step else np.zeros((n, P))
    offset = np.full(n, math.log(P))
    S, ess_b, mx = np.empty(n), np.empty(n), np.empty(n)
    mean = np.empty((n, d))
    spare = np.empty_like(x)  # the same memory layout as x (see by_component)
    all_rows = np.ones(n, dtype=bool)
    for t in range(1, steps + 1):
        x = model.transition(rng, t, x)
        if x.shape != (n, P, d):
            raise ValueError(f"model.transition returned shape {x.shape}, expected {(n, P, d)}")
        u = rng.random(n)
        lw = np.asarray(model.log_weight(t, x), dtype=float)
        if not (lw.flags.writeable and lw.flags.owndata):
            lw = lw.copy()  # normalized in place below
        if lw.shape != (n, P):
            raise ValueError(f"model.log_weight returned shape {lw.shape}, expected {(n, P)}")
        if carried is not None:
            lw += carried
        # lw -= its row maximum (rows of -inf, no particle compatible with the data, set to 0:
        # they are ignored), in one compiled pass: NumPy's max and subtraction, the same floats
        weights.shift_by_row_max(lw, mx)
        if not np.isfinite(mx.sum()) and (np.isnan(mx).any() or np.any(mx == np.inf)):
            raise ValueError("log weights must not be NaN or +inf")
        dead = mx == -np.inf
        if dead.any():
            mx[dead] = 0.0
        w = np.exp(lw, out=lw)
        weights.weighted_moments(w, x, S, mean, ess_b)
        collapsed[:, t - 1] = dead
        inc = np.log(S)
        inc += mx
        inc -= offset
        if dead.any():
            inc[dead] = 0.0
        log_ev += inc
        means[:, t - 1] = mean
        esss[:, t - 1] = ess_b
        cov = None
        if need_cov:
            dev = x - mean[:, None, :]
            cov = np.swapaxes(dev * (w / S[:, None])[..., None], -1, -2) @ dev
            cov = 0.5 * (cov + np.swapaxes(cov, -1, -2))
            covs[:, t - 1] = cov
        model.observe(t, mean.copy(), cov)
        todo = all_rows if every_step else ess_b <= ess_threshold * P
        if carried is not None:
            with np.errstate(divide="ignore"):
                carried = np.where(todo[:, None], 0.0, np.log(w / S[:, None]))
            offset = np.where(todo, math.log(P), 0.0)
        resampling.resample_rows(w, S, u, todo, x, spare)
        x, spare = spare, x
    return FilterOutput(mean=means, cov=covs, ess=esss, log_evidence=log_ev, collapsed=collapsed)
