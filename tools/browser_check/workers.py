"""Browsers side by side: how many, and what a ``--part`` child hands back to its parent.

:func:`browser_check.driver.check_site` runs :func:`default_workers` browsers; each one but
the first is a child process (``tools/browser_check <site> --part K/N``) that checks every
N-th page from the K-th and writes its findings with :func:`write_part`; the parent reads
them back with :func:`read_part`.
"""

from __future__ import annotations

import json
import os
from dataclasses import asdict
from pathlib import Path

from .accessibility import AXE_STATS, merge_axe_stats
from .figures import FIGURE_STATS
from .layout import LayoutResult
from .result import PageResult

#: Browsers that check the pages side by side: ``FUSIONCENTER_BROWSER_WORKERS``, else 2 (one
#: per core of the 2-core machine). One Chromium uses about 1.3 cores on this check (218 s of
#: CPU in 173 s on the fast site, 114 pages printed too), so in ``make test``, where the library
#: stage shares the cores, a second browser takes up the core the first leaves idle.
WORKERS_ENV = "FUSIONCENTER_BROWSER_WORKERS"


def default_workers() -> int:
    """:data:`WORKERS_ENV` if set (a positive integer), else 2."""
    raw = os.environ.get(WORKERS_ENV, "").strip()
    if not raw:
        return 2
    try:
        n = int(raw)
    except ValueError:
        n = 0
    if n < 1:
        raise ValueError(f"{WORKERS_ENV} must be a positive integer, got {raw!r}")
    return n


PART_FILE = "part.json"


def write_part(out: Path, results, layouts, problems, lines) -> None:
    """What a ``--part`` child found, for :func:`check_site` (JSON, written last)."""
    out.mkdir(parents=True, exist_ok=True)
    data = {"results": [asdict(r) for r in results], "layouts": [asdict(r) for r in layouts],
            "problems": problems, "figure_stats": FIGURE_STATS, "axe_stats": AXE_STATS,
            "lines": lines}
    tmp = out / (PART_FILE + ".tmp")
    tmp.write_text(json.dumps(data), encoding="utf-8")
    tmp.replace(out / PART_FILE)


def read_part(out: Path):
    """``(results, layouts, problems, figure stats, log lines)`` of a child, or ``None``;
    its :data:`AXE_STATS` are added to this process's."""
    try:
        data = json.loads((out / PART_FILE).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    merge_axe_stats(data.get("axe_stats", {}))
    return ([PageResult(**r) for r in data["results"]],
            [LayoutResult(**r) for r in data["layouts"]],
            data["problems"], data["figure_stats"], data["lines"])
