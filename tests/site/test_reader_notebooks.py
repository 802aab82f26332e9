"""The notebooks the site's download button serves are ready for plain Jupyter (and Colab)."""

from __future__ import annotations

import json
import os
import re
import sys
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
