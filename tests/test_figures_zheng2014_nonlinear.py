"""Registry entries of Part IV(b), nonlinear tracking (zheng2014 Figs. 7-10, Table III): each
computes in the fast profile, plots with labelled axes, passes its checks, and the checks fail
on corrupted data."""

from __future__ import annotations

import numpy as np
import pytest
from figure_helpers import cached_data, check_entry, data, failed

from fusioncenter import figures
from fusioncenter.figures.zheng2014 import nonlinear as zn
from fusioncenter.figures.zheng2014.nonlinear import feedback as zn_fb
from fusioncenter.figures.zheng2014.nonlinear import scenario as zn_sc

IDS = ["zheng2014-fig7", "zheng2014-fig8", "zheng2014-fig9", "zheng2014-fig10",
       "zheng2014-table3"]


@pytest.mark.parametrize("entry_id", IDS)
def test_entry_computes_plots_and_passes(entry_id):
    entry = figures.get(entry_id)
    assert entry.paper == "zheng2014" and entry.status in ("reproduced", "differs")
    assert entry.chapter == "book/zheng2014/nonlinear"
    assert entry.label == f"sec-{entry_id}"
    assert entry.parameters and entry.note
    assert "choices" in entry.parameters and entry.parameters["trials"]["paper"] == 200
    assert entry.parameters["particles"]["paper"] == 10_000
    check_entry(entry_id, paper=entry.paper, chapter_prefix=entry.chapter)


def test_placeholders_are_replaced_and_own_ids_empty():
    assert zn.OWN_IDS == ()
    for entry_id in IDS:
        assert figures.get(entry_id).compute is not None


def test_runs_are_shared_between_entries():
    # computed in this process at small sizes (the sharing does not depend on them; the fast
    # profile's runs take 9 s): 2 trials of 300 particles
    size = {"trials": 2, "particles": 300}
    computed = {i: figures.get(i).run_compute("fast", **size)
                for i in ("zheng2014-fig8", "zheng2014-fig9", "zheng2014-fig10")}
    seed = figures.get("zheng2014-fig8").seed
    keys = [k for k in zn_sc._RUNS if k[:4] == ("fast", seed, 2, 300)]
    # Fig. 8: 4 runs; Fig. 9 adds 3 x 4 (l = 2 shared); Fig. 10 adds CFwMD2 at 3 l (CFwMD
    # shared with Fig. 9)
    assert len(keys) == 4 + 12 + 3
    hits = zn_fb._fig10_table3.cache_info().hits
    t3 = figures.get("zheng2014-table3").run_compute("fast", **size)
    f10 = computed["zheng2014-fig10"]
    assert zn_fb._fig10_table3.cache_info().hits == hits + 1  # one computation for both entries
    assert np.array_equal(t3["cfwmd_transmissions"], f10["cfwmd_transmissions"])
    f8, f9 = computed["zheng2014-fig8"], computed["zheng2014-fig9"]
    i8, i9 = f8["schemes"].index("cfwmd"), list(f9["l"]).index(2.0)
    assert f8["tavg_position"][i8] == f9["tavg_position"][f9["schemes"].index("cfwmd"), i9]


def test_compute_is_seeded():
    a = cached_data("zheng2014-fig7")
    b = figures.get("zheng2014-fig7").run_compute("fast")
    assert np.array_equal(a["trajectory"], b["trajectory"])
    c = figures.get("zheng2014-fig7").run_compute("fast", seed=7)
    assert not np.array_equal(a["trajectory"], c["trajectory"])


def test_parameters_are_the_papers():
    p = figures.get("zheng2014-fig8").parameters
    assert (p["N"], p["region_m"], p["P0_signal"], p["alpha"], p["n_exponent"], p["r"],
            p["sigma2"], p["dt_s"], p["T"]) == (9, 20.0, 1e3, 1.0, 2.0, 1.0, 0.1, 0.5, 20)
    assert p["x0_mean"] == [-8.0, 2.0, -8.0, 2.0] and p["x0_cov_diag"] == [9.0, 4.0, 9.0, 4.0]
    assert p["l"] == 2
    assert figures.get("zheng2014-fig10").parameters["l"] == [2, 4, 6]
    t = figures.get("zheng2014-table3").parameters["printed"]
    assert t["cfwmd"] == (1.5978, 3.3480, 5.4835) and t["cfwmd2"] == (1.8970, 3.8775, 5.9533)


# ------------------------------------------------------------------ the checks can fail
def test_fig7_checks_fail_on_a_wrong_grid_or_a_target_that_stays():
    d = data("zheng2014-fig7")
    d["sensors"] = d["sensors"][:8]
    assert any("3 × 3 grid" in n for n in failed("zheng2014-fig7", d))
    d = data("zheng2014-fig7")
    d["fraction_outside"] = np.zeros_like(d["fraction_outside"])
    assert any("moves out" in n for n in failed("zheng2014-fig7", d))


def _swap(d, a, b, keys):
    i, j = d["schemes"].index(a), d["schemes"].index(b)
    for k in keys:
        d[k][[i, j]] = d[k][[j, i]]


