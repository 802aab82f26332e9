"""Let Sphinx read the book in parallel: declare what three extensions leave undeclared.

Sphinx reads the sources in parallel (``-j``, as ``tools/build_book.py`` renders) only if every
extension says it may; ``sphinx_multitoc_numbering`` and ``sphinx_jupyterbook_latex`` (loaded by
jupyter-book) and ``sphinx-mathjax-offline`` say nothing, so Sphinx warns and reads on one core.
None of them keeps anything per document while reading: the first replaces the section
numbering of the toctree collector (run in the main process after the documents are merged)
and sets its state at ``builder-inited`` (before the reading processes are forked), the second
adds transforms and sets two flags at ``builder-inited``, the third copies MathJax at
``build-finished``. They are declared safe here, on ``config-inited`` (every extension loaded);
a declaration they make themselves in a later version is left as it is.

Parallel reading also merges each domain's data from the reading processes, and
``sphinx_proof``'s domain has no ``merge_domaindata`` (Sphinx then stops the build). That domain
keeps no data of its own (its ``initial_data`` is empty: the proofs are in ``env.proof_list``,
which ``sphinx_proof`` merges itself on ``env-merge-info``), so there is nothing to merge: it
gets a ``merge_domaindata`` that does nothing, unless it has one or keeps data.

The HTML of a parallel build is that of a serial one (checked file by file when this was added).
"""

from __future__ import annotations

from sphinx.domains import Domain

UNDECLARED = ("sphinx_multitoc_numbering", "sphinx_jupyterbook_latex", "sphinx-mathjax-offline")


def _declare(app, config) -> None:
    for name in UNDECLARED:
        ext = app.extensions.get(name)
        if ext is not None and ext.parallel_read_safe is None:
            ext.parallel_read_safe = True
    domain = app.registry.domains.get("prf")
    if domain is not None and domain.merge_domaindata is Domain.merge_domaindata \
            and not domain.initial_data:
        domain.merge_domaindata = _nothing_to_merge


def _nothing_to_merge(self, docnames, otherdata) -> None:
    """``merge_domaindata`` of a domain without data of its own."""


def setup(app):
    app.connect("config-inited", _declare)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1.0"}
