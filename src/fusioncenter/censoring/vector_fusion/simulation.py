"""The vector scenario's Monte Carlo run (``run``, zheng2014 Section V; Figs. 4-6, Table II):
the trials simulated and tracked by a fusion centre of
:mod:`~fusioncenter.censoring.vector_fusion.fused` or
:mod:`~fusioncenter.censoring.vector_fusion.reference`, through
:func:`fusioncenter.montecarlo.simulate`."""

from __future__ import annotations

import numpy as np

from fusioncenter import montecarlo, particle
from fusioncenter._validate import one_of as _one_of
from fusioncenter._validate import posint as _posint
from fusioncenter.censoring import probability as cprob
from fusioncenter.censoring import results
from fusioncenter.censoring.ellipse import PROBABILITIES
from fusioncenter.censoring.vector import VectorScenario
from fusioncenter.censoring.vector_fusion.fused import FusedVectorFC
from fusioncenter.censoring.vector_fusion.reference import VectorExactFC, VectorFC

#: How ``scheme="cfwmd"`` fuses without feedback: ``"exact"`` (particles carry the local
#: predictions) or Proposition 6 ``"printed"`` (equivalent to CFoMD, see
#: :mod:`fusioncenter.censoring.vector`).
LIKELIHOODS = ("exact", "printed")

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
    ``probability="table"`` :class:`~fusioncenter.censoring.vector_fusion.fused.FusedVectorFC`
    (interpolation tables, sub-blocks), otherwise
    :class:`~fusioncenter.censoring.vector_fusion.reference.VectorFC` /
    :class:`~fusioncenter.censoring.vector_fusion.reference.VectorExactFC` (quadrature or sampled
    probabilities).
    """
    rng_data, rng_pf, rng_q = rng.spawn(3)
    # the filter's stream: SFC64 from the same spawned seed sequence (its normal draws, the
    # largest single cost of the filter, are ~15 % cheaper than PCG64's)
    rng_pf = np.random.Generator(np.random.SFC64(rng_pf.bit_generator.seed_seq))
    x, z = scenario.sample(rng_data, n)
    sel_u = rng_data.random(z.shape[:-1])
    if probability == "table":
        fused = FusedVectorFC(scenario, scheme, feedback, likelihood, eta, l, z, sel_u)
        out = particle.run_filter(fused, rng_pf, n, n_particles, scenario.T,
                                  ess_threshold=ess_threshold)
        return results.trial_columns(out, x, fused.sent, n_particles, fused.relaxed)
    fc = VectorFC(scenario, scheme, feedback, eta, l, z, sel_u, probability, n_q, rng_q)
    model = fc
    if scheme == "cfwmd" and feedback == "none" and likelihood == "exact":
        model = VectorExactFC(scenario, eta, z, fc.sent, probability, n_q, rng_q)
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
    :func:`fusioncenter.censoring.paired_difference`): ``scheme`` in
    :data:`~fusioncenter.censoring.SCHEMES`, ``feedback`` in
    :data:`~fusioncenter.censoring.FEEDBACK` (``"state+cov"`` is the paper's CFwMD2), ``l`` the
    target average number of sending sensors, ``eta = threshold(l, N, dof=m)``. ``likelihood``
    selects how ``scheme="cfwmd"`` fuses without feedback: ``"exact"`` (default: particles of
    dimension ``2 (N + 1)`` carry the local predictions) or Proposition 6 ``"printed"`` (which
    equals CFoMD; ``"corrected"`` of the scalar library -- the received sensors' conditions kept
    under the law (21) -- is a ``2 N m``-dimensional integral per particle and raises
    ``ValueError`` for ``scheme="cfwmd"`` without feedback; like every value it is ignored by
    the other scheme and feedback combinations, so the scalar library's default can be passed
    through).
    ``probability`` (``"table"``, ``"quadrature"``, ``"sampled"`` with ``n_q`` draws per particle)
    selects how the silent factor is evaluated (see
    :data:`~fusioncenter.censoring.ellipse.PROBABILITIES`).

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
        One of :data:`~fusioncenter.censoring.ellipse.PROBABILITIES`.
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
