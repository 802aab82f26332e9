"""One visual language: every registry figure draws each scheme and quantity with its look.

Each figure is drawn on its fast-profile data (shared with ``tests/test_figures_*.py`` through
``figure_helpers``); every legend entry whose label names a scheme must have that scheme's
colour and (where it draws markers) marker, and every entry naming a bound has that bound's line
style. Legends sit outside the data area, panels are stacked at the full width, and no text is
smaller than ``plotting.MIN_FONT_PT``.
"""

from __future__ import annotations

import matplotlib
import matplotlib.colors as mcolors
import matplotlib.pyplot as plt
import numpy as np
import pytest
from figure_helpers import cached_data
from matplotlib.container import ErrorbarContainer
from matplotlib.lines import Line2D

from fusioncenter import figures, plotting

FIGURE_IDS = [e.id for e in figures.entries() if e.plot is not None]


def _line(handle):
    if isinstance(handle, ErrorbarContainer):
        return handle.lines[0]
    return handle if isinstance(handle, Line2D) else None


def _same_color(a, b) -> bool:
    return np.allclose(mcolors.to_rgb(a), mcolors.to_rgb(b))


def _dashes(ls):
    """A line style as matplotlib draws it (offset, on-off sequence), in points of width 1."""
    probe = Line2D([], [], linestyle=ls, linewidth=1.0)
    return probe._unscaled_dash_pattern


def styled_violations(fig) -> list[str]:
    """Legend entries whose look contradicts :func:`plotting.classify` of their label."""
    bad = []
    for ax in fig.get_axes():
        for handle, label in zip(*ax.get_legend_handles_labels(), strict=True):
            line = _line(handle)
            if line is None:
                continue
            scheme, quantity = plotting.classify(label)
            want = plotting.look(scheme, quantity)
            marker = line.get_marker()
            if scheme is not None:
                if not _same_color(line.get_color(), want["color"]):
                    bad.append(f"{label!r}: colour {line.get_color()} is not {scheme}'s "
                               f"{want['color']}")
                if marker not in ("None", "none", "", " ", None) and marker != want["marker"]:
                    bad.append(f"{label!r}: marker {marker!r} is not {want['marker']!r}")
            elif quantity is not None:
                if line._unscaled_dash_pattern != _dashes(want["linestyle"]):
                    bad.append(f"{label!r}: line style {line.get_linestyle()!r} is not "
                               f"{quantity}'s {want['linestyle']!r}")
    return bad


def test_looks_are_distinct_and_follow_the_papers_key():
    triples = {(mcolors.to_hex(v["color"]), v["marker"], str(v["linestyle"]))
               for v in plotting.SCHEMES.values()}
    assert len(triples) == len(plotting.SCHEMES)
    # zheng2014's own key: circle random selection, triangle CFoMD, square CFwMD, plus all-send
    assert [plotting.SCHEMES[k]["marker"] for k in ("random", "cfomd", "cfwmd", "all-send")] \
        == ["o", "^", "s", "P"]
    assert plotting.classify("CFwMD2 (state + covariance)") == ("cfwmd2", None)
    assert plotting.classify("CFwMD, exact filter") == ("exact", None)
    assert plotting.classify("CFwMD (paper, Table I)") == ("cfwmd", "paper")
    assert plotting.classify("lower bound (37)") == (None, "lower-bound")
    with pytest.raises(ValueError, match="scheme"):
        plotting.look("cfwmd3")
    with pytest.raises(ValueError, match="fixed by the scheme"):
        plotting.look("cfwmd", color="red")


def test_a_wrong_look_is_caught():
    fig, ax = plotting.subplots()
    ax.plot([0, 1], [0, 1], label="CFoMD", **plotting.look("cfwmd"))
    ax.plot([0, 1], [1, 2], label="upper bound (37)", **plotting.look(quantity="lower-bound"))
    ax.set(xlabel="x (-)", ylabel="y (-)")
    ax.legend()
    bad = styled_violations(plotting.finish(fig))
    plt.close(fig)
    assert len(bad) == 2 and "CFoMD" in bad[0]


