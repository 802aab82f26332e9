"""Helpers that every chapter calls, so chapters stay short and alike."""

from __future__ import annotations

import base64
import html
import textwrap

from fusioncenter import figures, plotting
from fusioncenter._docstrings import Glossary
from fusioncenter.glue import glue
from fusioncenter.profile import ENV_VAR, current_profile

__all__ = ["FIGURE_METADATA", "assert_zero", "evidence_html", "evidence_text", "figure",
           "glue", "markdown_table", "md_table", "min_eig", "pm", "reproduce", "setup",
           "show", "show_bundle", "show_evidence"]

#: Metadata key under which :func:`reproduce` stores what the site's figure directive needs.
FIGURE_METADATA = "fusioncenter"

#: The arguments the helpers share, by name.
_doc = Glossary("""
entry_id : str
    The registry id the claims belong to (named in the heading).
claims : list of Claim
    The evaluated claims (:meth:`fusioncenter.figures.entry.Entry.run_checks`).
header : sequence of str
    The column titles.
rows : iterable of sequence
    One sequence per row; each cell is converted with :class:`str`.
""")


def _inline_figures() -> None:
    """In a notebook kernel, display figures inline even if MPLBACKEND says otherwise."""
    try:
        from IPython import get_ipython
    except ImportError:  # pragma: no cover (IPython comes with the book's environment)
        return
    shell = get_ipython()
    if shell is not None and type(shell).__name__ == "ZMQInteractiveShell":
        shell.run_line_magic("matplotlib", "inline")


def setup() -> str:
    """Apply the plotting style and print (and return) the profile this chapter runs in.

    A chapter's first cell calls it. In a Jupyter kernel it also selects the inline
    matplotlib backend (whatever ``MPLBACKEND`` says); everywhere it applies
    :func:`fusioncenter.plotting.use_style` and NumPy's print options ``precision=6,
    suppress=True``.

    Returns
    -------
    str
        The profile, ``"fast"`` or ``"paper"``
        (:func:`fusioncenter.profile.current_profile`), also printed with a hint on how to
        change it.

    Raises
    ------
    ValueError
        If the environment variable ``FUSIONCENTER_PROFILE`` names an unknown profile.
    """
    import numpy as np

    _inline_figures()
    plotting.use_style()
    np.set_printoptions(precision=6, suppress=True)
    profile = current_profile()
    print(f"profile: {profile}  (set {ENV_VAR}=fast|paper to change it)")
    return profile


def _shell():
    try:
        from IPython import get_ipython
    except ImportError:  # pragma: no cover
        return None
    return get_ipython()


def show_bundle(bundle: dict, metadata: dict) -> None:
    """Show a MIME bundle in a notebook; print its text elsewhere (tests, scripts).

    Parameters
    ----------
    bundle : dict
        MIME type -> data (``"image/png"`` base64, ``"text/plain"``, ...).
    metadata : dict
        The output's metadata (``scrapbook`` for glue, :data:`FIGURE_METADATA` for the site).

    Returns
    -------
    None
        Under IPython the bundle is displayed; elsewhere its ``text/plain`` is printed, if any.
    """
    if _shell() is None:
        if "text/plain" in bundle:
            print(bundle["text/plain"])
        return
    from IPython.display import display

    display(bundle, raw=True, metadata=metadata)


@_doc(returns=("str", "Lines of at most 88 characters: a count of the claims that hold, then "
                     "``PASS:`` or\n``FAIL:`` with each claim's name and its bracketed detail."))
def evidence_text(entry_id: str, claims) -> str:
    """The claims as wrapped plain text: one verdict line per claim, its detail indented."""
    held = sum(bool(c.passed) for c in claims)
    lines = [f"Evidence for {entry_id}: {held} of {len(claims)} claims hold"]
    for c in claims:
        lines += textwrap.wrap(f"{'PASS' if c.passed else 'FAIL'}: {c.name}", 88,
                               subsequent_indent="      ")
        if c.detail:
            lines += textwrap.wrap(str(c.detail), 88, initial_indent="      [",
                                   subsequent_indent="       ")
            lines[-1] += "]"
    return "\n".join(lines)


@_doc(returns=("str", "An HTML ``<details>`` block whose summary counts the claims that "
                     "hold; it is open when\na claim failed."))
def evidence_html(entry_id: str, claims) -> str:
    """The claims as a collapsible table (claim, value or detail, verdict)."""
    held = sum(bool(c.passed) for c in claims)
    rows = "".join(
        f'<tr class="fc-{"pass" if c.passed else "fail"}"><td>{html.escape(c.name)}</td>'
        f"<td>{html.escape(str(c.detail))}</td>"
        f'<td class="fc-verdict">{"PASS" if c.passed else "FAIL"}</td></tr>'
        for c in claims)
    failed = held < len(claims)
    return (
        f'<details class="fc-evidence"{" open" if failed else ""}>'
        f"<summary>Evidence: {held} of {len(claims)} claims of <code>{html.escape(entry_id)}"
        f"</code> hold</summary>"
        '<table class="fc-evidence-table"><thead><tr><th>claim</th><th>value / detail</th>'
        f"<th>verdict</th></tr></thead><tbody>{rows}</tbody></table></details>"
    )


