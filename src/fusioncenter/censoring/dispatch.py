"""The one dispatcher :func:`~fusioncenter.censoring.dispatch.run`: a linear, vector or nonlinear
scenario to its fusion centre."""

from __future__ import annotations

import numpy as np

from fusioncenter import montecarlo, particle
from fusioncenter._validate import one_of as _one_of
from fusioncenter._validate import posint as _posint
from fusioncenter.censoring import nonlinear, vector, vector_fusion
from fusioncenter.censoring.fusion import ExactFusionCentre, LinearFusionCentre, sub_blocks
from fusioncenter.censoring.probability import threshold
from fusioncenter.censoring.results import (
    CensoringResult,
    check_resampling,
    check_scheme,
    run_chunks,
    streams,
    trial_columns,
)
from fusioncenter.censoring.scenarios import LIKELIHOODS, LinearScenario


def _chunk(rng: np.random.Generator, n: int, *, scenario: LinearScenario, scheme: str,
           feedback: str, likelihood: str, eta: float, l: float, n_particles: int,
           ess_threshold: float) -> np.ndarray:
    """``chunk_fn`` for :func:`fusioncenter.montecarlo.simulate`: ``(n, T, d + 3)`` per trial.

    Columns: see :func:`trial_columns`. Two independent streams are spawned from ``rng``: the
    first draws the truth, the measurements and the random-selection uniforms (in that order, for
    every scheme: trials are paired across schemes), the second the filter's particles and
    resampling uniforms; the latter is an SFC64 generator seeded by the spawned seed sequence
    (its normal draws are 10-20 % cheaper than PCG64's here, and they are the largest single cost
    of the filter). :class:`LinearFusionCentre` runs through
    :func:`fusioncenter.particle.run_filter` sub-block by sub-block (:func:`sub_blocks`); the
    exact no-feedback filter :class:`ExactFusionCentre` on the whole block at once.
    """
    rng_data, rng_pf = streams(rng)
    x, z = scenario.sample(rng_data, n)
    sel_u = rng_data.random(z.shape)
    T = scenario.T
    if scheme == "cfwmd" and feedback == "none" and likelihood == "exact":
        fc = LinearFusionCentre(scenario, scheme, feedback, likelihood, eta, l, z, sel_u)
        model = ExactFusionCentre(scenario, eta, z, fc.sent)
        out = particle.run_filter(model, rng_pf, n, n_particles, T, ess_threshold=ess_threshold)
        return trial_columns(out, x, fc.sent, n_particles, model.relaxed)
    parts = []
    for R in sub_blocks(n, n_particles):
        fc = LinearFusionCentre(scenario, scheme, feedback, likelihood, eta, l, z[R], sel_u[R])
        out = particle.run_filter(fc, rng_pf, R.stop - R.start, n_particles, T,
                                  ess_threshold=ess_threshold)
        parts.append(trial_columns(out, x[R], fc.sent, n_particles))
    return np.concatenate(parts, axis=0)


