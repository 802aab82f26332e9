"""What the registry entries of Part IV share (zheng2014, Sections VII.A-D): runs and their
curves.

The scalar entries (:mod:`fusioncenter.figures.zheng2014.linear`,
:mod:`fusioncenter.figures.zheng2014.no_feedback`,
:mod:`fusioncenter.figures.zheng2014.choices`), the vector ones
(:mod:`fusioncenter.figures.zheng2014.vector`) and the nonlinear ones
(:mod:`fusioncenter.figures.zheng2014.nonlinear`) use these pieces:

* the schemes, their labels and the z-scores of the claims (:data:`SCHEMES`, :data:`LABELS`,
  :data:`Z_ORDER`, :data:`Z_TOL`);
* the settable parameters (:func:`settable`) and the run sizes they give (:func:`run_size`,
  :func:`check_block`);
* a run (:func:`run_scheme`, :func:`subset`) and its data as curves (:func:`curves`,
  :func:`stacked`);
* the registration (:func:`add_entry`).

How the entries compare the runs (paired differences, the data and claims of the figure groups)
is in :mod:`fusioncenter.figures.zheng2014.comparisons`; how they draw them in
:mod:`fusioncenter.figures.zheng2014.panels`.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from fusioncenter import censoring as cs
from fusioncenter import montecarlo
from fusioncenter.context import Parameter
from fusioncenter.figures.registry import Entry, register
from fusioncenter.profile import by_profile

#: The four schemes of Figs. 1, 4 and 8, in the order of their curves.
SCHEMES = ("all-send", "random", "cfomd", "cfwmd")
#: Legend labels of the schemes and of the variants of CFwMD (scalar observations).
LABELS = {"all-send": "all-send", "random": "random selection", "cfomd": "CFoMD",
          "cfwmd": "CFwMD", "cfwmd2": "CFwMD2", "printed": "CFwMD, Prop. 3 as printed",
          "corrected": "CFwMD, Prop. 3 corrected", "exact": "CFwMD, exact filter"}
#: A paired difference counts as an ordering when it exceeds Z_ORDER standard errors.
Z_ORDER = 4.0
#: Agreement of a Monte Carlo estimate with a printed value: |z| < Z_TOL, with the standard
#: error of the difference taken as sqrt(2) times ours (the paper's own Monte Carlo error, from
#: the same number of trials, is assumed equal to ours; it is not stated).
Z_TOL = 4.0
#: The ``Raises`` section of the entries' compute functions (``compute_doc(..., raises=RAISES)``):
#: they read ``over`` with ``dict.get``; its keys and values are checked by
#: :meth:`fusioncenter.figures.registry.Entry.run_compute`.
RAISES = (("ValueError", "For a ``profile`` other than ``\"fast\"`` and ``\"paper\"`` when a "
           "default size is read from it. Called directly, an unknown key of ``over`` is "
           "ignored."),)


def settable(trials: dict, particles: dict, *, N: int | None = None,
             l: float | None = None) -> tuple[Parameter, ...]:
    """The overridable parameters of an entry.

    Parameters
    ----------
    trials, particles : dict
        The profile defaults (``{"fast": ..., "paper": ...}``) of the Monte Carlo trials and
        of the particles of the fusion centre's filter (accuracy only).
    N : int, optional
        If given, the number of sensors is settable, with this default (the paper's setting:
        ``model=True``).
    l : float, optional
        If given, the target number of transmissions per step is settable (``model=True``).

    Returns
    -------
    tuple of Parameter
        ``trials``, ``particles``, then ``N`` and ``l`` if given.
    """
    out = [Parameter("trials", "int", "Monte Carlo trials", dict(trials), minimum=2),
           Parameter("particles", "int", "particles of the fusion centre's filter",
                     dict(particles), minimum=10)]
    if N is not None:
        out.append(Parameter("N", "int", "number of sensors (the paper's scalar sensors, "
                             "h = (1, 0), r = 1)", N, minimum=1, maximum=64, model=True))
    if l is not None:
        out.append(Parameter("l", "float", "target number of transmissions per step", l,
                             minimum=0.0, exclusive_minimum=True,
                             at_most="N" if N is not None else None, model=True))
    return tuple(out)


def run_size(profile: str, trials: dict, particles: dict, over: dict) -> tuple[int, int]:
    """Trials and particles of a run.

    Parameters
    ----------
    profile : str
        ``fast`` or ``paper``.
    trials, particles : dict
        The profile defaults.
    over : dict
        The overrides of the run (keys ``trials`` and ``particles`` win if present).

    Returns
    -------
    tuple of int
        ``(trials, particles)``.

    Raises
    ------
    ValueError
        If one block of trials of the particle filter would need more memory than the
        machine has (the message names ``particles`` and gives the estimate); the memory of
        the trials' results is checked by :func:`fusioncenter.montecarlo.simulate`.
    """
    n = over.get("trials") or by_profile(profile, **trials)
    P = over.get("particles") or by_profile(profile, **particles)
    check_block(P, min(n, montecarlo.DEFAULT_BLOCK_SIZE))
    return n, P


def check_block(P: int, block: int, per_particle: int = 0) -> int:
    """Check that a block of the particle filter fits in memory.

    Parameters
    ----------
    P, block, per_particle : int
        Particles, trials of a block, bytes a particle and trial (0: :data:`PARTICLE_BYTES`).

    Returns
    -------
    int
        ``P``; a ``ValueError`` naming ``particles`` with the estimate if it does not fit.
    """
    montecarlo.check_memory("particles", P, block * P * (per_particle or PARTICLE_BYTES),
                            f"the particle filter's arrays for a block of {block} trials")
    return P


#: Bytes the particle filter holds per particle and trial of a block, about (states, their
#: copy and noise for resampling and prediction, ancestors, weights: ten doubles).
PARTICLE_BYTES = 80


def run_scheme(sc, scheme: str, *, feedback: str, l: float, n: int, P: int, seed: int,
               likelihood: str = "corrected", executor=None,
               chunk_size: int | None = None) -> cs.CensoringResult:
    """One run of an entry: :func:`fusioncenter.censoring.run` under short names.

    Parameters
    ----------
    sc : LinearScenario or VectorScenario
        The scenario (a vector one is handed to the vector filter).
    scheme, feedback, l, likelihood, executor, chunk_size
        As in :func:`fusioncenter.censoring.run`.
    n, P : int
        Trials and particles.
    seed : int
        The seed (the same for every run of an entry: its runs share their trials).

    Returns
    -------
    CensoringResult
    """
    return cs.run(sc, scheme, l=l, n_trials=n, n_particles=P, seed=seed, feedback=feedback,
                  likelihood=likelihood, executor=executor, chunk_size=chunk_size)


def subset(res: cs.CensoringResult, n: int) -> cs.CensoringResult:
    """The first ``n`` trials of a run (whole blocks: the same trials as a run of ``n``).

    Parameters
    ----------
    res : CensoringResult
        A run.
    n : int
        The number of trials kept: ``res``'s own, or a multiple of its block size.

    Returns
    -------
    CensoringResult
        ``res`` itself if ``n`` is its number of trials, else a copy with the first ``n``.
    """
    if n == res.mc.n_trials:
        return res
    if n % res.mc.block_size:
        raise ValueError(f"n must be a multiple of the block size {res.mc.block_size}, got {n}")
    mc = montecarlo.MonteCarloResult(samples=res.mc.samples[:n], seed=res.mc.seed,
                                     block_size=res.mc.block_size)
    return dataclasses.replace(res, mc=mc)


def curves(res: cs.CensoringResult) -> dict:
    """The summaries of one run, under short keys.

    Parameters
    ----------
    res : CensoringResult
        A run.

    Returns
    -------
    dict
        ``rp, rpe, rv, rve`` (position and velocity RMSE against time, with stderrs), ``tp,
        tpe, tv, tve`` (their time averages), ``tr, tre`` (transmissions per step) and ``col``
        (collapsed steps).
    """
    p, v = res.rmse_position, res.rmse_velocity
    tp, tpe = res.time_averaged_rmse("position")
    tv, tve = res.time_averaged_rmse("velocity")
    tr, tre = res.average_transmissions
    return {"rp": p.value, "rpe": p.stderr, "rv": v.value, "rve": v.stderr, "tp": tp,
            "tpe": tpe, "tv": tv, "tve": tve, "tr": tr, "tre": tre, "col": res.collapsed}


def stack(cur: list[dict], key: str) -> np.ndarray:
    """One row per run.

    Parameters
    ----------
    cur : list of dict
        The :func:`curves` of several runs.
    key : str
        One of their keys.

    Returns
    -------
    numpy.ndarray
        The values of ``key``, stacked along a first axis.
    """
    return np.array([c[key] for c in cur])


def stacked(cur: list[dict], *, velocity_average: bool = True) -> dict:
    """The curves of several runs as data keys, one row per run.

    Parameters
    ----------
    cur : list of dict
        The :func:`curves` of the runs.
    velocity_average : bool
        Whether to include the time-averaged velocity RMSE.

    Returns
    -------
    dict
        ``rmse_position``, ``rmse_velocity`` (against time), ``tavg_position`` (and
        ``tavg_velocity``), ``transmissions``, each with its ``_stderr``.
    """
    out = {"rmse_position": stack(cur, "rp"), "rmse_position_stderr": stack(cur, "rpe"),
           "rmse_velocity": stack(cur, "rv"), "rmse_velocity_stderr": stack(cur, "rve"),
           "tavg_position": stack(cur, "tp"), "tavg_position_stderr": stack(cur, "tpe")}
    if velocity_average:
        out |= {"tavg_velocity": stack(cur, "tv"), "tavg_velocity_stderr": stack(cur, "tve")}
    return out | {"transmissions": stack(cur, "tr"), "transmissions_stderr": stack(cur, "tre")}




def add_entry(entry_id: str, kind: str, status: str, functions: tuple, **fields) -> Entry:
    """Register an entry of zheng2014, labelled ``sec-<id>`` in its chapter.

    Parameters
    ----------
    entry_id : str
        The id (``zheng2014-...``).
    kind : str
        ``figure`` or ``table``.
    status : str
        ``reproduced`` or ``differs``.
    functions : tuple
        ``(compute, plot, checks)``.
    **fields
        The other fields of :class:`~fusioncenter.figures.registry.Entry` (``caption``,
        ``chapter``, ``parameters``, ``settable``, ``note``, ...).

    Returns
    -------
    Entry
        The registered entry.
    """
    compute, plot, checks = functions
    return register(Entry(id=entry_id, paper="zheng2014", kind=kind, label=f"sec-{entry_id}",
                          compute=compute, plot=plot, checks=checks, status=status, **fields))
