"""Headless Chromium on the built site, as the browser check and the PDF printer drive it.

The browser is Debian's (``/usr/lib/chromium/chromium-headless-shell``, else ``chromium``;
playwright's own browser downloads are never used), started with :data:`CHROMIUM_ARGS` and a
resolver that knows no host but the loopback (:data:`LOOPBACK_ONLY`). The site is served to it
from a local HTTP server (:class:`LoopbackServer`, on :data:`LOCAL_HOST`), and pages load in a
window of :data:`VIEWPORT`.

Used by ``tools/browser_check`` (which reports every request to another host) and
``tools/pdf_book.py`` (which prints the pages it loads); neither imports the other.
"""

from __future__ import annotations

import http.server
import os
import shutil
import socketserver
from pathlib import Path

#: Debian's old headless shell (package chromium-headless-shell: the same Blink, no browser UI),
#: else Debian's chromium. On the fast site the shell takes 75.6 s for this check against 88.1 s
#: and 75.7 s against 87.7 s for the PDF's pages, with the same layout and figure measurements.
HEADLESS_SHELL = "/usr/lib/chromium/chromium-headless-shell"
CHROMIUM = (os.environ.get("FUSIONCENTER_CHROMIUM")
            or (HEADLESS_SHELL if os.access(HEADLESS_SHELL, os.X_OK) else None)
            or shutil.which("chromium") or "/usr/bin/chromium")
#: Chromium's resolver knows no host but the loopback (``LOCAL_HOST`` is an IP literal).
LOOPBACK_ONLY = "--host-resolver-rules=MAP * ~NOTFOUND, EXCLUDE 127.0.0.1"
CHROMIUM_ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]
INSTALL_HINT = ("install Debian's browser with `apt-get install chromium "
                "chromium-headless-shell`")
LOCAL_HOST = "127.0.0.1"
#: The window every page is loaded in (the browser check measures the layout there; the PDF's
#: print layout does not depend on it: the 238 pages of the API page print the same from
#: 1000 x 1400 and 400 x 900).
VIEWPORT = {"width": 1280, "height": 900}


def launch(playwright):
    """Start :data:`CHROMIUM` headless through ``playwright`` (a ``sync_playwright()``).

    Parameters
    ----------
    playwright
        The object ``sync_playwright()`` enters.

    Returns
    -------
    playwright.sync_api.Browser
        The browser; every host but the loopback fails to resolve in it.
    """
    if not Path(CHROMIUM).exists():
        raise FileNotFoundError(f"{CHROMIUM} not found")
    # every host but the loopback fails to resolve at once, inside Chromium: an external
    # request is reported by the "request" listener of the browser check and cannot reach
    # anything
    return playwright.chromium.launch(
        executable_path=CHROMIUM, args=[*CHROMIUM_ARGS, LOOPBACK_ONLY], headless=True)


class QuietHandler(http.server.SimpleHTTPRequestHandler):
    """Serves a folder (``directory=``) without logging each request."""

    def log_message(self, format: str, *args: object) -> None:  # noqa: A002 (the base's name)
        pass


class LoopbackServer(socketserver.ThreadingMixIn, http.server.HTTPServer):
    """A threaded HTTP server (one daemon thread per request), bound by its caller to
    :data:`LOCAL_HOST` on a free port."""

    daemon_threads = True
    allow_reuse_address = True
