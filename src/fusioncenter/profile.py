"""Execution profiles.

``fast``  seconds per figure: used by the tests, nbval and the strict site build.
``paper`` the papers' own trial, path and particle counts: used by the published site.

The book selects the profile with the environment variable ``FUSIONCENTER_PROFILE``.
"""

from __future__ import annotations

import os

PROFILES = ("fast", "paper")
ENV_VAR = "FUSIONCENTER_PROFILE"
DEFAULT_PROFILE = "fast"


def check_profile(profile: str) -> str:
    """Return ``profile`` if it is a known profile, else raise ``ValueError``."""
    if profile not in PROFILES:
        raise ValueError(f"profile must be one of {PROFILES}, got {profile!r}")
    return profile


def current_profile() -> str:
    """The profile selected by ``FUSIONCENTER_PROFILE`` (default ``fast``)."""
    value = os.environ.get(ENV_VAR, DEFAULT_PROFILE).strip() or DEFAULT_PROFILE
    try:
        return check_profile(value)
    except ValueError:
        raise ValueError(
            f"environment variable {ENV_VAR}={value!r}: expected one of {PROFILES}"
        ) from None


def by_profile(profile: str, *, fast, paper):
    """Pick the value for ``profile``: ``by_profile(p, fast=200, paper=50_000)``."""
    return {"fast": fast, "paper": paper}[check_profile(profile)]
