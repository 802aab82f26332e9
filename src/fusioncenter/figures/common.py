"""What the registry modules of every part share: the values of an entry's settable parameters.

An entry declares the parameters its ``compute`` accepts as overrides in its ``settable`` tuple
of :class:`fusioncenter.context.Parameter` (``--set key=value`` on the command line); the
compute reads the value of each one in a run with :func:`settings`, so that the default of a
parameter is written once, in its declaration. :func:`register_figure` registers a reproduced
figure from its fields and its three functions.
"""

from __future__ import annotations

from fusioncenter import context
from fusioncenter.context import Parameter
from fusioncenter.figures.registry import Entry, register

__all__ = ["register_figure", "settings", "trials_parameter"]


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
        :meth:`fusioncenter.figures.registry.Entry.run_compute`, parsed here otherwise).

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
        The other fields of :class:`fusioncenter.figures.registry.Entry` (``id``, ``paper``,
        ``caption``, ``chapter``, ``label``, ``parameters``, ``settable``, ``note``, ...).

    Returns
    -------
    fusioncenter.figures.registry.Entry
        The registered entry, with ``kind="figure"`` and ``status="reproduced"``.
    """
    compute, plot, checks = functions
    return register(Entry(kind="figure", status="reproduced", compute=compute, plot=plot,
                          checks=checks, **fields))
