"""Regenerate the executed reference notebooks that nbval checks (``make golden``).

For every notebook chapter of ``_toc.yml``: convert the MyST source with jupytext, execute it in
the ``fast`` profile from the chapter's own folder, drop image outputs (nbval does not compare
them, and they would bloat the repository), and write ``tests/golden/<docname>.ipynb``. Golden
files of chapters that left the table of contents are removed.

    python tools/make_golden.py            # all chapters
    python tools/make_golden.py book/background/kalman-riccati   # some
"""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

import jupytext
import nbformat
from nbclient import NotebookClient

sys.path.insert(0, str(Path(__file__).resolve().parent))
from chapters import GOLDEN, ROOT, golden_path, notebook_chapters, source  # noqa: E402
from kernel_fork import local_kernel_config  # noqa: E402

DROP_MIME = ("image/png", "image/jpeg", "image/svg+xml", "application/pdf")


def strip(nb: nbformat.NotebookNode) -> nbformat.NotebookNode:
    for cell in nb.cells:
        cell.metadata.pop("execution", None)
        if cell.cell_type != "code":
            continue
        kept = []
        for out in cell.get("outputs", []):
            if "data" in out:
                for mime in DROP_MIME:
                    out["data"].pop(mime, None)
                if not out["data"]:
                    continue
                out.get("metadata", {}).clear()
            kept.append(out)
        cell["outputs"] = kept
    nb.metadata.pop("widgets", None)
    return nb


def build(docname: str) -> Path:
    src = source(docname)
    nb = jupytext.read(src)
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3",
                                 "language": "python"}
    env_before = os.environ.get("FUSIONCENTER_PROFILE")
    os.environ["FUSIONCENTER_PROFILE"] = "fast"
    os.environ["FUSIONCENTER_STATIC_FIGURES"] = "1"  # the site's outputs (fusioncenter.explore)
    try:
        # the kernel on IPC sockets, not loopback TCP (tools/kernel_fork.py, LOCAL_KERNELS)
        NotebookClient(nb, timeout=1800, kernel_name="python3", config=local_kernel_config(),
                       resources={"metadata": {"path": str(src.parent)}}).execute()
    finally:
        if env_before is None:
            os.environ.pop("FUSIONCENTER_PROFILE", None)
        else:
            os.environ["FUSIONCENTER_PROFILE"] = env_before
    out = golden_path(docname)
    out.parent.mkdir(parents=True, exist_ok=True)
    nbformat.write(strip(nb), out)
    return out


def main(argv: list[str]) -> int:
    chapters = notebook_chapters()
    wanted = argv or chapters
    unknown = sorted(set(wanted) - set(chapters))
    if unknown:
        print(f"make_golden: not notebook chapters of _toc.yml: {unknown}", file=sys.stderr)
        return 2
    for docname in wanted:
        t0 = time.perf_counter()
        out = build(docname)
        print(f"make_golden: {out.relative_to(ROOT)} ({time.perf_counter() - t0:.1f} s)")
    if not argv:
        keep = {golden_path(d) for d in chapters}
        for stale in GOLDEN.glob("*.ipynb"):
            if stale not in keep:
                stale.unlink()
                print(f"make_golden: removed {stale.relative_to(ROOT)} (no longer a chapter)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
