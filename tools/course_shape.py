"""The course shape of the book's content chapters, read from their MyST sources.

A content chapter (the background, Parts I-IV and the synthesis) teaches first and checks
second (``shared/GUIDE.md`` section 3; issue 46). Read from the chapter's ``.md`` source:

- ``learn``: the box at the top says what the reader needs ("You need:" with the chapters it
  builds on, linked; the background chapter names outside prerequisites only);
- ``picture``: a numbered figure (``{book-figure}``, ``{registry-figure}`` or
  ``{explorable-figure}``) stands in the
  chapter's first ``##`` section, before any ``{prf:...}`` statement: the picture of the idea
  comes before the formulas;
- ``key ideas``: one ``## Key ideas`` section;
- ``notes``: one ``## Reproduction notes`` section, after the Key ideas and the Exercises;
  only ``## References`` may follow it;
- ``figure refs``: every numbered figure of the chapter is referred to (``{numref}``) from
  its prose, outside the figure's own caption;
- ``code``: the lines of code a reader sees unfolded before the Reproduction notes (code cells
  not tagged ``hide-input``, ``hide-cell``, ``remove-cell`` or ``remove-input``, outside the
  collapsed solutions; blank lines and cell options not counted). The median over the content
  chapters is at most :data:`MAX_MEDIAN_CODE_LINES`.

``python tools/course_shape.py [CHAPTER.md ...]`` prints one line per chapter and exits 1 when a
chapter misses a rule or the median is over its limit (all content chapters by default).
"""

from __future__ import annotations

import re
import statistics
import sys
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

#: The content chapters (issue 46): the background, Parts I-IV and the synthesis.
CONTENT_CHAPTERS = (
    "book/background/kalman-riccati",
    "book/mo2015/trigger", "book/mo2015/derivation", "book/mo2015/rate",
    "book/mo2015/conditional-mean", "book/mo2015/event-kf",
    "book/dey2009/random-riccati", "book/dey2009/scalar-bounds", "book/dey2009/vector",
    "book/dey2009/multisensor", "book/dey2009/distribution",
    "book/leong2011/steady-state", "book/leong2011/asymptotics", "book/leong2011/allocation",
    "book/leong2011/fading",
    "book/zheng2014/censoring-kl", "book/zheng2014/likelihood",
    "book/zheng2014/particle-filter", "book/zheng2014/results", "book/zheng2014/vector",
    "book/zheng2014/nonlinear", "book/zheng2014/reading",
    "book/synthesis/one-problem",
)
#: The median content chapter shows at most this many unfolded code lines before its notes.
MAX_MEDIAN_CODE_LINES = 40
FOLDED_TAGS = {"hide-input", "hide-cell", "remove-cell", "remove-input"}
FIGURE = re.compile(r"^(`{3,}|:{3,})\{(book-figure|registry-figure|explorable-figure)\}\s+(\S+)")
FENCE = re.compile(r"^(`{3,}|:{3,})(\{[^}]*\})?(.*)$")
NUMREF = re.compile(r"\{numref\}`(?:[^`<]*<)?([^`>]+)>?`")
NOTES = "Reproduction notes"
KEY_IDEAS = "Key ideas"


@dataclass
class Shape:
    """What :func:`read_shape` finds in one chapter source."""

    path: str
    h2: list[str] = field(default_factory=list)
    code_lines: int = 0
    figures: list[tuple[str, int]] = field(default_factory=list)  # (label, h2 index)
    first_prf_h2: int | None = None
    first_figure_line: int | None = None
    first_prf_line: int | None = None
    referenced: set[str] = field(default_factory=set)
    you_need: bool = False
    you_need_links: int = 0

    def problems(self) -> list[str]:
        out = []
        if not self.you_need:
            out.append("no 'You need:' prerequisites before the first section")
        elif self.you_need_links == 0 and not self.path.endswith("background/kalman-riccati.md"):
            out.append("'You need:' links no chapter")
        if not self.figures:
            out.append("no numbered figure")
        else:
            label, h2 = self.figures[0]
            if h2 != 0:
                out.append(f"the first figure ({label}) is not in the first '##' section")
            if self.first_prf_line is not None and self.first_figure_line > self.first_prf_line:
                out.append(f"the first figure ({label}) comes after a prf statement")
        if self.h2.count(KEY_IDEAS) != 1:
            out.append(f"{self.h2.count(KEY_IDEAS)} '## {KEY_IDEAS}' sections (want 1)")
        if self.h2.count(NOTES) != 1:
            out.append(f"{self.h2.count(NOTES)} '## {NOTES}' sections (want 1)")
        else:
            at = self.h2.index(NOTES)
            if KEY_IDEAS in self.h2 and self.h2.index(KEY_IDEAS) > at:
                out.append("the Key ideas come after the Reproduction notes")
            if "Exercises" in self.h2 and self.h2.index("Exercises") > at:
                out.append("the Exercises come after the Reproduction notes")
            after = [h for h in self.h2[at + 1:] if h != "References"]
            if after:
                out.append(f"sections after the Reproduction notes: {after}")
        unref = [label for label, _ in self.figures if label not in self.referenced]
        if unref:
            out.append(f"figures not referred to from the prose: {unref}")
        return out


