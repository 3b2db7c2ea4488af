"""`pendant --no-ui` over real HTTP on 127.0.0.1: it starts, serves, moves the arm, and stops."""

from __future__ import annotations

import time
from collections.abc import Iterator

import httpx
import pytest

from .helpers import angles_close
from .server import running_pendant

MOTION_DEADLINE_S = 30.0
POLL_INTERVAL_S = 0.05


@pytest.fixture(scope="module")
def base_url() -> Iterator[str]:
    with running_pendant("--model", "pulse75") as url:
        yield url


@pytest.fixture
def http(base_url: str) -> Iterator[httpx.Client]:
    with httpx.Client(base_url=base_url, timeout=5.0) as client:
        client.put("/sim/reset")
        yield client


def wait_until_idle(http: httpx.Client) -> str:
    # The server runs on the real clock, so the test waits for the motion like a user would.
    deadline = time.monotonic() + MOTION_DEADLINE_S
    status = http.get("/status/motion").json()
    while status == "RUNNING" and time.monotonic() < deadline:
        time.sleep(POLL_INTERVAL_S)
        status = http.get("/status/motion").json()
    return status


def test_a_motion_over_real_http_reaches_its_target(http: httpx.Client) -> None:
    start = http.get("/pose").json()["angles"]
    target = [start[0] + 10.0, start[1] + 5.0, *start[2:]]
    response = http.put("/pose", params={"speed": 100}, json={"angles": target})
    assert response.status_code == 200, response.text
    assert http.get("/status/motion").json() == "RUNNING"
    assert wait_until_idle(http) == "IDLE"
    assert angles_close(http.get("/pose").json()["angles"], target)


def test_errors_come_back_as_plain_text_over_http(http: httpx.Client) -> None:
    response = http.put("/pose", json={"angles": [0, 0]}, params={"speed": 10})
    assert response.status_code == 400
    assert response.headers["content-type"].startswith("text/plain")
    assert response.text == '"Incorrect format of input Message"'


def test_the_docs_are_served(http: httpx.Client) -> None:
    assert http.get("/openapi.json").json()["info"]["title"] == "PULSE REST API"
