"""Plot style and profile selection."""

from __future__ import annotations

import matplotlib.colors as mcolors
import numpy as np
import pytest

from fusioncenter import book, plotting
from fusioncenter.profile import by_profile, current_profile


def test_finish_rejects_unlabelled_axes():
    fig, ax = plotting.subplots()
    ax.plot([0, 1], [0, 1])
    with pytest.raises(ValueError, match="lacks a label"):
        plotting.finish(fig)
    ax.set(xlabel="time step", ylabel="variance (m$^2$)")
    assert plotting.finish(fig, title="t") is fig


def test_palette_is_okabe_ito_and_distinct():
    rgb = np.array([mcolors.to_rgb(c) for c in plotting.OKABE_ITO])
    assert len({tuple(c) for c in rgb}) == len(rgb) == 8
    fig, ax = plotting.subplots()
    lines = [ax.plot([0, 1], [i, i])[0] for i in range(3)]
    assert [ln.get_color().lower() for ln in lines] == [c.lower() for c in plotting.OKABE_ITO[:3]]
    assert len({ln.get_linestyle() for ln in lines}) == 3  # distinguishable without colour


def test_errorband_draws_band():
    fig, ax = plotting.subplots()
    x = np.arange(5.0)
    plotting.errorband(ax, x, x, np.ones(5), label="m")
    assert len(ax.collections) == 1


def test_profile_from_environment(monkeypatch, capsys):
    monkeypatch.delenv("FUSIONCENTER_PROFILE", raising=False)
    assert current_profile() == "fast"
    monkeypatch.setenv("FUSIONCENTER_PROFILE", "paper")
    assert current_profile() == "paper"
    assert book.setup() == "paper"
    assert "profile: paper" in capsys.readouterr().out
    assert by_profile("paper", fast=1, paper=2) == 2
    monkeypatch.setenv("FUSIONCENTER_PROFILE", "quick")
    with pytest.raises(ValueError, match="FUSIONCENTER_PROFILE"):
        current_profile()
