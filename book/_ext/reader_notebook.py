"""Turn an executed MyST notebook into one a reader can use in plain Jupyter or Colab.

The chapters are MyST markdown notebooks: their prose uses roles (``{glue:text}``, ``{cite:t}``,
``{eq}``, ``{ref}``, ``{doc}``, ``{prf:ref}``), labels ``(name)=``, directives (admonitions,
exercises, solutions, theorems) and ``$$ ... $$ (label)`` equations that only the book's
Sphinx build understands. :func:`reader_notebook` rewrites every markdown cell so that plain
Jupyter shows what the site shows: glued values, "Author (year)" citations with a references
cell at the end, links to the site's pages, bold-titled blockquotes, plain display math. It
also records the profile the outputs come from, in a note at the top and in the one marked
line of the install cell, so a re-run uses that profile unless the reader changes the line.
The install cell itself is written here (:func:`install_cell`): it installs the book's version of
the library from the package index, else from the wheel the site carries, and stops with one
message saying what failed and what to do when neither works.

This module knows nothing of Sphinx: the book's cross-reference targets reach it through a
:class:`Resolver` (``ipynb_download.py`` builds one from the Sphinx environment), so it can be
tested on small notebooks.
"""

from __future__ import annotations

import ast
import copy
import re
from collections.abc import Callable
from dataclasses import dataclass, field

GLUE_PREFIX = "application/papermill.record/"
PROFILE_LINE = re.compile(r'^os\.environ\.setdefault\("FUSIONCENTER_PROFILE", "[a-z]+"\).*$', re.M)
ROLE = re.compile(r"\{(?P<role>[a-z]+(?::[a-z]+)?)\}`(?P<body>[^`]*)`")
LABEL_LINE = re.compile(r"^\s*\((?P<name>[^()\s]+)\)=\s*$")
FENCE_OPEN = re.compile(
    r"^(?P<indent>\s*)(?P<fence>:{3,}|`{3,})\{(?P<name>[^}\s]+)\}\s*(?P<arg>.*)$")
OPTION = re.compile(r"^\s*:[A-Za-z_-]+:.*$")
EQ_LABEL = re.compile(r"\$\$\s*\((?P<label>[^()\s]+)\)\s*$")
EXPLICIT = re.compile(r"^(?P<text>.*?)\s*<(?P<target>[^<>]+)>$", re.S)
#: roles that a reader-ready notebook must not contain any more
MYST_LEFTOVER = re.compile(r"\{[a-z]+(?::[a-z]+)?\}`|^\s*\([^()\s]+\)=\s*$|^\s*(?::{3,}|`{3,})\{",
                           re.M)

TITLES = {"prf:theorem": "Theorem", "prf:lemma": "Lemma", "prf:proposition": "Proposition",
          "prf:corollary": "Corollary", "prf:algorithm": "Algorithm", "prf:definition":
          "Definition", "prf:remark": "Remark", "prf:example": "Example", "prf:proof": "Proof",
          "exercise": "Exercise", "note": "Note", "tip": "Tip", "warning": "Warning",
          "important": "Important", "caution": "Caution", "attention": "Attention",
          "hint": "Hint", "seealso": "See also", "danger": "Danger", "error": "Error"}


@dataclass
class Link:
    """Where a cross-reference points on the site and the text the site shows for it."""

    url: str
    text: str


@dataclass
class Resolver:
    """The book's cross-reference targets, as seen from one page.

    Each ``*`` callable returns a :class:`Link` or ``None`` when the target is unknown
    (``py``: a library name, linked to its entry on its module's page of the API reference).
    ``cite(keys, textual)`` returns the citation text; ``reference(key)`` the bibliography
    line of one entry.
    """

    doc: Callable[[str], Link | None]
    ref: Callable[[str], Link | None]
    eq: Callable[[str], Link | None]
    prf: Callable[[str], Link | None]
    cite: Callable[[list[str], bool], str]
    reference: Callable[[str], str]
    number: Callable[[str], str] = lambda label: ""
    #: a library name (``fusioncenter.event.posterior``): its entry on its module's API page
    py: Callable[[str], Link | None] = lambda target: None
    cited: list[str] = field(default_factory=list)


