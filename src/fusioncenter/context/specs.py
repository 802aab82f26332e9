"""Executor specs: the text that says where a compute's Monte Carlo tasks run, checked and
normalised (:func:`parse_executor`), and the spec used when none is given (:func:`default_spec`:
the environment variable :data:`EXECUTOR_ENV`, else by profile and :func:`cores`)."""

from __future__ import annotations

import os

from fusioncenter.profile import check_profile

__all__ = ["EXECUTOR_ENV", "cores", "parse_executor", "default_spec"]

#: Environment variable with the executor spec of the book build (and any process).
EXECUTOR_ENV = "FUSIONCENTER_EXECUTOR"


def cores() -> int:
    """The number of cores this process may use (at least 1).

    Returns
    -------
    int
        The size of the process's CPU affinity set (``os.sched_getaffinity``), or where that
        does not exist ``os.cpu_count()``; never less than 1.
    """
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover (not Linux)
        return max(1, os.cpu_count() or 1)


def parse_executor(spec: str) -> str:
    """Validate an executor spec and return it normalised.

    Parameters
    ----------
    spec : str
        ``auto``, ``serial``, ``processes``, ``processes:N`` (``N >= 1``, decimal digits only),
        ``dask:local`` or ``dask:ADDRESS``. Blanks around the spec, and around what follows
        ``dask:``, are ignored.

    Returns
    -------
    str
        ``auto``, ``serial``, ``processes:N`` (``processes`` alone becomes
        ``processes:<cores>``, see :func:`cores`; ``N`` without leading zeros), ``dask:local``
        or ``dask:ADDRESS``.

    Raises
    ------
    ValueError
        If ``spec`` is not a string, if ``N`` is not an integer ``>= 1``, if nothing follows
        ``dask:``, or if ``spec`` is none of the forms above.
    """
    if not isinstance(spec, str):
        raise ValueError(f"executor must be a string spec, got {spec!r}")
    s = spec.strip()
    if s in ("serial", "auto"):
        return s
    if s == "processes":
        return f"processes:{cores()}"
    if s.startswith("processes:"):
        n = s.split(":", 1)[1]
        if not n.isdigit() or int(n) < 1:
            raise ValueError(f"executor {spec!r}: processes:N needs an integer N >= 1")
        return f"processes:{int(n)}"
    if s.startswith("dask:") and s[5:].strip():
        return "dask:" + s[5:].strip()
    raise ValueError(f"executor must be one of auto, serial, processes[:N], dask:local or "
                     f"dask:ADDRESS (a dask.distributed scheduler), got {spec!r}")


def default_spec(profile: str) -> str:
    """The executor used when none is given: :data:`EXECUTOR_ENV` if set, else ``auto`` (a
    pool of the cores only for runs that repay it) for the ``paper`` profile on several
    cores, ``serial`` otherwise.

    Parameters
    ----------
    profile : str
        ``"fast"`` or ``"paper"``. It is checked only when :data:`EXECUTOR_ENV` is unset or
        blank (a set variable decides alone).

    Returns
    -------
    str
        A normalised spec (see :func:`parse_executor`): the variable's value, else ``auto``
        when ``profile`` is ``"paper"`` and :func:`cores` is above 1, else ``serial``.

    Raises
    ------
    ValueError
        If :data:`EXECUTOR_ENV` holds an invalid spec (the message names the variable), or if
        it is unset and ``profile`` is not a known profile.
    """
    env = os.environ.get(EXECUTOR_ENV, "").strip()
    if env:
        try:
            return parse_executor(env)
        except ValueError as exc:
            raise ValueError(f"environment variable {EXECUTOR_ENV}: {exc}") from None
    if check_profile(profile) == "paper" and cores() > 1:
        return "auto"
    return "serial"
