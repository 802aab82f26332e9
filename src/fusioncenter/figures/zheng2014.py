"""Registry entries of Part IV (zheng2014). Filled in by the Part IV issues."""

from __future__ import annotations

#: Ids of the book's own figures registered here (not figures of the paper).
OWN_IDS: tuple[str, ...] = ()
