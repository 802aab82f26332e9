"""A chapter reads as a book (issue 27), read from the served HTML of every chapter page.

``book/<part>/<chapter>.html`` (the API reference and the index pages are not chapters):
images in a cell's output that are not a numbered, captioned figure; outputs printing a Python
repr or a bare boolean; ASCII stand-ins for mathematics in prose, tables, headings, captions
and outputs; lines of unfolded code (cells not tagged hide-input/hide-cell) before the
Reproduction notes; doubled words in the prose ("the The", "Exercise Exercise"); numbers typed
in the prose that an output of the same page contradicts (41.8 where it prints 41.60). All
from the files (:func:`check_reading`), no browser.
"""

from __future__ import annotations

import os
import re
from html.parser import HTMLParser
from pathlib import Path

from .markup import VOID_TAGS
from .page import list_pages

#: The median chapter page shows at most this many non-blank lines of unfolded code before its
#: Reproduction notes (issue 46: the argument first, the audit after it).
MAX_MEDIAN_CODE_LINES = 40
#: The heading of the section that holds a chapter's audit; code after it is not counted.
NOTES_HEADING = "Reproduction notes"
#: Elements that end a run of prose: a doubled word is looked for inside one of them only.
_BLOCK_TAGS = {"p", "li", "td", "th", "dt", "dd", "h1", "h2", "h3", "h4", "h5", "h6",
               "figcaption", "caption", "div", "section", "table", "tr", "summary", "blockquote"}
#: Text that is not typed by hand: glued values, the numbers an explorable figure's slider
#: sets, section, figure and equation numbers, and the text of internal links ("Fig. 6.1").
_COMPUTED_CLASSES = ("pasted-text", "pasted-inline", "fc-explore-fact", "section-number",
                     "caption-number", "eqno", "internal")
#: Parts of a page whose typed numbers are compared with their own outputs only.
_SEGMENT_CLASSES = {"solution", "exercise", "admonition", "proof"}
#: A word written twice in a row (case-insensitive): "the The", "Exercise Exercise".
DOUBLED_WORD = re.compile(r"\b([A-Za-z]{2,})\s+\1\b", re.IGNORECASE)
#: A decimal number as text: 41.8, 0.437, -1.25 (not 3, not 1e-3's mantissa alone).
DECIMAL = re.compile(r"(?<![\w.])-?\d+\.\d+(?![\w.]*\d)")
#: Printed output that is a Python repr or a bare boolean, not a result for a reader.
REPR_OUTPUT = [
    ("bare boolean", re.compile(r"^\s*(?:True|False)\s*$|:\s*(?:True|False)\s*$", re.M)),
    ("array repr", re.compile(r"\barray\(")),
    ("Matrix repr", re.compile(r"\b(?:Immutable)?(?:Dense)?Matrix\(\[")),
    ("dict repr", re.compile(r"\{\s*'[^'\n]*'\s*:|\{\s*\"[^\"\n]*\"\s*:")),
    # three numbers or more: [a, b] is an interval, not a repr
    ("list repr", re.compile(r"\[\s*'[^'\n]*'\s*,|\[\s*-?\d[\d.e+-]*(?:\s*,\s*-?\d[\d.e+-]*)"
                             r"{2,}\s*\]|\[\s*-?\d[\d.e+-]*(?:\s+-?\d[\d.e+-]*){2,}\s*\]")),
]
#: ASCII stand-ins for mathematics (typeset them, or write Unicode: x̂, σᵥ, hᵀ, √).
GREEK = ("alpha|beta|gamma|delta|epsilon|zeta|eta|theta|kappa|lambda|mu|nu|xi|pi|rho|sigma|"
          "tau|phi|chi|psi|omega|Gamma|Delta|Sigma|Phi|Psi|Omega|Lambda|Theta")
ASCII_MATH = [
    ("hat name", re.compile(r"\b[A-Za-z]+_hat(?![A-Za-z])|\bhat_[A-Za-z]")),
    # sigma_v, lambda_12, sigma_w2, zeta_inf, gamma^2; not an identifier (delta_for_rate)
    ("Greek name with index", re.compile(rf"\b(?:{GREEK})(?:_\{{|_[A-Za-z0-9]{{1,2}}\b|_inf\b|"
                                         r"\^\d)")),
    ("TeX subscript", re.compile(r"\b[A-Za-z]_\{[^}\s]{1,12}\}")),
    ("transpose", re.compile(r"\b[A-Za-z]\^T\b")),
    ("sqrt", re.compile(r"\bsqrt\(")),
]