#: Where :func:`glue_values` keeps an explorable figure's caption facts (not a MIME type).
FACTS_KEY = "fusioncenter/facts"
#: A caption's number that follows an explorable figure's slider (book/_ext/explorable.py).
FACT = re.compile(r"\[\[([a-z0-9_]+)\]\]")


def glue_values(nb: dict) -> dict[str, dict]:
    """The glued outputs of an executed notebook: name -> MIME bundle (prefix removed)."""
    out: dict[str, dict] = {}
    for cell in nb.get("cells", []):
        for o in cell.get("outputs", []) if cell.get("cell_type") == "code" else []:
            scrap = (o.get("metadata") or {}).get("scrapbook")
            if not scrap or "name" not in scrap:
                continue
            prefix = scrap.get("mime_prefix", "")
            out[scrap["name"]] = {k[len(prefix):] if prefix and k.startswith(prefix) else k: v
                                  for k, v in (o.get("data") or {}).items()}
            meta = (o.get("metadata") or {}).get("fusioncenter") or {}
            if meta.get("frames"):  # an explorable figure: its caption's numbers at the start
                out[scrap["name"]][FACTS_KEY] = meta["frames"][int(meta["start"])]["facts"]
    return out


def format_plain_text(text: str, fmt_spec: str) -> str:
    """MyST-NB's formatting of a glued ``text/plain`` value with a format spec."""
    try:
        value = ast.literal_eval(text)
    except (SyntaxError, ValueError):
        value = text
    if fmt_spec == "":
        return str(value)
    kind = fmt_spec[-1]
    if kind == "s":
        value = str(value)
    elif kind in "bcdoxX":
        value = int(value)
    elif kind in "eEfFgGn%":
        value = float(value)
    return format(value, fmt_spec)


def _split_explicit(body: str) -> tuple[str | None, str]:
    m = EXPLICIT.match(body.strip())
    return (m["text"], m["target"].strip()) if m else (None, body.strip())


