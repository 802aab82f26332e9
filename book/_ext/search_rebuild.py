"""Keep the index entries of the pages a rebuild does not rewrite in the site's search index.

Sphinx 7.4 rebuilds ``searchindex.js`` from the previous one plus the pages it writes, but it
reads back neither the ``indexentries`` of the previous index nor keeps them in its pickled
environment (sphinx-doc/sphinx#12599, open). After a second build of the same tree, every page
that was not rewritten has lost its index entries: measured on the fast site, the section shrank
from 107 kB to nothing, and the search for "Table II" or "Fig. 3(a)" no longer put the page that
reproduces it first (tests/site/test_page.py failed on a second ``make test`` in one clone).

Before the index is written (``html-collect-pages`` comes first), every page that the indexer
holds from the previous index but did not index in this build gets its entries back from the
previous ``searchindex.js``, as Sphinx froze them (lower case; ``main`` as a flag). The entries of
the pages written in this build are Sphinx's own. tests/test_ext_search_rebuild.py builds a
small project twice, with and without this extension.
"""

from __future__ import annotations

from pathlib import Path


def restore_index_entries(app) -> int:
    """Give the kept pages their index entries from the previous index; returns how many
    pages got some."""
    from sphinx.search import js_index

    builder = app.builder
    indexer = getattr(builder, "indexer", None)
    path = Path(builder.outdir) / getattr(builder, "searchindex_filename", "searchindex.js")
    if indexer is None or not path.is_file():
        return 0
    try:
        frozen = js_index.loads(path.read_text(encoding="utf-8"))
    except ValueError:
        return 0
    if not isinstance(frozen, dict) or frozen.get("envversion") != app.env.version:
        return 0  # Sphinx did not load it either: nothing is kept from it
    names = frozen.get("docnames", [])
    # kept from the previous index (their titles are loaded), not indexed in this build
    kept = {doc for doc in indexer._titles if doc not in indexer._index_entries}
    restored: dict[str, set[tuple[str, str, str]]] = {}
    for entry, refs in (frozen.get("indexentries") or {}).items():
        for ref in refs:
            doc = names[ref[0]]
            if doc in kept:
                restored.setdefault(doc, set()).add((entry, ref[1], "main" if ref[2] else ""))
    for doc, entries in restored.items():
        indexer._index_entries[doc] = sorted(entries)
    return len(restored)


def _collect_pages(app):
    restore_index_entries(app)
    return []


def setup(app):
    app.connect("html-collect-pages", _collect_pages)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1.0"}
