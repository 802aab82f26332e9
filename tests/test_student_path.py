"""A chapter runs where the student is: the package, the first cell, Binder, the reader notebook."""

from __future__ import annotations

import json
import re
import sys
import tomllib
from pathlib import Path

import jupytext
import pytest
import yaml

import fusioncenter
from fusioncenter import glue as fc_glue

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))
sys.path.insert(0, str(ROOT / "book" / "_ext"))
import chapters  # noqa: E402
from reader_notebook import Link, Resolver, install_cell, reader_notebook  # noqa: E402

PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())
CONFIG = yaml.safe_load((ROOT / "_config.yml").read_text())


def _lock() -> dict[str, str]:
    pins = {}
    for line in (ROOT / "requirements" / "lock.txt").read_text().splitlines():
        if line and not line.startswith("#"):
            name, _, version = line.partition("==")
            pins[name.lower().replace("_", "-")] = version
    return pins


def _first_cells() -> dict[str, jupytext.jupytext.NotebookNode]:
    return {d: jupytext.read(chapters.source(d)).cells[0] for d in chapters.notebook_chapters()}


def test_every_chapter_starts_with_the_same_hidden_install_cell():
    cells = _first_cells()
    assert len(cells) >= 20
    sources = {c.source for c in cells.values()}
    assert len(sources) == 1, "the first cells differ between chapters"
    for doc, cell in cells.items():
        assert cell.cell_type == "code", doc
        assert cell.metadata.get("tags") == ["remove-cell"], doc
    src = sources.pop()
    assert '%pip install --quiet "fusioncenter[notebook]=={BOOK_VERSION}"' in src
    assert re.search(r'^os\.environ\.setdefault\("FUSIONCENTER_PROFILE", "fast"\)', src, re.M)
    version = re.search(r'^BOOK_VERSION = "([^"]+)"$', src, re.M)[1]
    assert version == fusioncenter.__version__ == _installed_version()


def _installed_version() -> str:
    import importlib.metadata

    return importlib.metadata.version("fusioncenter")


def test_install_cell_does_nothing_where_the_library_is_installed(monkeypatch):
    """The cell's Python with the magic replaced: here (editable install) it installs nothing."""
    src = next(iter(_first_cells().values())).source
    calls = []
    code = src.replace('%pip install --quiet "fusioncenter[notebook]=={BOOK_VERSION}"',
                       "calls.append(BOOK_VERSION)")
    monkeypatch.setenv("FUSIONCENTER_PROFILE", "paper")
    exec(compile(code, "install-cell", "exec"), {"calls": calls})
    assert calls == []
    import os

    assert os.environ["FUSIONCENTER_PROFILE"] == "paper"  # setdefault: the build's profile wins
    code_missing = code.replace('importlib.metadata.version("fusioncenter")',
                                'importlib.metadata.version("fusioncenter-not-installed")')
    exec(compile(code_missing, "install-cell", "exec"), {"calls": calls})
    assert calls == [fusioncenter.__version__]


def test_chapters_take_glue_from_the_library():
    for doc in chapters.notebook_chapters():
        text = chapters.source(doc).read_text()
        assert "from myst_nb import" not in text, doc


def test_package_metadata_is_complete_and_any_python_from_311():
    p = PYPROJECT["project"]
    assert p["requires-python"] == ">=3.11"
    assert p["dynamic"] == ["version"] and p["license"] == "MIT" and p["readme"] == "README.md"
    assert (ROOT / "LICENSE").exists()
    for v in ("3.11", "3.12", "3.13"):
        assert f"Programming Language :: Python :: {v}" in p["classifiers"]
    _notebook_extra_fits_a_jupyter_kernel(p["optional-dependencies"]["notebook"])
    wanted = (ROOT / "requirements" / "requirements.in").read_text().split()
    for tool in ("build", "twine", "pypdf"):
        assert tool in _lock(), f"{tool} is not pinned in requirements/lock.txt"
        assert tool in wanted, f"{tool} is not in requirements/requirements.in (make lock drops it)"


