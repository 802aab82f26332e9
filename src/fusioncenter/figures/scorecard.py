"""The reproduction scorecard, generated from the registry (never written by hand)."""

from __future__ import annotations

from collections import Counter

from fusioncenter.figures.registry import PAPERS, entries


def _link(entry) -> str:
    if entry.label:
        return f"{{ref}}`{entry.label}`"
    return f"{{doc}}`/{entry.chapter}`"


def _cell(text: str) -> str:
    return " ".join(str(text).split()).replace("|", "\\|")


def scorecard_markdown(paper: str | None = None) -> str:
    """The scorecard table of the registry's entries, as MyST Markdown.

    Parameters
    ----------
    paper : str, optional
        A key of :data:`~fusioncenter.figures.registry.PAPERS` to list only that paper's entries; by
        default every entry is listed.

    Returns
    -------
    str
        A table with one row per entry (paper, id, caption, status, note and a link to the
        chapter section that reproduces it), in the registry's order; or one italic sentence if
        the paper has no entries.

    Raises
    ------
    ValueError
        If ``paper`` is not a known paper.
    """
    if paper is not None and paper not in PAPERS:
        raise ValueError(f"paper must be one of {sorted(PAPERS)}, got {paper!r}")
    rows = [e for e in entries() if paper is None or e.paper == paper]
    if not rows:
        return "*No registry entries for this paper yet: its part's issue adds them.*"
    lines = [
        "| paper | id | figure / table | status | note | where |",
        "| --- | --- | --- | --- | --- | --- |",
    ]
    for e in rows:
        lines.append(
            f"| {e.paper} | `{e.id}` | {_cell(e.caption)} | **{e.status}** | "
            f"{_cell(e.note) or '—'} | {_link(e)} |"
        )
    return "\n".join(lines)


def status_counts(paper: str | None = None) -> dict[str, int]:
    """How many entries have each status.

    Parameters
    ----------
    paper : str, optional
        Count only this paper's entries (default: all).

    Returns
    -------
    dict of str to int
        The counts of ``"reproduced"``, ``"differs"`` and ``"not-started"`` entries, in that
        order (zero for a status no entry has).
    """
    counts = Counter(e.status for e in entries() if paper is None or e.paper == paper)
    return {s: counts.get(s, 0) for s in ("reproduced", "differs", "not-started")}
