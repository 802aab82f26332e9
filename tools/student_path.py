"""The student's path, offline: downloaded notebooks run in a fresh Python with nothing but Jupyter.

    python tools/student_path.py [--site _build/fast/_build/html] [--chapters a b c]

1. The built site is served on loopback, as it would be deployed: it carries the library's wheel
   (``_wheels/fusioncenter-<version>-py3-none-any.whl``, put there by tools/build_book.py).
2. A wheelhouse stands in for the package index, with the wheels of the library's dependencies,
   of ``[notebook]``'s and of nbclient + ipykernel for the student's Python (``pip wheel`` from
   the machine's registry or cache), but NOT the library itself.
3. A fresh virtual environment on Python 3.12 (pyenv's, or ``FUSIONCENTER_STUDENT_PYTHON``) gets
   only nbclient and ipykernel, from the wheelhouse.
4. The install cell of a download, run where neither the index nor the site can give the library,
   must stop the notebook in that cell with one message (``InstallFailed: ...``).
5. Each chapter's downloaded notebook (``<site>/_sources/<chapter>.ipynb``, what the site's
   download button serves) is copied into an empty directory outside the repository and executed
   there with nbclient, with ``PIP_NO_INDEX=1 PIP_FIND_LINKS=<wheelhouse>`` and the site's address
   (``FUSIONCENTER_BOOK_SITE``) on loopback: its first cell must install the library by itself,
   from the served site's wheel (the server's log must show the wheel fetched).

It fails on an error in any cell, on MyST markup left in a markdown cell, on a notebook whose
re-run prints a different ``profile:`` than its download, and on a library imported from
anywhere but the student's environment. It prints the time of every step.
"""

from __future__ import annotations

import argparse
import functools
import glob
import http.server
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "book" / "_ext"))
from reader_notebook import MYST_LEFTOVER  # noqa: E402

sys.path.insert(0, str(ROOT / "tools"))
from site_wheel import UV, WHEELS, wheel_name  # noqa: E402

#: One chapter per part of Parts I-III; mo2015/rate has an explorable figure (issue 47), which
#: a downloaded notebook without a kernel frontend shows as its small multiples.
DEFAULT_CHAPTERS = ["book/mo2015/rate", "book/dey2009/random-riccati",
                    "book/leong2011/steady-state"]
PROFILE = re.compile(r"^profile: (fast|paper)\b", re.M)

# Runs in the student's environment: execute one notebook with nbclient, write it back.
RUNNER = r"""
import json, sys, time
import nbclient, nbformat
path, cwd = sys.argv[1], sys.argv[2]
nb = nbformat.read(path, as_version=4)
t0 = time.perf_counter()
client = nbclient.NotebookClient(nb, timeout=1800, kernel_name="python3",
                                 resources={"metadata": {"path": cwd}})
try:
    client.execute()
    error = None
except Exception as exc:  # the error is the finding, reported by the caller
    error = f"{type(exc).__name__}: {exc}"[:4000]
nbformat.write(nb, path)
print(json.dumps({"seconds": time.perf_counter() - t0, "error": error}))
"""


def python_312() -> str:
    env = os.environ.get("FUSIONCENTER_STUDENT_PYTHON")
    if env:
        return env
    root = subprocess.run(["pyenv", "root"], capture_output=True, text=True).stdout.strip() \
        if shutil.which("pyenv") else os.path.expanduser("~/.pyenv")
    found = sorted(glob.glob(f"{root}/versions/3.12.*/bin/python"))
    if not found and shutil.which("python3.12"):
        found = [shutil.which("python3.12")]
    if not found:
        raise FileNotFoundError("no Python 3.12 (pyenv install 3.12, or set "
                                "FUSIONCENTER_STUDENT_PYTHON=/path/to/python3.12)")
    return found[-1]


def installer(vpy: str) -> list[str]:
    """The install command for the environment of ``vpy``: the book environment's uv (the same
    pins, in parallel), else that environment's pip."""
    if UV.exists():
        return [str(UV), "pip", "install", "--quiet", "--python", vpy]
    return [vpy, "-m", "pip", "install", "--quiet", "--disable-pip-version-check"]


def _step(name: str, t0: float) -> float:
    t = time.perf_counter()
    print(f"student: {name:<46} {t - t0:6.1f} s", flush=True)
    return t


