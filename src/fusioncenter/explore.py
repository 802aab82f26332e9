"""Figures the reader can move: a registry entry computed along a grid of one of its parameters.

An explorable figure is a registry entry and a :class:`Slider` over one of its settable
parameters. Each *frame* is the entry's own compute at one value of the grid, through the same
path as ``python -m fusioncenter compute ID --set NAME=VALUE`` (:meth:`Entry.run_compute
<fusioncenter.figures.entry.Entry.run_compute>`, so the book's compute cache keeps every
frame), drawn by the entry's own ``plot``. :func:`explore` computes the frames in a chapter
and shows them:

- on the book's site, the ``{explorable-figure} ID`` directive (label ``explore-ID``) turns
  the glued frames into a figure with a slider that needs no kernel and no network
  (``book/_ext/explorable.py``);
- in print and in a notebook without a kernel, a small-multiples figure at a few values;
- in a notebook with a kernel and ipywidgets, a slider of ipywidgets over the same frames.

The claims that should hold along the whole slider (the rate falls as the trigger parameter
grows; the bounds enclose the Monte Carlo mean at every value) are the slider's ``sweep``
checks, evaluated by :func:`sweep_claims` and shown as the figure's evidence.
"""

from __future__ import annotations

import base64
import io
import math
import os
import struct
from collections.abc import Callable
from dataclasses import dataclass, field

from fusioncenter import figures, plotting
from fusioncenter._docstrings import Glossary
from fusioncenter.profile import check_profile, current_profile

__all__ = ["FRAME_DPI", "STATIC_ENV", "Slider", "dumps_frames", "explore", "frames", "get",
           "name", "register", "render_frames", "sweep_claims", "write_frames_csv"]

#: Resolution of a frame's PNG: 6.4 in at 120 dpi is 768 px, the page column's width, so a
#: slider of 17 frames stays well under 2 MB.
FRAME_DPI = 120
#: Set (to anything but ``""`` or ``0``) by the book's build and tests: :func:`explore` then
#: shows the static figure even where ipywidgets can be imported.
STATIC_ENV = "FUSIONCENTER_STATIC_FIGURES"

#: Inches of white around a frame's tight bounding box (as the registry figures').
FRAME_PAD_IN = 0.1

SLIDERS: dict[str, Slider] = {}

#: The arguments the functions of the module share, by name.
_doc = Glossary("""
entry_id : str
    A registry id with a slider (:func:`get`).
profile : str, optional
    ``"fast"`` or ``"paper"``; default :func:`fusioncenter.profile.current_profile`.
seed : int, optional
    The seed; default the entry's.
data : list of dict
    Its frames (:func:`frames`).
""")


@dataclass(frozen=True)
class Slider:
    """A parameter of a registry entry that the reader can move, and its grid.

    Attributes
    ----------
    entry_id : str
        The registry entry.
    parameter : str
        One of the entry's settable parameters.
    values : tuple of float
        The grid, in increasing order (at least 15 values).
    label : str
        The slider's name for a reader and a screen reader, with its units, e.g.
        ``"trigger parameter δ (units of y²)"``.
    symbol : str
        How the value is written beside the slider: ``"δ"`` gives ``"δ = 0.25"``.
    unit : str
        The unit written after the value (``""`` for none).
    fmt : str
        The format of the value (``"{:.3g}"``).
    start : int
        The index of the value shown first (the entry's default).
    print_at : tuple of int
        The indices of the small multiples (print, and a notebook without a kernel).
    fixed : dict
        Overrides applied to every frame, per profile (``{"fast": {"trials": 40}, ...}``):
        the sizes that keep a grid cheap.
    facts : callable
        ``facts(data) -> dict[str, str]``: the numbers a caption quotes for one frame.
    sweep : callable
        ``sweep(values, frames) -> list[Claim]``: the claims that hold along the slider.
    """

    entry_id: str
    parameter: str
    values: tuple
    label: str
    symbol: str
    unit: str = ""
    fmt: str = "{:.3g}"
    start: int = 0
    print_at: tuple = ()
    fixed: dict = field(default_factory=dict)
    facts: Callable | None = None
    sweep: Callable | None = None

    def __post_init__(self) -> None:
        vals = tuple(float(v) for v in self.values)
        if len(vals) < 15 or any(b <= a for a, b in zip(vals, vals[1:], strict=False)):
            raise ValueError(f"values of the slider {self.entry_id}/{self.parameter} must be at "
                             f"least 15 increasing numbers, got {self.values!r}")
        if not 0 <= self.start < len(vals):
            raise ValueError(f"start must index values (0..{len(vals) - 1}), got {self.start}")
        if not self.print_at or any(not 0 <= i < len(vals) for i in self.print_at):
            raise ValueError(f"print_at must index values, got {self.print_at!r}")
        object.__setattr__(self, "values", vals)

    def text(self, i: int) -> str:
        """The value ``i`` as written beside the slider.

        Parameters
        ----------
        i : int
            An index of :attr:`values`.

        Returns
        -------
        str
            The symbol, the value in :attr:`fmt` and the unit: ``"δ = 0.25"``.
        """
        unit = f" {self.unit}" if self.unit else ""
        return f"{self.symbol} = {self.fmt.format(self.values[i])}{unit}"

    def overrides(self, profile: str, i: int) -> dict:
        """The overrides of one frame.

        Parameters
        ----------
        profile : str
            ``"fast"`` or ``"paper"`` (the key of :attr:`fixed`).
        i : int
            The frame: an index of :attr:`values`.

        Returns
        -------
        dict
            The fixed sizes of ``profile`` and the slider's parameter at ``values[i]``.
        """
        return {**self.fixed.get(profile, {}), self.parameter: self.values[i]}


