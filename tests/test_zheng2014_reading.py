"""zheng2014's results read across its settings (``fusioncenter.figures.zheng2014.reading``):
the error arithmetic against closed forms, the common form of Tables I-III against the registry's
own z-scores, and the chapter's claims pass on the fast-profile data and fail on corrupted
data."""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest
import scipy.stats
from figure_helpers import cached_data

from fusioncenter import censoring
from fusioncenter.figures.zheng2014 import reading as cc


# ------------------------------------------------------------------------- error arithmetic
def test_delta_bound_dominates_the_delta_method_for_any_correlation():
    rng = np.random.default_rng(0)
    for _ in range(200):
        k = int(rng.integers(1, 5))
        A = rng.normal(size=(k, k))
        C = A @ A.T
        g = rng.normal(size=k)
        se = np.sqrt(np.diag(C))
        assert math.sqrt(g @ C @ g) <= cc.delta_bound(g, se) * (1 + 1e-12)
    # attained for perfectly correlated estimates with gradients of one sign
    se = np.array([0.2, 0.5])
    C = np.outer(se, se)
    g = np.array([1.5, 2.0])
    assert math.isclose(math.sqrt(g @ C @ g), cc.delta_bound(g, se))


def test_delta_bound_rejects_bad_input():
    with pytest.raises(ValueError, match="one length"):
        cc.delta_bound([1, 2], [0.1])
    with pytest.raises(ValueError, match="non-negative"):
        cc.delta_bound([1], [-0.1])


def test_variance_ratio_is_one_at_the_design_rate_and_below_one_when_fewer_send():
    for dof in (1, 2):
        v, _ = cc.variance_ratio(2.0, 0.01, 2.0, 4, dof)
        assert math.isclose(float(v), 1.0, rel_tol=1e-12)
    v, _ = cc.variance_ratio([1.5, 1.7, 1.9], 0.0, 2.0, 4)
    assert np.all(np.diff(v) > 0) and np.all(v < 1)


def test_variance_ratio_closed_forms_and_derivative():
    # dof = 2: P(chi2_2 >= eta / v) = exp(-eta / (2 v))  =>  v = eta / (-2 log(rate))
    l, N, sent = 1.0, 4, 0.9296
    eta = censoring.threshold(l, N, dof=2)
    v, se = cc.variance_ratio(sent, 0.003, l, N, dof=2)
    assert math.isclose(float(v), eta / (-2 * math.log(sent / N)), rel_tol=1e-12)
    h = 1e-6
    up, _ = cc.variance_ratio(sent + h, 0.0, l, N, dof=2)
    dn, _ = cc.variance_ratio(sent - h, 0.0, l, N, dof=2)
    assert math.isclose(float(se), abs(float(up - dn)) / (2 * h) * 0.003, rel_tol=1e-5)
    # dof = 1 against a simulation: innovations of variance v s send at the predicted rate
    rng = np.random.default_rng(1)
    nu2 = 0.7 * rng.standard_normal(400_000) ** 2
    rate = np.mean(nu2 >= censoring.threshold(2, 9))
    v1, _ = cc.variance_ratio(9 * rate, 0.0, 2, 9)
    assert abs(float(v1) - 0.7) < 0.01


def test_variance_ratio_rejects_l_equal_to_n_and_impossible_rates():
    with pytest.raises(ValueError, match="l must lie"):
        cc.variance_ratio(1.0, 0.0, 4.0, 4)
    with pytest.raises(ValueError, match="sent"):
        cc.variance_ratio(4.0, 0.0, 2.0, 4)


# ------------------------------------------------------------------------- Tables I-III
def _table1_like(n_trials=1000):
    l = np.array([1.0, 2.0, 3.0])
    a, b = np.array([1.03, 1.75, 2.78]), np.array([1.02, 2.01, 3.01])
    sa, sb = np.full(3, 0.01), np.full(3, 0.012)
    return {"l": l, "cfwmd": a, "cfwmd_stderr": sa, "cfwmd2": b, "cfwmd2_stderr": sb,
            "paper_cfwmd": a + 0.02, "paper_cfwmd2": b - 0.01,
            "closer_z": (np.abs(a - l) - np.abs(b - l)) / 0.005, "n_trials": n_trials, "N": 4}


