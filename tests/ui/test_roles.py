"""One operator, many viewers: the server refuses a viewer's commands, the token guards control on an exposed
pendant, and the operator leaving stops a jog. Headless: sessions on the server's GUI, stand-in clients."""

from __future__ import annotations

from collections.abc import Iterator
from concurrent.futures import Future

import numpy as np
import pytest

from pendant.controller import MotionParams, MotionStatus, Pose
from pendant.eventlog import EventKind
from pendant.jog import JogFrame, JogRequest
from pendant.program import RunState
from pendant.sim import FakeClock, SimController
from pendant.ui.app import PendantUI
from pendant.ui.kit.commands import CommandRefused
from pendant.ui.kit.view_only import VIEW_ONLY_HINT
from pendant.ui.page.roles import MSG_NO_TOKEN, MSG_WRONG_TOKEN
from tests.support.doubles import FakeBrowser, fire
from tests.support.pages import new_page

TOKEN = "s3cret-token"
ANGLE_TOL_DEG = 1e-9
FUTURE_TIMEOUT_S = 60.0  # a safety net: a thread starved of CPU (nice 19, a loaded machine) may take seconds
HOME_MOVE = Pose(angles=[20.0, -90.0, 0.0, -90.0, -90.0, 0.0])


def _ui(sim: SimController, token: str | None) -> PendantUI:
    page = new_page(sim, sim.arm, token=token)
    page.refresh()
    return page


@pytest.fixture
def local_ui(sim: SimController) -> Iterator[PendantUI]:
    page = _ui(sim, token=None)
    yield page
    page.stop()


@pytest.fixture
def exposed_ui(sim: SimController) -> Iterator[PendantUI]:
    page = _ui(sim, token=TOKEN)
    yield page
    page.stop()


def angles(sim: SimController) -> np.ndarray:
    return np.asarray(sim.get_pose().angles)


def move(ui: PendantUI, client: FakeBrowser) -> Future[object]:
    return ui.runner.submit(
        "Move J", lambda c: c.set_pose(HOME_MOVE, MotionParams(speed=50.0)), client.handle
    )


def test_first_local_browser_operates_and_a_second_one_only_watches(
    local_ui: PendantUI, sim: SimController, clock: FakeClock
) -> None:
    operator, viewer = FakeBrowser(1), FakeBrowser(2)
    local_ui.desk.join(1)
    local_ui.desk.join(2)
    assert local_ui.desk.operator == 1

    before = angles(sim)
    with pytest.raises(CommandRefused):
        move(local_ui, viewer).result(FUTURE_TIMEOUT_S)
    assert local_ui.runner.refusal(viewer.handle, "J1+") is not None  # the jog panel asks the same question
    clock.advance(10.0)
    np.testing.assert_allclose(angles(sim), before, atol=ANGLE_TOL_DEG)
    assert viewer.notifications and "viewer" in viewer.notifications[0]
    assert any(e.kind is EventKind.REFUSED and "browser #2" in e.source for e in local_ui.events.recent())

    move(local_ui, operator).result(FUTURE_TIMEOUT_S)
    clock.advance(30.0)
    np.testing.assert_allclose(angles(sim), HOME_MOVE.angles, atol=1e-6)
    assert any(e.message == "Move J" and "browser #1" in e.source for e in local_ui.events.recent())


def test_freeze_is_never_refused(local_ui: PendantUI, sim: SimController, clock: FakeClock) -> None:
    local_ui.desk.join(1)
    local_ui.desk.join(2)
    move(local_ui, FakeBrowser(1)).result(FUTURE_TIMEOUT_S)
    clock.advance(0.5)
    local_ui.runner.submit("Freeze", lambda c: c.freeze(), FakeBrowser(2).handle, urgent=True).result(
        FUTURE_TIMEOUT_S
    )
    stopped = angles(sim)
    clock.advance(5.0)
    np.testing.assert_allclose(angles(sim), stopped, atol=ANGLE_TOL_DEG)


def test_a_viewers_page_has_its_controls_disabled_except_freeze(local_ui: PendantUI) -> None:
    local_ui.desk.join(1)
    local_ui.desk.join(2)
    viewer = local_ui.open_session(local_ui.server, client_id=2)
    assert viewer.locked
    assert viewer.status.viewer and viewer.jog.locked  # its live readouts at a viewer's rate
    assert viewer.jog.buttons[(0, 1)].disabled and viewer.target_panel.move_j.disabled
    assert viewer.io.outputs[1].disabled and viewer.robot_buttons["Home"].disabled
    assert (
        viewer.settings.set_tool.disabled and viewer.sim_panel is not None and viewer.sim_panel.reset.disabled
    )
    assert viewer.dashboard.record_start.disabled
    # Greyed out and saying why on hover: the program's Record, and the pad's HTML jog buttons.
    assert viewer.program.record.disabled and viewer.program.record.hint == VIEW_ONLY_HINT
    assert f'title="{VIEW_ONLY_HINT}"' in viewer.jog.pad.content and " disabled" in viewer.jog.pad.content
    assert not viewer.freeze.disabled
    assert not viewer.control.take_button.disabled and viewer.control.release_button.disabled
    assert viewer.control.take_button.visible and not viewer.control.release_button.visible

    assert local_ui.desk.release(1)
    with local_ui.browsers.lock:
        local_ui.sessions[2] = viewer
    assert viewer.control.take() is None  # no token on loopback
    assert not viewer.locked and not viewer.status.viewer
    assert not viewer.jog.buttons[(0, 1)].disabled and not viewer.target_panel.joints[0].disabled
    assert viewer.target_panel.set_joint_target(np.radians(HOME_MOVE.angles)).ok
    assert not viewer.target_panel.move_j.disabled
    assert not viewer.dashboard.record_start.disabled
    assert viewer.program.record.hint != VIEW_ONLY_HINT and "Hold to jog" in viewer.jog.pad.content
    assert viewer.control.take_button.disabled and not viewer.control.release_button.disabled
    assert not viewer.control.take_button.visible and viewer.control.release_button.visible


