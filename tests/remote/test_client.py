"""RemoteController against a scripted transport: wire parsing, status -> typed errors, retries, health."""

from __future__ import annotations

import json
from collections.abc import Callable

import httpx
import pytest

from pendant.controller.errors import (
    MSG_BAD_FORMAT,
    MSG_COLLISION,
    MSG_EMERGENCY,
    MSG_NOT_RESPONDING,
    MSG_UNREACHABLE_POSE,
    BadRequest,
    Collision,
    ControllerError,
    ControllerOffline,
    Emergency,
    NotResponding,
    PreconditionFailed,
    Unreachable,
)
from pendant.controller.types import (
    MotionParams,
    MotionStatus,
    MotionType,
    Pose,
    Position,
    RecoverResult,
    SignalLevel,
)
from pendant.remote import RemoteController

BASE_URL = "http://pulse.test:8081"
POSE_BODY = b'{"angles": [0, 90, 0, -90, 0, 0]}'
POSITION = Position.model_validate(
    {"point": {"x": 0.3, "y": 0, "z": 0.4}, "rotation": {"roll": 0, "pitch": 0, "yaw": 0}}
)
PARAMS = MotionParams(speed=25.0, motion_type=MotionType.LINEAR, tcp_max_velocity=0.5)


def controller_answering(handle: Callable[[httpx.Request], httpx.Response]) -> RemoteController:
    return RemoteController(BASE_URL, transport=httpx.MockTransport(handle), get_retries=2)


def always(status: int, body: bytes, content_type: str = "text/plain") -> RemoteController:
    return controller_answering(
        lambda _request: httpx.Response(status, content=body, headers={"content-type": content_type})
    )


@pytest.mark.parametrize("body", [b'"RUNNING"', b"RUNNING", b'"RUNNING"\n'])
def test_plain_text_results_are_read_quoted_or_raw(body: bytes) -> None:
    assert always(200, body).get_motion_status() is MotionStatus.RUNNING


def test_string_results_keep_their_text() -> None:
    assert always(200, b'"1346466AFG872"').get_robot_id() == "1346466AFG872"
    assert always(200, b"LOW").get_input(3) is SignalLevel.LOW
    assert always(200, b'"SUCCESS"').recover() is RecoverResult.SUCCESS


def test_json_results_are_typed() -> None:
    pose = always(200, POSE_BODY, "application/json").get_pose()
    assert pose == Pose(angles=[0.0, 90.0, 0.0, -90.0, 0.0, 0.0])


@pytest.mark.parametrize(
    ("status", "message", "error_type"),
    [
        (400, MSG_BAD_FORMAT, BadRequest),
        (412, MSG_COLLISION, Collision),
        (412, MSG_UNREACHABLE_POSE, Unreachable),
        (412, "speed must be a number from 1 to 100", PreconditionFailed),
        (500, MSG_NOT_RESPONDING, NotResponding),
        (503, MSG_EMERGENCY, Emergency),
    ],
)
def test_error_statuses_become_typed_errors_with_the_controllers_message(
    status: int, message: str, error_type: type[ControllerError]
) -> None:
    controller = always(status, json.dumps(message).encode())
    with pytest.raises(error_type) as caught:
        controller.set_pose(Pose(angles=[0.0] * 6), PARAMS)
    assert type(caught.value) is error_type
    assert caught.value.message == message
    assert controller.health().online  # an error answer is still an answer


def test_a_status_the_api_does_not_use_means_offline() -> None:
    controller = always(404, b'"Not Found"')
    with pytest.raises(ControllerOffline, match="404"):
        controller.get_pose()
    assert not controller.health().online


@pytest.mark.parametrize("body", [b"<html>hello</html>", b'{"angles": [1, 2]}', b""])
def test_an_unparsable_answer_is_offline_with_the_body_quoted(body: bytes) -> None:
    controller = always(200, body, "application/json")
    with pytest.raises(ControllerOffline, match=r"Unparsable answer .* GET /pose"):
        controller.get_pose()
    assert not controller.health().online


def test_unknown_status_word_is_unparsable() -> None:
    with pytest.raises(ControllerOffline, match="GET /status/motion"):
        always(200, b'"DANCING"').get_motion_status()


