"""make test executes each chapter once: tests/golden/conftest.py keeps nbval's executions and
tools/build_book.py (``--executed``) puts them in the site's execution cache."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import nbformat

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))
import build_book  # noqa: E402

CODE = ["x = 6 * 7",
        "from IPython.display import Markdown, display\n"
        "print('before')\ndisplay(Markdown('**shown**'))\nprint('after')",
        "x"]


def _notebook(code: list[str]) -> nbformat.NotebookNode:
    nb = nbformat.v4.new_notebook()
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3",
                                 "language": "python"}
    nb.cells = [nbformat.v4.new_markdown_cell("# A chapter")]
    nb.cells += [nbformat.v4.new_code_cell(c) for c in code]
    return nb


def test_kept_executions_are_adopted_only_for_the_same_code(tmp_path):
    golden, out = tmp_path / "golden", tmp_path / "executed"
    golden.mkdir()
    shutil.copy2(ROOT / "tests" / "golden" / "conftest.py", golden / "conftest.py")
    nbformat.write(_notebook(CODE), golden / "book__part__ok.ipynb")
    nbformat.write(_notebook(["raise ValueError('a failing cell')"]),
                   golden / "book__part__fails.ipynb")
    env = {**os.environ, "FUSIONCENTER_NBVAL_EXECUTED": str(out),
           "FUSIONCENTER_PROFILE": "fast"}
    proc = subprocess.run([sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-q",
                           "-p", "no:hypothesispytest", "-p", "no:anyio",
                           "--nbval-lax", "--nbval-current-env", str(golden)],
                          cwd=tmp_path, env=env, capture_output=True, text=True)
    assert proc.returncode == 1, proc.stdout[-2000:]  # the failing notebook fails
    assert [p.name for p in out.glob("*.ipynb")] == ["book__part__ok.ipynb"]  # only the passing

    ran = nbformat.read(out / "book__part__ok.ipynb", as_version=4)
    code = [c for c in ran.cells if c.cell_type == "code"]
    assert [c.execution_count for c in code] == [1, 2, 3]
    kinds = [(o.output_type, o.get("name") or sorted(o.get("data", {}))) for o in code[1].outputs]
    # the kernel's order (nbval's comparison merges the two prints into one stream)
    assert kinds == [("stream", "stdout"), ("display_data", ["text/markdown", "text/plain"]),
                     ("stream", "stdout")]
    assert code[2].outputs[0].data["text/plain"] == "42"
    assert ran.metadata["fusioncenter_nbval"]["profile"] == "fast"

    from jupyter_cache import get_cache

    cache = get_cache(str(tmp_path / "cache"))
    chapter = _notebook(CODE)
    chapter.cells.insert(2, nbformat.v4.new_markdown_cell("Some prose of the chapter."))
    row = build_book.adopt(cache, "book/part/ok", tmp_path / "ok.md", chapter, out, "fast")
    assert row["by"] == "nbval" and row["status"] == "ok"
    cached = cache.get_cache_bundle(cache.match_cache_notebook(_notebook(CODE)).pk).nb
    assert [len(c.outputs) for c in cached.cells if c.cell_type == "code"] == [0, 3, 1]

    other = _notebook([*CODE[:2], "x + 1"])
    assert build_book.adopt(get_cache(str(tmp_path / "c2")), "book/part/ok",
                            tmp_path / "ok.md", other, out, "fast") is None
    assert build_book.adopt(get_cache(str(tmp_path / "c3")), "book/part/ok",
                            tmp_path / "ok.md", _notebook(CODE), out, "paper") is None
    assert build_book.adopt(get_cache(str(tmp_path / "c4")), "book/part/missing",
                            tmp_path / "m.md", _notebook(CODE), out, "fast") is None
