"""What the operator types is what is used, focus stays where the operator put it, one truth (issue 31, 3-5).

One page for the whole module. Typed fast or slowly, "-69.3" in the Target tab's J1 box is where Move J
takes joint 1 (the server's answer to "-6" used to land in the box after "-69" was typed). A box left
empty or holding letters refuses the action that needs it, with the reason, and nothing moves or is added.
While the arm moves (driven through the API), the jog pad's J2+ keeps the keyboard focus. A refused upload
says only the refusal (not viser's "File uploaded successfully." beside it). Run pressed with Enter (disabled
while its run goes) leaves the focus in the panel, not on the page's body.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator
from pathlib import Path

import numpy as np
import pytest
from playwright.sync_api import Browser, Page

from tests.support.browser_pages import obstacles
from tests.support.jog_measure import ensure_operator
from tests.support.launchers import Pendant
from tests.support.typed import type_into, typed_box
from tests.support.waiting import wait_until

TYPED_DEG = -69.3
ANGLE_TOL_DEG = 0.01
MOVE_TIMEOUT_S = 60.0
SHOWN_TIMEOUT_MS = 15_000
HOLD_S = 0.6
MOVING_S = 2.0  # issue 31: focus unchanged after 2 s of motion
SLOW_SPEED_PERCENT = 5  # a 60° move outlasts MOVING_S
LOADED_CPU_SLOWDOWN = 4  # the page's CPU 4x slower (Chromium's throttling): keys 40 ms apart then race too


@pytest.fixture(scope="module")
def page(browser: Browser, pendant: Pendant) -> Iterator[Page]:
    page = browser.new_page(viewport={"width": 1400, "height": 900})
    page.goto(pendant.ui_url)
    ensure_operator(page)
    yield page
    page.close()


def go_home(pendant: Pendant) -> None:
    """Every joint at home (through the API), at rest."""
    wait_until(lambda: pendant.status() == "IDLE", MOVE_TIMEOUT_S, "the arm at rest")
    home = [0.0, -90.0, 90.0, -90.0, -90.0, 0.0]
    pendant.api.put("/pose", params={"speed": 100}, json={"angles": home}).raise_for_status()
    wait_until(
        lambda: np.allclose(pendant.pose(), home, atol=ANGLE_TOL_DEG) and pendant.status() == "IDLE",
        MOVE_TIMEOUT_S,
        "home",
    )


@pytest.mark.parametrize(("delay_ms", "cpu_slowdown"), [(0, 1), (20, 1), (40, LOADED_CPU_SLOWDOWN)])
def test_j1_typed_at_any_pace_is_where_move_j_goes(
    page: Page, pendant: Pendant, delay_ms: int, cpu_slowdown: int
) -> None:
    go_home(pendant)
    cdp = page.context.new_cdp_session(page)
    cdp.send("Emulation.setCPUThrottlingRate", {"rate": cpu_slowdown})  # a loaded machine, as in the issue
    try:
        typed_and_moved(page, pendant, delay_ms)
    finally:
        cdp.send("Emulation.setCPUThrottlingRate", {"rate": 1})
        cdp.detach()


def typed_and_moved(page: Page, pendant: Pendant, delay_ms: int) -> None:
    page.get_by_role("tab", name="Target").click()
    page.get_by_role("button", name="Target = current").click()
    type_into(page, "Move speed %", "100")  # a quick move (the speed typed is the one used too)
    box = type_into(page, "J1 °", f"{TYPED_DEG}", delay_ms=delay_ms)
    assert box.input_value() == f"{TYPED_DEG}"  # the box still says what was typed
    page.get_by_role("button", name="Move J").click()
    wait_until(
        lambda: abs(pendant.pose()[0] - TYPED_DEG) < ANGLE_TOL_DEG and pendant.status() == "IDLE",
        MOVE_TIMEOUT_S,
        f"joint 1 at {TYPED_DEG}° (it is at {pendant.pose()[0]:.2f}°)",
    )
    assert box.input_value() == f"{TYPED_DEG}"


def typed_paced(page: Page, cpu_slowdown: int, typing: Callable[[], None]) -> None:
    """`typing()` with the page's CPU `cpu_slowdown` times slower (Chromium's throttling), then back."""
    cdp = page.context.new_cdp_session(page)
    cdp.send("Emulation.setCPUThrottlingRate", {"rate": cpu_slowdown})
    try:
        typing()
    finally:
        cdp.send("Emulation.setCPUThrottlingRate", {"rate": 1})
        cdp.detach()


def type_and_leave(page: Page, label: str, text: str, delay_ms: int) -> None:
    """Type `text` into the box, one key every `delay_ms`, and leave it uncommitted: the next click commits
    it (leaving the box), as an operator who types and presses the action straight away."""
    box = typed_box(page, label)
    box.click()
    box.press("ControlOrMeta+a")
    box.press_sequentially(text, delay=delay_ms)


PACES = [(0, 1), (20, 1), (40, LOADED_CPU_SLOWDOWN)]
OBSTACLE_AT_MM = (TYPED_DEG, 250.0, 100.0)  # "-69.3, 250, 100": x is the number typed


@pytest.mark.parametrize(("delay_ms", "cpu_slowdown"), PACES)
def test_an_obstacle_position_typed_at_any_pace_is_where_add_obstacle_puts_it(
    page: Page, pendant: Pendant, delay_ms: int, cpu_slowdown: int
) -> None:
    """Committed by pressing Add obstacle straight after typing (no Enter): the box is at x -69.3 mm."""
    pendant.api.delete("/environment").raise_for_status()
    page.get_by_role("tab", name="Cell").click()
    type_into(page, "Name", f"typed{delay_ms}")
    typed = ", ".join(f"{v:g}" for v in OBSTACLE_AT_MM)

    def typing() -> None:
        type_and_leave(page, "Position mm", typed, delay_ms)
        page.get_by_role("button", name="Add obstacle").click()

    typed_paced(page, cpu_slowdown, typing)
    try:
        wait_until(lambda: len(obstacles(pendant)) == 1, MOVE_TIMEOUT_S, "the obstacle added")
        point = obstacles(pendant)[0]["centerPosition"]["point"]
        np.testing.assert_allclose([point[k] * 1000.0 for k in "xyz"], OBSTACLE_AT_MM, atol=1e-6)
        assert typed_box(page, "Position mm").input_value() == typed
    finally:
        pendant.api.delete("/environment").raise_for_status()


@pytest.mark.parametrize(("delay_ms", "cpu_slowdown"), PACES)
def test_j2_typed_at_any_pace_and_left_with_tab_is_where_move_j_goes(
    page: Page, pendant: Pendant, delay_ms: int, cpu_slowdown: int
) -> None:
    """Another joint's box, committed by leaving it (Tab; Move J stays disabled until the typed target is
    committed and checked), then Move J: joint 2 ends at -69.3 degrees."""
    go_home(pendant)
    page.get_by_role("tab", name="Target").click()
    page.get_by_role("button", name="Target = current").click()
    type_into(page, "Move speed %", "100")

    def typing() -> None:
        type_into(page, "J2 °", f"{TYPED_DEG}", delay_ms=delay_ms, commit="Tab")
        page.get_by_role("button", name="Move J").click()

    typed_paced(page, cpu_slowdown, typing)
    wait_until(
        lambda: abs(pendant.pose()[1] - TYPED_DEG) < ANGLE_TOL_DEG and pendant.status() == "IDLE",
        MOVE_TIMEOUT_S,
        f"joint 2 at {TYPED_DEG}° (it is at {pendant.pose()[1]:.2f}°)",
    )


TOOL_AT_MM = (TYPED_DEG, 0.0, 120.0)  # "-69.3, 0, 120": the TCP's offset from the flange, x as typed


@pytest.mark.parametrize(("delay_ms", "cpu_slowdown"), PACES)
def test_a_tool_offset_typed_at_any_pace_is_the_tool_set(
    page: Page, pendant: Pendant, delay_ms: int, cpu_slowdown: int
) -> None:
    """The Robot tab's tool XYZ (where Move L and the jogs take the TCP), committed by pressing Set tool
    straight after typing: the controller's tool is at x -69.3 mm."""
    before = pendant.api.get("/tool").json()
    page.get_by_role("tab", name="Robot").click()
    if not typed_box(page, "XYZ mm").is_visible():  # the folder starts folded; the page is the module's
        page.get_by_text("Tool (TCP offset from the flange)").click()
    typed_box(page, "XYZ mm").wait_for(timeout=SHOWN_TIMEOUT_MS)
    typed = ", ".join(f"{v:g}" for v in TOOL_AT_MM)

    def typing() -> None:
        type_and_leave(page, "XYZ mm", typed, delay_ms)  # the first: the tool's (the base's follows)
        page.get_by_role("button", name="Set tool").click()

    typed_paced(page, cpu_slowdown, typing)
    try:
        tool_mm = lambda: [pendant.api.get("/tool").json()["point"][k] * 1000.0 for k in "xyz"]  # noqa: E731
        wait_until(
            lambda: np.allclose(tool_mm(), TOOL_AT_MM, atol=1e-6), MOVE_TIMEOUT_S, f"the tool at {typed}"
        )
    finally:
        pendant.api.post("/tool", json=before).raise_for_status()


