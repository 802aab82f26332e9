"""``glue``: store a value in a notebook's outputs so that the prose can quote it.

A chapter quotes a computed number in its text with the MyST role ``{glue:text}`name:.4f```;
the number is stored by calling :func:`glue` in a code cell. In the book build this is MyST-NB's
own ``myst_nb.glue``. In plain Jupyter (a downloaded chapter, Colab, Binder) MyST-NB is usually
absent, and :func:`glue` then writes the same output itself: a display-data output whose
metadata carries ``{"scrapbook": {"name": ..., "mime_prefix": ...}}``, the format MyST-NB reads
back. A chapter therefore runs, and stores the same values, with or without MyST-NB.
"""

from __future__ import annotations

from typing import Any

#: MyST-NB's prefix for the MIME types of a value glued with ``display=False`` (not rendered).
GLUE_PREFIX = "application/papermill.record/"


def _fallback_glue(name: str, variable: Any, display: bool = True) -> None:
    from IPython.core.formatters import format_display_data
    from IPython.display import display as ipy_display

    mimebundle, metadata = format_display_data(variable)
    mime_prefix = "" if display else GLUE_PREFIX
    metadata["scrapbook"] = {"name": name, "mime_prefix": mime_prefix}
    ipy_display({mime_prefix + k: v for k, v in mimebundle.items()}, raw=True, metadata=metadata)


def glue(name: str, variable: Any, display: bool = True) -> None:
    """Store ``variable``'s display value under ``name`` in the notebook's outputs.

    Parameters
    ----------
    name : str
        The key the prose refers to (``{glue:text}`name```); a non-empty string.
    variable : object
        The value; what is stored is its display representation (``text/plain`` and any
        richer MIME type IPython produces for it). A NumPy scalar is stored as the Python
        number it holds: NumPy 2 shows ``np.float64(0.6)``, which a format such as
        ``{glue:text}`name:.3f``` cannot read.
    display : bool, default True
        Also show the value in the cell's output. ``False`` stores it hidden.

    Returns
    -------
    None
    """
    if not isinstance(name, str) or not name:
        raise ValueError(f"name must be a non-empty string, got {name!r}")
    import numpy as np

    if isinstance(variable, np.generic):
        variable = variable.item()
    try:
        from myst_nb import glue as myst_glue
    except ImportError:
        myst_glue = _fallback_glue
    myst_glue(name, variable, display=display)
