"""The reproduction scorecard and the index of figures, generated from the registry.

Neither is ever written by hand. Both emit MyST markdown meant for a text column about 700 px
wide: a narrow table whose first column is the link to the chapter section that reproduces the
entry, and the long texts (caption, note, registry id) in a collapsed block under it.
"""

from __future__ import annotations

import re
from collections import Counter

from fusioncenter._docstrings import Glossary
from fusioncenter.figures.registry import PAPERS, entries

__all__ = ["paper_reference", "scorecard_markdown", "figure_index_markdown", "status_counts",
           "status_sentence", "status_rows"]

#: The argument of the counts.
_doc = Glossary("""
paper : str, optional
    Count only this paper's entries (default: all).
""")

_ROMAN = {1: "I", 2: "II", 3: "III", 4: "IV", 5: "V", 6: "VI", 7: "VII", 8: "VIII", 9: "IX",
          10: "X"}


def paper_reference(entry) -> str:
    """How the paper itself names the entry: ``"Fig. 3(a)"``, ``"Table II"``.

    Derived from the registry id (``leong2011-fig3a``, ``zheng2014-table2``). An entry that is
    not one of the paper's own figures or tables (the book's additions, variants such as
    ``zheng2014-table1-choices``) gives ``"book's own"``.

    Parameters
    ----------
    entry : Entry
        A registry entry (its ``id`` and ``paper`` are read).

    Returns
    -------
    str
        ``"Fig. N"``, ``"Fig. N(x)"``, ``"Table R"`` (Roman numeral) or ``"book's own"``.
    """
    suffix = entry.id[len(entry.paper) + 1:] if entry.id.startswith(entry.paper + "-") else ""
    m = re.fullmatch(r"fig(\d+)([a-z]?)", suffix)
    if m:
        return f"Fig. {m.group(1)}" + (f"({m.group(2)})" if m.group(2) else "")
    m = re.fullmatch(r"table(\d+)", suffix)
    if m and int(m.group(1)) in _ROMAN:
        return f"Table {_ROMAN[int(m.group(1))]}"
    return "book's own"


def _link(entry, text: str | None = None) -> str:
    if entry.label:
        return f"{{ref}}`{text} <{entry.label}>`" if text else f"{{ref}}`{entry.label}`"
    return f"{{doc}}`{text} </{entry.chapter}>`" if text else f"{{doc}}`/{entry.chapter}`"


def _cell(text: str) -> str:
    return " ".join(str(text).split()).replace("|", "\\|")


def _plain(text: str) -> str:
    """Registry prose as literal MyST text: no emphasis from ``_`` or ``*``, no roles."""
    text = " ".join(str(text).split())
    return re.sub(r"([\\`*_{}\[\]<>#|$])", r"\\\1", text)


def _rows(paper: str | None):
    if paper is not None and paper not in PAPERS:
        raise ValueError(f"paper must be one of {sorted(PAPERS)}, got {paper!r}")
    return [e for e in entries() if paper is None or e.paper == paper]


def _name(entry, with_paper: bool) -> str:
    ref = paper_reference(entry)
    return f"{entry.paper} {ref}" if with_paper else ref


def _details(rows, with_paper: bool, title: str) -> str:
    """A collapsed block: per entry its registry id, caption and note."""
    lines = [f":::{{admonition}} {title}", ":class: dropdown", ""]
    for e in rows:
        lines += [f"`{e.id}` ({_name(e, with_paper)}, {e.kind}, **{e.status}**)",
                  f": {_plain(e.caption)}", ""]
        if e.note:
            lines += [f"  *Note:* {_plain(e.note)}", ""]
    lines.append(":::")
    return "\n".join(lines)


def _table(paper: str | None, empty: str, header: tuple[str, ...], cells, after=None) -> str:
    """A MyST table of the entries of ``paper`` (of all if ``None``): the ``header``, then the
    ``cells(entry)`` of every entry, and ``after(entries)`` below it; ``empty`` if there are
    none."""
    rows = _rows(paper)
    if not rows:
        return empty
    lines = ["| " + " | ".join(header) + " |", "|" + " --- |" * len(header)]
    lines += ["| " + " | ".join(cells(e)) + " |" for e in rows]
    table = "\n".join(lines)
    return table if after is None else table + "\n\n" + after(rows)