@_doc(returns=("str", "``explore-ID`` (a registry figure of the same entry, on the same "
                     "page, keeps ``ID``)."), entry_id="The registry id.")
def name(entry_id: str) -> str:
    """The explorable figure's label and glue key."""
    return f"explore-{entry_id}"


@_doc(returns=("Slider", "``slider``."),
      raises=(("ValueError", "If the entry already has a slider, or the parameter is not "
                             "settable."),),
      slider=("Slider", "The slider; its parameter must be one of the entry's settable "
                        "parameters."))
def register(slider: Slider) -> Slider:
    """Register ``slider`` under its entry's id (one slider per entry)."""
    from fusioncenter.figures.registry import REGISTRY

    if slider.entry_id in SLIDERS:
        raise ValueError(f"the entry {slider.entry_id!r} already has a slider")
    if slider.entry_id not in REGISTRY:
        raise ValueError(f"no registry entry {slider.entry_id!r} (register it first)")
    names = {p.name for p in REGISTRY[slider.entry_id].settable}
    if slider.parameter not in names:
        raise ValueError(f"parameter {slider.parameter!r} is not settable in "
                         f"{slider.entry_id!r} (settable: {sorted(names)})")
    SLIDERS[slider.entry_id] = slider
    return slider


@_doc(returns=("Slider", "Its slider."), entry_id="The registry id.",
      raises=(("KeyError", "If the entry has no slider (the message lists those that have "
                           "one)."),))
def get(entry_id: str) -> Slider:
    """The slider of a registry entry."""
    figures.get(entry_id)  # imports the module that registers the entry and its slider
    if entry_id not in SLIDERS:
        raise KeyError(f"{entry_id!r} has no slider; these have one: {sorted(SLIDERS)}")
    return SLIDERS[entry_id]


@_doc(returns=("list of dict", "``frames[i]`` is ``entry.run_compute(profile, seed, "
                              "**slider.overrides(profile, i))``,\nbit for bit what ``python "
                              "-m fusioncenter compute ID`` with those ``--set`` values\n"
                              "gives."))
def frames(entry_id: str, profile: str | None = None, seed: int | None = None) -> list[dict]:
    """The entry's data at every value of its slider, each the entry's own compute."""
    slider = get(entry_id)
    profile = current_profile() if profile is None else check_profile(profile)
    entry = figures.get(entry_id)
    return [entry.run_compute(profile, seed, **slider.overrides(profile, i))
            for i in range(len(slider.values))]


@_doc(returns=("list of fusioncenter.figures.claim.Claim", "The slider's ``sweep`` claims, "
                                                          "then the frames' own."))
def sweep_claims(entry_id: str, data: list[dict]) -> list:
    """The claims along the slider and, for every frame, the entry's own claims.

    The entry's claims make one claim, "every frame's claims hold", with the frames whose
    claims failed in its detail (claims about the paper's own setting are skipped where the
    slider changes a parameter of that setting).
    """
    from fusioncenter.figures.claim import Claim

    slider = get(entry_id)
    entry = figures.get(entry_id)
    out = list(slider.sweep(slider.values, data)) if slider.sweep else []
    model = any(p.name == slider.parameter and p.model for p in entry.settable)
    failed = []
    for i, d in enumerate(data):
        bad = [c.name for c in entry.run_checks(d)
               if not c.passed and not (model and c.paper_specific)]
        if bad:
            failed.append(f"{slider.text(i)}: {bad}")
    out.append(Claim(f"the entry's own claims hold in each of the {len(data)} frames",
                     not failed, "; ".join(failed) or "all hold"))
    return out


