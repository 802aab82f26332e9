"""The ``fusioncenter-api`` directive: the API reference of every public module of a package.

The API page (``book/api.md``) does not list the modules by hand. The directive walks the
package with :mod:`pkgutil`, keeps the modules whose dotted name has no component starting with
an underscore (``fusioncenter._compiled`` and ``fusioncenter.__main__`` are private), and writes
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


#: The folder of the module pages, beside the index page ``book/api.md``.
PAGES = "book/api"


def page_docname(module: str) -> str:
    """The page of a module: ``fusioncenter.figures.zheng2014`` is ``book/api/figures/zheng2014``;
    the package itself is documented on the index page, ``book/api``."""
    rest = module.split(".")[1:]
    return "/".join([PAGES, *rest])


def children(module: str, modules: list[str]) -> list[str]:
    """The public modules directly inside ``module``, in ``modules``' (sorted) order."""
    depth = module.count(".") + 1
    return [m for m in modules if m.startswith(module + ".") and m.count(".") == depth]


def page_text(module: str) -> str:
    """The MyST source of a module's page (written by ``tools/api_pages.py``)."""
    return (f"% Written by tools/api_pages.py: one page per public module.\n"
            f"# {module}\n\n```{{eval-rst}}\n.. fusioncenter-module:: {module}\n```\n")


def toc_sections(package: str, indent: str = "        ") -> list[str]:
    """The ``sections:`` of ``book/api`` in ``_toc.yml``: every module's page, each package's
    modules as its own sections, titled by the last part of the name (the sidebar is narrow)."""
    modules = public_modules(package)
    lines: list[str] = []

    def walk(module: str, pad: str) -> None:
        kids = children(module, modules)
        if not kids:
            return
        lines.append(f"{pad}sections:")
        for kid in kids:
            lines.extend([f"{pad}  - file: {page_docname(kid)}",
                          f"{pad}    title: {kid.rpartition('.')[2]}"])
            walk(kid, pad + "    ")

    walk(package, indent)
    return lines


def _summary(module: str, document) -> str:
    """The first sentence of a module's docstring, prepared as the page renders it."""
    from sphinx.ext.autosummary import extract_summary

    doc = (importlib.import_module(module).__doc__ or "").strip().splitlines()
    prepare_docstring(None, "module", module, None, {}, doc)
    return extract_summary(doc, document) if doc else ""


class _ModuleTable(SphinxDirective):
    """A table of modules: the name links to the module's page, then the one-line summary."""

    def table(self, modules: list[str], package: str = "") -> list[str]:
        """The table's reST; names inside ``package`` (a package's own table) are shown
        relative to it (``checks`` on the page of ``fusioncenter.censoring``)."""
        lines = [".. list-table::", "   :class: fc-api-modules", "   :header-rows: 1", "",
                 "   * - Module", "     - Summary"]
        for name in modules:
            summary = _summary(name, self.state.document).replace("\n", " ")
            shown = name.removeprefix(package + ".") if package else name
            lines += [f"   * - :doc:`{shown} </{page_docname(name)}>`", f"     - {summary}"]
        return lines + [""]

    def parse(self, lines: list[str], modules: list[str]) -> list[nodes.Node]:
        for name in modules:  # rebuild the page when a module changes
            module = importlib.import_module(name)
            if getattr(module, "__file__", None):
                self.env.note_dependency(module.__file__)
        container = nodes.section()
        container.document = self.state.document
        nested_parse_with_titles(self.state, StringList(lines, source="fusioncenter-api"),
                                 container)
        return container.children


_AUTOMODULE = ["   :members:", "   :undoc-members:", "   :ignore-module-all:", ""]


class FusioncenterApi(_ModuleTable):
    """The index page: a table of every public module of the package (a link to its page and
    its one-line summary), then the package's own docstring and members."""

    required_arguments = 1
    has_content = False

    def run(self) -> list[nodes.Node]:
        package = self.arguments[0]
        modules = public_modules(package)
        missing = [m for m in modules[1:] if page_docname(m) not in self.env.found_docs]
        if missing:
            raise self.error(f"no page for {', '.join(missing)}: run tools/api_pages.py")
        title = f"The package ``{package}``"
        lines = self.table(modules[1:])
        lines += [title, "-" * len(title), "", f".. automodule:: {package}", *_AUTOMODULE]
        return self.parse(lines, modules)


