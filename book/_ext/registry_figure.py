"""``{registry-figure} ID``: a registry entry's figure as a numbered, captioned figure.

A chapter shows a registry figure with ``fusioncenter.book.reproduce("ID", profile)``, which
displays the figure as a PNG (in plain Jupyter it is an ordinary cell output) glued under the
key ``ID``, and the evidence (every claim, its value, its verdict) glued under ``ID-evidence``.
The chapter tags that cell ``remove-output`` and follows it with::

    ```{registry-figure} ID
    ```

which makes, from the glued outputs (so a notebook restored from jupyter-cache gives the same
page):

- a ``figure`` node named ``ID`` (``{numref}`ID``` works), its image at the text width and
  linked to the full-resolution PNG, its alt text written from the figure's axes and legends;
- a caption: the registry caption, which paper figure it reproduces (or that it is the book's
  own; for an entry whose status is ``differs``, that it differs from it and how, in one
  line), the profile with its trial/path/particle counts, and the seed;
- links to the figure's data as JSON and CSV, written into the site by the command line's own
  serialisers (``python -m fusioncenter compute ID --json`` / ``--csv``);
- the evidence as a collapsible table;
- the figure's panel count, width fraction and smallest font in ``data-`` attributes, which
  ``tools/browser_check`` turns into displayed sizes;
- a smallest displayed width (:func:`legible_width`): on a narrow screen (a phone) the image
  keeps the width at which every panel is ``LEGIBLE_PANEL_PX`` wide and its smallest font
  ``LEGIBLE_FONT_PX`` high, and scrolls sideways in its own box; the caption wraps below it.
"""

from __future__ import annotations

import html
import math
import re
from pathlib import Path

from docutils import nodes
from docutils.statemachine import StringList
from myst_nb.core.variables import RetrievalError, render_variable_outputs
from myst_nb.ext.glue.utils import glue_warning, retrieve_glue_data
from myst_nb.ext.utils import DirectiveBase
from sphinx.util import logging

LOGGER = logging.getLogger(__name__)
DATA_DIR = "_figure-data"
STATIC = Path(__file__).with_name("registry_figure_static")
_ROMAN = {1: "I", 2: "II", 3: "III", 4: "IV", 5: "V", 6: "VI"}
#: The sizes a reader needs (issue 13), as displayed: a panel's width and the smallest font.
LEGIBLE_PANEL_PX = 500
LEGIBLE_FONT_PX = 11


def legible_width(meta: dict) -> int:
    """The smallest displayed width (CSS px) of the image at which each panel is at least
    ``LEGIBLE_PANEL_PX`` wide and its smallest font ``LEGIBLE_FONT_PX`` high: a font of
    ``min_font_pt`` points is ``min_font_pt * dpi / 72`` pixels in the ``width_px`` wide PNG."""
    panel = LEGIBLE_PANEL_PX / float(meta["panel_fraction"])
    font = LEGIBLE_FONT_PX * float(meta["width_px"]) * 72 / (float(meta["min_font_pt"])
                                                             * float(meta["dpi"]))
    return math.ceil(max(panel, font))


def paper_figure(entry_id: str) -> str | None:
    """``"Fig. 3(a)"`` / ``"Table II"`` for a paper's own figure id, ``None`` otherwise."""
    from fusioncenter.figures import PAPER_IDS

    if entry_id not in PAPER_IDS:
        return None
    m = re.fullmatch(r"[a-z]+\d{4}-fig(\d+)([a-z]?)", entry_id)
    if m:
        return f"Fig. {m[1]}" + (f"({m[2]})" if m[2] else "")
    m = re.fullmatch(r"[a-z]+\d{4}-table(\d+)", entry_id)
    return f"Table {_ROMAN.get(int(m[1]), m[1])}" if m else None


def counts(parameters: dict, profile: str) -> list[str]:
    """``"2000 paths"``-style phrases: every parameter that depends on the profile."""
    out = []
    for name, value in parameters.items():
        if isinstance(value, dict) and set(value) == {"fast", "paper"}:
            v = value[profile]
            v = ", ".join(map(str, v)) if isinstance(v, list | tuple) else str(v)
            out.append(f"{v} {name.replace('_', ' ')}")
    return out