@_doc(returns=("None", "The evidence is shown (its plain text printed outside a notebook)."),
      raises=(("AssertionError", "If a claim does not hold (after the evidence has been "
                                 "shown), naming the failed ones."),),
      name=("str", "The glue key of the evidence (the site's directive reads it)."),
      failure=("str", "What the error says happened, before the failed claims' names."))
def show_evidence(entry_id: str, claims, name: str, failure: str) -> None:
    """Show the evidence of a figure (every claim with its value and verdict), then fail
    loudly if a claim does not hold."""
    show_bundle({"text/plain": evidence_text(entry_id, claims),
                 "text/html": evidence_html(entry_id, claims)},
                {"scrapbook": {"name": name, "mime_prefix": ""}})
    failed = [c.name for c in claims if not c.passed]
    if failed:
        raise AssertionError(f"{entry_id}: {failure}: {failed}")


def _show_png(fig, name: str, **run) -> None:
    """Render ``fig`` once and show it, glued under ``name``, with what the site's figure
    directive needs (its layout facts, its id, the ``run`` facts and its alt text)."""
    png, facts = plotting.render(fig)
    meta = {**facts, "id": name, **run, "alt": plotting.describe(fig)}
    show_bundle({"image/png": base64.b64encode(png).decode("ascii")},
                {"scrapbook": {"name": name, "mime_prefix": ""}, FIGURE_METADATA: meta})


def figure(name: str, fig) -> None:
    """Show a figure a chapter draws itself as a numbered, captioned figure of the site.

    The chapter draws with :func:`fusioncenter.plotting.subplots` (``stack=True`` for more
    than one panel), passes the figure here, tags the cell ``remove-output`` and follows it
    with the site's directive, whose body is the caption::

        ```{book-figure} fig-mo2015-trigger-rate
        The trigger's rate against its threshold ...
        ```

    Parameters
    ----------
    name : str
        The figure's label: lowercase letters, digits and hyphens, starting with ``fig-``
        (``{numref}`` refers to it); unique in the book.
    fig : matplotlib.figure.Figure
        The figure; it is finished (:func:`fusioncenter.plotting.finish`: labelled axes,
        legends outside the data, no text under the smallest font), rendered once as a PNG at
        :data:`fusioncenter.plotting.SAVE_DPI` with its alt text
        (:func:`fusioncenter.plotting.describe`), shown, and closed.

    Returns
    -------
    None
        In a notebook the PNG is displayed (an ordinary output in plain Jupyter, glued under
        ``name`` for the site); outside one nothing is shown.

    Raises
    ------
    ValueError
        If ``name`` is not of the form above, or an axis of ``fig`` lacks a label.
    """
    import re

    import matplotlib.pyplot as plt

    if not isinstance(name, str) or not re.fullmatch(r"fig-[a-z0-9]+(-[a-z0-9]+)*", name):
        raise ValueError(f"name must look like 'fig-part-topic' (lowercase letters, digits "
                         f"and hyphens), got {name!r}")
    plotting.finish(fig)
    if _shell() is not None:
        _show_png(fig, name)
    plt.close(fig)


def reproduce(entry_id: str, profile: str | None = None, seed: int | None = None):
    """Compute, plot and check one registry entry; fail loudly if a claim does not hold.

    In a notebook it shows the figure (a PNG at :data:`fusioncenter.plotting.SAVE_DPI`,
    glued under the entry's id for the site's ``registry-figure`` directive) and then the
    evidence: every claim with its value and verdict, as a collapsible table (plain text
    outside a notebook). Every claim is evaluated; if any fails, an ``AssertionError`` names
    the failed ones. Returns ``(data, figure)``.

    Parameters
    ----------
    entry_id : str
        The registry id, e.g. ``"dey2009-fig1"`` (``python -m fusioncenter list`` shows all).
    profile : str, optional
        ``"fast"`` or ``"paper"``; default :func:`fusioncenter.profile.current_profile`.
    seed : int, optional
        A non-negative seed; default the entry's own.

    Returns
    -------
    data : dict
        What the entry's ``compute`` returned
        (:meth:`fusioncenter.figures.entry.Entry.run_compute`, with the executor of
        :func:`fusioncenter.context.default_spec`).
    figure : matplotlib.figure.Figure
        What the entry's ``plot`` made of ``data``. Under IPython (a notebook) it has been
        shown and closed (``plt.close``), so that it is not shown a second time.

    Raises
    ------
    AssertionError
        If a claim does not hold (after the evidence has been shown).
    fusioncenter.figures.registry.UnknownEntry
        If no entry has the id (a ``KeyError``).
    fusioncenter.figures.entry.EntryNotReady
        If the entry has no compute, plot or checks yet.
    ValueError
        If ``profile`` or ``seed`` is invalid.
    """
    entry = figures.get(entry_id)
    profile = current_profile() if profile is None else profile
    data = entry.run_compute(profile, seed)
    fig = entry.run_plot(data)
    claims = entry.run_checks(data)
    if _shell() is not None:
        import matplotlib.pyplot as plt

        _show_png(fig, entry.id, profile=profile, seed=entry.seed if seed is None else seed)
        plt.close(fig)  # shown once, by the line above (the inline backend would repeat it)
    show_evidence(entry_id, claims, f"{entry_id}-evidence", "claims failed")
    return data, fig


