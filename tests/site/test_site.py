"""Checks of the built HTML site (``pytest -m site``).

The site is taken from ``$FUSIONCENTER_SITE`` (default: the fast profile's build,
``_build/fast/_build/html``; build it with ``python tools/build_book.py --profile fast --strict``).
A missing site is a failure, not a skip.
"""

from __future__ import annotations

import functools
import http.client
import os
import re
import shutil
import sys
import threading
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import urlsplit

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[2]
DEFAULT_SITE = ROOT / "_build" / "fast" / "_build" / "html"
MATHJAX_ENTRY = "_static/mathjax/tex-chtml.js"

pytestmark = pytest.mark.site


@pytest.fixture(scope="module")
def site() -> Path:
    path = Path(os.environ.get("FUSIONCENTER_SITE", DEFAULT_SITE))
    if not (path / "index.html").is_file():
        pytest.fail(f"built site not found at {path} (no index.html); build it with "
                    "`python tools/build_book.py --profile fast --strict` or point "
                    "FUSIONCENTER_SITE at an HTML folder")
    return path


# --------------------------------------------------------------------------------------------
# Static scan for resources fetched from outside the site.
#
# What counts as "external": a URL starting with http://, https:// or // (protocol-relative).
# Links the reader may follow (<a href>, <link rel=canonical|next|prev|...>) are fine; only
# things the browser fetches by itself while rendering a page are flagged:
#   * HTML: <script src>, <link href> with a fetching rel (stylesheet, preload, modulepreload,
#     prefetch, preconnect, dns-prefetch, icon, manifest), <img|source|video|audio|track|embed
#     |input src>, srcset, <video poster>, <object data>, <iframe|frame src>; CSS in <style>
#     blocks and style="" attributes; and inline <script> bodies (same loader patterns as .js).
#   * CSS files: url(...) and @import after removing /* comments */ (vendored CSS such as Font
#     Awesome carries licence URLs in comments, which are never fetched).
#   * JS files: only obvious loaders whose argument is a literal remote URL -- import(),
#     importScripts(), fetch(), require(), loadScript(), new Worker(), sendBeacon(),
#     xhr.open(method, url), el.src/href = url, setAttribute("src"|"href", url),
#     document.write("<script src=url...") -- plus well-known tracker hosts. A bare URL string is
#     NOT flagged: vendored bundles (MathJax, Font Awesome, the theme) are full of namespace URIs
#     (http://www.w3.org/...), licence/help links and CDN defaults behind configuration that are
#     never fetched by this site (e.g. MathJax's latest.js CDN table, speech-rule-engine's
#     default mathmaps URL, sphinx-thebe's THEBE_JS_URL, only used when thebe is launched, which
#     this book disables). What is really fetched is checked at run time by
#     test_browser_check_of_every_page, which aborts and reports every non-loopback request.
# --------------------------------------------------------------------------------------------

REMOTE = r"(?:https?:)?//[A-Za-z0-9][A-Za-z0-9.-]*\.[A-Za-z]{2,}"
Q = r"[`'\"]"
JS_LOADERS = [
    re.compile(p)
    for p in (
        rf"\b(?:import|importScripts|fetch|require|loadScript|Worker|sendBeacon)\s*\(\s*{Q}"
        + REMOTE,
        rf"\.(?:src|href)\s*=\s*{Q}" + REMOTE,
        rf"\.open\s*\(\s*{Q}[A-Za-z]+{Q}\s*,\s*{Q}" + REMOTE,
        rf"setAttribute\s*\(\s*{Q}(?:src|href){Q}\s*,\s*{Q}" + REMOTE,
        r"document\.write(?:ln)?\s*\([^)]{0,200}?<(?:script|link|img|iframe)\b[^>]{0,200}?"
        r"(?:src|href)\s*=\s*\\?['\"]?" + REMOTE,
    )
]
TRACKERS = re.compile(r"googletagmanager\.com|google-analytics\.com|plausible\.io"
                      r"|fonts\.googleapis\.com|fonts\.gstatic\.com")
