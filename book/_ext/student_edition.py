"""The student edition: the same book without the solutions to its exercises.

Set ``FUSIONCENTER_EDITION=student`` for the build (``make book-student`` does) and every
solution is dropped: the ``{solution}`` directives and the gated ``{solution-start}`` ...
``{solution-end}`` blocks with whatever they contain (text, math, code cells and their outputs)
are removed from the pages, and the cells between them from the ``.ipynb`` offered for download.
Each dropped solution leaves one line saying so, and the page's MyST source is not copied to the
site. Unset (or ``instructor``) builds the instructor's edition, where the solutions stay on the
page, collapsed (``:class: dropdown``); any other value stops the build.

The doctree pass runs after sphinx-exercise merged the gated blocks into one solution node
(its transform has priority 10), so a gated solution goes with everything inside it.
"""

from __future__ import annotations

import json
import os
import re
from pathlib import Path

from docutils import nodes
from sphinx.transforms import SphinxTransform

EDITION_VAR = "FUSIONCENTER_EDITION"
EDITIONS = ("instructor", "student")
NOTE = "The solution is left out of the student edition."
_START = re.compile(r"^\s*(`{3,}|:{3,})\{solution(-start)?\}", re.M)
_END = re.compile(r"^\s*(`{3,}|:{3,})\{solution-end\}", re.M)


def edition() -> str:
    """The edition this build makes: ``instructor`` (default) or ``student``."""
    value = os.environ.get(EDITION_VAR, "").strip().lower() or "instructor"
    if value not in EDITIONS:
        raise ValueError(f"{EDITION_VAR} must be one of {EDITIONS} or unset, got {value!r}")
    return value


class DropSolutions(SphinxTransform):
    """Replace every merged solution node by a one-line note (student edition only)."""

    default_priority = 20

    def apply(self) -> None:
        if edition() != "student":
            return
        from sphinx_exercise.nodes import solution_end_node, solution_node, solution_start_node

        for cls in (solution_node, solution_start_node, solution_end_node):
            for node in list(self.document.findall(cls)):
                if cls is solution_node:
                    note = nodes.paragraph(classes=["solution-omitted"])
                    note += nodes.emphasis(text=NOTE)
                    node.replace_self(note)
                else:
                    node.parent.remove(node)


def _fence_end(text: str, fence: str, pos: int) -> int:
    """The index just after the line that closes a directive opened with ``fence``."""
    m = re.compile(rf"^\s*{re.escape(fence)}\s*$", re.M).search(text, pos)
    return len(text) if m is None else m.end()


def _strip_markdown(text: str, inside: bool) -> tuple[str, bool, int]:
    """Remove solution directives from one markdown cell; (kept text, still inside, removed)."""
    kept, pos, removed = [], 0, 0
    while pos <= len(text):
        if inside:
            m = _END.search(text, pos)
            if m is None:
                return "".join(kept), True, removed + 1
            pos, inside, removed = _fence_end(text, m.group(1), m.end()), False, removed + 1
            continue
        m = _START.search(text, pos)
        if m is None:
            kept.append(text[pos:])
            break
        kept.append(text[pos:m.start()] + f"*{NOTE}*\n")
        removed += 1
        pos = _fence_end(text, m.group(1), m.end())
        inside = bool(m.group(2))  # a gated {solution-start}: its body runs to {solution-end}
    return "".join(kept), inside, removed


def strip_notebook(nb: dict) -> int:
    """Remove the solutions from a notebook in place; return how many pieces went.

    A solution is a ``{solution}`` directive, or everything from ``{solution-start}`` to
    ``{solution-end}``, code cells included. Text around them in the same markdown cell stays.
    """
    kept, removed, inside = [], 0, False
    for cell in nb.get("cells", []):
        if cell.get("cell_type") != "markdown":
            if inside:
                removed += 1
            else:
                kept.append(cell)
            continue
        src = "".join(cell.get("source", ""))
        text, inside, n = _strip_markdown(src, inside)
        removed += n
        if text.strip():
            kept.append({**cell, "source": text})
    nb["cells"] = kept
    return removed


def _strip_download(app, pagename, templatename, context, doctree) -> None:
    """After ipynb_download copied the executed notebook, remove its solution cells."""
    if edition() != "student":
        return
    context["sourcename"] = ""  # Sphinx copies the MyST source (solutions and all) only if named
    if not context.get("ipynb_source"):
        return
    target = Path(app.outdir) / "_sources" / context["ipynb_source"]
    if not target.exists():
        return
    nb = json.loads(target.read_text(encoding="utf-8"))
    if strip_notebook(nb):
        target.write_text(json.dumps(nb, indent=1, ensure_ascii=False) + "\n", encoding="utf-8")


def setup(app):
    edition()  # a bad value fails the build at once
    app.add_transform(DropSolutions)
    app.connect("html-page-context", _strip_download, priority=600)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1.0"}
