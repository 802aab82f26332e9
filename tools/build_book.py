"""Build the Jupyter Book site in one profile, never leaving stale notebook outputs.

    python tools/build_book.py --profile paper            # the published site: _build/html
    python tools/build_book.py --profile fast --strict    # the test build: _build/fast/_build/html
    python tools/build_book.py --profile paper --edition student  # no solutions: _build/student

jupyter-cache keys a notebook's cached outputs on its cell sources only, so a change to the
library (``src/``), to the pinned environment (``requirements/lock.txt``), to the configuration
or to the profile would otherwise leave old outputs on the site. Each output folder therefore
records a fingerprint of those inputs; when it differs, the folder's whole ``_build`` (HTML,
doctrees and the execution cache) is removed first and everything is executed again.
"""

from __future__ import annotations

import argparse
import hashlib
import os
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
OUTPUTS = {"paper": ROOT, "fast": ROOT / "_build" / "fast"}
#: The student edition (book/_ext/student_edition.py) builds apart, so it never overwrites the
#: instructor's site nor shares its execution cache key.
STUDENT_OUTPUTS = {"paper": ROOT / "_build" / "student", "fast": ROOT / "_build" / "fast-student"}
FINGERPRINT_INPUTS = ["src", "requirements/lock.txt", "pyproject.toml", "_config.yml"]


def fingerprint(profile: str, edition: str = "instructor") -> str:
    h = hashlib.sha256(f"profile={profile}\nedition={edition}\n".encode())
    for rel in FINGERPRINT_INPUTS:
        path = ROOT / rel
        files = sorted(p for p in path.rglob("*") if p.is_file()) if path.is_dir() else [path]
        for f in files:
            if "__pycache__" in f.parts or f.suffix == ".pyc" or ".egg-info" in str(f):
                continue
            h.update(str(f.relative_to(ROOT)).encode() + b"\0" + f.read_bytes() + b"\0")
    return h.hexdigest()


def prepare(out: Path, profile: str, edition: str = "instructor") -> None:
    build = out / "_build"
    stamp = build / ".fusioncenter-fingerprint"
    want = fingerprint(profile, edition)
    have = stamp.read_text().strip() if stamp.exists() else None
    if have != want:
        if build.exists():
            print(f"build_book: inputs changed since the last {profile} build; "
                  f"removing {build.relative_to(ROOT)} (HTML, doctrees, execution cache)",
                  file=sys.stderr)
            for child in build.iterdir():
                if out == ROOT and child.name in ("fast", "test-reports", "student",
                                                  "fast-student"):
                    continue  # the fast build and test reports live in the paper build's folder
                shutil.rmtree(child) if child.is_dir() else child.unlink()
    build.mkdir(parents=True, exist_ok=True)
    stamp.write_text(want + "\n")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--profile", choices=sorted(OUTPUTS), required=True)
    ap.add_argument("--strict", action="store_true",
                    help="nitpicky, warnings are errors (-n -W --keep-going)")
    ap.add_argument("--edition", choices=["instructor", "student"], default="instructor",
                    help="student: leave the exercises' solutions out (FUSIONCENTER_EDITION)")
    args = ap.parse_args(argv)

    out = (STUDENT_OUTPUTS if args.edition == "student" else OUTPUTS)[args.profile]
    prepare(out, args.profile, args.edition)
    # registry results are shared between chapters through a folder that prepare() wipes with
    # the rest of the build when the fingerprint changes
    env = dict(os.environ, FUSIONCENTER_PROFILE=args.profile, PYTHONHASHSEED="0",
               FUSIONCENTER_EDITION=args.edition,
               FUSIONCENTER_COMPUTE_CACHE=str(out / "_build" / "compute-cache"))
    jb = Path(sys.executable).with_name("jupyter-book")
    cmd = [str(jb), "build", str(ROOT), "--path-output", str(out), "--builder", "html"]
    if args.strict:
        cmd += ["-n", "-W", "--keep-going"]
    print("build_book:", " ".join(cmd), file=sys.stderr)
    rc = subprocess.call(cmd, cwd=ROOT, env=env)
    index = out / "_build" / "html" / "index.html"
    if rc != 0:
        # Force a full re-execution next time: a failed build may have cached partial state.
        (out / "_build" / ".fusioncenter-fingerprint").unlink(missing_ok=True)
        reports = out / "_build" / "html" / "reports"
        print(f"build_book: FAILED (exit {rc}); execution reports, if any: {reports}",
              file=sys.stderr)
        return rc or 1
    if not index.exists():
        print(f"build_book: FAILED: {index} was not written", file=sys.stderr)
        return 1
    print(index)
    return 0


if __name__ == "__main__":
    sys.exit(main())