#: What a Jupyter kernel brings (ipykernel and IPython): Colab pins IPython 7.34.0
#: (google-colab 1.0.0 requires ipython==7.34.0), so the extra must accept it.
COLAB_IPYTHON = "7.34.0"


def _notebook_extra_fits_a_jupyter_kernel(extra: list[str]) -> None:
    """The extra ``[notebook]`` keeps Colab's IPython and names only modules the chapters (or
    the library's notebook helpers) import."""
    from packaging.requirements import Requirement

    imported = set()
    texts = [chapters.source(d).read_text() for d in chapters.notebook_chapters()]
    texts += [(ROOT / "src" / "fusioncenter" / f).read_text() for f in ("book.py", "glue.py")]
    for text in texts:
        imported |= {m.split(".")[0].lower()
                     for m in re.findall(r"^\s*(?:from|import) ([A-Za-z_][\w.]*)", text, re.M)}
    for line in extra:
        req = Requirement(line)
        assert req.name.lower() in imported, (
            f"[notebook] requires {req.name}, which no chapter imports")
        if req.name.lower() == "ipython":
            assert req.specifier.contains(COLAB_IPYTHON), (
                f"[notebook] requires {req} and would replace Colab's IPython {COLAB_IPYTHON}")
    assert "ipykernel" not in {Requirement(x).name.lower() for x in extra}, (
        "[notebook]: a Jupyter kernel brings ipykernel")


def test_notebook_extra_check_rejects_what_colab_cannot_keep():
    """The check above fails on the extra that replaced Colab's IPython, and on a module the
    chapters do not import."""
    with pytest.raises(AssertionError, match="Colab"):
        _notebook_extra_fits_a_jupyter_kernel(["ipython>=8", "mpmath>=1.3"])
    with pytest.raises(AssertionError, match="no chapter imports"):
        _notebook_extra_fits_a_jupyter_kernel(["pandas>=2"])


#: Files that may write the public addresses: _config.yml sets them; a package's metadata
#: (pyproject.toml) cannot read _config.yml, so it repeats them and the test below checks it.
ADDRESS_FILES = {"_config.yml", "pyproject.toml"}
TEXT_SUFFIXES = {".py", ".md", ".toml", ".yml", ".yaml", ".txt", ".json", ".sh", ".cfg", ".cff",
                 ".in", ".js", ".css", ".html", ""}


def _files_writing(needles: list[str]) -> dict[str, list[str]]:
    found: dict[str, list[str]] = {}
    skip = {".git", "_build", ".venv", "golden", "__pycache__", ".pytest_cache", ".ruff_cache",
            ".hypothesis", "node_modules"}
    for path in ROOT.rglob("*"):
        rel = path.relative_to(ROOT)
        if (skip & set(rel.parts) or any(x.endswith(".egg-info") for x in rel.parts)
                or not path.is_file() or path.suffix not in TEXT_SUFFIXES):
            continue
        try:
            text = path.read_text()
        except (UnicodeDecodeError, OSError):
            continue
        hits = [n for n in needles if n in text]
        if hits:
            found[rel.as_posix()] = hits
    return found


def test_public_addresses_are_written_only_in_config():
    """The site's and the repository's addresses are written in _config.yml alone; every
    consumer (the downloaded notebooks' links and install cell, the PDF's relinking, the launch
    buttons) reads them there, and pyproject.toml's copy agrees (the test after this)."""
    site = CONFIG["html"]["baseurl"]
    repo = CONFIG["repository"]["url"].rstrip("/")
    host = re.sub(r"^https?://", "", site).split("/")[0]
    found = _files_writing([site.rstrip("/"), repo, host])
    assert set(found) <= ADDRESS_FILES, {k: v for k, v in found.items() if k not in ADDRESS_FILES}
    # the consumers read the configured value
    ext = (ROOT / "book" / "_ext" / "ipynb_download.py").read_text()
    assert "app.config.html_baseurl" in ext and "site=_public_site(app)" in ext
    assert 'cfg.get("html", {}).get("baseurl"' in (ROOT / "tools" / "pdf_book.py").read_text()
    cell = install_cell("0.1.0", site, "paper")
    assert f'"FUSIONCENTER_BOOK_SITE", "{site}")' in cell