def test_bandwidth_table_matches_the_registry_rule_at_the_papers_trial_count():
    d = _table1_like(n_trials=5000)
    t = cc.bandwidth_table(d, paper_trials=5000, N=4, dof=1)
    # at the paper's trial count: the registry's (ours - paper) / (sqrt 2 stderr)
    assert np.allclose(t["z_printed"][0], (d["cfwmd"] - d["paper_cfwmd"])
                       / (math.sqrt(2) * d["cfwmd_stderr"]))
    assert np.allclose(t["closer_stderr"], 0.005)
    assert np.allclose(t["diff"][1], 0.01)
    assert t["ours"].shape == t["v"].shape == (2, 3)
    # fewer trials than the paper: the paper's error is smaller than ours
    t2 = cc.bandwidth_table(_table1_like(n_trials=500), paper_trials=5000, N=4, dof=1)
    assert np.all(t2["paper_stderr"] < t2["stderr"])
    assert np.all(np.abs(t2["z_printed"]) > np.abs(t["z_printed"]))


def test_bandwidth_table_of_table3_reproduces_the_registrys_z():
    d = cached_data("zheng2014-table3")
    meta = cc.table_meta()["nonlinear"]
    t = cc.bandwidth_table(d, **meta)
    assert meta == {"paper_trials": 200, "N": 9, "dof": 1}
    assert np.allclose(t["z_printed"][0], d["cfwmd_z_vs_printed"])
    assert np.allclose(t["z_printed"][1], d["cfwmd2_z_vs_printed"])
    assert np.allclose(t["closer"], d["closer"])
    assert np.allclose(t["closer_stderr"], d["closer_stderr"])


def test_bandwidth_table_rejects_unknown_layouts_and_shapes():
    with pytest.raises(ValueError, match="compute output"):
        cc.bandwidth_table({"l": [1.0]}, paper_trials=10, N=4, dof=1)
    d = _table1_like()
    d["cfwmd"] = d["cfwmd"][:2]
    with pytest.raises(ValueError, match="shape"):
        cc.bandwidth_table(d, paper_trials=10, N=4, dof=1)
    with pytest.raises(ValueError, match="missing"):
        cc.side_by_side({"scalar": _table1_like()}, cc.table_meta())


def _tables():
    data = {s: copy.deepcopy(cached_data(cc.TABLE_IDS[s])) for s in cc.SETTINGS}
    return data


def _failed_tables(data) -> list[str]:
    return [c.name for c in cc.bandwidth_claims(cc.side_by_side(data, cc.table_meta())) if not c]


def test_bandwidth_claims_pass_on_the_fast_profile():
    claims = cc.bandwidth_claims(cc.side_by_side(_tables(), cc.table_meta()))
    assert len(claims) >= 6 and all(claims), [c.name for c in claims if not c]


def test_bandwidth_claims_fail_on_corrupted_tables():
    data = _tables()  # swap the two schemes of Table II: CFwMD2 is no longer closer to l
    d = data["vector"]
    d["cfwmd"], d["cfwmd2"] = d["cfwmd2"].copy(), d["cfwmd"].copy()
    d["closer_z"] = -d["closer_z"]
    assert any("closer to l" in n for n in _failed_tables(data))

    data = _tables()  # a printed CFwMD2 value of Table III off by 0.3 transmissions
    data["nonlinear"]["printed_cfwmd2"] = data["nonlinear"]["printed_cfwmd2"] + 0.3
    assert any("agrees with the printed" in n for n in _failed_tables(data))

    data = _tables()  # our CFwMD of Table I sending as designed
    data["scalar"]["cfwmd"] = data["scalar"]["l"] + 0.001
    failed = _failed_tables(data)
    assert any("fewer than l" in n for n in failed)
    assert any("narrower" in n for n in failed)

    data = _tables()  # Table II, l = 1 at the printed 0.93
    data["vector"]["cfwmd"][0] = data["vector"]["paper_cfwmd"][0]
    assert any("Table II, l = 1" in n for n in _failed_tables(data))


