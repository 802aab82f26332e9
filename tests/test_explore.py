"""Explorable figures (``fusioncenter.explore``): every frame is the entry's own compute at the
slider's value, the data download holds every frame, and the claims along the slider hold."""

from __future__ import annotations

import base64
import csv
import json
import struct

import numpy as np
import pytest

from fusioncenter import cli, explore, figures
from fusioncenter.explore import Slider

#: Every entry with a slider, and one of its values to compute directly.
SLIDERS = ["mo2015-explore", "dey2009-explore", "leong2011-explore", "zheng2014-explore",
           "synthesis-explore"]


@pytest.fixture(scope="module", params=SLIDERS)
def explorable(request):
    entry_id = request.param
    return entry_id, explore.frames(entry_id, "fast")


def _same(a, b) -> bool:
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    if isinstance(a, np.ndarray):
        return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()
    return type(a) is type(b) and (a == b or (a != a and b != b))


def test_a_frame_is_the_entry_compute_at_that_value_bit_for_bit(explorable):
    entry_id, data = explorable
    slider = explore.get(entry_id)
    entry = figures.get(entry_id)
    for i in (0, slider.start, len(slider.values) - 1):
        direct = entry.run_compute("fast", None, **slider.overrides("fast", i))
        assert _same(data[i], direct), (entry_id, i)


def test_the_slider_has_at_least_15_values_and_shows_its_units(explorable):
    entry_id, data = explorable
    slider = explore.get(entry_id)
    assert len(slider.values) >= 15 and len(data) == len(slider.values)
    assert slider.label and slider.text(slider.start).startswith(f"{slider.symbol} = ")
    assert slider.start in slider.print_at and 3 <= len(slider.print_at) <= 4


def test_the_claims_along_the_slider_hold(explorable):
    entry_id, data = explorable
    claims = explore.sweep_claims(entry_id, data)
    assert len(claims) >= 2
    assert all(c.passed for c in claims), [(c.name, c.detail) for c in claims if not c.passed]


def test_the_data_download_holds_every_frame(explorable, tmp_path):
    entry_id, data = explorable
    slider = explore.get(entry_id)
    doc = json.loads(explore.dumps_frames(entry_id, data))
    assert doc["parameter"] == slider.parameter and doc["values"] == list(slider.values)
    assert len(doc["frames"]) == len(slider.values)
    for i in (0, len(data) - 1):
        assert doc["frames"][i] == json.loads(cli.dumps(data[i]))
    path = tmp_path / "frames.csv"
    explore.write_frames_csv(entry_id, data, path)
    with path.open() as f:
        rows = list(csv.reader(f))
    assert rows[0] == [slider.parameter, "name", "index", "value"]
    assert {float(r[0]) for r in rows[1:]} == set(slider.values)


def test_frames_are_drawn_at_one_size_and_stay_light(explorable):
    entry_id, data = explorable
    shown = explore.render_frames(entry_id, data)
    pngs = [base64.b64decode(f["png"]) for f in shown["frames"]]
    sizes = {struct.unpack(">II", p[16:24]) for p in pngs}
    assert len(sizes) == 1  # the panels do not move when the slider does
    assert sum(map(len, pngs)) < 2_000_000  # the page's budget for one explorable figure
    assert len({f["alt"] for f in shown["frames"]}) == len(pngs)  # each frame described
    assert all(f["facts"] for f in shown["frames"])


def test_the_mo2015_slider_moves_the_point_along_the_curve():
    data = explore.frames("mo2015-explore", "fast")
    for d in data:
        on_curve = np.interp(d["delta"], d["curve_delta"], d["curve_mse"])
        assert abs(on_curve - d["mse"]) < 1e-3


def test_a_claim_along_the_slider_can_fail():
    data = explore.frames("mo2015-explore", "fast")
    broken = [dict(d) for d in data]
    broken[3]["rate"], broken[4]["rate"] = broken[4]["rate"], broken[3]["rate"]
    claims = explore.sweep_claims("mo2015-explore", broken)
    assert not next(c for c in claims if "rate falls" in c.name).passed


@pytest.mark.parametrize("change, message", [
    ({"values": tuple(range(10))}, "at least 15"),
    ({"values": tuple(range(20, 0, -1))}, "increasing"),
    ({"start": 99}, "start"),
    ({"print_at": (0, 99)}, "print_at"),
])
def test_a_bad_slider_is_refused(change, message):
    fields = dict(entry_id="x", parameter="p", values=tuple(range(17)), label="p (units)",
                  symbol="p", start=0, print_at=(0, 8))
    with pytest.raises(ValueError, match=message):
        Slider(**{**fields, **change})


