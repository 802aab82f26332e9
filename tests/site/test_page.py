"""The page as a reader sees it: no raw markup, numbered exercises with solutions, indexes, search.

Checks of the built site (``$FUSIONCENTER_SITE``, default the fast build), of the book's sources
and of the detectors themselves (so that a check that cannot fail is noticed). The clipped-content
measurement runs in ``tools/browser_check``
(``test_site.py::test_browser_check_of_every_page``).
"""

from __future__ import annotations

import functools
import http.server
import re
import socketserver
import sys
import threading
from pathlib import Path
from urllib.parse import quote

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "book" / "_ext"))
import student_edition  # noqa: E402  (book/_ext is not a package)

pytestmark = pytest.mark.site

PART_INDEXES = ["book/mo2015/index", "book/dey2009/index", "book/leong2011/index",
                "book/zheng2014/index"]


sys.path.insert(0, str(ROOT / "tools"))
import browser_check as bc  # noqa: E402
from headless import launch  # noqa: E402


@pytest.fixture(scope="module")
def site() -> Path:
    import os

    path = Path(os.environ.get("FUSIONCENTER_SITE",
                               ROOT / "_build" / "fast" / "_build" / "html"))
    if not (path / "index.html").is_file():
        pytest.fail(f"built site not found at {path}; build it with "
                    "`python tools/build_book.py --profile fast --strict`")
    return path


# ------------------------------------------------------------------ the detectors themselves
@pytest.mark.parametrize("text", [
    r"The mean uses \tilde P, and so does the conclusion",
    r"least error for \gamma_{\text{total}} = 10^{-3}",
    r"only when every \kappa_i = 1",
    "see {cite}`mo2015`", "as in {eq}`eq-x`", "{glue:text}`zheng2014-x`",
    "the rate $\\lambda_i$ of sensor $i$", "display $$x$$",
])
def test_raw_markup_is_found(text):
    assert bc.find_raw_markup(text), text


@pytest.mark.parametrize("text", [
    "The mean uses P̃, and so does the conclusion", "γ_total = 10⁻³", "costs $5 and more",
    "E[Pₖ] against Z̄ₖ", "a | b", "Fig. 3(a): multi-access",
])
def test_plain_text_is_not_flagged(text):
    assert not bc.find_raw_markup(text), text


def test_raw_markup_only_outside_math_and_code():
    html = ('<html><head><title>The mean uses \\tilde P</title></head><body>'
            '<p>ok <span class="math notranslate">\\(\\tilde P\\)</span> ok</p>'
            '<pre>r"$\\tilde P$"</pre><div class="highlight"><pre>\\text{x}</pre></div>'
            '<p><a href="#x">see \\kappa_i</a></p></body></html>')
    found = [ex for _kind, ex in bc.raw_markup_in_html(html)]
    assert any("tilde" in ex for ex in found), found  # the page title
    assert any("kappa" in ex for ex in found), found  # the link text
    assert not any("text{x}" in ex for ex in found), found  # code is not prose
    assert len(found) == 2, found


def test_search_index_titles_are_scanned():
    index = ('Search.setIndex({"titles": ["Fine", "Uses \\\\tilde P"], '
             '"alltitles": {"$x$ law": []}})')
    found = bc.raw_markup_in_search_index(index)
    assert len(found) == 2, found


# ----------------------------------------------------------------------------- the site
def test_no_unrendered_markup(site: Path) -> None:
    problems, counts = bc.check_markup(site)
    assert counts.get("searchindex.js") is not None
    assert not problems, "unrendered MyST/LaTeX on the site:\n" + "\n".join(problems)


def _text(path: Path) -> str:
    return path.read_text(encoding="utf-8", errors="replace")


