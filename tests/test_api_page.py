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


def _public_objects():
    """``(module, name, object)`` for every public function and class defined in a public
    module of fusioncenter (by its ``__module__``, so re-exports are seen once)."""
    import importlib
    import inspect
    import pkgutil

    import fusioncenter

    names = [fusioncenter.__name__] + [m.name for m in pkgutil.walk_packages(
        fusioncenter.__path__, "fusioncenter.")]
    for name in sorted(names):
        if any(part.startswith("_") for part in name.split(".")[1:]):
            continue
        mod = importlib.import_module(name)
        for attr, obj in sorted(vars(mod).items()):
            if (not attr.startswith("_") and getattr(obj, "__module__", None) == name
                    and (inspect.isfunction(obj) or inspect.isclass(obj))
                    and not (inspect.isclass(obj) and issubclass(obj, BaseException))):
                yield name, attr, obj


def _returns_value(func) -> bool:
    import inspect
    import textwrap

    tree = ast.parse(textwrap.dedent(inspect.getsource(func)))
    return any((isinstance(n, ast.Return) and n.value is not None
                and not (isinstance(n.value, ast.Constant) and n.value.value is None))
               or isinstance(n, ast.Yield | ast.YieldFrom) for n in ast.walk(tree.body[0]))


def _arguments(obj) -> list[str]:
    import inspect

    try:
        return [p for p in inspect.signature(obj).parameters if p not in ("self", "cls")]
    except (TypeError, ValueError):
        return []


def test_public_functions_and_classes_have_numpydoc_sections():
    """Every public function documents its arguments (``Parameters``) and what it returns
    (``Returns`` or ``Yields``, unless it returns nothing); every public class taking arguments
    has ``Parameters`` or ``Attributes``. Read from the runtime docstrings, so that sections
    appended by a :class:`fusioncenter._docstrings.Glossary` count."""
    import inspect

    missing = []
    for module, name, obj in _public_objects():
        doc = inspect.getdoc(obj) or ""
        lacks = []
        if _arguments(obj) and not ("Parameters\n----------" in doc or (
                inspect.isclass(obj) and "Attributes\n----------" in doc)):
            lacks.append("Parameters")
        if inspect.isfunction(obj) and _returns_value(obj) and not (
                "Returns\n-------" in doc or "Yields\n------" in doc):
            lacks.append("Returns")
        if lacks:
            missing.append(f"{module}.{name} ({', '.join(lacks)})")
    assert not missing, f"{len(missing)} public names lack numpydoc sections: {missing}"
