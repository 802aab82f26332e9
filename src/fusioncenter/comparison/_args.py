"""The arguments of :mod:`fusioncenter.comparison`: one glossary of their descriptions (the
numpydoc sections of every function of the package) and the checks they share (each raises
``ValueError`` naming the argument)."""

from __future__ import annotations

import numpy as np

from fusioncenter import censoring
from fusioncenter._docstrings import Glossary
from fusioncenter._validate import finite as _finite

#: How the FC reads a missing packet (see :mod:`fusioncenter.comparison`).
RECEIVERS = ("csi", "naive")

#: The arguments of the package's functions, by name.
doc = Glossary("""
scenario : fusioncenter.censoring.LinearScenario
    The tracking problem.
rng : numpy.random.Generator
    The block's generator (spawned as :func:`~fusioncenter.comparison.link.draw` says).
n : int
    Trials of the block.
channel : Rayleigh, optional
    The law of the power gains (default ``Rayleigh(1)``, mean gain 1).
z : array_like
    Measurements ``(n, T, N)``.
xi : array_like
    Uniforms in ``[0, 1]`` ``(n, T, N)``, used as in :class:`~fusioncenter.comparison.link.Draw`.
lost : array_like
    Boolean ``(n, T, N)``: the channel was in outage (a packet sent then is not decoded).
scheme : str
    One of :data:`~fusioncenter.comparison.kalman_family.KF_SCHEMES`.
delta : float or array_like, optional
    ``"stochastic"`` only: the trigger parameter, ``> 0``, shared or one per sensor.
p : float or array_like, optional
    ``"random"`` only: the send probability in ``[0, 1]``, shared or one per sensor.
outage : float
    Outage probability of every packet, in ``[0, 1)``.
receiver : str
    How the FC reads a missing packet, one of ``RECEIVERS`` (``"csi"``, ``"naive"``).
runs : sequence of KFRun
    The configurations (:class:`~fusioncenter.comparison.kalman_family.KFRun`), run on the
    same trials.
l : float
    Average number of sensors sending per step (sets ``eta = censoring.threshold(l, N)``).
n_trials : int
    Number of Monte Carlo trials.
n_particles : int
    Particles per trial, ``>= 1``.
seed : int
    Non-negative seed; with ``n_trials`` and ``block_size`` it fixes the trials.
component : {"position", "velocity", "state"}, default "position"
    The error of the position, of the velocity, or of the whole state (their sum).
column : {"sent", "arrived"}, default "sent"
    Count the sensors that sent, or those whose packet arrived.
other : Summary
    A summary of another scheme on the same trials
    (:meth:`~fusioncenter.montecarlo.PerTrial.same_trials`).
block_size, executor, chunk_size
    As in :func:`fusioncenter.montecarlo.simulate`.
""", raises="""
ValueError
    If an argument is invalid (the message names it).
""")


def check_scenario(scenario) -> censoring.LinearScenario:
    """``scenario``, if it is a :class:`fusioncenter.censoring.LinearScenario`."""
    if not isinstance(scenario, censoring.LinearScenario):
        raise ValueError("scenario must be a fusioncenter.censoring.LinearScenario")
    return scenario


def check_outage(outage) -> float:
    """``outage`` as a float, if it is a probability in ``[0, 1)``."""
    try:
        ok = not isinstance(outage, bool | str | bytes) and 0.0 <= float(outage) < 1.0
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise ValueError(f"outage must be a probability in [0, 1), got {outage!r}")
    return float(outage)


def check_receiver(receiver: str) -> str:
    """``receiver``, if it is one of :data:`RECEIVERS`."""
    if receiver not in RECEIVERS:
        raise ValueError(f"receiver must be one of {RECEIVERS}, got {receiver!r}")
    return receiver


def per_sensor(name: str, value, N: int) -> np.ndarray:
    """``value`` as ``N`` finite floats: one per sensor, or a scalar repeated."""
    arr = _finite(name, value)
    if arr.ndim == 0:
        arr = np.full(N, float(arr))
    if arr.shape != (N,) or not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be a finite scalar or one value per sensor ({N},), "
                         f"got {value!r}")
    return arr
