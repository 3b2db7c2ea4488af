"""The proxy answers what the controller answers, byte for byte, for every endpoint and every error.

Two identical simulators on fake clocks, each served by uvicorn on 127.0.0.1: one asked directly, the other
through the proxy. Every request goes to both; status, content type and body must be equal.
"""

from __future__ import annotations

import json
import time
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import httpx
import pytest
from starlette.requests import Request
from starlette.responses import PlainTextResponse, Response

from pendant.api import create_app
from pendant.remote import create_proxy_app
from pendant.sim import FakeClock, SimController
from tests.support.threads import serve_in_thread

POSE = {"angles": [30.0, -80.0, 70.0, -80.0, -90.0, 10.0]}
POSITION = {
    "point": {"x": -0.4, "y": -0.1, "z": 0.45},
    "rotation": {"roll": 3.14159, "pitch": 0.0, "yaw": 0.0},
}
TOOL = {
    "name": "gripper",
    "point": {"x": 0, "y": 0, "z": 0.12},
    "rotation": {"roll": 0, "pitch": 0, "yaw": 0},
    "radius": 0.05,
}


ORIGIN = {"x": 0.0, "y": 0.0, "z": 0.0}
BOX = {
    "obstacleType": "BOX",
    "name": "far box",
    "sides": {"x": 0.1, "y": 0.1, "z": 0.1},
    "centerPosition": POSITION | {"point": {"x": 1.0, "y": 1.0, "z": 1.0}},
}
LINEAR = {"interpolationType": "BLEND", "velocity": 0.3, "acceleration": 1.0}
JOINT = {"interpolation_type": "SPLINE", "velocity": 40, "acceleration": 40}


@dataclass(frozen=True)
class Call:
    method: str
    path: str
    body: bytes | None = None
    content_type: str | None = None

    @staticmethod
    def json(method: str, path: str, document: object) -> Call:
        return Call(method, path, json.dumps(document).encode(), "application/json")


CALLS = [
    # Reads
    Call("GET", "/pose"),
    Call("GET", "/position"),
    Call("GET", "/status/motion"),
    Call("GET", "/status/motors"),
    Call("GET", "/tool"),
    Call("GET", "/base"),
    Call("GET", "/robot/id"),
    Call("GET", "/signal/output/1"),
    Call("GET", "/signal/input/4"),
    Call("HEAD", "/pose"),
    # Commands, accepted
    Call.json("POST", "/tool", TOOL),
    Call.json("POST", "/base", POSITION | {"point": {"x": 0.0, "y": 0.0, "z": 0.0}}),
    Call("PUT", "/signal/output/2/high"),
    Call("GET", "/signal/output/2"),
    Call.json("PUT", "/pose?speed=40&type=JOINT", POSE),
    Call("GET", "/status/motion"),
    Call.json("PUT", "/poses/run?speed=40", [POSE, POSE]),
    Call.json("PUT", "/position?speed=20&type=LINEAR&tcp_max_velocity=0.5", POSITION),
    Call.json("PUT", "/positions/run?speed=20", [POSITION]),
    Call("PUT", "/gripper/open?timeout=300"),
    Call("PUT", "/gripper/close"),
    Call("PUT", "/freeze"),
    Call("PUT", "/pack"),
    Call("PUT", "/relax"),
    Call("PUT", "/recover"),
    Call("PUT", "/freeze"),
    # SDK 1.8.4's operations
    Call("GET", "/status"),
    Call("GET", "/robot/info"),
    Call("GET", "/version/hardware"),
    Call("GET", "/version/software"),
    Call("GET", "/version/software/robot"),
    Call("POST", "/motors-log"),
    Call("GET", "/tool/info"),
    Call.json(
        "POST", "/tool/info", {"name": "cup", "tcp": POSITION | {"point": {"x": 0, "y": 0, "z": 0.05}}}
    ),
    Call("GET", "/tool/shape"),
    Call.json("POST", "/tool/shape", {"shape": [{"radius": 0.02, "begin": ORIGIN, "finish": ORIGIN}]}),
    Call.json("PUT", "/environment", BOX),
    Call("GET", "/environment"),
    Call("GET", "/environment/far%20box"),
    Call("DELETE", "/environment/far%20box"),
    Call("GET", "/environment/far%20box"),
    Call("DELETE", "/environment"),
    Call.json("PUT", "/jogging", {"acceleration": {"z": 0.5}}),
    Call("GET", "/status"),
    Call.json("PUT", "/jogging", {"acceleration": {}}),
    Call("POST", "/gripper/disable"),
    Call("PUT", "/gripper/close"),
    Call("POST", "/gripper/enable"),
    Call("PUT", "/stop/bind/3/high"),
    Call("PUT", "/sim/signal/input/3/high"),
    Call("DELETE", "/stop"),
    Call("POST", "/stop"),
    Call.json("PUT", "/pose?speed=40", POSE),
    Call("GET", "/status/failure"),
    Call("PUT", "/recover"),
    Call("PUT", "/zg/on"),
    Call("PUT", "/zg/off"),
    Call.json("PUT", "/run/linear/positions", {"positions": [POSITION], "motionParameters": LINEAR}),
    Call.json("PUT", "/run/linear/poses", {"poses": [POSE], "motionParameters": LINEAR}),
    Call.json("PUT", "/run/joint/positions", {"positions": [POSITION], "motionParameters": JOINT}),
    Call.json("PUT", "/run/joint/poses", {"poses": [POSE], "motionParameters": JOINT}),
    Call("PUT", "/freeze"),
    Call("PUT", "/sim/fault/twisted"),
    Call("PUT", "/untwisting/finish"),
    Call("PUT", "/untwisting/finish"),
    # Refused: 400, 412, 404, 405
    Call("PUT", "/pose?speed=40", b"{not json", "application/json"),
    Call.json("PUT", "/pose?speed=40", {"angles": [1, 2, 3]}),
    Call.json("PUT", "/pose", POSE),
    Call.json("PUT", "/pose?speed=400", POSE),
    Call.json("PUT", "/pose?speed=40", {"angles": [0, 0, 0, 0, 0, 1000]}),
    Call.json("PUT", "/pose?speed=40", {"angles": [0, -90, 160, 0, 0, 0]}),
    Call.json("PUT", "/position?speed=40", POSITION | {"point": {"x": 10.0, "y": 0.0, "z": 0.5}}),
    Call("GET", "/signal/output/9"),
    Call("GET", "/no/such/path"),
    Call("DELETE", "/pose"),
    Call("PUT", "/gripper/open?timeout=soon"),
    # Faults: 500 and 503 with their messages, then back
    Call("PUT", "/sim/fault/error"),
    Call("GET", "/status/motion"),
    Call.json("PUT", "/pose?speed=40", POSE),
    Call("PUT", "/recover"),
    Call("PUT", "/sim/fault/no_response"),
    Call("GET", "/pose"),
    Call("PUT", "/sim/fault/emergency"),
    Call("GET", "/pose"),
    Call("GET", "/status"),
    Call("GET", "/status/failure"),
    Call("PUT", "/relax"),
    Call("PUT", "/sim/reset"),
    Call("GET", "/status/motion"),
]