def test_errorbar_log_clips_and_notes():
    fig, ax = plotting.subplots(stack=True)
    plotting.errorbar_log(ax, [2, 4], [1.0, 10.0], [3.0, 1.0], label="equal power (mean)")
    ax.set(xlabel="M (-)", ylabel="power (W)")
    plotting.finish(fig)
    lo, _ = ax.get_ylim()
    assert lo > 0
    seg = ax.containers[0].lines[2][0].get_segments()
    assert min(s[:, 1].min() for s in seg) >= lo * (1 - 1e-9)  # nothing leaves the axis
    labels = ax.get_legend_handles_labels()[1]
    assert any("clipped" in t and "x = 2" in t for t in labels)
    plt.close(fig)


@pytest.mark.parametrize("entry_id", FIGURE_IDS)
def test_registry_figure_uses_the_visual_language(entry_id):
    fig = figures.get(entry_id).run_plot(cached_data(entry_id))
    try:
        assert styled_violations(fig) == []
        facts = plotting.layout_facts(fig)  # laid out as render() lays it out for the page
        renderer = fig.canvas.get_renderer()
        for ax in fig.get_axes():
            leg = ax.get_legend()
            if leg is None or not ax.has_data():
                continue
            a, b = ax.get_window_extent(renderer), leg.get_window_extent(renderer)
            assert not a.overlaps(b), f"{entry_id}: a legend sits on the data of {ax.get_title()}"
        assert facts["columns"] == 1, f"{entry_id}: panels side by side"
        assert facts["min_font_pt"] >= plotting.MIN_FONT_PT
        # at a 700 px text column, the narrowest data area is >= 500 px, fonts >= 11 px
        scale = 700 / facts["width_px"]
        assert facts["panel_fraction"] * 700 >= 500, facts
        assert facts["min_font_pt"] * facts["dpi"] / 72 * scale >= 11, facts
        assert plotting.describe(fig).count("Panel") == facts["panels"]
        assert panel_letters(fig) is not None, f"{entry_id}: panels without their own letter"
        assert unreadable_log_ticks(fig, draw=False) == [], entry_id  # laid out above
    finally:
        plt.close(fig)


def panel_letters(fig) -> list[str] | None:
    """The panels' letters, top to bottom (``[]`` for one panel); ``None`` if a panel of a
    figure of several lacks one or two share one."""
    panels = [ax for ax in fig.get_axes() if ax.get_visible() and ax.has_data()]
    if len(panels) < 2:
        return []
    found = [plotting.panels._PANEL_LETTER.match(plotting.panel_heading(ax)[0]) for ax in panels]
    letters = [m[1] for m in found if m]
    return letters if len(letters) == len(panels) == len(set(letters)) else None


def unreadable_log_ticks(fig, draw: bool = True) -> list[str]:
    """Tick labels of log axes written as ``k×10^n`` (matplotlib's minor labels on an axis of
    less than a decade): a reader wants plain numbers or powers of ten. The labels are set by
    a layout pass (``draw``; nothing is rasterised); ``draw=False`` reads those of the figure's
    last layout (after :func:`plotting.layout_facts`, a second pass cost 0.2 s a figure)."""
    if draw:
        fig.draw_without_rendering()
    bad = []
    for ax in fig.get_axes():
        for axis in (ax.xaxis, ax.yaxis):
            if axis.get_scale() != "log":
                continue
            for tick in (*axis.get_ticklabels(), *axis.get_ticklabels(minor=True)):
                if "\\times" in tick.get_text():
                    bad.append(f"{ax.get_ylabel() or ax.get_xlabel()}: {tick.get_text()}")
    return bad


