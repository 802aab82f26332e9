"""Registry entries of Part III (leong2011): each computes in the fast profile, plots with
labelled axes, passes its checks, and the checks fail on corrupted data."""

from __future__ import annotations

import numpy as np
import pytest
from figure_helpers import cached_data, check_entry, data, failed

from fusioncenter import figures
from fusioncenter.figures import leong2011
from fusioncenter.figures.leong2011 import fading_channels

IDS = ["leong2011-fig1", "leong2011-fig2", "leong2011-fig3a", "leong2011-fig3b",
       "leong2011-fig4a", "leong2011-fig4b", "leong2011-fig5a", "leong2011-fig5b",
       "leong2011-fig6a", "leong2011-fig6b"]


@pytest.mark.parametrize("entry_id", IDS)
def test_entry_computes_plots_and_passes(entry_id):
    entry = figures.get(entry_id)
    assert entry.paper == "leong2011" and entry.status == "reproduced"
    n = entry_id.removeprefix("leong2011-fig")[0]
    chapter = {"1": "asymptotics", "2": "asymptotics", "3": "allocation", "4": "allocation",
               "5": "fading", "6": "fading"}[n]
    assert entry.chapter == f"book/leong2011/{chapter}"
    assert entry.label == f"sec-{entry_id}"
    assert entry.parameters and entry.note
    check_entry(entry_id, paper="leong2011", chapter_prefix="book/leong2011/")


def test_placeholders_are_replaced_and_own_ids_empty():
    assert leong2011.OWN_IDS == ()
    for entry_id in IDS:
        assert figures.get(entry_id).compute is not None


def test_compute_is_seeded():
    entry = figures.get("leong2011-fig3a")
    a = cached_data("leong2011-fig3a")
    b = entry.run_compute("fast")
    assert np.array_equal(a["optimal"], b["optimal"])
    c = entry.run_compute("fast", seed=7)
    assert not np.array_equal(a["optimal"], c["optimal"])


def test_parameters_are_the_papers():
    p = figures.get("leong2011-fig1").parameters
    assert (p["a"], p["sigma_w2"], p["sigma_n2"], p["c"], p["sigma_v2"], p["h"]) == \
        (0.8, 1.5, 1.0, 1.0, 1.0, 0.8)
    for fig in ("3a", "4b", "5a", "6b"):
        p = figures.get(f"leong2011-fig{fig}").parameters
        assert (p["a"], p["sigma_w2"], p["sigma_n2"], p["D"], p["gamma_total"]) == \
            (0.9, 1.0, 1e-9, 2.0, 1e-3)
    assert leong2011.STATIC["realizations"]["paper"] == 1000
    assert leong2011.FADING["realizations"]["paper"] == 100
    assert leong2011.FADING["steps"]["paper"] == 1000


def test_fig1_constant_is_eq13():
    d = cached_data("leong2011-fig1")
    assert d["K"] == pytest.approx(0.8**2 * (1 + 1 / 0.8**2), rel=1e-14)


# ------------------------------------------------------------------ the checks can fail
def test_fig1_check_fails_on_a_wrong_constant():
    d = data("leong2011-fig1")
    d["K"] = d["K"] * 1.05
    d["asymptotic"] = d["sigma_w2"] + d["K"] / d["M"]
    assert any("1/M law" in name for name in failed("leong2011-fig1", d))


def test_fig2_check_fails_when_outside_the_bounds():
    d = data("leong2011-fig2")
    d["P_inf"] = d["P_inf"].copy()
    d["P_inf"][-1] = d["upper"][-1] * 1.01
    assert any("between the bounds (37)" in name for name in failed("leong2011-fig2", d))


@pytest.mark.parametrize("entry_id", ["leong2011-fig3a", "leong2011-fig4b"])
def test_static_check_fails_when_equal_power_wins(entry_id):
    d = data(entry_id)
    d["min_gap"] = d["min_gap"].copy()
    d["min_gap"][3] = -0.01
    assert any("never worse than equal" in name for name in failed(entry_id, d))


