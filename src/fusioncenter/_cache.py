"""The compute cache's file format and the library's source fingerprint.

A cache file is a NumPy ``.npz`` archive read with ``allow_pickle=False``: loading it can never
run code. It holds the stored object's arrays (``a0``, ``a1``, ...) and one record ``meta``
(UTF-8 JSON as a ``uint8`` array) with

* ``key``: what the data were computed from (the caller's key, the library's version and
  :func:`fingerprint` of its source, NumPy's version); a file whose key differs is stale and
  is computed again, never served;
* ``tree``: the object's structure (dicts, lists, tuples, numbers, strings, NumPy scalars and
  arrays by index, and the library's own dataclasses by class name and attributes);
* ``digest``: SHA-256 over the key, the tree and every array's dtype, shape and bytes. A file
  whose digest does not match (edited by hand, truncated, planted) is refused.

Only classes defined in :mod:`fusioncenter` are ever rebuilt (attributes set directly, no
``__init__`` run), so a planted file cannot name an arbitrary class.
"""

from __future__ import annotations

import contextlib
import dataclasses
import functools
import hashlib
import importlib
import io
import json
import math
import os
import sys
import threading
from pathlib import Path

FORMAT = 1
SUFFIX = ".npz"
#: Environment variable naming a folder where
#: :meth:`fusioncenter.figures.registry.Entry.run_compute` keeps its results.
CACHE_ENV = "FUSIONCENTER_COMPUTE_CACHE"


class ComputeCacheError(OSError):
    """A file of the compute cache (:data:`CACHE_ENV`) cannot be read back."""


class CacheFormatError(ValueError):
    """A cache file that cannot be trusted: corrupt, tampered with, or not written by us."""


class Unstorable(TypeError):
    """An object the cache format cannot hold (then it is not cached)."""


@functools.lru_cache(maxsize=1)
def fingerprint() -> str:
    """SHA-256 of the library's version and of every ``.py`` file of its source.

    Returns
    -------
    str
        64 hex digits; any change of the library's code gives another value (the same inputs
        as the book's build fingerprint of ``src``, restricted to the package's Python files).
    """
    from fusioncenter import __version__

    root = Path(__file__).resolve().parent
    h = hashlib.sha256(f"fusioncenter {__version__}\n".encode())
    for f in sorted(root.rglob("*.py")):
        if "__pycache__" in f.parts:
            continue
        h.update(f.relative_to(root).as_posix().encode() + b"\0" + f.read_bytes() + b"\0")
    return h.hexdigest()


def full_key(key: dict) -> dict:
    """``key`` with the library's version, source fingerprint and NumPy's version added."""
    import numpy as np

    from fusioncenter import __version__

    full = {**key, "version": __version__, "source": fingerprint(), "numpy": np.__version__}
    return json.loads(json.dumps(full, sort_keys=True, default=str))  # as read back


# ---------------------------------------------------------------------------- encoding
def _encode(value, arrays: list):
    import numpy as np

    if isinstance(value, np.ndarray | np.generic):  # before float: np.float64 is a float
        arr = np.asarray(value)
        if arr.dtype.hasobject or arr.dtype.kind == "V":
            raise Unstorable(f"array of dtype {arr.dtype}")
        arrays.append(arr)
        return {"t": "array" if isinstance(value, np.ndarray) else "scalar",
                "i": len(arrays) - 1}
    if value is None or isinstance(value, bool | str):
        return value
    if isinstance(value, int):
        return {"t": "int", "v": str(value)}
    if isinstance(value, float):
        value = float(value)
        return {"t": "float", "v": value.hex() if math.isfinite(value) else repr(value)}
    if isinstance(value, complex):
        return {"t": "complex", "v": [_encode(value.real, arrays), _encode(value.imag, arrays)]}
    if isinstance(value, dict):
        return {"t": "dict", "k": [_encode(k, arrays) for k in value],
                "v": [_encode(v, arrays) for v in value.values()]}
    if isinstance(value, list | tuple):
        return {"t": type(value).__name__, "v": [_encode(v, arrays) for v in value]}
    cls = type(value)
    if dataclasses.is_dataclass(value) and cls.__module__.split(".")[0] == "fusioncenter" \
            and hasattr(value, "__dict__"):
        return {"t": "obj", "c": f"{cls.__module__}:{cls.__qualname__}",
                "d": _encode(dict(vars(value)), arrays)}
    raise Unstorable(f"a value of type {cls.__module__}.{cls.__qualname__}")


