"""The ``{execution-status}`` directive: how each chapter of this build was executed.

``tools/build_book.py`` writes ``<out>/_build/execution-status.json`` (per chapter: profile,
execution time, executed in this build or taken from the execution cache, and when) before
Sphinx renders; the directive turns it into a table. Built without that tool (a bare
``jupyter-book build``) there is no record, and the page says so. The page is re-read on every
build (its source never changes, the record does).
"""

from __future__ import annotations

import json
from pathlib import Path

from docutils import nodes
from sphinx import addnodes
from sphinx.util.docutils import SphinxDirective

STATUS = "execution-status.json"


def _table(header: list[str], rows: list[list[str]]) -> nodes.table:
    table = nodes.table(classes=["execution-status"])
    group = nodes.tgroup(cols=len(header))
    table += group
    for _ in header:
        group += nodes.colspec(colwidth=1)
    head = nodes.thead()
    group += head
    body = nodes.tbody()
    group += body
    for target, cells in ((head, [header]), (body, rows)):
        for cells_row in cells:
            row = nodes.row()
            for cell in cells_row:
                entry = nodes.entry()
                entry += cell if isinstance(cell, nodes.Node) else nodes.paragraph(text=cell)
                row += entry
            target += row
    return table


def _when(iso: str) -> str:
    """``2026-12-01T23:05:49`` as ``2026-12-01 23:05``."""
    return iso.replace("T", " ")[:16]


class ExecutionStatus(SphinxDirective):
    has_content = False

    def run(self):
        path = Path(self.env.app.outdir).parent / STATUS
        if not path.exists():
            return [nodes.paragraph(text="No execution record: this site was not built with "
                                    "tools/build_book.py.")]
        rec = json.loads(path.read_text())
        rows = []
        for r in rec["chapters"]:
            para = nodes.paragraph()  # a link to the chapter, with its title
            ref = addnodes.pending_xref("", refdomain="std", reftype="doc",
                                        reftarget=f"/{r['doc']}", refexplicit=False,
                                        refdoc=self.env.docname, refwarn=True)
            ref += nodes.inline(text=r["doc"])
            para += ref
            secs = r.get("seconds")
            rows.append([para, r["profile"], "-" if secs is None else f"{secs:.1f}",
                         "cache" if r["from_cache"] else
                         f"executed by {r['by']}" if r.get("by") else "executed",
                         _when(r["executed"]),
                         r["status"]])
        total = sum(r.get("seconds") or 0.0 for r in rec["chapters"])
        executed = [r for r in rec["chapters"] if not r["from_cache"]]
        by_nbval = sum(1 for r in executed if r.get("by") == "nbval")
        stages = rec.get("stages", {})
        here = len(executed) - by_nbval
        summary = nodes.paragraph(text=(
            f"Profile {rec['profile']}, built {_when(rec['built'])}: {len(rec['chapters'])} "
            f"notebook chapters, "
            + (f"{here} executed in this build ({rec.get('jobs')} at a time), " if here else "")
            + (f"{by_nbval} executed by nbval's kernels in the same test run (their outputs "
               f"checked against the reference notebooks), " if by_nbval else "")
            + f"{len(rec['chapters']) - len(executed)} taken from the execution cache; their "
            f"execution times add up to {total:.1f} s"
            + (f", the execution stage took {stages['execution_s']:.1f} s of wall time"
               if "execution_s" in stages and here else "") + "."))
        header = ["chapter", "profile", "execution time (s)", "source", "executed at",
                  "status"]
        return [summary, _table(header, rows)]


def _always_outdated(app, env, added, changed, removed):
    return [d for d in env.found_docs if d.endswith("/status") or d == "status"]


def setup(app):
    app.add_directive("execution-status", ExecutionStatus)
    app.connect("env-get-outdated", _always_outdated)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1.0"}
