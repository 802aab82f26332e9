"""Lint the chapters' code as a reader sees it: ruff over every notebook chapter's code cells.

    python tools/lint_chapters.py            # every notebook chapter of _toc.yml
    python tools/lint_chapters.py book/mo2015/trigger   # some

Each MyST chapter is converted with jupytext to a notebook in a temporary folder (named as its
source, so that ruff's messages point at ``book/...``) and checked by ruff with the rules of
``pyproject.toml`` plus ``E501`` at :data:`LINE_LENGTH` characters: a code line of a chapter
fits the page's column (77 characters at 1280 px; a line that fits is never cut at the right
edge). ``E402`` is off (a chapter imports where it needs to). Exit status: ruff's (0 clean,
1 violations), 2 for an unknown chapter.
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
from pathlib import Path

import jupytext

sys.path.insert(0, str(Path(__file__).resolve().parent))
from chapters import ROOT, notebook_chapters, source  # noqa: E402

#: The longest code line of a chapter (characters).
LINE_LENGTH = 79


def main(argv: list[str]) -> int:
    chapters = notebook_chapters()
    wanted = argv or chapters
    unknown = sorted(set(wanted) - set(chapters))
    if unknown:
        print(f"lint_chapters: not notebook chapters of _toc.yml: {unknown}", file=sys.stderr)
        return 2
    with tempfile.TemporaryDirectory(prefix="lint-chapters-") as tmp:
        files = []
        for docname in wanted:
            out = Path(tmp) / f"{docname}.ipynb"
            out.parent.mkdir(parents=True, exist_ok=True)
            jupytext.write(jupytext.read(source(docname)), out)
            files.append(str(out.relative_to(tmp)))
        cmd = [sys.executable, "-m", "ruff", "check", "--no-cache",
               "--config", str(ROOT / "pyproject.toml"),
               f"--line-length={LINE_LENGTH}", "--extend-select", "E501",
               "--extend-ignore", "E402", *files]
        return subprocess.run(cmd, cwd=tmp).returncode


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