def _decode(node, arrays: dict):

    if node is None or isinstance(node, bool | str):
        return node
    if not isinstance(node, dict) or "t" not in node:
        raise CacheFormatError(f"unexpected node {node!r:.60}")
    t = node["t"]
    if t == "int":
        return int(node["v"])
    if t == "float":
        v = node["v"]
        return float(v) if v in ("nan", "inf", "-inf") else float.fromhex(v)
    if t == "complex":
        re, im = (_decode(x, arrays) for x in node["v"])
        return complex(re, im)
    if t in ("array", "scalar"):
        arr = arrays[f"a{int(node['i'])}"]
        return arr if t == "array" else arr[()]
    if t == "dict":
        return {_decode(k, arrays): _decode(v, arrays)
                for k, v in zip(node["k"], node["v"], strict=True)}
    if t in ("list", "tuple"):
        items = [_decode(v, arrays) for v in node["v"]]
        return items if t == "list" else tuple(items)
    if t == "obj":
        modname, _, qual = str(node["c"]).partition(":")
        if modname.split(".")[0] != "fusioncenter":
            raise CacheFormatError(f"class {node['c']!r} is not the library's")
        cls = importlib.import_module(modname)
        for part in qual.split("."):
            cls = getattr(cls, part)
        if not (isinstance(cls, type) and dataclasses.is_dataclass(cls)):
            raise CacheFormatError(f"{node['c']!r} is not one of the library's dataclasses")
        obj = object.__new__(cls)
        obj.__dict__.update(_decode(node["d"], arrays))
        return obj
    raise CacheFormatError(f"unknown node type {t!r}")


def _digest(meta: dict, arrays) -> str:
    h = hashlib.sha256(json.dumps(meta, sort_keys=True).encode())
    for arr in arrays:
        h.update(f"\0{arr.dtype.str}{arr.shape}\0".encode())
        h.update(arr.tobytes())
    return h.hexdigest()


def dump(path: Path, data, key: dict) -> None:
    """Write ``data`` to ``path`` under ``key`` (atomically: a temporary file renamed).

    Raises
    ------
    Unstorable
        If ``data`` holds something the format cannot store (nothing is written).
    """
    import numpy as np

    arrays: list = []
    meta = {"format": FORMAT, "key": full_key(key), "tree": _encode(data, arrays)}
    meta["digest"] = _digest(meta, arrays)
    payload = {f"a{i}": a for i, a in enumerate(arrays)}
    payload["meta"] = np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8)
    buf = io.BytesIO()
    np.savez(buf, **payload)
    tmp = path.with_name(f"{path.name}.{os.getpid()}.{threading.get_ident()}.tmp")
    tmp.write_bytes(buf.getvalue())
    tmp.replace(path)


