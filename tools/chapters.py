"""The book's chapters as the table of contents lists them, shared by the tools and the tests."""

from __future__ import annotations

from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parent.parent
GOLDEN = ROOT / "tests" / "golden"


def toc_files() -> list[str]:
    """Every ``file:`` of ``_toc.yml`` (the root first), without extension."""
    toc = yaml.safe_load((ROOT / "_toc.yml").read_text())
    out = [toc["root"]]

    def walk(node):
        if isinstance(node, dict):
            if "file" in node:
                out.append(node["file"])
            for key in ("parts", "chapters", "sections"):
                for child in node.get(key, []) or []:
                    walk(child)
        elif isinstance(node, list):
            for child in node:
                walk(child)

    walk(toc)
    return out


def source(docname: str) -> Path:
    for ext in (".md", ".ipynb"):
        p = ROOT / f"{docname}{ext}"
        if p.exists():
            return p
    raise FileNotFoundError(f"no source for toc entry {docname!r}")


def is_notebook(path: Path) -> bool:
    """A MyST markdown notebook (jupytext header with a kernelspec) or an .ipynb."""
    if path.suffix == ".ipynb":
        return True
    text = path.read_text()
    if not text.startswith("---"):
        return False
    header = text.split("---", 2)[1]
    return "kernelspec" in header and "jupytext" in header


def notebook_chapters() -> list[str]:
    return [d for d in toc_files() if is_notebook(source(d))]


def golden_path(docname: str) -> Path:
    return GOLDEN / (docname.replace("/", "__") + ".ipynb")
