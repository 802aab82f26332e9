"""Helpers that every chapter calls, so chapters stay short and alike."""

from __future__ import annotations

import base64
import html
import textwrap

from fusioncenter import figures, plotting
from fusioncenter.profile import ENV_VAR, current_profile

#: Metadata key under which :func:`reproduce` stores what the site's figure directive needs.
FIGURE_METADATA = "fusioncenter"


def _inline_figures() -> None:
    """In a notebook kernel, display figures inline even if MPLBACKEND says otherwise."""
    try:
        from IPython import get_ipython
    except ImportError:  # pragma: no cover (IPython comes with the book's environment)
        return
    shell = get_ipython()
    if shell is not None and type(shell).__name__ == "ZMQInteractiveShell":
        shell.run_line_magic("matplotlib", "inline")


def setup() -> str:
    """Apply the plotting style and print (and return) the profile this chapter runs in."""
    import numpy as np

    _inline_figures()
    plotting.use_style()
    np.set_printoptions(precision=6, suppress=True)
    profile = current_profile()
    print(f"profile: {profile}  (set {ENV_VAR}=fast|paper to change it)")
    return profile


def _shell():
    try:
        from IPython import get_ipython
    except ImportError:  # pragma: no cover
        return None
    return get_ipython()


def _display(bundle: dict, metadata: dict) -> None:
    """Show a MIME bundle in a notebook; print its text elsewhere (tests, scripts)."""
    if _shell() is None:
        if "text/plain" in bundle:
            print(bundle["text/plain"])
        return
    from IPython.display import display

    display(bundle, raw=True, metadata=metadata)


def evidence_text(entry_id: str, claims) -> str:
    """The claims as wrapped plain text: one verdict line per claim, its detail indented."""
    held = sum(bool(c.passed) for c in claims)
    lines = [f"Evidence for {entry_id}: {held} of {len(claims)} claims hold"]
    for c in claims:
        lines += textwrap.wrap(f"{'PASS' if c.passed else 'FAIL'}: {c.name}", 88,
                               subsequent_indent="      ")
        if c.detail:
            lines += textwrap.wrap(str(c.detail), 88, initial_indent="      [",
                                   subsequent_indent="       ")
            lines[-1] += "]"
    return "\n".join(lines)


def evidence_html(entry_id: str, claims) -> str:
    """The claims as a collapsible table (claim, value or detail, verdict)."""
    held = sum(bool(c.passed) for c in claims)
    rows = "".join(
        f'<tr class="fc-{"pass" if c.passed else "fail"}"><td>{html.escape(c.name)}</td>'
        f"<td>{html.escape(str(c.detail))}</td>"
        f'<td class="fc-verdict">{"PASS" if c.passed else "FAIL"}</td></tr>'
        for c in claims)
    failed = held < len(claims)
    return (
        f'<details class="fc-evidence"{" open" if failed else ""}>'
        f"<summary>Evidence: {held} of {len(claims)} claims of <code>{html.escape(entry_id)}"
        f"</code> hold</summary>"
        '<table class="fc-evidence-table"><thead><tr><th>claim</th><th>value / detail</th>'
        f"<th>verdict</th></tr></thead><tbody>{rows}</tbody></table></details>"
    )


def _show_figure(entry, fig, profile: str, seed: int) -> None:
    png, facts = plotting.render(fig)
    meta = {**facts, "id": entry.id, "profile": profile, "seed": seed,
            "alt": plotting.describe(fig)}
    _display({"image/png": base64.b64encode(png).decode("ascii")},
             {"scrapbook": {"name": entry.id, "mime_prefix": ""}, FIGURE_METADATA: meta})


def reproduce(entry_id: str, profile: str | None = None, seed: int | None = None):
    """Compute, plot and check one registry entry; fail loudly if a claim does not hold.

    In a notebook it shows the figure (a PNG at :data:`fusioncenter.plotting.SAVE_DPI`,
    glued under the entry's id for the site's ``registry-figure`` directive) and then the
    evidence: every claim with its value and verdict, as a collapsible table (plain text
    outside a notebook). Every claim is evaluated; if any fails, an ``AssertionError`` names
    the failed ones. Returns ``(data, figure)``.
    """
    entry = figures.get(entry_id)
    profile = current_profile() if profile is None else profile
    data = entry.run_compute(profile, seed)
    fig = entry.run_plot(data)
    claims = entry.run_checks(data)
    if _shell() is not None:
        import matplotlib.pyplot as plt

        _show_figure(entry, fig, profile, entry.seed if seed is None else seed)
        plt.close(fig)  # shown once, by the line above (the inline backend would repeat it)
    _display({"text/plain": evidence_text(entry_id, claims),
              "text/html": evidence_html(entry_id, claims)},
             {"scrapbook": {"name": f"{entry_id}-evidence", "mime_prefix": ""}})
    failed = [c.name for c in claims if not c.passed]
    if failed:
        raise AssertionError(f"{entry_id}: claims failed: {failed}")
    return data, fig
