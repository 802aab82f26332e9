"""The registry of figures and tables, and the command line that regenerates them."""

from __future__ import annotations

import csv
import json
import subprocess
import sys

import matplotlib.figure
import numpy as np
import pytest
from figure_helpers import data as fast_data

from fusioncenter import figures
from fusioncenter.cli import main
from fusioncenter.figures.scorecard import (
    scorecard_markdown,
    status_counts,
    status_rows,
    status_sentence,
)

OUR_OWN = {"background-riccati", "background-kf-montecarlo", "mo2015-rate", "mo2015-tradeoff",
           "mo2015-tracking"}


def test_registry_ids_are_exactly_the_papers_plus_our_own():
    from fusioncenter.figures.registry import own_ids

    own = own_ids()
    assert OUR_OWN <= own
    assert not own & set(figures.PAPER_IDS)
    expected = set(figures.PAPER_IDS) | own
    assert set(figures.ids()) == expected
    assert len(figures.ids()) == len(expected)  # no duplicates
    for entry_id in own:
        assert figures.get(entry_id).paper in {entry_id.split("-")[0], "book"}, entry_id
    assert len(figures.PAPER_IDS) == 4 + 10 + 10 + 3


def test_paper_ids_follow_the_papers():
    ids = set(figures.PAPER_IDS)
    assert {f"dey2009-fig{i}" for i in range(1, 5)} <= ids
    assert {"leong2011-fig3a", "leong2011-fig6b", "zheng2014-fig10", "zheng2014-table3"} <= ids


def test_statuses_are_honest():
    for e in figures.entries():
        assert e.status in figures.STATUSES
        if e.compute is None:
            assert e.status == "not-started", e.id
        if e.status != "not-started":
            assert e.plot is not None and e.checks is not None, e.id
        assert e.caption and e.chapter.startswith("book/")


def test_entry_validation():
    with pytest.raises(ValueError, match="unknown paper"):
        figures.Entry(id="x", paper="nobody2020", kind="figure", caption="c", chapter="book/x")
    with pytest.raises(ValueError, match="needs compute"):
        figures.Entry(id="x", paper="book", kind="figure", caption="c", chapter="book/x",
                      status="reproduced")
    with pytest.raises(ValueError, match="duplicate"):
        figures.register(figures.get("background-riccati"))


def test_every_paper_figure_has_a_real_entry():
    for entry_id in figures.PAPER_IDS:
        entry = figures.get(entry_id)
        assert entry.status in ("reproduced", "differs"), entry_id
        assert entry.compute is not None and entry.plot is not None and entry.checks is not None
        assert entry.paper == entry_id.split("-")[0]


def test_register_refuses_a_repeated_id(monkeypatch):
    from fusioncenter.figures import registry

    monkeypatch.setattr(registry, "REGISTRY", {})
    entry = figures.Entry(id="x-fig1", paper="book", kind="figure", caption="c", chapter="book/x")
    assert registry.register(entry) is entry
    assert registry.REGISTRY == {"x-fig1": entry}
    twin = figures.Entry(id="x-fig1", paper="book", kind="figure", caption="d", chapter="book/x")
    with pytest.raises(ValueError, match="duplicate"):
        registry.register(twin)
    assert registry.REGISTRY["x-fig1"] is entry


def test_unknown_id_suggests_near_matches():
    with pytest.raises(figures.UnknownEntry, match="did you mean dey2009-fig1"):
        figures.get("dey2009-fig01")


@pytest.fixture
def not_started(monkeypatch):
    """A not-started entry (every paper entry now has a compute): registered for one test."""
    from fusioncenter.figures import registry

    figures.ids()  # load the real entries first
    entry = figures.Entry(id="book-not-started", paper="book", kind="figure",
                          caption="a placeholder", chapter="book/howto")
    monkeypatch.setitem(registry.REGISTRY, entry.id, entry)
    return entry.id


def test_not_started_entry_refuses_to_compute(not_started):
    with pytest.raises(figures.EntryNotReady, match="not-started"):
        figures.get(not_started).run_compute("fast")


@pytest.mark.parametrize("entry_id", sorted(OUR_OWN))
def test_own_entries_compute_plot_and_pass_their_checks(entry_id):
    entry = figures.get(entry_id)
    data = fast_data(entry_id)  # run_compute("fast"), computed once per session (a copy)
    fig = entry.run_plot(data)
    assert isinstance(fig, matplotlib.figure.Figure)
    for ax in fig.get_axes():
        assert ax.get_xlabel() and ax.get_ylabel()
    claims = entry.run_checks(data)
    assert claims and all(claims), [c for c in claims if not c]


def test_monte_carlo_check_can_fail():
    """The claims are real: a wrong covariance is detected at the fast profile's trial count."""
    entry = figures.get("background-kf-montecarlo")
    data = entry.run_compute("fast")
    data["riccati_diag"] = data["riccati_diag"] * 1.1
    assert not all(entry.run_checks(data))


def test_compute_is_reproducible_and_seeded():
    entry = figures.get("background-kf-montecarlo")
    a, b = entry.run_compute("fast"), entry.run_compute("fast")
    assert (a["mse"] == b["mse"]).all()
    c = entry.run_compute("fast", seed=123)
    assert not (a["mse"] == c["mse"]).all()
    with pytest.raises(ValueError, match="profile"):
        entry.run_compute("huge")
    with pytest.raises(ValueError, match="seed"):
        entry.run_compute("fast", seed=-1)