def load(path: Path, key: dict):
    """The object stored in ``path`` under ``key``.

    Returns
    -------
    tuple
        ``(True, data)`` when the file holds data computed under ``key`` by this library
        (same version and source), ``(False, None)`` when it is stale (another key).

    Raises
    ------
    CacheFormatError
        If the file is not a cache file of this format or fails its integrity check.
    OSError
        If it cannot be read.
    """
    import numpy as np

    raw = path.read_bytes()
    try:
        with np.load(io.BytesIO(raw), allow_pickle=False) as z:
            arrays = {name: z[name] for name in z.files}
        meta = json.loads(arrays.pop("meta").tobytes().decode())
    except (ValueError, KeyError, OSError, EOFError, UnicodeDecodeError) as exc:
        raise CacheFormatError(f"not a compute-cache file ({type(exc).__name__}: "
                               f"{str(exc)[:80]})") from None
    if not isinstance(meta, dict) or meta.get("format") != FORMAT:
        raise CacheFormatError("not a compute-cache file of this format")
    digest = meta.pop("digest", None)
    try:
        ordered = [arrays[f"a{i}"] for i in range(len(arrays))]
    except KeyError:
        raise CacheFormatError("arrays missing or renamed") from None
    if digest != _digest(meta, ordered):
        raise CacheFormatError("its integrity check failed (the file was changed after it "
                               "was written)")
    if meta.get("key") != full_key(key):
        return False, None
    try:
        return True, _decode(meta["tree"], arrays)
    except (CacheFormatError, KeyError, TypeError, ValueError, AttributeError,
            ImportError) as exc:
        raise CacheFormatError(f"its contents cannot be decoded ({exc})") from None


@contextlib.contextmanager
def locked(path: Path):
    """An exclusive ``flock`` on ``path`` (created, removed afterwards): processes computing
    the same cache file take turns, so the second one reads what the first stored. (A process
    that opened the file just before its removal may compute it once more: harmless, the
    bytes are the same.)

    Parameters
    ----------
    path : pathlib.Path
        The lock file (its folder must exist).

    Yields
    ------
    None
        While the lock is held.
    """
    import fcntl

    with path.open("a") as fh:
        fcntl.flock(fh, fcntl.LOCK_EX)
        try:
            yield
        finally:
            path.unlink(missing_ok=True)
            fcntl.flock(fh, fcntl.LOCK_UN)


def distrust(path: Path, why: str) -> None:
    """Warn on stderr that the cache file ``path`` is not used, and why."""
    print(f"warning: compute cache file {path} not used: {why}; computing again",
          file=sys.stderr)


def read_cached(path: Path, key: dict) -> tuple:
    """What a compute-cache file holds, if it was written under ``key`` by this library.

    Parameters
    ----------
    path : pathlib.Path
        A file written by :func:`write_cached`.
    key : dict
        What the data are computed from (JSON-able); the library's version and source
        fingerprint are added (:func:`full_key`).

    Returns
    -------
    tuple
        ``(True, data)`` for a sound file of the same key; ``(False, None)`` when the file is
        stale (another key, another version of the library), or fails its integrity check,
        or is not a cache file at all (then a warning naming it goes to stderr): the caller
        computes again and overwrites it. Nothing in the file is ever executed.

    Raises
    ------
    ComputeCacheError
        If the file exists but cannot be read (permissions, an I/O error).
    """
    try:
        return load(path, key)
    except CacheFormatError as exc:
        distrust(path, str(exc))
        return False, None
    except OSError as exc:
        raise ComputeCacheError(
            f"compute cache file {path} is unreadable ({type(exc).__name__}: {exc}); delete "
            f"it (or the folder {CACHE_ENV} names) and run again") from None


def write_cached(path: Path, data, key: dict) -> None:
    """Store ``data`` in a compute-cache file under ``key``, atomically (a temporary file
    renamed), so that a reader never sees half a file. Data the format cannot hold (an
    object that is neither plain data nor one of the library's dataclasses) are not stored.

    Parameters
    ----------
    path : pathlib.Path
        The file (its folder must exist).
    data : object
        Dicts, lists, tuples, numbers, strings, NumPy arrays and scalars, the library's
        dataclasses.
    key : dict
        As in :func:`read_cached`.
    """
    try:
        dump(path, data, key)
    except Unstorable as exc:
        print(f"warning: {path.name} not stored in the compute cache (cannot store {exc})",
              file=sys.stderr)