# ------------------------------------------------------------------------- what silence buys
def _payoff_data():
    return {e: copy.deepcopy(cached_data(e)) for e in cc.PAYOFF_IDS}


def _failed_payoff(data) -> list[str]:
    rows = cc.payoff_rows(data)
    return [c.name for c in cc.payoff_claims(rows, cc.gain_by_l(data["zheng2014-fig9"]))
            if not c]


def test_payoff_rows_are_consistent_with_the_entries():
    data = _payoff_data()
    rows = cc.payoff_rows(data)
    assert [(r["setting"], r["feedback"], r["l"]) for r in rows] == [
        ("scalar", "state", 1.0), ("vector", "state", 1.0), ("scalar", "none", 1.0),
        ("vector", "none", 1.0), ("nonlinear", "state", 1.0), ("nonlinear", "state", 2.0)]
    for r in rows:  # paired differences agree with the RMSEs they are differences of
        m = r["rmse"]
        assert math.isclose(r["gain"], m["cfomd"] - m["cfwmd"], abs_tol=1e-9)
        assert math.isclose(r["loss"], m["cfomd"] - m["all-send"], abs_tol=1e-9)
        assert math.isclose(r["random_ratio"], (m["random"] - m["all-send"])
                            / (m["cfomd"] - m["all-send"]), rel_tol=1e-9)
        assert 0 < r["share_stderr"] and 0 < r["random_ratio_stderr"]
        assert r["share_stderr"] == cc.delta_bound(r["share_gradient"], r["share_input_stderr"])
    sweep = cc.gain_by_l(data["zheng2014-fig9"])
    assert sweep["l"][0] == 1.0 and math.isclose(sweep["gain"][0], rows[4]["gain"])
    with pytest.raises(ValueError, match="missing"):
        cc.payoff_rows({"zheng2014-fig1": data["zheng2014-fig1"]})


def test_payoff_claims_pass_on_the_fast_profile():
    data = _payoff_data()
    claims = cc.payoff_claims(cc.payoff_rows(data), cc.gain_by_l(data["zheng2014-fig9"]))
    assert len(claims) >= 6 and all(claims), [c.name for c in claims if not c]


def test_payoff_claims_fail_on_corrupted_data():
    data = _payoff_data()  # the printed Proposition 3 differing from CFoMD
    d = data["zheng2014-fig3"]
    d["tavg_position"][list(d["curves"]).index("printed")] -= 0.05
    assert any("printed Propositions" in n for n in _failed_payoff(data))

    data = _payoff_data()  # CFwMD no better than CFoMD on the nonlinear grid at l = 2
    data["zheng2014-fig8"]["diff_cfwmd-cfomd"] = 0.0
    assert any("pays wherever" in n for n in _failed_payoff(data))

    data = _payoff_data()  # CFwMD better than all-send in the scalar case: share above 1
    d = data["zheng2014-fig1"]
    j = [tuple(p) for p in d["pairs"]].index(("all-send", "cfwmd"))
    d["pair_diff_position"][j] = 0.2
    assert any("part, never all" in n for n in _failed_payoff(data))

    data = _payoff_data()  # the nonlinear gain growing with l
    data["zheng2014-fig9"]["diff_cfwmd-cfomd"][-1] = -1.0
    assert any("shrinks as l approaches" in n for n in _failed_payoff(data))


def test_scipy_chi2_isf_is_the_threshold_rule():
    """The variance ratio rests on the threshold design of eq. (8)."""
    assert math.isclose(censoring.threshold(1, 4), scipy.stats.chi2.isf(0.25, 1))