class FusioncenterModule(_ModuleTable):
    """A module's page: for a package, a table of its modules; then the module's docstring and
    its functions, classes and constants."""

    required_arguments = 1
    has_content = False

    def run(self) -> list[nodes.Node]:
        module = self.arguments[0]
        kids = children(module, public_modules(module.split(".")[0]))
        lines = []
        if kids:
            lines += [".. rubric:: Modules of this package", "", *self.table(kids, module)]
        lines += [f".. automodule:: {module}", *_AUTOMODULE]
        return self.parse(lines, [module])


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


# ---------------------------------------------------------------------------- ASCII mathematics
GREEK = frozenset("alpha beta gamma delta epsilon varepsilon zeta eta theta vartheta iota kappa "
                  "lambda mu nu xi pi rho sigma tau upsilon phi varphi chi psi omega Gamma Delta "
                  "Theta Lambda Xi Pi Sigma Upsilon Phi Psi Omega".split())
#: Function names written as words in the docstrings, and their TeX.
FUNCTIONS = {"exp": r"\exp", "log": r"\log", "ln": r"\ln", "det": r"\det", "min": r"\min",
             "max": r"\max", "sup": r"\sup", "lim": r"\lim", "sin": r"\sin", "cos": r"\cos",
             "tr": r"\tr", "diag": r"\operatorname{diag}", "rank": r"\operatorname{rank}",
             "erf": r"\operatorname{erf}", "erfc": r"\operatorname{erfc}",
             "Var": r"\operatorname{Var}", "Cov": r"\operatorname{Cov}", "inf": r"\infty",
             "in": r"\in", "iff": r"\iff"}
_TOKEN = re.compile(r"(?P<num>\d+(?:\.\d+)?(?:e[-+]?\d+)?)|(?P<word>[A-Za-z]+)|(?P<dots>\.\.\.?)"
                    r"|(?P<op>!=|>=|<=|->|[-+*/=<>~^_()\[\]{}|,;:.!])|(?P<space>\s+)|(?P<other>.)")
_OPERATOR = re.compile(r"[=~<>^+/*]|!=")
#: ``sigma_v2_i``: one subscript ``{v2,i}``.
_TWO_SUBSCRIPTS = re.compile(r"(?<![\w])([A-Za-z]+)_([A-Za-z0-9]+)_([A-Za-z0-9]+)(?![\w{])")
#: ``x_hat``, ``sigma_bar``: written as ``xhat``, ``sigmabar`` before reading the formula.
_ACCENT = re.compile(r"\b([A-Za-z]|" + "|".join(sorted(GREEK))
                     + r")_(bar|hat|tilde)(?![A-Za-z0-9])")


def _word_tex(word: str) -> str | None:
    """The TeX of a word in a formula, or None if the word is not mathematics (a name)."""
    if len(word) == 1:
        return word
    if word in GREEK:
        return "\\" + word
    if word in FUNCTIONS:
        return FUNCTIONS[word]
    for accent in ("bar", "hat", "tilde"):
        base = word.removesuffix(accent)
        if base != word and (len(base) == 1 or base in GREEK):
            return rf"\{accent}{{{_word_tex(base)}}}"
    return None


