"""The execution context: executor specs, bitwise-identical data under every executor, and the
documented parameter overrides of the registry entries."""

from __future__ import annotations

import numpy as np
import pytest

from fusioncenter import context, figures
from fusioncenter.context import Parameter
from fusioncenter.figures import dey2009, zheng2014


# ------------------------------------------------------------------------ executor specs
def test_executor_specs_are_validated_and_normalised():
    assert context.parse_executor("serial") == "serial"
    assert context.parse_executor(" auto ") == "auto"
    assert context.parse_executor(" processes:3 ") == "processes:3"
    assert context.parse_executor("processes") == f"processes:{context.cores()}"
    assert context.parse_executor("dask:local") == "dask:local"
    assert context.parse_executor("dask:tcp://10.0.0.5:8786") == "dask:tcp://10.0.0.5:8786"
    for bad in ("threads", "processes:0", "processes:x", "dask:", "", 3, None):
        with pytest.raises(ValueError, match="executor"):
            context.parse_executor(bad)


def test_default_spec_and_environment(monkeypatch):
    monkeypatch.delenv(context.EXECUTOR_ENV, raising=False)
    assert context.default_spec("fast") == "serial"
    expected = "serial" if context.cores() == 1 else "auto"
    assert context.default_spec("paper") == expected
    monkeypatch.setenv(context.EXECUTOR_ENV, "processes:2")
    assert context.default_spec("fast") == "processes:2"
    monkeypatch.setenv(context.EXECUTOR_ENV, "gpu")
    with pytest.raises(ValueError, match=context.EXECUTOR_ENV):
        context.default_spec("fast")


def test_no_executor_outside_a_context():
    assert context.current() is None and context.executor() is None and context.workers() == 1
    with context.activate(context.ExecutionContext("fast", 1, "serial")) as ctx:
        assert context.current() is ctx and context.executor() is None
    assert context.current() is None


# ------------------------------------------------------------------------ bitwise identity
def _flat(data: dict) -> dict:
    """Every value as bytes (arrays with dtype and shape), for a byte-for-byte comparison."""
    out = {}
    for k, v in data.items():
        if isinstance(v, np.ndarray):
            out[k] = (v.dtype.str, v.shape, v.tobytes())
        elif isinstance(v, float | np.floating):
            out[k] = np.float64(v).tobytes()
        else:
            out[k] = repr(v)
    return out


def _forget_fig1():
    """Compute zheng2014-fig1 again: drop its cached runs and the runs kept for the process."""
    zheng2014.linear._fig1_runs.cache_clear()
    zheng2014.runs.forget_runs()


CASES = [
    # a zheng2014 particle-filter entry and a dey2009 Monte Carlo entry, made cheap
    ("zheng2014-fig1", {"trials": 300, "particles": 40}, _forget_fig1),
    ("dey2009-fig1", {"paths": 2100, "grid_paths": 100}, None),
    ("leong2011-fig3a", {"realizations": 40}, None),
]


def test_data_are_bitwise_identical_under_every_executor():
    runs = {}
    try:
        for spec in ("serial", "processes:2", "dask:local"):
            for entry_id, over, clear in CASES:
                if clear is not None:
                    clear()  # compute again, on this executor
                runs[(entry_id, spec)] = _flat(figures.get(entry_id).run_compute(
                    "fast", executor=spec, **over))
    finally:
        context.shutdown()
    for entry_id, _, _ in CASES:
        serial = runs[(entry_id, "serial")]
        for spec in ("processes:2", "dask:local"):
            assert runs[(entry_id, spec)] == serial, (entry_id, spec)


def test_heavy_entries_use_the_executor(monkeypatch):
    """The executor is really used: with a counting executor the tasks go through it."""
    from concurrent.futures import Future

    class Counting:
        calls = 0

        def submit(self, fn, *args):
            Counting.calls += 1
            f = Future()
            f.set_result(fn(*args))
            return f

    monkeypatch.setattr(context.executors, "_pool", lambda spec: Counting())
    figures.get("dey2009-fig1").run_compute("fast", executor="processes:2", paths=2100,
                                            grid_paths=100)
    assert Counting.calls > 0


