"""Offer every executed chapter as a reader-ready ``.ipynb``, and point Colab at it.

sphinx-book-theme adds the ``.ipynb`` entry of the download menu only when a launch button is
configured, and then serves the notebook MyST-NB executed, whose markdown is MyST that plain
Jupyter cannot read. This extension

* always offers the download (``context["ipynb_source"]``, before the theme's header buttons,
  priority 500), and
* after the theme (priority 502) writes ``_sources/<page>.ipynb`` as the reader-ready copy of
  ``jupyter_execute/<page>.ipynb`` (``reader_notebook.reader_notebook``: glue values, citations,
  links to the site, readable admonitions, the profile it was executed in), and
* adds the whole book's PDF (``book.pdf`` at the site's root) to every download menu, and
* rewrites the theme's Colab link, which points at the ``.md`` source (Colab opens ``.ipynb``
  only), to the same notebook on the branch the GitHub workflow publishes them to
  (``fusioncenter_notebooks_branch``, default ``notebooks``).

Links in the notebook point to the site at ``html_baseurl`` (``html.baseurl`` in _config.yml),
and its install cell (``reader_notebook.install_cell``) falls back to the wheel the site carries
there (``_wheels/``) when the package index does not have the library.
With no ``repository.url`` in _config.yml, the launch buttons are switched off.
"""

from __future__ import annotations

import json
import os
import posixpath
import re
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from reader_notebook import Link, Resolver, reader_notebook  # noqa: E402
from sphinx.util import logging  # noqa: E402

LOG = logging.getLogger(__name__)
NOTEBOOKS_BRANCH = "fusioncenter_notebooks_branch"


def _is_md_notebook(context) -> bool:
    return str(context.get("sourcename", "")).endswith((".md", ".md.txt"))


def _executed(app, pagename) -> Path:
    return Path(app.outdir).parent / "jupyter_execute" / f"{pagename}.ipynb"


def _offer(app, pagename, templatename, context, doctree):
    if doctree is None or not _is_md_notebook(context) or not _executed(app, pagename).exists():
        return
    context["ipynb_source"] = f"{pagename}.ipynb"


def _site(app, pagename: str) -> str:
    base = (app.config.html_baseurl or "").strip()
    if base:
        return base.rstrip("/") + "/"
    # no site URL configured: links relative to the page (they work next to the built site)
    depth = pagename.count("/")
    return "../" * depth


def _public_site(app) -> str | None:
    """The book's public address (``html.baseurl`` in _config.yml), where the install cell of a
    downloaded notebook finds the library's wheel (``_wheels/``, written by tools/build_book.py);
    ``None`` when none is configured (the chapter's own install cell is kept then)."""
    base = (app.config.html_baseurl or "").strip()
    return base.rstrip("/") + "/" if base.startswith(("https://", "http://")) else None


def _bibliography(app):
    from pybtex.database import parse_file

    entries = {}
    for rel in app.config.bibtex_bibfiles:
        entries.update(parse_file(str(Path(app.srcdir) / rel)).entries)
    return entries


def _clean(text: str) -> str:
    return re.sub(r"[{}]", "", text).replace("\\&", "&").replace("--", "–").strip()


def _surnames(entry) -> list[str]:
    persons = entry.persons.get("author") or entry.persons.get("editor") or []
    return [_clean(" ".join(p.prelast_names + p.last_names)) for p in persons]


def _cite(entries, keys: list[str], textual: bool) -> str:
    parts = []
    for k in keys:
        e = entries.get(k)
        if e is None:
            parts.append(k)
            continue
        names = _surnames(e)
        who = (names[0] if len(names) == 1 else " and ".join(names) if len(names) == 2
               else f"{names[0]} et al." if names else k)
        year = _clean(e.fields.get("year", "n.d."))
        parts.append(f"{who} ({year})" if textual else f"{who}, {year}")
    return ", ".join(parts) if textual else "(" + "; ".join(parts) + ")"


