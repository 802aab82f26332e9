"""The library's wheel, built from this repository, and the copy the site carries.

``build_wheel`` builds ``fusioncenter-<version>-py3-none-any.whl`` through an sdist (so the
source tree stays clean), with the book environment's uv for the isolated build environment
where it has one. ``publish`` puts a wheel under a built site as
``_wheels/fusioncenter-<version>-py3-none-any.whl`` with an ``index.html`` listing it: the
stable address the install cell of every downloaded notebook falls back to
(``<html.baseurl>_wheels/...``, book/_ext/reader_notebook.py), and a folder
``pip --find-links <site>/_wheels/`` can read.
"""

from __future__ import annotations

import html
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
#: The book environment's uv (installed by tools/bootstrap.sh), where it could be had.
UV = Path(sys.executable).parent / "uv"
#: The folder of the site that holds the wheel.
WHEELS = "_wheels"


def version() -> str:
    """The library's version, read from its source (not from an installed copy)."""
    init = (ROOT / "src" / "fusioncenter" / "__init__.py").read_text()
    for line in init.splitlines():
        if line.startswith("__version__"):
            return line.split("=", 1)[1].strip().strip("\"'")
    raise ValueError("src/fusioncenter/__init__.py sets no __version__")


def wheel_name(ver: str | None = None) -> str:
    return f"fusioncenter-{ver or version()}-py3-none-any.whl"


def build_wheel(outdir: Path, run=None) -> Path:
    """Build the library's wheel into ``outdir`` (via an sdist) and return its path.

    ``run(name, cmd, **kw) -> exit code`` runs the build (tools/procs.py's ``run``, which an
    interrupt stops with the build's other stages); default: :func:`subprocess.run`."""
    outdir.mkdir(parents=True, exist_ok=True)
    # the isolated build environments with the book environment's uv when it has one (4.3 s
    # against 7.3 s with pip's); the wheel is the same
    uv = ["--installer", "uv"] if UV.exists() else []
    cmd = [sys.executable, "-m", "build", *uv, "--outdir", str(outdir), str(ROOT)]
    if run is None:
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    else:
        rc = run("wheel", cmd, stdout=subprocess.DEVNULL)
        if rc != 0:
            raise subprocess.CalledProcessError(rc, cmd)
    wheel = outdir / wheel_name()
    if not wheel.exists():
        raise FileNotFoundError(f"build did not write {wheel}")
    return wheel


def publish(wheel: Path, site: Path) -> Path:
    """Copy ``wheel`` to ``<site>/_wheels/`` with an index page; return the copy's path."""
    folder = site / WHEELS
    folder.mkdir(parents=True, exist_ok=True)
    target = folder / wheel.name
    shutil.copy2(wheel, target)
    links = "\n".join(f'<a href="{html.escape(w.name)}">{html.escape(w.name)}</a><br>'
                      for w in sorted(folder.glob("*.whl")))
    (folder / "index.html").write_text(
        "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>fusioncenter wheels"
        f"</title></head>\n<body>\n{links}\n</body></html>\n")
    return target
