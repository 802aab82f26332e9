"""The ``fusioncenter-api`` directive: the API reference of every public module of a package.

The API page (``book/api.md``) does not list the modules by hand. The directive walks the
package with :mod:`pkgutil`, keeps the modules whose dotted name has no component starting with
an underscore (``fusioncenter._kernels`` and ``fusioncenter.__main__`` are private), and writes
reStructuredText for Sphinx's own extensions to render: an ``autosummary`` table of the modules
(name and first line of the module docstring), then one section per module holding its
``automodule`` with ``:members:``. A module added, split or renamed in ``src/`` appears on the
page at the next build. It is used from MyST inside an ``{eval-rst}`` block, because autodoc
writes reStructuredText::

    .. fusioncenter-api:: fusioncenter

Each module is documented with ``:members:``, ``:undoc-members:`` (a public function without a
docstring is still part of the interface) and ``:ignore-module-all:`` (``__all__`` lists what
``from m import *`` exports, not everything the docstrings refer to). Imported names are not
repeated: autodoc skips functions and classes defined elsewhere, and data need a ``#:`` comment
or a docstring in the module itself to be documented at all.

Two adjustments make docstrings written for ``help()`` render as intended
(:func:`prepare_docstring`, run before napoleon):

* ``|x|`` is an absolute value in plain text but a substitution reference in reStructuredText:
  a bar outside literals and roles is escaped (lines that start with ``|`` or ``+``, the tables
  and line blocks of reStructuredText, are left alone);
* autosummary ends a module's one-line summary at the first period followed by a space; the
  abbreviations of :data:`ABBREVIATIONS` ("Figs. 1-4") do not end it;
* a constant's ``#:`` comment such as "Sample paths per curve: 2 000 (fast) ..." is prose, but
  napoleon reads the first ``words: words`` of an attribute's docstring as its type: the
  docstrings of constants and attributes are given back as they were before napoleon
  (:func:`restore_prose`).
"""

from __future__ import annotations

import importlib
import pkgutil
import re
import sys

from docutils import nodes
from docutils.statemachine import StringList
from sphinx.util.docutils import SphinxDirective
from sphinx.util.nodes import nested_parse_with_titles


def public_modules(package: str) -> list[str]:
    """Dotted names of ``package`` and of its public modules and subpackages, sorted."""
    pkg = importlib.import_module(package)
    names = [package]
    for info in pkgutil.walk_packages(pkg.__path__, prefix=package + "."):
        if not any(part.startswith("_") for part in info.name.split(".")):
            names.append(info.name)
    return sorted(names)


class FusioncenterApi(SphinxDirective):
    required_arguments = 1
    has_content = False

    def run(self) -> list[nodes.Node]:
        modules = public_modules(self.arguments[0])
        lines = [".. autosummary::", ""]
        lines += [f"   {name}" for name in modules]
        lines.append("")
        for name in modules:
            title = f"``{name}``"
            lines += [title, "-" * len(title), "", f".. automodule:: {name}", "   :members:",
                      "   :undoc-members:", "   :ignore-module-all:", ""]
        for name in modules:  # rebuild the page when any module changes
            module = importlib.import_module(name)
            if getattr(module, "__file__", None):
                self.env.note_dependency(module.__file__)
        container = nodes.section()
        container.document = self.state.document
        nested_parse_with_titles(self.state, StringList(lines, source="fusioncenter-api"),
                                 container)
        return container.children


#: ``literal``, ``:role:`target``` and ```interpreted``` spans, inside which a bar is text.
_PROTECTED = re.compile(r"``.+?``|(?::[\w:+.-]+:)?`[^`]+`_{0,2}")


#: A table row or rule, or a line of a line block: left as it is.
_TABLE_LINE = re.compile(r"^\s*(\|\s|\|$|\+[-=+])")


def _escape_bars(line: str) -> str:
    if _TABLE_LINE.match(line):
        return line
    out, pos = [], 0
    for m in _PROTECTED.finditer(line):
        out.append(re.sub(r"(?<!\\)\|", r"\\|", line[pos:m.start()]))
        out.append(m.group(0))
        pos = m.end()
    out.append(re.sub(r"(?<!\\)\|", r"\\|", line[pos:]))
    return "".join(out)


#: The docstrings of constants and attributes as they were before napoleon, by object name.
_PROSE: dict[str, list[str]] = {}


