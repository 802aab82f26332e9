"""The registry's index: every entry's summary and the module that registers it, without
importing any figure module.

``python -m fusioncenter list``, ``params ID`` and a misspelt id read the index
(``_index.json`` next to this file) instead of importing the figure modules (seconds of NumPy,
SciPy and matplotlib imports), and :func:`fusioncenter.figures.registry.get` imports only the
module of the entry asked for. The index records the library's source fingerprint
(:func:`fusioncenter._cache.fingerprint`): when the source has changed since it was written it is
not used (everything is imported, as without an index) and it is written again where the
package folder is writable. The registry writes it
(:func:`fusioncenter.figures.registry.build_index`, run by ``python -m fusioncenter.figures``);
``python -m fusioncenter.figures --check`` fails when the committed file is out of date (a
stage of ``make test``, before any test rewrites it); ``tests/test_registry_cli.py`` checks
that it matches the registry. This module reads and writes the file only: it imports neither
the registry nor any figure module.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

PATH = Path(__file__).with_name("_index.json")


def write(index: dict) -> None:
    """Write ``index`` (atomically; silently nothing where the folder is not writable).

    Parameters
    ----------
    index : dict
        ``{"source": fingerprint, "entries": rows}``
        (:func:`fusioncenter.figures.registry.build_index`).
    """
    tmp = PATH.with_name(f"{PATH.name}.{os.getpid()}.tmp")
    try:
        tmp.write_text(json.dumps(index, indent=0, ensure_ascii=False) + "\n",
                       encoding="utf-8")
        tmp.replace(PATH)
    except OSError:
        tmp.unlink(missing_ok=True)


_CURRENT: list = []


def load() -> list[dict] | None:
    """The index's entries if the index is current (same source fingerprint).

    Returns
    -------
    list of dict or None
        One row per entry (its summary, ``module`` and ``settable_lines``); ``None`` if the
        file is missing, unreadable or written from another source.
    """
    if _CURRENT:
        return _CURRENT[0]
    from fusioncenter import _cache

    try:
        index = json.loads(PATH.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    if not isinstance(index, dict) or index.get("source") != _cache.fingerprint():
        return None
    _CURRENT.append(index["entries"])
    return index["entries"]


def find(entry_id: str) -> dict | None:
    """The index row of one entry.

    Parameters
    ----------
    entry_id : str
        The id looked up (the index is read once per process).

    Returns
    -------
    dict or None
        Its row (:func:`load`); ``None`` if no row has that id, or the index is not current.
    """
    rows = load()
    if rows is None:
        return None
    return next((r for r in rows if r["id"] == entry_id), None)
