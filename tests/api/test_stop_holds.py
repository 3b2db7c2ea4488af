"""Only Recover leaves a protective stop, and the API's stops end a held jog, over real HTTP (issue 22).

The simulator's API served by uvicorn on loopback with the pendant's StopBus; a Jogger on the same bus
stands for the page's held button.
"""

from __future__ import annotations

import time
from collections.abc import Iterator

import httpx
import pytest

from pendant.api import create_app
from pendant.controller.errors import MSG_PROTECTIVE_STOP
from pendant.controller.stops import StopBus
from pendant.jog import JogFrame, Jogger, JogRequest
from pendant.sim import SimController
from tests.support.threads import serve_in_thread

PRECONDITION_FAILED = 412  # the reference's answer to a motion the arm cannot take now
MOVED_DEG = 1.0
RUN_S = 0.5  # J1 at 50 % turns well over MOVED_DEG in this time
STILL_TOL_DEG = 0.01
J1_PLUS = JogRequest(JogFrame.JOINT, 0, +1, speed_percent=20)


@pytest.fixture
def served() -> Iterator[tuple[httpx.Client, SimController, StopBus]]:
    sim, stops = SimController(), StopBus()
    with (
        serve_in_thread(create_app(sim, stops=stops)) as url,
        httpx.Client(base_url=url, timeout=30.0) as api,
    ):
        yield api, sim, stops


def a_little_further(api: httpx.Client) -> list[float]:
    angles = api.get("/pose").json()["angles"]
    angles[0] += 10.0
    return angles


def test_freeze_does_not_lift_a_protective_stop_only_recover_does(
    served: tuple[httpx.Client, SimController, StopBus],
) -> None:
    api, _, _ = served
    assert api.post("/stop").status_code == 200
    assert api.put("/freeze").status_code == 200  # open to everyone, never refused ...
    refused = api.put("/pose", params={"speed": 50}, json={"angles": a_little_further(api)})
    assert refused.status_code == PRECONDITION_FAILED  # ... and it does not leave the protective stop
    assert refused.json() == MSG_PROTECTIVE_STOP
    assert api.get("/status/motion").json() == "ERROR"

    assert api.put("/recover").json() == "SUCCESS"
    before = api.get("/pose").json()["angles"][0]
    assert api.put("/pose", params={"speed": 50}, json={"angles": a_little_further(api)}).status_code == 200
    time.sleep(RUN_S)
    api.put("/freeze")
    assert api.get("/pose").json()["angles"][0] > before + MOVED_DEG


@pytest.mark.parametrize("stop", ["PUT /freeze", "POST /stop"])
def test_a_stop_sent_to_the_api_ends_the_held_jog_until_it_is_released(
    served: tuple[httpx.Client, SimController, StopBus], stop: str
) -> None:
    api, sim, stops = served
    jogger = Jogger(sim, sim.arm, stops=stops)
    assert jogger.hold(J1_PLUS, jogger.releases, "browser")
    method, path = stop.split()
    assert api.request(method, path).status_code == 200
    stopped_at = sim.get_pose().angles[0]
    for _ in range(10):  # the button is still down: its confirmations keep coming
        assert not jogger.hold(J1_PLUS, jogger.releases, "browser")
    assert abs(sim.get_pose().angles[0] - stopped_at) < STILL_TOL_DEG
    assert (
        jogger.latch_cause("browser")
        == f"{'Freeze' if path == '/freeze' else 'Protective stop'} from the API (127.0.0.1)"
    )
