"""The chapters' shared helpers in fusioncenter.book: show, assert_zero, min_eig, pm, tables."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from IPython.display import Markdown, Math

from fusioncenter import book


def test_show_displays_the_equation(monkeypatch):
    shown = []
    monkeypatch.setattr("IPython.display.display", lambda obj: shown.append(obj))
    x = sp.Symbol("x")
    book.show("f(x)", x**2 / 2)
    assert len(shown) == 1 and isinstance(shown[0], Math)
    assert shown[0].data == r"f(x) = \frac{x^{2}}{2}"


def test_assert_zero_accepts_identities_and_rejects_the_rest():
    x, y = sp.symbols("x y", positive=True)
    book.assert_zero(1 / (x + y) - 1 / (x + y))
    book.assert_zero(x / (x * y + x) - 1 / (y + 1))
    book.assert_zero(0)
    with pytest.raises(AssertionError) as err:
        book.assert_zero(x / (x + y))
    assert "x" in str(err.value)  # the message is the expression


def test_assert_zero_on_matrices():
    a = sp.Symbol("a", positive=True)
    M = sp.Matrix([[a, 1], [0, a]])
    book.assert_zero(M * M.inv() - sp.eye(2))
    with pytest.raises(AssertionError):
        book.assert_zero(M.inv() - sp.zeros(2, 2))


def test_assert_zero_rewrite():
    t = sp.Symbol("t", real=True)
    expr = sp.erfc(t) + sp.erf(t) - 1
    book.assert_zero(expr, rewrite=sp.erf)
    book.assert_zero(sp.Matrix([expr, 0]), rewrite=sp.erf)
    with pytest.raises(AssertionError):
        book.assert_zero(sp.erfc(t) - sp.erf(t), rewrite=sp.erf)


def test_min_eig():
    assert book.min_eig([[2.0, 0.0], [0.0, 3.0]]) == pytest.approx(2.0)
    # only the symmetric part counts: [[1, 4], [0, 1]] -> [[1, 2], [2, 1]], eigenvalues -1, 3
    assert book.min_eig([[1.0, 4.0], [0.0, 1.0]]) == pytest.approx(-1.0)
    stack = np.stack([np.eye(2), -0.5 * np.eye(2)])
    assert book.min_eig(stack) == pytest.approx(-0.5)
    assert isinstance(book.min_eig(np.eye(3)), float)


def test_pm_fixed_decimals():
    assert book.pm(1.23456, 0.01) == "1.235 ± 0.010"
    assert book.pm(2, 0.5, digits=1) == "2.0 ± 0.5"
    assert book.pm(-0.0004, 0.0001, digits=2) == "-0.00 ± 0.00"


def test_tables():
    src = book.markdown_table(["a", "b"], [(1, "x"), (2.5, "y")])
    assert src.split("\n") == ["| a | b |", "|---|---|", "| 1 | x |", "| 2.5 | y |"]
    md = book.md_table(["a", "b"], [(1, "x"), (2.5, "y")])
    assert isinstance(md, Markdown) and md.data == src
    assert book.markdown_table(["only"], []) == "| only |\n|---|"


def test_a_pipe_in_a_table_cell_keeps_the_columns():
    from fusioncenter.book import markdown_table

    text = markdown_table(["what", "largest $|z|$"], [["a | b", "$|x| \\le 1$"]])
    assert text.splitlines()[0] == r"| what | largest $\vert{}z\vert{}$ |"
    assert text.splitlines()[2] == r"| a \| b | $\vert{}x\vert{} \le 1$ |"


def test_an_escaped_pipe_stays_escaped_once():
    from fusioncenter.book import markdown_table

    assert markdown_table(["a"], [[r"P\|0 and x | y"]]).splitlines()[2] == r"| P\|0 and x \| y |"
