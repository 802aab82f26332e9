"""The repository keeps its promises: the two commands, the pinned environment, the parts."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parent.parent


def _lock() -> dict[str, str]:
    pins = {}
    for line in (ROOT / "requirements/lock.txt").read_text().splitlines():
        if line and not line.startswith("#"):
            name, _, version = line.partition("==")
            assert version, f"unpinned lock line: {line!r}"
            pins[name.lower().replace("_", "-")] = version
    return pins


def test_readme_holds_the_two_commands():
    text = (ROOT / "README.md").read_text()
    assert "make book" in text and "make test" in text
    makefile = (ROOT / "Makefile").read_text()
    assert re.search(r"^book: venv$", makefile, re.M)
    assert re.search(r"^test: venv$", makefile, re.M)


def test_ci_runs_the_readme_test_command():
    ci = (ROOT / ".ci/run").read_text()
    assert "make test" in ci and "set -euo pipefail" in ci
    assert "apt-get install" in ci and "chromium" in ci


def test_ci_runs_the_other_python_and_the_students_path():
    """make test runs every test on 3.11; CI adds the stages issue 14 lets a CI-run target hold
    (the library's tests on another Python, the student's path)."""
    sys.path.insert(0, str(ROOT / "tools"))
    import run_tests

    for path in (".ci/run", ".github/workflows/book.yml"):
        lines = [ln.strip() for ln in (ROOT / path).read_text().splitlines()
                 if re.match(r"\s*make test\b", ln)]
        assert lines == ['make test WITH="pythons student"'], (path, lines)
    assert run_tests._optional(["--with", "pythons student"]) == set(run_tests.OPTIONAL)


def test_lock_pins_jupyter_book_1_and_every_extension():
    pins = _lock()
    assert pins["jupyter-book"].startswith("1.")
    for ext in ["sphinx", "sphinx-book-theme", "sphinx-proof", "sphinx-exercise",
                "sphinxcontrib-bibtex", "myst-nb", "myst-parser",
                "nbval", "jupytext", "numpy", "scipy", "sympy", "matplotlib", "filterpy", "numba",
                "playwright", "dask", "distributed"]:
        assert ext in pins, f"{ext} is not pinned in requirements/lock.txt"


def test_environment_yml_uses_python_311_and_the_same_lock():
    env = yaml.safe_load((ROOT / "environment.yml").read_text())
    deps = env["dependencies"]
    assert "python=3.11" in deps
    pip = next(d["pip"] for d in deps if isinstance(d, dict))
    assert "-r requirements/lock.txt" in pip
    # any conda package pinned explicitly must carry the lock's version
    pins = _lock()
    for d in deps:
        if isinstance(d, str) and "=" in d and not d.startswith("python="):
            name, version = d.split("=", 1)
            assert pins.get(name.lower()) == version.lstrip("="), d


def test_toc_has_the_parts_in_order():
    toc = yaml.safe_load((ROOT / "_toc.yml").read_text())
    captions = [p["caption"] for p in toc["parts"]]
    expected = ["Introduction", "Background", "Part I", "Part II", "Part III", "Part IV", "Part V",
                "Errata", "Reproduction scorecard", "Bibliography", "How to run and extend"]
    assert len(captions) == len(expected)
    for cap, want in zip(captions, expected, strict=True):
        assert cap.startswith(want), (cap, want)


def test_config_executes_strictly_and_serves_mathjax_locally():
    cfg = yaml.safe_load((ROOT / "_config.yml").read_text())
    assert cfg["execute"]["raise_on_error"] is True
    assert cfg["execute"]["allow_errors"] is False
    assert cfg["execute"]["execute_notebooks"] in ("cache", "force")
    sph = cfg["sphinx"]
    assert {"sphinx_proof", "sphinx_exercise"} <= set(sph["extra_extensions"])
    assert sph["local_extensions"]["mathjax4"] == "book/_ext"
    assert not sph["config"]["mathjax_path"].startswith(("http", "//"))


def test_mathjax_is_pinned_and_served_from_the_site(tmp_path):
    """book/_ext/mathjax4.py: MathJax 4 pinned by version and sha512, its font found on the
    site (no CDN), displays broken to the column; a tarball that does not match its integrity
    is refused."""
    sys.path.insert(0, str(ROOT / "book" / "_ext"))
    import mathjax4

    assert mathjax4.VERSION.startswith("4.")
    assert all(url.startswith("https://registry.npmjs.org/") and integ.startswith("sha512-")
               and mathjax4.VERSION in url for url, integ, _ in mathjax4.PACKAGES)
    assert mathjax4.CONFIG["loader"]["paths"]["fonts"] == "[mathjax]/fonts"
    assert mathjax4.CONFIG["output"]["displayOverflow"] == "linebreak"
    merged = mathjax4._merge({"tex": {"macros": {"E": "x"}}, "output": {"scale": 1}},
                             mathjax4.CONFIG)
    assert merged["tex"] == {"macros": {"E": "x"}} and merged["output"]["scale"] == 1
    assert mathjax4._kept("", "a11y/explorer.js") and not mathjax4._kept("", "tex-svg.js")

    bad = [(f"file://{tmp_path}/x.tgz", "sha512-AAAA", "")]
    (tmp_path / "x.tgz").write_bytes(b"not the package")
    old = mathjax4.PACKAGES
    mathjax4.PACKAGES = bad
    try:
        with pytest.raises(RuntimeError, match="integrity"):
            mathjax4.fetch(tmp_path / "tree", log=lambda *a: None)
    finally:
        mathjax4.PACKAGES = old
    assert not (tmp_path / "tree").exists()


def test_every_cited_key_is_in_the_bibliography():
    bib = (ROOT / "book/references.bib").read_text()
    keys = set(re.findall(r"^@\w+\{([^,]+),", bib, re.M))
    assert {"mo2015", "dey2009", "leong2011", "zheng2014"} <= keys
    for md in (ROOT / "book").rglob("*.md"):
        for group in re.findall(r"\{cite(?::[tp])?\}`([^`]+)`", md.read_text()):
            for key in group.split(","):
                assert key.strip() in keys, f"{md}: unknown citation {key!r}"


def test_build_fingerprint_tracks_library_and_lock(tmp_path, monkeypatch):
    import importlib.util

    spec = importlib.util.spec_from_file_location("build_book", ROOT / "tools/build_book.py")
    bb = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bb)
    (tmp_path / "src").mkdir()
    (tmp_path / "src/a.py").write_text("x = 1\n")
    for name in ("pyproject.toml", "_config.yml"):
        (tmp_path / name).write_text("")
    (tmp_path / "requirements").mkdir()
    (tmp_path / "requirements/lock.txt").write_text("numpy==2\n")
    monkeypatch.setattr(bb, "ROOT", tmp_path)
    base = bb.fingerprint("fast")
    assert bb.fingerprint("paper") != base
    (tmp_path / "src/a.py").write_text("x = 2\n")
    changed_src = bb.fingerprint("fast")
    assert changed_src != base
    (tmp_path / "requirements/lock.txt").write_text("numpy==3\n")
    assert bb.fingerprint("fast") != changed_src

    # prepare() wipes the old build (cache included) when the fingerprint changes
    out = tmp_path / "site"
    cache = out / "_build" / ".jupyter_cache"
    cache.mkdir(parents=True)
    (cache / "stale").write_text("old outputs")
    want = bb.prepare(out, "fast")
    assert not (cache / "stale").exists()
    cache.mkdir(parents=True)
    (cache / "kept").write_text("current outputs")
    bb.finish(out, want)  # the fingerprint is written only after a successful build
    bb.prepare(out, "fast")  # same inputs: the cache is kept
    assert (cache / "kept").exists()


@pytest.mark.parametrize("tool", sorted(p.stem for p in (ROOT / "tools").glob("*.py")))
def test_every_tool_imports(tool):
    """A tool's imports resolve (a stage such as tools/test_pythons.py fails in 0.1 s otherwise,
    long after the change that broke it)."""
    code = (f"import sys; sys.path.insert(0, {str(ROOT / 'tools')!r}); "
            f"sys.argv = ['{tool}']; import importlib; importlib.import_module({tool!r})")
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT,
                       timeout=120)
    assert p.returncode == 0, p.stderr[-2000:]


def test_readme_documents_every_exit_code_and_the_cache():
    """The README's exit-code table lists every code the command line uses (here, not in
    test_cli_claims.py: the 3.12 stage runs the library's tests outside the repository)."""
    from fusioncenter import cli

    text = (ROOT / "README.md").read_text()
    rows = {ln.split("|")[1].strip() for ln in text.splitlines()
            if ln.startswith("| ") and ln.split("|")[1].strip()[:1].isdigit()}
    codes = {cli.EXIT_OK, cli.EXIT_CLAIM, cli.EXIT_USAGE, cli.EXIT_RUNTIME, cli.EXIT_INTERNAL}
    assert {str(c) for c in codes} | {"130 / 143"} <= rows
    assert (cli.EXIT_INTERRUPTED, cli.EXIT_TERMINATED) == (130, 143)
    assert "FUSIONCENTER_COMPUTE_CACHE" in text and "`--csv -`" in text