# ------------------------------------------------------------------------ overrides
def test_every_settable_parameter_is_documented_and_typed():
    n = 0
    for e in figures.entries():
        for p in e.settable:
            assert isinstance(p, Parameter) and p.doc, (e.id, p.name)
            for profile in ("fast", "paper"):
                assert p.parse(p.default_for(profile)) is not None
            n += 1
    assert n >= 40
    assert {p.name for p in figures.get("zheng2014-table1").settable} == {"trials", "particles",
                                                                         "N"}


def test_unknown_and_invalid_overrides_are_clear_errors():
    e = figures.get("zheng2014-table1")
    with pytest.raises(ValueError, match="unknown parameter.*trial.*valid keys: N, particles, "
                                         "trials"):
        e.run_compute("fast", trial=5)
    with pytest.raises(ValueError, match="parameter trials: must be >= 2"):
        e.run_compute("fast", trials=1)
    with pytest.raises(ValueError, match="parameter N: expected an integer"):
        e.run_compute("fast", N="six")
    with pytest.raises(ValueError, match="parameter trials: expected"):
        e.run_compute("fast", trials=True)
    bare = figures.Entry(id="bare", paper="book", kind="figure", caption="", chapter="",
                         compute=lambda profile, seed: {})
    with pytest.raises(ValueError, match="no overrides"):
        bare.run_compute("fast", trials=3)
    p = Parameter("l", "floats", "targets", (1.0,), minimum=0.0)
    assert p.parse("1, 2.5") == (1.0, 2.5)
    for bad in ("", "1,nan", "-1", [1, "x"]):
        with pytest.raises(ValueError, match="parameter l"):
            p.parse(bad)


def test_overrides_change_the_data_and_are_recorded():
    e = figures.get("dey2009-fig1")
    d = e.run_compute("fast", paths=1500, grid_paths=64)
    assert d["n_paths"] == 1500 and d["n_grid_paths"] == 64
    assert e.resolved_parameters("fast", {"paths": "1500"}) == {
        "paths": 1500, "grid_paths": dey2009.GRID_PATHS["fast"]}
    assert e.resolved_parameters("paper") == {"paths": dey2009.PATHS["paper"],
                                              "grid_paths": dey2009.GRID_PATHS["paper"]}


def test_model_overrides_skip_the_paper_specific_claims():
    e = figures.get("zheng2014-table1")
    claims = [figures.Claim("general", True), figures.Claim("printed", False,
                                                           paper_specific=True)]
    assert e.split_claims(claims, {"trials": 10}) == (claims, [])
    checked, skipped = e.split_claims(claims, {"N": 6})
    assert [c.name for c in checked] == ["general"] and [c.name for c in skipped] == ["printed"]
    assert e.model_overridden({"N": 6, "trials": 9}) == ["N"]


def test_compute_cache_keys_include_the_overrides(monkeypatch, tmp_path):
    calls = []

    def compute(profile, seed, **over):
        calls.append(over)
        return {"n": over.get("n", 1)}

    e = figures.Entry(id="book-override-probe", paper="book", kind="figure", caption="c",
                      chapter="book/intro", compute=compute,
                      settable=(Parameter("n", "int", "a count", 1, minimum=1),))
    monkeypatch.setenv(figures.registry.CACHE_ENV, str(tmp_path))
    assert e.run_compute("fast", 1)["n"] == 1
    assert e.run_compute("fast", 1, n=5)["n"] == 5
    assert e.run_compute("fast", 1, n="5")["n"] == 5  # same value, cached
    assert calls == [{}, {"n": 5}]
    assert len(list(tmp_path.iterdir())) == 2