CSS_COMMENT = re.compile(r"/\*.*?\*/", re.S)
CSS_URL = re.compile(r"url\(\s*(['\"]?)([^'\")]*)\1\s*\)", re.I)
CSS_IMPORT = re.compile(r"@import\s+(?:url\(\s*)?['\"]?([^'\")\s;]+)", re.I)
FETCHING_RELS = {"stylesheet", "preload", "modulepreload", "prefetch", "preconnect",
                 "dns-prefetch", "icon", "shortcut", "apple-touch-icon", "manifest"}
SRC_TAGS = {"img", "source", "video", "audio", "track", "embed", "input", "iframe", "frame",
            "script"}
JS_TYPES = {"", "text/javascript", "application/javascript", "module"}


def is_remote(url: str | None) -> bool:
    u = (url or "").strip().lower()
    return u.startswith(("http://", "https://", "//"))


def css_problems(css: str) -> list[str]:
    css = CSS_COMMENT.sub("", css)
    found = [f"CSS url({m.group(2)})" for m in CSS_URL.finditer(css) if is_remote(m.group(2))]
    found += [f"CSS @import {m.group(1)}" for m in CSS_IMPORT.finditer(css)
              if is_remote(m.group(1))]
    return found


def js_problems(js: str) -> list[str]:
    found = [f"JS loader: {m.group(0)[:120]!r}" for rx in JS_LOADERS for m in rx.finditer(js)]
    found += [f"JS tracker host: {m.group(0)}" for m in TRACKERS.finditer(js)]
    return found


class _Scanner(HTMLParser):
    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.problems: list[str] = []
        self.scripts: list[str] = []  # src of every <script src>
        self._in: str | None = None  # "style" or "script" while inside an inline block
        self._buf: list[str] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        a = {k.lower(): (v or "") for k, v in attrs}
        if "style" in a:
            self.problems += [f"<{tag} style>: {p}" for p in css_problems(a["style"])]
        if tag == "script" and "src" in a:
            self.scripts.append(a["src"])
        if tag in SRC_TAGS and is_remote(a.get("src")):
            self.problems.append(f"<{tag} src={a['src']}>")
        for attr in ("srcset", "imagesrcset"):
            for cand in a.get(attr, "").split(","):
                if cand.strip() and is_remote(cand.split()[0]):
                    self.problems.append(f"<{tag} {attr}={cand.strip()}>")
        if tag == "video" and is_remote(a.get("poster")):
            self.problems.append(f"<video poster={a['poster']}>")
        if tag == "object" and is_remote(a.get("data")):
            self.problems.append(f"<object data={a['data']}>")
        if tag == "link" and is_remote(a.get("href")):
            rels = set(a.get("rel", "").lower().split())
            if rels & FETCHING_RELS:
                self.problems.append(f"<link rel={a.get('rel')} href={a['href']}>")
        if tag == "style" or (tag == "script" and "src" not in a
                              and a.get("type", "").lower() in JS_TYPES):
            self._in, self._buf = tag, []

    def handle_data(self, data: str) -> None:
        if self._in:
            self._buf.append(data)

    def handle_endtag(self, tag: str) -> None:
        if self._in and tag == self._in:
            body = "".join(self._buf)
            if tag == "style":
                self.problems += [f"<style>: {p}" for p in css_problems(body)]
            else:
                self.problems += [f"inline <script>: {p}" for p in js_problems(body)]
            self._in = None


def scan_html(text: str) -> _Scanner:
    s = _Scanner()
    s.feed(text)
    s.close()
    return s


