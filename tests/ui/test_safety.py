"""The arm's safety state in the page, headless: system state, protective stop, stop bound to an input, free
drive, identity and failures; and a controller without the SDK 1.8 operations greys those features out."""

from __future__ import annotations

import contextlib
import time
from collections.abc import Callable, Iterator
from typing import Any

import pytest

from pendant.api.app import create_app
from pendant.controller import MotionStatus, SignalLevel
from pendant.controller.system_types import SystemState
from pendant.remote import RemoteController
from pendant.sim import SimController
from pendant.ui.app import PendantUI
from pendant.ui.page.session import ClientSession
from tests.support.doubles import OPERATOR, VIEWER, FakeBrowser, fire
from tests.support.pages import new_page
from tests.support.threads import serve_in_thread
from tests.support.waiting import SAFETY_NET_S

WAIT_S = SAFETY_NET_S
SDK18_ONLY = (
    "/environment",
    "/status/failure",
    "/robot/info",
    "/version",
    "/tool/info",
    "/tool/shape",
    "/stop",
    "/zg",
)


def wait_for(condition: Callable[[], bool], what: str) -> None:
    deadline = time.monotonic() + WAIT_S
    while not condition():
        assert time.monotonic() < deadline, f"timed out waiting for {what}"
        time.sleep(0.02)


def test_the_status_shows_the_system_state(
    pendant_ui: PendantUI, ui: ClientSession, sim: SimController
) -> None:
    pendant_ui.refresh_cell()
    assert "system <b" in ui.status.content and ">ACTIVE</b>" in ui.status.content
    sim.zg_on()
    pendant_ui.refresh_cell()
    assert ">ZERO_GRAVITY</b>" in ui.status.content
    assert ui.robot_safety.free_drive.value is True  # the toggle follows the controller


def test_any_browser_may_stop_and_the_dashboard_lists_why(
    pendant_ui: PendantUI, ui: ClientSession, sim: SimController
) -> None:
    viewer = FakeBrowser(VIEWER)
    assert ui.status.stop.visible and ui.banner is not None and ui.banner.view is None
    fire(ui.status.stop, viewer)  # like Freeze: stopping is never refused
    wait_for(lambda: sim.get_motion_status() is MotionStatus.ERROR, "the protective stop")
    pendant_ui.refresh()
    pendant_ui.refresh_cell()
    assert "Protective stop (POST /stop)" in ui.failures.content
    assert "STOP_2" in ui.failures.content
    assert viewer.notifications == []
    # Recover is the banner's (under Freeze): one Recover in the whole page.
    assert ui.banner is not None and [b.label for b in ui.banner.buttons if b.visible] == ["Recover"]
    assert not ui.status.recover.visible and not ui.status.stop.visible
    assert "Recover" not in ui.robot_buttons

    fire(ui.banner.buttons[0], FakeBrowser(OPERATOR))
    wait_for(lambda: sim.get_motion_status() is MotionStatus.IDLE, "the recovery")
    pendant_ui.refresh()
    assert ui.status.stop.visible and ui.banner.view is None


def test_the_robot_tab_binds_the_stop_to_an_input_level(ui: ClientSession, sim: SimController) -> None:
    operator = FakeBrowser(OPERATOR)
    fire(ui.robot_safety.stop_port, operator, "DI1")
    fire(ui.robot_safety.stop_level, operator, "HIGH")
    ui.robot_safety.bind_stop(operator.handle).result(timeout=WAIT_S)
    assert sim.get_motion_status() is MotionStatus.IDLE
    sim.set_input(1, SignalLevel.HIGH)
    assert sim.get_motion_status() is MotionStatus.ERROR
    assert "digital input 1 went HIGH" in sim.get_failures()[-1].message


def test_the_free_drive_toggle_relaxes_the_arm(ui: ClientSession, sim: SimController) -> None:
    operator = FakeBrowser(OPERATOR)
    ui.robot_safety.set_free_drive(True, operator.handle).result(timeout=WAIT_S)
    assert sim.get_system_state() is SystemState.ZERO_GRAVITY
    ui.robot_safety.set_free_drive(False, operator.handle).result(timeout=WAIT_S)
    assert sim.get_system_state() is SystemState.ACTIVE


def test_the_robot_tab_shows_the_identity_and_versions(
    pendant_ui: PendantUI, ui: ClientSession, sim: SimController
) -> None:
    pendant_ui.refresh_cell()
    info = sim.get_robot_info()
    assert f"model {info.model}" in ui.robot_safety.identity.content
    assert sim.get_software_version().safetyVersion in ui.robot_safety.identity.content


