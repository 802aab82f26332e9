"""What the registry modules of every part share: the values of an entry's settable parameters.

An entry declares the parameters its ``compute`` accepts as overrides in its ``settable`` tuple
of :class:`fusioncenter.context.Parameter` (``--set key=value`` on the command line); the
compute reads the value of each one in a run with :func:`settings`, so that the default of a
parameter is written once, in its declaration. :func:`register_figure` registers a reproduced
figure from its fields and its three functions.

Every entry has the same three functions, with the same arguments: ``compute(profile, seed,
**over)`` returns the data, ``plot(data)`` draws them, ``checks(data)`` tests the paper's claims
on them. Their numpydoc sections are written once, in :data:`document` (a
:class:`fusioncenter._docstrings.Glossary`): :func:`compute_doc`, :func:`plot_doc` and
:func:`checks_doc` append them to a function's own summary, which says what is particular to
the entry (the data's keys, the figure's panels, the claims).
"""

from __future__ import annotations

import inspect
from collections.abc import Callable

from fusioncenter import context
from fusioncenter._docstrings import Glossary
from fusioncenter.context import Parameter
from fusioncenter.figures.registry import Entry, register

__all__ = ["checks_doc", "compute_doc", "document", "plot_doc", "register_figure", "settings",
           "trials_parameter"]

#: The arguments shared by the compute, plot and checks functions of the registry's entries
#: (and the helpers that take the same ``profile``, ``seed`` or ``data``).
document = Glossary("""
profile : {"fast", "paper"}
    The Monte Carlo profile: ``"fast"`` (the test build's sizes) or ``"paper"`` (the papers').
seed : int
    The root seed: every random draw of the run derives from it, so that the data are the
    same, bit for bit, under every executor and chunking.
**over
    Overrides of the entry's settable parameters (``python -m fusioncenter params ID`` lists
    them, ``--set key=value`` on the command line).
data : dict
    The entry's data, as its compute function returns them.
""", raises="""
ValueError
    For an unknown key of ``over`` (the message lists the valid keys) or an invalid value,
    naming the parameter.
""")


#: The arguments of the three decorators below.
_decorators = Glossary("""
returns : str
    What the function returns; a triple-quoted string may continue on indented lines
    (``inspect.cleandoc`` removes the indentation).
**overrides
    Descriptions of arguments particular to the decorated function (``name=(type, text)``).
""")
_DECORATOR = ("Callable", "The decorator (:meth:`fusioncenter._docstrings.Glossary.__call__`).")


@_decorators(returns=_DECORATOR, raises=())
def compute_doc(returns: str, **overrides) -> Callable:
    """The numpydoc sections of an entry's compute function; ``returns`` says what the
    returned ``dict`` holds (its keys)."""
    return document(returns=("dict", inspect.cleandoc(returns)), **overrides)


@_decorators(returns=_DECORATOR, raises=())
def plot_doc(returns: str = "The figure (:func:`fusioncenter.plotting.finish` applied).",
             **overrides) -> Callable:
    """The numpydoc sections of an entry's plot function (it raises nothing of its own);
    ``returns`` says what the figure shows, if the summary does not say it."""
    return document(returns=("matplotlib.figure.Figure", inspect.cleandoc(returns)), raises=(),
                    **overrides)


@_decorators(returns=_DECORATOR, raises=())
def checks_doc(returns: str = "One claim per statement of the paper checked on the data, "
               "each with its measured value in its detail.", **overrides) -> Callable:
    """The numpydoc sections of an entry's checks function (it raises nothing of its own);
    ``returns`` says what the claims are, if the summary does not say it."""
    return document(returns=("list of fusioncenter.figures.claim.Claim",
                             inspect.cleandoc(returns)), raises=(), **overrides)


def settings(entry_id: str, settable, profile: str, over: dict) -> dict:
    """The value of every settable parameter in one run: its override, else its default.

    Parameters
    ----------
    entry_id : str
        The entry's id (for the error message).
    settable : tuple of fusioncenter.context.Parameter
        The entry's settable parameters.
    profile : str
        ``"fast"`` or ``"paper"``: the default of a parameter may depend on it.
    over : dict
        The overrides (as given to ``compute``; already parsed when it runs through
        :meth:`fusioncenter.figures.entry.Entry.run_compute`, parsed here otherwise).

    Returns
    -------
    dict
        ``{name: value}`` for every parameter of ``settable``.

    Raises
    ------
    ValueError
        For an unknown key (listing the valid keys) or an invalid value.
    """
    over = context.check_overrides(entry_id, settable, over)
    return {p.name: over[p.name] if p.name in over else p.default_for(profile)
            for p in settable}


def trials_parameter(default, doc: str = "Monte Carlo trials", name: str = "trials",
                     minimum: int = 2) -> Parameter:
    """A Monte Carlo size (it changes only the accuracy: every claim still applies).

    Parameters
    ----------
    default : int or dict
        One value, or ``{profile: value}``.
    doc : str
        What it counts.
    name : str
        The keyword.
    minimum : int
        The smallest value accepted.

    Returns
    -------
    fusioncenter.context.Parameter
        An ``int`` parameter with ``model=False``.
    """
    return Parameter(name, "int", doc, dict(default) if isinstance(default, dict) else default,
                     minimum=minimum)


def register_figure(*, functions: tuple, **fields) -> Entry:
    """Register a reproduced figure: an entry with its compute, plot and checks.

    Parameters
    ----------
    functions : tuple
        ``(compute, plot, checks)`` of the entry.
    **fields
        The other fields of :class:`fusioncenter.figures.entry.Entry` (``id``, ``paper``,
        ``caption``, ``chapter``, ``label``, ``parameters``, ``settable``, ``note``, ...).

    Returns
    -------
    fusioncenter.figures.entry.Entry
        The registered entry, with ``kind="figure"`` and ``status="reproduced"``.
    """
    compute, plot, checks = functions
    return register(Entry(kind="figure", status="reproduced", compute=compute, plot=plot,
                          checks=checks, **fields))