def test_control_cannot_be_taken_from_the_operator(local_ui: PendantUI) -> None:
    local_ui.desk.join(1)
    local_ui.desk.join(2)
    reason = local_ui.desk.take(2)
    assert reason is not None and "browser #1 has control" in reason
    assert local_ui.desk.operator == 1


def test_exposed_pendant_gives_control_only_for_the_right_token(exposed_ui: PendantUI) -> None:
    desk = exposed_ui.desk
    desk.join(1, "10.0.0.7")
    assert desk.operator is None, "no browser gets control by connecting to an exposed pendant"
    assert desk.take(1) == MSG_NO_TOKEN
    assert desk.take(1, "guess") == MSG_WRONG_TOKEN
    refused = [e for e in exposed_ui.events.recent() if e.kind is EventKind.REFUSED]
    assert len(refused) == 2 and refused[-1].source == "browser #1 (10.0.0.7)"
    assert MSG_WRONG_TOKEN in refused[-1].message
    assert desk.take(1, TOKEN) is None
    assert desk.operator == 1


def test_the_access_token_field_and_the_url_token_both_work(exposed_ui: PendantUI) -> None:
    exposed_ui.desk.join(3)
    typed = exposed_ui.open_session(exposed_ui.server, client_id=3)
    assert typed.control.token is not None
    typed.control.token.value = "wrong"  # type: ignore[misc]  # viser 1.1.1: its setter is not beside the getter
    assert typed.control.take() == MSG_WRONG_TOKEN
    typed.control.token.value = TOKEN  # type: ignore[misc]  # viser 1.1.1: its setter is not beside the getter
    assert typed.control.take() is None
    assert typed.control.release()

    exposed_ui.desk.join(4)
    from_url = exposed_ui.open_session(exposed_ui.server, client_id=4, url_token=TOKEN)
    assert from_url.control.take() is None
    assert exposed_ui.desk.operator == 4


def test_operator_leaving_hands_control_on_and_stops_the_jog(
    local_ui: PendantUI, sim: SimController, clock: FakeClock
) -> None:
    local_ui.desk.join(1)
    local_ui.desk.join(2)  # connected while 1 operates: a viewer for now
    assert local_ui.jogger.hold(JogRequest(JogFrame.JOINT, 0, +1, 20.0))
    clock.advance(0.5)
    assert sim.get_motion_status() is MotionStatus.RUNNING

    local_ui.disconnect(FakeBrowser(1).handle)  # the operator's browser closes
    assert local_ui.desk.operator == 2, "the browser left waiting must get control, not nobody"
    assert local_ui.jogger.active is None
    stopped = angles(sim)
    clock.advance(5.0)
    np.testing.assert_allclose(angles(sim), stopped, atol=1e-6)
    assert sim.get_motion_status() is MotionStatus.IDLE
    messages = [e.message for e in local_ui.events.recent()]
    assert any("left: browser #2 has control" in m for m in messages)

    local_ui.disconnect(FakeBrowser(2).handle)  # the last one leaves: nobody is left to hand it to
    assert local_ui.desk.operator is None
    assert "left: control released" in local_ui.events.recent()[-1].message
    assert any(m == "Jog J1+" for m in messages) and any(
        "Jog J1+ stopped: control changed" in m for m in messages
    )


def test_a_viewer_cannot_record_or_run_a_program_and_the_log_says_who_did_what(
    local_ui: PendantUI, sim: SimController
) -> None:
    local_ui.desk.join(1)
    local_ui.desk.join(2)
    viewer_page = local_ui.open_session(local_ui.server, client_id=2)
    program = viewer_page.program
    assert program.record.disabled and program.run.disabled and not program.add.visible

    viewer = FakeBrowser(2)
    fire(program.record, viewer)  # a page with the lock removed: the server refuses all the same
    fire(program.run, viewer)
    assert local_ui.programs.program.steps == ()
    assert local_ui.programs.progress.state is RunState.IDLE
    refused = [e for e in local_ui.events.recent() if e.kind is EventKind.REFUSED]
    assert [e.message.split(":")[0] for e in refused] == ["Record", "Run"]
    assert all(e.source == "browser #2" for e in refused)

    viewer_page.close()  # both pages live on the server's one scene here: one at a time
    operator_page = local_ui.open_session(local_ui.server, client_id=1)
    assert not operator_page.program.record.disabled and not operator_page.program.run.disabled
    operator = FakeBrowser(1)
    fire(operator_page.program.record, operator)
    assert operator_page.program.pending is not None
    operator_page.program.pending.result(FUTURE_TIMEOUT_S)
    assert len(local_ui.programs.program.steps) == 1
    commands = [(e.source, e.message) for e in local_ui.events.recent() if e.kind is EventKind.COMMAND]
    assert ("browser #1", "Record") in commands


def test_the_operator_is_told_when_another_browser_asks_for_control(local_ui: PendantUI) -> None:
    local_ui.desk.join(1)
    local_ui.desk.join(2)
    operator = local_ui.open_session(local_ui.server, client_id=1)
    assert local_ui.browsers.add(1, operator)
    assert "asks for control" not in operator.control.role.content
    assert local_ui.desk.take(2) is not None  # refused: browser #1 has control
    assert "browser #2 asks for control" in operator.control.role.content
    assert local_ui.desk.release(1) and local_ui.desk.take(2) is None
    assert "asks for control" not in operator.control.role.content  # answered: control changed hands
