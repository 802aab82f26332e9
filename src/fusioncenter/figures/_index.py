"""The registry's index: every entry's summary and the module that registers it, without
importing any figure module.

``python -m fusioncenter list``, ``params ID`` and a misspelt id read the index
(``_index.json`` next to this file) instead of importing the figure modules (seconds of NumPy,
SciPy and matplotlib imports), and :func:`fusioncenter.figures.registry.get` imports only the
module of the entry asked for. The index records the library's source fingerprint
(:func:`fusioncenter._cache.fingerprint`): when the source has changed since it was written it is
not used (everything is imported, as without an index) and it is written again where the
package folder is writable. ``python -m fusioncenter.figures._index`` rewrites it
(:func:`fusioncenter.figures.registry.build_index`), ``--check`` fails when the committed file is
out of date (a stage of ``make test``, before any test rewrites it);
``tests/test_registry_cli.py`` checks that it matches the registry.
"""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path

PATH = Path(__file__).with_name("_index.json")


def write(index: dict) -> None:
    """Write ``index`` (atomically; silently nothing where the folder is not writable)."""
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


def find(entry_id: str) -> dict | None:
    """The index row of ``entry_id`` (``None``: no such id, or no current index)."""
    rows = load()
    if rows is None:
        return None
    return next((r for r in rows if r["id"] == entry_id), None)


if __name__ == "__main__":  # a script, not a dependency of the module
    if sys.argv[1:] == ["--check"]:  # make test's stage "index": the committed file is current
        if load() is None:
            print(f"error: {PATH} is out of date (the library's source changed since it was "
                  "written): run `python -m fusioncenter.figures._index` and commit it",
                  file=sys.stderr)
            sys.exit(1)
        print(f"{PATH.name}: current ({len(load() or [])} entries)", file=sys.stderr)
        sys.exit(0)
    import importlib

    importlib.import_module("fusioncenter.figures.registry").build_index()
    print(f"wrote {PATH} ({len(load() or [])} entries)", file=sys.stderr)
