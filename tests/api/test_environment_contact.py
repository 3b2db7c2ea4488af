"""An obstacle that touches the arm where it stands, over real HTTP with the `curl` binary: taken (200) and
logged, a move deeper into it refused (412, naming it), a move out of it accepted, and the page follows.

One simulator on a fake clock behind the API (uvicorn on loopback) and a pendant page (its event log and 3D
cell, refreshed as its loop would) sharing one event log, as `pendant` runs them.
"""

from __future__ import annotations

import json
import subprocess
from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np
import pytest

from pendant.api import create_app
from pendant.eventlog import EventLog
from pendant.sim import FakeClock, SimController
from pendant.ui.app import PendantUI
from tests.support.ports import free_port
from tests.support.threads import serve_in_thread
from tests.support.waiting import SAFETY_NET_S

CURL_TIMEOUT_S = SAFETY_NET_S
README_WALL = {  # Rozum's SDK README example 10's plane: x = -0.5 m, 13 mm into the wrist at power-on
    "obstacleType": "PLANE",
    "name": "wall",
    "points": [{"x": -0.5, "y": 0.4, "z": 0}, {"x": -0.5, "y": 0, "z": 0}, {"x": -0.5, "y": 0, "z": 0.1}],
}
HOME = [0.0, -90.0, 90.0, -90.0, -90.0, 0.0]
DEEPER = [0.0, -90.0, 95.0, -90.0, -90.0, 0.0]  # the forearm tips the gripper further past the wall
OUT = [15.0, -90.0, 90.0, -90.0, -90.0, 0.0]  # the base turns the wrist away from it
SETTLE_S = 30.0
DEG_TOL = 1e-6


@dataclass
class Cell:
    sim: SimController
    clock: FakeClock
    page: PendantUI
    url: str

    def curl(self, method: str, path: str, body: object = None) -> tuple[int, str]:
        """(status, body) of one request sent by the curl binary."""
        command = ["curl", "-sS", "--max-time", f"{CURL_TIMEOUT_S:g}", "-X", method, "-w", "\n%{http_code}"]
        if body is not None:
            command += ["-H", "Content-Type: application/json", "--data-binary", json.dumps(body)]
        done = subprocess.run(
            [*command, self.url + path],
            capture_output=True,
            text=True,
            timeout=CURL_TIMEOUT_S + 5,
            check=True,
        )
        text, _, status = done.stdout.rpartition("\n")
        return int(status), text

    def refresh_page(self) -> None:
        self.page.refresh()
        self.page.refresh_cell()

    def cell_events(self) -> list[str]:
        return [e.message for e in self.page.events.recent() if e.source == "cell"]


@pytest.fixture
def cell() -> Iterator[Cell]:
    clock = FakeClock()
    sim = SimController(clock=clock)
    events = EventLog()
    page = PendantUI(sim, sim.arm, host="127.0.0.1", port=free_port(), mode_line="Simulator", events=events)
    try:
        with serve_in_thread(create_app(sim, events=events)) as url:
            harness = Cell(sim, clock, page, url)
            harness.refresh_page()
            yield harness
    finally:
        page.stop()


def test_the_arm_backs_out_of_a_wall_added_where_it_stands_and_never_goes_deeper(cell: Cell) -> None:
    assert cell.sim.get_pose().angles == HOME
    status, body = cell.curl("PUT", "/environment", README_WALL)
    added = "Obstacle 'wall' added touching the arm (link5, link6, gripper_body)"
    assert (status, json.loads(body)) == (200, added)  # a JSON string, as every text answer
    cell.refresh_page()
    assert cell.cell_events() == [added]
    assert "PUT /environment -> 200" in [e.message for e in cell.page.events.recent()]
    assert cell.page.obstacles.shown == {"wall": True}  # red in the 3D scene

    status, body = cell.curl("PUT", "/pose?speed=50", {"angles": DEEPER})
    assert status == 412
    assert json.loads(body).startswith("Collision detected: the arm would go deeper into 'wall' (13 mm -> ")
    cell.clock.advance(SETTLE_S)
    assert json.loads(cell.curl("GET", "/pose")[1])["angles"] == HOME  # refused: nothing moved

    status, _ = cell.curl("PUT", "/pose?speed=50", {"angles": OUT})
    assert status == 200
    cell.clock.advance(SETTLE_S)
    assert json.loads(cell.curl("GET", "/pose")[1])["angles"] == pytest.approx(OUT, abs=DEG_TOL)
    assert cell.sim.environment.geometry.contacts(np.radians(OUT)) == {}  # out of contact
    cell.refresh_page()
    assert cell.page.obstacles.shown == {"wall": False}
    assert cell.cell_events()[1:] == ["The arm is clear of obstacle 'wall'"]

    status, body = cell.curl("PUT", "/pose?speed=50", {"angles": HOME})  # back in: a new contact
    assert (status, json.loads(body)) == (412, "Collision detected: the arm would touch 'wall'")
