"""Registry entries of Part IV(a) (zheng2014, Section VII.A): each computes in the fast profile,
plots with labelled axes (units), passes at least three claims, and the checks fail on
corrupted data."""

from __future__ import annotations

import matplotlib.figure
import matplotlib.pyplot as plt
import numpy as np
import pytest
from figure_helpers import cached_data, data, failed

from fusioncenter import figures
from fusioncenter.figures import zheng2014
from fusioncenter.figures.zheng2014 import linear, no_feedback

IDS = ["zheng2014-fig1", "zheng2014-fig2", "zheng2014-table1", "zheng2014-fig3",
       "zheng2014-table1-choices"]
STATUS = {"zheng2014-fig1": "reproduced", "zheng2014-fig2": "reproduced",
          "zheng2014-table1": "differs", "zheng2014-fig3": "differs",
          "zheng2014-table1-choices": "reproduced"}


@pytest.mark.parametrize("entry_id", IDS)
def test_entry_computes_plots_and_passes(entry_id):
    entry = figures.get(entry_id)
    assert entry.paper == "zheng2014" and entry.status == STATUS[entry_id]
    assert entry.chapter == "book/zheng2014/results"
    assert entry.label == f"sec-{entry_id}"
    assert entry.parameters and entry.note
    d = data(entry_id)
    assert set(d) >= {"n_trials", "n_particles", "N"}
    fig = entry.run_plot(d)
    assert isinstance(fig, matplotlib.figure.Figure)
    axes = [ax for ax in fig.get_axes() if ax.has_data()]
    assert axes
    for ax in axes:
        assert ax.get_xlabel() and ax.get_ylabel()
        assert "(" in ax.get_ylabel() and "(" in ax.get_xlabel()  # units
    plt.close(fig)
    claims = entry.run_checks(d)
    assert len(claims) >= 3 and all(claims), [c for c in claims if not c]


def test_ids_placeholders_and_own_ids():
    assert zheng2014.OWN_IDS == ("zheng2014-table1-choices",)
    for entry_id in IDS:
        assert figures.get(entry_id).compute is not None
        assert entry_id in zheng2014.DATA_KEYS
        assert figures.get(entry_id).compute.__module__.startswith(
            "fusioncenter.figures.zheng2014.")


def test_open_choices_are_listed():
    for entry_id in IDS[:4]:
        p = figures.get(entry_id).parameters
        assert "PF prior" in p["choices"] and "feedback moments" in p["choices"]
        assert (p["sigma2"], p["r"], p["x0"], p["T"], p["dt"]) == (4.0, 1.0, [0.0, 10.0], 20,
                                                                    1.0)
        assert p["trials"]["paper"] == 5000 and p["particles"]["paper"] == 1000
    assert figures.get("zheng2014-fig1").parameters["N"] == 2
    assert figures.get("zheng2014-fig2").parameters["N"] == 4


def test_paper_table_values_are_the_printed_ones():
    assert zheng2014.PAPER_TABLE1["cfwmd"] == (1.0625, 1.1709, 1.3536, 1.7399, 2.7838)
    assert zheng2014.PAPER_TABLE1["cfwmd2"] == (1.0530, 1.2230, 1.4992, 2.0002, 3.0095)
    d = cached_data("zheng2014-table1")
    assert np.array_equal(d["paper_cfwmd"], zheng2014.PAPER_TABLE1["cfwmd"])


def test_fig2_and_table1_share_their_runs():
    # at small sizes (the sharing does not depend on them; the fast profile's take 3.6 s)
    size = {"trials": 3, "particles": 200}
    f2 = figures.get("zheng2014-fig2").run_compute("fast", **size)
    hits = linear._fig2_runs.cache_info().hits
    t1 = figures.get("zheng2014-table1").run_compute("fast", **size)
    assert linear._fig2_runs.cache_info().hits == hits + 1  # Table I computed nothing anew
    assert f2["n_trials"] == t1["n_trials"] == 3 and np.array_equal(f2["l"], t1["l"])
    a, b = linear._fig2_runs(*linear._fig2_args("fast", figures.get("zheng2014-fig2").seed,
                                                size))
    assert a[2].average_transmissions[0] == t1["cfwmd"][2]
    assert b[2].time_averaged_rmse()[0] == f2["tavg_position"][1, 2]


def test_compute_is_seeded():
    entry = figures.get("zheng2014-fig1")
    a = cached_data("zheng2014-fig1")
    b = entry.run_compute("fast")
    assert np.array_equal(a["rmse_position"], b["rmse_position"])
    c = entry.run_compute("fast", seed=7)
    assert not np.array_equal(a["rmse_position"], c["rmse_position"])


