"""The record of one page's checks (:class:`PageResult`), which every detector adds to."""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass
class PageResult:
    """What the checks found on one page: the record every detector of a page writes to.

    Attributes
    ----------
    path : str
        The page, relative to the site's folder.
    problems : list of str
        Every problem found on it.
    math_expected, math_typeset : int
        Math elements in the served HTML, and those MathJax typeset.
    images, images_ok : int
        Images on the page, and those that loaded.
    fonts_loaded : int
        MathJax woff fonts loaded from the site.
    failed_urls : list of str
        Requests that failed or answered HTTP >= 400.
    explorables, explorables_moved : int
        Explorable figures on the page, and those whose slider moved them.
    """

    path: str
    problems: list[str] = field(default_factory=list)
    math_expected: int = 0
    math_typeset: int = 0
    images: int = 0
    images_ok: int = 0
    fonts_loaded: int = 0
    failed_urls: list[str] = field(default_factory=list)
    explorables: int = 0
    explorables_moved: int = 0

    @property
    def ok(self) -> bool:
        return not self.problems

    def line(self) -> str:
        status = "PASS" if self.ok else "FAIL"
        math = f"math {self.math_typeset}/{self.math_expected}" if self.math_expected else "math -"
        fonts = f" mathjax-fonts {self.fonts_loaded}" if self.math_expected else ""
        moved = (f", explorable figures moved {self.explorables_moved}/{self.explorables}"
                 if self.explorables else "")
        return (f"{status} {self.path}: {math}, images {self.images_ok}/{self.images}{fonts}"
                f"{moved}")
