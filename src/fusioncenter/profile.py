"""Execution profiles.

``fast``  seconds per figure: used by the tests, nbval and the strict site build.
``paper`` the papers' own trial, path and particle counts: used by the published site.

The book selects the profile with the environment variable ``FUSIONCENTER_PROFILE``.
"""

from __future__ import annotations

import os

#: The known profiles.
PROFILES = ("fast", "paper")
#: The environment variable that selects the profile of a chapter or a build.
ENV_VAR = "FUSIONCENTER_PROFILE"
#: The profile used when :data:`ENV_VAR` is unset.
DEFAULT_PROFILE = "fast"


def check_profile(profile: str) -> str:
    """Check that a profile name is known.

    Parameters
    ----------
    profile : str
        ``"fast"`` or ``"paper"`` (see :data:`PROFILES`).

    Returns
    -------
    str
        ``profile`` itself.

    Raises
    ------
    ValueError
        If ``profile`` is not one of :data:`PROFILES`.
    """
    if profile not in PROFILES:
        raise ValueError(f"profile must be one of {PROFILES}, got {profile!r}")
    return profile


def current_profile() -> str:
    """The profile selected by the environment variable ``FUSIONCENTER_PROFILE``.

    Returns
    -------
    str
        The variable's value with surrounding blanks removed, or ``"fast"`` if it is unset or
        blank.

    Raises
    ------
    ValueError
        If the variable names an unknown profile.
    """
    value = os.environ.get(ENV_VAR, DEFAULT_PROFILE).strip() or DEFAULT_PROFILE
    try:
        return check_profile(value)
    except ValueError:
        raise ValueError(
            f"environment variable {ENV_VAR}={value!r}: expected one of {PROFILES}"
        ) from None


def by_profile(profile: str, *, fast, paper):
    """Pick the value that belongs to a profile, e.g. ``by_profile(p, fast=200, paper=50_000)``.

    Parameters
    ----------
    profile : str
        ``"fast"`` or ``"paper"``.
    fast, paper : object
        The values for the two profiles (keyword-only).

    Returns
    -------
    object
        ``fast`` or ``paper``, whichever ``profile`` names.

    Raises
    ------
    ValueError
        If ``profile`` is unknown.
    """
    return {"fast": fast, "paper": paper}[check_profile(profile)]
