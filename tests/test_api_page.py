"""The API reference: an index page and one page per public module (which modules, where their
pages are, the toc entries), and how it prepares docstrings (bars, typeset formulas)."""

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


def test_the_index_is_in_the_toc_and_uses_the_directive():
    assert "- file: book/api\n" in (ROOT / "_toc.yml").read_text()
    assert ".. fusioncenter-api:: fusioncenter" in (ROOT / "book/api.md").read_text()


def test_every_public_module_has_its_page_in_the_toc():
    """The pages of book/api/ and the toc's sections of book/api are those tools/api_pages.py
    writes for the package as it is (a module added, renamed or removed needs a re-run)."""
    import subprocess

    res = subprocess.run([sys.executable, str(ROOT / "tools/api_pages.py"), "--check"],
                         capture_output=True, text=True)
    assert res.returncode == 0, res.stdout + res.stderr
    toc = (ROOT / "_toc.yml").read_text()
    for name in api_modules.public_modules("fusioncenter")[1:]:
        doc = api_modules.page_docname(name)
        page = ROOT / f"{doc}.md"
        assert page.read_text() == api_modules.page_text(name)
        assert f"- file: {doc}\n" in toc, name
    assert "book/api/censoring/vector_likelihood" in toc


def test_page_names_and_toc_nesting():
    assert api_modules.page_docname("fusioncenter") == "book/api"
    assert api_modules.page_docname("fusioncenter.riccati") == "book/api/riccati"
    assert api_modules.page_docname("fusioncenter.figures.zheng2014.common") == \
        "book/api/figures/zheng2014/common"
    mods = ["p", "p.a", "p.b", "p.b.c", "p.b.d", "p.e"]
    assert api_modules.children("p", mods) == ["p.a", "p.b", "p.e"]
    assert api_modules.children("p.b", mods) == ["p.b.c", "p.b.d"]
    sections = api_modules.toc_sections("fusioncenter", indent="")
    i = sections.index("  - file: book/api/event")
    assert sections[i + 1:i + 4] == ["    title: event", "    sections:",
                                     "      - file: book/api/event/kf"]
    text = api_modules.page_text("fusioncenter.event.kf")
    assert "\n# fusioncenter.event.kf\n" in text
    assert ".. fusioncenter-module:: fusioncenter.event.kf" in text


def test_dotted_names_break_at_their_dots():
    from docutils import nodes

    para = nodes.paragraph("", "", nodes.Text("fusioncenter.figures.zheng2014"))
    api_modules.break_at_dots(para)
    assert [type(n).__name__ for n in para.children] == ["Text", "wbr", "Text", "wbr", "Text"]
    assert para.astext() == "fusioncenter.figures.zheng2014"  # the text is unchanged


@pytest.mark.parametrize(("text", "tex"), [
    ("x_{k+1} = A x_k + w_k", "x_{k+1} = A x_k + w_k"),
    ("P - P C^T (C P C^T + R)^{-1} C P", "P - P C^T (C P C^T + R)^{-1} C P"),
    ("xi_i ~ U[0, 1]", r"\xi_i \sim U[0, 1]"),
    ("1 - E exp(-y^2 / (2 delta))", r"1 - E \exp(-y^2 / (2 \delta))"),
    ("xhat_{k|k-1}", r"\hat{x}_{k|k-1}"),
    ("x_hat_{k|k-1}", r"\hat{x}_{k|k-1}"),
    ("sigma_v2", r"\sigma_{v2}"),
    ("P_inf <= D", r"P_{\infty} \le D"),
    ("|U_i| >= a_i", r"|U_i| \ge a_i"),
    ("s = g P_pred g^T + r", r"s = g P_{\mathrm{pred}} g^T + r"),
    ("R^-1", "R^{-1}"),
    ("c^2 = 1e160", r"c^2 = 1 \times 10^{160}"),
    ("i in {1, ..., N}", r"i \in \{1, \dots , N\}"),
    ("(..., m, n)", r"(\dots , m, n)"),
    ("eta = chi2_{n_i}(l/N)", r"\eta = \chi^2_{n_i}(l/N)"),
    ("alpha_i = 1/sqrt(M)", r"\alpha_i = 1/\sqrt{M}"),
    ("g <= 2 u / (u + sqrt(u^2 + 4/pi))", r"g \le 2 u / (u + \sqrt{u^2 + 4/\pi})"),
])
def test_plain_text_formulas_are_read_as_tex(text, tex):
    assert api_modules.ascii_math(text) == tex


@pytest.mark.parametrize("text", [
    "steps", "True", "p_avg", "n_sensors", "np.inf", "exp_e1(0) = inf", "10**-0.3", "_",
    "scalar_update(p, c, r)", "(steps + 1, *broadcast_shape)", '"velocity"', "1e-9", "0",
    "fusioncenter.riccati", " (the ", "book/leong2011/allocation", "--json", "x = [position]",
])
def test_code_stays_code(text):
    assert api_modules.ascii_math(text) is None


