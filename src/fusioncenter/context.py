"""The execution context of a registry compute: where its Monte Carlo tasks run.

A registry entry's ``compute`` is a function of the profile, the seed and its documented
parameters only; *where* its trials run is the executor of the active context:

``serial``
    in the calling process;
``auto``
    serial, unless a Monte Carlo run is long enough to repay starting a process pool of the
    cores (about 5 s): :func:`fusioncenter.montecarlo.simulate` times the run's first block in
    the calling process and sends the remaining blocks to the pool only when their serial time
    would exceed :data:`AUTO_POOL_SECONDS` (a pool already started is used at once). The
    default, so that it is never slower than serial by more than a second or so;
``processes`` or ``processes:N``
    a pool of ``N`` worker processes (default: the number of usable cores), started with the
    ``spawn`` method (safe in notebooks, scripts and threads) and limited to one BLAS / OpenMP
    thread each;
``dask:local``
    a ``dask.distributed.LocalCluster`` of one single-threaded worker process per core;
``dask:ADDRESS``
    the ``dask.distributed`` scheduler at ``ADDRESS`` (e.g. ``tcp://10.0.0.5:8786``); its
    workers need the same environment (``requirements/lock.txt`` and this package).

Because :func:`fusioncenter.montecarlo.simulate` fixes every random draw by the seed and its
blocks, the data are bitwise identical under every executor: the executor is a matter of speed.

:func:`Entry.run_compute <fusioncenter.figures.registry.Entry.run_compute>` activates the
context; a compute that pays for parallel work asks for :func:`executor` (``None`` means
serial) and passes it to the Monte Carlo runner. The default spec is the environment variable
:data:`EXECUTOR_ENV` (how the book build sets it) or, unset, :func:`default_spec`: ``auto`` in
the ``paper`` profile on a machine with several cores, serial otherwise (the fast profile's
runs are too short to repay starting workers).

Pools are started on first use and kept for the life of the process (one per spec), so that a
chapter computing several entries starts its workers once; :func:`shutdown` stops them (also
registered with ``atexit``).
"""

from __future__ import annotations

import atexit
import contextlib
import contextvars
import os
import threading
from collections.abc import Iterator
from concurrent.futures import Executor
from dataclasses import dataclass, field
from typing import Any

from fusioncenter.profile import check_profile

__all__ = ["EXECUTOR_ENV", "AUTO_POOL_SECONDS", "ExecutionContext", "parse_executor",
           "default_spec", "cores", "activate", "current", "executor", "workers", "shutdown"]

#: Environment variable with the executor spec of the book build (and any process).
EXECUTOR_ENV = "FUSIONCENTER_EXECUTOR"
#: ``auto`` starts a process pool only for a Monte Carlo run whose remaining blocks would take
#: longer than this serially (seconds; at twice the ~5 s start-up of a pool, a pool of two
#: workers is then at worst as fast as serial).
AUTO_POOL_SECONDS = 10.0
#: Variables that cap the BLAS / OpenMP threads of a worker process.
THREAD_VARS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS",
               "VECLIB_MAXIMUM_THREADS", "NUMEXPR_NUM_THREADS")


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


