"""A chapter opened in JupyterLab (Binder, ``make lab``) shows its MyST rendered, not raw.

The book's environment carries ``jupyterlab-myst`` (requirements/requirements.in, Binder's
requirements) and ``jupytext``: a chapter's ``.md`` opens as a notebook whose markdown cells are
rendered by MyST (roles such as ``{cite:t}``, directives such as ``:::{admonition}``, labels,
maths). This test starts the environment's own JupyterLab on the loopback, opens a copy of a
chapter (never the repository's file: a notebook saved by JupyterLab would rewrite its header)
with jupytext's notebook view in headless Chromium, and reads the rendered markdown cells.
"""

from __future__ import annotations

import os
import re
import secrets
import shutil
import signal
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
CHAPTER = "book/mo2015/trigger.md"  # roles, a directive, labels and maths in its first cells
pytestmark = pytest.mark.site

#: MyST that a markdown renderer without MyST shows as typed
RAW_MYST = {
    "role": re.compile(r"\{[a-z]+(?::[a-z]+)?\}`"),
    "directive": re.compile(r"^(?::::?|```)\{[a-z-]+\}", re.M),
    "label": re.compile(r"^\([A-Za-z0-9_-]+\)=\s*$", re.M),
}


def raw_myst(text: str) -> dict[str, int]:
    """How many roles, directives and labels ``text`` (rendered cells' text) shows as typed."""
    return {k: len(rx.findall(text)) for k, rx in RAW_MYST.items() if rx.findall(text)}


def test_the_detector_sees_raw_myst():
    assert raw_myst("the estimate {cite:t}`mo2015` and\n:::{admonition} Note\n(sec-x)=\n") == \
        {"role": 1, "directive": 1, "label": 1}
    assert raw_myst("the estimate of Mo (2015), a note, and a section") == {}


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _rendered_cells(tmp_path: Path) -> tuple[list[str], int, int]:
    from playwright.sync_api import TimeoutError as PlaywrightTimeout
    from playwright.sync_api import sync_playwright

    sys.path.insert(0, str(ROOT / "tools"))
    from headless import CHROMIUM, CHROMIUM_ARGS, LOOPBACK_ONLY

    lab_bin = Path(sys.executable).parent / "jupyter-lab"
    if not lab_bin.exists():
        pytest.fail(f"{lab_bin} not found: the book's environment must carry JupyterLab")
    work = tmp_path / "lab"
    (work / Path(CHAPTER).parent).mkdir(parents=True)
    shutil.copy(ROOT / CHAPTER, work / CHAPTER)
    port, token = _free_port(), secrets.token_hex(8)
    log = (tmp_path / "lab.log").open("w")
    lab = subprocess.Popen(
        [str(lab_bin), "--no-browser", f"--port={port}", "--ServerApp.ip=127.0.0.1",
         f"--IdentityProvider.token={token}", f"--ServerApp.root_dir={work}", "--allow-root",
         "--LabApp.expose_app_in_browser=True", "--ServerApp.open_browser=False"],
        stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
    try:
        deadline = time.monotonic() + 120
        while True:  # the server answers
            try:
                urllib.request.urlopen(f"http://127.0.0.1:{port}/api/status?token={token}",
                                       timeout=2).read()
                break
            except OSError:
                if time.monotonic() > deadline or lab.poll() is not None:
                    pytest.fail("JupyterLab did not start: "
                                + (tmp_path / "lab.log").read_text()[-2000:])
                time.sleep(0.5)
        with sync_playwright() as pw:
            browser = pw.chromium.launch(executable_path=CHROMIUM, headless=True,
                                         args=[*CHROMIUM_ARGS, LOOPBACK_ONLY])
            page = browser.new_page(viewport={"width": 1400, "height": 3000})
            page.goto(f"http://127.0.0.1:{port}/lab?token={token}", timeout=120_000)
            page.wait_for_function("() => window.jupyterapp && window.jupyterapp.started",
                                   timeout=120_000)
            page.evaluate("""path => window.jupyterapp.started.then(() => {
                window.jupyterapp.commands.execute('docmanager:open',
                    {path, factory: 'Jupytext Notebook'}); return 1; })""", CHAPTER)
            # MyST's rendering of a markdown cell: a .myst widget inside the cell
            try:
                page.wait_for_selector(".jp-MarkdownCell .myst", state="attached",
                                       timeout=90_000)
            except PlaywrightTimeout:
                n = page.eval_on_selector_all(".jp-MarkdownCell", "els => els.length")
                pytest.fail(f"{CHAPTER} opened with {n} markdown cells, none rendered by MyST "
                            "(is jupyterlab-myst installed and enabled?)")
            page.wait_for_timeout(3000)  # the visible cells finish rendering
            texts = page.eval_on_selector_all(".jp-MarkdownCell .myst",
                                              "els => els.map(e => e.innerText)")
            admonitions = page.eval_on_selector_all(".jp-MarkdownCell .myst .admonition, "
                                                    ".jp-MarkdownCell .myst aside",
                                                    "els => els.length")
            maths = page.eval_on_selector_all(".jp-MarkdownCell .myst .katex",
                                              "els => els.length")
            browser.close()
        return texts, admonitions, maths
    finally:
        os.killpg(lab.pid, signal.SIGTERM)
        lab.wait(timeout=30)
        log.close()


def test_a_chapter_opened_in_jupyterlab_shows_myst_rendered(tmp_path):
    texts, admonitions, maths = _rendered_cells(tmp_path)
    assert len(texts) >= 5, f"only {len(texts)} markdown cells rendered by MyST"
    source = (ROOT / CHAPTER).read_text(encoding="utf-8")
    assert raw_myst(source), "the chapter has no MyST to render: choose another"
    left = raw_myst("\n".join(texts))
    assert not left, f"MyST shown raw in JupyterLab: {left}"
    assert admonitions >= 1, "the chapter's admonition is not rendered as one"
    assert maths >= 5, f"only {maths} formulas typeset"
