"""Finding 7 of the audit: one operator for the arm. The page's Remote control switch decides whether API
clients may move it (refusals name who has control), and a jog and an API motion take turns so that a jog's
freeze never drops a command a client was told was accepted. The API over real HTTP, the page headless."""

from __future__ import annotations

import json
from collections.abc import Iterator

import httpx
import numpy as np
import pytest

from pendant.access.http_guard import AccessRules
from pendant.access.remote import RemoteControl
from pendant.api import create_app
from pendant.cli import parse_settings, remote_control_default
from pendant.controller import MotionStatus, PreconditionFailed
from pendant.jog import JogFrame, JogRequest
from pendant.sim import FakeClock, SimController
from pendant.ui.app import PendantUI
from pendant.ui.page.session import ClientSession
from tests.support.doubles import OPERATOR, VIEWER, FakeBrowser, fire
from tests.support.pages import new_page
from tests.support.threads import serve_in_thread

TARGET = [30.0, -90.0, 90.0, -90.0, -90.0, 0.0]
ANGLE_TOL_DEG = 1e-6
J1_PLUS = JogRequest(JogFrame.JOINT, 0, +1, 20.0)


@pytest.fixture
def page(sim: SimController) -> Iterator[PendantUI]:
    ui = new_page(sim, sim.arm, remote=RemoteControl(enabled=False))
    ui.desk.join(OPERATOR, "10.0.0.7")
    ui.desk.join(VIEWER)
    ui.refresh()
    yield ui
    ui.stop()


@pytest.fixture
def api(page: PendantUI, sim: SimController) -> Iterator[httpx.Client]:
    app = create_app(sim, access=AccessRules(remote=page.remote, events=page.events))
    with serve_in_thread(app) as url, httpx.Client(base_url=url, timeout=30.0) as client:
        yield client


def session(page: PendantUI, client_id: int) -> ClientSession:
    """The panels of browser `client_id`, registered as the page registers a connected browser's."""
    built = page.open_session(page.server, client_id=client_id)
    with page.browsers.lock:
        page.sessions[client_id] = built
    return built


def angles(sim: SimController) -> np.ndarray:
    return np.asarray(sim.get_pose().angles)


def put_pose(api: httpx.Client) -> httpx.Response:
    return api.put("/pose", params={"speed": 20}, json={"angles": TARGET})


def test_with_remote_control_off_the_api_cannot_move_the_arm_and_is_told_who_has_control(
    page: PendantUI, api: httpx.Client, sim: SimController, clock: FakeClock
) -> None:
    before = angles(sim)
    answer = put_pose(api)
    assert answer.status_code == 403
    message = json.loads(answer.text)
    assert "Remote control is off" in message and "browser #1 (10.0.0.7) has control" in message
    assert api.post("/tool", json={"name": "t", "radius": 0.0, "position": {}}).status_code == 403
    clock.advance(10.0)
    np.testing.assert_allclose(angles(sim), before, atol=ANGLE_TOL_DEG)
    assert api.put("/freeze").status_code == 200  # stopping is open to every client
    assert api.get("/pose").status_code == 200  # and reading


def test_the_operator_turns_remote_control_on_and_a_viewer_cannot(
    page: PendantUI, api: httpx.Client, sim: SimController, clock: FakeClock
) -> None:
    viewer, operator = FakeBrowser(VIEWER), FakeBrowser(OPERATOR)
    viewers_panel = session(page, VIEWER).control
    assert viewers_panel.remote is not None
    fire(viewers_panel.remote, viewer, True)
    assert not page.remote.enabled
    assert viewers_panel.remote.value is False  # sprung back
    assert any("Remote control refused" in n for n in viewer.notifications)
    assert put_pose(api).status_code == 403

    operators_panel = session(page, OPERATOR).control
    assert operators_panel.remote is not None
    fire(operators_panel.remote, operator, True)
    assert page.remote.enabled
    assert viewers_panel.remote.value is True  # every page shows the switch as it is
    assert put_pose(api).status_code == 200
    clock.advance(10.0)
    np.testing.assert_allclose(angles(sim), TARGET, atol=ANGLE_TOL_DEG)
    messages = [e.message for e in page.events.recent()]
    assert any("Remote control on" in m for m in messages)


def test_an_api_command_is_refused_while_a_jog_is_held_and_runs_in_full_after(
    page: PendantUI, api: httpx.Client, sim: SimController, clock: FakeClock
) -> None:
    page.remote.set_enabled(True)
    assert page.jogger.hold(J1_PLUS)
    clock.advance(0.3)
    refused = put_pose(api)
    assert refused.status_code == 409
    assert "jogging" in json.loads(refused.text) and "browser #1" in json.loads(refused.text)
    page.jogger.release("released")  # the freeze of the release: it must not meet an accepted command
    assert put_pose(api).status_code == 200
    clock.advance(10.0)
    np.testing.assert_allclose(angles(sim), TARGET, atol=ANGLE_TOL_DEG)


def test_a_jog_is_refused_while_an_api_motion_runs_and_the_motion_is_not_dropped(
    page: PendantUI, api: httpx.Client, sim: SimController, clock: FakeClock
) -> None:
    page.remote.set_enabled(True)
    assert put_pose(api).status_code == 200
    clock.advance(0.3)
    assert sim.get_motion_status() is MotionStatus.RUNNING
    with pytest.raises(PreconditionFailed, match="API client's motion is under way"):
        page.jogger.hold(J1_PLUS)
    assert page.jogger.hold(J1_PLUS) is False  # the same press again: refused quietly, not 20 times a second
    page.jogger.release("released")
    clock.advance(10.0)
    np.testing.assert_allclose(angles(sim), TARGET, atol=ANGLE_TOL_DEG)  # the accepted command ran in full
    # Once the arm is seen stopped, the operator jogs again.
    assert page.jogger.hold(J1_PLUS)
    page.jogger.release("released")


@pytest.mark.parametrize(
    ("flags", "on"),
    [
        ([], True),  # the simulator on loopback: scripts work out of the box
        (["--no-ui"], True),  # no page, no operator to decide
        (["--host", "0.0.0.0"], False),
        (["--robot", "http://192.168.0.10:8081"], False),
        (["--robot", "http://192.168.0.10:8081", "--remote-control", "on"], True),
        (["--remote-control", "off"], False),
    ],
)
def test_remote_control_is_on_by_default_only_for_the_simulator_on_loopback(
    flags: list[str], on: bool
) -> None:
    assert remote_control_default(parse_settings(flags)) is on
