"""``{explorable-figure} ID``: a figure the reader moves on the static page, with no kernel.

A chapter calls :func:`fusioncenter.explore.explore` (``"ID"`` a registry entry with a slider)
in a cell tagged ``remove-output`` and follows it with the directive, whose body is the
caption::

    ```{explorable-figure} mo2015-explore
    At δ = [[rate]] ...
    ```

From the glued output (``explore-ID``: the frames as PNGs, their alt texts, values and caption
facts) it makes a numbered figure named ``explore-ID`` (``{numref}`explore-ID```) holding:

- the frame at the slider's start, written with the others to ``_explore/ID/NN.png``;
- a native range input (arrow keys move it; named by its label, its value spoken through
  ``aria-valuetext``) and the value with its units beside it; ``explorable.js`` swaps the
  frame, its alt text, the value and every ``[[fact]]`` of the caption when it moves;
- in print (the book's PDF, a page's PDF) the small multiples: the frames at the slider's
  ``print_at`` values, two to a row, and no control;
- links to the data of every frame (JSON and CSV, :func:`fusioncenter.explore.dumps_frames`,
  :func:`fusioncenter.explore.write_frames_csv`), and the claims along the slider as a
  collapsible evidence table.

Everything is served by the site (no CDN, no network). A ``[[name]]`` in the caption is the
current frame's fact ``name`` (:attr:`fusioncenter.explore.Slider.facts`).
"""

from __future__ import annotations

import base64
import html
import json
import re
from pathlib import Path

from docutils import nodes
from myst_nb.core.variables import RetrievalError, render_variable_outputs
from myst_nb.ext.glue.utils import glue_warning, retrieve_glue_data
from myst_nb.ext.utils import DirectiveBase
from sphinx.util import logging

LOGGER = logging.getLogger(__name__)
FRAMES_DIR = "_explore"
DATA_DIR = "_figure-data"
STATIC = Path(__file__).with_name("explorable_static")
FACT = re.compile(r"\[\[([a-z0-9_]+)\]\]")


def _facts_in(node: nodes.Element, facts: dict) -> list[str]:
    """Replace every ``[[name]]`` in the text of ``node`` by a span the script updates; return
    the names that are not facts of the frame."""
    missing = []
    for text in list(node.findall(nodes.Text)):
        parts = FACT.split(text.astext())
        if len(parts) == 1:
            continue
        new = []
        for k, part in enumerate(parts):
            if k % 2 == 0:
                if part:
                    new.append(nodes.Text(part))
            elif part in facts:
                new.append(nodes.raw("", f'<span class="fc-explore-fact" data-fact="{part}">'
                                         f"{html.escape(facts[part])}</span>", format="html"))
            else:
                missing.append(part)
        text.parent.replace(text, new)
    return missing


def _controls(name: str, meta: dict, up: str) -> str:
    frames = meta["frames"]
    start = int(meta["start"])
    entry_id = meta["id"]
    src = [f"{FRAMES_DIR}/{entry_id}/{i:02d}.png" for i in range(len(frames))]
    data = [{"src": up + s, "alt": f["alt"], "value": f["value"], "facts": f["facts"]}
            for s, f in zip(src, frames, strict=True)]
    label = html.escape(meta["label"])
    current = frames[start]
    payload = json.dumps(data).replace("</", "<\\/")  # no "</script>" inside the script
    prints = "".join(
        f'<div class="fc-explore-multiple"><p>{html.escape(frames[i]["value"])}</p>'
        f'<img src="{up}{src[i]}" alt="{html.escape(frames[i]["alt"])}" loading="eager"/></div>'
        for i in meta["print_at"])
    from registry_figure import facts_html

    return (
        f'{facts_html(name, meta, img="img.fc-explore-frame")}'
        f'<div class="fc-explore" data-id="{html.escape(entry_id)}">'
        f'<div class="fc-explore-controls">'
        f'<label for="{name}-slider">{label}</label>'
        f'<input type="range" class="fc-explore-slider" id="{name}-slider" min="0" '
        f'max="{len(frames) - 1}" step="1" value="{start}" '
        f'aria-valuetext="{html.escape(current["value"])}"/>'
        f'<output class="fc-explore-value" for="{name}-slider" aria-live="polite">'
        f'{html.escape(current["value"])}</output></div>'
        f'<a class="image-reference fc-explore-link" href="{up}{src[start]}">'
        f'<img class="fc-explore-frame" src="{up}{src[start]}" '
        f'alt="{html.escape(current["alt"])}" width="{meta["width_px"]}" '
        f'height="{meta["height_px"]}"/></a>'
        f'<div class="fc-explore-print">{prints}</div>'
        f'<script type="application/json" class="fc-explore-frames">'
        f'{payload}</script></div>')