def test_urls_are_set_in_one_place_and_agree():
    repo = CONFIG["repository"]["url"].rstrip("/")
    site = CONFIG["html"]["baseurl"]
    assert re.fullmatch(r"https://github\.com/[^/]+/[^/]+", repo)
    assert site.startswith("https://") and site.endswith("/")
    urls = PYPROJECT["project"]["urls"]
    assert urls["Source"] == repo and urls["Issues"] == f"{repo}/issues"
    assert urls["Homepage"] == urls["Documentation"] == site
    launch = CONFIG["launch_buttons"]
    assert launch["binderhub_url"] and launch["colab_url"]


#: repo2docker's base environment, into which Binder installs binder/requirements.txt, has
#: notebook 7.4.7, which requires jupyterlab>=4.4.9,<4.5: with the lock's JupyterLab 4.6.6 `pip
#: check` fails there. Binder therefore pins the notebook release made for that JupyterLab; its
#: wheel's Requires-Dist (below) must hold for Binder's pins, and the base's must not be kept.
BINDER_BASE = {"notebook": ("7.4.7", {"jupyterlab": ">=4.4.9,<4.5"})}
NOTEBOOK_REQUIRES = {"7.6.5": {"jupyterlab": ">=4.6.6,<4.7", "jupyterlab-server": ">=2.28.0,<3",
                               "jupyter-server": ">=2.19.0,<3", "notebook-shim": ">=0.2,<0.3",
                               "tornado": ">=6.2.0", "jupyter-builder": ">=1.0.2,<2"}}


def _binder_pins(text: str) -> dict[str, str]:
    pins = {}
    for line in text.splitlines():
        if line and not line.startswith("#"):
            name, _, version = line.partition("==")
            pins[name.lower().replace("_", "-")] = version
    return pins


def _binder_conflicts(pins: dict[str, str], lock: dict[str, str]) -> list[str]:
    """Binder's pins that conflict with what stays of repo2docker's base (`pip check` there), or
    that differ from the lock."""
    from packaging.specifiers import SpecifierSet

    bad = []
    env = dict(lock)
    env.update(pins)
    for name, (version, requires) in BINDER_BASE.items():
        if name not in pins:  # the base's release stays: its requirements must hold
            bad += [f"binder: {dep}=={env.get(dep)}, but repo2docker's {name} {version} "
                    f"requires {dep}{spec}" for dep, spec in requires.items()
                    if env.get(dep) and env[dep] not in SpecifierSet(spec)]
    if "notebook" in pins:
        requires = NOTEBOOK_REQUIRES.get(pins["notebook"])
        if requires is None:
            bad.append(f"binder: notebook=={pins['notebook']}: record its requirements in "
                       "NOTEBOOK_REQUIRES")
        else:
            bad += [f"binder: {dep}=={env.get(dep)}, but notebook {pins['notebook']} requires "
                    f"{dep}{spec}" for dep, spec in requires.items()
                    if dep in pins and pins[dep] not in SpecifierSet(spec)]
    for name, version in pins.items():
        if name not in BINDER_BASE and lock.get(name) != version:
            bad.append(f"binder: {name}=={version}, lock: {lock.get(name)}")
    return bad