def scorecard_markdown(paper: str | None = None) -> str:
    """The scorecard of one paper's entries (or of all): a narrow table, details collapsed.

    The table has three columns: the link to the section that reproduces the entry (named as
    the paper names it), its status, and the chapter. The caption, the note and the registry id
    of every entry follow in a collapsed block.

    Parameters
    ----------
    paper : str, optional
        A key of :data:`~fusioncenter.figures.papers.PAPERS` to list only that paper's entries; by
        default every entry is listed.

    Returns
    -------
    str
        The table and the collapsed block, in the registry's order; or one italic sentence if
        the paper has no entries.

    Raises
    ------
    ValueError
        If ``paper`` is not a known paper.
    """
    with_paper = paper is None

    def cells(e) -> tuple[str, str, str]:
        if paper_reference(e) == "book's own":  # no paper number: the section names it
            where = (f"{e.paper}, book's own" if with_paper else "book's own") + f": {_link(e)}"
        else:
            where = _link(e, _name(e, with_paper))
        return where, f"**{e.status}**", f"{{doc}}`/{e.chapter}`"

    return _table(paper, "*No registry entries for this paper yet: its part's issue adds them.*",
                  ("reproduced in", "status", "chapter"), cells,
                  lambda rows: _details(rows, with_paper,
                                        "Captions, notes and registry ids of these entries"))


def figure_index_markdown(paper: str) -> str:
    """The index of one paper's figures: paper figure -> chapter section -> registry id.

    Parameters
    ----------
    paper : str
        A key of :data:`~fusioncenter.figures.papers.PAPERS`.

    Returns
    -------
    str
        A three-column MyST table (the paper's name of the figure, a link to the section that
        reproduces it, the registry id), or one italic sentence if the paper has no entries.

    Raises
    ------
    ValueError
        If ``paper`` is not a known paper.
    """
    return _table(paper, "*No registry entries for this paper yet.*",
                  ("paper's figure", "reproduced in", "registry id"),
                  lambda e: (_cell(paper_reference(e)), _link(e), f"`{e.id}`"))


@_doc(returns=("dict of str to int", "The counts of ``\"reproduced\"``, ``\"differs\"`` "
                                    "and ``\"not-started\"`` entries, in that\norder (zero "
                                    "for a status no entry has)."))
def status_counts(paper: str | None = None) -> dict[str, int]:
    """How many entries have each status."""
    counts = Counter(e.status for e in entries() if paper is None or e.paper == paper)
    return {s: counts.get(s, 0) for s in ("reproduced", "differs", "not-started")}


@_doc(returns=("str", "The sentence (statuses no entry has are left out)."),
      raises=(("ValueError", "If ``paper`` is not a known paper."),))
def status_sentence(paper: str | None = None) -> str:
    """The entries' statuses in one sentence, e.g. ``"14 registry entries: 8 reproduced, 6
    differ from the paper."`` or ``"3 registry entries, all reproduced."``."""
    _rows(paper)  # validates the paper
    counts = status_counts(paper)
    total = sum(counts.values())
    if total == 0:
        return "No registry entries yet."
    head = f"{total} registry {'entry' if total == 1 else 'entries'}"
    if counts["reproduced"] == total:
        return f"{head}, {'reproduced' if total == 1 else 'all reproduced'}."
    d = counts["differs"]
    words = {"reproduced": f"{counts['reproduced']} reproduced",
             "differs": f"{d} {'differs' if d == 1 else 'differ'} from the paper",
             "not-started": f"{counts['not-started']} not started"}
    return head + ": " + ", ".join(words[k] for k, n in counts.items() if n) + "."


def status_rows() -> list[list]:
    """One row per paper (and the book's own figures), then the total: the name, the number
    of entries, and how many are reproduced, differ and are not started (for
    :func:`fusioncenter.book.md_table` with the header ``["paper", "entries", "reproduced",
    "differs", "not started"]``).

    Returns
    -------
    list of list
        ``[name, entries, reproduced, differs, not started]`` per paper, in the order of
        :data:`~fusioncenter.figures.papers.PAPERS` (the book's own figures as ``"book's
        own"``), and ``"total"`` last.
    """
    rows = []
    for paper in (*PAPERS, None):
        c = status_counts(paper)
        name = {"book": "book's own", None: "total"}.get(paper, paper)
        rows.append([name, sum(c.values()), *c.values()])
    return rows
