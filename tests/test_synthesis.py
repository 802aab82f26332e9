"""Part V (synthesis): the library pieces it adds, and its three registry entries (each computes in
the fast profile, plots with labelled axes and units, passes >= 3 claims, and the claims fail on
corrupted data)."""

from __future__ import annotations

import matplotlib.figure
import matplotlib.pyplot as plt
import numpy as np
import pytest
from figure_helpers import cached_data, data, failed

from fusioncenter import censoring, comparison, event, figures, models, montecarlo
from fusioncenter.fading import Rayleigh
from fusioncenter.figures import synthesis as fs

IDS = ["synthesis-frontier", "synthesis-cost", "synthesis-fading"]
SC = censoring.LinearScenario()


# ----------------------------------------------------------------------------- library
def test_scenario_model_is_the_tracking_model():
    a, b = comparison.scenario_model(SC), models.tracking_model()
    for name in ("A", "Q", "C", "R", "m0", "P0"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert censoring.scenarios.wna_model is models.wna_model  # the tracking model, defined once


def test_kf_filter_equals_event_kf_run_on_the_same_draws():
    """With a perfect link the stochastic trigger is exactly the library's event-triggered KF
    (event_kf_run measures at k = 0 too, where x_0 is known and nothing changes)."""
    model = models.tracking_model()
    for scheme, kw in (("stochastic", {"delta": 1.7}), ("random", {"p": 0.4}),
                       ("all-send", {})):
        run = event.event_kf_run(model, SC.T, scheme, np.random.default_rng(5), 64, **kw)
        rng = np.random.default_rng(5)
        _, y = model.sample(rng, 64, SC.T)
        xi = rng.random((64, SC.T + 1, 2))
        out = comparison.kf_filter(SC, y[:, 1:], xi[:, 1:], np.zeros((64, SC.T, 2), bool),
                                   scheme, **kw)
        assert np.array_equal(out.sent, run.gamma[:, 1:])
        assert np.max(np.abs(out.xhat - run.xhat[:, 1:])) < 1e-9
        assert np.max(np.abs(out.P - run.P[:, 1:])) < 1e-9


def test_draw_reproduces_censoring_trials():
    """The KF family sees censoring.run's trials: the all-send PF and KF errors are paired."""
    kf = comparison.run_kf(SC, [comparison.KFRun("all-send")], n_trials=64, seed=3)[0]
    pf = comparison.summary_from_censoring(
        censoring.run(SC, "all-send", l=2, n_trials=64, n_particles=300, seed=3))
    a, b = kf.samples[..., 0].mean(axis=1), pf.samples[..., 0].mean(axis=1)
    assert np.corrcoef(a, b)[0, 1] > 0.95
    other = comparison.run_kf(SC, [comparison.KFRun("all-send")], n_trials=64, seed=4)[0]
    assert np.corrcoef(other.samples[..., 0].mean(axis=1), b)[0, 1] < 0.5


def test_run_pf_without_outage_is_censorings_filter():
    for scheme in comparison.PF_SCHEMES:
        ref = comparison.summary_from_censoring(
            censoring.run(SC, scheme, l=1, n_trials=64, n_particles=200, seed=9))
        mine = comparison.run_pf(SC, scheme, l=1, n_trials=64, n_particles=200, seed=9)
        d, se = mine.paired_difference(ref)
        assert abs(d) <= 4 * se + 1e-9
        dr, ser = mine.paired_difference(ref, rate=True)
        assert abs(dr) <= 4 * ser + 1e-12
        naive = comparison.run_pf(SC, scheme, l=1, n_trials=64, n_particles=200, seed=9,
                                  receiver="naive")
        assert np.array_equal(naive.samples, mine.samples, equal_nan=True)  # nothing lost


def test_results_do_not_depend_on_chunking():
    runs = [comparison.KFRun("stochastic", delta=2.0, outage=0.2, receiver="naive")]
    a = comparison.run_kf(SC, runs, n_trials=40, seed=1, block_size=16)[0]
    b = comparison.run_kf(SC, runs, n_trials=40, seed=1, block_size=16, chunk_size=16)[0]
    assert np.array_equal(a.samples, b.samples)
    c = comparison.run_pf(SC, "cfwmd", l=1, n_trials=40, n_particles=50, seed=1, outage=0.2,
                          block_size=16)
    d = comparison.run_pf(SC, "cfwmd", l=1, n_trials=40, n_particles=50, seed=1, outage=0.2,
                          block_size=16, chunk_size=32)
    assert np.array_equal(c.samples, d.samples, equal_nan=True)


def test_losses_are_nested_and_have_the_outage_probability():
    d = comparison.draw(np.random.default_rng(0), 4000, SC)
    lost = [d.gain < comparison.outage_threshold(e) for e in (0.1, 0.3)]
    assert np.all(lost[1] | ~lost[0])  # lost at 0.1 => lost at 0.3
    for e, ls in zip((0.1, 0.3), lost, strict=True):
        assert abs(ls.mean() - e) < 4 * np.sqrt(e * (1 - e) / ls.size)


def test_energy_matched_outage_closed_form():
    ch = Rayleigh(2.5)
    for e1 in (0.05, 0.3, 0.7):
        g1 = comparison.outage_threshold(e1, ch)
        for rho in (0.0, 0.3, 1.0):
            direct = 1 - np.exp(-ch.lam * rho * g1)  # threshold scaled by the power ratio rho
            assert comparison.energy_matched_outage(e1, rho) == pytest.approx(direct, rel=1e-12,
                                                                               abs=1e-15)
    assert comparison.energy_matched_outage(0.4, 1.0) == pytest.approx(0.4)


def test_csi_receiver_keeps_the_trigger_exact_and_naive_does_not():
    runs = [comparison.KFRun("stochastic", delta=2.0, outage=0.3, receiver=r)
            for r in ("csi", "naive")]
    csi, naive = comparison.run_kf(SC, runs, n_trials=3000, seed=2)
    v, se = csi.calibration()
    assert abs(v) < 4 * se
    v, se = naive.calibration()
    assert v > 4 * se  # overconfident


def test_summary_pairing_is_enforced():
    a = comparison.run_kf(SC, [comparison.KFRun("all-send")], n_trials=8, seed=1)[0]
    b = comparison.run_kf(SC, [comparison.KFRun("all-send")], n_trials=8, seed=2)[0]
    with pytest.raises(ValueError, match="paired"):
        a.paired_difference(b)
    with pytest.raises(ValueError, match="component"):
        a.tavg_rmse("speed")


def test_flop_counts():
    kf = comparison.kf_flops(2, 2)
    assert kf["flops"] == 132
    per = [comparison.pf_flops(2, 2, p, "cfwmd")["flops"] / p for p in (10, 1000)]
    assert per[0] == per[1] == 43
    assert comparison.pf_flops(2, 2, 100, "cfomd")["flops"] < \
        comparison.pf_flops(2, 2, 100, "cfwmd")["flops"]
    with pytest.raises(ValueError, match="n_particles"):
        comparison.pf_flops(2, 2, 0)
    with pytest.raises(ValueError, match="scheme"):
        comparison.pf_flops(2, 2, 10, "exact")


@pytest.mark.parametrize("call, match", [
    (lambda: comparison.outage_threshold(1.0), "outage"),
    (lambda: comparison.outage_threshold(-0.1), "outage"),
    (lambda: comparison.energy_matched_outage(0.2, 1.5), "rate"),
    (lambda: comparison.run_kf(SC, [comparison.KFRun("stochastic")], n_trials=2, seed=0),
     "delta"),
    (lambda: comparison.run_kf(SC, [comparison.KFRun("random", p=1.5)], n_trials=2, seed=0), "p"),
    (lambda: comparison.run_kf(SC, [comparison.KFRun("all-send", receiver="x")], n_trials=2,
                               seed=0), "receiver"),
    (lambda: comparison.run_kf(SC, [comparison.KFRun("cfwmd")], n_trials=2, seed=0), "scheme"),
    (lambda: comparison.run_kf(SC, [], n_trials=2, seed=0), "runs"),
    (lambda: comparison.run_pf(SC, "random", l=1, n_trials=2, n_particles=5, seed=0), "scheme"),
    (lambda: comparison.run_pf(SC, "cfwmd", l=3, n_trials=2, n_particles=5, seed=0), "l "),
    (lambda: comparison.run_pf(SC, "cfwmd", l=1, n_trials=2, n_particles=0, seed=0),
     "n_particles"),
    (lambda: comparison.kf_filter(SC, np.zeros((2, 5, 2)), np.zeros((2, 5, 2)),
                                  np.zeros((2, 5, 2), bool), "all-send"), "z must"),
    (lambda: comparison.scenario_model("tracking"), "scenario"),
])
def test_bad_input_raises_value_error(call, match):
    with pytest.raises(ValueError, match=match):
        call()


# ----------------------------------------------------------------------------- registry entries


@pytest.mark.parametrize("entry_id", IDS)
def test_entry_computes_plots_and_passes(entry_id):
    entry = figures.get(entry_id)
    assert entry.paper == "book" and entry.status == "reproduced"
    assert entry.chapter == "book/synthesis/one-problem"
    assert entry.label == f"sec-{entry_id}"
    assert entry.parameters and entry.note
    assert entry_id in fs.OWN_IDS
    d = data(entry_id)
    fig = entry.run_plot(d)
    assert isinstance(fig, matplotlib.figure.Figure)
    axes = [ax for ax in fig.get_axes() if ax.has_data()]
    assert len(axes) >= 2
    for ax in axes:
        assert ax.get_xlabel() and ax.get_ylabel()
        assert "(" in ax.get_ylabel()  # units
    plt.close(fig)
    claims = entry.run_checks(d)
    assert len(claims) >= 3 and all(claims), [c for c in claims if not c]
    for c in claims:  # nbval prints the details: no timings in them
        assert "µs" not in c.detail and " s " not in c.detail


def test_frontier_compute_is_seeded_and_paired():
    d = cached_data("synthesis-frontier")
    assert d["n_trials"] == fs.TRIALS["fast"] and d["n_particles"] == fs.PARTICLES["fast"]
    assert np.all(np.isfinite(d["cfwmd_minus_trigger_se"])) and \
        np.all(d["cfwmd_minus_trigger_se"] > 0)
    # paired standard errors are smaller than unpaired ones (the point of pairing)
    unpaired = np.hypot(d["cfwmd_pos_se"], d["trigger_at_cfwmd_pos_se"])
    assert np.all(d["cfwmd_minus_trigger_se"] < unpaired)


def test_cost_entry_has_no_timing_in_its_claims_and_timings_are_positive():
    d = cached_data("synthesis-cost")
    assert d["kf_time"] > 0 and np.all(d["pf_time_cfwmd"] > 0)


# ------------------------------------------------------------------ the checks can fail
def test_frontier_fails_when_budgets_are_not_matched():
    d = data("synthesis-frontier")
    d["rate_trigger_minus_cfwmd"] = d["rate_trigger_minus_cfwmd"] + 0.1
    assert any("budgets matched" in n for n in failed("synthesis-frontier", d))


def test_frontier_fails_when_cfomd_wins():
    d = data("synthesis-frontier")
    d["cfwmd_minus_cfomd"] = -d["cfwmd_minus_cfomd"]
    assert any("CFwMD below CFoMD" in n for n in failed("synthesis-frontier", d))


def test_frontier_fails_when_random_selection_wins():
    d = data("synthesis-frontier")
    d["trigger_minus_random_at_cfwmd"] = np.abs(d["trigger_minus_random_at_cfwmd"])
    assert any("random selection above" in n for n in failed("synthesis-frontier", d))
    d = data("synthesis-frontier")
    d["cfomd_minus_random"] = np.abs(d["cfomd_minus_random"])
    assert any("random selection above" in n for n in failed("synthesis-frontier", d))


def test_frontier_fails_when_the_trigger_beats_cfwmd_or_the_gap_does_not_shrink():
    d = data("synthesis-frontier")
    d["cfwmd_minus_trigger"] = np.abs(d["cfwmd_minus_trigger"])
    names = failed("synthesis-frontier", d)
    assert any("CFwMD below the stochastic trigger" in n for n in names)
    d = data("synthesis-frontier")
    d["cfwmd_minus_trigger"] = np.full(3, d["cfwmd_minus_trigger"][0])
    assert any("shrinks" in n for n in failed("synthesis-frontier", d))


def test_frontier_fails_on_a_poor_particle_filter_or_an_inexact_kf():
    d = data("synthesis-frontier")
    d["pf_minus_kf_allsend"] = 0.05 * d["allsend_pos"]
    assert any("particle filter's own error" in n for n in failed("synthesis-frontier", d))
    d = data("synthesis-frontier")
    d["trigger_calibration"] = d["trigger_calibration"] + 10 * d["trigger_calibration_se"]
    assert any("exact at every rate" in n for n in failed("synthesis-frontier", d))
    d = data("synthesis-frontier")
    d["allsend_minus_cfwmd"] = -d["allsend_minus_cfwmd"]
    assert any("all-send" in n for n in failed("synthesis-frontier", d))


def test_cost_fails_on_cheap_particle_filters():
    d = data("synthesis-cost")
    d["pf_flops_at"] = d["pf_flops_at"] // 10
    assert any("two orders" in n for n in failed("synthesis-cost", d))
    d = data("synthesis-cost")
    d["pf_flops_cfwmd"] = d["pf_flops_cfwmd"] + 1000
    assert any("in proportion" in n for n in failed("synthesis-cost", d))


def test_cost_fails_when_particles_do_not_matter():
    d = data("synthesis-cost")
    d["excess"] = np.zeros_like(d["excess"])
    assert any("particles are needed" in n for n in failed("synthesis-cost", d))
    d = data("synthesis-cost")
    d["excess"] = d["excess"].copy()
    d["excess"][-1] = 0.05 * d["kf_rmse"]
    assert any("falls as particles" in n for n in failed("synthesis-cost", d))


def test_fading_fails_when_errors_do_not_grow():
    d = data("synthesis-fading")
    d["trigger_csi_step"] = -d["trigger_csi_step"]
    assert any("grows with the outage" in n for n in failed("synthesis-fading", d))


def test_fading_fails_when_silence_is_robust():
    d = data("synthesis-fading")
    d["cfwmd_naive_minus_csi"] = -d["cfwmd_naive_minus_csi"]
    assert any("lost packet as silence" in n for n in failed("synthesis-fading", d))
    d = data("synthesis-fading")
    d["cfwmd_naive_minus_cfomd"] = -np.abs(d["cfwmd_naive_minus_cfomd"])
    assert any("fragile" in n for n in failed("synthesis-fading", d))


def test_fading_fails_on_an_inexact_or_calibrated_naive_filter():
    d = data("synthesis-fading")
    d["trigger_csi_calibration"] = d["trigger_csi_calibration"] \
        + 10 * d["trigger_csi_calibration_se"]
    assert any("stays exact" in n for n in failed("synthesis-fading", d))
    d = data("synthesis-fading")
    d["trigger_naive_calibration"] = np.zeros_like(d["trigger_naive_calibration"])
    assert any("stays exact" in n for n in failed("synthesis-fading", d))


def test_fading_fails_on_spending_or_energy():
    d = data("synthesis-fading")
    d["cfwmd_csi_rate_span"] = -d["cfwmd_csi_rate_span"]
    assert any("spend more packets" in n for n in failed("synthesis-fading", d))
    d = data("synthesis-fading")
    d["energy_trigger_rho"] = 1.1 * d["energy_trigger_rho_design"]
    assert any("equal energy" in n for n in failed("synthesis-fading", d))
    d = data("synthesis-fading")
    d["energy_trigger_minus_allsend"] = np.abs(d["energy_trigger_minus_allsend"])
    assert any("equal energy" in n for n in failed("synthesis-fading", d))


def test_montecarlo_runner_is_the_one_used():
    """The entries' trials come from montecarlo.simulate blocks (seeded, chunk-independent)."""
    res = comparison.run_kf(SC, [comparison.KFRun("all-send")], n_trials=10, seed=7)[0]
    assert res.block_size == montecarlo.DEFAULT_BLOCK_SIZE and res.seed == 7
