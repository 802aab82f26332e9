"""Names and roles a screen reader needs, on every page (issue 48; checked by axe-core in
tools/browser_check).

* The navigation sidebar's expand/collapse toggles: pydata-sphinx-theme writes each as a
  ``<summary>`` that holds only a chevron icon (``role="presentation"``), which a screen reader
  announces as a nameless button. Each gets ``aria-label="Sections of <the entry's title>"``:
  the theme's ``generate_toctree_html`` (a function of the page's template context) is wrapped
  so that the navigation tree it returns (a BeautifulSoup, or HTML) carries the names.
* The bibliography: docutils marks each entry ``role="doc-biblioentry"`` inside a
  ``role="list"``; that DPUB-ARIA role is deprecated, and with it ignored the list holds no
  list item. The entries become ``role="listitem"``.
"""

from __future__ import annotations

import functools

from bs4 import BeautifulSoup


def label_toggles(soup) -> None:
    """Give every ``<summary>`` of ``soup`` (BeautifulSoup) that has no text of its own an
    ``aria-label`` named after the title of its entry (in place; a named one is kept)."""
    for summary in soup.select("details > summary"):
        if summary.get_text(strip=True) or summary.get("aria-label"):
            continue
        entry = summary.parent.parent
        link = entry.find("a", recursive=False) if entry is not None else None
        title = " ".join(link.get_text().split()) if link is not None else ""
        summary["aria-label"] = f"Sections of {title}" if title else "Sections"


def name_toggles(html: str) -> str:
    """``html`` (a navigation tree of the theme) with its toggles named (:func:`label_toggles`)."""
    if "<summary" not in html:
        return html
    soup = BeautifulSoup(html, "html.parser")
    label_toggles(soup)
    return str(soup)


def _page_context(app, pagename, templatename, context, doctree):
    generate = context.get("generate_toctree_html")
    if generate is not None and not getattr(generate, "fc_a11y", False):
        @functools.wraps(generate)
        def named(kind, *args, **kwargs):
            out = generate(kind, *args, **kwargs)
            if isinstance(out, str):
                return name_toggles(out)
            if hasattr(out, "select"):  # the theme's BeautifulSoup (cached per page)
                label_toggles(out)
            return out

        named.fc_a11y = True
        context["generate_toctree_html"] = named
    body = context.get("body")
    if body and 'role="doc-biblioentry"' in body:
        context["body"] = body.replace('role="doc-biblioentry"', 'role="listitem"')


def setup(app):
    # after the theme's own handlers (priority 500), which put generate_toctree_html there
    app.connect("html-page-context", _page_context, priority=900)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1.0"}
