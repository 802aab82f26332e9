"""Registry entries of Part IV(b), nonlinear tracking (zheng2014 Section VI, VII.C-D)."""

from __future__ import annotations

#: Ids of the book's own figures registered here (not figures of the paper).
OWN_IDS: tuple[str, ...] = ()
