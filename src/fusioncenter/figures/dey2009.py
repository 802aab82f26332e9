"""Registry entries of Part II (dey2009): filled in by that part's issue.

A module of this package registers the real entries of its paper's figures (replacing the
catalog's ``not-started`` placeholders) and its own figures, whose ids it lists in ``OWN_IDS``.
"""

#: Ids of the book's own figures registered here (not figures of the paper).
OWN_IDS: tuple[str, ...] = ()
