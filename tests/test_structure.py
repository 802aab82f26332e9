"""The library's structure: no import circles among the fusioncenter modules, no private name
used across modules, modules of a few hundred lines (issue 15's measures, issue 49's limits).

The import-circle check also covers the scripts of ``tools/`` and the Sphinx extensions of
``book/_ext/`` (:data:`SCRIPT_DIRS`): they are not packages, and import each other by a plain
``import x`` / ``from x import y`` once their folder is on ``sys.path`` (a script's own folder
is; the others insert ``tools/`` or ``book/_ext/``). Each such name is resolved to the file of
that name in either folder (``x.py``, or the package ``x/``; relative imports inside a package
as usual), which is what Python finds with both folders on the path.

Module size (src/): no module over :data:`MAX_LINES` lines, and a module over
:data:`CONCEPT_LINES` lines is one concept and says so: the first paragraph of its docstring
(up to the first blank line) contains :data:`CONCEPT_MARK`, followed by what that concept is,
e.g. ``One concept: the Kalman filter's time and measurement updates.``
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "src"
PKG = SRC / "fusioncenter"
#: Folders of scripts and Sphinx extensions that import each other's modules by plain name.
SCRIPT_DIRS = (ROOT / "tools", ROOT / "book" / "_ext")
#: The largest module of src/ in lines.
MAX_LINES = 500
#: A module of src/ over this many lines must say it is one concept (:data:`CONCEPT_MARK`).
CONCEPT_LINES = 450
#: What the first paragraph of such a module's docstring contains.
CONCEPT_MARK = "One concept:"
#: What is still outside the rules (other modules' work, issue 15): it may only shrink.
KNOWN_CYCLES: list[list[str]] = []
KNOWN_PRIVATE: set[str] = set()
#: Modules over MAX_LINES (none since issue 15's splits). The set may only shrink.
KNOWN_LARGE: set[str] = set()


def _modules(root: Path, paths) -> dict[str, Path]:
    """Dotted module name (as imported with ``root`` on ``sys.path``) -> file, for ``paths``."""
    out = {}
    for path in sorted(paths):
        parts = list(path.relative_to(root).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


MODULES = _modules(SRC, PKG.rglob("*.py"))


def _script_modules(dirs=SCRIPT_DIRS) -> dict[str, Path]:
    """The modules of ``dirs`` (each folder as if on ``sys.path``), one namespace for all."""
    out: dict[str, Path] = {}
    for folder in dirs:
        found = _modules(folder, (p for p in folder.rglob("*.py")
                                  if "__pycache__" not in p.parts))
        clash = set(found) & set(out)
        assert not clash, f"the same module name in two folders of scripts: {sorted(clash)}"
        out.update(found)
    return out


def _resolve(module: str, name: str | None, modules: dict[str, Path] = MODULES) -> str:
    """The module an import statement binds: ``from module import name`` is the submodule
    ``module.name`` if there is one, else ``module`` itself."""
    if name is not None and f"{module}.{name}" in modules:
        return f"{module}.{name}"
    return module


def _module_of(node: ast.expr, aliases: dict[str, str],
               modules: dict[str, Path] = MODULES) -> str | None:
    """The module an expression names (``m`` or ``pkg.m``, through the names the module's
    imports bound), or ``None``."""
    parts = []
    while isinstance(node, ast.Attribute):
        parts.append(node.attr)
        node = node.value
    if not isinstance(node, ast.Name) or node.id not in aliases:
        return None
    dotted = ".".join([aliases[node.id], *reversed(parts)])
    return dotted if dotted in modules else None


def _imports(mod: str, path: Path, modules: dict[str, Path] = MODULES):
    """``(edges, private)``: the modules of ``modules`` (default: fusioncenter's) that ``mod``
    imports (anywhere in its body), and the underscore names it takes from other such modules
    (by ``from ... import`` or as an attribute of an imported module)."""
    tree = ast.parse(path.read_text())
    ours = {m.partition(".")[0] for m in modules}
    edges, private, aliases = set(), [], {}
    package = mod if path.name == "__init__.py" else mod.rpartition(".")[0]
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                base = ".".join(package.split(".")[: len(package.split(".")) - node.level + 1]
                                + ([node.module] if node.module else []))
            if base.partition(".")[0] not in ours:
                continue
            for a in node.names:
                target = _resolve(base, a.name, modules)
                edges.add(target)
                if target == base and a.name.startswith("_") and not a.name.startswith("__"):
                    private.append(f"{base}.{a.name}")
                if target != base:
                    aliases[a.asname or a.name] = target
        elif isinstance(node, ast.Import):
            for a in node.names:
                top = a.name.partition(".")[0]
                if top in ours:
                    edges.add(a.name)
                    if a.asname:
                        aliases[a.asname] = a.name
                    else:  # ``import fusioncenter.x`` binds ``fusioncenter``
                        aliases[top] = top
    for node in ast.walk(tree):
        if not (isinstance(node, ast.Attribute) and node.attr.startswith("_")
                and not node.attr.startswith("__")):
            continue
        owner = _module_of(node.value, aliases, modules)  # ``m._x``, also ``pkg.m._x``
        if owner is not None and f"{owner}.{node.attr}" not in modules:
            private.append(f"{owner}.{node.attr}")
    edges.discard(mod)
    return edges, private


def _graph(modules: dict[str, Path] = MODULES):
    graph, private = {}, {}
    for mod, path in modules.items():
        graph[mod], private[mod] = _imports(mod, path, modules)
    return graph, private


def find_cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components with more than one module (Tarjan)."""
    index, low, stack, on, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in graph:
                continue
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def test_the_cycle_finder_finds_a_cycle():
    assert find_cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert find_cycles({"a": {"b"}, "b": set()}) == []


def test_the_checks_see_violations(tmp_path):
    """The private-name check catches both forms (``from m import _x`` and ``m._x``, also through
    a package: ``pkg.m._x``; a private module's public names are allowed), and ``from package
    import submodule`` is an edge to the submodule."""
    path = tmp_path / "probe.py"
    path.write_text("from fusioncenter.figures.registry import _load\n"
                    "from fusioncenter.figures import registry\n"
                    "from fusioncenter.figures.zheng2014 import common\n"
                    "from fusioncenter import censoring\n"
                    "import fusioncenter.kalman\n"
                    "registry._order\n"
                    "censoring.probability._log_prob_inside\n"
                    "fusioncenter.kalman._scale\n"
                    "fusioncenter._compiled.censored_normal.log_prob_inside\n"
                    "common.x._y\n")
    edges, private = _imports("fusioncenter.probe", path)
    assert edges == {"fusioncenter.figures.registry", "fusioncenter.figures.zheng2014.common",
                     "fusioncenter.censoring", "fusioncenter.kalman"}
    assert sorted(private) == ["fusioncenter.censoring.probability._log_prob_inside",
                               "fusioncenter.figures.registry._load",
                               "fusioncenter.figures.registry._order",
                               "fusioncenter.kalman._scale"]


def test_no_import_circles():
    graph, _ = _graph()
    assert "fusioncenter.censoring.dispatch" in graph["fusioncenter.censoring"]
    assert "fusioncenter.censoring.nonlinear" in graph["fusioncenter.censoring.dispatch"]
    cycles = find_cycles(graph)
    assert [c for c in cycles if c not in KNOWN_CYCLES] == []


def test_no_import_circles_in_tools_and_the_book_extensions():
    """tools/ and book/_ext/ (issue 49: tools/browser_check.py <-> tools/pdf_book.py was one)."""
    graph, _ = _graph(_script_modules())
    assert "headless" in graph["pdf_book"] and "pdf_book" in graph["browser_check.__main__"]
    assert "browser_check.page" in graph["browser_check.driver"]  # a relative import
    assert "reader_notebook" in graph["student_path"]  # tools/ -> book/_ext/
    assert find_cycles(graph) == []


def test_the_script_check_finds_a_circle_on_files(tmp_path):
    """On files laid out as tools/ and book/_ext/ are: a circle through a plain ``import`` and a
    ``from ... import`` across the two folders, and one inside a package by relative imports."""
    tools, ext = tmp_path / "tools", tmp_path / "ext"
    (tools / "pkg").mkdir(parents=True)
    ext.mkdir()
    (tools / "a.py").write_text("import sys\nsys.path.insert(0, 'ext')\nimport b\n")
    (ext / "b.py").write_text("def f():\n    from a import g\n")
    (tools / "c.py").write_text("import json\nimport pkg.x\n")
    (tools / "pkg" / "__init__.py").write_text("from .x import h\n")
    (tools / "pkg" / "x.py").write_text("from . import y\n")
    (tools / "pkg" / "y.py").write_text("from pkg.x import h\n")
    modules = _script_modules((tools, ext))
    assert sorted(modules) == ["a", "b", "c", "pkg", "pkg.x", "pkg.y"]
    graph, _ = _graph(modules)
    assert graph["c"] == {"pkg.x"} and graph["pkg"] == {"pkg.x"}
    assert find_cycles(graph) == [["a", "b"], ["pkg.x", "pkg.y"]]


def test_no_private_names_across_modules():
    _, private = _graph()
    found = {mod: names for mod, names in private.items() if names and mod not in KNOWN_PRIVATE}
    assert found == {}


def test_modules_stay_a_few_hundred_lines():
    sizes = {mod: len(path.read_text().splitlines()) for mod, path in MODULES.items()}
    large = {mod for mod, n in sizes.items() if n > MAX_LINES}
    assert large <= KNOWN_LARGE, sorted((n, mod) for mod, n in sizes.items()
                                        if mod in large - KNOWN_LARGE)
    assert max(n for mod, n in sizes.items() if mod.startswith("fusioncenter.censoring")) \
        <= MAX_LINES


def says_one_concept(path: Path) -> bool:
    """The first paragraph of the module's docstring contains :data:`CONCEPT_MARK`."""
    doc = ast.get_docstring(ast.parse(path.read_text())) or ""
    return CONCEPT_MARK in doc.strip().split("\n\n")[0]


def test_the_concept_mark_is_read_from_the_first_paragraph(tmp_path):
    path = tmp_path / "m.py"
    path.write_text('"""The Kalman filter.\n\nOne concept: its two updates."""\n')
    assert not says_one_concept(path)
    path.write_text('"""The Kalman filter.\nOne concept: its two updates.\n\nMore."""\nx = 1\n')
    assert says_one_concept(path)


def test_a_module_over_450_lines_says_it_is_one_concept():
    """Over :data:`CONCEPT_LINES` lines a module is one concept and says so (issue 49)."""
    long = sorted((len(path.read_text().splitlines()), mod) for mod, path in MODULES.items()
                  if len(path.read_text().splitlines()) > CONCEPT_LINES)
    assert [(n, mod) for n, mod in long if not says_one_concept(MODULES[mod])] == []
