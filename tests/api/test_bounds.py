"""Every value bounded (issue #16, findings 6 and 9), over real HTTP against `pendant --no-ui`: a refused
value gets the controller's kind of message and changes nothing; 405 names the methods that are allowed;
the API's documentation pages work with no network beyond the pendant itself."""

from __future__ import annotations

import json
import re
from collections.abc import Iterator

import httpx
import pytest

from pendant.api.errors import MSG_TIMEOUT
from pendant.api.limits import BODY_LIMITS, too_large_message
from pendant.controller.types import GRIPPER_TIMEOUT_MAX_MS, TOOL_NAME_MAX
from tests.support.launchers import running_pendant
from tests.support.waiting import SAFETY_NET_S

TOOL = {
    "point": {"x": 0.0, "y": 0.0, "z": 0.1},
    "rotation": {"roll": 0.0, "pitch": 0.0, "yaw": 0.0},
    "radius": 0.02,
}
EXTERNAL_URL = re.compile(r"""(?:src|href)\s*=\s*["']?(?:https?:)?//""", re.IGNORECASE)
ASSET_URL = re.compile(r"""(?:src|href|url)\s*[=:]\s*["']([^"']+\.(?:js|css|png))["']""")


@pytest.fixture(scope="module")
def base_url() -> Iterator[str]:
    with running_pendant() as url:
        yield url


@pytest.fixture
def api(base_url: str) -> Iterator[httpx.Client]:
    with httpx.Client(base_url=base_url, timeout=SAFETY_NET_S) as client:
        yield client
        client.put("/freeze")


def test_a_tool_name_longer_than_the_limit_is_refused_and_the_tool_kept(api: httpx.Client) -> None:
    before = api.get("/tool").json()
    refused = api.post("/tool", json=TOOL | {"name": "x" * (TOOL_NAME_MAX + 1)})
    assert refused.status_code == 400
    assert refused.json() == "Incorrect format of input Message"
    assert api.get("/tool").json() == before
    accepted = api.post("/tool", json=TOOL | {"name": "y" * TOOL_NAME_MAX})
    assert accepted.status_code == 200
    assert api.get("/tool").json()["name"] == "y" * TOOL_NAME_MAX
    schema = api.get("/openapi.json").json()["components"]["schemas"]["Tool"]["properties"]["name"]
    assert schema["maxLength"] == TOOL_NAME_MAX  # documented where clients read the contract


@pytest.mark.parametrize("timeout", [2147483647, GRIPPER_TIMEOUT_MAX_MS + 1, -1])
def test_a_gripper_timeout_beyond_a_minute_is_refused_and_nothing_queued(
    api: httpx.Client, timeout: int
) -> None:
    refused = api.put("/gripper/close", params={"timeout": timeout})
    assert refused.status_code == 412
    assert refused.json() == MSG_TIMEOUT
    assert api.get("/status/motion").json() == "IDLE"
    angles = api.get("/pose").json()["angles"]
    # 30 degrees at 10 %: seconds, still running when a machine starved of CPU (nice 19) asks.
    moved = api.put("/pose", params={"speed": 10}, json={"angles": [angles[0] + 30.0, *angles[1:]]})
    assert moved.status_code == 200
    assert api.get("/status/motion").json() == "RUNNING"  # nothing queued ahead of the next move


@pytest.mark.parametrize(
    ("method", "path", "allowed"),
    [
        ("POST", "/pose", "GET, PUT"),
        ("DELETE", "/position", "GET, PUT"),
        ("PUT", "/tool", "GET, POST"),
        ("GET", "/freeze", "PUT"),
        ("GET", "/poses/run", "PUT"),
        ("POST", "/signal/output/1", "GET"),
        ("PUT", "/status/motion", "GET"),
    ],
)
def test_405_names_every_allowed_method(api: httpx.Client, method: str, path: str, allowed: str) -> None:
    response = api.request(method, path)
    assert response.status_code == 405
    assert response.headers["allow"] == allowed
    assert response.json() == "Method Not Allowed"


@pytest.mark.parametrize("page", ["/docs", "/redoc"])
def test_the_documentation_pages_load_everything_from_the_pendant(api: httpx.Client, page: str) -> None:
    html = api.get(page)
    assert html.status_code == 200
    assert not EXTERNAL_URL.search(html.text), "the page references another host: blank offline"
    assets = ASSET_URL.findall(html.text)
    assert any(asset.endswith(".js") for asset in assets), assets
    for asset in assets:
        response = api.get(asset)
        assert response.status_code == 200, asset
        assert len(response.content) > 1000, asset
    spec = re.search(r"""(?:url|spec-url)\s*[=:]\s*['"]([^'"]*openapi\.json)['"]""", html.text)
    assert spec is not None and api.get(spec.group(1)).status_code == 200
    json.loads(api.get("/openapi.json").text)


@pytest.mark.parametrize(("method", "path"), sorted(BODY_LIMITS))
def test_each_body_limit_is_documented_with_its_413(api: httpx.Client, method: str, path: str) -> None:
    operation = api.get("/openapi.json").json()["paths"][path][method.lower()]
    limit = BODY_LIMITS[(method, path)]
    assert f"at most {limit} bytes" in operation["requestBody"]["description"]
    assert too_large_message(limit) in operation["responses"]["413"]["content"]["text/plain"]["examples"]