def find_repr_output(text: str) -> list[tuple[str, str]]:
    """The (kind, excerpt) of every Python repr or bare boolean in printed output ``text``."""
    return [(kind, " ".join(text[max(0, m.start() - 30):m.end() + 30].split()))
            for kind, rx in REPR_OUTPUT for m in rx.finditer(text)]


def find_doubled_words(blocks: list[str]) -> list[str]:
    """Every word written twice in a row inside one block of prose ("the The")."""
    out = []
    for block in blocks:
        text = " ".join(block.split())
        out += [" ".join(text[max(0, m.start() - 30):m.end() + 30].split())
                for m in DOUBLED_WORD.finditer(text)]
    return out


def _significant(token: str) -> int:
    return len(token.lstrip("-").replace(".", "").lstrip("0"))


def find_contradicted_numbers(typed: list[tuple[int, str]],
                              printed: list[tuple[int, str]]) -> list[str]:
    """Numbers typed in the prose that an output of the same part of the page contradicts.

    ``typed`` and ``printed`` are ``(segment, text)`` pairs: the prose and mathematics outside
    glued values, and the outputs (cell outputs, evidence tables), each with the segment of
    the page it stands in (a section, an exercise, a solution, an admonition). A decimal
    number of three or more significant digits typed in a segment is contradicted when no
    output number of that segment rounds to it at its decimals, but one lies within 2 % of it:
    "C ≈ 41.8" in a solution whose output prints 41.60.
    """
    numbers: dict[int, list[float]] = {}
    for seg, text in printed:
        numbers.setdefault(seg, []).extend(float(t) for t in DECIMAL.findall(text))
    out = []
    for seg, text in typed:
        outputs = numbers.get(seg, [])
        for token in DECIMAL.findall(text):
            if _significant(token) < 3:
                continue
            x, decimals = float(token), len(token.split(".")[1])
            if any(abs(y - x) <= 0.5 * 10.0 ** -decimals * 1.0001 for y in outputs):
                continue
            near = [y for y in outputs if y and abs(x - y) <= 0.02 * abs(y)]
            if near:
                out.append(f"{token} in the text, {near[0]:g} in an output")
    return out


def find_ascii_math(text: str) -> list[tuple[str, str]]:
    """The (kind, excerpt) of every ASCII stand-in for mathematics in ``text``."""
    return [(kind, " ".join(text[max(0, m.start() - 30):m.end() + 30].split()))
            for kind, rx in ASCII_MATH for m in rx.finditer(text)]


