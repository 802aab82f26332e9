"""A registry entry: one figure or table of the book, and the functions behind it.

An entry knows its paper, caption and parameters; ``compute(profile, seed, **overrides)``
returns plain data (a dict of named NumPy arrays and scalars, no matplotlib), where the
overrides are the entry's ``settable`` parameters (:class:`fusioncenter.context.Parameter`)
and the executor comes from the execution context (:mod:`fusioncenter.context`); ``plot(data)``
returns a matplotlib Figure; ``checks(data)`` returns the paper's claims about that figure
(:class:`fusioncenter.figures.claim.Claim`), each evaluated on the data. Its ``status`` is
honest: ``not-started`` (no compute yet), ``reproduced`` (matches the paper within the stated
Monte Carlo error) or ``differs`` (the note says how and why). The entries are collected by
:mod:`fusioncenter.figures.registry`.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from fusioncenter import context
from fusioncenter._docstrings import Glossary
from fusioncenter.context import Parameter
from fusioncenter.figures import compute_cache
from fusioncenter.figures.claim import Claim, nonfinite_keys
from fusioncenter.figures.papers import PAPERS
from fusioncenter.profile import check_profile

__all__ = ["STATUSES", "Entry", "EntryNotReady"]

STATUSES = ("not-started", "reproduced", "differs")

#: The argument of the methods that read an entry's data.
_doc = Glossary("""
data : dict
    The entry's data (:meth:`Entry.run_compute`).