class ExplorableFigure(DirectiveBase):
    """The directive (see the module docstring)."""

    required_arguments = 1
    has_content = True
    option_spec: dict = {}

    def run(self):
        from fusioncenter import explore

        entry_id = self.arguments[0].strip()
        name = explore.name(entry_id)
        if not self.content:
            return [glue_warning(f"explorable-figure {entry_id}: no caption (the directive's "
                                 "body)", self.document, self.line)]
        try:
            out = retrieve_glue_data(self.document, name)
            evidence = retrieve_glue_data(self.document, f"{name}-evidence")
        except RetrievalError as exc:
            return [glue_warning(f"explorable-figure {entry_id}: {exc} (does the page call "
                                 f"explore({entry_id!r})?)", self.document, self.line)]
        meta = dict(out.metadata.get("fusioncenter", {}))
        if not meta.get("frames"):
            return [glue_warning(f"explorable-figure {entry_id}: the glued output has no "
                                 "frames", self.document, self.line)]
        env = self.state.document.settings.env
        folder = Path(env.app.outdir) / FRAMES_DIR / entry_id
        folder.mkdir(parents=True, exist_ok=True)
        for i, frame in enumerate(meta["frames"]):
            (folder / f"{i:02d}.png").write_bytes(base64.b64decode(frame["png"]))
        up = "../" * env.docname.count("/")

        figure = nodes.figure("", classes=["fc-registry-figure", "fc-explorable"])
        self.set_source_info(figure)
        self.options["name"] = name
        self.add_name(figure)
        figure += nodes.raw("", _controls(name, meta, up), format="html")
        holder = nodes.Element()
        self.state.nested_parse(self.content, self.content_offset, holder)
        first, rest = (holder[0], holder[1:]) if len(holder) else (None, [])
        if not isinstance(first, nodes.paragraph):
            return [glue_warning(f"explorable-figure {entry_id}: the caption must start with "
                                 "a paragraph", self.document, self.line)]
        facts = meta["frames"][int(meta["start"])]["facts"]
        missing = _facts_in(first, facts)
        for part in rest:
            missing += _facts_in(part, facts)
        if missing:
            return [glue_warning(f"explorable-figure {entry_id}: the caption names facts the "
                                 f"frames do not have: {missing} (they have {sorted(facts)})",
                                 self.document, self.line)]
        figure += nodes.caption(first.rawsource, "", *first.children)
        stem = f"{up}{DATA_DIR}/{name}.{meta['profile']}.{meta['seed']}"
        n = len(meta["frames"])
        links = (f'<p class="fc-figure-data">Data of the {n} frames: '
                 f'<a href="{stem}.json" download>JSON</a> · '
                 f'<a href="{stem}.csv" download>CSV</a> (each frame is '
                 f'<code>python -m fusioncenter compute {entry_id} --set '
                 f'{meta["parameter"]}=VALUE</code>)</p>')
        figure += nodes.legend("", *rest, nodes.raw("", links, format="html"))
        records = env.__dict__.setdefault("fc_explorable_figures", {})
        records.setdefault(env.docname, set()).add(
            (entry_id, meta["profile"], int(meta["seed"])))
        shown = render_variable_outputs([evidence], self.document, self.line, self.source)
        return [figure, *shown]


def _write_data(app, exc):
    """Every explorable figure's frames as JSON and CSV (see the module docstring)."""
    if exc is not None or app.builder.format != "html":
        return
    import matplotlib

    backend = matplotlib.get_backend()
    from fusioncenter import explore, figures

    matplotlib.use(backend)
    folder = Path(app.outdir) / DATA_DIR
    folder.mkdir(parents=True, exist_ok=True)
    todo = sorted(set().union(*getattr(app.env, "fc_explorable_figures", {}).values()))
    for entry_id, profile, seed in todo:
        stem = folder / f"{explore.name(entry_id)}.{profile}.{seed}"
        js, csv = stem.with_name(stem.name + ".json"), stem.with_name(stem.name + ".csv")
        if js.exists() and csv.exists():
            continue
        # the book's build keeps every computed frame (FUSIONCENTER_COMPUTE_CACHE): these
        # are the frames the chapter drew
        entry = figures.get(entry_id)
        data = explore.frames(entry_id, profile, None if seed == entry.seed else seed)
        js.write_text(explore.dumps_frames(entry_id, data) + "\n")
        explore.write_frames_csv(entry_id, data, csv)
    LOGGER.info(f"explorable: data of {len(todo)} explorable figures in {folder}")


def setup(app):
    app.add_directive("explorable-figure", ExplorableFigure)
    app.add_css_file("explorable.css")
    app.add_js_file("explorable.js", defer="defer")
    from registry_figure import static_folder, track

    static_folder(app, STATIC)
    track(app, "fc_explorable_figures")
    app.connect("build-finished", _write_data)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