def test_exercises_numbered_per_chapter(site: Path) -> None:
    """Every exercise on a chapter page is "Exercise <chapter>.<k>", k = 1, 2, ... in order."""
    numbered = 0
    for page in sorted((site / "book").rglob("*.html")):
        titles = re.findall(r'class="exercise[^"]*".*?<p class="admonition-title">\s*'
                            r'(?:<span[^>]*>)?\s*Exercise\s+([0-9.]+)', _text(page), re.S)
        if not titles:
            continue
        chapters = {t.rsplit(".", 1)[0] for t in titles}
        assert len(chapters) == 1 and all("." in t for t in titles), (page.name, titles)
        assert [int(t.rsplit(".", 1)[1]) for t in titles] == list(range(1, len(titles) + 1)), (
            page.name, titles)
        numbered += len(titles)
    assert numbered >= 80, f"only {numbered} numbered exercises found on the site"


def test_solutions_are_collapsed(site: Path) -> None:
    found = 0
    for page in sorted((site / "book").rglob("*.html")):
        for cls in re.findall(r'<div class="(solution[^"]*)"', _text(page)):
            found += 1
            assert "dropdown" in cls.split(), (page.name, cls)
    assert found >= 80, f"only {found} solutions on the site"


def test_genindex_lists_glossary_terms_and_figures(site: Path) -> None:
    text = _text(site / "genindex.html")
    for term in ("CFwMD", "censoring", "fusion centre", "Fig. 3(a)", "Table II"):
        assert term in text, f"genindex.html does not list {term!r}"


def test_figure_index_is_linked_from_every_part(site: Path) -> None:
    from fusioncenter import figures

    index = site / "book" / "figure-index.html"
    text = _text(index)
    for entry in figures.entries():
        assert entry.id in text, f"figure index misses {entry.id}"
    for part in PART_INDEXES:
        assert "figure-index.html" in _text(site / f"{part}.html"), part


def test_notation_page_has_every_paper(site: Path) -> None:
    text = _text(site / "book" / "introduction" / "notation.html")
    for key in ("mo2015", "dey2009", "leong2011", "zheng2014"):
        assert f'id="sec-notation-{key}"' in text or f"notation-{key}" in text, key


class _Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args) -> None:
        pass


@pytest.fixture(scope="module")
def search(site: Path):
    """Run the site's own search (search.html?q=...) in headless Chromium: hrefs in order."""
    from playwright.sync_api import sync_playwright

    server = socketserver.ThreadingTCPServer(
        ("127.0.0.1", 0), functools.partial(_Quiet, directory=str(site)))
    server.daemon_threads = True
    threading.Thread(target=server.serve_forever, daemon=True).start()
    base = f"http://127.0.0.1:{server.server_address[1]}/"
    with sync_playwright() as pw:
        browser = launch(pw)
        page = browser.new_page()

        def run(query: str) -> list[str]:
            page.goto(base + "search.html?q=" + quote(query), wait_until="load")
            page.wait_for_function(
                "() => document.querySelectorAll('#search-results ul.search li').length > 0"
                " || /did not match|no results/i.test("
                "(document.querySelector('#search-results') || {}).textContent || '')",
                timeout=20_000)
            return page.eval_on_selector_all("#search-results ul.search li a",
                                             "els => els.map(a => a.getAttribute('href'))")

        yield run
        browser.close()
    server.shutdown()


@pytest.mark.parametrize("query, page", [
    ("Table II", "book/zheng2014/vector.html"),
    ("Fig. 3(a)", "book/leong2011/allocation.html"),
])
def test_search_finds_the_reproducing_page_first(search, query, page) -> None:
    hits = search(query)
    assert hits, f"search for {query!r} found nothing"
    first = re.sub(r"^(\./)+", "", hits[0].split("#")[0])
    assert first == page, f"search for {query!r}: first hit {hits[0]}, expected {page}; " \
                          f"all: {hits[:5]}"


# ------------------------------------------------------------------------- the sources
def _exercises_and_solutions():
    exercises, solved, open_ = [], set(), set()
    for md in sorted((ROOT / "book").rglob("*.md")):
        text = md.read_text(encoding="utf-8")
        for m in re.finditer(r"^```\{exercise\}([^\n]*)\n((?::[^\n]*\n)*)", text, re.M):
            opts = dict(re.findall(r"^:(\w+): *(.*)$", m.group(2), re.M))
            exercises.append((md.relative_to(ROOT).as_posix(), opts.get("label")))
            if "open" in m.group(1).lower() or "exercise-open" in opts.get("class", ""):
                open_.add(opts.get("label"))
        for m in re.finditer(r"^```\{solution(?:-start)?\} (\S+)\n((?::[^\n]*\n)*)", text, re.M):
            solved.add(m.group(1))
            assert ":class: dropdown" in m.group(2), f"{md.name}: solution {m.group(1)} " \
                                                     "is not collapsed (:class: dropdown)"
    return exercises, solved, open_