def test_layout_facts_are_renders_without_the_png():
    """What the registry-figure test reads instead of rendering each figure (0.3 s less)."""
    fig, (a, b) = plotting.subplots(2, 1, stack=True)
    a.plot([1, 2], [0.8, 3.1], label="x")
    b.plot([1, 2], [0.8, 3.1])
    for ax in (a, b):
        ax.set(xlabel="x (-)", ylabel="y (-)")
    a.set_title("a long title of the first panel")
    a.legend()
    plotting.finish(fig)
    laid = plotting.layout_facts(fig)
    png, facts = plotting.render(fig)
    plt.close(fig)
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    sizes = ("width_px", "height_px")
    assert {k: v for k, v in laid.items() if k not in sizes} == \
        {k: v for k, v in facts.items() if k not in sizes}
    assert laid["panels"] == 2 and laid["columns"] == 1
    for k in sizes:
        assert laid[k] == pytest.approx(facts[k], rel=0.03)
    for bad in (0, -200, float("nan"), float("inf"), True, "200"):
        with pytest.raises(ValueError, match="dpi"):
            plotting.layout_facts(fig, dpi=bad)
    with pytest.raises(ValueError, match="fig must be a matplotlib Figure"):
        plotting.layout_facts(a)


def test_panels_get_their_own_letters_and_log_ticks_read_plainly():
    fig, (a, b) = plotting.subplots(2, 1, stack=True)
    a.plot([1, 2], [0.8, 3.1], label="x")
    b.plot([1, 2], [0.8, 3.1])
    for ax in (a, b):
        ax.set(xlabel="x (-)", ylabel="y (-)", yscale="log")
    a.set_title("first")
    a.legend()
    plotting.finish(fig)
    assert panel_letters(fig) is None
    assert unreadable_log_ticks(fig)  # matplotlib's default: 2x10^0, 3x10^0
    plotting.letter_panels(fig)
    assert panel_letters(fig) == ["a", "b"]
    assert a.get_legend().get_title().get_text() == "(a) first" and b.get_title() == "(b)"
    plotting.letter_panels(fig)  # already lettered: unchanged
    assert a.get_legend().get_title().get_text() == "(a) first"
    for ax in (a, b):
        plotting.log_axis(ax)
    assert unreadable_log_ticks(fig) == []
    labels = [t.get_text() for t in b.yaxis.get_ticklabels(minor=True) if t.get_text()]
    assert "1.5" in labels and "3" in labels
    b.set_title("(a) again")
    with pytest.raises(ValueError, match="share a letter"):
        plotting.letter_panels(fig)
    with pytest.raises(ValueError, match="which"):
        plotting.log_axis(a, "z")
    plt.close(fig)


def test_subplots_stack_and_keep_the_grid_shape():
    fig, axes = plotting.subplots(2, 2, stack=True)
    assert axes.shape == (2, 2)
    xs = {round(ax.get_position().x0, 3) for ax in axes.flat}
    assert len(xs) == 1  # one column
    assert matplotlib.get_backend()  # the backend is left alone
    plt.close(fig)


def _fake_entry(claims):
    def plot(data):
        fig, ax = plotting.subplots(stack=True)
        ax.plot([0, 1], [0, 1], label="CFwMD", **plotting.look("cfwmd"))
        ax.set(xlabel="x (-)", ylabel="y (-)")
        return plotting.finish(fig)

    return figures.Entry(id="book-fake", paper="book", kind="figure", caption="A fake.",
                         chapter="book/x", compute=lambda profile, seed: {"x": 1.0},
                         plot=plot, checks=lambda data: claims, status="reproduced")


def test_reproduce_shows_every_claim_and_names_the_failed_ones(monkeypatch, capsys):
    from fusioncenter import book

    claims = [figures.Claim("first holds", True, "z = 3.1"),
              figures.Claim("second <fails>", False, "value 0.5 " + "x" * 200),
              figures.Claim("third fails", False, "")]
    monkeypatch.setattr(book.figures, "get", lambda _id: _fake_entry(claims))
    with pytest.raises(AssertionError, match=r"claims failed: \['second <fails>', 'third fails'\]"):
        book.reproduce("book-fake", "fast")
    out = capsys.readouterr().out
    assert "1 of 3 claims hold" in out
    assert out.count("PASS: ") == 1 and out.count("FAIL: ") == 2
    assert max(len(line) for line in out.splitlines()) <= 96  # wrapped, nothing cut off
    html = book.evidence_html("book-fake", claims)
    assert html.count("<tr class=") == 3 and "&lt;fails&gt;" in html
    assert html.startswith('<details class="fc-evidence" open>')  # a failure is shown open
    assert 'open' not in book.evidence_html("book-fake", claims[:1]).split(">")[0]
    plt.close("all")
