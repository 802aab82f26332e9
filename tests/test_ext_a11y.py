"""book/_ext/a11y.py: the sidebar's toggles get a name, the bibliography's entries a role that
is not deprecated (issue 48; the browser check runs axe-core on the built pages)."""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "book" / "_ext"))
import a11y  # noqa: E402

# as pydata-sphinx-theme 0.17 writes an entry with sections, and a part caption's toggle
NAV = ('<ul class="nav bd-sidenav"><li class="toctree-l1 has-children">'
       '<a class="reference internal" href="dey2009/index.html">Dey, Leong\n &amp; Evans</a>'
       '<details><summary><span class="toctree-toggle" role="presentation"><i class="fa">'
       '</i></span></summary><ul><li class="toctree-l2"><a href="x.html">x</a></li></ul>'
       '</details></li><li class="toctree-l0"><details><summary><p class="caption">Part I</p>'
       '<span class="toctree-toggle" role="presentation"></span></summary></details></li></ul>')


def test_an_icon_only_toggle_is_named_after_its_entry():
    out = a11y.name_toggles(NAV)
    assert '<summary aria-label="Sections of Dey, Leong &amp; Evans">' in out
    assert out.count("aria-label") == 1  # the caption's toggle has its text as its name
    assert a11y.name_toggles(out) == out


def test_the_bibliography_entries_become_list_items():
    context = {"body": '<div role="list" class="citation-list">\n<div class="citation" '
                       'id="id6" role="doc-biblioentry">\n<p>A book.</p></div></div>'}
    a11y._page_context(None, "book/bibliography", "page.html", context, None)
    assert 'role="listitem"' in context["body"] and "doc-biblioentry" not in context["body"]


def test_the_theme_function_is_wrapped_and_its_soup_labelled():
    from bs4 import BeautifulSoup

    context = {"generate_toctree_html": lambda kind, **kw: BeautifulSoup(NAV, "html.parser")}
    a11y._page_context(None, "intro", "page.html", context, None)
    soup = context["generate_toctree_html"](kind="sidebar", startdepth=0)
    assert soup.select_one("summary")["aria-label"] == "Sections of Dey, Leong & Evans"
