"""Registry entries of Part IV(b), vector observations (zheng2014 Figs. 4-6, Table II): each
computes in the fast profile, plots with labelled axes, passes its checks, and the checks fail on
corrupted data."""

from __future__ import annotations

import numpy as np
import pytest
from figure_helpers import cached_data, check_entry, data, failed

from fusioncenter import figures
from fusioncenter.censoring import vector, vector_fusion
from fusioncenter.figures.zheng2014 import vector as zv

IDS = ["zheng2014-fig4", "zheng2014-fig5", "zheng2014-table2", "zheng2014-fig6"]


@pytest.mark.parametrize("entry_id", IDS)
def test_entry_computes_plots_and_passes(entry_id):
    entry = figures.get(entry_id)
    assert entry.paper == "zheng2014" and entry.status in ("reproduced", "differs")
    assert entry.chapter == "book/zheng2014/vector"
    assert entry.label == f"sec-{entry_id}"
    assert entry.parameters and entry.note and "choices" in entry.parameters
    check_entry(entry_id, paper=entry.paper, chapter_prefix=entry.chapter)


def test_placeholders_are_replaced_and_parameters_are_the_papers():
    assert zv.OWN_IDS == ()
    for entry_id in IDS:
        assert figures.get(entry_id).compute is not None
    p = figures.get("zheng2014-fig4").parameters
    assert p["N"] == 2 and p["R"] == [[2.0, 0.0], [0.0, 4.0]] and p["H"] == [[1.0, 0.0],
                                                                                 [0.0, 1.0]]
    assert (p["sigma2"], p["T"], p["x0"], p["l"]) == (4.0, 20, [0.0, 10.0], 1.0)
    assert zv.TRIALS["paper"] == 5000 and zv.PARTICLES["paper"] == 1000
    assert zv.TRIALS_FIG5["paper"] == 5000 and zv.TRIALS_FIG6["paper"] == 5000
    assert figures.get("zheng2014-fig5").parameters["N"] == 4
    assert zv.PAPER_TABLE2["cfwmd"] == (0.9296, 1.7573, 2.8029)
    assert zv.PAPER_TABLE2["cfwmd2"] == (1.0069, 2.0035, 3.0151)


def test_fig5_and_table2_share_one_computation():
    # at small sizes (the sharing does not depend on them; the fast profile's take 3.7 s)
    over = {"trials": 3, "particles": 200}
    size = zv.common.run_size("fast", zv.TRIALS_FIG5, zv.PARTICLES_FIG5, over)
    assert size == (3, 200)
    a, b = zv._fig5_runs(figures.get("zheng2014-fig5").seed, *size)
    assert zv._fig5_runs(figures.get("zheng2014-table2").seed, *size)[0] is a
    d = figures.get("zheng2014-table2").run_compute("fast", **over)
    assert np.allclose(d["cfwmd"], [r.average_transmissions[0] for r in a])
    assert np.allclose(d["cfwmd2"], [r.average_transmissions[0] for r in b])


def test_fig4_and_fig6_share_their_blind_runs():
    """All-send and random selection ignore the broadcast: one run serves every feedback, and
    it equals the run made with that feedback (data of Figs. 4 and 6 unchanged)."""
    sc = vector.VectorScenario(N=2)
    kw = dict(l=1.0, n=64, P=50, seed=11)
    for scheme in zv._BLIND:
        a = zv._run(sc, scheme, feedback="state", **kw)
        b = zv._run(sc, scheme, feedback="none", **kw)
        assert a.mc is b.mc and (a.feedback, b.feedback) == ("state", "none")
        own = vector_fusion.run(sc, scheme, l=1.0, n_trials=64, n_particles=50, seed=11,
                                feedback="state")
        assert np.array_equal(own.mc.samples, a.mc.samples)
    c = zv._run(sc, "cfomd", feedback="state", **kw)
    assert c is zv._run(sc, "cfomd", feedback="state", **kw)
    assert c is not zv._run(sc, "cfomd", feedback="none", **kw)


def test_compute_is_seeded():
    entry = figures.get("zheng2014-fig4")
    a = cached_data("zheng2014-fig4")
    b = entry.run_compute("fast")
    assert np.array_equal(a["rmse_position"], b["rmse_position"])


# ------------------------------------------------------------------ the checks can fail
def test_fig4_check_fails_when_the_ordering_breaks():
    d = data("zheng2014-fig4")
    d["pair_diff_position"] = d["pair_diff_position"].copy()
    d["pair_diff_position"][1] = +0.01  # CFwMD no better than CFoMD
    assert any("position RMSE" in name for name in failed("zheng2014-fig4", d))
    d = data("zheng2014-fig4")
    d["transmissions"] = d["transmissions"].copy()
    d["transmissions"][list(d["schemes"]).index("cfwmd")] = 1.3
    assert any("save about half" in name for name in failed("zheng2014-fig4", d))


def test_fig5_check_fails_when_cfwmd2_loses_at_l2():
    d = data("zheng2014-fig5")
    d["diff"] = d["diff"].copy()
    d["diff"][1] = abs(d["diff"][1])
    assert any("l = 2, 3" in name for name in failed("zheng2014-fig5", d))
    d = data("zheng2014-fig5")
    d["tavg_position"] = d["tavg_position"].copy()
    d["tavg_position"][0, 2] = d["tavg_position"][0, 0] + 1.0
    assert any("decreases" in name for name in failed("zheng2014-fig5", d))


def test_table2_check_fails_on_wrong_rates():
    d = data("zheng2014-table2")
    d["cfwmd2"] = d["cfwmd2"] + 0.1
    assert any("within 0.03" in name for name in failed("zheng2014-table2", d))
    d = data("zheng2014-table2")
    d["closer_z"] = -np.abs(d["closer_z"])
    assert any("closer to l" in name for name in failed("zheng2014-table2", d))


def test_fig6_check_fails_when_printed_differs_or_exact_loses():
    d = data("zheng2014-fig6")
    d["printed_max_abs_diff"] = 1e-3
    assert any("as printed gives exactly" in name for name in failed("zheng2014-fig6", d))
    d = data("zheng2014-fig6")
    names = [tuple(p) for p in d["pairs"]]
    d["pair_diff"] = d["pair_diff"].copy()
    d["pair_diff"][names.index(("exact", "cfomd"))] = 0.0
    assert any("exact no-feedback" in name for name in failed("zheng2014-fig6", d))
    d = data("zheng2014-fig6")
    d["printed_mass"] = np.ones_like(d["printed_mass"])
    assert any("not a likelihood" in name for name in failed("zheng2014-fig6", d))
