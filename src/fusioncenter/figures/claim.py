"""A paper's claim about a figure or table, checked on the entry's computed data.

An entry's ``checks(data)`` returns a list of :class:`Claim`: what the paper states, whether
the data bear it out, and the numbers behind the verdict. A claim is only as good as the
numbers it reads, so :func:`nonfinite_keys` finds the data that hold NaN or an infinity
(:meth:`fusioncenter.figures.entry.Entry.run_checks` then fails every claim).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Claim", "nonfinite_keys"]


@dataclass(frozen=True)
class Claim:
    """One claim of a paper, checked on computed data.

    ``passed`` must be a real ``bool`` (a NumPy bool is converted): anything else, such as the
    string ``"False"``, is a ``TypeError``, never a pass. ``paper_specific`` marks a claim about
    the paper's own setting (its printed numbers, its ``N`` or ``l``): ``verify`` skips it when
    a model parameter is overridden.

    Attributes
    ----------
    name : str
        What is claimed, in words.
    passed : bool
        Whether the data bear the claim out.
    detail : str
        The numbers behind the verdict (shown next to it), or ``""``.
    paper_specific : bool
        The claim is about the paper's own setting.

    Raises
    ------
    TypeError
        If ``passed`` or ``paper_specific`` is not a ``bool`` (``passed`` may be a NumPy bool).
    """

    name: str
    passed: bool
    detail: str = ""
    paper_specific: bool = False

    def __post_init__(self) -> None:
        if isinstance(self.passed, np.bool_):
            object.__setattr__(self, "passed", bool(self.passed))
        if not isinstance(self.passed, bool):
            raise TypeError(f"claim {self.name!r}: passed must be a bool, got "
                            f"{type(self.passed).__name__} {self.passed!r}")
        if not isinstance(self.paper_specific, bool):
            raise TypeError(f"claim {self.name!r}: paper_specific must be a bool")

    def __bool__(self) -> bool:
        return self.passed


def nonfinite_keys(data: dict, allowed=()) -> list[str]:
    """The keys of ``data`` (outside ``allowed``) whose numbers include NaN or an infinity.

    Floats, complex numbers and numeric arrays are inspected, also inside lists, tuples and
    nested dicts (``outer.inner``); text and integers are never non-finite.

    Parameters
    ----------
    data : dict
        An entry's computed data.
    allowed : container of str
        Keys whose values may be non-finite (skipped).

    Returns
    -------
    list of str
        The offending top-level keys, as strings, in the order of ``data``.
    """
    bad = []

    def has_nonfinite(v) -> bool:
        if isinstance(v, dict):
            return any(has_nonfinite(x) for x in v.values())
        if isinstance(v, float | complex | np.floating | np.complexfloating):
            return not np.isfinite(v)
        if isinstance(v, list | tuple):
            return any(has_nonfinite(x) for x in v)
        if isinstance(v, np.ndarray):
            if v.dtype.kind in "fc":
                return not bool(np.isfinite(v).all())
            if v.dtype == object:
                return any(has_nonfinite(x) for x in v.ravel())
        return False

    for key, value in data.items():
        if key not in allowed and has_nonfinite(value):
            bad.append(str(key))
    return bad