def read_shape(path: str | Path) -> Shape:
    """Read one chapter's course shape from its MyST source (see the module docstring)."""
    path = Path(path)
    lines = path.read_text(encoding="utf-8").splitlines()
    shape = Shape(path=path.as_posix())
    in_code = False  # inside a code-cell
    code_visible = False
    fence: str | None = None  # the fence of a directive we are inside (caption, prf, ...)
    in_caption = False
    in_solution = False
    front = lines and lines[0] == "---"
    i = 0
    if front:
        i = lines.index("---", 1) + 1
    cell: list[str] = []
    while i < len(lines):
        line = lines[i]
        if in_code:
            if line.startswith("```") and line.strip("`") == "":
                if code_visible and not in_solution and NOTES not in shape.h2:
                    shape.code_lines += sum(1 for c in cell if c.strip())
                in_code, cell = False, []
            elif line.startswith(":tags:"):
                tags = set(re.findall(r"[\w-]+", line.split(":", 2)[2]))
                code_visible = not (tags & FOLDED_TAGS)
            elif not (line.startswith(":") and not cell):
                cell.append(line)
            i += 1
            continue
        if line.startswith("```{code-cell}"):
            in_code, code_visible, cell = True, True, []
            i += 1
            continue
        if line.startswith("```{solution-start}"):
            in_solution = True
        elif line.startswith("```{solution-end}"):
            in_solution = False
        m = FIGURE.match(line)
        if m:
            h2 = len(shape.h2) - 1
            # an explorable figure's label is explore-ID (fusioncenter.explore.name)
            label = ("explore-" if m.group(2) == "explorable-figure" else "") + m.group(3)
            shape.figures.append((label, h2))
            if shape.first_figure_line is None:
                shape.first_figure_line = i
            fence, in_caption = m.group(1), True
            i += 1
            continue
        if in_caption:
            if line.strip() == fence:
                in_caption, fence = False, None
            i += 1
            continue
        if re.match(r"^(`{3,}|:{3,})\{prf:", line) and shape.first_prf_line is None:
            shape.first_prf_line = i
        if line.startswith("## "):
            shape.h2.append(line[3:].strip())
        elif not shape.h2 and "You need" in line:
            shape.you_need = True
        if not shape.h2 and shape.you_need:
            shape.you_need_links += len(re.findall(r"\{doc\}`", line))
        shape.referenced.update(NUMREF.findall(line))
        i += 1
    return shape


def main(argv: list[str]) -> int:
    paths = argv or [f"{ROOT / c}.md" for c in CONTENT_CHAPTERS]
    failed = 0
    codes = []
    for p in paths:
        shape = read_shape(p)
        codes.append(shape.code_lines)
        problems = shape.problems()
        failed += bool(problems)
        rel = Path(p).resolve().relative_to(ROOT).as_posix()
        print(f"{rel}: {shape.code_lines} code lines before the notes, "
              f"{len(shape.figures)} figures; " + ("ok" if not problems else "; ".join(problems)))
    median = statistics.median(codes)
    print(f"median unfolded code lines before the notes: {median:g} "
          f"(limit {MAX_MEDIAN_CODE_LINES}); {failed} of {len(paths)} chapters miss a rule")
    return 1 if failed or (not argv and median > MAX_MEDIAN_CODE_LINES) else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