def ascii_math(text: str) -> str | None:
    """The TeX of a formula written in plain text (``P_{k|k-1} = A P A^T + Q``), or None.

    A docstring written for ``help()`` puts its formulas in double backquotes, in a plain-text
    notation that is nearly TeX: ``x_{k+1} = A x_k + w_k``, ``R^{-1}``, ``xi_i ~ U[0, 1]``,
    ``exp(-y^2 / (2 delta))``, ``xhat_{k|k}``. Such a literal is typeset when every word in it is
    a single letter, a Greek letter's name, a known function (:data:`FUNCTIONS`) or a letter
    with ``bar``/``hat``/``tilde``; a word of a subscript (``p_avg``) is allowed when the literal
    has an operator. Anything else (a Python name, a call, a string, a path) stays code.
    """
    if not text or text != text.strip() or text.strip("()[]{}.,_ ") == "" or "**" in text \
            or text[-1] in "~=<>^_+*/-":
        return None
    if re.fullmatch(r"[-+]?\d+(\.\d+)?(e[-+]?\d+)?", text):  # a bare number stays code
        return None
    text = _ACCENT.sub(r"\1\2", text)  # x_hat: xhat
    text = re.sub(r"\bchi2(?![A-Za-z0-9])", "chi^2", text)  # the chi-square law
    text = _TWO_SUBSCRIPTS.sub(r"\1_{\2,\3}", text)  # sigma_v2_i: sigma_{v2,i}
    tokens = [(m.lastgroup, m.group()) for m in _TOKEN.finditer(text)]
    if any(kind == "other" for kind, _ in tokens):
        return None
    has_operator = bool(_OPERATOR.search(text))
    out: list[str] = []
    i = 0
    while i < len(tokens):
        kind, tok = tokens[i]
        prev = out[-1] if out else ""
        if prev == "_" and kind in ("word", "num") and i + 1 < len(tokens) \
                and tokens[i + 1][0] in ("word", "num"):  # sigma_v2: one subscript "v2"
            tokens[i + 1] = ("sub", tok + tokens[i + 1][1])
            i += 1
            continue
        if kind == "sub":
            out.append("{" + tok + "}")
            i += 1
            continue
        if kind == "word":
            if tok in FUNCTIONS and tok != "inf" and i + 1 < len(tokens) \
                    and tokens[i + 1][1] == "_":  # exp_e1: a Python name
                return None
            if tok == "sqrt" and i + 1 < len(tokens) and tokens[i + 1][1] == "(":
                depth = 0  # sqrt(u^2 + 4/pi): \sqrt{u^2 + 4/pi}, its parentheses dropped
                for j in range(i + 1, len(tokens)):
                    depth += {"(": 1, ")": -1}.get(tokens[j][1], 0)
                    if depth == 0:
                        tokens[j] = ("op", "}")
                        break
                else:
                    return None
                out.append(r"\sqrt{")
                i += 2
                continue
            tex = _word_tex(tok)
            if tex is None:
                if prev != "_" or not has_operator:
                    return None
                tex = rf"\mathrm{{{tok}}}"
            if prev in ("_", "^") and (tex.startswith("\\") or len(tok) > 1):
                tex = "{" + tex + "}"
            elif tex.startswith("\\") and i + 1 < len(tokens) and tokens[i + 1][0] == "word":
                tex += " "
            out.append(tex)
        elif kind == "num":
            mant, _, exp = tok.partition("e")
            tex = (rf"{mant} \times 10^{{{int(exp)}}}" if exp else tok)
            if prev in ("_", "^") and (len(tok) > 1 or exp):
                tex = "{" + tex + "}"
            out.append(tex)
        elif kind == "dots":
            out.append(r"\dots ")
        elif kind == "space":
            out.append(" ")
        else:
            if tok in (":",) or (tok == "." and not (i + 1 == len(tokens))):
                return None
            if tok == "^" and i + 2 < len(tokens) and tokens[i + 1] == ("op", "-") \
                    and tokens[i + 2][0] in ("num", "word"):
                out.append("^{-" + tokens[i + 2][1] + "}")
                i += 3
                continue
            tex = {"!=": r"\ne ", ">=": r"\ge ", "<=": r"\le ", "->": r"\to ", "~": r"\sim ",
                   "*": r"\cdot ", "!": None}.get(tok, tok)
            if tex is None:
                return None
            if tok == "{" and prev not in ("_", "^"):
                tex = r"\{"
                depth = 0  # its match is a set brace too
                for j in range(i + 1, len(tokens)):
                    if tokens[j][1] == "{":
                        depth += 1
                    elif tokens[j][1] == "}":
                        if depth == 0:
                            tokens[j] = ("op", r"\}")
                            break
                        depth -= 1
            out.append(tex)
        i += 1
    tex = "".join(out).strip()
    tex = re.sub(r" {2,}", " ", re.sub(r"_\s*\{", "_{", tex))
    return None if _double_script(tex) else tex