def test_fig8_checks_fail_when_the_ordering_is_reversed():
    d = data("zheng2014-fig8")
    d["diff_cfwmd-cfomd"] = -d["diff_cfwmd-cfomd"]
    names = failed("zheng2014-fig8", d)
    assert any("outperforms CFoMD" in n for n in names)
    d = data("zheng2014-fig8")
    d["diff_cfwmd-all-send"] = -abs(d["diff_cfwmd-all-send"])
    assert any("all-send is the best" in n for n in failed("zheng2014-fig8", d))
    d = data("zheng2014-fig8")
    d["transmissions"] = d["transmissions"] + 1.0
    assert any("78 %" in n for n in failed("zheng2014-fig8", d))
    d = data("zheng2014-fig8")
    d["rise_pooled"] = -abs(d["rise_pooled"])
    assert any("increase at the later steps" in n for n in failed("zheng2014-fig8", d))


def test_fig9_checks_fail_on_corrupted_curves():
    d = data("zheng2014-fig9")
    d["diff_cfwmd-cfomd"] = np.abs(d["diff_cfwmd-cfomd"])
    names = failed("zheng2014-fig9", d)
    assert any("clear advantage" in n for n in names)
    assert any("never significantly worse" in n for n in names)
    d = data("zheng2014-fig9")
    d["more_tx_gain"] = -d["more_tx_gain"]
    assert any("more transmissions help" in n for n in failed("zheng2014-fig9", d))
    d = data("zheng2014-fig9")
    d["spread_shrink"] = -abs(d["spread_shrink"])
    assert any("approach each other" in n for n in failed("zheng2014-fig9", d))


def test_fig10_checks_fail_when_covariance_feedback_does_not_help():
    d = data("zheng2014-fig10")
    d["pooled_later"] = abs(d["pooled_later"])
    d["pooled_all"] = abs(d["pooled_all"])
    d["diff_all"] = np.abs(d["diff_all"]) + 10 * d["diff_all_stderr"]
    names = failed("zheng2014-fig10", d)
    assert any("second half" in n for n in names)
    assert any("not significantly worse" in n for n in names)
    assert any("is better than CFwMD, pooled" in n for n in names)


def test_fast_thresholds_keep_the_papers_effect_size():
    assert zn.z_required(3.0, 200) == 3.0 and zn.z_required(3.0, 400) == 3.0
    assert zn.z_required(3.0, 50) == pytest.approx(1.5)


def test_table3_checks_fail_on_wrong_counts():
    d = data("zheng2014-table3")
    d["closer"] = -np.abs(d["closer"])
    assert any("more closely" in n for n in failed("zheng2014-table3", d))
    d = data("zheng2014-table3")
    d["cfwmd_transmissions"] = d["l"] + 0.5
    assert any("fewer than l" in n for n in failed("zheng2014-table3", d))
    d = data("zheng2014-table3")
    d["half_shortfall"] = -np.abs(d["half_shortfall"])
    assert any("more than half" in n for n in failed("zheng2014-table3", d))


# ------------------------------------------------------------------ settable parameters
def test_every_zheng2014_entry_has_settable_parameters(capsys):
    from fusioncenter import cli

    for e in figures.entries():
        if e.paper == "zheng2014":
            assert e.settable, e.id
    assert cli.main(["params", "zheng2014-fig7"]) in (0, None)
    out = capsys.readouterr().out
    assert "trajectories (int" in out and "sigma2 (float" in out
    assert "changes the paper's setting" in out


def test_fig7_overrides_change_and_record_the_data():
    e = figures.get("zheng2014-fig7")
    base = cached_data("zheng2014-fig7")
    small = e.run_compute("fast", trajectories=500)
    assert small["ensemble"] == 500 and base["ensemble"] == zn.TRAJECTORIES
    assert np.array_equal(small["trajectory"], base["trajectory"])  # the sample comes first
    noisy = e.run_compute("fast", trajectories=500, sigma2="0.4")
    assert not np.array_equal(noisy["trajectory"], small["trajectory"])
    assert e.resolved_parameters("fast", {"sigma2": "0.4"}) == {
        "trajectories": zn.TRAJECTORIES, "sigma2": 0.4}
    assert e.model_overridden({"sigma2": 0.4, "trajectories": 9}) == ["sigma2"]
    checked, skipped = e.split_claims(e.run_checks(noisy), {"sigma2": 0.4})
    assert [c.name for c in checked] == [
        "N = 9 sensors on a 3 × 3 grid inside the 20 m × 20 m region"]
    assert len(skipped) == 3 and all(c.paper_specific for c in skipped)


def test_fig7_bad_overrides_name_the_valid_keys():
    e = figures.get("zheng2014-fig7")
    with pytest.raises(ValueError, match="unknown parameter.*valid keys: sigma2, trajectories"):
        e.run_compute("fast", trials=10)
    with pytest.raises(ValueError, match="parameter trajectories: must be >= 2"):
        e.run_compute("fast", trajectories=1)
    with pytest.raises(ValueError, match="parameter sigma2: must be >= "):
        e.run_compute("fast", sigma2=-1.0)
