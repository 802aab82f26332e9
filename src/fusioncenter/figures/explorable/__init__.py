"""The book's explorable figures: in each part one registry entry whose parameter the reader
moves (:mod:`fusioncenter.explore`), one module per part.

Each module of a part registers an ordinary entry (compute, plot, checks) with a settable
parameter and a :class:`fusioncenter.explore.Slider` over a grid of it (both with
:func:`fusioncenter.figures.explorable.declare.register`), and lists the entry in ``OWN_IDS``.
The chapters show it with :func:`fusioncenter.explore.explore` and the site's
``{explorable-figure}`` directive. Every frame is the entry's compute at one value of the grid,
so the slider shows nothing that ``python -m fusioncenter compute ID --set NAME=VALUE`` would
not.
"""

import importlib as _importlib
import pkgutil as _pkgutil

# Importing the package registers every part's entry (the registry's _load imports it); the
# lazy index imports only the module of the entry asked for.
#: The ids of the entries every module of the package registers (the registry's ``own_ids``).
OWN_IDS: tuple[str, ...] = ()
for _module in _pkgutil.iter_modules(__path__):
    _part = _importlib.import_module(f"{__name__}.{_module.name}")
    OWN_IDS += getattr(_part, "OWN_IDS", ())  # declare registers nothing
