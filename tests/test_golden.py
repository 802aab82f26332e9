"""Guards for the nbval reference notebooks (tests/golden).

nbval silently checks nothing in a cell that was never executed, and a reference notebook that no
longer matches its chapter would check stale code. These tests make both impossible, and prove
that nbval does fail on a changed output.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import jupytext
import nbformat
import pytest

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))
from chapters import GOLDEN, golden_path, notebook_chapters, source  # noqa: E402

CHAPTERS = notebook_chapters()


def _code_cells(nb):
    return [c for c in nb.cells if c.cell_type == "code"]


def test_there_are_notebook_chapters():
    assert "book/background/kalman-riccati" in CHAPTERS
    assert len(CHAPTERS) >= 6


def test_no_stray_golden_files():
    expected = {golden_path(d) for d in CHAPTERS}
    present = set(GOLDEN.glob("*.ipynb"))
    assert present == expected, "run `make golden`: golden files and chapters differ"


@pytest.mark.parametrize("docname", CHAPTERS)
def test_golden_matches_chapter(docname):
    gold_path = golden_path(docname)
    assert gold_path.exists(), f"{gold_path} missing: run `make golden`"
    gold = nbformat.read(gold_path, as_version=4)
    chapter = jupytext.read(source(docname))
    g_cells, c_cells = _code_cells(gold), _code_cells(chapter)
    assert [c.source for c in g_cells] == [c.source for c in c_cells], (
        f"{gold_path.name}: code differs from {docname}: run `make golden`"
    )
    assert [c.metadata.get("tags", []) for c in g_cells] == [
        c.metadata.get("tags", []) for c in c_cells
    ]


@pytest.mark.parametrize("docname", CHAPTERS)
def test_golden_fully_executed(docname):
    gold = nbformat.read(golden_path(docname), as_version=4)
    cells = _code_cells(gold)
    assert cells, f"{docname} has no code cells"
    counts = [c.get("execution_count") for c in cells]
    assert all(isinstance(n, int) for n in counts), f"unexecuted cells in {docname}: {counts}"
    assert counts == list(range(1, len(cells) + 1)), f"{docname}: not run top to bottom: {counts}"
    for c in cells:
        for out in c.outputs:
            assert out.output_type != "error", f"{docname}: error output stored"
            assert "image/png" not in out.get("data", {}), f"{docname}: image stored in golden"


def test_nbval_fails_on_a_changed_output(tmp_path):
    """Tamper with one stored output and check that strict nbval reports it."""
    nb = nbformat.v4.new_notebook()
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3",
                                 "language": "python"}
    cell = nbformat.v4.new_code_cell("print(6 * 7)")
    cell.execution_count = 1
    cell.outputs = [nbformat.v4.new_output("stream", name="stdout", text="41\n")]
    nb.cells = [cell]
    path = tmp_path / "tampered.ipynb"
    nbformat.write(nb, path)
    proc = subprocess.run(
        [sys.executable, "-m", "pytest", "--nbval", "--nbval-current-env", "-q",
         "-p", "no:cacheprovider", str(path)],
        capture_output=True, text=True, cwd=tmp_path, timeout=300,
    )
    assert proc.returncode != 0, proc.stdout
    assert "1 failed" in proc.stdout
