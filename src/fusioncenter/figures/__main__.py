"""``python -m fusioncenter.figures``: write the registry's index; ``--check``: test it is current.

The index (:mod:`fusioncenter.figures._index`) is built from the registry
(:func:`fusioncenter.figures.registry.build_index`, which imports every figure module). With
``--check`` (``make test``'s stage "index") nothing is imported or written: the command fails
when the committed file no longer matches the library's source.
"""

from __future__ import annotations

import sys

from fusioncenter.figures import _index, registry


def main(argv: list[str]) -> int:
    """Write the index, or with ``["--check"]`` only check it.

    Parameters
    ----------
    argv : list of str
        The command's arguments: ``[]`` or ``["--check"]``.

    Returns
    -------
    int
        The exit status: 0, or 1 if the checked index is out of date.
    """
    if argv == ["--check"]:
        if _index.load() is None:
            print(f"error: {_index.PATH} is out of date (the library's source changed since it "
                  "was written): run `python -m fusioncenter.figures` and commit it",
                  file=sys.stderr)
            return 1
        print(f"{_index.PATH.name}: current ({len(_index.load() or [])} entries)",
              file=sys.stderr)
        return 0
    registry.build_index()
    print(f"wrote {_index.PATH} ({len(_index.load() or [])} entries)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
