"""How the browser tests and the jog benchmark start Debian's Chromium (software WebGL, no sandbox)."""

from __future__ import annotations

import shutil

CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"
# WebUIOmniboxPopup off: Chromium 156 builds its address bar's suggestion popup as a hidden WebUI page (its
# own renderer, lit components) for every new window, and every test's fresh context is a new window: 0.5-0.75
# CPU-s each (4 Dec: an empty context and page 1.24-1.53 CPU-s of Chromium, 0.76 with it off), ~130 a run.
# Headless shows no address bar; what the pendant's page draws and runs is the same either way.
CHROMIUM_ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-features=WebUIOmniboxPopup",
]
