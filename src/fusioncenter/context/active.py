"""The active execution context: what a registry compute depends on (:class:`ExecutionContext`),
made active for a ``with`` block by :func:`activate` and read back by :func:`current`."""

from __future__ import annotations

import contextlib
import contextvars
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

from fusioncenter.context.specs import parse_executor
from fusioncenter.profile import check_profile

__all__ = ["ExecutionContext", "activate", "current"]


@dataclass(frozen=True)
class ExecutionContext:
    """Everything a registry compute depends on, and where it runs.

    ``profile`` and ``seed`` and ``parameters`` (the overrides of the entry's documented
    parameters) fix the data; ``executor`` (a spec of
    :func:`~fusioncenter.context.specs.parse_executor`) only where the Monte Carlo tasks run.
    The object is frozen; it is made active with :func:`activate`.

    Parameters
    ----------
    profile : str
        ``"fast"`` or ``"paper"``.
    seed : int
        The seed of the compute (not validated here:
        :meth:`~fusioncenter.figures.registry.Entry.run_compute` checks it is ``>= 0``).
    executor : str, default "serial"
        An executor spec; it is stored normalised by
        :func:`~fusioncenter.context.specs.parse_executor` (``processes``
        becomes ``processes:<cores>``).
    parameters : dict, default {}
        The parsed overrides of the entry's documented parameters, by name (see
        :func:`~fusioncenter.context.parameters.check_overrides`); empty when none is overridden.
    progress : bool, default False
        Report the progress of long Monte Carlo runs on stderr (the command line sets it;
        :func:`fusioncenter.montecarlo.simulate`).

    Raises
    ------
    ValueError
        If ``profile`` is unknown or ``executor`` is not a valid spec.
    """

    profile: str
    seed: int
    executor: str = "serial"
    parameters: dict[str, Any] = field(default_factory=dict)
    progress: bool = False

    def __post_init__(self) -> None:
        check_profile(self.profile)
        object.__setattr__(self, "executor", parse_executor(self.executor))


_CURRENT: contextvars.ContextVar[ExecutionContext | None] = contextvars.ContextVar(
    "fusioncenter_context", default=None)


@contextlib.contextmanager
def activate(ctx: ExecutionContext) -> Iterator[ExecutionContext]:
    """Make ``ctx`` the active context inside the ``with`` block (nests; thread-safe).

    The context is held in a ``contextvars`` variable: setting it affects only the calling
    thread (or asyncio task), and the previous context (``None`` at the top) is restored when
    the block exits, also on an exception.

    Parameters
    ----------
    ctx : ExecutionContext
        The context to activate.

    Yields
    ------
    ExecutionContext
        ``ctx`` itself (``with activate(ctx) as c:``).
    """
    token = _CURRENT.set(ctx)
    try:
        yield ctx
    finally:
        _CURRENT.reset(token)


def current() -> ExecutionContext | None:
    """The active context, or ``None`` outside
    :meth:`~fusioncenter.figures.registry.Entry.run_compute`.

    Returns
    -------
    ExecutionContext or None
        The context of the innermost :func:`activate` block of this thread, ``None`` outside
        every such block.
    """
    return _CURRENT.get()
