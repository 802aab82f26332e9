"""The result of a censoring run (:class:`CensoringResult`), the per-trial columns a fusion centre
reports (:func:`trial_columns`), and the Monte Carlo plumbing every ``run`` shares
(:func:`run_chunks`, :func:`streams`, the argument checks)."""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from fusioncenter import montecarlo, particle
from fusioncenter._validate import one_of as _one_of
from fusioncenter.censoring.scenarios import FEEDBACK, SCHEMES, LinearScenario


def streams(rng: np.random.Generator) -> tuple[np.random.Generator, np.random.Generator]:
    """The two streams of a block: ``(data, particle filter)`` (see :func:`_chunk`).

    Parameters
    ----------
    rng : numpy.random.Generator
        The block's generator (from :func:`fusioncenter.montecarlo.simulate`).

    Returns
    -------
    tuple of numpy.random.Generator
        The data stream (PCG64) and the particle filter's (SFC64).
    """
    rng_data, rng_pf = rng.spawn(2)
    return rng_data, np.random.Generator(np.random.SFC64(rng_pf.bit_generator.seed_seq))


def trial_columns(out: particle.FilterOutput, x_true: np.ndarray, sent: np.ndarray,
                  n_particles: int, relaxed: np.ndarray | None = None) -> np.ndarray:
    """The per-trial columns of a :class:`CensoringResult` from a filter's output.

    Parameters
    ----------
    out : fusioncenter.particle.FilterOutput
        The filter's output for ``n`` trials and ``T`` steps.
    x_true : numpy.ndarray
        True states ``(n, T + 1, d')``; the first two components are compared with the estimate.
    sent : numpy.ndarray
        Who sent, bool ``(n, T, N)`` (or ``(n, T, N)`` of a vector scenario).
    n_particles : int
        Particles per trial (to express the ESS as a fraction).
    relaxed : numpy.ndarray, optional
        Bool ``(n, T)``: steps whose constraints an exact filter relaxed (counted as collapsed).

    Returns
    -------
    numpy.ndarray
        ``(n, T, 5)``: squared error of the two state components, number of sensors that sent,
        ESS / ``n_particles``, 1 if the weights collapsed.
    """
    sq = (out.mean[..., :2] - x_true[:, 1:, :2]) ** 2
    collapsed = out.collapsed if relaxed is None else out.collapsed | relaxed
    n_sent = sent.reshape(*sent.shape[:2], -1).sum(axis=-1)
    return np.concatenate([sq, n_sent[..., None].astype(float),
                           out.ess[..., None] / n_particles,
                           collapsed[..., None].astype(float)], axis=-1)


# ----------------------------------------------------------------------------- results
class Curve(NamedTuple):
    """A per-step estimate and its Monte Carlo standard error, both ``(T,)``.

    Parameters
    ----------
    value, stderr : numpy.ndarray
        The estimate and its standard error ``(T,)``.
    """

    value: np.ndarray
    stderr: np.ndarray


