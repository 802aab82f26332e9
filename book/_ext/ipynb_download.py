"""Offer every executed chapter as an ``.ipynb`` in the page's download menu.

sphinx-book-theme adds the ``.ipynb`` entry only when a Binder/JupyterHub launch button is
configured. This extension does it unconditionally: for a page whose source is a MyST markdown
notebook, it copies the notebook MyST-NB executed (``jupyter_execute/<page>.ipynb``, with its
outputs) next to the page's sources and tells the theme about it. It runs before the theme's
header buttons (priority 500 < 501).
"""

from __future__ import annotations

import shutil
from pathlib import Path


def _add_ipynb(app, pagename, templatename, context, doctree):
    if doctree is None or not str(context.get("sourcename", "")).endswith((".md", ".md.txt")):
        return
    executed = Path(app.outdir).parent / "jupyter_execute" / f"{pagename}.ipynb"
    if not executed.exists():
        return
    target = Path(app.outdir) / "_sources" / f"{pagename}.ipynb"
    target.parent.mkdir(parents=True, exist_ok=True)
    shutil.copy2(executed, target)
    context["ipynb_source"] = f"{pagename}.ipynb"


def setup(app):
    app.connect("html-page-context", _add_ipynb, priority=500)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1.0"}