def test_no_external_resources(site: Path) -> None:
    problems: list[str] = []
    counts = {".html": 0, ".css": 0, ".js": 0}
    math_pages: list[Path] = []
    for path in sorted(site.rglob("*")):
        if path.suffix not in counts or not path.is_file():
            continue
        counts[path.suffix] += 1
        rel = path.relative_to(site).as_posix()
        text = path.read_text(encoding="utf-8", errors="replace")
        if path.suffix == ".css":
            found = css_problems(text)
        elif path.suffix == ".js":
            found = js_problems(text)
        else:
            scanner = scan_html(text)
            found = scanner.problems
            # The MathJax entry point of every page must be the site's own copy.
            for src in scanner.scripts:
                if "mathjax" in src.lower():
                    target = (path.parent / urlsplit(src).path).resolve()
                    if is_remote(src) or not target.is_file():
                        found.append(f"MathJax script {src} is not a file of the site")
                    elif target != (site / MATHJAX_ENTRY).resolve():
                        found.append(f"MathJax script {src} is not {MATHJAX_ENTRY}")
            if re.search(r'class="[^"]*\bmath\b', text):
                math_pages.append(path)
                if not any(urlsplit(s).path.endswith("mathjax/tex-chtml.js")
                           for s in scanner.scripts):
                    found.append(f"has math but does not load {MATHJAX_ENTRY}")
        problems += [f"{rel}: {p}" for p in found]

    assert counts[".html"] > 0, f"no HTML files under {site}"
    assert (site / MATHJAX_ENTRY).is_file(), f"{MATHJAX_ENTRY} missing from the site"
    # MathJax 4's font (book/_ext/mathjax4.py): its CHTML data and WOFF2 files, on the site
    fonts = list((site / "_static/mathjax/fonts/mathjax-newcm-font/chtml/woff2").glob("*.woff2"))
    assert fonts, "MathJax CHTML woff2 fonts missing from _static/mathjax"
    assert math_pages, "no page of the site contains math (class=\"math\")"
    if problems:
        pytest.fail("external resources referenced by the site:\n" + "\n".join(problems))


def _load_browser_check():
    sys.path.insert(0, str(ROOT / "tools"))
    import browser_check

    return browser_check


#: ``make test``: print the book's PDF there from the browser check's page loads
PDF_OUT = "FUSIONCENTER_PDF_OUT"


def test_browser_check_of_every_page(site: Path, capsys) -> None:
    browser_check = _load_browser_check()
    lines: list[str] = []
    printer = None
    if os.environ.get(PDF_OUT, "").strip():
        sys.path.insert(0, str(ROOT / "tools"))
        from pdf_book import Printer

        printer = Printer(site, Path(os.environ[PDF_OUT]))

    def log(line: str) -> None:
        print(line)
        lines.append(line)

    problems = browser_check.check_site(site, min_pages=8, min_math_pages=3, min_images=2,
                                        log=log, printer=printer)
    with capsys.disabled():  # the totals are printed whether the check passes or not
        totals = [y for x in lines if not x.startswith(("PASS ", "FAIL ", " "))
                  for y in x.splitlines()]
        print("\n" + "\n".join(f"browser check totals: {x}" for x in totals))
    if problems:
        pytest.fail("browser check found problems:\n" + "\n".join(problems))


#: a small page the browser check passes: a language, a title and an icon (``ICON``, at the root
#: of the served folder; axe-core and the favicon check ask for them)
PLAIN = ('<!doctype html><html lang="en"><head><title>{title}</title>'
         '<link rel="icon" href="/icon.svg"></head><body><main>{body}</main></body></html>')
ICON = ('<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 2 2">'
        '<circle cx="1" cy="1" r="1"/></svg>')


def test_browser_check_with_two_browsers_reports_what_one_does(tmp_path: Path) -> None:
    """The browsers that check the pages side by side (``--part`` children of
    tools/browser_check) report every page and problem that one browser reports, in the
    same order, and a child that cannot run fails the check."""
    browser_check = _load_browser_check()
    (tmp_path / "icon.svg").write_text(ICON)
    (tmp_path / "index.html").write_text(PLAIN.format(title="index", body="<p>index</p>"))
    for i in range(5):
        body = f"<p>page {i}</p>"
        if i == 1:
            body += '<img src="missing.png" alt="a figure that is not there">'
        if i == 4:
            body += '<img src="http://example.invalid/x.png" alt="from outside the site">'
        (tmp_path / f"p{i}.html").write_text(PLAIN.format(title=f"page {i}", body=body))
    found = {}
    for workers in (1, 2):
        lines: list[str] = []
        problems = browser_check.check_site(tmp_path, log=lines.append, workers=workers)
        problems = [re.sub(r"127\.0\.0\.1:\d+", "127.0.0.1:PORT", x) for x in problems]
        pages = [x.split(":")[0] for x in lines if x.startswith(("PASS ", "FAIL "))]
        found[workers] = (problems, sorted(pages), lines[-1])
    assert found[2] == found[1]
    problems, pages, last = found[1]
    assert len(pages) == 6 and last == "browser check: 4 passed, 2 failed"
    assert any("p1.html: image did not load" in x for x in problems)
    assert any("p4.html requested external URL http://example.invalid" in x for x in problems)
    # a child that cannot start its browser: the check fails and says which
    env = os.environ.copy()
    os.environ[browser_check.WORKERS_ENV] = "2"
    try:
        # the parent's browser was chosen when the module was loaded; the child's reads this
        os.environ["FUSIONCENTER_CHROMIUM"] = str(tmp_path / "no-such-browser")
        problems = browser_check.check_site(tmp_path, log=lambda _x: None)
    finally:
        os.environ.clear()
        os.environ.update(env)
    assert any(x.startswith("browser worker 2 of 2 failed") and "no-such-browser" in x
               for x in problems), problems