class OlderFirmware:
    """The simulator's API as an older controller answers it: 404 to every SDK 1.8 operation (or to the
    paths under `missing`)."""

    def __init__(self, app: Any, missing: tuple[str, ...] = (*SDK18_ONLY, "/status")) -> None:
        self._app = app
        self._missing = missing

    async def __call__(self, scope: dict[str, Any], receive: Any, send: Any) -> None:
        path = scope.get("path", "")
        if scope["type"] == "http" and (path.startswith(self._missing) and path != "/status/motion"):
            await send(
                {"type": "http.response.start", "status": 404, "headers": [(b"content-type", b"text/plain")]}
            )
            await send({"type": "http.response.body", "body": b"Not Found"})
            return
        await self._app(scope, receive, send)


@contextlib.contextmanager
def page_on(controller_app: Any, sim: SimController) -> Iterator[tuple[PendantUI, ClientSession]]:
    """A page whose browser is the operator, on a real HTTP controller serving `controller_app`."""
    with serve_in_thread(controller_app) as url:
        remote = RemoteController(url)
        page = new_page(remote, sim.arm, mode_line="Robot")
        page.desk.join(OPERATOR)
        page.refresh()
        page.refresh_cell()
        session = page.open_session(page.server)
        try:
            yield page, session
        finally:
            page.stop()


@pytest.fixture
def old_firmware_page(sim: SimController) -> Iterator[tuple[PendantUI, ClientSession]]:
    """A page on a real HTTP controller that answers 404 to every SDK 1.8 operation (older firmware)."""
    with page_on(OlderFirmware(create_app(sim)), sim) as served:
        yield served


def test_an_older_controller_greys_the_sdk18_features_out(
    old_firmware_page: tuple[PendantUI, ClientSession],
) -> None:
    page, ui = old_firmware_page
    page.refresh_cell()
    ui.show_cell(page.cell_state, page.identity, cell_changed=False)
    assert page.latest.motion_status is MotionStatus.IDLE  # the rest of the page works
    assert isinstance(page.controller, RemoteController) and page.controller.health().online  # not "offline"
    assert "**Cell unavailable:** The controller does not support GET /environment" in ui.cell.note.content
    assert ui.cell.apply.disabled and ui.cell.load.disabled
    assert "system state: not on this controller" in ui.status.content
    assert ui.status.stop.disabled
    assert "Failures unavailable" in ui.failures.content
    assert "not reported by this controller (older firmware)" in ui.robot_safety.identity.content
    assert ui.tool_shape.set_shape.disabled and ui.tool_shape.capsules.disabled
    assert "**Tool shape unavailable:** The controller does not support GET /tool/shape" in (
        ui.tool_shape.availability.note.content
    )
    robot = ui.robot_safety
    assert robot.free_drive.disabled and robot.bind.disabled and robot.unbind.disabled
    assert "**Free drive unavailable:** this controller has no SDK 1.8 safety operations" in (
        robot.free_drive_availability.note.content
    )
    ui.apply_role(OPERATOR)  # control handed over again: what the controller lacks stays greyed out
    assert ui.tool_shape.set_shape.disabled and robot.free_drive.disabled and ui.cell.apply.disabled


def test_a_command_the_controller_lacks_is_greyed_out_after_its_404(sim: SimController) -> None:
    """A controller with /status but without /zg and /stop/bind (a partial firmware): the first press says
    so, the toggle springs back, and the controls are greyed out from then on."""
    app = OlderFirmware(create_app(sim), missing=("/zg", "/stop/bind"))
    with page_on(app, sim) as (page, ui):
        page.refresh_cell()
        robot, operator = ui.robot_safety, FakeBrowser(OPERATOR)
        assert not robot.free_drive.disabled and not robot.bind.disabled  # nothing says they are missing
        fire(robot.free_drive, operator, True)
        wait_for(lambda: robot.free_drive.disabled, "free drive greyed out")
        assert operator.notifications == [
            "Free drive on refused: The controller does not support PUT /zg/on (HTTP 404: older firmware)"
        ]
        assert robot.free_drive.value is False  # sprang back: the arm is not in free drive
        assert sim.get_motion_status() is MotionStatus.IDLE
        fire(robot.bind, operator)
        wait_for(lambda: robot.bind.disabled and robot.unbind.disabled, "the input stop greyed out")
        assert "**Stop on input unavailable:**" in robot.input_stop.note.content
