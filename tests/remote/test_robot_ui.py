"""`pendant --robot URL` with its UI, as a user runs it: a simulator started separately plays the real arm.

Two processes on 127.0.0.1: `pendant --no-ui` (the "controller") and `pendant --robot ...` (page and proxy).
The pendant must serve its page, report the link in GET /pendant/health, pass a motion through its proxy, and
survive the controller's death: offline within a few seconds, still running, its page still served.
"""

from __future__ import annotations

from pathlib import Path

import httpx
import pytest

from pendant.sim import HOME_POSE_DEG
from tests.support.launchers import Launcher
from tests.support.ports import free_port, wait_for_port
from tests.support.waiting import SAFETY_NET_S, wait_until

pytestmark = pytest.mark.slow

START_TIMEOUT_S = 60.0  # the UI loads the arm model and meshes before it serves
OFFLINE_WITHIN_S = 30.0  # a safety net: the next health probe says so, given the CPU (nice 19)
MOTION_DEADLINE_S = SAFETY_NET_S
STOP_TIMEOUT_S = SAFETY_NET_S
POLL_INTERVAL_S = 0.1
CLIENT_TIMEOUT_S = 30.0
ANGLE_TOL_DEG = 1e-6
TARGET_DEG = [HOME_POSE_DEG[0] + 10.0, *HOME_POSE_DEG[1:]]


def page_served(url: str) -> bool:
    page = httpx.get(url, timeout=CLIENT_TIMEOUT_S)
    return page.status_code == 200 and "text/html" in page.headers["content-type"]


def test_the_pendant_drives_a_separate_simulator_and_outlives_it(launch: Launcher, tmp_path: Path) -> None:
    robot_port, ui_port, api_port = free_port(), free_port(), free_port()
    robot_url = f"http://127.0.0.1:{robot_port}"
    ui_url, api_url = f"http://127.0.0.1:{ui_port}/", f"http://127.0.0.1:{api_port}"
    simulator = launch(["--no-ui", "--api-port", str(robot_port)], "simulator")
    wait_for_port(robot_port, START_TIMEOUT_S)
    pendant_args = ["--robot", robot_url, "--ui-port", str(ui_port), "--api-port", str(api_port)]
    pendant_args += ["--remote-control", "on"]  # off by default in front of a real arm: API clients wait
    pendant = launch([*pendant_args, "--programs", str(tmp_path / "programs")])

    with (
        httpx.Client(base_url=api_url, timeout=CLIENT_TIMEOUT_S) as through_pendant,
        httpx.Client(base_url=robot_url, timeout=CLIENT_TIMEOUT_S) as robot,
    ):
        wait_until(lambda: through_pendant.get("/pendant/health").status_code == 200, START_TIMEOUT_S, "API")
        wait_until(lambda: page_served(ui_url), START_TIMEOUT_S, "the page")
        health = through_pendant.get("/pendant/health").json()
        assert (health["mode"], health["robot_url"], health["online"]) == ("robot", robot_url, True)
        assert health["motion_status"] == "IDLE"

        moved = through_pendant.put("/pose", params={"speed": 100}, json={"angles": TARGET_DEG})
        assert moved.status_code == 200, moved.text
        wait_until(
            lambda: robot.get("/status/motion").json() == "IDLE", MOTION_DEADLINE_S, "the motion's end"
        )
        assert robot.get("/pose").json()["angles"] == pytest.approx(TARGET_DEG, abs=ANGLE_TOL_DEG)

        simulator.kill()
        simulator.wait(STOP_TIMEOUT_S)
        wait_until(
            lambda: through_pendant.get("/pendant/health").json()["online"] is False,
            OFFLINE_WITHIN_S,
            "offline in /pendant/health",
        )
        health = through_pendant.get("/pendant/health").json()
        assert health["mode"] == "robot" and "unreachable" in health["last_error"]
        assert through_pendant.get("/pose").status_code == 502
        assert pendant.poll() is None, (tmp_path / "pendant.log").read_text()
        assert page_served(ui_url)