def prepare_docstring(app, what, name, obj, options, lines) -> None:
    """Escape plain-text bars; keep the docstring of a constant or attribute from napoleon."""
    in_literal = False
    for i, line in enumerate(lines):
        if in_literal and line.strip() and not line[:1].isspace():
            in_literal = False  # an unindented line ends a ``::`` literal block
        if not in_literal:
            lines[i] = _escape_bars(line)
        if line.rstrip().endswith("::"):
            in_literal = True
    if what in ("data", "attribute"):
        _PROSE[name] = list(lines)


def restore_prose(app, what, name, obj, options, lines) -> None:
    """Undo napoleon on a constant's or attribute's docstring: it is prose, not "type: text"."""
    if what in ("data", "attribute") and name in _PROSE:
        lines[:] = _PROSE.pop(name)


def _home(obj, namespace_module, target, domain) -> str | None:
    """The documented full name of ``obj`` (found as ``target`` in a module's namespace)."""
    if getattr(obj, "__module__", None) and getattr(obj, "__qualname__", None):
        return f"{obj.__module__}.{obj.__qualname__}"
    if isinstance(obj, type(sys)):
        return obj.__name__
    for full in domain.objects:
        mod, _, attr = full.rpartition(".")
        if attr == target.rpartition(".")[2] and mod in sys.modules and \
                getattr(sys.modules[mod], attr, None) is obj:
            return full
    return None


def _lookup(module: str, target: str):
    try:
        obj = importlib.import_module(module)
    except ImportError:
        return None
    for part in target.split("."):
        obj = getattr(obj, part, None)
        if obj is None:
            return None
    return obj


def resolve_imported(app, env, node, contnode):
    """Resolve a Python reference to where the object is documented.

    ``:data:`SCHEMES``` in a module that did ``from fusioncenter.censoring import SCHEMES`` (or
    uses a module alias) is looked up in that module's namespace, then in its parent packages';
    a dotted target such as ``fusioncenter.censoring.run`` (a package that re-exports a
    submodule's name) is imported as written. If the object found is documented elsewhere (a
    function or class by its ``__module__``, a constant by identity), the reference points
    there. Last, a bare name documented exactly once in the library (an autosummary line has no
    current module) resolves to that one object. Anything else stays unresolved, and the
    nitpicky build reports it.
    """
    if node.get("refdomain") != "py":
        return None
    target = node["reftarget"].lstrip("~.")
    domain = env.get_domain("py")
    candidates = []
    module = node.get("py:module") or ""
    while module:
        candidates.append((module, target))
        module = module.rpartition(".")[0]
    parts = target.split(".")
    candidates += [(".".join(parts[:i]), ".".join(parts[i:])) for i in range(len(parts) - 1, 0, -1)]
    for mod, rest in candidates:
        obj = _lookup(mod, rest)
        if obj is None:
            continue
        home = _home(obj, mod, rest, domain)
        if home is not None and home in domain.objects:
            return domain.resolve_xref(env, node["refdoc"], app.builder, node["reftype"], home,
                                       node, contnode)
    if "." not in target:
        found = [full for full in domain.objects
                 if full.startswith("fusioncenter.") and full.rpartition(".")[2] == target]
        if len(found) == 1:
            return domain.resolve_xref(env, node["refdoc"], app.builder, node["reftype"],
                                       found[0], node, contnode)
    return None


#: Abbreviations after which autosummary's one-line summary must not stop ("Part II: Figs.").
ABBREVIATIONS = (" Fig.", " Figs.", " Eq.", " Eqs.", " Sec.", " Prop.", " Props.", " e.g.",
                 " cf.", " resp.")


def setup(app):
    from sphinx.ext import autosummary

    app.add_directive("fusioncenter-api", FusioncenterApi)
    known = autosummary.WELL_KNOWN_ABBREVIATIONS
    autosummary.WELL_KNOWN_ABBREVIATIONS = (*known, *(a for a in ABBREVIATIONS if a not in known))
    app.setup_extension("sphinx.ext.autodoc")
    app.connect("autodoc-process-docstring", prepare_docstring, priority=400)  # before napoleon
    app.connect("autodoc-process-docstring", restore_prose, priority=600)  # after napoleon
    app.connect("missing-reference", resolve_imported)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1.0"}