def _quantized(png: bytes) -> bytes:
    """The PNG with a palette of 256 colours (a third of the RGBA file's bytes)."""
    from PIL import Image

    image = Image.open(io.BytesIO(png)).convert("RGB")
    buf = io.BytesIO()
    image.quantize(colors=256, method=Image.Quantize.MEDIANCUT).save(buf, "PNG", optimize=True)
    return buf.getvalue()


@_doc(returns=("dict", "``frames``: per frame its PNG (base64), alt text, value text and "
                      "caption facts;\n``facts``: the layout facts of the frames "
                      "(:func:`fusioncenter.plotting.render`);\n``small_multiples``: a PNG "
                      "(base64) of the frames at ``print_at``; and the slider's\n"
                      "``parameter``, ``label``, ``values``, ``start`` and ``print_at``."))
def render_frames(entry_id: str, data: list[dict]) -> dict:
    """Every frame drawn and described, and the small multiples: what the site needs.

    The first frame is laid out (:func:`fusioncenter.plotting.layout_facts`); every frame is
    then drawn once with that frame's panel positions and bounding box, so that the frames
    have the same size in pixels and the panels do not move when the slider does.
    """
    import matplotlib.pyplot as plt

    slider = get(entry_id)
    entry = figures.get(entry_id)
    first = entry.run_plot(data[0])
    facts = plotting.layout_facts(first, dpi=FRAME_DPI)
    positions = [ax.get_position() for ax in first.axes]
    box = first.get_tightbbox().padded(FRAME_PAD_IN)
    plt.close(first)
    out_frames, pngs = [], []
    for i, d in enumerate(data):
        fig = entry.run_plot(d)
        fig.set_layout_engine("none")
        for ax, pos in zip(fig.axes, positions, strict=True):
            ax.set_position(pos)
        buf = io.BytesIO()
        fig.savefig(buf, format="png", dpi=FRAME_DPI, bbox_inches=box)
        png = _quantized(buf.getvalue())
        out_frames.append({"png": base64.b64encode(png).decode("ascii"),
                           "alt": f"{slider.text(i)}. {plotting.describe(fig)}",
                           "value": slider.text(i),
                           "facts": slider.facts(d) if slider.facts else {}})
        plt.close(fig)
        pngs.append(png)
    w, h = struct.unpack(">II", pngs[0][16:24])
    return {"id": entry_id, "parameter": slider.parameter, "label": slider.label,
            "values": list(slider.values), "start": slider.start,
            "print_at": list(slider.print_at), "frames": out_frames,
            "facts": {**facts, "width_px": int(w), "height_px": int(h)},
            "small_multiples": base64.b64encode(
                _small_multiples(slider, pngs)).decode("ascii")}


