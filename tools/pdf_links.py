"""The PDF's links: the printed links between the site's pages made into links inside the PDF.

:func:`destinations` finds where each anchor of each printed page landed in the merged PDF;
:func:`relink` points every link to a page of the book there and every other link to the
local print server at the published site. Used by ``tools/pdf_book.py``'s ``Printer``.
"""

from __future__ import annotations

from urllib.parse import unquote, urlsplit


def destinations(docs) -> tuple[dict, dict, dict]:
    """Where each anchor of each page is in the merged PDF. ``docs`` is ``(docname, its
    PdfReader, the index of its first page in the merged PDF)`` in order. Returns
    ``(dests, first, page_doc)``: ``dests[doc][id] = (page index, left, top)`` from Chromium's
    named destinations, ``first[doc]`` the page index where ``doc`` starts, ``page_doc[index]``
    the doc a page belongs to."""
    dests: dict[str, dict[str, tuple[int, float, float]]] = {}
    page_doc: dict[int, str] = {}
    first: dict[str, int] = {}
    for doc, reader, start in docs:
        first[doc] = start
        for k in range(len(reader.pages)):
            page_doc[start + k] = doc
        table = {}
        for name, d in reader.named_destinations.items():
            try:
                k = reader.get_destination_page_number(d)
            except Exception:  # a destination without a page of this reader
                continue
            table[str(name).lstrip("/")] = (start + k, float(d.left or 0), float(d.top or 0))
        dests[doc] = table
    return dests, first, page_doc


def relink(writer, where, origin: str, baseurl: str) -> dict[str, int]:
    """Make the printed links work in the PDF.

    Chromium prints a link to another page of the site as a link to the local print server
    (``origin``, gone once the PDF is written) and a link inside the page as a named
    destination of that page's own PDF. Every link to a page of the book becomes a link to
    the place in the PDF (the anchor's destination, else the page's first page); every other
    link to the local server (figure data, the index, the search page) goes to the published
    site ``baseurl``; links elsewhere are kept. ``where`` is :func:`destinations`'s answer.
    Returns the counts by kind."""
    from pypdf.generic import ArrayObject, FloatObject, NameObject, NullObject

    dests, first, page_doc = where
    counts = {"internal": 0, "to the site": 0, "kept": 0, "unresolved": 0}

    def explicit(idx: int, left: float, top: float):
        return ArrayObject([writer.pages[idx].indirect_reference, NameObject("/XYZ"),
                            FloatObject(left), FloatObject(top), NullObject()])

    def target(doc: str, fragment: str):
        if fragment:
            for key in (fragment, unquote(fragment)):
                if key in dests.get(doc, {}):
                    return dests[doc][key]
        return (first[doc], 0.0, 10_000.0) if doc in first else None

    for i, page in enumerate(writer.pages):
        for ref in page.get("/Annots") or []:
            a = ref.get_object()
            if a.get("/Subtype") != "/Link":
                continue
            dest = a.get("/Dest")
            if dest is not None and not isinstance(dest, list):
                t = dests.get(page_doc.get(i, ""), {}).get(str(dest).lstrip("/"))
                if t is None:
                    counts["unresolved"] += 1
                    continue
                a[NameObject("/Dest")] = explicit(*t)
                counts["internal"] += 1
                continue
            action = a.get("/A")
            uri = str(action.get("/URI", "")) if action is not None else ""
            if not uri.startswith(origin + "/") or not origin:
                counts["kept"] += 1 if uri else 0
                continue
            parts = urlsplit(uri[len(origin):])
            path = unquote(parts.path).lstrip("/")
            doc = path.removesuffix(".html") if path.endswith(".html") else None
            t = target(doc, parts.fragment) if doc in first else None
            if t is not None:
                del a[NameObject("/A")]
                a[NameObject("/Dest")] = explicit(*t)
                counts["internal"] += 1
            else:
                action[NameObject("/URI")] = type(action["/URI"])(
                    baseurl.rstrip("/") + "/" + uri[len(origin):].lstrip("/"))
                counts["to the site"] += 1
    return counts