@dataclass(frozen=True)
class CensoringResult:
    """Output of :func:`run`. ``mc.samples`` keeps every trial: ``(n_trials, T, d + 3)``.

    Parameters
    ----------
    scenario : LinearScenario, VectorScenario or NonlinearScenario
        The scenario that was run.
    scheme, feedback, likelihood : str
        The run's choices.
    l, eta : float
        Target number of senders and the threshold it gives.
    n_particles : int
        Particles per trial.
    mc : fusioncenter.montecarlo.MonteCarloResult
        The per-trial samples.
    """

    scenario: LinearScenario
    scheme: str
    feedback: str
    likelihood: str
    l: float
    eta: float
    n_particles: int
    mc: montecarlo.MonteCarloResult = field(repr=False)

    @property
    def time(self) -> np.ndarray:
        return np.arange(1, self.scenario.T + 1)

    def _sq(self, component: str) -> np.ndarray:
        idx = {"position": self.scenario.position_index,
               "velocity": self.scenario.velocity_index}.get(component)
        if idx is None:
            raise ValueError(f"component must be 'position' or 'velocity', got {component!r}")
        return self.mc.samples[..., list(idx)].sum(axis=-1)  # (n, T)

    def rmse(self, component: str) -> Curve:
        """RMSE per step ``sqrt(mean_trials squared error)``; stderr by the delta method
        ``stderr(MSE) / (2 RMSE)``.

        Parameters
        ----------
        component : {"position", "velocity"}
            Whose squared errors (summed over the scenario's position or velocity components).

        Returns
        -------
        Curve
            The RMSE per step ``(T,)`` and its standard error.
        """
        sq = self._sq(component)
        mse = sq.mean(axis=0)
        se = sq.std(axis=0, ddof=1) / math.sqrt(sq.shape[0]) if sq.shape[0] > 1 \
            else np.full(mse.shape, np.nan)
        rm = np.sqrt(mse)
        with np.errstate(divide="ignore", invalid="ignore"):
            return Curve(rm, np.where(rm > 0, se / (2 * rm), 0.0))

    @property
    def rmse_position(self) -> Curve:
        return self.rmse("position")

    @property
    def rmse_velocity(self) -> Curve:
        return self.rmse("velocity")

    def _col(self, j: int) -> Curve:
        d = self.scenario.d
        return Curve(self.mc.mean[:, d + j], self.mc.stderr[:, d + j])

    @property
    def transmissions(self) -> Curve:
        """Mean number of sensors that sent, per step."""
        return self._col(0)

    @property
    def average_transmissions(self) -> tuple[float, float]:
        """Transmissions per step averaged over time and trials (Table I), with its stderr
        (computed from the per-trial time averages)."""
        per = self.mc.samples[..., self.scenario.d].mean(axis=1)
        se = per.std(ddof=1) / math.sqrt(per.size) if per.size > 1 else math.nan
        return float(per.mean()), float(se)

    @property
    def ess(self) -> Curve:
        """Mean effective sample size after weighting, as a fraction of the particles."""
        return self._col(1)

    @property
    def collapsed(self) -> int:
        """Number of (trial, step) pairs where no particle was compatible with the data (all
        weights zero: the step's data were ignored; for the exact no-feedback filter: the received
        sensors' constraints were relaxed for that step)."""
        return int(self.mc.samples[..., self.scenario.d + 2].sum())

    def time_averaged_rmse(self, component: str = "position") -> tuple[float, float]:
        """``mean_t RMSE_t`` with its stderr (delta method over trials).

        Parameters
        ----------
        component : str, optional
            ``"position"`` or ``"velocity"``.

        Returns
        -------
        tuple of float
            ``(value, stderr)``.
        """
        value, infl = tavg_influence(self, component)
        se = infl.std(ddof=1) / math.sqrt(infl.size) if infl.size > 1 else math.nan
        return value, float(se)


def tavg_influence(res: CensoringResult, component: str):
    """The time-averaged RMSE of a run and each trial's influence on it.

    Parameters
    ----------
    res : CensoringResult
        A run.
    component : str
        ``"position"`` or ``"velocity"``.

    Returns
    -------
    tuple
        The time-averaged RMSE (float) and the per-trial influence values
        ``sum_t sq_t / (2 T RMSE_t)`` ``(n_trials,)`` (delta method).
    """
    sq = res._sq(component)
    rm = np.sqrt(sq.mean(axis=0))
    with np.errstate(divide="ignore", invalid="ignore"):
        infl = np.where(rm > 0, sq / (2 * rm), 0.0).mean(axis=1)
    return float(rm.mean()), infl


