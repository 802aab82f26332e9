"""The registry's index: every entry's summary and the module that registers it, without
importing any figure module.

``python -m fusioncenter list``, ``params ID`` and a misspelt id read the index
(``_index.json`` next to this file) instead of importing the figure modules (seconds of NumPy,
SciPy and matplotlib imports), and :func:`fusioncenter.figures.registry.get` imports only the
module of the entry asked for. The index records the library's source fingerprint
(:func:`fusioncenter._cache.fingerprint`): when the source has changed since it was written it is
not used (everything is imported, as without an index) and it is written again where the
package folder is writable. ``python -m fusioncenter.figures._index`` rewrites it;
``tests/test_registry_cli.py`` checks that it matches the registry.
"""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path

PATH = Path(__file__).with_name("_index.json")


def build() -> dict:
    """The index of the registry as it is now (imports every figure module).

    Returns
    -------
    dict
        ``{"source": fingerprint, "entries": [summary + {"module": name, "settable_lines":
        [...]}, ...]}`` in the order of :func:`fusioncenter.figures.registry.entries`.
    """
    import importlib

    from fusioncenter import _cache
    from fusioncenter.figures import registry

    for name in registry._MODULES:
        importlib.import_module(f"fusioncenter.figures.{name}")
    module_of = registry.REGISTERED_BY
    rows = []
    for e in registry.entries():
        if e.id not in module_of:  # registered outside the modules (a test's probe)
            continue
        rows.append({**e.summary(), "module": module_of[e.id],
                     "settable_lines": e.settable_lines()})
    return {"source": _cache.fingerprint(), "entries": rows}


def write(index: dict | None = None) -> None:
    """Write the index (atomically; silently nothing where the folder is not writable)."""
    index = build() if index is None else index
    tmp = PATH.with_name(f"{PATH.name}.{os.getpid()}.tmp")
    try:
        tmp.write_text(json.dumps(index, indent=0, ensure_ascii=False) + "\n",
                       encoding="utf-8")
        tmp.replace(PATH)
    except OSError:
        tmp.unlink(missing_ok=True)


_CURRENT: list = []


def load() -> list[dict] | None:
    """The index's entries if the index is current (same source fingerprint), else ``None``."""
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


def entries() -> list[dict]:
    """Every entry's row: from the index when it is current, else built (and written)."""
    rows = load()
    if rows is None:
        index = build()
        write(index)
        rows = index["entries"]
        _CURRENT[:] = [rows]
    return rows


def find(entry_id: str) -> dict | None:
    """The index row of ``entry_id`` (``None``: no such id, or no current index)."""
    rows = load()
    if rows is None:
        return None
    return next((r for r in rows if r["id"] == entry_id), None)


if __name__ == "__main__":
    write()
    print(f"wrote {PATH} ({len(load() or [])} entries)", file=sys.stderr)
