"""The notebooks the site's download button serves are ready for plain Jupyter (and Colab)."""

from __future__ import annotations

import json
import os
import re
import sys
from html.parser import HTMLParser
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[2]
DEFAULT_SITE = ROOT / "_build" / "fast" / "_build" / "html"
sys.path.insert(0, str(ROOT / "tools"))
sys.path.insert(0, str(ROOT / "book" / "_ext"))
import chapters  # noqa: E402
from reader_notebook import MYST_LEFTOVER  # noqa: E402

pytestmark = pytest.mark.site
CONFIG = yaml.safe_load((ROOT / "_config.yml").read_text())


@pytest.fixture(scope="module")
def site() -> Path:
    return Path(os.environ.get("FUSIONCENTER_SITE", DEFAULT_SITE))


def _text(cell) -> str:
    s = cell["source"]
    return "".join(s) if isinstance(s, list) else s


def test_every_chapter_download_is_reader_ready(site):
    expected = "paper" if site == ROOT / "_build" / "html" else None
    bad = []
    for doc in chapters.notebook_chapters():
        path = site / "_sources" / f"{doc}.ipynb"
        if not path.is_file():
            bad.append(f"{doc}: no downloadable notebook")
            continue
        nb = json.loads(path.read_text())
        cells = nb["cells"]
        profile = re.search(r"\*\*`(fast|paper)` profile\*\*", _text(cells[0]))
        if not profile:
            bad.append(f"{doc}: no profile note in the first cell")
            continue
        if expected and profile[1] != expected:
            bad.append(f"{doc}: executed in {profile[1]}")
        line = f'os.environ["FUSIONCENTER_PROFILE"] = "{profile[1]}"  # <- THE PROFILE'
        if cells[1]["cell_type"] != "code" or line not in _text(cells[1]):
            bad.append(f"{doc}: the install cell does not set the profile")
        for cell in cells:
            if cell["cell_type"] == "markdown":
                bad += [f"{doc}: {m[0]!r}" for m in MYST_LEFTOVER.finditer(_text(cell))]
        md = "\n".join(_text(c) for c in cells if c["cell_type"] == "markdown")
        source = chapters.source(doc).read_text()
        if "{cite:" in source and "## Works cited in this chapter" not in md:
            bad.append(f"{doc}: citations without a references cell")
    assert not bad, "\n".join(bad[:40])


def test_launch_buttons_point_where_students_can_open_them(site):
    cfg = yaml.safe_load((ROOT / "_config.yml").read_text())
    repo = cfg["repository"]["url"].rstrip("/")
    org_repo = repo.split("github.com/")[1]
    page = (site / "book" / "mo2015" / "trigger.html").read_text()
    assert (f"https://colab.research.google.com/github/{org_repo}/blob/notebooks/"
            "book/mo2015/trigger.ipynb") in page
    assert f"https://mybinder.org/v2/gh/{org_repo}/main?urlpath=lab/tree/book/mo2015/trigger.md" \
        in page
    assert "book.pdf" in page


class _Ids(HTMLParser):
    def __init__(self):
        super().__init__()
        self.ids: set[str] = set()

    def handle_starttag(self, tag, attrs):
        self.ids.update(v for k, v in attrs if k in ("id", "name") and v)


def dead_links(site: Path, base: str) -> tuple[int, list[str]]:
    """Every link of every downloaded notebook that points into the site (``base``...): the
    number of links, and those whose page or anchor the built site does not have."""
    ids: dict[Path, set[str]] = {}
    link = re.compile(r"\]\((" + re.escape(base) + r"[^)\s]*)\)")
    count, dead = 0, []
    for nb in sorted((site / "_sources").rglob("*.ipynb")):
        for cell in json.loads(nb.read_text())["cells"]:
            for url in link.findall(_text(cell)):
                count += 1
                path, _, anchor = url[len(base):].partition("#")
                page = site / (path or "index.html")
                where = f"{nb.relative_to(site / '_sources')}: {url}"
                if not page.is_file():
                    dead.append(f"{where} (no page)")
                    continue
                if page not in ids:
                    parser = _Ids()
                    parser.feed(page.read_text())
                    ids[page] = parser.ids
                if anchor and anchor not in ids[page]:
                    dead.append(f"{where} (no anchor)")
    return count, dead


def test_every_link_of_every_download_reaches_its_anchor(site):
    base = CONFIG["html"]["baseurl"]
    count, dead = dead_links(site, base)
    assert count > 100, f"only {count} links into the site: the pattern misses them"
    assert not dead, f"{len(dead)} of {count} links lead nowhere:\n" + "\n".join(dead[:40])


def test_the_anchor_check_sees_a_dead_anchor(site, tmp_path):
    """The check above fails on a link whose anchor the page does not have (the case sensitivity
    of `#equation-...-Zbar` was one)."""
    fake = tmp_path / "site"
    (fake / "_sources").mkdir(parents=True)
    (fake / "p.html").write_text('<p id="equation-eq-zbar">x</p>')
    base = CONFIG["html"]["baseurl"]
    cells = [{"cell_type": "markdown", "source": f"[a]({base}p.html#equation-eq-zbar) "
              f"[b]({base}p.html#equation-eq-Zbar) [c]({base}q.html)"}]
    (fake / "_sources" / "n.ipynb").write_text(json.dumps({"cells": cells}))
    count, dead = dead_links(fake, base)
    assert count == 3 and len(dead) == 2


def test_the_site_carries_the_wheel_its_downloads_install(site):
    """The install cell of every download falls back to ``<html.baseurl>_wheels/<wheel>``: the
    site has that wheel (and an index page for ``pip --find-links``), and the cell reads the
    address from _config.yml."""
    import importlib.metadata

    base = CONFIG["html"]["baseurl"]
    version = importlib.metadata.version("fusioncenter")
    wheel = site / "_wheels" / f"fusioncenter-{version}-py3-none-any.whl"
    assert wheel.is_file(), f"no {wheel}: tools/build_book.py puts it there"
    assert f'href="{wheel.name}"' in (site / "_wheels" / "index.html").read_text()
    bad = []
    for doc in chapters.notebook_chapters():
        nb = json.loads((site / "_sources" / f"{doc}.ipynb").read_text())
        cell = _text(nb["cells"][1])
        if f'"FUSIONCENTER_BOOK_SITE", "{base}")' not in cell or "InstallFailed" not in cell:
            bad.append(doc)
    assert not bad, f"install cells without the site's wheel: {bad}"
