"""Unrendered markup: MyST or LaTeX source that reaches the reader.

The served HTML (text outside math, code and scripts; page titles; link texts) and the search
index (page and section titles of searchindex.js) must contain no MyST or LaTeX source: no TeX
control word (``\\tilde``, ``\\text{``), no role (``{cite}``, ``{eq}``, ``{glue}``...) and no
pair of ``$`` around text (:func:`check_markup`, from the files, no browser).
"""

from __future__ import annotations

import os
import re
from html.parser import HTMLParser
from pathlib import Path

from .page import list_pages

# Markup that must never reach the reader.
RAW_MARKUP = [
    ("TeX control word", re.compile(r"\\[A-Za-z]{2,}")),
    ("TeX delimiter", re.compile(r"\\[()\[\]]|\$\$")),
    ("MyST role", re.compile(r"\{(?:cite|cite:[tp]|eq|glue|glue:\w+|ref|doc|numref|term|math|"
                             r"index|download|prf:\w+)\}`?")),
    ("$ pair", re.compile(r"(?<![\\$\w])\$(?=[^\s$])[^$\n]{1,200}?(?<=[^\s\\$])\$(?![\w$])")),
]
# Elements whose text is not prose: math (typeset by MathJax), code, scripts.
_NOT_PROSE_TAGS = {"script", "style", "pre", "code", "kbd", "samp", "textarea", "svg",
                   "mjx-container"}
_NOT_PROSE_CLASSES = {"math", "highlight", "notranslate", "cell_input", "MathJax"}
VOID_TAGS = {"area", "base", "br", "col", "embed", "hr", "img", "input", "link", "meta",
             "source", "track", "wbr"}


def find_raw_markup(text: str) -> list[tuple[str, str]]:
    """The (kind, excerpt) of every piece of MyST/LaTeX source in ``text``."""
    found = []
    for kind, rx in RAW_MARKUP:
        for m in rx.finditer(text):
            a, b = max(0, m.start() - 30), min(len(text), m.end() + 30)
            found.append((kind, " ".join(text[a:b].split())))
    return found


class _ProseText(HTMLParser):
    """Collect the text of an HTML page that a reader sees as prose (and the page title)."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self._stack: list[bool] = []  # per open element: is it (or an ancestor) not prose?
        self.chunks: list[str] = []
        self._buf: list[str] = []

    def _flush(self) -> None:
        if self._buf:
            self.chunks.append("".join(self._buf))
            self._buf = []

    def handle_starttag(self, tag, attrs):
        if tag in VOID_TAGS:
            return
        a = {k: (v or "") for k, v in attrs}
        skip = (tag in _NOT_PROSE_TAGS or bool(set(a.get("class", "").split())
                                               & _NOT_PROSE_CLASSES))
        parent = self._stack[-1] if self._stack else False
        if skip != parent:
            self._flush()
        self._stack.append(parent or skip)

    def handle_endtag(self, tag):
        if tag in VOID_TAGS:
            return
        if self._stack:
            was = self._stack.pop()
            if was != (self._stack[-1] if self._stack else False):
                self._flush()
        if tag in ("p", "a", "li", "td", "th", "title", "h1", "h2", "h3", "h4", "h5", "h6",
                   "dt", "dd", "div", "span"):
            self._flush()

    def handle_data(self, data):
        if not (self._stack and self._stack[-1]):
            self._buf.append(data)

    def close(self):
        super().close()
        self._flush()


def raw_markup_in_html(text: str) -> list[tuple[str, str]]:
    parser = _ProseText()
    parser.feed(text)
    parser.close()
    return [hit for chunk in parser.chunks for hit in find_raw_markup(chunk)]


def raw_markup_in_search_index(text: str) -> list[tuple[str, str]]:
    """Raw markup in the page and section titles of a Sphinx ``searchindex.js``."""
    import json

    start, end = text.find("{"), text.rfind("}")
    data = json.loads(text[start:end + 1])
    titles = list(data.get("titles", [])) + list(data.get("alltitles", {}))
    return [hit for t in titles for hit in find_raw_markup(t)]


def check_markup(html_dir: str | os.PathLike[str]) -> tuple[list[str], dict[str, int]]:
    """Scan every page and the search index for unrendered markup: (problems, counts)."""
    html_dir = Path(html_dir)
    problems: list[str] = []
    counts: dict[str, int] = {}
    for path in list_pages(html_dir):
        rel = path.relative_to(html_dir).as_posix()
        hits = raw_markup_in_html(path.read_text(encoding="utf-8", errors="replace"))
        counts[rel] = len(hits)
        problems += [f"page {rel}: unrendered markup ({kind}): {ex!r}" for kind, ex in hits]
    index = html_dir / "searchindex.js"
    if index.is_file():
        hits = raw_markup_in_search_index(index.read_text(encoding="utf-8"))
        counts["searchindex.js"] = len(hits)
        problems += [f"searchindex.js: unrendered markup in a title ({kind}): {ex!r}"
                     for kind, ex in hits]
    else:
        problems.append("searchindex.js missing: the search index cannot be checked")
    return problems, counts


# ============================================================================================
# A chapter reads as a book (issue 27), read from the served HTML of every chapter page
# (``book/<part>/<chapter>.html``; the API reference and the index pages are not chapters):
# images in a cell's output that are not a numbered, captioned figure; outputs printing a
# Python repr or a bare boolean; ASCII stand-ins for mathematics in prose, tables, headings,
# captions and outputs; lines of unfolded code (cells not tagged hide-input/hide-cell) before
# the Reproduction notes; doubled words in the prose ("the The", "Exercise Exercise"); numbers
# typed in the prose that an output of the same page contradicts (41.8 where it prints 41.60).
