"""Run the library's tests on the other Pythons the package supports (``make test-pythons``).

    python tools/test_pythons.py [--quick] [3.12 3.13]

For each version (pyenv's ``$(pyenv root)/versions/3.1x.y``, else ``python3.1x`` on PATH): a
virtual environment in ``_build/pythons/<version>`` gets the library's wheel (built from this
repository, so the packaging is what is tested) with its dependencies at the lock's versions
(``-c requirements/lock.txt``; the dask and notebook extras too), pytest and hypothesis; then
the library's pytest runs there, from a copy of ``tests/`` outside the source tree so that
``fusioncenter`` is the installed one.
The book, nbval and site tests stay on the book's Python 3.11 (they need the pinned Jupyter Book).
``--quick`` (the ``pythons`` stage of CI's ``make test WITH="pythons student"``) leaves out
the tests marked ``heavy`` (registry entries, mpmath sweeps, worker clusters: listed in
``tests/conftest.py``), which ``make test`` runs on 3.11 with every other test; ``make
test-pythons`` runs every library test.
"""

from __future__ import annotations

import glob
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))
from site_wheel import build_wheel  # noqa: E402
from student_path import installer  # noqa: E402

VERSIONS = ["3.12", "3.13"]
# tests of the repository (its source tree, tools and structure) and of the book (Jupyter Book,
# jupytext, nbval, the built site)
NOT_LIBRARY = ["test_repository.py", "test_golden.py", "test_failing_book.py", "test_api_page.py",
               "test_interrupts.py", "test_structure.py", "test_registry_caption.py",
               "test_registry_texts.py", "test_errata_page.py",
               "test_student_path.py", "test_run_tests.py", "test_build_book_serve.py",
               "test_nbval_executed.py", "test_kernel_fork.py", "test_course_shape.py", "golden",
               "site", "test_ext_*.py"]  # test_ext_*: the book's Sphinx extensions


def interpreter(version: str) -> str | None:
    root = subprocess.run(["pyenv", "root"], capture_output=True, text=True).stdout.strip() \
        if shutil.which("pyenv") else os.path.expanduser("~/.pyenv")
    found = sorted(glob.glob(f"{root}/versions/{version}.*/bin/python"),
                   key=lambda p: [int(x) for x in Path(p).parent.parent.name.split(".")])
    return found[-1] if found else shutil.which(f"python{version}")


def main(argv: list[str] | None = None) -> int:
    args = list(argv if argv is not None else sys.argv[1:])
    quick = "--quick" in args
    versions = [a for a in args if a != "--quick"] or VERSIONS
    unknown = [a for a in versions if a.startswith("-")]
    if unknown:
        print(f"pythons: unknown option(s) {unknown}; usage: test_pythons.py [--quick] "
              "[3.12 3.13]")
        return 2
    selection = "not site and not slow" + (" and not heavy" if quick else "")
    failed = []
    with tempfile.TemporaryDirectory(prefix="fusioncenter-pythons-") as tmp:
        t0 = time.perf_counter()
        wheel = build_wheel(Path(tmp) / "dist")
        print(f"pythons: built {wheel.name} in {time.perf_counter() - t0:.1f} s", flush=True)
        tests = Path(tmp) / "tests"
        shutil.copytree(ROOT / "tests", tests,
                        ignore=shutil.ignore_patterns("__pycache__", *NOT_LIBRARY))
        shutil.copy2(ROOT / "pyproject.toml", Path(tmp) / "pyproject.toml")  # pytest settings
        for version in versions:
            py = interpreter(version)
            if py is None:
                print(f"pythons: FAILED: no Python {version} (pyenv install {version})")
                failed.append(version)
                continue
            t0 = time.perf_counter()
            venv = ROOT / "_build" / "pythons" / version
            if not (venv / "bin" / "python").exists():
                subprocess.run([py, "-m", "venv", str(venv)], check=True)
            vpy = str(venv / "bin" / "python")
            install = installer(vpy)
            subprocess.run([*install, "-c", str(ROOT / "requirements" / "lock.txt"),
                            "--force-reinstall", "--no-deps", str(wheel)], check=True)
            subprocess.run([*install, "-c", str(ROOT / "requirements" / "lock.txt"),
                            f"fusioncenter[dask,notebook] @ {wheel.as_uri()}", "pytest",
                            "hypothesis", "pyyaml"], check=True)
            t1 = time.perf_counter()
            env = {**os.environ, "FUSIONCENTER_PROFILE": "fast", "PYTHONHASHSEED": "0",
                   "MPLCONFIGDIR": str(Path(tmp) / "mplconfig"),  # this venv's font cache only
                   "PYTHONPYCACHEPREFIX": str(Path(tmp) / "pycache")}  # and bytecode
            env.pop("PYTHONPATH", None)
            rc = subprocess.call([vpy, "-m", "pytest", "-p", "no:cacheprovider", "-q",
                                  "-m", selection, str(tests)], cwd=tmp, env=env)
            where = subprocess.run([vpy, "-c", "import sys, fusioncenter; "
                                    "print(sys.version.split()[0], fusioncenter.__file__)"],
                                   capture_output=True, text=True, cwd=tmp).stdout.strip()
            print(f"pythons: {version}: {'ok' if rc == 0 else 'FAILED'} ({selection}; environment "
                  f"{t1 - t0:.0f} s, tests {time.perf_counter() - t1:.0f} s; {where})", flush=True)
            if rc != 0 or str(ROOT / "src") in where:
                failed.append(version)
    print(f"pythons: {len(versions) - len(failed)} of {len(versions)} Pythons ok"
          + (f" (failed: {', '.join(failed)})" if failed else ""))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
