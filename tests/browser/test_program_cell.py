"""In a real browser, teach a small pallet pick-and-place and run it: three corners, a loop until DI1 is HIGH,
a 2x2 pallet with the gripper closing in each cell, a relative approach to the place waypoint, the gripper
opening there, a relative retreat. The sensor (DI1, set through the simulator's /sim) ends the loop after a
pass. The saved file then runs the same way with `pendant run --robot` against the same pendant."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from collections.abc import Callable

import numpy as np
import pytest
from playwright.sync_api import Page, expect

from tests.support import preloaded
from tests.support.browser_pages import (
    ANGLE_TOL_DEG,
    ARTIFACTS,
    POLL_S,
    RUN_TIMEOUT_S,
    choose,
    move_to,
)
from tests.support.launchers import REPO_ROOT, Pendant
from tests.support.shared_pendants import NOT_REAL_TIME

# Not about real time: the shared pendant's simulator runs faster (tests/browser/conftest.py).
# alone: beside another worker the run did not reach "Finished" in time (CI, 27 Nov; not yet understood; in
# the serial pass the run was taken for finished before it started: mended below).
pytestmark = [pytest.mark.time_scale(NOT_REAL_TIME), pytest.mark.alone]

CORNERS_DEG = (
    [20.0, -90.0, 90.0, -90.0, -90.0, 0.0],
    [-20.0, -80.0, 80.0, -90.0, -90.0, 0.0],
    [0.0, -100.0, 100.0, -90.0, -90.0, 10.0],
)
PLACE_DEG = [45.0, -95.0, 95.0, -90.0, -90.0, 0.0]
POSITION_TOL_M = 0.002
CLICK_TIMEOUT_MS = 90_000
# The steps as listed (nesting is checked in the saved file: the list indents with em spaces).
EXPECTED_STEPS = [
    "Loop until DI1 HIGH",
    "Pallet 2x2 from P1, P2, P3 (approach 50 mm)",
    "Gripper close (500 ms)",
    "Move J to P4 z+50 mm (base) @ 20%",
    "Move J to P4 @ 20%",
    "Gripper open (500 ms)",
]


def click(page: Page, name: str) -> None:
    page.get_by_role("button", name=name, exact=True).click()


def edit(page: Page, name: str) -> None:
    """Click an editing button and wait until the page shows its edit (the selected step changes), as the
    operator looks before the next click: the pendant handles a browser's clicks on a pool of threads, and
    one sent before the last was done could apply to the step selected before it (a "lost" click)."""
    selected = page.get_by_label("Step", exact=True).first
    before = selected.input_value()
    click(page, name)
    expect(selected).not_to_have_value(before)


def wait_text(page: Page, text: str) -> None:
    page.get_by_text(text).first.wait_for(timeout=CLICK_TIMEOUT_MS)  # as long as a click may take


def tcp(pendant: Pendant) -> np.ndarray:
    point = pendant.api.get("/position").json()["point"]
    return np.array([point["x"], point["y"], point["z"]])


def near_place_then_sensor(pendant: Pendant, done: Callable[[], bool]) -> None:
    """Once the arm has been at the place waypoint, say the tray is empty (DI1 HIGH); wait for `done()`."""
    deadline = time.monotonic() + RUN_TIMEOUT_S
    while not np.allclose(pendant.pose(), PLACE_DEG, atol=ANGLE_TOL_DEG):
        assert time.monotonic() < deadline, f"the arm never reached the place waypoint ({pendant.pose()})"
        time.sleep(POLL_S)
    pendant.api.put("/sim/signal/input/1/high").raise_for_status()
    while not done():
        assert time.monotonic() < deadline, "the run did not finish"
        time.sleep(POLL_S)


def test_teach_and_run_a_pallet_pick_and_place(page: Page, pendant: Pendant) -> None:
    # Some thirty clicks on a page drawn by software WebGL: a loaded machine may take a while per click.
    page.set_default_timeout(CLICK_TIMEOUT_MS)
    take_control = page.get_by_role("button", name="Take control")
    if take_control.is_visible():
        take_control.click()
    page.get_by_role("tab", name="Program").click()
    # Nested steps are built in place: each new step goes after the selected one (by default: at the end).
    page.get_by_label("Insert after selected step", exact=True).check()

    for k, angles in enumerate(CORNERS_DEG, start=1):  # the tray's corners: waypoints without a move
        move_to(pendant, angles)
        click(page, "Add waypoint here")
        wait_text(page, f"P{k} (0 uses)")  # taught here, before the arm moves on
    edit(page, "Loop")
    wait_text(page, "1. Loop 2 times")
    choose(page, "times", "until")  # Input DI1, Level HIGH are the defaults
    wait_text(page, "1. Loop until DI1 HIGH")
    edit(page, "Pallet")  # from the last three waypoints taught
    edit(page, "Indent")  # into the loop
    edit(page, "Gripper close")
    edit(page, "Indent")  # into the pallet: done at each cell
    move_to(pendant, PLACE_DEG)
    click(page, "Add waypoint here")
    wait_text(page, "P4 (0 uses)")
    edit(page, "Relative move")  # 50 mm above P4 (the waypoint chosen in the table)
    edit(page, "Outdent")  # after the pallet, in the loop
    edit(page, "Move to waypoint")  # P4 itself, as the selected move
    edit(page, "Gripper open")
    edit(page, "Relative move")  # and back up
    for text in EXPECTED_STEPS:
        wait_text(page, text)
    page.screenshot(path=str(ARTIFACTS / "program-cell-taught.png"))

    # Away from P4 first (it was taught there): the run must bring the arm to the place waypoint itself. And
    # a pendant shared with an earlier module may still show its last run's "Finished" until this run starts.
    move_to(pendant, CORNERS_DEG[0])
    click(page, "Run")
    wait_text(page, "Running step")
    near_place_then_sensor(pendant, lambda: page.get_by_text("Finished").first.is_visible())
    page.screenshot(path=str(ARTIFACTS / "program-cell-finished.png"))
    p4 = tcp(pendant) - np.array([0.0, 0.0, 0.05])
    move_to(pendant, PLACE_DEG)
    np.testing.assert_allclose(tcp(pendant), p4, atol=POSITION_TOL_M)  # it ended 50 mm above P4

    # The text box in the row labelled "Save as name" (viser's label is not tied to its input).
    label = page.get_by_text("Save as name", exact=True)
    name_box = label.locator("xpath=ancestor::div[.//input][1]//input").first
    name_box.fill("cell")
    name_box.press("Enter")
    click(page, "Save as")
    saved = pendant.programs / "cell.json"
    deadline = time.monotonic() + 10.0
    while not saved.exists():
        assert time.monotonic() < deadline, "Save as wrote no file"
        time.sleep(POLL_S)
    loop = json.loads(saved.read_text())["steps"][0]
    assert (loop["kind"], loop["mode"], loop["port"], loop["level"]) == ("loop", "until", 1, "HIGH")
    assert [s["kind"] for s in loop["body"]] == ["pallet", "move", "move", "gripper", "move"]
    assert [s["kind"] for s in loop["body"][0]["body"]] == ["gripper"]
    assert [s["offset"] is not None for s in loop["body"] if s["kind"] == "move"] == [True, False, True]

    # The same file, headless, against the same controller.
    pendant.api.put("/sim/signal/input/1/low").raise_for_status()  # a full tray again
    move_to(pendant, CORNERS_DEG[0])
    env = {**os.environ, "PYTHONPATH": str(REPO_ROOT)}
    process = preloaded.popen(
        [sys.executable, "-m", "pendant", "run", str(saved), "--robot", str(pendant.api.base_url)],
        cwd=REPO_ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
    )
    near_place_then_sensor(pendant, lambda: process.poll() is not None)
    out, err = process.communicate()
    assert process.returncode == 0, err
    assert "step 2/7: Pallet 2x2 from P1, P2, P3" in out
    move_to(pendant, PLACE_DEG)
    np.testing.assert_allclose(tcp(pendant), p4, atol=POSITION_TOL_M)