def test_every_exercise_has_a_solution_or_is_marked_open() -> None:
    exercises, solved, open_ = _exercises_and_solutions()
    assert len(exercises) >= 80
    missing = [(f, lab) for f, lab in exercises if lab not in solved and lab not in open_]
    assert not missing, f"exercises with neither a solution nor the open mark: {missing}"


def test_student_edition_strips_gated_and_plain_solutions() -> None:
    cell = lambda kind, src: {"cell_type": kind, "metadata": {}, "source": src}  # noqa: E731
    # as MyST-NB writes the executed notebook: text around the directives in the same cell
    nb = {"cells": [
        cell("markdown", "## Exercises\n\n```{exercise}\n:label: ex-a\n\nDo it.\n```\n\n"
                         "```{solution-start} ex-a\n:class: dropdown\n```\n\nThe answer"),
        cell("code", "print(42)"),
        cell("markdown", "More of the answer.\n\n```{solution-end}\n```\n\nNext exercise.\n\n"
                         "```{solution} ex-b\n:class: dropdown\n\nShort answer.\n```\n\nAfter."),
        cell("code", "kept = True"),
    ]}
    dropped = student_edition.strip_notebook(nb)
    text = "\n".join(c["source"] for c in nb["cells"])
    assert dropped >= 3, text
    assert "print(42)" not in text and "kept = True" in text
    assert "answer" not in text.lower(), text
    for kept in ("## Exercises", "Do it.", "Next exercise.", "After."):
        assert kept in text, (kept, text)
    assert text.count(student_edition.NOTE) == 2, text


def test_student_edition_flag(monkeypatch) -> None:
    monkeypatch.delenv(student_edition.EDITION_VAR, raising=False)
    assert student_edition.edition() == "instructor"
    monkeypatch.setenv(student_edition.EDITION_VAR, "student")
    assert student_edition.edition() == "student"
    monkeypatch.setenv(student_edition.EDITION_VAR, "teacher")
    with pytest.raises(ValueError, match=student_edition.EDITION_VAR):
        student_edition.edition()


def test_config_registers_the_stylesheet_and_numbering() -> None:
    import yaml

    cfg = yaml.safe_load((ROOT / "_config.yml").read_text(encoding="utf-8"))
    sph = cfg["sphinx"]
    assert "fusioncenter.css" in sph["config"]["html_css_files"]
    assert (ROOT / sph["config"]["html_static_path"][0] / "fusioncenter.css").is_file()
    assert sph["config"]["numfig_secnum_depth"] == 1
    assert {"student_edition", "scroll_code"} <= set(sph["local_extensions"])
    toc = yaml.safe_load((ROOT / "_toc.yml").read_text(encoding="utf-8"))
    numbered = [p["caption"] for p in toc["parts"] if p.get("numbered")]
    assert sum(c.startswith("Part ") for c in numbered) == 5, numbered


def _mini_build(tmp_path: Path, monkeypatch, edition: str) -> str:
    """Build a one-page Sphinx project with an exercise and two kinds of solution."""
    from sphinx.application import Sphinx

    src = tmp_path / f"src-{edition}"
    src.mkdir()
    (src / "conf.py").write_text(
        "import sys\n"
        f"sys.path.insert(0, {str(ROOT / 'book' / '_ext')!r})\n"
        "extensions = ['myst_parser', 'sphinx_exercise', 'student_edition']\n"
        "myst_enable_extensions = ['dollarmath']\n", encoding="utf-8")
    (src / "index.md").write_text(
        "# Mini\n\n```{exercise}\n:label: ex-one\n\nWhat is $1 + 1$?\n```\n\n"
        "```{solution-start} ex-one\n:class: dropdown\n```\n\nThe gated answer is two.\n\n"
        "```{solution-end}\n```\n\n```{exercise}\n:label: ex-two\n\nAnd $2 + 2$?\n```\n\n"
        "```{solution} ex-two\n:class: dropdown\n\nThe plain answer is four.\n```\n\n"
        "Text after the solutions.\n", encoding="utf-8")
    monkeypatch.setenv(student_edition.EDITION_VAR, edition)
    out = tmp_path / f"out-{edition}"
    app = Sphinx(str(src), str(src), str(out), str(tmp_path / f"doctrees-{edition}"), "html",
                 status=None, warning=None, freshenv=True)
    app.build()
    return (out / "index.html").read_text(encoding="utf-8")