class _Rewriter:
    def __init__(self, resolver: Resolver, glue: dict[str, dict]):
        self.r = resolver
        self.glue = glue
        self.problems: list[str] = []

    def _link(self, role: str, body: str) -> str:
        text, target = _split_explicit(body)
        lookup = {"doc": self.r.doc, "ref": self.r.ref, "numref": self.r.ref, "eq": self.r.eq,
                  "prf:ref": self.r.prf}[role]
        link = lookup(target)
        if link is None:
            self.problems.append(f"unresolved {{{role}}}`{body}`")
            return text or target
        return f"[{(text or link.text).strip()}]({link.url})"

    def role(self, m: re.Match) -> str:
        role, body = m["role"], m["body"]
        if role in ("glue", "glue:text", "glue:any", "glue:md"):
            key, _, fmt = body.strip().rpartition(":") if role == "glue:text" else (body, "", "")
            if role == "glue:text" and not key:
                key, fmt = fmt, ""
            bundle = self.glue.get(key.strip())
            if bundle is None or "text/plain" not in bundle:
                self.problems.append(f"no glued value {key!r}")
                return body
            return format_plain_text(bundle["text/plain"], fmt or "")
        if role.startswith("cite") or role == "cite":
            keys = [k.strip() for k in body.split(",") if k.strip()]
            for k in keys:
                if k not in self.r.cited:
                    self.r.cited.append(k)
            return self.r.cite(keys, role in ("cite:t", "cite:ts", "cite:ct"))
        if role in ("doc", "ref", "numref", "eq", "prf:ref"):
            return self._link(role, body)
        if role in ("math",):
            return f"${body}$"
        if role.startswith("py:"):  # a library name: code, linked to its API reference entry
            text, target = _split_explicit(body)
            target = target.lstrip("~.")
            shown = text or (target.rpartition(".")[2] if body.strip().startswith("~") else target)
            link = self.r.py(target)
            if link is None:  # not documented: the API index, or plain code
                page = self.r.doc("/book/api")
                return f"[`{shown}`]({page.url})" if page else f"`{shown}`"
            return f"[`{shown}`]({link.url})"
        if role in ("sub", "sup", "abbr", "term", "code", "kbd", "file", "samp"):
            return body
        self.problems.append(f"unknown role {{{role}}}")
        return body

    def inline(self, text: str) -> str:
        return ROLE.sub(self.role, text)

    def block(self, lines: list[str]) -> list[str]:
        out: list[str] = []
        i = 0
        while i < len(lines):
            line = lines[i]
            if LABEL_LINE.match(line):
                i += 1
                continue
            m = FENCE_OPEN.match(line)
            if m and m["name"] not in ("code-cell",):
                fence = m["fence"]
                j = i + 1
                opts: dict[str, str] = {}
                while j < len(lines) and OPTION.match(lines[j]):
                    key, _, val = lines[j].strip()[1:].partition(":")
                    opts[key] = val.strip()
                    j += 1
                k = j
                while k < len(lines) and lines[k].strip() != fence:
                    k += 1
                body = lines[j:k]
                out += self.directive(m["name"], m["arg"].strip(), opts, body)
                i = k + 1
                continue
            line = EQ_LABEL.sub("$$", line)
            # a role may run over a line break ({doc}`text\n<target>`): take the next lines
            # of the paragraph until its backquotes close
            while line.count("`") % 2 and i + 1 < len(lines) and lines[i + 1].strip() \
                    and not FENCE_OPEN.match(lines[i + 1]):
                i += 1
                line = f"{line}\n{lines[i]}"
            out.extend(self.inline(line).split("\n"))
            i += 1
        return out

    def directive(self, name: str, arg: str, opts: dict, body: list[str]) -> list[str]:
        inner = self.block(body)
        while inner and not inner[0].strip():
            inner.pop(0)
        while inner and not inner[-1].strip():
            inner.pop()
        if name in ("math",):
            return ["$$", *inner, "$$"]
        if name == "solution-start":
            link = self.r.ref(arg)
            what = f"[{link.text.strip()}]({link.url})" if link else "the exercise"
            return [f"**Solution** to {what}:", ""]
        if name == "solution-end":
            return ["", "*(end of the solution)*"]
        if name in ("bibliography",):
            return []
        if name == "book-figure":  # the figure is the output of the cell above: its caption
            number = self.r.number(arg)
            head, *rest = inner or [""]
            quoted = [">", *(f"> {x}" if x.strip() else ">" for x in rest)] if rest else []
            return [f"> **Figure {number}.** {head}".replace("  ", " ").rstrip(), *quoted]
        if name == "explorable-figure":  # the small multiples are the output above
            number = self.r.number(f"explore-{arg}")
            facts = (self.glue.get(f"explore-{arg}") or {}).get(FACTS_KEY, {})
            head, *rest = [FACT.sub(lambda m: facts.get(m[1], "…"), x) for x in inner or [""]]
            quoted = [">", *(f"> {x}" if x.strip() else ">" for x in rest)] if rest else []
            return [f"> **Figure {number}.** {head}".replace("  ", " ").rstrip(), *quoted]
        if name == "admonition":
            title = self.inline(arg) or "Note"
        else:
            kind = TITLES.get(name, name.split(":")[-1].title())
            number = "" if "nonumber" in opts else self.r.number(opts.get("label", ""))
            title = f"{kind} {number}".strip()
            if arg:
                title += f" ({self.inline(arg)})"
            if name == "prf:proof":
                title = "Proof"
        if name == "solution":
            title = "Solution"
        quoted = [f"> {x}" if x.strip() else ">" for x in inner]
        return [f"> **{title}**", ">", *quoted] if quoted else [f"> **{title}**"]