def _double_script(tex: str) -> bool:
    """Whether TeX has ``a_b_c`` or ``a^b^c`` (an error in MathJax: "Double subscripts")."""
    i, last = 0, ""
    while i < len(tex):
        ch = tex[i]
        if ch in "_^":
            if last == ch:
                return True
            i += 1
            if tex[i:i + 1] == "{":  # a braced group
                depth = 0
                while i < len(tex):
                    depth += {"{": 1, "}": -1}.get(tex[i], 0)
                    i += 1
                    if depth == 0:
                        break
            elif tex[i:i + 1] == "\\":
                m = re.match(r"\\[A-Za-z]+|\\.", tex[i:])
                i += len(m.group(0)) if m else 1
            else:
                i += 1
            last = ch
            continue
        last = "" if not ch.isspace() else last
        i += 1
    return False


_LITERAL = re.compile(r"(?<![`\w])``(?P<body>[^`]+?)``(?!`)")
_DOLLAR = re.compile(r"(?<![\\$\w`])\$(?=[^\s$])(?P<body>[^$\n`]+?)(?<=\S)\$(?![\w$])")


def typeset_math(line: str) -> str:
    """Turn the formulas of one docstring line into ``:math:`` roles.

    A literal ``x_{k+1} = A x_k`` that :func:`ascii_math` reads as a formula, and a ``$...$``
    span outside literals, become :math:`x_{k+1} = A x_k`.
    """
    def literal(m: re.Match) -> str:
        if line[max(0, m.start() - 1):m.start()] == ":":  # a role's ``target``: not ours
            return m.group(0)
        tex = ascii_math(m["body"])
        return m.group(0) if tex is None else f":math:`{tex}`"

    parts, pos = [], 0
    for m in _PROTECTED.finditer(line):
        parts.append(_DOLLAR.sub(lambda d: f":math:`{d['body']}`", line[pos:m.start()]))
        token = m.group(0)
        parts.append(_LITERAL.sub(literal, token) if token.startswith("``") else token)
        pos = m.end()
    parts.append(_DOLLAR.sub(lambda d: f":math:`{d['body']}`", line[pos:]))
    return "".join(parts)


#: The docstrings of constants and attributes as they were before napoleon, by object name.
_PROSE: dict[str, list[str]] = {}


def prepare_docstring(app, what, name, obj, options, lines) -> None:
    """Escape plain-text bars; keep the docstring of a constant or attribute from napoleon."""
    in_literal = False
    for i, line in enumerate(lines):
        if in_literal and line.strip() and not line[:1].isspace():
            in_literal = False  # an unindented line ends a ``::`` literal block
        if not in_literal:
            lines[i] = line if _TABLE_LINE.match(line) else _escape_bars(typeset_math(line))
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


def documented_name(env, target: str, module: str = "") -> str | None:
    """The full name under which the object a Python reference names is documented.

    ``SCHEMES`` seen from a module that did ``from fusioncenter.censoring import SCHEMES`` (or
    uses a module alias) is looked up in that module's namespace, then in its parent packages';
    a dotted target such as ``fusioncenter.censoring.run`` (a package that re-exports a
    submodule's name) is imported as written. If the object found is documented elsewhere (a
    function or class by its ``__module__``, a constant by identity), that is its name. Last, a
    bare name documented exactly once in the library (an autosummary line has no current
    module) is that one object. Anything else is None.
    """
    target = target.lstrip("~.")
    domain = env.get_domain("py")
    if target in domain.objects:
        return target
    candidates = []
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
            return home
    if "." not in target:
        found = [full for full in domain.objects
                 if full.startswith("fusioncenter.") and full.rpartition(".")[2] == target]
        if len(found) == 1:
            return found[0]
    return None