def test_binder_is_slim_and_pinned_like_the_lock():
    lock = _lock()
    pins = _binder_pins((ROOT / "binder" / "requirements.txt").read_text())
    assert {"jupyterlab", "jupyterlab-myst", "jupytext", "numpy", "numba", "scipy"} <= set(pins)
    assert not {"jupyter-book", "pytest", "playwright", "sphinx"} & set(pins)
    assert _binder_conflicts(pins, lock) == []
    # the check sees the conflict that broke Binder's `pip check` (the base's notebook kept
    # with JupyterLab 4.6.6), a JupyterLab the pinned notebook refuses, and a pin off the lock
    assert _binder_conflicts({k: v for k, v in pins.items() if k != "notebook"}, lock)
    assert _binder_conflicts({**pins, "jupyterlab": "4.4.10"}, {**lock, "jupyterlab": "4.4.10"})
    assert _binder_conflicts({**pins, "numpy": "1.0.0"}, lock)
    viewers = json.loads((ROOT / "binder" / "overrides.json").read_text())[
        "@jupyterlab/docmanager-extension:plugin"]["defaultViewers"]
    assert viewers == {"markdown": "Jupytext Notebook", "myst": "Jupytext Notebook"}
    post = (ROOT / "binder" / "postBuild").read_text()
    assert "overrides.json" in post and "pip install" in post


def _captured_display(monkeypatch, module, attr):
    seen = []
    monkeypatch.setattr(module, attr, lambda obj, **kw: seen.append((obj, kw)))
    return seen


def test_glue_without_myst_nb_writes_what_myst_nb_writes(monkeypatch):
    import IPython.display
    myst_nb = pytest.importorskip("myst_nb")
    import myst_nb.ext.glue as mg

    ours = _captured_display(monkeypatch, IPython.display, "display")
    fc_glue._fallback_glue("x", 0.125, display=False)
    fc_glue._fallback_glue("y", "text", display=True)
    theirs = _captured_display(monkeypatch, mg, "ipy_display")
    myst_nb.glue("x", 0.125, display=False)
    myst_nb.glue("y", "text", display=True)
    assert ours == theirs and len(ours) == 2
    with pytest.raises(ValueError, match="name"):
        fc_glue.glue("", 1)


def _resolver() -> Resolver:
    return Resolver(
        doc=lambda t: Link("S/a/b.html", "Doc B") if t == "../a/b" else None,
        ref=lambda t: Link(f"S/y.html#{t}", "Exercise 3" if t == "ex-1" else "Section Y"),
        eq=lambda t: Link(f"S/p.html#equation-{t}", "(2.1)"),
        prf=lambda t: Link(f"S/p.html#{t}", "Theorem 1"),
        cite=lambda keys, textual: " / ".join(f"{k}-{'t' if textual else 'p'}" for k in keys),
        reference=lambda k: f"entry of {k}", number=lambda label: "7" if label else "")


def _executed_notebook(markdown: str) -> dict:
    record = "application/papermill.record/"
    return {"cells": [
        {"cell_type": "code", "metadata": {}, "outputs": [], "source":
            'import os\nos.environ.setdefault("FUSIONCENTER_PROFILE", "fast")  # the profile\n'},
        {"cell_type": "markdown", "metadata": {}, "source": markdown},
        {"cell_type": "code", "metadata": {}, "source": "setup()", "outputs": [
            {"output_type": "stream", "name": "stdout", "text": ["profile: paper  (set ...)\n"]},
            {"output_type": "display_data", "data": {record + "text/plain": "0.123456"},
             "metadata": {"scrapbook": {"name": "v", "mime_prefix": record}}},
            {"output_type": "display_data", "data": {"text/plain": "'12'"},
             "metadata": {"scrapbook": {"name": "n", "mime_prefix": ""}}}]}]}


