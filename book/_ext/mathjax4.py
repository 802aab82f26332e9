"""MathJax 4 served from the site itself, with its own line breaking of displays.

MathJax 4 breaks a display that is wider than its column at operators and relations (the
``displayOverflow: 'linebreak'`` output option), so a display is written on one line and
breaks only where the page is narrow (a phone), never where it once had to. The site serves
its own copy: the npm packages ``mathjax`` and ``@mathjax/mathjax-newcm-font`` (Apache-2.0),
pinned by version and by the registry's sha512 integrity, are unpacked once into
``<sys.prefix>/share/fusioncenter-mathjax/<version>`` (``tools/bootstrap.sh`` does it with
``python book/_ext/mathjax4.py``; a build does it if it is missing) and copied into the built
site's ``_static/mathjax``. The page then asks no other host for anything: the font's files
are found through ``loader.paths.fonts`` (:data:`CONFIG`).

Only what a page of this book loads is kept: the TeX-to-CHTML component, its TeX extensions,
the accessibility components (the expression explorer and the speech worker with its English
and Nemeth braille rules) and the font's CHTML data and WOFF2 files.
"""

from __future__ import annotations

import base64
import hashlib
import io
import shutil
import sys
import tarfile
import urllib.request
from pathlib import Path

VERSION = "4.1.3"
#: (tarball URL, sha512 integrity as the npm registry states it, folder in the tree)
PACKAGES = (
    (f"https://registry.npmjs.org/mathjax/-/mathjax-{VERSION}.tgz",
     "sha512-BN/8Pkgn7G1pIDYJqd9md+JHsE/jydSYbyOZnSdSA0WziuVO8mRxdYiWFumkVVly/8U+hm9DpIIoWuvySverzw==",
     ""),
    (f"https://registry.npmjs.org/@mathjax/mathjax-newcm-font/-/mathjax-newcm-font-{VERSION}.tgz",
     "sha512-gzAB3dFHilHX1l5x2xUqRL+1jDQt3Fyza1DkEMVXWC4E8SvsGdlgEza47HYi2WhVcgfkvf4zgUGzuhbq3Pjlew==",
     "fonts/mathjax-newcm-font/"),
)
#: What of each package the site serves (paths inside the package, a folder ends with "/").
KEEP = {
    "": ("LICENSE", "tex-chtml.js", "a11y/", "input/tex/extensions/", "ui/",
         "sre/speech-worker.js", "sre/mathmaps/base.json", "sre/mathmaps/en.json",
         "sre/mathmaps/nemeth.json"),
    "fonts/mathjax-newcm-font/": ("LICENSE", "chtml.js", "chtml/"),
}
#: Added to ``mathjax3_config`` (Sphinx writes it as ``window.MathJax``): the font from the
#: site, displays broken to the column's width where they do not fit it, and MathJax 3's
#: accessibility by default: every formula carries hidden MathML that screen readers read.
#: MathJax 4's own speech, Braille and expression explorer (semantic enrichment) stay one
#: click away in its context menu; on by default they made a page of this book typeset in
#: 15 s instead of 2.5 s (zheng2014/nonlinear, 2 busy cores), too slow for a reader and for
#: the browser check of every page.
CONFIG = {
    "loader": {"paths": {"fonts": "[mathjax]/fonts"}},
    "output": {"displayOverflow": "linebreak", "linebreaks": {"inline": True}},
    "options": {"menuOptions": {"settings": {
        "enrich": False, "speech": False, "braille": False, "assistiveMml": True}}},
}
MARK = ".complete"


def tree(prefix: str | Path | None = None) -> Path:
    """The unpacked MathJax of this version under ``prefix`` (default ``sys.prefix``)."""
    return Path(prefix or sys.prefix) / "share" / "fusioncenter-mathjax" / VERSION


def _kept(folder: str, name: str) -> bool:
    return any(name == k or (k.endswith("/") and name.startswith(k)) for k in KEEP[folder])


def fetch(dest: Path, log=print) -> Path:
    """Download, verify and unpack the pinned packages into ``dest`` (nothing if complete).

    Raises ``RuntimeError`` naming the package when a download fails or its checksum differs."""
    if (dest / MARK).is_file():
        return dest
    part = dest.with_name(dest.name + ".part")
    shutil.rmtree(part, ignore_errors=True)
    for url, integrity, folder in PACKAGES:
        log(f"mathjax4: fetching {url}")
        try:
            with urllib.request.urlopen(url, timeout=120) as r:
                blob = r.read()
        except OSError as exc:
            raise RuntimeError(f"mathjax4: cannot download {url}: {exc}") from exc
        algo, _, want = integrity.partition("-")
        got = base64.b64encode(hashlib.new(algo, blob).digest()).decode()
        if got != want:
            raise RuntimeError(f"mathjax4: {url} does not match its {algo} integrity")
        with tarfile.open(fileobj=io.BytesIO(blob), mode="r:gz") as tar:
            for member in tar.getmembers():
                name = member.name.partition("/")[2]  # npm tarballs hold package/...
                if member.isfile() and _kept(folder, name):
                    target = part / folder / name
                    target.parent.mkdir(parents=True, exist_ok=True)
                    target.write_bytes(tar.extractfile(member).read())
    (part / MARK).write_text(VERSION + "\n")
    shutil.rmtree(dest, ignore_errors=True)
    dest.parent.mkdir(parents=True, exist_ok=True)
    part.rename(dest)
    return dest


def _merge(base: dict, extra: dict) -> dict:
    out = dict(base)
    for key, value in extra.items():
        out[key] = _merge(out.get(key) or {}, value) if isinstance(value, dict) else value
    return out


def _configure(app, config) -> None:
    config.mathjax_path = "mathjax/tex-chtml.js"
    config.mathjax3_config = _merge(config.mathjax3_config or {}, CONFIG)


def _copy(app, exc) -> None:
    if exc is not None or app.builder.format != "html":
        return
    from sphinx.util import logging
    from sphinx.util.fileutil import copy_asset

    src = fetch(tree(), log=logging.getLogger(__name__).info)
    copy_asset(str(src), str(Path(app.outdir) / "_static" / "mathjax"),
               excluded=lambda path: path.endswith(MARK))


def setup(app):
    app.connect("config-inited", _configure)
    app.connect("build-finished", _copy)
    return {"parallel_read_safe": True, "parallel_write_safe": True}


if __name__ == "__main__":
    print(fetch(tree(sys.argv[1] if len(sys.argv) > 1 else None)))