def run(scenario: LinearScenario, scheme: str, *, l, n_trials: int, n_particles: int, seed: int,
        feedback: str = "state", likelihood: str = "corrected", ess_threshold: float = 1.0,
        chunk_size: int | None = None, executor=None, progress: bool = False,
        block_size: int = montecarlo.DEFAULT_BLOCK_SIZE) -> CensoringResult:
    """Simulate ``n_trials`` trials of ``scenario`` and track them with the FC's particle filter.

    ``scheme`` in :data:`SCHEMES`, ``feedback`` in :data:`FEEDBACK` (``"state+cov"`` is the
    paper's CFwMD2), ``l`` the target average number of sending sensors (``0 < l <= N``; sets
    ``eta = threshold(l, N)`` for the censoring schemes and ``p = l / N`` for random selection;
    ignored by all-send). ``likelihood`` selects how ``scheme="cfwmd"`` fuses with
    ``feedback="none"``: Proposition 3 ``"corrected"`` (``N <= 2``) or ``"printed"``, or the
    ``"exact"`` filter (particles of dimension ``2 (N + 1)``; about 10x the cost per particle). The
    filter resamples when ``ESS <= ess_threshold * n_particles`` (default: every step, as
    Algorithm 1).

    Runs through :func:`fusioncenter.montecarlo.simulate`: results are bitwise identical for any
    ``chunk_size`` and executor; trials are paired across schemes for the same ``seed``,
    ``n_trials`` and ``block_size``. Every scheme except the exact no-feedback filter runs
    :class:`LinearFusionCentre` through :func:`fusioncenter.particle.run_filter`, sub-block by
    sub-block: on the project's 2-core machine about 20 ns per particle and step for CFwMD
    with state feedback and 15 for all-send (CPU time, ``benchmarks/bench_particle_floor.py``),
    of which about 4-5 are the propagation with its normals drawn inline, 3-4 the silent factor
    and 4 the resampling; less for the schemes without a silent
    factor, more for CFwMD2 (two ``ndtr`` per particle) and for the corrected Proposition 3
    (bivariate normal probabilities). Peak memory of a task (tracemalloc): a few MiB for
    :class:`LinearFusionCentre` (it works on sub-blocks of about 32k particles: 5 MiB for the
    default 256 trials x 1000 particles), 340 bytes per particle of a block for the exact no-
    feedback filter (83 MiB), plus the per-trial results (``n_trials * T * 5 * 8`` bytes).

    A :class:`fusioncenter.censoring.vector.VectorScenario` or a
    :class:`fusioncenter.censoring.nonlinear.NonlinearScenario` is handed to the ``run`` of
    :mod:`fusioncenter.censoring.vector_fusion` or :mod:`fusioncenter.censoring.nonlinear`
    with the same arguments (Part IV(b)).

    Parameters
    ----------
    scenario : LinearScenario, VectorScenario or NonlinearScenario
        The model and its sizes.
    scheme : str
        One of :data:`SCHEMES`.
    l : float
        Target average number of sending sensors, ``0 < l <= N``.
    n_trials, n_particles : int
        Monte Carlo trials and particles per trial.
    seed : int
        Seed of the trials (the same seed pairs the trials of different schemes).
    feedback : str, optional
        One of :data:`FEEDBACK`.
    ess_threshold : float, optional
        Resample when ``ESS <= ess_threshold * n_particles``.
    chunk_size, executor, progress, block_size : optional
        How :func:`fusioncenter.montecarlo.simulate` splits and runs the trials (no effect on the
        numbers).
    likelihood : str, optional
        One of :data:`LIKELIHOODS` (used by ``scheme="cfwmd"`` with ``feedback="none"``).

    Returns
    -------
    CensoringResult
        Per-trial squared errors and transmissions, with RMSE curves and their standard errors.
    """
    for cls, fn in ((vector.VectorScenario, vector_fusion.run),
                    (nonlinear.NonlinearScenario, nonlinear.run)):
        if isinstance(scenario, cls):
            return fn(scenario, scheme, l=l, n_trials=n_trials, n_particles=n_particles,
                           seed=seed, feedback=feedback, likelihood=likelihood,
                           ess_threshold=ess_threshold, chunk_size=chunk_size,
                           executor=executor, progress=progress, block_size=block_size)
    if not isinstance(scenario, LinearScenario):
        raise ValueError("scenario must be a LinearScenario, VectorScenario or "
                         "NonlinearScenario")
    check_scheme(scheme, feedback)
    _one_of("likelihood", likelihood, LIKELIHOODS)
    eta = threshold(l, scenario.N)
    n_particles = _posint("n_particles", n_particles)
    if scheme == "cfwmd" and feedback == "none" and likelihood == "corrected" and scenario.N > 2:
        raise ValueError(f"likelihood='corrected' without feedback is implemented for N <= 2, "
                         f"got N = {scenario.N} (use likelihood='printed')")
    check_resampling(scenario, ess_threshold)
    return run_chunks(_chunk, scenario, scheme, feedback, likelihood, l=l, eta=eta,
                       n_particles=n_particles, ess_threshold=ess_threshold, n_trials=n_trials,
                       seed=seed, chunk_size=chunk_size, executor=executor, progress=progress,
                       block_size=block_size, chunk_kwargs={"likelihood": likelihood})
