"""Faults over real HTTP on 127.0.0.1, with the simulator as the "real" controller in its own process
(`python -m pendant --no-ui --api-port PORT`): it starts late, it dies mid-motion, it reports an emergency or
stops responding. The pendant must report it, never crash, and never replay a lost command."""

from __future__ import annotations

import subprocess
import time

import httpx
import pytest

from pendant.controller.errors import (
    MSG_EMERGENCY,
    MSG_NOT_RESPONDING,
    ControllerOffline,
    Emergency,
    NotResponding,
)
from pendant.controller.types import MotionParams, MotionStatus, Pose
from pendant.remote import RemoteController, create_proxy_app
from pendant.sim import HOME_POSE_DEG
from tests.support.launchers import Launcher
from tests.support.ports import free_port, wait_for_port
from tests.support.threads import serve_in_thread
from tests.support.waiting import SAFETY_NET_S

pytestmark = pytest.mark.slow

START_TIMEOUT_S = 60.0  # a process start on a loaded 2-core machine: seconds, not a measure
STOP_TIMEOUT_S = 5.0
ANGLE_TOL_DEG = 1e-6
SLOW = MotionParams(speed=2.0)  # a motion that lasts many seconds
FAR = Pose(angles=[120.0, -60.0, 60.0, -90.0, -90.0, 90.0])
QUIET_S = 0.5  # how long we watch a restarted controller for motion nobody asked for


def start_controller(launch: Launcher, port: int) -> subprocess.Popen[bytes]:
    process = launch(["--no-ui", "--api-port", str(port)], "controller")
    wait_for_port(port, START_TIMEOUT_S)
    return process


def kill(process: subprocess.Popen[bytes]) -> None:
    process.kill()
    process.wait(STOP_TIMEOUT_S)


def test_the_pendant_starts_before_the_controller(launch: Launcher) -> None:
    controller_port, pendant_port = free_port(), free_port()
    controller_url = f"http://127.0.0.1:{controller_port}"
    launch(["--no-ui", "--api-port", str(pendant_port), "--robot", controller_url])
    wait_for_port(pendant_port, START_TIMEOUT_S)

    with httpx.Client(base_url=f"http://127.0.0.1:{pendant_port}") as pendant:
        health = pendant.get("/pendant/health").json()
        assert health["mode"] == "robot" and health["robot_url"] == controller_url
        assert health["online"] is False
        assert "unreachable" in health["last_error"]
        assert pendant.get("/pose").status_code == 502

        start_controller(launch, controller_port)
        health = pendant.get("/pendant/health").json()
        assert health["online"] is True and health["motion_status"] == "IDLE"
        assert pendant.get("/pose").json()["angles"] == list(HOME_POSE_DEG)


def test_the_controller_dies_mid_motion_and_nothing_is_replayed(launch: Launcher) -> None:
    port = free_port()
    url = f"http://127.0.0.1:{port}"
    controller_process = start_controller(launch, port)
    with (
        RemoteController(url, read_timeout=1.0) as controller,
        serve_in_thread(create_proxy_app(url, read_timeout=1.0)) as proxy_url,
        httpx.Client(base_url=proxy_url) as through_proxy,
    ):
        controller.set_pose(FAR, SLOW)
        assert controller.get_motion_status() is MotionStatus.RUNNING
        assert through_proxy.get("/status/motion").content == b'"RUNNING"'

        kill(controller_process)
        with pytest.raises(ControllerOffline, match="unreachable"):
            controller.get_pose()
        assert not controller.health().online
        # Commands sent while it is down fail at once, through the client and through the proxy.
        with pytest.raises(ControllerOffline):
            controller.set_pose(FAR, SLOW)
        assert through_proxy.put("/pose?speed=2", json=FAR.model_dump()).status_code == 502

        start_controller(launch, port)
        assert controller.get_motion_status() is MotionStatus.IDLE
        assert controller.health().online  # back online on the next call
        assert through_proxy.get("/status/motion").content == b'"IDLE"'
        first_pose = controller.get_pose()
        time.sleep(QUIET_S)  # real time on purpose: the controller runs on its own clock
        assert controller.get_motion_status() is MotionStatus.IDLE
        assert controller.get_pose() == first_pose
        assert first_pose.angles == pytest.approx(list(HOME_POSE_DEG), abs=ANGLE_TOL_DEG)


def test_emergency_and_no_response_come_through_with_their_messages(launch: Launcher) -> None:
    port = free_port()
    url = f"http://127.0.0.1:{port}"
    start_controller(launch, port)
    # Waits of a safety net, not the defaults' 3 s: beside the timed tests this pass may get no CPU for
    # seconds (a clean-clone run: "did not answer GET /pose within 3 s"); the messages are what is tested.
    with (
        serve_in_thread(create_proxy_app(url, read_timeout=SAFETY_NET_S)) as proxy_url,
        RemoteController(proxy_url, read_timeout=SAFETY_NET_S) as controller,
        httpx.Client(base_url=proxy_url, timeout=SAFETY_NET_S) as through_proxy,
    ):
        through_proxy.put("/sim/fault/emergency").raise_for_status()
        with pytest.raises(Emergency) as emergency:
            controller.get_pose()
        assert emergency.value.message == MSG_EMERGENCY
        health = through_proxy.get("/pendant/health").json()
        assert health["online"] is True  # it answers: the arm is what is down
        assert health["last_error"] == MSG_EMERGENCY and health["motion_status"] == "EMERGENCY"

        through_proxy.put("/sim/reset").raise_for_status()
        through_proxy.put("/sim/fault/no_response").raise_for_status()
        with pytest.raises(NotResponding) as silent:
            controller.set_pose(FAR, SLOW)
        assert silent.value.message == MSG_NOT_RESPONDING

        through_proxy.put("/sim/reset").raise_for_status()
        assert controller.get_motion_status() is MotionStatus.IDLE


def test_kept_alive_connections_to_a_dead_controller_do_not_swallow_commands(launch: Launcher) -> None:
    port = free_port()
    url = f"http://127.0.0.1:{port}"
    controller_process = start_controller(launch, port)
    with (
        RemoteController(url) as controller,
        serve_in_thread(create_proxy_app(url)) as proxy_url,
        httpx.Client(base_url=proxy_url) as through_proxy,
    ):
        # Both leave a kept-alive connection behind...
        controller.freeze()
        assert through_proxy.put("/freeze").status_code == 200
        kill(controller_process)
        start_controller(launch, port)
        # ...to a process that is gone. The next command must go to the new one, once.
        controller.relax()
        assert controller.get_motion_status() is MotionStatus.ZERO_GRAVITY
        assert through_proxy.put("/freeze").status_code == 200
        assert controller.get_motion_status() is MotionStatus.IDLE
