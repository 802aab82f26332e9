"""A figure's alt text: what each panel plots against what, and its curves, in plain words
(``describe``; mathtext becomes Unicode)."""

from __future__ import annotations

import re

__all__ = ["describe"]

_GREEK = dict(zip(
    "alpha beta gamma delta epsilon varepsilon zeta eta theta kappa lambda mu nu xi pi rho "
    "sigma tau phi varphi chi psi omega Gamma Delta Theta Lambda Xi Pi Sigma Phi Psi "
    "Omega".split(), "αβγδεεζηθκλμνξπρστφφχψωΓΔΘΛΞΠΣΦΨΩ", strict=True))
_SYMBOLS = {"top": "ᵀ", "infty": "∞", "le": "≤", "leq": "≤", "ge": "≥", "geq": "≥",
            "times": "×", "cdot": "·", "pm": "±", "to": "→", "sim": "∼", "approx": "≈",
            "mid": "|", "ell": "ℓ", "sqrt": "√", "log": "log", "exp": "exp", "ln": "ln",
            "min": "min", "max": "max", "quad": " ", "qquad": " ", "left": "", "right": ""}


def _plain(s: str) -> str:
    """Mathtext to readable text for alt text: ``$\\sigma_v^2$`` -> ``σ_v^2``, ``\\mathbf{h}^\\top``
    -> ``hᵀ`` (Greek letters and common symbols in Unicode, font commands and accents
    dropped)."""
    s = s.replace("$", "")
    s = re.sub(r"\\(mathrm|mathbf|mathit|mathcal|text|textbf|operatorname|mathbb|boldsymbol)"
               r"\{([^}]*)\}", r"\2", s)
    s = re.sub(r"\\(tilde|bar|hat|check|vec|overline|widehat|widetilde)\s*", "", s)
    s = re.sub(r"\^\{?\\top\}?", "ᵀ", s)
    s = re.sub(r"\\([A-Za-z]+)",
               lambda m: _GREEK.get(m[1], _SYMBOLS.get(m[1], m[1])), s)
    return re.sub(r"[{}]", "", s).replace("\\,", " ").replace("\\ ", " ").strip()


def describe(fig) -> str:
    """Alt text: for every panel, what it plots against what, and its curves (legend labels).

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure; only visible axes with data are described.

    Returns
    -------
    str
        A sentence naming the number of panels (and the figure's title), then per panel its
        title, "y label against x label" (with "(log scale)" for a log y axis) and its legend
        labels, mathtext turned into plain text.
    """
    axes = [ax for ax in fig.get_axes() if ax.get_visible() and ax.has_data()]
    parts = []
    sup = fig._suptitle.get_text() if fig._suptitle is not None else ""
    head = f"{len(axes)}-panel figure" if len(axes) > 1 else "Figure"
    parts.append(head + (f" ({_plain(sup)})" if sup else "") + ".")
    for i, ax in enumerate(axes):
        leg = ax.get_legend()
        title = ax.get_title() or (leg.get_title().get_text() if leg is not None else "")
        scale = " (log scale)" if ax.get_yscale() == "log" else ""
        s = (f"Panel {i + 1}" + (f", {_plain(title)}" if title else "") + f": "
             f"{_plain(ax.get_ylabel())}{scale} against {_plain(ax.get_xlabel())}")
        if leg is not None:
            labels = [_plain(t.get_text()) for t in leg.get_texts()]
            s += "; curves: " + "; ".join(labels)
        parts.append(s + ".")
    return " ".join(parts)
