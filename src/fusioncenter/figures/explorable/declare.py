"""How a part declares its explorable figure: one call registers the entry and its slider.

Each module of :mod:`fusioncenter.figures.explorable` writes five functions (compute, plot,
checks, the slider's ``sweep`` claims and the caption's ``facts`` of one frame), the entry's
fields and the slider's; :func:`register` registers the reproduced figure
(:func:`fusioncenter.figures.common.register_figure`) and its
:class:`fusioncenter.explore.Slider`. Every ``sweep`` takes the slider's values and the frames
computed at them: :func:`sweep_doc` appends the numpydoc sections they share. The explorables
that run particle filters share their Monte Carlo sizes (:func:`pf_sizes`), which every frame
of the slider keeps (:func:`fixed_sizes`).
"""

from __future__ import annotations

import inspect
from collections.abc import Callable

from fusioncenter._docstrings import Glossary
from fusioncenter.context import Parameter
from fusioncenter.explore import Slider
from fusioncenter.explore import register as register_slider
from fusioncenter.figures import common
from fusioncenter.profile import PROFILES

__all__ = ["PF_PARTICLES", "PF_TRIALS", "fixed_sizes", "pf_sizes", "register", "sweep_doc"]

#: The Monte Carlo sizes of the explorables that run particle filters (zheng2014's and the
#: synthesis's), per profile: small, so that a grid of 15 to 17 frames costs a few seconds on
#: one core; the paired standard errors say what they resolve.
PF_TRIALS = {"fast": 256, "paper": 512}
#: The particles per trial of those explorables, per profile (with :data:`PF_TRIALS`).
PF_PARTICLES = {"fast": 200, "paper": 200}

#: The second argument of every ``sweep``; the first, the slider's values, is named after the
#: parameter (``deltas``, ``gains``) and described by each module.
_sweep = Glossary("""
frames : list of dict
    The entry's data at each of the values (:func:`fusioncenter.explore.frames`).
""")


def sweep_doc(returns: str, **values: tuple[str, str]) -> Callable:
    """The numpydoc sections of a slider's ``sweep(values, frames)``.

    Parameters
    ----------
    returns : str
        What the returned claims say (``inspect.cleandoc`` removes the indentation of a
        triple-quoted string's continuation lines).
    **values : tuple of str
        The first argument of the ``sweep``, by its name: ``(type, description)``.

    Returns
    -------
    Callable
        The decorator (:meth:`fusioncenter._docstrings.Glossary.__call__`).
    """
    return _sweep(returns=("list of fusioncenter.figures.claim.Claim", inspect.cleandoc(returns)),
                  **values)


def pf_sizes(trials: str, particles: str) -> tuple[Parameter, Parameter]:
    """The settable Monte Carlo sizes of an explorable that runs particle filters.

    Parameters
    ----------
    trials : str
        What the trials are shared by (the parameter's description).
    particles : str
        Which filters the particles are of (the parameter's description).

    Returns
    -------
    tuple of fusioncenter.context.Parameter
        ``trials`` (default :data:`PF_TRIALS`) and ``particles`` (default
        :data:`PF_PARTICLES`, at least 10).
    """
    return (common.trials_parameter(PF_TRIALS, trials),
            common.trials_parameter(PF_PARTICLES, particles, name="particles", minimum=10))


def fixed_sizes(settable) -> dict:
    """A slider's ``fixed``: the entry's Monte Carlo sizes at their defaults, per profile.

    Parameters
    ----------
    settable : tuple of fusioncenter.context.Parameter
        The entry's settable parameters.

    Returns
    -------
    dict
        ``{profile: {name: default}}`` for every parameter that does not change the model
        (``model=False``), in the order of ``settable``.
    """
    return {p: {q.name: q.default_for(p) for q in settable if not q.model} for p in PROFILES}


def register(*, functions: tuple, slider: dict, **fields) -> Slider:
    """Register an explorable figure: its entry, then the slider over its parameter.

    Parameters
    ----------
    functions : tuple
        ``(compute, plot, checks, sweep, facts)``: the entry's three functions, then the
        slider's claims along the grid and the caption's numbers of one frame
        (:class:`fusioncenter.explore.Slider`).
    slider : dict
        The other fields of the :class:`~fusioncenter.explore.Slider` (``parameter``,
        ``values``, ``label``, ``symbol``, ...).
    **fields
        The fields of the entry (:func:`fusioncenter.figures.common.register_figure`).

    Returns
    -------
    fusioncenter.explore.Slider
        The registered slider (its ``entry_id`` is the entry's ``id``).

    Raises
    ------
    ValueError
        If the entry's id is taken, or the slider's parameter is not one of its settable
        parameters.
    """
    compute, plot, checks, sweep, facts = functions
    entry = common.register_figure(functions=(compute, plot, checks), **fields)
    return register_slider(Slider(entry_id=entry.id, facts=facts, sweep=sweep, **slider))
