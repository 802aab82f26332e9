"""The documented parameters of a registry entry that a run may override (``--set`` on the
command line): :class:`Parameter` parses and bounds one value, ``check_overrides`` checks a
run's overrides against an entry's parameters."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from fusioncenter.profile import check_profile

__all__ = ["Parameter", "check_overrides"]


@dataclass(frozen=True)
class Parameter:
    """A documented parameter of a registry entry that ``compute`` accepts as an override.

    Parameters
    ----------
    name : str
        The keyword (``--set name=value`` on the command line).
    kind : {"int", "float", "floats"}
        ``int``, ``float`` or ``floats`` (a comma-separated list on the command line).
    doc : str
        One line: what it is, with its unit.
    default : object
        The value used without an override: one value, or a dict ``{profile: value}``.
    minimum, maximum : float or None, default None
        Inclusive bounds of the value (of every element for ``floats``); ``None``: unbounded.
    model : bool, default False
        ``True`` if it changes the paper's setting (``N``, ``l``, noise levels): the claims the
        entry marks paper-specific are then skipped by ``verify``. ``False`` (trials,
        particles, paths) if it changes only the Monte Carlo accuracy: every claim applies.
    exclusive_minimum : bool, default False
        The value must be strictly above ``minimum`` (``0 < l``).
    at_most : str or None, default None
        The name of another parameter of the entry that bounds this one from above
        (``l <= N``, ``trials_heavy <= trials``), checked on the values of the run before
        computing starts (:meth:`check_relations`).
    multiple_below : int or None, default None
        With ``at_most``: a value below the other parameter's must be a multiple of this
        (``trials_heavy``: whole blocks of 256 trials).

    Raises
    ------
    ValueError
        If ``kind`` is not one of the three kinds.
    """

    name: str
    kind: str
    doc: str
    default: Any
    minimum: float | None = None
    maximum: float | None = None
    model: bool = False
    exclusive_minimum: bool = False
    at_most: str | None = None
    multiple_below: int | None = None

    def __post_init__(self) -> None:
        if self.kind not in ("int", "float", "floats"):
            raise ValueError(f"parameter {self.name}: kind must be int, float or floats")

    def default_for(self, profile: str) -> Any:
        """The value used without an override in a run of ``profile``.

        Parameters
        ----------
        profile : str
            ``"fast"`` or ``"paper"``.

        Returns
        -------
        object
            ``default[profile]`` when ``default`` is a dict, else ``default`` itself
            (it is not parsed).

        Raises
        ------
        ValueError
            If ``default`` is a dict and ``profile`` is not a known profile.
        """
        d = self.default
        return d[check_profile(profile)] if isinstance(d, dict) else d

    def _scalar(self, value, kind: str):
        import math

        import numpy as np

        if isinstance(value, str):
            from fusioncenter._numbers import number

            value = number(self.name, value, kind)
        if isinstance(value, bool) or not isinstance(value, int | float | np.integer
                                                     | np.floating):
            raise ValueError(f"parameter {self.name}: expected a number, got {value!r}")
        if kind == "int":
            if isinstance(value, float | np.floating) and not float(value).is_integer():
                raise ValueError(f"parameter {self.name}: expected an integer, got {value!r}")
            value = int(value)
        else:
            value = float(value)
            if not math.isfinite(value):
                raise ValueError(f"parameter {self.name}: must be finite, got {value!r}")
        if self.minimum is not None and (value <= self.minimum if self.exclusive_minimum
                                         else value < self.minimum):
            op = ">" if self.exclusive_minimum else ">="
            raise ValueError(f"parameter {self.name}: must be {op} {self.minimum:g}, got "
                             f"{value!r}")
        if self.maximum is not None and value > self.maximum:
            raise ValueError(f"parameter {self.name}: must be <= {self.maximum:g}, got {value!r}")
        return value

    def parse(self, value) -> Any:
        """``value`` (a Python value or the text of ``--set``) checked and converted; a
        ``ValueError`` naming the parameter otherwise.

        Parameters
        ----------
        value : int, float, str, or list or tuple of them
            For ``int`` and ``float``: a number or its text (blanks around it are ignored);
            for ``int`` a float with an integer value is accepted; booleans are refused. For
            ``floats``: a non-empty list or tuple of such values, or their comma-separated
            text (empty items are skipped).

        Returns
        -------
        int, float or tuple of float
            ``int`` for kind ``int``, a finite ``float`` for ``float``, a tuple of finite
            floats for ``floats``.

        Raises
        ------
        ValueError
            If the value (or an element) is not a number of the kind, not finite (``float``,
            ``floats``), outside ``[minimum, maximum]``, or, for ``floats``, if there is no
            element or ``value`` is not a list, tuple or string.
        """
        if self.kind != "floats":
            return self._scalar(value, self.kind)
        if isinstance(value, str):
            value = [v for v in value.split(",") if v.strip()]
        if not isinstance(value, list | tuple) or not value:
            raise ValueError(f"parameter {self.name}: expected a non-empty list of numbers "
                             f"(comma-separated), got {value!r}")
        return tuple(self._scalar(v, "float") for v in value)

    def describe(self) -> str:
        """One line for ``python -m fusioncenter params ID``.

        Returns
        -------
        str
            ``name (kind, lo <= name <= hi; default D): doc``, the bounds shown only where they
            are set.
        """
        return f"{self.name} ({self.kind}{self.bounds()}; default {self._default_text()}): " \
            f"{self.doc}"

    def bounds(self) -> str:
        """Every bound of the parameter as text.

        Returns
        -------
        str
            ``", 0 < l <= N"`` (the form of :meth:`describe`), ``""`` if unbounded.
        """
        his = [f"{self.maximum:g}"] if self.maximum is not None else []
        if self.at_most:
            his.append(self.at_most)
        if self.minimum is None and not his:
            return ""
        lo = "" if self.minimum is None else \
            f"{self.minimum:g} {'<' if self.exclusive_minimum else '<='} "
        hi = "".join(f" <= {h}" for h in his)
        step = f", a multiple of {self.multiple_below} below {self.at_most}" \
            if self.multiple_below and self.at_most else ""
        return f", {lo}{self.name}{hi}{step}"

    def _default_text(self) -> str:
        d = self.default
        if isinstance(d, dict):
            return ", ".join(f"{k} {v}" for k, v in d.items())
        return str(d)

    def check_relations(self, values: dict) -> None:
        """Check the bound set by another parameter (:attr:`at_most`) on the run's values.

        Parameters
        ----------
        values : dict
            Every settable parameter's value in the run (overrides and defaults).

        Raises
        ------
        ValueError
            If the value exceeds the other parameter's (the message names both).
        """
        if self.at_most and self.at_most in values and values.get(self.name) is not None \
                and values[self.name] > values[self.at_most]:
            raise ValueError(f"parameter {self.name}: must be <= {self.at_most} "
                             f"({values[self.at_most]}), got {values[self.name]!r}")
        if self.at_most and self.multiple_below and self.at_most in values \
                and values.get(self.name) is not None \
                and values[self.name] < values[self.at_most] \
                and values[self.name] % self.multiple_below:
            raise ValueError(f"parameter {self.name}: below {self.at_most} "
                             f"({values[self.at_most]}) it must be a multiple of "
                             f"{self.multiple_below}, got {values[self.name]!r}")


def check_overrides(entry_id: str, declared, overrides: dict) -> dict:
    """``overrides`` checked against the ``declared`` :class:`Parameter` objects of an entry:
    the parsed values, or a ``ValueError`` listing the valid keys.

    Parameters
    ----------
    entry_id : str
        The registry id, named in the error message.
    declared : iterable of Parameter
        The entry's settable parameters.
    overrides : dict
        Parameter name to value (a Python value or the text of ``--set``).

    Returns
    -------
    dict
        The same keys, each value converted by :meth:`Parameter.parse`.

    Raises
    ------
    ValueError
        If a key is not a declared parameter (the message lists the valid keys), or a value
        is invalid (the message names the parameter).
    """
    by_name = {p.name: p for p in declared}
    unknown = sorted(set(overrides) - set(by_name))
    if unknown:
        valid = ", ".join(sorted(by_name)) or "none (this entry takes no overrides)"
        raise ValueError(f"{entry_id}: unknown parameter(s) {', '.join(unknown)}; valid keys: "
                         f"{valid}")
    return {k: by_name[k].parse(v) for k, v in overrides.items()}
