"""SIGTERM ends the page's pre-flight at once (issue #32): a real `pendant` whose operator pressed Check on a
program that takes minutes to check exits within QUIT_TIMEOUT_S of the signal. Before, the check ran on in a
worker thread that Python waits for at exit, and the process stayed up to the pre-flight's 30 s budget."""

from __future__ import annotations

import asyncio
import json
import signal
import subprocess
from pathlib import Path

import httpx

from pendant.program.files import AUTOSAVE_FILE
from tests.support.headless_viewer import click_message, find_button, open_viewer
from tests.support.launchers import Pendant, running_pendant_ui
from tests.support.programs import swings_file
from tests.support.waiting import wait_until

# As the API's pre-flight test: quitting is a freeze and closing the servers, seconds even at nice 19 on a
# loaded machine; well short of the 30 s pre-flight budget the process used to wait out.
QUIT_TIMEOUT_S = 20.0
PAGE_TIMEOUT_S = 60.0


async def check_then_sigterm(pendant: Pendant) -> None:
    """As the page's first browser (the operator): press Check, and once it runs, SIGTERM the pendant; the
    browser stays open meanwhile."""
    assert pendant.process is not None
    ws = await open_viewer(pendant.ui_port)
    try:
        await ws.send(click_message(await find_button(ws, "Check", PAGE_TIMEOUT_S)))
        await asyncio.to_thread(wait_until, lambda: checking(pendant.api), PAGE_TIMEOUT_S, "the Check")
        pendant.process.send_signal(signal.SIGTERM)
        await asyncio.to_thread(pendant.process.wait, QUIT_TIMEOUT_S)
    finally:
        await ws.close()


def checking(api: httpx.Client) -> bool:
    events = api.get("/pendant/events", params={"kind": "command", "text": "Check"}).json()["events"]
    return any(event["message"] == "Check" for event in events)


def test_sigterm_ends_the_pages_running_check_and_the_process(tmp_path: Path) -> None:
    programs = tmp_path / "programs"
    programs.mkdir()
    # The program on the page at start.
    autosave = {"program": swings_file(5000), "file_name": None, "dirty": True}
    (programs / AUTOSAVE_FILE).write_text(json.dumps(autosave))
    with running_pendant_ui("--programs", str(programs)) as pendant:
        try:
            asyncio.run(check_then_sigterm(pendant))
        except subprocess.TimeoutExpired:
            raise AssertionError(f"the pendant still ran {QUIT_TIMEOUT_S:g} s after SIGTERM") from None
