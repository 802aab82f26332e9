"""The errata page's own claims hold (``book/errata.md``).

Every entry carries a stable label ``(erratum-<paper>-<slug>)=``; the errata (E) and the notation
slips (N) are numbered in page order, the errata grouped by paper in the order of the papers;
every erratum's evidence is either an executable check in a chapter, with a test marked
``@erratum(label)`` that sees the check reject the printed form
(``tests/test_errata_printed_*.py``), or says "by reading"; and every such mark names an entry
that exists.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "book" / "errata.md"
PAPERS = ("mo2015", "dey2009", "leong2011", "zheng2014")
HEADING = re.compile(r"^\*\*([EN])(\d+|\?)\. (.*)\*\*\s*$")
LABEL = re.compile(r"^\((erratum-[a-z0-9-]+)\)=\s*$")
SECTION = re.compile(r"^\(sec-errata-([a-z0-9]+)\)=\s*$")
MARK = re.compile(r"""@erratum\(\s*["'](erratum-[a-z0-9-]+)["']\s*\)""")


def entries(text: str) -> list[dict]:
    """The page's entries in order: kind (E/N), number, label, section, evidence text."""
    lines = text.splitlines()
    found, section = [], None
    for i, line in enumerate(lines):
        if m := SECTION.match(line):
            section = m.group(1)
            continue
        m = HEADING.match(line)
        if not m:
            continue
        label = LABEL.match(lines[i - 1]) if i else None
        evidence, j = [], i + 1
        while j < len(lines) and not HEADING.match(lines[j]) and not lines[j].startswith("#"):
            if lines[j].startswith("evidence"):
                k = j + 1
                while k < len(lines) and lines[k].startswith((": ", "  ")):
                    evidence.append(lines[k].lstrip(": ").strip())
                    k += 1
            j += 1
        found.append({"kind": m.group(1), "number": m.group(2), "title": m.group(3),
                      "label": label.group(1) if label else None, "section": section,
                      "line": i + 1, "evidence": " ".join(evidence)})
    return found


def marked_labels() -> dict[str, list[str]]:
    marks: dict[str, list[str]] = {}
    for path in sorted((ROOT / "tests").glob("test_errata_printed_*.py")):
        for label in MARK.findall(path.read_text(encoding="utf-8")):
            marks.setdefault(label, []).append(path.name)
    return marks


def label_problems(found: list[dict]) -> list[str]:
    problems = [f"line {e['line']}: {e['kind']}{e['number']} has no label line before it"
                for e in found if not e["label"]]
    labels = [e["label"] for e in found if e["label"]]
    problems += [f"duplicate label {x}" for x in sorted({x for x in labels if labels.count(x) > 1})]
    problems += [f"label {x} does not name a paper of {PAPERS}" for x in labels
                 if x.split("-")[1] not in PAPERS]
    return problems


def numbering_problems(found: list[dict], kind: str) -> list[str]:
    numbers = [e["number"] for e in found if e["kind"] == kind]
    expected = [str(n) for n in range(1, len(numbers) + 1)]
    return [] if numbers == expected else [f"{kind} numbers in page order: {numbers}"]


def placement_problems(found: list[dict]) -> list[str]:
    errata = [e for e in found if e["kind"] == "E" and e["label"]]
    problems = [f"{e['label']} sits in section {e['section']}" for e in errata
                if e["section"] != e["label"].split("-")[1]]
    order = [PAPERS.index(e["label"].split("-")[1]) for e in errata]
    if order != sorted(order):
        problems.append("errata are not in the order of the papers")
    notes = [PAPERS.index(e["label"].split("-")[1]) for e in found
             if e["kind"] == "N" and e["label"]]
    if notes != sorted(notes):
        problems.append("notation slips are not in the order of the papers")
    return problems


def evidence_problems(found: list[dict], marks: dict[str, list[str]]) -> list[str]:
    problems = []
    for e in found:
        if e["kind"] != "E":
            continue
        name, ev = f"E{e['number']} ({e['label']})", e["evidence"]
        if not ev:
            problems.append(f"{name}: no evidence")
        elif ev.lower().startswith("by reading"):
            if e["label"] in marks:
                problems.append(f"{name}: says 'by reading' but has a printed-form test")
        elif "{ref}" not in ev and "{doc}" not in ev:
            problems.append(f"{name}: evidence names no chapter section")
        elif e["label"] not in marks:
            problems.append(f"{name}: no test of its printed form")
    labels = {e["label"] for e in found}
    problems += [f"@erratum({x!r}) names no entry of the page" for x in sorted(set(marks) - labels)]
    return problems


ENTRIES = entries(PAGE.read_text(encoding="utf-8"))


def test_the_page_has_entries_of_both_kinds():
    assert {e["kind"] for e in ENTRIES} == {"E", "N"}


def test_every_entry_has_a_unique_label_naming_its_paper():
    assert not label_problems(ENTRIES), "\n".join(label_problems(ENTRIES))


@pytest.mark.parametrize("kind", ["E", "N"])
def test_numbers_run_in_page_order(kind):
    assert not numbering_problems(ENTRIES, kind)


def test_errata_sit_in_their_papers_section_in_the_order_of_the_papers():
    assert not placement_problems(ENTRIES), "\n".join(placement_problems(ENTRIES))


def test_every_erratum_is_checked_against_its_printed_form_or_read():
    problems = evidence_problems(ENTRIES, marked_labels())
    assert not problems, "\n".join(problems)


def test_the_detectors_fail_on_a_broken_page():
    page = PAGE.read_text(encoding="utf-8")
    assert label_problems(entries(page.replace("(erratum-", "(nolabel-", 1)))
    errata = [e for e in ENTRIES if e["kind"] == "E"]
    swapped = [dict(e) for e in ENTRIES]
    first, last = (swapped.index(e) for e in (errata[0], errata[-1]))
    swapped[first], swapped[last] = swapped[last], swapped[first]
    assert numbering_problems(swapped, "E") and placement_problems(swapped)
    assert evidence_problems(ENTRIES, {})  # no printed-form tests at all
    unread = [dict(e, evidence="a sentence") if e["kind"] == "E" else e for e in ENTRIES]
    assert evidence_problems(unread, marked_labels())
    assert evidence_problems(ENTRIES, {**marked_labels(), "erratum-mo2015-nowhere": ["x"]})
