"""Regenerate docs/pendant.png: a real pendant (simulator) in Debian's chromium, running a taught program.

Run: .venv/bin/python scripts/screenshot.py [--out docs/pendant.png]
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import httpx

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from tests.support.ports import free_port
from tests.support.waiting import wait_until

CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking"]
VIEWPORT = {"width": 1400, "height": 860}
# A short pick-and-place taught through the API, as an operator would jog there and press Record.
TEACH_DEG = ([20.0, -80.0, 100.0, -110.0, -90.0, 0.0], [-30.0, -70.0, 80.0, -100.0, -90.0, 0.0])
SPEED_PERCENT = 40


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="docs/pendant.png")
    args = parser.parse_args()
    from playwright.sync_api import sync_playwright

    ui_port, api_port = free_port(), free_port()
    programs = tempfile.mkdtemp(prefix="pendant-programs-")
    process = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "pendant",
            "--ui-port",
            str(ui_port),
            "--api-port",
            str(api_port),
            "--programs",
            programs,
        ],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    api = httpx.Client(base_url=f"http://127.0.0.1:{api_port}", timeout=5.0)

    def idle() -> bool:
        return api.get("/status/motion").text.strip('"') == "IDLE"

    try:
        wait_until(lambda: api.get("/pose").status_code == 200)
        with sync_playwright() as playwright:
            browser = playwright.chromium.launch(executable_path="/usr/bin/chromium", args=CHROMIUM_ARGS)
            page = browser.new_page(viewport=VIEWPORT)
            page.goto(f"http://127.0.0.1:{ui_port}/")
            page.get_by_role("button", name="Freeze").wait_for(timeout=30_000)
            close = page.get_by_text("Software WebGL rendering detected")  # viser's notice, not ours
            if close.is_visible():
                page.locator(".mantine-Notification-closeButton").first.click()
            page.get_by_role("tab", name="Program").click()
            for angles in TEACH_DEG:
                api.put("/pose", params={"speed": SPEED_PERCENT}, json={"angles": angles})
                wait_until(idle)
                page.get_by_role("button", name="Record", exact=True).click()
                time.sleep(0.5)
            api.put("/signal/output/1/high")
            page.get_by_role("button", name="Run", exact=True).click()
            time.sleep(1.8)  # mid-way: the arm moving, the trail drawn, the step highlighted
            page.screenshot(path=args.out)
            browser.close()
    finally:
        process.terminate()
        process.wait(10)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
