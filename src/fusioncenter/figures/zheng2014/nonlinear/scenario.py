"""The nonlinear scenario of zheng2014 Section VII.C and the runs its entries share.

Every entry of :mod:`fusioncenter.figures.zheng2014.nonlinear` that filters is a
:func:`fusioncenter.censoring.nonlinear.run` of :data:`SCENARIO` with the same seed, trial
count, particle count and block size, so all runs of one profile and seed share the truth and
the measurements: schemes are compared by paired differences, and runs used by several entries
(Figs. 8 and 9 at ``l = 2``; Figs. 9 and 10 for CFwMD at ``l = 2, 4, 6``; Fig. 10 and Table III
entirely) are computed once and kept in :data:`_RUNS` (:func:`runs`). The blocks of 25 trials
of every missing run are spread over the execution context's executor
(:func:`fusioncenter.context.executor`: by default a process pool in the paper profile); the
results do not depend on it.

Also here: the run sizes (:data:`SIZES`, :func:`sizes`), the z-scores the claims need
(:func:`z_required`), a run's curves (:func:`curves`, :func:`stack_curves`) and the
registration of an entry with the scenario's parameters (:func:`entry`).
"""

from __future__ import annotations

import math

import numpy as np

from fusioncenter import censoring, context
from fusioncenter.censoring import nonlinear as cn
from fusioncenter.figures.common import document
from fusioncenter.figures.zheng2014.common import RAISES, add_entry, check_block, settable
from fusioncenter.profile import by_profile

CHAPTER = "book/zheng2014/nonlinear"
#: The scenario of Section VII.C (our choices for what the paper leaves open: see ``choices``).
SCENARIO = cn.NonlinearScenario()
#: Monte Carlo sizes: the paper's 200 trials and 10^4 particles; fast: seconds per entry.
SIZES = {"fast": {"trials": 40, "particles": 5000}, "paper": {"trials": 200, "particles": 10_000}}
#: Trials per independent random stream (part of the random-number design) and per task: at
#: 10^4 particles a block needs about 100 MB.
BLOCK = 25
#: z-score a paper's ordering claim must reach (paired Monte Carlo error) at paper scale.
Z_ORDER = 3.0
#: z-score for the weaker, time-resolved claims of Fig. 10, and for "not significantly worse".
Z_WEAK = 2.0
#: |z| within which a number counts as agreeing with the printed one.
Z_AGREE = 3.0


@document(returns=("float", "``z sqrt(min(1, trials / 200))``."), raises=(),
          z=("float", "The z-score required at 200 trials."), trials=("int", "The trials."))
def z_required(z: float, trials: int) -> float:
    """The z-score a claim needs with ``trials`` trials: ``z`` at the paper's 200 trials, and
    the same *effect size* (mean over per-trial standard deviation, ``z / sqrt(200)``) with
    fewer trials, ``z sqrt(trials / 200)``. The fast profile is a smoke test with a fifth of the
    trials; at paper scale every claim is checked at the full ``z``."""
    return z * math.sqrt(min(1.0, trials / SIZES["paper"]["trials"]))


#: The scenario's parameters, in every entry's ``parameters``.
PARAMS = {
    "N": 9, "region_m": 20.0, "P0_signal": 1e3, "alpha": 1.0, "n_exponent": 2.0, "r": 1.0,
    "sigma2": 0.1, "dt_s": 0.5, "T": 20, "x0_mean": [-8.0, 2.0, -8.0, 2.0],
    "x0_cov_diag": [9.0, 4.0, 9.0, 4.0],
    "trials": {p: s["trials"] for p, s in SIZES.items()},
    "particles": {p: s["particles"] for p, s in SIZES.items()},
    "block_size": BLOCK,
    "sensors_m": [list(p) for p in SCENARIO.sensors],
    "choices": SCENARIO.choices,
}


# ============================================================================ shared runs
#: ``(profile, seed, trials, particles, scheme, l, feedback) -> CensoringResult``, shared by the
#: entries.
_RUNS: dict[tuple, censoring.CensoringResult] = {}


def _run_one(scheme: str, l: float, feedback: str, n: int, P: int, seed: int, executor=None):
    """One run of :data:`SCENARIO`; with an executor its blocks are spread over the workers."""
    return cn.run(SCENARIO, scheme, l=l, n_trials=n, n_particles=P, seed=seed,
                  feedback=feedback, block_size=BLOCK, chunk_size=BLOCK, executor=executor)


def sizes(profile: str, over: dict) -> tuple[int, int]:
    """Trials and particles of a run (checked to fit: 400 bytes a particle in a block).

    Parameters
    ----------
    profile : str
        ``"fast"`` or ``"paper"`` (the default sizes of :data:`SIZES`).
    over : dict
        The overrides; ``trials`` and ``particles`` are read (``None`` or absent: the default).

    Returns
    -------
    n, P : int
        Trials and particles.

    Raises
    ------
    ValueError
        For an unknown ``profile`` when a default is read, or a block that would not fit.
    """
    n, P = (over.get(k) or by_profile(profile, **SIZES)[k] for k in ("trials", "particles"))
    return n, check_block(P, min(n, BLOCK), 400)