def test_a_page_without_an_icon_or_with_a_missing_one_fails(tmp_path):
    """Without ``<link rel="icon">`` a browser asks for /favicon.ico (a 404); an icon the site
    does not serve is the same 404. A page with a served icon passes."""
    head = '<!doctype html><html lang="en"><head><title>t</title>{link}</head>'
    body = "<body><main><p>text</p></main></body></html>"
    (tmp_path / "icon.svg").write_text('<svg xmlns="http://www.w3.org/2000/svg"/>')
    for name, link in (("index", '<link rel="icon" href="icon.svg">'), ("none", ""),
                       ("missing", '<link rel="icon" href="_static/favicon.ico">')):
        (tmp_path / f"{name}.html").write_text(head.format(link=link) + body)
    problems = _load_browser_check().check_site(tmp_path, workers=1)
    problems = [p for p in problems if p.startswith("page ")]
    assert sorted(p.split(":")[0] for p in problems) == ["page missing.html",
                                                         "page none.html"], problems
    assert any("no <link rel=\"icon\">" in p for p in problems)
    assert any("favicon.ico answered HTTP Error 404" in p for p in problems)


def test_browser_check_caches_static_files_and_still_checks_every_pages_fonts(
        site: Path, tmp_path: Path) -> None:
    """The check's server lets Chromium keep static files answered 200 (MathJax, its fonts),
    never pages or failed answers; a font taken from the cache still counts for its page, and
    a page whose font is missing still fails."""
    browser_check = _load_browser_check()
    site = site.resolve()  # the symbolic links below point at it
    page = next(p for p in sorted(site.rglob("*.html")) if "_static" not in p.parts
                and 'class="math' in p.read_text(encoding="utf-8", errors="replace"))
    # two copies of a math page at the site's depth, so that their links reach its _static
    here = tmp_path.joinpath(*page.relative_to(site).parts[:-1])
    here.mkdir(parents=True, exist_ok=True)
    top = page.relative_to(site).parts[0]
    for item in site.iterdir():  # the site's files (_static, searchindex.js...) but the pages
        if item.name not in (top, "index.html"):
            (tmp_path / item.name).symlink_to(item)
    html = page.read_text(encoding="utf-8")
    for name in ("a.html", "b.html"):
        (here / name).write_text(html, encoding="utf-8")
    (tmp_path / "index.html").write_text(PLAIN.format(title="index", body="<p>index</p>"))
    (tmp_path / "icon.svg").write_text(ICON)
    fonts = sorted(site.glob("_static/mathjax/**/*.woff*"))
    assert fonts

    served: list[tuple[str, str]] = []
    from browser_check.driver import CachingHandler as handler
    orig = handler.end_headers

    def spy(self) -> None:
        served.append((urlsplit(self.path).path, self._status))
        orig(self)

    handler.end_headers = spy
    try:
        lines: list[str] = []
        problems = browser_check.check_site(tmp_path, log=lines.append, workers=1)
    finally:
        handler.end_headers = orig
    assert not problems, problems
    counts = [int(m.group(1)) for x in lines if x.startswith("PASS ")
              for m in [re.search(r"mathjax-fonts (\d+)", x)] if m]
    assert len(counts) == 2 and min(counts) > 0, lines  # both copies' fonts counted
    woff = [p for p, _ in served if re.search(r"\.woff2?$", p)]
    assert woff and len(woff) == len(set(woff)), woff  # each font fetched once: cached
    assert sum(1 for p, _ in served if p.endswith(("/a.html", "/b.html"))) == 2

    # the headers themselves: pages and failures never kept, a static file kept
    from headless import LoopbackServer

    server = LoopbackServer(("127.0.0.1", 0), functools.partial(
        handler, directory=str(tmp_path)))
    threading.Thread(target=server.serve_forever, daemon=True).start()
    try:
        font = fonts[0].relative_to(site).as_posix()
        rel = here.relative_to(tmp_path).as_posix()
        for path, want in ((f"/{rel}/a.html".replace("//", "/"), "no-store"),
                           ("/", "no-store"), (f"/{font}", "max-age=3600"),
                           ("/_static/no-such-file.js", "no-store")):
            conn = http.client.HTTPConnection("127.0.0.1", server.server_address[1])
            conn.request("GET", path)
            resp = conn.getresponse()
            resp.read()
            conn.close()
            assert resp.getheader("Cache-Control") == want, (path, resp.status)
    finally:
        server.shutdown()
        server.server_close()

    # a page whose font file is missing still fails, though the other fonts are cached
    missing = tmp_path / "broken"
    missing.mkdir()
    for item in site.iterdir():
        if item.name not in (top, "index.html", "_static"):
            (missing / item.name).symlink_to(item)
    static = missing / "_static"
    static.mkdir()
    for item in (site / "_static").iterdir():
        if item.name != "mathjax":
            (static / item.name).symlink_to(item)
    shutil.copytree(site / "_static" / "mathjax", static / "mathjax")
    for f in (static / "mathjax").rglob("*.woff*"):
        f.unlink()
    sub = missing.joinpath(*page.relative_to(site).parts[:-1])
    sub.mkdir(parents=True, exist_ok=True)
    (sub / "c.html").write_text(html, encoding="utf-8")
    (missing / "index.html").write_text("<html><body><p>index</p></body></html>")
    problems = browser_check.check_site(missing, log=lambda _x: None, workers=1)
    assert any("MathJax font" in x or "no MathJax woff font" in x for x in problems), problems


