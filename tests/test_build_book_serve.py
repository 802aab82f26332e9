"""tools/build_book.py's execution worker (``--serve``): one process executes several chapters
one after another, each in a new kernel (forked from the lane's warm process,
tools/kernel_fork.py), and answers one result line per chapter."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))
import build_book  # noqa: E402

HEADER = """---
jupytext:
  text_representation:
    extension: .md
    format_name: myst
kernelspec:
  display_name: Python 3
  language: python
  name: python3
---
"""


def _chapter(path: Path, code: str) -> Path:
    path.write_text(HEADER + "\n# A chapter\n\n```{code-cell} ipython3\n" + code + "\n```\n")
    return path


def test_one_worker_executes_chapters_in_turn_in_new_kernels(tmp_path):
    ok = _chapter(tmp_path / "ok.md",
                  "import os\nx = 6 * 7\nprint('pid', os.getpid(), x, os.getppid())")
    bad = _chapter(tmp_path / "bad.md", "raise ValueError('chapter fails')")
    again = _chapter(tmp_path / "again.md",
                     "import os\nprint('pid', os.getpid(), 'x' in dir(), os.getppid())")
    requests = "".join(json.dumps({"src": str(src), "dest": str(tmp_path / f"{src.stem}.ipynb")})
                       + "\n" for src in (ok, bad, again))
    proc = subprocess.Popen([sys.executable, str(ROOT / "tools" / "build_book.py"), "--serve"],
                            stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, cwd=tmp_path)
    stdout, stderr = proc.communicate(requests, timeout=300)
    assert proc.returncode == 0, stderr[-2000:]
    assert "no forked kernels" not in stderr
    # the kernels run on IPC sockets (kernel_fork.LOCAL_KERNELS): no warning about plain TCP
    assert "without encryption" not in stderr
    results = [json.loads(line[len(build_book.RESULT):]) for line in stdout.splitlines()
               if line.startswith(build_book.RESULT)]
    assert [r["error"] for r in results] == [None, "CellExecutionError", None]
    assert "chapter fails" in results[1]["traceback"]
    assert all(r["seconds"] > 0 for r in (results[0], results[2]))

    def printed(name: str) -> str:
        nb = json.loads((tmp_path / name).read_text())
        texts = [o.get("text", "") for c in nb["cells"] if c["cell_type"] == "code"
                 for o in c.get("outputs", [])]
        return "".join("".join(t) if isinstance(t, list) else t for t in texts)

    first, third = printed("ok.ipynb").split(), printed("again.ipynb").split()
    assert first[2] == "42"
    assert third[2] == "False"  # a new kernel: nothing of the first chapter is left
    assert first[1] != third[1]  # ... in another process
    # both forked from the lane's one warm process (a kernel started as a new process is a
    # child of the lane itself, through jupyter_client)
    assert first[3] == third[3] != str(proc.pid)


def test_a_kernel_that_died_at_start_is_retried_and_a_chapter_error_is_not(tmp_path, monkeypatch):
    """A kernel that never answered (a lost race for a port) is started again; an error of the
    chapter itself, or a kernel that died after running cells, is reported, never retried."""
    import nbformat
    from jupyter_cache.executors import utils

    src = _chapter(tmp_path / "c.md", "x = 1")
    calls: list[int] = []

    def fake(nb, *, fail, ran=False, raises=False, **_):
        calls.append(1)
        if ran:
            next(c for c in nb.cells if c.cell_type == "code")["execution_count"] = 1
        err = fail(len(calls))
        if raises and err is not None:  # as jupyter-cache does when the kernel's start fails
            raise err
        return utils.ExecutionResult(nb, str(tmp_path), 0.1, err, err and repr(err))

    died = RuntimeError("Kernel died before replying to kernel_info")
    retries = build_book.KERNEL_START_RETRIES
    cases = [  # (what the n-th execution fails with, has a cell run, executions expected)
        (lambda n: died if n == 1 else None, False, 2),
        (lambda n: died, False, 1 + retries),
        (lambda n: died, True, 1),
        (lambda n: ValueError("chapter fails"), False, 1),
    ]
    for raises in (False, True):
        for fail, ran, expected in cases:
            calls.clear()
            monkeypatch.setattr(utils, "single_nb_execution",
                                lambda nb, fail=fail, ran=ran, raises=raises, **kw:
                                fake(nb, fail=fail, ran=ran, raises=raises))
            dest = tmp_path / "c.ipynb"
            dest.unlink(missing_ok=True)
            err = fail(expected)
            if raises and err is not None:  # the last failure reaches the lane (_serve_lines)
                with pytest.raises(type(err)):
                    build_book.execute_one(src, dest)
                assert len(calls) == expected
                continue
            info = build_book.execute_one(src, dest)
            assert len(calls) == expected
            assert nbformat.read(dest, as_version=4).cells
            assert (info["error"] is None) == (err is None)
