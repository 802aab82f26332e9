"""The command line's data formats: strict JSON (:func:`jsonable`, :func:`dumps`) and long-format
CSV (:func:`write_csv`) of what a registry ``compute`` returns (also used by the book's
downloads and the explorable figures)."""

from __future__ import annotations

import contextlib
import csv
import json
import math
import sys

__all__ = ["NONFINITE_JSON", "jsonable", "dumps", "write_csv"]

#: How non-finite floats are written in JSON (strict JSON has no NaN or infinity).
NONFINITE_JSON = {"nan": "NaN", "inf": "Infinity", "-inf": "-Infinity"}


def _float(x: float):
    if math.isfinite(x):
        return x
    return NONFINITE_JSON["nan" if math.isnan(x) else ("inf" if x > 0 else "-inf")]


def jsonable(value):
    """``value`` as plain JSON types: arrays to lists, NumPy scalars to Python numbers,
    non-finite floats to the strings of :data:`NONFINITE_JSON`, complex numbers to
    ``[re, im]``; anything else that JSON cannot hold to its ``str``.

    Parameters
    ----------
    value : object
        Typically the dict a registry ``compute`` returns; nested dicts, lists, tuples, sets
        and arrays are converted recursively.

    Returns
    -------
    object
        A ``dict`` (keys converted with ``str``), ``list``, ``str``, ``int``, ``float``
        (finite), ``bool`` or ``None``, which ``json.dumps(..., allow_nan=False)`` accepts.
        Tuples and sets become lists (a set in its iteration order).
    """
    np = sys.modules.get("numpy")  # no NumPy object exists before NumPy is imported

    if isinstance(value, dict):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple | set | frozenset):
        return [jsonable(v) for v in value]
    if np is not None and isinstance(value, np.ndarray):
        return jsonable(value.tolist())
    if np is not None and isinstance(value, np.generic):
        return jsonable(value.item())
    if isinstance(value, bool) or value is None or isinstance(value, str):
        return value
    if isinstance(value, int):
        return value
    if isinstance(value, float):
        return _float(value)
    if isinstance(value, complex):
        return [_float(value.real), _float(value.imag)]
    return str(value)


def dumps(value) -> str:
    """Strict JSON of :func:`jsonable` applied to ``value`` (``allow_nan=False``).

    Parameters
    ----------
    value : object
        What to encode (see :func:`jsonable`).

    Returns
    -------
    str
        One line of JSON (RFC 8259): no ``NaN`` or ``Infinity`` tokens.
    """
    return json.dumps(jsonable(value), allow_nan=False)


def write_csv(data: dict, path, run: dict | None = None) -> None:
    """Long format ``name,index,value``: one row per element of every array or scalar.

    ``index`` is the element's position (``i`` or ``i;j;...`` for arrays of several axes), empty
    for scalars. Non-numeric values are written as JSON text; non-finite floats as ``nan``,
    ``inf``, ``-inf``. With ``run``, its items come first as rows ``_run,KEY,VALUE``.

    Parameters
    ----------
    data : dict
        Name to value, as a registry ``compute`` returns. Each value goes through
        ``numpy.asarray``: a number or a numeric (or string) array gives one row per element;
        a value NumPy can only hold as an ``object`` array (a dict, ``None``, a ragged list)
        gives one row whose value is :func:`dumps` of it.
    path : str or pathlib.Path or file
        The file to write (created or overwritten), or an open text file (``sys.stdout``).
    run : dict, optional
        How the data were computed (the ``"_run"`` record of the command line): a ``str`` or
        ``int`` value is written as it is, anything else as :func:`dumps` of it.

    Returns
    -------
    None
        The CSV file is written, with the header row ``name,index,value``.

    Raises
    ------
    OSError
        If ``path`` cannot be opened for writing.
    """
    import numpy as np

    with contextlib.nullcontext(path) if hasattr(path, "write") else \
            open(path, "w", newline="") as fh:
        w = csv.writer(fh, lineterminator="\n" if hasattr(path, "write") else "\r\n")
        w.writerow(["name", "index", "value"])
        for key, value in (run or {}).items():
            w.writerow(["_run", key, value if isinstance(value, str | int) else dumps(value)])
        for name, value in data.items():
            arr = np.asarray(value)
            if arr.dtype == object:
                w.writerow([name, "", dumps(value)])
            elif arr.ndim == 0:
                w.writerow([name, "", arr.item()])
            else:
                for idx in np.ndindex(arr.shape):
                    w.writerow([name, ";".join(map(str, idx)), arr[idx].item()])
