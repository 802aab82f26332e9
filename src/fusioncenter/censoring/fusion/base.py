"""What every fusion-centre model shares: the four methods :func:`fusioncenter.particle.run_filter`
calls (:class:`FusionCentreModel`), the bases of the reference models (:class:`ReferenceFC`,
:class:`FeedbackModel`) and of the exact no-feedback filters (:class:`ExactModel`), and the
sensors' decisions every scheme shares (:func:`decisions_in_advance`, :func:`silent_rows`).

The linear, vector and nonlinear fusion centres
(:mod:`~fusioncenter.censoring.fusion.linear`, :mod:`~fusioncenter.censoring.fusion.exact`,
:mod:`fusioncenter.censoring.vector_fusion`, :mod:`fusioncenter.censoring.nonlinear`) build on
these."""

from __future__ import annotations

import abc

import numpy as np


class FusionCentreModel(abc.ABC):
    """A fusion centre as a model of :func:`fusioncenter.particle.run_filter` (the methods of
    :class:`fusioncenter.particle.FilterModel`, documented once here for every fusion centre).

    A model serves one block of ``n`` trials of one scenario: it draws the particles of the
    FC's filter, propagates them, weights them with the likelihood of what the FC received, and
    hears the filter's estimate after every step (with feedback, what it broadcasts next). The
    subclasses set the state dimension ``dim`` and, where the loop should skip the weighted
    covariance, ``needs_cov``.

    Attributes
    ----------
    dim : int
        The particles' dimension ``d`` (set by the subclass).
    """

    @abc.abstractmethod
    def initial(self, rng: np.random.Generator, n: int, P: int) -> np.ndarray:
        """Draw the particles at ``t = 0`` (A1.1).

        Parameters
        ----------
        rng : numpy.random.Generator
            The filter's random stream.
        n : int
            Number of trials of the block.
        P : int
            Particles per trial.

        Returns
        -------
        numpy.ndarray
            Particles ``(n, P, dim)``.
        """

    @abc.abstractmethod
    def transition(self, rng: np.random.Generator, t: int, x: np.ndarray) -> np.ndarray:
        """Propagate the particles from ``t - 1`` to ``t`` (A1.3).

        Parameters
        ----------
        rng : numpy.random.Generator
            The filter's random stream (the process noise, and whatever else the model draws).
        t : int
            The step reached, ``1..T``.
        x : numpy.ndarray
            Particles ``(n, P, dim)`` at ``t - 1`` (a model may update them in place).

        Returns
        -------
        numpy.ndarray
            Particles ``(n, P, dim)`` at ``t``.
        """

    @abc.abstractmethod
    def log_weight(self, t: int, x: np.ndarray) -> np.ndarray:
        """The log-likelihood of what the FC received at ``t``, per particle (A1.4).

        Parameters
        ----------
        t : int
            The step, ``1..T``.
        x : numpy.ndarray
            Particles ``(n, P, dim)`` at ``t``.

        Returns
        -------
        numpy.ndarray
            Log weights ``(n, P)``; a model may drop constants that are the same for every
            particle of a trial.
        """

    def observe(self, t: int, mean: np.ndarray, cov: np.ndarray | None) -> None:
        """Hear the filter's estimate at ``t``; by default nothing is done with it.

        A model with feedback forms from it what the sensors receive at ``t + 1``.

        Parameters
        ----------
        t : int
            The step, ``1..T``.
        mean : numpy.ndarray
            Weighted particle means ``(n, dim)``.
        cov : numpy.ndarray or None
            Weighted covariances ``(n, dim, dim)`` (NaN unless the model ``needs_cov``).
        """
        return None  # a model without feedback has no use for the estimate


class ReferenceFC(FusionCentreModel):
    """What the reference FC models (particles of the target's state) share: the initial law
    and transition of the scenario ``self.sc``, and the sensors' decisions that do not depend on
    the FC's broadcast.

    Attributes
    ----------
    sc : fusioncenter.censoring.scenarios.Scenario
        The scenario; its ``dynamics`` draw and propagate the particles.
    scheme : str
        The run's scheme.
    censor : bool
        Whether the scheme censors (CFoMD or CFwMD).
    N : int
        Number of sensors.
    sent : numpy.ndarray
        Who sent ``(n, T, N)``, bool (filled by the subclass and by :meth:`_fixed_decisions`).
    """

    def initial(self, rng, n, P):
        return self.sc.dynamics.initial(rng, n, P)

    def transition(self, rng, t, x):
        return self.sc.dynamics.transition(rng, t, x)

    def _fixed_decisions(self, feedback: str, l: float, sel_u: np.ndarray) -> None:
        """Fill ``self.sent`` where the decisions are known in advance: censoring without
        feedback (``self._local_decisions()``), random selection, all-send."""
        if self.censor and feedback == "none":
            self._local_decisions()
        elif self.scheme == "random":
            self.sent[:] = sel_u < l / self.N
        elif self.scheme == "all-send":
            self.sent[:] = True