def resolve_imported(app, env, node, contnode):
    """Resolve a Python reference to where the object is documented (:func:`documented_name`),
    on whichever module page that is. Anything else stays unresolved, and the nitpicky build
    reports it."""
    if node.get("refdomain") != "py":
        return None
    full = documented_name(env, node["reftarget"], node.get("py:module") or "")
    if full is None:
        return None
    return env.get_domain("py").resolve_xref(env, node["refdoc"], app.builder, node["reftype"],
                                             full, node, contnode)


class wbr(nodes.Element):
    """A line-break opportunity (HTML ``<wbr>``): set after each dot of a dotted name, so that
    ``fusioncenter.figures.zheng2014_nonlinear`` breaks between its parts, never inside one."""


def _visit_wbr(self, node) -> None:
    self.body.append("<wbr>")
    raise nodes.SkipNode


def _skip(self, node) -> None:
    raise nodes.SkipNode


def break_at_dots(node: nodes.Node) -> None:
    """Put a :class:`wbr` after every dot of the text inside ``node``."""
    for text in list(node.findall(nodes.Text)):
        parts = re.split(r"(?<=\.)(?=\w)", str(text))
        if len(parts) > 1:
            new: list[nodes.Node] = []
            for part in parts:
                new += [nodes.Text(part), wbr()]
            text.parent.replace(text, new[:-1])


def dotted_names_break_at_dots(app, doctree, docname: str) -> None:
    """On the API pages: the page's title (a module's dotted name) and the module tables."""
    if docname != PAGES and not docname.startswith(PAGES + "/"):
        return
    if docname != PAGES:
        for title in doctree.findall(nodes.title):
            break_at_dots(title)
            break
    for table in doctree.findall(nodes.table):
        if "fc-api-modules" in table["classes"]:
            for row in table.findall(nodes.row):
                break_at_dots(row)


def rehome_nodes(app, doctree) -> None:
    """Make every node of a page belong to the page's own document.

    MyST parses an ``{eval-rst}`` block (every API page) into a document of its own, and the
    nodes autodoc writes there keep that document as theirs (``node._document``). Sphinx
    pickles a page's doctree without the build environment (it removes ``settings.env`` from
    the page's document only), but through those nodes the other document's settings, and so
    the whole environment (every page's table of contents, the bibliography), went into each
    of the 71 API pages' doctrees: about 600 kB each, 30 of the 36 MB of doctrees, loaded
    again for figure numbering and for writing every page."""
    for node in doctree.findall():
        other = vars(node).get("_document")
        if other is not None and other is not doctree:
            node._document = doctree


#: Abbreviations after which autosummary's one-line summary must not stop ("Part II: Figs.").
ABBREVIATIONS = (" Fig.", " Figs.", " Eq.", " Eqs.", " Sec.", " Prop.", " Props.", " e.g.",
                 " cf.", " resp.")


def setup(app):
    from sphinx.ext import autosummary

    app.add_directive("fusioncenter-api", FusioncenterApi)
    app.add_directive("fusioncenter-module", FusioncenterModule)
    known = autosummary.WELL_KNOWN_ABBREVIATIONS
    autosummary.WELL_KNOWN_ABBREVIATIONS = (*known, *(a for a in ABBREVIATIONS if a not in known))
    app.setup_extension("sphinx.ext.autodoc")
    app.connect("autodoc-process-docstring", prepare_docstring, priority=400)  # before napoleon
    app.connect("autodoc-process-docstring", restore_prose, priority=600)  # after napoleon
    app.connect("missing-reference", resolve_imported)
    app.add_node(wbr, html=(_visit_wbr, None), latex=(_skip, None), text=(_skip, None),
                 man=(_skip, None), texinfo=(_skip, None))
    app.connect("doctree-resolved", dotted_names_break_at_dots)
    app.connect("doctree-read", rehome_nodes)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1.0"}