# ------------------------------------------------------------------ the checks can fail
def test_fig1_checks_fail_when_schemes_swap():
    d = data("zheng2014-fig1")
    d["pair_diff_position"] = d["pair_diff_position"].copy()
    d["pair_diff_position"][1] *= -1  # CFoMD better than CFwMD
    assert any("position RMSE" in n for n in failed("zheng2014-fig1", d))
    d = data("zheng2014-fig1")
    d["pair_diff_velocity"] = -d["pair_diff_velocity"]
    assert any("velocity RMSE" in n for n in failed("zheng2014-fig1", d))


def test_fig1_checks_fail_on_wrong_transmissions():
    d = data("zheng2014-fig1")
    d["transmissions"] = d["transmissions"].copy()
    d["transmissions"][1] = 1.2  # random selection
    d["transmissions"][3] = 1.25  # CFwMD
    names = failed("zheng2014-fig1", d)
    assert any("random selection sends" in n for n in names)
    assert any("save about half" in n for n in names)


def test_fig2_checks_fail_when_the_covariance_feedback_flips():
    d = data("zheng2014-fig2")
    d["diff"] = -d["diff"]
    names = failed("zheng2014-fig2", d)
    assert any("l = 1: CFwMD beats" in n for n in names)
    assert any("1 < l < 3" in n for n in names)
    d = data("zheng2014-fig2")
    d["rel_gain"] = d["rel_gain"][[0, 1, 2, 4, 3]].copy()  # swap l = 2 and l = 3
    assert any("l = 3" in n for n in failed("zheng2014-fig2", d))
    d = data("zheng2014-fig2")
    d["tavg_position"] = d["tavg_position"][:, ::-1].copy()
    assert any("decreases as l grows" in n for n in failed("zheng2014-fig2", d))


def test_table1_checks_fail_on_perturbed_or_swapped_columns():
    d = data("zheng2014-table1")
    d["cfwmd2"] = d["cfwmd2"] + np.array([0, 0, 0, 0.15, 0])
    d["z_cfwmd2"] = (d["cfwmd2"] - d["paper_cfwmd2"]) / (np.sqrt(2) * d["cfwmd2_stderr"])
    assert any("CFwMD2 agrees with the paper" in n for n in failed("zheng2014-table1", d))
    d = data("zheng2014-table1")
    d["cfwmd"], d["cfwmd2"] = d["cfwmd2"], d["cfwmd"]
    d["cfwmd_stderr"], d["cfwmd2_stderr"] = d["cfwmd2_stderr"], d["cfwmd_stderr"]
    names = failed("zheng2014-table1", d)
    assert any("closer to l" in n for n in names)
    assert any("fewer than l" in n for n in names)


def test_fig3_checks_fail_on_corruption():
    d = data("zheng2014-fig3")
    d["printed_max_abs_diff"] = 1e-3
    assert any("as printed" in n for n in failed("zheng2014-fig3", d))
    d = data("zheng2014-fig3")
    d["pair_diff"] = -d["pair_diff"]
    names = failed("zheng2014-fig3", d)
    assert any("random selection (paired)" in n for n in names)
    assert any("exact no-feedback filter" in n for n in names)
    d = data("zheng2014-fig3")
    d["transmissions"] = d["transmissions"] * 0.8
    assert any("design rate" in n for n in failed("zheng2014-fig3", d))


def test_choices_checks_fail_when_the_schemes_swap():
    d = data("zheng2014-table1-choices")
    d["cfwmd"], d["cfwmd2"] = d["cfwmd2"], d["cfwmd"]
    d["cfwmd_stderr"], d["cfwmd2_stderr"] = d["cfwmd2_stderr"], d["cfwmd_stderr"]
    d["diff_z"] = -d["diff_z"]
    names = failed("zheng2014-table1-choices", d)
    assert any("closer to l" in n for n in names)
    assert any("fewer than l" in n for n in names)
    assert any("lower position RMSE" in n for n in names)


def test_table1_silent_run_checks_can_fail():
    d = data("zheng2014-table1")
    d["silent_pairs_z"] = -d["silent_pairs_z"]
    assert any("consecutive steps" in n for n in failed("zheng2014-table1", d))
    d = data("zheng2014-table1")
    d["p_none"] = np.repeat(d["p_none_independent"][:, None], 2, axis=1) * 0.9
    assert any("independent-sensor" in n for n in failed("zheng2014-table1", d))