@dataclass(frozen=True)
class ExecutionContext:
    """Everything a registry compute depends on, and where it runs.

    ``profile`` and ``seed`` and ``parameters`` (the overrides of the entry's documented
    parameters) fix the data; ``executor`` (a spec of :func:`parse_executor`) only where the
    Monte Carlo tasks run. The object is frozen; it is made active with :func:`activate`.

    Parameters
    ----------
    profile : str
        ``"fast"`` or ``"paper"``.
    seed : int
        The seed of the compute (not validated here:
        :meth:`~fusioncenter.figures.registry.Entry.run_compute` checks it is ``>= 0``).
    executor : str, default "serial"
        An executor spec; it is stored normalised by :func:`parse_executor` (``processes``
        becomes ``processes:<cores>``).
    parameters : dict, default {}
        The parsed overrides of the entry's documented parameters, by name (see
        :func:`check_overrides`); empty when none is overridden.
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


def executor() -> Executor | None:
    """The active context's executor (started on first use), ``None`` when serial.

    A compute passes it to :func:`fusioncenter.montecarlo.simulate` (or a ``run`` built on
    it). Outside any context (a direct call of a compute function) it is ``None``.

    Returns
    -------
    concurrent.futures.Executor or None
        ``None`` outside a context or when its spec is ``serial``. For ``processes:N``, a
        ``concurrent.futures.ProcessPoolExecutor`` of ``N`` workers (``spawn`` start method,
        one BLAS / OpenMP thread each, Ctrl-C ignored in the workers); for ``dask:...``, the
        ``get_executor()`` of a ``dask.distributed.Client`` (of a new ``LocalCluster`` with
        one single-threaded worker process per core for ``dask:local``). One pool per spec is
        started on first use and reused until :func:`shutdown`.

    Raises
    ------
    RuntimeError
        If the scheduler of ``dask:ADDRESS`` cannot be reached (within 30 s).
    """
    ctx = current()
    if ctx is None or ctx.executor == "serial":
        return None
    if ctx.executor == "auto":
        return _AutoPool()
    return _pool(ctx.executor)


class _AutoPool:
    """The executor of ``auto``: a pool of the cores, started only when
    :func:`fusioncenter.montecarlo.simulate` (seeing ``adaptive``) finds a run that repays it."""

    adaptive = True
    spec = staticmethod(lambda: f"processes:{cores()}")

    def choose(self, serial_seconds: float):
        """The pool if the rest of the run (``serial_seconds`` serially) repays starting it
        (over :data:`AUTO_POOL_SECONDS`) or it runs already, else ``None`` (serial)."""
        if cores() > 1 and (self.spec() in _POOLS or serial_seconds > AUTO_POOL_SECONDS):
            return _pool(self.spec())
        return None

    def submit(self, fn, *args, **kwargs):  # used as a plain executor: the pool
        return _pool(self.spec()).submit(fn, *args, **kwargs)


def workers() -> int:
    """How many tasks the active executor runs at once (1 when serial).

    Returns
    -------
    int
        1 outside a context or when serial; ``N`` for ``processes:N``; for ``dask:...`` the
        total threads of the scheduler's workers (at least 1), or :func:`cores` if the
        scheduler cannot be asked. It is only a hint for cutting work into chunks.

    Raises
    ------
    RuntimeError
        If the scheduler of ``dask:ADDRESS`` cannot be reached (the pool is started here if
        it was not yet).
    """
    ctx = current()
    if ctx is None or ctx.executor == "serial":
        return 1
    if ctx.executor == "auto":
        return cores()
    if ctx.executor.startswith("processes:"):
        return int(ctx.executor.split(":", 1)[1])
    ex = _pool(ctx.executor)
    try:
        return max(1, sum(w["nthreads"] for w in ex._client.scheduler_info()["workers"].values()))
    except Exception:  # noqa: BLE001 (only a hint for chunking)
        return cores()


# ------------------------------------------------------------------------------ pools
_POOLS: dict[str, Any] = {}
_CLOSERS: list = []
_LOCK = threading.Lock()


def _worker_init() -> None:
    """Initializer of a pool worker: Ctrl-C is left to the parent (which stops the pool; a
    kernel's shutdown interrupts its whole process group), and one BLAS thread."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    _one_blas_thread()


def _one_blas_thread() -> None:
    """One BLAS / OpenMP thread in this process.

    The variables of :data:`THREAD_VARS` are set for anything the worker starts; the BLAS
    already loaded (a spawned worker imports NumPy while unpickling its first task, possibly
    before this runs) is limited through OpenBLAS's own ``*openblas_set_num_threads*`` (what
    threadpoolctl does); silently nothing where that is not found (not Linux, another BLAS).
    """
    import ctypes

    os.environ.update({k: "1" for k in THREAD_VARS})
    import numpy  # noqa: F401 (loads the BLAS, so that its threads can be set below)

    try:
        with open("/proc/self/maps") as fh:
            paths = {ln.split()[-1] for ln in fh
                     if "openblas" in ln.lower() and ln.split()[-1].startswith("/")}
    except OSError:  # pragma: no cover (not Linux)
        return
    names = ("scipy_openblas_set_num_threads64_", "scipy_openblas_set_num_threads",
             "openblas_set_num_threads64_", "openblas_set_num_threads")
    for path in sorted(paths):
        try:
            lib = ctypes.CDLL(path)
        except OSError:
            continue
        for name in names:
            fn = getattr(lib, name, None)
            if fn is not None:
                fn(1)
                break


@contextlib.contextmanager
def _thread_env() -> Iterator[None]:
    old = {k: os.environ.get(k) for k in THREAD_VARS}
    os.environ.update({k: "1" for k in THREAD_VARS})
    try:
        yield
    finally:
        for k, v in old.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def _start(spec: str):
    if spec.startswith("processes:"):
        import multiprocessing
        from concurrent.futures import ProcessPoolExecutor

        pool = ProcessPoolExecutor(int(spec.split(":", 1)[1]),
                                   mp_context=multiprocessing.get_context("spawn"),
                                   initializer=_worker_init)

        def close(kill: bool = False) -> None:
            if kill:  # interrupted: the workers' running tasks are not waited for
                for proc in list((pool._processes or {}).values()):
                    with contextlib.suppress(Exception):
                        proc.kill()
            pool.shutdown(wait=True, cancel_futures=True)

        close.kills = True
        _CLOSERS.append(close)
        return pool
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError as exc:
        raise RuntimeError(f"executor {spec}: dask.distributed is not installed ({exc})") \
            from None

    address = spec[len("dask:"):]
    if address == "local":
        with _thread_env():  # the nanny also sets them (distributed.nanny.pre-spawn-environ)
            cluster = LocalCluster(n_workers=cores(), threads_per_worker=1, processes=True,
                                   dashboard_address=None, silence_logs=40)
        client = Client(cluster)
        _CLOSERS.append(cluster.close)
    else:
        try:
            client = Client(address, timeout=30)
        except OSError as exc:
            raise RuntimeError(f"executor dask:{address}: cannot reach the scheduler ({exc})") \
                from None
    _CLOSERS.append(client.close)
    ex = client.get_executor()
    ex._client = client  # for workers()
    return ex


def _pool(spec: str):
    with _LOCK:
        pool = _POOLS.get(spec)
        if pool is None:
            pool = _POOLS[spec] = _start(spec)
        return pool


def shutdown(kill: bool = False) -> None:
    """Stop every pool and cluster this process started (the next use starts them again).

    Parameters
    ----------
    kill : bool, default False
        Kill the process pools' workers at once instead of letting their running tasks
        finish (what an interrupt or SIGTERM of the command line does).

    Returns
    -------
    None
        Dask clients are closed before their clusters and process pools are shut down after
        their running tasks finish (queued tasks are cancelled; with ``kill``, the workers
        are killed first); an error while closing one of them is ignored. It is also
        registered with ``atexit``.
    """
    with _LOCK:
        _POOLS.clear()
        closers = _CLOSERS[:]
        _CLOSERS.clear()
    for close in reversed(closers):  # client before cluster
        with contextlib.suppress(Exception):
            if kill and getattr(close, "kills", False):
                close(kill=True)
            else:
                close()


atexit.register(shutdown)


# ------------------------------------------------------------------------- parameters
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
