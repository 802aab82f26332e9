"""The mark that ties a test to an entry of the errata page (``book/errata.md``).

Every erratum whose evidence is an executable check has a test, marked
``@erratum("erratum-<paper>-<slug>")`` with the entry's label on the page, that evaluates the
**printed** form and asserts that the check rejects it (and that the correction passes it): the
mutation a wrong correction would survive. ``tests/test_errata_page.py`` checks that every such
entry has one, and that the entries whose evidence is reading say so.
"""

from __future__ import annotations

import pytest


def erratum(label: str):
    """Mark a test as the printed-form check of the erratum labelled ``label``."""
    if not label.startswith("erratum-"):
        raise ValueError(f"label must start with 'erratum-', got {label!r}")
    return pytest.mark.erratum(label)