def _reference(entries, key: str) -> str:
    e = entries.get(key)
    if e is None:
        return key
    persons = e.persons.get("author") or []
    names = [_clean(" ".join(p.first_names + p.middle_names + p.prelast_names + p.last_names))
             for p in persons]
    who = ", ".join(names) if names else key
    f = {k.lower(): _clean(v) for k, v in e.fields.items()}
    out = f"{who} ({f.get('year', 'n.d.')}). {f.get('title', '')}."
    venue = (f.get("journal") or f.get("booktitle") or f.get("howpublished") or f.get("note")
             or f.get("institution") or f.get("publisher") or f.get("school"))
    if venue:
        out += f" *{venue}*"
        if f.get("volume"):
            out += f", {f['volume']}"
            if f.get("number"):
                out += f"({f['number']})"
        if f.get("pages"):
            out += f", {f['pages']}"
        out += "."
    if f.get("doi"):
        out += f" doi:{f['doi']}"
    return out


def _resolver(app, pagename: str, doctree, entries) -> Resolver:
    env = app.env
    site = _site(app, pagename)
    std = env.get_domain("std")
    math = env.domaindata.get("math", {}).get("objects", {})
    proofs = getattr(env, "proof_list", {})
    shown: dict[str, str] = {}
    from docutils import nodes

    for ref in doctree.findall(nodes.reference):
        uri = ref.get("refuri") or ""
        key = ref.get("refid") or (uri.split("#", 1)[1] if "#" in uri else uri)
        shown.setdefault(key, ref.astext())

    def url(doc: str, anchor: str = "") -> str:
        return f"{site}{doc}.html" + (f"#{anchor}" if anchor else "")

    def doc(target: str):
        target = re.sub(r"\.(md|ipynb)$", "", target)
        name = (target.lstrip("/") if target.startswith("/")
                else posixpath.normpath(posixpath.join(posixpath.dirname(pagename), target)))
        if name not in env.titles:
            return None
        return Link(url(name), env.titles[name].astext())

    def ref(label: str):
        if label in std.labels:
            d, anchor, title = std.labels[label]
        elif label in std.anonlabels:
            d, anchor = std.anonlabels[label]
            title = None
        else:
            return None
        return Link(url(d, anchor), shown.get(anchor) or title or label)

    def eq(label: str):
        if label not in math:
            return None
        d, number = math[label][0], math[label][1]
        # the id MyST gives the equation's node (docutils' make_id: lower case, so
        # `eq-...-Zbar` is `#equation-eq-...-zbar` on the page)
        anchor = nodes.make_id(f"equation-{label}")
        nums = env.toc_fignumbers.get(d, {}).get("displaymath", {}).get(anchor)
        text = shown.get(anchor) or (f"({'.'.join(map(str, nums))})" if nums else f"({number})")
        return Link(url(d, anchor), text)

    def prf(label: str):
        if label not in proofs:
            return None
        d = proofs[label]["docname"]
        return Link(url(d, label), shown.get(label) or proofs[label]["realtype"].title())

    def number(label: str) -> str:
        for figtype in env.toc_fignumbers.get(pagename, {}).values():
            if label in figtype:
                return ".".join(map(str, figtype[label]))
        return ""

    def py(target: str):
        from api_modules import documented_name

        full = documented_name(env, target)
        if full is None:
            return None
        entry = env.get_domain("py").objects[full]
        return Link(url(entry.docname, entry.node_id), full)

    return Resolver(doc=doc, ref=ref, eq=eq, prf=prf, number=number, py=py,
                    cite=lambda keys, textual: _cite(entries, keys, textual),
                    reference=lambda key: _reference(entries, key))


def _macros(app) -> dict[str, str]:
    cfg = app.config.mathjax3_config or {}
    return dict((cfg.get("tex") or {}).get("macros") or {})


def _with_outputs(app, nb: dict) -> dict:
    """The executed notebook with its outputs.

    When MyST-NB takes a notebook from its execution cache, it writes the notebook to
    ``jupyter_execute`` without the outputs (it merges them only into the document it
    renders); take them from the same cache then.
    """
    if any(c.get("outputs") for c in nb["cells"] if c["cell_type"] == "code"):
        return nb
    import nbformat
    from jupyter_cache import get_cache

    path = (getattr(app.config, "nb_execution_cache_path", "")
            or str(Path(app.outdir).parent / ".jupyter_cache"))
    try:
        _, merged = get_cache(path).merge_match_into_notebook(nbformat.from_dict(nb))
    except KeyError:  # not in the cache: nothing was executed, leave it as it is
        return nb
    return json.loads(nbformat.writes(merged))


