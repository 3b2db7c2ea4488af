"""A stop is never refused for its form (issue 22): the `curl` binary and Python's urllib, in subprocesses,
stop a motion under way however they send PUT /freeze or POST /stop (empty form body, text/plain, multipart,
no body, a body too large for a command), on the simulator's API (`pendant --no-ui`) and through a proxy
(`pendant --no-ui --robot URL` in front of one). Commands without a body answer as they would with one, and
curl's `-d '{...}'` without a content type moves the arm. A page of another origin still cannot move it."""

from __future__ import annotations

import json
from collections.abc import Callable, Iterator

import httpx
import pytest

from tests.support.launchers import running_pendant
from tests.support.stop_clients import (
    FAR_POSE,
    SETTLE_DEG,
    STILL_DEG,
    STILL_WINDOW_S,
    curl,
    j1,
    j1_travel,
    ready_to_move,
    start_long_move,
    urllib_request,
)
from tests.support.waiting import SAFETY_NET_S

EVIL = "http://evil.example"
LARGE_BODY = "x" * 4096  # more than any bodiless command may carry (1 KiB)


@pytest.fixture(scope="module")
def arm_url() -> Iterator[str]:
    """The "real arm": a simulator on the wall clock."""
    with running_pendant() as url:
        yield url


@pytest.fixture(scope="module")
def proxy_url(arm_url: str) -> Iterator[str]:
    with running_pendant("--robot", arm_url) as url:
        yield url


@pytest.fixture(params=["simulator", "proxy"])
def api_url(request: pytest.FixtureRequest, arm_url: str) -> str:
    """Where the clients send their requests: the simulator itself, or the proxy in front of it."""
    return arm_url if request.param == "simulator" else request.getfixturevalue("proxy_url")


@pytest.fixture
def arm(arm_url: str, api_url: str) -> Iterator[httpx.Client]:
    """Reads of the arm itself (behind the proxy, if any); ready to move at the start."""
    with httpx.Client(base_url=arm_url, timeout=SAFETY_NET_S) as client:
        ready_to_move(client)
        yield client
        ready_to_move(client)


StopSender = Callable[[str], tuple[int, str]]

STOPS: dict[str, StopSender] = {
    "curl PUT -d '' /freeze": lambda url: curl("-X", "PUT", "-d", "", f"{url}/freeze"),
    "curl POST -d '' /stop": lambda url: curl("-X", "POST", "-d", "", f"{url}/stop"),
    "curl PUT /freeze, no body": lambda url: curl("-X", "PUT", f"{url}/freeze"),
    "curl PUT text/plain /freeze": lambda url: curl(
        "-X", "PUT", "-H", "Content-Type: text/plain", "-d", "stop!", f"{url}/freeze"
    ),
    "curl POST a form to /stop": lambda url: curl("-X", "POST", "-F", "why=now", f"{url}/stop"),
    "curl PUT a large body to /freeze": lambda url: curl("-X", "PUT", "-d", LARGE_BODY, f"{url}/freeze"),
    "urllib PUT data=b'' /freeze": lambda url: urllib_request("PUT", f"{url}/freeze"),
    "urllib POST data=b'' /stop": lambda url: urllib_request("POST", f"{url}/stop"),
    "urllib PUT text/plain /freeze": lambda url: urllib_request("PUT", f"{url}/freeze", "{}", "text/plain"),
    "urllib POST /stop, no body": lambda url: urllib_request("POST", f"{url}/stop", None),
}


@pytest.mark.parametrize("form", list(STOPS))
def test_every_form_of_stop_stops_a_motion_under_way(form: str, api_url: str, arm: httpx.Client) -> None:
    with httpx.Client(base_url=api_url, timeout=SAFETY_NET_S) as api:
        start_long_move(api, arm)
        status, body = STOPS[form](api_url)
        assert status == 200, body
        assert j1_travel(arm, STILL_WINDOW_S) < STILL_DEG, f"{form} left the arm moving"


