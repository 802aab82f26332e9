"""Numpydoc ``Parameters``, ``Returns`` and ``Raises`` sections written once per package.

The functions of a package share their arguments: ``a`` is "the state transition, ``|a| < 1``"
in every function of :mod:`fusioncenter.power` that takes it, ``n_paths`` "the number of Monte
Carlo paths" in every runner of :mod:`fusioncenter.fading`. A :class:`Glossary` holds one
description per argument name; decorating a function with it appends the numpydoc sections to
the function's own docstring (its summary and explanation), the parameters in the order of the
signature, so that ``help()``, the book's API page and the source say the same thing and the
shared descriptions are written (and corrected) in one place. The glossary is written as a
numpydoc ``Parameters`` section, and its default ``Raises`` section as one::

    doc = Glossary('''
    a : array_like
        State transition, ``|a| < 1``.
    ''', raises='''
    ValueError
        Naming the argument that is invalid.
    ''')

    @doc(returns=("numpy.ndarray", "The result."), sigma_w2=("array_like", "``>= 0``."))
    def f(a, sigma_w2): ...

A keyword given to the decorator describes that argument of this function only (a ``(type,
description)`` pair, or a string that keeps the glossary's type); :meth:`Glossary.extend` gives
a module its own variant of some entries. A description may be empty (``("lower, upper :
numpy.ndarray", "")`` under ``Returns``). Consecutive arguments with the same type and
description are listed together (``h_var_re, h_var_im : array_like``). The function object
itself is returned: its name, module and signature are untouched.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable

__all__ = ["Glossary"]

Entry = tuple[str, str]


def _indent(text: str) -> list[str]:
    return ["    " + line if line else "" for line in text.split("\n")] if text else []


def _raises(raised) -> list[str]:
    """The lines of a ``Raises`` section listing ``raised`` (none if it is empty)."""
    lines = ["", "Raises", "------"] if raised else []
    for kind, text in raised:
        lines += [kind, *_indent(text)]
    return lines


def parse(text: str) -> list[tuple[list[str], Entry]]:
    """The entries of a numpydoc section: ``(names, (type, description))``, in order.

    A line without indentation starts an entry (``names : type``, or ``names`` alone, several
    names separated by ``", "``); the indented lines below it are its description.
    """
    out: list[tuple[list[str], list[str], list[str]]] = []
    for line in inspect.cleandoc(text).split("\n") if text else []:
        if not line.strip():
            continue
        if line.startswith(" "):
            out[-1][2].append(line[4:])
        else:
            names, _, kind = line.partition(" : ")
            out.append((names.split(", "), [kind], []))
    return [(names, (kind[0], "\n".join(desc))) for names, kind, desc in out]


class Glossary:
    """Descriptions of the arguments of a package's functions, by argument name.

    ``parameters`` is written as a numpydoc ``Parameters`` section, ``raises`` as a ``Raises``
    section (the default of every decorated function).
    """

    def __init__(self, parameters: str = "", raises: str = "") -> None:
        self.raises = tuple((", ".join(names), entry[1]) for names, entry in parse(raises))
        self.entries = {name.lstrip("*"): entry for names, entry in parse(parameters)
                        for name in names}

    def extend(self, parameters: str = "", raises: str | None = None) -> Glossary:
        """A copy with the entries of ``parameters`` (and the ``Raises`` section) replaced."""
        new = Glossary(parameters, raises or "")
        new.entries = {**self.entries, **new.entries}
        if raises is None:
            new.raises = self.raises
        return new

    def _entry(self, name: str, overrides: dict[str, Entry | str]) -> Entry:
        if name in overrides:
            value = overrides[name]
            if isinstance(value, str):
                return self.entries[name][0], value
            return value
        if name not in self.entries:
            raise KeyError(f"no description of the argument {name!r}")
        return self.entries[name]

    def __call__(self, returns: Entry | tuple[Entry, ...], raises: tuple[Entry, ...] | None = None,
                 **overrides: Entry | str) -> Callable:
        """The decorator appending the sections to a function's docstring.

        ``returns`` is one ``(type, description)`` pair, or several for a tuple of results;
        ``raises`` replaces the glossary's ``Raises`` section.
        """
        returned = (returns,) if isinstance(returns[0], str) else returns

        def decorate(func: Callable) -> Callable:
            lines = self._section(func, "Parameters", overrides)
            lines += ["", "Returns", "-------"]
            for kind, text in returned:
                lines += [kind, *_indent(text)]
            func.__doc__ = "\n".join(lines + _raises(self.raises if raises is None else raises))
            return func

        return decorate

    def attributes(self, raises: tuple[Entry, ...] = (), **overrides: Entry | str) -> Callable:
        """The class decorator appending an ``Attributes`` section to a class's docstring.

        One entry per argument of the class's constructor (the fields of a dataclass or a
        ``NamedTuple``), in order; ``overrides`` as for the function decorator. ``raises`` is the
        class's ``Raises`` section (none by default: only a validating constructor raises).
        """

        def decorate(cls: type) -> type:
            cls.__doc__ = "\n".join(self._section(cls, "Attributes", overrides) + _raises(raises))
            return cls

        return decorate

    def _section(self, obj: Callable, title: str, overrides: dict[str, Entry | str]) -> list[str]:
        """``obj``'s docstring followed by the section ``title`` describing its arguments."""
        groups: list[tuple[list[str], Entry]] = []
        for p in inspect.signature(obj).parameters.values():
            if p.name == "self":
                continue
            shown = f"**{p.name}" if p.kind is p.VAR_KEYWORD else p.name
            entry = self._entry(p.name, overrides)
            # napoleon reads "a, b : type" under Attributes as the attribute "a, b": one each
            if groups and groups[-1][1] == entry and title != "Attributes":
                groups[-1][0].append(shown)
            else:
                groups.append(([shown], entry))
        unknown = set(overrides) - set(inspect.signature(obj).parameters)
        if unknown:
            raise KeyError(f"{obj.__name__} has no argument {sorted(unknown)}")
        lines = [inspect.cleandoc(obj.__doc__ or ""), "", title, "-" * len(title)]
        for names, (kind, text) in groups:
            lines.append(", ".join(names) + (f" : {kind}" if kind else ""))
            lines += _indent(text)
        return lines