def test_scorecard_of_a_paper_without_entries(monkeypatch):
    from fusioncenter.figures import registry

    figures.ids()
    monkeypatch.setattr(registry, "REGISTRY", {})
    assert "No registry entries" in scorecard_markdown("zheng2014")


def test_scorecard():
    table = scorecard_markdown()
    for entry_id in figures.ids():
        assert f"`{entry_id}`" in table
    counts = status_counts()
    assert sum(counts.values()) == len(figures.ids())
    assert "No registry entries" not in table
    with pytest.raises(ValueError, match="paper"):
        scorecard_markdown("nobody")


def test_status_sentence_and_rows():
    z = status_counts("zheng2014")
    assert status_sentence("zheng2014") == (
        f"{sum(z.values())} registry entries: {z['reproduced']} reproduced, {z['differs']} "
        "differ from the paper.")
    n = sum(status_counts("mo2015").values())
    assert status_sentence("mo2015") == f"{n} registry entries, all reproduced."
    assert "{" not in status_sentence() and "'" not in status_sentence()
    rows = status_rows()
    assert rows[-1][0] == "total" and rows[-1][1] == len(figures.ids())
    assert [r[0] for r in rows[:-1]] == [p if p != "book" else "book's own"
                                         for p in figures.PAPERS]
    assert all(r[1] == sum(r[2:]) for r in rows)
    with pytest.raises(ValueError, match="paper"):
        status_sentence("nobody")


# ------------------------------------------------------------------------------------ CLI
def test_cli_list_json(capsys):
    assert main(["list", "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)
    assert {r["id"] for r in rows} == set(figures.ids())
    assert {"id", "paper", "caption", "status", "note", "parameters"} <= set(rows[0])


def test_cli_compute_json_and_csv(capsys, tmp_path):
    assert main(["compute", "background-riccati", "--json"]) == 0
    out = capsys.readouterr()
    data = json.loads(out.out)
    assert len(data["p_scalar"]) == len(data["k"])
    assert "computing background-riccati" in out.err
    path = tmp_path / "d.csv"
    assert main(["compute", "background-kf-montecarlo", "--csv", str(path), "--seed", "3"]) == 0
    rows = list(csv.DictReader(path.open()))
    names = {r["name"] for r in rows}
    assert {"k", "mse", "stderr", "riccati_diag", "n_trials"} <= names
    assert any(r["name"] == "mse" and r["index"] == "0;0" for r in rows)


def test_cli_plot_and_verify(capsys, tmp_path):
    assert main(["plot", "background-riccati", "-o", str(tmp_path)]) == 0
    assert (tmp_path / "background-riccati.png").stat().st_size > 10_000
    assert main(["verify", "background-riccati"]) == 0
    assert "5 passed, 0 failed" in capsys.readouterr().out


@pytest.mark.parametrize(
    "argv",
    [
        ["compute", "no-such-figure", "--json"],
        ["verify", "book-not-started"],
        ["plot", "book-not-started", "-o", "/tmp/never"],
        ["compute", "background-riccati", "--json", "--seed", "-4"],
    ],
)
def test_cli_errors_exit_2_with_a_message(argv, capsys, not_started):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ")


def test_cli_bad_option_and_module_entry_point():
    proc = subprocess.run([sys.executable, "-m", "fusioncenter", "compute", "background-riccati",
                           "--profile", "huge", "--json"], capture_output=True, text=True)
    assert proc.returncode == 2 and "invalid choice" in proc.stderr
    proc = subprocess.run([sys.executable, "-m", "fusioncenter", "list"], capture_output=True,
                          text=True)
    assert proc.returncode == 0 and "dey2009-fig1" in proc.stdout


def test_compute_cache_is_used_only_when_the_build_names_a_folder(monkeypatch, tmp_path):
    calls = []

    def compute(profile, seed):
        calls.append((profile, seed))
        return {"x": np.arange(3.0) + seed, "profile": profile}

    entry = figures.Entry(id="book-cache-probe", paper="book", kind="figure", caption="c",
                          chapter="book/intro", compute=compute)
    monkeypatch.delenv(figures.registry.CACHE_ENV, raising=False)
    entry.run_compute("fast", 1)
    entry.run_compute("fast", 1)
    assert len(calls) == 2  # no folder: every call computes
    monkeypatch.setenv(figures.registry.CACHE_ENV, str(tmp_path / "cache"))
    a = entry.run_compute("fast", 1)
    b = entry.run_compute("fast", 1)
    c = entry.run_compute("fast", 2)  # another seed, another result
    d = entry.run_compute("paper", 1)  # another profile
    assert len(calls) == 5
    assert np.array_equal(a["x"], b["x"]) and b["profile"] == "fast"
    assert c["x"][0] == 2.0 and d["profile"] == "paper"
    assert sorted(p.name for p in (tmp_path / "cache").iterdir()) == [
        "book-cache-probe.fast.1.npz", "book-cache-probe.fast.2.npz",
        "book-cache-probe.paper.1.npz"]
