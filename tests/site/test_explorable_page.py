"""An explorable figure on a static page (book/_ext/explorable.py, issue 47) moves with the
keyboard, and the browser check (tools/browser_check, ``check_explorables``) sees one that
does not.

A small page, no built site: the directive's own HTML (``explorable._controls``) with three
frames drawn here, its script and stylesheet, served on loopback to the check's headless
Chromium.
"""

from __future__ import annotations

import functools
import http.server
import importlib.util
import io
import shutil
import socketserver
import sys
import threading
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
STATIC = ROOT / "book" / "_ext" / "explorable_static"

pytestmark = pytest.mark.site


def _load(name: str, path: Path):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules.setdefault(name, module)
    spec.loader.exec_module(module)
    return module


sys.path.insert(0, str(ROOT / "book" / "_ext"))
sys.path.insert(0, str(ROOT / "tools"))
import browser_check as bc  # noqa: E402
from headless import launch  # noqa: E402

explorable = _load("explorable", ROOT / "book" / "_ext" / "explorable.py")


def _png(shade: int) -> bytes:
    from PIL import Image

    buf = io.BytesIO()
    Image.new("RGB", (640, 400), (shade, shade, 255 - shade)).save(buf, "PNG")
    return buf.getvalue()


def _meta(values) -> dict:
    return {"id": "demo-explore", "label": "parameter d (units)", "start": 0,
            "print_at": [0, 2], "width_px": 640, "height_px": 400, "panels": 1, "columns": 1,
            "panel_fraction": 0.9, "min_font_pt": 10, "dpi": 100,
            "frames": [{"alt": f"d = {v}. A one-panel figure of the demo at d = {v}.",
                        "value": f"d = {v}", "facts": {"rate": f"0.{v}"}} for v in values]}


def _site(tmp: Path, values, *, script: bool = True) -> Path:
    folder = tmp / "_explore" / "demo-explore"
    folder.mkdir(parents=True)
    for i, _ in enumerate(values):
        (folder / f"{i:02d}.png").write_bytes(_png(40 * i))
    shutil.copy(STATIC / "explorable.css", tmp / "explorable.css")
    shutil.copy(STATIC / "explorable.js", tmp / "explorable.js")
    body = (f'<figure id="explore-demo-explore">'
            f'{explorable._controls("explore-demo-explore", _meta(values), "")}'
            '<figcaption>At this value the rate is <span class="fc-explore-fact" '
            'data-fact="rate">0.1</span>.</figcaption></figure>')
    js = '<script src="explorable.js"></script>' if script else ""
    (tmp / "index.html").write_text(
        '<!doctype html><html lang="en"><head><title>demo</title>'
        f'<link rel="stylesheet" href="explorable.css">{js}</head><body><main>{body}</main>'
        "</body></html>", encoding="utf-8")
    return tmp


class _Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args) -> None:
        pass


@pytest.fixture
def serve():
    from playwright.sync_api import sync_playwright

    servers = []

    def run(folder: Path):
        server = socketserver.ThreadingTCPServer(
            ("127.0.0.1", 0), functools.partial(_Quiet, directory=str(folder)))
        server.daemon_threads = True
        threading.Thread(target=server.serve_forever, daemon=True).start()
        servers.append(server)
        page = browser.new_page(viewport=bc.VIEWPORT)
        page.goto(f"http://127.0.0.1:{server.server_address[1]}/index.html", wait_until="load")
        return page

    with sync_playwright() as pw:
        browser = launch(pw)
        yield run
        browser.close()
    for server in servers:
        server.shutdown()


def test_the_arrow_key_moves_the_figure_its_value_and_its_caption(serve, tmp_path):
    page = serve(_site(tmp_path, [1, 2, 3]))
    res = bc.PageResult("index.html")
    bc.check_explorables(page, res)
    assert res.problems == [] and (res.explorables, res.explorables_moved) == (1, 1)
    page.locator("input.fc-explore-slider").focus()
    page.keyboard.press("ArrowRight")
    assert page.inner_text("output.fc-explore-value") == "d = 2"
    assert page.inner_text("figcaption") == "At this value the rate is 0.2."
    assert page.get_attribute("img.fc-explore-frame", "src").endswith("01.png")


def test_print_shows_the_small_multiples_and_no_control(serve, tmp_path):
    page = serve(_site(tmp_path, [1, 2, 3]))
    page.emulate_media(media="print")
    shown = page.evaluate("""() => ['.fc-explore-controls', 'img.fc-explore-frame',
        '.fc-explore-print'].map(s => getComputedStyle(document.querySelector(s)).display)""")
    assert shown == ["none", "none", "block"]
    assert page.locator(".fc-explore-multiple img").count() == 2


@pytest.mark.parametrize("values, script, problem", [
    ([1, 2, 3], False, "its script did not start"),
    ([1, 1, 1], True, "did not move it"),  # every frame says the same value
])
def test_the_check_sees_a_figure_that_does_not_move(serve, tmp_path, values, script, problem):
    page = serve(_site(tmp_path, values, script=script))
    res = bc.PageResult("index.html")
    bc.check_explorables(page, res)
    assert res.explorables_moved == 0
    assert any(problem in p for p in res.problems), res.problems