def _write(app, pagename, templatename, context, doctree):
    if context.get("ipynb_source") != f"{pagename}.ipynb":
        return
    executed = _executed(app, pagename)
    nb = _with_outputs(app, json.loads(executed.read_text()))
    # MyST-NB moves the glued outputs out of the notebook into <page>.glue.json
    glue_file = executed.with_name(executed.name[: -len(".ipynb")] + ".glue.json")
    glue = json.loads(glue_file.read_text()) if glue_file.exists() else {}
    if not hasattr(app, "_fc_bib"):
        app._fc_bib = _bibliography(app)
    from fusioncenter import __version__

    page_url = f"{_site(app, pagename)}{pagename}.html"
    reader, problems = reader_notebook(
        nb, _resolver(app, pagename, doctree, app._fc_bib), page_url=page_url,
        book_title=app.config.html_title or app.config.project or "the book", version=__version__,
        macros=_macros(app), profile=os.environ.get("FUSIONCENTER_PROFILE") or None, glue=glue,
        site=_public_site(app))
    for p in problems:
        LOG.warning(f"reader notebook {pagename}.ipynb: {p}", location=pagename)
    target = Path(app.outdir) / "_sources" / f"{pagename}.ipynb"
    target.parent.mkdir(parents=True, exist_ok=True)
    target.write_text(json.dumps(reader, indent=1, ensure_ascii=False) + "\n")
    _colab_to_notebook(app, pagename, context)


def _colab_to_notebook(app, pagename, context):
    """Point the theme's Colab button at the published reader-ready notebook."""
    opts = app.config.html_theme_options or {}
    repo = (opts.get("repository_url") or "").rstrip("/")
    m = re.match(r"https://github\.com/([^/]+)/([^/]+)$", repo)
    for group in context.get("header_buttons", []):
        if group.get("label") != "launch-buttons":
            continue
        for button in group.get("buttons", []):
            if button.get("text") == "Colab" and m:
                colab = opts["launch_buttons"]["colab_url"].rstrip("/")
                branch = getattr(app.config, NOTEBOOKS_BRANCH)
                button["url"] = f"{colab}/github/{m[1]}/{m[2]}/blob/{branch}/{pagename}.ipynb"


def _book_pdf_button(app, pagename, templatename, context, doctree):
    """"whole book" and "this page (PDF)" entries in every page's download menu: the typeset
    prints that ``make pdf`` (tools/pdf_book.py) writes into the site, ``book.pdf`` at its root
    and ``_pdf/<page>.pdf``."""
    for group in context.get("header_buttons", []):
        if group.get("label") == "download-buttons":
            group["buttons"].append({
                "type": "link", "url": context["pathto"]("book.pdf", 1), "text": "whole book",
                "tooltip": "The whole book as one PDF", "icon": "fas fa-book",
                "label": "download-book-pdf-button"})
            group["buttons"].append({
                "type": "link", "url": context["pathto"](f"_pdf/{pagename}.pdf", 1),
                "text": "this page (PDF)", "tooltip": "This page as a PDF handout",
                "icon": "fas fa-file-pdf", "label": "download-page-pdf-button"})


def _launch_settings(app, config):
    """Bring _config.yml's ``repository`` and ``launch_buttons`` into the theme's options.

    Jupyter Book writes them into ``html_theme_options``, but the ``sphinx.config``
    section of _config.yml sets ``html_theme_options`` too and replaces them. Without a
    repository URL the launch buttons are switched off (the theme would link them to
    jupyter-book's own repository).
    """
    import yaml

    cfg_file = Path(app.srcdir) / "_config.yml"
    cfg = yaml.safe_load(cfg_file.read_text()) if cfg_file.exists() else {}
    opts = config.html_theme_options
    repo = cfg.get("repository") or {}
    for key, yml in (("repository_url", "url"), ("repository_branch", "branch"),
                     ("path_to_docs", "path_to_book")):
        if yml in repo:
            opts.setdefault(key, repo[yml])
    if cfg.get("launch_buttons"):
        opts.setdefault("launch_buttons", dict(cfg["launch_buttons"]))
    if not (opts.get("repository_url") or "").strip():
        for key in ("binderhub_url", "colab_url", "jupyterhub_url"):
            if key in (opts.get("launch_buttons") or {}):
                opts["launch_buttons"][key] = ""


def setup(app):
    app.add_config_value(NOTEBOOKS_BRANCH, "notebooks", "html")
    app.connect("config-inited", _launch_settings)
    app.connect("html-page-context", _offer, priority=500)
    app.connect("html-page-context", _write, priority=502)
    app.connect("html-page-context", _book_pdf_button, priority=502)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "2.0"}