def test_motion_parameters_go_in_the_query_and_the_target_in_the_body() -> None:
    seen: list[httpx.Request] = []

    def handle(request: httpx.Request) -> httpx.Response:
        seen.append(request)
        return httpx.Response(200, content=request.content, headers={"content-type": "application/json"})

    answer = controller_answering(handle).set_position(POSITION, PARAMS)
    (request,) = seen
    assert request.method == "PUT"
    assert request.url.path == "/position"
    assert dict(request.url.params) == {"speed": "25.0", "type": "LINEAR", "tcp_max_velocity": "0.5"}
    assert Position.model_validate_json(request.content) == POSITION
    assert answer == POSITION


def test_io_and_gripper_paths() -> None:
    seen: list[str] = []

    def handle(request: httpx.Request) -> httpx.Response:
        seen.append(f"{request.method} {request.url.path}?{request.url.query.decode()}")
        return httpx.Response(200)

    controller = controller_answering(handle)
    controller.set_output(2, SignalLevel.HIGH)
    controller.set_output(1, SignalLevel.LOW)
    controller.open_gripper(700)
    controller.close_gripper(300)
    assert seen == [
        "PUT /signal/output/2/high?",
        "PUT /signal/output/1/low?",
        "PUT /gripper/open?timeout=700",
        "PUT /gripper/close?timeout=300",
    ]


def failing_then_answering(failures: int, error: Exception) -> tuple[RemoteController, list[str]]:
    calls: list[str] = []

    def handle(request: httpx.Request) -> httpx.Response:
        calls.append(request.method)
        if len(calls) <= failures:
            raise error
        return httpx.Response(200, content=POSE_BODY)

    return controller_answering(handle), calls


def test_a_get_is_retried_on_a_dropped_connection() -> None:
    controller, calls = failing_then_answering(2, httpx.RemoteProtocolError("Server disconnected"))
    assert controller.get_pose().angles[1] == 90.0
    assert calls == ["GET"] * 3


def test_a_get_gives_up_after_its_retries() -> None:
    controller, calls = failing_then_answering(3, httpx.ConnectError("Connection refused"))
    with pytest.raises(ControllerOffline, match=r"unreachable .*Connection refused"):
        controller.get_pose()
    assert len(calls) == 3


def test_a_get_that_timed_out_is_not_retried() -> None:
    controller, calls = failing_then_answering(1, httpx.ReadTimeout("timed out"))
    with pytest.raises(ControllerOffline, match="did not answer GET /pose within 3 s"):
        controller.get_pose()
    assert len(calls) == 1


@pytest.mark.parametrize(
    "error",
    [httpx.ConnectError("refused"), httpx.RemoteProtocolError("disconnected"), httpx.ReadTimeout("t")],
)
def test_a_command_is_never_sent_twice(error: Exception) -> None:
    controller, calls = failing_then_answering(1, error)
    with pytest.raises(ControllerOffline):
        controller.set_pose(Pose(angles=[10.0] * 6), PARAMS)
    assert calls == ["PUT"]
    # The next command goes out once, and nothing from before is replayed with it.
    controller.relax()
    assert calls == ["PUT", "PUT"]


def test_health_follows_the_link() -> None:
    controller, _calls = failing_then_answering(3, httpx.ConnectError("Connection refused"))
    assert controller.health().online is False
    assert controller.health().last_seen is None

    with pytest.raises(ControllerOffline):
        controller.get_pose()
    offline = controller.health()
    assert not offline.online
    assert offline.last_error is not None and "Connection refused" in offline.last_error

    controller.get_pose()  # offline -> online is noticed on the next answered call
    online = controller.health()
    assert online.online and online.last_error is None
    assert online.latency_s is not None and online.latency_s >= 0
    assert online.last_seen is not None


def test_ping_never_raises() -> None:
    controller = controller_answering(lambda _request: (_ for _ in ()).throw(httpx.ConnectError("refused")))
    health = controller.ping()
    assert not health.online
    assert health.last_error is not None


def test_the_gripper_is_what_this_client_last_told_it_and_unknown_before() -> None:
    controller = always(200, b"")
    assert controller.gripper_opening() is None  # the PULSE API has no gripper read
    controller.open_gripper(500)
    assert controller.gripper_opening() == 1.0
    controller.close_gripper(500)
    assert controller.gripper_opening() == 0.0
    refusing = always(503, b'"Robot unavailable in emergency state"')
    with pytest.raises(Emergency):
        refusing.open_gripper(500)
    assert refusing.gripper_opening() is None  # a refused command changes nothing