#: The downloaded notebook's first code cell (:func:`install_cell` fills in the three values).
#: It runs in any Jupyter kernel (Colab's IPython 7 too) and in plain Python.
INSTALL_CELL = r'''
# Lets this chapter run outside the book's repository (downloaded, Colab,
# Binder): installs the book's version of its library when it is missing,
# from the package index, else from the wheel on the book's site.
# Offline: set PIP_NO_INDEX=1 and PIP_FIND_LINKS=<a folder with the wheels>.
import importlib
import importlib.metadata
import os
import subprocess
import sys

@PROFILE@
BOOK_VERSION = "@VERSION@"
# the book's site (its wheel: <site>_wheels/); FUSIONCENTER_BOOK_SITE: a mirror
BOOK_SITE = os.environ.get("FUSIONCENTER_BOOK_SITE", "@SITE@")


class InstallFailed(Exception):
    """Shown by Jupyter as its message alone, not as a traceback."""

    def _render_traceback_(self):
        return [f"InstallFailed: {self}"]


def _install_fusioncenter():
    try:
        if importlib.metadata.version("fusioncenter") == BOOK_VERSION:
            return
    except importlib.metadata.PackageNotFoundError:
        pass
    wheel = (f"{BOOK_SITE.rstrip('/')}/_wheels/"
             f"fusioncenter-{BOOK_VERSION}-py3-none-any.whl")
    tries = {"the package index": f"fusioncenter[notebook]=={BOOK_VERSION}",
             "the book's site": f"fusioncenter[notebook] @ {wheel}"}
    said = []
    for where, want in tries.items():
        run = subprocess.run(
            [sys.executable, "-m", "pip", "install", "--quiet", "--no-color",
             "--disable-pip-version-check", want],
            capture_output=True, text=True)
        if run.returncode == 0:
            importlib.invalidate_caches()
            return
        errors = [x for x in run.stderr.splitlines() if "ERROR" in x]
        said.append(f"  from {where}: {(errors or ['pip failed'])[-1]}")
    raise InstallFailed(
        f"the library fusioncenter {BOOK_VERSION} could not be installed;"
        " pip said\n" + "\n".join(said) + "\nWhat to do: connect to the"
        " internet and run this cell again. Offline: download the wheel\n  "
        + wheel + "\ninto a folder with the wheels of its dependencies,"
        " start Jupyter with PIP_NO_INDEX=1 PIP_FIND_LINKS=<that folder>"
        " and run this cell again.")


_install_fusioncenter()
'''.lstrip("\n")

PROFILE_SET = ('os.environ["FUSIONCENTER_PROFILE"] = "{profile}"  '
               '# <- THE PROFILE of the outputs below; "fast" runs in seconds, "paper" at the '
               "papers' scale")
PROFILE_DEFAULT = 'os.environ.setdefault("FUSIONCENTER_PROFILE", "fast")  # the profile'


def install_cell(version: str, site: str, profile: str | None) -> str:
    """The source of a downloaded notebook's install cell.

    ``version`` is the library's version the outputs come from, ``site`` the book's public
    address (``html.baseurl``: the wheel is ``<site>_wheels/fusioncenter-<version>-py3-none-any
    .whl``), ``profile`` the profile the outputs were computed in (``None``: unknown, the cell
    defaults to ``"fast"``).
    """
    if not re.fullmatch(r"[0-9A-Za-z.+!-]+", version or ""):
        raise ValueError(f"version: a package version such as 0.1.0, not {version!r}")
    if not re.fullmatch(r"https?://[^\s\"'\\]+/", site or ""):
        raise ValueError(f"site: an http(s) address ending in /, not {site!r}")
    line = PROFILE_SET.format(profile=profile) if profile else PROFILE_DEFAULT
    return (INSTALL_CELL.replace("@PROFILE@", line).replace("@VERSION@", version)
            .replace("@SITE@", site))


def _profile_of(nb: dict) -> str | None:
    for cell in nb.get("cells", []):
        for o in cell.get("outputs", []) if cell.get("cell_type") == "code" else []:
            text = o.get("text", "")
            text = "".join(text) if isinstance(text, list) else text
            m = re.search(r"^profile: (fast|paper)\b", text, re.M)
            if m:
                return m[1]
    return None


