"""``tools/run_tests.py``'s scheduler: every stage runs once, none before its inputs."""

from __future__ import annotations

import sys
import threading
import time
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tools"))
import run_tests  # noqa: E402


def _jobs(log, seconds):
    lock = threading.Lock()

    def make(name):
        def fn():
            with lock:
                log.append(("start", name))
            time.sleep(seconds[name])
            with lock:
                log.append(("end", name))
            return run_tests.Stage(name, name != "b", seconds[name])
        return fn

    return [run_tests.Job("a", make("a")), run_tests.Job("b", make("b")),
            run_tests.Job("c", make("c"), after=("a",)), run_tests.Job("d", make("d")),
            run_tests.Job("e", make("e"), after=("a", "c"))]


def test_the_order_and_the_dependencies_on_two_workers():
    log: list = []
    seconds = {"a": 0.3, "b": 0.05, "c": 0.05, "d": 0.05, "e": 0.01}
    stages = run_tests.schedule(_jobs(log, seconds), 2)
    assert [s.name for s in stages] == list("abcde")  # the list order, whatever ran first
    assert [s.ok for s in stages] == [True, False, True, True, True]  # b failed, all ran
    pos = {ev: i for i, ev in enumerate(log)}
    assert pos[("start", "b")] < pos[("start", "d")]  # list order among the ready ones
    assert pos[("end", "a")] < pos[("start", "c")] < pos[("end", "c")] < pos[("start", "e")]
    assert pos[("start", "d")] < pos[("start", "c")]  # d did not wait for a: c could not start


def test_one_worker_runs_them_one_after_the_other_in_order():
    log: list = []
    seconds = dict.fromkeys("abcde", 0.01)
    run_tests.schedule(_jobs(log, seconds), 1)
    assert [name for ev, name in log if ev == "start"] == list("abcde")
    assert all(log[2 * i][1] == log[2 * i + 1][1] for i in range(5))  # never two at once


def test_every_heavy_test_exists():
    """tests/conftest.py's HEAVY names test functions that exist (a renamed test would
    otherwise silently run on every Python again)."""
    import ast

    from conftest import HEAVY

    tests = Path(__file__).resolve().parent
    for name in HEAVY:
        file, func = name.split("::")
        tree = ast.parse((tests / file).read_text())
        assert any(isinstance(n, ast.FunctionDef) and n.name == func for n in tree.body), name


def test_figure_helpers_read_the_runs_shared_cache(tmp_path, monkeypatch):
    """make test's library stage reads an entry that nbval's kernels computed (the run's compute
    cache) instead of computing it again; without the variable it computes."""
    import figure_helpers

    from fusioncenter import _cache, figures

    entry = figures.get("mo2015-rate")
    key = {"id": entry.id, "profile": "fast", "seed": entry.seed, "overrides": []}
    _cache.dump(tmp_path / f"{entry.id}.fast.{entry.seed}.npz", {"stored by": "a kernel"}, key)
    monkeypatch.setenv(figure_helpers.SHARED_CACHE, str(tmp_path))
    figure_helpers.cached_data.cache_clear()
    try:
        assert figure_helpers.cached_data(entry.id) == {"stored by": "a kernel"}
    finally:
        figure_helpers.cached_data.cache_clear()
    monkeypatch.delenv(figure_helpers.SHARED_CACHE)
    assert "stored by" not in figure_helpers.cached_data(entry.id)


def test_nbval_shards_cover_every_notebook_once_in_the_asked_ratio():
    from chapters import golden_path, notebook_chapters

    doc_of = {str(golden_path(d).relative_to(run_tests.ROOT)): d for d in notebook_chapters()}
    every = sorted(doc_of)

    def seconds(path):
        return run_tests.NBVAL_SECONDS.get(doc_of[path], run_tests.DEFAULT_SECONDS)

    for n, shares in ((1, None), (2, None), (2, (0.5, 0.5)), (3, None)):
        shards = run_tests.nbval_shards(n, shares)
        assert sorted(p for s in shards for p in s) == every  # each exactly once
        for gathering in run_tests.GATHERING:
            path = str(golden_path(gathering).relative_to(run_tests.ROOT))
            assert any(s[-1] == path for s in shards)  # last in its shard
        if n == 2:
            a, b = (sum(map(seconds, s)) for s in shards)
            want = run_tests.SHARD_1_SHARE if shares is None else 0.5
            assert abs(a / (a + b) - want) < 0.03, (a, b)
    with pytest.raises(ValueError, match="shares"):
        run_tests.nbval_shards(2, (1.0,))
    with pytest.raises(ValueError, match="shares"):
        run_tests.nbval_shards(2, (1.0, 0.0))


def test_optional_stages_are_named_or_refused(capsys):
    assert run_tests._optional([]) == set()
    assert run_tests._optional(["--with=student"]) == {"student"}
    assert run_tests._optional(["--with", "pythons,student"]) == {"pythons", "student"}
    with pytest.raises(ValueError, match="--with: unknown stage"):
        run_tests._optional(["--with", "pythons docs"])
    with pytest.raises(ValueError, match="unknown argument '--fast'"):
        run_tests._optional(["--fast"])
    assert run_tests.main(["--with", "docs"]) == 2  # refused before any stage starts
    assert "optional stages are ['pythons', 'student']" in capsys.readouterr().err