def test_a_slider_needs_a_settable_parameter_and_one_slider_per_entry():
    figures.get("mo2015-explore"), figures.get("mo2015-rate")
    ok = dict(values=tuple(range(1, 18)), label="p (units)", symbol="p", print_at=(0,))
    with pytest.raises(ValueError, match="not settable"):
        explore.register(Slider(entry_id="mo2015-rate", parameter="nope", **ok))
    with pytest.raises(ValueError, match="already has a slider"):
        explore.register(Slider(entry_id="mo2015-explore", parameter="delta", **ok))
    with pytest.raises(KeyError, match="has no slider"):
        explore.get("mo2015-rate")


def test_the_dey2009_slider_keeps_every_path_between_the_perfect_channel_and_above():
    data = explore.frames("dey2009-explore", "fast")
    assert all(d["min_lower_gap"] >= 0 for d in data)  # ℓ_k ≤ p_k on every path
    broken = [dict(d) for d in data]
    broken[5]["mean"] = broken[5]["mean"].copy()
    broken[5]["mean"][-1] = 1.5 * broken[4]["mean"][-1]  # a mean that rises with the gain
    claims = explore.sweep_claims("dey2009-explore", broken)
    assert not next(c for c in claims if "falls as the mean gain" in c.name).passed


def test_the_leong2011_mean_snr_is_the_sensor_law_s_mean():
    from fusioncenter import power
    from fusioncenter.figures.explorable import leong2011 as mod

    p = mod.MODEL
    rng = np.random.default_rng(7)
    sv, d = rng.chisquare(1, 400_000), rng.uniform(*p["d_range"], 400_000)
    h, c = d**-2.0, np.full(sv.shape, p["c"])
    rho, tau, kap = power.static_coefficients(p["a"], p["sigma_w2"], h, c, sv)
    for gamma in (1e-5, 1e-3, 1e-1):
        s = rho**2 * gamma / (gamma * tau + kap * p["sigma_n2"])
        s_opt, s_eq = mod.mean_snr(gamma)
        assert abs(s.mean() - s_opt) < 4 * s.std() / np.sqrt(s.size)
        e1, e2 = np.mean(rho / np.sqrt(kap)), np.mean(tau / kap)
        assert abs(gamma * e1**2 / (gamma * e2 + p["sigma_n2"]) / s_eq - 1) < 0.02
    with pytest.raises(ValueError, match="gamma"):
        mod.mean_snr(-1.0)


def test_the_zheng2014_slider_moves_the_censoring_schemes_only():
    data = explore.frames("zheng2014-explore", "fast")
    names = list(data[0]["schemes"])
    a, w = names.index("all-send"), names.index("cfwmd")
    # all-send ignores l: one run, the same numbers in every frame
    assert len({d["tavg_position"][a] for d in data}) == 1
    assert all(d["transmissions"][a] == 2.0 for d in data)
    assert [d["l"] for d in data] == list(explore.get("zheng2014-explore").values)
    broken = [dict(d) for d in data]
    for i in (9, 10):  # CFwMD sending 20 % more than l at l = 1.1 and 1.2
        broken[i]["transmissions"] = broken[i]["transmissions"].copy()
        broken[i]["transmissions"][w] = 1.2 * broken[i]["l"]
    claims = explore.sweep_claims("zheng2014-explore", broken)
    assert not next(c for c in claims if "track l" in c.name).passed
    assert next(c for c in claims if "never beaten" in c.name).passed


def test_the_synthesis_slider_puts_the_trigger_on_its_frontier_curve():
    data = explore.frames("synthesis-explore", "fast")
    ref = data[0]["ref_trigger_rate"], data[0]["ref_trigger_pos"]
    for d in data:  # the reference curves do not depend on the budget
        assert d["ref_trigger_pos"].tobytes() == ref[1].tobytes()
        assert np.all(np.diff(d["ref_trigger_rate"]) < 0)  # a larger delta sends less
        # the trigger tuned to CFwMD's rate sits on the curve of every delta (same trials)
        on_curve = np.interp(d["trigger_rate"], ref[0][::-1], ref[1][::-1])
        assert abs(on_curve / d["trigger_pos"] - 1) < 0.03, d["budget"]
    broken = [dict(d) for d in data]
    broken[4]["cfwmd_minus_trigger"] = 0.5 * broken[4]["cfwmd_minus_trigger_se"]
    claims = explore.sweep_claims("synthesis-explore", broken)
    assert not next(c for c in claims if "below the stochastic trigger" in c.name).passed