def _toc_files(node) -> list[str]:
    files: list[str] = []
    if isinstance(node, dict):
        for key in ("root", "file"):
            if isinstance(node.get(key), str):
                files.append(node[key])
        for value in node.values():
            if isinstance(value, (dict, list)):
                files += _toc_files(value)
    elif isinstance(node, list):
        for item in node:
            files += _toc_files(item)
    return files


def test_every_toc_page_built(site: Path) -> None:
    toc = yaml.safe_load((ROOT / "_toc.yml").read_text(encoding="utf-8"))
    files = _toc_files(toc)
    assert len(files) > 1, "no file: entries found in _toc.yml"
    missing = [f for f in files
               if not (site / Path(f).with_suffix(".html")).is_file()]
    assert not missing, "pages of _toc.yml without HTML in the site: " + ", ".join(missing)


def test_execution_status_page_lists_every_notebook_chapter(site):
    """The status page (book/status.md, rendered by book/_ext/exec_status.py from the build's
    execution record) has one row per notebook chapter, and the scorecard links to it."""
    sys.path.insert(0, str(ROOT / "tools"))
    from chapters import notebook_chapters

    html = (site / "book" / "status.html").read_text(encoding="utf-8")
    assert "No execution record" not in html
    rows = re.findall(r"<tr[^>]*>(.*?)</tr>", html, flags=re.S)
    body = [r for r in rows if "<td" in r]
    assert len(body) == len(notebook_chapters())
    for doc in notebook_chapters():
        assert f'href="{doc.removeprefix("book/")}.html' in html, doc  # a link to it
    assert all(re.search(r">\s*(cache|executed|executed by nbval)\s*<", r) for r in body)
    assert "status.html" in (site / "book" / "scorecard.html").read_text(encoding="utf-8")


def test_doctrees_hold_no_other_document(site):
    """Every node of a pickled page belongs to that page's document (api_modules.rehome_nodes):
    a node pointing at another document pickles that document's settings, and with them the
    whole build environment, into the page (it did for each API page, 600 kB each)."""
    import pickle

    doctrees = site.parent / ".doctrees"
    files = sorted(doctrees.rglob("*.doctree"))
    assert len(files) > 50, f"no doctrees under {doctrees}"
    strays = {}
    for f in files:
        doctree = pickle.loads(f.read_bytes())
        n = sum(1 for node in doctree.findall()
                if vars(node).get("_document") not in (None, doctree))
        if n:
            strays[str(f.relative_to(doctrees))] = n
    assert not strays, f"nodes of another document in: {strays}"