def _small_multiples(slider: Slider, pngs: list[bytes]) -> bytes:
    """The frames at ``print_at``, two to a row, each under a line with its value."""
    from matplotlib import font_manager
    from PIL import Image, ImageDraw, ImageFont

    images = [Image.open(io.BytesIO(pngs[i])).convert("RGB") for i in slider.print_at]
    w, h = images[0].size
    cols = 2 if len(images) > 1 else 1
    rows = math.ceil(len(images) / cols)
    head = 40
    sheet = Image.new("RGB", (cols * w, rows * (h + head)), "white")
    font = ImageFont.truetype(font_manager.findfont("DejaVu Sans"), 26)
    draw = ImageDraw.Draw(sheet)
    for k, (i, image) in enumerate(zip(slider.print_at, images, strict=True)):
        x, y = (k % cols) * w, (k // cols) * (h + head)
        draw.text((x + w // 2, y + head // 2), slider.text(i), fill="black", font=font,
                  anchor="mm")
        sheet.paste(image, (x, y + head))
    buf = io.BytesIO()
    sheet.quantize(colors=256, method=Image.Quantize.MEDIANCUT).save(buf, "PNG", optimize=True)
    return buf.getvalue()


def _widgets_wanted() -> bool:
    if os.environ.get(STATIC_ENV, "") not in ("", "0"):
        return False
    try:
        import ipywidgets  # noqa: F401
    except ImportError:
        return False
    from IPython import get_ipython

    return type(get_ipython()).__name__ == "ZMQInteractiveShell"


@_doc(returns=("list of dict", "The frames (:func:`frames`)."),
      raises=(("AssertionError", "If a claim along the slider does not hold (after the "
                                 "evidence has been shown)."),
              ("KeyError", "If the entry has no slider.")))
def explore(entry_id: str, profile: str | None = None, seed: int | None = None) -> list[dict]:
    """Compute, check and show an explorable figure; fail loudly if a claim does not hold.

    In a notebook it shows the small multiples (with the frames in the output's metadata, for
    the site's ``{explorable-figure} ID`` directive, glued under ``ID``), then the evidence
    (the slider's claims), glued under ``explore-ID`` and ``explore-ID-evidence``
    (:func:`name`). With a kernel, ipywidgets and
    :data:`STATIC_ENV` unset, it shows an ipywidgets slider over the frames instead.
    """
    from fusioncenter.book import FIGURE_METADATA, show_bundle, show_evidence

    slider = get(entry_id)
    profile = current_profile() if profile is None else check_profile(profile)
    data = frames(entry_id, profile, seed)
    claims = sweep_claims(entry_id, data)
    shown = render_frames(entry_id, data)
    if _widgets_wanted():
        _show_widget(slider, shown)
    else:
        meta = {**shown["facts"], **{k: v for k, v in shown.items() if k != "facts"},
                "alt": f"Small multiples at {len(slider.print_at)} values: " + "; ".join(
                    shown["frames"][i]["alt"] for i in slider.print_at)}
        meta.pop("small_multiples")
        meta.update(profile=profile, seed=figures.get(entry_id).seed if seed is None else seed)
        show_bundle({"image/png": shown["small_multiples"],
                     "text/plain": f"<explorable figure {entry_id}: {len(data)} frames of "
                                   f"{slider.parameter}>"},
                    {"scrapbook": {"name": name(entry_id), "mime_prefix": ""},
                     FIGURE_METADATA: meta})
    show_evidence(entry_id, claims, f"{name(entry_id)}-evidence",
                  "claims failed along the slider")
    return data


def _show_widget(slider: Slider, shown: dict) -> None:  # pragma: no cover (needs a frontend)
    """An ipywidgets slider over the rendered frames (a notebook with a kernel)."""
    import ipywidgets as widgets
    from IPython.display import display

    pngs = [base64.b64decode(f["png"]) for f in shown["frames"]]
    image = widgets.Image(value=pngs[slider.start], format="png",
                          layout=widgets.Layout(max_width="100%"))
    control = widgets.SelectionSlider(
        options=[(f["value"], i) for i, f in enumerate(shown["frames"])],
        value=slider.start, description=slider.symbol, continuous_update=True,
        layout=widgets.Layout(width="100%"))

    def move(change) -> None:
        image.value = pngs[change["new"]]

    control.observe(move, names="value")
    display(widgets.VBox([widgets.Label(slider.label), control, image]))


@_doc(returns=("str", "One line of strict JSON: ``{\"id\", \"parameter\", \"values\", "
                     "\"frames\"}``, ``frames[i]``\nbeing what ``python -m fusioncenter "
                     "compute ID --json`` prints for ``values[i]``\n(without its ``_run`` "
                     "record)."))
def dumps_frames(entry_id: str, data: list[dict]) -> str:
    """The data download of an explorable figure as JSON: every frame with its value."""
    from fusioncenter import cli

    slider = get(entry_id)
    return cli.dumps({"id": entry_id, "parameter": slider.parameter,
                      "values": list(slider.values), "frames": data})


@_doc(returns=("None", "The file is written."),
      path=("str or pathlib.Path", "The file to write: the command line's long format\n"
                                   "(:func:`fusioncenter.cli.write_csv`) of every frame, each "
                                   "row led by the slider's\nvalue."))
def write_frames_csv(entry_id: str, data: list[dict], path) -> None:
    """The data download of an explorable figure as CSV: ``PARAMETER,name,index,value``."""
    from fusioncenter import cli

    slider = get(entry_id)
    lines = [f"{slider.parameter},name,index,value"]
    for value, d in zip(slider.values, data, strict=True):
        buf = io.StringIO()
        cli.write_csv(d, buf)
        lines += [f"{value!r},{row}" for row in buf.getvalue().splitlines()[1:]]
    with open(path, "w", encoding="utf-8", newline="") as f:
        f.write("\n".join(lines) + "\n")