def test_parallel_computes_of_one_entry_share_the_cache(monkeypatch, tmp_path):
    """Two chapters (here threads; the lock is a file lock, so processes too) needing the same
    entry at once: one computes, the other waits and reads what it stored."""
    import threading
    import time

    calls = []

    def compute(profile, seed):
        calls.append(seed)
        time.sleep(0.5)
        return {"x": np.arange(4.0)}

    e = figures.Entry(id="book-lock-probe", paper="book", kind="figure", caption="c",
                      chapter="book/intro", compute=compute)
    monkeypatch.setenv(figures.registry.CACHE_ENV, str(tmp_path))
    out = []
    threads = [threading.Thread(target=lambda: out.append(e.run_compute("fast", 3)))
               for _ in range(3)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert calls == [3] and len(out) == 3
    assert all(np.array_equal(o["x"], np.arange(4.0)) for o in out)
    assert [p.name for p in tmp_path.iterdir()] == ["book-lock-probe.fast.3.npz"]


# ------------------------------------------------------------------------ the auto executor
def _draws(rng, n):
    return rng.standard_normal((n, 3))


def test_auto_starts_a_pool_only_for_a_run_that_repays_it(monkeypatch):
    """``auto``: a short run stays serial (no pool is started); a run whose serial time
    would exceed AUTO_POOL_SECONDS goes to the pool; the numbers are the same bitwise."""
    from concurrent.futures import Future

    from fusioncenter import montecarlo

    started, submitted = [], []

    class Pool:
        def submit(self, fn, *args):
            submitted.append(args)
            f = Future()
            f.set_result(fn(*args))
            return f

    def fake_pool(spec):
        started.append(spec)
        return Pool()

    monkeypatch.setattr(context.executors, "_pool", fake_pool)
    monkeypatch.setattr(context.executors, "cores", lambda: 2)
    serial = montecarlo.simulate(_draws, 5000, 7).samples
    with context.activate(context.ExecutionContext("paper", 7, "auto")):
        ex = context.executor()
        assert getattr(ex, "adaptive", False)
        short = montecarlo.simulate(_draws, 5000, 7, executor=ex).samples
        assert started == [] and submitted == []  # milliseconds of work: serial
        monkeypatch.setattr(context.executors, "AUTO_POOL_SECONDS", 0.0)  # as if the run were long
        long = montecarlo.simulate(_draws, 5000, 7, executor=context.executor()).samples
        assert started == ["processes:2"] and submitted
    assert short.tobytes() == serial.tobytes() == long.tobytes()


def test_auto_is_the_paper_default_and_documented(monkeypatch, capsys):
    from fusioncenter.cli import main

    monkeypatch.delenv(context.EXECUTOR_ENV, raising=False)
    assert context.parse_executor("auto") == "auto"
    assert main(["params", "zheng2014-table1"]) == 0
    out = capsys.readouterr().out
    assert "auto" in out and "about 5 s" in out


def test_progress_of_a_long_run_only(capsys, monkeypatch):
    """Progress on stderr (not a terminal): a first line with the estimate, then a line every
    30 s; nothing for a run expected to end within seconds."""
    from fusioncenter import montecarlo

    monkeypatch.setattr("sys.stderr.isatty", lambda: False, raising=False)
    quiet = montecarlo._Progress(1000, 256, eta=3.0, force=False)
    quiet.update(744)
    quiet.close()
    assert capsys.readouterr().err == ""
    loud = montecarlo._Progress(100_000, 256, eta=200.0, force=False)
    assert "Monte Carlo: 100000 trials, about 3 min" in capsys.readouterr().err
    loud.update(1000)
    assert capsys.readouterr().err == ""  # not 30 s yet
    loud.last -= 31
    loud.update(1000)
    err = capsys.readouterr().err
    assert "Monte Carlo: 2256 of 100000 trials (2.3 %), about" in err and "left" in err
