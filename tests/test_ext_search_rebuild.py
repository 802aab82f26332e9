"""book/_ext/search_rebuild.py: a rebuilt site's search index keeps every page's index entries.

A three-page Sphinx project is built, then built again with one page changed; the index entries
of the search index must be those of a fresh build. Without the extension the second build loses
the entries of the pages it did not rewrite (sphinx-doc/sphinx#12599): if a Sphinx release fixes
that, the last test fails and says the extension can go.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from sphinx.application import Sphinx

EXT = Path(__file__).resolve().parents[1] / "book" / "_ext"
PAGES = {
    "index": "Home\n====\n\n.. toctree::\n\n   a\n   b\n",
    "a": "Page A\n======\n\n.. index:: Table II\n\n.. index:: single: Fig. 3(a)\n\nText a.\n",
    "b": "Page B\n======\n\n.. index:: Riccati recursion\n\nText b.\n",
}


def _project(root: Path, extension: bool) -> Path:
    src = root / "src"
    src.mkdir(parents=True)
    exts = ["search_rebuild"] if extension else []
    (src / "conf.py").write_text(f"import sys\nsys.path.insert(0, {str(EXT)!r})\n"
                                 f"extensions = {exts!r}\nproject = 'p'\n")
    for name, text in PAGES.items():
        (src / f"{name}.rst").write_text(text)
    return src


def _build(src: Path, out: Path) -> dict:
    app = Sphinx(str(src), str(src), str(out / "html"), str(out / "doctrees"), "html",
                 status=None, warning=None, freshenv=False)
    app.build()
    text = (out / "html" / "searchindex.js").read_text(encoding="utf-8")
    frozen = json.loads(text[text.index("(") + 1:text.rindex(")")])
    names = frozen["docnames"]
    return {entry: sorted((names[r[0]], r[1], bool(r[2])) for r in refs)
            for entry, refs in frozen["indexentries"].items()}


def _fresh_and_rebuilt(tmp_path: Path, extension: bool) -> tuple[dict, dict]:
    src = _project(tmp_path, extension)
    fresh = _build(src, tmp_path / "out")
    page_b = src / "b.rst"
    page_b.write_text(page_b.read_text() + "\nMore text.\n")  # b is rewritten, a is kept
    return fresh, _build(src, tmp_path / "out")


def test_a_rebuild_keeps_the_index_entries_of_the_pages_it_does_not_rewrite(tmp_path):
    fresh, rebuilt = _fresh_and_rebuilt(tmp_path, extension=True)
    assert {"table ii", "fig. 3(a)", "riccati recursion"} <= set(fresh)
    assert rebuilt == fresh


def test_without_it_sphinx_loses_them(tmp_path):
    fresh, rebuilt = _fresh_and_rebuilt(tmp_path, extension=False)
    assert "table ii" in fresh
    if "table ii" in rebuilt:
        pytest.fail("Sphinx now keeps the index entries of a rebuild (sphinx-doc/sphinx#12599 "
                    "fixed): book/_ext/search_rebuild.py can go")
    assert "riccati recursion" in rebuilt  # the page it rewrote keeps its own