def paired_difference(a: CensoringResult, b: CensoringResult,
                      component: str = "position") -> tuple[float, float]:
    """Time-averaged RMSE of ``a`` minus that of ``b``, with its paired standard error.

    ``a`` and ``b`` must come from the same scenario, seed, ``n_trials`` and ``block_size``: then
    their trials share the truth and the measurements (see :func:`_chunk`), and the per-trial
    influence values ``sum_t sq_t / (2 T RMSE_t)`` of the two runs are differenced trial by
    trial (delta method), which removes most of the common Monte Carlo noise.

    Parameters
    ----------
    a, b : CensoringResult
        Two paired runs.
    component : str, optional
        ``"position"`` or ``"velocity"``.

    Returns
    -------
    tuple of float
        The difference of the time-averaged RMSEs and its standard error.
    """
    if (a.scenario != b.scenario or a.mc.seed != b.mc.seed or a.mc.n_trials != b.mc.n_trials
            or a.mc.block_size != b.mc.block_size):
        raise ValueError("a and b must share scenario, seed, n_trials and block_size to be paired")
    va, ia = tavg_influence(a, component)
    vb, ib = tavg_influence(b, component)
    diff = ia - ib
    se = diff.std(ddof=1) / math.sqrt(diff.size) if diff.size > 1 else math.nan
    return va - vb, float(se)


# ----------------------------------------------------------------------------- run
def check_scheme(scheme: str, feedback: str) -> None:
    """Check a run's ``scheme`` and ``feedback``.

    Parameters
    ----------
    scheme, feedback : str
        Must be in :data:`~fusioncenter.censoring.scenarios.SCHEMES` and
        :data:`~fusioncenter.censoring.scenarios.FEEDBACK`.

    Returns
    -------
    None
        Raises ``ValueError`` naming the parameter otherwise.
    """
    _one_of("scheme", scheme, SCHEMES)
    _one_of("feedback", feedback, FEEDBACK)


def check_resampling(scenario, ess_threshold: float) -> None:
    """Check that the cloud-moment feedback has a resampled cloud to use.

    Parameters
    ----------
    scenario : Scenario
        Its ``feedback_moments``.
    ess_threshold : float
        The run's resampling threshold.

    Returns
    -------
    None
        Raises ``ValueError`` if ``feedback_moments="particles"`` without resampling at every
        step.
    """
    if scenario.feedback_moments == "particles" and ess_threshold < 1.0:
        raise ValueError("feedback_moments='particles' needs resampling at every step "
                         "(ess_threshold=1.0)")


def run_chunks(chunk, scenario, scheme: str, feedback: str, likelihood: str, *, l, eta: float,
                n_particles: int, ess_threshold: float, n_trials: int, seed: int,
                chunk_size: int | None, executor, progress: bool, block_size: int,
                chunk_kwargs: dict) -> CensoringResult:
    """The trials of a ``run`` (arguments checked): ``chunk`` (the module's ``_chunk``, given
    also ``chunk_kwargs``) through :func:`fusioncenter.montecarlo.simulate`, as a
    :class:`CensoringResult`.

    Parameters
    ----------
    chunk : callable
        The module's ``chunk_fn`` for :func:`fusioncenter.montecarlo.simulate`.
    scenario, scheme, feedback, likelihood
        As in :func:`fusioncenter.censoring.run` (already checked).
    l, eta, n_particles, ess_threshold, n_trials, seed, chunk_size, executor, progress, block_size
        As in :func:`fusioncenter.censoring.run`; ``eta`` the threshold for ``l``.
    chunk_kwargs : dict
        Further keyword arguments of ``chunk``.

    Returns
    -------
    CensoringResult
        The result of the run.
    """
    fn = functools.partial(chunk, scenario=scenario, scheme=scheme, feedback=feedback, eta=eta,
                           l=float(l), n_particles=n_particles,
                           ess_threshold=float(ess_threshold), **chunk_kwargs)
    mc = montecarlo.simulate(fn, n_trials, seed, chunk_size=chunk_size, executor=executor,
                             progress=progress, block_size=block_size)
    return CensoringResult(scenario=scenario, scheme=scheme, feedback=feedback,
                           likelihood=likelihood, l=float(l), eta=eta, n_particles=n_particles,
                           mc=mc)
