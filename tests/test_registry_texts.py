"""What the registry prints for a reader is typeset text (issue 27, item 3).

Under every figure the site prints the entry's caption and its evidence table: each claim's
name and detail (:func:`fusioncenter.book.evidence_html`); the scorecard prints the notes, the
caption of a *differs* entry its reason, and the zheng2014 chapters the scenarios' ``choices``
and the claims of :mod:`fusioncenter.figures.zheng2014.reading`. None of it may hold a Python
repr, a bare boolean or an ASCII stand-in for mathematics: the site's own detectors
(``find_repr_output`` and ``find_ascii_math`` of ``tools/browser_check``) and the stricter
patterns below (``<=``, ``+/-``, ``->``, ``p_k``, ``P_inf``, ``x^2``, ``||e||``, ``sigma``,
``3 x 3``) find nothing.

The captions, notes and choices are checked statically; the claims need the entries' data
(fast profile, from the shared compute cache when the suite has one: ``figure_helpers``), so
that test is ``heavy``.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest
from figure_helpers import data

from fusioncenter import figures
from fusioncenter.censoring import nonlinear_model, scenarios, vector
from fusioncenter.figures.zheng2014 import reading as cc

ROOT = Path(__file__).resolve().parents[1]


sys.path.insert(0, str(ROOT / "tools"))
import browser_check as bc  # noqa: E402  (tools/ is not a package)
from browser_check.reading import GREEK  # noqa: E402

#: Stand-ins the site's detectors let through in registry text (they read chapter pages, where
#: code and math are excluded first); each has a Unicode form (≤, ±, →, pₖ, P∞, x², ‖e‖, σ, ×).
STRICT = [
    ("comparison", re.compile(r"<=|>=|!=")),
    ("plus-minus", re.compile(r"\+/-")),
    ("arrow", re.compile(r"->")),
    ("underscore subscript", re.compile(r"\b[A-Za-z]+_(?:\{|[A-Za-z0-9])")),
    ("caret", re.compile(r"\^")),
    ("norm bars", re.compile(r"\|\|")),
    ("Greek name", re.compile(rf"\b(?:{GREEK})\b")),
    ("sqrt or inf", re.compile(r"\b(?:sqrt|inf)\b")),
    ("times as x", re.compile(r"\d\s*x\s*\d")),
    ("Python literal", re.compile(r"\b(?:True|False|None)\b")),
]


def _stand_ins(text: str) -> list[tuple[str, str]]:
    strict = [(kind, " ".join(text[max(0, m.start() - 30):m.end() + 30].split()))
              for kind, rx in STRICT for m in rx.finditer(text)]
    return bc.find_repr_output(text) + bc.find_ascii_math(text) + strict


def _problems(texts) -> list[str]:
    return [f"{where}: {kind}: {excerpt!r}" for where, text in texts
            for kind, excerpt in _stand_ins(str(text))]


def test_the_stricter_patterns_find_what_they_should():
    for bad in ("E[p_k] <= s_k", "sigma_v", "P_inf", "1.0 +/- 0.1", "(P_inf - sigma_w2)",
                "x_0", "[-10, 10]^2", "closed form: True", "0.5 -> 0.2", "||e||", "3 x 3",
                "abscissae [-6.67 0. 6.67]", "[0, 0, 0, 0]"):
        assert _stand_ins(bad), bad
    for good in ("E[pₖ] ≤ sₖ", "σᵥ", "P∞ − σ_w²", "1.0 ± 0.1", "x₀", "[−10, 10]²",
                 "0.5 → 0.2", "‖e‖²", "3 × 3", "all-send − cfwmd", "l ∈ {1, 2, 3}",
                 "zheng2014-table1", "N(x̄₀, P₀)", "CFwMD2 − CFwMD = -0.0645 ± 0.0058"):
        assert not _stand_ins(good), (good, _stand_ins(good))


@pytest.mark.parametrize("entry", figures.entries(), ids=lambda e: e.id)
def test_caption_note_and_reason_are_typeset(entry):
    texts = [("caption", entry.caption), ("note", entry.note),
             ("reason", entry.differs_reason())]
    assert not _problems(texts)


@pytest.mark.parametrize("scenario", [
    scenarios.LinearScenario(), scenarios.LinearScenario(P0=((1.0, 0.0), (0.0, 1.0)),
                                                         feedback_moments="particles"),
    vector.VectorScenario(), nonlinear_model.NonlinearScenario(),
    nonlinear_model.NonlinearScenario(sensors=((0.0, 0.0), (1.0, -1.0)),
                                      initial_truth="random"),
], ids=["linear", "linear-P0", "vector", "nonlinear", "nonlinear-given"])
def test_scenario_choices_are_typeset(scenario):
    assert not _problems(scenario.choices.items())


def test_values_text_writes_numbers_as_a_reader_reads_them():
    assert scenarios.values_text((-8.0, 2.0, -8.0, 2.0)) == "(−8, 2, −8, 2)"
    assert scenarios.values_text(((1.0, 0.0), (0.0, 1.0))) == "((1, 0), (0, 1))"
    assert scenarios.values_text(-0.0) == "0" and scenarios.values_text(0.25) == "0.25"


@pytest.mark.parametrize("entry_id", figures.ids())
def test_claims_print_no_ascii_math_or_repr(entry_id):
    claims = figures.get(entry_id).run_checks(data(entry_id))
    assert claims
    assert not _problems([(f"claim {c.name!r}", c.name) for c in claims]
                         + [(f"detail of {c.name!r}", c.detail) for c in claims])


def test_zheng2014_reading_claims_are_typeset():
    payoff = {e: data(e) for e in cc.PAYOFF_IDS}
    claims = cc.payoff_claims(cc.payoff_rows(payoff), cc.gain_by_l(payoff["zheng2014-fig9"]))
    tables = {s: data(cc.TABLE_IDS[s]) for s in cc.SETTINGS}
    claims += cc.bandwidth_claims(cc.side_by_side(tables, cc.table_meta()))
    assert not _problems([(f"claim {c.name!r}", c.name) for c in claims]
                         + [(f"detail of {c.name!r}", c.detail) for c in claims])
