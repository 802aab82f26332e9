"""book/_ext/pybtex_plugins.py: pybtex's plugin lookups read the entry points once."""

from __future__ import annotations

import importlib.metadata
import sys
from pathlib import Path

import pybtex.plugin

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "book" / "_ext"))
import pybtex_plugins  # noqa: E402  (book/_ext is not a package)


def test_plugins_are_the_same_and_looked_up_once(monkeypatch):
    before = {(g, n): pybtex.plugin.find_plugin(g, n) for g, n in
              [("pybtex.style.formatting", "plain"), ("pybtex.backends", "plaintext"),
               ("pybtex.style.formatting", "unsrt")]}
    monkeypatch.setattr(pybtex.plugin, "entry_points", pybtex.plugin.entry_points)
    calls = []
    real = importlib.metadata.entry_points

    def counting(**kw):
        calls.append(kw)
        return real(**kw)

    monkeypatch.setattr(pybtex.plugin, "entry_points", counting)
    pybtex_plugins.setup(None)
    for _ in range(3):
        after = {key: pybtex.plugin.find_plugin(*key) for key in before}
        assert after == before
    assert len(calls) == len(before)  # one reading per (group, name), not one per request