@pytest.mark.parametrize(
    ("method", "path"),
    [("PUT", "/relax"), ("PUT", "/recover"), ("PUT", "/freeze"), ("POST", "/stop"), ("PUT", "/sim/reset")],
)
def test_urllib_empty_data_runs_a_bodiless_command(method: str, path: str, arm_url: str) -> None:
    """`urllib.request.Request(url, method=..., data=b'')` labels the empty body form-encoded: the command
    answers as it does without a body."""
    with httpx.Client(base_url=arm_url, timeout=SAFETY_NET_S) as arm:
        status, body = urllib_request(method, f"{arm_url}{path}")
        bare = arm.request(method, path)
        assert (status, body) == (bare.status_code, bare.text.strip())
        assert status == 200, body
        ready_to_move(arm)


def test_urllib_empty_data_runs_bodiless_commands_through_the_proxy(proxy_url: str, arm_url: str) -> None:
    with httpx.Client(base_url=arm_url, timeout=SAFETY_NET_S) as arm:
        assert urllib_request("PUT", f"{proxy_url}/relax")[0] == 200
        assert arm.get("/status/motion").text == '"ZERO_GRAVITY"'
        assert urllib_request("PUT", f"{proxy_url}/freeze")[0] == 200
        assert arm.get("/status/motion").text == '"IDLE"'


def test_curl_d_json_without_a_content_type_moves_the_arm(api_url: str, arm: httpx.Client) -> None:
    """What curl users type: `curl -X PUT -d '{"angles": [...]}' URL/pose` (sent as a form by curl)."""
    target = [FAR_POSE[0] / 6, *FAR_POSE[1:]]  # 10 degrees at 50 %: about a second
    status, body = curl("-X", "PUT", "-d", json.dumps({"angles": target}), f"{api_url}/pose")
    assert status == 200, body
    with httpx.Client(base_url=api_url, timeout=SAFETY_NET_S) as api:
        for _ in range(100):
            if api.get("/status/motion").text == '"IDLE"':
                break
            j1_travel(arm, 0.1)
    assert abs(j1(arm) - target[0]) < SETTLE_DEG


def test_a_foreign_page_can_at_most_stop_the_arm(api_url: str, arm: httpx.Client) -> None:
    before = j1(arm)
    for content_type in ("application/json", "text/plain"):
        status, _ = curl(
            "-X", "PUT", "-H", f"Origin: {EVIL}", "-H", f"Content-Type: {content_type}",
            "-d", json.dumps({"angles": FAR_POSE}), f"{api_url}/pose?speed=100",
        )  # fmt: skip
        assert status == 403
    assert curl("-X", "PUT", "-H", f"Origin: {EVIL}", f"{api_url}/relax")[0] == 403
    assert j1_travel(arm, STILL_WINDOW_S) < STILL_DEG
    assert j1(arm) == pytest.approx(before, abs=STILL_DEG)
    assert arm.get("/status/motion").text == '"IDLE"'
    with httpx.Client(base_url=api_url, timeout=SAFETY_NET_S) as api:
        start_long_move(api, arm)
        status, _ = curl("-X", "PUT", "-H", f"Origin: {EVIL}", f"{api_url}/freeze")
        assert status in (200, 403)  # a stop from anyone is harmless; refusing it is allowed too
        if status == 403:
            api.put("/freeze")
    assert j1_travel(arm, STILL_WINDOW_S) < STILL_DEG


def test_a_pages_command_in_a_simple_content_type_is_still_refused(api_url: str, arm: httpx.Client) -> None:
    """Fetch metadata marks a browser's request even without `Origin`: the content-type rule holds for it."""
    before = arm.get("/tool").json()
    status, body = curl(
        "-X", "POST", "-H", "Sec-Fetch-Mode: no-cors", "-H", "Sec-Fetch-Site: cross-site",
        "-H", "Content-Type: text/plain", "-d", json.dumps({"name": "evil", "radius": 0.01}),
        f"{api_url}/tool",
    )  # fmt: skip
    assert status == 415, body
    assert arm.get("/tool").json() == before
    status, _ = curl("-X", "PUT", "-H", "Sec-Fetch-Site: cross-site", "-d", "", f"{api_url}/freeze")
    assert status == 200  # but a stop, in whatever form, is not refused