def test_student_edition_build_drops_the_solutions(tmp_path, monkeypatch) -> None:
    teacher = _mini_build(tmp_path, monkeypatch, "instructor")
    student = _mini_build(tmp_path, monkeypatch, "student")
    for answer in ("The gated answer is two.", "The plain answer is four."):
        assert answer in teacher
        assert answer not in student
    for text in ("What is", "And", "Text after the solutions."):
        assert text in student
    assert student.count(student_edition.NOTE) == 2


# ------------------------------------------------------ a chapter reads as a book (issue 27)
@pytest.mark.parametrize("text", [
    "True", "  False  ", "the two agree: True", "array([1., 2.])", "Matrix([[1, 0]])",
    "mo2015: {'reproduced': 3, 'differs': 0}", "[0.1, 0.25, 3]", "['a', 'b']",
    "[ 0.1  0.2  0.3]",
])
def test_repr_output_is_found(text):
    assert bc.find_repr_output(text), text


@pytest.mark.parametrize("text", [
    "(10) and (11) agree to 1e-12", "largest |z| = 2.31", "True positives: 3 of 4",
    "Fig. 3(a) [paper]", "bins [1, 2)", "G′ in [0.2727, 1.5586] on [0, 1500]",
    "the square [-10, 10]^2 m",
])
def test_plain_output_is_not_flagged(text):
    assert not bc.find_repr_output(text), text


@pytest.mark.parametrize("text", [
    "x_hat_{k|k-1} is the prediction", "P_hat", "the noise sigma_v", "sigma^2 of it",
    "h^T P h", "sqrt(r) times", "uses x_{k|k-1}", "P_inf - sigma_w2", "zeta_inf = 3.3",
])
def test_ascii_math_is_found(text):
    assert bc.find_ascii_math(text), text


@pytest.mark.parametrize("text", [
    "x̂ₖ|ₖ₋₁ is the prediction", "P̂", "the noise σᵥ", "hᵀ P h", "√r times",
    "the sigma points", "a hat trick", "delta_for_rate(0.5, 1, √800)",
])
def test_unicode_math_is_not_flagged(text):
    assert not bc.find_ascii_math(text), text


def test_reading_counts_unfolded_code_and_finds_loose_images():
    page = (
        '<div class="cell docutils container"><div class="cell_input docutils container">'
        '<div class="highlight"><pre>a = 1\n\nb = 2\n</pre></div></div>'
        '<div class="cell_output docutils container"><img src="x/loose.png"/>'
        '<div class="output text_plain"><pre>{\'a\': 1}</pre></div></div></div>'
        '<div class="cell tag_hide-input docutils container"><details><summary>s</summary>'
        '<div class="cell_input docutils container"><div class="highlight"><pre>c = 3\n'
        '</pre></div></div></details></div>'
        '<figure><img src="fig.png"/><figcaption>Fig. 1</figcaption></figure>'
        '<p>The prediction x_hat and <span class="math">\\(\\hat x\\)</span>.</p>')
    r = bc.read_page(page)
    assert r.code_lines == 2
    assert r.loose_images == ["x/loose.png"]
    assert r.outputs == ["{'a': 1}"]
    assert bc.find_ascii_math(" ".join(r.prose)) and "hat x" not in " ".join(r.prose)


