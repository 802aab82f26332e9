"""Guards for the nbval reference notebooks (tests/golden).

nbval silently checks nothing in a cell that was never executed, and a reference notebook that no
longer matches its chapter would check stale code. These tests make both impossible, and prove
that nbval does fail on a changed output.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import jupytext
import nbformat
import pytest
from nbval.plugin import get_sanitize_patterns

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
         "-p", "no:cacheprovider", "-p", "no:hypothesispytest", "-p", "no:anyio", str(path)],
        capture_output=True, text=True, cwd=tmp_path, timeout=300,
    )
    assert proc.returncode != 0, proc.stdout
    assert "1 failed" in proc.stdout


def _sanitized(text: str) -> str:
    patterns = get_sanitize_patterns((ROOT / "tests/golden/sanitize.cfg").read_text())
    for regex, replace in patterns:
        text = re.sub(regex, replace, text)
    return text


@pytest.mark.parametrize("a, b", [
    ("0.5547560425483333", "0.5547560425483332"),  # last digits of a repr
    ("36.57335788380344", "36.573357883804"),
    ("relative gap 3.0e-13]", "relative gap 5.1e-16]"),  # sizes of rounding errors
    ("max |diff| 4.2e-15 0.0e+00", "max |diff| 0.0e+00 -1.1e-16"),
])
def test_sanitizer_ignores_machine_rounding(a, b):
    assert _sanitized(a) == _sanitized(b)


@pytest.mark.parametrize("a, b", [
    ("rmse 0.8143", "rmse 0.8144"),  # a number printed with a fixed format
    ("0.55475604", "0.55475605"),  # 8 decimals
    ("0.5547560425483333", "0.5547561425483333"),
    ("gap 2.6e-09", "gap 7.3e-08"),  # above 1e-9: compared
    ("p 1.5e-03", "p 1.6e-03"),
])
def test_sanitizer_keeps_real_differences(a, b):
    assert _sanitized(a) != _sanitized(b)
