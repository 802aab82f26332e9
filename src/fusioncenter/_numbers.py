"""The number syntax of ``--set`` values (:meth:`fusioncenter.context.Parameter.parse`)."""

from __future__ import annotations


def number(name: str, text: str, kind: str):
    """The number a ``--set`` value spells. Both kinds read Python's number syntax: digits
    with optional ``_`` separators (``4_00`` is 400) and scientific notation (``1e3``); an
    ``int`` accepts a scientific value only when it is a whole number (``1e3`` is 1000,
    ``1.5`` and ``1e-3`` are refused), read exactly (no rounding through a float)."""
    import re
    from decimal import Decimal, InvalidOperation

    t = text.strip()
    try:
        if re.search(r"(?<![0-9])_|_(?![0-9])", t):  # "_" only between digits, as in Python
            raise ValueError
        if kind != "int":
            return float(t)
        try:
            return int(t)
        except ValueError:
            d = Decimal(t)
            if not d.is_finite() or d != d.to_integral_value():
                raise ValueError from None
            return int(d)
    except (ValueError, InvalidOperation):
        what = "an integer" if kind == "int" else "a number"
        raise ValueError(f"parameter {name}: expected {what}, got {t!r}") from None
