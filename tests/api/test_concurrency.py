"""Over HTTP: planning never holds up the other clients (PUT /freeze above all), and the caps answer 412."""

from __future__ import annotations

import threading
from typing import Any

import pytest
from fastapi.testclient import TestClient

from pendant.sim import FakeClock, SimController
from pendant.sim.controller import MAX_QUEUED_COMMANDS, MAX_WAYPOINTS
from tests.support.api_client import TEXT, arm_state, finish_motion
from tests.support.waiting import SAFETY_NET_S

# Not a timing threshold: long enough on any machine; only a request stuck behind the plan runs into it.
HANG_S = SAFETY_NET_S


def hold_first_plan(
    monkeypatch: pytest.MonkeyPatch, sim: SimController, method: str
) -> tuple[threading.Event, threading.Event]:
    """Make the first call of a planner method wait for the returned `release`; `started` says it is in."""
    started, release = threading.Event(), threading.Event()
    original = getattr(sim.planner, method)

    def held(*args: Any, **kwargs: Any) -> Any:
        if not started.is_set():
            started.set()
            assert release.wait(HANG_S)
        return original(*args, **kwargs)

    monkeypatch.setattr(sim.planner, method, held)
    return started, release


def request_in_thread(
    client: TestClient, method: str, url: str, **kwargs: Any
) -> tuple[threading.Thread, list[Any]]:
    responses: list[Any] = []
    thread = threading.Thread(
        target=lambda: responses.append(client.request(method, url, **kwargs)), daemon=True
    )
    thread.start()
    return thread, responses


@pytest.mark.parametrize("motion_type", ["LINEAR", "JOINT"])
def test_freeze_and_reads_answer_while_a_run_is_planned(
    client: TestClient, sim: SimController, monkeypatch: pytest.MonkeyPatch, motion_type: str
) -> None:
    started, release = hold_first_plan(monkeypatch, sim, motion_type.lower())
    target = client.get("/position").json()
    target["point"]["z"] -= 0.05
    url = f"/positions/run?speed=50&type={motion_type}"
    run, run_answer = request_in_thread(client, "PUT", url, json=[target])
    try:
        assert started.wait(HANG_S)
        for method, path in (("PUT", "/freeze"), ("GET", "/pose"), ("GET", "/status/motion")):
            other, answer = request_in_thread(client, method, path)
            other.join(HANG_S)
            assert not other.is_alive(), f"{method} {path} waited for the plan"
            assert answer[0].status_code == 200
    finally:
        release.set()
        run.join(HANG_S)
    assert run_answer[0].status_code == 200, run_answer[0].text


def test_pack_is_planned_off_the_event_loop(
    client: TestClient, sim: SimController, monkeypatch: pytest.MonkeyPatch
) -> None:
    started, release = hold_first_plan(monkeypatch, sim, "joint")
    pack, pack_answer = request_in_thread(client, "PUT", "/pack")
    try:
        assert started.wait(HANG_S)
        freeze, answer = request_in_thread(client, "PUT", "/freeze")
        freeze.join(HANG_S)
        assert not freeze.is_alive(), "PUT /freeze waited for PUT /pack's plan"
        assert answer[0].status_code == 200
    finally:
        release.set()
        pack.join(HANG_S)
    assert pack_answer[0].status_code == 200


def test_too_many_waypoints_answer_412_naming_the_limit_and_change_nothing(client: TestClient) -> None:
    before = arm_state(client)
    position = client.get("/position").json()
    pose = client.get("/pose").json()
    for url, waypoint in (("/positions/run", position), ("/poses/run", pose)):
        response = client.put(url, params={"speed": 50}, json=[waypoint] * (MAX_WAYPOINTS + 1))
        assert response.status_code == 412
        assert response.headers["content-type"] == TEXT
        assert response.json() == f"waypoints must be 1 to {MAX_WAYPOINTS} per run (got {MAX_WAYPOINTS + 1})"
    assert arm_state(client) == before


def test_a_full_queue_answers_412_naming_the_limit(client: TestClient, clock: FakeClock) -> None:
    for _ in range(MAX_QUEUED_COMMANDS):
        assert client.put("/gripper/close", params={"timeout": 10}).status_code == 200
    pose = client.get("/pose").json()
    for response in (
        client.put("/gripper/open", params={"timeout": 10}),
        client.put("/pose", params={"speed": 50}, json=pose),
        client.put("/pack"),
    ):
        assert response.status_code == 412
        assert response.json().startswith(f"queue must hold at most {MAX_QUEUED_COMMANDS} commands")
    assert finish_motion(client, clock) == "IDLE"
    assert client.put("/pose", params={"speed": 50}, json=pose).status_code == 200