class _Reading(HTMLParser):
    """What a chapter page shows: unfolded code lines, output texts, output images outside a
    captioned figure, and its prose (outside math, code and outputs)."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.stack: list[tuple[str, set[str]]] = []
        self.code_lines = 0
        self.outputs: list[str] = []
        self.loose_images: list[str] = []
        self.prose: list[str] = []
        self.blocks: list[str] = []  # the prose, one string per block element
        #: (segment, text) of the prose and mathematics outside glued values, and of the
        #: outputs (cell outputs and evidence tables): :func:`find_contradicted_numbers`
        self.typed: list[tuple[int, str]] = []
        self.printed: list[tuple[int, str]] = []
        self._segments: list[tuple[int, int]] = [(0, 0)]  # (depth in the stack, segment)
        self._count = 0
        self.in_notes = False  # past the Reproduction notes' heading
        self._block: list[str] = []
        self._heading: list[str] | None = None
        self._code: list[str] | None = None
        self._out: list[str] | None = None
        self._out_depth = 0

    def _has(self, cls: str) -> bool:
        return any(cls in c for _t, c in self.stack)

    def _tag(self, tag: str) -> bool:
        return any(t == tag for t, _c in self.stack)

    def handle_starttag(self, tag, attrs):
        a = {k: (v or "") for k, v in attrs}
        classes = set(a.get("class", "").split())
        if tag == "img":
            if self._has("cell_output") and not self._tag("figure"):
                self.loose_images.append(a.get("src", "")[-40:])
            return
        if tag in VOID_TAGS:
            return
        if tag in _BLOCK_TAGS:
            self._flush()
        if tag == "h2":
            self._heading = []
        self.stack.append((tag, classes))
        if tag == "section" or (tag == "div" and classes & _SEGMENT_CLASSES) or (
                tag == "details" and "fc-evidence" in classes):
            self._count += 1
            self._segments.append((len(self.stack), self._count))
        if self._has("math") and len(self.stack) and tag == "span":
            self._block.append(" ∙ ")  # mathematics stands between two words
        if tag == "pre" and self._has("cell_input") and self._code is None:
            folded = (self._has("tag_hide-input") or self._has("tag_hide-cell")
                      or self._tag("details") or self._has("dropdown"))  # a closed solution
            self._code = [] if not (folded or self.in_notes) else None
        if "cell_output" in classes and self._out is None:
            self._out, self._out_depth = [], len(self.stack)

    def _flush(self) -> None:
        if self._block:
            self.blocks.append("".join(self._block))
            self._block = []

    def handle_endtag(self, tag):
        if tag in VOID_TAGS or not self.stack:
            return
        if tag in _BLOCK_TAGS:
            self._flush()
        if tag == "h2" and self._heading is not None:
            if NOTES_HEADING in " ".join("".join(self._heading).split()):
                self.in_notes = True
            self._heading = None
        while self.stack:
            if self._segments[-1][0] == len(self.stack):
                self._segments.pop()
            t, _c = self.stack.pop()
            if tag == "pre" and t == "pre" and self._code is not None:
                self.code_lines += sum(1 for line in "".join(self._code).splitlines()
                                       if line.strip())
                self._code = None
            if self._out is not None and len(self.stack) < self._out_depth:
                self.outputs.append("".join(self._out))
                self._out = None
            if t == tag:
                break

    def handle_data(self, data):
        if self._heading is not None:
            self._heading.append(data)
        segment = self._segments[-1][1]
        if self._out is not None or self._has("fc-evidence"):
            self.printed.append((segment, data))
        elif not (any(self._has(c) for c in _COMPUTED_CLASSES) or self._tag("pre")
                  or self._tag("script") or self._tag("style") or self._has("cell_input")):
            self.typed.append((segment, data))
        if self._code is not None:
            self._code.append(data)
        math = self._has("math") or self._tag("mjx-container")
        if self._out is not None:
            if not math:
                self._out.append(data)
            return
        if not (math or self._tag("pre") or self._tag("code") or self._tag("script")
                or self._tag("style") or self._has("cell_input") or self._has("highlight")):
            self.prose.append(data)
            if not self._has("fc-evidence"):
                self._block.append(data)

    def close(self):
        super().close()
        self._flush()


def is_chapter(rel: str) -> bool:
    """A chapter page of the book (``book/<part>/<chapter>.html``, not a part's index nor
    the API reference's module pages)."""
    parts = rel.split("/")
    return (len(parts) == 3 and parts[0] == "book" and parts[1] != "api"
            and parts[2] != "index.html")


def read_page(text: str) -> _Reading:
    parser = _Reading()
    parser.feed(text)
    parser.close()
    return parser


def check_reading(html_dir: str | os.PathLike[str]) -> tuple[list[str], dict]:
    """The reading checks of every chapter page: (problems, per-page visible code lines before
    the Reproduction notes)."""
    html_dir = Path(html_dir)
    problems: list[str] = []
    code: dict[str, int] = {}
    for path in list_pages(html_dir):
        rel = path.relative_to(html_dir).as_posix()
        if not is_chapter(rel):
            continue
        page = read_page(path.read_text(encoding="utf-8", errors="replace"))
        code[rel] = page.code_lines
        problems += [f"page {rel}: an output image outside a numbered, captioned figure "
                     f"(...{src})" for src in page.loose_images]
        for out in page.outputs:
            problems += [f"page {rel}: output prints a {kind}: {ex!r}"
                         for kind, ex in find_repr_output(out)]
            problems += [f"page {rel}: ASCII mathematics in an output ({kind}): {ex!r}"
                         for kind, ex in find_ascii_math(out)]
        problems += [f"page {rel}: ASCII mathematics in the text ({kind}): {ex!r}"
                     for kind, ex in find_ascii_math(" ".join(page.prose))]
        problems += [f"page {rel}: a doubled word: {ex!r}"
                     for ex in find_doubled_words(page.blocks)]
        problems += [f"page {rel}: a number typed in the prose contradicts an output "
                     f"({ex}): glue it from the cell" for ex in
                     find_contradicted_numbers(page.typed, page.printed)]
    if code:
        import statistics

        median = statistics.median(code.values())
        if median > MAX_MEDIAN_CODE_LINES:
            problems.append(f"the median chapter page shows {median:g} lines of unfolded code "
                            f"(> {MAX_MEDIAN_CODE_LINES})")
    return problems, code
