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
    """A MyST table of the entries (of one paper, or all): id, what, status, note, chapter."""
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
    counts = Counter(e.status for e in entries() if paper is None or e.paper == paper)
    return {s: counts.get(s, 0) for s in ("reproduced", "differs", "not-started")}