""")


class EntryNotReady(RuntimeError):
    """The entry has no compute (or plot, or checks) yet: its status is ``not-started``."""


@dataclass
class Entry:
    """A figure or table of the book: what it shows, and the functions that compute it, draw it
    and check the paper's claims on it.

    Attributes
    ----------
    id : str
        The stable id (``python -m fusioncenter list``).
    paper : str
        A key of :data:`PAPERS`.
    kind : str
        ``"figure"`` or ``"table"``.
    caption : str
        What the figure or table shows.
    chapter : str
        Sphinx docname of the chapter, e.g. ``"book/background/kalman-riccati"``.
    label : str
        MyST target in that chapter (``""``: the chapter itself).
    parameters : dict
        The model and run parameters behind the figure, as plain data (shown by
        :meth:`summary`).
    compute : callable or None
        ``compute(profile, seed, **overrides) -> dict`` of plain data.
    plot : callable or None
        ``plot(data)`` -> a matplotlib Figure.
    checks : callable or None
        ``checks(data)`` -> a list of :class:`Claim`.
    status : str
        One of ``STATUSES``: "not-started", "reproduced" or "differs".
    note : str
        How and why the result differs from the paper (required for ``"differs"``).
    reason : str
        The note in one line, for the caption of a ``"differs"`` entry ("Differs from Fig. 3
        of ...: <reason>."); ``""``: the note's first sentence (:meth:`differs_reason`).
    seed : int
        The default seed of :meth:`run_compute`.
    settable : tuple of Parameter
        The parameters ``compute`` accepts as keyword overrides (``--set key=value``).
    nonfinite_ok : tuple of str
        Data keys in which NaN or inf are legitimate values (e.g. an undefined z-score); in any
        other key they make every claim fail (see :meth:`run_checks`).

    Raises
    ------
    ValueError
        If ``paper``, ``kind`` or ``status`` is unknown, a status other than ``"not-started"``
        lacks ``compute`` or ``checks``, or ``"differs"`` lacks a ``note``.
    """

    id: str
    paper: str
    kind: str
    caption: str
    chapter: str
    label: str = ""
    parameters: dict[str, Any] = field(default_factory=dict)
    compute: Callable[..., dict] | None = None
    plot: Callable[[dict], Any] | None = None
    checks: Callable[[dict], list[Claim]] | None = None
    status: str = "not-started"
    note: str = ""
    reason: str = ""
    seed: int = 20260101
    settable: tuple[Parameter, ...] = ()
    nonfinite_ok: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if self.paper not in PAPERS:
            raise ValueError(f"entry {self.id}: unknown paper {self.paper!r}")
        if self.kind not in ("figure", "table"):
            raise ValueError(f"entry {self.id}: kind must be 'figure' or 'table'")
        if self.status not in STATUSES:
            raise ValueError(f"entry {self.id}: status must be one of {STATUSES}")
        if self.status != "not-started" and (self.compute is None or self.checks is None):
            raise ValueError(f"entry {self.id}: status {self.status!r} needs compute and checks")
        if self.status == "differs" and not self.note:
            raise ValueError(f"entry {self.id}: status 'differs' needs a note saying why")

    def differs_reason(self) -> str:
        """How the entry differs from the paper, in one line (no final full stop).

        Returns
        -------
        str
            :attr:`reason`, else the first sentence of :attr:`note`; ``""`` unless the status
            is ``"differs"``.
        """
        if self.status != "differs":
            return ""
        text = (self.reason or self.note).strip()
        if not self.reason:
            m = re.match(r"(.+?[.!?])(\s+[A-Z(]|$)", text, re.S)
            text = m[1] if m else text
        return text.rstrip(". ")

    # -- running -------------------------------------------------------------------------
    def _need(self, what: str):
        fn = getattr(self, what)
        if fn is None:
            raise EntryNotReady(
                f"{self.id}: no {what} yet (status {self.status!r}); see the issue for its part"
            )
        return fn

    def check_overrides(self, overrides: dict) -> dict:
        """The overrides parsed against :attr:`settable`.

        Parameters
        ----------
        overrides : dict
            Parameter name -> value (a string from the command line, or a value).

        Returns
        -------
        dict
            The parsed values (:func:`fusioncenter.context.check_overrides`).

        Raises
        ------
        ValueError
            Listing the valid keys for an unknown key, naming the parameter for a bad value.
        """
        return context.check_overrides(self.id, self.settable, overrides)

    def resolved_parameters(self, profile: str, overrides: dict | None = None) -> dict:
        """Every settable parameter's value in a run of ``profile`` with ``overrides``.

        Parameters
        ----------
        profile : str
            ``"fast"`` or ``"paper"`` (the defaults of the parameters not overridden).
        overrides : dict, optional
            The overrides, parsed by :meth:`check_overrides` here.

        Returns
        -------
        dict
            Parameter name -> value, for every parameter of :attr:`settable`.
        """
        check_profile(profile)
        over = self.check_overrides(overrides or {})
        return {p.name: over.get(p.name, p.default_for(profile)) for p in self.settable}

    def model_overridden(self, overrides: dict | None) -> list[str]:
        """The overridden parameters that change the paper's setting (not only the accuracy).

        Parameters
        ----------
        overrides : dict or None
            The overrides of a run.

        Returns
        -------
        list of str
            Their names, sorted, among the settable parameters marked ``model``.
        """
        by = {p.name: p for p in self.settable}
        return sorted(k for k in (overrides or {}) if k in by and by[k].model)

    def run_compute(self, profile: str = "fast", seed: int | None = None, *,
                    executor: str | None = None, progress: bool = False,
                    **overrides) -> dict:
        """``compute(profile, seed, **overrides)`` in an execution context, checked to return a
        dict.

        The data are kept in the entries' compute cache where the build asks for one, and
        read back from it by later calls (:mod:`fusioncenter.figures.compute_cache`).

        Parameters
        ----------
        profile : str, default "fast"
            The profile, ``"fast"`` or ``"paper"``.
        seed : int, optional
            A non-negative integer seed; default the entry's :attr:`seed`.
        executor : str, optional
            Where the Monte Carlo tasks run: ``serial``, ``processes[:N]``, ``dask:local`` or
            ``dask:ADDRESS`` (:func:`fusioncenter.context.parse_executor`). Default
            :func:`fusioncenter.context.default_spec`. The data do not depend on it.
        progress : bool, default False
            Report the progress of long Monte Carlo runs on stderr (the command line does).
        **overrides
            Values of the entry's :attr:`settable` parameters.

        Returns
        -------
        dict
            The entry's data, computed or read back from the cache.

        Raises
        ------
        ValueError
            For an invalid profile or seed, an unknown override key, a bad value, or a broken
            bound between parameters (:meth:`check_bounds`).
        EntryNotReady
            If the entry has no compute.
        TypeError
            If the compute does not return a dict.
        """
        check_profile(profile)
        if seed is not None and (isinstance(seed, bool) or not isinstance(seed, int | np.integer)
                                 or seed < 0):
            raise ValueError(f"seed must be a non-negative integer, got {seed!r}")
        seed = self.seed if seed is None else int(seed)
        spec = context.default_spec(profile) if executor is None else \
            context.parse_executor(executor)
        compute = self._need("compute")
        over = self.check_overrides(overrides)
        self.check_bounds(profile, over)
        ctx = context.ExecutionContext(profile, seed, spec, over, progress=bool(progress))
        return compute_cache.cached(self.id, profile, seed, over,
                                    lambda: self._compute_in(ctx, compute, over))

    def check_bounds(self, profile: str, overrides: dict) -> dict:
        """Every bound between parameters (``0 < l <= N``, ``trials_heavy <= trials``) checked
        on the values of a run of ``profile`` with the parsed ``overrides``, before computing.

        Parameters
        ----------
        profile : str
            ``"fast"`` or ``"paper"`` (the defaults of the parameters not overridden).
        overrides : dict
            The overrides parsed by :meth:`check_overrides`.

        Returns
        -------
        dict
            The resolved values (every settable parameter).

        Raises
        ------
        ValueError
            Naming the parameter and the bound it breaks.
        """
        values = {p.name: overrides.get(p.name, p.default_for(profile)) for p in self.settable}
        for p in self.settable:
            p.check_relations(values)
        return values

    def _compute_in(self, ctx, compute, over: dict) -> dict:
        with context.activate(ctx):
            data = compute(ctx.profile, ctx.seed, **over)
        if not isinstance(data, dict):
            raise TypeError(f"{self.id}: compute must return a dict, got {type(data).__name__}")
        return data

    @_doc(returns=("matplotlib.figure.Figure", "The figure."),
          raises=(("EntryNotReady", "If the entry has no plot."),))
    def run_plot(self, data: dict):
        """``plot(data)``, with each panel of a figure of several panels given its own letter
        (:func:`fusioncenter.plotting.letter_panels`)."""
        from fusioncenter import plotting

        return plotting.letter_panels(self._need("plot")(data))

    @_doc(returns=("list of Claim", "The claims, in the order the checks give them."),
          raises=(("EntryNotReady", "If the entry has no checks, or they return no claim."),
                  ("TypeError", "If the checks return anything but\n"
                                ":class:`~fusioncenter.figures.claim.Claim` objects.")))
    def run_checks(self, data: dict) -> list[Claim]:
        """The entry's claims evaluated on ``data``.

        A claim is only as good as the numbers it reads: if ``data`` hold NaN or inf outside
        :attr:`nonfinite_ok` (a computation gone wrong, or data tampered with), every claim is
        reported failed, with the offending keys in its detail, whatever its own test says.
        A check that raises on such data fails the same way instead of raising.
        """
        check = self._need("checks")
        bad = nonfinite_keys(data, self.nonfinite_ok)
        try:
            claims = list(check(data))
        except Exception as exc:  # noqa: BLE001 (re-raised below unless the data explain it)
            if not bad:
                raise
            return [Claim(f"{self.id}: the claims", False,
                          f"data have non-finite values in {', '.join(bad)}; the checks "
                          f"raised {type(exc).__name__}: {exc}")]
        if not claims:
            raise EntryNotReady(f"{self.id}: checks returned no claims")
        for c in claims:
            if not isinstance(c, Claim):
                raise TypeError(f"{self.id}: checks must return Claim objects, got {c!r}")
        if bad:
            note = f"FAILED: data have non-finite values in {', '.join(bad)}"
            claims = [Claim(c.name, False, f"{note}; {c.detail}" if c.detail else note,
                            c.paper_specific) for c in claims]
        return claims

    def split_claims(self, claims: list[Claim], overrides: dict | None = None) -> tuple:
        """The claims that apply to a run with ``overrides``, and those skipped.

        With a model parameter overridden, the paper-specific claims are skipped (they are
        about the paper's setting); otherwise every claim is checked.

        Parameters
        ----------
        claims : list of Claim
            The evaluated claims (:meth:`run_checks`).
        overrides : dict, optional
            The overrides of the run.

        Returns
        -------
        checked, skipped : list of Claim
            The claims that apply, and the paper-specific ones left out.
        """
        if not self.model_overridden(overrides):
            return list(claims), []
        return ([c for c in claims if not c.paper_specific],
                [c for c in claims if c.paper_specific])

    def settable_lines(self) -> list[str]:
        """The lines of ``fusioncenter params ID``.

        Returns
        -------
        list of str
            Each parameter with its type, every bound (also one set by another parameter)
            and its default per profile; one line saying there is none otherwise.
        """
        if not self.settable:
            return [f"{self.id}: no parameters to override"]
        return [p.describe() + ("  [changes the paper's setting]" if p.model else "")
                for p in self.settable]

    def summary(self) -> dict:
        """What ``fusioncenter list --json`` shows of the entry.

        Returns
        -------
        dict
            Its descriptive fields (id, paper, kind, caption, chapter, label, parameters,
            status, note), each settable parameter described, and whether it has a compute,
            a plot and checks.
        """
        return {
            "id": self.id,
            "paper": self.paper,
            "kind": self.kind,
            "caption": self.caption,
            "chapter": self.chapter,
            "label": self.label,
            "parameters": self.parameters,
            "settable": {p.name: p.describe() for p in self.settable},
            "status": self.status,
            "note": self.note,
            "has_compute": self.compute is not None,
            "has_plot": self.plot is not None,
            "has_checks": self.checks is not None,
        }

