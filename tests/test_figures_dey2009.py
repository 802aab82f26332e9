"""Registry entries of Part II (dey2009): they compute (fast profile), plot with labelled axes,
pass their checks, and the checks fail on corrupted data."""

from __future__ import annotations

import numpy as np
import pytest
from figure_helpers import cached_data, check_entry, data, failed

from fusioncenter import figures
from fusioncenter.figures import dey2009

PAPER = ["dey2009-fig1", "dey2009-fig2", "dey2009-fig3", "dey2009-fig4"]
IDS = PAPER + list(dey2009.OWN_IDS)


def test_own_ids_and_registration():
    assert set(dey2009.OWN_IDS) == {"dey2009-vector", "dey2009-ordering", "dey2009-distribution"}
    for entry_id in IDS:
        e = figures.get(entry_id)
        assert e.paper == "dey2009" and e.status == "reproduced"
        assert e.compute is not None and e.plot is not None and e.checks is not None
        assert e.label == f"sec-{entry_id}"
    assert figures.get("dey2009-fig1").chapter == "book/dey2009/scalar-bounds"
    assert figures.get("dey2009-fig2").chapter == "book/dey2009/scalar-bounds"
    assert figures.get("dey2009-fig3").chapter == "book/dey2009/multisensor"
    assert figures.get("dey2009-fig4").chapter == "book/dey2009/multisensor"
    assert figures.get("dey2009-vector").chapter == "book/dey2009/vector"
    assert figures.get("dey2009-ordering").chapter == "book/dey2009/multisensor"
    assert figures.get("dey2009-distribution").chapter == "book/dey2009/distribution"
    for entry_id in PAPER:  # the parameters the paper omits are marked as our choice
        assert "Our choice" in figures.get(entry_id).parameters["note"]


@pytest.mark.parametrize("entry_id", IDS)
def test_entry_computes_plots_and_passes(entry_id):
    check_entry(entry_id, paper="dey2009", chapter_prefix="book/dey2009/", min_claims=5)


def test_paper_scale_parameters():
    assert dey2009.PATHS["paper"] == 50_000 and dey2009.STEPS == 100
    d = cached_data("dey2009-fig1")
    assert d["mean"].shape == (len(dey2009.SIGMA_V), 101)
    assert d["n_paths"] == dey2009.PATHS["fast"]


def test_compute_is_seeded():
    entry = figures.get("dey2009-fig1")
    a = cached_data("dey2009-fig1")
    b = entry.run_compute("fast")
    np.testing.assert_array_equal(a["mean"], b["mean"])
    c = entry.run_compute("fast", seed=7)
    assert not np.array_equal(a["mean"], c["mean"])


# ------------------------------------------------------------------ the checks can fail
def test_scalar_dominance_fails_when_the_bound_is_too_low():
    d = data("dey2009-fig1")
    d["s"] = d["s"] * 0.8
    names = failed("dey2009-fig1", d)
    assert any(n.startswith("E[pₖ] ≤ sₖ") for n in names)
    assert any("exact at k = 1" in n for n in names)


def test_scalar_ordering_and_convergence_checks_fail():
    d = data("dey2009-fig1")
    d["q"], d["s"] = d["s"].copy(), d["q"].copy()
    assert any("sₖ ≤ qₖ" in n for n in failed("dey2009-fig1", d))
    d = data("dey2009-fig1")
    d["s_limit"] = d["s_limit"] * 1.01
    assert any("fixed points" in n for n in failed("dey2009-fig1", d))
    d = data("dey2009-fig1")
    d["window_diff"] = d["window_diff"] + 10 * d["window_diff_stderr"]
    assert any("converged" in n for n in failed("dey2009-fig1", d))
    d = data("dey2009-fig1")
    d["grid_s"] = d["grid_s"] * 0.7
    assert any(n.startswith("alternative") for n in failed("dey2009-fig1", d))


def test_nakagami_worse_than_rayleigh_can_fail():
    d = data("dey2009-fig2")
    d["rayleigh_mean"] = d["mean"] * 1.2
    assert any("worse than Rayleigh" in n for n in failed("dey2009-fig2", d))
    d = data("dey2009-fig2")
    d["rayleigh_s"] = d["s"] * 1.01
    assert any("tight bound is above Rayleigh" in n for n in failed("dey2009-fig2", d))


@pytest.mark.parametrize("entry_id", ["dey2009-fig3", "dey2009-fig4"])
def test_multisensor_checks_fail(entry_id):
    d = data(entry_id)
    d["t"] = d["mean"] * 0.9
    assert any("≤ tₖ" in n for n in failed(entry_id, d))
    d = data(entry_id)
    d["t_limit"] = d["s_limit"] * 2
    assert any("each of s and t" in n for n in failed(entry_id, d))
    d = data(entry_id)
    d["grid_s"] = d["grid_mean"] * 0.9
    assert any("grid" in n for n in failed(entry_id, d))


def test_ordering_checks_fail():
    d = data("dey2009-ordering")
    d["s_sensor1_last"] = d["s_sensor1_last"] * 2
    assert any("violated" in n for n in failed("dey2009-ordering", d))
    d = data("dey2009-ordering")
    d["s_valid"] = d["ma_mean"] * 0.9
    assert any("respected" in n for n in failed("dey2009-ordering", d))
    d = data("dey2009-ordering")
    d["alone_mean"] = d["ma_mean"] * 1.1
    assert any("noisier sensor hurts" in n for n in failed("dey2009-ordering", d))


def test_vector_checks_fail():
    d = data("dey2009-vector")
    d["Z_vPv"] = d["Z_vPv"] * 0.9
    assert any("PSD order" in n for n in failed("dey2009-vector", d))
    d = data("dey2009-vector")
    d["Z_next_quadrature"] = d["Z_next_quadrature"] * (1 + 1e-6)
    assert any("quadrature" in n for n in failed("dey2009-vector", d))
    d = data("dey2009-vector")
    d["mean_triu"][1] = d["mean_triu"][1] + 10 * d["stderr_triu"][1] + 1e-6
    assert any("exact at k = 1" in n for n in failed("dey2009-vector", d))


def test_distribution_checks_fail():
    d = data("dey2009-distribution")
    d["nakagami_min_rel_gap"] = -0.01
    assert any("lower envelope" in n for n in failed("dey2009-distribution", d))
    d = data("dey2009-distribution")
    d["rayleigh_ks_time"] = 1e-5
    assert any("stationary by" in n for n in failed("dey2009-distribution", d))
    d = data("dey2009-distribution")
    d["rayleigh_above_mean"] = 0.5
    assert any("right-skewed" in n for n in failed("dey2009-distribution", d))
    d = data("dey2009-distribution")
    d["nakagami_cdf_lo"] = d["rayleigh_cdf_lo"]
    assert any("spreads" in n for n in failed("dey2009-distribution", d))
