"""The runs of the scalar zheng2014 entries, kept for the life of the process.

Several entries of :mod:`fusioncenter.figures.zheng2014.linear` and
:mod:`fusioncenter.figures.zheng2014.choices` need the same run: Fig. 3's all-send and random
selection are Fig. 1's (the linear fusion centre's all-send and random selection do not use what
is fed back), and the "as chosen" row of ``zheng2014-table1-choices`` is the first trials of
Fig. 2's runs. :func:`kept_run` runs a scheme once per process and hands the run (or its first
trials) to every entry that asks for it again.

A run is identified by everything that fixes its numbers: the scenario (all its fields), the
scheme, what is fed back (where it matters), ``l``, the likelihood, the particles and the seed,
and the trials. A request for ``n`` trials is met by a kept run of more trials when ``n`` is a
multiple of the block size (:data:`fusioncenter.montecarlo.DEFAULT_BLOCK_SIZE`): its first ``n``
trials are then those of a run of ``n`` (:func:`~fusioncenter.figures.zheng2014.common.subset`).
The executor and the chunking are not part of the identity: they do not change the numbers. In a
fresh process nothing is kept, and every run is computed.
"""

from __future__ import annotations

import dataclasses
from collections import OrderedDict

from fusioncenter import censoring as cs
from fusioncenter import montecarlo
from fusioncenter.figures.zheng2014.common import run_scheme, subset

#: The most runs kept (the least recently used is dropped first). A paper-profile run of the
#: scalar entries holds about 4 MB (5000 trials x 20 steps x 5 columns); the five entries of
#: ``book/zheng2014/results`` make 48 distinct runs.
MAX_RUNS = 64

_KEPT: OrderedDict = OrderedDict()

#: The schemes whose linear fusion centre does not use the feedback (their decisions are known
#: in advance and their likelihood has no silent factor).
_NO_FEEDBACK_USE = ("all-send", "random")


def _identity(sc: cs.LinearScenario, scheme: str, feedback: str, l: float, likelihood: str,
              P: int, seed: int) -> tuple:
    if scheme in _NO_FEEDBACK_USE:
        feedback = "none"
    return (sc, scheme, feedback, float(l), likelihood, int(P), int(seed))


def kept_run(sc: cs.LinearScenario, scheme: str, *, feedback: str, l: float, n: int, P: int,
             seed: int, likelihood: str = "corrected", executor=None) -> cs.CensoringResult:
    """:func:`~fusioncenter.figures.zheng2014.common.run_scheme`, run once per process.

    Parameters
    ----------
    sc : LinearScenario
        The scenario (scalar observations).
    scheme, feedback, l, likelihood, executor
        As in :func:`fusioncenter.censoring.run`.
    n, P : int
        Trials and particles.
    seed : int
        The seed.

    Returns
    -------
    CensoringResult
        The same numbers as ``run_scheme(sc, scheme, ...)`` with these arguments, taken from a
        run kept in this process when there is one (see the module docstring); its
        ``feedback`` is the one asked for.

    Raises
    ------
    ValueError
        If ``sc`` is not a :class:`~fusioncenter.censoring.scenarios.LinearScenario` (and as
        :func:`fusioncenter.censoring.run` for bad arguments).
    """
    if not isinstance(sc, cs.LinearScenario):
        raise ValueError(f"sc must be a LinearScenario, got {type(sc).__name__}")
    ident = _identity(sc, scheme, feedback, l, likelihood, P, seed)
    found = None
    for key in _KEPT:
        m = key[1]
        if key[0] == ident and (m == n or (m > n and n % montecarlo.DEFAULT_BLOCK_SIZE == 0)):
            found = key
            break
    if found is None:
        res = run_scheme(sc, scheme, feedback=feedback, l=l, n=n, P=P, seed=seed,
                         likelihood=likelihood, executor=executor)
        _KEPT[(ident, n)] = res
        while len(_KEPT) > MAX_RUNS:
            _KEPT.popitem(last=False)
    else:
        _KEPT.move_to_end(found)
        res = subset(_KEPT[found], n)
    if res.feedback != feedback:
        res = dataclasses.replace(res, feedback=feedback)
    return res


def forget_runs() -> None:
    """Drop every kept run (the next requests compute again).

    Returns
    -------
    None
    """
    _KEPT.clear()
