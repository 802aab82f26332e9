"""Mark code listings as horizontally scrollable, and nothing else.

Every literal block that is code a reader copies (a code cell's input, a code fence in the
prose) gets the class ``fc-scroll-code``; the book's stylesheet (``book/_static/fusioncenter.css``)
lets exactly those scroll sideways, so that a long line of code keeps its layout. Cell outputs
(printed results, tables) do not get the class: they wrap, and the browser check
(``tools/browser_check.py``) fails on any other element whose content is wider than its box.
"""

from __future__ import annotations

from docutils import nodes
from sphinx.transforms import SphinxTransform

SCROLL_CLASS = "fc-scroll-code"


def _in_output(node: nodes.Node) -> bool:
    while node is not None:
        classes = node.get("classes", []) if isinstance(node, nodes.Element) else []
        if "output" in classes or "cell_output" in classes:
            return True
        node = node.parent
    return False


class MarkScrollableCode(SphinxTransform):
    default_priority = 900

    def apply(self) -> None:
        for node in self.document.findall(nodes.literal_block):
            if not _in_output(node) and SCROLL_CLASS not in node["classes"]:
                node["classes"].append(SCROLL_CLASS)


def setup(app):
    app.add_transform(MarkScrollableCode)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1.0"}