def test_the_boxs_earlier_text_typed_again_while_the_server_changed_it_is_the_one_used(
    page: Page, pendant: Pendant
) -> None:
    """J2 -69.3 is typed and run; the target follows the arm again and, while the operator is in the box,
    the arm goes home (the server's -90 is kept out of the box being edited). The operator types -69.3
    again and leaves the box: that is the target (main: the page dropped the commit, as the text was the
    box's earlier one; the box said -69.3, the server kept -90 and Move J stayed disabled)."""
    go_home(pendant)
    page.get_by_role("tab", name="Target").click()
    page.get_by_role("button", name="Target = current").click()
    type_into(page, "Move speed %", "100")
    type_into(page, "J2 °", f"{TYPED_DEG}", commit="Tab")
    page.get_by_role("button", name="Move J").click()
    wait_until(
        lambda: abs(pendant.pose()[1] - TYPED_DEG) < ANGLE_TOL_DEG and pendant.status() == "IDLE",
        MOVE_TIMEOUT_S,
        "joint 2 at the first -69.3",
    )
    page.get_by_role("button", name="Target = current").click()
    box = typed_box(page, "J2 °")
    box.click()
    box.press("ControlOrMeta+a")
    go_home(pendant)  # the server writes J2 -90 into the box while the operator is in it: held back
    page.locator('input[aria-label="J2 °"][data-pendant-held]').wait_for(timeout=SHOWN_TIMEOUT_MS)
    box.press_sequentially(f"{TYPED_DEG}")
    box.press("Tab")
    page.get_by_role("button", name="Move J").click(timeout=SHOWN_TIMEOUT_MS)
    wait_until(
        lambda: abs(pendant.pose()[1] - TYPED_DEG) < ANGLE_TOL_DEG and pendant.status() == "IDLE",
        MOVE_TIMEOUT_S,
        f"joint 2 at {TYPED_DEG}° again (it is at {pendant.pose()[1]:.2f}°)",
    )


