"""How the browser tests and the jog benchmark start Debian's Chromium (software WebGL, no sandbox)."""

from __future__ import annotations

import shutil

CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"
# WebUIOmniboxPopup and WebUIOmniboxAimPopup off: Chromium 156 builds its address bar's suggestion popup, and
# its "AI mode" popup (chrome://omnibox-popup.top-chrome/omnibox_popup_aim.html), as hidden WebUI pages (a
# renderer each, lit components) for every new window, and every test's fresh context is a new window, ~130 a
# run. An empty context and page cost 1.24-1.53 CPU-s of Chromium with both (4 Dec), 0.76 with the first off,
# 0.36-0.39 with both off (against 0.91-0.94 the same hour; CDP's Target.getTargets then lists no
# browser_ui target). Headless shows no address bar; what the pendant's page draws and runs is the same.
CHROMIUM_ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-features=WebUIOmniboxPopup,WebUIOmniboxAimPopup",
]