def test_reading_counts_code_only_before_the_reproduction_notes():
    cell = ('<div class="cell docutils container"><div class="cell_input docutils container">'
            '<div class="highlight"><pre>{}</pre></div></div></div>')
    page = ('<section id="a"><h2>1.1. The idea</h2>' + cell.format("a = 1\nb = 2")
            + '</section><section id="n"><h2>1.5. Reproduction <em>notes</em></h2>'
            + cell.format("assert a == 1") + "</section>")
    assert bc.read_page(page).code_lines == 2


@pytest.mark.parametrize("html, found", [
    ("<p>Start with the <a href='x'>The Kalman filter</a> chapter.</p>", "the The"),
    ("<p>as <a href='e'>Exercise Exercise 14.1</a> shows</p>", "Exercise Exercise"),
    ("<p>values of <span class='math'>\\(l\\)</span> of an entry</p>", None),
    ("<table><tr><td>reproduced</td><td>reproduced</td></tr></table>", None),
    ("<p>that is, that that rule</p>", "that that"),
])
def test_doubled_words_are_found_within_a_block_only(html, found):
    words = bc.find_doubled_words(bc.read_page(html).blocks)
    assert (found is None and not words) or any(found in w for w in words), words


SOLUTION = ('<div class="solution dropdown admonition"><p>So {}.</p>'
            '<div class="cell docutils container"><div class="cell_output docutils container">'
            '<div class="output stream"><pre>C = 41.60</pre></div></div></div></div>')


@pytest.mark.parametrize("prose, flagged", [
    ("<span class='math'>\\(C \\approx 41.8\\)</span>", True),  # the slip of Solution 12.4
    ("C is about 41.8", True),
    ("C is about 41.6", False),  # agrees at its precision
    ("C is about <span class='pasted-text'>41.8</span>", False),  # glued: the cell's own
    ("the paper prints 57.3", False),  # not near any output
    ("C is about 42", False),  # two significant digits: not compared
])
def test_numbers_typed_in_the_text_are_checked_against_the_outputs(prose, flagged):
    page = bc.read_page(SOLUTION.format(prose))
    assert bool(bc.find_contradicted_numbers(page.typed, page.printed)) is flagged


@pytest.mark.parametrize("prose", [
    '<h2><span class="section-number">41.8. </span>A section</h2>',  # a section number
    'see <a class="reference internal" href="#x">Fig. 41.8</a>',  # a link's own text
    'the rate is <span class="fc-explore-fact" data-fact="c">41.8</span>',  # a slider's value
])
def test_numbers_that_are_not_typed_are_not_compared(prose):
    page = bc.read_page(SOLUTION.format(prose))
    assert not bc.find_contradicted_numbers(page.typed, page.printed)


def test_a_closed_solution_shows_no_code():
    page = ('<div class="solution dropdown admonition"><div class="cell docutils container">'
            '<div class="cell_input docutils container"><div class="highlight"><pre>a = 1\n'
            '</pre></div></div></div></div>')
    assert bc.read_page(page).code_lines == 0


def test_numbers_are_compared_with_the_outputs_of_their_own_section_only():
    page = bc.read_page("<section><p>C is about 41.8.</p></section>"
                        + SOLUTION.format("nothing typed"))
    assert not bc.find_contradicted_numbers(page.typed, page.printed)


def test_the_reading_check_fails_on_a_slip(tmp_path):
    chapter = tmp_path / "book" / "part" / "chapter.html"
    chapter.parent.mkdir(parents=True)
    chapter.write_text("<html><body><p>Start with the The Kalman filter.</p>"
                       + SOLUTION.format("C is about 41.8") + "</body></html>")
    problems, _ = bc.check_reading(tmp_path)
    assert any("doubled word" in p for p in problems), problems
    assert any("41.8 in the text, 41.6 in an output" in p for p in problems), problems


def test_reading_checks_only_chapter_pages():
    assert bc.is_chapter("book/mo2015/trigger.html")
    assert not bc.is_chapter("book/mo2015/index.html")
    assert not bc.is_chapter("book/api.html") and not bc.is_chapter("index.html")
    assert not bc.is_chapter("book/api/event.html")


def test_the_chapter_pages_read_as_a_book(site: Path) -> None:
    problems, code = bc.check_reading(site)
    assert len(code) >= 25, sorted(code)
    assert not problems, "\n".join(problems[:40])