# -- helpers for the chapters' own cells ------------------------------------------------------
# (SymPy and IPython are imported inside the functions: importing this module stays cheap.)


def show(lhs: str, rhs) -> None:
    """Display the equation ``lhs = rhs`` as LaTeX in the notebook.

    Parameters
    ----------
    lhs : str
        LaTeX source of the left-hand side, e.g. ``r"P_{k+1}"``.
    rhs : sympy.Basic or sympy.MatrixBase
        A SymPy expression or matrix; it is rendered with :func:`sympy.latex`.

    Returns
    -------
    None
        The equation is passed to :func:`IPython.display.display` as a
        :class:`IPython.display.Math` object.
    """
    import sympy as sp
    from IPython.display import Math, display

    display(Math(f"{lhs} = {sp.latex(rhs)}"))


def _canonical(expr, rewrite):
    """``cancel(together(expr))``, after ``expr.rewrite(rewrite)`` if ``rewrite`` is given."""
    import sympy as sp

    if rewrite is not None:
        expr = expr.rewrite(rewrite)
    return sp.cancel(sp.together(expr))


def assert_zero(expr, rewrite=None) -> None:
    """Assert that a SymPy expression, or every entry of a SymPy matrix, is exactly zero.

    Each entry is first put over a common denominator (``together``, then ``cancel``), which is
    exact and much faster than :func:`sympy.simplify` alone on expressions with matrix
    inverses; ``simplify`` then decides.

    Parameters
    ----------
    expr : sympy.Basic or sympy.MatrixBase
        The expression (or matrix) that should vanish identically.
    rewrite : sympy function class, optional
        If given, every entry is rewritten in terms of it first (``expr.rewrite(rewrite)``),
        e.g. ``sympy.erf`` so that ``erfc`` and ``erf`` terms can cancel.

    Returns
    -------
    None

    Raises
    ------
    AssertionError
        If the simplified expression (or some entry) is not zero; the message is ``expr``.
    """
    import sympy as sp

    if isinstance(expr, sp.MatrixBase):
        canonical = expr.applyfunc(lambda e: _canonical(e, rewrite))
        assert sp.simplify(canonical) == sp.zeros(*expr.shape), expr
    else:
        assert sp.simplify(_canonical(sp.sympify(expr), rewrite)) == 0, expr


def min_eig(M) -> float:
    """Smallest eigenvalue of the symmetric part of a square matrix.

    Parameters
    ----------
    M : array_like, shape (..., n, n)
        A square matrix, or a stack of them.

    Returns
    -------
    float
        The smallest eigenvalue of ``(M + M^T) / 2`` (over the whole stack); it is ``>= 0``
        exactly when every matrix is positive semi-definite.
    """
    import numpy as np

    M = np.asarray(M, dtype=float)
    return float(np.linalg.eigvalsh(0.5 * (M + np.swapaxes(M, -1, -2))).min())


def pm(value: float, stderr: float, digits: int = 3) -> str:
    """Format an estimate and its standard error as ``"value ± stderr"``.

    Parameters
    ----------
    value : float
        The estimate.
    stderr : float
        Its standard error (or any half-width).
    digits : int, default 3
        Number of decimals of both numbers.

    Returns
    -------
    str
        For example ``pm(1.23456, 0.01)`` is ``"1.235 ± 0.010"``.
    """
    return f"{value:.{digits}f} ± {stderr:.{digits}f}"


@_doc(returns=("IPython.display.Markdown", "The table (a header line, a ``|---|`` rule "
                     "and one line per row); a notebook shows it\nas a rendered table when it "
                     "is the value of a cell or passed to ``display``."))
def md_table(header, rows):
    """A Markdown table, for display in a notebook."""
    from IPython.display import Markdown

    return Markdown(markdown_table(header, rows))


@_doc(returns=("str", "The lines of the table joined by newlines."))
def markdown_table(header, rows) -> str:
    """The Markdown source of the table that :func:`md_table` displays."""
    lines = ["| " + " | ".join(_cell(c) for c in header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(_cell(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)


def _cell(value) -> str:
    """A table cell's text with its ``|`` kept out of the table's syntax: ``\\vert`` inside
    ``$...$`` mathematics (``$|z|$``), an escaped ``\\|`` elsewhere (one already escaped is
    kept)."""
    import re

    parts = re.split(r"(\$[^$]*\$)", str(value))
    return "".join(p.replace("|", r"\vert{}") if p.startswith("$") and p.endswith("$")
                   and len(p) > 1 else re.sub(r"(?<!\\)\|", r"\\|", p) for p in parts)
