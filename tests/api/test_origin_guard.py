"""Finding 2 of the audit, over real HTTP: a web page of another origin, or a DNS-rebound host name, cannot
change the arm through the API port (the simulator's `pendant --no-ui`, and the proxy in front of a
controller); scripts without an Origin header work as before."""

from __future__ import annotations

import json
from collections.abc import Iterator

import httpx
import pytest

from pendant.access.http_guard import AccessRules
from pendant.access.origin import OriginPolicy
from pendant.api import create_app
from pendant.remote import create_proxy_app
from pendant.sim import FakeClock, SimController
from tests.support.launchers import running_pendant
from tests.support.threads import serve_in_thread

EVIL = "http://evil.example"
POSITION = {"point": {"x": 0, "y": 0, "z": 0.3}, "rotation": {"roll": 0, "pitch": 0, "yaw": 0}}
TOOL = {"name": "evil", "radius": 0.01, "position": POSITION}
POSE = {"angles": [10.0, -90.0, 90.0, -90.0, -90.0, 0.0]}


@pytest.fixture(scope="module")
def simulator() -> Iterator[str]:
    with running_pendant("--allowed-host", "pendant.lan") as url:
        yield url


@pytest.fixture(scope="module")
def proxy() -> Iterator[str]:
    """A proxy (as `pendant --robot URL` serves it) in front of a simulator on a fake clock."""
    controller = create_app(SimController("pulse75", FakeClock()))
    with serve_in_thread(controller) as controller_url:
        app = create_proxy_app(controller_url, access=AccessRules(origins=OriginPolicy("127.0.0.1")))
        with serve_in_thread(app) as proxy_url:
            yield proxy_url


@pytest.fixture(params=["simulator", "proxy"])
def api(request: pytest.FixtureRequest) -> Iterator[httpx.Client]:
    with httpx.Client(base_url=request.getfixturevalue(request.param), timeout=30.0) as client:
        yield client


def test_a_no_cors_text_plain_post_from_another_origin_changes_nothing(api: httpx.Client) -> None:
    before = api.get("/tool").json(), api.get("/base").json()
    for path in ("/tool", "/base"):
        body = json.dumps(TOOL if path == "/tool" else TOOL["position"])
        # What fetch(url, {method: "POST", mode: "no-cors", body}) sends from a page at evil.example.
        answer = api.post(
            path, content=body, headers={"Origin": EVIL, "Content-Type": "text/plain;charset=UTF-8"}
        )
        assert answer.status_code == 403
        assert answer.headers["content-type"].startswith("text/plain")
        assert "Cross-origin request refused" in json.loads(answer.text)
    assert (api.get("/tool").json(), api.get("/base").json()) == before


def test_a_foreign_origin_cannot_move_the_arm_even_with_json(api: httpx.Client) -> None:
    before = api.get("/pose").json()["angles"]  # the timestamp moves on
    answer = api.put("/pose", params={"speed": 50}, json=POSE, headers={"Origin": EVIL})
    assert answer.status_code == 403
    assert api.get("/pose").json()["angles"] == before
    assert api.get("/status/motion").text == '"IDLE"'


def test_a_json_body_sent_as_text_plain_by_a_page_is_refused_without_an_origin_too(api: httpx.Client) -> None:
    """A browser's request carries fetch metadata even where it leaves `Origin` out."""
    before = api.get("/tool").json()
    page = {"Sec-Fetch-Site": "cross-site", "Sec-Fetch-Mode": "no-cors"}
    answer = api.post("/tool", content=json.dumps(TOOL), headers={**page, "Content-Type": "text/plain"})
    assert answer.status_code == 415
    assert "application/json" in json.loads(answer.text)
    form_type = {"Content-Type": "application/x-www-form-urlencoded"}
    assert api.post("/tool", content=b"a=1", headers={**page, **form_type}).status_code == 415
    assert api.get("/tool").json() == before


def test_a_script_may_label_its_json_body_as_it_likes(api: httpx.Client) -> None:
    """No `Origin`, no `Sec-Fetch-*`: no page sent it, and the body is read as JSON whatever its type."""
    tool = {"name": "script", "radius": 0.01, **POSITION}
    answer = api.post("/tool", content=json.dumps(tool), headers={"Content-Type": "text/plain"})
    assert answer.status_code == 200, answer.text
    assert api.get("/tool").json()["name"] == "script"
    form_type = {"Content-Type": "application/x-www-form-urlencoded"}
    assert api.post("/tool", content=b"a=1", headers=form_type).status_code == 400  # not JSON: bad format


@pytest.mark.parametrize("host", ["evil.example", "evil.example:8081", "rebind.attacker.test"])
def test_a_dns_rebound_host_name_is_refused_reads_included(api: httpx.Client, host: str) -> None:
    for method, path in (("GET", "/pose"), ("GET", "/tool"), ("PUT", "/relax")):
        answer = api.request(method, path, headers={"Host": host})
        assert answer.status_code == 403, (method, path)
        assert "--allowed-host" in json.loads(answer.text)
    assert api.get("/status/motion").text == '"IDLE"'


def test_scripts_without_an_origin_and_the_pendants_own_origin_still_work(api: httpx.Client) -> None:
    own = str(api.base_url).rstrip("/")
    assert api.put("/relax", headers={"Origin": own}).status_code == 200
    assert api.put("/freeze").status_code == 200
    assert api.get("/pose", headers={"Host": "localhost"}).status_code == 200
    assert api.get("/pose", headers={"Host": "[::1]:8081"}).status_code == 200
    assert api.get("/status/motion").text == '"IDLE"'


def test_an_allowed_host_name_is_served(simulator: str) -> None:
    with httpx.Client(base_url=simulator) as api:
        assert api.get("/pose", headers={"Host": "pendant.lan:8081"}).status_code == 200
        assert api.get("/pose", headers={"Host": "other.lan"}).status_code == 403
