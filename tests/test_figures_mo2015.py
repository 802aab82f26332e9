"""Registry entries of Part I (mo2015): they compute, plot, pass their checks, and the checks
can fail. Also the closed forms that live in ``fusioncenter.figures.mo2015``."""

from __future__ import annotations

import numpy as np
import pytest
from figure_helpers import cached_data, check_entry, data, failed

from fusioncenter import event, figures, montecarlo
from fusioncenter.figures import mo2015
from fusioncenter.figures.mo2015 import event_kf

IDS = ["mo2015-rate", "mo2015-tradeoff", "mo2015-tracking"]


@pytest.mark.parametrize("entry_id", IDS)
def test_entry_computes_plots_and_passes(entry_id):
    assert figures.get(entry_id).status == "reproduced"
    check_entry(entry_id, paper="mo2015", chapter_prefix="book/mo2015/")


def test_compute_is_seeded():
    entry = figures.get("mo2015-tradeoff")
    a = cached_data("mo2015-tradeoff")
    b = entry.run_compute("fast")
    assert np.array_equal(a["mse_stochastic"], b["mse_stochastic"])
    c = entry.run_compute("fast", seed=7)
    assert not np.array_equal(a["mse_stochastic"], c["mse_stochastic"])


# ------------------------------------------------------------------ the checks can fail
def test_rate_check_fails_on_a_wrong_formula():
    d = data("mo2015-rate")
    d["rate_closed_at_mc"] = d["rate_closed_at_mc"] * 1.05
    assert any("Monte Carlo rate" in name for name in failed("mo2015-rate", d))


def test_rate_check_fails_on_a_broken_inverse():
    d = data("mo2015-rate")
    d["delta_back_xbar"] = d["delta_back_xbar"] * (1 + 1e-6)
    assert any("inverts" in name for name in failed("mo2015-rate", d))


def test_tradeoff_check_fails_on_scaled_mse():
    d = data("mo2015-tradeoff")
    d["mse_stochastic"] = d["mse_stochastic"] * 1.1
    assert any("exact E tr P" in name for name in failed("mo2015-tradeoff", d))


def test_tradeoff_check_fails_when_random_selection_wins():
    d = data("mo2015-tradeoff")
    d["diff"] = -d["diff"]
    assert any("below random selection" in name for name in failed("mo2015-tradeoff", d))


def test_tracking_check_fails_on_an_optimistic_covariance():
    """A filter that reports 10 % less covariance than its error is caught."""
    d = data("mo2015-tracking")
    d["stochastic_resid_k"] = d["stochastic_resid_k"] + 0.1 * d["stochastic_p_k"].sum(-1)
    assert any("exact" in name for name in failed("mo2015-tracking", d))


def test_tracking_check_fails_on_a_missed_rate():
    d = data("mo2015-tracking")
    d["stochastic_rate"] = d["stochastic_rate"] + 0.02
    assert any("target" in name for name in failed("mo2015-tracking", d))


def test_exactness_check_has_power_against_a_real_wrong_filter():
    """The trigger with silence ignored (CFoMD idea) is not exact; the same z-test sees it."""
    model = mo2015.tracking()
    delta = float(cached_data("mo2015-tracking")["delta"][3])  # target rate 0.5
    run = event_kf._tracking_run(model, 19, "stochastic-ignore", 2000, 5, delta=delta)
    z = run["resid_k"][1:] / run["resid_k_stderr"][1:]
    assert np.max(np.abs(z)) > mo2015.Z_TOL


# ------------------------------------------------------------------------- closed forms
def test_pattern_probabilities_match_simulation_and_marginals():
    xbar, Sigma, C, r = mo2015.example()
    delta = mo2015.tradeoff_deltas([0.4])[0]
    probs = mo2015.pattern_probabilities(Sigma, C, r, delta, xbar)
    assert abs(probs.sum() - 1) < 1e-12 and np.all(probs > 0)
    pats = mo2015.patterns(3)
    marg = probs @ pats  # P(gamma_i = 1)
    assert np.allclose(marg, event.communication_rate(Sigma, C, r, delta, xbar), atol=1e-13)

    def chunk(rng, n):
        _, y, _ = mo2015.draw_example(rng, n)
        g = event.sample_trigger(rng, y, delta)
        return np.eye(8)[mo2015.pattern_code(g)]

    res = montecarlo.simulate(chunk, 40_000, 11)
    z = (res.mean - probs) / res.stderr
    assert np.max(np.abs(z)) < 4.5
    # the decisions are dependent: the joint law is not the product of the marginals
    product = np.prod(np.where(pats, marg, 1 - marg), axis=1)
    assert np.max(np.abs(probs - product)) > 0.01


def test_expected_traces_limits():
    xbar, Sigma, C, r = mo2015.example()
    from fusioncenter import riccati

    all_send = np.trace(riccati.measurement_update(Sigma, C, np.diag(r)))
    assert mo2015.expected_trace_random(Sigma, C, r, 1.0) == pytest.approx(all_send, rel=1e-12)
    assert mo2015.expected_trace_random(Sigma, C, r, 0.0) == pytest.approx(np.trace(Sigma))
    tiny = mo2015.expected_trace_stochastic(Sigma, C, r, 1e-9, xbar)
    huge = mo2015.expected_trace_stochastic(Sigma, C, r, 1e9, xbar)
    assert tiny == pytest.approx(all_send, rel=1e-6)
    assert huge == pytest.approx(np.trace(Sigma), rel=1e-6)


def test_single_sensor_trigger_beats_random_selection():
    """One sensor: the pattern probabilities are equal at a matched rate, and a silent sensor
    still informs, so the trigger wins at every rate (a theorem, unlike with several sensors)."""
    Sigma, C, r = np.array([[2.0]]), np.array([[1.0]]), np.array([0.5])
    for rate in (0.1, 0.5, 0.9):
        for mu in (0.0, 1.5):
            d = event.delta_for_rate(rate, 2.5, mu)
            s = mo2015.expected_trace_stochastic(Sigma, C, r, d, [mu])
            assert s < mo2015.expected_trace_random(Sigma, C, r, rate)


def test_drop_posterior_equals_the_kalman_update_of_the_senders():
    xbar, Sigma, C, r = mo2015.example()
    rng = np.random.default_rng(3)
    y = rng.standard_normal(3)
    g = np.array([True, False, True])
    xhat, P = mo2015.drop_posterior(xbar, Sigma, C, r, g, y)
    x2, P2 = event.posterior(xbar, Sigma, C[g], r[g], 1.0, np.ones(2), y[g])
    assert np.allclose(xhat, x2, atol=1e-12) and np.allclose(P, P2, atol=1e-12)
