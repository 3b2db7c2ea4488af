"""A recording survives its pendant, with real processes: start a recording with the Dashboard's button in a
real browser, let it run ~10 s while the arm moves, then end the pendant. SIGTERM finishes the file; after
kill -9 the next pendant started on the same data folder repairs it and says so in its event log. Either way
the official reader reads back at least 8 s of /joints samples."""

from __future__ import annotations

import re
import signal
from pathlib import Path

import pytest
from playwright.sync_api import Browser

from pendant.telemetry.repair import finished
from tests.support.browser_pages import ARTIFACTS, open_tab, take_control
from tests.support.failure_pages import describe_pages
from tests.support.launchers import STOP_TIMEOUT_S, Pendant
from tests.support.launchers import running_pendant_ui as running_pendant
from tests.support.mcap_reading import read_mcap
from tests.support.waiting import wait_until

# A recording's samples a second on a real clock: run alone, after the rest.
pytestmark = [pytest.mark.slow, pytest.mark.measures]

RECORD_S = 10.0
SIGTERM_EXIT = 128 + signal.SIGTERM  # the shell's convention for "ended by SIGTERM"
SURVIVING_S = 8.0  # what must read back: the 10 s less the last flush (1 s) and a loaded machine's start
REPAIR_TIMEOUT_S = 60.0
UI_TIMEOUT_MS = 60_000  # a loaded machine draws the first page slowly
MOVE_SPEED_PERCENT = 20
FAR_DEG = [60.0, -60.0, 60.0, -90.0, -90.0, 30.0]


def record_for_a_while(browser: Browser, pendant: Pendant) -> None:
    """Press Start recording on the Dashboard (this browser has control on loopback), move the arm, and
    wait RECORD_S while the pendant records."""
    page = browser.new_page(viewport={"width": 1400, "height": 900})
    page.set_default_timeout(UI_TIMEOUT_MS)
    try:
        page.goto(pendant.ui_url)
        page.get_by_role("button", name="Freeze").wait_for(timeout=UI_TIMEOUT_MS)
        take_control(page)  # on a loaded machine the page may say whose control it is only later
        open_tab(page, "Dashboard")
        page.get_by_role("button", name="Start recording").click()
        page.get_by_text(re.compile(r"Recording · \d+ samples")).first.wait_for(timeout=UI_TIMEOUT_MS)
        pendant.api.put(
            "/pose", params={"speed": MOVE_SPEED_PERCENT}, json={"angles": FAR_DEG}
        ).raise_for_status()
        page.wait_for_timeout(RECORD_S * 1000)  # a real process recording on a real clock
        page.screenshot(path=str(ARTIFACTS / "recording-survives.png"))
    except Exception as error:
        # What the page showed, while its pendant still runs (the report's look comes after the pendant
        # has gone): a clean clone's "Recording · N samples" that never came left nothing to read.
        error.add_note(describe_pages(browser, "record_for_a_while"))
        error.add_note(f"what its pendant said last:\n{pendant.said()}")
        raise
    finally:
        page.close()


def joint_samples(folder: Path) -> tuple[Path, list[int]]:
    """The one recording in `folder` and its /joints log times (ns), read with the official reader."""
    [path] = sorted((folder / "recordings").glob("pendant-*.mcap"))
    assert finished(path), f"{path.name} is not a finished MCAP file"
    _, messages = read_mcap(path)
    return path, [time_ns for topic, time_ns, _ in messages if topic == "/joints"]


def rate_line(how: str, times: list[int]) -> str:
    span_s = (times[-1] - times[0]) / 1e9
    return (
        f"{how}: {len(times)} /joints samples over {span_s:.1f} s = {(len(times) - 1) / span_s:.1f} a second"
    )


def test_sigterm_finishes_the_recording(browser: Browser, tmp_path: Path) -> None:
    with running_pendant(env={"PENDANT_DATA_DIR": str(tmp_path)}) as pendant:
        record_for_a_while(browser, pendant)
        assert pendant.process is not None
        pendant.process.send_signal(signal.SIGTERM)
        assert pendant.process.wait(STOP_TIMEOUT_S) == SIGTERM_EXIT, "it exits by itself, not killed"
    path, times = joint_samples(tmp_path)
    span_s = (times[-1] - times[0]) / 1e9
    print(rate_line("SIGTERM", times))
    assert span_s >= SURVIVING_S, f"only {span_s:.1f} s of /joints in {path.name}"
    assert path.with_suffix(".csv").is_file(), "the CSV is written beside it when the recording stops"


def test_after_kill_9_the_next_start_repairs_the_recording(browser: Browser, tmp_path: Path) -> None:
    data = {"PENDANT_DATA_DIR": str(tmp_path)}
    with running_pendant(env=data) as pendant:
        record_for_a_while(browser, pendant)
        assert pendant.process is not None
        pendant.process.kill()
        pendant.process.wait(STOP_TIMEOUT_S)
    [left] = sorted((tmp_path / "recordings").glob("pendant-*.mcap"))
    assert not finished(left), "kill -9 leaves the file unfinished"
    with running_pendant(env=data) as again:
        # The repair runs beside the start-up: the pendant serves first, and says so once it is done.
        def said() -> list[str]:
            errors = again.api.get("/pendant/events", params={"kind": "error", "text": "repaired"}).json()
            return [event["message"] for event in errors["events"]]

        wait_until(
            lambda: any(left.stem in m and "repaired" in m for m in said()), REPAIR_TIMEOUT_S, "repair"
        )
    path, times = joint_samples(tmp_path)
    span_s = (times[-1] - times[0]) / 1e9
    print(rate_line("kill -9, repaired", times))
    assert span_s >= SURVIVING_S, f"only {span_s:.1f} s of /joints survived in {path.name}"