def test_reader_notebook_resolves_myst_for_plain_jupyter():
    md = ("(sec-x)=\n# Title\n\n{cite:t}`mo2015` find $\\E x$ = {glue:text}`v:.3f` and "
          "{glue:text}`n`; see {eq}`eq-a`, {ref}`sec-y`, {doc}`../a/b`, {prf:ref}`thm-1`.\n\n"
          "$$\nx = 1\n$$ (eq-a)\n\n:::{admonition} What\n:class: tip\n\n* one "
          "{cite:p}`mo2015,dey2009`\n:::\n\n```{prf:theorem} Big\n:label: thm-1\n\nIt holds.\n"
          "```\n\n::::{exercise}\n:label: ex-1\n\nDo it.\n::::\n\n:::{solution-start} ex-1\n"
          ":class: dropdown\n:::\nAnswer.\n:::{solution-end}\n:::\n")
    out, problems = reader_notebook(_executed_notebook(md), _resolver(), page_url="S/p.html",
                                    book_title="Book", version="9.9.9",
                                    macros={"E": "\\mathbb{E}"})
    assert problems == []
    note, install, prose, _code, refs = out["cells"]
    assert "`paper` profile" in note["source"] and "9.9.9" in note["source"]
    assert 'os.environ["FUSIONCENTER_PROFILE"] = "paper"  # <- THE PROFILE' in install["source"]
    text = prose["source"]
    for want in ("mo2015-t find $\\mathbb{E} x$ = 0.123 and 12",
                 "[(2.1)](S/p.html#equation-eq-a)", "[Section Y](S/y.html#sec-y)",
                 "[Doc B](S/a/b.html)", "[Theorem 1](S/p.html#thm-1)",
                 "> **What**", "> * one mo2015-p / dey2009-p", "> **Theorem 7 (Big)**",
                 "> It holds.", "> **Exercise 7**", "**Solution** to [Exercise 3](S/y.html#ex-1)",
                 "$$\nx = 1\n$$\n"):
        assert want in text, want
    assert "(sec-x)=" not in text and "{" not in text.replace("\\mathbb{E}", "")
    assert refs["source"] == ("## Works cited in this chapter\n\n"
                              "- entry of mo2015\n- entry of dey2009")


def test_reader_notebook_resolves_a_role_over_a_line_break_and_an_explorable_caption():
    md = ("**You need:** {doc}`the\nsecond <../a/b>` and {ref}`the section\n<sec-y>`.\n\n"
          "```{explorable-figure} mo2015-explore\nAt this value the rate is [[rate]].\n```\n")
    nb = _executed_notebook(md)
    nb["cells"][2]["outputs"].append(
        {"output_type": "display_data", "data": {"text/plain": "<explorable figure>"},
         "metadata": {"scrapbook": {"name": "explore-mo2015-explore", "mime_prefix": ""},
                      "fusioncenter": {"start": 1, "frames": [{"facts": {"rate": "0.9"}},
                                                              {"facts": {"rate": "0.466"}}]}}})
    out, problems = reader_notebook(nb, _resolver(), page_url="S/p.html", book_title="Book",
                                    version="9.9.9", macros={})
    assert problems == []
    text = out["cells"][2]["source"]
    assert "[the\nsecond](S/a/b.html)" in text and "[the section](S/y.html#sec-y)" in text
    assert "> **Figure 7.** At this value the rate is 0.466." in text, text


def test_reader_notebook_reports_what_it_cannot_resolve():
    _, problems = reader_notebook(
        _executed_notebook("{doc}`nowhere` and {glue:text}`missing:.2f` and {foo}`bar`"),
        _resolver(), page_url="S", book_title="B", version="1")
    assert any("unresolved {doc}" in p for p in problems)
    assert any("no glued value 'missing'" in p for p in problems)
    assert any("unknown role {foo}" in p for p in problems)