def caption_source(entry, meta: dict) -> tuple[str, str]:
    """The caption: the registry caption (plain text) and a MyST suffix.

    The suffix says which paper figure the entry reproduces, or, for an entry whose status is
    ``differs``, that it differs from it and how, in one line
    (:meth:`fusioncenter.figures.registry.Entry.differs_reason`).
    """
    fig = paper_figure(entry.id)
    reason = entry.differs_reason()
    if fig is not None and reason:
        what = f"Differs from {fig} of {{cite:t}}`{entry.paper}`: {reason}."
    elif fig is not None:
        what = f"Reproduces {fig} of {{cite:t}}`{entry.paper}`."
    elif entry.paper == "book":
        what = "This book's own figure."
    else:
        what = f"This book's own figure, on the model of {{cite:t}}`{entry.paper}`."
    if fig is None and reason:
        what += f" Differs from what the paper states: {reason}."
    run = [f"profile `{meta['profile']}`"] + counts(entry.parameters, meta["profile"])
    return entry.caption, f"{what} Computed in {', '.join(run)}; seed {meta['seed']}."


def _figure_node(directive, out, meta: dict, name: str, classes=()) -> nodes.figure:
    """A numbered figure node named ``name`` holding the glued PNG ``out`` at the text width,
    with the alt text of its metadata ``meta``."""
    image = render_variable_outputs(
        [out], directive.document, directive.line, directive.source,
        render={"image": {"alt": meta["alt"], "width": "100%"}})
    figure = nodes.figure("", *image, classes=["fc-registry-figure", *classes])
    directive.set_source_info(figure)
    directive.options["name"] = name
    directive.add_name(figure)
    return figure


def facts_html(name: str, meta: dict, img: str = "img") -> str:
    """The figure's facts for the browser check (``data-`` attributes of a hidden span) and
    its smallest legible width (of the figure's ``img``, a CSS selector): on a phone the image
    scrolls in its link's box. Shared with book/_ext/explorable.py."""
    facts = {k: meta[k] for k in ("panels", "columns", "panel_fraction", "min_font_pt",
                                  "dpi", "width_px", "height_px")}
    attrs = " ".join(f'data-{k.replace("_", "-")}="{html.escape(str(v))}"'
                     for k, v in facts.items())
    return (f'<style>figure#{name} {img} {{ min-width: {legible_width(meta)}px; }}</style>'
            f'<span class="fc-facts" data-id="{name}" {attrs} hidden></span>')


class RegistryFigure(DirectiveBase):
    """The directive (see the module docstring)."""

    required_arguments = 1
    has_content = False
    option_spec: dict = {}

    def run(self):
        from fusioncenter import figures

        entry_id = self.arguments[0].strip()
        try:
            entry = figures.get(entry_id)
        except KeyError as exc:
            return [glue_warning(f"registry-figure: {exc}", self.document, self.line)]
        try:
            out = retrieve_glue_data(self.document, entry_id)
            evidence = retrieve_glue_data(self.document, f"{entry_id}-evidence")
        except RetrievalError as exc:
            return [glue_warning(f"registry-figure {entry_id}: {exc} (does the page call "
                                 f"reproduce({entry_id!r})?)", self.document, self.line)]
        meta = dict(out.metadata.get("fusioncenter", {}))
        if not meta:
            return [glue_warning(f"registry-figure {entry_id}: the glued output has no figure "
                                 "facts", self.document, self.line)]
        figure = _figure_node(self, out, meta, entry_id)

        text, suffix = caption_source(entry, meta)
        holder = nodes.Element()
        self.state.nested_parse(StringList([suffix], source=self.source), self.content_offset,
                                holder)
        suffix_nodes = holder[0].children if len(holder) and isinstance(
            holder[0], nodes.paragraph) else []
        figure += nodes.caption("", nodes.Text(text + " "), *suffix_nodes)

        env = self.state.document.settings.env
        up = "../" * env.docname.count("/")
        stem = f"{up}{DATA_DIR}/{entry_id}.{meta['profile']}.{meta['seed']}"
        links = (f'{facts_html(entry_id, meta)}'
                 f'<p class="fc-figure-data">Data of this figure: '
                 f'<a href="{stem}.json" download>JSON</a> · '
                 f'<a href="{stem}.csv" download>CSV</a> '
                 f'(<code>python -m fusioncenter compute {entry_id} --profile '
                 f'{meta["profile"]} --json</code>)</p>')
        figure += nodes.legend("", nodes.raw("", links, format="html"))

        records = env.__dict__.setdefault("fc_registry_figures", {})
        records.setdefault(env.docname, set()).add((entry_id, meta["profile"], int(meta["seed"])))
        shown = render_variable_outputs([evidence], self.document, self.line, self.source)
        return [figure, *shown]


