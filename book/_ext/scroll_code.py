"""Mark code listings as horizontally scrollable, and nothing else; name what a folded cell does.

Every literal block that is code a reader copies (a code cell's input, a code fence in the
prose) gets the class ``fc-scroll-code``; the book's stylesheet (``book/_static/fusioncenter.css``)
lets exactly those scroll sideways, so that a long line of code keeps its layout. Cell outputs
(printed results, tables) do not get the class: they wrap, and the browser check
(``tools/browser_check``) fails on any other element whose content is wider than its box.

A folded cell (tag ``hide-input``) opens with a one-line comment that says what it does; its
toggle shows that line ("Show code: the figure's plot code") instead of myst-nb's
"Show code cell source", so that the page says what is folded without opening it.
"""

from __future__ import annotations

from docutils import nodes
from sphinx.transforms import SphinxTransform
from sphinx.transforms.post_transforms import SphinxPostTransform

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


class NameFoldedCells(SphinxPostTransform):
    """The toggle of a folded cell's input says what the cell does (its first comment line)."""

    default_priority = 200  # after myst-nb's HideInputCells (199) made the toggles
    formats = ("html",)

    def run(self, **kwargs) -> None:
        from myst_nb.sphinx_ import HideCodeCellNode

        for node in self.document.findall(HideCodeCellNode):
            if "above-input" not in node["classes"]:
                continue
            block = next(iter(node.findall(nodes.literal_block)), None)
            first = block.astext().lstrip().split("\n", 1)[0].strip() if block else ""
            if first.startswith("#") and len(first.lstrip("# ")) > 3:
                what = first.lstrip("# ").rstrip()
                node["prompt_show"] = f"Show code: {what}"
                node["prompt_hide"] = f"Hide code: {what}"


def setup(app):
    app.add_transform(MarkScrollableCode)
    app.add_post_transform(NameFoldedCells)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1.0"}
