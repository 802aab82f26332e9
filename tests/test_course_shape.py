"""Every content chapter has the course shape (issue 46; ``tools/course_shape.py``).

A chapter teaches first and checks second: prerequisites, a picture of the idea before the
formulas, Key ideas, exercises, and last the Reproduction notes, which hold the audit. The
checker reads the MyST sources; the browser check measures the same code lines on the built
pages (``tools/browser_check``, ``check_reading``).
"""

from __future__ import annotations

import statistics
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))
import course_shape  # noqa: E402
from chapters import notebook_chapters  # noqa: E402

GOOD = """\
---
jupytext:
  formats: md:myst
kernelspec:
  name: python3
---

# A chapter

:::{admonition} What you will learn
* one thing
**You need:** {doc}`the background </book/background/kalman-riccati>`.
:::

Why it matters.

## The idea in one picture

```{code-cell} ipython3
:tags: [hide-input]

# draws the idea
draw()
```

```{book-figure} fig-x-idea
A picture. {numref}`fig-x-idea` inside its own caption does not count.
```

{numref}`fig-x-idea` shows the idea.

## The argument

```{prf:theorem} A result
:label: thm-x
```

```{code-cell} ipython3
x = 1
y = 2
```

## Key ideas

* One.

## Exercises

```{solution-start} ex-x
:class: dropdown
```

```{code-cell} ipython3
not_counted = 1
```

```{solution-end}
```

## Reproduction notes

```{code-cell} ipython3
assert x == 1
assert y == 2
```

## References
"""


def shape_of(tmp_path: Path, text: str) -> course_shape.Shape:
    path = tmp_path / "chapter.md"
    path.write_text(text, encoding="utf-8")
    return course_shape.read_shape(path)


def test_the_content_chapters_are_notebook_chapters_of_the_toc():
    assert set(course_shape.CONTENT_CHAPTERS) <= set(notebook_chapters())
    assert len(course_shape.CONTENT_CHAPTERS) == 23


@pytest.mark.parametrize("docname", course_shape.CONTENT_CHAPTERS)
def test_chapter_has_the_course_shape(docname):
    shape = course_shape.read_shape(ROOT / f"{docname}.md")
    assert shape.problems() == []


def test_median_unfolded_code_before_the_notes():
    lines = {d: course_shape.read_shape(ROOT / f"{d}.md").code_lines
             for d in course_shape.CONTENT_CHAPTERS}
    assert statistics.median(lines.values()) <= course_shape.MAX_MEDIAN_CODE_LINES, lines


def test_the_checker_passes_a_chapter_of_the_right_shape(tmp_path):
    shape = shape_of(tmp_path, GOOD)
    assert shape.problems() == []
    # the two visible lines of the argument; the folded figure cell, the solution and the
    # notes do not count
    assert shape.code_lines == 2


@pytest.mark.parametrize("change, problem", [
    (("**You need:** {doc}`the background </book/background/kalman-riccati>`.\n", ""),
     "no 'You need:'"),
    (("{doc}`the background </book/background/kalman-riccati>`", "linear algebra"),
     "links no chapter"),
    (("## The idea in one picture\n", "## The idea in one picture\n\n## Another\n"),
     "not in the first '##' section"),
    (("## Key ideas\n", "## Summary\n"), "0 '## Key ideas'"),
    (("## Reproduction notes\n", "## Checks\n"), "0 '## Reproduction notes'"),
    (("## References\n", "## References\n\n## Key ideas again\n"), "after the Reproduction"),
    (("{numref}`fig-x-idea` shows the idea.", "The figure shows the idea."),
     "not referred to"),
])
def test_the_checker_finds_each_missing_piece(tmp_path, change, problem):
    old, new = change
    assert old in GOOD
    problems = shape_of(tmp_path, GOOD.replace(old, new, 1)).problems()
    assert any(problem in p for p in problems), problems


def test_a_figure_after_a_statement_is_found(tmp_path):
    text = GOOD.replace("## The idea in one picture\n",
                        "## The idea in one picture\n\n```{prf:lemma} Early\n```\n")
    assert any("after a prf statement" in p for p in shape_of(tmp_path, text).problems())


def test_visible_code_counts_until_the_notes(tmp_path):
    text = GOOD.replace("x = 1\ny = 2\n", "x = 1\ny = 2\n\nz = 3\n")
    assert shape_of(tmp_path, text).code_lines == 3
    folded = GOOD.replace("```{code-cell} ipython3\nx = 1",
                          "```{code-cell} ipython3\n:tags: [hide-input]\n\nx = 1")
    assert shape_of(tmp_path, folded).code_lines == 0


def test_the_front_page_has_the_reading_paths():
    """A course path and a researcher's path, and every content chapter placed on the first
    (in its table of weeks, or among the extensions that follow it)."""
    import re

    text = (ROOT / "book" / "intro.md").read_text(encoding="utf-8")
    assert "(sec-path-course)=" in text and "(sec-path-research)=" in text
    course = text[text.index("(sec-path-course)="):text.index("(sec-path-research)=")]
    linked = {"book/" + t for t in re.findall(r"\{doc\}`[^`<]*<([^>]+)>`", course)}
    assert set(course_shape.CONTENT_CHAPTERS) <= linked, \
        sorted(set(course_shape.CONTENT_CHAPTERS) - linked)
    research = text[text.index("(sec-path-research)="):]
    for page in ("scorecard", "errata", "figure-index", "howto"):
        assert f"<{page}>`" in research, page


def test_an_explorable_figure_is_referred_to_by_its_label(tmp_path):
    extra = "\n```{explorable-figure} mo2015-explore\nA slider.\n```\n\n"
    text = GOOD.replace("## Key ideas\n", extra + "## Key ideas\n")
    assert any("explore-mo2015-explore" in p for p in shape_of(tmp_path, text).problems())
    text = text.replace("A slider.\n```\n", "A slider.\n```\n\n{numref}`explore-mo2015-explore`"
                                            " moves.\n")
    assert shape_of(tmp_path, text).problems() == []
