"""``--set`` on the entries of Parts I-III and V and the Background chapter (issue 16 item 2).

For each entry: ``params`` lists its parameters, an override reaches the data and the output
records it, an unknown key or an out-of-bounds value is a ``ValueError``, and a model override
makes ``verify`` skip exactly the paper-specific claims. Small sizes keep every run short.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from fusioncenter import cli, figures

#: id -> (small overrides, {data key: expected value}, the parameters ``params`` must list)
CASES = {
    "mo2015-rate": ({"trials": 300}, {"n_trials": 300}, {"trials"}),
    "mo2015-tradeoff": ({"trials": 300}, {"n_trials": 300}, {"trials"}),
    "mo2015-tracking": ({"trials": 40, "calibration_trials": 40, "sigma2": 2.0},
                        {"n_trials": 40, "n_calibration": 40},
                        {"trials", "calibration_trials", "sigma2", "r"}),
    "background-riccati": ({"a": 0.9}, {}, {"a", "q", "r"}),
    "background-kf-montecarlo": ({"trials": 200, "r": 1.0}, {"n_trials": 200},
                                 {"trials", "q", "r"}),
    "leong2011-fig1": ({"a": 0.5, "M_max": 60}, {}, {"a", "sigma_w2", "sigma_n2", "c",
                                                     "sigma_v2", "h", "M_max"}),
    "leong2011-fig2": ({"a": 0.5, "M_max": 10}, {}, {"a", "sigma_w2", "sigma_n2", "M_max"}),
    "dey2009-ordering": ({"paths": 64, "grid_paths": 16}, {"n_paths": 64, "n_grid_paths": 16},
                         {"paths", "grid_paths"}),
    "dey2009-vector": ({"paths": 64, "lam": 10.0}, {"n_paths": 64, "lam": 10.0},
                       {"paths", "lam"}),
    "dey2009-distribution": ({"paths": 200, "alt_paths": 50, "sigma_v": 2.0},
                             {"n_paths": 200, "n_alt_paths": 50, "sigma_v": 2.0},
                             {"paths", "alt_paths", "sigma_v"}),
    "synthesis-frontier": ({"trials": 8, "particles": 20, "calibration_trials": 20},
                           {"n_trials": 8, "n_particles": 20},
                           {"trials", "particles", "calibration_trials"}),
    "synthesis-cost": ({"trials": 4}, {"n_trials": 4}, {"trials"}),
    "synthesis-fading": ({"trials": 8, "particles": 20, "calibration_trials": 20},
                         {"n_trials": 8, "n_particles": 20},
                         {"trials", "particles", "calibration_trials"}),
}

#: The entries with a model parameter, one such override, and their paper-specific claims
#: (the start of each claim's name).
MODEL_CASES = {
    "background-riccati": ({"a": 0.9}, ["scalar recursion from p₀ = 0 increases"]),
    "background-kf-montecarlo": ({"trials": 200, "q": 1.0}, []),
    "leong2011-fig1": ({"h": 0.5}, ["the asymptotic expression is accurate at 20 sensors"]),
    "leong2011-fig2": ({"sigma_n2": 2.0, "M_max": 20},
                       ["P∞ lies between the bounds (37)", "P∞ − σ_w² = O(1/M)"]),
    "dey2009-vector": ({"paths": 64, "lam": 10.0},
                       ["Z̄ₖ converges", "E[tr Pₖ] has converged"]),
    "dey2009-distribution": ({"paths": 200, "alt_paths": 50, "sigma_v": 2.0},
                             ["right-skewed", "Nakagami(1/2) spreads p more"]),
    "mo2015-tracking": ({"trials": 40, "calibration_trials": 40, "r": 2.0}, []),
}


def _cli(capsys, *argv) -> tuple[int, str]:
    code = cli.main(list(argv))
    return code, capsys.readouterr().out


@pytest.mark.parametrize("entry_id", sorted(CASES))
def test_params_lists_the_parameters(entry_id, capsys):
    code, out = _cli(capsys, "params", entry_id)
    assert code == 0
    lines = out.splitlines()
    assert lines[-1].startswith("Bounds are checked before computing"), lines[-1]
    listed = {line.split(" ", 1)[0] for line in lines[:-1]}
    assert listed == CASES[entry_id][2]
    assert {p.name for p in figures.get(entry_id).settable} == CASES[entry_id][2]


@pytest.mark.parametrize("entry_id", sorted(CASES))
def test_an_override_reaches_the_data_and_is_recorded(entry_id, capsys):
    over, expected, _ = CASES[entry_id]
    argv = ["compute", entry_id, "--profile", "fast", "--executor", "serial", "--json"]
    for k, v in over.items():
        argv += ["--set", f"{k}={v}"]
    code, out = _cli(capsys, *argv)
    assert code == 0
    data = json.loads(out)
    run = data.pop("_run")
    assert run["overridden"] == sorted(over)
    for k, v in over.items():
        assert run["parameters"][k] == v
    for k, v in expected.items():
        assert data[k] == v, k


@pytest.mark.parametrize("entry_id", ["background-riccati", "leong2011-fig1", "leong2011-fig2"])
def test_a_model_override_changes_the_deterministic_data(entry_id):
    e = figures.get(entry_id)
    base = e.run_compute("fast", executor="serial")
    over = e.run_compute("fast", executor="serial", **CASES[entry_id][0])
    assert "M" in base or "p_scalar" in base
    key = "P_inf" if "P_inf" in base else "p_scalar"
    assert base[key].shape != over[key].shape or not np.array_equal(base[key], over[key])


@pytest.mark.parametrize("entry_id", sorted(CASES))
def test_unknown_keys_and_bad_values_are_clear_errors(entry_id):
    e = figures.get(entry_id)
    valid = ", ".join(sorted(p.name for p in e.settable))
    with pytest.raises(ValueError, match=f"unknown parameter.*bogus.*valid keys: {valid}$"):
        e.run_compute("fast", bogus=1)
    p = next(p for p in e.settable if p.minimum is not None)
    low = p.minimum - 1
    with pytest.raises(ValueError, match=f"parameter {p.name}: must be >="):
        e.run_compute("fast", **{p.name: int(low) if p.kind == "int" else low})


@pytest.mark.parametrize("entry_id", sorted(MODEL_CASES))
def test_a_model_override_skips_exactly_the_paper_specific_claims(entry_id):
    e = figures.get(entry_id)
    over, specific = MODEL_CASES[entry_id]
    assert e.model_overridden(over)
    claims = e.run_checks(e.run_compute("fast", executor="serial", **over))
    checked, skipped = e.split_claims(claims, over)
    assert len(skipped) == len(specific)
    for c, start in zip(skipped, specific, strict=True):
        assert c.paper_specific and c.name.startswith(start), (c.name, start)
    assert not any(c.paper_specific for c in checked)
    sizes = {k: v for k, v in over.items() if not next(
        p for p in e.settable if p.name == k).model}
    assert e.split_claims(claims, sizes) == (claims, [])  # accuracy alone: every claim applies


def test_verify_says_which_claims_it_skips(capsys):
    code, out = _cli(capsys, "verify", "leong2011-fig1", "--profile", "fast", "--set", "h=0.5")
    lines = out.splitlines()
    assert [ln for ln in lines if ln.startswith("SKIP")] == [
        "SKIP  the asymptotic expression is accurate at 20 sensors (relative error < 1 %)  "
        "[paper-specific: h overridden]"]
    assert lines[-1].endswith("1 skipped (paper-specific)")
    assert code == 0