class BookFigure(DirectiveBase):
    """``{book-figure} NAME`` with the caption as its body: a figure a chapter draws itself
    (:func:`fusioncenter.book.figure` glued it under ``NAME``), numbered and captioned like a
    registry figure, with the same alt text, facts and legible width, and no data links."""

    required_arguments = 1
    has_content = True
    option_spec: dict = {}

    def run(self):
        name = self.arguments[0].strip()
        if not self.content:
            return [glue_warning(f"book-figure {name}: no caption (the directive's body)",
                                 self.document, self.line)]
        try:
            out = retrieve_glue_data(self.document, name)
        except RetrievalError as exc:
            return [glue_warning(f"book-figure {name}: {exc} (does the page call "
                                 f"fusioncenter.book.figure({name!r}, fig)?)",
                                 self.document, self.line)]
        meta = dict(out.metadata.get("fusioncenter", {}))
        if not meta:
            return [glue_warning(f"book-figure {name}: the glued output has no figure facts",
                                 self.document, self.line)]
        figure = _figure_node(self, out, meta, name, classes=["fc-book-figure"])
        holder = nodes.Element()
        self.state.nested_parse(self.content, self.content_offset, holder)
        first, rest = (holder[0], holder[1:]) if len(holder) else (None, [])
        if not isinstance(first, nodes.paragraph):
            return [glue_warning(f"book-figure {name}: the caption must start with a "
                                 "paragraph", self.document, self.line)]
        figure += nodes.caption(first.rawsource, "", *first.children)
        figure += nodes.legend("", *rest, nodes.raw("", facts_html(name, meta),
                                                     format="html"))
        return [figure]


def track(app, attr: str) -> None:
    """Keep ``env.<attr>`` (docname -> the figures a page shows) through incremental and
    parallel builds: a re-read page drops its records, a parallel reader's are merged. Shared
    with book/_ext/explorable.py."""

    def purge(app, env, docname):
        getattr(env, attr, {}).pop(docname, None)

    def merge(app, env, docnames, other):
        mine = env.__dict__.setdefault(attr, {})
        for doc in docnames:
            if doc in getattr(other, attr, {}):
                mine[doc] = getattr(other, attr)[doc]

    app.connect("env-purge-doc", purge)
    app.connect("env-merge-info", merge)


def static_folder(app, folder: Path) -> None:
    """Serve ``folder``'s files from the site's ``_static`` (on ``builder-inited``)."""
    app.connect("builder-inited", lambda app: app.config.html_static_path.append(str(folder)))


def _write_data(app, exc):
    """Write every shown figure's data as JSON and CSV (the command line's serialisers)."""
    if exc is not None or app.builder.format != "html":
        return
    import matplotlib

    backend = matplotlib.get_backend()
    from fusioncenter import cli, figures

    matplotlib.use(backend)  # importing the command line selects Agg; keep Sphinx's choice
    folder = Path(app.outdir) / DATA_DIR
    folder.mkdir(parents=True, exist_ok=True)
    todo = sorted(set().union(*getattr(app.env, "fc_registry_figures", {}).values()))
    for entry_id, profile, seed in todo:
        stem = f"{entry_id}.{profile}.{seed}"
        js, csv = folder / f"{stem}.json", folder / f"{stem}.csv"
        if js.exists() and csv.exists():
            continue
        # the book's build keeps every computed entry (FUSIONCENTER_COMPUTE_CACHE), so this
        # reads the very data the chapter plotted; without it, the entry is computed again
        data = figures.get(entry_id).run_compute(profile, None if seed == figures.get(
            entry_id).seed else seed)
        js.write_text(cli.dumps(data) + "\n")
        cli.write_csv(data, csv)
    LOGGER.info(f"registry_figure: data of {len(todo)} figures in {folder}")


def setup(app):
    app.add_directive("registry-figure", RegistryFigure)
    app.add_directive("book-figure", BookFigure)
    app.add_css_file("registry-figure.css")
    static_folder(app, STATIC)
    track(app, "fc_registry_figures")
    app.connect("build-finished", _write_data)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1.0"}