def _source(cell: dict) -> str:
    src = cell.get("source", "")
    return "".join(src) if isinstance(src, list) else src


def expand_macros(text: str, macros: dict[str, str]) -> str:
    """Replace the book's MathJax macros (``\\E``, ``\\R``, ...) by their definitions."""
    for name, value in macros.items():
        text = re.sub(r"\\" + re.escape(name) + r"(?![A-Za-z])", lambda _m, v=value: v, text)
    return text


def reader_notebook(nb: dict, resolver: Resolver, *, page_url: str, book_title: str,
                    version: str, macros: dict[str, str] | None = None,
                    profile: str | None = None,
                    glue: dict[str, dict] | None = None,
                    site: str | None = None) -> tuple[dict, list[str]]:
    """Return the reader-ready copy of the executed notebook ``nb`` and a list of problems.

    The profile the outputs were computed in is read from the chapter's ``profile: ...`` output
    line (printed by ``fusioncenter.book.setup``); ``profile`` is the fallback when there is
    none. ``glue`` adds glued values to those found in the outputs (MyST-NB moves the hidden
    ones from its executed notebook to ``<page>.glue.json``). ``site``, the book's public
    address, replaces the chapter's install cell by :func:`install_cell` (which falls back to
    the site's wheel); without it only the cell's profile line is set. The problems name every
    role left unresolved and any MyST markup left over.
    """
    nb = copy.deepcopy(nb)
    macros = macros or {}
    extra = {k: v.get("data", v) for k, v in (glue or {}).items()}  # outputs or MIME bundles
    rw = _Rewriter(resolver, {**glue_values(nb), **extra})
    profile = _profile_of(nb) or profile
    for cell in nb["cells"]:
        if cell.get("cell_type") == "markdown":
            text = "\n".join(rw.block(_source(cell).split("\n")))
            text = re.sub(r"\n{3,}", "\n\n", expand_macros(text, macros)).strip("\n")
            cell["source"] = text
        elif cell.get("cell_type") == "code":
            for o in cell.get("outputs", []):
                data = o.get("data") or {}
                for mime in ("text/latex", "text/markdown"):
                    if mime in data:
                        val = data[mime]
                        val = "".join(val) if isinstance(val, list) else val
                        data[mime] = expand_macros(val, macros)
    installer = None
    for cell in nb["cells"]:
        if cell.get("cell_type") == "code" and PROFILE_LINE.search(_source(cell)):
            installer = cell
            break
    if site and installer is not None:
        installer["source"] = install_cell(version, site, profile)
    elif profile and installer is not None:
        line = PROFILE_SET.format(profile=profile)
        installer["source"] = PROFILE_LINE.sub(lambda _m: line, _source(installer), count=1)
    elif installer is None:
        rw.problems.append("no install cell with the FUSIONCENTER_PROFILE line")
    note = (f"*This notebook is a chapter of [{book_title}]({page_url}) (`fusioncenter` "
            f"{version}).* Its outputs were computed in the **`{profile or 'unknown'}` profile**; "
            "the first code cell installs the book's version of the library when it is missing "
            "and selects that profile in one marked line (`FUSIONCENTER_PROFILE`): change it to "
            '`"fast"` for a run of seconds, or to `"paper"` for the papers\' own trial counts.')
    cells = [{"cell_type": "markdown", "id": "reader-note", "metadata": {}, "source": note}]
    cells += nb["cells"]
    if resolver.cited:
        refs = "\n".join(f"- {resolver.reference(k)}" for k in resolver.cited)
        cells.append({"cell_type": "markdown", "id": "reader-references", "metadata": {},
                      "source": "## Works cited in this chapter\n\n" + refs})
    nb["cells"] = cells
    for cell in nb["cells"]:
        if cell["cell_type"] == "markdown":
            for m in MYST_LEFTOVER.finditer(_source(cell)):
                rw.problems.append(f"MyST left in a markdown cell: {m[0]!r}")
    return nb, rw.problems