#: What the other Python's venv holds (tools/test_pythons.py): the library with its ``dask`` and
#: ``notebook`` extras, pytest, hypothesis and PyYAML, besides the standard library.
PYTHONS_VENV = {"fusioncenter", "numpy", "scipy", "sympy", "matplotlib", "filterpy", "tqdm",
                "numba", "dask", "distributed", "IPython", "mpmath", "pytest", "hypothesis",
                "yaml", "_pytest"}


def test_library_tests_import_only_what_the_other_pythons_venv_holds():
    """A test copied to ``make test-pythons`` must not import a book package (pybtex, Sphinx):
    its venv holds the library alone, and collection would fail there (stop 37's CI)."""
    import ast
    import fnmatch

    sys.path.insert(0, str(ROOT / "tools"))
    from test_pythons import NOT_LIBRARY

    tests = ROOT / "tests"
    local = {p.stem for p in tests.glob("*.py")}
    wrong = []
    for path in sorted(tests.rglob("*.py")):
        parts = path.relative_to(tests).parts
        if any(fnmatch.fnmatch(part, pat) for part in parts for pat in NOT_LIBRARY):
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            names = ([a.name for a in node.names] if isinstance(node, ast.Import) else
                     [node.module] if isinstance(node, ast.ImportFrom) and node.level == 0
                     else [])
            for name in names:
                top = name.split(".")[0]
                if top not in sys.stdlib_module_names | PYTHONS_VENV | local:
                    wrong.append(f"{path.relative_to(ROOT)}:{node.lineno} imports {name}")
    assert not wrong, ("add these tests to NOT_LIBRARY in tools/test_pythons.py:\n"
                       + "\n".join(wrong))