def test_static_check_fails_on_a_wrong_closed_form():
    d = data("leong2011-fig3b")
    d["solver_rel_gap"] = 3e-3  # e.g. the printed (24)
    assert any("SLSQP" in name for name in failed("leong2011-fig3b", d))


def test_static_check_fails_without_the_trend():
    d = data("leong2011-fig4a")
    d["optimal"] = d["optimal"][::-1].copy()
    assert any("trend downwards" in name for name in failed("leong2011-fig4a", d))


def test_orthogonal_benefit_check_can_fail():
    d = data("leong2011-fig4b")
    d["benefit_diff"] = -d["benefit_diff"]
    assert any("helps more in orthogonal" in name for name in failed("leong2011-fig4b", d))


@pytest.mark.parametrize("entry_id", ["leong2011-fig5a", "leong2011-fig6b"])
def test_fading_check_fails_when_no_csi_wins(entry_id):
    d = data(entry_id)
    d["log_ratio"] = -d["log_ratio"]
    assert any("full CSI beats no CSI" in name for name in failed(entry_id, d))


def test_fading_check_fails_on_a_missed_target():
    d = data("leong2011-fig6a")
    d["max_residual_csi"] = d["max_residual_csi"] + 1e-3
    assert any("Pₖ₊₁ ≤ D" in name for name in failed("leong2011-fig6a", d))


def test_lmmse_check_fails_on_a_wrong_variance():
    d = data("leong2011-fig5b")
    d["lmmse_z"] = d["lmmse_z"] + 6.0
    assert any("linear MMSE variance" in name for name in failed("leong2011-fig5b", d))


def test_lmmse_check_has_power_against_a_wrong_rbar():
    """At the paper profile's trial count the same check sees a filter whose Rbar forgets the
    fading-variance term (it understates its error by about 5 %)."""
    from fusioncenter import montecarlo, power

    p = leong2011.FADING
    rng = np.random.default_rng(3)
    sv, d, mu = fading_channels._draw_fading(rng, 1, 6)
    c = np.ones(6)
    hm, vr, vi = fading_channels._fading_stats(d[0], mu[0])
    al = power.lmmse_min_error("multi-access", p["gamma_total"], p["a"], p["sigma_w2"], c,
                               sv[0], p["sigma_n2"], hm, vr, vi)
    at = power.beamformed(al, hm)
    C, R = power.lmmse_matrices("multi-access", at, p["a"], p["sigma_w2"], c, sv[0],
                                p["sigma_n2"], hm, 0 * vr, 0 * vi)  # no fading variance

    def trial(rng, n):
        x, _, _ = power.simulate_nocsi(rng, n, 60, "multi-access", at, p["a"], p["sigma_w2"],
                                       c, sv[0], p["sigma_n2"], hm, vr, vi)
        # re-simulate observations of the same states, filter with the wrong Rbar
        y = c * x[..., None] + rng.standard_normal(x.shape + (6,)) * np.sqrt(sv[0])
        h = (hm.real + np.sqrt(vr) * rng.standard_normal(x.shape + (6,))
             + 1j * (hm.imag + np.sqrt(vi) * rng.standard_normal(x.shape + (6,))))
        zc = (at * h * y).sum(-1) + np.sqrt(p["sigma_n2"]) * (
            rng.standard_normal(x.shape) + 1j * rng.standard_normal(x.shape))
        xq, Pq = power.lmmse_filter(np.stack([zc.real, zc.imag], -1), p["a"], p["sigma_w2"],
                                    C, R)
        return ((x - xq[:, :60]) ** 2 / Pq[:60] - 1).mean(-1)

    n = leong2011.FADING["lmmse_check"]["trials"]["paper"]
    res = montecarlo.simulate(trial, n, 5)
    assert abs(res.mean / res.stderr) > leong2011.Z_TOL