# ------------------------------------------------------------------ runs kept for the process
def test_kept_runs_are_the_runs_they_stand_for():
    from fusioncenter import censoring as cs
    from fusioncenter.figures.zheng2014 import common, runs

    runs.forget_runs()
    sc = cs.LinearScenario(N=2)
    kw = dict(l=1.0, P=20, seed=5)
    for scheme in ("all-send", "random"):  # their FC ignores the feedback: one run for both
        a = runs.kept_run(sc, scheme, feedback="state", n=300, **kw)
        b = runs.kept_run(sc, scheme, feedback="none", n=300, **kw)
        assert b.mc is a.mc and b.feedback == "none" and a.feedback == "state"
        fresh = common.run_scheme(sc, scheme, feedback="none", n=300, **kw)
        assert np.array_equal(fresh.mc.samples, b.mc.samples)
    # the first whole blocks of a longer run
    long = runs.kept_run(sc, "cfwmd", feedback="state", n=600, **kw)
    short = runs.kept_run(sc, "cfwmd", feedback="state", n=512, **kw)
    assert short.mc.n_trials == 512 and np.shares_memory(short.mc.samples, long.mc.samples)
    fresh = common.run_scheme(sc, "cfwmd", feedback="state", n=512, **kw)
    assert np.array_equal(fresh.mc.samples, short.mc.samples)
    # not a multiple of the block size, another feedback, another scenario: run again
    assert runs.kept_run(sc, "cfwmd", feedback="state", n=300, **kw).mc.n_trials == 300
    assert not np.shares_memory(
        runs.kept_run(sc, "cfwmd", feedback="state+cov", n=512, **kw).mc.samples,
        long.mc.samples)
    other = runs.kept_run(cs.LinearScenario(N=2, r=2.0), "cfwmd", feedback="state", n=512, **kw)
    assert not np.shares_memory(other.mc.samples, long.mc.samples)
    with pytest.raises(ValueError, match="sc"):
        runs.kept_run("linear", "cfwmd", feedback="state", n=512, **kw)
    runs.forget_runs()


def test_fig3_takes_fig1s_all_send_and_random_runs():
    from fusioncenter.figures.zheng2014 import runs

    runs.forget_runs()
    linear._fig1_runs.cache_clear()
    no_feedback._fig3_runs.cache_clear()
    seed, n, P = 3, 256, 20
    f1 = linear._fig1_runs(seed, n, P, 2, 1.0)
    f3 = no_feedback._fig3_runs(seed, n, P, n)
    assert f3[0].mc is f1[0].mc and f3[1].mc is f1[1].mc  # all-send, random
    assert f3[0].feedback == "none" and f1[0].feedback == "state"
    runs.forget_runs()
    linear._fig1_runs.cache_clear()
    no_feedback._fig3_runs.cache_clear()


def test_kept_runs_are_stored_in_the_compute_cache(tmp_path, monkeypatch):
    from fusioncenter import censoring as cs
    from fusioncenter.figures import registry
    from fusioncenter.figures.zheng2014 import runs

    runs.forget_runs()
    monkeypatch.setenv(registry.CACHE_ENV, str(tmp_path))
    sc, kw = cs.LinearScenario(N=2), dict(l=1.0, P=20, seed=9)
    made = runs.kept_run(sc, "cfomd", feedback="state", n=512, **kw)
    assert len(list((tmp_path / "zheng2014-runs").glob("*.npz"))) == 1
    runs.forget_runs()  # a fresh process: read back, not run again

    def no_run(*args, **kwargs):
        raise AssertionError("ran again")

    monkeypatch.setattr(runs, "run_scheme", no_run)
    again = runs.kept_run(sc, "cfomd", feedback="state", n=512, **kw)
    assert np.array_equal(again.mc.samples, made.mc.samples)
    runs.forget_runs()
    first = runs.kept_run(sc, "cfomd", feedback="state", n=256, **kw)  # its first block
    assert np.array_equal(first.mc.samples, made.mc.samples[:256])
    with pytest.raises(AssertionError, match="ran again"):  # more trials: run
        runs.kept_run(sc, "cfomd", feedback="state", n=768, **kw)
    runs.forget_runs()
    for f in (tmp_path / "zheng2014-runs").glob("*.npz"):
        f.write_bytes(b"broken")  # not served: run again (and stored again)
    monkeypatch.undo()
    monkeypatch.setenv(registry.CACHE_ENV, str(tmp_path))
    again = runs.kept_run(sc, "cfomd", feedback="state", n=512, **kw)
    assert np.array_equal(again.mc.samples, made.mc.samples)
    runs.forget_runs()
    for f in (tmp_path / "zheng2014-runs").glob("*.npz"):
        f.unlink()
        f.mkdir()  # there, but unreadable
    with pytest.raises(registry.ComputeCacheError, match="unreadable"):
        runs.kept_run(sc, "cfomd", feedback="state", n=512, **kw)
    runs.forget_runs()
