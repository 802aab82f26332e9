"""Write the API reference's module pages and their entries in ``_toc.yml``.

The API reference is an index page (``book/api.md``: a table of every public module of
``fusioncenter`` with its one-line summary) and one page per public module under ``book/api/``
(``fusioncenter.figures.zheng2014`` is ``book/api/figures/zheng2014.md``), each a title and the
``fusioncenter-module`` directive of ``book/_ext/api_modules.py``. The book builds only the
pages its table of contents lists, so the pages are files in the repository and sections of
``book/api`` in ``_toc.yml``. Run this after adding, renaming or removing a module::

    python tools/api_pages.py          # write the pages and the toc entries
    python tools/api_pages.py --check  # exit 1 if they are out of date (tests/test_api_page.py)

A stale page (its module gone) is removed. The API entry must be the last of ``_toc.yml``: its
``sections:`` run to the end of the file.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "book" / "_ext"))
sys.path.insert(0, str(ROOT / "src"))
import api_modules  # noqa: E402

PACKAGE = "fusioncenter"
TOC_ENTRY = "      - file: book/api\n"


def wanted() -> tuple[dict[Path, str], str]:
    """The page files with their text, and the new ``_toc.yml``."""
    modules = api_modules.public_modules(PACKAGE)
    pages = {ROOT / f"{api_modules.page_docname(m)}.md": api_modules.page_text(m)
             for m in modules[1:]}
    toc = (ROOT / "_toc.yml").read_text()
    if TOC_ENTRY not in toc:
        raise SystemExit(f"api_pages: _toc.yml has no line {TOC_ENTRY.strip()!r}")
    head = toc[:toc.index(TOC_ENTRY) + len(TOC_ENTRY)]
    return pages, head + "\n".join(api_modules.toc_sections(PACKAGE)) + "\n"


def stale(pages: dict[Path, str]) -> list[Path]:
    folder = ROOT / api_modules.PAGES
    return sorted(p for p in folder.rglob("*.md") if p not in pages) if folder.is_dir() else []


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--check", action="store_true", help="report, write nothing")
    args = ap.parse_args(argv)
    pages, toc = wanted()
    changed = [p for p, text in pages.items() if not p.exists() or p.read_text() != text]
    old = stale(pages)
    toc_changed = (ROOT / "_toc.yml").read_text() != toc
    if args.check:
        for p in changed:
            print(f"api_pages: {p.relative_to(ROOT)} missing or out of date")
        for p in old:
            print(f"api_pages: {p.relative_to(ROOT)} documents no module")
        if toc_changed:
            print("api_pages: _toc.yml does not list the module pages as they are")
        if changed or old or toc_changed:
            print("api_pages: run python tools/api_pages.py")
            return 1
        return 0
    for p in changed:
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(pages[p])
    for p in old:
        p.unlink()
    for folder in sorted((ROOT / api_modules.PAGES).rglob("*"), reverse=True):
        if folder.is_dir() and not any(folder.iterdir()):
            folder.rmdir()
    if toc_changed:
        (ROOT / "_toc.yml").write_text(toc)
    print(f"api_pages: {len(pages)} pages ({len(changed)} written, {len(old)} removed), "
          f"_toc.yml {'updated' if toc_changed else 'unchanged'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