#: The overridable parameters of the filtering entries (Figs. 8-10, Table III).
SETTABLE = settable({p: s["trials"] for p, s in SIZES.items()},
                    {p: s["particles"] for p, s in SIZES.items()})


@document(returns=("dict", "``{spec: CensoringResult}``, in the order of ``specs``."),
          specs=("iterable of tuple", "``(scheme, l, feedback)`` of each run."), raises=RAISES,
          over="The sizes ``trials`` and ``particles`` (other keys are ignored).")
def runs(profile: str, seed: int, specs, **over) -> dict[tuple, censoring.CensoringResult]:
    """The runs ``(scheme, l, feedback)`` of ``specs`` for ``profile``, ``seed`` and the
    overrides ``over`` (trials, particles), computing only those not yet in :data:`_RUNS`, on
    the execution context's executor (one task per block of 25 trials, 8 per run at paper
    scale: every worker stays busy to the end)."""
    n, P = sizes(profile, over)
    specs = list(dict.fromkeys(specs))
    key = (profile, seed, n, P)
    todo = [s for s in specs if (*key, *s) not in _RUNS]
    ex = context.executor() if todo else None
    for s in todo:
        _RUNS[(*key, *s)] = _run_one(*s, n, P, seed, executor=ex)
    return {s: _RUNS[(*key, *s)] for s in specs}


def curves(res: censoring.CensoringResult) -> dict[str, np.ndarray]:
    """The position and velocity RMSE curves of a run, with their standard errors.

    Parameters
    ----------
    res : fusioncenter.censoring.CensoringResult
        A run.

    Returns
    -------
    dict
        ``rmse_position``, ``rmse_velocity`` and their ``_stderr``, each of shape (T,).
    """
    return {"rmse_position": res.rmse_position.value,
            "rmse_position_stderr": res.rmse_position.stderr,
            "rmse_velocity": res.rmse_velocity.value,
            "rmse_velocity_stderr": res.rmse_velocity.stderr}


def stack_curves(results, key: str) -> np.ndarray:
    """One curve of :func:`curves` for each run, stacked.

    Parameters
    ----------
    results : list of fusioncenter.censoring.CensoringResult
        The runs.
    key : str
        A key of :func:`curves`.

    Returns
    -------
    numpy.ndarray, shape (len(results), T)
    """
    return np.stack([curves(r)[key] for r in results])


def size_info(profile: str, seed: int, **over) -> dict:
    """The run sizes at the head of the filtering entries' data (:data:`SIZE_KEYS`).

    Parameters
    ----------
    profile : str
        ``"fast"`` or ``"paper"``.
    seed : int
        The seed of the runs.
    **over
        The overrides (``trials``, ``particles``).

    Returns
    -------
    dict
        ``profile``, ``seed``, ``trials``, ``particles``, ``block_size``.
    """
    n, P = sizes(profile, over)
    return {"profile": profile, "seed": seed, "trials": n, "particles": P, "block_size": BLOCK}


#: The run sizes at the head of the filtering entries' data (for their docstrings).
SIZE_KEYS = "``profile``, ``seed``, ``trials``, ``particles``, ``block_size`` (the run sizes); "


def spec(scheme: str, l: float, feedback: str = "state") -> tuple:
    """The key of a run in :func:`runs` (all-send always at ``l = N``).

    Parameters
    ----------
    scheme : str
        ``"all-send"``, ``"random"``, ``"cfomd"`` or ``"cfwmd"``.
    l : float
        The target number of transmissions per step.
    feedback : str, default "state"
        ``"state"`` (Proposition 7) or ``"state+cov"`` (Proposition 8).

    Returns
    -------
    tuple
        ``(scheme, l, feedback)``.
    """
    return (scheme, float(SCENARIO.N if scheme == "all-send" else l), feedback)


#: What every entry's note starts with (the scenario's unstated choices).
NOTE_SCENARIO = (
    "Scenario: the paper's parameters; sensors at the centres of the 3 × 3 cells of "
    "[−10, 10]² m and the true trajectory starting at x₀ = (−8, 2, −8, 2) in every trial (the "
    "filters' prior N(x₀, diag(9, 4, 9, 4))): neither is stated in the paper. ")


def entry(entry_id: str, kind: str, status: str, functions: tuple, parameters: dict,
          caption: str, note: str, settable=SETTABLE, **extra) -> None:
    """Register an entry of this chapter: the scenario's parameters and note, and those given.

    Parameters
    ----------
    entry_id, kind, status : str
        The entry's id, ``"figure"`` or ``"table"``, and its status.
    functions : tuple
        ``(compute, plot, checks)``.
    parameters : dict
        The entry's own parameters (added to :data:`PARAMS`).
    caption, note : str
        The caption, and the note (after the scenario's).
    settable : tuple of fusioncenter.context.Parameter, default SETTABLE
        The overridable parameters.
    **extra
        Further fields of :class:`fusioncenter.figures.registry.Entry` (``reason``, ...).
    """
    add_entry(entry_id, kind, status, functions, chapter=CHAPTER, settable=settable, **extra,
              parameters={**PARAMS, **parameters}, caption=caption, note=NOTE_SCENARIO + note)
