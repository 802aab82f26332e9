"""A notebook cell that raises must fail the book build; a passing one must not.

Builds two one-page fixture books (tests/fixtures/{failing,passing}_book: execute_notebooks:
force, raise_on_error: true) with the same strict flags as ``tools/build_book.py --strict``.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

FIXTURES = Path(__file__).resolve().parent / "fixtures"
JUPYTER_BOOK = Path(sys.executable).with_name("jupyter-book")


def build(book: str, out: Path) -> subprocess.CompletedProcess[str]:
    if not JUPYTER_BOOK.exists():
        pytest.fail(f"{JUPYTER_BOOK} not found: jupyter-book must be installed in this env")
    cmd = [str(JUPYTER_BOOK), "build", str(FIXTURES / book), "--path-output", str(out),
           "-n", "-W", "--keep-going"]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=300, cwd=out)


def test_failing_cell_fails_the_build(tmp_path: Path) -> None:
    result = build("failing_book", tmp_path)
    output = result.stdout + result.stderr
    assert result.returncode != 0, "a book whose cell raises was built successfully:\n" + output
    assert "deliberate failure" in output, output[-3000:]
    assert "RuntimeError" in output, output[-3000:]


def test_passing_cell_builds(tmp_path: Path) -> None:
    result = build("passing_book", tmp_path)
    output = result.stdout + result.stderr
    assert result.returncode == 0, output[-3000:]
    index = tmp_path / "_build" / "html" / "index.html"
    assert index.is_file(), f"no {index}:\n{output[-3000:]}"
    assert "Passing fixture" in index.read_text(encoding="utf-8")