class FeedbackModel(ReferenceFC):
    """The FC's feedback of a linear target (``self.sc.feedback_moments``): the predicted mean
    ``pred_mean (n, d)`` and covariance ``pred_cov (n, d, d)`` it broadcasts at every step.

    Attributes
    ----------
    pred_mean : numpy.ndarray
        The predicted state broadcast at the next step ``(n, d)``.
    pred_cov : numpy.ndarray
        Its covariance ``(n, d, d)`` (used by the sensors with ``feedback="state+cov"``).
    """

    def _first_prediction(self, n: int) -> None:
        """The broadcast of step 1: ``F x0`` and ``F P0 F^T + Q`` for every trial."""
        dyn = self.sc.dynamics
        self.pred_mean = np.broadcast_to(dyn.F @ dyn.m0, (n, dyn.dim)).copy()
        self.pred_cov = np.broadcast_to(dyn.F @ dyn.P0 @ dyn.F.T + dyn.Q,
                                        (n, dyn.dim, dyn.dim)).copy()

    def _cloud_moments(self, x: np.ndarray) -> None:
        """``feedback_moments="particles"``: broadcast the mean and covariance of the propagated
        particle cloud ``x (n, P, d)``."""
        if self.sc.feedback_moments == "particles":
            self.pred_mean = x.mean(axis=1)
            dev = x - self.pred_mean[:, None, :]
            self.pred_cov = np.swapaxes(dev, -1, -2) @ dev / x.shape[1]

    def observe(self, t: int, mean: np.ndarray, cov: np.ndarray | None) -> None:
        # feedback_moments="analytic": what is broadcast at t + 1, F mean and (if given) the
        # symmetrized F cov F^T + Q
        if self.sc.feedback_moments == "analytic":
            F, Q = self.sc.F, self.sc.Q
            self.pred_mean = mean @ F.T
            if cov is not None:
                pc = F @ cov @ F.T + Q
                self.pred_cov = 0.5 * (pc + np.swapaxes(pc, -1, -2))


class ExactModel(FusionCentreModel):
    """What the exact no-feedback filters share: a particle is ``(x_t, xhat^1_{t|t-1}, ...,
    xhat^N_{t|t-1})`` (``self.dim`` components, the state's first two), and a step where no
    particle of a trial is consistent with who sent is relaxed and recorded in
    ``self.relaxed (n, T)``.

    Attributes
    ----------
    sc : fusioncenter.censoring.scenarios.Scenario
        The scenario (a linear target).
    N : int
        Number of sensors.
    dim : int
        ``2 (N + 1)``: the state and every sensor's local prediction.
    relaxed : numpy.ndarray
        ``(n, T)``, bool: the trial-steps whose constraints were relaxed.
    needs_cov : bool
        ``False``: the loop skips the weighted covariance.
    """

    needs_cov = False

    def initial(self, rng, n, P):
        # the target's x_0 from the prior, and every sensor's local prediction F x0
        out = np.empty((n, P, self.dim))
        out[..., :2] = self.sc.dynamics.initial(rng, n, P)
        out[..., 2:] = np.tile(self.sc.F @ self.sc.dynamics.m0, self.N)
        return out

    def _consistent(self, full: np.ndarray, ok: np.ndarray, k: int) -> np.ndarray:
        """The log weights ``full (n, P)`` where ``ok`` (the particle explains who sent), ``-inf``
        elsewhere; a trial with no such particle keeps ``full`` (the constraint relaxed)."""
        w = np.where(ok, full, -np.inf)
        dead = ~ok.any(axis=1)
        if dead.any():  # no particle's local predictions explain who sent: relax the constraint
            w[dead] = full[dead]
            self.relaxed[dead, k] = True
        return w


def decisions_in_advance(scheme: str, feedback: str, l, sel_u: np.ndarray, shape: tuple,
                         local) -> np.ndarray:
    """The sensors' decisions ``sent (n, T, N)`` that do not depend on the FC's broadcast.

    Parameters
    ----------
    scheme, feedback : str
        The run's scheme and feedback (``"none"``, ``"state"``, ``"state+cov"``).
    l : float
        The target average number of sending sensors (random selection sends with ``l / N``).
    sel_u : numpy.ndarray
        ``(n, T, N)`` uniform draws of random selection.
    shape : tuple
        ``(n, T, N)``.
    local : callable
        No arguments; the censoring decisions of the sensors' own filters (no feedback).

    Returns
    -------
    numpy.ndarray
        Boolean ``(n, T, N)``: the local decisions for censoring without feedback, ``sel_u <
        l / N`` for random selection, all true for all-send, and all false for censoring with
        feedback (filled step by step by the fusion centre).
    """
    if scheme in ("cfomd", "cfwmd") and feedback == "none":
        return local()
    if scheme == "random":
        return sel_u < l / shape[-1]
    if scheme == "all-send":
        return np.ones(shape, dtype=bool)
    return np.zeros(shape, dtype=bool)


def silent_rows(fc, g, n_obs):
    """The trials of a block in which a sensor of the group ``g`` was silent, when the fusion
    centre ``fc`` uses silence in its likelihood (CFwMD with feedback); the step the linear and
    vector FCs share before they add the silent factor to the log weights.

    Parameters
    ----------
    fc : LinearFusionCentre or fusioncenter.censoring.vector_fusion.reference.VectorFC
        A fusion centre with ``scheme`` and ``fb`` (feedback in use).
    g : numpy.ndarray
        The sensors of one group (equal observation models).
    n_obs : numpy.ndarray
        Per trial, the number of the group's sensors received at this step ``(n,)``.

    Returns
    -------
    tuple of numpy.ndarray or None
        ``(n_sil, rows)``: ``len(g) - n_obs`` and the indices of its non-zero entries; ``None``
        when ``fc`` does not use silence or no trial has a silent sensor in ``g``.
    """
    if fc.scheme != "cfwmd" or not fc.fb:
        return None
    n_sil = len(g) - n_obs
    rows = np.flatnonzero(n_sil)
    return (n_sil, rows) if rows.size else None
