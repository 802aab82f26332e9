"""Shared body of the registry-entry tests (``tests/test_figures_*.py``).

An entry's fast-profile data are computed once per test session; ``data`` hands out a deep
copy, so a test may corrupt it to show that a check fails.

With the environment variable :data:`SHARED_CACHE` naming a folder (``make test``: the run's
compute cache, filled by nbval's kernels executing the chapters with the same library, profile
and seeds), :func:`cached_data` reads an entry found there instead of computing it again, and
stores one it computes. Only this helper uses it: the tests of seeding, executors and
overrides call ``run_compute`` themselves and always compute.
"""

from __future__ import annotations

import copy
import functools
import os
from unittest import mock

import matplotlib.figure
import matplotlib.pyplot as plt

from fusioncenter import figures
from fusioncenter.figures.registry import CACHE_ENV

SHARED_CACHE = "FUSIONCENTER_TEST_SHARED_CACHE"


@functools.cache
def cached_data(entry_id: str) -> dict:
    """The entry's fast-profile data (shared: do not modify; use :func:`data`)."""
    shared = os.environ.get(SHARED_CACHE, "").strip()
    with mock.patch.dict(os.environ, {CACHE_ENV: shared} if shared else {}):
        return figures.get(entry_id).run_compute("fast")


def data(entry_id: str) -> dict:
    return copy.deepcopy(cached_data(entry_id))


def failed(entry_id: str, d: dict) -> list[str]:
    """Names of the entry's claims that fail on ``d``."""
    return [c.name for c in figures.get(entry_id).run_checks(d) if not c]


def fails_after(entry_id: str, corrupt, fragment: str) -> bool:
    """Corrupt a copy of the data in place with ``corrupt(d)``; is a claim named with
    ``fragment`` then failing?"""
    d = data(entry_id)
    corrupt(d)
    return any(fragment in name for name in failed(entry_id, d))


def check_entry(entry_id: str, *, paper: str, chapter_prefix: str, units: bool = True,
                min_claims: int = 3) -> None:
    """The entry computes (fast), plots a Figure whose data axes are labelled (with units in
    parentheses on the y axis when ``units``) and passes at least ``min_claims`` claims."""
    entry = figures.get(entry_id)
    assert entry.paper == paper and entry.status != "not-started"
    assert entry.chapter.startswith(chapter_prefix) and entry.label.startswith(f"sec-{entry_id}")
    d = data(entry_id)
    fig = entry.run_plot(d)
    try:
        assert isinstance(fig, matplotlib.figure.Figure)
        axes = [ax for ax in fig.get_axes() if ax.has_data()]
        assert axes
        for ax in axes:
            assert ax.get_xlabel() and ax.get_ylabel()
            if units:
                assert "(" in ax.get_ylabel(), f"{entry_id}: no unit in {ax.get_ylabel()!r}"
    finally:
        plt.close(fig)
    claims = entry.run_checks(d)
    assert len(claims) >= min_claims and all(claims), [c for c in claims if not c]
