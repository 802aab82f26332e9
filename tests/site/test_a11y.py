"""The accessibility check of tools/browser_check (axe-core, issue 48) sees violations.

Small pages, no built site: each is loaded in the check's headless Chromium and checked by the
same function as every page of the site (:func:`browser_check.axe_violations`), in the light
and the dark colours of pydata-sphinx-theme (``data-theme`` on ``<html>``).
"""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

pytestmark = pytest.mark.site


sys.path.insert(0, str(ROOT / "tools"))
import browser_check as bc  # noqa: E402  (tools/ is not a package)
from headless import launch  # noqa: E402

#: a sidebar toggle as pydata-sphinx-theme writes it: an icon, no name
TOGGLE = ('<details><summary><span class="toctree-toggle" role="presentation"><i class="fa">'
          '</i></span></summary><ul><li>a section</li></ul></details>')
#: the same toggle with the name book/_ext/a11y.py gives it
NAMED_TOGGLE = TOGGLE.replace("<summary>", '<summary aria-label="Sections of Part I">')
#: dark text on a dark background, in the dark theme only
DARK_ONLY = ("<style>html[data-theme=dark] body { background: #222; } "
             "html[data-theme=dark] p.faint { color: #444; }</style>"
             '<p class="faint">Read me at night.</p>')


def _page(body: str) -> str:
    return (f'<!doctype html><html lang="en"><head><title>a page</title></head>'
            f"<body><main><h1>A page</h1>{body}</main></body></html>")


@pytest.fixture(scope="module")
def page():
    from playwright.sync_api import sync_playwright

    with sync_playwright() as pw:
        browser = launch(pw)
        context = browser.new_context(viewport=bc.VIEWPORT)
        yield context.new_page()
        browser.close()


def _found(page, body: str) -> set[tuple[str, str]]:
    page.set_content(_page(body))
    return {(v["id"], v["theme"]) for v in bc.axe_violations(page)}


def test_a_clean_page_has_no_violation(page):
    assert _found(page, "<p>Plain text.</p>" + NAMED_TOGGLE) == set()


def test_an_unnamed_summary_toggle_is_reported(page):
    assert ("summary-name", "light") in _found(page, TOGGLE)


def test_low_contrast_text_is_reported(page):
    found = _found(page, '<p style="color: #bbb">Light grey on white.</p>')
    assert ("color-contrast", "light") in found


def test_a_contrast_failure_of_the_dark_theme_only_is_reported(page):
    found = _found(page, DARK_ONLY)
    assert ("color-contrast", "dark") in found and ("color-contrast", "light") not in found


def test_the_page_is_put_back_as_it_was(page):
    page.set_content(_page("<p>Plain $x$.</p><mjx-container><span>x</span></mjx-container>"))
    page.evaluate("() => { document.documentElement.dataset.theme = 'light'; }")
    bc.axe_violations(page, aside="mjx-container")
    assert page.evaluate("() => [document.documentElement.dataset.theme, "
                         "document.documentElement.dataset.mode === undefined, "
                         "document.querySelectorAll('mjx-container').length]") == [
        "light", True, 1]


def test_check_accessibility_reports_a_problem_per_rule_and_theme(page):
    page.set_content(_page(TOGGLE + DARK_ONLY))
    res = bc.PageResult("p.html")
    bc.check_accessibility(page, res)
    assert len(res.problems) == 2, res.problems
    assert any("summary-name" in p and "light theme" in p for p in res.problems)
    assert any("color-contrast" in p and "dark theme" in p for p in res.problems)



def test_a_control_without_a_visible_focus_is_reported(page):
    page.set_content(_page("<style>button:focus { outline: none; }</style>"
                           "<button>Hidden focus</button>" + NAMED_TOGGLE))
    res = bc.PageResult("p.html")
    bc.check_focus(page, res)
    assert len(res.problems) == 1 and "1 of 2 controls" in res.problems[0], res.problems
    assert "Hidden focus (no visible focus)" in res.problems[0]
    page.set_content(_page("<button>Seen</button>" + NAMED_TOGGLE))
    res = bc.PageResult("p.html")
    bc.check_focus(page, res)
    assert res.problems == []


def test_uniform_markup_is_checked_on_the_first_page_that_has_it(page):
    """MathJax's output (and code listings) are checked by axe once per browser, then set
    aside: a contrast failure inside them is found on the first page only."""
    faint = ('<div class="highlight"><pre><span style="color: #ccc">faint = 1</span>'
             '</pre></div>')
    seen: set[str] = set()
    found = []
    for _ in range(2):
        page.set_content(_page(faint))
        res = bc.PageResult("p.html")
        bc.check_accessibility(page, res, seen=seen)
        found.append(any("color-contrast" in p for p in res.problems))
    assert found == [True, False] and seen == {"code"}
