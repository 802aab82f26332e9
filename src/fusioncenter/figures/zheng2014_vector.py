"""Registry entries of Part IV(b), vector observations (zheng2014 Section V, VII.B)."""

from __future__ import annotations

#: Ids of the book's own figures registered here (not figures of the paper).
OWN_IDS: tuple[str, ...] = ()
