"""Registry entries of Part V (the side-by-side comparison chapter); the book's own figures."""

from __future__ import annotations

#: Ids of the book's own figures registered here (not figures of the paper).
OWN_IDS: tuple[str, ...] = ()
