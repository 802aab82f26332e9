"""The API reference page: which modules it lists, and how it prepares docstrings."""

from __future__ import annotations

import ast
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "book" / "_ext"))
import api_modules  # noqa: E402


def test_public_modules_are_found_and_private_ones_left_out():
    names = api_modules.public_modules("fusioncenter")
    assert names[0] == "fusioncenter" and names == sorted(names)
    for name in ("fusioncenter.book", "fusioncenter.riccati", "fusioncenter.figures.registry",
                 "fusioncenter.figures.dey2009"):
        assert name in names
    assert not [n for n in names if any(p.startswith("_") for p in n.split("."))]
    assert "fusioncenter.figures.catalog" not in names  # deleted with the placeholders


def test_the_page_is_in_the_toc_and_uses_the_directive():
    assert "- file: book/api" in (ROOT / "_toc.yml").read_text()
    assert ".. fusioncenter-api:: fusioncenter" in (ROOT / "book/api.md").read_text()


@pytest.mark.parametrize(("line", "expected"), [
    ("P(|U_i| >= a_i)", r"P(\|U_i\| >= a_i)"),
    ("``|a| < 1`` and |a| < 1", r"``|a| < 1`` and \|a\| < 1"),
    (":func:`x|y` and |z|", r":func:`x|y` and \|z\|"),
    ("| a | b |", "| a | b |"),  # a table row
    ("+---+---+", "+---+---+"),
    (r"already \|x\|", r"already \|x\|"),
])
def test_bars_are_escaped_outside_literals(line, expected):
    assert api_modules._escape_bars(line) == expected


def test_literal_blocks_and_constants_are_left_alone():
    lines = ["Model::", "", "    |a| < 1", "", "after |b|"]
    api_modules.prepare_docstring(None, "module", "m", None, {}, lines)
    assert lines == ["Model::", "", "    |a| < 1", "", r"after \|b\|"]
    doc = ["Sample paths per curve: 2 000 (fast)."]
    api_modules.prepare_docstring(None, "data", "m.PATHS", None, {}, doc)
    napoleon_output = ["", ":type: Sample paths per curve", ""]
    api_modules.restore_prose(None, "data", "m.PATHS", None, {}, napoleon_output)
    assert napoleon_output == doc


@pytest.mark.parametrize("path", ["book.py", "profile.py", "censoring_compare.py",
                                  "figures/scorecard.py", "figures/background.py",
                                  "figures/common.py",
                                  *(f"figures/dey2009/{m}.py" for m in (
                                      "common", "scalar", "multisensor", "ordering", "vector",
                                      "distribution")),
                                  *(f"figures/leong2011/{m}.py" for m in ("common",)),
                                  "figures/zheng2014/common.py"])
def test_public_functions_have_numpydoc_sections(path):
    tree = ast.parse((ROOT / "src/fusioncenter" / path).read_text())
    missing = []
    for node in tree.body:
        if isinstance(node, ast.FunctionDef) and not node.name.startswith("_"):
            if "\nReturns\n-------\n" not in (ast.get_docstring(node) or ""):
                missing.append(node.name)
    assert not missing, f"{path}: no numpydoc Returns section: {missing}"