def test_an_empty_or_lettered_box_refuses_the_action_with_the_reason(page: Page, pendant: Pendant) -> None:
    go_home(pendant)
    # Jog speed with letters: J1+ held does not move the arm, and says why.
    page.get_by_role("tab", name="Jog").click()
    type_into(page, "Speed %", "fifty")
    page.get_by_text("⚠ 'fifty' is not a number").wait_for(timeout=SHOWN_TIMEOUT_MS)  # marked by the box
    before = np.array(pendant.pose())
    j1_plus = page.get_by_role("button", name="J1+", exact=True)
    j1_plus.hover()
    page.mouse.down()
    time.sleep(HOLD_S)
    page.mouse.up()
    page.get_by_text("Speed %: 'fifty' is not a number").first.wait_for(timeout=SHOWN_TIMEOUT_MS)
    np.testing.assert_allclose(pendant.pose(), before, atol=ANGLE_TOL_DEG)
    type_into(page, "Speed %", "10")
    # An obstacle's position emptied: Add obstacle adds nothing, and says why.
    page.get_by_role("tab", name="Cell").click()
    type_into(page, "Position mm", "")
    # The box marked first, as the operator sees it before pressing: the mark's line moves Add obstacle
    # down. In two full runs (4 Dec) the press came before it and nothing followed (no refusal, no
    # obstacle, the box marked); most likely it was aimed at the button's old place (not reproduced alone).
    page.get_by_text("⚠ empty: type 3 numbers").wait_for(timeout=SHOWN_TIMEOUT_MS)
    page.get_by_role("button", name="Add obstacle").click()
    page.get_by_text("Position mm: empty").first.wait_for(timeout=SHOWN_TIMEOUT_MS)
    assert pendant.api.get("/environment").json() == []


