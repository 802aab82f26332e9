"""Open every page of the built site in headless Chromium and check that it really renders.

    python tools/browser_check _build/fast/_build/html [--min-pages 8] [--min-math-pages 3]
                                                       [--min-images 2] [--workers 2]

The command line of :mod:`browser_check` (see its docstring for the checks). Exit status 1
on any problem. With ``--part K/N`` (not for the command line) it is one of the
browsers :func:`browser_check.driver.check_site` starts side by side (:func:`run_part`).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # tools/: headless, pdf_book
from browser_check.driver import NoBrowser, browse, check_site  # noqa: E402
from browser_check.page import list_pages  # noqa: E402
from browser_check.workers import WORKERS_ENV, write_part  # noqa: E402


def run_part(html_dir: Path, part: str, base: str, out: Path, print_to: Path | None) -> int:
    """A ``--part K/N`` child: check every N-th page from the K-th (0-based) against the
    server at ``base``, print them if ``print_to`` (the book's PDF path: its pages go to
    ``out/print``), and write the findings to ``out``."""
    k, n = (int(x) for x in part.split("/"))
    html_dir = html_dir.resolve()
    pages = list_pages(html_dir)[k::n]
    printer = None
    if print_to is not None:
        from pdf_book import Printer

        printer = Printer(html_dir, print_to)
    lines: list[str] = []
    try:
        results, layouts, problems = browse(base, html_dir, pages, printer, lines.append)
    except NoBrowser as exc:
        print(exc, file=sys.stderr)
        return 1
    if printer is not None:
        printer.dump(out / "print")
    write_part(out, results, layouts, problems, lines)
    return 0


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("html_dir", type=Path)
    ap.add_argument("--min-pages", type=int, default=0)
    ap.add_argument("--min-math-pages", type=int, default=0)
    ap.add_argument("--min-images", type=int, default=0)
    ap.add_argument("--workers", type=int, default=None,
                    help=f"browsers side by side (default ${WORKERS_ENV}, else 2)")
    # a child of check_site (one browser of several): not for the command line
    ap.add_argument("--part", help=argparse.SUPPRESS)
    ap.add_argument("--base", help=argparse.SUPPRESS)
    ap.add_argument("--part-out", type=Path, help=argparse.SUPPRESS)
    ap.add_argument("--print-to", type=Path, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.part:
        return run_part(args.html_dir, args.part, args.base, args.part_out, args.print_to)
    if args.workers is not None and args.workers < 1:
        ap.error("--workers must be at least 1")
    start = time.monotonic()
    problems = check_site(args.html_dir, min_pages=args.min_pages,
                          min_math_pages=args.min_math_pages, min_images=args.min_images,
                          log=lambda m: print(m, flush=True), workers=args.workers)
    if problems and not any(p.startswith("page ") or p.startswith("only ") for p in problems):
        # Nothing was checked (no browser, no site): say so on stdout too.
        for p in problems:
            print(f"ERROR: {p}")
        print("browser check: 0 passed, 0 failed")
    print(f"({time.monotonic() - start:.1f} s)", file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
