"""Drop duplicated inline ``<script>`` entries from each page.

With Sphinx 7.4, a body-only script that an extension registers after the builder started
(sphinx-thebe's ``const THEBE_JS_URL = ...``) is emitted twice, once with ``filename=None`` and
once with ``filename=''``; the second copy throws "Identifier has already been declared" in the
browser. Entries are keyed on (filename or '', attributes) and kept once, in order.
"""

from __future__ import annotations


def _dedupe(app, pagename, templatename, context, doctree):
    files = context.get("script_files")
    if not files:
        return
    seen, out = set(), []
    for js in files:
        key = (
            str(getattr(js, "filename", js) or ""),
            tuple(sorted((getattr(js, "attributes", {}) or {}).items())),
        )
        if key not in seen:
            seen.add(key)
            out.append(js)
    files[:] = out


def setup(app):
    app.connect("html-page-context", _dedupe)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1.0"}