def test_focus_on_j2_plus_stays_while_the_arm_moves(page: Page, pendant: Pendant) -> None:
    go_home(pendant)
    page.get_by_role("tab", name="Jog").click()
    j2_plus = page.get_by_role("button", name="J2+", exact=True)
    j2_plus.focus()
    far = [60.0, -90.0, 90.0, -90.0, -90.0, 0.0]
    pendant.api.put("/pose", params={"speed": SLOW_SPEED_PERCENT}, json={"angles": far}).raise_for_status()
    try:
        wait_until(lambda: pendant.status() == "RUNNING", MOVE_TIMEOUT_S, "the move started")
        time.sleep(MOVING_S)
        assert pendant.status() == "RUNNING"  # the pad's values changed meanwhile
        focused = page.evaluate(
            "() => document.activeElement && document.activeElement.getAttribute('aria-label')"
        )
        assert focused == "J2+"
    finally:
        pendant.api.put("/freeze").raise_for_status()


def test_a_refused_upload_says_only_the_refusal(page: Page, tmp_path: Path) -> None:
    bad = tmp_path / "not_a_program.json"
    bad.write_text("{ this is not json")
    page.get_by_role("tab", name="Program").click()
    page.locator("input[type=file]").first.set_input_files(str(bad))
    page.get_by_text("Upload refused").first.wait_for(timeout=SHOWN_TIMEOUT_MS)
    time.sleep(0.5)  # the page's pass over the notifications
    assert not page.get_by_text("File uploaded successfully.").is_visible()
    assert not page.get_by_text("File received.").is_visible()


def test_run_pressed_with_enter_leaves_the_focus_on_the_panel(page: Page, pendant: Pendant) -> None:
    go_home(pendant)
    page.get_by_role("tab", name="Program").click()
    page.get_by_role("button", name="Record", exact=True).click()
    page.get_by_text("Move J to P1").first.wait_for(timeout=SHOWN_TIMEOUT_MS)
    far = [90.0, -90.0, 90.0, -90.0, -90.0, 0.0]
    pendant.api.put("/pose", params={"speed": 100}, json={"angles": far}).raise_for_status()
    wait_until(
        lambda: abs(pendant.pose()[0] - 90.0) < ANGLE_TOL_DEG and pendant.status() == "IDLE",
        MOVE_TIMEOUT_S,
        "far",
    )
    run = page.get_by_role("button", name="Run", exact=True)
    run.focus()
    page.keyboard.press(
        "Enter"
    )  # the run goes back to P1 (seconds at the step's 20 %): Run is disabled meanwhile
    wait_until(lambda: pendant.status() == "RUNNING", MOVE_TIMEOUT_S, "the run moving the arm")
    time.sleep(MOVING_S)
    focused = page.evaluate(
        "() => document.activeElement === document.body ? null : document.activeElement.textContent"
    )
    pendant.api.put("/freeze").raise_for_status()
    assert focused is not None, "the focus fell to the page's body"