def test_reader_notebook_links_library_names_to_their_module_pages():
    """A library name links to its entry on its module's page of the API reference; a name the
    reference does not document links to the API index."""
    resolver = _resolver()
    resolver.doc = lambda t: Link("S/book/api.html", "API") if t == "/book/api" else None
    pages = {"fusioncenter.riccati.riccati_step": "riccati",
             "fusioncenter.particle.FilterModel": "particle"}
    resolver.py = lambda t: (Link(f"S/book/api/{pages[t]}.html#{t}", t) if t in pages else None)
    out, problems = reader_notebook(
        _executed_notebook("{py:func}`riccati.riccati_step <fusioncenter.riccati.riccati_step>`"
                           " and {py:class}`~fusioncenter.particle.FilterModel`"
                           " and {py:func}`fusioncenter.nowhere`"),
        resolver, page_url="S", book_title="B", version="1")
    assert problems == []
    text = out["cells"][2]["source"]
    assert "[`riccati.riccati_step`](S/book/api/riccati.html#fusioncenter.riccati.riccati_step)" \
        in text
    assert "[`FilterModel`](S/book/api/particle.html#fusioncenter.particle.FilterModel)" in text
    assert "[`fusioncenter.nowhere`](S/book/api.html)" in text


def _run_install_cell(source: str, monkeypatch, tmp_path) -> Exception | None:
    """Execute a downloaded notebook's install cell here, pip offline: no index, an empty
    folder of wheels, no retries."""
    for k in ("PIP_INDEX_URL", "PIP_EXTRA_INDEX_URL", "FUSIONCENTER_BOOK_SITE"):
        monkeypatch.delenv(k, raising=False)
    monkeypatch.setenv("PIP_NO_INDEX", "1")
    monkeypatch.setenv("PIP_FIND_LINKS", str(tmp_path))
    monkeypatch.setenv("PIP_RETRIES", "0")
    monkeypatch.setenv("PIP_TIMEOUT", "5")
    monkeypatch.setenv("FORCE_COLOR", "1")  # as in a Jupyter kernel, where pip's ERROR is red
    try:
        exec(compile(source, "install-cell", "exec"), {"__name__": "__main__"})
    except Exception as exc:  # the finding
        return exc
    return None


def test_downloaded_install_cell_stops_with_one_message_when_pip_fails(monkeypatch, tmp_path):
    """Neither the index nor the site has the version: the cell raises one exception whose
    rendering in Jupyter is its message alone, naming what failed and what to do."""
    import fusioncenter.book as fc_book

    site = "http://127.0.0.1:9/book/"  # nothing listens on port 9
    exc = _run_install_cell(install_cell("99.0.0", site, "fast"), monkeypatch, tmp_path)
    assert exc is not None and type(exc).__name__ == "InstallFailed", exc
    shown = exc._render_traceback_()
    assert len(shown) == 1
    msg = shown[0]
    assert msg.startswith("InstallFailed: the library fusioncenter 99.0.0 could not be installed")
    assert "from the package index: ERROR" in msg and "from the book's site: ERROR" in msg
    assert f"{site}_wheels/fusioncenter-99.0.0-py3-none-any.whl" in msg
    assert "PIP_NO_INDEX=1" in msg and "PIP_FIND_LINKS" in msg
    assert "\x1b" not in msg  # pip's colours stay out of the message
    assert fc_book.__file__.startswith(str(ROOT / "src"))  # nothing was installed over it


def test_downloaded_install_cell_installs_nothing_where_the_version_is_installed(
        monkeypatch, tmp_path):
    import subprocess

    calls = []
    monkeypatch.setattr(subprocess, "run", lambda *a, **k: calls.append(a))
    monkeypatch.setenv("FUSIONCENTER_PROFILE", "fast")
    source = install_cell(fusioncenter.__version__, CONFIG["html"]["baseurl"], "paper")
    assert _run_install_cell(source, monkeypatch, tmp_path) is None
    assert calls == []
    import os

    assert os.environ["FUSIONCENTER_PROFILE"] == "paper"  # the marked line sets it
    with pytest.raises(ValueError, match="site"):
        install_cell("0.1.0", "fusioncenter-book", "fast")
    with pytest.raises(ValueError, match="version"):
        install_cell("0.1.0\nimport os", CONFIG["html"]["baseurl"], "fast")