def test_docstring_lines_get_math_roles():
    line = "Model: ``x_{k+1} = A x_k + w_k`` via :func:`step` with ``steps``; $\\sigma^2$ here."
    assert api_modules.typeset_math(line) == (
        "Model: :math:`x_{k+1} = A x_k + w_k` via :func:`step` with ``steps``; "
        ":math:`\\sigma^2` here.")
    assert api_modules.typeset_math(":func:`f` ``$x$``") == ":func:`f` ``$x$``"
    lines = ["Bound ``|a| < 1`` and |a|.", "", "    ``|a|`` in a literal::", "",
             "    ``|a|``"]
    api_modules.prepare_docstring(None, "function", "m.f", None, {}, lines)
    assert lines[0] == r"Bound :math:`|a| < 1` and \|a\|."
    assert lines[4] == "    ``|a|``"  # inside the literal block: as written


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

    try:
        tree = ast.parse(textwrap.dedent(inspect.getsource(func)))
    except (OSError, TypeError):  # no source to read (made at run time)
        return False
    return any((isinstance(n, ast.Return) and n.value is not None
                and not (isinstance(n.value, ast.Constant) and n.value.value is None))
               or isinstance(n, ast.Yield | ast.YieldFrom) for n in ast.walk(tree.body[0]))


def _arguments(obj) -> list[str]:
    import inspect

    try:
        return [p for p in inspect.signature(obj).parameters if p not in ("self", "cls")]
    except (TypeError, ValueError):
        return []


def _public_methods(cls):
    """``(name, function, docstring)`` of the public methods a class defines itself (in its own
    ``__dict__``; static and class methods unwrapped, properties left out). The docstring is
    ``inspect.getdoc``'s: an override without one inherits its base's."""
    import inspect

    for name, f in vars(cls).items():
        if name.startswith("_"):
            continue
        if isinstance(f, staticmethod | classmethod):
            f = f.__func__
        if isinstance(f, property) or not inspect.isfunction(f):
            continue
        yield name, f, inspect.getdoc(getattr(cls, name)) or ""


def _lacks(func, doc: str) -> list[str]:
    """The sections a function's or method's docstring lacks: ``Parameters`` if it takes
    arguments, ``Returns`` (or ``Yields``) if it returns something."""
    lacks = []
    if _arguments(func) and "Parameters\n----------" not in doc:
        lacks.append("Parameters")
    if _returns_value(func) and not ("Returns\n-------" in doc or "Yields\n------" in doc):
        lacks.append("Returns")
    return lacks


def numpydoc_gaps() -> list[str]:
    """Every public function, class and method of fusioncenter's public modules whose
    docstring lacks a numpydoc section it needs: a function or method its ``Parameters`` (if
    it takes arguments) and ``Returns``/``Yields`` (if it returns something); a class, every
    one (base classes and classes without arguments too), ``Parameters`` or ``Attributes``.
    Read from the runtime docstrings, so that sections appended by a
    :class:`fusioncenter._docstrings.Glossary` count."""
    import inspect

    missing = []
    for module, name, obj in _public_objects():
        doc = inspect.getdoc(obj) or ""
        if inspect.isfunction(obj):
            lacks = _lacks(obj, doc)
            if lacks:
                missing.append(f"{module}.{name} ({', '.join(lacks)})")
            continue
        if not ("Parameters\n----------" in doc or "Attributes\n----------" in doc):
            missing.append(f"{module}.{name} (class: Parameters or Attributes)")
        for method, func, method_doc in _public_methods(obj):
            lacks = _lacks(func, method_doc)
            if lacks:
                missing.append(f"{module}.{name}.{method} ({', '.join(lacks)})")
    return missing


class _DocBase:
    """A base class with no argument and no section (for the test below)."""

    def rate(self, x):
        """The rate.

        Parameters
        ----------
        x : float
            A value.

        Returns
        -------
        float
            The rate.
        """
        return x

    def bare(self, x):
        """No sections."""
        return x


class _DocChild(_DocBase):
    """A child.

    Attributes
    ----------
    n : int
        A count.
    """

    def rate(self, x):  # no docstring: _DocBase.rate's
        return 2 * x

    @property
    def size(self):
        return 1


def test_the_numpydoc_count_sees_classes_and_methods():
    """A base class without arguments and without sections is counted, so is a method without
    ``Parameters`` or ``Returns``; an override without a docstring inherits its base's (found by
    ``inspect.getdoc`` through the class's qualified name: module-level classes), and a property
    is not a method."""
    import inspect

    assert "Attributes\n----------" not in (inspect.getdoc(_DocBase) or "")
    assert {name: _lacks(f, doc) for name, f, doc in _public_methods(_DocBase)} == {
        "rate": [], "bare": ["Parameters", "Returns"]}
    assert {name: _lacks(f, doc) for name, f, doc in _public_methods(_DocChild)} == {
        "rate": []}


def test_public_functions_and_classes_have_numpydoc_sections():
    """Every public function, class (base classes too) and method has its numpydoc sections
    (:func:`numpydoc_gaps`)."""
    missing = numpydoc_gaps()
    assert not missing, f"{len(missing)} public names lack numpydoc sections: {missing}"