@pytest.fixture(scope="module")
def direct_and_proxied() -> Iterator[tuple[httpx.Client, httpx.Client]]:
    epoch = time.time()  # the same time of day on both: timestamps and failure dates agree
    direct_app = create_app(SimController("pulse75", FakeClock(), epoch))
    proxied_app = create_app(SimController("pulse75", FakeClock(), epoch))
    with (
        serve_in_thread(direct_app) as direct_url,
        serve_in_thread(proxied_app) as controller_url,
        serve_in_thread(create_proxy_app(controller_url)) as proxy_url,
        httpx.Client(base_url=direct_url) as direct,
        httpx.Client(base_url=proxy_url) as proxied,
    ):
        yield direct, proxied


def answer(client: httpx.Client, call: Call) -> tuple[int, str | None, bytes]:
    headers = {"content-type": call.content_type} if call.content_type else {}
    response = client.request(call.method, call.path, content=call.body, headers=headers)
    return response.status_code, response.headers.get("content-type"), response.content


def test_every_answer_is_passed_through_byte_for_byte(
    direct_and_proxied: tuple[httpx.Client, httpx.Client],
) -> None:
    direct, proxied = direct_and_proxied
    statuses = set()
    for call in CALLS:
        expected = answer(direct, call)
        assert answer(proxied, call) == expected, call
        statuses.add(expected[0])
    assert statuses >= {200, 400, 404, 405, 412, 500, 503}  # the list covers every kind of answer


def test_concurrent_requests_each_get_their_own_answer(
    direct_and_proxied: tuple[httpx.Client, httpx.Client],
) -> None:
    direct, proxied = direct_and_proxied
    paths = ["/pose", "/position", "/status/motors", "/robot/id", "/tool"] * 8
    expected = {path: direct.get(path).content for path in set(paths)}
    with ThreadPoolExecutor(max_workers=8) as pool:
        answers = list(pool.map(lambda path: proxied.get(path).content, paths))
    assert answers == [expected[path] for path in paths]


def test_the_health_route_is_the_pendants_own(direct_and_proxied: tuple[httpx.Client, httpx.Client]) -> None:
    _direct, proxied = direct_and_proxied
    health = proxied.get("/pendant/health").json()
    assert health["mode"] == "robot"
    assert health["online"] is True
    assert health["motion_status"] == "IDLE"
    assert health["latency_s"] > 0


def test_a_hook_can_refuse_requests_before_they_reach_the_controller() -> None:
    seen: list[tuple[str, str, str | None]] = []

    def token_check(request: Request) -> Response | None:
        seen.append((request.method, request.url.path, request.client.host if request.client else None))
        if request.headers.get("authorization") != "Bearer let-me-in":
            return PlainTextResponse("Forbidden", status_code=403)
        return None

    sim = SimController("pulse75", FakeClock())
    with (
        serve_in_thread(create_app(sim)) as controller_url,
        serve_in_thread(create_proxy_app(controller_url, on_request=token_check)) as proxy_url,
        httpx.Client(base_url=proxy_url) as client,
    ):
        assert client.put("/relax").status_code == 403
        assert sim.get_motion_status().value == "IDLE"  # the refused command never reached the arm
        allowed = client.put("/relax", headers={"authorization": "Bearer let-me-in"})
        assert allowed.status_code == 200
        assert sim.get_motion_status().value == "ZERO_GRAVITY"
    assert seen == [("PUT", "/relax", "127.0.0.1"), ("PUT", "/relax", "127.0.0.1")]


def test_a_robot_url_must_be_plain_http() -> None:
    with pytest.raises(ValueError, match="http://HOST:8081"):
        create_proxy_app("https://192.168.0.10:8081")
