"""Helpers that every chapter calls, so chapters stay short and alike."""

from __future__ import annotations

from fusioncenter import figures, plotting
from fusioncenter.glue import glue
from fusioncenter.profile import ENV_VAR, current_profile

__all__ = ["glue", "reproduce", "setup"]


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


def reproduce(entry_id: str, profile: str | None = None, seed: int | None = None):
    """Compute, plot and check one registry entry; fail loudly if a claim does not hold.

    Prints one line per claim and returns ``(data, figure)``.
    """
    entry = figures.get(entry_id)
    profile = current_profile() if profile is None else profile
    data = entry.run_compute(profile, seed)
    fig = entry.run_plot(data)
    claims = entry.run_checks(data)
    for c in claims:
        print(f"{'PASS' if c.passed else 'FAIL'}: {c.name} [{c.detail}]")
    failed = [c.name for c in claims if not c.passed]
    if failed:
        raise AssertionError(f"{entry_id}: claims failed: {failed}")
    return data, fig
