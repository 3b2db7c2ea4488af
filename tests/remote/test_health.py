"""GET /pendant/health in sim mode (next to the simulator's API) and in robot mode (the proxy)."""

from __future__ import annotations

import time

import httpx
import pytest
from fastapi.testclient import TestClient

from pendant import __version__
from pendant.api import create_app
from pendant.config import Settings
from pendant.controller.errors import MSG_NOT_RESPONDING
from pendant.remote import HEALTH_PATH, RemoteController, create_proxy_app, health_router
from pendant.sim import Fault, SimController

UPTIME_S = 42.0


def sim_app_with_health(sim: SimController) -> TestClient:
    app = create_app(sim)
    app.include_router(health_router(Settings(), sim, started_at=time.monotonic() - UPTIME_S))
    return TestClient(app)


def test_sim_mode_reports_the_simulator(sim: SimController) -> None:
    health = sim_app_with_health(sim).get(HEALTH_PATH)
    assert health.status_code == 200
    body = health.json()
    assert body["mode"] == "sim" and body["robot_url"] is None
    assert body["online"] is True and body["motion_status"] == "IDLE" and body["last_error"] is None
    assert body["latency_s"] >= 0
    assert body["uptime_s"] >= UPTIME_S
    assert body["version"] == __version__


def test_sim_mode_reports_faults(sim: SimController) -> None:
    client = sim_app_with_health(sim)
    sim.inject_fault(Fault.EMERGENCY)
    assert client.get(HEALTH_PATH).json()["motion_status"] == "EMERGENCY"
    sim.reset()
    sim.inject_fault(Fault.NO_RESPONSE)
    body = client.get(HEALTH_PATH).json()
    assert body["online"] is True  # the controller answers; the arm does not
    assert body["motion_status"] is None and body["last_error"] == MSG_NOT_RESPONDING


def test_robot_mode_reports_the_remote_link(sim: SimController) -> None:
    with TestClient(create_app(sim)) as controller_api:
        remote = RemoteController("http://testserver", client=controller_api)
        app = create_app(sim)  # any app can carry the router; the controller is what matters
        app.include_router(
            health_router(Settings(robot_url="http://10.0.0.7:8081"), remote, time.monotonic())
        )
        body = TestClient(app).get(HEALTH_PATH).json()
    assert body["mode"] == "robot" and body["robot_url"] == "http://10.0.0.7:8081"
    assert body["online"] is True and body["motion_status"] == "IDLE"
    assert body["latency_s"] == pytest.approx(remote.health().latency_s)


def test_the_proxy_serves_health_even_with_nothing_behind_it() -> None:
    app = create_proxy_app("http://127.0.0.1:9", connect_timeout=0.2)
    with TestClient(app) as client:
        body = client.get(HEALTH_PATH).json()
    assert body["mode"] == "robot" and body["online"] is False and body["latency_s"] is None
    assert body["motion_status"] is None and "unreachable" in body["last_error"]


def test_health_is_not_forwarded() -> None:
    # /pendant/ is the pendant's namespace: an unknown path there is the pendant's 404, not the controller's.
    app = create_proxy_app("http://127.0.0.1:9", connect_timeout=0.2)
    with TestClient(app) as client:
        assert client.get("/pendant/nothing").status_code == 404
        assert client.get("/pose").status_code == httpx.codes.BAD_GATEWAY