def _text(cell) -> str:
    src = cell.get("source", "")
    return "".join(src) if isinstance(src, list) else src


def _profile(nb: dict) -> str | None:
    for cell in nb["cells"]:
        for o in cell.get("outputs", []):
            text = o.get("text", "")
            m = PROFILE.search("".join(text) if isinstance(text, list) else text)
            if m:
                return m[1]
    return None


def serve_site(site: Path) -> tuple[http.server.ThreadingHTTPServer, list[str]]:
    """Serve ``site`` on a free loopback port in a thread; the list collects the paths that were
    requested (and answered 200)."""
    fetched: list[str] = []

    class Handler(http.server.SimpleHTTPRequestHandler):
        def log_request(self, code="-", size="-"):
            if str(code) == "200":
                fetched.append(self.path)

        def log_message(self, *args):  # quiet
            pass

    server = http.server.ThreadingHTTPServer(
        ("127.0.0.1", 0), functools.partial(Handler, directory=str(site)))
    threading.Thread(target=server.serve_forever, daemon=True).start()
    return server, fetched


def install_failure(download: Path, vpy: str, runner: Path, work: Path, env: dict) -> list[str]:
    """Run the install cell of ``download`` followed by ``import fusioncenter`` where the library
    cannot be installed: it must stop in the install cell, with one line of error."""
    nb = json.loads(download.read_text())
    install = next(c for c in nb["cells"] if c["cell_type"] == "code")
    probe = {"cell_type": "code", "execution_count": None, "id": "probe", "metadata": {},
             "outputs": [], "source": "import fusioncenter"}
    nb["cells"] = [dict(install, outputs=[], execution_count=None), probe]
    work.mkdir()
    target = work / "install-fails.ipynb"
    target.write_text(json.dumps(nb))
    out = subprocess.run([vpy, str(runner), str(target), str(work)], cwd=work, env=env,
                         capture_output=True, text=True)
    if out.returncode != 0:
        return [f"install failure: runner failed: {out.stderr[-2000:]}"]
    cells = json.loads(target.read_text())["cells"]
    errors = [o for o in cells[0].get("outputs", []) if o.get("output_type") == "error"]
    if not errors or errors[0].get("ename") != "InstallFailed":
        return [f"install failure: the install cell did not stop with InstallFailed: {errors}"]
    shown = errors[0].get("traceback", [])
    problems = []
    if len(shown) != 1 or "PIP_NO_INDEX=1" not in shown[0] or "ERROR" not in shown[0]:
        problems.append(f"install failure: not one message saying what failed and what to do: "
                        f"{shown}")
    if cells[1].get("outputs") or cells[1].get("execution_count"):
        problems.append("install failure: the notebook went on past the install cell")
    return problems


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--site", type=Path, default=ROOT / "_build" / "fast" / "_build" / "html")
    ap.add_argument("--chapters", nargs="+", default=DEFAULT_CHAPTERS)
    ap.add_argument("--keep", action="store_true", help="keep the temporary directory")
    args = ap.parse_args(argv)

    notebooks = [args.site / "_sources" / f"{c}.ipynb" for c in args.chapters]
    missing = [str(n) for n in notebooks if not n.exists()]
    if missing:
        print(f"student: FAILED: downloaded notebooks missing (build the site first): {missing}")
        return 1
    problems: list[str] = []
    tmp = Path(tempfile.mkdtemp(prefix="fusioncenter-student-"))
    t_all = t = time.perf_counter()
    try:
        py = python_312()
        wheel = args.site / WHEELS / wheel_name()
        if not wheel.is_file():
            print(f"student: FAILED: the site carries no {WHEELS}/{wheel.name} (tools/"
                  "build_book.py puts it there: build the site again)")
            return 1
        server, fetched = serve_site(args.site)
        site_url = f"http://127.0.0.1:{server.server_address[1]}/"
        t = _step(f"site served at {site_url}", t)
        wheelhouse = tmp / "wheelhouse"
        subprocess.run([py, "-m", "pip", "wheel", "--quiet", "--disable-pip-version-check",
                        "--wheel-dir", str(wheelhouse),
                        f"fusioncenter[notebook] @ {wheel.resolve().as_uri()}", "nbclient",
                        "ipykernel"], check=True)
        for own in wheelhouse.glob("fusioncenter-*.whl"):  # the library only from the site
            own.unlink()
        t = _step(f"wheelhouse ({len(list(wheelhouse.glob('*.whl')))} wheels, no library)", t)
        venv = tmp / "student-venv"
        subprocess.run([py, "-m", "venv", str(venv)], check=True)
        vpy = str(venv / "bin" / "python")
        # the harness (nbclient and a kernel) with uv where it can be had: the student's own
        # step, the chapter's first cell, installs with the venv's pip
        subprocess.run([*installer(vpy), "--no-index", "--find-links", str(wheelhouse),
                        "nbclient", "ipykernel"], check=True)
        version = subprocess.run([vpy, "-c", "import sys; print(sys.version.split()[0])"],
                                 capture_output=True, text=True, check=True).stdout.strip()
        have = subprocess.run([vpy, "-c", "import fusioncenter"], capture_output=True,
                              env={k: v for k, v in os.environ.items()
                                   if not k.startswith("PYTHON")})
        if have.returncode == 0:
            problems.append("the fresh environment already has fusioncenter")
        t = _step(f"fresh venv, Python {version}, nbclient + ipykernel", t)
        env = {k: v for k, v in os.environ.items()
               if not k.startswith(("FUSIONCENTER_", "PIP_", "VIRTUAL_ENV", "PYTHON", "JUPYTER",
                                    "MPLBACKEND"))}
        env.update(PIP_NO_INDEX="1", PIP_FIND_LINKS=str(wheelhouse),
                   PIP_DISABLE_PIP_VERSION_CHECK="1", PATH=f"{venv / 'bin'}:{env['PATH']}",
                   PYTHONHASHSEED="0", MPLCONFIGDIR=str(tmp / "mplconfig"))  # the temporary
        # venv's font cache dies with it: never in a folder other runs read
        runner = tmp / "run_notebook.py"
        runner.write_text(RUNNER)
        # the install cell where neither the index nor the site has the library: one message
        problems += install_failure(notebooks[0], vpy, runner, tmp / "no-site",
                                    dict(env, FUSIONCENTER_BOOK_SITE=f"{site_url}nowhere/",
                                         PIP_RETRIES="1"))
        t = _step("install cell without the library: one message", t)
        env["FUSIONCENTER_BOOK_SITE"] = site_url
        for chapter, src in zip(args.chapters, notebooks, strict=True):
            nb = json.loads(src.read_text())
            for cell in nb["cells"]:
                if cell["cell_type"] == "markdown":
                    for m in MYST_LEFTOVER.finditer(_text(cell)):
                        problems.append(f"{chapter}: MyST left in a markdown cell: {m[0]!r}")
            want = _profile(nb)
            work = tmp / chapter.replace("/", "__")
            work.mkdir()
            target = work / src.name
            shutil.copy2(src, target)
            out = subprocess.run([vpy, str(runner), str(target), str(work)], cwd=work, env=env,
                                 capture_output=True, text=True)
            if out.returncode != 0:
                problems.append(f"{chapter}: runner failed: {out.stderr[-2000:]}")
                continue
            res = json.loads(out.stdout.strip().splitlines()[-1])
            if res["error"]:
                problems.append(f"{chapter}: {res['error']}")
            got = _profile(json.loads(target.read_text()))
            if got != want:
                problems.append(f"{chapter}: profile {want!r} in the download, {got!r} on re-run")
            t = _step(f"{chapter} ({res['seconds']:.1f} s, profile {got})", t)
        if f"/{WHEELS}/{wheel.name}" not in fetched:
            problems.append(f"the library was not installed from the site's {WHEELS}/ "
                            f"(requests: {sorted(set(fetched))[:10]})")
        where = subprocess.run([vpy, "-c", "import fusioncenter; print(fusioncenter.__file__)"],
                               capture_output=True, text=True, env=env, cwd=tmp)
        if not where.stdout.strip().startswith(str(venv)):
            problems.append(f"fusioncenter not installed into the student's venv: {where}")
        _step("total", t_all)
    finally:
        if "server" in locals():
            server.shutdown()
        if args.keep:
            print(f"student: kept {tmp}")
        else:
            shutil.rmtree(tmp, ignore_errors=True)
    for p in problems:
        print(f"student: FAILED: {p}")
    n = len(args.chapters)
    print(f"student: {n - len({p.split(':')[0] for p in problems if p.startswith('book/')})} "
          f"of {n} downloaded chapters ran in a fresh environment; {len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
