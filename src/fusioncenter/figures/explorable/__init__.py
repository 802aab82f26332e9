"""The book's explorable figures: in each part one registry entry whose parameter the reader
moves (:mod:`fusioncenter.explore`), one module per part.

Each module registers an ordinary entry (compute, plot, checks) with a settable parameter and a
:class:`fusioncenter.explore.Slider` over a grid of it, and lists the entry in ``OWN_IDS``. The
chapters show it with :func:`fusioncenter.explore.explore` and the site's
``{explorable-figure}`` directive. Every frame is the entry's compute at one value of the grid,
so the slider shows nothing that ``python -m fusioncenter compute ID --set NAME=VALUE`` would
not.
"""
